"""Issue 19 item 5: a full disk ends a run with one line — "no space left on device writing
PATH; N tasks kept; free space and rerun with --resume" — and exit code 1: no traceback, no
crash, no worker process left behind, no journaled task lost. ENOSPC is injected at the k-th
task into the journal's write, into the reservation of disk space before the HDF5 write and
into the HDF5 write itself; where user namespaces allow it, a real 2 MB file system is filled."""

from __future__ import annotations

import errno
import os
import shutil
import subprocess
import sys
import textwrap
import time

import psutil
import pytest

from floorslide.errors import OutputError
from floorslide.run import store
from floorslide.run.execute import execute
from floorslide.run.store import ENTRY_SUFFIX, ResultFile, journal_entries
from tests.conftest import ROOT
from tests.robustness.conftest import cli
from tests.run.test_runs import assert_same, results

JOURNAL_FAILS = """
real = store._write_file
calls = []
def flaky(path, data):
    if path.name.endswith(store.ENTRY_SUFFIX):
        calls.append(path)
        if len(calls) == K:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
    return real(path, data)
store._write_file = flaky
"""

RESERVE_FAILS = """
real = store._fallocate
calls = []
def flaky(fd, offset, length):
    calls.append(fd)
    if len(calls) == 2 * K - 1:  # two reservations per task: the write, then the done mark
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    return real(fd, offset, length)
store._fallocate = flaky
"""


def inject(monkeypatch, patch: str, k: int) -> None:
    """Run `patch` (one of the above) in this process."""
    namespace = {"store": store, "errno": errno, "os": os, "K": k}
    exec(patch, namespace)
    monkeypatch.setattr(store, "_write_file", namespace["store"]._write_file)
    monkeypatch.setattr(store, "_fallocate", namespace["store"]._fallocate)


def test_full_disk_writing_the_journal(the_plan, reference, tmp_path, monkeypatch):
    out = tmp_path / "j.h5"
    real_write, real_fallocate = store._write_file, store._fallocate
    inject(monkeypatch, JOURNAL_FAILS, 4)
    assert store._fallocate is real_fallocate and store._write_file is not real_write
    with pytest.raises(OutputError) as err:
        execute(the_plan, str(out), workers=1, progress=False)
    entry = out.with_name(out.name + ".journal") / f"t00003{ENTRY_SUFFIX}"
    assert str(err.value) == (
        f"no space left on device writing {entry}; 3 tasks kept; free space and rerun with --resume"
    )
    assert len(journal_entries(out)) == 3 and len(ResultFile(out).done_tasks()) == 3
    assert not list(entry.parent.glob("*.tmp"))  # the cut entry is removed, its space freed
    monkeypatch.undo()
    summary = execute(the_plan, str(out), workers=1, progress=False, resume=True)
    assert summary.resumed == 3 and summary.ran == 6
    assert_same(results(out), reference)


def test_full_disk_before_the_hdf5_write(the_plan, reference, tmp_path, monkeypatch):
    out = tmp_path / "h.h5"
    inject(monkeypatch, RESERVE_FAILS, 5)
    with pytest.raises(OutputError) as err:
        execute(the_plan, str(out), workers=1, progress=False)
    assert str(err.value) == (
        f"no space left on device writing {out}; 5 tasks kept; free space and rerun with --resume"
    )
    size = out.stat().st_size
    assert len(ResultFile(out).done_tasks()) == 4 and len(journal_entries(out)) == 5
    monkeypatch.undo()
    summary = execute(the_plan, str(out), workers=1, progress=False, resume=True)
    assert summary.resumed == 5 and summary.ran == 4
    assert_same(results(out), reference)
    assert out.stat().st_size > size


def test_full_disk_at_the_first_task_leaves_nothing(the_plan, tmp_path, monkeypatch):
    """Nothing was kept: the new file goes too, so the same command can simply run again."""
    out = tmp_path / "first.h5"
    inject(monkeypatch, JOURNAL_FAILS, 1)
    with pytest.raises(OutputError, match="; 0 tasks kept;"):
        execute(the_plan, str(out), workers=1, progress=False)
    assert not out.exists() and not out.with_name(out.name + ".journal").exists()


def leftover_processes(marker: str) -> list[psutil.Process]:
    found = []
    for p in psutil.process_iter(["cmdline"]):
        with_marker = marker in " ".join(p.info["cmdline"] or [])
        if with_marker and p.pid != os.getpid():
            found.append(p)
    return found


@pytest.mark.parametrize("patch", [JOURNAL_FAILS, RESERVE_FAILS], ids=["journal", "hdf5"])
def test_full_disk_on_the_command_line(patch, the_plan, reference, tmp_path):
    """Two worker processes: one line, exit code 1, no worker left, then --resume completes."""
    out = tmp_path / "cli.h5"
    args = ["run", str(the_plan.scene.path), "-o", str(out), "--workers", "2"]
    code = textwrap.dedent(
        f"""
        import errno, os, sys
        from floorslide.run import store
        K = 5
        {textwrap.indent(patch, " " * 8).strip()}
        from floorslide.cli import main
        sys.argv = ["floorslide", *{args!r}]
        main()
        """
    )
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300
    )
    assert proc.returncode == 1, proc.stderr
    (line,) = proc.stderr.strip().splitlines()
    assert line.startswith("floorslide: error: no space left on device writing ")
    assert line.endswith("tasks kept; free space and rerun with --resume")
    time.sleep(0.5)
    assert not leftover_processes(str(out))
    kept = len(journal_entries(out))
    assert f"; {kept} tasks kept;" in line
    done = cli("run", str(the_plan.scene.path), "-o", str(out), "--resume", "--workers", "2")
    assert done.returncode == 0, done.stderr
    assert f"{9 - kept} tasks run, {kept} already done" in done.stdout
    assert_same(results(out), reference)


def _can_mount_tmpfs(folder) -> bool:
    if not shutil.which("unshare"):
        return False
    probe = subprocess.run(
        ["unshare", "-rm", "sh", "-c", f"mount -t tmpfs -o size=1m none {folder}"],
        capture_output=True,
    )
    return probe.returncode == 0


def test_a_real_full_file_system(the_plan, reference, tmp_path):
    """A 2 MB tmpfs in a user namespace (skipped where they are not allowed): the run stops
    with the one line; once the file system is grown, --resume completes the same results."""
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    if not _can_mount_tmpfs(mnt):
        pytest.skip("cannot mount a tmpfs in a user namespace here")
    out = mnt / "r.h5"
    run = f"{sys.executable} -m floorslide.cli run {the_plan.scene.path} -o {out} --workers 2"
    script = f"""
        mount -t tmpfs -o size=2m none {mnt} || exit 90
        {run} > {tmp_path}/out1 2> {tmp_path}/err1; echo $? > {tmp_path}/rc1
        ls {out}.journal | wc -l > {tmp_path}/kept
        mount -o remount,size=20m {mnt} || exit 91
        {run} --resume > {tmp_path}/out2 2> {tmp_path}/err2; echo $? > {tmp_path}/rc2
        cp {out} {tmp_path}/final.h5
    """
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run(["unshare", "-rm", "sh", "-c", script], env=env, timeout=600)
    assert proc.returncode == 0
    read = lambda name: (tmp_path / name).read_text()  # noqa: E731
    assert read("rc1").strip() == "1", read("err1")
    kept = int(read("kept"))
    assert 0 < kept < 9
    assert read("err1").strip() == (
        f"floorslide: error: no space left on device writing {out}; {kept} tasks kept; free "
        "space and rerun with --resume"
    )
    assert read("rc2").strip() == "0", read("err2")
    assert f"{9 - kept} tasks run, {kept} already done" in read("out2")
    assert_same(results(tmp_path / "final.h5"), reference)
