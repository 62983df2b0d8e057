"""Scene files (TOML, docs/design.md §4): loading and validation with every problem at once.

A scene declares record sets, optional processing, buildings (lists sweep: one building per
value), contents (equipment with friction coefficients on chosen floors), floor response
spectra and report options. :func:`load_scene` returns a frozen :class:`Scene` or raises one
:class:`~floorslide.errors.SceneError` listing every problem with its key path, e.g.
``buildings[1].period: must be > 0``.
"""

from __future__ import annotations

import glob
import itertools
import math
import tomllib
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from floorslide.constants import MAX_ACCELERATION, MAX_LIST, G
from floorslide.errors import SceneError

TOP_KEYS = {"scene", "records", "processing", "buildings", "contents", "spectra", "report"}
RECORD_KEYS = {
    "set",
    "files",
    "catalog",
    "where",
    "scale_pga",
    "scale",
    "format",
    "units",
    "dt",
    "component",
    "vertical_component",
}
PROCESSING_KEYS = {
    "demean",
    "detrend",
    "detrend_order",
    "taper",
    "highpass",
    "lowpass",
    "bandpass",
    "filter_order",
    "zerophase",
    "baseline",
    "resample",
    "scale_pga",
    "scale",
}
FIXED_KEYS = {
    "id",
    "kind",
    "stories",
    "period",
    "damping",
    "mass",
    "stiffness",
    "profile",
    "period_h2",
    "damping_h2",
    "storey_heights",
}
ISOLATED_KEYS = {
    "id",
    "kind",
    "superstructure",
    "base_mass_ratio",
    "period",
    "damping",
    "isolator",
    "period_h2",
    "damping_h2",
}
DIRECTION_KEYS = ("period_h2", "damping_h2")
"""A building's model along the second horizontal component of a pair (uncoupled, no
torsion): ``period`` and ``damping`` are those along the first; without them, the same both
ways. A single-component record runs on the first direction's model."""
ISOLATOR_KEYS = {
    "linear": {"model"},
    "bilinear": {"model", "q_ratio", "yield_disp", "alpha", "capacity"},
    "friction_pendulum": {"model", "mu", "mu_s", "capacity", "radius"},
}
"""Keys of an isolated building's ``isolator`` table per ``model`` (``period`` and ``damping``
stay on the building: the isolation period — post-yield ``T_d`` of a bilinear layer, the
pendulum period — and a viscous ratio)."""
ISOLATOR_SWEEPS = {"q_ratio": "Q", "yield_disp": "Dy", "alpha": "alpha", "mu": "mu"}
"""Isolator keys a list sweeps, and their tag in variant ids (``fps@mu=0.04``)."""
DECOUPLING_LIMIT = {"fixed": 0.03, "isolated": 0.10}
"""The largest floor mass ratio at which the decoupled peak slide stays within 5 % of the coupled
one in the median over the bundled records (``scripts/coupled_equipment_table.py``, docs/design.md
§10f), on a fixed-base and a linearly isolated building."""
CONTENT_KEYS = {
    "id",
    "floors",
    "mu",
    "mu_s",
    "width",
    "height",
    "model",
    "frequency",
    "damping",
    "mass_ratio",
    "vertical",
    "direction",
    "restitution",
    "rocking",
    "allowable",
    "floor_mass_ratio",
    "coupled",
}
SCALE_KEYS = {
    "target",
    "periods",
    "period",
    "damping",
    "limits",
    "levels",
    "points",
    "match_suite",
}
"""Keys of a record set's ``scale`` table (target-spectrum scaling, docs/design.md §10e)."""
TARGET_KEYS = {"sds", "sd1", "tl"}
SPECTRA_KEYS = {"floors", "damping", "periods", "broadening"}
REPORT_KEYS = {"periods", "damping", "compare", "history_record"}
ID_MAX_CHARS = 64
"""Longest id of a record set, building or content."""
ID_RESERVED = "/:@"
"""Characters an id must not hold: ``/`` separates the groups of the result file, ``:`` the two
buildings of a comparison (``A:B``), ``@`` an id from its variant's tags (``iso@T=2.5``,
``set@0.3g``)."""
ID_RULE = (
    f"an id is 1–{ID_MAX_CHARS} characters: letters, digits, spaces and punctuation other than "
    "'/', ':' and '@', not '.' or '..', without control characters or spaces at either end"
)
"""What :func:`id_problem` allows, as the error messages say it."""
QA_ACTIONS = ("warn", "reject")
"""Values of ``[scene] qa`` (:mod:`floorslide.records.quality`)."""
MU_PLAUSIBLE = 2.0
"""Largest plausible Coulomb friction coefficient: dry friction between equipment and floor
finishes lies below about 1 (rubber on concrete); a value above this is almost surely a
percentage (``mu = 10`` for 0.10) and is warned about, not refused."""
ALLOWABLE_PLAUSIBLE = 5.0
"""Allowable displacements (m) at or above this are warned about: a gap of metres is almost
surely one written in cm or mm (``allowable = 10`` for 10 cm)."""


def friction_warning(mu: float) -> str | None:
    """The one-line warning for an implausible friction coefficient (above
    :data:`MU_PLAUSIBLE`), or None."""
    if not mu > MU_PLAUSIBLE:
        return None
    return (
        f"friction coefficient {mu:g} is implausible (dry friction is below about 1); "
        f"did you mean {mu / 100:.2f}?"
    )


def allowable_warning(value: float) -> str | None:
    """The one-line warning for an implausible allowable displacement (at or above
    :data:`ALLOWABLE_PLAUSIBLE` m), or None."""
    if not value >= ALLOWABLE_PLAUSIBLE:
        return None
    return (
        f"allowable displacement {value:g} m is implausible (the value is in m); did you mean "
        f"{value / 100:g} ({value:g} cm) or {value / 1000:g} ({value:g} mm)?"
    )


MAX_SCALE_PGA = MAX_ACCELERATION / G
"""Largest ``scale_pga`` (g): the most the solvers take
(:data:`floorslide.constants.MAX_ACCELERATION`)."""

MAX_STORIES = 200
"""Largest building a scene may declare (a 200-storey shear building has 400 states)."""


@dataclass(frozen=True)
class ScaleSpec:
    """Amplitude scaling of a set's records to a target spectrum (docs/design.md §10e).

    Each record is scaled by one factor: the one that minimises the mean squared misfit of the
    logarithms of its spectrum and the target's over ``period_range`` (``period`` None), or the
    one that matches the target at ``period``. ``levels`` (multiples of the target) make one set
    per level, the stripes of a fragility analysis.
    """

    target: Any = field(repr=False, compare=False)
    """The :class:`~floorslide.practice.target.TargetSpectrum`."""
    target_source: str
    """How the scene gave it: ``two-point S_DS = …`` or the CSV file's path."""
    period_range: tuple[float, float]
    """Range of the fit (no ``period``) and of the suite check, s."""
    period: float | None = None
    damping: float = 0.05
    limits: tuple[float, float] = (0.25, 4.0)
    levels: tuple[float, ...] = ()
    points: int = 40
    match_suite: bool = False
    """Raise the whole suite by one factor where its mean falls below 90 % of the target."""

    def grid(self) -> np.ndarray:
        """The periods of the records' spectra: ``points`` log-spaced over the range, and
        ``period`` itself."""
        lo, hi = self.period_range
        grid = np.geomspace(lo, hi, self.points)
        if self.period is not None:
            grid = np.unique(np.append(grid, self.period))
        return grid


@dataclass(frozen=True)
class RecordSetSpec:
    """A record set: files by glob or a catalog, with optional scaling (a list sweeps)."""

    set: str
    files: tuple[str, ...] = ()
    catalog: str | None = None
    where: dict = field(default_factory=dict)
    scale_pga: tuple[float, ...] = ()
    scale: ScaleSpec | None = None
    """Scaling to a target spectrum (``scale_pga`` and ``scale`` exclude each other)."""
    format: str | None = None
    units: str | None = None
    dt: float | None = None
    component: str | None = None
    vertical_component: str | None = None
    pairs: bool = False
    """A catalog of components (``file_h1``, ``file_h2``, optionally ``file_v``): each record
    is a pair of horizontal components, and its blocks slide in the plane."""


@dataclass(frozen=True)
class BuildingSpec:
    """One building of the study (one value of every swept parameter).

    A fixed-base building (or the superstructure of an isolated one) is either scaled to its
    fundamental period (``masses`` or ``mass`` and ``profile``) or given storey by storey
    (``masses`` and ``stiffnesses``; ``period`` is then its computed fundamental period).
    """

    id: str
    base: str
    kind: str
    stories: int
    period: float
    damping: float
    mass: float = 1.0
    profile: str = "uniform"
    superstructure: str = ""
    super_period: float = math.nan
    super_damping: float = math.nan
    base_mass_ratio: float = math.nan
    masses: tuple[float, ...] = ()
    stiffnesses: tuple[float, ...] = ()
    isolator: tuple[tuple[str, object], ...] = ()
    """A nonlinear isolation layer: ``(("model", "bilinear" | "friction_pendulum"), (key,
    value) …)``; empty for the linear isolator."""
    period_h2: float = math.nan
    """Along the second horizontal component: the fixed-base period (the isolation period of
    an isolated building); NaN: as along the first."""
    damping_h2: float = math.nan
    """Along the second horizontal component: the damping ratio (NaN: as along the first)."""
    super_period_h2: float = math.nan
    super_damping_h2: float = math.nan
    storey_heights: tuple[float, ...] = ()
    """Height of each storey, m (``()``: equal storeys); the code comparison's z/h."""

    @property
    def two_way(self) -> bool:
        """Whether the model differs between the two horizontal directions."""
        return not all(
            math.isnan(v)
            for v in (self.period_h2, self.damping_h2, self.super_period_h2, self.super_damping_h2)
        )

    @property
    def isolator_model(self) -> str:
        """``linear``, ``bilinear`` or ``friction_pendulum`` (``""`` for a fixed base)."""
        if self.kind != "isolated":
            return ""
        return str(dict(self.isolator).get("model", "linear"))

    def _shear_building(self, period: float, damping: float):
        from floorslide.building.model import ShearBuilding

        masses = self.masses or (self.mass,) * self.stories
        if self.stiffnesses:
            return ShearBuilding(masses, self.stiffnesses, damping)
        return ShearBuilding.from_period(
            self.stories, period, damping, mass=masses, profile=self.profile
        )

    def build(self):
        """The building model (a :class:`~floorslide.errors.ModelWarning` is not repeated: the
        scene lists it, :attr:`Scene.warnings`)."""
        from floorslide.building.model import IsolatedBuilding
        from floorslide.errors import ModelWarning

        if self.kind == "fixed":
            return self._shear_building(self.period, self.damping)
        sup = self._shear_building(self.super_period, self.super_damping)
        if self.isolator_model != "linear":
            from floorslide.building.isolators import BilinearIsolator, FrictionPendulum
            from floorslide.building.nonlinear import NonlinearIsolatedBuilding

            params = {k: v for k, v in self.isolator if k != "model"}
            cls = BilinearIsolator if self.isolator_model == "bilinear" else FrictionPendulum
            layer = cls(period=self.period, damping=self.damping, **params)
            return NonlinearIsolatedBuilding(sup, self.base_mass_ratio, layer)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ModelWarning)
            return IsolatedBuilding(sup, self.base_mass_ratio, self.period, self.damping)

    def build_plane(self):
        """The building in the plane: :meth:`build` when it is the same both ways, else a
        :class:`~floorslide.building.directions.BuildingPair` of the models along the two
        horizontal components (a linear building)."""
        first = self.build()
        if not self.two_way:
            return first
        from floorslide.building.directions import BuildingPair
        from floorslide.building.model import IsolatedBuilding
        from floorslide.errors import ModelWarning

        def pick(v, default):
            return default if math.isnan(v) else v

        if self.kind == "fixed":
            second = self._shear_building(
                pick(self.period_h2, self.period), pick(self.damping_h2, self.damping)
            )
        else:
            sup = self._shear_building(
                pick(self.super_period_h2, self.super_period),
                pick(self.super_damping_h2, self.super_damping),
            )
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ModelWarning)
                second = IsolatedBuilding(
                    sup,
                    self.base_mass_ratio,
                    pick(self.period_h2, self.period),
                    pick(self.damping_h2, self.damping),
                )
        return BuildingPair(first, second)


@dataclass(frozen=True)
class ContentSpec:
    """Equipment: friction values (a list sweeps) on chosen floors."""

    id: str
    floors: Any  # tuple of ints (and "roof": [1, 3, "roof"]), "all" or "roof"
    mu: tuple[float, ...]
    mu_s: tuple[float, ...] | None = None
    width: float | None = None
    height: float | None = None
    model: str = "rigid"
    frequency: float | None = None
    damping: float = 0.02
    mass_ratio: float = 1.0
    vertical: bool = False
    direction: str = "both"
    restitution: float | None = None  # rocking: None = Housner's 1 − 1.5 sin²α
    rocking: str = "exact"  # rocking method: "exact" (linearised) or "nonlinear"
    allowable: tuple[float, ...] = ()
    """Allowable displacements (m, increasing; e.g. the gap to a wall): the tables give the
    fraction of records whose peak slide exceeds each (docs/design.md §10e)."""
    floor_mass_ratio: float | None = None
    """Heavy equipment: the block's mass over its floor's (in (0, 1)); with `coupled` it is
    integrated with the building (:func:`floorslide.slide_coupled`, docs/design.md §10f)."""
    coupled: bool = True
    """With a `floor_mass_ratio`: whether the block acts back on its floor (False: decoupled,
    warned about above :data:`DECOUPLING_LIMIT`)."""

    def floors_of(self, stories: int) -> tuple[int, ...]:
        """The floors of a building with `stories` storeys this content stands on."""
        return _floors(self.floors, stories)


@dataclass(frozen=True)
class SpectraSpec:
    """Floor response spectra to compute."""

    floors: Any
    damping: tuple[float, ...]
    periods: tuple[float, ...]
    broadening: float = 0.0

    def floors_of(self, stories: int) -> tuple[int, ...]:
        return _floors(self.floors, stories)


@dataclass(frozen=True)
class Scene:
    """A validated scene."""

    name: str
    path: str
    text: str
    records: tuple[RecordSetSpec, ...]
    processing: dict
    buildings: tuple[BuildingSpec, ...]
    contents: tuple[ContentSpec, ...]
    spectra: SpectraSpec | None
    report: dict
    warnings: tuple[str, ...] = ()
    """Values that are valid but almost surely a mistake (``key.path: message``), shown by the
    dry run; e.g. an isolation period not above the superstructure's fixed-base period."""
    qa: str = "warn"
    """``[scene] qa``: what a record whose quality checks trip does (``"warn"``: it runs and its
    flags are stored and listed; ``"reject"``: it is skipped and reported, the others run)."""


def _floors(spec, stories: int) -> tuple[int, ...]:
    """The floors `spec` names in a building with `stories` storeys: ``"all"``, ``"roof"``, or
    a list of floor numbers that may hold ``"roof"`` (``[1, 3, "roof"]``), each floor once."""
    if spec == "all":
        return tuple(range(stories + 1))
    if spec == "roof":
        return (stories,)
    return tuple(sorted(set(stories if f == "roof" else int(f) for f in spec)))


class _Checker:
    """Collects problems with their key paths."""

    def __init__(self):
        self.problems: list[str] = []
        self.warnings: list[str] = []

    def add(self, where: str, message: str) -> None:
        self.problems.append(f"{where}: {message}")

    def warn(self, where: str, message: str) -> None:
        """A valid value that is almost surely a mistake: reported, not refused."""
        self.warnings.append(f"{where}: {message}")

    def keys(self, table: dict, allowed: set, where: str) -> None:
        for key in table:
            if key not in allowed:
                self.add(
                    f"{where}.{key}" if where else key,
                    f"unknown key; expected one of {', '.join(sorted(allowed))}",
                )

    def number(
        self, value, where, *, lo=None, hi=None, lo_open=False, hi_open=False, integer=False
    ):
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            self.add(where, f"must be a {'whole ' if integer else ''}number, got {value!r}")
            return None
        if integer and int(value) != value:
            self.add(where, f"must be a whole number, got {value!r}")
            return None
        bad = (lo is not None and (value <= lo if lo_open else value < lo)) or (
            hi is not None and (value >= hi if hi_open else value > hi)
        )
        if bad:
            lo_s = "" if lo is None else f"{'>' if lo_open else '≥'} {lo:g}"
            hi_s = "" if hi is None else f"{'<' if hi_open else '≤'} {hi:g}"
            self.add(where, f"must be {' and '.join(s for s in (lo_s, hi_s) if s)}, got {value!r}")
            return None
        return int(value) if integer else float(value)

    def numbers(self, value, where, **kw) -> tuple[float, ...]:
        """A number or a non-empty list of numbers (a sweep)."""
        items = value if isinstance(value, list) else [value]
        if not items:
            self.add(where, "must not be an empty list")
            return ()
        if len(items) > MAX_LIST:
            self.add(where, f"at most {MAX_LIST} values, got {len(items)}")
            return ()
        out = []
        for i, v in enumerate(items):
            got = self.number(v, f"{where}[{i}]" if isinstance(value, list) else where, **kw)
            if got is not None:
                out.append(got)
        return tuple(out) if len(out) == len(items) else ()

    def string(self, value, where) -> str | None:
        if not isinstance(value, str) or not value:
            self.add(where, f"must be a non-empty string, got {value!r}")
            return None
        return value

    def ident(self, value, where) -> str | None:
        """An id of a record set, building or content (:func:`id_problem`)."""
        problem = id_problem(value)
        if problem is not None:
            self.add(where, problem)
            return None
        return value


def name_problem(name: str) -> str | None:
    """Why `name` cannot be the name of a group of the result file (None if it can).

    HDF5 separates a path's groups with ``/`` and reads ``.`` as the group itself; a name
    with a NUL is cut short by the C library, and control characters do not survive the
    round trip through the file's text and the tables. Generated names (building variants
    ``iso@T=2.5,xi=0.1``, scaled sets ``set@0.3g``) obey this rule too.
    """
    if not name:
        return "must not be empty"
    if name in (".", ".."):
        return f"must not be {name!r} (HDF5 reads it as a folder)"
    if "/" in name:
        return "must not contain '/' (it separates the groups of the result file)"
    bad = next((ch for ch in name if not ch.isprintable()), None)
    if bad is not None:
        return f"must not contain control or invisible characters (got {bad!r})"
    return None


def id_problem(value: object) -> str | None:
    """Why `value` is not a valid id of a record set, building or content (None if it is).

    The one rule for every id a scene names (:data:`ID_RULE`): an id becomes the name of a
    group in the result file (:func:`name_problem`), is written with a variant's tags after
    ``@`` and is compared as ``A:B``, and is matched after stripping spaces. Unicode letters
    are fine (``Schrank``, ``機器``).
    """
    if not isinstance(value, str) or not value:
        return f"must be a non-empty string, got {value!r}; {ID_RULE}"
    problem = name_problem(value)
    if problem is None:
        reserved = [ch for ch in ID_RESERVED if ch in value]
        if reserved:
            problem = f"must not contain {' or '.join(map(repr, reserved))}"
        elif value != value.strip():
            problem = "must not begin or end with a space"
        elif len(value) > ID_MAX_CHARS:
            problem = f"must be at most {ID_MAX_CHARS} characters, got {len(value)}"
    if problem is None:
        return None
    shown = value if len(value) <= 40 else value[:40] + "…"
    return f"{shown!r} {problem}; {ID_RULE}"


def parse_comparison(spec: object) -> tuple[str, str]:
    """``"A:B"`` → ``("A", "B")``: the comparison of building A with building B (ids of
    buildings or of their variants), as ``[report] compare`` and ``--compare`` give it.

    Raises
    ------
    ValueError
        Not two non-empty building ids separated by one colon, or one building twice (a
        ratio of a building to itself is 1 by construction).
    """
    parts = spec.split(":") if isinstance(spec, str) else []
    if len(parts) != 2 or not all(p.strip() for p in parts):
        raise ValueError(f"expected A:B with two building ids, e.g. isolated:fixed, got {spec!r}")
    a, b = parts[0].strip(), parts[1].strip()
    if a == b:
        raise ValueError(f"{spec!r} compares building {a!r} with itself; give two buildings")
    return a, b


def _fmt(x: float) -> str:
    return f"{x:g}"


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file (all problems reported at once)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")  # a byte-order mark (Notepad) is skipped
    except FileNotFoundError:
        raise SceneError("no such scene file", str(path)) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"cannot read the scene file: {exc}", str(path)) from None
    return parse_scene(text, path)


def parse_scene(text: str, path: str | Path = "scene.toml") -> Scene:
    """Validate scene `text`; relative record paths are relative to `path`'s folder."""
    path = Path(path)
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"not valid TOML: {exc}", str(path)) from None
    ck = _Checker()
    ck.keys(doc, TOP_KEYS, "")
    base = path.parent
    name = path.stem
    qa = "warn"
    if "scene" in doc:
        if not isinstance(doc["scene"], dict):
            ck.add("scene", "must be a table")
        else:
            ck.keys(doc["scene"], {"name", "qa"}, "scene")
            if "name" in doc["scene"]:
                name = ck.string(doc["scene"]["name"], "scene.name") or name
            if "qa" in doc["scene"]:
                value = doc["scene"]["qa"]
                if value in QA_ACTIONS:
                    qa = value
                else:
                    ck.add(
                        "scene.qa",
                        f"{value!r}: expected one of {', '.join(map(repr, QA_ACTIONS))} (what "
                        "to do with a record whose quality checks trip)",
                    )
    records, record_ids = _records(doc.get("records"), ck, base)
    processing = _processing(doc.get("processing", {}), ck)
    buildings, building_ids = _buildings(doc.get("buildings"), ck)
    stories = {b.stories for b in buildings}
    contents = _contents(doc.get("contents", []), ck, stories)
    spectra = _spectra(doc.get("spectra"), ck, stories)
    report = _report(
        doc.get("report", {}), ck, building_ids, buildings, record_ids, spectra=spectra
    )
    # a lead-rubber layer does not feel the vertical (its blocks do: they run); a pendulum's
    # friction and restoring force scale with it, which fs.slide(..., vertical=) integrates but a
    # study (one building motion for all its contents) does not yet
    pendulums = [b.id for b in buildings if b.isolator_model == "friction_pendulum"]
    if pendulums:
        for i, c in enumerate(contents):
            if c.vertical:
                ck.add(
                    f"contents[{i}].vertical",
                    f"vertical shaking on a building on friction pendulums ({pendulums[0]}) is "
                    "not available in studies yet (fs.slide(..., vertical=, building=) runs it; "
                    "blocks without it, and on lead-rubber with it, run)",
                )
    _heavy_equipment(contents, buildings, records, ck)
    pair_sets = [r.set for r in records if r.pairs]
    if pair_sets:
        for i, c in enumerate(contents):
            what = (
                ("mu", "the 2-DOF sliding oscillator in the plane needs mu > 0")
                if c.model == "oscillator" and min(c.mu, default=1.0) <= 0.0
                else ("direction", "one-way sliding is 1-D")
                if c.direction != "both"
                else None
            )
            if what:
                ck.add(
                    f"contents[{i}].{what[0]}",
                    f"{what[1]}; the record set {pair_sets[0]!r} is a set of pairs (two "
                    "horizontal components: rigid blocks slide in the plane)",
                )
    if not contents and spectra is None:
        ck.add("contents", "the scene asks for nothing: give [[contents]] or [spectra]")
    if ck.problems:
        raise SceneError(ck.problems, str(path))
    return Scene(
        name,
        str(path),
        text,
        records,
        processing,
        buildings,
        contents,
        spectra,
        report,
        warnings=tuple(ck.warnings),
        qa=qa,
    )


def record_id_of(path: str | Path) -> str:
    """The record id of a record file: its name without the last extension (as the planner
    names records, and ``[report] history_record`` refers to them)."""
    return Path(path).stem


def _catalog_ids(
    catalog: str, where: dict, w: str, ck: _Checker, pairs: bool = False
) -> list[str] | None:
    """Record ids of the catalog rows `where` selects, or None when the catalog cannot be read
    (a problem: a malformed catalog, duplicate rows ...). `where` must name columns of the
    catalog, each of its values must occur in its column (a value that matches no row is a
    typo, also inside a list), and together they must select a row."""
    from floorslide.errors import RecordError
    from floorslide.records.catalog import load_catalog

    try:
        rows = load_catalog(catalog, components=pairs)
        entries = load_catalog(catalog, where=where or None, components=pairs) if where else rows
        if pairs:
            from floorslide.records.pairs import pair_rows

            chosen = pair_rows(catalog, where or None)
            ids = [row["id"] for row in chosen]
            if where and not chosen:
                entries = []
    except RecordError as exc:
        if exc.message.startswith("where: "):
            ck.add(f"{w}.where", exc.message.removeprefix("where: "))
        else:
            ck.add(f"{w}.catalog", str(exc))
        return None
    typos = False
    for key, wanted in where.items():
        values = wanted if isinstance(wanted, list) else [wanted]
        present = {e.row.get(key.lower(), "").strip() for e in rows}
        for j, value in enumerate(values):
            if str(value).strip() not in present:
                typos = True
                shown = sorted(present)
                listing = ", ".join(map(repr, shown[:8])) + (" …" if len(shown) > 8 else "")
                key_path = f"{w}.where.{key}" + (f"[{j}]" if isinstance(wanted, list) else "")
                ck.add(key_path, f"no row has {key} = {value!r} (values: {listing})")
    if not entries and not typos:
        ck.add(f"{w}.where" if where else f"{w}.catalog", f"selects no row of {catalog}")
    if pairs:
        _unique_ids(ids, [f"{r['h1'].path}+{r['h2'].path}" for r in chosen], f"{w}.catalog", ck)
        return ids
    ids = [record_id_of(e.path) for e in entries]
    _unique_ids(ids, [str(e.path) for e in entries], f"{w}.catalog", ck)
    return ids


def _where_values(where: dict, w: str, ck: _Checker) -> dict:
    """``where``: each value a string, number or boolean, or a non-empty list of them."""
    ok = {}
    for key, value in where.items():
        items = value if isinstance(value, list) else [value]
        if not items or not all(isinstance(v, str | int | float | bool) for v in items):
            ck.add(
                f"{w}.where.{key}",
                f"must be a value or a list of values to match, got {value!r}",
            )
            continue
        ok[key] = value
    return ok


def _each_file_once(files: list[str]) -> list[str]:
    """Globs are sets of files: overlapping ones (or two spellings of a path) name each file
    once, in the order first named."""
    seen: set[Path] = set()
    out = []
    for f in files:
        resolved = Path(f).resolve()
        if resolved not in seen:
            seen.add(resolved)
            out.append(f)
    return out


def _unique_ids(ids: list[str], paths: list[str], key: str, ck: _Checker) -> None:
    """Two records of one set with the same id (file name without extension) would be merged
    or counted twice in the tables: a problem naming both."""
    first: dict[str, str] = {}
    for rid, path in zip(ids, paths, strict=True):
        if rid in first and first[rid] != path:
            ck.add(
                key,
                f"two records named {rid!r} in one set ({first[rid]}, {path}); a record id "
                "(the file name without extension) must be unique within a set",
            )
            return
        first.setdefault(rid, path)


def _records(value, ck: _Checker, base: Path) -> tuple[tuple[RecordSetSpec, ...], list[str] | None]:
    """The record sets, and the ids of their records (None when some set's records are not
    known before reading, so that a name cannot be checked)."""
    if value is None:
        ck.add("records", "missing: give at least one [[records]] set")
        return (), None
    if not isinstance(value, list) or not value:
        ck.add("records", "must be a list of tables ([[records]])")
        return (), None
    out, names = [], set()
    ids: list[str] | None = []
    for i, r in enumerate(value):
        w = f"records[{i}]"
        if not isinstance(r, dict):
            ck.add(w, "must be a table")
            continue
        ck.keys(r, RECORD_KEYS, w)
        name = ck.ident(r.get("set"), f"{w}.set") if "set" in r else None
        if "set" not in r:
            ck.add(f"{w}.set", "missing: name the record set")
        elif name in names:
            ck.add(f"{w}.set", f"duplicate set name {name!r}")
        names.add(name)
        has_files, has_cat = "files" in r, "catalog" in r
        if has_files == has_cat:
            ck.add(w, "give exactly one of files (globs) or catalog (a CSV flatfile)")
        files: list[str] = []
        if has_files:
            pats = r["files"] if isinstance(r["files"], list) else [r["files"]]
            for j, pat in enumerate(pats):
                if not isinstance(pat, str) or not pat:
                    ck.add(f"{w}.files[{j}]", f"must be a path or glob, got {pat!r}")
                    continue
                full = pat if Path(pat).is_absolute() else str(base / pat)
                hits = sorted(glob.glob(full, recursive=True))
                if not hits:
                    ck.add(f"{w}.files[{j}]", f"matches no file ({full})")
                files += [h for h in hits if Path(h).is_file()]
            files = _each_file_once(files)
            _unique_ids([record_id_of(f) for f in files], files, f"{w}.files", ck)
        catalog = None
        if has_cat:
            cat = ck.string(r["catalog"], f"{w}.catalog")
            if cat:
                catalog = cat if Path(cat).is_absolute() else str(base / cat)
                if not Path(catalog).is_file():
                    ck.add(f"{w}.catalog", f"no such catalog file ({catalog})")
        where = r.get("where", {})
        if "where" in r and not has_cat:
            ck.add(f"{w}.where", "only applies to a catalog")
        if not isinstance(where, dict):
            ck.add(f"{w}.where", "must be a table of column = value")
            where = {}
        where = _where_values(where, w, ck)
        pairs = False
        if catalog and Path(catalog).is_file():
            from floorslide.records.pairs import is_pair_catalog

            pairs = is_pair_catalog(catalog)
            for key in ("component", "vertical_component"):
                if pairs and key in r:
                    ck.add(
                        f"{w}.{key}",
                        "a catalog of components (file_h1, file_h2, file_v) names each "
                        "component's file; this key is for multi-trace files",
                    )
        if catalog:
            got = _catalog_ids(catalog, where, w, ck, pairs) if Path(catalog).is_file() else None
            ids = None if got is None or ids is None else ids + got
        elif ids is not None:
            ids += [record_id_of(f) for f in files]
        scale = (
            ck.numbers(r["scale_pga"], f"{w}.scale_pga", lo=0, lo_open=True, hi=MAX_SCALE_PGA)
            if "scale_pga" in r
            else ()
        )
        target_scale = _scale(r["scale"], f"{w}.scale", ck, base) if "scale" in r else None
        if "scale" in r and "scale_pga" in r:
            ck.add(f"{w}.scale", "give scale (to a target spectrum) or scale_pga, not both")
        if target_scale is not None and len(target_scale.levels) > 1:
            n_known = None if catalog else len(files)
            if catalog and got is not None:
                n_known = len(got)
            if n_known is not None and n_known < 2:
                ck.add(
                    f"{w}.scale.levels",
                    f"stripes need at least 2 records each (a fragility fit); the set has "
                    f"{n_known}",
                )
        dt = ck.number(r["dt"], f"{w}.dt", lo=0, lo_open=True) if "dt" in r else None
        opts = {}
        for key in ("format", "units", "component", "vertical_component"):
            if key in r:
                opts[key] = ck.string(r[key], f"{w}.{key}")
        if "units" in r and isinstance(r["units"], str):
            from floorslide.errors import UnitsError
            from floorslide.records.units import canonical_units

            try:
                canonical_units(r["units"])
            except UnitsError as exc:
                ck.add(f"{w}.units", exc.message)
        out.append(
            RecordSetSpec(
                set=name or f"set{i}",
                files=tuple(dict.fromkeys(files)),
                catalog=catalog,
                where=dict(where),
                scale_pga=scale,
                scale=target_scale,
                dt=dt,
                pairs=pairs,
                **opts,
            )
        )
    return tuple(out), ids


def _target_csv(path: Path, where: str, ck: _Checker):
    """A target spectrum from a CSV of ``T, S_a`` rows
    (:func:`~floorslide.practice.target.read_target_csv`), or None with the problem added."""
    from floorslide.errors import ModelError
    from floorslide.practice.target import read_target_csv

    try:
        return read_target_csv(path)
    except ModelError as exc:
        ck.add(where, exc.message)
        return None


def _increasing_pair(value, where: str, ck: _Checker, what: str) -> tuple[float, float] | None:
    """Two numbers > 0, the second above the first, or None with the problem added."""
    if not (isinstance(value, list) and len(value) == 2):
        ck.add(where, f"must be {what}, got {value!r}")
        return None
    lo = ck.number(value[0], f"{where}[0]", lo=0, lo_open=True)
    hi = ck.number(value[1], f"{where}[1]", lo=0, lo_open=True)
    if lo is None or hi is None:
        return None
    if hi <= lo:
        ck.add(where, f"must increase: [{lo:g}, {hi:g}]")
        return None
    return lo, hi


def _scale_range(rng: tuple[float, float], where: str, ck: _Checker) -> None:
    """The records' spectra of a ``scale`` are computed over `rng` (``0.2 T … 2 T`` about a
    ``period``): within what a spectrum takes (:data:`floorslide.spectra.core.MAX_PERIOD`;
    the lower bound, ``dt/1000``, is checked by the planner once the records' dt is known)."""
    from floorslide.spectra.core import MAX_PERIOD

    if rng[1] > MAX_PERIOD:
        how = "" if where.endswith("periods") else " (the fit range 0.2·T–2·T)"
        ck.add(
            where,
            f"the records' spectra would reach {rng[1]:g} s{how}, above {MAX_PERIOD:g} s, "
            "beyond any structure",
        )


def _scale(value, w: str, ck: _Checker, base: Path) -> ScaleSpec | None:
    """A record set's ``scale`` table (docs/design.md §10e), or None with the problems added."""
    from floorslide.errors import ModelError
    from floorslide.practice.target import FACTOR_LIMITS, TargetSpectrum

    if not isinstance(value, dict):
        ck.add(w, "must be a table: { target = ..., periods = [T_lo, T_hi] or period = T }")
        return None
    ck.keys(value, SCALE_KEYS, w)
    n0 = len(ck.problems)
    target = None
    source = ""
    t = value.get("target")
    if t is None:
        ck.add(f"{w}.target", "missing: { sds = , sd1 = , tl = } (g, g, s) or a CSV of T, S_a")
    elif isinstance(t, dict):
        ck.keys(t, TARGET_KEYS, f"{w}.target")
        got = {}
        for key in ("sds", "sd1", "tl"):
            if key not in t:
                ck.add(f"{w}.target.{key}", "missing")
            else:
                got[key] = ck.number(t[key], f"{w}.target.{key}", lo=0, lo_open=True)
        if len(got) == 3 and None not in got.values():
            try:
                target = TargetSpectrum.two_point(got["sds"], got["sd1"], got["tl"])
                source = f"two-point: S_DS = {got['sds']:g} g, S_D1 = {got['sd1']:g} g, " + (
                    f"T_L = {got['tl']:g} s"
                )
            except ModelError as exc:
                ck.add(f"{w}.target.{exc.where or 'tl'}", exc.message)
    elif isinstance(t, str) and t:
        path = Path(t) if Path(t).is_absolute() else base / t
        if not path.is_file():
            ck.add(f"{w}.target", f"no such target file ({path})")
        else:
            target = _target_csv(path, f"{w}.target", ck)
            source = str(path)
    else:
        ck.add(f"{w}.target", f"must be {{ sds, sd1, tl }} or a CSV path, got {t!r}")
    period = None
    if "period" in value:
        period = ck.number(value["period"], f"{w}.period", lo=0, lo_open=True)
    rng = None
    if "periods" in value:
        rng = _increasing_pair(value["periods"], f"{w}.periods", ck, "a range [T_lo, T_hi] (s)")
    elif period is not None:
        rng = (0.2 * period, 2.0 * period)  # ASCE 7-22 §16.2.1's range about the period
    elif "period" not in value:
        ck.add(w, "give periods = [T_lo, T_hi] (fit over a range) or period = T (match at T)")
    if rng is not None and period is not None and not (rng[0] <= period <= rng[1]):
        ck.add(f"{w}.period", f"{period:g} s lies outside periods [{rng[0]:g}, {rng[1]:g}]")
    elif rng is not None:
        _scale_range(rng, f"{w}.periods" if "periods" in value else f"{w}.period", ck)
    if target is not None and rng is not None and not target.params:
        lo_t, hi_t = float(target.periods[0]), float(target.periods[-1])
        if rng[0] < lo_t or rng[1] > hi_t:
            key = f"{w}.periods" if "periods" in value else f"{w}.period"
            ck.add(
                key,
                f"the range {rng[0]:g}–{rng[1]:g} s reaches outside the target's "
                f"{lo_t:g}–{hi_t:g} s ({Path(source).name})",
            )
    damping = 0.05
    if "damping" in value:
        damping = ck.number(value["damping"], f"{w}.damping", lo=0, hi=1, hi_open=True)
    limits = FACTOR_LIMITS
    if "limits" in value:
        limits = (
            _increasing_pair(value["limits"], f"{w}.limits", ck, "[low, high] scale factors")
            or limits
        )
    levels: tuple[float, ...] = ()
    if "levels" in value:
        levels = ck.numbers(value["levels"], f"{w}.levels", lo=0, lo_open=True)
        if levels and len(set(levels)) != len(levels):
            ck.add(f"{w}.levels", "must not repeat a level")
        levels = tuple(sorted(levels))
    points = 40
    if "points" in value:
        points = ck.number(value["points"], f"{w}.points", lo=2, hi=1000, integer=True)
    match = value.get("match_suite", False)
    if not isinstance(match, bool):
        ck.add(f"{w}.match_suite", f"must be true or false, got {match!r}")
    if len(ck.problems) > n0 or target is None or rng is None:
        return None
    return ScaleSpec(
        target=target,
        target_source=source,
        period_range=rng,
        period=period,
        damping=float(damping),
        limits=(float(limits[0]), float(limits[1])),
        levels=levels,
        points=int(points),
        match_suite=bool(match),
    )


def _processing(value, ck: _Checker) -> dict:
    if not isinstance(value, dict):
        ck.add("processing", "must be a table")
        return {}
    ck.keys(value, PROCESSING_KEYS, "processing")
    for key in ("highpass", "lowpass", "resample", "scale_pga", "scale"):
        if key in value:
            ck.number(value[key], f"processing.{key}", lo=0, lo_open=True)
    if "taper" in value:
        ck.number(value["taper"], "processing.taper", lo=0, hi=0.5)
    if "highpass" in value and "lowpass" in value:
        hp, lp = value["highpass"], value["lowpass"]
        if isinstance(hp, int | float) and isinstance(lp, int | float) and hp >= lp:
            ck.add("processing.lowpass", f"must be above highpass ({hp} Hz), got {lp}")
    if "detrend" in value and value["detrend"] not in (
        "linear",
        "constant",
        "demean",
        "polynomial",
        True,
        False,
    ):
        ck.add(
            "processing.detrend",
            f"must be linear, constant or polynomial, got {value['detrend']!r}",
        )
    return {k: v for k, v in value.items() if k in PROCESSING_KEYS}


def _storey_values(value, where: str, ck: _Checker, unit: str) -> tuple[float, ...] | None:
    """A per-storey quantity: a number > 0 (every storey the same) as a 1-tuple, or a list of
    numbers > 0 (one per storey, from the first suspended floor up); None when invalid."""
    if isinstance(value, list):
        if not value:
            ck.add(where, f"must list one value per storey ({unit}), got an empty list")
            return None
        if len(value) > MAX_STORIES:
            ck.add(where, f"at most {MAX_STORIES} storeys, got {len(value)}")
            return None
        got = [ck.number(v, f"{where}[{j}]", lo=0, lo_open=True) for j, v in enumerate(value)]
        return None if None in got else tuple(got)
    got = ck.number(value, where, lo=0, lo_open=True)
    return None if got is None else (got,)


def _fixed_model(b: dict, w: str, ck: _Checker):
    """Storeys, per-storey masses and stiffnesses, periods and profile of a fixed building.

    Returns ``(stories, masses, stiffnesses, periods, profile)`` or None when invalid (the
    problems are reported). ``stiffnesses`` is ``()`` when the building is scaled to ``period``;
    else ``periods`` holds its computed fundamental period.
    """
    ok = True
    stories = None
    if "stories" in b:
        stories = ck.number(b["stories"], f"{w}.stories", lo=1, hi=MAX_STORIES, integer=True)
        ok = stories is not None
    mass = _storey_values(b.get("mass", 1.0), f"{w}.mass", ck, "kg")
    stiff = _storey_values(b["stiffness"], f"{w}.stiffness", ck, "N/m") if "stiffness" in b else ()
    ok = ok and mass is not None and stiff is not None
    lists = {key: len(b[key]) for key in ("mass", "stiffness") if isinstance(b.get(key), list)}
    if len(set(lists.values())) > 1:
        ck.add(
            f"{w}.stiffness",
            f"one value per storey: {lists['stiffness']} stiffnesses for {lists['mass']} masses",
        )
        ok = False
    elif lists:
        n = next(iter(lists.values()))
        if stories is not None and stories != n:
            key = next(iter(lists))
            ck.add(f"{w}.{key}", f"{n} values (one per storey) for stories = {stories}")
            ok = False
        stories = n
    if stories is None:
        stories = 1
    periods: tuple[float, ...] = ()
    if "period" in b and "stiffness" in b:
        ck.add(
            f"{w}.stiffness",
            "give period (stiffnesses scaled to it) or stiffness (storey by storey), not both",
        )
        ok = False
    elif "period" in b:
        periods = ck.numbers(b["period"], f"{w}.period", lo=0, lo_open=True)
        ok = ok and bool(periods)
    elif "stiffness" not in b:
        ck.add(f"{w}.period", "missing: the fundamental period, s (or storey stiffnesses)")
        ok = False
    profile = b.get("profile", "uniform")
    if profile not in ("uniform", "shear"):
        ck.add(f"{w}.profile", f"must be 'uniform' or 'shear', got {profile!r}")
        ok = False
    elif "profile" in b and "stiffness" in b:
        ck.add(f"{w}.profile", "only applies with period (storey stiffnesses are given)")
        ok = False
    if not ok:
        return None
    masses = tuple(np.broadcast_to(mass, (stories,)).tolist())
    stiffnesses = tuple(np.broadcast_to(stiff, (stories,)).tolist()) if stiff else ()
    if stiffnesses:
        from floorslide.building.model import ShearBuilding
        from floorslide.errors import ModelError

        try:
            periods = (float(ShearBuilding(masses, stiffnesses, 0.0).periods[0]),)
        except ModelError as exc:  # matrices beyond float64's range
            ck.add(f"{w}.stiffness", exc.message)
            return None
    return stories, masses, stiffnesses, periods, str(profile)


def _buildings(value, ck: _Checker) -> tuple[tuple[BuildingSpec, ...], set[str]]:
    """The building variants, and the id of every building declared — also of one with an
    invalid value, so that later names (superstructure, report.compare) are not reported again
    as unknown."""
    if value is None:
        ck.add("buildings", "missing: give at least one [[buildings]]")
        return (), set()
    if not isinstance(value, list) or not value:
        ck.add("buildings", "must be a list of tables ([[buildings]])")
        return (), set()
    fixed: dict[str, list[BuildingSpec]] = {}
    out: list[BuildingSpec] = []
    ids: set[str] = set()
    declared_fixed: set[str] = set()
    unknown_kind: set[str] = set()  # a superstructure of these is reported at its kind
    isolated = []
    for i, b in enumerate(value):
        w = f"buildings[{i}]"
        if not isinstance(b, dict):
            ck.add(w, "must be a table")
            continue
        bid = ck.ident(b.get("id"), f"{w}.id") if "id" in b else None
        # declared, even with an invalid id: names of it are not reported again as unknown
        named = b["id"] if isinstance(b.get("id"), str) and b["id"] else None
        if "id" not in b:
            ck.add(f"{w}.id", "missing: name the building")
        elif named in ids:
            ck.add(f"{w}.id", f"duplicate building id {named!r}")
        if named:
            ids.add(named)
        kind = b.get("kind")
        if kind not in ("fixed", "isolated"):
            ck.add(f"{w}.kind", f"must be 'fixed' or 'isolated', got {kind!r}")
            if named:
                unknown_kind.add(named)
            continue
        if kind == "isolated":
            ck.keys(b, ISOLATED_KEYS, w)
            isolated.append((i, b, bid))
            continue
        if named:
            declared_fixed.add(named)
        ck.keys(b, FIXED_KEYS, w)
        model = _fixed_model(b, w, ck)
        heights = _storey_heights(b, w, ck, model[0] if model else None)
        damps = ck.numbers(b.get("damping", 0.05), f"{w}.damping", lo=0, hi=1, hi_open=True)
        if model is None or not damps or not bid:
            continue
        stories, masses, stiffnesses, periods, profile = model
        p2, z2 = _direction_h2(b, w, ck, "stiffness" in b, nonlinear=False)
        variants = []
        for T, z in itertools.product(periods, damps):
            vid = bid
            tags = []
            if len(periods) > 1:
                tags.append(f"T={_fmt(T)}")
            if len(damps) > 1:
                tags.append(f"xi={_fmt(z)}")
            if tags:
                vid += "@" + ",".join(tags)
            variants.append(
                BuildingSpec(
                    vid,
                    bid,
                    "fixed",
                    stories,
                    T,
                    z,
                    masses[0],
                    profile,
                    masses=masses,
                    stiffnesses=stiffnesses,
                    period_h2=p2,
                    damping_h2=z2,
                    storey_heights=heights,
                )
            )
        fixed[bid] = variants
        out += variants
    from floorslide.building.model import isolation_period_warning

    for i, b, bid in isolated:
        w = f"buildings[{i}]"
        sup = b.get("superstructure")
        ratios = ck.numbers(
            b.get("base_mass_ratio", 1.0), f"{w}.base_mass_ratio", lo=0, lo_open=True
        )
        periods = (
            ck.numbers(b["period"], f"{w}.period", lo=0, lo_open=True) if "period" in b else ()
        )
        pendulum = _pendulum_period(b, w, ck, periods)
        if pendulum is not None:
            periods = (pendulum,)
        elif "period" not in b:
            ck.add(f"{w}.period", "missing: the isolation period, s")
        layers = _isolator(b.get("isolator"), f"{w}.isolator", ck)
        nonlinear = bool(layers) and dict(layers[0][0]).get("model", "linear") != "linear"
        damps = ck.numbers(
            b.get("damping", 0.0 if nonlinear else 0.1), f"{w}.damping", lo=0, hi=1, hi_open=True
        )
        p2, z2 = _direction_h2(b, w, ck, False, nonlinear=nonlinear)
        if isinstance(sup, str) and sup in unknown_kind:
            continue  # the superstructure's kind is invalid: reported there
        if not isinstance(sup, str) or sup not in declared_fixed:
            ck.add(f"{w}.superstructure", f"must be the id of a fixed building, got {sup!r}")
            continue
        if sup not in fixed:
            continue  # the superstructure is invalid: its problems are reported there
        if len(fixed[sup]) != 1:
            ck.add(
                f"{w}.superstructure",
                f"{sup!r} is swept; isolate a building with one period and damping",
            )
            continue
        s = fixed[sup][0]
        listed = isinstance(b.get("period"), list)
        for j, T in enumerate(periods):
            if T <= s.period:
                ck.warn(
                    f"{w}.period" + (f"[{j}]" if listed else ""),
                    isolation_period_warning(T, s.period, sup),
                )
        if not bid:
            continue
        for R, T, z, (layer, layer_tags) in itertools.product(
            ratios, periods, damps, layers or [((), [])]
        ):
            tags = []
            if len(ratios) > 1:
                tags.append(f"mb={_fmt(R)}")
            if len(periods) > 1:
                tags.append(f"T={_fmt(T)}")
            if len(damps) > 1:
                tags.append(f"xi={_fmt(z)}")
            tags += layer_tags
            vid = bid + ("@" + ",".join(tags) if tags else "")
            out.append(
                BuildingSpec(
                    vid,
                    bid,
                    "isolated",
                    s.stories,
                    T,
                    z,
                    s.mass,
                    s.profile,
                    sup,
                    s.period,
                    s.damping,
                    R,
                    masses=s.masses,
                    stiffnesses=s.stiffnesses,
                    isolator=layer,
                    period_h2=p2,
                    damping_h2=z2,
                    super_period_h2=s.period_h2,
                    super_damping_h2=s.damping_h2,
                    storey_heights=s.storey_heights,
                )
            )
    return tuple(out), ids


def _storey_heights(b: dict, w: str, ck: _Checker, stories: int | None) -> tuple[float, ...]:
    """``storey_heights`` of a fixed building (m, > 0; one number or one per storey), used for
    the code comparison's z/h; ``()`` when absent or invalid (reported)."""
    if "storey_heights" not in b:
        return ()
    got = _storey_values(b["storey_heights"], f"{w}.storey_heights", ck, "m")
    if got is None or stories is None:
        return ()
    if len(got) not in (1, stories):
        ck.add(
            f"{w}.storey_heights",
            f"{len(got)} heights (one per storey) for {stories} storeys",
        )
        return ()
    return tuple(np.broadcast_to(got, (stories,)).tolist())


def _direction_h2(b: dict, w: str, ck: _Checker, storeys_given: bool, nonlinear: bool):
    """``period_h2`` and ``damping_h2`` of a building (NaN when absent): its model along the
    second horizontal component of a pair, one value each."""
    out = []
    for key, hi in (("period_h2", None), ("damping_h2", 1)):
        if key not in b:
            out.append(math.nan)
            continue
        if isinstance(b[key], list):
            ck.add(f"{w}.{key}", "one value (the second direction is not swept)")
            out.append(math.nan)
            continue
        if nonlinear:
            ck.add(
                f"{w}.{key}",
                "a nonlinear isolation layer couples the two directions (it yields or slides "
                "under the resultant force): one model both ways",
            )
        elif key == "period_h2" and storeys_given:
            ck.add(f"{w}.{key}", "needs period (a building scaled to its period), not stiffness")
        lo_open = key == "period_h2"
        got = ck.number(b[key], f"{w}.{key}", lo=0, lo_open=lo_open, hi=hi, hi_open=hi is not None)
        out.append(math.nan if got is None else float(got))
    return tuple(out)


def _pendulum_period(b: dict, w: str, ck: _Checker, periods: tuple[float, ...]):
    """The period ``2π√(R/g)`` of a friction pendulum given by ``isolator.radius`` (None
    without one, or when invalid: the problem is reported). With ``period`` given too, both
    must agree (:func:`floorslide.building.spec.pendulum_period`)."""
    layer = b.get("isolator")
    if not isinstance(layer, dict) or "radius" not in layer:
        return None
    if layer.get("model") != "friction_pendulum":
        return None  # reported as an unknown key of the layer
    from floorslide.building.spec import pendulum_period
    from floorslide.errors import ModelError

    where = f"{w}.isolator.radius"
    radius = ck.number(layer["radius"], where, lo=0, lo_open=True)
    if radius is None:
        return None
    if "period" not in b:
        return pendulum_period(radius)
    if isinstance(b["period"], list) and len(b["period"]) > 1:
        ck.add(where, "a radius gives one pendulum period: do not sweep period with it")
        return None
    if not periods:
        return None  # the period is invalid: reported there
    try:
        return pendulum_period(radius, periods[0])
    except ModelError as exc:
        ck.add(where, exc.message)
        return None


def _isolator(value, where: str, ck: _Checker) -> list:
    """The variants of an ``isolator`` table: ``[(layer, tags)]`` with ``layer`` the
    :attr:`BuildingSpec.isolator` tuple and ``tags`` the swept values' id tags; ``[]`` for the
    linear isolator (no table, or ``model = "linear"``)."""
    if value is None:
        return []
    if not isinstance(value, dict):
        ck.add(where, 'must be a table, e.g. { model = "friction_pendulum", mu = 0.05 }')
        return []
    model = value.get("model")
    if not isinstance(model, str) or model not in ISOLATOR_KEYS:
        ck.add(
            f"{where}.model",
            f"must be one of {', '.join(map(repr, ISOLATOR_KEYS))}, got {model!r}",
        )
        return []
    ck.keys(value, ISOLATOR_KEYS[model], where)
    if model == "linear":
        return [((("model", "linear"),), [])]
    swept: dict[str, tuple[float, ...]] = {}
    fixed: dict[str, float] = {}
    for key in sorted(ISOLATOR_KEYS[model] - {"model"}):
        if key not in value:
            continue
        if key == "radius":
            continue  # the pendulum's period (_pendulum_period)
        if key in ISOLATOR_SWEEPS:
            vals = ck.numbers(value[key], f"{where}.{key}", lo=0, lo_open=key != "mu")
            if key == "mu":
                _warn_each(ck, value[key], vals, f"{where}.{key}", friction_warning)
            if vals:
                swept[key] = vals
        else:
            got = ck.number(value[key], f"{where}.{key}", lo=0, lo_open=True)
            if got is not None:
                fixed[key] = got
    need = {"bilinear": ("q_ratio",), "friction_pendulum": ("mu",)}[model]
    for key in need:
        if key not in value:
            ck.add(f"{where}.{key}", "missing")
    if model == "bilinear" and ("yield_disp" in value) == ("alpha" in value):
        ck.add(f"{where}.yield_disp", "give one of yield_disp and alpha")
    if model == "bilinear" and "alpha" in swept and max(swept["alpha"]) >= 1:
        ck.add(f"{where}.alpha", "alpha = k2/k1 must be < 1")
    if ck.problems and any(p.startswith(where) for p in ck.problems):
        return []
    keys = sorted(swept)
    out = []
    for combo in itertools.product(*(swept[k] for k in keys)):
        layer = (("model", model), *sorted(fixed.items()), *zip(keys, combo, strict=True))
        tags = [
            f"{ISOLATOR_SWEEPS[k]}={_fmt(v)}"
            for k, v in zip(keys, combo, strict=True)
            if len(swept[k]) > 1
        ]
        out.append((tuple(layer), tags))
    return out


def _warn_each(ck: _Checker, raw, values: tuple[float, ...], where: str, rule) -> None:
    """Warn (by key path, ``[j]`` for a list) about each value `rule` finds implausible."""
    for j, v in enumerate(values):
        message = rule(v)
        if message:
            ck.warn(f"{where}[{j}]" if isinstance(raw, list) else where, message)


def _floor_spec(value, where, ck: _Checker, stories: set[int]):
    if value in ("all", "roof"):
        return value
    items = value if isinstance(value, list) else [value]
    out = []
    for j, f in enumerate(items):
        if f == "roof" and isinstance(value, list):
            out.append("roof")
            continue
        if isinstance(f, str):
            ck.add(
                f"{where}[{j}]" if isinstance(value, list) else where,
                f"must be a floor number, 'roof' or 'all', got {f!r}",
            )
            continue
        got = ck.number(
            f, f"{where}[{j}]" if isinstance(value, list) else where, lo=0, integer=True
        )
        if got is None:
            continue
        for n in sorted(stories):
            if got > n:
                ck.add(
                    f"{where}",
                    f"floor {got} does not exist in a {n}-storey building (floors 0..{n})",
                )
                break
        out.append(got)
    if not items:
        ck.add(where, "must list at least one floor, or be 'all' or 'roof'")
    return tuple(out)


def _contents(value, ck: _Checker, stories: set[int]) -> tuple[ContentSpec, ...]:
    if not isinstance(value, list):
        ck.add("contents", "must be a list of tables ([[contents]])")
        return ()
    out, ids = [], set()
    for i, c in enumerate(value):
        w = f"contents[{i}]"
        if not isinstance(c, dict):
            ck.add(w, "must be a table")
            continue
        ck.keys(c, CONTENT_KEYS, w)
        cid = ck.ident(c.get("id"), f"{w}.id") if "id" in c else None
        if "id" not in c:
            ck.add(f"{w}.id", "missing: name the content")
        elif cid in ids:
            ck.add(f"{w}.id", f"duplicate content id {cid!r}")
        ids.add(cid)
        floors = _floor_spec(c.get("floors", "roof"), f"{w}.floors", ck, stories)
        if "mu" not in c:
            ck.add(f"{w}.mu", "missing: kinetic friction coefficient(s)")
        mu = ck.numbers(c.get("mu", []), f"{w}.mu", lo=0) if "mu" in c else ()
        _warn_each(ck, c.get("mu"), mu, f"{w}.mu", friction_warning)
        mu_s = None
        if "mu_s" in c:
            mu_s = ck.numbers(c["mu_s"], f"{w}.mu_s", lo=0)
            _warn_each(ck, c["mu_s"], mu_s, f"{w}.mu_s", friction_warning)
            if mu_s and len(mu_s) not in (1, len(mu)):
                ck.add(f"{w}.mu_s", f"must be one value or one per mu ({len(mu)}), got {len(mu_s)}")
            elif mu_s and len(mu_s) == 1:
                mu_s = mu_s * len(mu)
        width = height = None
        if ("width" in c) != ("height" in c):
            ck.add(w, "give both width and height (the rocking check), or neither")
        if "width" in c:
            width = ck.number(c["width"], f"{w}.width", lo=0, lo_open=True)
            height = ck.number(c.get("height"), f"{w}.height", lo=0, lo_open=True)
        restitution = None
        for key in ("restitution", "rocking"):
            if key in c and "width" not in c:
                ck.add(f"{w}.{key}", "applies to a rocking object: give width and height too")
        if "restitution" in c:
            restitution = ck.number(c["restitution"], f"{w}.restitution", lo=0, hi=1)
        elif width is not None and height is not None and width / height > 1.4142135:
            ck.add(
                f"{w}.restitution",
                "missing: Housner's 1 − 1.5 sin²α is negative for width/height > 1.414 "
                "(a squat block); give restitution in [0, 1]",
            )
        allowable: tuple[float, ...] = ()
        if "allowable" in c:
            allowable = ck.numbers(c["allowable"], f"{w}.allowable", lo=0, lo_open=True)
            _warn_each(ck, c["allowable"], allowable, f"{w}.allowable", allowable_warning)
            if allowable and len(set(allowable)) != len(allowable):
                ck.add(f"{w}.allowable", "must not repeat a displacement")
            allowable = tuple(sorted(allowable))
        rocking = c.get("rocking", "exact")
        if rocking not in ("exact", "nonlinear"):
            ck.add(f"{w}.rocking", f"must be 'exact' or 'nonlinear', got {rocking!r}")
        elif "rocking" in c and "width" in c:
            ck.warn(
                f"{w}.rocking",
                "no longer applies in a study: rocking objects are simulated as slide–rock "
                "blocks with the full equations (docs/design.md §10g); the key is ignored",
            )
        model = c.get("model", "rigid")
        freq = None
        damping, ratio = 0.02, 1.0
        if model not in ("rigid", "oscillator"):
            ck.add(f"{w}.model", f"must be 'rigid' or 'oscillator', got {model!r}")
        elif model == "oscillator":
            if "frequency" not in c:
                ck.add(
                    f"{w}.frequency", "missing: the clamped-base frequency of the oscillator, Hz"
                )
            else:
                freq = ck.number(c["frequency"], f"{w}.frequency", lo=0, lo_open=True)
            damping = ck.number(c.get("damping", 0.02), f"{w}.damping", lo=0, hi=1, hi_open=True)
            ratio = ck.number(c.get("mass_ratio", 1.0), f"{w}.mass_ratio", lo=0, lo_open=True)
        else:
            for key in ("frequency", "mass_ratio"):
                if key in c:
                    ck.add(f"{w}.{key}", "only applies to model = 'oscillator'")
        vertical = c.get("vertical", False)
        if not isinstance(vertical, bool):
            ck.add(f"{w}.vertical", f"must be true or false, got {vertical!r}")
        direction = c.get("direction", "both")
        if direction not in ("both", "positive", "negative"):
            ck.add(f"{w}.direction", f"must be both, positive or negative, got {direction!r}")
        if model == "oscillator":
            # not modelled for flexible equipment: never silently dropped
            if vertical is True:
                ck.add(f"{w}.vertical", "not modelled for the 2-DOF sliding oscillator yet")
            if direction != "both":
                ck.add(f"{w}.direction", "not modelled for the 2-DOF sliding oscillator yet")
        fmr, coupled = None, True
        if "floor_mass_ratio" in c:
            fmr = ck.number(
                c["floor_mass_ratio"], f"{w}.floor_mass_ratio", lo=0, lo_open=True, hi=1,
                hi_open=True,
            )  # fmt: skip
            if model != "rigid":
                ck.add(f"{w}.floor_mass_ratio", "applies to a rigid block (model = 'rigid')")
        if "coupled" in c:
            coupled = c["coupled"]
            if not isinstance(coupled, bool):
                ck.add(f"{w}.coupled", f"must be true or false, got {coupled!r}")
            elif "floor_mass_ratio" not in c:
                ck.add(f"{w}.coupled", "needs floor_mass_ratio (the block's mass over its floor's)")
        if fmr is not None and coupled is True:
            if vertical is True:
                ck.add(f"{w}.vertical", "heavy equipment coupled with its floor has no vertical")
            if direction != "both":
                ck.add(f"{w}.direction", "heavy equipment coupled with its floor slides both ways")
        out.append(
            ContentSpec(
                cid or f"content{i}",
                floors,
                mu,
                mu_s or None,
                width,
                height,
                str(model),
                freq,
                damping if damping is not None else 0.02,
                ratio if ratio is not None else 1.0,
                bool(vertical),
                str(direction),
                restitution,
                str(rocking),
                allowable,
                fmr,
                bool(coupled) if isinstance(coupled, bool) else True,
            )
        )
    return tuple(out)


def _heavy_equipment(contents, buildings, records, ck: _Checker) -> None:
    """Contents with a ``floor_mass_ratio``: coupled ones run on linear buildings and on
    nonlinear isolation, under single components only (one line by key path otherwise); a
    decoupled one heavier than :data:`DECOUPLING_LIMIT` of its floor is warned about."""
    pairs = [r.set for r in records if r.pairs]
    for i, c in enumerate(contents):
        if c.floor_mass_ratio is None:
            continue
        w = f"contents[{i}].floor_mass_ratio"
        if not c.coupled:
            kinds = sorted({b.kind for b in buildings if b.kind in DECOUPLING_LIMIT})
            over = [k for k in kinds if c.floor_mass_ratio > DECOUPLING_LIMIT[k]]
            if over:
                ck.warn(
                    w,
                    f"{c.floor_mass_ratio:g} of the floor's mass, run decoupled: above "
                    f"{DECOUPLING_LIMIT[over[0]]:g} on a {over[0]} building the decoupled peak "
                    "slide is more than 5 % off in the median (docs/design.md §10f); set "
                    "coupled = true",
                )
            continue
        if pairs:
            ck.add(
                w,
                "heavy equipment coupled with its floor is 1-D: the record set "
                f"{pairs[0]!r} is a set of pairs",
            )


def _spectra(value, ck: _Checker, stories: set[int]) -> SpectraSpec | None:
    if value is None:
        return None
    if not isinstance(value, dict):
        ck.add("spectra", "must be a table")
        return None
    ck.keys(value, SPECTRA_KEYS, "spectra")
    floors = _floor_spec(value.get("floors", "all"), "spectra.floors", ck, stories)
    damping = ck.numbers(value.get("damping", 0.05), "spectra.damping", lo=0, hi=1, hi_open=True)
    periods = value.get("periods", {"min": 0.02, "max": 5.0, "n": 100})
    grid: tuple[float, ...] = ()
    if isinstance(periods, dict):
        ck.keys(periods, {"min", "max", "n"}, "spectra.periods")
        lo = ck.number(periods.get("min"), "spectra.periods.min", lo=0, lo_open=True)
        hi = ck.number(periods.get("max"), "spectra.periods.max", lo=0, lo_open=True)
        n = ck.number(periods.get("n"), "spectra.periods.n", lo=2, hi=MAX_LIST, integer=True)
        if lo is not None and hi is not None and lo >= hi:
            ck.add("spectra.periods.max", f"must be above min ({lo:g} s)")
        elif None not in (lo, hi, n):
            grid = tuple(np.geomspace(lo, hi, n).tolist())
    else:
        grid = ck.numbers(periods, "spectra.periods", lo=0)
    _spectrum_size(grid, damping, ck)
    broadening = ck.number(
        value.get("broadening", 0.0), "spectra.broadening", lo=0, hi=1, hi_open=True
    )
    return SpectraSpec(floors, damping, grid, broadening or 0.0)


def _spectrum_size(grid: tuple[float, ...], damping: tuple[float, ...], ck: _Checker) -> None:
    """The limits of one spectrum (:mod:`floorslide.spectra.core`): no period beyond
    ``MAX_PERIOD``, at most ``MAX_OSCILLATORS`` periods × damping ratios. (Periods below
    ``dt/1000`` are refused by the planner, which knows the records' dt.)"""
    from floorslide.spectra.core import MAX_OSCILLATORS, MAX_PERIOD

    if grid and max(grid) > MAX_PERIOD:
        ck.add(
            "spectra.periods", f"{max(grid):g} s is above {MAX_PERIOD:g} s, beyond any structure"
        )
    if len(grid) * len(damping) > MAX_OSCILLATORS:
        ck.add(
            "spectra.damping",
            f"{len(grid)} periods x {len(damping)} damping ratios = {len(grid) * len(damping)} "
            f"oscillators per floor: at most {MAX_OSCILLATORS}",
        )


def _report(
    value,
    ck: _Checker,
    building_ids: set[str],
    buildings: tuple[BuildingSpec, ...],
    record_ids: list[str] | None,
    spectra: SpectraSpec | None = None,
) -> dict:
    """``[report]``: every name it holds is checked against the scene — buildings of
    ``compare`` (a base id or a variant id), ``history_record`` (a record of the sets, when
    they are known before reading), ``damping`` (one of the spectra's)."""
    if not isinstance(value, dict):
        ck.add("report", "must be a table")
        return {}
    ck.keys(value, REPORT_KEYS, "report")
    if "periods" in value:
        ck.numbers(value["periods"], "report.periods", lo=0)
    if "damping" in value:
        z = ck.number(value["damping"], "report.damping", lo=0, hi=1, hi_open=True)
        if z is not None and spectra is not None and spectra.damping:
            if not any(abs(z - d) <= 1e-9 for d in spectra.damping):
                listing = ", ".join(f"{d:g}" for d in spectra.damping)
                ck.add("report.damping", f"{z:g} is not among spectra.damping ({listing})")
    comps = value.get("compare", [])
    if not isinstance(comps, list):
        comps = [comps]
    valid_bases = {b.base for b in buildings}
    variants = {b.id for b in buildings}
    for j, comp in enumerate(comps):
        try:
            parts = parse_comparison(comp)
        except ValueError as exc:
            ck.add(f"report.compare[{j}]", str(exc))
            continue
        for p in parts:
            base_id = p.split("@")[0]
            if base_id not in building_ids:
                known = ", ".join(sorted(building_ids)) or "none"
                ck.add(f"report.compare[{j}]", f"unknown building {p!r} (buildings: {known})")
            elif "@" in p and base_id in valid_bases and p not in variants:
                known = ", ".join(sorted(v for v in variants if v.split("@")[0] == base_id))
                ck.add(f"report.compare[{j}]", f"no building variant {p!r} (variants: {known})")
    if "history_record" in value:
        name = ck.string(value["history_record"], "report.history_record")
        if name is not None and record_ids is not None and name not in record_ids:
            import difflib

            close = difflib.get_close_matches(name, record_ids, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            shown = ", ".join(record_ids[:5]) + (" …" if len(record_ids) > 5 else "")
            ck.add(
                "report.history_record",
                f"no record {name!r} in the record sets ({len(record_ids)} records: {shown}){hint}",
            )
    return dict(value)
