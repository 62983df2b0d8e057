"""Readers under random corruption of real files (hypothesis): the right record or one clear
error — never a crash, a hang or a silently different record.

Corruptions: truncation at any byte, a byte replaced by a non-numeric byte, header fields deleted
or edited, separators changed. Replacing a digit by another digit is not among them: no
checksum-free text format can tell that from a real value.
"""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from floorslide.errors import RecordError
from floorslide.records.read import read_record
from tests.conftest import ROOT

DATA = ROOT / "tests" / "data" / "records"
FILES = {
    "at2": DATA / "ELC180_ngawest2.AT2",
    "at2_old": DATA / "ELC180_peer2000.AT2",
    "cosmos": DATA / "ELC180.V2",
}
ORIGINAL = {k: read_record(p)[0].data.copy() for k, p in FILES.items()}
SETTINGS = settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


def check(path, original):
    """Either the same record, or one RecordError naming the file in one line."""
    try:
        st_ = read_record(path)
    except RecordError as exc:
        msg = str(exc)
        assert "\n" not in msg and str(path) in msg
        return "error"
    data = st_[0].data
    assert data.size == original.size and np.array_equal(data, original), "silently different"
    return "same"


@pytest.mark.parametrize("kind", ["at2", "at2_old"])
def test_at2_cut_inside_the_last_value(kind, tmp_path):
    """Found by the fuzzer: an AT2 file cut inside its last value ('-.5959150E-04' ->
    '-.5959150', '-.5959150E-0', '-.59') kept NPTS values and read as a different record."""
    raw = FILES[kind].read_bytes().rstrip()
    path = tmp_path / FILES[kind].name
    for drop in (1, 4, 7):
        path.write_bytes(raw[:-drop])
        with pytest.raises(RecordError, match="ends inside its last value"):
            read_record(path)
    path.write_bytes(raw)  # complete, without a final line break: the same record
    assert np.array_equal(read_record(path)[0].data, ORIGINAL[kind])


def test_cosmos_cut_inside_the_last_value_of_a_block(tmp_path):
    """Found by the fuzzer: a COSMOS file cut inside the last acceleration value
    ("-5.843930e-02" -> "-5.84393") read as a record with a different last sample. A block must
    end with its 'End-of-data' line."""
    raw = FILES["cosmos"].read_bytes()
    end = raw.index(b"End-of-data for Chan  1 acceleration")
    last = raw.rindex(b"\n", 0, end - 1) + 1  # the line of the last acceleration value
    path = tmp_path / "cut.V2"
    for cut in (last + 10, end - 1, end):
        path.write_bytes(raw[:cut])
        with pytest.raises(RecordError, match="truncated"):
            read_record(path)


@pytest.mark.parametrize("kind", sorted(FILES))
@SETTINGS
@given(frac=st.floats(min_value=0.0, max_value=1.0))
def test_truncation_at_any_byte(kind, frac, tmp_path_factory):
    raw = FILES[kind].read_bytes()
    cut = int(frac * len(raw))
    path = tmp_path_factory.mktemp("t") / FILES[kind].name
    path.write_bytes(raw[:cut])
    outcome = check(path, ORIGINAL[kind])
    if kind.startswith("at2") and cut < len(raw.rstrip()):
        assert outcome == "error"  # the data end the file: any cut into them is caught


@pytest.mark.parametrize("kind", sorted(FILES))
@SETTINGS
@given(
    pos=st.floats(min_value=0.0, max_value=0.999),
    byte=st.sampled_from(list(b"xZ#%!?,;:@$&*()[]{}~\x00\xff")),
)
def test_byte_replaced_by_non_numeric(kind, pos, byte, tmp_path_factory):
    raw = bytearray(FILES[kind].read_bytes())
    i = int(pos * len(raw))
    raw[i] = byte
    path = tmp_path_factory.mktemp("b") / FILES[kind].name
    path.write_bytes(bytes(raw))
    check(path, ORIGINAL[kind])


@pytest.mark.parametrize(
    ("kind", "old", "new"),
    [
        ("at2", b"NPTS=  3949", b"NPTS=  3948"),
        ("at2", b"NPTS=  3949", b"NPTS=  3950"),
        ("at2", b"DT=   .0100", b"DT=   -.0100"),
        ("at2", b"NPTS=  3949, ", b""),
        ("at2", b"UNITS OF G", b"UNITS OF FURLONGS"),
        ("at2_old", b"3949", b"3950"),
    ],
)
def test_edited_header_fields(kind, old, new, tmp_path):
    raw = FILES[kind].read_bytes()
    assert old in raw
    path = tmp_path / FILES[kind].name
    path.write_bytes(raw.replace(old, new, 1))
    assert check(path, ORIGINAL[kind]) == "error"


@SETTINGS
@given(sep=st.sampled_from([b",", b" , ", b"\t", b"   ", b";"]))
def test_changed_separators_in_text(sep, tmp_path_factory):
    """A two-column (time, acceleration) file with its separator changed."""
    src = ROOT / "data" / "records" / "slammer" / "ImperialValley_1940_ELC-180.txt"
    values = src.read_bytes().split()
    body = b"".join(b"%.2f" % (0.01 * k) + sep + v + b"\n" for k, v in enumerate(values))
    path = tmp_path_factory.mktemp("s") / "elc.txt"
    path.write_bytes(b"# units: g\n" + body)
    original = np.loadtxt(src) * 9.80665
    try:
        data = read_record(path)[0].data
    except RecordError as exc:
        assert sep == b";" and str(path) in str(exc)  # ';' is not a separator: a clear error
        return
    np.testing.assert_array_equal(data, original)


def test_sidecar_catalog_catches_a_truncated_bare_file(tmp_path):
    """A bare text file has no header to check against; read through its catalog (npts column),
    a truncated one is refused rather than read as a shorter record."""
    src = ROOT / "data" / "records" / "slammer"
    shutil.copy(src / "index.csv", tmp_path / "index.csv")
    lines = (src / "ImperialValley_1940_ELC-180.txt").read_text().splitlines()
    (tmp_path / "ImperialValley_1940_ELC-180.txt").write_text("\n".join(lines[:-10]) + "\n")
    with pytest.raises(RecordError):
        read_record(tmp_path / "ImperialValley_1940_ELC-180.txt")
