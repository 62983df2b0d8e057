"""What the design tables hold: their columns (name, unit, meaning), titles and conventions,
and the :class:`DesignTables` container that every output format reads.

The conventions every table, figure and report states (docs/design.md §10) are constants here, so
that
the notes, the docstrings and the README say the same:

- :data:`PERCENTILE`: the upper statistic, empirical (NumPy ``"linear"``);
- :data:`MIN_RECORDS`: below this many records a row carries the caution ``few_records``;
- rocking (:data:`ROCK`): an outcome of its own, never a zero slide.
"""

from __future__ import annotations

from dataclasses import dataclass

PERCENTILE = 84.0
"""The upper percentile of the tables (empirical, NumPy ``"linear"`` method)."""

MIN_RECORDS = 8
"""Rows with fewer records carry ``few_records = True`` (a caution, marked † in Markdown and
stated in figures). With ``n`` records the empirical 84th percentile sits at the position
``0.84·(n − 1)`` of the sorted values; for ``n ≤ 7`` that lies beyond ``n − 2``, between the two
largest values, so the "p84" is set by the largest record rather than estimated (and a median of
fewer than 8 records moves by a whole record's worth when one is added)."""

ROCK = "rock"
"""The outcome of a record under which the object rocks (Shenton 1996, mode ``rock``): it is
not simulated as a slider, so its slide is unknown — never zero (its rocking is simulated as a
rigid block, Housner 1963: the ``rocking`` table). In the statistics it is ranked
above every slide (rocking needs a floor acceleration above ``g·B/H``, more than the object
rests under); a median or 84th percentile that falls on rocking records is the outcome
``rock`` (NaN numbers, ``rocks`` in Markdown), and the mean over records of which any rocks is
``rock`` too."""

OUTCOMES = ("rest", "slide", ROCK)
"""Outcome of a statistic of the peak slide: ``rest`` (0), ``slide`` (> 0) or ``rock``."""

TABLE_NAMES = (
    "slides",
    "pfa",
    "frs",
    "slide_ratios",
    "pfa_ratios",
    "records",
    "isolators",
    "rocking",
    "plane",
    "scaling",
    "suite",
    "code",
    "exceedance",
    "fragility",
)
"""The tables, in output order."""


@dataclass(frozen=True)
class Column:
    """A column of a design table: its key, unit (``"1"`` dimensionless, ``""`` for labels)
    and meaning."""

    name: str
    units: str
    description: str


STATS = ("mean", "median", "p84")
"""The statistics of every quantity, in column order."""


def _stat_columns(prefix: str, units: str, what: str) -> list[Column]:
    return [
        Column(f"{prefix}_mean", units, f"mean of {what} ('rock' if any record rocks)"),
        Column(f"{prefix}_median", units, f"median of {what} (see median_outcome)"),
        Column(f"{prefix}_p84", units, f"84th percentile of {what} (see p84_outcome)"),
    ]


_BUILDING = [
    Column("record_set", "", "record set (scaled sets are named set@PGAg)"),
    Column("building", "", "building variant id"),
    Column("building_kind", "", "fixed or isolated"),
    Column("isolation_period", "s", "isolation period T_i (NaN for fixed-base)"),
]

_FLOOR = Column("floor", "1", "floor (0 = ground, or the base mat of an isolated building)")
FLOOR_LABEL = Column(
    "floor_label",
    "",
    "what the floor is: ground (floor 0 of a fixed-base building), base mat (floor 0 of an "
    "isolated building: above the isolators), floor n, or roof",
)


def floor_label(kind: str, floor: int, stories: int) -> str:
    """What floor `floor` of a building is: ``"ground"`` (floor 0 of a fixed-base building),
    ``"base mat"`` (floor 0 of an isolated one, above the isolation layer), ``"roof"`` (floor
    `stories`) or ``"floor n"`` (docs/design.md §2)."""
    floor = int(floor)
    if floor == 0:
        return "base mat" if kind == "isolated" else "ground"
    if floor == int(stories):
        return "roof"
    return f"floor {floor}"


_N_RECORDS = Column("n_records", "1", "records of the set on this building")
_FEW = Column(
    "few_records",
    "",
    f"caution: fewer than {MIN_RECORDS} records, the 84th percentile lies between the two "
    "largest values (set by the largest record)",
)

SLIDE_QUANTITIES = (
    "peak_slide",
    "residual_slide",
    "peak_abs_accel",
    "peak_abs_accel_g",
    "peak_deformation",
    "peak_top_accel",
    "peak_top_accel_g",
)
"""Quantities of the ``slides`` table with a mean, median and p84 each (the last three are for
2-DOF oscillators only, NaN for rigid blocks)."""

COLUMNS: dict[str, tuple[Column, ...]] = {
    "slides": (
        *_BUILDING,
        _FLOOR,
        Column("content", "", "content (equipment) id"),
        Column("model", "", "rigid or oscillator (2-DOF: a top mass on a spring over a base)"),
        Column("mu_k", "1", "kinetic friction coefficient"),
        Column("mu_s", "1", "static friction coefficient"),
        _N_RECORDS,
        Column("n_slid", "1", "records in which the object slid (peak slide > 0)"),
        Column(
            "n_rock",
            "1",
            "records in which the object rocks (mode rock): not simulated as a slider, its own "
            "outcome in the statistics — never counted as 0 slide",
        ),
        Column(
            "n_slide_rock",
            "1",
            "records with mode slide-rock (both start together): simulated as a slider",
        ),
        Column("rock_fraction", "1", "n_rock / n_records"),
        Column("mean_outcome", "", "rest, slide or rock: rock if any record rocks"),
        Column(
            "median_outcome",
            "",
            "rest, slide or rock: what the median falls on (rock ranked above every slide)",
        ),
        Column("p84_outcome", "", "rest, slide or rock: what the 84th percentile falls on"),
        _FEW,
        *_stat_columns("peak_slide", "m", "the peak slide max|u|"),
        *_stat_columns("residual_slide", "m", "the absolute residual slide |u(end)|"),
        *_stat_columns(
            "peak_abs_accel",
            "m/s**2",
            "the peak absolute acceleration of the object (of the sliding base for an oscillator)",
        ),
        *_stat_columns(
            "peak_abs_accel_g",
            "g",
            "the peak absolute acceleration of the object (of the sliding base for an oscillator)",
        ),
        *_stat_columns(
            "peak_deformation", "m", "the peak spring deformation max|z| (oscillators only)"
        ),
        *_stat_columns(
            "peak_top_accel",
            "m/s**2",
            "the peak absolute acceleration of the top mass (oscillators only)",
        ),
        *_stat_columns(
            "peak_top_accel_g", "g", "the peak absolute acceleration of the top mass (oscillators)"
        ),
    ),
    "pfa": (
        *_BUILDING,
        _FLOOR,
        _N_RECORDS,
        _FEW,
        Column("pfa_mean", "m/s**2", "mean of the true peak floor acceleration"),
        Column("pfa_median", "m/s**2", "median of the true peak floor acceleration"),
        Column("pfa_p84", "m/s**2", "84th percentile of the true peak floor acceleration"),
        Column("pfa_g_mean", "g", "mean of the true peak floor acceleration"),
        Column("pfa_g_median", "g", "median of the true peak floor acceleration"),
        Column("pfa_g_p84", "g", "84th percentile of the true peak floor acceleration"),
        Column("pfa_pga_median", "1", "median over records of PFA / PGA"),
    ),
    "frs": (
        *_BUILDING,
        _FLOOR,
        Column("damping", "1", "damping ratio of the spectrum"),
        Column("period", "s", "oscillator period"),
        Column("n_records", "1", "records with an ordinate at this period"),
        _FEW,
        Column("psa_median", "m/s**2", "median pseudo-spectral acceleration, unbroadened"),
        Column("psa_p84", "m/s**2", "84th percentile of the PSA, unbroadened"),
        Column("psa_g_median", "g", "median pseudo-spectral acceleration, unbroadened"),
        Column("psa_g_p84", "g", "84th percentile of the PSA, unbroadened"),
        Column(
            "broadening",
            "1",
            "peak broadening ±fraction in frequency of the psa_broadened columns (0: none)",
        ),
        Column("psa_broadened_median", "m/s**2", "median PSA, broadened (NaN without)"),
        Column("psa_broadened_p84", "m/s**2", "84th percentile of the PSA, broadened"),
        Column("psa_broadened_g_median", "g", "median PSA, broadened (NaN without)"),
        Column("psa_broadened_g_p84", "g", "84th percentile of the PSA, broadened"),
        Column(
            "orientation",
            "",
            "RotD50 for record pairs (the psa columns are then RotD50, Boore 2010); empty for "
            "one component",
        ),
        *(
            Column(f"{name}{unit_tag}_{stat}", units, f"{label} of {what}")
            for name, what in (
                ("rotd100", "RotD100, the largest over every direction (record pairs; else NaN)"),
                ("psa_h1", "the PSA along the pair's first component h1 (pairs; else NaN)"),
                ("psa_h2", "the PSA along the pair's second component h2 (pairs; else NaN)"),
            )
            for unit_tag, units in (("", "m/s**2"), ("_g", "g"))
            for stat, label in (("median", "median"), ("p84", "84th percentile"))
        ),
    ),
    "slide_ratios": (
        Column("comparison", "", "the comparison A:B as asked"),
        Column("record_set", "", "record set"),
        Column("building_a", "", "numerator building variant"),
        Column("building_b", "", "denominator building variant"),
        Column("isolation_period_a", "s", "isolation period of A (NaN for fixed-base)"),
        Column("isolation_period_b", "s", "isolation period of B (NaN for fixed-base)"),
        Column("floor", "1", "floor"),
        Column("content", "", "content id"),
        Column("mu_k", "1", "kinetic friction coefficient"),
        Column("mu_s", "1", "static friction coefficient"),
        Column("n_records_a", "1", "records on A"),
        Column("n_records_b", "1", "records on B"),
        Column("n_rock_a", "1", "records in which the object rocks on A"),
        Column("n_rock_b", "1", "records in which the object rocks on B"),
        Column("median_outcome_a", "", "rest, slide or rock: the median on A"),
        Column("median_outcome_b", "", "rest, slide or rock: the median on B"),
        Column("p84_outcome_a", "", "rest, slide or rock: the 84th percentile on A"),
        Column("p84_outcome_b", "", "rest, slide or rock: the 84th percentile on B"),
        _FEW,
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
        Column("isolation_period_b", "s", "isolation period of B (NaN for fixed-base)"),
        Column("floor", "1", "floor"),
        _FEW,
        Column("pfa_median_a", "m/s**2", "median PFA on A"),
        Column("pfa_median_b", "m/s**2", "median PFA on B"),
        Column("pfa_median_ratio", "1", "median PFA A / B"),
        Column("pfa_p84_ratio", "1", "84th-percentile PFA A / B"),
    ),
    "records": (
        Column("record_set", "", "record set (scaled sets are named set@PGAg)"),
        Column("record", "", "record id (file name without extension)"),
        Column("record_file", "", "the record's file"),
        Column("status", "", "ran, or rejected by the quality checks ([scene] qa = 'reject')"),
        Column("dt", "s", "time step"),
        Column("npts", "1", "samples"),
        Column("pga_g", "g", "peak ground acceleration as run (processed and scaled)"),
        Column("scale", "1", "factor applied to the record"),
        Column("qa_flags", "", "quality checks that tripped (floorslide.records.quality)"),
        Column("qa", "", "what each check found, with its numbers and remedy"),
    ),
    "isolators": (
        Column("record_set", "", "record set (scaled sets are named set@PGAg)"),
        Column("building", "", "building variant id (on nonlinear isolation)"),
        Column("isolator", "", "bilinear (lead-rubber) or friction_pendulum"),
        Column(
            "isolation_period",
            "s",
            "post-yield period T_d (bilinear) or pendulum period 2π√(R/g)",
        ),
        Column("isolation_damping", "1", "viscous damping ratio of the layer"),
        Column("q_ratio", "1", "characteristic strength Q/W (bilinear; else NaN)"),
        Column("yield_disp", "m", "yield displacement D_y (bilinear; else NaN)"),
        Column("alpha", "1", "post-yield over elastic stiffness k2/k1 (bilinear; else NaN)"),
        Column("mu", "1", "sliding friction coefficient (pendulum; else NaN)"),
        Column("mu_s", "1", "breakaway friction coefficient used, ≥ mu (pendulum; else NaN)"),
        Column("radius", "m", "radius of curvature R (pendulum; else NaN)"),
        Column("capacity", "m", "displacement capacity of the layer (NaN: none given)"),
        _N_RECORDS,
        _FEW,
        Column("peak_disp_median", "m", "median of the peak isolator displacement max|u0|"),
        Column("peak_disp_p84", "m", "84th percentile of the peak isolator displacement"),
        Column("peak_disp_max", "m", "largest peak isolator displacement of the set"),
        Column(
            "residual_disp_median",
            "m",
            "median of the absolute residual isolator displacement |u0(end)|",
        ),
        Column(
            "peak_force_ratio_median",
            "1",
            "median of the peak isolator force over the weight, max|V|/W (base shear ratio)",
        ),
        Column("peak_force_ratio_p84", "1", "84th percentile of the peak force ratio max|V|/W"),
        Column(
            "n_capacity_exceeded",
            "1",
            "records under which the isolator displacement exceeds the capacity",
        ),
        Column(
            "n_small_angle_exceeded",
            "1",
            "records under which a friction pendulum without a capacity goes beyond 0.2·R, "
            "where its small-angle model (W/R)·u is more than 2 % off",
        ),
        Column(
            "note",
            "",
            "what the numbers do not include (the impact beyond the capacity, the pendulum's "
            "geometry beyond 0.2·R)",
        ),
    ),
    "rocking": (
        *_BUILDING,
        _FLOOR,
        Column("content", "", "content (equipment) id, with a width and height"),
        Column("b_over_h", "1", "slenderness B/H = width / height"),
        Column("alpha", "rad", "slenderness angle α = atan(B/H): |θ| = α overturns it"),
        Column("mu_k", "1", "kinetic friction coefficient"),
        Column(
            "mu_s",
            "1",
            "static friction coefficient, one that holds its corner from rest (mu_s ≥ B/H): it "
            "rocks rather than slides, and slides while it rocks where the friction it needs "
            "exceeds mu_s (a slide–rock block, fs.slide_rock)",
        ),
        _N_RECORDS,
        _FEW,
        Column("n_rock", "1", "records under which it rocked (uplifted), overturned or not"),
        Column("rock_fraction", "1", "n_rock / n_records"),
        Column("n_overturn", "1", "records under which it overturned (|θ| reached α)"),
        Column("overturn_fraction", "1", "n_overturn / n_records (over every record of the set)"),
        Column(
            "n_slide_rock",
            "1",
            "records under which it slid and rocked and did not overturn (observed outcome "
            "slide-rock)",
        ),
        Column(
            "peak_ratio_median",
            "1",
            "median over every record of the peak rotation max|θ|/α (0 at rest; an overturned "
            "record counts as 1)",
        ),
        Column(
            "peak_ratio_p84",
            "1",
            "84th percentile over every record of max|θ|/α (an overturned record counts as 1)",
        ),
        Column(
            "impacts_median",
            "1",
            "median number of impacts over every record (0 at rest; up to the overturning), "
            "counting the whole cascade of ever smaller impacts to rest (each r times the "
            "last): thousands for a block that barely tilts, not a count of rocking cycles",
        ),
        Column(
            "significant_impacts_median",
            "1",
            "median number of significant impacts: those at |θ'| ≥ p·α·√(f(2 − f)), f = 0.01, "
            "the speed of a block rocking freely back from a tilt of 1 % of α (the cascade to "
            "rest left out; NaN in files written before they were counted)",
        ),
        Column(
            "slide_rock_time_median",
            "s",
            "median over every record of the time spent sliding and rocking at once (0 when it "
            "never did; NaN in files written before slide–rock was simulated)",
        ),
    ),
    "plane": (
        *_BUILDING,
        _FLOOR,
        Column("content", "", "content (equipment) id"),
        Column("mu_k", "1", "kinetic friction coefficient"),
        Column("mu_s", "1", "static friction coefficient"),
        Column("n_records", "1", "pairs of the set on this building (records that rock left out)"),
        _FEW,
        Column(
            "slide_2d_median",
            "m",
            "median of the peak slide in the plane, max|u| (both components at once)",
        ),
        Column("slide_2d_p84", "m", "84th percentile of the peak slide in the plane"),
        Column(
            "slide_1d_median",
            "m",
            "median of the larger of the two components' 1-D slides (each component alone)",
        ),
        Column("slide_1d_p84", "m", "84th percentile of the larger 1-D slide"),
        Column(
            "ratio_of_medians",
            "1",
            "slide_2d_median / slide_1d_median (what the 1-D practice misses at the median)",
        ),
        Column(
            "ratio_median",
            "1",
            "median over the records of the per-record ratio 2-D / max(1-D) (records where "
            "neither component slides left out)",
        ),
        Column("ratio_min", "1", "smallest per-record ratio 2-D / max(1-D)"),
        Column("ratio_max", "1", "largest per-record ratio 2-D / max(1-D)"),
        Column(
            "n_2d_above_1d",
            "1",
            "records whose slide in the plane exceeds both 1-D slides by more than 1 %",
        ),
    ),
}
"""Columns of every table, in order (``floor_label`` follows every ``floor``: see the end)."""

_OBJECT = [
    _FLOOR,
    Column("content", "", "content (equipment) id"),
    Column("mu_k", "1", "kinetic friction coefficient"),
    Column("mu_s", "1", "static friction coefficient"),
    Column(
        "state",
        "",
        "slide > a m (the peak slide exceeds the allowable displacement a) or overturn",
    ),
    Column("allowable", "m", "allowable displacement a (NaN for overturn)"),
]

COLUMNS.update(
    {
        "scaling": (
            Column("record_set", "", "scaled set (stripes: set@1.5x, set@0.3g)"),
            Column("family", "", "the scene's record set"),
            Column("method", "", "range (log least squares), period (match at T*) or pga"),
            Column("level", "1", "multiple of the target (or PGA in g for pga)"),
            Column("record", "", "record id"),
            Column("factor", "1", "amplitude factor applied (fit factor × level × suite factor)"),
            Column("fit_factor", "1", "factor fitting the record to the target (level 1)"),
            Column(
                "misfit",
                "1",
                "RMS of ln(scaled S_a / target S_a) over the range (0 for method period)",
            ),
            Column("outside_limits", "", "factor outside the scene's limits (a warning)"),
        ),
        "suite": (
            Column("record_set", "", "scaled set"),
            Column("target", "", "the target spectrum (two-point S_DS, S_D1, T_L, or its CSV)"),
            Column("method", "", "range (log least squares) or period (match at T*)"),
            Column("period", "s", "T* of method period (NaN for range)"),
            Column("period_lo", "s", "lower end of the period range"),
            Column("period_hi", "s", "upper end of the period range"),
            Column("damping", "1", "damping ratio of the spectra"),
            Column("level", "1", "multiple of the target of this stripe"),
            _N_RECORDS,
            Column("factor_min", "1", "smallest factor"),
            Column("factor_max", "1", "largest factor"),
            Column("n_outside_limits", "1", "factors outside the scene's limits"),
            Column(
                "suite_factor",
                "1",
                "common factor raising the suite to 90 % of the target (match_suite; else 1), "
                "included in the factors",
            ),
            Column(
                "mean_over_target_min",
                "1",
                "lowest ratio of the suite's mean spectrum to the (level × ) target in the range",
            ),
            Column("at_period", "s", "period of that lowest ratio"),
            Column("passes", "", "ASCE 7-22 §16.2.3: the mean is ≥ 90 % of the target"),
        ),
        "code": (
            *_BUILDING,
            _FLOOR,
            Column(
                "z_over_h",
                "1",
                "relative height z/h of the floor: from the building's storey_heights, else "
                "floor/stories (equal storeys)",
            ),
            Column(
                "period_a",
                "s",
                "T_a: the fixed-base model's fundamental period (NaN for isolated)",
            ),
            Column(
                "h_f",
                "1",
                "ASCE 7-22 Eq. 13.3-4: 1 + a1·z/h + a2·(z/h)^10, a1 = min(1/T_a, 2.5), "
                "a2 = max(0, 1 − (0.4/T_a)²) (NaN for isolated)",
            ),
            _N_RECORDS,
            _FEW,
            Column("pfa_pga_median", "1", "median over records of PFA/PGA"),
            Column("pfa_pga_p84", "1", "84th percentile over records of PFA/PGA"),
            Column("median_over_h_f", "1", "median PFA/PGA over H_f (> 1: above the code)"),
            Column("p84_over_h_f", "1", "84th-percentile PFA/PGA over H_f"),
            Column("note", "", "how the code treats the building"),
        ),
        "exceedance": (
            *_BUILDING,
            *_OBJECT,
            _N_RECORDS,
            Column(
                "n_rock",
                "1",
                "records under which the object rocks: no slide, left out of the slide "
                "fraction (never counted as not exceeding)",
            ),
            Column("n_exceed", "1", "records exceeding (slide > a, or overturning)"),
            Column(
                "n_records_exceedance",
                "1",
                "the fraction's denominator: records whose slide is known (n_records − n_rock) "
                "for a slide state; n_records to overturn",
            ),
            Column(
                "fraction",
                "1",
                "n_exceed / n_records_exceedance: (n_records − n_rock) for a slide, n_records "
                "to overturn",
            ),
            _FEW,
        ),
        "fragility": (
            Column("record_set", "", "set family whose scalings are the stripes"),
            Column("building", "", "building variant id"),
            Column("building_kind", "", "fixed or isolated"),
            Column("isolation_period", "s", "isolation period T_i (NaN for fixed-base)"),
            *_OBJECT,
            Column("im", "", "intensity measure of the stripes"),
            Column("levels", "", "each stripe's intensity"),
            Column("n_records", "1", "records per stripe (rocking ones left out of a slide)"),
            Column("n_exceed", "1", "exceedances per stripe"),
            Column("median", "", "fitted median θ, in the im's units (NaN: see note)"),
            Column("beta", "1", "fitted logarithmic standard deviation β (NaN: see note)"),
            Column("note", "", "why θ and β are NaN (no fit exists), else empty"),
        ),
    }
)


def _with_floor_label(columns: tuple[Column, ...]) -> tuple[Column, ...]:
    out: list[Column] = []
    for c in columns:
        out.append(c)
        if c.name == "floor":
            out.append(FLOOR_LABEL)
    return tuple(out)


COLUMNS.update({name: _with_floor_label(cols) for name, cols in COLUMNS.items()})

EMPTY_NOTES = {
    "isolators": "no building on nonlinear isolation in this study",
    "plane": "no set of record pairs (two horizontal components) in this study",
    "scaling": "no record set is scaled (scale or scale_pga): records ran as recorded",
    "suite": "no record set is scaled to a target spectrum ([[records]] scale)",
    "exceedance": (
        "no content gives allowable displacements (allowable) or has a width and height (the "
        "overturning fraction)"
    ),
    "fragility": ("no set has stripes (scale.levels or a list of scale_pga): no fragility fit"),
    "rocking": (
        "no content with a width and height whose static friction holds its corner "
        "(mu_s ≥ B/H) has rocking results in this file"
    ),
}
"""What an empty table means, stated where it is written (Markdown, CSV, notes)."""

PAIR_FRS_COLUMNS = frozenset(
    c.name for c in COLUMNS["frs"] if c.name.startswith(("rotd100", "psa_h1", "psa_h2"))
) | {"orientation"}
"""Columns of the ``frs`` table that only record pairs fill (left out of Markdown without
pairs)."""

OSCILLATOR_COLUMNS = frozenset(
    c.name for c in COLUMNS["slides"] if c.name.startswith(("peak_deformation", "peak_top_accel"))
)
"""Columns of the ``slides`` table that only oscillators fill (left out of Markdown when no
row is an oscillator)."""

TITLES = {
    "slides": "Sliding contents: peak slide, |residual| slide, peak object acceleration",
    "pfa": "Peak floor acceleration (PFA)",
    "frs": "Floor response spectra: PSA at the report periods",
    "slide_ratios": "Peak-slide ratios between buildings (A / B)",
    "pfa_ratios": "PFA ratios between buildings (A / B)",
    "records": "Records: quality flags (mean offset, trend, clipping, truncation, sampling)",
    "isolators": "Nonlinear isolators: peak and residual displacement, peak force / W",
    "rocking": "Rocking contents: rocking, overturning, peak rotation θ/α, impacts",
    "plane": "Sliding in the plane (record pairs): 2-D slide against each component's 1-D",
    "scaling": "Scaling of records to the target spectrum: factor and log misfit per record",
    "suite": "Suite check (ASCE 7-22 §16.2.3): mean scaled spectrum against 90 % of the target",
    "code": "Code comparison (ASCE 7-22 §13.3.1): PFA/PGA beside H_f",
    "exceedance": "Exceedance: fraction of records whose peak slide exceeds each allowable "
    "displacement, or that overturn",
    "fragility": "Fragility over stripes: lognormal median and β by maximum likelihood "
    "(Baker 2015)",
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
    names of :data:`COLUMNS`, SI values, NaN where a statistic is undefined or falls on rocking
    records — the ``*_outcome`` columns say which). Index it like a mapping:
    ``tables["slides"]``; :meth:`to_pandas` gives DataFrames.

    ``status`` is ``""`` for a complete result file, else its INCOMPLETE label (every format
    carries it).
    """

    source: str
    scene_name: str
    periods: tuple[float, ...]
    damping: float | None
    comparisons: tuple[Comparison, ...]
    tables: dict[str, list[dict]]
    notes: tuple[str, ...] = ()
    status: str = ""
    tasks_done: int | None = None
    tasks_planned: int | None = None

    def __getitem__(self, name: str) -> list[dict]:
        return self.tables[name]

    def __iter__(self):
        return iter(self.tables)

    @property
    def complete(self) -> bool:
        """False when the result file is incomplete (tasks missing)."""
        return not self.status

    def as_dict(self) -> dict[str, list[dict]]:
        """``{table name: rows}``."""
        return {name: list(rows) for name, rows in self.tables.items()}

    def to_pandas(self, name: str | None = None):
        """The tables as :class:`pandas.DataFrame` (one, or a dict of all by name).

        Columns in the order of :data:`COLUMNS`; ``df.attrs`` holds ``units`` (column →
        unit), ``notes``, ``status`` (``""`` or the INCOMPLETE label), ``source``.
        """
        from floorslide.report.formats import to_pandas

        return to_pandas(self, name)
