"""``--resume`` keeps a finished task only if its inputs are the ones this run would compute it
from: each task stores the fingerprint of its inputs (the record's processed samples, scale,
building, contents, spectra, floorslide's version), the plan lists them, and a task (or journal
entry) with another fingerprint runs again, said in one line. The stored scene and plan carry a
digest; a second writer is refused while a run holds the output's lock."""

from __future__ import annotations

import csv
import json
import shutil

import h5py
import numpy as np
import pytest

import floorslide
from floorslide.errors import OutputExistsError, ResultFileError
from floorslide.run.execute import execute
from floorslide.run.fingerprint import task_fingerprints
from floorslide.run.store import (
    HEADER_DIGEST_ATTR,
    ResultFile,
    ResultWriter,
    header_digest,
    journal_entries,
)
from floorslide.run.task import run_task
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene
from tests.conftest import ROOT
from tests.robustness.conftest import cli, without_tasks
from tests.run.test_runs import SCENE, assert_same, results

SLAMMER = ROOT / "data" / "records" / "slammer"
STATIONS = ("PET-090", "RIO-360", "ELC-180")


def catalog_scene(folder, stations=STATIONS):
    """A copy of the test study reading a catalog of its own in `folder` (the records copied
    beside it), so that its rows and files can be changed."""
    folder.mkdir(exist_ok=True)
    with open(SLAMMER / "index.csv", newline="") as fh:
        rows = [r for r in csv.DictReader(fh) if r["station_id"] in stations]
    write_catalog(folder, rows)
    for r in rows:
        shutil.copyfile(SLAMMER / r["file"], folder / r["file"])
    scene = folder / "study.toml"
    old = (SLAMMER / "index.csv").as_posix()
    text = SCENE.replace(old, "index.csv")
    text = "\n".join(line for line in text.splitlines() if not line.startswith("where = "))
    scene.write_text(text + "\n")
    return scene, rows


def write_catalog(folder, rows):
    with open(folder / "index.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def planned(scene):
    return plan(load_scene(scene), evaluate=False)


def drop_tasks(path, tids):
    """Leave `path` as a run killed before these tasks were written."""
    without_tasks(path, tids)


def test_a_deleted_catalog_row_never_mixes_records(tmp_path):
    """Before: the ids shifted, old tasks were kept under new ids' names (fixed and isolated
    buildings then held different records) or the file stayed INCOMPLETE forever."""
    scene, rows = catalog_scene(tmp_path / "study")
    out = tmp_path / "out.h5"
    execute(planned(scene), str(out), workers=1, progress=False)
    drop_tasks(out, ["t00007", "t00008"])  # killed near the end
    write_catalog(scene.parent, rows[1:])  # then a row deleted
    lines: list[str] = []
    new = planned(scene)
    summary = execute(new, str(out), workers=1, progress=False, resume=True, warn=lines.append)
    # the second record is now the history record (its tasks keep histories: they run
    # again), the third's finished task keeps its results under its new id, two never ran
    assert (summary.tasks, summary.ran, summary.resumed) == (6, 5, 1)
    said = " ".join(lines)
    assert "1 finished tasks keep their results under new task ids" in said
    assert "6 finished tasks were computed from other inputs" in said
    fresh = tmp_path / "fresh.h5"
    execute(new, str(fresh), workers=1, progress=False)
    assert_same(results(out), results(fresh))
    rf = ResultFile(out)
    assert rf.complete and rf.planned_tasks == 6 and len(rf.done_tasks()) == 6
    by_task = {t.task_id: t.meta["record"] for t in rf.tasks()}
    assert by_task == {t.task_id: t.record.record for t in new.tasks}


def test_a_replaced_record_runs_again(tmp_path):
    scene, rows = catalog_scene(tmp_path / "study")
    out = tmp_path / "out.h5"
    execute(planned(scene), str(out), workers=1, progress=False)
    drop_tasks(out, ["t00008"])
    record = scene.parent / rows[0]["file"]
    text = record.read_text().splitlines()
    record.write_text("\n".join(text[:-40]) + "\n")  # the same name, other samples
    with open(scene.parent / "index.csv", newline="") as fh:
        fixed = list(csv.DictReader(fh))
    fixed[0]["npts"] = str(int(fixed[0]["npts"]) - 40)
    write_catalog(scene.parent, fixed)
    lines: list[str] = []
    new = planned(scene)
    summary = execute(new, str(out), workers=1, progress=False, resume=True, warn=lines.append)
    n_record = sum(t.record.record == new.tasks[0].record.record for t in new.tasks)
    assert summary.ran == n_record + 1, lines
    assert any("were computed from other inputs" in line for line in lines)
    fresh = tmp_path / "fresh.h5"
    execute(new, str(fresh), workers=1, progress=False)
    assert_same(results(out), results(fresh))


def test_an_upgraded_floorslide_runs_everything_again(the_plan, reference, tmp_path, monkeypatch):
    out = tmp_path / "out.h5"
    execute(the_plan, str(out), workers=1, progress=False)
    drop_tasks(out, ["t00004"])
    monkeypatch.setattr(floorslide, "__version__", floorslide.__version__ + ".later")
    lines: list[str] = []
    summary = execute(the_plan, str(out), workers=1, progress=False, resume=True, warn=lines.append)
    assert summary.ran == 9 and summary.resumed == 0
    assert any("8 finished tasks were computed from other inputs" in line for line in lines)
    assert_same(results(out), reference)


def test_journal_entries_of_other_inputs_are_refused(the_plan, reference, tmp_path):
    out = tmp_path / "out.h5"
    prints = task_fingerprints(the_plan.tasks)
    stale = {tid: "0" * 64 for tid in prints}  # as if computed from other samples
    sc = the_plan.scene
    writer = ResultWriter(out, sc.text, sc.path, sc.name, the_plan.summary(), fingerprints=stale)
    for task in the_plan.tasks[:3]:
        writer.write(run_task(task))
    writer.close()
    out.unlink()  # only the journal is left
    assert len(journal_entries(out)) == 3
    lines: list[str] = []
    summary = execute(the_plan, str(out), workers=1, progress=False, resume=True, warn=lines.append)
    assert summary.ran == 9
    refused = [line for line in lines if "refused (computed from other inputs" in line]
    assert len(refused) == 3, lines
    assert_same(results(out), reference)


def test_each_task_and_the_plan_carry_the_fingerprint(the_plan, reference_file):
    rf = ResultFile(reference_file)
    prints = task_fingerprints(the_plan.tasks)
    assert rf.planned_fingerprints == prints
    assert rf.fingerprints(rf.done_tasks()) == prints
    assert len(set(prints.values())) == len(prints)


@pytest.fixture()
def copy(reference_file, tmp_path):
    path = tmp_path / "r.h5"
    shutil.copyfile(reference_file, path)
    return path


def test_a_changed_plan_is_refused_then_rebuilt(the_plan, reference, copy):
    """Before: one flipped bit in the stored task count made a half-finished file read as
    complete. The header's digest refuses it; --resume writes it again."""
    with h5py.File(copy, "a") as f:
        stored = json.loads(f["plan"][()])
        stored["tasks"] = 8
        del f["plan"]
        f.create_dataset("plan", data=json.dumps(stored))
    with pytest.raises(ResultFileError, match="stored scene and plan fail their integrity"):
        ResultFile(copy)
    done = cli("table", str(copy))
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1
    lines: list[str] = []
    execute(the_plan, str(copy), workers=1, progress=False, resume=True, warn=lines.append)
    assert any("fail their integrity check" in line for line in lines)
    assert ResultFile(copy).planned_tasks == 9
    assert_same(results(copy), reference)


def test_a_changed_scene_text_or_root_attribute_is_refused(copy):
    with h5py.File(copy, "a") as f:
        f.attrs["task_digest"] = "sha256-1"  # would turn task verification's header check off
    with pytest.raises(ResultFileError, match="integrity check"):
        ResultFile(copy)


def test_mixed_tasks_are_refused_by_every_reader(copy):
    """A task whose inputs are not those the plan lists (two runs mixed) is never read as
    part of the study, even with a valid task digest."""
    with h5py.File(copy, "a") as f:
        stored = json.loads(f["plan"][()])
        stored["fingerprints"]["t00002"] = "f" * 64
        del f["plan"]
        f.create_dataset("plan", data=json.dumps(stored))
        f.attrs[HEADER_DIGEST_ATTR] = header_digest(f)
    with pytest.raises(ResultFileError, match=r"t00002 .*two runs mixed"):
        list(ResultFile(copy).tasks())


def test_a_second_writer_is_refused_while_a_run_holds_the_lock(the_plan, tmp_path):
    """Before: run B with --overwrite deleted run A's journal; A then reported tasks that were
    in neither the file nor the journal."""
    out = tmp_path / "out.h5"
    sc = the_plan.scene
    prints = task_fingerprints(the_plan.tasks)
    with ResultWriter(out, sc.text, sc.path, sc.name, the_plan.summary(), fingerprints=prints) as a:
        a.write(run_task(the_plan.tasks[0]))
        for flag in ("--overwrite", "--resume"):
            done = cli("run", str(sc.path), "-o", str(out), "--workers", "1", flag)
            assert done.returncode == 2, done.stderr
            (line,) = done.stderr.strip().splitlines()
            assert line == (
                f"floorslide: error: {out}: is being written by another floorslide run (its "
                "journal is locked); wait for that run to end, or write to another file"
            )
        with pytest.raises(OutputExistsError, match="being written by another"):
            ResultWriter(out, sc.text, sc.path, sc.name, {}, overwrite=True)
        assert len(journal_entries(out)) == 1
        a.write(run_task(the_plan.tasks[1]))
        assert len(ResultFile(out).done_tasks()) == 2
    # released: the next run resumes it
    done = cli("run", str(sc.path), "-o", str(out), "--workers", "1", "--resume")
    assert done.returncode == 0, done.stderr
    assert "7 tasks run, 2 already done" in done.stdout


def test_fingerprints_are_the_same_in_every_process(the_plan):
    import subprocess
    import sys

    code = (
        "import json,sys; from floorslide.scene.planner import plan; "
        "from floorslide.scene.schema import load_scene; "
        "from floorslide.run.fingerprint import task_fingerprints; "
        f"print(json.dumps(task_fingerprints(plan(load_scene({str(the_plan.scene.path)!r}), "
        "evaluate=False).tasks)))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(out.stdout) == task_fingerprints(the_plan.tasks)
    assert np.all([len(v) == 64 for v in task_fingerprints(the_plan.tasks).values()])
