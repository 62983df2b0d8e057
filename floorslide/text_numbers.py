"""Numbers written as text: the one reading of a number in every file and option floorslide
parses (records, catalogs, target spectra, command-line options).

Two rules, each owned here:

- **No underscores.** Python's ``float`` and ``int`` read ``0_05`` as 5.0 and ``1_000`` as
  1000 (PEP 515 digit grouping). No record, catalog, spectrum table or engineer writes numbers
  that way: such a number is a typo (``0_05`` for ``0.05``) or damage, and is refused.
- **A count is a whole number in any spelling.** A count of samples or lines may be written
  ``2000``, ``2000.``, ``2000.0`` or ``2.0E+03`` (Fortran and spreadsheet output); it is read as
  the integer it denotes. A count with a fraction (``2000.5``), NaN or infinity is refused.

The functions raise :class:`ValueError` (with :data:`UNDERSCORE_HINT` as its message for an
underscore); each caller turns it into a one-line error naming its file, line or option.
"""

from __future__ import annotations

import math

UNDERSCORE_HINT = "underscores are not digit separators"
"""Why ``0_05`` is refused (the text of the :class:`ValueError`, and of messages)."""


def underscore_hint(text: str) -> str:
    """`` (underscores are not digit separators)`` when `text` holds one, else ``""``: the
    reason to append to a message refusing `text`."""
    return f" ({UNDERSCORE_HINT})" if "_" in text else ""


def parse_number(text: str) -> float:
    """``float(text)``, refusing underscores.

    Raises
    ------
    ValueError
        `text` is not a number, or holds an underscore (message :data:`UNDERSCORE_HINT`).

    Examples
    --------
    >>> parse_number(" 0.05 "), parse_number("2.0E+03")
    (0.05, 2000.0)
    >>> parse_number("0_05")
    Traceback (most recent call last):
    ...
    ValueError: underscores are not digit separators
    """
    if "_" in text:
        raise ValueError(UNDERSCORE_HINT)
    return float(text)


def parse_count(text: str) -> int:
    """A count (of samples, lines, periods): a finite whole number in any spelling.

    Raises
    ------
    ValueError
        Not a number, an underscore, NaN, infinite, or not whole.

    Examples
    --------
    >>> [parse_count(t) for t in ("2000", "2000.", "2000.0", "2.0E+03", "+12")]
    [2000, 2000, 2000, 2000, 12]
    >>> parse_count("2000.5")
    Traceback (most recent call last):
    ...
    ValueError: '2000.5' is not a whole number
    """
    value = parse_number(text)
    if not math.isfinite(value) or value != math.floor(value):
        raise ValueError(f"{text.strip()!r} is not a whole number")
    return int(value)


def is_count(text: str) -> bool:
    """Whether `text` is a count as :func:`parse_count` reads it (never raises)."""
    try:
        parse_count(text)
    except ValueError:
        return False
    return True
