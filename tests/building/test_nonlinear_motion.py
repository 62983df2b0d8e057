"""One exact motion from a building on nonlinear isolation: integrated once, read by every
consumer.

The building records the segments of its exact motion; rigid blocks, 2-DOF oscillators, rocking
blocks and floor spectra read them. Checked here: a motion streamed in chunks gives every
consumer the same bits as one kept whole; a floor of one motion gives the same bits as each
consumer's own call with ``building=``; ``floor_motions`` and the true PFA work on such a
building and, with a frictionless pendulum, equal the linear isolated building's (an independent
path: the linear building's exact recurrence); a study's task integrates the building once per
record; the combinations not built yet are refused in one line.
"""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
import floorslide.building.nonlinear_motion as nm
from floorslide.building import _nonlinear_kernel as kern
from tests.conftest import SLAMMER, G


@pytest.fixture(scope="module")
def kobe() -> np.ndarray:
    return np.loadtxt(SLAMMER / "Kobe_1995_KAK-000.txt") * G


def building(isolator, stories=3):
    sup = fs.ShearBuilding.from_period(stories=stories, period=0.5, damping=0.03)
    return fs.NonlinearIsolatedBuilding(sup, 1.0, isolator)


ISOLATORS = [
    pytest.param(fs.FrictionPendulum(mu=0.04, mu_s=0.07, period=2.5), id="pendulum"),
    pytest.param(fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02), id="bilinear"),
]


def _consumers(fm):
    """Every consumer's result on the floor motion `fm`, as flat arrays."""
    s = fs.slide(fm, mu_k=[0.03, 0.1], mu_s=[0.05, 0.12], histories=True)
    o = fs.slide_oscillator(fm, mu=[0.05, 0.2], frequency=4.0, mass_ratio=0.5, histories=True)
    r = fs.rock(fm, width=0.3, height=1.2, histories=True)
    sp = fs.response_spectrum(fm, periods=[0.0, 0.1, 0.5, 2.0], damping=[0.02, 0.05])
    return {
        "slide": np.concatenate([s.peak_slide, s.residual_slide, s.u.ravel()]),
        "oscillator": np.concatenate([o.peak_slide, o.peak_top_accel, o.u.ravel(), o.z.ravel()]),
        "rock": np.concatenate([r.peak_ratio, r.theta.ravel()]),
        "spectrum": np.concatenate([sp.psa.ravel(), sp.sd.ravel(), sp.sv.ravel()]),
    }


@pytest.mark.parametrize("isolator", ISOLATORS)
def test_a_streamed_motion_gives_every_consumer_the_same_bits(kobe, isolator, monkeypatch):
    b = building(isolator)
    whole = b.motion(kobe, 0.01, floors=[0, 3])
    monkeypatch.setattr(nm, "CHUNK_BYTES", 20_000)
    streamed = b.motion(kobe, 0.01, floors=[0, 3], max_bytes=0)
    assert whole.kept_whole and not streamed.kept_whole and len(streamed._checkpoints) > 20
    assert whole.response.event_times.size > 20  # the isolator does change branch
    bare = b.motion(kobe, 0.01, floors=[0, 3], keep_segments=False)  # integrated again per pass
    np.testing.assert_array_equal(whole.states, streamed.states)
    for floor in (0, 3):
        a = _consumers(whole.floor(floor))
        for other in (streamed, bare):
            c = _consumers(other.floor(floor))
            for key in a:
                np.testing.assert_array_equal(a[key], c[key], err_msg=key)


def test_one_motion_equals_each_consumers_own_call(kobe):
    """A floor of one motion, or `building=` and `floor=` (each call integrating the building
    itself): the same bits."""
    b = building(fs.FrictionPendulum(mu=0.05, period=3.0))
    a = 1.2 * kobe[:2500]
    fm = b.motion(a, 0.01).floor(2)
    s1 = fs.slide(fm, mu_k=[0.05, 0.1])
    s2 = fs.slide(a, 0.01, [0.05, 0.1], building=b, floor=2)
    np.testing.assert_array_equal(s1.peak_slide, s2.peak_slide)
    r1 = fs.rock(fm, width=0.4, height=1.6)
    r2 = fs.rock(a, 0.01, width=0.4, height=1.6, building=b, floor=2)
    assert r1.peak_ratio[0] == r2.peak_ratio[0] and r1.impacts[0] == r2.impacts[0]
    p1 = fs.response_spectrum(fm, periods=[0.2, 1.0])
    p2 = fs.response_spectrum(a, 0.01, [0.2, 1.0], building=b, floor=2)
    np.testing.assert_array_equal(p1.psa, p2.psa)
    o1 = fs.slide_oscillator(fm, mu=[0.1], frequency=5.0)
    o2 = fs.slide_oscillator(a, 0.01, [0.1], 5.0, building=b, floor=2)
    np.testing.assert_array_equal(o1.peak_slide, o2.peak_slide)
    assert fm.peak()[0] == b.motion(a, 0.01).peaks([2])[0][0]


def test_floor_motions_on_nonlinear_isolation_equal_the_linear_building_without_friction(kobe):
    """``floor_motions`` (every output kind) and ``peak_floor_acceleration`` on a building on
    friction pendulums: with mu = 0 the layer is linear, and they equal the linear isolated
    building's (its own exact recurrence, a path that shares nothing with the segments)."""
    a = kobe[:1500]
    b = building(fs.FrictionPendulum(mu=0.0, period=3.0))
    lin = fs.IsolatedBuilding(b.superstructure, 1.0, 3.0, 0.0)
    kinds = ["acceleration", "displacement", "velocity", "drift", "isolator"]
    got = fs.floor_motions(b, a, 0.01, floors=[1, 3], output=kinds)
    ref = fs.floor_motions(lin, a, 0.01, floors=[1, 3], output=kinds)
    for kind in kinds:
        scale = np.abs(ref[kind]).max()
        assert scale > 0
        # measured on this record: 5e-13 (acceleration) to 3e-15 (isolator) of the scale
        assert np.abs(got[kind] - ref[kind]).max() <= 1e-11 * scale, kind
    pk = fs.peak_floor_acceleration(b, a, 0.01, floors=[0, 3])
    pl = fs.peak_floor_acceleration(lin, a, 0.01, floors=[0, 3])
    np.testing.assert_allclose(pk.peak, pl.peak, rtol=1e-11)
    assert fs.floor_motions(b, a, 0.01, floors=3).shape == (1, a.size)


def test_refused_in_one_line(kobe):
    b = building(fs.FrictionPendulum(mu=0.05, period=3.0))
    a = kobe[:300]
    cases = [
        (lambda: fs.floor_motions(b, a, 0.01, method="newmark"), "method"),
        (lambda: fs.floor_motions(b, a, 0.01, floors=[7]), "floor 7 does not exist"),
        (
            lambda: fs.slide(
                a, 0.01, 0.1, building=b, floor=1, vertical=0.2 * a, direction="positive"
            ),
            "one-way sliding with vertical",
        ),
        (lambda: fs.slide(a, 0.01, 0.1, building=b), "floor is required"),
        (lambda: b.motion(a, 0.01, floors=[1]).floor(2), "not among the floors"),
        (lambda: fs.slide(b.motion(a, 0.01).floor(1), 0.01, 0.1, building=b), "FloorMotion"),
        (lambda: fs.peak_floor_acceleration(b, a, 0.01, output="drift"), "output"),
        (lambda: b.motion(a, 0.01, floors=[1], oscillator=(1, 6.0, 0.05)).floor(1), "oscillator"),
    ]
    for call, words in cases:
        with pytest.raises(fs.FloorslideError, match=words) as err:
            call()
        assert "\n" not in str(err.value)


def test_a_task_integrates_the_building_once(monkeypatch):
    """A study's task on friction pendulums with rigid blocks, flexible equipment, rocking blocks
    and two spectrum floors: the building is integrated once for the record (one kernel call:
    its segments fit in memory), and every consumer reads that motion."""
    from floorslide.run.task import run_task
    from floorslide.scene.planner import plan
    from floorslide.scene.schema import parse_scene
    from tests.conftest import ROOT

    catalog = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()
    text = f"""
[scene]
name = "once"

[[records]]
set = "s"
catalog = "{catalog}"
where = {{ station_id = "ELC-180" }}

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
isolator = {{ model = "friction_pendulum", mu = 0.05 }}

[[contents]]
id = "box"
floors = "roof"
mu = [0.03, 0.1]
width = 0.5
height = 1.0

[[contents]]
id = "tank"
floors = [1]
model = "oscillator"
frequency = 5.0
mu = [0.05]

[spectra]
floors = [0, 2]
periods = [0.0, 0.2, 1.0]
damping = [0.05]
"""
    tasks = [t for t in plan(parse_scene(text)).tasks if t.building.isolator_model != "linear"]
    tasks = [t for t in tasks if t.building.base == "iso"]
    assert len(tasks) == 1
    calls = []
    run = kern.nonlinear_run

    def counted(*args):
        calls.append(args[17])  # k0
        return run(*args)

    monkeypatch.setattr(kern, "nonlinear_run", counted)
    monkeypatch.setattr(nm.kern, "nonlinear_run", counted)
    result = run_task(tasks[0], force=True)
    assert calls == [0]
    assert {c.content for c in result.contents} == {"box", "tank"}
    assert [s.floor for s in result.spectra] == [0, 2]
    assert result.meta["isolator_peak_displacement"] > 0
