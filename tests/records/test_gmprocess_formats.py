"""More formats through USGS gmprocess (the optional extra ``floorslide[gmprocess]``).

Without gmprocess (simulated by making its import fail) an unknown file is one line that names
the extra. With gmprocess installed, each file of tests/data/gmprocess (excerpts of gmprocess's
own test data; see PROVENANCE.md there) reads through :func:`floorslide.read_record` and
``floorslide inspect``, and what comes out is checked against the file itself, parsed here in a
few lines per format (dt, npts, units, station, samples, the peak the header states) —
independently of gmprocess.
"""

from __future__ import annotations

import json
import logging
import re
import sys

import numpy as np
import pytest
from click.testing import CliRunner
from obspy import Stream, Trace

import floorslide as fs
from floorslide.cli import cli
from floorslide.errors import RecordError, UnitsError
from floorslide.records import gmprocess_formats
from floorslide.records.read import format_name, resolve_format
from floorslide.records.units import canonical_units
from tests.conftest import ROOT

DATA = ROOT / "tests" / "data" / "gmprocess"
EXTRA = 'pip install "floorslide[gmprocess]"'


@pytest.fixture
def no_gmprocess(monkeypatch):
    """gmprocess made unimportable, whether or not it is installed (and already imported)."""
    for name in [n for n in sys.modules if n == "gmprocess" or n.startswith("gmprocess.")]:
        monkeypatch.setitem(sys.modules, name, None)
    monkeypatch.setitem(sys.modules, "gmprocess", None)
    monkeypatch.setitem(sys.modules, "gmprocess.io.read", None)


# -- without gmprocess: always run ---------------------------------------------------------------


@pytest.mark.parametrize("name", ["0111a.smc", "ACAC1709.191"])
def test_unknown_format_names_the_extra(no_gmprocess, name):
    with pytest.raises(RecordError) as info:
        fs.read_record(DATA / name)
    text = str(info.value)
    assert "\n" not in text
    assert text.startswith(f"{DATA / name}: not a record in any format floorslide or ObsPy knows")
    assert text.endswith(EXTRA)
    assert "DMG/CSMIP" in text and "GeoNet" in text and "CWB" in text and "UNAM" in text


def test_garbage_still_unknown_and_names_the_extra(no_gmprocess, tmp_path):
    path = tmp_path / "garbage.bin"
    path.write_bytes(np.random.default_rng(0).integers(0, 256, 4096, dtype=np.uint8).tobytes())
    with pytest.raises(RecordError, match=r"not a record in any format .*floorslide\[gmprocess\]"):
        fs.read_record(path)


@pytest.mark.parametrize("fmt", ["gmprocess", "GMPROCESS", "gmprocess:dmg"])
def test_format_gmprocess_without_it(no_gmprocess, fmt):
    with pytest.raises(RecordError) as info:
        fs.read_record(DATA / "ce36456p_CE36456.V2", format=fmt)
    text = str(info.value)
    assert "\n" not in text and "needs gmprocess, which is not installed" in text
    assert text.endswith(EXTRA)


def test_cli_inspect_unknown_names_the_extra(no_gmprocess):
    result = CliRunner().invoke(cli, ["inspect", str(DATA / "0111a.smc")])
    assert result.exit_code == 3
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("floorslide: error: ")
    assert lines[0].endswith(EXTRA)


def test_format_names():
    assert resolve_format("gmprocess") == "gmprocess"
    assert resolve_format(" GMPROCESS:DMG ") == "gmprocess:dmg"
    assert format_name("gmprocess:cwb") == "gmprocess:cwb"
    with pytest.raises(RecordError, match=r"gmprocess"):
        resolve_format("dmg")


def _station_trace(units_type: str, units: str, channel: str = "HN1") -> Trace:
    """A trace shaped like a gmprocess StationTrace (its stats.standard / stats.coordinates)."""
    trace = Trace(np.array([1.0, -2.0, 3.0]), header={"delta": 0.01, "station": "ST01"})
    trace.stats.channel = channel
    trace.stats.standard = {
        "units_type": units_type,
        "units": units,
        "source_format": "dmg",
        "station_name": "Somewhere",
        "horizontal_orientation": np.float64(90.0),
        "vertical_orientation": np.nan,
    }
    trace.stats.coordinates = {"latitude": 35.9, "longitude": -120.5, "elevation": 0.0}
    return trace


def test_conversion_keeps_acceleration_only():
    traces = [
        _station_trace("acc", "cm/s^2", "HN1"),
        _station_trace("vel", "cm/s", "HN1"),
        _station_trace("disp", "cm", "HN1"),
        _station_trace("acc", "cm/s/s", "HN2"),
    ]
    out = gmprocess_formats.to_record_stream([Stream(traces)], "f.v2")
    assert [tr.stats.channel for tr in out] == ["HN1", "HN2"]
    meta = out[0].stats.gmprocess
    assert meta["units"] == "cm/s^2" and meta["units_canonical"] == "gal"
    assert meta["horizontal_orientation"] == 90.0 and type(meta["horizontal_orientation"]) is float
    assert meta["vertical_orientation"] is None  # NaN: unknown
    assert meta["latitude"] == 35.9 and meta["station_name"] == "Somewhere"
    assert out[0].stats._format == "gmprocess:dmg" and out[0].stats.units == "cm/s^2"
    assert type(out[0].stats) is not type(traces[0])  # plain ObsPy Traces, not gmprocess's


def test_conversion_refuses_a_file_without_acceleration():
    traces = [_station_trace("vel", "cm/s"), _station_trace("disp", "cm")]
    with pytest.raises(RecordError) as info:
        gmprocess_formats.to_record_stream([Stream(traces)], "f.v2")
    assert str(info.value) == (
        "f.v2: no acceleration in the file: gmprocess reads it as disp, vel only"
    )


def test_conversion_never_guesses_units():
    with pytest.raises(UnitsError, match=r"gmprocess gives units 'acc' for HN1; expected"):
        gmprocess_formats.to_record_stream([Stream([_station_trace("acc", "acc")])], "f.v2")


# -- with gmprocess ------------------------------------------------------------------------------


def _header_value(lines: list[str], key: str) -> str:
    return next(line.split(":", 1)[1].strip() for line in lines if line.startswith(key))


def _unam(path):
    lines = path.read_text().splitlines()
    slashes = lambda key: _header_value(lines, key).strip("/").split("/")  # noqa: E731
    dt = {float(v) for v in slashes("INTERVALO DE MUESTREO, C1-C6 (s)")}
    npts = {int(v) for v in slashes("NUM. TOTAL DE MUESTRAS, C1-C6")}
    assert len(dt) == 1 and len(npts) == 1
    data = np.array([[float(v) for v in line.split()] for line in lines[109:]])
    return {
        "format": "gmprocess:unam",
        "dt": dt.pop(),
        "npts": npts.pop(),
        "units": _header_value(lines, "UNIDADES DE LOS DATOS"),  # Gal (cm/s/s)
        "station": _header_value(lines, "CLAVE DE LA ESTACION"),
        "columns": data.T,  # V, N00E, N90E
    }


def _cwb(path):
    lines = path.read_text().splitlines()
    data = np.array(
        [[float(v) for v in line.split()] for line in lines if line.strip() and line[0] != "#"]
    )
    time, columns = data[:, 0], data[:, 1:].T  # Time U N E
    dt = 1.0 / float(_header_value(lines, "#SampleRate(Hz)"))
    assert np.allclose(np.diff(time), dt)
    return {
        "format": "gmprocess:cwb",
        "dt": dt,
        "npts": len(time),
        "units": _header_value(lines, "#AmplitudeUnit").split(".")[0],  # gal
        "station": _header_value(lines, "#StationCode"),
        "columns": columns,
    }


def _dmg(path):
    lines = path.read_text().splitlines()
    at = next(i for i, line in enumerate(lines) if "POINTS OF ACCEL DATA" in line)
    match = re.match(r"\s*(\d+) POINTS OF ACCEL DATA EQUALLY SPACED AT\s+(\S+) SEC\.", lines[at])
    npts, dt = int(match[1]), float(match[2])
    rows = lines[at + 1 : at + 1 + -(-npts // 8)]
    values = np.array([float(row[k : k + 10]) for row in rows for k in range(0, len(row), 10)])
    peak = re.search(
        r"PEAK ACCELERATION =\s*(\S+)\s+CM/SEC/SEC\s+AT\s+(\S+)\s+SEC", path.read_text()
    )
    return {
        "format": "gmprocess:dmg",
        "dt": dt,
        "npts": npts,
        "units": lines[at].split("UNITS:")[1].strip(" )"),  # CM/SEC/SEC
        "station": re.search(r"STATION NO\. (\d+)", lines[5])[1],
        "columns": values[None, :npts],
        "peak": (float(peak[1]), float(peak[2])),  # the peak of the whole record, in the excerpt
    }


def _smc(path):
    lines = path.read_text().splitlines()
    npts = int(lines[13][:10])  # first field of the third integer-header line
    rate = float(lines[17][15:30])  # second field of the first real-header line, samples/s
    rows = [line for line in lines[35:] if line.strip()]
    values = np.array([float(row[k : k + 10]) for row in rows for k in range(0, 80, 10)])
    return {
        "format": "gmprocess:smc",
        "dt": 1.0 / rate,
        "npts": npts,
        # USGS SMC files do not name their units; corrected accelerograms are in cm/s² (the
        # format's definition, which gmprocess follows)
        "units": "cm/s**2",
        "station": lines[2].strip()[:4],  # SAF0A: station SAF0, the A a record letter
        "columns": values[None, :npts],
    }


FILES = {
    "ACAC1709.191": _unam,
    "1-EAS.dat": _cwb,
    "ce36456p_CE36456.V2": _dmg,
    "0111a.smc": _smc,
}


@pytest.fixture(scope="module")
def gmprocess():
    return pytest.importorskip("gmprocess")


@pytest.mark.parametrize("name", sorted(FILES))
def test_reads_like_the_file_says(gmprocess, name):
    path = DATA / name
    expected = FILES[name](path)
    stream = fs.read_record(path)
    assert len(stream) == len(expected["columns"])
    assert canonical_units(expected["units"].split("(")[-1].strip(" ()")) == "gal"
    for trace, column in zip(stream, expected["columns"], strict=True):
        stats = trace.stats
        assert stats.delta == pytest.approx(expected["dt"], rel=1e-9)
        assert stats.npts == expected["npts"] == len(column)
        assert trace.data.dtype == np.float64
        np.testing.assert_allclose(trace.data, column * 0.01, rtol=1e-12, atol=0)
        assert stats.units == "m/s**2" and stats.original_units == "gal"
        assert stats.processing[-1].endswith("convert_units(from='gal', to='m/s**2', factor=0.01)")
        record = stats.record
        assert record.path == str(path) and record.format == expected["format"]
        assert record.station == expected["station"] == stats.station
        assert record.component == stats.channel and stats.channel[:2] in ("HN", "BN")
        assert record.event == ""  # gmprocess's readers keep no event
        assert stats.gmprocess["units_type"] == "acc"
        assert stats.gmprocess["units"] in ("cm/s^2", "cm/s/s")
        assert stats.gmprocess["source_format"].lower() == expected["format"].split(":")[1]
        assert stats.gmprocess["gmprocess_version"] == gmprocess_formats.gmprocess_version()
        json.dumps(dict(stats.gmprocess))  # plain values only
    if "peak" in expected:
        value, at = expected["peak"]
        index = int(np.argmax(np.abs(stream[0].data)))
        assert stream[0].data[index] == pytest.approx(value * 0.01, rel=1e-12)
        assert index * expected["dt"] == pytest.approx(at)


def test_component_selection_and_forced_format(gmprocess):
    north = fs.read_record(DATA / "1-EAS.dat", component="BN1")
    assert [tr.stats.channel for tr in north] == ["BN1"]
    forced = fs.read_record(DATA / "1-EAS.dat", format="gmprocess")
    assert [tr.stats.record.format for tr in forced] == ["gmprocess:cwb"] * 3
    assert len(fs.read_record(DATA / "1-EAS.dat", format="gmprocess:cwb")) == 3
    with pytest.raises(RecordError, match=r"format 'gmprocess:dmg' was given but gmprocess reads"):
        fs.read_record(DATA / "1-EAS.dat", format="gmprocess:dmg")
    with pytest.raises(UnitsError, match=r"units 'g' were given but the file says 'gal'"):
        fs.read_record(DATA / "1-EAS.dat", units="g")


def test_gmprocess_log_is_kept_not_printed(gmprocess, capsys):
    handlers = list(logging.getLogger().handlers)
    stream = fs.read_record(DATA / "ce36456p_CE36456.V2")
    assert logging.getLogger().handlers == handlers  # no console handler left behind
    assert "WARNING: Setting elevation to 0.0" in stream[0].stats.gmprocess["log"]
    assert capsys.readouterr().err == ""


def test_unknown_to_gmprocess_too(gmprocess, tmp_path):
    path = tmp_path / "garbage.bin"
    path.write_bytes(np.random.default_rng(0).integers(0, 256, 4096, dtype=np.uint8).tobytes())
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    assert "\n" not in str(info.value)
    assert "nor does gmprocess" in str(info.value)


def test_cli_inspect(gmprocess):
    paths = [str(DATA / name) for name in sorted(FILES)]
    result = CliRunner().invoke(cli, ["inspect", "--json", *paths])
    assert result.exit_code == 0, result.stderr
    rows = json.loads(result.stdout)
    assert len(rows) == 3 + 3 + 1 + 1
    assert {row["format"] for row in rows} == {FILES[name](DATA / name)["format"] for name in FILES}
    for row in rows:
        assert row["pga"] > 0 and row["station"]


def test_stated_peak_lines_of_dmg_and_geonet():
    """The header lines gmprocess does not read: a channel's peak acceleration and its time
    (GeoNet's as in its format description's sample header)."""
    geonet = "Acceleration:  Peak  -2080.5 mm/s/s at  23.28 s     RMS   145.6"
    match = gmprocess_formats.STATED_PEAK["geonet"].search(geonet)
    assert match.groups() == ("-2080.5", "mm/s/s", "23.28")
    dmg = "PEAK ACCELERATION =  -267.957    CM/SEC/SEC  AT   10.940   SEC."
    match = gmprocess_formats.STATED_PEAK["dmg"].search(dmg)
    assert match.groups() == ("-267.957", "CM/SEC/SEC", "10.940")


@pytest.mark.parametrize(
    ("old", "new", "says"),
    [
        # the time step in the real header, 0.020 -> 0.200 s: every time and velocity x10
        (
            "65.000      .020      .100",
            "65.000      .200      .100",
            "the header states the peak acceleration at 10.94 s ('PEAK ACCELERATION = -267.957 "
            "CM/SEC/SEC AT 10.940 SEC') but the samples peak at 2.67957 m/s² at 109.4 s "
            "(dt = 0.2 s): a damaged time step",
        ),
        (
            "PEAK ACCELERATION =  -267.957",
            "PEAK ACCELERATION =  -167.957",
            "1.67957 m/s²) but the samples peak at 2.67957 m/s² at 10.94 s",
        ),
    ],
)
def test_damaged_header_against_the_stated_peak(gmprocess, tmp_path, old, new, says):
    """A damaged GeoNet V2A time step (0.0200 -> 0.2000) read with exit 0 and every time off
    by 10: where the header states the peak and when, the samples must agree (here the DMG
    fixture, whose header states it; GeoNet's line is read the same way)."""
    text = (DATA / "ce36456p_CE36456.V2").read_text()
    assert text.count(old) == 1
    path = tmp_path / "damaged.V2"
    path.write_text(text.replace(old, new))
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"{path}: ")
    assert says in message
    stream = fs.read_record(DATA / "ce36456p_CE36456.V2")
    assert stream[0].stats.stated_peak.time == 10.94
