"""The nonlinear-isolator reference (tests/reference_isolators.py) against closed forms, limiting
cases and an independent linear integration: the reference is validated here before the
package's exact solver is tested against it."""

from __future__ import annotations

import numpy as np
import pytest

from tests.reference import linear_response
from tests.reference_isolators import G, bilinear_loop, isolated_response

# Kelly-type 1-storey isolated building: m_b = m_1 = 1e5 kg, fixed-base period 0.3 s, 2 %
# stiffness-proportional damping, isolation period T_d = 2.5 s (bilinear) or T = 3 s (FPS)
MB = M1 = 1e5
M_TOT = MB + M1
W = G * M_TOT
K2 = M_TOT * (2 * np.pi / 2.5) ** 2
R_FPS = G * (3.0 / (2 * np.pi)) ** 2


def shear(masses, k, xi=0.02):
    """``Ks`` and a stiffness-proportional ``Cs`` of a shear building on its base DOF (storey j
    between floors j-1 and j, floor 0 the base mat); ``xi`` at the fixed-base first mode."""
    n = len(masses)
    Ks = np.zeros((n, n))
    for j, kj in enumerate(k, start=1):
        Ks[j - 1, j - 1] += kj
        Ks[j, j] += kj
        Ks[j - 1, j] -= kj
        Ks[j, j - 1] -= kj
    if n == 1:
        return Ks, np.zeros((1, 1))
    m = np.asarray(masses[1:], dtype=float)
    w1 = np.sqrt(np.min(np.linalg.eigvals(Ks[1:, 1:] / m[:, None]).real))
    return Ks, 2 * xi / w1 * Ks


def one_storey():
    return shear([MB, M1], [M1 * (2 * np.pi / 0.3) ** 2])


def rel(a, b):
    return np.abs(a - b).max() / np.abs(b).max()


@pytest.fixture(scope="module")
def ground(elcentro):
    """El Centro NS, first 10 s."""
    ag, dt = elcentro
    return ag[:1001], dt


def balance(r):
    """Largest |input + initial - kinetic - strain - viscous - dissipated| over the samples,
    relative to the largest input energy (or the initial energy, in a free vibration)."""
    e = r["energy"]
    res = e["input"] + e["initial"] - e["kinetic"] - e["strain"] - e["viscous"] - e["dissipated"]
    return np.abs(res).max() / max(np.abs(e["input"]).max(), e["initial"])


# 1. friction pendulum free decay ---------------------------------------------------------


@pytest.mark.parametrize("mb", [1e5, 2.5e3])
def test_fps_free_decay_closed_form(mb):
    """Base mass alone (N = 0), R = 2 m, mu = 0.05, released at 0.5 m: half-cycles about ±mu R
    with half-period π√(R/g), extremes 0.5, -0.3, 0.1, then stuck at 0.1 = mu R, where the
    spring force is exactly the friction limit (it sticks: see the module docstring)."""
    R, mu = 2.0, 0.05
    half = np.pi * np.sqrt(R / G)
    r = isolated_response(
        [mb],
        [[0.0]],
        [[0.0]],
        {"kind": "friction_pendulum", "R": R, "mu": mu},
        np.zeros(601),
        0.01,
        u0=[0.5],
    )
    assert [e[1] for e in r["events"]] == ["slip", "reverse", "stick"]
    times = np.array([e[0] for e in r["events"]])
    assert np.abs(times - [0.0, half, 2 * half]).max() < 1e-8 * half
    assert np.abs(r["event_u0"] - [0.5, -0.3, 0.1]).max() < 1e-8
    after = r["t"] > 2 * half
    assert np.all(r["phase"][after] == "stuck")
    assert np.all(r["u"][after, 0] == r["event_u0"][-1])
    assert np.all(r["v"][after, 0] == 0.0)
    assert abs(r["residual_isolator"] - 0.1) < 1e-8
    assert r["peak_isolator"] == 0.5
    # stuck at the limit: the friction force holds exactly the pendulum's restoring force
    assert abs(r["F"][-1] + mu * r["W"]) < 1e-8 * r["W"]
    assert abs(r["peak_force_ratio"] - (0.5 / R - mu)) < 1e-12  # moving back from 0.5
    # the energy lost is mu W times the path length 0.8 + 0.4
    assert abs(r["energy"]["dissipated"][-1] - mu * r["W"] * 1.2) < 1e-8 * r["W"]


def test_fps_free_decay_period_independent_of_mass():
    """Two base masses, the same event times and extremes (to rounding)."""
    runs = [
        isolated_response(
            [mb],
            [[0.0]],
            [[0.0]],
            {"kind": "friction_pendulum", "R": 2.0, "mu": 0.05},
            np.zeros(401),
            0.01,
            u0=[0.5],
        )
        for mb in (1e5, 2.5e3)
    ]
    t0, t1 = (np.array([e[0] for e in r["events"]]) for r in runs)
    assert np.abs(t0 - t1).max() < 1e-12
    assert np.abs(runs[0]["u"] - runs[1]["u"]).max() < 1e-12


def test_fps_static_friction_holds_the_slider_earlier():
    """mu_s = 0.2 > mu = 0.05: released at 0.5 m (spring 0.25 W > 0.2 W) it slips, reaches -0.3 m
    after half a period (spring 0.15 W < 0.2 W) and sticks there."""
    R = 2.0
    r = isolated_response(
        [1e4],
        [[0.0]],
        [[0.0]],
        {"kind": "friction_pendulum", "R": R, "mu": 0.05, "mu_s": 0.2},
        np.zeros(301),
        0.01,
        u0=[0.5],
    )
    assert [e[1] for e in r["events"]] == ["slip", "stick"]
    assert abs(r["events"][1][0] - np.pi * np.sqrt(R / G)) < 1e-10
    assert abs(r["residual_isolator"] + 0.3) < 1e-10


def test_chattering_guard_raises_clearly():
    with pytest.raises(RuntimeError, match="chattering"):
        isolated_response(
            [1e4],
            [[0.0]],
            [[0.0]],
            {"kind": "friction_pendulum", "R": 2.0, "mu": 0.05},
            np.zeros(301),
            0.01,
            u0=[0.5],
            max_events=1,
        )


def test_bilinear_release_closed_form():
    """Base mass alone released at rest from D = 8 D_y (beyond yield, the element at its
    strength): elastic unloading on k1 about u_e = (k1 - k2) p / k1 until q = -Q at
    u = D - 2 D_y ("yield"), then a plastic arc on k2 about Q/k2 to the velocity zero
    ("unload"), both in closed form (to 1e-10)."""
    m, Q, Dy = M_TOT, 0.06 * W, 0.025
    kh = Q / Dy
    k1, D = K2 + kh, 8 * Dy
    r = isolated_response(
        [m],
        [[0.0]],
        [[0.0]],
        {"kind": "bilinear", "k1": k1, "k2": K2, "Q": Q},
        np.zeros(301),
        0.01,
        u0=[D],
    )
    w1, w2 = np.sqrt(k1 / m), np.sqrt(K2 / m)
    ue = kh * (D - Dy) / k1
    uy = D - 2 * Dy
    ty = np.arccos((uy - ue) / (D - ue)) / w1
    vy = -w1 * np.sqrt((D - ue) ** 2 - (uy - ue) ** 2)
    c = Q / K2  # centre of the plastic arc (q = -Q)
    amp = np.hypot(uy - c, vy / w2)
    theta0 = np.arctan2(-vy / w2, uy - c)
    t_ext, u_ext = ty + (np.pi - theta0) / w2, c - amp
    assert [e[1] for e in r["events"][:2]] == ["yield", "unload"]
    assert abs(r["events"][0][0] - ty) < 1e-10 * ty
    assert abs(r["event_u0"][0] - uy) < 1e-10 * D
    assert abs(r["events"][1][0] - t_ext) < 1e-10 * t_ext
    assert abs(r["event_u0"][1] - u_ext) < 1e-10 * D
    assert r["peak_isolator"] == D
    assert balance(r) < 1e-10


def test_bilinear_release_loaded_outwards_yields_at_once():
    """Released at rest beyond yield under a constant ground acceleration that pushes the base
    further out: it yields at t = 0 and swings on k2 (q = +Q) about
    u_c = (-m a_g - Q)/k2 to 2 u_c - D, half a period π/ω2 later, where it unloads."""
    m, Q, Dy = M_TOT, 0.06 * W, 0.025
    k1, D, ag = K2 + Q / Dy, 4 * Dy, -0.5 * G
    r = isolated_response(
        [m],
        [[0.0]],
        [[0.0]],
        {"kind": "bilinear", "k1": k1, "k2": K2, "Q": Q},
        np.full(301, ag),
        0.01,
        u0=[D],
    )
    uc = (-m * ag - Q) / K2
    assert uc > D
    assert r["events"][0] == (0.0, "yield")
    assert r["events"][1][1] == "unload"
    assert abs(r["events"][1][0] - np.pi * np.sqrt(m / K2)) < 1e-10
    assert abs(r["event_u0"][1] - (2 * uc - D)) < 1e-10 * D


# 2.-3. limiting cases on a real record -----------------------------------------------------


def test_fps_without_friction_is_the_linear_isolator(ground):
    """mu = 0: the pendulum is the linear isolator k = W/R (with a reversal event at every
    velocity zero of the base), to 1e-9 relative."""
    ag, dt = ground
    Ks, Cs = one_storey()
    lin = isolated_response([MB, M1], Ks, Cs, {"kind": "linear", "k": W / R_FPS}, ag, dt)
    fps = isolated_response(
        [MB, M1], Ks, Cs, {"kind": "friction_pendulum", "R": R_FPS, "mu": 0.0}, ag, dt
    )
    assert sum(e[1] == "reverse" for e in fps["events"]) >= 5
    assert not any(e[1] == "stick" for e in fps["events"])
    for key in ("u", "v", "a_abs", "f_iso"):
        assert rel(fps[key], lin[key]) < 1e-9, key
    assert abs(fps["peak_isolator"] / lin["peak_isolator"] - 1) < 1e-9
    assert abs(fps["peak_force_ratio"] / lin["peak_force_ratio"] - 1) < 1e-9


def test_bilinear_limits_are_linear(ground):
    """Q → 0: the linear isolator k2, with an error proportional to Q (the force differs by at
    most Q); Q never reached: the linear isolator k1 exactly (no event)."""
    ag, dt = ground
    Ks, Cs = one_storey()
    k1 = 10 * K2
    lin2 = isolated_response([MB, M1], Ks, Cs, {"kind": "linear", "k": K2}, ag, dt)
    errs = []
    for qw in (1e-10, 1e-12):
        iso = {"kind": "bilinear", "k1": k1, "k2": K2, "Q": qw * W}
        b = isolated_response([MB, M1], Ks, Cs, iso, ag, dt)
        assert {e[1] for e in b["events"]} == {"yield", "unload"}
        errs.append(max(rel(b[key], lin2[key]) for key in ("u", "v", "a_abs", "f_iso")))
    assert errs[1] < 1e-9
    assert 50 < errs[0] / errs[1] < 200  # linear in Q: the model, not noise
    lin1 = isolated_response([MB, M1], Ks, Cs, {"kind": "linear", "k": k1}, ag, dt)
    iso = {"kind": "bilinear", "k1": k1, "k2": K2, "Q": 1e3 * W}
    b = isolated_response([MB, M1], Ks, Cs, iso, ag, dt)
    assert b["events"] == []
    for key in ("u", "v", "a_abs", "f_iso"):
        assert rel(b[key], lin1[key]) < 1e-10, key


# 4. the bilinear loop ----------------------------------------------------------------------


@pytest.mark.parametrize("ratio", [3.0, 10.0])
def test_bilinear_loop_energy(ratio):
    """∮ f du over D → -D → D = 4 Q (D - D_y) (Kelly 1996), and the force path."""
    k2, Q, Dy = 1.2e6, 1.1e5, 0.025
    k1 = k2 + Q / Dy
    D = ratio * Dy
    loop = bilinear_loop(D, k1, k2, Q)
    assert abs(loop["energy"] / (4 * Q * (D - Dy)) - 1) < 1e-6
    assert np.abs(loop["q"]).max() <= Q
    assert abs(loop["f"].max() - (k2 * D + Q)) < 1e-9 * Q
    assert abs(loop["f"].min() + (k2 * D + Q)) < 1e-9 * Q


# 5. the linear kind against the independent state-space integration ------------------------


@pytest.mark.parametrize("rtol,tol_acc", [(1e-12, 1e-9), (1e-13, 1e-10)])
def test_linear_isolator_matches_state_space(ground, rtol, tol_acc):
    """Three storeys on a linear, viscous isolator vs ``tests.reference.linear_response`` on
    the assembled ``x' = A x + b a_g`` (x = [u, v], its rtol 1e-13): u, v, f_iso to 1e-10
    relative. The absolute accelerations (vs ``A x + b a_g`` plus the ground) are a small
    difference of large storey forces: 1.2e-10 measured at the default rtol 1e-12 (bound 1e-9),
    1e-11 at rtol 1e-13 (bound 1e-10)."""
    ag, dt = ground
    masses = [1.2e5, 1e5, 1e5, 0.8e5]
    Ks, Cs = shear(masses, [2.4e8, 2.0e8, 1.5e8], xi=0.03)
    k_i = sum(masses) * (2 * np.pi / 2.2) ** 2
    c_i = 2 * 0.1 * np.sqrt(k_i * sum(masses))
    iso = {"kind": "linear", "k": k_i, "c": c_i}
    r = isolated_response(masses, Ks, Cs, iso, ag, dt, rtol=rtol)
    n = len(masses)
    K, C = Ks.copy(), Cs.copy()
    K[0, 0] += k_i
    C[0, 0] += c_i
    Minv = np.diag(1.0 / np.asarray(masses))
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
    b = np.r_[np.zeros(n), -np.ones(n)]
    X = linear_response(A, b, ag, dt)
    assert rel(r["u"], X[:, :n]) < 1e-10
    assert rel(r["v"], X[:, n:]) < 1e-10
    a_abs = (X @ A.T + np.outer(ag, b))[:, n:] + ag[:, None]
    assert rel(r["a_abs"], a_abs) < tol_acc
    assert rel(r["f_iso"], k_i * X[:, 0] + c_i * X[:, n]) < 1e-10
    assert r["peak_isolator"] >= np.abs(X[:, 0]).max()
    assert r["peak_isolator"] < np.abs(X[:, 0]).max() * 1.01
    assert balance(r) < 1e-9


# 6. energy balance on El Centro: the event handling ---------------------------------------


@pytest.mark.parametrize(
    "iso",
    [
        {"kind": "bilinear", "k1": K2 + 0.06 * W / 0.025, "k2": K2, "Q": 0.06 * W},
        {"kind": "bilinear", "k1": K2 + 0.06 * W / 0.01, "k2": K2, "Q": 0.06 * W},
        {"kind": "friction_pendulum", "R": R_FPS, "mu": 0.06},
    ],
    ids=["bilinear-Dy25mm", "bilinear-Dy10mm", "fps"],
)
def test_energy_balance_closes(ground, iso):
    """Input = kinetic + strain + viscous + dissipated at every sample, 1e-6 of the input. The
    hysteretic / friction loss is branch bookkeeping (Q or mu W times the plastic / sliding
    path), not a quadrature, so a branch change at the wrong place (an early yield, a wrong
    plastic offset, a slider stopped while moving) breaks it."""
    ag, dt = ground
    Ks, Cs = one_storey()
    r = isolated_response([MB, M1], Ks, Cs, iso, ag, dt)
    kinds = {e[1] for e in r["events"]}
    if iso["kind"] == "bilinear":
        assert kinds == {"yield", "unload"}
        stored = r["q"] ** 2 / (2 * (iso["k1"] - iso["k2"]))
        assert np.abs(r["q"]).max() <= iso["Q"] * (1 + 1e-12)
    else:
        assert {"slip", "stick"} <= kinds
        stored = 0.0
        assert np.abs(r["F"]).max() <= iso["mu"] * r["W"] * (1 + 2e-9)
    assert balance(r) < 1e-6
    e = r["energy"]
    work_err = np.abs(e["isolator_work"] - stored - e["dissipated"]).max()
    assert work_err < 1e-6 * e["input"].max()
    assert e["dissipated"][-1] > 0.3 * e["input"][-1]
    assert r["peak_isolator"] >= np.abs(r["u"][:, 0]).max()
    assert r["residual_isolator"] == r["u"][-1, 0]
