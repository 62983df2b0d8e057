"""Buildings: fixed-base and isolated shear buildings as state space, exact floor motions."""

from floorslide.building.directions import BuildingPair, per_direction, plane_motions
from floorslide.building.exact import ExactStepper, foh_matrices
from floorslide.building.exact_motion import (
    BuildingMotion,
    FloorMotion,
    building_motion,
    floor_motion,
)
from floorslide.building.isolators import BilinearIsolator, FrictionPendulum
from floorslide.building.model import (
    IsolatedBuilding,
    LinearBuilding,
    ModalProperties,
    Rayleigh,
    ShearBuilding,
)
from floorslide.building.motions import Peaks, floor_motions, peak_floor_acceleration
from floorslide.building.nonlinear import (
    IsolatorResponse,
    NonlinearIsolatedBuilding,
    isolator_response,
)
from floorslide.building.nonlinear_motion import NonlinearFloorMotion, NonlinearMotion

__all__ = [
    "BilinearIsolator",
    "BuildingPair",
    "per_direction",
    "plane_motions",
    "BuildingMotion",
    "ExactStepper",
    "FloorMotion",
    "FrictionPendulum",
    "IsolatorResponse",
    "NonlinearIsolatedBuilding",
    "NonlinearFloorMotion",
    "NonlinearMotion",
    "isolator_response",
    "building_motion",
    "floor_motion",
    "IsolatedBuilding",
    "LinearBuilding",
    "ModalProperties",
    "Peaks",
    "Rayleigh",
    "ShearBuilding",
    "floor_motions",
    "foh_matrices",
    "peak_floor_acceleration",
]
