"""Intensity measures, exact for the piecewise-linear record (docs/design.md §2, §7).

References used here, all independent of floorslide's formulas:

- the docs/design.md §7 sine record ``a0 sin 2πft`` (f = 1 Hz, T_d = 10 s): Arias ``π a0²
T_d/(4g)``,
  CAV ``2 a0 T_d/π``, D5–95 = 9.0 s (and D5–75 = 7.0 s);
- closed forms for the *piecewise-linear* sine sampled with N = 1/(f·dt) samples per cycle (N
  even, so that every zero of the sine is a sample): ``∫a² = a0² T_d (2 + cos ωh)/6`` (the sums
  of sin² and of sin·sin-shifted over whole periods) and ``∫|a| = 2 f T_d a0 h cot(π f h)``
  (the trapezoid rule for |sin| over half periods);
- Simpson's rule on the samples and step midpoints, which is exact for ``a²`` of a
  piecewise-linear record (a quadratic in each step);
- closed-form single-step cases for peaks inside a step.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from obspy import Trace
from scipy.integrate import quad

import floorslide as fs
from floorslide.errors import RecordError, UnitsConversionWarning, UnitsError
from floorslide.records.measures import (
    MEASURE_KEYS,
    husid,
    husid_times,
    peak_velocity_displacement,
)
from tests.conftest import G

A0, F, TD = 2.0, 1.0, 10.0
OMEGA = 2 * np.pi * F


def sine(dt: float, phase: float = 0.0) -> np.ndarray:
    n = round(TD / dt)
    t = np.arange(n + 1) * dt
    return A0 * np.sin(OMEGA * t + phase)


def pl_energy_until(acc: np.ndarray, dt: float, t: float) -> float:
    """∫_0^t a² of the piecewise-linear record by Simpson's rule (exact for a quadratic)."""
    k = min(int(t // dt), acc.size - 2)
    a0, a1 = acc[:k], acc[1 : k + 1]
    full = dt / 6 * np.sum(a0**2 + 4 * ((a0 + a1) / 2) ** 2 + a1**2)
    s = t - k * dt
    left, right = acc[k], acc[k] + (acc[k + 1] - acc[k]) * s / dt
    return float(full + s / 6 * (left**2 + 4 * ((left + right) / 2) ** 2 + right**2))


def test_sine_record_fine_sampling_against_design_closed_forms():
    """dt = 1e-5 s (1e6 samples): the piecewise-linear record is within (ωh)²/6 = 7e-10 of the
    sine in ∫a² and (πfh)²/3 = 3e-10 in ∫|a|, so the closed forms hold to ~1e-9."""
    dt = 1e-5
    m = fs.measures(sine(dt), dt=dt)
    assert m["arias"] == pytest.approx(np.pi * A0**2 * TD / (4 * G), rel=1e-9)
    assert m["cav"] == pytest.approx(2 * A0 * TD / np.pi, rel=1e-9)
    assert m["npts"] == 1_000_001 and m["duration"] == pytest.approx(TD, rel=1e-12)
    assert m["pga"] == pytest.approx(A0, rel=1e-9) and m["pga_g"] == m["pga"] / G
    assert m["pgv"] == pytest.approx(A0 / (np.pi * F), rel=1e-9)  # v = a0/ω (1 − cos ωt)
    assert m["pgd"] == pytest.approx(A0 * TD / OMEGA, rel=1e-9)  # u = a0/ω (t − sin ωt/ω)
    # D5–95: see test_sine_significant_duration for the tolerance
    assert m["d5_95"] == pytest.approx(9.0, abs=1e-4)
    assert m["d5_75"] == pytest.approx(7.0, abs=1e-4)


@pytest.mark.parametrize("dt", [0.1, 0.05, 0.02, 0.01, 0.001])
def test_sine_record_exact_piecewise_linear_integrals(dt):
    """At any dt (here 10 to 1000 samples a cycle) Arias and CAV equal the closed forms of the
    piecewise-linear sine to rounding; the difference to the sine itself is the O(h²) of the
    interpolation, not an error of the method."""
    m = fs.measures(sine(dt), dt=dt)
    arias_pl = np.pi / (2 * G) * A0**2 * TD * (2 + np.cos(OMEGA * dt)) / 6
    cav_pl = 2 * F * TD * A0 * dt / np.tan(np.pi * F * dt)
    assert m["arias"] == pytest.approx(arias_pl, rel=1e-12)
    assert m["cav"] == pytest.approx(cav_pl, rel=1e-12)
    relative_gap = abs(m["arias"] / (np.pi * A0**2 * TD / (4 * G)) - 1)
    assert relative_gap == pytest.approx((1 - np.cos(OMEGA * dt)) / 3, rel=1e-6)


@pytest.mark.parametrize("dt", [0.1, 0.05, 0.01, 0.001])
def test_sine_significant_duration(dt):
    """With an even number of samples per cycle, each half cycle of the piecewise-linear sine
    carries 1/20 of ∫a², so the 5/75/95 % instants are 0.5, 7.5 and 9.5 s exactly: D5–95 = 9.0 s.

    Those instants are zeros of a, where the Husid curve is flat (E' = a² = 0, E'' = 0): a
    change δE of the level (one rounding of the cumulative sum or of 0.05·E_total) moves the
    instant by (3 δE/ȧ²)^(1/3), ≈ 1e-6 s for δE ≈ 1e-15 E. That is the conditioning of the
    problem, not of the method: the backward error, the ∫a² (computed independently) up to
    the returned instant versus the level, is at rounding level.
    """
    acc = sine(dt)
    m = fs.measures(acc, dt=dt)
    total = pl_energy_until(acc, dt, TD)
    slope = A0 * OMEGA
    bound = 3 * (3 * 1e-13 * total / slope**2) ** (1 / 3)
    assert m["d5_95"] == pytest.approx(9.0, abs=bound)
    assert m["d5_75"] == pytest.approx(7.0, abs=bound)
    t5, t75, t95 = husid_times(acc, dt, (0.05, 0.75, 0.95))
    for t, p in ((t5, 0.05), (t75, 0.75), (t95, 0.95)):
        assert pl_energy_until(acc, dt, t) == pytest.approx(p * total, rel=1e-12)


@pytest.mark.parametrize("dt", [0.07, 0.013, 0.031])
def test_husid_instants_inside_steps_well_conditioned(dt):
    """A phase-shifted sine sampled off its zeros: the levels fall inside steps where a ≠ 0,
    and the instants match an independent root-finding on the Simpson integral to 1e-10 s."""
    from scipy.optimize import brentq

    acc = sine(dt, phase=0.3)
    total = pl_energy_until(acc, dt, (acc.size - 1) * dt)
    got = husid_times(acc, dt, (0.05, 0.75, 0.95))
    for t, p in zip(got, (0.05, 0.75, 0.95), strict=True):
        ref = brentq(lambda x, p=p: pl_energy_until(acc, dt, x) - p * total, 0, TD, xtol=1e-14)
        assert t == pytest.approx(ref, abs=1e-10)
        assert t / dt != pytest.approx(round(t / dt), abs=1e-3)  # inside a step


@pytest.mark.parametrize("dt", [0.07, 0.013, 0.3])
def test_cav_with_sign_changes_inside_steps(dt):
    """Zero crossings inside steps: CAV against adaptive quadrature of |a| on each step, told
    where the kink is (the root of the step's linear function, by numpy.roots)."""
    acc = sine(dt, phase=0.3)
    ref = 0.0
    for k in range(acc.size - 1):
        slope = (acc[k + 1] - acc[k]) / dt
        kinks = [r.real for r in np.roots([slope, acc[k]]) if 0 < r.real < dt]
        ref += quad(lambda s, k=k, m=slope: abs(acc[k] + m * s), 0, dt, points=kinks or None)[0]
    assert any(acc[k] * acc[k + 1] < 0 for k in range(acc.size - 1))
    assert fs.measures(acc, dt=dt)["cav"] == pytest.approx(ref, rel=1e-11)


def test_pgv_peak_inside_a_step():
    """Triangle pulse a = [0, A, −A, 0]: a crosses zero mid-step 2, where v peaks at 3Ah/4;
    the samples only show Ah/2."""
    A, h = 3.0, 0.02
    pgv, _ = peak_velocity_displacement(np.array([0.0, A, -A, 0.0]), h)
    assert pgv == pytest.approx(3 * A * h / 4, rel=1e-14)
    # one step of a = A → −A: v = A s − A s²/h peaks at s = h/2 with Ah/4 (0 at both samples)
    pgv, _ = peak_velocity_displacement(np.array([A, -A]), h)
    assert pgv == pytest.approx(A * h / 4, rel=1e-14)


def test_pgd_peak_inside_a_step():
    """a = [1, 1, −7] m/s², h = 1 s: v = 1 + s − 4s² in step 2 vanishes at s* = (1+√17)/8,
    where u = 1/2 + s* + s*²/2 − (4/3)s*³ = 0.99526... > u(2 s) = 2/3."""
    s = (1 + np.sqrt(17)) / 8
    expected = 0.5 + s + s**2 / 2 - 4 / 3 * s**3
    _, pgd = peak_velocity_displacement(np.array([1.0, 1.0, -7.0]), 1.0)
    assert pgd == pytest.approx(expected, rel=1e-14)
    # scaled by a and h: u scales as a·h²
    _, pgd = peak_velocity_displacement(np.array([1.0, 1.0, -7.0]) * 2.5, 0.01)
    assert pgd == pytest.approx(2.5 * 1e-4 * expected, rel=1e-13)


def test_constant_acceleration():
    A, h, n = 1.5, 0.01, 101
    m = fs.measures(np.full(n, A), dt=h)
    T = (n - 1) * h
    assert m["pgv"] == pytest.approx(A * T, rel=1e-13)
    assert m["pgd"] == pytest.approx(A * T**2 / 2, rel=1e-13)
    assert m["arias"] == pytest.approx(np.pi / (2 * G) * A**2 * T, rel=1e-13)
    assert m["cav"] == pytest.approx(A * T, rel=1e-13)
    assert m["d5_95"] == pytest.approx(0.9 * T, rel=1e-12)  # E grows linearly


records = st.integers(2, 40).flatmap(
    lambda n: st.tuples(
        st.lists(st.floats(-10, 10, allow_subnormal=False), min_size=n, max_size=n),
        st.floats(0.001, 0.1),
    )
)


@settings(max_examples=60, deadline=None)
@given(records)
def test_against_dense_evaluation(record):
    """PGV/PGD against a dense evaluation (400 points a step; velocity by the trapezoid rule,
    exact for a piecewise-linear a on a grid containing the samples; displacement by the
    trapezoid rule on that, O((h/400)²)); Arias against Simpson on samples and midpoints
    (exact); CAV against the dense trapezoid rule."""
    values, dt = record
    acc = np.array(values)
    m = fs.measures(acc, dt=dt)
    sub = 400
    t = np.linspace(0, (acc.size - 1) * dt, (acc.size - 1) * sub + 1)
    a = np.interp(t, np.arange(acc.size) * dt, acc)
    step = t[1] - t[0]
    v = np.concatenate(([0.0], np.cumsum((a[1:] + a[:-1]) / 2 * step)))
    u = np.concatenate(([0.0], np.cumsum((v[1:] + v[:-1]) / 2 * step)))
    scale_v = np.abs(acc).max() * dt * acc.size + 1e-12
    scale_u = scale_v * dt * acc.size
    assert m["pgv"] >= np.abs(v).max() - 1e-12 * scale_v
    assert m["pgv"] == pytest.approx(np.abs(v).max(), abs=1e-5 * scale_v)
    assert m["pgd"] >= np.abs(u).max() - 1e-5 * scale_u
    assert m["pgd"] == pytest.approx(np.abs(u).max(), abs=1e-5 * scale_u)
    simpson = pl_energy_until(acc, dt, (acc.size - 1) * dt)
    assert m["arias"] == pytest.approx(np.pi / (2 * G) * simpson, rel=1e-12, abs=1e-300)
    cav_dense = np.sum((np.abs(a[1:]) + np.abs(a[:-1])) / 2 * step)
    assert m["cav"] == pytest.approx(cav_dense, rel=1e-5, abs=1e-12)
    assert m["cav"] <= cav_dense * (1 + 1e-12) + 1e-15  # trapezoid of |a| overestimates kinks


@settings(max_examples=60, deadline=None)
@given(records)
def test_husid_levels_are_reached_at_the_returned_times(record):
    values, dt = record
    acc = np.array(values)
    energy = husid(acc, dt)
    times = husid_times(acc, dt, (0.05, 0.5, 0.95))
    if energy[-1] == 0:
        assert np.isnan(times).all()
        return
    assert np.all(np.diff(times) >= 0)
    for t, p in zip(times, (0.05, 0.5, 0.95), strict=True):
        assert pl_energy_until(acc, dt, t) == pytest.approx(p * energy[-1], rel=1e-9)


def test_trace_and_array_agree_and_keys(elc_si):
    tr = Trace(elc_si.copy())
    tr.stats.delta = 0.01
    tr.stats.units = "m/s**2"
    from_trace = fs.measures(tr)
    assert tuple(from_trace) == (*MEASURE_KEYS, "notes")
    assert from_trace == fs.measures(elc_si, dt=0.01)
    assert from_trace["notes"] == ()
    assert from_trace["pga_g"] == pytest.approx(0.312881, rel=1e-12)


def test_invalid_input():
    with pytest.raises(RecordError, match="need dt"):
        fs.measures(np.ones(3))
    with pytest.raises(RecordError, match="must be > 0"):
        fs.measures(np.ones(3), dt=0.0)
    with pytest.raises(RecordError, match="non-empty"):
        fs.measures(np.array([]), dt=0.01)
    with pytest.raises(RecordError, match="NaN or infinite"):
        fs.measures(np.array([0.0, np.inf]), dt=0.01)
    tr = Trace(np.ones(3))
    with pytest.raises(UnitsError, match=r"no stats\.units"):
        fs.measures(tr)
    tr.stats.units = "furlongs/fortnight"
    with pytest.raises(UnitsError, match="'furlongs/fortnight'"):
        fs.measures(tr)


def test_trace_in_g_is_converted_with_a_note(elc_g):
    """docs/design.md §10: a Trace in g is converted (it used to be refused), and the result says
    so."""
    tr = Trace(elc_g.copy())
    tr.stats.delta = 0.01
    tr.stats.units = "g"
    with pytest.warns(UnitsConversionWarning, match="'g'"):
        m = fs.measures(tr)
    ref = fs.measures(elc_g * 9.80665, dt=0.01)
    assert {k: m[k] for k in MEASURE_KEYS} == {k: ref[k] for k in MEASURE_KEYS}
    assert len(m["notes"]) == 1 and "9.80665" in m["notes"][0]


def test_zero_record_and_single_sample():
    m = fs.measures(np.zeros(10), dt=0.01)
    assert m["pga"] == m["pgv"] == m["pgd"] == m["arias"] == m["cav"] == 0.0
    assert np.isnan(m["d5_95"]) and np.isnan(m["d5_75"])
    one = fs.measures(np.array([-2.0]), dt=0.01)
    assert one["pga"] == 2.0 and one["duration"] == 0.0 and one["arias"] == 0.0
    assert m["notes"] == ("d5_75, d5_95: undefined, the Arias intensity is 0 (a record of zeros)",)


def test_measures_beyond_floating_point_are_nan_with_a_note():
    """Samples of 1e200 m/s² gave CAV = inf, durations of 0 s and overflow RuntimeWarnings
    (issue 19 item 6): every measure that overflows, and the durations with ∫a², is NaN and a
    note names them."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = fs.measures(np.array([1e200, -1e200, 1e200, 0.0]), dt=0.01)
    assert m["pga"] == 1e200 and m["pgv"] == pytest.approx(5e197)
    assert all(np.isnan(m[k]) for k in ("arias", "cav", "d5_75", "d5_95"))
    assert m["notes"] == (
        "arias, cav, d5_75, d5_95: undefined, beyond floating point (samples up to 1e+200 m/s²)",
    )
    assert fs.measures(np.array([1e150, -1e150, 0.0]), dt=0.01)["notes"] == ()
