"""Records that start mid-motion: the floor is already beyond the friction limit at t = 0.

A cut record, or one with an offset, can start above ``mu·g``; the block must break away at
t = 0. Every exact solver is checked against references written apart from the package
(``tests/reference.py``): a record, and the same record with its first samples dropped.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import floorslide as fs
from tests.reference import (
    linear_peaks,
    rigid_block_ground,
    rigid_block_on_system,
    sliding_oscillator,
)

G = 9.80665


def spike(first=10.0, n=200):
    a = np.zeros(n)
    a[0] = first * G
    return a


def test_first_sample_beyond_friction_breaks_away_at_once():
    # closed form: slip from t = 0 while a falls linearly from 10 g to 0 over dt, then
    # decelerate at mu·g: u = v1²/(2 mu g) + |u(dt)|, v1 = (10 g/2 − mu g)·dt
    dt, mu = 0.01, 0.1
    v1 = (10 * G / 2 - mu * G) * dt
    u1 = 10 * G * (dt**2 / 2 - dt**2 / 6) - mu * G * dt**2 / 2
    expected = v1**2 / (2 * mu * G) + u1
    assert expected == pytest.approx(0.1209487, abs=5e-8)
    res = fs.slide(spike(), dt, mu)
    assert res.peak_slide[0] == pytest.approx(expected, rel=1e-12)
    assert res.residual_slide[0] == pytest.approx(-expected, rel=1e-12)
    assert res.slip_phases[0] == 1
    # friction transmits at most mu·g: the object never feels the 10 g spike
    assert res.peak_abs_accel[0] == pytest.approx(mu * G, rel=1e-12)
    # mirror image and one-way sliding
    assert fs.slide(-spike(), dt, mu).peak_slide[0] == pytest.approx(expected, rel=1e-12)
    assert fs.slide(spike(), dt, mu, direction="positive").peak_slide[0] == pytest.approx(
        expected, rel=1e-12
    )
    assert fs.slide(-spike(), dt, mu, direction="positive").peak_slide[0] == 0.0


def test_first_sample_beyond_static_friction_only():
    # mu_s > mu_k: a first sample between mu_k·g and mu_s·g does not start the block
    a = spike(first=0.15)
    assert fs.slide(a, 0.01, 0.1, 0.2).peak_slide[0] == 0.0
    assert fs.slide(a, 0.01, 0.1, 0.12).peak_slide[0] == pytest.approx(
        rigid_block_ground(a, 0.01, 0.1, 0.12)[0], rel=1e-12
    )


def test_vertical_shaking_first_sample():
    a = spike()
    vert = np.full(a.size, 0.5 * G)
    res = fs.slide(a, 0.01, 0.1, vertical=vert)
    # friction limit mu·(g + a_v) = 0.15 g throughout: the reference with mu scaled by 1.5
    ref = rigid_block_ground(a, 0.01, 0.15)
    assert res.peak_slide[0] == pytest.approx(ref[0], rel=1e-12)


@pytest.mark.parametrize("r", [0.5, 2.0])
def test_oscillator_first_sample_beyond_friction(r):
    a = spike()
    res = fs.slide_oscillator(a, 0.01, 0.1, 6.0, 0.02, r)
    pu, ures, pz = sliding_oscillator(a, 0.01, 0.1, 6.0, 0.02, r)
    assert pu > 0.1
    assert res.peak_slide[0] == pytest.approx(pu, rel=1e-9)
    assert res.residual_slide[0] == pytest.approx(ures, rel=1e-9)
    assert res.peak_deformation[0] == pytest.approx(pz, rel=1e-7)
    # the base never rides the 10 g spike: in slip its acceleration is bounded by the spring
    # and the friction force, (|q| + mu (1 + r) g)/r
    assert res.peak_base_accel[0] < 0.5 * G


def _record(values, drop):
    a = np.asarray(values, dtype=float) * G
    return a[drop:]


records = st.lists(st.floats(-1.5, 1.5), min_size=12, max_size=40)


@given(records, st.integers(0, 6), st.sampled_from([0.05, 0.2, 0.5]))
def test_ground_record_and_its_tail_against_the_closed_form(values, drop, mu):
    a = _record(values, drop)
    res = fs.slide(a, 0.01, mu)
    peak, resid = rigid_block_ground(a, 0.01, mu)
    assert res.peak_slide[0] == pytest.approx(peak, rel=1e-9, abs=1e-15)
    assert res.residual_slide[0] == pytest.approx(resid, rel=1e-9, abs=1e-14)


@settings(max_examples=25, deadline=None)
@given(records, st.integers(1, 6))
def test_stiff_floor_record_and_its_tail_against_the_ode_reference(values, drop):
    b = fs.ShearBuilding.from_period(stories=1, period=0.1, damping=0.05)
    a = _record(values, drop)
    res = fs.slide(a, 0.01, 0.1, building=b, floor=1)
    A, B = b.state_matrices()
    C, D, _ = b.output_matrices([1], "acceleration")
    peak, resid = rigid_block_on_system(A, B[:, 0], C[0], D[0, 0], a, 0.01, 0.1)
    assert res.peak_slide[0] == pytest.approx(peak, rel=1e-8, abs=1e-14)
    assert res.residual_slide[0] == pytest.approx(resid, rel=1e-8, abs=1e-13)


@settings(max_examples=25, deadline=None)
@given(records, st.integers(1, 6))
def test_oscillator_record_and_its_tail_against_the_reference(values, drop):
    a = _record(values, drop)
    res = fs.slide_oscillator(a, 0.01, 0.1, 6.0, 0.05, 0.5)
    pu, _, pz = sliding_oscillator(a, 0.01, 0.1, 6.0, 0.05, 0.5)
    assert res.peak_slide[0] == pytest.approx(pu, rel=1e-7, abs=1e-13)
    assert res.peak_deformation[0] == pytest.approx(pz, rel=1e-7, abs=1e-13)


@pytest.mark.parametrize("drop", [0, 1, 3])
def test_spectrum_of_a_record_starting_mid_motion(drop):
    a = spike(first=1.0, n=60)
    a[1:10] = np.linspace(0.5, -0.8, 9) * G
    a = a[drop:]
    T, xi = np.array([0.05, 0.2, 1.0]), 0.05
    sp = fs.response_spectrum(a, 0.01, T, xi)
    for i, t in enumerate(T):
        w = 2 * np.pi / t
        A = np.array([[0.0, 1.0], [-(w**2), -2 * xi * w]])
        ref = linear_peaks(A, np.array([0.0, -1.0]), np.array([[1.0, 0.0]]), a, 0.01)
        assert sp.sd[0, i] == pytest.approx(ref[0], rel=1e-9)


@pytest.mark.parametrize(
    ("method", "kw", "rel"),
    [
        ("slammer", {}, 0.01),
        ("newmark", {"substeps": 64}, 1e-5),
        ("solve_ivp", {"max_step": 0.01 / 16, "rtol": 1e-10}, 1e-9),
        ("reinterpolated", {}, 1e-12),
    ],
)
def test_approximate_methods_also_start_at_once(method, kw, rel):
    expected = rigid_block_ground(spike(), 0.01, 0.1)[0]
    for sign in (1, -1):
        res = fs.slide(sign * spike(), 0.01, 0.1, method=method, **kw)
        assert res.peak_slide[0] == pytest.approx(expected, rel=rel)
    assert fs.slide(-spike(), 0.01, 0.1, method=method, direction="positive", **kw).peak_slide[
        0
    ] == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize("method", ["newmark", "penalty"])
def test_approximate_oscillators_start_at_once(method):
    pu = sliding_oscillator(spike(), 0.01, 0.1, 6.0, 0.02, 0.5)[0]
    res = fs.slide_oscillator(spike(), 0.01, 0.1, 6.0, 0.02, 0.5, method=method)
    assert res.peak_slide[0] == pytest.approx(pu, rel=0.01)
