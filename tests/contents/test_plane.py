"""Rigid blocks sliding in the plane (issue 16, docs/design.md §10d): exact to rounding against
closed forms — the 1-D solver along any azimuth, the circular orbit — on the ground and on a
floor."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.contents.plane import slide_plane
from floorslide.errors import ModelError
from tests.conftest import ROOT, load_slammer

MUS = [0.03, 0.08, 0.15, 0.22]
MUS_S = [0.05, 0.1, 0.2, 0.25]  # mu_s > mu_k: starts from rest with m = 1


@pytest.fixture(scope="module")
def elc():
    return load_slammer("ImperialValley_1940_ELC-180.txt")


@pytest.mark.parametrize("angle", [0.0, 30.0, 137.0, 270.0])
def test_input_along_any_azimuth_is_the_1d_solver(elc, angle):
    acc, dt = elc
    th = np.radians(angle)
    r = slide_plane((acc * np.cos(th), acc * np.sin(th)), dt, MUS, MUS_S,
                    histories=True)  # fmt: skip
    ref = fs.slide(acc, dt, MUS, MUS_S, histories=True)
    assert (ref.peak_slide > 0).all()
    np.testing.assert_allclose(r.peak_slide, ref.peak_slide, rtol=1e-10)
    along = r.u[:, :, 0] * np.cos(th) + r.u[:, :, 1] * np.sin(th)
    across = -r.u[:, :, 0] * np.sin(th) + r.u[:, :, 1] * np.cos(th)
    scale = ref.peak_slide[:, None]
    assert np.max(np.abs(along - ref.u) / scale) <= 1e-10
    assert np.max(np.abs(across) / scale) <= 1e-12
    np.testing.assert_allclose(r.slide_fraction, ref.slide_fraction, rtol=1e-10)
    # the peak's direction is the azimuth or its opposite
    d = (r.peak_angle - angle) % 180.0
    assert np.all(np.minimum(d, 180.0 - d) < 1e-8)


@pytest.mark.parametrize("angle", [0.0, 60.0])
def test_on_a_floor_along_an_azimuth_too(elc, angle):
    acc, dt = elc
    b = fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.05)
    th = np.radians(angle)
    r = slide_plane((acc * np.cos(th), acc * np.sin(th)), dt, MUS, building=b, floor=2)
    ref = fs.slide(acc, dt, MUS, building=b, floor=2)
    np.testing.assert_allclose(r.peak_slide, ref.peak_slide, rtol=1e-10)
    np.testing.assert_allclose(np.hypot(*r.residual.T), np.abs(ref.residual_slide),
                               rtol=0, atol=1e-10 * ref.peak_slide.max())  # fmt: skip


def test_circular_input_settles_on_the_closed_form_orbit():
    """a = A(cos ωt, sin ωt), A = 3 m/s², ω = 2π, mu = 0.2: radius √(A² − (mu g)²)/ω² =
    0.0575014 m (docs/design.md §10d). The record is the circle sampled at dt = 1e-3 s and
    joined by straight lines — an inscribed polygon whose mean radius is A·(1 − (ω dt)²/24)
    (measured offset of the orbit: 5.7e-6 relative), so the tolerance is 2e-5."""
    A, om, mu, dt = 3.0, 2 * np.pi, 0.2, 1e-3
    t = np.arange(0, 40, dt)
    r = slide_plane((A * np.cos(om * t), A * np.sin(om * t)), dt, mu, histories=True)
    late = r.u[0][t > 30]
    centre = late.mean(axis=0)
    radius = np.hypot(*(late - centre).T)
    expect = np.sqrt(A**2 - (mu * fs.G) ** 2) / om**2
    assert expect == pytest.approx(0.0575014, abs=1e-7)
    assert radius.mean() == pytest.approx(expect, rel=2e-5)
    assert radius.std() < 1e-4 * expect
    assert r.slip_phases[0] == 1 and r.stops[0] == 0  # it never stops once it slides


def test_the_coupling_matters_on_a_real_pair():
    """The friction circle couples the directions: on Sylmar (Northridge 1994) the 2-D slide
    is not the larger 1-D one — measured 1.44, 1.71, 1.30 times it at mu 0.05, 0.1, 0.2."""
    from floorslide.records.pairs import read_pairs
    from tests.conftest import ROOT

    (p,) = read_pairs(ROOT / "data" / "records" / "pairs" / "index.csv", where={"rsn": "1084"})
    r = slide_plane(p, None, [0.05, 0.1, 0.2])
    assert np.all(r.ratio_2d_1d > 1.2)
    np.testing.assert_allclose(r.peak_slide_1d.max(axis=1) * r.ratio_2d_1d, r.peak_slide)


def test_bad_input():
    with pytest.raises(ModelError, match="mu_k"):
        slide_plane((np.zeros(5), np.zeros(5)), 0.01)
    with pytest.raises(ModelError, match="two horizontal components"):
        slide_plane(np.zeros(5), 0.01, 0.1)
    with pytest.raises(ModelError, match="floor"):
        slide_plane((np.zeros(5), np.zeros(5)), 0.01, 0.1, floor=1)


def test_energy_balance_to_rounding_on_real_pairs():
    """½|u'(end)|² = −mu_k g ∫|u'| dt − ∫ a·u' dt (per unit mass), both integrals exact on each
    step's series: measured 1e-15 … 6e-15 of the friction work on three bundled pairs."""
    from floorslide.records.pairs import read_pairs
    from tests.conftest import ROOT

    mus = np.array([0.05, 0.1, 0.2])
    for p in read_pairs(ROOT / "data" / "records" / "pairs" / "index.csv")[:3]:
        r = slide_plane(p, None, mus, 1.2 * mus, compare_1d=False)
        kinetic = 0.5 * np.sum(r.final_velocity**2, axis=1)
        friction = mus * fs.G * r.path
        assert (friction > 0).all()
        assert np.all(np.abs(kinetic + friction + r.work_floor) <= 1e-12 * friction)


@pytest.mark.parametrize("rsn", ["511", "879"])
@pytest.mark.parametrize("floor", [None, 2])
def test_no_kinetic_friction_is_the_two_components_alone(floor, rsn):
    """mu_k = mu_s = 0: nothing couples the directions, so the slide in the plane is the two
    components' frictionless 1-D slides side by side (u = −∬a); found wrong (stops where the
    speed's series had spurious roots) and fixed: the friction-free series has no stop. On a
    building's floor at rest (Lucerne) the floor's first coefficients are rounding, which
    crashed the start from rest (ZeroDivisionError) until they were told from the leading
    term."""
    (p,) = fs.read_pairs(ROOT / "data" / "records" / "pairs" / "index.csv", where={"rsn": rsn})
    b = None if floor is None else fs.BuildingPair(
        fs.ShearBuilding.from_period(2, 0.3), fs.ShearBuilding.from_period(2, 0.5)
    )  # fmt: skip
    r = slide_plane(p, None, 0.0, building=b, floor=floor, histories=True)
    bx, by = (None, None) if b is None else (b.h1, b.h2)
    u1 = fs.slide(p.h1, p.dt, 0.0, building=bx, floor=floor, histories=True).u[0]
    u2 = fs.slide(p.h2, p.dt, 0.0, building=by, floor=floor, histories=True).u[0]
    scale = r.peak_slide[0]
    assert np.max(np.abs(r.u[0, :, 0] - u1)) <= 1e-11 * scale
    assert np.max(np.abs(r.u[0, :, 1] - u2)) <= 1e-11 * scale
    sampled = np.hypot(u1, u2).max()
    assert sampled <= scale <= sampled * (1 + 1e-3)
    assert r.stops[0] == 0 and r.slide_fraction[0] == pytest.approx(1.0, abs=1e-9)


def test_no_kinetic_friction_after_a_static_breakaway_against_the_reference():
    from tests.reference_sliding2d import slide2d_reference

    (p,) = fs.read_pairs(ROOT / "data" / "records" / "pairs" / "index.csv", where={"rsn": "511"})
    h1, h2 = p.h1[:1200], p.h2[:1200]
    r = slide_plane((h1, h2), p.dt, 0.0, 0.05, histories=True, compare_1d=False)
    ref = slide2d_reference(h1, h2, p.dt, 0.0, 0.05)
    assert r.slip_phases[0] == ref["slips"] == 1
    assert abs(r.peak_slide[0] - ref["peak"]) <= 1e-8 * ref["peak"]
    assert np.max(np.abs(r.u[0] - ref["u"])) <= 1e-8 * ref["peak"]
