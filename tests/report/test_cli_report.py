"""floorslide table and floorslide plot (docs/design.md §3): outputs, exit codes, one-line
errors."""

from __future__ import annotations

import csv
import io
import json
import subprocess
import sys

import h5py
import numpy as np
import pytest

from floorslide.cli import REPORT_TABLES, main
from floorslide.report import COLUMNS, TABLE_NAMES, design_tables, format_markdown
from floorslide.report.formats import format_csv

PNG = b"\x89PNG\r\n\x1a\n"


def invoke(monkeypatch, capsys, *args):
    """Run the console entry point in this process: (exit code, stdout, stderr)."""
    monkeypatch.setattr(sys, "argv", ["floorslide", *map(str, args)])
    code = 0
    try:
        main()
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else 1
    out = capsys.readouterr()
    return code, out.out, out.err


def test_table_names_match_the_report_package():
    assert REPORT_TABLES == TABLE_NAMES


def test_table_markdown_on_stdout(monkeypatch, capsys, study):
    code, out, err = invoke(monkeypatch, capsys, "table", study.path)
    assert code == 0, err
    assert out == format_markdown(design_tables(study.path))


def test_table_csv_sections_directory_and_selection(monkeypatch, capsys, study, tmp_path):
    code, out, _ = invoke(monkeypatch, capsys, "table", study.path, "--format", "csv")
    assert code == 0
    assert [
        line[len("# table: ") :] for line in out.splitlines() if line.startswith("# table")
    ] == list(TABLE_NAMES)
    code, out, _ = invoke(
        monkeypatch, capsys, "table", study.path, "--format", "csv", "--table", "pfa"
    )
    # one table is a plain CSV: the '# table: pfa' line it began with is gone (issue 19 item 8)
    assert code == 0 and "# table" not in out
    assert out == format_csv("pfa", design_tables(study.path)["pfa"])
    assert next(csv.DictReader(io.StringIO(out)))["building"]
    two = ("--table", "pfa", "--table", "frs")
    code, out, _ = invoke(monkeypatch, capsys, "table", study.path, "--format", "csv", *two)
    assert code == 0 and out.startswith("# table: pfa\n") and "\n# table: frs\n" in out
    code, out, _ = invoke(
        monkeypatch, capsys, "table", study.path, "--format", "csv", "-o", tmp_path / "t"
    )
    assert code == 0
    written = out.split()
    assert [p.rsplit("/", 1)[1] for p in written] == [f"{n}.csv" for n in TABLE_NAMES]
    rows = list(csv.DictReader(io.StringIO((tmp_path / "t" / "slides.csv").read_text())))
    assert list(rows[0]) == [c.name for c in COLUMNS["slides"]] and len(rows) == 18


def test_table_json_options(monkeypatch, capsys, study, tmp_path):
    code, out, err = invoke(
        monkeypatch,
        capsys,
        "table",
        study.path,
        "--json",
        "--compare",
        "isolated@T=2:fixed",
        "--periods",
        "0.2,1",
        "--damping",
        "0.02",
    )
    assert code == 0, err
    data = json.loads(out)
    assert data["periods"] == [0.2, 1.0] and data["damping"] == 0.02
    assert {r["building_a"] for r in data["tables"]["slide_ratios"]} == {"isolated@T=2"}
    code, out, _ = invoke(
        monkeypatch, capsys, "table", study.path, "--format", "json", "-o", tmp_path / "t.json"
    )
    assert code == 0 and out.strip() == str(tmp_path / "t.json")
    assert json.loads((tmp_path / "t.json").read_text())["tables"]["pfa"]


@pytest.mark.parametrize(
    "args, option",
    [
        (["--compare", "isolated"], "--compare"),
        (["--compare", ":fixed"], "--compare"),
        (["--compare", "tower:fixed"], "--compare"),
        (["--compare", "fixed:fixed"], "--compare"),  # a building with itself
        (["--compare", "isolated:fixed", "--compare", "fixed:tower@T=1"], "--compare"),
        (["--damping", "0.1"], "--damping"),
        (["--periods", "0.1,x"], "--periods"),
        (["--periods", "-1"], "--periods"),
        (["--format", "xlsx"], "--format"),
        (["--format", "csv", "--json"], "--json"),
        (["--table", "nope"], "--table"),
    ],
)
def test_table_usage_errors_name_the_option(monkeypatch, capsys, study, args, option):
    code, out, err = invoke(monkeypatch, capsys, "table", study.path, *args)
    assert code == 2
    assert option in err and "Traceback" not in err
    assert out == ""


def _bad_files(tmp_path):
    junk = tmp_path / "junk.h5"
    junk.write_bytes(b"\x00garbage" * 10)
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = np.arange(3)
    cut = tmp_path / "cut.h5"
    return {
        "missing": (tmp_path / "missing.h5", "no such result file"),
        "corrupt": (junk, "corrupt or unreadable"),
        "foreign": (other, "not a floorslide result file"),
        "truncated": (cut, "corrupt or unreadable"),
    }


@pytest.mark.parametrize("command", ["table", "plot"])
@pytest.mark.parametrize("case", ["missing", "corrupt", "foreign", "truncated"])
def test_bad_result_files_give_one_line(monkeypatch, capsys, study, tmp_path, command, case):
    files = _bad_files(tmp_path)
    data = study.path.read_bytes()
    files["truncated"][0].write_bytes(data[: len(data) // 2])
    path, text = files[case]
    code, out, err = invoke(monkeypatch, capsys, command, path, "-o", tmp_path / "o")
    assert code == 2  # a bad result file is a bad argument (docs/design.md §3)
    assert err.count("\n") == 1 and err.startswith("floorslide: error: ") and text in err
    assert str(path) in err and out == ""


def test_plot_writes_named_pngs(monkeypatch, capsys, study, tmp_path):
    code, out, err = invoke(monkeypatch, capsys, "plot", study.path, "-o", tmp_path / "fig")
    assert code == 0, err
    names = [p.rsplit("/", 1)[1] for p in out.split()]
    assert names == [
        "frs_pulse-like.png",
        "slide_vs_mu_pulse-like.png",
        "slide_ratio_pulse-like_isolated-over-fixed.png",
        "pfa_profile_pulse-like.png",
        "slide_ecdf_pulse-like.png",
        "histories_broad-band.png",
        "frs_broad-band.png",
        "slide_vs_mu_broad-band.png",
        "slide_ratio_broad-band_isolated-over-fixed.png",
        "pfa_profile_broad-band.png",
        "slide_ecdf_broad-band.png",
    ]
    for name in names:
        data = (tmp_path / "fig" / name).read_bytes()
        assert data.startswith(PNG) and len(data) > 10_000
    assert sorted(p.name for p in (tmp_path / "fig").iterdir()) == sorted(names)


def test_plot_default_folder_json_and_compare(monkeypatch, capsys, study, tmp_path):
    local = tmp_path / "run.h5"
    local.write_bytes(study.path.read_bytes())
    code, out, err = invoke(
        monkeypatch, capsys, "plot", local, "--json", "--compare", "isolated@T=2.5:isolated@T=2"
    )
    assert code == 0, err
    paths = json.loads(out)
    assert all(p.startswith(str(tmp_path / "run-figures")) for p in paths)
    assert any(
        p.endswith("slide_ratio_broad-band_isolated_T_2.5-over-isolated_T_2.png") for p in paths
    )
    code, _, err = invoke(monkeypatch, capsys, "plot", local, "--compare", "a:b:c")
    assert code == 2 and "--compare" in err


def test_no_traceback_from_the_console_script(tmp_path):
    out = subprocess.run(
        [sys.executable, "-m", "floorslide.cli", "table", str(tmp_path / "nope.h5")],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 2
    assert out.stderr.strip() == f"floorslide: error: {tmp_path / 'nope.h5'}: no such result file"


@pytest.mark.slow
def test_figures_are_reproducible_bit_for_bit(study, tmp_path):
    from floorslide.report import plot_figures

    first = plot_figures(study.path, tmp_path / "a")
    second = plot_figures(study.path, tmp_path / "b")
    assert [p.name for p in first] == [p.name for p in second]
    for p, q in zip(first, second, strict=True):
        assert p.read_bytes() == q.read_bytes()


# --- issue 12 --------------------------------------------------------------------------------


@pytest.mark.parametrize("command", ["table", "plot"])
def test_incomplete_file_exits_4_with_one_line(
    monkeypatch, capsys, partial_study, tmp_path, command
):
    """Item 6: a run interrupted at 14 of 18 tasks is refused (exit 4) with one line saying how
    many tasks of how many are done and how to proceed; nothing is written."""
    code, out, err = invoke(monkeypatch, capsys, command, partial_study.path, "-o", tmp_path / "o")
    assert code == 4 and out == "" and err.count("\n") == 1
    assert err.startswith(f"floorslide: error: {partial_study.path}: INCOMPLETE: 14 of 18 tasks")
    assert "--resume" in err and "--allow-incomplete" in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()


def test_table_allow_incomplete_labels_every_format(monkeypatch, capsys, partial_study, tmp_path):
    path = partial_study.path
    code, out, err = invoke(monkeypatch, capsys, "table", path, "--allow-incomplete")
    assert code == 0 and "INCOMPLETE: 14 of 18 tasks done" in err and err.count("\n") == 1
    assert out.splitlines()[0].endswith("— INCOMPLETE") and "**INCOMPLETE: 14 of 18" in out
    code, out, _ = invoke(
        monkeypatch, capsys, "table", path, "--allow-incomplete", "--format", "csv", "-o", tmp_path
    )
    assert code == 0
    for name in TABLE_NAMES:
        text = (tmp_path / f"{name}.csv").read_text()
        assert text.startswith("# INCOMPLETE: 14 of 18 tasks done"), name
    code, out, _ = invoke(monkeypatch, capsys, "table", path, "--allow-incomplete", "--json")
    data = json.loads(out)
    assert code == 0 and data["complete"] is False and data["tasks_done"] == 14


def test_plot_allow_incomplete_labels_the_figures(monkeypatch, capsys, partial_study, tmp_path):
    from floorslide.report.plots import figure_slide_vs_mu
    from floorslide.report.study import load_study

    code, out, err = invoke(
        monkeypatch, capsys, "plot", partial_study.path, "--allow-incomplete", "-o", tmp_path
    )
    assert code == 0 and out.split() and "INCOMPLETE" in err
    study = load_study(partial_study.path)
    tables = design_tables(study, allow_incomplete=True)
    fig = figure_slide_vs_mu(study, tables, "broad-band")
    title = fig._suptitle
    assert (
        title.get_text().startswith("INCOMPLETE: 14 of 18 tasks done")
        and title.get_color() == "red"
    )


def test_plot_compare_fixed_over_isolated_draws(monkeypatch, capsys, study, tmp_path):
    """Item 6: --compare fixed:isolated used to write nothing and exit 0; its ratio is drawn
    versus the isolation period of B."""
    from floorslide.report.plots import figure_slide_ratio
    from floorslide.report.study import load_study

    code, out, err = invoke(
        monkeypatch, capsys, "plot", study.path, "--compare", "fixed:isolated", "-o", tmp_path
    )
    assert code == 0, err
    names = [p.rsplit("/", 1)[1] for p in out.split()]
    assert "slide_ratio_broad-band_fixed-over-isolated.png" in names
    assert "slide_ratio_pulse-like_fixed-over-isolated.png" in names
    s = load_study(study.path)
    fig = figure_slide_ratio(
        s, design_tables(s, compare=["fixed:isolated"]), "broad-band", "fixed:isolated"
    )
    ax = fig.axes[0]
    assert ax.get_xlabel() == "isolation period T_i of isolated (s)"
    xs = sorted({float(x) for line in ax.get_lines() for x in line.get_xdata()})
    assert {2.0, 2.5} <= set(xs)
    # two fixed-base buildings: one position per pair
    fig = figure_slide_ratio(
        s, design_tables(s, compare=["isolated@T=2:isolated@T=2.5"]), "broad-band",
        "isolated@T=2:isolated@T=2.5",
    )  # fmt: skip
    assert fig is not None


def test_plot_compare_that_draws_nothing_is_an_error(monkeypatch, capsys, study, tmp_path):
    code, out, err = invoke(
        monkeypatch, capsys, "plot", study.path, "--compare", "fixed:fixed", "-o", tmp_path
    )
    # a building compared with itself is refused before anything is drawn
    assert code == 2 and "--compare" in err and out == ""
    assert "'fixed:fixed' compares building 'fixed' with itself" in err


def test_help_and_readme_state_the_exit_codes(monkeypatch, capsys):
    """Item 6: a missing or foreign result file is bad usage (2) in code, --help and the docs
    (the result file's page, where the README's reference moved); an incomplete one is 4."""
    from tests.conftest import ROOT

    for command in ("table", "plot"):
        code, out, _ = invoke(monkeypatch, capsys, command, "--help")
        flat = " ".join(out.split())
        assert code == 0 and "--allow-incomplete" in flat
        assert "2 bad usage, or OUT.h5 missing, corrupt or not a floorslide result file" in flat
        assert "4 OUT.h5 is incomplete" in flat
        assert "a task in it fails its integrity check" in flat  # issue 19 item 4
    page = ROOT / "docs" / "site" / "guide" / "result-file.md"
    readme = " ".join(page.read_text(encoding="utf-8").split())
    assert "(exit code 1); a malformed" not in readme
    assert "or one with a task that fails its integrity check (each such task named;" in readme
    assert "is one line naming the file (exit code 2)" in readme
    assert "exit code 4" in readme


def test_demo_summary_never_shows_rocking_as_zero(study):
    """Item 4: the demo summary follows the tables' rule."""
    from floorslide.cli import demo_summary

    text = demo_summary(design_tables(study.path))
    fixed = [ln for ln in text.splitlines() if ln.startswith("| fixed |")]
    assert fixed[0].split(" | ")[2] == "rocks (3/3)"  # pulse-like, mu 0.05: every record rocks
    bb = fixed[1].split(" | ")
    assert bb[3].endswith("(1 rock)")  # broad-band, mu 0.1: one of three rocks
    assert "never count as 0" in text and "caution: 3 < 8 records" in text
