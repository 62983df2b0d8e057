"""Shared fixtures: real bundled records (data/ only, never ../shared)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

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
