"""Issue 19 item 2: ``floorslide run SCENE -o PATH`` never replaces what is at PATH by
accident. An existing file (a finished study, any text file) or the journal of an unfinished
run is refused in one line naming it, exit code 2, and left as it was; ``--resume`` continues
a run of the same scene and refuses anything else; ``--overwrite`` replaces."""

from __future__ import annotations

import shutil

import h5py
import pytest

from floorslide.run import journal
from floorslide.run.store import journal_dir, scene_digest, task_node, written_for
from floorslide.run.task import run_task
from tests.robustness.conftest import cli
from tests.run.test_runs import SCENE, assert_same, results

REFUSED = (
    "exists; not replaced (continue its run with --resume, same scene; or replace it with "
    "--overwrite)"
)


def run(scene, out, *args: str):
    return cli("run", str(scene), "-o", str(out), "--workers", "1", *args)


def other_scene(tmp_path):
    path = tmp_path / "other.toml"
    path.write_text(SCENE.replace('name = "test study"', 'name = "another study"'))
    return path


@pytest.fixture(params=["text", "study"])
def existing(request, reference_file, tmp_path):
    """Something a user keeps at the output path: notes, or a finished study's result."""
    path = tmp_path / "out.h5"
    if request.param == "text":
        path.write_text("field notes, not results\n")
    else:
        shutil.copyfile(reference_file, path)
    return path


def test_an_existing_file_is_refused_and_left_alone(the_plan, existing):
    before = existing.read_bytes()
    out = run(the_plan.scene.path, existing)
    assert out.returncode == 2 and not out.stdout, out.stderr
    assert out.stderr.strip() == f"floorslide: error: {existing}: {REFUSED}"
    assert existing.read_bytes() == before
    assert not journal_dir(existing).exists()


def test_the_journal_of_an_unfinished_run_is_refused(the_plan, reference_file, tmp_path):
    out = tmp_path / "r.h5"
    folder = journal_dir(out)
    folder.mkdir()
    (folder / "t00001.entry").write_bytes(b"a finished task")
    done = run(the_plan.scene.path, out)
    assert done.returncode == 2, done.stderr
    (line,) = done.stderr.strip().splitlines()
    assert line.startswith(f"floorslide: error: {folder}: holds 1 finished tasks of an unfin")
    assert "--resume" in line and "--overwrite" in line
    assert not out.exists() and (folder / "t00001.entry").exists()


def test_overwrite_replaces(the_plan, reference, existing):
    journal_dir(existing).mkdir()
    (journal_dir(existing) / "t00003.entry").write_bytes(b"from an older run")
    out = run(the_plan.scene.path, existing, "--overwrite")
    assert out.returncode == 0, out.stderr
    assert "9 tasks run, 0 already done" in out.stdout
    assert_same(results(existing), reference)
    assert not journal_dir(existing).exists()


def test_resume_refuses_what_is_not_a_run_of_the_scene(the_plan, reference_file, tmp_path):
    notes = tmp_path / "notes.h5"
    notes.write_text("field notes\n")
    out = run(the_plan.scene.path, notes, "--resume")
    assert out.returncode == 2 and notes.read_text() == "field notes\n"
    assert out.stderr.strip() == (
        f"floorslide: error: {notes}: not a floorslide result file; not replaced (choose "
        "another -o, or replace it with --overwrite)"
    )
    study = tmp_path / "study.h5"
    shutil.copyfile(reference_file, study)
    before = study.read_bytes()
    out = run(other_scene(tmp_path), study, "--resume")
    assert out.returncode == 2 and study.read_bytes() == before
    assert out.stderr.strip() == (
        f"floorslide: error: {study}: was written for a different scene; resume with the same "
        "scene file"
    )


def test_resume_and_overwrite_exclude_each_other(the_plan, tmp_path):
    out = run(the_plan.scene.path, tmp_path / "r.h5", "--resume", "--overwrite")
    assert out.returncode == 2 and "--resume and --overwrite exclude each other" in out.stderr
    assert not (tmp_path / "r.h5").exists()


def test_written_for(the_plan, reference_file, tmp_path):
    """What the demo may replace: a result of its own scene, even one a kill left unreadable
    (when its journal says which scene it was), and nothing else."""
    scene = the_plan.scene.text
    assert written_for(reference_file, scene)
    assert not written_for(reference_file, scene + "\n# another scene\n")
    assert not written_for(tmp_path / "missing.h5", scene)
    text = tmp_path / "notes.h5"
    text.write_text("notes")
    assert not written_for(text, scene)
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = 1
    assert not written_for(other, scene)
    cut = tmp_path / "cut.h5"
    cut.write_bytes(reference_file.read_bytes()[:3000])  # a kill in the middle of a write
    assert not written_for(cut, scene)  # no journal: whose it was is unknown
    folder = journal_dir(cut)
    folder.mkdir()
    (folder / "t00000.entry").write_bytes(b"not an entry")
    assert not written_for(cut, scene)
    result = run_task(the_plan.tasks[0])
    entry = journal.encode(result.task_id, scene_digest(scene), task_node(result))
    (folder / f"{result.task_id}.entry").write_bytes(entry)
    assert written_for(cut, scene)
    assert not written_for(cut, scene + "\n# another scene\n")
