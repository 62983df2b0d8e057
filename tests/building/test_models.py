"""Building models against closed forms and published values (docs/design.md §7)."""

from __future__ import annotations

import control
import numpy as np
import pytest

from floorslide.building.model import IsolatedBuilding, Rayleigh, ShearBuilding
from floorslide.errors import ModelError


def test_kelly_two_dof_periods_and_participation():
    """Kelly (1996) linear isolation theory, T_s = 0.2 s, T_b = 2.5 s, m_b = m
    (docs/design.md §7)."""
    fb = ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    iso = IsolatedBuilding(fb, base_mass_ratio=1.0, period=2.5, damping=0.10)
    mp = iso.modal_properties(normalize="first")
    assert mp.periods[0] == pytest.approx(2.504010, abs=5e-7)
    assert mp.periods[1] == pytest.approx(0.1411949, abs=5e-8)
    assert mp.participation[0] == pytest.approx(0.996790, abs=5e-7)


def test_kelly_closed_form_frequencies():
    """Kelly eq. 2.6: (1-γ)ω⁴ − (ω_b²+ω_s²)ω² + ω_b²ω_s² = 0, γ = m/(m+m_b), for several m_b/m."""
    for ratio in (0.25, 1.0, 3.0):
        fb = ShearBuilding.from_period(1, 0.3, 0.0)
        iso = IsolatedBuilding(fb, base_mass_ratio=ratio, period=2.0, damping=0.0)
        wb2, ws2 = (2 * np.pi / 2.0) ** 2, (2 * np.pi / 0.3) ** 2
        gamma = 1 / (1 + ratio)
        w2 = np.sort(np.roots([1 - gamma, -(wb2 + ws2), wb2 * ws2]).real)
        np.testing.assert_allclose(iso.modal_properties().circular_frequencies ** 2, w2, rtol=1e-12)


def test_from_period_gives_the_period_and_uniform_chain_eigenvalues():
    fb = ShearBuilding.from_period(stories=5, period=0.8, damping=0.05, mass=2.0e5)
    assert fb.periods[0] == pytest.approx(0.8, rel=1e-13)
    # uniform chain: ω_j = 2 sqrt(k/m) sin((2j-1)π/(2(2N+1)))  (Chopra 2012, Example 18.1-ish)
    k, m, N = fb.storey_stiffness[0], 2.0e5, 5
    j = np.arange(1, N + 1)
    w = 2 * np.sqrt(k / m) * np.sin((2 * j - 1) * np.pi / (2 * (2 * N + 1)))
    np.testing.assert_allclose(fb.modal_properties().circular_frequencies, w, rtol=1e-12)


def test_shear_profile_is_stiffer_at_the_base():
    fb = ShearBuilding.from_period(stories=4, period=0.5, damping=0.05, profile="shear")
    k = fb.storey_stiffness
    assert np.all(np.diff(k) < 0)
    assert fb.periods[0] == pytest.approx(0.5, rel=1e-13)
    # storey shear of an inverted triangle: k_j ∝ Σ_{i≥j} i
    np.testing.assert_allclose(k / k[0], np.array([10, 9, 7, 4]) / 10, rtol=1e-13)


def test_effective_masses_sum_to_total_mass():
    fb = ShearBuilding(masses=[3.0, 2.0, 1.0], stiffnesses=[900.0, 600.0, 300.0], damping=0.05)
    iso = IsolatedBuilding(fb, base_mass_ratio=0.7, period=3.0, damping=0.15)
    for b in (fb, iso):
        mp = b.modal_properties()
        assert mp.effective_mass.sum() == pytest.approx(b.total_mass, rel=1e-12)
        for norm in ("roof", "first"):
            np.testing.assert_allclose(
                b.modal_properties(norm).effective_mass, mp.effective_mass, rtol=1e-10
            )


def test_a_mode_that_leaves_the_roof_still_keeps_its_shape():
    """50 storeys, the shear profile: a high mode's roof component is exactly 0 (others
    ~1e-21); the default normalisation (positive roof) kept it as sign 0, erasing the shape
    (participation NaN, a RuntimeWarning). Every mode is finite, mass-normalised, and the
    effective masses sum to the total mass."""
    b = ShearBuilding.from_period(50, 5.0, 0.05, profile="shear")
    with np.errstate(all="raise"):
        mp = b.modal_properties()
    M = np.diag(b.mass)
    np.testing.assert_allclose(mp.shapes.T @ M @ mp.shapes, np.eye(50), atol=1e-10)
    assert np.all(np.isfinite(mp.participation)) and np.all(mp.shapes[-1] >= 0)
    assert mp.effective_mass.sum() == pytest.approx(b.total_mass, rel=1e-10)


@pytest.mark.parametrize("damping", [0.02, [0.02, 0.05, 0.1]])
def test_classical_damping_gives_modal_poles(damping):
    """Classically damped: poles −ξω ± iω√(1−ξ²), the ω of the undamped problem."""
    fb = ShearBuilding(masses=[3.0, 2.0, 1.0], stiffnesses=[900.0, 600.0, 300.0], damping=damping)
    w = fb.modal_properties().circular_frequencies
    xi = np.broadcast_to(np.asarray(damping, float), w.shape)
    expected = np.concatenate(
        [-xi * w + 1j * w * np.sqrt(1 - xi**2), -xi * w - 1j * w * np.sqrt(1 - xi**2)]
    )
    poles = control.poles(fb.state_space())
    np.testing.assert_allclose(np.sort_complex(poles), np.sort_complex(expected), rtol=1e-10)
    np.testing.assert_allclose(
        np.sort_complex(poles), np.sort_complex(np.linalg.eigvals(fb.state_space().A)), rtol=1e-12
    )


def test_rayleigh_damping_matches_ratio_at_anchor_modes():
    fb = ShearBuilding(
        masses=[1.0] * 4, stiffnesses=[400.0] * 4, damping=Rayleigh(0.05, modes=(1, 3))
    )
    w = fb.modal_properties().circular_frequencies
    phi = fb.modal_properties().shapes  # mass-normalised
    xi = np.diag(phi.T @ fb.damping_matrix @ phi) / (2 * w)
    assert xi[0] == pytest.approx(0.05, rel=1e-12)
    assert xi[2] == pytest.approx(0.05, rel=1e-12)
    assert xi[1] < 0.05 < xi[3]


def test_isolated_system_is_not_classically_damped_and_keeps_superstructure_damping():
    fb = ShearBuilding.from_period(2, 0.3, 0.05)
    iso = IsolatedBuilding(fb, 1.0, 2.5, 0.10)
    M = np.diag(iso.mass)
    K, C = iso.stiffness_matrix, iso.damping_matrix
    # Caughey–O'Kelly condition C M⁻¹ K = K M⁻¹ C fails for non-classical damping
    lhs = C @ np.linalg.solve(M, K)
    assert np.abs(lhs - lhs.T).max() > 1e-3 * np.abs(lhs).max()
    # a rigid translation of superstructure with the base mat costs no superstructure force
    v = np.ones(iso.n_dof)
    assert (C @ v)[0] == pytest.approx(iso.isolator_damping, rel=1e-12)
    np.testing.assert_allclose((C @ v)[1:], 0.0, atol=1e-12 * np.abs(C).max())
    mtot = iso.total_mass
    assert 2 * np.pi * np.sqrt(mtot / iso.isolator_stiffness) == pytest.approx(2.5, rel=1e-14)
    assert iso.isolator_damping * 2.5 / (4 * np.pi * mtot) == pytest.approx(0.10, rel=1e-14)


def test_state_space_outputs_only_what_was_asked():
    fb = ShearBuilding.from_period(3, 0.4, 0.05)
    iso = IsolatedBuilding(fb, 1.0, 2.5, 0.1)
    ss = iso.state_space(floors=[3, 1], outputs=["acceleration", "drift"])
    assert ss.noutputs == 4
    assert ss.output_labels == ["acceleration_3", "acceleration_1", "drift_3", "drift_1"]
    ss = iso.state_space(outputs="isolator")
    assert ss.noutputs == 1 and ss.output_labels == ["isolator_displacement"]
    ss = fb.state_space(floors=[0])
    assert ss.D[0, 0] == 1.0 and not ss.C.any()  # floor 0 of a fixed base is the ground


@pytest.mark.parametrize(
    "make",
    [
        lambda: ShearBuilding([1.0, 0.0], [1.0, 1.0]),
        lambda: ShearBuilding([1.0, -1.0], [1.0, 1.0]),
        lambda: ShearBuilding([1.0], [0.0]),
        lambda: ShearBuilding([1.0, 1.0], [1.0]),
        lambda: ShearBuilding([1.0], [1.0], damping=-0.01),
        lambda: ShearBuilding([1.0], [1.0], damping=1.0),
        lambda: ShearBuilding([1.0], [1.0], damping=float("nan")),
        lambda: ShearBuilding([1.0, 1.0], [1.0, 1.0], damping=[0.05]),
        lambda: ShearBuilding([1.0, 1.0], [1.0, 1.0], damping=Rayleigh(0.05, (1, 1))),
        lambda: ShearBuilding.from_period(0, 0.5),
        lambda: ShearBuilding.from_period(2, 0.0),
        lambda: ShearBuilding.from_period(2, -1.0),
        lambda: ShearBuilding.from_period(2, 0.5, profile="parabolic"),
        lambda: IsolatedBuilding(ShearBuilding.from_period(1, 0.2), base_mass_ratio=0.0),
        lambda: IsolatedBuilding(ShearBuilding.from_period(1, 0.2), period=0.0),
        lambda: IsolatedBuilding(ShearBuilding.from_period(1, 0.2), damping=1.2),
        lambda: ShearBuilding.from_period(2, 0.5).state_space(outputs="jerk"),
        lambda: ShearBuilding.from_period(2, 0.5).state_space(outputs="isolator"),
        lambda: ShearBuilding.from_period(2, 0.5).state_space(floors=[3]),
        lambda: ShearBuilding.from_period(2, 0.5).state_space(floors=[-1]),
        lambda: ShearBuilding.from_period(2, 0.5).state_space(floors=[1.5]),
        lambda: ShearBuilding.from_period(2, 0.5).state_space(floors=[0], outputs="drift"),
    ],
)
def test_bad_parameters_give_one_clear_error(make):
    with pytest.raises(ModelError) as err:
        make()
    assert "\n" not in str(err.value) and len(str(err.value)) < 200


def test_modal_frequencies_in_hz_and_rad_per_s():
    """Issue 12 item 8: engineers read Hz; both units are given under unmistakable names, and the
    old ``frequencies`` (rad/s) still works, with a DeprecationWarning naming both."""
    sdof = ShearBuilding(masses=[2.0], stiffnesses=[800.0], damping=0.0)  # ω = √(k/m) = 20 rad/s
    mp = sdof.modal_properties()
    assert mp.circular_frequencies[0] == pytest.approx(20.0, rel=1e-14)
    assert mp.frequencies_hz[0] == pytest.approx(20.0 / (2 * np.pi), rel=1e-14)
    fb = ShearBuilding.from_period(stories=3, period=0.4, damping=0.05)
    mp = fb.modal_properties()
    assert mp.frequencies_hz[0] == pytest.approx(2.5, rel=1e-13)  # 1 / 0.4 s
    np.testing.assert_allclose(mp.frequencies_hz, 1 / mp.periods, rtol=1e-14)
    np.testing.assert_allclose(mp.circular_frequencies, 2 * np.pi * mp.frequencies_hz, rtol=1e-14)
    with pytest.warns(DeprecationWarning, match="frequencies_hz"):
        old = mp.frequencies
    np.testing.assert_array_equal(old, mp.circular_frequencies)


def test_isolation_period_not_above_the_fixed_base_period_warns():
    """Accepted without a word (issue 19 item 8): physically possible, almost surely a
    mistake — a ModelWarning, not an error; the model is built as asked."""
    from floorslide.errors import ModelWarning

    fb = ShearBuilding.from_period(2, 0.5, 0.05)
    for period in (0.5, 0.3):
        with pytest.warns(ModelWarning) as caught:
            iso = IsolatedBuilding(fb, 1.0, period, 0.1)
        assert len(caught) == 1 and str(caught[0].message) == (
            f"isolation period {period:g} s is not above the fixed-base period 0.5 s of the "
            "superstructure: the isolators would not isolate (almost surely a mistake)"
        )
        assert caught[0].filename == __file__  # points at the caller
        assert iso.isolation_period == period
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        IsolatedBuilding(fb, 1.0, 0.51, 0.1)
