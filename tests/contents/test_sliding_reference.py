"""Exact sliding against an independent reference on real bundled records.

The reference is SciPy's DOP853 (rtol 1e-12) integrating the building and the block together
with event location, restarted at every sample and with steps ≤ dt/16 so that brief threshold
excursions inside a step are not stepped over. Agreement is required to 1e-8 relative for slides
above 1 mm (docs/design.md §7, issue 4).
"""

from __future__ import annotations

import numpy as np
import pytest

from floorslide.building.model import IsolatedBuilding, ShearBuilding
from floorslide.contents.sliding import slide


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


def test_ground_real_record(elcentro):
    acc, dt = elcentro
    compare(acc[:1800], dt, [0.05, 0.15], [0.05, 0.2])


def test_stiff_building_floor_real_record(elcentro):
    acc, dt = elcentro
    fb = ShearBuilding.from_period(1, 0.1, 0.05)
    compare(acc[:1200], dt, [0.1, 0.2], building=fb, floor=1)


def test_isolated_roof_real_record(coarse_record):
    acc, dt = coarse_record
    iso = IsolatedBuilding(ShearBuilding.from_period(2, 0.3, 0.02), 1.0, 2.0, 0.1)
    compare(acc[:700], dt, [0.05, 0.1], building=iso, floor=2)


def test_vertical_shaking_real_record(elcentro):
    acc, dt = elcentro
    vert = 0.6 * acc[::-1].copy()  # a second real component as vertical motion (|a_v| < g)
    res = compare(acc[:1500], dt, [0.1, 0.2], vertical=vert[:1500])
    plain = slide(acc[:1500], dt, [0.1, 0.2])
    assert not np.allclose(res.peak_slide, plain.peak_slide, rtol=1e-3)


@pytest.mark.parametrize("direction", ["positive", "negative"])
def test_one_way_sliding_real_record(direction, elcentro):
    acc, dt = elcentro
    res = compare(acc[:1500], dt, [0.1, 0.15], direction=direction)
    sign = -1 if direction == "positive" else 1
    assert np.all(sign * res.residual_slide >= 0)
