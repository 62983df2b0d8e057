"""The first run of a fresh install: compiling the numerical kernels, said and shown.

floorslide's kernels are compiled by numba the first time they are called and kept in a disk
cache (:mod:`floorslide._jit`), so only a fresh install (or an upgrade, which changes their
sources) pays for it — up to a few minutes on a small machine. A command that needs kernels
calls :func:`prepare` with the *families* it needs before it computes anything:

- a family already compiled for this floorslide, numba, NumPy and Python is recognised by a
  marker file in the kernel cache (a few ``stat`` calls: a warm call prints nothing and costs
  nothing noticeable);
- otherwise one line on stderr says ``compiling numerical kernels (first run only, ~N s)``, the
  missing families compile in processes of their own, as many at once as there are cores, and
  their progress follows (one line per family, and meanwhile a running clock on a terminal or a
  line every 30 s in a log), then the
  command runs on the cached kernels. stdout is untouched (``--json`` stays machine-readable).

A kernel compiled outside the families (a call with argument types no family made) is still
announced: :func:`prepare` watches numba's compile events in this process and says
``compiling numerical kernels (first run only)`` on the first one. ``floorslide warmup``
compiles every family in advance.

Run as ``python -m floorslide.firstrun FAMILY`` it compiles one family (the side processes).
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["FAMILIES", "Family", "compile_families", "missing", "prepare"]

NOTICE = "compiling numerical kernels (first run only"
"""The start of the line that announces a compilation (tests look for it)."""

HEARTBEAT = 30.0
"""Seconds between the progress lines written when stderr is not a terminal (a log)."""


def _record() -> np.ndarray:
    """A short ground record (61 samples, m/s²) that makes every phase of the kernels run."""
    return np.sin(np.linspace(0.0, 6.0, 61)) * 4.0


_STUDY = """
[[records]]
set = "s"
catalog = "{catalog}"
where = {{ {where} }}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 2
period = 0.3
{buildings}

{contents}
[spectra]
floors = "all"
periods = {{ min = 0.05, max = 2.0, n = 4 }}

[report]
history_record = "{history}"
"""
"""A study of one record, as small as a study gets: its tasks run what a real study's run."""

_CONTENTS = '[[contents]]\nid = "c"\nfloors = "roof"\nmu = [0.05, 0.3, 1.0]\n{content}\n'
"""The study's contents (left out when only the building and its spectra are compiled)."""

_ISOLATORS = ('{ model = "friction_pendulum", mu = 0.06 }',
              '{ model = "bilinear", q_ratio = 0.06, yield_disp = 0.02 }')  # fmt: skip
"""Both kinds of nonlinear isolation, as a scene spells them."""


def _study(
    buildings: str = "",
    content: str | None = "width = 0.3\nheight = 1.0",
    pairs: bool = False,
    nonlinear_only: bool = False,
) -> None:
    """Plan a one-record study (the dry run's evaluation included) and run its tasks here,
    as ``floorslide run`` does: the kernels get the argument types of a real study (records
    read from files are read-only arrays, for one). The study always has a fixed-base building
    (the superstructure its isolated buildings name); `nonlinear_only` runs only the tasks on
    nonlinear isolation, without the evaluation (what the linear study compiles)."""
    import importlib.resources
    import tempfile as tf

    from floorslide.run.task import run_task
    from floorslide.run.warmup import family
    from floorslide.scene.planner import plan
    from floorslide.scene.schema import load_scene

    records = importlib.resources.files("floorslide.data") / "records"
    with importlib.resources.as_file(records) as folder, tf.TemporaryDirectory() as tmp:
        if pairs:
            catalog, where, history = (
                folder / "pairs" / "index.csv",
                'rsn = "511"',
                "RSN511_PALMSPR_ARM",
            )
        else:
            catalog, where = folder / "slammer" / "index.csv", 'station_id = "PET-090"'
            history = "CapeMendocino_1992_PET-090"
        contents = _CONTENTS.format(content=content) if content is not None else ""
        text = _STUDY.format(catalog=catalog.as_posix(), where=where, buildings=buildings,
                             contents=contents, history=history)  # fmt: skip
        path = Path(tmp) / "study.toml"
        path.write_text(text, encoding="utf-8")
        for task in plan(load_scene(path), evaluate=not nonlinear_only).tasks:
            if not nonlinear_only or family(task) == "nonlinear":
                run_task(task)


def _ground() -> None:
    """``floorslide slide RECORD`` and ``fs.slide`` on the ground: rigid blocks, both ways and
    one way."""
    from floorslide.building.exact_motion import floor_motion
    from floorslide.contents.sliding import slide

    fm = floor_motion(None, _record(), None, 0.01)
    for direction in ("both", "positive"):
        slide(fm, None, [0.1, 0.2], None, direction=direction)
    slide(_record(), 0.01, mu_k=[0.1], histories=True)


def _study_linear() -> None:
    """A study's tasks on linear buildings (fixed-base and linearly isolated), the planner's
    evaluation included: the building's exact motion, its peaks and samples, rigid blocks,
    slide–rock blocks, floor spectra and histories."""
    _study(
        'damping = 0.02\n\n[[buildings]]\nid = "iso"\nkind = "isolated"\n'
        'superstructure = "fixed"\nperiod = 2.0'
    )


def _floors() -> None:
    """Floors of linear buildings for the one-record commands (``--building``) and the Python
    API: the building's exact motion, its peaks and samples, rigid blocks, rocking and
    slide–rock blocks and floor spectra on a floor; rocking and slide–rock blocks and response
    spectra on the ground."""
    from floorslide.building.exact_motion import floor_motion
    from floorslide.building.model import ShearBuilding
    from floorslide.contents.rocking_block import rock
    from floorslide.contents.slide_rock import slide_rock
    from floorslide.run import warmup
    from floorslide.spectra.core import response_spectrum

    warmup._linear_tasks()
    fixed = ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    for building, floor in ((None, None), (fixed, 1)):  # as the one-record commands call them
        fm = floor_motion(building, _record(), floor, 0.01)
        fm.peak()
        rock(fm, width=[0.01, 0.3], height=[1.0, 1.0], restitution=None, method="exact")
        rock(fm, width=[0.01, 0.3], height=[1.0, 1.0], restitution=None, method="nonlinear")
        slide_rock(fm, None, [0.01, 0.3], [1.0, 1.0], [0.3, 0.4], mu_s=[0.35, 0.5],
                   histories=building is not None)  # fmt: skip
        response_spectrum(_record(), 0.01, np.array([0.0, 0.5]), [0.05], building=building,
                          floor=floor)  # fmt: skip


def _oscillator() -> None:
    """Flexible (2-DOF) equipment, on the ground and on a floor."""
    import floorslide as fs

    _study(content='model = "oscillator"\nfrequency = 6.0')
    fb = fs.ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    for building, floor in ((None, None), (fb, 1)):
        fs.slide_oscillator(
            _record(), 0.01, mu=[0.05, 0.1], frequency=6.0, damping=0.02, mass_ratio=0.5,
            building=building, floor=floor, histories=True,
        )  # fmt: skip


def _nonlinear() -> None:
    """Buildings on nonlinear isolation (lead-rubber, friction pendulum) and the contents and
    spectra that read their motion, as the one-record commands and the Python API call them."""
    import floorslide as fs
    from floorslide.run import warmup

    fm = warmup._nonlinear_tasks()
    fs.rock(fm, width=0.01, height=1.0)  # rocking without friction: the commands', no task's


def _iso_studies() -> str:
    """A scene's buildings on both kinds of nonlinear isolation."""
    return "".join(
        f'[[buildings]]\nid = "iso{i}"\nkind = "isolated"\nsuperstructure = "fixed"\n'
        f"period = 3.0\nisolator = {isolator}\n\n"
        for i, isolator in enumerate(_ISOLATORS)
    )


def _nonlinear_core() -> None:
    """A study's buildings on nonlinear isolation alone, with floor spectra and nothing on the
    floors: the building's kernel and the spectra on its segments, which no other family
    compiles (so that they compile beside the linear study's)."""
    _study(_iso_studies(), content=None, nonlinear_only=True)


def _study_nonlinear() -> None:
    """A study's tasks on nonlinear isolation (both kinds): what they add to the linear study's
    kernels and the building's (compiled first, :data:`FAMILIES` ``after``)."""
    _study(_iso_studies(), nonlinear_only=True)


def _plane() -> None:
    """Two horizontal components: sliding in the plane, RotD spectra, the floor's vector
    peak."""
    import floorslide as fs
    from floorslide.building.directions import plane_motions, plane_peak
    from floorslide.pair import make_pair

    ag = _record()
    pair = make_pair(ag, 0.6 * ag[::-1].copy(), 0.01)
    _study('period_h2 = 0.4\n\n[[buildings]]\nid = "iso"\nkind = "isolated"\n'
           'superstructure = "fixed"\nperiod = 2.0', pairs=True)  # fmt: skip
    fb = fs.ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    two = fs.BuildingPair(fb, fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.02))
    for building, floor in ((None, None), (fb, 1), (two, 0), (two, 1)):
        fs.slide_plane(pair, None, [0.1, 0.2], None, building=building, floor=floor)
        fs.rotd_spectrum(pair, periods=[0.0, 0.5], building=building, floor=floor)
        plane_peak(*plane_motions(building, pair.h1, pair.h2, pair.dt, floor))


def _bench() -> None:
    """``floorslide bench``: every approximate method of the accuracy-versus-cost study."""
    from floorslide.bench.compile import measure_here

    measure_here()


@dataclass(frozen=True)
class Family:
    """Kernels compiled together, by one short call of each.

    Attributes
    ----------
    name
        What ``floorslide warmup`` calls it.
    title
        What it is for, in a few words.
    seconds
        Compile time on an empty cache, s, side process included (measured on the 2-core
        development machine, one family at a time): what the estimate is made of.
    run
        Calls each kernel of the family once on a short input.
    after
        Families compiled first when they are compiled too (their kernels are then loaded
        from the disk cache instead of compiled twice side by side).
    """

    name: str
    title: str
    seconds: float
    run: Callable[[], None]
    after: tuple[str, ...] = ()


# fmt: off
FAMILIES: dict[str, Family] = {
    f.name: f
    for f in (
        Family("study", "a study's tasks on linear buildings", 53.0, _study_linear),
        Family("nonlinear-core", "buildings on nonlinear isolation", 33.0, _nonlinear_core),
        Family("study-nonlinear", "a study's tasks on nonlinear isolation", 5.0,
               _study_nonlinear, after=("study", "nonlinear-core")),
        Family("ground", "rigid blocks on the ground", 15.0, _ground),
        Family("floors", "one-record commands on linear buildings", 40.0, _floors,
               after=("study",)),
        Family("oscillator", "2-DOF sliding equipment", 25.0, _oscillator, after=("study",)),
        Family("nonlinear", "one-record commands on nonlinear isolation", 30.0, _nonlinear,
               after=("study-nonlinear",)),
        Family("plane", "two horizontal components", 65.0, _plane, after=("study",)),
        Family("bench", "approximate methods of the bench", 30.0, _bench),
    )
}
# fmt: on
"""Every family, in the order ``floorslide warmup`` lists them."""

USER_FAMILIES = (
    "study",
    "nonlinear-core",
    "study-nonlinear",
    "ground",
    "floors",
    "oscillator",
    "nonlinear",
    "plane",
)
"""What ``floorslide warmup`` compiles by default: every kernel a study or a one-record
command runs (the bench's approximate methods only when asked for)."""


def scene_families(scene) -> list[str]:
    """The families a study of `scene` (a validated :class:`floorslide.scene.schema.Scene`)
    runs: linear buildings always (the planner integrates them), and equipment on the ground,
    nonlinear isolation, 2-DOF equipment and pairs of components where the scene has them."""
    names = ["study"]
    fixed = [b for b in scene.buildings if b.kind == "fixed"]
    if any(0 in c.floors_of(b.stories) for c in scene.contents for b in fixed):
        names.append("ground")  # equipment on the ground (floor 0 of a fixed-base building)
    if any(b.isolator_model not in ("", "linear") for b in scene.buildings):
        names += ["nonlinear-core", "study-nonlinear"]
    if any(c.model == "oscillator" for c in scene.contents):
        names.append("oscillator")
    if any(r.pairs for r in scene.records):
        names.append("plane")
    return names


# --- which families are compiled ----------------------------------------------------------


def _cache_folder() -> Path:
    """Where this process's kernels are cached: ``NUMBA_CACHE_DIR`` when set, else
    floorslide's folder (:func:`floorslide._jit.cache_root`, or its fallback when that cannot
    be written)."""
    from numba.core import config

    from floorslide import _jit

    if config.CACHE_DIR:
        return Path(config.CACHE_DIR)
    for root in (_jit.cache_root(), _jit._fallback_root()):
        try:
            root.mkdir(parents=True, exist_ok=True)
        except OSError:
            continue
        if os.access(root, os.W_OK):
            return root
    return _jit.cache_root()  # pragma: no cover - nothing writable: markers are not kept


def _key() -> str:
    """What a compiled kernel depends on: floorslide's kernel sources and their folder (an
    installed copy and a source tree beside it have caches of their own), numba, NumPy,
    Python and the processor (numba compiles for the host CPU)."""
    import numba
    from llvmlite import binding

    from floorslide import _jit  # (so spelt: this file is not a kernel source of the stamp)

    parts = (
        _jit.kernel_sources_stamp(),
        str(_jit.PACKAGE_DIR),  # the kernel cache is per source folder (floorslide._jit)
        numba.__version__,
        np.__version__,
        sys.version,
        binding.get_host_cpu_name(),
    )
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()[:20]


def _marker(name: str) -> Path:
    tag = f"py{sys.version_info[0]}{sys.version_info[1]}"
    return _cache_folder() / tag / "compiled" / f"{name}-{_key()}"


def missing(names: Iterable[str]) -> list[str]:
    """The families among `names` not compiled yet for this installation, in `names`' order."""
    return [n for n in dict.fromkeys(names) if not _marker(n).exists()]


def _mark(name: str) -> None:
    path = _marker(name)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(f"{FAMILIES[name].title}\n", encoding="utf-8")
    except OSError:  # pragma: no cover - a cache that cannot be written: compiled next time
        pass


# --- compiling ---------------------------------------------------------------------------


def _workers(requested: int | None) -> int:
    if requested:
        return max(1, requested)
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def _depth(name: str, among: list[str]) -> int:
    """How many `after` families (among `among`) come before `name`, at most, in a chain."""
    deps = [a for a in FAMILIES[name].after if a in among]
    return 1 + max(_depth(a, among) for a in deps) if deps else 0


def estimate(names: Iterable[str], workers: int, load: float = 0.0) -> float:
    """Wall time to compile `names` on `workers` processes, longest first, s: the families'
    measured compile times, stretched when the machine's `load` (processes already running,
    e.g. the 1-minute load average) and the workers together exceed its cores."""
    names = list(names)
    lanes = [0.0] * max(1, workers)
    end: dict[str, float] = {}
    for name in sorted(names, key=lambda n: (_depth(n, names), -FAMILIES[n].seconds)):
        lane = lanes.index(min(lanes))
        start = max([lanes[lane]] + [end.get(a, 0.0) for a in FAMILIES[name].after])
        end[name] = lanes[lane] = start + FAMILIES[name].seconds
    cores = _workers(None)
    return max(lanes) * max(1.0, (load + min(workers, cores)) / cores)


def _load() -> float:
    try:
        return os.getloadavg()[0]
    except (AttributeError, OSError):  # pragma: no cover - not Unix
        return 0.0


def _say(line: str) -> None:
    print(f"floorslide: {line}", file=sys.stderr, flush=True)


SIDE_PYTHON = (sys.executable, "-P")
"""How a side process starts Python: ``-P`` keeps the working folder off its ``sys.path`` — run
from a source checkout beside an installed copy (CI, a developer), ``python -m`` would import
the checkout's floorslide instead of the one this process runs (and find no ``floorslide.data``
there: the bundled data install under that name from the top-level ``data/``)."""


def _side_env() -> dict[str, str]:
    """The side processes' environment: this process's, and the folder of the floorslide it
    imported on ``PYTHONPATH`` when that folder is not a site-packages folder (a source tree
    imported from the working folder or by ``PYTHONPATH``), so that they import the same one."""
    import site

    import floorslide

    env = dict(os.environ, PYTHONWARNINGS="ignore")
    root = Path(floorslide.__file__).resolve().parents[1]
    sites = {Path(p).resolve() for p in [*site.getsitepackages(), site.getusersitepackages()]}
    if root not in sites:
        env["PYTHONPATH"] = os.pathsep.join(filter(None, (str(root), env.get("PYTHONPATH"))))
    return env


def _next(queue: list[str], running: Iterable[str]) -> str | None:
    """The first family of `queue` (longest first) whose ``after`` families are neither queued
    nor running (done, or not asked for), or None while each waits for one."""
    waiting = set(queue) | set(running)
    return next((n for n in queue if not set(FAMILIES[n].after) & waiting), None)


def compile_families(
    names: Iterable[str], *, workers: int | None = None, say: Callable[[str], None] = _say
) -> dict[str, float]:
    """Compile the families `names` (the ones compiled already are skipped), each in a process
    of its own, at most `workers` at once (default: the cores this process may use), saying
    what happens through `say`: one line per family as it is done, and meanwhile a running
    clock on a terminal, or a line every :data:`HEARTBEAT` seconds in a log.

    Returns
    -------
    dict
        Seconds each family took, by name; a family whose process failed is left out (its
        kernels compile when first called) and said so.
    """
    todo = missing(names)
    if not todo:
        return {}
    workers = min(_workers(workers), len(todo))
    total = estimate(todo, workers, _load())
    say(
        f"{NOTICE}, ~{max(1, round(total))} s): "
        + ", ".join(FAMILIES[n].title for n in todo)
        + (f"; {workers} at once" if workers > 1 else "")
    )
    queue = sorted(todo, key=lambda n: -FAMILIES[n].seconds)
    running: dict[str, tuple[subprocess.Popen, float, object]] = {}
    done: dict[str, float] = {}
    finished = 0
    start = beat = time.monotonic()
    clock = sys.stderr.isatty()
    env = _side_env()
    while queue or running:
        while len(running) < workers:
            name = _next(queue, running)
            if name is None:
                break
            queue.remove(name)
            err = tempfile.TemporaryFile()  # a file, not a pipe: a chatty child never blocks
            proc = subprocess.Popen(
                [*SIDE_PYTHON, "-m", "floorslide.firstrun", name],
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=err,
                env=env,
            )
            running[name] = (proc, time.monotonic(), err)
        time.sleep(0.2)
        for name, (proc, began, err) in list(running.items()):
            if proc.poll() is None:
                continue
            del running[name]
            finished += 1
            if proc.returncode == 0:
                done[name] = time.monotonic() - began
                line = f"  {FAMILIES[name].title}: compiled in {done[name]:.0f} s"
            else:
                err.seek(0)
                text = err.read().decode(errors="replace").strip().splitlines()
                last = text[-1] if text else f"exit code {proc.returncode}"
                line = f"  {FAMILIES[name].title}: not compiled ahead ({last}); compiled when used"
            err.close()
            if clock:
                print("\r\033[K", end="", file=sys.stderr)
            say(f"{line} ({finished}/{len(todo)})")
        now = time.monotonic()
        if running and (clock or now - beat >= HEARTBEAT):
            beat = now
            still = ", ".join(FAMILIES[n].title for n in running)
            if clock:  # a running clock on one line
                print(f"\r\033[Kfloorslide:   {now - start:.0f} s … {still}", end="",
                      file=sys.stderr, flush=True)  # fmt: skip
            else:  # a line now and then in a log
                say(f"  {now - start:.0f} s, compiling: {still}")
    if done:
        say(
            f"kernels compiled in {time.monotonic() - start:.0f} s; later runs load them "
            f"from {_cache_folder()}"
        )
    return done


# --- the command line's hook -------------------------------------------------------------

_WATCHING: list = []


def _watch() -> None:
    """Announce, once, any floorslide kernel this process compiles that no family compiled."""
    if _WATCHING:
        return
    from numba.core import event

    pid = os.getpid()

    class _Notice(event.Listener):
        said = False

        def on_start(self, ev) -> None:
            if self.said or os.getpid() != pid:  # not in forked workers
                return
            dispatcher = ev.data.get("dispatcher") if isinstance(ev.data, dict) else None
            module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
            if module.startswith("floorslide"):
                self.said = True
                _say(f"{NOTICE}) …")

        def on_end(self, ev) -> None:
            pass

    listener = _Notice()
    event.register("numba:compile", listener)
    _WATCHING.append(listener)


def prepare(names: Iterable[str], *, workers: int | None = None) -> None:
    """Before a command computes: compile the families `names` it needs that are not compiled
    yet, saying so on stderr (nothing at all when they are), and announce any other
    compilation this process does."""
    try:
        compile_families(names, workers=workers)
    except Exception as exc:  # compiling ahead only saves time: never fail the command
        _say(f"warning: compiling ahead failed ({exc}); kernels compile when first used")
    _watch()


def _main(argv: list[str]) -> int:
    for name in argv:
        FAMILIES[name].run()
        _mark(name)
    return 0


if __name__ == "__main__":  # pragma: no cover - run in a side process
    sys.exit(_main(sys.argv[1:]))
