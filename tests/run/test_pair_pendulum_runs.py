"""Scenes with a set of record pairs on a building on friction pendulums (issue 31, docs/design.md
§10b): the building is integrated once per record, coupled in the plane, and every stored
quantity — floor peaks, plane slides, rocking in each component, RotD spectra, the bearing's
outputs and orbit — equals the public API on the same model; lead-rubber bearings too."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.plane_isolation import PlaneIsolatedMotion
from floorslide.building.poly_peaks import PolyComponent, poly_peaks
from floorslide.run.execute import execute
from floorslide.run.store import ResultFile
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene
from tests.conftest import ROOT

CATALOG = (ROOT / "data" / "records" / "pairs" / "index.csv").as_posix()
WIDTH, HEIGHT = 0.3, 1.5  # B/H = 0.2


def scene(isolator: str = 'model = "friction_pendulum", mu = 0.05, capacity = 0.3') -> str:
    return f"""
[scene]
name = "pairs on pendulums"

[[records]]
set = "pairs"
catalog = "{CATALOG}"
where = {{ rsn = ["1084"] }}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 2
period = 0.3

[[buildings]]
id = "fps"
kind = "isolated"
superstructure = "fixed"
period = 3.0
damping = 0.0
isolator = {{ {isolator} }}

[[contents]]
id = "box"
floors = [0, 2]
mu = [0.05, 0.1, 0.2]

[[contents]]
id = "cabinet"
floors = "roof"
mu = [0.3]
width = {WIDTH}
height = {HEIGHT}

[spectra]
floors = "roof"
damping = [0.05]
periods = [0.0, 0.2, 0.5, 1.0, 3.0]

[report]
history_record = "RSN1084_NORTHR_SCS"
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("pairs_fps")
    path = tmp / "s.toml"
    path.write_text(scene())
    sc = load_scene(path)
    p = plan(sc)
    out = tmp / "out.h5"
    execute(p, str(out), workers=1)
    (b,) = [b for b in sc.buildings if b.base == "fps"]
    (pair,) = fs.read_pairs(CATALOG, where={"rsn": "1084"})
    task = next(t for t in ResultFile(out).tasks() if t.meta["building"] == "fps")
    return task, b.build_plane(), pair, p


def test_the_plan_counts_blocks_in_the_plane_on_the_pendulum_building(run):
    _, _, _, p = run
    assert "rigid blocks sliding in the plane" in p.describe()


def test_the_bearing_outputs_are_the_coupled_responses(run):
    t, model, pair, _ = run
    ref = fs.building.plane_isolation.plane_isolator_response(model, pair.h1, pair.h2, pair.dt)
    m = t.meta
    assert m["isolator"] == "friction_pendulum"
    assert m["isolator_peak_displacement"] == ref.peak_displacement
    assert m["isolator_peak_direction"] == ref.peak_direction
    assert m["isolator_residual_h1"] == ref.residual[0]
    assert m["isolator_residual_h2"] == ref.residual[1]
    assert m["isolator_peak_force_ratio"] == ref.peak_force_ratio
    # Sylmar drives this 3 s pendulum far beyond the 0.3 m capacity: flagged
    assert ref.peak_displacement > 0.3 and m["isolator_capacity_exceeded"] == 1
    h = t.histories
    np.testing.assert_array_equal(h.isolator_displacement, ref.displacement[:, 0])
    np.testing.assert_array_equal(h.isolator_displacement_h2, ref.displacement[:, 1])
    np.testing.assert_array_equal(h.isolator_force_ratio_h2, ref.force_ratio[:, 1])


def test_floor_peaks_are_the_true_peaks_of_the_coupled_motion(run):
    t, model, pair, _ = run
    motion = PlaneIsolatedMotion(model, pair.h1, pair.h2, pair.dt)
    pk = poly_peaks(motion, [int(f) for f in t.floors])
    np.testing.assert_array_equal(t.pfa, pk.peak)
    np.testing.assert_array_equal(t.pfa_components, pk.components)
    # the stored floor accelerations at the samples never exceed the true peaks, and come
    # within the in-step excess of them
    h = t.histories
    at = np.hypot(h.floor_acceleration, h.floor_acceleration_h2).max(axis=1)
    rows = [list(t.floors).index(f) for f in h.floors]
    assert (at <= t.pfa[rows] * (1 + 1e-14)).all()
    assert (at >= 0.97 * t.pfa[rows]).all()


def test_stored_slides_equal_slide_plane_on_the_building(run):
    t, model, pair, _ = run
    seen = 0
    for c in t.contents:
        if c.content != "box":
            continue
        ref = fs.slide_plane(pair, None, c.mu_k, building=model, floor=c.floor)
        slid = c.modes == "slide"
        np.testing.assert_array_equal(c.peak_slide[slid], ref.peak_slide[slid])
        np.testing.assert_array_equal(c.peak_angle[slid], ref.peak_angle[slid])
        np.testing.assert_array_equal(c.residual_h1[slid], ref.residual[slid, 0])
        np.testing.assert_array_equal(c.peak_slide_h2[slid], ref.peak_slide_1d[slid, 1])
        assert (c.peak_slide[~slid] == 0).all() and (ref.peak_slide[~slid] == 0).all()
        seen += int(slid.sum())
    assert seen >= 3


def test_a_rocking_block_slides_and_rocks_in_each_component_of_the_coupled_motion(run):
    t, model, pair, _ = run
    (c,) = [c for c in t.contents if c.content == "cabinet"]
    assert c.modes[0] == "rock"
    motion = PlaneIsolatedMotion(model, pair.h1, pair.h2, pair.dt)
    ref = [fs.slide_rock(PolyComponent(motion, 2, d), None, WIDTH, HEIGHT, 0.3) for d in (0, 1)]
    over = [bool(r.overturned[0]) for r in ref]
    assert bool(c.overturned[0]) == any(over)
    if not any(over):
        k = 0 if ref[0].peak_ratio[0] >= ref[1].peak_ratio[0] else 1
        assert c.rock_peak_ratio[0] == ref[k].peak_ratio[0]
        assert c.peak_slide[0] == ref[k].peak_slide[0]
        assert c.rock_time[0] == ref[k].mode_time[0, 2] + ref[k].mode_time[0, 3]
    # a slide–rock block's slide, never NaN
    assert np.isfinite(c.peak_slide[0])


def test_roof_spectra_are_rotd_of_the_coupled_motion(run):
    t, model, pair, _ = run
    (s,) = t.spectra
    ref = fs.rotd_spectrum(pair, None, s.periods, list(s.damping), building=model, floor=2)
    np.testing.assert_array_equal(s.psa, ref.rotd50)
    np.testing.assert_array_equal(s.rotd100, ref.rotd100)
    np.testing.assert_array_equal(s.psa_h2, ref.h2.psa)
    # period 0 is the floor's own peak along the worst direction: the vector PFA
    assert s.rotd100[0, 0] == pytest.approx(t.pfa[list(t.floors).index(2)], rel=1e-12)


def test_the_report_draws_the_bearing_orbit(run, tmp_path):
    import matplotlib

    from floorslide.report.plots import _orbit_panel

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t, *_ = run
    fig, ax = plt.subplots()
    _orbit_panel(ax, t)
    labels = [line.get_label() for line in ax.get_lines()]
    assert any(lb.startswith("peak |u0|") for lb in labels)
    assert any("EXCEEDED" in lb for lb in labels)
    plt.close(fig)


def test_lead_rubber_under_pairs_runs_on_its_coupled_motion(tmp_path):
    """The same scene on lead-rubber bearings (circular yield surface): the bearing's outputs
    and the plane slides equal the API on the scene's model."""
    from floorslide.building.plane_isolation import plane_isolator_response

    path = tmp_path / "s.toml"
    path.write_text(scene('model = "bilinear", q_ratio = 0.05, yield_disp = 0.01'))
    sc = load_scene(path)
    p = plan(sc)
    assert not p.failures
    out = tmp_path / "out.h5"
    execute(p, str(out), workers=1)
    t = next(t for t in ResultFile(out).tasks() if t.meta["building"] == "fps")
    (b,) = [b for b in sc.buildings if b.base == "fps"]
    model = b.build_plane()
    (pair,) = fs.read_pairs(CATALOG, where={"rsn": "1084"})
    ref = plane_isolator_response(model, pair.h1, pair.h2, pair.dt)
    assert t.meta["isolator"] == "bilinear"
    assert t.meta["isolator_peak_displacement"] == ref.peak_displacement
    assert t.meta["isolator_peak_direction"] == ref.peak_direction
    for c in t.contents:
        if c.content == "box":
            api = fs.slide_plane(pair, None, c.mu_k, building=model, floor=c.floor)
            slid = c.modes == "slide"
            np.testing.assert_array_equal(c.peak_slide[slid], api.peak_slide[slid])


def test_flexible_equipment_in_the_plane_on_both_buildings(tmp_path):
    """A 2-DOF sliding oscillator on a set of pairs: on the fixed building (its linear motion)
    and on the pendulum building (its coupled motion) the stored peaks equal
    fs.slide_oscillator_plane on the scene's models, bit for bit; the history record keeps its
    path in the plane and the spring's deformation."""
    flex = """
[[contents]]
id = "pump"
floors = "roof"
mu = [0.05, 0.15]
model = "oscillator"
frequency = 4.0
damping = 0.03
mass_ratio = 0.5
"""
    path = tmp_path / "s.toml"
    path.write_text(scene().replace("[spectra]", flex + "\n[spectra]"))
    sc = load_scene(path)
    p = plan(sc)
    assert "2-DOF sliding oscillators in the plane" in p.describe()
    out = tmp_path / "out.h5"
    execute(p, str(out), workers=1)
    (pair,) = fs.read_pairs(CATALOG, where={"rsn": "1084"})
    seen = 0
    for t in ResultFile(out).tasks():
        (b,) = [b for b in sc.buildings if b.id == t.meta["building"]]
        (c,) = [c for c in t.contents if c.content == "pump"]
        model = b.build_plane()
        ref = fs.slide_oscillator_plane(pair, None, c.mu_k, 4.0, 0.03, 0.5, building=model,
                                        floor=2)  # fmt: skip
        np.testing.assert_array_equal(c.peak_slide, ref.peak_slide)
        np.testing.assert_array_equal(c.peak_deformation, ref.peak_deformation)
        np.testing.assert_array_equal(c.peak_top_accel, ref.peak_top_accel)
        np.testing.assert_array_equal(c.peak_angle, ref.peak_angle)
        assert ref.peak_slide.max() > 0.0
        h = t.histories
        if h is not None:
            u = h.plane["pump/floor_2"]
            assert u.shape == (2, pair.h1.size, 2)
            assert np.isfinite(h.deformation["pump/floor_2"]).all()
        seen += 1
    assert seen == 2
