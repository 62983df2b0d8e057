"""One task: a record on a building — floor peaks, sliding contents, floor spectra.

A pure function of its input (the planner's :class:`~floorslide.scene.planner.Task`, which
carries the record's samples), so it runs the same in this process, a local worker process or
a Dask worker, and gives the same numbers bit for bit.
"""

from __future__ import annotations

import time
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from floorslide.building.exact_motion import building_motion
from floorslide.building.isolators import small_angle_note
from floorslide.contents.coupled import slide_coupled
from floorslide.contents.oscillator import slide_oscillator
from floorslide.contents.slide_rock import slide_rock
from floorslide.contents.sliding import slide
from floorslide.errors import FloorslideError, NonFiniteError
from floorslide.run.results import ContentResult, Histories, SpectrumResult, TaskResult
from floorslide.scene.planner import Task, decide
from floorslide.spectra.core import broaden, response_spectrum

HISTORY_MU = 3
"""Friction values per content whose slide histories are kept for figures."""


def _meta(task: Task) -> dict:
    b, r = task.building, task.record
    return dict(
        record_set=r.set,
        record=r.record,
        record_file=r.label,
        building=b.id,
        building_base=b.base,
        building_kind=b.kind,
        stories=b.stories,
        isolation_period=b.period if b.kind == "isolated" else float("nan"),
        isolation_damping=b.damping if b.kind == "isolated" else float("nan"),
        superstructure=b.superstructure,
        fixed_period=b.period if b.kind == "fixed" else b.super_period,
        dt=r.dt,
        npts=int(r.acc.size),
        pga=float(np.abs(r.acc).max())
        if r.acc2 is None
        else float(max(np.abs(r.acc).max(), np.abs(r.acc2).max())),
        components=1 if r.acc2 is None else 2,
        component_names=",".join(r.components),
        scale=r.scale,
        qa_flags=r.qa_flags,
    )


def isolator_parameters(model) -> dict[str, float]:
    """The parameters of a nonlinear isolation layer as task attributes.

    Parameters
    ----------
    model
        A :class:`~floorslide.building.nonlinear.NonlinearIsolatedBuilding`.

    Returns
    -------
    dict
        ``isolator_capacity`` (m, NaN when none is given) and, for a lead-rubber layer,
        ``isolator_q_ratio`` (Q/W), ``isolator_yield_disp`` (D_y, m) and ``isolator_alpha``
        (k₂/k₁) — both of the last two whichever was given —, for a friction pendulum
        ``isolator_mu``, ``isolator_mu_s`` (the breakaway coefficient used, ≥ mu) and
        ``isolator_radius`` (R, m).
    """
    c = model.constants
    cap = model.isolator.capacity
    out = {"isolator_capacity": float("nan") if cap is None else float(cap)}
    if model.kind == "bilinear":
        out.update(
            isolator_q_ratio=float(model.isolator.q_ratio),
            isolator_yield_disp=float(c["D_y"]),
            isolator_alpha=float(c["k2"] / c["k1"]),
        )
    else:
        out.update(
            isolator_mu=float(c["mu"]),
            isolator_mu_s=float(c["mu_s"]),
            isolator_radius=float(c["R"]),
        )
    return out


@dataclass(frozen=True)
class TaskFailure:
    """A task that could not be computed (a solver at its event limit, a non-finite state):
    what a run reports instead of its result — the task is left out of the result file (which
    stays INCOMPLETE) and the run goes on with the others (docs/design.md §9)."""

    task_id: str
    message: str
    """One line naming the record, the building and, where one is at fault, the object."""


def task_label(task: Task) -> str:
    """``record NAME (SET) on building ID``: how warnings and failures name a task."""
    return f"record {task.record.record} ({task.record.set}) on building {task.building.id}"


@contextmanager
def _naming(what: str):
    """Prefix `what` (the object or layer being computed) to a floorslide error raised inside,
    so that a task's failure says which object it was."""
    try:
        yield
    except FloorslideError as exc:
        exc.args = (f"{what}: {exc}",)
        raise


def attempt_task(task: Task, force: bool = False) -> TaskResult | TaskFailure:
    """:func:`run_task`, with an error a user can act on (a :class:`~floorslide.errors.
    FloorslideError`: a solver's event limit, a non-finite state) turned into a
    :class:`TaskFailure` naming the task, so that one task never stops a study."""
    try:
        return run_task(task, force)
    except FloorslideError as exc:
        return TaskFailure(task.task_id, f"{task_label(task)}: {exc}")


def task_warnings(result: TaskResult) -> list[str]:
    """One line per thing a user should not miss in a finished task, naming its record and
    building: an isolator beyond its capacity, or a friction pendulum beyond its small-angle
    model (:func:`floorslide.building.isolators.small_angle_exceeded`). The same flags are
    stored in the task's attributes and listed by the tables."""
    m = result.meta
    if "isolator_peak_displacement" not in m:
        return []
    where = f"record {m['record']} ({m['record_set']}) on building {m['building']}"
    peak = float(m["isolator_peak_displacement"])
    out = []
    if m.get("isolator_capacity_exceeded"):
        out.append(
            f"{where}: isolator displacement {peak:.4g} m exceeds its capacity "
            f"{float(m['isolator_capacity']):g} m (the impact that would follow is not modelled)"
        )
    if m.get("isolator_small_angle_exceeded"):
        out.append(f"{where}: {small_angle_note(peak, float(m['isolator_radius']))}")
    return out


ROCKS = ("rock", "slide-rock")
"""Shenton modes in which an object with a geometry is simulated as one slide–rock block
(:func:`floorslide.slide_rock`), once per friction pair: it rocks while friction holds its
corner and slides while it rocks once the friction it needs exceeds ``mu_s``."""


def rocking_results(content, modes, mu, mu_s, arrays, rocker) -> dict:
    """The rocking arrays of a content on one floor (:class:`~floorslide.run.results.
    ContentResult`), one entry per friction pair, what it did (``outcomes``), and the slide of
    each friction pair that rocks, written into its sliding `arrays`.

    Parameters
    ----------
    content
        The :class:`~floorslide.scene.schema.ContentSpec` (without a width and height, no
        rocking: empty dict).
    modes
        Shenton's mode per friction pair (:func:`~floorslide.scene.planner.decide`).
    mu, mu_s
        The kinetic and static friction per pair.
    arrays
        ``(peak, residual, peak_acc, fraction, slips, rocks)`` from :func:`_slide_arrays`:
        where the object rocks (Shenton's ``rock`` or ``slide-rock``) they are filled from the
        simulation — peak and residual slide (signed ``U(end)``), the fraction of the record
        spent sliding (``(time in slide + time in slide–rock)/duration``); the object's peak
        acceleration is the floor's PFA where it stayed at rest and NaN otherwise (not tracked
        for a block that rocks), its slip phases 0 at rest and −1 otherwise (not counted).
    rocker
        ``rocker(index) → SlideRockResult`` of the blocks of the content's geometry on the
        floor under friction pairs `index` (called at most once, with every pair that rocks).

    Returns
    -------
    dict
        ``rock_peak_ratio``, ``rock_impacts``, ``rock_significant_impacts``,
        ``rock_time`` (time rocking, with or without sliding), ``slide_rock_time`` (time
        sliding and rocking at once), ``overturned``, ``overturn_time``, ``outcomes`` (the
        simulation's mode: rest, slide, rock, slide-rock or overturn) and, when it was
        simulated, the :class:`~floorslide.SlideRockResult` under ``"result"`` and the friction
        pairs it holds under ``"index"``. Where the object slides (Shenton's ``slide``) the
        rocking arrays are NaN (−1 impacts), its slide-rock time 0 (a block with
        ``mu_s < B/H`` never tips) and the outcome ``slide``; where it stays at rest (the
        floor's true peak never reaches ``g·B/H``) they are zero, the exact answer, without a
        simulation.
    """
    if content.width is None:
        return {}
    n = len(modes)
    out = dict(
        rock_peak_ratio=np.full(n, np.nan),
        rock_impacts=np.full(n, -1, dtype=np.int64),
        rock_significant_impacts=np.full(n, -1, dtype=np.int64),
        rock_time=np.full(n, np.nan),
        slide_rock_time=np.zeros(n),
        overturned=np.full(n, np.nan),
        overturn_time=np.full(n, np.nan),
    )
    outcomes = list(modes)
    rest = np.array([m == "rest" for m in modes])
    for name in (
        "rock_peak_ratio",
        "rock_impacts",
        "rock_significant_impacts",
        "rock_time",
        "overturned",
    ):
        out[name][rest] = 0
    rocks = np.array([i for i, m in enumerate(modes) if m in ROCKS], dtype=np.int64)
    if rocks.size:
        r = rocker(rocks)
        peak, resid, acc_obj, frac, slips = arrays[:5]
        out["rock_peak_ratio"][rocks] = r.peak_ratio
        out["rock_impacts"][rocks] = r.impacts
        out["rock_significant_impacts"][rocks] = r.significant_impacts
        out["rock_time"][rocks] = r.mode_time[:, 2] + r.mode_time[:, 3]
        out["slide_rock_time"][rocks] = r.mode_time[:, 3]
        out["overturned"][rocks] = r.overturned.astype(float)
        out["overturn_time"][rocks] = r.overturn_time
        peak[rocks], resid[rocks] = r.peak_slide, r.residual_slide
        frac[rocks] = (r.mode_time[:, 1] + r.mode_time[:, 3]) / r.duration if r.duration > 0 else 0
        still = np.array([m == "rest" for m in r.mode])
        acc_obj[rocks] = np.where(still, acc_obj[rocks], np.nan)
        slips[rocks] = np.where(still, 0, -1)
        for j, i in enumerate(rocks):
            outcomes[i] = r.mode[j]
        out["result"], out["index"] = r, rocks
    out["outcomes"] = np.array(outcomes)
    return out


def _severest(r) -> int:
    """Of the blocks of a :class:`~floorslide.SlideRockResult`, the one whose rotation history
    the history record keeps: the first to overturn, else the largest peak rotation."""
    if r.overturned.any():
        return int(np.nanargmin(np.where(r.overturned, r.overturn_time, np.inf)))
    return int(np.argmax(r.peak_ratio))


def _slide_rocker(fm, content, mu, mu_s, histories):
    """``rocker(index)`` for :func:`rocking_results`: slide–rock blocks of the content's
    geometry and restitution under friction pairs `index` on the floor motion `fm` (a
    :class:`~floorslide.FloorMotion`, a nonlinear one, or a ``PolyComponent``)."""

    def rocker(index):
        return slide_rock(fm, None, content.width, content.height, mu[index], mu_s=mu_s[index],
                          restitution=content.restitution, histories=histories)  # fmt: skip

    return rocker


def _frictions(content) -> tuple[np.ndarray, np.ndarray]:
    """A content's kinetic and static friction coefficients, one per object (the static ones
    default to the kinetic)."""
    mu = np.asarray(content.mu, dtype=float)
    return mu, np.asarray(content.mu_s if content.mu_s else content.mu, dtype=float)


def _slide_arrays(n: int, pfa: float, modes) -> tuple[np.ndarray, ...]:
    """A content's sliding arrays on a floor before anything is integrated: no slide and the
    floor's PFA (the exact answer of an object that does not slide), NaN (−1 slip phases)
    where it rocks (Shenton's ``rock`` or ``slide-rock``: :func:`rocking_results` fills them
    from its slide–rock simulation). Returns ``(peak, residual, peak_acc, fraction, slips,
    rocks)``."""
    peak, resid, frac = np.zeros(n), np.zeros(n), np.zeros(n)
    acc_obj = np.full(n, pfa)
    slips = np.zeros(n, dtype=np.int64)
    rocks = np.array([m in ROCKS for m in modes], dtype=bool)
    for arr in (peak, resid, acc_obj, frac):
        arr[rocks] = np.nan
    slips[rocks] = -1
    return peak, resid, acc_obj, frac, slips, rocks


def _content_result(content, floor, modes, reasons, mu, mu_s, arrays, **extra) -> ContentResult:
    """The :class:`ContentResult` of a content on a floor: its sliding `arrays` (as from
    :func:`_slide_arrays`, filled), the common mode (or ``mixed``) and the skip reasons."""
    peak, resid, acc_obj, frac, slips = arrays[:5]
    return ContentResult(
        content=content.id,
        floor=floor,
        model=content.model,
        mode=modes[0] if len(set(modes)) == 1 else "mixed",
        skipped="; ".join(f"{k} ({v})" for k, v in reasons.items()),
        mu_k=mu,
        mu_s=mu_s,
        peak_slide=peak,
        residual_slide=resid,
        peak_abs_accel=acc_obj,
        slide_fraction=frac,
        slip_phases=slips,
        vertical=content.vertical,
        modes=np.array(modes),
        **extra,
    )


def run_task(task: Task, force: bool = False) -> TaskResult:
    """Compute everything `task` asks for (see the planner for the skip rules).

    Raises
    ------
    NonFiniteError
        A result that must be a number (a floor's PFA, a spectrum, an isolator's peak, a slide
        or rotation) is NaN or infinite: the solvers overflowed (docs/design.md §9).
    """
    result = _run(task, force)
    _check_finite(result)
    return result


def _check_finite(result: TaskResult) -> None:
    """Every number a task computes is finite — except the NaN that mean "not this kind of
    result" (a rocker's slide, a slider's rotation, an oscillator's deformation on a rigid
    block, no overturning): the PFA, spectra and isolator peaks are finite, and no array holds
    an infinity. A solver that overflowed says so instead of writing NaN or zeros."""
    bad = []
    if not np.all(np.isfinite(result.pfa)):
        bad.append("the floors' PFA")
    for key in ("isolator_peak_displacement", "isolator_peak_force_ratio"):
        if key in result.meta and not np.isfinite(result.meta[key]):
            bad.append(key)
    for sp in result.spectra:
        if not all(np.all(np.isfinite(getattr(sp, k))) for k in ("psa", "sd")):
            bad.append(f"the floor spectrum of floor {sp.floor}")
    for c in result.contents:
        for name, value in vars(c).items():
            if isinstance(value, np.ndarray) and value.dtype.kind == "f" and np.isinf(value).any():
                bad.append(f"{name} of content {c.content} on floor {c.floor}")
    if bad:
        raise NonFiniteError(f"not finite (the solvers overflowed): {', '.join(bad)}", "task")


def _run(task: Task, force: bool) -> TaskResult:
    t0 = time.perf_counter()
    rec = task.record
    acc, dt = rec.acc, rec.dt
    if rec.is_pair:
        return _run_pair(task, force, t0)
    model = task.building.build()
    floors = np.array(task.floors, dtype=np.int64)
    # the building integrated once for this record — on linear or nonlinear isolation alike:
    # every floor peak, content, spectrum and history below reads this motion
    motion = building_motion(model, acc, dt)
    pfa = motion.peaks(list(task.floors))[0] if floors.size else np.zeros(0)
    pfa_of = dict(zip(task.floors, pfa, strict=True))
    meta = _meta(task)
    iso = getattr(motion, "response", None)  # the isolator's own outputs (nonlinear isolation)
    if iso is not None:
        meta.update(
            isolator=task.building.isolator_model,
            **isolator_parameters(model),
            isolator_peak_displacement=iso.peak_displacement,
            isolator_residual_displacement=iso.residual_displacement,
            isolator_peak_force_ratio=iso.peak_force_ratio,
            isolator_capacity_exceeded=int(iso.capacity_exceeded),
            isolator_small_angle_exceeded=int(iso.small_angle_exceeded),
        )
    result = TaskResult(task.task_id, meta, floors, np.asarray(pfa, dtype=float))
    hist_slides, hist_mu, hist_deform, hist_top, hist_rock = {}, {}, {}, {}, {}

    def heavy(content) -> bool:
        return content.floor_mass_ratio is not None and content.coupled

    def heavy_mass(content, floor: int) -> float:
        """The block's mass in the model's units: its ratio times its floor's mass (the floor's
        degree of freedom: a nonlinear building's are its floors, the mat first)."""
        return content.floor_mass_ratio * float(model.mass[model.dof_of(floor)])

    for content, floor in task.contents:
        with _naming(f"content {content.id} on floor {floor}"):
            mu, mu_s = _frictions(content)
            # the skip rule below the breakaway level is the building's alone: heavy equipment
            # changes its floor's motion, so it is always integrated
            modes, integrate, reasons = decide(content, pfa_of[floor], force or heavy(content))
            n = mu.size
            arrays = _slide_arrays(n, pfa_of[floor], modes)
            peak, resid, acc_obj, frac, slips, rocks = arrays
            deform = top = None
            idx = np.nonzero(integrate)[0]
            fm = motion.floor(floor)
            if content.model == "oscillator":
                deform = np.full(n, np.nan)
                top = np.full(n, np.nan)
                if idx.size:
                    r = slide_oscillator(
                        fm,
                        None,
                        mu[idx],
                        content.frequency,
                        content.damping,
                        content.mass_ratio,
                        mu_s=mu_s[idx],
                    )
                    peak[idx], resid[idx] = r.peak_slide, r.residual_slide
                    acc_obj[idx], frac[idx], slips[idx] = (
                        r.peak_base_accel,
                        r.slide_fraction,
                        r.slip_phases,
                    )
                    deform[idx], top[idx] = r.peak_deformation, r.peak_top_accel
            elif heavy(content):
                # heavy equipment acting back on its floor: integrated with the building (its
                # own run; every friction pair that does not rock, see decide above)
                coupled_pfa = np.full(n, np.nan)
                if idx.size:
                    r = slide_coupled(rec.acc, dt, mu[idx], mass=heavy_mass(content, floor),
                                      building=model, floor=floor, mu_s=mu_s[idx])  # fmt: skip
                    peak[idx], resid[idx] = r.peak_slide, r.residual_slide
                    acc_obj[idx], frac[idx] = r.peak_abs_accel, r.slide_fraction
                    slips[idx] = r.slip_phases
                    coupled_pfa[idx] = r.pfa
            elif idx.size:
                vert = rec.vertical if content.vertical else None
                r = slide(fm, None, mu[idx], mu_s[idx], vertical=vert, direction=content.direction)
                peak[idx], resid[idx] = r.peak_slide, r.residual_slide
                acc_obj[idx], frac[idx], slips[idx] = (
                    r.peak_abs_accel,
                    r.slide_fraction,
                    r.slip_phases,
                )
            rocking = rocking_results(
                content, modes, mu, mu_s, arrays,
                _slide_rocker(fm, content, mu, mu_s, task.histories),
            )  # fmt: skip
            rock_result = rocking.pop("result", None)
            rock_index = rocking.pop("index", None)
            extra = dict(peak_deformation=deform, peak_top_accel=top, **rocking)
            if heavy(content):
                extra["coupled_pfa"] = coupled_pfa
            result.contents.append(
                _content_result(content, floor, modes, reasons, mu, mu_s, arrays, **extra)
            )
            if task.histories and rock_result is not None:
                j = _severest(rock_result)
                hist_rock[f"{content.id}/floor_{floor}"] = (
                    rock_result.theta[j] / rock_result.alpha[j]
                )
            if task.histories:
                pick = np.unique(np.linspace(0, n - 1, min(HISTORY_MU, n)).round().astype(int))
                key = f"{content.id}/floor_{floor}"
                if content.model == "oscillator":
                    r = slide_oscillator(
                        fm,
                        None,
                        mu[pick],
                        content.frequency,
                        content.damping,
                        content.mass_ratio,
                        mu_s=mu_s[pick],
                        histories=True,
                    )
                    hist_deform[key], hist_top[key] = r.z, r.top_accel
                elif heavy(content):
                    r = slide_coupled(rec.acc, dt, mu[pick], mass=heavy_mass(content, floor),
                                      building=model, floor=floor, mu_s=mu_s[pick],
                                      histories=True)  # fmt: skip
                else:
                    r = slide(
                        fm,
                        None,
                        mu[pick],
                        mu_s[pick],
                        histories=True,
                        direction=content.direction,
                        vertical=rec.vertical if content.vertical else None,
                    )
                hist_slides[key], hist_mu[key] = r.u, mu[pick]
                # an object that rocks is not a slider: its slide history is its slide–rock
                # block's U (an oscillator's deformation and top acceleration are NaN there)
                for arr in (hist_slides.get(key), hist_deform.get(key), hist_top.get(key)):
                    if arr is not None:
                        arr[rocks[pick]] = np.nan
                if key in hist_slides and rock_result is not None:
                    where = {int(i): j for j, i in enumerate(rock_index)}
                    for row, i in enumerate(pick):
                        if int(i) in where:
                            hist_slides[key][row] = rock_result.slide[where[int(i)]]
    sc = task.spectra
    for floor in task.spectra_floors:
        with _naming(f"floor spectrum of floor {floor}"):
            sp = response_spectrum(
                motion.floor(floor), None, np.asarray(sc.periods), list(sc.damping)
            )
            out = SpectrumResult(floor, sp.periods, sp.damping, sp.psa, sp.sa, sp.sv, sp.sd)
            _broadened(out, sp, sc.broadening)
            result.spectra.append(out)
    if task.histories:
        fl = np.array(task.floors, dtype=np.int64)
        motions = motion.samples(list(task.floors)) if fl.size else np.zeros((0, acc.size))
        bearing = {}
        if iso is not None:
            bearing = dict(
                isolator_displacement=iso.isolator_displacement,
                isolator_force_ratio=iso.isolator_force / model.weight,
            )
        result.histories = Histories(
            dt, fl, motions, hist_slides, hist_mu, hist_deform, hist_top, rocking=hist_rock,
            **bearing,
        )  # fmt: skip
    result.seconds = time.perf_counter() - t0
    return result


def _worse_rocking(a, b):
    """Of blocks sliding and rocking along the two components (two
    :class:`~floorslide.SlideRockResult` of the same blocks), per block the more severe: the
    one that overturned (the earlier, if both), else the larger peak rotation."""
    from dataclasses import fields, replace

    both = a.overturned & b.overturned
    take_a = np.where(
        both,
        a.overturn_time <= b.overturn_time,
        np.where(a.overturned != b.overturned, a.overturned, a.peak_ratio >= b.peak_ratio),
    )
    picked = {}
    for f in fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray) and x.ndim >= 1 and x.shape[0] == take_a.size:
            mask = take_a.reshape((-1,) + (1,) * (x.ndim - 1))
            picked[f.name] = np.where(mask, x, y)
        elif f.name in ("mode", "sequence"):
            picked[f.name] = tuple(u if t else v for u, v, t in zip(x, y, take_a, strict=True))
    return replace(a, **picked)


def _run_pair(task: Task, force: bool, t0: float) -> TaskResult:
    """A task of a pair of horizontal components (docs/design.md §10d): rigid blocks slide in
    the plane (:func:`floorslide.slide_plane`), beside each component's 1-D slide; a floor's
    PFA is the true peak of its acceleration vector (:func:`~floorslide.building.directions.
    plane_peak`), its per-direction peaks are kept too; a block that rocks rocks in the plane of
    each component (its faces along them), and the more severe of the two is reported.

    On nonlinear isolation the building is integrated once, coupled in the plane
    (:class:`~floorslide.building.plane_isolation.PlaneIsolatedMotion`, its segments recorded
    on its one pass and kept): every floor peak
    (:func:`~floorslide.building.poly_peaks.poly_peaks`), block,
    rocker, spectrum and history reads that one motion, and the bearing's outputs (peak
    displacement and direction, residual vector, peak force over W) go into the task's
    attributes (docs/design.md §10b)."""
    from floorslide.building.directions import plane_motions, plane_peak
    from floorslide.building.plane_isolation import PlaneIsolatedMotion, couples_directions
    from floorslide.building.poly_peaks import KeptPolyMotion, PolyComponent, poly_peaks
    from floorslide.building.poly_segments import (
        GroundPolyMotion,
        LinearPolyMotion,
        samples_on_poly,
    )
    from floorslide.constants import G
    from floorslide.contents.plane import slide_plane
    from floorslide.contents.plane_oscillator import slide_oscillator_plane_on_segments
    from floorslide.contents.plane_segments import slide_plane_on_segments

    rec = task.record
    dt = rec.dt
    model = task.building.build_plane()
    floors = list(task.floors)
    meta = _meta(task)
    coupled = None
    if couples_directions(model):
        coupled = PlaneIsolatedMotion(model, rec.acc, rec.acc2, dt, keep_segments=True)
        peaks = poly_peaks(coupled, floors)
        pfa, per_dir = peaks.peak, peaks.components
        iso = coupled.response
        bx = coupled.building[0]
        meta.update(
            isolator=task.building.isolator_model,
            **isolator_parameters(bx),
            isolator_peak_displacement=iso.peak_displacement,
            isolator_peak_direction=iso.peak_direction,
            isolator_residual_displacement=float(np.hypot(*iso.residual)),
            isolator_residual_h1=float(iso.residual[0]),
            isolator_residual_h2=float(iso.residual[1]),
            isolator_peak_force_ratio=iso.peak_force_ratio,
            isolator_capacity_exceeded=int(iso.capacity_exceeded),
            isolator_small_angle_exceeded=int(iso.small_angle_exceeded),
        )
    else:
        motions = {f: plane_motions(model, rec.acc, rec.acc2, dt, f) for f in floors}
        pfa = np.array([plane_peak(*motions[f])[0] for f in floors])
        per_dir = np.array([[fm.peak()[0] for fm in motions[f]] for f in floors]).reshape(-1, 2)
    pfa_of = dict(zip(floors, pfa, strict=True))
    result = TaskResult(task.task_id, meta, np.array(floors, dtype=np.int64), pfa)
    result.pfa_components = per_dir

    def plane_slide(mu_k, mu_s, floor, vert, **kw):
        if coupled is not None:
            return slide_plane_on_segments(coupled, floor, mu_k, mu_s, vertical=vert, **kw)
        return slide_plane((rec.acc, rec.acc2), dt, mu_k, mu_s, building=model,
                           floor=floor if model is not None else None, vertical=vert,
                           **kw)  # fmt: skip

    def components(floor):
        if coupled is not None:
            return PolyComponent(coupled, floor, 0), PolyComponent(coupled, floor, 1)
        return motions[floor]

    poly = [coupled]

    def plane_oscillators(content, floor, mu_k, mu_s, histories=False):
        """2-DOF oscillators in the plane on the task's poly motion (made once: the coupled
        one, or the ground's or linear building's own, kept in memory)."""
        if poly[0] is None:
            if model is None:
                poly[0] = GroundPolyMotion(rec.acc, rec.acc2, dt)
            else:
                poly[0] = KeptPolyMotion(
                    LinearPolyMotion(model, rec.acc, rec.acc2, dt, floors=sorted(set(floors)))
                )
        return slide_oscillator_plane_on_segments(
            poly[0], floor if model is not None else None, mu_k, mu_s,
            frequency=content.frequency, damping=content.damping,
            mass_ratio=content.mass_ratio, histories=histories,
        )  # fmt: skip

    hist_slides, hist_mu, hist_plane, hist_rock = {}, {}, {}, {}
    hist_deform, hist_top = {}, {}
    for content, floor in task.contents:
        with _naming(f"content {content.id} on floor {floor}"):
            mu, mu_s = _frictions(content)
            modes, integrate, reasons = decide(content, pfa_of[floor], force)
            n = mu.size
            arrays = _slide_arrays(n, pfa_of[floor], modes)
            peak, resid, acc_obj, frac, slips, rocks = arrays
            angle, r1, r2 = np.full(n, np.nan), np.zeros(n), np.zeros(n)
            one_d = np.zeros((n, 2))
            ratio = np.full(n, np.nan)
            for arr in (r1, r2, one_d):
                arr[rocks] = np.nan
            idx = np.nonzero(integrate)[0]
            vert = rec.vertical if content.vertical else None
            oscillator = content.model == "oscillator"
            deform = top = None
            if oscillator:
                # flexible equipment in the plane: its base's peak acceleration is not tracked
                # (NaN), nor its 1-D comparison
                deform, top = np.full(n, np.nan), np.full(n, np.nan)
                one_d[:] = np.nan
                if idx.size:
                    r = plane_oscillators(content, floor, mu[idx], mu_s[idx])
                    peak[idx], frac[idx] = r.peak_slide, r.slide_fraction
                    slips[idx] = r.slip_phases
                    resid[idx] = np.hypot(r.residual[:, 0], r.residual[:, 1])
                    r1[idx], r2[idx] = r.residual[:, 0], r.residual[:, 1]
                    angle[idx] = r.peak_angle
                    acc_obj[idx] = np.nan
                    deform[idx], top[idx] = r.peak_deformation, r.peak_top_accel
            elif idx.size:
                r = plane_slide(mu[idx], mu_s[idx], floor, vert)
                peak[idx], frac[idx], slips[idx] = r.peak_slide, r.slide_fraction, r.slip_phases
                resid[idx] = np.hypot(r.residual[:, 0], r.residual[:, 1])
                r1[idx], r2[idx] = r.residual[:, 0], r.residual[:, 1]
                angle[idx] = r.peak_angle
                one_d[idx] = r.peak_slide_1d
                ratio[idx] = r.ratio_2d_1d
                # a block in the plane is stuck while |a| ≤ mu_b g and slides at mu_k g ≤ mu_b g:
                # once it has broken away its peak acceleration is the breakaway level (with
                # vertical shaking the friction limit varies: not known in closed form, NaN)
                slid = r.slip_phases > 0
                acc_obj[idx[slid]] = np.minimum(
                    pfa_of[floor], np.maximum(mu[idx], mu_s[idx])[slid] * G
                )
                if vert is not None:
                    acc_obj[idx[slid]] = np.nan

            fms = components(floor)
            along = {}

            def rocker(index, fms=fms, content=content, mu=mu, mu_s=mu_s, along=along):
                # a block rocks in the plane of each component (its faces along them): both
                # simulated, the more severe kept; each component's slide beside
                a, b = (_slide_rocker(f, content, mu, mu_s, task.histories)(index) for f in fms)
                along.update(h1=a.peak_slide, h2=b.peak_slide)
                return _worse_rocking(a, b)

            rocking = rocking_results(content, modes, mu, mu_s, arrays, rocker)
            rock_result = rocking.pop("result", None)
            rock_index = rocking.pop("index", None)
            if rock_index is not None:
                # the kept block slides along one component: |U(end)| (its direction in the
                # plane, and so residual_h1/_h2 and peak_angle, are not known: NaN)
                resid[rock_index] = np.abs(resid[rock_index])
                one_d[rock_index, 0], one_d[rock_index, 1] = along["h1"], along["h2"]
            result.contents.append(
                _content_result(
                    content,
                    floor,
                    modes,
                    reasons,
                    mu,
                    mu_s,
                    arrays,
                    peak_angle=angle,
                    residual_h1=r1,
                    residual_h2=r2,
                    peak_slide_h1=one_d[:, 0].copy(),
                    peak_slide_h2=one_d[:, 1].copy(),
                    ratio_2d_1d=ratio,
                    peak_deformation=deform,
                    peak_top_accel=top,
                    **rocking,
                )
            )
            key = f"{content.id}/floor_{floor}"
            if task.histories and rock_result is not None:
                j = _severest(rock_result)
                hist_rock[key] = rock_result.theta[j] / rock_result.alpha[j]
            if task.histories:
                pick = np.unique(np.linspace(0, n - 1, min(HISTORY_MU, n)).round().astype(int))
                if oscillator:
                    r = plane_oscillators(content, floor, mu[pick], mu_s[pick], histories=True)
                    zh = np.hypot(r.z[:, :, 0], r.z[:, :, 1])
                    zh[rocks[pick]] = np.nan
                    hist_deform[key] = zh
                    # the top's acceleration history is not kept in the plane: NaN
                    hist_top[key] = np.full_like(zh, np.nan)
                else:
                    r = plane_slide(mu[pick], mu_s[pick], floor, vert, histories=True,
                                    compare_1d=False)  # fmt: skip
                u = r.u
                u[rocks[pick]] = np.nan
                hist_plane[key] = u
                hist_slides[key] = np.hypot(u[:, :, 0], u[:, :, 1])
                hist_mu[key] = mu[pick]
    for floor in task.spectra_floors:
        with _naming(f"floor spectrum of floor {floor}"):
            result.spectra.append(_pair_spectrum(task, model, floor, coupled))
    if task.histories:
        fl = np.array(floors, dtype=np.int64)
        bearing = {}
        if coupled is not None:
            both = samples_on_poly(coupled, floors).reshape(len(floors), 2, rec.acc.size)
            acc1, acc2 = both[:, 0].copy(), both[:, 1].copy()
            iso = coupled.response
            bearing = dict(
                isolator_displacement=iso.displacement[:, 0].copy(),
                isolator_force_ratio=iso.force_ratio[:, 0].copy(),
                isolator_displacement_h2=iso.displacement[:, 1].copy(),
                isolator_force_ratio_h2=iso.force_ratio[:, 1].copy(),
            )
        else:
            acc1 = np.array([motions[f][0].samples() for f in floors]).reshape(-1, rec.acc.size)
            acc2 = np.array([motions[f][1].samples() for f in floors]).reshape(-1, rec.acc.size)
        result.histories = Histories(
            dt, fl, acc1, hist_slides, hist_mu, hist_deform, hist_top, rocking=hist_rock,
            plane=hist_plane, floor_acceleration_h2=acc2, **bearing,
        )  # fmt: skip
    result.seconds = time.perf_counter() - t0
    return result


def _pair_spectrum(task: Task, model, floor: int, coupled=None) -> SpectrumResult:
    """The floor spectrum of a pair (:func:`floorslide.rotd_spectrum`; on the `coupled` poly
    motion of a building on friction pendulums, :func:`~floorslide.spectra.poly_segments.
    rotd_on_poly`): RotD50 as ``psa`` (and ``sd = psa/ω²``), RotD100 and each direction's PSA
    beside it; ``sa`` and ``sv`` are NaN (RotD is defined on the oscillator's displacement)."""
    from floorslide.spectra.core import Spectrum
    from floorslide.spectra.poly_segments import rotd_on_poly
    from floorslide.spectra.rotd import rotd_spectrum

    rec, sc = task.record, task.spectra
    if coupled is not None:
        r = rotd_on_poly(coupled, floor, np.asarray(sc.periods), list(sc.damping))
    else:
        r = rotd_spectrum((rec.acc, rec.acc2), rec.dt, np.asarray(sc.periods), list(sc.damping),
                          building=model, floor=floor if model is not None else None)  # fmt: skip
    T = r.periods
    w2 = np.where(T > 0, (2 * np.pi / np.where(T > 0, T, 1.0)) ** 2, np.inf)
    psa = r.rotd50
    sd = psa / w2
    nan = np.full_like(psa, np.nan)
    out = SpectrumResult(floor, T, r.damping, psa, nan, nan.copy(), sd)
    out.orientation = "RotD50"
    out.rotd100, out.psa_h1, out.psa_h2 = r.rotd100, r.h1.psa, r.h2.psa
    _broadened(out, Spectrum(T, r.damping, psa, nan, nan, sd, psa / np.sqrt(w2)), sc.broadening)
    return out


def _broadened(out: SpectrumResult, sp, factor: float) -> None:
    """Add to `out` the spectra `sp` broadened by ``±factor`` (nothing when 0)."""
    if factor:
        wide = broaden(sp, factor)
        out.broadening = float(factor)
        out.psa_broadened, out.sa_broadened = wide.psa, wide.sa
        out.sv_broadened, out.sd_broadened = wide.sv, wide.sd
