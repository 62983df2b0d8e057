"""The single-record solver commands: floorslide slide and floorslide spectrum
(docs/design.md §3)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

from floorslide.building import (
    BilinearIsolator,
    FrictionPendulum,
    IsolatedBuilding,
    NonlinearIsolatedBuilding,
    ShearBuilding,
    peak_floor_acceleration,
)
from floorslide.cli import cli
from floorslide.contents.sliding import slide
from floorslide.spectra import response_spectrum
from tests.conftest import SLAMMER, floorslide_cli, load_slammer

RECORD = str(SLAMMER / "ImperialValley_1940_ELC-180.txt")


def run(*args):
    """``floorslide ARGS`` (the entry point, in this process: :func:`floorslide_cli`)."""
    return floorslide_cli(*args)


def test_slide_json_matches_the_api():
    out = run("slide", RECORD, "--mu", "0.05,0.2", "--mu-s", "0.1,0.25", "--json")
    assert out.returncode == 0, out.stderr
    rows = json.loads(out.stdout)
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    ref = slide(acc, dt, [0.05, 0.2], [0.1, 0.25])
    assert [r["mu_k"] for r in rows] == [0.05, 0.2]
    for key in ("mu_k", "mu_s", "peak_slide", "residual_slide", "peak_abs_accel"):
        assert key in rows[0]
    np.testing.assert_allclose([r["peak_slide"] for r in rows], ref.peak_slide, rtol=1e-12)


def test_slide_scale_pga_and_direction():
    out = run(
        "slide", RECORD, "--mu", "0.1", "--scale-pga", "0.6", "--direction", "positive", "--json"
    )
    assert out.returncode == 0, out.stderr
    row = json.loads(out.stdout)[0]
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    acc = acc * (0.6 * 9.80665 / np.abs(acc).max())
    ref = slide(acc, dt, 0.1, direction="positive")
    assert row["peak_slide"] == pytest.approx(ref.peak_slide[0], rel=1e-12)
    assert row["residual_slide"] <= 0


def test_spectrum_json_keys_and_values():
    out = run("spectrum", RECORD, "--periods", "0,0.2,1", "--damping", "0.02,0.05", "--json")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    for key in ("periods", "damping", "psa", "sa", "sv", "sd"):
        assert key in data
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    ref = response_spectrum(acc, dt, [0, 0.2, 1], [0.02, 0.05])
    np.testing.assert_allclose(data["psa"], ref.psa, rtol=1e-12)
    assert data["periods"] == [0.0, 0.2, 1.0]


def test_spectrum_log_spaced_periods_text_output():
    out = run("spectrum", RECORD, "--periods", "0.1:2:5")
    assert out.returncode == 0, out.stderr
    assert "PSA (g)" in out.stdout and len(out.stdout.splitlines()) == 1 + 1 + 1 + 5


@pytest.mark.parametrize(
    ("args", "code", "text"),
    [
        (("slide", RECORD, "--mu", "abc"), 2, "--mu"),
        (("slide", RECORD), 2, "--mu"),
        (("slide", "missing.AT2", "--mu", "0.1"), 3, "missing.AT2"),
        (("slide", RECORD, "--mu", "-0.1"), 2, "mu_k"),
        (("spectrum", RECORD, "--periods", "1:0.5:3"), 2, "periods"),
        (("spectrum", RECORD, "--damping", "1.5"), 2, "damping"),
        # issue 19 item 7: killed by the OOM killer (23.8 GB), a MemoryError traceback
        (("spectrum", RECORD, "--periods", "0.1:5:100000000"), 2, "at most 10000"),
        (("spectrum", RECORD, "--periods", "1e-9,1e9"), 2, "1e+09 s is above 10000 s"),
        (("spectrum", RECORD, "--periods", "1e-9,1"), 2, "1e-09 s is below dt/1000"),
        (("spectrum", RECORD, "--periods", "0.1:5:10000", "--damping", "0.02,0.05"), 0, ""),
        (("spectrum", RECORD, "--dt", "0_01"), 2, "'0_01'"),  # float('0_01') is 1.0
        (("slide", RECORD, "--mu", "0_1"), 2, "--mu"),
        (("slide", RECORD, "--mu", "0.1,,0.2"), 2, "item 2 of '0.1,,0.2' is empty"),  # dropped
        (("slide", RECORD, "--mu", ",".join(["0.1"] * 10001)), 2, "at most 10000 values, got"),
        (("slide", RECORD, "--mu", "0.1", "--scale-pga", "0_3"), 2, "'0_3'"),
        (("spectrum", RECORD, "--periods", "0.1:5:1_00"), 2, "--periods"),
        (("slide", RECORD, "--mu", "0.1", "--building", "fixed:period=0_4"), 2, "period='0_4'"),
    ],
)
def test_user_mistakes_give_one_clear_line(args, code, text):
    out = run(*args)
    assert out.returncode == code
    assert "Traceback" not in out.stderr
    assert text in out.stderr
    if code == 2:
        assert len([line for line in out.stderr.splitlines() if "rror" in line]) == 1


def test_isolation_that_does_not_isolate_is_a_one_line_warning():
    """--building isolated:period=0.3,super_period=0.4 (issue 19 item 8): computed as asked,
    with one warning line on stderr."""
    spec = "isolated:period=0.3,super_period=0.4"
    out = run("slide", RECORD, "--mu", "0.1", "--building", spec, "--json")
    assert out.returncode == 0, out.stderr
    assert out.stderr == (
        "floorslide: warning: isolation period 0.3 s is not above the fixed-base period 0.4 s "
        "of the superstructure: the isolators would not isolate (almost surely a mistake)\n"
    )
    assert json.loads(out.stdout)[0]["mu_k"] == 0.1


# --building / --floor (issue 12 item 8): a one-off floor check without a scene -------------

FIXED = "fixed:period=0.4,stories=3,damping=0.05"
ISOLATED = "isolated:period=2.5,damping=0.1,super_period=0.4,stories=3"
STOREYS = "fixed:masses=2e5/2e5/1.5e5,stiffnesses=3e8/3e8/2e8,damping=0.03"


def fixed_building():
    return ShearBuilding.from_period(stories=3, period=0.4, damping=0.05)


@pytest.mark.parametrize(
    ("spec", "floor", "building", "number"),
    [
        (FIXED, None, fixed_building, 3),
        (ISOLATED, "2", lambda: IsolatedBuilding(fixed_building(), 1.0, 2.5, 0.1), 2),
        (
            STOREYS,
            "roof",
            lambda: ShearBuilding([2e5, 2e5, 1.5e5], [3e8, 3e8, 2e8], 0.03),
            3,
        ),
        (
            "fps:period=3,mu=0.06,super_period=0.4,stories=3",
            "roof",
            lambda: NonlinearIsolatedBuilding(
                fixed_building(), 1.0, FrictionPendulum(mu=0.06, period=3.0)
            ),
            3,
        ),
        (
            "isolated:period=2.5,isolator=bilinear,q_ratio=0.06,yield_disp=0.02,"
            "super_period=0.4,stories=3",
            "1",
            lambda: NonlinearIsolatedBuilding(
                fixed_building(), 1.0, BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02)
            ),
            1,
        ),
    ],
    ids=["fixed", "isolated", "storeys", "fps", "lead-rubber"],
)
def test_slide_on_a_floor_of_a_building(spec, floor, building, number):
    args = ["slide", RECORD, "--mu", "0.05,0.2", "--building", spec, "--json"]
    out = run(*args, *(["--floor", floor] if floor else []))
    assert out.returncode == 0, out.stderr
    rows = json.loads(out.stdout)
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    ref = slide(acc, dt, [0.05, 0.2], building=building(), floor=number)
    ground = slide(acc, dt, [0.05, 0.2])
    np.testing.assert_allclose([r["peak_slide"] for r in rows], ref.peak_slide, rtol=1e-12)
    assert not np.allclose(ref.peak_slide, ground.peak_slide, rtol=0.05)  # the floor matters
    assert rows[0]["building"] == spec and rows[0]["floor"] == number


def test_slide_header_says_which_building_and_floor():
    out = run("slide", RECORD, "--mu", "0.1", "--building", FIXED)
    assert out.returncode == 0, out.stderr
    header = out.stdout.splitlines()[1]
    assert header.startswith("on floor 3 (roof) of: fixed-base, 3 storeys, T1 = 0.4 s")
    assert "PFA = " in header
    ground = run("slide", RECORD, "--mu", "0.1")
    assert ground.stdout.splitlines()[0].endswith("on the ground")


def test_floor_zero_of_a_fixed_building_is_the_ground():
    base = run("slide", RECORD, "--mu", "0.1", "--json")
    floor0 = run("slide", RECORD, "--mu", "0.1", "--json", "--building", FIXED, "--floor", "0")
    assert floor0.returncode == 0, floor0.stderr
    assert json.loads(floor0.stdout)[0]["peak_slide"] == json.loads(base.stdout)[0]["peak_slide"]


def test_floor_response_spectrum_from_the_command_line():
    out = run(
        "spectrum", RECORD, "--periods", "0,0.4,1", "--building", ISOLATED, "--floor", "3", "--json"
    )
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    iso = IsolatedBuilding(fixed_building(), 1.0, 2.5, 0.1)
    ref = response_spectrum(acc, dt, [0, 0.4, 1], 0.05, building=iso, floor=3)
    np.testing.assert_allclose(data["psa"], ref.psa, rtol=1e-12)
    assert data["building"] == ISOLATED and data["floor"] == 3
    # at T = 0 the floor spectrum is the peak floor acceleration (isolation: well below PGA)
    pfa = peak_floor_acceleration(iso, acc, dt, [3]).peak[0]
    assert data["psa"][0][0] == pytest.approx(pfa, rel=1e-12)
    assert pfa < 0.5 * np.abs(acc).max()
    text = run("spectrum", RECORD, "--periods", "1", "--building", ISOLATED).stdout
    assert text.splitlines()[1].startswith("floor response spectra on floor 3 (roof) of: isolated")


@pytest.mark.parametrize(
    ("args", "texts"),
    [
        (("--building", "fixed:perod=0.4,stories=3,foo=1"), ("'perod'", "'foo'", "known keys")),
        (("--building", "fixed:period=abc"), ("period='abc'", "not a number")),
        (("--building", "fixed:stories=3"), ("period is missing",)),
        (("--building", "isolated:period=2.5"), ("super_period is missing",)),
        (("--building", "isolated:period=2.5,super_period=-1"), ("super_period", "> 0")),
        (("--building", "fixed:period=0.4,damping=1.5"), ("damping", "[0, 1)")),
        (("--building", "tower:period=1"), ("unknown kind 'tower'",)),
        (("--building", "fixed:masses=1/1"), ("stiffnesses is missing",)),
        (("--building", "fixed:period=0.4", "--floor", "2"), ("--floor", "0..1")),
        (("--building", "fixed:period=0.4", "--floor", "top"), ("--floor", "'top'")),
        # int('1_0') is 10: a floor of a 12-storey building, not the typo it is
        (("--building", "fixed:period=0.4,stories=12", "--floor", "1_0"), ("--floor", "'1_0'")),
        (("--floor", "2"), ("--floor", "needs --building")),
    ],
)
@pytest.mark.parametrize("command", ["slide", "spectrum"])
def test_building_option_mistakes_are_one_line_usage_errors(command, args, texts):
    extra = ("--mu", "0.1") if command == "slide" else ()
    result = CliRunner().invoke(cli, [command, RECORD, *extra, *args])
    assert result.exit_code == 2, result.output
    error = [line for line in result.stderr.splitlines() if line.startswith("Error:")]
    assert len(error) == 1 and "Traceback" not in result.stderr
    option = "--floor" if "--floor" in texts else "--building"
    assert option in error[0]
    for text in texts:
        assert text in error[0]


def test_rock_json_matches_the_api_on_the_ground_and_on_a_roof():
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    out = run("rock", RECORD, "--width", "0.2,0.3", "--height", "1.2", "--json")
    assert out.returncode == 0, out.stderr
    rows = json.loads(out.stdout)
    from floorslide.contents.rocking_block import rock

    ref = rock(acc, dt, [0.2, 0.3], 1.2)
    assert [r["peak_ratio"] for r in rows] == list(ref.peak_ratio)
    assert [r["impacts"] for r in rows] == list(ref.impacts)
    assert [r["mode"] for r in rows] == list(ref.mode)
    spec = "isolated:period=2.5,damping=0.1,super_period=0.4,stories=3"
    out = run("rock", RECORD, "--width", "0.12", "--height", "1.2", "--building", spec,
              "--method", "nonlinear", "--json")  # fmt: skip
    assert out.returncode == 0, out.stderr
    row = json.loads(out.stdout)[0]
    b = IsolatedBuilding(ShearBuilding.from_period(3, 0.4, 0.05), 1.0, 2.5, 0.1)
    ref = rock(acc, dt, 0.12, 1.2, building=b, floor=3, method="nonlinear")
    assert row["peak_ratio"] == ref.peak_ratio[0] and row["impacts"] == ref.impacts[0]
    assert row["floor"] == 3 and row["method"] == "nonlinear"


def test_rock_table_and_bad_geometry():
    out = run("rock", RECORD, "--width", "0.2", "--height", "1.2", "--scale-pga", "0.8")
    assert out.returncode == 0, out.stderr
    assert "peak th/a" in out.stdout and ("overturns at" in out.stdout or "rock" in out.stdout)
    out = run("rock", RECORD, "--width", "-0.2", "--height", "1.2")
    assert out.returncode == 2 and "--width" in out.stderr and "> 0 m" in out.stderr
    out = run("rock", RECORD, "--width", "0.2", "--height", "1.2", "--restitution", "2")
    assert out.returncode == 2 and "--restitution" in out.stderr


def test_rock_with_friction_is_slide_rock():
    """``rock --mu``: each block under each friction value by fs.slide_rock (one row per block
    and friction value, the JSON equal to the API's); a --mu-s below --mu is refused by name."""
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    out = run("rock", RECORD, "--width", "0.3,0.5", "--height", "1.2", "--mu", "0.25,0.45",
              "--mu-s", "0.26,0.5", "--scale-pga", "0.6", "--json")  # fmt: skip
    assert out.returncode == 0, out.stderr
    rows = json.loads(out.stdout)
    import floorslide as fs

    a = acc * (0.6 * 9.80665 / np.max(np.abs(acc)))
    ref = fs.slide_rock(a, dt, [0.3, 0.3, 0.5, 0.5], 1.2, [0.25, 0.45, 0.25, 0.45],
                        mu_s=[0.26, 0.5, 0.26, 0.5])  # fmt: skip
    assert [(r["width"], r["mu_k"]) for r in rows] == [(0.3, 0.25), (0.3, 0.45), (0.5, 0.25),
                                                      (0.5, 0.45)]  # fmt: skip
    np.testing.assert_allclose([r["peak_ratio"] for r in rows], ref.peak_ratio, rtol=1e-12)
    np.testing.assert_allclose([r["peak_slide"] for r in rows], ref.peak_slide, rtol=1e-12)
    assert [r["mode"] for r in rows] == list(ref.mode)
    out = run("rock", RECORD, "--width", "0.3", "--height", "1.2", "--mu", "0.3")
    assert out.returncode == 0 and "sl-rock" in out.stdout
    out = run("rock", RECORD, "--width", "0.3", "--height", "1.2", "--mu", "0.3", "--mu-s", "0.2")
    assert out.returncode == 2 and "--mu-s" in out.stderr


# ------------------------------------------------------------------ two components (issue 16)
PAIR_DIR = SLAMMER.parent / "pairs"
H1 = str(PAIR_DIR / "RSN1084_NORTHR_SCS052.AT2")
H2 = str(PAIR_DIR / "RSN1084_NORTHR_SCS142.AT2")


def test_slide_two_components_matches_slide_plane():
    import floorslide as fs

    out = run("slide", H1, H2, "--mu", "0.1,0.2", "--mu-s", "0.15,0.2", "--json")
    assert out.returncode == 0, out.stderr
    rows = json.loads(out.stdout)
    ref = fs.slide_plane(fs.read_pair(H1, H2), None, [0.1, 0.2], [0.15, 0.2])
    np.testing.assert_allclose([r["peak_slide"] for r in rows], ref.peak_slide, rtol=1e-12)
    np.testing.assert_allclose([r["peak_angle"] for r in rows], ref.peak_angle, rtol=1e-12)
    np.testing.assert_allclose([r["residual"] for r in rows], ref.residual, rtol=1e-12)
    np.testing.assert_allclose([r["peak_slide_1d"] for r in rows], ref.peak_slide_1d, rtol=1e-12)
    assert rows[0]["components"] == ["52", "142"]


def test_slide_two_components_on_a_building_per_direction_text():
    import floorslide as fs

    args = ["slide", H1, H2, "--mu", "0.1", "--scale-pga", "0.5"]
    args += ["--building", "fixed:period=0.4,stories=3"]
    args += ["--building-h2", "fixed:period=1.0,stories=3"]
    out = run(*args, "--json")
    assert out.returncode == 0, out.stderr
    (row,) = json.loads(out.stdout)
    p = fs.read_pair(H1, H2)
    f = 0.5 * fs.G / max(np.abs(p.h1).max(), np.abs(p.h2).max())
    b = fs.BuildingPair(fs.ShearBuilding.from_period(3, 0.4), fs.ShearBuilding.from_period(3, 1.0))
    ref = fs.slide_plane((f * p.h1, f * p.h2), p.dt, 0.1, building=b, floor=3)
    assert abs(row["peak_slide"] - ref.peak_slide[0]) <= 1e-12 * ref.peak_slide[0]
    text = run(*args)
    assert text.returncode == 0, text.stderr
    assert "sliding in the plane" in text.stdout and "along 142" in text.stdout
    assert "2-D/1-D" in text.stdout


@pytest.mark.parametrize(
    ("extra", "hint"),
    [
        (["--direction", "positive"], "--direction"),
        (["--building-h2", "fixed:period=1"], "--building-h2"),
        (["--pair"], "--pair"),
    ],
)
def test_slide_two_component_mistakes(extra, hint):
    out = run("slide", H1, H2, "--mu", "0.1", *extra)
    assert out.returncode == 2
    assert hint in out.stderr


@pytest.mark.parametrize("command", ["slide", "spectrum"])
def test_one_file_twice_or_two_earthquakes_are_not_a_pair(command):
    """'slide A A' ran, with a note calling the parallel components '90 degrees off'; two
    earthquakes at two stations passed as one pair."""
    landers = H1.replace("RSN1084_NORTHR_SCS052", "RSN879_LANDERS_LCN260")
    extra = ["--mu", "0.1"] if command == "slide" else ["--periods", "1"]
    for second, text in ((H1, "the same file is given as both"), (landers, "different stations")):
        out = run(command, H1, second, *extra)
        assert out.returncode == 3, out.stderr
        assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
        assert out.stderr.startswith(f"floorslide: error: {H1} + {second}: ")
        assert text in out.stderr


def test_slide_one_record_is_not_a_pair():
    out = run("slide", H1, "--pair", "--mu", "0.1")
    assert out.returncode != 0
    assert "one component in the file" in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1


def test_spectrum_of_two_components_is_rotd():
    import floorslide as fs

    out = run("spectrum", H1, H2, "--periods", "0,0.2,1.0", "--damping", "0.05", "--json")
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout)
    ref = fs.rotd_spectrum(fs.read_pair(H1, H2), None, [0.0, 0.2, 1.0], 0.05)
    np.testing.assert_allclose(got["rotd50"], ref.rotd50, rtol=1e-13)
    np.testing.assert_allclose(got["rotd100"], ref.rotd100, rtol=1e-13)
    np.testing.assert_allclose(got["h1"]["psa"], ref.h1.psa, rtol=1e-13)
    assert got["components"] == ["52", "142"]
    text = run("spectrum", H1, H2, "--periods", "0.5", "--building", "fixed:period=0.4,stories=2",
               "--building-h2", "fixed:period=0.8,stories=2")  # fmt: skip
    assert text.returncode == 0, text.stderr
    assert "RotD50 and RotD100" in text.stdout and "along 142" in text.stdout


def test_two_components_on_nonlinear_isolation():
    """Bearings under two components are the coupled (bidirectional) layer: friction pendulums
    and lead-rubber bearings run in the plane."""
    pairs = SLAMMER.parent / "pairs"
    a, b = sorted(str(p) for p in pairs.glob("RSN1084_*.AT2"))
    spec = "fps:period=3,mu=0.06,super_period=0.4"
    out = run("slide", a, b, "--mu", "0.1", "--building", spec)
    assert out.returncode == 0, out.stderr
    assert "sliding in the plane" in out.stdout and "friction pendulum" in out.stdout
    spec = "lrb:period=2.5,q_ratio=0.06,yield_disp=0.02,super_period=0.4"
    out = run("slide", a, b, "--mu", "0.1", "--building", spec)
    assert out.returncode == 0, out.stderr
    assert "sliding in the plane" in out.stdout and "bilinear layer" in out.stdout
