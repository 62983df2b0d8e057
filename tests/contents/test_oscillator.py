"""The 2-DOF sliding oscillator: limits, Brochard & Gantenbein's case, an independent reference."""

from __future__ import annotations

import numpy as np
import pytest

from floorslide.building.model import IsolatedBuilding, ShearBuilding
from floorslide.building.motions import floor_motions
from floorslide.contents.oscillator import slide_oscillator
from floorslide.contents.rocking import response_mode
from floorslide.contents.sliding import slide
from floorslide.errors import ModelError
from tests.reference import sliding_oscillator


def test_free_free_frequency_of_brochard_case():
    """Clamped 6 Hz, m2/m1 = 0.5: free–free frequency 6·√(1 + 1/r) = 6√3 = 10.3923 Hz. With
    mu = 0.01 the base slides most of the time and the spring vibrates at it (FFT peak within the
    frequency resolution plus the stick phases' pull, 2 %)."""
    assert 6 * np.sqrt(1 + 1 / 0.5) == pytest.approx(10.3923, abs=5e-5)


def test_fixed_base_limit_is_the_sdof_oscillator_exactly(elcentro):
    acc, dt = elcentro
    res = slide_oscillator(
        acc, dt, 1e6, frequency=6.0, damping=0.02, mass_ratio=0.5, histories=True
    )
    sdof = ShearBuilding.from_period(1, 1 / 6.0, 0.02)
    z = floor_motions(sdof, acc, dt, floors=[1], output="displacement")[0]
    np.testing.assert_allclose(res.z[0], z, rtol=0, atol=1e-12 * np.abs(z).max())
    assert res.peak_slide[0] == 0.0 and res.slip_phases[0] == 0
    top = floor_motions(sdof, acc, dt, floors=[1])[0]
    np.testing.assert_allclose(res.top_accel[0], top, rtol=0, atol=1e-11 * np.abs(top).max())
    np.testing.assert_allclose(res.base_accel[0], acc, rtol=0, atol=1e-15 * np.abs(acc).max())


def test_stiff_spring_converges_to_the_rigid_block(elcentro):
    """A very stiff spring: the 2-DOF becomes one rigid block of mass m1 + m2
    (docs/design.md §8)."""
    acc, dt = elcentro
    rigid = slide(acc, dt, [0.1, 0.2]).peak_slide
    errs = []
    for f in (50.0, 400.0, 1600.0):  # 1600 Hz: 348 exact sub-steps per record step
        res = slide_oscillator(acc, dt, [0.1, 0.2], frequency=f, damping=0.05, mass_ratio=0.5)
        assert np.all(np.isfinite(res.peak_slide))
        errs.append(np.abs(res.peak_slide - rigid).max() / rigid.max())
    assert errs[2] < 5e-5
    assert errs[0] > errs[1] > errs[2]


@pytest.mark.parametrize("mu", [0.02, 0.1])
def test_agrees_with_independent_event_integration(mu, elcentro):
    acc, dt = elcentro
    acc = np.concatenate([[0.0], acc[150:650]])  # from rest: the reference detects crossings only
    res = slide_oscillator(acc, dt, mu, frequency=6.0, damping=0.02, mass_ratio=0.5)
    pu, ures, pz = sliding_oscillator(acc, dt, mu, 6.0, 0.02, 0.5)
    assert res.slip_phases[0] > 3
    assert res.peak_slide[0] == pytest.approx(pu, rel=1e-7)
    assert res.residual_slide[0] == pytest.approx(ures, abs=1e-7 * pu)
    assert res.peak_deformation[0] == pytest.approx(pz, rel=1e-7)


def test_on_a_floor_equals_on_the_exact_floor_motion_when_stuck(elcentro):
    """Stuck on the roof of an isolated building, the oscillator is the SDOF driven by the
    building's exact floor motion: as a 2-storey chain (building + oscillator) it matches."""
    acc, dt = elcentro
    acc = acc[:1500]
    iso = IsolatedBuilding(ShearBuilding.from_period(2, 0.3, 0.05), 1.0, 2.5, 0.1)
    res = slide_oscillator(
        acc,
        dt,
        10.0,
        frequency=8.0,
        damping=0.03,
        mass_ratio=1.0,
        building=iso,
        floor=2,
        histories=True,
    )
    assert res.slip_phases[0] == 0
    # reference: integrate building + oscillator as one linear system
    from tests.reference import linear_response

    A, B = iso.state_matrices()
    Ca, _, _ = iso.output_matrices([2])
    n = A.shape[0]
    w = 2 * np.pi * 8.0
    Aug = np.zeros((n + 2, n + 2))
    Aug[:n, :n] = A
    Aug[n, n + 1] = 1.0
    Aug[n + 1, :n] = -Ca[0]
    Aug[n + 1, n] = -(w**2)
    Aug[n + 1, n + 1] = -2 * 0.03 * w
    X = linear_response(Aug, np.concatenate([B[:, 0], [0.0, 0.0]]), acc, dt)
    np.testing.assert_allclose(res.z[0], X[:, n], rtol=0, atol=1e-9 * np.abs(X[:, n]).max())


def test_brochard_low_friction_vibrates_at_free_free_frequency(elcentro):
    acc, dt = elcentro
    res = slide_oscillator(
        acc, dt, 0.01, frequency=6.0, damping=0.02, mass_ratio=0.5, histories=True
    )
    assert res.slide_fraction[0] > 0.8
    freq = np.fft.rfftfreq(acc.size, dt)
    spec = np.abs(np.fft.rfft(res.z[0]))
    sel = freq > 2.0
    assert freq[sel][np.argmax(spec[sel])] == pytest.approx(6 * np.sqrt(3), rel=0.02)


@pytest.mark.parametrize(
    "bad",
    [
        dict(frequency=0.0),
        dict(frequency=6.0, damping=1.0),
        dict(frequency=6.0, mass_ratio=0.0),
        dict(frequency=6.0, mu=-1.0),
        dict(frequency=6.0, mass_ratio="x"),  # a ValueError before: now one line
        dict(frequency="fast"),
    ],
)
def test_bad_oscillator_parameters(bad):
    kw = dict(mu=0.1) | bad
    with pytest.raises(ModelError):
        slide_oscillator(np.zeros(10), 0.01, **kw)


@pytest.mark.parametrize(
    ("width", "height", "mu_s", "peak_g", "mode"),
    [
        (0.6, 1.2, 0.3, 0.2, "rest"),  # B/H = 0.5 > mu: slides above 0.3 g
        (0.6, 1.2, 0.3, 0.31, "slide"),
        (0.6, 1.2, 0.3, 0.6, "slide"),
        (0.4, 2.0, 0.3, 0.25, "rock"),  # B/H = 0.2 < mu: rocks above 0.2 g
        (0.4, 2.0, 0.3, 0.19, "rest"),
        (0.5, 1.0, 0.5, 0.51, "slide-rock"),
        (0.5, 1.0, 0.5, 0.5, "rest"),
    ],
)
def test_shenton_response_mode(width, height, mu_s, peak_g, mode):
    assert response_mode(width, height, mu_s, peak_g * 9.80665) == mode


def test_response_mode_bad_input():
    with pytest.raises(ModelError):
        response_mode(0.0, 1.0, 0.3, 1.0)
    with pytest.raises(ModelError):
        response_mode(1.0, 1.0, -0.3, 1.0)
