"""Approximate 2-DOF sliding oscillator (Newmark, grip-spring penalty): each converges to the exact
solver as its step, tolerance or grip stiffness is refined, on bundled real records.

Tolerances: both methods locate the stick/slip switches only to within a step (Newmark) or
follow them with a lag of order ``1/ω_g`` (penalty), so their errors fall about like ``h`` and
``1/f_g``, with noise (a switch moving across a step boundary); the tests compare a coarse with a
much finer setting (a factor 16–256 apart) and ask for a 10× smaller error and an absolute
bound a few times above the measured one.
"""

from __future__ import annotations

import numpy as np
import pytest

from floorslide.building.model import IsolatedBuilding, ShearBuilding
from floorslide.building.motions import floor_motions
from floorslide.contents.oscillator import slide_oscillator
from floorslide.errors import ModelError

OSC = dict(frequency=6.0, damping=0.02, mass_ratio=0.5)  # Brochard & Gantenbein (1989)


def errors(res, ref) -> tuple[float, float, float]:
    """Relative errors of the peak slide and peak deformation, and of the residual slide
    relative to the peak slide (max over objects)."""
    e_u = np.max(np.abs(res.peak_slide - ref.peak_slide) / ref.peak_slide)
    e_z = np.max(np.abs(res.peak_deformation - ref.peak_deformation) / ref.peak_deformation)
    e_r = np.max(np.abs(res.residual_slide - ref.residual_slide) / ref.peak_slide)
    return float(e_u), float(e_z), float(e_r)


def test_newmark_converges_on_the_ground(elcentro):
    acc, dt = elcentro
    mus = [0.05, 0.1]
    ref = slide_oscillator(acc, dt, mus, **OSC)
    coarse = errors(slide_oscillator(acc, dt, mus, **OSC, method="newmark", substeps=1), ref)
    fine = errors(slide_oscillator(acc, dt, mus, **OSC, method="newmark", substeps=256), ref)
    # measured: coarse (0.17, 0.012, 0.099), fine (7.9e-4, 7.0e-5, 1.1e-3)
    assert coarse[0] > 0.05
    for c, f in zip(coarse, fine, strict=True):
        assert f < c / 10
    assert max(fine) < 3e-3


def test_newmark_converges_with_static_friction_above_kinetic(elcentro):
    acc, dt = elcentro
    acc = acc[:1200]
    ref = slide_oscillator(acc, dt, 0.1, **OSC, mu_s=0.15)
    got = [
        errors(slide_oscillator(acc, dt, 0.1, **OSC, mu_s=0.15, method="newmark", substeps=k), ref)
        for k in (1, 256)
    ]
    # measured: (0.039, 0.013, ·) at dt, (2.9e-4, 1.2e-4, ·) at dt/256
    assert got[1][0] < got[0][0] / 10 and got[1][1] < got[0][1] / 10
    assert max(got[1][:2]) < 1.5e-3


def test_newmark_on_an_isolated_roof_uses_exact_floor_samples(coarse_record):
    acc, dt = coarse_record
    iso = IsolatedBuilding(ShearBuilding.from_period(3, 0.4, 0.05), 1.0, 2.5, 0.10)
    mus = [0.03, 0.06]
    kw = dict(building=iso, floor=3)
    ref = slide_oscillator(acc, dt, mus, **OSC, **kw)
    coarse = errors(slide_oscillator(acc, dt, mus, **OSC, **kw, method="newmark", substeps=1), ref)
    fine = errors(slide_oscillator(acc, dt, mus, **OSC, **kw, method="newmark", substeps=64), ref)
    # measured: coarse (0.019, 0.19, ·), fine (4.9e-5, 1.6e-5, ·)
    assert fine[0] < coarse[0] / 10 and fine[1] < coarse[1] / 10
    assert max(fine[:2]) < 5e-4
    # the same as Newmark on the (exact, oversampled) floor samples as a ground motion
    af = floor_motions(iso, acc, dt, floors=[3], oversample=4)[0]
    on_floor = slide_oscillator(acc, dt, mus, **OSC, **kw, method="newmark", substeps=4)
    on_samples = slide_oscillator(af, dt / 4, mus, **OSC, method="newmark", substeps=1)
    np.testing.assert_array_equal(on_floor.peak_slide, on_samples.peak_slide)


def test_newmark_without_sliding_is_the_newmark_sdof(elcentro):
    """mu large: the base never slips, and the oscillator by Newmark is the fixed-base SDOF by
    Newmark (floorslide's building solver, incremental form; same scheme, so to rounding)."""
    acc, dt = elcentro
    res = slide_oscillator(acc, dt, 100.0, **OSC, method="newmark", substeps=2)
    assert res.peak_slide[0] == 0.0 and res.slip_phases[0] == 0
    sdof = ShearBuilding.from_period(1, 1 / 6.0, 0.02)
    z = floor_motions(
        sdof, acc, dt, floors=[1], output="displacement", method="newmark", substeps=1,
        oversample=2,
    )[0]  # fmt: skip
    assert res.peak_deformation[0] == pytest.approx(np.abs(z).max(), rel=1e-10)


def test_penalty_converges_as_the_grip_stiffens(elcentro):
    acc, dt = elcentro
    acc = acc[:1200]
    ref = slide_oscillator(acc, dt, 0.1, **OSC, mu_s=0.15)
    got = [
        errors(
            slide_oscillator(
                acc, dt, 0.1, **OSC, mu_s=0.15, method="penalty", grip_frequency=f, rtol=1e-7
            ),
            ref,
        )
        for f in (50.0, 800.0)
    ]
    # measured: 50 Hz (0.036, 0.0099, ·), 800 Hz (7.8e-5, 2.0e-5, ·): error ~ 1/f_g or faster
    assert got[1][0] < got[0][0] / 10 and got[1][1] < got[0][1] / 10
    assert max(got[1][:2]) < 5e-4


def test_penalty_converges_as_rtol_shrinks(elcentro):
    acc, dt = elcentro
    acc = acc[:1200]
    ref = slide_oscillator(acc, dt, 0.1, **OSC, mu_s=0.15)
    loose, tight = (
        errors(
            slide_oscillator(
                acc, dt, 0.1, **OSC, mu_s=0.15, method="penalty", grip_frequency=800.0, rtol=rtol
            ),
            ref,
        )
        for rtol in (1e-2, 1e-7)
    )
    # measured: rtol 1e-2 (0.14, 0.036, ·), rtol 1e-7 (7.8e-5, 2.0e-5, ·)
    assert tight[0] < loose[0] / 10 and tight[1] < loose[1] / 10


@pytest.mark.parametrize("integrator", ["LSODA", "Radau"])
def test_penalty_on_a_stiff_floor(integrator, coarse_record):
    acc, dt = coarse_record
    acc = acc[:400]
    stiff = ShearBuilding.from_period(1, 0.1, 0.05)
    kw = dict(building=stiff, floor=1)
    ref = slide_oscillator(acc, dt, [0.1, 0.3], **OSC, **kw)
    got = slide_oscillator(
        acc, dt, [0.1, 0.3], **OSC, **kw, method="penalty", grip_frequency=400.0,
        integrator=integrator,
    )  # fmt: skip
    e_u, e_z, e_r = errors(got, ref)
    # measured on the whole record: 4.2e-4 and 7e-5 at 400 Hz
    assert e_u < 3e-3 and e_z < 3e-3 and e_r < 3e-3
    assert np.all(got.slide_fraction > 0) and np.all(got.slip_phases > 0)


def test_penalty_never_slipping_moves_only_by_the_grip(elcentro):
    acc, dt = elcentro
    acc = acc[:800]
    res = slide_oscillator(acc, dt, 100.0, **OSC, method="penalty", grip_frequency=100.0)
    assert res.slip_phases[0] == 0
    # the stuck base moves by F/k_g at most: |F| ≤ |q| + r|a_f| ≤ peak top acc + r·PGA
    kg = 1.5 * (2 * np.pi * 100.0) ** 2
    bound = (res.peak_top_accel[0] + 0.5 * np.abs(acc).max()) / kg
    assert 0 < res.peak_slide[0] <= bound * 1.01


@pytest.mark.parametrize(
    "bad",
    [
        dict(method="rk4"),
        dict(method="newmark", substeps=0),
        dict(method="newmark", substeps=2.5),
        dict(method="penalty", grip_frequency=0.0),
        dict(method="penalty", grip_damping=-0.1),
        dict(method="penalty", rtol=0.0),
        dict(method="penalty", integrator="RK45"),
        dict(method="newmark", histories=True),
    ],
)
def test_bad_approximate_settings(bad):
    with pytest.raises(ModelError):
        slide_oscillator(np.ones(10), 0.01, 0.1, **OSC, **bad)
