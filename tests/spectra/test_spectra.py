"""Response spectra and floor response spectra against closed forms and a reference."""

from __future__ import annotations

import numpy as np
import pytest

from floorslide.building.model import IsolatedBuilding, ShearBuilding
from floorslide.building.motions import peak_floor_acceleration
from floorslide.contents.oscillator import slide_oscillator
from floorslide.errors import ModelError
from floorslide.spectra import broaden, envelope, period_grid, response_spectrum
from tests.reference import linear_peaks


@pytest.mark.parametrize("dt", [0.001, 0.01, 0.05, 0.3, 1.0])
def test_step_input_any_dt(dt):
    """A step a0 from t = 0: PSA/a0 = 1 + exp(−πξ/√(1−ξ²)) = 1.854468 at 5 % for any dt, which
    needs the peaks inside steps (the first peak is at T_d/2, generally between samples)."""
    a0 = 2.5
    acc = np.full(int(np.ceil(12 / dt)) + 1, a0)
    T = np.array([0.37, 1.0, 2.3])
    sp = response_spectrum(acc, dt, T, 0.05)
    expected = 1 + np.exp(-np.pi * 0.05 / np.sqrt(1 - 0.05**2))
    assert expected == pytest.approx(1.854468, abs=5e-7)
    np.testing.assert_allclose(sp.psa[0] / a0, expected, rtol=1e-12)
    sp10 = response_spectrum(acc, dt, T, [0.1])
    np.testing.assert_allclose(
        sp10.psa[0] / a0, 1 + np.exp(-np.pi * 0.1 / np.sqrt(1 - 0.01)), rtol=1e-12
    )


@pytest.mark.parametrize("xi", [0.05, 0.2])
def test_harmonic_resonance_closed_form(xi):
    """a0 sin ωt at resonance from rest: the amplitude grows monotonically to the steady
    (a0/ω²)/(2ξ); SA → a0√(1+4ξ²)/(2ξ). dt = T/1000 (the sampled sine's fundamental is low by
    (ωdt)²/12 = 3.3e-6)."""
    T, a0 = 0.5, 1.3
    w = 2 * np.pi / T
    dt = T / 1000
    t = np.arange(int(25 / (xi * w) / dt) + 1) * dt
    sp = response_spectrum(a0 * np.sin(w * t), dt, [T], xi)
    U = a0 / w**2 / (2 * xi)
    assert sp.sd[0, 0] == pytest.approx(U, rel=1e-5)
    assert sp.sv[0, 0] == pytest.approx(U * w, rel=1e-5)
    assert sp.sa[0, 0] == pytest.approx(a0 * np.sqrt(1 + 4 * xi**2) / (2 * xi), rel=1e-5)


def test_pseudo_values_and_zero_period(elcentro):
    acc, dt = elcentro
    T = np.array([0.0, 0.05, 0.3, 1.0, 4.0])
    sp = response_spectrum(acc, dt, T, [0.02, 0.05])
    w = np.where(T > 0, 2 * np.pi / np.where(T > 0, T, 1), 0)
    np.testing.assert_allclose(sp.psa[:, 1:], sp.sd[:, 1:] * w[1:] ** 2, rtol=1e-14)
    np.testing.assert_allclose(sp.psv, sp.sd * w, rtol=1e-14)
    pga = np.abs(acc).max()
    assert np.all(sp.psa[:, 0] == pga) and np.all(sp.sa[:, 0] == pga)
    assert np.all(sp.sd[:, 0] == 0)
    # SA ≠ PSA with damping; SA ≥ PSA·... they differ by the damping force
    assert not np.allclose(sp.sa[:, 1:], sp.psa[:, 1:], rtol=1e-3)


def test_short_periods_tend_to_the_true_peak(coarse_record):
    """PSA → PGA as T → 0 on the ground; on a floor → the true PFA (inside steps)."""
    acc, dt = coarse_record
    sp = response_spectrum(acc, dt, [0.004, 0.002], 0.05)
    pga = np.abs(acc).max()
    np.testing.assert_allclose(sp.psa[0], pga, rtol=2e-3)
    b = ShearBuilding.from_period(1, 0.15, 0.02)
    pfa = peak_floor_acceleration(b, acc, dt, floors=[1]).peak[0]
    fr = response_spectrum(acc, dt, [0.0, 0.002], 0.05, building=b, floor=1)
    assert fr.psa[0, 0] == pfa
    assert fr.psa[0, 1] == pytest.approx(pfa, rel=1e-3)


def oscillator_reference(A, b, Ca, da, acc, dt, T, xi):
    """Peaks of q, q', ω²q + 2ξωq' of an oscillator on a floor, by the DOP853 reference."""
    n = A.shape[0]
    w = 2 * np.pi / T
    Aug = np.zeros((n + 2, n + 2))
    Aug[:n, :n] = A
    Aug[n, n + 1] = 1.0
    Aug[n + 1, :n] = -Ca
    Aug[n + 1, n] = -(w**2)
    Aug[n + 1, n + 1] = -2 * xi * w
    baug = np.concatenate([b, [0.0, -da]])
    C = np.zeros((3, n + 2))
    C[0, n] = 1.0
    C[1, n + 1] = 1.0
    C[2, n] = w**2
    C[2, n + 1] = 2 * xi * w
    return linear_peaks(Aug, baug, C, acc, dt)


def test_closed_form_step_against_high_precision_and_expm():
    """The ground oscillator's exact step (closed form, Taylor series below ωh = 0.5) against a
    40-digit matrix exponential of the augmented first-order hold, and against SciPy's expm over
    ωh from 1e-5 to 40 (expm itself loses up to ~4e-12 at large ωh)."""
    import mpmath as mp
    import scipy.linalg

    from floorslide.spectra.core import _sdof_recurrence

    def augmented(w, xi):
        return [[0, 1, 0, 0], [-(w**2), -2 * xi * w, -1, 0], [0, 0, 0, 1], [0, 0, 0, 0]]

    def split(E, h):
        E = np.asarray(E, dtype=float)
        return E[:2, :2], E[:2, 2] - E[:2, 3] / h, E[:2, 3] / h

    mp.mp.dps = 40
    for xi, th in [(0.0, 31.8), (0.05, 3.0), (0.05, 0.51), (0.02, 0.49), (0.05, 1e-4), (0.3, 7.0)]:
        h = 0.01
        w = th / h
        E = mp.expm(mp.matrix(augmented(mp.mpf(w), mp.mpf(xi))) * mp.mpf(h))
        ref = split(E.tolist(), h)
        got = _sdof_recurrence(np.array([w]), np.array([xi]), h)
        for g, r in zip(got, ref, strict=True):
            np.testing.assert_allclose(g[0], r, rtol=0, atol=5e-14 * np.abs(r).max())
    th = np.geomspace(1e-5, 40, 300)
    for xi in (0.0, 0.05, 0.5, 0.99):
        w = th / 0.01
        got = _sdof_recurrence(w, np.full(w.size, xi), 0.01)
        E = scipy.linalg.expm(np.array([augmented(wi, xi) for wi in w]) * 0.01)
        for i, ref in enumerate(split(e, 0.01) for e in E):
            for g, r in zip(got, ref, strict=True):
                np.testing.assert_allclose(g[i], r, rtol=0, atol=1e-11 * np.abs(r).max())


def test_ground_spectrum_matches_reference(elcentro):
    acc, dt = elcentro
    acc = acc[:1200]
    T = [0.05, 0.3, 1.5]
    sp = response_spectrum(acc, dt, T, 0.05)
    for i, t in enumerate(T):
        ref = oscillator_reference(
            np.zeros((0, 0)), np.zeros(0), np.zeros(0), 1.0, acc, dt, t, 0.05
        )
        np.testing.assert_allclose([sp.sd[0, i], sp.sv[0, i], sp.sa[0, i]], ref, rtol=1e-9)


def test_floor_spectrum_of_stiff_building_matches_reference(coarse_record):
    """FRS on a stiff building (T = 0.1 s) under dt = 0.02 s: the exact chain ground → building
    → oscillator, compared with the reference integrating all three together."""
    acc, dt = coarse_record
    acc = acc[100:500]
    b = ShearBuilding.from_period(1, 0.1, 0.02)
    A, B = b.state_matrices()
    Ca, Da, _ = b.output_matrices([1])
    T = [0.05, 0.1, 0.4]
    sp = response_spectrum(acc, dt, T, 0.05, building=b, floor=1)
    for i, t in enumerate(T):
        ref = oscillator_reference(A, B[:, 0], Ca[0], float(Da[0, 0]), acc, dt, t, 0.05)
        np.testing.assert_allclose([sp.sd[0, i], sp.sv[0, i], sp.sa[0, i]], ref, rtol=1e-9)
    # re-interpolating sampled floor motion underestimates the FRS peak of a stiff building
    approx = response_spectrum(acc, dt, T, 0.05, building=b, floor=1, method="reinterpolated")
    assert approx.psa[0, 1] < sp.psa[0, 1] * 0.98


@pytest.mark.parametrize("where", ["ground", "stiff floor", "isolated roof"])
def test_skip_rules_change_nothing_across_blocks(where, elcentro, coarse_record):
    """The kernel skips the in-step search wherever a rigorous bound says no peak can grow: the
    spectra equal those of searching every step of every oscillator. 40 periods × 2 damping
    ratios span three blocks of oscillators and sub-stepped short periods; oscillators in later
    blocks agree with the independent reference."""
    acc, dt = coarse_record if where == "stiff floor" else elcentro
    acc = acc[100:700]
    kw = {}
    if where == "stiff floor":
        kw = dict(building=ShearBuilding.from_period(1, 0.1, 0.02), floor=1)
    elif where == "isolated roof":
        kw = dict(
            building=IsolatedBuilding(ShearBuilding.from_period(2, 0.3, 0.05), 1.0, 2.5, 0.1),
            floor=2,
        )
    T = np.geomspace(0.02, 4.0, 40)
    Z = np.array([0.02, 0.1])
    from floorslide.building.exact_motion import single_use_motion
    from floorslide.spectra.core import _exact

    fm = single_use_motion(kw.get("building"), acc, dt, kw.get("floor"))
    got = _exact(fm, T, Z)
    full = _exact(fm, T, Z, search_all=True)
    for a, b in zip(got, full, strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-13, atol=0)
    if kw:
        b = kw["building"]
        A, B = b.state_matrices()
        Ca, Da, _ = b.output_matrices([kw["floor"]])
        args = (A, B[:, 0], Ca[0], float(Da[0, 0]))
    else:
        args = (np.zeros((0, 0)), np.zeros(0), np.zeros(0), 1.0)
    for iz, it in ((0, 0), (1, 5), (1, 33)):  # oscillators 0, 45 and 73: blocks 0, 1 and 2
        ref = oscillator_reference(*args, acc, dt, T[it], Z[iz])
        np.testing.assert_allclose([x[iz, it] for x in got], ref, rtol=1e-9)


def test_isolated_roof_frs_matches_reference(elcentro):
    acc, dt = elcentro
    acc = acc[:800]
    iso = IsolatedBuilding(ShearBuilding.from_period(2, 0.3, 0.05), 1.0, 2.5, 0.1)
    A, B = iso.state_matrices()
    Ca, _, _ = iso.output_matrices([2])
    sp = response_spectrum(acc, dt, [0.25, 2.5], 0.05, building=iso, floor=2)
    for i, t in enumerate([0.25, 2.5]):
        ref = oscillator_reference(A, B[:, 0], Ca[0], 0.0, acc, dt, t, 0.05)
        np.testing.assert_allclose([sp.sd[0, i], sp.sv[0, i], sp.sa[0, i]], ref, rtol=1e-9)


def test_brochard_base_spectrum_peaks_at_free_free_frequency(elcentro):
    """Brochard & Gantenbein (1989): with mu = 0.01 the sliding base's acceleration spectrum
    peaks at the free–free frequency 6√3 = 10.39 Hz (the base acceleration history at the
    samples is taken as piecewise linear)."""
    acc, dt = elcentro
    res = slide_oscillator(
        acc, dt, 0.01, frequency=6.0, damping=0.02, mass_ratio=0.5, histories=True
    )
    f = np.linspace(3.0, 25.0, 441)
    sp = response_spectrum(res.base_accel[0], dt, 1 / f, 0.02)
    assert f[np.argmax(sp.psa[0])] == pytest.approx(6 * np.sqrt(3), rel=0.02)


def test_broadening_and_envelope():
    T = period_grid({"min": 0.1, "max": 1.0, "n": 201})
    psa = np.where(np.isclose(T, T[100]), 10.0, 1.0)[None, :]
    from floorslide.spectra.core import Spectrum

    sp = Spectrum(T, np.array([0.05]), psa, psa, psa, psa, psa)
    b = broaden(sp, 0.15)
    assert b.broadening == 0.15
    plateau = T[b.psa[0] >= 10.0 - 1e-12]
    tp = T[100]
    # a peak at f_p covers 0.85 f_p … 1.15 f_p: periods T_p/1.15 … T_p/0.85 (grid step 1.16 %)
    lo, hi = tp / 1.15, tp / 0.85
    assert plateau.min() >= lo * (1 - 1e-9) and plateau.max() <= hi * (1 + 1e-9)
    assert plateau.min() <= lo * 1.012 and plateau.max() >= hi / 1.012
    e = envelope([sp, b])
    np.testing.assert_array_equal(e.psa, np.maximum(sp.psa, b.psa))
    with pytest.raises(ModelError):
        broaden(sp, 1.5)


@pytest.mark.parametrize("method", ["samples", "newmark", "fft"])
def test_approximate_spectra_are_close_and_converge(method, coarse_record):
    acc, dt = coarse_record
    T = [0.05, 0.2, 1.0]
    exact = response_spectrum(acc, dt, T, 0.05)
    approx = response_spectrum(acc, dt, T, 0.05, method=method)
    err = np.abs(approx.psa - exact.psa).max() / exact.psa.max()
    assert 0 < err < 0.2
    if method == "newmark":
        finer = response_spectrum(acc, dt, T, 0.05, method=method, substeps=16)
        assert np.abs(finer.psa - exact.psa).max() / exact.psa.max() < err / 4
    if method == "samples":  # peaks at samples can only underestimate
        assert np.all(approx.sd <= exact.sd * (1 + 1e-12))


@pytest.mark.parametrize(
    "bad",
    [
        dict(periods=[-1.0]),
        dict(periods=[]),
        dict(periods={"min": 1.0, "max": 0.5, "n": 10}),
        dict(periods=[1.0], damping=1.0),
        dict(periods=[1.0], method="duhamel"),
        dict(periods=[1.0], floor=1),
    ],
)
def test_bad_spectrum_arguments(bad):
    with pytest.raises(ModelError):
        response_spectrum(np.ones(10), 0.01, **bad)


@pytest.mark.parametrize(
    ("periods", "damping", "text"),
    [
        ({"min": 0.1, "max": 5.0, "n": 100_000_000}, 0.05, "100000000 periods: at most 10000"),
        (np.linspace(0.1, 5, 10_001), 0.05, "10001 periods: at most 10000"),
        ([1e-9, 1.0], 0.05, "period 1e-09 s is below dt/1000 = 1e-05 s (dt = 0.01 s)"),
        ([1.0, 1e9], 0.05, "period 1e+09 s is above 10000 s"),
        (np.linspace(0.1, 5, 10_000), np.linspace(0, 0.2, 11), "110000 oscillators: at most"),
        ([1.0], np.full(10_001, 0.05), "10001 damping: at most 10000"),
    ],
)
def test_spectrum_sizes_that_would_exhaust_memory_are_refused(periods, damping, text):
    """A 1e8-period grid was killed by the OOM killer at 23.8 GB; T = 1e-9 s raised a
    MemoryError (1.3e8 sub-steps per step): a ModelError now, before any work."""
    with pytest.raises(ModelError) as info:
        response_spectrum(np.ones(10), 0.01, periods, damping)
    assert text in str(info.value) and info.value.exit_code == 2


def test_spectrum_limits_are_inclusive():
    sp = response_spectrum(np.sin(np.arange(200) * 0.3), 0.01, [0.0, 1e-5, 1e4], [0.0, 0.05])
    assert sp.psa.shape == (2, 3) and np.isfinite(sp.psa).all()
