"""Design tables: statistics against NumPy computed here, ratios, conventions, formats."""

from __future__ import annotations

import csv
import io
import json
import math

import numpy as np
import pytest

from floorslide.errors import ModelError, ResultFileError, SceneError
from floorslide.report import COLUMNS, TABLE_NAMES, design_tables
from floorslide.report.tables import (
    format_csv,
    format_csv_sections,
    format_json,
    format_markdown,
    interpolate_spectrum,
    load_study,
    ratio,
    write_csv,
)
from floorslide.run.store import ResultWriter
from tests.report.conftest import BUILDINGS, DAMPING, MU, PERIODS, SETS, G, write_study

SCENE_SETS = ["pulse-like", "broad-band"]  # the scene's order, not alphabetical
BUILDING_IDS = list(BUILDINGS)


def _stats(x):
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    if x.size == 0:
        return (math.nan,) * 3
    return (np.mean(x), np.median(x), np.percentile(x, 84))


def _ranked(values, rock, q):
    """Hyndman & Fan definition 7 written out, rocking records sorted above every value:
    (value, lands on a rocking record)."""
    known = sorted(v for v, r in zip(values, rock, strict=True) if not r)
    n = len(values)
    h = (n - 1) * q / 100
    j = math.floor(h)
    g = h - j
    if j >= len(known) or (g > 0 and j + 1 >= len(known)):
        return math.nan, True
    if g == 0:
        return known[j], False
    return known[j] + g * (known[j + 1] - known[j]), False


def _close(a, b):
    if isinstance(b, float) and math.isnan(b):
        return isinstance(a, float) and math.isnan(a)
    return a == pytest.approx(b, rel=1e-12, abs=0.0)


@pytest.fixture(scope="module")
def tables(study):
    return design_tables(study.path)


def test_slide_statistics_match_numpy(study, tables):
    rows = tables["slides"]
    assert len(rows) == len(SETS) * len(BUILDINGS) * len(MU)
    for row in rows:
        i = int(np.nonzero(MU == row["mu_k"])[0][0])
        truth = [
            study.truth[(row["record_set"], row["building"], r)] for r in SETS[row["record_set"]]
        ]
        peak = [t["peak"][i] for t in truth]
        resid = [abs(t["resid"][i]) for t in truth]
        acc = [t["acc"][i] for t in truth]
        modes = [t["modes"][i] for t in truth]
        rock = [m == "rock" for m in modes]
        assert row["n_records"] == 3
        assert row["n_rock"] == sum(rock) and row["rock_fraction"] == sum(rock) / 3
        assert row["n_slid"] == sum(p > 0 for p in peak if np.isfinite(p))
        assert row["few_records"] is True  # 3 < 8 records
        for prefix, values in (
            ("peak_slide", peak),
            ("residual_slide", resid),
            ("peak_abs_accel", acc),
            ("peak_abs_accel_g", np.array(acc) / G),
        ):
            if not any(rock):
                expected = dict(zip(("mean", "median", "p84"), _stats(values), strict=True))
            else:
                expected = {"mean": math.nan}
                for stat, q in (("median", 50), ("p84", 84)):
                    expected[stat] = _ranked(values, rock, q)[0]
            for name, value in expected.items():
                assert _close(row[f"{prefix}_{name}"], float(value)), (prefix, name, row)
            for name in ("deformation", "top_accel", "top_accel_g"):
                assert math.isnan(row[f"peak_{name}_median"])  # rigid blocks: not applicable


def test_rocking_is_its_own_outcome_never_zero(study, tables):
    """Issue 12 item 4: a rocking object is counted as an outcome ranked above every slide,
    not left out (which took the median over the weakest records)."""
    rows = {(r["record_set"], r["building"], r["mu_k"]): r for r in tables["slides"]}
    some = rows[("broad-band", "fixed", 0.1)]  # bb3 rocks, bb1 and bb2 slide
    assert (some["n_records"], some["n_rock"], some["n_slid"]) == (3, 1, 2)
    outcomes = tuple(some[f"{s}_outcome"] for s in ("mean", "median", "p84"))
    assert outcomes == ("rock", "slide", "rock")
    assert math.isnan(some["peak_slide_mean"]) and math.isnan(some["peak_slide_p84"])
    slid = [study.truth[("broad-band", "fixed", r)]["peak"][1] for r in ("bb1", "bb2")]
    # the middle of the three outcomes [bb1, bb2, rock] is the larger slide — not the median
    # of the two records left after dropping the rocking one
    assert some["peak_slide_median"] == max(slid) != np.median(slid)
    every = rows[("pulse-like", "fixed", 0.05)]
    assert (every["n_rock"], every["n_slid"], every["rock_fraction"]) == (3, 0, 1.0)
    assert {every[f"{s}_outcome"] for s in ("mean", "median", "p84")} == {"rock"}
    assert math.isnan(every["peak_slide_median"]) and math.isnan(every["peak_abs_accel_p84"])
    text = format_markdown(tables)
    line = next(ln for ln in text.splitlines() if ln.startswith("| pulse-like | fixed |"))
    assert line.count("rocks") == 12  # mean, median, p84 of the 4 rigid-block quantities


def test_rock_ranking_edge_cases():
    from floorslide.report.statistics import placement, summarize_outcomes

    # 14 of 18 records rock: the median and p84 are "rock", not the median of the 4 others
    values = [0.0, 0.0, 0.0, 0.01] + [math.nan] * 14
    rock = [False] * 4 + [True] * 14
    got = summarize_outcomes(values, rock)
    assert all(math.isnan(v) for v in got.values())
    assert placement(18, 14).median and placement(18, 14).p84
    # 2 of 18 rock: the median is over all 18 (the 9th/10th of the sorted outcomes)
    known = np.linspace(0.0, 0.16, 16)
    got = summarize_outcomes([*known, math.nan, math.nan], [False] * 16 + [True] * 2)
    padded = np.concatenate([known, [1e9, 1e9]])
    assert got["median"] == np.percentile(padded, 50)
    assert math.isnan(got["mean"]) and math.isnan(got["p84"]) is False
    assert got["p84"] == np.percentile(padded, 84)  # 0.84·17 = 14.28: both neighbours known
    assert placement(18, 3).p84  # 0.84·17 = 14.28 → 15th and 16th; the 16th rocks
    # no rocking: exactly numpy
    x = [0.3, 0.0, 0.1, 0.7, 0.2]
    assert tuple(summarize_outcomes(x, [False] * 5).values()) == tuple(
        float(v) for v in (np.mean(x), np.median(x), np.percentile(x, 84))
    )


def test_percentile_is_numpy_linear():
    from floorslide.report.tables import summarize

    x = [0.0, 0.0, 0.1, 0.4]
    assert summarize(x)[2] == pytest.approx(np.percentile(x, 84, method="linear"))
    assert summarize([0.2])[2] == 0.2
    assert all(math.isnan(v) for v in summarize([math.nan]))


def test_pfa_statistics_match_numpy(study, tables):
    rows = tables["pfa"]
    assert len(rows) == len(SETS) * len(BUILDINGS) * 2
    for row in rows:
        truth = [
            study.truth[(row["record_set"], row["building"], r)] for r in SETS[row["record_set"]]
        ]
        pfa = [t["pfa"][row["floor"]] for t in truth]
        mean, median, p84 = _stats(pfa)
        assert _close(row["pfa_mean"], mean) and _close(row["pfa_median"], median)
        assert _close(row["pfa_p84"], p84) and _close(row["pfa_g_p84"], p84 / G)
        amp = np.median([t["pfa"][row["floor"]] / t["pga"] for t in truth])
        assert _close(row["pfa_pga_median"], amp)


def test_frs_ordinates_report_periods_and_damping(study, tables):
    # [report] periods = [0.1, 0.25, 0.5, 10.0], damping = 0.05; 10 s is outside the grid
    assert tables.periods == (0.1, 0.25, 0.5)
    assert tables.damping == 0.05
    assert any("10 s" in n and "left out" in n for n in tables.notes)
    rows = tables["frs"]
    assert len(rows) == len(SETS) * len(BUILDINGS) * 2 * 3
    logp = np.log(PERIODS)
    for row in rows:
        truth = [
            study.truth[(row["record_set"], row["building"], r)] for r in SETS[row["record_set"]]
        ]
        curves = [t["psa"][1, row["floor"]] for t in truth]  # damping row 1 = 0.05
        j = np.searchsorted(PERIODS, row["period"]) - 1
        w = (np.log(row["period"]) - logp[j]) / (logp[j + 1] - logp[j])
        at = [c[j] + w * (c[j + 1] - c[j]) for c in curves]
        assert row["psa_median"] == pytest.approx(np.median(at), rel=1e-12)
        assert row["psa_p84"] == pytest.approx(np.percentile(at, 84), rel=1e-12)
        assert row["psa_g_median"] == pytest.approx(np.median(at) / G, rel=1e-12)


def test_interpolation_exact_on_grid_nan_outside():
    grid = np.array([0.0, 0.1, 0.2, 0.4])
    values = np.array([1.0, 2.0, 3.0, 5.0])
    out = interpolate_spectrum(grid, values, [0.0, 0.1, np.sqrt(0.02), 0.4, 0.05, 1.0])
    assert out[0] == 1.0 and out[1] == 2.0 and out[3] == 5.0
    assert out[2] == pytest.approx(2.5, rel=1e-12)  # halfway in ln T
    assert math.isnan(out[4]) and math.isnan(out[5])


def test_defaults_without_a_report_table(plain_study):
    t = design_tables(plain_study.path)
    assert t.periods == (0.1, 0.2, 0.3, 0.5, 1.0, 2.0, 3.0)  # standard periods in 0.05-4 s
    assert t.damping == 0.05
    assert [c.spec for c in t.comparisons] == ["isolated:fixed"]  # isolated over superstructure
    assert not any("left out" in n for n in t.notes)
    explicit = design_tables(plain_study.path, periods=[0.05, 4.0, 5.0], damping=0.02)
    assert explicit.periods == (0.05, 4.0) and explicit.damping == 0.02
    row = explicit["frs"][0]
    curves = [
        plain_study.truth[(row["record_set"], row["building"], r)] for r in SETS[row["record_set"]]
    ]
    assert row["psa_median"] == np.median([c["psa"][0, row["floor"]][0] for c in curves])


def test_slide_ratios_and_zero_denominators(tables):
    rows = tables["slide_ratios"]
    assert {r["comparison"] for r in rows} == {"isolated:fixed"}
    assert len(rows) == len(SETS) * 2 * len(MU)
    slides = {(r["record_set"], r["building"], r["mu_k"]): r for r in tables["slides"]}
    for r in rows:
        a = slides[(r["record_set"], r["building_a"], r["mu_k"])]
        b = slides[(r["record_set"], r["building_b"], r["mu_k"])]
        assert r["building_b"] == "fixed"
        assert r["isolation_period_a"] == BUILDINGS[r["building_a"]]["isolation_period"]
        assert _close(r["peak_slide_median_a"], a["peak_slide_median"])
        assert _close(r["peak_slide_median_b"], b["peak_slide_median"])
        assert (r["n_rock_a"], r["n_rock_b"]) == (a["n_rock"], b["n_rock"])
        assert r["median_outcome_b"] == b["median_outcome"] and r["few_records"]
        if b["peak_slide_median"] > 0 and a["median_outcome"] != "rock":
            assert r["peak_slide_median_ratio"] == pytest.approx(
                a["peak_slide_median"] / b["peak_slide_median"], rel=1e-12
            )
            if b["p84_outcome"] != "rock" and a["p84_outcome"] != "rock":
                assert r["peak_slide_p84_ratio"] == pytest.approx(
                    a["peak_slide_p84"] / b["peak_slide_p84"], rel=1e-12
                )
            else:
                assert math.isnan(r["peak_slide_p84_ratio"])
    by = {(r["record_set"], r["building_a"], r["mu_k"]): r for r in rows}
    assert math.isnan(by[("broad-band", "isolated@T=2", 0.2)]["peak_slide_median_ratio"])  # 0/0
    assert by[("pulse-like", "isolated@T=2", 0.2)]["peak_slide_median_ratio"] == math.inf  # x/0
    assert math.isnan(by[("pulse-like", "isolated@T=2.5", 0.2)]["peak_slide_median_ratio"])
    assert math.isnan(by[("pulse-like", "isolated@T=2", 0.05)]["peak_slide_median_ratio"])  # rocks
    pfa = tables["pfa_ratios"]
    assert len(pfa) == len(SETS) * 2 * 2
    p = {(r["record_set"], r["building"], r["floor"]): r for r in tables["pfa"]}
    for r in pfa:
        num = p[(r["record_set"], r["building_a"], r["floor"])]["pfa_median"]
        den = p[(r["record_set"], r["building_b"], r["floor"])]["pfa_median"]
        assert r["pfa_median_ratio"] == pytest.approx(num / den, rel=1e-12)


def test_ratio_conventions():
    assert ratio(1.0, 2.0) == 0.5
    assert math.isnan(ratio(0.0, 0.0))
    assert ratio(0.3, 0.0) == math.inf
    assert math.isnan(ratio(math.nan, 1.0)) and math.isnan(ratio(1.0, math.nan))


def test_compare_by_variant_and_base_ids(study):
    one = design_tables(study.path, compare=["isolated@T=2.5:fixed"])
    assert {(r["building_a"], r["building_b"]) for r in one["slide_ratios"]} == {
        ("isolated@T=2.5", "fixed")
    }
    rev = design_tables(study.path, compare=["fixed:isolated", "isolated@T=2.5:isolated@T=2"])
    pairs = [(r["comparison"], r["building_a"], r["building_b"]) for r in rev["pfa_ratios"]]
    assert dict.fromkeys(pairs) == dict.fromkeys(
        [
            ("fixed:isolated", "fixed", "isolated@T=2"),
            ("fixed:isolated", "fixed", "isolated@T=2.5"),
            ("isolated@T=2.5:isolated@T=2", "isolated@T=2.5", "isolated@T=2"),
        ]
    )
    inf_row = next(
        r
        for r in rev["slide_ratios"]
        if r["record_set"] == "pulse-like"
        and r["building_b"] == "isolated@T=2"
        and r["mu_k"] == 0.2
    )
    assert inf_row["peak_slide_median_ratio"] == 0.0  # 0 / x


@pytest.mark.parametrize(
    "compare, text",
    [(["isolated"], "expected A:B"), (["a:b:c"], "expected A:B"), (["tower:fixed"], "'tower'")],
)
def test_bad_compare_is_a_model_error_naming_the_argument(study, compare, text):
    with pytest.raises(ModelError, match=text) as info:
        design_tables(study.path, compare=compare)
    assert info.value.where == "compare"


def test_bad_report_table_is_a_scene_error(tmp_path, study):
    bad = write_study(tmp_path / "bad.h5", report='\n[report]\ncompare = ["tower:fixed"]\n')
    with pytest.raises(SceneError) as info:
        design_tables(bad.path)
    assert info.value.where == "report.compare[0]"
    bad = write_study(tmp_path / "bad2.h5", report="\n[report]\ndamping = 0.03\n")
    with pytest.raises(SceneError, match=r"0\.02, 0\.05") as info:
        design_tables(bad.path)
    assert info.value.where == "report.damping"
    with pytest.raises(ModelError) as info:
        design_tables(study.path, damping=0.1)
    assert info.value.where == "damping"


def test_order_is_deterministic_and_follows_the_scene(tmp_path, study, tables):
    keys = [(r["record_set"], r["building"], r["floor"], r["mu_k"]) for r in tables["slides"]]
    expected = [(s, b, 1, float(m)) for s in SCENE_SETS for b in BUILDING_IDS for m in MU]
    assert keys == expected
    frs = [(r["record_set"], r["building"], r["floor"], r["period"]) for r in tables["frs"]]
    assert frs == sorted(
        frs, key=lambda k: (SCENE_SETS.index(k[0]), BUILDING_IDS.index(k[1]), k[2], k[3])
    )
    ratios = [(r["record_set"], r["building_a"]) for r in tables["slide_ratios"]]
    assert ratios == [(s, b) for s in SCENE_SETS for b in BUILDING_IDS[1:] for _ in MU]
    other = write_study(tmp_path / "shuffled.h5", order_seed=7)  # tasks in another file order
    again = design_tables(other.path)
    for name in TABLE_NAMES:
        assert json.dumps(again[name], default=str) == json.dumps(tables[name], default=str)
    strip = lambda text: text.split("\n", 3)[3]  # noqa: E731 - drop the source line
    assert strip(format_markdown(again)) == strip(format_markdown(tables))


def test_markdown_structure(tables):
    text = format_markdown(tables)
    assert text.startswith("# Design tables: synthetic study")
    assert "numpy.percentile, method 'linear'" in text
    sections = [line for line in text.splitlines() if line.startswith("## ")]
    assert len(sections) == len(TABLE_NAMES)
    lines = text.splitlines()
    start = lines.index(sections[0]) + 2
    header = lines[start]
    assert "peak_slide_median (m)" in header and "peak_abs_accel_p84 (m/s²)" in header
    assert "peak_deformation" not in header  # no oscillator in this study
    shown = len(COLUMNS["slides"]) - 9  # without the 9 oscillator columns
    assert header.count("|") == shown + 1
    body = [ln for ln in lines[start + 2 : start + 2 + len(tables["slides"])]]
    assert all(ln.count("|") == shown + 1 for ln in body)
    assert "| rocks |" in text  # every record rocks
    assert "†" in text  # p84 from 3 < 8 records
    assert "∞" in text and "—" in text  # x/0 and 0/0 ratios


def test_csv_sections_and_directory(tmp_path, tables):
    text = format_csv_sections(tables)
    parts = text.split("# table: ")[1:]
    assert [p.split("\n", 1)[0] for p in parts] == list(TABLE_NAMES)
    paths = write_csv(tables, tmp_path / "csv")
    assert [p.name for p in paths] == [f"{n}.csv" for n in TABLE_NAMES]
    for name, path in zip(TABLE_NAMES, paths, strict=True):
        # an empty table may say why in a '# …' line above its header (the isolators table of
        # a study without nonlinear isolation): comment lines are skipped as pandas does
        lines = [ln for ln in path.read_text().splitlines() if not ln.startswith("#")]
        header, *rows = list(csv.reader(lines))
        assert header == [c.name for c in COLUMNS[name]]
        assert len(rows) == len(tables[name])
        assert path.read_text() == format_csv(name, tables[name])
    assert (
        (tmp_path / "csv" / "isolators.csv")
        .read_text()
        .startswith(
            "# no building on nonlinear isolation in this study\nrecord_set,building,isolator,"
        )
    )
    slides = list(csv.DictReader(io.StringIO(format_csv("slides", tables["slides"]))))
    assert float(slides[1]["peak_slide_median"]) == tables["slides"][1]["peak_slide_median"]
    assert slides[0]["peak_slide_median"] == ""  # NaN (every record rocks)
    ratios = list(csv.DictReader(io.StringIO(format_csv("slide_ratios", tables["slide_ratios"]))))
    assert {r["peak_slide_median_ratio"] for r in ratios} >= {"", "inf"}


def test_json_is_strict_and_complete(tables):
    data = json.loads(format_json(tables))
    assert set(data["tables"]) == set(TABLE_NAMES)
    assert data["percentile"] == 84.0 and data["damping"] == 0.05
    assert data["periods"] == [0.1, 0.25, 0.5]
    for name in TABLE_NAMES:
        assert [c["name"] for c in data["columns"][name]] == [c.name for c in COLUMNS[name]]
        assert len(data["tables"][name]) == len(tables[name])
    units = {c["name"]: c["units"] for c in data["columns"]["slides"]}
    assert units["peak_slide_p84"] == "m" and units["peak_abs_accel_g_mean"] == "g"
    first = data["tables"]["slides"][0]
    assert first["peak_slide_median"] is None and first["n_rock"] == 3
    assert first["median_outcome"] == "rock" and data["complete"] is True
    assert data["status"] == "" and data["tasks_done"] == data["tasks_planned"] == 18
    assert None in {r["peak_slide_median_ratio"] for r in data["tables"]["slide_ratios"]}


def test_result_file_problems(tmp_path):
    with pytest.raises(ResultFileError, match="no such result file"):
        design_tables(tmp_path / "missing.h5")
    junk = tmp_path / "junk.h5"
    junk.write_bytes(b"not an hdf5 file at all")
    with pytest.raises(ResultFileError, match="corrupt or unreadable"):
        design_tables(junk)
    import h5py

    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = np.arange(3)
    with pytest.raises(ResultFileError, match="not a floorslide result file"):
        design_tables(other)
    empty = tmp_path / "empty.h5"
    ResultWriter(empty, "[scene]\n", "s.toml", "empty", {}).finish()
    with pytest.raises(ResultFileError, match="no finished task"):
        load_study(empty)


def test_stored_damping_rows_are_kept_apart(study):
    t = design_tables(study.path, damping=0.02, periods=[PERIODS[3]])
    row = t["frs"][0]
    truth = [study.truth[(row["record_set"], row["building"], r)] for r in SETS[row["record_set"]]]
    assert row["psa_median"] == np.median([c["psa"][0, row["floor"]][3] for c in truth])
    assert DAMPING[0] == row["damping"]


# --- issue 12 --------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def rich(rich_study):
    return design_tables(rich_study.path)


def test_oscillator_results_are_tabulated(rich_study, rich):
    """Item 3: spring deformation and top-mass acceleration of 2-DOF equipment, with units and
    statistics; peak_abs_accel is the sliding base's."""
    rows = [r for r in rich["slides"] if r["content"] == "rack"]
    assert len(rows) == len(SETS) * len(BUILDINGS) * 2
    for row in rows:
        i = [0.1, 0.3].index(row["mu_k"])
        racks = [
            rich_study.truth[(row["record_set"], row["building"], r)]["rack"]
            for r in SETS[row["record_set"]]
        ]
        deform = [c.peak_deformation[i] for c in racks]
        top = [c.peak_top_accel[i] for c in racks]
        base = [c.peak_abs_accel[i] for c in racks]
        rock = [m == "rock" for m in (c.modes[i] for c in racks)]
        assert row["model"] == "oscillator" and row["n_rock"] == sum(rock)
        if not any(rock):
            assert _close(row["peak_deformation_median"], float(np.median(deform)))
            assert _close(row["peak_deformation_p84"], float(np.percentile(deform, 84)))
            assert _close(row["peak_top_accel_mean"], float(np.mean(top)))
            assert _close(row["peak_top_accel_g_median"], float(np.median(top)) / G)
            assert _close(row["peak_abs_accel_median"], float(np.median(base)))
        else:  # pulse-like, fixed, mu 0.3: one of three rocks
            assert _close(row["peak_deformation_median"], _ranked(deform, rock, 50)[0])
            assert math.isnan(row["peak_top_accel_p84"]) and row["p84_outcome"] == "rock"
    units = {c.name: c.units for c in COLUMNS["slides"]}
    assert units["peak_deformation_p84"] == "m" and units["peak_top_accel_median"] == "m/s**2"
    assert units["peak_top_accel_g_mean"] == "g"
    cabinet = next(r for r in rich["slides"] if r["content"] == "cabinet")
    assert math.isnan(cabinet["peak_deformation_median"])  # rigid: not applicable
    text = format_markdown(rich)
    assert "peak_deformation_median (m)" in text and "peak_top_accel_g_p84 (g)" in text
    data = json.loads(format_json(rich))
    first = next(r for r in data["tables"]["slides"] if r["content"] == "rack")
    assert first["peak_deformation_median"] == pytest.approx(
        next(r for r in rows if r["building"] == first["building"] and r["mu_k"] == 0.1)[
            "peak_deformation_median"
        ]
    )


def test_broadened_and_unbroadened_frs(rich_study, rich):
    """Item 5: both spectra, each labelled; the notes say which is which."""
    rows = rich["frs"]
    assert rows and all(r["broadening"] == 0.15 for r in rows)
    for row in rows[:6]:
        truth = [
            rich_study.truth[(row["record_set"], row["building"], r)]
            for r in SETS[row["record_set"]]
        ]
        j = np.searchsorted(PERIODS, row["period"]) - 1
        logp = np.log(PERIODS)
        w = (np.log(row["period"]) - logp[j]) / (logp[j + 1] - logp[j])
        at = np.array(
            [
                c["psa"][1, row["floor"]][j] * (1 - w) + c["psa"][1, row["floor"]][j + 1] * w
                for c in truth
            ]
        )
        assert row["psa_median"] == pytest.approx(np.median(at), rel=1e-12)
        assert row["psa_broadened_median"] == pytest.approx(1.25 * np.median(at), rel=1e-12)
        assert row["psa_broadened_g_p84"] == pytest.approx(1.25 * np.percentile(at, 84) / G)
    assert any("unbroadened" in n and "±15 %" in n for n in rich.notes)
    text = format_markdown(rich)
    assert "psa_broadened_median (m/s²)" in text and "| broadening |" in text


def test_no_broadening_is_said(tables):
    assert all(r["broadening"] == 0.0 for r in tables["frs"])
    assert all(math.isnan(r["psa_broadened_median"]) for r in tables["frs"])
    assert any("no peak broadening" in n for n in tables.notes)
    assert "psa_broadened_median" not in format_markdown(tables)  # no such column shown


def test_few_records_caution(tables):
    """Item 6: statistics from fewer than MIN_RECORDS records carry a caution."""
    from floorslide.report import MIN_RECORDS

    assert MIN_RECORDS == 8
    for name in ("slides", "pfa", "frs", "slide_ratios", "pfa_ratios"):
        assert all(r["few_records"] is True for r in tables[name]), name
    assert any(n.startswith("few_records: fewer than 8 records") for n in tables.notes)
    slides = list(csv.DictReader(io.StringIO(format_csv("slides", tables["slides"]))))
    assert {r["few_records"] for r in slides} == {"True"}


def test_placement_threshold_matches_the_documented_reason():
    """MIN_RECORDS = 8: the first n for which p84 does not interpolate into the largest value."""
    from floorslide.report import MIN_RECORDS

    for n in range(2, 20):
        h = 0.84 * (n - 1)
        uses_largest = math.ceil(h) >= n - 1
        assert uses_largest == (n < MIN_RECORDS), n


def test_incomplete_file_is_refused_then_labelled(partial_study):
    """Item 6: 14 of 18 tasks done — refused by default, labelled INCOMPLETE in every format
    when allowed."""
    from floorslide.errors import IncompleteResultError

    with pytest.raises(IncompleteResultError, match="INCOMPLETE: 14 of 18 tasks done") as info:
        design_tables(partial_study.path)
    assert info.value.exit_code == 4 and "--resume" in str(info.value)
    t = design_tables(partial_study.path, allow_incomplete=True)
    assert not t.complete and t.status.startswith("INCOMPLETE: 14 of 18 tasks done")
    md = format_markdown(t)
    assert md.splitlines()[0].endswith("— INCOMPLETE") and "**INCOMPLETE: 14 of 18" in md
    assert md.count("(INCOMPLETE)") == len(TABLE_NAMES)
    for name in TABLE_NAMES:
        text = format_csv(name, t[name], t.status)
        assert text.startswith("# INCOMPLETE: 14 of 18 tasks done")
    sections = format_csv_sections(t)
    assert sections.count("# INCOMPLETE: 14 of 18") == len(TABLE_NAMES)
    data = json.loads(format_json(t))
    assert data["complete"] is False and data["status"].startswith("INCOMPLETE")
    assert (data["tasks_done"], data["tasks_planned"]) == (14, 18)
    frames = t.to_pandas()
    assert frames["slides"].attrs["status"].startswith("INCOMPLETE")


def test_tables_as_dataframes(tables):
    """Item 10: DataFrames with the tables' columns, values and units."""
    import pandas as pd

    frames = tables.to_pandas()
    assert list(frames) == list(TABLE_NAMES)
    for name in TABLE_NAMES:
        df = frames[name]
        assert isinstance(df, pd.DataFrame) and len(df) == len(tables[name])
        assert list(df.columns) == [c.name for c in COLUMNS[name]]
        assert df.attrs["units"] == {c.name: c.units for c in COLUMNS[name]}
    df = tables.to_pandas("slides")
    assert df["peak_slide_median"].iloc[1] == tables["slides"][1]["peak_slide_median"]
    assert df["n_rock"].dtype.kind == "i" and df.attrs["status"] == ""
    with pytest.raises(KeyError, match="no table 'nope'"):
        tables.to_pandas("nope")


def test_markdown_shows_scene_and_catalog_strings_as_text(tables):
    """Scene and catalog strings went into the Markdown raw: '<script>' ran in a viewer that
    renders HTML, '|' and a newline broke the table, '[x](url)' became a link."""
    import dataclasses

    evil = "<script>alert(1)</script>|x\ny [a](http://e) `c` \\"
    rows = [dict(r) for r in tables["slides"]]
    rows[0]["record_set"] = evil
    hostile = dataclasses.replace(
        tables,
        scene_name=evil,
        notes=(*tables.notes, f"note {evil}"),
        tables={**tables.tables, "slides": rows},
    )
    text = format_markdown(hostile, ["slides"])
    assert "<" not in text and ">" not in text.replace("&gt;", "")
    shown = "&lt;script&gt;alert(1)&lt;/script&gt;\\|x\\\\ny \\[a\\](http://e) \\`c\\` \\\\"
    assert text.startswith(f"# Design tables: {shown}\n")
    assert f"- note {shown}\n" in text
    lines = text.splitlines()
    header = next(ln for ln in lines if ln.startswith("| record_set"))
    row = next(ln for ln in lines if shown in ln and ln.startswith("| "))
    # the row has as many cells as the header: no '|' of the string splits it
    cells = lambda line: len(line.replace("\\|", "").split("|"))  # noqa: E731
    assert cells(row) == cells(header)
