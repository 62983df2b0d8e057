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
KEYS = {
    "record",
    "format",
    "component",
    "station",
    "event",
    *MEASURE_KEYS,
    "notes",
    "processing",
    "qa",
}


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
    # the 36 SLAMMER components and the 10 PEER pairs' 20 components (data/records/pairs)
    assert len(all_bundled) == 56
    slammer = [row for row in all_bundled if Path(row["record"]).parent.name == "slammer"]
    pairs = [row for row in all_bundled if Path(row["record"]).parent.name == "pairs"]
    assert len(pairs) == 20 and {row["format"] for row in pairs} == {"AT2"}
    assert {Path(row["record"]).name for row in slammer} == {p.name for p in SLAMMER.glob("*.txt")}
    for row in slammer:
        assert set(row) == KEYS
        assert row["format"] == "text"  # the name --format takes, not the plugin FSTEXT
        assert row["pga"] == pytest.approx(row["pga_g"] * 9.80665, rel=1e-15)
        assert 0 < row["d5_75"] < row["d5_95"] <= row["duration"]
        assert row["processing"] == []  # nothing applied unless asked
        assert row["qa"]["flags"] == []  # the bundled records are processed: no flags
        assert set(row["qa"]["checks"]) >= {"offset", "trend", "clipping", "truncated"}


def test_inspect_values_are_those_of_the_api(all_bundled):
    row = next(r for r in all_bundled if r["record"].endswith(ELC_FILE))
    trace = fs.read_record(SLAMMER / ELC_FILE)[0]
    assert {k: row[k] for k in MEASURE_KEYS} == {k: fs.measures(trace)[k] for k in MEASURE_KEYS}
    assert row["station"] == "El Centro Array #9" and row["event"] == "Imperial Valley 1940"


def test_shell_glob_and_explicit_files_read_each_record_once(all_bundled):
    """``floorslide inspect data/records/*`` and ``data/records/slammer/*``: the catalog, the
    files it lists (not read twice) and PROVENANCE.md (skipped)."""
    for pattern, n in (("data/records/*", 56), ("data/records/slammer/*", 36)):
        paths = sorted(glob(str(ROOT / pattern)))
        result = run("--json", *paths)
        assert result.exit_code == 0, result.stderr
        rows = json.loads(result.stdout)
        assert len(rows) == n
        expect = [r["pga"] for r in all_bundled if n == 56 or "/slammer/" in r["record"]]
        assert sorted(r["pga"] for r in rows) == sorted(expect)
    # a file given both alone and through its catalog is read once, through the catalog
    result = run("--json", str(SLAMMER / ELC_FILE), str(SLAMMER / "index.csv"))
    assert len(json.loads(result.stdout)) == 36


def test_table_output():
    result = run(str(SLAMMER / "index.csv"))
    lines = result.stdout.splitlines()
    assert lines[0].split()[:4] == ["record", "format", "dt(s)", "npts"]
    assert "pga(g)" in lines[0] and "d5-95(s)" in lines[0]
    assert len(lines) == 1 + 36 + 1
    assert lines[-1] == "quality: no flags on the 36 records"
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
    assert row["notes"] == ["d5_75, d5_95: undefined, the Arias intensity is 0 (a record of zeros)"]
    assert "-" in run(str(zeros)).stdout.splitlines()[1]


def _not_json(constant: str):
    raise AssertionError(f"{constant} is not JSON")


def test_json_is_strict_when_measures_overflow(tmp_path):
    """Samples of 1e200 g printed ``"cav": Infinity``, which is not JSON, and durations of 0 s
    (issue 19 item 6): the measures beyond floating point are null, with a note saying why."""
    big = tmp_path / "big.txt"
    big.write_text("# dt: 0.01\n# units: g\n1e200\n-1e200\n1e200\n0\n")
    result = run("--json", str(big))
    assert result.exit_code == 0 and result.stderr == ""
    (row,) = json.loads(result.stdout, parse_constant=_not_json)
    assert row["pga_g"] == pytest.approx(1e200) and row["pgv"] > 0
    assert [row[k] for k in ("arias", "cav", "d5_75", "d5_95")] == [None] * 4
    assert row["notes"] == [
        "arias, cav, d5_75, d5_95: undefined, beyond floating point (samples up to 9.81e+200 m/s²)"
    ]
    table = run(str(big)).stdout
    assert f"note: {big}: arias, cav, d5_75, d5_95: undefined" in table


def test_help():
    result = CliRunner().invoke(cli, ["inspect", "--help"])
    assert result.exit_code == 0
    for option in ("--json", "--format", "--units", "--dt", "--component"):
        assert option in result.stdout


# Issue 12 item 7: non-records, catalogs of components, format names, exit codes --------------

PAIR_HEADER = (
    "file_h1,file_h2,rsn,event,date,station,comp_h1,comp_h2,dt,npts_h1,npts_h2,units,"
    "pga_h1_g,pga_h2_g"  # the columns of PEER pair flatfiles (shared/records/pairs/index.csv)
)


def pair_catalog(tmp_path: Path, npts_h2: int = 3949) -> Path:
    """A catalog of components naming two bundled AT2 files of El Centro 1940 NS."""
    h1, h2 = FIXTURES / "ELC180_ngawest2.AT2", FIXTURES / "ELC180_peer2000.AT2"
    row = f"{h1},{h2},6,Imperial Valley-02,5/19/1940,El Centro Array #9,180,180,0.01,3949,"
    path = tmp_path / "index.csv"
    path.write_text(f"{PAIR_HEADER}\n{row}{npts_h2},g,0.3129,0.3129\n")
    return path


def one_error_line(result) -> str:
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    return lines[0]


def test_a_scene_file_is_not_silently_inspected(tmp_path):
    """``floorslide inspect scene.toml`` printed nothing and exited 0."""
    scene = tmp_path / "scene.toml"
    scene.write_text('[scene]\nname = "x"\n')
    result = run(str(scene))
    assert result.exit_code == 3 and result.stdout == ""
    line = one_error_line(result)
    assert str(scene) in line and "not a record" in line and "floorslide run" in line
    # the records named with it are still inspected
    result = run("--json", str(scene), str(SLAMMER / ELC_FILE))
    assert result.exit_code == 3 and len(json.loads(result.stdout)) == 1


@pytest.mark.parametrize("name", ["results.h5", "notes.json"])
def test_other_non_records_named_are_errors(tmp_path, name):
    path = tmp_path / name
    path.write_bytes(b"{}")
    result = run(str(path))
    assert result.exit_code == 3 and str(path) in one_error_line(result)


def test_nothing_but_documentation_is_an_error(tmp_path):
    readme = tmp_path / "README.md"
    readme.write_text("# records\n")
    result = run(str(readme))
    assert result.exit_code == 3 and "no record to read" in one_error_line(result)


def test_catalog_of_components_shows_every_component(tmp_path):
    """A PEER pair flatfile (file_h1, file_h2) got 'line 2: 17 columns'."""
    result = run("--json", str(pair_catalog(tmp_path)))
    assert result.exit_code == 0, result.stderr
    rows = json.loads(result.stdout)
    assert [Path(r["record"]).name for r in rows] == ["ELC180_ngawest2.AT2", "ELC180_peer2000.AT2"]
    ref = fs.measures(fs.read_record(SLAMMER / ELC_FILE)[0])  # the SLAMMER copy of the record
    for row in rows:
        assert row["format"] == "AT2" and row["npts"] == 3949
        assert row["pga_g"] == pytest.approx(ref["pga_g"], rel=1e-4)


def test_catalog_of_components_checks_each_component(tmp_path):
    result = run("--json", str(pair_catalog(tmp_path, npts_h2=4000)))
    assert result.exit_code == 3
    line = one_error_line(result)
    assert "ELC180_peer2000.AT2" in line and "npts=4000" in line
    assert len(json.loads(result.stdout)) == 1  # h1 is still shown


def test_catalog_of_components_elsewhere_says_what_it_is(tmp_path):
    path = pair_catalog(tmp_path)
    with pytest.raises(fs.RecordError, match="catalog of components"):
        fs.read_catalog(path)
    with pytest.raises(fs.RecordError, match="is a record catalog, not a record"):
        fs.read_record(path)


def test_format_column_shows_the_name_users_give():
    result = run(str(SLAMMER / ELC_FILE))
    assert result.exit_code == 0
    assert "FSTEXT" not in result.stdout
    assert result.stdout.splitlines()[1].split()[1] == "text"


@pytest.mark.parametrize(
    ("option", "value", "text"),
    [
        ("--units", "furlongs", "unknown units 'furlongs'"),
        ("--format", "nope", "unknown format 'nope'"),
        ("--dt", "-1", "must be > 0"),
        ("--dt", "0", "must be > 0"),
    ],
)
@pytest.mark.parametrize("command", ["inspect", "slide", "spectrum"])
def test_bad_option_values_are_usage_errors(command, option, value, text):
    """A bad --units/--format/--dt is bad usage (exit 2) naming the option — not an unreadable
    record (exit 3) blamed on the file."""
    extra = ["--mu", "0.1"] if command == "slide" else []
    result = CliRunner().invoke(cli, [command, str(SLAMMER / ELC_FILE), *extra, option, value])
    assert result.exit_code == 2, result.output
    error = [line for line in result.stderr.splitlines() if line.startswith("Error:")]
    assert len(error) == 1 and option in error[0] and text in error[0]


def test_every_json_the_commands_print_is_strict():
    """slide --json and spectrum --json go through the same helper as inspect --json."""
    from floorslide.cli import _strict_json

    data = {"a": [float("inf"), np.float64("nan"), 1.5], "b": (np.float64("-inf"), "x")}
    assert json.loads(_strict_json(data), parse_constant=_not_json) == {
        "a": [None, None, 1.5],
        "b": [None, "x"],
    }
