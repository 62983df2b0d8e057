"""Figures that were easy to misread: each case drawn from the synthetic study, changed where
needed to hold it, and checked on the matplotlib objects."""

from __future__ import annotations

import copy
import dataclasses

import numpy as np
import pytest

from floorslide.report import design_tables, plots
from floorslide.report.columns import ROCK
from floorslide.report.study import load_study
from tests.conftest import ROOT


def _strip_marks(ax) -> list[float]:
    """The x of every mark in the 'rock' strip above `ax`."""
    xs = []
    for child in ax.child_axes:
        for line in child.get_lines():
            xs += list(np.asarray(line.get_xdata(), dtype=float))
    return xs


def test_slide_vs_mu_keeps_a_friction_value_at_which_every_building_rocks(study):
    """At the largest mu every building rocks: that mu stays on the axis, its marks in the
    strip (matplotlib's autoscale left it off: the strip was empty)."""
    tables = design_tables(study.path)
    rows = [
        dict(
            r,
            median_outcome=ROCK,
            p84_outcome=ROCK,
            peak_slide_median=np.nan,
            peak_slide_p84=np.nan,
            n_rock=r["n_records"],
        )
        if r["mu_k"] == 0.2 and r["record_set"] == "broad-band"
        else r
        for r in tables["slides"]
    ]
    rocked = dataclasses.replace(tables, tables={**tables.tables, "slides": rows})
    st = load_study(study.path)
    fig = plots.figure_slide_vs_mu(st, rocked, "broad-band")
    ax = fig.axes[0]
    lo, hi = ax.get_xlim()
    assert lo < 0.05 and hi > 0.2
    marks = _strip_marks(ax)
    assert marks and all(lo <= x <= hi for x in marks)
    assert sum(abs(x - 0.2) < 0.02 for x in marks) == 2 * 3  # median and p84, 3 buildings


@pytest.fixture
def histories_everywhere(study):
    """The study with the history record stored on every building, of 2 of the cabinet's 3
    friction values."""
    st = load_study(study.path)
    fixed = next(t for t in st.tasks if t.meta["record"] == "bb1" and t.meta["building"] == "fixed")
    h = copy.deepcopy(fixed.histories)
    h.slides["cabinet/floor_1"] = h.slides["cabinet/floor_1"][[0, 2]]
    h.mu_k["cabinet/floor_1"] = np.array([0.05, 0.2])
    for t in st.tasks:
        if t.meta["record"] == "bb1":
            t.histories = h
    return st


def test_the_histories_figure_says_what_it_leaves_out(histories_everywhere, monkeypatch):
    monkeypatch.setattr(plots, "MAX_HISTORY_BUILDINGS", 2)
    fig = plots.figure_histories(histories_everywhere, "broad-band")
    title = " ".join(fig.get_suptitle().split())
    assert "slide histories of 2 of its 3 friction values (mu = 0.05, 0.2" in title
    assert "2 of the 3 buildings (evenly picked: fixed, isolated@T=2.5)" in title


def test_the_histories_figure_fits_a_page(histories_everywhere):
    """Three buildings: two side by side, the third below (it was 3 columns: 1.7 pages wide)."""
    fig = plots.figure_histories(histories_everywhere, "broad-band")
    assert fig.get_figwidth() * plots.DPI <= 1400
    titles = [ax.get_title() for ax in fig.axes if ax.get_visible()]
    assert sum(t.endswith("floor absolute acceleration") for t in titles) == 3


def _fragility_tables(study):
    tables = design_tables(study.path)
    base = dict(record_set="bb", building="fixed", floor=1, content="cabinet", mu_k=0.1,
                mu_s=0.1, im="multiple of the target spectrum", levels=(0.5, 1.0, 1.5),
                n_records=(10, 10, 10), note="")  # fmt: skip
    rows = [  # a near-jump from three stripes, and a gradual rise
        dict(base, state="slide > 0.05 m", n_exceed=(0, 1, 10), median=1.03, beta=0.055),
        dict(base, state="slide > 0.1 m", n_exceed=(1, 4, 7), median=1.1, beta=0.6),
    ]
    return dataclasses.replace(tables, tables={**tables.tables, "fragility": rows})


def test_fragility_says_when_the_stripes_do_not_resolve_beta(study):
    fig = plots.figure_fragility(load_study(study.path), _fragility_tables(study), "bb")
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    jump = next(t for t in labels if t.startswith("slide > 0.05 m"))
    assert "β unresolved: 1 of 3 stripes between 0 and 1" in jump
    gradual = next(t for t in labels if t.startswith("slide > 0.1 m"))
    assert gradual == "slide > 0.1 m: θ = 1.1, β = 0.60"


def test_fragility_draws_extrapolation_dotted_and_its_legend_off_the_curves(study):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = plots.figure_fragility(load_study(study.path), _fragility_tables(study), "bb")
    ax = fig.axes[0]
    solid = [ln for ln in ax.get_lines() if ln.get_linestyle() == "-"]
    dotted = [ln for ln in ax.get_lines() if ln.get_linestyle() == ":"]
    assert len(solid) == 2
    for ln in solid:  # the fit is drawn solid between the stripes only
        x = np.asarray(ln.get_xdata(), dtype=float)
        assert x.min() == 0.5 and x.max() == 1.5
    assert dotted  # and dotted beyond them
    for ln in dotted:
        x = np.asarray(ln.get_xdata(), dtype=float)
        assert x.max() <= 0.5 or x.min() >= 1.5
    assert "fit beyond the stripes (extrapolated)" in [
        t.get_text() for t in ax.get_legend().get_texts()
    ]
    FigureCanvasAgg(fig).draw()
    legend, panel = ax.get_legend().get_window_extent(), ax.get_window_extent()
    assert not legend.overlaps(panel), "the legend covers the curves"


def test_every_building_of_the_spectra_figure_has_its_own_marker(study):
    fig = plots.figure_frs(load_study(study.path), "broad-band", 0.05)
    ax = fig.axes[0]
    markers = [ln.get_marker() for ln in ax.get_lines()]
    assert len(markers) == 3 and len(set(markers)) == 3 and "None" not in markers


def test_the_ecdf_avoids_a_friction_value_at_which_the_object_rocks(study, monkeypatch):
    """At the median stored mu (0.1) the object rocks under every record: the panel takes
    the median of the values at which it slides, and any value can be asked for."""
    from floorslide.report import records

    real = records.record_rows

    def rocking_at_01(st):
        return [
            dict(r, outcome=ROCK, peak_slide=np.nan) if r["mu_k"] == 0.1 else r for r in real(st)
        ]

    monkeypatch.setattr(records, "record_rows", rocking_at_01)
    st = load_study(study.path)
    tables = design_tables(study.path)
    title = plots.figure_slide_ecdf(st, tables, "broad-band").axes[0].get_title()
    assert "mu_k = 0.05 (the median value at which it slides)" in title
    title = plots.figure_slide_ecdf(st, tables, "broad-band", mu=0.2).axes[0].get_title()
    assert "mu_k = 0.2 (as asked)" in title
    title = plots.figure_slide_ecdf(st, tables, "broad-band", mu=0.12).axes[0].get_title()
    assert "mu_k = 0.1 (the stored value nearest 0.12)" in title


TARGET_SCENE = f"""
[scene]
name = "scaled to a target"

[[records]]
set = "design"
catalog = "{(ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()}"
where = {{ station_id = ["ELC-180", "TAF-021", "EMO-270"] }}

[records.scale]
target = {{ sds = 1.0, sd1 = 0.6, tl = 8.0 }}
periods = [0.2, 2.0]
levels = [0.5, 1.0]

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.3

[[contents]]
id = "box"
floors = [1]
mu = [0.3]

[spectra]
floors = [0]
damping = [0.05]
periods = [0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0]
"""


@pytest.fixture(scope="module")
def scaled(tmp_path_factory):
    from floorslide.run.execute import execute
    from floorslide.scene.planner import plan
    from floorslide.scene.schema import parse_scene

    path = tmp_path_factory.mktemp("scaled") / "scaled.h5"
    p = plan(parse_scene(TARGET_SCENE, ROOT / "s.toml"))
    execute(p, str(path), workers=1, progress=False)
    return load_study(path)


def test_scaled_records_are_drawn_against_the_target(scaled, tmp_path):
    """The figure that was missing: each record's scaled spectrum (the ground of the
    fixed-base building as run), their mean, the target × level and 90 % of it."""
    from floorslide.practice.target import TargetSpectrum
    from floorslide.report.plots import G, figure_scaled_spectra

    target = TargetSpectrum.two_point(1.0, 0.6, 8.0)
    for rs, level in (("design@0.5x", 0.5), ("design@1x", 1.0)):
        fig = figure_scaled_spectra(scaled, rs)
        ax = fig.axes[0]
        lines = ax.get_lines()
        grey = [ln for ln in lines if ln.get_color() == "0.6"]
        assert len(grey) == 3
        psa = []
        for t in scaled.set_tasks(rs):
            (sp,) = [s for s in t.spectra if int(s.floor) == 0]
            psa.append(np.asarray(sp.psa)[0] / G)
        mean = next(ln for ln in lines if ln.get_color() == "black")
        np.testing.assert_allclose(mean.get_ydata(), np.mean(psa, axis=0), rtol=1e-12)
        red = [ln for ln in lines if ln.get_color() == "tab:red"]
        x = np.asarray(red[0].get_xdata())
        np.testing.assert_allclose(red[0].get_ydata(), level * target(x), rtol=1e-12)
        np.testing.assert_allclose(red[1].get_ydata(), 0.9 * level * target(x), rtol=1e-12)
        assert "suite check" in fig.get_suptitle()
    names = [p.name for p in plots.plot_figures(scaled, tmp_path / "fig")]
    assert "scaled_spectra_design_0.5x.png" in names and "scaled_spectra_design_1x.png" in names


def test_no_scaled_spectra_without_a_target(study):
    assert plots.figure_scaled_spectra(load_study(study.path), "broad-band") is None
