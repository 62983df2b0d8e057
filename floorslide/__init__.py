"""floorslide: sliding of freestanding equipment on the floors of fixed-base and base-isolated
buildings under recorded earthquakes.

The public API (DESIGN §3) is re-exported here; nothing else lives in this module.
"""

from floorslide.errors import (
    FloorslideError,
    ModelError,
    RecordError,
    ResultFileError,
    SceneError,
    UnitsError,
)

G = 9.80665
"""Standard gravity, m/s² (DESIGN §2)."""

__all__ = [
    "G",
    "FloorslideError",
    "ModelError",
    "RecordError",
    "ResultFileError",
    "SceneError",
    "UnitsError",
]
