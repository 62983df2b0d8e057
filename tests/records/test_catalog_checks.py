"""Catalogs and sidecars that used to give wrong results with exit 0 (issue 19, items 6, 8):
duplicate rows counted twice, a --units/--dt contradicting the sidecar applied silently, and
the message for a catalog with the wrong columns."""

from __future__ import annotations

import shutil
import subprocess
import sys

import numpy as np
import pytest

import floorslide as fs
from floorslide.errors import RecordError, UnitsError
from floorslide.records.catalog import load_catalog
from tests.conftest import SLAMMER
from tests.records.conftest import ELC_FILE

ELC_LINE = 20  # the line of ELC-180 in data/records/slammer/index.csv


@pytest.fixture
def folder(tmp_path):
    """The bundled El Centro record with the bundled catalog as its sidecar."""
    shutil.copy(SLAMMER / "index.csv", tmp_path / "index.csv")
    shutil.copy(SLAMMER / ELC_FILE, tmp_path / ELC_FILE)
    return tmp_path


# ------------------------------------------------------------------------- duplicates


def test_duplicate_rows_are_refused(tmp_path):
    """The same record listed twice was read twice: n_records = 3 for 2 records."""
    for name in ("a.txt", "b.txt"):
        shutil.copy(SLAMMER / ELC_FILE, tmp_path / name)
    catalog = tmp_path / "cat.csv"
    catalog.write_text("file,dt,units,set\na.txt,0.01,g,x\nb.txt,0.01,g,x\n./a.txt,0.01,g,y\n")
    for call in (lambda: load_catalog(catalog), lambda: fs.read_catalog(catalog, {"set": "y"})):
        with pytest.raises(RecordError) as info:
            call()
        message = str(info.value)
        assert message.startswith(f"{catalog}: lines 2 and 4 both list './a.txt'")
        assert "\n" not in message and info.value.exit_code == 3
    catalog.write_text("file_h1,file_h2,dt,units\na.txt,a.txt,0.01,g\n")
    with pytest.raises(RecordError, match=r"line 2 lists 'a.txt' twice \(file_h1, file_h2\)"):
        load_catalog(catalog, components=True)


def test_components_of_one_file_are_not_duplicates(tmp_path):
    catalog = tmp_path / "cat.csv"
    catalog.write_text("file,dt,units,component\nst.v2,,,N\nst.v2,,,E\n")
    assert [e.component for e in load_catalog(catalog)] == ["N", "E"]
    catalog.write_text("file,dt,units,component\nst.v2,,,N\nst.v2,,,n\n")
    with pytest.raises(RecordError, match=r"lines 2 and 3 both list 'st.v2' \(component n\)"):
        load_catalog(catalog)


def test_inspect_refuses_a_catalog_with_duplicates(tmp_path):
    shutil.copy(SLAMMER / ELC_FILE, tmp_path / "a.txt")
    (tmp_path / "cat.csv").write_text("file,dt,units\na.txt,0.01,g\na.txt,0.01,g\n")
    out = subprocess.run(
        [sys.executable, "-m", "floorslide.cli", "inspect", str(tmp_path / "cat.csv")],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 3 and out.stdout == ""
    assert out.stderr.count("\n") == 1 and "lines 2 and 3 both list 'a.txt'" in out.stderr


# -------------------------------------------------------------------------- sidecars


def test_units_or_dt_contradicting_the_sidecar_are_errors(folder):
    """--units gal on a file whose index.csv says g gave a PGA 981 times too small."""
    path = folder / ELC_FILE
    with pytest.raises(UnitsError) as info:
        fs.read_record(path, units="gal")
    assert str(info.value) == (
        f"{path}: units 'gal' were given but index.csv line {ELC_LINE} says 'g'"
    )
    with pytest.raises(RecordError, match=rf"dt = 0.02 s was given but index.csv line {ELC_LINE}"):
        fs.read_record(path, dt=0.02)
    with pytest.raises(RecordError, match=r"dt = 0\.02 s was given"):
        fs.read_record(path, dt=0.02, units="g")  # also when both are given
    agreed = fs.read_record(path, dt=0.01, units="g")[0]
    np.testing.assert_array_equal(agreed.data, fs.read_record(path)[0].data)
    assert agreed.stats.catalog.station_id == "ELC-180"


def test_file_header_contradicting_the_sidecar_is_an_error(folder):
    path = folder / ELC_FILE
    path.write_text("# units: gal\n" + path.read_text())
    with pytest.raises(
        UnitsError, match=rf"units 'gal' are in the file but index.csv line {ELC_LINE}"
    ):
        fs.read_record(path)
    path.write_text("# dt: 0.02\n" + (SLAMMER / ELC_FILE).read_text())
    with pytest.raises(RecordError, match=r"dt = 0.02 s is in the file but index.csv"):
        fs.read_record(path)


def test_inspect_units_contradicting_the_sidecar(folder):
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "floorslide.cli",
            "inspect",
            "--units",
            "gal",
            str(folder / ELC_FILE),
        ],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 3 and out.stdout == ""
    assert out.stderr.strip().endswith(
        f"units 'gal' were given but index.csv line {ELC_LINE} says 'g'"
    )


def test_a_sidecar_that_cannot_be_used_is_named(folder):
    index = folder / "index.csv"
    lines = index.read_text().splitlines()
    index.write_text("\n".join([*lines, lines[ELC_LINE - 1]]) + "\n")
    with pytest.raises(RecordError) as info:
        fs.read_record(folder / ELC_FILE)
    message = str(info.value)
    assert "its dt or units are not given, and the index.csv next to it cannot be used" in message
    assert f"lines {ELC_LINE} and {len(lines) + 1} both list" in message


def test_a_catalog_of_components_serves_as_sidecar(tmp_path):
    shutil.copy(SLAMMER / ELC_FILE, tmp_path / "h1.txt")
    (tmp_path / "index.csv").write_text("file_h1,file_h2,dt,units\nh1.txt,,0.01,g\n")
    assert fs.read_record(tmp_path / "h1.txt")[0].stats.delta == 0.01


# ------------------------------------------------------------------- wrong columns


def test_wrong_columns_say_what_is_required_and_found(tmp_path):
    catalog = tmp_path / "flat.csv"
    catalog.write_text("\ufeffName, Step,unit\na.txt,0.01,g\n", encoding="utf-8")
    with pytest.raises(RecordError) as info:
        fs.read_catalog(catalog)
    assert str(info.value) == (
        f"{catalog}: not a record catalog: no column 'file', 'dt', 'units'; a catalog needs "
        "the columns file, dt, units (or file_h1, file_h2 ..., dt, units); line 1 has: name, "
        "step, unit"
    )


def test_a_relative_path_that_leaves_the_catalog_folder_is_refused(tmp_path):
    """A catalog's '../../etc/passwd' was read as a record (its text quoted in the errors and
    the result file). Relative paths stay under the catalog's folder; absolute ones are the
    user's own, used as given."""
    from floorslide.errors import SceneError
    from floorslide.scene.schema import parse_scene

    folder = tmp_path / "cat"
    (folder / "sub").mkdir(parents=True)
    (folder / "sub" / "rec.txt").write_text("0.1\n0.2\n-0.1\n")
    (tmp_path / "outside.txt").write_text("0.1\n0.2\n-0.1\n")
    catalog = folder / "index.csv"
    catalog.write_text("file,dt,units\nsub/../sub/rec.txt,0.01,g\n../outside.txt,0.01,g\n")
    with pytest.raises(RecordError) as info:
        fs.read_catalog(catalog)
    assert str(info.value) == (
        f"{catalog}:3: file '../outside.txt' leaves the catalog's folder; a relative path is "
        "read inside it: move the catalog up to a folder that holds its records, or give an "
        "absolute path"
    )
    scene = (
        '[[records]]\nset = "s"\ncatalog = "cat/index.csv"\n[[buildings]]\nid = "f"\n'
        'kind = "fixed"\nperiod = 0.2\n[[contents]]\nid = "c"\nmu = [0.1]\n'
    )
    with pytest.raises(SceneError, match=r"records\[0\]\.catalog: .*index.csv:3: file "):
        parse_scene(scene, tmp_path / "s.toml")  # caught by the dry run
    catalog.write_text(f"file,dt,units\nsub/rec.txt,0.01,g\n{tmp_path / 'outside.txt'},0.01,g\n")
    assert [tr.stats.npts for tr in fs.read_catalog(catalog)] == [3, 3]
