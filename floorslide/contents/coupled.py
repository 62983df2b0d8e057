"""Heavy equipment coupled with its floor: a rigid block on a building, one system.

A block of mass ``m`` stands on floor ``j`` of a building (fixed-base
:class:`~floorslide.ShearBuilding`, linearly :class:`~floorslide.IsolatedBuilding`, or on
nonlinear isolation, :class:`~floorslide.NonlinearIsolatedBuilding`), 1-D,
Coulomb friction ``mu_s`` (breakaway) and ``mu_k`` (sliding). Coordinates as everywhere in
floorslide (docs/design.md §2): the building's displacements ``u`` relative to the ground, the
block's slide ``s`` relative to its floor, the floor's absolute acceleration
``a_f = u_j'' + a_g``. While the block

- **sticks**, it adds ``m`` to floor ``j``: ``(M + m e_j e_jᵀ) u'' + C u' + K u =
  −(M + m e_j e_jᵀ) ι a_g``; the friction it needs is ``m·a_f`` (``a_f`` of this stuck system);
- **slides** with relative velocity of sign ``σ``, friction ``−σ·mu_k·m·g`` acts on the block and
  its reaction ``+σ·mu_k·m·g`` on the floor: ``M u'' + C u' + K u = −M ι a_g + e_j·σ·mu_k·m·g``
  and ``m (a_f + s'') = −σ·mu_k·m·g``, i.e. ``s'' = −a_f − σ·mu_k·g`` (the rigid block's law of
  :func:`~floorslide.slide`, with ``a_f`` now the floor's acceleration under that force).

The block breaks away when the friction it needs, ``|m·a_f|``, exceeds ``mu_s·m·g`` (toward
``σ = −sign(a_f)``: the floor runs ahead of it), and stops when ``s'`` reaches 0; it then sticks
if the stuck system needs at most ``mu_s·m·g`` of friction there, else slides the other way. The
damping matrix ``C`` is the building's own: the block adds mass, not dashpots. Each phase is a
linear time-invariant system and the ground is piecewise linear, so the whole response is exact
(event-driven; :mod:`floorslide.contents._coupled_kernel`).

On a building on nonlinear isolation (:class:`~floorslide.NonlinearIsolatedBuilding`) the mode is
the pair (isolator branch, block phase), each pair linear time-invariant and the isolator's
events those of the building alone (:mod:`floorslide.contents.coupled_nonlinear`,
:mod:`floorslide.contents._coupled_nonlinear_kernel`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from floorslide.building.exact import ExactStepper, model_substeps, spectral_radius
from floorslide.building.model import LinearBuilding
from floorslide.building.nonlinear import NonlinearIsolatedBuilding
from floorslide.constants import G
from floorslide.contents import _coupled_kernel as kern
from floorslide.contents.events import SLIDE_MAX_EVENTS
from floorslide.contents.sliding import friction_pairs
from floorslide.errors import ModelError, SolverLimitError
from floorslide.inputs import RecordLike, as_record

__all__ = ["CoupledSlideResult", "slide_coupled"]


@dataclass(frozen=True)
class CoupledSlideResult:
    """A heavy block sliding on a floor it acts back on, one entry per case (mu_k, mu_s, mass).

    Attributes
    ----------
    mu_k, mu_s
        Kinetic and static friction coefficients.
    mass
        Mass of the block, kg.
    mass_ratio
        ``mass / floor_mass``.
    floor, floor_mass
        The floor the block stands on and its mass (kg, without the block).
    peak_slide
        ``max |s|``, m (``s`` the block's displacement relative to its floor).
    residual_slide
        ``s`` at the end of the record, m.
    slide_fraction
        Fraction of the record duration spent sliding.
    slip_phases
        Number of slip phases (breakaways and reversals).
    time_of_peak
        Time of the peak slide, s.
    pfa
        The floor's peak absolute acceleration with the block on it, m/s²: the true peak,
        inside steps too (the floor's acceleration jumps at breakaways and stops when
        ``mu_s > mu_k``; both sides count).
    time_of_pfa
        Its time, s.
    peak_abs_accel
        Peak absolute acceleration of the block, m/s² (the floor's while stuck, ``mu_k·g``
        while sliding).
    duration, dt, substeps
        Record duration (s), step (s) and the exact sub-steps per step.
    u, v, floor_acceleration, mode
        Histories at the samples, ``(n_cases, npts)``, only when requested: slide (m), its
        velocity (m/s), the floor's absolute acceleration with the block (m/s²; the input of
        a floor response spectrum, :func:`~floorslide.response_spectrum` — sample-based
        then) and the mode (0 stuck, ±1 sliding with that sign of velocity).
    notes
        What was done to the input record (unit conversion of a Trace), one line each; on a
        building on nonlinear isolation also a layer beyond its capacity or a pendulum beyond
        its small-angle range.
    peak_isolator_displacement, residual_isolator_displacement
        On a :class:`~floorslide.NonlinearIsolatedBuilding` only (else ``None``): the isolator's
        true peak ``|u_0|`` (inside steps) and its displacement at the end, m, per case.
    isolator_displacement
        Its history at the samples, ``(n_cases, npts)``, with ``histories`` (nonlinear
        isolation only).
    """

    mu_k: np.ndarray
    mu_s: np.ndarray
    mass: np.ndarray
    mass_ratio: np.ndarray
    floor: int
    floor_mass: float
    peak_slide: np.ndarray
    residual_slide: np.ndarray
    slide_fraction: np.ndarray
    slip_phases: np.ndarray
    time_of_peak: np.ndarray
    pfa: np.ndarray
    time_of_pfa: np.ndarray
    peak_abs_accel: np.ndarray
    duration: float
    dt: float
    substeps: int
    u: np.ndarray | None = field(default=None, repr=False)
    v: np.ndarray | None = field(default=None, repr=False)
    floor_acceleration: np.ndarray | None = field(default=None, repr=False)
    mode: np.ndarray | None = field(default=None, repr=False)
    notes: tuple[str, ...] = ()
    peak_isolator_displacement: np.ndarray | None = None
    residual_isolator_displacement: np.ndarray | None = None
    isolator_displacement: np.ndarray | None = field(default=None, repr=False)

    def to_records(self) -> list[dict]:
        """One JSON-ready dict per case (snake_case keys, SI values)."""
        keys = (
            "mu_k",
            "mu_s",
            "mass",
            "mass_ratio",
            "peak_slide",
            "residual_slide",
            "slide_fraction",
            "time_of_peak",
            "pfa",
            "time_of_pfa",
            "peak_abs_accel",
        )
        out = []
        for i in range(self.mu_k.size):
            row = {k: float(getattr(self, k)[i]) for k in keys}
            row["slip_phases"] = int(self.slip_phases[i])
            row["floor"] = self.floor
            if self.peak_isolator_displacement is not None:
                row["peak_isolator_displacement"] = float(self.peak_isolator_displacement[i])
                row["residual_isolator_displacement"] = float(
                    self.residual_isolator_displacement[i]
                )
            out.append(row)
        return out


def _check_building(building, *, nonlinear: bool = True):
    """The building, or a one-line ModelError naming ``building`` (also for a building on
    nonlinear isolation when not `nonlinear`: the approximate solvers are linear only)."""
    if building is None:
        raise ModelError(
            "slide_coupled needs building= (a ShearBuilding or IsolatedBuilding): on the "
            "ground the block acts back on nothing, use slide",
            "building",
        )
    if isinstance(building, LinearBuilding):
        return building
    if isinstance(building, NonlinearIsolatedBuilding):
        if nonlinear:
            return building
        raise ModelError(
            f"a block coupled with a {type(building).__name__} (nonlinear isolation) is not "
            "modelled by the approximate solvers: give a ShearBuilding or a linear "
            "IsolatedBuilding (slide_coupled integrates it exactly)",
            "building",
        )
    if getattr(building, "segmented", False):
        raise ModelError(
            "acc must be the ground record and building the building: a floor motion cannot "
            "carry a block that acts back on it",
            "building",
        )
    if hasattr(building, "h1") and hasattr(building, "h2"):
        raise ModelError(
            "a BuildingPair (one model per direction) is not modelled yet by slide_coupled "
            "(1-D): give one of its models (pair.h1 or pair.h2)",
            "building",
        )
    raise ModelError(
        "expected a ShearBuilding, IsolatedBuilding or NonlinearIsolatedBuilding, got "
        f"{type(building).__name__}",
        "building",
    )


def _check_floor(building: LinearBuilding, floor) -> int:
    """The degree of freedom of `floor`, or a one-line ModelError naming ``floor``."""
    if floor is None:
        raise ModelError("floor is required (the floor the block stands on)", "floor")
    (f,) = building.check_floors([floor])
    dof = building.dof_of(f)
    if dof is None:
        raise ModelError(
            "floor 0 of a fixed-base building is the ground: the block acts back on nothing "
            "there, use slide",
            "floor",
        )
    return dof


def _masses(mass, floor_mass: float, floor: int) -> np.ndarray:
    """The block masses as a 1-D array, or a one-line ModelError naming ``mass``."""
    if mass is None:
        raise ModelError("mass (of the block, kg) is required", "mass")
    arr = np.atleast_1d(np.asarray(mass, dtype=float)).ravel()
    if arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(arr <= 0):
        raise ModelError(f"mass must be finite and > 0 kg, got {arr.tolist()}", "mass")
    big = arr[arr > floor_mass]
    if big.size:
        raise ModelError(
            f"mass {big[0]:g} kg is larger than floor {floor}'s own mass {floor_mass:g} kg: "
            "that is not equipment on a floor but a different building (model it as one)",
            "mass",
        )
    return arr


def branch_system(building: LinearBuilding, dof: int, mass: float, branch: int):
    """``(A, b)`` of the augmented state ``[u; u'; s; s'; f]`` on `branch`
    (:data:`~floorslide.contents._coupled_kernel.STICK` or ``SLIDE``), block of `mass` kg on
    degree of freedom `dof`, and the rows ``(floor, event)`` of the floor's absolute
    acceleration and of the branch's event function."""
    n = building.n_dof
    N = 2 * n + 3
    i_s, i_v, i_f = 2 * n, 2 * n + 1, 2 * n + 2
    M = np.array(building.mass, dtype=float)
    if branch == kern.STICK:
        M[dof] += mass
    A = np.zeros((N, N))
    A[:n, n : 2 * n] = np.eye(n)
    A[n : 2 * n, :n] = -building.stiffness_matrix / M[:, None]
    A[n : 2 * n, n : 2 * n] = -building.damping_matrix / M[:, None]
    b = np.zeros(N)
    b[n : 2 * n] = -1.0
    if branch == kern.SLIDE:
        A[n + dof, i_f] = mass / M[dof]  # the reaction m·f of the block's friction
        A[i_s, i_v] = 1.0
        A[i_v] = -A[n + dof]  # s'' = −a_f − f, a_f = u_j'' + a_g = A[n+j]·x
        A[i_v, i_f] -= 1.0
    floor_row = A[n + dof].copy()  # a_f = A[n+j]·x + (b[n+j] + 1)·a_g, the last term 0
    event_row = floor_row if branch == kern.STICK else np.eye(N)[i_v]
    return A, b, floor_row, event_row


_CACHE: dict = {}
_CACHE_SIZE = 16


def _setup(building: LinearBuilding, dof: int, mass: float, dt: float, mus: float, muk: float):
    """The kernel's :class:`~floorslide.contents._coupled_kernel.CoupledSetup` (matrices
    memoised on the building's matrices, the floor, the mass and dt: friction sweeps pay for
    the matrix exponentials once)."""
    key = (
        building.mass.tobytes(),
        building.stiffness_matrix.tobytes(),
        building.damping_matrix.tobytes(),
        dof,
        float(mass),
        float(dt),
    )
    hit = _CACHE.get(key)
    if hit is None:
        systems = [branch_system(building, dof, mass, b) for b in (kern.STICK, kern.SLIDE)]
        N = systems[0][0].shape[0]
        rho = max(spectral_radius(s[0]) for s in systems)
        m = model_substeps(rho, dt, N)
        steppers = [ExactStepper.build(s[0], s[1], dt, m) for s in systems]
        K = max(st.order for st in steppers)
        phi = np.empty((2, N, N))
        p = np.empty((2, N))
        q = np.empty((2, N))
        SR = np.empty((2, N, K + 1, N))
        SB = np.empty((2, N, K + 1))
        ER = np.empty((2, K + 1, N))
        EB = np.empty((2, K + 1))
        FR = np.empty((2, K + 1, N))
        FB = np.empty((2, K + 1))
        for j, (st, (_A, _b, frow, erow)) in enumerate(zip(steppers, systems, strict=True)):
            phi[j] = st.phi
            p[j], q[j] = st.input_weights()
            SR[j], SB[j] = st.taylor_rows(np.eye(N), order=K)
            er, eb = st.taylor_rows(erow[None, :], order=K)
            ER[j], EB[j] = er[0], eb[0]
            fr, fb = st.taylor_rows(frow[None, :], order=K)
            FR[j], FB[j] = fr[0], fb[0]
        hit = (phi, p, q, SR, SB, ER, EB, FR, FB, m, st.h, N)
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = hit
    phi, p, q, SR, SB, ER, EB, FR, FB, m, h, N = hit
    n = building.n_dof
    return kern.CoupledSetup(
        phi, p, q, SR, SB, ER, EB, FR, FB, int(m), float(h),
        np.array([mus * G, muk * G]), np.array([2 * n, 2 * n + 1, 2 * n + 2], dtype=np.int64),
        SLIDE_MAX_EVENTS,
    )  # fmt: skip


def slide_coupled(
    acc: RecordLike,
    dt: float | None = None,
    mu_k=None,
    *,
    mass=None,
    building: LinearBuilding | None = None,
    floor: int | None = None,
    mu_s=None,
    histories: bool = False,
) -> CoupledSlideResult:
    """Sliding of a heavy rigid block that acts back on its floor (building and block
    integrated together, exactly).

    Parameters
    ----------
    acc
        Ground acceleration samples, m/s², taken as piecewise linear; or an ObsPy Trace or
        one-trace Stream (see :mod:`floorslide.inputs`). Not a FloorMotion: the block changes
        the floor's motion, which therefore cannot be integrated beforehand.
    dt
        Time step, s.
    mu_k
        Kinetic friction coefficient(s) ≥ 0, required.
    mass
        Mass of the block, kg: ``0 < mass ≤`` the floor's own mass. `mu_k`, `mu_s` and `mass`
        broadcast together; each case is one integration of building and block.
    building
        A :class:`~floorslide.ShearBuilding`, a linear :class:`~floorslide.IsolatedBuilding` or
        a :class:`~floorslide.NonlinearIsolatedBuilding` (lead-rubber or friction pendulum;
        :mod:`floorslide.contents.coupled_nonlinear`: a pendulum carries the block's weight,
        ``W = (M + m)·g``, a lead-rubber layer keeps its constants). Its damping matrix is kept:
        the block adds mass, not damping.
    floor
        The floor the block stands on (1..N on a fixed-base building, 0..N isolated: 0 is the
        base mat).
    mu_s
        Static (breakaway) coefficient(s), default `mu_k`; ``mu_s ≥ mu_k``.
    histories
        Also return the slide, its velocity, the floor's absolute acceleration and the mode at
        the samples.

    Returns
    -------
    CoupledSlideResult

    Raises
    ------
    ModelError
        A missing or invalid argument, one line naming it: no building or floor, floor 0 of a
        fixed-base building (the ground), a BuildingPair (not modelled yet: the plane),
        ``mass ≤ 0`` or larger than the floor's, ``mu_s < mu_k``.
    SolverLimitError
        Stick–slip (or isolator) chatter beyond the event limit in one sub-step.

    Notes
    -----
    Limits (tests): ``mass → 0`` is the decoupled :func:`~floorslide.slide` on the building's
    floor; friction so large that the block never slides is the building with ``mass`` added
    to the floor; ``mu_k = mu_s = 0`` leaves the building as if the block were absent (the block
    stays where it was in absolute terms, its slide ``= −u_j``). ``mu_s < mu_k`` is refused:
    at a breakaway the stuck system's floor acceleration is just beyond ``mu_s·g``, and kinetic
    friction larger than that stops the block at once (no consistent slide).

    References
    ----------
    Westermo, B., Udwadia, F. (1983). Periodic response of a sliding oscillator system to
    harmonic excitation. *Earthquake Eng. Struct. Dyn.* 11, 135–146 (stick–slip with events).
    Van Loan, C. F. (1978). Computing integrals involving the matrix exponential. *IEEE Trans.
    Automatic Control* 23(3), 395–404 (the exact first-order-hold steps).
    """
    from floorslide.building.exact_motion import FloorMotion
    from floorslide.building.nonlinear_motion import NonlinearMotion
    from floorslide.building.plane_isolation import PlaneIsolatedMotion

    if isinstance(acc, FloorMotion | NonlinearMotion | PlaneIsolatedMotion) or getattr(
        acc, "segmented", False
    ):
        raise ModelError(
            "acc must be the ground record: the block acts back on the building, so its floor "
            "motion cannot be integrated beforehand",
            "acc",
        )
    building = _check_building(building)
    dof = _check_floor(building, floor)
    nonlinear = isinstance(building, NonlinearIsolatedBuilding)
    f = dof if nonlinear else int(building.dof_floors[dof])
    if mu_k is None:
        raise ModelError("mu_k (the kinetic friction coefficient) is required", "mu_k")
    mk, ms = friction_pairs(mu_k, mu_s)
    low = np.flatnonzero(ms < mk)
    if low.size:
        i = int(low[0])
        raise ModelError(
            f"mu_s = {ms[i]:g} < mu_k = {mk[i]:g}: a coupled block needs mu_s ≥ mu_k (kinetic "
            "friction above the breakaway level would stop it at once)",
            "mu_s",
        )
    floor_mass = float(building.mass[dof])
    masses = _masses(mass, floor_mass, f)
    try:
        mk, ms, masses = (np.ascontiguousarray(v) for v in np.broadcast_arrays(mk, ms, masses))
    except ValueError:
        raise ModelError(
            f"mass ({masses.size} values) must be one value or one per mu_k ({mk.size})", "mass"
        ) from None
    a, dt, notes = as_record(acc, dt, "acc")
    npts = a.size
    ncase = mk.size
    shape = (ncase, npts) if histories else (ncase, 0)
    hs, hv, ha = np.zeros(shape), np.zeros(shape), np.zeros(shape)
    hm = np.zeros(shape, dtype=np.int64)
    if nonlinear:
        return _slide_coupled_nonlinear(
            building, dof, a, dt, mk, ms, masses, floor_mass, histories, notes
        )
    res = np.zeros((ncase, kern.NOUT))
    residual = np.zeros(ncase)
    substeps = 1
    for i in range(ncase):
        S = _setup(building, dof, float(masses[i]), dt, float(ms[i]), float(mk[i]))
        substeps = S.substeps
        x = np.zeros(S.phi.shape[1])
        kern.coupled_run(S, a, x, res[i], hs[i], hv[i], ha[i], hm[i])
        if res[i, kern.LIMIT_AT] >= 0.0:
            raise SolverLimitError(
                f"slide_coupled: more than {SLIDE_MAX_EVENTS} friction events inside one "
                f"sub-step at t = {res[i, kern.LIMIT_AT]:.6g} s (mu_k = {mk[i]:g}, mass = "
                f"{masses[i]:g} kg): stick-slip chatter the exact solver cannot resolve; check "
                "the record for spikes"
            )
        residual[i] = x[S.index[0]]
    return _result(kern, res, mk, ms, masses, f, floor_mass, residual, npts, dt, substeps,
                   (hs, hv, ha, hm) if histories else None, notes)  # fmt: skip


def _result(K, res, mk, ms, masses, floor, floor_mass, residual, npts, dt, substeps, hist, notes,
            **extra) -> CoupledSlideResult:  # fmt: skip
    """The :class:`CoupledSlideResult` of a kernel's result rows `res` (columns of the kernel
    module `K`: the linear or the nonlinear one, which name them alike); `hist` the histories
    ``(u, v, floor acceleration, mode)`` or None; `extra` the nonlinear building's fields."""
    duration = (npts - 1) * dt
    hs, hv, ha, hm = hist if hist is not None else (None,) * 4
    return CoupledSlideResult(
        mu_k=mk,
        mu_s=ms,
        mass=masses,
        mass_ratio=masses / floor_mass,
        floor=floor,
        floor_mass=floor_mass,
        peak_slide=res[:, K.PEAK_SLIDE].copy(),
        residual_slide=residual,
        slide_fraction=res[:, K.SLIDE_TIME] / duration if duration > 0 else np.zeros(len(res)),
        slip_phases=res[:, K.SLIPS].astype(int),
        time_of_peak=res[:, K.T_PEAK].copy(),
        pfa=res[:, K.PFA].copy(),
        time_of_pfa=res[:, K.T_PFA].copy(),
        peak_abs_accel=res[:, K.BLOCK_PEAK_ACC].copy(),
        duration=duration,
        dt=dt,
        substeps=int(substeps),
        u=hs,
        v=hv,
        floor_acceleration=ha,
        mode=hm,
        notes=tuple(notes),
        **extra,
    )


def _slide_coupled_nonlinear(building, dof, a, dt, mk, ms, masses, floor_mass, histories, notes):
    """:func:`slide_coupled` on a :class:`~floorslide.NonlinearIsolatedBuilding`
    (:mod:`floorslide.contents.coupled_nonlinear`)."""
    from floorslide.building.isolators import small_angle_exceeded, small_angle_note
    from floorslide.contents import _coupled_nonlinear_kernel as nkern
    from floorslide.contents import coupled_nonlinear as cnl

    npts = a.size
    ncase = mk.size
    shape = (ncase, npts) if histories else (ncase, 0)
    hs, hv, ha, hu = (np.zeros(shape) for _ in range(4))
    hm = np.zeros(shape, dtype=np.int64)
    res = np.zeros((ncase, nkern.NOUT))
    residual = np.zeros(ncase)
    residual_iso = np.zeros(ncase)
    substeps = 1
    n = building.n_dof
    for i in range(ncase):
        S, _consts = cnl.setup(building, dof, float(masses[i]), dt, float(ms[i]), float(mk[i]))
        substeps = S.substeps
        x = np.zeros(S.phi.shape[1])
        branch = cnl.initial_branch(building)
        nkern.coupled_nonlinear_run(S, a, x, branch, res[i], hs[i], hv[i], ha[i], hm[i], hu[i])
        if res[i, nkern.LIMIT_AT] >= 0.0:
            raise SolverLimitError(
                f"slide_coupled: more than {SLIDE_MAX_EVENTS} friction or isolator events "
                f"inside one sub-step at t = {res[i, nkern.LIMIT_AT]:.6g} s (mu_k = {mk[i]:g}, "
                f"mass = {masses[i]:g} kg): chatter the exact solver cannot resolve; check the "
                "record for spikes"
            )
        residual[i] = x[2 * n + 1]
        residual_iso[i] = x[0]
    peak_iso = res[:, nkern.ISO_PEAK].copy()
    iso = building.isolator
    worst = float(peak_iso.max())
    if iso.capacity is not None and worst > iso.capacity:
        notes = [
            *notes,
            f"isolator displacement {worst:.4g} m exceeds its capacity {iso.capacity:g} m: the "
            "impact that would follow is not modelled",
        ]
    if small_angle_exceeded(iso, worst):
        notes = [*notes, small_angle_note(worst, iso.R)]
    return _result(nkern, res, mk, ms, masses, dof, floor_mass, residual, npts, dt, substeps,
                   (hs, hv, ha, hm) if histories else None, notes,
                   peak_isolator_displacement=peak_iso,
                   residual_isolator_displacement=residual_iso,
                   isolator_displacement=hu if histories else None)  # fmt: skip
