"""Fixtures of the records tests: real record files of the project only (data/, tests/data/)."""

from __future__ import annotations

import numpy as np
import pytest

from tests.conftest import ROOT, SLAMMER, G

FIXTURES = ROOT / "tests" / "data" / "records"
ELC_FILE = "ImperialValley_1940_ELC-180.txt"


@pytest.fixture(scope="session")
def elc_g() -> np.ndarray:
    """El Centro 1940 NS (ELC-180) in g as bundled, read with NumPy (independent of floorslide)."""
    return np.loadtxt(SLAMMER / ELC_FILE)


@pytest.fixture(scope="session")
def elc_si(elc_g) -> np.ndarray:
    """The same in m/s²."""
    return elc_g * G
