"""The fast paths of the plane-sliding kernel (contents/_plane_kernel.py) against independent
results: a slow-manifold step against the explicit series steps it replaces, and slide_plane
against the independent event-located reference (tests/reference_sliding2d.py) on the ground
and on a floor — the runs where those paths (slow-manifold steps, stops declared once the
remaining slide is below rounding) are taken thousands of times."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.contents import _plane_kernel as pk
from floorslide.contents.plane import slide_plane
from floorslide.numerics.polynomial import taylor_shift
from tests.contents.test_sliding2d_reference import _pair, _run_pair
from tests.reference_sliding2d import slide2d_reference

D = 20
MUG = 0.66


def _explicit(ax0, ay0, v, span, max_steps=200_000):
    """v and u after `span` by the kernel's explicit series steps (Jorba–Zou steps of
    moving_series: exact to rounding, but ≈ 6|v|/|a| long when the block is slow)."""
    K = ax0.size - 1
    ax, ay = np.zeros(K + 1), np.zeros(K + 1)
    y, rho, w = np.zeros((D + 2, 2)), np.zeros(D + 2), np.zeros((D + 2, 2))
    s0, u, steps = 0.0, np.zeros(2), 0
    v = np.array(v, dtype=float)
    while s0 < span:
        L = span - s0
        taylor_shift(ax0, K, s0, ax)
        taylor_shift(ay0, K, s0, ay)
        De = pk.moving_series(ax, ay, K, v[0], v[1], np.hypot(*v), MUG, D, L, y, rho, w)
        assert De > 0
        H = pk._step_size(y, De, L) if De == D else L
        k = np.arange(De + 1)
        u += (y[: De + 1] * (H ** (k + 1) / (k + 1))[:, None]).sum(axis=0)
        v = (y[: De + 1] * (H**k)[:, None]).sum(axis=0)
        s0 += H
        steps += 1
        assert steps < max_steps
    return v, u, steps


@pytest.mark.parametrize("seed", range(6))
def test_slow_manifold_step_is_the_explicit_steps(seed):
    """A creeping block (|v| from 1e-9 to 1e-5 m/s, |a| from 1 to 1.05 mu g, the floor's
    acceleration changing at 3 m/s³) on its slow manifold (after explicit steps over 40
    relaxation times |v|/|a|): one slow-manifold step over 2 ms equals the 26 to 114 explicit
    steps over the same time to 1e-13 of v and of u (measured ≤ 1e-14), after a sideways move
    ≤ 2^-26 |v|."""
    rng = np.random.default_rng(seed)
    th = rng.uniform(0, 2 * np.pi)
    a0 = MUG * rng.uniform(1.0, 1.05) * np.array([np.cos(th), np.sin(th)])
    slope = 3.0 * rng.normal(size=2)
    r0 = 10.0 ** rng.uniform(-9, -5)
    t1 = 40 * r0 / MUG
    ax0, ay0 = np.array([a0[0], slope[0]]), np.array([a0[1], slope[1]])
    v1, _, _ = _explicit(ax0, ay0, -r0 * a0 / np.hypot(*a0), t1)
    ax1, ay1 = (
        np.array([a0[0] + slope[0] * t1, slope[0]]),
        np.array([a0[1] + slope[1] * t1, slope[1]]),
    )
    y, rho, sl = np.zeros((D + 2, 2)), np.zeros(D + 2), np.zeros((5, D + 2))
    span = 2e-3
    De, phi0 = pk.slow_series(ax1, ay1, 1, v1[0], v1[1], MUG, D, span, y, rho, sl)
    assert De == D and abs(phi0) <= pk.SLOW_TOL
    H = pk._step_size(y, D, span)
    assert H == span
    k = np.arange(D + 1)
    v_slow = (y[: D + 1] * (H**k)[:, None]).sum(axis=0)
    u_slow = (y[: D + 1] * (H ** (k + 1) / (k + 1))[:, None]).sum(axis=0)
    v_ref, u_ref, steps = _explicit(ax1, ay1, v1, span)
    assert steps >= 20
    assert np.hypot(*(v_slow - v_ref)) <= 1e-13 * np.hypot(*v_ref)
    assert np.hypot(*(u_slow - u_ref)) <= 1e-13 * np.hypot(*u_ref)


@pytest.mark.parametrize(("mu_k", "mu_s"), [(0.1, None), (0.2, None), (0.1, 0.15)])
def test_against_the_independent_reference_on_the_ground(mu_k, mu_s):
    """El Centro 1940 (x) and half of Rinaldi (y): slide_plane against the event-located SciPy
    reference at every sample, to 1e-8 of the peak (measured ≤ 2e-13), with the same stops."""
    ax, ay, dt = _pair()
    ref = _run_pair(mu_k) if mu_s is None else slide2d_reference(ax, ay, dt, mu_k, mu_s, rtol=1e-12)
    r = slide_plane((ax, ay), dt, mu_k, mu_s, histories=True, compare_1d=False)
    peak = ref["peak"]
    assert abs(r.peak_slide[0] - peak) <= 1e-8 * peak
    assert np.abs(r.u[0] - ref["u"]).max() <= 1e-8 * peak
    assert r.stops[0] == ref["stops"] and r.slip_phases[0] == ref["slips"]


@pytest.mark.slow
def test_against_the_independent_reference_on_a_floor():
    """The same pair under a 3-storey shear building (T = 0.4 s), on its roof: the reference
    integrates the building with the block (DOP853); to 1e-8 of the peak (measured 5e-13)."""
    ax, ay, dt = _pair()
    n = 2000
    b = fs.ShearBuilding.from_period(3, 0.4)
    A, B = b.state_matrices()
    C, Dm, _ = b.output_matrices([3], "acceleration")
    system = (A, B.ravel(), C[0], float(Dm[0, 0]))
    ref = slide2d_reference(ax[:n], ay[:n], dt, 0.2, floor_systems=(system, system))
    r = slide_plane((ax[:n], ay[:n]), dt, 0.2, building=b, floor=3, histories=True,
                    compare_1d=False)  # fmt: skip
    peak = ref["peak"]
    assert ref["stops"] >= 3
    assert abs(r.peak_slide[0] - peak) <= 1e-8 * peak
    assert np.abs(r.u[0] - ref["u"]).max() <= 1e-8 * peak
