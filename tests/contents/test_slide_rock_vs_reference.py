"""fs.slide_rock against the independent event-located reference (tests/reference_sliderock.py,
DOP853 at rtol 1e-13, written apart from the kernel) on real records, with blocks that go through
rest, slide, rock, slide–rock and overturning, on the ground and on a roof. Measured: θ within
3.8e-12·α, the slide within 7e-14 m, the mode at every sample, the impacts and the seconds in each
mode identical (to 1e-9)."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from tests.conftest import load_slammer
from tests.reference_sliderock import slide_rock_reference

CASES = {
    # file, samples, scale, width, height, mu_k, mu_s
    "elc slide-rock": ("ImperialValley_1940_ELC-180.txt", 1500, 1.0, 0.3, 1.2, 0.25, 0.26),
    "petrolia all modes": ("CapeMendocino_1992_PET-090.txt", 1000, 1.0, 0.3, 1.2, 0.22, 0.27),
    "petrolia long slide-rock": ("CapeMendocino_1992_PET-090.txt", 1000, 1.0, 0.3, 1.2, 0.25, 0.26),
    "kobe overturns": ("Kobe_1995_KAK-000.txt", 1500, 3.5, 0.4, 1.6, 0.26, 0.3),
}


def assert_agree(r, ref, modes=True):
    a = r.alpha[0]
    scale = max(float(np.nanmax(np.abs(ref["slide"]))), 1e-3)
    np.testing.assert_allclose(r.theta[0] / a, ref["theta"] / a, rtol=0, atol=1e-10)
    np.testing.assert_allclose(r.slide[0], ref["slide"], rtol=0, atol=1e-10 * scale)
    assert r.impacts[0] == ref["impacts"]
    assert bool(r.overturned[0]) == bool(ref["overturned"])
    np.testing.assert_allclose(r.peak_ratio[0], ref["peak_ratio"], rtol=0, atol=1e-10)
    np.testing.assert_allclose(r.peak_slide[0], ref["peak_slide"], rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(r.mode_time[0], ref["mode_time"], rtol=1e-9, atol=1e-9)
    if modes:
        np.testing.assert_array_equal(r.mode_history[0], ref["mode"])


@pytest.mark.parametrize("key", list(CASES))
def test_on_the_ground(key):
    name, n, scale, W, H, mk, ms = CASES[key]
    acc, dt = load_slammer(name)
    acc = acc[:n] * scale
    ref = slide_rock_reference(acc, dt, W, H, mk, ms)
    r = fs.slide_rock(acc, dt, W, H, mk, mu_s=ms, histories=True)
    assert r.mode_time[0, 3] > 0.0  # it slides while it rocks
    assert_agree(r, ref)


def test_on_a_roof():
    """The reference integrates the building with the block (its state-space model); the solver
    reads the building's exact floor polynomials."""
    b = fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.03)
    ss = b.state_space(floors=[1])
    system = (np.asarray(ss.A), np.asarray(ss.B)[:, 0], np.asarray(ss.C)[0], float(ss.D[0, 0]))
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    acc = acc[:600]
    ref = slide_rock_reference(acc, dt, 0.3, 1.2, 0.22, 0.27, floor_system=system)
    r = fs.slide_rock(acc, dt, 0.3, 1.2, 0.22, mu_s=0.27, building=b, floor=1, histories=True)
    assert r.mode_time[0, 3] > 0.0
    assert_agree(r, ref)
