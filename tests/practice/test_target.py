"""Target spectra and scaling (docs/design.md §14), against the code's formula and a brute-force
minimisation."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from floorslide.errors import ModelError
from floorslide.practice import TargetSpectrum, scale_factor, suite_check


def test_two_point_spectrum_values_and_corners():
    t = TargetSpectrum.two_point(sds=1.0, sd1=0.6, tl=8.0)  # T_0 = 0.12 s, T_S = 0.6 s
    T = np.array([0.0, 0.06, 0.12, 0.3, 0.6, 1.0, 2.0, 8.0, 10.0])
    expect = [0.4, 0.7, 1.0, 1.0, 1.0, 0.6, 0.3, 0.075, 0.6 * 8.0 / 100.0]
    np.testing.assert_allclose(t(T), expect, rtol=1e-15)
    for corner in (0.12, 0.6, 8.0):  # continuous at every corner
        a, b = t(np.array([corner * (1 - 1e-12), corner * (1 + 1e-12)]))
        assert abs(a - b) < 1e-9


def test_table_target_interpolates_in_log_log_and_refuses_outside():
    t = TargetSpectrum.from_table([0.1, 1.0, 10.0], [1.0, 0.1, 0.001])  # S = 0.1/T, then 0.1/T²
    np.testing.assert_allclose(t(np.array([0.1, 0.3162277660168379, 1.0, 3.0])),
                               [1.0, 0.31622776601683794, 0.1, 0.1 / 9], rtol=1e-13)  # fmt: skip
    with pytest.raises(ModelError, match="outside the target"):
        t(np.array([20.0]))


@pytest.mark.parametrize(
    "T, S, match",
    [
        ([0.1, 0.1, 1.0], [1, 1, 1], "strictly increasing"),
        ([0.5, 0.2, 1.0], [1, 1, 1], "strictly increasing"),
        ([0.1, 0.2, 1.0], [1, -0.1, 1], "S_a must be > 0"),
        ([0.1], [1], "at least two"),
    ],
)
def test_bad_target_tables_are_one_line_errors(T, S, match):
    with pytest.raises(ModelError, match=match) as exc:
        TargetSpectrum.from_table(T, S)
    assert exc.value.where == "target"


def test_scale_factor_recovers_a_proportional_spectrum():
    t = TargetSpectrum.two_point(1.2, 0.5, 6.0)
    T = np.geomspace(0.05, 4.0, 60)
    fit = scale_factor(T, t(T) / 2.5, t, period_range=(0.2, 3.0))
    assert fit.factor == pytest.approx(2.5, rel=1e-14)
    assert fit.misfit < 1e-14 and not fit.outside_limits


def test_scale_factor_minimises_the_log_misfit():
    t = TargetSpectrum.two_point(1.0, 0.6, 8.0)
    T = np.geomspace(0.05, 4.0, 80)
    rng = np.random.default_rng(3)
    S = t(T) * np.exp(0.4 * rng.standard_normal(T.size)) * 0.3
    fit = scale_factor(T, S, t, period_range=(0.1, 2.0))
    inside = (T >= 0.1) & (T <= 2.0)

    def cost(lnf):
        return np.mean((lnf + np.log(S[inside]) - np.log(t(T[inside]))) ** 2)

    best = minimize_scalar(cost, bracket=(-3, 3), tol=1e-14).x
    assert np.log(fit.factor) == pytest.approx(best, abs=1e-7)
    assert fit.misfit == pytest.approx(np.sqrt(cost(np.log(fit.factor))), rel=1e-12)


def test_scale_to_one_period_and_limits():
    t = TargetSpectrum.two_point(1.0, 0.6, 8.0)
    T = np.geomspace(0.05, 4.0, 40)
    fit = scale_factor(T, t(T) / 10.0, t, period=1.0)
    assert fit.factor == pytest.approx(10.0, rel=1e-12) and fit.outside_limits
    with pytest.raises(ModelError, match="either period_range or period"):
        scale_factor(T, t(T), t)
    with pytest.raises(ModelError, match="outside the spectrum"):
        scale_factor(T, t(T), t, period=10.0)


def test_suite_check_at_ninety_percent():
    t = TargetSpectrum.two_point(1.0, 0.6, 8.0)
    T = np.geomspace(0.05, 4.0, 40)
    ok = np.vstack([t(T) * 0.95, t(T) * 0.9])  # mean 0.925 of the target everywhere
    passes, ratio, _ = suite_check(T, ok, t, (0.2, 3.0))
    assert passes and ratio == pytest.approx(0.925)
    low = np.vstack([t(T) * 0.95, t(T) * np.where(T > 1.0, 0.7, 0.9)])
    passes, ratio, at = suite_check(T, low, t, (0.2, 3.0))
    assert not passes and ratio == pytest.approx(0.825) and at > 1.0
