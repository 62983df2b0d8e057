"""The smoothed plane oscillator (:mod:`floorslide.contents.plane_oscillator_approx`)
approaches the exact :func:`floorslide.slide_oscillator_plane` as ``eps → 0``, on the ground
and on a floor (the building integrated inside the ODE), and refuses bad settings in one line.

The case: the first 6 s of the RSN 511 pair (dt = 0.005 s), the bench's oscillator (6 Hz, 2 %,
m₁/m₂ = 0.5). Ground, mu 0.05: exact peak slide 4.56 mm, peak deformation 1.00 mm. On the floor
of a 1-storey building (T = 0.2 s, 5 %), mu 0.08: 6.01 mm and 1.43 mm.
"""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.bench.cases import OSCILLATOR
from floorslide.bench.study import load_pairs
from floorslide.contents.plane_oscillator_approx import slide_oscillator_plane_smoothed
from floorslide.errors import ModelError


@pytest.fixture(scope="module")
def pair():
    p = load_pairs(("511",))[0]
    return p.acc[:, :1200], p.dt


def rel(got, ref):
    return float(np.max(np.abs(got / ref - 1.0)))


def errors(pair, mu, eps, **kw):
    acc, dt = pair
    ex = fs.slide_oscillator_plane(acc, dt, mu, **OSCILLATOR, **kw)
    r = slide_oscillator_plane_smoothed(acc, dt, mu, **OSCILLATOR, eps=eps, rtol=1e-8, **kw)
    return rel(r.peak_slide, ex.peak_slide), rel(r.peak_deformation, ex.peak_deformation)


def test_ground_approaches_exact_as_eps_shrinks(pair):
    """Measured (rtol 1e-8): peak slide 0.15, 0.051, 3.8e-3 and peak deformation 0.30, 0.070,
    0.011 at eps = 1e-2, 1e-3, 1e-4 m/s (the slides are millimetres: eps must be well below
    the sliding speeds, a few cm/s)."""
    coarse = errors(pair, 0.05, 1e-2)
    fine = errors(pair, 0.05, 1e-4)
    assert coarse[0] > 0.05 and coarse[1] > 0.1  # visibly wrong at 1 cm/s
    assert fine[0] < 0.01 and fine[1] < 0.02
    assert fine[0] < coarse[0] / 10 and fine[1] < coarse[1] / 10


def test_floor_approaches_exact_as_eps_shrinks(pair):
    """On a floor, the building inside the ODE. Measured: peak slide 0.013, 0.10, 0.015 (not
    monotone: a lucky cancellation at 1e-2) and peak deformation 0.12, 0.013, 2.3e-3 at
    eps = 1e-2, 1e-3, 1e-4 m/s."""
    b = fs.ShearBuilding.from_period(1, 0.2, 0.05)
    coarse = errors(pair, 0.08, 1e-3, building=b, floor=1)
    fine = errors(pair, 0.08, 1e-4, building=b, floor=1)
    assert fine[0] < 0.03 and fine[1] < 0.005
    assert fine[0] < coarse[0] / 3 and fine[1] < coarse[1] / 3


def test_a_pair_along_one_axis_slides_along_it(pair):
    acc, dt = pair
    one = np.vstack([acc[0], np.zeros_like(acc[0])])
    r = slide_oscillator_plane_smoothed(one, dt, 0.05, **OSCILLATOR, eps=1e-3, rtol=1e-6)
    assert abs(r.residual[0, 1]) < 1e-12 and r.peak_slide[0] > 0


@pytest.mark.parametrize(
    ("kw", "field"),
    [
        ({"eps": -1.0}, "eps"),
        ({"rtol": 0.0}, "rtol"),
        ({"integrator": "RK45"}, "integrator"),
        ({"floor": 2}, "floor"),
        ({"building": fs.ShearBuilding.from_period(1, 0.2, 0.05)}, "floor"),
        ({"building": "a building", "floor": 1}, "building"),
    ],
)
def test_bad_settings_are_refused_in_one_line(kw, field):
    acc = np.zeros((2, 20))
    with pytest.raises(ModelError, match=field) as err:
        slide_oscillator_plane_smoothed(acc, 0.01, 0.1, frequency=5.0, **kw)
    assert "\n" not in str(err.value)
