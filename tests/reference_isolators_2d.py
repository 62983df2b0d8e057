"""Independent high-accuracy reference for a shear building on friction pendulums under two
horizontal ground components (a bidirectional layer: one vector displacement of the mat).

Like ``tests/reference_isolators.py`` it shares no code with floorslide (only the constant
``G``): SciPy's DOP853 integrates each step of the piecewise-linear records separately,
restarting at every sample and at every phase change, which ``solve_ivp`` locates as a terminal
event on its dense output. It is the reference the bidirectional layer of floorslide is checked
against (docs/design.md, "isolators in the plane").

Model (SI, coordinates relative to the ground; per direction ``d`` = x, y: ``u_d[0]`` the mat,
``u_d[i]`` floor ``i``; the superstructure may differ per direction, the masses are shared)::

    M u_d'' + Cs_d u_d' + Ks_d u_d + e0 (k u_d[0] + c u_d[0]' + F_d) = -M 1 a_gd(t)

with ``k = W/R`` (the pendulum's small-angle restoring stiffness, ``W = g Σm``) and the friction
``F = (F_x, F_y)`` on the mat:

* sliding: ``F = mu W V/|V|``, ``V = (u_x[0]', u_y[0]')`` the mat's velocity;
* stuck: ``V = V' = 0`` and ``F = F_needed`` (each direction's mat equation with ``u0'' = u0' =
  0``); stuck while ``|F_needed| <= mu_s W (1 + stick_rtol)`` — the friction circle. A
  breakaway (``|F_needed|`` crossing the limit upwards) starts a slide along
  ``F_needed/|F_needed|``.

A slide is integrated as in ``tests/reference_sliding2d.py``: each slide segment fixes a unit
vector ``e`` (the mat velocity's direction at the segment start) and uses the friction
direction ``n = sign(p) V/|V|`` with ``p = V·e``; the *stop* is the transversal crossing
``p = 0`` (direction −1), and a *turn* event ``p − |V|/2`` (direction −1) restarts the segment
with ``e`` = the new direction once the velocity has turned 60° away, so a stop is only reported
with ``|V| = 0`` to the root finder's accuracy (a turn at a speed below ``1e-9·max|a|·dt``,
where the direction of a rounding-size velocity wanders, is taken as the stop it is). At a
stop the mat sticks if ``|F_needed|`` is inside the circle, else it slides on at once along
``F_needed/|F_needed|``. From rest the
friction direction is ``e`` itself until ``|V|`` leaves zero (``V = c τ e + O(τ²)``), and so
is it while the velocity's component across ``e`` is below ``1e-12`` of the one along it plus
``1e-12·max|a|·dt`` (a rounding-size cross velocity would make the equations stiff near every
stop and start, at the rate ``mu g/|V|``).

Returns the mat's and floors' displacements and velocities at the samples, the mat's peak
displacement magnitude (over the segment ends and the samples — a lower bound of the true peak
within the integration accuracy where it is a smooth maximum between samples; the tests use
samples), the residual vector, the events and the friction work.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

G = 9.80665
_STUCK, _SLIDE = 0, 1


def isolated_response_2d(
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
    mat_displacement=(0.0, 0.0),
    mat_velocity=(0.0, 0.0),
    stick_rtol: float = 1e-9,
    max_events: int = 200,
):
    """Response of a shear building on friction pendulums to the two piecewise-linear ground
    components ``acc_x``, ``acc_y`` (m/s², samples at ``k dt``).

    ``masses = [m_b, m_1 .. m_N]``; ``Ks``, ``Cs``: one ``(N+1)×(N+1)`` matrix for both
    directions, or a pair ``(x, y)``; ``isolator = {"R", "mu", "mu_s"?, "c"?}``;
    ``mat_displacement``/``mat_velocity``: the mat's initial state (the floors start at rest
    relative to the ground, displaced with the mat). Returns a dict: ``t``, ``ux``, ``uy``,
    ``vx``, ``vy`` (npts × N+1), ``phase`` per sample, ``events`` (``(t, kind)``), ``W``,
    ``peak_mat`` (max |u_mat| over samples and segment ends), ``residual`` (the mat's final
    displacement vector), ``friction_work`` (∫ F·V dt over the slides).
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
    W = G * m.sum()
    R = float(isolator["R"])
    mu = float(isolator["mu"])
    mu_s = float(isolator.get("mu_s", mu) or mu)
    c_iso = float(isolator.get("c", 0.0) or 0.0)
    if mu < 0 or mu_s < mu:
        raise ValueError("friction pendulum needs 0 <= mu <= mu_s")
    k = W / R
    lim = mu_s * W * (1.0 + stick_rtol)
    # a speed below this is a stop: near a stop the direction of a velocity of rounding size
    # wanders, and a "turn" there would restart the segment without end
    v_tol = 1e-9 * max(np.abs(ax).max(), np.abs(ay).max(), mu * G) * dt
    q_tol = 1e-3 * v_tol  # a cross velocity below this is rounding (see the slide's direction)
    m0 = m[0]

    # state: [ux (n), uy (n), vx (n), vy (n), friction work]
    y = np.zeros(4 * n + 1)
    y[0], y[n] = mat_displacement
    y[1:n] += mat_displacement[0]  # the floors move with the mat: no storey strain at t = 0
    y[n + 1 : 2 * n] += mat_displacement[1]
    y[2 * n], y[3 * n] = mat_velocity

    def split(y):
        return y[:n], y[n : 2 * n], y[2 * n : 3 * n], y[3 * n : 4 * n]

    def forces(u, v, K, C):
        r = C @ v + K @ u
        r[0] += k * u[0] + c_iso * v[0]
        return r

    def needed(y, agx, agy):
        ux, uy, vx, vy = split(y)
        rx = forces(ux, vx, Kx, Cx)
        ry = forces(uy, vy, Ky, Cy)
        return np.array([-m0 * agx - rx[0], -m0 * agy - ry[0]])

    def rhs(phase, e, t0, a0, s):
        agx0, agy0 = a0
        sx, sy = s

        def f(t, y):
            agx = agx0 + sx * (t - t0)
            agy = agy0 + sy * (t - t0)
            ux, uy, vx, vy = split(y)
            rx = forces(ux, vx, Kx, Cx)
            ry = forces(uy, vy, Ky, Cy)
            out = np.empty_like(y)
            out[: 2 * n] = y[2 * n : 4 * n]
            axx = -agx - rx / m
            ayy = -agy - ry / m
            if phase == _STUCK:
                axx[0] = 0.0
                ayy[0] = 0.0
                out[0] = 0.0
                out[n] = 0.0
                out[4 * n] = 0.0
            else:
                V = np.array([vx[0], vy[0]])
                speed = np.hypot(V[0], V[1])
                p = V @ e
                q = V[1] * e[0] - V[0] * e[1]
                if abs(q) <= 1e-12 * abs(p) + q_tol or speed == 0.0:
                    # along e to rounding: the direction is e (V/|V| would make a rounding-size
                    # cross velocity stiff near a stop, at the rate mu g/|V|)
                    nvec = e  # sign(p) V/|V| → e on both sides of the stop
                else:
                    nvec = (1.0 if p >= 0 else -1.0) * V / speed
                F = mu * W * nvec
                axx[0] -= F[0] / m0
                ayy[0] -= F[1] / m0
                out[4 * n] = F @ V
            out[2 * n : 3 * n] = axx
            out[3 * n : 4 * n] = ayy
            return out

        return f

    t_out = np.arange(npts) * dt
    UX = np.empty((npts, n))
    UY = np.empty((npts, n))
    VX = np.empty((npts, n))
    VY = np.empty((npts, n))
    phases = []
    events = []
    peak = np.hypot(y[0], y[n])

    # the initial phase: sliding if the mat moves, else stuck unless the demand is outside
    if np.hypot(*mat_velocity) > 0.0:
        phase, e = _SLIDE, np.asarray(mat_velocity, dtype=float) / np.hypot(*mat_velocity)
    else:
        phase, e = _STUCK, np.array([1.0, 0.0])
        F = needed(y, ax[0], ay[0])
        if np.hypot(*F) > lim:
            phase, e = _SLIDE, F / np.hypot(*F)
            events.append((0.0, "slip"))

    def record(kk):
        ux, uy, vx, vy = split(y)
        UX[kk], UY[kk], VX[kk], VY[kk] = ux, uy, vx, vy
        phases.append("stuck" if phase == _STUCK else "sliding")

    record(0)
    for kk in range(npts - 1):
        t0, t1 = t_out[kk], t_out[kk + 1]
        sx = (ax[kk + 1] - ax[kk]) / dt
        sy = (ay[kk + 1] - ay[kk]) / dt
        t = t0
        count = 0
        while t < t1:
            a0 = (ax[kk] + sx * (t - t0), ay[kk] + sy * (t - t0))
            f = rhs(phase, e, t, a0, (sx, sy))
            if phase == _STUCK:

                def breakaway(tt, yy, t=t, a0=a0, sx=sx, sy=sy):
                    agx = a0[0] + sx * (tt - t)
                    agy = a0[1] + sy * (tt - t)
                    F = needed(yy, agx, agy)
                    return F @ F - lim * lim

                breakaway.terminal, breakaway.direction = True, 1
                evs = [breakaway]
            else:

                def stop(tt, yy, e=e):
                    return yy[2 * n] * e[0] + yy[3 * n] * e[1]

                def turn(tt, yy, e=e):
                    V = (yy[2 * n], yy[3 * n])
                    return V[0] * e[0] + V[1] * e[1] - 0.5 * np.hypot(*V)

                stop.terminal, stop.direction = True, -1
                turn.terminal, turn.direction = True, -1
                evs = [stop, turn]
            sol = solve_ivp(
                f, (t, t1), y, method="DOP853", rtol=rtol, atol=atol, events=evs,
                first_step=min(1e-6, (t1 - t) / 4) if t > t0 else None,
            )  # fmt: skip
            if sol.status < 0:
                raise RuntimeError(sol.message)
            y = sol.y[:, -1].copy()
            t_end = sol.t[-1]
            peak = max(peak, np.hypot(y[0], y[n]))
            if sol.status == 0 or t_end >= t1:
                t = t1
                break
            t = t_end
            count += 1
            if count > max_events:
                raise RuntimeError(f"more than {max_events} events in the step at t = {t0}")
            which = next(i for i, te in enumerate(sol.t_events) if te.size)
            agx = ax[kk] + sx * (t - t0)
            agy = ay[kk] + sy * (t - t0)
            if phase == _STUCK:  # breakaway along the demand
                F = needed(y, agx, agy)
                phase, e = _SLIDE, F / np.hypot(*F)
                events.append((t, "slip"))
            elif which == 1 and np.hypot(y[2 * n], y[3 * n]) > v_tol:  # turned: a new direction
                V = np.array([y[2 * n], y[3 * n]])
                e = V / np.hypot(*V)
            else:  # stopped (or a turn at a rounding-level speed, which is a stop): stick inside
                # the friction circle, else slide on along the demand
                y[2 * n] = 0.0
                y[3 * n] = 0.0
                F = needed(y, agx, agy)
                if np.hypot(*F) <= lim:
                    phase = _STUCK
                    events.append((t, "stick"))
                else:
                    e = F / np.hypot(*F)
                    events.append((t, "reverse"))
        record(kk + 1)
    return {
        "t": t_out,
        "ux": UX,
        "uy": UY,
        "vx": VX,
        "vy": VY,
        "phase": phases,
        "events": events,
        "W": W,
        "peak_mat": float(peak),
        "residual": np.array([UX[-1, 0], UY[-1, 0]]),
        "friction_work": float(y[4 * n]),
    }


def circular_orbit(A: float, omega: float, mu: float, R: float) -> tuple[float, float]:
    """The steady orbit of a rigid mass on a friction pendulum (radius ``R``) under the ground
    acceleration ``a = A (cos ωt, sin ωt)`` (``A > mu g``): it slides for ever on a circle of
    radius ``r = √(A² − (mu g)²)/|g/R − ω²|``, its displacement leading the ground's
    acceleration by ``φ = π − atan2(mu g, (g/R − ω²) r)``. Returns ``(r, φ)``.

    From ``(g/R − ω²) u + mu g V/|V| = −a`` with ``u = r (cos(ωt+φ), sin(ωt+φ))`` and ``V/|V|``
    its tangent: the two terms are orthogonal, so their norms add in quadrature."""
    s = G / R - omega**2
    r = np.sqrt(A * A - (mu * G) ** 2) / abs(s)
    phi = np.pi - np.arctan2(mu * G, s * r)
    return float(r), float(phi)
