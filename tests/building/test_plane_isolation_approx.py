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
    smoothed_plane_isolator_response,
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


def test_the_smoothed_model_is_isotropic(elcentro):
    """The Park–Wen interaction has no preferred axis: shaking along 37° gives the response
    along 0° turned by 37° (pendulum and lead-rubber; ≤ 1e-6 of the peak, the integrator's
    tolerance; measured ≤ 1.7e-9)."""
    ag, dt = elcentro
    a = 2.0 * ag[:601]
    th = np.radians(37.0)
    for b in (building(stories=2), _lrb()):
        r0 = smoothed_plane_isolator_response(b, a, np.zeros_like(a), dt, rtol=1e-10)
        r = smoothed_plane_isolator_response(b, a * np.cos(th), a * np.sin(th), dt, rtol=1e-10)
        top = np.abs(r0.displacement).max()
        assert top > 0.01 and np.abs(r0.displacement[:, 1]).max() == 0.0
        for d, c in enumerate((np.cos(th), np.sin(th))):
            assert np.abs(r.displacement[:, d] - c * r0.displacement[:, 0]).max() < 1e-6 * top


def test_the_smoothed_model_tends_to_the_exact_coupled_bearing():
    """Sylmar's strongest 3 s (both components) on a 3-storey pendulum building: the smoothed
    bearing's orbit approaches the exact coupled one as its elastic displacement Y shrinks
    (measured: 1.0e-2 of the peak at 1 mm, 3.3e-3 at 0.1 mm, 1.6e-3 at 0.025 mm)."""
    p = read_pair(PAIRS / "RSN1084_NORTHR_SCS052.AT2", PAIRS / "RSN1084_NORTHR_SCS142.AT2")
    h1, h2 = p.h1[1000:1600], p.h2[1000:1600]
    b = building(stories=3, mu=0.06)
    ex = plane_isolator_response(b, h1, h2, p.dt)
    top = np.abs(ex.displacement).max()
    assert top > 0.1
    err = [
        np.abs(
            smoothed_plane_isolator_response(b, h1, h2, p.dt, yield_disp=y).displacement
            - ex.displacement
        ).max()
        / top
        for y in (1e-3, 1e-4, 2.5e-5)
    ]
    assert err[2] < err[1] < err[0] and err[2] < 5e-3


def test_bad_settings_are_refused_in_one_line(elcentro):
    ag, dt = elcentro
    a = ag[:100]
    with pytest.raises(ModelError, match="substeps"):
        newmark_plane_isolator_response(building(), a, a, dt, substeps=0)
    with pytest.raises(ModelError, match="friction_yield"):
        newmark_plane_isolator_response(building(), a, a, dt, friction_yield=-1.0)
    with pytest.raises(ModelError, match="acc"):
        uncoupled_plane_isolator_response(building(), a, a[:50], dt)
    with pytest.raises(ModelError, match="yield_disp"):
        smoothed_plane_isolator_response(building(), a, a, dt, yield_disp=0.0)
    with pytest.raises(ModelError, match="its own D_y"):
        smoothed_plane_isolator_response(_lrb(), a, a, dt, yield_disp=1e-3)
