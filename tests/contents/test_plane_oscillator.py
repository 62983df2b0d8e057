"""The 2-DOF sliding oscillator in the plane (docs/design.md §10d): along any azimuth it is the 1-D
oscillator (ground, a linear building's floor, a friction-pendulum building's floor); never
slipping it is the clamped-base oscillator (RotD100 and the 1-D spectrum); against an
independent event-located DOP853 reference on real pairs; bad input refused in one line."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.plane_isolation import PlaneIsolatedMotion
from floorslide.building.poly_segments import GroundPolyMotion, LinearPolyMotion
from floorslide.contents.plane_oscillator import slide_oscillator_plane_on_segments
from floorslide.errors import ModelError
from tests.conftest import ROOT
from tests.reference_oscillator2d import oscillator2d_reference

PAIRS = ROOT / "data" / "records" / "pairs" / "index.csv"
MUS = [0.08, 0.15, 0.3]
OSC = dict(frequency=3.0, damping=0.05, mass_ratio=0.8)


def _pair(rsn: str):
    (p,) = fs.read_pairs(PAIRS, where={"rsn": rsn})
    return p


@pytest.fixture(scope="module")
def sylmar():
    """Northridge 1994, Sylmar (RSN 1084), its first 1200 samples (6 s, both PGAs in them)."""
    p = _pair("1084")
    return p.h1[:1200].copy(), p.h2[:1200].copy(), p.dt


def _along(a, theta):
    th = np.radians(theta)
    return a * np.cos(th), a * np.sin(th), np.array([np.cos(th), np.sin(th)])


def _worst_1d(r2, r1, e) -> float:
    """Largest difference between the plane result along `e` and the 1-D one, relative to each
    quantity's largest value; the slip phases must agree."""
    np.testing.assert_array_equal(r2.slip_phases, r1.slip_phases)
    worst = 0.0
    for x, y in (
        (r2.peak_slide, r1.peak_slide),
        (r2.residual @ e, r1.residual_slide),
        (r2.peak_deformation, r1.peak_deformation),
        (r2.peak_top_accel, r1.peak_top_accel),
        (r2.slide_fraction, r1.slide_fraction),
    ):
        worst = max(worst, float(np.max(np.abs(x - y)) / np.max(np.abs(y))))
    # nothing across the line
    across = np.array([-e[1], e[0]])
    assert np.max(np.abs(r2.residual @ across)) <= 1e-12 * np.max(r2.peak_slide)
    return worst


@pytest.mark.parametrize("theta", [0.0, 37.0, 90.0, 200.0])
def test_along_an_azimuth_on_the_ground_is_the_1d_oscillator(sylmar, theta):
    """Measured ≤ 1.3e-13 (1.2e-15 along the axes; mu_s = mu_k: every breakaway a start of
    order 2)."""
    h1, _, dt = sylmar
    ax, ay, e = _along(h1, theta)
    r2 = fs.slide_oscillator_plane((ax, ay), dt, MUS, **OSC)
    r1 = fs.slide_oscillator(h1, dt, MUS, **OSC)
    assert (r1.peak_slide > 0).all() and (r1.slip_phases > 1).all()
    assert _worst_1d(r2, r1, e) <= 1e-10


def test_along_an_azimuth_with_static_friction_above_kinetic(sylmar):
    """mu_s > mu_k (starts of order 1, stops that slide on at once). Measured 6.3e-14."""
    h1, _, dt = sylmar
    ax, ay, e = _along(h1, 37.0)
    ms = [0.1, 0.2, 0.35]
    r2 = fs.slide_oscillator_plane((ax, ay), dt, MUS, mu_s=ms, **OSC)
    r1 = fs.slide_oscillator(h1, dt, MUS, mu_s=ms, **OSC)
    assert _worst_1d(r2, r1, e) <= 1e-10


@pytest.mark.parametrize("theta", [37.0, 200.0])
def test_along_an_azimuth_on_a_linear_building_is_the_1d_oscillator(sylmar, theta):
    """Roof of a 2-storey building (LinearPolyMotion). Measured ≤ 4.2e-14."""
    h1, _, dt = sylmar
    b = fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.05)
    ax, ay, e = _along(h1, theta)
    r2 = slide_oscillator_plane_on_segments(LinearPolyMotion(b, ax, ay, dt), 2, MUS, **OSC)
    r1 = fs.slide_oscillator(h1, dt, MUS, building=b, floor=2, **OSC)
    assert (r1.peak_slide > 0).all()
    assert _worst_1d(r2, r1, e) <= 1e-10


@pytest.mark.parametrize("theta", [0.0, 37.0])
def test_along_an_azimuth_on_a_friction_pendulum_building_is_the_1d_oscillator(sylmar, theta):
    """Floor 1 of a building on friction pendulums (PlaneIsolatedMotion against the 1-D
    segmented motion). Measured ≤ 2.3e-13."""
    h1, _, dt = sylmar
    sup = fs.ShearBuilding.from_period(stories=2, period=0.3, damping=0.03)
    b = fs.NonlinearIsolatedBuilding(sup, 1.0, fs.FrictionPendulum(mu=0.05, period=3.0))
    ax, ay, e = _along(h1, theta)
    mus = [0.05, 0.1]
    r2 = slide_oscillator_plane_on_segments(PlaneIsolatedMotion(b, ax, ay, dt), 1, mus, **OSC)
    r1 = fs.slide_oscillator(h1, dt, mus, building=b, floor=1, **OSC)
    assert (r1.peak_slide > 0).all()
    assert _worst_1d(r2, r1, e) <= 1e-10


def test_never_slipping_is_the_clamped_base_oscillator(sylmar):
    """mu = 5: the base moves with the floor and z is the linear oscillator: along an azimuth
    the 1-D spectrum's SD and SA (measured 4.7e-15), in the plane RotD100/ω² (measured
    6.6e-15)."""
    h1, h2, dt = sylmar
    f, xi = OSC["frequency"], OSC["damping"]
    w = 2 * np.pi * f
    ax, ay, _ = _along(h1, 37.0)
    r = fs.slide_oscillator_plane((ax, ay), dt, [5.0], **OSC, histories=True)
    assert r.slip_phases[0] == 0 and r.peak_slide[0] == 0.0 and not r.u.any()
    sp = fs.response_spectrum(h1, dt, [1.0 / f], damping=xi)
    assert abs(r.peak_deformation[0] - sp.sd[0, 0]) <= 1e-10 * sp.sd[0, 0]
    assert abs(r.peak_top_accel[0] - sp.sa[0, 0]) <= 1e-10 * sp.sa[0, 0]
    r = fs.slide_oscillator_plane((h1, h2), dt, [5.0], **OSC)
    rotd = fs.rotd_spectrum((h1, h2), dt, [1.0 / f], damping=xi)
    sd100 = rotd.rotd100[0, 0] / w**2
    assert abs(r.peak_deformation[0] - sd100) <= 1e-10 * sd100


@pytest.mark.parametrize(
    ("rsn", "window", "mu_k", "mu_s", "osc"),
    [
        ("1084", (1200, 1600), 0.2, 0.24, dict(frequency=3.0, damping=0.05, mass_ratio=1.0)),
        ("1084", (1200, 1600), 0.3, 0.33, dict(frequency=8.0, damping=0.02, mass_ratio=0.5)),
        ("879", (0, 2000), 0.2, 0.24, dict(frequency=3.0, damping=0.05, mass_ratio=1.0)),
        ("879", (0, 2000), 0.3, 0.33, dict(frequency=8.0, damping=0.02, mass_ratio=0.5)),
    ],
)
def test_against_the_event_located_reference(rsn, window, mu_k, mu_s, osc):
    """Real pairs on the ground against tests/reference_oscillator2d.py (DOP853 at rtol 1e-12,
    restarted at every sample and event): measured ≤ 2.6e-11 of the peak (slide, residual and u at
    the samples; Sylmar ≤ 1.6e-12), deformation and top acceleration ≤ 2.5e-11, the same
    numbers of slip phases and stops."""
    p = _pair(rsn)
    h1, h2 = p.h1[slice(*window)].copy(), p.h2[slice(*window)].copy()
    r = fs.slide_oscillator_plane((h1, h2), p.dt, [mu_k], mu_s=[mu_s], **osc, histories=True)
    ref = oscillator2d_reference(h1, h2, p.dt, mu_k, mu_s, **osc)
    peak = ref["peak_slide"]
    assert peak > 1e-3 and ref["stops"] >= 2
    assert abs(r.peak_slide[0] - peak) <= 1e-8 * peak
    assert np.max(np.abs(r.residual[0] - ref["residual"])) <= 1e-8 * peak
    assert np.max(np.abs(r.u[0] - ref["u"])) <= 1e-8 * peak
    for name in ("peak_deformation", "peak_top_accel"):
        assert abs(getattr(r, name)[0] - ref[name]) <= 1e-8 * ref[name], name
    assert r.slip_phases[0] == ref["slips"] and r.stops[0] == ref["stops"]
    assert abs(r.slide_fraction[0] * r.duration - ref["slide_time"]) <= 1e-9


def test_histories_and_segments_cut_anywhere(sylmar):
    """The same motion cut into pieces at random points gives the same answer (measured
    3.9e-15); u and z at the samples stay within the peaks found inside steps."""
    h1, h2, dt = sylmar
    ref = slide_oscillator_plane_on_segments(GroundPolyMotion(h1, h2, dt), None, MUS, **OSC,
                                             histories=True)  # fmt: skip
    r = slide_oscillator_plane_on_segments(GroundPolyMotion(h1, h2, dt, split=7), None, MUS,
                                           **OSC, histories=True)  # fmt: skip
    for name in ("peak_slide", "peak_deformation", "peak_top_accel", "residual"):
        x, y = getattr(r, name), getattr(ref, name)
        assert np.max(np.abs(x - y)) <= 1e-12 * np.max(np.abs(y)), name
    assert r.u.shape == (3, h1.size, 2) and r.z.shape == (3, h1.size, 2)
    np.testing.assert_allclose(r.u[:, -1], r.residual, rtol=0, atol=0)
    assert (np.linalg.norm(r.u, axis=2).max(axis=1) <= r.peak_slide * (1 + 1e-15)).all()
    assert (np.linalg.norm(r.z, axis=2).max(axis=1) <= r.peak_deformation * (1 + 1e-15)).all()


def test_bad_input_is_refused_in_one_line(sylmar):
    h1, h2, dt = sylmar
    pair = (h1, h2)
    cases = [
        (dict(mu=None, frequency=3.0), "mu"),
        (dict(mu=0.0, frequency=3.0), "mu"),
        (dict(mu=-0.1, frequency=3.0), "mu_k"),
        (dict(mu=0.1, frequency=None), "frequency"),
        (dict(mu=0.1, frequency=-1.0), "frequency"),
        (dict(mu=0.1, frequency=3.0, damping=1.0), "damping"),
        (dict(mu=0.1, frequency=3.0, mass_ratio=0.0), "mass_ratio"),
        (dict(mu=0.1, frequency=3.0, mass_ratio="x"), "mass_ratio"),
        (dict(mu=[0.1, 0.2], frequency=3.0, mu_s=[0.1, 0.2, 0.3]), "mu_s"),
        (dict(mu=0.1, frequency=3.0, vertical=h1), "vertical"),
        (dict(mu=0.1, frequency=3.0, floor=2), "floor"),
        (dict(mu=0.1, frequency=3.0, building=fs.ShearBuilding.from_period(2, 0.3)), "floor"),
        (dict(mu=0.1, frequency=3.0, building=fs.ShearBuilding.from_period(2, 0.3), floor=7),
         "floors"),
    ]  # fmt: skip
    for kwargs, where in cases:
        with pytest.raises(ModelError) as info:
            fs.slide_oscillator_plane(pair, dt, **kwargs)
        assert "\n" not in str(info.value) and info.value.where == where, (kwargs, info.value)
    with pytest.raises(ModelError) as info:
        fs.slide_oscillator_plane(h1, dt, 0.1, 3.0)
    assert info.value.where == "acc"
    with pytest.raises(ModelError) as info:
        fs.slide_oscillator_plane(pair, None, 0.1, 3.0)
    assert info.value.where == "dt"
