"""Issue 34: a run that writes its tasks in batches (more than one task at a time) killed with
SIGKILL while tasks are journaled but not yet in the result file loses no finished task:
``--resume`` counts every journaled task done, runs only the others, and the tables equal
those of an uninterrupted run."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from floorslide.run.execute import execute, write_batch
from floorslide.run.store import ResultFile, journal_entries
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene
from tests.conftest import ROOT
from tests.robustness.test_kill_resume import tables
from tests.run.test_runs import SCENE


@pytest.mark.slow
def test_a_kill_between_batches_loses_no_finished_task(tmp_path):
    scene = tmp_path / "s.toml"
    big = SCENE.replace("period = [2.0, 3.0]", "period = [1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0]")
    big = big.replace('station_id = ["ELC-180", "RIO-360", "PET-090"]', 'set = "pulse-like"')
    scene.write_text(big)  # 18 records × 9 buildings = 162 tasks
    p = plan(load_scene(scene))
    n = len(p.tasks)
    batch = write_batch(n)
    assert n == 162 and batch == 10  # the file lags the journal by up to 9 tasks
    out = tmp_path / "k.h5"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    cmd = [sys.executable, "-m", "floorslide.cli", "run", str(scene), "-o", str(out)]
    cmd += ["--workers", "2"]
    lagged = []
    for attempt, target in enumerate((25, 75, 125)):  # halfway between two batches
        proc = subprocess.Popen(
            cmd + (["--resume"] if attempt else []),
            env=env,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        deadline = time.time() + 120
        while time.time() < deadline and proc.poll() is None:
            if len(journal_entries(out)) >= target:
                break
            time.sleep(0.002)
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        journaled = len(journal_entries(out))
        assert 0 < journaled < n, journaled
        try:
            in_file = len(ResultFile(out).done_tasks())
        except Exception:  # killed inside a write: resume rebuilds the file from the journal
            in_file = None
        if in_file is not None:
            assert in_file <= journaled
            lagged.append(journaled - in_file)
        # the next run keeps every task journaled before the kill, whether in the file or not
        if attempt == 2:
            done = subprocess.run([*cmd, "--resume"], env=env, capture_output=True, text=True)
            assert done.returncode == 0, done.stderr
            assert f"{n - journaled} tasks run, {journaled} already done" in done.stdout
    assert any(k > 0 for k in lagged), lagged  # some kill found finished tasks only journaled
    assert len(ResultFile(out).done_tasks()) == n and not ResultFile(out).verify()
    ref = tmp_path / "ref.h5"
    execute(p, str(ref), workers=1, progress=False)
    assert tables(out, tmp_path / "a") == tables(ref, tmp_path / "b")
