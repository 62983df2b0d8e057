"""A heavy rigid block coupled with its floor (``slide_coupled``): its limits (a tiny mass is the
decoupled block, one that never slides is added floor mass, a frictionless one leaves the
building alone) and an independent event-located ODE reference (``tests/reference_coupled.py``)."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.model import LinearBuilding
from floorslide.contents.coupled import slide_coupled
from floorslide.errors import ModelError
from tests.conftest import load_slammer
from tests.reference_coupled import coupled_response

FLOOR_MASS = 1.0e5


@pytest.fixture(scope="module")
def fixed():
    """A 3-storey fixed-base shear building, T = 0.5 s, 100 t per floor, 5 % damping."""
    return fs.ShearBuilding.from_period(3, 0.5, damping=0.05, mass=FLOOR_MASS)


@pytest.fixture(scope="module")
def isolated(fixed):
    return fs.IsolatedBuilding(fixed, 1.0, period=2.5, damping=0.10)


def _rel(a, b, scale):
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) / scale


@pytest.mark.parametrize("where", ["fixed", "isolated"])
def test_tiny_mass_equals_the_decoupled_slide(where, fixed, isolated, elcentro):
    """m → 0: the decoupled rigid block on the building's floor. The coupling is O(m/M_floor)
    (measured: the difference scales with the mass ratio, 2e-9 at 1e-9)."""
    a, dt = elcentro
    b = fixed if where == "fixed" else isolated
    floor = 3
    mu = np.array([0.1, 0.2, 0.3]) if where == "fixed" else np.array([0.04, 0.06, 0.08])
    ref = fs.slide(a, dt, mu, building=b, floor=floor)
    r = slide_coupled(a, dt, mu, mass=1e-9 * FLOOR_MASS, building=b, floor=floor)
    assert np.all(ref.peak_slide > 1e-3)
    assert np.max(np.abs(r.peak_slide - ref.peak_slide) / ref.peak_slide) <= 1e-8
    assert np.max(np.abs(r.residual_slide - ref.residual_slide) / ref.peak_slide) <= 1e-8
    # slip phases: fs.slide counts one breakaway of El Centro at t = 6.31 s twice (mu = 0.3;
    # the independent reference and this solver once)
    assert np.max(np.abs(r.slip_phases - ref.slip_phases)) <= 1
    assert np.allclose(r.slide_fraction, ref.slide_fraction, rtol=1e-7, atol=0)
    # the floor's motion: the building's own, to O(m/M) — 1e-12 here
    r = slide_coupled(
        a, dt, mu[1], mass=1e-12 * FLOOR_MASS, building=b, floor=floor, histories=True
    )
    floor_acc = fs.floor_motions(b, a, dt, floors=[floor])[0]
    pfa = fs.peak_floor_acceleration(b, a, dt, floors=[floor]).peak[0]
    assert _rel(r.floor_acceleration[0], floor_acc, pfa) <= 1e-10
    assert abs(r.pfa[0] - pfa) / pfa <= 1e-10


def test_never_slides_equals_the_building_with_the_mass_added(fixed, elcentro):
    """mu → ∞: the block sticks throughout; the floor moves as the building with `m` added to
    it (same K and C), whose periods shift as the eigenvalues of ``M'⁻¹K`` say."""
    a, dt = elcentro
    floor, m = 3, 0.3 * FLOOR_MASS
    r = slide_coupled(a, dt, 100.0, mass=m, building=fixed, floor=floor, histories=True)
    assert r.peak_slide[0] == 0.0 and r.slip_phases[0] == 0 and r.slide_fraction[0] == 0.0
    masses = fixed.mass.copy()
    masses[floor - 1] += m
    heavier = LinearBuilding(
        masses,
        fixed.damping_matrix,
        fixed.stiffness_matrix,
        fixed.dof_floors,
        fixed.storey_below,
    )
    floor_acc = fs.floor_motions(heavier, a, dt, floors=[floor])[0]
    pfa = fs.peak_floor_acceleration(heavier, a, dt, floors=[floor]).peak[0]
    assert _rel(r.floor_acceleration[0], floor_acc, pfa) <= 1e-10
    assert abs(r.pfa[0] - pfa) / pfa <= 1e-10
    # the period shift: the undamped periods depend on M and K only
    w2 = np.sort(np.linalg.eigvals(np.diag(1 / masses) @ fixed.stiffness_matrix).real)
    T1 = 2 * np.pi / np.sqrt(w2[0])
    shifted = fs.ShearBuilding(masses, fixed.storey_stiffness, damping=0.05)
    assert abs(shifted.periods[0] - T1) / T1 <= 1e-12
    assert T1 > fixed.periods[0] * 1.03  # 30 % more roof mass: a longer period


@pytest.mark.parametrize("where", ["fixed", "isolated"])
def test_frictionless_block_leaves_the_building_alone(where, fixed, isolated, elcentro):
    """mu = 0: no force reaches the floor (the block is stuck only at isolated instants), so the
    building moves as if the block were absent, and the block stays where it was in absolute
    terms: its slide is minus the floor's absolute displacement (the floor's relative to the
    ground plus the ground's, the exact double integral of the piecewise-linear record)."""
    a, dt = elcentro
    b = fixed if where == "fixed" else isolated
    floor = 2
    r = slide_coupled(a, dt, 0.0, mass=0.3 * FLOOR_MASS, building=b, floor=floor, histories=True)
    out = fs.floor_motions(b, a, dt, floors=[floor], output=["acceleration", "displacement"])
    acc, disp = out["acceleration"][0], out["displacement"][0]
    pfa = fs.peak_floor_acceleration(b, a, dt, floors=[floor]).peak[0]
    assert _rel(r.floor_acceleration[0], acc, pfa) <= 1e-10
    assert abs(r.pfa[0] - pfa) / pfa <= 1e-10
    vg = np.concatenate([[0.0], np.cumsum(0.5 * dt * (a[:-1] + a[1:]))])
    xg = np.concatenate([[0.0], np.cumsum(dt * vg[:-1] + dt * dt * (a[:-1] / 3 + a[1:] / 6))])
    absolute = disp + xg
    peak = np.max(np.abs(absolute))
    assert _rel(r.u[0], -absolute, peak) <= 1e-10
    assert r.peak_slide[0] >= peak * (1 - 1e-12)  # the samples' peak; inside steps ≥


CASES = [
    ("ImperialValley_1940_ELC-180.txt", 0.2, 0.2),
    ("CapeMendocino_1992_PET-090.txt", 0.15, 0.2),
]


@pytest.mark.parametrize("ratio", [0.01, 0.3])
@pytest.mark.parametrize(("record", "mu_k", "mu_s"), CASES)
def test_against_an_independent_reference(record, mu_k, mu_s, ratio, fixed):
    """SciPy DOP853 of building and block together with stop/breakaway events (rtol 1e-12),
    600 samples around the record's peak: peak and residual slide, the floor's true peak
    acceleration and its samples ≤ 1e-8 of the peak (measured ≤ 2e-12)."""
    a, dt = load_slammer(record)
    k0 = max(0, int(np.argmax(np.abs(a))) - 200)
    a = a[k0 : k0 + 600]
    floor, m = 3, ratio * FLOOR_MASS
    ref = coupled_response(
        fixed.mass, fixed.stiffness_matrix, fixed.damping_matrix, floor - 1, m, mu_k, mu_s, a, dt
    )
    r = slide_coupled(a, dt, mu_k, mu_s=mu_s, mass=m, building=fixed, floor=floor, histories=True)
    assert ref["slips"] >= 3 and ref["peak_slide"] > 1e-3
    peak = ref["peak_slide"]
    assert abs(r.peak_slide[0] - peak) / peak <= 1e-8
    assert abs(r.residual_slide[0] - ref["residual_slide"]) / peak <= 1e-8
    assert _rel(r.u[0], ref["s"], peak) <= 1e-8
    assert abs(r.pfa[0] - ref["pfa"]) / ref["pfa"] <= 1e-8
    assert _rel(r.floor_acceleration[0], ref["a_f"], ref["pfa"]) <= 1e-8
    assert r.slip_phases[0] == ref["slips"]
    assert np.array_equal(r.mode[0], ref["mode"])
    assert abs(r.slide_fraction[0] * r.duration - ref["slide_time"]) <= 1e-8 * r.duration


def test_heavier_block_changes_the_floor(fixed, elcentro):
    """The decoupled assumption's error grows with the mass ratio; cases broadcast."""
    a, dt = elcentro
    r = slide_coupled(a, dt, 0.2, mass=np.array([1e-3, 0.3]) * FLOOR_MASS, building=fixed, floor=3)
    assert r.mass_ratio.tolist() == pytest.approx([1e-3, 0.3])
    d = fs.slide(a, dt, 0.2, building=fixed, floor=3)
    err = np.abs(r.peak_slide / d.peak_slide - 1)
    assert err[0] < 0.01 < err[1]
    assert len(r.to_records()) == 2


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        (dict(mass=0.0), "mass"),
        (dict(mass=-1.0), "mass"),
        (dict(mass=2 * FLOOR_MASS), "mass"),
        (dict(mass=None), "mass"),
        (dict(mu_s=0.1), "mu_s"),
        (dict(building=None), "building"),
        (dict(floor=None), "floor"),
        (dict(floor=0), "floor"),
        (dict(floor=7), "floors"),
        (dict(mu_k=None), "mu_k"),
    ],
)
def test_bad_input_is_refused_in_one_line(kwargs, key, fixed, elcentro):
    a, dt = elcentro
    args = dict(mu_k=0.2, mass=1000.0, building=fixed, floor=3)
    args.update(kwargs)
    mu_k = args.pop("mu_k")
    with pytest.raises(ModelError) as info:
        slide_coupled(a[:100], dt, mu_k, **args)
    assert info.value.where == key
    assert "\n" not in str(info.value)


def test_a_building_pair_is_not_modelled_yet(fixed, elcentro):
    """The plane (one model per direction) is refused; a building on nonlinear isolation is
    accepted (tests/contents/test_coupled_nonlinear.py)."""
    a, dt = elcentro
    with pytest.raises(ModelError, match="not modelled yet") as info:
        slide_coupled(
            a[:100], dt, 0.2, mass=1000.0, building=fs.BuildingPair(fixed, fixed), floor=3
        )
    assert info.value.where == "building"
    fm = fs.floor_motion(fixed, a[:100], 3, dt)
    with pytest.raises(ModelError, match="ground record"):
        slide_coupled(fm, dt, 0.2, mass=1000.0, building=fixed, floor=3)


def test_block_on_the_base_mat_of_an_isolated_building(isolated):
    """Floor 0 of an isolated building is the base mat, a degree of freedom like the others:
    against the reference (mu_s > mu_k: the floor's acceleration jumps at events)."""
    a, dt = load_slammer("Northridge_1994_RRS-228.txt")
    k0 = max(0, int(np.argmax(np.abs(a))) - 200)
    a = a[k0 : k0 + 600]
    b, m, mu_k, mu_s = isolated, 0.1 * isolated.mass[0], 0.08, 0.1
    ref = coupled_response(b.mass, b.stiffness_matrix, b.damping_matrix, 0, m, mu_k, mu_s, a, dt)
    r = slide_coupled(a, dt, mu_k, mu_s=mu_s, mass=m, building=b, floor=0, histories=True)
    assert ref["slips"] >= 3
    assert abs(r.peak_slide[0] - ref["peak_slide"]) / ref["peak_slide"] <= 1e-8
    assert abs(r.pfa[0] - ref["pfa"]) / ref["pfa"] <= 1e-8
    assert _rel(r.floor_acceleration[0], ref["a_f"], ref["pfa"]) <= 1e-8
    assert r.slip_phases[0] == ref["slips"]


def test_stiff_building_coarse_dt(coarse_record):
    """A stiff building (T = 0.1 s) under a dt = 0.02 s record: several exact sub-steps per
    step, events inside them; still the reference's answer."""
    a, dt = coarse_record
    k0 = max(0, int(np.argmax(np.abs(a))) - 100)
    a = a[k0 : k0 + 300]
    b = fs.ShearBuilding.from_period(3, 0.1, damping=0.05, mass=FLOOR_MASS)
    m, mu = 0.1 * FLOOR_MASS, 0.3
    ref = coupled_response(b.mass, b.stiffness_matrix, b.damping_matrix, 2, m, mu, mu, a, dt)
    r = slide_coupled(a, dt, mu, mass=m, building=b, floor=3, histories=True)
    assert r.substeps > 1 and ref["slips"] >= 3
    assert abs(r.peak_slide[0] - ref["peak_slide"]) / ref["peak_slide"] <= 1e-8
    assert abs(r.pfa[0] - ref["pfa"]) / ref["pfa"] <= 1e-8
    assert _rel(r.u[0], ref["s"], ref["peak_slide"]) <= 1e-8
    assert r.slip_phases[0] == ref["slips"]


def test_floor_history_feeds_a_floor_spectrum(fixed, elcentro):
    """The floor's absolute acceleration with the block at the samples is the input of a floor
    response spectrum (sample-based: re-interpolated between samples)."""
    a, dt = elcentro
    r = slide_coupled(a, dt, 0.2, mass=0.1 * FLOOR_MASS, building=fixed, floor=3, histories=True)
    sp = fs.response_spectrum(r.floor_acceleration[0], dt, [0.2, 0.5, 1.0], 0.05)
    assert np.all(np.isfinite(sp.psa)) and np.all(sp.psa > 0)
    assert r.floor_acceleration.shape == (1, a.size) and r.mode.shape == (1, a.size)
