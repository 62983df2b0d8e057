"""A smoothed-friction approximation of the 2-DOF sliding oscillator in the plane, beside the
exact :func:`floorslide.slide_oscillator_plane` (for ``floorslide bench``; docs/design.md §6,
§10d).

The model is the exact solver's, per unit top mass (``q = 2ξw z' + w² z``, ``a`` the floor's
absolute acceleration, ``u`` the base's slide relative to the floor and ``z`` the spring's
deformation, 2-vectors; ``r = m_base/m_top``)::

    u'' = −a + q/r − (mu_k (1 + r) g / r) w,      z'' = −(1 + 1/r) q + (mu_k (1 + r) g / r) w,

with the Coulomb direction ``w = u'/|u'|`` (and sticking) replaced by the regularised
friction circle ``w = u'/sqrt(|u'|² + eps²)`` (the isotropic counterpart of ``tanh(v/eps)``;
no sticking: a base the exact solver holds creeps at a speed of order ``eps``; ``mu_s > mu_k``
has no counterpart). The oscillator — and on a floor the linear building, both directions,
its states beside the oscillator's — is integrated over the whole record as one ODE by SciPy's
:func:`~scipy.integrate.solve_ivp` (``LSODA`` by default, with the analytic Jacobian: the
friction's transition is stiff, its rate ``mu_k (1 + r) g/(r eps)``). The ground is the
record joined by straight lines, as in the exact solver; integrating the building inside the
ODE gives its exact floor motion (no interpolation of sampled floor accelerations). Peaks of
``|u|`` and ``|z|`` are located as events (``u·u' = 0``, ``z·z' = 0``) besides the samples and
the solver's steps. The error is the regularisation's (and the tolerance's): it shrinks as
``eps → 0``.

References
----------
Westermo, B., Udwadia, F. (1983). Periodic response of a sliding oscillator system to harmonic
excitation. *Earthquake Eng. Struct. Dyn.* 11, 135–146.
Mokha, A., Constantinou, M. C., Reinhorn, A. M. (1993). Verification of friction model of
Teflon bearings under triaxial load. *J. Struct. Eng.* 119(1), 240–261 (the regularised
friction circle in the plane).
Petzold, L. (1983). Automatic selection of methods for solving stiff and nonstiff systems of
ordinary differential equations. *SIAM J. Sci. Stat. Comput.* 4(1), 136–148 (LSODA).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from floorslide._jit import njit
from floorslide.building.model import LinearBuilding
from floorslide.constants import G
from floorslide.contents.oscillator import oscillator_parameters
from floorslide.contents.plane_oscillator import _friction
from floorslide.errors import ModelError, SolverLimitError
from floorslide.pair import as_pair

__all__ = ["PlaneOscillatorApprox", "slide_oscillator_plane_smoothed"]

INTEGRATORS = ("LSODA", "Radau", "BDF")
"""SciPy's implicit integrators accepted."""

ATOL = 0.1
"""``atol = ATOL·rtol`` on every state (m, m/s)."""


@dataclass(frozen=True)
class PlaneOscillatorApprox:
    """The smoothed plane oscillator, one entry per ``mu_k``: the fields of
    :class:`~floorslide.contents.plane_oscillator.PlaneOscillatorResult` it can give.

    Attributes
    ----------
    mu_k
        Kinetic friction coefficients.
    peak_slide, peak_deformation
        ``max |u|`` and ``max |z|``, m.
    residual
        ``u`` at the end, ``(n, 2)``, m.
    notes
        Settings and solver statistics, one line each.
    """

    mu_k: np.ndarray
    peak_slide: np.ndarray
    peak_deformation: np.ndarray
    residual: np.ndarray
    notes: tuple[str, ...] = ()


@njit(cache=True)
def _ground2(t, acc, dt):
    x = t / dt
    k = int(x)
    npts = acc.shape[1]
    if k < 0:
        return acc[0, 0], acc[1, 0]
    if k >= npts - 1:
        return acc[0, npts - 1], acc[1, npts - 1]
    s = x - k
    return (acc[0, k] + s * (acc[0, k + 1] - acc[0, k]),
            acc[1, k] + s * (acc[1, k + 1] - acc[1, k]))  # fmt: skip


@njit(cache=True)
def _floor_acc(t, y, minv, K, C, j, acc, dt, out):
    """The floor's absolute acceleration (2-vector) into `out`; building states, if any, are
    ``y[:4n]`` (``u_x, v_x, u_y, v_y``), and their derivatives are written to ``dy[:4n]``
    by :func:`_rhs`."""
    n = minv.size
    g1, g2 = _ground2(t, acc, dt)
    if j < 0:
        out[0] = g1
        out[1] = g2
        return
    for d in range(2):
        o = 2 * n * d
        s = 0.0
        for c in range(n):
            s += K[j, c] * y[o + c] + C[j, c] * y[o + n + c]
        out[d] = -s * minv[j]


@njit(cache=True)
def _rhs(t, y, minv, K, C, j, acc, dt, w, xi, r, fr, eps):
    n = minv.size if j >= 0 else 0
    dy = np.empty(y.size)
    g1, g2 = _ground2(t, acc, dt)
    for d in range(2):
        o = 2 * n * d
        ag = g1 if d == 0 else g2
        for i in range(n):
            dy[o + i] = y[o + n + i]
            s = 0.0
            for c in range(n):
                s += K[i, c] * y[o + c] + C[i, c] * y[o + n + c]
            dy[o + n + i] = -s * minv[i] - ag
    a = np.empty(2)
    _floor_acc(t, y, minv, K, C, j, acc, dt, a)
    b = 4 * n  # oscillator: u (2), u' (2), z (2), z' (2)
    vx, vy = y[b + 2], y[b + 3]
    den = math.sqrt(vx * vx + vy * vy + eps * eps)
    for d in range(2):
        q = 2.0 * xi * w * y[b + 6 + d] + w * w * y[b + 4 + d]
        f = fr * y[b + 2 + d] / den
        dy[b + d] = y[b + 2 + d]
        dy[b + 2 + d] = -a[d] + q / r - f
        dy[b + 4 + d] = y[b + 6 + d]
        dy[b + 6 + d] = -(1.0 + 1.0 / r) * q + f
    return dy


@njit(cache=True)
def _jac(t, y, minv, K, C, j, acc, dt, w, xi, r, fr, eps):
    n = minv.size if j >= 0 else 0
    J = np.zeros((y.size, y.size))
    for d in range(2):
        o = 2 * n * d
        for i in range(n):
            J[o + i, o + n + i] = 1.0
            for c in range(n):
                J[o + n + i, o + c] = -K[i, c] * minv[i]
                J[o + n + i, o + n + c] = -C[i, c] * minv[i]
    b = 4 * n
    vx, vy = y[b + 2], y[b + 3]
    den = math.sqrt(vx * vx + vy * vy + eps * eps)
    v = (vx, vy)
    for d in range(2):
        # the floor's acceleration a_d = −(K_j u + C_j v)/M_j enters u''
        if n:
            o = 2 * n * d
            for c in range(n):
                J[b + 2 + d, o + c] = K[j, c] * minv[j]
                J[b + 2 + d, o + n + c] = C[j, c] * minv[j]
        J[b + d, b + 2 + d] = 1.0
        J[b + 4 + d, b + 6 + d] = 1.0
        # q's derivatives
        J[b + 2 + d, b + 4 + d] += w * w / r
        J[b + 2 + d, b + 6 + d] += 2.0 * xi * w / r
        J[b + 6 + d, b + 4 + d] = -(1.0 + 1.0 / r) * w * w
        J[b + 6 + d, b + 6 + d] = -(1.0 + 1.0 / r) * 2.0 * xi * w
        for e in range(2):
            dw = ((1.0 if d == e else 0.0) / den - v[d] * v[e] / den**3) * fr
            J[b + 2 + d, b + 2 + e] -= dw
            J[b + 6 + d, b + 2 + e] += dw
    return J


def slide_oscillator_plane_smoothed(
    acc,
    dt: float | None = None,
    mu=None,
    frequency: float | None = None,
    damping: float = 0.02,
    mass_ratio: float = 1.0,
    *,
    building: LinearBuilding | None = None,
    floor: int | None = None,
    eps: float = 1e-3,
    rtol: float = 1e-8,
    integrator: str = "LSODA",
) -> PlaneOscillatorApprox:
    """The 2-DOF sliding oscillator in the plane with the regularised friction circle
    ``mu_k N u'/sqrt(|u'|² + eps²)`` on the base, integrated by SciPy's ``solve_ivp``.

    Parameters
    ----------
    acc, dt
        A pair of horizontal components, as :func:`floorslide.slide_oscillator_plane`.
    mu
        Kinetic friction coefficient(s) of the base, > 0.
    frequency, damping, mass_ratio
        The oscillator, as :func:`floorslide.slide_oscillator_plane`.
    building, floor
        A linear building (:class:`~floorslide.ShearBuilding` or a linear
        :class:`~floorslide.IsolatedBuilding`, the same model in both directions), integrated
        inside the ODE, and the floor the oscillator stands on; none: the ground.
    eps
        Velocity scale of the friction's transition, m/s (> 0).
    rtol
        Relative tolerance of ``solve_ivp`` (``atol = 0.1·rtol`` on every state).
    integrator
        ``"LSODA"``, ``"Radau"`` or ``"BDF"``.

    Returns
    -------
    PlaneOscillatorApprox

    Raises
    ------
    ModelError
        Invalid input or setting, one line naming it (a BuildingPair or a building on nonlinear
        isolation is not taken).
    SolverLimitError
        ``solve_ivp`` failed.

    Notes
    -----
    Measured on the bench's case (``oscillator-plane-ground``: the RSN 511 pair, mu 0.2 and 0.5
    of its peak ground acceleration over g; slides of a few millimetres): peak-slide error
    38 %, 14 %, 2.3 % and peak-deformation error 28 %, 4.3 %, 0.7 % at ``eps`` = 1e-2, 1e-3,
    1e-4 m/s (``rtol = eps/100``). ``eps`` must be small beside the sliding speeds.
    """
    from scipy.integrate import solve_ivp  # SciPy's integrators: only when asked for

    e, rt = float(eps), float(rtol)
    if not (math.isfinite(e) and e > 0):
        raise ModelError(f"eps must be > 0 m/s, got {eps!r}", "eps")
    if not (math.isfinite(rt) and 0 < rt < 1):
        raise ModelError(f"rtol must be in (0, 1), got {rtol!r}", "rtol")
    if integrator not in INTEGRATORS:
        raise ModelError(
            f"integrator must be one of {', '.join(INTEGRATORS)}, got {integrator!r}",
            "integrator",
        )
    pair = as_pair(acc, dt)
    mk, _ = _friction(mu, None)
    f, xi, r = oscillator_parameters(frequency, damping, mass_ratio)
    if building is None:
        if floor not in (None, 0):
            raise ModelError(f"floor={floor!r} needs building= (without, the ground)", "floor")
        j = -1
    elif not isinstance(building, LinearBuilding):
        raise ModelError(
            f"the smoothed oscillator takes a linear building (ShearBuilding or linear "
            f"IsolatedBuilding), got {type(building).__name__}",
            "building",
        )
    elif floor is None:
        raise ModelError("floor is required with building=", "floor")
    else:
        (fl,) = building.check_floors([floor])
        dof = building.dof_of(fl)
        j = -1 if dof is None else int(dof)
    if j >= 0:
        K = np.ascontiguousarray(building.stiffness_matrix, dtype=float)
        C = np.ascontiguousarray(building.damping_matrix, dtype=float)
        minv = 1.0 / np.asarray(building.mass, dtype=float)
    else:
        K = C = np.zeros((1, 1))
        minv = np.ones(1)
    n = minv.size if j >= 0 else 0
    a = np.ascontiguousarray(np.vstack([pair.h1, pair.h2]), dtype=float)
    dtp = float(pair.dt)
    t_end = (a.shape[1] - 1) * dtp
    w = 2.0 * math.pi * f
    b = 4 * n
    ts = np.arange(a.shape[1]) * dtp
    ts[-1] = t_end
    peak, peak_z = np.zeros(mk.size), np.zeros(mk.size)
    residual = np.zeros((mk.size, 2))
    steps = 0

    def slide_event(t, y):
        return y[b] * y[b + 2] + y[b + 1] * y[b + 3]

    def spring_event(t, y):
        return y[b + 4] * y[b + 6] + y[b + 5] * y[b + 7]

    for i in range(mk.size):
        args = (minv, K, C, j, a, dtp, w, xi, r, float(mk[i]) * (1.0 + r) * G / r, e)
        sol = solve_ivp(
            lambda t, y, args=args: _rhs(t, y, *args),
            (0.0, t_end),
            np.zeros(b + 8),
            method=integrator,
            rtol=rt,
            atol=rt * ATOL,
            jac=lambda t, y, args=args: _jac(t, y, *args),
            dense_output=True,
            events=(slide_event, spring_event),
        )
        if not sol.success:
            raise SolverLimitError(f"solve_ivp failed: {sol.message}", "rtol")
        steps += sol.t.size
        ys = np.concatenate(
            [sol.sol(ts), sol.y] + [ev.reshape(-1, b + 8).T for ev in sol.y_events], axis=1
        )
        peak[i] = np.hypot(ys[b], ys[b + 1]).max()
        peak_z[i] = np.hypot(ys[b + 4], ys[b + 5]).max()
        residual[i] = sol.y[b : b + 2, -1]
    where = "ground" if j < 0 else f"floor {floor}, building inside the ODE"
    notes = (
        *pair.notes,
        f"friction circle smoothed: u'/sqrt(|u'|² + {e:g}²), solve_ivp {integrator} rtol {rt:g}",
        f"{where}; {steps} solver steps",
    )
    return PlaneOscillatorApprox(mk, peak, peak_z, residual, notes)
