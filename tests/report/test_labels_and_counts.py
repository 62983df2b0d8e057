"""What a table shows cannot be misread: floor 0 is named for what it is (the ground of a
fixed-base building, the base mat of an isolated one), docs/design.md §2 and §10."""

from __future__ import annotations

import pytest

from floorslide.report import COLUMNS, design_tables
from floorslide.report.columns import floor_label
from floorslide.report.records import RECORD_COLUMNS, record_table
from floorslide.report.tables import format_markdown


@pytest.fixture(scope="module")
def tables(study):
    return design_tables(study.path)


def test_floor_label_names_ground_base_mat_and_roof():
    assert floor_label("fixed", 0, 3) == "ground"
    assert floor_label("isolated", 0, 3) == "base mat"
    assert floor_label("fixed", 3, 3) == "roof"
    assert floor_label("isolated", 2, 3) == "floor 2"


def test_floor_zero_is_ground_or_base_mat_in_every_table(tables):
    pfa = tables["pfa"]
    labels = {(r["building"], r["floor"]): r["floor_label"] for r in pfa}
    assert labels[("fixed", 0)] == "ground"
    assert labels[("isolated@T=2", 0)] == "base mat"
    assert labels[("fixed", 1)] == "roof"
    for name, cols in COLUMNS.items():
        names = [c.name for c in cols]
        if "floor" in names:
            assert names[names.index("floor") + 1] == "floor_label", name
            assert all(r["floor_label"] for r in tables[name]), name
    ratios = [r for r in tables["pfa_ratios"] if r["floor"] == 0]
    assert ratios and all(r["floor_label"] == "base mat (A) / ground (B)" for r in ratios)


def test_markdown_and_per_record_table_say_base_mat(study, tables):
    text = format_markdown(tables, ["pfa"])
    assert "| base mat |" in text and "| ground |" in text
    df = record_table(study.path)
    assert [c.name for c in RECORD_COLUMNS].index("floor_label") == 7
    assert set(df.floor_label) == {"roof"}


def test_one_component_frs_has_no_pair_columns_in_markdown(tables):
    """The pair columns (RotD100, each direction) are NaN for one component and left out of
    Markdown; CSV and JSON keep every column."""
    row = tables["frs"][0]
    assert row["orientation"] == "" and row["rotd100_median"] != row["rotd100_median"]
    text = format_markdown(tables, ["frs"])
    assert "rotd100" not in text and "orientation" not in text


def test_per_record_floor_spectra_are_a_dataframe(study):
    """spectra_table: the stored spectra record by record, each value the stored one."""
    import numpy as np

    import floorslide as fs
    from floorslide.report.records import SPECTRA_COLUMNS
    from floorslide.run.store import ResultFile

    df = fs.spectra_table(study.path, damping=0.05)
    assert list(df.columns) == [c.name for c in SPECTRA_COLUMNS]
    assert df.attrs["units"]["psa"] == "m/s**2" and set(df.damping) == {0.05}
    tasks = list(ResultFile(study.path).tasks())
    n_rows = sum(s.periods.size for t in tasks for s in t.spectra)
    assert len(df) == n_rows
    t = tasks[0]
    s = t.spectra[0]
    sel = df[(df.record == t.meta["record"]) & (df.record_set == t.meta["record_set"])
             & (df.building == t.meta["building"]) & (df.floor == s.floor)]  # fmt: skip
    k = list(np.asarray(s.damping)).index(0.05)
    np.testing.assert_array_equal(sel.psa.to_numpy(), np.asarray(s.psa)[k])
    np.testing.assert_array_equal(sel.period.to_numpy(), np.asarray(s.periods))
    assert len(fs.spectra_table(study.path)) == 2 * n_rows  # both damping ratios
    assert set(df[df.floor == 0].floor_label) == {"ground", "base mat"}
