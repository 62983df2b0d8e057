"""Scene validation: every problem at once, each with its key path (docs/design.md §4, §9)."""

from __future__ import annotations

import pytest

from floorslide.errors import SceneError
from floorslide.scene.schema import parse_scene
from tests.conftest import ROOT

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()

GOOD = f"""
[scene]
name = "small"

[[records]]
set = "bb"
catalog = "{CATALOG}"
where = {{ station_id = ["ELC-180", "TAF-021"] }}
scale_pga = [0.2, 0.4]

[processing]
detrend = "linear"

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 2
period = [0.2, 0.3]
damping = 0.02

[[buildings]]
id = "fb1"
kind = "fixed"
stories = 2
period = 0.3

[[buildings]]
id = "iso"
kind = "isolated"
superstructure = "fb1"
period = [2.0, 3.0]
damping = [0.05, 0.1]

[[contents]]
id = "cabinet"
floors = [1, 2]
mu = [0.1, 0.2]
mu_s = 0.25
width = 0.5
height = 1.5

[[contents]]
id = "rack"
model = "oscillator"
frequency = 8.0
mass_ratio = 0.5
mu = 0.2

[spectra]
floors = "all"
periods = {{ min = 0.05, max = 2.0, n = 5 }}
"""


def test_good_scene_and_sweeps():
    sc = parse_scene(GOOD, ROOT / "x.toml")
    assert sc.name == "small"
    ids = [b.id for b in sc.buildings]
    assert ids == [
        "fixed@T=0.2",
        "fixed@T=0.3",
        "fb1",
        "iso@T=2,xi=0.05",
        "iso@T=2,xi=0.1",
        "iso@T=3,xi=0.05",
        "iso@T=3,xi=0.1",
    ]
    iso = sc.buildings[-1]
    assert iso.super_period == 0.3 and iso.base_mass_ratio == 1.0
    assert sc.contents[0].mu_s == (0.25, 0.25)
    assert sc.contents[1].floors_of(2) == (2,)
    assert sc.spectra.floors_of(2) == (0, 1, 2) and len(sc.spectra.periods) == 5
    assert sc.records[0].scale_pga == (0.2, 0.4)


BAD = f"""
unknown_top = 1

[[records]]
set = "bb"
catalog = "{CATALOG}"
files = ["*.AT2"]

[[records]]
set = "bb"
files = ["nothing/here/*.AT2"]
units = "furlongs"

[processing]
highpass = 10.0
lowpass = 5.0
notch = 1

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 0
period = -0.2

[[buildings]]
id = "iso"
kind = "isolated"
superstructure = "nope"
period = 2.0

[[buildings]]
id = "odd"
kind = "tower"

[[contents]]
id = "cabinet"
floors = [5]
mu = [-0.1, 0.2]
width = 0.5

[[contents]]
id = "cabinet"
model = "oscillator"
mu = 0.1

[spectra]
periods = {{ min = 2.0, max = 1.0, n = 1 }}
damping = 1.5
"""


def test_every_problem_reported_with_its_key_path():
    with pytest.raises(SceneError) as err:
        parse_scene(BAD, ROOT / "bad.toml")
    problems = err.value.problems
    expected = [
        "unknown_top: unknown key",
        "records[0]: give exactly one of files",
        "records[1].set: duplicate set name",
        "records[1].files[0]: matches no file",
        "records[1].units:",
        "processing.notch: unknown key",
        "processing.lowpass: must be above highpass",
        "buildings[0].stories: must be ≥ 1",
        "buildings[0].period: must be > 0",
        "buildings[1].superstructure: must be the id of a fixed building",
        "buildings[2].kind: must be 'fixed' or 'isolated'",
        "contents[0].mu[0]: must be ≥ 0",
        "contents[0]: give both width and height",
        "contents[1].id: duplicate content id",
        "contents[1].frequency: missing",
        "spectra.periods.max: must be above min",
        "spectra.periods.n: must be ≥ 2",
        "spectra.damping: must be ≥ 0 and < 1",
    ]
    for e in expected:
        assert any(p.startswith(e) for p in problems), (e, problems)
    assert str(err.value).startswith(str(ROOT / "bad.toml"))


def test_not_toml_and_missing_sections():
    with pytest.raises(SceneError, match="not valid TOML"):
        parse_scene("[[records]\nset=", "a.toml")
    with pytest.raises(SceneError) as err:
        parse_scene("[scene]\nname='x'\n", "a.toml")
    assert any(p.startswith("records: missing") for p in err.value.problems)
    assert any(p.startswith("buildings: missing") for p in err.value.problems)


def test_user_strings_with_newlines_stay_on_one_line():
    """A catalog path or a key holding a newline (found by the scene fuzzer) is named with the
    newline escaped: the error stays one line."""
    text = GOOD.replace(f'catalog = "{CATALOG}"', 'catalog = "a/\\n"').replace(
        'name = "small"', 'name = "small"\n"odd\\tkey" = 1'
    )
    with pytest.raises(SceneError) as err:
        parse_scene(text, ROOT / "x\ny.toml")
    assert "\n" not in str(err.value) and "\t" not in str(err.value)
    problems = err.value.problems
    cat = "records[0].catalog: no such catalog file ("
    assert any(p.startswith(cat) and p.endswith("a/\\n)") for p in problems)
    assert any(p.startswith("scene.odd\\tkey: unknown key") for p in problems)
    assert all("\n" not in p for p in problems)


# --- issue 12, item 8: storey-by-storey buildings, no follow-on errors ----------------------

STOREYS = f"""
[[records]]
set = "bb"
catalog = "{CATALOG}"
where = {{ station_id = "ELC-180" }}

[[buildings]]
id = "given"
kind = "fixed"
mass = [2.0e5, 1.5e5, 1.0e5]
stiffness = [3.0e8, 2.5e8, 2.0e8]
damping = 0.03

[[buildings]]
id = "scaled"
kind = "fixed"
mass = [2.0e5, 1.5e5, 1.0e5]
period = [0.3, 0.5]
profile = "shear"

[[buildings]]
id = "iso"
kind = "isolated"
superstructure = "given"
period = 2.5

[[contents]]
id = "cabinet"
mu = 0.2
"""


def test_storey_masses_and_stiffnesses_are_accepted():
    from floorslide.building.model import ShearBuilding

    sc = parse_scene(STOREYS, ROOT / "x.toml")
    given, scaled3, scaled5, iso = sc.buildings
    direct = ShearBuilding([2.0e5, 1.5e5, 1.0e5], [3.0e8, 2.5e8, 2.0e8], 0.03)
    model = given.build()
    assert given.stories == 3 and given.period == pytest.approx(direct.periods[0], rel=1e-12)
    assert (model.stiffness_matrix == direct.stiffness_matrix).all()
    assert (model.mass == direct.mass).all()
    assert [scaled3.id, scaled5.id] == ["scaled@T=0.3", "scaled@T=0.5"]
    m = scaled5.build()
    assert m.periods[0] == pytest.approx(0.5, rel=1e-12) and list(m.mass) == [2e5, 1.5e5, 1e5]
    isolated = iso.build()
    assert isolated.superstructure.stiffness_matrix.tolist() == direct.stiffness_matrix.tolist()
    assert iso.stories == 3 and iso.super_period == given.period


@pytest.mark.parametrize(
    "body, problem",
    [
        ("mass = [1.0, 1.0]\nstiffness = [5.0, 5.0]\nperiod = 0.3", "buildings[0].stiffness: give"),
        ("mass = [1.0, 1.0, 1.0]\nstories = 2\nperiod = 0.3", "buildings[0].mass: 3 values"),
        ("mass = [1.0, 1.0, 1.0]\nstiffness = [5.0, 5.0]", "buildings[0].stiffness: one value"),
        ("mass = [1.0, 1.0]\nstiffness = [5.0, -1]", "buildings[0].stiffness[1]: must be > 0"),
        ("mass = []\nperiod = 0.3", "buildings[0].mass: must list one value per storey"),
        ("stiffness = [5.0, 5.0]\nprofile = 'shear'", "buildings[0].profile: only applies"),
        ("mass = [1.0, 2.0]", "buildings[0].period: missing"),
    ],
)
def test_storey_lists_bad_values(body, problem):
    text = STOREYS.replace(
        "mass = [2.0e5, 1.5e5, 1.0e5]\nstiffness = [3.0e8, 2.5e8, 2.0e8]\n", body + "\n", 1
    )
    with pytest.raises(SceneError) as err:
        parse_scene(text, ROOT / "x.toml")
    assert [p for p in err.value.problems if p.startswith(problem)], err.value.problems
    assert len(err.value.problems) == 1, err.value.problems


def test_one_bad_value_reports_only_itself():
    """An invalid value of a building is reported once: its id still names it for the
    isolated building on it and for [report] compare (no follow-on errors)."""
    text = GOOD.replace("period = 0.3\n", "period = 0.3\ndamping = 15\n", 1) + (
        '\n[report]\ncompare = ["iso:fb1", "iso@T=2,xi=0.05:fixed@T=0.2"]\n'
    )
    with pytest.raises(SceneError) as err:
        parse_scene(text, ROOT / "x.toml")
    assert err.value.problems == ["buildings[1].damping: must be ≥ 0 and < 1, got 15"]
    text = GOOD.replace("stories = 2\nperiod = [0.2, 0.3]", "stories = 2\nperiod = [0.2, -1]")
    with pytest.raises(SceneError) as err:
        parse_scene(text, ROOT / "x.toml")
    assert err.value.problems == ["buildings[0].period[1]: must be > 0, got -1"]


def test_a_bad_kind_reports_only_itself():
    """A typo in the superstructure's kind also reported the isolated building on it, and
    the comparisons naming it (issue 19 item 8)."""
    text = GOOD.replace('id = "fb1"\nkind = "fixed"', 'id = "fb1"\nkind = "fxed"') + (
        '\n[report]\ncompare = ["iso:fb1", "iso@T=2,xi=0.05:fb1"]\n'
    )
    with pytest.raises(SceneError) as err:
        parse_scene(text, ROOT / "x.toml")
    assert err.value.problems == ["buildings[1].kind: must be 'fixed' or 'isolated', got 'fxed'"]


# --- issue 12, item 6: every name in the scene is checked when it is validated --------------


@pytest.mark.parametrize(
    "report, problem",
    [
        ('history_record = "ImperialValley_1940_ELC-18"', "report.history_record: no record"),
        ('compare = ["iso@T=9,xi=0.1:fb1"]', "report.compare[0]: no building variant"),
        ('compare = ["tower:fb1"]', "report.compare[0]: unknown building 'tower'"),
        ('compare = ["fb1 : fb1"]', "report.compare[0]: 'fb1 : fb1' compares building 'fb1' with"),
        ("damping = 0.02", "report.damping: 0.02 is not among spectra.damping (0.05)"),
    ],
)
def test_report_names_are_checked(report, problem):
    with pytest.raises(SceneError) as err:
        parse_scene(GOOD + f"\n[report]\n{report}\n", ROOT / "x.toml")
    assert len(err.value.problems) == 1 and err.value.problems[0].startswith(problem)


def test_history_record_typo_suggests_the_record():
    with pytest.raises(SceneError, match="did you mean 'ImperialValley_1940_ELC-180'"):
        parse_scene(GOOD + '\n[report]\nhistory_record = "ImperialValley_1940_ELC180"\n', "x")
    ok = parse_scene(GOOD + '\n[report]\nhistory_record = "ImperialValley_1940_ELC-180"\n', "x")
    assert ok.report["history_record"] == "ImperialValley_1940_ELC-180"


def test_history_record_of_file_sets(tmp_path):
    (tmp_path / "recs").mkdir()
    for name in ("a.AT2", "b.AT2"):
        (tmp_path / "recs" / name).write_text("x")
    text = (
        '[[records]]\nset = "s"\nfiles = ["recs/*.AT2"]\n'
        '[[buildings]]\nid = "f"\nkind = "fixed"\nperiod = 0.2\n'
        '[[contents]]\nid = "c"\nmu = [0.1]\n[report]\nhistory_record = "{}"\n'
    )
    assert parse_scene(text.format("b"), tmp_path / "s.toml").report["history_record"] == "b"
    with pytest.raises(SceneError, match=r"report.history_record: no record 'c' .*2 records: a, b"):
        parse_scene(text.format("c"), tmp_path / "s.toml")


def test_where_naming_nothing_is_a_scene_error():
    text = GOOD.replace(
        'where = { station_id = ["ELC-180", "TAF-021"] }', 'where = { set = "brod-band" }'
    )
    with pytest.raises(SceneError) as err:
        parse_scene(text, ROOT / "x.toml")
    assert err.value.problems == [
        "records[0].where.set: no row has set = 'brod-band' (values: 'broad-band', 'pulse-like')"
    ]
    text = GOOD.replace('where = { station_id = ["ELC-180", "TAF-021"] }', 'where = { sett = "x" }')
    with pytest.raises(SceneError, match=r"records\[0\].where: no column 'sett'"):
        parse_scene(text, ROOT / "x.toml")


def test_dry_run_catches_a_history_record_typo(tmp_path, monkeypatch, capsys):
    import sys

    from floorslide.cli import main

    path = tmp_path / "s.toml"
    path.write_text(GOOD + '\n[report]\nhistory_record = "nope"\n')
    monkeypatch.setattr(sys, "argv", ["floorslide", "run", str(path), "--dry-run"])
    with pytest.raises(SystemExit) as exit_:
        main()
    err = capsys.readouterr().err
    assert exit_.value.code == 2 and err.count("\n") == 1
    assert "report.history_record: no record 'nope'" in err


# --- ids: names of groups in the result file, checked when the scene is loaded ----------

ODD_IDS = [
    ("cabinet/rack", "must not contain '/'"),
    (".", "must not be '.'"),
    ("..", "must not be '..'"),
    ("a\\u0000b", "control or invisible characters"),
    ("a\\u0007b", "control or invisible characters"),
    ("a\\u200bb", "control or invisible characters"),
    (" cabinet", "must not begin or end with a space"),
    ("cab@1", "must not contain '@'"),
    ("a:b", "must not contain ':'"),
    ("x" * 65, "at most 64 characters"),
]


@pytest.mark.parametrize(("value", "problem"), ODD_IDS)
@pytest.mark.parametrize(
    ("key", "where"),
    [
        ('id = "cabinet"', "contents[0].id"),
        ('id = "fb1"', "buildings[1].id"),
        ('set = "bb"', "records[0].set"),
    ],
)
def test_ids_that_cannot_name_a_result_group_are_refused_at_load(key, where, value, problem):
    """An id with '/' ran into a result file the reports called corrupt; '.', '..', NUL and
    control characters gave integrity alarms: every id is checked once, by key path, saying
    what an id may be."""
    name = key.split(" = ")[0]
    text = GOOD.replace(key, f'{name} = "{value}"', 1)
    text = text.replace('superstructure = "fb1"', f'superstructure = "{value}"')
    with pytest.raises(SceneError) as err:
        parse_scene(text, ROOT / "x.toml")
    mine = [p for p in err.value.problems if p.startswith(f"{where}: ")]
    assert mine, err.value.problems
    assert problem in mine[0]
    assert "letters, digits, spaces and punctuation other than '/', ':' and '@'" in mine[0]
    if where == "buildings[1].id":  # the isolated building on it is not reported again
        assert not any(p.startswith("buildings[2]") for p in err.value.problems)


def test_ids_in_any_script_with_punctuation_are_valid():
    text = (
        GOOD.replace('id = "cabinet"', 'id = "Schrank Ä-1 (0.6 m), #2"', 1)
        .replace('set = "bb"', 'set = "機器 set.v2"', 1)
        .replace('id = "fb1"', 'id = "fb 1+2"', 1)
        .replace('superstructure = "fb1"', 'superstructure = "fb 1+2"', 1)
    )
    sc = parse_scene(text, ROOT / "x.toml")
    assert sc.contents[0].id == "Schrank Ä-1 (0.6 m), #2"
    assert sc.records[0].set == "機器 set.v2"


def test_building_variant_ids_are_valid_result_names():
    """Sweeps name variants ``iso@T=2,xi=0.05``: generated names obey the rule of a name in
    the result file (the base id's rule without the '@' it adds)."""
    from floorslide.scene.schema import name_problem

    text = GOOD.replace("period = [2.0, 3.0]", "period = [1e-05, 2.5e6]", 1).replace(
        'superstructure = "fb1"',
        'superstructure = "fb1"\nbase_mass_ratio = [0.5, 1.25]\n'
        'isolator = { model = "friction_pendulum", mu = [0.0, 0.04] }',
        1,
    )
    sc = parse_scene(text, ROOT / "x.toml")
    variants = [b.id for b in sc.buildings]
    assert "iso@mb=0.5,T=1e-05,xi=0.05,mu=0" in variants
    for vid in variants:
        assert name_problem(vid) is None, vid
