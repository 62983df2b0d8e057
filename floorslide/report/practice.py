"""Design-practice tables (docs/design.md §10e): the scaling of records to a target spectrum,
the code's floor amplification beside the computed one, and the exceedance of allowable
displacements and its fragility over stripes.

``scaling``
    scaled set × record: the factor (the fit's factor times the stripe's level), the fit's own
    factor and its log misfit, and whether the factor lies outside the scene's limits.
``suite``
    set scaled to a target: the target, the period range, the number of records, and the suite
    check of ASCE 7-22 §16.2.3 (the mean spectrum against 90 % of the target over the range:
    the lowest ratio and where it occurs).
``code``
    record set × building × floor: the median and 84th percentile of PFA/PGA over the records
    beside ASCE 7-22 §13.3.1 ``H_f`` (Eq. 13.3-4) for a fixed-base building, with
    ``z/h = floor/stories`` (equal storey heights) and ``T_a`` the model's fundamental period.
    Isolated buildings get no ``H_f``: ASCE 7-22 §17 takes component demands from the response
    history analysis of the isolated structure (the row's note says so).
``exceedance``
    record set × building × floor × content × friction pair × state: the fraction of records
    whose peak slide exceeds each allowable displacement of the content (``allowable``), and the
    fraction under which it overturns (contents with a width and height). A record under which
    the object rocks has no slide (it is simulated as a rocking block): it is left out of the
    slide fractions and counted in ``n_rock``, never taken as 0.
``fragility``
    set family with stripes (``scale.levels`` or a list of ``scale_pga``) × building × floor ×
    content × friction pair × state: the lognormal fragility fitted by maximum likelihood over
    the stripes (Baker 2015, binomial likelihood), its median and β, and each stripe's level,
    records and exceedances.

References
----------
ASCE (2022). *Minimum Design Loads and Associated Criteria for Buildings and Other Structures*,
ASCE/SEI 7-22. §13.3.1, §16.2.3, §17.

Baker, J. W. (2015). Efficient analytical fragility function fitting using dynamic structural
analysis. *Earthquake Spectra* 31(1), 579–599.
"""

from __future__ import annotations

import math
from collections import defaultdict

import numpy as np

from floorslide.report.columns import MIN_RECORDS, ROCK
from floorslide.report.records import record_rows
from floorslide.report.statistics import summarize
from floorslide.report.study import Study, _float, _natural, _rank

ISOLATED_NOTE = (
    "isolated: ASCE 7-22 §17 takes component demands from the response history analysis of "
    "the isolated structure, not from H_f"
)
"""How the code treats isolated buildings (the tables' notes)."""

ISOLATED_ROW_NOTE = "no H_f: ASCE 7-22 §17 (response history)"
"""The ``note`` of a ``code`` row of an isolated building."""

OVERTURN = "overturn"
"""The ``state`` of overturning (contents with a width and height)."""


def _slide_state(allowable: float) -> str:
    return f"slide > {allowable:g} m"


def allowables(study: Study) -> dict[str, tuple[float, ...]]:
    """``{content id: allowable displacements (m, increasing, each once)}`` from the stored
    scene (``allowable``: a number or a list); contents without one are left out."""
    items = study.scene.get("contents", [])
    out = {}
    for c in items if isinstance(items, list) else []:
        if not isinstance(c, dict) or not isinstance(c.get("id"), str):
            continue
        a = c.get("allowable", ())
        a = a if isinstance(a, list | tuple) else [a]
        vals = {_float(x) for x in a if not isinstance(x, bool)}
        vals = sorted(x for x in vals if math.isfinite(x) and x > 0)
        if vals:
            out[c["id"]] = tuple(vals)
    return out


def pfa_profiles(study: Study, record_set: str) -> dict[str, dict[int, list[tuple[str, float]]]]:
    """Per building (in the tables' order) and floor: ``(record, PFA/PGA)`` of every record
    of the set, records in natural order; records without a positive PGA are left out."""
    out: dict[str, dict[int, list[tuple[str, float]]]] = {}
    for t in study.set_tasks(record_set):
        pga = _float(t.meta.get("pga"))
        if not (math.isfinite(pga) and pga > 0):
            continue
        by_floor = out.setdefault(str(t.meta["building"]), {})
        for floor, pfa in zip(np.asarray(t.floors).tolist(), np.asarray(t.pfa), strict=True):
            by_floor.setdefault(int(floor), []).append((str(t.meta["record"]), float(pfa) / pga))
    order = list(study.buildings)
    return {
        b: {f: sorted(v, key=lambda o: _natural(o[0])) for f, v in sorted(out[b].items())}
        for b in sorted(out, key=lambda b: _rank(order, b))
    }


def fixed_period(study: Study, record_set: str, bid: str) -> float:
    """The fixed-base fundamental period stored with the building's tasks of the set (the
    superstructure's for an isolated building; NaN if none is stored)."""
    for t in study.set_tasks(record_set):
        if str(t.meta["building"]) == bid:
            value = _float(t.meta.get("fixed_period"))
            return value if math.isfinite(value) and value > 0 else math.nan
    return math.nan


def scaling_table(study: Study) -> list[dict]:
    """The ``scaling`` table (see the module docstring)."""
    rows = []
    for e in study.scaling:
        for r in e.get("records", []):
            rows.append(
                dict(
                    record_set=str(e["set"]),
                    family=str(e.get("family", "")),
                    method=str(e.get("method", "")),
                    level=_float(e.get("level")),
                    record=str(r["record"]),
                    factor=_float(r.get("factor")),
                    fit_factor=_float(r.get("fit_factor")),
                    misfit=_float(r.get("misfit")),
                    outside_limits=bool(r.get("outside_limits", False)),
                )
            )
    return rows


def suite_table(study: Study) -> list[dict]:
    """The ``suite`` table (see the module docstring)."""
    rows = []
    for e in study.scaling:
        s = e.get("suite")
        if not isinstance(s, dict):
            continue
        lo, hi = [*(e.get("period_range") or []), math.nan, math.nan][:2]
        f = [_float(r.get("factor")) for r in e.get("records", [])]
        rows.append(
            dict(
                record_set=str(e["set"]),
                target=str(e.get("target_source") or e.get("target", "")),
                method=str(e.get("method", "")),
                period=_float(e.get("period")),
                period_lo=_float(lo),
                period_hi=_float(hi),
                damping=_float(e.get("damping")),
                level=_float(e.get("level")),
                n_records=len(f),
                factor_min=min(f) if f else math.nan,
                factor_max=max(f) if f else math.nan,
                n_outside_limits=sum(bool(r.get("outside_limits")) for r in e.get("records", [])),
                suite_factor=_float(e.get("suite_factor"), 1.0),
                mean_over_target_min=_float(s.get("min_ratio")),
                at_period=_float(s.get("at")),
                passes=bool(s.get("passes")),
            )
        )
    return rows


def storey_heights(study: Study, building) -> list[float] | None:
    """The scene's ``storey_heights`` of a building (of its superstructure when isolated), or
    None when the scene gives none (equal storeys)."""
    by_id = {b.get("id"): b for b in study.scene.get("buildings", []) if isinstance(b, dict)}
    spec = by_id.get(building.base, {})
    if spec.get("kind") == "isolated":
        spec = by_id.get(spec.get("superstructure"), {})
    value = spec.get("storey_heights")
    if value is None:
        return None
    return [float(v) for v in (value if isinstance(value, list) else [value])]


def _relative_heights(study: Study, building) -> np.ndarray:
    """``z/h`` of the building's floors (:func:`floorslide.practice.code.relative_heights`);
    NaN when the building has no storeys."""
    from floorslide.practice.code import relative_heights

    if building.stories < 1:
        return np.full(1, math.nan)
    return relative_heights(building.stories, storey_heights(study, building))


def code_table(study: Study) -> list[dict]:
    """The ``code`` table (see the module docstring): ASCE 7-22 Eq. 13.3-4 beside the computed
    PFA/PGA (:func:`pfa_profiles`, as the PFA-profile figure draws it)."""
    from floorslide.practice.code import asce7_floor_amplification

    rows = []
    for rs in study.sets:
        for bid, floors in pfa_profiles(study, rs).items():
            b = study.buildings[bid]
            fixed = b.kind == "fixed"
            period = fixed_period(study, rs, bid)
            heights = _relative_heights(study, b)
            for floor, obs in floors.items():
                amp = np.array([a for _, a in obs], dtype=float)
                amp = amp[np.isfinite(amp)]
                _, med, p84 = summarize(amp)
                z_h = float(heights[floor]) if 0 <= floor < heights.size else math.nan
                h_f = math.nan
                if fixed and 0 <= z_h <= 1 and period > 0:
                    h_f = float(asce7_floor_amplification(z_h, period))
                rows.append(
                    dict(
                        record_set=rs,
                        building=bid,
                        building_kind=b.kind,
                        isolation_period=b.isolation_period,
                        floor=floor,
                        z_over_h=z_h,
                        period_a=period if fixed else math.nan,
                        h_f=h_f,
                        n_records=int(amp.size),
                        few_records=amp.size < MIN_RECORDS,
                        pfa_pga_median=med,
                        pfa_pga_p84=p84,
                        median_over_h_f=med / h_f if h_f == h_f else math.nan,
                        p84_over_h_f=p84 / h_f if h_f == h_f else math.nan,
                        note="" if fixed else ISOLATED_ROW_NOTE,
                    )
                )
    return rows


def _exceedance_groups(study: Study) -> dict[tuple, dict]:
    """Per (set, building, floor, content, mu_k, mu_s): records, rocking records, and per
    state the records exceeding it."""
    allow = allowables(study)
    groups: dict[tuple, dict] = {}
    for r in record_rows(study):
        states = [_slide_state(a) for a in allow.get(r["content"], ())]
        has_rock = r.get("observed_outcome", "") != "" or math.isfinite(_float(r.get("overturned")))
        if not states and not has_rock:
            continue
        key = (r["record_set"], r["building"], r["floor"], r["content"], r["mu_k"], r["mu_s"])
        g = groups.setdefault(key, dict(n=0, n_rock=0, exceed=defaultdict(int), states=[]))
        if not g["states"]:
            g["states"] = list(zip(states, allow.get(r["content"], ()), strict=True))
            if has_rock:
                g["states"].append((OVERTURN, math.nan))
        g["n"] += 1
        rocks = r["outcome"] == ROCK
        g["n_rock"] += int(rocks)
        peak = _float(r["peak_slide"])
        for state, a in g["states"]:
            if state == OVERTURN:
                g["exceed"][state] += int(_float(r.get("overturned"), 0.0) == 1.0)
            elif not rocks and peak > a:
                g["exceed"][state] += 1
    return groups


def _object_cols(rs, b, floor, content, mu_k, mu_s, state, allowable) -> dict:
    """The columns naming an object and its state in the exceedance and fragility tables."""
    return dict(
        record_set=rs,
        building=b.id,
        building_kind=b.kind,
        isolation_period=b.isolation_period,
        floor=floor,
        content=content,
        mu_k=mu_k,
        mu_s=mu_s,
        state=state,
        allowable=allowable,
    )


def exceedance_table(study: Study) -> list[dict]:
    """The ``exceedance`` table (see the module docstring)."""
    rows = []
    for (rs, bid, floor, content, mu_k, mu_s), g in _exceedance_groups(study).items():
        b = study.buildings[bid]
        for state, a in g["states"]:
            over = state == OVERTURN
            n_known = g["n"] if over else g["n"] - g["n_rock"]
            k = g["exceed"][state]
            rows.append(
                dict(
                    **_object_cols(rs, b, floor, content, mu_k, mu_s, state, a),
                    n_records=g["n"],
                    n_rock=0 if over else g["n_rock"],
                    n_exceed=k,
                    n_records_exceedance=n_known,
                    fraction=k / n_known if n_known else math.nan,
                    few_records=n_known < MIN_RECORDS,
                )
            )
    return rows


def stripes(study: Study) -> dict[str, tuple[str, list[tuple[str, float]]]]:
    """``{family: (IM label, [(set, level), …] by level)}`` of the families with two or more
    scalings (``scale.levels``, or a list of ``scale_pga``)."""
    fam: dict[str, list[tuple[str, float]]] = defaultdict(list)
    label: dict[str, str] = {}
    for e in study.scaling:
        family = str(e.get("family", ""))
        level = _float(e.get("level"))
        if family and math.isfinite(level) and str(e["set"]) != family:
            fam[family].append((str(e["set"]), level))
            label[family] = str(e.get("im", ""))
    return {f: (label[f], sorted(v, key=lambda x: x[1])) for f, v in fam.items() if len(v) > 1}


def fragility_table(study: Study, exceedance: list[dict]) -> list[dict]:
    """The ``fragility`` table (see the module docstring): one lognormal curve per family,
    building, floor, content, friction pair and state, by maximum likelihood over the stripes
    (:func:`floorslide.practice.fragility.fit_fragility`)."""
    from floorslide.practice.fragility import fit_fragility

    families = stripes(study)
    if not families:
        return []
    by_set = defaultdict(dict)
    for r in exceedance:
        key = (r["building"], r["floor"], r["content"], r["mu_k"], r["mu_s"], r["state"])
        by_set[r["record_set"]][key] = r
    rows = []
    for family, (im, members) in families.items():
        keys = [k for s, _ in members for k in by_set.get(s, {})]
        for key in dict.fromkeys(keys):
            got = [(lvl, by_set[s].get(key)) for s, lvl in members]
            got = [(lvl, r) for lvl, r in got if r is not None]
            levels = tuple(lvl for lvl, _ in got)
            known = tuple(
                r["n_records"] - r["n_rock"] for _, r in got
            )  # rocking records have no slide
            k = tuple(r["n_exceed"] for _, r in got)
            bid, floor, content, mu_k, mu_s, state = key
            b = study.buildings[bid]
            row = dict(
                **_object_cols(
                    family, b, floor, content, mu_k, mu_s, state, got[0][1]["allowable"]
                ),
                im=im,
                levels=levels,
                n_records=known,
                n_exceed=k,
            )
            rocks = [(lvl, r["n_rock"]) for lvl, r in got if r["n_rock"]]
            caveat = (
                "rocking records have no slide and are left out ("
                + ", ".join(f"{n} at {lvl:g}" for lvl, n in rocks)
                + ")"
                if rocks
                else ""
            )
            usable = [(x, n, m) for x, n, m in zip(levels, known, k, strict=True) if n > 0]
            if len(usable) < 2:
                note = "fewer than 2 stripes with a slide: no fit"
                row.update(median=math.nan, beta=math.nan)
            elif any(n < 2 for _, n, _ in usable):
                note = "a stripe has a single record: no fit (give each stripe ≥ 2 records)"
                row.update(median=math.nan, beta=math.nan)
            else:
                x, n, m = (np.array(v, dtype=float) for v in zip(*usable, strict=True))
                fit = fit_fragility(x, n.astype(int), m.astype(int))
                note = fit.note
                if len(usable) < len(levels) and not note:
                    note = "fitted over the stripes with a slide only"
                if math.isfinite(fit.median) and not x[0] <= fit.median <= x[-1]:
                    side = "above the largest" if fit.median > x[-1] else "below the smallest"
                    note = "; ".join(filter(None, (note, f"θ lies {side} stripe: extrapolated")))
                row.update(median=fit.median, beta=fit.beta)
            row["note"] = "; ".join(filter(None, (note, caveat)))
            rows.append(row)
    return rows


def practice_notes(study: Study) -> list[str]:
    """The conventions of the practice tables, for the notes every output carries."""
    notes = []
    if any(e.get("method") in ("range", "period") for e in study.scaling):
        notes.append(
            "scaling to a target spectrum (scaling, suite tables): one factor per record, the "
            "geometric mean of target/record S_a over the range (least squares in ln S_a) or "
            "the ratio at T*, times the stripe's level; a pair is scaled on its RotD100 "
            "(ASCE 7-22 §16.2.3.2); the suite passes when its mean spectrum is ≥ 90 % of the "
            "target at every period of the range"
        )
    notes.append(
        "code: ASCE 7-22 §13.3.1 H_f with z/h = floor/stories (equal storey heights) and "
        f"T_a = the model's fixed-base period; {ISOLATED_NOTE}"
    )
    if allowables(study) or any(
        c.rock_peak_ratio is not None for t in study.tasks for c in t.contents
    ):
        notes.append(
            "exceedance: fraction of records whose peak slide exceeds the allowable "
            "displacement; records under which the object rocks (a slide–rock block) are left out "
            "(n_rock), never counted as not exceeding; overturn counts every record"
        )
    if stripes(study):
        notes.append(
            "fragility: lognormal P(exceed | im) = Φ(ln(im/θ)/β) by maximum likelihood over the "
            "stripes (binomial likelihood, Baker 2015); NaN θ, β with a note where no estimate "
            "exists (no exceedance, all exceed, or a 0 → 1 jump)"
        )
    return notes
