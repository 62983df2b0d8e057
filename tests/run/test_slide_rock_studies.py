"""Studies simulate objects that rock as slide–rock blocks (docs/design.md §10c "In a study",
§10g): every friction pair under which a content with width and height rocks (Shenton's
``rock`` or ``slide-rock``) is one :func:`floorslide.slide_rock` block on the floor the
sliders read — its stored results equal a direct call bit for bit, an object at ``mu_s = B/H``
is simulated once (no bounds), and files written before ``slide_rock_time`` was stored still
read."""

from __future__ import annotations

import math

import numpy as np
import pytest

import floorslide as fs
import floorslide.run.task as task_module
from floorslide.report.records import record_table
from floorslide.report.tables import design_tables
from floorslide.run.execute import execute
from floorslide.run.store import ResultFile
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene
from tests.conftest import ROOT

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()
WIDTH, HEIGHT = 0.4, 1.6  # B/H = 0.25
MU = [0.1, 0.25, 0.3, 0.6]  # slides; mu_s = B/H (Shenton's slide-rock); rocks; rocks
MU_S = [0.1, 0.25, 0.5, 0.6]

SCENE = f"""
[scene]
name = "slide-rock"

[[records]]
set = "s"
catalog = "{CATALOG}"
where = {{ station_id = ["PET-090"] }}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.3
damping = 0.03

[[buildings]]
id = "lin"
kind = "isolated"
superstructure = "fixed"
period = 2.0
damping = 0.1

[[contents]]
id = "cabinet"
floors = "roof"
mu = {MU}
mu_s = {MU_S}
width = {WIDTH}
height = {HEIGHT}

[report]
history_record = "CapeMendocino_1992_PET-090"
"""


def _run(tmp, name="out.h5"):
    path = tmp / "s.toml"
    path.write_text(SCENE)
    p = plan(load_scene(path))
    out = tmp / name
    execute(p, str(out), workers=1)
    return p, out


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    p, out = _run(tmp_path_factory.mktemp("sliderock"))
    return p, ResultFile(out), out


def _direct(p, t, histories=False):
    rec = next(r for r in p.records if r.record == t.meta["record"])
    model = next(b for b in p.scene.buildings if b.id == t.meta["building"]).build()
    return fs.slide_rock(
        rec.acc, rec.dt, WIDTH, HEIGHT, np.array(MU), mu_s=np.array(MU_S),
        building=model, floor=1, histories=histories,
    )  # fmt: skip


def test_a_rocking_content_equals_slide_rock_bit_for_bit_on_linear_buildings(run):
    p, rf, _ = run
    seen = set()
    for t in rf.tasks():
        (c,) = t.contents
        direct = _direct(p, t)
        for i, mode in enumerate(c.modes):
            if mode not in ("rock", "slide-rock"):
                continue
            seen.add(t.meta["building"])
            assert c.rock_peak_ratio[i] == direct.peak_ratio[i]
            assert c.peak_slide[i] == direct.peak_slide[i]
            assert c.residual_slide[i] == direct.residual_slide[i]
            assert c.rock_time[i] == direct.mode_time[i, 2] + direct.mode_time[i, 3]
            assert c.slide_rock_time[i] == direct.mode_time[i, 3]
            frac = (direct.mode_time[i, 1] + direct.mode_time[i, 3]) / direct.duration
            assert c.slide_fraction[i] == frac
            assert c.rock_impacts[i] == direct.impacts[i]
            assert c.rock_significant_impacts[i] == direct.significant_impacts[i]
            assert c.outcomes[i] == direct.mode[i]
            assert np.isfinite(c.peak_slide[i])  # never NaN any more
    assert seen == {"fixed", "lin"}


def test_slide_rock_at_mu_s_equal_b_over_h_is_simulated_once_without_bounds(run):
    p, rf, _ = run
    modes = set()
    for t in rf.tasks():
        (c,) = t.contents
        assert c.modes[0] == "slide" and c.slide_rock_time[0] == 0
        modes.add(str(c.modes[1]))
        direct = _direct(p, t)
        # one slide–rock block: its slide and its rotation are those of one simulation, and
        # what it did is the simulation's mode (not "slide-rock" by Shenton's label)
        assert c.peak_slide[1] == direct.peak_slide[1]
        assert c.rock_peak_ratio[1] == direct.peak_ratio[1]
        assert c.outcomes[1] == direct.mode[1]
        assert "bound" not in c.skipped
    assert "slide-rock" in modes  # Shenton's mode at mu_s = B/H, once the floor exceeds g·B/H


def test_the_history_record_keeps_theta_over_alpha_and_the_slide(run):
    p, rf, _ = run
    kept = 0
    for t in rf.tasks():
        if t.histories is None:
            continue
        (c,) = t.contents
        key = "cabinet/floor_1"
        if key not in t.histories.rocking:
            continue
        direct = _direct(p, t, histories=True)
        rocks = [i for i, m in enumerate(c.modes) if m in ("rock", "slide-rock")]
        ratios = [np.array_equal(t.histories.rocking[key], direct.theta[i] / direct.alpha[i],
                                 equal_nan=True) for i in rocks]  # fmt: skip
        assert any(ratios)
        for row, mu in enumerate(t.histories.mu_k[key]):
            i = MU.index(float(mu))
            if i in rocks:
                np.testing.assert_array_equal(t.histories.slides[key][row], direct.slide[i])
        kept += 1
    assert kept > 0


def test_the_tables_show_the_slide_rock_results(run):
    _, _, out = run
    df = record_table(out)
    rocked = df[df["mode"].isin(["rock", "slide-rock"])]
    assert len(rocked) and rocked.peak_slide.notna().all()
    assert rocked.slide_rock_time_s.notna().all() and rocked.rock_significant_impacts.notna().all()
    assert (rocked.outcome == "rock").all()
    rows = design_tables(out)["rocking"]
    assert {(r["mu_k"], r["mu_s"]) for r in rows} == {(0.25, 0.25), (0.3, 0.5), (0.6, 0.6)}
    for r in rows:
        sel = rocked[(rocked.mu_k == r["mu_k"]) & (rocked.mu_s == r["mu_s"])]
        sel = sel[sel.building == r["building"]]
        assert r["slide_rock_time_median"] == np.median(sel.slide_rock_time_s)
        assert r["n_slide_rock"] == int((sel.observed_outcome == "slide-rock").sum())
    notes = " ".join(design_tables(out).notes)
    assert "bound" not in notes


def test_a_file_written_before_slide_rock_time_was_stored_still_reads(tmp_path, monkeypatch):
    real = task_module.rocking_results

    def older(*args, **kw):
        out = real(*args, **kw)
        out.pop("slide_rock_time", None)  # as a run before slide–rock did: no dataset
        return out

    monkeypatch.setattr(task_module, "rocking_results", older)
    _, out = _run(tmp_path, "old.h5")
    monkeypatch.undo()
    for t in ResultFile(out).tasks():
        (c,) = t.contents
        assert c.rock_peak_ratio is not None
        assert c.slide_rock_time.shape == c.rock_peak_ratio.shape
        assert np.isnan(c.slide_rock_time).all()
    df = record_table(out)
    assert df.slide_rock_time_s.isna().all()
    for r in design_tables(out)["rocking"]:
        assert math.isnan(r["slide_rock_time_median"])
