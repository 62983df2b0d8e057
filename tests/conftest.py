"""Shared fixtures: real bundled records (data/ only, never ../shared).

Property tests and fuzzers (hypothesis) draw the same examples on every run, so that the test
command gives the same verdict on every machine; ``FLOORSLIDE_HYPOTHESIS=explore`` draws new
random examples each run (how the fuzzers find new bugs).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import settings

settings.register_profile("deterministic", derandomize=True, database=None)
settings.register_profile("explore")
settings.load_profile(os.environ.get("FLOORSLIDE_HYPOTHESIS", "deterministic"))

ROOT = Path(__file__).resolve().parents[1]
SLAMMER = ROOT / "data" / "records" / "slammer"
G = 9.80665


def load_slammer(name: str) -> tuple[np.ndarray, float]:
    """A bundled SLAMMER record in m/s² and its dt (read with NumPy, independent of floorslide's
    readers so that numerical tests do not depend on them)."""
    import csv

    with open(SLAMMER / "index.csv", newline="") as fh:
        rows = {r["file"]: r for r in csv.DictReader(fh)}
    row = rows[name]
    return np.loadtxt(SLAMMER / name) * G, float(row["dt"])


def floorslide_cli(*args: str, cwd: str | os.PathLike | None = None):
    """``floorslide ARGS`` as a console-script call, run in this process: the entry point
    (:func:`floorslide.cli.main`: its one-line warnings, error lines and exit codes) with
    ``sys.argv``, the standard streams, the warning filters of a fresh interpreter, the signal
    handlers and the working folder (`cwd`) as a new process would have them, restored after.
    Returns what :func:`subprocess.run` with ``capture_output=True, text=True`` returns.

    For the single-record commands and the set-up commands: a new process per call costs a
    second of imports and kernel loading, ~60 times over in the command-line tests. Runs,
    signals and kills stay in real processes (their tests start them)."""
    import signal
    import subprocess
    import sys
    import warnings

    from click.testing import CliRunner

    from floorslide.cli import exit_status, main

    handlers = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)}
    argv, here = sys.argv, os.getcwd()
    code: int | str | None = None
    with CliRunner().isolation() as (out, err, _), warnings.catch_warnings():
        warnings.resetwarnings()  # a fresh interpreter's filters (pytest's are stricter)
        for category in (DeprecationWarning, PendingDeprecationWarning, ImportWarning,
                         ResourceWarning):  # fmt: skip
            warnings.simplefilter("ignore", category)
        sys.argv = ["floorslide", *map(str, args)]
        try:
            if cwd is not None:
                os.chdir(cwd)
            main()
        except SystemExit as exc:
            code = exc.code
        finally:
            sys.argv = argv
            os.chdir(here)
            for sig, handler in handlers.items():
                signal.signal(sig, handler)
            sys.stdout.flush()
            sys.stderr.flush()
        code = exit_status(code)
        sys.stderr.flush()
        stdout, stderr = out.getvalue().decode(), err.getvalue().decode()
    return subprocess.CompletedProcess(["floorslide", *map(str, args)], code, stdout, stderr)


@pytest.fixture(scope="session")
def elcentro():
    """El Centro 1940 NS (ELC-180), dt = 0.01 s, m/s²."""
    return load_slammer("ImperialValley_1940_ELC-180.txt")


@pytest.fixture(scope="session")
def coarse_record():
    """Cape Mendocino 1992 Petrolia (PET-090), a pulse-like record at dt = 0.02 s, m/s²."""
    return load_slammer("CapeMendocino_1992_PET-090.txt")


# --- the suite in parallel, its kernels compiled once ----------------------------------------

PRECOMPILE_FROM = 100
"""A selection of at least this many tests has the kernel families compiled ahead (below it,
the few kernels it calls compile when called)."""


@pytest.hookimpl(tryfirst=True)
def pytest_cmdline_main(config):
    """``python -m pytest`` runs the tests in parallel, one process per core (``-n auto``), the
    tests of one module in one process (``--dist loadscope``: a module-scoped fixture — a study
    run once, the quick bench — is set up once, not once per process); set here rather than in
    ``addopts`` so that ``-p no:xdist`` still works. ``-n 0`` (or ``-n N``, ``--dist ...``,
    ``--pdb``) as given wins. (Not ``--dist loadgroup``: with pytest 9 and pytest-xdist 3.8 its
    ``xdist_group`` marks are ignored, the groups' tests handed out one by one.)"""
    option = config.option
    if not config.pluginmanager.hasplugin("xdist") or hasattr(config, "workerinput"):
        return
    if option.numprocesses is None and not option.usepdb:
        option.numprocesses = "auto"
    if option.numprocesses and option.dist == "no":
        option.dist = "loadscope"


def _precompile(config, count: int) -> None:
    """Compile, in the controller and before any test runs, the kernel families not compiled
    yet for this source tree, as many at once as there are cores (``floorslide warmup``'s
    side processes): test processes then load every kernel instead of each compiling the same
    ones. A warm cache costs a few ``stat`` calls."""
    if count < PRECOMPILE_FROM:
        return
    from floorslide import firstrun

    todo = firstrun.missing(firstrun.FAMILIES)  # (markers per source folder and sources)
    if not todo:
        return
    reporter = config.pluginmanager.get_plugin("terminalreporter")

    def say(line: str) -> None:
        if reporter is not None:
            reporter.write_line(f"floorslide: {line}")

    # (the side processes import the floorslide imported here: this tree's, firstrun._side_env)
    firstrun.compile_families(todo, say=say)


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_node_collection_finished(node, ids):
    """In the controller of a parallel run, once the first test process has collected (tests
    are handed out only when every process has)."""
    config = node.config
    if not getattr(config, "_floorslide_precompiled", False):
        config._floorslide_precompiled = True
        _precompile(config, len(ids))


def pytest_collection_finish(session):
    """A serial run (``-n 0``, ``-p no:xdist``): before the first test."""
    config = session.config
    if not hasattr(config, "workerinput") and not config.option.collectonly:
        _precompile(config, len(session.items))


def pytest_collection_modifyitems(session, config, items):
    """The modules with the most ``slow`` tests first, the order kept otherwise (a module's
    tests stay together and in order): a parallel run hands out whole modules in this order
    (``--dist loadscope``), so the long ones start first and the short ones fill in at the end
    instead of one process finishing a long module while the other waits."""
    from collections import Counter

    slow = Counter(item.path for item in items if item.get_closest_marker("slow") is not None)
    items.sort(key=lambda item: -slow[item.path])
