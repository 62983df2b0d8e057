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
        block[10] = block[10].replace("-306.831", f"{-306.831 * (k + 1):.3f}")  # its peak
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
    # the EW file: the same recording's layout, its direction line changed and its scale
    # doubled (two components holding the same samples are not a pair)
    ew = ns.replace("Dir.              N-S", "Dir.              E-W")
    ew = ew.replace("7845(gal)/8223790", "15690(gal)/8223790").replace("36.185", "72.370")
    assert ew != ns
    (tmp_path / "AOM0081801241951.EW").write_text(ew)
    p = read_pair(tmp_path / "AOM0081801241951.EW")
    one = fs.read_record(RAW / "AOM0081801241951.NS")[0].data
    np.testing.assert_array_equal(p.h1, one)
    np.testing.assert_allclose(p.h2, 2 * one, rtol=1e-15, atol=0)
    assert p.vertical is None
    assert "AOM0081801241951.NS + AOM0081801241951.EW" in p.label
    assert p.names == ("NS", "EW") and p.azimuths == (0.0, 90.0)


def test_one_component_alone_is_not_a_pair():
    with pytest.raises(RecordError, match="one component in the file"):
        read_pair(RECORDS / "ELC180.V2")


# ------------------------------------------------------- two components of one recording


SYLMAR = (PAIRS / "RSN1084_NORTHR_SCS052.AT2", PAIRS / "RSN1084_NORTHR_SCS142.AT2")
LUCERNE = PAIRS / "RSN879_LANDERS_LCN260.AT2"


def test_the_same_file_or_samples_as_both_components_is_refused(tmp_path):
    """'slide A A' ran with a note calling the components '90 degrees off'."""
    with pytest.raises(RecordError) as info:
        read_pair(SYLMAR[0], SYLMAR[0])
    message = str(info.value)
    assert "the same file is given as both horizontal components" in message
    assert message.startswith(f"{SYLMAR[0]} + {SYLMAR[0]}: ") and "\n" not in message
    copy = tmp_path / "copy.AT2"
    copy.write_bytes(SYLMAR[0].read_bytes())
    with pytest.raises(RecordError, match=r"both components hold the same 8773 samples"):
        read_pair(SYLMAR[0], copy)


def test_components_of_different_recordings_are_refused():
    """Two earthquakes (Northridge at Sylmar, Landers at Lucerne) passed as one pair."""
    with pytest.raises(RecordError) as info:
        read_pair(SYLMAR[0], LUCERNE)
    message = str(info.value)
    assert message.startswith(f"{SYLMAR[0]} + {LUCERNE}: the components are of different")
    assert "'Sylmar - Converter Sta' and 'Lucerne'" in message


def _text_component(path, station, start, scale):
    rng = np.random.default_rng(7)
    samples = "\n".join(f"{v:.5f}" for v in scale * rng.standard_normal(200))
    path.write_text(
        f"# dt: 0.01\n# units: g\n# station: {station}\n# starttime: {start}\n{samples}\n"
    )
    return path


def test_components_that_start_far_apart_are_refused(tmp_path):
    a = _text_component(tmp_path / "a.txt", "X", "2020-01-01T00:00:00", 0.1)
    b = _text_component(tmp_path / "b.txt", "X", "2020-01-01T00:00:30", 0.2)
    assert read_pair(a, b).npts == 200  # 30 s: one recording, triggered apart
    late = _text_component(tmp_path / "c.txt", "X", "2020-01-01T01:00:00", 0.2)
    with pytest.raises(RecordError, match=r"the components start 3600 s apart .* at most 60 s"):
        read_pair(a, late)
    other = _text_component(tmp_path / "d.txt", "Y", "2020-01-01T00:00:00", 0.2)
    with pytest.raises(RecordError, match=r"different stations \('X' and 'Y'\)"):
        read_pair(a, other)


def test_parallel_components_are_called_parallel():
    """The note called two components along one axis '90 degrees off'."""
    p = make_pair(np.ones(10), np.arange(10.0), 0.01, names=("180", "180"))
    (note,) = p.notes
    assert "not perpendicular by their azimuths (parallel: both along one axis)" in note
    (note,) = make_pair(np.ones(10), np.arange(10.0), 0.01, names=("10", "80")).notes
    assert "(70 degrees apart, 20 degrees from perpendicular)" in note


def _pair_catalog(tmp_path, rows):
    catalog = tmp_path / "pairs.csv"
    lines = ["file_h1,file_h2,comp_h1,comp_h2,dt,units"]
    lines += [f"{a},{b},1,2,0.005,g" for a, b in rows]
    catalog.write_text("\n".join(lines) + "\n")
    return catalog


def test_a_catalog_pair_of_one_file_or_two_recordings_is_refused(tmp_path):
    from floorslide.errors import SceneError
    from floorslide.scene.planner import plan
    from floorslide.scene.schema import parse_scene

    sylmar = [p.as_posix() for p in SYLMAR]
    scene = (
        '[[records]]\nset = "p"\ncatalog = "pairs.csv"\n[[buildings]]\nid = "f"\n'
        'kind = "fixed"\nperiod = 0.2\n[[contents]]\nid = "c"\nmu = [0.1]\n'
    )
    _pair_catalog(tmp_path, [(sylmar[0], sylmar[0])])
    with pytest.raises(SceneError) as info:  # caught when the scene is loaded (--dry-run)
        parse_scene(scene, tmp_path / "s.toml")
    assert "records[0].catalog:" in str(info.value)
    assert "pairs.csv: line 2 lists" in str(info.value) and "twice (file_h1, file_h2)" in str(
        info.value
    )
    mixed = ((PAIRS / "RSN181_IMPVALL.H_H-E06140.AT2").as_posix(), LUCERNE.as_posix())
    catalog = _pair_catalog(tmp_path, [(sylmar[0], sylmar[1]), mixed])
    with pytest.raises(RecordError, match=r"pairs.csv:3: the components are of different"):
        read_pairs(catalog)
    p = plan(parse_scene(scene, tmp_path / "s.toml"), evaluate=False)
    assert [r.record for r in p.records] == ["RSN1084_NORTHR_SCS"]
    (failure,) = p.failures
    assert failure.startswith(f"{catalog}:3: the components are of different stations")
    assert "(RSN181_IMPVALL.H_H-E06140.AT2, RSN879_LANDERS_LCN260.AT2)" in failure
