"""numba compilation time on a fresh install, measured in a separate process with an empty
kernel cache.

floorslide's kernels are cached on disk (``@njit(cache=True)``), so in a normal process the
first call only loads them; what a fresh install pays once is measured here: a child Python
process with ``NUMBA_CACHE_DIR`` set to an empty temporary directory calls every method of the
study once, on a short prefix of a record, in the order of the study, and reports the numba
compilation each call triggered (a kernel shared by several methods is compiled by the first).

Run as ``python -m floorslide.bench.compile`` it prints that table as JSON.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile

from floorslide.errors import FloorslideError


def measure_here(record: str = "PET-090", prefix: int = 64) -> list[dict]:
    """Call each method (first setting of each) once in this process, in the study's order, and
    record the numba compilation each call triggers (the solvers in the plane on the first
    bundled pair of :data:`~floorslide.bench.study.PAIRS`)."""
    from floorslide.bench.cases import FULL, solvers
    from floorslide.bench.study import PAIRS, load_pairs, load_records
    from floorslide.bench.timing import CompileTimer

    (rec,) = load_records((record,))
    (two,) = load_pairs(PAIRS[:1])
    rows = []
    for solver in solvers(FULL):
        acc, dt = (two.acc[:, :prefix], two.dt) if solver.pair else (rec.acc[:prefix], rec.dt)
        with CompileTimer() as setup:  # friction from the floor's PFA: counted with "exact"
            ctx = solver.context(acc, dt)
        seen = set()
        for method in solver.methods:
            if method.method in seen:
                continue
            seen.add(method.method)
            with CompileTimer() as timer:
                method.run(acc, dt, ctx)
            if method.exact:
                timer.total += setup.total
                timer.kernels = setup.kernels + [k for k in timer.kernels if k not in setup.kernels]
            rows.append(
                dict(
                    solver=solver.key,
                    method=method.method,
                    compile_time=timer.total,
                    kernels=list(timer.kernels),
                )
            )
    return rows


def fresh_compile_times(timeout: float = 600.0) -> list[dict]:
    """numba compilation per method on an empty cache (in a child process).

    Returns
    -------
    list of dict
        ``solver, method, compile_time`` (s) and ``kernels`` (qualified names) for each method
        that compiled at least one kernel, in the order of the study.

    Raises
    ------
    FloorslideError
        If the child process fails.
    """
    with tempfile.TemporaryDirectory(prefix="floorslide-numba-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        proc = subprocess.run(
            [sys.executable, "-m", "floorslide.bench.compile"],
            env=env,
            capture_output=True,
            text=True,
            timeout=timeout,
            check=False,
        )
    if proc.returncode != 0:
        tail = proc.stderr.strip().splitlines()[-1:] or ["no message"]
        raise FloorslideError(f"compile-time measurement failed: {tail[0]}", "bench")
    rows = json.loads(proc.stdout)
    return [r for r in rows if r["kernels"]]


if __name__ == "__main__":  # pragma: no cover - run in a child process
    print(json.dumps(measure_here()))
