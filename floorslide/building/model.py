"""Shear-building models: fixed-base and linearly isolated, as python-control state space.

Coordinates (docs/design.md §2): every degree of freedom is a floor's horizontal displacement
*relative to
the ground*; floors are numbered 0 (the ground, or the isolated base mat) to N (the roof). The
equation of motion is ``M u'' + C u' + K u = -M ι a_g(t)`` with a diagonal mass matrix and
``ι = 1``; the state is ``x = [u; u']`` and the model is ``x' = A x + B a_g``.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

import numpy as np

from floorslide.building.exact import model_substeps, spectral_radius
from floorslide.errors import ModelError, ModelWarning
from floorslide.numerics.blas import eigh

if TYPE_CHECKING:  # pragma: no cover
    import control

OUTPUTS = ("acceleration", "displacement", "velocity", "drift", "isolator")
"""Outputs a building model can give: absolute floor acceleration (m/s²), floor displacement and
velocity relative to the ground (m, m/s), inter-storey drift of the storey below a floor (m), and
the isolator displacement (m, isolated buildings only)."""


@dataclass(frozen=True)
class Rayleigh:
    """Rayleigh damping ``C = a0 M + a1 K`` with ratio `ratio` at two modes.

    Parameters
    ----------
    ratio
        Damping ratio reached at both anchor modes.
    modes
        The two (1-based) modes at which the ratio is matched.

    References
    ----------
    Chopra, A. K. (2012). *Dynamics of Structures*, 4th ed., §11.4.1, eq. 11.4.9.
    """

    ratio: float
    modes: tuple[int, int] = (1, 2)


DampingSpec = float | Sequence[float] | Rayleigh


@dataclass(frozen=True)
class ModalProperties:
    """Undamped modal properties of a building (classical modes of ``K φ = ω² M φ``).

    Attributes
    ----------
    periods
        Natural periods, s, longest first.
    frequencies_hz
        Natural frequencies ``f_n = 1/T_n``, Hz (cycles per second), lowest first.
    circular_frequencies
        Natural circular frequencies ``ω_n = 2π f_n``, rad/s, lowest first.
    shapes
        Mode shapes as columns, one row per degree of freedom (floor), normalised as requested.
    participation
        Participation factors ``Γ_n = φ_nᵀ M ι / φ_nᵀ M φ_n`` (depend on the normalisation).
    effective_mass
        Effective modal masses ``(φ_nᵀ M ι)² / φ_nᵀ M φ_n``, kg (independent of normalisation);
        they sum to the total mass.
    """

    periods: np.ndarray
    frequencies_hz: np.ndarray
    circular_frequencies: np.ndarray
    shapes: np.ndarray
    participation: np.ndarray
    effective_mass: np.ndarray

    @property
    def frequencies(self) -> np.ndarray:
        """Deprecated: the circular frequencies in rad/s (not Hz, despite the name); use
        :attr:`circular_frequencies` (rad/s) or :attr:`frequencies_hz` (Hz)."""
        warnings.warn(
            "ModalProperties.frequencies is in rad/s; use circular_frequencies (rad/s) or "
            "frequencies_hz (Hz)",
            DeprecationWarning,
            stacklevel=2,
        )
        return self.circular_frequencies


def _positive(values, name: str) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(values, dtype=float))
    if arr.ndim != 1 or arr.size == 0:
        raise ModelError(f"{name} must be a non-empty list of numbers", name)
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0):
        raise ModelError(f"{name} must be finite and > 0, got {arr.tolist()}", name)
    return arr


def _ratio(value: float, name: str) -> float:
    value = float(value)
    if not np.isfinite(value) or value < 0 or value >= 1:
        raise ModelError(
            f"{name} must be a damping ratio in [0, 1) (under-damped), got {value}", name
        )
    return value


def _finite(matrix: np.ndarray, what: str, key: str) -> np.ndarray:
    """`matrix` if every entry is finite, else a ModelError naming `key`: a building whose
    matrices overflow float64 gives no meaningful response (its floors would read 0)."""
    if not np.all(np.isfinite(matrix)):
        raise ModelError(
            f"the building's {what} is not finite (its entries overflow float64): give masses "
            "(kg) and stiffnesses (N/m) of a building, e.g. in SI without extreme exponents",
            key,
        )
    return matrix


def chain_stiffness(stiffnesses: np.ndarray) -> np.ndarray:
    """Stiffness matrix of a shear chain fixed to the ground at its first spring.

    ``stiffnesses[j]`` connects degree of freedom ``j-1`` (the ground for ``j = 0``) to ``j``.
    """
    n = stiffnesses.size
    K = np.zeros((n, n))
    for j, k in enumerate(stiffnesses):
        K[j, j] += k
        if j > 0:
            K[j - 1, j - 1] += k
            K[j - 1, j] -= k
            K[j, j - 1] -= k
    return K


def _modes(M: np.ndarray, K: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Circular frequencies (ascending) and mass-normalised mode shapes of ``K φ = ω² M φ``."""
    w2, phi = eigh(K, M)
    return np.sqrt(np.maximum(w2, 0.0)), phi


def modal_damping_matrix(M: np.ndarray, K: np.ndarray, damping: DampingSpec) -> np.ndarray:
    """Classical damping matrix from modal ratios or Rayleigh coefficients.

    A single ratio applies to every mode, a sequence gives one ratio per mode (``C = M Φ diag(2 ξ_n
    ω_n) Φᵀ M`` with mass-normalised ``Φ``, Chopra 2012 eq. 11.4.22), a :class:`Rayleigh` matches a
    ratio at two modes (eq. 11.4.9).
    """
    n = M.shape[0]
    w, phi = _modes(M, K)
    if isinstance(damping, Rayleigh):
        ratio = _ratio(damping.ratio, "damping.ratio")
        i, j = damping.modes
        if not (1 <= i <= n and 1 <= j <= n and i != j):
            raise ModelError(
                f"Rayleigh damping needs two different modes in 1..{n}, got {damping.modes}",
                "damping.modes",
            )
        wi, wj = w[i - 1], w[j - 1]
        a0 = ratio * 2 * wi * wj / (wi + wj)
        a1 = ratio * 2 / (wi + wj)
        return a0 * M + a1 * K
    if np.ndim(damping) == 0:
        ratios = np.full(n, float(damping))
    else:
        ratios = np.asarray(damping, dtype=float).ravel()
    if ratios.size != n:
        raise ModelError(
            f"damping must be one ratio or one per mode ({n}), got {ratios.size}", "damping"
        )
    for r in ratios:
        _ratio(r, "damping")
    Mphi = M @ phi
    return Mphi @ np.diag(2 * ratios * w) @ Mphi.T


def check_floors(floors, stories: int) -> list[int]:
    """A floor selection of a building of `stories` storeys validated (floors 0..stories, any
    order, repeats allowed; ``None`` or ``"all"`` means all): the one rule of every building
    kind."""
    if floors is None or (isinstance(floors, str) and floors == "all"):
        return list(range(stories + 1))
    floors = [floors] if np.isscalar(floors) else list(floors)
    out = []
    for f in floors:
        if isinstance(f, bool) or not float(f).is_integer():
            raise ModelError(f"floor numbers must be integers, got {f!r}", "floors")
        f = int(f)
        if not 0 <= f <= stories:
            raise ModelError(f"floor {f} does not exist; floors are 0..{stories}", "floors")
        out.append(f)
    return out


@dataclass(frozen=True, eq=False)
class LinearBuilding:
    """A linear lumped-mass building driven by horizontal ground acceleration.

    Subclasses fill the mass (diagonal), damping and stiffness matrices in coordinates relative
    to the ground. ``dof_floors[i]`` is the floor number of degree of freedom ``i``.
    """

    mass: np.ndarray
    damping_matrix: np.ndarray
    stiffness_matrix: np.ndarray
    dof_floors: tuple[int, ...]
    storey_below: tuple[tuple[int | None, int], ...] = field(repr=False)
    """For every degree of freedom: (index of the DOF below or None for the ground, floor)."""

    def __post_init__(self):
        # one check for every building: matrices that overflowed give NaN responses
        _finite(self.mass, "mass matrix", "mass")
        _finite(self.stiffness_matrix, "stiffness matrix", "stiffness")
        _finite(self.damping_matrix, "damping matrix", "damping")

    # ----------------------------------------------------------------- basic properties
    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom."""
        return self.mass.size

    @property
    def stories(self) -> int:
        """Number of storeys of the superstructure (the roof is floor ``stories``)."""
        return max(self.dof_floors)

    @property
    def total_mass(self) -> float:
        """Total mass above the ground, kg."""
        return float(self.mass.sum())

    @property
    def floors(self) -> tuple[int, ...]:
        """Floor numbers 0 (ground or base mat) to N (roof)."""
        return tuple(range(self.stories + 1))

    def dof_of(self, floor: int) -> int | None:
        """Index of the degree of freedom of `floor`, or ``None`` for the (rigid) ground."""
        try:
            return self.dof_floors.index(int(floor))
        except ValueError:
            if int(floor) == 0:
                return None
            raise ModelError(
                f"floor {floor} does not exist; floors are 0..{self.stories}", "floors"
            ) from None

    def check_floors(self, floors: Sequence[int] | int | None) -> list[int]:
        """Validate a floor selection (any order, repeats allowed); ``None`` means all floors."""
        return check_floors(floors, self.stories)

    # ----------------------------------------------------------------- modal properties
    def modal_properties(
        self, normalize: Literal["mass", "roof", "first"] = "mass"
    ) -> ModalProperties:
        """Undamped natural periods, mode shapes, participation factors and effective masses.

        Parameters
        ----------
        normalize
            ``"mass"`` (``φᵀ M φ = 1``), ``"roof"`` (roof component 1) or ``"first"`` (component
            of the lowest degree of freedom 1: floor 1 of a fixed-base building, the base mat of
            an isolated one — Kelly's normalisation).

        References
        ----------
        Chopra (2012), §13.1, eqs. 13.1.5 (participation) and 13.2.12 (effective mass).
        Kelly, J. M. (1996). *Earthquake-Resistant Design with Rubber*, 2nd ed., §2.1.
        """
        M = np.diag(self.mass)
        w, phi = _modes(M, self.stiffness_matrix)
        if normalize == "roof":
            phi = phi / phi[-1]
        elif normalize == "first":
            phi = phi / phi[0]
        elif normalize == "mass":
            # sign convention: positive roof component (+ where it is 0: a high mode of a
            # tall building can leave the roof still, and sign 0 would erase the shape)
            phi = phi * np.where(phi[-1] < 0, -1.0, 1.0)
        else:
            raise ModelError(f"normalize must be mass, roof or first, got {normalize!r}")
        iota = np.ones(self.n_dof)
        Ln = phi.T @ M @ iota
        mn = np.einsum("in,ij,jn->n", phi, M, phi)
        return ModalProperties(
            periods=2 * np.pi / w,
            frequencies_hz=w / (2 * np.pi),
            circular_frequencies=w,
            shapes=phi,
            participation=Ln / mn,
            effective_mass=Ln**2 / mn,
        )

    @property
    def periods(self) -> np.ndarray:
        """Undamped natural periods, s, longest first."""
        return self.modal_properties().periods

    def substeps(self, dt: float) -> int:
        """Sub-steps per record step of `dt` on which the building is stepped exactly
        (``ρ(A)·h ≤ 0.5``; :func:`~floorslide.building.exact.model_substeps`: a ModelError
        beyond its limits — a building too stiff for the records' dt)."""
        A, _ = self.state_matrices()
        return model_substeps(spectral_radius(A), dt, A.shape[0])

    # ----------------------------------------------------------------- state space
    def state_matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """``A`` (2n × 2n) and ``B`` (2n × 1) of ``x' = A x + B a_g`` with ``x = [u; u']``."""
        n = self.n_dof
        Minv = 1.0 / self.mass
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        with np.errstate(over="ignore", invalid="ignore"):  # overflow: the stepper says so
            A[n:, :n] = -Minv[:, None] * self.stiffness_matrix
            A[n:, n:] = -Minv[:, None] * self.damping_matrix
        B = np.zeros((2 * n, 1))
        B[n:, 0] = -1.0
        return A, B

    def output_matrices(
        self,
        floors: Sequence[int] | int | None = None,
        outputs: str | Sequence[str] = "acceleration",
    ) -> tuple[np.ndarray, np.ndarray, list[str]]:
        """Rows ``C`` and ``D`` of the requested outputs, and their names.

        Only what was asked is produced: for every output kind (in the order given) one row per
        requested floor. ``drift`` rows exist for floors ≥ 1 (the storey below the floor);
        ``isolator`` is a single row (isolated buildings only) and ignores `floors`.
        """
        floors = self.check_floors(floors)
        outputs = [outputs] if isinstance(outputs, str) else list(outputs)
        n = self.n_dof
        A, _ = self.state_matrices()
        rows, feed, names = [], [], []
        for kind in outputs:
            if kind not in OUTPUTS:
                raise ModelError(
                    f"unknown output {kind!r}; expected one of {', '.join(OUTPUTS)}", "outputs"
                )
            if kind == "isolator":
                if not isinstance(self, IsolatedBuilding):
                    raise ModelError("output 'isolator' needs an isolated building", "outputs")
                r = np.zeros(2 * n)
                r[0] = 1.0
                rows.append(r)
                feed.append(0.0)
                names.append("isolator_displacement")
                continue
            for f in floors:
                i = self.dof_of(f)
                r = np.zeros(2 * n)
                d = 0.0
                if kind == "acceleration":
                    if i is None:
                        d = 1.0  # the ground itself
                    else:
                        r[:] = A[n + i]
                elif kind == "displacement" and i is not None:
                    r[i] = 1.0
                elif kind == "velocity" and i is not None:
                    r[n + i] = 1.0
                elif kind == "drift":
                    if f == 0:
                        raise ModelError(
                            "drift is defined for floors 1..N (the storey below the floor)",
                            "outputs",
                        )
                    below, _ = self.storey_below[i]
                    r[i] = 1.0
                    if below is not None:
                        r[below] = -1.0
                rows.append(r)
                feed.append(d)
                names.append(f"{kind}_{f}")
        C = np.array(rows).reshape(len(rows), 2 * n)
        D = np.array(feed).reshape(len(rows), 1)
        return C, D, names

    def state_space(
        self,
        floors: Sequence[int] | int | None = None,
        outputs: str | Sequence[str] = "acceleration",
    ) -> control.StateSpace:
        """The building as a python-control ``StateSpace``: ground acceleration in, the requested
        outputs (absolute floor accelerations by default) out.

        Parameters
        ----------
        floors
            Floors to output (0..N, any order, repeats allowed); default all.
        outputs
            One or several of ``acceleration`` (absolute, m/s²), ``displacement`` and
            ``velocity`` (relative to the ground), ``drift`` (storey below each floor ≥ 1) and
            ``isolator`` (isolator displacement).
        """
        A, B = self.state_matrices()
        C, D, names = self.output_matrices(floors, outputs)
        states = [f"u{f}" for f in self.dof_floors] + [f"v{f}" for f in self.dof_floors]
        import control  # python-control costs ~0.8 s to import: only when asked for

        return control.ss(A, B, C, D, inputs=["ground_acceleration"], outputs=names, states=states)


class ShearBuilding(LinearBuilding):
    """A fixed-base N-storey shear building.

    Parameters
    ----------
    masses
        Floor masses m_1..m_N, kg (floor 1 is the first suspended floor, N the roof).
    stiffnesses
        Storey stiffnesses k_1..k_N, N/m (k_1 connects floor 1 to the ground).
    damping
        One modal damping ratio for all modes, one ratio per mode, or :class:`Rayleigh`.
        Ratios must be in [0, 1): over-damped modal specifications are rejected.

    Examples
    --------
    >>> fb = ShearBuilding.from_period(stories=3, period=0.4, damping=0.05)
    >>> round(float(fb.periods[0]), 12)
    0.4
    """

    def __init__(self, masses, stiffnesses, damping: DampingSpec = 0.05):
        m = _positive(masses, "masses")
        k = _positive(stiffnesses, "stiffnesses")
        if m.size != k.size:
            raise ModelError(
                f"masses ({m.size}) and stiffnesses ({k.size}) must have one value per storey",
                "stiffnesses",
            )
        with np.errstate(over="ignore", invalid="ignore"):
            K = _finite(chain_stiffness(k), "stiffness matrix", "stiffnesses")
            C = modal_damping_matrix(np.diag(m), K, damping)
        n = m.size
        below = tuple((None if i == 0 else i - 1, i + 1) for i in range(n))
        super().__init__(m, C, K, tuple(range(1, n + 1)), below)
        object.__setattr__(self, "storey_stiffness", k)
        object.__setattr__(self, "damping", damping)

    @classmethod
    def from_period(
        cls,
        stories: int,
        period: float,
        damping: DampingSpec = 0.05,
        mass: float | Sequence[float] = 1.0,
        profile: Literal["uniform", "shear"] = "uniform",
    ) -> ShearBuilding:
        """A shear building whose fundamental period is `period`.

        Parameters
        ----------
        stories
            Number of storeys N ≥ 1.
        period
            Fundamental fixed-base period, s.
        damping
            As in the constructor.
        mass
            Floor mass (one value for all floors, or one per floor), kg.
        profile
            ``"uniform"``: equal storey stiffnesses. ``"shear"``: storey stiffness proportional
            to the storey shear of an inverted-triangle (code) load, ``k_j ∝ Σ_{i≥j} m_i·i``,
            which gives a nearly straight first mode (a common design profile).
        """
        if isinstance(stories, bool) or int(stories) != stories or stories < 1:
            raise ModelError(f"stories must be an integer ≥ 1, got {stories!r}", "stories")
        stories = int(stories)
        period = float(_positive(period, "period")[0])
        m = np.broadcast_to(_positive(mass, "mass"), (stories,)).astype(float)
        if profile == "uniform":
            shape = np.ones(stories)
        elif profile == "shear":
            weights = m * np.arange(1, stories + 1)
            shape = np.cumsum(weights[::-1])[::-1] / weights.sum()
        else:
            raise ModelError(f"profile must be 'uniform' or 'shear', got {profile!r}", "profile")
        w1 = _modes(np.diag(m), chain_stiffness(shape))[0][0]
        with np.errstate(over="ignore", invalid="ignore"):
            k = shape * (2 * np.pi / period / w1) ** 2
        if not np.all(np.isfinite(k)):
            raise ModelError(
                f"masses up to {m.max():g} kg with a period of {period:g} s need storey "
                "stiffnesses beyond float64's range: give masses of a building (kg)",
                "mass",
            )
        return cls(m, k, damping)


def isolation_period_warning(period: float, fixed_base: float, superstructure: str = "") -> str:
    """The warning for an isolation period at or below the superstructure's fixed-base period:
    physically possible, but the isolation layer then does not isolate."""
    name = f" {superstructure!r}" if superstructure else ""
    return (
        f"isolation period {period:g} s is not above the fixed-base period {fixed_base:.4g} s "
        f"of the superstructure{name}: the isolators would not isolate (almost surely a mistake)"
    )


class IsolatedBuilding(LinearBuilding):
    """A superstructure on a base mat carried by a linear isolation layer (Kelly 1996).

    The base mat (floor 0) has mass ``m_b = base_mass_ratio · m`` with ``m`` the superstructure
    mass; the isolator stiffness and damping follow from the nominal isolation period and ratio,
    ``T_i = 2π √((m + m_b)/k_i)`` and ``ξ_i = c_i T_i / (4π (m + m_b))``. The superstructure keeps
    its own damping matrix (acting on drifts relative to the base), so the combined system is not
    classically damped; it is treated exactly in state space.

    Parameters
    ----------
    superstructure
        The fixed-base building to isolate.
    base_mass_ratio
        ``m_b / m`` (> 0).
    period
        Nominal isolation period T_i, s (> 0).
    damping
        Isolation damping ratio ξ_i in [0, 1).

    Warns
    -----
    ModelWarning
        When ``period`` is not above the superstructure's fixed-base fundamental period: the
        model is valid, but such a layer does not isolate, so it is almost surely a mistake.

    References
    ----------
    Kelly, J. M. (1996). *Earthquake-Resistant Design with Rubber*, 2nd ed., Springer, ch. 2,
    eqs. 2.1–2.6.
    """

    def __init__(
        self,
        superstructure: ShearBuilding,
        base_mass_ratio: float = 1.0,
        period: float = 2.5,
        damping: float = 0.10,
    ):
        if not isinstance(superstructure, ShearBuilding):
            raise ModelError("superstructure must be a ShearBuilding", "superstructure")
        ratio = float(_positive(base_mass_ratio, "base_mass_ratio")[0])
        period = float(_positive(period, "period")[0])
        xi = _ratio(damping, "damping")
        fixed_base = float(superstructure.periods[0])
        if period <= fixed_base:
            warnings.warn(ModelWarning(isolation_period_warning(period, fixed_base)), stacklevel=2)
        ms = superstructure.mass
        with np.errstate(over="ignore", invalid="ignore"):  # overflow: __post_init__ says so
            mtot = ms.sum() * (1 + ratio)
            mb = ratio * ms.sum()
            ki = mtot * (2 * np.pi / period) ** 2
            ci = 4 * np.pi * mtot * xi / period
        n = ms.size + 1
        iota = np.ones(ms.size)
        Ks, Cs = superstructure.stiffness_matrix, superstructure.damping_matrix

        def assemble(isolator: float, sup: np.ndarray) -> np.ndarray:
            out = np.zeros((n, n))
            out[0, 0] = isolator + iota @ sup @ iota
            out[0, 1:] = -iota @ sup
            out[1:, 0] = -sup @ iota
            out[1:, 1:] = sup
            return out

        below = ((None, 0), *tuple((i - 1, i) for i in range(1, n)))
        with np.errstate(over="ignore", invalid="ignore"):
            C, K = assemble(ci, Cs), assemble(ki, Ks)
        super().__init__(np.concatenate([[mb], ms]), C, K, tuple(range(n)), below)
        for name, value in dict(
            superstructure=superstructure,
            base_mass_ratio=ratio,
            isolation_period=period,
            isolation_damping=xi,
            isolator_stiffness=ki,
            isolator_damping=ci,
        ).items():
            object.__setattr__(self, name, value)
