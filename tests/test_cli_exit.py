"""The console script ends without the interpreter's teardown (floorslide.cli.leave): the
exit code, everything printed and the atexit functions are as with ``sys.exit``; an open
HDF5 file or a running thread takes the usual exit."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import h5py
import pytest

from tests.conftest import ROOT


def python(code: str, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code), *args],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )


@pytest.mark.parametrize(("code", "expected"), [(0, 0), (3, 3), (None, 0), ("'bad'", 1)])
def test_exit_code_output_and_atexit(code, expected):
    out = python(
        f"""
        import atexit, sys
        from floorslide.cli import leave
        atexit.register(lambda: print("atexit ran", file=sys.stderr))
        sys.stdout.write("x" * 200_000)  # more than a pipe's buffer
        leave({code})
        print("not reached")
        """
    )
    assert out.returncode == expected, out.stderr
    assert out.stdout == "x" * 200_000
    assert out.stderr.splitlines()[-1] == "atexit ran"
    if expected == 1:
        assert out.stderr.splitlines()[0] == "bad"


def test_an_open_hdf5_file_is_closed_by_the_usual_exit(tmp_path):
    path = tmp_path / "open.h5"
    out = python(
        """
        import sys, h5py, numpy as np
        from floorslide.cli import leave
        f = h5py.File(sys.argv[1], "w")
        f["a"] = np.arange(100_000.0)
        f.attrs["done"] = 1
        leave(0)
        """,
        str(path),
    )
    assert out.returncode == 0, out.stderr
    with h5py.File(path, "r") as f:
        assert f["a"].shape == (100_000,) and f.attrs["done"] == 1


def test_a_running_thread_is_waited_for():
    out = python(
        """
        import threading, time
        from floorslide.cli import leave
        threading.Thread(target=lambda: (time.sleep(0.3), print("thread done"))).start()
        leave(0)
        """
    )
    assert out.returncode == 0 and out.stdout == "thread done\n", out.stderr


def test_the_console_script_and_python_m_use_it():
    from importlib.metadata import entry_points

    (script,) = [e for e in entry_points(group="console_scripts") if e.name == "floorslide"]
    assert script.value == "floorslide.cli:entry"
    text = (ROOT / "floorslide" / "cli.py").read_text(encoding="utf-8")
    assert text.rstrip().endswith('if __name__ == "__main__":  # pragma: no cover\n    entry()')
    out = subprocess.run(
        [sys.executable, "-m", "floorslide.cli", "slide", "missing.AT2", "--mu", "0.1"],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert out.returncode == 3 and out.stderr.count("\n") == 1, out.stderr
