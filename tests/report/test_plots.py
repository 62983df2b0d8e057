"""Figures (issue 12): rocking never drawn at 0, flexible equipment, broadening, incomplete."""

from __future__ import annotations

import numpy as np
import pytest

from floorslide.report import design_tables
from floorslide.report.plots import (
    building_colors,
    figure_frs,
    figure_histories,
    figure_oscillators,
    figure_slide_vs_mu,
    plot_figures,
)
from floorslide.report.study import load_study


@pytest.fixture(scope="module")
def rich(rich_study):
    s = load_study(rich_study.path)
    return s, design_tables(s)


def _lines_of(ax, color):
    return [line for line in ax.get_lines() if line.get_color() == color]


def test_rocking_is_drawn_at_the_top_never_at_zero(study):
    """Item 4: the median of pulse-like/fixed at mu 0.05 is 'rock' (every record rocks): no
    point at 0, an x at the top of the panel."""
    s = load_study(study.path)
    fig = figure_slide_vs_mu(s, design_tables(s), "pulse-like")
    ax = fig.axes[0]
    color = building_colors(s)["fixed"]
    lines = _lines_of(ax, color)
    median = next(line for line in lines if line.get_linestyle() == "-")
    x, y = np.asarray(median.get_xdata()), np.asarray(median.get_ydata(), dtype=float)
    assert np.isnan(y[x == 0.05]).all() and np.isfinite(y[x == 0.1]).all()
    (strip,) = ax.child_axes  # the 'rock' strip above the panel
    assert [t.get_text() for t in strip.get_yticklabels()] == ["rock"]
    tops = _lines_of(strip, color)
    assert {line.get_marker() for line in tops} == {"x", "^"}  # median and p84 rock
    assert {float(v) for line in tops for v in line.get_xdata()} == {0.05}
    for line in lines:  # nothing of the fixed building at y = 0 for mu = 0.05
        xs, ys = np.asarray(line.get_xdata()), np.asarray(line.get_ydata(), dtype=float)
        assert not np.any((xs == 0.05) & (ys == 0.0))
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert any("never 0" in t for t in labels)
    assert "caution: only 3 records (< 8)" in " ".join(fig._suptitle.get_text().split())


def test_oscillator_figure_and_histories(rich):
    """Item 3: spring deformation and top-mass acceleration in a figure and in the histories."""
    s, tables = rich
    fig = figure_oscillators(s, tables, "broad-band")
    labels = [ax.get_ylabel() for ax in fig.axes if ax.get_visible()]
    assert labels == ["peak spring deformation (mm)", "peak top-mass acceleration (g)"]
    row = next(
        r
        for r in tables["slides"]
        if r["content"] == "rack" and r["building"] == "fixed" and r["record_set"] == "broad-band"
    )
    color = building_colors(s)["fixed"]
    median = next(l for l in _lines_of(fig.axes[0], color) if l.get_linestyle() == "-")
    assert median.get_ydata()[0] == pytest.approx(1000 * row["peak_deformation_median"])
    assert figure_oscillators(load_study(s.source), design_tables(s), "pulse-like") is not None
    hist = figure_histories(s, "broad-band")
    titles = [ax.get_title() for ax in hist.axes]
    assert any("rack on floor 1: spring deformation" in t for t in titles)
    assert any("rack on floor 1: top mass absolute acceleration" in t for t in titles)
    assert any("rack on floor 1: base slide" in t for t in titles)


def test_frs_figure_shows_both_spectra(rich):
    s, _ = rich
    fig = figure_frs(s, "broad-band", 0.05)
    assert "broadened ±15 %" in fig._suptitle.get_text()
    styles = {line.get_linestyle() for line in fig.axes[0].get_lines()}
    assert styles == {"-", "--"}


@pytest.mark.slow
def test_plot_figures_writes_the_oscillator_figure(rich_study, tmp_path):
    names = [p.name for p in plot_figures(rich_study.path, tmp_path)]
    assert "oscillators_broad-band.png" in names and "oscillators_pulse-like.png" in names


def test_tables_made_already_give_the_same_figures(study, tmp_path):
    """The demo and the HTML report hand their design tables to plot_figures: the same
    files, byte for byte, as when it makes them."""
    s = load_study(study.path)
    own = plot_figures(s, tmp_path / "own")
    given = plot_figures(s, tmp_path / "given", tables=design_tables(s))
    assert [p.name for p in given] == [p.name for p in own] and own
    for a, b in zip(own, given, strict=True):
        assert a.read_bytes() == b.read_bytes(), a.name
