"""Floor response spectra on nonlinear isolation: the riders' fast path against the series.

On a sub-step without isolator events a rider (a response-spectrum oscillator on a floor) is
advanced by its exact linear update, and searched inside the sub-step only where a rigorous
filter cannot rule out a new peak (``_riders_fast`` of ``floorslide.spectra._segment_kernels``,
reading the building's segments); the reference is the series path on every segment
(``floorslide.spectra.segmented.BY_SERIES``). The spectra agree to rounding,
and their peaks are never below the rider's exact response sampled 64 times finer (the
oscillator integrated as two more states of the building, on the record resampled at dt/64:
the same piecewise-linear ground motion, so the same exact solution, at more samples).
"""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building import nonlinear as nl
from floorslide.spectra import segmented as sg
from tests.conftest import SLAMMER, G

PERIODS = np.geomspace(0.02, 5.0, 12)
DAMPING = [0.0, 0.05, 0.3]
RECORDS = {
    # name: (dt, first sample, samples): the strong motion, shortened for the series path
    "ImperialValley_1979_EMO-270.txt": (0.005, 600, 1600),
    "CapeMendocino_1992_PET-090.txt": (0.02, 0, 900),
}
FINE = 64


def record(name: str) -> tuple[np.ndarray, float]:
    dt, start, n = RECORDS[name]
    return np.loadtxt(SLAMMER / name).ravel()[start : start + n] * G, dt


def building(isolator: str, stories: int):
    sup = fs.ShearBuilding.from_period(stories=stories, period=0.2 * stories, damping=0.02)
    if isolator == "pendulum":
        layer = fs.FrictionPendulum(mu=0.06, period=3.0)
    else:
        layer = fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02)
    return fs.NonlinearIsolatedBuilding(sup, 1.0, layer)


def spectrum(b, a, dt, floor, *, series: bool, periods=PERIODS, damping=DAMPING):
    old = sg.BY_SERIES
    sg.BY_SERIES = series
    try:
        return fs.response_spectrum(a, dt, periods, damping, building=b, floor=floor)
    finally:
        sg.BY_SERIES = old


CASES = [
    pytest.param("pendulum", 1, "ImperialValley_1979_EMO-270.txt", id="pendulum-1-IV"),
    pytest.param("pendulum", 1, "CapeMendocino_1992_PET-090.txt", id="pendulum-1-CM"),
    pytest.param("bilinear", 1, "ImperialValley_1979_EMO-270.txt", id="bilinear-1-IV"),
    pytest.param("pendulum", 3, "CapeMendocino_1992_PET-090.txt", id="pendulum-3-CM"),
    pytest.param("bilinear", 3, "ImperialValley_1979_EMO-270.txt", id="bilinear-3-IV"),
]


@pytest.mark.parametrize(("isolator", "stories", "name"), CASES)
def test_fast_path_equals_the_series_path(isolator, stories, name):
    """Every floor, 12 periods from 0.02 s (up to 7 series parts per sub-step at dt = 0.02 s)
    to 5 s, damping 0, 5 % and 30 %: the same spectra to rounding, the fast path's peaks
    never lower beyond rounding, and most sub-steps on the fast path with few searches."""
    a, dt = record(name)
    b = building(isolator, stories)
    for floor in range(stories + 1):
        ref = spectrum(b, a, dt, floor, series=True)
        new = spectrum(b, a, dt, floor, series=False)
        stats = sg.LAST_STATS.copy()
        for q in ("psa", "sa", "sd", "sv"):
            r, v = getattr(ref, q), getattr(new, q)
            assert np.all(r > 0), q
            # the velocity of a stiff rider is a small difference of large terms
            # (q' ≈ −a_f'/ω²): its rounding is relative to the velocity scale SA/ω
            w = 2 * np.pi / ref.periods[None, :]
            tol = 1e-12 * (np.maximum(r, ref.sa / w) if q == "sv" else r)
            assert np.all(np.abs(v - r) <= tol), (q, floor, np.abs(v - r).max())
        # riders went through the fast path on most sub-steps and were seldom searched
        riders = PERIODS.size * len(DAMPING)
        assert stats[0] >= 0.8 * (a.size - 1)
        assert stats[1] == stats[0] * riders
        assert stats[2] <= 0.2 * stats[1]


def _sampled_peaks(b, a, dt, floor, w, xi):
    """``max|q|, max|q'|, max|ω² q + 2ξω q'|`` of the rider's exact response at the samples
    of the record resampled 64 times finer (the oscillator as two more states of every
    branch; its states at the samples of the building's motion)."""
    t = np.arange(a.size) * dt
    tf = np.linspace(0.0, t[-1], (a.size - 1) * FINE + 1)
    fine = np.interp(tf, t, a)
    X = nl.nonlinear_motion(
        b, fine, dt / FINE, floors=[floor], oscillator=(floor, w, xi), keep_segments=False
    ).states
    q, v = X[:, -2], X[:, -1]
    return np.array([np.abs(q).max(), np.abs(v).max(), np.abs(w * w * q + 2 * xi * w * v).max()])


@pytest.mark.parametrize(
    ("isolator", "stories", "name"),
    [
        pytest.param("pendulum", 1, "ImperialValley_1979_EMO-270.txt", id="pendulum-1-IV"),
        pytest.param("bilinear", 3, "CapeMendocino_1992_PET-090.txt", id="bilinear-3-CM"),
    ],
)
def test_peaks_never_below_the_exact_response_sampled_finer(isolator, stories, name):
    """The fast path's peaks (SD, SV, SA) against the rider's exact response at 64 samples per
    record step: never lower (beyond rounding), and close to them (the sampled maximum misses
    at most ``(ωh/64)²/8`` of a crest's height, relatively); against the oscillator's true
    peaks as the augmented system finds them at the record's own dt: equal to 1e-9."""
    a, dt = record(name)
    a = a[: 600 if dt < 0.01 else 300]
    b = building(isolator, stories)
    floor = stories
    periods = [0.02, 0.1, 0.5, 3.0]
    sp = spectrum(b, a, dt, floor, series=False, periods=periods)
    for i, xi in enumerate(DAMPING):
        for j, T in enumerate(periods):
            w = 2 * np.pi / T
            got = np.array([sp.sd[i, j], sp.sv[i, j], sp.sa[i, j]])
            sampled = _sampled_peaks(b, a, dt, floor, w, xi)
            assert np.all(got >= sampled * (1 - 1e-12)), (T, xi, got, sampled)
            assert np.all(got <= sampled * (1 + 1e-3)), (T, xi, got, sampled)
            exact = nl.isolator_response(b, a, dt, floors=[floor], oscillator=(floor, w, xi))
            np.testing.assert_allclose(got, exact.pfa, rtol=1e-9)


def test_overdamped_riders_take_the_series_search():
    """The filter needs ``ξ < 1`` (a free vibration of bounded derivatives): riders with
    ``ξ ≥ 1`` (possible through the segment pass itself) are searched on every sub-step, and
    still agree with the series path."""
    a, dt = record("ImperialValley_1979_EMO-270.txt")
    a = a[:400]
    b = building("pendulum", 1)
    fm = b.motion(a, dt, floors=[1]).floor(1)
    out = {}
    for series in (True, False):
        sg.BY_SERIES = series
        try:  # (fs.response_spectrum refuses ξ ≥ 1; the segment pass takes any)
            out[series] = sg.spectrum_on_segments(
                fm, np.array([0.05, 1.0]), np.array([0.05, 1.0, 2.0])
            )
        finally:
            sg.BY_SERIES = False
    stats = sg.LAST_STATS
    assert stats[2] >= 4 * stats[0]  # the four riders with ξ ≥ 1, on every fast sub-step
    for q in ("sd", "sv", "sa"):
        np.testing.assert_allclose(getattr(out[False], q), getattr(out[True], q), rtol=1e-11)
