"""The compact summary of any study: printed by ``run`` and ``demo`` at their end, again by
``table --summary`` (text or JSON), and the opening of the HTML report."""

from __future__ import annotations

import dataclasses
import json

from floorslide.report import design_tables
from floorslide.report.summary import (
    MAX_FRICTION_COLUMNS,
    format_summary,
    summary_blocks,
    summary_rows,
)
from tests.conftest import ROOT
from tests.report.test_cli_report import invoke


def test_the_summary_has_a_block_per_set_content_and_floor(study):
    tables = design_tables(study.path)
    blocks = summary_blocks(tables)
    assert [(b.record_set, b.content, b.floor) for b in blocks] == [
        ("pulse-like", "cabinet", 1),
        ("broad-band", "cabinet", 1),
    ]
    b = blocks[1]
    assert b.friction_labels == ("mu 0.05", "mu 0.1", "mu 0.2")
    assert [r.building for r in b.rows] == ["fixed", "isolated@T=2", "isolated@T=2.5"]
    pfa = {(r["building"]): r["pfa_g_median"] for r in tables["pfa"]
           if r["record_set"] == "broad-band" and r["floor"] == 1}  # fmt: skip
    assert [r.pfa_g for r in b.rows] == [pfa[r.building] for r in b.rows]
    text = format_summary(tables)
    assert text.count("| building | PFA (g) |") == 2 and "quality checks" in text


def test_many_friction_values_are_picked_and_said(study):
    tables = design_tables(study.path)
    rows = []
    for k in range(12):  # 12 friction values, made up from the stored rows
        for r in tables["slides"]:
            if r["mu_k"] == 0.05:
                rows.append(dict(r, mu_k=0.01 * (k + 1), mu_s=0.01 * (k + 1)))
    many = dataclasses.replace(tables, tables={**tables.tables, "slides": rows})
    b = summary_blocks(many)[0]
    assert len(b.friction) == MAX_FRICTION_COLUMNS and b.friction_all == 12
    assert b.friction[0][0] == 0.01 and b.friction[-1][0] == 0.12
    assert f"{MAX_FRICTION_COLUMNS} of 12 friction values (all: the slides table)" in b.heading


def test_table_summary_prints_the_summary(monkeypatch, capsys, study):
    code, out, _ = invoke(monkeypatch, capsys, "table", study.path, "--summary")
    assert code == 0
    assert out.rstrip("\n") == format_summary(design_tables(study.path))
    code, out, _ = invoke(monkeypatch, capsys, "table", study.path, "--summary", "--json")
    data = json.loads(out)
    assert code == 0 and data["complete"] is True
    assert data["rows"] == json.loads(json.dumps(summary_rows(design_tables(study.path))))
    rock = next(
        r for r in data["rows"]
        if r["record_set"] == "pulse-like" and r["building"] == "fixed" and r["mu_k"] == 0.05
    )  # fmt: skip
    assert rock["median_outcome"] == "rock" and rock["peak_slide_median"] is None
    for other in (("--table", "slides"), ("--per-record",), ("--format", "csv")):
        code, _, err = invoke(monkeypatch, capsys, "table", study.path, "--summary", *other)
        assert code == 2 and "--summary and" in err


SCENE = f"""
[scene]
name = "one record"

[[records]]
set = "one"
catalog = "{(ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()}"
where = {{ station_id = "ELC-180" }}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.25
damping = 0.03

[[contents]]
id = "box"
floors = [1]
mu = [0.05, 0.2]
"""


def test_run_ends_with_the_summary(monkeypatch, capsys, tmp_path):
    scene = tmp_path / "one.toml"
    scene.write_text(SCENE, encoding="utf-8")
    out_h5 = tmp_path / "one.h5"
    code, out, _ = invoke(monkeypatch, capsys, "run", scene, "-o", out_h5, "--workers", 1)
    assert code == 0
    summary = format_summary(design_tables(out_h5))
    assert summary in out
    assert "one (1 records) — 'box' on floor 1: median peak slide" in out
    assert out.rstrip().endswith(f"--summary; all tables: floorslide table {out_h5})")


def test_the_rocking_legend_is_printed_once(study):
    text = format_summary(design_tables(study.path))
    assert text.count("never count as 0") == 1
    lines = text.splitlines()
    assert (
        "never count as 0"
        in lines[lines.index(next(ln for ln in lines if "(3 records)" in ln)) + 1]
    )
