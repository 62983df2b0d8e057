"""Independent high-accuracy reference for base-isolated shear buildings with nonlinear
isolators (linear, bilinear lead-rubber, friction pendulum).

Like ``tests/reference.py`` it shares no code with floorslide: SciPy's DOP853 integrates each
step of the piecewise-linear record separately (the forcing is smooth inside a step), restarting
at every sample and at every branch change of the isolator, which ``solve_ivp`` locates as a
terminal event.

Model (SI, coordinates relative to the ground; ``u[0]`` = base mat = isolator displacement,
``u[i]`` = floor ``i``)::

    M u'' + Cs u' + Ks u + e0 f_iso = -M 1 a_g(t),      M = diag(m_b, m_1 .. m_N)

``Ks``, ``Cs``: the superstructure alone assembled on the base DOF (no isolator term). ``N = 0``
(the base mass alone, ``Ks = Cs = [[0]]``) is allowed. ``W = g (m_b + Σ m_i)``.

Isolators (all with an optional viscous term ``c u0'``):

* ``{"kind": "linear", "k", "c"}``: ``f = k u0 + c u0'``.
* ``{"kind": "bilinear", "k1", "k2", "Q", "c"}`` (Kelly 1996; Naeim & Kelly 1999):
  ``f = k2 u0 + c u0' + q`` with ``q`` elastic-perfectly-plastic, stiffness ``k1 - k2``,
  strength ``Q``. Branches: *elastic* (``q = (k1 - k2)(u0 - p)``, ``p`` frozen) and *plastic*
  (``q = ±Q``). Events: ``q ∓ Q`` while elastic ("yield"), ``u0'`` while plastic ("unload").
* ``{"kind": "friction_pendulum", "R", "mu", "mu_s", "c"}`` (Zayas et al. 1990):
  ``f = (W/R) u0 + c u0' + F``. Sliding: ``F = mu W sign(u0')``. Stuck: ``u0' = u0'' = 0`` and
  ``F = F_needed`` (the base equation with ``u0'' = 0``). Events: ``u0'`` while sliding
  ("stick" or "reverse"), ``|F_needed| - mu_s W`` while stuck ("slip"). Starts stuck.

Modelling decisions (documented here, relied on by the tests):

* FPS at the limit: one threshold ``lim = mu_s W (1 + stick_rtol)`` (``stick_rtol = 1e-9``)
  decides both breakaway (``|F_needed| > lim``) and sticking at a velocity zero
  (``|F_needed| <= lim``). A slider that stops exactly at the friction limit (free decay ending at
  ``|u0| = mu R``) therefore sticks, whatever the last rounding bit of ``F_needed``; the bias is
  1e-9 relative on the breakaway force.
* ``mu_s`` defaults to ``mu``; ``mu_s < mu`` is refused. ``mu = 0`` is allowed (then the slider
  sticks only where ``F_needed`` is exactly 0).
* At a sample where the branch changes, the sample outputs (``a_abs``, ``f_iso``, ``q``/``F``)
  are those of the branch *after* the sample (a breakaway at the sample is applied before the
  sample is recorded). Only the FPS has a jump there (the base acceleration at stick/slip);
  the bilinear force is continuous.
* Bilinear initial displacement beyond yield (``u0`` argument): the element starts at its
  strength (``p = u0 - sign(u0) Q/(k1 - k2)``), at rest on its yield point: it unloads
  elastically, or yields at once if the base accelerates outwards.
* A velocity zero in the plastic branch at which the base keeps accelerating in the loading
  direction (a touch) does not unload.
* At a velocity zero ("stick", "reverse", "unload") ``u0'`` is set to exactly 0 (a change at
  rounding level), and an event function of the new phase that starts from an exact zero (the
  stop event after a breakaway or reversal, the reload event after an unload) is divided by
  ``(t - t0)`` or ``(t - t0)²`` (``_from_zero``): ``solve_ivp`` otherwise reports a later
  crossing inside its first step at ``t0`` itself, which chatters.
* ``peak_isolator``: max ``|u0|`` over the segment ends and the roots of ``u0'`` located by
  ``solve_ivp`` as (non-terminal) events on the dense output — exact to the integration
  accuracy, not a sampled maximum. In plastic / sliding / stuck phases ``u0`` is monotone, so
  the ends suffice. ``peak_force_ratio``: max ``|f_iso| / W`` over the same points and the
  samples.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

G = 9.80665

# branches
_LIN, _ELASTIC, _PLASTIC, _STICK, _SLIP = range(5)
_PHASE_NAMES = {
    _LIN: "linear",
    _ELASTIC: "elastic",
    _PLASTIC: "plastic",
    _STICK: "stuck",
    _SLIP: "sliding",
}


class _Isolator:
    def __init__(self, spec, W):
        spec = dict(spec)
        self.kind = spec.pop("kind")
        self.c = float(spec.pop("c", 0.0) or 0.0)
        if self.kind == "linear":
            self.klin = float(spec.pop("k"))
        elif self.kind == "bilinear":
            self.k1 = float(spec.pop("k1"))
            self.k2 = float(spec.pop("k2"))
            self.Q = float(spec.pop("Q"))
            if not self.k1 > self.k2 >= 0.0 or not self.Q > 0.0:
                raise ValueError("bilinear isolator needs k1 > k2 >= 0 and Q > 0")
            self.klin = self.k2
            self.kh = self.k1 - self.k2
            self.fy = self.Q
        elif self.kind == "friction_pendulum":
            self.R = float(spec.pop("R"))
            self.mu = float(spec.pop("mu"))
            mu_s = spec.pop("mu_s", None)
            self.mu_s = self.mu if mu_s is None else float(mu_s)
            if self.mu < 0.0 or self.mu_s < self.mu:
                raise ValueError("friction pendulum needs 0 <= mu <= mu_s")
            self.klin = W / self.R
            self.fy = self.mu * W
        else:
            raise ValueError(f"unknown isolator kind {self.kind!r}")
        if spec:
            raise ValueError(f"unknown isolator parameters {sorted(spec)}")


def isolated_response(
    masses,
    Ks,
    Cs,
    isolator,
    acc,
    dt,
    *,
    rtol=1e-12,
    atol=1e-15,
    u0=None,
    stick_rtol=1e-9,
    max_events=200,
):
    """Response of a base-isolated shear building with a (nonlinear) isolator to the
    piecewise-linear ground acceleration through ``acc`` (m/s²) at ``t = k dt``.

    ``masses = [m_b, m_1 .. m_N]``; ``Ks``, ``Cs`` the (N+1)×(N+1) superstructure matrices on
    the base DOF; ``isolator`` a dict (see the module docstring); ``u0`` an optional initial
    displacement vector (velocities start at 0). ``max_events`` caps the branch changes inside
    one record step (chattering guard: a RuntimeError beyond it).

    Returns a dict with, at the samples: ``t``, ``u``, ``v`` (npts × N+1, relative),
    ``a_abs`` (absolute accelerations of floors 0..N from the equations of motion, branch after
    the sample), ``f_iso``, ``q`` (bilinear) or ``F`` (FPS), ``phase`` (branch names), and
    ``energy`` (dict of arrays: ``input`` = -∫ a_g 1ᵀM u' dt, ``kinetic``, ``strain``,
    ``viscous`` = ∫ (u'ᵀCs u' + c u0'²) dt, ``dissipated`` = Q Σ|Δu0| over plastic phases or
    mu W Σ|Δu0| over sliding phases (bookkeeping of the branches, not a quadrature),
    ``isolator_work`` = ∫ (q or F) u0' dt (quadrature), and the scalar ``initial`` = the initial
    strain energy); plus ``events`` (list of ``(t, kind)``), ``event_u0`` (u0 at each event),
    ``W``, ``peak_isolator``, ``residual_isolator``, ``peak_force_ratio``.
    """
    m = np.atleast_1d(np.asarray(masses, dtype=float))
    n = m.size
    Ks = np.asarray(Ks, dtype=float).reshape(n, n)
    Cs = np.asarray(Cs, dtype=float).reshape(n, n)
    acc = np.asarray(acc, dtype=float).ravel()
    npts = acc.size
    W = G * m.sum()
    iso = _Isolator(isolator, W)
    m0, klin, ci = m[0], iso.klin, iso.c
    lim = iso.mu_s * W * (1.0 + stick_rtol) if iso.kind == "friction_pendulum" else None

    y = np.zeros(2 * n + 3)  # [u, v, input energy, viscous energy, isolator work]
    if u0 is not None:
        y[:n] = np.asarray(u0, dtype=float).ravel()
    # branch parameter: elastic (p, s_anchor, u_anchor), plastic / sliding the sign, else 0
    if iso.kind == "linear":
        br, par = _LIN, 0.0
    elif iso.kind == "bilinear":
        br, par = _ELASTIC, (0.0, 0.0, 0.0)
        if iso.kh * abs(y[0]) > iso.Q:  # released beyond yield: at its strength, anchored
            sg = float(np.sign(y[0]))
            br, par = _ELASTIC, (y[0] - sg * iso.Q / iso.kh, sg, y[0])
    else:
        br, par = _STICK, 0.0

    def restoring(u, v):
        """Linear forces (superstructure + linear isolator terms) and their viscous part."""
        rc = Cs @ v
        rc[0] += ci * v[0]
        r = rc + Ks @ u
        r[0] += klin * u[0]
        return r, rc

    def f_nl(br, par, u, r0, ag):
        """The hysteretic / friction force q or F."""
        if br == _ELASTIC:
            return iso.kh * (u[0] - par[0])
        if br in (_PLASTIC, _SLIP):
            return par * iso.fy
        if br == _STICK:
            return -m0 * ag - r0  # F_needed: the base equation with u0'' = 0 (u0' = 0)
        return 0.0

    def accel(br, par, u, v, ag):
        r, rc = restoring(u, v)
        f = f_nl(br, par, u, r[0], ag)
        a = -ag - r / m
        a[0] -= f / m0
        if br == _STICK:
            a[0] = 0.0
        return a, f, rc

    def strain(u, br, par):
        e = 0.5 * u @ Ks @ u + 0.5 * klin * u[0] ** 2
        if iso.kind == "bilinear":
            q = f_nl(br, par, u, 0.0, 0.0)
            e += 0.5 * q * q / iso.kh
        return e

    def settle(br, par, y, ag, t_abs):
        """Phase-start check: a stuck slider whose F_needed is beyond the limit breaks away; an
        element at rest on its yield point (a release beyond yield) and loaded further yields."""
        if br == _ELASTIC and par[1] != 0.0 and y[0] == par[2] and y[n] == 0.0:
            if par[1] * accel(br, par, y[:n], y[n : 2 * n], ag)[0][0] > 0.0:
                events.append((t_abs, "yield"))
                event_u0.append(y[0])
                return _PLASTIC, par[1]
        if br == _STICK:
            r, _ = restoring(y[:n], y[n : 2 * n])
            F = -m0 * ag - r[0]
            if F > lim or F < -lim:
                events.append((t_abs, "slip"))
                event_u0.append(y[0])
                return _SLIP, (1.0 if F > 0 else -1.0)
        return br, par

    out_u = np.zeros((npts, n))
    out_v = np.zeros((npts, n))
    out_a = np.zeros((npts, n))
    out_f = np.zeros(npts)
    out_nl = np.zeros(npts)
    phase = []
    e_names = ("input", "kinetic", "strain", "viscous", "dissipated", "isolator_work")
    energy = {k: np.zeros(npts) for k in e_names}
    events, event_u0 = [], []
    dissipated = 0.0
    e_initial = strain(y[:n], br, par)
    peak = abs(y[0])
    peak_f = 0.0

    def record(k, y, br, par, ag):
        nonlocal peak_f
        u, v = y[:n], y[n : 2 * n]
        a, f, _ = accel(br, par, u, v, ag)
        fiso = klin * u[0] + ci * v[0] + f
        out_u[k], out_v[k], out_a[k] = u, v, a + ag
        out_f[k], out_nl[k] = fiso, f
        phase.append(_PHASE_NAMES[br])
        peak_f = max(peak_f, abs(fiso))
        energy["input"][k] = y[2 * n]
        energy["viscous"][k] = y[2 * n + 1]
        energy["isolator_work"][k] = y[2 * n + 2]
        energy["kinetic"][k] = 0.5 * v @ (m * v)
        energy["strain"][k] = strain(u, br, par)
        energy["dissipated"][k] = dissipated

    def point(yy, br, par):
        """Peaks at an in-step point (a segment end or a root of u0'); a stuck phase has its
        extremes at its ends, where the neighbouring phases or the samples see them."""
        nonlocal peak, peak_f
        peak = max(peak, abs(yy[0]))
        if br != _STICK:
            fiso = klin * yy[0] + ci * yy[n] + f_nl(br, par, yy[:n], 0.0, 0.0)
            peak_f = max(peak_f, abs(fiso))

    for k in range(npts - 1):
        a0 = acc[k]
        s = (acc[k + 1] - a0) / dt
        t = 0.0
        br, par = settle(br, par, y, a0, k * dt)
        record(k, y, br, par, a0)
        for nev in range(max_events + 1):
            if nev == max_events:
                raise RuntimeError(
                    f"isolated_response: more than {max_events} branch changes in the record "
                    f"step starting at t = {k * dt:.6g} s (chattering); last events "
                    f"{events[-4:]}"
                )
            br, par = settle(br, par, y, a0 + s * t, k * dt + t)

            def rhs(tt, yy, br=br, par=par, a0=a0, s=s):
                ag = a0 + s * tt
                u, v = yy[:n], yy[n : 2 * n]
                a, f, rc = accel(br, par, u, v, ag)
                out = np.empty(2 * n + 3)
                out[:n] = v
                out[n : 2 * n] = a
                out[2 * n] = -ag * (m @ v)
                out[2 * n + 1] = v @ rc
                out[2 * n + 2] = f * v[0]
                if br == _STICK:
                    out[0] = 0.0
                return out

            abase = accel(br, par, y[:n], y[n : 2 * n], a0 + s * t)[0][0]
            evs, terminal = _events(br, par, n, iso, lim, m0, a0, s, restoring, t, y, abase)
            y_start = y
            sol = solve_ivp(
                rhs, (t, dt), y, method="DOP853", rtol=rtol, atol=atol, events=evs or None
            )
            if not sol.success:
                raise RuntimeError(f"isolated_response: solve_ivp failed: {sol.message}")
            for i, ev in enumerate(evs):
                if not ev.terminal:
                    for ye in sol.y_events[i]:
                        point(ye, br, par)
            y = sol.y[:, -1].copy()
            t = sol.t[-1]
            point(y, br, par)
            if br in (_PLASTIC, _SLIP):
                dissipated += par * iso.fy * (y[0] - y_start[0])
            if sol.status != 1:
                break
            i_ev = next(i for i in terminal if sol.t_events[i].size)
            ag = a0 + s * t
            t_abs = k * dt + t
            if br == _ELASTIC:
                br, par = _PLASTIC, (1.0 if i_ev == terminal[0] else -1.0)
                events.append((t_abs, "yield"))
                event_u0.append(y[0])
            elif br == _PLASTIC:
                # u0' = 0 (to the last bit: the next phase's events start from exact zeros)
                y[n] = 0.0
                a = accel(br, par, y[:n], y[n : 2 * n], ag)[0]
                if par * a[0] < 0.0:
                    br, par = _ELASTIC, (y[0] - par * iso.Q / iso.kh, par, y[0])
                    events.append((t_abs, "unload"))
                    event_u0.append(y[0])
                # else a touch: the base keeps loading, the element stays plastic
            elif br == _STICK:
                br, par = _SLIP, (1.0 if i_ev == terminal[0] else -1.0)
                events.append((t_abs, "slip"))
                event_u0.append(y[0])
            elif br == _SLIP:
                y[n] = 0.0
                r, _ = restoring(y[:n], y[n : 2 * n])
                F = -m0 * ag - r[0]
                if -lim <= F <= lim:
                    br, par = _STICK, 0.0
                    events.append((t_abs, "stick"))
                else:
                    br, par = _SLIP, (1.0 if F > 0 else -1.0)
                    events.append((t_abs, "reverse"))
                event_u0.append(y[0])
            if t >= dt * (1 - 1e-14):
                break
    br, par = settle(br, par, y, acc[-1], (npts - 1) * dt)
    record(npts - 1, y, br, par, acc[-1])

    res = {
        "t": np.arange(npts) * dt,
        "u": out_u,
        "v": out_v,
        "a_abs": out_a,
        "f_iso": out_f,
        "phase": np.array(phase),
        "energy": dict(energy, initial=e_initial),
        "events": events,
        "event_u0": np.array(event_u0),
        "W": W,
        "peak_isolator": peak,
        "residual_isolator": y[0],
        "peak_force_ratio": peak_f / W,
    }
    if iso.kind == "bilinear":
        res["q"] = out_nl
    elif iso.kind == "friction_pendulum":
        res["F"] = out_nl
    return res


def _from_zero(g, t0, order, limit):
    """``g(t) / (t - t0)**order`` with its limit at ``t0``: an event function that starts from
    an exact zero of that order (a phase beginning on its own switching surface). Same sign and
    roots after ``t0``, but nonzero at ``t0``, so that ``solve_ivp`` (which would otherwise put
    the root of a later crossing inside its first step at ``t0`` itself) finds the true one."""

    def h(tt, yy):
        return limit if tt <= t0 else g(tt, yy) / (tt - t0) ** order

    h.terminal, h.direction = g.terminal, g.direction
    return h


def _events(br, par, n, iso, lim, m0, a0, s, restoring, t0, y0, abase):
    """Event functions of a branch; returns (events, indices of the terminal ones) — the
    terminal ones in the order (upper, lower) where there are two. ``abase``: the base
    acceleration at the phase start ``(t0, y0)``, for the limits of `_from_zero`."""
    evs = []
    if br in (_LIN, _ELASTIC):

        def vel(tt, yy):
            return yy[n]

        vel.terminal = False
        vel.direction = 0.0
        evs.append(vel)
    if br == _ELASTIC:
        p, sa, ua = par

        def up(tt, yy):
            if sa > 0:  # measured from the unload point: an exact zero there
                return iso.kh * (yy[0] - ua)
            return iso.kh * (yy[0] - p) - iso.Q

        def lo(tt, yy):
            if sa < 0:
                return -iso.kh * (yy[0] - ua)
            return -iso.kh * (yy[0] - p) - iso.Q

        for ev in (up, lo):
            ev.terminal, ev.direction = True, 1.0
        if sa != 0.0 and y0[0] == ua:  # the phase starts at the unload point (u0' = 0 there)
            i = 0 if sa > 0 else 1
            lims = sa * iso.kh * abase / 2.0
            up, lo = [
                _from_zero(ev, t0, 2, lims) if j == i else ev for j, ev in enumerate((up, lo))
            ]
        evs += [up, lo]
    elif br == _STICK:

        def needed(tt, yy):
            r, _ = restoring(yy[:n], yy[n : 2 * n])
            return -m0 * (a0 + s * tt) - r[0]

        def up(tt, yy):
            return needed(tt, yy) - lim

        def lo(tt, yy):
            return -needed(tt, yy) - lim

        for ev in (up, lo):
            ev.terminal, ev.direction = True, 1.0
        evs += [up, lo]
    elif br in (_PLASTIC, _SLIP):

        def stop(tt, yy, sg=par):
            return sg * yy[n]

        stop.terminal, stop.direction = True, -1.0
        if y0[n] == 0.0:  # from rest (breakaway, reversal, or a touch): an exact zero
            stop = _from_zero(stop, t0, 1, par * abase)
        evs.append(stop)
    terminal = [i for i, ev in enumerate(evs) if ev.terminal]
    return evs, terminal


def bilinear_loop(D, k1, k2, Q, n=20001):
    """The bilinear element alone under the displacement cycle 0 → D → -D → D (``n`` points on
    0 → D, ``2n - 1`` more on each of the other two legs), by the return mapping of the
    elastic-perfectly-plastic part (exact at the grid points, the legs being monotone).

    Returns a dict: ``u``, ``q`` (the hysteretic part), ``f = k2 u + q``, ``energy`` = ∮ f du over
    the closed cycle D → -D → D (trapezoid on the grid), ``energy_path`` = ∫ f du over the whole
    path from 0.
    """
    kh = k1 - k2
    u = np.concatenate(
        [
            np.linspace(0.0, D, n),
            np.linspace(D, -D, 2 * n - 1)[1:],
            np.linspace(-D, D, 2 * n - 1)[1:],
        ]
    )
    q = np.zeros_like(u)
    for i in range(1, u.size):
        q[i] = min(max(q[i - 1] + kh * (u[i] - u[i - 1]), -Q), Q)
    f = k2 * u + q
    work = 0.5 * (f[1:] + f[:-1]) * np.diff(u)
    return {
        "u": u,
        "q": q,
        "f": f,
        "energy": float(work[n - 1 :].sum()),
        "energy_path": float(work.sum()),
    }
