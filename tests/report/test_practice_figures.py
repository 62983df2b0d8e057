"""Issue 18 figures: the PFA/PGA profile against ASCE 7-22 §13.3.1 ``H_f``, the empirical CDF of
the peak slide (rocking records never drawn as a slide of 0), the fragility curves of the
``fragility`` table, and every figure of a single design (one friction value, one fixed-base
and one isolated building).

The run: three short SLAMMER records (Northridge RRS-228, Cape Mendocino PET-090 and RIO-360)
on a 3-storey fixed-base building (T = 0.2 s: ``H_f`` at the roof is 1 + 2.5 = 3.5) and the
same building on linear isolation (T_i = 2.5 s), a cabinet on floors 1 and 3 and a slender
block on the roof (B/H = 0.25 ≤ mu = 0.3: it holds its corner and rocks wherever the roof's
PFA exceeds 0.25 g — under all three records on the fixed base, under two on isolation).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from matplotlib.figure import Figure

from floorslide.practice import asce7_floor_amplification, fit_fragility
from floorslide.report import plots
from floorslide.report.plots import (
    _allowables,
    _png,
    figure_fragility,
    figure_pfa_profile,
    figure_slide_ecdf,
    figure_slide_ratio,
    figure_slide_vs_mu,
    plot_figures,
)
from floorslide.report.records import record_rows
from floorslide.report.study import load_study
from floorslide.report.tables import design_tables
from floorslide.run.execute import execute
from floorslide.run.store import ResultFile
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene
from tests.conftest import ROOT

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()
T_FIXED = 0.2
STORIES = 3

SCENE = f"""
[scene]
name = "single design"

[[records]]
set = "s"
catalog = "{CATALOG}"
where = {{ station_id = ["RRS-228", "PET-090", "RIO-360"] }}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = {STORIES}
period = {T_FIXED}
damping = 0.05

[[buildings]]
id = "iso"
kind = "isolated"
superstructure = "fixed"
period = 2.5
damping = 0.1

[[contents]]
id = "cabinet"
floors = [1, 3]
mu = [0.3]
width = 0.5
height = 1.5

[[contents]]
id = "slender"
floors = "roof"
mu = [0.3]
width = 0.4
height = 1.6

[spectra]
floors = "all"
damping = [0.05]
periods = {{ min = 0.05, max = 4.0, n = 30 }}
"""


@pytest.fixture(scope="module")
def single(tmp_path_factory):
    """The result file of the run described above."""
    folder = tmp_path_factory.mktemp("single")
    path = folder / "scene.toml"
    path.write_text(SCENE)
    out = folder / "out.h5"
    execute(plan(load_scene(path)), str(out), workers=1)
    return out


@pytest.fixture(scope="module")
def read(single):
    """The single design read: study and design tables."""
    study = load_study(single)
    return study, design_tables(study)


def _fragility_rows(buildings: dict) -> list[dict]:
    """Rows of the ``fragility`` table (the contract of issue 18) for the set family
    ``design``: two slide states fitted from made-up stripe counts, and ``overturn`` with no
    exceedance (no fit, a note)."""
    levels = (0.5, 0.75, 1.0, 1.5, 2.0)
    n = (7,) * 5
    rows = []
    for bid, b in buildings.items():
        for state, allowable, k in (
            ("slide > 0.05 m", 0.05, (0, 1, 3, 5, 6)),
            ("slide > 0.2 m", 0.2, (0, 0, 1, 2, 4)),
            ("overturn", math.nan, (0, 0, 0, 0, 0)),
        ):
            fit = fit_fragility(levels, n, k)
            rows.append(
                dict(
                    record_set="design",
                    building=bid,
                    building_kind=b.kind,
                    isolation_period=b.isolation_period,
                    floor=STORIES,
                    content="cabinet",
                    mu_k=0.3,
                    mu_s=0.3,
                    state=state,
                    allowable=allowable,
                    im="multiple of the target spectrum",
                    levels=levels,
                    n_records=n,
                    n_exceed=k,
                    median=fit.median,
                    beta=fit.beta,
                    note=fit.note,
                )
            )
    return rows


def _with_fragility(tables, rows):
    return dataclasses.replace(tables, tables={**tables.tables, "fragility": rows})


def _labelled(ax, start: str):
    return [ln for ln in ax.get_lines() if str(ln.get_label()).startswith(start)]


# --------------------------------------------------------------------------------------------
# PFA/PGA profile


def test_pfa_profile_against_asce7_hf(single, read):
    study, tables = read
    fig = figure_pfa_profile(study, tables, "s")
    assert isinstance(fig, Figure)
    fixed_ax, iso_ax = fig.axes
    assert fixed_ax.get_title() == "fixed-base buildings"
    assert iso_ax.get_title() == "isolated buildings"
    # the code's H_f, dotted, over z/h in [0, 1]: 1 + 2.5 z/h for T_a = 0.2 s, 3.5 at the roof
    (hf,) = _labelled(fixed_ax, "ASCE 7-22 H_f (T_a = 0.2 s)")
    x, y = hf.get_xdata(), hf.get_ydata()
    assert hf.get_linestyle() == ":" and len(x) == 50
    assert y[0] == 0 and y[-1] == STORIES
    assert x[-1] == pytest.approx(float(asce7_floor_amplification(1.0, T_FIXED)))
    assert x[-1] == pytest.approx(3.5)
    np.testing.assert_allclose(x, 1 + 2.5 * y / STORIES)
    assert not _labelled(iso_ax, "ASCE 7-22")  # never for an isolated building
    texts = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    assert any(t.startswith("isolated buildings: ASCE 7-22 §17") for t in texts)
    # the medians are NumPy medians of each record's PFA/PGA, read independently of the report
    ratio: dict[tuple[str, int], list[float]] = {}
    for t in ResultFile(single).tasks():
        for floor, pfa in zip(t.floors, t.pfa, strict=True):
            ratio.setdefault((t.meta["building"], int(floor)), []).append(pfa / t.meta["pga"])
    for ax, bid in ((fixed_ax, "fixed"), (iso_ax, "iso")):
        (median,) = _labelled(ax, f"{bid}: median (3 records)")
        floors = median.get_ydata()
        np.testing.assert_array_equal(floors, np.arange(STORIES + 1))
        expected = [np.median(ratio[(bid, f)]) for f in floors]
        np.testing.assert_allclose(median.get_xdata(), expected, rtol=1e-12)
        assert median.get_marker() == "o"
    table = {
        (r["building"], r["floor"]): r["pfa_pga_median"]
        for r in tables["pfa"]
        if r["record_set"] == "s"
    }
    (median,) = _labelled(fixed_ax, "fixed: median")
    np.testing.assert_allclose(median.get_xdata(), [table[("fixed", f)] for f in range(4)])


def test_pfa_profile_without_tasks_or_period(study):
    s = load_study(study.path)
    tables = design_tables(s)
    assert figure_pfa_profile(s, tables, "no such set") is None
    # a file without the fixed-base period: no H_f, and the figure says why
    fig = figure_pfa_profile(s, tables, "broad-band")
    assert len(fig.axes) == 2
    assert not _labelled(fig.axes[0], "ASCE 7-22")
    texts = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    assert "no H_f for fixed: the file does not store T_a" in texts


# --------------------------------------------------------------------------------------------
# empirical CDF of the peak slide


def _steps(ax) -> dict[str, object]:
    return {str(ln.get_label()): ln for ln in ax.get_lines() if ln.get_drawstyle() != "default"}


def test_ecdf_rocking_records_are_never_a_slide_of_zero(study):
    s = load_study(study.path)
    fig = figure_slide_ecdf(s, design_tables(s), "broad-band")
    (ax,) = fig.axes  # one content on one floor
    assert ax.get_title() == "cabinet on floor 1, mu_k = 0.1"  # the median of 0.05, 0.1, 0.2
    steps = _steps(ax)
    assert set(steps) == {"fixed (1 rock)", "isolated@T=2", "isolated@T=2.5"}
    # fixed, mu 0.1: record bb3 rocks; the curve ends at 2 of 3 records, not at 1
    fixed = steps["fixed (1 rock)"]
    assert fixed.get_ydata()[-1] == pytest.approx(2 / 3)
    slides = sorted(study.truth[("broad-band", "fixed", r)]["peak"][1] for r in ("bb1", "bb2"))
    np.testing.assert_allclose(fixed.get_xdata()[1:3], slides)
    np.testing.assert_allclose(fixed.get_ydata()[:3], [0, 1 / 3, 2 / 3])
    assert steps["isolated@T=2"].get_ydata()[-1] == 1.0
    assert figure_slide_ecdf(s, design_tables(s), "no such set") is None


def test_ecdf_on_a_real_run_and_allowables(read):
    study, tables = read
    rows = [r for r in record_rows(study) if r["content"] == "slender"]
    n_rock = {
        b: sum(r["outcome"] == "rock" for r in rows if r["building"] == b) for b in study.buildings
    }
    assert n_rock == {"fixed": 3, "iso": 2}  # the scene's premise
    scene = {**study.scene, "contents": [dict(c) for c in study.scene["contents"]]}
    scene["contents"][0]["allowable"] = [0.2, 0.05]
    scene["contents"][1]["allowable"] = 0.1
    with_gaps = dataclasses.replace(study, scene=scene)
    assert _allowables(with_gaps, "cabinet") == (0.05, 0.2)
    assert _allowables(with_gaps, "slender") == (0.1,)
    assert _allowables(study, "cabinet") == ()
    fig = figure_slide_ecdf(with_gaps, tables, "s")
    assert [ax.get_title() for ax in fig.axes] == [
        "cabinet on floor 1, mu_k = 0.3",
        "cabinet on floor 3, mu_k = 0.3",
        # it rocks under most records at every friction value: said, not hidden
        "slender on floor 3, mu_k = 0.3 (the median stored value: it rocks under most records)",
    ]
    steps = _steps(fig.axes[2])
    # the iso slender rests under one record (slide 0) and rocks under two: it ends at 1/3
    assert steps["iso (2 rock)"].get_ydata()[-1] == pytest.approx(1 / 3)
    assert "fixed (3 rock)" not in steps  # no slide to draw: a legend entry only
    labels = [t.get_text() for t in fig.axes[2].get_legend().get_texts()]
    assert "fixed (3 rock): no slide drawn" in labels
    vertical = [ln for ln in fig.axes[0].get_lines() if ln.get_linestyle() == ":"]
    assert sorted(ln.get_xdata()[0] for ln in vertical) == [0.05, 0.2]


def test_ecdf_of_one_record_is_a_dot_plot(read):
    study, tables = read
    first = sorted(t.meta["record"] for t in study.tasks)[0]
    one = dataclasses.replace(study, tasks=[t for t in study.tasks if t.meta["record"] == first])
    fig = figure_slide_ecdf(one, tables, "s")
    ax = fig.axes[0]
    assert not _steps(ax)
    dots = [ln for ln in ax.get_lines() if ln.get_marker() == "o" and len(ln.get_xdata())]
    assert len(dots) == 2 and all(ln.get_linestyle() == "None" for ln in dots)
    assert [t.get_text() for t in ax.get_yticklabels()] == ["fixed", "iso"]


# --------------------------------------------------------------------------------------------
# fragility


def test_fragility_curves_and_notes(read):
    study, tables = read
    rows = _fragility_rows(study.buildings)
    with_rows = _with_fragility(tables, rows)
    assert figure_fragility(study, tables, "design") is None  # no fragility table
    assert figure_fragility(study, with_rows, "other") is None  # no row of that family
    fig = figure_fragility(study, with_rows, "design")
    assert len(fig.axes) == 2  # one panel per building (one floor, content and mu_k)
    for ax, bid in zip(fig.axes, study.buildings, strict=True):
        assert ax.get_title() == f"{bid}: cabinet on floor {STORIES}, mu_k = 0.3"
        assert ax.get_xlabel() == "multiple of the target spectrum"
        assert ax.get_ylabel() == "P(exceed)"
        curves = [ln for ln in ax.get_lines() if ln.get_linestyle() == "-"]
        markers = [ln for ln in ax.get_lines() if ln.get_linestyle() == "None"]
        assert len(curves) == 2 and len(markers) == 3  # no curve for 'overturn'
        for curve, row in zip(curves, rows[:2], strict=True):
            x, y = curve.get_xdata(), curve.get_ydata()
            i = int(np.argmin(np.abs(x - row["median"])))
            assert x[i] == row["median"] and y[i] == pytest.approx(0.5, abs=1e-12)
            assert x[0] <= min(row["levels"]) and x[-1] >= max(row["levels"])
        np.testing.assert_allclose(markers[0].get_ydata(), np.array(rows[0]["n_exceed"]) / 7)
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        fit = rows[0]
        assert labels[0] == f"slide > 0.05 m: θ = {fit['median']:.3g}, β = {fit['beta']:.2f}"
        assert labels[2].startswith("overturn, no fit: no record exceeds")


# --------------------------------------------------------------------------------------------
# a single design: every figure, and one friction value or isolation period that reads


@pytest.mark.slow
def test_single_design_figures(single, read, tmp_path, monkeypatch):
    study, tables = read
    with_rows = _with_fragility(tables, _fragility_rows(study.buildings))
    monkeypatch.setattr(plots, "design_tables", lambda *a, **k: with_rows)
    written = plot_figures(single, tmp_path, workers=1)
    assert [p.name for p in written] == [
        "histories_s.png",
        "rocking_s.png",
        "frs_s.png",
        "slide_vs_mu_s.png",
        "overturning_s.png",
        "slide_ratio_s_iso-over-fixed.png",
        "pfa_profile_s.png",
        "slide_ecdf_s.png",
        "fragility_design.png",
    ]
    assert all(p.stat().st_size > 10_000 for p in written)
    # the same input gives the same bytes
    assert (
        _png(figure_pfa_profile(study, tables, "s"))
        == (tmp_path / "pfa_profile_s.png").read_bytes()
    )


def test_one_friction_value_or_period_does_not_collapse_the_axis(read):
    """A single design: the x axis spans ±50 % of its one value with one tick (not ±0.05 with
    ticks every 0.005), and the buildings stand side by side at it, not on top of each other."""
    study, tables = read
    fig = figure_slide_vs_mu(study, tables, "s")
    ax = fig.axes[0]  # cabinet on floor 1
    assert ax.get_xlim() == pytest.approx((0.15, 0.45))
    assert list(ax.get_xticks()) == [0.3]
    medians = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
    x = sorted(float(ln.get_xdata()[0]) for ln in medians)
    assert len(x) == 2 and x[0] < 0.3 < x[1]
    fig = figure_slide_ratio(study, tables, "s", "iso:fixed")
    assert fig.axes[0].get_xlim() == pytest.approx((1.25, 3.75))
    assert list(fig.axes[0].get_xticks()) == [2.5]
