"""The exact motion of a building on nonlinear isolation: integrated once, read by every consumer.

A building on a piecewise-linear isolation layer (lead-rubber, friction pendulum) is linear
between isolator events, so its exact motion under a piecewise-linear record is a sequence of
*segments*: a whole sub-step of one branch (the common case), or the piece of a sub-step
between two events. The compiled kernel (:func:`floorslide.building._nonlinear_kernel.
nonlinear_run`) integrates the building alone, locating every event inside steps, and records
each segment — its sub-step, the branch's matrices, the states at its ends, the ground's value
and slope there, its length and start time. With the branch's Taylor rows of a floor's absolute
acceleration, a segment's start state gives the floor's in-step polynomial on it, exact to
rounding. Rigid blocks, 2-DOF sliding oscillators, rocking blocks and floor spectra all read
these segments (``floorslide.contents._segment_kernels``, ``floorslide.spectra.
_segment_kernels``); none integrates the building itself, and nothing rides inside the
building's kernel.

Memory is bounded as for :class:`~floorslide.building.exact_motion.BuildingMotion`: segments
that fit in :data:`MAX_SEGMENT_BYTES` are kept whole; a longer record is *streamed*: the first
pass records the kernel's state at the start of each chunk of record steps (the building's
state, its branch, whether an event just happened), and each consumer's pass integrates the
chunk again from there — the same operations from the same state, so the same bits.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np

from floorslide.building import _nonlinear_kernel as kern
from floorslide.errors import ModelError, NonFiniteError, SolverLimitError

__all__ = ["MAX_SEGMENT_BYTES", "NonlinearFloorMotion", "NonlinearMotion"]

MAX_SEGMENT_BYTES = 128 * 2**20
"""Largest segment record (bytes) a motion keeps whole."""

CHUNK_BYTES = 1024 * 2**10
"""Size of one chunk of segments handed out by a streamed motion."""


@dataclass(eq=False)
class _Kernel:
    """What the kernel needs for one building, record step and set of outputs."""

    mat_of: np.ndarray
    PHI: np.ndarray
    PP: np.ndarray
    QQ: np.ndarray
    RR: np.ndarray
    BB: np.ndarray
    ER: np.ndarray
    EB: np.ndarray
    OR: np.ndarray
    OB: np.ndarray
    G: np.ndarray
    K: int
    consts: np.ndarray
    n: int
    max_events: int
    rho: float
    """The largest spectral radius of the branches' state matrices (what sets the sub-steps)."""

    @property
    def N(self) -> int:
        return self.PHI.shape[1]

    @property
    def GT(self) -> np.ndarray:
        """The chord-bound rows with the functions last (as the kernel lays them out)."""
        return np.ascontiguousarray(self.G.transpose(0, 2, 3, 1))


@dataclass(eq=False)
class NonlinearMotion:
    """The exact motion of a building on nonlinear isolation under one record.

    Build it with :meth:`floorslide.NonlinearIsolatedBuilding.motion`; take floors with
    :meth:`floor`. ``response`` is the building's own result (floor accelerations at the
    samples, true peaks, the isolator's displacement, force, branches and events:
    :class:`~floorslide.building.nonlinear.IsolatorResponse`).

    Attributes
    ----------
    building
        The :class:`~floorslide.NonlinearIsolatedBuilding`.
    acc, dt
        Ground acceleration samples (m/s², read-only) and the record step, s.
    substeps, h
        Sub-steps per record step and their length, s.
    floors
        The floors whose rows the motion carries (output row ``i`` is floor ``floors[i]``;
        then the isolator force and displacement).
    response
        The building's response.
    """

    building: object
    acc: np.ndarray
    dt: float
    substeps: int
    h: float
    floors: tuple[int, ...]
    response: object
    kernel: _Kernel = field(repr=False)
    chunk_steps: int = 0
    notes: tuple[str, ...] = ()
    _whole: tuple | None = field(default=None, repr=False)
    _checkpoints: list | None = field(default=None, repr=False)
    _samples: tuple | None = field(default=None, repr=False)
    _start: tuple | None = field(default=None, repr=False)
    augmented: bool = False
    """An oscillator is appended to the building's states (its outputs replace the floors')."""

    @property
    def npts(self) -> int:
        return self.acc.size

    @property
    def kept_whole(self) -> bool:
        """Whether every segment is held in memory (else chunks are integrated again)."""
        return self._whole is not None

    def chunks(self) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]]:
        """The segments, chunk by chunk of record steps: ``(SI, SF, SX, SY, count)`` (the
        columns of :func:`~floorslide.building._nonlinear_kernel.nonlinear_run`); read-only."""
        if self._whole is not None:
            yield self._whole
            return
        steps = self.npts - 1
        if self._checkpoints is None:
            # built without its segments (keep_segments=False): integrated again from the start,
            # chunk after chunk, carrying the state
            x, carry = self._start[0].copy(), self._start[1].copy()
            chunk = max(1, CHUNK_BYTES // (segment_bytes(self.kernel.N) * self.substeps))
            for k0 in range(0, steps, chunk):
                k1 = min(k0 + chunk, steps)
                cap = (k1 - k0) * self.substeps + (k1 - k0) // 4 + 64
                *segments, x, carry = _run_chunk(self, k0, k1, x, carry, cap, scratch=True)
                yield tuple(segments)
            return
        for c, k0 in enumerate(range(0, steps, self.chunk_steps)):
            k1 = min(k0 + self.chunk_steps, steps)
            x, carry, cap = self._checkpoints[c]
            yield _run_chunk(self, k0, k1, x.copy(), carry.copy(), cap, scratch=True)[:5]

    @property
    def states(self) -> np.ndarray:
        """The building's state ``[u (n); u' (n); F0; extra]`` at each record sample (rows;
        displacements and velocities relative to the ground), read-only."""
        X = self._samples[2][0].view()
        X.setflags(write=False)
        return X

    def floor(self, floor: int) -> NonlinearFloorMotion:
        """The motion of `floor` (0 is the base mat, above the isolators)."""
        if floor is None:
            raise ModelError("floor is required with building=", "floor")
        if self.augmented:
            raise ModelError(
                "this motion carries an oscillator appended as states (its outputs are the "
                "oscillator's): build the motion without oscillator= to read its floors",
                "oscillator",
            )
        (floor,) = self.building.check_floors([floor])
        if floor not in self.floors:
            raise ModelError(
                f"floor {floor} is not among the floors this motion was built for "
                f"({', '.join(map(str, self.floors))})",
                "floor",
            )
        return NonlinearFloorMotion(self, floor, self.floors.index(floor))

    def samples(self, floors: Sequence[int] | int | None = None) -> np.ndarray:
        """The floors' absolute accelerations at the record samples, m/s²."""
        rows = self._rows(floors)
        return self.response.floor_acceleration[rows].copy()

    def peaks(self, floors: Sequence[int] | int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """True peak absolute accelerations of `floors` (inside steps) and their times, s."""
        rows = self._rows(floors)
        return self.response.pfa[rows].copy(), self._samples[1][rows].copy()

    def _rows(self, floors) -> list[int]:
        if floors is None:
            return list(range(len(self.floors)))
        fl = [floors] if np.isscalar(floors) else list(floors)
        return [self.floor(int(f)).row for f in fl]


@dataclass(frozen=True, eq=False)
class NonlinearFloorMotion:
    """One floor of a :class:`NonlinearMotion`: what a consumer reads.

    On segment ``s`` (branch matrices ``m``, start state ``x``, ground ``a_s + slope·τ``) the
    floor's absolute acceleration is ``Σ_j c_j τ^j`` with ``c = taylor_coefficients(OR[m,
    row], OB[m, row], x, a_s, slope)``, equal to the exact function to rounding.
    """

    motion: NonlinearMotion
    floor: int
    row: int

    segmented = True
    """Consumers read this motion segment by segment (a linear building's motion is read by
    sub-step states)."""

    ground = False

    @property
    def building(self):
        return self.motion.building

    @property
    def acc(self) -> np.ndarray:
        return self.motion.acc

    @property
    def dt(self) -> float:
        return self.motion.dt

    @property
    def notes(self) -> tuple[str, ...]:
        return self.motion.notes

    @property
    def substeps(self) -> int:
        return self.motion.substeps

    @property
    def h(self) -> float:
        return self.motion.h

    def samples(self) -> np.ndarray:
        """The floor's absolute acceleration at the record samples, m/s²."""
        return self.motion.response.floor_acceleration[self.row].copy()

    def peak(self) -> tuple[float, float]:
        """The true peak floor acceleration (inside steps included) and its time, s."""
        return float(self.motion.response.pfa[self.row]), float(self.motion._samples[1][self.row])


def _run_chunk(motion_or_setup, k0, k1, x, carry, cap, *, scratch=False, out=None, record=True):
    """Integrate record steps ``k0 … k1 − 1`` from ``(x, carry)`` recording segments, with room
    for ``cap`` (more when the kernel reports more). Returns ``(SI, SF, SX, SY, count, x,
    carry)``; without `record`, no segment is kept. With `scratch`, the peaks and events go to
    throw-away arrays (a later pass of a streamed motion: they are the first pass's)."""
    mo = motion_or_setup
    kn: _Kernel = mo.kernel
    X, BR, Yo, ev, peak, t_peak = mo._samples[2] if out is None else out
    if scratch:
        peak = peak.copy()
        t_peak = t_peak.copy()
        ev = tuple(np.empty(0, dtype=a.dtype) for a in ev)
    x_start, carry_start = x.copy(), carry.copy()
    while True:
        SI = np.zeros((cap, 4), dtype=np.int64)
        SF = np.empty((cap, 5))
        SX = np.empty((cap, kn.N))
        SY = np.empty((cap, kn.N))
        x = x_start.copy()
        carry = carry_start.copy()
        count = kern.nonlinear_run(
            kn.mat_of, kn.PHI, kn.PP, kn.QQ, kn.RR, kn.BB, kn.ER, kn.EB, kn.OR, kn.OB, kn.G,
            kn.K, kn.consts, mo.acc, mo.substeps, mo.h, kn.n, k0, k1, x, carry, X, BR, Yo,
            ev[0], ev[1], ev[2], peak, t_peak, kn.max_events, SI, SF, SX, SY,
        )  # fmt: skip
        if count < 0:
            row = -1 - count
            raise SolverLimitError(
                f"more than {kn.max_events} isolator events inside one sub-step at "
                f"t = {row * mo.h:.6g} s: stick–slip chatter the exact solver cannot resolve",
                "isolator",
            )
        if count <= cap or not record:
            break
        cap = count
    for a in (SI, SF, SX, SY):
        a.setflags(write=False)
    return SI, SF, SX, SY, count, x, carry


def segment_bytes(N: int) -> int:
    """Bytes of one recorded segment of a building with `N` states."""
    return 8 * (4 + 5 + 2 * N)


def integrate(motion: NonlinearMotion, x0, branch0, keep_segments: bool, max_bytes: int):
    """The first pass over the record: the samples, peaks and events of ``motion.response``
    (made by the caller from what this returns), and the segments kept whole or the chunks'
    checkpoints. Returns ``(X, BR, Yo, events, peak, t_peak)`` with the events trimmed."""
    kn = motion.kernel
    npts = motion.npts
    steps = npts - 1
    m = motion.substeps
    N = kn.N
    nout = kn.OR.shape[1]
    X = np.empty((npts, N))
    BR = np.empty(npts, dtype=np.int64)
    Yo = np.empty((npts, nout))
    peak = np.zeros(nout)
    t_peak = np.zeros(nout)
    x = np.array(x0, dtype=float)
    carry = np.array([branch0, 0, 0], dtype=np.int64)
    ev_cap = max(64, npts)
    ev = (np.empty(ev_cap, dtype=np.int64), np.empty(ev_cap), np.empty(ev_cap, dtype=np.int64))
    if not keep_segments or steps * m * segment_bytes(N) <= max_bytes:
        chunk = max(steps, 1)
    else:
        chunk = max(1, CHUNK_BYTES // (segment_bytes(N) * m))
    motion.chunk_steps = chunk
    ranges = [(k0, min(k0 + chunk, steps)) for k0 in range(0, steps, chunk)] or [(0, 0)]
    checkpoints = []
    whole = None
    for k0, k1 in ranges:
        # room for every sub-step and an event in one of four (more: the chunk runs again)
        cap = (k1 - k0) * m + (k1 - k0) // 4 + 64 if keep_segments else 0
        while True:
            peak_try, tp_try = peak.copy(), t_peak.copy()
            res = _run_chunk(
                motion,
                k0,
                k1,
                x.copy(),
                carry.copy(),
                cap,
                out=(X, BR, Yo, ev, peak_try, tp_try),
                record=keep_segments,
            )
            if res[6][2] <= ev[0].size:
                break
            # more events than room: keep those before the chunk, make room, run it again
            ev_cap = int(res[6][2]) + npts
            ev = tuple(
                np.concatenate([a[: int(carry[2])], np.empty(ev_cap - int(carry[2]), a.dtype)])
                for a in ev
            )
        SI, SF, SX, SY, count, x_new, carry_new = res
        peak, t_peak = peak_try, tp_try
        if keep_segments:
            if len(ranges) == 1:
                whole = (SI, SF, SX, SY, count)
            else:
                checkpoints.append((x.copy(), carry.copy(), count))
        x, carry = x_new, carry_new
    n_ev = int(carry[2])
    events = tuple(a[:n_ev].copy() for a in ev)
    motion._whole = whole
    motion._checkpoints = checkpoints if (keep_segments and whole is None) else None
    motion._start = (np.array(x0, dtype=float), np.array([branch0, 0, 0], dtype=np.int64))
    motion._samples = (peak, t_peak, (X, BR, Yo, ev, peak, t_peak))
    if not (np.all(np.isfinite(peak)) and np.all(np.isfinite(X[-1]))):
        raise NonFiniteError(
            "the building's response is not finite (it overflows float64)", "building"
        )
    return X, BR, Yo, events, peak, t_peak
