"""Rocking blocks (fs.rock): closed forms of the linearised Housner block (docs/design.md §12).

Free rocking from θ0 (r = 1): ``θ(t) = α − (α − θ0) cosh(pt)`` until the impact, period
``T = (4/p) arccosh(1/(1 − θ0/α))``; a rectangular pulse of amplitude ``a_p`` and duration
``t_p`` overturns the block iff ``a_p/(gα) ≥ 1/(1 − exp(−p t_p))``; an impact keeps ``r²`` of
the kinetic energy; no uplift while ``|a_f| ≤ g tan α``; mirror symmetry.
"""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.constants import G
from floorslide.errors import ModelError

B, H = 0.25, 1.2
ALPHA = np.arctan(B / H)
P = np.sqrt(3 * G / (4 * 0.5 * np.hypot(B, H)))


def period(theta0: float) -> float:
    """Linearised free-rocking period from rest at θ0 with r = 1 (Housner 1963, eq. 11)."""
    return 4.0 / P * np.arccosh(1.0 / (1.0 - theta0 / ALPHA))


@pytest.mark.parametrize("method", ["exact"])
def test_free_rocking_follows_the_closed_form_and_its_period(method):
    theta0 = 0.4 * ALPHA
    T = period(theta0)
    n = 2000
    dt = 2 * T / n  # two periods, T a whole number of steps
    r = fs.rock(
        np.zeros(n + 1), dt, B, H, restitution=1.0, initial_angle=theta0, histories=True,
        method=method,
    )  # fmt: skip
    th = r.theta[0]
    t = np.arange(n + 1) * dt
    quarter = t <= T / 4
    expect = ALPHA - (ALPHA - theta0) * np.cosh(P * t[quarter])
    assert np.max(np.abs(th[quarter] - expect)) <= 1e-12 * ALPHA
    # a period later (and two) the block is back at θ0; half a period later at −θ0
    assert abs(th[n // 4] + theta0) <= 1e-11 * ALPHA
    assert abs(th[n // 2] - theta0) <= 1e-11 * ALPHA
    assert abs(th[n] - theta0) <= 1e-10 * ALPHA
    assert r.impacts[0] == 4
    assert r.peak_ratio[0] == pytest.approx(0.4, abs=1e-13)
    assert not r.overturned[0]


def test_an_impact_keeps_r_squared_of_the_energy():
    """After the first impact the next extreme θ1 satisfies the linearised energy balance
    ``α² − (α − |θ1|)² = r² (α² − (α − θ0)²)``; the record ends exactly there."""
    theta0, rr = 0.5 * ALPHA, 0.8
    theta1 = ALPHA - np.sqrt(ALPHA**2 - rr**2 * (ALPHA**2 - (ALPHA - theta0) ** 2))
    t1 = period(theta0) / 4 + period(theta1) / 4
    n = 1000
    r = fs.rock(np.zeros(n + 1), t1 / n, B, H, restitution=rr, initial_angle=theta0, histories=True)
    assert r.impacts[0] == 1
    assert abs(r.theta[0, -1] + theta1) <= 1e-11 * ALPHA


@pytest.mark.parametrize("p_tp", [0.5, 1.0, 2.0])
def test_rectangular_pulse_overturns_exactly_above_the_threshold(p_tp):
    """Linearised threshold ``a_p/(gα) = 1/(1 − exp(−p t_p))`` (p·t_p = 1: 1.581977) bracketed at
    ±0.1 %: the pulse is the record's samples at −a_p from t = dt to t_p (its one-sample
    onset ramp changes the threshold by far less than 0.1 %), then 30/p of zeros."""
    threshold = 1.0 / (1.0 - np.exp(-p_tp))
    if p_tp == 1.0:
        assert threshold == pytest.approx(1.581977, abs=1e-6)
    tp = p_tp / P
    dt = tp / 2000
    tail = int(30 / P / dt)
    for factor, overturns in ((1.001, True), (0.999, False)):
        ap = factor * threshold * G * ALPHA
        acc = np.concatenate([[0.0], np.full(2000, -ap), np.zeros(tail)])
        r = fs.rock(acc, dt, B, H)
        assert bool(r.overturned[0]) is overturns
        if overturns:
            assert r.mode == ("overturn",)
            assert r.peak_ratio[0] == 1.0
            assert r.overturn_time[0] > tp
        else:
            assert r.peak_ratio[0] < 1.0
            assert np.isnan(r.overturn_time[0])


@pytest.mark.parametrize("method", ["exact", "nonlinear"])
def test_no_uplift_below_g_tan_alpha(method):
    t = np.arange(0, 6, 0.005)
    acc = 0.9999 * G * np.tan(ALPHA) * np.sin(2 * np.pi * 1.3 * t)
    r = fs.rock(acc, 0.005, B, H, method=method, histories=True)
    assert r.mode == ("rest",)
    assert r.peak_ratio[0] == 0.0 and r.impacts[0] == 0 and r.rocking_time[0] == 0.0
    assert not np.any(r.theta)
    # just above it, it uplifts
    r = fs.rock(acc * 1.0002, 0.005, B, H, method=method)
    assert r.uplifts[0] >= 1 and r.mode == ("rock",)


@pytest.mark.parametrize("method", ["exact", "nonlinear"])
def test_mirror_symmetry(method):
    rng = np.random.default_rng(3)
    acc = np.convolve(rng.normal(size=3000), np.ones(25) / 25, mode="same") * 6.0
    widths, heights = [0.2, 0.3, 0.4], [1.0, 1.5, 1.1]
    a = fs.rock(acc, 0.01, widths, heights, method=method, histories=True)
    b = fs.rock(-acc, 0.01, widths, heights, method=method, histories=True)
    np.testing.assert_array_equal(a.theta, -b.theta)
    np.testing.assert_array_equal(a.peak_ratio, b.peak_ratio)
    np.testing.assert_array_equal(a.impacts, b.impacts)
    assert a.mode == b.mode
    assert any(m != "rest" for m in a.mode)


def test_bad_input_is_refused_with_the_key():
    acc = np.zeros(10)
    with pytest.raises(ModelError, match="width"):
        fs.rock(acc, 0.01, -0.2, 1.0)
    with pytest.raises(ModelError, match="restitution"):
        fs.rock(acc, 0.01, 0.2, 1.0, restitution=1.5)
    with pytest.raises(ModelError, match="method"):
        fs.rock(acc, 0.01, 0.2, 1.0, method="rk5")
    with pytest.raises(ModelError, match="initial_angle"):
        fs.rock(acc, 0.01, 0.2, 1.0, initial_angle=0.3)
    with pytest.raises(ModelError, match="restitution"):
        fs.rock(acc, 0.01, 2.0, 1.0)  # squat: Housner's r < 0


@pytest.mark.parametrize(("f0", "rr"), [(0.5, 0.9), (0.3, 0.7), (0.02, 0.95)])
def test_significant_impacts_leave_out_the_cascade_to_rest(f0, rr):
    """Free rocking from θ0 = f0·α (linearised): the k-th impact comes at
    ``|θ'| = r^(k−1)·p·α·√(f0(2 − f0))`` (energy conserved between impacts), so the impacts
    at or above ``p·α·√(f(2 − f))``, f = 0.01, number ``⌊ln(√(f(2−f))/√(f0(2−f0)))/ln r⌋ + 1``;
    all impacts run on to ``r^k·√(f0(2 − f0)) ≤ 10⁻¹²``: ``⌈ln(10⁻¹²/√(f0(2−f0)))/ln r⌉``."""
    w0 = np.sqrt(f0 * (2 - f0))
    x = np.log(np.sqrt(0.01 * 1.99) / w0) / np.log(rr)
    assert 0.05 < x % 1 < 0.95  # no impact near the threshold
    significant = int(np.floor(x)) + 1 if x >= 0 else 0
    total = int(np.ceil(np.log(1e-12 / w0) / np.log(rr)))
    r = fs.rock(np.zeros(3001), 0.01, B, H, restitution=rr, initial_angle=f0 * ALPHA)
    assert r.mode == ("rock",) and r.peak_ratio[0] == pytest.approx(f0, abs=1e-12)
    assert r.significant_impacts[0] == significant
    assert r.impacts[0] == total
    assert r.to_records()[0]["significant_impacts"] == significant
