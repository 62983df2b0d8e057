"""Shared fixtures: real bundled records (data/ only, never ../shared).

Property tests and fuzzers (hypothesis) draw the same examples on every run, so that the test
command gives the same verdict on every machine; ``FLOORSLIDE_HYPOTHESIS=explore`` draws new
random examples each run (how the fuzzers find new bugs).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import settings

settings.register_profile("deterministic", derandomize=True, database=None)
settings.register_profile("explore")
settings.load_profile(os.environ.get("FLOORSLIDE_HYPOTHESIS", "deterministic"))

ROOT = Path(__file__).resolve().parents[1]
SLAMMER = ROOT / "data" / "records" / "slammer"
G = 9.80665


def load_slammer(name: str) -> tuple[np.ndarray, float]:
    """A bundled SLAMMER record in m/s² and its dt (read with NumPy, independent of floorslide's
    readers so that numerical tests do not depend on them)."""
    import csv

    with open(SLAMMER / "index.csv", newline="") as fh:
        rows = {r["file"]: r for r in csv.DictReader(fh)}
    row = rows[name]
    return np.loadtxt(SLAMMER / name) * G, float(row["dt"])


@pytest.fixture(scope="session")
def elcentro():
    """El Centro 1940 NS (ELC-180), dt = 0.01 s, m/s²."""
    return load_slammer("ImperialValley_1940_ELC-180.txt")


@pytest.fixture(scope="session")
def coarse_record():
    """Cape Mendocino 1992 Petrolia (PET-090), a pulse-like record at dt = 0.02 s, m/s²."""
    return load_slammer("CapeMendocino_1992_PET-090.txt")
