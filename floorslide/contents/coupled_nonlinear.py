"""The matrices of a heavy block coupled with a building on nonlinear isolation (1-D).

:func:`~floorslide.slide_coupled` on a :class:`~floorslide.NonlinearIsolatedBuilding`: the
discrete mode is the pair (isolator branch, block phase), each pair linear time-invariant
(:mod:`floorslide.contents._coupled_nonlinear_kernel`). This module builds each pair's system
``(A, b)`` of the augmented state ``[u (n); u' (n); F0; s; s'; f]`` and the kernel's stacks.

The layer under the block (docs/design.md §10f): a friction pendulum carries the block's weight
whatever the block does (its vertical load is the building's and the block's), so its constants
are those of the building with the block's mass, ``W = (M + m)·g``: restoring stiffness ``W/R``,
friction ``mu·W`` (and its viscous term from ``M + m``). A lead-rubber layer's stiffnesses and
strength are properties of the rubber and lead, given for the building: its constants are the
building's own (without the block).
"""

from __future__ import annotations

import numpy as np

from floorslide.building.exact import ExactStepper, model_substeps, spectral_radius
from floorslide.building.isolators import (
    ELASTIC,
    PLASTIC_NEG,
    PLASTIC_POS,
    STICK,
)
from floorslide.constants import G
from floorslide.contents import _coupled_nonlinear_kernel as kern
from floorslide.contents.events import SLIDE_MAX_EVENTS


def layer_constants(building, mass: float) -> dict:
    """The layer's constants under the building with a block of `mass` kg on it (module
    notes): a pendulum's from the total mass with the block, a lead-rubber layer's the
    building's own."""
    if building.kind == "bilinear":
        return dict(building.constants)
    return building.isolator.constants(building.total_mass + mass)


def pair_system(building, dof: int, mass: float, branch: int, phase: int, consts: dict):
    """``(A, b)`` of the augmented state ``[u; u'; F0; s; s'; f]`` on the layer's `branch` with
    the block (of `mass` kg on degree of freedom `dof`) in `phase`
    (:data:`~floorslide.contents._coupled_nonlinear_kernel.STUCK` or ``SLIDING``); then the rows
    ``(C, D)`` of the floor's absolute acceleration and of the friction a stuck pendulum needs
    (zero on the other branches)."""
    n = building.n_dof
    N = 2 * n + 4
    iF, i_s, i_v, i_f = 2 * n, 2 * n + 1, 2 * n + 2, 2 * n + 3
    M = np.array(building.mass, dtype=float)
    if phase == kern.STUCK:
        M[dof] += mass
    if branch == ELASTIC:
        k, cv = consts["k1"], consts["c"]
    elif branch in (PLASTIC_POS, PLASTIC_NEG):
        k, cv = consts["k2"], consts["c"]
    else:
        k, cv = consts["k"], consts["c"]
    Kt = building.stiffness_matrix.copy()
    Ct = building.damping_matrix.copy()
    Kt[0, 0] += k
    Ct[0, 0] += cv
    A = np.zeros((N, N))
    A[:n, n : 2 * n] = np.eye(n)
    A[n : 2 * n, :n] = -Kt / M[:, None]
    A[n : 2 * n, n : 2 * n] = -Ct / M[:, None]
    A[n, iF] = -1.0 / M[0]
    b = np.zeros(N)
    b[n : 2 * n] = -1.0
    if phase == kern.SLIDING:
        A[n + dof, i_f] = mass / M[dof]  # the reaction m·f of the block's friction
    if branch == STICK:  # the mat moves with the ground
        A[0, :] = 0.0
        A[n, :] = 0.0
        b[n] = 0.0
    if phase == kern.SLIDING:
        # s'' = −a_f − f, a_f = A[n+j]·x + (b[n+j] + 1)·a_g
        A[i_s, i_v] = 1.0
        A[i_v] = -A[n + dof]
        A[i_v, i_f] -= 1.0
        b[i_v] = -(b[n + dof] + 1.0)
    floor = (A[n + dof].copy(), b[n + dof] + 1.0)
    r = np.zeros(N)
    d = 0.0
    if branch == STICK:
        # F = −(K u + C u')_0 − k u_0 − M_0 a_g (+ m f on the mat while the block slides)
        r[:n] = -building.stiffness_matrix[0]
        r[n : 2 * n] = -building.damping_matrix[0]
        r[0] -= k
        d = -M[0]
        if phase == kern.SLIDING and dof == 0:
            r[i_f] = mass
    return A, b, floor, (r, d)


_CACHE: dict = {}
_CACHE_SIZE = 16


def setup(building, dof: int, mass: float, dt: float, mus: float, muk: float):
    """The kernel's :class:`~floorslide.contents._coupled_nonlinear_kernel.CoupledNonlinearSetup`
    (matrices memoised on the building, the floor, the mass and dt), and the layer's
    constants."""
    consts = layer_constants(building, mass)
    key = (
        building.kind,
        building.mass.tobytes(),
        building.stiffness_matrix.tobytes(),
        building.damping_matrix.tobytes(),
        tuple(sorted(consts.items())),
        dof,
        float(mass),
        float(dt),
    )
    hit = _CACHE.get(key)
    if hit is None:
        branches = sorted(set(building.branches()))
        mat_of = np.full(7, -1, dtype=np.int64)
        for j, br in enumerate(branches):
            mat_of[br] = j
        systems = [
            pair_system(building, dof, mass, br, ph, consts)
            for br in branches
            for ph in (kern.STUCK, kern.SLIDING)
        ]
        N = systems[0][0].shape[0]
        rho = max(spectral_radius(s[0]) for s in systems)
        m = model_substeps(rho, dt, N)
        steppers = [ExactStepper.build(s[0], s[1], dt, m) for s in systems]
        K = max(st.order for st in steppers)
        P = len(systems)
        phi = np.empty((P, N, N))
        p = np.empty((P, N))
        q = np.empty((P, N))
        SR = np.empty((P, N, K + 1, N))
        SB = np.empty((P, N, K + 1))
        ER = np.zeros((P, K + 1, N))
        EB = np.zeros((P, K + 1))
        FR = np.empty((P, K + 1, N))
        FB = np.empty((P, K + 1))
        for j, (st, (_A, _b, (fr, fd), (er, ed))) in enumerate(zip(steppers, systems, strict=True)):
            phi[j] = st.phi
            p[j], q[j] = st.input_weights()
            SR[j], SB[j] = st.taylor_rows(np.eye(N), order=K)
            rows, beta = st.taylor_rows(fr[None, :], np.array([fd]), order=K)
            FR[j], FB[j] = rows[0], beta[0]
            if np.any(er != 0.0):
                rows, beta = st.taylor_rows(er[None, :], np.array([ed]), order=K)
                ER[j], EB[j] = rows[0], beta[0]
        hit = (phi, p, q, SR, SB, ER, EB, FR, FB, mat_of, int(m), float(st.h))
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = hit
    phi, p, q, SR, SB, ER, EB, FR, FB, mat_of, m, h = hit
    if building.kind == "bilinear":
        layer = [consts["k1"] - consts["k2"], consts["D_y"], consts["Q"], 0.0, 0.0]
    else:
        layer = [1.0, 0.0, 0.0, consts["mu"] * consts["W"], consts["mu_s"] * consts["W"]]
    S = kern.CoupledNonlinearSetup(
        phi, p, q, SR, SB, ER, EB, FR, FB, mat_of, m, h,
        np.array([mus * G, muk * G, *layer]), int(building.n_dof), SLIDE_MAX_EVENTS,
    )  # fmt: skip
    return S, consts


def initial_branch(building) -> int:
    """The layer's branch at t = 0 from rest: elastic, or a stuck pendulum (the kernel settles
    it: a record that starts beyond its friction breaks it away at once)."""
    return ELASTIC if building.kind == "bilinear" else STICK
