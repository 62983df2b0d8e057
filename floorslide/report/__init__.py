"""Reports: design tables and figures from a result file (DESIGN §3, §5).

``design_tables(path)`` gives the statistics over record sets and the ratios between buildings;
``plot_figures(path, folder)`` writes the PNG figures. Both read the result file only.
matplotlib is imported only when ``plot_figures`` is first used.
"""

from floorslide.report.tables import (
    COLUMNS,
    TABLE_NAMES,
    Column,
    Comparison,
    DesignTables,
    Study,
    design_tables,
    format_csv,
    format_json,
    format_markdown,
    load_study,
    to_json,
    write_csv,
)

__all__ = [
    "COLUMNS",
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
    "to_json",
    "write_csv",
]


def __getattr__(name: str):
    if name == "plot_figures":
        from floorslide.report.plots import plot_figures

        return plot_figures
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
