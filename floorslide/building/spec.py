"""A building in one line of text, for the command line: ``KIND:key=value,key=value,...``.

``floorslide slide`` and ``floorslide spectrum`` take ``--building SPEC`` so that a one-off floor
check needs no scene file. The keys are those of a scene's ``[[buildings]]`` table
(docs/design.md §4),
with the superstructure of an isolated building inline:

``fixed`` — a fixed-base shear building, either from its fundamental period,
    ``period`` (s, required), ``stories`` (default 1), ``damping`` (default 0.05), ``mass``
    (kg per floor, default 1), ``profile`` (``uniform`` or ``shear``)
    (:meth:`ShearBuilding.from_period <floorslide.building.model.ShearBuilding.from_period>`),
    or storey by storey, ``masses`` (kg) and ``stiffnesses`` (N/m), one value per storey from
    floor 1 up, with ``damping`` (:class:`~floorslide.building.model.ShearBuilding`);
``isolated`` — that superstructure on a linear isolation layer
    (:class:`~floorslide.building.model.IsolatedBuilding`): ``period`` (isolation period
    T_i, s, required), ``damping`` (ξ_i, default 0.10), ``base_mass_ratio`` (m_b/m, default 1);
    the superstructure as ``super_period`` (s) with ``stories``, ``super_damping`` (default
    0.05), ``mass``, ``profile`` — or as ``masses`` and ``stiffnesses`` with ``super_damping``;
    ``isolator`` (``linear``, default; ``friction_pendulum`` or ``bilinear``) puts it on a
    nonlinear layer (:class:`~floorslide.building.nonlinear.NonlinearIsolatedBuilding`), as a
    scene's ``isolator = {...}`` does: a friction pendulum takes ``mu`` (required), ``mu_s``,
    ``radius`` (m) instead of ``period`` (the pendulum period), ``capacity`` (m), ``damping``
    (default 0); a bilinear (lead-rubber) layer ``q_ratio`` (Q/W, required), ``period`` (the
    post-yield period T_d), ``yield_disp`` (m) or ``alpha`` (k2/k1), ``capacity``, ``damping``
    (default 0);
``fps`` and ``lrb`` — ``isolated`` with ``isolator=friction_pendulum`` or ``bilinear``:
    ``fps:period=3,mu=0.06,stories=3,super_period=0.4``.

A list (``masses``, ``stiffnesses``, per-floor ``mass``, per-mode ``damping``) separates its
values with ``/``: ``fixed:masses=2e5/2e5/1.5e5,stiffnesses=3e8/3e8/2e8,damping=0.03``.
Defaults are those of the scene file. Every mistake is a :class:`~floorslide.errors.ModelError`
whose ``where`` is the key at fault (or ``kind``), on one line; unknown keys are listed with the
keys the kind accepts.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from floorslide.building.model import IsolatedBuilding, LinearBuilding, ShearBuilding
from floorslide.errors import ModelError
from floorslide.text_numbers import parse_number

KINDS = ("fixed", "isolated", "fps", "lrb")
"""Building kinds of a spec (the scene's ``kind``; ``fps`` and ``lrb`` are isolated buildings on
friction pendulums and lead-rubber bearings)."""

ISOLATORS = {
    "linear": "linear",
    "friction_pendulum": "friction_pendulum",
    "fps": "friction_pendulum",
    "pendulum": "friction_pendulum",
    "bilinear": "bilinear",
    "lrb": "bilinear",
    "lead_rubber": "bilinear",
}
"""Names of the isolation layer (``isolator=``) and the model each means."""
_PENDULUM_KEYS = ("mu", "mu_s", "radius", "capacity")
_BILINEAR_KEYS = ("q_ratio", "yield_disp", "alpha", "capacity")

_SUPER_FORM = ("period", "stories", "mass", "profile")
_STOREY_FORM = ("masses", "stiffnesses")
KEYS: dict[str, tuple[str, ...]] = {
    "fixed": ("period", "stories", "damping", "mass", "profile", "masses", "stiffnesses"),
    "isolated": (
        "period",
        "damping",
        "base_mass_ratio",
        "super_period",
        "super_damping",
        "stories",
        "mass",
        "profile",
        "masses",
        "stiffnesses",
        "isolator",
        "mu",
        "mu_s",
        "radius",
        "q_ratio",
        "yield_disp",
        "alpha",
        "capacity",
    ),
}
KEYS["fps"] = tuple(
    k for k in KEYS["isolated"] if k not in ("isolator", "q_ratio", "yield_disp", "alpha")
)
KEYS["lrb"] = tuple(k for k in KEYS["isolated"] if k not in ("isolator", "mu", "mu_s", "radius"))
"""The keys each kind accepts."""

PENDULUM_PERIOD_TOLERANCE = 1e-3
"""A friction pendulum given both a radius and a period in a scene: they must agree to this
relative difference in period (``T = 2π√(R/g)``)."""


def pendulum_period(radius: float, period: float | None = None) -> float:
    """The period ``T = 2π√(R/g)`` of a friction pendulum of radius `radius` (m); with `period`
    given too (s), that period, once checked to agree within :data:`PENDULUM_PERIOD_TOLERANCE`
    (a :class:`~floorslide.errors.ModelError` at ``radius`` otherwise).

    Examples
    --------
    >>> round(pendulum_period(2.0), 4)
    2.8375
    """
    from floorslide.constants import G

    radius = float(radius)
    if not np.isfinite(radius) or radius <= 0:
        raise ModelError(f"must be > 0, got {radius!r}", "radius")
    own = 2 * np.pi * np.sqrt(radius / G)
    if period is None:
        return float(own)
    if abs(period - own) > PENDULUM_PERIOD_TOLERANCE * own:
        raise ModelError(
            f"R = {radius:g} m gives the pendulum period 2π√(R/g) = {own:.4g} s, but "
            f"period = {period:g} s; give one of radius and period",
            "radius",
        )
    return float(period)


EXAMPLES = (
    "fixed:period=0.4,stories=3,damping=0.05",
    "isolated:period=2.5,damping=0.1,super_period=0.4,stories=3",
    "fixed:masses=2e5/2e5/1.5e5,stiffnesses=3e8/3e8/2e8",
    "fps:period=3,mu=0.06,super_period=0.4,stories=3",
    "lrb:q_ratio=0.06,period=2.5,yield_disp=0.02,super_period=0.4,stories=3",
)
"""Specs shown in help and error messages."""


def _split(text: str) -> tuple[str, dict[str, str]]:
    """``KIND`` and its ``key -> value text``; one-line errors for the syntax."""
    if not isinstance(text, str):
        raise ModelError(f"expected KIND:key=value,..., e.g. {EXAMPLES[0]!r}", "kind")
    kind, _, rest = text.partition(":")
    kind = kind.strip().lower()
    if kind not in KINDS:
        raise ModelError(
            f"unknown kind {kind!r}; expected fixed, isolated, fps or lrb (KIND:key=value,..., "
            f"e.g. {EXAMPLES[0]!r})",
            "kind",
        )
    values: dict[str, str] = {}
    for item in rest.split(","):
        if not item.strip():
            continue
        key, eq, value = item.partition("=")
        key = key.strip().lower()
        if not eq or not key:
            raise ModelError(f"expected key=value, got {item.strip()!r}", key or "kind")
        if key in values:
            raise ModelError(f"{key} given twice", key)
        values[key] = value.strip()
    unknown = [k for k in values if k not in KEYS[kind]]
    if unknown:
        raise ModelError(
            f"unknown key{'s' if len(unknown) > 1 else ''} {', '.join(map(repr, unknown))} for "
            f"{'an' if kind in ('isolated', 'fps', 'lrb') else 'a'} {kind} building; known keys: "
            f"{', '.join(KEYS[kind])}",
            unknown[0],
        )
    return kind, values


def _number(values: dict[str, str], key: str, default: float | None = None) -> float:
    if key not in values:
        if default is None:
            raise ModelError(f"{key} is missing", key)
        return default
    try:
        return parse_number(values[key])
    except ValueError:
        raise ModelError(f"{key}={values[key]!r} is not a number", key) from None


def _numbers(values: dict[str, str], key: str) -> list[float]:
    parts = values[key].split("/")
    try:
        return [parse_number(p) for p in parts]
    except ValueError:
        raise ModelError(
            f"{key}={values[key]!r}: expected numbers separated by '/' (e.g. 2e5/2e5/1.5e5)", key
        ) from None


def _scalar_or_list(values: dict[str, str], key: str, default: float) -> float | list[float]:
    if key not in values:
        return default
    numbers = _numbers(values, key)
    return numbers[0] if len(numbers) == 1 else numbers


def _integer(values: dict[str, str], key: str, default: int) -> int:
    if key not in values:
        return default
    try:
        text = values[key]
        parse_number(text)  # no underscores (text_numbers owns the rule)
        return int(text)
    except ValueError:
        raise ModelError(f"{key}={values[key]!r} is not a whole number", key) from None


def _renamed(call: Callable[[], ShearBuilding], names: dict[str, str]) -> ShearBuilding:
    """Build, reporting a model error under the spec's own key name."""
    try:
        return call()
    except ModelError as exc:
        key = names.get(exc.where or "", exc.where)
        message = exc.message
        if exc.where and key != exc.where and message.startswith(exc.where):
            message = key + message[len(exc.where) :]
        raise ModelError(message, key) from None


def _superstructure(values: dict[str, str], kind: str) -> ShearBuilding:
    """The fixed-base building of a spec (the superstructure of an isolated one)."""
    period_key = "period" if kind == "fixed" else "super_period"
    damping_key = "damping" if kind == "fixed" else "super_damping"
    names = {"period": period_key, "damping": damping_key}
    storey_form = [k for k in _STOREY_FORM if k in values]
    period_form = [k for k in (period_key, *_SUPER_FORM[1:]) if k in values]
    if storey_form and period_form:
        raise ModelError(
            f"give {period_key}= (with stories=, mass=, profile=) or masses= and stiffnesses=, "
            f"not both ({', '.join(period_form)} and {', '.join(storey_form)} given)",
            period_form[0],
        )
    damping = _scalar_or_list(values, damping_key, 0.05)
    if storey_form:
        for key in _STOREY_FORM:
            if key not in values:
                raise ModelError(f"{key} is missing (masses= and stiffnesses= go together)", key)
        masses, stiffnesses = _numbers(values, "masses"), _numbers(values, "stiffnesses")
        return _renamed(lambda: ShearBuilding(masses, stiffnesses, damping), names)
    if period_key not in values:
        what = "fundamental period" if kind == "fixed" else "superstructure's fixed-base period"
        raise ModelError(
            f"{period_key} is missing: the {what}, s (or give masses= and stiffnesses=)",
            period_key,
        )
    period = _number(values, period_key)
    stories = _integer(values, "stories", 1)
    mass = _scalar_or_list(values, "mass", 1.0)
    profile = values.get("profile", "uniform")
    return _renamed(
        lambda: ShearBuilding.from_period(stories, period, damping, mass=mass, profile=profile),
        names,
    )


def parse_building(text: str):
    """The building a one-line spec describes (see the module notes for the keys).

    Parameters
    ----------
    text
        ``KIND:key=value,...``, e.g. ``"fixed:period=0.4,stories=3,damping=0.05"`` or
        ``"isolated:period=2.5,damping=0.1,super_period=0.4,stories=3"``.

    Returns
    -------
    ShearBuilding, IsolatedBuilding or NonlinearIsolatedBuilding

    Raises
    ------
    ModelError
        Bad syntax, an unknown kind or key, a missing or invalid value; ``where`` is the key.

    Examples
    --------
    >>> b = parse_building("fixed:period=0.4,stories=3")
    >>> b.stories, round(float(b.periods[0]), 12)
    (3, 0.4)
    """
    kind, values = _split(text)
    superstructure = _superstructure(values, "isolated" if kind in ("fps", "lrb") else kind)
    if kind == "fixed":
        return superstructure
    preset = {"fps": "friction_pendulum", "lrb": "bilinear"}.get(kind, "linear")
    name = values.get("isolator", preset).strip().lower()
    if name not in ISOLATORS:
        raise ModelError(
            f"unknown isolator {name!r}; expected linear, friction_pendulum (fps) or bilinear "
            "(lrb)",
            "isolator",
        )
    model = ISOLATORS[name]
    base_mass_ratio = _number(values, "base_mass_ratio", 1.0)
    if model == "linear":
        stray = [k for k in (*_PENDULUM_KEYS, *_BILINEAR_KEYS) if k in values]
        if stray:
            raise ModelError(
                f"{stray[0]} is a key of a nonlinear isolation layer: add "
                "isolator=friction_pendulum or isolator=bilinear (or write fps:/lrb:)",
                stray[0],
            )
        if "period" not in values:
            raise ModelError("period is missing: the isolation period T_i, s", "period")
        return IsolatedBuilding(
            superstructure,
            base_mass_ratio=base_mass_ratio,
            period=_number(values, "period"),
            damping=_number(values, "damping", 0.10),
        )
    return _nonlinear(superstructure, base_mass_ratio, model, values)


def _nonlinear(superstructure, base_mass_ratio: float, model: str, values: dict[str, str]):
    """The building on a nonlinear layer of a spec (keys as a scene's ``isolator`` table)."""
    from floorslide.building.isolators import BilinearIsolator, FrictionPendulum
    from floorslide.building.nonlinear import NonlinearIsolatedBuilding

    own = _PENDULUM_KEYS if model == "friction_pendulum" else _BILINEAR_KEYS
    other = _BILINEAR_KEYS if model == "friction_pendulum" else _PENDULUM_KEYS
    stray = [k for k in other if k in values and k not in own]
    if stray:
        layer = "friction pendulum" if model == "friction_pendulum" else "bilinear layer"
        raise ModelError(f"{stray[0]} is not a key of a {layer}", stray[0])
    args: dict[str, float] = {"damping": _number(values, "damping", 0.0)}
    for key in (*own, "period"):
        if key in values:
            args[key] = _number(values, key)
    if model == "friction_pendulum":
        if "mu" not in values:
            raise ModelError("mu is missing: the pendulum's friction coefficient", "mu")
        if "period" not in values and "radius" not in values:
            raise ModelError("give the pendulum's period (s) or radius (m)", "period")
        make = FrictionPendulum
    else:
        for key, what in (("q_ratio", "Q/W, the characteristic strength over the weight"),
                          ("period", "the post-yield period T_d, s")):  # fmt: skip
            if key not in values:
                raise ModelError(f"{key} is missing: {what}", key)
        make = BilinearIsolator
    try:
        layer = make(**args)
        return NonlinearIsolatedBuilding(superstructure, base_mass_ratio, layer)
    except ModelError as exc:
        key = (exc.where or "isolator").removeprefix("isolator.")
        message = exc.message.removeprefix(f"{exc.where}: ") if exc.where else exc.message
        raise ModelError(message, key) from None


def _damping_text(damping: object) -> str:
    if np.ndim(damping) == 0 and not hasattr(damping, "ratio"):
        return f"ξ = {float(damping):g}"  # type: ignore[arg-type]
    if hasattr(damping, "ratio"):
        return f"Rayleigh ξ = {damping.ratio:g}"  # type: ignore[attr-defined]
    return "ξ = " + "/".join(f"{float(z):g}" for z in np.ravel(damping))  # type: ignore[arg-type]


def describe_building(building: LinearBuilding) -> str:
    """One line saying what a building is: kind, storeys, periods and damping.

    Examples
    --------
    >>> describe_building(parse_building("fixed:period=0.4,stories=3"))
    'fixed-base, 3 storeys, T1 = 0.4 s, ξ = 0.05'
    """
    if isinstance(building, IsolatedBuilding):
        sup = building.superstructure
        return (
            f"isolated, T_i = {building.isolation_period:g} s, "
            f"ξ_i = {building.isolation_damping:g}, m_b/m = {building.base_mass_ratio:g}, "
            f"T1 = {building.periods[0]:.4g} s; superstructure {describe_building(sup)}"
        )
    if getattr(building, "segmented", False):  # on a nonlinear isolation layer
        iso = building.isolator
        if building.kind == "friction_pendulum":
            mu_s = f", mu_s = {iso.mu_s:g}" if iso.mu_s is not None else ""
            layer = f"friction pendulums, mu = {iso.mu:g}{mu_s}, T = {iso.T:.4g} s"
        else:
            layer = f"lead-rubber (bilinear), Q/W = {iso.q_ratio:g}, T_d = {iso.period:g} s"
        return (
            f"isolated on {layer}, m_b/m = {building.base_mass_ratio:g}; superstructure "
            f"{describe_building(building.superstructure)}"
        )
    storeys = "storey" if building.stories == 1 else "storeys"
    damping = _damping_text(getattr(building, "damping", None))
    return f"fixed-base, {building.stories} {storeys}, T1 = {building.periods[0]:.4g} s, {damping}"
