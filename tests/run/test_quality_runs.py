"""Quality checks in a study: ``[scene] qa = "warn"`` runs a flagged record and stores its flags
(task attribute, plan, records table, per-record table); ``"reject"`` leaves it out, reports it
and runs the others; the dry run lists both."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from floorslide.cli import cli
from floorslide.errors import SceneError
from floorslide.report import design_tables
from floorslide.report.records import record_table
from floorslide.run.execute import execute
from floorslide.run.store import ResultFile
from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene, parse_scene
from tests.conftest import ROOT

KNET = (ROOT / "tests" / "data" / "raw" / "AOM0081801241951.NS").as_posix()
ELC = (ROOT / "data" / "records" / "slammer" / "ImperialValley_1940_ELC-180.txt").as_posix()
CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()


def scene_text(qa: str | None, processing: str = "") -> str:
    line = f'qa = "{qa}"' if qa else ""
    return f"""
[scene]
name = "qa"
{line}

[[records]]
set = "raw"
files = ["{KNET}"]

[[records]]
set = "clean"
catalog = "{CATALOG}"
where = {{ station_id = ["ELC-180"] }}

{processing}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.3
damping = 0.05

[[contents]]
id = "box"
floors = "roof"
mu = [0.01, 0.1]

[spectra]
floors = "all"
periods = [0.1, 1.0]
damping = [0.05]
"""


def load(tmp_path, text: str):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return load_scene(path)


def test_warn_runs_the_flagged_record_and_stores_its_flags(tmp_path):
    sc = load(tmp_path, scene_text(None))
    assert sc.qa == "warn"
    p = plan(sc)
    assert len(p.records) == 2 and not p.failures
    raw = next(r for r in p.records if r.set == "raw")
    assert raw.qa_flags == "offset"
    assert "quality checks: 1 records flagged; they run (qa = 'warn')" in p.describe()
    assert "raw/AOM0081801241951: offset: pre-event mean" in p.describe()
    out = tmp_path / "out.h5"
    summary = execute(p, str(out), workers=1)
    assert summary.failures == []
    rf = ResultFile(out)
    flags = {t.meta["record"]: t.meta["qa_flags"] for t in rf.tasks()}
    assert flags == {"AOM0081801241951": "offset", "ImperialValley_1940_ELC-180": ""}
    stored = rf.plan["quality"]
    assert stored["action"] == "warn" and stored["rejected"] == []
    (item,) = stored["flagged"]
    assert item["record"] == "AOM0081801241951" and item["flags"][0]["check"] == "offset"
    assert item["flags"][0]["values"]["mean_ratio"] > 0.05
    rows = design_tables(out)["records"]
    assert [(r["record_set"], r["status"], r["qa_flags"]) for r in rows] == [
        ("raw", "ran", "offset"),
        ("clean", "ran", ""),
    ]
    assert "demean = true in [processing]" in rows[0]["qa"]
    per = record_table(out)
    assert set(per.loc[per.record_set == "raw", "qa_flags"]) == {"offset"}
    assert set(per.loc[per.record_set == "clean", "qa_flags"]) == {""}


def test_processing_in_the_scene_removes_the_flag(tmp_path):
    p = plan(load(tmp_path, scene_text("reject", "[processing]\ndemean = true")))
    assert len(p.records) == 2 and not p.failures and not p.rejected
    assert all(r.qa == () for r in p.records)


def test_reject_leaves_the_record_out_and_the_batch_goes_on(tmp_path):
    sc = load(tmp_path, scene_text("reject"))
    p = plan(sc)
    assert [r.set for r in p.records] == ["clean"]
    assert len(p.failures) == 1 and "rejected by the quality checks (offset" in p.failures[0]
    assert p.rejected[0]["record"] == "AOM0081801241951"
    text = p.describe()
    assert "1 records rejected, not run (qa = 'reject')" in text
    assert "unreadable record" not in text  # it was read: rejected, not unreadable
    out = tmp_path / "out.h5"
    summary = execute(p, str(out), workers=1)
    assert summary.tasks == 1 and len(summary.failures) == 1
    rows = design_tables(out)["records"]
    assert [(r["record_set"], r["status"], r["qa_flags"]) for r in rows] == [
        ("clean", "ran", ""),
        ("raw", "rejected", "offset"),
    ]
    # the command line: the run finishes, reports the rejected record, exit 3 (records left out)
    cli_out = tmp_path / "cli.h5"
    result = CliRunner().invoke(cli, ["run", str(tmp_path / "scene.toml"), "-o", str(cli_out)])
    assert result.exit_code == 3
    assert "rejected by the quality checks" in result.stderr
    md = CliRunner().invoke(cli, ["table", str(cli_out), "--table", "records", "--json"])
    data = json.loads(md.stdout)
    assert [r["status"] for r in data["tables"]["records"]] == ["ran", "rejected"]


def test_samples_per_period_against_the_scene_periods(tmp_path):
    text = scene_text(None).replace("periods = [0.1, 1.0]", "periods = [0.015, 1.0]")
    p = plan(load(tmp_path, text))
    clean = next(r for r in p.records if r.set == "clean")
    assert clean.qa_flags == "samples_per_period"  # dt 0.01 s: 0.015 s spans 1.5 samples


def test_bad_qa_value_names_the_key():
    with pytest.raises(SceneError, match=r"scene\.qa: 'strict': expected one of 'warn', 'reject'"):
        parse_scene(scene_text("strict"))
