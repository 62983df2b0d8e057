"""Consumers on a building on friction pendulums under two components: its exact motion in the
plane (floorslide.building.plane_isolation.PlaneIsolatedMotion, polynomial segments) read by
the plane slide and the spectra on segments — against the 1-D building along an azimuth, the
linear building without friction, and the public API (docs/design.md §10b)."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.plane_isolation import PlaneIsolatedMotion
from floorslide.constants import G
from floorslide.contents.plane_segments import slide_plane_on_segments
from floorslide.errors import ModelError
from floorslide.spectra.poly_segments import rotd_on_poly, spectrum_on_poly
from tests.building.test_plane_isolation import building

PERIODS = [0.2, 0.5, 1.0, 3.0]
MU = [0.03, 0.1, 0.3]


@pytest.fixture(scope="module")
def strong(elcentro):
    ag, dt = elcentro
    return 2.0 * ag[:1201], dt


@pytest.mark.parametrize("deg", [0.0, 37.0, 90.0])
def test_along_an_azimuth_blocks_and_spectra_are_the_1d_buildings(strong, deg):
    """Along azimuth θ the floor moves on that line as the 1-D building's floor (its own
    segment solver): the plane slide equals the 1-D slide and the spectrum along θ equals the
    1-D floor spectrum, ≤ 1e-10 (measured: ≤ 2e-12)."""
    a, dt = strong
    b = building(stories=2, mu_s=0.07)
    th = np.radians(deg)
    motion = PlaneIsolatedMotion(b, a * np.cos(th), a * np.sin(th), dt)
    # the mat (floor 0) too, whose acceleration jumps at the bearing's stops, on the axes
    for floor in (1, 2) if 0.0 < deg < 90.0 else (0, 1, 2):
        one = fs.slide(a, dt, MU, building=b, floor=floor)
        got = slide_plane_on_segments(motion, floor, MU, compare_1d=False)
        assert one.peak_slide.max() > 0.01
        np.testing.assert_allclose(got.peak_slide, one.peak_slide, rtol=1e-10, atol=1e-14)
        np.testing.assert_allclose(
            got.residual @ [np.cos(th), np.sin(th)], one.residual_slide, rtol=0,
            atol=1e-10 * one.peak_slide.max(),
        )  # fmt: skip
        sp1 = fs.response_spectrum(a, dt, PERIODS, building=b, floor=floor)
        sp = spectrum_on_poly(motion, floor, PERIODS, direction=deg)
        np.testing.assert_allclose(sp.psa, sp1.psa, rtol=1e-10)


def test_without_friction_it_is_the_linear_building_in_both_directions(strong):
    """mu = 0: blocks and RotD on the pendulum building equal those on the linear building of
    the pendulum's stiffness and damping (each direction under its component), ≤ 1e-10."""
    a, dt = strong
    h1, h2 = a[:801], 0.6 * a[200:1001]
    b = building(stories=2, mu=0.0, damping=0.05)
    lin = b.equivalent_linear(1.0)
    got = fs.slide_plane((h1, h2), dt, MU, building=b, floor=2)
    ref = fs.slide_plane((h1, h2), dt, MU, building=lin, floor=2)
    np.testing.assert_allclose(got.peak_slide, ref.peak_slide, rtol=1e-10)
    np.testing.assert_allclose(got.residual, ref.residual, rtol=0, atol=1e-10)
    r1 = fs.rotd_spectrum((h1, h2), dt, PERIODS, building=b, floor=2)
    r2 = fs.rotd_spectrum((h1, h2), dt, PERIODS, building=lin, floor=2)
    np.testing.assert_allclose(r1.rotd50, r2.rotd50, rtol=1e-10)
    np.testing.assert_allclose(r1.rotd100, r2.rotd100, rtol=1e-10)


def test_constant_vertical_is_a_stronger_gravity_for_bearing_and_blocks(strong):
    """A constant vertical acceleration c scales the bearing's friction and restoring force and
    the blocks' friction by (1 + c/g): blocks on the pendulum building under c equal blocks
    with mu (1 + c/g) on the pendulum of radius R/(1 + c/g) and friction mu (1 + c/g),
    ≤ 1e-9 (measured: 2.7e-14)."""
    a, dt = strong
    h1, h2 = a, 0.7 * a[::-1].copy()
    c = 0.3 * G
    s = 1.0 + c / G
    R = G * (3.0 / (2 * np.pi)) ** 2
    b = building(stories=2, mu=0.05)
    eq = building(stories=2, mu=0.05 * s, fps_period=2 * np.pi * np.sqrt(R / s / G))
    mu = np.array(MU)
    got = fs.slide_plane((h1, h2), dt, mu, building=b, floor=2, vertical=np.full_like(h1, c))
    ref = fs.slide_plane((h1, h2), dt, mu * s, building=eq, floor=2)
    assert ref.peak_slide.max() > 0.01
    np.testing.assert_allclose(got.peak_slide, ref.peak_slide, rtol=1e-9)
    np.testing.assert_allclose(got.residual, ref.residual, rtol=0, atol=1e-9 * ref.peak_slide.max())


def test_the_public_api_reads_the_coupled_motion(strong):
    """fs.slide_plane and fs.rotd_spectrum on a pendulum building (one model, or a model per
    direction on one mat) read its plane motion, and on a lead-rubber building its own
    (tests/building/test_plane_bilinear.py); approximate methods are refused in one line."""
    a, dt = strong
    h1, h2 = a, 0.8 * a[::-1].copy()
    b = building(stories=2)
    motion = PlaneIsolatedMotion(b, h1, h2, dt)
    direct = slide_plane_on_segments(motion, 1, MU)
    api = fs.slide_plane((h1, h2), dt, MU, building=b, floor=1)
    np.testing.assert_array_equal(api.peak_slide, direct.peak_slide)
    rd = rotd_on_poly(motion, 1, PERIODS)
    ra = fs.rotd_spectrum((h1, h2), dt, PERIODS, building=b, floor=1)
    np.testing.assert_array_equal(ra.rotd50, rd.rotd50)
    pair_of_models = (b, building(stories=2, period=0.5))
    res = fs.slide_plane((h1, h2), dt, MU, building=pair_of_models, floor=2)
    assert np.all(np.isfinite(res.peak_slide))
    sup = fs.ShearBuilding.from_period(stories=2, period=0.3, damping=0.03)
    lrb = fs.NonlinearIsolatedBuilding(
        sup, 1.0, fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02)
    )
    res = fs.slide_plane((h1, h2), dt, MU, building=lrb, floor=1)
    assert np.all(np.isfinite(res.peak_slide)) and res.peak_slide.max() > 0.0
    with pytest.raises(ModelError, match="method"):
        fs.slide_plane((h1, h2), dt, MU, building=b, floor=1, method="newmark")
