"""A building on friction pendulums under two horizontal components (the friction circle coupled
with the superstructure, floorslide/building/_plane_isolation_kernel.py) against the 1-D
building along any azimuth, closed forms, the linear layer without friction, and the
independent reference tests/reference_isolators_2d.py on real pairs (docs/design.md §10b)."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.isolators import FrictionPendulum
from floorslide.building.nonlinear import NonlinearIsolatedBuilding, isolator_response
from floorslide.building.plane_isolation import plane_isolator_response, plane_layer
from floorslide.constants import G
from floorslide.errors import ModelError
from floorslide.records.pairs import read_pair
from tests.conftest import ROOT
from tests.reference_isolators_2d import circular_orbit, isolated_response_2d

PAIRS = ROOT / "data" / "records" / "pairs"


def building(stories=1, period=0.3, mu=0.05, mu_s=None, fps_period=3.0, ratio=1.0, **kw):
    m = 1e5
    k = m * (2 * np.pi / period) ** 2 * stories
    sup = fs.ShearBuilding(masses=[m] * stories, stiffnesses=[k] * stories, damping=0.02)
    iso = FrictionPendulum(mu=mu, period=fps_period, mu_s=mu_s, **kw)
    return NonlinearIsolatedBuilding(sup, ratio, iso)


@pytest.mark.parametrize("deg", [0.0, 37.0, 90.0, 200.0])
def test_along_any_azimuth_it_is_the_1d_building(elcentro, deg):
    """A pair along azimuth θ moves the mat and every floor on that line as the 1-D building
    under the record (its own exact event-driven solver): ≤ 1e-10 of the peak."""
    ag, dt = elcentro
    a = 2.0 * ag[:1201]
    b = building(stories=2, mu_s=0.07)
    one = isolator_response(b, a, dt)
    th = np.radians(deg)
    r = plane_isolator_response(b, a * np.cos(th), a * np.sin(th), dt)
    u1 = one.isolator_displacement
    scale = np.abs(u1).max()
    assert scale > 0.05  # it does slide
    assert np.abs(r.displacement[:, 0] - np.cos(th) * u1).max() < 1e-10 * scale
    assert np.abs(r.displacement[:, 1] - np.sin(th) * u1).max() < 1e-10 * scale
    assert r.peak_displacement == pytest.approx(one.peak_displacement, rel=1e-10)
    assert abs(r.residual @ [np.cos(th), np.sin(th)] - one.residual_displacement) < 1e-10 * scale
    acc = fs.floor_motions(b, a, dt)
    top = np.abs(acc).max()
    assert np.abs(r.floor_acceleration[:, :, 0] - np.cos(th) * acc.T).max() < 1e-10 * top
    assert np.abs(r.floor_acceleration[:, :, 1] - np.sin(th) * acc.T).max() < 1e-10 * top
    # the same events at the same times
    assert len(r.event_times) == len(one.event_times)
    np.testing.assert_allclose(r.event_times, one.event_times, rtol=0, atol=1e-9)


def test_free_decay_along_an_azimuth_closed_form():
    """The mat (superstructure negligible) released at 0.45 m along 30° on R = 2 m, mu = 0.05:
    extremes 0.45, −0.25, 0.05 m every half period π√(R/g) on that line (each 2 mu R less), then
    stuck inside the friction circle (|u| < mu R)."""
    R, mu, th = 2.0, 0.05, np.radians(30.0)
    d = np.array([np.cos(th), np.sin(th)])
    b = building(mu=mu, ratio=1e9, period=0.05, fps_period=2 * np.pi * np.sqrt(R / G))
    z = np.zeros(601)
    r = plane_isolator_response(b, z, z, 0.01, initial_displacement=0.45 * d)
    half = np.pi * np.sqrt(R / G)
    assert r.event_kinds == ("reverse", "stick")
    np.testing.assert_allclose(r.event_times, [half, 2 * half], rtol=0, atol=1e-5 * half)
    np.testing.assert_allclose(r.residual, 0.05 * d, atol=1e-5 * 0.5)
    cross = -r.displacement[:, 0] * d[1] + r.displacement[:, 1] * d[0]
    assert np.abs(cross).max() < 1e-14
    assert r.peak_displacement == pytest.approx(0.45, rel=1e-14)
    assert r.peak_direction == pytest.approx(30.0, abs=1e-10)


def test_circular_ground_motion_gives_the_circular_orbit():
    """A rigid mass on a friction pendulum (R = 1 m, mu = 0.05) under a = A (cos ωt, sin ωt),
    A = 3 m/s², ω = 2π, started on its steady orbit, stays on the circle
    r = √(A² − (mu g)²)/|g/R − ω²| = 0.0997466 m, to the piecewise-linear record's O(dt²)."""
    A, w, mu, R = 3.0, 2 * np.pi, 0.05, 1.0
    rr, phi = circular_orbit(A, w, mu, R)
    b = building(mu=mu, ratio=1e6, period=0.05, fps_period=2 * np.pi * np.sqrt(R / G))
    errors = []
    for dt in (0.002, 0.001):
        t = np.arange(round(2.0 / dt) + 1) * dt
        u0 = rr * np.array([np.cos(phi), np.sin(phi)])
        v0 = rr * w * np.array([-np.sin(phi), np.cos(phi)])
        out = plane_isolator_response(
            b, A * np.cos(w * t), A * np.sin(w * t), dt, initial_displacement=u0,
            initial_velocity=v0,
        )  # fmt: skip
        assert out.event_kinds == ()  # it never stops
        radius = np.hypot(out.displacement[:, 0], out.displacement[:, 1])
        errors.append(np.abs(radius - rr).max() / rr)
        assert out.slide_fraction == pytest.approx(1.0, abs=1e-12)
    assert errors[1] < 2e-5
    assert 3.0 < errors[0] / errors[1] < 5.0


def test_without_friction_each_direction_is_the_linear_isolated_building(elcentro):
    """mu = 0: the layer is linear (stiffness W/R, the isolator's damping): each direction
    equals the linearly isolated building under its component, to rounding."""
    ag, dt = elcentro
    ax, ay = ag[:801], 0.6 * ag[200:1001]
    b = building(stories=3, mu=0.0, damping=0.05)
    r = plane_isolator_response(b, ax, ay, dt)
    lin = b.equivalent_linear(1.0)  # mu = 0: the pendulum's own period and damping
    for d, a in enumerate((ax, ay)):
        ref = fs.floor_motions(lin, a, dt, floors=[0, 1, 2, 3], output="displacement")
        got = r.floor_displacement[:, :, d]
        scale = np.abs(ref).max()
        assert np.abs(got - ref.T).max() < 1e-12 * scale
        ref = fs.floor_motions(lin, a, dt, floors=[0, 1, 2, 3])
        got = r.floor_acceleration[:, :, d]  # (measured: 1.2e-12 of the peak)
        assert np.abs(got - ref.T).max() < 5e-12 * np.abs(ref).max()


def test_constant_vertical_is_a_pendulum_under_a_stronger_gravity(elcentro):
    """A constant vertical acceleration c scales the normal force by (1 + c/g): the restoring
    force and the friction both, which is the 1-D pendulum of radius R/(1 + c/g) and friction
    mu (1 + c/g) without it."""
    ag, dt = elcentro
    a = 2.0 * ag[:1001]
    c = 0.3 * G
    R, mu = G * (3.0 / (2 * np.pi)) ** 2, 0.05
    b = building(stories=2, mu=mu)
    r = plane_isolator_response(b, a, np.zeros_like(a), dt, vertical=np.full_like(a, c))
    s = 1.0 + c / G
    eq = building(stories=2, mu=mu * s, fps_period=2 * np.pi * np.sqrt(R / s / G))
    one = isolator_response(eq, a, dt)
    scale = np.abs(one.isolator_displacement).max()
    assert np.abs(r.displacement[:, 0] - one.isolator_displacement).max() < 1e-10 * scale
    assert np.abs(r.displacement[:, 1]).max() == 0.0


PAIR_CASES = [
    # (components, scale, first sample, storeys, mu_s): 2 s around each pair's strongest shaking
    ("RSN1084_NORTHR_SCS052.AT2", "RSN1084_NORTHR_SCS142.AT2", 0.5, 1200, 3, 0.08),
    ("RSN738_LOMAP_NAS180.AT2", "RSN738_LOMAP_NAS270.AT2", 2.0, 2200, 2, None),
    ("RSN879_LANDERS_LCN260.AT2", "RSN879_LANDERS_LCN345.AT2", 1.0, 2800, 2, None),
]


@pytest.mark.parametrize("f1, f2, scale, k0, stories, mu_s", PAIR_CASES)
def test_against_the_independent_reference_on_real_pairs(f1, f2, scale, k0, stories, mu_s):
    """Every floor and the mat under a real pair (2 s of its strongest shaking), against the
    event-located DOP853 reference written apart (tests/reference_isolators_2d.py): ≤ 1e-8 of
    the peak (measured: ≤ 7.2e-13)."""
    p = read_pair(PAIRS / f1, PAIRS / f2)
    h1, h2 = scale * p.h1[k0 : k0 + 400], scale * p.h2[k0 : k0 + 400]
    b = building(stories=stories, mu_s=mu_s)
    r = plane_isolator_response(b, h1, h2, p.dt)
    iso = {"R": b.isolator.R, "mu": 0.05}
    if mu_s is not None:
        iso["mu_s"] = mu_s
    ref = isolated_response_2d(b.mass, b.stiffness_matrix, b.damping_matrix, iso, h1, h2, p.dt)
    top = max(np.abs(ref["ux"]).max(), np.abs(ref["uy"]).max())
    assert np.abs(ref["ux"][:, 0]).max() > 0.01  # the bearing does slide
    assert np.abs(r.floor_displacement[:, :, 0] - ref["ux"]).max() < 1e-8 * top
    assert np.abs(r.floor_displacement[:, :, 1] - ref["uy"]).max() < 1e-8 * top
    assert r.peak_displacement >= ref["peak_mat"] * (1 - 1e-8)
    np.testing.assert_allclose(r.residual, ref["residual"], rtol=0, atol=1e-8 * top)


def test_a_pair_of_models_must_share_the_mat_and_the_layer():
    """A superstructure per direction stands on one mat and one layer; anything else is refused
    with the key path."""
    bx = building(stories=2)
    with pytest.raises(ModelError, match=r"building\[1\]\.base_mass_ratio"):
        plane_layer((bx, building(stories=2, ratio=2.0)))
    with pytest.raises(ModelError, match=r"building\[1\]\.isolator"):
        plane_layer((bx, building(stories=2, mu=0.06)))
    assert plane_layer((bx, building(stories=2, period=0.5)))[1] is not bx


def test_energy_balance_on_a_real_pair():
    """Energy balance of the building on friction pendulums under Sylmar's strongest 4 s (both
    components): the input ``−∫ vᵀM1·a_g`` equals the kinetic and strain energy at the end, the
    viscous dissipation and the bearing's friction work (the kernel's own, ``∫ mu N |V|``).
    The integrals of the sampled power by the trapezoid rule err by ``O(h²)``: on the same
    piecewise-linear record sampled at dt/10 and dt/20 the imbalance falls by 4.00, and its
    Richardson extrapolation is ≤ 1e-10 of the input (measured 3e-13)."""
    from scipy.integrate import trapezoid

    p = read_pair(PAIRS / "RSN1084_NORTHR_SCS052.AT2", PAIRS / "RSN1084_NORTHR_SCS142.AT2")
    sl = slice(1000, 1800)
    t = np.arange(800) * p.dt
    b = building(stories=3, mu=0.06)
    c = b.constants
    K = b.stiffness_matrix.copy()
    C = b.damping_matrix.copy()
    K[0, 0] += c["k"]
    C[0, 0] += c["c"]
    out = []
    for k in (10, 20):
        tf = np.arange(799 * k + 1) * (p.dt / k)
        ag = np.stack([np.interp(tf, t, p.h1[sl]), np.interp(tf, t, p.h2[sl])], axis=1)
        r = plane_isolator_response(b, ag[:, 0], ag[:, 1], p.dt / k)
        u, v = r.floor_displacement, r.floor_velocity
        e_in = trapezoid(-np.einsum("i,tid,td->t", b.mass, v, ag), tf)
        kinetic = 0.5 * np.einsum("i,id,id->", b.mass, v[-1], v[-1])
        strain = 0.5 * np.einsum("id,ij,jd->", u[-1], K, u[-1])
        viscous = trapezoid(np.einsum("tid,ij,tjd->t", v, C, v), tf)
        assert r.friction_work > 0.5 * e_in  # the bearing dissipates most of it
        out.append((e_in, e_in - kinetic - strain - viscous - r.friction_work))
    (_, b10), (e20, b20) = out
    assert abs(b20) < 1e-6 * e20
    assert 3.9 < b10 / b20 < 4.1
    assert abs((4 * b20 - b10) / 3) < 1e-10 * e20
