"""Sliding in the plane with vertical shaking (docs/design.md §10d): friction ``mu_k·(g + a_v)``,
breakaway at ``max(mu_s, mu_k)·(g + a_v)``, free flight where ``g + a_v ≤ 0`` — against the 1-D
solver with the same vertical along any azimuth (ground and floor, with and without lift-off), a
constant vertical as a scaled friction, and the energy balance."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.constants import G
from floorslide.contents.plane import slide_plane
from floorslide.errors import ModelError
from tests.conftest import ROOT, load_slammer

MUS = [0.03, 0.08, 0.15, 0.22]
MUS_S = [0.05, 0.1, 0.2, 0.25]  # mu_s > mu_k: starts from rest with m = 1
MUS_EQ = [0.05, 0.12, 0.2]  # mu_s = mu_k: breakaways with m = 2


@pytest.fixture(scope="module")
def rec():
    """El Centro 1940 horizontal, and Northridge RRS-228 (a horizontal record of the same dt)
    as a stand-in vertical, scaled to half El Centro's PGA."""
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    v, dtv = load_slammer("Northridge_1994_RRS-228.txt")
    assert dtv == dt
    n = min(acc.size, v.size)
    acc, v = acc[:n], v[:n]
    v = v * (0.5 * np.abs(acc).max() / np.abs(v).max())
    return acc, v, dt


def _along(acc, dt, av, angle, mu, mu_s, **kw):
    th = np.radians(angle)
    r = slide_plane((acc * np.cos(th), acc * np.sin(th)), dt, mu, mu_s, vertical=av,
                    histories=True, compare_1d=False, **kw)  # fmt: skip
    ref = fs.slide(acc, dt, mu, mu_s, vertical=av, histories=True, **kw)
    assert (ref.peak_slide > 0).all()
    scale = ref.peak_slide[:, None]
    along = r.u[:, :, 0] * np.cos(th) + r.u[:, :, 1] * np.sin(th)
    across = -r.u[:, :, 0] * np.sin(th) + r.u[:, :, 1] * np.cos(th)
    err_peak = np.max(np.abs(r.peak_slide - ref.peak_slide) / ref.peak_slide)
    err_u = np.max(np.abs(along - ref.u) / scale)
    err_x = np.max(np.abs(across) / scale)
    return r, ref, err_peak, err_u, err_x


@pytest.mark.parametrize(("angle", "mu_s"), [(0.0, MUS_S), (37.0, MUS_S), (200.0, MUS)])
def test_along_any_azimuth_is_the_1d_solver_with_vertical(rec, angle, mu_s):
    acc, av, dt = rec
    r, ref, ep, eu, ex = _along(acc, dt, av, angle, MUS, mu_s)
    assert ep <= 1e-10 and eu <= 1e-10 and ex <= 1e-12, (ep, eu, ex)
    assert ref.liftoff_time == 0.0 and r.liftoff_time == 0.0


def test_on_a_floor_with_vertical(rec):
    acc, av, dt = rec
    b = fs.ShearBuilding.from_period(2, 0.4)
    _, _, ep, eu, ex = _along(acc, dt, av, 60.0, MUS, MUS_S, building=b, floor=2)
    assert ep <= 1e-10 and eu <= 1e-10 and ex <= 1e-12, (ep, eu, ex)


@pytest.mark.parametrize("on_floor", [False, True])
def test_lift_off_is_free_flight_as_in_1d(rec, on_floor):
    """A vertical of 1.3 g peak lifts the block off (g + a_v ≤ 0) several times."""
    acc, av, dt = rec
    av = av * (1.3 * G / np.abs(av).max())
    kw = {"building": fs.ShearBuilding.from_period(2, 0.4), "floor": 2} if on_floor else {}
    r, ref, ep, eu, ex = _along(acc, dt, av, 115.0, MUS, MUS_S, **kw)
    assert ref.liftoff_count > 0
    assert r.liftoff_count == ref.liftoff_count
    assert abs(r.liftoff_time - ref.liftoff_time) <= 1e-12 * ref.liftoff_time
    assert ep <= 1e-10 and eu <= 1e-10 and ex <= 1e-12, (ep, eu, ex)


@pytest.mark.parametrize("c", [-3.0, 2.5])
def test_constant_vertical_scales_friction(rec, c):
    acc, _, dt = rec
    pair = (acc * 0.6, np.roll(acc, 300) * 0.8)
    mu = np.array(MUS)
    mu_s = np.array(MUS_S)
    r = slide_plane(pair, dt, mu, mu_s, vertical=np.full(acc.size, c), compare_1d=False)
    f = 1.0 + c / G
    ref = slide_plane(pair, dt, mu * f, mu_s * f, compare_1d=False)
    scale = ref.peak_slide.max()
    assert (ref.peak_slide[:2] > 0).all()
    assert np.max(np.abs(r.peak_slide - ref.peak_slide)) <= 1e-12 * scale
    assert np.max(np.abs(r.residual - ref.residual)) <= 1e-12 * scale


def test_energy_balance_with_vertical():
    (p,) = fs.read_pairs(ROOT / "data" / "records" / "pairs" / "index.csv", where={"rsn": "1084"})
    av = 0.5 * np.roll(p.h2, 500)  # a stand-in vertical (0.46 g peak)
    mu = [0.05, 0.1, 0.2, 0.3]
    for kw in ({}, {"building": fs.ShearBuilding.from_period(2, 0.4), "floor": 2}):
        r = slide_plane(p, mu_k=mu, mu_s=[0.06, 0.1, 0.25, 0.3], vertical=av, compare_1d=False,
                        **kw)  # fmt: skip
        kin = 0.5 * np.sum(r.final_velocity**2, axis=1)
        bal = kin + r.work_friction + r.work_floor
        assert (r.work_friction > 0).all()
        assert np.max(np.abs(bal) / r.work_friction) <= 2e-12, bal / r.work_friction


def test_vertical_validation(rec):
    acc, av, dt = rec
    with pytest.raises(ModelError, match="samples"):
        slide_plane((acc, acc), dt, 0.1, vertical=av[:-1])
    with pytest.raises(ModelError, match="vertical"):
        slide_plane((acc, acc), dt, 0.1, vertical=av, method="newmark")
