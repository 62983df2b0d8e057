"""Exact floor motions against closed forms and an independent fine-step integration."""

from __future__ import annotations

import itertools

import control
import numpy as np
import pytest

from floorslide.building._instep import poly_val
from floorslide.building.exact import ExactStepper, foh_matrices
from floorslide.building.model import IsolatedBuilding, ShearBuilding
from floorslide.building.motions import floor_motions, peak_floor_acceleration
from floorslide.errors import ModelError
from tests.reference import linear_response


def buildings():
    fb = ShearBuilding.from_period(stories=3, period=0.4, damping=0.05)
    return {"fixed": fb, "isolated": IsolatedBuilding(fb, 1.0, 2.5, 0.10)}


def rel_err(a, b):
    return np.abs(a - b).max() / np.abs(b).max()


@pytest.mark.parametrize("kind", ["fixed", "isolated"])
def test_exact_floor_motions_match_independent_integration(kind, elcentro):
    """Exact FOH samples vs DOP853 step by step (rtol 1e-13): 1e-9 relative, RMS and peak."""
    ag, dt = elcentro
    ag = ag[:1500]
    b = buildings()[kind]
    A, B = b.state_matrices()
    C, D, _ = b.output_matrices(None, ["acceleration", "displacement", "drift"][:1])
    X = linear_response(A, B[:, 0], ag, dt)
    ref = C @ X.T + D @ ag[None, :]
    got = floor_motions(b, ag, dt)
    assert rel_err(got, ref) < 1e-9
    rms = np.sqrt(np.mean((got - ref) ** 2)) / np.sqrt(np.mean(ref**2))
    assert rms < 1e-9
    np.testing.assert_allclose(np.abs(got).max(axis=1), np.abs(ref).max(axis=1), rtol=1e-9)


def test_sdof_ramp_closed_form_at_coarse_dt():
    """1 storey under a_g = s·t: u = −s(t/ω² − 2ξ/ω³) + homogeneous part; exact at any dt."""
    T, xi, s = 0.3, 0.05, 2.0
    b = ShearBuilding.from_period(1, T, xi)
    w = 2 * np.pi / T
    wd = w * np.sqrt(1 - xi**2)
    dt = 0.07  # coarse on purpose
    t = np.arange(40) * dt
    u = floor_motions(b, s * t, dt, floors=[1], output="displacement")[0]
    # particular + homogeneous with u(0) = u'(0) = 0
    up0, vp0 = s * 2 * xi / w**3, -s / w**2
    c1 = -up0
    c2 = (-vp0 + xi * w * c1) / wd
    exact = -s * (t / w**2 - 2 * xi / w**3) + np.exp(-xi * w * t) * (
        c1 * np.cos(wd * t) + c2 * np.sin(wd * t)
    )
    np.testing.assert_allclose(u, exact, rtol=0, atol=1e-13 * np.abs(exact).max())


def test_sdof_harmonic_steady_state_amplitude_and_phase():
    """Linear oscillator under a0·sin ωt (docs/design.md §7): steady relative displacement amplitude
    (a0/ω_n²)/√((1−r²)² + (2ξr)²) and phase atan2(2ξr, 1−r²). dt = T/4000: the piecewise-linear
    record differs from the sine by (ωdt)²/8 ≈ 3e-7 relative, hence rtol 2e-6."""
    Tn, xi, a0 = 0.5, 0.05, 1.5
    wn = 2 * np.pi / Tn
    for r in (0.5, 1.0, 1.7):
        w = r * wn
        T = 2 * np.pi / w
        dt = T / 4000
        t = np.arange(int(max(60 * T, 25 / (xi * wn)) / dt) + 1) * dt
        b = ShearBuilding.from_period(1, Tn, xi)
        u = floor_motions(b, a0 * np.sin(w * t), dt, floors=[1], output="displacement")[0]
        last = t > t[-1] - T
        # u = −U sin(ωt − θ) with U, θ below: fit sin/cos components on the last cycle
        M = np.column_stack([np.sin(w * t[last]), np.cos(w * t[last])])
        cs, cc = np.linalg.lstsq(M, u[last], rcond=None)[0]
        U = (a0 / wn**2) / np.sqrt((1 - r**2) ** 2 + (2 * xi * r) ** 2)
        theta = np.arctan2(2 * xi * r, 1 - r**2)
        assert np.hypot(cs, cc) == pytest.approx(U, rel=2e-6)
        assert np.arctan2(cc, -cs) == pytest.approx(theta, abs=2e-6)


@pytest.mark.parametrize("kind", ["fixed", "isolated"])
def test_harmonic_steady_state_equals_python_control_frequency_response(kind):
    """dt = T/1000: the piecewise-linear sine's fundamental is sinc²(ωdt/2) ≈ 1 − 3.3e-6 of the
    sine's, hence rtol 1e-5; the record lasts until transients decayed below 1e-9."""
    b = buildings()[kind]
    ss = b.state_space()
    decay = -np.max(control.poles(ss).real)
    for f in (0.3, 1.7, 4.0):
        w = 2 * np.pi * f
        dt = 1 / f / 1000
        t_end = max(21 / decay, 3 / f)
        t = np.arange(int(t_end / dt) + 1) * dt
        Y = floor_motions(b, np.sin(w * t), dt)
        fr = control.frequency_response(ss, [w])
        mag = np.abs(np.asarray(fr.complex).reshape(-1))
        last = t > t[-1] - 1 / f
        amp = 0.5 * (Y[:, last].max(axis=1) - Y[:, last].min(axis=1))
        np.testing.assert_allclose(amp, mag, rtol=1e-5)


def test_taylor_form_equals_state_at_inside_a_step(elcentro):
    """The compiled in-step representation equals Φ(τ)x_k + Γ₀(τ)a_k + Γ₁(τ)s_k."""
    b = buildings()["isolated"]
    A, B = b.state_matrices()
    st = ExactStepper.build(A, B[:, 0], 0.02)
    C, D, _ = b.output_matrices(None)
    R, beta = st.taylor_rows(C, D[:, 0])
    rng = np.random.default_rng(1)
    from floorslide.building._instep import taylor_coefficients

    for _ in range(20):
        x = rng.normal(size=st.n) * [1e-2] * st.n
        a0, slope = rng.normal(), rng.normal() * 50
        tau = rng.uniform(0, st.h)
        y_ref = C @ st.state_at(x, a0, slope, tau) + D[:, 0] * (a0 + slope * tau)
        c = np.empty(st.order + 1)
        for i in range(C.shape[0]):
            taylor_coefficients(R[i], beta[i], x, a0, slope, c)
            assert poly_val(c, st.order, tau) == pytest.approx(y_ref[i], rel=1e-12, abs=1e-14)


def test_foh_matrices_match_scipy_cont2discrete():
    from scipy.signal import cont2discrete

    b = buildings()["fixed"]
    A, B = b.state_matrices()
    dt = 0.013
    phi, g0, _g1 = foh_matrices(A, B[:, 0], dt)
    Ad, Bd, _Cd, Dd, _ = cont2discrete(
        (A, B, np.eye(A.shape[0]), np.zeros((A.shape[0], 1))), dt, "foh"
    )
    np.testing.assert_allclose(phi, Ad, rtol=1e-12, atol=1e-14)
    # SciPy's FOH form uses a shifted state; its input-to-output map at the next sample is
    # Φ(Γ₁/dt) + (Γ₀ − Γ₁/dt) + ... — compare the total DC gain instead
    np.testing.assert_allclose(
        np.linalg.solve(np.eye(A.shape[0]) - phi, g0),
        np.linalg.solve(np.eye(A.shape[0]) - Ad, Bd[:, 0]) + Dd[:, 0],
        rtol=1e-9,
        atol=1e-15,
    )


def test_true_pfa_includes_peaks_inside_steps(coarse_record):
    """At dt = 0.02 s the floor peak falls between samples; the true peak equals the maximum of
    the exact in-step response on a dense grid (reference: state_at with its own expm)."""
    ag, dt = coarse_record
    b = ShearBuilding.from_period(2, 0.15, 0.02)
    pk = peak_floor_acceleration(b, ag, dt, floors=[2, 1])
    sampled = np.abs(floor_motions(b, ag, dt, floors=[2, 1])).max(axis=1)
    assert np.all(pk.peak > sampled * (1 + 1e-4))
    A, B = b.state_matrices()
    st = ExactStepper.build(A, B[:, 0], dt, substeps=1)
    C, _, _ = b.output_matrices([2, 1])
    X = linear_response(A, B[:, 0], ag, dt)
    for i in range(2):
        k = int(pk.time[i] // dt)
        taus = np.linspace(0, dt, 4001)
        vals = [abs(C[i] @ st.state_at(X[k], ag[k], (ag[k + 1] - ag[k]) / dt, tau)) for tau in taus]
        assert pk.peak[i] >= max(vals) * (1 - 1e-12)
        assert pk.peak[i] == pytest.approx(max(vals), rel=1e-7)  # dense grid resolves 1e-7


def test_oversampled_motion_is_the_same_exact_response(elcentro):
    ag, dt = elcentro
    ag = ag[:800]
    b = buildings()["isolated"]
    y1 = floor_motions(b, ag, dt)
    y4 = floor_motions(b, ag, dt, oversample=4)
    assert y4.shape[1] == (ag.size - 1) * 4 + 1
    # same response through two recurrences: rounding differs (~1e-12 after 800 steps)
    np.testing.assert_allclose(y4[:, ::4], y1, rtol=0, atol=1e-10 * np.abs(y1).max())


def test_outputs_and_floor_selection(elcentro):
    ag, dt = elcentro
    ag = ag[:600]
    b = buildings()["isolated"]
    full = floor_motions(
        b, ag, dt, output=["acceleration", "displacement", "drift", "isolator"], floors=[1, 2, 3]
    )
    assert set(full) == {"acceleration", "displacement", "drift", "isolator"}
    np.testing.assert_allclose(
        full["drift"][0], full["displacement"][0] - full["isolator"][0], atol=1e-15
    )
    np.testing.assert_allclose(
        full["drift"][2], full["displacement"][2] - full["displacement"][1], atol=1e-15
    )
    rep = floor_motions(b, ag, dt, floors=[3, 1, 3])
    np.testing.assert_array_equal(rep[0], rep[2])
    np.testing.assert_array_equal(rep[1], full["acceleration"][0])
    fb = buildings()["fixed"]
    np.testing.assert_array_equal(floor_motions(fb, ag, dt, floors=[0])[0], ag)
    with pytest.raises(ModelError, match="floor 7 does not exist"):
        floor_motions(b, ag, dt, floors=[1, 7])


@pytest.mark.parametrize("method", ["zoh", "newmark", "forced_response"])
def test_approximate_methods_are_approximate_and_converge(method, elcentro):
    ag, dt = elcentro
    ag = ag[:2000]
    b = buildings()["fixed"]
    exact = floor_motions(b, ag, dt)
    if method == "forced_response":  # python-control interpolates linearly too: same samples
        assert rel_err(floor_motions(b, ag, dt, method=method), exact) < 1e-11
        return
    if method == "zoh":
        errs = [rel_err(floor_motions(b, ag[::1], dt, method="zoh"), exact)]
        assert errs[0] > 1e-3
        return
    errs = [
        rel_err(floor_motions(b, ag, dt, method="newmark", substeps=k), exact) for k in (1, 2, 4, 8)
    ]
    assert errs[0] > 1e-3
    assert all(e2 < e1 / 3 for e1, e2 in itertools.pairwise(errs))  # second order


@pytest.mark.parametrize(
    "bad",
    [
        dict(ground_acc=[], dt=0.01),
        dict(ground_acc=[0.0, np.nan], dt=0.01),
        dict(ground_acc=[0.0, np.inf], dt=0.01),
        dict(ground_acc=[0.0, 1.0], dt=0.0),
        dict(ground_acc=[0.0, 1.0], dt=-0.01),
        dict(ground_acc=[0.0, 1.0], dt=0.01, method="rk4"),
        dict(ground_acc=[0.0, 1.0], dt=0.01, oversample=0),
    ],
)
def test_bad_records_give_clear_errors(bad):
    with pytest.raises(ModelError):
        floor_motions(buildings()["fixed"], **bad)
