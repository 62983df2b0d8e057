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
    with pytest.raises(ModelError, match="couple"):
        per_direction("a building")
    with pytest.raises(ModelError, match="fewer"):
        fs.building_motion(STIFF, np.zeros(10), 0.01, substeps=1)
