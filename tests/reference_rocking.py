"""Independent high-accuracy reference for a rigid rectangular block rocking on a moving floor
(Housner 1963).

Like ``tests/reference.py`` and ``tests/reference_isolators.py`` it shares no code with
floorslide (only the constant ``G``): SciPy's DOP853 integrates each step of the
piecewise-linear record separately (the forcing is smooth inside a step), restarting at every
sample and at every event (uplift, impact, rest, overturning), which ``solve_ivp`` locates as a
terminal event on its dense output.

Model (SI). The block has full base width ``width = 2b`` and full height ``height = 2h``, its
centre of mass at its centre; ``R = sqrt(b² + h²)``, ``alpha = atan(b/h)``,
``p = sqrt(3 g / (4 R))``. ``θ > 0`` is the rotation about the corner that uplift uses when the
floor accelerates negatively. Rocking on the side ``s = sign(θ)``:

* ``method="linear"`` (slender block, linearised): ``θ'' = p² (θ - alpha s) - p² a_f / g``;
* ``method="nonlinear"`` (Housner): ``θ'' = -p² [sin(alpha s - θ) + (a_f/g) cos(alpha s - θ)]``.

``a_f`` is the floor acceleration: the record itself, or with ``floor_system = (A, b, c, d)`` the
absolute acceleration ``a_f = c·x + d a_g`` of a linear building ``x' = A x + b a_g`` that starts
at rest and is integrated together with the block (one-way coupling: the block does not load
the building).

Rules (documented here, relied on by the tests and shared with floorslide's solver as a
contract):

* Rest: at ``θ = θ' = 0`` the block stays at rest while ``|a_f| ≤ g tan(alpha)`` (both
  methods). It uplifts at the first instant ``a_f < -g tan(alpha)`` (``s = +1``) or
  ``a_f > g tan(alpha)`` (``s = -1``), from ``θ = θ' = 0``. A rest phase that begins with the
  floor already beyond the threshold (a record that starts there, or a rest after an impact)
  uplifts at once. The crossings are terminal events of ``±a_f - g tan(alpha)`` (direction +1);
  one found at the very end of a record step with the floor not strictly beyond the threshold
  (a record that touches ``±g tan(alpha)`` exactly at a sample) does not uplift there: the next
  step decides, from the trend of the floor (a touch that turns back leaves the block at rest).
* Impact: ``s θ`` returning to 0 (direction -1, terminal). ``θ`` is set to exactly 0,
  ``θ' ← r θ'`` and the block continues on the other side. If ``|θ'|`` after the impact is
  ``≤ REST_VELOCITY · p · alpha`` (``REST_VELOCITY = 1e-12``; this includes ``r = 0``) the block
  comes to rest (``θ = θ' = 0``) and the rest rule applies at once (it may uplift again at
  once). A chattering sequence of impacts (velocities shrinking by ``r`` each time, in a finite
  time) therefore ends after about ``log(1e-12) / log(r)`` impacts.
* Overturning: the first instant ``s θ = alpha`` (terminal). The time is recorded, the
  integration stops, and the samples after it are NaN.
* A phase that starts on its own impact surface (``θ = 0`` after an uplift or an impact) has its
  impact event divided by ``(t - t0)`` (``θ' ≠ 0``) or ``(t - t0)²`` (``θ' = 0``), with the
  limit at ``t0`` (``s θ'``, or ``max(s θ''/2, 0)``) as its value there: ``solve_ivp`` would
  otherwise see the exact zero at ``t0`` as a crossing. Likewise the ``θ' = 0`` event of a phase
  that starts from rest.
* A rocking segment that ends (without an event) with the block on the wrong side of its
  corner (``s θ < 0``) missed its impact: at rounding level (``|θ| ≤ 1e-12 alpha``, only after a
  grazing uplift, the floor turning back as it reached the threshold) the block is put back at
  rest; beyond, a RuntimeError.
* Peaks: ``max |θ|`` over the segment ends and the roots of ``θ'`` located by ``solve_ivp`` as
  non-terminal events (between the samples, to the integration accuracy).
* A safety cap ``max_events`` (terminal events in the whole record, 100000 by default) raises a
  RuntimeError rather than hang.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from scipy.integrate import solve_ivp

from floorslide.constants import G

REST_VELOCITY = 1e-12
"""After an impact, ``|θ'| ≤ REST_VELOCITY · p · alpha`` brings the block to rest."""

_END = 1e-14
"""A record step is finished once the local time reaches ``dt (1 - _END)``."""


def free_rocking_period(theta0: float, alpha: float, p: float) -> float:
    """Period of free rocking of the linearised block with ``r = 1`` from rest at ``theta0``.

    Parameters
    ----------
    theta0 : float
        Release angle (rad), ``0 < theta0 < alpha``.
    alpha : float
        Slenderness angle ``atan(b/h)`` (rad).
    p : float
        Frequency parameter ``sqrt(3 g / (4 R))`` (rad/s).

    Returns
    -------
    float
        ``(4/p) arccosh(1 / (1 - theta0/alpha))`` (s): four times the fall from ``theta0`` to
        the impact, ``θ(t) = alpha - (alpha - theta0) cosh(p t)``.
    """
    return 4.0 / p * float(np.arccosh(1.0 / (1.0 - theta0 / alpha)))


def pulse_overturn_threshold(p_tp: float) -> float:
    """Overturning threshold of the linearised block under a rectangular floor pulse.

    Parameters
    ----------
    p_tp : float
        Pulse duration times the frequency parameter, ``p t_p``.

    Returns
    -------
    float
        ``a_p / (g alpha) = 1 / (1 - exp(-p t_p))``: the smallest pulse amplitude ``a_p`` (a
        floor acceleration ``-a_p`` for ``0 < t < t_p``, then 0) that overturns the block
        (Housner 1963), the state at ``t_p`` then lying on the stable manifold of ``θ = alpha``.
    """
    return float(-1.0 / np.expm1(-p_tp))


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


def rock_reference(
    acc: Sequence[float] | np.ndarray,
    dt: float,
    *,
    width: float,
    height: float,
    restitution: float | None = None,
    method: str = "linear",
    floor_system: tuple | None = None,
    g: float = G,
    rtol: float = 1e-13,
    atol: float = 1e-15,
    theta0: float = 0.0,
    theta_dot0: float = 0.0,
    max_events: int = 100_000,
) -> dict:
    """Rocking of a rigid rectangular block on a floor, by DOP853 step by step with events.

    Parameters
    ----------
    acc : array_like
        Ground acceleration samples (m/s²), piecewise linear between samples.
    dt : float
        Sample step (s).
    width, height : float
        Full base width ``2b`` and full height ``2h`` of the block (m).
    restitution : float, optional
        Coefficient ``r`` multiplying ``θ'`` at each impact, in [0, 1]; by default Housner's
        ``1 - 1.5 sin²(alpha)``.
    method : {"linear", "nonlinear"}
        Linearised slender-block equation or Housner's full equation (module docstring).
    floor_system : tuple, optional
        ``(A, b, c, d)``: a building ``x' = A x + b a_g`` at rest at ``t = 0`` whose floor
        acceleration is ``a_f = c·x + d a_g``. Without it ``a_f = a_g``.
    g : float
        Gravity (m/s²).
    rtol, atol : float
        Tolerances of DOP853.
    theta0, theta_dot0 : float
        Initial angle (rad, ``|theta0| < alpha``) and angular velocity (rad/s). With
        ``theta0 = 0`` and ``theta_dot0 ≠ 0`` the block starts on the side ``sign(theta_dot0)``.
    max_events : int
        Cap on the terminal events of the whole record (a RuntimeError beyond it).

    Returns
    -------
    dict
        ``theta``, ``theta_dot`` (at the samples, NaN after overturning), ``peak_ratio``
        (``max |θ| / alpha`` between the samples too; 1.0 if overturned), ``impacts``,
        ``rocking_time`` (s with ``θ ≠ 0``), ``overturned``, ``t_overturn`` (s or NaN),
        ``uplifts`` (from rest), ``alpha``, ``p``, ``r``; and for the tests ``impact_log``
        (rows ``[t, θ' before, θ' after]``), ``extrema`` (rows ``[t, θ]`` at the roots of ``θ'``
        while rocking) and ``events`` (list of ``(t, kind)``, kind in "uplift", "impact",
        "rest", "overturn").
    """
    acc = np.asarray(acc, dtype=float).ravel()
    npts = acc.size
    if npts < 2 or not dt > 0.0:
        raise ValueError("rock_reference: need at least 2 samples and dt > 0")
    if not (width > 0.0 and height > 0.0):
        raise ValueError("rock_reference: width and height must be positive")
    if method not in ("linear", "nonlinear"):
        raise ValueError(f"rock_reference: unknown method {method!r}")
    alpha = float(np.arctan2(width, height))
    R = float(np.hypot(width / 2.0, height / 2.0))
    p = float(np.sqrt(3.0 * g / (4.0 * R)))
    p2 = p * p
    r = 1.0 - 1.5 * np.sin(alpha) ** 2 if restitution is None else float(restitution)
    if not 0.0 <= r <= 1.0:
        raise ValueError("rock_reference: restitution must be in [0, 1]")
    if abs(theta0) >= alpha:
        raise ValueError("rock_reference: |theta0| must be below alpha")
    thr = g * np.tan(alpha)
    v_rest = REST_VELOCITY * p * alpha
    linear = method == "linear"

    if floor_system is None:
        A, bv, cv, dd = np.zeros((0, 0)), np.zeros(0), np.zeros(0), 1.0
    else:
        A, bv, cv, dd = floor_system
        A = np.atleast_2d(np.asarray(A, dtype=float))
        bv = np.asarray(bv, dtype=float).ravel()
        cv = np.asarray(cv, dtype=float).ravel()
        dd = float(dd)
    n = A.shape[0]
    TH, TD = n, n + 1

    def block_acc(theta: float, s: float, af: float) -> float:
        if linear:
            return p2 * (theta - alpha * s) - p2 * af / g
        phi = alpha * s - theta
        return -p2 * (np.sin(phi) + af / g * np.cos(phi))

    y = np.zeros(n + 2)
    y[TH], y[TD] = theta0, theta_dot0
    if theta0 != 0.0:
        mode = 1 if theta0 > 0.0 else -1
    elif theta_dot0 != 0.0:
        mode = 1 if theta_dot0 > 0.0 else -1
    else:
        mode = 0  # 0: at rest; ±1: rocking on the side s

    theta_out = np.full(npts, np.nan)
    tdot_out = np.full(npts, np.nan)
    theta_out[0], tdot_out[0] = y[TH], y[TD]
    peak = abs(theta0)
    impacts = uplifts = nev = 0
    rocking: list[float] = []  # the rocking segments (local times: summed exactly by fsum)
    overturned = False
    t_overturn = np.nan
    impact_log: list[tuple[float, float, float]] = []
    extrema: list[tuple[float, float]] = []
    events: list[tuple[float, str]] = []

    for k in range(npts - 1):
        a0, a1 = float(acc[k]), float(acc[k + 1])
        sl = (a1 - a0) / dt
        t = 0.0
        if n == 0 and mode == 0 and max(abs(a0), abs(a1)) < thr:
            # at rest on a floor that stays inside the threshold (linear in the step)
            theta_out[k + 1], tdot_out[k + 1] = y[TH], y[TD]
            continue

        def ground(tt: float, a0: float = a0, a1: float = a1, sl: float = sl) -> float:
            """The record in the step, exact at both samples (so that a record touching the
            threshold at a sample is seen to touch it)."""
            return a0 + sl * tt if tt <= 0.5 * dt else a1 - sl * (dt - tt)

        def floor(tt: float, yy: np.ndarray, ground=ground) -> float:
            return float(cv @ yy[:n]) + dd * ground(tt)

        while True:
            if nev > max_events:
                raise RuntimeError(
                    f"rock_reference: more than {max_events} events (chattering?) by "
                    f"t = {k * dt + t:.9g} s; last {events[-4:]}"
                )
            t_abs = k * dt + t
            if mode == 0:
                af = floor(t, y)
                if af < -thr or af > thr:  # beyond the threshold at the start of a rest phase
                    mode = 1 if af < -thr else -1
                    uplifts += 1
                    nev += 1
                    events.append((t_abs, "uplift"))
                    continue

                def rhs(tt, yy, ground=ground):
                    out = np.zeros(n + 2)
                    out[:n] = A @ yy[:n] + bv * ground(tt)
                    return out

                def up(tt, yy, floor=floor):
                    return floor(tt, yy) - thr

                def lo(tt, yy, floor=floor):
                    return -floor(tt, yy) - thr

                up.terminal = lo.terminal = True
                up.direction = lo.direction = 1.0
                evs = [up, lo]
            else:
                s = float(mode)

                def rhs(tt, yy, s=s, ground=ground, floor=floor):
                    out = np.empty(n + 2)
                    out[:n] = A @ yy[:n] + bv * ground(tt)
                    out[TH] = yy[TD]
                    out[TD] = block_acc(yy[TH], s, floor(tt, yy))
                    return out

                def impact(tt, yy, s=s):
                    return s * yy[TH]

                def over(tt, yy, s=s):
                    return s * yy[TH] - alpha

                def still(tt, yy):
                    return yy[TD]

                impact.terminal, impact.direction = True, -1.0
                over.terminal, over.direction = True, 1.0
                still.terminal, still.direction = False, 0.0
                if y[TH] == 0.0:  # the phase starts on its impact surface
                    acc0 = block_acc(0.0, s, floor(t, y))
                    if y[TD] != 0.0:
                        impact = _from_zero(impact, t, 1, s * y[TD])
                    else:
                        impact = _from_zero(impact, t, 2, max(s * acc0 / 2.0, 0.0))
                        still = _from_zero(still, t, 1, acc0)
                evs = [impact, over, still]

            sol = solve_ivp(rhs, (t, dt), y, method="DOP853", rtol=rtol, atol=atol, events=evs)
            if not sol.success:
                raise RuntimeError(f"rock_reference: solve_ivp failed: {sol.message}")
            t_end = float(sol.t[-1])
            y = sol.y[:, -1].copy()
            if mode != 0:
                rocking.append(t_end - t)
                for te, ye in zip(sol.t_events[2], sol.y_events[2], strict=True):
                    if te > t:
                        extrema.append((k * dt + te, ye[TH]))
                        peak = max(peak, abs(ye[TH]))
                peak = max(peak, abs(y[TH]))
            t = t_end
            t_abs = k * dt + t
            if sol.status == 0 and mode != 0 and mode * y[TH] < 0.0:  # the impact was missed
                if abs(y[TH]) > 1e-12 * alpha:
                    raise RuntimeError(
                        f"rock_reference: the block sank below the floor at t = {t_abs:.9g} s"
                    )
                # a grazing uplift (the floor touched the threshold and turned back): rest
                y[TH] = y[TD] = 0.0
                mode = 0
                events.append((t_abs, "rest"))
            elif sol.status == 1:
                nev += 1
                af = floor(t, y)
                if mode == 0 and -thr <= af <= thr and t >= dt * (1.0 - _END):
                    pass  # the floor reaches the threshold at the sample: the next step decides
                elif mode == 0:
                    mode = 1 if sol.t_events[1].size else -1
                    uplifts += 1
                    y[TH] = y[TD] = 0.0
                    events.append((t_abs, "uplift"))
                elif sol.t_events[1].size:  # overturning
                    overturned = True
                    t_overturn = t_abs
                    events.append((t_abs, "overturn"))
                    break
                else:  # impact
                    before = y[TD]
                    after = r * before
                    impacts += 1
                    impact_log.append((t_abs, before, after))
                    events.append((t_abs, "impact"))
                    y[TH] = 0.0
                    if abs(after) <= v_rest:
                        y[TD] = 0.0
                        mode = 0
                        events.append((t_abs, "rest"))
                    else:
                        y[TD] = after
                        mode = -mode
            if t >= dt * (1.0 - _END):
                break
        if overturned:
            break
        theta_out[k + 1], tdot_out[k + 1] = y[TH], y[TD]

    return {
        "theta": theta_out,
        "theta_dot": tdot_out,
        "peak_ratio": 1.0 if overturned else peak / alpha,
        "impacts": impacts,
        "rocking_time": math.fsum(rocking),
        "overturned": overturned,
        "t_overturn": t_overturn,
        "uplifts": uplifts,
        "alpha": alpha,
        "p": p,
        "r": r,
        "impact_log": np.array(impact_log, dtype=float).reshape(-1, 3),
        "extrema": np.array(extrema, dtype=float).reshape(-1, 2),
        "events": events,
    }
