"""The ground spectrum's skip rules for steps whose response may have two critical points: a
derivative of one sign at both ends is searched only if it comes within its chord deviation
``dt²/8·max|f'''|`` of zero. The rules must change nothing: every spectrum equals the one
found by searching every step, and the in-step peak between two close zeros of ``q'`` is
still found against an independent reference."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.exact_motion import single_use_motion
from floorslide.spectra.core import _exact
from tests.reference import linear_peaks
from tests.spectra.test_two_critical_points import DT, two_zero_record


@pytest.mark.parametrize(
    ("wdt", "xi", "z1", "z2"),
    [
        (0.1, 0.05, 0.4, 0.9),
        (0.2, 0.05, 0.55, 0.9),
        (0.45, 0.05, 0.45, 0.95),
        (0.3, 0.02, 0.3, 0.8),
        (0.05, 0.1, 0.2, 0.9),  # ω·dt small: the chord deviation is small too
        (0.35, 0.0, 0.4, 0.95),
        (0.2, 0.2, 0.3, 0.85),
    ],
)
def test_close_zeros_of_the_velocity_are_still_searched(wdt, xi, z1, z2):
    """q' has two zeros in the last step, q' keeps its sign at the step's ends and |q| peaks
    between them, above every sample (a filter that dropped the step would miss it by more
    than 10⁻⁵ relative: checked by zeroing the chord deviation)."""
    w = wdt / DT
    acc = two_zero_record(w, xi, z1=z1, z2=z2)
    A = np.array([[0.0, 1.0], [-(w**2), -2 * xi * w]])
    ref = linear_peaks(A, np.array([0.0, -1.0]), np.array([[1.0, 0.0]]), acc, DT)[0]
    T = np.array([2 * np.pi / w])
    Z = np.array([xi])
    end = abs(fs.response_spectrum(acc, DT, T, xi, method="samples").sd[0, 0])
    assert (ref - end) / ref > 5e-5  # the peak is inside the last step, above the samples
    sd, _, _ = _exact(single_use_motion(None, acc, DT, None), T, Z)
    full, _, _ = _exact(single_use_motion(None, acc, DT, None), T, Z, search_all=True)
    assert sd[0, 0] == pytest.approx(full[0, 0], rel=1e-13)
    assert sd[0, 0] == pytest.approx(ref, rel=1e-10)


def _records(rng):
    """Short records with features that make in-step peaks: white noise, a slow sine plus
    noise (a particular solution that dominates the free vibration), sparse pulses, a ramp."""
    n = 400
    t = np.arange(n) * DT
    yield rng.normal(size=n)
    yield np.sin(2 * np.pi * 0.7 * t) + 0.05 * rng.normal(size=n)
    pulses = np.zeros(n)
    pulses[rng.integers(0, n, 12)] = rng.normal(size=12) * 5.0
    yield pulses
    yield np.cumsum(rng.normal(size=n)) * 0.1 + np.linspace(0.0, 3.0, n)


@pytest.mark.parametrize("seed", [0, 1])
def test_skip_rules_change_nothing(seed):
    """Every peak (|q|, |q'| and the pseudo-acceleration |ω²q + 2ξωq'|) equals, to rounding,
    the one found by searching every step, on 100 periods from 0.02 s (ω·dt up to 3: several
    sub-steps) to 5 s and four damping ratios including 0."""
    rng = np.random.default_rng(seed)
    T = np.geomspace(0.02, 5.0, 100)
    Z = np.array([0.0, 0.02, 0.05, 0.2])
    for acc in _records(rng):
        got = _exact(single_use_motion(None, acc, DT, None), T, Z)
        full = _exact(single_use_motion(None, acc, DT, None), T, Z, search_all=True)
        for g, f in zip(got, full, strict=True):
            # a peak searched anew is re-evaluated from the Taylor polynomial: rounding apart
            np.testing.assert_allclose(g, f, rtol=1e-13, atol=0)


def test_the_filter_skips_steps():
    """Not vacuous: on a noisy record most steps are not searched."""
    rng = np.random.default_rng(3)
    acc = rng.normal(size=400)
    T = np.geomspace(0.02, 5.0, 50)
    Z = np.array([0.05])
    counts = np.zeros(2, dtype=np.int64)
    _exact(single_use_motion(None, acc, DT, None), T, Z, counts=counts)
    assert 0 < counts[0] < 0.5 * T.size * acc.size
