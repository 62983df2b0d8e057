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

It does not find the instants where the layer yields, unloads, sticks or breaks away: it
steps over them (a step that holds one has a larger local error, a finite number of them
leaves the global second order of the trapezoidal rule), and it reports peaks over the
sub-steps, not the true peaks inside steps that the exact solver finds.

The pendulum's friction is where the models differ from the exact one, not only the
integration: at a stop the rigid–plastic friction force changes at once, which an elastic
(OpenSees) friction cannot; it then rings at the frequency of the
stuck building, undamped by the average-acceleration rule, which shifts later breakaways
(tests/building/test_nonlinear_approx.py measures the gap).

References
----------
Newmark, N. M. (1959). A method of computation for structural dynamics. *J. Eng. Mech. Div.
ASCE* 85(EM3), 67–94.
Simo, J. C., Hughes, T. J. R. (1998). *Computational Inelasticity*, Springer, ch. 1.
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
        ``"newmark"``.
    dt
        Record step, s.
    floors
        Floors of ``floor_acceleration`` (0 = the base mat).
    floor_acceleration
        Absolute accelerations at the samples, ``(len(floors), npts)``, m/s².
    pfa
        Peak absolute acceleration per floor over the computed points (sub-steps), m/s².
    isolator_displacement, isolator_force
        At the samples (m, N); the force is the layer's on the mat (viscous term included).
    peak_displacement
        ``max |u_0|`` over the computed points, m.
    residual_displacement
        ``u_0`` at the end of the record, m.
    peak_force_ratio
        ``max |f_iso| / W`` over the computed points.
    work
        Newton iterations.
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
