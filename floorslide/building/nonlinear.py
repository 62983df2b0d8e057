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
from floorslide.building.model import ShearBuilding, check_floors
from floorslide.building.nonlinear_motion import (
    MAX_SEGMENT_BYTES,
    NonlinearMotion,
    _Kernel,
    integrate,
)
from floorslide.constants import G
from floorslide.errors import ModelError
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

    segmented = True
    """Its motion is a list of segments between isolator events (:class:`NonlinearMotion`)."""

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

    def check_floors(self, floors) -> list[int]:
        """Validate a floor selection (any order, repeats allowed; 0 is the base mat); ``None``
        means all floors."""
        return check_floors(floors, self.stories)

    def dof_of(self, floor: int) -> int:
        """The degree of freedom of `floor` (every floor is one; 0 is the base mat)."""
        (floor,) = self.check_floors([floor])
        return floor

    def motion(self, acc, dt: float | None = None, *, floors=None, **options):
        """The building's exact motion under a record, for every consumer
        (:func:`nonlinear_motion`)."""
        return nonlinear_motion(self, acc, dt, floors=floors, **options)

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


def _assembled(key, systems, mats, outputs, r_f, d_f, dt, m, n, mat_of):
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
        G = kern._chord_rows(RR, BB, ER, EB, OR, OB, n, dt / m, mat_of)
        for a in (PHI, PP, QQ, RR, BB, ER, EB, OR, OB, G):
            a.setflags(write=False)
        return PHI, PP, QQ, RR, BB, ER, EB, OR, OB, K, G

    return _memoised(_ASSEMBLY_CACHE, key, make)


def _kernel(building, acc, dt, floors, oscillator):
    """The kernel's matrices and constants for `building` at record step `dt` with output rows
    for `floors` (and an oscillator appended as states), and the sub-steps."""
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
    m = model_substeps(rho, dt, N)
    mat_of = np.full(7, -1, dtype=np.int64)  # -1: not a branch of this layer
    for j, b in enumerate(mats):
        mat_of[b] = j
    key = (prep_key, float(dt), int(m))
    PHI, PP, QQ, RR, BB, ER, EB, OR, OB, K, Gc = _assembled(
        key, systems, mats, outputs, r_f, d_f, dt, m, building.n_dof, mat_of
    )
    c = building.constants
    if building.kind == "bilinear":
        consts = [c["k1"] - c["k2"], c["D_y"], c["Q"], 0.0, 0.0]
    else:
        consts = [1.0, 0.0, 0.0, c["mu"] * c["W"], c["mu_s"] * c["W"]]
    consts = np.array(consts + list(r_f) + [d_f])
    kn = _Kernel(mat_of, PHI, PP, QQ, RR, BB, ER, EB, OR, OB, Gc, K, consts, building.n_dof,
                 MAX_EVENTS_PER_SUBSTEP, float(rho))  # fmt: skip
    return kn, m


def nonlinear_motion(
    building: NonlinearIsolatedBuilding,
    acc,
    dt: float | None = None,
    *,
    floors=None,
    initial_displacement=None,
    oscillator=None,
    keep_segments: bool = True,
    max_bytes: int = MAX_SEGMENT_BYTES,
) -> NonlinearMotion:
    """Integrate a building on nonlinear isolation once under a piecewise-linear record.

    Parameters
    ----------
    building
        The building.
    acc, dt
        Ground acceleration (m/s²) and its time step, or a Trace.
    floors
        Floors whose motion is kept (default all; 0 is the base mat): their absolute
        accelerations at the samples and true peaks, and the rows every consumer on them reads.
    initial_displacement
        Displacements relative to the ground at t = 0 (one per floor, 0 = the mat; default
        rest), for free-vibration checks.
    oscillator
        ``(floor, ω, ξ)``: a linear oscillator on `floor` integrated with the building as two
        more states of every branch; its peaks ``max|q|, max|q'|, max|ω²q + 2ξωq'|`` (SD, SV,
        SA) are then ``response.pfa`` instead of the floors' (the augmented form: an
        independent reference for the floor spectra read from the segments).
    keep_segments
        Record the segments for consumers (default); ``False`` for the building's own response
        only.
    max_bytes
        Largest segment record kept whole; a longer one is streamed (each consumer's pass
        integrates the chunks again from checkpoints the first pass records).

    Returns
    -------
    NonlinearMotion
        With ``response`` (:class:`IsolatorResponse`).

    Raises
    ------
    SolverLimitError
        More than :data:`MAX_EVENTS_PER_SUBSTEP` branch changes inside one sub-step.
    """
    acc, dt, notes = as_record(acc, dt)
    acc = np.array(acc, dtype=float)
    acc.setflags(write=False)
    n = building.n_dof
    floors = building.check_floors(floors)
    kn, m = _kernel(building, acc, dt, floors, oscillator)
    N = kn.N
    x0 = np.zeros(N)
    if initial_displacement is not None:
        u = np.asarray(initial_displacement, dtype=float).ravel()
        if u.size != n:
            raise ModelError(f"give {n} displacements (floors 0..{n - 1})", "initial_displacement")
        x0[:n] = u
    branch0 = _initial(building, x0, float(acc[0]))
    motion = NonlinearMotion(
        building,
        acc,
        float(dt),
        int(m),
        dt / m,
        tuple(floors),
        None,
        kn,
        notes=tuple(notes),
        augmented=oscillator is not None,
    )
    X, BR, Yo, events, peak, _ = integrate(motion, x0, branch0, keep_segments, max_bytes)
    motion.response = _response(building, motion, X, BR, Yo, events, peak, oscillator)
    return motion


def _response(building, motion, X, BR, Yo, events, peak, oscillator) -> IsolatorResponse:
    """The building's own response, from the first pass."""
    n = building.n_dof
    acc = motion.acc
    floors = list(motion.floors)
    if oscillator is None:
        acc_out = np.ascontiguousarray(Yo[:, :-2].T)
        force = Yo[:, -2].copy()
    else:
        # with an oscillator as states the outputs are the oscillator's: the floors' are formed
        # here from the states at the samples
        acc_out = np.empty((len(floors), acc.size))
        force = np.empty(acc.size)
        for b in sorted(set(building.branches())):
            sel = BR == b
            if not sel.any():
                continue
            C, D = building.output_rows(b, floors)
            vals = C @ X[sel, : 2 * n + 1].T + D[:, None] * acc[sel][None, :]
            acc_out[:, sel] = vals[:-2]
            force[sel] = vals[-2]
    ev_row, ev_tau, ev_branch = events
    times = ev_row * motion.h + ev_tau
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
    W = building.constants["W"]
    return IsolatorResponse(
        dt=float(motion.dt),
        substeps=int(motion.substeps),
        floors=tuple(floors),
        floor_acceleration=acc_out,
        pfa=peak.copy() if oscillator is not None else peak[:-2].copy(),
        isolator_displacement=X[:, 0].copy(),
        isolator_force=force,
        peak_displacement=peak_disp,
        residual_displacement=float(X[-1, 0]),
        peak_force_ratio=float("nan") if oscillator is not None else float(peak[-2] / W),
        branch=BR.copy(),
        event_times=times,
        event_branches=ev_branch.copy(),
        capacity_exceeded=exceeded,
        small_angle_exceeded=small_angle,
        notes=notes,
    )


def isolator_response(
    building: NonlinearIsolatedBuilding,
    acc,
    dt: float | None = None,
    *,
    floors=None,
    initial_displacement=None,
    oscillator=None,
) -> IsolatorResponse:
    """Exact response of a building on nonlinear isolation to a piecewise-linear record: the
    building's own outputs (:func:`nonlinear_motion` without keeping the segments; parameters
    as there)."""
    return nonlinear_motion(
        building,
        acc,
        dt,
        floors=floors,
        initial_displacement=initial_displacement,
        oscillator=oscillator,
        keep_segments=False,
    ).response
