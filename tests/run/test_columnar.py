"""Issue 34 part 1: the columnar result file (format 2). Its number of HDF5 objects does not
grow with the tasks; a file of format 1 reads as before and converts with ``floorslide
upgrade`` to the same tasks; a value changed in a column fails its task's digest."""

from __future__ import annotations

import shutil
from dataclasses import fields

import h5py
import numpy as np
import pytest

from floorslide.errors import ResultFileError
from floorslide.run.execute import execute
from floorslide.run.store import FORMAT, LEGACY_FORMAT, ResultFile, upgrade
from floorslide.scene.planner import plan
from floorslide.scene.schema import parse_scene
from tests.conftest import ROOT
from tests.robustness.conftest import cli

FORMAT1 = ROOT / "tests" / "data" / "format1" / "study.h5"
CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()


def scene(stations: list[str]) -> str:
    return f"""
[[records]]
set = "s"
catalog = "{CATALOG}"
where = {{ station_id = {stations!r} }}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.3

[[buildings]]
id = "iso"
kind = "isolated"
superstructure = "fixed"
period = 2.5
damping = 0.1

[[contents]]
id = "box"
floors = [0, 1]
mu = [0.05, 0.2]

[spectra]
floors = "all"
periods = [0.2, 1.0]
damping = [0.05]
"""


def objects(path) -> tuple[int, int]:
    counts = [0, 0]
    with h5py.File(path, "r") as f:

        def visit(name, obj):
            counts[0] += 1
            counts[1] += len(obj.attrs)

        f.visititems(visit)
    return counts[0], counts[1]


def assert_same_tasks(a, b):
    """Two TaskResults equal field by field, arrays with their dtypes (seconds aside)."""

    def same(x, y, where):
        if hasattr(x, "__dataclass_fields__"):
            for f in fields(x):
                same(getattr(x, f.name), getattr(y, f.name), f"{where}.{f.name}")
        elif isinstance(x, dict):
            assert x.keys() == y.keys(), where
            for k in x:
                same(x[k], y[k], f"{where}.{k}")
        elif isinstance(x, list):
            assert len(x) == len(y), where
            for i, (p, q) in enumerate(zip(x, y, strict=True)):
                same(p, q, f"{where}[{i}]")
        elif isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape, where
            np.testing.assert_array_equal(x, y, err_msg=where)
        else:
            assert type(x) is type(y), where
            assert x == y or (x != x and y != y), where

    same(a, b, a.task_id)


@pytest.fixture(scope="module")
def two_studies(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("columnar")
    out = {}
    for name, stations in (("small", ["PET-090", "RIO-360"]), ("large", None)):
        stations = stations or ["PET-090", "RIO-360", "ELC-180", "TAF-021"]
        path = tmp / f"{name}.toml"
        path.write_text(scene(stations))
        result = tmp / f"{name}.h5"
        execute(plan(parse_scene(path.read_text(), path)), str(result), workers=1, progress=False)
        out[name] = result
    return out


def test_the_object_count_does_not_grow_with_the_tasks(two_studies):
    small, large = (ResultFile(two_studies[k]) for k in ("small", "large"))
    assert small.format == FORMAT and len(small.done_tasks()) == 4
    assert len(large.done_tasks()) == 8
    n_small, n_large = objects(two_studies["small"]), objects(two_studies["large"])
    # histories: one record of the set, on each building, in both
    assert n_small == n_large and n_small[0] < 100, (n_small, n_large)


def test_a_format_1_file_reads_and_upgrades_to_the_same_tasks(tmp_path):
    old = ResultFile(FORMAT1)
    assert old.format == LEGACY_FORMAT and old.verified
    before = list(old.tasks())
    new, n = upgrade(FORMAT1, tmp_path / "new.h5")
    assert n == len(before) == 3
    rf = ResultFile(new)
    assert rf.format == FORMAT and rf.scene_text == old.scene_text and rf.plan == old.plan
    after = list(rf.tasks())
    for a, b in zip(before, after, strict=True):
        assert_same_tasks(a, b)
    assert objects(new)[0] < objects(FORMAT1)[0]
    # on the command line: in place, then refused as already converted
    copy = tmp_path / "copy.h5"
    shutil.copyfile(FORMAT1, copy)
    done = cli("upgrade", str(copy))
    assert done.returncode == 0 and done.stdout.strip() == f"{copy}: 3 tasks in the columnar format"
    assert ResultFile(copy).format == FORMAT
    again = cli("upgrade", str(copy))
    assert again.returncode == 2 and "already of format 2" in again.stderr
    assert cli("table", str(copy)).returncode == 0


def test_a_value_changed_in_a_column_fails_its_task_only(two_studies, tmp_path):
    path = tmp_path / "r.h5"
    shutil.copyfile(two_studies["small"], path)
    with h5py.File(path, "a") as f:
        row = 3
        task = int(f["contents/task"][row])
        tid = f["tasks/id"][task].decode()
        f["contents/peak_slide"][row] = f["contents/peak_slide"][row] + 0.01
    with pytest.raises(ResultFileError, match=f"task {tid} fails the integrity check"):
        list(ResultFile(path).tasks())
    assert list(ResultFile(path).verify()) == [tid]
    with h5py.File(path, "a") as f:
        other = (task + 1) % 4
        f["tasks/pga"][other] = 2 * f["tasks/pga"][other]  # an attribute of another task
    assert len(ResultFile(path).verify()) == 2


def test_resume_rebuilds_a_task_that_fails(two_studies, tmp_path):
    path = tmp_path / "r.h5"
    shutil.copyfile(two_studies["small"], path)
    reference = {t.task_id: t for t in ResultFile(path).tasks()}
    with h5py.File(path, "a") as f:
        f["spectra/psa"][0] = 0.0
        tid = f["tasks/id"][int(f["spectra/task"][0])].decode()
    p = plan(parse_scene(scene(["PET-090", "RIO-360"]), tmp_path / "s.toml"))
    summary = execute(p, str(path), workers=1, progress=False, resume=True)
    assert summary.ran == 1 and summary.resumed == 3
    again = {t.task_id: t for t in ResultFile(path).tasks()}
    assert again.keys() == reference.keys()
    np.testing.assert_array_equal(again[tid].spectra[0].psa, reference[tid].spectra[0].psa)


def test_upgrade_and_rebuild_in_several_batches(tmp_path, two_studies, monkeypatch):
    """Copies append tasks in batches, each committed before the next: with batches of 2 (the
    fixture's 3 tasks; a rebuild of 4) every task is kept — a later batch once overwrote the
    rows of the first (the demo's 288 tasks upgraded to 32)."""
    import floorslide.run.store as store

    monkeypatch.setattr(store, "COPY_BATCH", 2)
    new, n = upgrade(FORMAT1, tmp_path / "new.h5")
    rf = ResultFile(new)
    assert n == 3 and len(rf.done_tasks()) == 3 and rf.complete
    for a, b in zip(ResultFile(FORMAT1).tasks(), rf.tasks(), strict=True):
        assert_same_tasks(a, b)
    # a resume that rebuilds the file copies its tasks in batches too
    path = tmp_path / "r.h5"
    shutil.copyfile(two_studies["small"], path)
    with h5py.File(path, "a") as f:
        f["spectra/psa"][0] = 0.0
    p = plan(parse_scene(scene(["PET-090", "RIO-360"]), tmp_path / "s.toml"))
    summary = execute(p, str(path), workers=1, progress=False, resume=True)
    assert summary.ran == 1 and summary.resumed == 3
    assert len(ResultFile(path).done_tasks()) == 4 and not ResultFile(path).verify()


def test_the_writer_reads_the_columns_once_and_keeps_them_right(two_studies, tmp_path, monkeypatch):
    """After its first batch, the writer hands `columns.append` the columns it left in the file
    instead of reading them again: at every later batch they equal what the file holds (names,
    rows, kinds, types, shapes, attributes), and the file reads as one written without it."""
    from floorslide.run import columns, store

    real = store.append_tasks
    seen = {"known": 0, "read": 0}

    def checked(f, batch, expect, known=None):
        if known:
            seen["known"] += 1
            held = columns.load_schema(f)
            for t in columns.TABLES:
                a, b = known[t], held[t]
                assert (a.names, a.rows) == (b.names, b.rows), t
                for name in a.names:
                    x, y = a.columns[name], b.columns[name]
                    assert (x.kind, x.dtype, x.shape, x.attrs) == (
                        y.kind,
                        y.dtype,
                        y.shape,
                        y.attrs,
                    ), f"{t}/{name}"
        else:
            seen["read"] += 1
        return real(f, batch, expect, known)

    monkeypatch.setattr(store, "append_tasks", checked)
    path = tmp_path / "large.toml"
    path.write_text(scene(["PET-090", "RIO-360", "ELC-180", "TAF-021"]))
    out = tmp_path / "large.h5"
    execute(plan(parse_scene(path.read_text(), path)), str(out), workers=1, progress=False)
    assert seen == {"known": 7, "read": 1}  # 8 tasks, one batch each (fewer than 32)
    for a, b in zip(ResultFile(two_studies["large"]).tasks(), ResultFile(out).tasks(), strict=True):
        for r in (a, b):  # the time each task took differs from run to run
            r.seconds = 0.0
            r.meta.pop("seconds", None)
        assert_same_tasks(a, b)


def test_a_failed_batch_makes_the_writer_read_the_columns_again(tmp_path, monkeypatch):
    """A batch that failed may have left columns half-written: the next one reads the file."""
    from floorslide.run import store

    real = store.append_tasks
    calls: list[bool] = []

    def flaky(f, batch, expect, known=None):
        calls.append(bool(known))
        if len(calls) == 2:
            real(f, batch, expect, known)
            raise OSError(5, "Input/output error")
        return real(f, batch, expect, known)

    monkeypatch.setattr(store, "append_tasks", flaky)
    path = tmp_path / "s.toml"
    path.write_text(scene(["PET-090", "RIO-360"]))
    p = plan(parse_scene(path.read_text(), path))
    writer = store.ResultWriter(
        tmp_path / "s.h5", p.scene.text, p.scene.path, p.scene.name, p.summary(), batch=1
    )
    from floorslide.run.task import run_task

    results = [run_task(t) for t in p.tasks[:3]]
    writer.write(results[0])
    with pytest.raises(store.OutputError):
        writer.write(results[1])
    # an error HDF5 reported (the file closed after it) leaves no mark: no rebuild on resume
    assert not (store.journal_dir(tmp_path / "s.h5") / store.WRITING).exists()
    writer.write(results[2])
    assert calls == [False, True, False]
    writer.close()


def test_a_run_killed_while_writing_is_rebuilt_on_resume(tmp_path):
    """A process killed in the middle of a batch's write leaves the journal's mark; the resume
    says so and writes the file again from the tasks it holds (HDF5's own structures can be
    half-written even where the tasks read back: a later write then failed for ever)."""
    import os

    from floorslide.run import store
    from floorslide.run.task import run_task

    path = tmp_path / "s.toml"
    path.write_text(scene(["PET-090", "RIO-360"]))
    p = plan(parse_scene(path.read_text(), path))
    results = [run_task(t) for t in p.tasks]
    out = tmp_path / "s.h5"
    args = (out, p.scene.text, p.scene.path, p.scene.name, p.summary())
    pid = os.fork()
    if pid == 0:  # the run that is killed: its second batch is written, never committed
        try:
            real = store.append_tasks

            def killed(f, batch, expect, known=None):
                real(f, batch, expect, known)
                if batch[0][0] == results[1].task_id:
                    f.flush()
                    os._exit(9)

            store.append_tasks = killed
            w = store.ResultWriter(*args, batch=1)
            for r in results:
                w.write(r)
        finally:
            os._exit(1)
    _, status = os.waitpid(pid, 0)
    assert os.WEXITSTATUS(status) == 9
    assert (store.journal_dir(out) / store.WRITING).exists()
    warned: list[str] = []
    w = store.ResultWriter(*args, resume=True, warn=warned.append, batch=1)
    assert any("stopped while writing" in line for line in warned), warned
    assert not (store.journal_dir(out) / store.WRITING).exists()
    for r in results:
        if r.task_id not in w.done:
            w.write(r)
    w.finish()
    w.close()
    rf = ResultFile(out)
    assert rf.verified and sorted(rf.done_tasks()) == sorted(r.task_id for r in results)
    assert not store.journal_dir(out).exists()  # finished: the journal and its mark are gone
