"""Units of acceleration: names, spellings and the factor to m/s².

floorslide works in SI inside (docs/design.md §2); a record's units are converted once, at the
edge: when
a file is read (:func:`floorslide.read_record`) or when a solver is given an ObsPy Trace whose
``stats.units`` is not m/s² (:mod:`floorslide.inputs`). This module is neutral (NumPy-free and
ObsPy-free) so that the numerical core can use it; ``floorslide.records.units`` re-exports it.

The four units of the command line (``g``, ``gal``, ``m/s**2``, ``mm/s**2``) and a few others met
in strong-motion files (``mg``, ``in/s**2``, ``nm/s**2``) are known, each under its common
spellings (``G``, ``cm/s^2``, ``cm/sec/sec``, ``m/s2``, ``m·s⁻²`` ...). Anything else is an error
that lists what is accepted — units are never guessed.
"""

from __future__ import annotations

import re

from floorslide.constants import G
from floorslide.errors import UnitsError

SI_UNITS = "m/s**2"
"""The canonical name of the SI unit of acceleration used in ``stats.units``."""

FACTORS: dict[str, float] = {
    "g": G,
    "mg": 1e-3 * G,
    "gal": 1e-2,
    "m/s**2": 1.0,
    "mm/s**2": 1e-3,
    "nm/s**2": 1e-9,
    "in/s**2": 0.0254,
}
"""Factor from each canonical unit to m/s² (``g`` = 9.80665 m/s² exactly; 1 gal = 1 cm/s²)."""

_LENGTHS = {"m": "m/s**2", "cm": "gal", "mm": "mm/s**2", "nm": "nm/s**2", "in": "in/s**2"}
_ALIASES = {
    "g": "g",
    "gs": "g",
    "g's": "g",
    "g0": "g",
    "gn": "g",
    "gravity": "g",
    "mg": "mg",
    "millig": "mg",
    "milli-g": "mg",
    "gal": "gal",
    "gals": "gal",
    "galileo": "gal",
}
# "<length>/s**2" in all the usual spellings: m/s**2, m/s^2, m/s2, m/s/s, m/sec/sec, m/sec**2,
# m s-2, m*s^-2, ms-2, mps2, m·s⁻² ...
_PER_S2 = re.compile(
    r"^(?P<len>m|cm|mm|nm|in|inch|inches)"
    r"(?:/(?:s|sec)(?:\*\*2|\^2|2)|/(?:s|sec)/(?:s|sec)|\*?(?:s|sec)(?:\*\*|\^)?-2|ps2|pss)$"
)


def canonical_units(units: str) -> str:
    """The canonical name of an acceleration unit given in any accepted spelling.

    Parameters
    ----------
    units
        A unit name such as ``"g"``, ``"G"``, ``"gal"``, ``"cm/s^2"``, ``"cm/sec/sec"``,
        ``"m/s**2"``, ``"m/s2"``, ``"mm/s**2"`` (case, spaces and ``²``/``⁻²`` ignored).

    Returns
    -------
    str
        One of the keys of :data:`FACTORS`: ``g``, ``mg``, ``gal``, ``m/s**2``, ``mm/s**2``,
        ``nm/s**2``, ``in/s**2``.

    Raises
    ------
    UnitsError
        If the unit is not an acceleration unit floorslide knows.
    """
    if not isinstance(units, str):
        raise UnitsError(f"units must be a string such as 'g' or 'm/s**2', not {units!r}")
    key = units.strip().lower()
    for old, new in (("²", "2"), ("⁻", "-"), ("·", "*"), (" ", ""), ("seconds", "s")):
        key = key.replace(old, new)
    if key in FACTORS:
        return key
    if key in _ALIASES:
        return _ALIASES[key]
    match = _PER_S2.match(key)
    if match:
        length = match.group("len")
        return _LENGTHS["in" if length.startswith("in") else length]
    accepted = ", ".join(FACTORS)
    raise UnitsError(
        f"unknown units {units!r}; expected one of {accepted} "
        "(also spelled e.g. G, cm/s^2, cm/sec/sec, m/s2)"
    )


def to_si_factor(units: str) -> float:
    """Factor that converts an acceleration in ``units`` to m/s².

    Parameters
    ----------
    units
        Any spelling accepted by :func:`canonical_units`.

    Returns
    -------
    float
        The factor: ``value_in_m_s2 = factor * value_in_units`` (e.g. 9.80665 for ``"g"``,
        0.01 for ``"gal"``).

    Raises
    ------
    UnitsError
        If the unit is unknown.

    Examples
    --------
    >>> to_si_factor("g")
    9.80665
    >>> to_si_factor("cm/s^2")
    0.01
    """
    return FACTORS[canonical_units(units)]
