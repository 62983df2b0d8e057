"""ASCE 7-22 §13.3.1 floor amplification and lognormal fragility by maximum likelihood (Baker
2015), against hand values and samples drawn from a known curve."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import ndtr

from floorslide.errors import ModelError
from floorslide.practice import (
    asce7_approximate_period,
    asce7_floor_amplification,
    exceedance_fraction,
    fit_fragility,
)


@pytest.mark.parametrize(
    "Ta, roof",
    [(0.5, 1 + 2.0 + (1 - 0.64)), (0.2, 1 + 2.5 + 0.0), (2.0, 1 + 0.5 + (1 - 0.04))],
)
def test_hf_hand_values(Ta, roof):
    hf = asce7_floor_amplification([0.0, 0.5, 1.0], Ta)
    a1 = min(1 / Ta, 2.5)
    a2 = max(0.0, 1 - (0.4 / Ta) ** 2)
    np.testing.assert_allclose(hf, [1.0, 1 + a1 / 2 + a2 / 1024, roof], rtol=1e-15)


def test_hf_without_period_and_bad_input():
    np.testing.assert_allclose(asce7_floor_amplification([0, 1]), [1.0, 3.5])
    with pytest.raises(ModelError):
        asce7_floor_amplification([1.2], 0.5)


def test_approximate_period():
    # 'all other' systems: C_t = 0.02, x = 0.75, h_n = 30 ft (9.144 m): 0.02·30^0.75
    assert asce7_approximate_period(9.144) == pytest.approx(0.02 * 30**0.75, rel=1e-12)
    with pytest.raises(ModelError, match="unknown structural system"):
        asce7_approximate_period(10.0, "timber")


def test_exceedance_fraction():
    peaks = [0.01, 0.04, 0.2, np.nan, 0.5]
    np.testing.assert_allclose(exceedance_fraction(peaks, [0.05, 0.1, 0.3]), [0.5, 0.5, 0.25])
    with pytest.raises(ModelError, match="> 0"):
        exceedance_fraction(peaks, [0.0])


def test_fit_recovers_a_known_lognormal():
    """40 synthetic studies of 8 stripes × 40 records drawn from θ = 0.4, β = 0.5: the estimates
    scatter by their sampling error (measured over 200 studies: σ(ln θ̂) = 0.055, σ(β̂) = 0.048)
    around the truth, each within 4.5 σ and their mean within 3 σ/√40."""
    theta, beta = 0.4, 0.5
    x = np.geomspace(0.1, 1.6, 8)
    n = np.full(x.size, 40)
    ln_t, b = [], []
    for seed in range(40):
        k = np.random.default_rng(seed).binomial(n, ndtr(np.log(x / theta) / beta))
        fit = fit_fragility(x, n, k)
        assert fit.note == ""
        ln_t.append(math.log(fit.median / theta))
        b.append(fit.beta - beta)
    assert max(map(abs, ln_t)) < 4.5 * 0.055 and max(map(abs, b)) < 4.5 * 0.048
    assert abs(np.mean(ln_t)) < 3 * 0.055 / math.sqrt(40)
    assert abs(np.mean(b)) < 3 * 0.048 / math.sqrt(40)


def test_fit_is_the_maximum_of_the_likelihood():
    x = np.array([0.2, 0.3, 0.5, 0.8, 1.2])
    n = np.array([20, 20, 20, 20, 20])
    k = np.array([1, 4, 9, 15, 19])
    fit = fit_fragility(x, n, k)

    def loglik(t, b):
        p = ndtr(np.log(x / t) / b)
        return np.sum(k * np.log(p) + (n - k) * np.log1p(-p))

    best = loglik(fit.median, fit.beta)
    for dt in (-1e-3, 1e-3):
        for db in (-1e-3, 1e-3):
            assert loglik(fit.median * math.exp(dt), fit.beta * math.exp(db)) < best


def test_degenerate_stripes_give_a_note_not_a_crash():
    x = [0.2, 0.4, 0.8]
    none = fit_fragility(x, [10, 10, 10], [0, 0, 0])
    assert math.isnan(none.median) and "no record exceeds" in none.note
    every = fit_fragility(x, [10, 10, 10], [10, 10, 10])
    assert math.isnan(every.beta) and "every record exceeds" in every.note
    step = fit_fragility(x, [10, 10, 10], [0, 10, 10])
    assert "β → 0" in step.note


def test_stripes_with_one_record_are_refused():
    with pytest.raises(ModelError, match="needs ≥ 2") as exc:
        fit_fragility([0.2, 0.4], [1, 10], [0, 5])
    assert exc.value.where == "stripes"
