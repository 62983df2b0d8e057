"""A building on friction pendulums (under two horizontal components and optionally the
vertical) or on lead-rubber bearings (two horizontal components): the bearing's friction circle
or yield circle coupled with the superstructure in both directions, exact to rounding
(docs/design.md, "isolators in the plane").

:func:`plane_isolator_response` gives the bearing's own outputs (orbit, peak displacement and
its direction, residual vector, peak force over weight, events, friction work);
:class:`PlaneIsolatedMotion` is the building's exact motion as polynomial segments
(:class:`~floorslide.building.poly_segments.PolySegments`), which every plane consumer reads.
The compiled integrators are :mod:`floorslide.building._plane_isolation_kernel` (friction
pendulums) and :mod:`floorslide.building._plane_bilinear_kernel` (lead-rubber, with
:mod:`floorslide.building.plane_bilinear`).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from floorslide.building import _plane_isolation_kernel as pk
from floorslide.building import plane_bilinear as pb
from floorslide.building.isolators import (
    SLIP_POS,
    STICK,
    BilinearIsolator,
    small_angle_exceeded,
    small_angle_note,
)
from floorslide.building.nonlinear import NonlinearIsolatedBuilding
from floorslide.constants import G
from floorslide.errors import ModelError, SolverLimitError

CHUNK_STEPS = 2048
"""Record steps per chunk of segments (:meth:`PlaneIsolatedMotion.poly_chunks`)."""
MAX_EVENTS_KEPT = 100_000
"""Most events whose times are kept."""
MAX_KEPT_BYTES = 512 * 2**20
"""Most bytes of segments a motion made with ``keep_segments`` holds; beyond, its consumers
stream them from the checkpoints again."""


def couples_directions(building) -> bool:
    """Whether `building` is on nonlinear isolation (one model, or a pair of models): its
    bearings respond to both horizontal components together, so plane consumers read its
    :class:`PlaneIsolatedMotion` rather than one motion per direction."""
    if isinstance(building, tuple | list) and len(building) == 2:
        return any(isinstance(b, NonlinearIsolatedBuilding) for b in building)
    return isinstance(building, NonlinearIsolatedBuilding)


def plane_layer(
    building, *, bilinear: bool = False
) -> tuple[NonlinearIsolatedBuilding, NonlinearIsolatedBuilding]:
    """The models along ``x`` and ``y`` of a building on friction pendulums or lead-rubber
    bearings under two components: one :class:`NonlinearIsolatedBuilding` (the same
    superstructure both ways) or a pair of them (a superstructure per direction on one mat and
    one layer). Anything else is refused in one line naming ``building``. (`bilinear`, which
    let the approximate solvers take lead-rubber before the exact solver did, is kept for
    them; both layers are taken either way.)"""
    if isinstance(building, NonlinearIsolatedBuilding):
        bx = by = building
    elif isinstance(building, tuple | list) and len(building) == 2:
        bx, by = building
        for name, b in (("building[0]", bx), ("building[1]", by)):
            if not isinstance(b, NonlinearIsolatedBuilding):
                raise ModelError(
                    f"a building per direction on nonlinear isolation is a pair of "
                    f"NonlinearIsolatedBuilding, got {type(b).__name__}",
                    name,
                )
        if bx.isolator != by.isolator:
            raise ModelError(
                "the two directions' models must stand on one isolation layer (the same "
                "isolator): a bearing is one device in the plane",
                "building[1].isolator",
            )
        if bx.mass.shape != by.mass.shape or not np.array_equal(bx.mass, by.mass):
            raise ModelError(
                "the two directions' models must share the base mat and the floor masses (one "
                "building): got different masses or base_mass_ratio",
                "building[1].base_mass_ratio",
            )
    else:
        raise ModelError(
            f"building must be a NonlinearIsolatedBuilding or a pair of them, got "
            f"{type(building).__name__}",
            "building",
        )
    return bx, by


@dataclass(frozen=True)
class _Setup:
    """The compiled integrator's inputs for one building, record and vertical."""

    A: np.ndarray
    As: np.ndarray
    bv: np.ndarray
    consts: np.ndarray
    acc1: np.ndarray
    acc2: np.ndarray
    accv: np.ndarray
    has_vert: bool
    substeps: int
    h: float
    n: int


def _setup(bx, by, h1, h2, dt, vertical) -> _Setup:
    n = bx.n_dof
    N = 2 * n
    A = np.zeros((2, N, N))
    As = np.zeros((2, N, N))
    bv = np.zeros((2, N))
    for d, b in enumerate((bx, by)):
        Ad, bd = b.branch_system(SLIP_POS)
        A[d] = Ad[:N, :N]
        bv[d] = bd[:N]
        As[d] = b.branch_system(STICK)[0][:N, :N]
    c = bx.constants
    mb = float(bx.mass[0])
    consts = np.array(
        [n, mb, c["mu"] * c["W"], c["mu_s"] * c["W"], c["W"], c["k"] / (mb * G), c["W"] / G]
    )
    m = max(bx.substeps(dt), by.substeps(dt))
    has_vert = vertical is not None
    accv = np.ascontiguousarray(vertical, dtype=float) if has_vert else np.zeros(1)
    return _Setup(A, As, bv, consts, h1, h2, accv, has_vert, m, dt / m, n)


def _initial(s: _Setup, x: np.ndarray) -> tuple[int, int]:
    """Mode and start order at t = 0 (the mat at rest unless `x` moves it)."""
    n = s.n
    mu, mus = s.consts[2], s.consts[3]
    if x[0, n] != 0.0 or x[1, n] != 0.0:
        return pk.SLIP, 0
    if mu == 0.0 and mus == 0.0:
        return pk.SLIP, 0
    av = s.accv[0] if s.has_vert else 0.0
    g = [
        s.A[d, n] @ x[d] + s.bv[d, n] * (s.acc1[0] if d == 0 else s.acc2[0])
        - s.consts[5] * av * x[d, 0]
        for d in range(2)
    ]  # fmt: skip
    lim = mus / s.consts[4] * (s.consts[4] + s.consts[6] * av) / s.consts[1]
    if np.hypot(*g) > lim:
        return pk.SLIP, 1
    return pk.STICK, 0


@dataclass(frozen=True)
class PlaneIsolatorResponse:
    """The response of a building on friction pendulums or lead-rubber bearings to two
    horizontal components. On lead-rubber bearings (:mod:`floorslide.building.plane_bilinear`)
    the bearing's force is ``k_2 u_b + c u_b' + q`` (``q`` the plastic element's, ``|q| ≤ Q``),
    ``friction_work`` is the plastic (hysteretic) work ``∫ q·u_p' dt`` (J), ``slide_fraction``
    and ``sliding`` the share of the record and the samples where the element yields, the
    events ``"yield"`` (``|q|`` reaching ``Q``) and ``"unload"`` (``q·u_b'`` falling through 0),
    ``peak_force_ratio`` the peak of ``|f_b|/W`` inside steps (as the 1-D layer's), and
    ``small_angle_exceeded`` is False.

    Attributes
    ----------
    dt, substeps
        Record step and sub-steps per step.
    displacement
        The bearing's displacement vector at the samples, ``(npts, 2)``, m (its orbit).
    velocity
        The mat's velocity relative to the ground at the samples, ``(npts, 2)``, m/s.
    floor_displacement
        Every floor's displacement relative to the ground, ``(npts, n_dof, 2)`` (floor 0 the
        mat).
    floor_velocity
        Every floor's velocity relative to the ground, ``(npts, n_dof, 2)``, m/s.
    floor_acceleration
        Every floor's absolute acceleration at the samples, ``(npts, n_dof, 2)``, m/s².
    peak_displacement
        ``max_t |u_b(t)|`` inside steps, m; ``peak_direction`` its direction (degrees from
        ``h1`` towards ``h2``) and ``peak_time`` its time, s.
    residual
        ``u_b`` at the end of the record, m (2-vector).
    peak_force_ratio
        The largest ``|f_b|/W`` (restoring plus friction) over the steps' ends.
    force_ratio
        The bearing's force vector over the weight at the samples, ``(npts, 2)`` (with
        `displacement`, its hysteresis in each direction).
    friction_work
        ``∫ mu N |V| dt``, J.
    slide_fraction
        Share of the record the bearing slides.
    sliding
        At each sample, whether the bearing slides.
    event_times, event_kinds
        Breakaways (``"slip"``), stops that stick (``"stick"``) and stops that slide on at once
        (``"reverse"``).
    """

    dt: float
    substeps: int
    displacement: np.ndarray
    velocity: np.ndarray
    floor_displacement: np.ndarray
    floor_acceleration: np.ndarray
    peak_displacement: float
    peak_direction: float
    peak_time: float
    residual: np.ndarray
    peak_force_ratio: float
    friction_work: float
    slide_fraction: float
    sliding: np.ndarray
    event_times: np.ndarray
    event_kinds: tuple[str, ...]
    force_ratio: np.ndarray | None = None
    floor_velocity: np.ndarray | None = None
    capacity_exceeded: bool = False
    small_angle_exceeded: bool = False
    notes: tuple[str, ...] = ()


def _floor_accelerations(s: _Setup, XS, sliding, wdir, acc, av) -> np.ndarray:
    """Every floor's absolute acceleration at the samples, ``(npts, n_dof, 2)``: the state's
    derivative on the branch it is on after the sample (sliding: the kinetic friction along the
    mat's velocity and the restoring force scaled by ``1 + a_v/g``; stuck: the mat moves with
    the ground), plus the ground."""
    n = s.n
    out = np.empty((XS.shape[0], n, 2))
    c = s.consts[2] * (1.0 + av / G) / s.consts[1]  # mu N / m_b
    for d in range(2):
        slip = XS[:, d] @ s.A[d, n:].T + acc[:, [d]] * s.bv[d, n:]
        slip[:, 0] -= s.consts[5] * av * XS[:, d, 0] + c * wdir[:, d]
        stick = XS[:, d] @ s.As[d, n:].T + acc[:, [d]] * s.bv[d, n:]
        stick[:, 0] = 0.0
        out[:, :, d] = np.where(sliding[:, None], slip, stick) + acc[:, [d]]
    return out


_KIND_NAMES = {pk.EV_BREAK: "slip", pk.EV_STICK: "stick", pk.EV_ON: "reverse"}


class PlaneIsolatedMotion:
    """The exact motion of a building on friction pendulums (under two components and the
    vertical) or on lead-rubber bearings (two components; :mod:`floorslide.building.
    plane_bilinear`), integrated once for its own outputs (:attr:`response`) and again chunk by
    chunk from checkpoints for the segments its consumers read (:meth:`poly_chunks`; the same
    bits).

    Attributes: ``dt``, ``npts``, ``acc1``, ``acc2`` (the ground at the samples, m/s²),
    ``vertical`` (or None), ``floors`` (every floor, 0 the mat), ``building`` (the pair of
    models), ``response`` (:class:`PlaneIsolatorResponse`), ``notes`` (the bearing's: small
    angle, capacity). With ``keep_segments`` the first pass records the segments and keeps
    them (up to :data:`MAX_KEPT_BYTES`): every consumer then reads them without integrating
    again — what a study's task does."""

    def __init__(self, building, h1, h2, dt: float, *, vertical=None, initial_displacement=None,
                 initial_velocity=None, keep_segments: bool = False):  # fmt: skip
        bx, by = plane_layer(building)
        h1 = np.ascontiguousarray(h1, dtype=float)
        h2 = np.ascontiguousarray(h2, dtype=float)
        if h1.shape != h2.shape or h1.ndim != 1 or h1.size < 2:
            raise ModelError("the two components must be 1-D arrays of one length ≥ 2", "acc")
        self._bilinear = isinstance(bx.isolator, BilinearIsolator)
        if vertical is not None:
            vertical = np.ascontiguousarray(vertical, dtype=float)
            if vertical.shape != h1.shape:
                raise ModelError("vertical must have as many samples as the pair", "vertical")
            low = np.flatnonzero(G + vertical <= 0.0)
            if low.size and not self._bilinear:
                raise ModelError(
                    f"g + a_v ≤ 0 at t = {low[0] * dt:.6g} s: the bearing would lift off, which "
                    "is not modelled",
                    "vertical",
                )
        self.building = (bx, by)
        self.dt = float(dt)
        self.npts = h1.size
        self.acc1, self.acc2, self.vertical = h1, h2, vertical
        self.floors = tuple(range(bx.n_dof))
        n = bx.n_dof
        if self._bilinear:
            self._s = pb.bilinear_setup(bx, by, h1, h2, self.dt)
            x, carry = pb.initial_state(self._s, initial_displacement, initial_velocity)
        else:
            self._s = _setup(bx, by, h1, h2, self.dt, vertical)
            x = np.zeros((2, 2 * n))
            if initial_displacement is not None:
                x[:, 0] = np.asarray(initial_displacement, dtype=float)
                x[:, 1:n] = x[:, [0]]
            if initial_velocity is not None:
                x[:, n] = np.asarray(initial_velocity, dtype=float)
            mode, start = _initial(self._s, x)
            carry = np.array([mode, start, 0.0, 0.0, 0.0])
        self._checkpoints = []
        self._kept: list | None = [] if keep_segments else None
        XS = np.zeros((self.npts, 2, x.shape[1]))
        MODES = np.zeros(self.npts, dtype=np.int64)
        peak = np.zeros(pk.NPEAK)
        peak[pk.P_TIME] = 0.0
        EV = np.zeros((MAX_EVENTS_KEPT, 2))
        fl = np.array(self.floors, dtype=np.int64)
        s = self._s
        kept_bytes = 0
        for k0 in range(0, self.npts - 1, CHUNK_STEPS):
            k1 = min(k0 + CHUNK_STEPS, self.npts - 1)
            # the running peaks too: the solver's thresholds scale with them (a pass again from
            # here must take the same steps)
            self._checkpoints.append((k0, k1, x.copy(), carry.copy(), peak.copy()))
            if self._kept is None:
                SEG, COEF = np.zeros((0, 4)), np.zeros((0, 1, 2, pk.DEGREE))
                out = self._run(fl, k0, k1, x, carry, XS, MODES, peak, EV, SEG, COEF)
            else:
                # the segments recorded on this (only) pass; a chunk that holds more than its
                # room runs again from its checkpoint with the room it needs
                x0, carry0, peak0 = x.copy(), carry.copy(), peak.copy()
                cap = (k1 - k0) * s.substeps * 4 + 64
                while True:
                    SEG, COEF = np.zeros((cap, 4)), np.zeros((cap, fl.size, 2, pk.DEGREE))
                    out = self._run(fl, k0, k1, x, carry, XS, MODES, peak, EV, SEG, COEF)
                    if out <= cap:
                        break
                    cap = out
                    x[:], carry[:], peak[:] = x0, carry0, peak0
                if out >= 0:
                    seg = _segments(SEG, COEF, out, self.floors, k0, k1)
                    kept_bytes += seg.coef.nbytes
                    self._kept.append(seg)
                    if kept_bytes > MAX_KEPT_BYTES:
                        self._kept = None  # too long to keep: consumers stream
            if out < 0:
                row = -1 - out
                raise SolverLimitError(
                    pb.limit_message(row * s.h)
                    if self._bilinear
                    else f"the friction pendulum needed more than {pk.MAX_STEPS} series steps "
                    f"in one sub-step at t = {row * s.h:.6g} s (creep at the friction limit "
                    "the solver cannot resolve)",
                    "building",
                )
        if self._bilinear:
            self.response = pb.bilinear_response(self, XS, MODES, peak, EV, carry)
        else:
            self.response = self._response(XS, MODES, peak, EV, int(carry[pk.C_EVENTS]))
        self.notes = self.response.notes
        if self._bilinear and vertical is not None:
            # kept for the blocks on its floors, whose friction it scales
            self.notes += (
                "vertical shaking does not act on the lead-rubber layer in this model (its "
                "force does not depend on the normal load); the blocks on its floors feel it",
            )

    def _run(self, fl, k0, k1, x, carry, XS, MODES, peak, EV, SEG, COEF) -> int:
        """The layer's compiled integrator over record steps ``k0 … k1 − 1``."""
        s = self._s
        if self._bilinear:
            return s.run(fl, k0, k1, x, carry, XS, MODES, peak, EV, SEG, COEF)
        return pk.plane_run(s.A, s.bv, s.As, s.consts, fl, s.acc1, s.acc2, s.accv, s.has_vert,
                            s.substeps, s.h, k0, k1, x, carry, XS, MODES, peak, EV, SEG,
                            COEF)  # fmt: skip

    def _response(self, XS, MODES, peak, EV, n_ev) -> PlaneIsolatorResponse:
        bx, _ = self.building
        n = bx.n_dof
        W = bx.weight
        c = bx.constants
        u = XS[:, :, 0].copy()
        v = XS[:, :, n].copy()
        # the bearing force at the samples: restoring + damping + friction (sliding: mu N
        # along V; stuck: what the mat needs, m_b G)
        av = self.vertical if self.vertical is not None else np.zeros(self.npts)
        scale = 1.0 + av / G
        force = c["k"] * scale[:, None] * u + c["c"] * v
        sliding = MODES == pk.SLIP
        speed = np.hypot(v[:, 0], v[:, 1])
        with np.errstate(invalid="ignore", divide="ignore"):
            wdir = np.where(speed[:, None] > 0, v / speed[:, None], 0.0)
        force += np.where(sliding[:, None], c["mu"] * W * scale[:, None] * wdir, 0.0)
        s = self._s
        acc = np.stack([self.acc1, self.acc2], axis=1)
        drive = np.einsum("dq,kdq->kd", s.A[:, n], XS) + s.bv[:, n] * acc
        drive -= s.consts[5] * av[:, None] * u
        force += np.where(sliding[:, None], 0.0, float(bx.mass[0]) * drive)
        floor_acc = _floor_accelerations(s, XS, sliding, wdir, acc, av)
        ratio = float(np.hypot(force[:, 0], force[:, 1]).max() / W)
        small = small_angle_exceeded(bx.isolator, float(peak[pk.P_DISP]))
        notes = ()
        if small:
            notes = (small_angle_note(float(peak[pk.P_DISP]), bx.isolator.R),)
        return PlaneIsolatorResponse(
            **response_fields(self, XS, n, peak, EV, n_ev, _KIND_NAMES, notes),
            floor_acceleration=floor_acc,
            peak_force_ratio=ratio,
            sliding=sliding,
            force_ratio=force / W,
            small_angle_exceeded=bool(small),
        )

    def poly_chunks(self) -> Iterator:
        """The motion's segments chunk by chunk
        (:class:`~floorslide.building.poly_segments.PolySegments`): those recorded by the
        first pass (``keep_segments``), else integrated again from its checkpoints (the same
        bits)."""
        if self._kept is not None:
            yield from self._kept
            return
        s = self._s
        fl = np.array(self.floors, dtype=np.int64)
        for k0, k1, x0, carry0, peak0 in self._checkpoints:
            cap = (k1 - k0) * s.substeps * 4 + 64
            while True:
                x = x0.copy()
                carry = carry0.copy()
                XS = np.zeros((self.npts, 2, x.shape[1]))
                MODES = np.zeros(self.npts, dtype=np.int64)
                SEG = np.zeros((cap, 4))
                COEF = np.zeros((cap, fl.size, 2, pk.DEGREE))
                got = self._run(fl, k0, k1, x, carry, XS, MODES, peak0.copy(),
                                np.zeros((0, 2)), SEG, COEF)  # fmt: skip
                if got <= cap:
                    break
                cap = got
            yield _segments(SEG, COEF, got, self.floors, k0, k1)


def _segments(SEG, COEF, got, floors, k0, k1):
    """The :class:`~floorslide.building.poly_segments.PolySegments` of one chunk from the
    kernel's records (its first `got` rows)."""
    from floorslide.building.poly_segments import PolySegments

    return PolySegments(
        t0=SEG[:got, 0].copy(),
        length=SEG[:got, 1].copy(),
        step=SEG[:got, 2].astype(np.int64),
        ends=SEG[:got, 3] != 0.0,
        coef=COEF[:got],
        floors=floors,
        k0=k0,
        k1=k1,
    )


def response_fields(motion, XS, n, peak, EV, n_ev, kind_names, notes) -> dict:
    """The :class:`PlaneIsolatorResponse` fields every bearing shares, from the first pass of
    `motion`: its states at the samples ``XS`` (per direction ``[u (n); u' (n); …]``), the
    kernel's peaks and events (``n_ev`` of them, named by `kind_names`), and its `notes` with
    the capacity's, when exceeded."""
    bx, _ = motion.building
    cap = bx.isolator.capacity
    exceeded = cap is not None and peak[pk.P_DISP] > cap
    if exceeded:
        notes = (
            *notes,
            f"the bearing displacement {peak[pk.P_DISP]:.4g} m exceeds the capacity {cap:g} m "
            "(the impact that would follow is not modelled)",
        )
    u = XS[:, :, 0].copy()
    kept = min(n_ev, EV.shape[0])
    duration = (motion.npts - 1) * motion.dt
    return dict(
        dt=motion.dt,
        substeps=motion._s.substeps,
        displacement=u,
        velocity=XS[:, :, n].copy(),
        floor_displacement=XS[:, :, :n].transpose(0, 2, 1).copy(),
        floor_velocity=XS[:, :, n : 2 * n].transpose(0, 2, 1).copy(),
        peak_displacement=float(peak[pk.P_DISP]),
        peak_direction=float(np.degrees(peak[pk.P_ANGLE])),
        peak_time=float(peak[pk.P_TIME]),
        residual=u[-1].copy(),
        friction_work=float(peak[pk.P_WORK]),
        slide_fraction=float(peak[pk.P_SLIDE_TIME] / duration) if duration > 0 else 0.0,
        event_times=EV[:kept, 0].copy(),
        event_kinds=tuple(kind_names[int(k)] for k in EV[:kept, 1]),
        capacity_exceeded=bool(exceeded),
        notes=notes,
    )


def plane_isolator_response(
    building, h1, h2, dt: float, *, vertical=None, initial_displacement=None,
    initial_velocity=None,
) -> PlaneIsolatorResponse:  # fmt: skip
    """Exact response of a building on friction pendulums or lead-rubber bearings to two
    horizontal components ``h1``, ``h2`` (m/s², samples at ``k·dt``) and, on friction
    pendulums, optionally the vertical (the friction and the pendulum's restoring force scale
    with ``g + a_v``; a lead-rubber bearing does not take it: refused): the bearing's orbit,
    its peak displacement and direction, the residual vector, the peak force over weight.

    `building`: one :class:`~floorslide.building.nonlinear.NonlinearIsolatedBuilding` on a
    :class:`~floorslide.building.isolators.FrictionPendulum` or a
    :class:`~floorslide.building.isolators.BilinearIsolator` (its superstructure both ways) or a
    pair of them (a superstructure per direction on one mat and layer)."""
    return PlaneIsolatedMotion(
        building, h1, h2, dt, vertical=vertical, initial_displacement=initial_displacement,
        initial_velocity=initial_velocity,
    ).response  # fmt: skip
