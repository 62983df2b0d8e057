"""The approximate solvers of a building on nonlinear isolation under two components
(floorslide/building/plane_isolation_approx.py): Newmark with Newton on a circular yield surface
against the 1-D Newmark along an azimuth and against the exact coupled solver as its friction
element stiffens; the uncoupled model against the coupled one under one component."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.nonlinear_approx import newmark_isolator_response
from floorslide.building.plane_isolation import plane_isolator_response
from floorslide.building.plane_isolation_approx import (
    newmark_plane_isolator_response,
    uncoupled_plane_isolator_response,
)
from floorslide.errors import ModelError
from floorslide.records.pairs import read_pair
from tests.building.test_plane_isolation import PAIRS, building


def _lrb(stories=2):
    sup = fs.ShearBuilding.from_period(stories=stories, period=0.3, damping=0.03)
    return fs.NonlinearIsolatedBuilding(
        sup, 1.0, fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02)
    )


@pytest.mark.parametrize("kind", ["pendulum", "lead-rubber"])
def test_newmark_along_an_azimuth_is_the_1d_newmark(elcentro, kind):
    """On a line the circular yield surface is the 1-D return map: the 2-D Newmark equals the
    1-D one along 37°, ≤ 1e-9 (measured: 1.2e-12 displacement, 1.9e-11 accelerations)."""
    ag, dt = elcentro
    a = 2.0 * ag[:1201]
    b = building(stories=2) if kind == "pendulum" else _lrb()
    th = np.radians(37.0)
    r2 = newmark_plane_isolator_response(b, a * np.cos(th), a * np.sin(th), dt, substeps=4)
    r1 = newmark_isolator_response(b, a, dt, substeps=4)
    u1 = r1.isolator_displacement
    assert np.abs(u1).max() > 0.01
    for d, c in enumerate((np.cos(th), np.sin(th))):
        assert np.abs(r2.displacement[:, d] - c * u1).max() < 1e-9 * np.abs(u1).max()
        ref = c * np.asarray(r1.floor_acceleration).T
        top = np.abs(r1.floor_acceleration).max()
        assert np.abs(r2.floor_acceleration[:, :, d] - ref).max() < 1e-9 * top


def test_newmark_tends_to_the_exact_coupled_bearing():
    """Sylmar (RSN 1084, both components, 8,773 samples) on a 3-storey pendulum building: the
    2-D Newmark at dt/16 approaches the exact coupled peak bearing displacement as its friction
    element stiffens (measured: 2.6e-3 at 0.25 mm, 2.5e-4 at 0.01 mm), while the uncoupled
    model stays 10 % low — an independent check of the coupled solver on a whole record."""
    p = read_pair(PAIRS / "RSN1084_NORTHR_SCS052.AT2", PAIRS / "RSN1084_NORTHR_SCS142.AT2")
    b = building(stories=3)
    exact = plane_isolator_response(b, p.h1, p.h2, p.dt).peak_displacement
    err = [
        abs(
            newmark_plane_isolator_response(
                b, p.h1, p.h2, p.dt, substeps=16, friction_yield=fy
            ).peak_displacement
            / exact
            - 1.0
        )
        for fy in (2.5e-4, 1e-5)
    ]
    assert err[1] < 1e-3 < err[0] < 1e-2
    un = uncoupled_plane_isolator_response(b, p.h1, p.h2, p.dt).peak_displacement
    assert 0.85 < un / exact < 0.95


def test_uncoupled_under_one_component_is_the_coupled_building(elcentro):
    """Under one component the two models are one: the uncoupled response equals the exact
    coupled one, ≤ 1e-10."""
    ag, dt = elcentro
    a = 2.0 * ag[:801]
    b = building(stories=2, mu_s=0.07)
    z = np.zeros_like(a)
    un = uncoupled_plane_isolator_response(b, a, z, dt)
    co = plane_isolator_response(b, a, z, dt)
    top = np.abs(co.displacement).max()
    assert top > 0.01
    assert np.abs(un.displacement - co.displacement).max() < 1e-10 * top
    acc = np.abs(co.floor_acceleration).max()
    assert np.abs(un.floor_acceleration - co.floor_acceleration).max() < 1e-10 * acc


def test_bad_settings_are_refused_in_one_line(elcentro):
    ag, dt = elcentro
    a = ag[:100]
    with pytest.raises(ModelError, match="substeps"):
        newmark_plane_isolator_response(building(), a, a, dt, substeps=0)
    with pytest.raises(ModelError, match="friction_yield"):
        newmark_plane_isolator_response(building(), a, a, dt, friction_yield=-1.0)
    with pytest.raises(ModelError, match="acc"):
        uncoupled_plane_isolator_response(building(), a, a[:50], dt)
