"""Compile (or load) the kernels of a study's tasks in side processes, side by side with the
process that needs them next.

On a fresh install numba compiles every kernel once, into its disk cache, one after the other
in the process that first calls it: a study's planner compiles the floor-motion kernels of its
evaluation, then the first task the sliding and spectra kernels, then the first task on
nonlinear isolation that kernel. Started here, the tasks' families (``"linear"``,
``"nonlinear"``) compile in processes of their own while the planner compiles its own, and
the tasks find them in the disk cache (the demo from a fresh install, measured: 67 s → 53 s).
The local runner does the same for the families other than its first task's. A process that
has a family's kernels already (loaded or compiled) starts nothing for it.
"""

from __future__ import annotations

import multiprocessing
import sys
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from floorslide.building.nonlinear_motion import NonlinearFloorMotion


def _linear_tasks() -> None:
    """One short call of each kernel a task on a linear building runs: the building's motion,
    its floors' peaks and samples, rigid blocks with and without histories, slide–rock blocks
    (a study's rockers), floor spectra."""
    from floorslide.building.exact_motion import building_motion
    from floorslide.building.model import IsolatedBuilding, ShearBuilding
    from floorslide.contents.slide_rock import slide_rock
    from floorslide.contents.sliding import slide
    from floorslide.spectra.core import response_spectrum

    ag = np.sin(np.linspace(0.0, 6.0, 61)) * 2.0
    fixed = ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    for b in (fixed, IsolatedBuilding(fixed, 1.0, 2.0, 0.1)):
        motion = building_motion(b, ag, 0.01)
        motion.peaks([0, 1] if b is not fixed else [1])
        motion.samples([1])
        fm = motion.floor(1)
        slide(fm, None, np.array([0.1]), np.array([0.1]))
        slide(fm, None, np.array([0.1]), np.array([0.1]), histories=True)
        slide_rock(fm, None, [0.3], [1.0], [0.4], mu_s=[0.5])
        response_spectrum(fm, None, np.array([0.5]), [0.05])


def _nonlinear_tasks() -> NonlinearFloorMotion:
    """One short call of each kernel a task on nonlinear isolation runs: the building's motion
    (its segments), rigid blocks with and without histories, slide–rock blocks (a study's
    rockers), 2-DOF oscillators and floor spectra reading them. Returns the roof's motion (for
    :mod:`floorslide.firstrun`, which adds the one-record commands' calls on it)."""
    import floorslide as fs

    sup = fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.03)
    b = fs.NonlinearIsolatedBuilding(sup, 1.0, fs.FrictionPendulum(mu=0.05, period=3.0))
    ag = np.sin(np.linspace(0.0, 6.0, 61)) * 2.0
    fm = b.motion(ag, 0.01).floor(1)
    fs.slide(fm, mu_k=[0.1])
    fs.slide(fm, mu_k=[0.1], histories=True)
    fs.slide_rock(fm, None, [0.3], [1.0], [0.4], mu_s=[0.5])
    fs.slide_oscillator(fm, mu=[0.1], frequency=5.0)
    fs.response_spectrum(fm, periods=[0.5])
    return fm


def family(task) -> str:
    """The kernel family a planned task needs: ``"nonlinear"`` on a building on nonlinear
    isolation, else ``"linear"``."""
    model = getattr(getattr(task, "building", None), "isolator_model", "")
    return "nonlinear" if model not in ("", "linear") else "linear"


def _loaded(family: str) -> bool:
    """Whether this process has the family's kernels already."""
    if family == "nonlinear":
        from floorslide.building import _nonlinear_kernel as k
        from floorslide.contents import _segment_kernels as c
        from floorslide.spectra import _segment_kernels as sp

        return bool(
            k.nonlinear_run.signatures
            and c.blocks_on_segments.signatures
            and sp.oscillators_on_segments.signatures
        )
    from floorslide.contents import _kernels as k

    return bool(k.slide_kernel.signatures)


COMPILED_BY = {"linear": ("study",), "nonlinear": ("nonlinear-core", "study-nonlinear")}
"""The :mod:`floorslide.firstrun` families that compile a kernel family's tasks' kernels."""


def start(families) -> list:
    """Start a side process per kernel family (``"linear"``, ``"nonlinear"``) this process has
    not loaded yet and the disk cache does not hold yet; returns them (:func:`finish` them
    before the tasks run). None on platforms without ``fork``."""
    if sys.platform == "win32":  # pragma: no cover - spawn would re-import everything
        return []
    from floorslide.firstrun import missing

    ctx = multiprocessing.get_context("fork")
    target = {"linear": _linear_tasks, "nonlinear": _nonlinear_tasks}
    procs = []
    for family in families:
        # compiled already (floorslide.firstrun's families, marked in the disk cache): a side
        # process would only load them, for nothing
        if not _loaded(family) and missing(COMPILED_BY[family]):
            p = ctx.Process(target=_quietly, args=(target[family],), daemon=True)
            p.start()
            procs.append(p)
    return procs


def _quietly(target) -> None:
    """Run `target` in a side process that leaves interruptions to its parent: Ctrl-C (sent to
    the whole process group) is ignored here rather than printed as a traceback, and SIGTERM
    (the parent ending its daemon children) ends it at once."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for name in ("SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_DFL)
    target()


def finish(procs) -> None:
    """Wait for the side processes (their kernels are then in the disk cache)."""
    for p in procs:
        p.join()
