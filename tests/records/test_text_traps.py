"""Text records that used to read as a wrong record without a word (issue 19, items 6, 7, 8):
a sample-count first line, underscores in numbers, a time column in milliseconds, a byte-order
mark; and the memory a long text record takes to read."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

import floorslide as fs
from floorslide.errors import RecordError
from floorslide.records.catalog import load_catalog
from floorslide.records.formats.text import CHUNK_BYTES
from tests.conftest import G
from tests.records.conftest import FIXTURES


def _one_line(info: pytest.ExceptionInfo, path) -> str:
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"{path}: ")
    assert info.value.exit_code == 3
    return message


# ------------------------------------------------------------------ a sample-count first line


def test_count_line_is_not_read_as_a_sample(tmp_path, elc_g):
    """'3949' above 3949 samples was read as a 3949 g spike."""
    path = tmp_path / "counted.txt"
    path.write_text("# dt: 0.01\n# units: g\n3949\n" + "\n".join(f"{v:.6g}" for v in elc_g))
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    message = _one_line(info, path)
    assert "line 3: 3949 is the number of values after it, a sample count" in message
    assert "'# npts: 3949'" in message


def test_count_line_of_a_truncated_file(tmp_path, elc_g):
    path = tmp_path / "cut.txt"
    path.write_text("3949\n" + "\n".join(f"{v:.6g}" for v in elc_g[:3900]) + "\n")
    with pytest.raises(RecordError) as info:
        fs.read_record(path, dt=0.01, units="g")
    message = _one_line(info, path)
    assert "line 1: 3949 looks like a sample count" in message
    assert "3900 values follow it: a truncated file?" in message


@pytest.mark.parametrize("count", ["3949.", "3949.0", "3.949E+03", "+3949"])
def test_count_line_in_any_spelling_is_a_count(tmp_path, elc_g, count):
    """'3949.' or '3.949E+03' above 3949 samples was read as a sample (a 3949 g spike)."""
    path = tmp_path / "counted.txt"
    path.write_text(f"# dt: 0.01\n# units: g\n{count}\n" + "\n".join(f"{v:.6g}" for v in elc_g))
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    message = _one_line(info, path)
    assert f"line 3: {count} is the number of values after it, a sample count" in message


@pytest.mark.parametrize("count", ["2000", "2000.", "2.0E+03"])
def test_count_of_a_truncated_file_in_gal_is_not_its_peak(tmp_path, elc_g, count):
    """'2000.' above the first 1500 samples of a record in gal (peak 311 gal) was read as a
    2000 gal sample: PGA 2.04 g instead of 0.32 g, and no flag named it. A whole first value
    above every other value and above their number is a count that disagrees with them."""
    path = tmp_path / "cut_gal.txt"
    gal = elc_g[:1500] * 980.665
    path.write_text(f"# dt: 0.01\n# units: gal\n{count}\n" + "\n".join(f"{v:.4f}" for v in gal))
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    message = _one_line(info, path)
    assert f"line 3: {count} looks like a sample count, not a sample" in message
    assert "1500 values follow it: a truncated file?" in message


def test_count_header_in_any_spelling(tmp_path):
    path = tmp_path / "npts.txt"
    body = "# dt: 0.01\n# units: g\n# npts: {}\n0.1\n0.2\n-0.1\n"
    for count in ("3", "3.", "3.0E+00"):
        path.write_text(body.format(count))
        assert fs.read_record(path)[0].stats.npts == 3
    path.write_text(body.format("4."))
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    assert "truncated: the header says npts=4 but the file holds only 3 values" in _one_line(
        info, path
    )
    path.write_text(body.format("3.5"))
    with pytest.raises(RecordError, match=r"header npts: '3.5' is not a whole number"):
        fs.read_record(path)


@pytest.mark.parametrize("count", ["3949.", "3.949E+03"])
def test_cosmos_and_at2_counts_in_any_spelling(tmp_path, count):
    """COSMOS count lines ('3949. acceleration pts', '100. Real-header values ...') and the
    AT2 NPTS are whole numbers in any spelling; a count with a fraction is refused in one
    line."""
    v2 = (FIXTURES / "ELC180.V2").read_text()
    want = fs.read_record(FIXTURES / "ELC180.V2")[0].data
    path = tmp_path / "counts.V2"
    path.write_text(
        v2.replace("    3949 acceleration pts", f"{count:>8} acceleration pts").replace(
            " 100 Real-header", " 100. Real-header"
        )
    )
    np.testing.assert_array_equal(fs.read_record(path)[0].data, want)
    path.write_text(v2.replace("    3949 acceleration pts", "  3949.5 acceleration pts"))
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    assert "line 50: the number of points '3949.5' is not a whole number" in _one_line(info, path)
    at2 = (FIXTURES / "ELC180_ngawest2.AT2").read_text()
    path = tmp_path / "counts.AT2"
    path.write_text(at2.replace("NPTS=  3949", f"NPTS= {count}"))
    assert fs.read_record(path)[0].stats.npts == 3949
    path.write_text(at2.replace("NPTS=  3949", "NPTS= 4.0E+03"))
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    message = _one_line(info, path)
    assert "truncated: the header says NPTS=4000 but the file holds only 3949 values" in message


def test_catalog_npts_with_a_fraction_is_refused(tmp_path, elc_g):
    """A catalog's npts '3949.5' was cut to 3949 and passed."""
    (tmp_path / "rec.txt").write_text("\n".join(f"{v:.6g}" for v in elc_g) + "\n")
    catalog = tmp_path / "index.csv"
    catalog.write_text("file,dt,units,npts\nrec.txt,0.01,g,3.949E+03\n")
    assert fs.read_catalog(catalog)[0].stats.npts == 3949
    catalog.write_text("file,dt,units,npts\nrec.txt,0.01,g,3949.5\n")
    with pytest.raises(RecordError, match=r"index.csv:2: npts '3949.5' is not a whole number"):
        fs.read_catalog(catalog)


def test_count_line_above_two_columns(tmp_path):
    path = tmp_path / "counted2.txt"
    path.write_text("# units: g\n3\n0.00 0.1\n0.01 0.2\n0.02 0.3\n")
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    assert "line 2: a lone whole number (3) above two-column data" in _one_line(info, path)


def test_whole_number_samples_still_read(tmp_path):
    """A first sample that is a whole number but not a count is a sample: counts-like integer
    records and records starting at 0 read as before."""
    path = tmp_path / "ints.txt"
    path.write_text("# dt: 0.01\n# units: mm/s**2\n7\n3\n-4\n12\n0\n")
    np.testing.assert_array_equal(fs.read_record(path)[0].data, [0.007, 0.003, -0.004, 0.012, 0])
    path.write_text("0\n0.5\n-0.25\n")
    np.testing.assert_array_equal(
        fs.read_record(path, dt=0.01, units="g")[0].data, [0.0, 0.5 * G, -0.25 * G]
    )


# ------------------------------------------------------------------------- underscores


@pytest.mark.parametrize(
    ("body", "where"),
    [
        ("0.01\n1_000\n0.02\n", "line 4, column 1: '1_000'"),  # the fast path
        ("0.01\n# a comment\n0.02\n-1_0.5\n", "line 6, column 1: '-1_0.5'"),  # line by line
        ("0.0 0.01\n0.01 2_0\n", "line 4, column 6: '2_0'"),
    ],
)
def test_underscores_are_not_digit_separators(tmp_path, body, where):
    """Python's float reads '1_000' as 1000 and '0_01' as 1: a record holds no such number."""
    path = tmp_path / "under.txt"
    path.write_text("# dt: 0.01\n# units: g\n" + body)
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    message = _one_line(info, path)
    assert f"{where} is not a number (underscores are not digit separators" in message


def test_underscores_in_headers_and_other_formats(tmp_path):
    path = tmp_path / "dt.txt"
    path.write_text("# dt: 0_01\n# units: g\n0.1\n0.2\n")
    with pytest.raises(RecordError, match=r"header dt: '0_01' is not a number of seconds"):
        fs.read_record(path)
    lines = (FIXTURES / "ELC180_ngawest2.AT2").read_text().splitlines()
    lines[6] = lines[6].replace(".", "_", 1)
    bad = tmp_path / "under.AT2"
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(RecordError, match=r"line 7, column \d+: '.*_.*' is not a number \(under"):
        fs.read_record(bad)
    lines = (FIXTURES / "ELC180_ngawest2.AT2").read_text().splitlines()
    lines[3] = lines[3].replace("3949", "3_949")
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(RecordError, match=r"NPTS '3_949' is not a number \(underscores"):
        fs.read_record(bad)
    catalog = tmp_path / "index.csv"
    (tmp_path / "bare.txt").write_text("0.1\n0.2\n")
    catalog.write_text("file,dt,units,npts\nbare.txt,0_01,g,2\n")
    with pytest.raises(
        RecordError, match=r"index.csv:2: dt '0_01' is not a number of seconds \(un"
    ):
        fs.read_catalog(catalog)
    catalog.write_text("file,dt,units,npts\nbare.txt,0.01,g,1_0\n")
    with pytest.raises(RecordError, match=r"index.csv:2: npts '1_0' is not a whole number \(under"):
        fs.read_catalog(catalog)


# ------------------------------------------------------------------ time in milliseconds


def test_time_column_in_milliseconds_is_refused(tmp_path):
    """A time column in ms gave dt = 5 s without a word."""
    times = 5.0 * np.arange(200)
    body = "\n".join(f"{t:g},{a:.4f}" for t, a in zip(times, np.sin(times / 50), strict=True))
    path = tmp_path / "ms.csv"
    path.write_text("# units: g\ntime_ms,acc_g\n" + body + "\n")
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    message = _one_line(info, path)
    assert "line 2: the time column is in milliseconds ('time_ms')" in message
    path.write_text("# units: g\n# time units: ms\n" + body + "\n")
    with pytest.raises(RecordError, match=r"the header: the time column is in milliseconds"):
        fs.read_record(path)
    path.write_text("# units: g\n" + body + "\n")  # unlabelled: dt = 5 s is not an accelerogram
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    message = _one_line(info, path)
    assert "line 3: the time column steps by 5 s, implausible for an accelerogram" in message
    seconds = "\n".join(f"{0.005 * k:.3f},{a:.4f}" for k, a in enumerate(np.ones(5)))
    path.write_text("# units: g\ntime_s,acc\n" + seconds + "\n")
    assert fs.read_record(path)[0].stats.delta == pytest.approx(0.005)


# ------------------------------------------------------------------------ byte-order mark

BOM = b"\xef\xbb\xbf"


def test_byte_order_mark_record_catalog_and_sidecar(tmp_path):
    """A UTF-8 BOM (Notepad, Excel) made a header line read as '3 columns' and a bare file's
    first value '\\ufeff0.01' not a number."""
    path = tmp_path / "header.txt"
    path.write_bytes(BOM + b"# dt: 0.01\n# units: g\n0.01\n0.02\n-0.01\n")
    tr = fs.read_record(path)[0]
    assert tr.stats.delta == 0.01
    np.testing.assert_array_equal(tr.data, np.array([0.01, 0.02, -0.01]) * G)
    (tmp_path / "bare.txt").write_bytes(BOM + b"0.01\n0.02\n")
    (tmp_path / "index.csv").write_bytes(BOM + b"file,dt,units\nbare.txt,0.02,g\n")
    tr = fs.read_record(tmp_path / "bare.txt")[0]  # through the sidecar
    assert tr.stats.delta == 0.02 and tr.stats.catalog.file == "bare.txt"
    assert [e.path.name for e in load_catalog(tmp_path / "index.csv")] == ["bare.txt"]
    at2 = tmp_path / "bom.AT2"
    at2.write_bytes(BOM + (FIXTURES / "ELC180_ngawest2.AT2").read_bytes())
    np.testing.assert_array_equal(
        fs.read_record(at2)[0].data, fs.read_record(FIXTURES / "ELC180_ngawest2.AT2")[0].data
    )


def test_utf16_is_named(tmp_path):
    path = tmp_path / "wide.txt"
    path.write_bytes("# dt: 0.01\n# units: g\n0.01\n".encode("utf-16"))
    with pytest.raises(RecordError) as info:
        fs.read_record(path)
    assert "UTF-16 text; floorslide reads ASCII or UTF-8 text" in _one_line(info, path)


# ----------------------------------------------------------------------------- memory


def test_long_text_record_memory_is_a_few_times_its_samples(tmp_path):
    """A 10-million-sample text record took 1.8 GB to read (a Python string per line, the
    text copied several times); it is read block by block into one array now. Here 10⁶
    samples (8 MB of float64): the peak of traced allocations stays within 4x the samples."""
    n = 1_000_000
    rng = np.random.default_rng(19)
    values = np.round(rng.standard_normal(n) * 0.1, 6)
    path = tmp_path / "long.txt"
    np.savetxt(path, values, fmt="%.6f", header="dt: 0.005\nunits: g")
    assert path.stat().st_size > 2 * CHUNK_BYTES  # several blocks
    tracemalloc.start()
    try:
        tr = fs.read_record(path)[0]
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert tr.stats.npts == n and tr.stats.delta == 0.005
    np.testing.assert_array_equal(tr.data, values * G)
    assert peak <= 4 * values.nbytes, f"{peak / 1e6:.1f} MB for {values.nbytes / 1e6:.0f} MB"


def test_block_boundaries_do_not_move_values_or_lines(tmp_path, monkeypatch):
    """Blocks of a few bytes: the same record, and messages name the right line."""
    import floorslide.records.formats.text as text

    monkeypatch.setattr(text, "CHUNK_BYTES", 7)
    path = tmp_path / "small.txt"
    path.write_text("# dt: 0.01\n# units: g\n0.125\n\n-0.5\n# note\n0.25\n1e-3\n")
    np.testing.assert_array_equal(
        fs.read_record(path)[0].data, [0.125 * G, -0.5 * G, 0.25 * G, 1e-3 * G]
    )
    path.write_text("# units: g\n0.00 1\n0.01 2\n\n0.025 3\n0.03 4\n")
    with pytest.raises(RecordError, match=r"line 5: time 0.025 s is .* off the uniform grid"):
        fs.read_record(path)
    path.write_text("# dt: 0.01\n# units: g\n0.1\n0.2\n0.3\n0.4\nx.5\n")
    with pytest.raises(RecordError, match=r"line 7, column 1: 'x.5' is not a number"):
        fs.read_record(path)
