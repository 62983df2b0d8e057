"""Approximate solvers of the 2-DOF sliding oscillator, kept for the accuracy-versus-cost study
(docs/design.md §6).

The model is the one of :mod:`floorslide.contents.oscillator` (per unit top mass: a top mass on a
spring of circular frequency ``w`` and damping ratio ``xi`` over a base of mass ratio
``r = m_base/m_top`` sliding on its floor under the normal force ``N = (1 + r)·g``; ``u`` is the
base slide relative to the floor, ``z`` the spring deformation, ``q = 2ξw z' + w² z``):

- stick: ``u' = 0``, ``z'' = −a_f − q``; the friction force needed, ``F = q − r a_f``, must stay
  within ``mu_s·N``;
- slip with sign ``s``: ``r (u'' + a_f) = q − s mu_k N`` and ``z'' = −q − a_f − u''``.

Two classical ways to integrate it approximately:

``newmark``
    Newmark's average-acceleration (trapezoid, γ = 1/2, β = 1/4) method on sub-steps
    ``h = dt/substeps`` for both phases, the state of each phase advanced as a linear system, with
    the stick/slip checks made at the sub-step ends only: a slip phase stops at the first sub-step
    whose velocity has changed sign (the velocity is set to zero there), a stuck base breaks away
    at the first sub-step whose friction demand exceeds the limit. The floor motion is sampled at
    ``h`` (exact samples of the building's response on a floor, the record joined by straight
    lines on the ground); peaks are read at the sub-steps. Switches are located to within one
    sub-step, so the error falls like ``h`` (Chopra 2012, §5.4; the stick/slip logic of
    Jibson 1993 applied to both masses).

``penalty``
    The regularised ("grip spring") formulation of Brochard & Gantenbein (1989): while stuck,
    the base is held by a stiff spring and dashpot to an anchor on the floor; when the spring
    force reaches ``mu_s·N`` the base slides with Coulomb friction ``mu_k·N``, and when its
    velocity vanishes it is gripped again (the anchor placed so that the force is continuous).
    The grip is a model error of its own — a stuck base still moves by ``F/k_g`` and follows the
    friction demand with a lag of order ``1/ω_g``, and the grip adds a spurious high-frequency
    mode (Brochard & Gantenbein's 55 Hz peak) — which vanishes as the grip stiffness grows, at
    the price of a stiff system. The building (on a floor), the object and the grip are
    integrated together by SciPy's ``solve_ivp`` (``LSODA`` or ``Radau``, at ``rtol``), with the
    phase switches and the extrema of ``u`` and ``z`` located as events. The grip is given by
    its frequency ``f_g``: the whole object (both masses) on the grip spring vibrates at ``f_g``
    (``k_g = (1 + r)(2π f_g)²`` per unit top mass) with damping ratio ``grip_damping``.

References
----------
Newmark, N. M. (1959). A method of computation for structural dynamics. *J. Eng. Mech. Div.*
ASCE 85(EM3), 67–94.
Chopra, A. K. (2012). *Dynamics of Structures*, 4th ed., §5.4 (average acceleration).
Jibson, R. W. (1993). Predicting earthquake-induced landslide displacements using Newmark's
sliding block analysis. *Transportation Research Record* 1411, 9–17.
Brochard, D., Gantenbein, F. (1989). Seismic response of a sliding structure. *Transactions
SMiRT 10*, vol. K2, 1147–1152.
Westermo, B., Udwadia, F. (1983). Periodic response of a sliding oscillator system to harmonic
excitation. *Earthquake Eng. Struct. Dyn.* 11, 135–146.
Hairer, E., Wanner, G. (1996). *Solving Ordinary Differential Equations II*, 2nd ed. (Radau IIA);
Petzold, L. (1983). Automatic selection of methods for solving stiff and nonstiff systems of
ordinary differential equations. *SIAM J. Sci. Stat. Comput.* 4(1), 136–148 (LSODA).
"""

from __future__ import annotations

import math
from operator import itemgetter

import numpy as np

from floorslide._jit import njit
from floorslide.building.model import LinearBuilding
from floorslide.building.motions import floor_motions
from floorslide.errors import ModelError

METHODS = ("newmark", "penalty")
INTEGRATORS = ("LSODA", "Radau", "BDF")
"""SciPy integrators of the penalty method (imported when it runs)."""


def slide_oscillator(
    a: np.ndarray,
    dt: float,
    mu_k: np.ndarray,
    mu_s: np.ndarray,
    w: float,
    xi: float,
    r: float,
    g: float,
    building: LinearBuilding | None,
    floor: int | None,
    method: str,
    substeps: int = 16,
    rtol: float = 1e-6,
    grip_frequency: float = 100.0,
    grip_damping: float = 0.1,
    integrator: str = "LSODA",
) -> np.ndarray:
    """The response of 2-DOF sliding oscillators by an approximate method.

    Inputs are validated by :func:`floorslide.contents.oscillator.slide_oscillator`, which
    dispatches here; see the module docstring for the methods.

    Parameters
    ----------
    a, dt
        Ground acceleration samples (m/s²) and their step (s); without `building`, the motion
        the object stands on.
    mu_k, mu_s
        Kinetic and static friction coefficients, one per object.
    w, xi, r
        Clamped-base circular frequency (rad/s), damping ratio and ``m_base/m_top``.
    g
        Gravity, m/s².
    building, floor
        The floor the object stands on (``None``: on `a` itself).
    method
        ``"newmark"`` or ``"penalty"``.
    substeps
        Newmark sub-steps per record step.
    rtol
        Relative tolerance of ``solve_ivp`` (penalty).
    grip_frequency, grip_damping
        Frequency (Hz) of the whole object on its grip spring and the grip's damping ratio
        (penalty).
    integrator
        ``"LSODA"`` (default), ``"Radau"`` or ``"BDF"`` (penalty).

    Returns
    -------
    ndarray
        ``(n_objects, 7)``: peak ``|u|``, residual ``u``, peak ``|z|`` (m), peak top and base
        absolute accelerations (m/s²), time spent sliding (s), number of slip phases.
    """
    if method not in METHODS:
        raise ModelError(f"unknown method {method!r}; expected exact or one of {METHODS}", "method")
    mub = np.maximum(mu_k, mu_s)
    on_floor = building is not None and building.dof_of(floor) is not None
    out = np.zeros((mu_k.size, 7))
    if method == "newmark":
        if int(substeps) != substeps or substeps < 1:
            raise ModelError(f"substeps must be an integer ≥ 1, got {substeps!r}", "substeps")
        k = int(substeps)
        if on_floor:
            af = floor_motions(building, a, dt, floors=[floor], oversample=k)[0]
        elif k > 1:
            af = np.interp(np.arange((a.size - 1) * k + 1) / k, np.arange(a.size), a)
        else:
            af = a
        newmark_kernel(np.ascontiguousarray(af), dt / k, w, xi, r, g, mub, mu_k, out)
        return out
    if not (np.isfinite(rtol) and 0 < rtol < 1):
        raise ModelError(f"rtol must be in (0, 1), got {rtol!r}", "rtol")
    if not (np.isfinite(grip_frequency) and grip_frequency > 0):
        raise ModelError(f"grip_frequency must be > 0 Hz, got {grip_frequency!r}", "grip_frequency")
    if not (np.isfinite(grip_damping) and grip_damping >= 0):
        raise ModelError(f"grip_damping must be ≥ 0, got {grip_damping!r}", "grip_damping")
    if integrator not in INTEGRATORS:
        raise ModelError(
            f"integrator must be one of {', '.join(INTEGRATORS)}, got {integrator!r}", "integrator"
        )
    if on_floor:
        A, B = building.state_matrices()
        b = np.ascontiguousarray(B[:, 0])
        Ca, Da, _ = building.output_matrices([floor], "acceleration")
        ca, da = np.ascontiguousarray(Ca[0]), float(Da[0, 0])
    else:
        A, b, ca, da = np.zeros((0, 0)), np.zeros(0), np.zeros(0), 1.0
    wg = 2 * math.pi * float(grip_frequency)
    kg = (1 + r) * wg**2
    cg = 2 * float(grip_damping) * (1 + r) * wg
    for i in range(mu_k.size):
        out[i] = _penalty_one(
            a, dt, np.ascontiguousarray(A), b, ca, da, w, xi, r, g, mub[i], mu_k[i], kg, cg,
            float(rtol), integrator,
        )  # fmt: skip
    return out


@njit(cache=True)
def newmark_kernel(af, h, w, xi, r, g, mub, muk, out):
    """Average-acceleration integration of 2-DOF sliding oscillators on the floor samples `af`
    (step `h`), stick/slip checked at the samples; ``out[i]`` as in :func:`slide_oscillator`.

    Each phase is linear: in stick ``z'' + 2ξw z' + w² z = −a_f``; in slip with sign ``s`` the
    spring obeys ``z'' + (1 + 1/r)(2ξw z' + w² z) = s f_k/r`` (the floor drops out) and the base
    ``u'' = −a_f + (q − s f_k)/r``; Newmark's average acceleration (total form, Chopra 2012,
    Table 5.4.2) advances ``z``, the trapezoid rule ``u``. After a switch the accelerations are
    recomputed from the new phase's equations at the current state.
    """
    c = 2.0 * xi * w
    k = w * w
    kf = 1.0 + 1.0 / r
    n = af.size
    for i in range(mub.size):
        fb = mub[i] * (1.0 + r) * g
        fk = muk[i] * (1.0 + r) * g
        u = 0.0
        v = 0.0
        z = 0.0
        zd = 0.0
        a0 = af[0]
        demand = r * a0
        mode = 0
        phases = 0
        if demand > fb:
            mode = -1
            phases = 1
        elif demand < -fb:
            mode = 1
            phases = 1
        if mode == 0:
            vd = 0.0
            zdd = -a0
            pk_base = abs(a0)
        else:
            s = float(mode)
            vd = -a0 - s * fk / r
            zdd = s * fk / r
            pk_base = abs(a0 + vd)
        pk_u = 0.0
        pk_z = 0.0
        pk_top = 0.0
        slip_time = 0.0
        for j in range(1, n):
            a1 = af[j]
            if mode == 0:
                cc = c
                kk = k
                p = -a1
            else:
                cc = kf * c
                kk = kf * k
                p = float(mode) * fk / r
            kh = kk + 2.0 * cc / h + 4.0 / (h * h)
            rhs = p + 4.0 / (h * h) * z + 4.0 / h * zd + zdd + cc * (2.0 / h * z + zd)
            z1 = rhs / kh
            zdd1 = 4.0 / (h * h) * (z1 - z) - 4.0 / h * zd - zdd
            zd1 = zd + 0.5 * h * (zdd + zdd1)
            q1 = c * zd1 + k * z1
            z = z1
            zd = zd1
            zdd = zdd1
            if mode == 0:
                demand = r * a1 - q1
                if demand > fb:
                    mode = -1
                elif demand < -fb:
                    mode = 1
                if mode != 0:
                    phases += 1
                    s = float(mode)
                    vd = -a1 + (q1 - s * fk) / r
                    zdd = -q1 - a1 - vd
            else:
                s = float(mode)
                vd1 = -a1 + (q1 - s * fk) / r
                v1 = v + 0.5 * h * (vd + vd1)
                u += h * v + 0.25 * h * h * (vd + vd1)
                slip_time += h
                v = v1
                vd = vd1
                if s * v <= 0.0:
                    # the base stopped inside this sub-step: stick, or slip the other way
                    v = 0.0
                    demand = r * a1 - q1
                    if demand > fb:
                        mode = -1
                    elif demand < -fb:
                        mode = 1
                    else:
                        mode = 0
                    if mode == 0:
                        vd = 0.0
                        zdd = -a1 - q1
                    else:
                        if float(mode) != s:
                            phases += 1
                        s = float(mode)
                        vd = -a1 + (q1 - s * fk) / r
                        zdd = -q1 - a1 - vd
            if abs(u) > pk_u:
                pk_u = abs(u)
            if abs(z) > pk_z:
                pk_z = abs(z)
            if abs(q1) > pk_top:
                pk_top = abs(q1)
            ab = abs(a1 + vd) if mode != 0 else abs(a1)
            if ab > pk_base:
                pk_base = ab
        out[i, 0] = pk_u
        out[i, 1] = u
        out[i, 2] = pk_z
        out[i, 3] = pk_top
        out[i, 4] = pk_base
        out[i, 5] = slip_time
        out[i, 6] = phases


@njit(cache=True)
def _penalty_rhs(t, y, mode, A, b, ca, da, acc, dt, w, xi, r, fk, kg, cg):
    """Right-hand side of building + object + grip; ``y = [x, u, v, z, z', e]`` with ``e`` the
    grip spring's deformation; the ground acceleration is the record's piecewise-linear
    function."""
    n = A.shape[0]
    npts = acc.size
    tk = t / dt
    k = int(tk)
    if k > npts - 2:
        k = npts - 2
    if k < 0:
        k = 0
    ag = acc[k] + (acc[k + 1] - acc[k]) * (tk - k)
    dy = np.empty(n + 5)
    af = da * ag
    for i in range(n):
        s_ = b[i] * ag
        for j in range(n):
            s_ += A[i, j] * y[j]
        dy[i] = s_
        af += ca[i] * y[i]
    v = y[n + 1]
    zd = y[n + 3]
    q = 2.0 * xi * w * zd + w * w * y[n + 2]
    if mode == 0:
        force = kg * y[n + 4] + cg * v
        de = v
    else:
        force = mode * fk
        de = 0.0
    vd = -af + (q - force) / r
    dy[n] = v
    dy[n + 1] = vd
    dy[n + 2] = zd
    dy[n + 3] = -q - af - vd
    dy[n + 4] = de
    return dy


def _root(g, dense, t0, t1, g0, g1):
    """A root of ``g(dense(t))`` in ``[t0, t1]`` where ``g`` changes sign between the step ends
    (brentq on the solver's interpolant; the secant of the end values when the interpolant
    does not bracket it — LSODA's can disagree with its own step ends, scipy issue #14480)."""
    f0, f1 = g(dense(t0)), g(dense(t1))
    if f0 * f1 < 0.0:
        from scipy.optimize import brentq

        return brentq(lambda tt: g(dense(tt)), t0, t1, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    return t0 + (t1 - t0) * (g0 / (g0 - g1)) if g0 != g1 else t1


def _penalty_one(a, dt, A, b, ca, da, w, xi, r, g, mub, muk, kg, cg, rtol, integrator):
    """One oscillator by the grip-spring (penalty) formulation, phase by phase.

    Each phase is integrated by SciPy's `integrator` stepping on its own (the object and the
    building together, the phase's constant Jacobian given), and the state is checked at every
    step: a phase switch (grip force reaching ``mu_s·N``, or the slip velocity vanishing) ends
    the phase at the located root; the extrema of ``u`` and ``z`` inside steps are located as
    the roots of ``u'`` and ``z'`` on the solver's interpolant. Returns the row of
    :func:`slide_oscillator`.
    """
    n = A.shape[0]
    fb = mub * (1.0 + r) * g
    fk = muk * (1.0 + r) * g
    t_end = (a.size - 1) * dt
    if a.size < 2:
        return np.array([0.0, 0.0, 0.0, 0.0, abs(da * a[0]), 0.0, 0.0])
    c2, w2 = 2.0 * xi * w, w * w
    atol = 1e-3 * rtol
    import scipy.integrate

    Solver = getattr(scipy.integrate, integrator)
    # offsets: a phase that starts on its switching surface (gripped at mu_k·N = mu_s·N, or
    # released at v = 0) must not end at once on rounding
    fb_event = fb * (1.0 + 1e-9)
    y = np.zeros(n + 5)
    mode = 0
    pk = np.zeros(4)  # |u|, |z|, |q| (top acceleration), |base acceleration|
    slip_time = 0.0
    phases = 0
    t = 0.0
    guard = 0
    max_phases = 10 * a.size + 1000

    def base_acc(yy, mode):
        force = kg * yy[n + 4] + cg * yy[n + 1] if mode == 0 else mode * fk
        return (c2 * yy[n + 3] + w2 * yy[n + 2] - force) / r

    def record(yy, mode):
        pk[0] = max(pk[0], abs(yy[n]))
        pk[1] = max(pk[1], abs(yy[n + 2]))
        pk[2] = max(pk[2], abs(c2 * yy[n + 3] + w2 * yy[n + 2]))
        pk[3] = max(pk[3], abs(base_acc(yy, mode)))

    record(y, mode)
    pk[3] = max(pk[3], abs(da * a[0]))
    while t < t_end and guard < max_phases:
        guard += 1
        md = float(mode)

        def fun(tt, yy, md=md):
            return _penalty_rhs(tt, yy, md, A, b, ca, da, a, dt, w, xi, r, fk, kg, cg)

        f0 = fun(t, np.zeros(n + 5))
        jac = np.empty((n + 5, n + 5))
        for j in range(n + 5):
            e = np.zeros(n + 5)
            e[j] = 1.0
            jac[:, j] = fun(t, e) - f0
        if mode == 0:

            def switch(yy):
                force = kg * yy[n + 4] + cg * yy[n + 1]
                return max(force, -force) - fb_event

            watch = (n + 3, n + 1)  # extrema of z and u
        else:

            def switch(yy, md=md):
                return -(md * yy[n + 1] + 1e-12)

            watch = (n + 3,)
        solver = Solver(fun, t, y, t_end, rtol=rtol, atol=atol, jac=(lambda tt, yy, jac=jac: jac))
        switched = False
        while solver.status == "running":
            t_old, y_old = solver.t, solver.y.copy()
            solver.step()
            if solver.status == "failed":
                raise ModelError(
                    f"{integrator} failed at t = {solver.t:.6g} s (penalty method)", "rtol"
                )
            t_new, y_new = solver.t, solver.y
            g_old, g_new = switch(y_old), switch(y_new)
            t_stop = t_new
            dense = None
            if g_old < 0.0 <= g_new:
                dense = solver.dense_output()
                t_stop = _root(switch, dense, t_old, t_new, g_old, g_new)
                switched = True
            for idx in watch:
                if y_old[idx] * y_new[idx] < 0.0:
                    if dense is None:
                        dense = solver.dense_output()
                    te = _root(itemgetter(idx), dense, t_old, t_new, y_old[idx], y_new[idx])
                    if te <= t_stop:
                        record(dense(te), mode)
            if switched:
                y = dense(t_stop)
                if mode != 0:
                    slip_time += t_stop - t
                t = t_stop
                record(y, mode)
                break
            record(y_new, mode)
            if mode != 0:
                slip_time += t_new - t_old
        if not switched:
            y = solver.y.copy()
            break
        if mode == 0:
            force_now = kg * y[n + 4] + cg * y[n + 1]
            mode = 1 if force_now > 0 else -1
            phases += 1
        else:
            # gripped again: the anchor is placed so that the force stays mu_k·N
            y[n + 1] = 0.0
            y[n + 4] = md * fk / kg
            mode = 0
    return np.array([pk[0], y[n], pk[1], pk[2], pk[3], slip_time, float(phases)])
