"""Approximate sliding solvers, kept for the accuracy-versus-cost study (docs/design.md §6).

- ``slammer``: Jibson's (1993) per-sample trapezoid, as USGS SLAMMER integrates a rigid block,
  generalised symmetrically to two-way sliding, on the sampled floor motion;
- ``newmark``: average-acceleration (trapezoid) integration of the relative motion with
  stick/slip checks at ``dt/substeps``, on exact floor samples at that step;
- ``solve_ivp``: SciPy's adaptive Runge–Kutta (``RK45`` or ``DOP853``) with event location at a
  tolerance, restarted at every sample (the forcing has a kink there), building and block
  integrated together;
- ``reinterpolated``: the exact event-driven solver applied to floor *samples* joined by straight
  lines — what one gets by exporting floor accelerations and sliding a block on them.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building.exact_motion import single_use_motion
from floorslide.building.motions import floor_motions
from floorslide.constants import G
from floorslide.errors import ModelError


def slide(
    a,
    dt,
    mk,
    ms,
    building,
    floor,
    vert,
    direction,
    method,
    histories,
    substeps,
    rtol,
    integrator,
    max_step=None,
):
    """Dispatch of :func:`floorslide.contents.sliding.slide` to an approximate method."""
    from floorslide.contents.sliding import SlideResult, _allowed, _slide_exact

    allow_pos, allow_neg = _allowed(direction)
    if histories:
        raise ModelError(f"histories are only available with method='exact', not {method!r}")
    on_floor = building is not None and building.dof_of(floor) is not None
    if method == "reinterpolated":
        af = floor_motions(building, a, dt, floors=[floor])[0] if on_floor else a
        res = _slide_exact(single_use_motion(None, af, dt, None), mk, ms, vert, direction, False)
        return _renamed(res, method)
    if method in ("slammer", "newmark"):
        k = 1 if method == "slammer" else int(substeps)
        if k < 1:
            raise ModelError(f"substeps must be ≥ 1, got {substeps}", "substeps")
        if on_floor:
            af = floor_motions(building, a, dt, floors=[floor], oversample=k)[0]
        else:
            af = np.interp(np.arange((a.size - 1) * k + 1) / k, np.arange(a.size), a)
        if vert is not None:
            nv = G + np.interp(np.arange((a.size - 1) * k + 1) / k, np.arange(a.size), vert)
        else:
            nv = np.full(1, G)
        out = np.zeros((mk.size, 3))
        _trapezoid(
            af,
            dt / k,
            nv,
            vert is not None,
            np.maximum(mk, ms),
            mk,
            allow_pos,
            allow_neg,
            method == "slammer",
            out,
        )
        duration = (a.size - 1) * dt
        return SlideResult(
            mu_k=mk,
            mu_s=ms,
            peak_slide=out[:, 0],
            residual_slide=out[:, 1],
            peak_abs_accel=out[:, 2],
            slide_fraction=np.full(mk.size, np.nan),
            slip_phases=np.full(mk.size, -1),
            time_of_peak=np.full(mk.size, np.nan),
            duration=duration,
            method=method,
            direction=direction,
        )
    if method == "solve_ivp":
        if integrator not in ("RK45", "DOP853", "Radau", "LSODA", "BDF", "RK23"):
            raise ModelError(f"unknown integrator {integrator!r}", "integrator")
        rows = [
            _ivp_one(
                a,
                dt,
                mk[i],
                max(mk[i], ms[i]),
                building if on_floor else None,
                floor,
                vert,
                allow_pos,
                allow_neg,
                rtol,
                integrator,
                max_step,
            )
            for i in range(mk.size)
        ]
        arr = np.array(rows).reshape(mk.size, 3)
        return SlideResult(
            mu_k=mk,
            mu_s=ms,
            peak_slide=arr[:, 0],
            residual_slide=arr[:, 1],
            peak_abs_accel=arr[:, 2],
            slide_fraction=np.full(mk.size, np.nan),
            slip_phases=np.full(mk.size, -1),
            time_of_peak=np.full(mk.size, np.nan),
            duration=(a.size - 1) * dt,
            method=method,
            direction=direction,
        )
    raise ModelError(f"unknown method {method!r}")


def _renamed(res, method):
    from dataclasses import replace

    return replace(res, method=method)


@njit(cache=True)
def _trapezoid(af, h, nv, has_vert, mub, muk, allow_pos, allow_neg, jibson, out):
    """Per-sample trapezoid integration of the block's relative motion (Jibson 1993).

    In floorslide's sign convention the relative acceleration while sliding is
    ``−a_f − mu_k N sign(v)``; stick/slip is checked only at the samples. With ``jibson`` the
    SLAMMER logic is followed literally (tolerance 1e-5 on the velocity, the yield acceleration
    scaled by ``a/a_y`` while stuck); otherwise a plain stick/slip check.
    """
    n = af.size
    for i in range(mub.size):
        v = 0.0
        u = 0.0
        acc_prev = 0.0
        peak = 0.0
        peak_abs = abs(af[0])
        # a record that starts beyond the friction limit (cut mid-motion) breaks away at t = 0
        nn = max(nv[0], 0.0)
        dir0 = 0.0
        if af[0] > mub[i] * nn and allow_neg:
            acc_prev, dir0 = -af[0] + muk[i] * nn, -1.0
        elif af[0] < -mub[i] * nn and allow_pos:
            acc_prev, dir0 = -af[0] - muk[i] * nn, 1.0
        if dir0 != 0.0:
            peak_abs = muk[i] * nn
        for k in range(1, n):
            a = af[k]
            nn = nv[k] if has_vert else nv[0]
            if nn < 0.0:
                nn = 0.0
            fb = mub[i] * nn
            fk = muk[i] * nn
            started = dir0 if k == 1 else 0.0
            sliding = (abs(v) >= 1e-5 if jibson else v != 0.0) or started != 0.0
            if not sliding:
                if a > fb and allow_neg:
                    acc_rel = -a + fk
                elif a < -fb and allow_pos:
                    acc_rel = -a - fk
                else:
                    acc_rel = 0.0
            else:
                s = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else started)
                acc_rel = -a - fk * s
            v_new = v + 0.5 * h * (acc_rel + acc_prev)
            if sliding and v_new * (v if v != 0.0 else started) <= 0.0:
                # the velocity changed sign between samples: the block stopped
                u += 0.5 * h * v
                v_new = 0.0
                acc_rel = 0.0
            elif not sliding and acc_rel == 0.0:
                v_new = 0.0
            else:
                u += 0.5 * h * (v_new + v)
            if not allow_pos and v_new > 0.0:
                v_new = 0.0
                acc_rel = 0.0
            if not allow_neg and v_new < 0.0:
                v_new = 0.0
                acc_rel = 0.0
            v = v_new
            acc_prev = acc_rel
            if abs(u) > peak:
                peak = abs(u)
            pa = abs(a + acc_rel)
            if pa > peak_abs:
                peak_abs = pa
        out[i, 0] = peak
        out[i, 1] = u
        out[i, 2] = peak_abs


def _ivp_one(
    a, dt, muk, mub, building, floor, vert, allow_pos, allow_neg, rtol, integrator, max_step=None
):
    """One block by SciPy's solve_ivp with event location; building and block together."""
    from scipy.integrate import solve_ivp  # SciPy's integrators: only when asked for

    if building is not None:
        A, B = building.state_matrices()
        b = B[:, 0]
        Ca, Da, _ = building.output_matrices([floor], "acceleration")
        ca, da = Ca[0], float(Da[0, 0])
    else:
        A = np.zeros((0, 0))
        b = np.zeros(0)
        ca, da = np.zeros(0), 1.0
    n = A.shape[0]
    x = np.zeros(n)
    u = v = 0.0
    mode = 0
    peak = 0.0
    peak_abs = abs(da * a[0])
    atol = 1e-14
    for k in range(a.size - 1):
        a0 = a[k]
        sl = (a[k + 1] - a0) / dt
        if vert is not None:
            n0 = G + vert[k]
            sn = (vert[k + 1] - vert[k]) / dt
        else:
            n0, sn = G, 0.0
        t = 0.0
        guard = 0
        while t < dt and guard < 1000:
            guard += 1

            def floor_acc(tt, y, a0=a0, sl=sl):
                return ca @ y[:n] + da * (a0 + sl * tt)

            def normal(tt, n0=n0, sn=sn):
                return max(n0 + sn * tt, 0.0)

            if mode == 0:
                # beyond the friction limit already when sticking begins (a record that starts
                # mid-motion): break away at once
                af_now = floor_acc(t, x)
                if af_now > mub * normal(t) and allow_neg:
                    mode = -1
                    continue
                if af_now < -mub * normal(t) and allow_pos:
                    mode = 1
                    continue

                def rhs(tt, y, a0=a0, sl=sl):
                    return np.concatenate([A @ y[:n] + b * (a0 + sl * tt), [0.0, 0.0]])

                def up(tt, y):
                    return floor_acc(tt, y) - mub * normal(tt)

                def lo(tt, y):
                    return -floor_acc(tt, y) - mub * normal(tt)

                up.terminal = lo.terminal = True
                up.direction = lo.direction = 1.0
                events = ([up] if allow_neg else []) + ([lo] if allow_pos else [])
            else:
                s = float(mode)

                def rhs(tt, y, a0=a0, sl=sl, s=s):
                    af = ca @ y[:n] + da * (a0 + sl * tt)
                    return np.concatenate(
                        [A @ y[:n] + b * (a0 + sl * tt), [y[n + 1], -af - s * muk * normal(tt)]]
                    )

                def stop(tt, y, s=s):
                    # offset 1e-13 m/s: a phase that starts at v = 0 must not stop at once on
                    # rounding (the root found by the event locator is only good to ~1 ulp)
                    return s * y[n + 1] + 1e-13

                stop.terminal = True
                stop.direction = -1.0
                events = [stop]
            y0 = np.concatenate([x, [u, v]])
            sol = solve_ivp(
                rhs,
                (t, dt),
                y0,
                method=integrator,
                rtol=rtol,
                atol=atol,
                events=events or None,
                max_step=max_step or np.inf,
            )
            y = sol.y[:, -1]
            x, u, v = y[:n], y[n], y[n + 1]
            peak = max(peak, abs(u))
            hit = sol.status == 1
            t_new = sol.t[-1]
            if mode != 0:
                peak_abs = max(peak_abs, muk * max(normal(t), normal(t_new)))
            else:
                tt = np.linspace(t, t_new, 5)
                peak_abs = max(
                    peak_abs, *(abs(floor_acc(q, np.concatenate([x, [0, 0]]))) for q in tt[-1:])
                )
            t = t_new
            if not hit:
                break
            if mode == 0:
                af = floor_acc(t, y)
                mode = -1 if af > 0 else 1
                v = 0.0
            else:
                v = 0.0
                af = floor_acc(t, y)
                fb = mub * normal(t)
                if af > fb and allow_neg:
                    mode = -1
                elif af < -fb and allow_pos:
                    mode = 1
                else:
                    mode = 0
            if t >= dt * (1 - 1e-13):
                break
    return peak, u, peak_abs
