"""Approximate solvers for buildings on nonlinear isolation, kept for the accuracy-versus-cost
study (docs/design.md §6): what a structural-analysis program computes, against the exact
event-driven solver of :mod:`floorslide.building.nonlinear`.

- :func:`newmark_isolator_response` — what OpenSees does with an ``elastomericBearingPlasticity``
  or ``singleFPBearing`` element: Newmark's average-acceleration rule (γ = 1/2, β = 1/4;
  Newmark 1959) on ``dt/substeps`` with the record interpolated linearly, and Newton–Raphson
  iterations at each step on the isolator's force, given by return mapping of an
  elastic–perfectly-plastic element (Simo & Hughes 1998, §1.3). The friction
  pendulum is modelled as OpenSees' ``singleFPBearing`` with a ``Coulomb`` friction model does:
  friction is an elastic–perfectly-plastic element of strength ``mu·W`` and a large initial
  stiffness, so that sticking is a small elastic displacement, not a constraint.
- :func:`smooth_isolator_response` — a regularised model integrated by SciPy's
  :func:`~scipy.integrate.solve_ivp` to a tolerance: Wen's (1976) smooth hysteresis for the
  bilinear layer (in the normalised form of 3D-BASIS, Nagarajaiah, Reinhorn & Constantinou
  1991: ``A = 1``, ``β = γ = 1/2``, which gives the same ``k_1``, ``k_2`` and ``Q`` and tends
  to the bilinear loop as the exponent grows), ``mu·W·tanh(u_0'/eps)`` for the pendulum's
  friction.

Neither finds the instants where the layer yields, unloads, sticks or breaks away: Newmark
steps over them (a step that holds one has a larger local error, a finite number of them
leaves the global second order of the trapezoidal rule), the smooth model replaces them by a
fast transition it must resolve with small steps. Both report peaks over the points they
compute (the sub-steps, the solver's steps), not the true peaks inside steps that the exact
solver finds.

The pendulum's friction is where the models differ from the exact one, not only the
integration: at a stop the rigid–plastic friction force changes at once, which an elastic
(OpenSees) or smooth friction cannot; the elastic one then rings at the frequency of the
stuck building, undamped by the average-acceleration rule, which shifts later breakaways
(tests/building/test_nonlinear_approx.py measures both gaps).

References
----------
Newmark, N. M. (1959). A method of computation for structural dynamics. *J. Eng. Mech. Div.
ASCE* 85(EM3), 67–94.
Simo, J. C., Hughes, T. J. R. (1998). *Computational Inelasticity*, Springer, ch. 1.
Wen, Y.-K. (1976). Method for random vibration of hysteretic systems. *J. Eng. Mech. Div.
ASCE* 102(EM2), 249–263.
Nagarajaiah, S., Reinhorn, A. M., Constantinou, M. C. (1991). Nonlinear dynamic analysis of
3-D base-isolated structures. *J. Struct. Eng.* 117(7), 2035–2054.
Schellenberg, A. OpenSees ``singleFPBearing`` element (``SingleFPSimple2d``) and its example
``TestFPS3d_0.tcl``: 18 kip on ``mu = 0.163`` with ``kInit = 250`` kip/in, ``Reff = 34.68``
in — a friction yield displacement of 0.30 mm.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from floorslide._jit import njit
from floorslide.building.nonlinear import NonlinearIsolatedBuilding
from floorslide.errors import ModelError
from floorslide.inputs import as_record

FRICTION_YIELD_DISP = 2.5e-4
"""Default elastic displacement of the pendulum's friction element in
:func:`newmark_isolator_response`, m: the friction force ``mu·W`` is reached over 0.25 mm
(0.01 in), the order of the OpenSees example for ``singleFPBearing`` (0.30 mm; module
notes); OpenSees' ``kInit`` is then ``W/R + mu·W/0.25 mm``."""


@dataclass(frozen=True)
class ApproxIsolatorResponse:
    """The response of a :class:`NonlinearIsolatedBuilding` by an approximate method.

    The fields that matter of :class:`~floorslide.building.nonlinear.IsolatorResponse`, with
    the peaks taken over the points the method computes (see the module notes).

    Attributes
    ----------
    method
        ``"newmark"`` or ``"smooth"``.
    dt
        Record step, s.
    floors
        Floors of ``floor_acceleration`` (0 = the base mat).
    floor_acceleration
        Absolute accelerations at the samples, ``(len(floors), npts)``, m/s².
    pfa
        Peak absolute acceleration per floor over the computed points (sub-steps, solver
        steps), m/s².
    isolator_displacement, isolator_force
        At the samples (m, N); the force is the layer's on the mat (viscous term included).
    peak_displacement
        ``max |u_0|`` over the computed points, m.
    residual_displacement
        ``u_0`` at the end of the record, m.
    peak_force_ratio
        ``max |f_iso| / W`` over the computed points.
    work
        Newton iterations (Newmark) or right-hand-side evaluations (smooth).
    elapsed
        Wall time of the integration, s.
    notes
        What the method did (model parameters, convergence).
    """

    method: str
    dt: float
    floors: tuple[int, ...]
    floor_acceleration: np.ndarray
    pfa: np.ndarray
    isolator_displacement: np.ndarray
    isolator_force: np.ndarray
    peak_displacement: float
    residual_displacement: float
    peak_force_ratio: float
    work: int
    elapsed: float
    notes: tuple[str, ...] = ()


def _check(building, acc, dt, floors):
    if not isinstance(building, NonlinearIsolatedBuilding):
        raise ModelError("building must be a NonlinearIsolatedBuilding", "building")
    acc, dt, notes = as_record(acc, dt)
    n = building.n_dof
    floors = list(building.floors) if floors is None else [int(f) for f in floors]
    for f in floors:
        if not 0 <= f < n:
            raise ModelError(f"floor {f} does not exist; floors are 0..{n - 1}", "floors")
    c = building.constants
    if building.kind == "friction_pendulum" and c["mu_s"] > c["mu"]:
        raise ModelError(
            "the approximate methods have one friction coefficient (as OpenSees' Coulomb "
            "model): give mu_s = mu, or use the exact solver",
            "isolator.mu_s",
        )
    return np.ascontiguousarray(acc, dtype=float), float(dt), floors, tuple(notes)


# --------------------------------------------------------------------------------------------
# Newmark + Newton–Raphson
# --------------------------------------------------------------------------------------------


@njit(cache=True)
def _return_map(du, q_n, kk, qy):
    """Elastic–perfectly-plastic element (Simo & Hughes 1998, §1.3): force and consistent
    tangent after the increment `du` from the committed force `q_n`."""
    q = q_n + kk * du
    if abs(q) <= qy:
        return q, kk
    return (qy if q > 0.0 else -qy), 0.0


@njit(cache=True)
def _newmark_run(m, K, C, Kinv, kl, cl, kk, qy, acc, substeps, h, tol, max_iter, Y, peak):
    """Newmark average acceleration with Newton–Raphson on the isolator's hysteretic force.

    ``K``, ``C`` hold the superstructure on the mat plus the layer's linear terms (``kl``,
    ``cl`` on the mat); ``Kinv`` is the inverse of ``K + 2/h C + 4/h² M``. The hysteretic
    force ``q`` acts on the mat only, so the step's equations
    ``(K + 2/h C + 4/h² M) u + e_0 q(u_0) = p̂`` condense exactly to the scalar
    ``u_0 + g_0 q(u_0) = y_0`` (``g = Kinv e_0``, ``y = Kinv p̂``), on which Newton's iterates
    are those of full Newton–Raphson with the consistent tangent. ``Y`` (n + 2, npts)
    receives the absolute accelerations of all DOFs, the isolator force and its displacement
    at the samples; ``peak`` their maxima of ``|·|`` over all sub-steps. Returns
    ``(iterations, steps that did not converge)``.
    """
    n = m.size
    u = np.zeros(n)
    v = np.zeros(n)
    a = np.zeros(n)
    un = np.zeros(n)
    p = np.empty(n)
    y = np.empty(n)
    g = np.empty(n)
    for i in range(n):
        g[i] = Kinv[i, 0]
    q = 0.0
    # at rest with zero force: M a = −M 1 a_g
    for i in range(n):
        a[i] = -acc[0]
    npts = acc.size
    iters = 0
    failed = 0
    for i in range(n):
        Y[i, 0] = a[i] + acc[0]
        peak[i] = abs(Y[i, 0])
    Y[n, 0] = 0.0
    Y[n + 1, 0] = 0.0
    c4 = 4.0 / (h * h)
    c2 = 2.0 / h
    for k in range(npts - 1):
        a0 = acc[k]
        a1 = acc[k + 1]
        for sub in range(substeps):
            gb = a0 + (a1 - a0) * ((sub + 1) / substeps) if sub + 1 < substeps else a1
            # effective load: −M 1 a_g + M (4/h² u + 4/h v + a) + C (2/h u + v)
            for i in range(n):
                s = m[i] * (-gb + c4 * u[i] + 2.0 * c2 * v[i] + a[i])
                for j in range(n):
                    s += C[i, j] * (c2 * u[j] + v[j])
                p[i] = s
            for i in range(n):
                s = 0.0
                for j in range(n):
                    s += Kinv[i, j] * p[j]
                y[i] = s
            # Newton on u0 + g0 q(u0) = y0, from the last converged state
            x = u[0]
            ok = False
            for _ in range(max_iter):
                iters += 1
                qt, kt = _return_map(x - u[0], q, kk, qy)
                phi = x + g[0] * qt - y[0]
                dx = -phi / (1.0 + g[0] * kt)
                x += dx
                if abs(dx) <= tol:
                    ok = True
                    break
            if not ok:
                failed += 1
            qt, kt = _return_map(x - u[0], q, kk, qy)
            q = qt
            for i in range(n):
                un[i] = y[i] - g[i] * q
            for i in range(n):
                du = un[i] - u[i]
                a[i] = c4 * du - 2.0 * c2 * v[i] - a[i]
                v[i] = c2 * du - v[i]
                u[i] = un[i]
            f = kl * u[0] + cl * v[0] + q
            for i in range(n):
                val = abs(a[i] + gb)
                if val > peak[i]:
                    peak[i] = val
            if abs(f) > peak[n]:
                peak[n] = abs(f)
            if abs(u[0]) > peak[n + 1]:
                peak[n + 1] = abs(u[0])
        for i in range(n):
            Y[i, k + 1] = a[i] + a1
        Y[n, k + 1] = kl * u[0] + cl * v[0] + q
        Y[n + 1, k + 1] = u[0]
    return iters, failed


def _layer(building, friction_yield):
    """Linear stiffness and viscous coefficient of the layer, and its elastic–perfectly-plastic
    element (stiffness, strength)."""
    c = building.constants
    if building.kind == "bilinear":
        return c["k2"], c["c"], c["k1"] - c["k2"], c["Q"]
    qy = c["mu"] * c["W"]
    return c["k"], c["c"], qy / friction_yield, qy


def newmark_isolator_response(
    building: NonlinearIsolatedBuilding,
    acc,
    dt: float | None = None,
    *,
    substeps: int = 1,
    tol: float = 1e-10,
    max_iter: int = 50,
    floors=None,
    friction_yield: float = FRICTION_YIELD_DISP,
) -> ApproxIsolatorResponse:
    """Newmark average acceleration with Newton–Raphson iterations — what OpenSees computes.

    Newmark's (1959) trapezoidal rule (γ = 1/2, β = 1/4) on sub-steps ``h = dt/substeps``,
    the record interpolated linearly between its samples, the superstructure linear
    (``building.mass``, ``stiffness_matrix``, ``damping_matrix``) and the layer's force
    ``f = k u_0 + c u_0' + q`` with ``q`` an elastic–perfectly-plastic element found by return
    mapping (Simo & Hughes 1998, §1.3) and Newton–Raphson iterations on the step's equilibrium
    with the consistent tangent (the module notes):

    - bilinear (OpenSees' ``elastomericBearingPlasticity``): ``k = k_2``, ``q`` of stiffness
      ``k_1 − k_2`` and strength ``Q`` — the same model as the exact solver's;
    - friction pendulum (OpenSees' ``singleFPBearing`` with ``Coulomb`` friction):
      ``k = W/R``, ``q`` of strength ``mu·W`` reached over `friction_yield` (stiffness
      ``mu·W/friction_yield``, OpenSees' ``kInit − W/R``). The exact solver's sticking
      (the mat moves with the ground) becomes an oscillation of at most `friction_yield`
      at the period of the stuck building, which the average-acceleration rule does not
      damp. Only ``mu_s = mu`` (one friction coefficient, as the Coulomb model).

    Parameters
    ----------
    building
        The building.
    acc, dt
        Ground acceleration (m/s²) and its time step, or a Trace.
    substeps
        Sub-steps per record step (≥ 1).
    tol
        Newton iterations stop when the correction of the isolator displacement is below
        ``tol`` times the layer's elastic displacement (``D_y`` or `friction_yield`).
    max_iter
        Newton iterations per step at most (a step that does not converge is kept, as
        OpenSees' ``algorithm Newton`` with a test that only warns; counted in ``notes``).
    floors
        Floors whose absolute accelerations are returned (default all).
    friction_yield
        Elastic displacement of the pendulum's friction element, m (default
        :data:`FRICTION_YIELD_DISP`).

    Returns
    -------
    ApproxIsolatorResponse
        Peaks over the samples and sub-steps: the method does not see inside its steps.
    """
    acc, dt, floors, notes = _check(building, acc, dt, floors)
    k = int(substeps)
    if k != substeps or k < 1:
        raise ModelError(f"substeps must be an integer ≥ 1, got {substeps!r}", "substeps")
    fy = float(friction_yield)
    if not np.isfinite(fy) or fy <= 0:
        raise ModelError(f"must be > 0, got {friction_yield!r}", "friction_yield")
    n = building.n_dof
    h = dt / k
    kl, cl, kk, qy = _layer(building, fy)
    K = building.stiffness_matrix.copy()
    C = building.damping_matrix.copy()
    K[0, 0] += kl
    C[0, 0] += cl
    Kinv = np.linalg.inv(K + 2.0 / h * C + 4.0 / h**2 * np.diag(building.mass))
    scale = building.constants["D_y"] if building.kind == "bilinear" else fy
    Y = np.empty((n + 2, acc.size))
    peak = np.zeros(n + 2)
    t0 = time.perf_counter()
    iters, failed = _newmark_run(
        building.mass, K, C, Kinv, kl, cl, kk, qy, acc, k, h, tol * scale, int(max_iter), Y, peak
    )
    elapsed = time.perf_counter() - t0
    notes = (*notes, f"Newmark average acceleration, h = dt/{k} = {h:.6g} s")
    if building.kind == "friction_pendulum":
        notes += (f"friction element: mu·W reached over {fy:g} m (kInit = W/R + mu·W/{fy:g})",)
    if failed:
        notes += (f"{failed} steps did not converge in {max_iter} Newton iterations",)
    W = building.constants["W"]
    return ApproxIsolatorResponse(
        method="newmark",
        dt=dt,
        floors=tuple(floors),
        floor_acceleration=Y[floors],
        pfa=peak[floors],
        isolator_displacement=Y[n + 1].copy(),
        isolator_force=Y[n].copy(),
        peak_displacement=float(peak[n + 1]),
        residual_displacement=float(Y[n + 1, -1]),
        peak_force_ratio=float(peak[n] / W),
        work=int(iters),
        elapsed=elapsed,
        notes=notes,
    )


# --------------------------------------------------------------------------------------------
# Smooth (regularised) model through solve_ivp
# --------------------------------------------------------------------------------------------


@njit(cache=True)
def _ground(t, acc, dt):
    """The piecewise-linear record at time `t`."""
    x = t / dt
    k = int(x)
    if k < 0:
        return acc[0]
    if k >= acc.size - 1:
        return acc[-1]
    s = x - k
    return acc[k] + s * (acc[k + 1] - acc[k])


@njit(cache=True)
def _smooth_force(y, n, kind, par):
    """The layer's force on the mat and its derivatives in ``u_0``, ``u_0'`` and ``z``.

    ``par = [k, c, Q or mu·W, D_y or eps, exponent]``; for the bilinear layer the hysteretic
    force is ``Q z`` (``z`` the last state), for the pendulum ``mu·W·tanh(u_0'/eps)``."""
    u0 = y[0]
    v0 = y[n]
    k = par[0]
    c = par[1]
    s = par[2]
    if kind == 0:
        return k * u0 + c * v0 + s * y[2 * n], k, c
    th = np.tanh(v0 / par[3])
    return k * u0 + c * v0 + s * th, k, c + s * (1.0 - th * th) / par[3]


@njit(cache=True)
def _smooth_rhs(t, y, m, K, C, kind, par, acc, dt):
    n = m.size
    ag = _ground(t, acc, dt)
    out = np.empty(y.size)
    f, _, _ = _smooth_force(y, n, kind, par)
    for i in range(n):
        out[i] = y[n + i]
        s = 0.0
        for j in range(n):
            s += K[i, j] * y[j] + C[i, j] * y[n + j]
        if i == 0:
            s += f
        out[n + i] = -ag - s / m[i]
    if kind == 0:
        # Wen (1976) with A = 1, β = γ = 1/2: D_y z' = u0' (1 − |z|^ν (1 + sign(u0' z)) / 2)
        v0 = y[n]
        z = y[2 * n]
        az = abs(z) ** par[4]
        load = 1.0 if v0 * z > 0.0 else (0.5 if v0 * z == 0.0 else 0.0)
        out[2 * n] = v0 * (1.0 - az * load) / par[3]
    return out


@njit(cache=True)
def _smooth_jac(t, y, m, K, C, kind, par, acc, dt):
    n = m.size
    J = np.zeros((y.size, y.size))
    _, dfu, dfv = _smooth_force(y, n, kind, par)
    for i in range(n):
        J[i, n + i] = 1.0
        for j in range(n):
            J[n + i, j] = -K[i, j] / m[i]
            J[n + i, n + j] = -C[i, j] / m[i]
    J[n, 0] -= dfu / m[0]
    J[n, n] -= dfv / m[0]
    if kind == 0:
        J[n, 2 * n] = -par[2] / m[0]
        v0 = y[n]
        z = y[2 * n]
        nu = par[4]
        az = abs(z) ** nu
        load = 1.0 if v0 * z > 0.0 else (0.5 if v0 * z == 0.0 else 0.0)
        J[2 * n, n] = (1.0 - az * load) / par[3]
        dz = nu * abs(z) ** (nu - 1.0) * (1.0 if z > 0.0 else -1.0) if z != 0.0 else 0.0
        J[2 * n, 2 * n] = -v0 * dz * load / par[3]
    return J


SMOOTH_EPS = 1e-3
"""Default velocity scale of the pendulum's regularised friction, m/s (see
:func:`smooth_isolator_response`)."""

SMOOTH_SHARPNESS = 20.0
"""Default exponent of the bilinear layer's smooth hysteresis (see
:func:`smooth_isolator_response`)."""


def smooth_isolator_response(
    building: NonlinearIsolatedBuilding,
    acc,
    dt: float | None = None,
    *,
    eps: float = SMOOTH_EPS,
    sharpness: float = SMOOTH_SHARPNESS,
    rtol: float = 1e-8,
    method: str = "LSODA",
    floors=None,
) -> ApproxIsolatorResponse:
    """A regularised (smooth) isolation layer integrated by SciPy's ``solve_ivp``.

    The layer's force is ``f = k u_0 + c u_0' + h``, with ``k``, ``c`` those of the exact
    model and the hysteretic part ``h`` smooth:

    - bilinear: ``h = Q z`` with Wen's (1976) hysteretic variable in the normalised form of
      3D-BASIS (Nagarajaiah et al. 1991; ``A = 1``, ``β = γ = 1/2``; OpenSees'
      ``elastomericBearingBoucWen`` with ``eta = ν``)::

          D_y z' = u_0' (1 − |z|^ν (1 + sign(u_0' z)) / 2),

      elastic (``h' = (k_1 − k_2) u_0'``) at ``z = 0`` and on unloading, tending to ``±Q`` on
      loading, so the initial and post-yield stiffnesses ``k_1``, ``k_2`` and the strength
      ``Q`` are the exact model's; the loop tends to the bilinear one as the exponent
      ``ν`` (`sharpness`) grows (the knee is rounded over ≈ ``D_y`` for ``ν = 2``, over
      ``D_y·ln 2/ν`` for large ``ν``);
    - pendulum: ``h = mu·W·tanh(u_0'/eps)``: no sticking, a slow creep instead, at speed
      ``eps·artanh(F/(mu·W))`` where the exact layer sticks with friction ``F``; the
      friction's transition is stiff (its rate ``mu·W/(m_b·eps)``), hence the implicit
      default ``LSODA``. ``mu_s`` > ``mu`` has no counterpart (refused).

    The record is the piecewise-linear one of the exact solver; the integration runs once
    over the whole record (the kinks of the record at its samples are steps of the solver's
    error control) with ``atol = rtol × 1e-3`` (m, m/s and the dimensionless ``z``) and the
    analytic Jacobian; samples are read from the dense output.

    Parameters
    ----------
    building
        The building.
    acc, dt
        Ground acceleration (m/s²) and its time step, or a Trace.
    eps
        Velocity scale of the pendulum's friction, m/s (default :data:`SMOOTH_EPS`).
    sharpness
        Exponent ``ν`` of the bilinear layer's hysteresis (default :data:`SMOOTH_SHARPNESS`).
    rtol
        Relative tolerance of ``solve_ivp``.
    method
        ``"LSODA"``, ``"Radau"`` or ``"BDF"`` (implicit, with the Jacobian); an explicit
        method (``"RK45"``, ``"DOP853"``) is accepted but slow on the stiff friction.
    floors
        Floors whose absolute accelerations are returned (default all).

    Returns
    -------
    ApproxIsolatorResponse
        Peaks over the samples and the solver's steps.
    """
    from scipy.integrate import solve_ivp  # SciPy's integrators: only when asked for

    acc, dt, floors, notes = _check(building, acc, dt, floors)
    if method not in ("LSODA", "Radau", "BDF", "RK45", "DOP853", "RK23"):
        raise ModelError(f"unknown integrator {method!r}", "method")
    n = building.n_dof
    c = building.constants
    if building.kind == "bilinear":
        nu = float(sharpness)
        if not np.isfinite(nu) or nu < 1:
            raise ModelError(f"must be ≥ 1, got {sharpness!r}", "sharpness")
        kind = 0
        par = np.array([c["k2"], c["c"], c["Q"], c["D_y"], nu])
        y0 = np.zeros(2 * n + 1)
        notes = (*notes, f"Wen hysteresis, exponent {nu:g}")
    else:
        e = float(eps)
        if not np.isfinite(e) or e <= 0:
            raise ModelError(f"must be > 0, got {eps!r}", "eps")
        kind = 1
        par = np.array([c["k"], c["c"], c["mu"] * c["W"], e, 0.0])
        y0 = np.zeros(2 * n)
        notes = (*notes, f"friction mu·W·tanh(u0'/{e:g} m/s)")
    m = building.mass
    K = building.stiffness_matrix
    C = building.damping_matrix
    args = (m, K, C, kind, par, acc, dt)
    t_end = (acc.size - 1) * dt
    t0 = time.perf_counter()
    sol = solve_ivp(
        lambda t, y: _smooth_rhs(t, y, *args),
        (0.0, t_end),
        y0,
        method=method,
        rtol=rtol,
        atol=rtol * 1e-3,
        jac=None if method in ("RK45", "DOP853", "RK23") else lambda t, y: _smooth_jac(t, y, *args),
        dense_output=True,
    )
    if not sol.success:
        raise ModelError(f"solve_ivp failed: {sol.message}", "method")
    ts = np.arange(acc.size) * dt
    ts[-1] = min(ts[-1], sol.t[-1])
    ys = sol.sol(ts)
    elapsed = time.perf_counter() - t0
    # outputs at the samples and at the solver's own steps
    tt = np.concatenate([ts, sol.t])
    yy = np.concatenate([ys, sol.y], axis=1)
    force = np.empty(tt.size)
    for j in range(tt.size):
        force[j] = _smooth_force(yy[:, j], n, kind, par)[0]
    # absolute accelerations: M (u'' + a_g) = −K u − C u' − e_0 f
    inner = -(K @ yy[:n] + C @ yy[n : 2 * n])
    inner[0] -= force
    absacc = inner / m[:, None]
    ns = acc.size
    notes = (*notes, f"solve_ivp {method}: {sol.t.size} steps, {sol.nfev} evaluations")
    return ApproxIsolatorResponse(
        method="smooth",
        dt=dt,
        floors=tuple(floors),
        floor_acceleration=absacc[floors, :ns],
        pfa=np.abs(absacc[floors]).max(axis=1),
        isolator_displacement=yy[0, :ns].copy(),
        isolator_force=force[:ns],
        peak_displacement=float(np.abs(yy[0]).max()),
        residual_displacement=float(ys[0, -1]),
        peak_force_ratio=float(np.abs(force).max() / c["W"]),
        work=int(sol.nfev),
        elapsed=elapsed,
        notes=notes,
    )
