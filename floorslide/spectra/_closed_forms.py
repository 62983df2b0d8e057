"""Closed forms of the spectrum set-up: integrals of a damped oscillator's impulse responses.

The skip test of the spectrum kernel on a floor bounds the response to the floor's deviation
``δ`` from the straight line through its step-end values by ``max|δ|·∫₀^dt |g|`` for each
quantity's impulse response ``g`` (:func:`floorslide.spectra._kernels._stage_floor`). Each such
``g`` is a damped sinusoid ``e^{−at}(P cos bt + Q sin bt)`` with ``a = ξω``, ``b = ω_d =
ω√(1 − ξ²)``, and ``∫₀^dt |g|`` has a closed form: between consecutive zeros of the sinusoid the
integral of ``e^{−at} sin(bt + φ)`` is elementary, and over whole half-periods the pieces form a
geometric series of ratio ``e^{−aπ/b}``.
"""

from __future__ import annotations

import numpy as np
import scipy.special

from floorslide.numerics.blas import expm

_MARGIN = 1.0 + 1e-9
"""Relative margin of the integrals (rounding of the closed form; they only make a skip test
conservative)."""


def _phi1(z: np.ndarray) -> np.ndarray:
    """``(e^z − 1)/z`` for complex ``z``, to rounding: its Taylor series for ``|z| < 0.5``, where
    the quotient cancels."""
    out = np.empty_like(z)
    small = np.abs(z) < 0.5
    big = ~small
    out[big] = np.expm1(z[big].real) * np.exp(1j * z[big].imag) / z[big]
    out[big] += (np.exp(1j * z[big].imag) - 1.0) / z[big]
    zs = z[small]
    term = np.ones_like(zs)
    acc = np.zeros_like(zs)
    for k in range(1, 25):  # |z|^k/(k+1)! < 0.5^24/25! ≈ 4e-33
        acc += term
        term = term * zs / (k + 1)
    out[small] = acc
    return out


def _piece(a, b, theta0, t0, length):
    """``|∫_{t0}^{t0+L} e^{−at} sin(bt − bt0 + θ0) dt|`` on an interval where the sinusoid keeps its
    sign: ``e^{−a t0}·|Im(e^{iθ0}·L·φ₁((−a + ib)L))|``."""
    z = (-a + 1j * b) * length
    return np.exp(-a * t0) * np.abs((np.exp(1j * theta0) * length * _phi1(z)).imag)


def abs_damped_sinusoid_integral(a, b, P, Q, dt):
    """``∫₀^dt |e^{−at}(P cos bt + Q sin bt)| dt``, elementwise, in closed form.

    With ``P cos bt + Q sin bt = R sin(bt + φ)`` (``R = √(P² + Q²)``, ``φ = atan2(P, Q)``) the
    sinusoid vanishes at ``t_k = (kπ − φ)/b``. Between consecutive zeros inside ``(0, dt)`` the
    integral of ``|e^{−at} sin(bt + φ)|`` is ``b/(a² + b²)·(e^{−a t_k} + e^{−a t_{k+1}})`` (the
    antiderivative ``−e^{−at}(a sin + b cos)/(a² + b²)`` at the zeros), a geometric series of
    ratio ``r = e^{−aπ/b}`` summed in closed form; the two end pieces are integrated by
    :func:`_piece` (stable when ``dt`` is a small fraction of the period).

    Parameters
    ----------
    a, b
        Decay rate ``ξω`` (≥ 0) and circular frequency ``ω_d`` (> 0), arrays.
    P, Q
        Coefficients of ``cos`` and ``sin``, arrays.
    dt
        Length of the interval, s.
    """
    a, b, P, Q = np.broadcast_arrays(*(np.asarray(x, float) for x in (a, b, P, Q)))
    R = np.hypot(P, Q)
    phi = np.arctan2(P, Q)
    # zeros k_lo..k_hi inside (0, dt)
    k_lo = np.floor(phi / np.pi) + 1.0
    k_hi = np.ceil((b * dt + phi) / np.pi) - 1.0
    nz = np.maximum(k_hi - k_lo + 1.0, 0.0)
    out = np.empty(a.shape)
    none = nz == 0
    out[none] = _piece(a[none], b[none], phi[none], 0.0, np.full(int(none.sum()), dt))
    some = ~none
    if some.any():
        a_, b_, phi_ = a[some], b[some], phi[some]
        lo, hi, n = k_lo[some], k_hi[some], nz[some]
        t_lo = (lo * np.pi - phi_) / b_
        t_hi = (hi * np.pi - phi_) / b_
        first = _piece(a_, b_, phi_, 0.0, t_lo)
        last = _piece(a_, b_, np.where(hi % 2 == 0, 0.0, np.pi), t_hi, dt - t_hi)
        # n − 1 whole half-periods from t_lo: Σ_{j<n−1} r^j (e^{−a t_lo} + e^{−a t_lo} r)
        x = a_ * np.pi / b_
        with np.errstate(invalid="ignore", divide="ignore"):
            geo = np.where(x > 0, np.expm1(-x * (n - 1.0)) / np.expm1(-x), n - 1.0)
        whole = b_ / (a_**2 + b_**2) * np.exp(-a_ * t_lo) * (1.0 + np.exp(-x)) * geo
        out[some] = first + whole + last
    return R * out * _MARGIN


def impulse_integrals(w, xi, dt) -> np.ndarray:
    """``∫₀^dt |h|``, ``∫₀^dt |h'|`` and ``∫₀^dt |ω²h + 2ξωh'|`` of the oscillators' impulse
    responses ``h = e^{−ξωt} sin(ω_d t)/ω_d``, ``(3, len(w))``, in closed form
    (:func:`abs_damped_sinusoid_integral`) with a relative margin of 1e-9 for rounding:

    - ``h``: ``P = 0``, ``Q = 1/ω_d``;
    - ``h' = e^{−ξωt}(cos ω_d t − ξω/ω_d sin ω_d t)``;
    - ``ω²h + 2ξωh' = e^{−ξωt}(2ξω cos ω_d t + ω²(1 − 2ξ²)/ω_d sin ω_d t)``.
    """
    w = np.asarray(w, float)
    xi = np.asarray(xi, float)
    a = xi * w
    b = w * np.sqrt(1.0 - xi**2)
    rows = [
        (np.zeros_like(w), 1.0 / b),
        (np.ones_like(w), -a / b),
        (2.0 * a, w**2 * (1.0 - 2.0 * xi**2) / b),
    ]
    return np.ascontiguousarray(
        np.stack([abs_damped_sinusoid_integral(a, b, P, Q, dt) for P, Q in rows])
    )


SERIES_NORM = 4.0
"""Largest ``ωh(1 + 2ξ)`` (a bound of the norm of ``hJ`` in the scaled state) for which
:func:`coupled_recurrence` sums the oscillator's φ-functions by their Taylor series: its terms
grow to at most ``~e^{‖hJ‖}`` times the result before they shrink, so the sum keeps ~1e-14 up to
this bound (it covers periods down to ~1.7 steps at 5 % damping). The few oscillators beyond it
take SciPy's ``expm`` of the augmented matrix."""

_TAIL = 1e-18
"""A series is truncated once its terms bound falls below ``_TAIL`` times its first term's."""


def _phi_columns(w, xi, h, jmax):
    """``φ_j(hJ)·e₂`` for ``j = 0..jmax`` of the oscillators ``J = [[0, 1], [−ω², −2ξω]]``,
    ``(m, 2, jmax + 1)``, by the series ``φ_j(X) = Σ_i X^i/(i + j)!`` in the scaled state
    ``[ωq, q']`` (where ``X = θ[[0, 1], [−1, −2ξ]]`` with ``θ = ωh`` and ``‖X‖ ≤ θ(1 + 2ξ) ≤``
    :data:`SERIES_NORM`), then scaled back (row 0 divided by ``ω``)."""
    th = w * h
    m = w.size
    norm = float(np.max(th * (1.0 + 2.0 * xi))) if m else 0.0
    # powers u_i = X^i e₂ until norm^i/i! < _TAIL (the φ_j with j ≥ 1 converge faster still)
    terms = 1
    bound = 1.0
    while bound >= _TAIL and terms < 200:
        bound *= norm / terms
        terms += 1
    U = np.empty((m, 2, terms))
    U[:, 0, 0] = 0.0
    U[:, 1, 0] = 1.0
    for i in range(1, terms):
        U[:, 0, i] = th * U[:, 1, i - 1]
        U[:, 1, i] = th * (-U[:, 0, i - 1] - 2.0 * xi * U[:, 1, i - 1])
    i = np.arange(terms)[:, None]
    j = np.arange(jmax + 1)[None, :]
    F = 1.0 / scipy.special.factorial(i + j)
    out = U @ F
    out[:, 0, :] /= w[:, None]
    return out


def coupled_recurrence(A, b, Ca, da, w, xi, h):
    """Exact step ``h`` of oscillators on a floor, coupled to the building's state, by series.

    The building ``x' = Ax + b·a`` (``n`` states) drives oscillators ``q'' + 2ξωq' + ω²q = −a_f``
    with the floor acceleration ``a_f = Ca·x + da·a``; over a step whose ground acceleration
    ``a`` is linear from ``a₀`` to ``a₁``,

    ``[q, q']⁺ = Φ [q, q'] + P_x x + p a₀ + r a₁``

    (the oscillator rows of the exponential of the augmented first-order-hold matrix, Van Loan
    1978). With ``J = [[0, 1], [−ω², −2ξω]]``, ``e₂ = [0, 1]ᵀ``, ``φ_j(X) = Σ_i X^i/(i + j)!``
    (so that ``∫₀^h e^{(h−s)J} s^p/p! ds = h^{p+1} φ_{p+1}(hJ)``) and the building's moments
    ``M_k = Ca·A^k``, ``β_k = Ca·A^k·b``, expanding ``e^{As}`` in the convolution gives

    - ``Φ = e^{hJ}`` (Nigam & Jennings 1969, :func:`floorslide.spectra.core._sdof_recurrence`);
    - ``P_x = −Σ_k h^{k+1} φ_{k+1}(hJ) e₂ M_k``;
    - the responses to ``a = 1`` and ``a = t``: ``g₀ = −[da·h φ₁ + Σ_k β_k h^{k+2} φ_{k+2}] e₂``,
      ``g₁ = −[da·h² φ₂ + Σ_k β_k h^{k+3} φ_{k+3}] e₂``; ``p = g₀ − g₁/h``, ``r = g₁/h``.

    The building series converges like ``(ρ(A)h)^k/k!`` (the callers step with ``ρ(A)h ≤ 0.5``)
    and is truncated adaptively. The ``φ_j`` are summed as in :func:`_phi_columns` for
    ``ωh(1 + 2ξ) ≤`` :data:`SERIES_NORM`; the oscillators beyond it get the augmented matrix's
    ``expm`` (:func:`expm_recurrence`). ``h`` may be one value or one per oscillator.

    Returns ``Φ (m, 2, 2)``, ``P_x (m, 2, n)``, ``p (m, 2)``, ``r (m, 2)``.
    """
    from floorslide.spectra.core import _sdof_recurrence

    n = A.shape[0]
    m = w.size
    h = np.broadcast_to(np.asarray(h, float), w.shape)
    Pqq, _, _ = _sdof_recurrence(w, xi, h)
    Pqx = np.zeros((m, 2, n))
    pq = np.zeros((m, 2))
    qq = np.zeros((m, 2))
    series = w * h * (1.0 + 2.0 * xi) <= SERIES_NORM
    if series.any():
        hs = h[series]
        hmax = float(hs.max())
        # building moments M_k = Ca A^k until M_k h^k / k! is negligible
        Mk = [np.asarray(Ca, float)]
        fact = 1.0
        first = np.abs(Mk[0]).sum() + abs(float(Ca @ b)) * hmax + 1e-300
        while len(Mk) < 200:
            k = len(Mk)
            Mk.append(Mk[-1] @ A)
            fact *= k
            size = (np.abs(Mk[-1]).sum() + abs(float(Mk[-1] @ b)) * hmax) * hmax**k / fact
            if k > 2 and size < _TAIL * first:
                break
        M = np.array(Mk)
        B = M @ b
        K = M.shape[0]
        ph = _phi_columns(w[series], xi[series], hs, K + 2)
        hp = hs[:, None] ** np.arange(1, K + 4)  # h^(j+1), j = 0..K+2
        Pqx[series] = -((ph[:, :, 1 : K + 1] * hp[:, None, :K]) @ M)
        g0 = -(da * hp[:, 0:1] * ph[:, :, 1] + (ph[:, :, 2 : K + 2] * hp[:, None, 1 : K + 1]) @ B)
        g1 = -(da * hp[:, 1:2] * ph[:, :, 2] + (ph[:, :, 3 : K + 3] * hp[:, None, 2 : K + 2]) @ B)
        pq[series] = g0 - g1 / hs[:, None]
        qq[series] = g1 / hs[:, None]
    rest = ~series
    if rest.any():
        _, Pqx[rest], pq[rest], qq[rest] = expm_recurrence(A, b, Ca, da, w[rest], xi[rest], h[rest])
    return Pqq, Pqx, pq, qq


def expm_recurrence(A, b, Ca, da, w, xi, h):
    """The same recurrence as :func:`coupled_recurrence` from one batched ``expm`` of the
    augmented first-order-hold matrices (Van Loan 1978): the reference, and the fallback for
    ``ωh(1 + 2ξ) >`` :data:`SERIES_NORM`."""
    n = A.shape[0]
    m = w.size
    N = n + 2
    aug = np.zeros((m, N + 2, N + 2))
    aug[:, :n, :n] = A
    aug[:, :n, N] = b
    aug[:, n, n + 1] = 1.0
    aug[:, n + 1, :n] = -Ca
    aug[:, n + 1, n] = -(w**2)
    aug[:, n + 1, n + 1] = -2 * xi * w
    aug[:, n + 1, N] = -da
    aug[:, N, N + 1] = 1.0
    h = np.broadcast_to(np.asarray(h, float), w.shape)
    E = expm(aug * h[:, None, None])
    Pqq = np.ascontiguousarray(E[:, n:N, n:N])
    Pqx = np.ascontiguousarray(E[:, n:N, :n])
    g0 = E[:, n:N, N]
    g1 = E[:, n:N, N + 1] / h[:, None]
    return Pqq, Pqx, np.ascontiguousarray(g0 - g1), np.ascontiguousarray(g1)
