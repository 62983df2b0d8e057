"""Journal entries: one finished task in a file of JSON and raw array bytes, nothing that runs.

An entry is written before its task goes into the result file, atomically (a temporary file,
fsync, rename), so that a run killed at any moment keeps every finished task
(docs/design.md §5, §9). Its format is data only, so a planted or damaged entry can never run
code; it is validated field by field on load and checked against its SHA-256 digest::

    b"floorslide journal entry\\n"         magic line
    8 bytes                               length H of the header, unsigned little-endian
    H bytes                               header, JSON (UTF-8)
    the rest                              the arrays' bytes, one after the other

The header is ``{"version": 1, "task_id", "scene_sha256", "digest", "id_sha256", "group"}``:
the task's id, the SHA-256 of the scene's text it was computed for, the digest of its group
(:func:`floorslide.run.snapshot.digest`), the SHA-256 of the id and that digest (so that a
damaged id is refused too: the group's digest does not cover it; entries written before it was
kept have none and are read as before) and the group itself, where a group is
``{"attrs": {name: value}, "groups": {name: group}, "datasets": {name: {"value": value,
"attrs": {...}}}}`` and a value is ``{"text": [str, ...], "shape": [...]}`` or ``{"dtype":
"<f8", "shape": [...], "offset": bytes from the start of the arrays, "nbytes": ...}``. Only
booleans, integers, floats and complex numbers of a fixed size are accepted as arrays.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
import struct
from typing import Any

import numpy as np

from floorslide.run.snapshot import Data, Node, digest

_DTYPE = re.compile(r"[<>|=]?[biufc][1-9][0-9]?")
"""Type strings of the arrays an entry may hold (byte order, kind, item size)."""
MAGIC = b"floorslide journal entry\n"
VERSION = 1
MAX_DEPTH = 16
"""Groups nested deeper than this are refused (a task nests 5 deep)."""


class EntryError(ValueError):
    """A file is not a journal entry, or a damaged one."""


def _text_items(value: Any) -> list[str]:
    arr = np.asarray(value, dtype=object)
    out = []
    for item in arr.ravel(order="C"):
        if isinstance(item, bytes):
            item = item.decode("utf-8", "surrogateescape")
        if not isinstance(item, str):
            raise TypeError(f"not text: {type(item).__name__}")
        out.append(item)
    return out


def _encode_value(value: Any, blobs: list[bytes], offset: list[int]) -> dict:
    if isinstance(value, str | bytes):
        return {"text": _text_items(value), "shape": []}
    arr = np.asarray(value)
    if arr.dtype.kind in "OSU":
        return {"text": _text_items(arr), "shape": list(arr.shape)}
    if arr.dtype.kind not in "biufc":
        raise TypeError(f"cannot journal values of type {arr.dtype}")
    blob = np.ascontiguousarray(arr).tobytes()
    out = {"dtype": arr.dtype.str, "shape": list(arr.shape), "offset": offset[0]}
    out["nbytes"] = len(blob)
    blobs.append(blob)
    offset[0] += len(blob)
    return out


def _encode_attrs(attrs: dict, blobs: list[bytes], offset: list[int]) -> dict:
    return {k: _encode_value(v, blobs, offset) for k, v in attrs.items()}


def _encode_node(node: Node, blobs: list[bytes], offset: list[int]) -> dict:
    groups, datasets = {}, {}
    for name, child in node.items():
        if isinstance(child, Node):
            groups[name] = _encode_node(child, blobs, offset)
        else:
            datasets[name] = {
                "value": _encode_value(child.value, blobs, offset),
                "attrs": _encode_attrs(child.attrs, blobs, offset),
            }
    return {
        "attrs": _encode_attrs(node.attrs, blobs, offset),
        "groups": groups,
        "datasets": datasets,
    }


def encode(task_id: str, scene_sha256: str, node: Node, node_digest: str | None = None) -> bytes:
    """The bytes of the journal entry of one task.

    Parameters
    ----------
    task_id
        The task's id.
    scene_sha256
        SHA-256 (hex) of the text of the scene the task belongs to.
    node
        The task's group, as it goes into the result file.
    node_digest
        ``digest(node)`` when the caller has it already (the writer stores the same digest in
        the result file); computed here otherwise.
    """
    blobs: list[bytes] = []
    group = _encode_node(node, blobs, [0])
    if node_digest is None:
        node_digest = digest(node)
    header = {
        "version": VERSION,
        "task_id": task_id,
        "scene_sha256": scene_sha256,
        "digest": node_digest,
        "id_sha256": _id_digest(task_id, node_digest),
        "group": group,
    }
    text = json.dumps(header, ensure_ascii=True, allow_nan=False).encode()
    return b"".join([MAGIC, struct.pack("<Q", len(text)), text, *blobs])


def _id_digest(task_id: str, node_digest: str) -> str:
    """SHA-256 of a task's id and its group's digest: what binds the id to the group."""
    text = f"{task_id}\n{node_digest}".encode("utf-8", "surrogateescape")
    return hashlib.sha256(text).hexdigest()


# --- decoding: every field checked; nothing but numbers and text is ever built -----------


def _need(ok: bool, what: str) -> None:
    if not ok:
        raise EntryError(what)


def _name(name: Any) -> str:
    _need(isinstance(name, str) and name not in ("", ".", "..") and "/" not in name, "bad name")
    return name


def _shape(shape: Any) -> tuple[int, ...]:
    _need(isinstance(shape, list) and len(shape) <= 32, "bad shape")
    for n in shape:
        _need(isinstance(n, int) and not isinstance(n, bool) and 0 <= n < 1 << 40, "bad shape")
    return tuple(shape)


def _decode_value(spec: Any, payload: memoryview) -> Any:
    _need(isinstance(spec, dict), "bad value")
    shape = _shape(spec.get("shape"))
    if "text" in spec:
        _need(set(spec) == {"text", "shape"}, "bad text value")
        items = spec["text"]
        _need(isinstance(items, list) and all(isinstance(s, str) for s in items), "bad text")
        _need(len(items) == math.prod(shape), "text does not match its shape")
        encoded = [s.encode("utf-8", "surrogateescape") for s in items]
        if not shape:
            return encoded[0]
        arr = np.empty(len(encoded), dtype=object)
        arr[:] = encoded
        return arr.reshape(shape)
    _need(set(spec) == {"dtype", "shape", "offset", "nbytes"}, "bad array value")
    code, offset, nbytes = spec["dtype"], spec["offset"], spec["nbytes"]
    # only plain numeric type strings reach NumPy: its parser evaluates others (a "," raised a
    # SyntaxError from ast.literal_eval)
    _need(isinstance(code, str) and _DTYPE.fullmatch(code) is not None, f"refused dtype {code!r}")
    try:
        dtype = np.dtype(code)
    except (TypeError, ValueError, SyntaxError):
        raise EntryError(f"bad dtype {code!r}") from None
    _need(dtype.kind in "biufc" and dtype.str == code, f"refused dtype {code!r}")
    for n in (offset, nbytes):
        _need(isinstance(n, int) and not isinstance(n, bool) and n >= 0, "bad offset")
    _need(nbytes == math.prod(shape) * dtype.itemsize, "array size does not match its shape")
    _need(offset + nbytes <= len(payload), "array beyond the end of the entry")
    arr = np.frombuffer(payload[offset : offset + nbytes], dtype=dtype).reshape(shape).copy()
    return arr[()] if not shape else arr


def _decode_attrs(spec: Any, payload: memoryview) -> dict:
    _need(isinstance(spec, dict), "bad attributes")
    return {_name(k): _decode_value(v, payload) for k, v in spec.items()}


def _decode_node(spec: Any, payload: memoryview, depth: int) -> Node:
    _need(depth <= MAX_DEPTH, "groups nested too deep")
    _need(isinstance(spec, dict) and set(spec) == {"attrs", "groups", "datasets"}, "bad group")
    _need(isinstance(spec["groups"], dict) and isinstance(spec["datasets"], dict), "bad group")
    node = Node(_decode_attrs(spec["attrs"], payload))
    for name, sub in spec["groups"].items():
        node.children[_name(name)] = _decode_node(sub, payload, depth + 1)
    for name, ds in spec["datasets"].items():
        _need(_name(name) not in node.children, "a name used twice")
        _need(isinstance(ds, dict) and set(ds) == {"value", "attrs"}, "bad dataset")
        node.children[name] = Data(
            _decode_value(ds["value"], payload), _decode_attrs(ds["attrs"], payload)
        )
    return node


def decode(data: bytes, scene_sha256: str) -> tuple[str, Node]:
    """The task id and group of a journal entry, validated.

    Parameters
    ----------
    data
        The entry file's bytes.
    scene_sha256
        SHA-256 (hex) of the current scene's text; an entry written for another scene is
        refused.

    Returns
    -------
    (task_id, node)

    Raises
    ------
    EntryError
        Not a journal entry (e.g. a pickle), damaged (its digest does not match), written by
        another version or for another scene.
    """
    _need(data.startswith(MAGIC), "not a floorslide journal entry")
    start = len(MAGIC) + 8
    _need(len(data) >= start, "cut short")
    (size,) = struct.unpack("<Q", data[len(MAGIC) : start])
    _need(size <= len(data) - start, "cut short")
    try:
        header = json.loads(data[start : start + size].decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError):
        raise EntryError("damaged header") from None
    _need(isinstance(header, dict), "damaged header")
    _need(header.get("version") == VERSION, f"entry format {header.get('version')!r}, not 1")
    task_id, scene = header.get("task_id"), header.get("scene_sha256")
    _need(isinstance(task_id, str) and isinstance(header.get("digest"), str), "damaged header")
    _need(scene == scene_sha256, "written for another scene")
    node = _decode_node(header.get("group"), memoryview(data)[start + size :], 0)
    _need(digest(node) == header["digest"], "damaged (its digest does not match)")
    if "id_sha256" in header:
        _need(
            header["id_sha256"] == _id_digest(task_id, header["digest"]),
            "damaged (its task id does not match its digest)",
        )
    return _name(task_id), node
