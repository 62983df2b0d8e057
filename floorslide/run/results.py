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


@dataclass
class SpectrumResult:
    """Floor response spectra of one floor of a task."""

    floor: int
    periods: np.ndarray
    damping: np.ndarray
    psa: np.ndarray
    sa: np.ndarray
    sv: np.ndarray
    sd: np.ndarray


@dataclass
class Histories:
    """Histories kept for figures (one record of the study): floor accelerations and slides."""

    dt: float
    floors: np.ndarray
    floor_acceleration: np.ndarray  # (n_floors, npts), m/s²
    slides: dict[str, np.ndarray] = field(default_factory=dict)  # "content/floor_f" → (n_mu, npts)
    mu_k: dict[str, np.ndarray] = field(default_factory=dict)


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
