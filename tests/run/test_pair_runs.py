"""Scenes with a set of record pairs (issue 16, docs/design.md §10d): blocks slide in the plane
on buildings with a model per direction; what a run stores equals the API; the plane table and
figures; scene keys checked by key path."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.directions import plane_motions, plane_peak
from floorslide.errors import SceneError
from floorslide.run.execute import execute
from floorslide.run.store import ResultFile
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene, parse_scene
from tests.conftest import ROOT

CATALOG = (ROOT / "data" / "records" / "pairs" / "index.csv").as_posix()
RSN = ["1084", "879", "511"]
WIDTH, HEIGHT = 0.4, 1.6  # B/H = 0.25


def scene(extra_building: str = "", contents: str = "", records: str = "") -> str:
    return f"""
[scene]
name = "pairs"

[[records]]
set = "pairs"
catalog = "{CATALOG}"
where = {{ rsn = {RSN} }}
{records}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 2
period = 0.3
period_h2 = 0.5
damping_h2 = 0.03
{extra_building}

[[buildings]]
id = "iso"
kind = "isolated"
superstructure = "fixed"
period = 2.5
damping = 0.1

[[contents]]
id = "box"
floors = [0, 2]
mu = [0.1, 0.2]
{contents}

[[contents]]
id = "cabinet"
floors = "roof"
mu = [0.15, 0.3]
width = {WIDTH}
height = {HEIGHT}

[spectra]
floors = "roof"
damping = [0.05]
periods = [0.0, 0.1, 0.3, 1.0, 3.0]
broadening = 0.15

[report]
history_record = "RSN1084_NORTHR_SCS"
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("pairs")
    path = tmp / "s.toml"
    path.write_text(scene())
    p = plan(load_scene(path))
    out = tmp / "out.h5"
    execute(p, str(out), workers=1)
    return p, ResultFile(out), tmp


def _pair(rsn: str):
    (p,) = fs.read_pairs(CATALOG, where={"rsn": rsn})
    return p


def _model(bid: str):
    sup = (fs.ShearBuilding.from_period(2, 0.3), fs.ShearBuilding.from_period(2, 0.5, 0.03))
    if bid == "fixed":
        return fs.BuildingPair(*sup)
    return fs.BuildingPair(*(fs.IsolatedBuilding(s, 1.0, 2.5, 0.1) for s in sup))


def test_the_plan_reads_pairs_and_counts_planar_blocks(run):
    p, _, _ = run
    assert len(p.records) == 3 and all(r.is_pair for r in p.records)
    assert p.records[0].record == "RSN1084_NORTHR_SCS"
    assert p.records[0].components == ("52", "142")
    text = p.describe()
    assert "rigid blocks sliding in the plane" in text


def test_stored_slides_equal_slide_plane(run):
    _, rf, _ = run
    seen = 0
    for t in rf.tasks():
        pair = _pair(_rsn(t.meta["record"]))
        model = _model(t.meta["building"])
        assert int(t.meta["components"]) == 2
        assert t.meta["component_names"] == ",".join(pair.names)
        for i, f in enumerate(t.floors):
            peak, _ = plane_peak(*plane_motions(model, pair.h1, pair.h2, pair.dt, int(f)))
            assert t.pfa[i] == pytest.approx(peak, rel=1e-12)
            assert t.pfa_components[i, 0] <= peak * (1 + 1e-12)
        for c in t.contents:
            if c.content != "box":
                continue
            ref = fs.slide_plane(pair, None, c.mu_k, building=model, floor=c.floor)
            slid = c.modes == "slide"
            np.testing.assert_allclose(c.peak_slide[slid], ref.peak_slide[slid], rtol=1e-12)
            np.testing.assert_allclose(c.peak_angle[slid], ref.peak_angle[slid], rtol=1e-12)
            np.testing.assert_allclose(c.residual_h1[slid], ref.residual[slid, 0], rtol=1e-12)
            np.testing.assert_allclose(
                c.residual_slide[slid], np.hypot(*ref.residual[slid].T), rtol=1e-12
            )
            np.testing.assert_allclose(c.peak_slide_h1[slid], ref.peak_slide_1d[slid, 0],
                                       rtol=1e-12)  # fmt: skip
            np.testing.assert_allclose(c.ratio_2d_1d[slid], ref.ratio_2d_1d[slid], rtol=1e-12)
            # a block that rests (the vector PFA never reaches mu g): exactly no slide
            assert (c.peak_slide[~slid] == 0).all()
            assert (ref.peak_slide[~slid] == 0).all()
            seen += int(slid.sum())
    assert seen >= 10


def _rsn(record: str) -> str:
    return record.split("_")[0].removeprefix("RSN")


def test_a_rocking_block_slides_and_rocks_in_each_component_and_keeps_the_worse(run):
    _, rf, _ = run
    checked = 0
    for t in rf.tasks():
        pair = _pair(_rsn(t.meta["record"]))
        model = _model(t.meta["building"])
        for c in t.contents:
            if c.content != "cabinet" or c.rock_peak_ratio is None:
                continue
            for i, m in enumerate(c.modes):
                if m != "rock":
                    continue
                fms = plane_motions(model, pair.h1, pair.h2, pair.dt, c.floor)
                ref = [
                    fs.slide_rock(fm, None, WIDTH, HEIGHT, c.mu_k[i], mu_s=c.mu_s[i]) for fm in fms
                ]
                over = [bool(r.overturned[0]) for r in ref]
                assert bool(c.overturned[i]) == any(over)
                if not any(over):
                    k = 0 if ref[0].peak_ratio[0] >= ref[1].peak_ratio[0] else 1
                    assert c.rock_peak_ratio[i] == ref[k].peak_ratio[0]
                    # the kept block's slide along its component; each component's beside
                    assert c.peak_slide[i] == ref[k].peak_slide[0]
                    assert c.residual_slide[i] == abs(ref[k].residual_slide[0])
                    assert c.slide_rock_time[i] == ref[k].mode_time[0, 3]
                    assert c.outcomes[i] == ref[k].mode[0]
                assert c.peak_slide_h1[i] == ref[0].peak_slide[0]
                assert c.peak_slide_h2[i] == ref[1].peak_slide[0]
                assert np.isnan(c.peak_angle[i]) and np.isnan(c.ratio_2d_1d[i])
                checked += 1
    assert checked >= 1


def test_floor_spectra_of_a_pair_are_rotd50_beside_rotd100_and_each_direction(run):
    _, rf, _ = run
    n = 0
    for t in rf.tasks():
        pair = _pair(_rsn(t.meta["record"]))
        (s,) = t.spectra
        assert s.orientation == "RotD50" and s.floor == 2
        ref = fs.rotd_spectrum(pair, None, s.periods, list(s.damping), building=_model(
            t.meta["building"]), floor=2)  # fmt: skip
        np.testing.assert_allclose(s.psa, ref.rotd50, rtol=1e-13)
        np.testing.assert_allclose(s.rotd100, ref.rotd100, rtol=1e-13)
        np.testing.assert_allclose(s.psa_h1, ref.h1.psa, rtol=1e-13)
        np.testing.assert_allclose(s.psa_h2, ref.h2.psa, rtol=1e-13)
        w2 = (2 * np.pi / s.periods[1:]) ** 2
        np.testing.assert_allclose(s.sd[:, 1:], s.psa[:, 1:] / w2, rtol=1e-15)
        assert np.isnan(s.sa).all() and np.isnan(s.sv).all()
        assert (s.psa_broadened >= s.psa).all()
        n += 1
    assert n == 6


def test_histories_keep_the_path_in_the_plane(run):
    _, rf, _ = run
    t = next(t for t in rf.tasks() if t.histories is not None and t.meta["building"] == "fixed")
    h = t.histories
    assert h.floor_acceleration_h2.shape == h.floor_acceleration.shape
    u = h.plane["box/floor_2"]
    assert u.shape[2] == 2
    np.testing.assert_array_equal(h.slides["box/floor_2"], np.hypot(u[:, :, 0], u[:, :, 1]))
    pair = _pair("1084")
    ref = fs.slide_plane(pair, None, h.mu_k["box/floor_2"], building=_model("fixed"), floor=2,
                         histories=True)  # fmt: skip
    np.testing.assert_allclose(u, ref.u, rtol=0, atol=1e-12)


@pytest.mark.slow
def test_plane_table_and_figures(run):
    _, rf, tmp = run
    tables = fs.design_tables(rf.path)
    rows = tables["plane"]
    assert rows and {r["content"] for r in rows} == {"box"} | (
        {"cabinet"} if any(r["content"] == "cabinet" for r in rows) else set()
    )
    for r in rows:
        assert r["n_records"] <= 3
        if r["slide_1d_median"] > 0:
            assert r["ratio_of_medians"] == pytest.approx(
                r["slide_2d_median"] / r["slide_1d_median"]
            )
        if r["slide_2d_median"] > 0:
            assert r["ratio_min"] <= r["ratio_median"] <= r["ratio_max"]
        else:  # neither slides under any record: no ratio
            assert np.isnan(r["ratio_median"])
    assert any("slides in the plane" in n for n in tables.notes)
    written = fs.plot_figures(rf.path, tmp / "fig")
    names = {p.name for p in written}
    assert {"plane_path_pairs.png", "plane_ratio_pairs.png"} <= names


@pytest.mark.parametrize(
    ("kw", "message"),
    [
        (
            dict(contents='model = "oscillator"\nfrequency = 5.0\nvertical = true'),
            r"contents\[0\]\.vertical",
        ),
        (dict(contents='direction = "positive"'), r"contents\[0\]\.direction: one-way"),
        (dict(records='component = "N"'), r"records\[0\]\.component: a catalog of components"),
        (dict(extra_building="damping = [0.02, 0.05]\nperiod_h2x = 1"), r"period_h2x"),
    ],
)
def test_pair_scene_mistakes_are_refused_by_key_path(kw, message):
    with pytest.raises(SceneError, match=message):
        parse_scene(scene(**kw), ROOT / "scene.toml")


def test_vertical_shaking_in_the_plane_needs_the_pairs_vertical(tmp_path):
    """A content with vertical = true on a set of pairs whose catalog has no file_v: every pair
    is reported (it cannot run), none is silently run without the vertical."""
    path = tmp_path / "v.toml"
    path.write_text(scene(contents="vertical = true"))
    p = plan(load_scene(path), evaluate=False)
    assert not p.records
    assert len(p.failures) == 3 and all("need a vertical record" in f for f in p.failures)


def test_direction_keys_are_checked():
    text = scene().replace("period_h2 = 0.5", "period_h2 = [0.5, 0.6]")
    with pytest.raises(SceneError, match=r"buildings\[0\]\.period_h2: one value"):
        parse_scene(text, ROOT / "scene.toml")
    text = scene().replace("period_h2 = 0.5", "period_h2 = -1")
    with pytest.raises(SceneError, match=r"buildings\[0\]\.period_h2: must be > 0"):
        parse_scene(text, ROOT / "scene.toml")
    fps = scene() + (
        '\n[[buildings]]\nid = "fps"\nkind = "isolated"\nsuperstructure = "fixed"\n'
        'period = 3.0\nperiod_h2 = 3.5\nisolator = { model = "friction_pendulum", mu = 0.05 }\n'
    )
    with pytest.raises(SceneError, match=r"buildings\[2\]\.period_h2: a nonlinear isolation"):
        parse_scene(fps, ROOT / "scene.toml")


def test_the_bundled_pairs_scene_plans_every_pair():
    p = plan(load_scene(ROOT / "data" / "scenes" / "pairs.toml"), evaluate=False)
    assert len(p.records) == 10 and all(r.is_pair for r in p.records)
    assert len(p.tasks) == 20 and not p.failures
    # seven of the ten pairs have components of different lengths (npts_h1 != npts_h2 in the
    # catalog): padded, and said so
    assert sum("padded" in r.meta.get("pair_notes", "") for r in p.records) == 7


def test_a_pair_with_its_vertical_slides_with_vertical_shaking(tmp_path):
    """A catalog of components with file_v: contents with vertical = true slide in the plane
    under the varying normal force, as slide_plane(vertical=) (a stand-in vertical: another
    record's component, padded to the pair's length)."""
    d = ROOT / "data" / "records" / "pairs"
    cat = tmp_path / "v.csv"
    cat.write_text(
        "file_h1,file_h2,file_v,dt,units,comp_h1,comp_h2\n"
        f"{d / 'RSN1084_NORTHR_SCS052.AT2'},{d / 'RSN1084_NORTHR_SCS142.AT2'},"
        f"{d / 'RSN511_PALMSPR_ARM270.AT2'},0.005,g,52,142\n"
    )
    text = scene(contents="vertical = true").replace(CATALOG, cat.as_posix())
    text = text.replace(f"where = {{ rsn = {RSN} }}", "")
    path = tmp_path / "v.toml"
    path.write_text(text.split("[spectra]")[0])
    p = plan(load_scene(path))
    assert len(p.records) == 1 and p.records[0].vertical is not None and not p.failures
    out = tmp_path / "v.h5"
    execute(p, str(out), workers=1)
    (t,) = [t for t in ResultFile(out).tasks() if t.meta["building"] == "fixed"]
    (c,) = [c for c in t.contents if c.content == "box" and c.floor == 2]
    rec = p.records[0]
    ref = fs.slide_plane((rec.acc, rec.acc2), rec.dt, c.mu_k, building=_model("fixed"), floor=2,
                         vertical=rec.vertical)  # fmt: skip
    assert c.vertical
    np.testing.assert_allclose(c.peak_slide, ref.peak_slide, rtol=1e-12)
    plain = fs.slide_plane((rec.acc, rec.acc2), rec.dt, c.mu_k, building=_model("fixed"), floor=2)
    assert np.all(np.abs(c.peak_slide - plain.peak_slide) > 1e-6 * plain.peak_slide)


def test_frs_table_gives_rotd100_and_each_direction(run):
    """The frs table of a pair set: RotD50 (psa, orientation RotD50), and beside it the median
    and p84 of RotD100 and of each direction's PSA, the stored arrays' statistics."""
    from floorslide.report import design_tables, format_markdown

    _, rf, _ = run
    tables = design_tables(rf.path)
    rows = [r for r in tables["frs"] if r["period"] == 0.3]
    assert rows
    stored = {}
    for t in rf.tasks():
        (s,) = t.spectra
        k = list(np.asarray(s.periods)).index(0.3)
        stored.setdefault(t.meta["building"], []).append(
            [np.asarray(getattr(s, n))[0, k] for n in ("psa", "rotd100", "psa_h1", "psa_h2")]
        )
    for r in rows:
        got = np.array(stored[r["building"]])
        assert r["orientation"] == "RotD50"
        assert r["psa_median"] == pytest.approx(np.median(got[:, 0]), rel=1e-12)
        assert r["rotd100_median"] == pytest.approx(np.median(got[:, 1]), rel=1e-12)
        assert r["rotd100_p84"] == pytest.approx(np.percentile(got[:, 1], 84), rel=1e-12)
        assert r["psa_h1_median"] == pytest.approx(np.median(got[:, 2]), rel=1e-12)
        assert r["psa_h2_g_p84"] == pytest.approx(np.percentile(got[:, 3], 84) / 9.80665)
        assert r["rotd100_median"] >= r["psa_median"]
    assert "rotd100_median" in format_markdown(tables, ["frs"])
