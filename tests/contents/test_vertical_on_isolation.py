"""Vertical shaking on a building on nonlinear isolation in 1-D (issue 31, docs/design.md §10b):
on lead-rubber the vertical scales the blocks' friction only (the layer does not feel it), on
friction pendulums the bearing's friction and restoring force too. Against the linear building
a lead-rubber layer that never yields is, a constant vertical's closed-form equivalents, and the
plane solver on its axis."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.constants import G
from floorslide.errors import ModelError

MU = [0.03, 0.08, 0.2]


@pytest.fixture(scope="module")
def record(elcentro):
    ag, dt = elcentro
    a = 1.5 * ag[:1501]
    av = 0.4 * ag[200:1701][::-1].copy()  # a vertical of its own, as strong as 0.4 of it
    return a, av, dt


def _lrb(yield_disp=0.02, q_ratio=0.06):
    sup = fs.ShearBuilding.from_period(stories=2, period=0.3, damping=0.03)
    iso = fs.BilinearIsolator(q_ratio=q_ratio, period=2.5, yield_disp=yield_disp)
    return fs.NonlinearIsolatedBuilding(sup, 1.0, iso)


def _fps(mu=0.05, period=3.0):
    sup = fs.ShearBuilding.from_period(stories=2, period=0.3, damping=0.03)
    return fs.NonlinearIsolatedBuilding(sup, 1.0, fs.FrictionPendulum(mu=mu, period=period))


def test_lead_rubber_that_never_yields_is_the_linear_building_with_vertical(record):
    """A lead-rubber layer whose yield displacement the record never reaches is the linear
    building of stiffness k1: blocks with a varying vertical on its segments equal the linear
    building's exact solver with vertical (≤ 1e-10 of the peak; measured ≤ 1.3e-13)."""
    a, av, dt = record
    b = _lrb(yield_disp=1.0, q_ratio=1.0)
    lin = b.equivalent_linear(1e-3)
    for floor in (0, 2):
        got = fs.slide(a, dt, MU, building=b, floor=floor, vertical=av, histories=True)
        ref = fs.slide(a, dt, MU, building=lin, floor=floor, vertical=av, histories=True)
        top = ref.peak_slide.max()
        assert top > 0.005 and ref.slip_phases.sum() > 3
        np.testing.assert_allclose(got.peak_slide, ref.peak_slide, rtol=0, atol=1e-10 * top)
        np.testing.assert_allclose(got.residual_slide, ref.residual_slide, rtol=0,
                                   atol=1e-10 * top)  # fmt: skip
        np.testing.assert_array_equal(got.slip_phases, ref.slip_phases)
        np.testing.assert_allclose(got.peak_abs_accel, ref.peak_abs_accel, rtol=1e-10)
        np.testing.assert_allclose(got.u, ref.u, rtol=0, atol=1e-10 * top)
        assert got.liftoff_time == ref.liftoff_time and got.liftoff_count == ref.liftoff_count


def test_lead_rubber_under_a_constant_vertical_is_a_higher_friction(record):
    """The layer ignores the vertical; a block's friction under a constant ``c`` is
    ``mu (g + c)``: the same as ``mu (1 + c/g)`` without vertical, on the yielding layer
    (≤ 1e-10 of the peak; measured 4e-16)."""
    a, _, dt = record
    b = _lrb()
    c = 0.25 * G
    s = 1.0 + c / G
    got = fs.slide(a, dt, MU, building=b, floor=2, vertical=np.full_like(a, c))
    ref = fs.slide(a, dt, np.array(MU) * s, building=b, floor=2)
    top = ref.peak_slide.max()
    assert top > 0.005
    np.testing.assert_allclose(got.peak_slide, ref.peak_slide, rtol=0, atol=1e-10 * top)
    np.testing.assert_allclose(got.peak_abs_accel, ref.peak_abs_accel, rtol=1e-10)


def test_pendulum_under_a_constant_vertical_is_the_scaled_pendulum(record):
    """On friction pendulums the vertical acts on the bearing too: a constant ``c`` is the
    pendulum of radius ``R/(1 + c/g)`` and friction ``mu(1 + c/g)`` with blocks of friction
    ``mu_b(1 + c/g)`` — the 1-D building's own solver without vertical (≤ 1e-10 of the peak;
    measured ≤ 1.4e-13)."""
    a, _, dt = record
    c = 0.25 * G
    s = 1.0 + c / G
    b = _fps()
    R = b.isolator.R
    eq = _fps(mu=0.05 * s, period=2 * np.pi * np.sqrt(R / s / G))
    for floor in (1, 2):
        got = fs.slide(a, dt, MU, building=b, floor=floor, vertical=np.full_like(a, c),
                       histories=True)  # fmt: skip
        ref = fs.slide(a, dt, np.array(MU) * s, building=eq, floor=floor, histories=True)
        top = ref.peak_slide.max()
        assert top > 0.005
        np.testing.assert_allclose(got.peak_slide, ref.peak_slide, rtol=0, atol=1e-10 * top)
        np.testing.assert_allclose(got.residual_slide, ref.residual_slide, rtol=0,
                                   atol=1e-10 * top)  # fmt: skip
        np.testing.assert_array_equal(got.slip_phases, ref.slip_phases)
        np.testing.assert_allclose(got.u, ref.u, rtol=0, atol=1e-10 * top)
        assert np.isnan(got.peak_abs_accel).all()
        assert any("peak_abs_accel is not tracked" in n for n in got.notes)


def test_pendulum_with_a_varying_vertical_is_the_plane_solver_on_its_axis(record):
    """With a varying vertical the 1-D slide on friction pendulums is the coupled plane
    integrator under the record and a still second component (its blocks on the axis), and the
    vertical changes the answer."""
    a, av, dt = record
    b = _fps()
    got = fs.slide(a, dt, MU, building=b, floor=2, vertical=av)
    plane = fs.slide_plane((a, np.zeros_like(a)), dt, MU, building=b, floor=2, vertical=av)
    np.testing.assert_array_equal(got.peak_slide, plane.peak_slide)
    np.testing.assert_array_equal(got.residual_slide, plane.residual[:, 0])
    assert (plane.residual[:, 1] == 0.0).all()
    without = fs.slide(a, dt, MU, building=b, floor=2)
    assert np.abs(got.peak_slide - without.peak_slide).max() > 1e-4


def test_what_is_not_modelled_is_refused_in_one_line(record):
    a, av, dt = record
    b = _fps()
    with pytest.raises(ModelError, match="one-way sliding with vertical shaking on friction"):
        fs.slide(a, dt, MU, building=b, floor=2, vertical=av, direction="positive")
    fm = b.motion(a, dt, floors=[2]).floor(2)
    with pytest.raises(ModelError, match="integrated without the vertical"):
        fs.slide(fm, None, MU, vertical=av)
    with pytest.raises(ModelError, match="vertical has 10 samples"):
        fs.slide(a, dt, MU, building=_lrb(), floor=2, vertical=av[:10])
    with pytest.raises(ModelError, match="lift off"):
        fs.slide(a, dt, MU, building=b, floor=2, vertical=np.full_like(a, -1.2 * G))
