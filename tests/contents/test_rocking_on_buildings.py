"""Rocking blocks on the floors of buildings (issue 15): fixed-base, linearly isolated and on
nonlinear isolation, where the blocks ride along in the event-driven integration. The limits
of the nonlinear layers are the linear buildings, reached by other code paths."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from tests.conftest import SLAMMER, G

WIDTHS = [0.04, 0.06, 0.1]
HEIGHTS = [1.0, 1.2, 1.0]


@pytest.fixture(scope="module")
def elc() -> np.ndarray:
    return np.loadtxt(SLAMMER / "ImperialValley_1940_ELC-180.txt") * G


def superstructure():
    return fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.03)


def assert_same_rocking(a, b, tol=1e-9):
    """Two computations of the same rocking from floor motions equal to rounding. Times of
    impacts at small angular velocity amplify a rounding-level difference of the floor motion
    by the inverse of that velocity: the total rocking time is compared at 10·tol."""
    alpha = np.asarray(a.alpha)[:, None]
    np.testing.assert_array_equal(a.overturned, b.overturned)
    np.testing.assert_array_equal(a.impacts, b.impacts)
    np.testing.assert_allclose(a.peak_ratio, b.peak_ratio, rtol=0, atol=tol)
    np.testing.assert_allclose(a.rocking_time, b.rocking_time, rtol=10 * tol)
    np.testing.assert_allclose(a.overturn_time, b.overturn_time, rtol=tol)
    np.testing.assert_allclose(a.theta / alpha, b.theta / alpha, rtol=0, atol=tol)


@pytest.mark.parametrize("method", ["exact", "nonlinear"])
def test_on_a_frictionless_pendulum_as_on_the_linear_isolated_roof(elc, method):
    """mu = 0: the pendulum is the linear isolator k = W/R (undamped); the blocks ride along in
    the nonlinear kernel there and on the linear building's floor motion here. The two floor
    motions, formed differently, agree to 3e-13 of the roof's PFA (measured); rocking with
    hundreds of impacts amplifies such a difference up to ~1e5 times (measured: 2.3e-8 of α),
    hence 1e-7 here — a wrong term of either path would be off by orders of magnitude more."""
    sup = superstructure()
    b = fs.NonlinearIsolatedBuilding(sup, 1.0, fs.FrictionPendulum(mu=0.0, period=3.0))
    lin = fs.IsolatedBuilding(sup, 1.0, 3.0, 0.0)
    kw = dict(method=method, histories=True)
    a = fs.rock(elc, 0.01, WIDTHS, HEIGHTS, building=b, floor=2, **kw)
    ref = fs.rock(elc, 0.01, WIDTHS, HEIGHTS, building=lin, floor=2, **kw)
    assert (ref.impacts > 0).all()  # they do rock
    assert_same_rocking(a, ref, tol=1e-7)


def test_on_a_stuck_pendulum_as_on_the_fixed_base_roof(elc):
    """mu = 2 never slides: the base mat moves with the ground, the superstructure is the
    fixed-base building."""
    sup = superstructure()
    b = fs.NonlinearIsolatedBuilding(sup, 1.0, fs.FrictionPendulum(mu=2.0, period=3.0))
    a = fs.rock(elc, 0.01, WIDTHS, HEIGHTS, building=b, floor=2, histories=True)
    ref = fs.rock(elc, 0.01, WIDTHS, HEIGHTS, building=sup, floor=2, histories=True)
    assert (ref.impacts > 0).all()
    assert_same_rocking(a, ref)


def test_a_floor_motion_is_the_same_as_building_and_floor(elc):
    sup = superstructure()
    fm = fs.floor_motion(sup, elc, 1, 0.01)
    a = fs.rock(fm, width=WIDTHS, height=HEIGHTS, histories=True)
    b = fs.rock(elc, 0.01, WIDTHS, HEIGHTS, building=sup, floor=1, histories=True)
    np.testing.assert_array_equal(a.theta, b.theta)
    np.testing.assert_array_equal(a.peak_ratio, b.peak_ratio)


def test_the_ground_floor_of_a_fixed_base_building_is_the_ground(elc):
    a = fs.rock(elc, 0.01, WIDTHS, HEIGHTS, building=superstructure(), floor=0, histories=True)
    b = fs.rock(elc, 0.01, WIDTHS, HEIGHTS, histories=True)
    np.testing.assert_array_equal(a.theta, b.theta)
