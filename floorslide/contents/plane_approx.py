"""Approximate methods for rigid blocks sliding in the plane, beside the exact solver of
:mod:`floorslide.contents.plane` (for ``floorslide bench``; docs/design.md §6, §10d).

The model is the exact solver's: while sliding ``v' = −a(t) − mu_k g v/|v|`` (``v = u'`` the
block's velocity relative to its floor, ``a`` the floor's absolute acceleration, 2-vectors); a
block at rest breaks away when ``|a| > mu_b g``, ``mu_b = max(mu_s, mu_k)``; at a stop it sticks
if ``|a| ≤ mu_b g``, else slides on. Three approximations of it:

``"components"``
    The common practice: each horizontal component slid alone by the exact 1-D solver
    (:func:`floorslide.slide`, the same floor motions), the two slides taken together as the
    vector ``u(t) = (u_1(t), u_2(t))``. Each direction then has its own friction ``mu g`` —
    a friction *square*, not the friction circle — so the block sticks and slides in each
    direction independently: this is a different model, not a discretisation, and its error does
    not shrink with any setting. Exact for an input along one component's axis (the other slide
    is zero). ``peak_slide`` is ``max |u|`` over the samples and at each component's own time
    of peak (the other component interpolated linearly there): within O(dt²) of the in-step
    maximum, and exactly the 1-D peak when one component is zero.

``"newmark"``
    Fixed sub-steps ``h = dt/k`` of the Moreau–Jean time-stepping scheme (Jean 1999), the
    friction as a return map (Simo & Hughes 1998, the closest-point projection onto the
    admissible set): over a sub-step the floor's impulse is the trapezoid of its acceleration
    samples (exact for a floor linear in the sub-step), giving the trial velocity without
    friction ``v* = v_n − h (a_n + a_{n+1})/2``; the friction impulse is then implicit
    (backward Euler): a block at rest stays at rest if the trial change is within the static
    limit, ``|v*| ≤ mu_b g h``, else, and for a sliding block, ``|v*|`` is reduced by
    ``mu_k g h`` along ``v*`` (``v_{n+1} = (1 − mu_k g h/|v*|) v*``), or to zero — a stop — if
    ``|v*| ≤ mu_k g h``. The displacement is advanced by the trapezoid of the velocities
    (``θ = 1/2``). Stops and breakaways are thus placed at sub-step ends and the friction
    direction is that at the sub-step's end: first order in ``h`` in the plane, where the
    direction turns (measured orders 0.97–1.03 on the bundled pairs; in 1-D, between stops and
    breakaways, it is Newmark's average acceleration).
    The floor acceleration is sampled at the sub-steps: the record joined by straight lines on
    the ground, the building's exact response (:func:`floorslide.floor_motions` with
    ``oversample=k``) on a floor. Peaks, the path ``∫|v| dt`` and the work ``∫ a·v dt`` are
    read at the sub-steps (trapezoids).

``"solve_ivp"``
    SciPy's :func:`~scipy.integrate.solve_ivp` (``RK45`` by default, or ``integrator``) at
    ``rtol``, restarted at every record sample (the floor acceleration has a kink there) and at
    every event, the building (on a floor) integrated with the block, each direction's model
    under its component; absolute tolerances are ``rtol`` times the record's scales (a velocity
    ``max|a_g|·dt``, a displacement ``max|a_g|·dt²``). A stuck block breaks away at the first
    root of ``|a|² − (mu_b g)²``: on the ground a quadratic in each step, solved in closed form;
    on a floor a terminal event, with steps of at most ``dt/4`` so that short excursions are
    seen. A sliding block stops where its speed falls to ``v_stop = 10·rtol·max|a_g|·dt``
    (terminal event; ``|v|`` reaches zero without crossing it, and an explicit method chatters
    about it), or where the velocity's component along its direction at the segment's start
    falls through zero with the speed at most ``v_stop`` (else the velocity has turned by a
    right angle: a new segment). Two things make the plain equation hard for an ODE solver,
    and are dealt with so that the error shrinks with ``rtol``:

    - *the start from rest*, where ``v/|v|`` is undefined: below ``v_stop`` the friction's
      direction goes linearly from that of a start from rest, ``−a/|a|``, to ``v/|v|``, which
      makes the field continuous and gives Coulomb's start ``v' = −(|a| − mu_k g)·a/|a|``
      (a block found slower than ``v_stop`` at a sample, with the floor within the static
      limit, is at rest);
    - *stiffness at low speed*: the velocity's direction relaxes at the rate ``mu_k g/|v|``,
      far beyond an explicit method's stability limit after a breakaway (with
      ``mu_s = mu_k`` the speed grows like ``τ²``), so a segment that begins slower than
      ``(2/30)·mu_k g·dt`` is integrated by SciPy's implicit ``BDF`` (analytic Jacobian), and
      an explicit segment ends where the speed falls to ``(1/30)·mu_k g·dt``.

    Peaks of ``|u|`` between the step ends are located as events (``u·v = 0`` falling); the
    path and work are integrated with the state. On a floor the building's states are
    integrated over the whole record at ``rtol`` per step, and the error grows with the
    number of steps, amplified where the floor barely exceeds the friction limit: measured
    4–4,000 times ``rtol`` on floors (levelling off near 4e-7 on the bench's isolated roof),
    about ``rtol`` on the ground.

All three return the fields of :class:`~floorslide.contents.plane.PlaneSlideResult` with the
same meaning; where a method cannot give one it is NaN (float fields) or −1 (counts): the
components' ``slide_fraction``, ``path`` and ``work_floor`` are NaN and their ``slip_phases`` and
``stops`` −1 (two independent 1-D slides have no single slide history).

References
----------
Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In
*Nonsmooth Mechanics and Applications*, CISM Courses and Lectures 302, Springer, 1–82.
Jean, M. (1999). The non-smooth contact dynamics method. *Comput. Methods Appl. Mech. Engrg.*
177(3–4), 235–257.
Simo, J. C., Hughes, T. J. R. (1998). *Computational Inelasticity*. Springer (return mapping
algorithms, ch. 1–3).
Acary, V., Brogliato, B. (2008). *Numerical Methods for Nonsmooth Dynamical Systems*. Springer,
LNACM 35 (the Moreau–Jean scheme, its order one).
Dormand, J. R., Prince, P. J. (1980). A family of embedded Runge–Kutta formulae. *J. Comput.
Appl. Math.* 6(1), 19–26.
Shampine, L. F., Reichelt, M. W. (1997). The MATLAB ODE suite. *SIAM J. Sci. Comput.* 18(1),
1–22 (event location).
Newmark, N. M. (1965). Effects of earthquakes on dams and embankments. *Géotechnique* 15(2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from floorslide._jit import njit
from floorslide.building.directions import per_direction
from floorslide.building.exact_motion import FloorMotion
from floorslide.building.motions import floor_motions
from floorslide.contents.sliding import slide
from floorslide.errors import ModelError, SolverLimitError

METHODS = ("components", "newmark", "solve_ivp")
"""The approximate methods (``method=`` of :func:`floorslide.slide_plane`)."""
STOP_FACTOR = 10.0
"""solve_ivp: a sliding speed at or below ``STOP_FACTOR`` times the velocity tolerance is a
stop."""
INTEGRATORS = ("RK45", "DOP853", "RK23", "Radau", "BDF", "LSODA")
IMPLICIT = ("Radau", "BDF", "LSODA")
START_INTEGRATOR = "BDF"
"""solve_ivp: the implicit method of the segments that begin with a sliding speed below
``2·SWITCH_SPEED·mu_k g·dt`` (from rest, and until the block is that fast; an explicit segment
ends where the speed falls to ``SWITCH_SPEED·mu_k g·dt``)."""
SWITCH_SPEED = 1.0 / 30.0
"""solve_ivp: beyond ``SWITCH_SPEED·mu_k g·dt`` an explicit method's stability limit on the
direction's relaxation, ``h ≈ 3|v|/(mu_k g)``, is above a tenth of the record step."""

# columns of the newmark kernel's output
PEAK, ANGLE, T_PEAK, UX, UY, VX, VY, SLIDE_TIME, SLIPS, STOPS, PATH, WORK = range(12)
NCOL = 12


@dataclass(frozen=True)
class Approximation:
    """What an approximate method computed, one entry per friction pair (the fields of
    :class:`~floorslide.contents.plane.PlaneSlideResult` of the same names; angles in degrees;
    ``peak_slide_1d`` only from ``"components"``, else None)."""

    peak_slide: np.ndarray
    peak_angle: np.ndarray
    time_of_peak: np.ndarray
    residual: np.ndarray
    slide_fraction: np.ndarray
    slip_phases: np.ndarray
    stops: np.ndarray
    path: np.ndarray
    work_floor: np.ndarray
    final_velocity: np.ndarray
    u: np.ndarray | None = None
    peak_slide_1d: np.ndarray | None = None


def approximate(
    method: str,
    h1: np.ndarray,
    h2: np.ndarray,
    dt: float,
    mk: np.ndarray,
    ms: np.ndarray,
    building,
    floor: int | None,
    fm1: FloorMotion,
    fm2: FloorMotion,
    g: float,
    histories: bool = False,
    substeps: int = 4,
    rtol: float = 1e-6,
    integrator: str = "RK45",
) -> Approximation:
    """Slide blocks in the plane by an approximate method (validated and dispatched by
    :func:`floorslide.slide_plane`; see the module docstring).

    Parameters
    ----------
    method
        One of :data:`METHODS`.
    h1, h2, dt
        Ground accelerations along ``x`` and ``y`` (m/s², equal lengths) and their step (s).
    mk, ms
        Kinetic and static coefficients, equal 1-D arrays.
    building, floor
        As :func:`floorslide.slide_plane` (None: on the ground).
    fm1, fm2
        The floor's exact motions along ``x`` and ``y``
        (:func:`~floorslide.building.directions.plane_motions`).
    g
        Gravity, m/s².
    histories
        Also return ``u`` at the samples, ``(n, npts, 2)``.
    substeps
        ``k`` of ``"newmark"`` (sub-step ``dt/k``).
    rtol, integrator
        Relative tolerance and SciPy method of ``"solve_ivp"``.

    Returns
    -------
    Approximation
    """
    if method == "components":
        return _components(fm1, fm2, mk, ms, dt, histories)
    mub = np.maximum(mk, ms)
    if method == "newmark":
        k = int(substeps) if float(substeps) == int(substeps) else 0
        if k < 1:
            raise ModelError(f"substeps must be an integer ≥ 1, got {substeps!r}", "substeps")
        a1, a2 = _floor_samples(building, floor, h1, h2, dt, k)
        npts = h1.size
        out = np.zeros((mk.size, NCOL))
        hist = np.zeros((mk.size, npts, 2) if histories else (0, 0, 2))
        _return_map(a1, a2, k, dt / k, g, mub, mk, out, hist, histories)
        duration = (npts - 1) * dt
        return Approximation(
            peak_slide=out[:, PEAK].copy(),
            peak_angle=np.degrees(out[:, ANGLE]),
            time_of_peak=out[:, T_PEAK].copy(),
            residual=out[:, [UX, UY]].copy(),
            slide_fraction=out[:, SLIDE_TIME] / duration if duration > 0 else np.zeros(mk.size),
            slip_phases=out[:, SLIPS].astype(int),
            stops=out[:, STOPS].astype(int),
            path=out[:, PATH].copy(),
            work_floor=out[:, WORK].copy(),
            final_velocity=out[:, [VX, VY]].copy(),
            u=hist if histories else None,
        )
    if method == "solve_ivp":
        if integrator not in INTEGRATORS:
            raise ModelError(
                f"unknown integrator {integrator!r}; expected one of {', '.join(INTEGRATORS)}",
                "integrator",
            )
        if not (np.isfinite(rtol) and 0.0 < rtol < 1.0):
            raise ModelError(f"rtol must be in (0, 1), got {rtol!r}", "rtol")
        return _solve_ivp(h1, h2, dt, mk, mub, building, floor, g, histories, rtol, integrator)
    raise ModelError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}", "method")


# -- components ------------------------------------------------------------------------------


def _components(fm1, fm2, mk, ms, dt, histories) -> Approximation:
    r1 = slide(fm1, None, mk, ms, histories=True)
    r2 = slide(fm2, None, mk, ms, histories=True)
    u = np.stack([r1.u, r2.u], axis=-1)  # (n, npts, 2)
    npts = u.shape[1]
    t = np.arange(npts) * dt
    mag = np.hypot(u[..., 0], u[..., 1])
    n = mk.size
    peak = np.zeros(n)
    angle = np.zeros(n)
    tpk = np.zeros(n)
    for i in range(n):
        j = int(np.argmax(mag[i]))
        best, vec, when = mag[i, j], u[i, j], t[j]
        # each component's own peak, inside a step (the other interpolated there)
        for c, res in ((0, r1), (1, r2)):
            tc = float(res.time_of_peak[i])
            if not np.isfinite(tc) or res.peak_slide[i] <= 0.0:
                continue
            other = float(np.interp(tc, t, u[i, :, 1 - c]))
            jn = min(round(tc / dt), npts - 1)
            sign = 1.0 if u[i, jn, c] >= 0.0 else -1.0
            cand = np.empty(2)
            cand[c], cand[1 - c] = sign * res.peak_slide[i], other
            m = float(np.hypot(*cand))
            if m > best or (m == best and tc < when):  # the first time of a held peak
                best, vec, when = m, cand, tc
        peak[i] = best
        angle[i] = math.degrees(math.atan2(vec[1], vec[0])) if best > 0 else 0.0
        tpk[i] = when
    nan = np.full(n, np.nan)
    return Approximation(
        peak_slide=peak,
        peak_angle=angle,
        time_of_peak=tpk,
        residual=u[:, -1, :].copy(),
        slide_fraction=nan,
        slip_phases=np.full(n, -1),
        stops=np.full(n, -1),
        path=nan.copy(),
        work_floor=nan.copy(),
        final_velocity=np.stack([r1.v[:, -1], r2.v[:, -1]], axis=-1),
        u=u if histories else None,
        peak_slide_1d=np.stack([r1.peak_slide, r2.peak_slide], axis=-1),
    )


# -- newmark: Moreau–Jean with the friction as a return map -----------------------------------


def _floor_samples(building, floor, h1, h2, dt, k):
    """The floor's absolute acceleration along x and y at the sub-steps ``dt/k``: the record
    joined by straight lines on the ground, the exact response of each direction's model on a
    floor."""
    bx, by = per_direction(building)
    out = []
    for b, a in ((bx, h1), (by, h2)):
        if b is not None and b.dof_of(floor) is not None:
            out.append(
                np.ascontiguousarray(floor_motions(b, a, dt, floors=[floor], oversample=k)[0])
            )
        elif k == 1:
            out.append(np.ascontiguousarray(a, dtype=float))
        else:
            t = np.arange((a.size - 1) * k + 1) / k
            out.append(np.interp(t, np.arange(a.size), a))
    return out[0], out[1]


@njit(cache=True)
def _return_map(a1, a2, k, h, g, mub, muk, out, hist, histories):
    """Every block (``mub``, ``muk``) by the Moreau–Jean scheme on the floor samples ``a1, a2``
    at sub-steps ``h`` (``k`` per record step); ``out`` columns as :data:`NCOL`, ``hist`` the
    slides at the record samples (when `histories`)."""
    n = a1.size
    for i in range(mub.size):
        fb = mub[i] * g * h
        fk = muk[i] * g * h
        ux = uy = vx = vy = 0.0
        peak = 0.0
        angle = 0.0
        tpk = 0.0
        slide_time = 0.0
        slips = 0
        stops = 0
        path = 0.0
        work = 0.0
        moving = False
        for j in range(1, n):
            # trial velocity without friction: the floor's impulse over the sub-step
            wx = vx - 0.5 * h * (a1[j - 1] + a1[j])
            wy = vy - 0.5 * h * (a2[j - 1] + a2[j])
            wn = math.hypot(wx, wy)
            if not moving:
                if wn <= fb:
                    # stuck: the friction needed is within the static limit
                    if histories and j % k == 0:
                        hist[i, j // k, 0] = ux
                        hist[i, j // k, 1] = uy
                    continue
                moving = True
                slips += 1
            # return map onto the friction disc: reduce |v*| by mu_k g h, or stop
            if wn > fk:
                s = 1.0 - fk / wn
                nx, ny = s * wx, s * wy
            else:
                nx = ny = 0.0
                moving = False
                stops += 1
            ux += 0.5 * h * (vx + nx)
            uy += 0.5 * h * (vy + ny)
            sp0 = math.hypot(vx, vy)
            sp1 = math.hypot(nx, ny)
            path += 0.5 * h * (sp0 + sp1)
            work += 0.5 * h * (a1[j - 1] * vx + a2[j - 1] * vy + a1[j] * nx + a2[j] * ny)
            slide_time += h
            vx, vy = nx, ny
            m = math.hypot(ux, uy)
            if m > peak:
                peak = m
                angle = math.atan2(uy, ux)
                tpk = j * h
            if histories and j % k == 0:
                hist[i, j // k, 0] = ux
                hist[i, j // k, 1] = uy
        out[i, PEAK] = peak
        out[i, ANGLE] = angle
        out[i, T_PEAK] = tpk
        out[i, UX] = ux
        out[i, UY] = uy
        out[i, VX] = vx
        out[i, VY] = vy
        out[i, SLIDE_TIME] = slide_time
        out[i, SLIPS] = slips
        out[i, STOPS] = stops
        out[i, PATH] = path
        out[i, WORK] = work


# -- solve_ivp ---------------------------------------------------------------------------------


def _systems(building, floor):
    """``(A, b, c, d)`` of the floor acceleration along x and y (``a_f = c·x + d a_g`` with
    ``x' = A x + b a_g``); empty states on the ground."""
    out = []
    for b in per_direction(building):
        if b is None or b.dof_of(floor) is None:
            out.append((np.zeros((0, 0)), np.zeros(0), np.zeros(0), 1.0))
            continue
        A, B = b.state_matrices()
        C, D, _ = b.output_matrices([floor], "acceleration")
        out.append((A, B[:, 0].copy(), C[0].copy(), float(D[0, 0])))
    return out


def _solve_ivp(h1, h2, dt, mk, mub, building, floor, g, histories, rtol, integrator):
    (A1, b1, c1, d1), (A2, b2, c2, d2) = _systems(building, floor)
    n1, n2 = A1.shape[0], A2.shape[0]
    npts = h1.size
    amax = max(float(np.hypot(h1, h2).max()), 1e-12)
    # absolute tolerances from the record's scales: a velocity gained in a step, and the
    # displacement it makes in a step (building states: displacements then velocities)
    vel, disp = amax * dt, amax * dt * dt
    xs = np.concatenate([np.full(n1 // 2, disp), np.full(n1 - n1 // 2, vel)])
    ys = np.concatenate([np.full(n2 // 2, disp), np.full(n2 - n2 // 2, vel)])
    scale = np.concatenate([xs, ys, [disp, disp, vel, vel, disp, amax * disp]])
    systems = ((A1, b1, c1, d1), (A2, b2, c2, d2))
    rows = []
    for i in range(mk.size):
        fk, fb = float(mk[i]) * g, float(mub[i]) * g
        v_stop = STOP_FACTOR * rtol * vel
        rows.append(
            _ivp_block(h1, h2, dt, fk, fb, systems, rtol, rtol * scale, v_stop, integrator,
                       histories)
        )  # fmt: skip
    duration = (npts - 1) * dt

    def col(j):
        return np.array([r[j] for r in rows], dtype=float)

    return Approximation(
        peak_slide=col(0),
        peak_angle=col(1),
        time_of_peak=col(2),
        residual=np.array([r[3] for r in rows]).reshape(mk.size, 2),
        slide_fraction=col(4) / duration if duration > 0 else np.zeros(mk.size),
        slip_phases=col(5).astype(int),
        stops=col(6).astype(int),
        path=col(7),
        work_floor=col(8),
        final_velocity=np.array([r[9] for r in rows]).reshape(mk.size, 2),
        u=np.stack([r[10] for r in rows]) if histories else None,
    )


def _check(sol, t: float) -> None:
    if not sol.success:
        raise SolverLimitError(f"solve_ivp failed at t = {t:g} s: {sol.message}", "rtol")


def _breakaway(a0x, a0y, sx, sy, lim2, t, dt):
    """First ``τ`` in ``[t, dt)`` where ``|a0 + s τ|²`` rises through ``lim2`` (a convex
    quadratic, below `lim2` at `t`: its larger root), or None."""
    S = sx * sx + sy * sy
    if S == 0.0:
        return None
    B = a0x * sx + a0y * sy
    C = a0x * a0x + a0y * a0y - lim2
    disc = B * B - S * C
    if disc < 0.0:
        return None
    root = math.sqrt(disc)
    tau = (root - B) / S if B <= 0.0 else -C / (B + root)
    if tau >= dt:
        return None
    return max(tau, t)


def _slide_field(floor_acc, xdot, fk, v_stop, n1, n, AX, c1, c2):
    """Right-hand side and Jacobian of a slide: ``y = [x, u, v, path, work]``, the floor's
    acceleration ``floor_acc(t, y)`` (building states ``x`` first, ``n`` of them, ``n1`` of the
    x direction), friction ``fk = mu_k g``; below the speed `v_stop` the friction's direction
    is blended (module docstring)."""
    UX, UY, VX, VY, PA, WA = range(n, n + 6)

    def rhs(tt, y):
        ax, ay = floor_acc(tt, y)
        vx, vy = y[VX], y[VY]
        sp = math.hypot(vx, vy)
        out = np.empty(y.size)
        if n:
            out[:n] = xdot(tt, y)
        if sp >= v_stop:
            nx, ny = vx / sp, vy / sp
        else:
            # below the stop speed (only on the way out of rest: a slower block
            # stops at the event below) the friction's direction goes linearly from
            # the direction of a start from rest, −a/|a|, to v/|v|: a continuous
            # field, with Coulomb's start −(|a| − mu_k g)·a/|a|
            am = math.hypot(ax, ay)
            w = 1.0 - sp / v_stop
            nx = vx / v_stop - (w * ax / am if am > 0.0 else 0.0)
            ny = vy / v_stop - (w * ay / am if am > 0.0 else 0.0)
        out[VX] = -ax - fk * nx
        out[VY] = -ay - fk * ny
        out[UX], out[UY] = vx, vy
        out[PA] = sp
        out[WA] = ax * vx + ay * vy
        return out

    def jac(tt, y):
        ax, ay = floor_acc(tt, y)
        vx, vy = y[VX], y[VY]
        sp = math.hypot(vx, vy)
        J = np.zeros((y.size, y.size))
        J[:n, :n] = AX
        J[UX, VX] = J[UY, VY] = 1.0
        J[VX, :n1] = -c1
        J[VY, n1:n] = -c2
        wx, wy = (vx / sp, vy / sp) if sp > 0.0 else (0.0, 0.0)
        if sp >= v_stop:  # ∂n/∂v = (I − v̂v̂ᵀ)/|v|
            f = -fk / sp
            J[VX, VX], J[VX, VY] = f * (1.0 - wx * wx), -f * wx * wy
            J[VY, VX], J[VY, VY] = -f * wx * wy, f * (1.0 - wy * wy)
        else:  # ∂n/∂v = (I + â v̂ᵀ)/v_stop
            am = math.hypot(ax, ay)
            bx, by = (ax / am, ay / am) if am > 0.0 else (0.0, 0.0)
            f = -fk / v_stop
            J[VX, VX], J[VX, VY] = f * (1.0 + bx * wx), f * bx * wy
            J[VY, VX], J[VY, VY] = f * by * wx, f * (1.0 + by * wy)
        J[PA, VX], J[PA, VY] = wx, wy
        J[WA, VX], J[WA, VY] = ax, ay
        J[WA, :n1] = vx * c1
        J[WA, n1:n] = vy * c2
        return J

    return rhs, jac


def _ivp_block(h1, h2, dt, fk, fb, systems, rtol, atol, v_stop, integrator, histories):
    """One block by solve_ivp, step by step; returns its peak, angle (deg), time of peak,
    residual, slide time, breakaways, stops, path, work, final velocity and history."""
    from scipy.integrate import solve_ivp  # SciPy's integrators: only when asked for

    (A1, b1, c1, d1), (A2, b2, c2, d2) = systems
    n1, n2 = A1.shape[0], A2.shape[0]
    n = n1 + n2
    UX, UY, VX, VY, PA, WA = range(n, n + 6)
    fb2 = fb * fb
    v_switch = SWITCH_SPEED * fk * dt
    AX = np.zeros((n, n))
    AX[:n1, :n1], AX[n1:, n1:] = A1, A2
    x = np.zeros(n)
    u = np.zeros(2)
    v = np.zeros(2)
    path = work = 0.0
    peak, angle, tpk = 0.0, 0.0, 0.0
    slide_time = 0.0
    slips = stops = 0
    moving = False
    npts = h1.size
    hist = np.zeros((npts, 2)) if histories else None

    def note(t_abs, ux, uy):
        nonlocal peak, angle, tpk
        m = math.hypot(ux, uy)
        if m > peak:
            peak, angle, tpk = m, math.degrees(math.atan2(uy, ux)), t_abs

    for k in range(npts - 1):
        t_k = k * dt
        g0x, g0y = float(h1[k]), float(h2[k])
        gsx, gsy = (float(h1[k + 1]) - g0x) / dt, (float(h2[k + 1]) - g0y) / dt

        def floor_acc(tt, xx, g0x=g0x, g0y=g0y, gsx=gsx, gsy=gsy):
            ax = d1 * (g0x + gsx * tt)
            ay = d2 * (g0y + gsy * tt)
            if n1:
                ax += float(c1 @ xx[:n1])
            if n2:
                ay += float(c2 @ xx[n1:n])
            return ax, ay

        def xdot(tt, xx, g0x=g0x, g0y=g0y, gsx=gsx, gsy=gsy):
            out = np.empty(n)
            out[:n1] = A1 @ xx[:n1] + b1 * (g0x + gsx * tt)
            out[n1:] = A2 @ xx[n1:n] + b2 * (g0y + gsy * tt)
            return out

        t = 0.0
        for _ in range(10_000):
            if t >= dt * (1.0 - 1e-12):
                break
            if not moving:
                ax, ay = floor_acc(t, x)
                if ax * ax + ay * ay > fb2:
                    moving = True
                    slips += 1
                    continue
                if n == 0:
                    tb = _breakaway(g0x, g0y, gsx, gsy, fb2, t, dt)
                    if tb is None:
                        break
                    t = tb
                    moving = True
                    slips += 1
                    continue

                def brk(tt, xx):
                    bx, by = floor_acc(tt, xx)
                    return bx * bx + by * by - fb2

                brk.terminal, brk.direction = True, 1.0
                sol = solve_ivp(
                    xdot, (t, dt), x, method=integrator, rtol=rtol, atol=atol[:n],
                    events=[brk], max_step=dt / 4,
                )  # fmt: skip
                _check(sol, t_k + t)
                x = sol.y[:, -1].copy()
                t = float(sol.t[-1])
                if sol.status == 1:
                    moving = True
                    slips += 1
                continue

            rhs, jac = _slide_field(floor_acc, xdot, fk, v_stop, n1, n, AX, c1, c2)

            def slowest(tt, y):
                return math.hypot(y[VX], y[VY]) - v_stop

            def turn(tt, y):
                return y[UX] * y[VX] + y[UY] * y[VY]

            slowest.terminal, slowest.direction = True, -1.0
            turn.terminal, turn.direction = False, -1.0
            events = [slowest, turn]
            sp0 = math.hypot(v[0], v[1])
            if sp0 > 0.0:
                # the velocity's component along its direction at the segment's start falls
                # through zero at a stop — |v| only touches zero, and an explicit method
                # chatters about it — or where the velocity has turned by a right angle (not
                # from rest, where the direction is still settling onto −a)
                ex, ey = v[0] / sp0, v[1] / sp0

                def along(tt, y, ex=ex, ey=ey):
                    return y[VX] * ex + y[VY] * ey

                along.terminal, along.direction = True, -1.0
                events.append(along)
            if t == 0.0 and 0.0 < sp0 < v_stop:
                ax, ay = floor_acc(t, x)
                if ax * ax + ay * ay <= fb2:
                    # barely moving at a sample with the floor within the limit: at rest
                    v[:] = 0.0
                    moving = False
                    continue
            y0 = np.concatenate([x, u, v, [path, work]])
            kw = {}
            method = integrator
            if integrator not in IMPLICIT:
                if sp0 < 2.0 * v_switch:
                    # the direction relaxes at the rate mu_k g/|v|: stiff at low speed
                    method = START_INTEGRATOR
                else:

                    def slow(tt, y):
                        return math.hypot(y[VX], y[VY]) - v_switch

                    slow.terminal, slow.direction = True, -1.0
                    events.append(slow)
            if method in IMPLICIT:
                kw["jac"] = jac
            sol = solve_ivp(
                rhs, (t, dt), y0, method=method, rtol=rtol, atol=atol, events=events, **kw
            )
            _check(sol, t_k + t)
            y = sol.y[:, -1]
            for te, ye in zip(sol.t_events[1], sol.y_events[1], strict=True):
                note(t_k + te, ye[UX], ye[UY])
            slide_time += float(sol.t[-1]) - t
            t = float(sol.t[-1])
            x = y[:n].copy()
            u = y[[UX, UY]].copy()
            v = y[[VX, VY]].copy()
            path, work = float(y[PA]), float(y[WA])
            note(t_k + t, u[0], u[1])
            if sol.status == 1 and (sol.t_events[0].size or math.hypot(v[0], v[1]) <= v_stop):
                # a stop (else the velocity turned: a new segment along its new direction)
                stops += 1
                v[:] = 0.0
                ax, ay = floor_acc(t, x)
                if ax * ax + ay * ay <= fb2:
                    moving = False
        else:  # pragma: no cover - a safety net
            raise SolverLimitError(
                f"solve_ivp: more than 10000 segments in the step at t = {t_k:g} s", "rtol"
            )
        if histories:
            hist[k + 1] = u
    return (peak, angle, tpk, u, slide_time, slips, stops, path, work, v, hist)
