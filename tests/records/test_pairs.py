"""Record pairs (issue 16): two horizontal components of one recording from the bundled PEER
pairs (data/records/pairs), padded to one length and said so, rotated to any azimuth."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.errors import RecordError
from floorslide.records.pairs import make_pair, read_pair, read_pairs
from tests.conftest import ROOT

PAIRS = ROOT / "data" / "records" / "pairs"


@pytest.fixture(scope="module")
def pairs():
    return read_pairs(PAIRS / "index.csv")


def test_the_bundled_pairs_read_with_their_catalog_values(pairs):
    import csv

    rows = list(csv.DictReader(open(PAIRS / "index.csv", newline="")))
    assert len(pairs) == len(rows) == 10
    # the catalog's PGA has 6 decimals: within half a unit of the last
    for p, row in zip(pairs, rows, strict=True):
        assert p.dt == float(row["dt"])
        assert p.npts == max(int(row["npts_h1"]), int(row["npts_h2"]))
        assert np.abs(p.h1).max() / fs.G == pytest.approx(float(row["pga_h1_g"]), abs=5.001e-7)
        assert np.abs(p.h2).max() / fs.G == pytest.approx(float(row["pga_h2_g"]), abs=5.001e-7)
        assert p.names == (row["comp_h1"], row["comp_h2"])
        padded = int(row["npts_h1"]) != int(row["npts_h2"])
        assert any("padded with" in n for n in p.notes) == padded


def test_components_of_different_lengths_are_padded_with_zeros_and_said_so(pairs):
    p = next(p for p in pairs if p.names == ("90", "180"))  # St Elias: 12353 and 12377 samples
    assert p.npts == 12377
    assert np.all(p.h1[12353:] == 0.0) and np.any(p.h2[12353:] != 0.0)
    (note,) = [n for n in p.notes if "padded" in n]
    assert "12353 samples, padded with 24 zero(s) to 12377" in note


def test_azimuths_and_a_pair_that_is_not_perpendicular(pairs):
    sylmar = next(p for p in pairs if p.names == ("52", "142"))
    assert sylmar.azimuths == (52.0, 142.0) and not any("perpendicular" in n for n in sylmar.notes)
    lucerne = next(p for p in pairs if p.names == ("260", "345"))
    assert any("not perpendicular" in n and "5 degrees" in n for n in lucerne.notes)
    tcu = next(p for p in pairs if p.names == ("E", "N"))
    assert tcu.azimuths == (90.0, 0.0)


def test_rotation(pairs):
    p = pairs[0]
    for angle in (0.0, 30.0, 137.5):
        r = p.rotated(angle)
        np.testing.assert_allclose(r.h1, p.along(angle), rtol=0, atol=1e-15)
        np.testing.assert_allclose(r.along(20.0), p.along(angle + 20.0), rtol=0, atol=1e-12)
        # the horizontal motion's magnitude does not depend on the axes
        np.testing.assert_allclose(np.hypot(r.h1, r.h2), np.hypot(p.h1, p.h2), rtol=1e-13)
    assert p.rotated(30.0).azimuths == (82.0, 172.0)


def test_two_files_give_the_catalogs_pair(pairs):
    p = read_pair(PAIRS / "RSN181_IMPVALL.H_H-E06140.AT2", PAIRS / "RSN181_IMPVALL.H_H-E06230.AT2")
    q = next(q for q in pairs if q.names == ("140", "230"))
    np.testing.assert_array_equal(p.h1, q.h1)
    np.testing.assert_array_equal(p.h2, q.h2)
    assert p.npts == 7818 and any("padded with 1 zero" in n for n in p.notes)


def test_bad_pairs_are_refused():
    with pytest.raises(RecordError, match="different time steps"):
        make_pair(np.ones(10), np.ones(10), 0.01, dt2=0.02)
    with pytest.raises(RecordError, match="NaN"):
        make_pair(np.ones(10), np.full(10, np.nan), 0.01)
    with pytest.raises(RecordError, match="at least 2"):
        make_pair(np.ones(10), np.ones(1), 0.01)
    with pytest.raises(RecordError, match="file_h1"):
        read_pairs(ROOT / "data" / "records" / "slammer" / "index.csv")


# ------------------------------------------------------------------ one multi-channel file
RECORDS = ROOT / "tests" / "data" / "records"
RAW = ROOT / "tests" / "data" / "raw"


def _cosmos_channels(tmp_path, components):
    """A COSMOS V2 file of several channels: the El Centro fixture's channel repeated, each with
    its own component line (and the values scaled, to tell them apart)."""
    lines = (RECORDS / "ELC180.V2").read_text().splitlines()
    head = next(i for i, s in enumerate(lines) if "acceleration pts" in s)
    end = next(i for i, s in enumerate(lines) if s.startswith("End-of-data"))
    blocks = []
    for k, comp in enumerate(components):
        block = lines[: end + 1]
        block[8] = block[8].replace("180 deg", comp)
        block[head + 1 : end] = [f"{(k + 1) * float(s):15.6e}" for s in block[head + 1 : end]]
        blocks.append("\n".join(block))
    path = tmp_path / "three.V2"
    path.write_text("\n".join(blocks) + "\n")
    return path


def test_a_pair_from_one_cosmos_file_with_three_channels(tmp_path):
    path = _cosmos_channels(tmp_path, ["180 deg", "090 deg", "Up"])
    one = fs.read_record(RECORDS / "ELC180.V2")[0].data
    p = read_pair(path)
    assert p.names == ("180", "090")
    assert p.azimuths == (180.0, 90.0)
    np.testing.assert_allclose(p.h1, one, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(p.h2, 2 * one, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(p.vertical, 3 * one, rtol=1e-6, atol=1e-12)
    # without the vertical; a file with three horizontals is refused
    assert read_pair(_cosmos_channels(tmp_path, ["180 deg", "090 deg"])).vertical is None
    with pytest.raises(RecordError, match="3 horizontal and 0 vertical"):
        read_pair(_cosmos_channels(tmp_path, ["180 deg", "090 deg", "045 deg"]))


def test_a_pair_from_a_miniseed_stream(tmp_path):
    from obspy import Stream, Trace

    rng = np.random.default_rng(3)
    data = rng.normal(size=(3, 500))
    st = Stream([Trace(d, header={"delta": 0.01, "channel": c, "station": "X"})
                 for d, c in zip(data, ["HNZ", "HNN", "HNE"], strict=True)])  # fmt: skip
    path = tmp_path / "x.mseed"
    st.write(str(path), format="MSEED", encoding="FLOAT64")
    p = read_pair(path, units="m/s**2")
    np.testing.assert_array_equal(p.h1, data[1])
    np.testing.assert_array_equal(p.h2, data[2])
    np.testing.assert_array_equal(p.vertical, data[0])
    assert p.azimuths is None or p.azimuths == (0.0, 90.0)


def test_a_knet_pair_from_one_of_its_files(tmp_path):
    ns = (RAW / "AOM0081801241951.NS").read_text()
    (tmp_path / "AOM0081801241951.NS").write_text(ns)
    with pytest.raises(RecordError, match=r"AOM0081801241951\.EW not found"):
        read_pair(tmp_path / "AOM0081801241951.NS")
    # the EW file: the same recording's layout, its direction line changed
    ew = ns.replace("Dir.              N-S", "Dir.              E-W")
    assert ew != ns
    (tmp_path / "AOM0081801241951.EW").write_text(ew)
    p = read_pair(tmp_path / "AOM0081801241951.EW")
    one = fs.read_record(RAW / "AOM0081801241951.NS")[0].data
    np.testing.assert_array_equal(p.h1, one)
    np.testing.assert_array_equal(p.h2, one)
    assert p.vertical is None
    assert "AOM0081801241951.NS + AOM0081801241951.EW" in p.label
    assert p.names == ("NS", "EW") and p.azimuths == (0.0, 90.0)


def test_one_component_alone_is_not_a_pair():
    with pytest.raises(RecordError, match="one component in the file"):
        read_pair(RECORDS / "ELC180.V2")
