"""The accuracy-versus-cost study: every method of every solver on bundled real records, its
error against the exact method and its CPU time (docs/design.md §6).

The exact method is the reference. Its own error floor is measured too: the same exact method on
the same piecewise-linear record sampled at ``dt/2`` (an identical input function, so any
difference is floating-point rounding) — the level below which no error in the table means
anything.
"""

from __future__ import annotations

import csv
import io
import os
import platform
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from importlib.resources import files

import numpy as np
from threadpoolctl import threadpool_limits

from floorslide.bench.cases import FULL, METRICS, QUICK, Ladder, Method, Solver, error, resample
from floorslide.bench.cases import solvers as make_solvers
from floorslide.bench.timing import CompileTimer, Timing, measure
from floorslide.errors import ModelError

RECORDS = ("PET-090", "ELC-180")
"""Bundled SLAMMER records of the default run (catalog ``station_id``): Cape Mendocino 1992,
Petrolia (pulse-like, PGA 0.66 g, 1,800 samples at dt = 0.02 s) and Imperial Valley 1940,
El Centro (broad-band, PGA 0.31 g, 3,949 samples at dt = 0.01 s). ``--quick`` runs the first."""

PAIRS = ("511", "1084")
"""Bundled PEER pairs of horizontal components of the default run for the solvers in the plane
(catalog ``rsn``): N. Palm Springs 1986, Anza - Red Mountain (2,207 samples at dt = 0.005 s)
and Northridge 1994, Sylmar Converter Station (near-fault, PGA 0.92 g, 8,773 samples).
``--quick`` runs the first."""

TIMING = {"quick": (3, 1.0), "full": (7, 4.0)}
"""Timing repeats per method and record, and the CPU budget (s) after which no further repeat
starts (:func:`floorslide.bench.timing.measure`), of the quick and the default study."""

PREFIX = 64
"""Samples of the record the warm-up call runs on."""


@dataclass(frozen=True)
class Record:
    """A bench record: its catalog id, description, samples (m/s²; ``(2, npts)`` for a pair of
    horizontal components) and step (s)."""

    station_id: str
    label: str
    acc: np.ndarray = field(repr=False)
    dt: float

    @property
    def npts(self) -> int:
        """Samples (of each component)."""
        return int(self.acc.shape[-1])

    def to_dict(self) -> dict:
        """What the study reports of it."""
        return dict(
            station_id=self.station_id,
            label=self.label,
            dt=self.dt,
            npts=self.npts,
            components=1 if self.acc.ndim == 1 else int(self.acc.shape[0]),
        )


@dataclass(frozen=True)
class Row:
    """One method at one setting on one solver, over all the records of the study.

    Attributes
    ----------
    solver, method, family, setting, substeps, rtol, grip_hz
        What ran (see :class:`floorslide.bench.cases.Method`).
    cpu_time
        CPU time of the method, summed over the records (each a median over ``repeats``), s.
    time_ratio
        ``cpu_time`` over that of the solver's exact method.
    first_call, compile_time
        Warm-up call (numba compilation or cache loading) and the numba compilation in it, s,
        summed over the records; not part of ``cpu_time``. The exact method's also hold the
        per-record set-up (the floor's PFA that sets the friction values).
    repeats
        Fewest timings any record's median was taken over.
    error
        Headline relative error: the maximum of the solver's metrics. For the exact method, its
        rounding floor (the exact method against itself on the record sampled at dt/2).
    errors
        Relative error per metric (:data:`floorslide.bench.cases.METRICS`).
    """

    solver: str
    method: str
    family: str
    setting: str
    substeps: int | None
    rtol: float | None
    grip_hz: float | None
    cpu_time: float
    time_ratio: float
    first_call: float
    compile_time: float
    repeats: int
    error: float
    errors: dict[str, float]

    def to_dict(self) -> dict:
        """Flat, JSON-ready: one ``err_<metric>`` key per metric of :data:`METRICS` (``None``
        where the metric does not apply)."""
        out = asdict(self)
        errs = out.pop("errors")
        for metric in METRICS:
            out[f"err_{metric}"] = errs.get(metric)
        return out


@dataclass(frozen=True)
class BenchResult:
    """Everything a study produced.

    Attributes
    ----------
    rows
        One per solver and method setting, in the order of :func:`floorslide.bench.cases.solvers`.
    solvers
        ``key → title`` of every solver.
    metrics
        ``solver key → its metric keys``.
    records
        The records used (``station_id``, description, dt, npts, components).
    quick
        Whether this was the ``--quick`` study.
    machine
        Where it ran (platform, Python, CPU count).
    inputs
        ``solver key → the station_id of each record it ran on`` (single records, or pairs of
        components for the solvers in the plane).
    """

    rows: tuple[Row, ...]
    solvers: dict[str, str]
    metrics: dict[str, tuple[str, ...]]
    records: tuple[dict, ...]
    quick: bool
    machine: dict
    inputs: dict[str, tuple[str, ...]] = field(default_factory=dict)

    def records_of(self, solver: str) -> tuple[dict, ...]:
        """The records `solver` ran on."""
        ids = self.inputs.get(solver)
        if ids is None:
            return self.records
        return tuple(r for r in self.records if r["station_id"] in ids)

    @classmethod
    def from_dict(cls, data: dict) -> BenchResult:
        """The study back from :meth:`to_dict` (or a ``bench.json``)."""
        rows = []
        for r in data["rows"]:
            metrics = data["metrics"][r["solver"]]
            fields = {k: r[k] for k in Row.__dataclass_fields__ if k != "errors"}
            nan = float("nan")
            rows.append(
                Row(
                    **{
                        k: (nan if v is None and k in ("time_ratio", "error") else v)
                        for k, v in fields.items()
                    },
                    errors={m: r[f"err_{m}"] for m in metrics},
                )
            )
        return cls(
            rows=tuple(rows),
            solvers=dict(data["solvers"]),
            metrics={k: tuple(v) for k, v in data["metrics"].items()},
            records=tuple(data["records"]),
            quick=bool(data["quick"]),
            machine=dict(data["machine"]),
            inputs={k: tuple(v) for k, v in data.get("inputs", {}).items()},
        )

    def to_dict(self) -> dict:
        """JSON-ready."""
        return dict(
            quick=self.quick,
            machine=self.machine,
            records=list(self.records),
            solvers=self.solvers,
            metrics={k: list(v) for k, v in self.metrics.items()},
            inputs={k: list(v) for k, v in self.inputs.items()},
            rows=[r.to_dict() for r in self.rows],
        )


def load_records(ids: tuple[str, ...]) -> tuple[Record, ...]:
    """The bundled SLAMMER records with these catalog ``station_id`` values, in m/s²."""
    from floorslide.records.catalog import read_catalog

    index = files("floorslide.data") / "records" / "slammer" / "index.csv"
    out = []
    for sid in ids:
        traces = read_catalog(str(index), where={"station_id": sid})
        if len(traces) != 1:
            raise ModelError(f"no single bundled record with station_id {sid!r}", "records")
        tr = traces[0]
        row = tr.stats.catalog
        label = f"{row.event}, {row.station} ({sid})"
        out.append(Record(sid, label, np.ascontiguousarray(tr.data, float), float(tr.stats.delta)))
    return tuple(out)


def load_pairs(rsns: tuple[str, ...]) -> tuple[Record, ...]:
    """The bundled PEER pairs of horizontal components with these catalog ``rsn`` values, in
    m/s², as records of ``(2, npts)`` samples (``station_id`` ``RSN<rsn>``)."""
    from floorslide.records.pairs import read_pairs

    index = files("floorslide.data") / "records" / "pairs" / "index.csv"
    rows = {r["rsn"]: r for r in csv.DictReader(io.StringIO(index.read_text(encoding="utf-8")))}
    out = []
    for rsn in rsns:
        pairs = read_pairs(str(index), where={"rsn": str(rsn)})
        if len(pairs) != 1:
            raise ModelError(f"no single bundled pair with rsn {rsn!r}", "records")
        p, row = pairs[0], rows[str(rsn)]
        sid = f"RSN{rsn}"
        label = f"{row['event']}, {row['station']} ({sid}, {row['comp_h1']}/{row['comp_h2']})"
        acc = np.ascontiguousarray(np.stack([p.h1, p.h2]), dtype=float)
        out.append(Record(sid, label, acc, float(p.dt)))
    return tuple(out)


def run_bench(
    quick: bool = False,
    records: tuple[str, ...] | None = None,
    only: tuple[str, ...] | None = None,
    progress: Callable[[str], None] | None = None,
    pairs: tuple[str, ...] | None = None,
) -> BenchResult:
    """Run the accuracy-versus-cost study.

    Parameters
    ----------
    quick
        The short study (one record, fewer settings and repeats: under a minute on 2 cores).
    records
        Catalog ``station_id`` values of bundled records (default :data:`RECORDS`, or its first
        with `quick`).
    only
        Keys of the solvers to run (default: all).
    progress
        Called with a short message before each method.
    pairs
        Catalog ``rsn`` values of bundled pairs of components for the solvers in the plane
        (default :data:`PAIRS`, or its first with `quick`).

    Returns
    -------
    BenchResult

    Notes
    -----
    CPU time is ``time.process_time`` of this process with the BLAS thread pools limited to
    one thread; see :mod:`floorslide.bench.timing` for warm-up, repeats and compile time.
    """
    ladder: Ladder = QUICK if quick else FULL
    ids = records or (RECORDS[:1] if quick else RECORDS)
    all_solvers = make_solvers(ladder)
    if only:
        unknown = set(only) - {s.key for s in all_solvers}
        if unknown:
            known = ", ".join(s.key for s in all_solvers)
            raise ModelError(f"unknown solver(s) {sorted(unknown)}; expected some of {known}")
        all_solvers = tuple(s for s in all_solvers if s.key in only)
    singles = load_records(tuple(ids)) if any(not s.pair for s in all_solvers) else ()
    rsns = pairs or (PAIRS[:1] if quick else PAIRS)
    doubles = load_pairs(tuple(rsns)) if any(s.pair for s in all_solvers) else ()
    repeats, budget = TIMING["quick" if quick else "full"]
    rows: list[Row] = []
    with threadpool_limits(limits=1):
        for solver in all_solvers:
            recs = doubles if solver.pair else singles
            rows += _run_solver(solver, recs, repeats, budget, progress)
    return BenchResult(
        rows=tuple(rows),
        solvers={s.key: s.title for s in all_solvers},
        metrics={s.key: s.metrics for s in all_solvers},
        records=tuple(r.to_dict() for r in singles + doubles),
        inputs={
            s.key: tuple(r.station_id for r in (doubles if s.pair else singles))
            for s in all_solvers
        },
        quick=quick,
        machine=dict(
            platform=platform.platform(),
            processor=platform.processor() or platform.machine(),
            python=platform.python_version(),
            cpus=os.cpu_count(),
        ),
    )


def _run_solver(
    solver: Solver,
    recs: tuple[Record, ...],
    repeats: int,
    budget: float,
    progress: Callable[[str], None] | None,
) -> list[Row]:
    # per-record settings (friction from the floor's PFA): their first-call and compile time
    # are counted with the exact method's
    with CompileTimer() as setup:
        t0 = time.process_time()
        contexts = [solver.context(r.acc, r.dt) for r in recs]
        setup_time = time.process_time() - t0
    refs: list[dict] = []
    floors: list[dict] = []
    measured: list[tuple[Method, list[Timing], list[dict]]] = []
    for method in solver.methods:
        if progress:
            progress(f"{solver.key}: {method.method} {method.setting}".rstrip())
        timings, results = [], []
        for rec, ctx in zip(recs, contexts, strict=True):
            timing, result = measure(
                lambda m=method, rec=rec, ctx=ctx: m.run(rec.acc, rec.dt, ctx),
                lambda m=method, rec=rec, ctx=ctx: m.run(rec.acc[..., :PREFIX], rec.dt, ctx),
                repeats=repeats,
                budget=budget,
            )
            timings.append(timing)
            results.append(result)
            if method.exact:
                refs.append(result)
                floors.append(_rounding_floor(method, rec, ctx))
        measured.append((method, timings, results))
    t_exact = sum(t.cpu_time for t in measured[0][1])
    rows = []
    for method, timings, results in measured:
        against = floors if method.exact else results
        errs = {
            metric: max(error(metric, got, ref) for got, ref in zip(against, refs, strict=True))
            for metric in solver.metrics
        }
        cpu = sum(t.cpu_time for t in timings)
        rows.append(
            Row(
                solver=solver.key,
                method=method.method,
                family=method.family,
                setting=method.setting,
                substeps=method.substeps,
                rtol=method.rtol,
                grip_hz=method.grip_hz,
                cpu_time=cpu,
                time_ratio=cpu / t_exact if t_exact > 0 else float("nan"),
                first_call=sum(t.first_call for t in timings) + setup_time * method.exact,
                compile_time=sum(t.compile_time for t in timings) + setup.total * method.exact,
                repeats=min(t.repeats for t in timings),
                error=max(errs.values()),
                errors=errs,
            )
        )
    return rows


def _rounding_floor(method: Method, rec: Record, ctx: dict) -> dict:
    """The exact method on the record sampled at dt/2 (the same piecewise-linear function),
    its samples taken back at dt."""
    out = dict(method.run(resample(rec.acc, 2), rec.dt / 2, ctx))
    if "samples" in out:
        out["samples"] = np.asarray(out["samples"])[..., ::2]
    return out
