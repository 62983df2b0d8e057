"""The HDF5 result file: one writer, tasks written in batches, a journal, resume.

**Format 2 (written now): columnar.** A task is built as the group below (format 1's layout,
:func:`task_node`) and its digest is over that group, but it is stored as rows of three
tables, one dataset per quantity over all tasks (:mod:`floorslide.run.columns` documents
them)::

    /                        attrs floorslide_format=2, floorslide_version, scene_name, created,
                             task_digest, header_sha256
    /scene, /plan            as below
    /tasks/                  one row per task: id, sha256 (the task's digest), raw,
                             histories, a column per task attribute (record, building, pga,
                             …, fingerprint) and floors, pfa, pfa_components ragged
                             (``<name>#n`` each row's length); attr rows (the rows done)
    /contents/               one row per (task, content, floor, friction pair): task (its row
                             of /tasks), content, group, floor, pair, a column per quantity
                             (mu_k, mu_s, peak_slide, …, modes and outcomes as text) and the
                             content's model, mode, skipped, vertical
    /spectra/                one row per (task, floor): task, group, floor, periods (rows,
                             periods), damping (rows, damping), psa, sa, sv, sd (rows, damping,
                             periods), broadened.psa …, rotd100, psa_h1, psa_h2, broadening,
                             orientation
    /histories/<task>        the group histories/ below, of the tasks that keep histories
    /raw/<task>              a task whose group does not fit the tables, stored whole (none today)

Each table's ``present`` (rows, columns) says which columns a row has; a column carries the
``units`` (and ``broadening``) its values had. The number of HDF5 objects does not grow with
the tasks (about 150 for the demo's 288 tasks, against 10,700 in format 1). Reading rebuilds
each task's group from the columns (a few large reads) and checks it against its ``sha256``
as before: integrity, the journal and resume are unchanged in what they guarantee.

**Format 1 (one group per task)** is read as before, by the same reader, with its checks;
``floorslide upgrade OLD.h5 [-o NEW.h5]`` (:func:`upgrade`) converts it to format 2, and
``--resume`` on it writes the file again in format 2. Its layout, which is also the group each
task's digest is computed over::

    /                        attrs floorslide_format=1, floorslide_version, scene_name, created,
                             task_digest="sha256-1" (every task carries its digest)
    /scene                   the scene file's text (attr path)
    /plan                    the plan as JSON text (what runs, what was skipped and why;
                             "quality": the records' quality flags with their numbers and the
                             records rejected by ``[scene] qa = "reject"``)
    /tasks/<task>            one group per (record × building); attrs: record_set, record,
                             record_file, building (the variant, e.g. "isolated@T=2.5"),
                             building_base (the scene's id), building_kind, stories,
                             isolation_period, isolation_damping (NaN when fixed),
                             superstructure, fixed_period, dt, npts, pga, scale, qa_flags
                             (the record's quality flags, comma-separated; "" none), seconds,
                             components (1, or 2 for a pair; pga is then the larger
                             component's), component_names (a pair's, e.g. "052,142");
                             on nonlinear isolation also isolator (bilinear |
                             friction_pendulum), its parameters isolator_capacity (m, NaN:
                             none), isolator_q_ratio, isolator_yield_disp (m), isolator_alpha
                             (bilinear) or isolator_mu, isolator_mu_s, isolator_radius (m)
                             (pendulum), and the results isolator_peak_displacement (m),
                             isolator_residual_displacement (m), isolator_peak_force_ratio
                             (peak base shear / W), isolator_capacity_exceeded (0/1);
                             under a pair (friction pendulums in the plane) the peak and
                             residual are the vector's length, with isolator_peak_direction
                             (degrees from h1 towards h2), isolator_residual_h1 and
                             isolator_residual_h2 (m);
                             sha256 (the task's digest, written with it); done = 1, set last
      floors                 floors output (0 = ground or base mat)
      pfa                    true peak floor acceleration per floor (m/s**2); of a pair of
                             components the peak of the acceleration vector, and
      pfa_components         (pairs only) the peak along each component, (n_floors, 2)
      contents/<content>/floor_<f>/
                             mu_k, mu_s (1), peak_slide (m), residual_slide (m),
                             peak_abs_accel (m/s**2), slide_fraction (1), slip_phases (1)
                             [+ peak_deformation (m), peak_top_accel (m/s**2) for oscillators;
                             coupled_pfa (m/s**2, the floor's true PFA with the block) for
                             heavy equipment coupled with its floor],
                             modes (per friction pair, Shenton's: rest/slide/rock/slide-rock;
                             where it is rock or slide-rock the object is one slide–rock block,
                             fs.slide_rock, per friction pair, and the slide values are its
                             slide — NaN in files written before); for contents with a
                             width and height also rock_peak_ratio (1, max|θ|/α), rock_impacts
                             (1, the cascade to rest included), rock_significant_impacts (1,
                             at |θ'| ≥ p·α·√(f(2 − f)), f = 0.01; −1 where it slides
                             instead; absent in older files),
                             rock_time (s, rocking with or without sliding), slide_rock_time
                             (s, sliding and rocking at once; absent in older files),
                             overturned (1: 1/0), overturn_time (s, NaN:
                             never) — NaN (−1 impacts) where the object slides — and outcomes
                             (what it did: rest/slide/rock/slide-rock/overturn); for a pair
                             of components (the block slides in the plane; peak_slide = peak
                             |u|, residual_slide = |u(end)|) also peak_angle (deg from h1
                             towards h2), residual_h1, residual_h2 (m), peak_slide_h1,
                             peak_slide_h2 (m, each component's 1-D slide), ratio_2d_1d (1); attrs
                             model, mode (the common mode or "mixed"), skipped (reasons and
                             counts, or ""), vertical
      spectra/floor_<f>/     periods (s), damping (1), psa, sa (m/s**2), sv (m/s), sd (m): the
                             spectra as computed, unbroadened (rows: damping, columns:
                             periods); attr broadening (the scene's ±fraction, 0 for none).
                             Every spectrum dataset has an attr broadening: 0 here. For a
                             pair of components attr orientation = "RotD50": psa is RotD50
                             (Boore 2010), sd = psa/ω², sa and sv NaN, and rotd100, psa_h1,
                             psa_h2 (m/s**2) RotD100 and each direction's PSA.
        broadened/           only when broadening > 0: psa, sa, sv, sd widened by ±broadening
                             in frequency (floorslide.spectra.broaden; ASCE 4, US NRC RG
                             1.122); attr broadening on the group and on every dataset
      histories/             (one record of the study, every building, for figures) attr dt; floors,
                             floor_acceleration (m/s**2); slides/<content>/floor_<f>/ (attr
                             model): u (m; the sliding base's for an oscillator), mu_k (1)
                             [+ z (m, spring deformation), top_accel (m/s**2) for oscillators];
                             rows of friction values under which the object rocks are NaN;
                             on nonlinear isolation also isolator_displacement (m, u0 relative
                             to the ground) and isolator_force_ratio (1, the layer's force
                             over W) at the samples: the hysteresis loop; rocking/<content>/
                             floor_<f>/theta_ratio (1, θ/α at the samples, NaN once
                             overturned; of its friction pair that overturned first, else
                             of the largest peak rotation) for contents that rock under the
                             record; for a pair
                             floor_acceleration_h2 (m/s**2, along h2; floor_acceleration is
                             along h1), and slides/.../u is |u|, u_plane (m, (n_mu, npts, 2))
                             the path in the plane (2-DOF oscillators: z is |z|, top_accel
                             NaN, not kept in the plane); on nonlinear isolation the bearing's
                             histories above are along h1, isolator_displacement_h2 (m) and
                             isolator_force_ratio_h2 (1) along h2 (its orbit)

Reading stays backward compatible: a file written before the unbroadened spectra were kept
has no ``broadening`` attr on ``spectra/floor_<f>``; if its scene asked for broadening, its
``psa`` … are the broadened spectra and are read as such (the unbroadened ones are NaN, lost).
Histories without ``z``/``top_accel`` read as rigid-block histories; histories without
``isolator_displacement``/``isolator_force_ratio`` (other buildings, older files) read with
both None.

The plan (``/plan``, attr-free JSON) holds ``tasks``, the number of tasks of the run: a file
with fewer tasks done is incomplete (:attr:`ResultFile.complete`).

**Integrity.** Each task's ``sha256`` attribute is the SHA-256 of its group — every dataset's
values, dtype and shape and every attribute, in a canonical order, its own ``sha256`` and
``done`` left out (:func:`floorslide.run.snapshot.digest`). Every reader checks it:
:meth:`ResultFile.tasks` (so ``table``, ``plot`` and every report) refuses a file with a task
that fails, naming the task, and ``--resume`` rebuilds such a task. A file without the root
attribute ``task_digest`` was written before floorslide kept digests: it reads as
before, with a note that its values are unverified (:attr:`ResultFile.verified`).

**Writing.** A task is first journaled; then a batch of tasks (:attr:`ResultWriter.batch`:
one for runs of fewer than 32 tasks, about a sixteenth of the run else, at most 64, and at
least every :data:`FLUSH_SECONDS`) is appended to the tables with their digests and the file
closed (flushed), then counted done (each table's ``rows``; rows beyond it, from a write cut
short, are ignored and overwritten). The journal ``<file>.journal/`` beside the file keeps every
finished task as its own file ``<task>.entry``, written atomically first (JSON and raw array
bytes, checked against the task's digest when read, never able to run code: see
:mod:`floorslide.run.journal`), so a run killed at any moment loses no finished task:
``--resume`` copies journal entries the result file lacks (or rebuilds the file from the
journal if the kill left it unreadable) and skips tasks already done and verified. The journal
is removed when a run completes. Before each write the file is grown by the disk space the
write needs (``posix_fallocate``; HDF5 trims it to its data when it closes the file), so that a
full disk stops the run with a clean error before HDF5 writes — HDF5 does not survive running
out of space in the middle of a write.

**Existing files.** A run never replaces a file: ``--resume`` continues the run of the same
scene in it, ``--overwrite`` replaces it, anything else is refused (:class:`OutputExistsError`).
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import hashlib
import io
import json
import os
import shutil
import stat
import sys
import time
import tomllib
from collections.abc import Callable, Collection, Iterator, Mapping
from pathlib import Path

import h5py
import numpy as np

from floorslide import outputs
from floorslide.errors import OutputError, OutputExistsError, ResultFileError, one_line
from floorslide.run import columns, journal
from floorslide.run.results import (
    PLANE_FIELDS,
    ROCK_FIELDS,
    ContentResult,
    Histories,
    SpectrumResult,
    TaskResult,
)
from floorslide.run.snapshot import (
    DIGEST_SCHEME,
    H5_ERRORS,
    Data,
    Node,
    SnapshotError,
    digest,
    snapshot,
)

FORMAT = 2
"""The layout written: the columnar tables of :mod:`floorslide.run.columns`."""
LEGACY_FORMAT = 1
"""One group per task (``/tasks/<task>``): read as before, converted by ``floorslide upgrade``."""
append_tasks = columns.append
COPY_BATCH = 256
"""Tasks appended per batch when a file is rebuilt or upgraded (each batch committed before the
next: rows are appended after the committed ones)."""
"""Writes a batch of tasks into the open file (a name of its own, so tests can fail it)."""
FLUSH_SECONDS = 30.0
"""A batch of tasks is written at least this often (seconds), whatever its size."""
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
    "coupled_pfa": "m/s**2",
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
    "isolator_displacement": "m",
    "isolator_force_ratio": "1",
    "isolator_displacement_h2": "m",
    "isolator_force_ratio_h2": "1",
    "rock_peak_ratio": "1",
    "rock_impacts": "1",
    "rock_significant_impacts": "1",
    "rock_time": "s",
    "slide_rock_time": "s",
    "overturned": "1",
    "overturn_time": "s",
    "theta_ratio": "1",
    "pfa_components": "m/s**2",
    "peak_angle": "deg",
    "residual_h1": "m",
    "residual_h2": "m",
    "peak_slide_h1": "m",
    "peak_slide_h2": "m",
    "ratio_2d_1d": "1",
    "u_plane": "m",
    "floor_acceleration_h2": "m/s**2",
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
ROTD_FIELDS = ("rotd100", "psa_h1", "psa_h2")
"""The spectra of a pair beside RotD50 (``psa``): RotD100 and each direction's PSA."""
ISOLATOR_HISTORIES = (
    "isolator_displacement",
    "isolator_force_ratio",
    "isolator_displacement_h2",
    "isolator_force_ratio_h2",
)
"""Histories of a building on nonlinear isolation (absent for other buildings)."""

DIGEST_ATTR = "sha256"
"""Attribute of a task group: the digest of the group (:func:`floorslide.run.snapshot.digest`)."""
DIGESTS_ATTR = "task_digest"
"""Root attribute of files whose every task carries a digest: the integrity scheme,
:data:`INTEGRITY` (files of ``"sha256-1"`` carry task digests but no header digest)."""
INTEGRITY = "sha256-2"
"""The integrity scheme written: every task carries its digest (:data:`DIGEST_ATTR`) and the
header (the root's attributes, ``/scene`` and ``/plan``) carries :data:`HEADER_DIGEST_ATTR`."""
LEGACY_INTEGRITY = DIGEST_SCHEME
"""Files written before the header had a digest: tasks verified, the header not."""
HEADER_DIGEST_ATTR = "header_sha256"
"""Root attribute: the digest of the header (:func:`header_digest`)."""
FINGERPRINT_ATTR = "fingerprint"
"""Attribute of a task group: the fingerprint of its inputs
(:mod:`floorslide.run.fingerprint`), which the plan also lists (``fingerprints``)."""
BOOKKEEPING = frozenset({"done", DIGEST_ATTR})
"""Attributes of a task group that its digest leaves out (set after the group is written)."""
ENTRY_SUFFIX = ".entry"
WRITING = "writing.mark"
"""In the journal folder while a batch is written into the result file: found by a resume, it
says the last run stopped in the middle of a write (killed), which can leave HDF5's internal
structures half-written even where the tasks read back; the file is then rebuilt."""
"""Suffix of a journal entry file (``<task>.entry``)."""
HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
LOCK_WAIT = 10.0
"""Seconds the writer waits for an HDF5 file lock held by another process before giving up.

HDF5 locks a file with ``flock``, which belongs to the open file description, not to the
process: a child forked while the writer has the file open (a Dask nanny restarting a lost
worker in the writer's process, any ``subprocess`` or ``multiprocessing`` start from another
thread) holds a copy of the descriptor, and with it the lock, until it closes its copies (at
exec, or at once with ``close_fds``). Closing the file in the writer does not release the lock
then, and reopening it at once fails with errno 11 (EAGAIN, "unable to lock file"). The lock is
gone a moment later, so the writer waits for it."""
READ_LOCK_WAIT = 1.0
"""Seconds a reader waits for the lock of a file being written (then: one-line error)."""
RESERVE_MIN = 1 << 20
RESERVE_PER_OBJECT = 4096
"""Disk space made sure of before a task is written: twice its values' bytes, this much per
HDF5 object and RESERVE_MIN (measured: a task of the demo grows the file by about 30 kB)."""


def _noop(message: str) -> None:
    del message


def warn_stderr(message: str) -> None:
    """Print `message` on stderr as one line, ``floorslide: warning: ...``."""
    print(f"floorslide: warning: {one_line(message)}", file=sys.stderr, flush=True)


def scene_digest(text: str) -> str:
    """SHA-256 (hex) of a scene's text: which scene a journal entry was computed for."""
    return hashlib.sha256(text.encode("utf-8", "surrogateescape")).hexdigest()


def journal_dir(path: str | Path) -> Path:
    """The journal folder beside a result file."""
    path = Path(path)
    return path.with_name(path.name + ".journal")


def journal_entries(path: str | Path) -> list[Path]:
    """The journal entries (finished tasks) of the run writing `path`, in name order."""
    folder = journal_dir(path)
    return sorted(folder.glob(f"*{ENTRY_SUFFIX}")) if folder.is_dir() else []


# --- the layout of a task ----------------------------------------------------------------


def _data(name: str, value) -> Data:
    return Data(np.asarray(value), {"units": UNITS.get(name, "1")})


def _rocking_of(h) -> dict:
    """The rocking arrays and outcomes of a stored content group (none in files written
    before rocking was simulated, or for contents without a geometry)."""
    if "rock_peak_ratio" not in h:
        return {}
    out = {name: _value(h, name) for name in ROCK_FIELDS}
    if "rock_significant_impacts" in h:
        out["rock_significant_impacts"] = _value(h, "rock_significant_impacts")
    # written before slide–rock was simulated: its time unknown (NaN)
    n = np.asarray(out["rock_peak_ratio"]).size
    out["slide_rock_time"] = (
        _value(h, "slide_rock_time") if "slide_rock_time" in h else np.full(n, np.nan)
    )
    out["outcomes"] = np.array([_s(m) for m in _value(h, "outcomes")])
    return out


def task_node(result: TaskResult) -> Node:
    """The group of one task as it is stored (the layout in this module's docstring), without
    its digest and ``done`` mark."""
    meta = {k: v for k, v in result.meta.items() if k not in BOOKKEEPING}
    g = Node({**meta, "seconds": result.seconds})
    g.children["floors"] = _data("floors", result.floors.astype(np.int64))
    g.children["pfa"] = _data("pfa", result.pfa)
    if result.pfa_components is not None:
        g.children["pfa_components"] = _data("pfa_components", result.pfa_components)
    contents = g.group("contents")
    for c in result.contents:
        h = contents.group(c.content).group(f"floor_{c.floor}")
        for name in CONTENT_FIELDS:
            h.children[name] = _data(name, getattr(c, name))
        for name in ("peak_deformation", "peak_top_accel", "coupled_pfa"):
            if getattr(c, name) is not None:
                h.children[name] = _data(name, getattr(c, name))
        if c.modes is not None:
            h.children["modes"] = Data(np.asarray(c.modes, dtype=object), {"units": "1"})
        if c.rock_peak_ratio is not None:
            for name in ROCK_FIELDS:
                h.children[name] = _data(name, getattr(c, name))
            if c.rock_significant_impacts is not None:
                h.children["rock_significant_impacts"] = _data(
                    "rock_significant_impacts", c.rock_significant_impacts
                )
            if c.slide_rock_time is not None:
                h.children["slide_rock_time"] = _data("slide_rock_time", c.slide_rock_time)
            h.children["outcomes"] = Data(np.asarray(c.outcomes, dtype=object), {"units": "1"})
        if c.peak_angle is not None:
            for name in PLANE_FIELDS:
                h.children[name] = _data(name, getattr(c, name))
        h.attrs.update(model=c.model, mode=c.mode, skipped=c.skipped, vertical=c.vertical)
    spectra = g.group("spectra")
    for s in result.spectra:
        h = spectra.group(f"floor_{s.floor}")
        h.attrs["broadening"] = float(s.broadening)
        for name in SPECTRUM_FIELDS:
            h.children[name] = _data(name, getattr(s, name))
            if name in ORDINATE_FIELDS:
                h.children[name].attrs["broadening"] = 0.0
        if s.orientation:
            h.attrs["orientation"] = s.orientation
            for name in ROTD_FIELDS:
                h.children[name] = _data("psa", getattr(s, name))
        if s.broadening:
            b = h.group("broadened")
            b.attrs["broadening"] = float(s.broadening)
            for name in ORDINATE_FIELDS:
                b.children[name] = _data(name, getattr(s, f"{name}_broadened"))
                b.children[name].attrs["broadening"] = float(s.broadening)
    if result.histories is not None:
        hi = result.histories
        hg = g.group("histories")
        hg.attrs["dt"] = hi.dt
        hg.children["floors"] = _data("floors", hi.floors)
        hg.children["floor_acceleration"] = _data("floor_acceleration", hi.floor_acceleration)
        for name in ISOLATOR_HISTORIES:
            if getattr(hi, name) is not None:
                hg.children[name] = _data(name, getattr(hi, name))
        for key, u in hi.slides.items():
            sg = hg.group(f"slides/{key}")
            sg.children["u"] = _data("u", u)
            sg.children["mu_k"] = _data("mu_k", hi.mu_k[key])
            oscillator = key in hi.deformation
            sg.attrs["model"] = "oscillator" if oscillator else "rigid"
            if oscillator:
                sg.children["z"] = _data("z", hi.deformation[key])
                sg.children["top_accel"] = _data("top_accel", hi.top_accel[key])
        for key, theta in hi.rocking.items():
            hg.group(f"rocking/{key}").children["theta_ratio"] = _data("theta_ratio", theta)
        if hi.floor_acceleration_h2 is not None:
            hg.children["floor_acceleration_h2"] = _data(
                "floor_acceleration_h2", hi.floor_acceleration_h2
            )
        for key, u in hi.plane.items():
            hg.group(f"slides/{key}").children["u_plane"] = _data("u_plane", u)
    return g


def _node_size(node: Node) -> tuple[int, int]:
    """Bytes of the values and number of objects of a group (to reserve disk space)."""
    nbytes, objects = 0, 1
    for child in node.children.values():
        if isinstance(child, Node):
            b, o = _node_size(child)
            nbytes, objects = nbytes + b, objects + o
        else:
            value = np.asarray(child.value)
            nbytes += value.size * 64 if value.dtype.kind == "O" else value.nbytes
            objects += 1
    return nbytes, objects


# --- low-level file operations -----------------------------------------------------------


def _is_lock_conflict(exc: BaseException) -> bool:
    return isinstance(exc, BlockingIOError) or "unable to lock file" in str(exc)


_no_space = outputs.no_space


def _open_h5(path: Path, mode: str, wait: float | None = None) -> h5py.File:
    """``h5py.File(path, mode)``, waiting up to `wait` seconds (default :data:`LOCK_WAIT`)
    for a lock held by another process (see :data:`LOCK_WAIT` for why one can linger)."""
    deadline = time.monotonic() + (LOCK_WAIT if wait is None else wait)
    delay = 0.005
    while True:
        try:
            return h5py.File(path, mode)
        except OSError as exc:
            if not _is_lock_conflict(exc) or time.monotonic() >= deadline:
                raise
        time.sleep(delay)
        delay = min(2 * delay, 0.25)


def _stamp(path: Path) -> tuple | None:
    """The file's identity (device, inode), size and modification time (None if it cannot be
    read)."""
    try:
        st = os.stat(path)
    except OSError:
        return None
    return st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns


def _is_hdf5(path: Path) -> bool:
    with open(path, "rb") as fh:
        return fh.read(len(HDF5_SIGNATURE)) == HDF5_SIGNATURE


def _write_file(path: Path, data: bytes) -> None:
    """Write `data` as the file `path` atomically (:func:`floorslide.outputs.write_atomically`:
    an exclusive temporary file, fsync, rename). A failure (a full disk) removes the temporary
    file and leaves `path` as it was."""
    outputs.write_atomically(path, data)


def header_digest(f: h5py.File) -> str:
    """The digest of a result file's header: the root's attributes (but this digest's own),
    ``/scene`` and ``/plan`` with their attributes (:func:`floorslide.run.snapshot.digest`).

    A bit flipped there (the task count, a scale factor, the integrity scheme itself) would
    make a half-finished file read as complete or unverified; with this digest it is refused.
    """
    node = Node({k: v for k, v in f.attrs.items() if k != HEADER_DIGEST_ATTR})
    for name in ("scene", "plan"):
        ds = f[name]
        if not isinstance(ds, h5py.Dataset):
            raise ValueError(f"/{name} is not a dataset")
        node.children[name] = Data(ds[()], dict(ds.attrs))
    return digest(node)


def _write_header(f: h5py.File, scene_text: str, scene_path: str, scene_name: str, plan: dict):
    """Write (or replace) the header of the open result file `f` and its digest."""
    from floorslide import __version__

    for name in ("scene", "plan"):
        if name in f:
            del f[name]
    f.attrs["floorslide_format"] = FORMAT
    f.attrs["floorslide_version"] = __version__
    f.attrs["scene_name"] = scene_name
    if "created" not in f.attrs:
        f.attrs["created"] = time.strftime("%Y-%m-%dT%H:%M:%S")
    f.attrs[DIGESTS_ATTR] = INTEGRITY
    ds = f.create_dataset("scene", data=scene_text)
    ds.attrs["path"] = scene_path
    f.create_dataset("plan", data=json.dumps(plan))
    f.attrs[HEADER_DIGEST_ATTR] = header_digest(f)


_fallocate = getattr(os, "posix_fallocate", None)


def _reserve(path: Path, nbytes: int) -> None:
    """Allocate `nbytes` of disk at the end of the HDF5 file `path`, for the write that follows.

    HDF5 writes new objects at its end of data, inside this space, and trims the file to its
    end of data when it closes it; a file left with the space (a kill in between) reads as it
    is. Without ``posix_fallocate`` (or on a file system without it) the free space is
    checked instead.

    Raises
    ------
    OSError
        ENOSPC (or EDQUOT) when the space is not there; the file is left as it was.
    """
    fd = os.open(path, os.O_RDWR)
    try:
        size = os.fstat(fd).st_size
        try:
            if _fallocate is None:
                raise OSError(errno.EOPNOTSUPP, os.strerror(errno.EOPNOTSUPP))
            _fallocate(fd, size, nbytes)
        except OSError as exc:
            with contextlib.suppress(OSError):
                os.ftruncate(fd, size)
            if exc.errno not in (errno.EOPNOTSUPP, errno.ENOSYS, errno.EINVAL):
                raise
            if shutil.disk_usage(path.parent).free < nbytes:
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path)) from None
    finally:
        os.close(fd)


# --- writing -----------------------------------------------------------------------------


class ResultWriter:
    """The single writer of a result file (not shared between processes).

    While it is open, the writer holds an advisory lock (``flock``) on the run's journal
    folder ``<file>.journal/``: a second run writing the same file (``--resume`` or
    ``--overwrite`` included) is refused in one line instead of deleting the first one's
    journal or mixing its tasks in. The lock is released by :meth:`finish`, :meth:`abandon`
    or :meth:`close` (and by the operating system when the process ends).

    Parameters
    ----------
    path
        The result file.
    scene_text, scene_path, scene_name, plan
        What the file stores about its run (``/scene``, its ``path``, the ``scene_name``
        attribute, ``/plan``).
    resume
        Continue the run of the same scene in `path`: its verified tasks whose inputs are
        unchanged and the valid entries of its journal are kept; a task that fails its
        integrity check, or whose inputs changed (`fingerprints`), is run again.
    overwrite
        Replace the regular file at `path` (and an old journal beside it).
    task_ids
        The run's task ids: a journal entry of any other task is refused (default: any, or the
        keys of `fingerprints`).
    fingerprints
        The fingerprint of each task's inputs (:func:`floorslide.run.fingerprint.
        task_fingerprints`), stored with each task and in the plan; on `resume`, a stored task
        or journal entry with another fingerprint is run again and said so.
    warn
        Called with one line for each thing a resumed run refuses or rebuilds (default: none).

    Raises
    ------
    OutputExistsError
        `path` exists (or a journal of an unfinished run is beside it) and neither `resume`
        nor `overwrite` was given; `path` is not a regular file (a folder, a device, a link);
        another run is writing it.
    ResultFileError
        `resume` on a file that is not a floorslide result file, or of another scene.
    OutputError
        The file or its journal cannot be written.
    """

    def __init__(
        self,
        path: str | Path,
        scene_text: str,
        scene_path: str,
        scene_name: str,
        plan: dict,
        resume: bool = False,
        *,
        overwrite: bool = False,
        task_ids: Collection[str] | None = None,
        fingerprints: Mapping[str, str] | None = None,
        warn: Callable[[str], None] | None = None,
        batch: int = 1,
    ):
        if resume and overwrite:
            raise ValueError("resume and overwrite exclude each other")
        self.path = Path(path)
        self.journal = journal_dir(self.path)
        self.scene_text, self.scene_path, self.scene_name = scene_text, scene_path, scene_name
        self.fingerprints = dict(fingerprints) if fingerprints is not None else None
        self.plan = dict(plan)
        if self.fingerprints is not None:
            self.plan["fingerprints"] = self.fingerprints
            if task_ids is None:
                task_ids = list(self.fingerprints)
        self.scene_sha256 = scene_digest(scene_text)
        self.task_ids = None if task_ids is None else set(task_ids)
        self.warn = warn or _noop
        self.done: set[str] = set()
        """Tasks in the file, verified (or unverified in a file that predates digests)."""
        self.kept: set[str] = set()
        """Tasks kept whatever happens next: in the file or in the journal."""
        self.created = False
        """Whether this writer created the file (so that a run that keeps nothing removes it)."""
        self._lock_fd: int | None = None
        self._made_journal = False
        self.batch = max(1, int(batch))
        self._pending: list[tuple[str, Node, str]] = []
        self._last_flush = time.monotonic()
        self._columns: dict = {}
        """The tables' columns after this writer's last batch (:func:`columns.append`'s
        `known`), valid while the file is as that batch left it (:attr:`_columns_stamp`)."""
        self._columns_stamp: tuple | None = None
        self._check_target(resume, overwrite)
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputError(
                f"cannot create the output folder: {exc.strerror}", str(self.path)
            ) from None
        self._lock()
        try:
            if resume:
                self._open_for_resume()
                self._recover_journal()
            else:
                self._refuse_to_replace(overwrite)
                self._create()
        except BaseException:
            self._unlock(remove_new_journal=True)
            raise

    # opening

    def _check_target(self, resume: bool, overwrite: bool) -> None:
        """Refuse what may never be written: not a regular file (with `overwrite` too)."""
        if overwrite:
            outputs.check_target(self.path, replace=True, advice="choose another -o")
            return
        if resume:
            try:
                mode = os.lstat(self.path).st_mode
            except FileNotFoundError:
                return
            except OSError as exc:
                raise OutputError(f"cannot be read: {exc.strerror}", str(self.path)) from None
            if not stat.S_ISREG(mode):
                raise ResultFileError(
                    "not a floorslide result file (not a regular file); not replaced (choose "
                    "another -o)",
                    str(self.path),
                )

    def _lock(self) -> None:
        """Create the journal folder if need be and lock it (``flock``, not waiting).

        Raises
        ------
        OutputExistsError
            Another run holds the lock, or the journal's place holds something else.
        """
        for _ in range(5):
            try:
                os.mkdir(self.journal)
                made = True
            except FileExistsError:
                made = False
            except OSError as exc:
                raise OutputError(
                    f"cannot create the journal folder: {exc.strerror}", str(self.journal)
                ) from None
            try:
                fd = os.open(self.journal, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW)
            except OSError:
                kind = "a symbolic link" if self.journal.is_symlink() else "not a folder"
                raise OutputExistsError(
                    f"is {kind}; floorslide keeps the journal of a run there (move it away)",
                    str(self.journal),
                ) from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as exc:
                os.close(fd)
                if made:
                    with contextlib.suppress(OSError):
                        os.rmdir(self.journal)
                if exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                    raise OutputExistsError(
                        "is being written by another floorslide run (its journal is locked); "
                        "wait for that run to end, or write to another file",
                        str(self.path),
                    ) from None
                raise OutputError(
                    f"cannot lock the journal: {exc.strerror}", str(self.journal)
                ) from None
            held, now = os.fstat(fd), None
            with contextlib.suppress(OSError):
                now = os.stat(self.journal)
            if now is not None and (held.st_dev, held.st_ino) == (now.st_dev, now.st_ino):
                self._lock_fd, self._made_journal = fd, made
                return
            os.close(fd)  # the folder was removed (a run ending) between mkdir and flock
        raise OutputError("cannot lock the journal (it keeps being replaced)", str(self.journal))

    def _unlock(self, remove_new_journal: bool = False) -> None:
        """Release the lock; with `remove_new_journal`, remove the journal folder this writer
        created if it is still empty."""
        if remove_new_journal and self._made_journal:
            with contextlib.suppress(OSError):
                os.rmdir(self.journal)
        if self._lock_fd is not None:
            with contextlib.suppress(OSError):
                os.close(self._lock_fd)
            self._lock_fd = None

    def _refuse_to_replace(self, overwrite: bool) -> None:
        if overwrite:
            self._clear_journal()
            return
        if self.path.exists() or self.path.is_symlink():
            raise OutputExistsError(
                "exists; not replaced (continue its run with --resume, same scene; or replace "
                "it with --overwrite)",
                str(self.path),
            )
        entries = journal_entries(self.path)
        if entries:
            raise OutputExistsError(
                f"holds {len(entries)} finished tasks of an unfinished run; continue it with "
                "--resume (same scene) or start again with --overwrite",
                str(self.journal),
            )

    def _clear_journal(self) -> None:
        """Remove what an older run left in the (locked) journal folder."""
        for entry in list(self.journal.iterdir()):
            with contextlib.suppress(OSError):
                if entry.is_dir() and not entry.is_symlink():
                    shutil.rmtree(entry)
                else:
                    entry.unlink()

    def _image(self) -> bytes:
        """A new result file holding no task, as bytes."""
        buf = io.BytesIO()
        with h5py.File(buf, "w") as f:
            _write_header(f, self.scene_text, self.scene_path, self.scene_name, self.plan)
            columns.init(f)
        return buf.getvalue()

    def _create(self) -> None:
        """A new file in place of `path` (written in memory, then as plain bytes, so that a
        full disk is a clean error)."""
        try:
            _write_file(self.path, self._image())
        except OSError as exc:
            raise self._failure(exc, self.path) from None
        self.done = set()
        self.created = True

    def _open_for_resume(self) -> None:
        if not self.path.exists():
            self._create()
            return
        if not self.path.is_file() or not _is_hdf5(self.path):
            raise ResultFileError(
                "not a floorslide result file; not replaced (choose another -o, or replace it "
                "with --overwrite)",
                str(self.path),
            )
        mark = self.journal / WRITING
        cut = mark.exists()
        try:
            reader = ResultFile(self.path, repair=True)
        except UnreadableResultError as exc:
            self.warn(
                f"{self.path}: {exc.message}; it is rebuilt from its journal and the tasks "
                "missing from the journal run again"
            )
            self._create()
            mark.unlink(missing_ok=True)
            return
        if reader.header_problem:
            self.warn(
                f"{self.path}: its stored scene and plan fail their integrity check "
                f"({reader.header_problem}); they are written again, and only tasks whose "
                "inputs match this run's are kept"
            )
        elif reader.scene_text != self.scene_text:
            raise ResultFileError(
                "was written for a different scene; resume with the same scene file",
                str(self.path),
            )
        problems = reader.verify()
        for tid, problem in problems.items():
            self.warn(f"{self.path}: task {tid} fails the integrity check ({problem}); rebuilt")
        self.done = set(reader.done_tasks()) - set(problems)
        if not reader.verified:
            self.warn(
                f"{self.path}: written before floorslide kept task digests; its "
                f"{len(self.done)} finished tasks are kept unverified"
            )
        drop = set(reader.damaged) | set(problems)
        moves = self._reconcile(reader, drop)
        self.kept = set(self.done)
        if cut:
            self.warn(
                f"{self.path}: the last run stopped while writing it; it is written again with "
                f"the {len(self.done)} finished tasks it holds"
            )
        if reader.format != FORMAT or drop or moves or reader.partial or cut:
            # a file of format 1 is converted; tasks dropped or renamed, or a write cut short:
            # the file is written again with the tasks kept (a few large writes)
            self._rebuild(reader, moves)
            mark.unlink(missing_ok=True)
            return
        try:
            _reserve(self.path, RESERVE_MIN + len(json.dumps(self.plan)) * 2)
            with _open_h5(self.path, "a") as f:
                self._header(f)
        except (*H5_ERRORS, OSError) as exc:
            if isinstance(exc, OutputError):
                raise
            self._rebuild(reader, moves)

    def _reconcile(self, reader: ResultFile, drop: set[str]) -> dict[str, str]:
        """Compare the stored tasks' fingerprints with this run's: keep those that match, move
        a task whose inputs are a new task's under another id (a catalog row deleted shifts
        the ids), drop the rest (added to `drop`); say what changed.

        Returns
        -------
        dict
            Moves: stored id → this run's id.
        """
        if self.fingerprints is None:
            return {}
        new = self.fingerprints
        stored = reader.fingerprints(sorted(self.done))
        keep = {tid for tid in self.done if tid in new and stored.get(tid) == new[tid]}
        by_print: dict[str, list[str]] = {}
        for tid in sorted(self.done - keep):
            if stored.get(tid):
                by_print.setdefault(stored[tid], []).append(tid)
        moves = {}
        for tid in sorted(new):
            if tid in keep:
                continue
            sources = by_print.get(new[tid])
            if sources:
                moves[sources.pop(0)] = tid
        gone = self.done - keep - set(moves)
        unprinted = sum(1 for tid in gone if not stored.get(tid))
        changed = sum(1 for tid in gone if stored.get(tid) and tid in new)
        removed = len(gone) - unprinted - changed
        if unprinted:
            self.warn(
                f"{self.path}: {unprinted} finished tasks carry no fingerprint of their inputs "
                "(written by an earlier floorslide); they run again"
            )
        if changed:
            self.warn(
                f"{self.path}: {changed} finished tasks were computed from other inputs (a "
                "record's samples, scale, building, contents, spectra or the floorslide "
                "version changed); they run again"
            )
        if removed:
            self.warn(f"{self.path}: {removed} finished tasks are no longer in the plan; removed")
        if moves:
            self.warn(
                f"{self.path}: {len(moves)} finished tasks keep their results under new task ids "
                "(the plan's tasks shifted; their inputs are unchanged)"
            )
        drop |= gone
        self.done = keep | set(moves.values())
        return moves

    def _header(self, f: h5py.File) -> None:
        _write_header(f, self.scene_text, self.scene_path, self.scene_name, self.plan)

    def _rebuild(self, reader: ResultFile, moves: Mapping[str, str] | None = None) -> None:
        """Rewrite the file (in the format written now) with its verified, current tasks
        only, stored ids renamed by `moves`."""
        moves = moves or {}
        renamed = {dst for dst in moves.values()}
        wanted = {}
        for tid in reader.done_tasks():
            name = moves.get(tid, tid)
            if name in self.done and (tid in moves or tid not in renamed):
                wanted[tid] = name
        tmp = None
        try:
            fd, tmp = outputs.temporary(self.path)
            os.close(fd)
            _write_file(tmp, self._image())
            _reserve(tmp, 2 * self.path.stat().st_size + RESERVE_MIN)
            with _open_h5(tmp, "a") as dst:
                batch = []
                for tid, node, _ in reader.nodes(list(wanted)):
                    if node is None:  # verified a moment ago: only damage since then
                        self.done.discard(wanted[tid])
                        continue
                    batch.append((wanted[tid], node, digest(node)))
                    if len(batch) >= COPY_BATCH:
                        append_tasks(dst, batch, len(wanted))
                        columns.commit(dst)  # the next batch's rows follow these
                        batch = []
                append_tasks(dst, batch, len(wanted))
                columns.commit(dst)
            outputs.replace_atomically(tmp, self.path)
        except (*H5_ERRORS, OSError) as exc:
            if tmp is not None:
                with contextlib.suppress(OSError):
                    tmp.unlink()
            raise self._failure(exc, tmp or self.path) from None

    def _recover_journal(self) -> None:
        """Put the journal's valid entries the file lacks into it; refuse the others."""
        refused = 0
        for entry in sorted(self.journal.iterdir()):
            if entry.name == WRITING:
                continue
            if entry.name.endswith(".tmp"):  # cut short by a kill: that task runs again
                with contextlib.suppress(OSError):
                    entry.unlink()
                continue
            try:
                if not entry.name.endswith(ENTRY_SUFFIX):
                    raise journal.EntryError(
                        "not a floorslide journal entry (pickle files are never loaded: they "
                        "could run code)"
                    )
                if not stat.S_ISREG(os.lstat(entry).st_mode):
                    raise journal.EntryError("not a regular file")
                tid, node = journal.decode(entry.read_bytes(), self.scene_sha256)
                if entry.name != f"{tid}{ENTRY_SUFFIX}":
                    raise journal.EntryError(f"holds task {tid}, not {entry.stem}")
                if self.task_ids is not None and tid not in self.task_ids:
                    raise journal.EntryError(f"{tid} is not a task of this run")
                if self.fingerprints is not None and (
                    _s(node.attrs.get(FINGERPRINT_ATTR, "")) != self.fingerprints[tid]
                ):
                    raise journal.EntryError(
                        "computed from other inputs (a record's samples, scale, building, "
                        "contents, spectra or the floorslide version changed)"
                    )
                _read_task(node, tid)  # the layout of a task, or refused
            except (OSError, journal.EntryError, KeyError, ValueError, TypeError) as exc:
                refused += 1
                if refused <= 10:
                    self.warn(f"{entry}: refused ({exc}); its task runs again")
                continue
            if tid not in self.done and tid not in {t for t, _, _ in self._pending}:
                self._pending.append((tid, node, digest(node)))
            self.kept.add(tid)
        if refused > 10:
            self.warn(f"{self.journal}: {refused - 10} more entries refused; their tasks run again")
        self.flush()

    # writing

    def _failure(self, exc: BaseException, where: Path) -> OutputError:
        kept = len(self.kept)
        if _no_space(exc):
            return OutputError(
                f"no space left on device writing {where}; {kept} tasks kept; free space and "
                "rerun with --resume"
            )
        if _is_lock_conflict(exc):
            return OutputError(
                f"{where} is open in another program (HDF5 file lock); {kept} tasks kept; close "
                "it and rerun with --resume"
            )
        reason = getattr(exc, "strerror", None) or str(exc)
        return OutputError(
            f"cannot write {where}: {reason}; {kept} tasks kept; rerun with --resume"
        )

    def write(self, result: TaskResult) -> None:
        """Journal the task atomically; write it with its digest (a batch of :attr:`batch`
        tasks at once, or every :data:`FLUSH_SECONDS`), close (flush), mark them done.

        Raises
        ------
        OutputError
            One line: what could not be written (a full disk: "no space left on device"), how
            many tasks are kept, and to rerun with ``--resume``.
        """
        if self.fingerprints is not None:
            result.meta[FINGERPRINT_ATTR] = self.fingerprints[result.task_id]
        node = task_node(result)  # holds no bookkeeping attribute: digest(node) is its digest
        node_digest = digest(node)
        tid = result.task_id
        entry = self.journal / f"{tid}{ENTRY_SUFFIX}"
        try:
            _write_file(entry, journal.encode(tid, self.scene_sha256, node, node_digest))
        except OSError as exc:
            raise self._failure(exc, entry) from None
        self.kept.add(tid)
        self._pending.append((tid, node, node_digest))
        due = time.monotonic() - self._last_flush >= FLUSH_SECONDS
        if len(self._pending) >= self.batch or due:
            self.flush()

    @property
    def _expect(self) -> int:
        n = self.plan.get("tasks")
        return n if isinstance(n, int) and n > 0 else len(self.task_ids or ())

    def flush(self) -> None:
        """Write the tasks journaled but not yet in the file (one batch: a few large writes),
        close the file (flushed), then count them done (the tables' ``rows``).

        Raises
        ------
        OutputError
            As :meth:`write`; the tasks stay in the journal.
        """
        self._last_flush = time.monotonic()
        if not self._pending:
            return
        batch, self._pending = self._pending, []
        nbytes = objects = 0
        for _, node, _ in batch:
            b, o = _node_size(node)
            nbytes, objects = nbytes + b, objects + (o if "histories" in node.children else 0)
        if self._columns_stamp is None or self._columns_stamp != _stamp(self.path):
            self._columns.clear()  # changed since (or never written here): read it again
        self._columns_stamp = None
        mark = self.journal / WRITING
        with contextlib.suppress(OSError):
            mark.touch()
        try:
            _reserve(self.path, 2 * nbytes + RESERVE_PER_OBJECT * objects + RESERVE_MIN)
            with _open_h5(self.path, "a") as f:
                append_tasks(f, batch, self._expect, self._columns)
            _reserve(self.path, RESERVE_MIN)
            with _open_h5(self.path, "a") as f:
                columns.commit(f)
        except (*H5_ERRORS, OSError) as exc:
            self._columns.clear()
            raise self._failure(exc, self.path) from None
        finally:
            # HDF5 closed the file, even after an error it reported; only a killed process
            # leaves the mark (then a resume rebuilds the file)
            with contextlib.suppress(OSError):
                mark.unlink()
        self._columns_stamp = _stamp(self.path)
        self.done.update(tid for tid, _, _ in batch)

    def _flush_quietly(self) -> None:
        """Write what is pending if the file takes it (else it stays in the journal)."""
        with contextlib.suppress(OutputError):
            self.flush()
        self._pending = []

    def finish(self) -> None:
        """A completed run: the journal is no longer needed; the lock is released."""
        self.flush()
        shutil.rmtree(self.journal, ignore_errors=True)
        self._unlock()

    def abandon(self) -> None:
        """A run that failed before keeping any task: remove the file it created (and its empty
        journal), so that the same command can simply be run again; the lock is released."""
        self._flush_quietly()
        if self.created and not self.kept:
            with contextlib.suppress(OSError):
                self.path.unlink()
            with contextlib.suppress(OSError):
                self.journal.rmdir()
        self._unlock()

    def close(self) -> None:
        """Write what is pending, release the lock (the journal stays for ``--resume``)."""
        if self._lock_fd is not None:
            self._flush_quietly()
        self._unlock()

    def __enter__(self) -> ResultWriter:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


# --- reading -----------------------------------------------------------------------------


class UnreadableResultError(ResultFileError):
    """A result file that is HDF5 but cannot be read (damaged, cut short by a kill)."""


def _integrity_message(problems: dict[str, str], scene: str, path: Path) -> str:
    names = list(problems)
    if len(names) == 1:
        tid = names[0]
        return (
            f"task {tid} fails the integrity check ({problems[tid]}); rebuild it with "
            f"floorslide run {scene} -o {path} --resume"
        )
    shown = ", ".join(f"{tid} ({problems[tid]})" for tid in names[:3])
    if len(names) > 3:
        shown += f" and {len(names) - 3} more"
    return (
        f"tasks {shown} fail the integrity check; rebuild them with floorslide run {scene} "
        f"-o {path} --resume"
    )


class ResultFile:
    """Read a result file; refuse one that is not a floorslide result or is corrupt.

    Parameters
    ----------
    path
        The result file.
    repair
        Open for ``--resume``: task entries that are not readable groups are listed in
        :attr:`damaged` instead of refusing the file.

    Raises
    ------
    ResultFileError
        Missing, not a floorslide result file, or (:class:`UnreadableResultError`) corrupt.
    """

    def __init__(self, path: str | Path, *, repair: bool = False):
        self.path = Path(path)
        if not self.path.exists():
            raise ResultFileError("no such result file", str(self.path))
        self.damaged: list[str] = []
        """Task entries that are not readable groups (only with `repair`)."""
        self.partial: list[str] = []
        """Task groups not marked done (a write cut short)."""
        self._done: list[str] = []
        try:
            if not _is_hdf5(self.path):
                raise ValueError("not an HDF5 file")
            with _open_h5(self.path, "r", wait=READ_LOCK_WAIT) as f:
                fmt = f.attrs.get("floorslide_format")
                if fmt == FORMAT and all(t in f for t in columns.TABLES):
                    self.format = FORMAT
                elif fmt == LEGACY_FORMAT and "tasks" in f:
                    self.format = LEGACY_FORMAT
                else:
                    raise ResultFileError("not a floorslide result file", str(self.path))
                self.verified = DIGESTS_ATTR in f.attrs
                self.header_problem = _header_problem(f)
                """Why the header fails its integrity check ("" when it passes or predates
                the check); only with `repair`, else the file is refused."""
                if self.header_problem and not repair:
                    raise ResultFileError(
                        f"its stored scene and plan fail their integrity check "
                        f"({self.header_problem}); rebuild it with floorslide run SCENE -o "
                        f"{self.path} --resume",
                        str(self.path),
                    )
                self.scene_text = _s(f["scene"][()])
                self.scene_name = str(f.attrs.get("scene_name", ""))
                self.scene_path = _s(f["scene"].attrs.get("path", ""))
                plan = f["plan"][()]
                self.plan = json.loads(plan.decode() if isinstance(plan, bytes) else plan)
                if not isinstance(self.plan, dict):
                    raise ValueError("the stored plan is not a JSON object")
                tasks = f["tasks"]
                if self.format == FORMAT:
                    self._done = self._ids(f)
                for k in tasks if self.format == LEGACY_FORMAT else ():
                    try:
                        g = tasks.get(k)  # None when a kill left the link but not the group
                        if not isinstance(g, h5py.Group):
                            raise ValueError(f"task {k} is damaged")
                        # every attribute name is listed (damaged attributes raise here, not
                        # read as absent); the writer sets the done mark to 1 or not at all
                        mark = g.attrs["done"] if "done" in set(g.attrs) else None
                        if mark is not None and not (np.ndim(mark) == 0 and mark == 1):
                            raise ValueError(f"task {k} is damaged (its done mark is {mark!r})")
                        done = mark is not None
                    except H5_ERRORS:
                        if not repair:
                            raise
                        self.damaged.append(k)
                        continue
                    (self._done if done else self.partial).append(k)
        except ResultFileError:
            raise
        except H5_ERRORS as exc:
            if _is_lock_conflict(exc):
                raise ResultFileError(
                    "is open for writing in another process (HDF5 file lock); try again when "
                    "it is closed",
                    str(self.path),
                ) from None
            hint = (
                " (rebuild it with floorslide run --resume)"
                if journal_dir(self.path).exists()
                else ""
            )
            raise UnreadableResultError(
                f"corrupt or unreadable result file: {exc}{hint}", str(self.path)
            ) from None

    @staticmethod
    def _ids(f: h5py.File) -> list[str]:
        """The ids of the rows counted in the task table of a file of format 2."""
        g = f["tasks"]
        n = g.attrs["rows"]
        if not (np.ndim(n) == 0 and int(n) == n and n >= 0):
            raise ValueError(f"the task table's row count is damaged ({n!r})")
        if not n:
            return []
        ids = g["id"]
        if not isinstance(ids, h5py.Dataset) or ids.shape[0] < n:
            raise ValueError("the task table is damaged (fewer ids than rows)")
        out = [columns._text(x) for x in ids[: int(n)]]
        if len(set(out)) != len(out):
            raise ValueError("the task table is damaged (an id appears twice)")
        return out

    def done_tasks(self) -> list[str]:
        """Ids of the tasks marked done."""
        return list(self._done)

    def _lookup(self, f: h5py.File) -> Callable[[str], tuple[Node | None, str]]:
        """A function of the open file `f`: a done task's node (checked against its digest)
        and "", or None and why it fails."""
        if self.format == LEGACY_FORMAT:
            tasks = f["tasks"]
            return lambda tid: self._task(tasks, tid)
        try:
            cols = columns.Columns(f, H5_ERRORS)
        except (*H5_ERRORS, SnapshotError) as exc:
            broken = f"unreadable: {exc}"
            return lambda tid: (None, broken)
        return lambda tid: self._column_task(cols, tid)

    def _column_task(self, cols: columns.Columns, tid: str) -> tuple[Node | None, str]:
        try:
            node = cols.node(tid)
            stored = cols.digest_of(tid)
        except (SnapshotError, *H5_ERRORS) as exc:
            return None, f"unreadable: {exc}"
        if not stored:
            return None, "no digest"
        return self._checked(node, stored, tid, frozenset())

    def _checked(self, node: Node, stored, tid: str, skip: frozenset) -> tuple[Node | None, str]:
        try:
            ok = _s(stored) == digest(node, skip)
        except SnapshotError as exc:
            return None, f"unreadable: {exc}"
        if not ok:
            return None, "values changed after it was written"
        planned = self.planned_fingerprints
        if planned is not None and _s(node.attrs.get(FINGERPRINT_ATTR, "")) != planned.get(tid):
            return None, "computed from other inputs than the stored plan's: two runs mixed"
        return node, ""

    def nodes(self, tids: Collection[str]) -> Iterator[tuple[str, Node | None, str]]:
        """Each task of `tids` as its node (without bookkeeping attributes, its digest is the
        task's) and "", or None and why it fails its integrity check."""
        with _open_h5(self.path, "r", wait=READ_LOCK_WAIT) as f:
            lookup = self._lookup(f)
            for tid in tids:
                node, problem = lookup(tid)
                if node is not None and BOOKKEEPING & set(node.attrs):
                    node = Node(
                        {k: v for k, v in node.attrs.items() if k not in BOOKKEEPING},
                        node.children,
                    )
                yield tid, node, problem

    @property
    def planned_fingerprints(self) -> dict[str, str] | None:
        """The fingerprint of each planned task's inputs, from the stored plan (None in files
        written before floorslide kept them)."""
        prints = self.plan.get("fingerprints")
        return prints if isinstance(prints, dict) and not self.header_problem else None

    def fingerprints(self, tids: Collection[str]) -> dict[str, str]:
        """The stored fingerprint of the inputs of each task of `tids` ("" where none is
        stored or the group cannot be read)."""
        out = {}
        with _open_h5(self.path, "r") as f:
            if self.format == FORMAT:
                try:
                    cols = columns.Columns(f, H5_ERRORS)
                except (*H5_ERRORS, SnapshotError):
                    return dict.fromkeys(tids, "")
                for tid in tids:
                    value = cols.attr(tid, FINGERPRINT_ATTR) if tid in cols.row_of else None
                    out[tid] = "" if value is None else _s(value)
                return out
            tasks = f["tasks"]
            for tid in tids:
                try:
                    out[tid] = _s(tasks[tid].attrs.get(FINGERPRINT_ATTR, ""))
                except H5_ERRORS:
                    out[tid] = ""
        return out

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

    def _task(self, tasks: h5py.Group, tid: str) -> tuple[Node | None, str]:
        """A done task's group, read whole, and ``""`` — or None and why it fails."""
        try:
            node = snapshot(tasks[tid])
        except (SnapshotError, *H5_ERRORS) as exc:
            return None, f"unreadable: {exc}"
        stored = node.attrs.get(DIGEST_ATTR)
        if stored is None:
            return (None, "no digest") if self.verified else (node, "")
        return self._checked(node, stored, tid, BOOKKEEPING)

    def verify(self) -> dict[str, str]:
        """Every done task that fails its integrity check, with why (empty when all pass)."""
        problems = {}
        with _open_h5(self.path, "r") as f:
            lookup = self._lookup(f)
            for tid in self._done:
                node, problem = lookup(tid)
                if node is None:
                    problems[tid] = problem
        return problems

    def tasks(self) -> Iterator[TaskResult]:
        """Every finished task, in file order, each checked against its digest.

        Raises
        ------
        ResultFileError
            A task fails its integrity check (every failing task is named) or the file is
            corrupt.
        """
        legacy = self._legacy_broadening()
        try:
            with _open_h5(self.path, "r", wait=READ_LOCK_WAIT) as f:
                lookup = self._lookup(f)
                for i, tid in enumerate(self._done):
                    node, problem = lookup(tid)
                    if node is None:
                        problems = {tid: problem}
                        for other in self._done[i + 1 :]:
                            if (found := lookup(other))[0] is None:
                                problems[other] = found[1]
                        scene = self.scene_path or "SCENE.toml"
                        raise ResultFileError(
                            _integrity_message(problems, scene, self.path), str(self.path)
                        )
                    yield _read_task(node, tid, legacy)
        except ResultFileError:
            raise
        except (*H5_ERRORS, AttributeError) as exc:
            raise ResultFileError(f"corrupt result file: {exc}", str(self.path)) from None


def _header_problem(f: h5py.File) -> str:
    """Why the header of the open result file `f` fails its integrity check, or ""."""
    scheme = f.attrs.get(DIGESTS_ATTR)
    if scheme is None:  # written before floorslide kept digests: read unverified, with a note
        return ""
    stored = f.attrs.get(HEADER_DIGEST_ATTR)
    if stored is None:  # written before the header had a digest
        return "no digest" if _s(scheme) == INTEGRITY else ""
    if _s(scheme) != INTEGRITY:
        return f"the integrity scheme is {_s(scheme)!r}"
    try:
        ok = _s(stored) == header_digest(f)
    except (SnapshotError, *H5_ERRORS) as exc:
        return f"unreadable: {exc}"
    return "" if ok else "changed after it was written"


def _journal_of(path: Path, scene_sha256: str) -> bool:
    """Whether a journal entry beside `path` was written for the scene of this digest."""
    for entry in journal_entries(path):
        try:
            journal.decode(entry.read_bytes(), scene_sha256)
        except (OSError, journal.EntryError):
            continue
        return True
    return False


def written_for(path: str | Path, scene_text: str) -> bool:
    """Whether `path` holds a run of the scene `scene_text`: a floorslide result file of that
    scene, or the unreadable remains of one (a run killed mid-write) whose journal is of it.

    Parameters
    ----------
    path
        The file (it may be missing: then False).
    scene_text
        The scene's text, as stored in ``/scene``.
    """
    path = Path(path)
    if not path.is_file():
        return False
    try:
        return ResultFile(path).scene_text == scene_text
    except UnreadableResultError:
        return _journal_of(path, scene_digest(scene_text))
    except ResultFileError:
        return False


def _s(value) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


def _group(node: Node, name: str) -> Node:
    child = node[name]
    if not isinstance(child, Node):
        raise ValueError(f"{name} is not a group")
    return child


def _value(node: Node, name: str):
    child = node[name]
    if not isinstance(child, Data):
        raise ValueError(f"{name} is not a dataset")
    return child.value


def _groups(node: Node) -> Iterator[tuple[str, Node]]:
    for name, child in node.items():
        if not isinstance(child, Node):
            raise ValueError(f"{name} is not a group")
        yield name, child


def _read_spectrum(k: str, h: Node, legacy_broadening: float) -> SpectrumResult:
    floor = int(k.split("_")[1])
    fields = {n: _value(h, n) for n in SPECTRUM_FIELDS}
    if "broadening" not in h.attrs and legacy_broadening > 0:
        # written before the unbroadened spectra were kept: what is stored is broadened
        wide = {f"{n}_broadened": fields[n] for n in ORDINATE_FIELDS}
        lost = {n: np.full_like(fields[n], np.nan, dtype=float) for n in ORDINATE_FIELDS}
        return SpectrumResult(floor, **{**fields, **lost}, broadening=legacy_broadening, **wide)
    out = SpectrumResult(floor, **fields, broadening=float(h.attrs.get("broadening", 0.0)))
    if "orientation" in h.attrs:
        out.orientation = _s(h.attrs["orientation"])
        for name in ROTD_FIELDS:
            setattr(out, name, _value(h, name))
    if "broadened" in h:
        b = _group(h, "broadened")
        for n in ORDINATE_FIELDS:
            setattr(out, f"{n}_broadened", _value(b, n))
    return out


def _read_task(g: Node, tid: str, legacy_broadening: float = 0.0) -> TaskResult:
    """The task stored in the group `g` (read whole with :func:`snapshot`).

    Raises
    ------
    KeyError, ValueError
        `g` is not a task's group.
    """
    meta = {
        k: (v.item() if hasattr(v, "item") else v)
        for k, v in g.attrs.items()
        if k not in BOOKKEEPING
    }
    meta = {k: _s(v) if isinstance(v, bytes | str) else v for k, v in meta.items()}
    contents = []
    for cname, cg in _groups(_group(g, "contents")):
        for fname, h in _groups(cg):
            contents.append(
                ContentResult(
                    content=cname,
                    floor=int(fname.split("_")[1]),
                    model=_s(h.attrs["model"]),
                    mode=_s(h.attrs["mode"]),
                    skipped=_s(h.attrs["skipped"]),
                    vertical=bool(h.attrs["vertical"]),
                    **{name: _value(h, name) for name in CONTENT_FIELDS},
                    peak_deformation=_value(h, "peak_deformation")
                    if "peak_deformation" in h
                    else None,
                    peak_top_accel=_value(h, "peak_top_accel") if "peak_top_accel" in h else None,
                    coupled_pfa=_value(h, "coupled_pfa") if "coupled_pfa" in h else None,
                    modes=np.array([_s(m) for m in _value(h, "modes")]) if "modes" in h else None,
                    **_rocking_of(h),
                    **{n: _value(h, n) for n in PLANE_FIELDS if n in h},
                )
            )
    spectra = [_read_spectrum(k, h, legacy_broadening) for k, h in _groups(_group(g, "spectra"))]
    hist = None
    if "histories" in g:
        hg = _group(g, "histories")
        slides, mus, deform, top, plane = {}, {}, {}, {}, {}
        if "slides" in hg:
            for cname, cg in _groups(_group(hg, "slides")):
                for fname, h in _groups(cg):
                    key = f"{cname}/{fname}"
                    slides[key] = _value(h, "u")
                    mus[key] = _value(h, "mu_k")
                    if "u_plane" in h:
                        plane[key] = _value(h, "u_plane")
                    if "z" in h:
                        deform[key], top[key] = _value(h, "z"), _value(h, "top_accel")
        rocking = {}
        if "rocking" in hg:
            for cname, cg in _groups(_group(hg, "rocking")):
                for fname, h in _groups(cg):
                    rocking[f"{cname}/{fname}"] = _value(h, "theta_ratio")
        hist = Histories(
            float(hg.attrs["dt"]),
            _value(hg, "floors"),
            _value(hg, "floor_acceleration"),
            slides,
            mus,
            deform,
            top,
            **{n: _value(hg, n) if n in hg else None for n in ISOLATOR_HISTORIES},
            rocking=rocking,
            plane=plane,
            floor_acceleration_h2=_value(hg, "floor_acceleration_h2")
            if "floor_acceleration_h2" in hg
            else None,
        )
    return TaskResult(
        task_id=tid,
        meta=meta,
        floors=_value(g, "floors"),
        pfa=_value(g, "pfa"),
        pfa_components=_value(g, "pfa_components") if "pfa_components" in g else None,
        contents=contents,
        spectra=spectra,
        histories=hist,
        seconds=float(g.attrs.get("seconds", 0.0)),
    )


# --- converting ----------------------------------------------------------------------------


def upgrade(src: str | Path, dst: str | Path | None = None) -> tuple[Path, int]:
    """Convert a result file of format 1 (one group per task) to the format written now.

    Every task is read through the reader of format 1 and checked against its digest (a file
    with a task that fails is refused: rebuild it with ``floorslide run --resume`` first), then
    written as rows of the tables with the same digest; the header (scene, plan, scene name,
    creation time) is kept. The file is written beside `dst` and renamed into place at the end.

    Parameters
    ----------
    src
        The file of format 1.
    dst
        The new file (default: `src`, replaced).

    Returns
    -------
    (path, tasks)
        The file written and the number of tasks converted.

    Raises
    ------
    ResultFileError
        `src` is not a floorslide result file, is already of this format, or a task fails its
        integrity check.
    OutputError
        `dst` cannot be written.
    """
    src = Path(src)
    dst = src if dst is None else Path(dst)
    reader = ResultFile(src)
    if reader.format == FORMAT:
        raise ResultFileError(f"already of format {FORMAT}; nothing to upgrade", str(src))
    problems = reader.verify()
    if problems:
        scene = reader.scene_path or "SCENE.toml"
        raise ResultFileError(_integrity_message(problems, scene, src), str(src))
    if dst != src:
        outputs.check_target(dst, replace=False, advice="choose another -o")
    with _open_h5(src, "r") as f:
        created = f.attrs.get("created")
    tmp = None
    try:
        dst.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = outputs.temporary(dst)
        os.close(fd)
        with h5py.File(tmp, "w") as f:
            if created is not None:
                f.attrs["created"] = created
            _write_header(f, reader.scene_text, reader.scene_path, reader.scene_name, reader.plan)
            columns.init(f)
            done = reader.done_tasks()
            batch: list[tuple[str, Node, str]] = []
            for tid, node, problem in reader.nodes(done):
                if node is None:
                    raise ResultFileError(_integrity_message({tid: problem}, "SCENE", src))
                batch.append((tid, node, digest(node)))
                if len(batch) >= COPY_BATCH:
                    append_tasks(f, batch, len(done))
                    columns.commit(f)  # the next batch's rows follow these
                    batch = []
            append_tasks(f, batch, len(done))
            columns.commit(f)
        outputs.replace_atomically(tmp, dst)
        tmp = None
    except (*H5_ERRORS, OSError) as exc:
        if isinstance(exc, ResultFileError | OutputError):
            raise
        reason = getattr(exc, "strerror", None) or str(exc)
        raise OutputError(f"cannot write {dst}: {reason}") from None
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                Path(tmp).unlink()
    return dst, len(done)
