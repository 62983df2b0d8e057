"""A run stopped by SIGINT (Ctrl-C, sent to the whole process group), SIGTERM (``kill``) or
SIGHUP (a closed terminal) keeps what finished, says so in one line —
``floorslide: interrupted (SIGTERM); N finished tasks are in OUT (continue with --resume)`` — and
exits with 128 + the signal (130, 143, 129), whenever the signal comes: while tasks run, while a
result is written, while the worker pool shuts down, between the last task and the summary, or
inside a finaliser (where Python swallows the KeyboardInterrupt: the run used to finish with exit
0). ``--resume`` then completes it. SIGTERM and SIGHUP used to end the run without a word."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import textwrap
import time

import psutil
import pytest

from floorslide.run.store import ResultFile, journal_entries
from tests.conftest import ROOT
from tests.run.test_runs import SCENE

LINE = re.compile(
    r"^floorslide: interrupted \((SIG[A-Z]+)\); (\d+) finished tasks are in (.+) "
    r"\(continue with --resume\)$"
)
ENV = dict(os.environ, PYTHONPATH=str(ROOT))


def _cmd(scene, out, *extra):
    return [sys.executable, "-m", "floorslide.cli", "run", str(scene), "-o", str(out),
            "--workers", "2", *extra]  # fmt: skip


def _leftovers(out) -> list:
    return [
        p for p in psutil.process_iter(["cmdline"]) if str(out) in " ".join(p.info["cmdline"] or [])
    ]


def _check_interrupted(proc, err: str, sig: int, out) -> int:
    assert proc.returncode == 128 + sig, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    m = LINE.match(lines[0])
    assert m and m.group(1) == signal.Signals(sig).name and m.group(3) == str(out), err
    kept = int(m.group(2))
    # what the line says is what --resume finds: the journal's entries (or, when the signal
    # came after the file was completed, its tasks)
    assert kept == (len(journal_entries(out)) or len(ResultFile(out).done_tasks()))
    time.sleep(0.5)
    assert not _leftovers(out)
    return kept


@pytest.mark.slow
@pytest.mark.parametrize(
    ("sig", "target", "group"),
    [(signal.SIGINT, 5, True), (signal.SIGTERM, 60, False), (signal.SIGHUP, 150, False)],
    ids=["ctrl-c-early", "sigterm-mid", "sighup-late"],
)
def test_a_signal_while_tasks_run_keeps_what_finished(tmp_path, sig, target, group):
    scene = tmp_path / "s.toml"
    big = SCENE.replace("period = [2.0, 3.0]", "period = [1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0]")
    big = big.replace('station_id = ["ELC-180", "RIO-360", "PET-090"]', 'set = "pulse-like"')
    scene.write_text(big)  # 18 records × 9 buildings = 162 tasks
    out = tmp_path / "k.h5"
    proc = subprocess.Popen(_cmd(scene, out), env=ENV, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)  # fmt: skip
    deadline = time.time() + 180
    while time.time() < deadline and proc.poll() is None and len(journal_entries(out)) < target:
        time.sleep(0.002)
    assert proc.poll() is None, "the run ended before the signal"
    if group:
        os.killpg(proc.pid, sig)  # as a terminal's Ctrl-C: the workers get it too
    else:
        proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    kept = _check_interrupted(proc, err, sig, out)
    assert target <= kept < 162
    done = subprocess.run(_cmd(scene, out, "--resume"), env=ENV, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert f"{162 - kept} tasks run, {kept} already done, 162 in all" in done.stdout
    assert len(ResultFile(out).done_tasks()) == 162


# where the signal is sent from inside the run (deterministic), and how
WINDOWS = {
    # a KeyboardInterrupt raised inside a finaliser is only reported by Python ("Exception
    # ignored in ..."): the run went on and finished with exit 0
    "in-a-finaliser": """
        from floorslide.run import store
        real = store.ResultWriter.write
        n = [0]
        class Trip:
            def __del__(self):
                os.kill(os.getpid(), SIG)
                sum(range(1000))  # the handler runs here, inside __del__
        def write(self, result):
            real(self, result)
            n[0] += 1
            if n[0] == 3:
                t = Trip()
                del t
        store.ResultWriter.write = write
    """,
    "while-a-result-is-written": """
        from floorslide.run import store
        real = store.ResultWriter.write
        def write(self, result):
            os.kill(os.getpid(), SIG)
            real(self, result)
        store.ResultWriter.write = write
    """,
    "in-the-pool-shutdown": """
        import concurrent.futures.process as P
        real = P.ProcessPoolExecutor.shutdown
        def shutdown(self, *a, **k):
            os.kill(os.getpid(), SIG)
            return real(self, *a, **k)
        P.ProcessPoolExecutor.shutdown = shutdown
    """,
    "between-the-last-task-and-the-summary": """
        from floorslide import cli
        real = cli._print_summary
        def summary(*a, **k):
            os.kill(os.getpid(), SIG)
            return real(*a, **k)
        cli._print_summary = summary
    """,
}


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize("window", list(WINDOWS))
def test_no_signal_is_lost_whenever_it_comes(the_plan, tmp_path, window, sig):
    out = tmp_path / "w.h5"
    code = (
        f"import os, signal, sys\nSIG = {int(sig)}\n"
        + textwrap.dedent(WINDOWS[window])
        + "from floorslide.cli import main\n"
        + f"sys.argv = ['floorslide', *{_cmd(the_plan.scene.path, out)[3:]!r}]\nmain()\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], env=ENV, capture_output=True, text=True,
                          timeout=300)  # fmt: skip
    assert "Traceback" not in proc.stderr and "Exception ignored" not in proc.stderr
    kept = _check_interrupted(proc, proc.stderr, sig, out)
    assert 1 <= kept <= 9
