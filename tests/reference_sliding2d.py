"""Independent high-accuracy reference for a rigid block sliding in the plane (isotropic Coulomb
friction) under two horizontal floor-acceleration components.

Like ``tests/reference.py`` and ``tests/reference_rocking.py`` it shares no code with floorslide
(only the constant ``G``): SciPy's ``solve_ivp`` integrates each step of the piecewise-linear
record separately (the forcing is smooth inside a step), restarting at every sample and at every
event, which it locates as a terminal event on its dense output.

Model (SI, per unit mass). The floor absolute acceleration is ``a(t) = (a_x, a_y)``: each
component piecewise linear between the samples, or with ``floor_systems = ((A1, b1, c1, d1),
(A2, b2, c2, d2))`` the acceleration ``c_i·x_i + d_i a_gi`` of a linear building
``x_i' = A_i x_i + b_i a_gi`` (x from ground component 1, y from component 2), at rest at
``t = 0`` and integrated together with the block, or (for tests) an analytic callable. The
block moves by ``u = (u_x, u_y)`` relative to the floor, ``v = u'``; the normal force is ``g``.

* Stick (``v = 0``): the block stays stuck while ``|a| ≤ mu_b g``, ``mu_b = max(mu_s, mu_k)``,
  and breaks away at the first instant ``|a| > mu_b g`` (the terminal event
  ``|a|² - (mu_b g)²``, direction +1; for a record without buildings the root of this quadratic
  in closed form). A stick phase that begins with ``|a| > mu_b g`` (at ``t = 0``) slides at once.
* Slide: ``v' = -a - mu_k g v/|v|``. A stop is an instant ``|v| = 0``: the block sticks if
  ``|a| ≤ mu_b g`` there, else it slides on at once, starting in the direction ``-a/|a|``.

Formulation of a slide (why it is reliable at stops and at breakaway):

* Velocity in a rotating reference frame. Each slide segment fixes a unit vector ``d`` (the
  velocity direction at the segment start) and integrates ``v = p d + q d⊥``
  (``d⊥ = (-d_y, d_x)``) with the friction direction ``n = sign(p) v/|v|``. While ``p > 0`` this
  is ``v/|v|``; beyond ``p = 0`` it is its continuation through the stop (a block that reaches
  ``v = 0`` along a line keeps the same ``n``), so the right-hand side stays continuous across
  the stop and the *stop* is the smooth transversal crossing ``p = 0`` (terminal, direction -1).
  A second terminal event, *turn*, ``p - |v|/2`` (direction -1), fires when the velocity has
  turned 60° away from ``d``; the segment then restarts with ``d`` = the new direction. Hence a
  stop is only ever reported with ``p = 0`` *and* ``|q| ≤ √3 p`` ⇒ ``|v| = 0`` to the root
  finder's accuracy: it cannot be confused with the velocity merely turning through a right
  angle (checked: the largest ``|v|`` at a reported stop is returned as ``stop_speed_max``).
  Error control on the Cartesian components weights a direction error by ``|v|``, which is
  what the displacement feels; a polar form
  (``|v|``, angle) would not do: near a stop the angle behaves like ``(t_s - t)^κ``,
  ``κ = |a|/(mu_k g - |a|)``, with an O(1) amplitude.
* Start from rest (breakaway, or a stop with ``|a| > mu_b g``). ``v/|v|`` is undefined at
  ``v = 0``: an analytic first step of ``MINI_STEP = 1e-7`` s uses the asymptotics, with
  ``d = -a0/|a0|``, ``c0 = |a0| - mu_k g`` (0 at a breakaway with ``mu_s = mu_k``),
  ``ṡ = d|a|/dt`` and ``b⊥ = ȧ·d⊥``: along ``d``, ``p = c0 τ + ṡ τ²/2``; across,
  ``q' = -b⊥ τ - mu_k g q/(c0 τ)`` gives ``q = -b⊥ c0 τ²/(2 c0 + mu_k g)`` (0 in the tie case,
  where ``q = O(τ³)``); ``u`` gains their integrals, the floor states a Heun step, the work
  integrals their expansions. The neglected terms are O(τ³) in ``v`` (≈ 1e-20 m/s: measured,
  the sampled ``u`` of a 2-D El Centro run changes by 8e-13 of its peak with a first step of
  1e-5 s, ∝ τ³, and by 7e-15 with 1e-8 s). Since ``p' = -a·d - mu_k g`` does not depend on
  ``p``, an error in ``p`` is carried, not amplified (Coulomb friction is a monotone
  operator: two velocities under the same floor motion never move apart, for
  ``mu_s = mu_k``). At a breakaway with
  ``c0 = 0`` a touch (``ṡ ≤ 0``) does not start a slide.
* Stiffness at low speed. The direction relaxes at the rate ``mu_k g/|v|``: after a breakaway
  with ``mu_s = mu_k`` (``|v| ≈ ṡ τ²/2``) this is far beyond an explicit method's stability
  limit for a long time (``τ ≲ 2 mu_k g/ṡ``). A slide from rest is therefore integrated by
  SciPy's implicit ``Radau`` (``stiff_method``; L-stable, analytic Jacobian) until the terminal
  event ``|v| = R_SWITCH_FRACTION · mu_k g · dt``, then by ``DOP853`` down to its stop (near a
  stop ``|v| ≈ c (t_s - t)``: the stability limit shrinks with the remaining time, so the steps
  shrink geometrically, costly only if ``c ≪ mu_k g``; a stiff method there stalls on the
  non-smooth approach, see below). The state at a terminal event
  of a Radau segment is recomputed by re-integrating its last step to the event time (Radau's
  dense output is only of order 3). ``atol`` on ``(p, q)`` is
  ``min(atol, rtol · max(|v0|, 0.1 · R_SWITCH_FRACTION · mu_k g dt))`` (``|v0|`` the speed at
  the segment start): relative to the segment's speed, with a floor that keeps the error
  accumulated from the tiny start speeds below ``rtol`` times the speed a slide gains in a
  sample step (an absolute 1e-15 there moved results by 1e-9 relative).
* Rounding-level speeds. A turn found with ``|v| ≤ STOP_SPEED · g · dt`` (``≈ 1e-13`` m/s),
  and the terminal event ``|v| = STOP_SPEED · g · dt`` (direction -1), are stops: just before a
  stop the side component decays like a fractional power of ``t_s - t`` (the velocity can swing
  by up to 90° within a time below the resolution of ``t``), which no integrator resolves.
  Zeroing such a velocity changes ``u`` by at most that speed times the rest of the record
  (monotonicity again), ≤ 4e-12 m over 40 s.
* Peaks: ``max |u|`` over the segment ends and over the roots of ``d|u|²/dt = 2 u·v``
  (direction -1, non-terminal events located on the dense output, between the samples; like
  any sign-change detector it would miss a maximum and a minimum of ``|u|`` inside one
  integrator step, which at these tolerances is a small fraction of a sample step).
* Work integrals (per unit mass), accumulated with the state: ``work_friction = ∫ mu_k g |v|``
  and ``work_floor = ∫ a·v``; the energy balance ``|v|²/2 = -work_friction - work_floor`` then
  tests the integration, the resets at stops (``v ← 0``) and the analytic first steps.
* A safety cap ``max_events`` on breakaways, stops and turns raises a RuntimeError.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from scipy.integrate import solve_ivp

from floorslide.constants import G

MINI_STEP = 1e-7
"""Length (s) of the analytic first step of a slide from rest."""

R_SWITCH_FRACTION = 1.0 / 300.0
"""A slide from rest is integrated by the stiff method until the speed
``R_SWITCH_FRACTION · mu_k g · dt`` (beyond it DOP853 needs at most about 100 steps per record
step at its stability limit ``h ≈ 3 |v| / (mu_k g)``), by DOP853 after."""

STOP_SPEED = 1e-12
"""``|v| ≤ STOP_SPEED · g · dt`` during a slide is a stop (module docstring)."""

_END = 1e-14
"""A record step is finished once the local time reaches ``dt (1 - _END)``."""

_STICK, _SLIDE = 0, 1

FloorSystem = tuple[np.ndarray, np.ndarray, np.ndarray, float]


def _system(spec: Sequence) -> FloorSystem:
    A, b, c, d = spec
    A = np.atleast_2d(np.asarray(A, dtype=float))
    return A, np.asarray(b, dtype=float).ravel(), np.asarray(c, dtype=float).ravel(), float(d)


def _breakaway_root(
    ax0: float, ay0: float, sx: float, sy: float, thr2: float, t: float, dt: float
) -> float | None:
    """First instant in ``[t, dt)`` at which ``|a0 + s τ|² = thr2`` on the way up, or None.

    The quadratic is convex, and the block is stuck at ``t`` (``|a(t)|² ≤ thr2``), so the
    crossing is its larger root (computed without cancellation)."""
    S2 = sx * sx + sy * sy
    B = ax0 * sx + ay0 * sy
    C = ax0 * ax0 + ay0 * ay0 - thr2
    if S2 == 0.0:
        return None
    D = B * B - S2 * C
    if D < 0.0:
        return None
    sq = math.sqrt(D)
    if B >= 0.0:
        qq = -(B + sq)
        r2 = C / qq if qq != 0.0 else 0.0
    else:
        r2 = (-B + sq) / S2
    if r2 >= dt:
        return None
    return max(r2, t)


def _stick_segment(
    acc: Callable,
    xdot: Callable,
    x: np.ndarray,
    t: float,
    dt: float,
    thr2: float,
    n: int,
    rtol: float,
    atol: float,
) -> tuple[float, np.ndarray, bool]:
    """Stuck block on a floor driven by a building or an analytic acceleration: integrates the
    floor states (a dummy one without building) to the end of the step or to the breakaway
    ``|a|² - thr2`` (terminal, direction +1). Returns ``(t, x, broke_away)``."""

    def rhs(tt, yy):
        out = np.zeros(yy.size)
        out[:n] = xdot(tt, yy[:n])
        return out

    def brk(tt, yy):
        ax, ay = acc(tt, yy[:n])
        return ax * ax + ay * ay - thr2

    brk.terminal, brk.direction = True, 1.0
    y0 = np.append(x, 0.0)
    sol = solve_ivp(
        rhs,
        (t, dt),
        y0,
        method="DOP853",
        rtol=rtol,
        atol=atol,
        events=[brk],
        max_step=dt / 16 if n else np.inf,
    )
    if not sol.success:
        raise RuntimeError(f"slide2d_reference: solve_ivp failed: {sol.message}")
    return float(sol.t[-1]), sol.y[:n, -1].copy(), sol.status == 1


def slide2d_reference(
    acc_x: Sequence[float] | np.ndarray,
    acc_y: Sequence[float] | np.ndarray,
    dt: float,
    mu_k: float,
    mu_s: float | None = None,
    *,
    floor_systems: tuple[Sequence, Sequence] | None = None,
    accel: Callable[[float], tuple[float, float]] | None = None,
    accel_rate: Callable[[float], tuple[float, float]] | None = None,
    g: float = G,
    rtol: float = 1e-12,
    atol: float = 1e-15,
    max_events: int = 100_000,
    stiff_method: str = "Radau",
) -> dict:
    """Rigid block sliding in the plane on a floor, by DOP853 (Radau at the start of a slide)
    step by step with events.

    Parameters
    ----------
    acc_x, acc_y : array_like
        Ground (or, without ``floor_systems``, floor) acceleration samples of the two horizontal
        components (m/s²), piecewise linear between samples, same length ``npts ≥ 2``. With
        ``accel`` only their length is used (the sample grid of the outputs).
    dt : float
        Sample step (s).
    mu_k : float
        Kinetic friction coefficient (≥ 0).
    mu_s : float, optional
        Static coefficient, ``mu_k`` by default; the breakaway level is ``max(mu_s, mu_k) g``.
    floor_systems : pair of tuples, optional
        ``((A1, b1, c1, d1), (A2, b2, c2, d2))``: the x floor acceleration is
        ``c1·x1 + d1 acc_x`` with ``x1' = A1 x1 + b1 acc_x`` (at rest at ``t = 0``), the y one
        likewise from ``acc_y``.
    accel : callable, optional
        ``accel(t) -> (a_x, a_y)``, a smooth floor acceleration used instead of the records
        (for closed-form tests; no interpolation error). Exclusive with ``floor_systems``.
    accel_rate : callable, optional
        Its derivative, for the analytic first step of a slide from rest; by default a central
        difference (that step is 1e-7 s long: its O(τ²) terms are immaterial).
    g : float
        Gravity (m/s²).
    rtol, atol : float
        Tolerances of the integrators (``atol`` on the velocity is further limited relative to
        the speed at the start of a segment, module docstring).
    max_events : int
        Cap on breakaways + stops + turns (a RuntimeError beyond it).
    stiff_method : {"Radau", "BDF"}
        SciPy's implicit method for the start of a slide from rest.

    Returns
    -------
    dict
        ``u``, ``v`` (npts, 2) at the samples; ``peak`` (max |u| between the samples too),
        ``peak_angle`` (degrees, ``atan2(u_y, u_x)`` at the peak), ``t_peak``; ``residual``
        (u at the end); ``slide_time`` (s); ``slips`` (breakaways from stick, including one at
        ``t = 0``); ``stops`` (instants ``|v|`` reaches 0, whether the block then sticks or
        slides on); ``events`` (list of ``(t, kind)``, kind in "breakaway", "stick", "pass" —
        a stop at which the block slides on at once); ``work_friction``, ``work_floor``
        (npts,) at the samples; diagnostics ``turns`` (reference-frame changes),
        ``stop_speed_max`` (largest ``|v|`` found at a stop before it was zeroed) and
        ``stiff_segments``.
    """
    acc_x = np.asarray(acc_x, dtype=float).ravel()
    acc_y = np.asarray(acc_y, dtype=float).ravel()
    npts = acc_x.size
    if npts < 2 or acc_y.size != npts or not dt > 0.0:
        raise ValueError("slide2d_reference: need two records of equal length ≥ 2 and dt > 0")
    if stiff_method not in ("Radau", "BDF"):
        raise ValueError(f"slide2d_reference: unknown stiff_method {stiff_method!r}")
    if mu_k < 0.0:
        raise ValueError("slide2d_reference: mu_k must be ≥ 0")
    if accel is not None and floor_systems is not None:
        raise ValueError("slide2d_reference: accel and floor_systems are exclusive")
    mu_s = mu_k if mu_s is None else float(mu_s)
    muk = mu_k * g
    thr = max(mu_s, mu_k) * g
    thr2 = thr * thr
    r_switch = R_SWITCH_FRACTION * muk * dt
    v_stop = STOP_SPEED * g * dt

    if floor_systems is not None:
        A1, b1, c1, d1 = _system(floor_systems[0])
        A2, b2, c2, d2 = _system(floor_systems[1])
    else:
        A1 = A2 = np.zeros((0, 0))
        b1 = b2 = c1 = c2 = np.zeros(0)
        d1 = d2 = 1.0
    n1, n2 = A1.shape[0], A2.shape[0]
    n = n1 + n2
    AX = np.zeros((n, n))
    AX[:n1, :n1], AX[n1:, n1:] = A1, A2
    # state during a slide: [x1, x2, u_x, u_y, p, q, work_friction, work_floor]
    UX, UY, P, Q, WF, WA = n, n + 1, n + 2, n + 3, n + 4, n + 5
    N = n + 6

    x = np.zeros(n)
    u = np.zeros(2)
    vel = np.zeros(2)  # global velocity
    wf = wa = 0.0
    u_out = np.zeros((npts, 2))
    v_out = np.zeros((npts, 2))
    wf_out = np.zeros(npts)
    wa_out = np.zeros(npts)
    peak, peak_angle, t_peak = 0.0, 0.0, 0.0
    slips = stops = turns = nev = stiff_segments = 0
    stop_speed_max = 0.0
    sliding: list[float] = []
    events: list[tuple[float, str]] = []
    mode = _STICK
    refused = False  # a tie breakaway just refused (a touch): do not retry at once
    starting = False  # a slide from rest not yet at the switch speed: the stiff method
    from_stop = False  # the slide from rest follows a stop (not a breakaway from stick)

    def note_peak(t_abs: float, ux: float, uy: float) -> None:
        nonlocal peak, peak_angle, t_peak
        m = math.hypot(ux, uy)
        if m > peak:
            peak, peak_angle, t_peak = m, math.degrees(math.atan2(uy, ux)), t_abs

    def count_event() -> None:
        nonlocal nev
        nev += 1
        if nev > max_events:
            raise RuntimeError(
                f"slide2d_reference: more than {max_events} events (chattering?); "
                f"last {events[-4:]}"
            )

    for k in range(npts - 1):
        t_k = k * dt
        ax0, ax1 = float(acc_x[k]), float(acc_x[k + 1])
        ay0, ay1 = float(acc_y[k]), float(acc_y[k + 1])
        sx, sy = (ax1 - ax0) / dt, (ay1 - ay0) / dt

        def ground(tt: float, a0=ax0, a1=ax1, s=sx, b0=ay0, b1_=ay1, sb=sy) -> tuple[float, float]:
            """The two records in the step, exact at both samples."""
            if tt <= 0.5 * dt:
                return a0 + s * tt, b0 + sb * tt
            return a1 - s * (dt - tt), b1_ - sb * (dt - tt)

        if accel is not None:

            def acc(tt: float, xx: np.ndarray, t_k=t_k) -> tuple[float, float]:
                ax, ay = accel(t_k + tt)
                return float(ax), float(ay)

            def rate(tt: float, xx: np.ndarray, t_k=t_k) -> tuple[float, float]:
                if accel_rate is not None:
                    rx, ry = accel_rate(t_k + tt)
                    return float(rx), float(ry)
                h = 1e-6
                (px, py), (mx, my) = accel(t_k + tt + h), accel(t_k + tt - h)
                return (px - mx) / (2 * h), (py - my) / (2 * h)

            def xdot(tt: float, xx: np.ndarray) -> np.ndarray:
                return xx[:0]

        elif n == 0:

            def acc(tt: float, xx: np.ndarray, ground=ground) -> tuple[float, float]:
                return ground(tt)

            def rate(tt: float, xx: np.ndarray, sx=sx, sy=sy) -> tuple[float, float]:
                return sx, sy

            def xdot(tt: float, xx: np.ndarray) -> np.ndarray:
                return xx[:0]

        else:

            def xdot(tt: float, xx: np.ndarray, ground=ground) -> np.ndarray:
                gx, gy = ground(tt)
                out = np.empty(n)
                out[:n1] = A1 @ xx[:n1] + b1 * gx
                out[n1:] = A2 @ xx[n1:n] + b2 * gy
                return out

            def acc(tt: float, xx: np.ndarray, ground=ground) -> tuple[float, float]:
                gx, gy = ground(tt)
                return float(c1 @ xx[:n1]) + d1 * gx, float(c2 @ xx[n1:n]) + d2 * gy

            def rate(tt: float, xx: np.ndarray, xdot=xdot, sx=sx, sy=sy) -> tuple[float, float]:
                xd = xdot(tt, xx)
                return float(c1 @ xd[:n1]) + d1 * sx, float(c2 @ xd[n1:]) + d2 * sy

        t = 0.0
        if (
            mode == _STICK
            and n == 0
            and accel is None
            and max(ax0**2 + ay0**2, ax1**2 + ay1**2) < thr2
        ):
            # stuck on a floor inside the friction limit all step (|a|² is convex in the step)
            u_out[k + 1], v_out[k + 1] = u, 0.0
            wf_out[k + 1], wa_out[k + 1] = wf, wa
            continue

        for _ in range(100_000):
            if t >= dt * (1.0 - _END):
                break
            if mode == _STICK:
                ax, ay = acc(t, x)
                if ax * ax + ay * ay > thr2 and not refused:
                    mode, from_stop = _SLIDE, False  # from rest: the analytic start below
                    vel[:] = 0.0
                    continue
                refused = False
                if n == 0 and accel is None:
                    t_brk = _breakaway_root(ax0, ay0, sx, sy, thr2, t, dt)
                    t = dt if t_brk is None else t_brk
                else:
                    t, x, brk = _stick_segment(acc, xdot, x, t, dt, thr2, n, rtol, atol)
                    t_brk = t if brk else None
                if t_brk is not None and t < dt * (1.0 - _END):
                    mode, from_stop = _SLIDE, False
                    vel[:] = 0.0
                elif t_brk is not None:
                    t = dt  # a crossing at the sample: the next step starts stuck and decides
                continue

            # sliding
            if vel[0] == 0.0 and vel[1] == 0.0:
                # start from rest: analytic first step
                ax, ay = acc(t, x)
                am = math.hypot(ax, ay)
                rx, ry = rate(t, x)
                dx, dy = -ax / am, -ay / am
                sdot = -(dx * rx + dy * ry)  # d|a|/dt
                c0 = am - muk
                if c0 <= 1e-13 * max(muk, 1.0) and sdot <= 0.0:
                    mode = _STICK  # a touch of the limit with mu_s = mu_k: no slide
                    refused = True
                    continue
                c0 = max(c0, 0.0)
                tau = min(MINI_STEP, dt - t)
                s1 = c0 * tau + 0.5 * sdot * tau * tau
                s2 = 0.5 * c0 * tau * tau + sdot * tau**3 / 6.0
                if s1 <= 0.0:
                    raise RuntimeError(f"slide2d_reference: no start at t = {t_k + t:.12g} s")
                if n:  # Heun's step, second order
                    xd = xdot(t, x)
                    x = x + 0.5 * tau * (xd + xdot(t + tau, x + tau * xd))
                # the side component: q' = -(ȧ·d⊥) τ - mu_k g q/(c0 τ) ⇒ q = -(ȧ·d⊥) φ τ²
                den = 2.0 * c0 + muk
                phi = c0 / den if den > 0.0 else 0.5
                bq = -rx * dy + ry * dx  # ȧ·d⊥
                q1 = -bq * phi * tau * tau
                q2 = -bq * phi * tau**3 / 3.0
                u = u + np.array([s2 * dx - q2 * dy, s2 * dy + q2 * dx])
                wf += muk * s2
                wa += -am * s2 - sdot * c0 * tau**3 / 3.0
                vel[:] = s1 * dx - q1 * dy, s1 * dy + q1 * dx
                if not from_stop:
                    slips += 1
                    events.append((t_k + t, "breakaway"))
                    count_event()
                sliding.append(tau)
                t += tau
                starting = True
                continue

            r0 = math.hypot(vel[0], vel[1])
            dx, dy = vel[0] / r0, vel[1] / r0
            y0 = np.empty(N)
            y0[:n] = x
            y0[UX], y0[UY], y0[P], y0[Q], y0[WF], y0[WA] = u[0], u[1], r0, 0.0, wf, wa
            stiff = starting = starting and muk > 0.0 and r0 < r_switch

            def rhs(tt, yy, dx=dx, dy=dy, acc=acc, xdot=xdot):
                ax, ay = acc(tt, yy[:n])
                p, q = yy[P], yy[Q]
                r = math.hypot(p, q)
                if r > 0.0:
                    sg = 1.0 if p >= 0.0 else -1.0
                    fp, fq = sg * p / r, sg * q / r
                else:
                    sg, fp, fq = 1.0, 1.0, 0.0
                ap = ax * dx + ay * dy
                aq = -ax * dy + ay * dx
                out = np.empty(N)
                out[:n] = xdot(tt, yy[:n])
                out[UX] = p * dx - q * dy
                out[UY] = p * dy + q * dx
                out[P] = -ap - muk * fp
                out[Q] = -aq - muk * fq
                out[WF] = muk * sg * r
                out[WA] = ap * p + aq * q
                return out

            def jac(tt, yy, dx=dx, dy=dy, acc=acc):
                ax, ay = acc(tt, yy[:n])
                p, q = yy[P], yy[Q]
                r = math.hypot(p, q)
                J = np.zeros((N, N))
                J[:n, :n] = AX
                J[UX, P], J[UX, Q] = dx, -dy
                J[UY, P], J[UY, Q] = dy, dx
                # ∂(a_p, a_q)/∂x: a_x depends on x1 via c1, a_y on x2 via c2
                J[P, :n1], J[P, n1:n] = -dx * c1, -dy * c2
                J[Q, :n1], J[Q, n1:n] = dy * c1, -dx * c2
                vx, vy = p * dx - q * dy, p * dy + q * dx
                J[WA, :n1], J[WA, n1:n] = vx * c1, vy * c2
                J[WA, P], J[WA, Q] = ax * dx + ay * dy, -ax * dy + ay * dx
                if r > 0.0:
                    sg = 1.0 if p >= 0.0 else -1.0
                    wp, wq = p / r, q / r
                    f = -muk * sg / r
                    J[P, P], J[P, Q] = f * (1 - wp * wp), -f * wp * wq
                    J[Q, P], J[Q, Q] = -f * wp * wq, f * (1 - wq * wq)
                    J[WF, P], J[WF, Q] = muk * sg * wp, muk * sg * wq
                return J

            def ev_stop(tt, yy):
                return yy[P]

            def ev_turn(tt, yy):
                return yy[P] - 0.5 * math.hypot(yy[P], yy[Q])

            def ev_peak(tt, yy, dx=dx, dy=dy):
                vx = yy[P] * dx - yy[Q] * dy
                vy = yy[P] * dy + yy[Q] * dx
                return yy[UX] * vx + yy[UY] * vy

            def ev_floor(tt, yy):
                return math.hypot(yy[P], yy[Q]) - v_stop

            def ev_switch(tt, yy):
                return math.hypot(yy[P], yy[Q]) - r_switch

            ev_stop.terminal, ev_stop.direction = True, -1.0
            ev_turn.terminal, ev_turn.direction = True, -1.0
            ev_peak.terminal, ev_peak.direction = False, -1.0
            ev_floor.terminal, ev_floor.direction = True, -1.0
            ev_switch.terminal, ev_switch.direction = True, 1.0
            evs = [ev_stop, ev_turn, ev_peak, ev_floor] + ([ev_switch] if stiff else [])
            at = np.full(N, atol)
            at[P] = at[Q] = min(atol, rtol * max(r0, 0.1 * r_switch))
            kw = dict(rtol=rtol, atol=at)
            if stiff:
                kw.update(method=stiff_method, jac=jac)
                stiff_segments += 1
            else:
                kw.update(method="DOP853")
            sol = solve_ivp(rhs, (t, dt), y0, events=evs, **kw)
            if not sol.success:
                raise RuntimeError(f"slide2d_reference: solve_ivp failed: {sol.message}")
            t_end = float(sol.t[-1])
            y = sol.y[:, -1].copy()
            if stiff and sol.status == 1 and sol.t.size > 1:
                # recompute the event state to the implicit method's step accuracy: its last
                # step again, from the last accepted step end, ending at the event
                again = solve_ivp(rhs, (float(sol.t[-2]), t_end), sol.y[:, -2], **kw)
                y = again.y[:, -1].copy()
            for te, ye in zip(sol.t_events[2], sol.y_events[2], strict=True):
                if t < te <= t_end:
                    note_peak(t_k + te, ye[UX], ye[UY])
            sliding.append(t_end - t)
            t = t_end
            x = y[:n].copy()
            u = y[[UX, UY]].copy()
            wf, wa = float(y[WF]), float(y[WA])
            p, q = float(y[P]), float(y[Q])
            vel[:] = p * dx - q * dy, p * dy + q * dx
            note_peak(t_k + t, u[0], u[1])
            if sol.status != 1:
                continue
            hit = [bool(sol.t_events[i].size) for i in (0, 1, 3)]
            spd = math.hypot(p, q)
            if hit[1] and not hit[0] and not hit[2] and spd > v_stop:
                turns += 1
                count_event()
                continue
            if not any(hit):
                starting = False  # the switch to DOP853 (|v| at the level, ± rounding)
                continue
            # a stop
            if hit[0]:
                stop_speed_max = max(stop_speed_max, spd)
            stops += 1
            count_event()
            vel[:] = 0.0
            starting = False
            ax, ay = acc(t, x)
            if ax * ax + ay * ay > thr2:
                events.append((t_k + t, "pass"))  # slides on at once (from rest, above)
                from_stop = True
            else:
                events.append((t_k + t, "stick"))
                mode = _STICK
        else:
            raise RuntimeError(f"slide2d_reference: no progress in step {k}")
        u_out[k + 1] = u
        v_out[k + 1] = vel
        wf_out[k + 1], wa_out[k + 1] = wf, wa

    return {
        "u": u_out,
        "v": v_out,
        "peak": peak,
        "peak_angle": peak_angle,
        "t_peak": t_peak,
        "residual": u_out[-1].copy(),
        "slide_time": math.fsum(sliding),
        "slips": slips,
        "stops": stops,
        "events": events,
        "work_friction": wf_out,
        "work_floor": wa_out,
        "turns": turns,
        "stop_speed_max": stop_speed_max,
        "stiff_segments": stiff_segments,
    }
