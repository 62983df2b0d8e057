"""Hard cases of sliding in the plane (issue 16): friction from 1e-4 to 2, components of very
different amplitude, a velocity that passes near zero while the floor still drives it, sticking
just below the static limit for a long time, a million-sample pair."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

import floorslide as fs
from floorslide.contents.plane import slide_plane
from floorslide.records.pairs import read_pairs
from tests.conftest import ROOT

PAIRS = ROOT / "data" / "records" / "pairs" / "index.csv"


@pytest.fixture(scope="module")
def sylmar():
    (p,) = read_pairs(PAIRS, where={"rsn": "1084"})
    return p


def balance(r, mus):
    kinetic = 0.5 * np.sum(r.final_velocity**2, axis=1)
    return np.abs(kinetic + mus * fs.G * r.path + r.work_floor)


def test_friction_from_1e_4_to_2(sylmar):
    mus = np.array([1e-4, 2.0])
    r = slide_plane(sylmar, None, mus, compare_1d=False)
    assert np.all(np.isfinite(r.peak_slide))
    assert r.peak_slide[1] == 0.0 and r.slip_phases[1] == 0  # 2 g > the PGA (0.92 g)
    assert r.peak_slide[0] > 0.2  # nearly frictionless: the ground's own displacement
    assert balance(r, mus)[0] <= 1e-12 * max(np.abs(r.work_floor[0]), 1e-300)


def test_components_of_very_different_amplitude_approach_the_1d_slide(sylmar):
    """h2 scaled by 1e-7: the plane slide tends to h1's 1-D slide (to ~1e-7 relative)."""
    mus = [0.05, 0.15]
    r = slide_plane((sylmar.h1, 1e-7 * sylmar.h2), sylmar.dt, mus)
    ref = fs.slide(sylmar.h1, sylmar.dt, mus)
    np.testing.assert_allclose(r.peak_slide, ref.peak_slide, rtol=1e-5)


def test_velocity_passing_near_zero_while_driven():
    """A push along x, then one along y of the same size, crossing just as the block would stop:
    its velocity passes (near) zero while |a| > mu g, its direction turns fast — no hang, no
    chatter, the energy balance holds."""
    dt = 0.001
    t = np.arange(0, 4, dt)
    ax = np.where(t < 1.0, 4.0, 0.0) + np.where((t >= 1.0) & (t < 1.2), -4.0 * 9, 0.0)
    ay = np.where(t >= 1.1, 3.0 * np.sin(7 * t), 0.0)
    mus = np.array([0.1, 0.3])
    r = slide_plane((ax, ay), dt, mus, histories=True, compare_1d=False)
    assert np.all(np.isfinite(r.peak_slide)) and np.all(r.stops < 1000)
    assert np.all(balance(r, mus) <= 1e-11 * mus * fs.G * r.path)


def test_a_million_sample_pair_in_bounded_memory(sylmar):
    """The pair repeated to a million samples: memory O(1) beyond the record, and a late copy
    slides as the first (no drift)."""
    quiet = np.zeros(2000)  # 10 s of rest between copies: the block stops in it
    whole = 1_000_000 // (sylmar.npts + quiet.size)
    reps = whole + 1
    h1 = np.tile(np.concatenate([sylmar.h1, quiet]), reps)[:1_000_000]
    h2 = np.tile(np.concatenate([sylmar.h2, quiet]), reps)[:1_000_000]
    tracemalloc.start()
    r = slide_plane((h1, h2), sylmar.dt, 0.2, compare_1d=False)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert peak < 40e6
    one = slide_plane(sylmar, None, 0.2, compare_1d=False)
    assert r.slip_phases[0] >= whole * one.slip_phases[0]
    assert np.isfinite(r.peak_slide[0]) and r.peak_slide[0] >= one.peak_slide[0]


@pytest.mark.parametrize("mu_k", [0.2, 0.15])
def test_sticking_just_below_the_static_limit_for_a_long_time(mu_k):
    """A floor acceleration of constant magnitude turning in the plane, 1e-9 below mu_s·g for
    200 s (40,000 samples): the block never moves — no chatter, no creeping — and 1e-9 above
    it breaks away at once and slides."""
    mu_s = 0.2
    dt = 0.005
    t = np.arange(40_001) * dt
    w = 2 * np.pi * 0.7
    for factor, moves in ((1 - 1e-9, False), (1 + 1e-9, True)):
        A = factor * mu_s * fs.G
        r = fs.slide_plane((A * np.cos(w * t), A * np.sin(w * t)), dt, mu_k, mu_s,
                           compare_1d=False)  # fmt: skip
        if not moves:
            assert r.peak_slide[0] == 0.0
            assert r.slip_phases[0] == 0 and r.slide_fraction[0] == 0.0
        else:
            assert r.slip_phases[0] >= 1 and r.peak_slide[0] > 0.0
            assert np.isfinite(r.peak_slide[0])
