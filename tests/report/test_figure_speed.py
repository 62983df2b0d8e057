"""The figures' fast save (:func:`floorslide.report.plots.png_bytes`): the bytes of a plain
``savefig`` — layout engine run once, ticks and text layouts reused, metrics shared between
figures — and the figure left as it was."""

from __future__ import annotations

import functools
import io
import os
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import matplotlib as mpl
import numpy as np
import pytest
from matplotlib.axis import Axis
from matplotlib.figure import Figure

from floorslide.outputs import PNG_SOFTWARE
from floorslide.report import design_tables, plots
from floorslide.report.study import load_study

META = {"Software": PNG_SOFTWARE}


def _savefig(fig: Figure, dpi: float = plots.DPI) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, dpi=dpi, format="png", metadata=META)
    return buf.getvalue()


def _assert_same(build, dpi: float = plots.DPI) -> None:
    """A figure from `build` saved by png_bytes is the bytes of the same figure built again
    and saved by savefig."""
    fast = plots.png_bytes(build(), dpi, META)
    assert fast == _savefig(build(), dpi)


def _panels(layout: str | None = "constrained") -> Figure:
    """What the report's figures use: a shared-x grid, log and symlog axes with mathtext tick
    labels, an offset text, an inset, a colorbar, a suptitle, titles and an outside legend."""
    rng = np.random.default_rng(3)
    fig = Figure(figsize=(9.0, 6.5), layout=layout)
    axes = fig.subplots(2, 2, sharex="col")
    t = np.linspace(0.0, 20.0, 400)
    for k, ax in enumerate(axes[:, 0]):
        ax.plot(t, np.sin(t * (k + 1)) * 10 ** (3 * k), label=f"series {k}")
        ax.set_title(f"panel {k}: $\\theta/\\alpha$ against time", fontsize="medium")
        ax.set_ylabel("value (m/s²)")
        ax.grid(alpha=0.3)
    axes[1, 0].set_xlabel("time (s)")
    periods = np.geomspace(0.05, 4.0, 30)
    axes[0, 1].loglog(periods, 1 + periods**-0.5, "o-", ms=3)
    axes[0, 1].set_xlabel("period (s)")
    axes[0, 1].grid(alpha=0.3, which="both")
    axes[1, 1].plot(periods, rng.normal(size=periods.size) * 1e-2, "^", mfc="none")
    axes[1, 1].set_xscale("log")
    axes[1, 1].set_yscale("symlog", linthresh=1e-3)
    axes[1, 1].set_ylabel("peak slide (m)")
    inset = axes[1, 1].inset_axes([0.0, 1.02, 1.0, 0.1], sharex=axes[1, 1])
    inset.set_yticks([0.5], ["rock"])
    inset.plot([0.1, 1.0], [0.5, 0.5], "x")
    image = axes[0, 1].imshow(
        rng.random((8, 8)), extent=(0.05, 4.0, 1.0, 6.0), aspect="auto", alpha=0.3
    )
    fig.colorbar(image, ax=axes[0, 1], label="fraction")
    axes[0, 0].annotate("peak", (5.0, 0.9), xytext=(4, 4), textcoords="offset points")
    fig.legend(loc="outside lower center" if layout else "lower center", ncols=2)
    fig.suptitle("A suptitle long enough to be wrapped in two lines\nsecond line")
    return fig


@pytest.mark.parametrize("layout", ["constrained", "compressed", "tight", None])
def test_png_bytes_are_those_of_savefig(layout):
    _assert_same(functools.partial(_panels, layout))


def test_png_bytes_at_another_dpi_and_settings():
    """Another resolution, and text settings changed between figures: the shared metrics
    are not those of the other settings."""
    _assert_same(_panels, dpi=72)
    with mpl.rc_context({"font.size": 13, "mathtext.fontset": "stix"}):
        _assert_same(_panels)
    _assert_same(_panels)


def test_png_bytes_leaves_the_figure_and_matplotlib_as_they_were():
    fig = _panels()
    canvas, dpi, engine = fig.canvas, fig.dpi, fig.get_layout_engine()
    plots.png_bytes(fig, plots.DPI, META)
    assert fig.canvas is canvas and fig.dpi == dpi and fig.get_layout_engine() is engine
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            assert isinstance(axis, Axis)
            assert "_update_ticks" not in vars(axis)
            assert "_get_ticklabel_bboxes" not in vars(axis)
    # saved again, the layout starts from the first one's (as savefig's does): the same bytes
    # as a second savefig
    again = _panels()
    _savefig(again)
    assert plots.png_bytes(fig, plots.DPI, META) == _savefig(again)


@pytest.fixture(scope="module")
def rich(rich_study):
    s = load_study(rich_study.path)
    return s, design_tables(s)


def test_report_figures_are_the_bytes_of_savefig(rich):
    """Every kind of the report's figures the synthetic study has, drawn by the fast save
    one after the other (sharing the text metrics), against savefig."""
    s, tables = rich
    kinds = [
        functools.partial(plots.figure_histories, s, "broad-band"),
        functools.partial(plots.figure_frs, s, "broad-band", 0.05),
        functools.partial(plots.figure_slide_vs_mu, s, tables, "pulse-like"),
        functools.partial(plots.figure_oscillators, s, tables, "broad-band"),
        functools.partial(plots.figure_slide_ratio, s, tables, "broad-band", "isolated:fixed"),
        functools.partial(plots.figure_pfa_profile, s, tables, "broad-band"),
        functools.partial(plots.figure_slide_ecdf, s, tables, "pulse-like", None),
    ]
    drawn = 0
    for build in kinds:
        if build() is None:
            continue
        _assert_same(build)
        drawn += 1
    assert drawn >= 5


def test_work_precision_figure_is_the_bytes_of_savefig(monkeypatch):
    """The benchmark's work-precision diagram (log-log, annotations, a legend below) goes
    through the fast save: the bytes of savefig."""
    from floorslide.bench import figures

    def row(method, family, setting, cpu, err):
        return SimpleNamespace(
            solver="s", method=method, family=family, setting=setting, cpu_time=cpu, error=err
        )

    rows = [row("exact", "exact", "", 2e-3, 0.0)]
    rows += [row("rk", "Runge-Kutta", f"dt/{n}", 1e-3 * n, 1e-2 / n**4) for n in (1, 2, 4, 8)]
    rows += [row("euler", "Euler", "dt/1", 5e-4, 0.3)]
    result = SimpleNamespace(
        rows=rows,
        solvers={"s": "a block on the ground"},
        metrics={"s": ("peak_slide", "residual_slide")},
        records_of=lambda solver: ({"station_id": "KOBE"}, {"station_id": "AOM008"}),
    )
    fast = figures.work_precision_figure(result, "s")
    monkeypatch.setattr(plots, "png_bytes", lambda fig, dpi, meta: _savefig(fig, dpi))
    assert fast == figures.work_precision_figure(result, "s")


def test_png_bytes_does_not_resolve_the_backend():
    """Reading every rcParam would resolve matplotlib's backend, importing pyplot (and its
    time) into a process that draws without it."""
    code = (
        "import sys\n"
        "from matplotlib.figure import Figure\n"
        "from floorslide.report.plots import png_bytes\n"
        "fig = Figure(layout='constrained')\n"
        "fig.subplots().plot([1, 2])\n"
        "png_bytes(fig, 50)\n"
        "assert 'matplotlib.pyplot' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, env=_child_env())


def _child_env() -> dict[str, str]:
    """This process' environment, its floorslide first on the path, without a backend set."""
    import floorslide

    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}
    root = str(Path(floorslide.__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [root, env.get("PYTHONPATH")]))
    return env
