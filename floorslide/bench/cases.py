"""What the accuracy-versus-cost study runs: the solvers, their methods and settings, and the
quantities whose error is measured (docs/design.md §6).

Every solver has its exact method (the reference) and approximate methods, each either a single
point or a *family* over a step (``dt/k``) or a tolerance. A method returns the quantities users
use, keyed by metric name (:data:`METRICS`); :func:`error` turns two such results into a relative
error.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from floorslide.building.model import IsolatedBuilding, LinearBuilding, ShearBuilding
from floorslide.building.motions import floor_motions, peak_floor_acceleration
from floorslide.constants import G
from floorslide.contents.oscillator import slide_oscillator
from floorslide.contents.sliding import slide
from floorslide.spectra.core import response_spectrum

METRICS = {
    "peak_slide": "peak slide",
    "residual_slide": "residual slide",
    "peak_deformation": "peak spring deformation",
    "pfa": "PFA",
    "samples": "floor acceleration samples",
    "psa": "PSA",
    "isolator": "peak isolator displacement",
    "rock_peak": "peak rocking angle θ/α",
}
"""Metric key → what it measures. Relative errors: peak slide, peak deformation, PFA and PSA
against the exact value of the same object, floor or period; the residual slide against the
exact *peak* slide (a residual can be near zero; in the plane, the length of the difference of
the residual vectors); samples: ``max|y − y_exact| / max|y_exact|`` per floor. Each is the
maximum over objects (or floors, periods) and records."""

ETA = (0.2, 0.5)
"""Friction as a fraction of the peak acceleration of the motion the object stands on:
``mu = eta·PFA/g`` (``eta = mu·g/A`` of docs/design.md §7), so that every object slides on every
floor."""

OSCILLATOR = dict(frequency=6.0, damping=0.02, mass_ratio=0.5)
"""The 2-DOF sliding oscillator of Brochard & Gantenbein (1989): clamped 6 Hz, 2 %, m1/m2 = 0.5."""

DAMPING = 0.05

Run = Callable[[np.ndarray, float, dict], dict]


@dataclass(frozen=True)
class Method:
    """One method at one setting.

    Attributes
    ----------
    method
        The method's name (as the ``method=`` of the API, or a peer's name).
    family
        The line it belongs to in the work–precision figure.
    setting
        Its setting in words (``"dt/4"``, ``"rtol 1e-06"``, ``"grip 200 Hz"``, ``""``).
    run
        ``run(acc, dt, context) → {metric: array}``.
    substeps, rtol, grip_hz
        The setting as numbers (``None`` where it does not apply).
    """

    method: str
    family: str
    setting: str
    run: Run = field(repr=False, compare=False)
    substeps: int | None = None
    rtol: float | None = None
    grip_hz: float | None = None

    @property
    def exact(self) -> bool:
        return self.method == "exact"


@dataclass(frozen=True)
class Solver:
    """A solver of the study: what it computes, on what, by which methods.

    Attributes
    ----------
    key
        Short name (``"slide-ground"``), used for file names.
    title
        What is computed, in words (figure titles).
    metrics
        Metric keys whose errors are measured; the headline error is their maximum.
    methods
        The exact method first, then the approximate ones.
    context
        ``context(acc, dt) → dict`` of per-record settings (friction values, periods).
    pair
        Whether it takes two horizontal components: ``acc`` is then ``(2, npts)`` (x along the
        pair's ``h1``, y along ``h2``), and the study runs it on bundled pairs of components
        (:data:`floorslide.bench.study.PAIRS`) instead of single records.
    """

    key: str
    title: str
    metrics: tuple[str, ...]
    methods: tuple[Method, ...]
    context: Callable[[np.ndarray, float], dict] = field(repr=False, compare=False)
    pair: bool = False


@dataclass(frozen=True)
class Ladder:
    """The settings a study uses (the default run and ``--quick`` differ only here)."""

    substeps: tuple[int, ...]
    rtols: tuple[float, ...]
    grips_hz: tuple[float, ...]
    fft_oversample: tuple[int, ...]
    n_periods: int
    penalty_rtol: float = 1e-7


FULL = Ladder(
    substeps=(1, 2, 4, 8, 16, 32, 64),
    rtols=(1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10),
    grips_hz=(25.0, 50.0, 100.0, 200.0, 400.0, 800.0, 1600.0),
    fft_oversample=(1, 2, 4, 8),
    n_periods=50,
)
QUICK = Ladder(
    substeps=(1, 4, 16, 64),
    rtols=(1e-3, 1e-7),
    grips_hz=(50.0, 200.0, 800.0),
    fft_oversample=(1, 4),
    n_periods=20,
)


def stiff_building() -> ShearBuilding:
    """A stiff 1-storey building: T = 0.1 s, 5 % damping."""
    return ShearBuilding.from_period(1, 0.1, 0.05)


def isolated_building() -> IsolatedBuilding:
    """A 3-storey building (T = 0.4 s, 5 %) on linear isolation (T = 2.5 s, 10 %, m_b = m)."""
    return IsolatedBuilding(ShearBuilding.from_period(3, 0.4, 0.05), 1.0, 2.5, 0.10)


def resample(acc: np.ndarray, k: int) -> np.ndarray:
    """The same piecewise-linear record sampled at ``dt/k`` (along the last axis: a pair of
    components ``(2, npts)`` too)."""
    if k == 1:
        return acc
    if acc.ndim > 1:
        return np.stack([resample(a, k) for a in acc])
    return np.interp(np.arange((acc.size - 1) * k + 1) / k, np.arange(acc.size), acc)


def _mus(building: LinearBuilding | None, floor: int):
    def context(acc: np.ndarray, dt: float) -> dict:
        if building is None:
            peak = float(np.abs(acc).max())
        else:
            peak = float(peak_floor_acceleration(building, acc, dt, floors=[floor]).peak[0])
        return {"mu": np.array(ETA) * peak / G}

    return context


def _slide_result(res) -> dict:
    return {"peak_slide": res.peak_slide, "residual_slide": res.residual_slide}


def sliding_solver(
    key: str, title: str, building: LinearBuilding | None, floor: int, ladder: Ladder
) -> Solver:
    """Rigid blocks (``mu = eta·PFA/g``) on the ground or on a floor: the exact event-driven
    solver, SLAMMER's per-sample trapezoid (Jibson 1993), Newmark at ``dt/k``, SciPy's DOP853
    restarted at every sample with events at ``rtol``, and (on a floor) the exact solver on
    floor samples at ``dt/k`` joined by straight lines."""
    kw = {} if building is None else {"building": building, "floor": floor}

    def run(method: str, **settings) -> Run:
        def go(acc, dt, ctx):
            return _slide_result(slide(acc, dt, ctx["mu"], method=method, **settings, **kw))

        return go

    methods = [Method("exact", "exact", "", run("exact"))]
    methods.append(Method("slammer", "SLAMMER per-sample trapezoid", "dt", run("slammer")))
    methods += [
        Method("newmark", "Newmark avg. acc., dt/k", f"dt/{k}", run("newmark", substeps=k), k)
        for k in ladder.substeps
    ]
    if building is not None:

        def reinterpolated(k: int) -> Run:
            def go(acc, dt, ctx):
                af = floor_motions(building, acc, dt, floors=[floor], oversample=k)[0]
                return _slide_result(slide(af, dt / k, ctx["mu"]))

            return go

        methods += [
            Method(
                "reinterpolated",
                "exact on floor samples at dt/k, re-interpolated",
                f"dt/{k}",
                reinterpolated(k),
                k,
            )
            for k in ladder.substeps
        ]
    methods += [
        Method(
            "solve_ivp",
            "solve_ivp DOP853, rtol",
            f"rtol {r:.0e}",
            run("solve_ivp", rtol=r, integrator="DOP853"),
            rtol=r,
        )
        for r in ladder.rtols
    ]
    return Solver(
        key, title, ("peak_slide", "residual_slide"), tuple(methods), _mus(building, floor)
    )


def _plane_mus(building: LinearBuilding | None, floor: int):
    """``mu = eta·max|a_f|/g`` with ``|a_f|`` the magnitude of the floor's horizontal
    acceleration (both directions' exact floor samples; at the samples, where the peak of a
    piecewise-linear vector on the ground is)."""

    def context(acc: np.ndarray, dt: float) -> dict:
        if building is None:
            af = acc
        else:
            af = np.stack([floor_motions(building, a, dt, floors=[floor])[0] for a in acc])
        return {"mu": np.array(ETA) * float(np.hypot(af[0], af[1]).max()) / G}

    return context


def plane_solver(
    key: str, title: str, building: LinearBuilding | None, floor: int, ladder: Ladder
) -> Solver:
    """Rigid blocks sliding in the plane under a pair of components (``mu = eta·max|a_f|/g``),
    on the ground or on a floor (one model both ways): the exact Taylor-series solver, the
    Moreau–Jean scheme at ``dt/k`` (friction as a return map), SciPy's RK45 at ``rtol`` with
    events, and each component slid alone by the exact 1-D solver
    (:mod:`floorslide.contents.plane_approx`)."""
    from floorslide.contents.plane import slide_plane

    kw = {} if building is None else {"building": building, "floor": floor}

    def run(method: str, **settings) -> Run:
        def go(acc, dt, ctx):
            r = slide_plane(acc, dt, ctx["mu"], method=method, compare_1d=False, **settings, **kw)
            return {"peak_slide": r.peak_slide, "residual_slide": r.residual}

        return go

    methods = [Method("exact", "exact", "", run("exact"))]
    methods += [
        Method(
            "newmark",
            "Moreau–Jean return map, dt/k",
            f"dt/{k}",
            run("newmark", substeps=k),
            k,
        )
        for k in ladder.substeps
    ]
    methods += [
        Method(
            "solve_ivp", "solve_ivp RK45, rtol", f"rtol {r:.0e}", run("solve_ivp", rtol=r), rtol=r
        )
        for r in ladder.rtols
    ]
    methods.append(
        Method("components", "each component alone (1-D exact), as a vector", "", run("components"))
    )
    return Solver(
        key,
        title,
        ("peak_slide", "residual_slide"),
        tuple(methods),
        _plane_mus(building, floor),
        pair=True,
    )


def oscillator_solver(ladder: Ladder) -> Solver:
    """The 2-DOF sliding oscillator on the ground: exact, Newmark at ``dt/k``, and the grip
    spring (penalty) at growing grip frequencies, integrated by LSODA."""

    def run(method: str, **settings) -> Run:
        def go(acc, dt, ctx):
            res = slide_oscillator(acc, dt, ctx["mu"], **OSCILLATOR, method=method, **settings)
            return {"peak_slide": res.peak_slide, "peak_deformation": res.peak_deformation}

        return go

    methods = [Method("exact", "exact", "", run("exact"))]
    methods += [
        Method("newmark", "Newmark avg. acc., dt/k", f"dt/{k}", run("newmark", substeps=k), k)
        for k in ladder.substeps
    ]
    methods += [
        Method(
            "penalty",
            f"grip spring (penalty), LSODA rtol {ladder.penalty_rtol:g}",
            f"grip {f:g} Hz",
            run("penalty", grip_frequency=f, rtol=ladder.penalty_rtol),
            rtol=ladder.penalty_rtol,
            grip_hz=f,
        )
        for f in ladder.grips_hz
    ]
    return Solver(
        "oscillator-ground",
        "2-DOF sliding oscillator (6 Hz, 2 %, m₁/m₂ = 0.5) on the ground",
        ("peak_slide", "peak_deformation"),
        tuple(methods),
        _mus(None, 0),
    )


def floor_motion_solver(
    key: str, title: str, building: LinearBuilding, floors: list[int], ladder: Ladder
) -> Solver:
    """Floor accelerations of `floors`: the exact first-order hold (samples) with the true
    PFA inside steps, against exact samples at ``dt/k`` with the PFA read at them, zero-order hold
    and Newmark at ``dt/k`` (PFA at their own steps), python-control's ``forced_response``."""

    def sampled(method: str, k: int) -> Run:
        def go(acc, dt, ctx):
            y = floor_motions(building, acc, dt, floors, oversample=k, method=method)
            return {"pfa": np.abs(y).max(axis=1), "samples": y[:, ::k]}

        return go

    def exact(acc, dt, ctx):
        y = floor_motions(building, acc, dt, floors)
        pfa = peak_floor_acceleration(building, acc, dt, floors).peak
        return {"pfa": pfa, "samples": y}

    methods = [Method("exact", "exact", "", exact)]
    methods += [
        Method(
            "samples",
            "exact samples at dt/k, PFA read at samples",
            f"dt/{k}",
            sampled("exact", k),
            k,
        )
        for k in ladder.substeps
    ]
    methods += [
        Method("zoh", "zero-order hold, dt/k", f"dt/{k}", sampled("zoh", k), k)
        for k in ladder.substeps
    ]
    methods += [
        Method("newmark", "Newmark avg. acc., dt/k", f"dt/{k}", sampled("newmark", k), k)
        for k in ladder.substeps
    ]
    methods.append(
        Method(
            "forced_response", "python-control forced_response", "dt", sampled("forced_response", 1)
        )
    )
    return Solver(key, title, ("pfa", "samples"), tuple(methods), lambda acc, dt: {})


def _periods(ladder: Ladder):
    def context(acc: np.ndarray, dt: float) -> dict:
        return {"periods": np.geomspace(0.02, 5.0, ladder.n_periods)}

    return context


def spectrum_solver(
    key: str, title: str, building: LinearBuilding | None, floor: int, ladder: Ladder
) -> Solver:
    """PSA at 5 % over log-spaced periods 0.02–5 s: exact (peaks inside steps), peaks at samples
    of ``dt/k``, Newmark at ``dt/k``, FFT of the record sampled at ``dt/k``, (on a floor) the exact
    spectrum of floor samples at ``dt/k`` re-interpolated, and the peers pyrotd and eqsig when
    installed (given the exact floor samples on a floor)."""
    kw = {} if building is None else {"building": building, "floor": floor}

    def run(method: str, k: int = 1, **settings) -> Run:
        def go(acc, dt, ctx):
            sp = response_spectrum(
                resample(acc, k), dt / k, ctx["periods"], DAMPING, method=method, **settings, **kw
            )
            return {"psa": sp.psa[0]}

        return go

    methods = [Method("exact", "exact", "", run("exact"))]
    methods += [
        Method("samples", "peaks at samples of dt/k", f"dt/{k}", run("samples", k), k)
        for k in ladder.substeps
    ]
    methods += [
        Method("newmark", "Newmark avg. acc., dt/k", f"dt/{k}", run("newmark", substeps=k), k)
        for k in ladder.substeps
    ]
    methods += [
        Method("fft", "FFT of the record at dt/k", f"dt/{k}", run("fft", k), k)
        for k in ladder.fft_oversample
    ]
    if building is not None:

        def reinterpolated(k: int) -> Run:
            def go(acc, dt, ctx):
                af = floor_motions(building, acc, dt, floors=[floor], oversample=k)[0]
                return {"psa": response_spectrum(af, dt / k, ctx["periods"], DAMPING).psa[0]}

            return go

        methods += [
            Method(
                "reinterpolated",
                "exact on floor samples at dt/k, re-interpolated",
                f"dt/{k}",
                reinterpolated(k),
                k,
            )
            for k in ladder.substeps
        ]
    methods += _peers(building, floor)
    return Solver(key, title, ("psa",), tuple(methods), _periods(ladder))


def _peers(building: LinearBuilding | None, floor: int) -> list[Method]:
    """pyrotd and eqsig, when installed (``pip install floorslide[bench]``)."""

    def motion(acc, dt):
        if building is None:
            return acc
        return floor_motions(building, acc, dt, floors=[floor])[0]

    out = []
    try:
        import pyrotd

        def run_pyrotd(acc, dt, ctx):
            freqs = 1.0 / ctx["periods"]
            return {"psa": pyrotd.calc_spec_accels(dt, motion(acc, dt), freqs, DAMPING).spec_accel}

        out.append(Method("pyrotd", "pyrotd (frequency domain)", "dt", run_pyrotd))
    except ImportError:
        pass
    try:
        import eqsig

        def run_eqsig(acc, dt, ctx):
            T = ctx["periods"]
            res = eqsig.sdof.pseudo_response_spectra(motion(acc, dt), dt, T, xi=DAMPING)
            return {"psa": np.asarray(res[2])}

        out.append(Method("eqsig", "eqsig (Nigam–Jennings, peaks at samples)", "dt", run_eqsig))
    except ImportError:
        pass
    return out


ROCK_HEIGHT = 1.5
"""Height of the bench's rocking blocks, m (their widths follow the record: :func:`_blocks`)."""


def _blocks(building: LinearBuilding | None, floor: int):
    """Rocking blocks of height :data:`ROCK_HEIGHT` with ``tan α = eta·PFA/g`` (``eta`` of
    :data:`ETA`): every block uplifts on every record."""

    def context(acc: np.ndarray, dt: float) -> dict:
        ctx = _mus(building, floor)(acc, dt)
        return {"width": ctx["mu"] * ROCK_HEIGHT}

    return context


def rocking_solver(ladder: Ladder) -> Solver:
    """Rocking blocks on the ground: the full equation solved exactly to rounding
    (the reference), the linearised equation solved exactly (its error is the linearisation's),
    fixed-step RK4 at ``dt/k`` with interpolated events, and SciPy's RK45 at ``rtol``
    (:mod:`floorslide.contents.rocking_approx`)."""
    from floorslide.contents.rocking_block import rock

    def run(method: str, **settings) -> Run:
        def go(acc, dt, ctx):
            r = rock(acc, dt, ctx["width"], ROCK_HEIGHT, method=method, **settings)
            return {"rock_peak": r.peak_ratio}

        return go

    methods = [
        Method("exact", "exact (full equation)", "", run("nonlinear")),
        Method("linearised", "linearised equation, exact", "", run("exact")),
    ]
    methods += [
        Method("rk4", "RK4, dt/k, interpolated events", f"dt/{k}", run("rk4", substeps=k), k)
        for k in ladder.substeps
    ]
    methods += [
        Method(
            "solve_ivp", "solve_ivp RK45, rtol", f"rtol {r:.0e}", run("solve_ivp", rtol=r), rtol=r
        )
        # every other tolerance of the full study (each run restarts at every event: slow)
        for r in (ladder.rtols if len(ladder.rtols) <= 2 else ladder.rtols[::2])
    ]
    return Solver(
        "rocking-ground",
        "Rocking block on the ground (Housner; tan α = eta·PGA/g, height 1.5 m)",
        ("rock_peak",),
        tuple(methods),
        _blocks(None, 0),
    )


def _slide_rockers(acc: np.ndarray, dt: float) -> dict:
    """Blocks of height :data:`ROCK_HEIGHT` with ``tan α = eta·PGA/g`` whose friction lets them
    rock first and then slip while they rock: ``mu_s = 1.1 tan α``, ``mu_k = 1.02 tan α``."""
    lam = np.array(ETA) * float(np.abs(acc).max()) / G
    return {"width": lam * ROCK_HEIGHT, "mu": 1.02 * lam, "mu_s": 1.1 * lam}


def slide_rock_solver(ladder: Ladder) -> Solver:
    """Slide–rock blocks on the ground (docs/design.md §10g): the exact solver (every mode's
    series to rounding, every mode change located) against the fixed-step RK4 of
    :mod:`floorslide.contents.slide_rock_approx` at ``dt/k`` with interpolated events."""
    from floorslide.contents.slide_rock import slide_rock

    def run(method: str, **settings) -> Run:
        def go(acc, dt, ctx):
            r = slide_rock(acc, dt, ctx["width"], ROCK_HEIGHT, ctx["mu"], mu_s=ctx["mu_s"],
                           method=method, **settings)  # fmt: skip
            return {"rock_peak": r.peak_ratio, "peak_slide": r.peak_slide}

        return go

    methods = [Method("exact", "exact (every mode's series, events located)", "", run("exact"))]
    for k in ladder.substeps:
        fixed = run("fixed_step", substeps=k)
        methods.append(Method("fixed_step", "RK4, dt/k, interpolated events", f"dt/{k}", fixed, k))
    return Solver(
        "slide-rock-ground",
        "Slide–rock block on the ground (tan α = eta·PGA/g, mu_s 1.1 tan α, mu_k 1.02 tan α)",
        ("rock_peak", "peak_slide"),
        tuple(methods),
        _slide_rockers,
    )


def nonlinear_building(isolator):
    """The 3-storey superstructure of the isolated building (T = 0.4 s, 5 %) on a nonlinear
    layer."""
    from floorslide.building.nonlinear import NonlinearIsolatedBuilding

    return NonlinearIsolatedBuilding(ShearBuilding.from_period(3, 0.4, 0.05), 1.0, isolator)


def isolation_solver(key: str, title: str, isolator, ladder: Ladder) -> Solver:
    """A building on nonlinear isolation: its floors' accelerations (samples, true PFA) and the
    peak isolator displacement by the exact event-driven solver, against Newmark with Newton
    iterations at ``dt/k`` (OpenSees' scheme) and a smoothed model through ``solve_ivp``
    (:mod:`floorslide.building.nonlinear_approx`). For the friction pendulum Newmark's family is
    over the elastic friction's yield displacement at ``dt/16`` (at a fixed one it converges to
    its own elastic-friction model, not to the Coulomb pendulum), the samples are left out
    (the exact base acceleration jumps at every stop, which no smoothed model can match
    sample by sample)."""
    from floorslide.building.isolators import BilinearIsolator
    from floorslide.building.nonlinear import isolator_response
    from floorslide.building.nonlinear_approx import (
        newmark_isolator_response,
        smooth_isolator_response,
    )

    building = nonlinear_building(isolator)
    bilinear = isinstance(isolator, BilinearIsolator)

    def result(r) -> dict:
        out = {"pfa": np.asarray(r.pfa), "isolator": np.array([r.peak_displacement])}
        if bilinear:
            out["samples"] = np.asarray(r.floor_acceleration)
        return out

    def exact(acc, dt, ctx):
        return result(isolator_response(building, acc, dt))

    def newmark(k: int, fy: float | None = None) -> Run:
        kw = {} if fy is None else {"friction_yield": fy}
        return lambda acc, dt, ctx: result(
            newmark_isolator_response(building, acc, dt, substeps=k, **kw)
        )

    def smooth(**kw) -> Run:
        return lambda acc, dt, ctx: result(smooth_isolator_response(building, acc, dt, **kw))

    methods = [Method("exact", "exact", "", exact)]
    if bilinear:
        methods += [
            Method("newmark", "Newmark + Newton, dt/k", f"dt/{k}", newmark(k), k)
            for k in ladder.substeps
        ]
        methods += [
            Method("smooth", "Wen-smoothed, solve_ivp LSODA", f"sharpness {n}", smooth(sharpness=n))
            for n in ((5, 50) if len(ladder.substeps) < 5 else (5, 20, 50))
        ]
    else:
        methods += [
            Method(
                "newmark",
                "Newmark + Newton, dt/16, elastic friction",
                f"yield {1000 * fy:g} mm",
                newmark(16, fy),
                16,
            )
            for fy in (2.5e-4, 1e-4, 1e-5)
        ]
        methods += [
            Method("smooth", "tanh friction, solve_ivp LSODA", f"eps {e:g} m/s", smooth(eps=e))
            for e in (1e-2, 1e-3)
        ]
    metrics = ("pfa", "isolator", "samples") if bilinear else ("pfa", "isolator")
    return Solver(key, title, metrics, tuple(methods), lambda acc, dt: {})


def plane_isolation_solver(ladder: Ladder) -> Solver:
    """The 3-storey building on friction pendulums (mu 0.06, T 3 s) under a pair of components:
    the peak bearing displacement ``max |u_b|`` (the exact solver's true peak inside steps;
    Newmark's over its sub-steps; the uncoupled model's at the samples) by the exact coupled
    solver (:mod:`floorslide.building.plane_isolation`), against Newmark with Newton on a circular
    yield surface at ``dt/16`` over the friction element's elastic displacement and the
    smoothed (Park–Wen) bidirectional bearing through ``solve_ivp`` over its elastic
    displacement ``Y``, and the uncoupled per-direction model
    (:mod:`floorslide.building.plane_isolation_approx`)."""
    from floorslide.building.plane_isolation import plane_isolator_response
    from floorslide.building.plane_isolation_approx import (
        newmark_plane_isolator_response,
        smoothed_plane_isolator_response,
        uncoupled_plane_isolator_response,
    )

    building = nonlinear_building(_pendulum())

    def result(r) -> dict:
        return {"isolator": np.array([r.peak_displacement])}

    def exact(acc, dt, ctx):
        return result(plane_isolator_response(building, acc[0], acc[1], dt))

    def newmark(fy: float) -> Run:
        return lambda acc, dt, ctx: result(
            newmark_plane_isolator_response(
                building, acc[0], acc[1], dt, substeps=16, friction_yield=fy
            )
        )

    def uncoupled(acc, dt, ctx):
        return result(uncoupled_plane_isolator_response(building, acc[0], acc[1], dt))

    methods = [Method("exact", "exact", "", exact)]
    methods += [
        Method(
            "newmark",
            "Newmark + Newton, dt/16, circular friction",
            f"yield {1000 * fy:g} mm",
            newmark(fy),
            16,
        )
        for fy in ((2.5e-4, 1e-5) if len(ladder.substeps) < 5 else (2.5e-4, 1e-4, 1e-5))
    ]

    def smoothed(y: float) -> Run:
        return lambda acc, dt, ctx: result(
            smoothed_plane_isolator_response(building, acc[0], acc[1], dt, yield_disp=y)
        )

    methods += [
        Method(
            "smoothed",
            "Park–Wen smoothed bearing, solve_ivp LSODA rtol 1e-8",
            f"Y {1000 * y:g} mm",
            smoothed(y),
            rtol=1e-8,
        )
        for y in ((2.5e-4,) if len(ladder.substeps) < 5 else (1e-3, 2.5e-4, 2.5e-5))
    ]
    methods.append(Method("uncoupled", "each direction alone (1-D exact)", "", uncoupled))
    return Solver(
        "isolation-pendulum-plane",
        "3-storey building on friction pendulums (mu 0.06, T 3 s) under two components",
        ("isolator",),
        tuple(methods),
        lambda acc, dt: {},
        pair=True,
    )


def plane_bilinear_solver(ladder: Ladder) -> Solver:
    """The 3-storey building on lead-rubber bearings (Q/W 0.06, T_d 2.5 s, D_y 20 mm) under a
    pair of components: the peak bearing displacement ``max |u_b|`` by the exact coupled solver
    (circular yield surface, :mod:`floorslide.building.plane_bilinear`), against Newmark with
    Newton and radial return on ``dt/k`` (OpenSees' bidirectional
    ``elastomericBearingPlasticity``), the smoothed Park–Wen bearing through ``solve_ivp`` (its
    yield displacement ``D_y``) and the uncoupled per-direction model
    (:mod:`floorslide.building.plane_isolation_approx`)."""
    from floorslide.building.plane_isolation import plane_isolator_response
    from floorslide.building.plane_isolation_approx import (
        newmark_plane_isolator_response,
        smoothed_plane_isolator_response,
        uncoupled_plane_isolator_response,
    )

    building = nonlinear_building(_bilinear())

    def result(r) -> dict:
        return {"isolator": np.array([r.peak_displacement])}

    def exact(acc, dt, ctx):
        return result(plane_isolator_response(building, acc[0], acc[1], dt))

    def newmark(k: int) -> Run:
        return lambda acc, dt, ctx: result(
            newmark_plane_isolator_response(building, acc[0], acc[1], dt, substeps=k)
        )

    def smoothed(acc, dt, ctx):
        return result(smoothed_plane_isolator_response(building, acc[0], acc[1], dt))

    def uncoupled(acc, dt, ctx):
        return result(uncoupled_plane_isolator_response(building, acc[0], acc[1], dt))

    methods = [Method("exact", "exact", "", exact)]
    methods += [
        Method("newmark", "Newmark + Newton, circular yield surface", f"dt/{k}", newmark(k), k)
        for k in ladder.substeps
    ]
    methods.append(
        Method(
            "smoothed",
            "Park–Wen smoothed bearing, solve_ivp LSODA rtol 1e-8",
            "Y = D_y",
            smoothed,
            rtol=1e-8,
        )
    )
    methods.append(Method("uncoupled", "each direction alone (1-D exact)", "", uncoupled))
    return Solver(
        "isolation-bilinear-plane",
        "3-storey building on lead-rubber bearings (Q/W 0.06, T_d 2.5 s) under two components",
        ("isolator",),
        tuple(methods),
        lambda acc, dt: {},
        pair=True,
    )


COUPLED_MASS = 0.1
"""The coupled block's mass as a fraction of the roof's (``slide-coupled``)."""


def coupled_building() -> ShearBuilding:
    """The 3-storey fixed-base building of ``slide-coupled``: T = 0.5 s, 5 %."""
    return ShearBuilding.from_period(3, 0.5, 0.05)


def coupled_solver(ladder: Ladder) -> Solver:
    """A block of 10 % of the roof's mass coupled with the roof of a 3-storey building
    (``mu = eta·PFA/g`` of the bare roof): the peak slide and the roof's PFA by the exact
    event-driven solver (:func:`floorslide.slide_coupled`), against the tanh-smoothed friction
    through ``solve_ivp`` over ``eps`` and Newmark with stick/slip checks at ``dt/k``
    (:mod:`floorslide.contents.coupled_approx`)."""
    from floorslide.contents.coupled import slide_coupled
    from floorslide.contents.coupled_approx import slide_coupled_newmark, slide_coupled_smoothed

    building = coupled_building()
    mass = COUPLED_MASS * float(building.mass[-1])
    kw = dict(mass=mass, building=building, floor=3)

    def result(r) -> dict:
        return {"peak_slide": np.asarray(r.peak_slide), "pfa": np.asarray(r.pfa)}

    def exact(acc, dt, ctx):
        return result(slide_coupled(acc, dt, ctx["mu"], **kw))

    def newmark(k: int) -> Run:
        return lambda acc, dt, ctx: result(
            slide_coupled_newmark(acc, dt, ctx["mu"], substeps=k, **kw)
        )

    def smoothed(eps: float, rtol: float) -> Run:
        return lambda acc, dt, ctx: result(
            slide_coupled_smoothed(acc, dt, ctx["mu"], eps=eps, rtol=rtol, **kw)
        )

    methods = [Method("exact", "exact", "", exact)]
    methods += [
        Method(
            "smoothed", "tanh friction, solve_ivp LSODA", f"eps {e:g} m/s", smoothed(e, r), rtol=r
        )
        for e, r in _eps_ladder(ladder)
    ]
    methods += [
        Method("newmark", "Newmark avg. acc. + stick/slip, dt/k", f"dt/{k}", newmark(k), k)
        for k in ladder.substeps
    ]
    return Solver(
        "slide-coupled",
        "Block (10 % of the roof mass) coupled with the roof of a 3-storey building (T = 0.5 s)",
        ("peak_slide", "pfa"),
        tuple(methods),
        _mus(building, 3),
    )


def _eps_ladder(ladder: Ladder) -> tuple[tuple[float, float], ...]:
    """(eps m/s, rtol) of the smoothed-friction families, ``rtol = eps/100`` (eps in m/s): two
    settings quick, three full. Tighter tolerances move the peak-slide error by less than 5 %
    of itself (measured on PET-090 and RSN 511 at eps 1e-4: rtol 1e-6 against 1e-7) at
    1.5–2× the cost."""
    full = ((1e-2, 1e-4), (1e-3, 1e-5), (1e-4, 1e-6))
    return full[::2] if len(ladder.substeps) < 5 else full


def plane_oscillator_solver(ladder: Ladder) -> Solver:
    """The 2-DOF sliding oscillator in the plane on the ground pair (``mu = eta·max|a_g|/g``):
    the exact Taylor-series solver (:func:`floorslide.slide_oscillator_plane`) against the
    smoothed friction circle through ``solve_ivp`` over ``eps``
    (:mod:`floorslide.contents.plane_oscillator_approx`)."""
    from floorslide.contents.plane_oscillator import slide_oscillator_plane
    from floorslide.contents.plane_oscillator_approx import slide_oscillator_plane_smoothed

    def result(r) -> dict:
        return {
            "peak_slide": np.asarray(r.peak_slide),
            "peak_deformation": np.asarray(r.peak_deformation),
        }

    def exact(acc, dt, ctx):
        return result(slide_oscillator_plane(acc, dt, ctx["mu"], **OSCILLATOR))

    def smoothed(eps: float, rtol: float) -> Run:
        return lambda acc, dt, ctx: result(
            slide_oscillator_plane_smoothed(acc, dt, ctx["mu"], **OSCILLATOR, eps=eps, rtol=rtol)
        )

    methods = [Method("exact", "exact", "", exact)]
    methods += [
        Method(
            "smoothed",
            "smoothed friction circle, solve_ivp LSODA",
            f"eps {e:g} m/s",
            smoothed(e, r),
            rtol=r,
        )
        for e, r in _eps_ladder(ladder)
    ]
    return Solver(
        "oscillator-plane-ground",
        "2-DOF sliding oscillator (6 Hz, 2 %, m₁/m₂ = 0.5) in the plane on the ground",
        ("peak_slide", "peak_deformation"),
        tuple(methods),
        _plane_mus(None, 0),
        pair=True,
    )


def solvers(ladder: Ladder) -> tuple[Solver, ...]:
    """Every solver of the study, in the order of the table."""
    stiff, iso = stiff_building(), isolated_building()
    return (
        sliding_solver("slide-ground", "Rigid block on the ground", None, 0, ladder),
        sliding_solver(
            "slide-stiff-floor",
            "Rigid block on a stiff 1-storey building (T = 0.1 s)",
            stiff,
            1,
            ladder,
        ),
        sliding_solver(
            "slide-isolated-roof",
            "Rigid block on the roof of a 3-storey isolated building",
            iso,
            3,
            ladder,
        ),
        oscillator_solver(ladder),
        floor_motion_solver(
            "floor-motions-stiff",
            "Floor motion of a stiff 1-storey building (T = 0.1 s)",
            stiff,
            [1],
            ladder,
        ),
        floor_motion_solver(
            "floor-motions-isolated",
            "Floor motions of a 3-storey isolated building (base mat to roof)",
            iso,
            [0, 1, 2, 3],
            ladder,
        ),
        spectrum_solver(
            "spectra-ground", "Response spectrum (PSA, 5 %) of the ground", None, 0, ladder
        ),
        spectrum_solver(
            "frs-stiff-floor",
            "Floor response spectrum (PSA, 5 %), stiff 1-storey building",
            stiff,
            1,
            ladder,
        ),
        spectrum_solver(
            "frs-isolated-roof",
            "Floor response spectrum (PSA, 5 %), roof of the 3-storey isolated building",
            iso,
            3,
            ladder,
        ),
        isolation_solver(
            "isolation-bilinear",
            "3-storey building on lead-rubber isolation (Q/W 0.06, D_y 20 mm, T_d 2.5 s)",
            _bilinear(),
            ladder,
        ),
        isolation_solver(
            "isolation-pendulum",
            "3-storey building on a friction pendulum (mu 0.06, T 3 s)",
            _pendulum(),
            ladder,
        ),
        plane_isolation_solver(ladder),
        plane_bilinear_solver(ladder),
        rocking_solver(ladder),
        slide_rock_solver(ladder),
        plane_solver(
            "plane-ground", "Rigid block sliding in the plane on the ground", None, 0, ladder
        ),
        plane_solver(
            "plane-roof",
            "Rigid block sliding in the plane on the roof of the 3-storey isolated building",
            iso,
            3,
            ladder,
        ),
        coupled_solver(ladder),
        plane_oscillator_solver(ladder),
    )


def _bilinear():
    from floorslide.building.isolators import BilinearIsolator

    return BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02)


def _pendulum():
    from floorslide.building.isolators import FrictionPendulum

    return FrictionPendulum(mu=0.06, period=3.0)


def error(metric: str, got: dict, ref: dict) -> float:
    """Relative error of `metric` (see :data:`METRICS`), maximum over its entries."""
    g = np.asarray(got[metric], dtype=float)
    r = np.asarray(ref[metric], dtype=float)
    if metric == "residual_slide":
        diff = (
            np.abs(g - r) if g.ndim == 1 else np.hypot(g[..., 0] - r[..., 0], g[..., 1] - r[..., 1])
        )
        return float(np.max(diff / np.asarray(ref["peak_slide"], dtype=float)))
    if metric == "samples":
        return float(np.max(np.abs(g - r).max(axis=-1) / np.abs(r).max(axis=-1)))
    return float(np.max(np.abs(g - r) / np.abs(r)))
