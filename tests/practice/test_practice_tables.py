"""The design-practice tables (docs/design.md §10e) of a real run with stripes: every number
recomputed here from the per-record table (pandas) and the practice functions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floorslide.practice.code import asce7_floor_amplification
from floorslide.practice.fragility import fit_fragility
from floorslide.report import COLUMNS, design_tables, format_csv, format_markdown
from floorslide.report.records import record_table
from floorslide.report.study import load_study
from floorslide.run.execute import execute
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene
from tests.conftest import ROOT

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()
LEVELS = (0.5, 1.0, 2.0)

SCENE = f"""
[scene]
name = "practice"

[[records]]
set = "design"
catalog = "{CATALOG}"
where = {{ station_id = ["ELC-180", "TAF-021", "EMO-270", "EDA-270"] }}

[records.scale]
target = {{ sds = 1.0, sd1 = 0.6, tl = 8.0 }}
periods = [0.1, 2.0]
levels = {list(LEVELS)}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 2
period = 0.3
damping = 0.05

[[buildings]]
id = "iso"
kind = "isolated"
superstructure = "fixed"
period = 2.5
damping = 0.1

[[contents]]
id = "cab"
floors = "roof"
mu = [0.1, 0.3]
allowable = [0.01, 0.05]
width = 0.6
height = 1.8
"""


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    d = tmp_path_factory.mktemp("practice")
    (d / "scene.toml").write_text(SCENE, encoding="utf-8")
    out = d / "out.h5"
    with pytest.warns(UserWarning):  # some factors at level 2 lie beyond 4
        p = plan(load_scene(d / "scene.toml"))
    execute(p, str(out), workers=1)
    return load_study(out)


@pytest.fixture(scope="module")
def tables(study):
    return design_tables(study)


def test_scaling_rows_are_the_factors_the_tasks_ran_with(study, tables):
    rows = tables["scaling"]
    assert len(rows) == 4 * len(LEVELS)
    ran = {(t.meta["record_set"], t.meta["record"]): float(t.meta["scale"]) for t in study.tasks}
    for r in rows:
        assert r["factor"] == ran[(r["record_set"], r["record"])]
        assert r["factor"] == pytest.approx(r["level"] * r["fit_factor"], rel=1e-15)
        assert r["outside_limits"] == (not 0.25 <= r["factor"] <= 4.0)
    suite = tables["suite"]
    assert [s["record_set"] for s in suite] == [f"design@{x:g}x" for x in LEVELS]
    assert len({round(s["mean_over_target_min"], 12) for s in suite}) == 1  # level-invariant


def test_code_table_against_numpy_and_the_formula(tables):
    df = record_table(load_study(tables.source))
    for row in tables["code"]:
        sel = df[(df.record_set == row["record_set"]) & (df.building == row["building"])]
        sel = sel.drop_duplicates("record")
        amp = (sel.pfa / sel.pga).to_numpy()
        assert row["pfa_pga_median"] == pytest.approx(np.median(amp), rel=1e-12)
        assert row["pfa_pga_p84"] == pytest.approx(np.percentile(amp, 84), rel=1e-12)
        if row["building_kind"] == "fixed":
            assert row["z_over_h"] == 1.0 and row["period_a"] == pytest.approx(0.3)
            # a1 = min(1/0.3, 2.5) = 2.5, a2 = 1 − (0.4/0.3)² < 0 → 0: H_f = 3.5
            assert row["h_f"] == pytest.approx(3.5)
            assert row["h_f"] == float(asce7_floor_amplification(1.0, 0.3))
            assert row["median_over_h_f"] == pytest.approx(row["pfa_pga_median"] / 3.5)
            assert row["note"] == ""
        else:
            assert math.isnan(row["h_f"]) and "§17" in row["note"]


def test_exceedance_counts_from_the_per_record_table(study, tables):
    df = record_table(study)
    rows = tables["exceedance"]
    states = {r["state"] for r in rows}
    assert states == {"slide > 0.01 m", "slide > 0.05 m", "overturn"}
    for r in rows:
        sel = df[
            (df.record_set == r["record_set"])
            & (df.building == r["building"])
            & (df.content == r["content"])
            & (df.mu_k == r["mu_k"])
        ]
        assert r["n_records"] == len(sel) == 4
        if r["state"] == "overturn":
            k = int((sel.overturned == 1.0).sum())
            assert r["n_exceed"] == k and r["fraction"] == k / 4
            continue
        rock = sel.outcome == "rock"
        k = int((sel.peak_slide[~rock] > r["allowable"]).sum())
        assert r["n_rock"] == int(rock.sum())
        assert r["n_exceed"] == k
        n = 4 - int(rock.sum())
        assert (math.isnan(r["fraction"]) and n == 0) or r["fraction"] == k / n
    # the cases that matter occur: something slides past an allowable, something rocks
    assert any(r["n_exceed"] > 0 for r in rows if r["state"].startswith("slide"))


def test_exceedance_fraction_states_its_denominator(tables):
    """The fraction of a slide state is over the records that did not rock: that count is a
    column, beside the fraction, so that 1/3 is not read as 1 of the 4 records."""
    names = [c.name for c in COLUMNS["exceedance"]]
    assert names.index("n_records_exceedance") == names.index("fraction") - 1
    rows = tables["exceedance"]
    for r in rows:
        over = r["state"] == "overturn"
        assert r["n_records_exceedance"] == r["n_records"] - (0 if over else r["n_rock"])
        if r["n_records_exceedance"]:
            assert r["fraction"] == r["n_exceed"] / r["n_records_exceedance"]


def test_fragility_rows_fit_the_stripes_counts(tables):
    rows = tables["fragility"]
    ex = {(r["record_set"], r["building"], r["mu_k"], r["state"]): r for r in tables["exceedance"]}
    assert rows and all(r["record_set"] == "design" for r in rows)
    fitted = 0
    for r in rows:
        assert r["levels"] == LEVELS
        for lvl, n, k in zip(r["levels"], r["n_records"], r["n_exceed"], strict=True):
            e = ex[(f"design@{lvl:g}x", r["building"], r["mu_k"], r["state"])]
            assert k == e["n_exceed"]
            assert n == e["n_records"] - e["n_rock"]
        if math.isfinite(r["median"]):
            fitted += 1
            use = [(x, n, k) for x, n, k in zip(r["levels"], r["n_records"], r["n_exceed"],
                                                strict=True) if n > 0]  # fmt: skip
            fit = fit_fragility(*zip(*use, strict=True))
            assert (r["median"], r["beta"]) == (fit.median, fit.beta)
        else:
            assert r["note"]  # a NaN fit always says why
    assert fitted > 0


def test_outputs_carry_the_new_tables(tables):
    md = format_markdown(tables)
    for title in ("Suite check (ASCE 7-22 §16.2.3)", "Code comparison", "Fragility over stripes"):
        assert title in md
    csv = format_csv("fragility", tables["fragility"])
    assert "0.5; 1.0; 2.0" in csv  # the stripes' levels in one cell


def test_report_holds_the_practice_section(study, tmp_path):
    from floorslide.report.html import write_report

    text = write_report(study, tmp_path / "r.html", tables=design_tables(study), figures=[])
    text = text.read_text(encoding="utf-8")
    assert "Design practice: scaling, exceedance, fragility" in text
    assert text.index('id="table-code"') < text.index('id="table-scaling"')  # with the PFA
    for name in ("scaling", "suite", "code", "exceedance", "fragility"):
        assert f'id="table-{name}"' in text
    assert 'id="empty-plane"' in text  # an empty table says why
    # provenance: every record with its catalog metadata
    assert 'id="table-provenance"' in text
    assert {(r["record"], r["station_id"]) for r in study.provenance} == {
        ("ImperialValley_1940_ELC-180", "ELC-180"),
        ("KernCounty_1952_TAF-021", "TAF-021"),
        ("ImperialValley_1979_EMO-270", "EMO-270"),
        ("ImperialValley_1979_EDA-270", "EDA-270"),
    }
    assert "Imperial Valley 1940" in text


def test_bundled_design_scene_plans_its_stripes():
    sc = load_scene(ROOT / "data" / "scenes" / "design.toml")
    with pytest.warns(UserWarning, match="lie outside 0.25–4"):
        p = plan(sc, evaluate=False)
    assert [e["set"] for e in p.scaling] == [f"design@{x:g}x" for x in (0.25, 0.5, 1.0, 1.5)]
    assert all(e["suite"]["passes"] for e in p.scaling)  # match_suite
    assert len(p.tasks) == 18 * 4 * 2


def test_a_real_report_with_figures_renders(study, tmp_path):
    """The report of a real run (every figure embedded, ~MBs) renders in headless Chromium."""
    from floorslide.report.html import write_report
    from tests.report.test_html_report import rendered_ink

    path = write_report(study, tmp_path / "report.html", workers=1)
    assert path.stat().st_size > 200_000  # the figures are in it
    inked = rendered_ink(path, tmp_path)
    assert inked > 0.01, f"the rendered report looks blank ({inked:.4f} of pixels inked)"


def test_code_h_f_uses_the_storey_heights(study, monkeypatch):
    """With storey_heights = [4, 2] m floor 1 is at z/h = 4/6, not 1/2, and H_f follows
    (ASCE 7-22 Eq. 13.3-4 at that height); the roof stays at 1."""
    import dataclasses

    from floorslide.practice.code import relative_heights
    from floorslide.report import practice
    from floorslide.report.practice import code_table

    profiles = practice.pfa_profiles

    def every_floor(st, rs):  # the study stores the roof only: floor 1 gets its values too
        return {b: {0: fl[2], 1: fl[2], 2: fl[2]} for b, fl in profiles(st, rs).items()}

    monkeypatch.setattr(practice, "pfa_profiles", every_floor)

    scene = dict(study.scene)
    scene["buildings"] = [dict(b) for b in scene["buildings"]]
    scene["buildings"][0]["storey_heights"] = [4.0, 2.0]
    tall = dataclasses.replace(study, scene=scene)
    equal = {(r["building"], r["floor"]): r for r in code_table(study)}
    rows = {(r["building"], r["floor"]): r for r in code_table(tall)}
    assert relative_heights(2, [4.0, 2.0]).tolist() == [0.0, 4 / 6, 1.0]
    assert rows[("fixed", 2)]["z_over_h"] == 1.0
    floors = [f for (b, f) in rows if b == "fixed"]
    for f in floors:
        z = relative_heights(2, [4.0, 2.0])[f]
        assert rows[("fixed", f)]["z_over_h"] == z
        assert rows[("fixed", f)]["h_f"] == float(asce7_floor_amplification(z, 0.3))
    assert floors == [0, 1, 2] and equal[("fixed", 1)]["z_over_h"] == 0.5
    assert rows[("fixed", 1)]["z_over_h"] == 4 / 6
    iso = [r for (b, f), r in rows.items() if b == "iso"]
    assert all(r["z_over_h"] == relative_heights(2, [4.0, 2.0])[r["floor"]] for r in iso)
