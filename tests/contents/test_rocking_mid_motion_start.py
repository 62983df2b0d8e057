"""Rocking blocks on records that start mid-motion: the floor is already beyond the uplift level
``g tan α`` at t = 0.

The record ``[3 g, 0, 0, …]`` is 3 g at t = 0 falling linearly to 0 at t = dt: beyond the level
right at t = 0, so the block uplifts at t = 0 whatever dt — the same piecewise-linear function
sampled finer gives the same rocking. Checked against the closed form of the linearised block,
against the same function at finer dt, and against the independent event-located reference
(``tests/reference_rocking.py``).
"""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.constants import G
from tests.reference_rocking import rock_reference

B, H = 0.3, 1.8
A0 = 3.0 * G
DT = 0.01


def spike(dt: float = DT, fine: int = 1, seconds: float = 3.0) -> np.ndarray:
    """3 g at t = 0 falling linearly to 0 at t = ``dt``, then 0 — sampled at ``dt/fine`` (the
    same piecewise-linear function for every ``fine``)."""
    a = np.zeros(round(seconds / dt) * fine + 1)
    a[: fine + 1] = A0 * (1.0 - np.arange(fine + 1) / fine)
    return a


def linearised_peak_ratio() -> float:
    """Peak ``|θ|/α`` of the linearised block lifted at t = 0 onto corner ``s = −1`` by
    ``a_f = A0 (1 − t/dt)``: on ``[0, dt]`` ``θ'' − p²θ = p²(α − a_f/g)`` from rest gives
    ``θ = (A0/g − α)(1 − cosh pt) − A0 t/(g dt) + A0/(g dt p) sinh pt``; then free rocking
    ``θ + α = (θ1 + α) cosh p(t − dt) + (θ1'/p) sinh p(t − dt)``, whose extreme is
    ``θ + α = √((θ1 + α)² − (θ1'/p)²)`` (Housner 1963, eq. 8)."""
    alpha = np.arctan(B / H)
    p = np.sqrt(3 * G / (4 * 0.5 * np.hypot(B, H)))
    c1, c2 = alpha - A0 / G, A0 / (G * DT * p)
    th1 = -(alpha - A0 / G) - A0 / G + c1 * np.cosh(p * DT) + c2 * np.sinh(p * DT)
    w1 = -A0 / (G * DT) + c1 * p * np.sinh(p * DT) + c2 * p * np.cosh(p * DT)
    return float((alpha - np.sqrt((th1 + alpha) ** 2 - (w1 / p) ** 2)) / alpha)


def test_first_sample_beyond_the_uplift_level_lifts_at_once():
    expected = linearised_peak_ratio()
    assert expected == pytest.approx(0.0313008, abs=5e-8)
    for sign in (1.0, -1.0):
        r = fs.rock(sign * spike(), DT, B, H)
        assert r.mode == ("rock",)
        assert r.uplifts[0] == 1
        assert r.peak_ratio[0] == pytest.approx(expected, rel=1e-11)


@pytest.mark.parametrize("method", ["exact", "nonlinear"])
@pytest.mark.parametrize("fine", [4, 10])
def test_the_same_record_at_a_finer_dt_rocks_the_same(method, fine):
    coarse = fs.rock(spike(), DT, B, H, method=method, histories=True)
    finer = fs.rock(spike(fine=fine), DT / fine, B, H, method=method, histories=True)
    alpha = coarse.alpha[0]
    assert coarse.peak_ratio[0] > 0.03
    assert finer.peak_ratio[0] == pytest.approx(coarse.peak_ratio[0], rel=1e-10)
    assert finer.impacts[0] == coarse.impacts[0] and finer.uplifts[0] == coarse.uplifts[0] == 1
    assert finer.rocking_time[0] == pytest.approx(coarse.rocking_time[0], rel=1e-10)
    theta = finer.theta[0, ::fine][: coarse.theta.shape[1]]
    assert np.max(np.abs(theta - coarse.theta[0])) <= 1e-10 * alpha


@pytest.mark.parametrize("method", ["exact", "nonlinear"])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_start_beyond_the_level_against_the_reference(method, sign):
    acc = sign * spike(seconds=1.5)
    ref = rock_reference(
        acc, DT, width=B, height=H, method="linear" if method == "exact" else method
    )
    r = fs.rock(acc, DT, B, H, method=method, histories=True)
    assert ref["uplifts"] == 1 and ref["impacts"] > 5
    assert r.uplifts[0] == ref["uplifts"] and r.impacts[0] == ref["impacts"]
    assert np.max(np.abs(r.theta[0] - ref["theta"])) <= 1e-9 * r.alpha[0]
    assert abs(r.peak_ratio[0] - ref["peak_ratio"]) <= 1e-9


def test_approximate_methods_also_lift_at_once():
    exact = fs.rock(spike(), DT, B, H, method="nonlinear").peak_ratio[0]
    for method in ("rk4", "solve_ivp"):
        r = fs.rock(spike(), DT, B, H, method=method)
        assert r.uplifts[0] == 1
        assert r.peak_ratio[0] == pytest.approx(exact, rel=0.01)
