"""How many worker processes a run or a set of figures gets.

floorslide's parallel work — a run's tasks, a report's figures — is CPU-bound and each job is
independent, so more processes than jobs, or than the machine can run at once, only cost
memory and fork time (``--workers 10000`` forked hundreds of processes for 3 tasks). The count
asked for is capped at the number of jobs and at :data:`PER_CORE` processes per usable core; a
cap on an explicit request is said in one line.
"""

from __future__ import annotations

import os

PER_CORE = 2
"""Most worker processes per usable core. CPU-bound jobs gain nothing beyond one per core; the
second leaves room for a core count that under-reports (hyper-threads, a container's quota
that ``os.sched_getaffinity`` does not see)."""


def usable_cores() -> int:
    """Cores this process may run on (its CPU affinity where the platform says, else
    :func:`os.cpu_count`), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def worker_count(requested: int | None, jobs: int, what: str = "tasks") -> tuple[int, str]:
    """The worker processes for `jobs` independent jobs.

    Parameters
    ----------
    requested
        ``--workers N`` (None: one per usable core).
    jobs
        Jobs to run (tasks, figures).
    what
        What the jobs are, for the note ("tasks", "figures").

    Returns
    -------
    (n, note)
        ``n = min(requested, jobs, PER_CORE × cores)``, at least 1; `note` is one line saying
        why an explicit request was reduced (``""`` when it was not, or none was given).
    """
    if jobs <= 0:
        return 1, ""
    cores = usable_cores()
    cap = PER_CORE * cores
    asked = cores if requested is None else int(requested)
    n = max(1, min(asked, cap, jobs))
    if requested is None or n >= asked:
        return n, ""
    reasons = []
    if jobs < asked:
        reasons.append(f"{jobs} {what} to do")
    if cap < asked:
        reasons.append(f"at most {PER_CORE} processes per core, {cores} core{'s' * (cores > 1)}")
    return n, f"--workers {asked} reduced to {n} ({'; '.join(reasons)})"
