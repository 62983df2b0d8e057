"""Test helper: a copy of a result file in format 1 (one group per task), as floorslide wrote
before the columnar format (issue 34).

Tests of older files (no digests, no broadening, older signing, …) and tests that edit a
task's group directly write such a copy and edit it as before; the reader of format 1 is kept.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py

from floorslide.run.snapshot import digest, write_node
from floorslide.run.store import (
    DIGEST_ATTR,
    HEADER_DIGEST_ATTR,
    LEGACY_FORMAT,
    ResultFile,
    header_digest,
)


def to_format1(src: str | Path, dst: str | Path | None = None) -> Path:
    """Write the result file `src` (format 2) as a file of format 1 at `dst` (default: in
    place): the same header (its digest recomputed for the format), each done task as the group
    its digest is over, with its ``sha256`` and ``done = 1``, in the order of the file."""
    src = Path(src)
    dst = src if dst is None else Path(dst)
    rf = ResultFile(src)
    nodes = []
    for tid, node, problem in rf.nodes(rf.done_tasks()):
        assert node is not None, f"{tid}: {problem}"
        nodes.append((tid, node))
    tmp = dst.with_name(dst.name + ".format1")
    with h5py.File(src, "r") as f, h5py.File(tmp, "w") as out:
        for k, v in f.attrs.items():
            out.attrs[k] = v
        for name in ("scene", "plan"):
            f.copy(f[name], out, name)
        out.attrs["floorslide_format"] = LEGACY_FORMAT
        if HEADER_DIGEST_ATTR in out.attrs:
            out.attrs[HEADER_DIGEST_ATTR] = header_digest(out)
        tasks = out.create_group("tasks")
        for tid, node in nodes:
            g = write_node(tasks, tid, node)
            g.attrs[DIGEST_ATTR] = digest(node)
            g.attrs["done"] = 1
    shutil.move(tmp, dst)
    return dst


def resign_header(f: h5py.File) -> None:
    """Recompute the header digest of the open file `f` (after a test edited the header as an
    older writer would have written it)."""
    if HEADER_DIGEST_ATTR in f.attrs:
        f.attrs[HEADER_DIGEST_ATTR] = header_digest(f)
