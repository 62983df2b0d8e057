"""Design tables from a result file: statistics over record sets and ratios between buildings.

Everything here reads the result file only (docs/design.md §5) through
:class:`~floorslide.report.study.Study` and returns plain rows; :mod:`floorslide.report.formats`
writes them as Markdown, CSV, JSON or pandas DataFrames (docs/design.md §3, ``floorslide table``).

Tables (one row per …, statistics over the records of a set; units in :data:`COLUMNS`):

``slides``
    record set × building × floor × content × friction pair: number of records, how many made
    the object slide, rock or slide-rock; mean, median and 84th percentile of the peak slide, of
    the absolute residual slide and of the peak absolute acceleration of the object (m/s² and
    g; of the sliding base for a 2-DOF oscillator) and, for oscillators, of the peak spring
    deformation and of the top mass's peak absolute acceleration.
``pfa``
    record set × building × floor: peak floor acceleration (true peak, inside steps).
``frs``
    record set × building × floor × period: median and 84th percentile of the floor's
    pseudo-spectral acceleration at the report periods and damping, unbroadened and (when the
    scene asked for it) broadened.
``slide_ratios`` and ``pfa_ratios``
    comparison ``A:B`` × record set × floor (× content × friction pair): the statistic of
    building A divided by that of building B, for every variant of A and of B.
``records``
    record set × record: dt, samples, PGA as run, scale, and the record's quality flags
    (:mod:`floorslide.records.quality`) with their numbers; records rejected by ``[scene] qa =
    "reject"`` follow with status ``rejected``.
``isolators``
    record set × building on nonlinear isolation: the layer (model, period, damping and its
    parameters), median and 84th percentile of the peak isolator displacement, its largest
    value, median |residual| displacement, median and 84th percentile of the peak isolator
    force over the weight (V/W), and how many records take the layer beyond its capacity
    (the impact that would follow is not modelled: the ``note`` says so). Empty, with a note,
    when no building is on nonlinear isolation.
``plane``
    record set of pairs (two horizontal components) × building × floor × content × friction
    pair: the median and 84th percentile of the peak slide in the plane (2-D) next to those of
    the larger of the two components' 1-D slides, the ratio of the medians, and the median,
    smallest and largest per-record ratio 2-D / max(1-D). Empty, with a note, without pairs.
``rocking``
    record set × building × floor × content × friction pair with a width and height whose
    static friction holds its corner (``mu_s ≥ B/H``: it rocks rather than slides, Shenton
    1996; simulated as a slide–rock block, :func:`floorslide.slide_rock`, which slides while it
    rocks once the friction it needs exceeds ``mu_s``): the slenderness, how many records made
    it rock, overturn, and slide while rocking, the median and 84th percentile over every
    record of its peak rotation ``max|θ|/α`` (0 at rest, 1 when it overturned), the median
    number of impacts and the median time in slide–rock. Empty, with a note, without such a
    content (or in a file written before rocking was simulated).

``scaling``, ``suite``, ``code``, ``exceedance``, ``fragility``
    the design-practice tables (docs/design.md §10e): :mod:`floorslide.report.practice`.

Conventions
-----------
- **Percentiles** are empirical: ``numpy.percentile(x, 84)`` with NumPy's default ``"linear"``
  method (Hyndman & Fan 1996, definition 7). A lognormal fit is not used because slides are
  often exactly zero (the object does not slide under some records).
- **Rocking** is an outcome of its own, never a zero slide: an object that would rock (Shenton
  1996, mode ``rock`` or ``slide-rock``) is simulated as a slide–rock block, not as a slider
  (its slide is in the per-record table; it may overturn). Every statistic of the ``slides``
  table is over all ``n_records`` records, the rocking ones ranked above every slide: a median
  or p84 that falls on them is the outcome ``rock`` (``median_outcome``, ``p84_outcome``; the
  numbers are NaN), and so is the mean once any record rocks
  (:data:`~floorslide.report.columns.ROCK`). ``n_rock`` counts them; ``n_slide_rock`` counts
  Shenton's mode ``slide-rock`` (``mu_s = B/H``), among them. What the rocking blocks did is
  the ``rocking`` table.
- **Few records**: rows over fewer than :data:`~floorslide.report.columns.MIN_RECORDS` records
  carry ``few_records = True`` (the p84 is then set by the largest record).
- **Ratios** are ratios of statistics (median of A / median of B), not statistics of per-record
  ratios. ``0/0`` (neither slides) is NaN; ``x/0`` with ``x > 0`` is ``inf``; a NaN statistic
  (also one that falls on rocking records) gives a NaN ratio. The numerator and denominator
  are in the row beside the ratio.
- **FRS ordinates** between stored periods are interpolated linearly in ``ln T``, per record,
  before the statistics; periods outside the stored grid are left out (and said so in the
  notes). ``psa_*`` columns are the unbroadened spectra; ``psa_broadened_*`` those broadened by
  the row's ``broadening``.
- **Incomplete** result files are refused unless ``allow_incomplete``; then every output says
  INCOMPLETE (``DesignTables.status``).

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. *Bull.
Seismol. Soc. Am.* 53(2), 403–417.

Hyndman, R. J., Fan, Y. (1996). Sample quantiles in statistical packages. *The American
Statistician* 50(4), 361–365.

Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes.
*J. Eng. Mech.* 122(7), 690–693.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from floorslide.constants import G
from floorslide.errors import ModelError, SceneError
from floorslide.report.columns import (
    COLUMNS,
    EMPTY_NOTES,
    MIN_RECORDS,
    PERCENTILE,
    ROCK,
    SLIDE_QUANTITIES,
    STATS,
    TABLE_NAMES,
    TITLES,
    Column,
    Comparison,
    DesignTables,
    floor_label,
)
from floorslide.report.formats import (
    format_csv,
    format_csv_sections,
    format_json,
    format_markdown,
    format_markdown_table,
    to_json,
    write_csv,
)
from floorslide.report.practice import (
    code_table,
    exceedance_table,
    fragility_table,
    practice_notes,
    scaling_table,
    suite_table,
)
from floorslide.report.records import record_rows, significant_impacts
from floorslide.report.statistics import (
    interpolate_spectrum,
    outcome,
    placement,
    ratio,
    summarize,
    summarize_outcomes,
)
from floorslide.report.study import Building, Study, _float, _natural, _rank, load_study
from floorslide.run.store import ResultFile

__all__ = [
    "COLUMNS",
    "MIN_RECORDS",
    "PERCENTILE",
    "TABLE_NAMES",
    "TITLES",
    "Building",
    "Column",
    "Comparison",
    "DesignTables",
    "Study",
    "design_tables",
    "format_csv",
    "format_csv_sections",
    "format_json",
    "format_markdown",
    "format_markdown_table",
    "interpolate_spectrum",
    "load_study",
    "parse_comparison",
    "ratio",
    "resolve_comparisons",
    "resolve_damping",
    "resolve_periods",
    "summarize",
    "to_json",
    "write_csv",
]

STANDARD_PERIODS = (0.1, 0.2, 0.3, 0.5, 1.0, 2.0, 3.0)
"""FRS ordinates (s) reported when the scene's ``[report]`` gives no ``periods``; only those
inside the stored period grid are kept."""

DEFAULT_DAMPING = 0.05
"""Damping ratio of the FRS ordinates when ``[report]`` gives none (else the first stored)."""

_TOL = 1e-9

PAIR_SPECTRA = ("rotd100", "psa_h1", "psa_h2")
"""The spectra a pair of horizontal components stores beside its RotD50 ``psa``
(:class:`~floorslide.run.results.SpectrumResult`): RotD100 and each direction's PSA; the
``frs`` table gives their median and 84th percentile (NaN for one component)."""


# --------------------------------------------------------------------------------------------
# statistics


def _stats_cols(prefix: str, values) -> dict:
    mean, median, p84 = summarize(values)
    return {f"{prefix}_mean": mean, f"{prefix}_median": median, f"{prefix}_p84": p84}


def _by_record(observations: list[tuple]) -> list[tuple]:
    """Observations ``(record, ...)`` in record order, so that sums (the mean) do not depend
    on the order of the tasks in the file."""
    return sorted(observations, key=lambda o: _natural(o[0]))


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

    def key(record_set: str, bid: str) -> tuple:
        return (_rank(sets, record_set), _rank(bids, bid))

    return key


def slide_table(study: Study) -> list[dict]:
    """The ``slides`` table (see the module docstring).

    Groups the per-record rows (:func:`~floorslide.report.records.record_rows`, already in
    the table's order) and takes each quantity's statistics over every record of the group,
    rocking records as their own outcome (:func:`~floorslide.report.statistics.summarize_outcomes`).
    """
    groups: dict[tuple, list[dict]] = {}
    for r in record_rows(study):
        key = (r["record_set"], r["building"], r["floor"], r["content"], r["mu_k"], r["mu_s"])
        groups.setdefault(key, []).append(r)
    rows = []
    for (rs, bid, floor, content, mu_k, mu_s), obs in groups.items():
        rock = [o["outcome"] == ROCK for o in obs]
        n, n_rock = len(obs), int(sum(rock))
        place = placement(n, n_rock)
        row = _building_cols(study, rs, bid)
        row.update(
            floor=floor,
            content=content,
            model=obs[0]["model"],
            mu_k=mu_k,
            mu_s=mu_s,
            n_records=n,
            n_slid=sum(o["outcome"] == "slide" for o in obs),
            n_rock=n_rock,
            n_slide_rock=sum(o["mode"] == "slide-rock" for o in obs),
            rock_fraction=n_rock / n,
        )
        stats = {}
        for q in SLIDE_QUANTITIES:
            values = np.array([o[q] for o in obs], dtype=float)
            if q == "residual_slide":
                values = np.abs(values)  # the per-record table keeps the sign
            got = summarize_outcomes(values, rock)
            stats.update({f"{q}_{s}": got[s] for s in STATS})
        row.update(
            {f"{s}_outcome": outcome(place, s, stats[f"peak_slide_{s}"]) for s in STATS},
            few_records=n < MIN_RECORDS,
        )
        row.update(stats)
        rows.append(row)
    return rows


def _qa_text(flags) -> str:
    """The flags of a record as one cell: ``check: message [remedy]; …``."""
    parts = []
    for f in flags:
        remedy = f.get("fix_scene") and f" [{f['fix_scene']} in [processing]]"
        parts.append(f"{f.get('check', '')}: {f.get('message', '')}{remedy or ''}")
    return "; ".join(parts)


def records_table(study: Study) -> list[dict]:
    """The ``records`` table: every record of the study (one row per record set × record, as
    run) with its quality flags, then the records the quality checks rejected."""
    details = {
        (str(item.get("set", "")), str(item.get("record", ""))): item.get("flags", [])
        for item in study.quality.get("flagged", [])
    }
    seen: dict[tuple[str, str], dict] = {}
    for t in study.tasks:
        m = t.meta
        key = (str(m["record_set"]), str(m["record"]))
        if key in seen:
            continue
        flags = details.get((key[0].split("@")[0], key[1]), [])
        seen[key] = dict(
            record_set=key[0],
            record=key[1],
            record_file=str(m.get("record_file", "")),
            status="ran",
            dt=_float(m.get("dt")),
            npts=int(_float(m.get("npts"), 0)),
            pga_g=_float(m.get("pga")) / G,
            scale=_float(m.get("scale")),
            qa_flags=str(m.get("qa_flags", "") or ""),
            qa=_qa_text(flags),
        )
    set_rank = {s: i for i, s in enumerate(study.sets)}
    rows = sorted(
        seen.values(), key=lambda r: (set_rank.get(r["record_set"], len(set_rank)), r["record"])
    )
    for item in study.quality.get("rejected", []):
        flags = item.get("flags", [])
        rows.append(
            dict(
                record_set=str(item.get("set", "")),
                record=str(item.get("record", "")),
                record_file=str(item.get("label", "")),
                status="rejected",
                dt=math.nan,
                npts=0,
                pga_g=math.nan,
                scale=math.nan,
                qa_flags=",".join(str(f.get("check", "")) for f in flags),
                qa=_qa_text(flags),
            )
        )
    return rows


ISOLATOR_PARAMETERS = ("q_ratio", "yield_disp", "alpha", "mu", "mu_s", "radius", "capacity")
"""Parameters of a nonlinear layer in the ``isolators`` table (task attributes
``isolator_<name>``; NaN where the layer has none)."""

IMPACT_NOT_MODELLED = (
    "impact with the moat wall (or the bearing's rim) is not modelled: beyond the capacity the "
    "response is that of an unlimited layer"
)


def _isolator_note(exceeded: int, n: int, capacity: float, small_angle: int = 0) -> str:
    """The ``note`` of an ``isolators`` row."""
    if exceeded:
        return f"capacity exceeded under {exceeded} of {n} records; {IMPACT_NOT_MODELLED}"
    if small_angle:
        return (
            f"no capacity given; beyond 0.2·R under {small_angle} of {n} records, where the "
            "pendulum's small-angle restoring force (W/R)·u is more than 2 % off"
        )
    if math.isnan(capacity):
        return "no capacity given"
    return ""


def isolator_table(study: Study) -> list[dict]:
    """The ``isolators`` table (see the module docstring): one row per record set × building
    on nonlinear isolation, from the task attributes a run stores."""
    groups: dict[tuple[str, str], list[tuple]] = defaultdict(list)
    layer: dict[str, dict] = {}
    for t in study.tasks:
        m = t.meta
        if "isolator_peak_displacement" not in m:
            continue
        rs, bid = str(m["record_set"]), str(m["building"])
        groups[(rs, bid)].append(
            (
                str(m["record"]),
                _float(m["isolator_peak_displacement"]),
                abs(_float(m.get("isolator_residual_displacement"))),
                _float(m.get("isolator_peak_force_ratio")),
                bool(_float(m.get("isolator_capacity_exceeded"), 0)),
                bool(_float(m.get("isolator_small_angle_exceeded"), 0)),
            )
        )
        layer.setdefault(
            bid,
            {
                "isolator": str(m.get("isolator", "")),
                "isolation_damping": _float(m.get("isolation_damping")),
                **{k: _float(m.get(f"isolator_{k}")) for k in ISOLATOR_PARAMETERS},
            },
        )
    bkey = _order_key(study)
    rows = []
    for rs, bid in sorted(groups, key=lambda k: bkey(*k)):
        obs = _by_record(groups[(rs, bid)])
        peak, resid, force = (np.array([o[j] for o in obs]) for j in (1, 2, 3))
        _, peak_median, peak_p84 = summarize(peak)
        _, force_median, force_p84 = summarize(force)
        exceeded = sum(o[4] for o in obs)
        small_angle = sum(o[5] for o in obs)
        finite = peak[np.isfinite(peak)]
        row = {
            "record_set": rs,
            "building": bid,
            "isolator": layer[bid]["isolator"],
            "isolation_period": study.buildings[bid].isolation_period,
        }
        row.update(layer[bid])
        row.update(
            n_records=len(obs),
            few_records=len(obs) < MIN_RECORDS,
            peak_disp_median=peak_median,
            peak_disp_p84=peak_p84,
            peak_disp_max=float(finite.max()) if finite.size else math.nan,
            residual_disp_median=summarize(resid)[1],
            peak_force_ratio_median=force_median,
            peak_force_ratio_p84=force_p84,
            n_capacity_exceeded=exceeded,
            n_small_angle_exceeded=small_angle,
            note=_isolator_note(exceeded, len(obs), row["capacity"], small_angle),
        )
        rows.append({c.name: row[c.name] for c in COLUMNS["isolators"]})
    return rows


def _geometry(study: Study) -> dict[str, float]:
    """``B/H`` of every content of the stored scene that has a width and height."""
    out = {}
    items = study.scene.get("contents", [])
    for item in items if isinstance(items, list) else []:
        if not isinstance(item, dict) or not isinstance(item.get("id"), str):
            continue
        width, height = _float(item.get("width")), _float(item.get("height"))
        if math.isfinite(width) and math.isfinite(height) and width > 0 and height > 0:
            out[item["id"]] = width / height
    return out


def holds_corner(mu_s: float, b_over_h: float) -> bool:
    """Whether static friction `mu_s` holds the corner of a block of slenderness `b_over_h`, so
    that it rocks rather than slides (``mu_s ≥ B/H``, equality to 1e-12 relative as in
    :func:`floorslide.response_mode`, where it is ``slide-rock``)."""
    return mu_s > b_over_h or abs(mu_s - b_over_h) <= 1e-12 * b_over_h


def rocking_table(study: Study) -> list[dict]:
    """The ``rocking`` table (see the module docstring): one row per record set × building ×
    floor × content × friction pair with rocking results, from the per-record arrays a run
    stores (:class:`~floorslide.run.results.ContentResult`: ``rock_peak_ratio``,
    ``rock_impacts``, ``overturned``, ``slide_rock_time``, ``outcomes``)."""
    slender = _geometry(study)
    groups: dict[tuple, list[tuple]] = defaultdict(list)
    for t in study.tasks:
        m = t.meta
        for c in t.contents:
            if c.content not in slender or c.rock_peak_ratio is None:
                continue
            b_h = slender[c.content]
            sr_time = getattr(c, "slide_rock_time", None)
            for i, mu_s in enumerate(np.asarray(c.mu_s, float)):
                if not holds_corner(mu_s, b_h):
                    continue  # it slides rather than rocks under this friction
                key = (str(m["record_set"]), str(m["building"]), int(c.floor), c.content,
                       float(c.mu_k[i]), float(mu_s))  # fmt: skip
                observed = str(c.outcomes[i]) if c.outcomes is not None else ""
                groups[key].append(
                    (
                        str(m["record"]),
                        float(c.rock_peak_ratio[i]),
                        float(c.rock_impacts[i]),
                        float(c.overturned[i]),
                        significant_impacts(c, i),
                        math.nan if sr_time is None else float(sr_time[i]),
                        float(observed == "slide-rock"),
                    )
                )
    bkey = _order_key(study)

    def key(k: tuple) -> tuple:
        return (*bkey(k[0], k[1]), k[2], _rank(study.contents, k[3]), _natural(k[3]), k[4], k[5])

    rows = []
    for k in sorted(groups, key=key):
        rs, bid, floor, content, mu_k, mu_s = k
        obs = _by_record(groups[k])
        peak, impacts, over, big, sr_time, sr = (
            np.array([o[j] for o in obs], dtype=float) for j in (1, 2, 3, 4, 5, 6)
        )
        n = len(obs)
        n_rock = int(np.sum((peak > 0) | (over > 0)))
        n_over = int(np.sum(over > 0))
        _, peak_median, peak_p84 = summarize(peak)
        row = _building_cols(study, rs, bid)
        row.update(
            floor=floor,
            floor_label=_floor_label_of(study, bid, floor),
            content=content,
            b_over_h=slender[content],
            alpha=math.atan(slender[content]),
            mu_k=mu_k,
            mu_s=mu_s,
            n_records=n,
            few_records=n < MIN_RECORDS,
            n_rock=n_rock,
            rock_fraction=n_rock / n,
            n_overturn=n_over,
            overturn_fraction=n_over / n,
            n_slide_rock=int(np.sum(sr)),
            peak_ratio_median=peak_median,
            peak_ratio_p84=peak_p84,
            impacts_median=summarize(impacts)[1],
            significant_impacts_median=summarize(big)[1],
            slide_rock_time_median=summarize(sr_time)[1],
        )
        rows.append({c.name: row[c.name] for c in COLUMNS["rocking"]})
    return rows


def plane_table(study: Study) -> list[dict]:
    """The ``plane`` table (see the module docstring): per record set of pairs × building ×
    floor × content × friction pair, the slide in the plane against the larger of the two
    components' 1-D slides. Records under which the object rocks (a slide–rock block along
    one component, not a slide in the plane) are left out (``n_records`` counts the
    others)."""
    groups: dict[tuple, list[tuple[str, float, float, float]]] = defaultdict(list)
    for t in study.tasks:
        m = t.meta
        for c in t.contents:
            if c.peak_angle is None:
                continue
            modes = list(c.modes) if c.modes is not None else []
            for i in range(np.asarray(c.mu_k).size):
                two = float(c.peak_slide[i])
                if not math.isfinite(two) or (i < len(modes) and modes[i] in (ROCK, "slide-rock")):
                    continue  # rocks: no slide in the plane
                one = max(float(c.peak_slide_h1[i]), float(c.peak_slide_h2[i]))
                key = (str(m["record_set"]), str(m["building"]), int(c.floor), c.content,
                       float(c.mu_k[i]), float(c.mu_s[i]))  # fmt: skip
                groups[key].append((str(m["record"]), two, one, float(c.ratio_2d_1d[i])))
    bkey = _order_key(study)

    def key(k: tuple) -> tuple:
        return (*bkey(k[0], k[1]), k[2], _rank(study.contents, k[3]), _natural(k[3]), k[4], k[5])

    rows = []
    for k in sorted(groups, key=key):
        rs, bid, floor, content, mu_k, mu_s = k
        obs = _by_record(groups[k])
        two, one, per = (np.array([o[j] for o in obs], dtype=float) for j in (1, 2, 3))
        _, two_med, two_p84 = summarize(two)
        _, one_med, one_p84 = summarize(one)
        finite = per[np.isfinite(per)]
        row = _building_cols(study, rs, bid)
        row.update(
            floor=floor,
            floor_label=_floor_label_of(study, bid, floor),
            content=content,
            mu_k=mu_k,
            mu_s=mu_s,
            n_records=len(obs),
            few_records=len(obs) < MIN_RECORDS,
            slide_2d_median=two_med,
            slide_2d_p84=two_p84,
            slide_1d_median=one_med,
            slide_1d_p84=one_p84,
            ratio_of_medians=ratio(two_med, one_med),
            ratio_median=float(np.median(finite)) if finite.size else math.nan,
            ratio_min=float(finite.min()) if finite.size else math.nan,
            ratio_max=float(finite.max()) if finite.size else math.nan,
            n_2d_above_1d=int(np.sum(two > 1.01 * one)),
        )
        rows.append({c.name: row[c.name] for c in COLUMNS["plane"]})
    return rows


def pfa_table(study: Study) -> list[dict]:
    """The ``pfa`` table (see the module docstring)."""
    groups: dict[tuple, list[tuple[str, float, float]]] = defaultdict(list)
    for t in study.tasks:
        rs, bid = str(t.meta["record_set"]), str(t.meta["building"])
        pga = _float(t.meta.get("pga"))
        for floor, pfa in zip(np.asarray(t.floors).tolist(), np.asarray(t.pfa), strict=True):
            groups[(rs, bid, int(floor))].append((str(t.meta["record"]), float(pfa), pga))
    bkey = _order_key(study)
    rows = []
    for key in sorted(groups, key=lambda k: (*bkey(k[0], k[1]), k[2])):
        rs, bid, floor = key
        obs = _by_record(groups[key])
        pfa = np.array([o[1] for o in obs])
        pga = np.array([o[2] for o in obs])
        amp = np.divide(pfa, pga, out=np.full_like(pfa, np.nan), where=pga > 0)
        row = _building_cols(study, rs, bid)
        row.update(floor=floor, n_records=len(pfa), few_records=len(pfa) < MIN_RECORDS)
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


def stored_broadening(study: Study) -> float:
    """The peak broadening of the stored spectra (0 when none)."""
    for t in study.tasks:
        for s in t.spectra:
            if s.broadening:
                return float(s.broadening)
    return 0.0


def frs_table(study: Study, periods: Sequence[float], damping: float | None) -> list[dict]:
    """The ``frs`` table (see the module docstring): unbroadened and broadened PSA."""
    if damping is None or not periods:
        return []
    groups: dict[tuple, list[tuple[str, np.ndarray, np.ndarray]]] = defaultdict(list)
    broadening = stored_broadening(study)
    nan = np.full(len(periods), np.nan)
    for t in study.tasks:
        rs, bid = str(t.meta["record_set"]), str(t.meta["building"])
        record = str(t.meta["record"])
        for s in t.spectra:
            zs = np.atleast_1d(np.asarray(s.damping, dtype=float))
            hit = np.nonzero(np.abs(zs - damping) <= _TOL)[0]
            if hit.size == 0:
                continue
            psa = np.atleast_2d(np.asarray(s.psa, dtype=float))[hit[0]]
            wide = nan
            if s.psa_broadened is not None:
                row = np.atleast_2d(np.asarray(s.psa_broadened, dtype=float))[hit[0]]
                wide = interpolate_spectrum(s.periods, row, periods)
            pair = []
            for name in PAIR_SPECTRA:
                values = getattr(s, name, None)
                if values is None:
                    pair.append(nan)
                    continue
                row = np.atleast_2d(np.asarray(values, dtype=float))[hit[0]]
                pair.append(interpolate_spectrum(s.periods, row, periods))
            groups[(rs, bid, int(s.floor))].append(
                (record, interpolate_spectrum(s.periods, psa, periods), wide, *pair,
                 str(getattr(s, "orientation", "") or ""))
            )  # fmt: skip
    bkey = _order_key(study)
    rows = []
    for key in sorted(groups, key=lambda k: (*bkey(k[0], k[1]), k[2])):
        rs, bid, floor = key
        obs = _by_record(groups[key])
        stack = np.array([o[1] for o in obs])
        wide = np.array([o[2] for o in obs])
        pairs = {name: np.array([o[3 + k] for o in obs]) for k, name in enumerate(PAIR_SPECTRA)}
        orientation = ", ".join(sorted({o[-1] for o in obs if o[-1]}))
        for j, p in enumerate(periods):
            _, median, p84 = summarize(stack[:, j])
            _, wmedian, wp84 = summarize(wide[:, j])
            n = int(np.isfinite(stack[:, j]).sum() or np.isfinite(wide[:, j]).sum())
            row = _building_cols(study, rs, bid)
            row.update(
                floor=floor,
                damping=damping,
                period=float(p),
                n_records=n,
                few_records=n < MIN_RECORDS,
                psa_median=median,
                psa_p84=p84,
                psa_g_median=median / G,
                psa_g_p84=p84 / G,
                broadening=broadening,
                psa_broadened_median=wmedian,
                psa_broadened_p84=wp84,
                psa_broadened_g_median=wmedian / G,
                psa_broadened_g_p84=wp84 / G,
                orientation=orientation,
            )
            for name, values in pairs.items():
                _, pmedian, pp84 = summarize(values[:, j])
                row.update(
                    {
                        f"{name}_median": pmedian,
                        f"{name}_p84": pp84,
                        f"{name}_g_median": pmedian / G,
                        f"{name}_g_p84": pp84 / G,
                    }
                )
            rows.append(row)
    return rows


# --------------------------------------------------------------------------------------------
# comparisons


def parse_comparison(spec: str) -> tuple[str, str]:
    """``"A:B"`` → ``("A", "B")`` (:func:`floorslide.scene.schema.parse_comparison`, the one
    rule of a comparison for the scene and the command line).

    Raises
    ------
    ValueError
        Not two non-empty building ids separated by one colon, or one building twice.
    """
    from floorslide.scene.schema import parse_comparison as rule

    return rule(spec)


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
                        "isolation_period_b": study.buildings[b].isolation_period,
                        **{k: r[k] for k in keys},
                        "few_records": bool(r["few_records"] or other["few_records"]),
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
            "n_records_a": a["n_records"],
            "n_records_b": b["n_records"],
            "n_rock_a": a["n_rock"],
            "n_rock_b": b["n_rock"],
            "median_outcome_a": a["median_outcome"],
            "median_outcome_b": b["median_outcome"],
            "p84_outcome_a": a["p84_outcome"],
            "p84_outcome_b": b["p84_outcome"],
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


def _floor_label_of(study: Study, bid: str, floor: int) -> str:
    b = study.buildings.get(bid)
    return "" if b is None else floor_label(b.kind, floor, b.stories)


def _label_floors(study: Study, rows: list[dict]) -> None:
    """Add ``floor_label`` to every row with a ``floor``: ground and base mat are both floor
    0 (:func:`~floorslide.report.columns.floor_label`); a ratio row whose buildings differ
    names both (``base mat (A) / ground (B)``)."""
    for row in rows:
        if "floor" not in row or "floor_label" in row:
            continue
        floor = int(row["floor"])
        if "building" in row:
            row["floor_label"] = _floor_label_of(study, str(row["building"]), floor)
            continue
        a = _floor_label_of(study, str(row.get("building_a", "")), floor)
        b = _floor_label_of(study, str(row.get("building_b", "")), floor)
        row["floor_label"] = a if a == b else f"{a} (A) / {b} (B)"


# --------------------------------------------------------------------------------------------
# the API


def _heavy_equipment_notes(study: Study) -> list[str]:
    """What the tables say about heavy equipment (contents with a ``floor_mass_ratio``): the
    coupled ones' PFA, and a warning for each decoupled one above the decoupling-error table's
    5 % ratio (:data:`floorslide.scene.schema.DECOUPLING_LIMIT`, docs/design.md §10f)."""
    from floorslide.scene.schema import DECOUPLING_LIMIT

    out = []
    if any(c.coupled_pfa is not None for t in study.tasks for c in t.contents):
        out.append(
            "heavy equipment (floor_mass_ratio, coupled): integrated with the building, its "
            "mass on the floor while it sticks and its friction while it slides (docs/design.md "
            "§10f); the floors' pfa columns are the building's without it, coupled_pfa its "
            "floor's with it"
        )
    contents = study.scene.get("contents", [])
    kinds = {b.kind for b in study.buildings.values()}
    for c in contents if isinstance(contents, list) else []:
        if not isinstance(c, dict) or c.get("coupled", True) is not False:
            continue
        ratio = c.get("floor_mass_ratio")
        over = sorted(k for k in kinds & DECOUPLING_LIMIT.keys() if _above(ratio, k))
        if over:
            out.append(
                f"warning: content {c.get('id')!r} is run decoupled at {ratio:g} of its floor's "
                f"mass, above {DECOUPLING_LIMIT[over[0]]:g} on a {over[0]} building, where the "
                "decoupled peak slide is more than 5 % off in the median (docs/design.md §10f)"
            )
    return out


def _above(ratio, kind: str) -> bool:
    from floorslide.scene.schema import DECOUPLING_LIMIT

    return isinstance(ratio, int | float) and ratio > DECOUPLING_LIMIT[kind]


def table_notes(study: Study, damping: float | None) -> list[str]:
    """The conventions every output of the tables states (docs/design.md §10)."""
    notes = []
    if study.status:
        notes.append(study.status)
    n_by_set = defaultdict(set)
    for t in study.tasks:
        n_by_set[str(t.meta["record_set"])].add(str(t.meta["record"]))
    sizes = ", ".join(f"{rs}: {len(n_by_set[rs])}" for rs in study.sets)
    notes += [
        "units: SI (m, s, m/s**2); columns ending in _g are in g = 9.80665 m/s**2",
        f"statistics over the records of each set (records per set: {sizes}); "
        f"p84 = {PERCENTILE:g}th percentile, empirical (numpy.percentile, method 'linear')",
        "rocking objects (Shenton 1996, mode rock or slide-rock) are simulated as slide–rock "
        "blocks, not as sliders, and never count as 0 slide: each is its own outcome, ranked "
        "above every slide over all n_records records; a median or p84 that falls on rocking "
        "records is 'rock' (median_outcome, p84_outcome; 'rocks' in Markdown, no number), and "
        "so is the mean once any record rocks (their slides are in the per-record table)",
        f"few_records: fewer than {MIN_RECORDS} records — the p84 then lies between the two "
        "largest values (set by the largest record); read these statistics with caution (†)",
        "residual_slide statistics are of |u(end)|; for 2-DOF oscillators peak_abs_accel is "
        "the sliding base's, peak_deformation the spring's and peak_top_accel the top mass's",
        "ratios are ratios of statistics (A / B); 0/0 (neither slides) is NaN, x/0 is inf",
    ]
    if any(c.rock_peak_ratio is not None for t in study.tasks for c in t.contents):
        notes.append(
            "rocking: contents with a width and height that rock are simulated as rigid blocks "
            "that rock, slide, or slide while rocking (fs.slide_rock, once per friction pair; "
            "Housner 1963, Shenton 1996) — the rocking table and the per-record rock_* columns; "
            "peak_ratio is max|θ|/α, 1 for a record under which the block overturned, 0 at "
            "rest; slide_rock_time is the time it slid while rocking; impacts count the whole "
            "cascade of ever smaller impacts to rest (each r times the last), thousands for a "
            "block that barely tilts — not a count of rocking cycles; significant_impacts "
            "(those at |θ'| ≥ p·α·√(f(2 − f)), f = 0.01) are not counted by slide–rock blocks "
            "(NaN), only in files written before"
        )
    elif any(
        ROCK in (list(c.modes) if c.modes is not None else [c.mode])
        for t in study.tasks
        for c in t.contents
    ):
        notes.append(
            "rocking: this file was written before rocking objects were simulated: it holds "
            "no rocking results (the rocking table is empty)"
        )
    if any(int(t.meta.get("components", 1)) == 2 for t in study.tasks):
        notes.append(
            "record pairs (two horizontal components): a block slides in the plane (isotropic "
            "Coulomb friction, both components at once); its peak_slide is max|u|, its "
            "residual_slide |u(end)| and its peak_abs_accel the breakaway level mu_s·g once it "
            "slid; the PFA is the peak of the floor's acceleration vector; a rocking block "
            "rocks (and slides) in the plane of each component and the more severe is kept; the "
            "plane "
            "table compares the 2-D slide with each component's 1-D slide"
        )
    notes += _heavy_equipment_notes(study)
    if any("isolator_peak_displacement" in t.meta for t in study.tasks):
        notes.append(
            "isolators: displacements are the isolation layer's u0 relative to the ground; "
            "residual_disp statistics are of |u0(end)|; the force ratio is the layer's force "
            f"on the base mat over the total weight W (base shear V/W); {IMPACT_NOT_MODELLED}"
        )
    notes += practice_notes(study)
    if damping is not None:
        b = stored_broadening(study)
        wide = (
            f"psa_broadened_* broadened by ±{b * 100:g} % in frequency (ASCE 4, US NRC RG 1.122)"
            if b
            else "no peak broadening (psa_broadened_* empty)"
        )
        notes.append(
            f"FRS: PSA at {damping:g} damping, interpolated linearly in ln(period) between stored "
            f"periods; psa_* are the unbroadened spectra, {wide}"
        )
        if any(getattr(s, "orientation", "") for t in study.tasks for s in t.spectra):
            notes.append(
                "FRS of record pairs: psa is RotD50 (Boore 2010: the median over 180 directions "
                "of the peak response along each, exact with in-step peaks; orientation RotD50); "
                "RotD100 and each direction's PSA are the rotd100_*, psa_h1_* and psa_h2_* "
                "columns"
            )
        lost = any(
            s.broadening and np.isnan(np.asarray(s.psa, dtype=float)).all()
            for t in study.tasks
            for s in t.spectra
        )
        if lost:
            notes.append(
                "FRS: this file predates keeping the unbroadened spectra; psa_* are unknown (NaN)"
            )
    return notes


def design_tables(
    result: str | Path | ResultFile | Study,
    compare: Sequence[str] | None = None,
    periods: Sequence[float] | None = None,
    damping: float | None = None,
    *,
    allow_incomplete: bool = False,
) -> DesignTables:
    """Design tables of a result file (docs/design.md §3, ``floorslide table``).

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
    allow_incomplete
        Accept a result file whose run is not finished; the tables then carry its
        INCOMPLETE label (``status``, notes, every output format).

    Returns
    -------
    DesignTables
        ``tables`` maps ``slides``, ``pfa``, ``frs``, ``slide_ratios``, ``pfa_ratios``,
        ``records``, ``isolators``, ``rocking``, ``plane``, ``scaling``, ``suite``, ``code``,
        ``exceedance``, ``fragility`` to
        rows (dicts, SI values; columns and units in :data:`COLUMNS`), in a fixed order:
        record sets and buildings as in the scene (isolated variants by period), floors up,
        contents as in the scene, friction ascending.

    Raises
    ------
    ResultFileError
        Missing, corrupt or empty result file.
    IncompleteResultError
        Tasks are missing and `allow_incomplete` is False.
    ModelError
        A bad `compare`, `periods` or `damping` argument (its ``where`` names the argument).
    SceneError
        A bad ``[report]`` entry of the stored scene (its ``where`` names the key).

    Notes
    -----
    Percentiles are empirical (``numpy.percentile``, ``"linear"``; Hyndman & Fan 1996,
    definition 7). Records in which the object rocks (simulated as a rocking block, not as a
    slider; Shenton 1996, Housner 1963) are an outcome of their own in the slide statistics,
    ranked above every slide; a statistic that falls on them is ``rock``, never 0. Ratios are
    ratios of statistics; ``0/0`` is NaN, ``x/0`` is inf.
    """
    study = load_study(result)
    study.require_complete(allow_incomplete)
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
        "records": records_table(study),
        "isolators": isolator_table(study),
        "rocking": rocking_table(study),
        "plane": plane_table(study),
        "scaling": scaling_table(study),
        "suite": suite_table(study),
        "code": code_table(study),
    }
    tables["exceedance"] = exceedance_table(study)
    tables["fragility"] = fragility_table(study, tables["exceedance"])
    for rows in tables.values():
        _label_floors(study, rows)
    notes = table_notes(study, z) + period_notes + study.notes
    notes += [f"{name}: {note}" for name, note in EMPTY_NOTES.items() if not tables[name]]
    return DesignTables(
        source=study.source,
        scene_name=study.scene_name,
        periods=chosen,
        damping=z,
        comparisons=comparisons,
        tables=tables,
        notes=tuple(notes),
        status=study.status,
        tasks_done=study.tasks_done,
        tasks_planned=study.tasks_planned,
    )
