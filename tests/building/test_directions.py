"""A building with a model per horizontal direction (docs/design.md §10d): each direction is the
existing exact model under its own component, stepped on one time grid."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.directions import BuildingPair, per_direction, plane_motions
from floorslide.errors import ModelError
from tests.conftest import load_slammer


@pytest.fixture(scope="module")
def rec():
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    return acc[:3000], dt


STIFF = fs.ShearBuilding.from_period(3, 0.15)
SOFT = fs.ShearBuilding.from_period(3, 1.2, damping=0.03)


def test_each_direction_is_its_own_building(rec):
    acc, dt = rec
    h2 = 0.7 * acc[::-1].copy()
    fm1, fm2 = plane_motions(BuildingPair(SOFT, STIFF), acc, h2, dt, 3)
    # one time grid: the stiffer direction's sub-steps
    assert fm1.substeps == fm2.substeps == fs.building_motion(STIFF, acc, dt).substeps
    assert fm1.substeps > fs.building_motion(SOFT, acc, dt).substeps
    for fm, b, a in ((fm1, SOFT, acc), (fm2, STIFF, h2)):
        alone = fs.building_motion(b, a, dt).floor(3)
        p, tp = fm.peak()
        q, tq = alone.peak()
        assert abs(p - q) <= 1e-12 * q  # more sub-steps: the same exact motion
        assert abs(tp - tq) <= 1e-9
        np.testing.assert_allclose(
            fs.slide(fm, mu_k=0.1).peak_slide, fs.slide(alone, mu_k=0.1).peak_slide, rtol=1e-11
        )


def test_plane_sliding_on_a_building_per_direction(rec):
    """A block on a two-way building sliding along x only: the 1-D slide on the x model."""
    acc, dt = rec
    zero = np.zeros_like(acc)
    r = fs.slide_plane((acc, zero), dt, mu_k=[0.05, 0.2], building=BuildingPair(SOFT, STIFF),
                       floor=2)  # fmt: skip
    ref = fs.slide(acc, dt, mu_k=[0.05, 0.2], building=SOFT, floor=2)
    np.testing.assert_allclose(r.peak_slide, ref.peak_slide, rtol=1e-10)
    r2 = fs.slide_plane((zero, acc), dt, mu_k=[0.05, 0.2], building=BuildingPair(SOFT, STIFF),
                        floor=2)  # fmt: skip
    ref2 = fs.slide(acc, dt, mu_k=[0.05, 0.2], building=STIFF, floor=2)
    np.testing.assert_allclose(r2.peak_slide, ref2.peak_slide, rtol=1e-10)
    np.testing.assert_allclose(np.abs(r2.peak_angle), 90.0, atol=1e-9)


def test_one_building_is_both_directions():
    assert per_direction(SOFT) == (SOFT, SOFT)
    assert per_direction(None) == (None, None)
    assert per_direction((SOFT, STIFF)) == (SOFT, STIFF)


def test_bad_building_pairs():
    with pytest.raises(ModelError, match="different floors"):
        BuildingPair(SOFT, fs.ShearBuilding.from_period(2, 0.5))
    with pytest.raises(ModelError, match="different floors"):
        BuildingPair(SOFT, fs.IsolatedBuilding(SOFT, 1.0, 2.5, 0.1))
    with pytest.raises(ModelError, match="pair of models"):
        per_direction((SOFT, SOFT, SOFT))
    with pytest.raises(ModelError, match="got str"):
        per_direction("a building")
    fps = fs.NonlinearIsolatedBuilding(SOFT, 1.0, fs.FrictionPendulum(mu=0.05, period=3.0))
    with pytest.raises(ModelError, match="couple the two directions"):
        per_direction(fps)
    with pytest.raises(ModelError, match="fewer"):
        fs.building_motion(STIFF, np.zeros(10), 0.01, substeps=1)


@pytest.mark.parametrize("building", [None, STIFF, BuildingPair(SOFT, STIFF)])
def test_plane_peak_is_the_true_peak_of_the_vector(rec, building):
    """max_t |a(t)| inside steps: above every sample of a 64-times finer exact grid, and
    within its sampling error of it."""
    from floorslide.building.directions import plane_peak
    from floorslide.building.motions import floor_motions

    acc, dt = rec
    h2 = 0.8 * np.roll(acc, 137)
    floor = None if building is None else 3
    fm1, fm2 = plane_motions(building, acc, h2, dt, floor)
    peak, t = plane_peak(fm1, fm2)
    bx, by = per_direction(building)
    n = 64
    if building is None:
        grid = np.arange((acc.size - 1) * n + 1) / n
        f1, f2 = np.interp(grid, np.arange(acc.size), acc), np.interp(grid, np.arange(acc.size), h2)
    else:
        f1 = floor_motions(bx, acc, dt, floors=[3], oversample=n)[0]
        f2 = floor_motions(by, h2, dt, floors=[3], oversample=n)[0]
    fine = np.hypot(f1, f2)
    k = int(np.argmax(fine))
    assert fine.max() <= peak * (1 + 1e-13)
    assert peak - fine.max() <= 2e-3 * peak  # the grid misses at most its curvature's share
    assert abs(t - k * dt / n) <= dt / n
    if building is None:
        assert peak == fine.max()  # piecewise linear: |a| is convex on a step, peak at a sample


@pytest.mark.parametrize("angle", [0.0, 35.0, 90.0, 200.0])
def test_plane_peak_along_an_azimuth_is_the_1d_peak(rec, angle):
    from floorslide.building.directions import plane_peak

    acc, dt = rec
    th = np.radians(angle)
    fm1, fm2 = plane_motions(SOFT, np.cos(th) * acc, np.sin(th) * acc, dt, 2)
    peak, t = plane_peak(fm1, fm2)
    ref, tref = fs.building_motion(SOFT, acc, dt).floor(2).peak()
    assert abs(peak - ref) <= 1e-13 * ref
    assert abs(t - tref) <= 1e-9
