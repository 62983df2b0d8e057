"""The first run says what it does: a command that compiles kernels on an empty cache announces
it on stderr with an estimate and its progress; with the kernels cached it says nothing, and
stdout stays machine-readable either way. ``floorslide warmup`` compiles in advance."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from floorslide import firstrun
from tests.conftest import ROOT

RECORD = "data/records/slammer/ImperialValley_1940_ELC-180.txt"


def cli(*args: str, cache) -> subprocess.CompletedProcess:
    """``floorslide ARGS`` in a fresh process whose kernel cache is the folder `cache`."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), NUMBA_CACHE_DIR=str(cache))
    env.pop("FLOORSLIDE_CACHE_DIR", None)
    return subprocess.run(
        [sys.executable, "-m", "floorslide.cli", *args],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env=env,
        timeout=900,
    )


@pytest.mark.slow
def test_first_run_announces_compiling_then_is_silent(tmp_path):
    """One small family (rigid blocks on the ground) on an empty cache: the notice with its
    estimate and progress on stderr, the JSON on stdout untouched; then nothing to say."""
    first = cli("slide", RECORD, "--mu", "0.1", "--json", cache=tmp_path)
    assert first.returncode == 0, first.stderr
    assert "floorslide: compiling numerical kernels (first run only, ~" in first.stderr
    assert "rigid blocks on the ground: compiled in" in first.stderr  # progress
    assert "kernels compiled in" in first.stderr
    assert "compiling" not in first.stdout
    rows = json.loads(first.stdout)
    assert rows[0]["mu_k"] == 0.1 and rows[0]["peak_slide"] > 0

    again = cli("slide", RECORD, "--mu", "0.1", "--json", cache=tmp_path)
    assert again.returncode == 0, again.stderr
    assert "compil" not in again.stderr
    assert json.loads(again.stdout) == rows

    warm = cli("warmup", "ground", cache=tmp_path)
    assert warm.returncode == 0, warm.stderr
    assert warm.stdout.strip() == "kernels compiled: ground (already)"
    assert "compil" not in warm.stderr


def test_warmup_refuses_an_unknown_family(tmp_path):
    out = cli("warmup", "everything", cache=tmp_path)
    assert out.returncode == 2
    assert "unknown family 'everything'" in out.stderr and "ground" in out.stderr


def test_a_family_that_fails_is_said_and_left_to_first_use(tmp_path, monkeypatch):
    """A side process that fails does not fail the command: one line says so."""
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr("numba.core.config.CACHE_DIR", str(tmp_path))
    fake = firstrun.Family("no-such", "a family the side process does not know", 1.0, print)
    monkeypatch.setitem(firstrun.FAMILIES, "no-such", fake)
    monkeypatch.setattr(firstrun, "_load", lambda: 0.0)  # the estimate as measured
    lines: list[str] = []
    done = firstrun.compile_families(["no-such"], say=lines.append)
    assert done == {}
    assert lines[0].startswith("compiling numerical kernels (first run only, ~1 s)")
    assert "not compiled ahead" in lines[1] and "compiled when used" in lines[1]
    assert firstrun.missing(["no-such"]) == ["no-such"]  # no marker for it


def test_estimate_packs_families_on_the_cores():
    f = firstrun.FAMILIES
    names = ["nonlinear", "floors", "ground"]
    assert firstrun.estimate(names, 1) == pytest.approx(sum(f[n].seconds for n in names))
    two = firstrun.estimate(names, 2)
    if firstrun._workers(None) >= 2:
        assert max(f[n].seconds for n in names) <= two < sum(f[n].seconds for n in names)
    assert firstrun.estimate(names, 1, load=8.0) > firstrun.estimate(names, 1)  # a busy machine


def test_scene_families():
    from floorslide.scene.schema import load_scene

    # the demo: a study on linear buildings and on nonlinear isolation, nothing for the
    # one-record commands (rocking without friction, ground spectra, ...) nor the ground
    assert firstrun.scene_families(load_scene(ROOT / "data/scenes/demo.toml")) == [
        "study",
        "nonlinear-core",
        "study-nonlinear",
    ]
    pairs = firstrun.scene_families(load_scene(ROOT / "data/scenes/pairs.toml"))
    assert pairs[0] == "study" and "plane" in pairs and "nonlinear-core" not in pairs
    # equipment on the ground (floor 0 of the fixed-base building) adds its family
    assert "ground" in firstrun.scene_families(load_scene(ROOT / "data/scenes/design.toml"))


def test_families_wait_for_those_they_build_on():
    """A family whose kernels another compiles starts after it when both are asked for (the
    demo's nonlinear study loads the linear study's and the building's kernels instead of
    compiling them a second time beside them), and at once when it is asked for alone."""
    f = firstrun.FAMILIES
    demo = ["study", "nonlinear-core", "study-nonlinear"]
    queue = sorted(demo, key=lambda n: -f[n].seconds)
    assert firstrun._next(queue, []) == "study"
    assert firstrun._next(["nonlinear-core", "study-nonlinear"], ["study"]) == "nonlinear-core"
    assert firstrun._next(["study-nonlinear"], ["study", "nonlinear-core"]) is None
    assert firstrun._next(["study-nonlinear"], ["study"]) is None
    assert firstrun._next(["study-nonlinear"], []) == "study-nonlinear"
    assert firstrun._next(["floors"], []) == "floors"  # "study" not asked for
    # two workers: the two first side by side, the third after the longer of them
    two = max(f["study"].seconds, f["nonlinear-core"].seconds) + f["study-nonlinear"].seconds
    if firstrun._workers(None) >= 2:
        assert firstrun.estimate(demo, 2) == pytest.approx(two)
    for name, family in f.items():  # every `after` names a family, never itself
        assert set(family.after) <= set(f) - {name}


def test_side_processes_import_the_floorslide_this_process_runs(tmp_path):
    """Run from a folder holding another floorslide (a source checkout beside an installed
    copy: CI's quick start), a side process still imports this process's floorslide — with
    ``python -m`` the working folder's would come first, and its missing ``floorslide.data``
    failed every family."""
    import floorslide

    shadow = tmp_path / "floorslide"
    shadow.mkdir()
    (shadow / "__init__.py").write_text("raise ImportError('the working folder shadows')\n")
    out = subprocess.run(
        [*firstrun.SIDE_PYTHON, "-c", "import floorslide; print(floorslide.__file__)"],
        cwd=tmp_path,
        env=firstrun._side_env(),
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode == 0, out.stderr
    assert Path(out.stdout.strip()).resolve() == Path(floorslide.__file__).resolve()
    # and without -P it would not: the reason for it
    bad = subprocess.run(
        [sys.executable, "-c", "import floorslide"], cwd=tmp_path, capture_output=True,
        text=True, check=False, env=firstrun._side_env(),
    )  # fmt: skip
    assert "shadows" in bad.stderr
