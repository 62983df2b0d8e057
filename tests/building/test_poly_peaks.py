"""True floor peaks, kept motions and one component of a poly motion (floorslide.building.
poly_peaks): against the 1-D building along an azimuth, a dense evaluation of the polynomials,
and rocking on the 1-D building on nonlinear isolation (docs/design.md §6)."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.exact_motion import building_motion
from floorslide.building.plane_isolation import PlaneIsolatedMotion
from floorslide.building.poly_peaks import KeptPolyMotion, PolyComponent, poly_peaks
from floorslide.building.poly_segments import poly_values
from floorslide.errors import ModelError
from tests.building.test_plane_isolation import PAIRS, building, read_pair


@pytest.fixture(scope="module")
def strong(elcentro):
    ag, dt = elcentro
    return 2.0 * ag[:1201], dt


@pytest.mark.parametrize("deg", [0.0, 37.0, 90.0])
def test_along_an_azimuth_the_peaks_are_the_1d_buildings(strong, deg):
    """The vector's peak equals the 1-D building's true floor peaks (its own in-step search),
    and the components are its projections: ≤ 1e-12 (measured ≤ 3e-13)."""
    a, dt = strong
    b = building(stories=2, mu_s=0.07)
    th = np.radians(deg)
    pk = poly_peaks(PlaneIsolatedMotion(b, a * np.cos(th), a * np.sin(th), dt))
    p1, t1 = building_motion(b, a, dt).peaks([0, 1, 2])
    np.testing.assert_allclose(pk.peak, p1, rtol=1e-12)
    np.testing.assert_allclose(pk.time, t1, rtol=0, atol=1e-9)
    np.testing.assert_allclose(pk.components[:, 0], p1 * abs(np.cos(th)), rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(pk.components[:, 1], p1 * abs(np.sin(th)), rtol=1e-12, atol=1e-13)


def test_peaks_bound_and_attain_a_dense_evaluation():
    """On a real pair the peaks are at least the largest of 64 points per segment and exceed it
    by no more than the in-segment curvature allows (≤ 1e-6 relative); the stated time gives
    the stated peak."""
    pair = read_pair(PAIRS / "RSN1084_NORTHR_SCS052.AT2", PAIRS / "RSN1084_NORTHR_SCS142.AT2")
    sl = slice(1200, 2400)
    b = building(stories=3, mu_s=0.08)
    motion = KeptPolyMotion(PlaneIsolatedMotion(b, pair.h1[sl], pair.h2[sl], pair.dt))
    pk = poly_peaks(motion)
    tau = np.linspace(0.0, 1.0, 64)
    dense = np.zeros((4, 3))
    best_t = np.zeros(4)
    for seg in motion.poly_chunks():
        v = poly_values(seg.coef[:, :, :, None, :],
                        (seg.length[:, None] * tau)[:, None, None, :])  # fmt: skip
        mag = np.hypot(v[:, :, 0], v[:, :, 1])  # (nseg, nfl, 64)
        flat = mag.max(axis=2).max(axis=0)
        i = np.argmax(mag.max(axis=2), axis=0)
        for f in range(4):
            if flat[f] > dense[f, 0]:
                dense[f, 0] = flat[f]
                best_t[f] = seg.t0[i[f]]
        dense[:, 1:] = np.maximum(dense[:, 1:], np.abs(v).max(axis=3).max(axis=0))
    assert (pk.peak >= dense[:, 0]).all()
    assert (pk.peak <= dense[:, 0] * (1 + 1e-6)).all()
    assert (pk.components >= dense[:, 1:]).all()
    assert (pk.components <= dense[:, 1:] * (1 + 1e-6)).all()
    assert np.abs(pk.time - best_t).max() < pair.dt


def test_a_kept_motion_is_the_streamed_one(strong):
    a, dt = strong
    b = building(stories=2)
    m = PlaneIsolatedMotion(b, a, 0.5 * a[::-1].copy(), dt)
    kept, streamed = KeptPolyMotion(m), KeptPolyMotion(m, max_bytes=0)
    assert kept.kept and not streamed.kept
    for x, y in zip(kept.poly_chunks(), m.poly_chunks(), strict=True):
        np.testing.assert_array_equal(x.coef, y.coef)
        np.testing.assert_array_equal(x.t0, y.t0)
    assert kept.response is m.response and kept.floors == m.floors
    np.testing.assert_array_equal(poly_peaks(streamed).peak, poly_peaks(kept).peak)


@pytest.mark.parametrize("method", ["exact", "nonlinear"])
@pytest.mark.parametrize("direction", [0, 1])
def test_rocking_on_one_component_is_rocking_on_the_1d_building(strong, method, direction):
    """Under one component the other direction is still, and a block rocking along the moving
    one rocks as on the 1-D building on friction pendulums (its own segments): impacts equal,
    θ/α to ≤ 1e-8 (measured ≤ 5e-10: rocking amplifies the 1e-13 difference of the floors)."""
    a, dt = strong
    b = building(stories=2, mu_s=0.07)
    z = np.zeros_like(a)
    h1, h2 = (a, z) if direction == 0 else (z, a)
    m = PlaneIsolatedMotion(b, h1, h2, dt)
    kw = dict(width=[0.3, 0.2, 0.4], height=[1.5, 1.2, 1.0], method=method, histories=True)
    one = fs.rock(a, dt, building=b, floor=2, **kw)
    got = fs.rock(PolyComponent(m, 2, direction), **kw)
    assert one.impacts.sum() > 10 and one.overturned.any()
    np.testing.assert_array_equal(got.impacts, one.impacts)
    np.testing.assert_array_equal(got.overturned, one.overturned)
    np.testing.assert_allclose(got.peak_ratio, one.peak_ratio, rtol=1e-8)
    ok = ~np.isnan(one.theta)
    assert np.array_equal(ok, ~np.isnan(got.theta))
    err = np.abs(got.theta - one.theta)[ok] / np.repeat(one.alpha, ok.sum(axis=1))
    assert err.max() < 1e-8
    # the still direction: nothing moves a block there
    still = fs.rock(PolyComponent(m, 2, 1 - direction), **kw)
    assert (still.peak_ratio == 0).all()


def test_a_component_is_refused_what_it_cannot_do(strong):
    a, dt = strong
    m = PlaneIsolatedMotion(building(), a, a, dt)
    with pytest.raises(ModelError, match="direction must be 0 or 1"):
        PolyComponent(m, 1, 2)
    with pytest.raises(ModelError, match="floor 5 is not in the motion"):
        PolyComponent(m, 5, 0)
    with pytest.raises(ModelError, match="method='rk4' reads samples"):
        fs.rock(PolyComponent(m, 1, 0), width=0.3, height=1.5, method="rk4")
    with pytest.raises(ModelError, match="give no building= or floor="):
        fs.rock(PolyComponent(m, 1, 0), width=0.3, height=1.5, floor=1)


@pytest.mark.parametrize("kind", ["pendulum", "lead-rubber"])
def test_segments_kept_by_the_first_pass_are_the_streamed_ones(elcentro, kind):
    """``keep_segments``: the segments recorded on the motion's one pass equal those its
    checkpoints integrate again, bit for bit (the whole record: several chunks), and its
    response is the same."""
    ag, dt = elcentro
    a = 2.0 * ag
    if kind == "pendulum":
        b = building(stories=2)
    else:
        sup = fs.ShearBuilding.from_period(stories=2, period=0.3, damping=0.03)
        b = fs.NonlinearIsolatedBuilding(
            sup, 1.0, fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02)
        )
    h2 = 0.5 * a[::-1].copy()
    kept = PlaneIsolatedMotion(b, a, h2, dt, keep_segments=True)
    streamed = PlaneIsolatedMotion(b, a, h2, dt)
    np.testing.assert_array_equal(kept.response.displacement, streamed.response.displacement)
    assert kept.response.friction_work == streamed.response.friction_work
    chunks = list(kept.poly_chunks())
    assert len(chunks) == len(list(streamed.poly_chunks())) >= 2
    for x, y in zip(chunks, streamed.poly_chunks(), strict=True):
        np.testing.assert_array_equal(x.coef, y.coef)
        np.testing.assert_array_equal(x.t0, y.t0)
        np.testing.assert_array_equal(x.ends, y.ends)
