"""docs/design.md §8 hard cases for building models: finite, stable and still right."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from floorslide.building.model import IsolatedBuilding, ShearBuilding
from floorslide.building.motions import floor_motions, peak_floor_acceleration
from tests.reference import linear_response


def check_against_reference(b, ag, dt, floors=None, tol=1e-9):
    A, B = b.state_matrices()
    C, D, _ = b.output_matrices(floors)
    X = linear_response(A, B[:, 0], ag, dt)
    ref = C @ X.T + D @ ag[None, :]
    got = floor_motions(b, ag, dt, floors=floors)
    assert np.all(np.isfinite(got))
    err = np.abs(got - ref).max() / np.abs(ref).max()
    assert err < tol, err
    return got


def test_stiff_building_coarse_dt(coarse_record):
    """T = 0.01 s under dt = 0.02 s: ω·dt = 12.6 rad per step, still exact."""
    ag, dt = coarse_record
    ag = ag[:600]
    b = ShearBuilding.from_period(1, 0.01, 0.05)
    got = check_against_reference(b, ag, dt)
    # a very stiff building moves with the ground: floor ≈ ground (1 + O((ω_n dt)^-2))
    assert np.abs(got[1] - ag).max() < 0.02 * np.abs(ag).max()
    pk = peak_floor_acceleration(b, ag, dt, floors=[1])
    assert np.isfinite(pk.peak[0]) and pk.peak[0] >= np.abs(got[1]).max()


def test_fifty_storeys(elcentro):
    ag, dt = elcentro
    ag = ag[:300]
    b = ShearBuilding.from_period(50, 5.0, 0.05, profile="shear")
    assert b.periods[0] == pytest.approx(5.0, rel=1e-12)
    check_against_reference(b, ag, dt, floors=[50, 25, 1])


def test_flexible_undamped_isolation(elcentro):
    """T_i = 6 s with ξ_i = 0: lightly damped, very flexible, still exact and finite."""
    ag, dt = elcentro
    ag = ag[:1000]
    iso = IsolatedBuilding(ShearBuilding.from_period(3, 0.4, 0.02), 1.0, 6.0, 0.0)
    check_against_reference(iso, ag, dt)


def test_zero_superstructure_damping(elcentro):
    ag, dt = elcentro
    ag = ag[:1000]
    fb = ShearBuilding.from_period(3, 0.4, 0.0)
    check_against_reference(fb, ag, dt)
    check_against_reference(IsolatedBuilding(fb, 1.0, 2.5, 0.1), ag, dt)


def test_million_sample_record_bounded_memory_and_no_drift():
    """10⁶ samples of a 2 Hz sine at dt = 1 ms: memory is the output plus O(1); the steady
    response at the end equals the one 900 s earlier (no drift, no accumulation)."""
    dt, f = 0.001, 2.0
    n = 1_000_000
    t = np.arange(n) * dt
    ag = np.sin(2 * np.pi * f * t)
    b = IsolatedBuilding(ShearBuilding.from_period(3, 0.4, 0.05), 1.0, 2.5, 0.1)
    floor_motions(b, ag[:10], dt, floors=[3])  # compile outside the measurement
    tracemalloc.start()
    y = floor_motions(b, ag, dt, floors=[3])[0]
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 1.5 * y.nbytes + 1e6
    per = round(1 / f / dt)
    early = y[100_000 : 100_000 + per]
    start = 100_000 + per * ((n - per - 100_000) // per)
    late = y[start : start + per]
    np.testing.assert_allclose(late, early, rtol=0, atol=1e-10 * np.abs(early).max())
