"""The demo runs on the bundled data and writes results, tables and figures; run again, it
replaces its own output and nothing else."""

from __future__ import annotations

import os
import subprocess
import sys
from importlib.resources import files

import h5py
import pytest

from floorslide.cli import _demo_may_replace
from floorslide.run.store import ResultFile, written_for
from tests.conftest import ROOT


def demo(out, *args: str) -> subprocess.CompletedProcess:
    """``floorslide demo -o OUT ARGS`` in a fresh process."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run(
        [sys.executable, "-m", "floorslide.cli", "demo", "-o", str(out), *args],
        capture_output=True,
        text=True,
        env=env,
        cwd=out.parent,
    )


@pytest.mark.slow
def test_demo(tmp_path):
    out = demo(tmp_path / "d", "--workers", "2")
    assert out.returncode == 0, out.stderr
    rf = ResultFile(tmp_path / "d" / "results.h5")
    assert len(rf.done_tasks()) == 36 * 8
    assert "pulse-like (18 records)" in out.stdout and "| isolated@T=2.5 |" in out.stdout
    # issue 14 item 5: the friction-pendulum variant beside the linear model, with its loop
    assert "| fps |" in out.stdout
    assert (tmp_path / "d" / "figures" / "hysteresis_broad-band.png").exists()
    assert (tmp_path / "d" / "tables" / "isolators.csv").exists()
    # issue 12 item 4: 9 of 18 records rock under the cabinet at mu = 0.4 on isolated@T=2
    # (pulse-like); the median falls on them and reads "rocks", not the 0.0 of the 9 others;
    # issue 15: rocking is simulated, the cell says how many of them overturn
    row = next(ln for ln in out.stdout.splitlines()[::-1] if ln.startswith("| isolated@T=2 |"))
    cell = row.split(" | ")[7]
    assert cell.startswith("rocks (9/18; ") and cell.endswith(" overturn)"), row
    assert "never count as 0" in out.stdout and "the rocking table" in out.stdout
    assert "rocking objects are not simulated" not in out.stdout  # the old legend
    assert (tmp_path / "d" / "tables" / "rocking.csv").exists()
    for name in ("rocking_broad-band.png", "overturning_broad-band.png"):
        assert (tmp_path / "d" / "figures" / name).exists(), name
    tables = sorted(p.name for p in (tmp_path / "d" / "tables").iterdir())
    assert "tables.md" in tables and "slides.csv" in tables
    figures = list((tmp_path / "d" / "figures").glob("*.png"))
    assert len(figures) >= 6
    # issue 19 item 2: the README's quick start run a second time replaces its own results
    again = demo(tmp_path / "d", "--workers", "2")
    assert again.returncode == 0, again.stderr
    assert again.stdout.split("tasks in")[0] == out.stdout.split("tasks in")[0]
    assert len(ResultFile(tmp_path / "d" / "results.h5").done_tasks()) == 36 * 8
    # issue 18: the demo writes its HTML report and prints its link
    report = tmp_path / "d" / "report.html"
    assert report.stat().st_size > 500_000  # figures embedded
    assert f"report:  {report.resolve().as_uri()}" in again.stdout
    assert 'id="table-exceedance"' in report.read_text(encoding="utf-8")  # the cabinet's gaps
    # a demo result written by an earlier floorslide (its demo scene had other text under the
    # same name) is one the demo may replace too (the decision the demo takes before any
    # work; a third whole run would only repeat the second)
    h5 = tmp_path / "d" / "results.h5"
    scene = (files("floorslide.data") / "scenes" / "demo.toml").read_text(encoding="utf-8")
    with h5py.File(h5, "r+") as f:
        text, attrs = f["scene"][()], dict(f["scene"].attrs)
        del f["scene"]
        f["scene"] = text.decode().replace("allowable = [0.05, 0.1, 0.3]", "")
        f["scene"].attrs.update(attrs)
    assert not written_for(h5, scene)  # not the scene's own result any more …
    assert _demo_may_replace(h5, scene)  # … but an earlier demo's, replaced


def test_demo_leaves_other_files_alone(tmp_path):
    """Issue 19 item 2: a results.h5 that is not the demo's is refused in one line, exit 2."""
    folder = tmp_path / "d"
    folder.mkdir()
    mine = folder / "results.h5"
    with h5py.File(mine, "w") as f:
        f["mine"] = [1.0, 2.0]
    before = mine.read_bytes()
    out = demo(folder)
    assert out.returncode == 2, out.stderr
    assert out.stderr.strip() == (
        f"floorslide: error: {mine}: exists and is not a floorslide result of the demo scene; "
        "not replaced (choose another folder with -o, or move the file away)"
    )
    assert mine.read_bytes() == before and not out.stdout
