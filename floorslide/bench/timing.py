"""CPU timing for the study: ``time.process_time``, one warm-up call excluded, median of
repeats, numba compilation measured apart.

The warm-up is the first call of a method in the process, made on a short prefix of the record:
it triggers numba's compilation (or loads the compiled kernels from the on-disk cache) and
fills the per-building caches, at a fraction of a full call's cost. Its CPU time is reported
as ``first_call`` and the numba compilation inside it — from numba's ``numba:compile`` events,
which fire only when a kernel is really compiled, not when it comes from the cache — as
``compile``; neither is part of the timings. Then the method runs on the full record: the first
full call gives the result, and calls are repeated (batched when short, so that each timing
lasts at least ``min_time``) until ``repeats`` timings or ``budget`` seconds; the median is
reported.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numba.core import event as numba_event


class CompileTimer(numba_event.Listener):
    """Sums the durations of top-level numba compilations (nested compilations of callees and
    of numba's own overloads are inside their caller's) and names the floorslide kernels
    compiled."""

    def __init__(self) -> None:
        self.total = 0.0
        self.kernels: list[str] = []
        self._depth = 0
        self._start = 0.0

    def on_start(self, event) -> None:
        if self._depth == 0:
            self._start = time.perf_counter()
        self._depth += 1
        dispatcher = event.data.get("dispatcher") if isinstance(event.data, dict) else None
        func = getattr(dispatcher, "py_func", None)
        module = getattr(func, "__module__", "") or ""
        # floorslide's own kernels only (numba's internal overloads compile along with them)
        if module.startswith("floorslide"):
            name = f"{module}.{func.__qualname__}"
            if name not in self.kernels:
                self.kernels.append(name)

    def on_end(self, event) -> None:
        self._depth -= 1
        if self._depth == 0:
            self.total += time.perf_counter() - self._start

    def __enter__(self) -> CompileTimer:
        numba_event.register("numba:compile", self)
        return self

    def __exit__(self, *exc) -> None:
        numba_event.unregister("numba:compile", self)


@dataclass(frozen=True)
class Timing:
    """CPU time of one method on one record.

    Attributes
    ----------
    cpu_time
        Median CPU time of a full call, s.
    repeats
        Number of timings the median is taken over.
    first_call
        CPU time of the warm-up call on the record's prefix, s (numba compilation or cache
        loading, set-up), not part of `cpu_time`.
    compile_time
        numba compilation inside the warm-up call, s (0 when the kernels came from the cache or
        were compiled by an earlier method).
    kernels
        The kernels compiled during the warm-up.
    """

    cpu_time: float
    repeats: int
    first_call: float
    compile_time: float
    kernels: tuple[str, ...] = field(default=())


def measure(
    full: Callable[[], Any],
    warmup: Callable[[], Any],
    repeats: int = 5,
    budget: float = 5.0,
    min_time: float = 0.02,
) -> tuple[Timing, Any]:
    """Time `full` after one warm-up call of `warmup`; returns the timing and `full`'s result.

    Parameters
    ----------
    full
        The call to time (the method on the full record).
    warmup
        The first call (the method on a prefix of the record).
    repeats
        Largest number of timings.
    budget
        CPU seconds after which no further repeat is started.
    min_time
        Short calls are batched so that one timing lasts at least this long, s.
    """
    with CompileTimer() as timer:
        t0 = time.process_time()
        warmup()
        first = time.process_time() - t0
    t0 = time.process_time()
    result = full()
    once = time.process_time() - t0
    spent = once
    if once >= min_time:
        times = [once]
        while len(times) < repeats and spent + once <= budget:
            t0 = time.process_time()
            full()
            times.append(time.process_time() - t0)
            spent += times[-1]
    else:
        inner = max(1, math.ceil(min_time / max(once, 1e-7)))
        times = []
        while len(times) < repeats and (not times or spent + min_time <= budget):
            t0 = time.process_time()
            for _ in range(inner):
                full()
            dt = time.process_time() - t0
            times.append(dt / inner)
            spent += dt
    timing = Timing(
        cpu_time=float(np.median(times)),
        repeats=len(times),
        first_call=first,
        compile_time=timer.total,
        kernels=tuple(timer.kernels),
    )
    return timing, result
