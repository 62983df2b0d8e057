"""Independent high-accuracy reference for a heavy rigid block coupled with its floor.

Shares no code with floorslide (plain NumPy/SciPy): SciPy's DOP853 integrates building and block
together over each step of the piecewise-linear record separately (the forcing is smooth inside a
step), restarting at every sample and at every phase change, which ``solve_ivp`` locates as a
terminal event.

Model (SI, coordinates relative to the ground; ``u`` the building's DOFs, ``s`` the block's
slide relative to floor DOF ``j``, ``a_f = u_j'' + a_g`` the floor's absolute acceleration)::

    stuck:       (M + m e_j e_jᵀ) u'' + C u' + K u = −(M + m e_j e_jᵀ) 1 a_g,   s' = 0
    sliding σ:   M u'' + C u' + K u = −M 1 a_g + e_j σ mu_k m g,
                 s'' = −a_f − σ mu_k g

Events: stuck → sliding when ``a_f`` of the stuck system (``−(K u + C u')_j / (M_j + m)``)
crosses ``+mu_s g`` upward (then σ = −1) or ``−mu_s g`` downward (σ = +1); sliding → stop when
``s'`` comes back to 0, then stuck if ``|a_f(stuck)| ≤ mu_s g`` there, else sliding the other
way. The block starts stuck, the building at rest.

``peak_slide``: max ``|s|`` over the samples and events (``s`` is monotone in a phase).
``pfa``: max ``|a_f|`` inside steps too — on each integrated piece, ``|a_f|`` of the dense
output on a grid refined by a bounded Brent search around its largest value (both sides of a
jump count).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

G = 9.80665


def coupled_response(M, K, C, j, m, mu_k, mu_s, acc, dt, *, rtol=1e-12, atol=1e-15, grid=12):
    """Response of building ``(M, K, C)`` (diagonal masses ``M``) with a block of mass ``m`` on
    DOF ``j`` to the piecewise-linear ground acceleration through ``acc`` at ``t = k·dt``.

    Returns a dict: ``s``, ``sd``, ``a_f``, ``mode`` at the samples (``a_f`` and ``mode`` those
    after a change at a sample), ``peak_slide``, ``residual_slide``, ``pfa``, ``slips``,
    ``slide_time``, ``events`` (list of ``(t, new mode)``).
    """
    M = np.asarray(M, dtype=float)
    K = np.asarray(K, dtype=float)
    C = np.asarray(C, dtype=float)
    acc = np.asarray(acc, dtype=float)
    n = M.size
    Mst = M.copy()
    Mst[j] += m
    npts = acc.size

    def need(y):
        r = K[j] @ y[:n] + C[j] @ y[n : 2 * n]
        return -r / Mst[j]

    def rhs(mode):
        def f(t, y, a0, sl, t0):
            ag = a0 + sl * (t - t0)
            u, v = y[:n], y[n : 2 * n]
            r = K @ u + C @ v
            out = np.empty_like(y)
            out[:n] = v
            if mode == 0:
                out[n : 2 * n] = -r / Mst - ag
                out[2 * n] = 0.0
                out[2 * n + 1] = 0.0
            else:
                force = np.zeros(n)
                force[j] = mode * mu_k * m * G
                ud = (-r + force) / M - ag
                out[n : 2 * n] = ud
                out[2 * n] = y[2 * n + 1]
                out[2 * n + 1] = -(ud[j] + ag) - mode * mu_k * G
            return out

        return f

    def floor_acc(mode, y):
        if mode == 0:
            return need(y)
        r = K[j] @ y[:n] + C[j] @ y[n : 2 * n]
        return (-r + mode * mu_k * m * G) / M[j]

    def events(mode):
        if mode == 0:

            def up(t, y, *args):
                return need(y) - mu_s * G

            def down(t, y, *args):
                return need(y) + mu_s * G

            up.terminal, up.direction = True, 1
            down.terminal, down.direction = True, -1
            return [up, down]

        def stop(t, y, *args):
            return y[2 * n + 1]

        stop.terminal, stop.direction = True, (-1 if mode > 0 else 1)
        return [stop]

    def piece_peak(sol, mode, ta, tb):
        ts = np.linspace(ta, tb, grid + 1)
        vals = np.array([abs(floor_acc(mode, sol.sol(t))) for t in ts])
        i = int(np.argmax(vals))
        best = vals[i]
        lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, grid)]
        if hi > lo:
            r = minimize_scalar(
                lambda t: -abs(floor_acc(mode, sol.sol(t))),
                bounds=(lo, hi),
                method="bounded",
                options={"xatol": 1e-14 * max(1.0, tb)},
            )
            best = max(best, -r.fun)
        return best

    y = np.zeros(2 * n + 2)
    mode = 0
    s_h = np.zeros(npts)
    sd_h = np.zeros(npts)
    af_h = np.zeros(npts)
    mode_h = np.zeros(npts, dtype=int)
    af_h[0] = floor_acc(0, y)
    peak_slide = 0.0
    pfa = abs(af_h[0])
    slips = 0
    slide_time = 0.0
    ev_list = []
    for k in range(npts - 1):
        t0 = k * dt
        t1 = (k + 1) * dt
        a0 = acc[k]
        sl = (acc[k + 1] - acc[k]) / dt
        t = t0
        guard = 0
        while t < t1:
            guard += 1
            if guard > 200:
                raise RuntimeError(f"more than 200 events in step {k}")
            sol = solve_ivp(
                rhs(mode),
                (t, t1),
                y,
                method="DOP853",
                rtol=rtol,
                atol=atol,
                events=events(mode),
                dense_output=True,
                args=(a0, sl, t0),
            )
            hit = [(te[0], i) for i, te in enumerate(sol.t_events) if te.size]
            te = min(hit)[0] if hit else t1
            y_end = sol.y_events[min(hit)[1]][0].copy() if hit else sol.y[:, -1].copy()
            pfa = max(pfa, piece_peak(sol, mode, t, te))
            if mode != 0:
                slide_time += te - t
            y = y_end
            peak_slide = max(peak_slide, abs(y[2 * n]))
            if not hit:
                t = t1
                break
            # an event at te
            y[2 * n + 1] = 0.0
            if mode == 0:
                mode = -1 if min(hit)[1] == 0 else 1
                slips += 1
            else:
                a = need(y)
                new = -1 if a > mu_s * G else (1 if a < -mu_s * G else 0)
                if new != 0:
                    slips += 1
                mode = new
            ev_list.append((te, mode))
            t = te
        s_h[k + 1] = y[2 * n]
        sd_h[k + 1] = y[2 * n + 1]
        af_h[k + 1] = floor_acc(mode, y)
        mode_h[k + 1] = mode
    return dict(
        s=s_h,
        sd=sd_h,
        a_f=af_h,
        mode=mode_h,
        peak_slide=peak_slide,
        residual_slide=s_h[-1],
        pfa=pfa,
        slips=slips,
        slide_time=slide_time,
        events=ev_list,
    )
