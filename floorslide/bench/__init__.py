"""The accuracy-versus-cost study (docs/design.md §6): every solver's exact method against its
approximate ones, on bundled real records — error in what users use, CPU time, numba
compilation apart — written as tables (CSV, Markdown, JSON) and work–precision diagrams.

>>> from floorslide.bench import run_bench, write_outputs
>>> result = run_bench(quick=True)                      # doctest: +SKIP
>>> write_outputs(result, "floorslide-bench")           # doctest: +SKIP
"""

from floorslide.bench.output import to_csv, to_json, to_markdown, write_outputs
from floorslide.bench.study import BenchResult, Row, run_bench

__all__ = [
    "BenchResult",
    "Row",
    "run_bench",
    "to_csv",
    "to_json",
    "to_markdown",
    "write_outputs",
]
