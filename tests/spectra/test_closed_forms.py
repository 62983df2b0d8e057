"""Closed forms of the spectrum set-up against SciPy's expm and high-precision references."""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
import scipy.linalg

from floorslide.building.exact import spectral_radius, substeps_for
from floorslide.building.model import IsolatedBuilding, ShearBuilding
from floorslide.spectra._closed_forms import (
    _MARGIN,
    abs_damped_sinusoid_integral,
    coupled_recurrence,
    expm_recurrence,
    impulse_integrals,
)

PERIODS = np.geomspace(0.01, 10.0, 40)
DAMPING = (0.0, 0.02, 0.05, 0.2, 0.5, 0.99)
DTS = (0.001, 0.005, 0.01, 0.02, 0.05)


def _floor(building, floor):
    A, B = building.state_matrices()
    Ca, Da, _ = building.output_matrices([floor], "acceleration")
    return A, B[:, 0], Ca[0], float(np.ravel(Da[0])[0])


BUILDINGS = {
    "fixed roof": (ShearBuilding.from_period(1, 0.2, 0.05), 1),
    "isolated roof": (
        IsolatedBuilding(ShearBuilding.from_period(3, 0.4, 0.05), 1.0, 2.5, 0.10),
        3,
    ),
    "isolated base": (
        IsolatedBuilding(ShearBuilding.from_period(3, 0.4, 0.05), 1.0, 2.5, 0.10),
        0,
    ),
    "5-storey roof": (ShearBuilding.from_period(5, 0.6, 0.03), 5),
}


def _scaled(w, Pqq, Pqx, pq, qq):
    """The recurrence in the scaled state ``[ωq, q']`` (rows of one unit)."""
    S = Pqq.copy()
    S[:, 0, 1] *= w
    S[:, 1, 0] /= w
    X = Pqx.copy()
    X[:, 0] *= w[:, None]
    p, r = pq.copy(), qq.copy()
    p[:, 0] *= w
    r[:, 0] *= w
    return S, X, p, r


@pytest.mark.parametrize("name", list(BUILDINGS))
def test_coupled_recurrence_against_expm(name):
    """The series of the oscillator-on-a-floor step against SciPy's expm of the augmented
    first-order-hold matrix, on the periods 0.01–10 s, damping 0–0.99 and dt 0.001–0.05 s (on
    the building's own sub-steps, ρ(A)h ≤ 0.5, as the spectrum uses it): the oscillator block
    and the coupling to the building to 1e-14 of their norms. The input weights agree to 1e-11
    of the step's response to a constant ground acceleration (``p + r``) only: on the isolated
    roof that response starts at a high order in time and both computations cancel, and
    expm's own error there (~5e-12) is several times the series' (checked against a 34-digit
    expm in the next test); elsewhere they agree to ~1e-14."""
    building, floor = BUILDINGS[name]
    A, b, Ca, da = _floor(building, floor)
    rho = spectral_radius(A)
    for dt in DTS:
        h = dt / int(substeps_for(np.array([rho]), dt)[0])
        for xi in DAMPING:
            w = 2 * np.pi / PERIODS
            x = np.full(w.size, xi)
            got = _scaled(w, *coupled_recurrence(A, b, Ca, da, w, x, h))
            ref = _scaled(w, *expm_recurrence(A, b, Ca, da, w, x, h))
            for g, r in zip(got[:2], ref[:2], strict=True):
                err = np.abs(g - r).max(axis=(1, 2)) / np.abs(r).max(axis=(1, 2))
                # expm itself loses ~1e-13 once ωh passes a few units (periods < 2.5h: none
                # of these below dt = 0.02 s)
                tol = np.where(w * h < 2.5, 1e-14, 2e-12)
                assert np.all(err <= tol), (dt, xi, PERIODS[np.argmax(err / tol)], err.max())
            r0 = ref[2] + ref[3]
            scale = np.abs(r0).max(axis=1)
            for g, r in zip(got[2:], ref[2:], strict=True):
                err = np.abs(g - r).max(axis=1) / scale
                assert np.all(err <= 1e-11), (dt, xi, PERIODS[np.argmax(err)], err.max())


def _mp_recurrence(A, b, Ca, da, w, xi, h):
    """The recurrence from a 34-digit expm of the augmented matrix."""
    mp.mp.dps = 34
    n = A.shape[0]
    N = n + 2
    M = mp.zeros(N + 2, N + 2)
    for i in range(n):
        for j in range(n):
            M[i, j] = mp.mpf(float(A[i, j]))
        M[i, N] = mp.mpf(float(b[i]))
        M[n + 1, i] = -mp.mpf(float(Ca[i]))
    M[n, n + 1] = 1
    M[n + 1, n] = -(mp.mpf(w) ** 2)
    M[n + 1, n + 1] = -2 * mp.mpf(xi) * mp.mpf(w)
    M[n + 1, N] = -mp.mpf(da)
    M[N, N + 1] = 1
    hh = mp.mpf(h)
    E = mp.expm(M * hh)
    Pqq = np.array([[float(E[n + i, n + j]) for j in range(2)] for i in range(2)])
    Pqx = np.array([[float(E[n + i, j]) for j in range(n)] for i in range(2)])
    pq = np.array([float(E[n + i, N] - E[n + i, N + 1] / hh) for i in range(2)])
    qq = np.array([float(E[n + i, N + 1] / hh) for i in range(2)])
    return Pqq[None], Pqx[None], pq[None], qq[None]


@pytest.mark.parametrize(
    ("name", "dt", "T", "xi"),
    [
        ("isolated roof", 0.001, 0.1477, 0.05),
        ("isolated roof", 0.001, 0.01, 0.05),
        ("isolated roof", 0.01, 0.3, 0.0),
        ("fixed roof", 0.01, 0.2, 0.05),  # resonance with the building
        ("fixed roof", 0.02, 0.05, 0.99),
        ("5-storey roof", 0.005, 3.0, 0.02),
    ],
)
def test_coupled_recurrence_against_high_precision(name, dt, T, xi):
    """Each weight of the series recurrence against a 34-digit expm: the series is at least as
    accurate as SciPy's expm (which is off by up to ~5e-12 on the input weights of the
    isolated roof, whose floor acceleration starts at a high order in time)."""
    building, floor = BUILDINGS[name]
    A, b, Ca, da = _floor(building, floor)
    h = dt / int(substeps_for(np.array([spectral_radius(A)]), dt)[0])
    w = np.array([2 * np.pi / T])
    x = np.array([xi])
    ref = _scaled(w, *_mp_recurrence(A, b, Ca, da, w[0], xi, h))
    got = _scaled(w, *coupled_recurrence(A, b, Ca, da, w, x, h))
    old = _scaled(w, *expm_recurrence(A, b, Ca, da, w, x, h))
    for g, o, r in zip(got, old, ref, strict=True):
        err = np.abs(g - r).max() / np.abs(r).max()
        assert err <= max(2e-15, 2 * np.abs(o - r).max() / np.abs(r).max())


def _mp_abs_integral(a, b, P, Q, dt):
    mp.mp.dps = 30
    a, b, P, Q = (mp.mpf(float(v)) for v in (a, b, P, Q))
    phi = mp.atan2(P, Q)
    zeros = [(k * mp.pi - phi) / b for k in range(int(mp.floor(phi / mp.pi)) + 1, 400)]
    pts = [mp.mpf(0)] + [t for t in zeros if t < dt] + [mp.mpf(dt)]
    f = lambda t: mp.exp(-a * t) * (P * mp.cos(b * t) + Q * mp.sin(b * t))  # noqa: E731
    return float(sum(abs(mp.quad(f, [pts[j], pts[j + 1]])) for j in range(len(pts) - 1)))


@pytest.mark.parametrize("dt", [0.001, 0.01, 0.05])
@pytest.mark.parametrize("T_over_dt", [1 / 50, 1 / 7.3, 0.5, 0.9, 3.0, 50.0, 1e4])
@pytest.mark.parametrize("xi", [0.0, 0.05, 0.5, 0.99])
def test_impulse_integrals_against_quadrature(dt, T_over_dt, xi):
    """``∫₀^dt |h|``, ``∫|h'|``, ``∫|ω²h + 2ξωh'|`` in closed form against 30-digit quadrature
    between the zeros (whole half-periods summed as a geometric series, the end pieces stable
    when dt is a small fraction of the period), with their relative margin of 1e-9."""
    w = 2 * np.pi / (T_over_dt * dt)
    got = impulse_integrals(np.array([w]), np.array([xi]), dt)[:, 0]
    a = xi * w
    b = w * np.sqrt(1 - xi**2)
    rows = [(0.0, 1 / b), (1.0, -a / b), (2 * a, w**2 * (1 - 2 * xi**2) / b)]
    for g, (P, Q) in zip(got, rows, strict=True):
        ref = _mp_abs_integral(a, b, P, Q, dt)
        assert g >= ref
        assert g / _MARGIN == pytest.approx(ref, rel=1e-13)


def test_abs_integral_many_half_periods():
    """Thousands of half-periods in the interval (a period of dt/1000): the geometric sum
    against the sum of the half-periods one by one."""
    a, b, dt = 3.0, 2 * np.pi * 1000 / 0.01, 0.01
    got = abs_damped_sinusoid_integral(np.array([a]), np.array([b]), 0.3, 0.7, dt)[0]
    R, phi = np.hypot(0.3, 0.7), np.arctan2(0.3, 0.7)
    k = np.arange(int(np.floor(phi / np.pi)) + 1, int(np.ceil((b * dt + phi) / np.pi)))
    t = np.concatenate([[0.0], (k * np.pi - phi) / b, [dt]])
    F = -np.exp(-a * t) * (a * np.sin(b * t + phi) + b * np.cos(b * t + phi)) / (a * a + b * b)
    assert got / _MARGIN == pytest.approx(R * np.abs(np.diff(F)).sum(), rel=1e-12)


def test_spectrum_on_a_floor_does_not_call_expm(monkeypatch):
    """A floor spectrum's set-up (periods ≥ 2.5 record steps) needs no matrix exponential per
    oscillator: the closed forms and series replace it."""
    from floorslide.spectra import _closed_forms, core
    from floorslide.spectra.core import response_spectrum

    calls = []
    real = scipy.linalg.expm

    def counting(M):
        calls.append(np.shape(M))
        return real(M)

    monkeypatch.setattr(_closed_forms.scipy.linalg, "expm", counting)
    core._kernel_data.cache_clear()
    building, floor = BUILDINGS["fixed roof"]
    acc = np.sin(np.arange(400) * 0.05)
    response_spectrum(
        acc, 0.01, np.geomspace(0.03, 5.0, 20), (0.02, 0.05), building=building, floor=floor
    )
    assert all(len(s) == 2 for s in calls), calls  # only the building's own (n+2)-square ones
