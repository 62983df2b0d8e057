"""Nonlinear isolation layers: lead-rubber (bilinear) and friction-pendulum bearings.

A base-isolated building is the superstructure (a :class:`~floorslide.building.model.
ShearBuilding`) on a base mat of mass ``m_b`` carried by an isolation layer whose force on the
mat is ``f_iso``. In coordinates relative to the ground (``u_0`` the mat's displacement, the
isolator's; ``u_i`` floor ``i``'s):

.. math::

    M u'' + C_s u' + K_s u + e_0 f_{iso} = -M \\mathbf{1} a_g(t),

with ``K_s``, ``C_s`` the superstructure's matrices assembled on the mat (no isolator term). The
layers here are piecewise linear, so between *events* the whole building is linear
time-invariant and its response to a piecewise-linear record is known in closed form; the
events are located inside steps (:mod:`floorslide.building.nonlinear`).

``BilinearIsolator`` (Kelly 1996 ch. 4; Naeim & Kelly 1999 §4; the model of OpenSees'
``elastomericBearingPlasticity``): ``f = k_2 u_0 + c u_0' + q`` with ``q`` an elastic–perfectly
plastic element of stiffness ``k_1 − k_2`` and strength ``Q`` (the characteristic strength, the
force at zero displacement on the yield branch); yield displacement ``D_y = Q/(k_1 − k_2)``.
Given as ``q_ratio = Q/W``, ``yield_disp = D_y`` (or ``alpha = k_2/k_1``) and the post-yield
period ``T_d = 2π√(M/k_2)`` (``M`` the total mass above the ground, ``W = M g``).

``FrictionPendulum`` (single concave surface; Zayas, Low & Mahin 1990; the model of OpenSees'
``singleFPBearing`` with constant friction): ``f = (W/R) u_0 + c u_0' + F`` with Coulomb friction
``F = mu·W·sign(u_0')`` while sliding; while stuck the mat moves with the ground and
``|F| ≤ mu_s·W``. Given as ``radius = R`` or ``period = 2π√(R/g)`` (independent of the mass).
This is the *small-angle* model (Zayas, Low & Mahin 1990, eq. 1 with ``sin θ ≈ tan θ ≈ θ``):
on a spherical surface the slider at horizontal displacement ``u`` sits at ``sin θ = u/R`` and
the surface's restoring force is ``W tan θ = (W/R) u / √(1 − (u/R)²)`` (Almazán, De la Llera &
Inaudi 1998, the large-displacement formulation), so ``(W/R) u`` is low by
``1 − √(1 − (u/R)²)``: 0.5 % at ``u = 0.1 R``, 2.0 % at :data:`SMALL_ANGLE_LIMIT` ``= 0.2 R``,
8 % at ``0.4 R``, and a displacement ``≥ R`` is off the surface altogether. A response beyond
``0.2 R`` is flagged (``small_angle_exceeded``) unless a displacement ``capacity`` is given —
then the capacity is the limit the user vouches for, and is flagged when exceeded.

Optional viscous damping ``damping`` is a ratio at the layer's own period (``T_d``, or the
pendulum period): ``c = 4π M ξ / T``.

References
----------
Kelly, J. M. (1996). *Earthquake-Resistant Design with Rubber*, 2nd ed., Springer.
Naeim, F., Kelly, J. M. (1999). *Design of Seismic Isolated Structures*, Wiley.
Zayas, V. A., Low, S. S., Mahin, S. A. (1990). A simple pendulum technique for achieving
seismic isolation. *Earthquake Spectra* 6(2), 317–333.
Almazán, J. L., De la Llera, J. C., Inaudi, J. A. (1998). Modelling aspects of structures
isolated with the frictional pendulum system. *Earthquake Eng. Struct. Dyn.* 27(8), 845–867.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from floorslide.constants import G
from floorslide.errors import ModelError

SMALL_ANGLE_LIMIT = 0.2
"""Largest friction-pendulum displacement, as a fraction of the radius ``R``, that the
small-angle model ``(W/R)·u`` is trusted to: there it is 2.0 % below the spherical surface's
``W tan θ`` (``1 − √(1 − 0.2²)``; module notes); beyond it a response is flagged."""

# Branches of the piecewise-linear isolation layer (the kernel's codes).
LINEAR, ELASTIC, PLASTIC_POS, PLASTIC_NEG, SLIP_POS, SLIP_NEG, STICK = range(7)
BRANCH_NAMES = ("linear", "elastic", "yield+", "yield-", "slip+", "slip-", "stick")


def _positive(value, key: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ModelError(f"{value!r} is not a number", key) from None
    if not math.isfinite(x) or x <= 0:
        raise ModelError(f"must be > 0, got {value!r}", key)
    return x


def _ratio(value, key: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ModelError(f"{value!r} is not a number", key) from None
    if not math.isfinite(x) or not 0 <= x < 1:
        raise ModelError(f"must be in [0, 1), got {value!r}", key)
    return x


@dataclass(frozen=True)
class BilinearIsolator:
    """A lead-rubber (bilinear hysteretic) isolation layer (module notes).

    Parameters
    ----------
    q_ratio
        Characteristic strength over weight, ``Q/W`` (> 0).
    period
        Post-yield period ``T_d = 2π√(M/k_2)``, s.
    yield_disp
        Yield displacement ``D_y``, m; or give ``alpha``.
    alpha
        Post-yield over elastic stiffness ``k_2/k_1`` in (0, 1); ``D_y = Q (1/k_2 − ...)``
        follows as ``Q/(k_1 − k_2)``.
    damping
        Viscous damping ratio at ``T_d`` (default 0).
    capacity
        Displacement capacity of the layer (m, optional): a response beyond it is reported
        (the impact with the moat wall that would follow is not modelled).
    """

    q_ratio: float
    period: float
    yield_disp: float | None = None
    alpha: float | None = None
    damping: float = 0.0
    capacity: float | None = None

    def __post_init__(self):
        _positive(self.q_ratio, "isolator.q_ratio")
        if self.capacity is not None:
            _positive(self.capacity, "isolator.capacity")
        _positive(self.period, "isolator.period")
        _ratio(self.damping, "isolator.damping")
        if (self.yield_disp is None) == (self.alpha is None):
            raise ModelError("give one of yield_disp and alpha", "isolator.yield_disp")
        if self.yield_disp is not None:
            _positive(self.yield_disp, "isolator.yield_disp")
        else:
            a = float(self.alpha)
            if not 0 < a < 1:
                raise ModelError(
                    f"alpha = k2/k1 must be in (0, 1), got {self.alpha!r}", "isolator.alpha"
                )

    def constants(self, total_mass: float) -> dict:
        """``k1, k2, Q, D_y, c, W`` for a building of total mass `total_mass` (kg)."""
        W = total_mass * G
        k2 = total_mass * (2 * np.pi / self.period) ** 2
        Q = self.q_ratio * W
        if self.yield_disp is not None:
            dy = float(self.yield_disp)
            k1 = k2 + Q / dy
        else:
            k1 = k2 / float(self.alpha)
            dy = Q / (k1 - k2)
        c = 4 * np.pi * total_mass * self.damping / self.period
        return dict(k1=k1, k2=k2, Q=Q, D_y=dy, c=c, W=W)


@dataclass(frozen=True)
class FrictionPendulum:
    """A single concave friction-pendulum isolation layer (module notes).

    Parameters
    ----------
    mu
        Kinetic (sliding) friction coefficient, ≥ 0.
    radius
        Radius of curvature R, m; or give ``period = 2π√(R/g)``.
    period
        Pendulum period, s.
    mu_s
        Static coefficient (default ``mu``); sliding starts when the friction needed exceeds
        ``max(mu_s, mu)·W``.
    damping
        Viscous damping ratio at the pendulum period (default 0).
    capacity
        Displacement capacity of the bearing (m, optional): a response beyond it is reported
        (the impact with the bearing's rim or the moat wall is not modelled). Without it, a
        response beyond :attr:`small_angle_limit` (``0.2 R``) is reported instead.

    Notes
    -----
    The restoring force is the small-angle ``(W/R)·u`` (Zayas, Low & Mahin 1990): exact for
    ``u ≪ R``, 2 % below the spherical surface's ``W tan θ`` at ``u = 0.2 R`` (module notes).
    """

    mu: float
    radius: float | None = None
    period: float | None = None
    mu_s: float | None = None
    damping: float = 0.0
    capacity: float | None = None

    def __post_init__(self):
        if self.capacity is not None:
            _positive(self.capacity, "isolator.capacity")
        try:
            mu = float(self.mu)
        except (TypeError, ValueError):
            raise ModelError(f"{self.mu!r} is not a number", "isolator.mu") from None
        if not math.isfinite(mu) or mu < 0:
            raise ModelError(f"must be ≥ 0, got {self.mu!r}", "isolator.mu")
        if self.mu_s is not None:
            ms = float(self.mu_s)
            if not math.isfinite(ms) or ms < 0:
                raise ModelError(f"must be ≥ 0, got {self.mu_s!r}", "isolator.mu_s")
        if (self.radius is None) == (self.period is None):
            raise ModelError("give one of radius and period", "isolator.radius")
        if self.radius is not None:
            _positive(self.radius, "isolator.radius")
        else:
            _positive(self.period, "isolator.period")
        _ratio(self.damping, "isolator.damping")

    @property
    def R(self) -> float:
        """Radius of curvature, m."""
        if self.radius is not None:
            return float(self.radius)
        return G * (float(self.period) / (2 * np.pi)) ** 2

    @property
    def T(self) -> float:
        """Pendulum period ``2π√(R/g)``, s."""
        return 2 * np.pi * math.sqrt(self.R / G)

    @property
    def small_angle_limit(self) -> float:
        """Largest displacement the small-angle model is trusted to, :data:`SMALL_ANGLE_LIMIT`
        ``· R`` (m)."""
        return SMALL_ANGLE_LIMIT * self.R

    def constants(self, total_mass: float) -> dict:
        """``k (= W/R), mu, mu_s, c, W`` for a building of total mass `total_mass` (kg)."""
        W = total_mass * G
        mu = float(self.mu)
        mu_s = max(mu, float(self.mu_s)) if self.mu_s is not None else mu
        c = 4 * np.pi * total_mass * self.damping / self.T
        return dict(k=W / self.R, mu=mu, mu_s=mu_s, c=c, W=W, R=self.R)


def small_angle_exceeded(isolator, peak_displacement: float) -> bool:
    """Whether a peak isolator displacement is beyond what the layer's model is trusted to:
    a :class:`FrictionPendulum` without a ``capacity`` beyond its
    :attr:`~FrictionPendulum.small_angle_limit` (``0.2 R``; with a capacity, the capacity is
    the limit and is checked instead). Other layers have no such limit (False)."""
    return (
        isinstance(isolator, FrictionPendulum)
        and isolator.capacity is None
        and peak_displacement > isolator.small_angle_limit
    )


def small_angle_note(peak_displacement: float, R: float) -> str:
    """One line saying that `peak_displacement` (m) is beyond the small-angle model of a
    friction pendulum of radius `R` (m)."""
    exact = R * R - peak_displacement**2
    error = (
        f"{100 * (1 - math.sqrt(exact) / R):.2g} % low"
        if exact > 0
        else "meaningless (off the spherical surface)"
    )
    return (
        f"isolator displacement {peak_displacement:.4g} m = {peak_displacement / R:.3g}·R is "
        f"beyond {SMALL_ANGLE_LIMIT:g}·R = {SMALL_ANGLE_LIMIT * R:.4g} m (R = {R:.4g} m), "
        f"where the friction pendulum's small-angle restoring force (W/R)·u is {error} against "
        "the spherical surface's W·tan θ (give the bearing's capacity to check against it "
        "instead)"
    )


def equivalent_linear(isolator, total_mass: float, displacement: float) -> tuple[float, float]:
    """Effective period and damping ratio of a nonlinear layer at a design displacement.

    The secant stiffness at ``D`` and the damping ratio that dissipates the loop's energy per
    cycle at that stiffness, ``β = E_loop / (2π K_eff D²)`` — the equivalent-linear model of
    ASCE 7-22 ch. 17 and of the AASHTO *Guide Specifications for Seismic Isolation Design*
    (Naeim & Kelly 1999 §4): for the bilinear layer ``K_eff = k₂ + Q/D``,
    ``E_loop = 4Q(D − D_y)`` (``D ≥ D_y``; below yield the layer is linear in ``k₁``, no
    hysteresis); for the pendulum ``K_eff = W/R + mu·W/D``, ``E_loop = 4 mu W D``, so
    ``β = 2 mu / (π (mu + D/R))``. A viscous ratio of the layer adds at its own stiffness,
    ``c/(2 √(K_eff M))``.

    Returns
    -------
    (period, damping)
        ``T_eff = 2π√(M/K_eff)`` (s) and ``β_eff``.
    """
    D = _positive(displacement, "displacement")
    c = isolator.constants(total_mass)
    if isinstance(isolator, BilinearIsolator):
        if D <= c["D_y"]:
            k_eff, energy = c["k1"], 0.0
        else:
            k_eff = c["k2"] + c["Q"] / D
            energy = 4.0 * c["Q"] * (D - c["D_y"])
    elif isinstance(isolator, FrictionPendulum):
        k_eff = c["W"] / c["R"] + c["mu"] * c["W"] / D
        energy = 4.0 * c["mu"] * c["W"] * D
    else:
        raise ModelError("isolator must be a BilinearIsolator or a FrictionPendulum", "isolator")
    beta = energy / (2 * np.pi * k_eff * D * D) + c["c"] / (2 * math.sqrt(k_eff * total_mass))
    return 2 * np.pi * math.sqrt(total_mass / k_eff), float(beta)
