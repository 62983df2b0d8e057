"""Figures from a result file (docs/design.md §3, ``floorslide plot``), drawn with matplotlib (Agg).

One figure per kind and record set, with one panel per floor or per content on a floor:

``histories_<set>.png``
    floor accelerations and sliding histories of the study's history record (the task(s) that
    stored histories), one column per building;
``hysteresis_<set>.png``
    buildings on nonlinear isolation only: the isolator's hysteresis loop under the history
    record, force / W against isolator displacement (mm), one panel per building, with the
    peak displacement and the capacity (when given; red when exceeded) marked;
``rocking_<set>.png``
    contents that rock under the history record only: their rotation over their slenderness
    ``θ/α`` against time, one panel per building (at most 4), the lines ``θ/α = ±1`` (the
    block overturns there) marked, an overturning marked where it happens;
``frs_<set>.png``
    floor response spectra: median PSA over the set's records per building, one panel per
    floor, log period axis;
``slide_vs_mu_<set>.png``
    peak slide versus kinetic friction: median (line) and 84th percentile (open triangles) per
    building, one panel per content and floor; where a statistic falls on rocking records
    (objects that rock are not simulated as sliders) it is drawn as a marker at the top of the
    panel — never as 0;
``oscillators_<set>.png``
    2-DOF (flexible) equipment only: peak spring deformation and the top mass's peak absolute
    acceleration versus kinetic friction, median and 84th percentile per building;
``overturning_<set>.png``
    contents with rocking results only (the ``rocking`` table): the fraction of the set's
    records under which each rocked and overturned, against the buildings (their isolation
    period when every one is an isolation variant; else one position per building, in the
    tables' order), one series per content and floor;
``slide_ratio_<set>_<A>-over-<B>.png``
    median peak-slide ratio A / B versus the isolation period of A (or of B when A is
    fixed-base; building pairs side by side when neither is isolated), one curve per friction
    coefficient, per comparison (as in the design tables);
``scaled_spectra_<set>.png``
    sets scaled to a target spectrum whose file holds floor-0 spectra of a fixed-base
    building at the scaling's damping: each record's scaled PSA, their mean, the target times
    the set's level and 90 % of it, the fitting range, the suite check in the title;
``pfa_profile_<set>.png``
    PFA/PGA up the height (floor on the y axis), median and 84th percentile per building, one
    panel per building kind, beside the ASCE 7-22 §13.3.1 floor amplification ``H_f`` (Eq.
    13.3-4) of each fixed-base building (none for isolated buildings: ASCE 7-22 §17);
``slide_ecdf_<set>.png``
    the empirical distribution of the peak slide over the records, one step curve per
    building, one panel per content and floor at the content's median friction value;
    records where the object rocks are never drawn as a slide of 0 (the curve ends at the
    fraction of records that slide or rest); allowable displacements marked;
``fragility_<family>.png``
    per set family with a ``fragility`` table (stripes of scaled records): the fraction of
    each stripe's records exceeding each damage state and the fitted lognormal fragility
    (Baker 2015), one panel per building, floor, content and friction value.

A figure whose data the file does not hold (no nonlinear isolation, no 2-DOF equipment, no
rocking results — contents without width and height, or a file written before rocking was
simulated) is not drawn, and :func:`plot_figures` does not list it.

A single design reads as one: with one friction coefficient (one isolation period) the x axis
of the friction (ratio) figures is centred on it with a single tick, the buildings side by side
at it, and a statistic of 0 is drawn whole on the axis.

Every figure states its statistic and number of records; a result file whose run is not
finished is refused unless ``allow_incomplete``, and then every figure's title starts with
INCOMPLETE (in red).

Figures are built on :class:`matplotlib.figure.Figure` objects (no pyplot state) and written as
PNG without a timestamp, so the same result file gives the same files.
"""

from __future__ import annotations

import contextlib
import functools
import io
import math
import os
import re
import threading
from collections import defaultdict
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from floorslide import outputs
from floorslide.constants import G
from floorslide.errors import ModelError
from floorslide.report.columns import MIN_RECORDS, ROCK, DesignTables
from floorslide.report.practice import allowables, fixed_period, pfa_profiles
from floorslide.report.statistics import interpolate_spectrum, summarize
from floorslide.report.study import Study, _natural, _rank, load_study
from floorslide.report.tables import design_tables, resolve_damping
from floorslide.run.results import TaskResult
from floorslide.run.store import ResultFile

MAX_PANELS = 12
"""At most this many panels per figure (floors or content × floor, evenly picked)."""

MAX_COLUMNS = 2
"""At most this many buildings side by side in the history figure (more go to further rows:
the figure stays readable at a page's width)."""

MAX_BUILDING_PANELS = 4
"""At most this many buildings (one panel each) in the hysteresis and rocking figures."""

MAX_HISTORY_BUILDINGS = 8
"""At most this many buildings in the history figure (evenly picked beyond; its title says
how many of how many)."""

SLIDE_LINTHRESH = 1e-3
"""Peak-slide axes are symmetric-log, linear below this slide (m) so that zero shows."""

DPI = 110


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9._-]+", "_", text).strip("_") or "x"


def _pick(items: Sequence, cap: int = MAX_PANELS) -> tuple[list, bool]:
    """At most `cap` items, evenly spaced, first and last kept; and whether some were left."""
    items = list(items)
    if len(items) <= cap:
        return items, False
    idx = np.unique(np.linspace(0, len(items) - 1, cap).round().astype(int))
    return [items[i] for i in idx], True


def _grid(n: int, width: float = 4.8, height: float = 3.5) -> tuple[int, int, tuple]:
    ncols = min(3, max(n, 1))
    nrows = math.ceil(max(n, 1) / ncols)
    return nrows, ncols, (max(width * ncols + 2.4, 8.5), height * nrows + 1.2)


def _new_figure(n: int, **kw) -> tuple[Figure, list]:
    nrows, ncols, size = _grid(n, **kw)
    fig = Figure(figsize=size, layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False).ravel().tolist()
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig, axes[:n]


def building_colors(study: Study) -> dict[str, object]:
    """A fixed colour per building: fixed-base in black and greys, isolated variants along
    viridis in order of isolation period."""
    fixed = [b for b in study.buildings.values() if b.kind != "isolated"]
    isolated = [b for b in study.buildings.values() if b.kind == "isolated"]
    greys = ["black", "dimgray", "darkgray", "silver"]
    out: dict[str, object] = {b.id: greys[i % len(greys)] for i, b in enumerate(fixed)}
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    for i, b in enumerate(isolated):
        out[b.id] = cmap(0.05 + 0.85 * (i / max(len(isolated) - 1, 1)))
    return out


def _floor_label(study: Study, floor: int, buildings: Sequence[str]) -> str:
    if floor != 0:
        return f"floor {floor}"
    kinds = {study.buildings[b].kind for b in buildings}
    if kinds == {"isolated"}:
        return "floor 0 (base mat)"
    if "isolated" in kinds:
        return "floor 0 (ground / base mat)"
    return "floor 0 (ground)"


def _suptitle(fig: Figure, study: Study, text: str) -> None:
    """The figure's title, wrapped to the figure's width; INCOMPLETE first (in red) when
    tasks are missing (docs/design.md §10)."""
    import textwrap

    if study.status:
        text = f"INCOMPLETE: {study.tasks_done} of {study.tasks_planned} tasks done — {text}"
    width = max(40, int(fig.get_figwidth() * 10.5))
    lines = [textwrap.fill(line, width, break_on_hyphens=False) for line in text.split("\n")]
    fig.suptitle("\n".join(lines), color="red" if study.status else "black")


def _few(n: int) -> str:
    """The caution of a statistic over few records, for titles (``""`` when enough)."""
    if n >= MIN_RECORDS:
        return ""
    return f"; caution: only {n} records (< {MIN_RECORDS}), the p84 is set by the largest"


def _png(fig: Figure | None) -> bytes | None:
    """The figure as PNG bytes (no time stamp or software version: the same figure gives the
    same bytes; ``Software`` is :data:`floorslide.outputs.PNG_SOFTWARE`, by which a figure of
    an earlier run is recognised and replaced), None for no figure; drawn by
    :func:`png_bytes`."""
    if fig is None:
        return None
    return png_bytes(fig, DPI, {"Software": outputs.PNG_SOFTWARE})


# --------------------------------------------------------------------------------------------
# saving: the bytes of Figure.savefig for less CPU


def png_bytes(fig: Figure, dpi: float, metadata: dict[str, str] | None = None) -> bytes:
    """The figure as PNG bytes: the bytes of ``fig.savefig(buf, format="png", dpi=dpi,
    metadata=metadata)`` (Agg), for about a third less CPU on the report's figures.

    ``savefig`` on a figure with a layout engine draws it twice: once with the drawing turned
    off (the engine runs inside it: constrained layout measures every Axes twice, tick labels
    and titles included), then for real. Here the engine runs once, on the renderer the PNG is
    drawn with, and the figure is saved with the engine off (no draw for nothing). While it is
    laid out and drawn, each axis reuses its ticks and their labels' extents as long as its
    place, limits, locator and formatter are the same (an Axes is measured several times a
    pass: title, axis labels, spines), and the string metrics and mathtext parses are shared
    by the figures a process draws (:class:`_TextCache`). Nothing drawn changes: the same
    calls give the same numbers, and ``tests/report/test_figure_speed.py`` checks the bytes
    against ``savefig``.

    Parameters
    ----------
    fig
        The figure (its canvas, dpi and layout engine are as before on return).
    dpi
        Resolution, dots per inch.
    metadata
        PNG text chunks, as for ``savefig`` (e.g. ``{"Software": ...}``).

    Returns
    -------
    bytes
        The PNG file.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.layout_engine import PlaceHolderLayoutEngine

    buf = io.BytesIO()
    engine = fig.get_layout_engine()
    old_canvas, old_dpi = fig.canvas, fig.dpi
    with _SAVE_LOCK:
        canvas = FigureCanvasAgg(fig)
        try:
            fig.dpi = dpi
            _TEXT.bind(canvas.get_renderer())
            with _reused_ticks(fig):
                if (
                    engine is not None
                    and fig.axes
                    and not isinstance(engine, PlaceHolderLayoutEngine)
                ):
                    try:
                        engine.execute(fig)
                    except ValueError:  # as Figure.draw: the engine may not fit (tiny figure)
                        pass
                    _set_layout_engine(fig, None)
                fig.savefig(buf, dpi=dpi, format="png", metadata=metadata)
        finally:
            if fig.get_layout_engine() is not engine:
                fig.set_layout_engine(engine)
            fig.dpi = old_dpi
            fig.set_canvas(old_canvas)
    return buf.getvalue()


_SAVE_LOCK = threading.RLock()
"""One :func:`png_bytes` at a time in a process (the shared :class:`_TextCache` settings are
checked and bound to one renderer at a time)."""


def _set_layout_engine(fig: Figure, engine) -> None:
    """``fig.set_layout_engine(engine)``, None meaning none whatever the rcParams say (no
    place holder either: ``savefig`` would draw the figure once for nothing again)."""
    import matplotlib as mpl

    with mpl.rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
        fig.set_layout_engine(engine)


class _TextCache:
    """String metrics and the mathtext parser shared by the figures a process draws.

    Agg measures a string from the string, its font properties, whether it is mathtext and the
    resolution, whatever the figure; matplotlib keeps these per renderer, i.e. per figure, and
    parses each figure's mathtext again. Everything is dropped when a ``text.*``, ``font.*`` or
    ``mathtext.*`` setting or the renderer's class changes, and past :attr:`LIMIT` entries.
    """

    LIMIT = 50_000

    def __init__(self) -> None:
        self.settings: tuple = ()
        self.metrics: dict[tuple, tuple[float, float, float]] = {}
        self.mathtext = None

    def bind(self, renderer) -> None:
        """Let `renderer` (a new one: one per figure) measure strings and parse mathtext
        through the shared cache."""
        import matplotlib as mpl

        rc = mpl.rcParams  # by key: reading them all would resolve the backend (pyplot)
        settings = (
            type(renderer),
            *((k, repr(rc[k])) for k in rc if k.startswith(_TEXT_SETTINGS)),
        )
        if settings != self.settings or len(self.metrics) > self.LIMIT:
            self.settings, self.metrics, self.mathtext = settings, {}, None
        parser = getattr(renderer, "mathtext_parser", None)
        if parser is not None:
            if self.mathtext is None:
                self.mathtext = parser
            else:
                renderer.mathtext_parser = self.mathtext
        measure = renderer.get_text_width_height_descent
        metrics = self.metrics

        def cached(s, prop, ismath):
            if ismath == "TeX":
                return measure(s, prop, ismath)
            key = (s, prop.copy(), ismath, renderer.dpi)
            out = metrics.get(key)
            if out is None:
                out = metrics[key] = measure(s, prop, ismath)
            return out

        renderer.get_text_width_height_descent = cached

    def forget_parser(self) -> None:
        """Drop the shared mathtext parser (in a forked process: its parses hold the parent's
        FreeType faces, which read the font file through a descriptor the processes share —
        two processes drawing glyphs through it at once read each other's bytes)."""
        self.mathtext = None


_TEXT_SETTINGS = ("text.", "font.", "mathtext.")
_TEXT = _TextCache()
if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_TEXT.forget_parser)


def _all_axes(fig: Figure) -> list:
    """The figure's Axes and their child Axes (insets), each once."""
    out: list = []
    todo = list(fig.axes)
    while todo:
        ax = todo.pop(0)
        if not any(ax is a for a in out):
            out.append(ax)
            todo.extend(getattr(ax, "child_axes", ()))
    return out


def _axis_state(axis) -> tuple:
    """What an axis' ticks and their labels' extents depend on while a figure is laid out and
    drawn: its Axes' place (pixels), its view and data limits, its locators and formatters
    (and the place and limits of the axis they belong to, if another: shared axes); limits and
    places as bytes (cheap; exact)."""
    state: list = [
        axis.axes.bbox.get_points().tobytes(),
        np.asarray(axis.get_view_interval()).tobytes(),
        np.asarray(axis.get_data_interval()).tobytes(),
        axis.get_minpos(),
    ]
    for ticker in (axis.major, axis.minor):
        for part in (ticker.locator, ticker.formatter):
            state.append(id(part))
            owner = getattr(part, "axis", None)
            if owner is not None and owner is not axis:
                state += [
                    id(owner),
                    owner.axes.bbox.get_points().tobytes(),
                    np.asarray(owner.get_view_interval()).tobytes(),
                ]
    return tuple(state)


_REUSED = ("_update_ticks", "_get_ticklabel_bboxes")


@contextlib.contextmanager
def _reused_ticks(fig: Figure):
    """While in it, each axis of `fig` computes its ticks (locator, formatter, labels) and its
    tick labels' extents once per :func:`_axis_state`: matplotlib does it for the axis itself,
    its label, its Axes' title and spines, several times per layout pass and draw."""
    patched = []
    for ax in _all_axes(fig):
        for name in ("xaxis", "yaxis", "zaxis"):
            axis = getattr(ax, name, None)
            if axis is None or not all(hasattr(axis, m) for m in _REUSED):
                continue
            update, extents = axis._update_ticks, axis._get_ticklabel_bboxes
            memo: dict[str, tuple] = {}

            def reused_update(axis=axis, update=update, memo=memo):
                key = _axis_state(axis)
                hit = memo.get("ticks")
                if hit is None or hit[0] != key:
                    hit = memo["ticks"] = (key, update())
                return list(hit[1])

            def reused_extents(ticks, renderer, axis=axis, extents=extents, memo=memo):
                key = (_axis_state(axis), [id(t) for t in ticks], id(renderer))
                hit = memo.get("extents")
                if hit is None or hit[0] != key:
                    hit = memo["extents"] = (key, extents(ticks, renderer))
                return list(hit[1][0]), list(hit[1][1])

            patched.append((axis, {n: axis.__dict__[n] for n in _REUSED if n in axis.__dict__}))
            axis._update_ticks = reused_update
            axis._get_ticklabel_bboxes = reused_extents
    try:
        yield
    finally:
        for axis, before in patched:
            for name in _REUSED:
                if name in before:
                    setattr(axis, name, before[name])
                else:
                    axis.__dict__.pop(name, None)


_JOBS: list[Callable[[], Figure | None]] = []
"""The figure jobs of the :func:`_render` in progress, inherited by its forked workers."""


def _draw(i: int) -> bytes | None:
    return _png(_JOBS[i]())


def _render(jobs: list[Callable[[], Figure | None]], workers: int) -> list[bytes | None]:
    """Draw every job's figure as PNG bytes, in order; in `workers` forked processes when more
    than one is asked for and the platform forks (the figures are independent; matplotlib's
    layout and text rendering, ~0.3 s a figure with :func:`png_bytes`, is where a report's time
    goes); never more processes than figures nor than :func:`floorslide.parallel.worker_count`
    allows."""
    import multiprocessing

    from floorslide.parallel import worker_count

    workers = worker_count(int(workers), len(jobs))[0]
    if workers <= 1 or "fork" not in multiprocessing.get_all_start_methods():
        return [_png(job()) for job in jobs]
    _JOBS[:] = jobs
    try:
        with multiprocessing.get_context("fork").Pool(workers, initializer=_worker_signals) as pool:
            out = pool.map(_draw, range(len(jobs)), chunksize=1)
            # the workers end on their own (a terminate's SIGTERM could meet a handler the
            # command installed, inherited by the fork, and leave a worker waiting for ever)
            pool.close()
            pool.join()
            return out
    finally:
        _JOBS.clear()


def _worker_signals() -> None:
    """A figure worker leaves interruptions to the command: Ctrl-C (sent to the whole process
    group) is ignored, SIGTERM and SIGHUP take their default action (the command's handlers,
    inherited by the fork, would raise inside the pool's queue and could leave it locked)."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for name in ("SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_DFL)


# --------------------------------------------------------------------------------------------
# figures


_HISTORY_ROWS = {
    "u": ("slide u (m)", "slide relative to the floor"),
    "z": ("spring deformation z (m)", "spring deformation (top relative to base)"),
    "top": ("top acceleration (m/s²)", "top mass absolute acceleration"),
}


def _history_curves(h, key: str, kind: str) -> np.ndarray | None:
    source = {"u": h.slides, "z": h.deformation, "top": h.top_accel}[kind]
    return np.atleast_2d(source[key]) if key in source else None


def _stored_friction(study: Study, tasks: Sequence[TaskResult], keys: Sequence[str]) -> str:
    """What the history figure says of its friction values: for each content and floor whose
    histories hold fewer friction values than it has (the result file keeps those of
    :data:`floorslide.run.task.HISTORY_MU`), which of how many; ``""`` when all are drawn."""
    parts = []
    for k in keys:
        content, floor = k.rsplit("/floor_", 1)
        drawn = sorted(
            {float(m) for t in tasks for m in np.atleast_1d(t.histories.mu_k.get(k, []))}
        )
        every = sorted(
            {
                float(m)
                for t in tasks
                for c in t.contents
                if c.content == content and int(c.floor) == int(floor)
                for m in np.atleast_1d(c.mu_k)
            }
        )
        if drawn and len(drawn) < len(every):
            shown = ", ".join(f"{m:g}" for m in drawn)
            parts.append(
                f"{content} on floor {floor}: slide histories of {len(drawn)} of its "
                f"{len(every)} friction values (mu = {shown}; the file stores these)"
            )
    return "; ".join(parts)


def figure_histories(study: Study, record_set: str) -> Figure | None:
    """Floor accelerations and sliding histories of the set's history task(s), or None.

    One column per building that stored histories, at most :data:`MAX_COLUMNS` side by side
    (more go to further rows) and at most :data:`MAX_HISTORY_BUILDINGS` (evenly picked; the
    title says how many of how many); row 1: the absolute acceleration of every output floor
    (m/s²); next rows: the slide ``u`` (m, relative to the floor; of the sliding base for an
    oscillator) of each content on each floor, one curve per stored friction value — the
    title says which of the content's friction values the file stores histories of — and for
    2-DOF oscillators also the spring deformation and the top mass's absolute acceleration. A
    friction value under which the object rocks has no curve (it is not simulated as a
    slider): its legend entry says so.
    """
    order = list(study.buildings)
    tasks = sorted(
        (t for t in study.set_tasks(record_set) if t.histories is not None),
        key=lambda t: order.index(t.meta["building"]),
    )
    if not tasks:
        return None
    n_buildings = len(tasks)
    tasks, building_cut = _pick(tasks, MAX_HISTORY_BUILDINGS)
    keys: list[str] = []
    oscillators: set[str] = set()
    for t in tasks:
        for k in t.histories.slides:
            if k not in keys:
                keys.append(k)
        oscillators |= set(getattr(t.histories, "deformation", {}))

    def key_order(k: str):
        content, floor = k.rsplit("/floor_", 1)
        rank = study.contents.index(content) if content in study.contents else len(study.contents)
        return (rank, content, int(floor))

    keys = sorted(keys, key=key_order)
    keys, cut = _pick(keys, 6)
    rows = [(k, kind) for k in keys for kind in (("u", "z", "top") if k in oscillators else ("u",))]
    per_block = 1 + len(rows)
    ncols = min(MAX_COLUMNS, len(tasks))
    blocks = math.ceil(len(tasks) / ncols)
    nrows = blocks * per_block
    fig = Figure(figsize=(5.6 * ncols + 1.0, 2.6 * nrows + 1.0), layout="constrained")
    grid = fig.subplots(nrows, ncols, squeeze=False, sharex=True)
    for j in range(len(tasks), blocks * ncols):  # the empty end of the last row of buildings
        for i in range(per_block):
            grid[(blocks - 1) * per_block + i][j % ncols].set_visible(False)
    from matplotlib import colormaps

    records = sorted({str(t.meta["record"]) for t in tasks})
    said = []
    if building_cut:
        shown = ", ".join(str(t.meta["building"]) for t in tasks)
        said.append(f"{len(tasks)} of the {n_buildings} buildings (evenly picked: {shown})")
    friction = _stored_friction(study, tasks, keys)
    if friction:
        said.append(friction)
    _suptitle(
        fig,
        study,
        f"Floor motions and sliding — record {', '.join(records)}, set {record_set}"
        + (" (some panels left out)" if cut else "")
        + ("\n" + "; ".join(said) if said else ""),
    )
    for j, t in enumerate(tasks):
        top, col = (j // ncols) * per_block, j % ncols
        axes = [grid[top + i][col] for i in range(per_block)]
        h = t.histories
        time = np.arange(h.floor_acceleration.shape[-1]) * h.dt
        ax = axes[0]
        floors = np.asarray(h.floors).tolist()
        cmap = colormaps["plasma"]
        pair = getattr(h, "floor_acceleration_h2", None) is not None
        for i, floor in enumerate(floors):
            color = cmap(0.1 + 0.75 * i / max(len(floors) - 1, 1))
            acc = h.floor_acceleration[i]
            if pair:
                acc = np.hypot(acc, h.floor_acceleration_h2[i])
            ax.plot(time, acc, lw=0.7, color=color, label=f"floor {floor}")
        ax.set_title(
            f"{t.meta['building']}: floor absolute acceleration"
            + (" |a| (both components)" if pair else "")
        )
        ax.set_ylabel("acceleration (m/s²)")
        ax.grid(alpha=0.3)
        if floors:
            ax.legend(fontsize="small", loc="upper right")
        for i, (k, kind) in enumerate(rows, start=1):
            ax = axes[i]
            content, floor = k.rsplit("/floor_", 1)
            curves = _history_curves(h, k, kind)
            if curves is None:
                ax.text(0.5, 0.5, "not on this building", ha="center", transform=ax.transAxes)
                ax.set_axis_off()
                continue
            mus = np.atleast_1d(h.mu_k.get(k, np.full(curves.shape[0], np.nan)))
            for m in range(curves.shape[0]):
                color = colormaps["viridis"](0.1 + 0.8 * m / max(curves.shape[0] - 1, 1))
                label = f"mu = {mus[m]:g}"
                if not np.isfinite(curves[m]).any():
                    ax.plot([], [], lw=0, marker="x", color=color, label=f"{label}: rocks, not "
                            "simulated as a slider")  # fmt: skip
                    continue
                ax.plot(time[: curves.shape[1]], curves[m], lw=0.9, color=color, label=label)
            ylabel, what = _HISTORY_ROWS[kind]
            if kind == "u" and k in oscillators:
                what = "base slide relative to the floor (2-DOF)"
            if kind == "u" and k in getattr(h, "plane", {}):
                ylabel, what = "slide |u| (m)", "slide |u| in the plane (both components)"
            ax.set_title(f"{content} on floor {floor}: {what}")
            ax.set_ylabel(ylabel)
            ax.grid(alpha=0.3)
            ax.legend(fontsize="small", loc="upper left")
        axes[-1].set_xlabel("time (s)")
        axes[-1].xaxis.set_tick_params(labelbottom=True)
    return fig


def figure_plane(study: Study, record_set: str) -> Figure | None:
    """The path of each block in the plane under the history record of a set of pairs: one
    panel per building × content × floor, ``u_h2`` against ``u_h1`` (m, equal axes) for each
    stored friction value, the peak ``max|u|`` marked (●) and the end (residual, ■); or None
    without pair histories."""
    order = list(study.buildings)
    tasks = sorted(
        (
            t
            for t in study.set_tasks(record_set)
            if t.histories is not None and getattr(t.histories, "plane", None)
        ),
        key=lambda t: order.index(t.meta["building"]),
    )
    if not tasks:
        return None
    panels = [(t, k) for t in tasks for k in t.histories.plane]
    panels, cut = _pick(panels, MAX_PANELS)
    fig, axes = _new_figure(len(panels), width=4.4, height=4.4)
    from matplotlib import colormaps

    t0 = tasks[0]
    names = [*str(t0.meta.get("component_names", "h1,h2")).split(","), "h1", "h2"]
    record = str(t0.meta["record"])
    _suptitle(
        fig,
        study,
        f"Slide path in the plane — record {record} ({names[0]}, {names[1]}), set "
        f"{record_set}; ● peak |u|, ■ end (residual)" + (" (some panels left out)" if cut else ""),
    )
    for ax, (t, k) in zip(axes, panels, strict=False):
        u = np.asarray(t.histories.plane[k], dtype=float)
        mus = np.atleast_1d(t.histories.mu_k.get(k, np.full(u.shape[0], np.nan)))
        reach = 0.0
        for m in range(u.shape[0]):
            color = colormaps["viridis"](0.1 + 0.8 * m / max(u.shape[0] - 1, 1))
            path = u[m]
            if not np.isfinite(path).any():
                ax.plot([], [], lw=0, marker="x", color=color,
                        label=f"mu = {mus[m]:g}: rocks, not simulated as a slider")  # fmt: skip
                continue
            mag = np.hypot(path[:, 0], path[:, 1])
            i = int(np.nanargmax(mag))
            reach = max(reach, float(np.nanmax(mag)))
            ax.plot(path[:, 0], path[:, 1], lw=0.9, color=color,
                    label=f"mu = {mus[m]:g}: peak {mag[i]:.3g} m")  # fmt: skip
            ax.plot(path[i, 0], path[i, 1], "o", color=color, ms=5)
            ax.plot(path[-1, 0], path[-1, 1], "s", color=color, ms=5)
        lim = 1.08 * reach if reach > 0 else 1e-3
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_aspect("equal")
        ax.axhline(0, color="0.7", lw=0.5)
        ax.axvline(0, color="0.7", lw=0.5)
        content, floor = k.rsplit("/floor_", 1)
        ax.set_title(f"{t.meta['building']}: {content} on floor {floor}", fontsize="medium")
        ax.set_xlabel(f"u along {names[0]} (m)")
        ax.set_ylabel(f"u along {names[1]} (m)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize="x-small", loc="upper left")
    return fig


def figure_plane_ratio(study: Study, record_set: str) -> Figure | None:
    """Per building: each record's slide in the plane against the larger of its two
    components' 1-D slides (log axes, every stored friction value and floor), with the 1:1
    line and the median ratio; or None without pairs (or without slides)."""
    points: dict[str, list[tuple[float, float, float]]] = defaultdict(list)
    for t in study.set_tasks(record_set):
        for c in t.contents:
            if c.peak_angle is None:
                continue
            one = np.maximum(np.asarray(c.peak_slide_h1, float), np.asarray(c.peak_slide_h2, float))
            two = np.asarray(c.peak_slide, float)
            for i in range(two.size):
                if np.isfinite(two[i]) and two[i] > 0 and one[i] > 0:
                    points[str(t.meta["building"])].append((one[i], two[i], float(c.mu_k[i])))
    bids = [b for b in study.buildings if points.get(b)]
    if not bids:
        return None
    bids, cut = _pick(bids, MAX_PANELS)
    fig, axes = _new_figure(len(bids), width=4.4, height=4.2)
    n_rec = len({str(t.meta["record"]) for t in study.set_tasks(record_set)})
    _suptitle(
        fig,
        study,
        f"Sliding in the plane against each component alone — set {record_set}, {n_rec} "
        "record pairs; every friction value and floor; ratio = 2-D / max(1-D)"
        + _few(n_rec)
        + (" (some panels left out)" if cut else ""),
    )
    for ax, bid in zip(axes, bids, strict=False):
        arr = np.array(points[bid])
        ratio = arr[:, 1] / arr[:, 0]
        sc = ax.scatter(arr[:, 0], arr[:, 1], c=arr[:, 2], s=12, cmap="viridis")
        lo = max(min(arr[:, 0].min(), arr[:, 1].min()), 1e-6)
        hi = max(arr[:, 0].max(), arr[:, 1].max())
        ax.plot([lo, hi], [lo, hi], color="0.3", lw=0.8, label="2-D = 1-D")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(
            f"{bid}: ratio median {np.median(ratio):.2f}, range {ratio.min():.2f}–"
            f"{ratio.max():.2f}",
            fontsize="medium",
        )
        ax.set_xlabel("larger 1-D slide, each component alone (m)")
        ax.set_ylabel("slide in the plane (m)")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize="small", loc="upper left")
        fig.colorbar(sc, ax=ax, label="mu_k")
    return fig


def _layer_label(meta: dict) -> str:
    """The isolation layer of a task in words, for titles (``""`` when not stored)."""

    def num(key: str) -> float:
        try:
            return float(meta.get(key, math.nan))
        except (TypeError, ValueError):
            return math.nan

    model = str(meta.get("isolator", ""))
    period = num("isolation_period")
    if model == "friction_pendulum":
        text = f"friction pendulum, mu = {num('isolator_mu'):g}, T = {period:g} s"
    elif model == "bilinear":
        text = (
            f"lead-rubber, Q/W = {num('isolator_q_ratio'):g}, "
            f"D_y = {1000 * num('isolator_yield_disp'):.3g} mm, T_d = {period:g} s"
        )
    else:
        return model
    return text.replace("= nan", "= ?")


def _hysteresis_tasks(study: Study, record_set: str) -> list[TaskResult]:
    """The set's tasks that stored the isolator's loop, in building order."""
    order = list(study.buildings)
    return sorted(
        (
            t
            for t in study.set_tasks(record_set)
            if t.histories is not None
            and getattr(t.histories, "isolator_displacement", None) is not None
            and getattr(t.histories, "isolator_force_ratio", None) is not None
        ),
        key=lambda t: order.index(t.meta["building"]),
    )


def _orbit_panel(ax, t: TaskResult) -> None:
    """One building's bearing orbit under a pair (mm, along h1 and h2), its peak vector (inside
    steps) and the capacity circle, when given (red when exceeded)."""
    h, m = t.histories, t.meta
    x = 1000.0 * np.asarray(h.isolator_displacement, dtype=float)
    y = 1000.0 * np.asarray(h.isolator_displacement_h2, dtype=float)
    ax.plot(x, y, lw=0.8, color="tab:blue", label="orbit (at the samples)")
    ax.plot(x[-1:], y[-1:], "o", ms=4, color="tab:blue", mfc="white", label="end (residual)")
    peak = 1000.0 * float(m.get("isolator_peak_displacement", math.nan))
    th = math.radians(float(m.get("isolator_peak_direction", math.nan)))
    reach = float(np.nanmax(np.hypot(x, y))) if x.size else 0.0
    if math.isfinite(peak) and math.isfinite(th):
        ax.plot([peak * math.cos(th)], [peak * math.sin(th)], "o", ms=5, color="0.3",
                label=f"peak |u0| = {peak:.4g} mm at {math.degrees(th):.0f}°")  # fmt: skip
        reach = max(reach, peak)
    capacity = 1000.0 * float(m.get("isolator_capacity", math.nan))
    if math.isfinite(capacity):
        exceeded = bool(m.get("isolator_capacity_exceeded", 0))
        phi = np.linspace(0.0, 2.0 * np.pi, 361)
        ax.plot(capacity * np.cos(phi), capacity * np.sin(phi), ls=":", lw=1.4,
                color="red" if exceeded else "tab:orange",
                label=f"capacity {capacity:.4g} mm"
                + (": EXCEEDED (impact not modelled)" if exceeded else ""))  # fmt: skip
        reach = max(reach, capacity)
    lim = 1.08 * reach if reach > 0 else 1.0
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal", adjustable="box")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.axvline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("bearing displacement along h1 (mm)")
    ax.set_ylabel("along h2 (mm)")
    ax.set_title(f"{m['building']}, record {m['record']}\n{_layer_label(m)}", fontsize="medium")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small", loc="upper left")


def _hysteresis_panel(ax, t: TaskResult) -> None:
    """One building's loop: force / W against isolator displacement (mm), with its peak
    displacement (inside steps) and its capacity marked; under a pair, the bearing's orbit in
    the plane (:func:`_orbit_panel`)."""
    h, m = t.histories, t.meta
    if getattr(h, "isolator_displacement_h2", None) is not None:
        _orbit_panel(ax, t)
        return
    x = 1000.0 * np.asarray(h.isolator_displacement, dtype=float)
    y = np.asarray(h.isolator_force_ratio, dtype=float)
    ax.plot(x, y, lw=0.8, color="tab:blue", label="loop (at the samples)")
    ax.plot(x[-1:], y[-1:], "o", ms=4, color="tab:blue", mfc="white", label="end (residual)")
    peak = float(m.get("isolator_peak_displacement", np.abs(x).max() / 1000.0))
    ax.axvline(1000 * peak, color="0.3", ls="--", lw=0.9)
    ax.axvline(
        -1000 * peak, color="0.3", ls="--", lw=0.9, label=f"peak |u0| = {1000 * peak:.4g} mm"
    )
    capacity = float(m.get("isolator_capacity", math.nan))
    if math.isfinite(capacity):
        exceeded = bool(m.get("isolator_capacity_exceeded", 0))
        label = f"capacity {1000 * capacity:.4g} mm" + (
            ": EXCEEDED (impact not modelled)" if exceeded else ""
        )
        for sign in (1, -1):
            ax.axvline(
                sign * 1000 * capacity,
                color="red" if exceeded else "tab:orange",
                ls=":",
                lw=1.4,
                label=label if sign > 0 else None,
            )
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.axvline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("isolator displacement u0 (mm)")
    ax.set_ylabel("isolator force / W (V/W)")
    ax.set_title(f"{m['building']}, record {m['record']}\n{_layer_label(m)}", fontsize="medium")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small", loc="upper left")


def figure_hysteresis(study: Study, record_set: str) -> Figure | None:
    """Hysteresis loops of the set's history task(s) on nonlinear isolation, or None.

    One panel per building on nonlinear isolation that stored its loop (at most
    :data:`MAX_BUILDING_PANELS`; under a pair of components, its orbit in the plane with the
    capacity circle instead): the isolation layer's force over the total weight (V/W)
    against the isolator displacement (mm) at the samples, the true peak displacement (found inside
    steps) as dashed lines and the layer's capacity, when given, dotted (red when exceeded:
    the impact that would follow is not modelled).
    """
    tasks = _hysteresis_tasks(study, record_set)
    if not tasks:
        return None
    tasks, cut = _pick(tasks, MAX_BUILDING_PANELS)
    fig, axes = _new_figure(len(tasks))
    records = sorted({str(t.meta["record"]) for t in tasks})
    what = (
        "Bearing orbit — isolator displacement in the plane of the pair"
        if all(getattr(t.histories, "isolator_displacement_h2", None) is not None for t in tasks)
        else "Isolator hysteresis — force / W versus isolator displacement"
    )
    _suptitle(
        fig,
        study,
        f"{what}, record {', '.join(records)}, set {record_set}"
        + (" (some buildings left out)" if cut else ""),
    )
    for ax, t in zip(axes, tasks, strict=True):
        _hysteresis_panel(ax, t)
    return fig


def _rocking_curves(t: TaskResult, study: Study) -> list[tuple[str, int, np.ndarray, dict]]:
    """The θ/α histories of a task's contents that rocked under its record: ``(content, floor,
    θ/α, values)`` in the tables' order, ``values`` the block's ``peak_ratio``, ``impacts`` and
    ``overturn_time`` (the stored per-record results)."""
    results = {(c.content, int(c.floor)): c for t_ in (t,) for c in t_.contents}
    out = []
    for key, ratio in getattr(t.histories, "rocking", {}).items():
        content, floor = key.rsplit("/floor_", 1)
        ratio = np.asarray(ratio, dtype=float)
        c = results.get((content, int(floor)))
        values = {"peak_ratio": math.nan, "impacts": math.nan, "overturn_time": math.nan}
        if c is not None and c.rock_peak_ratio is not None:
            peak = np.asarray(c.rock_peak_ratio, dtype=float)
            if np.isfinite(peak).any():
                i = int(np.nanargmax(peak))  # every pair whose friction holds the corner
                values = {
                    "peak_ratio": float(peak[i]),
                    "impacts": float(c.rock_impacts[i]),
                    "overturn_time": float(c.overturn_time[i]),
                }
        moved = np.isfinite(values["overturn_time"]) or np.nanmax(np.abs(ratio), initial=0) > 0
        if moved:
            out.append((content, int(floor), ratio, values))
    rank = {c: i for i, c in enumerate(study.contents)}
    return sorted(out, key=lambda x: (rank.get(x[0], len(rank)), x[0], x[1]))


def _rocking_panel(ax, t: TaskResult, curves: list) -> None:
    """One building's rocking histories θ/α against time, ±1 (overturning) and each
    overturning marked."""
    from matplotlib import colormaps

    h = t.histories
    time = np.arange(h.floor_acceleration.shape[-1]) * h.dt
    cmap = colormaps["tab10"]
    for k, (content, floor, ratio, v) in enumerate(curves):
        color = cmap(k % 10)
        n = min(time.size, ratio.size)
        label = f"{content} on floor {floor}: "
        if np.isfinite(v["overturn_time"]):
            label += f"overturns at {v['overturn_time']:.3g} s"
        else:
            label += f"max|θ|/α = {v['peak_ratio']:.3g}"
        if np.isfinite(v["impacts"]):
            k_impacts = int(v["impacts"])
            label += f", {k_impacts} impact" + ("" if k_impacts == 1 else "s")
        ax.plot(time[:n], ratio[:n], lw=0.8, color=color, label=label)
        if np.isfinite(v["overturn_time"]):
            finite = ratio[np.isfinite(ratio)]
            sign = 1.0 if finite.size == 0 or finite[-1] >= 0 else -1.0
            ax.plot(
                [v["overturn_time"]], [sign], "X", ms=10, color="red", mec="black", mew=0.6,
                zorder=5,
            )  # fmt: skip
    for sign in (1, -1):
        ax.axhline(sign, color="red", ls=":", lw=1.2)
        ax.annotate(
            "overturns",
            (1.0, sign),
            xycoords=("axes fraction", "data"),
            xytext=(-4, -10 if sign > 0 else 3),
            textcoords="offset points",
            ha="right",
            color="red",
            fontsize="small",
        )
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_ylim(-1.2, 1.2)
    # the whole record, also after an overturning (the history is NaN from there)
    ax.set_xlim(0.0, time[-1] if time.size > 1 else 1.0)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("rotation θ/α (–)")
    ax.set_title(f"{t.meta['building']}, record {t.meta['record']}", fontsize="medium")
    ax.grid(alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    if any(np.isfinite(v["overturn_time"]) for *_, v in curves):
        handles.append(Line2D([], [], color="red", marker="X", mec="black", ls="none", ms=8))
        labels.append("overturning (θ/α reaches ±1)")
    ax.legend(handles, labels, fontsize="small", loc="best")  # not over an overturning mark


def figure_rocking(study: Study, record_set: str) -> Figure | None:
    """Rocking histories θ/α of the contents that rock under the set's history record, one
    panel per building (at most :data:`MAX_BUILDING_PANELS`), or None when none rocks (or the
    file holds no rocking histories).

    θ is the block's rotation, α = atan(B/H) its slenderness: the block overturns when |θ/α|
    reaches 1 (the dotted lines); the history ends there (NaN) and the overturning is marked.
    """
    order = list(study.buildings)
    panels = []
    for t in sorted(
        (t for t in study.set_tasks(record_set) if t.histories is not None),
        key=lambda t: order.index(t.meta["building"]),
    ):
        curves = _rocking_curves(t, study)
        if curves:
            panels.append((t, curves))
    if not panels:
        return None
    panels, cut = _pick(panels, MAX_BUILDING_PANELS)
    fig, axes = _new_figure(len(panels))
    records = sorted({str(t.meta["record"]) for t, _ in panels})
    _suptitle(
        fig,
        study,
        f"Rocking — rotation over slenderness θ/α against time, record {', '.join(records)}, "
        f"set {record_set}; the block overturns at θ/α = ±1"
        + (" (some buildings left out)" if cut else ""),
    )
    for ax, (t, curves) in zip(axes, panels, strict=True):
        _rocking_panel(ax, t, curves)
    return fig


def figure_overturning(study: Study, tables: DesignTables, record_set: str) -> Figure | None:
    """Fractions of the set's records under which each content with rocking results rocked
    (dashed, open markers), overturned (solid) and slid while it rocked (dotted, triangles:
    the slide–rock mode, where any did), against the buildings, one series per content, floor
    and friction pair; or None when the set has no row in the ``rocking`` table.

    The x axis is the isolation period when the buildings are variants of one isolated
    building, each of its own period; else one position per building in the tables' order.
    """
    rows = [r for r in tables["rocking"] if r["record_set"] == record_set]
    if not rows:
        return None
    bids = [b for b in study.buildings if any(r["building"] == b for r in rows)]
    periods = [study.buildings[b].isolation_period for b in bids]
    numeric = (
        all(math.isfinite(p) for p in periods)
        and len(set(periods)) == len(periods)
        and len({study.buildings[b].base for b in bids}) == 1
    )
    x_of = {b: (periods[i] if numeric else float(i)) for i, b in enumerate(bids)}
    series = list(dict.fromkeys((r["content"], r["floor"], r["mu_k"], r["mu_s"]) for r in rows))
    fig, (ax,) = _new_figure(1, width=max(4.8, 0.75 * len(bids) + 2.0), height=4.2)
    n = _records_of(rows)
    _suptitle(
        fig,
        study,
        f"Rocking and overturning — set {record_set}\nfraction of the {n} records under which "
        f"the block rocked (dashed, open), overturned (solid) and slid while rocking (dotted)"
        + (f"; caution: only {n} records (< {MIN_RECORDS})" if n < MIN_RECORDS else ""),
    )
    from matplotlib import colormaps

    cmap = colormaps["tab10"]
    handles, labels = [], []
    any_slid = False
    for k, (content, floor, mu_k, mu_s) in enumerate(series):
        color = cmap(k % 10)
        sel = sorted(
            (
                r
                for r in rows
                if (r["content"], r["floor"], r["mu_k"], r["mu_s"]) == (content, floor, mu_k, mu_s)
            ),
            key=lambda r: x_of[r["building"]],
        )
        x = np.array([x_of[r["building"]] for r in sel])
        over = np.array([r["overturn_fraction"] for r in sel], dtype=float)
        rock = np.array([r["rock_fraction"] for r in sel], dtype=float)
        # slid while it rocked (slide–rock, docs/design.md §10g); NaN in older files' tables
        slid = np.array(
            [r.get("n_slide_rock", math.nan) / r["n_records"] for r in sel], dtype=float
        )
        ax.plot(x, rock, "--s", color=color, mfc="none", ms=6, lw=1.0)
        ax.plot(x, over, "-o", color=color, ms=5, lw=1.4)
        if np.nansum(slid) > 0:
            ax.plot(x, slid, ":^", color=color, mfc="none", ms=6, lw=1.0)
            any_slid = True
        handles.append(Line2D([], [], color=color, marker="o", ms=5))
        labels.append(
            f"{content} on floor {floor}, mu {mu_k:g}/{mu_s:g} (B/H = {sel[0]['b_over_h']:.3g})"
        )
    handles += [
        Line2D([], [], color="0.3", marker="o", ms=5),
        Line2D([], [], color="0.3", marker="s", mfc="none", ls="--", ms=6),
    ]
    labels += ["overturned", "rocked (overturned or not)"]
    if any_slid:
        handles.append(Line2D([], [], color="0.3", marker="^", mfc="none", ls=":", ms=6))
        labels.append("slid while it rocked (slide–rock)")
    if numeric:
        ax.set_xlabel("isolation period T_i (s)")
    else:
        ax.set_xticks(range(len(bids)), bids, rotation=30, ha="right", fontsize="small")
        ax.set_xlim(-0.5, len(bids) - 0.5)
        ax.set_xlabel("building")
    ax.set_ylim(-0.03, 1.03)
    ax.set_ylabel(f"fraction of the {n} records (–)")
    ax.grid(alpha=0.3)
    fig.legend(
        handles,
        labels,
        loc="outside lower center",
        ncols=min(3, len(handles)),
        title="content",
        fontsize="small",
    )
    return fig


def _median_spectrum(
    tasks: Sequence[TaskResult], floor: int, damping: float, broadened: bool = False
):
    """Median PSA of `floor` over the tasks (unbroadened, or `broadened`): grid, median,
    number of records; ``(None, None, 0)`` when none is stored."""
    grid, stack = None, []
    for t in tasks:
        for s in t.spectra:
            if int(s.floor) != floor:
                continue
            zs = np.atleast_1d(np.asarray(s.damping, dtype=float))
            hit = np.nonzero(np.abs(zs - damping) <= 1e-9)[0]
            values = s.psa_broadened if broadened else s.psa
            if hit.size == 0 or values is None:
                continue
            psa = np.atleast_2d(np.asarray(values, dtype=float))[hit[0]]
            if not np.isfinite(psa).any():
                continue  # an older file: the unbroadened spectra were not kept
            periods = np.asarray(s.periods, dtype=float)
            if grid is None:
                grid = periods
            stack.append(
                psa if np.array_equal(periods, grid) else interpolate_spectrum(periods, psa, grid)
            )
    if grid is None:
        return None, None, 0
    return grid, np.nanmedian(np.array(stack), axis=0), len(stack)


MARKERS = ("o", "s", "^", "D", "v", "P", "X", "<", ">", "*")
"""A marker per building in the spectra figure, beside its colour: neighbouring isolation
periods have close colours, their markers tell them apart."""


SPREAD = 4.0
"""A spectra panel whose curves' peaks differ by more than this factor has a log PSA axis (a
fixed-base floor's peak otherwise flattens the isolated floors' curves into one band)."""


def figure_frs(study: Study, record_set: str, damping: float) -> Figure | None:
    """Median floor response spectra (PSA, g) of the set per building, one panel per floor
    (log period axis): unbroadened (solid) and, when stored, broadened (dashed), each building
    with its colour and its marker (:data:`MARKERS`), on a log PSA axis where the peaks differ
    by more than :data:`SPREAD` times; or None when the set has no spectra."""
    tasks = study.set_tasks(record_set)
    by_building: dict[str, list[TaskResult]] = defaultdict(list)
    for t in tasks:
        by_building[t.meta["building"]].append(t)
    floors = sorted({int(s.floor) for t in tasks for s in t.spectra})
    if not floors:
        return None
    floors, cut = _pick(floors, 9)
    broadening = max((float(s.broadening) for t in tasks for s in t.spectra), default=0.0)
    colors = building_colors(study)
    fig, axes = _new_figure(len(floors))
    n_records = len({str(t.meta["record"]) for t in tasks})
    wide = (
        f"solid: unbroadened, dashed: broadened ±{broadening * 100:g} % in frequency"
        if broadening
        else "unbroadened (no peak broadening)"
    )
    rotd = any(getattr(s, "orientation", "") for t in tasks for s in t.spectra)
    _suptitle(
        fig,
        study,
        f"Floor response spectra — set {record_set}\nmedian "
        + ("RotD50 PSA over {n} record pairs" if rotd else "PSA over {n} records").format(
            n=n_records
        )
        + f", {damping * 100:g} % damping; {wide}{_few(n_records)}"
        + (" (some floors left out)" if cut else ""),
    )
    handles = {}
    for ax, floor in zip(axes, floors, strict=True):
        present = []
        for bid in study.buildings:
            if bid not in by_building:
                continue
            for broadened, style in ((False, "-"), (True, "--")):
                grid, median, n = _median_spectrum(by_building[bid], floor, damping, broadened)
                if grid is None:
                    continue
                if bid not in present:
                    present.append(bid)
                pos = grid > 0
                k = list(study.buildings).index(bid)
                (line,) = ax.plot(
                    grid[pos],
                    median[pos] / G,
                    style,
                    color=colors[bid],
                    lw=1.4,
                    marker=MARKERS[k % len(MARKERS)],
                    ms=4.5,
                    mfc="white" if k // len(MARKERS) % 2 else colors[bid],
                    # markers a few points apart, shifted per building so that they interleave
                    markevery=(k % 5, 5),
                )
                if not broadened:
                    handles.setdefault(bid, (line, f"{bid} ({n} records)"))
        ax.set_xscale("log")
        ax.set_xlabel("period T (s)")
        peaks = [np.nanmax(ln.get_ydata()) for ln in ax.get_lines() if len(ln.get_ydata())]
        if peaks and min(peaks) > 0 and max(peaks) / min(peaks) > SPREAD:
            ax.set_yscale("log")  # the curves of a stiff and an isolated building apart
            ax.set_ylabel("median PSA (g, log scale)")
        else:
            ax.set_ylabel("median PSA (g)")
        ax.set_title(_floor_label(study, floor, present))
        ax.grid(alpha=0.3, which="both")
    labels = [lab for _, lab in handles.values()]
    lines = [h for h, _ in handles.values()]
    if broadening:
        lines += [Line2D([], [], color="0.3"), Line2D([], [], color="0.3", ls="--")]
        labels += ["unbroadened", f"broadened ±{broadening * 100:g} %"]
    fig.legend(
        lines,
        labels,
        loc="outside lower center",
        ncols=min(4, len(lines)),
        title="building",
        fontsize="small",
    )
    return fig


def _scale_target(study: Study, entry: dict):
    """The target spectrum of a scaled set (:class:`floorslide.practice.target.TargetSpectrum`)
    from the stored scene's ``[[records]] scale.target``, and ``""``; or None and why not (a
    target CSV that is no longer where the scene said)."""
    from floorslide.errors import FloorslideError
    from floorslide.practice.target import TargetSpectrum, read_target_csv

    spec = next(
        (
            r.get("scale", {}).get("target")
            for r in study.scene.get("records", [])
            if r.get("set") == entry.get("family")
        ),
        None,
    )
    if isinstance(spec, dict):
        return TargetSpectrum.two_point(spec["sds"], spec["sd1"], spec["tl"]), ""
    if isinstance(spec, str):
        path = Path(spec)
        if not path.is_absolute():
            path = Path(study.scene_path).parent / path
        try:
            return read_target_csv(path), ""
        except (FloorslideError, OSError):
            return None, f"target not drawn: its file {path} is not readable here"
    return None, "target not drawn: not in the stored scene"


def figure_scaled_spectra(study: Study, record_set: str) -> Figure | None:
    """The records of a set scaled to a target spectrum (``[[records]] scale``) against it:
    each record's scaled PSA (g) at the scaling's damping (thin grey), their mean (black), the
    target times the set's level (red) and 90 % of it (red dashed: ASCE 7-22 §16.2.3), the
    fitting range shaded (or the period ``T*`` matched), log–log, with the suite check's lowest
    ratio in the title. The records' spectra are the stored spectra of floor 0 of a
    fixed-base building (the ground, scaled as the tasks ran it), so the figure is drawn only
    when ``[spectra]`` holds floor 0 and that damping; None otherwise, for a set not scaled to
    a target, and for a set of record pairs (its stored spectra are RotD50, its scaling
    RotD100)."""
    entry = next(
        (e for e in study.scaling if e.get("set") == record_set and e.get("method") in
         ("range", "period")),
        None,
    )  # fmt: skip
    if entry is None:
        return None
    damping = float(entry.get("damping", 0.05))
    grounds = [
        t
        for t in study.set_tasks(record_set)
        if study.buildings[t.meta["building"]].kind != "isolated"
    ]
    curves: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for t in grounds:
        rec = str(t.meta["record"])
        if rec in curves:
            continue
        for sp in t.spectra:
            if int(sp.floor) != 0 or getattr(sp, "orientation", ""):
                continue
            zs = np.atleast_1d(np.asarray(sp.damping, dtype=float))
            hit = np.nonzero(np.abs(zs - damping) <= 1e-9)[0]
            if hit.size:
                psa = np.atleast_2d(np.asarray(sp.psa, dtype=float))[hit[0]]
                curves[rec] = (np.asarray(sp.periods, dtype=float), psa / G)
    if not curves:
        return None
    level = float(entry.get("level", 1.0))
    target, why = _scale_target(study, entry)
    fig = Figure(figsize=(8.5, 5.4), layout="constrained")
    ax = fig.subplots()
    grid = next(iter(curves.values()))[0]
    pos = grid > 0
    stack = []
    for periods, psa in curves.values():
        psa = psa if np.array_equal(periods, grid) else interpolate_spectrum(periods, psa, grid)
        stack.append(psa)
        ax.plot(grid[pos], psa[pos], color="0.6", lw=0.7)
    mean = np.mean(stack, axis=0)
    ax.plot(grid[pos], mean[pos], color="black", lw=2.0)
    handles = [Line2D([], [], color="0.6", lw=0.7), Line2D([], [], color="black", lw=2.0)]
    labels = [f"each record, scaled ({len(curves)})", "mean of the scaled records"]
    lo, hi = [*(entry.get("period_range") or []), math.nan, math.nan][:2]
    if target is not None:
        tg = grid[pos & (grid >= target.periods[0]) & (grid <= target.periods[-1])]
        sa = level * target(tg)
        ax.plot(tg, sa, color="tab:red", lw=2.0)
        ax.plot(tg, 0.9 * sa, color="tab:red", lw=1.3, ls="--")
        handles += [Line2D([], [], color="tab:red", lw=2.0),
                    Line2D([], [], color="tab:red", lw=1.3, ls="--")]  # fmt: skip
        times = "" if level == 1 else f"{level:g} × "
        labels += [f"{times}target", f"90 % of {times}target (ASCE 7-22 §16.2.3)"]
    if math.isfinite(lo) and math.isfinite(hi):
        ax.axvspan(lo, hi, color="tab:blue", alpha=0.08, lw=0)
        handles.append(Line2D([], [], color="tab:blue", alpha=0.25, lw=8))
        labels.append(f"scaling range {lo:g}–{hi:g} s")
    if entry.get("period") is not None and entry.get("method") == "period":
        ax.axvline(float(entry["period"]), color="tab:blue", ls=":", lw=1.3)
        handles.append(Line2D([], [], color="tab:blue", ls=":", lw=1.3))
        labels.append(f"T* = {float(entry['period']):g} s (matched)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("period T (s)")
    ax.set_ylabel(f"PSA (g), {damping * 100:g} % damping")
    ax.grid(alpha=0.3, which="both")
    suite = entry.get("suite") if isinstance(entry.get("suite"), dict) else {}
    check = ""
    if suite:
        verdict = "passes" if suite.get("passes") else "falls short"
        check = (
            f"; suite check {verdict}: lowest mean / target {float(suite.get('min_ratio')):.2f} "
            f"at {float(suite.get('at')):g} s (≥ 0.90 asked)"
        )
    _suptitle(
        fig,
        study,
        f"Scaled records against the target — set {record_set}\nthe spectra of floor 0 of the "
        f"fixed-base building (the ground as run){check}" + (f"; {why}" if why else ""),
    )
    fig.legend(handles, labels, loc="outside lower center", ncols=3, fontsize="small")
    return fig


def _panel_keys(rows: Sequence[dict], study: Study) -> list[tuple[int, str]]:
    keys = {(r["floor"], r["content"]) for r in rows}
    return sorted(
        keys,
        key=lambda k: (
            study.contents.index(k[1]) if k[1] in study.contents else len(study.contents),
            k[1],
            k[0],
        ),
    )


def _statistic_panel(
    ax, rows: list[dict], quantity: str, color, scale: float = 1.0, dx: float = 0.0
) -> list[tuple[np.ndarray, str, object]]:
    """Median (line, dots) and 84th percentile (open triangles) of `quantity` versus mu_k on
    `ax` (shifted by `dx` to set buildings side by side at a single mu), leaving out statistics
    that fall on rocking records (never drawn at 0). Returns those as ``(mu_k values, "median" |
    "p84", color)`` for :func:`_rock_strip`."""
    series: dict[float | None, list[dict]] = defaultdict(list)
    mu_k = [r["mu_k"] for r in rows]
    split = len(set(mu_k)) < len(mu_k)
    for r in rows:
        series[r["mu_s"] if split else None].append(r)
    rocks = []
    for _, srows in series.items():
        srows = sorted(srows, key=lambda r: r["mu_k"])
        x = np.array([r["mu_k"] for r in srows]) + dx
        for stat, style in (("median", "-o"), ("p84", "^")):
            y = np.array([r[f"{quantity}_{stat}"] for r in srows], dtype=float) * scale
            rock = np.array([r[f"{stat}_outcome"] == ROCK for r in srows])
            y = np.where(rock, np.nan, y)
            # clip_on=False: a statistic of 0 shows whole on the axis, not half cut by it
            kw = dict(color=color, ms=4 if stat == "median" else 6, clip_on=False)
            if stat == "p84":
                kw["mfc"] = "none"
            else:
                kw["lw"] = 1.3
            ax.plot(x, y, style, **kw)
            if rock.any():
                rocks.append((x[rock], stat, color))
    return rocks


def _one_position(ax, x: float) -> None:
    """An x axis around a single value (one friction coefficient or isolation period: a
    single design) — ±50 % of it and one tick — instead of matplotlib's ±0.05 with ticks at
    every 0.005, which reads as a sweep that is not there."""
    half = 0.5 * abs(x) if x else 0.5
    ax.set_xlim(x - half, x + half)
    ax.set_xticks([x], [f"{x:g}"])


def _mu_axis(ax, mus: Sequence[float]) -> None:
    """The friction axis over every stored mu_k — also those at which every building rocks,
    which have no slide to draw (matplotlib would leave them off the axis, and their marks in
    the 'rock' strip with them) — with matplotlib's usual 5 % margins; a single value centred
    (:func:`_one_position`)."""
    if len(mus) == 1:
        _one_position(ax, mus[0])
        return
    pad = 0.05 * (mus[-1] - mus[0])
    ax.set_xlim(mus[0] - pad, mus[-1] + pad)


def _dodge(x: float, k: int, n: int) -> float:
    """The shift of the `k`-th of `n` buildings drawn side by side at a single x value."""
    if n <= 1:
        return 0.0
    step = min(0.08, 0.6 / (n - 1)) * (abs(x) if x else 1.0)
    return (k - (n - 1) / 2) * step


ROCK_STRIP = 0.14
"""Height of the 'rock' strip above a panel, as a fraction of the panel's height."""


def _rock_strip(ax, rocks: list[tuple[np.ndarray, str, object]]):
    """A strip above the panel, sharing its mu axis, for the statistics that are 'rock'
    (``x`` the median, open triangle the p84): an outcome of its own, apart from the slide
    axis — never a value on it."""
    strip = ax.inset_axes((0.0, 1.02, 1.0, ROCK_STRIP), sharex=ax)
    strip.set_ylim(0, 1)
    strip.set_yticks([0.5], ["rock"])
    strip.tick_params(labelbottom=False, bottom=False, left=False, labelsize="small")
    strip.set_facecolor("0.94")
    # several buildings rock at the same mu: dodge them sideways, in the legend's order
    colors = list(dict.fromkeys(map(str, (c for _, _, c in rocks))))
    lo, hi = ax.get_xlim()
    step = 0.012 * (hi - lo)
    for x, stat, color in rocks:
        k = colors.index(str(color))
        xs = x + (k - (len(colors) - 1) / 2) * step
        if stat == "median":
            strip.plot(xs, np.full(x.size, 0.64), "x", color=color, ms=7, mew=1.5, ls="none")
        else:
            strip.plot(xs, np.full(x.size, 0.3), "^", color=color, mfc="none", ms=6, ls="none")
    ax.set_xlim(lo, hi)
    return strip


def _rock_legend() -> tuple[Line2D, str]:
    return (
        Line2D([], [], color="0.3", marker="x", ls="none", ms=8),
        "in the 'rock' strip above a panel: the median (x) or p84 (△) falls on records\n"
        "where the object rocks (not simulated as a slider) — ranked above every slide, never 0",
    )


def _records_of(rows: Sequence[dict]) -> int:
    return max((int(r["n_records"]) for r in rows), default=0)


def figure_slide_vs_mu(study: Study, tables: DesignTables, record_set: str) -> Figure | None:
    """Peak slide versus mu_k per building (median line, 84th percentile open triangles;
    statistics that fall on rocking records drawn at the top of the panel, never at 0), one
    panel per content and floor, or None."""
    rows = [r for r in tables["slides"] if r["record_set"] == record_set]
    if not rows:
        return None
    panels, cut = _pick(_panel_keys(rows, study))
    colors = building_colors(study)
    fig, axes = _new_figure(len(panels))
    n = _records_of(rows)
    _suptitle(
        fig,
        study,
        f"Peak slide versus friction — set {record_set}\nmedian (line) and 84th percentile "
        f"(open triangles) over {n} records{_few(n)}" + (" (some panels left out)" if cut else ""),
    )
    used: list[str] = []
    any_rock = False
    mus = sorted({r["mu_k"] for r in rows})
    for ax, (floor, content) in zip(axes, panels, strict=True):
        rocks = []
        here = {r["building"] for r in rows if r["floor"] == floor and r["content"] == content}
        present = [b for b in study.buildings if b in here]
        for k, bid in enumerate(present):
            sel = [
                r
                for r in rows
                if r["building"] == bid and r["floor"] == floor and r["content"] == content
            ]
            if bid not in used:
                used.append(bid)
            dx = _dodge(mus[0], k, len(present)) if len(mus) == 1 else 0.0
            rocks += _statistic_panel(ax, sel, "peak_slide", colors[bid], dx=dx)
        _mu_axis(ax, mus)
        ax.set_yscale("symlog", linthresh=SLIDE_LINTHRESH)
        top = ax.get_ylim()[1]  # room above the top marker, not cut by the frame
        ax.set_ylim(0, 1.6 * top if top > SLIDE_LINTHRESH else top)
        ax.set_xlabel("kinetic friction coefficient mu_k (–)")
        ax.set_ylabel("peak slide (m; linear below 1 mm)")
        if rocks:
            any_rock = True
            _rock_strip(ax, rocks).set_title(f"{content} on floor {floor}")
        else:
            ax.set_title(f"{content} on floor {floor}")
        ax.grid(alpha=0.3, which="both")
    handles = [Line2D([], [], color=colors[b], marker="o", ms=4) for b in used]
    labels = list(used)
    handles += [
        Line2D([], [], color="0.3", marker="o", ms=4),
        Line2D([], [], color="0.3", marker="^", mfc="none", ls="none", ms=6),
    ]
    labels += ["median (line)", "84th percentile"]
    if any_rock:
        h, lab = _rock_legend()
        handles.append(h)
        labels.append(lab)
    fig.legend(
        handles,
        labels,
        loc="outside lower center",
        ncols=min(3, len(handles)),
        title="building",
        fontsize="small",
    )
    return fig


def figure_oscillators(study: Study, tables: DesignTables, record_set: str) -> Figure | None:
    """2-DOF (flexible) equipment: peak spring deformation (mm) and the top mass's peak
    absolute acceleration (g) versus mu_k per building, median and 84th percentile, two panels
    per content and floor; None when the set has no oscillator."""
    rows = [
        r for r in tables["slides"] if r["record_set"] == record_set and r["model"] == "oscillator"
    ]
    if not rows:
        return None
    keys, cut = _pick(_panel_keys(rows, study), MAX_PANELS // 2)
    panels = [(k, q) for k in keys for q in ("peak_deformation", "peak_top_accel_g")]
    colors = building_colors(study)
    fig, axes = _new_figure(len(panels))
    n = _records_of(rows)
    _suptitle(
        fig,
        study,
        f"Flexible equipment (2-DOF sliding oscillators) — set {record_set}\nmedian (line) and "
        f"84th percentile (open triangles) over {n} records{_few(n)}"
        + (" (some panels left out)" if cut else ""),
    )
    used: list[str] = []
    any_rock = False
    mus = sorted({r["mu_k"] for r in rows})
    for ax, ((floor, content), quantity) in zip(axes, panels, strict=True):
        scale = 1000.0 if quantity == "peak_deformation" else 1.0
        rocks = []
        here = {r["building"] for r in rows if r["floor"] == floor and r["content"] == content}
        present = [b for b in study.buildings if b in here]
        for k, bid in enumerate(present):
            sel = [
                r
                for r in rows
                if r["building"] == bid and r["floor"] == floor and r["content"] == content
            ]
            if bid not in used:
                used.append(bid)
            dx = _dodge(mus[0], k, len(present)) if len(mus) == 1 else 0.0
            rocks += _statistic_panel(ax, sel, quantity, colors[bid], scale, dx=dx)
        _mu_axis(ax, mus)
        ax.set_ylim(bottom=0)
        ax.set_xlabel("kinetic friction coefficient mu_k (–)")
        if quantity == "peak_deformation":
            ax.set_ylabel("peak spring deformation (mm)")
            title = f"{content} on floor {floor}: spring deformation"
        else:
            ax.set_ylabel("peak top-mass acceleration (g)")
            title = f"{content} on floor {floor}: top mass absolute acceleration"
        if rocks:
            any_rock = True
            _rock_strip(ax, rocks).set_title(title)
        else:
            ax.set_title(title)
        ax.grid(alpha=0.3)
    handles = [Line2D([], [], color=colors[b], marker="o", ms=4) for b in used]
    labels = list(used)
    if any_rock:
        h, lab = _rock_legend()
        handles.append(h)
        labels.append(lab)
    fig.legend(
        handles,
        labels,
        loc="outside lower center",
        ncols=min(3, len(handles)),
        title="building",
        fontsize="small",
    )
    return fig


def _series_name(bid: str) -> str:
    """A variant id without its isolation-period tag: the curve it belongs to."""
    if "@" not in bid:
        return bid
    base, tags = bid.split("@", 1)
    rest = [t for t in tags.split(",") if not t.startswith("T=")]
    return base + ("@" + ",".join(rest) if rest else "")


def _ratio_axis(rows: Sequence[dict], a_name: str, b_name: str):
    """How the ratio figure places its points: versus the isolation period of A, else of B
    (A fixed-base over isolated variants), else one position per building pair.

    Returns ``(x_of(row), series_of(row), label, ticks)``; ``ticks`` is None or the pair
    labels of a categorical axis."""
    if all(math.isfinite(r["isolation_period_a"]) for r in rows):
        return (
            lambda r: r["isolation_period_a"],
            lambda r: (_series_name(r["building_a"]), r["building_b"]),
            f"isolation period T_i of {a_name} (s)",
            None,
        )
    if all(math.isfinite(r["isolation_period_b"]) for r in rows):
        return (
            lambda r: r["isolation_period_b"],
            lambda r: (r["building_a"], _series_name(r["building_b"])),
            f"isolation period T_i of {b_name} (s)",
            None,
        )
    pairs = list(dict.fromkeys((r["building_a"], r["building_b"]) for r in rows))
    return (
        lambda r: float(pairs.index((r["building_a"], r["building_b"]))),
        lambda r: ("", ""),
        "building pair A / B",
        [f"{a} / {b}" for a, b in pairs],
    )


def figure_slide_ratio(
    study: Study, tables: DesignTables, record_set: str, comparison: str
) -> Figure | None:
    """Median peak-slide ratio A / B, one curve per mu_k, one panel per content and floor:
    versus the isolation period of A — or of B when A is fixed-base (``fixed:isolated``) —
    or per building pair when neither is isolated; None when the comparison has no rows."""
    rows = [
        r
        for r in tables["slide_ratios"]
        if r["record_set"] == record_set and r["comparison"] == comparison
    ]
    if not rows:
        return None
    a_name, b_name = comparison.split(":")
    x_of, series_of, xlabel, ticks = _ratio_axis(rows, a_name, b_name)
    panels, cut = _pick(_panel_keys(rows, study))
    fig, axes = _new_figure(len(panels))
    n = max(max(int(r["n_records_a"]), int(r["n_records_b"])) for r in rows)
    versus = "per building pair" if ticks else f"versus {xlabel.split(' (')[0]}"
    _suptitle(
        fig,
        study,
        f"Median peak-slide ratio {a_name} / {b_name} — set {record_set}\n"
        f"{versus}, one curve per friction coefficient, medians over {n} records{_few(n)}"
        + (" (some panels left out)" if cut else ""),
    )
    from matplotlib import colormaps

    mus = sorted({(r["mu_k"], r["mu_s"]) for r in rows})
    same = all(abs(k - s) <= 1e-12 for k, s in mus)
    cmap = colormaps["plasma"]
    mu_color = {m: cmap(0.05 + 0.8 * i / max(len(mus) - 1, 1)) for i, m in enumerate(mus)}
    series = sorted({series_of(r) for r in rows})
    positions = sorted({x_of(r) for r in rows})
    styles = ["-", "--", ":", "-."]
    gaps = rocks = False
    for ax, (floor, content) in zip(axes, panels, strict=True):
        ax.axhline(1.0, color="0.5", lw=0.8, ls="--")
        panel_rocks: list[tuple[np.ndarray, str, object]] = []
        for si, name in enumerate(series):
            for mu in mus:
                sel = sorted(
                    (
                        r
                        for r in rows
                        if r["floor"] == floor
                        and r["content"] == content
                        and (r["mu_k"], r["mu_s"]) == mu
                        and series_of(r) == name
                    ),
                    key=x_of,
                )
                if not sel:
                    continue
                x = np.array([x_of(r) for r in sel])
                y = np.array([r["peak_slide_median_ratio"] for r in sel], dtype=float)
                rock = np.array(
                    [ROCK in (r["median_outcome_a"], r["median_outcome_b"]) for r in sel]
                )
                rocks = rocks or bool(rock.any())
                gaps = gaps or not np.isfinite(y[~rock]).all()
                y = np.where(np.isfinite(y), y, np.nan)
                style = styles[si % len(styles)] if not ticks else "none"
                # clip_on=False: a ratio of 0 shows whole on the axis, not half cut by it
                ax.plot(x, y, style, marker="o", ms=4, color=mu_color[mu], clip_on=False)
                if rock.any():
                    panel_rocks.append((x[rock], "median", mu_color[mu]))
        ax.set_ylim(bottom=0)
        if ticks:
            ax.set_xticks(range(len(ticks)), ticks, rotation=30, ha="right", fontsize="small")
            ax.set_xlim(-0.5, len(ticks) - 0.5)
        elif len(positions) == 1:
            _one_position(ax, positions[0])
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"median peak slide {a_name} / {b_name} (–)")
        title_ax = _rock_strip(ax, panel_rocks) if panel_rocks else ax
        title_ax.set_title(f"{content} on floor {floor}")
        ax.grid(alpha=0.3)
    handles = [Line2D([], [], color=mu_color[m], marker="o", ms=4) for m in mus]
    labels = [f"mu = {k:g}" if same else f"mu_k = {k:g}, mu_s = {s:g}" for k, s in mus]
    if len(series) > 1:
        for si, (sa, sb) in enumerate(series):
            handles.append(Line2D([], [], color="0.3", ls=styles[si % len(styles)]))
            labels.append(f"{sa} / {sb}")
    handles.append(Line2D([], [], color="0.5", ls="--", lw=0.8))
    labels.append("ratio 1")
    if gaps:
        handles.append(Line2D([], [], ls="none"))
        labels.append("gaps: 0/0 (neither slides) or x/0\n(only A slides), see slide_ratios")
    if rocks:
        handles.append(Line2D([], [], color="0.3", marker="x", ls="none", ms=8))
        labels.append("x in the 'rock' strip: a median is 'rock'\n(rocking, not a slide): no ratio")
    fig.legend(
        handles,
        labels,
        loc="outside lower center",
        ncols=min(3, len(handles)),
        title="friction",
        fontsize="small",
    )
    return fig


# --------------------------------------------------------------------------------------------
# design practice (docs/design.md §10e): PFA profile against the code, slide ECDF, fragility


def _percentiles(values: Sequence[float]) -> tuple[float, float]:
    """Median and 84th percentile of the finite values (as in the design tables)."""
    _, median, p84 = summarize(values)
    return median, p84


def figure_pfa_profile(study: Study, tables: DesignTables, record_set: str) -> Figure | None:
    """Peak floor acceleration over the peak ground acceleration up the height, against the
    code's floor amplification; or None when the set has no tasks.

    One panel per building kind (fixed-base, isolated), floor on the y axis (0 = ground, or
    the base mat of an isolated building, up to the roof), PFA/PGA on the x axis: per building
    the median over the set's records (line with markers) and the 84th percentile (dashed,
    open triangles), each record's PFA/PGA from its task. For every fixed-base building the
    ASCE 7-22 §13.3.1 floor amplification (Eq. 13.3-4)

    ``H_f = 1 + a_1·(z/h) + a_2·(z/h)^10``, ``a_1 = 1/T_a ≤ 2.5``,
    ``a_2 = max(0, 1 − (0.4/T_a)²)``

    is drawn dotted in the building's colour over ``z/h`` in [0, 1] (equal storey heights,
    ``z/h = floor/stories``), with markers at the floors, taking ``T_a`` as the model's
    fixed-base fundamental period (stored with each task; the code's ``T_a`` is the approximate
    period of §12.8.2.1, which estimates it). Isolated buildings get no ``H_f``: ASCE 7-22 §17
    takes component demands from the response history analysis of the isolated structure.

    Parameters
    ----------
    study
        The result file, read.
    tables
        The design tables (unused; the figures share one signature).
    record_set
        The set whose records are summarised.

    References
    ----------
    ASCE/SEI 7-22, *Minimum Design Loads and Associated Criteria for Buildings and Other
    Structures*, §13.3.1, Eq. 13.3-4; §17.
    """
    from floorslide.practice.code import asce7_floor_amplification

    profiles = pfa_profiles(study, record_set)
    if not profiles:
        return None
    kinds = ["isolated" if study.buildings[b].kind == "isolated" else "fixed" for b in profiles]
    panels = [k for k in ("fixed", "isolated") if k in kinds]
    top = max(max(floors) for floors in profiles.values())
    fig, axes = _new_figure(len(panels), width=4.6, height=max(3.6, 2.6 + 0.4 * top))
    colors = building_colors(study)
    n = max(len(v) for floors in profiles.values() for v in floors.values())
    isolated = "isolated" in panels
    periods = {
        b: fixed_period(study, record_set, b)
        for b, k in zip(profiles, kinds, strict=True)
        if k == "fixed"
    }
    code = {b: t for b, t in periods.items() if math.isfinite(t) and study.buildings[b].stories}
    missing_ta = [b for b in periods if b not in code]
    _suptitle(
        fig,
        study,
        f"Peak floor acceleration over PGA up the height — set {record_set}\nmedian (line) and "
        f"84th percentile (dashed, open triangles) over {n} records{_few(n)}"
        + ("; ASCE 7-22 §13.3.1 H_f (dotted) for fixed-base buildings" if code else ""),
    )
    for ax, kind in zip(axes, panels, strict=True):
        bids = [b for b, k in zip(profiles, kinds, strict=True) if k == kind]
        right = 1.0
        for bid in bids:
            color = colors[bid]
            floors = sorted(profiles[bid])
            stats = [_percentiles([v for _, v in profiles[bid][f]]) for f in floors]
            median = np.array([s[0] for s in stats])
            p84 = np.array([s[1] for s in stats])
            n_b = max(len(profiles[bid][f]) for f in floors)
            ax.plot(
                median,
                floors,
                "-o",
                color=color,
                ms=5,
                lw=1.5,
                label=f"{bid}: median ({n_b} records)",
            )
            ax.plot(p84, floors, "--^", color=color, mfc="none", ms=6, lw=1.0)
            right = max(right, float(np.nanmax(np.r_[median, p84])))
            if kind != "fixed":
                continue
            if bid not in code:
                continue
            period, stories = code[bid], study.buildings[bid].stories
            z = np.linspace(0.0, 1.0, 50)
            hf = asce7_floor_amplification(z, period)
            ax.plot(
                hf,
                z * stories,
                ":",
                color=color,
                lw=1.6,
                label=f"ASCE 7-22 H_f (T_a = {period:.3g} s)",
            )
            at = np.array([f for f in floors if 0 <= f <= stories], dtype=float)
            ax.plot(
                asce7_floor_amplification(at / stories, period),
                at,
                "s",
                color=color,
                mfc="white",
                ms=5,
                ls="none",
            )
            right = max(right, float(hf.max()))
        ax.axvline(1.0, color="0.6", lw=0.8, ls="-", zorder=0)
        ax.set_xlim(0.0, 1.12 * right)
        ax.set_ylim(-0.35, top + 0.35)
        ticks = list(range(top + 1))
        labels = [str(f) for f in ticks]
        labels[0] = "0 (base mat)" if kind == "isolated" else "0 (ground)"
        roofs = {study.buildings[b].stories for b in bids}
        if len(roofs) == 1 and (roof := roofs.pop()) in ticks and roof > 0:
            labels[roof] = f"{roof} (roof)"
        if top > 12:
            step = math.ceil(top / 12)
            keep = [i for i in ticks if i % step == 0 or i == top]
            ticks, labels = keep, [labels[i] for i in keep]
        ax.set_yticks(ticks, labels)
        ax.set_ylabel("floor")
        ax.set_xlabel("PFA / PGA (–)")
        ax.set_title("fixed-base buildings" if kind == "fixed" else "isolated buildings")
        ax.grid(alpha=0.3)
        ax.legend(fontsize="x-small", loc="lower right" if kind == "fixed" else "upper right")
    handles = [
        Line2D([], [], color="0.3", marker="o", ms=5),
        Line2D([], [], color="0.3", marker="^", mfc="none", ls="--", ms=6),
        Line2D([], [], color="0.6", lw=0.8),
    ]
    labels = ["median over the records", "84th percentile", "PFA = PGA"]
    if code:
        handles.append(Line2D([], [], color="0.3", ls=":", marker="s", mfc="white", ms=5))
        labels.append("ASCE 7-22 §13.3.1 H_f (Eq. 13.3-4), z/h = floor / stories")
    if missing_ta:
        handles.append(Line2D([], [], ls="none"))
        labels.append(f"no H_f for {', '.join(missing_ta)}: the file does not store T_a")
    if isolated:
        handles.append(Line2D([], [], ls="none"))
        labels.append(
            "isolated buildings: ASCE 7-22 §17 takes component demands from\n"
            "response-history analysis, no H_f"
        )
    fig.legend(
        handles, labels, loc="outside lower center", ncols=min(2, len(handles)), fontsize="small"
    )
    return fig


def _allowables(study: Study, content: str) -> tuple[float, ...]:
    """The allowable displacements (m) of a content in the stored scene, increasing; ``()``
    when it has none (:func:`floorslide.report.practice.allowables`)."""
    return allowables(study).get(content, ())


def _median_pair(rows: Sequence[dict]) -> tuple[float, float]:
    """The stored friction pair ``(mu_k, mu_s)`` at the median of the content's mu_k values
    (the lower of the two middle ones for an even count: a value that was simulated)."""
    pairs = sorted({(float(r["mu_k"]), float(r["mu_s"])) for r in rows})
    mus = sorted({k for k, _ in pairs})
    mu_k = mus[(len(mus) - 1) // 2]
    same = [p for p in pairs if p[0] == mu_k]
    return same[(len(same) - 1) // 2]


def _ecdf_pair(rows: Sequence[dict], mu: float | None) -> tuple[float, float, str]:
    """The friction pair of an ECDF panel and how it was chosen: the stored mu_k nearest to
    `mu` when given; else the median (:func:`_median_pair`) of the pairs under which the
    object slides or rests under at least half the records on every building — a pair under
    which it mostly rocks has little curve to show — or of all pairs when there is none; how
    is ``""`` for the plain median of the stored values."""
    if mu is not None:
        pairs = sorted({(float(r["mu_k"]), float(r["mu_s"])) for r in rows})
        mu_k = min((k for k, _ in pairs), key=lambda k: (abs(k - mu), k))
        same = [p for p in pairs if p[0] == mu_k]
        pick = same[(len(same) - 1) // 2]
        how = "as asked" if abs(mu_k - mu) <= 1e-12 else f"the stored value nearest {mu:g}"
        return (*pick, how)
    groups: dict = defaultdict(list)
    for r in rows:
        groups[(float(r["mu_k"]), float(r["mu_s"]), r["building"])].append(r)
    rocky = {
        (k, s)
        for (k, s, _), g in groups.items()
        if 2 * sum(r["outcome"] == ROCK for r in g) > len(g)
    }
    slides = [r for r in rows if (float(r["mu_k"]), float(r["mu_s"])) not in rocky]
    if not slides:
        return (*_median_pair(rows), "the median stored value: it rocks under most records")
    how = "" if not rocky else "the median value at which it slides"
    return (*_median_pair(slides), how)


def _ecdf_points(rows: Sequence[dict]) -> tuple[np.ndarray, np.ndarray, int, int]:
    """The empirical CDF of the peak slide over `rows` (one per record): the sorted slides of
    the records where the object slides or rests, their fractions ``i/n`` of all ``n`` records
    — a record where it rocks is never ≤ any slide —, ``n`` and the number that rock."""
    n = len(rows)
    slides = np.sort(
        np.array(
            [
                r["peak_slide"]
                for r in rows
                if r["outcome"] != ROCK and math.isfinite(r["peak_slide"])
            ],
            dtype=float,
        )
    )
    return slides, np.arange(1, slides.size + 1) / max(n, 1), n, n - slides.size


def figure_slide_ecdf(
    study: Study, tables: DesignTables, record_set: str, mu: float | None = None
) -> Figure | None:
    """The empirical distribution of the peak slide over the set's records, one panel per
    content and floor, one step curve per building, for one friction value per panel — the
    stored mu_k nearest `mu`, else the median of the content's stored values at which it
    slides rather than rocks (:func:`_ecdf_pair`; the panel's title says which and why); or
    None when the set has no slide results.

    ``F(x)`` is the fraction of all ``n`` records whose peak slide is at most ``x``. A record
    under which the object rocks (not simulated as a slider) has no slide: it is never ≤ any
    ``x`` and never drawn as 0, so the curve ends at ``(n − n_rock)/n`` and the legend says how
    many rock. Peak slide on a symmetric-log axis (linear below :data:`SLIDE_LINTHRESH`, so
    that the records at rest, 0, show); the content's allowable displacements (scene
    ``allowable``) as dotted grey lines. With one record per building a dot plot (a marker per
    record, buildings on the y axis) replaces the one-step curve.
    """
    from floorslide.report.records import record_rows

    rows = [r for r in record_rows(study) if r["record_set"] == record_set]
    if not rows:
        return None
    panels, cut = _pick(_panel_keys(rows, study))
    colors = building_colors(study)
    n_all = len({r["record"] for r in rows})
    fig, axes = _new_figure(len(panels))
    _suptitle(
        fig,
        study,
        f"Peak slide over the records (empirical CDF) — set {record_set}, {n_all} records\n"
        "one friction value per panel (in its title); records where the "
        "object rocks are never ≤ any slide: a curve ends at the fraction that slides or rests"
        + (" (some panels left out)" if cut else ""),
    )
    any_allowable = False
    for ax, (floor, content) in zip(axes, panels, strict=True):
        prow = [r for r in rows if r["floor"] == floor and r["content"] == content]
        mu_k, mu_s, how = _ecdf_pair(prow, mu)
        prow = [r for r in prow if r["mu_k"] == mu_k and r["mu_s"] == mu_s]
        bids = [b for b in study.buildings if any(r["building"] == b for r in prow)]
        curves = {b: _ecdf_points([r for r in prow if r["building"] == b]) for b in bids}
        allowable = _allowables(study, content)
        reach = max(
            [float(c[0].max()) for c in curves.values() if c[0].size] + list(allowable) + [0.0]
        )
        right = max(1.5 * reach, 2 * SLIDE_LINTHRESH)
        dots = max(c[2] for c in curves.values()) == 1
        for i, bid in enumerate(bids):
            slides, y, _, n_rock = curves[bid]
            label = bid + (f" ({n_rock} rock)" if n_rock else "")
            if dots:
                if slides.size:
                    ax.plot(
                        slides, np.full(slides.size, i), "o", color=colors[bid], ms=7, label=label
                    )
                else:
                    ax.plot([], [], "o", color=colors[bid], ms=7, label=label)
                    ax.annotate(
                        "rocks: not a slider",
                        (0.0, i),
                        xytext=(6, 0),
                        textcoords="offset points",
                        va="center",
                        fontsize="small",
                        color=colors[bid],
                    )
                continue
            if slides.size == 0:
                ax.plot([], [], "-", color=colors[bid], label=label + ": no slide drawn")
                continue
            x = np.r_[slides[0], slides, right]
            yy = np.r_[0.0, y, y[-1]]
            ax.step(x, yy, where="post", color=colors[bid], lw=1.5, label=label)
            last = np.r_[slides[1:] != slides[:-1], True]  # ties: one marker, at the top
            ax.plot(slides[last], y[last], "o", color=colors[bid], ms=3.5)
        for a in allowable:
            any_allowable = True
            ax.axvline(a, color="0.5", ls=":", lw=1.3, zorder=0)
            ax.annotate(
                f"allowable {a:g} m",
                (a, 1.0),
                xycoords=("data", "axes fraction"),
                xytext=(-2, -4),
                textcoords="offset points",
                rotation=90,
                ha="right",
                va="top",
                fontsize="x-small",
                color="0.35",
            )
        ax.set_xscale("symlog", linthresh=SLIDE_LINTHRESH)
        ax.set_xlim(-0.3 * SLIDE_LINTHRESH, right)
        ax.set_xlabel("peak slide (m; linear below 1 mm)")
        if dots:
            ax.set_yticks(range(len(bids)), bids, fontsize="small")
            ax.set_ylim(-0.6, len(bids) - 0.4)
            ax.set_ylabel("building (one record)")
        else:
            ax.set_ylim(-0.02, 1.05)
            ax.set_ylabel(f"fraction of the records ≤ x (of {max(c[2] for c in curves.values())})")
        same = abs(mu_k - mu_s) <= 1e-12
        label = f"mu_k = {mu_k:g}" + ("" if same else f", mu_s = {mu_s:g}")
        ax.set_title(f"{content} on floor {floor}, {label}" + (f" ({how})" if how else ""))
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize="x-small", loc="best", title="building", title_fontsize="x-small")
    if any_allowable:
        fig.legend(
            [Line2D([], [], color="0.5", ls=":", lw=1.3)],
            ["allowable displacement of the content (scene 'allowable')"],
            loc="outside lower center",
            fontsize="small",
        )
    return fig


def _fragility_keys(rows: Sequence[dict], study: Study) -> list[tuple]:
    """The panels of the fragility figure, ``(building, floor, content, mu_k, mu_s)``, in the
    tables' order."""
    keys = {
        (r["building"], int(r["floor"]), r["content"], float(r["mu_k"]), float(r["mu_s"]))
        for r in rows
    }
    return sorted(
        keys,
        key=lambda k: (
            _rank(list(study.buildings), k[0]),
            _natural(k[0]),
            _rank(study.contents, k[2]),
            k[2],
            k[1],
            k[3],
            k[4],
        ),
    )


def _fragility_key(r: dict) -> tuple:
    return (r["building"], int(r["floor"]), r["content"], float(r["mu_k"]), float(r["mu_s"]))


def figure_fragility(study: Study, tables: DesignTables, record_set: str) -> Figure | None:
    """Fragility curves of the ``fragility`` table's rows of a set family (its stripes of
    scaled records), or None when it has none.

    One panel per building, floor, content and mu_k (at most :data:`MAX_PANELS`): per damage
    state (``slide > a m``, ``overturn``) the fraction of each stripe's records that exceed
    (markers, each stripe's number of records written small) and the lognormal fragility
    fitted to them by maximum likelihood with a binomial likelihood per stripe,
    ``P(exceed | IM = x) = Φ(ln(x/θ)/β)`` (Baker 2015, Eq. 11), over a log-spaced range of the
    intensity measure covering the stripes; where the fit does not exist (θ and β NaN) the
    legend gives the table's note instead.

    References
    ----------
    Baker, J. W. (2015). Efficient analytical fragility function fitting using dynamic
    structural analysis. *Earthquake Spectra* 31(1), 579–599.
    """
    import textwrap

    from scipy.stats import norm

    rows = [r for r in tables.tables.get("fragility", []) if r["record_set"] == record_set]
    if not rows:
        return None
    keys, cut = _pick(_fragility_keys(rows, study))
    states = list(dict.fromkeys(r["state"] for r in rows))
    from matplotlib import colormaps

    cmap = colormaps["tab10"]
    color = {s: cmap(i % 10) for i, s in enumerate(states)}
    ims = list(dict.fromkeys(str(r["im"]) for r in rows))
    fig, axes = _new_figure(len(keys))
    # stripes left empty (every record rocks: no slide) are said in the legend, not here
    n_min = min(
        (n for r in rows for n in r["n_records"] if n > 0),
        default=MIN_RECORDS,
    )
    _suptitle(
        fig,
        study,
        f"Fragility — set {record_set}: fraction of each stripe's records exceeding (markers; "
        f"n per stripe written small) and the lognormal fit Φ(ln(x/θ)/β) by maximum likelihood "
        "(Baker 2015)"
        + (
            f"; caution: stripes of only {n_min} records (< {MIN_RECORDS})"
            if n_min < MIN_RECORDS
            else ""
        )
        + (" (some panels left out)" if cut else ""),
    )
    for ax, key in zip(axes, keys, strict=True):
        bid, floor, content, mu_k, mu_s = key
        sel = [r for r in rows if _fragility_key(r) == key]
        same = abs(mu_k - mu_s) <= 1e-12
        mu = f"mu_k = {mu_k:g}" + ("" if same else f", mu_s = {mu_s:g}")
        ax.set_title(f"{bid}: {content} on floor {floor}, {mu}", fontsize="medium")
        sel.sort(key=lambda r: states.index(r["state"]))
        levels_all = np.concatenate([np.asarray(r["levels"], dtype=float) for r in sel])
        levels_all = levels_all[np.isfinite(levels_all) & (levels_all > 0)]
        if levels_all.size == 0:
            ax.text(0.5, 0.5, "no stripes", ha="center", transform=ax.transAxes)
            continue
        lo, hi = float(levels_all.min()), float(levels_all.max())
        left, right = lo / 1.3, hi * 1.3
        handles, labels = [], []
        extrapolated = unresolved = False
        counts = {tuple(r["n_records"]) for r in sel}
        shared = len(counts) == 1 and len({tuple(r["levels"]) for r in sel}) == 1
        for j, r in enumerate(sel):
            c = color[r["state"]]
            x = np.asarray(r["levels"], dtype=float)
            n = np.asarray(r["n_records"], dtype=float)
            k = np.asarray(r["n_exceed"], dtype=float)
            frac = np.divide(k, n, out=np.full_like(k, np.nan), where=n > 0)
            median, beta = float(r["median"]), float(r["beta"])
            if math.isfinite(median) and math.isfinite(beta) and median > 0 and beta > 0:
                a, b = min(lo, median), max(hi, median)
                if median < lo / 10 or median > hi * 10:
                    a, b = lo, hi
                xs = np.union1d(
                    np.geomspace(a / 1.3, b * 1.3, 200), [median] if a <= median <= b else []
                )
                left, right = min(left, xs[0]), max(right, xs[-1])
                # solid between this row's stripes (where it is fitted), dotted beyond
                lo_x, hi_x = float(x.min()), float(x.max())
                for seg, style, lw in (
                    (np.union1d(xs[(xs > lo_x) & (xs < hi_x)], [lo_x, hi_x]), "-", 1.5),
                    (np.union1d(xs[xs < lo_x], [lo_x]), ":", 1.3),
                    (np.union1d(xs[xs > hi_x], [hi_x]), ":", 1.3),
                ):
                    if seg.size > 1:
                        cdf = norm.cdf(np.log(seg / median) / beta)
                        ax.plot(seg, cdf, style, color=c, lw=lw)
                        extrapolated = extrapolated or style == ":"
                handles.append(Line2D([], [], color=c, lw=1.5, marker="o", ms=5))
                labels.append(f"{r['state']}: θ = {median:.3g}, β = {beta:.2f}")
                partial = int(np.sum((frac > 0) & (frac < 1)))
                if partial < 2:  # the rise lies between two stripes: any steeper β fits
                    unresolved = True
                    labels[-1] = (
                        f"{r['state']}: θ = {median:.3g}, β = {beta:.2g}?\n"
                        f"  β unresolved: {partial} of {len(x)} stripes between 0 and 1"
                    )
            else:
                # the note's first clause; the whole note is in the fragility table
                note = str(r.get("note", "")).split(";")[0].split(":")[0] or "no fit"
                handles.append(Line2D([], [], color=c, ls="none", marker="o", ms=5))
                labels.append(
                    f"{r['state']}, no fit: " + textwrap.fill(note, 44, break_on_hyphens=False)
                )
            ax.plot(x, frac, "o", color=c, ms=6, mec="white", mew=0.5, zorder=3)
            if not shared:
                for xi, fi, ni in zip(x, frac, n, strict=True):
                    ax.annotate(
                        f"{int(ni)}",
                        (xi, fi),
                        xytext=(4, 4 + 8 * j),
                        textcoords="offset points",
                        fontsize="xx-small",
                        color=c,
                    )
        if shared:
            x0 = np.asarray(sel[0]["levels"], dtype=float)
            for xi, ni in zip(x0, sel[0]["n_records"], strict=True):
                ax.annotate(
                    f"n={int(ni)}",
                    (xi, 0.0),
                    xycoords=("data", "axes fraction"),
                    xytext=(0, 3),
                    textcoords="offset points",
                    ha="center",
                    fontsize="xx-small",
                    color="0.3",
                )
        ax.set_xscale("log")
        ax.set_xlim(left, right)
        ticks = np.unique(levels_all)
        if ticks.size <= 8:
            from matplotlib.ticker import NullFormatter

            ax.set_xticks(ticks, [f"{t:g}" for t in ticks])
            ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_ylim(-0.08, 1.05)
        ax.set_xlabel(" / ".join(ims))
        ax.set_ylabel("P(exceed)")
        ax.grid(alpha=0.3, which="both")
        if extrapolated:
            handles.append(Line2D([], [], color="0.3", ls=":", lw=1.3))
            labels.append("fit beyond the stripes (extrapolated)")
        if unresolved:
            handles.append(Line2D([], [], ls="none"))
            labels.append("?: the stripes do not resolve β (its rise lies between two stripes)")
        # below the panel, never over the curves and markers
        ax.legend(
            handles,
            labels,
            fontsize="x-small",
            loc="upper center",
            bbox_to_anchor=(0.5, -0.2),
            title="state",
            title_fontsize="x-small",
        )
    return fig


# --------------------------------------------------------------------------------------------
# the API


def plot_figures(
    result: str | Path | ResultFile | Study,
    directory: str | Path,
    compare: Sequence[str] | None = None,
    damping: float | None = None,
    *,
    allow_incomplete: bool = False,
    workers: int = 1,
    ecdf_mu: float | None = None,
    tables: DesignTables | None = None,
) -> list[Path]:
    """Write the figures of a result file as PNG files into `directory` (created).

    Parameters
    ----------
    result
        Path of a result file, a :class:`ResultFile` or a :class:`~floorslide.report.tables.Study`.
    directory
        Output folder.
    compare
        Comparisons ``"A:B"`` for the ratio figures (default as for the design tables: the
        scene's ``[report] compare``, else every isolated building against its
        superstructure).
    damping
        Damping ratio of the FRS figure (default as for the design tables).
    allow_incomplete
        Accept a result file whose run is not finished; every figure's title then starts
        with INCOMPLETE.
    workers
        Draw the figures in this many processes (forked; where the platform cannot fork, one).
        The files are the same bytes whatever the number.
    ecdf_mu
        The friction value of the peak-slide ECDF figure (the stored mu_k nearest to it; by
        default the median of each content's values at which it slides rather than rocks).
    tables
        The study's design tables when made already, with the same `compare` and `damping`
        (the demo and the HTML report make them for themselves): not made a second time.

    Returns
    -------
    list of Path
        The files written, in order: per record set, histories (if stored), hysteresis (if
        a building on nonlinear isolation stored its loop), rocking (if a content rocks under
        the history record), for a set of record pairs the slide path in the plane (history
        record) and the 2-D against 1-D slides (every record), FRS, peak slide versus mu,
        oscillators (if any), overturning (if the file holds rocking results), one
        peak-slide ratio figure per comparison, the scaled records against the target (sets
        scaled to a target, with floor-0 spectra), the PFA/PGA profile against ASCE 7-22 H_f, the
        empirical CDF of the peak slide; then, once per set family with rows in the
        ``fragility`` table, the fragility curves. A figure without data is not drawn and not
        listed.

    Raises
    ------
    ResultFileError
        Missing, corrupt or empty result file.
    IncompleteResultError
        Tasks are missing and `allow_incomplete` is False.
    ModelError, SceneError
        A bad `compare` or `damping`, or a bad ``[report]`` entry.
    OutputExistsError
        A file in `directory` holds something other than a figure floorslide drew, or is
        the result file (nothing of it is replaced).
    OutputError
        The output folder or a file cannot be written.
    """
    study = load_study(result)
    study.require_complete(allow_incomplete)
    if tables is None:
        tables = design_tables(study, compare=compare, damping=damping, allow_incomplete=True)
    if compare is not None:
        drawn = {r["comparison"] for r in tables["slide_ratios"]}
        for comp in tables.comparisons:
            if comp.spec not in drawn:
                raise ModelError(
                    f"{comp.spec!r} draws nothing: its buildings share no content on a floor "
                    "(no peak-slide ratio to plot)",
                    "compare",
                )
    z = resolve_damping(study, damping)
    directory = Path(directory)
    written: list[Path] = []
    used: set[str] = set()

    def target(stem: str) -> Path:
        name, k = stem, 2
        while name in used:
            name, k = f"{stem}-{k}", k + 1
        used.add(name)
        return directory / f"{name}.png"

    jobs: list[tuple[str, Callable[[], Figure | None]]] = []
    for rs in study.sets:
        s = _slug(rs)
        jobs += [
            (f"histories_{s}", functools.partial(figure_histories, study, rs)),
            (f"hysteresis_{s}", functools.partial(figure_hysteresis, study, rs)),
            (f"rocking_{s}", functools.partial(figure_rocking, study, rs)),
            (f"plane_path_{s}", functools.partial(figure_plane, study, rs)),
            (f"plane_ratio_{s}", functools.partial(figure_plane_ratio, study, rs)),
        ]
        if z is not None:
            jobs.append((f"frs_{s}", functools.partial(figure_frs, study, rs, z)))
        jobs += [
            (f"slide_vs_mu_{s}", functools.partial(figure_slide_vs_mu, study, tables, rs)),
            (f"oscillators_{s}", functools.partial(figure_oscillators, study, tables, rs)),
            (f"overturning_{s}", functools.partial(figure_overturning, study, tables, rs)),
        ]
        for comp in tables.comparisons:
            a, b = comp.spec.split(":")
            jobs.append(
                (
                    f"slide_ratio_{s}_{_slug(a)}-over-{_slug(b)}",
                    functools.partial(figure_slide_ratio, study, tables, rs, comp.spec),
                )
            )
        jobs += [
            (f"scaled_spectra_{s}", functools.partial(figure_scaled_spectra, study, rs)),
            (f"pfa_profile_{s}", functools.partial(figure_pfa_profile, study, tables, rs)),
            (
                f"slide_ecdf_{s}",
                functools.partial(figure_slide_ecdf, study, tables, rs, ecdf_mu),
            ),
        ]
    families = sorted({str(r["record_set"]) for r in tables.tables.get("fragility", [])})
    for family in families:
        jobs.append(
            (
                f"fragility_{_slug(family)}",
                functools.partial(figure_fragility, study, tables, family),
            )
        )
    for stem, png in zip(
        (stem for stem, _ in jobs), _render([job for _, job in jobs], workers), strict=True
    ):
        if png is not None:
            path = outputs.write_output(
                target(stem),
                png,
                inputs=[study.source],
                replace=outputs.floorslide_png,
                advice="choose another folder with -o, or move the file away",
                what="the figure",
            )
            written.append(path)
    return written
