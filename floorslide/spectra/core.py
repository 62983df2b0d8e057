"""Response spectra and floor response spectra, exact at any dt.

For every period and damping ratio, the linear oscillator ``q'' + 2ξω q' + ω² q = −a_f(t)`` is
driven by the floor's absolute acceleration — the ground record itself (piecewise linear) or the
building's exact floor response to it. The oscillator is stepped exactly together with the
floor (the augmented first-order hold of ``building/exact.py``; on the ground the recurrence of
Nigam & Jennings 1969) and its peaks are searched inside steps. Spectral values:

- ``sd = max|q|`` (m), ``psa = ω²·sd``, ``psv = ω·sd`` (pseudo-spectral values);
- ``sv = max|q'|`` (m/s, relative velocity);
- ``sa = max|q'' + a_f| = max|ω² q + 2ξω q'|`` (m/s², absolute acceleration — not PSA).

At period 0 the oscillator is rigid: ``psa = sa`` = the true peak of the floor motion (inside
steps), ``sd = sv = 0``.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from floorslide.building.exact import (
    MAX_PHASE,
    spectral_radius,
    substeps_for,
    taylor_degree,
    taylor_degrees,
)
from floorslide.building.exact_motion import (
    FloorMotion,
    _cached_stepper,
    single_use_motion,
    unwrap,
)
from floorslide.building.model import LinearBuilding
from floorslide.building.motions import floor_motions
from floorslide.constants import MAX_LIST
from floorslide.errors import ModelError
from floorslide.inputs import RecordLike
from floorslide.spectra import _kernels as K
from floorslide.spectra._closed_forms import coupled_recurrence, impulse_integrals
from floorslide.spectra._kernels import (
    NB,
    NCOEF,
    NFB,
    SpectrumSetup,
    sample_peaks,
    screen_thresholds,
    spectrum_kernel,
    spectrum_state,
)

# running totals of the kernel's work (diagnostics for benchmarks): oscillator-steps searched
# inside, floor sub-step data computed
METHODS = ("exact", "samples", "newmark", "fft", "reinterpolated")

MAX_OSCILLATORS = 100_000
"""Most oscillators (periods × damping ratios) one spectrum computes."""
MAX_PERIOD = 1e4
"""Longest period, s: beyond any structure (the oscillator's relative displacement is then
the ground's displacement)."""
MIN_PERIOD_STEPS = 1000
"""Shortest positive period is ``dt / MIN_PERIOD_STEPS``: the exact solver steps each
oscillator on sub-steps of at most ``MAX_PHASE/ω``, about ``4π·dt/T`` per record step, so a
shorter one needs absurd sub-step counts (``T = 1e-9`` s at dt = 0.01 s: 1.3e8 per step and a
MemoryError). Use ``T = 0`` for the peak acceleration."""


@dataclass(frozen=True)
class Spectrum:
    """Response spectra, one row per damping ratio.

    Attributes
    ----------
    periods
        Oscillator periods, s (0 allowed: the peak of the motion).
    damping
        Damping ratios.
    psa, sa, sv, sd, psv
        ``(len(damping), len(periods))``: pseudo-spectral acceleration (m/s²), absolute
        acceleration (m/s²), relative velocity (m/s), relative displacement (m), pseudo-velocity
        (m/s).
    method
        How it was computed.
    broadening
        Peak-broadening factor applied (0 when none).
    notes
        What was done to the input record (e.g. its conversion from g to m/s² when it came as
        an ObsPy Trace in g), one line each; empty for samples given in m/s².
    """

    periods: np.ndarray
    damping: np.ndarray
    psa: np.ndarray
    sa: np.ndarray
    sv: np.ndarray
    sd: np.ndarray
    psv: np.ndarray
    method: str = "exact"
    broadening: float = 0.0
    notes: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        """JSON-ready dict with SI values (``psa[i]`` belongs to ``damping[i]``)."""
        return dict(
            periods=self.periods.tolist(),
            damping=self.damping.tolist(),
            psa=self.psa.tolist(),
            sa=self.sa.tolist(),
            sv=self.sv.tolist(),
            sd=self.sd.tolist(),
            psv=self.psv.tolist(),
            method=self.method,
            broadening=self.broadening,
            notes=list(self.notes),
        )


def period_grid(periods) -> np.ndarray:
    """Periods from a list or from ``{"min": .., "max": .., "n": ..}`` (log-spaced), validated:
    finite, ``0 ≤ T ≤`` :data:`MAX_PERIOD`, at most :data:`~floorslide.constants.MAX_LIST` of
    them (a scene's limit)."""
    if isinstance(periods, dict):
        try:
            lo, hi, n = float(periods["min"]), float(periods["max"]), int(periods["n"])
        except (KeyError, TypeError, ValueError):
            raise ModelError("periods must be a list or {min, max, n}", "periods") from None
        if not (0 < lo < hi and n >= 2):
            raise ModelError(f"periods need 0 < min < max and n ≥ 2, got {periods}", "periods")
        _check_count(n, "periods")
        arr = np.geomspace(lo, hi, n)
    else:
        arr = np.atleast_1d(np.asarray(periods, dtype=float)).ravel()
        if arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(arr < 0):
            raise ModelError("periods must be finite and ≥ 0 s", "periods")
        _check_count(arr.size, "periods")
    if arr.max() > MAX_PERIOD:
        raise ModelError(
            f"period {arr.max():g} s is above {MAX_PERIOD:g} s, beyond any structure "
            "(its spectral displacement is the ground's displacement)",
            "periods",
        )
    return arr


def _check_count(n: int, name: str) -> None:
    """At most :data:`~floorslide.constants.MAX_LIST` periods (or damping ratios)."""
    if n > MAX_LIST:
        raise ModelError(f"{n} {name}: at most {MAX_LIST} in one spectrum", name)


def damping_ratios(damping) -> np.ndarray:
    """Damping ratios in [0, 1), at most :data:`~floorslide.constants.MAX_LIST` of them, as an
    array."""
    arr = np.atleast_1d(np.asarray(damping, dtype=float)).ravel()
    if arr.size == 0:
        raise ModelError("damping ratios must be in [0, 1), got none", "damping")
    bad = arr[~(np.isfinite(arr) & (arr >= 0) & (arr < 1))]
    if bad.size:
        shown = ", ".join(f"{z:g}" for z in bad[:3]) + (" …" if bad.size > 3 else "")
        raise ModelError(f"damping ratios must be in [0, 1), got {shown}", "damping")
    _check_count(arr.size, "damping")
    return arr


def check_oscillators(periods: np.ndarray, damping: np.ndarray, dt: float | None = None) -> None:
    """Refuse a spectrum whose oscillators would exhaust memory or time: more than
    :data:`MAX_OSCILLATORS` (periods × damping ratios), or, given the record's `dt`, a positive
    period below ``dt /`` :data:`MIN_PERIOD_STEPS`. Raises :class:`ModelError`."""
    if periods.size * damping.size > MAX_OSCILLATORS:
        raise ModelError(
            f"{periods.size} periods x {damping.size} damping ratios = "
            f"{periods.size * damping.size} oscillators: at most {MAX_OSCILLATORS}",
            "periods",
        )
    if dt is None:
        return
    positive = periods[periods > 0]
    if positive.size and positive.min() < dt / MIN_PERIOD_STEPS:
        raise ModelError(
            f"period {positive.min():g} s is below dt/{MIN_PERIOD_STEPS} = "
            f"{dt / MIN_PERIOD_STEPS:g} s (dt = {dt:g} s): its oscillator would need over "
            f"{MIN_PERIOD_STEPS} sub-steps per record step; give 0 for the peak acceleration",
            "periods",
        )


def _sdof_recurrence(w, xi, h):
    """Exact step of oscillators on the ground, ``q'' + 2ξωq' + ω²q = −a`` with ``a`` linear over
    a step ``h``: ``[q, q']⁺ = Φ [q, q'] + p a + q a⁺`` (Nigam & Jennings 1969).

    In the scaled state ``y = [ωq, q']`` the system matrix is ``θJ`` with ``θ = ωh`` and
    ``J = [[0, 1], [−1, −2ξ]]``; the step is ``e^{θJ}`` (closed form) and the input weights are
    ``h(φ₁ − φ₂)b`` and ``hφ₂b`` with ``φ₁(X) = X⁻¹(e^X − I)``, ``φ₂(X) = X⁻¹(φ₁(X) − I)``:
    in closed form for ``θ ≥ 0.5`` and by their Taylor series below, where the closed form
    cancels (series truncated once its terms fall below 1e-20). Returns ``Φ`` ``(m, 2, 2)``,
    ``p`` and ``q`` ``(m, 2)``; ``h`` may be one value or one per oscillator.
    """
    w = np.asarray(w, float)
    xi = np.asarray(xi, float)
    h = np.broadcast_to(np.asarray(h, float), w.shape)
    th = w * h
    m = w.size
    J = np.zeros((m, 2, 2))
    J[:, 0, 1] = 1.0
    J[:, 1, 0] = -1.0
    J[:, 1, 1] = -2.0 * xi
    eye = np.broadcast_to(np.eye(2), (m, 2, 2))
    sq = np.sqrt(1.0 - xi**2)
    thd = th * sq
    E = np.exp(-xi * th)[:, None, None] * (
        np.cos(thd)[:, None, None] * eye
        + (np.sin(thd) / sq)[:, None, None] * (J + xi[:, None, None] * eye)
    )
    X = th[:, None, None] * J
    # closed form (J⁻¹ = [[−2ξ, −1], [1, 0]])
    Jinv = np.zeros((m, 2, 2))
    Jinv[:, 0, 0] = -2.0 * xi
    Jinv[:, 0, 1] = -1.0
    Jinv[:, 1, 0] = 1.0
    Xinv = Jinv / th[:, None, None]
    F1 = Xinv @ (E - eye)
    F2 = Xinv @ (F1 - eye)
    # Taylor series where θ < 0.5
    small = th < 0.5
    if small.any():
        Xs = X[small]
        term = np.broadcast_to(np.eye(2), Xs.shape).copy()
        S1 = np.zeros_like(Xs)
        S2 = np.zeros_like(Xs)
        fact = 1.0  # k!
        for k in range(30):
            S1 += term / (fact * (k + 1))
            S2 += term / (fact * (k + 1) * (k + 2))
            term = term @ Xs
            fact *= k + 1
            # ‖X‖ ≤ (1 + 2ξ)θ < 1.5: the terms left shrink faster than geometrically
            if np.abs(term).max() / fact < 1e-20:
                break
        F1[small] = S1
        F2[small] = S2
    # back to [q, q']: Φ_ij = E_ij d_j / d_i with d = (ω, 1); b = [0, −1] in both
    Phi = E.copy()
    Phi[:, 0, 1] /= w
    Phi[:, 1, 0] *= w
    g1 = -h[:, None] * F1[:, :, 1]
    g2 = -h[:, None] * F2[:, :, 1]
    g1[:, 0] /= w
    g2[:, 0] /= w
    return np.ascontiguousarray(Phi), np.ascontiguousarray(g1 - g2), np.ascontiguousarray(g2)


def _oscillator_blocks(A, b, Ca, da, w, xi, h):
    """Exact sub-step recurrence of oscillators coupled to a floor, by the series of
    :func:`~floorslide.spectra._closed_forms.coupled_recurrence` (the augmented first-order hold
    of Van Loan 1978 without a matrix exponential per oscillator); on the ground, in closed form
    (:func:`_sdof_recurrence`)."""
    n = A.shape[0]
    if n == 0:
        Pqq, pq, qq = _sdof_recurrence(w, xi, h)
        return Pqq, np.zeros((w.size, 2, 0)), pq, qq
    return coupled_recurrence(A, b, Ca, da, w, xi, h)


def _blocks(w, xi, dt, Pqq, Pqx, pq, qq, one_crit, Ih):
    """Kernel data in blocks of ``NB`` oscillators, row by row (see ``_kernels._stage_ground``).

    Returns the coefficient rows ``(n_blocks, NCOEF·NB)`` and the coupling rows
    ``(n_blocks, 2·n_states·NB)``.
    """
    nosc = w.size
    n = Pqx.shape[2]
    nblk = -(-nosc // NB)
    w2 = w * w
    kd = w2 * dt * dt / 8.0
    sa = w2 * (1 + 2 * xi)
    rows = np.zeros((NCOEF, nblk * NB))
    for r, v in (
        (K.P0, Pqq[:, 0, 0]),
        (K.P1, Pqq[:, 0, 1]),
        (K.P2, Pqq[:, 1, 0]),
        (K.P3, Pqq[:, 1, 1]),
        (K.P4, pq[:, 0]),
        (K.P5, pq[:, 1]),
        (K.X0, qq[:, 0]),
        (K.X1, qq[:, 1]),
        (K.W, w),
        (K.W2, w2),
        (K.C2, 2 * xi * w),
        (K.IW2, 1 / w2),
        (K.AS, 2 * xi * w / w2**2),
        (K.XIW, xi * w),
        (K.IWD, 1 / (w * np.sqrt(1 - xi**2))),
        (K.KD2, kd**2),
        (K.KV2, (kd * w) ** 2),
        (K.KA2, (kd * sa) ** 2),
        (K.SA, sa),
        (K.SA2, sa**2),
        (K.ONE, one_crit.astype(float)),
        (K.IH0, Ih[0]),
        (K.IH1, Ih[1]),
        (K.IH2, Ih[2]),
    ):
        rows[r, :nosc] = v
    C = np.ascontiguousarray(rows.reshape(NCOEF, nblk, NB).transpose(1, 0, 2).reshape(nblk, -1))
    px = np.zeros((2 * n, nblk * NB))
    px[0::2, :nosc] = Pqx[:, 0, :].T
    px[1::2, :nosc] = Pqx[:, 1, :].T
    PX = np.ascontiguousarray(px.reshape(2 * n, nblk, NB).transpose(1, 0, 2).reshape(nblk, -1))
    return C, PX


@functools.lru_cache(maxsize=16)
def _kernel_data(
    dt: float, T_bytes: bytes, Z_bytes: bytes, n: int, system: bytes, period_major: bool = False
) -> SpectrumSetup:
    """Everything the spectrum kernel needs but the record, for oscillators of periods ``T`` and
    damping ratios ``Z`` on a floor whose state-space data (``n`` states; ``A``, ``b``, ``Ca``,
    ``da`` packed in ``system``) is given, or on the ground (``n = 0``). Cached: a study asks for
    the same periods, damping ratios, dt and building record after record. The arrays returned
    are shared between calls: they are returned read-only.

    Oscillators are numbered damping-major (``i_Z·len(T) + i_T``), or with `period_major`
    period-major (``i_T·len(Z) + i_Z``): then the damping ratios of one period sit in one block
    of the kernel and share the floor's sub-step data of their group (same sub-steps), which
    the kernel computes once per block and step."""
    T = np.frombuffer(T_bytes)
    Z = np.frombuffer(Z_bytes)
    on_floor = n > 0
    if on_floor:
        sysv = np.frombuffer(system)
        A = sysv[: n * n].reshape(n, n)
        b = sysv[n * n : n * n + n]
        Ca = sysv[n * n + n : n * n + 2 * n]
        da = float(sysv[-1])
        rho_b = spectral_radius(A)
    else:
        A, b, Ca, da, rho_b = np.zeros((0, 0)), np.zeros(0), np.zeros(0), 1.0, 0.0
    TT, ZZ = np.meshgrid(T, Z)
    if period_major:
        TT, ZZ = TT.T, ZZ.T
    w = np.ascontiguousarray(2 * np.pi / TT.ravel())
    xi = np.ascontiguousarray(ZZ.ravel())
    nosc = w.size
    # record-step recurrence of every oscillator coupled to the floor
    Pqq, Pqx, pq, qq = _oscillator_blocks(A, b, Ca, da, w, xi, dt)
    one_crit = np.maximum(w, rho_b) * dt <= MAX_PHASE
    # the building: record step, and its own sub-steps for the floor-acceleration bound
    if on_floor:
        own = _cached_stepper(n, A.tobytes(), b.tobytes(), float(dt), None)
        b_R, b_beta = own.taylor_rows(Ca[None, :], np.array([da]))
        b_phi, (b_p, b_q), b_R, b_beta = own.phi, own.input_weights(), b_R[0], b_beta[0]
        b_K, b_m = own.order, own.substeps
    else:
        b_phi, b_p, b_q = np.zeros((0, 0)), np.zeros(0), np.zeros(0)
        b_R, b_beta, b_K, b_m = np.zeros((2, 0)), np.array([1.0, 0.0]), 1, 1
    # in-step search: sub-steps per oscillator (at most one critical point on each), grouped
    # by their number
    m_all = substeps_for(np.maximum(w, rho_b), dt)
    groups = np.unique(m_all)
    grp = np.searchsorted(groups, m_all).astype(np.int64)
    G_K = np.array(
        [taylor_degree(max(rho_b, w[m_all == m].max()) * dt / m) for m in groups], dtype=np.int64
    )
    K_osc = taylor_degrees(np.maximum(rho_b, w) * dt / m_all)
    kr = int(G_K.max()) + 1
    G_phi = np.zeros((groups.size, n, n))
    G_p = np.zeros((groups.size, n))
    G_q = np.zeros((groups.size, n))
    G_R = np.zeros((groups.size, kr, n))
    G_beta = np.zeros((groups.size, kr))
    S_Pqq = np.zeros((nosc, 2, 2))
    S_Pqx = np.zeros((nosc, 2, n))
    S_pq = np.zeros((nosc, 2))
    S_qq = np.zeros((nosc, 2))
    # the oscillators' own sub-steps: the record step itself for one sub-step, else all in one
    # batch (each with its own sub-step dt/m)
    one = m_all == 1
    S_Pqq[one], S_Pqx[one], S_pq[one], S_qq[one] = Pqq[one], Pqx[one], pq[one], qq[one]
    if not one.all():
        more = ~one
        S_Pqq[more], S_Pqx[more], S_pq[more], S_qq[more] = _oscillator_blocks(
            A, b, Ca, da, w[more], xi[more], dt / m_all[more]
        )
    for g, m in enumerate(groups):
        if on_floor:
            # (the building's sub-step matrices: one small expm per group, cached with those
            # of the floor motions)
            st = _cached_stepper(n, A.tobytes(), b.tobytes(), float(dt), int(m))
            R, beta = st.taylor_rows(Ca[None, :], np.array([da]), order=int(G_K[g]))
            G_phi[g] = st.phi
            G_p[g], G_q[g] = st.input_weights()
            G_R[g, : R.shape[1]] = R[0]
            G_beta[g, : R.shape[1]] = beta[0]
    Ih = impulse_integrals(w, xi, dt) if on_floor else np.zeros((3, nosc))
    C, PX = _blocks(w, xi, dt, Pqq, Pqx, pq, qq, one_crit, Ih)
    return SpectrumSetup(
        *_read_only(
            C,
            PX,
            w,
            xi,
            b_phi,
            b_p,
            b_q,
            np.ascontiguousarray(b_R),
            np.ascontiguousarray(b_beta),
            int(b_K),
            int(b_m),
            grp,
            groups.astype(np.int64),
            G_K,
            K_osc,
            G_phi,
            G_p,
            G_q,
            G_R,
            G_beta,
            S_Pqq,
            S_Pqx,
            S_pq,
            S_qq,
        )
    )


def _read_only(*items) -> tuple:
    """``items`` with every array made read-only (they are cached and shared)."""
    for x in items:
        if isinstance(x, np.ndarray):
            x.setflags(write=False)
    return items


def _exact(fm, T, Z, search_all=False, counts=None):
    """Exact spectra on the ground or a floor (a :class:`FloorMotion`); returns sd, sv, sa of
    shape (len(Z), len(T)).

    ``counts`` (``int64[2]``, optional) is incremented by the oscillator·steps searched inside
    the step and the floor sub-step data computed (benchmarks report the search fraction)."""
    if counts is None:
        counts = np.zeros(2, dtype=np.int64)
    a, dt = fm.acc, fm.dt
    building, floor = fm.building, fm.floor
    on_floor = not fm.ground
    if on_floor:
        A, B = building.state_matrices()
        Ca, Da, _ = building.output_matrices([floor], "acceleration")
        system = (A.shape[0], np.concatenate([A.ravel(), B[:, 0], Ca[0], Da[0]]).tobytes())
        # the floor is stepped on the building's own sub-steps (ρ(A)·h ≤ 0.5), where the skip
        # tests of most oscillators can use the sign of a derivative: the floor motion's grid
        up = fm.substeps
    else:
        system = (0, b"")
        up = 1
    pos = T > 0
    h = dt / up
    out = np.zeros((int(pos.sum()) * Z.size, 3))
    if pos.any():  # (periods 0 only: no oscillator)
        setup = _kernel_data(
            float(h),
            np.asarray(T[pos], float).tobytes(),
            np.asarray(Z, float).tobytes(),
            *system,
            period_major=True,
        )
        S = spectrum_state(setup.C.shape[0], fm.beta[0] * a[0])
        # two passes (see _kernels): the peaks at the samples, then the search inside the
        # steps where a larger peak is not excluded
        FB = np.zeros(NFB)
        for k0, X in fm.chunks():
            sample_peaks(setup, X, k0, a, up, h, S, FB)
        screen_thresholds(setup.C, S, setup.w.size, FB, h, on_floor)
        for k0, X in fm.chunks():
            spectrum_kernel(setup, X, k0, a, up, h, search_all, S, out, counts)
    sd = np.zeros((Z.size, T.size))
    sv = np.zeros((Z.size, T.size))
    sa = np.zeros((Z.size, T.size))
    # (oscillators period-major: see _kernel_data)
    sd[:, pos] = out[:, 0].reshape(-1, Z.size).T
    sv[:, pos] = out[:, 1].reshape(-1, Z.size).T
    sa[:, pos] = out[:, 2].reshape(-1, Z.size).T
    if (~pos).any():
        sa[:, ~pos] = fm.peak()[0]
    return sd, sv, sa


def response_spectrum(
    acc: RecordLike | FloorMotion,
    dt: float | None = None,
    periods=None,
    damping=0.05,
    *,
    building: LinearBuilding | None = None,
    floor: int | None = None,
    method: str = "exact",
    substeps: int = 4,
) -> Spectrum:
    """Response spectra of a record, or floor response spectra (FRS) of a building's floor.

    Parameters
    ----------
    acc
        Ground acceleration samples, m/s² (or, without `building`, any motion taken as piecewise
        linear). Or an ObsPy Trace or one-trace Stream: dt from ``stats.delta``, units from
        ``stats.units`` (converted to m/s² with a
        :class:`~floorslide.errors.UnitsConversionWarning` and a line in ``notes``; see
        :mod:`floorslide.inputs`). Or a :class:`~floorslide.FloorMotion`: the floor's exact
        motion integrated once (then no `building` or `floor` here).
    dt
        Time step, s; required for samples, optional for a Trace (must equal ``stats.delta``)
        or a FloorMotion.
    periods
        Oscillator periods (s, list; 0 gives the peak of the motion) or ``{"min", "max", "n"}``
        (log-spaced); required. At most :data:`~floorslide.constants.MAX_LIST` (as in a scene),
        none above :data:`MAX_PERIOD` nor, but 0, below ``dt /`` :data:`MIN_PERIOD_STEPS`.
    damping
        Damping ratio or list of ratios (at most :data:`MAX_OSCILLATORS` oscillators in all).
    building, floor
        Floor response spectrum of `floor`, driven by the building's exact floor motion.
    method
        ``"exact"``; approximate: ``"samples"`` (exact recurrence, peaks at samples only),
        ``"newmark"`` (average acceleration at ``dt/substeps`` on exact floor samples), ``"fft"``
        (frequency-domain transfer function, peaks at samples), ``"reinterpolated"`` (exact
        solver on floor samples joined by straight lines).
    substeps
        Sub-steps of ``"newmark"``.

    Returns
    -------
    Spectrum

    References
    ----------
    Nigam, N. C., Jennings, P. C. (1969). Calculation of response spectra from strong-motion
    earthquake records. *Bull. Seismol. Soc. Am.* 59(2), 909–922.
    Van Loan (1978), Theorem 1 (the augmented matrix exponential).
    """
    fm, a, dt, notes = unwrap(acc, dt, building, floor)
    if getattr(fm, "segmented", False) or getattr(building, "segmented", False):
        # a floor of a building on nonlinear isolation: its segments, integrated once
        from floorslide.spectra.segmented import spectrum_on_segments

        if method != "exact":
            raise ModelError(
                f"method={method!r} is not available on a building on nonlinear isolation "
                "(the exact method is)",
                "method",
            )
        if periods is None:
            raise ModelError("periods are required: a list in s or {min, max, n}", "periods")
        T = period_grid(periods)
        Z = damping_ratios(damping)
        check_oscillators(T, Z, dt)
        if fm is None:
            if floor is None:
                raise ModelError("floor is required with building=", "floor")
            fm = building.motion(a, dt, floors=[floor]).floor(floor)
        return spectrum_on_segments(fm, T, Z, notes)
    if fm is not None:
        building, floor = fm.building, fm.floor
    if periods is None:
        raise ModelError("periods are required: a list in s or {min, max, n}", "periods")
    T = period_grid(periods)
    Z = damping_ratios(damping)
    check_oscillators(T, Z, dt)
    if method not in METHODS:
        raise ModelError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    if building is not None:
        if floor is None:
            raise ModelError("floor is required with building=", "floor")
        building.check_floors([floor])
    elif floor not in (None, 0):
        raise ModelError("floor= needs building=", "floor")
    if method == "exact":
        if fm is None:
            fm = single_use_motion(building, a, dt, floor)
        sd, sv, sa = _exact(fm, T, Z)
    else:
        from floorslide.spectra import approximate

        sd, sv, sa = approximate.spectra(a, dt, T, Z, building, floor, method, int(substeps))
    w = np.where(T > 0, 2 * np.pi / np.where(T > 0, T, 1.0), 0.0)
    psa = sd * w**2
    psa[:, T == 0] = sa[:, T == 0]
    return Spectrum(
        periods=T, damping=Z, psa=psa, sa=sa, sv=sv, sd=sd, psv=sd * w, method=method, notes=notes
    )


def broaden(spectrum: Spectrum, factor: float = 0.15) -> Spectrum:
    """Peak broadening of a design floor response spectrum.

    Each ordinate becomes the largest ordinate within ``±factor`` in frequency:
    ``S_b(f) = max{S(f') : f/(1+factor) ≤ f' ≤ f/(1−factor)}``, the ±15 % of ASCE 4-16 §6.2.3
    and US NRC Regulatory Guide 1.122 (ordinates between grid periods interpolated linearly in
    log-period). Periods 0 are left as they are.
    """
    if not (0 < factor < 1):
        raise ModelError(f"broadening factor must be in (0, 1), got {factor}", "broadening")
    T = spectrum.periods
    pos = T > 0
    Tp = T[pos]
    order = np.argsort(Tp)
    Ts = Tp[order]
    lt = np.log(Ts)

    def widen(S: np.ndarray) -> np.ndarray:
        out = S.copy()
        for i in range(S.shape[0]):
            row = S[i, pos][order]
            new = row.copy()
            for j, t in enumerate(Ts):
                lo, hi = t * (1 - factor), t * (1 + factor)  # f' ∈ [f/(1+β), f/(1−β)]
                inside = (Ts >= lo) & (Ts <= hi)
                ends = np.interp(np.log([lo, hi]), lt, row)
                new[j] = max(row[inside].max(initial=-np.inf), ends.max())
            tmp = np.empty_like(row)
            tmp[order] = new
            out[i, pos] = tmp
        return out

    return replace(
        spectrum,
        psa=widen(spectrum.psa),
        sa=widen(spectrum.sa),
        sv=widen(spectrum.sv),
        sd=widen(spectrum.sd),
        psv=widen(spectrum.psv),
        broadening=float(factor),
    )


def envelope(spectra: Sequence[Spectrum]) -> Spectrum:
    """Ordinate-wise maximum of spectra on the same periods and damping ratios."""
    spectra = list(spectra)
    if not spectra:
        raise ModelError("envelope needs at least one spectrum")
    first = spectra[0]
    for s in spectra[1:]:
        if not (
            np.array_equal(s.periods, first.periods) and np.array_equal(s.damping, first.damping)
        ):
            raise ModelError("spectra must share periods and damping ratios to be enveloped")
    stack = {
        k: np.max([getattr(s, k) for s in spectra], axis=0)
        for k in ("psa", "sa", "sv", "sd", "psv")
    }
    notes = tuple(dict.fromkeys(n for s in spectra for n in s.notes))
    return replace(first, **stack, method="envelope", notes=notes)


def floor_samples(acc, dt, building, floor, oversample=1):
    """Exact samples of the floor absolute acceleration (the record itself on the ground)."""
    if building is None or building.dof_of(floor) is None:
        if oversample == 1:
            return acc
        return np.interp(
            np.arange((acc.size - 1) * oversample + 1) / oversample, np.arange(acc.size), acc
        )
    return floor_motions(building, acc, dt, floors=[floor], oversample=oversample)[0]
