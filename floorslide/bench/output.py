"""Tables of the study: CSV (one flat table), Markdown (one table per solver) and JSON."""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path

from floorslide import outputs
from floorslide.bench.cases import METRICS
from floorslide.bench.study import BenchResult

COLUMNS = (
    "solver",
    "method",
    "family",
    "setting",
    "substeps",
    "rtol",
    "grip_hz",
    "cpu_time",
    "time_ratio",
    "first_call",
    "compile_time",
    "repeats",
    "error",
    *(f"err_{m}" for m in METRICS),
)
"""Columns of the CSV and of each JSON row: times in s, errors relative (see
:data:`floorslide.bench.cases.METRICS`); empty (``null``) where a setting or metric does not
apply."""


def to_csv(result: BenchResult) -> str:
    """The flat table as CSV (SI: seconds; errors relative)."""
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    for row in result.rows:
        d = row.to_dict()
        writer.writerow({k: "" if d[k] is None else _plain(d[k]) for k in COLUMNS})
    return buf.getvalue()


def _plain(value):
    if isinstance(value, float):
        return repr(value)
    return value


def to_json(result: BenchResult, compile_rows: list[dict] | None = None) -> str:
    """The study as JSON: ``rows`` (columns :data:`COLUMNS`), ``records``, ``solvers``,
    ``metrics``, ``machine``, ``quick`` and ``compile`` (the numba compilation on an empty cache;
    ``null`` when not measured)."""
    out = result.to_dict()
    out["compile"] = compile_rows
    return json.dumps(_finite(out), indent=1)


def _finite(obj):
    """NaN and infinities as ``null`` (JSON has neither)."""
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_finite(v) for v in obj]
    return obj


def _ms(seconds: float) -> str:
    ms = seconds * 1e3
    if ms >= 100:
        return f"{ms:.0f}"
    if ms >= 10:
        return f"{ms:.1f}"
    return f"{ms:.2f}" if ms >= 0.1 else f"{ms:.3f}"


def _err(value: float | None) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "—"
    return "0" if value == 0 else f"{value:.1e}"


def markdown_table(result: BenchResult, solver: str) -> str:
    """The rows of one solver as a Markdown table."""
    metrics = result.metrics[solver]
    head = ["method", "setting", "CPU (ms)", "× exact", "first call (ms)", "compile (ms)"]
    head += [f"error: {METRICS[m]}" for m in metrics]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * 2 + "---:|" * (len(head) - 2)]
    for row in result.rows:
        if row.solver != solver:
            continue
        name = "exact (rounding floor)" if row.method == "exact" else row.family
        cells = [
            name,
            row.setting or "—",
            _ms(row.cpu_time),
            f"{row.time_ratio:.3g}",
            _ms(row.first_call),
            _ms(row.compile_time),
        ]
        cells += [_err(row.errors.get(m)) for m in metrics]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def summary_markdown(result: BenchResult, target: float = 0.01) -> str:
    """One line per method family: its error and time at the coarsest setting, the cheapest
    setting within `target` (relative error), and the finest setting; the exact method's time
    and rounding floor with the solver's name."""
    head = (
        "| solver (exact: CPU, rounding floor) | method | coarsest: error, ms "
        f"| cheapest within {target * 100:g} %: setting, ms (× exact) "
        "| finest: setting, error, ms |"
    )
    lines = [head, "|---|---|---|---|---|"]
    for key in result.solvers:
        rows = [r for r in result.rows if r.solver == key]
        exact = next(r for r in rows if r.method == "exact")
        families: dict[str, list] = {}
        for r in rows:
            if r.method != "exact":
                families.setdefault(r.family, []).append(r)
        first = True
        for family, members in families.items():
            label = f"`{key}` ({_ms(exact.cpu_time)} ms, {_err(exact.error)})" if first else ""
            first = False
            coarse, fine = members[0], members[-1]
            within = next((m for m in members if m.error <= target), None)
            if within is None:
                reach = "not reached"
            else:
                reach = f"{within.setting}, {_ms(within.cpu_time)} ({within.time_ratio:.3g}×)"
            if len(members) > 1:
                finest = f"{fine.setting}, {_err(fine.error)}, {_ms(fine.cpu_time)}"
            else:
                finest = "—"
            lines.append(
                f"| {label} | {family} | {_err(coarse.error)}, {_ms(coarse.cpu_time)} "
                f"| {reach} | {finest} |"
            )
    return "\n".join(lines)


def to_markdown(result: BenchResult, compile_rows: list[dict] | None = None) -> str:
    """The study as Markdown: the records, a summary, one table per solver, the compile
    table."""
    recs = "; ".join(
        f"{r['label']}: {r['npts']} samples at dt = {r['dt']:g} s" for r in result.records
    )
    parts = [
        f"Records: {recs}. CPU time: `time.process_time`, one thread, median of repeats after a "
        "warm-up call, summed over the records; errors relative to the exact method, maximum "
        "over records, objects, floors and periods.",
    ]
    parts.append(f"**Summary**\n\n{summary_markdown(result)}")
    for key, title in result.solvers.items():
        parts.append(f"**{title}** (`{key}`)\n\n{markdown_table(result, key)}")
    if compile_rows:
        parts.append(compile_markdown(compile_rows))
    return "\n\n".join(parts) + "\n"


def compile_markdown(compile_rows: list[dict]) -> str:
    """The compile table as Markdown."""
    lines = [
        "**numba compilation on a fresh install** (empty cache; a kernel shared by several "
        "methods is compiled once, by the first)",
        "",
        "| solver | method | compile (s) | kernels compiled |",
        "|---|---|---:|---|",
    ]
    for r in compile_rows:
        kernels = ", ".join(k.rsplit(".", 1)[-1] for k in r["kernels"]) or "—"
        lines.append(f"| {r['solver']} | {r['method']} | {r['compile_time']:.2f} | {kernels} |")
    return "\n".join(lines)


def write_outputs(
    result: BenchResult, directory: str | Path, compile_rows: list[dict] | None = None
) -> list[Path]:
    """Write ``bench.csv``, ``bench.md``, ``bench.json``, ``compile.csv`` (when measured) and one
    figure per solver (``<solver>.png``) to `directory`; returns the paths written."""
    from floorslide.bench.figures import work_precision_figure

    out = Path(directory)
    written = []
    advice = "choose another folder with -o, or move the file away"
    for name, text, rule in (
        ("bench.csv", to_csv(result), None),
        ("bench.md", to_markdown(result, compile_rows), outputs.starts_with(b"Records: ")),
        ("bench.json", to_json(result, compile_rows), outputs.starts_with(b'{\n "quick": ')),
    ):
        rule = rule or outputs.same_first_line(text)
        written.append(outputs.write_output(out / name, text, replace=rule, advice=advice))
    if compile_rows is not None:
        buf = io.StringIO()
        writer = csv.writer(buf, lineterminator="\n")
        writer.writerow(["solver", "method", "compile_time", "kernels"])
        for r in compile_rows:
            writer.writerow(
                [r["solver"], r["method"], repr(r["compile_time"]), " ".join(r["kernels"])]
            )
        text = buf.getvalue()
        written.append(
            outputs.write_output(
                out / "compile.csv", text, replace=outputs.same_first_line(text), advice=advice
            )
        )
    for key in result.solvers:
        png = work_precision_figure(result, key)
        written.append(
            outputs.write_output(
                out / f"{key}.png", png, replace=outputs.floorslide_png, advice=advice
            )
        )
    return written
