"""``--workers`` is capped at what can be used: no more processes than tasks (or figures) and at
most :data:`floorslide.parallel.PER_CORE` per core; an explicit request that is reduced is said
in one line (``--workers 10000`` forked hundreds of processes for 3 tasks)."""

from __future__ import annotations

import multiprocessing
import os

import pytest

from floorslide import parallel
from floorslide.parallel import PER_CORE, usable_cores, worker_count
from tests.run.test_task_failures import _write


def test_the_count_is_capped_at_the_jobs_and_the_cores():
    cores = usable_cores()
    assert worker_count(None, 1000) == (min(cores, 1000), "")
    assert worker_count(2, 1000)[0] == min(2, PER_CORE * cores)
    n, note = worker_count(10000, 3)
    assert n == min(3, PER_CORE * cores)
    assert note.startswith(f"--workers 10000 reduced to {n} (3 tasks to do")
    n, note = worker_count(10000, 10**6, "figures")
    assert n == PER_CORE * cores and f"at most 2 processes per core, {cores} core" in note
    assert worker_count(PER_CORE * cores, 10**6) == (PER_CORE * cores, "")
    assert worker_count(5, 0) == (1, "")  # nothing to do (a finished run resumed)


def _count_pools(monkeypatch) -> list[int]:
    """The sizes of the process pools a run or a report asks for."""
    import concurrent.futures

    sizes: list[int] = []
    real_executor = concurrent.futures.ProcessPoolExecutor
    real_pool = multiprocessing.context.ForkContext.Pool

    def executor(*args, max_workers=None, **kw):
        sizes.append(max_workers)
        return real_executor(*args, max_workers=max_workers, **kw)

    def pool(self, processes=None, *args, **kw):
        sizes.append(processes)
        return real_pool(self, processes, *args, **kw)

    monkeypatch.setattr("floorslide.run.execute.ProcessPoolExecutor", executor)
    monkeypatch.setattr(multiprocessing.context.ForkContext, "Pool", pool)
    return sizes


def test_a_run_forks_no_more_workers_than_tasks(tmp_path, capsys, monkeypatch):
    from floorslide.cli import run

    monkeypatch.setattr(parallel, "usable_cores", lambda: 2)
    sizes = _count_pools(monkeypatch)
    _write(tmp_path)  # 2 tasks
    with pytest.raises(SystemExit) as exit_:
        run.main([str(tmp_path / "scene.toml"), "-o", str(tmp_path / "o.h5"), "--workers",
                  "10000"], standalone_mode=False)  # fmt: skip
        raise SystemExit(0)
    assert exit_.value.code in (0, None)
    err = capsys.readouterr().err.splitlines()
    notes = [ln for ln in err if "--workers" in ln]
    assert notes == ["floorslide: warning: --workers 10000 reduced to 2 (2 tasks to do; at most 2 "
                     "processes per core, 2 cores)"]  # fmt: skip
    # the first task runs in this process, the other in a pool of one: never more than tasks
    assert all(s <= 1 for s in sizes), sizes


def test_figures_fork_no_more_workers_than_the_machine_allows(tmp_path, capsys, monkeypatch):
    from floorslide.cli import plot, run

    _write(tmp_path)
    out = tmp_path / "o.h5"
    with pytest.raises(SystemExit):
        run.main([str(tmp_path / "scene.toml"), "-o", str(out), "--workers", "1"],
                 standalone_mode=False)  # fmt: skip
        raise SystemExit(0)
    capsys.readouterr()
    monkeypatch.setattr(parallel, "usable_cores", lambda: 1)
    sizes = _count_pools(monkeypatch)
    with pytest.raises(SystemExit) as exit_:
        plot.main([str(out), "-o", str(tmp_path / "fig"), "--workers", "10000"],
                  standalone_mode=False)  # fmt: skip
        raise SystemExit(0)
    assert exit_.value.code in (0, None)
    err = capsys.readouterr().err.splitlines()
    assert [ln for ln in err if "--workers" in ln] == [
        "floorslide: warning: --workers 10000 reduced to 2 (at most 2 processes per core, 1 core)"
    ]
    assert sizes and all(s <= 2 for s in sizes), sizes
    assert os.listdir(tmp_path / "fig")
