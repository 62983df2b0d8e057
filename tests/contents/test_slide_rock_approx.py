"""The approximate slide–rock scheme (floorslide.contents.slide_rock_approx, for the bench)
against the independent reference (tests/reference_sliderock.py) on real records: its errors
fall as its step shrinks — at RK4's fourth order while the block only rocks, more slowly once it
slides while rocking (measured: about first order on El Centro's slide–rock, whose instants
decided at a step's end are O(h)) — and its mode times agree to a small part of dt."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floorslide.constants import G
from floorslide.contents.slide_rock_approx import COLUMNS, fixed_step
from floorslide.errors import SolverLimitError
from tests.conftest import load_slammer
from tests.reference_sliderock import slide_rock_reference

SUBSTEPS = (4, 8, 16, 32)

CASES = {
    # file, samples, width, height, mu_k, mu_s
    "kobe rock": ("Kobe_1995_KAK-000.txt", 2000, 0.25, 1.2, 0.2, 0.3),
    "elc rock": ("ImperialValley_1940_ELC-180.txt", 1500, 0.3, 1.2, 0.22, 0.27),
    "elc slide-rock": ("ImperialValley_1940_ELC-180.txt", 1500, 0.3, 1.2, 0.25, 0.26),
    "petrolia all modes": ("CapeMendocino_1992_PET-090.txt", 1000, 0.3, 1.2, 0.22, 0.27),
}


def housner(width, height):
    return 1.0 - 1.5 * math.sin(math.atan2(width, height)) ** 2


def run(key):
    name, n, width, height, mu_k, mu_s = CASES[key]
    acc, dt = load_slammer(name)
    acc = acc[:n]
    ref = slide_rock_reference(acc, dt, width, height, mu_k, mu_s)
    rows = [
        fixed_step(acc, dt, [width], [height], [mu_k], [mu_s], [housner(width, height)], G, k)[0]
        for k in SUBSTEPS
    ]
    return ref, np.array(rows), dt


@pytest.mark.parametrize("key", ["kobe rock", "elc rock"])
def test_fourth_order_while_it_only_rocks(key):
    ref, rows, _ = run(key)
    assert ref["impacts"] > 100 and ref["mode_time"][1] == ref["mode_time"][3] == 0.0
    errors = np.abs(rows[:, COLUMNS.index("peak_ratio")] - ref["peak_ratio"])
    # measured: ratios 14–19 per halving (order ≈ 4); a second-order scheme gives 4
    assert (errors[:-1] / np.maximum(errors[1:], 1e-16) > 10).all()
    assert errors[0] < 1e-8
    assert (rows[:, COLUMNS.index("impacts")] == ref["impacts"]).all()
    times = rows[:, 6:10]
    assert np.max(np.abs(times - ref["mode_time"])) < 1e-6
    assert np.max(np.abs(times[-1] - ref["mode_time"])) < 1e-8


@pytest.mark.parametrize("key", ["elc slide-rock", "petrolia all modes"])
def test_converges_where_it_slides_and_rocks(key):
    ref, rows, dt = run(key)
    assert ref["mode_time"][3] > 0.05 and ref["peak_slide"] > 1e-3
    slide = np.abs(rows[:, COLUMNS.index("peak_slide")] - ref["peak_slide"]) / ref["peak_slide"]
    ratio = np.abs(rows[:, COLUMNS.index("peak_ratio")] - ref["peak_ratio"])
    # measured (k = 4 → 32): slide 9.3e-7 → 1.1e-7 (elc), 1.5e-4 → 2e-7 (petrolia); ratio
    # 8.6e-8 → 1e-8 (elc), 3e-8 → 1e-11 (petrolia): at least first order
    for err in (slide, ratio):
        assert err[-1] <= err[0] / 6
        assert (np.diff(err) < 0.1 * err[0]).all()
    assert slide[-1] < 1e-6 and ratio[-1] < 1e-7
    residual = rows[:, COLUMNS.index("residual_slide")]
    assert abs(residual[-1] - ref["residual_slide"]) < 1e-6 * ref["peak_slide"] + 1e-6
    assert (np.abs(rows[:, COLUMNS.index("impacts")] - ref["impacts"]) <= 1).all()
    times = rows[:, 6:10]
    assert np.max(np.abs(times - ref["mode_time"])) < 0.1 * dt
    assert np.max(np.abs(times[-1] - ref["mode_time"])) < 0.01 * dt
    np.testing.assert_allclose(times.sum(axis=1), ref["mode_time"].sum(), rtol=1e-12)


def test_overturning():
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    acc = acc[:1500]
    ref = slide_rock_reference(acc, dt, 0.25, 1.2, 0.2, 0.3)
    assert ref["overturned"]
    out = fixed_step(acc, dt, [0.25], [1.2], [0.2], [0.3], [housner(0.25, 1.2)], G, 8)[0]
    assert out[COLUMNS.index("overturned")] == 1.0 and out[COLUMNS.index("peak_ratio")] == 1.0
    assert math.isnan(out[COLUMNS.index("residual_slide")])
    assert out[COLUMNS.index("overturn_time")] == pytest.approx(ref["overturn_time"], abs=1e-6)
    assert out[COLUMNS.index("impacts")] == ref["impacts"]


def test_a_squat_block_slides_as_the_reference():
    """Sliding alone is a cubic in a step (linear floor): RK4 is exact on it and the stops are
    polished to rounding, so every substep count gives the reference's slide."""
    acc, dt = load_slammer("CapeMendocino_1992_PET-090.txt")
    acc = acc[:1000]
    ref = slide_rock_reference(acc, dt, 0.5, 1.2, 0.2, 0.3)
    for k in (1, 4):
        out = fixed_step(acc, dt, [0.5], [1.2], [0.2], [0.3], [housner(0.5, 1.2)], G, k)[0]
        assert abs(out[0] - ref["peak_slide"]) <= 1e-12 * ref["peak_slide"]
        assert abs(out[1] - ref["residual_slide"]) <= 1e-12 * ref["peak_slide"]
        np.testing.assert_allclose(out[6:10], ref["mode_time"], atol=1e-10)


def test_many_blocks_in_one_call_and_the_painleve_case():
    acc, dt = load_slammer("CapeMendocino_1992_PET-090.txt")
    acc = acc[:1000]
    B, H = np.array([0.3, 0.5]), np.array([1.2, 1.2])
    r = np.array([housner(0.3, 1.2), housner(0.5, 1.2)])
    both = fixed_step(acc, dt, B, H, [0.22, 0.2], [0.27, 0.3], r, G, 4)
    for i in range(2):
        one = fixed_step(acc, dt, B[i : i + 1], H[i : i + 1], [[0.22, 0.2][i]], [[0.27, 0.3][i]],
                         r[i : i + 1], G, 4)  # fmt: skip
        np.testing.assert_array_equal(both[i], one[0])
    pulse = np.r_[-60.0 * G * np.ones(3), 60 * G * np.ones(20)]
    with pytest.raises(SolverLimitError, match="Painlevé"):
        fixed_step(pulse, 0.01, [0.2], [1.2], [100.0], [100.0], [1.0], G, 4)
    with pytest.raises(ValueError, match="mu_s"):
        fixed_step(acc, dt, [0.3], [1.2], [0.3], [0.2], [1.0], G, 4)
