"""Records: reading accelerograms (formats as ObsPy plugins), catalogs, processing, measures.

docs/design.md §1 steps 1–2: any accelerogram file becomes an :class:`obspy.Trace` in m/s² with its
metadata (:func:`read_record`, :func:`read_catalog`), processed only as asked (:func:`process`),
described by exact intensity measures (:func:`measures`) and checked (:func:`check_record`:
mean offset, trend, clipping, truncation, sampling).
"""

from floorslide.records.catalog import RecordFailure, load_catalog, read_catalog
from floorslide.records.measures import measures
from floorslide.records.pairs import RecordPair, make_pair, read_pair, read_pairs
from floorslide.records.process import process
from floorslide.records.quality import check_record
from floorslide.records.read import read_record
from floorslide.records.units import canonical_units, to_si_factor

__all__ = [
    "RecordFailure",
    "RecordPair",
    "make_pair",
    "read_pair",
    "read_pairs",
    "canonical_units",
    "check_record",
    "load_catalog",
    "measures",
    "process",
    "read_catalog",
    "read_record",
    "to_si_factor",
]
