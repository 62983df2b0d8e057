"""The planner: a scene becomes tasks (record × building), simulating only what is asked for.

Rules (docs/design.md §1), each counted in the plan and printed by ``floorslide run --dry-run``:

- floors nobody asked about (no content, no spectrum there) are not output;
- floor 0 of a fixed-base building is the ground: no building model is stepped for it;
- an object whose floor never reaches ``max(mu_s, mu_k)·g`` (its true peak, inside steps) is
  not integrated: its answer is exactly zero slide and the floor's peak acceleration;
- objects that would rock (Shenton 1996, from width/height: ``mu_s > B/H`` and the floor's true
  peak above ``g·B/H``) are simulated as rocking blocks (:func:`floorslide.rock`: impacts,
  overturning), once per content, floor and task, not as sliders; objects whose floor stays
  below both thresholds rest (exact: no slide, no uplift); without width/height, sliding only;
- vertical shaking and the flexible (2-DOF) model run only where a content declares them.

Records are read, processed and scaled once, here; a record that cannot be read is reported
and the others still run. The per-object rules are decided by :func:`decide`, which the
dry run and the workers share.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from floorslide.constants import G
from floorslide.contents.rocking import response_mode
from floorslide.errors import FloorslideError, RecordError, SceneError, one_line
from floorslide.scene.schema import (
    BuildingSpec,
    ContentSpec,
    RecordSetSpec,
    Scene,
    SpectraSpec,
    record_id_of,
)


@dataclass(frozen=True)
class LoadedRecord:
    """A record of the study, read, processed and scaled (arrays in m/s²)."""

    set: str
    record: str
    label: str
    acc: np.ndarray
    dt: float
    vertical: np.ndarray | None
    scale: float
    meta: dict = field(default_factory=dict)
    qa: tuple[dict, ...] = ()
    """The record's quality flags (:meth:`floorslide.records.quality.Flag.to_dict`; a flag
    of the vertical component has its check prefixed ``vertical:``, of a pair's second
    horizontal component ``h2:``), empty when none tripped."""
    acc2: np.ndarray | None = None
    """A pair's second horizontal component (m/s², as long as ``acc``: the shorter one padded
    with zeros); None for a single component."""
    components: tuple[str, ...] = ()
    """A pair's component names (``("052", "142")``)."""

    @property
    def is_pair(self) -> bool:
        """Whether the record is a pair of horizontal components (blocks slide in the plane)."""
        return self.acc2 is not None

    @property
    def qa_flags(self) -> str:
        """The codes of the flags, comma-separated ("" when none)."""
        return ",".join(f["check"] for f in self.qa)


@dataclass(frozen=True)
class Task:
    """One record on one building: what to output and to simulate."""

    task_id: str
    record: LoadedRecord
    building: BuildingSpec
    floors: tuple[int, ...]
    contents: tuple[tuple[ContentSpec, int], ...]
    spectra_floors: tuple[int, ...]
    spectra: SpectraSpec | None = None
    histories: bool = False


@dataclass
class Plan:
    """Tasks to run and what is skipped, with counts."""

    scene: Scene
    tasks: list[Task]
    records: list[LoadedRecord]
    failures: list[str]
    skipped: Counter = field(default_factory=Counter)
    runs: Counter = field(default_factory=Counter)
    rejected: list[dict] = field(default_factory=list)
    """Records left out by ``[scene] qa = "reject"``: set, record, label and flags."""
    scaling: list[dict] = field(default_factory=list)
    """Per scaled set (``scale`` or ``scale_pga``): its family, level, method, each record's
    factor (and misfit) and, for a target, the suite check (docs/design.md §10e)."""
    evaluated: bool = True
    """Whether the per-object rules were evaluated (and counted) here; else each task decides
    them from its floor's true PFA."""

    def quality(self) -> dict:
        """The quality checks of the study (JSON-ready, stored in the plan): ``action`` (the
        scene's ``qa``), ``flagged`` (records that ran with flags, with their details) and
        ``rejected`` (records left out by ``qa = "reject"``)."""
        seen: set[tuple[str, str]] = set()
        flagged = []
        for r in self.records:
            key = (r.set.split("@")[0], r.record)
            if r.qa and key not in seen:
                seen.add(key)
                flagged.append(dict(set=key[0], record=r.record, label=r.label, flags=list(r.qa)))
        return dict(action=self.scene.qa, flagged=flagged, rejected=list(self.rejected))

    def summary(self) -> dict:
        """JSON-ready plan summary (stored in the result file)."""
        return dict(
            scene=self.scene.name,
            records=len(self.records),
            record_failures=self.failures,
            buildings=[b.id for b in self.scene.buildings],
            tasks=len(self.tasks),
            runs=dict(self.runs),
            skipped=dict(self.skipped),
            quality=self.quality(),
            scaling=self.scaling,
            provenance=self.provenance(),
        )

    def provenance(self) -> list[dict]:
        """Per record of each scene set (once, whatever its scalings): its file and the
        catalog's metadata (event, station, owner, … as the catalog gives them), for reports."""
        seen: set[tuple[str, str]] = set()
        out = []
        for r in self.records:
            key = (r.set.split("@")[0], r.record)
            if key in seen:
                continue
            seen.add(key)
            meta = {k: v for k, v in r.meta.items() if k not in ("set", "record", "file")}
            out.append(dict(set=key[0], record=r.record, file=r.label, **meta))
        return out

    def _scaling_lines(self, rs: RecordSetSpec) -> list[str]:
        """How a set's records were scaled to its target, and its suite check."""
        if rs.scale is None:
            return []
        sc = rs.scale
        how = (
            f"matched at T = {sc.period:g} s"
            if sc.period is not None
            else f"least squares in ln S_a over {sc.period_range[0]:g}–{sc.period_range[1]:g} s"
        )
        lines = [f"    scaled to {sc.target_source} ({how}, damping {sc.damping:g})"]
        for e in self.scaling:
            if e["family"] != rs.set or "suite" not in e:
                continue
            f = [r["factor"] for r in e["records"]]
            wide = sum(r["outside_limits"] for r in e["records"])
            s = e["suite"]
            verdict = "passes" if s["passes"] else "FAILS"
            if e.get("suite_factor", 1.0) > 1.0:
                verdict += f" after raising every record by {e['suite_factor']:.4g} (match_suite)"
            lines.append(
                f"    set {e['set']!r}: factors {min(f):.3g}–{max(f):.3g}"
                + (f" ({wide} outside {sc.limits[0]:g}–{sc.limits[1]:g})" if wide else "")
                + f"; suite mean ≥ 90 % of the target over the range: {verdict} (lowest "
                f"{100 * s['min_ratio']:.0f} % at {s['at']:.3g} s)"
            )
        return lines

    def describe(self) -> str:
        """Human-readable plan: what runs, what is skipped and why, with counts."""
        lines = [
            f"scene {self.scene.name!r}: {len(self.records)} records × "
            f"{len(self.scene.buildings)} buildings = {len(self.tasks)} tasks"
        ]
        for rs in self.scene.records:
            mine = [r for r in self.records if r.set.split("@")[0] == rs.set]
            stripes = len({r.set for r in mine})
            n = str(len({r.record for r in mine}))
            if stripes > 1:
                n += f" × {stripes} scalings = {len(mine)}"
            if rs.pairs:
                lines.append(
                    f"  record set {rs.set!r}: {n} record pairs (two horizontal components: "
                    "blocks slide in the plane)"
                )
            else:
                lines.append(f"  record set {rs.set!r}: {n} records")
            lines += self._scaling_lines(rs)
        for b in self.scene.buildings:
            extra = (
                f", on isolation T_i = {b.period:g} s, ξ_i = {b.damping:g}"
                if b.kind == "isolated"
                else f", T = {b.period:g} s, ξ = {b.damping:g}"
            )
            if b.two_way:
                h2 = [
                    f"{name} = {v:g}"
                    for name, v in (
                        ("T_h2", b.period_h2),
                        ("ξ_h2", b.damping_h2),
                        ("superstructure T_h2", b.super_period_h2),
                        ("superstructure ξ_h2", b.super_damping_h2),
                    )
                    if v == v
                ]
                extra += f"; along h2: {', '.join(h2)}"
            if b.isolator_model not in ("", "linear"):
                params = ", ".join(f"{k} = {v:g}" for k, v in b.isolator if k != "model")
                extra += (
                    f", {b.isolator_model.replace('_', ' ')} ({params}; exact, events inside steps)"
                )
            lines.append(f"  building {b.id!r}: {b.kind}, {b.stories} storeys{extra}")
        if self.scene.warnings:
            lines.append("warnings (valid, but almost surely a mistake):")
            lines += [f"  {warning}" for warning in self.scene.warnings]
        lines.append("runs:")
        for what, count in sorted(self.runs.items()):
            lines.append(f"  {count:7d}  {what}")
        if not self.evaluated and any(t.contents for t in self.tasks):
            lines.append(
                "  (which objects rock and which never slide: each task decides from its "
                "floor's true PFA; `floorslide run --dry-run` counts them beforehand)"
            )
        lines.append("skipped:")
        if not self.skipped:
            lines.append("        0  (nothing)")
        for what, count in sorted(self.skipped.items()):
            lines.append(f"  {count:7d}  {what}")
        for failure in self.failures:
            if not failure.endswith(REJECTED_SUFFIX):  # listed with the quality checks below
                lines.append(f"  unreadable record: {failure}")
        lines += self._describe_quality()
        return "\n".join(lines)

    def _describe_quality(self) -> list[str]:
        """The quality flags of the records, and the records rejected for them."""
        q = self.quality()
        if not q["flagged"] and not q["rejected"]:
            return [f"quality checks: no record flagged (qa = {q['action']!r})"]
        lines = []
        for items, what in (
            (q["flagged"], "records flagged; they run (qa = 'warn')"),
            (q["rejected"], "records rejected, not run (qa = 'reject')"),
        ):
            if not items:
                continue
            lines.append(f"quality checks: {len(items)} {what}:")
            for item in items:
                for f in item["flags"]:
                    fix = f" [remedy: {f['fix_scene']} in [processing]]" if f["fix_scene"] else ""
                    lines.append(
                        f"  {item['set']}/{item['record']}: {f['check']}: {f['message']}{fix}"
                    )
        return lines


REJECTED_SUFFIX = "; [scene] qa = 'reject')"
"""The end of the failure line of a record left out by the quality checks."""

MODE_CODES = {"rest": 0, "slide": 1, "rock": 2, "slide-rock": 3}


def decide(content: ContentSpec, pfa: float, force: bool = False):
    """Per friction pair: Shenton's response mode, and whether it must be integrated.

    Returns ``(modes, integrate, reasons)``: ``modes`` a list of mode names, ``integrate`` a
    boolean array, ``reasons`` a Counter of skip reasons. An object is integrated as a slider
    unless it rocks (``rock`` or ``slide-rock``: it is a slide–rock block instead), or its
    floor's true peak acceleration never exceeds ``max(mu_s, mu_k)·g`` (then its exact answer
    is no slide) — the latter only without vertical shaking, whose friction limit varies. With
    `force` everything that is not rocking is integrated (to check the rules).
    """
    mu = np.asarray(content.mu, dtype=float)
    mu_s = np.asarray(content.mu_s if content.mu_s else content.mu, dtype=float)
    mub = np.maximum(mu, mu_s)
    modes = []
    integrate = np.ones(mu.size, dtype=bool)
    reasons: Counter = Counter()
    for i in range(mu.size):
        if content.width is not None:
            mode = response_mode(content.width, content.height, float(mu_s[i]), float(pfa))
        else:
            mode = "slide" if pfa > mub[i] * G else "rest"
        modes.append(mode)
        if mode in ("rock", "slide-rock") and content.vertical:
            reasons[
                "objects with vertical = true that rock: rocked without the vertical shaking "
                "(not modelled for rocking)"
            ] += 1
        if mode in ("rock", "slide-rock") and content.direction != "both":
            reasons[
                "objects with one-way sliding that rock: their slide–rock blocks slide both ways "
                "(one-way sliding is not modelled for rocking)"
            ] += 1
        if mode in ("rock", "slide-rock"):
            integrate[i] = False
            reasons[
                "objects that rock (Shenton 1996: mu_s ≥ B/H, floor PFA > g·B/H): simulated as "
                "slide–rock blocks (fs.slide_rock), not as sliders"
            ] += 1
        elif not force and not content.vertical and content.model == "rigid" and pfa <= mub[i] * G:
            integrate[i] = False
            reasons[
                "objects whose floor never reaches mu_s·g: exact zero slide, not integrated"
            ] += 1
    return modes, integrate, reasons


def _quality(tr, vtr, periods) -> tuple[dict, ...]:
    """The quality flags of a record as it will run (processed), its vertical component's
    prefixed ``vertical:``."""
    from floorslide.records.quality import check_record

    flags = [f.to_dict() for f in check_record(tr.data, tr.stats.delta, periods=periods).flags]
    if vtr is not None:
        for f in check_record(vtr.data, vtr.stats.delta).flags:
            flags.append({**f.to_dict(), "check": f"vertical:{f.check}"})
    return tuple(flags)


FAILURE_CHARS = 300
"""Longest description of a record that failed, as the plan (stored in the result file) keeps
it: the reason on one line, never the raw text of a damaged file."""


class _Failures(list):
    """The failures of a plan: each a one-line description of at most :data:`FAILURE_CHARS`
    characters (control characters escaped; a longer one is cut, ``…``)."""

    def append(self, text: object) -> None:
        line = one_line(str(text))
        super().append(line if len(line) <= FAILURE_CHARS else line[: FAILURE_CHARS - 1] + "…")


def _rejected(rs, record_id, label, flags, failures, rejected) -> None:
    """A record left out by ``[scene] qa = "reject"``: listed in `rejected` and `failures`."""
    if rejected is not None:
        rejected.append(dict(set=rs.set, record=record_id, label=label, flags=list(flags)))
    codes = ", ".join(f["check"] for f in flags)
    failures.append(f"{label}: rejected by the quality checks ({codes}{REJECTED_SUFFIX}")


def _scalings(rs: RecordSetSpec, pga: float, spectrum=None):
    """``(set name, factor, info)`` per scaling of a set.

    ``scale_pga``: PGA to that many g (a list makes one set per value, ``set@0.3g``).
    ``scale``: the factor fitting the record's spectrum to the target (docs/design.md §10e,
    :func:`floorslide.practice.target.scale_factor`) times each level (a list makes one set per
    level, ``set@1.5x``); `spectrum` is a callable giving the record's PSA (g) on the scale's
    period grid. ``info`` is what the result file keeps of the scaling (None without one).
    """
    if rs.scale is not None:
        from floorslide.practice.target import outside_limits, scale_factor

        sc = rs.scale
        psa = spectrum()
        fit = scale_factor(
            sc.grid(),
            psa,
            sc.target,
            period_range=None if sc.period is not None else sc.period_range,
            period=sc.period,
            limits=sc.limits,
        )
        levels = sc.levels or (1.0,)
        for level in levels:
            factor = level * fit.factor
            name = rs.set if len(levels) == 1 and not sc.levels else f"{rs.set}@{level:g}x"
            yield (
                name,
                factor,
                dict(
                    level=level,
                    fit_factor=fit.factor,
                    misfit=fit.misfit,
                    outside_limits=outside_limits(factor, sc.limits),
                    psa=psa,
                ),
            )
        return
    scales = rs.scale_pga or (None,)
    for sc in scales:
        factor = 1.0 if sc is None else (sc * G / pga if pga > 0 else 1.0)
        info = None if sc is None else dict(level=sc)
        yield (rs.set if sc is None or len(scales) == 1 else f"{rs.set}@{sc:g}g"), factor, info


class _ScaleGridError(Exception):
    """A set's ``scale`` asks for spectra below what its records' dt allows: a scene error
    (:func:`plan` names the key), not a failure of each record."""

    def __init__(self, key: str, message: str):
        self.key = key
        super().__init__(message)


def _check_scale_grid(rs: RecordSetSpec, dt: float, label: str) -> None:
    """Raise :class:`_ScaleGridError` when `rs`'s scaling spectra reach below ``dt/1000``
    (:data:`floorslide.spectra.core.MIN_PERIOD_STEPS`) of a record of step `dt`."""
    from floorslide.spectra.core import MIN_PERIOD_STEPS

    sc = rs.scale
    if sc is None:
        return
    lo = float(sc.period_range[0])
    if lo < dt / MIN_PERIOD_STEPS:
        # a `period` alone makes the range 0.2·T–2·T (scene.schema._scale)
        about = sc.period is not None and tuple(sc.period_range) == (
            0.2 * sc.period,
            2.0 * sc.period,
        )
        how = " (0.2·T)" if about else ""
        raise _ScaleGridError(
            "period" if about else "periods",
            f"the records' spectra would reach down to {lo:g} s{how}, below dt/"
            f"{MIN_PERIOD_STEPS} = {dt / MIN_PERIOD_STEPS:g} s of record {label} (dt = {dt:g} s)",
        )


def _record_spectrum(rs: RecordSetSpec, acc, dt: float, acc2=None):
    """A callable: the record's spectrum on `rs.scale`'s grid, g — PSA of one component, the
    maximum-direction spectrum RotD100 of a pair (ASCE 7-22 §16.2.3.2)."""

    def psa() -> np.ndarray:
        sc = rs.scale
        if acc2 is None:
            from floorslide.spectra.core import response_spectrum

            return response_spectrum(acc, dt, sc.grid(), sc.damping).psa[0] / G
        from floorslide.spectra.rotd import rotd_spectrum

        got = rotd_spectrum((acc, acc2), dt, sc.grid(), sc.damping, directions=False)
        return np.asarray(got.rotd100)[0] / G

    return psa


class _Scaling:
    """What the planner keeps of each scaled set, for the result file (docs/design.md §10e)."""

    def __init__(self) -> None:
        self.sets: dict[str, dict] = {}
        self.spectra: dict[str, list[np.ndarray]] = {}

    def add(self, rs: RecordSetSpec, set_name: str, record_id: str, factor: float, info):
        if info is None:
            return
        entry = self.sets.get(set_name)
        if entry is None:
            entry = dict(set=set_name, family=rs.set, level=info["level"], records=[])
            if rs.scale is not None:
                sc = rs.scale
                entry.update(
                    method="period" if sc.period is not None else "range",
                    im="multiple of the target spectrum",
                    target=sc.target.name,
                    target_source=sc.target_source,
                    period_range=list(sc.period_range),
                    period=sc.period,
                    damping=sc.damping,
                    limits=list(sc.limits),
                    levels=list(sc.levels),
                )
            else:
                entry.update(method="pga", im="PGA (g)", levels=list(rs.scale_pga))
            self.sets[set_name] = entry
            self.spectra[set_name] = []
        rec = dict(record=record_id, factor=float(factor))
        if "misfit" in info:
            rec.update(
                fit_factor=float(info["fit_factor"]),
                misfit=float(info["misfit"]),
                outside_limits=bool(info["outside_limits"]),
            )
            self.spectra[set_name].append(np.asarray(info["psa"]) * factor)
        entry["records"].append(rec)

    def match_suite(self, rs: RecordSetSpec, records: list[LoadedRecord]) -> list[LoadedRecord]:
        """Raise every record of each of `rs`'s sets by one common factor so that the suite's
        mean spectrum is ≥ 90 % of the target over the range (``match_suite = true``; ASCE
        7-22 §16.2.3): ``c = max(1, 0.9 / min ratio)``, stored as ``suite_factor``."""
        import dataclasses

        from floorslide.practice.target import SUITE_FRACTION, outside_limits, suite_check

        sc = rs.scale
        common: dict[str, float] = {}
        for name, entry in self.sets.items():
            if entry["family"] != rs.set or not self.spectra[name]:
                continue
            mean = np.mean(self.spectra[name], axis=0) / entry["level"]
            _, ratio, _ = suite_check(sc.grid(), mean, sc.target, sc.period_range)
            c = max(1.0, SUITE_FRACTION / ratio) if ratio > 0 else 1.0
            common[name] = c
            entry["suite_factor"] = c
            for rec in entry["records"]:
                rec["factor"] *= c
                rec["outside_limits"] = outside_limits(rec["factor"], sc.limits)
            self.spectra[name] = [p * c for p in self.spectra[name]]
        out = []
        for r in records:
            c = common.get(r.set, 1.0)
            if c == 1.0:
                out.append(r)
                continue
            out.append(
                dataclasses.replace(
                    r,
                    acc=r.acc * c,
                    vertical=None if r.vertical is None else r.vertical * c,
                    acc2=None if r.acc2 is None else r.acc2 * c,
                    scale=r.scale * c,
                )
            )
        return out

    def finish(self, scene: Scene) -> list[dict]:
        """The entries with each target-scaled set's suite check (ASCE 7-22 §16.2.3: mean
        spectrum ≥ 90 % of the target over the range), warning of factors outside the
        limits."""
        import warnings

        from floorslide.errors import FloorslideWarning
        from floorslide.practice.target import suite_check

        specs = {rs.set: rs for rs in scene.records}
        out = []
        for name, entry in self.sets.items():
            rs = specs[entry["family"]]
            psa = self.spectra[name]
            if rs.scale is not None and psa:
                sc = rs.scale
                grid = sc.grid()
                mean = np.mean(psa, axis=0) / entry["level"]
                target = sc.target(grid)
                passes, ratio, at = suite_check(grid, mean, sc.target, sc.period_range)
                entry.update(
                    suite=dict(passes=passes, min_ratio=ratio, at=at),
                    periods=grid.tolist(),
                    mean_psa=(mean * entry["level"]).tolist(),
                    target_psa=(target * entry["level"]).tolist(),
                )
                wide = [r for r in entry["records"] if r["outside_limits"]]
                if wide:
                    lo, hi = sc.limits
                    shown = ", ".join(f"{r['record']} ({r['factor']:.3g})" for r in wide[:3])
                    warnings.warn(
                        f"set {name!r}: {len(wide)} of {len(entry['records'])} scale factors "
                        f"lie outside {lo:g}–{hi:g}: {shown}{', …' if len(wide) > 3 else ''}",
                        FloorslideWarning,
                        stacklevel=2,
                    )
            out.append(entry)
        return out


def _load_set(
    rs: RecordSetSpec,
    processing: dict,
    failures: list[str],
    periods: tuple[float, ...] = (),
    qa: str = "warn",
    rejected: list[dict] | None = None,
    scaling: _Scaling | None = None,
) -> list[LoadedRecord]:
    """The records of a set, read, processed, checked (:mod:`floorslide.records.quality`,
    against the scene's spectra `periods`) and scaled; with ``qa = "reject"`` a flagged record
    is left out and added to `rejected`."""
    from floorslide.records.catalog import load_catalog
    from floorslide.records.process import process
    from floorslide.records.read import read_record

    if rs.pairs:
        return _load_pairs(rs, processing, failures, periods, qa, rejected, scaling)
    sources = []
    if rs.catalog:
        try:
            for entry in load_catalog(rs.catalog, where=rs.where or None):
                sources.append((record_id_of(entry.path), str(entry.path.resolve()), entry.read))
        except RecordError as exc:
            failures.append(str(exc))
            return []
    for f in rs.files:

        def reader(f=f):
            return read_record(f, format=rs.format, units=rs.units, dt=rs.dt)

        sources.append((record_id_of(f), f, reader))
    out = []
    for record_id, label, reader in sources:
        try:
            stream = reader()
            vert = None
            if rs.component is not None:
                picked = [tr for tr in stream if tr.stats.channel.endswith(rs.component)]
                if not picked:
                    raise RecordError(f"no component {rs.component!r}", label)
                horizontal = picked[0]
            else:
                horizontal = stream[0]
            vtr = None
            if rs.vertical_component is not None:
                picked = [tr for tr in stream if tr.stats.channel.endswith(rs.vertical_component)]
                if not picked:
                    raise RecordError(f"no vertical component {rs.vertical_component!r}", label)
                vtr = picked[0]
            tr = process(horizontal, **processing) if processing else horizontal
            if rs.vertical_component is not None:
                vtr = process(vtr, **processing) if processing else vtr
                if vtr.stats.npts != tr.stats.npts or vtr.stats.delta != tr.stats.delta:
                    raise RecordError(
                        "vertical and horizontal components differ in dt or length", label
                    )
                vert = np.asarray(vtr.data, dtype=float)
        except FloorslideError as exc:
            failures.append(str(exc) if isinstance(exc, RecordError) else f"{label}: {exc}")
            continue
        flags = _quality(tr, vtr, periods)
        if flags and qa == "reject":
            _rejected(rs, record_id, label, flags, failures, rejected)
            continue
        acc = np.asarray(tr.data, dtype=float)
        pga = float(np.abs(acc).max())
        catalog_meta = dict(getattr(tr.stats, "catalog", {}) or {})
        _check_scale_grid(rs, float(tr.stats.delta), label)
        try:
            scalings = list(_scalings(rs, pga, _record_spectrum(rs, acc, float(tr.stats.delta))))
        except FloorslideError as exc:
            failures.append(f"{label}: {exc}")
            continue
        for set_name, factor, info in scalings:
            if not _scaled_ok(label, set_name, factor, (acc, vert), failures):
                continue
            if scaling is not None:
                scaling.add(rs, set_name, record_id, factor, info)
            out.append(
                LoadedRecord(
                    set=set_name,
                    record=record_id,
                    label=label,
                    acc=acc * factor,
                    dt=float(tr.stats.delta),
                    vertical=None if vert is None else vert * factor,
                    scale=factor,
                    meta={k: str(v) for k, v in catalog_meta.items()},
                    qa=flags,
                )
            )
    return out


def _scaled_ok(label: str, set_name: str, factor: float, arrays, failures: list[str]) -> bool:
    """Whether a record scaled by `factor` (its components `arrays`, None where absent) is one
    the solvers take: a finite factor, samples finite and within
    :data:`~floorslide.constants.MAX_ACCELERATION`. If not, the record is a failure of its own
    (named, with the factor) — never a run on overflowing numbers that reads "no slide"."""
    from floorslide.inputs import check_amplitude

    try:
        if not np.isfinite(factor) or factor <= 0:
            raise RecordError(f"scale factor {factor!r} is not a finite positive number")
        with np.errstate(over="ignore", invalid="ignore"):
            peak = max(float(np.abs(a).max()) * factor for a in arrays if a is not None)
        check_amplitude(peak)
    except FloorslideError as exc:
        how = "" if factor == 1.0 else f"scaled by {factor:.4g} ({set_name}), "
        failures.append(f"{label}: {how}{exc.message}")
        return False
    return True


def _load_pairs(
    rs: RecordSetSpec,
    processing: dict,
    failures: list[str],
    periods: tuple[float, ...],
    qa: str,
    rejected: list[dict] | None,
    scaling: _Scaling | None = None,
) -> list[LoadedRecord]:
    """The pairs of a catalog of components (:func:`floorslide.records.pairs.pair_rows`): each
    component read, processed and checked as a record of its own, the shorter padded with
    zeros to the longer (said in ``meta["pair_notes"]``), and both scaled by one factor — the
    larger component's PGA to ``scale_pga``."""
    from floorslide.pair import make_pair
    from floorslide.records.pairs import check_components, pair_rows
    from floorslide.records.process import process

    try:
        rows = pair_rows(rs.catalog, rs.where or None)
    except RecordError as exc:
        failures.append(str(exc))
        return []
    out = []
    for row in rows:
        label = f"{rs.catalog}:{row['line']}"
        try:
            traces = []
            for key in ("h1", "h2", "v"):
                e = row[key]
                if e is None:
                    traces.append(None)
                    continue
                stream = e.read()
                if len(stream) != 1:
                    raise RecordError(f"{len(stream)} traces; a component takes one", e.where)
                traces.append(stream[0])
            names = (row["h1"].path.name, row["h2"].path.name)
            check_components(traces[0], traces[1], *names, label)
            if processing:
                traces = [tr if tr is None else process(tr, **processing) for tr in traces]
            t1, t2, tv = traces
            pair = make_pair(
                t1.data,
                t2.data,
                float(t1.stats.delta),
                None if tv is None else tv.data,
                names=(row["h1"].row.get("comp") or "h1", row["h2"].row.get("comp") or "h2"),
                label=label,
                dt2=float(t2.stats.delta),
                dt_v=None if tv is None else float(tv.stats.delta),
            )
        except FloorslideError as exc:
            failures.append(str(exc) if isinstance(exc, RecordError) else f"{label}: {exc}")
            continue
        flags = list(_quality(t1, tv, periods))
        from floorslide.records.quality import check_record

        for f in check_record(t2.data, t2.stats.delta, periods=periods).flags:
            flags.append({**f.to_dict(), "check": f"h2:{f.check}"})
        flags = tuple(flags)
        record_id = row["id"]
        if flags and qa == "reject":
            _rejected(rs, record_id, label, flags, failures, rejected)
            continue
        pga = float(max(np.abs(pair.h1).max(), np.abs(pair.h2).max()))
        _check_scale_grid(rs, pair.dt, label)
        meta = {k: str(v) for k, v in row["h1"].row.items() if k not in ("file", "comp")}
        meta["files"] = f"{row['h1'].path.name} + {row['h2'].path.name}"
        if pair.notes:
            meta["pair_notes"] = "; ".join(pair.notes)
        try:
            scalings = list(_scalings(rs, pga, _record_spectrum(rs, pair.h1, pair.dt, pair.h2)))
        except FloorslideError as exc:
            failures.append(f"{label}: {exc}")
            continue
        for set_name, factor, info in scalings:
            if not _scaled_ok(label, set_name, factor, (pair.h1, pair.h2, pair.vertical), failures):
                continue
            if scaling is not None:
                scaling.add(rs, set_name, record_id, factor, info)
            out.append(
                LoadedRecord(
                    set=set_name,
                    record=record_id,
                    label=label,
                    acc=pair.h1 * factor,
                    dt=pair.dt,
                    vertical=None if pair.vertical is None else pair.vertical * factor,
                    scale=factor,
                    meta=meta,
                    qa=flags,
                    acc2=pair.h2 * factor,
                    components=pair.names,
                )
            )
    return out


def _check_short_periods(scene: Scene, records: list[LoadedRecord]) -> None:
    """Spectra periods below ``dt/1000`` of a record (known once the records are read and
    processed) would need absurd sub-step counts: an invalid scene, before anything runs."""
    from floorslide.spectra.core import MIN_PERIOD_STEPS

    if scene.spectra is None or not records:
        return
    positive = [T for T in scene.spectra.periods if T > 0]
    coarsest = max(records, key=lambda r: r.dt)
    if positive and min(positive) < coarsest.dt / MIN_PERIOD_STEPS:
        raise SceneError(
            f"spectra.periods: {min(positive):g} s is below dt/{MIN_PERIOD_STEPS} = "
            f"{coarsest.dt / MIN_PERIOD_STEPS:g} s of record {coarsest.label} (dt = "
            f"{coarsest.dt:g} s); its oscillator would need over {MIN_PERIOD_STEPS} sub-steps "
            "per step (0 gives the peak acceleration)",
            scene.path,
        )


def _building_key(scene: Scene, base: str) -> str:
    """The key path ``buildings[i]`` of the scene's building table with id `base`."""
    import tomllib

    try:
        tables = tomllib.loads(scene.text).get("buildings", [])
    except (tomllib.TOMLDecodeError, AttributeError, TypeError):
        tables = []
    for i, b in enumerate(tables if isinstance(tables, list) else []):
        if isinstance(b, dict) and b.get("id") == base:
            return f"buildings[{i}]"
    return "buildings"


def _check_buildings(scene: Scene, records: list[LoadedRecord]) -> None:
    """Every building (each direction of a two-way one) can be built — its matrices finite,
    not beyond float64's range — and steps the coarsest record within
    :data:`~floorslide.building.exact.MAX_SUBSTEPS` sub-steps per record step and
    :data:`~floorslide.building.exact.MAX_STEP_BYTES` of states (known once the records are
    read): otherwise a run would give NaN floors read as "no slide", exhaust the memory or the
    user's patience, so it is an invalid scene, one line per building, before anything runs
    (``--dry-run`` says so too)."""
    from floorslide.building.directions import per_direction
    from floorslide.building.plane_isolation import couples_directions, plane_layer
    from floorslide.errors import ModelError

    coarsest = max(records, key=lambda r: r.dt) if records else None
    problems = []
    for b in scene.buildings:
        key = f"{_building_key(scene, b.base)} (building {b.id!r}"
        try:
            if not b.two_way:
                models = (b.build(),)
            elif couples_directions(plane := b.build_plane()):
                models = plane_layer(plane)  # nonlinear isolation in the plane: one layer
            else:
                models = per_direction(plane)
            if coarsest is None:
                continue
            key += f", under record {coarsest.label}"
            for model in models:
                model.substeps(coarsest.dt)
        except ModelError as exc:
            problems.append(f"{key}): {exc.message}")
    if problems:
        raise SceneError(problems, scene.path)


def plan(scene: Scene, *, force: bool = False, evaluate: bool = True) -> Plan:
    """Turn a scene into tasks.

    Parameters
    ----------
    scene
        A validated scene.
    force
        Integrate every object even where the answer is known (to check the skip rules).
    evaluate
        Also evaluate the per-object rules (true PFA per task and floor) so the plan counts them.
    """
    failures: list[str] = _Failures()
    records: list[LoadedRecord] = []
    rejected: list[dict] = []
    periods = tuple(scene.spectra.periods) if scene.spectra is not None else ()
    scaling = _Scaling()
    for i, rs in enumerate(scene.records):
        try:
            got = _load_set(rs, scene.processing, failures, periods, scene.qa, rejected, scaling)
        except _ScaleGridError as exc:
            raise SceneError(f"records[{i}].scale.{exc.key}: {exc}", scene.path) from None
        if rs.scale is not None and rs.scale.match_suite:
            got = scaling.match_suite(rs, got)
        records += got
    _check_short_periods(scene, records)
    _check_buildings(scene, records)
    history = scene.report.get("history_record")
    if history is None and records:
        history = records[0].record
    tasks: list[Task] = []
    p = Plan(
        scene,
        tasks,
        records,
        failures,
        rejected=rejected,
        scaling=scaling.finish(scene),
        evaluated=evaluate,
    )
    if rejected:
        p.skipped["records rejected by the quality checks ([scene] qa = 'reject')"] += len(rejected)
    needs_vertical = [c.id for c in scene.contents if c.vertical]
    if needs_vertical:
        for r in records:
            if r.vertical is None:
                failures.append(
                    f"{r.label}: contents {needs_vertical} need a vertical record; give the set a "
                    f"vertical_component"
                )
        records[:] = [r for r in records if r.vertical is not None or not needs_vertical]
    hist_key = next(((r.set, r.record) for r in records if r.record == history), None)
    for r in records:
        for b in scene.buildings:
            floors_all = set(range(b.stories + 1))
            items = tuple((c, f) for c in scene.contents for f in c.floors_of(b.stories))
            sfloors = scene.spectra.floors_of(b.stories) if scene.spectra else ()
            out = tuple(sorted({f for _, f in items} | set(sfloors)))
            skipped_floors = len(floors_all) - len(out)
            if skipped_floors:
                p.skipped["floor outputs nobody asked for (not output)"] += skipped_floors
            if b.kind == "fixed" and 0 in out:
                p.skipped[
                    "floor-0 outputs of fixed-base buildings: the ground, no building model"
                ] += 1
            # figures compare buildings: the history record keeps histories on every building
            want_hist = (r.set, r.record) == hist_key
            tid = f"t{len(tasks):05d}"
            tasks.append(Task(tid, r, b, out, items, tuple(sfloors), scene.spectra, want_hist))
            p.runs["tasks (record × building)"] += 1
            p.runs["floor spectra"] += len(sfloors)
            for c, _ in items:
                if c.vertical:
                    p.runs["objects with vertical shaking"] += len(c.mu)
    if not any(c.vertical for c in scene.contents):
        p.skipped["vertical shaking: declared by no content, not simulated"] += 1
    if evaluate and tasks:
        from floorslide.building.motions import peak_floor_acceleration
        from floorslide.run import warmup

        # the tasks' kernels compile (fresh install) in processes of their own while this one
        # compiles those of the evaluation below; they are in the disk cache when it returns
        # (the demo from a fresh install, measured: 67 s with none, 60–62 s with the
        # nonlinear family's alone, 53 s with both)
        warming = warmup.start(sorted({warmup.family(t) for t in tasks}))
        for t in tasks:
            if not t.contents:
                continue
            floors = sorted({f for _, f in t.contents})
            if t.record.is_pair:
                from floorslide.building.directions import plane_motions, plane_peak
                from floorslide.building.plane_isolation import (
                    PlaneIsolatedMotion,
                    couples_directions,
                )
                from floorslide.building.poly_peaks import poly_peaks

                model = t.building.build_plane()
                r = t.record
                if couples_directions(model):  # friction pendulums: one coupled motion
                    motion = PlaneIsolatedMotion(model, r.acc, r.acc2, r.dt, keep_segments=True)
                    peaks = poly_peaks(motion, floors).peak.tolist()
                else:
                    peaks = [
                        plane_peak(*plane_motions(model, r.acc, r.acc2, r.dt, f))[0] for f in floors
                    ]
                pfa = dict(zip(floors, peaks, strict=True))
                for c, f in t.contents:
                    _modes, integrate, reasons = decide(c, pfa[f], force)
                    p.skipped.update(reasons)
                    label = (
                        "2-DOF sliding oscillators in the plane"
                        if c.model == "oscillator"
                        else "rigid blocks sliding in the plane"
                    )
                    p.runs[f"{label} (object × floor × task)"] += int(integrate.sum())
                    if any(m in ("rock", "slide-rock") for m in _modes):
                        p.runs["rocking blocks, planar in each component's direction"] += 1
                continue
            model = t.building.build()
            if warming and warmup.family(t) == "nonlinear":
                warmup.finish(warming)  # the nonlinear kernel is among them
                warming = []
            peaks = peak_floor_acceleration(model, t.record.acc, t.record.dt, floors=floors).peak
            pfa = dict(zip(floors, peaks, strict=True))
            for c, f in t.contents:
                heavy = c.floor_mass_ratio is not None and c.coupled
                _modes, integrate, reasons = decide(c, pfa[f], force or heavy)
                p.skipped.update(reasons)
                label = (
                    "heavy equipment coupled with its floor"
                    if heavy
                    else "2-DOF sliding oscillators"
                    if c.model == "oscillator"
                    else "rigid blocks"
                )
                p.runs[f"{label} integrated (object × floor × task)"] += int(integrate.sum())
                if any(m in ("rock", "slide-rock") for m in _modes):
                    how = "linearised" if c.rocking == "exact" else "full equation"
                    p.runs[f"rocking blocks simulated, {how} (content × floor × task)"] += 1
        warmup.finish(warming)
    return p
