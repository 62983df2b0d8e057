"""``execute(..., meanwhile=)``: the caller's work for after the run (the demo imports the
report's modules) done in a thread of the main process while the worker processes compute."""

from __future__ import annotations

import threading

import pytest

from floorslide.run.execute import execute
from floorslide.scene.planner import plan
from floorslide.scene.schema import parse_scene
from tests.run.test_columnar import scene


@pytest.fixture(scope="module")
def the_plan(tmp_path_factory):
    path = tmp_path_factory.mktemp("meanwhile") / "s.toml"
    path.write_text(scene(["PET-090", "RIO-360"]))
    return plan(parse_scene(path.read_text(), path))


def test_it_runs_in_a_thread_beside_the_workers_and_is_done_at_the_return(the_plan, tmp_path):
    ran: list[tuple[str, bool]] = []

    def work():
        ran.append((threading.current_thread().name, threading.current_thread().daemon))

    summary = execute(the_plan, str(tmp_path / "a.h5"), workers=2, progress=False, meanwhile=work)
    assert summary.tasks == 4 and not summary.failures
    assert ran == [("floorslide-meanwhile", True)]


def test_without_worker_processes_it_is_not_called(the_plan, tmp_path):
    ran = []
    execute(
        the_plan, str(tmp_path / "b.h5"), workers=1, progress=False, meanwhile=lambda: ran.append(1)
    )
    assert ran == []


def test_its_errors_leave_the_run_alone(the_plan, tmp_path):
    def broken():
        raise ImportError("no such module")

    summary = execute(the_plan, str(tmp_path / "c.h5"), workers=2, progress=False, meanwhile=broken)
    assert summary.tasks == 4 and summary.ran == 4 and not summary.failures
