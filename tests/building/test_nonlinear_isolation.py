"""Buildings on nonlinear isolation (issue 14, first part: the building alone): closed forms and
limits that tie the event-driven exact solver to known answers."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.isolators import (
    PLASTIC_POS,
    SLIP_NEG,
    SLIP_POS,
    STICK,
    BilinearIsolator,
    FrictionPendulum,
)
from floorslide.building.nonlinear import NonlinearIsolatedBuilding, isolator_response
from floorslide.errors import ModelError
from tests.conftest import SLAMMER, G

ELC = SLAMMER / "ImperialValley_1940_ELC-180.txt"


@pytest.fixture(scope="module")
def elc() -> np.ndarray:
    return np.loadtxt(ELC)[:1500] * G  # the first 15 s, dt = 0.01 s


def rigid_mat(isolator, ratio=1e8):
    """A building whose superstructure is negligible against its mat: a rigid block on the
    isolator (the closed forms' model)."""
    sup = fs.ShearBuilding([1.0], [(2 * np.pi / 0.05) ** 2], damping=0.05)
    return NonlinearIsolatedBuilding(sup, ratio, isolator)


def test_friction_pendulum_free_decay_closed_form():
    """R = 2 m, mu = 0.05, u0 = 0.5 m: extremes 0.5, −0.3, 0.1, then at rest (|u| ≤ mu·R);
    each half cycle lasts π√(R/g), whatever the mass."""
    half = np.pi * np.sqrt(2.0 / G)
    for ratio in (1e8, 3e8):
        b = rigid_mat(FrictionPendulum(mu=0.05, radius=2.0), ratio)
        r = isolator_response(b, np.zeros(801), 0.01, initial_displacement=[0.5, 0.5])
        assert r.branch[0] == SLIP_NEG  # released at 0.5 m it slides back at once
        t = r.event_times
        assert r.event_branches[0] == SLIP_POS and t[0] == pytest.approx(half, rel=1e-9)
        assert r.event_branches[1] == STICK and t[1] == pytest.approx(2 * half, rel=1e-9)
        u = r.isolator_displacement
        k1, k2 = round(t[0] / 0.01), round(t[1] / 0.01)
        # the samples nearest the stops are within (v²/2a) of the extremes; the true peak is exact
        assert r.peak_displacement == pytest.approx(0.5, abs=1e-12)
        assert u[k1 - 2 : k1 + 3].min() == pytest.approx(-0.3, abs=1e-3)
        assert r.residual_displacement == pytest.approx(0.1, abs=1e-9)
        assert np.all(np.abs(u[k2 + 1 :] - 0.1) < 1e-9)


def test_pendulum_period_is_independent_of_mass():
    times = []
    for scale in (1.0, 50.0):
        sup = fs.ShearBuilding([scale], [scale * (2 * np.pi / 0.05) ** 2], damping=0.05)
        b = NonlinearIsolatedBuilding(sup, 1e8, FrictionPendulum(mu=0.02, period=3.0))
        r = isolator_response(b, np.zeros(501), 0.01, initial_displacement=[0.3, 0.3])
        times.append(r.event_times[:3])
    np.testing.assert_allclose(times[0], times[1], rtol=1e-12)
    assert times[0][0] == pytest.approx(1.5, rel=1e-9)  # half of T = 3 s
    assert times[0][1] == pytest.approx(3.0, rel=1e-9)


def linear_twin(period, damping=0.0):
    sup = fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.05)
    return sup, fs.IsolatedBuilding(sup, base_mass_ratio=1.0, period=period, damping=damping)


def test_frictionless_pendulum_is_the_linear_isolator(elc):
    """mu = 0: the pendulum is the linear isolator of stiffness W/R (period 2π√(R/g))."""
    sup, lin = linear_twin(3.0)
    b = NonlinearIsolatedBuilding(sup, 1.0, FrictionPendulum(mu=0.0, period=3.0))
    r = isolator_response(b, elc, 0.01)
    ref = fs.floor_motions(lin, elc, 0.01)
    scale = np.abs(ref).max()
    assert np.abs(r.floor_acceleration - ref).max() < 1e-9 * scale
    pk = fs.peak_floor_acceleration(lin, elc, 0.01).peak
    np.testing.assert_allclose(r.pfa, pk, rtol=1e-9)


def test_bilinear_without_strength_is_the_linear_isolator(elc):
    """Q → 0: the bilinear layer is the linear isolator of its post-yield stiffness k2."""
    sup, lin = linear_twin(2.5, damping=0.1)
    iso = BilinearIsolator(q_ratio=1e-13, period=2.5, yield_disp=0.01, damping=0.1)
    b = NonlinearIsolatedBuilding(sup, 1.0, iso)
    r = isolator_response(b, elc, 0.01)
    ref = fs.floor_motions(lin, elc, 0.01)
    assert np.abs(r.floor_acceleration - ref).max() < 1e-9 * np.abs(ref).max()


def test_bilinear_that_never_yields_is_linear_in_k1(elc):
    sup = fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.05)
    iso = BilinearIsolator(q_ratio=10.0, period=2.5, yield_disp=5.0)  # D_y far beyond reach
    b = NonlinearIsolatedBuilding(sup, 1.0, iso)
    k1 = b.constants["k1"]
    t1 = 2 * np.pi * np.sqrt(b.total_mass / k1)
    lin = fs.IsolatedBuilding(sup, base_mass_ratio=1.0, period=t1, damping=0.0)
    r = isolator_response(b, elc, 0.01)
    assert len(r.event_times) == 0
    ref = fs.floor_motions(lin, elc, 0.01)
    assert np.abs(r.floor_acceleration - ref).max() < 1e-9 * np.abs(ref).max()


def test_bilinear_yields_and_its_force_stays_on_the_bilinear_envelope(elc):
    sup = fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.03)
    iso = BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.01)
    b = NonlinearIsolatedBuilding(sup, 1.0, iso)
    r = isolator_response(b, elc * 2.0, 0.01)
    c = b.constants
    assert PLASTIC_POS in r.event_branches
    u, f = r.isolator_displacement, r.isolator_force
    # the force lies between the two yield lines k2·u ± Q (the envelope), to rounding
    lines = np.abs(f - c["k2"] * u)
    assert lines.max() <= c["Q"] * (1 + 1e-9) + 1e-6
    assert r.peak_displacement >= np.abs(u).max()
    assert r.peak_force_ratio * c["W"] >= np.abs(f).max() * (1 - 1e-12)


def test_bad_isolator_parameters_name_their_key():
    with pytest.raises(ModelError, match=r"isolator\.radius"):
        FrictionPendulum(mu=0.05, radius=-1.0)
    with pytest.raises(ModelError, match=r"isolator\.mu"):
        FrictionPendulum(mu=-0.1, radius=2.0)
    with pytest.raises(ModelError, match=r"isolator\.alpha"):
        BilinearIsolator(q_ratio=0.05, period=2.5, alpha=1.2)
    with pytest.raises(ModelError, match=r"isolator\.q_ratio"):
        BilinearIsolator(q_ratio=0.0, period=2.5, yield_disp=0.01)
    with pytest.raises(ModelError, match="one of yield_disp and alpha"):
        BilinearIsolator(q_ratio=0.05, period=2.5)


def _loop_energy(k1, k2, Q, D, n=200_000):
    """∮ f du of the bilinear element over the cycle 0 → D → −D → D (the last two legs: one
    closed loop), by hand: the elastic–plastic part stepped on a fine path, trapezoid rule."""
    path = np.concatenate(
        [np.linspace(0, D, n), np.linspace(D, -D, 2 * n)[1:], np.linspace(-D, D, 2 * n)[1:]]
    )
    q = np.zeros(path.size)
    for i in range(1, path.size):
        q[i] = np.clip(q[i - 1] + (k1 - k2) * (path[i] - path[i - 1]), -Q, Q)
    f = k2 * path + q
    loop = slice(n - 1, None)
    u, f = path[loop], f[loop]
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(u)))


def test_equivalent_linear_dissipates_the_loop_energy():
    from floorslide.building.isolators import equivalent_linear

    iso = BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02)
    M = 2e5
    c = iso.constants(M)
    for D in (0.06, 0.2):
        T, beta = equivalent_linear(iso, M, D)
        k_eff = M * (2 * np.pi / T) ** 2
        assert k_eff == pytest.approx(c["k2"] + c["Q"] / D, rel=1e-12)
        energy = _loop_energy(c["k1"], c["k2"], c["Q"], D)
        assert energy == pytest.approx(4 * c["Q"] * (D - c["D_y"]), rel=1e-4)
        assert 2 * np.pi * beta * k_eff * D * D == pytest.approx(energy, rel=1e-4)
    fps = FrictionPendulum(mu=0.05, radius=2.0)
    T, beta = equivalent_linear(fps, M, 0.2)
    assert beta == pytest.approx(2 * 0.05 / (np.pi * (0.05 + 0.2 / 2.0)), rel=1e-12)
    assert T < fps.T  # friction stiffens the secant
    T0, beta0 = equivalent_linear(FrictionPendulum(mu=0.0, radius=2.0), M, 0.2)
    assert T0 == pytest.approx(fps.T, rel=1e-12) and beta0 == 0.0
    sup = fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.03)
    lin = NonlinearIsolatedBuilding(sup, 1.0, iso).equivalent_linear(0.2)
    assert isinstance(lin, fs.IsolatedBuilding) and lin.isolation_damping > 0.1


def test_the_kernels_warm_up_in_side_processes():
    """A study's kernels compile (or load) in side processes that exit cleanly; a process
    that has them already starts none."""
    from floorslide.run import warmup

    procs = warmup.start(["linear", "nonlinear"])
    warmup.finish(procs)
    assert all(p.exitcode == 0 for p in procs)
    warmup._linear_tasks()  # (from the disk cache the side processes filled)
    warmup._nonlinear_tasks()
    assert warmup.start(["linear", "nonlinear"]) == []


def test_no_side_process_for_kernels_the_disk_cache_holds(monkeypatch):
    """Kernels compiled already (the first run's families, marked in the disk cache) are not
    loaded in side processes for nothing: a warm run starts none, even in a process that has
    not loaded them yet."""
    from floorslide import firstrun
    from floorslide.run import warmup

    monkeypatch.setattr(warmup, "_loaded", lambda family: False)
    asked: list[str] = []
    monkeypatch.setattr(firstrun, "missing", lambda names: asked.extend(names) or [])
    assert warmup.start(["linear", "nonlinear"]) == []
    assert asked == ["study", "nonlinear-core", "study-nonlinear"]
