"""One-line building specs of the command line (``--building``, issue 12 item 8)."""

from __future__ import annotations

import numpy as np
import pytest

from floorslide.building import (
    BilinearIsolator,
    FrictionPendulum,
    IsolatedBuilding,
    NonlinearIsolatedBuilding,
    Rayleigh,
    ShearBuilding,
)
from floorslide.building.spec import describe_building, parse_building
from floorslide.errors import ModelError


def same(a, b) -> None:
    assert type(a) is type(b)
    np.testing.assert_array_equal(a.mass, b.mass)
    np.testing.assert_array_equal(a.stiffness_matrix, b.stiffness_matrix)
    np.testing.assert_array_equal(a.damping_matrix, b.damping_matrix)


@pytest.mark.parametrize(
    ("spec", "model"),
    [
        ("fixed:period=0.4", lambda: ShearBuilding.from_period(1, 0.4, 0.05)),
        (
            "FIXED: period = 0.4 , stories=3, damping=0.02, mass=2e5, profile=shear",
            lambda: ShearBuilding.from_period(3, 0.4, 0.02, mass=2e5, profile="shear"),
        ),
        (
            "fixed:masses=2e5/2e5/1.5e5,stiffnesses=3e8/3e8/2e8",
            lambda: ShearBuilding([2e5, 2e5, 1.5e5], [3e8, 3e8, 2e8], 0.05),
        ),
        (
            "fixed:masses=1/1,stiffnesses=100/100,damping=0.02/0.04",
            lambda: ShearBuilding([1, 1], [100, 100], [0.02, 0.04]),
        ),
        (
            "isolated:period=2.5,damping=0.1,super_period=0.4,stories=3",
            lambda: IsolatedBuilding(ShearBuilding.from_period(3, 0.4, 0.05), 1.0, 2.5, 0.1),
        ),
        (
            "isolated:period=3,base_mass_ratio=0.5,masses=1/1,stiffnesses=100/50,super_damping=0.02",
            lambda: IsolatedBuilding(ShearBuilding([1, 1], [100, 50], 0.02), 0.5, 3.0, 0.1),
        ),
    ],
)
def test_specs_build_the_models_they_name(spec, model):
    same(parse_building(spec), model())


def test_defaults_are_the_scene_defaults():
    """docs/design.md §4 / scene schema: stories 1, damping 0.05 (fixed) and 0.10 (isolation),
    base_mass_ratio 1, uniform profile, mass 1."""
    iso = parse_building("isolated:period=2,super_period=0.2")
    assert iso.isolation_damping == 0.1 and iso.base_mass_ratio == 1.0 and iso.stories == 1
    assert iso.superstructure.damping == 0.05
    # Kelly: T_s = 0.2 s, T_b = 2.5 s, m_b = m gives T1 = 2.504010 s (docs/design.md §7)
    kelly = parse_building("isolated:period=2.5,super_period=0.2,damping=0")
    assert kelly.periods[0] == pytest.approx(2.504010, abs=5e-7)


@pytest.mark.parametrize(
    ("spec", "where", "text"),
    [
        ("fixed:perod=0.4,foo=1", "perod", "unknown keys 'perod', 'foo'"),
        ("fixed:period=0.4,base_mass_ratio=2", "base_mass_ratio", "known keys: period"),
        ("fixed:period=x", "period", "'x' is not a number"),
        ("fixed:stories=2", "period", "period is missing"),
        ("fixed", "period", "period is missing"),
        ("fixed:period=0.4,stories=2.5", "stories", "whole number"),
        ("fixed:period=0.4,stories=0", "stories", "≥ 1"),
        ("fixed:period=0.4,period=1", "period", "twice"),
        ("fixed:period", "period", "key=value"),
        ("fixed:period=0.4,masses=1", "period", "not both"),
        ("fixed:masses=1/2,stiffnesses=1", "stiffnesses", "one value per storey"),
        ("fixed:masses=1/x,stiffnesses=1/1", "masses", "separated by '/'"),
        ("isolated:super_period=0.4", "period", "isolation period"),
        ("isolated:period=2,super_period=0.4,super_damping=2", "super_damping", "[0, 1)"),
        ("isolated:period=2,super_period=0", "super_period", "> 0"),
        ("isolated:period=2,super_period=0.4,damping=-1", "damping", "[0, 1)"),
        ("hotel:period=1", "kind", "unknown kind 'hotel'"),
        ("isolated:period=3,mu=0.05,super_period=0.4", "mu", "isolator=friction_pendulum"),
        ("fps:period=3,super_period=0.4", "mu", "mu is missing"),
        ("fps:mu=0.05,super_period=0.4", "period", "period (s) or radius (m)"),
        ("fps:period=3,radius=2,mu=0.05,super_period=0.4", "radius", "one of radius and period"),
        ("fps:period=3,mu=-0.1,super_period=0.4", "mu", "≥ 0"),
        ("fps:period=3,mu=0.05,q_ratio=0.1,super_period=0.4", "q_ratio", "an fps building"),
        ("lrb:period=2.5,super_period=0.4", "q_ratio", "q_ratio is missing"),
        ("lrb:q_ratio=0.06,period=2.5,super_period=0.4", "yield_disp", "yield_disp and alpha"),
        ("isolated:period=2,isolator=rubber,super_period=0.4", "isolator", "unknown isolator"),
        (
            "isolated:period=2,isolator=bilinear,mu=0.1,q_ratio=0.1,yield_disp=0.01,"
            "super_period=0.4",
            "mu",
            "not a key of a bilinear layer",
        ),
    ],
)
def test_mistakes_name_the_key(spec, where, text):
    with pytest.raises(ModelError) as exc:
        parse_building(spec)
    assert exc.value.where == where
    assert text in exc.value.message and "\n" not in str(exc.value)


def test_description():
    assert describe_building(parse_building("fixed:period=0.4,stories=3")) == (
        "fixed-base, 3 storeys, T1 = 0.4 s, ξ = 0.05"
    )
    text = describe_building(parse_building("isolated:period=2.5,super_period=0.2"))
    assert text.startswith("isolated, T_i = 2.5 s, ξ_i = 0.1, m_b/m = 1, T1 = 2.5")
    assert text.endswith("superstructure fixed-base, 1 storey, T1 = 0.2 s, ξ = 0.05")
    rayleigh = ShearBuilding([1, 1], [100, 100], Rayleigh(0.05))
    assert "Rayleigh ξ = 0.05" in describe_building(rayleigh)


def _nonlinear_same(a, b) -> None:
    assert type(a) is NonlinearIsolatedBuilding and type(b) is NonlinearIsolatedBuilding
    np.testing.assert_array_equal(a.mass, b.mass)
    np.testing.assert_array_equal(a.stiffness_matrix, b.stiffness_matrix)
    np.testing.assert_array_equal(a.damping_matrix, b.damping_matrix)
    assert a.isolator == b.isolator


@pytest.mark.parametrize(
    ("spec", "isolator"),
    [
        (
            "fps:period=3,mu=0.06,super_period=0.4,stories=3",
            FrictionPendulum(mu=0.06, period=3.0),
        ),
        (
            "isolated:isolator=friction_pendulum,radius=2.2,mu=0.05,mu_s=0.08,capacity=0.4,"
            "super_period=0.4,stories=3",
            FrictionPendulum(mu=0.05, radius=2.2, mu_s=0.08, capacity=0.4),
        ),
        (
            "lrb:q_ratio=0.06,period=2.5,yield_disp=0.02,super_period=0.4,stories=3",
            BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02),
        ),
        (
            "isolated:isolator=bilinear,q_ratio=0.05,period=2.5,alpha=0.1,damping=0.02,"
            "super_period=0.4,stories=3",
            BilinearIsolator(q_ratio=0.05, period=2.5, alpha=0.1, damping=0.02),
        ),
    ],
)
def test_nonlinear_isolation_in_one_line(spec, isolator):
    """``fps:``/``lrb:`` or ``isolator=`` put the superstructure on a nonlinear layer with the
    keys of a scene's ``isolator`` table."""
    got = parse_building(spec)
    ref = NonlinearIsolatedBuilding(ShearBuilding.from_period(3, 0.4, 0.05), 1.0, isolator)
    _nonlinear_same(got, ref)
    text = describe_building(got)
    assert text.startswith("isolated on ") and "superstructure fixed-base, 3 storeys" in text


def test_pendulum_period_is_two_pi_root_r_over_g_and_checks_a_period_given_too():
    """One rule for a pendulum given by its radius (the scene's isolator.radius): T = 2π√(R/g),
    R = 2 m → 2.8375 s; a period given too must agree within 0.1 %."""
    import re

    from floorslide.building.spec import pendulum_period

    assert pendulum_period(2.0) == pytest.approx(2 * np.pi * np.sqrt(2.0 / 9.80665), rel=1e-15)
    assert pendulum_period(2.0, 2.8375) == 2.8375
    text = "gives the pendulum period 2π√(R/g) = 2.837 s, but period = 3 s; give one of radius"
    with pytest.raises(ModelError, match=re.escape(text)) as err:
        pendulum_period(2.0, 3.0)
    assert err.value.where == "radius"
    by_r = parse_building("fps:mu=0.05,radius=2,super_period=0.4,stories=3")
    assert by_r.isolator.T == pytest.approx(pendulum_period(2.0), rel=1e-12)
