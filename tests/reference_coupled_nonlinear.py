"""Independent high-accuracy reference for a heavy rigid block coupled with its floor on a
building over a nonlinear isolation layer (lead-rubber or friction pendulum), 1-D.

Shares no code with floorslide (plain NumPy/SciPy; only the value of ``G``): SciPy's DOP853
integrates building, layer and block together over each step of the piecewise-linear record
separately (the forcing is smooth inside a step), restarting at every sample and at every change
of the layer's branch or of the block's phase, which ``solve_ivp`` locates as terminal events.
It joins the models of ``tests/reference_isolators.py`` (the layer) and
``tests/reference_coupled.py`` (the block), written again here.

Model (SI, coordinates relative to the ground; ``u[0]`` the base mat = the isolator's
displacement, ``u[i]`` floor ``i``; the block of mass ``m`` on DOF ``j``, its slide ``s``
relative to it)::

    M' u'' + Cs u' + Ks u + e0 f_iso = −M' 1 a_g + e_j σ mu_k m g      (σ = 0 while stuck)
    M' = M + m e_j e_jᵀ while the block sticks, M while it slides;
    s'' = −(u_j'' + a_g) − σ mu_k g while it slides, s' = 0 while it sticks.

Layers (``f_iso = k u0 + c u0' + q``):

* ``{"kind": "bilinear", "k1", "k2", "Q", "c"}``: ``k = k2``, ``q`` elastic-perfectly-plastic of
  stiffness ``k1 − k2`` and strength ``Q`` (elastic ``q = (k1 − k2)(u0 − p)``, plastic ``±Q``);
  the constants are the rubber's, whatever the block.
* ``{"kind": "friction_pendulum", "R", "mu", "mu_s", "c"}``: ``W = g (Σ M + m)`` (the pendulum
  carries the block's weight too), ``k = W/R``, sliding ``q = mu W sign(u0')``, stuck
  ``u0' = u0'' = 0`` with ``q = F_needed`` (the mat's equation with ``u0'' = 0``, the block's
  mass or friction reaction in it when it stands on the mat).

Events (terminal): yield (``q = ±Q``) and unloading (``u0' = 0``, unless the mat keeps loading:
a touch) of the rubber; breakaway (``|F_needed| = mu_s W``) and stop (``u0' = 0``; then stuck if
``|F_needed| ≤ mu_s W``, else reversed) of the pendulum; breakaway (``|a_f| = mu_s g``, ``a_f`` of
the system with the block stuck; toward ``σ = −sign a_f``) and stop (``s' = 0``; then stuck if
``|a_f| ≤ mu_s g``, else reversed) of the block. After every event (and at t = 0) a stuck part
beyond its friction limit breaks away at once (a pendulum's breakaway makes the mat's
acceleration jump; a block on the mat that slides changes the friction the pendulum needs).

Outputs: ``peak_slide`` (``s`` is monotone in a phase: piece ends), ``pfa`` (max ``|a_f|`` on each
piece's dense output, a grid refined by a bounded Brent search; both sides of a jump count),
``peak_isolator`` (piece ends and the roots of ``u0'`` in elastic pieces, non-terminal events),
histories at the samples (mode and branch after a change at a sample).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

G = 9.80665

_ELASTIC, _PLASTIC, _STICK, _SLIP = range(4)


def _from_zero(g, t0, order, limit):
    """``g / (t − t0)**order`` with its limit at ``t0``: an event function that starts from an
    exact zero (a phase starting on its switching surface) keeps its later roots but is nonzero
    at ``t0``, so that ``solve_ivp`` does not report the start itself."""

    def h(tt, yy):
        return limit if tt <= t0 else g(tt, yy) / (tt - t0) ** order

    h.terminal, h.direction = g.terminal, g.direction
    return h


def coupled_isolated_response(
    M, Ks, Cs, isolator, j, m, mu_k, mu_s, acc, dt, *, rtol=1e-12, atol=1e-15, grid=12
):
    """Response of a building on a nonlinear layer (``M = [m_b, m_1 …]``, ``Ks``, ``Cs`` the
    superstructure assembled on the mat's DOF, no layer term) with a block of mass ``m`` on
    DOF ``j`` (0 = the mat) to the piecewise-linear ground acceleration through ``acc`` at
    ``t = k·dt``; the building at rest, the block stuck, a pendulum stuck, rubber unstrained.

    Returns a dict: at the samples ``s``, ``sd``, ``a_f``, ``u0``, ``mode``, ``branch``; and
    ``peak_slide``, ``residual_slide``, ``pfa``, ``peak_isolator``, ``residual_isolator``,
    ``slips`` (block breakaways and reversals), ``iso_events``, ``slide_time``, ``events``.
    """
    M = np.asarray(M, dtype=float)
    Ks = np.asarray(Ks, dtype=float)
    Cs = np.asarray(Cs, dtype=float)
    acc = np.asarray(acc, dtype=float)
    n = M.size
    npts = acc.size
    iso = dict(isolator)
    kind = iso["kind"]
    ci = float(iso.get("c", 0.0))
    if kind == "bilinear":
        k1, k2, Q = float(iso["k1"]), float(iso["k2"]), float(iso["Q"])
        kh = k1 - k2
        klin = k2
        lim = None
    else:
        W = G * (M.sum() + m)
        klin = W / float(iso["R"])
        muW = float(iso["mu"]) * W
        lim = float(iso.get("mu_s", iso["mu"])) * W

    def masses(mode):
        Mm = M.copy()
        if mode == 0:
            Mm[j] += m
        return Mm

    def restoring(u, v):
        r = Ks @ u + Cs @ v
        r[0] += klin * u[0] + ci * v[0]
        return r

    def block_force(mode):
        f = np.zeros(n)
        f[j] = mode * mu_k * m * G
        return f

    def needed(br, mode, y, ag):
        """The friction a stuck pendulum needs (mat's equation with u0'' = 0)."""
        u, v = y[:n], y[n : 2 * n]
        r = restoring(u, v)
        return -masses(mode)[0] * ag - r[0] + block_force(mode)[0]

    def q_of(br, par, mode, y, ag):
        if br == _ELASTIC:
            return kh * (y[0] - par[0])
        if br in (_PLASTIC, _SLIP):
            return par * (Q if kind == "bilinear" else muW)
        return needed(br, mode, y, ag)

    def accel(br, par, mode, y, ag):
        u, v = y[:n], y[n : 2 * n]
        r = restoring(u, v)
        r[0] += q_of(br, par, mode, y, ag)
        a = (-r + block_force(mode)) / masses(mode) - ag
        if br == _STICK:
            a[0] = 0.0
        return a

    def floor_acc(br, par, mode, y, ag):
        return accel(br, par, mode, y, ag)[j] + ag

    def rhs(br, par, mode, a0, sl, t0):
        def f(t, y):
            ag = a0 + sl * (t - t0)
            a = accel(br, par, mode, y, ag)
            out = np.zeros_like(y)
            out[:n] = y[n : 2 * n]
            out[n : 2 * n] = a
            if br == _STICK:
                out[0] = 0.0
            if mode != 0:
                out[2 * n] = y[2 * n + 1]
                out[2 * n + 1] = -(a[j] + ag) - mode * mu_k * G
            return out

        return f

    def event_functions(br, par, mode, a0, sl, tk, t0, y0):
        """The piece's event functions (ground ``a0 + sl (t − tk)``, the piece from ``t0``)."""
        ag_start = a0 + sl * (t0 - tk)
        evs = []
        # the layer's
        if br == _ELASTIC:

            def vel(t, y):
                return y[n]

            vel.terminal, vel.direction = False, 0.0
            evs.append(("peak", vel))
            p, sa, ua = par

            def up(t, y):
                if sa > 0:
                    return kh * (y[0] - ua)
                return kh * (y[0] - p) - Q

            def lo(t, y):
                if sa < 0:
                    return -kh * (y[0] - ua)
                return -kh * (y[0] - p) - Q

            for ev in (up, lo):
                ev.terminal, ev.direction = True, 1.0
            if sa != 0.0 and y0[0] == ua:  # starts at the unload point, u0' = 0 there
                abase = accel(br, par, mode, y0, ag_start)[0]
                lims = sa * kh * abase / 2.0
                if sa > 0:
                    up = _from_zero(up, t0, 2, lims)
                else:
                    lo = _from_zero(lo, t0, 2, lims)
            evs += [("yield+", up), ("yield-", lo)]
        elif br == _STICK:

            def up(t, y):
                return needed(br, mode, y, a0 + sl * (t - tk)) - lim

            def lo(t, y):
                return -needed(br, mode, y, a0 + sl * (t - tk)) - lim

            for ev in (up, lo):
                ev.terminal, ev.direction = True, 1.0
            evs += [("slip+", up), ("slip-", lo)]
        else:  # plastic or sliding: u0' falls back through 0

            def stop(t, y, sg=par):
                return sg * y[n]

            stop.terminal, stop.direction = True, -1.0
            if y0[n] == 0.0:
                abase = accel(br, par, mode, y0, ag_start)[0]
                stop = _from_zero(stop, t0, 1, par * abase)
            evs.append(("iso_stop", stop))
        # the block's
        if mode == 0:

            def bup(t, y):
                return floor_acc(br, par, 0, y, a0 + sl * (t - tk)) - mu_s * G

            def bdn(t, y):
                return floor_acc(br, par, 0, y, a0 + sl * (t - tk)) + mu_s * G

            bup.terminal, bup.direction = True, 1.0
            bdn.terminal, bdn.direction = True, -1.0
            evs += [("break-", bup), ("break+", bdn)]
        else:

            def bstop(t, y):
                return y[2 * n + 1]

            bstop.terminal, bstop.direction = True, (-1.0 if mode > 0 else 1.0)
            evs.append(("block_stop", bstop))
        return evs

    counts = {"slips": 0, "iso_events": 0}
    ev_list = []

    def settle(br, par, mode, y, ag, t):
        for _ in range(4):
            changed = False
            if br == _STICK:
                F = needed(br, mode, y, ag)
                if abs(F) > lim:
                    br, par = _SLIP, (1.0 if F > 0 else -1.0)
                    y[n] = 0.0
                    counts["iso_events"] += 1
                    ev_list.append((t, "slip"))
                    changed = True
            if mode == 0:
                af = floor_acc(br, par, 0, y, ag)
                if abs(af) > mu_s * G:
                    mode = -1 if af > 0 else 1
                    y[2 * n + 1] = 0.0
                    counts["slips"] += 1
                    ev_list.append((t, "break"))
                    changed = True
            if not changed:
                break
        return br, par, mode

    def piece_peak(sol, br, par, mode, a0, sl, t0, ta, tb):
        def val(t):
            return abs(floor_acc(br, par, mode, sol.sol(t), a0 + sl * (t - t0)))

        ts = np.linspace(ta, tb, grid + 1)
        vals = np.array([val(t) for t in ts])
        i = int(np.argmax(vals))
        best = vals[i]
        lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, grid)]
        if hi > lo:
            r = minimize_scalar(
                lambda t: -val(t),
                bounds=(lo, hi),
                method="bounded",
                options={"xatol": 1e-14 * max(1.0, tb)},
            )
            best = max(best, -r.fun)
        return best

    y = np.zeros(2 * n + 2)
    br, par = (_ELASTIC, (0.0, 0.0, 0.0)) if kind == "bilinear" else (_STICK, 0.0)
    mode = 0
    br, par, mode = settle(br, par, mode, y, acc[0], 0.0)
    hist = {k: np.zeros(npts) for k in ("s", "sd", "a_f", "u0")}
    mode_h = np.zeros(npts, dtype=int)
    branch_h = np.zeros(npts, dtype=int)
    hist["a_f"][0] = floor_acc(br, par, mode, y, acc[0])
    peak_slide = 0.0
    pfa = abs(hist["a_f"][0])
    peak_iso = 0.0
    slide_time = 0.0
    for k in range(npts - 1):
        t0 = k * dt
        t1 = (k + 1) * dt
        a0 = acc[k]
        sl = (acc[k + 1] - a0) / dt
        t = t0
        for guard in range(201):
            if guard == 200:
                raise RuntimeError(f"more than 200 events in step {k}")
            evs = event_functions(br, par, mode, a0, sl, t0, t, y)
            sol = solve_ivp(
                rhs(br, par, mode, a0, sl, t0),
                (t, t1),
                y,
                method="DOP853",
                rtol=rtol,
                atol=atol,
                events=[e for _, e in evs],
                dense_output=True,
            )
            if not sol.success:
                raise RuntimeError(sol.message)
            for i, (name, _e) in enumerate(evs):
                if name == "peak":
                    for ye in sol.y_events[i]:
                        peak_iso = max(peak_iso, abs(ye[0]))
            hit = [
                (sol.t_events[i][0], i)
                for i, (name, _e) in enumerate(evs)
                if name != "peak" and sol.t_events[i].size
            ]
            if hit:
                te, ie = min(hit)
                y_end = sol.y_events[ie][0].copy()
            else:
                te, ie = t1, -1
                y_end = sol.y[:, -1].copy()
            pfa = max(pfa, piece_peak(sol, br, par, mode, a0, sl, t0, t, te))
            if mode != 0:
                slide_time += te - t
            y = y_end
            peak_slide = max(peak_slide, abs(y[2 * n]))
            peak_iso = max(peak_iso, abs(y[0]))
            if not hit:
                break
            name = evs[ie][0]
            ag = a0 + sl * (te - t0)
            if name in ("yield+", "yield-"):
                br, par = _PLASTIC, (1.0 if name == "yield+" else -1.0)
                counts["iso_events"] += 1
            elif name == "iso_stop":
                y[n] = 0.0
                if br == _PLASTIC:
                    a = accel(br, par, mode, y, ag)
                    if par * a[0] < 0.0:
                        br, par = _ELASTIC, (y[0] - par * Q / kh, par, y[0])
                        counts["iso_events"] += 1
                else:
                    F = needed(_STICK, mode, y, ag)
                    if -lim <= F <= lim:
                        br, par = _STICK, 0.0
                    else:
                        br, par = _SLIP, (1.0 if F > 0 else -1.0)
                    counts["iso_events"] += 1
            elif name in ("slip+", "slip-"):
                br, par = _SLIP, (1.0 if name == "slip+" else -1.0)
                counts["iso_events"] += 1
            elif name in ("break-", "break+"):
                y[2 * n + 1] = 0.0
                mode = -1 if name == "break-" else 1
                counts["slips"] += 1
            else:  # the block stops
                y[2 * n + 1] = 0.0
                af = floor_acc(br, par, 0, y, ag)
                new = -1 if af > mu_s * G else (1 if af < -mu_s * G else 0)
                if new != 0:
                    counts["slips"] += 1
                mode = new
            ev_list.append((te, name))
            br, par, mode = settle(br, par, mode, y, ag, te)
            t = te
            if t >= t1:
                break
        hist["s"][k + 1] = y[2 * n]
        hist["sd"][k + 1] = y[2 * n + 1]
        hist["a_f"][k + 1] = floor_acc(br, par, mode, y, acc[k + 1])
        hist["u0"][k + 1] = y[0]
        mode_h[k + 1] = mode
        branch_h[k + 1] = br
    return dict(
        hist,
        mode=mode_h,
        branch=branch_h,
        peak_slide=peak_slide,
        residual_slide=hist["s"][-1],
        pfa=pfa,
        peak_isolator=peak_iso,
        residual_isolator=hist["u0"][-1],
        slips=counts["slips"],
        iso_events=counts["iso_events"],
        slide_time=slide_time,
        events=ev_list,
    )
