"""A heavy rigid block coupled with its floor on a building over nonlinear isolation
(``slide_coupled`` on a ``NonlinearIsolatedBuilding``, 1-D): its limits (a tiny mass is the
decoupled block, one that never slides is added floor mass, a frictionless one leaves the building
alone, a frictionless pendulum is the linear isolated building) and an independent event-located
ODE reference (``tests/reference_coupled_nonlinear.py``)."""

from __future__ import annotations

import copy

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.model import LinearBuilding
from floorslide.errors import ModelError
from tests.conftest import load_slammer
from tests.reference_coupled_nonlinear import coupled_isolated_response

FLOOR_MASS = 1.0e5
ISOLATORS = {
    "lead_rubber": fs.BilinearIsolator(q_ratio=0.05, period=2.5, yield_disp=0.02, damping=0.02),
    "pendulum": fs.FrictionPendulum(mu=0.05, period=3.0, mu_s=0.06),
}


@pytest.fixture(scope="module")
def sup():
    """A 3-storey fixed-base shear building, T = 0.5 s, 100 t per floor, 5 % damping."""
    return fs.ShearBuilding.from_period(3, 0.5, damping=0.05, mass=FLOOR_MASS)


def nonlinear(sup, kind, isolator=None):
    return fs.NonlinearIsolatedBuilding(sup, 1.0, isolator or ISOLATORS[kind])


def loaded(b, floor, m, *, weight_only=False):
    """The building with ``m`` kg added to `floor` (``weight_only``: only the pendulum's load),
    its layer's constants as the coupled solver's: a pendulum's from the total mass with the
    block, a lead-rubber layer's unchanged. Same stiffness and damping matrices."""
    out = copy.copy(b)
    total = b.total_mass + m
    if not weight_only:
        out.mass = b.mass.copy()
        out.mass[floor] += m
    if b.kind == "friction_pendulum":
        out.constants = b.isolator.constants(total)
    return out


def _rel(a, b, scale):
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) / scale


@pytest.mark.parametrize("kind", ["lead_rubber", "pendulum"])
def test_tiny_mass_equals_the_decoupled_slide(kind, sup, elcentro):
    """m → 0: the decoupled rigid block on the nonlinear building's floor (fs.slide reading its
    motion). The coupling is O(m/M_floor): measured ≤ 1e-9 at 1e-9."""
    a, dt = elcentro
    b = nonlinear(sup, kind)
    floor = 3
    mu = np.array([0.04, 0.06, 0.1])
    ref = fs.slide(a, dt, mu, building=b, floor=floor)
    r = fs.slide_coupled(a, dt, mu, mass=1e-9 * FLOOR_MASS, building=b, floor=floor)
    assert np.all(ref.peak_slide > 1e-2)
    assert np.max(np.abs(r.peak_slide - ref.peak_slide) / ref.peak_slide) <= 1e-8
    assert np.max(np.abs(r.residual_slide - ref.residual_slide) / ref.peak_slide) <= 1e-8
    assert np.array_equal(r.slip_phases, ref.slip_phases)
    assert np.allclose(r.slide_fraction, ref.slide_fraction, rtol=1e-7, atol=0)
    # the floor's and the isolator's motion: the building's own, to O(m/M) — 1e-12 here
    r = fs.slide_coupled(
        a, dt, mu[1], mass=1e-12 * FLOOR_MASS, building=b, floor=floor, histories=True
    )
    own = fs.isolator_response(b, a, dt, floors=[floor])
    pfa = own.pfa[0]
    assert _rel(r.floor_acceleration[0], own.floor_acceleration[0], pfa) <= 1e-10
    assert abs(r.pfa[0] - pfa) / pfa <= 1e-10
    peak = own.peak_displacement
    assert abs(r.peak_isolator_displacement[0] - peak) / peak <= 1e-10
    assert _rel(r.isolator_displacement[0], own.isolator_displacement, peak) <= 1e-10
    assert abs(r.residual_isolator_displacement[0] - own.residual_displacement) <= 1e-10 * peak


@pytest.mark.parametrize(("kind", "floor"), [("lead_rubber", 3), ("pendulum", 3), ("pendulum", 0)])
def test_never_slides_equals_the_building_with_the_mass_added(kind, floor, sup, elcentro):
    """mu → ∞: the block sticks throughout; building and layer move as the
    NonlinearIsolatedBuilding with ``m`` added to the floor (a pendulum's constants from the
    heavier weight, the rubber's unchanged), the isolator's displacement too. On the mat
    (floor 0) the pendulum's breakaway friction carries the block's mass."""
    a, dt = elcentro
    b = nonlinear(sup, kind)
    m = 0.3 * FLOOR_MASS
    r = fs.slide_coupled(a, dt, 100.0, mass=m, building=b, floor=floor, histories=True)
    assert r.peak_slide[0] == 0.0 and r.slip_phases[0] == 0 and r.slide_fraction[0] == 0.0
    heavier = loaded(b, floor, m)
    own = fs.isolator_response(heavier, a, dt, floors=[floor])
    pfa = own.pfa[0]
    assert _rel(r.floor_acceleration[0], own.floor_acceleration[0], pfa) <= 1e-10
    assert abs(r.pfa[0] - pfa) / pfa <= 1e-10
    peak = own.peak_displacement
    assert abs(r.peak_isolator_displacement[0] - peak) / peak <= 1e-10
    assert _rel(r.isolator_displacement[0], own.isolator_displacement, peak) <= 1e-10
    # the mass matters: the building alone differs by far more than the tolerance
    alone = fs.isolator_response(b, a, dt, floors=[floor])
    assert abs(alone.peak_displacement - peak) / peak > 1e-3


@pytest.mark.parametrize("kind", ["lead_rubber", "pendulum"])
def test_frictionless_block_leaves_the_building_alone(kind, sup, elcentro):
    """mu = 0: no horizontal force reaches the floor, so the building moves as if the block were
    absent — on lead rubber exactly the building alone; a pendulum still carries its weight
    (``W = (M + m)·g``: stiffer and more friction), so the building alone with that load. The
    block's slide is then minus the floor's absolute displacement: its peak is at least the
    floor's relative one."""
    a, dt = elcentro
    b = nonlinear(sup, kind)
    floor, m = 2, 0.3 * FLOOR_MASS
    r = fs.slide_coupled(a, dt, 0.0, mass=m, building=b, floor=floor, histories=True)
    ref_b = b if kind == "lead_rubber" else loaded(b, floor, m, weight_only=True)
    own = fs.isolator_response(ref_b, a, dt, floors=[floor])
    pfa = own.pfa[0]
    assert _rel(r.floor_acceleration[0], own.floor_acceleration[0], pfa) <= 1e-10
    assert abs(r.pfa[0] - pfa) / pfa <= 1e-10
    peak = own.peak_displacement
    assert abs(r.peak_isolator_displacement[0] - peak) / peak <= 1e-10
    assert _rel(r.isolator_displacement[0], own.isolator_displacement, peak) <= 1e-10
    if kind == "pendulum":  # the block's weight on the pendulum matters
        alone = fs.isolator_response(b, a, dt, floors=[floor])
        assert abs(alone.peak_displacement - peak) / peak > 1e-3


@pytest.mark.parametrize("floor", [3, 0])
def test_frictionless_pendulum_equals_the_linear_coupled_building(floor, sup, elcentro):
    """FrictionPendulum(mu = 0, period = T) is the linear undamped isolated building of
    stiffness ``W/R`` with ``W = (M + m)·g`` (the block's weight on it): the coupled block on it
    is the linear coupled solver's (events at every zero of the mat's velocity there, none on the
    linear one)."""
    a, dt = elcentro
    T, m = 3.0, 0.1 * FLOOR_MASS
    b = nonlinear(sup, "pendulum", fs.FrictionPendulum(mu=0.0, period=T))
    lin = fs.IsolatedBuilding(sup, 1.0, T, 0.0)
    K = lin.stiffness_matrix.copy()
    K[0, 0] += m * (2 * np.pi / T) ** 2  # the block's weight over R
    lin = LinearBuilding(lin.mass, lin.damping_matrix, K, lin.dof_floors, lin.storey_below)
    mu = np.array([0.05, 0.1])
    r = fs.slide_coupled(a, dt, mu, mu_s=0.12, mass=m, building=b, floor=floor, histories=True)
    ref = fs.slide_coupled(a, dt, mu, mu_s=0.12, mass=m, building=lin, floor=floor, histories=True)
    assert np.all(ref.peak_slide > 1e-2) and np.all(ref.slip_phases >= 5)
    P = ref.peak_slide
    assert np.max(np.abs(r.peak_slide - P) / P) <= 1e-10
    assert np.max(np.abs(r.residual_slide - ref.residual_slide) / P) <= 1e-10
    assert np.max(np.abs(r.u - ref.u).max(axis=1) / P) <= 1e-10
    assert np.max(np.abs(r.pfa - ref.pfa) / ref.pfa) <= 1e-10
    assert _rel(r.floor_acceleration, ref.floor_acceleration, ref.pfa.max()) <= 1e-10
    assert np.array_equal(r.slip_phases, ref.slip_phases)
    assert np.array_equal(r.mode, ref.mode)


RECORDS = ["ImperialValley_1940_ELC-180.txt", "CapeMendocino_1992_PET-090.txt"]


def _reference_case(b, floor, m, mu_k, mu_s, a, dt):
    """The independent reference on `b`, its layer given by its physical constants."""
    c = b.constants
    if b.kind == "bilinear":
        spec = dict(kind="bilinear", k1=c["k1"], k2=c["k2"], Q=c["Q"], c=c["c"])
    else:
        # the reference forms W = (M + m)·g itself; the viscous term is the solver's
        cw = b.isolator.constants(b.total_mass + m)
        spec = dict(kind="friction_pendulum", R=c["R"], mu=c["mu"], mu_s=c["mu_s"], c=cw["c"])
    return coupled_isolated_response(
        b.mass, b.stiffness_matrix, b.damping_matrix, spec, floor, m, mu_k, mu_s, a, dt
    )


@pytest.mark.parametrize("ratio", [0.01, 0.3])
@pytest.mark.parametrize("kind", ["lead_rubber", "pendulum"])
@pytest.mark.parametrize("record", RECORDS)
def test_against_an_independent_reference(record, kind, ratio, sup):
    """SciPy DOP853 of building, layer and block together with all their events (rtol 1e-12),
    400 samples around the record's peak, the block on the roof (mu_s > mu_k): slides, the
    floor's true peak acceleration and its samples, the isolator's peak and samples ≤ 1e-8 of
    their peaks (measured ≤ 4e-11); slip counts, isolator events and the mode at every sample
    identical."""
    a, dt = load_slammer(record)
    k0 = max(0, int(np.argmax(np.abs(a))) - 200)
    a = a[k0 : k0 + 400]
    b = nonlinear(sup, kind)
    floor, m, mu_k, mu_s = 3, ratio * FLOOR_MASS, 0.1, 0.12
    ref = _reference_case(b, floor, m, mu_k, mu_s, a, dt)
    r = fs.slide_coupled(a, dt, mu_k, mu_s=mu_s, mass=m, building=b, floor=floor, histories=True)
    _agree(r, ref)


@pytest.mark.parametrize("kind", ["lead_rubber", "pendulum"])
def test_block_on_the_base_mat(kind, sup):
    """The block on the mat (floor 0): a pendulum's breakaway makes the mat's acceleration
    jump (the block may break away at once), and the friction the stuck pendulum needs carries
    the block's mass or its friction reaction."""
    a, dt = load_slammer("CapeMendocino_1992_PET-090.txt")
    k0 = max(0, int(np.argmax(np.abs(a))) - 200)
    a = a[k0 : k0 + 400]
    b = nonlinear(sup, kind)
    m, mu_k, mu_s = 0.3 * b.mass[0], 0.1, 0.12
    ref = _reference_case(b, 0, m, mu_k, mu_s, a, dt)
    r = fs.slide_coupled(a, dt, mu_k, mu_s=mu_s, mass=m, building=b, floor=0, histories=True)
    _agree(r, ref)


def _agree(r, ref):
    assert ref["slips"] >= 2 and ref["iso_events"] >= 4 and ref["peak_slide"] > 1e-3
    P = ref["peak_slide"]
    assert abs(r.peak_slide[0] - P) / P <= 1e-8
    assert abs(r.residual_slide[0] - ref["residual_slide"]) / P <= 1e-8
    assert _rel(r.u[0], ref["s"], P) <= 1e-8
    assert abs(r.pfa[0] - ref["pfa"]) / ref["pfa"] <= 1e-8
    assert _rel(r.floor_acceleration[0], ref["a_f"], ref["pfa"]) <= 1e-8
    D = ref["peak_isolator"]
    assert abs(r.peak_isolator_displacement[0] - D) / D <= 1e-8
    assert _rel(r.isolator_displacement[0], ref["u0"], D) <= 1e-8
    assert r.slip_phases[0] == ref["slips"]
    assert np.array_equal(r.mode[0], ref["mode"])
    assert abs(r.slide_fraction[0] * r.duration - ref["slide_time"]) <= 1e-8 * r.duration


def test_results_carry_the_isolator(sup, elcentro):
    """Cases broadcast; the records hold the isolator's peak and residual displacement; a
    linear building's result has none."""
    a, dt = elcentro
    b = nonlinear(sup, "pendulum")
    r = fs.slide_coupled(a, dt, 0.1, mass=np.array([1e3, 3e4]), building=b, floor=3)
    rows = r.to_records()
    assert len(rows) == 2 and rows[1]["peak_isolator_displacement"] > 0.01
    assert r.u is None and r.isolator_displacement is None
    lin = fs.slide_coupled(a[:200], dt, 0.1, mass=1e3, building=sup, floor=3)
    assert lin.peak_isolator_displacement is None
    assert "peak_isolator_displacement" not in lin.to_records()[0]


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        (dict(mass=0.0), "mass"),
        (dict(mass=2 * FLOOR_MASS), "mass"),
        (dict(floor=0, mass=4 * FLOOR_MASS), "mass"),  # the mat: 300 t
        (dict(mass=None), "mass"),
        (dict(mu_s=0.1), "mu_s"),
        (dict(floor=None), "floor"),
        (dict(floor=4), "floors"),
        (dict(floor=-1), "floors"),
        (dict(mu_k=None), "mu_k"),
    ],
)
def test_bad_input_is_refused_in_one_line(kwargs, key, sup, elcentro):
    a, dt = elcentro
    b = nonlinear(sup, "lead_rubber")
    args = dict(mu_k=0.2, mass=1000.0, building=b, floor=3)
    args.update(kwargs)
    mu_k = args.pop("mu_k")
    with pytest.raises(ModelError) as info:
        fs.slide_coupled(a[:100], dt, mu_k, **args)
    assert info.value.where == key
    assert "\n" not in str(info.value)


def test_motions_and_the_plane_are_refused(sup, elcentro):
    """The ground record only (not the building's motion, which the block changes), 1-D only."""
    a, dt = elcentro
    b = nonlinear(sup, "pendulum")
    for acc in (b.motion(a[:100], dt), np.vstack([a[:100], a[:100]])):
        with pytest.raises(ModelError) as info:
            fs.slide_coupled(acc, dt, 0.2, mass=1000.0, building=b, floor=3)
        assert info.value.where == "acc" and "\n" not in str(info.value)
    with pytest.raises(ModelError) as info:
        fs.slide_coupled(a[:100], dt, 0.2, mass=1000.0, building=b.motion(a[:100], dt), floor=3)
    assert info.value.where == "building"


def test_the_approximate_coupled_solvers_refuse_nonlinear_isolation(sup, elcentro):
    """The benchmark's approximate coupled solvers (linear only) still refuse it in one line."""
    from floorslide.contents.coupled_approx import slide_coupled_newmark

    a, dt = elcentro
    b = nonlinear(sup, "pendulum")
    with pytest.raises(ModelError, match="approximate solvers") as info:
        slide_coupled_newmark(a[:100], dt, 0.2, mass=1000.0, building=b, floor=3)
    assert info.value.where == "building" and "\n" not in str(info.value)


@pytest.mark.parametrize(("kind", "floor"), [("lead_rubber", 3), ("pendulum", 0)])
def test_stiff_superstructure_coarse_dt(kind, floor, coarse_record):
    """A stiff superstructure (T = 0.1 s) under a dt = 0.02 s record: many exact sub-steps per
    step, events inside them; still the reference's answer (measured ≤ 3.4e-10)."""
    a, dt = coarse_record
    k0 = max(0, int(np.argmax(np.abs(a))) - 200)
    a = a[k0 : k0 + 300]
    stiff = fs.ShearBuilding.from_period(3, 0.1, damping=0.05, mass=FLOOR_MASS)
    b = nonlinear(stiff, kind)
    m, mu_k, mu_s = 0.1 * b.mass[floor], 0.1, 0.12
    ref = _reference_case(b, floor, m, mu_k, mu_s, a, dt)
    r = fs.slide_coupled(a, dt, mu_k, mu_s=mu_s, mass=m, building=b, floor=floor, histories=True)
    assert r.substeps > 5
    _agree(r, ref)
