"""The friction pendulum is a small-angle model: its restoring force ``(W/R)·u`` is 2 % below
the spherical surface's ``W tan θ`` (``sin θ = u/R``) at ``u = 0.2 R``. A response beyond that,
without a displacement capacity to vouch for it, is flagged (docs/design.md §10b)."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.isolators import SMALL_ANGLE_LIMIT, small_angle_exceeded
from floorslide.building.nonlinear import NonlinearIsolatedBuilding, isolator_response


def rigid_mat(isolator):
    """A rigid block on the isolator (the superstructure negligible against the mat)."""
    sup = fs.ShearBuilding([1.0], [(2 * np.pi / 0.05) ** 2], damping=0.05)
    return NonlinearIsolatedBuilding(sup, 1e8, isolator)


def test_the_limit_is_where_the_small_angle_force_is_two_percent_low():
    x = SMALL_ANGLE_LIMIT
    assert 1 - np.sqrt(1 - x**2) == pytest.approx(0.0202, abs=5e-5)  # (W/R)u against W tan θ
    fp = fs.FrictionPendulum(mu=0.05, radius=2.0)
    assert fp.small_angle_limit == pytest.approx(0.4, rel=1e-15)
    assert not small_angle_exceeded(fp, 0.4) and small_angle_exceeded(fp, 0.4000001)


@pytest.mark.parametrize(
    ("u0", "capacity", "flagged", "exceeded"),
    [
        (0.3, None, True, False),  # 0.3 R, no capacity: beyond the small-angle model
        (0.15, None, False, False),  # 0.15 R: within it
        (0.3, 0.5, False, False),  # a capacity vouches for the bearing up to 0.5 R
        (0.3, 0.25, False, True),  # ... and is the limit that is checked
    ],
)
def test_a_pendulum_beyond_a_fifth_of_its_radius_is_flagged(u0, capacity, flagged, exceeded):
    """Free decay from ``u0`` (R = 1 m, mu = 0.02): the peak displacement is ``u0``."""
    b = rigid_mat(fs.FrictionPendulum(mu=0.02, radius=1.0, capacity=capacity))
    r = isolator_response(b, np.zeros(301), 0.01, initial_displacement=[u0, u0])
    assert r.peak_displacement == pytest.approx(u0, abs=1e-12)
    assert r.small_angle_exceeded is flagged
    assert r.capacity_exceeded is exceeded
    notes = [n for n in r.notes if "small-angle" in n]
    if flagged:
        assert len(notes) == 1
        assert "0.3 m = 0.3·R is beyond 0.2·R = 0.2 m" in notes[0]
        assert "4.6 % low" in notes[0]  # 1 − √(1 − 0.3²)
    else:
        assert notes == []


def test_a_lead_rubber_layer_has_no_such_limit():
    iso = fs.BilinearIsolator(q_ratio=0.05, period=2.5, yield_disp=0.01)
    b = rigid_mat(iso)
    r = isolator_response(b, np.zeros(301), 0.01, initial_displacement=[0.5, 0.5])
    assert r.peak_displacement > 0.4
    assert r.small_angle_exceeded is False
