"""Design tables from a result file: statistics over record sets and ratios between buildings.

Everything here reads the result file only (DESIGN §5) through
:class:`~floorslide.run.store.ResultFile` and returns plain rows; the command line formats them
as Markdown, CSV or JSON (DESIGN §3, ``floorslide table``).

Tables (one row per …, statistics over the records of a set; units in :data:`COLUMNS`):

``slides``
    record set × building × floor × content × friction pair: number of records, mean, median and
    84th percentile of the peak slide, of the absolute residual slide and of the peak absolute
    acceleration of the object (m/s² and g); how many records made the object slide and rock.
``pfa``
    record set × building × floor: peak floor acceleration (true peak, inside steps).
``frs``
    record set × building × floor × period: median and 84th percentile of the floor's
    pseudo-spectral acceleration at the report periods and damping.
``slide_ratios`` and ``pfa_ratios``
    comparison ``A:B`` × record set × floor (× content × friction pair): the statistic of
    building A divided by that of building B, for every variant of A and of B.

Conventions
-----------
- **Percentiles** are empirical: ``numpy.percentile(x, 84)`` with NumPy's default ``"linear"``
  method (Hyndman & Fan 1996, definition 7). A lognormal fit is not used because slides are
  often exactly zero (the object does not slide under some records).
- **Rocking**: an object that would rock (Shenton 1996) is not simulated as a slider; its slide
  and acceleration are not known (NaN in the file). Statistics are taken over the records whose
  slide is known (``n_stats`` of ``n_records``: all but mode ``rock``); ``n_rocked`` counts
  records with mode ``rock`` or ``slide-rock``. With ``n_stats = 0`` the statistics are NaN.
- **Ratios** are ratios of statistics (median of A / median of B), not statistics of per-record
  ratios. ``0/0`` (neither slides) is NaN; ``x/0`` with ``x > 0`` is ``inf``; a NaN statistic
  gives a NaN ratio. The numerator and denominator are in the row beside the ratio.
- **FRS ordinates** between stored periods are interpolated linearly in ``ln T``, per record,
  before the statistics; periods outside the stored grid are left out (and said so in the
  notes).

References
----------
Hyndman, R. J., Fan, Y. (1996). Sample quantiles in statistical packages. *The American
Statistician* 50(4), 361–365.

Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes.
*J. Eng. Mech.* 122(7), 690–693.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
import tomllib
from collections import defaultdict
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from floorslide.constants import G
from floorslide.errors import FloorslideError, ModelError, ResultFileError, SceneError
from floorslide.run.results import TaskResult
from floorslide.run.store import ResultFile

PERCENTILE = 84.0
"""The upper percentile of the tables (empirical, NumPy ``"linear"`` method)."""

STANDARD_PERIODS = (0.1, 0.2, 0.3, 0.5, 1.0, 2.0, 3.0)
"""FRS ordinates (s) reported when the scene's ``[report]`` gives no ``periods``; only those
inside the stored period grid are kept."""

DEFAULT_DAMPING = 0.05
"""Damping ratio of the FRS ordinates when ``[report]`` gives none (else the first stored)."""

ROCKING_MODES = ("rock", "slide-rock")
"""Per-record modes counted as rocking (Shenton 1996)."""

TABLE_NAMES = ("slides", "pfa", "frs", "slide_ratios", "pfa_ratios")
"""The tables, in output order."""

_TOL = 1e-9


# --------------------------------------------------------------------------------------------
# table structure


@dataclass(frozen=True)
class Column:
    """A column of a design table: its key, unit (``"1"`` dimensionless, ``""`` for labels)
    and meaning."""

    name: str
    units: str
    description: str


def _stat_columns(prefix: str, units: str, what: str) -> list[Column]:
    return [
        Column(f"{prefix}_mean", units, f"mean of {what}"),
        Column(f"{prefix}_median", units, f"median of {what}"),
        Column(f"{prefix}_p84", units, f"84th percentile of {what}"),
    ]


_BUILDING = [
    Column("record_set", "", "record set (scaled sets are named set@PGAg)"),
    Column("building", "", "building variant id"),
    Column("building_kind", "", "fixed or isolated"),
    Column("isolation_period", "s", "isolation period T_i (NaN for fixed-base)"),
]

_FLOOR = Column("floor", "1", "floor (0 = ground, or the base mat of an isolated building)")
_N_RECORDS = Column("n_records", "1", "records of the set on this building")

COLUMNS: dict[str, tuple[Column, ...]] = {
    "slides": (
        *_BUILDING,
        _FLOOR,
        Column("content", "", "content (equipment) id"),
        Column("model", "", "rigid or oscillator"),
        Column("mu_k", "1", "kinetic friction coefficient"),
        Column("mu_s", "1", "static friction coefficient"),
        _N_RECORDS,
        Column("n_stats", "1", "records in the statistics: all but those with mode rock"),
        Column("n_slid", "1", "records in which the object slid (peak slide > 0)"),
        Column("n_rocked", "1", "records in which the object rocks (rock or slide-rock)"),
        *_stat_columns("peak_slide", "m", "the peak slide max|u|"),
        *_stat_columns("residual_slide", "m", "the absolute residual slide |u(end)|"),
        *_stat_columns("peak_abs_accel", "m/s**2", "the peak absolute object acceleration"),
        *_stat_columns("peak_abs_accel_g", "g", "the peak absolute object acceleration"),
    ),
    "pfa": (
        *_BUILDING,
        _FLOOR,
        _N_RECORDS,
        *_stat_columns("pfa", "m/s**2", "the true peak floor acceleration"),
        *_stat_columns("pfa_g", "g", "the true peak floor acceleration"),
        Column("pfa_pga_median", "1", "median over records of PFA / PGA"),
    ),
    "frs": (
        *_BUILDING,
        _FLOOR,
        Column("damping", "1", "damping ratio of the spectrum"),
        Column("period", "s", "oscillator period"),
        Column("n_records", "1", "records with an ordinate at this period"),
        Column("psa_median", "m/s**2", "median pseudo-spectral acceleration"),
        Column("psa_p84", "m/s**2", "84th percentile of the pseudo-spectral acceleration"),
        Column("psa_g_median", "g", "median pseudo-spectral acceleration"),
        Column("psa_g_p84", "g", "84th percentile of the pseudo-spectral acceleration"),
    ),
    "slide_ratios": (
        Column("comparison", "", "the comparison A:B as asked"),
        Column("record_set", "", "record set"),
        Column("building_a", "", "numerator building variant"),
        Column("building_b", "", "denominator building variant"),
        Column("isolation_period_a", "s", "isolation period of A (NaN for fixed-base)"),
        Column("floor", "1", "floor"),
        Column("content", "", "content id"),
        Column("mu_k", "1", "kinetic friction coefficient"),
        Column("mu_s", "1", "static friction coefficient"),
        Column("n_stats_a", "1", "records in A's statistics"),
        Column("n_stats_b", "1", "records in B's statistics"),
        Column("peak_slide_median_a", "m", "median peak slide on A"),
        Column("peak_slide_median_b", "m", "median peak slide on B"),
        Column("peak_slide_median_ratio", "1", "median peak slide A / B"),
        Column("peak_slide_p84_ratio", "1", "84th-percentile peak slide A / B"),
        Column("peak_abs_accel_median_ratio", "1", "median peak object acceleration A / B"),
    ),
    "pfa_ratios": (
        Column("comparison", "", "the comparison A:B as asked"),
        Column("record_set", "", "record set"),
        Column("building_a", "", "numerator building variant"),
        Column("building_b", "", "denominator building variant"),
        Column("isolation_period_a", "s", "isolation period of A (NaN for fixed-base)"),
        Column("floor", "1", "floor"),
        Column("pfa_median_a", "m/s**2", "median PFA on A"),
        Column("pfa_median_b", "m/s**2", "median PFA on B"),
        Column("pfa_median_ratio", "1", "median PFA A / B"),
        Column("pfa_p84_ratio", "1", "84th-percentile PFA A / B"),
    ),
}
"""Columns of every table, in order."""

TITLES = {
    "slides": "Sliding contents: peak slide, |residual| slide, peak object acceleration",
    "pfa": "Peak floor acceleration (PFA)",
    "frs": "Floor response spectra: PSA at the report periods",
    "slide_ratios": "Peak-slide ratios between buildings (A / B)",
    "pfa_ratios": "PFA ratios between buildings (A / B)",
}


@dataclass(frozen=True)
class Comparison:
    """A comparison ``A:B`` and the building variants it matches on each side."""

    spec: str
    a: tuple[str, ...]
    b: tuple[str, ...]

    def pairs(self) -> list[tuple[str, str]]:
        """Every (numerator, denominator) pair of distinct variants."""
        return [(x, y) for x in self.a for y in self.b if x != y]


@dataclass(frozen=True)
class DesignTables:
    """The design tables of a result file.

    ``tables`` maps each name of :data:`TABLE_NAMES` to its rows (dicts keyed by the column
    names of :data:`COLUMNS`, SI values, NaN where a statistic is undefined). Index it like a
    mapping: ``tables["slides"]``.
    """

    source: str
    scene_name: str
    periods: tuple[float, ...]
    damping: float | None
    comparisons: tuple[Comparison, ...]
    tables: dict[str, list[dict]]
    notes: tuple[str, ...] = ()

    def __getitem__(self, name: str) -> list[dict]:
        return self.tables[name]

    def __iter__(self):
        return iter(self.tables)

    def as_dict(self) -> dict[str, list[dict]]:
        """``{table name: rows}``."""
        return {name: list(rows) for name, rows in self.tables.items()}


# --------------------------------------------------------------------------------------------
# the study: a result file read once


@dataclass(frozen=True)
class Building:
    """A building variant as recorded in the result file's task attributes."""

    id: str
    base: str
    kind: str
    stories: int
    isolation_period: float
    isolation_damping: float
    superstructure: str


@dataclass
class Study:
    """A result file read once: its tasks, buildings, and the order of sets, buildings and
    contents (the scene's order, then natural order)."""

    source: str
    scene_name: str
    scene: dict
    report: dict
    tasks: list[TaskResult]
    buildings: dict[str, Building]
    sets: list[str]
    contents: list[str]
    notes: list[str] = field(default_factory=list)

    def set_tasks(self, record_set: str) -> list[TaskResult]:
        """The tasks of one record set."""
        return [t for t in self.tasks if t.meta["record_set"] == record_set]


def _natural(text: str) -> tuple:
    """Sort key treating runs of digits (with a decimal point) as numbers: T=2.5 < T=10."""
    parts = re.split(r"(\d+(?:\.\d+)?)", text)
    return tuple((0, float(p), "") if i % 2 else (1, 0.0, p) for i, p in enumerate(parts))


def _rank(order: Sequence[str], name: str) -> int:
    return order.index(name) if name in order else len(order)


def _float(value, default: float = math.nan) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        return default


def load_study(result: str | Path | ResultFile | Study) -> Study:
    """Read a result file once for tables and figures.

    Parameters
    ----------
    result
        Path of a result file (``floorslide run -o``), an open :class:`ResultFile`, or a
        :class:`Study` (returned as is).

    Returns
    -------
    Study

    Raises
    ------
    ResultFileError
        The file is missing, corrupt, not a floorslide result file, or holds no finished task.
    """
    if isinstance(result, Study):
        return result
    rf = result if isinstance(result, ResultFile) else ResultFile(result)
    source = str(rf.path)
    notes: list[str] = []
    try:
        scene = tomllib.loads(rf.scene_text)
    except tomllib.TOMLDecodeError as exc:
        scene = {}
        notes.append(f"the stored scene text is not valid TOML ({exc}); report options ignored")
    report = scene.get("report", {})
    if not isinstance(report, dict):
        report = {}
    tasks = list(rf.tasks())
    if not tasks:
        raise ResultFileError(
            "holds no finished task (run the scene, or continue it with floorslide run --resume)",
            source,
        )
    required = ("record_set", "record", "building")
    for t in tasks:
        missing = [k for k in required if k not in t.meta]
        if missing:
            raise ResultFileError(
                f"task {t.task_id} lacks the attributes {', '.join(missing)}", source
            )

    def scene_ids(key: str, attr: str) -> list[str]:
        items = scene.get(key, [])
        out = []
        for item in items if isinstance(items, list) else []:
            if isinstance(item, dict) and isinstance(item.get(attr), str):
                out.append(item[attr])
        return out

    buildings: dict[str, Building] = {}
    for t in tasks:
        m = t.meta
        bid = str(m["building"])
        if bid not in buildings:
            buildings[bid] = Building(
                id=bid,
                base=str(m.get("building_base", "") or bid.split("@")[0]),
                kind=str(m.get("building_kind", "")),
                stories=int(_float(m.get("stories"), 0)),
                isolation_period=_float(m.get("isolation_period")),
                isolation_damping=_float(m.get("isolation_damping")),
                superstructure=str(m.get("superstructure", "") or ""),
            )
    base_order = scene_ids("buildings", "id")

    def building_key(b: Building):
        nan_first = lambda x: (0, 0.0) if math.isnan(x) else (1, x)  # noqa: E731
        return (
            _rank(base_order, b.base),
            _natural(b.base),
            nan_first(b.isolation_period),
            nan_first(b.isolation_damping),
            _natural(b.id),
        )

    ordered = dict(sorted(buildings.items(), key=lambda kv: building_key(kv[1])))
    set_order = scene_ids("records", "set")
    sets = sorted(
        {str(t.meta["record_set"]) for t in tasks},
        key=lambda s: (_rank(set_order, s.split("@")[0]), _natural(s)),
    )
    content_order = scene_ids("contents", "id")
    contents = sorted(
        {c.content for t in tasks for c in t.contents},
        key=lambda c: (_rank(content_order, c), _natural(c)),
    )
    return Study(source, rf.scene_name, scene, report, tasks, ordered, sets, contents, notes)


# --------------------------------------------------------------------------------------------
# statistics


def summarize(values: Iterable[float]) -> tuple[float, float, float]:
    """Mean, median and 84th percentile of the finite values (NaN, NaN, NaN if none).

    The percentile is ``numpy.percentile(x, 84)`` with the ``"linear"`` method (Hyndman & Fan
    1996, definition 7).
    """
    x = np.asarray(list(values), dtype=float)
    x = x[np.isfinite(x)]
    if x.size == 0:
        return (math.nan, math.nan, math.nan)
    return (
        float(np.mean(x)),
        float(np.median(x)),
        float(np.percentile(x, PERCENTILE, method="linear")),
    )


def ratio(a: float, b: float) -> float:
    """``a / b`` with the table's conventions: NaN if either is NaN or both are zero, ``inf``
    for ``a > 0 = b``."""
    if not (math.isfinite(a) and math.isfinite(b)):
        return math.nan
    if b == 0.0:
        return math.nan if a == 0.0 else math.copysign(math.inf, a)
    return a / b


def _pair_modes(c) -> list[str]:
    """Per friction pair: the object's mode under this record."""
    n = len(c.mu_k)
    if c.modes is not None and len(c.modes) == n:
        return [str(m) for m in c.modes]
    if c.mode in ("rest", "slide", "rock", "slide-rock"):
        return [c.mode] * n
    out = []
    for p in np.asarray(c.peak_slide, dtype=float):
        out.append("rock" if not np.isfinite(p) else ("slide" if p > 0 else "rest"))
    return out


def _by_record(observations: list[tuple]) -> list[tuple]:
    """Observations ``(record, ...)`` in record order, so that sums (the mean) do not depend
    on the order of the tasks in the file."""
    return sorted(observations, key=lambda o: _natural(o[0]))


def _stats_cols(prefix: str, values: Iterable[float]) -> dict:
    mean, median, p84 = summarize(values)
    return {f"{prefix}_mean": mean, f"{prefix}_median": median, f"{prefix}_p84": p84}


def _building_cols(study: Study, record_set: str, bid: str) -> dict:
    b = study.buildings[bid]
    return {
        "record_set": record_set,
        "building": bid,
        "building_kind": b.kind,
        "isolation_period": b.isolation_period,
    }


def _order_key(study: Study):
    sets = study.sets
    bids = list(study.buildings)
    contents = study.contents

    def key(record_set: str, bid: str) -> tuple:
        return (_rank(sets, record_set), _rank(bids, bid))

    return key, contents


def slide_table(study: Study) -> list[dict]:
    """The ``slides`` table (see the module docstring)."""
    groups: dict[tuple, list[tuple]] = defaultdict(list)
    models: dict[str, str] = {}
    for t in study.tasks:
        rs, bid = str(t.meta["record_set"]), str(t.meta["building"])
        record = str(t.meta["record"])
        for c in t.contents:
            models.setdefault(c.content, c.model)
            modes = _pair_modes(c)
            for i in range(len(c.mu_k)):
                key = (rs, bid, int(c.floor), c.content, float(c.mu_k[i]), float(c.mu_s[i]))
                groups[key].append(
                    (
                        record,
                        float(c.peak_slide[i]),
                        float(c.residual_slide[i]),
                        float(c.peak_abs_accel[i]),
                        modes[i],
                    )
                )
    bkey, contents = _order_key(study)
    rows = []
    for key in sorted(
        groups, key=lambda k: (*bkey(k[0], k[1]), k[2], _rank(contents, k[3]), k[4], k[5])
    ):
        rs, bid, floor, content, mu_k, mu_s = key
        obs = _by_record(groups[key])
        peak = np.array([o[1] for o in obs])
        resid = np.abs(np.array([o[2] for o in obs]))
        acc = np.array([o[3] for o in obs])
        finite = np.isfinite(peak)
        row = _building_cols(study, rs, bid)
        row.update(
            floor=floor,
            content=content,
            model=models[content],
            mu_k=mu_k,
            mu_s=mu_s,
            n_records=len(obs),
            n_stats=int(finite.sum()),
            n_slid=int((peak[finite] > 0).sum()),
            n_rocked=sum(o[4] in ROCKING_MODES for o in obs),
        )
        row.update(_stats_cols("peak_slide", peak))
        row.update(_stats_cols("residual_slide", resid))
        row.update(_stats_cols("peak_abs_accel", acc))
        row.update(_stats_cols("peak_abs_accel_g", acc / G))
        rows.append(row)
    return rows


def pfa_table(study: Study) -> list[dict]:
    """The ``pfa`` table (see the module docstring)."""
    groups: dict[tuple, list[tuple[str, float, float]]] = defaultdict(list)
    for t in study.tasks:
        rs, bid = str(t.meta["record_set"]), str(t.meta["building"])
        pga = _float(t.meta.get("pga"))
        for floor, pfa in zip(np.asarray(t.floors).tolist(), np.asarray(t.pfa), strict=True):
            groups[(rs, bid, int(floor))].append((str(t.meta["record"]), float(pfa), pga))
    bkey, _ = _order_key(study)
    rows = []
    for key in sorted(groups, key=lambda k: (*bkey(k[0], k[1]), k[2])):
        rs, bid, floor = key
        obs = _by_record(groups[key])
        pfa = np.array([o[1] for o in obs])
        pga = np.array([o[2] for o in obs])
        amp = np.divide(pfa, pga, out=np.full_like(pfa, np.nan), where=pga > 0)
        row = _building_cols(study, rs, bid)
        row.update(floor=floor, n_records=len(pfa))
        row.update(_stats_cols("pfa", pfa))
        row.update(_stats_cols("pfa_g", pfa / G))
        row["pfa_pga_median"] = summarize(amp)[1]
        rows.append(row)
    return rows


def _stored_damping(study: Study) -> list[float]:
    out: list[float] = []
    for t in study.tasks:
        for s in t.spectra:
            for z in np.atleast_1d(s.damping).tolist():
                if not any(abs(z - d) <= _TOL for d in out):
                    out.append(float(z))
    return out


def _stored_grid(study: Study) -> np.ndarray:
    for t in study.tasks:
        for s in t.spectra:
            return np.asarray(s.periods, dtype=float)
    return np.zeros(0)


def resolve_damping(study: Study, damping: float | None = None) -> float | None:
    """The damping ratio of the FRS ordinates: `damping`, else ``[report] damping``, else 5 %
    if stored, else the first stored one; None when the file holds no spectra.

    Raises
    ------
    ModelError
        `damping` is not among the stored damping ratios (key ``damping``).
    SceneError
        ``[report] damping`` is not among them (key ``report.damping``).
    """
    stored = _stored_damping(study)
    if not stored:
        return None
    listing = ", ".join(f"{z:g}" for z in stored)
    for value, where, err in (
        (damping, "damping", ModelError),
        (study.report.get("damping"), "report.damping", SceneError),
    ):
        if value is None:
            continue
        z = _float(value)
        for d in stored:
            if abs(d - z) <= _TOL:
                return d
        raise err(f"{value!r} is not a stored damping ratio (the file holds {listing})", where)
    for d in stored:
        if abs(d - DEFAULT_DAMPING) <= _TOL:
            return d
    return stored[0]


def resolve_periods(
    study: Study, periods: Sequence[float] | None = None
) -> tuple[tuple[float, ...], list[str]]:
    """The FRS periods of the tables and notes on what was left out.

    `periods`, else ``[report] periods``, else :data:`STANDARD_PERIODS`; only periods inside
    the stored grid (``min ≤ T ≤ max``) are kept, sorted, without duplicates.

    Raises
    ------
    ModelError, SceneError
        A period is not a number ≥ 0 (key ``periods`` or ``report.periods``).
    """
    grid = _stored_grid(study)
    if grid.size == 0:
        return (), []
    if periods is not None:
        asked, where, err = list(periods), "periods", ModelError
    elif "periods" in study.report:
        value = study.report["periods"]
        asked = value if isinstance(value, list) else [value]
        where, err = "report.periods", SceneError
    else:
        asked, where, err = list(STANDARD_PERIODS), "", None
    values = []
    for p in asked:
        x = _float(p)
        if not (math.isfinite(x) and x >= 0):
            raise (err or ModelError)(f"periods must be numbers ≥ 0 s, got {p!r}", where)
        values.append(x)
    lo, hi = float(grid.min()), float(grid.max())
    keep = sorted({x for x in values if lo * (1 - _TOL) <= x <= hi * (1 + _TOL)})
    dropped = sorted({x for x in values if x not in keep})
    notes = []
    if dropped and err is not None:
        notes.append(
            "FRS periods outside the stored grid "
            f"({lo:g}–{hi:g} s) left out: {', '.join(f'{x:g}' for x in dropped)} s"
        )
    return tuple(keep), notes


def interpolate_spectrum(grid: np.ndarray, values: np.ndarray, periods: Sequence[float]):
    """Ordinates at `periods`, interpolated linearly in ``ln T`` between stored periods.

    A period equal to a stored one (to 1e-9 relative) takes its value exactly; periods
    outside the grid give NaN. A stored period 0 (the peak of the motion) is used only for a
    requested period 0.
    """
    grid = np.asarray(grid, dtype=float)
    values = np.asarray(values, dtype=float)
    order = np.argsort(grid)
    grid, values = grid[order], values[order]
    pos = grid > 0
    out = np.full(len(periods), np.nan)
    for j, p in enumerate(periods):
        exact = np.nonzero(np.abs(grid - p) <= _TOL * max(p, 1e-300))[0]
        if exact.size:
            out[j] = values[exact[0]]
        elif p > 0 and pos.sum() >= 2 and grid[pos][0] <= p <= grid[pos][-1]:
            out[j] = np.interp(np.log(p), np.log(grid[pos]), values[pos])
    return out


def frs_table(study: Study, periods: Sequence[float], damping: float | None) -> list[dict]:
    """The ``frs`` table (see the module docstring)."""
    if damping is None or not periods:
        return []
    groups: dict[tuple, list[tuple[str, np.ndarray]]] = defaultdict(list)
    for t in study.tasks:
        rs, bid = str(t.meta["record_set"]), str(t.meta["building"])
        record = str(t.meta["record"])
        for s in t.spectra:
            zs = np.atleast_1d(np.asarray(s.damping, dtype=float))
            hit = np.nonzero(np.abs(zs - damping) <= _TOL)[0]
            if hit.size == 0:
                continue
            psa = np.atleast_2d(np.asarray(s.psa, dtype=float))[hit[0]]
            groups[(rs, bid, int(s.floor))].append(
                (record, interpolate_spectrum(s.periods, psa, periods))
            )
    bkey, _ = _order_key(study)
    rows = []
    for key in sorted(groups, key=lambda k: (*bkey(k[0], k[1]), k[2])):
        rs, bid, floor = key
        stack = np.array([o[1] for o in _by_record(groups[key])])
        for j, p in enumerate(periods):
            _, median, p84 = summarize(stack[:, j])
            row = _building_cols(study, rs, bid)
            row.update(
                floor=floor,
                damping=damping,
                period=float(p),
                n_records=int(np.isfinite(stack[:, j]).sum()),
                psa_median=median,
                psa_p84=p84,
                psa_g_median=median / G,
                psa_g_p84=p84 / G,
            )
            rows.append(row)
    return rows


# --------------------------------------------------------------------------------------------
# comparisons


def parse_comparison(spec: str) -> tuple[str, str]:
    """``"A:B"`` → ``("A", "B")``.

    Raises
    ------
    ValueError
        Not two non-empty building ids separated by one colon.
    """
    parts = spec.split(":") if isinstance(spec, str) else []
    if len(parts) != 2 or not all(p.strip() for p in parts):
        raise ValueError(f"expected A:B with two building ids, e.g. isolated:fixed, got {spec!r}")
    return parts[0].strip(), parts[1].strip()


def _match(study: Study, name: str) -> tuple[str, ...]:
    if name in study.buildings:
        return (name,)
    return tuple(bid for bid, b in study.buildings.items() if b.base == name)


def resolve_comparisons(
    study: Study, compare: Sequence[str] | None = None
) -> tuple[Comparison, ...]:
    """The comparisons of the ratio tables.

    `compare` (``"A:B"`` strings), else ``[report] compare``, else every isolated building
    against its superstructure. ``A`` and ``B`` are building variant ids or base ids, a base
    id matching all its variants (``isolated`` matches ``isolated@T=2``, ``isolated@T=2.5``).

    Raises
    ------
    ModelError
        A `compare` entry is malformed or names a building the file does not hold (key
        ``compare``).
    SceneError
        The same for ``[report] compare`` (key ``report.compare[i]``).
    """
    if compare is not None:
        specs, where, err = list(compare), "compare", ModelError
    elif "compare" in study.report:
        value = study.report["compare"]
        specs = value if isinstance(value, list) else [value]
        where, err = "report.compare", SceneError
    else:
        bases = {}
        for b in study.buildings.values():
            if (
                b.kind == "isolated"
                and b.superstructure
                and b.superstructure in {x.base for x in study.buildings.values()}
            ):
                bases.setdefault(b.base, b.superstructure)
        specs, where, err = [f"{a}:{b}" for a, b in bases.items()], "", ModelError
    known = ", ".join(
        dict.fromkeys([*study.buildings, *(b.base for b in study.buildings.values())])
    )
    out = []
    for j, spec in enumerate(specs):
        at = f"{where}[{j}]" if where == "report.compare" else where
        try:
            a, b = parse_comparison(spec)
        except ValueError as exc:
            raise err(str(exc), at) from None
        sides = []
        for name in (a, b):
            found = _match(study, name)
            if not found:
                raise err(f"unknown building {name!r} in {spec!r} (the file holds: {known})", at)
            sides.append(found)
        out.append(Comparison(spec, sides[0], sides[1]))
    return tuple(out)


def _ratio_rows(
    study: Study, rows: list[dict], comparisons: Sequence[Comparison], keys: Sequence[str], make
) -> list[dict]:
    """Rows of a ratio table: for each comparison, set and (A, B) pair, each row of A with a
    row of B at the same `keys`; `make(row_a, row_b)` gives the statistic columns."""
    index = {(r["record_set"], r["building"], *(r[k] for k in keys)): r for r in rows}
    out = []
    for comp in comparisons:
        for rs in study.sets:
            for a, b in comp.pairs():
                for r in rows:
                    if r["record_set"] != rs or r["building"] != a:
                        continue
                    other = index.get((rs, b, *(r[k] for k in keys)))
                    if other is None:
                        continue
                    row = {
                        "comparison": comp.spec,
                        "record_set": rs,
                        "building_a": a,
                        "building_b": b,
                        "isolation_period_a": study.buildings[a].isolation_period,
                        **{k: r[k] for k in keys},
                    }
                    row.update(make(r, other))
                    out.append(row)
    return out


def slide_ratio_table(
    study: Study, slides: list[dict], comparisons: Sequence[Comparison]
) -> list[dict]:
    """The ``slide_ratios`` table from the ``slides`` rows."""

    def make(a: dict, b: dict) -> dict:
        return {
            "n_stats_a": a["n_stats"],
            "n_stats_b": b["n_stats"],
            "peak_slide_median_a": a["peak_slide_median"],
            "peak_slide_median_b": b["peak_slide_median"],
            "peak_slide_median_ratio": ratio(a["peak_slide_median"], b["peak_slide_median"]),
            "peak_slide_p84_ratio": ratio(a["peak_slide_p84"], b["peak_slide_p84"]),
            "peak_abs_accel_median_ratio": ratio(
                a["peak_abs_accel_median"], b["peak_abs_accel_median"]
            ),
        }

    return _ratio_rows(study, slides, comparisons, ("floor", "content", "mu_k", "mu_s"), make)


def pfa_ratio_table(study: Study, pfa: list[dict], comparisons: Sequence[Comparison]) -> list[dict]:
    """The ``pfa_ratios`` table from the ``pfa`` rows."""

    def make(a: dict, b: dict) -> dict:
        return {
            "pfa_median_a": a["pfa_median"],
            "pfa_median_b": b["pfa_median"],
            "pfa_median_ratio": ratio(a["pfa_median"], b["pfa_median"]),
            "pfa_p84_ratio": ratio(a["pfa_p84"], b["pfa_p84"]),
        }

    return _ratio_rows(study, pfa, comparisons, ("floor",), make)


# --------------------------------------------------------------------------------------------
# the API


def design_tables(
    result: str | Path | ResultFile | Study,
    compare: Sequence[str] | None = None,
    periods: Sequence[float] | None = None,
    damping: float | None = None,
) -> DesignTables:
    """Design tables of a result file (DESIGN §3, ``floorslide table``).

    Parameters
    ----------
    result
        Path of a result file, a :class:`ResultFile` or a :class:`Study`.
    compare
        Comparisons ``"A:B"`` (building variant or base ids) for the ratio tables; default the
        scene's ``[report] compare``, else every isolated building against its
        superstructure.
    periods
        FRS periods (s); default ``[report] periods``, else :data:`STANDARD_PERIODS`. Periods
        outside the stored grid are left out (see ``notes``).
    damping
        FRS damping ratio, one of those stored; default ``[report] damping``, else 0.05 if
        stored, else the first stored.

    Returns
    -------
    DesignTables
        ``tables`` maps ``slides``, ``pfa``, ``frs``, ``slide_ratios``, ``pfa_ratios`` to
        rows (dicts, SI values; columns and units in :data:`COLUMNS`), in a fixed order:
        record sets and buildings as in the scene (isolated variants by period), floors up,
        contents as in the scene, friction ascending.

    Raises
    ------
    ResultFileError
        Missing, corrupt or empty result file.
    ModelError
        A bad `compare`, `periods` or `damping` argument (its ``where`` names the argument).
    SceneError
        A bad ``[report]`` entry of the stored scene (its ``where`` names the key).

    Notes
    -----
    Percentiles are empirical (``numpy.percentile``, ``"linear"``; Hyndman & Fan 1996,
    definition 7). Statistics skip records in which the object rocks (not simulated as a
    slider; Shenton 1996). Ratios are ratios of statistics; ``0/0`` is NaN, ``x/0`` is inf.
    """
    study = load_study(result)
    comparisons = resolve_comparisons(study, compare)
    z = resolve_damping(study, damping)
    chosen, period_notes = resolve_periods(study, periods)
    slides = slide_table(study)
    pfa = pfa_table(study)
    tables = {
        "slides": slides,
        "pfa": pfa,
        "frs": frs_table(study, chosen, z),
        "slide_ratios": slide_ratio_table(study, slides, comparisons),
        "pfa_ratios": pfa_ratio_table(study, pfa, comparisons),
    }
    notes = [
        "units: SI (m, s, m/s**2); columns ending in _g are in g = 9.80665 m/s**2",
        f"statistics over the records of each set; p84 = {PERCENTILE:g}th percentile, "
        "empirical (numpy.percentile, method 'linear')",
        "objects that rock (Shenton 1996) are not simulated as sliders: slide and acceleration "
        "statistics are over the n_stats records whose slide is known (all but mode rock)",
        "residual_slide statistics are of |u(end)|",
        "ratios are ratios of statistics (A / B); 0/0 (neither slides) is NaN, x/0 is inf",
    ]
    if z is not None:
        notes.append(
            f"FRS: PSA at {z:g} damping, interpolated linearly in ln(period) between stored periods"
        )
    notes += period_notes + study.notes
    return DesignTables(
        source=study.source,
        scene_name=study.scene_name,
        periods=chosen,
        damping=z,
        comparisons=comparisons,
        tables=tables,
        notes=tuple(notes),
    )


# --------------------------------------------------------------------------------------------
# formatting


def _md_cell(value, column: Column, row: Mapping) -> str:
    if isinstance(value, float):
        if math.isnan(value):
            rocked = row.get("n_stats") == 0 and row.get("n_rocked", 0) > 0
            if rocked and column.name.endswith(("_mean", "_median", "_p84")):
                return "rocks"
            return "—"
        if math.isinf(value):
            return "∞" if value > 0 else "-∞"
        if column.name in ("mu_k", "mu_s", "period", "damping", "isolation_period"):
            return f"{value:g}"
        return f"{value:.4g}"
    text = str(value)
    return text.replace("|", "\\|")


def _md_heading(column: Column) -> str:
    if column.units in ("", "1"):
        return column.name
    return f"{column.name} ({column.units.replace('**2', '²')})"


def format_markdown_table(name: str, rows: Sequence[Mapping]) -> str:
    """One table as GitHub Markdown; NaN as ``—`` (``rocks`` where every record rocks),
    ``inf`` as ``∞``."""
    cols = COLUMNS[name]
    lines = [
        "| " + " | ".join(_md_heading(c) for c in cols) + " |",
        "|" + "|".join("---" for _ in cols) + "|",
    ]
    for row in rows:
        lines.append("| " + " | ".join(_md_cell(row[c.name], c, row) for c in cols) + " |")
    if not rows:
        lines.append("| " + " | ".join("" for _ in cols) + " |")
    return "\n".join(lines)


def format_markdown(tables: DesignTables, names: Sequence[str] = TABLE_NAMES) -> str:
    """The design tables as one Markdown document: a title, the conventions, one section per
    table."""
    out = [f"# Design tables: {tables.scene_name or Path(tables.source).name}", ""]
    out.append(f"From `{tables.source}`.")
    out.append("")
    for note in tables.notes:
        out.append(f"- {note}")
    if tables.comparisons:
        comps = "; ".join(
            f"{c.spec} ({', '.join(c.a)} over {', '.join(c.b)})" for c in tables.comparisons
        )
        out.append(f"- comparisons: {comps}")
    for name in names:
        out += ["", f"## {TITLES[name]}", ""]
        rows = tables[name]
        if not rows:
            out.append("_No rows._")
            continue
        out.append(format_markdown_table(name, rows))
    return "\n".join(out) + "\n"


def _csv_cell(value) -> str:
    if isinstance(value, float):
        if math.isnan(value):
            return ""
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    return str(value)


def format_csv(name: str, rows: Sequence[Mapping]) -> str:
    """One table as CSV: a header of column names, full-precision numbers, NaN as an empty
    cell, ``inf`` as ``inf``."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    cols = COLUMNS[name]
    writer.writerow([c.name for c in cols])
    for row in rows:
        writer.writerow([_csv_cell(row[c.name]) for c in cols])
    return buf.getvalue()


def format_csv_sections(tables: DesignTables, names: Sequence[str] = TABLE_NAMES) -> str:
    """Several tables as CSV on one stream: each preceded by a line ``# table: NAME`` and
    followed by a blank line."""
    parts = [f"# table: {name}\n{format_csv(name, tables[name])}" for name in names]
    return "\n".join(parts)


def write_csv(tables: DesignTables, directory: str | Path, names: Sequence[str] = TABLE_NAMES):
    """Write one ``NAME.csv`` per table into `directory` (created); returns the paths."""
    directory = Path(directory)
    try:
        directory.mkdir(parents=True, exist_ok=True)
        paths = []
        for name in names:
            path = directory / f"{name}.csv"
            path.write_text(format_csv(name, tables[name]), encoding="utf-8")
            paths.append(path)
    except OSError as exc:
        raise FloorslideError(
            f"cannot write the tables: {exc.strerror or exc}", str(directory)
        ) from None
    return paths


def _json_value(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, np.generic):
        return _json_value(value.item())
    return value


def to_json(tables: DesignTables, names: Sequence[str] = TABLE_NAMES) -> dict:
    """The tables as a JSON-ready dict: ``source``, ``scene``, ``notes``, ``periods``,
    ``damping``, ``comparisons``, ``columns`` (name → list of ``{name, units,
    description}``) and ``tables`` (name → rows); NaN and inf become ``null``."""
    return {
        "source": tables.source,
        "scene": tables.scene_name,
        "notes": list(tables.notes),
        "periods": list(tables.periods),
        "damping": tables.damping,
        "percentile": PERCENTILE,
        "comparisons": [
            {"spec": c.spec, "a": list(c.a), "b": list(c.b)} for c in tables.comparisons
        ],
        "columns": {
            name: [
                {"name": c.name, "units": c.units, "description": c.description}
                for c in COLUMNS[name]
            ]
            for name in names
        },
        "tables": {
            name: [{k: _json_value(v) for k, v in row.items()} for row in tables[name]]
            for name in names
        },
    }


def format_json(tables: DesignTables, names: Sequence[str] = TABLE_NAMES) -> str:
    """:func:`to_json` as text (strict JSON: no NaN)."""
    return json.dumps(to_json(tables, names), indent=1, allow_nan=False)
