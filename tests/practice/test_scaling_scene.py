"""Target-spectrum scaling from the scene (docs/design.md §10e): the scene keys, their bad-input
errors with key paths, and the planner's factors checked against spectra of the scaled records
computed afresh (exact, and an independent approximate method)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floorslide.constants import G
from floorslide.errors import SceneError
from floorslide.practice.target import SUITE_FRACTION, TargetSpectrum
from floorslide.scene.planner import plan
from floorslide.scene.schema import parse_scene
from floorslide.spectra import response_spectrum
from tests.conftest import ROOT

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()
RECORDS = (ROOT / "data" / "records" / "slammer").as_posix()


def _scene(scale: str, *, where: str = '["ELC-180", "TAF-021", "EMO-270"]', extra: str = "") -> str:
    return f"""
[scene]
name = "scaling"

[[records]]
set = "s"
catalog = "{CATALOG}"
where = {{ station_id = {where} }}
scale = {scale}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.2
damping = 0.02

[[contents]]
id = "cab"
mu = [0.2]
{extra}
"""


TWO_POINT = "{ sds = 1.0, sd1 = 0.6, tl = 8.0 }"


def _problems(text: str, tmp_path) -> str:
    with pytest.raises(SceneError) as err:
        parse_scene(text, tmp_path / "scene.toml")
    return str(err.value)


def test_range_scaling_fits_the_target_in_the_log_mean(tmp_path):
    sc = parse_scene(_scene(f"{{ target = {TWO_POINT}, periods = [0.1, 2.0] }}"), tmp_path / "a")
    p = plan(sc, evaluate=False)
    spec = sc.records[0].scale
    grid = spec.grid()
    assert len(p.records) == 3
    entry = p.scaling[0]
    assert entry["method"] == "range" and entry["set"] == "s"
    target = TargetSpectrum.two_point(1.0, 0.6, 8.0)(grid)
    for r in p.records:
        # the scaled record's spectrum, computed afresh, fits the target in the mean of logs
        psa = response_spectrum(r.acc, r.dt, grid, 0.05).psa[0] / G
        resid = np.log(psa / target)
        assert abs(resid.mean()) < 1e-12
        stored = next(x for x in entry["records"] if x["record"] == r.record)
        assert stored["factor"] == pytest.approx(r.scale, rel=1e-15)
        assert stored["misfit"] == pytest.approx(np.sqrt(np.mean(resid**2)), rel=1e-10)
        # an independent method (Newmark average acceleration on the samples) agrees to its
        # own accuracy: the factor is right, not just self-consistent
        approx = response_spectrum(r.acc / r.scale, r.dt, grid, 0.05, method="newmark").psa[0]
        f_ref = math.exp(np.mean(np.log(target * G / approx)))
        assert r.scale == pytest.approx(f_ref, rel=2e-2)
    # the suite check, recomputed from the scaled records
    mean = np.mean(
        [response_spectrum(r.acc, r.dt, grid, 0.05).psa[0] / G for r in p.records], axis=0
    )
    ratio = mean / target
    assert entry["suite"]["min_ratio"] == pytest.approx(ratio.min(), rel=1e-12)
    assert entry["suite"]["at"] == pytest.approx(grid[np.argmin(ratio)])
    assert entry["suite"]["passes"] == bool(ratio.min() >= SUITE_FRACTION)


def test_period_scaling_matches_the_target_at_the_period(tmp_path):
    sc = parse_scene(_scene(f"{{ target = {TWO_POINT}, period = 1.0 }}"), tmp_path / "a")
    assert sc.records[0].scale.period_range == pytest.approx((0.2, 2.0))
    p = plan(sc, evaluate=False)
    for r in p.records:
        psa = response_spectrum(r.acc, r.dt, [1.0], 0.05).psa[0, 0] / G
        assert psa == pytest.approx(0.6, rel=1e-12)  # S_D1 / T at T = 1 s


def test_levels_make_stripes_named_and_scaled(tmp_path):
    sc = parse_scene(
        _scene(f"{{ target = {TWO_POINT}, periods = [0.1, 2.0], levels = [2.0, 0.5] }}"),
        tmp_path / "a",
    )
    p = plan(sc, evaluate=False)
    sets = sorted({r.set for r in p.records})
    assert sets == ["s@0.5x", "s@2x"]
    by = {(r.set, r.record): r.scale for r in p.records}
    for rec in {r.record for r in p.records}:
        assert by[("s@2x", rec)] == pytest.approx(4 * by[("s@0.5x", rec)], rel=1e-15)
    assert {e["level"] for e in p.scaling} == {0.5, 2.0}
    assert "3 × 2 scalings = 6 records" in p.describe()


def test_factors_outside_the_limits_warn(tmp_path):
    sc = parse_scene(
        _scene(f"{{ target = {TWO_POINT}, periods = [0.1, 2.0], limits = [0.9, 1.1] }}"),
        tmp_path / "a",
    )
    with pytest.warns(UserWarning, match=r"set 's': \d of 3 scale factors lie outside 0.9–1.1"):
        p = plan(sc, evaluate=False)
    flags = [r["outside_limits"] for r in p.scaling[0]["records"]]
    assert flags == [not (0.9 <= r["factor"] <= 1.1) for r in p.scaling[0]["records"]]


def test_csv_target(tmp_path):
    csv = tmp_path / "target.csv"
    csv.write_text("T_s,Sa_g\n0.05,0.5\n0.2,1.0\n1.0,0.6\n4.0,0.15\n", encoding="utf-8")
    sc = parse_scene(
        _scene('{ target = "target.csv", periods = [0.1, 3.0] }'), tmp_path / "scene.toml"
    )
    t = sc.records[0].scale.target
    assert t(np.array([0.2, 1.0])) == pytest.approx([1.0, 0.6])
    # log-log interpolation: S_a(0.5) = 1.0·(0.5/0.2)^(ln 0.6/ln 5)
    assert float(t(np.array([0.5]))[0]) == pytest.approx(2.5 ** (math.log(0.6) / math.log(5)))


@pytest.mark.parametrize(
    ("csv", "scale", "expect"),
    [
        (
            "0.1,0.5\n0.3,1.0\n0.2,0.8\n",
            '{ target = "t.csv", periods = [0.1, 0.2] }',
            "records[0].scale.target: t.csv line 3: periods must increase, "
            "got T = 0.2 s after 0.3 s",
        ),
        (
            "0.1,0.5\n0.3,-1.0\n",
            '{ target = "t.csv", periods = [0.1, 0.2] }',
            "records[0].scale.target: t.csv line 2: S_a must be > 0 g, got -1 (negative)",
        ),
        (
            "0.1,0.5\n0.3,1.0\n1.0,0.5\n",
            '{ target = "t.csv", periods = [0.05, 2.0] }',
            "records[0].scale.periods: the range 0.05–2 s reaches outside the target's 0.1–1 s",
        ),
    ],
)
def test_bad_target_csv(tmp_path, csv, scale, expect):
    (tmp_path / "t.csv").write_text(csv, encoding="utf-8")
    text = _problems(_scene(scale), tmp_path)
    assert expect in text


TARGET_ROWS = "T_s,Sa_g\n0.05,0.5\n0.2,1.0\n1.0,0.6\n4.0,0.15\n"


@pytest.mark.parametrize(
    ("content", "expect"),
    [
        # float('0_05') is 5.0: the row read as T = 5 s
        (
            b"T_s,Sa_g\n0.01,0.5\n0_05,1.0\n1.0,0.6\n",
            "t.csv line 3: '0_05' is not a number (underscores are not digit separators)",
        ),
        (TARGET_ROWS.encode("utf-16"), "t.csv: UTF-16 text; a target spectrum is a UTF-8 CSV"),
        (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", "t.csv: binary data, not text"),
        (b"T,Sa\n0.1,0.5\n0.2,1.0 # S\xe4ule\n", "t.csv line 3: not UTF-8 text"),
        # decimal commas: '0,05;1,2' read as T = 0, S_a = 5
        (b"0,05;1,2\n0,2;1,0\n", "t.csv line 1: 4 fields ('0, 05, 1, 2'); a target spectrum"),
    ],
)
def test_target_csv_that_is_not_t_sa_text_is_one_key_path_line(tmp_path, content, expect):
    """A binary or UTF-16 target gave a traceback; '0_05' and decimal commas were read as
    other numbers."""
    (tmp_path / "t.csv").write_bytes(content)
    with pytest.raises(SceneError) as err:
        parse_scene(_scene('{ target = "t.csv", periods = [0.1, 0.2] }'), tmp_path / "s.toml")
    problems = [p for p in err.value.problems if p.startswith("records[0].scale.target: ")]
    assert len(problems) == 1 and expect in problems[0], err.value.problems
    assert "\n" not in str(err.value)


def test_target_csv_size_and_rows_are_bounded(tmp_path, monkeypatch):
    """A 125 MB target CSV took 1.28 GB to read: a file above 10 MiB is refused before it is
    read, and one with too many rows as soon as it has them."""
    import tracemalloc

    from floorslide.practice import target

    big = tmp_path / "t.csv"
    with open(big, "wb") as fh:
        fh.truncate(target.MAX_TARGET_BYTES + 1)
    scene = _scene('{ target = "t.csv", periods = [0.1, 0.2] }')
    tracemalloc.start()
    try:
        text = _problems(scene, tmp_path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert "records[0].scale.target: t.csv: 10,485,761 bytes; a target spectrum is a" in text
    assert "at most 10 MiB and 100,000 rows" in text
    assert peak < 2**20
    monkeypatch.setattr(target, "MAX_TARGET_ROWS", 3)
    big.write_text(TARGET_ROWS)
    assert "t.csv: more than 3 rows" in _problems(scene, tmp_path)


@pytest.mark.parametrize(
    ("scale", "extra", "expect"),
    [
        (
            f"{{ target = {TWO_POINT}, periods = [0.1, 2.0], levels = [0.5, 1.0] }}",
            "",
            "records[0].scale.levels: stripes need at least 2 records each (a fragility fit); "
            "the set has 1",
        ),
        (
            f"{{ target = {TWO_POINT}, periods = [0.1, 2.0] }}",
            "allowable = [0.05, 0.0]",
            "contents[0].allowable[1]: must be > 0, got 0.0",
        ),
        (
            f"{{ target = {TWO_POINT}, periods = [0.1, 2.0] }}",
            "allowable = -0.1",
            "contents[0].allowable: must be > 0, got -0.1",
        ),
        (f"{{ target = {TWO_POINT} }}", "", "records[0].scale: give periods = [T_lo, T_hi]"),
        (
            f"{{ target = {TWO_POINT}, periods = [2.0, 0.1] }}",
            "",
            "records[0].scale.periods: must increase: [2, 0.1]",
        ),
        (
            "{ target = { sds = 1.0, sd1 = 0.6 }, period = 1.0 }",
            "",
            "records[0].scale.target.tl: missing",
        ),
        (
            f"{{ target = {TWO_POINT}, period = 1.0, periods = [0.1, 0.5] }}",
            "",
            "records[0].scale.period: 1 s lies outside periods [0.1, 0.5]",
        ),
        ('{ target = "none.csv", period = 1.0 }', "", "records[0].scale.target: no such target"),
    ],
)
def test_bad_scale_and_allowable(tmp_path, scale, extra, expect):
    text = _problems(_scene(scale, where='["ELC-180"]', extra=extra), tmp_path)
    assert expect in text


def test_scale_and_scale_pga_exclude_each_other(tmp_path):
    text = _scene(f"{{ target = {TWO_POINT}, period = 1.0 }}").replace(
        "scale = {", "scale_pga = 0.3\nscale = {"
    )
    assert "records[0].scale: give scale (to a target spectrum) or scale_pga, not both" in (
        _problems(text, tmp_path)
    )


def test_allowable_is_sorted(tmp_path):
    sc = parse_scene(
        _scene(f"{{ target = {TWO_POINT}, period = 1.0 }}", extra="allowable = [0.3, 0.05, 0.1]"),
        tmp_path / "a",
    )
    assert sc.contents[0].allowable == (0.05, 0.1, 0.3)


def test_match_suite_raises_the_suite_to_ninety_percent(tmp_path):
    scale = f"{{ target = {TWO_POINT}, periods = [0.2, 3.0], match_suite = true }}"
    sc = parse_scene(_scene(scale), tmp_path / "a")
    before = plan(
        parse_scene(_scene(scale.replace("true", "false")), tmp_path / "b"), evaluate=False
    )
    p = plan(sc, evaluate=False)
    ratio0 = before.scaling[0]["suite"]["min_ratio"]
    assert ratio0 < SUITE_FRACTION  # these three records fall short over 0.2–3 s
    c = p.scaling[0]["suite_factor"]
    assert c == pytest.approx(SUITE_FRACTION / ratio0, rel=1e-14)
    grid = sc.records[0].scale.grid()
    target = TargetSpectrum.two_point(1.0, 0.6, 8.0)(grid)
    mean = np.mean(
        [response_spectrum(r.acc, r.dt, grid, 0.05).psa[0] / G for r in p.records], axis=0
    )
    assert (mean / target).min() == pytest.approx(SUITE_FRACTION, rel=1e-12)
    assert p.scaling[0]["suite"]["passes"]
    for r0, r in zip(before.records, p.records, strict=True):
        assert r.scale == pytest.approx(c * r0.scale, rel=1e-15)
    assert "after raising every record by" in p.describe()
