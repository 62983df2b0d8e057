"""The per-record table: one row per record × building × floor × content × friction pair, read
from a result file — what the ``slides`` and ``rocking`` design tables summarise, record by
record.

``record_table(path)`` gives it as a :class:`pandas.DataFrame`; ``floorslide table OUT.h5
--per-record`` as CSV (or JSON). Columns and units are in :data:`RECORD_COLUMNS`.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from floorslide.constants import G
from floorslide.report.columns import FLOOR_LABEL, ROCK, Column, floor_label
from floorslide.report.study import Study, _float, _natural, _rank, load_study
from floorslide.run.results import PLANE_FIELDS
from floorslide.run.store import ResultFile

RECORD_COLUMNS: tuple[Column, ...] = (
    Column("record_set", "", "record set (scaled sets are named set@PGAg)"),
    Column("record", "", "record id (file name without extension)"),
    Column("record_file", "", "the record's file"),
    Column("building", "", "building variant id"),
    Column("building_kind", "", "fixed or isolated"),
    Column("isolation_period", "s", "isolation period T_i (NaN for fixed-base)"),
    Column("floor", "1", "floor (0 = ground, or the base mat of an isolated building)"),
    FLOOR_LABEL,
    Column("content", "", "content (equipment) id"),
    Column("model", "", "rigid or oscillator"),
    Column("mu_k", "1", "kinetic friction coefficient"),
    Column("mu_s", "1", "static friction coefficient"),
    Column("mode", "", "Shenton's mode from the floor's PFA: rest, slide, rock or slide-rock"),
    Column(
        "outcome",
        "",
        "rest (no slide), slide or rock (mode rock or slide-rock: simulated as a slide–rock "
        "block, fs.slide_rock, not as a slider — its slide values are that block's, NaN in "
        "files written before for mode rock; what it did: observed_outcome)",
    ),
    Column(
        "peak_slide",
        "m",
        "peak slide max|u| (of the sliding base for an oscillator; in the plane for a pair)",
    ),
    Column("residual_slide", "m", "residual slide u(end), signed; |u(end)| for a pair"),
    Column(
        "peak_abs_accel",
        "m/s**2",
        "peak absolute acceleration of the object (base); NaN where it rocked (not tracked)",
    ),
    Column(
        "peak_abs_accel_g",
        "g",
        "peak absolute acceleration of the object (base); NaN where it rocked (not tracked)",
    ),
    Column("slide_fraction", "1", "fraction of the record spent sliding"),
    Column("slip_phases", "1", "breakaways and reversals (NaN where the object rocks)"),
    Column("peak_deformation", "m", "peak spring deformation max|z| (oscillators; else NaN)"),
    Column("peak_top_accel", "m/s**2", "peak absolute acceleration of the top mass (oscillators)"),
    Column("peak_top_accel_g", "g", "peak absolute acceleration of the top mass (oscillators)"),
    Column("pfa", "m/s**2", "true peak acceleration of the floor under this record"),
    Column("pga", "m/s**2", "peak ground acceleration of the record as run (after scaling)"),
    Column("scale", "1", "factor applied to the record"),
    Column("skipped", "", 'why the object was not integrated ("" when it was)'),
    Column(
        "qa_flags",
        "",
        "the record's quality flags (floorslide.records.quality; see the records table)",
    ),
    Column(
        "isolator_peak_disp_m",
        "m",
        "peak isolator displacement max|u0| under this record (nonlinear isolation; else NaN)",
    ),
    Column(
        "isolator_residual_disp_m",
        "m",
        "residual isolator displacement u0(end), signed (nonlinear isolation; else NaN)",
    ),
    Column(
        "isolator_peak_force_ratio",
        "1",
        "peak isolator force over the weight max|V|/W (nonlinear isolation; else NaN)",
    ),
    Column(
        "isolator_capacity_exceeded",
        "",
        "the isolator displacement exceeds the layer's capacity (the impact that would follow "
        "is not modelled); empty (NaN) without nonlinear isolation",
    ),
    Column(
        "isolator_small_angle_exceeded",
        "",
        "a friction pendulum without a capacity went beyond 0.2·R, where its small-angle "
        "restoring force (W/R)·u is more than 2 % off (False for other layers); empty (NaN) "
        "without nonlinear isolation",
    ),
    Column(
        "rock_peak_ratio",
        "1",
        "peak rotation of the rocking block max|θ|/α (1: it overturned; 0: at rest); NaN where "
        "the object slides instead (mu_s < B/H) or the content has no width and height",
    ),
    Column(
        "rock_impacts",
        "1",
        "impacts while rocking (up to the overturning), the whole cascade of ever smaller "
        "impacts to rest included (thousands for a block that barely tilts: not a count of "
        "rocking cycles); NaN where it slides instead or the "
        "content has no width and height",
    ),
    Column(
        "rock_significant_impacts",
        "1",
        "significant impacts: at |θ'| ≥ p·α·√(f(2 − f)), f = 0.01, the speed of a block "
        "rocking freely back from a tilt of 1 % of α (the cascade to rest left out); NaN where "
        "not applicable or in files written before they were counted",
    ),
    Column("overturned", "1", "1 if the block overturned, else 0; NaN where not applicable"),
    Column("overturn_time_s", "s", "when it overturned (NaN: it did not, or not applicable)"),
    Column("rock_time_s", "s", "time spent rocking (sliding or not); NaN where not applicable"),
    Column(
        "slide_rock_time_s",
        "s",
        "time spent sliding and rocking at once (0 where it slides or rests); NaN where not "
        "applicable and in files written before slide–rock was simulated",
    ),
    Column(
        "observed_outcome",
        "",
        "what the object did in the simulation: rest, slide, rock, slide-rock (it slid and "
        "rocked) or overturn; empty for contents without width and height and in files "
        "written before rocking was simulated",
    ),
    Column(
        "peak_angle",
        "deg",
        "a pair (two horizontal components): direction of the peak slide, from h1 towards h2; "
        "NaN for one component",
    ),
    Column("residual_h1", "m", "a pair: the residual slide along h1 (NaN for one component)"),
    Column("residual_h2", "m", "a pair: the residual slide along h2 (NaN for one component)"),
    Column("peak_slide_h1", "m", "a pair: the 1-D slide of component h1 alone (NaN for one)"),
    Column("peak_slide_h2", "m", "a pair: the 1-D slide of component h2 alone (NaN for one)"),
    Column(
        "ratio_2d_1d",
        "1",
        "a pair: peak_slide / max(peak_slide_h1, peak_slide_h2) (NaN for one component, or "
        "when neither slides)",
    ),
)
"""Columns of the per-record table, in order."""

PLANE_VALUES = PLANE_FIELDS
"""The per-record columns of a pair (NaN for one component): the pair's arrays of a content
result (:data:`~floorslide.run.results.PLANE_FIELDS`)."""

ROCK_VALUES = (
    "rock_peak_ratio",
    "rock_impacts",
    "rock_significant_impacts",
    "overturned",
    "overturn_time_s",
    "rock_time_s",
    "slide_rock_time_s",
)
"""The per-record rocking columns (NaN where not applicable)."""


def _outcome(mode: str, peak: float) -> str:
    """``rock`` for an object that rocks (Shenton's ``rock`` or ``slide-rock``: a slide–rock
    block, its own outcome; NaN slides in older files), else ``slide`` or ``rest``."""
    if mode in (ROCK, "slide-rock") or not math.isfinite(peak):
        return ROCK
    return "slide" if peak > 0 else "rest"


def _modes(c) -> list[str]:
    """Per friction pair: the object's mode under this record (older files: from the values)."""
    n = len(c.mu_k)
    if c.modes is not None and len(c.modes) == n:
        return [str(m) for m in c.modes]
    if c.mode in ("rest", "slide", "rock", "slide-rock"):
        return [c.mode] * n
    return [
        ROCK if not np.isfinite(p) else ("slide" if p > 0 else "rest")
        for p in np.asarray(c.peak_slide, dtype=float)
    ]


def isolator_values(meta: dict) -> dict:
    """The isolator's results of a task as per-record columns: NaN (all five) for a building
    without nonlinear isolation, and for a task written before they were stored."""
    if "isolator_peak_displacement" not in meta:
        return {
            "isolator_peak_disp_m": math.nan,
            "isolator_residual_disp_m": math.nan,
            "isolator_peak_force_ratio": math.nan,
            "isolator_capacity_exceeded": math.nan,
            "isolator_small_angle_exceeded": math.nan,
        }
    return {
        "isolator_peak_disp_m": _float(meta["isolator_peak_displacement"]),
        "isolator_residual_disp_m": _float(meta.get("isolator_residual_displacement")),
        "isolator_peak_force_ratio": _float(meta.get("isolator_peak_force_ratio")),
        "isolator_capacity_exceeded": bool(_float(meta.get("isolator_capacity_exceeded"), 0)),
        "isolator_small_angle_exceeded": bool(_float(meta.get("isolator_small_angle_exceeded"), 0)),
    }


def plane_values(c, i: int) -> dict:
    """The pair columns of friction pair `i` of a content result (NaN for one component)."""
    if getattr(c, "peak_angle", None) is None:
        return dict.fromkeys(PLANE_VALUES, math.nan)
    return {name: float(getattr(c, name)[i]) for name in PLANE_VALUES}


def significant_impacts(c, i: int) -> float:
    """The significant impacts of friction pair `i` of a content result (NaN where not
    applicable, and in files written before they were counted)."""
    big = getattr(c, "rock_significant_impacts", None)
    if big is None or len(big) <= i or big[i] < 0:
        return math.nan
    return float(big[i])


def _slide_rock_time(c, i: int) -> float:
    """The time in slide–rock of friction pair `i` (NaN in files written before it was kept)."""
    t = getattr(c, "slide_rock_time", None)
    return math.nan if t is None or len(t) <= i else float(t[i])


def rocking_values(c, i: int) -> dict:
    """The rocking columns of friction pair `i` of a content result: NaN (and an empty
    ``observed_outcome``) for a content without width and height, a file written before rocking
    was simulated, and a friction pair under which the object slides instead (stored as NaN and
    −1 impacts)."""
    if c.rock_peak_ratio is None or len(c.rock_peak_ratio) <= i:
        out: dict = dict.fromkeys(ROCK_VALUES, math.nan)
        out["observed_outcome"] = ""
        return out
    impacts = float(c.rock_impacts[i])
    observed = c.outcomes[i] if c.outcomes is not None and len(c.outcomes) > i else ""
    return {
        "rock_peak_ratio": float(c.rock_peak_ratio[i]),
        "rock_impacts": impacts if impacts >= 0 else math.nan,
        "rock_significant_impacts": significant_impacts(c, i),
        "overturned": float(c.overturned[i]),
        "overturn_time_s": float(c.overturn_time[i]),
        "rock_time_s": float(c.rock_time[i]),
        "slide_rock_time_s": _slide_rock_time(c, i),
        "observed_outcome": str(observed),
    }


def record_rows(study: Study) -> list[dict]:
    """The per-record rows of a study (dicts keyed by :data:`RECORD_COLUMNS`), in the tables'
    order: record sets, buildings and contents as in the scene, floors up, friction ascending,
    records in natural order."""
    buildings = list(study.buildings)
    rows = []
    for t in study.tasks:
        m = t.meta
        bid = str(m["building"])
        pfa_of = dict(zip(np.asarray(t.floors).tolist(), np.asarray(t.pfa).tolist(), strict=True))
        isolator = isolator_values(m)
        b = study.buildings[bid]
        for c in t.contents:
            modes = _modes(c)
            osc = c.peak_deformation is not None
            for i in range(len(c.mu_k)):
                peak = float(c.peak_slide[i])
                out = _outcome(modes[i], peak)
                acc = float(c.peak_abs_accel[i])
                top = float(c.peak_top_accel[i]) if osc else math.nan
                phases = float(c.slip_phases[i])
                rows.append(
                    {
                        "record_set": str(m["record_set"]),
                        "record": str(m["record"]),
                        "record_file": str(m.get("record_file", "")),
                        "building": bid,
                        "building_kind": study.buildings[bid].kind,
                        "isolation_period": study.buildings[bid].isolation_period,
                        "floor": int(c.floor),
                        "floor_label": floor_label(b.kind, int(c.floor), b.stories),
                        "content": c.content,
                        "model": c.model,
                        "mu_k": float(c.mu_k[i]),
                        "mu_s": float(c.mu_s[i]),
                        "mode": modes[i],
                        "outcome": out,
                        "peak_slide": peak,
                        "residual_slide": float(c.residual_slide[i]),
                        "peak_abs_accel": acc,
                        "peak_abs_accel_g": acc / G,
                        "slide_fraction": float(c.slide_fraction[i]),
                        "slip_phases": math.nan if out == ROCK else phases,
                        "peak_deformation": float(c.peak_deformation[i]) if osc else math.nan,
                        "peak_top_accel": top,
                        "peak_top_accel_g": top / G,
                        "pfa": float(pfa_of.get(int(c.floor), math.nan)),
                        "pga": _float(m.get("pga")),
                        "qa_flags": str(m.get("qa_flags", "") or ""),
                        "scale": _float(m.get("scale")),
                        "skipped": c.skipped,
                        **isolator,
                        **rocking_values(c, i),
                        **plane_values(c, i),
                    }
                )

    def key(r: dict) -> tuple:
        return (
            _rank(study.sets, r["record_set"]),
            _rank(buildings, r["building"]),
            r["floor"],
            _rank(study.contents, r["content"]),
            r["mu_k"],
            r["mu_s"],
            _natural(r["record"]),
        )

    return sorted(rows, key=key)


def record_table(result: str | Path | ResultFile | Study, *, allow_incomplete: bool = False):
    """The per-record table of a result file as a :class:`pandas.DataFrame`.

    One row per record × building × floor × content × friction pair, columns as in
    :data:`RECORD_COLUMNS` (SI values; where the object rocks ``outcome`` says ``rock`` and its
    slide values are its slide–rock block's; for contents with a width and height the block's
    peak rotation, impacts, overturning, time rocking and in slide–rock, and
    ``observed_outcome`` what it did).
    ``df.attrs`` holds ``units`` (column → unit), ``source`` and ``status`` (``""``, or the
    INCOMPLETE label).

    Parameters
    ----------
    result
        Path of a result file, a :class:`ResultFile` or a
        :class:`~floorslide.report.study.Study`.
    allow_incomplete
        Accept a result file whose run is not finished (the DataFrame's ``status`` says
        INCOMPLETE).

    Raises
    ------
    ResultFileError
        Missing, corrupt or empty result file.
    IncompleteResultError
        The run is not finished and `allow_incomplete` is False.

    Examples
    --------
    >>> df = record_table("demo.h5")  # doctest: +SKIP
    >>> df[df.outcome != "rock"].groupby(["building", "mu_k"]).peak_slide.max()  # doctest: +SKIP
    """
    import pandas as pd

    study = load_study(result)
    study.require_complete(allow_incomplete)
    rows = record_rows(study)
    df = pd.DataFrame(rows, columns=[c.name for c in RECORD_COLUMNS])
    df.attrs.update(
        units={c.name: c.units for c in RECORD_COLUMNS},
        source=study.source,
        status=study.status,
    )
    return df


SPECTRA_COLUMNS: tuple[Column, ...] = (
    Column("record_set", "", "record set (scaled sets are named set@PGAg)"),
    Column("record", "", "record id (file name without extension)"),
    Column("building", "", "building variant id"),
    Column("building_kind", "", "fixed or isolated"),
    Column("isolation_period", "s", "isolation period T_i (NaN for fixed-base)"),
    Column("floor", "1", "floor (0 = ground, or the base mat of an isolated building)"),
    FLOOR_LABEL,
    Column("damping", "1", "damping ratio of the oscillator"),
    Column("period", "s", "oscillator period (0: the floor's true peak acceleration)"),
    Column(
        "orientation",
        "",
        "RotD50 for a record pair (psa is then RotD50, Boore 2010; sa and sv NaN); empty for "
        "one component",
    ),
    Column("psa", "m/s**2", "pseudo-spectral acceleration ω²·SD, unbroadened"),
    Column("psa_g", "g", "pseudo-spectral acceleration, unbroadened"),
    Column("sa", "m/s**2", "peak absolute acceleration of the oscillator (NaN for a pair)"),
    Column("sv", "m/s", "peak relative velocity (NaN for a pair)"),
    Column("sd", "m", "peak relative displacement"),
    Column("broadening", "1", "peak broadening ±fraction of psa_broadened (0: none)"),
    Column("psa_broadened", "m/s**2", "PSA broadened by ±broadening in frequency (NaN: none)"),
    Column("rotd100", "m/s**2", "a pair: RotD100, the largest over every direction (else NaN)"),
    Column("psa_h1", "m/s**2", "a pair: the PSA along the first component h1 (else NaN)"),
    Column("psa_h2", "m/s**2", "a pair: the PSA along the second component h2 (else NaN)"),
)
"""Columns of the per-record floor spectra, in order."""


def _spectrum_values(values, i: int, n: int) -> np.ndarray:
    if values is None:
        return np.full(n, math.nan)
    return np.atleast_2d(np.asarray(values, dtype=float))[i]


def spectra_rows(study: Study, damping: float | None = None) -> list[dict]:
    """The per-record floor spectra of a study (dicts keyed by :data:`SPECTRA_COLUMNS`): one
    row per record × building × floor × damping ratio × stored period, in the tables' order
    (record sets and buildings as in the scene, floors up, damping and periods ascending,
    records in natural order); only `damping` when given."""
    buildings = list(study.buildings)
    rows = []
    for t in study.tasks:
        m = t.meta
        bid = str(m["building"])
        b = study.buildings[bid]
        for s in t.spectra:
            periods = np.atleast_1d(np.asarray(s.periods, dtype=float))
            zetas = np.atleast_1d(np.asarray(s.damping, dtype=float))
            n = periods.size
            orientation = str(getattr(s, "orientation", "") or "")
            for i, z in enumerate(zetas.tolist()):
                if damping is not None and abs(z - damping) > 1e-9:
                    continue
                cols = {
                    name: _spectrum_values(getattr(s, name, None), i, n)
                    for name in ("psa", "sa", "sv", "sd", "psa_broadened", "rotd100")
                }
                cols["psa_h1"] = _spectrum_values(getattr(s, "psa_h1", None), i, n)
                cols["psa_h2"] = _spectrum_values(getattr(s, "psa_h2", None), i, n)
                for j, p in enumerate(periods.tolist()):
                    rows.append(
                        {
                            "record_set": str(m["record_set"]),
                            "record": str(m["record"]),
                            "building": bid,
                            "building_kind": b.kind,
                            "isolation_period": b.isolation_period,
                            "floor": int(s.floor),
                            "floor_label": floor_label(b.kind, int(s.floor), b.stories),
                            "damping": float(z),
                            "period": float(p),
                            "orientation": orientation,
                            "psa": float(cols["psa"][j]),
                            "psa_g": float(cols["psa"][j]) / G,
                            "sa": float(cols["sa"][j]),
                            "sv": float(cols["sv"][j]),
                            "sd": float(cols["sd"][j]),
                            "broadening": float(s.broadening or 0.0),
                            "psa_broadened": float(cols["psa_broadened"][j]),
                            "rotd100": float(cols["rotd100"][j]),
                            "psa_h1": float(cols["psa_h1"][j]),
                            "psa_h2": float(cols["psa_h2"][j]),
                        }
                    )

    def key(r: dict) -> tuple:
        return (
            _rank(study.sets, r["record_set"]),
            _rank(buildings, r["building"]),
            r["floor"],
            r["damping"],
            r["period"],
            _natural(r["record"]),
        )

    return sorted(rows, key=key)


def spectra_table(
    result: str | Path | ResultFile | Study,
    *,
    damping: float | None = None,
    allow_incomplete: bool = False,
):
    """The floor response spectra of a result file, record by record, as a
    :class:`pandas.DataFrame` — what the ``frs`` table summarises.

    One row per record × building × floor × damping ratio × stored period (long form: pivot
    it for one column per record), columns as in :data:`SPECTRA_COLUMNS` (SI values;
    ``psa_g`` in g). For a record pair ``psa`` is RotD50 (``orientation``), ``rotd100``,
    ``psa_h1`` and ``psa_h2`` beside it. ``df.attrs`` holds ``units`` (column → unit),
    ``source`` and ``status`` (``""``, or the INCOMPLETE label).

    Parameters
    ----------
    result
        Path of a result file, a :class:`ResultFile` or a
        :class:`~floorslide.report.study.Study`.
    damping
        Keep only this damping ratio (default: every stored one).
    allow_incomplete
        Accept a result file whose run is not finished (``status`` says INCOMPLETE).

    Raises
    ------
    ResultFileError
        Missing, corrupt or empty result file.
    IncompleteResultError
        The run is not finished and `allow_incomplete` is False.

    Examples
    --------
    >>> df = spectra_table("demo.h5", damping=0.05)  # doctest: +SKIP
    >>> df[df.floor_label == "roof"].pivot_table("psa_g", "period", "record")  # doctest: +SKIP
    """
    import pandas as pd

    study = load_study(result)
    study.require_complete(allow_incomplete)
    rows = spectra_rows(study, damping)
    df = pd.DataFrame(rows, columns=[c.name for c in SPECTRA_COLUMNS])
    df.attrs.update(
        units={c.name: c.units for c in SPECTRA_COLUMNS},
        source=study.source,
        status=study.status,
    )
    return df
