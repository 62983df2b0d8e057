"""Scene validation: every problem at once, each with its key path (DESIGN §4, §9)."""

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
