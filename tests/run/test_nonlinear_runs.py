"""Scenes with buildings on nonlinear isolation (issue 14): the `isolator` table, its sweeps
and checks, and runs whose results equal the Python API's."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.nonlinear import isolator_response
from floorslide.errors import SceneError
from floorslide.report import design_tables
from floorslide.run.execute import execute
from floorslide.run.store import ResultFile
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene, parse_scene
from tests.conftest import ROOT

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()


def scene(isolator: str, contents: str = "") -> str:
    return f"""
[scene]
name = "nonlinear"

[[records]]
set = "s"
catalog = "{CATALOG}"
where = {{ station_id = ["ELC-180", "TAF-021"] }}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 2
period = 0.3
damping = 0.03

[[buildings]]
id = "iso"
kind = "isolated"
superstructure = "fixed"
period = 3.0
isolator = {isolator}

[[contents]]
id = "box"
floors = "roof"
mu = [0.03, 0.1]
{contents}

[spectra]
floors = [0, 2]
periods = [0.0, 0.2, 1.0]
damping = [0.05]
"""


def test_isolator_tables_sweep_and_name_variants():
    sc = parse_scene(scene('{ model = "friction_pendulum", mu = [0.04, 0.06], mu_s = 0.08 }'))
    fps = [b for b in sc.buildings if b.base == "iso"]
    assert [b.id for b in fps] == ["iso@mu=0.04", "iso@mu=0.06"]
    assert all(b.isolator_model == "friction_pendulum" and b.damping == 0.0 for b in fps)
    model = fps[1].build()
    assert isinstance(model, fs.NonlinearIsolatedBuilding)
    assert model.constants["mu"] == 0.06 and model.constants["mu_s"] == 0.08
    assert model.isolator.T == pytest.approx(3.0)
    sc = parse_scene(scene('{ model = "bilinear", q_ratio = [0.05, 0.08], yield_disp = 0.02 }'))
    assert [b.id for b in sc.buildings if b.base == "iso"] == ["iso@Q=0.05", "iso@Q=0.08"]
    linear = parse_scene(scene('{ model = "linear" }'))
    assert isinstance(linear.buildings[-1].build(), fs.IsolatedBuilding)


@pytest.mark.parametrize(
    ("isolator", "contents", "message"),
    [
        ('{ model = "lead" }', "", "iso.*model: must be one of"),
        ('{ model = "friction_pendulum" }', "", r"isolator\.mu: missing"),
        ('{ model = "friction_pendulum", mu = -0.1 }', "", r"isolator\.mu: must be ≥ 0"),
        ('{ model = "bilinear", q_ratio = 0.05 }', "", "give one of yield_disp and alpha"),
        ('{ model = "bilinear", q_ratio = 0.05, alpha = 1.5, yield_disp = 0.01 }', "", "one of"),
        ('{ model = "bilinear", q_ratio = 0.0, yield_disp = 0.01 }', "", r"q_ratio: must be > 0"),
        (
            '{ model = "friction_pendulum", mu = 0.05, radius = 2 }',
            "",
            "give one of radius and period",
        ),
        (
            '{ model = "friction_pendulum", mu = 0.05 }',
            "vertical = true",
            r"contents\[0\]\.vertical: vertical shaking on a building on friction pendulums",
        ),
    ],
)
def test_bad_isolators_are_refused_by_key_path(isolator, contents, message):
    with pytest.raises(SceneError, match=message):
        parse_scene(scene(isolator, contents))


def test_a_run_on_a_friction_pendulum_equals_the_api(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(scene('{ model = "friction_pendulum", mu = 0.05 }'))
    p = plan(load_scene(path))
    out = tmp_path / "out.h5"
    execute(p, str(out), workers=1)
    tasks = {(t.meta["record"], t.meta["building"]): t for t in ResultFile(out).tasks()}
    rec = next(r for r in p.records if r.record == "ImperialValley_1940_ELC-180")
    t = tasks[(rec.record, "iso")]
    model = p.scene.buildings[-1].build()
    direct = isolator_response(model, rec.acc, rec.dt, floors=[0, 2])
    np.testing.assert_array_equal(t.pfa, direct.pfa)
    assert t.meta["isolator"] == "friction_pendulum"
    assert t.meta["isolator_peak_displacement"] == direct.peak_displacement
    assert t.meta["isolator_residual_displacement"] == direct.residual_displacement
    (c,) = t.contents
    s = fs.slide(rec.acc, rec.dt, [0.03, 0.1], building=model, floor=2)
    integrated = c.skipped == ""
    np.testing.assert_allclose(c.peak_slide, s.peak_slide, rtol=1e-12, atol=1e-15)
    assert integrated or np.all(c.peak_slide == 0)
    sp = fs.response_spectrum(rec.acc, rec.dt, [0.0, 0.2, 1.0], [0.05], building=model, floor=2)
    roof = next(x for x in t.spectra if x.floor == 2)
    np.testing.assert_array_equal(roof.psa, sp.psa)
    # the history record keeps the floors' accelerations and the slides
    assert t.histories is not None and t.histories.floor_acceleration.shape[0] == 2
    tables = design_tables(out)
    assert {r["building"] for r in tables["pfa"]} == {"fixed", "iso"}


def test_a_run_with_flexible_equipment_on_a_bilinear_layer_equals_the_api(tmp_path):
    path = tmp_path / "s.toml"
    flex = 'model = "oscillator"\nfrequency = 5.0\ndamping = 0.02\nmass_ratio = 0.5'
    path.write_text(scene('{ model = "bilinear", q_ratio = 0.05, yield_disp = 0.02 }', flex))
    p = plan(load_scene(path))
    out = tmp_path / "out.h5"
    execute(p, str(out), workers=1)
    rec = p.records[0]
    t = next(
        t for t in ResultFile(out).tasks()
        if t.meta["record"] == rec.record and t.meta["building"] == "iso"
    )  # fmt: skip
    (c,) = t.contents
    model = p.scene.buildings[-1].build()
    r = fs.slide_oscillator(rec.acc, rec.dt, [0.03, 0.1], 5.0, 0.02, 0.5, building=model, floor=2)
    done = np.isfinite(c.peak_deformation)
    assert done.any()
    np.testing.assert_array_equal(c.peak_slide[done], r.peak_slide[done])
    np.testing.assert_array_equal(c.peak_deformation[done], r.peak_deformation[done])
    # the history record (the first record) keeps the 2-DOF equipment's histories too, as on
    # linear buildings
    assert t.histories is not None
    rh = fs.slide_oscillator(
        rec.acc, rec.dt, [0.03, 0.1], 5.0, 0.02, 0.5, building=model, floor=2,
        histories=True,
    )  # fmt: skip
    key = "box/floor_2"
    rows = np.isfinite(t.histories.deformation[key][:, 0])
    assert rows.any()
    np.testing.assert_array_equal(t.histories.slides[key][rows], rh.u[rows])
    np.testing.assert_array_equal(t.histories.deformation[key][rows], rh.z[rows])
    np.testing.assert_array_equal(t.histories.top_accel[key][rows], rh.top_accel[rows])


def test_a_vertical_content_on_a_lead_rubber_layer_reads_the_record_sets_vertical(tmp_path):
    """A record set of three-component files (``vertical_component``): a content with
    ``vertical = true`` on a lead-rubber building slides with the vertical (the layer does not
    feel it; the blocks' friction does), as fs.slide(vertical=) — the vertical component is
    read, not dropped (it was set to None after being picked, and the planner failed)."""
    from obspy import Stream, Trace

    from tests.conftest import load_slammer

    a, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    av = 0.5 * a[::-1].copy()  # a stand-in vertical: the record reversed
    st = Stream()
    for ch, x in (("HNE", a[:1500]), ("HNZ", av[:1500])):
        st += Trace(np.asarray(x, dtype=np.float64), header={"delta": dt, "channel": ch})
    f = tmp_path / "elc.mseed"
    st.write(str(f), format="MSEED")
    text = scene('{ model = "bilinear", q_ratio = 0.05, yield_disp = 0.02 }', "vertical = true")
    text = text.replace(
        f'catalog = "{CATALOG}"\nwhere = {{ station_id = ["ELC-180", "TAF-021"] }}',
        f'files = ["{f.as_posix()}"]\nunits = "m/s**2"\ncomponent = "E"\nvertical_component = "Z"',
    )
    path = tmp_path / "v.toml"
    path.write_text(text)
    p = plan(load_scene(path))
    assert not p.failures and p.records[0].vertical is not None
    rec = p.records[0]
    np.testing.assert_array_equal(rec.vertical, av[:1500])
    out = tmp_path / "v.h5"
    execute(p, str(out), workers=1)
    t = next(t for t in ResultFile(out).tasks() if t.meta["building"] == "iso")
    (c,) = t.contents
    model = p.scene.buildings[-1].build()
    ref = fs.slide(rec.acc, rec.dt, [0.03, 0.1], building=model, floor=2, vertical=rec.vertical)
    np.testing.assert_array_equal(c.peak_slide, ref.peak_slide)
    plain = fs.slide(rec.acc, rec.dt, [0.03, 0.1], building=model, floor=2)
    assert np.abs(plain.peak_slide - ref.peak_slide).max() > 1e-4
