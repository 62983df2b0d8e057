"""Command-line outputs a user cannot misread (docs/design.md §3, §10): units stated in JSON,
floor 0 named for what it is, implausible friction coefficients warned about."""

from __future__ import annotations

import json

import numpy as np
import pytest

from floorslide.constants import G
from tests.conftest import SLAMMER, floorslide_cli

RECORD = str(SLAMMER / "ImperialValley_1940_ELC-180.txt")
ISOLATED = "isolated:period=2.5,damping=0.1,super_period=0.4,stories=3"


def run(*args):
    """``floorslide ARGS`` (the entry point, in this process: :func:`floorslide_cli`)."""
    return floorslide_cli(*args)


def test_spectrum_json_states_its_units_and_matches_the_text_in_g():
    out = run("spectrum", RECORD, "--periods", "0.2,1", "--json")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert data["units"]["psa"] == "m/s**2" and data["units"]["sd"] == "m"
    assert data["floor_label"] == "ground"
    text = run("spectrum", RECORD, "--periods", "0.2,1").stdout.splitlines()
    psa_g = [float(line.split()[1]) for line in text[-2:]]
    np.testing.assert_allclose(np.array(data["psa"][0]) / G, psa_g, atol=5e-5)


@pytest.mark.parametrize(("floor", "label"), [("0", "base mat"), ("3", "roof"), ("1", "floor 1")])
def test_spectrum_json_names_floor_zero_of_an_isolated_building(floor, label):
    out = run("spectrum", RECORD, "--periods", "0.5", "--building", ISOLATED, "--floor", floor,
              "--json")  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["floor_label"] == label


def test_spectrum_json_of_two_components_states_its_units():
    from tests.test_cli_solvers import H1, H2

    out = run("spectrum", H1, H2, "--periods", "0.5", "--json")
    assert out.returncode == 0, out.stderr
    units = json.loads(out.stdout)["units"]
    assert units["rotd50"] == units["rotd100"] == "m/s**2" and units["h1"]["psa"] == "m/s**2"


def test_friction_as_a_percentage_is_a_one_line_warning():
    out = run("slide", RECORD, "--mu", "10,20", "--json")
    assert out.returncode == 0, out.stderr
    assert out.stderr.splitlines() == [
        "floorslide: warning: --mu: friction coefficient 10 is implausible (dry friction is "
        "below about 1); did you mean 0.10?",
        "floorslide: warning: --mu: friction coefficient 20 is implausible (dry friction is "
        "below about 1); did you mean 0.20?",
    ]
    assert run("slide", RECORD, "--mu", "0.1,1.5").stderr == ""


def test_a_pendulum_given_by_its_radius_runs_on_the_single_record_commands():
    """isolator=friction_pendulum with radius= (the period 2π√(R/g)) on --building: the block
    slides on that building's roof, and the header says the pendulum's period."""
    spec = "isolated:isolator=friction_pendulum,mu=0.05,radius=2,super_period=0.4,stories=3"
    out = run("slide", RECORD, "--mu", "0.1", "--building", spec)
    assert out.returncode == 0, out.stderr
    assert "isolated on a friction pendulum, R = 2 m, T = 2.837 s, mu = 0.05" in out.stdout
    assert "Traceback" not in out.stderr
