"""Approximate solvers of a heavy block coupled with its floor, beside the exact
:func:`floorslide.slide_coupled` (for ``floorslide bench``; docs/design.md §6, §10f).

The model is the exact solver's: a rigid block of mass ``m`` on degree of freedom ``j`` of a
linear building (``M``, ``C``, ``K``; displacements ``u`` relative to the ground), its slide
``s`` relative to the floor, friction ``F`` on the block and ``−F`` on the floor::

    M u'' + C u' + K u = −M ι a_g − e_j F,     m (a_f + s'') = F,     a_f = u_j'' + a_g,

with Coulomb friction ``|F| ≤ mu_s m g`` while stuck and ``F = −σ mu_k m g`` while sliding
(``σ`` the sign of ``s'``). Two approximations of it:

:func:`slide_coupled_smoothed`
    The regularised friction law ``F = −mu_k m g tanh(s'/eps)`` (no sticking: a block the exact
    solver holds creeps at speed ``eps·artanh(|a_f|/(mu_k g))``; ``mu_s > mu_k`` has no
    counterpart), building and block as one ODE integrated over the whole record by SciPy's
    :func:`~scipy.integrate.solve_ivp` (``LSODA`` by default, with the analytic Jacobian; the
    friction's transition is stiff, its rate ``mu_k g (1 + m/M_j)/eps``). The ground is the
    exact solver's: the samples joined by straight lines. Extrema of ``s`` are located as events
    (``s' = 0``); the floor's PFA is read from the dense output at ``dt/8`` and at the solver's
    steps. The error is the regularisation's: it shrinks as ``eps → 0`` (and ``rtol → 0``).

:func:`slide_coupled_newmark`
    Newmark's average-acceleration method (γ = 1/2, β = 1/4; Chopra 2012 §5.4) on sub-steps
    ``h = dt/k``, the building with the block's mass added to floor ``j`` while it sticks and
    under the constant reaction ``σ mu_k m g`` while it slides, each phase a linear system; the
    floor's acceleration is re-evaluated by equilibrium at each sub-step's start (it jumps at a
    breakaway). Stick/slip is checked at sub-step ends only: a stuck block breaks away at the
    end of the first sub-step where the stuck system needs more friction than ``mu_s m g``
    (toward ``σ = −sign(a_f)``), a sliding block stops where its velocity changes sign (the stop
    placed inside the sub-step by linear interpolation of ``s'``; the building is not
    re-integrated). Switches are thus late by up to one sub-step: first order in ``h``. The
    ground is the record joined by straight lines, sampled at ``h``; peaks (slide, floor
    acceleration) are read at sub-step ends and at stops.

References
----------
Newmark, N. M. (1959). A method of computation for structural dynamics. *J. Eng. Mech. Div.*
ASCE 85(EM3), 67–94.
Chopra, A. K. (2012). *Dynamics of Structures*, 4th ed., §5.4 (average acceleration).
Karnopp, D. (1985). Computer simulation of stick-slip friction in mechanical dynamic systems.
*J. Dyn. Syst. Meas. Control* 107(1), 100–103 (why smoothed friction creeps where Coulomb sticks).
Petzold, L. (1983). Automatic selection of methods for solving stiff and nonstiff systems of
ordinary differential equations. *SIAM J. Sci. Stat. Comput.* 4(1), 136–148 (LSODA).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from floorslide._jit import njit
from floorslide.building.nonlinear_approx import _ground
from floorslide.constants import G
from floorslide.contents.coupled import _check_building, _check_floor, _masses
from floorslide.contents.sliding import friction_pairs
from floorslide.errors import ModelError, SolverLimitError
from floorslide.inputs import as_record

__all__ = ["CoupledApproxResult", "slide_coupled_newmark", "slide_coupled_smoothed"]

INTEGRATORS = ("LSODA", "Radau", "BDF")
"""SciPy's implicit integrators accepted by :func:`slide_coupled_smoothed`."""

ATOL = 0.1
"""``atol = ATOL·rtol`` on every state (m, m/s) of :func:`slide_coupled_smoothed`."""

PFA_OVERSAMPLE = 8
"""The smoothed model's floor acceleration is read from the dense output at ``dt/8``."""


@dataclass(frozen=True)
class CoupledApproxResult:
    """An approximate coupled slide, one entry per case (mu_k, mass): the fields of
    :class:`~floorslide.contents.coupled.CoupledSlideResult` an approximation can give.

    Attributes
    ----------
    method
        ``"smoothed"`` or ``"newmark"``.
    mu_k, mass
        Kinetic friction coefficient and mass of the block (kg).
    peak_slide, residual_slide
        ``max |s|`` and ``s`` at the end, m.
    pfa
        Peak absolute acceleration of the block's floor, m/s².
    notes
        What was done (settings, solver statistics), one line each.
    """

    method: str
    mu_k: np.ndarray
    mass: np.ndarray
    peak_slide: np.ndarray
    residual_slide: np.ndarray
    pfa: np.ndarray
    notes: tuple[str, ...] = ()


def _inputs(acc, dt, mu_k, mu_s, mass, building, floor):
    building = _check_building(building, nonlinear=False)
    dof = _check_floor(building, floor)
    if mu_k is None:
        raise ModelError("mu_k (the kinetic friction coefficient) is required", "mu_k")
    mk, ms = friction_pairs(mu_k, mu_s)
    if np.any(ms < mk):
        raise ModelError("mu_s must be ≥ mu_k (as slide_coupled)", "mu_s")
    masses = _masses(mass, float(building.mass[dof]), int(building.dof_floors[dof]))
    try:
        mk, ms, masses = (np.ascontiguousarray(v) for v in np.broadcast_arrays(mk, ms, masses))
    except ValueError:
        raise ModelError(
            f"mass ({masses.size} values) must be one value or one per mu_k ({mk.size})", "mass"
        ) from None
    a, dt, notes = as_record(acc, dt, "acc")
    return building, dof, mk, ms, masses, a, dt, list(notes)


# -- smoothed friction through solve_ivp ---------------------------------------------------------


@njit(cache=True)
def _smooth_rhs(t, y, minv, K, C, j, mass, fk, eps, acc, dt):
    n = minv.size
    ag = _ground(t, acc, dt)
    out = np.empty(y.size)
    F = -fk * mass * math.tanh(y[2 * n + 1] / eps)
    for i in range(n):
        out[i] = y[n + i]
        s = 0.0
        for c in range(n):
            s += K[i, c] * y[c] + C[i, c] * y[n + c]
        if i == j:
            s += F
        out[n + i] = -s * minv[i] - ag
    out[2 * n] = y[2 * n + 1]
    out[2 * n + 1] = F / mass - (out[n + j] + ag)
    return out


@njit(cache=True)
def _smooth_jac(t, y, minv, K, C, j, mass, fk, eps, acc, dt):
    n = minv.size
    J = np.zeros((y.size, y.size))
    th = math.tanh(y[2 * n + 1] / eps)
    dF = -fk * mass * (1.0 - th * th) / eps
    for i in range(n):
        J[i, n + i] = 1.0
        for c in range(n):
            J[n + i, c] = -K[i, c] * minv[i]
            J[n + i, n + c] = -C[i, c] * minv[i]
    J[n + j, 2 * n + 1] = -dF * minv[j]
    J[2 * n, 2 * n + 1] = 1.0
    for c in range(2 * n + 2):
        J[2 * n + 1, c] = -J[n + j, c]
    J[2 * n + 1, 2 * n + 1] += dF / mass
    return J


def slide_coupled_smoothed(
    acc,
    dt: float | None = None,
    mu_k=None,
    *,
    mass=None,
    building=None,
    floor: int | None = None,
    eps: float = 1e-3,
    rtol: float = 1e-8,
    integrator: str = "LSODA",
) -> CoupledApproxResult:
    """The coupled block with smoothed friction ``F = −mu_k m g tanh(s'/eps)`` (on the block;
    ``−F`` on the floor), building and block integrated as one ODE by SciPy's ``solve_ivp``.

    Parameters
    ----------
    acc, dt
        Ground acceleration (m/s², the samples joined by straight lines) and its step (s), or a
        Trace.
    mu_k
        Kinetic friction coefficient(s) ≥ 0.
    mass, building, floor
        As :func:`floorslide.slide_coupled`.
    eps
        Velocity scale of the friction's transition, m/s (> 0); the exact model is its limit
        ``eps → 0``.
    rtol
        Relative tolerance of ``solve_ivp`` (``atol = 0.1·rtol`` on every state, m and m/s).
    integrator
        ``"LSODA"``, ``"Radau"`` or ``"BDF"`` (implicit: the friction is stiff).

    Returns
    -------
    CoupledApproxResult

    Raises
    ------
    ModelError
        Invalid input (as :func:`floorslide.slide_coupled`) or setting, one line naming it.
    SolverLimitError
        ``solve_ivp`` failed.

    Notes
    -----
    A block that the exact model holds creeps here at the speed where ``tanh`` balances the
    friction it needs; its slide therefore drifts by about ``eps·artanh(|a_f|/(mu_k g))`` per
    second of sticking, and ``mu_s`` has no counterpart (the coefficient used is ``mu_k``).
    Measured on the bench's case (``slide-coupled``: PET-090, block of 10 % of the roof's mass
    on a 3-storey building, T = 0.5 s, two frictions): peak-slide error 1.8 %, 0.25 %, 0.04 %
    and roof-PFA error 0.13 %, 0.025 %, 0.001 % at ``eps`` = 1e-2, 1e-3, 1e-4 m/s
    (``rtol = eps/100``): 6–7× per decade of ``eps``.

    References
    ----------
    Karnopp, D. (1985). Computer simulation of stick-slip friction in mechanical dynamic
    systems. *J. Dyn. Syst. Meas. Control* 107(1), 100–103.
    Petzold, L. (1983). *SIAM J. Sci. Stat. Comput.* 4(1), 136–148 (LSODA).
    """
    from scipy.integrate import solve_ivp  # SciPy's integrators: only when asked for

    e, r = float(eps), float(rtol)
    if not (math.isfinite(e) and e > 0):
        raise ModelError(f"eps must be > 0 m/s, got {eps!r}", "eps")
    if not (math.isfinite(r) and 0 < r < 1):
        raise ModelError(f"rtol must be in (0, 1), got {rtol!r}", "rtol")
    if integrator not in INTEGRATORS:
        raise ModelError(
            f"integrator must be one of {', '.join(INTEGRATORS)}, got {integrator!r}",
            "integrator",
        )
    building, j, mk, _ms, masses, a, dt, notes = _inputs(acc, dt, mu_k, None, mass, building, floor)
    n = building.n_dof
    K = np.ascontiguousarray(building.stiffness_matrix, dtype=float)
    C = np.ascontiguousarray(building.damping_matrix, dtype=float)
    minv = 1.0 / np.asarray(building.mass, dtype=float)
    t_end = (a.size - 1) * dt
    grid = np.linspace(0.0, t_end, (a.size - 1) * PFA_OVERSAMPLE + 1)
    peak, residual, pfa = (np.zeros(mk.size) for _ in range(3))
    steps = 0
    for i in range(mk.size):
        args = (minv, K, C, j, float(masses[i]), float(mk[i]) * G, e, a, dt)

        def event(t, y):
            return y[2 * n + 1]

        sol = solve_ivp(
            lambda t, y, args=args: _smooth_rhs(t, y, *args),
            (0.0, t_end),
            np.zeros(2 * n + 2),
            method=integrator,
            rtol=r,
            atol=r * ATOL,
            jac=lambda t, y, args=args: _smooth_jac(t, y, *args),
            dense_output=True,
            events=event,
        )
        if not sol.success:
            raise SolverLimitError(f"solve_ivp failed: {sol.message}", "rtol")
        steps += sol.t.size
        ys = np.concatenate([sol.sol(grid), sol.y, sol.y_events[0].reshape(-1, 2 * n + 2).T], 1)
        peak[i] = np.abs(ys[2 * n]).max()
        residual[i] = sol.y[2 * n, -1]
        F = -args[5] * masses[i] * np.tanh(ys[2 * n + 1] / e)
        af = -(K[j] @ ys[:n] + C[j] @ ys[n : 2 * n] + F) * minv[j]
        pfa[i] = np.abs(af).max()
    notes.append(f"friction mu_k·m·g·tanh(s'/{e:g} m/s), solve_ivp {integrator} rtol {r:g}")
    notes.append(f"{steps} solver steps")
    return CoupledApproxResult("smoothed", mk, masses, peak, residual, pfa, tuple(notes))


# -- Newmark average acceleration with stick/slip checks ----------------------------------------


@njit(cache=True)
def _newmark_run(ag, h, M, K, C, j, mass, fs, fk, out):
    """Newmark (γ = 1/2, β = 1/4) on the sub-step samples `ag` of the ground; `out` ←
    ``(peak |s|, s at the end, peak |a_f|)``."""
    n = M.size
    Ms = np.empty((2, n))  # diagonal masses: 0 stuck (block on floor j), 1 sliding
    for i in range(n):
        Ms[0, i] = M[i]
        Ms[1, i] = M[i]
    Ms[0, j] += mass
    Kinv = np.empty((2, n, n))
    for mode in range(2):
        Keff = K + (2.0 / h) * C
        for i in range(n):
            Keff[i, i] += 4.0 / (h * h) * Ms[mode, i]
        Kinv[mode] = np.linalg.inv(Keff)
    u = np.zeros(n)
    v = np.zeros(n)
    a = np.zeros(n)
    s = 0.0
    sd = 0.0
    mode = 0
    sig = 0.0
    peak = 0.0
    pfa = abs(ag[0])
    for k in range(ag.size - 1):
        # the floor's reaction (sliding) and the acceleration at the step's start by equilibrium
        react = sig * fk * mass if mode == 1 else 0.0
        for i in range(n):
            r = -Ms[mode, i] * ag[k] - (K[i] @ u) - (C[i] @ v)
            if i == j:
                r += react
            a[i] = r / Ms[mode, i]
        af0 = a[j] + ag[k]
        pfa = max(pfa, abs(af0))
        rhs = np.empty(n)
        for i in range(n):
            p1 = -Ms[mode, i] * ag[k + 1] + (react if i == j else 0.0)
            rhs[i] = p1 + Ms[mode, i] * (4.0 / (h * h) * u[i] + 4.0 / h * v[i] + a[i])
        rhs += C @ ((2.0 / h) * u + v)
        u1 = Kinv[mode] @ rhs
        v1 = (2.0 / h) * (u1 - u) - v
        a1 = (4.0 / (h * h)) * (u1 - u) - (4.0 / h) * v - a
        af1 = a1[j] + ag[k + 1]
        pfa = max(pfa, abs(af1))
        if mode == 1:
            sdd0 = -af0 - sig * fk
            sdd1 = -af1 - sig * fk
            sd1 = sd + 0.5 * h * (sdd0 + sdd1)
            if sig * sd1 <= 0.0:  # stops inside the step: s' linear to zero
                theta = sd / (sd - sd1) if sd != sd1 else 0.0
                s += 0.5 * theta * h * sd
                sd = 0.0
                mode = 0
                sig = 0.0
            else:
                s += 0.5 * h * (sd + sd1)
                sd = sd1
        elif abs(af1) > fs:  # the stuck system needs more friction than mu_s·m·g
            mode = 1
            sig = -1.0 if af1 > 0.0 else 1.0
        peak = max(peak, abs(s))
        u, v = u1, v1
    out[0] = peak
    out[1] = s
    out[2] = pfa


def slide_coupled_newmark(
    acc,
    dt: float | None = None,
    mu_k=None,
    *,
    mass=None,
    building=None,
    floor: int | None = None,
    mu_s=None,
    substeps: int = 1,
) -> CoupledApproxResult:
    """The coupled block by Newmark's average acceleration on ``dt/substeps`` with stick/slip
    checks at the sub-step ends (first order in the sub-step).

    Parameters
    ----------
    acc, dt, mu_k, mass, building, floor, mu_s
        As :func:`floorslide.slide_coupled`.
    substeps
        Sub-steps per record step (integer ≥ 1); the ground is the record joined by straight
        lines, sampled there.

    Returns
    -------
    CoupledApproxResult

    Raises
    ------
    ModelError
        Invalid input or setting, one line naming it.

    Notes
    -----
    See the module's docstring: the phases are linear systems integrated by Newmark's
    unconditionally stable trapezoid; breakaways are placed at the end of the sub-step where
    the stuck system's friction demand first exceeds ``mu_s m g``, stops by linear
    interpolation of the block's velocity inside the sub-step.

    References
    ----------
    Newmark, N. M. (1959). *J. Eng. Mech. Div.* ASCE 85(EM3), 67–94.
    Chopra, A. K. (2012). *Dynamics of Structures*, 4th ed., §5.4.
    """
    if isinstance(substeps, bool) or not isinstance(substeps, (int, np.integer)) or substeps < 1:
        raise ModelError(f"substeps must be an integer ≥ 1, got {substeps!r}", "substeps")
    building, j, mk, ms, masses, a, dt, notes = _inputs(acc, dt, mu_k, mu_s, mass, building, floor)
    k = int(substeps)
    ag = a if k == 1 else np.interp(np.arange((a.size - 1) * k + 1) / k, np.arange(a.size), a)
    M = np.asarray(building.mass, dtype=float)
    K = np.ascontiguousarray(building.stiffness_matrix, dtype=float)
    C = np.ascontiguousarray(building.damping_matrix, dtype=float)
    out = np.zeros((mk.size, 3))
    for i in range(mk.size):
        _newmark_run(
            np.ascontiguousarray(ag), dt / k, M, K, C, j, float(masses[i]),
            float(ms[i]) * G, float(mk[i]) * G, out[i],
        )  # fmt: skip
    notes.append(f"Newmark average acceleration, dt/{k}, stick/slip at sub-step ends")
    return CoupledApproxResult(
        "newmark", mk, masses, out[:, 0].copy(), out[:, 1].copy(), out[:, 2].copy(), tuple(notes)
    )
