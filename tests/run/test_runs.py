"""Runs end to end: results, skip rules against forced simulation, kill and resume, Dask."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from floorslide.building.motions import peak_floor_acceleration
from floorslide.contents.sliding import slide
from floorslide.run.execute import execute
from floorslide.run.store import ResultFile, journal_dir, journal_entries
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene
from tests.conftest import ROOT

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()

SCENE = f"""
[scene]
name = "test study"

[[records]]
set = "mixed"
catalog = "{CATALOG}"
where = {{ station_id = ["ELC-180", "RIO-360", "PET-090"] }}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 2
period = 0.3
damping = 0.02

[[buildings]]
id = "isolated"
kind = "isolated"
superstructure = "fixed"
period = [2.0, 3.0]
damping = 0.1

[[contents]]
id = "cabinet"
floors = [0, 2]
mu = [0.05, 0.15, 0.3, 0.6]
width = 0.4
height = 1.6

[spectra]
floors = "all"
periods = [0.1, 0.3, 1.0, 2.5]
damping = [0.05]
"""


@pytest.fixture()
def scene_file(tmp_path):
    path = tmp_path / "study.toml"
    path.write_text(SCENE)
    return path


def results(path) -> dict:
    return {(t.meta["record"], t.meta["building"]): t for t in ResultFile(path).tasks()}


def assert_same(a: dict, b: dict, exact=True):
    assert a.keys() == b.keys()
    for key in a:
        ta, tb = a[key], b[key]
        np.testing.assert_array_equal(ta.pfa, tb.pfa)
        for ca, cb in zip(ta.contents, tb.contents, strict=True):
            for name in ("peak_slide", "residual_slide", "peak_abs_accel", "slip_phases"):
                x, y = getattr(ca, name), getattr(cb, name)
                if exact:
                    np.testing.assert_array_equal(x, y)
                else:
                    np.testing.assert_allclose(x, y, rtol=1e-12, atol=0)
        for sa, sb in zip(ta.spectra, tb.spectra, strict=True):
            np.testing.assert_array_equal(sa.psa, sb.psa)


def test_end_to_end_serial(scene_file, tmp_path):
    sc = load_scene(scene_file)
    p = plan(sc)
    assert len(p.tasks) == 3 * 3 and not p.failures
    out = tmp_path / "r.h5"
    summary = execute(p, str(out), workers=1, progress=False)
    assert summary.ran == 9 and not journal_dir(out).exists()
    res = results(out)
    rf = ResultFile(out)
    assert rf.scene_text == SCENE and rf.plan["tasks"] == 9
    # independent check of one task: the API directly
    t = res[("ImperialValley_1940_ELC-180", "isolated@T=2")]
    b = sc.buildings[1].build()
    acc = next(r for r in p.records if r.record == "ImperialValley_1940_ELC-180").acc
    pk = peak_floor_acceleration(b, acc, 0.01, floors=[0, 1, 2]).peak
    np.testing.assert_array_equal(t.pfa, pk)
    roof = next(c for c in t.contents if c.floor == 2)
    direct = slide(acc, 0.01, [0.05, 0.15], building=b, floor=2)
    slid = roof.modes[:2] == "slide"
    np.testing.assert_allclose(roof.peak_slide[:2][slid], direct.peak_slide[slid], rtol=1e-14)
    # rocking objects: mu_s > B/H = 0.25 and PFA above 0.25 g
    rock = roof.modes == "rock"
    assert np.all(np.isnan(roof.peak_slide[rock]))
    assert all(m in ("rest", "slide", "rock", "slide-rock") for m in roof.modes)
    # floors nobody asked about are not output: floor 1 has spectra only
    assert list(t.floors) == [0, 1, 2]
    assert {c.floor for c in t.contents} == {0, 2}
    # fixed-base floor 0 is the ground
    g = next(c for c in res[("ImperialValley_1940_ELC-180", "fixed")].contents if c.floor == 0)
    direct0 = slide(acc, 0.01, [0.05, 0.15])
    np.testing.assert_allclose(g.peak_slide[:2], direct0.peak_slide, rtol=1e-14)


def test_every_skip_rule_gives_the_forced_numbers(scene_file, tmp_path):
    """Skipped objects (never reaching breakaway) get exactly what the full simulation gives."""
    sc = load_scene(scene_file)
    p = plan(sc)
    assert any("never reaches" in k for k in p.skipped)
    assert any("rock" in k for k in p.skipped)
    execute(p, str(tmp_path / "skip.h5"), workers=1, progress=False)
    execute(plan(sc, force=True), str(tmp_path / "force.h5"), workers=1, progress=False, force=True)
    a, b = results(tmp_path / "skip.h5"), results(tmp_path / "force.h5")
    n_skipped = sum(int("never reaches" in c.skipped) for t in a.values() for c in t.contents)
    assert n_skipped > 0
    assert_same(a, b, exact=False)


def test_parallel_equals_serial(scene_file, tmp_path):
    p = plan(load_scene(scene_file))
    execute(p, str(tmp_path / "s.h5"), workers=1, progress=False)
    execute(p, str(tmp_path / "p.h5"), workers=2, progress=False)
    assert_same(results(tmp_path / "s.h5"), results(tmp_path / "p.h5"))


@pytest.mark.slow
def test_dask_local_cluster_equals_serial(scene_file, tmp_path):
    from dask.distributed import LocalCluster

    p = plan(load_scene(scene_file))
    execute(p, str(tmp_path / "s.h5"), workers=1, progress=False)
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as lc:
        execute(p, str(tmp_path / "d.h5"), scheduler=lc.scheduler_address, progress=False)
    assert_same(results(tmp_path / "s.h5"), results(tmp_path / "d.h5"))


@pytest.mark.slow
def test_killed_run_resumes_to_identical_results(scene_file, tmp_path):
    out = tmp_path / "k.h5"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "floorslide.cli",
            "run",
            str(scene_file),
            "-o",
            str(out),
            "--workers",
            "1",
        ],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.time() + 120
    while time.time() < deadline:
        if len(journal_entries(out)) >= 3:
            break
        time.sleep(0.01)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    finished = len(journal_entries(out))
    assert 3 <= finished < 9, finished
    # the killed file is readable (or, if the kill hit a write, rebuilt by --resume)
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "floorslide.cli",
            "run",
            str(scene_file),
            "-o",
            str(out),
            "--resume",
            "--workers",
            "1",
        ],
        env=env,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    assert f"{9 - finished} tasks run, {finished} already done" in done.stdout
    ref = tmp_path / "ref.h5"
    execute(plan(load_scene(scene_file)), str(ref), workers=1, progress=False)
    assert_same(results(out), results(ref))


def test_resume_refuses_a_different_scene(scene_file, tmp_path):
    out = tmp_path / "r.h5"
    p = plan(load_scene(scene_file))
    execute(p, str(out), workers=1, progress=False)
    other = tmp_path / "other.toml"
    other.write_text(SCENE.replace("test study", "other study"))
    from floorslide.errors import ResultFileError

    with pytest.raises(ResultFileError, match="different scene"):
        execute(plan(load_scene(other)), str(out), workers=1, resume=True, progress=False)


def run_cli(*args, cwd=None):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run(
        [sys.executable, "-m", "floorslide.cli", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
    )


def test_cli_run_dry_run_and_errors(scene_file, tmp_path):
    out = run_cli("run", str(scene_file), "--dry-run")
    assert out.returncode == 0, out.stderr
    assert "3 records × 3 buildings = 9 tasks" in out.stdout
    assert "objects that rock" in out.stdout and "never reaches" in out.stdout
    bad = tmp_path / "bad.toml"
    bad.write_text(SCENE.replace("period = 0.3", "period = -0.3").replace("mu = [", "mu = [-1, "))
    out = run_cli("run", str(bad))
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "buildings[0].period: must be > 0" in out.stderr and "contents[0].mu[0]" in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1
    out = run_cli("run", str(tmp_path / "missing.toml"))
    assert out.returncode == 2 and "no such scene file" in out.stderr


def test_a_bad_record_does_not_stop_the_others(tmp_path):
    good = ROOT / "data" / "records" / "slammer" / "ImperialValley_1940_ELC-180.txt"
    (tmp_path / "recs").mkdir()
    (tmp_path / "recs" / "good.txt").write_text("# dt: 0.01\n# units: g\n" + good.read_text())
    (tmp_path / "recs" / "bad.txt").write_text("# dt: 0.01\n# units: g\n0.1\nabc\n")
    scene = tmp_path / "s.toml"
    scene.write_text(
        '[[records]]\nset = "s"\nfiles = ["recs/*.txt"]\n'
        '[[buildings]]\nid = "f"\nkind = "fixed"\nperiod = 0.2\n'
        '[[contents]]\nid = "c"\nmu = [0.1]\n'
    )
    out = run_cli("run", str(scene), "-o", str(tmp_path / "o.h5"))
    assert out.returncode == 3
    assert "bad.txt" in out.stderr and "Traceback" not in out.stderr
    res = results(tmp_path / "o.h5")
    assert [k[0] for k in res] == ["good"]


def test_a_run_integrates_each_building_once_per_record(scene_file, tmp_path, monkeypatch):
    """Every task integrates its building once (one ``foh_states`` pass: the floor peaks, each
    content, each floor spectrum and the histories all read that motion); the planner's
    per-object rules need the true PFA, which a real run leaves to the tasks (the dry run
    evaluates it to count, once per task too)."""
    from floorslide.building import exact_motion
    from floorslide.cli import run

    calls = []
    real = exact_motion.foh_states

    def counting(phi, p, q, acc, k0, *rest):
        if k0 == 0:  # a pass through the record starts (a streamed one goes on chunk by chunk)
            calls.append(1)
        return real(phi, p, q, acc, k0, *rest)

    monkeypatch.setattr(exact_motion, "foh_states", counting)
    out = tmp_path / "once.h5"
    with pytest.raises(SystemExit) as exit_:
        run.main([str(scene_file), "-o", str(out), "--workers", "1"], standalone_mode=False)
        raise SystemExit(0)
    assert exit_.value.code in (0, None)
    n_tasks = ResultFile(out).plan["tasks"]
    assert len(calls) == n_tasks
    calls.clear()
    with pytest.raises(SystemExit):
        run.main([str(scene_file), "--dry-run"], standalone_mode=False)
    assert len(calls) == n_tasks
