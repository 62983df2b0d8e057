"""Bad input gets a clear answer, and nothing is lost (docs/design.md §9, issue 2).

Each case: ``read_record`` raises a RecordError (UnitsError for units) whose one-line message
names the file and the problem; ``floorslide inspect`` on the bad file and a good catalog prints
that line on stderr without a traceback, still reports the good record, and exits with 3.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from obspy import Stream, Trace

import floorslide as fs
from floorslide.cli import cli
from floorslide.errors import RecordError, UnitsError
from tests.conftest import ROOT, SLAMMER
from tests.records.conftest import ELC_FILE, FIXTURES

AT2 = FIXTURES / "ELC180_ngawest2.AT2"
COSMOS = FIXTURES / "ELC180.V2"


def _at2_lines() -> list[str]:
    return AT2.read_text().splitlines()


def _write(path: Path, lines: list[str]) -> Path:
    path.write_text("\n".join(lines) + "\n")
    return path


def _at2_with(tmp: Path, name: str, line4: str | None = None, **changes: str) -> Path:
    lines = _at2_lines()
    if line4 is not None:
        lines[3] = line4
    for index, text in changes.items():
        lines[int(index[1:])] = text
    return _write(tmp / name, lines)


def _mseed(tmp: Path, name: str, data: np.ndarray, channels=("HNN",)) -> Path:
    st = Stream()
    for ch in channels:
        tr = Trace(np.asarray(data, dtype=np.float64))
        tr.stats.delta, tr.stats.station, tr.stats.channel = 0.01, "ELC", ch
        st.append(tr)
    path = tmp / name
    st.write(str(path), format="MSEED", encoding="FLOAT64")
    return path


def _cosmos_with(tmp: Path, name: str, old: str, new: str) -> Path:
    text = COSMOS.read_text()
    assert old in text
    path = tmp / name
    path.write_text(text.replace(old, new, 1))
    return path


def _case(name: str, tmp: Path):
    """(path, read_record keywords, expected exception type, regex of the message)."""
    t = tmp
    lines = _at2_lines()
    if name == "empty file":
        (t / "empty.AT2").write_text("")
        return t / "empty.AT2", {}, RecordError, "empty file"
    if name == "blank file":
        (t / "blank.txt").write_text("\n  \n\t\n")
        return t / "blank.txt", {"format": "text"}, RecordError, "empty file"
    if name == "truncated AT2":
        return (
            _write(t / "trunc.AT2", lines[:-3]),
            {},
            RecordError,
            r"truncated: the header says NPTS=3949 but the file holds only 3935 values",
        )
    if name == "more values than NPTS":
        return (
            _at2_with(t, "long.AT2", "NPTS=  3900, DT=   .0100 SEC,"),
            {},
            RecordError,
            r"NPTS=3900 but the file holds 3949 values; header and data disagree",
        )
    if name == "NPTS missing":
        return (
            _at2_with(t, "nonpts.AT2", "DT=   .0100 SEC,"),
            {"format": "AT2"},
            RecordError,
            r"gives no NPTS",
        )
    if name == "DT missing":
        return _at2_with(t, "nodt.AT2", "NPTS=  3949,"), {}, RecordError, r"gives no DT"
    if name == "no NPTS/DT line":
        return (
            _write(t / "nohdr.AT2", lines[:3] + lines[4:]),
            {"format": "AT2"},
            RecordError,
            r"no NPTS/DT line",
        )
    if name == "NPTS not a number":
        return (
            _at2_with(t, "nptsx.AT2", "NPTS=  39x9, DT=   .0100 SEC,"),
            {},
            RecordError,
            r"NPTS '39x9' is not a number",
        )
    if name == "non-numeric token":
        bad = lines[:]
        bad[9] = "".join(v.rjust(15) for v in ("-.1E-02", ".2E-02", ".61x2620E-02", "0", "0"))
        return (
            _write(t / "token.AT2", bad),
            {},
            RecordError,
            r"line 10, column 34: '.61x2620E-02' is not a number",
        )
    if name == "non-numeric token in text":
        (t / "token.txt").write_text("# dt: 0.01\n# units: g\n0.1\n0.2\n 0.3q\n")
        return t / "token.txt", {}, RecordError, r"line 5, column 2: '0.3q' is not a number"
    if name == "NaN sample":
        bad = lines[:]
        bad[6] = bad[6][:15] + "NaN".rjust(15) + bad[6][30:]
        return (
            _write(t / "nan.AT2", bad),
            {},
            RecordError,
            r"line 7, column 28 \(sample 12\): NaN value",
        )
    if name == "infinite sample in text":
        (t / "inf.txt").write_text("# dt: 0.01\n# units: g\n0.1\n-inf\n")
        return t / "inf.txt", {}, RecordError, r"line 4: infinite value in column 1"
    if name == "NaN sample in MiniSEED":
        data = np.zeros(100)
        data[41] = np.nan
        return (
            _mseed(t, "nan.mseed", data),
            {"units": "g"},
            RecordError,
            r"sample 42: NaN value",
        )
    if name == "dt zero":
        return _at2_with(t, "dt0.AT2", "NPTS=  3949, DT=   .0000 SEC,"), {}, RecordError, "> 0"
    if name == "dt negative in text header":
        (t / "dtneg.txt").write_text("# dt: -0.01\n# units: g\n0.1\n0.2\n")
        return t / "dtneg.txt", {}, RecordError, r"header dt: -0.01 must be > 0"
    if name == "dt given negative":
        return (
            SLAMMER / ELC_FILE,
            {"dt": -0.01, "units": "g"},
            RecordError,
            r"dt = -0.01: the time step must be > 0",
        )
    if name == "COSMOS sample interval zero":
        return (
            _cosmos_with(
                t, "dt0.V2", "      10.000000      39.490000", "       0.000000      39.490000"
            ),
            {},
            RecordError,
            r"sample interval 0.0 ms: the time step must be > 0",
        )
    if name == "COSMOS length inconsistent":
        return (
            _cosmos_with(
                t, "len.V2", "      10.000000      39.490000", "      10.000000      19.490000"
            ),
            {},
            RecordError,
            r"record length 19.49 s \(real header 63\) disagrees with 3949 samples",
        )
    if name == "COSMOS truncated":
        text = COSMOS.read_text().splitlines()
        end = text.index("End-of-data for Chan  1 acceleration")
        return (
            _write(t / "trunc.V2", text[: end - 20]),
            {},
            RecordError,
            r"truncated: line \d+ announces 3949 acceleration values but only 3929 follow",
        )
    if name == "COSMOS raw counts":
        return (
            _cosmos_with(
                t, "v0.V2", "       2       1       4     120", "       0       1      50     120"
            ),
            {},
            RecordError,
            r"raw counts \(COSMOS V0\)",
        )
    if name == "unknown units given":
        return AT2, {"units": "furlongs"}, UnitsError, r"unknown units 'furlongs'"
    if name == "unknown units in AT2 header":
        return (
            _at2_with(t, "fur.AT2", None, l2="ACCELERATION TIME SERIES IN UNITS OF FURLONGS"),
            {},
            UnitsError,
            r"unknown units 'FURLONGS'",
        )
    if name == "unknown units in text header":
        (t / "units.txt").write_text("# dt: 0.01\n# units: parsecs\n0.1\n0.2\n")
        return t / "units.txt", {}, UnitsError, r"header units: unknown units 'parsecs'"
    if name == "units contradict the file":
        return AT2, {"units": "gal"}, UnitsError, r"units 'gal' were given but the file says 'g'"
    if name == "binary garbage":
        rng = np.random.default_rng(0)
        (t / "garbage.bin").write_bytes(rng.integers(0, 256, 4096, dtype=np.uint8).tobytes())
        return t / "garbage.bin", {}, RecordError, r"not a record in any format"
    if name == "binary garbage named .AT2":
        rng = np.random.default_rng(1)
        (t / "garbage2.AT2").write_bytes(rng.integers(0, 256, 4096, dtype=np.uint8).tobytes())
        return t / "garbage2.AT2", {}, RecordError, r"binary data, not a text record"
    if name == "directory":
        (t / "folder").mkdir()
        return t / "folder", {}, RecordError, r"is a directory"
    if name == "missing file":
        return t / "missing.AT2", {}, RecordError, r"no such file"
    if name == "component not in a multi-trace file":
        return (
            _mseed(t, "three.mseed", np.ones(50), ("HNE", "HNN", "HNZ")),
            {"units": "g", "component": "X"},
            RecordError,
            r"no component 'X' in this file; it holds HNE, HNN, HNZ",
        )
    if name == "text with three columns":
        (t / "three.txt").write_text("0 1 2\n0 1 2\n")
        return t / "three.txt", {"format": "text"}, RecordError, r"line 1: 3 columns"
    if name == "text with a ragged row":
        (t / "ragged.txt").write_text("# units: g\n0.00 1\n0.01 2\n0.02\n")
        return t / "ragged.txt", {}, RecordError, r"line 4: 1 columns where the data above have 2"
    if name == "non-uniform time column":
        (t / "jitter.txt").write_text("# units: g\n0.00 1\n0.01 2\n0.025 3\n0.03 4\n")
        return t / "jitter.txt", {}, RecordError, r"line 4: time 0.025 s is .* off the uniform grid"
    if name == "text npts inconsistent":
        (t / "npts.txt").write_text("# dt: 0.01\n# units: g\n# npts: 5\n0.1\n0.2\n")
        said = r"truncated: the header says npts=5 but the file holds only 2 values"
        return t / "npts.txt", {}, RecordError, said
    if name == "unknown format":
        return AT2, {"format": "XYZ"}, RecordError, r"unknown format 'XYZ'"
    raise AssertionError(name)


CASES = [
    "empty file",
    "blank file",
    "truncated AT2",
    "more values than NPTS",
    "NPTS missing",
    "DT missing",
    "no NPTS/DT line",
    "NPTS not a number",
    "non-numeric token",
    "non-numeric token in text",
    "NaN sample",
    "infinite sample in text",
    "NaN sample in MiniSEED",
    "dt zero",
    "dt negative in text header",
    "dt given negative",
    "COSMOS sample interval zero",
    "COSMOS length inconsistent",
    "COSMOS truncated",
    "COSMOS raw counts",
    "unknown units given",
    "unknown units in AT2 header",
    "unknown units in text header",
    "units contradict the file",
    "binary garbage",
    "binary garbage named .AT2",
    "directory",
    "missing file",
    "component not in a multi-trace file",
    "text with three columns",
    "text with a ragged row",
    "non-uniform time column",
    "text npts inconsistent",
    "unknown format",
]


@pytest.mark.parametrize("name", CASES)
def test_read_record_gives_one_clear_line(tmp_path, name):
    path, kwargs, error, pattern = _case(name, tmp_path)
    with pytest.raises(error) as info:
        fs.read_record(path, **kwargs)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: ") or name == "unknown format"
    assert info.value.where == str(path) or name == "unknown format"
    assert info.value.exit_code == 3
    assert _search(pattern, message), message


def _search(pattern: str, text: str) -> bool:
    import re

    return re.search(pattern, text) is not None


@pytest.fixture
def good_catalog(tmp_path) -> Path:
    """A one-row catalog of a real record (catalog rows ignore the command-line options)."""
    folder = tmp_path / "good"
    folder.mkdir()
    shutil.copy(SLAMMER / ELC_FILE, folder / ELC_FILE)
    (folder / "index.csv").write_text(f"file,dt,units,station\n{ELC_FILE},0.01,g,El Centro\n")
    return folder / "index.csv"


_FLAGS = {"format": "--format", "units": "--units", "dt": "--dt", "component": "--component"}


BAD_OPTION = {
    "dt given negative": ("--dt", "must be > 0 s, got -0.01"),
    "unknown units given": ("--units", "unknown units 'furlongs'"),
    "unknown format": ("--format", "unknown format 'XYZ'"),
}
"""Cases where the fault is the option's value, not the file: bad usage (exit 2), naming the
option, before any record is read."""


@pytest.mark.parametrize("name", [c for c in CASES if c not in BAD_OPTION])
def test_inspect_reports_the_bad_file_and_keeps_going(tmp_path, good_catalog, name):
    path, kwargs, _, pattern = _case(name, tmp_path)
    args = ["inspect", "--json"]
    for key, value in kwargs.items():
        args += [_FLAGS[key], str(value)]
    result = CliRunner().invoke(cli, [*args, str(path), str(good_catalog)])
    assert result.exit_code == 3, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert "Traceback" not in result.stderr
    errors = result.stderr.strip().splitlines()
    assert len(errors) == 1 and errors[0].startswith(f"floorslide: error: {path}: ")
    pattern = {"directory": "no records found in this directory"}.get(name, pattern)
    assert _search(pattern, errors[0]), errors[0]
    rows = json.loads(result.stdout)
    assert [row["station"] for row in rows] == ["El Centro"]


@pytest.mark.parametrize("name", list(BAD_OPTION))
def test_inspect_bad_option_value_is_bad_usage(tmp_path, good_catalog, name):
    path, kwargs, _, _ = _case(name, tmp_path)
    args = ["inspect", "--json"]
    for key, value in kwargs.items():
        args += [_FLAGS[key], str(value)]
    result = CliRunner().invoke(cli, [*args, str(path), str(good_catalog)])
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.stderr and result.stdout == ""
    errors = [line for line in result.stderr.splitlines() if line.startswith("Error:")]
    option, text = BAD_OPTION[name]
    assert len(errors) == 1 and option in errors[0] and text in errors[0]


def test_inspect_directory_without_records(tmp_path, good_catalog):
    empty = tmp_path / "docs"
    empty.mkdir()
    (empty / "README.md").write_text("# nothing here\n")
    result = CliRunner().invoke(cli, ["inspect", str(empty), str(good_catalog)])
    assert result.exit_code == 3
    assert (
        result.stderr.strip() == f"floorslide: error: {empty}: no records found in this directory"
    )
    assert "El Centro" not in result.stdout  # the table shows paths
    assert ELC_FILE in result.stdout


def test_inspect_missing_argument_path(tmp_path, good_catalog):
    result = CliRunner().invoke(cli, ["inspect", str(tmp_path / "nope"), str(good_catalog)])
    assert result.exit_code == 3
    assert "no such file or directory" in result.stderr


def test_console_script_exit_code_and_no_traceback(tmp_path, good_catalog):
    """The installed entry point (floorslide.cli:entry, which runs main), in a subprocess."""
    (tmp_path / "empty.AT2").write_text("")
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            "from floorslide.cli import entry; entry()",
            "inspect",
            "--json",
            str(tmp_path / "empty.AT2"),
            str(good_catalog),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 3
    assert proc.stderr.strip() == f"floorslide: error: {tmp_path / 'empty.AT2'}: empty file"
    assert len(json.loads(proc.stdout)) == 1


# ------------------------------------------------- the peak a header states, checked


def test_samples_that_disagree_with_the_stated_peak_are_refused(tmp_path):
    """A header stating the peak (COSMOS 'Max = … at … sec', K-NET 'Max. Acc. (gal)') is
    checked against the samples: a damaged sample (a new spike) or scale factor would read
    silently as another record."""
    v2 = (FIXTURES / "ELC180.V2").read_text()
    assert fs.read_record(FIXTURES / "ELC180.V2")[0].stats.stated_peak.time == 2.15
    lines = v2.splitlines()
    first = next(i for i, s in enumerate(lines) if "acceleration pts" in s) + 1
    lines[first + 1000] = f"{999.0:15.6e}"  # a damaged sample at 10 s: 999 gal
    path = tmp_path / "spike.V2"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    message = str(info.value)
    assert message.startswith(f"{path}: the header states the peak acceleration ('Max = ")
    assert "Max = -306.831 cm/sec2 at 2.150 sec', 3.06831 m/s²)" in message
    assert "but the samples peak at 9.99 m/s² at 10 s (dt = 0.01 s)" in message
    knet = (FIXTURES / "ELC180.knet").read_text()
    fs.read_record(FIXTURES / "ELC180.knet", format="KNET")  # the fixture's header agrees
    # K-NET states the peak of the record less its mean: a real raw record (offset 2.4 gal)
    raw = fs.read_record(ROOT / "tests" / "data" / "raw" / "AOM0081801241951.NS")[0].data
    assert abs(raw).max() > 1.06 * 0.36185
    path = tmp_path / "scale.knet"
    path.write_text(knet.replace("3920(gal)/6182761", "39200(gal)/6182761"))
    said = (
        r"'Max. Acc. \(gal\) 306.831', 3.06831 m/s²\) but the samples less their mean peak at 30.68"
    )
    with pytest.raises(RecordError, match=said):
        fs.read_record(path, format="KNET")
