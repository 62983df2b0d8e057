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
