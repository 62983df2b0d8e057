"""Floor motions: the exact response of a building to a piecewise-linear ground record.

The default method samples the exact response (first-order hold, :mod:`floorslide.building.exact`)
and finds the true peak floor acceleration, including peaks inside steps. Approximate methods
are kept for the accuracy-versus-cost study (docs/design.md §6).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from floorslide._jit import njit
from floorslide.building._kernels import foh_outputs
from floorslide.building.exact import foh_matrices
from floorslide.building.exact_motion import building_motion, check_building, ground_peak, stepper
from floorslide.building.model import LinearBuilding
from floorslide.errors import ModelError
from floorslide.inputs import RecordLike, as_record, check_record

__all__ = ["Peaks", "check_record", "floor_motions", "peak_floor_acceleration", "stepper"]

METHODS = ("exact", "zoh", "newmark", "forced_response")


def floor_motions(
    building: LinearBuilding,
    ground_acc: RecordLike,
    dt: float | None = None,
    floors: Sequence[int] | int | None = None,
    output: str | Sequence[str] = "acceleration",
    oversample: int = 1,
    method: str = "exact",
    substeps: int = 1,
):
    """Samples of the building's response to the piecewise-linear ground record.

    Parameters
    ----------
    building
        A :class:`~floorslide.ShearBuilding` or :class:`~floorslide.IsolatedBuilding`.
    ground_acc
        Ground acceleration samples, m/s²; or an ObsPy Trace or one-trace Stream (units from
        ``stats.units``, converted to m/s² with a
        :class:`~floorslide.errors.UnitsConversionWarning` if need be; see
        :mod:`floorslide.inputs`).
    dt
        Time step of the record, s (required for samples; from ``stats.delta`` for a Trace).
    floors
        Floors (0..N, any order, repeats allowed); default all.
    output
        ``"acceleration"`` (absolute, default), ``"displacement"``, ``"velocity"``, ``"drift"``,
        ``"isolator"`` — or a list of them, in which case a dict name → array is returned.
    oversample
        Return samples at ``dt/oversample`` (of the same exact response).
    method
        ``"exact"`` (first-order hold, default); approximate: ``"zoh"`` (zero-order hold of the
        record), ``"newmark"`` (average acceleration on ``dt/substeps``), ``"forced_response"``
        (python-control's ``forced_response`` as is).
    substeps
        Sub-steps per record step for ``"newmark"``.

    Returns
    -------
    ndarray or dict
        ``(len(floors), npts)`` per output kind (``npts = (n−1)·oversample + 1``). A Trace's
        unit conversion is announced by the warning only (an array has no ``notes``).

    References
    ----------
    Van Loan (1978); Chopra (2012), §5.4 (Newmark's method).
    """
    if building is None:
        raise ModelError(
            "floor_motions needs a building (on the ground the motion is the record itself)",
            "building",
        )
    check_building(building, "floor_motions")
    a, dt, _ = as_record(ground_acc, dt, "ground_acc")
    if method not in METHODS:
        raise ModelError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    if int(oversample) != oversample or oversample < 1:
        raise ModelError(f"oversample must be an integer ≥ 1, got {oversample!r}", "oversample")
    oversample = int(oversample)
    kinds = [output] if isinstance(output, str) else list(output)
    floors = building.check_floors(floors)
    segmented = getattr(building, "segmented", False)
    if not segmented:
        C, D, _ = building.output_matrices(floors, kinds)
    if oversample > 1:
        t_old = np.arange(a.size)
        a = np.interp(np.arange((a.size - 1) * oversample + 1) / oversample, t_old, a)
        dt = dt / oversample
    if segmented:
        if method != "exact":
            raise ModelError(
                f"method={method!r} is not available on a building on nonlinear isolation (the "
                "exact method is)",
                "method",
            )
        Y = _segmented_samples(building, a, dt, floors, kinds)
    elif method == "exact":
        Y = building_motion(building, a, dt, max_bytes=0, copy=False).samples(floors, kinds)
    elif method == "zoh":
        A, B = building.state_matrices()
        phi, g0, _ = foh_matrices(A, B[:, 0], dt)
        Y = np.empty((C.shape[0], a.size))
        foh_outputs(phi, g0, np.zeros_like(g0), C, D[:, 0], a, 1, np.zeros(A.shape[0]), Y)
    elif method == "newmark":
        Y = _newmark_outputs(building, a, dt, int(substeps), C, D[:, 0])
    else:
        import control

        ss = building.state_space(floors, kinds)
        t = np.arange(a.size) * dt
        Y = np.atleast_2d(control.forced_response(ss, t, a).outputs)
    if isinstance(output, str):
        return Y
    per = len(floors)
    out, row = {}, 0
    for kind in kinds:
        rows = 1 if kind == "isolator" else per
        out[kind] = Y[row : row + rows]
        row += rows
    return out


@dataclass(frozen=True)
class Peaks:
    """True peaks of building outputs over a record, including peaks inside steps.

    Attributes
    ----------
    floors
        Floors, in the order requested.
    peak
        ``max_t |y(t)|`` per floor (m/s² for accelerations).
    time
        Time of each peak, s.
    notes
        What was done to the input record (e.g. its conversion from g to m/s²), one line each;
        empty for samples given in m/s².
    """

    floors: tuple[int, ...]
    peak: np.ndarray
    time: np.ndarray
    notes: tuple[str, ...] = ()


def peak_floor_acceleration(
    building: LinearBuilding | None,
    ground_acc: RecordLike,
    dt: float | None = None,
    floors: Sequence[int] | int | None = None,
    output: str = "acceleration",
) -> Peaks:
    """The true peak floor acceleration (PFA) of each floor, including peaks inside steps.

    Without a building the ground record itself is the motion, whose peak (piecewise linear)
    is at a sample.

    Parameters
    ----------
    building
        The building, or None for the ground.
    ground_acc
        Ground acceleration samples, m/s²; or an ObsPy Trace or one-trace Stream (see
        :mod:`floorslide.inputs`: units from ``stats.units``, converted and noted).
    dt
        Time step, s (required for samples; from ``stats.delta`` for a Trace).
    floors
        Floors (0..N); default all.
    output
        Output kind, as in :func:`floor_motions` (default absolute acceleration).

    Returns
    -------
    Peaks
        With the unit conversion of a Trace, if any, in ``notes``.
    """
    check_building(building, "peak_floor_acceleration")
    a, dt, notes = as_record(ground_acc, dt, "ground_acc")
    if building is None:
        peak, t = ground_peak(a, dt)
        return Peaks((0,), np.array([peak]), np.array([t]), notes)
    floors = building.check_floors(floors)
    if getattr(building, "segmented", False):
        if output != "acceleration":
            raise ModelError(
                "on a building on nonlinear isolation the true peaks are those of the floors' "
                "absolute accelerations (output='acceleration'); the isolator's are in "
                "isolator_response",
                "output",
            )
        motion = building.motion(a, dt, floors=sorted(set(floors)), keep_segments=False)
        peak, tpk = motion.peaks(floors)
    else:
        peak, tpk = building_motion(building, a, dt, max_bytes=0, copy=False).peaks(floors, output)
    return Peaks(tuple(floors), peak, tpk, notes)


def _segmented_samples(building, a, dt, floors, kinds) -> np.ndarray:
    """Rows of :func:`floor_motions` on a building on nonlinear isolation: the floors' absolute
    accelerations from its motion; displacements, velocities and drifts (relative to the ground)
    from its states at the samples; the isolator's displacement."""
    motion = building.motion(a, dt, floors=sorted(set(floors)), keep_segments=False)
    X = motion.states  # at the samples: [u (n); u' (n); F0]
    n = building.n_dof
    rows = []
    for kind in kinds:
        if kind == "isolator":
            rows.append(X[:, 0])
            continue
        if kind not in ("acceleration", "displacement", "velocity", "drift"):
            raise ModelError(
                f"unknown output {kind!r}; expected one of acceleration, displacement, "
                "velocity, drift, isolator",
                "outputs",
            )
        for f in floors:
            if kind == "acceleration":
                rows.append(motion.samples([f])[0])
            elif kind == "displacement":
                rows.append(X[:, f])
            elif kind == "velocity":
                rows.append(X[:, n + f])
            else:
                if f == 0:
                    raise ModelError(
                        "drift is defined for floors 1..N (the storey below the floor)", "outputs"
                    )
                rows.append(X[:, f] - X[:, f - 1])
    return np.array(rows).reshape(len(rows), a.size)


def _newmark_outputs(building, a, dt, substeps, C, D):
    if substeps < 1:
        raise ModelError(f"substeps must be ≥ 1, got {substeps}", "substeps")
    M = np.diag(building.mass)
    h = dt / substeps
    Keff = building.stiffness_matrix + 2.0 / h * building.damping_matrix + 4.0 / h**2 * M
    Kinv = np.linalg.inv(Keff)
    Y = np.empty((C.shape[0], a.size))
    _newmark_kernel(
        building.mass,
        building.damping_matrix,
        building.stiffness_matrix,
        Kinv,
        a,
        h,
        substeps,
        C,
        D,
        Y,
    )
    return Y


@njit(cache=True)
def _newmark_kernel(m, Cd, K, Kinv, acc, h, substeps, C, D, Y):
    """Newmark average acceleration (γ = 1/2, β = 1/4) on sub-steps, incremental form
    (Chopra 2012, Table 5.4.2); ground acceleration interpolated linearly."""
    n = m.size
    u = np.zeros(n)
    v = np.zeros(n)
    acc_rel = np.zeros(n)
    # initial relative acceleration: M ü = -M a_g - C v - K u
    for i in range(n):
        acc_rel[i] = -acc[0]
    rhs = np.empty(n)
    du = np.empty(n)
    npts = acc.size
    for k in range(npts):
        ag = acc[k]
        for r in range(C.shape[0]):
            s = D[r] * ag
            for j in range(n):
                s += C[r, j] * u[j] + C[r, n + j] * v[j]
            Y[r, k] = s
        if k == npts - 1:
            break
        a1 = acc[k + 1]
        for sub in range(substeps):
            ga = ag + (a1 - ag) * (sub / substeps)
            gb = ag + (a1 - ag) * ((sub + 1) / substeps) if sub + 1 < substeps else a1
            dp = -(gb - ga)
            for i in range(n):
                rhs[i] = m[i] * dp + m[i] * (4.0 / h * v[i] + 2.0 * acc_rel[i])
                s = 0.0
                for j in range(n):
                    s += Cd[i, j] * (2.0 * v[j])
                rhs[i] += s
            for i in range(n):
                s = 0.0
                for j in range(n):
                    s += Kinv[i, j] * rhs[j]
                du[i] = s
            for i in range(n):
                dv = 2.0 / h * du[i] - 2.0 * v[i]
                u[i] += du[i]
                v[i] += dv
            # equilibrium acceleration at the end of the sub-step
            for i in range(n):
                s = 0.0
                for j in range(n):
                    s += Cd[i, j] * v[j] + K[i, j] * u[j]
                acc_rel[i] = -gb - s / m[i]
