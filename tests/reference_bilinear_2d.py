"""Independent high-accuracy reference for a shear building on lead-rubber (bilinear) bearings
under two horizontal ground components (a bidirectional layer with a circular yield surface).

Like ``tests/reference_isolators_2d.py`` it shares no code with floorslide (plain NumPy and
SciPy): SciPy's DOP853 integrates each step of the piecewise-linear records separately,
restarting at every sample and at every change of branch, which ``solve_ivp`` locates as a
terminal event on its dense output. It is the reference the exact lead-rubber layer in the
plane is checked against (docs/design.md §10b, "In the plane").

Model (SI, coordinates relative to the ground; per direction ``d`` = x, y: ``u_d[0]`` the mat,
``u_d[i]`` floor ``i``; the superstructure may differ per direction, the masses are shared)::

    M u_d'' + Cs_d u_d' + Ks_d u_d + e0 (k2 u_d[0] + c u_d[0]' + q_d) = -M 1 a_gd(t)

with the plastic element's force ``q = (q_x, q_y)``, ``|q| <= Q``, ``k_e = k1 - k2``:

* elastic (``|q| < Q``, or ``|q| = Q`` unloading): ``q' = k_e V`` (``V`` the mat's velocity);
* plastic (``|q| = Q`` and ``q·V > 0``): ``q' = k_e (V - (q·V) q / Q²)`` — the associated flow
  of a circular yield surface without hardening (Simo & Hughes 1998, §2.3).

Events: *yield* where ``|q|² - Q²`` crosses 0 upwards on the elastic branch; *unload* where
``q·V`` crosses 0 downwards on the plastic branch. At every restart on the plastic branch ``q``
is set back to length ``Q``. The plastic work ``∫ q·V dt`` over the plastic branch is
integrated as one more state.

Returns the floors' displacements, velocities and absolute accelerations and ``q`` at the
samples, the events and the plastic work.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

G = 9.80665
_ELASTIC, _PLASTIC = 0, 1


def bilinear_response_2d(
    masses,
    Ks,
    Cs,
    isolator: dict,
    acc_x,
    acc_y,
    dt: float,
    *,
    rtol: float = 1e-12,
    atol: float = 1e-15,
    max_events: int = 200,
):
    """Response of a shear building on a bidirectional bilinear layer to the two
    piecewise-linear ground components ``acc_x``, ``acc_y`` (m/s², samples at ``k dt``), from
    rest.

    ``masses = [m_b, m_1 .. m_N]``; ``Ks``, ``Cs``: one ``(N+1)×(N+1)`` matrix for both
    directions (assembled on the mat, without the isolator), or a pair ``(x, y)``;
    ``isolator = {"k1", "k2", "Q", "c"?}``. Returns a dict: ``t``, ``ux``, ``uy``, ``vx``,
    ``vy``, ``accx``, ``accy`` (absolute accelerations; all npts × N+1), ``q`` (npts × 2),
    ``branch`` per sample, ``events`` (``(t, "yield" | "unload")``), ``plastic_work``.
    """
    m = np.atleast_1d(np.asarray(masses, dtype=float))
    n = m.size
    pair = lambda M: (M, M) if np.ndim(M) == 2 else (M[0], M[1])  # noqa: E731
    Kx, Ky = (np.asarray(M, dtype=float).reshape(n, n) for M in pair(Ks))
    Cx, Cy = (np.asarray(M, dtype=float).reshape(n, n) for M in pair(Cs))
    ax = np.asarray(acc_x, dtype=float).ravel()
    ay = np.asarray(acc_y, dtype=float).ravel()
    if ax.size != ay.size:
        raise ValueError("the two components must have as many samples")
    npts = ax.size
    k1 = float(isolator["k1"])
    k2 = float(isolator["k2"])
    Q = float(isolator["Q"])
    c_iso = float(isolator.get("c", 0.0) or 0.0)
    ke = k1 - k2

    # state: [ux (n), uy (n), vx (n), vy (n), qx, qy, plastic work]
    iq = 4 * n
    y = np.zeros(4 * n + 3)

    def forces(u, v, q, K, C):
        r = C @ v + K @ u
        r[0] += k2 * u[0] + c_iso * v[0] + q
        return r

    def accelerations(y):
        """The floors' absolute accelerations (x, y) at a state."""
        ux, uy, vx, vy = y[:n], y[n : 2 * n], y[2 * n : 3 * n], y[3 * n : 4 * n]
        return (-forces(ux, vx, y[iq], Kx, Cx) / m, -forces(uy, vy, y[iq + 1], Ky, Cy) / m)

    def rhs(branch, t0, a0, s):
        def f(t, y):
            agx = a0[0] + s[0] * (t - t0)
            agy = a0[1] + s[1] * (t - t0)
            out = np.empty_like(y)
            out[: 2 * n] = y[2 * n : 4 * n]
            fx, fy = accelerations(y)
            out[2 * n : 3 * n] = fx - agx
            out[3 * n : 4 * n] = fy - agy
            V = np.array([y[2 * n], y[3 * n]])
            q = y[iq : iq + 2]
            if branch == _PLASTIC:
                qv = q @ V
                out[iq : iq + 2] = ke * (V - qv * q / (Q * Q))
                out[iq + 2] = qv
            else:
                out[iq : iq + 2] = ke * V
                out[iq + 2] = 0.0
            return out

        return f

    def yielding(t, y):
        return y[iq] ** 2 + y[iq + 1] ** 2 - Q * Q

    def unloading(t, y):
        return y[iq] * y[2 * n] + y[iq + 1] * y[3 * n]

    yielding.terminal, yielding.direction = True, 1
    unloading.terminal, unloading.direction = True, -1

    t_out = np.arange(npts) * dt
    out = {k: np.empty((npts, n)) for k in ("ux", "uy", "vx", "vy", "accx", "accy")}
    qs = np.empty((npts, 2))
    branches = []
    events = []
    branch = _ELASTIC

    def record(kk):
        out["ux"][kk], out["uy"][kk] = y[:n], y[n : 2 * n]
        out["vx"][kk], out["vy"][kk] = y[2 * n : 3 * n], y[3 * n : 4 * n]
        out["accx"][kk], out["accy"][kk] = accelerations(y)
        qs[kk] = y[iq : iq + 2]
        branches.append("plastic" if branch == _PLASTIC else "elastic")

    record(0)
    for kk in range(npts - 1):
        t0, t1 = t_out[kk], t_out[kk + 1]
        sx = (ax[kk + 1] - ax[kk]) / dt
        sy = (ay[kk + 1] - ay[kk]) / dt
        t = t0
        count = 0
        while t < t1:
            a0 = (ax[kk] + sx * (t - t0), ay[kk] + sy * (t - t0))
            if branch == _PLASTIC:
                y[iq : iq + 2] *= Q / np.hypot(y[iq], y[iq + 1])
            sol = solve_ivp(
                rhs(branch, t, a0, (sx, sy)), (t, t1), y, method="DOP853", rtol=rtol,
                atol=atol, events=[unloading if branch == _PLASTIC else yielding],
                first_step=min(1e-6, (t1 - t) / 4) if t > t0 else None,
            )  # fmt: skip
            if sol.status < 0:
                raise RuntimeError(sol.message)
            y = sol.y[:, -1].copy()
            if sol.status == 0 or sol.t[-1] >= t1:
                break
            t = sol.t[-1]
            count += 1
            if count > max_events:
                raise RuntimeError(f"more than {max_events} events in the step at t = {t0}")
            if branch == _PLASTIC:
                branch = _ELASTIC
                events.append((t, "unload"))
            else:
                branch = _PLASTIC
                events.append((t, "yield"))
        if branch == _PLASTIC:
            y[iq : iq + 2] *= Q / np.hypot(y[iq], y[iq + 1])
        record(kk + 1)
    return {
        "t": t_out,
        **out,
        "q": qs,
        "branch": branches,
        "events": events,
        "plastic_work": float(y[iq + 2]),
    }
