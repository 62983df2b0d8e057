"""Figures from a result file (DESIGN §3, ``floorslide plot``), drawn with matplotlib (Agg).

One figure per kind and record set, with one panel per floor or per content on a floor:

``histories_<set>.png``
    floor accelerations and sliding histories of the study's history record (the task(s) that
    stored histories), one column per building;
``frs_<set>.png``
    floor response spectra: median PSA over the set's records per building, one panel per
    floor, log period axis;
``slide_vs_mu_<set>.png``
    peak slide versus kinetic friction: median (line) and 84th percentile (open triangles) per
    building, one panel per content and floor;
``slide_ratio_<set>_<A>-over-<B>.png``
    median peak-slide ratio A / B versus the isolation period of A, one curve per friction
    coefficient, per comparison (as in the design tables).

Figures are built on :class:`matplotlib.figure.Figure` objects (no pyplot state) and written as
PNG without a timestamp, so the same result file gives the same files.
"""

from __future__ import annotations

import math
import re
from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from floorslide.constants import G
from floorslide.errors import FloorslideError
from floorslide.report.tables import (
    DesignTables,
    Study,
    design_tables,
    interpolate_spectrum,
    load_study,
    resolve_damping,
)
from floorslide.run.results import TaskResult
from floorslide.run.store import ResultFile

MAX_PANELS = 12
"""At most this many panels per figure (floors or content × floor, evenly picked)."""

MAX_COLUMNS = 4
"""At most this many buildings side by side in the history figure."""

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


def _save(fig: Figure, path: Path) -> Path:
    fig.savefig(path, dpi=DPI, format="png", metadata={"Software": None})
    return path


# --------------------------------------------------------------------------------------------
# figures


def figure_histories(study: Study, record_set: str) -> Figure | None:
    """Floor accelerations and sliding histories of the set's history task(s), or None.

    Columns: buildings that stored histories (at most :data:`MAX_COLUMNS`); row 1: the
    absolute acceleration of every output floor (m/s²); next rows: the slide ``u`` (m,
    relative to the floor) of each content on each floor, one curve per stored friction value.
    """
    order = list(study.buildings)
    tasks = sorted(
        (t for t in study.set_tasks(record_set) if t.histories is not None),
        key=lambda t: order.index(t.meta["building"]),
    )
    if not tasks:
        return None
    tasks, _ = _pick(tasks, MAX_COLUMNS)
    keys: list[str] = []
    for t in tasks:
        for k in t.histories.slides:
            if k not in keys:
                keys.append(k)

    def key_order(k: str):
        content, floor = k.rsplit("/floor_", 1)
        rank = study.contents.index(content) if content in study.contents else len(study.contents)
        return (rank, content, int(floor))

    keys = sorted(keys, key=key_order)
    keys, cut = _pick(keys, 6)
    nrows, ncols = 1 + len(keys), len(tasks)
    fig = Figure(figsize=(5.6 * ncols + 1.0, 2.6 * nrows + 1.0), layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False, sharex="col")
    from matplotlib import colormaps

    records = sorted({str(t.meta["record"]) for t in tasks})
    fig.suptitle(
        f"Floor motions and sliding — record {', '.join(records)}, set {record_set}"
        + (" (some panels left out)" if cut else "")
    )
    for j, t in enumerate(tasks):
        h = t.histories
        time = np.arange(h.floor_acceleration.shape[-1]) * h.dt
        ax = axes[0][j]
        floors = np.asarray(h.floors).tolist()
        cmap = colormaps["plasma"]
        for i, floor in enumerate(floors):
            color = cmap(0.1 + 0.75 * i / max(len(floors) - 1, 1))
            ax.plot(time, h.floor_acceleration[i], lw=0.7, color=color, label=f"floor {floor}")
        ax.set_title(f"{t.meta['building']}: floor absolute acceleration")
        ax.set_ylabel("acceleration (m/s²)")
        ax.grid(alpha=0.3)
        if floors:
            ax.legend(fontsize="small", loc="upper right")
        for i, k in enumerate(keys, start=1):
            ax = axes[i][j]
            content, floor = k.rsplit("/floor_", 1)
            if k not in h.slides:
                ax.text(0.5, 0.5, "not on this building", ha="center", transform=ax.transAxes)
                ax.set_axis_off()
                continue
            u = np.atleast_2d(h.slides[k])
            mus = np.atleast_1d(h.mu_k.get(k, np.full(u.shape[0], np.nan)))
            for m in range(u.shape[0]):
                color = colormaps["viridis"](0.1 + 0.8 * m / max(u.shape[0] - 1, 1))
                ax.plot(time[: u.shape[1]], u[m], lw=0.9, color=color, label=f"mu = {mus[m]:g}")
            ax.set_title(f"{content} on floor {floor}: slide relative to the floor")
            ax.set_ylabel("slide u (m)")
            ax.grid(alpha=0.3)
            ax.legend(fontsize="small", loc="upper left")
        axes[-1][j].set_xlabel("time (s)")
    return fig


def _median_spectrum(tasks: Sequence[TaskResult], floor: int, damping: float):
    grid, stack = None, []
    for t in tasks:
        for s in t.spectra:
            if int(s.floor) != floor:
                continue
            zs = np.atleast_1d(np.asarray(s.damping, dtype=float))
            hit = np.nonzero(np.abs(zs - damping) <= 1e-9)[0]
            if hit.size == 0:
                continue
            psa = np.atleast_2d(np.asarray(s.psa, dtype=float))[hit[0]]
            periods = np.asarray(s.periods, dtype=float)
            if grid is None:
                grid = periods
            stack.append(
                psa if np.array_equal(periods, grid) else interpolate_spectrum(periods, psa, grid)
            )
    if grid is None:
        return None, None, 0
    return grid, np.nanmedian(np.array(stack), axis=0), len(stack)


def figure_frs(study: Study, record_set: str, damping: float) -> Figure | None:
    """Median floor response spectra (PSA, g) of the set per building, one panel per floor
    (log period axis), or None when the set has no spectra."""
    tasks = study.set_tasks(record_set)
    by_building: dict[str, list[TaskResult]] = defaultdict(list)
    for t in tasks:
        by_building[t.meta["building"]].append(t)
    floors = sorted({int(s.floor) for t in tasks for s in t.spectra})
    if not floors:
        return None
    floors, cut = _pick(floors, 9)
    colors = building_colors(study)
    fig, axes = _new_figure(len(floors))
    fig.suptitle(
        f"Floor response spectra — set {record_set}\nmedian PSA over records, "
        f"{damping * 100:g} % damping" + (" (some floors left out)" if cut else "")
    )
    handles = {}
    for ax, floor in zip(axes, floors, strict=True):
        present = []
        for bid in study.buildings:
            if bid not in by_building:
                continue
            grid, median, n = _median_spectrum(by_building[bid], floor, damping)
            if grid is None:
                continue
            present.append(bid)
            pos = grid > 0
            (line,) = ax.plot(grid[pos], median[pos] / G, color=colors[bid], lw=1.4)
            handles.setdefault(bid, (line, f"{bid} ({n} records)"))
        ax.set_xscale("log")
        ax.set_xlabel("period T (s)")
        ax.set_ylabel("median PSA (g)")
        ax.set_title(_floor_label(study, floor, present))
        ax.grid(alpha=0.3, which="both")
    fig.legend(
        [h for h, _ in handles.values()],
        [lab for _, lab in handles.values()],
        loc="outside lower center",
        ncols=min(4, len(handles)),
        title="building",
        fontsize="small",
    )
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


def figure_slide_vs_mu(study: Study, tables: DesignTables, record_set: str) -> Figure | None:
    """Peak slide versus mu_k per building (median line, 84th percentile open triangles,
    ``x`` where every record rocks), one panel per content and floor, or None."""
    rows = [r for r in tables["slides"] if r["record_set"] == record_set]
    if not rows:
        return None
    panels, cut = _pick(_panel_keys(rows, study))
    colors = building_colors(study)
    fig, axes = _new_figure(len(panels))
    fig.suptitle(
        f"Peak slide versus friction — set {record_set}\nmedian (line) and 84th percentile "
        "(open triangles) over records" + (" (some panels left out)" if cut else "")
    )
    used: list[str] = []
    any_rock = False
    for ax, (floor, content) in zip(axes, panels, strict=True):
        for bid in study.buildings:
            sel = sorted(
                (
                    r
                    for r in rows
                    if r["building"] == bid and r["floor"] == floor and r["content"] == content
                ),
                key=lambda r: (r["mu_s"], r["mu_k"]),
            )
            if not sel:
                continue
            if bid not in used:
                used.append(bid)
            series: dict[float | None, list[dict]] = defaultdict(list)
            mu_k = [r["mu_k"] for r in sel]
            split = len(set(mu_k)) < len(mu_k)
            for r in sel:
                series[r["mu_s"] if split else None].append(r)
            for _, srows in series.items():
                srows = sorted(srows, key=lambda r: r["mu_k"])
                x = np.array([r["mu_k"] for r in srows])
                med = np.array([r["peak_slide_median"] for r in srows])
                p84 = np.array([r["peak_slide_p84"] for r in srows])
                ax.plot(x, med, "-o", color=colors[bid], ms=4, lw=1.3)
                ax.plot(x, p84, "^", color=colors[bid], mfc="none", ms=6)
                rocks = np.array([r["n_rocked"] > 0 for r in srows])
                if rocks.any():
                    any_rock = True
                    at = np.where(np.isfinite(med), med, 0.0)[rocks]
                    ax.plot(x[rocks], at, "x", color=colors[bid], ms=9, mew=1.5)
        ax.set_yscale("symlog", linthresh=SLIDE_LINTHRESH)
        ax.set_ylim(bottom=0)
        ax.set_xlabel("kinetic friction coefficient mu_k (–)")
        ax.set_ylabel("peak slide (m; linear below 1 mm)")
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
        handles.append(Line2D([], [], color="0.3", marker="x", ls="none", ms=8))
        labels.append("rocks under some records (left out) or all (drawn at 0)")
    fig.legend(
        handles,
        labels,
        loc="outside lower center",
        ncols=min(4, len(handles)),
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


def figure_slide_ratio(
    study: Study, tables: DesignTables, record_set: str, comparison: str
) -> Figure | None:
    """Median peak-slide ratio A / B versus the isolation period of A, one curve per mu_k,
    one panel per content and floor; None if A has no isolation period or no rows."""
    rows = [
        r
        for r in tables["slide_ratios"]
        if r["record_set"] == record_set
        and r["comparison"] == comparison
        and math.isfinite(r["isolation_period_a"])
    ]
    if not rows:
        return None
    a_name, b_name = comparison.split(":")
    panels, cut = _pick(_panel_keys(rows, study))
    fig, axes = _new_figure(len(panels))
    fig.suptitle(
        f"Median peak-slide ratio {a_name} / {b_name} — set {record_set}\n"
        "versus isolation period, one curve per friction coefficient"
        + (" (some panels left out)" if cut else "")
    )
    from matplotlib import colormaps

    mus = sorted({(r["mu_k"], r["mu_s"]) for r in rows})
    same = all(abs(k - s) <= 1e-12 for k, s in mus)
    cmap = colormaps["plasma"]
    mu_color = {m: cmap(0.05 + 0.8 * i / max(len(mus) - 1, 1)) for i, m in enumerate(mus)}
    series = sorted({(_series_name(r["building_a"]), r["building_b"]) for r in rows})
    styles = ["-", "--", ":", "-."]
    gaps = False
    for ax, (floor, content) in zip(axes, panels, strict=True):
        ax.axhline(1.0, color="0.5", lw=0.8, ls="--")
        for si, (sname, b) in enumerate(series):
            for mu in mus:
                sel = sorted(
                    (
                        r
                        for r in rows
                        if r["floor"] == floor
                        and r["content"] == content
                        and (r["mu_k"], r["mu_s"]) == mu
                        and _series_name(r["building_a"]) == sname
                        and r["building_b"] == b
                    ),
                    key=lambda r: r["isolation_period_a"],
                )
                if not sel:
                    continue
                x = np.array([r["isolation_period_a"] for r in sel])
                y = np.array([r["peak_slide_median_ratio"] for r in sel])
                gaps = gaps or not np.isfinite(y).all()
                y = np.where(np.isfinite(y), y, np.nan)
                ax.plot(x, y, styles[si % len(styles)], marker="o", ms=4, color=mu_color[mu])
        ax.set_ylim(bottom=0)
        ax.set_xlabel(f"isolation period T_i of {a_name} (s)")
        ax.set_ylabel(f"median peak slide {a_name} / {b_name} (–)")
        ax.set_title(f"{content} on floor {floor}")
        ax.grid(alpha=0.3)
    handles = [Line2D([], [], color=mu_color[m], marker="o", ms=4) for m in mus]
    labels = [f"mu = {k:g}" if same else f"mu_k = {k:g}, mu_s = {s:g}" for k, s in mus]
    if len(series) > 1:
        for si, (sname, b) in enumerate(series):
            handles.append(Line2D([], [], color="0.3", ls=styles[si % len(styles)]))
            labels.append(f"{sname} / {b}")
    handles.append(Line2D([], [], color="0.5", ls="--", lw=0.8))
    labels.append("ratio 1")
    if gaps:
        handles.append(Line2D([], [], ls="none"))
        labels.append("gaps: 0/0 (neither slides) or x/0 (only A slides), see slide_ratios")
    fig.legend(
        handles,
        labels,
        loc="outside lower center",
        ncols=min(4, len(handles)),
        title="friction",
        fontsize="small",
    )
    return fig


# --------------------------------------------------------------------------------------------
# the API


def plot_figures(
    result: str | Path | ResultFile | Study,
    directory: str | Path,
    compare: Sequence[str] | None = None,
    damping: float | None = None,
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

    Returns
    -------
    list of Path
        The files written, in order: per record set, histories (if stored), FRS, peak slide
        versus mu, then one peak-slide ratio figure per comparison.

    Raises
    ------
    ResultFileError
        Missing, corrupt or empty result file.
    ModelError, SceneError
        A bad `compare` or `damping`, or a bad ``[report]`` entry.
    FloorslideError
        The output folder or a file cannot be written.
    """
    study = load_study(result)
    tables = design_tables(study, compare=compare, damping=damping)
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

    try:
        directory.mkdir(parents=True, exist_ok=True)
        for rs in study.sets:
            s = _slug(rs)
            fig = figure_histories(study, rs)
            if fig is not None:
                written.append(_save(fig, target(f"histories_{s}")))
            if z is not None:
                fig = figure_frs(study, rs, z)
                if fig is not None:
                    written.append(_save(fig, target(f"frs_{s}")))
            fig = figure_slide_vs_mu(study, tables, rs)
            if fig is not None:
                written.append(_save(fig, target(f"slide_vs_mu_{s}")))
            for comp in tables.comparisons:
                fig = figure_slide_ratio(study, tables, rs, comp.spec)
                if fig is not None:
                    a, b = comp.spec.split(":")
                    written.append(
                        _save(fig, target(f"slide_ratio_{s}_{_slug(a)}-over-{_slug(b)}"))
                    )
    except OSError as exc:
        raise FloorslideError(
            f"cannot write the figures: {exc.strerror or exc}", str(directory)
        ) from None
    return written
