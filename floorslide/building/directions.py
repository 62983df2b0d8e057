"""A building in both horizontal directions: one linear model per direction, uncoupled (no
torsion; docs/design.md §10d).

Each direction is the existing exact model (:mod:`floorslide.building.exact`) driven by the
pair's component along it — ``h1`` drives the model along ``x``, ``h2`` the one along ``y``. A
single :class:`~floorslide.building.model.LinearBuilding` stands for the same model in both
directions; :class:`BuildingPair` holds two (a period and damping per direction). The two
directions' floor motions are stepped on one time grid (the larger of the two sub-step counts),
so that the plane's solvers see both on the same sub-steps.

Nonlinear isolators are not split this way: a lead-rubber bearing or a friction pendulum
yields and slides under the *resultant* of both directions' forces (bidirectional plasticity),
which two uncoupled 1-D models would misstate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from floorslide.building.exact_motion import FloorMotion, building_motion, stepper
from floorslide.building.model import LinearBuilding
from floorslide.errors import ModelError


@dataclass(frozen=True)
class BuildingPair:
    """A building with its own linear model along each horizontal direction (uncoupled).

    Attributes
    ----------
    h1, h2
        The models along ``x`` (driven by the pair's ``h1``) and ``y`` (``h2``); the same
        number of floors.
    """

    h1: LinearBuilding
    h2: LinearBuilding

    def __post_init__(self) -> None:
        for name in ("h1", "h2"):
            b = getattr(self, name)
            if not isinstance(b, LinearBuilding):
                raise ModelError(
                    f"BuildingPair.{name} must be a linear building (ShearBuilding or "
                    f"IsolatedBuilding), got {type(b).__name__}: nonlinear isolators couple the "
                    "two directions",
                    name,
                )
        if self.h1.stories != self.h2.stories or _has_base(self.h1) != _has_base(self.h2):
            raise ModelError(
                f"the two directions' models have different floors ({_floors(self.h1)} and "
                f"{_floors(self.h2)}): one building has the same floors both ways",
                "h2",
            )

    @property
    def stories(self) -> int:
        """Number of storeys (the same both ways)."""
        return self.h1.stories


def _has_base(b: LinearBuilding) -> bool:
    return 0 in b.dof_floors


def _floors(b: LinearBuilding) -> str:
    return f"floors {'0..' if _has_base(b) else '1..'}{b.stories}"


def per_direction(building) -> tuple[LinearBuilding | None, LinearBuilding | None]:
    """The models along ``x`` and ``y``: ``(None, None)`` on the ground, the same model twice
    for one building, the two of a :class:`BuildingPair` (or of a 2-tuple)."""
    if building is None:
        return None, None
    if isinstance(building, BuildingPair):
        return building.h1, building.h2
    if isinstance(building, tuple | list):
        if len(building) != 2:
            raise ModelError(
                f"a building per direction is a pair of models, got {len(building)}", "building"
            )
        bp = BuildingPair(*building)
        return bp.h1, bp.h2
    if isinstance(building, LinearBuilding):
        return building, building
    if getattr(building, "segmented", False):
        raise ModelError(
            "a building on nonlinear isolation has no motion per direction (nonlinear isolators "
            "couple the two directions): fs.slide_plane, fs.rotd_spectrum and scenes with pair "
            "sets read its coupled plane motion (PlaneIsolatedMotion)",
            "building",
        )
    raise ModelError(
        f"building must be a linear building or a BuildingPair in the plane, got "
        f"{type(building).__name__}",
        "building",
    )


def plane_motions(
    building, h1: np.ndarray, h2: np.ndarray, dt: float, floor: int | None, **kw
) -> tuple[FloorMotion, FloorMotion]:
    """The exact motions of one floor along ``x`` and ``y`` (each direction's model under its
    component), on one time grid: both with the larger of the two directions' sub-step counts.

    Parameters
    ----------
    building
        None (the ground), one linear building (both directions), a :class:`BuildingPair` or a
        2-tuple of linear buildings.
    h1, h2
        Ground accelerations along ``x`` and ``y``, m/s², of equal length.
    dt
        Time step, s.
    floor
        The floor (0 or None on the ground).
    **kw
        Passed to :func:`~floorslide.building.exact_motion.building_motion` (``max_bytes``,
        ``copy``).
    """
    bx, by = per_direction(building)
    if bx is None:
        if floor not in (None, 0):
            raise ModelError("floor= needs building=", "floor")
        f = 0
    else:
        if floor is None:
            raise ModelError("floor is required with building=", "floor")
        f = int(floor)
    m = None
    if bx is not None:
        m = max(stepper(bx, dt).substeps, stepper(by, dt).substeps)
    fm1 = building_motion(bx, h1, dt, substeps=m, **kw).floor(f)
    fm2 = building_motion(by, h2, dt, substeps=m, **kw).floor(f)
    return fm1, fm2


def plane_peak(fm1: FloorMotion, fm2: FloorMotion) -> tuple[float, float]:
    """The true peak of the floor's horizontal acceleration vector, ``max_t |a(t)|`` with
    ``a = (a_x, a_y)``, inside steps, and its time (s): the level a block's static friction
    must hold in the plane. Both motions must come from :func:`plane_motions` (one time
    grid)."""
    from floorslide.building._plane_peak import plane_peak_kernel

    if fm1.substeps != fm2.substeps or fm1.acc.size != fm2.acc.size:
        raise ModelError("the two directions' motions are not on one time grid", "building")
    out = np.array([-1.0, 0.0])
    for (k0, X1), (_, X2) in zip(fm1.chunks(), fm2.chunks(), strict=True):
        plane_peak_kernel(X1, X2, k0, fm1.R, fm1.beta, fm2.R, fm2.beta, fm1.acc, fm2.acc,
                          fm1.substeps, fm1.h, out)  # fmt: skip
    return float(out[0]), float(out[1])
