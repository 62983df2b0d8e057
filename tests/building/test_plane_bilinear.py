"""A building on lead-rubber (bilinear) bearings under two horizontal components (a circular
yield surface coupled with the superstructure, floorslide/building/_plane_bilinear_kernel.py)
against the 1-D building along any azimuth, the linear buildings it tends to, the independent
reference tests/reference_bilinear_2d.py on real pairs, and the consumers that read its motion
(docs/design.md §10b, "In the plane")."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.isolators import BilinearIsolator
from floorslide.building.nonlinear import NonlinearIsolatedBuilding, isolator_response
from floorslide.building.plane_isolation import (
    PlaneIsolatedMotion,
    plane_isolator_response,
    plane_layer,
)
from floorslide.records.pairs import read_pair
from tests.conftest import ROOT
from tests.reference_bilinear_2d import bilinear_response_2d

PAIRS = ROOT / "data" / "records" / "pairs"
PERIODS = [0.2, 0.5, 1.0, 3.0]
MU = [0.03, 0.1, 0.3]


def building(stories=1, period=0.3, q_ratio=0.06, lrb_period=2.5, yield_disp=0.02, ratio=1.0,
             **kw):  # fmt: skip
    m = 1e5
    k = m * (2 * np.pi / period) ** 2 * stories
    sup = fs.ShearBuilding(masses=[m] * stories, stiffnesses=[k] * stories, damping=0.02)
    iso = BilinearIsolator(q_ratio=q_ratio, period=lrb_period, yield_disp=yield_disp, **kw)
    return NonlinearIsolatedBuilding(sup, ratio, iso)


@pytest.fixture(scope="module")
def strong(elcentro):
    ag, dt = elcentro
    return 2.0 * ag[:1201], dt


@pytest.mark.parametrize("deg", [0.0, 37.0, 90.0, 200.0])
def test_along_any_azimuth_it_is_the_1d_building(strong, deg):
    """A pair along azimuth θ moves the mat and every floor on that line as the 1-D building
    under the record (its own exact event-driven solver, matrix exponentials on each branch):
    ≤ 1e-10 of the peak (measured: 3.8e-14 displacement, 1.1e-13 accelerations), the same
    yields and unloadings at the same times (1.5e-14 s apart) and the same peak force (5e-15)."""
    a, dt = strong
    b = building(stories=2, damping=0.05)
    one = isolator_response(b, a, dt)
    th = np.radians(deg)
    c, s = np.cos(th), np.sin(th)
    r = plane_isolator_response(b, a * c, a * s, dt)
    u1 = one.isolator_displacement
    scale = np.abs(u1).max()
    assert scale > 5 * b.constants["D_y"]  # it does yield
    assert np.abs(r.displacement[:, 0] - c * u1).max() < 1e-10 * scale
    assert np.abs(r.displacement[:, 1] - s * u1).max() < 1e-10 * scale
    assert r.peak_displacement == pytest.approx(one.peak_displacement, rel=1e-10)
    assert abs(r.residual @ [c, s] - one.residual_displacement) < 1e-10 * scale
    assert r.peak_force_ratio == pytest.approx(one.peak_force_ratio, rel=1e-10)
    W = b.weight
    f1 = one.isolator_force
    assert np.abs(r.force_ratio[:, 0] - c * f1 / W).max() < 1e-10 * np.abs(f1).max() / W
    acc = fs.floor_motions(b, a, dt)
    top = np.abs(acc).max()
    assert np.abs(r.floor_acceleration[:, :, 0] - c * acc.T).max() < 1e-10 * top
    assert np.abs(r.floor_acceleration[:, :, 1] - s * acc.T).max() < 1e-10 * top
    # the same events at the same times; yielding where the 1-D layer is on a plastic branch
    assert len(r.event_times) == len(one.event_times) > 4
    np.testing.assert_allclose(r.event_times, one.event_times, rtol=0, atol=1e-9)
    assert r.event_kinds[:2] == ("yield", "unload")
    np.testing.assert_array_equal(r.sliding, np.isin(one.branch, [2, 3]))


def test_vanishing_strength_is_the_linear_building_of_k2(strong):
    """Q → 0 (Q = 1e-13 W): the layer is the linear spring k₂ and the damper in both
    directions — each direction equals the linearly isolated building of period T_d under its
    own component, to rounding (measured: 3.1e-12 of the peak)."""
    a, dt = strong
    ax, ay = a[:801], 0.6 * a[200:1001]
    b = building(stories=3, q_ratio=1e-13, damping=0.05)
    r = plane_isolator_response(b, ax, ay, dt)
    lin = fs.IsolatedBuilding(b.superstructure, 1.0, period=2.5, damping=0.05)
    for d, g in enumerate((ax, ay)):
        ref = fs.floor_motions(lin, g, dt, floors=[0, 1, 2, 3], output="displacement")
        scale = np.abs(ref).max()
        assert np.abs(r.floor_displacement[:, :, d] - ref.T).max() < 1e-10 * scale
        ref = fs.floor_motions(lin, g, dt, floors=[0, 1, 2, 3])
        assert np.abs(r.floor_acceleration[:, :, d] - ref.T).max() < 1e-10 * np.abs(ref).max()


def test_a_layer_that_never_yields_is_the_linear_building_of_k1(strong):
    """A strength far above the demand (Q = 2 W, k₁ = 5 k₂, D_y = 0.78 m): no event, and each
    direction is the linearly isolated building of stiffness k₁ (its period T_d/√5) and the
    layer's damper, to rounding (measured: 1.6e-13 of the peak)."""
    a, dt = strong
    ax, ay = a[:801], 0.6 * a[200:1001]
    b = building(stories=2, q_ratio=2.0, yield_disp=None, alpha=0.2, damping=0.05)
    r = plane_isolator_response(b, ax, ay, dt)
    assert r.event_kinds == () and not r.sliding.any() and r.friction_work == 0.0
    lin = b.equivalent_linear(0.5 * b.constants["D_y"])  # below yield: k₁, the damper
    for d, g in enumerate((ax, ay)):
        ref = fs.floor_motions(lin, g, dt, floors=[0, 1, 2], output="displacement")
        scale = np.abs(ref).max()
        assert np.abs(r.floor_displacement[:, :, d] - ref.T).max() < 1e-10 * scale
        ref = fs.floor_motions(lin, g, dt, floors=[0, 1, 2])
        assert np.abs(r.floor_acceleration[:, :, d] - ref.T).max() < 1e-10 * np.abs(ref).max()


PAIR_CASES = [
    # (components, scale, first sample, storeys): 2 s around each pair's strongest shaking
    ("RSN1084_NORTHR_SCS052.AT2", "RSN1084_NORTHR_SCS142.AT2", 1.0, 1200, 3),
    ("RSN738_LOMAP_NAS180.AT2", "RSN738_LOMAP_NAS270.AT2", 2.0, 2200, 2),
    ("RSN879_LANDERS_LCN260.AT2", "RSN879_LANDERS_LCN345.AT2", 2.5, 2800, 2),
]


@pytest.mark.parametrize("f1, f2, scale, k0, stories", PAIR_CASES)
def test_against_the_independent_reference_on_real_pairs(f1, f2, scale, k0, stories):
    """Every floor and the mat under a real pair (2 s of its strongest shaking; a damped layer
    and, for the first pair, a superstructure per direction), against the event-located DOP853
    reference written apart (tests/reference_bilinear_2d.py): displacements and absolute
    accelerations ≤ 1e-8 of the peak (measured: ≤ 2.3e-13 and ≤ 2.2e-12), the same events
    (≤ 1e-12 s apart; measured 1.1e-13 s), the plastic work ≤ 1e-8 (measured: 1.2e-13)."""
    p = read_pair(PAIRS / f1, PAIRS / f2)
    h1, h2 = scale * p.h1[k0 : k0 + 400], scale * p.h2[k0 : k0 + 400]
    b = building(stories=stories, damping=0.05)
    Ks, Cs = b.stiffness_matrix, b.damping_matrix
    if stories == 3:
        by = building(stories=stories, period=0.5, damping=0.05)
        b = (b, by)
        Ks, Cs = (Ks, by.stiffness_matrix), (Cs, by.damping_matrix)
    r = plane_isolator_response(b, h1, h2, p.dt)
    bx = plane_layer(b)[0]
    ref = bilinear_response_2d(bx.mass, Ks, Cs, bx.constants, h1, h2, p.dt)
    top = max(np.abs(ref["ux"]).max(), np.abs(ref["uy"]).max())
    assert np.hypot(ref["ux"][:, 0], ref["uy"][:, 0]).max() > 2 * bx.constants["D_y"]
    assert len(ref["events"]) >= 4
    for d, key in enumerate("xy"):
        assert np.abs(r.floor_displacement[:, :, d] - ref["u" + key]).max() < 1e-8 * top
        atop = max(np.abs(ref["accx"]).max(), np.abs(ref["accy"]).max())
        assert np.abs(r.floor_acceleration[:, :, d] - ref["acc" + key]).max() < 1e-8 * atop
    assert r.event_kinds == tuple(k for _, k in ref["events"])
    np.testing.assert_allclose(r.event_times, [t for t, _ in ref["events"]], rtol=0, atol=1e-12)
    assert r.friction_work == pytest.approx(ref["plastic_work"], rel=1e-8)
    assert r.peak_displacement >= np.hypot(ref["ux"][:, 0], ref["uy"][:, 0]).max() * (1 - 1e-12)


def test_the_plastic_force_stays_on_its_circle_along_a_whole_record():
    """The element's force q = f − k₂u − cu' (from the bearing force at the samples) is within
    the yield circle |q| ≤ Q everywhere and on it while yielding, to rounding (measured:
    1.8e-15 of Q), over the whole Sylmar pair (8773 samples, 88 events); the plastic work is
    positive and below the work Q·(path of the mat) a force of Q along the motion would do.
    The segments consumers read, integrated again chunk by chunk from the first pass's
    checkpoints (5 chunks), give the floors' accelerations at the samples (measured: 8.3e-14
    of the peak)."""
    from floorslide.building.poly_segments import samples_on_poly

    p = read_pair(PAIRS / "RSN1084_NORTHR_SCS052.AT2", PAIRS / "RSN1084_NORTHR_SCS142.AT2")
    b = building(stories=3, damping=0.05)
    motion = PlaneIsolatedMotion(b, p.h1, p.h2, p.dt)
    r = motion.response
    ref = r.floor_acceleration.transpose(1, 2, 0)
    assert np.abs(samples_on_poly(motion) - ref).max() < 1e-12 * np.abs(ref).max()
    c = b.constants
    q = r.force_ratio * b.weight - c["k2"] * r.displacement - c["c"] * r.velocity
    size = np.hypot(q[:, 0], q[:, 1]) / c["Q"]
    tol = 1e-12 * (1 + c["k2"] * np.abs(r.displacement).max() / c["Q"])
    assert size.max() <= 1 + tol
    assert np.abs(size[r.sliding] - 1).max() <= tol
    assert r.sliding.any() and (~r.sliding).any() and len(r.event_times) > 20
    path = np.hypot(*np.diff(r.displacement, axis=0).T).sum()
    assert 0 < r.friction_work < c["Q"] * path * 1.01
    assert 0 < r.slide_fraction < 1 and not r.small_angle_exceeded


@pytest.mark.parametrize("floor", [0, 2])
def test_consumers_read_it_and_along_an_azimuth_equal_the_1d_building(strong, floor):
    """fs.slide_plane and fs.rotd_spectrum read the coupled motion of a lead-rubber building;
    along azimuth 0 the plane slide equals fs.slide on the 1-D building and RotD100 the 1-D
    floor spectrum, ≤ 1e-10 (measured: ≤ 1e-12)."""
    a, dt = strong
    b = building(stories=2, damping=0.05)
    z = np.zeros_like(a)
    got = fs.slide_plane((a, z), dt, MU, building=b, floor=floor)
    one = fs.slide(a, dt, MU, building=b, floor=floor)
    assert one.peak_slide.max() > 0.01
    np.testing.assert_allclose(got.peak_slide, one.peak_slide, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(got.residual[:, 0], one.residual_slide, rtol=0,
                               atol=1e-10 * one.peak_slide.max())  # fmt: skip
    rd = fs.rotd_spectrum((a, z), dt, PERIODS, building=b, floor=floor)
    sp = fs.response_spectrum(a, dt, PERIODS, building=b, floor=floor)
    np.testing.assert_allclose(rd.rotd100, sp.psa, rtol=1e-10)


def test_the_public_api_on_a_pair_and_a_model_per_direction(strong):
    """Under a true pair, one model or a superstructure per direction on one mat: the plane
    slide and RotD run on the coupled motion and equal the motion's own consumers; vertical
    shaking leaves the bearing as it is (this model's force does not depend on the normal load,
    said in the notes) and scales the blocks' friction: a constant ``c`` is ``mu (1 + c/g)``."""
    from floorslide.contents.plane_segments import slide_plane_on_segments
    from floorslide.spectra.poly_segments import rotd_on_poly

    a, dt = strong
    h1, h2 = a, 0.8 * a[::-1].copy()
    b = building(stories=2)
    motion = PlaneIsolatedMotion(b, h1, h2, dt)
    # the response's states at the samples: the mat's velocity is floor 0's
    np.testing.assert_array_equal(motion.response.floor_velocity[:, 0], motion.response.velocity)
    api = fs.slide_plane((h1, h2), dt, MU, building=b, floor=1)
    np.testing.assert_array_equal(api.peak_slide, slide_plane_on_segments(motion, 1, MU).peak_slide)
    ra = fs.rotd_spectrum((h1, h2), dt, PERIODS, building=b, floor=1)
    np.testing.assert_array_equal(ra.rotd50, rotd_on_poly(motion, 1, PERIODS).rotd50)
    res = fs.slide_plane((h1, h2), dt, MU, building=(b, building(stories=2, period=0.5)), floor=2)
    assert np.all(np.isfinite(res.peak_slide)) and res.peak_slide.max() > 0.0
    c = 0.3 * 9.80665
    with_v = PlaneIsolatedMotion(b, h1, h2, dt, vertical=np.full_like(h1, c))
    np.testing.assert_array_equal(with_v.response.displacement, motion.response.displacement)
    assert any("does not act on the lead-rubber layer" in n for n in with_v.notes)
    got = fs.slide_plane((h1, h2), dt, MU, building=b, floor=1, vertical=np.full_like(h1, c))
    ref = fs.slide_plane((h1, h2), dt, np.array(MU) * (1 + c / 9.80665), building=b, floor=1)
    np.testing.assert_allclose(got.peak_slide, ref.peak_slide, rtol=1e-12, atol=1e-15)


def test_circular_ground_motion_gives_the_circular_orbit():
    """A rigid mass on lead-rubber bearings (base mass dominant; T_d = 2.5 s, Q = 0.06 W,
    D_y = 0.02 m, the layer's damping ξ = 0.3 to let the start die out) under
    a = A (cos ωt, sin ωt), A = 3 m/s², ω = 2π, settles on a circle, yielding for ever. With
    u = r e(ωt + ψ) and z = q/Q = e(ωt + ψ + φ), the flow rule D_y z' = v − (z·v) z gives
    D_y ω = r ω cos φ (the element's force leads the displacement by φ, cos φ = D_y/r), and the
    mat's equation |(ω₂² − ω² + iωc) r + (Q/M) e^{iφ}| = A (ω₂² = k₂/M, c per unit mass)
    gives r = 0.0846208 m: reached to the piecewise-linear record's O(dt²) (measured: 1.3e-5
    at dt = 2 ms, 3.3e-6 at 1 ms)."""
    from scipy.optimize import brentq

    A, w = 3.0, 2 * np.pi
    b = building(ratio=1e9, period=0.05, damping=0.3)
    c = b.constants
    M = b.total_mass
    w2, q, cm, dy = c["k2"] / M, c["Q"] / M, c["c"] / M, c["D_y"]

    def residual(r):
        cos = dy / r
        return (
            ((w2 - w * w) * r + q * cos) ** 2 + (w * cm * r + q * np.sqrt(1 - cos**2)) ** 2 - A**2
        )

    rr = brentq(residual, dy * (1 + 1e-12), 10.0, xtol=1e-15, rtol=1e-15)
    assert rr == pytest.approx(0.0846208, abs=1e-7)
    errors = []
    for dt in (0.002, 0.001):
        t = np.arange(round(30.0 / dt) + 1) * dt
        out = plane_isolator_response(b, A * np.cos(w * t), A * np.sin(w * t), dt)
        late = t > 25.0
        assert out.event_kinds == ("yield",) and out.sliding[late].all()
        u = out.displacement[late]
        radius = np.hypot(u[:, 0], u[:, 1])
        errors.append(np.abs(radius - rr).max() / rr)
        qv = out.force_ratio[late] * b.weight - c["k2"] * u - c["c"] * out.velocity[late]
        lead = np.arctan2(u[:, 0] * qv[:, 1] - u[:, 1] * qv[:, 0], (u * qv).sum(axis=1))
        assert np.abs(np.cos(lead) - dy / rr).max() < 1e-3
    assert errors[1] < 1e-5
    assert 3.0 < errors[0] / errors[1] < 5.0
