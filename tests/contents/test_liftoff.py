"""Vertical shaking with lift-off: the block flies (no friction) while g + a_v ≤ 0, and its
slide can peak in flight (the velocity reverses under the floor's acceleration); every peak is
found, against an event-located reference written apart from the kernel."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from tests.reference import rigid_block_vertical

G = 9.80665


def test_peak_slide_inside_a_flight():
    dt = 0.01
    n = 120
    t = np.arange(n) * dt
    # a push that starts the block sliding (u growing), then a floor acceleration that reverses
    # it while the vertical acceleration below −g lifts it off: u peaks in flight (near
    # t = 0.2875 s, between samples), and the block comes back less than that afterwards
    acc = np.where(t < 0.2, -0.6 * G, 0.8 * G)
    acc[t >= 0.32] = 0.0
    vert = np.where((t > 0.25) & (t < 0.32), -1.5 * G, 0.0)
    res = fs.slide(acc, dt, 0.2, vertical=vert)
    peak, resid = rigid_block_vertical(acc, vert, dt, 0.2)
    assert res.liftoff_count >= 1
    assert peak > abs(resid) + 0.01  # the peak is not the end value
    assert res.peak_slide[0] == pytest.approx(peak, rel=1e-8)
    assert res.residual_slide[0] == pytest.approx(resid, rel=1e-8, abs=1e-12)


@pytest.mark.slow
def test_vertical_shaking_on_a_real_record(elcentro):
    acc, dt = elcentro
    acc = np.ascontiguousarray(acc[:500])  # the peak slide and 15 lift-offs are in it
    vert = -1.2 * G * np.sin(2 * np.pi * 3.0 * np.arange(acc.size) * dt)
    for mu in (0.1, 0.3):
        res = fs.slide(acc, dt, mu, vertical=vert)
        peak, resid = rigid_block_vertical(acc, vert, dt, mu)
        assert res.liftoff_count > 5
        assert res.peak_slide[0] == pytest.approx(peak, rel=1e-7)
        assert res.residual_slide[0] == pytest.approx(resid, rel=1e-7, abs=1e-11)
