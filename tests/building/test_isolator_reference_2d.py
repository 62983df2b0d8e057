"""The reference for a building on friction pendulums under two components
(tests/reference_isolators_2d.py) against closed forms and the 1-D reference: validated here
before the package's bidirectional layer is tested against it."""

from __future__ import annotations

import numpy as np
import pytest

from tests.reference_isolators import G, isolated_response
from tests.reference_isolators_2d import circular_orbit, isolated_response_2d

MB = M1 = 1e5


def shear_one_storey(period: float, xi: float = 0.02):
    """``Ks``, ``Cs`` of a 1-storey superstructure on its mat (stiffness-proportional damping)."""
    k = M1 * (2 * np.pi / period) ** 2
    Ks = np.array([[k, -k], [-k, k]])
    return Ks, 2 * xi / (2 * np.pi / period) * Ks


def test_free_decay_along_an_azimuth_closed_form():
    """The mat alone (R = 2 m, mu = 0.05) released at 0.5 m along 30°: it swings on that line
    as the 1-D pendulum does — extremes 0.5, −0.3, 0.1 m every half period π√(R/g), then stuck
    at mu·R, where the spring force is exactly the friction limit."""
    R, mu, th = 2.0, 0.05, np.radians(30.0)
    d = np.array([np.cos(th), np.sin(th)])
    r = isolated_response_2d(
        [MB], [[0.0]], [[0.0]], {"R": R, "mu": mu}, np.zeros(601), np.zeros(601), 0.01,
        mat_displacement=tuple(0.5 * d),
    )  # fmt: skip
    half = np.pi * np.sqrt(R / G)
    assert [e[1] for e in r["events"]] == ["slip", "reverse", "stick"]
    times = np.array([e[0] for e in r["events"]])
    assert np.abs(times - [0.0, half, 2 * half]).max() < 1e-8 * half
    np.testing.assert_allclose(r["residual"], 0.1 * d, atol=1e-9)
    # on the line all along: the cross-line displacement stays at rounding level
    cross = -r["ux"][:, 0] * d[1] + r["uy"][:, 0] * d[0]
    assert np.abs(cross).max() < 1e-12


@pytest.mark.parametrize("deg", [0.0, 37.0, 90.0, 200.0])
def test_along_any_azimuth_it_is_the_1d_building(elcentro, deg):
    """A pair along azimuth θ (``a cos θ``, ``a sin θ``): the mat and the floor move on that
    line exactly as the 1-D building under ``a`` (the 1-D reference, written apart)."""
    ag, dt = elcentro
    a = 2.0 * ag[:801]
    th = np.radians(deg)
    Ks, Cs = shear_one_storey(0.3)
    iso = {"R": G * (3.0 / (2 * np.pi)) ** 2, "mu": 0.05}
    one = isolated_response([MB, M1], Ks, Cs, {"kind": "friction_pendulum", **iso}, a, dt)
    two = isolated_response_2d([MB, M1], Ks, Cs, iso, a * np.cos(th), a * np.sin(th), dt)
    scale = np.abs(one["u"]).max()
    assert np.abs(one["u"][:, 0]).max() > 0.02  # it does slide
    assert np.abs(two["ux"] - np.cos(th) * one["u"]).max() < 1e-8 * scale
    assert np.abs(two["uy"] - np.sin(th) * one["u"]).max() < 1e-8 * scale
    kinds_1d = [e[1] for e in one["events"] if e[1] in ("slip", "stick")]
    assert [e[1] for e in two["events"] if e[1] in ("slip", "stick")] == kinds_1d


def test_circular_ground_motion_gives_the_circular_orbit():
    """A rigid mass on a friction pendulum (R = 1 m, mu = 0.05) under a = A (cos ωt, sin ωt),
    A = 3 m/s², ω = 2π, started on its steady orbit: it stays on the circle
    r = √(A² − (mu g)²)/|g/R − ω²| = 0.0997466 m, to the piecewise-linear record's O(dt²)
    (the record is the chords of the circle: 4× closer at half the step)."""
    A, w, mu, R = 3.0, 2 * np.pi, 0.05, 1.0
    r, phi = circular_orbit(A, w, mu, R)
    assert r == pytest.approx(0.0997466, abs=5e-8)
    errors = []
    for dt in (0.002, 0.001):
        t = np.arange(round(2.0 / dt) + 1) * dt
        u0 = r * np.array([np.cos(phi), np.sin(phi)])
        v0 = r * w * np.array([-np.sin(phi), np.cos(phi)])
        out = isolated_response_2d(
            [1e4], [[0.0]], [[0.0]], {"R": R, "mu": mu}, A * np.cos(w * t), A * np.sin(w * t),
            dt, mat_displacement=tuple(u0), mat_velocity=tuple(v0),
        )  # fmt: skip
        assert out["events"] == []  # it never stops
        radius = np.hypot(out["ux"][:, 0], out["uy"][:, 0])
        errors.append(np.abs(radius - r).max() / r)
    assert errors[1] < 2e-5
    assert 3.0 < errors[0] / errors[1] < 5.0


def test_without_friction_each_direction_is_its_own_linear_building(elcentro):
    """mu = 0 and a superstructure of its own per direction: the layer is linear, and each
    direction equals the 1-D reference of its own building."""
    ag, dt = elcentro
    ax, ay = ag[:601], 0.6 * ag[200:801]
    iso = {"R": 2.0, "mu": 0.0}
    (Kx, Cx), (Ky, Cy) = shear_one_storey(0.3), shear_one_storey(0.5)
    two = isolated_response_2d([MB, M1], (Kx, Ky), (Cx, Cy), iso, ax, ay, dt)
    for K, C, a, u in ((Kx, Cx, ax, two["ux"]), (Ky, Cy, ay, two["uy"])):
        one = isolated_response([MB, M1], K, C, {"kind": "friction_pendulum", **iso}, a, dt)
        assert np.abs(u - one["u"]).max() < 1e-8 * np.abs(one["u"]).max()
