"""``floorslide inspect``: every bundled record, directories, catalogs, options, output."""

from __future__ import annotations

import json
from glob import glob
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from obspy import Stream, Trace

import floorslide as fs
from floorslide.cli import cli
from floorslide.records.measures import MEASURE_KEYS
from tests.conftest import ROOT, SLAMMER
from tests.records.conftest import ELC_FILE, FIXTURES

RECORDS = ROOT / "data" / "records"
KEYS = {"record", "format", "component", "station", "event", *MEASURE_KEYS}


def run(*args: str):
    result = CliRunner().invoke(cli, ["inspect", *args])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    return result


@pytest.fixture(scope="module")
def all_bundled():
    result = run("--json", str(RECORDS))
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)


def test_inspect_reads_every_bundled_record(all_bundled):
    assert len(all_bundled) == 36
    assert {Path(row["record"]).name for row in all_bundled} == {
        p.name for p in SLAMMER.glob("*.txt")
    }
    for row in all_bundled:
        assert set(row) == KEYS
        assert row["format"] == "FSTEXT"
        assert row["pga"] == pytest.approx(row["pga_g"] * 9.80665, rel=1e-15)
        assert 0 < row["d5_75"] < row["d5_95"] <= row["duration"]


def test_inspect_values_are_those_of_the_api(all_bundled):
    row = next(r for r in all_bundled if r["record"].endswith(ELC_FILE))
    trace = fs.read_record(SLAMMER / ELC_FILE)[0]
    assert {k: row[k] for k in MEASURE_KEYS} == {k: fs.measures(trace)[k] for k in MEASURE_KEYS}
    assert row["station"] == "El Centro Array #9" and row["event"] == "Imperial Valley 1940"


def test_shell_glob_and_explicit_files_read_each_record_once(all_bundled):
    """``floorslide inspect data/records/*`` and ``data/records/slammer/*``: the catalog, the
    files it lists (not read twice) and PROVENANCE.md (skipped)."""
    for pattern in ("data/records/*", "data/records/slammer/*"):
        paths = sorted(glob(str(ROOT / pattern)))
        result = run("--json", *paths)
        assert result.exit_code == 0, result.stderr
        rows = json.loads(result.stdout)
        assert len(rows) == 36
        assert sorted(r["pga"] for r in rows) == sorted(r["pga"] for r in all_bundled)
    # a file given both alone and through its catalog is read once, through the catalog
    result = run("--json", str(SLAMMER / ELC_FILE), str(SLAMMER / "index.csv"))
    assert len(json.loads(result.stdout)) == 36


def test_table_output():
    result = run(str(SLAMMER / "index.csv"))
    lines = result.stdout.splitlines()
    assert lines[0].split()[:4] == ["record", "format", "dt(s)", "npts"]
    assert "pga(g)" in lines[0] and "d5-95(s)" in lines[0]
    assert len(lines) == 1 + 36
    elc = next(line for line in lines if ELC_FILE in line)
    assert "0.3129" in elc and "3949" in elc
    assert result.stderr == ""  # no progress bar when stderr is not a terminal


def test_formats_and_options(tmp_path):
    result = run("--json", str(FIXTURES))
    assert result.exit_code == 0, result.stderr
    rows = {Path(r["record"]).name: r for r in json.loads(result.stdout)}
    assert {r["format"] for r in rows.values()} == {"AT2", "COSMOSV2", "KNET"}
    assert rows["ELC180_ngawest2.AT2"]["station"] == "El Centro Array #9"
    assert rows["ELC180_ngawest2.AT2"]["component"] == "180"
    pgas = [r["pga_g"] for r in rows.values()]
    assert max(pgas) - min(pgas) < 1e-5

    bare = tmp_path / "bare.txt"
    bare.write_text("\n".join(str(v) for v in np.sin(np.arange(100) / 5)))
    result = run("--json", "--dt", "0.02", "--units", "gal", str(bare))
    row = json.loads(result.stdout)[0]
    assert row["dt"] == 0.02 and row["pga"] == pytest.approx(
        0.01 * np.abs(np.sin(np.arange(100) / 5)).max()
    )


def test_multi_trace_file_gives_a_row_per_component(tmp_path):
    path = tmp_path / "three.mseed"
    st = Stream()
    for k, channel in enumerate(("HNE", "HNN", "HNZ"), start=1):
        tr = Trace(np.sin(np.arange(200) / 7) * k)
        tr.stats.delta, tr.stats.station, tr.stats.channel = 0.01, "ABC", channel
        st.append(tr)
    st.write(str(path), format="MSEED", encoding="FLOAT64")
    rows = json.loads(run("--json", "--units", "m/s**2", str(path)).stdout)
    assert [r["component"] for r in rows] == ["HNE", "HNN", "HNZ"]
    assert [r["station"] for r in rows] == ["ABC"] * 3
    table = run("--units", "m/s**2", str(path)).stdout
    assert f"{path} [HNZ]" in table
    rows = json.loads(run("--json", "--units", "m/s**2", "--component", "Z", str(path)).stdout)
    assert [r["component"] for r in rows] == ["HNZ"]


def test_nan_durations_are_null_in_json(tmp_path):
    zeros = tmp_path / "zeros.txt"
    zeros.write_text("# dt: 0.01\n# units: g\n" + "0\n" * 10)
    row = json.loads(run("--json", str(zeros)).stdout)[0]
    assert row["d5_95"] is None and row["pga"] == 0.0
    assert "-" in run(str(zeros)).stdout.splitlines()[1]


def test_help():
    result = CliRunner().invoke(cli, ["inspect", "--help"])
    assert result.exit_code == 0
    for option in ("--json", "--format", "--units", "--dt", "--component"):
        assert option in result.stdout
