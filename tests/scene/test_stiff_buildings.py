"""A building too stiff for the records' dt — its exact stepping would need more sub-steps per
record step than :data:`floorslide.building.exact.MAX_SUBSTEPS` (or more memory per step than
:data:`~floorslide.building.exact.MAX_STEP_BYTES`) — is refused when the scene is planned, in
one line naming the building's key, what it would need and what to change, so that
``--dry-run`` catches it: a 200-storey building of period 1e-6 s was a MemoryError traceback
(dry run too), of period 0.01 s a run of minutes per record without a word."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.exact import MAX_PHASE, MAX_SUBSTEPS, model_substeps
from floorslide.errors import ModelError, SceneError
from floorslide.scene.planner import plan
from floorslide.scene.schema import parse_scene

SCENE = """
[[records]]
set = "s"
files = ["r.txt"]
units = "g"
dt = 0.01

[[buildings]]
id = "low"
kind = "fixed"
period = 0.3

[[buildings]]
id = "tall"
kind = "fixed"
stories = 200
period = {period}

[[contents]]
id = "c"
mu = [0.1]
"""


def _write(tmp_path, period: str):
    t = np.arange(0.0, 3.0, 0.01)
    np.savetxt(tmp_path / "r.txt", 0.3 * np.sin(2 * np.pi * t))
    path = tmp_path / "scene.toml"
    path.write_text(SCENE.format(period=period))
    return path


def test_the_dry_run_refuses_a_building_that_would_exhaust_the_memory(tmp_path, monkeypatch,
                                                                       capsys):  # fmt: skip
    from floorslide.cli import main

    path = _write(tmp_path, "1e-6")
    monkeypatch.setattr(sys, "argv", ["floorslide", "run", str(path), "--dry-run"])
    with pytest.raises(SystemExit) as exit_:
        main()
    err = capsys.readouterr().err
    assert exit_.value.code == 2
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert err.startswith(f"floorslide: error: {path}: buildings[1] (building 'tall', ")
    assert "would need 32079098 sub-steps per record step at dt = 0.01 s" in err
    assert f"at most {MAX_SUBSTEPS} sub-steps" in err
    assert "give it a longer period or fewer stories, or records with dt ≤" in err


def test_a_building_that_would_run_for_minutes_is_refused_too(tmp_path):
    """Period 0.01 s: 3208 sub-steps of 400 states per record step."""
    sc = parse_scene(_write(tmp_path, "[0.01, 4.0]").read_text(), tmp_path / "scene.toml")
    with pytest.raises(SceneError) as err:
        plan(sc, evaluate=False)
    (problem,) = err.value.problems
    assert problem.startswith("buildings[1] (building 'tall@T=0.01', under record ")
    assert "would need 3208 sub-steps" in problem
    assert err.value.exit_code == 2
    # the 4 s variant of the same table is fine (9 sub-steps)
    assert fs.ShearBuilding.from_period(stories=200, period=4.0).substeps(0.01) == 9


def test_the_solvers_refuse_it_in_one_line_too():
    tall = fs.ShearBuilding.from_period(stories=200, period=1e-6)
    acc = np.zeros(10)
    with pytest.raises(ModelError, match="would need 32079098 sub-steps") as err:
        fs.slide(acc, 0.01, 0.1, building=tall, floor=200)
    assert err.value.where == "building"
    with pytest.raises(ModelError, match="sub-steps per record step"):
        fs.floor_motions(tall, acc, 0.01, floors=[200])


def test_the_limit_is_on_the_fastest_time_scale():
    """``m = ⌈ρ·dt/0.5⌉`` sub-steps: 1000 allowed, 1001 refused; the stiff hard case (T = 0.01 s
    under dt = 0.02 s) needs 26."""
    dt = 0.02
    assert model_substeps(MAX_SUBSTEPS * MAX_PHASE / dt, dt, 2) == MAX_SUBSTEPS
    with pytest.raises(ModelError, match=f"would need {MAX_SUBSTEPS + 1} sub-steps"):
        model_substeps((MAX_SUBSTEPS + 0.5) * MAX_PHASE / dt, dt, 2)
    with pytest.raises(ModelError, match="MiB of states per step"):
        model_substeps(1.0, dt, 10**7)  # one step's states beyond the memory limit
    stiff = fs.ShearBuilding.from_period(stories=1, period=0.01, damping=0.05)
    assert stiff.substeps(dt) == 26


def test_a_stiff_superstructure_on_nonlinear_isolation_is_refused():
    sup = fs.ShearBuilding.from_period(stories=200, period=1e-5, damping=0.05)
    b = fs.NonlinearIsolatedBuilding(sup, 1.0, fs.FrictionPendulum(mu=0.05, period=3.0))
    with pytest.raises(ModelError, match="sub-steps per record step"):
        b.substeps(0.01)
    with pytest.raises(ModelError, match="sub-steps per record step"):
        fs.isolator_response(b, np.zeros(10), 0.01)
