"""Shared by the fault tests: the 9-task study of tests/run/test_runs.py, planned once per
module, and its results from an undisturbed serial run."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from floorslide.run.execute import execute
from floorslide.scene.planner import plan
from floorslide.scene.schema import parse_scene
from tests.conftest import ROOT
from tests.run.test_runs import SCENE, results


@pytest.fixture(scope="module")
def the_plan(tmp_path_factory):
    path = tmp_path_factory.mktemp("scene") / "study.toml"
    path.write_text(SCENE)
    return plan(parse_scene(SCENE, path))


@pytest.fixture(scope="module")
def reference_file(the_plan, tmp_path_factory):
    out = tmp_path_factory.mktemp("ref") / "ref.h5"
    execute(the_plan, str(out), workers=1, progress=False)
    return out


@pytest.fixture(scope="module")
def reference(reference_file):
    return results(reference_file)


def cli(*args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    """``floorslide ARGS`` in a fresh process."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run(
        [sys.executable, "-m", "floorslide.cli", *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=timeout,
    )


def without_tasks(path, tids) -> None:
    """Rewrite the result file `path` (format 2) without the tasks `tids`, as a run killed
    before they were written leaves it."""
    import h5py

    from floorslide.run import columns
    from floorslide.run.snapshot import digest
    from floorslide.run.store import ResultFile

    rf = ResultFile(path)
    keep = [t for t in rf.done_tasks() if t not in set(tids)]
    batch = [(t, node, digest(node)) for t, node, _ in rf.nodes(keep)]
    with h5py.File(path, "a") as f:
        for name in (*columns.TABLES, "histories", "raw"):
            if name in f:
                del f[name]
        columns.init(f)
        columns.append(f, batch)
        columns.commit(f)
