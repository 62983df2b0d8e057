"""Approximate methods of the heavy block coupled with its floor
(:mod:`floorslide.contents.coupled_approx`): both approach the exact :func:`floorslide.
slide_coupled` as their setting is refined, and refuse bad settings in one line.

The case: the first 10 s of PET-090 (dt = 0.02 s), a block of 10 % of the roof's mass with
mu = 0.5 on the roof of a 3-storey fixed-base building (T = 0.5 s, 5 %): exact peak slide
0.197 m, roof PFA 17.06 m/s².
"""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.bench.study import load_records
from floorslide.contents.coupled_approx import slide_coupled_newmark, slide_coupled_smoothed
from floorslide.errors import ModelError

MU = 0.5


@pytest.fixture(scope="module")
def case():
    rec = load_records(("PET-090",))[0]
    building = fs.ShearBuilding.from_period(3, 0.5, 0.05)
    kw = dict(mass=0.1 * float(building.mass[-1]), building=building, floor=3)
    acc = rec.acc[:500]
    return acc, rec.dt, kw, fs.slide_coupled(acc, rec.dt, MU, **kw)


def rel(got, ref):
    return float(np.max(np.abs(got / ref - 1.0)))


def test_smoothed_approaches_exact_as_eps_shrinks(case):
    """Measured (rtol 1e-8): peak slide 1.4e-2, 1.7e-3, 2.1e-4 and PFA 7.7e-4, 9.3e-5, 1.0e-5
    at eps = 1e-2, 1e-3, 1e-4 m/s: the regularisation's error, ~ linear in eps."""
    acc, dt, kw, ex = case
    errs = []
    for eps in (1e-2, 1e-4):
        r = slide_coupled_smoothed(acc, dt, MU, eps=eps, rtol=1e-8, **kw)
        errs.append((rel(r.peak_slide, ex.peak_slide), rel(r.pfa, ex.pfa)))
    assert 5e-3 < errs[0][0] < 3e-2
    assert errs[1][0] < 5e-4 and errs[1][1] < 5e-5
    assert errs[1][0] < errs[0][0] / 20 and errs[1][1] < errs[0][1] / 20


def test_newmark_approaches_exact_as_substeps_grow(case):
    """Measured: peak slide 0.135, 0.059, 9.2e-3, 3.6e-3 and PFA 1.6e-2, 3.6e-3, 5.2e-4,
    3.7e-4 at dt/1, dt/4, dt/16, dt/64 (switches late by up to a sub-step: first order)."""
    acc, dt, kw, ex = case
    errs = [
        rel(slide_coupled_newmark(acc, dt, MU, substeps=k, **kw).peak_slide, ex.peak_slide)
        for k in (1, 16, 64)
    ]
    assert errs[0] > 0.05  # the record's own step is visibly wrong
    assert errs[1] < errs[0] / 5 and errs[2] < 6e-3


def test_few_substeps_and_mass_to_zero_agree_with_slide():
    """A tiny block barely acts back: Newmark's coupled slide is then the decoupled one's on
    the same floor (within its own step error)."""
    rng = np.random.default_rng(3)
    acc = np.convolve(rng.standard_normal(300), np.ones(5) / 5, "same") * 4.0
    b = fs.ShearBuilding.from_period(2, 0.3, 0.05)
    ex = fs.slide_coupled(acc, 0.01, 0.2, mass=1e-6 * float(b.mass[-1]), building=b, floor=2)
    r = slide_coupled_newmark(
        acc, 0.01, 0.2, mass=1e-6 * float(b.mass[-1]), building=b, floor=2, substeps=32
    )
    assert rel(r.peak_slide, ex.peak_slide) < 0.02


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda a, kw: slide_coupled_smoothed(a, 0.02, MU, eps=0.0, **kw), "eps"),
        (lambda a, kw: slide_coupled_smoothed(a, 0.02, MU, rtol=2.0, **kw), "rtol"),
        (lambda a, kw: slide_coupled_smoothed(a, 0.02, MU, integrator="RK45", **kw), "integrator"),
        (lambda a, kw: slide_coupled_newmark(a, 0.02, MU, substeps=0, **kw), "substeps"),
        (lambda a, kw: slide_coupled_newmark(a, 0.02, MU, substeps=2.5, **kw), "substeps"),
        (lambda a, kw: slide_coupled_newmark(a, 0.02, MU, mu_s=0.1, **kw), "mu_s"),
        (lambda a, kw: slide_coupled_newmark(a, 0.02, MU, **{**kw, "floor": 0}), "floor"),
        (lambda a, kw: slide_coupled_smoothed(a, 0.02, MU, **{**kw, "building": None}), "building"),
    ],
)
def test_bad_settings_are_refused_in_one_line(call, field):
    b = fs.ShearBuilding.from_period(3, 0.5, 0.05)
    kw = dict(mass=0.1 * float(b.mass[-1]), building=b, floor=3)
    with pytest.raises(ModelError, match=field) as err:
        call(np.zeros(20), kw)
    assert "\n" not in str(err.value)
