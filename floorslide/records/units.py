"""Units of acceleration, as the records package has always exported them.

The table and the parser live in the neutral module :mod:`floorslide.units` (the numerical core
uses them too and must not import ObsPy, which ``floorslide.records`` does); this module
re-exports them.
"""

from floorslide.units import FACTORS, SI_UNITS, canonical_units, to_si_factor

__all__ = ["FACTORS", "SI_UNITS", "canonical_units", "to_si_factor"]
