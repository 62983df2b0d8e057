"""Blocks sliding in the plane on a poly motion (docs/design.md §16): the segments of the ground
pair and of a linear building's floor give fs.slide_plane's answer, aligned with the record or
cut at arbitrary points; degree-23 segments of a circular motion give the closed-form orbit."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.poly_segments import GroundPolyMotion, LinearPolyMotion
from floorslide.contents.plane_segments import slide_plane_on_segments
from floorslide.errors import ModelError
from tests.conftest import ROOT
from tests.poly_motions import Counted, Harmonic, OneSegment, Recut

MUS = [0.05, 0.1, 0.2, 0.3]
MUS_S = [0.06, 0.12, 0.24, 0.3]
FIELDS = ("peak_slide", "residual", "slide_fraction", "path", "work_floor", "final_velocity",
          "peak_angle", "peak_slide_1d")  # fmt: skip


@pytest.fixture(scope="module")
def sylmar():
    """Northridge 1994, Sylmar (RSN 1084), its first 1200 samples (6 s, both PGAs in them)."""
    (p,) = fs.read_pairs(ROOT / "data" / "records" / "pairs" / "index.csv", where={"rsn": "1084"})
    return p.h1[:1200].copy(), p.h2[:1200].copy(), p.dt


def _worst(r, ref) -> float:
    """Largest difference of the result fields, relative to each field's largest value."""
    worst = 0.0
    for name in FIELDS:
        x = np.asarray(getattr(r, name), dtype=float)
        y = np.asarray(getattr(ref, name), dtype=float)
        worst = max(worst, float(np.max(np.abs(x - y)) / np.max(np.abs(y))))
    np.testing.assert_array_equal(r.slip_phases, ref.slip_phases)
    np.testing.assert_array_equal(r.stops, ref.stops)
    return worst


@pytest.mark.parametrize("split", [None, 7])
def test_ground_segments_are_slide_plane(sylmar, split):
    """Measured: aligned, every field bit for bit but the 1-D comparison (5.7e-15: here the plane
    solver with one component zeroed, there the 1-D solver); cut at random points ≤ 7.4e-15
    relative, u at the samples 1.6e-15."""
    h1, h2, dt = sylmar
    ref = fs.slide_plane((h1, h2), dt, MUS, MUS_S, histories=True)
    assert (ref.peak_slide > 0).all() and (ref.stops > 0).all()
    r = slide_plane_on_segments(GroundPolyMotion(h1, h2, dt, split=split), None, MUS, MUS_S,
                                histories=True)  # fmt: skip
    assert _worst(r, ref) <= 1e-12
    assert np.max(np.abs(r.u - ref.u)) <= 1e-12 * np.max(np.abs(ref.u))
    np.testing.assert_allclose(r.time_of_peak, ref.time_of_peak, rtol=0, atol=1e-8)
    if split is None:
        np.testing.assert_array_equal(r.peak_slide, ref.peak_slide)


@pytest.mark.parametrize("split", [None, 7])
@pytest.mark.parametrize("pair", [False, True])
def test_building_floor_segments_are_slide_plane(sylmar, split, pair):
    """Floor 2 of a 2-storey building (one model, or one per direction): measured aligned, bit
    for bit but the 1-D comparison (≤ 6.4e-15); cut at random points ≤ 1.0e-14 relative, u at
    the samples ≤ 2.5e-15."""
    h1, h2, dt = sylmar
    if pair:
        b = fs.BuildingPair(fs.ShearBuilding.from_period(2, 0.3),
                            fs.ShearBuilding.from_period(2, 0.5))  # fmt: skip
    else:
        b = fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.05)
    ref = fs.slide_plane((h1, h2), dt, MUS, MUS_S, building=b, floor=2, histories=True)
    assert (ref.peak_slide > 0).all()
    motion = LinearPolyMotion(b, h1, h2, dt, split=split)
    r = slide_plane_on_segments(motion, 2, MUS, MUS_S, histories=True)
    assert _worst(r, ref) <= 1e-12
    assert np.max(np.abs(r.u - ref.u)) <= 1e-12 * np.max(np.abs(ref.u))
    np.testing.assert_allclose(r.time_of_peak, ref.time_of_peak, rtol=0, atol=1e-8)


def test_circular_motion_settles_on_the_closed_form_orbit():
    """a = A(cos ωt, sin ωt), A = 3 m/s², ω = 2π, mu = 0.2: the orbit's radius
    √(A² − (mu g)²)/ω² = 0.0575014 m and speed ω times it (docs/design.md §10d). On exact
    degree-23 segments (not the sampled polygon of test_plane) measured: radius 4e-15, its
    spread 5e-14, final speed 1.3e-14 relative."""
    A, om, mu, dt = 3.0, 2 * np.pi, 0.2, 0.05
    m = Harmonic(A, om, dt, 801)
    r = slide_plane_on_segments(m, None, mu, histories=True, compare_1d=False)
    t = np.arange(m.npts) * dt
    late = r.u[0][t > 30]
    centre = late.mean(axis=0)
    radius = np.hypot(*(late - centre).T)
    expect = np.sqrt(A**2 - (mu * fs.G) ** 2) / om**2
    assert expect == pytest.approx(0.0575014, abs=1e-7)
    assert radius.mean() == pytest.approx(expect, rel=1e-12)
    assert radius.std() < 1e-12 * expect
    assert np.hypot(*r.final_velocity[0]) == pytest.approx(expect * om, rel=1e-12)
    assert r.slip_phases[0] == 1 and r.stops[0] == 0
    # energy: ½|u'(end)|² = −mu_k g·path − work_floor (measured 1.3e-16 of the friction work)
    kinetic = 0.5 * np.sum(r.final_velocity[0] ** 2)
    friction = mu * fs.G * r.path[0]
    assert abs(kinetic + friction + r.work_floor[0]) <= 1e-12 * friction


@pytest.mark.parametrize("lift", [False, True])
@pytest.mark.parametrize("kind", ["ground", "floor"])
def test_vertical_shaking_is_slide_plane(sylmar, kind, lift):
    """A stand-in vertical (Lucerne's 260 component, 10–16 s, scaled to 0.5 g, or to 1.3 g:
    five lift-offs): measured aligned bit for bit but the 1-D comparison (≤ 1.3e-15), cut at
    random points ≤ 1.3e-14 relative; the lift-off time and count equal."""
    h1, h2, dt = sylmar
    (q,) = fs.read_pairs(ROOT / "data" / "records" / "pairs" / "index.csv", where={"rsn": "879"})
    av = q.h1[2000:3200] / np.abs(q.h1[2000:3200]).max() * (1.3 if lift else 0.5) * fs.G
    b = None if kind == "ground" else fs.ShearBuilding.from_period(2, 0.4, 0.05)
    fl = None if b is None else 2
    ref = fs.slide_plane((h1, h2), dt, MUS, MUS_S, building=b, floor=fl, vertical=av,
                         histories=True)  # fmt: skip
    assert (ref.liftoff_count == 5) if lift else (ref.liftoff_count == 0)
    for split in (None, 7):
        m = GroundPolyMotion(h1, h2, dt, split=split) if b is None else LinearPolyMotion(
            b, h1, h2, dt, split=split)  # fmt: skip
        r = slide_plane_on_segments(m, fl, MUS, MUS_S, vertical=av, histories=True)
        assert _worst(r, ref) <= 1e-12
        assert np.max(np.abs(r.u - ref.u)) <= 1e-12 * np.max(np.abs(ref.u))
        np.testing.assert_allclose(r.work_friction, ref.work_friction, rtol=1e-12)
        assert (r.liftoff_time, r.liftoff_count) == (ref.liftoff_time, ref.liftoff_count)


def test_one_pass_over_the_motion(sylmar):
    """The slide in the plane and the two 1-D comparisons read the motion once (a producer may
    integrate a building on every pass)."""
    h1, h2, dt = sylmar
    m = Counted(GroundPolyMotion(h1[:300], h2[:300], dt))
    r = slide_plane_on_segments(m, None, MUS, histories=True)
    assert m.passes == 1 and np.isfinite(r.peak_slide_1d).all()


def test_refusals(sylmar):
    h1, h2, dt = sylmar
    g = GroundPolyMotion(h1[:50], h2[:50], dt)
    with pytest.raises(ModelError, match="vertical has 49 samples") as e:
        slide_plane_on_segments(g, None, 0.1, vertical=h1[:49])
    assert "\n" not in str(e.value)
    with pytest.raises(ModelError, match="floor 3"):
        slide_plane_on_segments(g, 3, 0.1)
    m = LinearPolyMotion(fs.ShearBuilding.from_period(2, 0.3), h1[:50], h2[:50], dt)
    with pytest.raises(ModelError, match="floor is required"):
        slide_plane_on_segments(m, None, 0.1)
    with pytest.raises(ModelError, match="mu_k"):
        slide_plane_on_segments(g, None)


def test_tiny_segments(sylmar):
    """Segments of 1e-9 of a step at both ends of every step: measured 1.2e-14 relative to the
    aligned ground segments."""
    h1, h2, dt = sylmar
    g = GroundPolyMotion(h1, h2, dt)
    ref = slide_plane_on_segments(g, None, MUS, MUS_S, histories=True)
    r = slide_plane_on_segments(Recut(g, [1e-9, 0.5, 1 - 1e-9]), None, MUS, MUS_S,
                                histories=True)  # fmt: skip
    assert _worst(r, ref) <= 1e-12
    assert np.max(np.abs(r.u - ref.u)) <= 1e-12 * np.max(np.abs(ref.u))


@pytest.mark.parametrize("mu_s", [0.2, 0.3])
@pytest.mark.parametrize("L", [1.0, 1e-3])
def test_a_large_degree_23_term(L, mu_s):
    """One segment of ``a = 30 (τ/L)^23`` m/s² along the azimuth 30° (its whole weight in the
    last coefficient, 3e70 for L = 1 ms): the block breaks away at ``τ_b = L (mu_b g/30)^(1/23)``
    and slides along −30° with ``u'' = −a + mu_k g`` to the end — closed forms; measured
    ≤ 1.3e-15 relative (peak slide, final speed, slide time)."""
    A, mu = 30.0, 0.2
    c = np.zeros(24)
    c[23] = A / L**23
    th = np.radians(30.0)
    r = slide_plane_on_segments(OneSegment(c * np.cos(th), L, c * np.sin(th)), None, mu, mu_s)
    tb = L * (max(mu, mu_s) * fs.G / A) ** (1 / 23)
    a23 = A / L**23
    u = -a23 / 24 * ((L**25 - tb**25) / 25 - tb**24 * (L - tb)) + mu * fs.G * (L - tb) ** 2 / 2
    v = -a23 * (L**24 - tb**24) / 24 + mu * fs.G * (L - tb)
    assert r.peak_slide[0] == pytest.approx(abs(u), rel=1e-14)
    assert np.hypot(*r.final_velocity[0]) == pytest.approx(abs(v), rel=1e-14)
    assert r.slide_fraction[0] * L == pytest.approx(L - tb, rel=1e-14)
    assert r.peak_angle[0] == pytest.approx(-150.0, abs=1e-12)
    assert (r.slip_phases[0], r.stops[0]) == (1, 0)


def test_a_jump_of_the_floor_acceleration_at_a_segment_start_breaks_a_block_away():
    """The mat of a building on friction pendulums jumps in acceleration at the bearing's stops:
    a stuck block on it breaks away at the segment's start. Constant a = 0.2 then −1.75 m/s²
    (each for half a step): the closed form of a block with mu = 0.03 from rest."""
    from floorslide.building.poly_segments import DEGREE, PolySegments
    from floorslide.constants import G

    class Jumps:
        dt, npts, floors, notes = 0.02, 2, (0,), ()

        def poly_chunks(self):
            coef = np.zeros((2, 1, 2, DEGREE))
            coef[:, 0, 0, 0] = [0.2, -1.75]
            yield PolySegments(np.array([0.0, 0.01]), np.array([0.01, 0.01]),
                               np.zeros(2, dtype=np.int64), np.array([False, True]), coef,
                               (0,), 0, 1)  # fmt: skip

    mu = 0.03
    r = slide_plane_on_segments(Jumps(), 0, [mu], compare_1d=False)
    # u'' = 1.75 − mu g from rest for 0.01 s (the block stays stuck under 0.2 < mu g)
    expect = 0.5 * (1.75 - mu * G) * 0.01**2
    assert r.slip_phases[0] == 1
    assert r.peak_slide[0] == pytest.approx(expect, rel=1e-12)
