"""Independent event-located reference for the 2-DOF sliding oscillator in the plane on the
ground (piecewise-linear components), by SciPy's DOP853 restarted at every sample and event.

It shares no code with floorslide (only the constant ``G``). Per unit top mass, ``r`` the mass
ratio ``m_base/m_top``, ``k = 1 + 1/r``, ``q = 2ξw z' + w² z``, ``a`` the ground acceleration:

* stuck (``u' = 0``): ``z'' = −a − q``; the friction needed ``F = r a − q``; breakaway at the first
  ``|F|² = (mu_b (1 + r) g)²`` on the way up (terminal event), ``mu_b = max(mu_s, mu_k)``;
* sliding: ``u'' = −a + q/r − f v/|v|``, ``z'' = −k q + f v/|v|``, ``f = mu_k (1 + r) g / r``; a
  stop is the terminal event ``|v|² = v_stop²`` on the way down (``v_stop = 1e-12·g·dt``; the
  velocity is then zeroed — the slide so dropped is below ``v_stop`` times the rest of the
  record); there the base sticks if ``|F| ≤ mu_b (1 + r) g``, else slides on at once.

A slide from rest starts with an analytic step of ``MINI = 1e-7`` s along ``d = −e/|e|``
(``e = a − q/r``): ``v = (|e| − f) τ d``, exact to O(τ²) — so ``mu_s > mu_k`` (or a stop with
``|F|`` beyond the level) is needed: at a breakaway with ``mu_s = mu_k`` the speed starts as
``τ²`` and the explicit integrator would crawl (not supported: ValueError). The slow start is
stiff (the direction relaxes at the rate ``f/|v|``); DOP853 takes steps of about ``3|v|/f``,
growing geometrically with ``τ``, and so near a stop.

Peaks (of ``|u|``, ``|z|`` and ``|q|``, the top's absolute acceleration): at the ends of every
integration segment and at the non-terminal events ``u·u' = 0``, ``z·z' = 0``, ``q·q' = 0``
(direction −1), located on DOP853's dense output.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from floorslide.constants import G

MINI = 1e-7
"""Length (s) of the analytic first step of a slide from rest."""


def oscillator2d_reference(acc_x, acc_y, dt, mu_k, mu_s=None, *, frequency, damping=0.02,
                           mass_ratio=1.0, rtol=1e-12, max_events=100_000):  # fmt: skip
    """The 2-DOF sliding oscillator in the plane on the ground pair ``(acc_x, acc_y)``.

    Returns a dict: ``peak_slide``, ``residual`` (2,), ``peak_deformation``, ``peak_top_accel``,
    ``slide_time``, ``slips`` (slip phases from rest), ``stops``, ``u`` (npts, 2)."""
    ax_s = np.asarray(acc_x, dtype=float)
    ay_s = np.asarray(acc_y, dtype=float)
    mu_s = mu_k if mu_s is None else float(mu_s)
    if not mu_s > mu_k > 0.0:
        raise ValueError("oscillator2d_reference needs mu_s > mu_k > 0 (module docstring)")
    w = 2.0 * math.pi * frequency
    c2, w2, r = 2.0 * damping * w, w * w, float(mass_ratio)
    kk = 1.0 + 1.0 / r
    level = max(mu_s, mu_k) * (1.0 + r) * G
    f = mu_k * (1.0 + r) * G / r
    v_stop = 1e-12 * G * dt
    npts = ax_s.size
    u = np.zeros(2)
    v = np.zeros(2)
    z = np.zeros(2)
    p = np.zeros(2)
    sliding = False
    peaks = {"u": 0.0, "z": 0.0, "q": 0.0}
    slide_time = 0.0
    slips = stops = nev = 0
    u_out = np.zeros((npts, 2))

    def note(uu, zz, pp):
        peaks["u"] = max(peaks["u"], math.hypot(*uu))
        peaks["z"] = max(peaks["z"], math.hypot(*zz))
        peaks["q"] = max(peaks["q"], math.hypot(*(c2 * pp + w2 * zz)))

    for kstep in range(npts - 1):
        a0 = np.array([ax_s[kstep], ay_s[kstep]])
        s = (np.array([ax_s[kstep + 1], ay_s[kstep + 1]]) - a0) / dt

        def acc(t, a0=a0, s=s):
            return a0 + s * t

        t = 0.0
        while t < dt * (1.0 - 1e-14):
            nev += 1
            if nev > max_events:
                raise RuntimeError("oscillator2d_reference: too many events")
            a = acc(t)
            if not sliding:
                F = r * a - (c2 * p + w2 * z)
                if F @ F > level * level:
                    sliding = True
                    slips += 1
                    v[:] = 0.0
                    continue

                def rhs_stick(tt, y):
                    zz, pp = y[:2], y[2:]
                    return np.concatenate([pp, -acc(tt) - c2 * pp - w2 * zz])

                def brk(tt, y):
                    F = r * acc(tt) - (c2 * y[2:] + w2 * y[:2])
                    return F @ F - level * level

                brk.terminal, brk.direction = True, 1.0

                def zpk(tt, y):
                    return y[:2] @ y[2:]

                def qpk(tt, y):
                    zz, pp = y[:2], y[2:]
                    pd = -acc(tt) - c2 * pp - w2 * zz
                    return (c2 * pp + w2 * zz) @ (c2 * pd + w2 * pp)

                zpk.direction = qpk.direction = -1.0
                sol = solve_ivp(rhs_stick, (t, dt), np.concatenate([z, p]), method="DOP853",
                                rtol=rtol, atol=1e-16, events=[brk, zpk, qpk])  # fmt: skip
                for ev in (1, 2):
                    for ye in sol.y_events[ev]:
                        note(u, ye[:2], ye[2:])
                y = sol.y[:, -1]
                z, p = y[:2].copy(), y[2:].copy()
                note(u, z, p)
                if sol.status == 1:
                    t = float(sol.t_events[0][0])
                    sliding = True
                    slips += 1
                    v[:] = 0.0
                else:
                    t = dt
                continue
            # sliding
            if not v.any():
                # the analytic start from rest
                q0 = c2 * p + w2 * z
                e = a - q0 / r
                ne = math.hypot(*e)
                d = -e / ne
                c0 = ne - f
                if not c0 > 0.0:
                    raise ValueError("oscillator2d_reference: a start at the kinetic level")
                tau = min(MINI, dt - t)
                u = u + 0.5 * c0 * tau * tau * d
                z = z + p * tau
                p = p + (-kk * q0 + f * d) * tau
                v = c0 * tau * d
                slide_time += tau
                t += tau
                continue

            def rhs(tt, y):
                vv, zz, pp = y[2:4], y[4:6], y[6:8]
                q = c2 * pp + w2 * zz
                n = vv / math.hypot(*vv)
                return np.concatenate([vv, -acc(tt) + q / r - f * n, pp, -kk * q + f * n])

            def stop(tt, y):
                return y[2:4] @ y[2:4] - v_stop * v_stop

            stop.terminal, stop.direction = True, -1.0

            def upk(tt, y):
                return y[0:2] @ y[2:4]

            def zpk(tt, y):
                return y[4:6] @ y[6:8]

            def qpk(tt, y):
                d = rhs(tt, y)
                return (c2 * y[6:8] + w2 * y[4:6]) @ (c2 * d[6:8] + w2 * d[4:6])

            upk.direction = zpk.direction = qpk.direction = -1.0
            atol = np.array([1e-15, 1e-15, 1e-17, 1e-17, 1e-15, 1e-15, 1e-14, 1e-14])
            sol = solve_ivp(rhs, (t, dt), np.concatenate([u, v, z, p]), method="DOP853",
                            rtol=rtol, atol=atol, events=[stop, upk, zpk, qpk])  # fmt: skip
            if not sol.success:
                raise RuntimeError(f"oscillator2d_reference: {sol.message}")
            for ev in (1, 2, 3):
                for ye in sol.y_events[ev]:
                    note(ye[0:2], ye[4:6], ye[6:8])
            y = sol.y[:, -1]
            u, v, z, p = y[0:2].copy(), y[2:4].copy(), y[4:6].copy(), y[6:8].copy()
            note(u, z, p)
            t_end = float(sol.t_events[0][0]) if sol.status == 1 else dt
            slide_time += t_end - t
            t = t_end
            if sol.status == 1:
                stops += 1
                v[:] = 0.0
                F = r * acc(t) - (c2 * p + w2 * z)
                if F @ F <= level * level:
                    sliding = False
                else:
                    slips += 1
        u_out[kstep + 1] = u
    return {
        "peak_slide": peaks["u"],
        "residual": u.copy(),
        "peak_deformation": peaks["z"],
        "peak_top_accel": peaks["q"],
        "slide_time": slide_time,
        "slips": slips,
        "stops": stops,
        "u": u_out,
    }
