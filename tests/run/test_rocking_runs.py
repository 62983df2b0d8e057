"""Runs with contents that rock (issue 15): a content with width and height that rocks
(Shenton) is simulated as a slide–rock block (``fs.slide_rock``, once per friction pair) on
every building — fixed-base, linearly isolated, on nonlinear isolation — its results stored per
friction pair, equal to ``fs.slide_rock``, its slides the block's, and its θ/α history kept for
the history record."""

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
WIDTH, HEIGHT = 0.3, 1.5  # B/H = 0.2: rocks where mu_s > 0.2 and the PFA exceeds 0.2 g


def scene(contents: str = "") -> str:
    return f"""
[scene]
name = "rocking"

[[records]]
set = "s"
catalog = "{CATALOG}"
where = {{ station_id = ["ELC-180", "PET-090"] }}

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

[[buildings]]
id = "fps"
kind = "isolated"
superstructure = "fixed"
period = 3.0
isolator = {{ model = "friction_pendulum", mu = 0.05 }}

[[contents]]
id = "cabinet"
floors = "roof"
mu = [0.1, 0.3, 0.5]
width = {WIDTH}
height = {HEIGHT}
{contents}
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("rocking")
    path = tmp / "s.toml"
    path.write_text(scene("restitution = 0.9"))
    p = plan(load_scene(path))
    out = tmp / "out.h5"
    execute(p, str(out), workers=1)
    return p, ResultFile(out)


def test_rockers_are_simulated_and_equal_the_api(run):
    p, rf = run
    buildings = {b.id: b.build() for b in p.scene.buildings}
    seen_rock = seen_over = 0
    for t in rf.tasks():
        rec = next(r for r in p.records if r.record == t.meta["record"])
        (c,) = t.contents
        assert c.rock_peak_ratio is not None and c.outcomes is not None
        mu = np.asarray(c.mu_k)
        direct = fs.slide_rock(
            rec.acc, rec.dt, WIDTH, HEIGHT, mu, mu_s=np.asarray(c.mu_s), restitution=0.9,
            building=buildings[t.meta["building"]], floor=1,
        )  # fmt: skip
        for i, mode in enumerate(c.modes):
            if mode == "slide":  # mu 0.1 < B/H: it slides, no rocking numbers
                assert np.isnan(c.rock_peak_ratio[i]) and c.rock_impacts[i] == -1
                assert c.outcomes[i] == "slide" and c.slide_rock_time[i] == 0
                continue
            if mode == "rest":
                assert c.rock_peak_ratio[i] == 0 and c.overturned[i] == 0
                assert c.outcomes[i] == "rest"
                continue
            assert mode == "rock"
            seen_rock += 1
            # its slide is the slide–rock block's, never NaN nor a "0 slide" by assumption
            assert c.peak_slide[i] == direct.peak_slide[i]
            assert c.residual_slide[i] == direct.residual_slide[i]
            assert c.rock_peak_ratio[i] == direct.peak_ratio[i]
            assert c.rock_impacts[i] == direct.impacts[i]
            assert c.rock_significant_impacts[i] == direct.significant_impacts[i]
            assert c.rock_time[i] == direct.mode_time[i, 2] + direct.mode_time[i, 3]
            assert c.slide_rock_time[i] == direct.mode_time[i, 3]
            assert c.overturned[i] == float(direct.overturned[i])
            assert np.array_equal(c.overturn_time[i], direct.overturn_time[i], equal_nan=True)
            assert c.outcomes[i] == direct.mode[i]
            seen_over += c.outcomes[i] == "overturn"
    assert seen_rock > 0 and seen_over > 0  # Petrolia (PGA 0.66 g) overturns it somewhere


def test_the_history_record_keeps_theta_over_alpha(run):
    p, rf = run
    buildings = {b.id: b.build() for b in p.scene.buildings}
    kept = 0
    for t in rf.tasks():
        if t.histories is None:
            continue
        rec = next(r for r in p.records if r.record == t.meta["record"])
        (c,) = t.contents
        key = "cabinet/floor_1"
        if not any(m == "rock" for m in c.modes):
            assert key not in t.histories.rocking
            continue
        rocks = [i for i, m in enumerate(c.modes) if m == "rock"]
        direct = fs.slide_rock(
            rec.acc, rec.dt, WIDTH, HEIGHT, np.asarray(c.mu_k)[rocks],
            mu_s=np.asarray(c.mu_s)[rocks], restitution=0.9,
            building=buildings[t.meta["building"]], floor=1, histories=True,
        )  # fmt: skip
        # the rotation of the pair that overturned first, else of the largest peak rotation
        if direct.overturned.any():
            j = int(np.argmin(np.where(direct.overturned, direct.overturn_time, np.inf)))
        else:
            j = int(np.argmax(direct.peak_ratio))
        np.testing.assert_array_equal(t.histories.rocking[key], direct.theta[j] / direct.alpha[j])
        # the slide history of a friction value under which it rocks is its block's U
        for row, mu in enumerate(t.histories.mu_k[key]):
            if mu in np.asarray(c.mu_k)[rocks]:
                k = list(np.asarray(c.mu_k)[rocks]).index(mu)
                np.testing.assert_array_equal(t.histories.slides[key][row], direct.slide[k])
        kept += 1
    assert kept > 0


@pytest.mark.parametrize(
    ("contents", "message"),
    [
        ("restitution = 1.5", r"contents\[0\]\.restitution: must be"),
        ('rocking = "rk4"', r"contents\[0\]\.rocking: must be 'exact' or 'nonlinear'"),
    ],
)
def test_bad_rocking_keys_are_refused_by_key_path(contents, message):
    with pytest.raises(SceneError, match=message):
        parse_scene(scene(contents))


def test_rocking_keys_need_a_geometry():
    text = scene().replace(f"width = {WIDTH}\nheight = {HEIGHT}\n", "restitution = 0.8\n")
    with pytest.raises(SceneError, match=r"contents\[0\]\.restitution: applies to a rocking"):
        parse_scene(text)
