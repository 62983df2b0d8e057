"""Rigid blocks on the floors of buildings on nonlinear isolation (issue 14): the chain ground →
nonlinear building → block, exact end to end."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.nonlinear import isolator_response
from tests.conftest import SLAMMER, G
from tests.reference import rigid_block_ground


@pytest.fixture(scope="module")
def elc() -> np.ndarray:
    return np.loadtxt(SLAMMER / "ImperialValley_1940_ELC-180.txt") * G


def building(isolator, stories=2):
    sup = fs.ShearBuilding.from_period(stories=stories, period=0.4, damping=0.03)
    return fs.NonlinearIsolatedBuilding(sup, 1.0, isolator)


def test_frictionless_pendulum_equals_the_linear_isolated_roof(elc):
    """mu = 0: the blocks slide on the roof as on the linear isolated building's (fs.slide)."""
    b = building(fs.FrictionPendulum(mu=0.0, period=3.0))
    lin = fs.IsolatedBuilding(b.superstructure, 1.0, 3.0, 0.0)
    mus = [0.02, 0.05, 0.1, 0.2]
    r = fs.slide(elc, 0.01, mus, building=b, floor=2)
    ref = fs.slide(elc, 0.01, mus, building=lin, floor=2)
    assert ref.peak_slide[:3].min() > 0.1  # they do slide
    np.testing.assert_allclose(r.peak_slide, ref.peak_slide, rtol=1e-11, atol=1e-14)
    np.testing.assert_allclose(r.residual_slide, ref.residual_slide, rtol=0, atol=1e-11)
    np.testing.assert_allclose(r.peak_abs_accel, ref.peak_abs_accel, rtol=1e-11)
    np.testing.assert_array_equal(r.slip_phases, ref.slip_phases)


@pytest.mark.parametrize(
    "isolator",
    [
        fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02),
        fs.FrictionPendulum(mu=0.06, period=3.0),
    ],
    ids=["bilinear", "pendulum"],
)
def test_against_a_block_on_finely_sampled_floor_motion(elc, isolator):
    """An independent check of the chain: the building's roof acceleration sampled at dt/n
    (exact there; the record interpolated linearly, which leaves it unchanged) drives the
    closed-form rigid-block reference of tests/reference.py, which reads it as piecewise linear —
    an O((dt/n)²) approximation of the true roof motion that converges on the exact chain."""
    a = 1.5 * elc[:800]
    dt = 0.01
    b = building(isolator)
    mus = [0.05, 0.1]
    exact = fs.slide(a, dt, mus, building=b, floor=2)
    assert exact.peak_slide.min() > 0.01
    t = np.arange(a.size) * dt
    errors = []
    for n in (4, 16):
        tf = np.arange((a.size - 1) * n + 1) * (dt / n)
        roof = isolator_response(b, np.interp(tf, t, a), dt / n, floors=[2]).floor_acceleration[0]
        ref = np.array([rigid_block_ground(roof, dt / n, mu)[0] for mu in mus])
        errors.append(np.abs(ref - exact.peak_slide).max() / exact.peak_slide.max())
    # measured: 3.1e-5 → 1.9e-6 (bilinear), 1.9e-4 → 1.2e-5 (pendulum); 1.2e-7 and 7.3e-7 at
    # dt/64: O(h²) convergence on the exact chain
    assert errors[1] < 5e-5
    assert errors[1] < errors[0] / 10


def test_a_block_that_never_slides_feels_the_true_peak_floor_acceleration(elc):
    b = building(fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02))
    r = fs.slide(elc, 0.01, [5.0], building=b, floor=2)
    pfa = isolator_response(b, elc, 0.01, floors=[2]).pfa[0]
    assert r.peak_slide[0] == 0.0 and r.slip_phases[0] == 0
    assert r.peak_abs_accel[0] == pytest.approx(pfa, rel=1e-12)


def test_fs_slide_takes_a_building_or_its_floor_motion(elc):
    """A building on nonlinear isolation with floor=, or a floor of its motion integrated once:
    the same bits; the approximate methods are refused in one line, and vertical shaking
    scales the bearing too (tests/contents/test_vertical_on_isolation.py): a motion integrated
    without it is refused."""
    b = building(fs.FrictionPendulum(mu=0.06, period=3.0))
    via_slide = fs.slide(elc[:600], 0.01, [0.05, 0.1], building=b, floor=2)
    direct = fs.slide(b.motion(elc[:600], 0.01).floor(2), mu_k=[0.05, 0.1])
    np.testing.assert_array_equal(via_slide.peak_slide, direct.peak_slide)
    with pytest.raises(fs.ModelError, match="not available"):
        fs.slide(elc[:600], 0.01, 0.1, building=b, floor=2, method="newmark")
    with pytest.raises(fs.ModelError, match="integrated without the vertical"):
        fs.slide(b.motion(elc[:600], 0.01).floor(2), mu_k=0.1, vertical=0.3 * elc[:600])


def test_flexible_equipment_on_a_frictionless_pendulum_equals_the_linear_isolated_roof(elc):
    """The 2-DOF sliding oscillator (6 Hz, 2 %, r = 0.5) riding along: with mu = 0 it equals
    fs.slide_oscillator on the linear isolated building."""
    b = building(fs.FrictionPendulum(mu=0.0, period=3.0))
    lin = fs.IsolatedBuilding(b.superstructure, 1.0, 3.0, 0.0)
    mus = [0.02, 0.05, 0.1]
    r = fs.slide_oscillator(elc, 0.01, mus, 6.0, 0.02, 0.5, building=b, floor=2)
    ref = fs.slide_oscillator(elc, 0.01, mus, 6.0, 0.02, 0.5, building=lin, floor=2)
    for name in ("peak_slide", "residual_slide", "peak_deformation", "peak_top_accel"):
        a, c = getattr(r, name), getattr(ref, name)
        assert np.abs(a - c).max() <= 1e-11 * np.abs(c).max(), name
    np.testing.assert_array_equal(r.slip_phases, ref.slip_phases)


def test_flexible_equipment_histories_on_a_frictionless_pendulum(elc):
    """Issue 14: the 2-DOF oscillator's histories (u, z, top and base accelerations) on a
    building on nonlinear isolation: with mu = 0 those of the linear isolated roof."""
    b = building(fs.FrictionPendulum(mu=0.0, period=3.0))
    lin = fs.IsolatedBuilding(b.superstructure, 1.0, 3.0, 0.0)
    mus = [0.02, 0.1]
    kw = dict(building=b, floor=2, histories=True)
    r = fs.slide_oscillator(elc, 0.01, mus, 6.0, 0.02, 0.5, **kw)
    ref = fs.slide_oscillator(elc, 0.01, mus, 6.0, 0.02, 0.5, **{**kw, "building": lin})
    for name in ("u", "z", "top_accel", "base_accel"):
        a, c = getattr(r, name), getattr(ref, name)
        assert a.shape == c.shape == (2, elc.size), name
        assert np.abs(a - c).max() <= 1e-10 * np.abs(c).max(), name
    # the histories end where the results do, and their peaks are bounded by the true peaks
    np.testing.assert_array_equal(r.u[:, -1], r.residual_slide)
    assert np.all(np.abs(r.u).max(axis=1) <= r.peak_slide)
    assert np.abs(r.u).max() > 1e-3  # the bases do slide
