"""Independent high-accuracy reference for a rigid block that slides, rocks, or both
(design §10g; Shenton & Jones 1991, Shenton 1996).

Like ``tests/reference_rocking.py`` it shares no code with floorslide (only the constant ``G``):
SciPy's DOP853 integrates each step of the piecewise-linear record separately (the forcing is
smooth inside a step), restarting at every sample and at every event, which ``solve_ivp``
locates as a terminal event on its dense output.

Model (SI, per unit mass). Full width ``width = 2b``, full height ``height = 2h``, centre of
mass at the centre; ``R = sqrt(b² + h²)``, ``alpha = atan(b/h)``, ``p² = 3 g / (4 R)``,
``lam = b/h``. ``θ > 0`` is clockwise (the top moving +x), about the corner ``s = +1`` (the +x
corner, which a negative floor acceleration lifts onto); ``u = alpha s - θ``. ``U`` is the
slide (the upright position's displacement relative to the floor, +x), ``V = U'`` the contact
corner's velocity relative to the floor while rocking, ``σ`` the slip direction. The state is
``[x (building), θ, θ', U, U', W_floor, W_friction]``; the two works are integrated with the
motion as quadratures.

* rest: ``θ = 0``, ``U' = 0`` (``F = a_f``, ``N = g``);
* slide: ``U'' = -a_f - σ mu_k g``;
* rock (corner stuck): ``θ'' = -p² (sin u + (a_f/g) cos u)``, ``F = a_f + R (cos u θ')'``,
  ``N = g + R (sin u θ')'``;
* slide-rock: ``w = sin u - σ mu_k cos u``,
  ``θ'' = -w (g - R cos u θ'²) / (R (1/3 + w sin u))``, ``N = g + R (sin u θ')'``,
  ``F = -σ mu_k N``, ``U'' = F - R (cos u θ')' - a_f``;

with ``(cos u θ')' = cos u θ'' + sin u θ'²`` and ``(sin u θ')' = sin u θ'' - cos u θ'²``.

Rules (§10g; the contract shared with floorslide's solver):

* From rest, at an instant with ``A = |a_f|`` and ``s = σ = -sign a_f``: rest while
  ``A ≤ g min(mu_s, lam)``; beyond, slide if ``mu_s < lam``; else rock if ``mu_s ≥ μ_c(A)``
  (``μ_c = (a (4 lam² + 1) + 3 lam) / (lam² + 4 + 3 a lam)``, ``a = A/g``); else slide-rock if
  ``mu_k > lam``; else slide. A rest ends at the terminal events ``±a_f - g min(mu_s, lam)``
  (direction +1), where ``A`` equals the level: a block with ``mu_s < lam`` slides, one with
  ``mu_s ≥ lam`` rocks (``μ_c(lam) = lam``). One found at the very end of a record step with
  the floor not strictly beyond the level (a record that touches it at a sample) does not
  end the rest there: the next step decides. A rest that begins with the floor beyond the level
  (the record's start, a stop, an impact to rest) is classified at once.
* Slide stop: ``σ U'`` back to 0 (terminal, direction -1): ``U' = 0`` and the from-rest rule.
* Rock → slide-rock: ``mu_s N ∓ F`` reaching 0 (terminal, direction -1): ``σ = -sign F``,
  ``V = 0``. A rock phase that begins beyond the limit (after an impact) slips at once.
* Slide-rock → rock: ``σ V`` back to 0 (terminal): ``V = 0``; the stuck corner's ``F`` and
  ``N`` (the rock equations) decide: rock if ``|F| ≤ mu_s N``, else slip on with
  ``σ = -sign F``.
* Impact (rock or slide-rock, ``s θ`` back to 0, terminal): Housner's rough impact about the new
  corner, ``θ'⁺ = r θ'⁻ + (3 cos(alpha) / (4 R)) V⁻``, ``U' = 0``, ``s ← -s`` in rock (then the
  friction check at once); ``s θ'⁺ ≤ REST_VELOCITY · p · alpha`` (too small, or the wrong sign)
  ends in rest (then the from-rest rule). ``W_impacts`` accumulates the kinetic energy lost.
* Overturning: ``s θ = alpha`` (terminal); the samples after it are NaN, mode code 4.
* Free flight (``N`` reaching 0) and the Painlevé case (``1/3 + w sin u ≤ 0.01``) raise
  ``RuntimeError`` naming the time.
* A phase that starts on its own event surface (``θ = 0``, ``θ' = 0``, ``U' = 0``) has that
  event divided by ``(t - t0)`` (first derivative nonzero at ``t0``) or ``(t - t0)²``, with the
  limit at ``t0`` (clamped at 0 on the side of no crossing) as its value there: ``solve_ivp``
  would otherwise see the exact zero at ``t0`` as a crossing.
* The state at a terminal event is integrated anew from the phase's start to the event's time
  (the dense output that located it is an order less accurate than DOP853's steps).
* Peaks: ``max |θ|`` over the segment ends and the roots of ``θ'`` (non-terminal events);
  ``max |U|`` over the segment ends (``U`` is monotone within a slide or slide-rock segment,
  whose ends are the roots of ``U'``).
* Energy per unit mass in the floor's frame,
  ``E = ½ v_c² + (R²/6) θ'² + g (y_c - h)``: ``E_end - E_0 = W_floor - W_friction - W_impacts``
  with ``W_floor = -∫ a_f x_c' dt`` and ``W_friction = ∫ mu_k N |U'| dt``.
* A safety cap ``max_events`` (terminal events in the whole record) raises a RuntimeError.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from scipy.integrate import solve_ivp

from floorslide.constants import G

REST_VELOCITY = 1e-12
"""After an impact, ``s θ' ≤ REST_VELOCITY · p · alpha`` brings the block to rest."""

PAINLEVE = 0.01
"""Slide-rock is refused where ``1/3 + w sin u`` falls to this value."""

_END = 1e-14
"""A record step is finished once the local time reaches ``dt (1 - _END)``."""

REST, SLIDE, ROCK, SLIDE_ROCK, OVERTURNED = 0, 1, 2, 3, 4
NAMES = ("rest", "slide", "rock", "slide-rock", "overturn")


def critical_friction(a: float, lam: float) -> float:
    """Friction that pure rocking needs at its onset from rest (Shenton 1996).

    Parameters
    ----------
    a : float
        Floor acceleration over g, ``|a_f|/g``.
    lam : float
        Aspect ratio ``b/h``.

    Returns
    -------
    float
        ``μ_c = (a (4 lam² + 1) + 3 lam) / (lam² + 4 + 3 a lam)``.
    """
    return (a * (4.0 * lam * lam + 1.0) + 3.0 * lam) / (lam * lam + 4.0 + 3.0 * a * lam)


def _from_zero(
    ev: Callable[[float, np.ndarray], float], t0: float, order: int, limit: float
) -> Callable[[float, np.ndarray], float]:
    """``ev(t, y) / (t - t0)**order``, valued ``limit`` at ``t0``: an event function of a phase
    that starts from an exact zero of ``ev``, with the same roots after ``t0``."""

    def h(tt: float, yy: np.ndarray) -> float:
        return limit if tt <= t0 else ev(tt, yy) / (tt - t0) ** order

    h.terminal = getattr(ev, "terminal", False)  # type: ignore[attr-defined]
    h.direction = getattr(ev, "direction", 0.0)  # type: ignore[attr-defined]
    return h


def _event(fun: Callable, terminal: bool, direction: float) -> Callable:
    fun.terminal = terminal  # type: ignore[attr-defined]
    fun.direction = direction  # type: ignore[attr-defined]
    return fun


def slide_rock_reference(
    acc: Sequence[float] | np.ndarray,
    dt: float,
    width: float,
    height: float,
    mu_k: float,
    mu_s: float | None = None,
    restitution: float | None = None,
    floor_system: tuple | None = None,
    *,
    g: float = G,
    rtol: float = 1e-13,
    atol: float = 1e-16,
    max_events: int = 100_000,
) -> dict:
    """One block that slides, rocks or both on a floor, by DOP853 step by step with events.

    Parameters
    ----------
    acc : array_like
        Ground acceleration samples (m/s²), piecewise linear between samples.
    dt : float
        Sample step (s).
    width, height : float
        Full base width ``2b`` and full height ``2h`` (m).
    mu_k : float
        Kinetic friction coefficient.
    mu_s : float, optional
        Static friction coefficient, ``≥ mu_k`` (default ``mu_k``).
    restitution : float, optional
        ``r`` of the impact rule, in [0, 1]; by default Housner's ``1 - 1.5 sin²(alpha)``.
    floor_system : tuple, optional
        ``(A, b, c, d)``: a building ``x' = A x + b a_g`` at rest at ``t = 0`` whose floor
        acceleration is ``a_f = c·x + d a_g`` (one-way coupling). Without it ``a_f = a_g``.
    g : float
        Gravity (m/s²).
    rtol, atol : float
        Tolerances of DOP853.
    max_events : int
        Cap on the terminal events of the whole record (a RuntimeError beyond it).

    Returns
    -------
    dict
        ``theta``, ``slide`` (``U``), ``mode`` (codes 0 rest, 1 slide, 2 rock, 3 slide-rock,
        4 overturned, after the events at each sample) at the samples (NaN after overturning);
        ``peak_slide``, ``residual_slide`` (NaN if overturned), ``peak_ratio`` (1.0 if
        overturned), ``overturned``, ``overturn_time`` (s or NaN), ``impacts``, ``mode_time``
        (s in rest, slide, rock, slide-rock), ``energy`` (dict ``delta_E``, ``W_floor``,
        ``W_friction``, ``W_impacts``), ``alpha``, ``p``, ``r``, ``lam`` and ``events`` (list of
        ``(t, kind)``; kind a mode's name entered, "impact", or "stick" for a slide-rock whose
        slip stops).
    """
    acc = np.asarray(acc, dtype=float).ravel()
    npts = acc.size
    if npts < 2 or not dt > 0.0:
        raise ValueError("slide_rock_reference: need at least 2 samples and dt > 0")
    if not (width > 0.0 and height > 0.0):
        raise ValueError("slide_rock_reference: width and height must be positive")
    mu_s = float(mu_k) if mu_s is None else float(mu_s)
    mu_k = float(mu_k)
    if not 0.0 <= mu_k <= mu_s:
        raise ValueError("slide_rock_reference: need 0 <= mu_k <= mu_s")
    b, h = width / 2.0, height / 2.0
    alpha = math.atan2(b, h)
    lam = b / h
    R = math.hypot(b, h)
    p2 = 3.0 * g / (4.0 * R)
    p = math.sqrt(p2)
    r = 1.0 - 1.5 * math.sin(alpha) ** 2 if restitution is None else float(restitution)
    if not 0.0 <= r <= 1.0:
        raise ValueError("slide_rock_reference: restitution must be in [0, 1]")
    level = g * min(mu_s, lam)
    v_rest = REST_VELOCITY * p * alpha
    k_imp = 3.0 * math.cos(alpha) / (4.0 * R)

    if floor_system is None:
        Am, bv, cv, dd = np.zeros((0, 0)), np.zeros(0), np.zeros(0), 1.0
    else:
        Am, bv, cv, dd = floor_system
        Am = np.atleast_2d(np.asarray(Am, dtype=float))
        bv = np.asarray(bv, dtype=float).ravel()
        cv = np.asarray(cv, dtype=float).ravel()
        dd = float(dd)
    n = Am.shape[0]
    TH, TD, UU, UD, WF, WR = n, n + 1, n + 2, n + 3, n + 4, n + 5

    def dynamics(mode: int, s: float, sg: float, th: float, td: float, ud: float, af: float):
        """``(θ'', U'', N, F, x_c')`` of the mode; for slide-rock also checks Painlevé."""
        if mode == REST:
            return 0.0, 0.0, g, af, 0.0
        if mode == SLIDE:
            return 0.0, -af - sg * mu_k * g, g, -sg * mu_k * g, ud
        u = alpha * s - th
        su, cu = math.sin(u), math.cos(u)
        if mode == ROCK:
            tdd = -p2 * (su + af / g * cu)
            N = g + R * (su * tdd - cu * td * td)
            F = af + R * (cu * tdd + su * td * td)
            return tdd, 0.0, N, F, R * cu * td
        w = su - sg * mu_k * cu
        den = 1.0 / 3.0 + w * su
        tdd = -w * (g - R * cu * td * td) / (R * den)
        N = g + R * (su * tdd - cu * td * td)
        F = -sg * mu_k * N
        udd = F - R * (cu * tdd + su * td * td) - af
        return tdd, udd, N, F, ud + R * cu * td

    def energy(y: np.ndarray, mode: int, s: float) -> float:
        th, td, ud = y[TH], y[TD], y[UD]
        if mode in (REST, SLIDE):
            return 0.5 * ud * ud
        u = alpha * s - th
        vx = ud + R * math.cos(u) * td
        vy = R * math.sin(u) * td
        return 0.5 * (vx * vx + vy * vy) + R * R / 6.0 * td * td + g * (R * math.cos(u) - h)

    def from_rest(af: float, crossing: bool) -> int:
        A = abs(af)
        if not crossing and A <= level:
            return REST
        if mu_s < lam:
            return SLIDE
        if crossing:
            return ROCK
        if mu_s >= critical_friction(A / g, lam):
            return ROCK
        return SLIDE_ROCK if mu_k > lam else SLIDE

    y = np.zeros(n + 6)
    mode, s, sg = REST, 1.0, 1.0
    theta_out = np.full(npts, np.nan)
    slide_out = np.full(npts, np.nan)
    mode_out = np.full(npts, OVERTURNED, dtype=int)
    peak_th = peak_u = 0.0
    impacts = nev = 0
    w_imp = 0.0
    times: list[list[float]] = [[], [], [], []]
    overturned = False
    t_over = math.nan
    events: list[tuple[float, str]] = []

    def enter(new: int, t_abs: float) -> None:
        events.append((t_abs, NAMES[new]))

    for k in range(npts - 1):
        a0, a1 = float(acc[k]), float(acc[k + 1])
        sl = (a1 - a0) / dt
        t = 0.0

        def ground(tt: float, a0: float = a0, a1: float = a1, sl: float = sl) -> float:
            """The record in the step, exact at both samples."""
            return a0 + sl * tt if tt <= 0.5 * dt else a1 - sl * (dt - tt)

        def floor(tt: float, yy: np.ndarray, ground=ground) -> float:
            return float(cv @ yy[:n]) + dd * ground(tt)

        while True:
            if nev > max_events:
                raise RuntimeError(
                    f"slide_rock_reference: more than {max_events} events by "
                    f"t = {k * dt + t:.9g} s; last {events[-4:]}"
                )
            t_abs = k * dt + t
            af = floor(t, y)
            # instantaneous rules at the start of a phase
            if mode == REST:
                new = from_rest(af, crossing=False)
                if new != REST:
                    mode = new
                    s = sg = -1.0 if af > 0.0 else 1.0
                    nev += 1
                    enter(mode, t_abs)
                    continue
                if n == 0 and t == 0.0 and max(abs(a0), abs(a1)) < level:
                    times[REST].append(dt)  # at rest on a floor inside the level (linear)
                    break
            elif mode == ROCK:
                _, _, N, F, _ = dynamics(ROCK, s, sg, y[TH], y[TD], 0.0, af)
                if abs(F) > mu_s * N:
                    mode, sg = SLIDE_ROCK, (-1.0 if F > 0.0 else 1.0)
                    nev += 1
                    enter(mode, t_abs)
                    continue
            if mode == SLIDE_ROCK:
                u = alpha * s - y[TH]
                w = math.sin(u) - sg * mu_k * math.cos(u)
                if 1.0 / 3.0 + w * math.sin(u) <= PAINLEVE:
                    raise RuntimeError(f"slide_rock_reference: Painlevé case at t = {t_abs:.9g} s")

            m_, s_, sg_ = mode, s, sg

            def rhs(tt, yy, m_=m_, s_=s_, sg_=sg_, ground=ground, floor=floor):
                out = np.zeros(n + 6)
                out[:n] = Am @ yy[:n] + bv * ground(tt)
                if m_ == REST:
                    return out
                af = floor(tt, yy)
                tdd, udd, N, _, xcd = dynamics(m_, s_, sg_, yy[TH], yy[TD], yy[UD], af)
                out[TH] = yy[TD]
                out[TD] = tdd
                out[UU] = yy[UD]
                out[UD] = udd
                out[WF] = -af * xcd
                if m_ in (SLIDE, SLIDE_ROCK):
                    out[WR] = mu_k * N * abs(yy[UD])
                return out

            def accel(tt, yy, m_=m_, s_=s_, sg_=sg_, floor=floor):
                return dynamics(m_, s_, sg_, yy[TH], yy[TD], yy[UD], floor(tt, yy))

            if mode == REST:
                evs = [
                    _event(lambda tt, yy, floor=floor: floor(tt, yy) - level, True, 1.0),
                    _event(lambda tt, yy, floor=floor: -floor(tt, yy) - level, True, 1.0),
                ]
            elif mode == SLIDE:
                stop = _event(lambda tt, yy, sg_=sg_: sg_ * yy[UD], True, -1.0)
                if y[UD] == 0.0:
                    d1 = sg * accel(t, y)[1]
                    stop = _from_zero(stop, t, 1, d1) if d1 > 0.0 else _from_zero(stop, t, 2, 0.0)
                evs = [stop]
            else:
                impact = _event(lambda tt, yy, s_=s_: s_ * yy[TH], True, -1.0)
                over = _event(lambda tt, yy, s_=s_: s_ * yy[TH] - alpha, True, 1.0)
                still = _event(lambda tt, yy: yy[TD], False, 0.0)
                lift = _event(lambda tt, yy, accel=accel: accel(tt, yy)[2], True, -1.0)
                tdd0 = accel(t, y)[0]
                if y[TH] == 0.0:  # the phase starts on its impact surface
                    if y[TD] != 0.0:
                        impact = _from_zero(impact, t, 1, s * y[TD])
                    else:
                        impact = _from_zero(impact, t, 2, max(s * tdd0 / 2.0, 0.0))
                if y[TD] == 0.0:
                    still = _from_zero(still, t, 1, tdd0)
                evs = [impact, over, lift, still]
                if mode == ROCK:
                    evs += [
                        _event(
                            lambda tt, yy, accel=accel: mu_s * accel(tt, yy)[2] - accel(tt, yy)[3],
                            True,
                            -1.0,
                        ),
                        _event(
                            lambda tt, yy, accel=accel: mu_s * accel(tt, yy)[2] + accel(tt, yy)[3],
                            True,
                            -1.0,
                        ),
                    ]
                else:

                    def painleve(tt, yy, s_=s_, sg_=sg_):
                        u = alpha * s_ - yy[TH]
                        w = math.sin(u) - sg_ * mu_k * math.cos(u)
                        return 1.0 / 3.0 + w * math.sin(u) - PAINLEVE

                    slip = _event(lambda tt, yy, sg_=sg_: sg_ * yy[UD], True, -1.0)
                    if y[UD] == 0.0:
                        d1 = sg * accel(t, y)[1]
                        slip = (
                            _from_zero(slip, t, 1, d1) if d1 > 0.0 else _from_zero(slip, t, 2, 0.0)
                        )
                    evs += [slip, _event(painleve, True, -1.0)]

            sol = solve_ivp(rhs, (t, dt), y, method="DOP853", rtol=rtol, atol=atol, events=evs)
            if not sol.success:
                raise RuntimeError(f"slide_rock_reference: solve_ivp failed: {sol.message}")
            t_end = float(sol.t[-1])
            if sol.status == 1 and t_end > t:
                # the state at the event from a run that ends there (the dense output that
                # located it is an order less accurate than the steps)
                y = (
                    solve_ivp(rhs, (t, t_end), y, method="DOP853", rtol=rtol, atol=atol)
                    .y[:, -1]
                    .copy()
                )
            else:
                y = sol.y[:, -1].copy()
            times[mode].append(t_end - t)
            if mode in (ROCK, SLIDE_ROCK):
                for te, ye in zip(sol.t_events[3], sol.y_events[3], strict=True):
                    if te > t:
                        peak_th = max(peak_th, abs(ye[TH]))
                peak_th = max(peak_th, abs(y[TH]))
            peak_u = max(peak_u, abs(y[UU]))
            t = t_end
            t_abs = k * dt + t
            fired = [i for i, te in enumerate(sol.t_events) if te.size and evs[i].terminal]
            if sol.status == 0:
                # a phase that ends (without an event) on the wrong side of its surface
                if mode in (ROCK, SLIDE_ROCK) and s * y[TH] < 0.0:
                    if abs(y[TH]) > 1e-12 * alpha:
                        raise RuntimeError(
                            f"slide_rock_reference: the block sank at t = {t_abs:.9g} s"
                        )
                    y[TH] = y[TD] = y[UD] = 0.0
                    mode = REST
                    enter(mode, t_abs)
            else:
                nev += 1
                af = floor(t, y)
                if mode == REST:
                    if abs(af) <= level and t >= dt * (1.0 - _END):
                        pass  # the floor reaches the level at the sample: the next step decides
                    else:
                        side = -1.0 if fired[0] == 0 else 1.0
                        mode = from_rest(-side * level, crossing=True)
                        s = sg = side
                        enter(mode, t_abs)
                elif mode == SLIDE:
                    y[UD] = 0.0
                    mode = REST
                    enter(mode, t_abs)
                elif 1 in fired:  # overturning
                    overturned = True
                    t_over = t_abs
                    enter(OVERTURNED, t_abs)
                    break
                elif 2 in fired:
                    raise RuntimeError(
                        f"slide_rock_reference: free flight (N = 0) at t = {t_abs:.9g} s"
                    )
                elif mode == SLIDE_ROCK and 5 in fired:
                    raise RuntimeError(f"slide_rock_reference: Painlevé case at t = {t_abs:.9g} s")
                elif 0 in fired:  # impact about the new corner
                    before = energy(y, mode, s)
                    y[TH] = 0.0
                    after_v = r * y[TD] + k_imp * y[UD]
                    y[UD] = 0.0
                    s = -s
                    impacts += 1
                    events.append((t_abs, "impact"))
                    if s * after_v <= v_rest:
                        y[TD] = 0.0
                        w_imp += before
                        mode = REST
                        enter(mode, t_abs)
                    else:
                        y[TD] = after_v
                        w_imp += before - energy(y, ROCK, s)
                        if mode != ROCK:
                            mode = ROCK
                            enter(mode, t_abs)
                elif mode == ROCK:  # the friction limit
                    F = dynamics(ROCK, s, sg, y[TH], y[TD], 0.0, af)[3]
                    mode, sg = SLIDE_ROCK, (-1.0 if F > 0.0 else 1.0)
                    y[UD] = 0.0
                    enter(mode, t_abs)
                else:  # slide-rock: the slip stops
                    y[UD] = 0.0
                    _, _, N, F, _ = dynamics(ROCK, s, sg, y[TH], y[TD], 0.0, af)
                    if abs(F) <= mu_s * N:
                        mode = ROCK
                        enter(mode, t_abs)
                    else:
                        sg = -1.0 if F > 0.0 else 1.0
                        events.append((t_abs, "slip on"))
            if t >= dt * (1.0 - _END):
                break
        if overturned:
            break
        theta_out[k + 1], slide_out[k + 1], mode_out[k + 1] = y[TH], y[UU], mode
    # the sample 0: the mode after the classification at t = 0
    theta_out[0], slide_out[0] = 0.0, 0.0
    first = [ev for ev in events if ev[0] == 0.0 and ev[1] in NAMES]
    mode_out[0] = NAMES.index(first[-1][1]) if first else REST
    e_end = energy(y, mode, s)
    return {
        "theta": theta_out,
        "slide": slide_out,
        "mode": mode_out,
        "peak_slide": peak_u,
        "residual_slide": math.nan if overturned else float(y[UU]),
        "peak_ratio": 1.0 if overturned else peak_th / alpha,
        "overturned": overturned,
        "overturn_time": t_over,
        "impacts": impacts,
        "mode_time": np.array([math.fsum(x) for x in times]),
        "energy": {
            "delta_E": e_end,
            "W_floor": float(y[WF]),
            "W_friction": float(y[WR]),
            "W_impacts": w_imp,
        },
        "alpha": alpha,
        "p": p,
        "r": r,
        "lam": lam,
        "events": events,
    }
