"""Issue 19 item 4: each task carries a SHA-256 digest of its group; every reader checks it.
A value changed in place, a flipped byte in the data or in an object header: ``table``,
``plot`` and the Python reports refuse the file naming the task, ``--resume`` rebuilds it. A
file from before the digests reads, with a note that it is unverified.

Format 2 (issue 34) stores the tasks as rows of columns: a value edited in a row fails that
row's task; a damaged column (its object header, its dtype, its attributes) fails every task
that uses it. Files from before the digests were of format 1: those cases edit a format-1 copy
(tests/format1.py)."""

from __future__ import annotations

import json
import shutil

import h5py
import numpy as np
import pytest

from floorslide.errors import FloorslideError, ResultFileError
from floorslide.report import design_tables, plot_figures, record_table
from floorslide.report.study import load_study
from floorslide.run import columns
from floorslide.run.execute import execute
from floorslide.run.store import ResultFile
from tests.format1 import to_format1
from tests.robustness.conftest import cli
from tests.run.test_runs import assert_same, results

TASK = "t00004"
DATASET = "contents/peak_slide"
"""The column of the peak slides of every task, content, floor and friction pair."""


def task_row(f: h5py.File, tid: str) -> int:
    """The row of task `tid` in the task table."""
    n = int(f["tasks"].attrs["rows"])
    return [columns._text(x) for x in f["tasks/id"][:n]].index(tid)


def row(f: h5py.File, tid: str = TASK, content="cabinet", floor=2, pair=0) -> int:
    """The row of the contents table of (task, content, floor, friction pair)."""
    c = f["contents"]
    n = int(c.attrs["rows"])
    names = np.array([columns._text(x) for x in c["content"][:n]])
    hit = np.flatnonzero(
        (c["task"][:n] == task_row(f, tid))
        & (names == content)
        & (c["floor"][:n] == floor)
        & (c["pair"][:n] == pair)
    )
    assert hit.size == 1, hit
    return int(hit[0])


def users(f: h5py.File, column: str) -> set[str]:
    """The tasks with a value in `column` of the contents table."""
    c = f["contents"]
    n = int(c.attrs["rows"])
    names = json.loads(c.attrs["names"])
    rows = c["task"][:n][c["present"][:n, names.index(column)].astype(bool)]
    ids = [columns._text(x) for x in f["tasks/id"][: int(f["tasks"].attrs["rows"])]]
    return {ids[int(r)] for r in rows}


@pytest.fixture()
def copy(reference_file, tmp_path):
    """A fresh copy of the reference result file (no journal beside it)."""
    out = tmp_path / "r.h5"
    shutil.copyfile(reference_file, out)
    return out


def header_message(path, dataset: str, kind: int) -> int:
    """File offset of the body of the first message of type `kind` in the (version 1) object
    header of `dataset` (HDF5 file format specification, IV.A.1.a)."""
    with h5py.File(path, "r") as f:
        addr = h5py.h5o.get_info(f[dataset].id).addr
    raw = path.read_bytes()
    assert raw[addr] == 1, "not a version 1 object header"
    pos = addr + 16
    for _ in range(int.from_bytes(raw[addr + 2 : addr + 4], "little")):
        size = int.from_bytes(raw[pos + 2 : pos + 4], "little")
        if int.from_bytes(raw[pos : pos + 2], "little") == kind:
            return pos + 8
        pos += 8 + size
    raise AssertionError(f"no message {kind}")


def flip(path, offset: int, mask: int) -> None:
    raw = bytearray(path.read_bytes())
    raw[offset] ^= mask
    path.write_bytes(bytes(raw))


def test_a_value_changed_in_place_is_refused_by_every_report(copy, tmp_path):
    with h5py.File(copy, "a") as f:
        f[DATASET][row(f, pair=1)] *= 1.01  # a plausible, wrong value
    out = cli("table", str(copy))
    assert out.returncode == 2 and not out.stdout, out.stderr
    (line,) = out.stderr.strip().splitlines()
    assert line.startswith(f"floorslide: error: {copy}: task {TASK} fails the integrity check")
    assert "values changed after it was written" in line and "--resume" in line
    for report in (design_tables, record_table):
        with pytest.raises(ResultFileError, match=f"task {TASK} fails the integrity check"):
            report(copy)
    with pytest.raises(ResultFileError, match=f"task {TASK} fails"):
        plot_figures(copy, tmp_path / "figures")
    out = cli("plot", str(copy), "-o", str(tmp_path / "fig"))
    assert out.returncode == 2 and f"task {TASK} fails the integrity check" in out.stderr


def test_every_failing_task_is_named(copy):
    with h5py.File(copy, "a") as f:
        for tid in ("t00001", "t00006"):
            f["tasks/pga"][task_row(f, tid)] = 0.0  # attributes count too
        f[DATASET][row(f, "t00002")] += 1e-3
    with pytest.raises(ResultFileError) as err:
        list(ResultFile(copy).tasks())
    assert str(err.value).startswith(f"{copy}: tasks t00001 (values changed")
    assert "t00002 (" in str(err.value) and "t00006 (" in str(err.value)
    assert "t00000" not in str(err.value)


def test_a_column_attribute_changed_fails_every_task_using_it(copy):
    with h5py.File(copy, "a") as f:
        f["tasks/pfa"].attrs["units"] = "g"  # the units of every task's pfa
        tids = [columns._text(x) for x in f["tasks/id"][: int(f["tasks"].attrs["rows"])]]
    problems = ResultFile(copy).verify()
    assert set(problems) == set(tids) and len(tids) == 9
    assert set(problems.values()) == {"values changed after it was written"}


def test_resume_rebuilds_the_task_that_fails(the_plan, reference, copy):
    with h5py.File(copy, "a") as f:
        f[DATASET][row(f)] = 0.123
    warned = []
    summary = execute(
        the_plan, str(copy), workers=1, progress=False, resume=True, warn=warned.append
    )
    assert summary.ran == 1 and summary.resumed == 8
    assert warned == [
        f"{copy}: task {TASK} fails the integrity check (values changed after it "
        "was written); rebuilt"
    ]
    assert_same(results(copy), reference)


def test_a_flipped_data_byte_is_refused_then_rebuilt(the_plan, reference, copy):
    with h5py.File(copy, "r") as f:
        ds = f[DATASET]
        r = row(f)
        chunk = r // ds.chunks[0]
        offset = ds.id.get_chunk_info_by_coord((chunk * ds.chunks[0],)).byte_offset
        offset += (r - chunk * ds.chunks[0]) * ds.dtype.itemsize
    flip(copy, offset + 3, 0x01)  # the third byte of the task's first peak slide
    out = cli("table", str(copy))
    assert out.returncode == 2 and f"task {TASK} fails the integrity check" in out.stderr
    done = cli("run", str(the_plan.scene.path), "-o", str(copy), "--resume", "--workers", "1")
    assert done.returncode == 0, done.stderr
    assert "1 tasks run, 8 already done" in done.stdout
    assert_same(results(copy), reference)


def test_resume_on_a_damaged_object_header_without_journal(the_plan, reference, copy):
    """A flipped version of a dataset's datatype message (the kind of flip that made
    ``--resume`` end in a KeyError traceback): in format 2 the dataset is a column, so every
    task with a value in it is reported, and since HDF5 cannot delete such a dataset, the
    file is rewritten without them and they are rebuilt."""
    with h5py.File(copy, "r") as f:
        tids = users(f, "peak_slide")
    assert TASK in tids
    flip(copy, header_message(copy, DATASET, kind=3), 0x70)
    every = r"t00000 \(unreadable: /contents/peak_slide: .* and 6 more fail"
    with pytest.raises(ResultFileError, match=every):
        list(ResultFile(copy).tasks())
    assert set(ResultFile(copy).verify()) == tids
    done = cli("run", str(the_plan.scene.path), "-o", str(copy), "--resume", "--workers", "1")
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == len(tids), lines
    for tid, line in zip(sorted(tids), lines, strict=True):
        assert line.startswith(f"floorslide: warning: {copy}: task {tid} fails the integrity")
    assert f"{len(tids)} tasks run, {9 - len(tids)} already done" in done.stdout
    assert_same(results(copy), reference)
    assert cli("table", str(copy)).returncode == 0


def test_a_file_from_before_the_digests_reads_unverified(reference, copy):
    to_format1(copy)  # files from before the digests were of format 1
    with h5py.File(copy, "a") as f:
        del f.attrs["task_digest"]
        for task in f["tasks"].values():
            del task.attrs["sha256"]
    assert not ResultFile(copy).verified
    assert_same(results(copy), reference)
    out = cli("table", str(copy))
    assert out.returncode == 0, out.stderr
    (line,) = out.stderr.strip().splitlines()
    assert line == (
        f"floorslide: note: {copy}: written before floorslide kept task digests: its values "
        "are read unverified"
    )


def test_a_digest_removed_from_a_task_is_refused(copy):
    with h5py.File(copy, "a") as f:
        f["tasks/sha256"][task_row(f, TASK)] = ""
    with pytest.raises(ResultFileError, match=f"task {TASK} fails the integrity check \\(no dig"):
        list(ResultFile(copy).tasks())


def test_a_digest_removed_from_a_format1_task_is_refused(copy):
    to_format1(copy)
    with h5py.File(copy, "a") as f:
        del f[f"tasks/{TASK}"].attrs["sha256"]
    with pytest.raises(ResultFileError, match=f"task {TASK} fails the integrity check \\(no dig"):
        list(ResultFile(copy).tasks())


def test_digest_covers_the_dtype_of_a_column(copy):
    """The same numbers stored with another dtype fail every task that has them."""
    with h5py.File(copy, "a") as f:
        ds = f[DATASET]
        data, attrs, chunks = ds[()], dict(ds.attrs), ds.chunks
        tids = users(f, "peak_slide")
        del f[DATASET]
        new = f.create_dataset(
            DATASET, data=data.astype(np.float32), chunks=chunks, maxshape=(None,)
        )
        new.attrs.update(attrs)
    assert set(ResultFile(copy).verify()) == tids and TASK in tids


def test_digest_covers_values_dtypes_shapes_and_attributes(copy):
    """The same numbers stored with another dtype or shape fail too (format 1: a group per
    task, read by the reader of format 1)."""
    to_format1(copy)
    with h5py.File(copy, "a") as f:
        g = f[f"tasks/{TASK}"]
        pfa = g["pfa"][()]
        del g["pfa"]
        g.create_dataset("pfa", data=pfa.astype(np.float32).astype(np.float64).reshape(1, -1))
        g["pfa"].attrs["units"] = "m/s**2"
    with pytest.raises(ResultFileError, match=f"task {TASK} fails"):
        list(ResultFile(copy).tasks())


def flipped_copies(reference_file, tmp_path, n: int, seed: int):
    """`n` copies of the reference file, each with one bit flipped anywhere in it."""
    raw = reference_file.read_bytes()
    rng = np.random.default_rng(seed)
    for k in range(n):
        damaged = bytearray(raw)
        pos = int(rng.integers(0, len(raw)))
        damaged[pos] ^= 1 << int(rng.integers(0, 8))
        path = tmp_path / f"flip{k}" / "r.h5"
        path.parent.mkdir()
        path.write_bytes(bytes(damaged))
        yield pos, path


def test_a_flipped_bit_anywhere_is_refused_or_harmless(reference_file, reference, tmp_path):
    """Reading a file with one bit flipped anywhere gives the reference values or a one-line
    ResultFileError — never other values, never another exception."""
    outcomes = {"same": 0, "refused": 0}
    for pos, path in flipped_copies(reference_file, tmp_path, 60, seed=19):
        try:
            got = results(path)
            load_study(path)
        except ResultFileError as exc:
            assert "\n" not in str(exc), pos
            outcomes["refused"] += 1
            continue
        assert_same(got, reference)
        outcomes["same"] += 1
    assert outcomes["refused"] > 20, outcomes  # most of the file is task data


def test_resume_after_a_flipped_bit_anywhere(the_plan, reference_file, reference, tmp_path):
    """``--resume`` on such a file without a journal completes the same results (rebuilding
    what fails) or stops with a one-line floorslide error: never a traceback."""
    for pos, path in flipped_copies(reference_file, tmp_path, 12, seed=7):
        try:
            execute(the_plan, str(path), workers=1, progress=False, resume=True, warn=print)
        except FloorslideError as exc:
            assert "\n" not in str(exc), pos
            continue
        assert_same(results(path), reference)
