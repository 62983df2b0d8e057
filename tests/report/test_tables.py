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
        assert row["n_records"] == 3
        assert row["n_stats"] == int(np.isfinite(peak).sum())
        assert row["n_slid"] == sum(p > 0 for p in peak if np.isfinite(p))
        assert row["n_rocked"] == sum(m == "rock" for m in modes)
        for prefix, values in (
            ("peak_slide", peak),
            ("residual_slide", resid),
            ("peak_abs_accel", acc),
            ("peak_abs_accel_g", np.array(acc) / G),
        ):
            for name, expected in zip(("mean", "median", "p84"), _stats(values), strict=True):
                assert _close(row[f"{prefix}_{name}"], float(expected)), (prefix, name, row)


def test_rocking_is_counted_and_left_out(tables):
    rows = {(r["record_set"], r["building"], r["mu_k"]): r for r in tables["slides"]}
    some = rows[("broad-band", "fixed", 0.1)]
    assert (some["n_records"], some["n_stats"], some["n_rocked"]) == (3, 2, 1)
    assert math.isfinite(some["peak_slide_median"])
    every = rows[("pulse-like", "fixed", 0.05)]
    assert (every["n_stats"], every["n_rocked"], every["n_slid"]) == (0, 3, 0)
    assert math.isnan(every["peak_slide_median"]) and math.isnan(every["peak_abs_accel_p84"])


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
        if b["peak_slide_median"] > 0 and a["n_stats"] and b["n_stats"]:
            assert r["peak_slide_median_ratio"] == pytest.approx(
                a["peak_slide_median"] / b["peak_slide_median"], rel=1e-12
            )
            assert r["peak_slide_p84_ratio"] == pytest.approx(
                a["peak_slide_p84"] / b["peak_slide_p84"], rel=1e-12
            )
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
    assert header.count("|") == len(COLUMNS["slides"]) + 1
    body = [ln for ln in lines[start + 2 : start + 2 + len(tables["slides"])]]
    assert all(ln.count("|") == len(COLUMNS["slides"]) + 1 for ln in body)
    assert "| rocks |" in text  # every record rocks
    assert "∞" in text and "—" in text  # x/0 and 0/0 ratios


def test_csv_sections_and_directory(tmp_path, tables):
    text = format_csv_sections(tables)
    parts = text.split("# table: ")[1:]
    assert [p.split("\n", 1)[0] for p in parts] == list(TABLE_NAMES)
    paths = write_csv(tables, tmp_path / "csv")
    assert [p.name for p in paths] == [f"{n}.csv" for n in TABLE_NAMES]
    for name, path in zip(TABLE_NAMES, paths, strict=True):
        rows = list(csv.DictReader(io.StringIO(path.read_text())))
        assert list(rows[0]) == [c.name for c in COLUMNS[name]]
        assert len(rows) == len(tables[name])
        assert path.read_text() == format_csv(name, tables[name])
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
    assert first["peak_slide_median"] is None and first["n_rocked"] == 3
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
