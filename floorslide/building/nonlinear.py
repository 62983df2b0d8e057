"""Buildings on nonlinear (piecewise-linear) isolation, integrated exactly, events inside steps.

:class:`NonlinearIsolatedBuilding` is a superstructure on a base mat over a
:class:`~floorslide.building.isolators.BilinearIsolator` or
:class:`~floorslide.building.isolators.FrictionPendulum` layer. :func:`isolator_response`
integrates it under a piecewise-linear ground record with the compiled event-driven kernel
(:mod:`floorslide.building._nonlinear_kernel`): on each sub-step the active branch is linear
time-invariant and stepped exactly; yield, unloading, breakaway, stop and reversal are located
inside sub-steps as first crossings of the branch's in-step polynomials. The result holds the
floors' absolute accelerations and the isolator's displacement and force at the samples, their
true peaks (inside steps), the residual isolator displacement, the branch history and the
events.

Status: the building alone. Sliding contents and floor spectra on such a building (the exact
chain of issue 14) read its motion in a later step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from floorslide.building import _nonlinear_kernel as kern
from floorslide.building.exact import (
    ExactStepper,
    model_substeps,
    spectral_radius,
    substeps_for,
)
from floorslide.building.isolators import (
    BRANCH_NAMES,
    ELASTIC,
    PLASTIC_NEG,
    PLASTIC_POS,
    SLIP_NEG,
    SLIP_POS,
    STICK,
    BilinearIsolator,
    FrictionPendulum,
    small_angle_exceeded,
    small_angle_note,
)
from floorslide.building.model import ShearBuilding
from floorslide.constants import G
from floorslide.errors import ModelError, NonFiniteError, SolverLimitError
from floorslide.inputs import as_record

MAX_EVENTS_PER_SUBSTEP = 64


class NonlinearIsolatedBuilding:
    """A superstructure on a base mat over a nonlinear isolation layer.

    Parameters
    ----------
    superstructure
        The fixed-base building.
    base_mass_ratio
        ``m_b / m`` (> 0), ``m`` the superstructure's mass.
    isolator
        A :class:`BilinearIsolator` or :class:`FrictionPendulum`.
    """

    def __init__(self, superstructure: ShearBuilding, base_mass_ratio: float, isolator):
        if not isinstance(superstructure, ShearBuilding):
            raise ModelError("superstructure must be a ShearBuilding", "superstructure")
        if not isinstance(isolator, BilinearIsolator | FrictionPendulum):
            raise ModelError(
                "isolator must be a BilinearIsolator or a FrictionPendulum", "isolator"
            )
        ratio = float(base_mass_ratio)
        if not np.isfinite(ratio) or ratio <= 0:
            raise ModelError(f"must be > 0, got {base_mass_ratio!r}", "base_mass_ratio")
        ms = superstructure.mass
        self.superstructure = superstructure
        self.isolator = isolator
        self.base_mass_ratio = ratio
        n = ms.size + 1
        iota = np.ones(ms.size)

        def assemble(sup: np.ndarray) -> np.ndarray:
            out = np.zeros((n, n))
            out[0, 0] = iota @ sup @ iota
            out[0, 1:] = -iota @ sup
            out[1:, 0] = -sup @ iota
            out[1:, 1:] = sup
            return out

        with np.errstate(over="ignore", invalid="ignore"):
            self.mass = np.concatenate([[ratio * ms.sum()], ms])
            self.stiffness_matrix = assemble(superstructure.stiffness_matrix)
            self.damping_matrix = assemble(superstructure.damping_matrix)
            self.constants = isolator.constants(self.total_mass)
        finite = [self.mass, self.stiffness_matrix, self.damping_matrix]
        if not all(np.all(np.isfinite(a)) for a in finite) or not all(
            np.isfinite(v) for v in self.constants.values()
        ):
            raise ModelError(
                "the building's matrices or isolator constants are not finite (they overflow "
                "float64): give masses (kg) and stiffnesses (N/m) of a building",
                "base_mass_ratio",
            )

    @property
    def n_dof(self) -> int:
        return self.mass.size

    @property
    def stories(self) -> int:
        return self.n_dof - 1

    @property
    def floors(self) -> tuple[int, ...]:
        return tuple(range(self.n_dof))

    @property
    def total_mass(self) -> float:
        return float(self.mass.sum())

    @property
    def weight(self) -> float:
        """``W = M g``, N."""
        return self.total_mass * G

    @property
    def kind(self) -> str:
        return "bilinear" if isinstance(self.isolator, BilinearIsolator) else "friction_pendulum"

    def equivalent_linear(self, displacement: float):
        """The equivalent-linear isolated building at a design isolator displacement (m): the
        same superstructure and mat on a linear layer with the effective period and damping
        of :func:`~floorslide.building.isolators.equivalent_linear` — what a linear analysis
        would use, to compare with the nonlinear response."""
        from floorslide.building.isolators import equivalent_linear
        from floorslide.building.model import IsolatedBuilding

        period, damping = equivalent_linear(self.isolator, self.total_mass, displacement)
        if damping >= 1:
            raise ModelError(
                f"effective damping {damping:.3g} ≥ 1 at {displacement:g} m", "displacement"
            )
        return IsolatedBuilding(self.superstructure, self.base_mass_ratio, period, damping)

    def substeps(self, dt: float) -> int:
        """Sub-steps per record step of `dt` on which every branch is stepped exactly
        (``ρ·h ≤ 0.5`` for the fastest branch; :func:`~floorslide.building.exact.model_substeps`:
        a ModelError beyond its limits)."""
        systems = [self.branch_system(b)[0] for b in self.branches()]
        rho = max(spectral_radius(A) for A in systems)
        return model_substeps(rho, dt, systems[0].shape[0])

    def branches(self) -> tuple[int, ...]:
        """The branches this layer can be on."""
        if self.kind == "bilinear":
            return (ELASTIC, PLASTIC_POS, PLASTIC_NEG)
        return (SLIP_POS, SLIP_NEG, STICK)

    def branch_system(self, branch: int) -> tuple[np.ndarray, np.ndarray]:
        """``A`` (N × N) and ``b`` of the augmented state ``[u; u'; F0]`` on `branch`."""
        n = self.n_dof
        N = 2 * n + 1
        c = self.constants
        if branch == ELASTIC:
            k, cv = c["k1"], c["c"]
        elif branch in (PLASTIC_POS, PLASTIC_NEG):
            k, cv = c["k2"], c["c"]
        else:
            k, cv = c["k"], c["c"]
        Minv = 1.0 / self.mass
        Kt = self.stiffness_matrix.copy()
        Ct = self.damping_matrix.copy()
        Kt[0, 0] += k
        Ct[0, 0] += cv
        A = np.zeros((N, N))
        A[:n, n : 2 * n] = np.eye(n)
        A[n : 2 * n, :n] = -Minv[:, None] * Kt
        A[n : 2 * n, n : 2 * n] = -Minv[:, None] * Ct
        A[n, 2 * n] = -Minv[0]
        b = np.zeros(N)
        b[n : 2 * n] = -1.0
        if branch == STICK:  # the mat moves with the ground
            A[0, :] = 0.0
            A[n, :] = 0.0
            b[n] = 0.0
        return A, b

    def needed_friction_row(self) -> tuple[np.ndarray, float]:
        """``(r, d)`` with the friction a stuck pendulum needs ``F = r·x + d·a_g``."""
        n = self.n_dof
        N = 2 * n + 1
        r = np.zeros(N)
        r[:n] = -self.stiffness_matrix[0]
        r[n : 2 * n] = -self.damping_matrix[0]
        r[0] -= self.constants.get("k", 0.0)
        return r, -float(self.mass[0])

    def output_rows(self, branch: int, floors) -> tuple[np.ndarray, np.ndarray]:
        """Rows ``C, D`` of the absolute accelerations of `floors`, then the isolator force,
        then the isolator displacement."""
        A, b = self.branch_system(branch)
        n = self.n_dof
        N = 2 * n + 1
        C = np.zeros((len(floors) + 2, N))
        D = np.zeros(len(floors) + 2)
        C[-1, 0] = 1.0
        for j, f in enumerate(floors):
            C[j] = A[n + f]
            D[j] = b[n + f] + 1.0
        c = self.constants
        if branch == STICK:
            r, d = self.needed_friction_row()
            C[-2] = r
            C[-2, 0] += c["k"]
            D[-2] = d
        else:
            # f = k u0 + c u0' + F0 = −m_b (u0'' + a_g) + (storey force on the mat)
            C[-2] = -self.mass[0] * A[n]
            C[-2, :n] -= self.stiffness_matrix[0]
            C[-2, n : 2 * n] -= self.damping_matrix[0]
            D[-2] = -self.mass[0] * (b[n] + 1.0)
        return C, D


@dataclass(frozen=True)
class IsolatorResponse:
    """The response of a :class:`NonlinearIsolatedBuilding` to one record.

    Attributes
    ----------
    dt, substeps
        Record step and sub-steps per step.
    floors
        Floors of ``floor_acceleration`` (0 = the base mat).
    floor_acceleration
        Absolute accelerations at the samples, ``(len(floors), npts)``, m/s².
    pfa
        True peak absolute acceleration per floor (inside steps), m/s².
    isolator_displacement, isolator_force
        At the samples (m, N); the force is the layer's on the mat.
    peak_displacement
        ``max |u_0|`` inside steps, m.
    residual_displacement
        ``u_0`` at the end of the record, m.
    peak_force_ratio
        ``max |f_iso| / W`` (base shear over weight at the isolation level).
    branch
        Branch at each sample (see :data:`~floorslide.building.isolators.BRANCH_NAMES`).
    event_times, event_branches
        When the layer changed branch and into which.
    """

    dt: float
    substeps: int
    floors: tuple[int, ...]
    floor_acceleration: np.ndarray
    pfa: np.ndarray
    isolator_displacement: np.ndarray
    isolator_force: np.ndarray
    peak_displacement: float
    residual_displacement: float
    peak_force_ratio: float
    branch: np.ndarray
    event_times: np.ndarray
    event_branches: np.ndarray
    capacity_exceeded: bool = False
    """The isolator displacement went beyond the layer's ``capacity`` (when one is given)."""
    small_angle_exceeded: bool = False
    """A friction pendulum without a ``capacity`` went beyond
    :attr:`~floorslide.building.isolators.FrictionPendulum.small_angle_limit` (``0.2 R``),
    where its small-angle restoring force ``(W/R)·u`` is more than 2 % off."""
    notes: tuple[str, ...] = ()
    block_states: np.ndarray | None = None
    """Final states of the rigid blocks asked for (columns of ``floorslide.contents._kernels``)."""
    block_slides: np.ndarray | None = None
    """Their slides at the samples (with ``block_histories=True``), m."""
    oscillator_peaks: np.ndarray | None = None
    """Peaks ``max|q|, max|q'|, max|ω²q + 2ξωq'|`` of the oscillators asked for."""
    flexible_states: np.ndarray | None = None
    """Final states of the 2-DOF sliding oscillators asked for (columns of
    ``floorslide.contents._oscillator_kernel``)."""
    flexible_histories: np.ndarray | None = None
    """With ``flexible_histories=True``: the 2-DOF oscillators' ``(u, z, top, base)`` at the
    samples, ``(n, npts, 4)`` (as :func:`floorslide.slide_oscillator`'s histories)."""
    rocker_states: np.ndarray | None = None
    """Final states of the rocking blocks asked for (columns of
    ``floorslide.contents._rocking_kernel``)."""
    rocker_theta: np.ndarray | None = None
    """With ``rocker_histories=True``: their ``θ`` at the samples (NaN once overturned), rad."""

    def branch_names(self) -> list[str]:
        return [BRANCH_NAMES[b] for b in self.branch]


def _augmented(building: NonlinearIsolatedBuilding, branch: int, oscillator):
    """The branch's ``(A, b)``, with an oscillator ``(floor, ω, ξ)`` on a floor appended as
    states ``[q, q']`` driven by the floor's absolute acceleration:
    ``q'' = −ω² q − 2ξω q' − a_f``."""
    A, b = building.branch_system(branch)
    if oscillator is None:
        return A, b
    floor, w, xi = oscillator
    n = building.n_dof
    N = A.shape[0]
    Aa = np.zeros((N + 2, N + 2))
    Aa[:N, :N] = A
    ba = np.concatenate([b, [0.0, 0.0]])
    Aa[N, N + 1] = 1.0
    Aa[N + 1, N] = -w * w
    Aa[N + 1, N + 1] = -2.0 * xi * w
    Aa[N + 1, :N] = -A[n + floor]  # −a_f = −(A[n+f]·x + (b[n+f] + 1)·a_g)
    ba[N + 1] = -(b[n + floor] + 1.0)
    return Aa, ba


def _outputs(building, branch, floors, oscillator, N):
    """Output rows of a run: the floors' absolute accelerations, the isolator force and
    displacement; or, with an oscillator, its ``q``, ``q'`` and absolute acceleration."""
    if oscillator is None:
        return building.output_rows(branch, floors)
    _floor, w, xi = oscillator
    C = np.zeros((3, N))
    C[0, N - 2] = 1.0
    C[1, N - 1] = 1.0
    C[2, N - 2] = -w * w
    C[2, N - 1] = -2.0 * xi * w
    return C, np.zeros(3)


def _initial(building: NonlinearIsolatedBuilding, x0: np.ndarray, a0: float) -> int:
    """The branch at t = 0 (the layer at rest unless `x0` strains it)."""
    c = building.constants
    n = building.n_dof
    if building.kind == "bilinear":
        u = x0[0]
        pl = u - np.clip(u, -c["D_y"], c["D_y"])
        x0[2 * n] = -(c["k1"] - c["k2"]) * pl
        return ELASTIC
    r, d = building.needed_friction_row()
    x0[n] = 0.0
    F = float(r @ x0[: r.size] + d * a0)
    if abs(F) <= c["mu_s"] * c["W"]:
        return STICK
    x0[2 * n] = np.sign(F) * c["mu"] * c["W"]
    return SLIP_POS if F > 0 else SLIP_NEG


_OSCILLATORS_BY_SERIES = False
"""Private switch: advance the riders of ``oscillators=`` by the series on every sub-step (the
reference path of the tests) instead of their exact linear update on sub-steps without events
(:func:`floorslide.building._nonlinear_kernel._riders_fast`)."""
_LAST_RIDER_STATS = np.zeros(4, dtype=np.int64)
"""Counters of the last call with riders (sub-steps on the fast path, rider·sub-steps there,
flagged rider·sub-steps, polynomial searches): for profiling and tests."""

_CACHE_SIZE = 32
"""Most buildings (with their floors, time step …) whose matrices are kept per cache."""
_PREPARED_CACHE: dict = {}
_ASSEMBLY_CACHE: dict = {}


def _memoised(cache: dict, key, make):
    """``cache[key]``, made by ``make()`` the first time (the oldest entry is dropped beyond
    :data:`_CACHE_SIZE`)."""
    hit = cache.get(key)
    if hit is None:
        if len(cache) >= _CACHE_SIZE:
            cache.pop(next(iter(cache)))
        hit = cache[key] = make()
    return hit


def _prepared(key, building, floors, oscillator):
    """The layer's branches (sorted), each branch's ``(A, b)``, their largest spectral radius,
    the output rows per branch and the needed-friction row, memoised on `key` (the building's
    matrices and constants, the floors and the oscillator)."""

    def make():
        mats = sorted(set(building.branches()))
        systems = {b: _augmented(building, b, oscillator) for b in mats}
        N = next(iter(systems.values()))[0].shape[0]
        rho = max(spectral_radius(A) for A, _ in systems.values())
        outputs = [_outputs(building, b, floors, oscillator, N) for b in mats]
        r_f, d_f = building.needed_friction_row()
        r_f = np.concatenate([r_f, np.zeros(N - r_f.size)])
        return systems, rho, mats, outputs, r_f, float(d_f)

    return _memoised(_PREPARED_CACHE, key, make)


def _assembled(key, systems, mats, outputs, r_f, d_f, dt, m):
    """The kernel's matrices for the branches `mats` (exact sub-step recurrences, Taylor rows
    of the states, of the needed friction and of the outputs), memoised on `key` — the bytes
    of the building's matrices and constants, the floors, the oscillator, dt and the sub-steps
    — so that a building used on many records (or many calls) pays for its matrix
    exponentials once. The arrays are shared between calls and never written."""

    def make():
        steppers = {b: ExactStepper.build(*systems[b], dt, m) for b in mats}
        K = max(s.order for s in steppers.values())
        N = next(iter(systems.values()))[0].shape[0]
        nb = len(mats)
        nout = outputs[0][0].shape[0]
        PHI = np.empty((nb, N, N))
        PP = np.empty((nb, N))
        QQ = np.empty((nb, N))
        RR = np.empty((nb, N, K + 1, N))
        BB = np.empty((nb, N, K + 1))
        ER = np.zeros((nb, K + 1, N))
        EB = np.zeros((nb, K + 1))
        OR = np.empty((nb, nout, K + 1, N))
        OB = np.empty((nb, nout, K + 1))
        for j, b in enumerate(mats):
            st = steppers[b]
            PHI[j] = st.phi
            PP[j], QQ[j] = st.input_weights()
            RR[j], BB[j] = st.taylor_rows(np.eye(N), order=K)
            if b == STICK:
                er, eb = st.taylor_rows(r_f[None, :], np.array([d_f]), order=K)
                ER[j], EB[j] = er[0], eb[0]
            C, D = outputs[j]
            OR[j], OB[j] = st.taylor_rows(C, D, order=K)
        return PHI, PP, QQ, RR, BB, ER, EB, OR, OB, K

    return _memoised(_ASSEMBLY_CACHE, key, make)


def isolator_response(
    building: NonlinearIsolatedBuilding,
    acc,
    dt: float | None = None,
    *,
    floors=None,
    initial_displacement=None,
    blocks=None,
    oscillator=None,
    block_histories: bool = False,
    oscillators=None,
    flexible=None,
    flexible_histories: bool = False,
    rockers=None,
    rocker_histories: bool = False,
) -> IsolatorResponse:
    """Exact response of a building on nonlinear isolation to a piecewise-linear record.

    Parameters
    ----------
    building
        The building.
    acc, dt
        Ground acceleration (m/s²) and its time step, or a Trace.
    floors
        Floors whose absolute accelerations are returned (default all).
    initial_displacement
        Displacements relative to the ground at t = 0 (one per floor, 0 = the mat; default
        rest), for free-vibration checks.
    blocks
        Rigid blocks riding along, ``(floor, mu_b, mu_k, direction)`` each (``mu_b`` the
        breakaway coefficient ``max(mu_s, mu_k)``; direction ``"both"``, ``"positive"`` or
        ``"negative"``): each advanced exactly, segment by segment, by the rigid-block kernel
        on the floor's exact in-step acceleration (:func:`slide_on_isolation` wraps this).
        Their final states are in ``block_states``.
    oscillator
        ``(floor, ω, ξ)``: a linear oscillator on `floor` riding along (it does not act
        back), integrated with the building as two more states of every branch; its peaks
        ``max|q|, max|q'|, max|ω²q + 2ξωq'|`` (SD, SV, SA) are then ``pfa`` instead of the
        floors' (the augmented form; a reference for the next).
    oscillators
        ``[(floor, ω, ξ), …]``: linear oscillators riding along (they do not act back); their
        peaks ``(SD, SV, SA)`` are in ``oscillator_peaks`` (:func:`floor_spectrum_on_isolation`
        wraps this). On a sub-step without isolator events (the common case) each is advanced
        by its exact linear update ``(q, q')(h) = Φ·(q, q')(0) + W_branch·[x; a_g; slope]``
        and searched inside the sub-step only where a rigorous filter cannot rule out a new
        peak; through a segment between events by the Taylor series of its exact response to
        the floor's in-step polynomial (``_OSCILLATORS_BY_SERIES`` forces the series
        everywhere: the reference of the tests).
    flexible
        ``(floor, f, ξ, r, mu_b, mu_k)``: 2-DOF sliding oscillators (frequency ``f`` Hz, damping
        ξ, mass ratio ``r``; breakaway and kinetic friction arrays) riding along, advanced by
        the 2-DOF kernel's exact step (:func:`slide_oscillator_on_isolation` wraps this);
        final states in ``flexible_states``; with ``flexible_histories`` their histories at
        the samples in ``flexible_histories``.
    rockers
        ``(floor, par, states, nonlinear)``: rocking blocks on `floor` riding along, parameters
        ``par`` and initial states ``states`` as :func:`floorslide.rock` prepares them (the
        columns of :mod:`floorslide.contents._rocking_kernel`), the full equation when
        `nonlinear`; advanced by its exact part step on the floor's in-step polynomial
        (:func:`floorslide.rock` wraps this); final states in ``rocker_states``, with
        ``rocker_histories`` ``θ`` at the samples in ``rocker_theta``.

    Returns
    -------
    IsolatorResponse

    Raises
    ------
    SolverLimitError
        More than :data:`MAX_EVENTS_PER_SUBSTEP` branch changes inside one sub-step.
    """
    acc, dt, _notes = as_record(acc, dt)
    n = building.n_dof
    N = 2 * n + 1
    floors = list(building.floors) if floors is None else [int(f) for f in floors]
    for f in floors:
        if not 0 <= f < n:
            raise ModelError(f"floor {f} does not exist; floors are 0..{n - 1}", "floors")
    prep_key = (
        building.kind,
        building.mass.tobytes(),
        building.stiffness_matrix.tobytes(),
        building.damping_matrix.tobytes(),
        tuple(sorted(building.constants.items())),
        tuple(floors),
        None if oscillator is None else tuple(float(v) for v in oscillator),
    )
    systems, rho, mats, outputs, r_f, d_f = _prepared(prep_key, building, floors, oscillator)
    N = next(iter(systems.values()))[0].shape[0]
    oscillators = [] if oscillators is None else list(oscillators)
    m = model_substeps(rho, dt, N)
    from floorslide.contents.oscillator import phase_radius

    if flexible is not None:
        f_floor, f_hz, f_xi, f_r, f_mub, f_muk = flexible
        w2 = 2 * np.pi * float(f_hz)
        rho_obj = phase_radius(w2, float(f_xi), float(f_r))
        h_b = dt / m
        ho2 = h_b / substeps_for(rho_obj, h_b)
    mat_of = np.full(7, -1, dtype=np.int64)  # -1: not a branch of this layer
    for j, b in enumerate(mats):
        mat_of[b] = j
    nout = 3 if oscillator is not None else len(floors) + 2
    key = (prep_key, float(dt), int(m))
    assembled = _assembled(key, systems, mats, outputs, r_f, d_f, dt, m)
    PHI, PP, QQ, RR, BB, ER, EB, OR, OB, K = assembled
    c = building.constants
    W = c["W"]
    if building.kind == "bilinear":
        consts = [c["k1"] - c["k2"], c["D_y"], c["Q"], 0.0, 0.0]
    else:
        consts = [1.0, 0.0, 0.0, c["mu"] * W, c["mu_s"] * W]
    consts = np.array(consts + list(r_f) + [d_f])
    x0 = np.zeros(N)
    if initial_displacement is not None:
        u = np.asarray(initial_displacement, dtype=float).ravel()
        if u.size != n:
            raise ModelError(f"give {n} displacements (floors 0..{n - 1})", "initial_displacement")
        x0[:n] = u
    branch0 = _initial(building, x0, float(acc[0]))
    X = np.empty((acc.size, N))
    BR = np.empty(acc.size, dtype=np.int64)
    cap = max(64, acc.size)
    peak = np.zeros(nout)
    t_peak = np.zeros(nout)
    from floorslide.contents._kernels import LIMIT_AT, NCOL
    from floorslide.contents.events import SLIDE_MAX_EVENTS

    blocks = [] if blocks is None else list(blocks)
    # oscillators by floor, then by their own rate (the kernel shares the floor polynomial's
    # shifts between oscillators with the same part grid)
    osc_out = np.array([floors.index(int(o[0])) for o in oscillators], dtype=np.int64)
    osc_w = np.array([float(o[1]) for o in oscillators])
    osc_xi = np.array([float(o[2]) for o in oscillators])
    osc_rho = osc_w * np.where(osc_xi > 1.0, osc_xi + np.sqrt(np.abs(osc_xi**2 - 1.0)), 1.0)
    osc_order = np.lexsort((osc_rho, osc_out))
    osc_out, osc_w, osc_xi, osc_rho = (
        osc_out[osc_order],
        osc_w[osc_order],
        osc_xi[osc_order],
        osc_rho[osc_order],
    )
    from floorslide.building.exact import taylor_degree

    # each oscillator goes through a segment in parts with ρ·h ≤ MAX_PHASE (the kernel's 0.5)
    phase = min(0.5, float(osc_rho.max()) * dt / m) if oscillators else 0.0
    D = max(K, taylor_degree(phase)) + 2
    from floorslide.contents._oscillator_kernel import O_LIMIT_AT, O_NCOL

    if flexible is not None:
        K2 = max(K, taylor_degree(max(rho, rho_obj) * ho2))
        flex = np.array([floors.index(int(f_floor)), w2, float(f_xi), float(f_r), ho2, K2])
        mub2 = np.ascontiguousarray(f_mub, dtype=float)
        muk2 = np.ascontiguousarray(f_muk, dtype=float)
    else:
        flex = np.array([0.0, 1.0, 0.0, 1.0, 1.0, 3.0])
        mub2 = np.zeros(0)
        muk2 = np.zeros(0)
    blk_out = np.array([floors.index(int(b[0])) for b in blocks], dtype=np.int64)
    order = np.argsort(blk_out, kind="stable")
    blk_out = blk_out[order]
    blk_floor = np.array([int(blocks[i][0]) for i in order], dtype=np.int64)
    mub = np.array([float(blocks[i][1]) for i in order])
    muk = np.array([float(blocks[i][2]) for i in order])
    dirs = {str(b[3]) for b in blocks} or {"both"}
    if len(dirs) > 1:
        raise ModelError("blocks of one call slide in one direction setting", "direction")
    (direction,) = dirs
    # the outputs (floors' accelerations, isolator force) at the samples, from the kernel; with
    # an oscillator riding as states its outputs are the oscillator's, so the floors' are
    # formed here afterwards
    Yo = np.empty((acc.size, nout) if oscillator is None else (0, nout))
    H2 = np.zeros((muk2.size, acc.size, 4) if flexible_histories else (0, 0, 4))
    from floorslide.contents import _rocking_kernel as rk

    if rockers is not None:
        rk_floor, rk_par0, rk_states0, rk_nonlinear = rockers
        rk_par = np.ascontiguousarray(rk_par0, dtype=float)
        rk_out = np.full(rk_par.shape[0], floors.index(int(rk_floor)), dtype=np.int64)
        rk_phase = rk.NONLINEAR_PHASE if rk_nonlinear else rk.LINEAR_PHASE
        # parts of p·L ≤ rk_phase on every segment (the kernel splits each), the series degree
        # as floorslide.rock chooses it for that phase
        rk_D = max(K + 2, taylor_degree(rk_phase * (2.0 if rk_nonlinear else 1.0)))
    else:
        rk_par = np.zeros((0, rk.NPAR))
        rk_states0 = np.zeros((0, rk.NCOL))
        rk_out = np.zeros(0, dtype=np.int64)
        rk_nonlinear, rk_phase, rk_D = False, rk.LINEAR_PHASE, 3
    while True:
        ev_row = np.empty(cap, dtype=np.int64)
        ev_tau = np.empty(cap)
        ev_branch = np.empty(cap, dtype=np.int64)
        peak[:] = 0.0
        bstates = np.zeros((len(blocks), NCOL))
        bstates[:, LIMIT_AT] = -1.0
        hist_u = np.zeros((len(blocks), acc.size) if block_histories else (0, 0))
        osc_S = np.zeros((2, len(oscillators)))
        osc_P = np.zeros((3, len(oscillators)))
        osc_stats = np.zeros(4, dtype=np.int64)
        S2 = np.zeros((muk2.size, O_NCOL))
        S2[:, O_LIMIT_AT] = -1.0
        rk_states = np.array(rk_states0, dtype=float, copy=True)
        rk_hist = np.zeros((rk_out.size, acc.size) if rocker_histories else (0, 0))
        n_ev = kern.nonlinear_run(
            mat_of, PHI, PP, QQ, RR, BB, ER, EB, OR, OB, K, consts, acc, m, dt / m,
            x0, branch0, X, BR, ev_row, ev_tau, ev_branch, peak, t_peak, MAX_EVENTS_PER_SUBSTEP,
            blk_out, blk_floor, mub, muk, direction != "negative", direction != "positive", G,
            bstates, n,
            hist_u, osc_out, osc_w, osc_xi, osc_rho, osc_S, osc_P, D, flex, mub2, muk2, S2,
            Yo, H2, rk_out, rk_par, rk_states, rk_D, bool(rk_nonlinear), rk_phase, rk_hist,
            not _OSCILLATORS_BY_SERIES, osc_stats,
        )  # fmt: skip
        if len(blocks) and (bstates[:, LIMIT_AT] >= 0).any():
            t = float(bstates[bstates[:, LIMIT_AT] >= 0, LIMIT_AT].min())
            raise SolverLimitError(
                f"more than {SLIDE_MAX_EVENTS} friction events of a block inside one segment at "
                f"t = {t:.6g} s: stick-slip chatter the exact solver cannot resolve",
                "blocks",
            )
        if n_ev < 0:
            row = -1 - n_ev
            raise SolverLimitError(
                f"more than {MAX_EVENTS_PER_SUBSTEP} isolator events inside one sub-step at "
                f"t = {row * dt / m:.6g} s: stick–slip chatter the exact solver cannot resolve",
                "isolator",
            )
        if n_ev <= cap:
            break
        cap = n_ev
    if oscillators:
        _LAST_RIDER_STATS[:] = osc_stats
    h = dt / m
    samples = X
    br = BR
    if not (np.all(np.isfinite(peak)) and np.all(np.isfinite(samples[-1]))):
        raise NonFiniteError(
            "the building's response is not finite (it overflows float64)", "building"
        )
    if oscillator is None:
        acc_out = np.ascontiguousarray(Yo[:, :-2].T)
        force = Yo[:, -2].copy()
    else:
        acc_out = np.empty((len(floors), acc.size))
        force = np.empty(acc.size)
        for b in mats:
            sel = br == b
            if not sel.any():
                continue
            C, D = building.output_rows(b, floors)
            vals = C @ samples[sel, : 2 * n + 1].T + D[:, None] * acc[sel][None, :]
            acc_out[:, sel] = vals[:-2]
            force[sel] = vals[-2]
    times = ev_row[:n_ev] * h + ev_tau[:n_ev]
    cap_m = building.isolator.capacity
    # (with `oscillator`, peak holds the oscillator's peaks, not the isolator's)
    peak_disp = float("nan") if oscillator is not None else float(peak[-1])
    exceeded = cap_m is not None and peak_disp > cap_m
    notes = ()
    if exceeded:
        notes = (
            f"isolator displacement {peak_disp:.4g} m exceeds its capacity {cap_m:g} m: "
            "the impact that would follow (moat wall, bearing rim) is not modelled; the response "
            "after it is that of an unlimited layer",
        )
    small_angle = small_angle_exceeded(building.isolator, peak_disp)
    if small_angle:
        notes += (small_angle_note(peak_disp, building.isolator.R),)
    return IsolatorResponse(
        dt=float(dt),
        substeps=int(m),
        floors=tuple(floors),
        floor_acceleration=acc_out,
        pfa=peak.copy() if oscillator is not None else peak[:-2].copy(),
        isolator_displacement=samples[:, 0].copy(),
        isolator_force=force,
        peak_displacement=peak_disp,
        residual_displacement=float(samples[-1, 0]),
        peak_force_ratio=float("nan") if oscillator is not None else float(peak[-2] / W),
        branch=br.copy(),
        event_times=times,
        event_branches=ev_branch[:n_ev].copy(),
        capacity_exceeded=exceeded,
        small_angle_exceeded=small_angle,
        notes=notes,
        block_states=bstates[np.argsort(order, kind="stable")] if len(blocks) else None,
        block_slides=hist_u[np.argsort(order, kind="stable")] if block_histories else None,
        oscillator_peaks=osc_P.T[np.argsort(osc_order, kind="stable")] if oscillators else None,
        flexible_states=S2 if flexible is not None else None,
        flexible_histories=H2 if flexible is not None and flexible_histories else None,
        rocker_states=rk_states if rockers is not None else None,
        rocker_theta=rk_hist if rockers is not None and rocker_histories else None,
    )


def slide_on_isolation(
    building: NonlinearIsolatedBuilding,
    acc,
    dt: float | None = None,
    mu_k=None,
    mu_s=None,
    *,
    floor: int,
    direction: str = "both",
    histories: bool = False,
):
    """Rigid blocks (Coulomb friction) on a floor of a building on nonlinear isolation, exact
    end to end: ground → nonlinear building (events located inside steps) → block (the
    rigid-block kernel on the floor's exact in-step acceleration, segment by segment).

    Parameters as :func:`floorslide.slide` (``mu_k``, ``mu_s`` one value or one per object;
    breakaway at ``max(mu_s, mu_k)·g``); no vertical shaking.

    Returns
    -------
    SlideResult
        With the isolator's response in ``notes``-free form (see :func:`isolator_response` for
        the building itself).
    """
    from floorslide.contents._kernels import DISP as DISP_COL
    from floorslide.contents._kernels import PEAK_ACC, PEAK_DISP, SLIDE_TIME, SLIPS, T_PEAK
    from floorslide.contents.sliding import SlideResult

    acc, dt, notes = as_record(acc, dt)
    if direction not in ("both", "positive", "negative"):
        raise ModelError(f"direction must be both, positive or negative, got {direction!r}")
    mk = np.atleast_1d(np.asarray(mu_k, dtype=float))
    ms = mk.copy() if mu_s is None else np.broadcast_to(np.asarray(mu_s, dtype=float), mk.shape)
    if mk.size == 0 or np.any(~np.isfinite(mk)) or np.any(mk < 0) or np.any(ms < 0):
        raise ModelError("friction coefficients must be finite and ≥ 0", "mu_k")
    mb = np.maximum(mk, ms)
    blocks = [(floor, mb[i], mk[i], direction) for i in range(mk.size)]
    r = isolator_response(
        building, acc, dt, floors=[floor], blocks=blocks, block_histories=histories
    )
    S = r.block_states
    duration = (acc.size - 1) * dt
    return SlideResult(
        mu_k=mk,
        mu_s=np.asarray(ms, dtype=float).copy(),
        peak_slide=S[:, PEAK_DISP].copy(),
        residual_slide=S[:, DISP_COL].copy(),
        peak_abs_accel=S[:, PEAK_ACC].copy(),
        slide_fraction=S[:, SLIDE_TIME] / duration if duration > 0 else np.zeros(mk.size),
        slip_phases=S[:, SLIPS].astype(np.int64),
        time_of_peak=S[:, T_PEAK].copy(),
        liftoff_time=0.0,
        liftoff_count=0,
        duration=duration,
        method="exact",
        direction=direction,
        u=r.block_slides,
        notes=tuple(notes),
    )


def floor_spectrum_on_isolation(
    building: NonlinearIsolatedBuilding,
    acc,
    dt: float | None = None,
    periods=None,
    damping=(0.05,),
    *,
    floor: int,
):
    """Floor response spectra of a building on nonlinear isolation, exact end to end.

    Every oscillator ``(T, ξ)`` rides along one integration of the building (it does not act
    back), and its peaks are found inside steps (:func:`isolator_response` with
    ``oscillators=``): on a sub-step without isolator events by its exact linear update
    (precomputed per branch) and a rigorous filter that leaves few sub-steps to search; through
    a segment between events by the Taylor series of its exact response to the floor's
    in-step polynomial. The building keeps its own sub-steps; each oscillator's series goes
    through them in parts short for it (``ω h ≤ 0.5``).

    Returns
    -------
    Spectrum
        ``psa = ω²·SD``, ``sa``, ``sv``, ``sd``, ``psv = ω·SD``; a period of 0 gives the
        floor's true peak acceleration.
    """
    from floorslide.spectra.core import Spectrum, check_oscillators, damping_ratios, period_grid

    acc, dt, notes = as_record(acc, dt)
    T = period_grid([0.1, 0.5, 1.0] if periods is None else periods)
    Z = damping_ratios(damping)
    check_oscillators(T, Z, dt)
    shape = (Z.size, T.size)
    sd, sv, sa = np.zeros(shape), np.zeros(shape), np.zeros(shape)
    cells = [(i, j) for i in range(Z.size) for j in range(T.size) if T[j] > 0]
    oscs = [(floor, 2 * np.pi / T[j], Z[i]) for i, j in cells]
    r = isolator_response(building, acc, dt, floors=[floor], oscillators=oscs or None)
    for (i, j), (q, v, a) in zip(cells, r.oscillator_peaks if oscs else [], strict=True):
        sd[i, j], sv[i, j], sa[i, j] = q, v, a
    sa[:, T == 0] = r.pfa[0]
    w = np.where(T > 0, 2 * np.pi / np.where(T > 0, T, 1.0), 0.0)
    psa = np.where(T > 0, w * w * sd, sa)
    return Spectrum(T, Z, psa, sa, sv, sd, w * sd, method="exact", notes=tuple(notes))


def slide_oscillator_on_isolation(
    building: NonlinearIsolatedBuilding,
    acc,
    dt: float | None = None,
    mu=None,
    frequency: float | None = None,
    damping: float = 0.02,
    mass_ratio: float = 1.0,
    *,
    mu_s=None,
    floor: int,
    histories: bool = False,
):
    """2-DOF sliding oscillators (flexible equipment) on a floor of a building on nonlinear
    isolation, exact end to end: the 2-DOF kernel's event-driven step runs on the floor's exact
    in-step acceleration, segment by segment, inside the building's integration.

    Parameters as :func:`floorslide.slide_oscillator` (``histories``: also the histories of
    ``u``, ``z`` and both absolute accelerations at the samples).

    Returns
    -------
    OscillatorResult
    """
    from floorslide.contents import _oscillator_kernel as cols
    from floorslide.contents.events import OSCILLATOR_MAX_EVENTS
    from floorslide.contents.oscillator import OscillatorResult

    acc, dt, notes = as_record(acc, dt)
    mk = np.atleast_1d(np.asarray(mu, dtype=float))
    ms = mk.copy() if mu_s is None else np.broadcast_to(np.asarray(mu_s, dtype=float), mk.shape)
    if mk.size == 0 or np.any(~np.isfinite(mk)) or np.any(mk < 0) or np.any(ms < 0):
        raise ModelError("friction coefficients must be finite and ≥ 0", "mu")
    f = float(frequency) if frequency is not None else float("nan")
    if not (np.isfinite(f) and f > 0):
        raise ModelError(f"frequency must be > 0 Hz, got {frequency}", "frequency")
    mb = np.maximum(mk, ms)
    r = isolator_response(
        building,
        acc,
        dt,
        floors=[floor],
        flexible=(floor, f, float(damping), float(mass_ratio), mb, mk),
        flexible_histories=histories,
    )
    S = r.flexible_states
    H = r.flexible_histories
    if (S[:, cols.O_LIMIT_AT] >= 0).any():
        raise SolverLimitError(
            f"more than {OSCILLATOR_MAX_EVENTS} friction events of a 2-DOF oscillator inside one "
            "part: stick-slip chatter the exact solver cannot resolve",
            "slide_oscillator",
        )
    duration = (acc.size - 1) * dt
    return OscillatorResult(
        mu_k=mk,
        mu_s=np.asarray(ms, dtype=float).copy(),
        peak_slide=S[:, cols.O_PEAK_U].copy(),
        residual_slide=S[:, cols.O_U].copy(),
        peak_deformation=S[:, cols.O_PEAK_Z].copy(),
        peak_top_accel=S[:, cols.O_PEAK_TOP].copy(),
        peak_base_accel=S[:, cols.O_PEAK_BASE].copy(),
        slide_fraction=S[:, cols.O_SLIDE_TIME] / duration if duration > 0 else np.zeros(mk.size),
        slip_phases=S[:, cols.O_SLIPS].astype(int),
        u=H[:, :, 0].copy() if histories else None,
        z=H[:, :, 1].copy() if histories else None,
        top_accel=H[:, :, 2].copy() if histories else None,
        base_accel=H[:, :, 3].copy() if histories else None,
        notes=tuple(notes),
    )
