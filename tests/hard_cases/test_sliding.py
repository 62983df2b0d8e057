"""docs/design.md §8 hard cases for the rigid-block solver: finite, stable and still right."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from floorslide.building.model import ShearBuilding
from floorslide.constants import G
from floorslide.contents.sliding import slide
from floorslide.errors import ModelError


def reference(acc, dt, mu_k, mu_s=None, **kw):
    return slide(acc, dt, mu_k, mu_s, method="solve_ivp", rtol=1e-12, max_step=dt / 16, **kw)


def test_stick_slip_chatter():
    """A Nyquist-rate record just above mu·g: the block breaks away, stops and sticks inside
    every step — hundreds of events in consecutive steps — and still matches the reference."""
    dt, mu = 0.01, 0.2
    k = np.arange(400)
    acc = 1.05 * mu * G * (-1.0) ** k * (1 + 0.1 * np.sin(0.05 * k))
    res = slide(acc, dt, mu, histories=True)
    assert res.slip_phases[0] > 250
    ref = reference(acc, dt, mu)
    assert res.peak_slide[0] == pytest.approx(ref.peak_slide[0], rel=1e-8)
    assert res.residual_slide[0] == pytest.approx(
        ref.residual_slide[0], abs=1e-8 * ref.peak_slide[0]
    )
    assert np.all(np.isfinite(res.u))


def test_input_exactly_at_breakaway():
    """|a_f| = mu_s·g exactly is not enough to start sliding (strict inequality)."""
    mu_s = 0.3
    acc = np.concatenate([np.linspace(0, mu_s * G, 50), np.full(200, mu_s * G), np.zeros(10)])
    acc[50:250] = mu_s * G
    res = slide(np.concatenate([acc, -acc]), 0.01, 0.1, mu_s)
    assert res.peak_slide[0] == 0.0 and res.slip_phases[0] == 0
    assert res.peak_abs_accel[0] == mu_s * G


@pytest.mark.parametrize(("mu_k", "mu_s"), [(0.1, 0.2), (0.15, 0.12)])
def test_static_and_kinetic_friction_in_either_order(mu_k, mu_s, elcentro):
    acc, dt = elcentro
    acc = acc[:1500]
    res = slide(acc, dt, mu_k, mu_s)
    ref = reference(acc, dt, mu_k, mu_s)
    assert res.peak_slide[0] > 1e-3
    assert res.peak_slide[0] == pytest.approx(ref.peak_slide[0], rel=1e-8)
    if mu_s < mu_k:  # breakaway effectively at mu_k: identical to mu_s = mu_k
        same = slide(acc, dt, mu_k, mu_k)
        assert res.peak_slide[0] == same.peak_slide[0]
        assert res.residual_slide[0] == same.residual_slide[0]


def test_friction_from_1e_4_to_2(elcentro):
    acc, dt = elcentro
    mus = np.logspace(-4, np.log10(2.0), 25)
    res = slide(acc, dt, mus, histories=True)
    for arr in (res.peak_slide, res.residual_slide, res.peak_abs_accel, res.u, res.v):
        assert np.all(np.isfinite(arr))
    assert res.peak_slide[-1] == 0.0  # 2 g is above the PGA (0.31 g)
    # tiny friction: close to the frictionless motion −d(t), |Δu| ≤ mu g t²/2 over the record
    free = slide(acc, dt, 0.0, histories=True)
    T = (acc.size - 1) * dt
    assert np.abs(res.u[0] - free.u[0]).max() <= 1e-4 * G * T**2 / 2
    # the object's absolute acceleration never exceeds max(mu_s, mu_k)·g once it slides
    slid = res.slip_phases > 0
    assert np.all(res.peak_abs_accel[slid] <= mus[slid] * G * (1 + 1e-12))
    sliding = res.v != 0.0
    assert np.all(
        np.abs(res.abs_accel[sliding]) <= (mus[:, None] * G * (1 + 1e-12) * sliding)[sliding]
    )


def test_many_objects_in_one_call_equal_single_calls(elcentro):
    acc, dt = elcentro
    mus = [0.05, 0.1, 0.2]
    many = slide(acc, dt, mus, [0.07, 0.1, 0.25])
    for i, (mk, ms) in enumerate(zip(mus, [0.07, 0.1, 0.25], strict=True)):
        one = slide(acc, dt, mk, ms)
        assert one.peak_slide[0] == many.peak_slide[i]
        assert one.residual_slide[0] == many.residual_slide[i]


def test_stiff_building_coarse_dt(coarse_record):
    """T = 0.01 s under dt = 0.02 s: 26 exact sub-steps per step, still the reference answer."""
    acc, dt = coarse_record
    acc = acc[150:450]
    b = ShearBuilding.from_period(1, 0.01, 0.05)
    res = slide(acc, dt, [0.1, 0.3], building=b, floor=1)
    ref = reference(acc, dt, [0.1, 0.3], building=b, floor=1)
    assert np.all(res.peak_slide > 1e-3)
    np.testing.assert_allclose(res.peak_slide, ref.peak_slide, rtol=1e-8)


def test_million_sample_record_bounded_memory_and_no_drift():
    """10⁶ samples of a 2 Hz sine (dt = 1 ms) in steady slip–slip: the steady half range after
    1000 s is the closed form (Westermo & Udwadia 1983) and memory stays O(1) without histories."""
    n, dt, f, eta = 1_000_000, 0.001, 2.0, 0.4
    w = 2 * np.pi * f
    a0 = 0.5 * G
    acc = a0 * np.sin(w * np.arange(n) * dt)
    slide(acc[:100], dt, eta * 0.5)  # compile outside the measurement
    tracemalloc.start()
    full = slide(acc, dt, eta * 0.5)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 1e5  # the record itself is 8 MB
    res = slide(acc, dt, eta * 0.5, histories=True)
    assert res.residual_slide[0] == full.residual_slide[0]
    assert np.isfinite(full.peak_slide[0]) and np.isfinite(full.residual_slide[0])
    per = int(1 / f / dt)
    half = 0.5 * np.ptp(res.u[0, -per - 1 :]) / (a0 / w**2)
    # dt = T/500: the sampled sine's fundamental is lower by (ωdt)²/12 ≈ 1.3e-5
    assert half == pytest.approx(np.sqrt(1 - (np.pi * eta / 2) ** 2), rel=5e-5)
    early = res.u[0, 100 * per : 101 * per] - res.u[0, 100 * per : 101 * per].mean()
    k0 = per * ((n - 1) // per - 1)
    late = res.u[0, k0 : k0 + per] - res.u[0, k0 : k0 + per].mean()
    np.testing.assert_allclose(late, early, rtol=0, atol=1e-9 * a0 / w**2)
    # slip–slip is a limit cycle around a drifting centre only through the start: the residual
    # stays within one half range of the first cycles' centre
    assert abs(full.residual_slide[0]) < 2 * a0 / w**2


def test_vertical_constant_equals_scaled_gravity(elcentro):
    """A constant vertical acceleration c is gravity g + c: identical to mu·(g + c)/g."""
    acc, dt = elcentro
    c = 0.3 * G
    with_v = slide(acc, dt, [0.1, 0.2], vertical=np.full(acc.size, c))
    scaled = slide(acc, dt, np.array([0.1, 0.2]) * (G + c) / G)
    np.testing.assert_allclose(with_v.peak_slide, scaled.peak_slide, rtol=1e-12)
    assert with_v.liftoff_time == 0.0


def test_liftoff_is_reported():
    dt = 0.01
    t = np.arange(300) * dt
    acc = 0.3 * G * np.sin(2 * np.pi * t)
    vert = np.where((t > 1.0) & (t < 1.5), -1.5 * G, 0.0)
    res = slide(acc, dt, 0.2, vertical=vert)
    assert res.liftoff_count == 1
    # g + a_v crosses 0 two thirds into the step down to −1.5 g and one third into the step up
    assert res.liftoff_time == pytest.approx((1.49 + dt / 3) - (1.0 + 2 * dt / 3), rel=1e-9)
    assert np.isfinite(res.peak_slide[0]) and res.peak_slide[0] > 0


@pytest.mark.parametrize(
    "bad",
    [
        dict(mu_k=-0.1),
        dict(mu_k=[]),
        dict(mu_k=np.nan),
        dict(mu_k=[0.1, 0.2], mu_s=[0.1, 0.2, 0.3]),
        dict(mu_k=0.1, direction="up"),
        dict(mu_k=0.1, method="euler"),
        dict(mu_k=0.1, vertical=np.zeros(3)),
        dict(mu_k=0.1, floor=2),
    ],
)
def test_bad_arguments_give_clear_errors(bad):
    with pytest.raises(ModelError):
        slide(np.zeros(10), 0.01, **bad)
