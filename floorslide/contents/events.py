"""Limits of the event-driven kernels, and how reaching one is reported.

The exact kernels advance each object through a sub-step event by event (breakaway, stop,
reversal, lift-off, landing). Real stick–slip chatter produces a few events per sub-step; a
number in the thousands means a pathological input the solver cannot resolve (a Zeno cascade).
The kernels then stop handling that object's events in the sub-step and record when it
happened; the wrappers turn that into a :class:`~floorslide.errors.SolverLimitError` instead of
returning a response that silently skipped part of a step (docs/design.md §9).
"""

from __future__ import annotations

import numpy as np

from floorslide.errors import SolverLimitError

SLIDE_MAX_EVENTS = 10000
"""Most events one rigid block may have inside one sub-step."""
OSCILLATOR_MAX_EVENTS = 1000
"""Most events one 2-DOF sliding oscillator may have inside one sub-step."""


def check_event_limit(first_hit: np.ndarray, mu_k: np.ndarray, limit: int, solver: str) -> None:
    """Raise :class:`SolverLimitError` if any object reached the event limit.

    Parameters
    ----------
    first_hit
        Per object, the start time (s) of the first sub-step where the limit was reached, or a
        negative value if it never was.
    mu_k
        Kinetic friction coefficient of each object (named in the message).
    limit
        The limit that applied.
    solver
        Name of the solver, for the message.
    """
    hit = np.flatnonzero(np.asarray(first_hit) >= 0.0)
    if hit.size == 0:
        return
    i = int(hit[0])
    raise SolverLimitError(
        f"{solver}: more than {limit} friction events inside one sub-step at t = "
        f"{float(first_hit[i]):.6g} s (mu_k = {float(mu_k[i]):g}; {hit.size} object(s)): "
        "stick-slip chatter the exact solver cannot resolve; check the record for spikes or "
        "use an approximate method"
    )
