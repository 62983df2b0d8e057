"""Issue 14: isolator results in the reports — the per-record columns and the ``isolators``
design table equal statistics computed here from the task attributes, an empty table says why,
and ``hysteresis_<set>.png`` is drawn for a study on nonlinear isolation and only then."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floorslide.report import design_tables, format_markdown, record_table
from floorslide.report.formats import format_csv
from floorslide.run.store import ResultFile
from tests.run.isolation_study import run_study

ISOLATORS = {
    # capacity 0.32 m: rec1 exceeds it (peak 0.332 m), rec2 and rec3 stay within
    "fps": '{ model = "friction_pendulum", mu = [0.04, 0.08], capacity = 0.32 }',
    "lrb": '{ model = "bilinear", q_ratio = 0.05, alpha = 0.1 }',
}
P84 = 84.0  # the package's percentile, numpy "linear" (Hyndman & Fan definition 7)


@pytest.fixture(scope="module")
def nonlinear(tmp_path_factory):
    """The study with three records on fixed, fps@mu=0.04, fps@mu=0.08 and lrb."""
    _, out = run_study(tmp_path_factory.mktemp("nonlinear"), ISOLATORS, n=3)
    return out


@pytest.fixture(scope="module")
def linear_only(tmp_path_factory):
    _, out = run_study(tmp_path_factory.mktemp("linear"), {"iso": '{ model = "linear" }'}, n=1)
    return out


def _by_building(out) -> dict[str, list[dict]]:
    metas: dict[str, list[dict]] = {}
    for t in ResultFile(out).tasks():
        metas.setdefault(t.meta["building"], []).append(t.meta)
    return metas


def test_per_record_columns_are_the_task_attributes(nonlinear):
    df = record_table(nonlinear)
    metas = {(m["record"], m["building"]): m for ms in _by_building(nonlinear).values() for m in ms}
    assert len(df) == len(metas)  # one content, one friction value: a row per task
    assert df.attrs["units"]["isolator_peak_disp_m"] == "m"
    for row in df.to_dict("records"):
        m = metas[(row["record"], row["building"])]
        if row["building"] == "fixed":
            for k in ("isolator_peak_disp_m", "isolator_residual_disp_m"):
                assert math.isnan(row[k])
            assert math.isnan(row["isolator_peak_force_ratio"])
            assert math.isnan(row["isolator_capacity_exceeded"])
            continue
        assert row["isolator_peak_disp_m"] == m["isolator_peak_displacement"]
        assert row["isolator_residual_disp_m"] == m["isolator_residual_displacement"]
        assert row["isolator_peak_force_ratio"] == m["isolator_peak_force_ratio"]
        assert row["isolator_capacity_exceeded"] is bool(m["isolator_capacity_exceeded"])
    exceeded = df[df.building == "fps@mu=0.04"].set_index("record").isolator_capacity_exceeded
    assert exceeded.to_dict() == {"rec1": True, "rec2": False, "rec3": False}


def test_the_isolators_table_equals_statistics_of_the_task_attributes(nonlinear):
    rows = design_tables(nonlinear)["isolators"]
    metas = _by_building(nonlinear)
    assert [r["building"] for r in rows] == ["fps@mu=0.04", "fps@mu=0.08", "lrb"]
    for row in rows:
        ms = metas[row["building"]]
        peak = np.array([m["isolator_peak_displacement"] for m in ms])
        resid = np.abs([m["isolator_residual_displacement"] for m in ms])
        force = np.array([m["isolator_peak_force_ratio"] for m in ms])
        expected = {
            "record_set": "s",
            "isolator": ms[0]["isolator"],
            "isolation_period": 2.5,
            "isolation_damping": 0.0,
            "n_records": 3,
            "few_records": True,
            "peak_disp_median": np.median(peak),
            "peak_disp_p84": np.percentile(peak, P84, method="linear"),
            "peak_disp_max": peak.max(),
            "residual_disp_median": np.median(resid),
            "peak_force_ratio_median": np.median(force),
            "peak_force_ratio_p84": np.percentile(force, P84, method="linear"),
            "n_capacity_exceeded": sum(m["isolator_capacity_exceeded"] for m in ms),
        }
        for key, value in expected.items():
            if isinstance(value, str):
                assert row[key] == value, (row["building"], key)
            else:
                assert row[key] == pytest.approx(value, rel=1e-15, abs=0), (row["building"], key)
    fps04, fps08, lrb = rows
    assert (fps04["mu"], fps04["mu_s"], fps04["capacity"]) == (0.04, 0.04, 0.32)
    assert fps08["mu"] == 0.08 and math.isnan(fps04["q_ratio"])
    assert fps04["radius"] == pytest.approx(9.80665 * (2.5 / (2 * math.pi)) ** 2, rel=1e-14)
    assert lrb["q_ratio"] == 0.05 and lrb["alpha"] == pytest.approx(0.1, rel=1e-14)
    assert lrb["yield_disp"] > 0 and math.isnan(lrb["capacity"]) and math.isnan(lrb["mu"])
    assert fps04["n_capacity_exceeded"] == 1 and fps08["n_capacity_exceeded"] == 0
    assert fps04["note"].startswith("capacity exceeded under 1 of 3 records")
    assert "moat wall" in fps04["note"] and "not modelled" in fps04["note"]
    assert fps08["note"] == "" and lrb["note"] == "no capacity given"


def test_the_isolators_table_in_markdown_keeps_the_parameters_used(nonlinear):
    text = format_markdown(design_tables(nonlinear), ["isolators"])
    header = next(ln for ln in text.splitlines() if ln.startswith("| record_set"))
    assert "peak_disp_median (m)" in header and "| mu |" in header and "q_ratio" in header
    assert "| yield_disp (m) |" in header and "capacity (m)" in header
    assert "isolators: displacements are the isolation layer's u0" in text


def test_without_nonlinear_isolation_the_table_says_so(linear_only):
    tables = design_tables(linear_only)
    assert tables["isolators"] == []
    note = "no building on nonlinear isolation in this study"
    assert f"isolators: {note}" in tables.notes
    md = format_markdown(tables, ["isolators"])
    assert f"_No rows: {note}._" in md
    assert format_csv("isolators", []).startswith(f"# {note}\nrecord_set,building,isolator,")
    status = "INCOMPLETE: 1 of 2 tasks done"
    assert format_csv("isolators", [], status).startswith(f"# {status}\n# {note}\nrecord_set,")
    df = record_table(linear_only)
    assert df.isolator_peak_disp_m.isna().all() and df.isolator_capacity_exceeded.isna().all()


def test_the_hysteresis_figure_is_drawn_on_nonlinear_isolation(nonlinear, tmp_path):
    from floorslide.report.plots import figure_hysteresis, plot_figures
    from floorslide.report.study import load_study

    names = [p.name for p in plot_figures(nonlinear, tmp_path / "fig")]
    assert names[:2] == ["histories_s.png", "hysteresis_s.png"]  # after the histories
    assert (tmp_path / "fig" / "hysteresis_s.png").read_bytes()[:4] == b"\x89PNG"
    study = load_study(nonlinear)
    fig = figure_hysteresis(study, "s")
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert [ax.get_title().split(",")[0] for ax in axes] == ["fps@mu=0.04", "fps@mu=0.08", "lrb"]
    task = next(t for t in study.tasks if t.histories and t.meta["building"] == "fps@mu=0.04")
    ax = axes[0]
    assert "record rec1" in ax.get_title() and "friction pendulum, mu = 0.04" in ax.get_title()
    loop = ax.get_lines()[0]
    np.testing.assert_array_equal(loop.get_xdata(), 1000 * task.histories.isolator_displacement)
    np.testing.assert_array_equal(loop.get_ydata(), task.histories.isolator_force_ratio)
    assert ax.get_xlabel() == "isolator displacement u0 (mm)"
    assert ax.get_ylabel() == "isolator force / W (V/W)"
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    peak = 1000 * task.meta["isolator_peak_displacement"]
    assert f"peak |u0| = {peak:.4g} mm" in labels
    assert "capacity 320 mm: EXCEEDED (impact not modelled)" in labels  # rec1 exceeds it
    assert not any("capacity" in t.get_text() for t in axes[2].get_legend().get_texts())


def test_no_hysteresis_figure_without_nonlinear_isolation(linear_only, tmp_path):
    from floorslide.report.plots import plot_figures

    names = [p.name for p in plot_figures(linear_only, tmp_path / "fig")]
    assert "histories_s.png" in names
    assert not any(n.startswith("hysteresis") for n in names)
