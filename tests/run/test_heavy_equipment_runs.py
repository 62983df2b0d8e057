"""Heavy equipment in a scene (``floor_mass_ratio``, ``coupled``; docs/design.md §10f): coupled
contents run with the building (fs.slide_coupled) and store the floor's PFA with the block;
decoupled heavy contents are warned about above the decoupling-error table's 5 % ratio; what is
not modelled is refused by key path."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.errors import SceneError
from floorslide.run.execute import execute
from floorslide.run.store import ResultFile
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene, parse_scene
from tests.conftest import ROOT

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()


def scene(content: str = "floor_mass_ratio = 0.1", extra: str = "") -> str:
    return f"""
[scene]
name = "heavy"

[[records]]
set = "s"
catalog = "{CATALOG}"
where = {{ station_id = ["ELC-180", "PET-090"] }}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 3
period = 0.5
damping = 0.03

[[buildings]]
id = "iso"
kind = "isolated"
superstructure = "fixed"
period = 2.5
damping = 0.1
{extra}

[[contents]]
id = "chiller"
floors = "roof"
mu = [0.1, 0.2]
{content}
"""


def test_coupled_heavy_equipment_equals_the_api(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(scene())
    sc = load_scene(path)
    p = plan(sc)
    assert "heavy equipment coupled with its floor integrated" in p.describe()
    out = tmp_path / "out.h5"
    execute(p, str(out), workers=1)
    seen = 0
    for t in ResultFile(out).tasks():
        rec = next(r for r in p.records if r.record == t.meta["record"])
        (b,) = [b for b in sc.buildings if b.id == t.meta["building"]]
        model = b.build()
        m = 0.1 * float(model.mass[list(model.dof_floors).index(3)])
        ref = fs.slide_coupled(rec.acc, rec.dt, [0.1, 0.2], mass=m, building=model, floor=3)
        (c,) = t.contents
        np.testing.assert_array_equal(c.peak_slide, ref.peak_slide)
        np.testing.assert_array_equal(c.coupled_pfa, ref.pfa)
        np.testing.assert_array_equal(c.slip_phases, ref.slip_phases)
        assert c.skipped == ""
        # the block acts back: its slide is not the decoupled one
        plain = fs.slide(rec.acc, rec.dt, [0.1, 0.2], building=model, floor=3)
        assert np.abs(plain.peak_slide - ref.peak_slide).max() > 1e-5
        seen += 1
    assert seen == 4


@pytest.mark.parametrize(
    "isolator",
    [
        'isolator = { model = "friction_pendulum", mu = 0.05 }',
        'isolator = { model = "bilinear", q_ratio = 0.06, yield_disp = 0.02 }',
    ],
)
def test_coupled_heavy_equipment_on_nonlinear_isolation_equals_the_api(tmp_path, isolator):
    """A coupled content on a building on friction pendulums or lead-rubber bearings runs with
    the building (fs.slide_coupled on the nonlinear building), bit for bit."""
    path = tmp_path / "s.toml"
    path.write_text(scene(extra=isolator))
    sc = load_scene(path)
    p = plan(sc)
    out = tmp_path / "out.h5"
    execute(p, str(out), workers=1)
    seen = 0
    for t in ResultFile(out).tasks():
        if t.meta["building"] != "iso":
            continue
        rec = next(r for r in p.records if r.record == t.meta["record"])
        (b,) = [b for b in sc.buildings if b.id == "iso"]
        model = b.build()
        assert isinstance(model, fs.NonlinearIsolatedBuilding)
        m = 0.1 * float(model.mass[model.dof_of(3)])
        ref = fs.slide_coupled(rec.acc, rec.dt, [0.1, 0.2], mass=m, building=model, floor=3)
        (c,) = t.contents
        np.testing.assert_array_equal(c.peak_slide, ref.peak_slide)
        np.testing.assert_array_equal(c.coupled_pfa, ref.pfa)
        seen += 1
    assert seen == 2


def test_a_decoupled_heavy_block_is_warned_about():
    sc = parse_scene(scene("floor_mass_ratio = 0.2\ncoupled = false"), ROOT / "s.toml")
    (w,) = [w for w in sc.warnings if "floor_mass_ratio" in w]
    assert "contents[0].floor_mass_ratio: 0.2 of the floor's mass, run decoupled" in w
    light = parse_scene(scene("floor_mass_ratio = 0.01\ncoupled = false"), ROOT / "s.toml")
    assert not [w for w in light.warnings if "floor_mass_ratio" in w]


@pytest.mark.parametrize(
    ("content", "extra", "message"),
    [
        (
            "floor_mass_ratio = 1.5",
            "",
            r"contents\[0\]\.floor_mass_ratio: must be > 0 and < 1, got 1.5",
        ),
        (
            "floor_mass_ratio = 0",
            "",
            r"contents\[0\]\.floor_mass_ratio: must be > 0 and < 1, got 0",
        ),
        ("coupled = false", "", r"contents\[0\]\.coupled: needs floor_mass_ratio"),
        ("floor_mass_ratio = 0.1\nvertical = true", "", r"contents\[0\]\.vertical: heavy"),
        (
            'floor_mass_ratio = 0.1\nmodel = "oscillator"\nfrequency = 5.0',
            "",
            r"contents\[0\]\.floor_mass_ratio: applies to a rigid block",
        ),
    ],
)
def test_what_is_not_modelled_is_refused_by_key_path(content, extra, message):
    with pytest.raises(SceneError, match=message):
        parse_scene(scene(content, extra), ROOT / "s.toml")


@pytest.mark.parametrize(
    ("content", "key"),
    [
        ('model = "oscillator"\nfrequency = 5.0\nvertical = true', "vertical"),
        ('model = "oscillator"\nfrequency = 5.0\ndirection = "positive"', "direction"),
    ],
)
def test_flexible_equipment_refuses_what_it_does_not_model(content, key):
    """Vertical shaking and one-way sliding are not modelled for the 2-DOF oscillator: refused
    by key path (a run ignored them before)."""
    with pytest.raises(SceneError, match=rf"contents\[0\]\.{key}: not modelled for the 2-DOF"):
        parse_scene(scene(content), ROOT / "s.toml")


def test_the_tables_say_what_heavy_equipment_did(tmp_path):
    """The design tables' notes: coupled heavy equipment's PFA, and a warning for a decoupled
    heavy content above the decoupling-error table's ratio."""
    from floorslide.report import design_tables

    cases = (
        ("floor_mass_ratio = 0.1", "heavy equipment (floor_mass_ratio, coupled)"),
        ("floor_mass_ratio = 0.2\ncoupled = false", "warning: content 'chiller' is run decoupled"),
    )
    for i, (content, words) in enumerate(cases):
        path = tmp_path / "s.toml"
        path.write_text(scene(content).replace('["ELC-180", "PET-090"]', '["ELC-180"]'))
        out = tmp_path / f"out{i}.h5"
        execute(plan(load_scene(path)), str(out), workers=1)
        notes = design_tables(out).notes
        assert any(words in n for n in notes), notes
