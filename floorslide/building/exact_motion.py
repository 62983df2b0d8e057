"""The exact floor motion: computed once, read by every exact solver.

A building driven by a piecewise-linear ground record is integrated **once** by one compiled
kernel (:func:`floorslide.building._kernels.foh_states`, the exact first-order-hold recurrence,
Van Loan 1978) on its own sub-steps (``ρ(A)·h ≤ 0.5``, :mod:`floorslide.building.exact`). The
result, a :class:`BuildingMotion`, holds the building's state at the start of every sub-step;
a :class:`FloorMotion` is one floor of it: with the floor's Taylor rows, the state at a sub-step
start gives the Taylor polynomial of the floor's absolute acceleration on that sub-step, equal
to the exact in-step function to rounding. Sliding blocks, the 2-DOF oscillator, floor spectra,
the true peak floor acceleration and the floor samples all read this object; none steps the
building itself. The ground is the trivial case: no states, and the record's own linear
segments (polynomials of degree 1).

Memory is bounded: a motion whose states fit in :data:`MAX_STATE_BYTES` keeps them whole;
a longer one is *streamed*: each consumer's pass recomputes the states chunk by chunk
(:data:`CHUNK_BYTES`) from the state at the chunk's start, which the first pass records (the
same recurrence from the same state: the same bits), so a million-sample record on a 50-storey
building needs well under a megabyte besides its samples, at the price of one recurrence pass
per consumer. The solvers called with ``building=`` and ``floor=`` stream the motion they build
(they are its only consumer, so nothing is integrated twice and memory stays O(1)).

References
----------
Van Loan, C. F. (1978). Computing integrals involving the matrix exponential. *IEEE Trans.
Automatic Control* 23(3), 395–404.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np

from floorslide.building._kernels import foh_peaks, foh_states, state_outputs
from floorslide.building.exact import ExactStepper
from floorslide.building.model import LinearBuilding
from floorslide.building.nonlinear_motion import NonlinearFloorMotion
from floorslide.errors import ModelError, NonFiniteError
from floorslide.inputs import RecordLike, as_record

__all__ = [
    "CHUNK_BYTES",
    "MAX_STATE_BYTES",
    "BuildingMotion",
    "FloorMotion",
    "building_motion",
    "floor_motion",
    "ground_peak",
    "single_use_motion",
    "stepper",
    "unwrap",
]

MAX_STATE_BYTES = 128 * 2**20
"""Largest building-state history (bytes) a motion keeps whole."""

CHUNK_BYTES = 256 * 2**10
"""Size of one chunk of states handed out by a streamed motion (small: it is the memory a
streamed motion needs besides its checkpoints, and it stays in the cache)."""


def stepper(building: LinearBuilding, dt: float, substeps: int | None = None) -> ExactStepper:
    """The exact stepper of `building` for record step `dt`.

    Discretising is a matrix exponential and an eigenvalue problem (about a millisecond), done
    once per record and content otherwise; a small cache keyed by the *values* of the state
    matrices (never by object identity, so it cannot go stale) keeps it, and each call gets its
    own copies of the arrays (nothing shared can be written)."""
    A, B = building.state_matrices()
    A = np.ascontiguousarray(A, dtype=float)
    b = np.ascontiguousarray(B[:, 0], dtype=float)
    st = _cached_stepper(A.shape[0], A.tobytes(), b.tobytes(), float(dt), substeps)
    return dataclasses.replace(
        st,
        A=st.A.copy(),
        b=st.b.copy(),
        phi=st.phi.copy(),
        gamma0=st.gamma0.copy(),
        gamma1=st.gamma1.copy(),
    )


@functools.lru_cache(maxsize=32)
def _cached_stepper(
    n: int, A_bytes: bytes, b_bytes: bytes, dt: float, substeps: int | None
) -> ExactStepper:
    A = np.frombuffer(A_bytes).reshape(n, n).copy()
    b = np.frombuffer(b_bytes).copy()
    return ExactStepper.build(A, b, dt, substeps)


@dataclass(frozen=True, eq=False)
class BuildingMotion:
    """The exact response of a building (or the ground) to one piecewise-linear record.

    Build it with :func:`building_motion`; take floors with :meth:`floor`.

    Attributes
    ----------
    building
        The building, or None for the ground.
    acc
        Ground acceleration samples, m/s² (read-only).
    dt
        Record time step, s.
    substeps, h
        Sub-steps per record step (``ρ(A)·h ≤ 0.5``) and their length, s.
    stepper
        The exact sub-step recurrence (None on the ground).
    chunk_steps
        Record steps per chunk of states.
    notes
        What was done to the input record (e.g. a Trace's unit conversion), one line each.
    """

    building: LinearBuilding | None
    acc: np.ndarray
    dt: float
    substeps: int
    h: float
    stepper: ExactStepper | None
    chunk_steps: int
    notes: tuple[str, ...] = ()
    _states: np.ndarray | None = field(default=None, repr=False)
    _checkpoints: list[np.ndarray] | None = field(default=None, repr=False)

    @property
    def n(self) -> int:
        """Number of building states (0 on the ground)."""
        return 0 if self.stepper is None else self.stepper.n

    @property
    def npts(self) -> int:
        """Samples of the record."""
        return self.acc.size

    @property
    def kept_whole(self) -> bool:
        """Whether every state is held in memory (else chunks are recomputed on demand)."""
        return self._states is not None

    def chunks(self) -> Iterator[tuple[int, np.ndarray]]:
        """The states, chunk by chunk: ``(k0, X)`` where ``X[(k − k0)·substeps + r]`` is the
        state at the start of sub-step ``r`` of record step ``k`` and the last row the state at
        the end of the chunk's last step (read-only)."""
        steps = self.npts - 1
        m = self.substeps
        if self._states is not None:
            L = self.chunk_steps
            for k0 in range(0, max(steps, 1), L):
                k1 = min(k0 + L, steps)
                yield k0, self._states[k0 * m : k1 * m + 1]
            return
        # streaming: each chunk recomputed from the state at its start; the first pass through
        # the record records those states (checkpoints), later passes start from them
        st = self.stepper
        p, q = st.input_weights()
        cps = self._checkpoints
        buf = np.empty((self.chunk_steps * m + 1, self.n))
        x = np.zeros(self.n)
        for c, k0 in enumerate(range(0, steps, self.chunk_steps)):
            k1 = min(k0 + self.chunk_steps, steps)
            if c == len(cps):
                cps.append(x)
            X = buf[: (k1 - k0) * m + 1]
            foh_states(st.phi, p, q, self.acc, k0, k1, m, cps[c], X)
            _check_states(X, k1 * self.dt)
            x = X[-1].copy()
            X.setflags(write=False)
            yield k0, X

    def floor(self, floor: int) -> FloorMotion:
        """The motion of `floor` (0..N; 0 is the ground of a fixed-base building and the base
        mat of an isolated one)."""
        b = self.building
        if b is None:
            if floor not in (None, 0):
                raise ModelError("floor= needs building=", "floor")
            floor = 0
        else:
            if floor is None:
                raise ModelError("floor is required with building=", "floor")
            (floor,) = b.check_floors([floor])
        if b is None or b.dof_of(floor) is None:  # the ground (under a fixed-base building)
            return FloorMotion(self, floor, np.zeros((2, 0)), np.array([1.0, 0.0]), 1)
        Ca, Da, _ = b.output_matrices([floor], "acceleration")
        Cv, _, _ = b.output_matrices([floor], "velocity")
        Cd, _, _ = b.output_matrices([floor], "displacement")
        R, beta = self.stepper.taylor_rows(Ca, Da[:, 0])
        return FloorMotion(
            self,
            floor,
            np.ascontiguousarray(R[0]),
            np.ascontiguousarray(beta[0]),
            self.stepper.order,
            rv=np.ascontiguousarray(Cv[0]),
            rd=np.ascontiguousarray(Cd[0]),
        )

    def samples(
        self,
        floors: Sequence[int] | int | None = None,
        output: str | Sequence[str] = "acceleration",
    ) -> np.ndarray:
        """Outputs `output` (kinds as in :func:`~floorslide.floor_motions`, rows stacked kind by
        kind) of `floors` at the record samples; the record itself on the ground."""
        if self.building is None:
            return self.acc[None, :].copy()
        C, D, _ = self.building.output_matrices(floors, output)
        Y = np.empty((C.shape[0], self.npts))
        C = np.ascontiguousarray(C)
        D = np.ascontiguousarray(D[:, 0])
        for k0, X in self.chunks():
            state_outputs(X, k0, self.substeps, C, D, self.acc, Y)
        return Y

    def peaks(
        self, floors: Sequence[int] | int | None = None, output: str = "acceleration"
    ) -> tuple[np.ndarray, np.ndarray]:
        """True peaks ``max_t |y(t)|`` of an output of `floors` over the record, inside steps
        included, and their times (:func:`~floorslide.building._kernels.foh_peaks`)."""
        if self.building is None:
            peak, t = ground_peak(self.acc, self.dt)
            return np.array([peak]), np.array([t])
        C, D, _ = self.building.output_matrices(floors, output)
        R, beta = (frozen(x) for x in self.stepper.taylor_rows(C, D[:, 0]))
        peak = np.zeros(C.shape[0])
        tpk = np.zeros(C.shape[0])
        for k0, X in self.chunks():
            foh_peaks(X, k0, R, beta, self.acc, self.substeps, self.h, peak, tpk)
        if not np.all(np.isfinite(peak)):
            raise NonFiniteError(
                f"the peak {output} of a floor is not finite (it overflows float64)", "building"
            )
        return peak, tpk


@dataclass(frozen=True, eq=False)
class FloorMotion:
    """The exact absolute acceleration of one floor under one record.

    On sub-step ``r`` of record step ``k`` (start state ``x``, ground ``a_g(τ) = a + s·τ``) the
    floor's absolute acceleration is ``Σ_j c_j τ^j`` with ``c_j = R[j]·x + β_j·a + β_{j−1}/j·s``
    (:func:`floorslide.building._instep.taylor_coefficients`), equal to the exact function to
    rounding on the sub-step. On the ground, ``R`` has no columns and ``β = [1, 0]``.

    Attributes
    ----------
    motion
        The :class:`BuildingMotion` it belongs to (its states, record and sub-steps).
    floor
        Floor number.
    R, beta
        Taylor rows of the absolute acceleration, ``(K+1, n)`` and ``(K+1,)``.
    order
        Degree ``K`` of the Taylor polynomials.
    rv, rd
        Rows of the floor's velocity and displacement relative to the ground (empty on the
        ground).
    """

    motion: BuildingMotion
    floor: int
    R: np.ndarray
    beta: np.ndarray
    order: int
    rv: np.ndarray = field(default_factory=lambda: np.zeros(0))
    rd: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self) -> None:
        # read-only like the states and the record: a kernel reading them compiles once
        for name in ("R", "beta", "rv", "rd"):
            object.__setattr__(self, name, frozen(getattr(self, name)))

    @property
    def ground(self) -> bool:
        """True when the floor is the ground (its rows read no building state)."""
        return self.R.shape[1] == 0

    @property
    def building(self) -> LinearBuilding | None:
        """The building (None for a motion of the ground itself)."""
        return self.motion.building

    @property
    def acc(self) -> np.ndarray:
        """The ground record, m/s²."""
        return self.motion.acc

    @property
    def dt(self) -> float:
        """Record time step, s."""
        return self.motion.dt

    @property
    def notes(self) -> tuple[str, ...]:
        """What was done to the input record."""
        return self.motion.notes

    @property
    def substeps(self) -> int:
        """Sub-steps per record step of the states (1 on the ground)."""
        return 1 if self.ground else self.motion.substeps

    @property
    def h(self) -> float:
        """Sub-step length, s."""
        return self.dt / self.substeps

    def chunks(self) -> Iterator[tuple[int, np.ndarray]]:
        """The building states chunk by chunk, as :meth:`BuildingMotion.chunks` (on the ground
        one chunk of zero-width states)."""
        if self.ground:
            yield 0, frozen(np.zeros((self.acc.size, 0)))
            return
        yield from self.motion.chunks()

    def samples(self) -> np.ndarray:
        """The floor's absolute acceleration at the record samples, m/s²."""
        if self.ground:
            return self.acc.copy()
        return self.motion.samples([self.floor])[0]

    def peak(self) -> tuple[float, float]:
        """The true peak floor acceleration (inside steps included) and its time, s."""
        if self.ground:
            return ground_peak(self.acc, self.dt)
        p, t = self.motion.peaks([self.floor])
        return float(p[0]), float(t[0])


def building_motion(
    building: LinearBuilding | None,
    ground_acc: RecordLike,
    dt: float | None = None,
    *,
    max_bytes: int = MAX_STATE_BYTES,
    copy: bool = True,
    substeps: int | None = None,
) -> BuildingMotion:
    """Integrate `building` once under the piecewise-linear ground record.

    Parameters
    ----------
    building
        A :class:`~floorslide.ShearBuilding` or :class:`~floorslide.IsolatedBuilding`; None for
        the ground.
    ground_acc
        Ground acceleration samples, m/s²; or an ObsPy Trace or one-trace Stream (see
        :mod:`floorslide.inputs`).
    dt
        Time step, s (required for samples).
    max_bytes
        Largest state history kept whole. A longer one (or any, with 0) is streamed: each
        consumer's pass recomputes the states chunk by chunk (:data:`CHUNK_BYTES`) from the
        state at each chunk's start, recorded by the first pass; memory stays O(1) in the
        record's length.
    copy
        Keep a read-only copy of the samples (default), so that the motion cannot change
        under the caller; ``False`` reads the caller's array in place (the solvers do this for
        a motion they build and use at once).
    substeps
        Sub-steps per record step of a building (default: the fewest with ``ρ(A)·h ≤ 0.5``).
        More may be asked — the two directions of a building stepped on one time grid — fewer
        is an error. Ignored on the ground.

    Returns
    -------
    BuildingMotion
    """
    if getattr(building, "segmented", False):  # on nonlinear isolation: its segments
        return building.motion(ground_acc, dt, max_bytes=max_bytes)
    a, dt, notes = as_record(ground_acc, dt, "ground_acc")
    a = frozen(np.array(a, dtype=float) if copy else a)
    steps = a.size - 1
    if building is None:  # no states: zero-width, kept whole
        X = frozen(np.zeros((a.size, 0)))
        return BuildingMotion(None, a, dt, 1, dt, None, max(steps, 1), notes, X)
    st = stepper(building, dt)
    if substeps is not None and int(substeps) != st.substeps:
        if int(substeps) < st.substeps:
            raise ModelError(
                f"substeps={substeps} is fewer than the {st.substeps} this building needs at "
                f"dt={dt:g} s",
                "substeps",
            )
        st = stepper(building, dt, int(substeps))
    m, n = st.substeps, st.n
    rows = steps * m + 1
    if rows * n * 8 <= max_bytes:
        p, q = st.input_weights()
        X = np.empty((rows, n))
        foh_states(st.phi, p, q, a, 0, steps, m, np.zeros(n), X)
        _check_states(X, steps * dt)
        X.setflags(write=False)
        return BuildingMotion(building, a, dt, m, st.h, st, max(steps, 1), notes, X, None)
    L = max(1, min(steps, CHUNK_BYTES // (8 * n * m)))
    return BuildingMotion(building, a, dt, m, st.h, st, L, notes, None, [])


def frozen(x: np.ndarray) -> np.ndarray:
    """`x` read-only: itself if it is already, else a read-only view (no copy; `x` itself
    stays writable). The arrays handed to the kernels are read-only whatever their source (a
    record read from a file is; one made in memory is not), so that each kernel compiles once
    and not once for either kind (numba types a read-only array apart)."""
    if not x.flags.writeable:
        return x
    v = x.view()
    v.setflags(write=False)
    return v


def _check_states(X: np.ndarray, t_end: float) -> None:
    """Raise :class:`~floorslide.errors.NonFiniteError` when the building's state at the end of
    a stretch `X` ending at `t_end` is not finite (a NaN or inf in the exact recurrence stays
    one, so the last row tells), instead of handing NaN floors to every consumer."""
    if not np.all(np.isfinite(X[-1])):
        raise NonFiniteError(
            f"the building's response is not finite by t = {t_end:.6g} s (it overflows float64)",
            "building",
        )


def ground_peak(acc: np.ndarray, dt: float) -> tuple[float, float]:
    """Peak ``|a|`` of a piecewise-linear record and its time: at a sample."""
    k = int(np.argmax(np.abs(acc)))
    return float(abs(acc[k])), k * dt


def single_use_motion(building, acc: np.ndarray, dt: float, floor) -> FloorMotion:
    """The floor motion a solver builds for its own single pass (``slide(acc, dt, building=,
    floor=)``): streamed (memory O(1) in the record's length) and reading `acc` in place."""
    return building_motion(building, acc, dt, max_bytes=0, copy=False).floor(floor)


def floor_motion(
    building: LinearBuilding | None,
    ground_acc: RecordLike,
    floor: int | None = None,
    dt: float | None = None,
) -> FloorMotion:
    """The exact motion of one floor, for many contents or spectra on it.

    ``fm = floor_motion(building, acc, floor, dt)`` then ``slide(fm, mu_k=...)``,
    ``slide_oscillator(fm, ...)``, ``response_spectrum(fm, periods=...)`` integrate the building
    once instead of once per call. With several floors, take them from one
    :func:`building_motion`.
    """
    return building_motion(building, ground_acc, dt).floor(0 if building is None else floor)


def check_building(building, consumer: str = "this function"):
    """Refuse, in one line naming ``building``, what is not one building model: a
    :class:`~floorslide.BuildingPair` (one model per direction: its consumers take two
    components) or anything else."""
    if building is None or isinstance(building, LinearBuilding):
        return
    if getattr(building, "segmented", False):
        return
    if hasattr(building, "h1") and hasattr(building, "h2"):
        raise ModelError(
            f"a BuildingPair (one model per direction) needs two horizontal components: use "
            f"slide_plane or rotd_spectrum with a record pair, or give {consumer} one of its "
            "models (pair.h1 or pair.h2)",
            "building",
        )
    raise ModelError(
        f"expected a ShearBuilding, IsolatedBuilding or NonlinearIsolatedBuilding, got "
        f"{type(building).__name__}",
        "building",
    )


def unwrap(acc, dt, building, floor, name: str = "acc"):
    """What a solver was given, as ``(FloorMotion or None, samples, dt, notes)``: a FloorMotion
    passed as the record (then `building`/`floor` must not be given, and `dt`, if given, must be
    its own), or a record with an optional building and floor."""
    check_building(building)
    if isinstance(acc, FloorMotion | NonlinearFloorMotion):
        if building is not None or floor is not None:
            raise ModelError(
                f"{name} is a FloorMotion: give building= and floor= when building it, not here",
                "building",
            )
        if dt is not None and (isinstance(dt, bool) or not np.isscalar(dt)):
            raise ModelError(
                f"{name} is a FloorMotion, whose dt is its own: give the other arguments by "
                f"keyword (e.g. mu_k=..., mu=..., periods=...), not {dt!r} in dt's place",
                "dt",
            )
        if dt is not None and not np.isclose(float(dt), acc.dt, rtol=1e-9, atol=0.0):
            raise ModelError(f"dt={dt} differs from the FloorMotion's dt={acc.dt}", "dt")
        return acc, acc.acc, acc.dt, acc.notes
    a, dt, notes = as_record(acc, dt, name)
    return None, a, dt, notes
