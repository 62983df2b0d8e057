"""A run killed with SIGKILL at several random moments, resumed each time, ends with tables
byte-identical to an uninterrupted run (docs/design.md §5, §9)."""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time

import psutil
import pytest

from floorslide.report import design_tables, write_csv
from floorslide.run.execute import execute
from floorslide.run.store import journal_entries
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene
from tests.conftest import ROOT
from tests.run.test_runs import SCENE


def tables(path, folder):
    paths = write_csv(design_tables(path), folder)
    return {p.name: p.read_bytes() for p in paths}


@pytest.mark.slow
def test_repeated_kills_then_resume_give_identical_tables(tmp_path):
    scene = tmp_path / "s.toml"
    big = SCENE.replace("period = [2.0, 3.0]", "period = [1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0]")
    big = big.replace('station_id = ["ELC-180", "RIO-360", "PET-090"]', 'set = "pulse-like"')
    scene.write_text(big)  # 18 records × 9 buildings = 162 tasks, ~7 s on 2 workers
    out = tmp_path / "k.h5"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    cmd = [
        sys.executable,
        "-m",
        "floorslide.cli",
        "run",
        str(scene),
        "-o",
        str(out),
        "--workers",
        "2",
    ]
    rng = random.Random(20261122)
    targets = sorted(rng.sample(range(1, 150), 3))  # kill once this many tasks are journaled
    seen = []
    for attempt, target in enumerate(targets):
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
        seen.append(len(journal_entries(out)))
    assert all(0 < n < 162 for n in seen) and seen == sorted(seen), seen
    time.sleep(0.5)
    assert not [
        p for p in psutil.process_iter(["cmdline"]) if str(out) in " ".join(p.info["cmdline"] or [])
    ]
    done = subprocess.run([*cmd, "--resume"], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    ref = tmp_path / "ref.h5"
    execute(plan(load_scene(scene)), str(ref), workers=1, progress=False)
    assert tables(out, tmp_path / "a") == tables(ref, tmp_path / "b")
