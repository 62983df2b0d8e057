"""A building on lead-rubber (bilinear) bearings under two horizontal components: the plastic
element's circular yield surface coupled with the superstructure in both directions, exact to
rounding (docs/design.md §10b, "In the plane").

The bearing's force on the mat is ``f = k_2 u_b + c u_b' + q``: a linear spring and damper in
parallel with an elastic–perfectly-plastic element of stiffness ``k_1 − k_2`` whose force ``q``
stays in the disc ``|q| ≤ Q`` — elastic (``q' = (k_1 − k_2) u_b'``) inside it or unloading on
it, plastic (``q' = (k_1 − k_2)(u_b' − (q·u_b') q/Q²)``) on it while ``q·u_b' > 0`` (Park, Wen &
Ang 1986, the sharp limit of their biaxial model; Simo & Hughes 1998, §2.3). Along one azimuth
it is the 1-D bilinear layer of :mod:`floorslide.building.nonlinear`. Vertical shaking does not
act on this bearing model.

This module holds what :class:`~floorslide.building.plane_isolation.PlaneIsolatedMotion` needs
for this layer — the compiled kernel's inputs (:func:`bilinear_setup`, :func:`initial_state`)
and the bearing's outputs (:func:`bilinear_response`); the kernel is
:mod:`floorslide.building._plane_bilinear_kernel`.

References
----------
Park, Y. J., Wen, Y. K., Ang, A. H.-S. (1986). Random vibration of hysteretic systems under
bi-directional ground motions. *Earthq. Eng. Struct. Dyn.* 14(4), 543–557.
Simo, J. C., Hughes, T. J. R. (1998). *Computational Inelasticity*, Springer, §2.3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from floorslide.building import _plane_bilinear_kernel as bk
from floorslide.building import _plane_isolation_kernel as pk
from floorslide.building.isolators import PLASTIC_POS

EVENT_NAMES = {bk.EV_YIELD: "yield", bk.EV_UNLOAD: "unload"}
"""The events' names in :attr:`PlaneIsolatorResponse.event_kinds`."""


@dataclass(frozen=True)
class BilinearSetup:
    """The compiled integrator's inputs for one building and record: each direction's system
    ``A[d]`` (``(2n+1)²``: the states ``[u; u'; z]``, ``k_2`` on the mat and ``−Q/m_b`` on
    ``z = q/Q``) and ground column ``bv[d]``, ``consts = [n, D_y, Q, k_2, c]``, the sub-steps per
    record step and their length ``h``."""

    A: np.ndarray
    bv: np.ndarray
    consts: np.ndarray
    acc1: np.ndarray
    acc2: np.ndarray
    substeps: int
    h: float
    n: int

    @property
    def width(self) -> int:
        """Entries of one direction's state."""
        return 2 * self.n + 1

    def run(self, floors, k0, k1, x, carry, XS, MODES, peak, EV, SEG, COEF) -> int:
        """:func:`~floorslide.building._plane_bilinear_kernel.bilinear_run` over record steps
        ``k0 … k1 − 1``."""
        return bk.bilinear_run(self.A, self.bv, self.consts, floors, self.acc1, self.acc2,
                               self.substeps, self.h, k0, k1, x, carry, XS, MODES, peak, EV,
                               SEG, COEF)  # fmt: skip


def bilinear_setup(bx, by, h1: np.ndarray, h2: np.ndarray, dt: float) -> BilinearSetup:
    """The kernel's inputs for the pair of models `bx`, `by` (one mat, one layer) under the
    components `h1`, `h2` at step `dt`: the sub-steps are the larger of the two models'
    (``ρ·h ≤ 0.5`` on every branch, elastic ``k_1`` included)."""
    n = bx.n_dof
    iz = 2 * n
    c = bx.constants
    A = np.zeros((2, iz + 1, iz + 1))
    bv = np.zeros((2, iz + 1))
    for d, b in enumerate((bx, by)):
        Ad, bd = b.branch_system(PLASTIC_POS)  # k_2 on the mat; −1/m_b on the constant force
        A[d] = Ad
        A[d, :, iz] *= c["Q"]  # the plastic element's force Q z
        A[d, iz, :] = 0.0  # z's row is the kernel's own
        bv[d] = bd
    consts = np.array([n, c["D_y"], c["Q"], c["k2"], c["c"]], dtype=float)
    m = max(bx.substeps(dt), by.substeps(dt))
    return BilinearSetup(A, bv, consts, h1, h2, m, dt / m, n)


def initial_state(s: BilinearSetup, displacement=None, velocity=None) -> tuple[np.ndarray, ...]:
    """The state ``(2, 2n+1)`` and the carried ``(mode, fresh, events)`` at t = 0: the mat at
    `displacement` and `velocity` (default rest; the floors displaced with it, at rest
    relative to it), the plastic element strained elastically up to ``D_y`` along the
    displacement (``z = u/D_y``, or ``u/|u|`` beyond ``D_y``: the rest of the displacement
    plastic, as :func:`floorslide.building.nonlinear._initial` in 1-D), elastic."""
    n = s.n
    x = np.zeros((2, s.width))
    if displacement is not None:
        x[:, 0] = np.asarray(displacement, dtype=float)
        x[:, 1:n] = x[:, [0]]
    if velocity is not None:
        x[:, n] = np.asarray(velocity, dtype=float)
    u = x[:, 0]
    r = float(np.hypot(u[0], u[1]))
    dy = float(s.consts[1])
    x[:, 2 * n] = u / dy if r <= dy else u / r
    return x, np.array([bk.ELASTIC, 0.0, 0.0])


def limit_message(t: float) -> str:
    """Why the integrator stopped at `t` (s)."""
    return (
        f"the lead-rubber bearing needed more than {bk.MAX_STEPS} series steps in one sub-step "
        f"at t = {t:.6g} s (or its series overflowed)"
    )


def bilinear_response(motion, XS, MODES, peak, EV, carry):
    """The bearing's outputs (:class:`~floorslide.building.plane_isolation.
    PlaneIsolatorResponse`) from the first pass of `motion`: its force ``k_2 u + c u' + Q z`` at
    the samples (``force_ratio``) and its peak inside steps (``peak_force_ratio``, as the 1-D
    layer's), ``friction_work`` the plastic (hysteretic) work ``∫ q·u_p' dt = Q ∫ z·u' dt``
    over the yielding branches (J), ``slide_fraction``/``sliding`` the share of time yielding
    and the branch at each sample, events ``"yield"`` and ``"unload"``."""
    from floorslide.building.plane_isolation import PlaneIsolatorResponse, response_fields

    bx, _ = motion.building
    s: BilinearSetup = motion._s
    n = s.n
    W = bx.weight
    c = bx.constants
    u = XS[:, :, 0].copy()
    v = XS[:, :, n].copy()
    z = XS[:, :, 2 * n]
    force = c["k2"] * u + c["c"] * v + c["Q"] * z
    acc = np.stack([motion.acc1, motion.acc2], axis=1)
    floor_acc = np.empty((XS.shape[0], n, 2))
    for d in range(2):
        rel = XS[:, d] @ s.A[d, n : 2 * n].T + acc[:, [d]] * s.bv[d, n : 2 * n]
        floor_acc[:, :, d] = rel + acc[:, [d]]
    return PlaneIsolatorResponse(
        **response_fields(motion, XS, n, peak, EV, int(carry[bk.C_EVENTS]), EVENT_NAMES, ()),
        floor_acceleration=floor_acc,
        peak_force_ratio=float(peak[pk.P_FORCE] / W),
        sliding=MODES == bk.PLASTIC,
        force_ratio=force / W,
        small_angle_exceeded=False,
    )
