"""A group of an HDF5 file as plain data, written and read in one pass, and its digest.

A :class:`Node` is a group: its attributes and its children, each a :class:`Node` or a
:class:`Data` (a dataset's value and attributes). The result store builds a task as a Node,
writes it with :func:`write_node`, reads it back with :func:`snapshot` and checks it against
the SHA-256 :func:`digest` stored beside it (docs/design.md §5).

:func:`snapshot` reads through h5py's low-level interface, every object and attribute exactly
once, with one NumPy type per HDF5 type looked up once per file: it reads a task of the demo in
about a third of the time h5py's high-level interface needs to read its datasets alone, so that
verifying every value costs nothing noticeable.

The digest is over a canonical encoding, independent of how HDF5 lays the group out on disk:
children and attributes in the order of their names (UTF-8 bytes), each name, and each value
as its kind (numbers or text), shape and, for numbers, the NumPy dtype string (``<f8``) and the
bytes in C order; text as UTF-8. Every field is length-prefixed, so no two different groups
share an encoding. A value written from memory and read back from the file encode the same.
"""

from __future__ import annotations

import hashlib
import math
import struct
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import h5py
import numpy as np
from h5py import h5a, h5d, h5g, h5l, h5o, h5s, h5t

DIGEST_SCHEME = "sha256-1"
"""Name of the digest of :func:`digest` (stored with it, so that a later scheme can differ)."""

MAX_VALUE_BYTES = 1 << 32
"""A dataset or attribute larger than this (4 GiB) is taken for damage, not read."""

H5_ERRORS = (OSError, KeyError, ValueError, RuntimeError, TypeError, IndexError, MemoryError)
"""What h5py raises on a damaged file (HDF5's error stack mapped to Python exceptions)."""


class SnapshotError(ValueError):
    """A group cannot be read as plain groups, datasets and attributes (damaged or foreign)."""


@dataclass
class Data:
    """A dataset: its value (an array; a NumPy scalar or ``bytes`` when 0-d) and attributes.

    ``data[()]`` gives the value, as for an h5py dataset.
    """

    value: Any
    attrs: dict[str, Any] = field(default_factory=dict)

    def __getitem__(self, key):
        return self.value if key == () else self.value[key]


@dataclass
class Node:
    """A group: attributes and children (groups and datasets) by name.

    ``node["a/b"]``, ``"a/b" in node`` and ``node.items()`` (in name order) work as for an
    h5py group.
    """

    attrs: dict[str, Any] = field(default_factory=dict)
    children: dict[str, Node | Data] = field(default_factory=dict)

    def __getitem__(self, path: str) -> Node | Data:
        item: Node | Data = self
        for part in path.split("/"):
            if not isinstance(item, Node) or part not in item.children:
                raise KeyError(path)
            item = item.children[part]
        return item

    def __contains__(self, path: str) -> bool:
        try:
            self[path]
        except KeyError:
            return False
        return True

    def items(self) -> Iterator[tuple[str, Node | Data]]:
        """Children in the order of their names (as HDF5 lists them)."""
        for name in sorted(self.children, key=_name_key):
            yield name, self.children[name]

    def group(self, path: str) -> Node:
        """The subgroup at `path`, created (with any missing parents) if absent."""
        node = self
        for part in path.split("/"):
            child = node.children.setdefault(part, Node())
            if not isinstance(child, Node):
                raise KeyError(f"{path}: {part} is a dataset")
            node = child
        return node


def _name_key(name: str) -> bytes:
    return name.encode("utf-8", "surrogateescape")


# --- writing -----------------------------------------------------------------------------


def _is_text(value: Any) -> bool:
    if isinstance(value, str | bytes):
        return True
    return isinstance(value, np.ndarray) and value.dtype.kind in "OSU"


def write_node(parent: h5py.Group, name: str, node: Node) -> h5py.Group:
    """Write `node` as the new group `parent/name` (text datasets as variable-length UTF-8).

    Returns
    -------
    h5py.Group
        The group written.
    """
    group = parent.create_group(name)
    for key, value in node.attrs.items():
        group.attrs[key] = value
    for child_name, child in node.children.items():
        if isinstance(child, Node):
            write_node(group, child_name, child)
            continue
        value = child.value
        if _is_text(value):
            ds = group.create_dataset(
                child_name,
                data=np.asarray(value, dtype=object),
                dtype=h5py.string_dtype(),
            )
        else:
            ds = group.create_dataset(child_name, data=np.asarray(value))
        for key, attr in child.attrs.items():
            ds.attrs[key] = attr
    return group


# --- reading -----------------------------------------------------------------------------


class _Types:
    """The NumPy dtype and in-memory HDF5 type of each HDF5 type met, built once each (h5py
    builds them anew on every read, which costs more than the read)."""

    def __init__(self) -> None:
        self._known: list[tuple[h5t.TypeID, np.dtype, h5t.TypeID]] = []

    def __call__(self, tid: h5t.TypeID) -> tuple[np.dtype, h5t.TypeID]:
        for known, dtype, mtype in self._known:
            if known.equal(tid):
                return dtype, mtype
        dtype = tid.dtype
        if dtype.subdtype is not None:
            raise SnapshotError(f"unsupported HDF5 array type {dtype}")
        mtype = h5t.py_create(dtype)
        self._known.append((tid, dtype, mtype))
        return dtype, mtype


def _empty(shape: tuple[int, ...] | None, dtype: np.dtype, what: str) -> np.ndarray:
    if shape is None:
        raise SnapshotError(f"{what}: has no dataspace")
    if math.prod(shape) * dtype.itemsize > MAX_VALUE_BYTES:
        raise SnapshotError(f"{what}: implausible size {shape}")
    return np.empty(shape, dtype=dtype)


def _attrs(oid, types: _Types, where: str) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for i in range(h5a.get_num_attrs(oid)):
        attr = h5a.open(oid, index=i)
        name = attr.name.decode("utf-8", "surrogateescape")
        dtype, mtype = types(attr.get_type())
        arr = _empty(attr.shape, dtype, f"{where} attribute {name}")
        if arr.size:
            attr.read(arr, mtype=mtype)
        out[name] = arr[()] if arr.ndim == 0 else arr
    return out


def _data(did, types: _Types, where: str) -> Data:
    dtype, mtype = types(did.get_type())
    arr = _empty(did.shape, dtype, where)
    if arr.size:
        did.read(h5s.ALL, h5s.ALL, arr, mtype=mtype)
    return Data(arr[()] if arr.ndim == 0 else arr, _attrs(did, types, where))


def _walk(gid, types: _Types, seen: set, where: str) -> Node:
    links: list[tuple[bytes, int]] = []

    def visit(name: bytes, info) -> None:
        links.append((name, info.type))

    gid.links.iterate(visit, info=True)
    node = Node(_attrs(gid, types, where))
    for raw, kind in links:
        name = raw.decode("utf-8", "surrogateescape")
        path = f"{where}/{name}"
        if kind != h5l.TYPE_HARD:
            raise SnapshotError(f"{path}: a soft or external link, not an object")
        oid = h5o.open(gid, raw)
        if isinstance(oid, h5d.DatasetID):
            node.children[name] = _data(oid, types, path)
        elif isinstance(oid, h5g.GroupID):
            addr = h5o.get_info(oid).addr
            if addr in seen:
                raise SnapshotError(f"{path}: a group linked twice")
            seen.add(addr)
            node.children[name] = _walk(oid, types, seen, path)
        else:
            raise SnapshotError(f"{path}: neither a group nor a dataset")
    return node


def snapshot(group: h5py.Group) -> Node:
    """Read `group` whole: every subgroup, dataset and attribute, each once.

    Values are as h5py's ``dataset[()]`` gives them (arrays; NumPy scalars for 0-d values;
    variable-length text as ``bytes``).

    Raises
    ------
    SnapshotError
        The group cannot be read: damaged, or holding links or types floorslide never writes.
    """
    where = group.name or ""
    try:
        return _walk(group.id, _Types(), {h5o.get_info(group.id).addr}, where)
    except SnapshotError:
        raise
    except H5_ERRORS as exc:
        raise SnapshotError(f"{where}: {exc}") from None


# --- digest ------------------------------------------------------------------------------


def _text(item: Any) -> bytes:
    if isinstance(item, bytes):
        return item
    if isinstance(item, str):
        return item.encode("utf-8", "surrogateescape")
    raise SnapshotError(f"not text: {type(item).__name__}")


def _feed_value(h, value: Any) -> None:
    if isinstance(value, str | bytes):
        h.update(b"t" + struct.pack("<I", 0))
        blob = _text(value)
        h.update(struct.pack("<Q", len(blob)) + blob)
        return
    arr = np.asarray(value)
    shape = struct.pack(f"<I{arr.ndim}Q", arr.ndim, *arr.shape)
    if arr.dtype.kind in "OSU":
        h.update(b"t" + shape)
        for item in arr.ravel(order="C"):
            blob = _text(item)
            h.update(struct.pack("<Q", len(blob)) + blob)
        return
    if arr.dtype.kind not in "biufc":
        raise SnapshotError(f"unsupported value type {arr.dtype}")
    code = arr.dtype.str.encode()
    blob = np.ascontiguousarray(arr).tobytes()
    h.update(b"n" + struct.pack("<I", len(code)) + code + shape)
    h.update(struct.pack("<Q", len(blob)) + blob)


def _feed_name(h, name: str) -> None:
    blob = _name_key(name)
    h.update(struct.pack("<Q", len(blob)) + blob)


def _feed_attrs(h, attrs: dict[str, Any], skip: frozenset[str] = frozenset()) -> None:
    keys = sorted((k for k in attrs if k not in skip), key=_name_key)
    h.update(struct.pack("<Q", len(keys)))
    for key in keys:
        _feed_name(h, key)
        _feed_value(h, attrs[key])


def _feed_node(h, node: Node, skip: frozenset[str]) -> None:
    _feed_attrs(h, node.attrs, skip)
    h.update(struct.pack("<Q", len(node.children)))
    for name, child in node.items():
        _feed_name(h, name)
        if isinstance(child, Node):
            h.update(b"G")
            _feed_node(h, child, frozenset())
        else:
            h.update(b"D")
            _feed_value(h, child.value)
            _feed_attrs(h, child.attrs)


def digest(node: Node, skip_attrs: frozenset[str] = frozenset()) -> str:
    """SHA-256 (hex) of `node`'s canonical encoding (see the module's docstring).

    Parameters
    ----------
    node
        The group, from memory or from :func:`snapshot`.
    skip_attrs
        Attributes of `node` itself (not of its children) left out, e.g. the digest itself.

    Raises
    ------
    SnapshotError
        A value that is neither numbers nor text.
    """
    h = hashlib.sha256(DIGEST_SCHEME.encode() + b"\0")
    _feed_node(h, node, skip_attrs)
    return h.hexdigest()
