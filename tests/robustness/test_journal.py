"""Issue 19 item 3: the journal cannot run code. A planted pickle (the old journal format), a
pickle under an entry's name, a damaged entry, an entry of another scene or of no task of the
run: each is refused in one warning line naming it, and its task runs again."""

from __future__ import annotations

import json
import pickle
import struct

import numpy as np
import pytest

from floorslide.errors import OutputError
from floorslide.run import journal
from floorslide.run.execute import execute
from floorslide.run.snapshot import Node, digest
from floorslide.run.store import ENTRY_SUFFIX, journal_dir, journal_entries, task_node
from tests.robustness.conftest import cli
from tests.robustness.test_faults import fail_after
from tests.run.test_runs import assert_same, results


class Payload:
    """Unpickling it creates the file `marker` (what a planted journal entry could do)."""

    def __init__(self, marker):
        self.marker = str(marker)

    def __reduce__(self):
        return (open, (self.marker, "w"))


def interrupted_run(the_plan, out, monkeypatch, n=5):
    """A run stopped by a full disk at the n-th task: n tasks journaled, n - 1 in the file."""
    fail_after(monkeypatch, n)
    with pytest.raises(OutputError):
        execute(the_plan, str(out), workers=1, progress=False)
    monkeypatch.undo()
    assert len(journal_entries(out)) == n


def test_planted_pickles_never_run(the_plan, reference, tmp_path, monkeypatch):
    out = tmp_path / "r.h5"
    interrupted_run(the_plan, out, monkeypatch)
    folder = journal_dir(out)
    marker = tmp_path / "pwned"
    payload = pickle.dumps(Payload(marker))
    (folder / "t00007.pkl").write_bytes(payload)  # the old journal's format
    (folder / f"t00004{ENTRY_SUFFIX}").write_bytes(payload)  # a pickle under an entry's name
    scene = the_plan.scene.path
    done = cli("run", str(scene), "-o", str(out), "--resume", "--workers", "1")
    assert done.returncode == 0, done.stderr
    assert not marker.exists()
    warnings = done.stderr.strip().splitlines()
    assert len(warnings) == 2 and "Traceback" not in done.stderr, done.stderr
    assert warnings[0].startswith(f"floorslide: warning: {folder / 't00004.entry'}: refused")
    assert "not a floorslide journal entry" in warnings[0]
    assert warnings[1].startswith(f"floorslide: warning: {folder / 't00007.pkl'}: refused")
    assert "9 tasks run" not in done.stdout and "already done" in done.stdout
    assert_same(results(out), reference)


def rewrite_header(data: bytes, change) -> bytes:
    """An entry's bytes with its JSON header changed by `change(header)`."""
    start = len(journal.MAGIC) + 8
    (size,) = struct.unpack("<Q", data[len(journal.MAGIC) : start])
    header = json.loads(data[start : start + size])
    change(header)
    text = json.dumps(header).encode()
    return journal.MAGIC + struct.pack("<Q", len(text)) + text + data[start + size :]


def test_foreign_or_damaged_entries_are_refused(the_plan, reference, tmp_path, monkeypatch):
    out = tmp_path / "r.h5"
    interrupted_run(the_plan, out, monkeypatch, n=6)
    out.unlink()  # lost: --resume rebuilds the file from the journal
    folder = journal_dir(out)
    path = {i: folder / f"t0000{i}{ENTRY_SUFFIX}" for i in range(6)}

    def object_dtype(header):
        header["group"]["datasets"]["pfa"]["value"]["dtype"] = "|O"

    path[0].write_bytes(rewrite_header(path[0].read_bytes(), object_dtype))
    path[1].write_bytes(journal.encode("t00001", "0" * 64, Node({"x": 1})))  # another scene
    path[2].write_bytes(path[2].read_bytes()[:-50])  # cut short
    flipped = bytearray(path[3].read_bytes())
    flipped[-20] ^= 0x10  # a value changed: its digest no longer matches
    path[3].write_bytes(bytes(flipped))
    warned = []
    summary = execute(
        the_plan, str(out), workers=1, progress=False, resume=True, warn=warned.append
    )
    assert len(warned) == 4, warned
    for i, line in enumerate(warned):
        assert line.startswith(f"{path[i]}: refused (") and line.endswith("its task runs again")
    assert "dtype" in warned[0] and "another scene" in warned[1]
    assert "cut short" in warned[2] or "beyond the end" in warned[2]
    assert "digest" in warned[3]
    assert summary.ran == 7 and summary.resumed == 2
    assert_same(results(out), reference)


def test_every_damaged_entry_is_refused_or_read_right(the_plan):
    """Flip bits all over a real entry: decoding either refuses it or gives the same task."""
    from floorslide.run.task import run_task

    result = run_task(the_plan.tasks[4])
    node = task_node(result)
    data = journal.encode(result.task_id, "a" * 64, node)
    want = digest(node)
    positions = np.random.default_rng(19).integers(0, len(data), 400)
    outcomes = {"refused": 0, "same": 0}
    for k, pos in enumerate(positions):
        damaged = bytearray(data)
        damaged[pos] ^= 1 << (k % 8)
        try:
            tid, got = journal.decode(bytes(damaged), "a" * 64)
        except journal.EntryError:
            outcomes["refused"] += 1
            continue
        assert tid == result.task_id and digest(got) == want
        outcomes["same"] += 1
    assert outcomes["refused"] > 350, outcomes


def test_a_damaged_task_id_is_refused(the_plan):
    """The group's digest does not cover the id in the header: a flipped bit there (found by
    the bit-flip test above: 't00004' read as 't00000') is refused by the id's own digest;
    an entry written before that digest was kept still reads."""
    import json
    import struct

    from floorslide.run.task import run_task

    result = run_task(the_plan.tasks[4])
    node = task_node(result)
    data = journal.encode(result.task_id, "a" * 64, node)
    at = data.index(result.task_id.encode())
    for bit in range(7):
        damaged = bytearray(data)
        damaged[at + len(result.task_id) - 1] ^= 1 << bit
        with pytest.raises(journal.EntryError):
            journal.decode(bytes(damaged), "a" * 64)
    start = len(journal.MAGIC) + 8
    (size,) = struct.unpack("<Q", data[len(journal.MAGIC) : start])
    header = json.loads(data[start : start + size])
    del header["id_sha256"]
    text = json.dumps(header).encode()
    old = journal.MAGIC + struct.pack("<Q", len(text)) + text + data[start + size :]
    tid, got = journal.decode(old, "a" * 64)
    assert tid == result.task_id and digest(got) == digest(node)


@pytest.mark.parametrize("code", [",", "(2,)f8", "O", "V8", "f8,f8", "<U4"])
def test_a_type_string_other_than_a_plain_number_is_refused(code):
    """NumPy's dtype parser evaluates type strings like ',' (a SyntaxError escaped the
    journal's checks, found by the bit-flip test): only byte order + kind + size pass."""
    from floorslide.run.journal import EntryError, _decode_value

    spec = {"dtype": code, "shape": [1], "offset": 0, "nbytes": 8}
    with pytest.raises(EntryError):
        _decode_value(spec, memoryview(b"\0" * 8))
