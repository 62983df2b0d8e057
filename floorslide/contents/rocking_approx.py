"""Approximate methods for rocking blocks, beside the exact ones (for ``floorslide bench``).

Both take the floor acceleration as the piecewise-linear function through its samples (on a
building: the floor's exact motion sampled at the record's dt, then re-interpolated — as a user
of a general-purpose solver would feed it) and the conventions of
:mod:`floorslide.contents.rocking_block`:

- ``"rk4"``: the classical fixed-step Runge–Kutta scheme at ``dt/substeps`` with the events
  found by sign changes over a step and placed by linear interpolation (the usual hand-written
  rocking integrator, e.g. Yim, Chopra & Penzien 1980 used fixed steps with interpolated
  impacts); after an impact or an uplift the step restarts there.
- ``"solve_ivp"``: SciPy's adaptive ``RK45``/``DOP853`` over the whole record at ``rtol`` with
  ``max_step = dt``, impacts, uplift and overturning as terminal events (how rocking is
  typically scripted with ODE libraries, e.g. MATLAB's ``ode45`` with events).

References
----------
Yim, C.-S., Chopra, A. K., Penzien, J. (1980). Rocking response of rigid blocks to earthquakes.
*Earthquake Eng. Struct. Dyn.* 8(6), 565–587.
"""

from __future__ import annotations

import math

import numpy as np

from floorslide._jit import njit
from floorslide.contents._rocking_kernel import REST_VELOCITY


@njit(cache=True, inline="always")
def _theta_dd(th, s, af, alpha, p2, g, nonlinear):
    if nonlinear:
        return -p2 * (math.sin(alpha * s - th) + af / g * math.cos(alpha * s - th))
    return p2 * (th - alpha * s) - p2 * af / g


@njit(cache=True)
def _rk4_block(af, dt, k, alpha, p, r, tan_a, g, nonlinear, out):
    """One block by fixed-step RK4 at ``dt/k`` on the floor samples ``af`` (linear between
    them). ``out = [peak |θ|/α, impacts, uplifts, rocking time, overturned, overturn time]``."""
    p2 = p * p
    level = g * tan_a
    h = dt / k
    th = 0.0
    w = 0.0
    s = 0.0
    peak = 0.0
    impacts = 0
    uplifts = 0
    rtime = 0.0
    t_over = -1.0
    n = af.size
    for i in range(n - 1):
        a0 = af[i]
        slope = (af[i + 1] - a0) / dt
        for j in range(k):
            t0 = j * h
            left = h
            while left > 0.0:
                tau = t0 + (h - left)  # time into the record step
                if s == 0.0:
                    a_beg = a0 + slope * tau
                    a_end = a0 + slope * (tau + left)
                    if abs(a_end) > level and abs(a_beg) <= level:
                        # uplift where the linear floor crosses the level
                        target = level if a_end > 0 else -level
                        frac = (target - a_beg) / (a_end - a_beg)
                        left -= frac * left
                        s = -1.0 if a_end > 0 else 1.0
                        uplifts += 1
                        continue
                    if abs(a_beg) > level:
                        s = -1.0 if a_beg > 0 else 1.0
                        uplifts += 1
                        continue
                    left = 0.0
                    continue
                # one RK4 step of length `left`
                hh = left
                am = a0 + slope * (tau + 0.5 * hh)
                ae = a0 + slope * (tau + hh)
                ab = a0 + slope * tau
                k1t, k1w = w, _theta_dd(th, s, ab, alpha, p2, g, nonlinear)
                k2t = w + 0.5 * hh * k1w
                k2w = _theta_dd(th + 0.5 * hh * k1t, s, am, alpha, p2, g, nonlinear)
                k3t = w + 0.5 * hh * k2w
                k3w = _theta_dd(th + 0.5 * hh * k2t, s, am, alpha, p2, g, nonlinear)
                k4t = w + hh * k3w
                k4w = _theta_dd(th + hh * k3t, s, ae, alpha, p2, g, nonlinear)
                th1 = th + hh / 6.0 * (k1t + 2 * k2t + 2 * k3t + k4t)
                w1 = w + hh / 6.0 * (k1w + 2 * k2w + 2 * k3w + k4w)
                if s * th1 >= alpha:
                    frac = (alpha - s * th) / (s * th1 - s * th)
                    rtime += frac * hh
                    t_over = i * dt + tau + frac * hh
                    peak = 1.0
                    out[0], out[1], out[2], out[3], out[4], out[5] = (
                        peak, impacts, uplifts, rtime, 1.0, t_over,
                    )  # fmt: skip
                    return
                if s * th1 < 0.0 and s * th > 0.0:
                    # impact where θ crosses 0, by linear interpolation
                    frac = th / (th - th1)
                    w_imp = w + frac * (w1 - w)
                    rtime += frac * hh
                    impacts += 1
                    left -= frac * hh
                    th = 0.0
                    w = r * w_imp
                    if abs(w) <= REST_VELOCITY * p * alpha:
                        w = 0.0
                        s = 0.0
                    else:
                        s = -s
                    continue
                if s * th1 < 0.0:
                    # a grazing uplift that fell back: rest
                    th, w, s = 0.0, 0.0, 0.0
                    rtime += hh
                    left = 0.0
                    continue
                th, w = th1, w1
                peak = max(peak, abs(th) / alpha)
                rtime += hh
                left = 0.0
    out[0], out[1], out[2], out[3], out[4], out[5] = peak, impacts, uplifts, rtime, 0.0, t_over


def rk4(af: np.ndarray, dt: float, alpha, p, r, tan_a, g: float, nonlinear: bool, substeps: int):
    """Fixed-step RK4 of every block (arrays ``alpha, p, r, tan_a``) on the floor samples."""
    out = np.zeros((np.size(alpha), 6))
    af = np.ascontiguousarray(af, dtype=float)
    for i in range(out.shape[0]):
        _rk4_block(
            af, dt, int(substeps), alpha[i], p[i], r[i], tan_a[i], g, bool(nonlinear), out[i]
        )
    return out


def solve_ivp_blocks(
    af: np.ndarray,
    dt: float,
    alpha,
    p,
    r,
    tan_a,
    g: float,
    nonlinear: bool,
    rtol: float = 1e-6,
    integrator: str = "RK45",
):
    """Every block by SciPy's adaptive integrator over the whole record (``max_step = dt``),
    events terminal: uplift from rest, impact, overturning."""
    from scipy.integrate import solve_ivp

    t_end = (af.size - 1) * dt
    tt = np.arange(af.size) * dt

    def a_f(t):
        return float(np.interp(t, tt, af))

    out = np.zeros((np.size(alpha), 6))
    for i in range(out.shape[0]):
        al, pp, rr, level = float(alpha[i]), float(p[i]), float(r[i]), g * float(tan_a[i])
        p2 = pp * pp
        t, th, w, s = 0.0, 0.0, 0.0, 0.0
        peak, impacts, uplifts, rtime, over, t_over = 0.0, 0, 0, 0.0, 0.0, -1.0
        guard = 0
        t_uplift = -1.0
        while t < t_end and guard < 100000:
            guard += 1
            if s == 0.0:
                # a floor already beyond the level when the rest begins (a record that starts
                # there, t = 0; a rest after an impact) lifts the block at once
                a_now = a_f(t)
                if t != t_uplift and abs(a_now) > level:
                    t_uplift = t
                    s = -1.0 if a_now > 0 else 1.0
                    uplifts += 1
                    continue
                # at rest until |a_f| exceeds the level: scan the samples, then interpolate (a
                # block back at rest at once after an uplift waits for the next sample)
                k0 = int(np.floor(t / dt + 1e-9)) + (1 if t == t_uplift else 0)
                hit = -1
                for k in range(max(k0, 0), af.size - 1):
                    if abs(af[k + 1]) > level:
                        hit = k
                        break
                if hit < 0:
                    break
                a0, a1 = af[hit], af[hit + 1]
                target = level if a1 > 0 else -level
                frac = 0.0 if abs(a0) > level else (target - a0) / (a1 - a0)
                t = max(t, (hit + frac) * dt)
                t_uplift = t
                s = -1.0 if a1 > 0 else 1.0
                uplifts += 1
                continue

            def rhs(tq, y, s=s, al=al, p2=p2):
                a = a_f(tq)
                if nonlinear:
                    u = al * s - y[0]
                    return [y[1], -p2 * (np.sin(u) + a / g * np.cos(u))]
                return [y[1], p2 * (y[0] - al * s) - p2 * a / g]

            # the phase starts on its impact surface (θ = 0): the event is s·θ over (t − t0)
            # (after an impact, θ' ≠ 0) or (t − t0)² (from rest), whose limits at t0 are
            # positive — else the start itself, or rounding just after it, reads as an impact
            power = 1 if w != 0.0 else 2

            def impact(tq, y, s=s, t0=t, power=power):
                d = tq - t0
                return s * y[0] / d**power if d > 0.0 else 1.0

            impact.terminal, impact.direction = True, -1

            def overturn(tq, y, s=s, al=al):
                return s * y[0] - al

            overturn.terminal, overturn.direction = True, 1
            sol = solve_ivp(
                rhs,
                (t, t_end),
                [th, w],
                method=integrator,
                rtol=rtol,
                atol=rtol * 1e-3 * al,
                max_step=dt,
                events=(impact, overturn),
            )
            seg = np.abs(sol.y[0])
            peak = max(peak, float(seg.max()) / al)
            rtime += sol.t[-1] - t
            t = sol.t[-1]
            if sol.status == 1 and sol.t_events[1].size:
                over, t_over, peak = 1.0, float(sol.t_events[1][0]), 1.0
                break
            if sol.status == 1 and sol.t_events[0].size:
                impacts += 1
                w = rr * float(sol.y_events[0][0][1])
                th = 0.0
                if abs(w) <= REST_VELOCITY * pp * al:
                    w, s = 0.0, 0.0
                else:
                    s = -s
                continue
            break
        out[i] = (peak, impacts, uplifts, rtime, over, t_over)
    return out
