"""Scenes that used to run and give wrong results with exit 0 (issue 19, items 6, 7, 8): a
`where` that selects nothing or names a typo, a malformed catalog, the same record twice in a
set, spectra too large for memory, a byte-order mark, an isolation period that does not
isolate. Each is a key-path problem (exit 2) caught by ``--dry-run``, or a warning it shows."""

from __future__ import annotations

import shutil
import sys

import pytest

from floorslide.errors import SceneError
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene, parse_scene
from tests.conftest import SLAMMER
from tests.scene.test_schema import CATALOG, GOOD

WHERE = 'where = { station_id = ["ELC-180", "TAF-021"] }'

SMALL = """
[[records]]
set = "s"
{records}

[[buildings]]
id = "fb"
kind = "fixed"
period = 0.4
stories = 2

[[contents]]
id = "c"
mu = [0.1]
"""


def _problems(text: str, path) -> list[str]:
    with pytest.raises(SceneError) as err:
        parse_scene(text, path)
    return err.value.problems


def _dry_run(tmp_path, monkeypatch, capsys, text: str):
    from floorslide.cli import main

    path = tmp_path / "scene.toml"
    path.write_text(text)
    monkeypatch.setattr(sys, "argv", ["floorslide", "run", str(path), "--dry-run"])
    with pytest.raises(SystemExit) as exit_:
        main()
    out = capsys.readouterr()
    return exit_.value.code, out.out, out.err


# ------------------------------------------------------------------------------ where


def test_a_where_value_that_matches_no_row_is_named(tmp_path):
    """In a list, a typo used to be dropped silently: the set had one record fewer."""
    text = GOOD.replace(WHERE, 'where = { station_id = ["ELC-180", "TAF021"] }')
    problems = _problems(text, tmp_path / "x.toml")
    assert len(problems) == 1
    assert problems[0].startswith(
        "records[0].where.station_id[1]: no row has station_id = 'TAF021' (values: 'BOL-000',"
    )


def test_where_values_that_together_select_nothing(tmp_path):
    text = GOOD.replace(WHERE, 'where = { set = "pulse-like", station_id = "ELC-180" }')
    assert _problems(text, tmp_path / "x.toml") == [
        f"records[0].where: selects no row of {CATALOG}"
    ]


def test_where_value_of_the_wrong_type(tmp_path):
    text = GOOD.replace(WHERE, "where = { set = { a = 1 } }")
    assert _problems(text, tmp_path / "x.toml") == [
        "records[0].where.set: must be a value or a list of values to match, got {'a': 1}"
    ]


@pytest.mark.parametrize(
    ("where", "problem"),
    [
        ('where = { set = "nothing" }', "records[0].where.set: no row has set = 'nothing'"),
        ('where = { sett = "x" }', "records[0].where: no column 'sett' in the catalog"),
    ],
)
def test_dry_run_refuses_a_where_that_selects_nothing(
    tmp_path, monkeypatch, capsys, where, problem
):
    """Such a scene ran 0 tasks and wrote an empty file (exit 0), or printed the problem in the
    plan on stdout (exit 3)."""
    code, out, err = _dry_run(tmp_path, monkeypatch, capsys, GOOD.replace(WHERE, where))
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and problem in err and err.startswith("floorslide: error: ")


# ----------------------------------------------------------------------------- catalogs


def test_a_malformed_catalog_is_a_scene_error(tmp_path, monkeypatch, capsys):
    """It was an 'unreadable record' inside the plan on stdout, exit 3."""
    (tmp_path / "flat.csv").write_text("name,step,unit\na.txt,0.01,g\n")
    code, out, err = _dry_run(
        tmp_path, monkeypatch, capsys, SMALL.format(records='catalog = "flat.csv"')
    )
    assert code == 2 and out == ""
    assert "records[0].catalog: " in err and "not a record catalog" in err
    assert "line 1 has: name, step, unit" in err


def test_a_catalog_listing_a_record_twice_is_a_scene_error(tmp_path):
    shutil.copy(SLAMMER / "Kobe_1995_KAK-000.txt", tmp_path / "a.txt")
    (tmp_path / "cat.csv").write_text("file,dt,units\na.txt,0.01,g\na.txt,0.01,g\n")
    (problem,) = _problems(SMALL.format(records='catalog = "cat.csv"'), tmp_path / "s.toml")
    assert (
        problem.startswith("records[0].catalog: ") and "lines 2 and 3 both list 'a.txt'" in problem
    )


# ----------------------------------------------------------- the same record twice in a set


def test_overlapping_globs_name_each_file_once(tmp_path):
    for name in ("a.txt", "b.txt"):
        shutil.copy(SLAMMER / "Kobe_1995_KAK-000.txt", tmp_path / name)
    (tmp_path / "index.csv").write_text("file,dt,units\na.txt,0.01,g\nb.txt,0.01,g\n")
    text = SMALL.format(records='files = ["*.txt", "a.txt", "./b.txt"]')
    sc = parse_scene(text, tmp_path / "s.toml")
    assert [p.split("/")[-1] for p in sc.records[0].files] == ["a.txt", "b.txt"]
    p = plan(sc, evaluate=False)
    assert [r.record for r in p.records] == ["a", "b"] and len(p.tasks) == 2


def test_two_records_with_one_name_in_a_set(tmp_path):
    """Two files named x.* would be one record 'x' in the tables, counted twice."""
    for folder in ("one", "two"):
        (tmp_path / folder).mkdir()
        shutil.copy(SLAMMER / "Kobe_1995_KAK-000.txt", tmp_path / folder / "x.txt")
    (problem,) = _problems(SMALL.format(records='files = ["*/x.txt"]'), tmp_path / "s.toml")
    assert problem.startswith("records[0].files: two records named 'x' in one set (")
    (tmp_path / "cat.csv").write_text("file,dt,units\none/x.txt,0.01,g\ntwo/x.txt,0.01,g\n")
    (problem,) = _problems(SMALL.format(records='catalog = "cat.csv"'), tmp_path / "s.toml")
    assert problem.startswith("records[0].catalog: two records named 'x' in one set (")


def test_the_same_record_in_two_sets_is_legitimate(tmp_path):
    text = GOOD + f'\n[[records]]\nset = "again"\ncatalog = "{CATALOG}"\n{WHERE}\n'
    sc = parse_scene(text, tmp_path / "x.toml")
    assert [r.set for r in sc.records] == ["bb", "again"]


# -------------------------------------------------------------------------------- spectra


def test_spectra_limits(tmp_path):
    base = SMALL.format(records=f'catalog = "{CATALOG}"\n{WHERE}')
    problems = _problems(base + "[spectra]\nperiods = [0.1, 2e4]\n", tmp_path / "s.toml")
    assert problems == ["spectra.periods: 20000 s is above 10000 s, beyond any structure"]
    problems = _problems(
        base + "[spectra]\nperiods = { min = 0.01, max = 5, n = 10000 }\n"
        "damping = [0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.09, 0.1, 0.2]\n",
        tmp_path / "s.toml",
    )
    assert problems == [
        "spectra.damping: 10000 periods x 11 damping ratios = 110000 oscillators per floor: "
        "at most 100000"
    ]


def test_spectra_periods_below_dt_over_1000_are_refused_by_the_planner(tmp_path):
    """1e-9 s at dt = 0.01 s asked for 1.3e8 sub-steps per step: a MemoryError mid-run."""
    text = SMALL.format(records=f'catalog = "{CATALOG}"\n{WHERE}')
    sc = parse_scene(text + "[spectra]\nperiods = [0, 1e-9, 0.5]\n", tmp_path / "s.toml")
    with pytest.raises(SceneError) as err:
        plan(sc, evaluate=False)
    message = str(err.value)
    assert "spectra.periods: 1e-09 s is below dt/1000 = 1e-05 s of record" in message
    assert "(dt = 0.01 s)" in message and err.value.exit_code == 2
    ok = parse_scene(text + "[spectra]\nperiods = [0, 1e-5, 0.5]\n", tmp_path / "s.toml")
    assert len(plan(ok, evaluate=False).tasks) == 2


# ---------------------------------------------------------------------- byte-order mark


def test_scene_file_with_a_byte_order_mark(tmp_path):
    """Notepad's BOM made the first line 'not valid TOML: Invalid statement'."""
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + GOOD.encode())
    assert load_scene(path).name == "small"


# ------------------------------------------------------------------ isolation period


def test_isolation_period_not_above_the_fixed_base_period_warns(tmp_path):
    """Accepted without a word; physically possible, so a warning, shown by the dry run."""
    text = GOOD.replace("period = [2.0, 3.0]", "period = [0.3, 2.0, 0.2]")
    sc = parse_scene(text, tmp_path / "x.toml")
    assert sc.warnings == tuple(
        f"buildings[2].period[{j}]: isolation period {T} s is not above the fixed-base period "
        "0.3 s of the superstructure 'fb1': the isolators would not isolate (almost surely a "
        "mistake)"
        for j, T in ((0, "0.3"), (2, "0.2"))
    )
    assert parse_scene(GOOD, tmp_path / "x.toml").warnings == ()
    described = plan(sc, evaluate=False).describe()
    assert "warnings (valid, but almost surely a mistake):" in described
    assert f"  {sc.warnings[1]}" in described.splitlines()


def test_a_run_says_the_isolation_does_not_isolate(tmp_path, monkeypatch, capsys):
    """`floorslide run` (not only --dry-run) shows the warning, one line on stderr."""
    from floorslide.cli import main

    records = f'catalog = "{CATALOG}"\nwhere = {{ station_id = "ELC-180" }}'
    text = SMALL.format(records=records) + (
        '\n[[buildings]]\nid = "iso"\nkind = "isolated"\nsuperstructure = "fb"\nperiod = 0.3\n'
    )
    path = tmp_path / "scene.toml"
    path.write_text(text)
    argv = ["floorslide", "run", str(path), "-o", str(tmp_path / "out.h5"), "--workers", "1"]
    monkeypatch.setattr(sys, "argv", argv)
    main()  # returns: exit 0
    assert capsys.readouterr().err == (
        f"floorslide: warning: {path}: buildings[1].period: isolation period 0.3 s is not above "
        "the fixed-base period 0.4 s of the superstructure 'fb': the isolators would not "
        "isolate (almost surely a mistake)\n"
    )


def test_a_failed_record_is_stored_as_a_short_description(tmp_path):
    """The plan (stored in the result file) kept the raw text of a damaged file's line: a
    failure is one line of at most FAILURE_CHARS characters, quoting at most an excerpt."""
    from floorslide.scene.planner import FAILURE_CHARS

    shutil.copy(SLAMMER / "Kobe_1995_KAK-000.txt", tmp_path / "good.txt")
    (tmp_path / "index.csv").write_text("file,dt,units\ngood.txt,0.01,g\n")
    junk = "<script>" + "A" * 5000
    (tmp_path / "bad.AT2").write_text(f"PEER\nx, y, z, 1\nUNITS OF G\nNPTS= ,DT= {junk} SEC\n1\n")
    scene = parse_scene(SMALL.format(records='files = ["*.txt", "*.AT2"]'), tmp_path / "s.toml")
    p = plan(scene, evaluate=False)
    assert [r.record for r in p.records] == ["good"]
    (failure,) = p.failures
    assert "gives no NPTS" in failure and "A" * 100 not in failure
    assert len(failure) <= FAILURE_CHARS and "\n" not in failure
    assert p.summary()["record_failures"] == [failure]
