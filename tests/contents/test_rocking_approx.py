"""Approximate rocking methods (floorslide.contents.rocking_approx, for the bench): they solve
the full equation on the floor's samples and must converge to the exact solution of it
(``method="nonlinear"``) as their step or tolerance shrinks."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.errors import ModelError
from tests.conftest import load_slammer

WIDTHS, HEIGHT = [0.5, 0.6], 1.2


@pytest.fixture(scope="module")
def petrolia():
    acc, dt = load_slammer("CapeMendocino_1992_PET-090.txt")
    return acc, dt, fs.rock(acc, dt, WIDTHS, HEIGHT, method="nonlinear")


def test_rk4_converges_to_the_exact_full_equation(petrolia):
    acc, dt, exact = petrolia
    assert (exact.uplifts > 0).all() and not exact.overturned.any()
    errors = []
    for k in (1, 4, 16, 64):
        r = fs.rock(acc, dt, WIDTHS, HEIGHT, method="rk4", substeps=k)
        errors.append(np.max(np.abs(r.peak_ratio - exact.peak_ratio) / exact.peak_ratio))
    assert errors[-1] < 1e-4
    assert errors[-1] < errors[0] / 100


def test_solve_ivp_converges_to_the_exact_full_equation(petrolia):
    """Its peak is the largest |θ| at its own steps (as such scripts take it), so it stays a
    little below the true peak between steps; it still gains 10× from rtol 1e-3 to 1e-9."""
    acc, dt, exact = petrolia
    errors = []
    for rtol in (1e-3, 1e-9):
        r = fs.rock(acc, dt, WIDTHS, HEIGHT, method="solve_ivp", rtol=rtol)
        np.testing.assert_array_equal(r.overturned, exact.overturned)
        errors.append(np.max(np.abs(r.peak_ratio - exact.peak_ratio) / exact.peak_ratio))
    assert errors[1] < 2e-3 and errors[1] < errors[0] / 10


def test_approximate_methods_on_a_floor_use_its_samples():
    """On a floor they integrate the floor's exact samples joined by straight lines: the same
    as the ground method given those samples, bit for bit."""
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    b = fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.03)
    samples = fs.floor_motion(b, acc, 1, dt).samples()
    for method in ("rk4", "solve_ivp"):
        r = fs.rock(acc, dt, 0.35, HEIGHT, building=b, floor=1, method=method)
        ref = fs.rock(samples, dt, 0.35, HEIGHT, method=method)
        assert r.uplifts[0] > 0
        assert r.peak_ratio[0] == ref.peak_ratio[0] and r.impacts[0] == ref.impacts[0]


def test_approximate_methods_give_peaks_only():
    with pytest.raises(ModelError, match="histories"):
        fs.rock(np.zeros(10), 0.01, 0.2, 1.0, method="rk4", histories=True)
