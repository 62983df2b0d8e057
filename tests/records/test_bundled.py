"""Every bundled record, read through its catalog; npts against index.csv, PGA against
PROVENANCE.md; catalog filters, sidecar lookup and batch failures."""

from __future__ import annotations

import csv
import re
import shutil

import numpy as np
import pytest

import floorslide as fs
from floorslide.errors import RecordError, UnitsError
from floorslide.records.catalog import RecordFailure, is_catalog, load_catalog
from floorslide.records.read import PROCESSING_PREFIX
from tests.conftest import SLAMMER, G

INDEX = SLAMMER / "index.csv"


def _index_rows() -> dict[str, dict[str, str]]:
    with open(INDEX, newline="") as fh:
        return {row["file"]: row for row in csv.DictReader(fh)}


def _provenance_pga() -> dict[str, float]:
    """PGA (g) per file from the table of PROVENANCE.md."""
    table = {}
    for line in (SLAMMER / "PROVENANCE.md").read_text().splitlines():
        match = re.match(r"^\|\s*`([^`]+)`\s*\|.*\|\s*([0-9.]+)\s*\|\s*$", line)
        if match:
            table[match.group(1)] = float(match.group(2))
    return table


@pytest.fixture(scope="module")
def catalog_traces():
    return fs.read_catalog(INDEX)


def test_every_bundled_file_is_in_the_catalog_and_provenance():
    files = {p.name for p in SLAMMER.glob("*.txt")}
    assert len(files) == 36
    assert set(_index_rows()) == files
    assert set(_provenance_pga()) == files


def test_every_bundled_record_reads_through_the_catalog(catalog_traces):
    rows = _index_rows()
    pga = _provenance_pga()
    assert len(catalog_traces) == 36
    for trace in catalog_traces:
        name = trace.stats.catalog.file
        row = rows[name]
        assert trace.stats.npts == int(row["npts"]), name
        assert trace.stats.delta == float(row["dt"]), name
        assert trace.data.dtype == np.float64
        assert trace.stats.units == "m/s**2"
        assert trace.stats.original_units == "g"
        # PROVENANCE.md gives max|value| of the file with 6 significant digits
        measured = fs.measures(trace)["pga_g"]
        assert measured == pytest.approx(pga[name], rel=5e-6), name
        # all catalog columns kept as metadata, quoted fields with commas intact
        assert dict(trace.stats.catalog) == row
        assert trace.stats.record.event == row["event"]
        assert trace.stats.record.station == row["station"]
        assert trace.stats.catalog_line >= 2


def test_catalog_values_equal_the_file_in_si(catalog_traces):
    trace = next(t for t in catalog_traces if t.stats.catalog.station_id == "ELC-180")
    np.testing.assert_array_equal(
        trace.data, np.loadtxt(SLAMMER / "ImperialValley_1940_ELC-180.txt") * G
    )
    assert trace.stats.processing == [
        f"{PROCESSING_PREFIX}: convert_units(from='g', to='m/s**2', factor=9.80665)"
    ]


def test_quoted_fields_with_commas():
    rows = {e.row["station_id"]: e.row for e in load_catalog(INDEX)}
    assert rows["CYC-285"]["station"] == "Coyote Lake Dam, SW abut"


def test_where_filters_on_catalog_columns():
    pulse = fs.read_catalog(INDEX, where={"set": "pulse-like"})
    broad = fs.read_catalog(INDEX, where={"set": "broad-band"})
    assert len(pulse) == len(broad) == 18
    assert {t.stats.catalog.set for t in pulse} == {"pulse-like"}
    two = fs.read_catalog(INDEX, where={"station_id": ["ELC-180", "TAF-021"]})
    assert sorted(t.stats.catalog.station_id for t in two) == ["ELC-180", "TAF-021"]
    # values are compared as strings: a number matches its CSV spelling
    m65 = fs.read_catalog(INDEX, where={"magnitude": 6.5, "set": "pulse-like"})
    assert m65 and all(t.stats.catalog.magnitude == "6.5" for t in m65)
    assert fs.read_catalog(INDEX, where={"set": "no-such-set"}) == []


def test_where_on_an_unknown_column_is_an_error():
    with pytest.raises(RecordError, match="no column 'sett'"):
        fs.read_catalog(INDEX, where={"sett": "pulse-like"})


def test_is_catalog():
    assert is_catalog(INDEX)
    assert not is_catalog(SLAMMER / "PROVENANCE.md")
    assert not is_catalog(SLAMMER / "Kobe_1995_KAK-000.txt")
    assert not is_catalog(SLAMMER / "missing.csv")


def test_sidecar_gives_dt_units_and_metadata():
    """A bare SLAMMER file read alone: dt, units and metadata come from index.csv next to it."""
    st = fs.read_record(SLAMMER / "Kobe_1995_KAK-000.txt")
    tr = st[0]
    assert tr.stats.delta == 0.01 and tr.stats.npts == 3999
    assert tr.stats.original_units == "g"
    assert tr.stats.catalog.station_id == "KAK-000"
    assert tr.stats.catalog_file == str(INDEX)
    assert tr.stats.record.event == "Kobe, Japan 1995"


def test_given_dt_and_units_are_checked_against_the_sidecar(tmp_path):
    """Given dt and units that agree with the sidecar row are used with its metadata; ones
    that contradict it are errors (issue 19: --units gal on a file in g was applied)."""
    st = fs.read_record(SLAMMER / "Kobe_1995_KAK-000.txt", dt=0.01, units="g")
    assert st[0].stats.catalog.station_id == "KAK-000"
    with pytest.raises(UnitsError, match=r"units 'gal' were given but index.csv line \d+ says"):
        fs.read_record(SLAMMER / "Kobe_1995_KAK-000.txt", dt=0.01, units="gal")


def test_without_sidecar_a_bare_file_needs_dt_and_units(tmp_path):
    bare = tmp_path / "bare.txt"
    shutil.copy(SLAMMER / "Kobe_1995_KAK-000.txt", bare)
    with pytest.raises(RecordError, match=r"without a time step.*index.csv"):
        fs.read_record(bare)
    with pytest.raises(UnitsError, match=r"without stated units.*units="):
        fs.read_record(bare, dt=0.01)
    assert fs.read_record(bare, dt=0.01, units="g")[0].stats.npts == 3999


def test_sidecar_that_does_not_list_the_file(tmp_path):
    shutil.copy(INDEX, tmp_path / "index.csv")
    shutil.copy(SLAMMER / "Kobe_1995_KAK-000.txt", tmp_path / "other.txt")
    with pytest.raises(RecordError, match="without a time step"):
        fs.read_record(tmp_path / "other.txt")


def _bad_catalog(tmp_path):
    """A copy of two bundled rows plus a missing file, a bad dt and bad units (each row its own
    file: a catalog lists a record once)."""
    shutil.copy(SLAMMER / "Kobe_1995_KAK-000.txt", tmp_path / "Kobe_1995_KAK-000.txt")
    for name in ("Kobe_1995_SHI-000.txt", "bad_dt.txt", "bad_units.txt"):
        shutil.copy(SLAMMER / "Kobe_1995_SHI-000.txt", tmp_path / name)
    (tmp_path / "index.csv").write_text(
        "file,dt,units,station\n"
        "Kobe_1995_KAK-000.txt,0.01,g,Kakogawa\n"
        "missing.txt,0.01,g,Nowhere\n"
        "bad_dt.txt,-0.01,g,Shin-Osaka\n"
        "bad_units.txt,0.01,furlongs,Shin-Osaka\n"
        "Kobe_1995_SHI-000.txt,0.01,gal,Shin-Osaka\n"
    )
    return tmp_path / "index.csv"


def test_catalog_errors_raise_by_default(tmp_path):
    path = _bad_catalog(tmp_path)
    with pytest.raises(RecordError) as info:
        fs.read_catalog(path)
    message = str(info.value)
    assert "missing.txt: no such file (listed in index.csv line 3)" in message
    assert "\n" not in message


def test_catalog_errors_collected_so_the_batch_keeps_going(tmp_path):
    path = _bad_catalog(tmp_path)
    traces, failures = fs.read_catalog(path, errors="collect")
    assert [t.stats.catalog.station for t in traces] == ["Kakogawa", "Shin-Osaka"]
    assert traces[1].stats.original_units == "gal"
    assert all(isinstance(f, RecordFailure) for f in failures)
    assert [f.entry.line for f in failures] == [3, 4, 5]
    assert "no such file" in str(failures[0])
    assert "must be > 0" in str(failures[1]) and "index.csv:4" in str(failures[1])
    assert isinstance(failures[2].error, UnitsError)
    assert "furlongs" in str(failures[2])


def test_catalog_structure_errors(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("file,units\nx.txt,g\n")
    with pytest.raises(RecordError, match="no column 'dt'"):
        fs.read_catalog(bad)
    bad.write_text("file,dt,units\nx.txt,0.01,g,extra\n")
    with pytest.raises(RecordError, match=r"bad.csv:2: 4 fields where the header has 3"):
        fs.read_catalog(bad)
    with pytest.raises(RecordError, match="no such catalog"):
        fs.read_catalog(tmp_path / "none.csv")
    with pytest.raises(ValueError, match="errors must be"):
        fs.read_catalog(INDEX, errors="ignore")  # type: ignore[call-overload]


def test_read_record_on_a_catalog_says_so():
    with pytest.raises(RecordError, match="is a record catalog"):
        fs.read_record(INDEX)
