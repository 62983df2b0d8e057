"""The rocking reference of ``tests/reference_rocking.py`` against closed forms, so that it can be
trusted to validate floorslide's rocking solver: the free-rocking period (linearised, and by
quadrature for Housner's equation), the rectangular-pulse overturning threshold, the rest rule,
mirror symmetry, the energy lost per impact, and the building floor path."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from tests.conftest import load_slammer
from tests.reference import linear_response
from tests.reference_rocking import (
    free_rocking_period,
    pulse_overturn_threshold,
    rock_reference,
)

G = 9.80665
W, H = 0.5, 2.0  # a slender block: alpha = atan(0.25) ≈ 0.245 rad, p ≈ 2.67 rad/s
ALPHA = float(np.arctan2(W, H))
P = float(np.sqrt(3.0 * G / (4.0 * np.hypot(W / 2, H / 2))))


def test_parameters_and_closed_forms():
    res = rock_reference(np.zeros(3), 0.01, width=W, height=H)
    assert res["alpha"] == pytest.approx(ALPHA, rel=1e-15)
    assert res["p"] == pytest.approx(P, rel=1e-15)
    assert res["r"] == pytest.approx(1.0 - 1.5 * np.sin(ALPHA) ** 2, rel=1e-15)
    assert res["peak_ratio"] == 0.0 and res["impacts"] == 0 and res["uplifts"] == 0
    # the design value: p t_p = 1 → a_p / (g alpha) = 1.581977
    assert abs(pulse_overturn_threshold(1.0) - 1.581977) <= 1e-6
    # θ(t) = alpha - (alpha - θ0) cosh(p t) reaches 0 at a quarter period
    theta0 = 0.3 * ALPHA
    quarter = free_rocking_period(theta0, ALPHA, P) / 4
    assert ALPHA - (ALPHA - theta0) * np.cosh(P * quarter) == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize("method", ["linear", "nonlinear"])
def test_free_rocking_period(method):
    """r = 1, no floor motion, released at 0.3 alpha: periodic; the impacts on the same side are
    a period apart, the extremes are ±θ0. Linearised: the arccosh closed form; Housner's
    equation: its quarter period by quadrature of the energy integral."""
    theta0 = 0.3 * ALPHA
    if method == "linear":
        period = free_rocking_period(theta0, ALPHA, P)
    else:
        # ½ θ'² = p² [cos(alpha - θ0) - cos(alpha - θ)], θ = θ0 (1 - v²): a smooth integrand
        def f(v):
            x = theta0 * v * v / 2
            d = np.sin(ALPHA - theta0 + x) * theta0 / 2 * np.sinc(x / np.pi)
            return theta0 / (P * np.sqrt(d))

        period = 4 * quad(f, 0.0, 1.0, epsabs=0.0, epsrel=1e-13)[0]
    dt = 0.01
    n = int(3.2 * period / dt) + 2
    res = rock_reference(
        np.zeros(n), dt, width=W, height=H, restitution=1.0, method=method, theta0=theta0
    )
    ti = res["impact_log"][:, 0]
    assert res["impacts"] >= 6 and not res["overturned"] and res["uplifts"] == 0
    assert abs(ti[0] / (period / 4) - 1) <= 1e-9
    for k in range(ti.size - 2):
        assert abs((ti[k + 2] - ti[k]) / period - 1) <= 1e-9
        assert abs((ti[k + 1] - ti[k]) / (period / 2) - 1) <= 1e-9
    ext = res["extrema"]
    assert ext.shape[0] >= 5
    assert np.allclose(np.abs(ext[:, 1]), theta0, rtol=1e-11, atol=0)
    assert np.all(np.sign(ext[:, 1]) == (-1.0) ** (np.arange(ext.shape[0]) + 1))
    assert abs(res["peak_ratio"] - 0.3) <= 1e-11
    assert res["rocking_time"] == pytest.approx((n - 1) * dt, rel=1e-14)


def pulse(p_tp, factor, pdt=0.005, length=30.0):
    """Floor acceleration -a_p from t = 0 to t_p, then 0, a_p = factor × threshold × g alpha.

    A piecewise-linear record cannot be rectangular: the first sample is already -a_p (the
    block uplifts at t = 0) and the fall to 0 is one sample long, centred on t_p (samples at
    t_p ± dt/2), so that the impulse is exact and the error is second order, ~(p dt)²: with
    p dt = 0.005 the overturning threshold moves by 1.6e-6 relative (p t_p = 0.5, the worst;
    measured by bisection), far inside the ±1e-3 tested.
    """
    t_p = p_tp / P
    m = int(np.ceil(p_tp / pdt))
    dt = t_p / (m + 0.5)
    acc = np.zeros(int(np.ceil((t_p + length / P) / dt)) + 1)
    acc[: m + 1] = -factor * pulse_overturn_threshold(p_tp) * G * ALPHA
    return acc, dt


@pytest.mark.parametrize("p_tp", [0.5, 1.0, 2.0])
def test_pulse_overturning_threshold(p_tp):
    acc, dt = pulse(p_tp, 1.001)
    over = rock_reference(acc, dt, width=W, height=H)
    assert over["overturned"] and over["peak_ratio"] == 1.0
    assert over["uplifts"] == 1 and over["impacts"] == 0
    k = int(over["t_overturn"] / dt)
    assert np.isfinite(over["theta"][: k + 1]).all() and np.isnan(over["theta"][k + 1 :]).all()
    assert over["rocking_time"] == pytest.approx(over["t_overturn"], rel=1e-14)

    acc, dt = pulse(p_tp, 0.999)
    safe = rock_reference(acc, dt, width=W, height=H)
    assert not safe["overturned"] and np.isnan(safe["t_overturn"])
    assert 0.9 < safe["peak_ratio"] < 1.0
    # it falls back, rocks, and comes to rest (a finite chattering sequence of impacts)
    assert safe["impacts"] >= 2 and safe["uplifts"] == 1
    rest = [t for t, kind in safe["events"] if kind == "rest"]
    assert len(rest) <= 1
    end = rest[0] if rest else (acc.size - 1) * dt
    assert safe["rocking_time"] == pytest.approx(end, rel=1e-13)


def test_pulse_threshold_tight():
    """p t_p = 1 at ±1e-4 of the threshold (the ramp moves it by ~1e-6)."""
    assert rock_reference(*pulse(1.0, 1.0001), width=W, height=H)["overturned"]
    assert not rock_reference(*pulse(1.0, 0.9999), width=W, height=H)["overturned"]


@pytest.mark.parametrize("method", ["linear", "nonlinear"])
@pytest.mark.parametrize("building", [False, True])
def test_no_uplift_below_threshold(method, building):
    dt = 0.01
    t = np.arange(0.0, 2.0, dt)
    acc = 0.999 * G * np.tan(ALPHA) * np.sin(2 * np.pi * 1.3 * t + 0.4)
    # a "building" whose floor is the ground itself: the rest events go through solve_ivp
    system = ([[-1.0]], [1.0], [0.0], 1.0) if building else None
    res = rock_reference(acc, dt, width=W, height=H, method=method, floor_system=system)
    assert res["peak_ratio"] == 0 and res["impacts"] == 0 and res["uplifts"] == 0
    assert res["rocking_time"] == 0.0 and not res["overturned"]
    assert np.all(res["theta"] == 0.0) and np.all(res["theta_dot"] == 0.0)
    # just above: it uplifts
    res = rock_reference(acc * 1.002 / 0.999, dt, width=W, height=H, method=method)
    assert res["uplifts"] >= 1 and res["peak_ratio"] > 0.0


@pytest.mark.parametrize("method", ["linear", "nonlinear"])
@pytest.mark.parametrize("building", [False, True])
def test_touching_the_threshold_at_samples(method, building):
    """A triangle wave whose peaks are exactly ±g tan(alpha) at samples: |a_f| ≤ g tan(alpha)
    throughout, so the block stays at rest (the rest rule is ``≤``)."""
    thr = G * np.tan(ALPHA)
    acc = np.tile(thr * np.array([0.0, 0.5, 1.0, 0.5, 0.0, -0.5, -1.0, -0.5]), 3)
    system = ([[-1.0]], [1.0], [0.0], 1.0) if building else None
    res = rock_reference(acc, 0.01, width=W, height=H, method=method, floor_system=system)
    assert res["uplifts"] == 0 and res["impacts"] == 0 and res["peak_ratio"] == 0.0
    assert np.all(res["theta"] == 0.0)
    # beyond by 1e-12 relative: an uplift at every peak (the threshold is sharp)
    res = rock_reference(
        acc * (1 + 1e-12), 0.01, width=W, height=H, method=method, floor_system=system
    )
    assert res["uplifts"] >= 6 and res["peak_ratio"] > 0.0 and not res["overturned"]


@pytest.mark.parametrize("method", ["linear", "nonlinear"])
@pytest.mark.parametrize(("width", "height", "scale"), [(0.6, 1.2, 2.5), (0.5, 2.0, 1.2)])
def test_mirror_symmetry(method, width, height, scale):
    """Negating the record mirrors θ (El Centro, 15 s: several uplifts, chattering rests)."""
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    acc = scale * acc[:1500]
    a = rock_reference(acc, dt, width=width, height=height, method=method)
    b = rock_reference(-acc, dt, width=width, height=height, method=method)
    assert a["uplifts"] >= 1 and a["impacts"] >= 10 and not a["overturned"]
    assert np.max(np.abs(a["theta"] + b["theta"])) <= 1e-12 * a["alpha"]
    assert np.max(np.abs(a["theta_dot"] + b["theta_dot"])) <= 1e-12 * a["alpha"] * a["p"]
    for key in ("impacts", "uplifts", "overturned"):
        assert a[key] == b[key]
    assert a["peak_ratio"] == pytest.approx(b["peak_ratio"], rel=1e-12)
    assert a["rocking_time"] == pytest.approx(b["rocking_time"], rel=1e-12)


@pytest.mark.parametrize("method", ["linear", "nonlinear"])
def test_energy_per_impact(method):
    """Released at 0.5 alpha with r = 0.8: the impact velocity from energy conservation, the
    kinetic-energy ratio r² across the impact, and the amplitude on the other side."""
    theta0, r = 0.5 * ALPHA, 0.8
    res = rock_reference(
        np.zeros(201), 0.01, width=W, height=H, restitution=r, method=method, theta0=theta0
    )
    t1, before, after = res["impact_log"][0]
    assert (after / before) ** 2 == pytest.approx(r * r, rel=1e-12)
    assert before < 0.0 and after < 0.0
    if method == "linear":  # ½θ'² - ½p²(θ - alpha)² conserved
        v2 = P * P * (ALPHA**2 - (ALPHA - theta0) ** 2)
        assert t1 == pytest.approx(free_rocking_period(theta0, ALPHA, P) / 4, rel=1e-10)
    else:  # ½θ'² + p² cos(alpha - θ) conserved
        v2 = 2 * P * P * (np.cos(ALPHA - theta0) - np.cos(ALPHA))
    assert before**2 == pytest.approx(v2, rel=1e-11)
    # the next extreme, on the other side, from the energy left: r² v2
    theta1 = -res["extrema"][0, 1]
    assert res["extrema"][0, 0] > t1 and theta1 > 0
    if method == "linear":
        assert ALPHA**2 - (ALPHA - theta1) ** 2 == pytest.approx(r * r * v2 / P**2, rel=1e-11)
    else:
        lhs = 2 * P * P * (np.cos(ALPHA - theta1) - np.cos(ALPHA))
        assert lhs == pytest.approx(r * r * v2, rel=1e-11)


def test_zero_restitution_and_event_cap():
    """r = 0: the block comes to rest at its first impact; a low event cap raises."""
    res = rock_reference(
        np.zeros(101), 0.01, width=W, height=H, restitution=0.0, theta0=0.5 * ALPHA
    )
    assert res["impacts"] == 1 and [k for _, k in res["events"]] == ["impact", "rest"]
    assert res["theta"][-1] == 0.0 and res["theta_dot"][-1] == 0.0
    assert res["rocking_time"] == pytest.approx(res["impact_log"][0, 0], rel=1e-14)
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    with pytest.raises(RuntimeError, match="more than 20 events"):
        rock_reference(acc[:1500], dt, width=W, height=H, max_events=20)


W_F, H_F = 0.8, 2.0  # rocks on the SDOF floor without overturning


def sdof_floor():
    w, xi = 2 * np.pi / 0.5, 0.05
    A = np.array([[0.0, 1.0], [-w * w, -2 * xi * w]])
    b = np.array([0.0, -1.0])
    c = np.array([-w * w, -2 * xi * w])  # absolute acceleration of the SDOF
    dt = 0.01
    t = np.arange(301) * dt  # 3 s of a 1 Hz sine, 3 m/s²
    return (A, b, c, 0.0), 3.0 * np.sin(2 * np.pi * t), dt


@pytest.mark.parametrize("method", ["linear", "nonlinear"])
def test_floor_system(method):
    system, acc, dt = sdof_floor()
    fine = rock_reference(acc, dt, width=W_F, height=H_F, method=method, floor_system=system)
    loose = rock_reference(
        acc, dt, width=W_F, height=H_F, method=method, floor_system=system, rtol=1e-11
    )
    assert fine["uplifts"] >= 1 and fine["impacts"] >= 2 and not fine["overturned"]
    assert 0.05 < fine["peak_ratio"] < 1.0
    assert abs(fine["peak_ratio"] - loose["peak_ratio"]) <= 1e-8
    assert np.max(np.abs(fine["theta"] - loose["theta"])) <= 1e-8 * fine["alpha"]
    # the uplift instant: the floor acceleration (from tests/reference.py's linear response)
    # is at ±g tan(alpha) there
    thr = G * np.tan(fine["alpha"])
    _, sols = linear_response(system[0], system[1], acc, dt, dense=True)
    for t_up in [t for t, kind in fine["events"] if kind == "uplift"]:
        k = int(t_up / dt)
        af = system[2] @ sols[k](t_up - k * dt)
        assert abs(abs(af) - thr) <= 1e-9 * thr
    # a "building" whose floor is the ground (c = 0, d = 1) gives the ground result
    acc = 1.5 * acc
    ground = rock_reference(acc, dt, width=W_F, height=H_F, method=method)
    same = rock_reference(
        acc, dt, width=W_F, height=H_F, method=method, floor_system=([[-1.0]], [1.0], [0.0], 1.0)
    )
    assert ground["uplifts"] >= 1 and ground["impacts"] >= 2
    assert np.max(np.abs(ground["theta"] - same["theta"])) <= 1e-12 * ground["alpha"]
    assert ground["impacts"] == same["impacts"] and ground["uplifts"] == same["uplifts"]
