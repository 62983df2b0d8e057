"""Approximate method for a block that slides, rocks or both (design §10g), for the bench.

The model is §10g's (Shenton & Jones 1991; Shenton 1996): four modes — rest, slide, rock about
a stuck corner, slide–rock — with Shenton's from-rest rule (``mu_s ≥ mu_k``), the friction
limit that lets a rocking corner slip, the stop of a slip, Housner's rough impact about the new
corner (``θ'⁺ = r θ'⁻ + (3 cos α / (4R)) V⁻``, then rock, or rest at or below
``1e-12·p·α`` or with the wrong sign) and overturning at ``|θ| = α``.

The scheme is the usual hand-written one: the floor's samples joined by straight lines, the
classical fixed-step Runge–Kutta scheme on steps of ``dt/substeps`` of the current mode's ODE
(state ``θ, θ', U, U'``), events detected by a sign change over a step and located by cubic
Hermite interpolation of the event function (from its values and slopes at the two ends;
linear interpolation for the friction limit, whose slope is not at hand; exact for a rest's
threshold, the floor being linear); the step is then integrated again to that instant, the mode
rules applied there, and the rest of the step integrated in the new mode. The instants of
impacts, stops and overturning are polished by Newton's method on the RK4 step of that length
(a cascade's late impacts come far inside a step, where the cubic alone misplaces them).
Peaks of ``|θ|`` between steps come from the Hermite cubic of θ. Free flight (``N ≤ 0``) and
the Painlevé case (``1/3 + w sin u ≤ 0.01``) stop it with
:class:`~floorslide.errors.SolverLimitError`.

References
----------
Shenton, H. W., Jones, N. P. (1991). Base excitation of rigid bodies. I: Formulation. *J. Eng.
Mech.* 117(10), 2286–2306.
Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes.
*J. Eng. Mech.* 122(7), 690–693.
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. *Bull.
Seismol. Soc. Am.* 53(2), 403–417.
"""

from __future__ import annotations

import math

import numpy as np

from floorslide._jit import njit
from floorslide.contents._rocking_kernel import REST_VELOCITY
from floorslide.errors import SolverLimitError

REST, SLIDE, ROCK, SLIDE_ROCK = 0, 1, 2, 3
PAINLEVE = 0.01
"""Slide–rock is refused where ``1/3 + w sin u`` falls to this value (§10g)."""

COLUMNS = (
    "peak_slide",
    "residual_slide",
    "peak_ratio",
    "overturned",
    "overturn_time",
    "impacts",
    "time_rest",
    "time_slide",
    "time_rock",
    "time_slide_rock",
)
"""The columns of :func:`fixed_step`'s result."""

_ERRORS = ("", "free flight (N reached 0)", "the Painlevé case", "more than 10000 events")


@njit(cache=True, inline="always")
def _rates(mode, s, sg, th, w, v, af, R, alpha, p2, g, mu_k):
    """``(θ'', U'', N, F)`` of the mode at one state (§10g's table)."""
    if mode == REST:
        return 0.0, 0.0, g, af
    if mode == SLIDE:
        return 0.0, -af - sg * mu_k * g, g, -sg * mu_k * g
    u = alpha * s - th
    su = math.sin(u)
    cu = math.cos(u)
    if mode == ROCK:
        tdd = -p2 * (su + af / g * cu)
        return tdd, 0.0, g + R * (su * tdd - cu * w * w), af + R * (cu * tdd + su * w * w)
    ww = su - sg * mu_k * cu
    tdd = -ww * (g - R * cu * w * w) / (R * (1.0 / 3.0 + ww * su))
    N = g + R * (su * tdd - cu * w * w)
    F = -sg * mu_k * N
    return tdd, F - R * (cu * tdd + su * w * w) - af, N, F


@njit(cache=True)
def _rk4(mode, s, sg, th, w, U, v, ab, slope, hh, R, alpha, p2, g, mu_k):
    """One classical RK4 step of length ``hh`` from ``(θ, θ', U, U')``, floor ``ab + slope·t``."""
    am = ab + slope * 0.5 * hh
    ae = ab + slope * hh
    a1, b1, _, _ = _rates(mode, s, sg, th, w, v, ab, R, alpha, p2, g, mu_k)
    th2, w2, v2 = th + 0.5 * hh * w, w + 0.5 * hh * a1, v + 0.5 * hh * b1
    a2, b2, _, _ = _rates(mode, s, sg, th2, w2, v2, am, R, alpha, p2, g, mu_k)
    th3, w3, v3 = th + 0.5 * hh * w2, w + 0.5 * hh * a2, v + 0.5 * hh * b2
    a3, b3, _, _ = _rates(mode, s, sg, th3, w3, v3, am, R, alpha, p2, g, mu_k)
    th4, w4, v4 = th + hh * w3, w + hh * a3, v + hh * b3
    a4, b4, _, _ = _rates(mode, s, sg, th4, w4, v4, ae, R, alpha, p2, g, mu_k)
    return (
        th + hh / 6.0 * (w + 2.0 * w2 + 2.0 * w3 + w4),
        w + hh / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4),
        U + hh / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4),
        v + hh / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4),
    )


@njit(cache=True, inline="always")
def _hermite(x, g0, m0, g1, m1):
    """The cubic Hermite interpolant on [0, 1] of values ``g0, g1`` and slopes ``m0, m1``."""
    c2 = 3.0 * (g1 - g0) - 2.0 * m0 - m1
    c3 = 2.0 * (g0 - g1) + m0 + m1
    return g0 + x * (m0 + x * (c2 + x * c3))


@njit(cache=True)
def _first_root(g0, m0, g1, m1):
    """First root in (0, 1] of the Hermite cubic of a function positive just after 0
    (``g0 > 0``, or ``g0 = 0`` rising) and at most 0 at 1: a scan of 16 points, then
    bisection."""
    lo = 0.0
    hi = 1.0
    for q in range(1, 17):
        x = q / 16.0
        if _hermite(x, g0, m0, g1, m1) <= 0.0:
            hi = x
            break
        lo = x
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _hermite(mid, g0, m0, g1, m1) > 0.0:
            lo = mid
        else:
            hi = mid
    return hi


@njit(cache=True)
def _max_abs(th0, w0, th1, w1, hh, upto):
    """``max |θ|`` on ``[0, upto]`` of a step (fraction) from the Hermite cubic of θ."""
    best = max(abs(th0), abs(_hermite(upto, th0, hh * w0, th1, hh * w1)))
    m0 = hh * w0
    m1 = hh * w1
    c1 = m0
    c2 = 3.0 * (th1 - th0) - 2.0 * m0 - m1
    c3 = 2.0 * (th0 - th1) + m0 + m1
    # roots of c1 + 2 c2 x + 3 c3 x²
    qa, qb, qc = 3.0 * c3, 2.0 * c2, c1
    if qa == 0.0:
        if qb != 0.0:
            x = -qc / qb
            if 0.0 < x < upto:
                best = max(best, abs(_hermite(x, th0, m0, th1, m1)))
        return best
    disc = qb * qb - 4.0 * qa * qc
    if disc < 0.0:
        return best
    sq = math.sqrt(disc)
    for x in ((-qb + sq) / (2.0 * qa), (-qb - sq) / (2.0 * qa)):
        if 0.0 < x < upto:
            best = max(best, abs(_hermite(x, th0, m0, th1, m1)))
    return best


@njit(cache=True)
def _polish(kind, fr, mode, s, sg, th, w, U, v, ab, slope, hh, R, alpha, p2, g, mu_k):
    """The event's fraction of the step refined by Newton's method on the RK4 step of that
    length (``kind`` 0: ``σ U'``, 1: ``α − s θ``, 2: ``s θ``; each decreasing through 0).

    The Hermite cubic over the whole step places a root far smaller than the step (the late
    impacts of a cascade, ``θ'`` tiny) with an error of the cubic's, not the root's, size:
    the impact velocity taken there would be wrong and the cascade would last too long."""
    for _ in range(4):
        te, we, _, ve = _rk4(mode, s, sg, th, w, U, v, ab, slope, fr * hh, R, alpha, p2, g, mu_k)
        if kind == 2:
            gv, gd = s * te, s * we
        elif kind == 1:
            gv, gd = alpha - s * te, -s * we
        else:
            _, udd, _, _ = _rates(
                mode, s, sg, te, we, ve, ab + slope * fr * hh, R, alpha, p2, g, mu_k
            )
            gv, gd = sg * ve, sg * udd
        if not gd < 0.0:
            break
        new = fr - gv / (gd * hh)
        if not 0.0 < new <= 1.0:
            break
        if abs(new - fr) <= 1e-15:
            return new
        fr = new
    return fr


@njit(cache=True, inline="always")
def _from_rest(A, crossing, level, lam, mu_k, mu_s, g):
    """Shenton's from-rest rule (§10g) at a floor acceleration of magnitude ``A``."""
    if not crossing and A <= level:
        return REST
    if mu_s < lam:
        return SLIDE
    if crossing:
        return ROCK
    a = A / g
    mu_c = (a * (4.0 * lam * lam + 1.0) + 3.0 * lam) / (lam * lam + 4.0 + 3.0 * a * lam)
    if mu_s >= mu_c:
        return ROCK
    if mu_k > lam:
        return SLIDE_ROCK
    return SLIDE


@njit(cache=True)
def _block(af, dt, k, B, H, mu_k, mu_s, r, g, out):
    """One block by fixed-step RK4 at ``dt/k`` on the floor samples ``af`` (linear between
    them); fills ``out`` (:data:`COLUMNS`) and returns ``(error code, time)``."""
    b = 0.5 * B
    h = 0.5 * H
    R = math.hypot(b, h)
    alpha = math.atan2(b, h)
    lam = b / h
    p2 = 3.0 * g / (4.0 * R)
    v_rest = REST_VELOCITY * math.sqrt(p2) * alpha
    level = g * min(mu_s, lam)
    kimp = 3.0 * math.cos(alpha) / (4.0 * R)
    mode = REST
    s = 1.0
    sg = 1.0
    th = 0.0
    w = 0.0
    U = 0.0
    v = 0.0
    peak_th = 0.0
    peak_u = 0.0
    impacts = 0
    times = np.zeros(4)
    hs = dt / k
    for i in range(af.size - 1):
        a0 = af[i]
        slope = (af[i + 1] - a0) / dt
        for j in range(k):
            t0 = j * hs
            left = hs
            guard = 0
            while left > 0.0:
                guard += 1
                if guard > 10000:
                    return 3, i * dt + t0
                tau = t0 + (hs - left)
                ab = a0 + slope * tau
                if mode == REST:
                    if abs(ab) > level:  # beyond the level when the rest begins
                        mode = _from_rest(abs(ab), False, level, lam, mu_k, mu_s, g)
                        s = -1.0 if ab > 0.0 else 1.0
                        sg = s
                        continue
                    ae = a0 + slope * (tau + left)
                    if abs(ae) > level:  # the floor crosses the level in the step
                        target = level if ae > 0.0 else -level
                        frac = (target - ab) / (ae - ab)
                        times[REST] += frac * left
                        left -= frac * left
                        mode = SLIDE if mu_s < lam else ROCK
                        s = -1.0 if ae > 0.0 else 1.0
                        sg = s
                        continue
                    times[REST] += left
                    left = 0.0
                    continue
                if mode == ROCK:
                    _, _, N, F = _rates(ROCK, s, sg, th, w, 0.0, ab, R, alpha, p2, g, mu_k)
                    if abs(F) > mu_s * N:  # beyond the friction limit (after an impact)
                        mode = SLIDE_ROCK
                        sg = -1.0 if F > 0.0 else 1.0
                        v = 0.0
                        continue
                if mode == SLIDE_ROCK:
                    u = alpha * s - th
                    ww = math.sin(u) - sg * mu_k * math.cos(u)
                    if 1.0 / 3.0 + ww * math.sin(u) <= PAINLEVE:
                        return 2, i * dt + tau
                hh = left
                ae = ab + slope * hh
                th1, w1, U1, v1 = _rk4(
                    mode, s, sg, th, w, U, v, ab, slope, hh, R, alpha, p2, g, mu_k
                )
                tdd0, udd0, N0, F0 = _rates(mode, s, sg, th, w, v, ab, R, alpha, p2, g, mu_k)
                _, udd1, N1, F1 = _rates(mode, s, sg, th1, w1, v1, ae, R, alpha, p2, g, mu_k)
                # the earliest event in the step: its kind and fraction
                kind = -1
                fr = 2.0
                if mode == SLIDE or mode == SLIDE_ROCK:
                    if sg * v1 <= 0.0 and (sg * v > 0.0 or sg * udd0 > 0.0):
                        x = _first_root(sg * v, sg * udd0 * hh, sg * v1, sg * udd1 * hh)
                        if x < fr:
                            kind, fr = 0, x  # the slip stops
                    elif sg * v1 <= 0.0:
                        kind, fr = 0, 1.0  # a slip that never got going
                if mode == ROCK or mode == SLIDE_ROCK:
                    if s * th1 >= alpha:
                        x = _first_root(alpha - s * th, -s * w * hh, alpha - s * th1, -s * w1 * hh)
                        if x < fr:
                            kind, fr = 1, x
                    if s * th1 < 0.0:
                        if s * th > 0.0 or s * w > 0.0 or s * tdd0 > 0.0:
                            x = _first_root(s * th, s * w * hh, s * th1, s * w1 * hh)
                            if x < fr:
                                kind, fr = 2, x
                        elif fr > 1.0:
                            kind, fr = 5, 1.0  # a grazing uplift that fell back: rest
                    if mode == ROCK:
                        g0 = mu_s * N0 - abs(F0)
                        g1 = mu_s * N1 - abs(F1)
                        if g1 <= 0.0 and g0 > 0.0:
                            x = g0 / (g0 - g1)
                            if x < fr:
                                kind, fr = 3, x
                    if N1 <= 0.0:
                        x = N0 / (N0 - N1) if N0 > 0.0 else 0.0
                        if x < fr:
                            return 1, i * dt + tau + x * hh
                if kind < 0:
                    if mode == ROCK or mode == SLIDE_ROCK:
                        peak_th = max(peak_th, _max_abs(th, w, th1, w1, hh, 1.0))
                    th, w, U, v = th1, w1, U1, v1
                    peak_u = max(peak_u, abs(U))
                    times[mode] += hh
                    left = 0.0
                    continue
                # integrate again to the event (its instant polished by Newton's method on
                # the RK4 step, see _polish), then apply the rules there
                if kind <= 2 and fr < 1.0:
                    fr = _polish(
                        kind, fr, mode, s, sg, th, w, U, v, ab, slope, hh, R, alpha, p2, g, mu_k
                    )
                he = fr * hh
                if kind != 5 and fr < 1.0:
                    th1, w1, U1, v1 = _rk4(
                        mode, s, sg, th, w, U, v, ab, slope, he, R, alpha, p2, g, mu_k
                    )
                if mode == ROCK or mode == SLIDE_ROCK:
                    peak_th = max(peak_th, _max_abs(th, w, th1, w1, he, 1.0))
                times[mode] += he
                left -= he
                if left < 1e-12 * hs:
                    left = 0.0
                th, w, U, v = th1, w1, U1, v1
                peak_u = max(peak_u, abs(U))
                ae = ab + slope * he
                if kind == 1:  # overturning
                    out[0] = peak_u
                    out[1] = np.nan
                    out[2] = 1.0
                    out[3] = 1.0
                    out[4] = i * dt + tau + he
                    out[5] = impacts
                    out[6:10] = times
                    return 0, 0.0
                if kind == 5:
                    th, w, v = 0.0, 0.0, 0.0
                    mode = REST
                elif kind == 0:
                    v = 0.0
                    if mode == SLIDE:
                        mode = REST
                    else:
                        _, _, N, F = _rates(ROCK, s, sg, th, w, 0.0, ae, R, alpha, p2, g, mu_k)
                        if abs(F) <= mu_s * N:
                            mode = ROCK
                        else:
                            sg = -1.0 if F > 0.0 else 1.0
                elif kind == 2:  # Housner's rough impact about the new corner
                    wn = r * w + kimp * v
                    th, v = 0.0, 0.0
                    s = -s
                    impacts += 1
                    if s * wn <= v_rest:
                        w = 0.0
                        mode = REST
                    else:
                        w = wn
                        mode = ROCK
                else:  # kind == 3: the rocking corner slips
                    _, _, N, F = _rates(ROCK, s, sg, th, w, 0.0, ae, R, alpha, p2, g, mu_k)
                    mode = SLIDE_ROCK
                    sg = -1.0 if F > 0.0 else 1.0
                    v = 0.0
    out[0] = peak_u
    out[1] = U
    out[2] = peak_th / alpha
    out[3] = 0.0
    out[4] = np.nan
    out[5] = impacts
    out[6:10] = times
    return 0, 0.0


def fixed_step(
    af: np.ndarray,
    dt: float,
    B: np.ndarray,
    H: np.ndarray,
    mu_k: np.ndarray,
    mu_s: np.ndarray,
    r: np.ndarray,
    g: float,
    substeps: int,
) -> np.ndarray:
    """Blocks that slide, rock or both, by fixed-step RK4 with interpolated events (§10g).

    Parameters
    ----------
    af : numpy.ndarray
        Floor acceleration samples (m/s²), taken as linear between the samples.
    dt : float
        Sample step (s).
    B, H : numpy.ndarray
        Full width ``2b`` and full height ``2h`` of each block (m).
    mu_k, mu_s : numpy.ndarray
        Kinetic and static friction coefficients of each block (``mu_s ≥ mu_k``).
    r : numpy.ndarray
        Restitution of each block's impacts (Housner's ``1 − 1.5 sin²α`` is the rough impact
        that conserves the angular momentum about the new corner).
    g : float
        Gravity (m/s²).
    substeps : int
        RK4 steps per sample step.

    Returns
    -------
    numpy.ndarray
        Shape ``(n_blocks, 10)``, the columns :data:`COLUMNS`: peak slide ``max |U|`` (m, at
        the steps and events), residual slide (m, NaN if overturned), ``max |θ|/α`` (1 if
        overturned), overturned (0/1), overturning time (s, NaN if none), impacts, and the
        seconds spent at rest, sliding, rocking and in slide–rock.

    Raises
    ------
    floorslide.errors.SolverLimitError
        Free flight (``N`` reaching 0), the Painlevé case, or more than 10 000 events in a
        step (chatter), naming the block and the time.

    Notes
    -----
    The model, its from-rest rule and its impact are Shenton & Jones (1991), Shenton (1996)
    and design §10g; the module docstring describes the scheme.
    """
    af = np.ascontiguousarray(af, dtype=float)
    B, H, mu_k, mu_s, r = (np.asarray(x, dtype=float).ravel() for x in (B, H, mu_k, mu_s, r))
    if not (B.size == H.size == mu_k.size == mu_s.size == r.size):
        raise ValueError("fixed_step: B, H, mu_k, mu_s and r must have one value per block")
    if np.any(mu_s < mu_k):
        raise ValueError("fixed_step: mu_s must be at least mu_k")
    out = np.zeros((B.size, len(COLUMNS)))
    for i in range(B.size):
        code, t = _block(
            af, float(dt), int(substeps), B[i], H[i], mu_k[i], mu_s[i], r[i], float(g), out[i]
        )
        if code:
            raise SolverLimitError(
                f"slide-rock (block {i}: B = {B[i]:g} m, H = {H[i]:g} m): {_ERRORS[code]} "
                f"at t = {t:.6g} s"
            )
    return out
