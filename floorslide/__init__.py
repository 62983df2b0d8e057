"""floorslide: sliding of freestanding equipment on the floors of fixed-base and base-isolated
buildings under recorded earthquakes.

The public API (docs/design.md §3) is re-exported here; nothing else lives in this module.
The names are resolved on first use (PEP 562), so ``import floorslide`` — and the command line's
``--help`` — does not pay for numba, SciPy, python-control, ObsPy or matplotlib until a name that
needs them is used.
"""

from __future__ import annotations

import importlib
from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as _version
from typing import TYPE_CHECKING

_EXPORTS: dict[str, tuple[str, ...]] = {
    "floorslide.building": (
        "BilinearIsolator",
        "BuildingMotion",
        "BuildingPair",
        "FloorMotion",
        "FrictionPendulum",
        "IsolatedBuilding",
        "IsolatorResponse",
        "NonlinearFloorMotion",
        "NonlinearIsolatedBuilding",
        "NonlinearMotion",
        "Rayleigh",
        "ShearBuilding",
        "building_motion",
        "floor_motion",
        "floor_motions",
        "isolator_response",
        "peak_floor_acceleration",
    ),
    "floorslide.constants": ("G",),
    "floorslide.contents": (
        "CoupledSlideResult",
        "OscillatorResult",
        "PlaneOscillatorResult",
        "PlaneSlideResult",
        "RockResult",
        "SlideResult",
        "SlideRockResult",
        "response_mode",
        "rock",
        "slide",
        "slide_coupled",
        "slide_oscillator",
        "slide_oscillator_plane",
        "slide_plane",
        "slide_rock",
    ),
    "floorslide.errors": (
        "FloorslideError",
        "FloorslideWarning",
        "IncompleteResultError",
        "ModelError",
        "OutputError",
        "OutputExistsError",
        "RecordError",
        "ResultFileError",
        "SceneError",
        "UnitsConversionWarning",
        "UnitsError",
    ),
    "floorslide.records": (
        "RecordPair",
        "check_record",
        "measures",
        "process",
        "read_catalog",
        "read_pair",
        "read_pairs",
        "read_record",
    ),
    "floorslide.report": (
        "design_tables",
        "plot_figures",
        "record_table",
        "spectra_table",
    ),
    "floorslide.spectra": (
        "RotDSpectrum",
        "Spectrum",
        "broaden",
        "envelope",
        "response_spectrum",
        "rotd_spectrum",
    ),
}
"""The subpackage each public name is imported from, on first use."""

_SOURCE = {name: module for module, names in _EXPORTS.items() for name in names}

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs only
    from floorslide.building import (
        BilinearIsolator,
        BuildingMotion,
        BuildingPair,
        FloorMotion,
        FrictionPendulum,
        IsolatedBuilding,
        IsolatorResponse,
        NonlinearFloorMotion,
        NonlinearIsolatedBuilding,
        NonlinearMotion,
        Rayleigh,
        ShearBuilding,
        building_motion,
        floor_motion,
        floor_motions,
        isolator_response,
        peak_floor_acceleration,
    )
    from floorslide.constants import (
        G,
    )
    from floorslide.contents import (
        CoupledSlideResult,
        OscillatorResult,
        PlaneOscillatorResult,
        PlaneSlideResult,
        RockResult,
        SlideResult,
        SlideRockResult,
        response_mode,
        rock,
        slide,
        slide_coupled,
        slide_oscillator,
        slide_oscillator_plane,
        slide_plane,
        slide_rock,
    )
    from floorslide.errors import (
        FloorslideError,
        FloorslideWarning,
        IncompleteResultError,
        ModelError,
        OutputError,
        OutputExistsError,
        RecordError,
        ResultFileError,
        SceneError,
        UnitsConversionWarning,
        UnitsError,
    )
    from floorslide.records import (
        RecordPair,
        check_record,
        measures,
        process,
        read_catalog,
        read_pair,
        read_pairs,
        read_record,
    )
    from floorslide.report import (
        design_tables,
        plot_figures,
        record_table,
        spectra_table,
    )
    from floorslide.spectra import (
        RotDSpectrum,
        Spectrum,
        broaden,
        envelope,
        response_spectrum,
        rotd_spectrum,
    )


def __getattr__(name: str):
    """Import a public name from its subpackage on first use (PEP 562)."""
    module = _SOURCE.get(name)
    if module is None:
        raise AttributeError(f"module 'floorslide' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_SOURCE))


try:
    __version__ = _version("floorslide")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

__all__ = [
    "BilinearIsolator",
    "BuildingMotion",
    "FloorMotion",
    "FrictionPendulum",
    "G",
    "IsolatedBuilding",
    "IsolatorResponse",
    "NonlinearIsolatedBuilding",
    "NonlinearMotion",
    "NonlinearFloorMotion",
    "isolator_response",
    "Rayleigh",
    "ShearBuilding",
    "OscillatorResult",
    "PlaneSlideResult",
    "PlaneOscillatorResult",
    "RecordPair",
    "BuildingPair",
    "RockResult",
    "SlideResult",
    "CoupledSlideResult",
    "slide_coupled",
    "SlideRockResult",
    "slide_rock",
    "Spectrum",
    "broaden",
    "design_tables",
    "plot_figures",
    "record_table",
    "spectra_table",
    "envelope",
    "response_mode",
    "response_spectrum",
    "rotd_spectrum",
    "RotDSpectrum",
    "slide_oscillator",
    "slide_oscillator_plane",
    "building_motion",
    "floor_motion",
    "floor_motions",
    "peak_floor_acceleration",
    "read_pair",
    "read_pairs",
    "rock",
    "slide",
    "slide_plane",
    "FloorslideError",
    "FloorslideWarning",
    "IncompleteResultError",
    "ModelError",
    "OutputError",
    "OutputExistsError",
    "RecordError",
    "ResultFileError",
    "SceneError",
    "UnitsConversionWarning",
    "UnitsError",
    "check_record",
    "measures",
    "process",
    "read_catalog",
    "read_record",
]
