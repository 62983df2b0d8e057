"""A result file read once for tables and figures: its tasks, buildings and order, and
whether the run is complete.

The study is what :mod:`floorslide.report.tables`, :mod:`floorslide.report.records` and
:mod:`floorslide.report.plots` read; they never open the HDF5 file themselves (docs/design.md §5).

An *incomplete* file — fewer tasks done than the plan stored in it counts, e.g. a run
interrupted at 22 of 40 tasks — gives statistics that silently lack records. docs/design.md §10:
reports from it are refused (:class:`~floorslide.errors.IncompleteResultError`, exit code 4
on the command line) unless asked for explicitly, and then labelled INCOMPLETE everywhere.
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from floorslide.errors import IncompleteResultError, ResultFileError
from floorslide.run.results import TaskResult
from floorslide.run.store import ResultFile


@dataclass(frozen=True)
class Building:
    """A building variant as recorded in the result file's task attributes."""

    id: str
    base: str
    kind: str
    stories: int
    isolation_period: float
    isolation_damping: float
    superstructure: str


@dataclass
class Study:
    """A result file read once: its tasks, buildings, and the order of sets, buildings and
    contents (the scene's order, then natural order)."""

    source: str
    scene_name: str
    scene: dict
    report: dict
    tasks: list[TaskResult]
    buildings: dict[str, Building]
    sets: list[str]
    contents: list[str]
    notes: list[str] = field(default_factory=list)
    tasks_planned: int | None = None
    scene_path: str = ""
    quality: dict = field(default_factory=dict)
    """The plan's record quality checks: ``action``, ``flagged`` and ``rejected`` records with
    their flags (empty for files written before floorslide checked records)."""
    provenance: list[dict] = field(default_factory=list)
    """Per record of each set: ``set``, ``record``, ``file`` and the catalog's metadata (empty
    for files written before floorslide stored it)."""
    scaling: list[dict] = field(default_factory=list)
    """The plan's scaled sets (``scale`` to a target or ``scale_pga``): family, level, method,
    per record factor and misfit, the suite check (docs/design.md §10e); empty when the records
    ran as recorded or the file predates it."""

    def set_tasks(self, record_set: str) -> list[TaskResult]:
        """The tasks of one record set."""
        return [t for t in self.tasks if t.meta["record_set"] == record_set]

    @property
    def tasks_done(self) -> int:
        """Tasks finished (and read) from the file."""
        return len(self.tasks)

    @property
    def complete(self) -> bool:
        """Every planned task is done (True when the stored plan does not say how many)."""
        return self.tasks_planned is None or self.tasks_done >= self.tasks_planned

    @property
    def status(self) -> str:
        """``""`` for a complete file, else the INCOMPLETE label every report carries."""
        if self.complete:
            return ""
        return (
            f"INCOMPLETE: {self.tasks_done} of {self.tasks_planned} tasks done — statistics "
            "lack the records of the missing tasks"
        )

    def require_complete(self, allow_incomplete: bool = False) -> None:
        """Refuse an incomplete file unless `allow_incomplete`.

        Raises
        ------
        IncompleteResultError
            Tasks are missing (one line: how many of how many, and how to proceed).
        """
        if self.complete or allow_incomplete:
            return
        scene = self.scene_path or "SCENE.toml"
        raise IncompleteResultError(
            f"INCOMPLETE: {self.tasks_done} of {self.tasks_planned} tasks done; finish the run "
            f"(floorslide run {scene} -o {self.source} --resume) or report what is there, "
            "labelled INCOMPLETE (--allow-incomplete; allow_incomplete=True in Python)",
            self.source,
        )


def _natural(text: str) -> tuple:
    """Sort key treating runs of digits (with a decimal point) as numbers: T=2.5 < T=10."""
    parts = re.split(r"(\d+(?:\.\d+)?)", text)
    return tuple((0, float(p), "") if i % 2 else (1, 0.0, p) for i, p in enumerate(parts))


def _rank(order: Sequence[str], name: str) -> int:
    return order.index(name) if name in order else len(order)


def _float(value, default: float = math.nan) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        return default


def load_study(result: str | Path | ResultFile | Study) -> Study:
    """Read a result file once for tables and figures.

    Parameters
    ----------
    result
        Path of a result file (``floorslide run -o``), an open :class:`ResultFile`, or a
        :class:`Study` (returned as is).

    Returns
    -------
    Study

    Raises
    ------
    ResultFileError
        The file is missing, corrupt, not a floorslide result file, holds no finished task, or
        a task fails its integrity check (its values changed after it was written: every such
        task is named).

    Notes
    -----
    An incomplete file is read (``Study.complete`` is False, ``Study.status`` its label);
    :meth:`Study.require_complete` refuses it. A file written before floorslide kept task
    digests is read with a note in ``Study.notes`` that its values are unverified.
    """
    if isinstance(result, Study):
        return result
    rf = result if isinstance(result, ResultFile) else ResultFile(result)
    source = str(rf.path)
    notes: list[str] = []
    try:
        scene = tomllib.loads(rf.scene_text)
    except tomllib.TOMLDecodeError as exc:
        scene = {}
        notes.append(f"the stored scene text is not valid TOML ({exc}); report options ignored")
    report = scene.get("report", {})
    if not isinstance(report, dict):
        report = {}
    tasks = list(rf.tasks())  # each checked against its digest
    if not rf.verified:
        notes.append("written before floorslide kept task digests: its values are read unverified")
    if not tasks:
        raise ResultFileError(
            "holds no finished task (run the scene, or continue it with floorslide run --resume)",
            source,
        )
    required = ("record_set", "record", "building")
    for t in tasks:
        missing = [k for k in required if k not in t.meta]
        if missing:
            raise ResultFileError(
                f"task {t.task_id} lacks the attributes {', '.join(missing)}", source
            )

    def scene_ids(key: str, attr: str) -> list[str]:
        items = scene.get(key, [])
        out = []
        for item in items if isinstance(items, list) else []:
            if isinstance(item, dict) and isinstance(item.get(attr), str):
                out.append(item[attr])
        return out

    buildings: dict[str, Building] = {}
    for t in tasks:
        m = t.meta
        bid = str(m["building"])
        if bid not in buildings:
            buildings[bid] = Building(
                id=bid,
                base=str(m.get("building_base", "") or bid.split("@")[0]),
                kind=str(m.get("building_kind", "")),
                stories=int(_float(m.get("stories"), 0)),
                isolation_period=_float(m.get("isolation_period")),
                isolation_damping=_float(m.get("isolation_damping")),
                superstructure=str(m.get("superstructure", "") or ""),
            )
    base_order = scene_ids("buildings", "id")

    def building_key(b: Building):
        nan_first = lambda x: (0, 0.0) if math.isnan(x) else (1, x)  # noqa: E731
        return (
            _rank(base_order, b.base),
            _natural(b.base),
            nan_first(b.isolation_period),
            nan_first(b.isolation_damping),
            _natural(b.id),
        )

    ordered = dict(sorted(buildings.items(), key=lambda kv: building_key(kv[1])))
    set_order = scene_ids("records", "set")
    sets = sorted(
        {str(t.meta["record_set"]) for t in tasks},
        key=lambda s: (_rank(set_order, s.split("@")[0]), _natural(s)),
    )
    content_order = scene_ids("contents", "id")
    contents = sorted(
        {c.content for t in tasks for c in t.contents},
        key=lambda c: (_rank(content_order, c), _natural(c)),
    )
    return Study(
        source,
        rf.scene_name,
        scene,
        report,
        tasks,
        ordered,
        sets,
        contents,
        notes,
        tasks_planned=rf.planned_tasks,
        scene_path=rf.scene_path,
        quality=_quality(rf.plan),
        scaling=_dicts(rf.plan, "scaling"),
        provenance=_dicts(rf.plan, "provenance"),
    )


def _dicts(plan, key: str) -> list[dict]:
    """The list of tables `key` of a stored plan (empty when absent or malformed)."""
    items = plan.get(key) if isinstance(plan, dict) else None
    return [e for e in items if isinstance(e, dict)] if isinstance(items, list) else []


def _quality(plan: dict) -> dict:
    """The ``quality`` part of a stored plan, with its lists always present."""
    q = plan.get("quality") if isinstance(plan, dict) else None
    q = q if isinstance(q, dict) else {}
    return dict(
        action=str(q.get("action", "")),
        flagged=list(q.get("flagged", []) or []),
        rejected=list(q.get("rejected", []) or []),
    )
