"""Approximate solvers for a building on nonlinear isolation under two horizontal components,
kept for the accuracy-versus-cost study (docs/design.md §6, §10b "In the plane") beside the
exact coupled solver (:mod:`floorslide.building.plane_isolation`):

- :func:`newmark_plane_isolator_response` — what OpenSees computes with a three-dimensional
  ``singleFPBearing`` (Coulomb friction) or ``elastomericBearingPlasticity``: Newmark's average
  acceleration rule on ``dt/substeps`` and Newton–Raphson iterations on the bearing's force,
  an elastic–perfectly-plastic element with a *circular* yield surface (radial return, Simo &
  Hughes 1998, §2.3), so the two directions share one friction (or yield) force. For the
  pendulum, friction is reached over an elastic displacement `friction_yield`, as in 1-D
  (:func:`floorslide.building.nonlinear_approx.newmark_isolator_response`).
- :func:`smoothed_plane_isolator_response` — the smoothed bidirectional model of the
  design literature (3D-BASIS, SAP2000's and ETABS' friction and rubber isolators): a Bouc–Wen
  hysteretic vector ``z`` with Park, Wen & Ang's (1986) interaction, ``|z| ≤ 1`` turning with the
  bearing's velocity once it yields, integrated with the superstructure in both directions by
  SciPy's ``solve_ivp``; the bearing's force ``k_l u + c u' + Q z`` (``Q = mu W`` for the
  pendulum, Constantinou, Mokha & Reinhorn 1990).
- :func:`uncoupled_plane_isolator_response` — the per-direction model: each direction's 1-D
  building under its own component (a friction force of its own along each axis), by the exact
  1-D solver; the model the coupled one replaces.

References
----------
Newmark, N. M. (1959). *J. Eng. Mech. Div. ASCE* 85(EM3), 67–94.
Simo, J. C., Hughes, T. J. R. (1998). *Computational Inelasticity*, Springer, §2.3 (radial
return for a circular yield surface).
Mokha, A., Constantinou, M. C., Reinhorn, A. M. (1993). *J. Struct. Eng.* 119(1), 240–261.
Park, Y. J., Wen, Y. K., Ang, A. H.-S. (1986). Random vibration of hysteretic systems under
bi-directional ground motions. *Earthq. Eng. Struct. Dyn.* 14(4), 543–557.
Constantinou, M., Mokha, A., Reinhorn, A. (1990). Teflon bearings in base isolation II:
modeling. *J. Struct. Eng.* 116(2), 455–474.
Nagarajaiah, S., Reinhorn, A. M., Constantinou, M. C. (1991). Nonlinear dynamic analysis of 3-D
base-isolated structures. *J. Struct. Eng.* 117(7), 2035–2054 (eq. 6, the biaxial model).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from floorslide._jit import njit
from floorslide.building.nonlinear import isolator_response
from floorslide.building.nonlinear_approx import FRICTION_YIELD_DISP
from floorslide.building.plane_isolation import plane_layer
from floorslide.errors import ModelError

__all__ = [
    "PlaneApproxResponse",
    "newmark_plane_isolator_response",
    "smoothed_plane_isolator_response",
    "uncoupled_plane_isolator_response",
]


@dataclass(frozen=True)
class PlaneApproxResponse:
    """A building on nonlinear isolation under two components, by an approximate method.

    Attributes
    ----------
    method
        ``"newmark"``, ``"smoothed"`` or ``"uncoupled"``.
    dt
        Record step, s.
    displacement
        The bearing's displacement vector at the samples, ``(npts, 2)``, m.
    floor_acceleration
        Every floor's absolute acceleration at the samples, ``(npts, n_dof, 2)``, m/s².
    peak_displacement
        ``max |u_b|`` over the points the method computes, m.
    work
        Newton iterations (Newmark), right-hand side evaluations (smoothed); 0 for the
        uncoupled model.
    elapsed
        Wall time of the integration, s.
    notes
        What the method did.
    """

    method: str
    dt: float
    displacement: np.ndarray
    floor_acceleration: np.ndarray
    peak_displacement: float
    work: int
    elapsed: float
    notes: tuple[str, ...] = ()


@njit(cache=True)
def _radial_return(dux, duy, qx, qy, kk, qmax, T):
    """Circular elastic–perfectly-plastic element: force after the increment ``(dux, duy)``
    from the committed force ``(qx, qy)``, and its consistent tangent in ``T`` (2×2)."""
    tx = qx + kk * dux
    ty = qy + kk * duy
    r = np.hypot(tx, ty)
    if r <= qmax:
        T[0, 0] = kk
        T[1, 1] = kk
        T[0, 1] = 0.0
        T[1, 0] = 0.0
        return tx, ty
    nx, ny = tx / r, ty / r
    s = kk * qmax / r
    T[0, 0] = s * (1.0 - nx * nx)
    T[1, 1] = s * (1.0 - ny * ny)
    T[0, 1] = -s * nx * ny
    T[1, 0] = T[0, 1]
    return qmax * nx, qmax * ny


@njit(cache=True)
def _newmark_plane(m, Kinv, C, acc, substeps, h, kk, qmax, tol, max_iter, A, U, peak):
    """Newmark average acceleration in both directions with Newton–Raphson on the bearing's
    circular element. ``Kinv[d]`` inverts ``K_d + 2/h C_d + 4/h² M`` (the layer's linear terms
    in ``K_d``, ``C_d``); the element acts on the mat only, so each step condenses exactly to
    ``u_0d + g_d q_d(u_0) = y_d`` (``g_d = Kinv[d] e_0``), two equations. ``A`` (npts, n, 2)
    receives the absolute accelerations at the samples, ``U`` (npts, 2) the bearing;
    ``peak[0]`` the largest ``|u_b|`` over the sub-steps. Returns (iterations, failures)."""
    n = m.size
    u = np.zeros((2, n))
    v = np.zeros((2, n))
    a = np.zeros((2, n))
    un = np.zeros(n)
    y = np.zeros((2, n))
    p = np.zeros(n)
    T = np.zeros((2, 2))
    q = np.zeros(2)
    c4 = 4.0 / (h * h)
    c2 = 2.0 / h
    npts = acc.shape[1]
    for d in range(2):
        for i in range(n):
            a[d, i] = -acc[d, 0]
            A[0, i, d] = 0.0
    iters = 0
    failed = 0
    for k in range(npts - 1):
        for sub in range(substeps):
            for d in range(2):
                a0 = acc[d, k]
                a1 = acc[d, k + 1]
                gb = a0 + (a1 - a0) * ((sub + 1) / substeps) if sub + 1 < substeps else a1
                for i in range(n):
                    s = m[i] * (-gb + c4 * u[d, i] + 2.0 * c2 * v[d, i] + a[d, i])
                    for j in range(n):
                        s += C[d, i, j] * (c2 * u[d, j] + v[d, j])
                    p[i] = s
                for i in range(n):
                    s = 0.0
                    for j in range(n):
                        s += Kinv[d, i, j] * p[j]
                    y[d, i] = s
            g0 = Kinv[0, 0, 0]
            g1 = Kinv[1, 0, 0]
            x0 = u[0, 0]
            x1 = u[1, 0]
            ok = False
            for _ in range(max_iter):
                iters += 1
                fx, fy = _radial_return(x0 - u[0, 0], x1 - u[1, 0], q[0], q[1], kk, qmax, T)
                r0 = x0 + g0 * fx - y[0, 0]
                r1 = x1 + g1 * fy - y[1, 0]
                j00 = 1.0 + g0 * T[0, 0]
                j01 = g0 * T[0, 1]
                j10 = g1 * T[1, 0]
                j11 = 1.0 + g1 * T[1, 1]
                det = j00 * j11 - j01 * j10
                dx0 = -(j11 * r0 - j01 * r1) / det
                dx1 = -(-j10 * r0 + j00 * r1) / det
                x0 += dx0
                x1 += dx1
                if abs(dx0) <= tol and abs(dx1) <= tol:
                    ok = True
                    break
            if not ok:
                failed += 1
            fx, fy = _radial_return(x0 - u[0, 0], x1 - u[1, 0], q[0], q[1], kk, qmax, T)
            q[0] = fx
            q[1] = fy
            for d in range(2):
                qd = q[d]
                for i in range(n):
                    un[i] = y[d, i] - Kinv[d, i, 0] * qd
                for i in range(n):
                    du = un[i] - u[d, i]
                    a[d, i] = c4 * du - 2.0 * c2 * v[d, i] - a[d, i]
                    v[d, i] = c2 * du - v[d, i]
                    u[d, i] = un[i]
            r = np.hypot(u[0, 0], u[1, 0])
            if r > peak[0]:
                peak[0] = r
        for d in range(2):
            for i in range(n):
                A[k + 1, i, d] = a[d, i] + acc[d, k + 1]
            U[k + 1, d] = u[d, 0]
    return iters, failed


def _pair(building, h1, h2, dt):
    bx, by = plane_layer(building, bilinear=True)
    h1 = np.ascontiguousarray(h1, dtype=float)
    h2 = np.ascontiguousarray(h2, dtype=float)
    if h1.shape != h2.shape or h1.ndim != 1 or h1.size < 2:
        raise ModelError("the two components must be 1-D arrays of one length ≥ 2", "acc")
    if not dt > 0:
        raise ModelError(f"must be > 0, got {dt!r}", "dt")
    return bx, by, h1, h2, float(dt)


def newmark_plane_isolator_response(
    building, h1, h2, dt: float, *, substeps: int = 1, tol: float = 1e-10, max_iter: int = 50,
    friction_yield: float = FRICTION_YIELD_DISP,
) -> PlaneApproxResponse:  # fmt: skip
    """Newmark average acceleration with Newton–Raphson on a bearing with a circular yield
    surface (module notes) — OpenSees' bidirectional ``singleFPBearing`` /
    ``elastomericBearingPlasticity``.

    Parameters
    ----------
    building
        A :class:`~floorslide.building.nonlinear.NonlinearIsolatedBuilding` (friction pendulum
        or lead-rubber), or a pair of them on one mat and layer.
    h1, h2, dt
        The two horizontal ground components (m/s²) and their step (s).
    substeps
        Sub-steps per record step (≥ 1).
    tol
        Newton stops when the corrections are below ``tol`` times the element's elastic
        displacement.
    max_iter
        Newton iterations per step at most (a step that does not converge is kept and counted
        in ``notes``).
    friction_yield
        The pendulum's friction element's elastic displacement, m.
    """
    bx, by, h1, h2, dt = _pair(building, h1, h2, dt)
    k = int(substeps)
    if k != substeps or k < 1:
        raise ModelError(f"substeps must be an integer ≥ 1, got {substeps!r}", "substeps")
    fy = float(friction_yield)
    if not np.isfinite(fy) or fy <= 0:
        raise ModelError(f"must be > 0, got {friction_yield!r}", "friction_yield")
    c = bx.constants
    if bx.kind == "bilinear":
        kl, cl, kk, qmax, scale = c["k2"], c["c"], c["k1"] - c["k2"], c["Q"], c["D_y"]
    else:
        kl, cl, qmax, scale = c["k"], c["c"], c["mu"] * c["W"], fy
        kk = qmax / fy
    h = dt / k
    n = bx.n_dof
    Kinv = np.empty((2, n, n))
    C = np.empty((2, n, n))
    for d, b in enumerate((bx, by)):
        K = b.stiffness_matrix.copy()
        Cd = b.damping_matrix.copy()
        K[0, 0] += kl
        Cd[0, 0] += cl
        Kinv[d] = np.linalg.inv(K + 2.0 / h * Cd + 4.0 / h**2 * np.diag(b.mass))
        C[d] = Cd
    acc = np.vstack([h1, h2])
    A = np.zeros((h1.size, n, 2))
    U = np.zeros((h1.size, 2))
    peak = np.zeros(1)
    t0 = time.perf_counter()
    iters, failed = _newmark_plane(
        bx.mass, Kinv, C, acc, k, h, kk, qmax, tol * scale, int(max_iter), A, U, peak
    )
    elapsed = time.perf_counter() - t0
    notes = (f"Newmark average acceleration, h = dt/{k} = {h:.6g} s, circular yield surface",)
    if bx.kind != "bilinear":
        notes += (f"friction element: mu·W reached over {fy:g} m",)
    if failed:
        notes += (f"{failed} steps did not converge in {max_iter} Newton iterations",)
    return PlaneApproxResponse(
        method="newmark", dt=dt, displacement=U, floor_acceleration=A,
        peak_displacement=float(peak[0]), work=int(iters), elapsed=elapsed, notes=notes,
    )  # fmt: skip


def smoothed_plane_isolator_response(
    building, h1, h2, dt: float, *, yield_disp: float | None = None, rtol: float = 1e-8,
    atol: float = 1e-12, integrator: str = "LSODA",
) -> PlaneApproxResponse:  # fmt: skip
    """The smoothed bidirectional (Park–Wen / Bouc–Wen) bearing coupled with the
    superstructure in both directions, by SciPy's ``solve_ivp`` (module notes).

    With ``A = 1``, ``β = γ = 1/2`` and exponent 2 (Nagarajaiah et al. 1991, eq. 6), the
    hysteretic vector obeys

    ``Y ż_x = u̇_x − z_x (β|u̇_x z_x| + γ u̇_x z_x + β|u̇_y z_y| + γ u̇_y z_y)``

    (and the same with ``x ↔ y``): ``|z|`` never exceeds 1, and on ``|z| = 1`` with the bearing
    moving outward ``z`` turns towards the velocity (the friction circle, smoothed). The
    bearing's force is ``k_l u + c u̇ + Q z``: for the friction pendulum ``k_l = W/R``,
    ``Q = mu W`` and ``Y`` the small elastic displacement before sliding (default
    :data:`~floorslide.building.nonlinear_approx.FRICTION_YIELD_DISP`); for lead-rubber
    ``k_l = k₂``, ``Q`` and ``Y = D_y`` its own. Not exact: stiction (``mu_s``) is not
    represented and sliding starts gradually.

    Parameters
    ----------
    building
        A :class:`~floorslide.building.nonlinear.NonlinearIsolatedBuilding` (friction pendulum
        or lead-rubber), or a pair of them on one mat and layer.
    h1, h2, dt
        The two horizontal ground components (m/s², linear between samples) and their step (s).
    yield_disp
        ``Y``, m (pendulum only; lead-rubber uses its ``D_y``).
    rtol, atol, integrator
        ``solve_ivp``'s tolerances and method (``max_step = dt``).
    """
    from scipy.integrate import solve_ivp

    bx, by, h1, h2, dt = _pair(building, h1, h2, dt)
    c = bx.constants
    if bx.kind == "bilinear":
        if yield_disp is not None:
            raise ModelError("a lead-rubber bearing yields at its own D_y", "yield_disp")
        kl, cl, qmax, Y = c["k2"], c["c"], c["Q"], c["D_y"]
    else:
        Y = FRICTION_YIELD_DISP if yield_disp is None else float(yield_disp)
        kl, cl, qmax = c["k"], c["c"], c["mu"] * c["W"]
    if not np.isfinite(Y) or Y <= 0:
        raise ModelError(f"must be > 0, got {yield_disp!r}", "yield_disp")
    n = bx.n_dof
    Minv = 1.0 / bx.mass
    K = np.empty((2, n, n))
    C = np.empty((2, n, n))
    for d, b in enumerate((bx, by)):
        K[d] = b.stiffness_matrix
        C[d] = b.damping_matrix
        K[d][0, 0] += kl
        C[d][0, 0] += cl
    t_grid = np.arange(h1.size) * dt
    acc = np.vstack([h1, h2])
    beta = gamma = 0.5
    calls = [0]

    def accel(t, y):
        """The floors' relative accelerations ``(2, n)``, ``ż`` and the ground there."""
        calls[0] += 1
        k = min(int(t / dt), h1.size - 2)
        w = t / dt - k
        ag = (1.0 - w) * acc[:, k] + w * acc[:, k + 1]
        u = y[: 2 * n].reshape(2, n)
        v = y[2 * n : 4 * n].reshape(2, n)
        z = y[4 * n :]
        a = np.empty((2, n))
        for d in range(2):
            f = K[d] @ u[d] + C[d] @ v[d]
            f[0] += qmax * z[d]
            a[d] = -Minv * f - ag[d]
        vx, vy = v[0, 0], v[1, 0]
        zx, zy = z
        s = beta * abs(vx * zx) + gamma * vx * zx + beta * abs(vy * zy) + gamma * vy * zy
        dz = np.array([vx - zx * s, vy - zy * s]) / Y
        return a, dz, ag

    def rhs(t, y):
        a, dz, _ = accel(t, y)
        return np.concatenate([y[2 * n : 4 * n], a.ravel(), dz])

    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, t_grid[-1]), np.zeros(4 * n + 2), method=integrator,
                    t_eval=t_grid, rtol=rtol, atol=atol, max_step=dt)  # fmt: skip
    elapsed = time.perf_counter() - t0
    if not sol.success:
        raise ModelError(f"solve_ivp ({integrator}) failed: {sol.message}", "integrator")
    Yt = sol.y.T
    U = np.stack([Yt[:, 0], Yt[:, n]], axis=1)
    A = np.empty((h1.size, n, 2))
    for i, (t, y) in enumerate(zip(sol.t, Yt, strict=True)):
        a, _, ag = accel(t, y)
        A[i] = (a + ag[:, None]).T
    notes = (
        f"Park–Wen smoothed bearing, Y = {Y:g} m, solve_ivp {integrator} rtol {rtol:g}, "
        "max_step = dt; no stiction",
    )
    return PlaneApproxResponse(
        method="smoothed", dt=dt, displacement=U, floor_acceleration=A,
        peak_displacement=float(np.hypot(U[:, 0], U[:, 1]).max()), work=int(sol.nfev),
        elapsed=elapsed, notes=notes,
    )  # fmt: skip


def uncoupled_plane_isolator_response(building, h1, h2, dt: float) -> PlaneApproxResponse:
    """The per-direction model: each direction's 1-D building under its own component by the
    exact 1-D solver (:func:`~floorslide.building.nonlinear.isolator_response`), taken
    together as a vector — as if the bearing had a friction (yield) force of its own along each
    axis. ``peak_displacement`` is the largest ``|u_b|`` at the samples."""
    bx, by, h1, h2, dt = _pair(building, h1, h2, dt)
    t0 = time.perf_counter()
    rs = [isolator_response(b, a, dt) for b, a in ((bx, h1), (by, h2))]
    elapsed = time.perf_counter() - t0
    U = np.stack([r.isolator_displacement for r in rs], axis=1)
    A = np.stack([np.asarray(r.floor_acceleration).T for r in rs], axis=2)
    return PlaneApproxResponse(
        method="uncoupled", dt=dt, displacement=U, floor_acceleration=A,
        peak_displacement=float(np.hypot(U[:, 0], U[:, 1]).max()), work=0, elapsed=elapsed,
        notes=("each direction alone (uncoupled): a friction force of its own along each axis",),
    )  # fmt: skip
