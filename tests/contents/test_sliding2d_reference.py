"""The plane-sliding reference of ``tests/reference_sliding2d.py`` against independent results, so
that it can be trusted to validate floorslide's 2-D sliding solver: the closed-form 1-D block of
``tests/reference.py`` (input along an axis, and along an azimuth), the steady circular orbit
under a rotating acceleration (analytic, and its O(dt²) shift when the input is sampled), the
energy balance, stick–slip with many stops, buildings under the floor (against the 1-D DOP853
reference, and tolerance-independence), isotropy, and independence from its own numerical
parameters."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

import tests.reference_sliding2d as ref2d
from tests.conftest import load_slammer
from tests.reference import rigid_block_ground, rigid_block_on_system
from tests.reference_sliding2d import slide2d_reference

G = 9.80665


@functools.cache
def _elc() -> tuple[np.ndarray, float]:
    return load_slammer("ImperialValley_1940_ELC-180.txt")


@functools.cache
def _pair(scale: float = 1.0) -> tuple[np.ndarray, np.ndarray, float]:
    """Two different horizontal components of equal dt (0.01 s): El Centro 1940 (x) and, from
    t = 3 s, half of Northridge 1994 Rinaldi (y)."""
    acc, dt = _elc()
    rr, dt2 = load_slammer("Northridge_1994_RRS-228.txt")
    assert dt2 == dt
    ay = np.zeros_like(acc)
    ay[300 : 300 + rr.size] = 0.5 * rr[: acc.size - 300]
    return scale * acc, scale * ay, dt


@functools.cache
def _run_pair(mu: float, rtol: float = 1e-12, scale: float = 1.0, n: int | None = None) -> dict:
    ax, ay, dt = _pair(scale)
    return slide2d_reference(ax[:n], ay[:n], dt, mu, rtol=rtol)


def _sdof(period: float, xi: float = 0.05) -> tuple:
    """A single-storey building: x = [drift, drift velocity], a_floor = -ω² x1 - 2ξω x2."""
    w = 2 * np.pi / period
    return (
        np.array([[0.0, 1.0], [-w * w, -2 * xi * w]]),
        np.array([0.0, -1.0]),
        np.array([-w * w, -2 * xi * w]),
        0.0,
    )


FLOORS = (_sdof(0.5), _sdof(0.3))


@pytest.mark.parametrize(("mu_k", "mu_s"), [(0.1, None), (0.2, None), (0.1, 0.15)])
def test_one_axis_equals_closed_form_1d(mu_k, mu_s):
    """a_y = 0: the plane reference is the 1-D block (closed form of tests/reference.py) — peak
    and residual to 1e-8 (measured ≤ 4e-15), u_y exactly 0, the first breakaway at the
    record's first crossing of mu_b g, and a stop where |a| > mu_b g slides on ("pass", the 1-D
    reversal)."""
    acc, dt = _elc()
    res = slide2d_reference(acc, np.zeros_like(acc), dt, mu_k, mu_s)
    peak, resid = rigid_block_ground(acc, dt, mu_k, mu_s)
    assert abs(res["peak"] - peak) <= 1e-8 * peak
    assert abs(res["residual"][0] - resid) <= 1e-8 * peak
    assert np.all(res["u"][:, 1] == 0.0) and np.all(res["v"][:, 1] == 0.0)
    assert res["peak_angle"] in (0.0, 180.0)
    # the first crossing of |a| = mu_b g, by linear interpolation of the record
    thr = max(mu_k, mu_s or 0.0) * G
    k = int(np.argmax(np.abs(acc) > thr)) - 1
    a0, a1 = acc[k], acc[k + 1]
    t_cross = (k + (math.copysign(thr, a1) - a0) / (a1 - a0)) * dt
    assert res["events"][0][1] == "breakaway"
    assert abs(res["events"][0][0] - t_cross) <= 1e-12
    assert res["slips"] == sum(e[1] == "breakaway" for e in res["events"])
    assert res["stops"] == sum(e[1] in ("stick", "pass") for e in res["events"])
    assert res["stop_speed_max"] <= 1e-12


@pytest.mark.parametrize("mu", [0.1, 0.2])
def test_azimuth_30_equals_1d(mu):
    """Input along 30°: u stays on that line with the 1-D magnitudes (≤ 1e-8, measured
    ≤ 3e-15) and a perpendicular part ≤ 1e-10 of the peak at every sample (measured ≤ 2e-13)."""
    acc, dt = _elc()
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    res = slide2d_reference(c * acc, s * acc, dt, mu)
    peak, resid = rigid_block_ground(acc, dt, mu)
    along = res["u"] @ [c, s]
    perp = res["u"] @ [-s, c]
    assert abs(res["peak"] - peak) <= 1e-8 * peak
    assert abs(along[-1] - resid) <= 1e-8 * peak
    assert np.abs(perp).max() <= 1e-10 * peak
    assert min(abs(res["peak_angle"] - 30.0), abs(res["peak_angle"] + 150.0)) <= 1e-6


A_CIRC, W_CIRC, MU_CIRC = 3.0, 2 * np.pi, 0.2


def _circle(t: float) -> tuple[float, float]:
    return A_CIRC * math.cos(W_CIRC * t), A_CIRC * math.sin(W_CIRC * t)


def _circle_rate(t: float) -> tuple[float, float]:
    return -A_CIRC * W_CIRC * math.sin(W_CIRC * t), A_CIRC * W_CIRC * math.cos(W_CIRC * t)


def _orbit(res: dict, per_period: int) -> tuple[np.ndarray, np.ndarray]:
    """Radius about the mean position, and speed, over the last period of samples."""
    last = res["u"][-per_period:]
    radius = np.linalg.norm(last - last.mean(axis=0), axis=1)
    return radius, np.linalg.norm(res["v"][-per_period:], axis=1)


def test_circular_orbit_analytic():
    """a = A (cos ωt, sin ωt), |a| > mu g: the block slides from t = 0 and settles on a circle
    of radius √(A² - (mu g)²)/ω² = 0.0575014 m at the speed √(A² - (mu g)²)/ω (friction
    opposes v, the rest of a turns it). With the analytic acceleration: to 1e-10 after 20 s
    (measured 2e-13); no stop."""
    root = math.sqrt(A_CIRC**2 - (MU_CIRC * G) ** 2)
    R, V = root / W_CIRC**2, root / W_CIRC
    assert R == pytest.approx(0.0575014, abs=1e-7)
    dt = 0.05
    npts = round(20.0 / dt) + 1
    res = slide2d_reference(
        np.zeros(npts), np.zeros(npts), dt, MU_CIRC, accel=_circle, accel_rate=_circle_rate
    )
    radius, speed = _orbit(res, 20)
    assert np.abs(radius / R - 1).max() <= 1e-10
    assert np.abs(speed / V - 1).max() <= 1e-10
    assert res["events"] == [(0.0, "breakaway")] and res["stops"] == 0
    assert res["slide_time"] == pytest.approx(20.0, rel=1e-14)


def test_circular_orbit_sampled_record():
    """The same rotating acceleration as a record sampled at dt = 5 ms, piecewise linear: a
    chord of the circle averages A (1 - (ω dt)²/12) over a step, so the orbit shrinks by
    (A²/(A² - (mu g)²)) (ω dt)²/12 = 1.44e-4 — measured 1.436e-4; with that O(dt²) amplitude
    the radius agrees to 1e-7 (measured 6e-9, the ripple at the sample rate)."""
    dt, T = 5e-3, 12.0
    t = np.arange(round(T / dt) + 1) * dt
    res = slide2d_reference(A_CIRC * np.cos(W_CIRC * t), A_CIRC * np.sin(W_CIRC * t), dt, MU_CIRC)
    radius, _ = _orbit(res, round(1.0 / dt))
    R = math.sqrt(A_CIRC**2 - (MU_CIRC * G) ** 2) / W_CIRC**2
    a_eff = A_CIRC * (1 - (W_CIRC * dt) ** 2 / 12)
    R_eff = math.sqrt(a_eff**2 - (MU_CIRC * G) ** 2) / W_CIRC**2
    assert 1.3e-4 <= 1 - radius.mean() / R <= 1.6e-4
    assert np.abs(radius / R_eff - 1).max() <= 1e-7


def test_peak_between_samples():
    """The peak of |u| is found between the samples (roots of u·v): on the circular orbit a
    coarse grid (dt = 0.1 s, 10 samples a turn) gives the same peak as a fine one (2 ms) to
    1e-10 (measured 2e-12), above every sample of the fine run, which comes within
    O(dt²) of it."""
    T = 5.0
    peaks, samples = [], []
    for dt in (0.1, 0.002):
        npts = round(T / dt) + 1
        res = slide2d_reference(
            np.zeros(npts), np.zeros(npts), dt, MU_CIRC, accel=_circle, accel_rate=_circle_rate
        )
        peaks.append(res["peak"])
        samples.append(np.linalg.norm(res["u"], axis=1).max())
        u_peak = res["peak"] * np.array(
            [math.cos(math.radians(res["peak_angle"])), math.sin(math.radians(res["peak_angle"]))]
        )
        k = round(res["t_peak"] / dt)
        assert np.linalg.norm(res["u"][k] - u_peak) <= 2 * dt * np.abs(res["v"]).max()
    assert abs(peaks[0] - peaks[1]) <= 1e-10 * peaks[1]
    assert samples[0] < peaks[0] - 1e-4  # the coarse samples miss the peak
    assert peaks[1] - 1e-5 <= samples[1] <= peaks[1] * (1 + 1e-14)


def test_energy_balance():
    """Kinetic energy = -(friction work) - ∫ a·v dt at every sample (per unit mass, both
    integrals accumulated with the state) on a 2-D record with 41 breakaways and 43 stops:
    ≤ 1e-9 of the friction work (measured 1e-14). The resets v ← 0 at stops, the analytic
    first steps and the integration all enter this balance."""
    res = _run_pair(0.1)
    ke = 0.5 * (res["v"] ** 2).sum(axis=1)
    wf, wa = res["work_friction"], res["work_floor"]
    assert res["stops"] >= 20 and res["slips"] >= 20
    assert np.all(np.diff(wf) >= 0.0) and wf[-1] > 0.0
    assert np.abs(ke + wf + wa).max() <= 1e-9 * wf[-1]
    assert res["stop_speed_max"] <= 1e-12
    # the friction work is mu g × the path length; the path is at least the net displacement
    assert wf[-1] / (0.1 * G) >= np.linalg.norm(res["residual"])


def _check_event_sequence(events: list) -> None:
    """Breakaways only from stick; a pass is followed by sliding; time never goes back."""
    stuck = True
    t_prev = -1.0
    for t, kind in events:
        assert t >= t_prev
        t_prev = t
        if kind == "breakaway":
            assert stuck
            stuck = False
        else:
            assert not stuck
            stuck = kind == "stick"


def test_stick_slip_many_stops():
    """Two components scaled by 1.5, mu = 0.3: |a| crosses mu g again and again (15
    breakaways, 16 stops). Finite, consistent event sequence, and rtol 1e-12 vs 1e-10 agree to
    1e-7 on the peak and on u at every sample (measured 1e-12)."""
    fine = _run_pair(0.3, 1e-12, 1.5)
    coarse = _run_pair(0.3, 1e-10, 1.5)
    assert fine["stops"] >= 5 and fine["slips"] >= 5
    assert np.all(np.isfinite(fine["u"])) and np.all(np.isfinite(fine["v"]))
    _check_event_sequence(fine["events"])
    assert fine["stops"] == coarse["stops"] and fine["slips"] == coarse["slips"]
    assert abs(fine["peak"] - coarse["peak"]) <= 1e-7 * fine["peak"]
    assert np.abs(fine["u"] - coarse["u"]).max() <= 1e-7 * fine["peak"]
    assert 0.0 < fine["slide_time"] < (fine["u"].shape[0] - 1) * 0.01


@pytest.mark.slow
def test_floor_systems_tolerance_independent():
    """Two single-storey floors (T = 0.5 s and 0.3 s, 5 %) driven by the two components,
    integrated with the block: rtol 1e-12 vs 1e-10 agree to 1e-7 (measured 3e-13 on the peak,
    7e-12 on u), and the energy balance holds."""
    ax, ay, dt = _pair()
    n = 2000
    fine = slide2d_reference(ax[:n], ay[:n], dt, 0.3, floor_systems=FLOORS)
    coarse = slide2d_reference(ax[:n], ay[:n], dt, 0.3, floor_systems=FLOORS, rtol=1e-10)
    assert fine["stops"] >= 5
    _check_event_sequence(fine["events"])
    assert abs(fine["peak"] - coarse["peak"]) <= 1e-7 * fine["peak"]
    assert np.abs(fine["u"] - coarse["u"]).max() <= 1e-7 * fine["peak"]
    ke = 0.5 * (fine["v"] ** 2).sum(axis=1)
    bal = ke + fine["work_friction"] + fine["work_floor"]
    assert np.abs(bal).max() <= 1e-9 * fine["work_friction"][-1]


@pytest.mark.slow
def test_floor_system_one_axis_equals_1d_reference():
    """A building under x only (the y ground at rest): the 1-D DOP853 building + block reference
    of tests/reference.py, to 1e-8 on peak and residual (measured 1e-14)."""
    acc, dt = _elc()
    n = 1000
    res = slide2d_reference(acc[:n], np.zeros(n), dt, 0.3, floor_systems=FLOORS)
    peak, resid = rigid_block_on_system(*FLOORS[0], acc[:n], dt, 0.3)
    assert res["stops"] >= 3
    assert abs(res["peak"] - peak) <= 1e-8 * peak
    assert abs(res["residual"][0] - resid) <= 1e-8 * peak
    assert np.all(res["u"][:, 1] == 0.0)


def test_isotropy():
    """Rotating both input components by 40° rotates the response: same peak (1e-9), peak
    angle +40°, u rotated at every sample (1e-9 of the peak; measured 2e-15)."""
    ax, ay, dt = _pair()
    n = 1200
    base = _run_pair(0.2, n=n)
    c, s = math.cos(math.radians(40)), math.sin(math.radians(40))
    rot = slide2d_reference(c * ax[:n] - s * ay[:n], s * ax[:n] + c * ay[:n], dt, 0.2)
    assert abs(rot["peak"] - base["peak"]) <= 1e-9 * base["peak"]
    dang = (rot["peak_angle"] - base["peak_angle"] - 40.0 + 180.0) % 360.0 - 180.0
    assert abs(dang) <= 1e-6
    u_rot = base["u"] @ np.array([[c, s], [-s, c]])
    assert np.abs(rot["u"] - u_rot).max() <= 1e-9 * base["peak"]


@pytest.mark.slow
def test_independent_of_numerical_parameters(monkeypatch):
    """The stiff integrator of the slide starts (Radau vs BDF), the length of the analytic first
    step (1e-7 vs 1e-8 s) and the switch speed to DOP853 (×10) change nothing beyond 1e-9 of the
    peak (measured ≤ 8e-13) on a 2-D record with many breakaways (mu_s = mu_k: every start is
    the stiff tie case)."""
    n = 1000
    base = _run_pair(0.1, n=n)
    assert base["slips"] >= 10 and base["stiff_segments"] >= 10
    ax, ay, dt = _pair()
    runs = [slide2d_reference(ax[:n], ay[:n], dt, 0.1, stiff_method="BDF")]
    monkeypatch.setattr(ref2d, "MINI_STEP", 1e-8)
    runs.append(slide2d_reference(ax[:n], ay[:n], dt, 0.1))
    monkeypatch.setattr(ref2d, "MINI_STEP", 1e-7)
    monkeypatch.setattr(ref2d, "R_SWITCH_FRACTION", 1.0 / 30.0)
    runs.append(slide2d_reference(ax[:n], ay[:n], dt, 0.1))
    for res in runs:
        assert res["stops"] == base["stops"]
        assert abs(res["peak"] - base["peak"]) <= 1e-9 * base["peak"]
        assert np.abs(res["u"] - base["u"]).max() <= 1e-9 * base["peak"]


def test_event_cap_and_arguments():
    acc, dt = _elc()
    with pytest.raises(RuntimeError, match="events"):
        slide2d_reference(acc, np.zeros_like(acc), dt, 0.1, max_events=3)
    with pytest.raises(ValueError):
        slide2d_reference(acc, acc[:-1], dt, 0.1)
    with pytest.raises(ValueError):
        slide2d_reference(acc, acc, dt, 0.1, stiff_method="RK45")
    res = slide2d_reference(np.zeros(5), np.zeros(5), dt, 0.1)
    assert res["peak"] == 0.0 and res["slips"] == 0 and res["events"] == []
