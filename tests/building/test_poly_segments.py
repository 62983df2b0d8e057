"""The poly-segment contract and its two producers (docs/design.md §16): the segments hold the
ground pair and a linear building's floors exactly (samples against the exact stepper), aligned
or cut at arbitrary points; a chunk that breaks the contract is refused in one line."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.exact_motion import building_motion
from floorslide.building.poly_segments import (
    DEGREE,
    GroundPolyMotion,
    LinearPolyMotion,
    check_segments,
    samples_on_poly,
)
from floorslide.errors import ModelError
from tests.conftest import load_slammer


@pytest.fixture(scope="module")
def pair():
    a, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    b, _ = load_slammer("CapeMendocino_1992_PET-090.txt")
    return a[:700].copy(), 0.7 * b[:700], dt


def _chunks_ok(motion):
    n = 0
    for seg in motion.poly_chunks():
        check_segments(seg, motion.dt)
        n += seg.nseg
    return n


@pytest.mark.parametrize("split", [None, 3])
def test_ground_samples(pair, split):
    """Measured: 2.2e-16 (a + slope·dt is a_{k+1} to rounding), 4.4e-16 cut."""
    h1, h2, dt = pair
    g = GroundPolyMotion(h1, h2, dt, split=split)
    n = _chunks_ok(g)
    assert n == h1.size - 1 if split is None else n > 1.5 * (h1.size - 1)
    S = samples_on_poly(g)
    assert S.shape == (1, 2, h1.size)
    assert np.max(np.abs(S[0, 0] - h1)) <= 1e-15 * np.max(np.abs(h1))
    assert np.max(np.abs(S[0, 1] - h2)) <= 1e-15 * np.max(np.abs(h2))


@pytest.mark.parametrize("split", [None, 5])
@pytest.mark.parametrize("two", [False, True])
def test_building_samples(pair, split, two):
    """Every floor's absolute accelerations at the samples against the exact stepper's
    (BuildingMotion.samples): measured ≤ 5.3e-15 relative, aligned or cut."""
    h1, h2, dt = pair
    if two:
        b = fs.BuildingPair(fs.ShearBuilding.from_period(2, 0.3),
                            fs.ShearBuilding.from_period(2, 0.5))  # fmt: skip
        bx, by = b.h1, b.h2
    else:
        b = bx = by = fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.05)
    m = LinearPolyMotion(b, h1, h2, dt, split=split)
    assert m.floors == (0, 1, 2)
    _chunks_ok(m)
    S = samples_on_poly(m)
    for d, (bd, a) in enumerate(((bx, h1), (by, h2))):
        ref = building_motion(bd, a, dt).samples([0, 1, 2])
        assert np.max(np.abs(S[:, d] - ref)) <= 2e-14 * np.max(np.abs(ref))
    np.testing.assert_array_equal(samples_on_poly(m, [2]), S[2:3])


def test_isolated_building_floors(pair):
    """Base mat and roof of an isolated building: measured 7.0e-14 relative (the Taylor
    polynomial summed at τ = h against the exact recurrence: the rounding of its terms, which
    partly cancel on the isolated building's floors)."""
    h1, h2, dt = pair
    b = fs.IsolatedBuilding(fs.ShearBuilding.from_period(2, 0.3, 0.05), 1.0, 2.5, 0.1)
    m = LinearPolyMotion(b, h1, h2, dt, floors=[0, 2])
    S = samples_on_poly(m)
    for d, a in enumerate((h1, h2)):
        ref = building_motion(b, a, dt).samples([0, 2])
        assert np.max(np.abs(S[:, d] - ref)) <= 2e-13 * np.max(np.abs(ref))


def test_bad_chunks_are_refused_in_one_line(pair):
    h1, h2, dt = pair
    seg = next(GroundPolyMotion(h1, h2, dt).poly_chunks())
    t0 = seg.t0.copy()
    t0[5] += 1e-6
    bad = [
        (dataclasses.replace(seg, t0=t0), "starts at"),
        (dataclasses.replace(seg, length=-seg.length), "length"),
        (dataclasses.replace(seg, coef=seg.coef[..., : DEGREE - 1]), "coef has shape"),
        (dataclasses.replace(seg, ends=~seg.ends), "ends"),
        (dataclasses.replace(seg, k1=seg.k1 + 1), "steps"),
        (dataclasses.replace(seg, step=seg.step.astype(np.int32)), "int64"),
    ]
    for s, what in bad:
        with pytest.raises(ModelError, match=what) as e:
            check_segments(s, dt)
        assert "\n" not in str(e.value) and e.value.where == "motion"
    with pytest.raises(ModelError, match="outside its record step"):
        check_segments(dataclasses.replace(seg, t0=seg.t0 + 0.5 * dt), dt)
    with pytest.raises(ModelError, match="floor 3"):
        samples_on_poly(GroundPolyMotion(h1, h2, dt), [3])


class _Chunks:
    """A poly motion handing out the given chunks."""

    def __init__(self, chunks, dt, npts):
        self.chunks, self.dt, self.npts = chunks, dt, npts
        self.floors = (0,)
        self.notes = ()

    def poly_chunks(self):
        yield from self.chunks


def test_chunks_must_cover_the_record_in_order(monkeypatch):
    import floorslide.building.poly_segments as ps

    monkeypatch.setattr(ps, "CHUNK_STEPS", 256)  # chunks of 256 steps: three on 600 samples
    rng = np.random.default_rng(1)
    h1, h2, dt = rng.normal(size=600), rng.normal(size=600), 0.01
    chunks = list(GroundPolyMotion(h1, h2, dt).poly_chunks())
    assert [(c.k0, c.k1) for c in chunks] == [(0, 256), (256, 512), (512, 599)]
    assert samples_on_poly(_Chunks(chunks, dt, 600)).shape == (1, 2, 600)
    for bad, what in (
        (_Chunks(chunks[:2], dt, 600), "end at step 512"),
        (_Chunks([chunks[0], chunks[2]], dt, 600), "starts at step 512"),
        (_Chunks(chunks[1:], dt, 600), "starts at step 256"),
        (_Chunks(chunks, dt, 1), "at least 2"),
    ):
        with pytest.raises(ModelError, match=what):
            samples_on_poly(bad)
