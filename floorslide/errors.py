"""Exception types users see.

Every error a user can cause is a :class:`FloorslideError` carrying the file, line or key at
fault; the command line turns it into one line and an exit code (docs/design.md §3, §9).
"""

from __future__ import annotations

import re

_CONTROL = re.compile(r"[\x00-\x1f\x7f]")


def one_line(text: str) -> str:
    """``text`` with its control characters (newlines, tabs, ...) shown as escapes, so that an
    error naming a user's string stays on one line."""
    return _CONTROL.sub(lambda m: m.group().encode("unicode_escape").decode(), text)


def excerpt(text: object, limit: int = 40) -> str:
    """A user's text quoted in a message: ``repr`` of its first `limit` characters on one line
    (control characters escaped, ``…`` where it was cut) — never a whole line of a file,
    which may be long or binary."""
    text = one_line(str(text))
    return repr(text if len(text) <= limit else text[:limit] + "…")


class FloorslideError(Exception):
    """Base class of the errors floorslide reports to its users.

    Parameters
    ----------
    message
        What is wrong and what was expected.
    where
        The file, ``file:line``, or scene key path at fault (optional).
    """

    exit_code = 1

    def __init__(self, message: str, where: str | None = None):
        self.message = one_line(message)
        self.where = one_line(where) if where else where
        super().__init__(f"{self.where}: {self.message}" if where else self.message)


class RecordError(FloorslideError):
    """A record cannot be read or is not a valid accelerogram (exit code 3)."""

    exit_code = 3


class UnitsError(RecordError):
    """The units of a record are unknown or not supported."""


class SceneError(FloorslideError):
    """A scene file is invalid; holds every problem found (exit code 2)."""

    exit_code = 2

    def __init__(self, problems: list[str] | str, where: str | None = None):
        problems = [problems] if isinstance(problems, str) else problems
        self.problems = [one_line(p) for p in problems]
        super().__init__("; ".join(self.problems), where)


class ModelError(FloorslideError):
    """Invalid building, object or solver parameters given through the API or CLI (exit code 2)."""

    exit_code = 2


class ResultFileError(FloorslideError):
    """A result file given to floorslide is missing, corrupt or not a floorslide result file
    (a bad argument: exit code 2)."""

    exit_code = 2


class IncompleteResultError(ResultFileError):
    """A result file whose run is not finished (tasks missing) was given for a report without
    allowing it (exit code 4; docs/design.md §10)."""

    exit_code = 4


class OutputError(FloorslideError):
    """Results cannot be written (full disk, unwritable folder); what finished is kept."""

    exit_code = 1


class OutputExistsError(FloorslideError):
    """A run would replace an existing file (or the journal of an unfinished run) without
    ``--resume`` or ``--overwrite`` (a bad argument: exit code 2)."""

    exit_code = 2


class SolverLimitError(FloorslideError):
    """An exact solver met more events (breakaways, stops, reversals) inside one sub-step than it
    handles: stick–slip chatter it cannot resolve. Rather than return a response that silently
    skipped the rest of that sub-step, it stops (exit code 1)."""

    exit_code = 1


class NonFiniteError(FloorslideError):
    """A model or a solver produced NaN or infinite values from finite input (magnitudes
    beyond float64's range inside it). Rather than return zeros or NaN as a result, it stops,
    naming the building, record or object (exit code 1; in a run, that task fails alone)."""

    exit_code = 1


class Interrupted(KeyboardInterrupt):
    """A command interrupted by SIGINT, SIGTERM or SIGHUP (``signum`` says which; the command
    line exits with ``128 + signum``). A :class:`KeyboardInterrupt`, so everything that handles
    Ctrl-C handles it (:func:`floorslide.run.execute.interrupt_signals`)."""

    def __init__(self, signum: int = 2):
        super().__init__(signum)
        self.signum = int(signum)


class FloorslideWarning(UserWarning):
    """Base class of the warnings floorslide gives: something was done to the input that the
    caller should know of (the same text is kept in the result's ``notes``)."""


class UnitsConversionWarning(FloorslideWarning):
    """A solver was given a record (ObsPy Trace) whose ``stats.units`` is not m/s²; its data
    were converted to m/s² and the conversion recorded in the result's ``notes``."""


class ModelWarning(FloorslideWarning):
    """Building or object parameters that are physically possible but almost surely a mistake
    (an isolation period not above the superstructure's fixed-base period); scenes list them
    in the dry run."""
