"""floorslide: sliding of freestanding equipment on the floors of fixed-base and base-isolated
buildings under recorded earthquakes.

The public API (docs/design.md §3) is re-exported here; nothing else lives in this module.
"""

from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as _version

from floorslide.building import (
    BilinearIsolator,
    BuildingMotion,
    BuildingPair,
    FloorMotion,
    FrictionPendulum,
    IsolatedBuilding,
    IsolatorResponse,
    NonlinearIsolatedBuilding,
    Rayleigh,
    ShearBuilding,
    building_motion,
    floor_motion,
    floor_motions,
    isolator_response,
    peak_floor_acceleration,
)
from floorslide.constants import G
from floorslide.contents import (
    OscillatorResult,
    PlaneSlideResult,
    RockResult,
    SlideResult,
    response_mode,
    rock,
    slide,
    slide_oscillator,
    slide_plane,
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
from floorslide.report import design_tables, plot_figures, record_table
from floorslide.spectra import (
    RotDSpectrum,
    Spectrum,
    broaden,
    envelope,
    response_spectrum,
    rotd_spectrum,
)

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
    "isolator_response",
    "Rayleigh",
    "ShearBuilding",
    "OscillatorResult",
    "PlaneSlideResult",
    "RecordPair",
    "BuildingPair",
    "RockResult",
    "SlideResult",
    "Spectrum",
    "broaden",
    "design_tables",
    "plot_figures",
    "record_table",
    "envelope",
    "response_mode",
    "response_spectrum",
    "rotd_spectrum",
    "RotDSpectrum",
    "slide_oscillator",
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
