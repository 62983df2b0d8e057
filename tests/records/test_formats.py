"""Each format with real record data (El Centro 1940 NS): values, units, dt and metadata.

The AT2, COSMOS V2 and K-NET files of tests/data/records/ hold the bundled ELC-180 samples in
each format's real layout (written once by scripts/make_record_fixtures.py); MiniSEED and SAC
are written here with ObsPy; text variants are written here.
"""

from __future__ import annotations

import numpy as np
import obspy
import pytest
from obspy import Stream, Trace, UTCDateTime

import floorslide as fs
from floorslide.errors import RecordError, UnitsError
from floorslide.records.formats.at2 import _is_at2
from floorslide.records.formats.cosmos import _is_cosmos_v2
from floorslide.records.formats.text import _is_text
from tests.conftest import SLAMMER, G
from tests.records.conftest import ELC_FILE, FIXTURES

AT2_WEST2 = FIXTURES / "ELC180_ngawest2.AT2"
AT2_OLD = FIXTURES / "ELC180_peer2000.AT2"
COSMOS = FIXTURES / "ELC180.V2"
KNET = FIXTURES / "ELC180.knet"
KNET_GAL_PER_COUNT = 3920 / 6182761


# ---------------------------------------------------------------- PEER AT2


def test_at2_ngawest2(elc_g, elc_si):
    st = fs.read_record(AT2_WEST2)
    assert len(st) == 1
    tr = st[0]
    # E15.7 holds the 6 significant digits of the source exactly: same doubles, same product
    np.testing.assert_array_equal(tr.data, elc_si)
    assert tr.stats.delta == 0.01 and tr.stats.npts == 3949
    assert tr.stats.units == "m/s**2" and tr.stats.original_units == "g"
    assert tr.stats.record.format == "AT2"
    assert tr.stats.record.event == "Imperial Valley-02, 5/19/1940"
    assert tr.stats.record.station == "El Centro Array #9"
    assert tr.stats.record.component == "180"
    assert tr.stats.at2.date == "5/19/1940"
    assert tr.stats.at2.header[3].startswith("NPTS=  3949")


def test_at2_older_header(elc_si):
    tr = fs.read_record(AT2_OLD)[0]
    np.testing.assert_array_equal(tr.data, elc_si)
    assert tr.stats.delta == 0.01
    assert tr.stats.original_units == "g"
    assert tr.stats.record.event == "IMPERIAL VALLEY 05/19/40 0439"
    assert tr.stats.record.station == "EL CENTRO ARRAY #9"
    assert tr.stats.record.component == "180"


@pytest.mark.parametrize(
    "npts_line",
    [
        "NPTS=3949 DT=0.01",
        "NPTS = 3949, DT = 0.0100 SEC",
        "DT=   .0100 SEC, NPTS=  3949",
        "3949    0.0100    NPTS, DT",
        "0.0100   3949   DT, NPTS",
        "NPTS 3949 DT 0.01",
    ],
)
def test_at2_npts_dt_spellings(tmp_path, elc_si, npts_line):
    lines = AT2_WEST2.read_text().splitlines()
    lines[3] = npts_line
    path = tmp_path / "x.AT2"
    path.write_text("\n".join(lines) + "\n")
    assert _is_at2(path)
    tr = fs.read_record(path)[0]
    assert tr.stats.delta == 0.01 and tr.stats.npts == 3949
    np.testing.assert_array_equal(tr.data, elc_si)


def test_at2_units_from_header(tmp_path, elc_g):
    lines = AT2_WEST2.read_text().splitlines()
    lines[2] = "ACCELERATION TIME SERIES IN UNITS OF CM/SEC/SEC"
    path = tmp_path / "gal.AT2"
    path.write_text("\n".join(lines) + "\n")
    tr = fs.read_record(path)[0]
    assert tr.stats.original_units == "gal"
    np.testing.assert_allclose(tr.data, elc_g * 0.01, rtol=1e-15)


def test_at2_without_units_needs_them(tmp_path, elc_si):
    lines = AT2_WEST2.read_text().splitlines()
    lines[2] = "ACCELERATION TIME SERIES"
    path = tmp_path / "nounits.AT2"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(UnitsError, match="without stated units"):
        fs.read_record(path)
    np.testing.assert_array_equal(fs.read_record(path, units="g")[0].data, elc_si)


def test_at2_obspy_read_autodetects_through_the_entry_points(elc_g):
    st = obspy.read(str(AT2_WEST2))
    assert st[0].stats._format == "AT2"
    np.testing.assert_array_equal(st[0].data, elc_g)  # plugins return the file's values
    assert st[0].stats.units == "g"
    head = obspy.read(str(AT2_WEST2), headonly=True)
    assert head[0].stats.npts == 3949 and head[0].data.size == 0


def test_is_format_checks():
    assert _is_at2(AT2_WEST2) and _is_at2(AT2_OLD)
    assert _is_cosmos_v2(COSMOS)
    for other in (COSMOS, KNET, SLAMMER / ELC_FILE):
        assert not _is_at2(other)
    for other in (AT2_WEST2, KNET, SLAMMER / ELC_FILE):
        assert not _is_cosmos_v2(other)
    assert _is_text(SLAMMER / ELC_FILE)
    for other in (AT2_WEST2, AT2_OLD, COSMOS, KNET, SLAMMER / "index.csv"):
        assert not _is_text(other)
    for check in (_is_at2, _is_cosmos_v2, _is_text):  # never raise
        assert not check("/no/such/file")
        assert not check(FIXTURES)


# ---------------------------------------------------------------- COSMOS V2


def test_cosmos_v2(elc_g):
    st = fs.read_record(COSMOS)
    assert len(st) == 1  # the velocity record after the acceleration is skipped
    tr = st[0]
    # (1E15.6) of the values in cm/s²: 7 significant digits
    np.testing.assert_allclose(tr.data, elc_g * G, rtol=0, atol=5e-7 * np.abs(elc_g * G).max())
    assert tr.stats.delta == 0.01 and tr.stats.npts == 3949
    assert tr.stats.original_units == "gal"
    assert tr.stats.starttime == UTCDateTime(1940, 5, 19, 4, 36, 40)
    assert (tr.stats.network, tr.stats.station, tr.stats.channel) == ("NP", "ELC", "HNN")
    assert tr.stats.record.component == "180"
    assert tr.stats.record.event.startswith("Imperial Valley Earthquake")
    meta = tr.stats.cosmos
    assert meta.process_level == "V2"
    assert meta.station_name == "El Centro Array #9"
    assert meta.magnitude == 6.95 and meta.station_latitude == 32.794
    assert obspy.read(str(COSMOS))[0].stats._format == "COSMOSV2"


def _second_channel(text: str) -> str:
    acc = text.split("End-of-data for Chan  1 acceleration\n")[0]
    acc += "End-of-data for Chan  1 acceleration\n"
    other = acc.replace("<SCNL>ELC.HNN.", "<SCNL>ELC.HNE.").replace(
        "Sta Chan   1: 180 deg", "Sta Chan   2: 270 deg"
    )
    return text + other


def test_cosmos_multichannel_and_component(tmp_path):
    path = tmp_path / "two.V2"
    path.write_text(_second_channel(COSMOS.read_text()))
    st = fs.read_record(path)
    assert [tr.stats.channel for tr in st] == ["HNN", "HNE"]
    assert [tr.stats.record.component for tr in st] == ["180", "270"]
    east = fs.read_record(path, component="E")
    assert len(east) == 1 and east[0].stats.channel == "HNE"
    assert fs.read_record(path, component="270")[0].stats.channel == "HNE"
    with pytest.raises(RecordError, match=r"no component 'Z' in this file; it holds 180, 270"):
        fs.read_record(path, component="Z")


def test_cosmos_fixed_width_fields_that_touch(tmp_path, elc_g):
    """Fortran (8F9.4): a value like -306.8314 fills its field and touches its neighbour."""
    lines = COSMOS.read_text().splitlines()
    start = next(i for i, ln in enumerate(lines) if "acceleration pts" in ln)
    end = next(i for i, ln in enumerate(lines) if ln.startswith("End-of-data"))
    values = elc_g * 980.665
    body = ["".join(f"{v:9.4f}" for v in values[i : i + 8]) for i in range(0, values.size, 8)]
    assert any(len(line.split()) < 8 for line in body[:-1])  # some fields do touch
    header = lines[start].replace("(1E15.6)", "(8F9.4)")
    path = tmp_path / "touch.V2"
    path.write_text("\n".join([*lines[:start], header, *body, *lines[end : end + 1]]) + "\n")
    tr = fs.read_record(path)[0]
    np.testing.assert_allclose(tr.data, values * 0.01, atol=0.5e-4 * 0.01)


# ---------------------------------------------------------------- K-NET / KiK-net (ObsPy)


def test_knet(elc_g):
    tr = fs.read_record(KNET)[0]
    assert tr.stats._format == "KNET" and tr.stats.record.format == "KNET"
    # counts rounded to the nearest integer: error ≤ half a count
    tolerance = 0.5 * KNET_GAL_PER_COUNT * 0.01 * (1 + 1e-9)
    np.testing.assert_allclose(tr.data, elc_g * G, rtol=0, atol=tolerance)
    assert tr.stats.delta == 0.01 and tr.stats.npts == 3949
    assert tr.stats.original_units == "gal" and tr.stats.units == "m/s**2"
    assert tr.stats.calib == 1.0
    assert "counts x calib" in tr.stats.processing[-1]
    assert tr.stats.station == "ELC180" and tr.stats.record.component == "NS"
    # K-NET times are JST, and the logger adds 15 s to the record time (ObsPy undoes both)
    assert tr.stats.starttime == UTCDateTime(1940, 5, 19, 4, 36, 40)
    assert tr.stats.knet.mag == 7.0


def test_knet_units_must_agree():
    assert fs.read_record(KNET, units="gal")[0].stats.original_units == "gal"
    with pytest.raises(UnitsError, match="units 'g' were given but the file says 'gal'"):
        fs.read_record(KNET, units="g")


# ---------------------------------------------------------------- MiniSEED and SAC (ObsPy)


def _elc_trace(elc_g, channel="HNN", scale=980.665) -> Trace:
    tr = Trace(elc_g * scale)
    tr.stats.delta = 0.01
    tr.stats.network, tr.stats.station, tr.stats.channel = "NP", "ELC", channel
    tr.stats.starttime = UTCDateTime(1940, 5, 19, 4, 36, 40)
    return tr


def test_miniseed_needs_units(tmp_path, elc_g, elc_si):
    path = tmp_path / "elc.mseed"
    _elc_trace(elc_g).write(str(path), format="MSEED", encoding="FLOAT64")
    with pytest.raises(UnitsError, match=r"MSEED file without stated units; give them"):
        fs.read_record(path)
    tr = fs.read_record(path, units="gal")[0]
    np.testing.assert_allclose(tr.data, elc_si, rtol=1e-14)
    assert tr.stats.record.format == "MSEED" and tr.stats.original_units == "gal"
    assert tr.stats.delta == 0.01 and tr.id == "NP.ELC..HNN"
    assert tr.stats.record.component == "HNN"
    with pytest.raises(RecordError, match=r"dt = 0.02 s was given but the file says 0.01 s"):
        fs.read_record(path, units="gal", dt=0.02)


def test_miniseed_three_components(tmp_path, elc_g):
    path = tmp_path / "three.mseed"
    st = Stream([_elc_trace(elc_g * k, ch) for k, ch in ((1, "HNN"), (0.5, "HNE"), (0.2, "HNZ"))])
    st.write(str(path), format="MSEED", encoding="FLOAT64")
    assert len(fs.read_record(path, units="gal")) == 3
    up = fs.read_record(path, units="gal", component="Z")
    assert len(up) == 1 and up[0].stats.channel == "HNZ"
    np.testing.assert_allclose(up[0].data, 0.2 * elc_g * G, rtol=1e-14)
    assert fs.read_record(path, units="gal", component="hne")[0].stats.channel == "HNE"
    with pytest.raises(RecordError, match=r"no component 'X' in this file; it holds HNE, HNN, HNZ"):
        fs.read_record(path, units="gal", component="X")


def test_sac(tmp_path, elc_g, elc_si):
    tr = _elc_trace(elc_g, scale=1.0)
    path = tmp_path / "elc.sac"
    tr.stats.sac = {"kevnm": "IMPVALL40"}
    tr.write(str(path), format="SAC")
    out = fs.read_record(path, units="g")[0]
    np.testing.assert_allclose(out.data, elc_si, rtol=1e-6)  # SAC stores float32
    assert out.stats.record.event == "IMPVALL40"
    assert out.stats.record.format == "SAC"


def test_sac_idep_iacc_is_not_trusted(tmp_path, elc_g):
    tr = _elc_trace(elc_g)
    tr.stats.sac = {"idep": 8}
    path = tmp_path / "iacc.sac"
    tr.write(str(path), format="SAC")
    with pytest.raises(UnitsError, match="IDEP=IACC"):
        fs.read_record(path)


# ---------------------------------------------------------------- plain text


def test_self_describing_text(tmp_path, elc_g, elc_si):
    path = tmp_path / "elc.txt"
    path.write_text(
        "# El Centro 1940, copied from SLAMMER\n"
        "# event: Imperial Valley 1940\n"
        "# station = El Centro Array #9\n"
        "# Component: 180\n"
        "# dt: 0.01 s\n"
        "# units: G\n"
        "% a MATLAB-style comment\n"
        "! a Fortran-style comment\n" + "\n".join(f"{v:.9g}" for v in elc_g) + "\n"
    )
    assert _is_text(path)
    tr = fs.read_record(path)[0]
    np.testing.assert_array_equal(tr.data, elc_si)
    assert tr.stats.delta == 0.01 and tr.stats.original_units == "g"
    assert tr.stats.record.event == "Imperial Valley 1940"
    assert tr.stats.record.station == "El Centro Array #9"
    assert tr.stats.record.component == "180"
    assert tr.stats.fstext.header["component"] == "180"
    with pytest.raises(RecordError, match=r"dt = 0.02 s was given but the header says 0.01 s"):
        fs.read_record(path, dt=0.02)
    st = obspy.read(str(path))
    assert st[0].stats._format == "FSTEXT"


def test_two_column_csv_with_names(tmp_path, elc_g):
    t = 5.0 + 0.01 * np.arange(elc_g.size)
    path = tmp_path / "elc.csv"
    path.write_text(
        "# units: cm/s^2\ntime,acc\n"
        + "\n".join(f"{ti:.2f}, {v:.9g}" for ti, v in zip(t, elc_g * 980.665, strict=True))
    )
    tr = fs.read_record(path)[0]
    assert tr.stats.delta == pytest.approx(0.01, rel=1e-12)
    assert tr.stats.original_units == "gal"
    assert tr.stats.fstext.names == ["time", "acc"] and tr.stats.fstext.t0 == 5.0
    assert tr.stats.starttime == UTCDateTime(5.0)
    np.testing.assert_allclose(tr.data, elc_g * G, rtol=1e-8)


def test_one_column_with_dt_and_units_given(tmp_path, elc_g, elc_si):
    path = tmp_path / "plain.dat"
    path.write_text("\n".join(f"{v:.9g}" for v in elc_g) + "\n")
    tr = fs.read_record(path, dt=0.01, units="g")[0]
    np.testing.assert_array_equal(tr.data, elc_si)
    st = obspy.read(str(path), dt=0.01)
    assert st[0].stats.delta == 0.01


def test_whitespace_and_comma_separators(tmp_path):
    path = tmp_path / "mixed.txt"
    path.write_text("# sampling_rate: 50 Hz\n# units: m/s**2\n0.0,1.0\n0.02 ,  2.0\n0.04\t3.0\n")
    tr = fs.read_record(path)[0]
    assert tr.stats.delta == pytest.approx(0.02) and list(tr.data) == [1.0, 2.0, 3.0]
