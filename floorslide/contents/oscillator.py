"""The 2-DOF sliding oscillator: flexible equipment whose base slides on its floor.

A top mass on a spring and dashpot (the equipment's flexibility, clamped-base frequency `f`,
damping ratio `ξ`) over a base mass that slides with Coulomb friction under the full weight
(Westermo & Udwadia 1983; Brochard & Gantenbein 1989, whose ``r = m2/m1`` is `mass_ratio`). In
stick it is an SDOF oscillator on the floor, in slip a free–free 2-DOF linear system with a
constant friction force, of frequency ``f·√(1 + 1/r)``. Both phases are solved exactly and the
switches are located to machine precision: no penalty "grip" spring (which put a spurious 55 Hz
peak in the 1989 study).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace

import numpy as np

from floorslide.building.exact import spectral_radius, substeps_for, taylor_degree
from floorslide.building.exact_motion import FloorMotion, single_use_motion, unwrap
from floorslide.building.model import LinearBuilding
from floorslide.constants import G
from floorslide.contents import _oscillator_batch as batch
from floorslide.contents import _oscillator_kernel as cols
from floorslide.contents._oscillator_kernel import oscillator_kernel
from floorslide.contents.events import OSCILLATOR_MAX_EVENTS, check_event_limit
from floorslide.contents.sliding import friction_pairs
from floorslide.errors import ModelError
from floorslide.inputs import RecordLike


@functools.lru_cache(maxsize=64)
def phase_radius(w: float, xi: float, r: float) -> float:
    """Largest spectral radius of the oscillator's two phase matrices: stick
    ``[[0, 1], [−w², −2ξw]]`` and slip ``[[0, 1], [−w²k, −2ξwk]]`` with ``k = 1 + 1/r`` (the
    relative motion of the free–free pair). Sub-step lengths come from it: for an overdamped
    slip phase (``ξ√k > 1``) it is close to ``2ξwk``, far above the slip frequency ``w√k``.
    """
    k = 1.0 + 1.0 / r
    stick = np.array([[0.0, 1.0], [-w * w, -2.0 * xi * w]])
    slip = np.array([[0.0, 1.0], [-w * w * k, -2.0 * xi * w * k]])
    return max(spectral_radius(stick), spectral_radius(slip))


@dataclass(frozen=True)
class OscillatorResult:
    """Response of 2-DOF sliding oscillators, one entry per friction pair.

    Attributes
    ----------
    mu_k, mu_s
        Friction coefficients.
    peak_slide, residual_slide
        Base slide relative to the floor: ``max |u|`` and ``u`` at the end, m.
    peak_deformation
        ``max |z|`` of the spring (top relative to base), m.
    peak_top_accel, peak_base_accel
        Peak absolute accelerations of the top and base masses, m/s².
    slide_fraction
        Fraction of the record spent sliding.
    slip_phases
        Number of breakaways and reversals.
    u, z, top_accel, base_accel
        Histories at the samples (``(n_mu, npts)``) when requested.
    notes
        What was done to the input record (e.g. its conversion from g to m/s² when it came as
        an ObsPy Trace in g), one line each; empty for samples given in m/s².
    """

    mu_k: np.ndarray
    mu_s: np.ndarray
    peak_slide: np.ndarray
    residual_slide: np.ndarray
    peak_deformation: np.ndarray
    peak_top_accel: np.ndarray
    peak_base_accel: np.ndarray
    slide_fraction: np.ndarray
    slip_phases: np.ndarray
    u: np.ndarray | None = field(default=None, repr=False)
    z: np.ndarray | None = field(default=None, repr=False)
    top_accel: np.ndarray | None = field(default=None, repr=False)
    base_accel: np.ndarray | None = field(default=None, repr=False)
    notes: tuple[str, ...] = ()


def oscillator_parameters(frequency, damping, mass_ratio) -> tuple[float, float, float]:
    """The checked 2-DOF oscillator (1-D and in the plane): ``(f, ξ, r)``, each refused in
    one line naming its argument (a number where one is expected, in its range)."""
    if frequency is None:
        raise ModelError("frequency (the clamped-base frequency, Hz) is required", "frequency")
    checks = (
        ("frequency", frequency, lambda v: v > 0, "> 0 Hz"),
        ("damping", damping, lambda v: 0 <= v < 1, "in [0, 1)"),
        ("mass_ratio", mass_ratio, lambda v: v > 0, "> 0"),
    )
    out = []
    for name, value, good, what in checks:
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise ModelError(f"{name} must be a number {what}, got {value!r}", name) from None
        if isinstance(value, bool) or not (math.isfinite(v) and good(v)):
            raise ModelError(f"{name} must be {what}, got {value!r}", name)
        out.append(v)
    return out[0], out[1], out[2]


def slide_oscillator(
    acc: RecordLike | FloorMotion,
    dt: float | None = None,
    mu=None,
    frequency: float | None = None,
    damping: float = 0.02,
    mass_ratio: float = 1.0,
    *,
    mu_s=None,
    building: LinearBuilding | None = None,
    floor: int | None = None,
    histories: bool = False,
    method: str = "exact",
    substeps: int = 16,
    rtol: float = 1e-6,
    grip_frequency: float = 100.0,
    grip_damping: float = 0.1,
    integrator: str = "LSODA",
    vertical=None,
    direction: str = "both",
) -> OscillatorResult:
    """Peak slide, spring deformation and accelerations of a 2-DOF sliding oscillator.

    Parameters
    ----------
    acc, dt
        Ground acceleration (m/s²) and time step (s); without `building` the motion the
        object stands on. Or an ObsPy Trace or one-trace Stream, dt from ``stats.delta`` (a
        given dt must equal it) and units from ``stats.units`` (converted to m/s² with a
        :class:`~floorslide.errors.UnitsConversionWarning` and a line in ``notes``; see
        :mod:`floorslide.inputs`). Or a :class:`~floorslide.FloorMotion`: the floor's exact
        motion integrated once (then no `building` or `floor` here).
    mu
        Kinetic friction coefficient(s), required (``mu_s`` defaults to it).
    frequency
        Clamped-base (fixed-base) natural frequency of the equipment, Hz; required.
    damping
        Damping ratio of the equipment on its clamped base, in [0, 1).
    mass_ratio
        ``r = m_base / m_top`` (> 0).
    mu_s
        Static coefficient(s).
    building, floor
        Put the oscillator on `floor` of `building` (exact chain ground → building → object).
    histories
        Also return the histories of u, z and both absolute accelerations (exact method only).
    method
        ``"exact"`` (default: both phases solved exactly, switches to machine precision);
        approximate, for the accuracy-versus-cost study
        (:mod:`floorslide.contents.oscillator_approx`):
        ``"newmark"`` (average acceleration with stick/slip checks at ``dt/substeps``) or
        ``"penalty"`` (Brochard & Gantenbein's grip spring of frequency `grip_frequency` and
        damping ratio `grip_damping`, integrated by SciPy's `integrator` at `rtol`).
    substeps, rtol, grip_frequency, grip_damping, integrator
        Settings of the approximate methods.
    vertical, direction
        What :func:`~floorslide.slide` takes for a rigid block: not modelled for the 2-DOF
        oscillator yet — refused in one line unless None and ``"both"``.

    Returns
    -------
    OscillatorResult

    References
    ----------
    Westermo, B., Udwadia, F. (1983), *Earthquake Eng. Struct. Dyn.* 11, 135–146.
    Brochard, D., Gantenbein, F. (1989). Seismic response of a sliding structure. *Transactions
    SMiRT 10*, vol. K2, 1147–1152.
    """
    if vertical is not None:
        raise ModelError(
            "vertical shaking is not modelled for the 2-DOF sliding oscillator yet (a rigid "
            "block takes it: fs.slide)",
            "vertical",
        )
    if direction != "both":
        raise ModelError(
            f"one-way sliding (direction={direction!r}) is not modelled for the 2-DOF sliding "
            "oscillator yet (a rigid block takes it: fs.slide)",
            "direction",
        )
    fm, a, dt, notes = unwrap(acc, dt, building, floor)
    if getattr(fm, "segmented", False) or getattr(building, "segmented", False):
        # a floor of a building on nonlinear isolation: its segments, integrated once
        from floorslide.contents.segmented import oscillators_on_segments

        if method != "exact":
            raise ModelError(
                "only the exact method is available on a building on nonlinear isolation",
                "method",
            )
        if mu is None or frequency is None:
            missing = "mu" if mu is None else "frequency"
            raise ModelError(f"slide_oscillator needs {missing}", missing)
        mk, ms = friction_pairs(mu, mu_s)
        f, xi, r = oscillator_parameters(frequency, damping, mass_ratio)
        if fm is None:
            if floor is None:
                raise ModelError("floor is required with building=", "floor")
            fm = building.motion(a, dt, floors=[floor]).floor(floor)
        return oscillators_on_segments(fm, mk, ms, f, xi, r, histories, notes)
    if fm is not None:
        building, floor = fm.building, fm.floor
    if mu is None or frequency is None:
        missing = "mu" if mu is None else "frequency"
        raise ModelError(f"slide_oscillator needs {missing}", missing)
    mk, ms = friction_pairs(mu, mu_s)
    f, xi, r = oscillator_parameters(frequency, damping, mass_ratio)
    w = 2 * math.pi * f
    if building is not None and floor is None:
        raise ModelError("floor is required with building=", "floor")
    on_floor = building is not None and building.dof_of(floor) is not None
    if building is not None:
        building.check_floors([floor])
    if method != "exact":
        result = _approximate(
            a, dt, mk, ms, w, xi, r, building, floor, method, histories,
            dict(substeps=substeps, rtol=rtol, grip_frequency=grip_frequency,
                 grip_damping=grip_damping, integrator=integrator),
        )  # fmt: skip
        return replace(result, notes=notes) if notes else result
    if fm is None:
        fm = single_use_motion(building if on_floor else None, a, dt, floor if on_floor else 0)
    states, hist = _exact_states(fm, a, mk, ms, w, xi, r, histories)
    check_event_limit(states[:, cols.O_LIMIT_AT], mk, OSCILLATOR_MAX_EVENTS, "slide_oscillator")
    duration = (a.size - 1) * dt
    return OscillatorResult(
        mu_k=mk,
        mu_s=ms,
        peak_slide=states[:, cols.O_PEAK_U].copy(),
        residual_slide=states[:, cols.O_U].copy(),
        peak_deformation=states[:, cols.O_PEAK_Z].copy(),
        peak_top_accel=states[:, cols.O_PEAK_TOP].copy(),
        peak_base_accel=states[:, cols.O_PEAK_BASE].copy(),
        slide_fraction=states[:, cols.O_SLIDE_TIME] / duration
        if duration > 0
        else np.zeros(mk.size),
        slip_phases=states[:, cols.O_SLIPS].astype(int),
        u=hist[:, :, 0].copy() if histories else None,
        z=hist[:, :, 1].copy() if histories else None,
        top_accel=hist[:, :, 2].copy() if histories else None,
        base_accel=hist[:, :, 3].copy() if histories else None,
        notes=notes,
    )


def _exact_states(fm, a, mk, ms, w, xi, r, histories, batched=True, counts=None):
    """Run the exact kernel over the floor motion `fm` for every friction pair at once:
    ``(states, hist)``, the kernel's state columns per pair and the histories at the samples.

    ``batched``: the batched kernel (:mod:`floorslide.contents._oscillator_batch`: exact
    propagators shared by all pairs, the event kernel only for parts where something may
    happen), or else the event kernel on every part
    (:func:`~floorslide.contents._oscillator_kernel.oscillator_kernel`, the reference the
    tests compare with). ``counts``: the batched kernel's part counters
    (:data:`~floorslide.contents._oscillator_batch.C_NCOL` integers), incremented.
    """
    m_o, ho, K = oscillator_parts(fm, w, xi, r)
    states = np.zeros((mk.size, cols.O_NCOL))
    states[:, cols.O_LIMIT_AT] = -1.0
    hist = np.zeros((mk.size, a.size, 4) if histories else (0, 0, 4))
    if histories:
        hist[:, 0, 3] = fm.beta[0] * a[0]
    mub = np.maximum(mk, ms)
    if batched:
        prop = _propagators(ho, K, w, xi, r)
        if counts is None:
            counts = np.zeros(batch.C_NCOL, dtype=np.int64)
    for k0, X in fm.chunks():
        if batched:
            batch.oscillator_batch_kernel(
                X, k0, fm.R, fm.beta, a, fm.substeps, fm.h, m_o, K, w, xi, r, G, mub, mk,
                *prop, states, hist, histories, OSCILLATOR_MAX_EVENTS, counts,
            )  # fmt: skip
        else:
            oscillator_kernel(
                X, k0, fm.R, fm.beta, a, fm.substeps, fm.h, m_o, K, w, xi, r, G, mub, mk,
                states, hist, histories, OSCILLATOR_MAX_EVENTS,
            )  # fmt: skip
    return states, hist


def oscillator_parts(fm, w: float, xi: float, r: float) -> tuple[int, float, int]:
    """How the 2-DOF oscillator steps through the floor motion `fm`: each of the motion's own
    sub-steps split into ``m_o`` parts of length ``ho`` so that the oscillator's phases have
    ρ·h ≤ 0.5 (the floor polynomial is shifted to each part), and the Taylor degree ``K`` of
    a part for the faster of the oscillator and the building. Returns ``(m_o, ho, K)``."""
    rho_obj = phase_radius(w, xi, r)
    rho_b = 0.0 if fm.ground else spectral_radius(fm.motion.stepper.A)
    m_o = substeps_for(rho_obj, fm.h)
    ho = fm.h / m_o
    return m_o, ho, max(fm.order, taylor_degree(max(rho_b, rho_obj) * ho))


@functools.lru_cache(maxsize=32)
def _propagators(ho: float, K: int, w: float, xi: float, r: float):
    """:func:`~floorslide.contents._oscillator_batch.phase_propagators`, kept for repeated
    calls with the same oscillator and part length (read-only arrays)."""
    out = batch.phase_propagators(ho, K, w, xi, r)
    for arr in out:
        arr.setflags(write=False)
    return out


def _approximate(a, dt, mk, ms, w, xi, r, building, floor, method, histories, settings):
    """Dispatch to :mod:`floorslide.contents.oscillator_approx` (no histories there)."""
    from floorslide.contents import oscillator_approx

    if histories:
        raise ModelError(f"histories are only available with method='exact', not {method!r}")
    out = oscillator_approx.slide_oscillator(
        a, dt, mk, ms, w, xi, r, G, building, floor, method, **settings
    )
    duration = (a.size - 1) * dt
    return OscillatorResult(
        mu_k=mk,
        mu_s=ms,
        peak_slide=out[:, 0],
        residual_slide=out[:, 1],
        peak_deformation=out[:, 2],
        peak_top_accel=out[:, 3],
        peak_base_accel=out[:, 4],
        slide_fraction=out[:, 5] / duration if duration > 0 else np.zeros(mk.size),
        slip_phases=out[:, 6].astype(int),
    )
