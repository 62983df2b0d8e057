"""A task that fails (a solver at its event limit) fails alone: it is reported in one line that
names the record, the building and the object, left out of the result file (which stays
INCOMPLETE, so ``table`` says so), the other tasks still run and are written, the exit code is
3 — as for an unreadable record — and ``--resume`` runs only what is missing."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide.contents.sliding as sliding_mod
from floorslide.run.store import ResultFile

SCENE = """
[scene]
name = "one task fails"

[[records]]
set = "s"
files = ["rec*.txt"]
units = "g"
dt = 0.01

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.2

[[contents]]
id = "box"
floors = [1]
mu = [0.1]
"""


def _write(folder):
    t = np.arange(0.0, 3.0, 0.01)
    # "calm" never reaches mu·g on the roof (the box is not integrated); "strong" slides
    np.savetxt(folder / "rec_calm.txt", 0.01 * np.sin(2 * np.pi * 2.0 * t))
    np.savetxt(folder / "rec_strong.txt", 0.5 * np.sin(2 * np.pi * 2.0 * t))
    (folder / "scene.toml").write_text(SCENE)


def _run(args, capsys) -> tuple[int, list[str]]:
    from floorslide.cli import run

    with pytest.raises(SystemExit) as exit_:
        run.main(args, standalone_mode=False)
        raise SystemExit(0)
    err = capsys.readouterr().err.splitlines()
    return exit_.value.code or 0, [ln for ln in err if ln.startswith("floorslide: error:")]


@pytest.mark.parametrize("workers", ["1", "2"])
def test_a_task_at_the_event_limit_fails_alone(tmp_path, capsys, monkeypatch, workers):
    _write(tmp_path)
    monkeypatch.setattr(sliding_mod, "SLIDE_MAX_EVENTS", 1)  # forked workers inherit it
    out = tmp_path / "out.h5"
    scene = str(tmp_path / "scene.toml")
    code, errors = _run([scene, "-o", str(out), "--workers", workers], capsys)
    assert code == 3
    assert len(errors) == 1, errors
    assert errors[0].startswith(
        "floorslide: error: record rec_strong (s) on building fixed: content box on floor 1: "
    )
    assert "more than 1 friction events" in errors[0]
    stored = ResultFile(out)
    assert [t.meta["record"] for t in stored.tasks()] == ["rec_calm"]
    # the file is incomplete, and the tables say so
    from floorslide.cli import table
    from floorslide.errors import IncompleteResultError

    with pytest.raises(IncompleteResultError, match="INCOMPLETE: 1 of 2 tasks done") as exc:
        table.main([str(out)], standalone_mode=False)
    assert exc.value.exit_code == 4
    # --resume runs only the failed task (and reports it again while it fails)
    code, errors = _run([scene, "-o", str(out), "--resume", "--workers", "1"], capsys)
    assert code == 3 and len(errors) == 1 and "rec_strong" in errors[0]
    # once it can run, --resume completes the file
    monkeypatch.setattr(sliding_mod, "SLIDE_MAX_EVENTS", 10000)
    code, errors = _run([scene, "-o", str(out), "--resume", "--workers", "1"], capsys)
    assert code == 0 and errors == []
    assert sorted(t.meta["record"] for t in ResultFile(out).tasks()) == ["rec_calm", "rec_strong"]
