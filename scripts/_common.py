"""Helpers shared by the benchmark scripts: bundled records and robust timing."""

from __future__ import annotations

import csv
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SLAMMER = ROOT / "data" / "records" / "slammer"
G = 9.80665


def slammer(name: str) -> tuple[np.ndarray, float]:
    """A bundled SLAMMER record in m/s² and its dt."""
    with open(SLAMMER / "index.csv", newline="") as fh:
        rows = {r["file"]: r for r in csv.DictReader(fh)}
    return np.loadtxt(SLAMMER / name) * G, float(rows[name]["dt"])


def record_4000() -> tuple[np.ndarray, float]:
    """Kobe 1995 KAK-000: 3,999 samples at dt = 0.01 s (the 4,000-sample benchmark record)."""
    return slammer("Kobe_1995_KAK-000.txt")


def timeit(fn, repeat: int = 7, min_time: float = 0.05) -> float:
    """Median wall time of `fn()` in seconds (one warm-up call excluded; calls batched so each
    timing lasts at least `min_time`)."""
    fn()
    t0 = time.perf_counter()
    fn()
    once = time.perf_counter() - t0
    inner = max(1, int(min_time / max(once, 1e-9)))
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(inner):
            fn()
        times.append((time.perf_counter() - t0) / inner)
    return float(np.median(times))


def markdown_table(header: list[str], rows: list[list]) -> str:
    """A Markdown table."""
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)
