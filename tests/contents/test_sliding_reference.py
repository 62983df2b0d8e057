"""Exact sliding against independent references on real bundled records.

Two references: floorslide's own ``method="solve_ivp"`` (SciPy's DOP853, rtol 1e-12, building
and block together with event location, restarted at every sample, steps ≤ dt/16), and — so
that a convention shared by floorslide's methods cannot hide a mistake (issue 20 §4) — the
references of ``tests/reference.py``, written apart from the package: the closed-form block on
the ground, DOP853 on the augmented building + block state, and DOP853 with lift-off for
vertical shaking. Agreement is required to 1e-8 relative for slides above 1 mm (docs/design.md
§7, issue 4).
"""

from __future__ import annotations

import numpy as np
import pytest

from floorslide.building.model import IsolatedBuilding, ShearBuilding
from floorslide.contents.sliding import slide
from tests.reference import rigid_block_ground, rigid_block_on_system, rigid_block_vertical


def independent(acc, dt, exact, building=None, floor=None, vertical=None):
    """``exact`` (a SlideResult) against the references written apart from the package."""
    for i, (mk, ms) in enumerate(zip(exact.mu_k, exact.mu_s, strict=True)):
        if vertical is not None:
            assert mk == ms
            peak, resid = rigid_block_vertical(acc, vertical, dt, mk)
        elif building is None:
            peak, resid = rigid_block_ground(acc, dt, mk, ms)
        else:
            A, B = building.state_matrices()
            C, D, _ = building.output_matrices([floor], "acceleration")
            peak, resid = rigid_block_on_system(A, B[:, 0], C[0], D[0, 0], acc, dt, mk, ms)
        scale = max(peak, 1e-3)
        assert abs(exact.peak_slide[i] - peak) <= 1e-8 * scale
        assert abs(exact.residual_slide[i] - resid) <= 1e-8 * scale


def compare(acc, dt, mu_k, mu_s=None, **kw):
    exact = slide(acc, dt, mu_k, mu_s, **kw)
    ref = slide(acc, dt, mu_k, mu_s, method="solve_ivp", rtol=1e-12, max_step=dt / 16, **kw)
    big = exact.peak_slide > 1e-3
    assert big.any()
    np.testing.assert_allclose(exact.peak_slide[big], ref.peak_slide[big], rtol=1e-8)
    residual_err = np.abs(exact.residual_slide - ref.residual_slide)[big]
    assert np.all(residual_err <= 1e-8 * exact.peak_slide[big])
    small = ~big
    np.testing.assert_allclose(exact.peak_slide[small], ref.peak_slide[small], rtol=0, atol=1e-11)
    return exact


@pytest.mark.slow
def test_ground_real_record(elcentro):
    acc, dt = elcentro
    res = compare(acc[:1000], dt, [0.05, 0.15], [0.05, 0.2])  # the strong motion (10 s)
    independent(acc[:1000], dt, res)


@pytest.mark.slow
def test_stiff_building_floor_real_record(elcentro):
    acc, dt = elcentro
    fb = ShearBuilding.from_period(1, 0.1, 0.05)
    res = compare(acc[:600], dt, [0.1, 0.2], building=fb, floor=1)
    independent(acc[:600], dt, res, fb, 1)


@pytest.mark.slow
def test_isolated_roof_real_record(coarse_record):
    acc, dt = coarse_record
    iso = IsolatedBuilding(ShearBuilding.from_period(2, 0.3, 0.02), 1.0, 2.0, 0.1)
    res = compare(acc[:700], dt, [0.05, 0.1], building=iso, floor=2)
    independent(acc[:700], dt, res, iso, 2)


@pytest.mark.slow
def test_vertical_shaking_real_record(elcentro):
    acc, dt = elcentro
    vert = 0.6 * acc[::-1].copy()  # a second real component as vertical motion (|a_v| < g)
    # the first 8 s (strong motion; the references restart at every sample and lift-off)
    res = compare(acc[:800], dt, [0.1, 0.2], vertical=vert[:800])
    independent(acc[:800], dt, res, vertical=vert[:800])
    plain = slide(acc[:800], dt, [0.1, 0.2])
    assert not np.allclose(res.peak_slide, plain.peak_slide, rtol=1e-3)


@pytest.mark.slow
@pytest.mark.parametrize("direction", ["positive", "negative"])
def test_one_way_sliding_real_record(direction, elcentro):
    acc, dt = elcentro
    res = compare(acc[:1000], dt, [0.1, 0.15], direction=direction)
    sign = -1 if direction == "positive" else 1
    assert np.all(sign * res.residual_slide >= 0)
