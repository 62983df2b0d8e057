"""Issue 15: rocking results in the reports — the per-record rocking columns equal the stored
arrays, the ``rocking`` design table equals NumPy statistics of them, an empty table says why,
the demo summary says how many records overturn, and ``rocking_<set>.png`` and
``overturning_<set>.png`` are drawn from a run with rocking results and only then.

The run: three short pulse-like SLAMMER records scaled to 0.35 g on a 1-storey fixed-base
building and the same on linear isolation (T_i = 2 and 3 s), with on the roof a slender cabinet
(B/H = 0.2; mu 0.1 slides, mu 0.3 holds its corner and rocks), a squat crate (B/H = 1, mu 0.2:
it slides) and a box without width and height. On the fixed base the cabinet rocks under every
record and overturns under two (one of them the history record, Northridge RRS-228).
"""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from floorslide.report import design_tables, format_markdown, record_table
from floorslide.report.formats import format_csv
from floorslide.run.execute import execute
from floorslide.run.store import ResultFile
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene
from tests.conftest import ROOT
from tests.format1 import to_format1

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()
HISTORY = "Northridge_1994_RRS-228"
B_OVER_H = 0.3 / 1.5
P84 = 84.0  # the package's percentile, numpy "linear" (Hyndman & Fan definition 7)
NOTE = (
    "no content with a width and height whose static friction holds its corner (mu_s ≥ B/H) "
    "has rocking results in this file"
)

SCENE = f"""
[scene]
name = "rocking"

[[records]]
set = "s"
catalog = "{CATALOG}"
where = {{ station_id = ["PET-090", "RRS-228", "KJM-000"] }}
scale_pga = 0.35

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.2
damping = 0.05

[[buildings]]
id = "iso"
kind = "isolated"
superstructure = "fixed"
period = [2.0, 3.0]
damping = 0.1

[[contents]]
id = "cabinet"
floors = "roof"
mu = [0.1, 0.3]
width = 0.3
height = 1.5

[[contents]]
id = "crate"
floors = "roof"
mu = [0.2]
width = 1.0
height = 1.0

[[contents]]
id = "box"
floors = "roof"
mu = [0.2]

[report]
history_record = "{HISTORY}"
"""


@pytest.fixture(scope="module")
def rocking(tmp_path_factory):
    """The result file of the run described above."""
    folder = tmp_path_factory.mktemp("rocking")
    path = folder / "scene.toml"
    path.write_text(SCENE)
    out = folder / "out.h5"
    execute(plan(load_scene(path)), str(out), workers=1)
    return out


@pytest.fixture(scope="module")
def older(rocking, tmp_path_factory):
    """The same file as one written before rocking was simulated: no rocking arrays, outcomes
    or histories (each task signed again as an older writer signed it; such files were of
    format 1, one group per task)."""
    from floorslide.run.snapshot import digest, snapshot
    from floorslide.run.store import BOOKKEEPING

    out = tmp_path_factory.mktemp("older") / "out.h5"
    to_format1(rocking, out)
    names = ("rock_peak_ratio", "rock_impacts", "rock_time", "overturned", "overturn_time")
    with h5py.File(out, "r+") as f:
        for g in f["tasks"].values():
            for content in g["contents"].values():
                for floor in content.values():
                    for name in (*names, "outcomes"):
                        if name in floor:
                            del floor[name]
            if "histories/rocking" in g:
                del g["histories/rocking"]
            g.attrs["sha256"] = digest(snapshot(g), BOOKKEEPING)
    return out


def _cabinets(out) -> dict[str, list[tuple[str, object]]]:
    """Per building: (record, the cabinet's stored ContentResult) of every task."""
    by: dict[str, list] = {}
    for t in ResultFile(out).tasks():
        c = next(c for c in t.contents if c.content == "cabinet")
        by.setdefault(t.meta["building"], []).append((t.meta["record"], c))
    return by


def test_per_record_rocking_columns_are_the_stored_arrays(rocking):
    df = record_table(rocking)
    assert df.attrs["units"]["rock_peak_ratio"] == "1"
    assert df.attrs["units"]["overturn_time_s"] == "s"
    seen = 0
    for t in ResultFile(rocking).tasks():
        for c in t.contents:
            sel = df[
                (df.record == t.meta["record"])
                & (df.building == t.meta["building"])
                & (df.content == c.content)
            ].sort_values("mu_k")
            assert len(sel) == len(c.mu_k)
            if c.content == "box":  # no width and height: nothing to say about rocking
                for k in ("rock_peak_ratio", "rock_impacts", "overturned", "rock_time_s"):
                    assert sel[k].isna().all(), k
                assert (sel.observed_outcome == "").all()
                continue
            impacts = np.where(c.rock_impacts >= 0, c.rock_impacts, np.nan)
            np.testing.assert_array_equal(sel.rock_peak_ratio, c.rock_peak_ratio)
            np.testing.assert_array_equal(sel.rock_impacts, impacts)
            np.testing.assert_array_equal(sel.overturned, c.overturned)
            np.testing.assert_array_equal(sel.overturn_time_s, c.overturn_time)
            np.testing.assert_array_equal(sel.rock_time_s, c.rock_time)
            np.testing.assert_array_equal(sel.slide_rock_time_s, c.slide_rock_time)
            assert list(sel.observed_outcome) == [str(o) for o in c.outcomes]
            seen += len(sel)
    assert seen
    # a block that rocks is its own outcome 'rock'; its slide values are its slide–rock block's
    rocked = df[df.observed_outcome.isin(["rock", "slide-rock", "overturn"])]
    assert len(rocked) and (rocked.outcome == "rock").all() and rocked.peak_slide.notna().all()
    over = df[df.observed_outcome == "overturn"]
    assert len(over) and (over.rock_peak_ratio == 1).all() and (over.overturned == 1).all()
    assert over.overturn_time_s.notna().all()
    slid = df[(df.content == "cabinet") & (df.mu_s == 0.1) & (df.observed_outcome == "slide")]
    assert len(slid) and slid.rock_peak_ratio.isna().all() and slid.rock_impacts.isna().all()


def test_the_rocking_table_equals_numpy_statistics_of_the_stored_arrays(rocking):
    rows = design_tables(rocking)["rocking"]
    # one row per building for the cabinet; the crate slides (mu 0.2 < B/H = 1), the box has
    # no geometry
    assert [(r["building"], r["content"]) for r in rows] == [
        ("fixed", "cabinet"),
        ("iso@T=2", "cabinet"),
        ("iso@T=3", "cabinet"),
    ]
    cabinets = _cabinets(rocking)
    for row in rows:
        obs = sorted(cabinets[row["building"]], key=lambda o: o[0])
        i = list(obs[0][1].mu_s).index(0.3)  # the friction that holds the corner
        peak = np.array([c.rock_peak_ratio[i] for _, c in obs])
        impacts = np.array([c.rock_impacts[i] for _, c in obs], dtype=float)
        over = np.array([c.overturned[i] for _, c in obs])
        n = len(obs)
        n_rock = int(np.sum((peak > 0) | (over > 0)))
        expected = {
            "record_set": "s",
            "floor": 1,
            "b_over_h": B_OVER_H,
            "alpha": math.atan(B_OVER_H),
            "mu_k": 0.3,
            "mu_s": 0.3,
            "n_records": 3,
            "few_records": True,
            "n_rock": n_rock,
            "rock_fraction": n_rock / n,
            "n_overturn": int(over.sum()),
            "overturn_fraction": over.sum() / n,
            "peak_ratio_median": np.median(peak),
            "peak_ratio_p84": np.percentile(peak, P84, method="linear"),
            "impacts_median": np.median(impacts),
        }
        for key, value in expected.items():
            if isinstance(value, str | bool):
                assert row[key] == value, (row["building"], key)
            else:
                assert row[key] == pytest.approx(value, rel=1e-15, abs=0), (row["building"], key)
    fixed, iso2, iso3 = rows
    # the case the table is for: the fixed base overturns the cabinet, isolation does not
    assert fixed["n_rock"] == 3 and fixed["n_overturn"] == 2 and fixed["peak_ratio_median"] == 1
    assert iso2["n_rock"] == 1 and iso2["n_overturn"] == 0 and 0 < iso2["peak_ratio_p84"] < 1
    assert iso3["n_rock"] == 0 and iso3["peak_ratio_p84"] == 0 and iso3["impacts_median"] == 0
    assert fixed["building_kind"] == "fixed" and math.isnan(fixed["isolation_period"])
    assert iso3["isolation_period"] == 3.0


def test_the_rocking_table_in_markdown_and_csv(rocking):
    tables = design_tables(rocking)
    assert any(n.startswith("rocking: contents with a width and height") for n in tables.notes)
    text = format_markdown(tables, ["rocking"])
    header = next(ln for ln in text.splitlines() if ln.startswith("| record_set"))
    assert "| alpha (rad) |" in header and "| peak_ratio_p84 |" in header
    assert "| mu_s |" in header and "| n_overturn |" in header
    assert "| slide_rock_time_median (s) |" in header and "| n_slide_rock |" in header
    fixed = next(ln for ln in text.splitlines() if ln.startswith("| s | fixed |"))
    assert "| 1† |" in fixed  # a p84 over 3 < 8 records
    csv = format_csv("rocking", tables["rocking"])
    assert csv.startswith(
        "record_set,building,building_kind,isolation_period,floor,floor_label,content,"
    )
    assert len(csv.splitlines()) == 1 + 3


def test_without_rocking_results_the_table_says_so(study):
    """The synthetic study: contents without width and height (and modes 'rock' written as a
    file from before rocking was simulated)."""
    tables = design_tables(study.path)
    assert tables["rocking"] == []
    assert f"rocking: {NOTE}" in tables.notes
    assert any("written before rocking objects were simulated" in n for n in tables.notes)
    assert f"_No rows: {NOTE}._" in format_markdown(tables, ["rocking"])
    assert format_csv("rocking", []).startswith(f"# {NOTE}\nrecord_set,building,")
    status = "INCOMPLETE: 1 of 2 tasks done"
    assert format_csv("rocking", [], status).startswith(f"# {status}\n# {NOTE}\nrecord_set,")
    df = record_table(study.path)
    assert df.rock_peak_ratio.isna().all() and df.overturned.isna().all()
    assert (df.observed_outcome == "").all()


def test_a_file_from_before_rocking_was_simulated_still_reports(older, tmp_path):
    from floorslide.cli import demo_summary
    from floorslide.report.plots import plot_figures

    tables = design_tables(older)
    assert tables["rocking"] == [] and f"rocking: {NOTE}" in tables.notes
    df = record_table(older)
    assert df.rock_peak_ratio.isna().all() and (df.observed_outcome == "").all()
    fixed = next(r for r in tables["slides"] if r["building"] == "fixed" and r["mu_s"] == 0.3)
    assert fixed["median_outcome"] == "rock" and math.isnan(fixed["peak_slide_median"])
    text = demo_summary(tables)
    assert "| rocks (3/3) |" in text and "overturn" not in text
    names = [p.name for p in plot_figures(older, tmp_path / "fig")]
    assert not any(n.startswith(("rocking", "overturning")) for n in names)


def test_the_demo_summary_says_how_many_overturn(rocking):
    from floorslide.cli import demo_summary

    text = demo_summary(design_tables(rocking))
    lines = text.splitlines()
    start = next(i for i, ln in enumerate(lines) if "'cabinet' on floor 1" in ln)
    legend = lines[start + 1]
    assert "m of them overturn" in legend and "the rocking table" in legend
    assert "never count as 0" in legend and "not simulated" not in legend
    table = lines[start + 2 :]
    fixed = next(ln for ln in table if ln.startswith("| fixed |")).split(" | ")
    assert fixed[3] == "rocks (3/3; 2 overturn) |"  # mu 0.3: every record rocks, two overturn
    assert not fixed[2].startswith("rocks")  # mu 0.1: it slides
    iso2 = next(ln for ln in table if ln.startswith("| iso@T=2 |")).split(" | ")
    assert iso2[3].endswith("(1 rock; 0 overturn) |")  # the median is a rest, one record rocks
    # the crate and the box never rock: no line about rocking under their headings
    crate = next(i for i, ln in enumerate(lines) if "'crate' on floor 1" in ln)
    assert lines[crate + 1].startswith("(caution")


@pytest.mark.slow
def test_the_rocking_figures_are_drawn_from_the_run(rocking, tmp_path):
    from floorslide.report.plots import figure_overturning, figure_rocking, plot_figures
    from floorslide.report.study import load_study

    names = [p.name for p in plot_figures(rocking, tmp_path / "fig")]
    assert names[:2] == ["histories_s.png", "rocking_s.png"]  # after the histories
    assert names.index("overturning_s.png") == names.index("slide_vs_mu_s.png") + 1
    again = {p.name: p for p in plot_figures(rocking, tmp_path / "again")}
    for name in ("rocking_s.png", "overturning_s.png"):
        png = (tmp_path / "fig" / name).read_bytes()
        assert png[:4] == b"\x89PNG" and again[name].read_bytes() == png  # bit for bit
    study = load_study(rocking)
    tables = design_tables(study)

    # rocking_s.png: theta/alpha under the history record, a panel per building that rocks
    fig = figure_rocking(study, "s")
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert [ax.get_title() for ax in axes] == [
        f"fixed, record {HISTORY}",
        f"iso@T=2, record {HISTORY}",
    ]  # the cabinet stays at rest on iso@T=3
    tasks = {t.meta["building"]: t for t in study.tasks if t.histories is not None}
    for ax in axes:
        task = tasks[ax.get_title().split(",")[0]]
        curve = ax.get_lines()[0]
        np.testing.assert_array_equal(curve.get_ydata(), task.histories.rocking["cabinet/floor_1"])
        levels = {float(ln.get_ydata()[0]) for ln in ax.get_lines()[1:] if ln.get_ls() == ":"}
        assert levels == {1.0, -1.0}
        assert [t.get_text() for t in ax.texts] == ["overturns", "overturns"]
    c = next(c for c in tasks["fixed"].contents if c.content == "cabinet")
    t_over = float(c.overturn_time[1])
    assert math.isfinite(t_over)  # the cabinet overturns on the fixed base
    marker = next(ln for ln in axes[0].get_lines() if ln.get_marker() == "X")
    assert float(marker.get_xdata()[0]) == t_over and abs(float(marker.get_ydata()[0])) == 1
    labels = [t.get_text() for t in axes[0].get_legend().get_texts()]
    assert f"cabinet on floor 1: overturns at {t_over:.3g} s, 1 impact" in labels
    assert not any(ln.get_marker() == "X" for ln in axes[1].get_lines())

    # overturning_s.png: fractions against the buildings, in the tables' order
    fig = figure_overturning(study, tables, "s")
    (ax,) = [ax for ax in fig.axes if ax.get_visible()]
    assert [t.get_text() for t in ax.get_xticklabels()] == ["fixed", "iso@T=2", "iso@T=3"]
    rock, over = ax.get_lines()[:2]
    rows = tables["rocking"]
    np.testing.assert_array_equal(rock.get_ydata(), [r["rock_fraction"] for r in rows])
    np.testing.assert_array_equal(over.get_ydata(), [r["overturn_fraction"] for r in rows])
    # the slide–rock mode: a dotted series of the fraction that slid while rocking, when any did
    slid = [r["n_slide_rock"] / r["n_records"] for r in rows]
    dotted = [ln for ln in ax.get_lines() if ln.get_linestyle() == ":"]
    if sum(slid) > 0:
        np.testing.assert_array_equal(dotted[0].get_ydata(), slid)
    else:
        assert not dotted


def test_no_rocking_figures_without_rocking_results(study, tmp_path):
    from floorslide.report.plots import plot_figures

    names = [p.name for p in plot_figures(study.path, tmp_path / "fig")]
    assert "histories_broad-band.png" in names
    assert not any(n.startswith(("rocking", "overturning")) for n in names)


def test_impacts_are_said_to_count_the_cascade_to_rest(rocking):
    """A block that tilts to 2 % of α counts over a thousand impacts (the geometric cascade to
    rest): every output that shows the count says what it counts."""
    from floorslide.report.columns import COLUMNS
    from floorslide.report.records import RECORD_COLUMNS

    tables = design_tables(rocking)
    assert any("cascade" in n and "rocking cycles" in n for n in tables.notes)
    described = {c.name: c.description for c in COLUMNS["rocking"]}
    assert "cascade" in described["impacts_median"]
    assert "cascade" in next(c.description for c in RECORD_COLUMNS if c.name == "rock_impacts")


def test_significant_impacts_of_slide_rock_blocks(rocking):
    """A run simulates a rocking object as a slide–rock block (fs.slide_rock), which counts
    significant impacts as fs.rock does: stored per friction pair, in the per-record table and
    the rocking table's median; 0 where the object stayed at rest without a simulation."""
    from floorslide.run.store import ResultFile

    df = record_table(rocking)
    rocked = df[df["mode"].isin(["rock", "slide-rock"])]
    assert len(rocked) and rocked.rock_significant_impacts.notna().all()
    assert (rocked.rock_significant_impacts <= rocked.rock_impacts).all()
    assert rocked.rock_impacts.notna().all()
    rest = df[(df["mode"] == "rest") & df.rock_peak_ratio.notna()]
    assert (rest.rock_significant_impacts == 0).all()
    for t in ResultFile(rocking).tasks():
        for c in t.contents:
            if c.content == "cabinet":
                rocks = np.array([m in ("rock", "slide-rock") for m in c.modes])
                assert (c.rock_significant_impacts[rocks] >= 0).all()
    for r in design_tables(rocking)["rocking"]:
        sel = df[(df.building == r["building"]) & (df.content == r["content"])
                 & (df.mu_s == r["mu_s"])]  # fmt: skip
        expected = sel.rock_significant_impacts.dropna()
        if len(expected):
            assert r["significant_impacts_median"] == np.median(expected)
        else:
            assert math.isnan(r["significant_impacts_median"])
