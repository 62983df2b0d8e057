"""Benchmark: rocking blocks (issue 15) — throughput of the exact solver, and what the
linearised equation misses against the full one as blocks get stockier.

1. Throughput on the ground, batched over blocks (Kobe KAK-000, 3,999 samples, 1.5 m tall
   blocks): blocks that stay at rest (B/H = 0.67), a mix (B/H 0.07–0.4: rest, rock, overturn)
   and slender blocks (B/H 0.03–0.07, hundreds of impacts each), with the linearised (exact)
   and the full (nonlinear) equation: block·steps per second.
2. Linearisation error against α: for α from 0.05 to 0.6 rad, the bundled SLAMMER records
   scaled to PGA = 1.5·g·tan α (so that every block uplifts), the relative difference of the
   peak θ/α between the two equations (median and max over the records) and the number of
   records where only one of them overturns.

Usage::

    python scripts/bench_rocking.py
"""

from __future__ import annotations

import csv

import numpy as np
from _common import SLAMMER, G, markdown_table, record_4000, slammer, timeit

import floorslide as fs


def throughput() -> list[list[str]]:
    ag, dt = record_4000()
    rows = []
    n = 1000
    cases = {
        "at rest (B/H 0.67)": np.full(n, 1.0),
        "mixed (B/H 0.07–0.4)": np.linspace(0.1, 0.6, n),
        "slender (B/H 0.03–0.07)": np.linspace(0.05, 0.1, n),
    }
    for label, widths in cases.items():
        for method in ("exact", "nonlinear"):
            r = fs.rock(ag, dt, widths, 1.5, method=method)
            t = timeit(lambda w=widths, m=method: fs.rock(ag, dt, w, 1.5, method=m), repeat=3)
            modes = {k: r.mode.count(k) for k in ("rest", "rock", "overturn")}
            rows.append(
                [
                    label,
                    method,
                    ", ".join(f"{v} {k}" for k, v in modes.items()),
                    f"{r.impacts.mean():.0f}",
                    f"{t * 1e3:.1f} ms",
                    f"{n * ag.size / t:.2e}",
                ]
            )
    return rows


def linearisation() -> list[list[str]]:
    with open(SLAMMER / "index.csv", newline="") as fh:
        names = [r["file"] for r in csv.DictReader(fh)]
    records = [slammer(name) for name in names]
    rows = []
    for alpha in (0.05, 0.1, 0.2, 0.3, 0.45, 0.6):
        height = 1.5
        width = height * np.tan(alpha)
        errs, disagree, over = [], 0, 0
        for acc, dt in records:
            a = acc * (1.5 * G * np.tan(alpha) / np.abs(acc).max())
            lin = fs.rock(a, dt, width, height, method="exact", restitution=0.9)
            full = fs.rock(a, dt, width, height, method="nonlinear", restitution=0.9)
            over += int(full.overturned[0])
            if lin.overturned[0] != full.overturned[0]:
                disagree += 1
            elif not full.overturned[0]:
                errs.append(abs(lin.peak_ratio[0] - full.peak_ratio[0]) / full.peak_ratio[0])
        rows.append(
            [
                f"{alpha:g}",
                f"{np.tan(alpha):.3f}",
                f"{over}/{len(records)}",
                f"{disagree}",
                f"{np.median(errs):.1e}" if errs else "–",
                f"{np.max(errs):.1e}" if errs else "–",
            ]
        )
    return rows


def main() -> None:
    print(
        markdown_table(
            ["blocks (1,000)", "equation", "outcomes", "impacts/block", "time", "block·steps/s"],
            throughput(),
        )
    )
    print()
    print(
        markdown_table(
            [
                "α (rad)",
                "B/H",
                "overturn (full)",
                "records where only one overturns",
                "peak θ/α difference, median",
                "max",
            ],
            linearisation(),
        )
    )


if __name__ == "__main__":
    main()
