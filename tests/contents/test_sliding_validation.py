"""Rigid-block sliding against every sliding row of docs/design.md §7 (closed forms and published
values).

The solver is exact for the piecewise-linear record. A sampled smooth pulse differs from the pulse
by O(dt²), so the published values of smooth pulses are checked on the Richardson extrapolation
of two sample rates (error O(dt⁴) ≈ 1e-13 here): agreement to the digits published checks both
the exactness and the convergence order.
"""

from __future__ import annotations

import numpy as np
import pytest

from floorslide.constants import G
from floorslide.contents.sliding import slide


def pulse(kind: str, A: float, Tp: float, N: int, length: float = 30.0):
    """A half-sine or one-sine pulse sampled N times per Tp, then zeros (length in Tp)."""
    dt = Tp / N
    k = np.arange(int(length * N) + 1)
    t = k * dt
    w = np.pi / Tp if kind == "half" else 2 * np.pi / Tp
    return np.where(k <= N, A * np.sin(w * t), 0.0), dt


def normalized_peak(kind, eta, A=G, Tp=0.5, N=2000):
    def one(n):
        acc, dt = pulse(kind, A, Tp, n)
        return slide(acc, dt, eta * A / G).peak_slide[0] / (A * Tp**2)

    coarse, fine = one(N), one(2 * N)
    return (4 * fine - coarse) / 3, fine


def rectangular_exact(A, Tp, dt, mu_k, mu_s):
    """Closed form for the piecewise-linear rectangular pulse: A on [0, Tp − dt], a linear ramp to
    0 on [Tp − dt, Tp], then 0; the block breaks away at t = 0 (A > mu_s g)."""
    F = mu_k * G
    T1 = Tp - dt
    u1 = -(A - F) * T1**2 / 2
    v1 = -(A - F) * T1
    v2 = v1 + (-A + F) * dt + A * dt / 2
    u2 = u1 + v1 * dt + (-A + F) * dt**2 / 2 + A * dt**2 / 6
    return abs(u2 - v2**2 / (2 * F))


@pytest.mark.parametrize(
    ("A_g", "mu_k", "mu_s", "published"),
    [(0.5, 0.2, 0.2, 0.330974437), (0.5, 0.15, 0.3, 0.514849125)],
)
def test_rectangular_pulse_newmark_1965(A_g, mu_k, mu_s, published):
    A, Tp = A_g * G, 0.3
    # Newmark's formula reproduces the published value ...
    assert A * Tp**2 * (A - mu_k * G) / (2 * mu_k * G) == pytest.approx(published, abs=5e-10)
    for dt in (0.01, 0.001, 1e-4):
        n = round(Tp / dt)
        acc = np.zeros(n + round(5 / dt))
        acc[:n] = A
        got = slide(acc, dt, mu_k, mu_s).peak_slide[0]
        # ... the solver is exact for the sampled pulse at any dt ...
        assert got == pytest.approx(rectangular_exact(A, Tp, dt, mu_k, mu_s), rel=1e-12)
    # ... and tends to the published value as dt → 0 (the ramp costs O(dt/Tp))
    assert got == pytest.approx(published, rel=5e-4)


@pytest.mark.parametrize(
    ("eta", "published"),
    [
        (0.1, 1.71825014),
        (0.2, 0.71520037),
        (0.3, 0.38767822),
        (0.5, 0.13820786),
        (0.7, 0.04382955),
        (0.9, 0.00465421),
    ],
)
def test_half_sine_pulse(eta, published):
    value, fine = normalized_peak("half", eta)
    assert value == pytest.approx(published, abs=6e-9)
    assert abs(fine - value) < 1e-6 * value  # the O(dt²) term is small and was removed


@pytest.mark.parametrize(
    ("eta", "published"),
    [(0.1, 0.1205076), (0.2, 0.0908714), (0.3, 0.0669472), (0.5, 0.0320621), (0.7, 0.0109552)],
)
def test_one_sine_pulse(eta, published):
    value, _ = normalized_peak("one", eta)
    assert value == pytest.approx(published, abs=6e-8)


def test_makris_black_self_similarity():
    """u_max/(A Tp²) depends only on eta: (0.5 g, 0.2 s) and (2 g, 1.5 s) at eta = 0.3 give
    0.387678220557 (docs/design.md §7), even for the sampled pulses (same samples per Tp)."""
    a, _ = normalized_peak("half", 0.3, A=0.5 * G, Tp=0.2)
    b, _ = normalized_peak("half", 0.3, A=2 * G, Tp=1.5)
    assert a == pytest.approx(b, rel=1e-12)
    assert a == pytest.approx(0.387678220557, abs=2e-12)


def ground_kinematics(acc, dt):
    """Exact velocity and displacement of the piecewise-linear record at the samples."""
    s = np.diff(acc) / dt
    dv = acc[:-1] * dt + s * dt**2 / 2
    v = np.concatenate([[0.0], np.cumsum(dv)])
    dd = v[:-1] * dt + acc[:-1] * dt**2 / 2 + s * dt**3 / 6
    return v, np.concatenate([[0.0], np.cumsum(dd)])


def test_frictionless_limit(elcentro):
    """mu → 0: the object stays put in space, u(t) = −(floor displacement), acceleration 0."""
    acc, dt = elcentro
    acc = acc[:2000]
    res = slide(acc, dt, [0.0], histories=True)
    v, d = ground_kinematics(acc, dt)
    scale = np.abs(d).max()
    np.testing.assert_allclose(res.u[0], -d, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(res.v[0], -v, rtol=0, atol=1e-12 * np.abs(v).max())
    # the true peak of the cubic displacement, inside steps where the velocity vanishes
    s = np.diff(acc) / dt
    peak = scale
    for k in range(acc.size - 1):
        for tau in np.roots([s[k] / 2, acc[k], v[k]]):
            if abs(tau.imag) < 1e-300 and 0 < tau.real < dt:
                tau = tau.real
                dk = d[k] + v[k] * tau + acc[k] * tau**2 / 2 + s[k] * tau**3 / 6
                peak = max(peak, abs(dk))
    assert peak > scale
    assert res.peak_slide[0] == pytest.approx(peak, rel=1e-12)
    np.testing.assert_array_equal(res.abs_accel[0, 1:], 0.0)


def test_no_slide_below_breakaway(elcentro):
    """mu_s·g above the peak floor acceleration: no slide; object acceleration = floor's."""
    acc, dt = elcentro
    pga = np.abs(acc).max()
    res = slide(acc, dt, mu_k=0.1, mu_s=pga / G * 1.0000001, histories=True)
    assert res.peak_slide[0] == 0.0 and res.residual_slide[0] == 0.0
    assert res.slip_phases[0] == 0
    assert res.peak_abs_accel[0] == pga
    np.testing.assert_array_equal(res.abs_accel[0], acc)


def steady_half_range(eta, cycles=40, per_cycle=4000):
    """Half peak-to-peak slide over the last cycle under a0 sin ωt, in units a0/ω²; and whether
    the block stuck during the last cycles."""
    a0, w = 0.3 * G, 2 * np.pi * 2.0  # mu·g is a0 to the last bit at eta = 1
    T = 2 * np.pi / w
    dt = T / per_cycle
    t = np.arange(cycles * per_cycle + 1) * dt
    res = slide(a0 * np.sin(w * t), dt, eta * 0.3, histories=True)
    last = slice(-per_cycle - 1, None)
    u = res.u[0, last]
    stuck = np.count_nonzero(res.v[0, -5 * per_cycle :] == 0.0)
    return 0.5 * (u.max() - u.min()) / (a0 / w**2), stuck


@pytest.mark.parametrize("eta", [0.2, 0.4, 0.5, 0.53])
def test_westermo_udwadia_slip_slip(eta):
    """eta ≤ 1/√(1 + π²/4) = 0.537029: steady slip–slip, half range √(1 − (π eta/2)²) a0/ω².
    dt = T/4000: the sampled sine's fundamental differs by (ωdt)²/12 ≈ 2e-7."""
    assert 1 / np.sqrt(1 + np.pi**2 / 4) == pytest.approx(0.537029, abs=5e-7)
    half, stuck = steady_half_range(eta)
    assert stuck == 0
    assert half == pytest.approx(np.sqrt(1 - (np.pi * eta / 2) ** 2), rel=2e-6)


@pytest.mark.parametrize(
    ("eta", "published"),
    [(0.55, 0.505566), (0.6, 0.394186), (0.7, 0.216247), (0.8, 0.093897), (0.9, 0.022968)],
)
def test_westermo_udwadia_stick_slip(eta, published):
    half, stuck = steady_half_range(eta)
    assert stuck > 0
    assert half == pytest.approx(published, abs=2e-6)


@pytest.mark.parametrize("eta", [1.0, 1.5])
def test_westermo_udwadia_no_slip(eta):
    half, _ = steady_half_range(eta, cycles=3)
    assert half == 0.0
