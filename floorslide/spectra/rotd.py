"""RotD50 and RotD100 spectra (Boore 2010) of two horizontal components, on the ground or on a
building's floor, exact with peaks inside steps (docs/design.md §10d).

For an oscillator of period ``T`` and damping ``ξ``, ``q1(t)`` and ``q2(t)`` are its relative
displacements under each direction's (floor) motion; along the angle ``θ`` (from ``h1`` towards
``h2``) the response is ``q_θ(t) = q1(t) cos θ + q2(t) sin θ`` (Boore 2010: the oscillator's two
responses rotated, equal by linearity to its response to the motion along θ). Then

- ``RotD100 = ω² · max_t |(q1, q2)|``: the largest response over *all* angles (the continuous
  maximum: no angle grid), the peak of the response vector;
- ``RotD50 = ω² · median_j max_t |q_θj|`` over ``θ_j = j·180°/n``, ``j = 0..n−1`` (Boore uses
  ``n = 180``: 1° steps); numpy's median (for an even ``n`` the mean of the two middle values).

Every maximum over time is exact for the record as the piecewise-linear function through its
samples (the meaning of ``response_spectrum(method="exact")``): found inside steps by the
kernels of :mod:`floorslide.spectra._rotd_kernels`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from floorslide.building.directions import plane_motions
from floorslide.building.exact_motion import FloorMotion
from floorslide.building.plane_isolation import PlaneIsolatedMotion, couples_directions
from floorslide.errors import ModelError
from floorslide.pair import as_pair
from floorslide.spectra import _kernels as K
from floorslide.spectra import _rotd_kernels as RK
from floorslide.spectra.core import (
    Spectrum,
    _kernel_data,
    check_oscillators,
    damping_ratios,
    period_grid,
    response_spectrum,
)

METHODS = ("exact", "samples")

MAX_ANGLES = 3600
"""Most angles of one RotD spectrum (0.05° apart)."""

MAX_VALUES = 20_000_000
"""Most per-angle peaks (oscillators × angles) of one RotD spectrum (160 MB)."""


@dataclass(frozen=True)
class RotDSpectrum:
    """RotD50 and RotD100 spectra (Boore 2010), one row per damping ratio.

    Attributes
    ----------
    periods
        Oscillator periods, s (0: the peaks of the motion itself).
    damping
        Damping ratios.
    rotd50, rotd100
        ``(len(damping), len(periods))``: pseudo-spectral accelerations (m/s²), the median over
        the angles and the largest over every direction.
    angle100, time100
        Direction (degrees from ``h1`` towards ``h2``, in [0, 180)) and time (s) of RotD100.
    psa_angles
        ``(len(damping), len(periods), len(angles))``: PSA along each angle, ``ω²·max|q_θ|``.
    angles
        The angles, degrees (``j·180/n``).
    h1, h2
        Ordinary spectra of each direction's motion (:func:`response_spectrum` of the floor
        motion along ``h1`` and ``h2``, same method), or None when not asked for.
    method
        ``"exact"`` or ``"samples"``.
    notes
        What was done to the components (padding), one line each.
    """

    periods: np.ndarray
    damping: np.ndarray
    rotd50: np.ndarray
    rotd100: np.ndarray
    angle100: np.ndarray
    time100: np.ndarray
    psa_angles: np.ndarray
    angles: np.ndarray
    h1: Spectrum | None
    h2: Spectrum | None
    method: str = "exact"
    notes: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        """JSON-ready dict with SI values (``rotd50[i]`` belongs to ``damping[i]``; the
        per-angle values are left out)."""
        return dict(
            periods=self.periods.tolist(),
            damping=self.damping.tolist(),
            rotd50=self.rotd50.tolist(),
            rotd100=self.rotd100.tolist(),
            angle100=self.angle100.tolist(),
            time100=self.time100.tolist(),
            angles=int(self.angles.size),
            h1=None if self.h1 is None else self.h1.to_dict(),
            h2=None if self.h2 is None else self.h2.to_dict(),
            method=self.method,
            notes=list(self.notes),
        )


def _angle_count(angles) -> int:
    if isinstance(angles, bool) or not isinstance(angles, int | np.integer):
        raise ModelError(f"angles must be a whole number of angles, got {angles!r}", "angles")
    if not 2 <= int(angles) <= MAX_ANGLES:
        raise ModelError(f"angles must be from 2 to {MAX_ANGLES}, got {angles}", "angles")
    return int(angles)


def _copy(x) -> np.ndarray:
    return np.array(x, dtype=float, order="C")


def _read_only(x: np.ndarray) -> np.ndarray:
    v = x.view()
    v.setflags(write=False)
    return v


def _system(fm: FloorMotion) -> tuple[int, bytes]:
    """The floor's state-space data as :func:`~floorslide.spectra.core._kernel_data` takes it."""
    if fm.ground:
        return 0, b""
    A, B = fm.building.state_matrices()
    Ca, Da, _ = fm.building.output_matrices([fm.floor], "acceleration")
    return A.shape[0], np.concatenate([A.ravel(), B[:, 0], Ca[0], Da[0]]).tobytes()


def _direction(fm: FloorMotion, setup) -> RK.Direction:
    """One direction's kernel data (:class:`~floorslide.spectra._rotd_kernels.Direction`) from
    the spectrum kernel's setup (None when there is no oscillator of positive period)."""
    n = fm.R.shape[1]
    if setup is None:
        z = np.zeros
        F, FX, S, SX = z((0, 8)), z((0, 2, n)), z((0, 8)), z((0, 2, n))
        G = (z((1, n, n)), z((1, n)), z((1, n)), z((1, 1, n)), z((1, 1)))
        b = (z((n, n)), z(n), z(n), z((1, n)), np.array([1.0]), 1, 1)
    else:
        nosc = setup.w.size
        C = np.asarray(setup.C)
        nblk = C.shape[0]
        rows = C.reshape(nblk, K.NCOEF, K.NB).transpose(1, 0, 2).reshape(K.NCOEF, -1)[:, :nosc]
        F = rows[[K.P0, K.P1, K.P2, K.P3, K.P4, K.P5, K.X0, K.X1]].T
        PX = np.asarray(setup.PX)
        px = PX.reshape(nblk, 2 * n, K.NB).transpose(1, 0, 2).reshape(2 * n, nblk * K.NB)
        FX = px[:, :nosc].reshape(n, 2, nosc).transpose(2, 1, 0)
        Pqq, pq, qq = setup.S_Pqq, setup.S_pq, setup.S_qq
        S = np.column_stack([Pqq.reshape(-1, 4), pq, qq])
        SX = setup.S_Pqx
        G_beta = _copy(setup.G_beta)
        if n == 0:  # the record itself: y = a_g
            G_beta[:, 0] = 1.0
        G = (setup.G_phi, setup.G_p, setup.G_q, setup.G_R, G_beta)
        b = (setup.b_phi, setup.b_p, setup.b_q, setup.b_R, setup.b_beta, setup.b_K, setup.b_m)
    return RK.Direction(
        _read_only(np.asarray(fm.acc, dtype=float)),
        _copy(F),
        _copy(FX),
        _copy(S),
        _copy(SX),
        *(_copy(x) for x in G),
        *(_copy(x) for x in b[:5]),
        int(b[5]),
        int(b[6]),
        _copy(fm.R),
        _copy(fm.beta),
        int(fm.order),
    )


def rotd_spectrum(
    acc,
    dt: float | None = None,
    periods=None,
    damping=0.05,
    *,
    building=None,
    floor: int | None = None,
    angles: int = 180,
    method: str = "exact",
    directions: bool = True,
) -> RotDSpectrum:
    """RotD50 and RotD100 spectra (Boore 2010) of two horizontal components, on the ground or on
    a building's floor, with the ordinary spectra of each direction beside them.

    Parameters
    ----------
    acc
        The two horizontal ground components: a :class:`~floorslide.RecordPair`, ``(a_x, a_y)``
        or an array ``(2, npts)``, m/s² (components of different lengths are padded with zeros
        to the longer one, and ``notes`` says so: :func:`floorslide.pair.make_pair`).
    dt
        Time step, s (with arrays).
    periods
        Oscillator periods (s, list; 0 gives the peaks of the motion itself) or
        ``{"min", "max", "n"}``; required; the limits of :func:`response_spectrum`.
    damping
        Damping ratio or ratios.
    building, floor
        The spectra of `floor`: one linear building for both directions, or a
        :class:`~floorslide.BuildingPair` (a model per direction; uncoupled, no torsion); each
        direction's floor motion is its building's exact response to that component.
    angles
        Number ``n`` of angles ``θ_j = j·180°/n`` of RotD50 (Boore: 180, 1° apart); from 2 to
        :data:`MAX_ANGLES`.
    method
        ``"exact"`` (peaks inside steps) or ``"samples"`` (the same exact recurrence, peaks at
        the record's samples only: low by up to ``1 − cos(ω·dt/2)`` relative, and RotD100 is then
        the largest sampled vector).
    directions
        Also compute ``h1`` and ``h2``, the ordinary spectra of each direction's motion.

    Returns
    -------
    RotDSpectrum

    Raises
    ------
    ModelError
        Bad periods, damping, angles, method, building or floor.
    RecordError
        Bad components (:func:`floorslide.pair.make_pair`).

    Notes
    -----
    For each oscillator the responses ``q1``, ``q2`` to the two directions' motions are stepped
    exactly (on a floor together with each direction's building), and along ``θ``
    ``q_θ = q1 cos θ + q2 sin θ`` (Boore 2010). ``RotD100 = ω²·max_t |(q1, q2)|`` is the
    continuous maximum over all angles (``max_θ max_t |q_θ| = max_t max_θ |q_θ|``), found inside
    steps; ``RotD50 = ω²·median_j max_t |q_θj|``, each maximum found inside steps; at period 0
    the same of the floor acceleration ``(a1, a2)`` (RotD100: the peak of ``|a(t)|``). With
    ``n`` angles, ``max_j max_t |q_θj| ≤ RotD100/ω² ≤ max_j max_t |q_θj| / cos(90°/n)``.

    References
    ----------
    Boore, D. M. (2010). Orientation-independent, nongeometric-mean measures of seismic
    intensity from two horizontal components of motion. *Bull. Seismol. Soc. Am.* 100(4),
    1830–1835.
    Nigam, N. C., Jennings, P. C. (1969). *Bull. Seismol. Soc. Am.* 59(2), 909–922.
    """
    pair = as_pair(acc, dt)
    if periods is None:
        raise ModelError("periods are required: a list in s or {min, max, n}", "periods")
    T = period_grid(periods)
    Z = damping_ratios(damping)
    check_oscillators(T, Z, pair.dt)
    n_ang = _angle_count(angles)
    if T.size * Z.size * n_ang > MAX_VALUES:
        raise ModelError(
            f"{T.size} periods x {Z.size} damping ratios x {n_ang} angles = "
            f"{T.size * Z.size * n_ang} peaks: at most {MAX_VALUES}",
            "angles",
        )
    if method not in METHODS:
        raise ModelError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    if couples_directions(building):
        if method != "exact":
            raise ModelError(
                f"method={method!r} is not available on nonlinear isolation in the plane",
                "method",
            )
        from floorslide.spectra.poly_segments import rotd_on_poly

        motion = PlaneIsolatedMotion(building, pair.h1, pair.h2, pair.dt)
        res = rotd_on_poly(
            motion, 0 if floor is None else floor, T, Z, angles=n_ang, directions=directions
        )
        return dataclasses.replace(res, notes=tuple(pair.notes) + tuple(res.notes))
    fm1, fm2 = plane_motions(building, pair.h1, pair.h2, pair.dt, floor)
    theta = np.arange(n_ang) * (180.0 / n_ang)
    psa_angles, rotd100, angle100, time100 = _peaks(fm1, fm2, T, Z, theta, method == "exact")
    sp1 = sp2 = None
    if directions:
        sp1 = response_spectrum(fm1, periods=T, damping=Z, method=method)
        sp2 = response_spectrum(fm2, periods=T, damping=Z, method=method)
    return RotDSpectrum(
        periods=T,
        damping=Z,
        rotd50=np.median(psa_angles, axis=-1),
        rotd100=rotd100,
        angle100=angle100,
        time100=time100,
        psa_angles=psa_angles,
        angles=theta,
        h1=sp1,
        h2=sp2,
        method=method,
        notes=pair.notes,
    )


def _peaks(fm1, fm2, T, Z, theta, exact, search_all=False):
    """PSA along each angle ``(n_Z, n_T, n_angles)``, RotD100, its direction and its time
    ``(n_Z, n_T)`` from the two directions' floor motions (on one time grid)."""
    rad = np.deg2rad(theta)
    cs, sn = np.cos(rad), np.sin(rad)
    n_ang = theta.size
    up, h = fm1.substeps, fm1.h
    pos = T > 0
    Tp = np.ascontiguousarray(T[pos])
    setups = [None, None]
    if Tp.size:
        setups = [
            _kernel_data(float(h), Tp.tobytes(), np.asarray(Z, float).tobytes(), *_system(fm))
            for fm in (fm1, fm2)
        ]
    d1, d2 = _direction(fm1, setups[0]), _direction(fm2, setups[1])
    nosc = Tp.size * Z.size
    M = np.zeros((nosc, n_ang))
    R2 = np.zeros(nosc)
    W = np.zeros((nosc, 3))
    M0 = np.zeros((1, n_ang))
    R20 = np.zeros(1)
    W0 = np.zeros((1, 3))
    if nosc:
        s1, s2 = setups
        if not (np.array_equal(s1.grp, s2.grp) and np.array_equal(s1.G_m, s2.G_m)):
            raise RuntimeError("the two directions' oscillators have different sub-steps")
        rows = np.asarray(s1.C).reshape(-1, K.NCOEF, K.NB)
        bank = RK.Bank(
            _copy(s1.w),
            _copy(s1.xi),
            _copy(rows[:, K.IH0].ravel()[:nosc]),
            _copy(rows[:, K.IH1].ravel()[:nosc]),
            np.array(s1.grp, dtype=np.int64),
            np.array(s1.G_m, dtype=np.int64),
            np.maximum(s1.K_osc, s2.K_osc).astype(np.int64),
            cs,
            sn,
        )
    ST = np.zeros((nosc, 4))
    for (k0, X1), (_, X2) in zip(fm1.chunks(), fm2.chunks(), strict=True):
        X1, X2 = _read_only(X1), _read_only(X2)
        if nosc:
            RK.rotd_kernel(bank, d1, d2, X1, X2, k0, up, h, exact, search_all, ST, M, R2, W)
        if not pos.all():
            RK.rigid_kernel(d1, d2, X1, X2, k0, up, h, exact, search_all, cs, sn, M0, R20, W0)
    shape = (Z.size, T.size)
    psa_angles = np.zeros((*shape, n_ang))
    rotd100 = np.zeros(shape)
    where = np.zeros((*shape, 3))
    if nosc:
        w2 = (np.asarray(setups[0].w) ** 2).reshape(Z.size, -1)
        psa_angles[:, pos] = M.reshape(Z.size, -1, n_ang) * w2[..., None]
        rotd100[:, pos] = np.sqrt(R2).reshape(Z.size, -1) * w2
        where[:, pos] = W.reshape(Z.size, -1, 3)
    if not pos.all():
        psa_angles[:, ~pos] = M0[0]
        rotd100[:, ~pos] = np.sqrt(R20[0])
        where[:, ~pos] = W0[0]
    angle100 = np.degrees(np.arctan2(where[..., 2], where[..., 1])) % 180.0
    angle100[(rotd100 == 0) | (angle100 >= 180.0)] = 0.0
    return psa_angles, rotd100, angle100, where[..., 0]
