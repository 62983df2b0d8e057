"""Floor response spectra of buildings on nonlinear isolation (issue 14): exact end to end."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.nonlinear import isolator_response
from tests.conftest import SLAMMER, G

PERIODS = [0.0, 0.05, 0.2, 0.5, 1.0, 3.0]


@pytest.fixture(scope="module")
def elc() -> np.ndarray:
    return np.loadtxt(SLAMMER / "ImperialValley_1940_ELC-180.txt") * G


def building(isolator):
    sup = fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.03)
    return fs.NonlinearIsolatedBuilding(sup, 1.0, isolator)


def test_frictionless_pendulum_equals_the_linear_floor_spectrum(elc):
    b = building(fs.FrictionPendulum(mu=0.0, period=3.0))
    lin = fs.IsolatedBuilding(b.superstructure, 1.0, 3.0, 0.0)
    sp = fs.response_spectrum(elc, 0.01, PERIODS, [0.02, 0.05], building=b, floor=2)
    ref = fs.response_spectrum(elc, 0.01, PERIODS, [0.02, 0.05], building=lin, floor=2)
    for name in ("psa", "sa", "sv", "sd", "psv"):
        a, r = getattr(sp, name), getattr(ref, name)
        assert np.abs(a - r).max() <= 1e-11 * np.abs(r).max(), name


@pytest.mark.parametrize(
    "isolator",
    [
        fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02),
        fs.FrictionPendulum(mu=0.06, period=3.0),
    ],
    ids=["bilinear", "pendulum"],
)
def test_converges_to_the_spectrum_of_finely_sampled_floor_motion(elc, isolator):
    """Independent check: the floor's exact acceleration sampled at dt/n, taken as piecewise
    linear by the ground spectrum (Nigam–Jennings exact for that), is an O((dt/n)²)
    approximation of the true floor motion — its spectrum converges on the exact one."""
    a = 1.5 * elc[:800]
    dt = 0.01
    b = building(isolator)
    T = [0.1, 0.3, 1.0]
    exact = fs.response_spectrum(a, dt, T, 0.05, building=b, floor=2)
    t = np.arange(a.size) * dt
    errors = []
    for n in (4, 16):
        tf = np.arange((a.size - 1) * n + 1) * (dt / n)
        roof = isolator_response(b, np.interp(tf, t, a), dt / n, floors=[2]).floor_acceleration[0]
        ref = fs.response_spectrum(roof, dt / n, T, 0.05)
        errors.append(np.abs(ref.psa - exact.psa).max() / exact.psa.max())
    assert errors[1] < 1e-4
    assert errors[1] < errors[0] / 10  # O(h²): about 16× per 4× finer


def test_period_zero_is_the_true_peak_floor_acceleration(elc):
    b = building(fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02))
    sp = fs.response_spectrum(elc, 0.01, [0.0, 1.0], 0.05, building=b, floor=1)
    assert sp.sa[0, 0] == pytest.approx(
        isolator_response(b, elc, 0.01, floors=[1]).pfa[0], rel=1e-12
    )
    with pytest.raises(fs.ModelError, match="not available on a building on nonlinear"):
        fs.response_spectrum(elc, 0.01, [1.0], 0.05, building=b, floor=1, method="newmark")


@pytest.mark.parametrize(
    "isolator",
    [
        fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02),
        fs.FrictionPendulum(mu=0.06, mu_s=0.08, period=3.0),
    ],
    ids=["bilinear", "pendulum"],
)
def test_riding_oscillators_equal_oscillators_integrated_as_states(elc, isolator):
    """Two exact forms: the oscillators' Taylor series on the floor's in-step polynomial (the
    spectrum's) and the oscillator as two more states of every branch (a linear system solved
    by the branch's own recurrence and Taylor rows)."""
    a = 1.5 * elc[:1200]
    b = building(isolator)
    sp = fs.response_spectrum(a, 0.01, [0.05, 0.3, 2.0], [0.02, 0.1], building=b, floor=2)
    for i, xi in enumerate([0.02, 0.1]):
        for j, T in enumerate([0.05, 0.3, 2.0]):
            w = 2 * np.pi / T
            r = isolator_response(b, a, 0.01, floors=[2], oscillator=(2, w, xi))
            np.testing.assert_allclose([sp.sd[i, j], sp.sv[i, j], sp.sa[i, j]], r.pfa, rtol=1e-9)
