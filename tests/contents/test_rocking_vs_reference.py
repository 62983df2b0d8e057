"""fs.rock against the independent event-located ODE reference (tests/reference_rocking.py) on
real records, on the ground and on building floors: the linearised equation (``exact``) to
1e-10, the full equation (``nonlinear``) to 1e-9 — θ at every sample and its peak in units of
α, the rocking time and the overturning time relative — and the same counts of uplifts and
impacts."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from tests.conftest import load_slammer
from tests.reference_rocking import rock_reference

RECORDS = {
    # file, samples used, block (width, height), scale
    "elc": ("ImperialValley_1940_ELC-180.txt", 1500, 0.3, 1.2, 1.0),
    "kobe": ("Kobe_1995_KAK-000.txt", 2000, 0.25, 1.2, 1.0),
    "petrolia": ("CapeMendocino_1992_PET-090.txt", 1000, 0.4, 1.2, 1.0),
    "elc-overturns": ("ImperialValley_1940_ELC-180.txt", 1500, 0.3, 1.2, 2.0),
}
TOL = {"exact": 1e-10, "nonlinear": 1e-9}


def compare(r, ref, tol):
    alpha = r.alpha[0]
    assert r.impacts[0] == ref["impacts"]
    assert r.uplifts[0] == ref["uplifts"]
    assert bool(r.overturned[0]) == bool(ref["overturned"])
    theta = r.theta[0]
    np.testing.assert_array_equal(np.isnan(theta), np.isnan(ref["theta"]))
    ok = ~np.isnan(theta)
    assert np.max(np.abs(theta[ok] - ref["theta"][ok])) <= tol * alpha
    assert abs(r.peak_ratio[0] - ref["peak_ratio"]) <= tol
    assert r.rocking_time[0] == pytest.approx(ref["rocking_time"], rel=tol, abs=1e-14)
    if ref["overturned"]:
        assert r.overturn_time[0] == pytest.approx(ref["t_overturn"], rel=tol)


@pytest.mark.parametrize("method", ["exact", "nonlinear"])
@pytest.mark.parametrize("key", list(RECORDS))
def test_on_the_ground(key, method):
    name, n, width, height, scale = RECORDS[key]
    acc, dt = load_slammer(name)
    acc = acc[:n] * scale
    ref = rock_reference(
        acc, dt, width=width, height=height, method="linear" if method == "exact" else method
    )
    r = fs.rock(acc, dt, width, height, method=method, histories=True)
    assert r.impacts[0] > 10 or r.overturned[0]  # it does rock
    compare(r, ref, TOL[method])


BUILDINGS = {
    "fixed T=0.3 s": lambda: fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.03),
    "isolated T=2.5 s": lambda: fs.IsolatedBuilding(
        fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.03), 1.0, 2.5, 0.1
    ),
}


@pytest.mark.parametrize("method", ["exact", "nonlinear"])
@pytest.mark.parametrize("kind", list(BUILDINGS))
def test_on_the_roof(kind, method):
    """The reference integrates the building's state space (python-control's matrices) with the
    block; floorslide rocks the block on the building's exact floor motion."""
    building = BUILDINGS[kind]()
    roof = building.stories
    ss = building.state_space(floors=[roof])
    system = (np.asarray(ss.A), np.asarray(ss.B)[:, 0], np.asarray(ss.C)[0], float(ss.D[0, 0]))
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    acc = acc[:1200]
    width = 0.15 if kind.startswith("isolated") else 0.35
    ref = rock_reference(
        acc,
        dt,
        width=width,
        height=1.2,
        method="linear" if method == "exact" else method,
        floor_system=system,
    )
    r = fs.rock(acc, dt, width, 1.2, building=building, floor=roof, method=method, histories=True)
    assert r.uplifts[0] > 0
    compare(r, ref, TOL[method])
