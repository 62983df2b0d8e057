"""The per-record table (issue 12 item 10): one row per record × building × floor × content ×
friction value, as a DataFrame and as CSV/JSON from ``floorslide table --per-record``."""

from __future__ import annotations

import csv
import io
import json
import math
import sys

import numpy as np
import pytest

from floorslide.cli import main
from floorslide.errors import IncompleteResultError
from floorslide.report import RECORD_COLUMNS, design_tables, record_table
from tests.report.conftest import BUILDINGS, MU, RACK_MU, SETS, G


def test_record_table_is_a_dataframe_of_every_value(rich_study):
    import floorslide as fs

    df = fs.record_table(rich_study.path)
    n_records = sum(len(r) for r in SETS.values())
    assert len(df) == n_records * len(BUILDINGS) * (len(MU) + len(RACK_MU))
    assert list(df.columns) == [c.name for c in RECORD_COLUMNS]
    assert df.attrs["units"]["peak_slide"] == "m" and df.attrs["status"] == ""
    for (rs, bid, rec), truth in rich_study.truth.items():
        sel = df[(df.record == rec) & (df.building == bid) & (df.content == "cabinet")]
        assert (sel.record_set == rs).all() and list(sel.mu_k) == list(MU)
        np.testing.assert_array_equal(sel.peak_slide, truth["peak"])
        np.testing.assert_array_equal(sel.residual_slide, truth["resid"])  # signed
        np.testing.assert_array_equal(sel.peak_abs_accel_g, truth["acc"] / G)
        assert list(sel.outcome) == [
            "rock" if m == "rock" else ("slide" if p > 0 else "rest")
            for m, p in zip(truth["modes"], truth["peak"], strict=True)
        ]
        assert (sel.pfa == truth["pfa"][1]).all() and (sel.pga == truth["pga"]).all()
        rack = df[(df.record == rec) & (df.building == bid) & (df.content == "rack")]
        np.testing.assert_array_equal(rack.peak_deformation, truth["rack"].peak_deformation)
        np.testing.assert_array_equal(rack.peak_top_accel, truth["rack"].peak_top_accel)
        assert (rack.model == "oscillator").all()
    rocks = df[df.outcome == "rock"]
    assert rocks.peak_slide.isna().all() and rocks.slip_phases.isna().all()


def test_record_table_agrees_with_the_design_tables(study):
    df = record_table(study.path)
    slides = design_tables(study.path)["slides"]
    grouped = df.groupby(["record_set", "building", "mu_k"], sort=False)
    for row in slides:
        g = grouped.get_group((row["record_set"], row["building"], row["mu_k"]))
        assert len(g) == row["n_records"] and (g.outcome == "rock").sum() == row["n_rock"]
        if row["n_rock"] == 0:  # no rocking: the plain median of the column
            assert row["peak_slide_median"] == pytest.approx(g.peak_slide.median(), rel=1e-15)
        else:  # pandas would skip the NaNs silently: the tables must not
            assert row["mean_outcome"] == "rock" and math.isnan(row["peak_slide_mean"])
            if row["n_rock"] < row["n_records"]:
                assert not math.isnan(g.peak_slide.mean())
    first = df.iloc[: len(MU) * 3]  # the scene's first set, first building, records in order
    assert list(first.record_set.unique()) == ["pulse-like"]
    assert list(first.record.unique()) == SETS["pulse-like"]


def test_record_table_refuses_an_incomplete_file(partial_study):
    with pytest.raises(IncompleteResultError):
        record_table(partial_study.path)
    df = record_table(partial_study.path, allow_incomplete=True)
    assert df.attrs["status"].startswith("INCOMPLETE: 14 of 18")
    assert len(df) == 14 * len(MU)


def invoke(monkeypatch, capsys, *args):
    monkeypatch.setattr(sys, "argv", ["floorslide", *map(str, args)])
    code = 0
    try:
        main()
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else 1
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_per_record_csv_and_json(monkeypatch, capsys, study, tmp_path):
    code, out, err = invoke(monkeypatch, capsys, "table", study.path, "--per-record")
    assert code == 0, err
    rows = list(csv.DictReader(io.StringIO(out)))
    df = record_table(study.path)
    assert len(rows) == len(df) and list(rows[0]) == list(df.columns)
    i = int(np.nonzero((df.outcome == "slide").to_numpy())[0][0])
    assert float(rows[i]["peak_slide"]) == df.peak_slide.iloc[i]  # full precision
    rock = next(r for r in rows if r["outcome"] == "rock")
    assert rock["peak_slide"] == ""  # not 0
    code, out, err = invoke(monkeypatch, capsys, "table", study.path, "--per-record", "--json")
    assert code == 0, err
    data = json.loads(out)
    assert [c["name"] for c in data["columns"]] == list(df.columns)
    assert len(data["rows"]) == len(df) and data["complete"] is True
    target = tmp_path / "per_record.csv"
    code, out, _ = invoke(monkeypatch, capsys, "table", study.path, "--per-record", "-o", target)
    assert code == 0 and out.strip() == str(target)
    import pandas as pd

    back = pd.read_csv(target)
    assert len(back) == len(df) and back.peak_slide.iloc[i] == df.peak_slide.iloc[i]
    code, _, err = invoke(
        monkeypatch, capsys, "table", study.path, "--per-record", "--table", "pfa"
    )
    assert code == 2 and "--per-record and --table" in err


def test_cli_per_record_incomplete(monkeypatch, capsys, partial_study):
    code, out, err = invoke(monkeypatch, capsys, "table", partial_study.path, "--per-record")
    assert code == 4 and out == "" and err.count("\n") == 1
    code, out, err = invoke(
        monkeypatch, capsys, "table", partial_study.path, "--per-record", "--allow-incomplete"
    )
    assert code == 0 and out.startswith("# INCOMPLETE: 14 of 18 tasks done")
    import pandas as pd

    df = pd.read_csv(io.StringIO(out), comment="#")
    assert len(df) == 14 * len(MU)
