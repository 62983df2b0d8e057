"""Running a plan: locally on all cores, on N workers, or on a Dask distributed scheduler.

Tasks are pure functions of their input, so every way of running gives the same numbers. The
main process is the single writer of the result file: results are written as tasks finish, in
whatever order they finish, each one journaled and flushed before it is marked done. At most a
few tasks per worker are in flight, so memory stays O(one task) per worker.
"""

from __future__ import annotations

import multiprocessing
import os
import queue
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from contextlib import contextmanager, suppress
from dataclasses import dataclass, field

from tqdm import tqdm

from floorslide.errors import FloorslideError, Interrupted
from floorslide.parallel import worker_count
from floorslide.run.store import ResultWriter, warn_stderr
from floorslide.run.task import TaskFailure, attempt_task, task_warnings
from floorslide.scene.planner import Plan


@dataclass
class RunSummary:
    """What a run did."""

    out: str
    tasks: int
    ran: int
    resumed: int
    failures: list[str]
    """Unreadable records (the plan's) and tasks that failed (:class:`~floorslide.run.task.
    TaskFailure`: left out of the result file, which then stays INCOMPLETE), one line each."""
    seconds: float
    interrupted: bool = False
    warnings: list[str] = field(default_factory=list)
    """One line per flag of a finished task a user should not miss
    (:func:`~floorslide.run.task.task_warnings`)."""
    signal: int = 0
    """The signal that interrupted the run (``signal.SIGINT``, ``SIGTERM`` or ``SIGHUP``; 0 when
    it was not interrupted)."""
    kept: int = 0
    """Finished tasks in the result file (those resumed and those run now)."""


INTERRUPT_SIGNALS = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)
"""The signals that interrupt a run (Ctrl-C, ``kill``, a closed terminal): each keeps what
finished, like the others, and the command exits with ``128 + signal`` (130, 143, 129)."""


@contextmanager
def interrupt_signals(received: list[int] | None = None) -> Iterator[list[int]]:
    """While inside, :data:`INTERRUPT_SIGNALS` raise :class:`Interrupted` in the main thread
    and are appended to the list yielded (`received`, or a new one) — so a signal whose
    exception was swallowed (raised inside a finaliser, which Python only reports) is still
    known. Nested, the inner context shares the outer's list when given it. Elsewhere than
    in the main thread (where handlers cannot be set) nothing changes."""
    got = [] if received is None else received
    if threading.current_thread() is not threading.main_thread():
        yield got
        return

    def handler(signum, frame):
        got.append(signum)
        raise Interrupted(signum)

    previous = {sig: signal.signal(sig, handler) for sig in INTERRUPT_SIGNALS}
    try:
        yield got
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


def _worker_init() -> None:
    """Worker initializer.

    One BLAS thread per process: the matrices here are tiny; threaded BLAS only spins, and with
    one process per core it oversubscribes the machine (10× slower measured on 2 cores). And on
    Linux the worker dies with its parent: a run killed with SIGKILL leaves no orphans behind.
    """
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=1)
    # the main process alone decides about interruptions (and stops its pool): a worker that
    # took Ctrl-C itself (sent to the whole process group) could die holding the task queue's
    # lock and leave the others, and the run's exit, waiting on it for ever
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for sig in INTERRUPT_SIGNALS[1:]:
        signal.signal(sig, signal.SIG_DFL)
    if sys.platform.startswith("linux"):
        import ctypes

        try:
            libc = ctypes.CDLL("libc.so.6", use_errno=True)
            libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
        except OSError:  # pragma: no cover - no glibc
            pass
        if os.getppid() == 1:  # the parent already died between fork and prctl
            os._exit(1)


def _run_local(
    todo,
    workers: int,
    force: bool,
    on_result: Callable,
    received: list[int] | None = None,
    meanwhile: Callable[[], object] | None = None,
) -> None:
    """Run `todo` here (one worker) or in a pool of forked worker processes, calling
    `on_result` as each finishes. An interruption (`received`: the list of an enclosing
    :func:`interrupt_signals`) is taken while a task computes or the pool is waited on; the
    pool's own bookkeeping (starting a worker, handing out a task, shutting down) is finished
    first (:func:`_deferred`): interrupted half-way it left a dead pipe that Python's exit then
    tripped over. On the way out, the tasks in flight finish (unwritten) and the pool stops.

    `meanwhile`, with a pool, runs in a thread of this process once the workers are forked
    (this process mostly waits on them), and has finished when the run returns; its errors are
    ignored (it only prepares what the caller does next, which meets them itself)."""
    received = [] if received is None else received
    if workers <= 1:
        for task in todo:
            on_result(attempt_task(task, force))
        return
    # the first task here: the compiled kernels it needs are then loaded (or compiled, on a
    # fresh install) once, in this process, and every forked worker inherits them
    todo = list(todo)
    if todo:
        # the other families' kernels compile (fresh install) in side processes meanwhile
        from floorslide.run import warmup

        first = warmup.family(todo[0])
        warming = warmup.start(sorted({warmup.family(t) for t in todo} - {first}))
        on_result(attempt_task(todo[0], force))
        warmup.finish(warming)
        todo = todo[1:]
    workers = min(workers, len(todo))  # no process without a task
    if workers <= 1:
        for task in todo:
            on_result(attempt_task(task, force))
        return
    ctx = multiprocessing.get_context("fork" if sys.platform != "win32" else "spawn")
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_worker_init)
    pending = set()
    queue = iter(todo)
    try:
        with _deferred(received):
            for _ in range(2 * workers):
                task = next(queue, None)
                if task is None:
                    break
                pending.add(pool.submit(attempt_task, task, force))
        helper = _start_meanwhile(meanwhile)
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                on_result(fut.result())
                task = next(queue, None)
                if task is not None:
                    with _deferred(received):
                        pending.add(pool.submit(attempt_task, task, force))
    except BaseException:
        # the tasks not started are cancelled; those in flight finish (killing their workers
        # could leave the pool's feeder thread blocked on a pipe nobody reads, and Python's
        # exit waiting on it for ever), unwritten; a second signal meanwhile is only recorded
        with _deferred(received, stop=False):
            for fut in pending:
                fut.cancel()
            pool.shutdown(wait=True, cancel_futures=True)
        raise
    with _deferred(received):
        pool.shutdown(wait=True)
    if helper is not None:
        helper.join()


def _start_meanwhile(meanwhile: Callable[[], object] | None) -> threading.Thread | None:
    """`meanwhile` started in a daemon thread (None without it)."""
    if meanwhile is None:
        return None

    def run() -> None:
        with suppress(Exception):
            meanwhile()

    helper = threading.Thread(target=run, name="floorslide-meanwhile", daemon=True)
    helper.start()
    return helper


@contextmanager
def _deferred(received: list[int], stop: bool = True) -> Iterator[None]:
    """Inside, the :data:`INTERRUPT_SIGNALS` are only recorded in `received` (the main
    thread's handlers swapped for one that appends), so the section completes; right after
    it, with `stop`, a recorded signal raises :class:`Interrupted`. Outside the main thread,
    nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def record(signum, frame):
        received.append(signum)

    previous = {sig: signal.signal(sig, record) for sig in INTERRUPT_SIGNALS}
    try:
        yield
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)
    if stop and received:
        raise Interrupted(received[0])


def _run_task_single_blas(task, force):
    """attempt_task on a Dask worker with one BLAS thread."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):
        return attempt_task(task, force)


SCHEDULER_TIMEOUT = 60.0
"""Seconds a run on a Dask scheduler waits for a worker when none is connected."""

POLL = 0.5
"""Seconds between looks at a Dask scheduler's workers while no task finishes."""


def _workers(client) -> int:
    return len(client.scheduler_info().get("workers", {}))


class _WorkerWait:
    """How long a run has had no Dask worker: says so once, gives up after `timeout` s."""

    def __init__(self, address: str, timeout: float, warn: Callable[[str], None]):
        self.address, self.timeout, self.warn = address, timeout, warn
        self.since: float | None = None
        self.told = False

    def progress(self) -> None:
        """A task finished, or a worker is connected: the wait is over."""
        self.since = None

    def idle(self) -> None:
        """No task finished for a while and no worker is connected.

        Raises
        ------
        FloorslideError
            No worker for `timeout` seconds.
        """
        now = time.monotonic()
        self.since = now if self.since is None else self.since
        if not self.told:
            self.warn(
                f"no Dask worker is connected to the scheduler at {self.address}; waiting up "
                f"to {self.timeout:g} s for one (--scheduler-timeout)"
            )
            self.told = True
        if now - self.since >= self.timeout:
            raise FloorslideError(
                f"no Dask worker connected to the scheduler at {self.address} within "
                f"{self.timeout:g} s; start workers (dask worker {self.address}) or wait "
                "longer (--scheduler-timeout), then rerun with --resume",
                "--scheduler",
            )


def _run_dask(
    todo, address: str, force: bool, on_result: Callable, timeout: float, warn: Callable
) -> None:
    """Run `todo` on the Dask scheduler at `address`, calling `on_result` as each finishes.

    Finished futures are collected by their done-callbacks, not with ``distributed.wait`` or
    ``as_completed``: those use the process's *default* client, which is another one (with its
    own event loop) whenever a second Client is made in the same process during the run (a
    notebook's, a test's), and then fail with "bound to a different event loop".
    """
    try:
        from dask.distributed import Client
    except ImportError:  # pragma: no cover - dask[distributed] is a dependency
        raise FloorslideError("--scheduler needs dask.distributed installed") from None
    try:
        client = Client(address, timeout="10s", set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise FloorslideError(
            f"cannot reach the Dask scheduler at {address}: {exc}", "--scheduler"
        ) from None
    try:
        finished: queue.Queue = queue.Queue()
        futures = [
            client.submit(_run_task_single_blas, t, force, pure=False, retries=2) for t in todo
        ]
        for fut in futures:  # the list keeps every future alive until it is collected
            fut.add_done_callback(finished.put)
        waiting = _WorkerWait(address, timeout, warn)
        for _ in todo:
            fut = _next_finished(finished, client, waiting)
            on_result(fut.result())
            fut.release()
    finally:
        client.close()


def _next_finished(finished: queue.Queue, client, waiting: _WorkerWait):
    """The next future to finish, looking at the scheduler's workers every :data:`POLL` s."""
    while True:
        try:
            fut = finished.get(timeout=POLL)
        except queue.Empty:
            if _workers(client):
                waiting.progress()
            else:
                waiting.idle()
            continue
        waiting.progress()
        return fut


def write_batch(n_tasks: int) -> int:
    """Tasks written into the result file at once: about a sixteenth of the run (1 for runs
    of fewer than 32 tasks, at most 64), every task journaled first all the same."""
    return max(1, min(64, n_tasks // 16))


def execute(
    plan: Plan,
    out: str,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    resume: bool = False,
    overwrite: bool = False,
    force: bool = False,
    progress: bool | None = None,
    scheduler_timeout: float = SCHEDULER_TIMEOUT,
    warn: Callable[[str], None] = warn_stderr,
    signals: list[int] | None = None,
    meanwhile: Callable[[], object] | None = None,
) -> RunSummary:
    """Run every task of `plan` not already done in `out` and write the results.

    Parameters
    ----------
    plan
        From :func:`floorslide.scene.planner.plan`.
    out
        Result file (HDF5).
    workers
        Local worker processes (default: one per usable core; 1 runs in this process), at most
        one per task to run and :data:`~floorslide.parallel.PER_CORE` per core (a request
        reduced is said in one line through `warn`).
    scheduler
        Address of a running ``dask.distributed`` scheduler to send the tasks to instead.
    resume
        Continue an interrupted run of the same scene: finished tasks are kept and skipped;
        tasks that fail their integrity check and journal entries that are refused run again.
    overwrite
        Replace an existing `out` (without it, or `resume`, an existing `out` is refused).
    force
        Integrate every object even where the answer is known (checks the planner's rules).
    progress
        Show a progress bar with ETA (default: when stderr is a terminal).
    scheduler_timeout
        With `scheduler`: seconds to wait while no Dask worker is connected before giving up.
    warn
        Called with one line for each warning: entries refused or tasks rebuilt on resume, a
        scheduler without workers, a `workers` request reduced (default: printed on stderr).
    signals
        The list of an enclosing :func:`interrupt_signals` (the command line's, which also
        covers the summary after the run); without it the run sets up its own. SIGINT, SIGTERM
        and SIGHUP then interrupt the run alike: what finished is kept, the file is left for
        ``--resume`` and the summary says ``interrupted`` and which ``signal``.
    meanwhile
        Work of the caller's for after the run (importing the report's modules, say), done in
        a thread of this process while local worker processes compute the tasks; not called
        without them. Its errors are ignored: the caller meets them when it does that work.

    Raises
    ------
    OutputExistsError
        `out` exists and neither `resume` nor `overwrite` was given.
    OutputError
        Results cannot be written (a full disk): one line, how many tasks are kept; no worker
        process is left behind and every journaled task is kept for ``--resume``.
    FloorslideError
        The Dask scheduler cannot be reached, or has no worker for `scheduler_timeout` s.
    """
    from floorslide.run.fingerprint import task_fingerprints

    t0 = time.perf_counter()
    sc = plan.scene
    writer = ResultWriter(
        out,
        sc.text,
        sc.path,
        sc.name,
        plan.summary(),
        resume=resume,
        overwrite=overwrite,
        fingerprints=task_fingerprints(plan.tasks),
        warn=warn,
        batch=write_batch(len(plan.tasks)),
    )
    todo = [t for t in plan.tasks if t.task_id not in writer.done]
    resumed = len(plan.tasks) - len(todo)
    show = sys.stderr.isatty() if progress is None else progress
    bar = tqdm(
        total=len(plan.tasks),
        initial=resumed,
        disable=not show,
        unit="task",
        file=sys.stderr,
        dynamic_ncols=True,
    )
    ran = 0
    failed: list[str] = []
    flagged: list[str] = []

    def on_result(result):
        nonlocal ran
        if received:  # a signal whose exception was swallowed (in a finaliser): stop here
            raise Interrupted(received[0])
        # a result is written whole, then the run stops if a signal came meanwhile
        with _deferred(received):
            if isinstance(result, TaskFailure):
                failed.append(result.message)  # left out of the file: it stays INCOMPLETE
            else:
                writer.write(result)
                ran += 1
                flagged.extend(task_warnings(result))
            bar.update()

    from threadpoolctl import threadpool_limits

    signum = 0
    with interrupt_signals(signals) as received:
        try:
            try:
                if scheduler:
                    _run_dask(todo, scheduler, force, on_result, scheduler_timeout, warn)
                else:
                    n, note = worker_count(workers, len(todo))
                    if note:
                        warn(note)
                    with threadpool_limits(limits=1):
                        _run_local(todo, n, force, on_result, received, meanwhile)
            except Exception:
                writer.abandon()
                raise
            finally:
                bar.close()
            if not received:
                with _deferred(received):
                    writer.flush()
            if not received and len(writer.done) == len(plan.tasks):
                with _deferred(received):
                    writer.finish()
        except KeyboardInterrupt as exc:
            signum = getattr(exc, "signum", signal.SIGINT)
        finally:
            writer.close()  # unlocks; the journal stays for --resume unless finished
        # a signal is never lost: one whose exception was swallowed still interrupts
        signum = signum or (received[0] if received else 0)
    return RunSummary(
        str(out),
        len(plan.tasks),
        len(writer.done) - resumed if signum else ran,
        resumed,
        list(plan.failures) + failed,
        time.perf_counter() - t0,
        bool(signum),
        flagged,
        int(signum),
        len(writer.done),
    )
