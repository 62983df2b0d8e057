"""The columnar layout of a result file (format 2): tasks as rows of a few tables.

A task is built in memory as a :class:`~floorslide.run.snapshot.Node` (the group it was in
format 1, :func:`floorslide.run.store.task_node`), and its digest is over that node. This
module stores many such nodes as columns and gives them back, value for value and dtype for
dtype, so that the digest of a node read back equals the digest of the node written:

``tasks``
    one row per task: ``id``, ``sha256`` (its digest), ``raw``, ``histories`` (flags), one
    column per attribute of the task (``record``, ``pga``, …) and the task's arrays
    (``floors``, ``pfa``, ``pfa_components``) *ragged*: concatenated along their first axis,
    with ``<name>#n`` the length of each row's part.
``contents``
    one row per (task, content, floor, friction pair): coordinates ``task`` (the row of
    ``tasks``), ``content``, ``group`` (``floor_<f>``), ``floor``, ``pair`` (0, 1, … within
    the content and floor), one column per quantity (``mu_k``, ``mu_s``, ``peak_slide``, …,
    ``outcomes`` as text) and the content's attributes (``model``, ``mode``, ``skipped``,
    ``vertical``) repeated on each of its rows.
``spectra``
    one row per (task, floor): ``task``, ``group``, ``floor``; ``periods`` (rows, periods),
    ``damping`` (rows, damping), ``psa`` … (rows, damping, periods), ``broadened.psa`` …,
    the attributes ``broadening``, ``orientation``, ``broadened.broadening``.

Every table group has the attributes ``rows`` (the rows written and complete: rows beyond it
are the remains of a write cut short and are ignored), ``names`` (JSON: the columns in the
order of the columns of ``present``) and ``kinds`` (JSON: each column's kind: ``a`` an
attribute, ``r`` a ragged array, ``k`` an array stacked per row, ``p`` an array with one value
per row); ``present`` (rows, columns) says which columns a row has (a missing quantity is a
fill value there: NaN, 0 or ""). A column dataset carries the attributes of the datasets it
holds (``units``, ``broadening``).

A task's histories (one record per record set has them) stay a group, ``/histories/<task>``,
as in format 1; a task whose node does not fit these tables (nothing floorslide writes today)
is stored whole as ``/raw/<task>``. The number of HDF5 objects is thus independent of the
number of tasks but for the few that keep histories.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import h5py
import numpy as np

from floorslide.run.snapshot import Data, Node, snapshot, write_node

TABLES = ("tasks", "contents", "spectra")
RESERVED = {
    "tasks": {"id", "sha256", "raw", "histories", "present"},
    "contents": {"task", "content", "group", "floor", "pair", "present"},
    "spectra": {"task", "group", "floor", "present"},
}
TEXT = h5py.string_dtype()
CHUNK_BYTES = 1 << 16
"""Target size of a chunk of a column (bytes)."""


class Misfit(ValueError):
    """A task's node does not fit the tables (it is then stored whole under ``/raw``)."""


def _need(ok: bool, why: str) -> None:
    if not ok:
        raise Misfit(why)


# --- leaves ------------------------------------------------------------------------------


def _is_text_scalar(v: Any) -> bool:
    return isinstance(v, str | bytes)


def _attr_key(attrs: dict) -> tuple:
    """A canonical form of a dataset's attributes, types included (to compare them)."""
    out = []
    for k in sorted(attrs):
        v = attrs[k]
        if _is_text_scalar(v):
            out.append((k, "t", v.decode() if isinstance(v, bytes) else v))
        else:
            a = np.asarray(v)
            _need(a.ndim == 0 and a.dtype.kind in "biuf", f"attribute {k} not a scalar")
            out.append((k, a.dtype.str, a.tobytes()))
    return tuple(out)


def _spec_of(value: Any, kind: str) -> tuple[str, tuple]:
    """(dtype string or "text", the shape of one row) of a leaf's value."""
    if kind == "a":
        if _is_text_scalar(value):
            return "text", ()
        a = np.asarray(value)
        _need(a.ndim == 0 and a.dtype.kind in "biuf", "an attribute that is not a scalar")
        return a.dtype.str, ()
    a = np.asarray(value)
    _need(a.ndim >= 1, "a 0-d dataset")
    text = a.dtype.kind in "OSU"
    _need(text or a.dtype.kind in "biufc", f"values of type {a.dtype}")
    dtype = "text" if text else a.dtype.str
    return dtype, (tuple(a.shape) if kind == "k" else tuple(a.shape[1:]))


def _leaves(node: Node, prefix: str, array_kind: str, out: dict) -> None:
    """Flatten a group into leaves: name → (kind, value, dataset attrs)."""
    for k, v in node.attrs.items():
        _need("." not in k and "#" not in k, f"attribute name {k!r}")
        out[prefix + k] = ("a", v, None)
    for name, child in node.children.items():
        _need("." not in name and "#" not in name, f"name {name!r}")
        if isinstance(child, Node):
            _need(bool(child.attrs or child.children), f"an empty group {name}")
            _leaves(child, f"{prefix}{name}.", array_kind, out)
        else:
            out[prefix + name] = (array_kind, child.value, child.attrs)


@dataclass
class Instance:
    """One group of a task in a table: its coordinates, its rows and its leaves."""

    coords: dict[str, Any]
    rows: int
    leaves: dict[str, tuple[str, Any, dict | None]]


def split(node: Node) -> tuple[dict[str, list[Instance]], Node | None]:
    """A task's node as table instances, and its histories group (or None).

    Raises
    ------
    Misfit
        The node does not fit the tables.
    """
    _need(set(node.children) >= {"contents", "spectra"}, "no contents or spectra group")
    root = Node(dict(node.attrs))
    for name, child in node.children.items():
        if name in ("contents", "spectra", "histories"):
            _need(isinstance(child, Node), f"{name} is not a group")
            continue
        _need(isinstance(child, Data), f"an unknown group {name}")
        root.children[name] = child
    leaves: dict = {}
    _leaves(root, "", "r", leaves)
    out: dict[str, list[Instance]] = {"tasks": [Instance({}, 1, leaves)], "contents": []}
    contents = node.children["contents"]
    _need(not contents.attrs, "attributes on contents")
    for cname, cnode in contents.items():
        _need(isinstance(cnode, Node) and not cnode.attrs and cnode.children, f"content {cname}")
        for gname, g in cnode.items():
            _need(isinstance(g, Node), f"content {cname}/{gname}")
            lv: dict = {}
            _leaves(g, "", "p", lv)
            lengths = {len(np.asarray(v)) for k, v, _ in lv.values() if k == "p"}
            _need(len(lengths) == 1 and min(lengths) > 0, f"content {cname}/{gname}: lengths")
            coords = {"content": cname, "group": gname, "floor": _floor(gname)}
            out["contents"].append(Instance(coords, lengths.pop(), lv))
    spectra = node.children["spectra"]
    _need(not spectra.attrs, "attributes on spectra")
    out["spectra"] = []
    for gname, g in spectra.items():
        _need(isinstance(g, Node), f"spectra/{gname}")
        lv = {}
        _leaves(g, "", "k", lv)
        out["spectra"].append(Instance({"group": gname, "floor": _floor(gname)}, 1, lv))
    for table, instances in out.items():
        for inst in instances:
            clash = RESERVED[table] & set(inst.leaves)
            _need(not clash, f"reserved names {sorted(clash)}")
    hist = node.children.get("histories")
    return out, hist


def _floor(group: str) -> int:
    head, _, tail = group.partition("_")
    return int(tail) if head == "floor" and tail.isdigit() else -1


# --- the schema of a file's tables -------------------------------------------------------


@dataclass
class Column:
    kind: str
    dtype: str  # a NumPy dtype string, or "text"
    shape: tuple  # of one row (kinds "a", "k") or one element along the first axis ("r", "p")
    attrs: tuple | None  # _attr_key of the datasets' attributes (None for "a")
    raw_attrs: dict = field(default_factory=dict)


@dataclass
class Table:
    names: list[str] = field(default_factory=list)
    columns: dict[str, Column] = field(default_factory=dict)
    rows: int = 0

    def fit(self, inst: Instance) -> None:
        """Add the columns `inst` needs; refuse it if it clashes with the columns there."""
        for name, (kind, value, attrs) in inst.leaves.items():
            dtype, shape = _spec_of(value, kind)
            key = None if attrs is None else _attr_key(attrs)
            col = self.columns.get(name)
            if col is None:
                self.columns[name] = Column(kind, dtype, shape, key, dict(attrs or {}))
                self.names.append(name)
                continue
            _need(col.kind == kind and col.dtype == dtype, f"{name}: kind or type")
            _need(col.shape == shape and col.attrs == key, f"{name}: shape or attributes")


def load_schema(f: h5py.File) -> dict[str, Table]:
    """The tables' columns as written in `f` (empty tables if none yet)."""
    out = {}
    for t in TABLES:
        table = Table()
        if t in f:
            g = f[t]
            table.rows = int(g.attrs["rows"])
            names = json.loads(g.attrs["names"])
            kinds = json.loads(g.attrs["kinds"])
            for name in names:
                ds = g[name]
                dtype = "text" if h5py.check_string_dtype(ds.dtype) else ds.dtype.str
                attrs = dict(ds.attrs)
                kind = kinds[name]
                key = None if kind == "a" else _attr_key(attrs)
                table.columns[name] = Column(kind, dtype, tuple(ds.shape[1:]), key, attrs)
                table.names.append(name)
        out[t] = table
    return out


# --- writing -----------------------------------------------------------------------------


def _fill(dtype: str):
    if dtype == "text":
        return ""
    d = np.dtype(dtype)
    return np.nan if d.kind in "fc" else 0


def _chunk(shape: tuple, itemsize: int, expect: int) -> tuple:
    per_row = max(1, math.prod(shape) * itemsize)
    rows = max(1, min(max(expect, 1), CHUNK_BYTES // per_row))
    return (rows, *(max(1, n) for n in shape))


def _create(g: h5py.Group, name: str, dtype: str, shape: tuple, rows: int, expect: int, fill):
    np_dtype = TEXT if dtype == "text" else np.dtype(dtype)
    itemsize = 16 if dtype == "text" else np.dtype(dtype).itemsize
    ds = g.create_dataset(
        name,
        shape=(rows, *shape),
        maxshape=(None, *(n if n else None for n in shape)),  # a chunk is never empty
        dtype=np_dtype,
        chunks=_chunk(shape, itemsize, expect),
        fillvalue=None if dtype == "text" else fill,
    )
    if rows and dtype == "text":
        ds[:] = np.full((rows, *shape), "", dtype=object)
    return ds


def _as_column(values: list, dtype: str, shape: tuple) -> np.ndarray:
    if dtype == "text":
        if not values:
            return np.empty((0, *shape), dtype=object)
        arr = np.concatenate([np.asarray(v, dtype=object).reshape(-1, *shape) for v in values])
        return arr
    if not values:
        return np.empty((0, *shape), dtype=np.dtype(dtype))
    return np.concatenate(
        [np.asarray(v, dtype=np.dtype(dtype)).reshape(-1, *shape) for v in values]
    )


def _append(
    g: h5py.Group, name: str, data: np.ndarray, start: int, expect: int, dtype: str
) -> h5py.Dataset | None:
    """Write `data` at rows `start`… of the column `name`; returns the column if this call
    created it (else None)."""
    ds = g.get(name)
    made = ds is None
    if made:
        ds = _create(g, name, dtype, tuple(data.shape[1:]), start, expect, _fill(dtype))
    end = start + len(data)
    if ds.shape[0] != end:
        ds.resize(end, axis=0)
    if len(data):
        ds[start:end] = data
    return ds if made else None


def append(
    f: h5py.File,
    tasks: Iterable[tuple[str, Node, str]],
    expect_tasks: int = 0,
    known: dict[str, Table] | None = None,
) -> list[str]:
    """Append tasks (id, node, digest) to the tables of the open file `f`, their data flushed
    but not yet counted: :func:`commit` makes them part of the file.

    `known`, when given, is the caller's record of the tables' columns: if it is filled, it is
    taken for what `f` holds instead of reading every column's attributes again (a writer that
    alone wrote the file since it last read it: the schema after its last committed batch);
    it is emptied at once and filled again with the columns after this batch, its rows counted
    as :func:`commit` will count them, only once the batch is written whole (a caller whose
    commit then fails empties it: the next append reads the file again).

    Returns
    -------
    list
        The ids of the tasks stored whole under ``/raw`` (their nodes did not fit).
    """
    schema = dict(known) if known else load_schema(f)
    listed = {t: set(schema[t].names) for t in TABLES}
    if known is not None:
        known.clear()  # filled again only once this batch is written whole
    pending: dict[str, list[Instance]] = {t: [] for t in TABLES}
    task_rows: list[dict] = []
    raw: list[str] = []
    for tid, node, node_digest in tasks:
        row = len(task_rows) + schema["tasks"].rows
        try:
            parts, hist = split(node)
            trial = {t: _copy(schema[t]) for t in TABLES}
            for t in TABLES:
                for inst in parts[t]:
                    trial[t].fit(inst)
        except Misfit:
            parts, hist = None, None
        if parts is None:
            raw.append(tid)
            task_rows.append({"id": tid, "sha256": node_digest, "raw": 1, "histories": 0})
            _replace(f, "raw", tid, node)
            pending["tasks"].append(Instance({}, 1, {}))
            continue
        schema = {t: trial[t] for t in TABLES}
        task_rows.append(
            {"id": tid, "sha256": node_digest, "raw": 0, "histories": int(hist is not None)}
        )
        if hist is not None:
            _replace(f, "histories", tid, hist)
        pending["tasks"].append(parts["tasks"][0])
        for t in ("contents", "spectra"):
            for inst in parts[t]:
                inst.coords["task"] = row
                pending[t].append(inst)
    n_tasks = max(expect_tasks, schema["tasks"].rows + len(task_rows))
    scale = n_tasks / max(1, len(task_rows))
    after = {}
    for t in TABLES:
        rows = _write_table(
            f, t, schema[t], pending[t], task_rows if t == "tasks" else None, scale, listed[t]
        )
        after[t] = _copy(schema[t])
        after[t].rows = rows
    f.flush()
    if known is not None:
        known.update(after)
    return raw


def _copy(table: Table) -> Table:
    return Table(list(table.names), dict(table.columns), table.rows)


def _replace(f: h5py.File, group: str, tid: str, node: Node) -> None:
    parent = f.require_group(group)
    if tid in parent:
        del parent[tid]
    write_node(parent, tid, node)


def _write_table(
    f, name: str, table: Table, insts: list[Instance], task_rows, scale: float, listed: set[str]
) -> int:
    """Write the rows of `insts` (and `task_rows`) after the table's rows; `listed` are the
    columns the file listed before this batch. Returns the table's rows with these."""
    g = f.require_group(name)
    start = table.rows
    n_rows = sum(i.rows for i in insts)
    expect = int(n_rows * scale) + 1
    index = {n: k for k, n in enumerate(table.names)}
    present = np.zeros((n_rows, len(table.names)), dtype=np.uint8)
    values: dict[str, list] = {n: [] for n in table.names}
    counts: dict[str, list] = {n: [] for n, c in table.columns.items() if c.kind == "r"}
    coords: dict[str, list] = {}
    row = 0
    for inst in insts:
        for k, v in inst.coords.items():
            coords.setdefault(k, []).append(
                np.full(inst.rows, v, dtype=object if isinstance(v, str) else np.int64)
            )
        if name == "contents":
            coords.setdefault("pair", []).append(np.arange(inst.rows, dtype=np.int64))
        for cname, col in table.columns.items():
            leaf = inst.leaves.get(cname)
            if leaf is not None:
                present[row : row + inst.rows, index[cname]] = 1
                value = leaf[1]
                if col.kind == "a":
                    value = [value] * inst.rows
                elif col.kind == "k":
                    value = np.asarray(value)[None]
                values[cname].append(value)
                if col.kind == "r":
                    counts[cname].append([len(np.asarray(leaf[1]))])
            else:
                if col.kind == "r":
                    counts[cname].append([0])
                    continue
                fill = _fill(col.dtype)
                shape = col.shape
                values[cname].append(
                    np.full(
                        (inst.rows, *shape),
                        fill,
                        dtype=object if col.dtype == "text" else np.dtype(col.dtype),
                    )
                )
        row += inst.rows
    if task_rows is not None:
        for key in ("id", "sha256"):
            _append(
                g, key, np.array([r[key] for r in task_rows], dtype=object), start, expect, "text"
            )
        for key in ("raw", "histories"):
            _append(
                g, key, np.array([r[key] for r in task_rows], dtype=np.uint8), start, expect, "|u1"
            )
    for key, parts in coords.items():
        dtype = "text" if parts[0].dtype == object else "<i8"
        _append(g, key, np.concatenate(parts) if parts else np.empty(0), start, expect, dtype)
    for cname, col in table.columns.items():
        data = _as_column(values[cname], col.dtype, col.shape)
        if col.kind == "r":
            base = _ragged_rows(g, cname, start)
            made = _append(g, cname, data, base, expect, col.dtype)
            _append(
                g,
                f"{cname}#n",
                np.asarray([c for part in counts[cname] for c in part], dtype=np.int64),
                start,
                expect,
                "<i8",
            )
        else:
            made = _append(g, cname, data, start, expect, col.dtype)
        if made is not None or cname not in listed:  # a listed column has them (its key)
            ds = g[cname] if made is None else made
            for k, v in col.raw_attrs.items():
                if k not in ds.attrs:
                    ds.attrs[k] = v
    if "present" in g and g["present"].shape[1] < len(table.names):
        old = g["present"]
        keep = old[:start]
        del g["present"]
        grown = np.zeros((start, len(table.names)), dtype=np.uint8)
        grown[:, : keep.shape[1]] = keep
        _append(g, "present", grown, 0, expect, "|u1")
    _append(g, "present", present, start, expect, "|u1")
    g.attrs["names"] = json.dumps(table.names)
    g.attrs["kinds"] = json.dumps({n: c.kind for n, c in table.columns.items()})
    g.attrs["pending"] = start + n_rows
    if "rows" not in g.attrs:
        g.attrs["rows"] = start
    return start + n_rows


def _ragged_rows(g: h5py.Group, name: str, start: int) -> int:
    """The elements of a ragged column that belong to its first `start` rows."""
    if f"{name}#n" not in g or start == 0:
        return 0
    return int(np.asarray(g[f"{name}#n"][:start]).sum())


def commit(f: h5py.File) -> None:
    """Count the rows :func:`append` wrote (the "done" mark of a batch)."""
    for t in TABLES:
        if t in f:
            f[t].attrs["rows"] = int(f[t].attrs.get("pending", f[t].attrs["rows"]))


def init(f: h5py.File) -> None:
    """Empty tables in a new file."""
    for t in TABLES:
        g = f.create_group(t)
        g.attrs["rows"] = 0
        g.attrs["names"] = "[]"
        g.attrs["kinds"] = "{}"


# --- reading -----------------------------------------------------------------------------


class Columns:
    """A file's tables, read whole, each column in one read; a column that cannot be read is
    kept as its error (the tasks using it fail their integrity check, the others read)."""

    def __init__(self, f: h5py.File, errors: tuple):
        self.f = f
        self.errors = errors
        self.tables: dict[str, dict] = {}
        self.broken: dict[str, dict[str, str]] = {}
        for t in TABLES:
            g = f[t]
            n = int(g.attrs["rows"])
            if not (np.ndim(n) == 0 and n >= 0):
                raise ValueError(f"/{t}: rows {n!r}")
            names = json.loads(g.attrs["names"])
            kinds = json.loads(g.attrs["kinds"])
            if not isinstance(names, list) or not isinstance(kinds, dict):
                raise ValueError(f"/{t}: damaged names")
            cols: dict[str, Any] = {"#rows": n, "#names": names, "#kinds": kinds}
            broken: dict[str, str] = {}
            fixed = ["present", *sorted(RESERVED[t] - {"present"})]
            for name in fixed:
                if name == "pair" and t != "contents":
                    continue
                cols[name] = self._read(g, name, n)
            if n and cols["present"].shape != (n, len(names)):
                raise ValueError(f"/{t}/present: shape {cols['present'].shape}")
            for name in names:
                try:
                    if kinds[name] == "r":
                        counts = self._read(g, f"{name}#n", n).astype(np.int64)
                        ends = np.cumsum(counts)
                        total = int(ends[-1]) if n else 0
                        cols[f"{name}#end"] = ends
                        cols[name] = (self._read(g, name, total), dict(g[name].attrs))
                    else:
                        cols[name] = (self._read(g, name, n), dict(g[name].attrs))
                except (*errors, KeyError) as exc:
                    broken[name] = f"/{t}/{name}: {exc}"
            self.tables[t] = cols
            self.broken[t] = broken
        ids = self.tables["tasks"]["id"]
        self.ids = [_text(x) for x in ids]
        if len(set(self.ids)) != len(self.ids):
            raise ValueError("a task id appears twice")
        self.row_of = {tid: i for i, tid in enumerate(self.ids)}
        self.members = {t: _members(self.tables[t]["task"], len(self.ids)) for t in TABLES[1:]}

    @staticmethod
    def _read(g: h5py.Group, name: str, n: int) -> np.ndarray:
        if n == 0 and name not in g:
            return np.zeros((0, 0) if name == "present" else 0, dtype=np.int64)
        ds = g[name]
        if not isinstance(ds, h5py.Dataset) or ds.shape[0] < n:
            raise ValueError(f"/{g.name}/{name} is damaged (shorter than its rows)")
        return ds[:n]

    def digest_of(self, tid: str) -> str:
        return _text(self.tables["tasks"]["sha256"][self.row_of[tid]])

    def attr(self, tid: str, name: str) -> Any:
        """A task attribute's value (None if absent or unreadable)."""
        cols = self.tables["tasks"]
        i = self.row_of[tid]
        if name not in cols["#names"] or name in self.broken["tasks"]:
            return None
        if not cols["present"][i, cols["#names"].index(name)]:
            return None
        return _scalar(cols[name][0][i])

    def node(self, tid: str) -> Node:
        """The node of a task, rebuilt.

        Raises
        ------
        ValueError, KeyError, OSError...
            A column it needs cannot be read, or the file is damaged.
        """
        i = self.row_of[tid]
        tasks = self.tables["tasks"]
        if tasks["raw"][i]:
            return snapshot(self.f["raw"][tid])
        node = _rebuild(tasks, self.broken["tasks"], i, i, 1)
        contents = node.group("contents")
        cols = self.tables["contents"]
        rows = self.members["contents"].get(i, np.empty(0, dtype=np.int64))
        starts = [r for r in rows if cols["pair"][r] == 0]
        for r0 in starts:
            n = 1
            while (
                r0 + n < cols["#rows"] and cols["pair"][r0 + n] == n and cols["task"][r0 + n] == i
            ):
                n += 1
            inst = _rebuild(cols, self.broken["contents"], r0, r0, n)
            cname, gname = _text(cols["content"][r0]), _text(cols["group"][r0])
            contents.group(cname).children[gname] = inst
        spectra = node.group("spectra")
        cols = self.tables["spectra"]
        for r in self.members["spectra"].get(i, []):
            spectra.children[_text(cols["group"][r])] = _rebuild(
                cols, self.broken["spectra"], r, r, 1
            )
        if tasks["histories"][i]:
            node.children["histories"] = snapshot(self.f["histories"][tid])
        return node


def _members(task_col: np.ndarray, n_tasks: int) -> dict[int, np.ndarray]:
    order = np.argsort(task_col, kind="stable")
    keys = task_col[order]
    out = {}
    bounds = np.flatnonzero(np.diff(keys)) + 1
    for part in np.split(order, bounds):
        if len(part):
            out[int(task_col[part[0]])] = part
    return out


def _text(x) -> str:
    return x.decode("utf-8", "surrogateescape") if isinstance(x, bytes) else str(x)


def _scalar(x):
    if isinstance(x, bytes):
        return x.decode("utf-8", "surrogateescape")
    return x


def _rebuild(cols: dict, broken: dict, row: int, start: int, n: int) -> Node:
    """The group of one instance: rows `start` … `start + n` of the table (`row` for the
    ragged columns of the tasks table)."""
    node = Node()
    names, kinds, present = cols["#names"], cols["#kinds"], cols["present"]
    for k, name in enumerate(names):
        if not present[start, k]:
            continue
        if name in broken:
            raise ValueError(broken[name])
        kind = kinds[name]
        data, attrs = cols[name]
        *path, leaf = name.split(".")
        target = node.group(".".join(path).replace(".", "/")) if path else node
        if kind == "a":
            target.attrs[leaf] = _scalar(data[start])
            continue
        if kind == "r":
            ends = cols[f"{name}#end"]
            lo = int(ends[row - 1]) if row else 0
            value = data[lo : int(ends[row])]
        elif kind == "k":
            value = data[start]
        else:
            value = data[start : start + n]
        target.children[leaf] = Data(np.array(value), dict(attrs))
    return node
