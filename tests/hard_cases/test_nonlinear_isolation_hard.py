"""Hard cases of buildings on nonlinear isolation (issue 14): extreme strengths and friction,
chatter, a tall superstructure, a million samples, a capacity exceeded — finite, stable, and
still right where a closed form or a limit says what right is."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.isolators import STICK, BilinearIsolator, FrictionPendulum
from floorslide.building.nonlinear import NonlinearIsolatedBuilding, isolator_response
from tests.conftest import SLAMMER, G


@pytest.fixture(scope="module")
def elc() -> np.ndarray:
    return np.loadtxt(SLAMMER / "ImperialValley_1940_ELC-180.txt") * G


def one_storey():
    return fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.03)


@pytest.mark.parametrize("q_ratio", [1e-4, 0.3])
def test_bilinear_extreme_strengths(elc, q_ratio):
    b = NonlinearIsolatedBuilding(
        one_storey(), 1.0, BilinearIsolator(q_ratio=q_ratio, period=2.5, yield_disp=0.01)
    )
    r = isolator_response(b, elc, 0.01)
    c = b.constants
    assert np.all(np.isfinite(r.floor_acceleration))
    # on the envelope k2·u ± Q
    assert (
        np.abs(r.isolator_force - c["k2"] * r.isolator_displacement).max()
        <= c["Q"] * (1 + 1e-9) + 1e-9 * c["W"]
    )


def test_friction_pendulum_with_high_friction_stays_stuck_under_weak_shaking(elc):
    """mu = 0.2 against a record scaled to 0.08 g: never slides — the mat moves with the ground,
    and the building is the fixed-base superstructure on it."""
    sup = one_storey()
    b = NonlinearIsolatedBuilding(sup, 1.0, FrictionPendulum(mu=0.2, period=3.0))
    a = elc * (0.08 / (np.abs(elc).max() / G))
    r = isolator_response(b, a, 0.01)
    assert len(r.event_times) == 0 and np.all(r.branch == STICK)
    assert r.peak_displacement == 0.0
    np.testing.assert_array_equal(r.floor_acceleration[0], a)  # the mat is the ground
    # the roof: the fixed-base building's, with the mat as its ground
    roof_fixed = fs.floor_motions(sup, a, 0.01, floors=[1])[0]
    assert np.abs(r.floor_acceleration[1] - roof_fixed).max() < 1e-9 * np.abs(roof_fixed).max()


def test_chatter_many_stick_slip_switches(elc):
    """A 25 Hz shaking just above the friction limit: hundreds of breakaways and stops, each
    located; finite and the stops at rest."""
    stiff = fs.ShearBuilding.from_period(stories=1, period=0.01, damping=0.02)
    b = NonlinearIsolatedBuilding(stiff, 1.0, FrictionPendulum(mu=0.05, period=3.0))
    t = np.arange(0, 4, 0.002)
    a = 0.06 * G * np.sin(2 * np.pi * 25 * t)
    r = isolator_response(b, a, 0.002)
    assert len(r.event_times) > 100
    assert np.all(np.diff(r.event_times) >= 0)
    assert np.isfinite(r.peak_displacement) and r.peak_displacement < 0.01


def test_long_undamped_post_yield_period(elc):
    b = NonlinearIsolatedBuilding(
        one_storey(), 1.0, BilinearIsolator(q_ratio=0.03, period=6.0, yield_disp=0.005)
    )
    r = isolator_response(b, elc, 0.01)
    assert np.isfinite(r.peak_displacement) and r.peak_displacement > 0.05


def test_twenty_storeys_on_a_frictionless_pendulum_is_the_linear_isolator(elc):
    sup = fs.ShearBuilding.from_period(stories=20, period=2.0, damping=0.05)
    b = NonlinearIsolatedBuilding(sup, 0.5, FrictionPendulum(mu=0.0, period=4.0))
    lin = fs.IsolatedBuilding(sup, base_mass_ratio=0.5, period=4.0, damping=0.0)
    a = elc[:1000]
    r = isolator_response(b, a, 0.01, floors=[0, 10, 20])
    ref = fs.floor_motions(lin, a, 0.01, floors=[0, 10, 20])
    assert np.abs(r.floor_acceleration - ref).max() < 1e-8 * np.abs(ref).max()


def test_a_million_samples(elc):
    a = np.tile(elc, 1_000_000 // elc.size + 1)[:1_000_000]
    b = NonlinearIsolatedBuilding(
        one_storey(), 1.0, BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02)
    )
    r = isolator_response(b, a, 0.01, floors=[1])
    assert r.floor_acceleration.shape == (1, 1_000_000)
    assert np.all(np.isfinite(r.floor_acceleration)) and np.isfinite(r.peak_displacement)


def test_capacity_exceeded_is_reported(elc):
    iso = FrictionPendulum(mu=0.03, period=3.0, capacity=0.02)
    r = isolator_response(NonlinearIsolatedBuilding(one_storey(), 1.0, iso), elc, 0.01)
    assert r.peak_displacement > 0.02 and r.capacity_exceeded
    assert "not modelled" in r.notes[0]
    ok = FrictionPendulum(mu=0.03, period=3.0, capacity=10.0)
    r = isolator_response(NonlinearIsolatedBuilding(one_storey(), 1.0, ok), elc, 0.01)
    assert not r.capacity_exceeded and r.notes == ()


def test_a_million_samples_streamed_to_every_consumer(elc):
    """A million samples on friction pendulums: the motion's segments do not fit the memory a
    motion keeps whole, so it is streamed (each consumer's pass integrates the chunks again from
    checkpoints); a block too rough to slide feels the floor's true PFA, and the spectrum's
    zero period is that PFA too."""
    a = np.tile(elc, 1_000_000 // elc.size + 1)[:1_000_000]
    b = NonlinearIsolatedBuilding(one_storey(), 1.0, fs.FrictionPendulum(mu=0.05, period=3.0))
    m = b.motion(a, 0.01, floors=[1], max_bytes=64 * 2**20)
    assert not m.kept_whole and len(m._checkpoints) > 10
    fm = m.floor(1)
    pfa = fm.peak()[0]
    s = fs.slide(fm, mu_k=[0.05, 5.0])
    assert s.peak_slide[0] > 0 and s.peak_slide[1] == 0.0
    assert s.peak_abs_accel[1] == pytest.approx(pfa, rel=1e-12)
    sp = fs.response_spectrum(fm, periods=[0.0, 1.0])
    assert sp.sa[0, 0] == pfa and np.isfinite(sp.psa).all()
