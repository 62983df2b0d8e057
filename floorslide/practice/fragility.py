"""Exceedance of allowable displacements and lognormal fragility curves (docs/design.md §10e).

Per building, floor and object: the fraction of records whose peak slide exceeds an allowable
displacement (a gap to a wall), and — over stripes of records scaled to increasing intensity
levels — a lognormal fragility ``P(exceed | IM = x) = Φ(ln(x/θ)/β)`` fitted by maximum likelihood
with a binomial likelihood per stripe (Baker 2015, Eq. 11).

Reference
---------
Baker, J. W. (2015). Efficient analytical fragility function fitting using dynamic structural
analysis. *Earthquake Spectra* 31(1), 579–599.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ndtr

from floorslide.errors import ModelError


def exceedance_fraction(peaks, allowable) -> np.ndarray:
    """The fraction of `peaks` (one per record, m) that exceed each allowable displacement.

    NaN peaks (records where the object was not simulated as a slider, e.g. it rocks) are left
    out of both counts; use the rocking results for those.
    """
    a = np.atleast_1d(np.asarray(allowable, dtype=float))
    if np.any(~np.isfinite(a)) or np.any(a <= 0):
        raise ModelError("allowable displacements must be > 0 m", "allowable")
    p = np.asarray(peaks, dtype=float).ravel()
    p = p[np.isfinite(p)]
    if p.size == 0:
        return np.full(a.shape, np.nan)
    return (p[None, :] > a[:, None]).mean(axis=1)


@dataclass(frozen=True)
class LognormalFragility:
    """A fitted lognormal fragility curve.

    Attributes
    ----------
    median
        ``θ``, the intensity with a 50 % probability of exceedance (NaN when the data cannot
        fix it).
    beta
        ``β``, the logarithmic standard deviation (NaN when the data cannot fix it).
    levels, n, k
        The stripes: intensity levels, records per stripe, exceedances per stripe.
    note
        Empty for a regular fit; otherwise why the maximum-likelihood estimate does not exist
        (no exceedance at any level, exceedance everywhere, or a perfect separation).
    """

    median: float
    beta: float
    levels: np.ndarray
    n: np.ndarray
    k: np.ndarray
    note: str = ""

    def probability(self, x) -> np.ndarray:
        """``Φ(ln(x/θ)/β)``."""
        x = np.asarray(x, dtype=float)
        return ndtr(np.log(x / self.median) / self.beta)


def _neg_log_likelihood(params, lx, n, k):
    ln_theta, ln_beta = params
    z = (lx - ln_theta) / math.exp(ln_beta)
    p = np.clip(ndtr(z), 1e-300, 1.0)
    q = np.clip(ndtr(-z), 1e-300, 1.0)
    return -float(np.sum(k * np.log(p) + (n - k) * np.log(q)))


def fit_fragility(levels, n_records, n_exceed) -> LognormalFragility:
    """Maximum-likelihood lognormal fragility over stripes (Baker 2015, Eq. 11).

    Maximises ``Σ_j [k_j ln Φ(ln(x_j/θ)/β) + (n_j − k_j) ln(1 − Φ(ln(x_j/θ)/β))]`` over
    ``(ln θ, ln β)`` (Nelder–Mead from the moment estimate, then polished).

    Parameters
    ----------
    levels
        Intensity of each stripe (e.g. the scale level, or S_a(T*) in g), > 0.
    n_records, n_exceed
        Records per stripe (≥ 2 each) and how many of them exceed.

    Returns
    -------
    LognormalFragility
        With NaN parameters and a note when the estimate does not exist: no stripe has an
        exceedance, every record of every stripe exceeds, or the fractions jump from 0 to 1
        between two stripes (β → 0).
    """
    from scipy.optimize import minimize

    x = np.asarray(levels, dtype=float).ravel()
    n = np.asarray(n_records, dtype=float).ravel()
    k = np.asarray(n_exceed, dtype=float).ravel()
    if not (x.size == n.size == k.size) or x.size < 2:
        raise ModelError("fragility needs at least two stripes, one count each", "stripes")
    if np.any(~np.isfinite(x)) or np.any(x <= 0):
        raise ModelError("stripe intensities must be > 0", "stripes")
    if np.any(n < 2):
        j = int(np.argmax(n < 2))
        raise ModelError(
            f"stripe {j + 1} (level {x[j]:g}) has {int(n[j])} record(s); a stripe needs ≥ 2",
            "stripes",
        )
    if np.any(k < 0) or np.any(k > n):
        raise ModelError("exceedances per stripe must lie between 0 and its records", "stripes")
    order = np.argsort(x)
    x, n, k = x[order], n[order], k[order]
    nan = math.nan
    if not np.any(k > 0):
        return LognormalFragility(nan, nan, x, n, k, "no record exceeds at any level: the "
                                  f"median lies above the largest level ({x[-1]:g})")  # fmt: skip
    if np.all(k == n):
        return LognormalFragility(nan, nan, x, n, k, "every record exceeds at every level: the "
                                  f"median lies below the smallest level ({x[0]:g})")  # fmt: skip
    frac = k / n
    if np.all(np.isin(frac, (0.0, 1.0))) and np.all(np.diff(frac) >= 0):
        j = int(np.argmax(frac == 1.0))
        return LognormalFragility(
            nan, nan, x, n, k,
            f"the fractions jump from 0 to 1 between levels {x[j - 1]:g} and {x[j]:g}: "
            "β → 0 (no spread); more stripes between them would fix it",
        )  # fmt: skip
    lx = np.log(x)
    # start: the level where the fraction crosses 1/2, and a spread from the range of levels
    mid = float(np.interp(0.5, np.maximum.accumulate(frac), lx)) if frac.max() >= 0.5 else lx[-1]
    start = np.array([mid, math.log(max(0.1, 0.5 * (lx[-1] - lx[0])))])
    res = minimize(_neg_log_likelihood, start, args=(lx, n, k), method="Nelder-Mead",
                   options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 4000})  # fmt: skip
    res = minimize(_neg_log_likelihood, res.x, args=(lx, n, k), method="Nelder-Mead",
                   options={"xatol": 1e-12, "fatol": 1e-14, "maxiter": 4000})  # fmt: skip
    ln_theta, ln_beta = res.x
    return LognormalFragility(math.exp(ln_theta), math.exp(ln_beta), x, n, k)
