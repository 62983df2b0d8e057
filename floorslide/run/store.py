"""The HDF5 result file: one writer, tasks written as they finish, a journal, resume.

Layout (every dataset carries a ``units`` attribute; ``1`` means dimensionless)::

    /                        attrs floorslide_format=1, floorslide_version, scene_name, created
    /scene                   the scene file's text (attr path)
    /plan                    the plan as JSON text (what runs, what was skipped and why)
    /tasks/<task>            one group per (record × building); attrs: record_set, record,
                             record_file, building (the variant, e.g. "isolated@T=2.5"),
                             building_base (the scene's id), building_kind, stories,
                             isolation_period, isolation_damping (NaN when fixed),
                             superstructure, fixed_period, dt, npts, pga, scale, seconds;
                             done = 1, set last
      floors                 floors output (0 = ground or base mat)
      pfa                    true peak floor acceleration per floor (m/s**2)
      contents/<content>/floor_<f>/
                             mu_k, mu_s (1), peak_slide (m), residual_slide (m),
                             peak_abs_accel (m/s**2), slide_fraction (1), slip_phases (1)
                             [+ peak_deformation (m), peak_top_accel (m/s**2) for oscillators],
                             modes (per friction pair: rest/slide/rock/slide-rock; rocking
                             objects are not simulated: their slide values are NaN); attrs
                             model, mode (the common mode or "mixed"), skipped (reasons and
                             counts, or ""), vertical
      spectra/floor_<f>/     periods (s), damping (1), psa, sa (m/s**2), sv (m/s), sd (m): the
                             spectra as computed, unbroadened (rows: damping, columns:
                             periods); attr broadening (the scene's ±fraction, 0 for none).
                             Every spectrum dataset has an attr broadening: 0 here.
        broadened/           only when broadening > 0: psa, sa, sv, sd widened by ±broadening
                             in frequency (floorslide.spectra.broaden; ASCE 4, US NRC RG
                             1.122); attr broadening on the group and on every dataset
      histories/             (one record of the study, every building, for figures) attr dt; floors,
                             floor_acceleration (m/s**2); slides/<content>/floor_<f>/ (attr
                             model): u (m; the sliding base's for an oscillator), mu_k (1)
                             [+ z (m, spring deformation), top_accel (m/s**2) for oscillators];
                             rows of friction values under which the object rocks are NaN

Reading stays backward compatible: a file written before the unbroadened spectra were kept
has no ``broadening`` attr on ``spectra/floor_<f>``; if its scene asked for broadening, its
``psa`` … are the broadened spectra and are read as such (the unbroadened ones are NaN, lost).
Histories without ``z``/``top_accel`` read as rigid-block histories.

The plan (``/plan``, attr-free JSON) holds ``tasks``, the number of tasks of the run: a file
with fewer tasks done is incomplete (:attr:`ResultFile.complete`).

A task is written, the file closed (flushed), then marked done. Beside the file, the journal
``<file>.journal/`` keeps every finished task as its own small file written atomically first,
so a run killed at any moment loses no finished task: ``--resume`` copies journal entries the
result file lacks (or rebuilds the file from the journal if the kill left it unreadable) and
skips tasks already done. The journal is removed when a run completes.
"""

from __future__ import annotations

import json
import os
import pickle
import time
import tomllib
from collections.abc import Iterator
from pathlib import Path

import h5py
import numpy as np

from floorslide.errors import OutputError, ResultFileError
from floorslide.run.results import ContentResult, Histories, SpectrumResult, TaskResult

FORMAT = 1
UNITS = {
    "floors": "1",
    "pfa": "m/s**2",
    "mu_k": "1",
    "mu_s": "1",
    "peak_slide": "m",
    "residual_slide": "m",
    "peak_abs_accel": "m/s**2",
    "slide_fraction": "1",
    "slip_phases": "1",
    "peak_deformation": "m",
    "peak_top_accel": "m/s**2",
    "periods": "s",
    "damping": "1",
    "psa": "m/s**2",
    "sa": "m/s**2",
    "sv": "m/s",
    "sd": "m",
    "floor_acceleration": "m/s**2",
    "u": "m",
    "z": "m",
    "top_accel": "m/s**2",
}
CONTENT_FIELDS = (
    "mu_k",
    "mu_s",
    "peak_slide",
    "residual_slide",
    "peak_abs_accel",
    "slide_fraction",
    "slip_phases",
)
SPECTRUM_FIELDS = ("periods", "damping", "psa", "sa", "sv", "sd")
ORDINATE_FIELDS = ("psa", "sa", "sv", "sd")


def _put(group: h5py.Group, name: str, data) -> h5py.Dataset:
    ds = group.create_dataset(name, data=np.asarray(data))
    ds.attrs["units"] = UNITS.get(name, "1")
    return ds


def journal_dir(path: Path) -> Path:
    """The journal folder beside a result file."""
    path = Path(path)
    return path.with_name(path.name + ".journal")


class ResultWriter:
    """The single writer of a result file (not shared between processes)."""

    def __init__(
        self,
        path: str | Path,
        scene_text: str,
        scene_path: str,
        scene_name: str,
        plan: dict,
        resume: bool = False,
    ):
        self.path = Path(path)
        self.journal = journal_dir(self.path)
        self.done: set[str] = set()
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.journal.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputError(
                f"cannot create the output folder: {exc.strerror}", str(self.path)
            ) from None
        fresh = True
        if resume and self.path.exists():
            try:
                reader = ResultFile(self.path)
                if reader.scene_text != scene_text:
                    raise ResultFileError(
                        "was written for a different scene; resume with the same scene file",
                        str(self.path),
                    )
                self.done = set(reader.done_tasks())
                fresh = False
            except ResultFileError as exc:
                if "different scene" in exc.message:
                    raise
                # unreadable after a kill: rebuild it from the journal below
                fresh = True
        if fresh:
            self._create(scene_text, scene_path, scene_name, plan)
        if resume:
            for entry in sorted(self.journal.glob("*.pkl")):
                try:
                    with open(entry, "rb") as fh:
                        result = pickle.load(fh)
                except (OSError, pickle.UnpicklingError, EOFError):
                    continue  # an entry cut short by the kill: that task runs again
                if result.task_id not in self.done:
                    self._write_h5(result)
                    self.done.add(result.task_id)

    def _create(self, scene_text, scene_path, scene_name, plan) -> None:
        from floorslide import __version__

        tmp = self.path.with_name(self.path.name + ".tmp")
        try:
            with h5py.File(tmp, "w") as f:
                f.attrs["floorslide_format"] = FORMAT
                f.attrs["floorslide_version"] = __version__
                f.attrs["scene_name"] = scene_name
                f.attrs["created"] = time.strftime("%Y-%m-%dT%H:%M:%S")
                ds = f.create_dataset("scene", data=scene_text)
                ds.attrs["path"] = scene_path
                f.create_dataset("plan", data=json.dumps(plan))
                f.create_group("tasks")
            os.replace(tmp, self.path)
        except OSError as exc:
            raise OutputError(f"cannot write the result file: {exc}", str(self.path)) from None

    def write(self, result: TaskResult) -> None:
        """Journal the task atomically, write it to the file, close (flush), mark it done."""
        entry = self.journal / f"{result.task_id}.pkl"
        tmp = entry.with_suffix(".tmp")
        try:
            with open(tmp, "wb") as fh:
                pickle.dump(result, fh, protocol=pickle.HIGHEST_PROTOCOL)
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(tmp, entry)
            self._write_h5(result)
        except OSError as exc:
            raise OutputError(
                f"cannot write task {result.task_id}: {exc.strerror or exc}; finished tasks are "
                f"kept (resume with --resume)",
                str(self.path),
            ) from None
        self.done.add(result.task_id)

    def _write_h5(self, result: TaskResult) -> None:
        with h5py.File(self.path, "a") as f:
            tasks = f["tasks"]
            if result.task_id in tasks:
                del tasks[result.task_id]
            g = tasks.create_group(result.task_id)
            for key, value in result.meta.items():
                g.attrs[key] = value
            g.attrs["seconds"] = result.seconds
            _put(g, "floors", result.floors.astype(np.int64))
            _put(g, "pfa", result.pfa)
            cg = g.create_group("contents")
            for c in result.contents:
                h = cg.require_group(c.content).create_group(f"floor_{c.floor}")
                for name in CONTENT_FIELDS:
                    _put(h, name, getattr(c, name))
                for name in ("peak_deformation", "peak_top_accel"):
                    if getattr(c, name) is not None:
                        _put(h, name, getattr(c, name))
                if c.modes is not None:
                    ds = h.create_dataset(
                        "modes", data=np.asarray(c.modes, dtype=object), dtype=h5py.string_dtype()
                    )
                    ds.attrs["units"] = "1"
                h.attrs["model"] = c.model
                h.attrs["mode"] = c.mode
                h.attrs["skipped"] = c.skipped
                h.attrs["vertical"] = c.vertical
            sg = g.create_group("spectra")
            for s in result.spectra:
                h = sg.create_group(f"floor_{s.floor}")
                h.attrs["broadening"] = float(s.broadening)
                for name in SPECTRUM_FIELDS:
                    ds = _put(h, name, getattr(s, name))
                    if name in ORDINATE_FIELDS:
                        ds.attrs["broadening"] = 0.0
                if s.broadening:
                    b = h.create_group("broadened")
                    b.attrs["broadening"] = float(s.broadening)
                    for name in ORDINATE_FIELDS:
                        ds = _put(b, name, getattr(s, f"{name}_broadened"))
                        ds.attrs["broadening"] = float(s.broadening)
            if result.histories is not None:
                hi = result.histories
                hg = g.create_group("histories")
                hg.attrs["dt"] = hi.dt
                _put(hg, "floors", hi.floors)
                _put(hg, "floor_acceleration", hi.floor_acceleration)
                for key, u in hi.slides.items():
                    sgr = hg.require_group(f"slides/{key}")
                    _put(sgr, "u", u)
                    _put(sgr, "mu_k", hi.mu_k[key])
                    # getattr: a journal entry pickled before these fields existed
                    deformation = getattr(hi, "deformation", {})
                    oscillator = key in deformation
                    sgr.attrs["model"] = "oscillator" if oscillator else "rigid"
                    if oscillator:
                        _put(sgr, "z", deformation[key])
                        _put(sgr, "top_accel", hi.top_accel[key])
            f.flush()
        with h5py.File(self.path, "a") as f:
            f["tasks"][result.task_id].attrs["done"] = 1

    def finish(self) -> None:
        """A completed run: the journal is no longer needed."""
        for entry in self.journal.glob("*"):
            entry.unlink()
        try:
            self.journal.rmdir()
        except OSError:
            pass


class ResultFile:
    """Read a result file; refuse one that is not a floorslide result or is corrupt."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        if not self.path.exists():
            raise ResultFileError("no such result file", str(self.path))
        try:
            with h5py.File(self.path, "r") as f:
                if f.attrs.get("floorslide_format") != FORMAT or "tasks" not in f:
                    raise ResultFileError("not a floorslide result file", str(self.path))
                self.scene_text = (
                    f["scene"][()].decode()
                    if isinstance(f["scene"][()], bytes)
                    else str(f["scene"][()])
                )
                self.scene_name = str(f.attrs.get("scene_name", ""))
                self.scene_path = _s(f["scene"].attrs.get("path", ""))
                plan = f["plan"][()]
                self.plan = json.loads(plan.decode() if isinstance(plan, bytes) else plan)
                if not isinstance(self.plan, dict):
                    raise ValueError("the stored plan is not a JSON object")
                self._done = []
                tasks = f["tasks"]
                for k in tasks:
                    g = tasks.get(k)  # None when a kill left the link but not the group
                    if not isinstance(g, h5py.Group):
                        raise ValueError(f"task {k} is damaged")
                    if g.attrs.get("done") == 1:
                        self._done.append(k)
        except ResultFileError:
            raise
        except (OSError, KeyError, ValueError, RuntimeError) as exc:
            hint = (
                " (rebuild it with floorslide run --resume)"
                if journal_dir(self.path).exists()
                else ""
            )
            raise ResultFileError(
                f"corrupt or unreadable result file: {exc}{hint}", str(self.path)
            ) from None

    def done_tasks(self) -> list[str]:
        """Ids of the tasks marked done."""
        return list(self._done)

    @property
    def planned_tasks(self) -> int | None:
        """The number of tasks of the run, from the stored plan (None if it does not say)."""
        n = self.plan.get("tasks")
        return n if isinstance(n, int) and not isinstance(n, bool) and n >= 0 else None

    @property
    def complete(self) -> bool:
        """Whether every planned task is done (True when the plan does not say how many)."""
        n = self.planned_tasks
        return n is None or len(self._done) >= n

    def _legacy_broadening(self) -> float:
        """The scene's ``[spectra] broadening``, for files that did not label their spectra."""
        try:
            scene = tomllib.loads(self.scene_text)
            value = scene.get("spectra", {}).get("broadening", 0.0)
            return float(value) if isinstance(value, int | float) else 0.0
        except (tomllib.TOMLDecodeError, AttributeError):
            return 0.0

    def tasks(self) -> Iterator[TaskResult]:
        """Every finished task, in file order."""
        legacy = self._legacy_broadening()
        try:
            with h5py.File(self.path, "r") as f:
                for tid in self._done:
                    yield _read_task(f["tasks"][tid], tid, legacy)
        except (OSError, KeyError, ValueError) as exc:
            raise ResultFileError(f"corrupt result file: {exc}", str(self.path)) from None


def _s(value) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


def _read_spectrum(k: str, h: h5py.Group, legacy_broadening: float) -> SpectrumResult:
    floor = int(k.split("_")[1])
    fields = {n: h[n][()] for n in SPECTRUM_FIELDS}
    if "broadening" not in h.attrs and legacy_broadening > 0:
        # written before the unbroadened spectra were kept: what is stored is broadened
        wide = {f"{n}_broadened": fields[n] for n in ORDINATE_FIELDS}
        lost = {n: np.full_like(fields[n], np.nan, dtype=float) for n in ORDINATE_FIELDS}
        return SpectrumResult(floor, **{**fields, **lost}, broadening=legacy_broadening, **wide)
    out = SpectrumResult(floor, **fields, broadening=float(h.attrs.get("broadening", 0.0)))
    if "broadened" in h:
        for n in ORDINATE_FIELDS:
            setattr(out, f"{n}_broadened", h["broadened"][n][()])
    return out


def _read_task(g: h5py.Group, tid: str, legacy_broadening: float = 0.0) -> TaskResult:
    meta = {k: (v.item() if hasattr(v, "item") else v) for k, v in g.attrs.items()}
    meta = {k: _s(v) if isinstance(v, bytes | str) else v for k, v in meta.items()}
    contents = []
    for cname, cg in g["contents"].items():
        for fname, h in cg.items():
            contents.append(
                ContentResult(
                    content=cname,
                    floor=int(fname.split("_")[1]),
                    model=_s(h.attrs["model"]),
                    mode=_s(h.attrs["mode"]),
                    skipped=_s(h.attrs["skipped"]),
                    vertical=bool(h.attrs["vertical"]),
                    **{name: h[name][()] for name in CONTENT_FIELDS},
                    peak_deformation=h["peak_deformation"][()] if "peak_deformation" in h else None,
                    peak_top_accel=h["peak_top_accel"][()] if "peak_top_accel" in h else None,
                    modes=np.array([_s(m) for m in h["modes"][()]]) if "modes" in h else None,
                )
            )
    spectra = [_read_spectrum(k, h, legacy_broadening) for k, h in g["spectra"].items()]
    hist = None
    if "histories" in g:
        hg = g["histories"]
        slides, mus, deform, top = {}, {}, {}, {}
        if "slides" in hg:
            for cname, cg in hg["slides"].items():
                for fname, h in cg.items():
                    key = f"{cname}/{fname}"
                    slides[key] = h["u"][()]
                    mus[key] = h["mu_k"][()]
                    if "z" in h:
                        deform[key], top[key] = h["z"][()], h["top_accel"][()]
        hist = Histories(
            float(hg.attrs["dt"]),
            hg["floors"][()],
            hg["floor_acceleration"][()],
            slides,
            mus,
            deform,
            top,
        )
    return TaskResult(
        task_id=tid,
        meta=meta,
        floors=g["floors"][()],
        pfa=g["pfa"][()],
        contents=contents,
        spectra=spectra,
        histories=hist,
        seconds=float(g.attrs.get("seconds", 0.0)),
    )
