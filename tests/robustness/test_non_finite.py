"""Non-finite intermediate results are errors, never numbers: a record scaled (or read) beyond
what the solvers' float64 arithmetic takes, a building whose matrices overflow, a solver whose
state or result is NaN or infinite — each is one line naming the record, building or key, at
the first place it is known (the scene, the plan, the model, the task), never "0 slide, rest"
with exit 0 (docs/design.md §9)."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import floorslide as fs
from floorslide.constants import MAX_ACCELERATION, G
from floorslide.errors import ModelError, NonFiniteError

SCENE = """
[[records]]
set = "s"
files = ["r*.txt"]
units = "g"
dt = 0.01
{scale}

[[buildings]]
id = "fixed"
kind = "fixed"
{building}

[[contents]]
id = "box"
mu = [0.1]
"""


def _run(tmp_path, monkeypatch, capsys, scale="", building="period = 0.3", records=None,
         dry=True):  # fmt: skip
    from floorslide.cli import main

    t = np.arange(0.0, 3.0, 0.01)
    for name, rec in (records or {"r1": 0.3 * np.sin(2 * np.pi * t)}).items():
        np.savetxt(tmp_path / f"{name}.txt", rec)
    path = tmp_path / "scene.toml"
    path.write_text(SCENE.format(scale=scale, building=building))
    args = ["floorslide", "run", str(path), "-o", str(tmp_path / "o.h5"), "--workers", "1"]
    monkeypatch.setattr(sys, "argv", args + (["--dry-run"] if dry else []))
    with pytest.raises(SystemExit) as exit_:
        main()
        raise SystemExit(0)
    return exit_.value.code, capsys.readouterr().err


def test_a_scale_beyond_any_ground_motion_is_refused_by_the_scene(tmp_path, monkeypatch, capsys):
    """scale_pga = 1e307 g: the building's floor overflowed inside the kernels and the box read
    "0 slide, rest" with exit 0."""
    code, err = _run(tmp_path, monkeypatch, capsys, scale="scale_pga = 1e307")
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "records[0].scale_pga: must be > 0 and ≤ 100000, got 1e+307" in err


def test_a_record_beyond_what_the_solvers_take_fails_alone(tmp_path, monkeypatch, capsys):
    t = np.arange(0.0, 3.0, 0.01)
    records = {"r1": 0.3 * np.sin(2 * np.pi * t), "r2": 1e200 * np.sin(2 * np.pi * t)}
    code, err = _run(tmp_path, monkeypatch, capsys, records=records, dry=False)
    assert code == 3 and "Traceback" not in err
    (line,) = [ln for ln in err.splitlines() if ln.startswith("floorslide: error:")]
    assert "r2.txt: its samples reach" in line and "beyond the 100000 g the solvers take" in line
    from floorslide.run.store import ResultFile

    assert [t.meta["record"] for t in ResultFile(tmp_path / "o.h5").tasks()] == ["r1"]


@pytest.mark.parametrize(
    ("building", "message"),
    [
        ("period = 0.3\nmass = 1e308", "buildings[0] (building 'fixed'): masses up to 1e+308 kg"),
        ("mass = 1e-300\nstiffness = 1e300", "buildings[0].stiffness: the building's damping"),
    ],
)
def test_a_building_whose_matrices_overflow_is_refused(tmp_path, monkeypatch, capsys, building,
                                                       message):  # fmt: skip
    """Masses of 1e308 kg: storey stiffnesses of inf; the floors were NaN, read as "rest"."""
    code, err = _run(tmp_path, monkeypatch, capsys, building=building)
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1 and "RuntimeWarning" not in err, err
    assert message in err, err


def test_the_solvers_refuse_samples_they_cannot_take():
    acc = np.zeros(10)
    acc[0] = 1.01 * MAX_ACCELERATION
    with pytest.raises(ModelError, match="its samples reach") as err:
        fs.slide(acc, 0.01, 0.1)
    assert err.value.where == "acc"
    acc[0] = MAX_ACCELERATION  # the limit itself is taken
    assert fs.slide(acc, 0.01, 0.1).peak_slide[0] > 0
    assert MAX_ACCELERATION == pytest.approx(1e5 * G)


def test_a_building_beyond_float64_is_refused_by_the_model():
    with pytest.raises(ModelError, match="not finite"):
        fs.ShearBuilding([1e-300], [1e300])
    with pytest.raises(ModelError, match="beyond float64"):
        fs.ShearBuilding.from_period(2, 0.3, mass=1e308)
    with pytest.raises(ModelError, match="not finite"):
        fs.NonlinearIsolatedBuilding(
            fs.ShearBuilding.from_period(2, 0.3, mass=1e300), 1e300,
            fs.FrictionPendulum(mu=0.05, period=3.0),
        )  # fmt: skip


def test_a_task_whose_result_is_not_finite_fails_alone(tmp_path, monkeypatch):
    """The task is the last chokepoint: a solver that returned an infinity (here made to) makes
    the task a failure naming the record, building and quantity."""
    import floorslide.run.task as task_mod
    from floorslide.run.task import TaskFailure, attempt_task
    from floorslide.scene.planner import plan
    from floorslide.scene.schema import parse_scene

    t = np.arange(0.0, 3.0, 0.01)
    np.savetxt(tmp_path / "r1.txt", 0.3 * np.sin(2 * np.pi * t))
    p = plan(parse_scene(SCENE.format(scale="", building="period = 0.3"), tmp_path / "s.toml"))
    real = task_mod.slide

    def overflowing(*args, **kw):
        r = real(*args, **kw)
        r.peak_slide[:] = np.inf
        return r

    monkeypatch.setattr(task_mod, "slide", overflowing)
    out = attempt_task(p.tasks[0])
    assert isinstance(out, TaskFailure)
    assert out.message.startswith("record r1 (s) on building fixed: task: not finite")
    assert "peak_slide of content box on floor 1" in out.message
    with pytest.raises(NonFiniteError):
        task_mod.run_task(p.tasks[0])
