"""Reports: design tables and figures from a result file (docs/design.md §3, §5).

``design_tables(path)`` gives the statistics over record sets and the ratios between buildings
(``.to_pandas()`` as DataFrames); ``record_table(path)`` the per-record values as a DataFrame,
``spectra_table(path)`` the per-record floor spectra as one; ``plot_figures(path, folder)``
writes the PNG figures. All read the result file only, and refuse an incomplete one unless
``allow_incomplete=True`` (then they label it INCOMPLETE).
matplotlib is imported only when ``plot_figures`` is first used, pandas when a DataFrame is.
"""

from floorslide.report.columns import (
    COLUMNS,
    MIN_RECORDS,
    TABLE_NAMES,
    Column,
    Comparison,
    DesignTables,
)
from floorslide.report.formats import (
    format_csv,
    format_json,
    format_markdown,
    to_json,
    write_csv,
)
from floorslide.report.records import RECORD_COLUMNS, SPECTRA_COLUMNS, record_table, spectra_table
from floorslide.report.study import Study, load_study
from floorslide.report.tables import design_tables

__all__ = [
    "COLUMNS",
    "MIN_RECORDS",
    "RECORD_COLUMNS",
    "SPECTRA_COLUMNS",
    "TABLE_NAMES",
    "Column",
    "Comparison",
    "DesignTables",
    "Study",
    "design_tables",
    "format_csv",
    "format_json",
    "format_markdown",
    "load_study",
    "plot_figures",
    "record_table",
    "spectra_table",
    "to_json",
    "write_csv",
]


def __getattr__(name: str):
    if name == "plot_figures":
        from floorslide.report.plots import plot_figures

        return plot_figures
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
