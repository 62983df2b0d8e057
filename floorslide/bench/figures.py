"""Work–precision diagrams: error versus CPU time, log–log, one line per method family, the exact
method as a point at its own time on its rounding floor (Hairer, Nørsett & Wanner 1993, §II.1:
the "work-precision diagram")."""

from __future__ import annotations

import math

from floorslide.bench.cases import METRICS
from floorslide.bench.study import BenchResult
from floorslide.outputs import PNG_SOFTWARE

ERROR_FLOOR = 1e-16
"""Errors below this (including exact zeros) are drawn at it: a log axis has no zero."""

MARKERS = "osD^v<>ph"


def work_precision_figure(result: BenchResult, solver: str) -> bytes:
    """The work–precision diagram of `solver` as PNG bytes.

    Parameters
    ----------
    result
        A study from :func:`floorslide.bench.run_bench`.
    solver
        The solver's key.

    Returns
    -------
    bytes
        The PNG (``Software`` :data:`floorslide.outputs.PNG_SOFTWARE`).
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from floorslide.report.plots import png_bytes

    rows = [r for r in result.rows if r.solver == solver]
    exact = next(r for r in rows if r.method == "exact")
    fig = Figure(figsize=(7.2, 6.0), dpi=110, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    families: dict[str, list] = {}
    for r in rows:
        if r.method != "exact":
            families.setdefault(r.family, []).append(r)
    for i, (family, members) in enumerate(families.items()):
        x = [m.cpu_time * 1e3 for m in members]
        y = [max(m.error, ERROR_FLOOR) for m in members]
        marker = MARKERS[i % len(MARKERS)]
        if len(members) > 1:
            (line,) = ax.plot(x, y, linestyle="-", marker=marker, ms=5, label=family)
        else:  # a single point: hollow and larger, visible on top of a family's point
            (line,) = ax.plot(
                x, y, linestyle="none", marker=marker, ms=9, mfc="none", mew=1.5, label=family
            )
        if len(members) > 1:
            ends = [(members[0].setting, x[0], y[0]), (members[-1].setting, x[-1], y[-1])]
            if abs(math.log10(x[-1] / x[0])) < 0.15 and abs(math.log10(y[-1] / y[0])) < 0.3:
                # first and last on top of each other: one label for the family
                ends = [(f"{members[0].setting} … {members[-1].setting}", x[-1], y[-1])]
            for text, xi, yi in ends:
                ax.annotate(
                    text,
                    (xi, yi),
                    textcoords="offset points",
                    xytext=(4, 3),
                    fontsize=7,
                    color=line.get_color(),
                )
    t_exact = exact.cpu_time * 1e3
    floor = max(exact.error, ERROR_FLOOR)
    ax.axhline(floor, color="k", lw=0.8, ls=":")
    ax.axvline(t_exact, color="k", lw=0.8, ls=":")
    ax.plot(
        [t_exact],
        [floor],
        marker="*",
        ms=14,
        color="k",
        linestyle="none",
        label=f"exact ({t_exact:.3g} ms); dotted: its time and rounding floor",
    )
    ax.set_xscale("log")
    ax.set_yscale("log")
    recs = result.records_of(solver)
    n = len(recs)
    ax.set_xlabel(f"CPU time per run, ms (median, one thread; sum over {n} record{'s' * (n > 1)})")
    names = " and ".join(METRICS[m] for m in result.metrics[solver])
    metrics = result.metrics[solver]
    over = "periods" if "psa" in metrics else "floors" if "pfa" in metrics else "objects"
    ax.set_ylabel(f"relative error of {names}\n(max over records and {over})")
    ids = ", ".join(r["station_id"] for r in recs)
    ax.set_title(f"{result.solvers[solver]}\nrecords: {ids}", fontsize=10)
    ax.grid(True, which="major", lw=0.4, alpha=0.6)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, frameon=False)
    # savefig's bytes (dpi: the figure's), for less CPU: laid out once
    return png_bytes(fig, fig.dpi, {"Software": PNG_SOFTWARE})
