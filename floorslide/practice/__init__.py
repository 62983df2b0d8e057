"""Design practice around the exact results (docs/design.md §10e): target spectra and the scaling
of records to them, the code's floor amplification (ASCE 7-22 §13.3.1), and exceedance and
fragility of contents. Pure numerical functions; the scene, tables and report use them."""

from floorslide.practice.code import asce7_approximate_period, asce7_floor_amplification
from floorslide.practice.fragility import LognormalFragility, exceedance_fraction, fit_fragility
from floorslide.practice.target import (
    ScaleFit,
    TargetSpectrum,
    scale_factor,
    suite_check,
)

__all__ = [
    "LognormalFragility",
    "ScaleFit",
    "TargetSpectrum",
    "asce7_approximate_period",
    "asce7_floor_amplification",
    "exceedance_fraction",
    "fit_fragility",
    "scale_factor",
    "suite_check",
]
