"""The fingerprint of a task's inputs: what ``--resume`` compares before keeping a finished task.

A task's results are a pure function of its inputs: the record's processed and scaled samples
(and its second and vertical components), its time step and scale factor, the building, the
contents and floors, the spectra asked for, whether histories are kept, and the floorslide that
computed them. The fingerprint is the SHA-256 of all of these in a canonical encoding (floats by
their exact bits, arrays by their bytes in little-endian order, dataclasses field by field), so
that a record file replaced, a catalog row deleted or fixed (the tasks that follow then carry
other records), a units column corrected or floorslide upgraded gives other fingerprints and
``--resume`` runs those tasks again instead of mixing old and new results (docs/design.md §5).
"""

from __future__ import annotations

import dataclasses
import hashlib
import struct
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

SCHEME = "floorslide-task-inputs-1"
"""Names the encoding below; part of every fingerprint."""


def _feed(h, value: Any) -> None:
    """Feed `value` to the hash `h` in a canonical, type-tagged encoding."""
    if value is None:
        h.update(b"N")
    elif isinstance(value, bool | np.bool_):
        h.update(b"T" if value else b"F")
    elif isinstance(value, int | np.integer):
        h.update(b"i" + str(int(value)).encode() + b";")
    elif isinstance(value, float | np.floating):
        h.update(b"f" + struct.pack("<d", float(value)))
    elif isinstance(value, str):
        data = value.encode("utf-8", "surrogatepass")
        h.update(b"s" + str(len(data)).encode() + b":" + data)
    elif isinstance(value, np.ndarray):
        arr = np.ascontiguousarray(value)
        if arr.dtype.kind == "f":
            arr = arr.astype("<f8", copy=False)
        elif arr.dtype.kind in "iub":
            arr = arr.astype("<i8", copy=False)
        else:
            raise TypeError(f"cannot fingerprint an array of {arr.dtype}")
        h.update(b"a" + repr(arr.shape).encode() + arr.dtype.str.encode())
        h.update(arr.tobytes())
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        h.update(b"D" + type(value).__name__.encode() + b"(")
        for f in dataclasses.fields(value):
            _feed(h, f.name)
            _feed(h, getattr(value, f.name))
        h.update(b")")
    elif isinstance(value, Mapping):
        h.update(b"{")
        for k in sorted(value, key=str):
            _feed(h, str(k))
            _feed(h, value[k])
        h.update(b"}")
    elif isinstance(value, Iterable):
        h.update(b"[")
        for item in value:
            _feed(h, item)
        h.update(b"]")
    else:
        raise TypeError(f"cannot fingerprint {type(value).__name__}")


def digest_of(*values: Any) -> str:
    """SHA-256 (hex) of `values` in the canonical encoding."""
    h = hashlib.sha256(SCHEME.encode())
    for v in values:
        _feed(h, v)
    return h.hexdigest()


def _record_digest(record) -> str:
    """The record's part: its identity, samples, time step, scale and components."""
    return digest_of(
        record.set,
        record.record,
        record.label,
        record.dt,
        record.scale,
        record.acc,
        record.acc2,
        record.vertical,
        tuple(record.components),
    )


def task_fingerprints(tasks: Iterable, version: str | None = None) -> dict[str, str]:
    """The fingerprint of each task's inputs, by task id.

    Parameters
    ----------
    tasks
        :class:`floorslide.scene.planner.Task` objects.
    version
        The floorslide version that computes them (default: this one).

    Returns
    -------
    dict
        Task id → SHA-256 (hex). Each record's samples are hashed once, however many tasks
        (buildings) share it.
    """
    if version is None:
        from floorslide import __version__ as version
    records: dict[int, str] = {}
    out = {}
    for t in tasks:
        key = id(t.record)
        if key not in records:
            records[key] = _record_digest(t.record)
        out[t.task_id] = digest_of(
            version,
            records[key],
            t.building,
            t.floors,
            t.contents,
            t.spectra_floors,
            t.spectra,
            t.histories,
        )
    return out
