"""Exact stepping of a linear system driven by a piecewise-linear record.

For ``x' = A x + b a(t)`` with ``a`` linear inside each step, ``a(t_k + τ) = a_k + s_k τ``, the
state inside the step is known in closed form (first-order hold):

    x(t_k + τ) = Φ(τ) x_k + Γ₀(τ) a_k + Γ₁(τ) s_k,
    Φ(τ) = e^{Aτ},  Γ₀(τ) = ∫₀^τ e^{Aσ} b dσ,  Γ₁(τ) = ∫₀^τ e^{A(τ-σ)} b σ dσ,

all three read off one matrix exponential of the augmented matrix
``[[A, b, 0], [0, 0, 1], [0, 0, 0]]·τ`` (Van Loan 1978, Theorem 1). Stepping with ``τ = dt``
gives the samples exactly for the piecewise-linear record, at any dt.

This module is the one mechanism every exact solver composes with: sliding contents, floor
response spectra and the flexible oscillator on a floor all need the state *inside* a step.
For compiled kernels it also provides the Taylor form of any output at a step start
(:meth:`ExactStepper.taylor_rows` with :func:`floorslide.building._instep.taylor_coefficients`):
on sub-steps with ``ρ(A)·h ≤ 0.5`` the degree-``K`` Taylor polynomial equals the exact in-step
function to rounding, so events and peaks inside steps are roots and extrema of a polynomial.

References
----------
Van Loan, C. F. (1978). Computing integrals involving the matrix exponential. *IEEE Trans.
Automatic Control* 23(3), 395–404.
Franklin, G. F., Powell, J. D., Workman, M. (1998). *Digital Control of Dynamic Systems*, 3rd ed.,
§6.3.2 (triangle hold equivalent).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from floorslide.errors import ModelError
from floorslide.numerics.blas import expm

MAX_PHASE = 0.5
"""Largest ``ρ(A)·h`` of a sub-step on which Taylor polynomials represent the in-step response."""

TAYLOR_TOL = 1e-18
"""Truncation bound ``(ρh)^{K+1}/(K+1)!`` that fixes the Taylor degree ``K``."""


def foh_matrices(A: np.ndarray, b: np.ndarray, tau: float) -> tuple[np.ndarray, ...]:
    """``Φ(τ), Γ₀(τ), Γ₁(τ)`` of the first-order-hold solution, from one augmented exponential.

    Parameters
    ----------
    A
        State matrix (n × n).
    b
        Input vector (n,) or (n, 1).
    tau
        Time since the step start, s.

    Returns
    -------
    phi, gamma0, gamma1
        ``e^{Aτ}`` (n × n) and the two input vectors (n,).

    References
    ----------
    Van Loan (1978), Theorem 1.
    """
    n = A.shape[0]
    b = np.asarray(b, dtype=float).reshape(n)
    aug = np.zeros((n + 2, n + 2))
    aug[:n, :n] = A
    aug[:n, n] = b
    aug[n, n + 1] = 1.0
    E = expm(aug * tau)
    # contiguous copies: compiled kernels are specialised on the memory layout
    return np.ascontiguousarray(E[:n, :n]), E[:n, n].copy(), E[:n, n + 1].copy()


def spectral_radius(A: np.ndarray) -> float:
    """Largest modulus of the eigenvalues of ``A``."""
    if A.size == 0:
        return 0.0
    return float(np.max(np.abs(np.linalg.eigvals(A))))


def substeps_for(rate, dt: float):
    """Fewest equal sub-steps of ``dt`` with ``rate·h ≤ MAX_PHASE`` (at most one critical point
    per sub-step; Taylor polynomials of modest degree equal the response to rounding). ``rate``
    (a spectral radius or circular frequency, 1/s) may be an array: one count each, ``int64``."""
    m = np.maximum(1, np.ceil(np.asarray(rate, dtype=float) * dt / MAX_PHASE - 1e-12))
    return int(m) if m.ndim == 0 else m.astype(np.int64)


MAX_SUBSTEPS = 1000
"""Most sub-steps per record step a building model may need: its fastest mode's period down
to ``dt/80`` (``2π·dt/(MAX_PHASE·MAX_SUBSTEPS)``). Real buildings need a few, a very stiff one
(T = 0.01 s under dt = 0.02 s) 26; a 200-storey building of period 0.01 s would need 3208 at
dt = 0.01 s (minutes a record), of 10⁻⁶ s 3·10⁷ (tens of GB: a MemoryError)."""

MAX_STEP_BYTES = 64 * 2**20
"""Most memory the states of one record step may take, ``(substeps + 1)·n·8`` bytes: the least a
streamed motion (:mod:`floorslide.building.exact_motion`) holds at once."""


def model_substeps(rate: float, dt: float, n_states: int) -> int:
    """:func:`substeps_for` of a building model with `n_states` states and spectral radius `rate`
    (1/s), within :data:`MAX_SUBSTEPS` and :data:`MAX_STEP_BYTES`.

    Raises
    ------
    ModelError
        Beyond either limit: one line with the sub-steps and memory it would need, the period
        of its fastest mode, and what to change (key ``building``; a scene names its own).
    """
    m = substeps_for(rate, dt)
    need = (m + 1) * n_states * 8
    if m <= MAX_SUBSTEPS and need <= MAX_STEP_BYTES:
        return m
    fastest = 2 * math.pi / rate
    dt_ok = MAX_SUBSTEPS * MAX_PHASE / rate
    raise ModelError(
        f"would need {m} sub-steps per record step at dt = {dt:g} s ({need / 2**20:.3g} MiB of "
        f"states per step, {n_states} states): its fastest time scale 2π/ρ(A) is {fastest:.3g} s; "
        f"at most {MAX_SUBSTEPS} sub-steps and {MAX_STEP_BYTES // 2**20} MiB are allowed — give "
        f"it a longer period or fewer stories, or records with dt ≤ {dt_ok:.3g} s",
        "building",
    )


def taylor_degree(phase: float, tol: float = TAYLOR_TOL) -> int:
    """Smallest degree ``K ≥ 3`` with ``phase^{K+1}/(K+1)! ≤ tol``."""
    K = 3
    while phase > 0 and phase ** (K + 1) / math.factorial(K + 1) > tol and K < 60:
        K += 1
    return K


def taylor_degrees(phases: np.ndarray, tol: float = TAYLOR_TOL) -> np.ndarray:
    """:func:`taylor_degree` of each phase (``0 ≤ phase ≤ 1``, where ``phase^{K+1}/(K+1)!``
    decreases with ``K``), as ``int64``."""
    phases = np.asarray(phases, dtype=float)
    K = np.full(phases.shape, 3, dtype=np.int64)
    for k in range(3, 60):
        K += phases ** (k + 1) / math.factorial(k + 1) > tol
    return K


@dataclass(frozen=True, eq=False)
class ExactStepper:
    """Exact stepping of ``x' = A x + b a(t)`` for a piecewise-linear ``a`` sampled at ``dt``.

    A step of ``dt`` is split into ``substeps`` equal sub-steps of length ``h`` (the ground
    record is linear on each, so this is still exact) such that ``ρ(A)·h ≤ 0.5``.

    Attributes
    ----------
    A, b
        The continuous model.
    dt
        Record time step, s.
    substeps
        Sub-steps per record step.
    h
        Sub-step length, s.
    phi, gamma0, gamma1
        ``Φ(h), Γ₀(h), Γ₁(h)``.
    order
        Degree ``K`` of the in-step Taylor polynomials.
    """

    A: np.ndarray
    b: np.ndarray
    dt: float
    substeps: int
    h: float
    phi: np.ndarray
    gamma0: np.ndarray
    gamma1: np.ndarray
    order: int

    @classmethod
    def build(cls, A: np.ndarray, b: np.ndarray, dt: float, substeps: int | None = None):
        """Discretise ``(A, b)`` for record step `dt` (sub-steps chosen from ``ρ(A)`` unless
        given)."""
        A = np.asarray(A, dtype=float)
        b = np.asarray(b, dtype=float).reshape(A.shape[0])
        if not (np.all(np.isfinite(A)) and np.all(np.isfinite(b))):
            raise ModelError(
                "the state matrices are not finite (the building's masses and stiffnesses "
                "overflow float64 in M⁻¹K and M⁻¹C)",
                "building",
            )
        rho = spectral_radius(A)
        if substeps is None:
            substeps = model_substeps(rho, dt, A.shape[0])
        h = dt / substeps
        phi, g0, g1 = foh_matrices(A, b, h)
        if not (np.all(np.isfinite(phi)) and np.all(np.isfinite(g0)) and np.all(np.isfinite(g1))):
            raise ModelError(
                f"the exact sub-step matrices (h = {h:.3g} s) are not finite: the building's "
                "matrices are beyond float64's range",
                "building",
            )
        return cls(A, b, float(dt), int(substeps), h, phi, g0, g1, taylor_degree(rho * h))

    @property
    def n(self) -> int:
        """State dimension."""
        return self.A.shape[0]

    def input_weights(self, h: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Vectors ``p, q`` with ``x_{k+1} = Φ x_k + p a_k + q a_{k+1}`` for a step `h`."""
        h = self.h if h is None else h
        if h == self.h:
            g0, g1 = self.gamma0, self.gamma1
        else:
            _, g0, g1 = foh_matrices(self.A, self.b, h)
        return g0 - g1 / h, g1 / h

    def state_at(self, x: np.ndarray, a0: float, slope: float, tau: float) -> np.ndarray:
        """``x(t_k + τ) = Φ(τ) x_k + Γ₀(τ) a_k + Γ₁(τ) s_k`` for any ``τ`` (reference
        evaluation with its own matrix exponential)."""
        phi, g0, g1 = foh_matrices(self.A, self.b, tau)
        return phi @ np.asarray(x, dtype=float) + g0 * a0 + g1 * slope

    def taylor_rows(
        self, C: np.ndarray, D: np.ndarray | None = None, order: int | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Rows giving the Taylor coefficients of outputs ``y = C x + D a`` at a step start.

        Returns
        -------
        R
            ``(n_out, K+1, n)`` with ``R[:, j] = C A^j / j!``.
        beta
            ``(n_out, K+1)`` with ``beta[:, 0] = D`` and ``beta[:, j] = C A^{j-1} b / j!``.

        Notes
        -----
        With ``a(τ) = a_k + s τ``: ``y^{(j)} = C A^j x + C A^{j-1} b a_k + C A^{j-2} b s``
        (terms with negative powers absent; the ``D`` term enters ``j = 0`` and ``j = 1``).
        """
        K = self.order if order is None else order
        C = np.atleast_2d(np.asarray(C, dtype=float))
        m = C.shape[0]
        D = np.zeros(m) if D is None else np.asarray(D, dtype=float).reshape(m)
        R = np.empty((m, K + 1, self.n))
        beta = np.empty((m, K + 1))
        row = C.copy()
        beta[:, 0] = D
        fact = 1.0
        for j in range(K + 1):
            if j > 0:
                fact *= j
                beta[:, j] = (row @ self.b) / fact
                row = row @ self.A
            R[:, j] = row / fact
        return R, beta
