"""What one task (a record on a building) produces: plain data classes of NumPy arrays.

They travel from a worker (local process or Dask) to the single writer of the result file and
back out of it for tables and figures.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class ContentResult:
    """One content (equipment type) on one floor of a task, one entry per friction pair.

    ``mode`` is Shenton's response mode from the floor's true PFA (``"slide"`` when no geometry
    was given); ``skipped`` says why nothing was integrated (``""`` when it was): the exact
    answer of a skipped slider is then zero slide and the floor's peak acceleration.

    A content with width and height that rocks (Shenton's ``rock`` or ``slide-rock``) is
    simulated as one block that rocks, slides, or slides while it rocks
    (:func:`floorslide.slide_rock`, once per friction pair: once the friction a rocking block
    needs exceeds ``mu_s`` its corner slips): its sliding arrays hold that block's slide
    (its peak acceleration NaN, its slip phases −1 unless it stayed at rest: not tracked),
    its rocking arrays its rotation, ``slide_rock_time`` the time it spent sliding and
    rocking at once, and ``outcomes`` what it did — ``rest``, ``slide``, ``rock``,
    ``slide-rock`` (it both slid and rocked) or ``overturn``.
    """

    content: str
    floor: int
    model: str  # "rigid" or "oscillator"
    mode: str
    skipped: str
    mu_k: np.ndarray
    mu_s: np.ndarray
    peak_slide: np.ndarray
    residual_slide: np.ndarray
    peak_abs_accel: np.ndarray
    slide_fraction: np.ndarray
    slip_phases: np.ndarray
    vertical: bool = False
    peak_deformation: np.ndarray | None = None
    peak_top_accel: np.ndarray | None = None
    modes: np.ndarray | None = None  # per friction pair: rest, slide, rock or slide-rock
    # rocking (contents with width and height; None otherwise), per friction pair: NaN (−1 for
    # the impacts) where the object slides instead (Shenton 1996), 0 where it stays at rest
    rock_peak_ratio: np.ndarray | None = None  # max|θ|/α, 1 when it overturned
    rock_impacts: np.ndarray | None = None
    rock_time: np.ndarray | None = None  # s spent rocking (sliding or not)
    overturned: np.ndarray | None = None  # 1.0 or 0.0
    overturn_time: np.ndarray | None = None  # s (NaN: never)
    outcomes: np.ndarray | None = None  # observed: rest, slide, rock, overturn or slide-rock
    # a pair of horizontal components (None for one): the block slides in the plane; then
    # peak_slide is the peak |u|, residual_slide |u(end)|, and per friction pair
    peak_angle: np.ndarray | None = None  # direction of the peak, degrees from h1 towards h2
    residual_h1: np.ndarray | None = None  # the residual vector's components, m
    residual_h2: np.ndarray | None = None
    peak_slide_h1: np.ndarray | None = None  # each component's 1-D slide alone, m
    peak_slide_h2: np.ndarray | None = None
    ratio_2d_1d: np.ndarray | None = None  # peak_slide / max(1-D slides)
    # rocking: the impacts at |θ'| ≥ p·α·√(f(2 − f)), f = 0.01 (RockResult.significant_impacts;
    # SlideRockResult.significant_impacts; −1 where it slides instead; None in files written
    # before they were counted)
    rock_significant_impacts: np.ndarray | None = None
    # rocking: s spent sliding and rocking at once (0 where it slides or rests; NaN in files
    # written before slide–rock was simulated)
    slide_rock_time: np.ndarray | None = None
    # heavy equipment coupled with its floor (floor_mass_ratio, coupled): the floor's true PFA
    # with the block on it, per friction pair (NaN where it was not integrated)
    coupled_pfa: np.ndarray | None = None


ROCK_FIELDS = ("rock_peak_ratio", "rock_impacts", "rock_time", "overturned", "overturn_time")
"""The rocking arrays of a :class:`ContentResult` (present together, or all None)."""
PLANE_FIELDS = (
    "peak_angle",
    "residual_h1",
    "residual_h2",
    "peak_slide_h1",
    "peak_slide_h2",
    "ratio_2d_1d",
)
"""The arrays of a :class:`ContentResult` of a pair of components (present together, or all
None)."""


@dataclass
class SpectrumResult:
    """Floor response spectra of one floor of a task.

    ``psa``, ``sa``, ``sv``, ``sd`` are the spectra as computed (unbroadened; NaN when a file
    written before they were kept holds only broadened ones). With ``broadening > 0`` the
    ``*_broadened`` arrays are the spectra widened by ``±broadening`` in frequency
    (:func:`floorslide.spectra.broaden`), else None.
    """

    floor: int
    periods: np.ndarray
    damping: np.ndarray
    psa: np.ndarray
    sa: np.ndarray
    sv: np.ndarray
    sd: np.ndarray
    broadening: float = 0.0
    psa_broadened: np.ndarray | None = None
    sa_broadened: np.ndarray | None = None
    sv_broadened: np.ndarray | None = None
    sd_broadened: np.ndarray | None = None
    orientation: str = ""
    """``""`` for one component; ``"RotD50"`` for a pair of horizontal components: then ``psa``
    is RotD50 (Boore 2010), ``sd = psa/ω²`` the same for the displacement, ``sa`` and ``sv``
    are NaN (not defined by RotD), and ``rotd100``, ``psa_h1``, ``psa_h2`` hold RotD100 and
    each direction's PSA."""
    rotd100: np.ndarray | None = None
    psa_h1: np.ndarray | None = None
    psa_h2: np.ndarray | None = None


@dataclass
class Histories:
    """Histories kept for figures (one record of the study): floor accelerations and slides.

    Keys are ``"content/floor_f"``; each value has one row per stored friction value
    (``(n_mu, npts)``). ``slides`` is the slide u relative to the floor (of the sliding base
    for a 2-DOF oscillator); ``deformation`` (spring deformation z, m) and ``top_accel`` (the
    top mass's absolute acceleration, m/s²) are kept for oscillators only.

    On a building on nonlinear isolation ``isolator_displacement`` (the isolator's displacement
    u₀ relative to the ground, m) and ``isolator_force_ratio`` (the isolation layer's force on
    the base mat over the total weight W, the base shear ratio V/W) at the samples give its
    hysteresis loop; both are None for every other building (and in files written before they
    were kept).

    ``rocking`` holds, per content that rocks under the record (same keys), its rotation over
    its slenderness ``θ/α`` at the samples (NaN after it overturned): of the friction pair that
    overturned first, else of the largest peak rotation. Under a friction value under which
    the object rocks ``slides`` holds its slide–rock block's slide ``U`` (one component); of a
    pair of components it is NaN there.

    For a pair of horizontal components ``floor_acceleration`` is along ``h1`` and
    ``floor_acceleration_h2`` along ``h2``; ``slides`` holds the slide's magnitude ``|u|`` and
    ``plane`` the slide vector ``(u_h1, u_h2)`` (``(n_mu, npts, 2)``, the path in the plane);
    on nonlinear isolation ``isolator_displacement``/``isolator_force_ratio`` are then along
    ``h1`` and ``isolator_displacement_h2``/``isolator_force_ratio_h2`` along ``h2`` (the
    bearing's orbit and its force vector over W).
    """

    dt: float
    floors: np.ndarray
    floor_acceleration: np.ndarray  # (n_floors, npts), m/s²
    slides: dict[str, np.ndarray] = field(default_factory=dict)
    mu_k: dict[str, np.ndarray] = field(default_factory=dict)
    deformation: dict[str, np.ndarray] = field(default_factory=dict)
    top_accel: dict[str, np.ndarray] = field(default_factory=dict)
    isolator_displacement: np.ndarray | None = None  # (npts,), m
    isolator_force_ratio: np.ndarray | None = None  # (npts,), V/W
    rocking: dict[str, np.ndarray] = field(default_factory=dict)  # θ/α, (npts,), NaN overturned
    plane: dict[str, np.ndarray] = field(default_factory=dict)  # pairs: u, (n_mu, npts, 2), m
    floor_acceleration_h2: np.ndarray | None = None  # pairs: along h2, (n_floors, npts), m/s²
    isolator_displacement_h2: np.ndarray | None = None  # pairs on nonlinear isolation, (npts,)
    isolator_force_ratio_h2: np.ndarray | None = None  # pairs on nonlinear isolation, (npts,)


@dataclass
class TaskResult:
    """Everything one task computed."""

    task_id: str
    meta: dict
    floors: np.ndarray
    pfa: np.ndarray
    contents: list[ContentResult] = field(default_factory=list)
    spectra: list[SpectrumResult] = field(default_factory=list)
    histories: Histories | None = None
    seconds: float = 0.0
    pfa_components: np.ndarray | None = None
    """A pair's true peak floor accelerations along each component, ``(n_floors, 2)``, m/s²
    (``pfa`` is then the peak of the vector); None for one component."""
