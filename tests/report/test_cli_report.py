"""floorslide table and floorslide plot (DESIGN §3): outputs, exit codes, one-line errors."""

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
    assert code == 0 and out.startswith("# table: pfa\n") and "# table: slides" not in out
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
    assert code == 2  # a bad result file is a bad argument (DESIGN §3)
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
        "histories_broad-band.png",
        "frs_broad-band.png",
        "slide_vs_mu_broad-band.png",
        "slide_ratio_broad-band_isolated-over-fixed.png",
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


def test_figures_are_reproducible_bit_for_bit(study, tmp_path):
    from floorslide.report import plot_figures

    first = plot_figures(study.path, tmp_path / "a")
    second = plot_figures(study.path, tmp_path / "b")
    assert [p.name for p in first] == [p.name for p in second]
    for p, q in zip(first, second, strict=True):
        assert p.read_bytes() == q.read_bytes()
