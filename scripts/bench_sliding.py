"""Benchmark: the exact rigid-block solver and the approximate methods.

1. One 4,000-sample record × 1,000 friction values, on the ground and on the roof of a 3-storey
   isolated building (and of the fixed-base one): object·steps per second on one core.
2. One 1,000,000-sample record × 10 friction values.
3. Each approximate method: its time and its error on the peak slide against the exact result.

Usage::

    python scripts/bench_sliding.py
"""

from __future__ import annotations

import numpy as np
from _common import markdown_table, record_4000, slammer, timeit

import floorslide as fs


def throughput() -> None:
    ag, dt = record_4000()
    mus = np.linspace(0.01, 0.5, 1000)
    fb = fs.ShearBuilding.from_period(3, 0.4, 0.05)
    iso = fs.IsolatedBuilding(fb, 1.0, 2.5, 0.10)
    rows = []
    for name, kw in (
        ("ground", {}),
        ("roof, 3-storey isolated", dict(building=iso, floor=3)),
        ("roof, 3-storey fixed-base", dict(building=fb, floor=3)),
    ):
        t = timeit(lambda kw=kw: fs.slide(ag, dt, mus, **kw), repeat=3)
        rows.append(
            [name, f"{ag.size} × {mus.size}", f"{t * 1e3:.1f}", f"{ag.size * mus.size / t:.2e}"]
        )
    n = 1_000_000
    long = np.tile(ag, n // ag.size + 1)[:n]
    mus10 = np.linspace(0.05, 0.5, 10)
    t = timeit(lambda: fs.slide(long, dt, mus10), repeat=3)
    rows.append(["ground, 10⁶ samples", f"{n} × 10", f"{t * 1e3:.1f}", f"{n * 10 / t:.2e}"])
    print(markdown_table(["case", "samples × objects", "ms", "object·steps / s"], rows))


def approximate() -> None:
    ag, dt = slammer("ImperialValley_1940_ELC-180.txt")
    mus = np.array([0.05, 0.1, 0.2])
    stiff = fs.ShearBuilding.from_period(1, 0.1, 0.05)
    rows = []
    for where, kw in (("ground", {}), ("stiff floor (T = 0.1 s)", dict(building=stiff, floor=1))):
        exact = fs.slide(ag, dt, mus, **kw)
        te = timeit(lambda kw=kw: fs.slide(ag, dt, mus, **kw), repeat=5)
        rows.append([where, "exact", f"{te * 1e3:.2f}", "0"])
        cases = [("slammer (Jibson 1993, per sample)", dict(method="slammer"))]
        cases += [(f"newmark dt/{k}", dict(method="newmark", substeps=k)) for k in (1, 4, 16, 64)]
        cases += [("reinterpolated floor samples", dict(method="reinterpolated"))]
        cases += [
            (f"solve_ivp DOP853 rtol {r:g}", dict(method="solve_ivp", rtol=r)) for r in (1e-4, 1e-8)
        ]
        for name, mkw in cases:
            if name.startswith("reinterpolated") and not kw:
                continue
            repeat = 1 if mkw["method"] == "solve_ivp" else 5
            t = timeit(
                lambda mkw=mkw, kw=kw: fs.slide(ag, dt, mus, **mkw, **kw), repeat=repeat, min_time=0
            )
            got = fs.slide(ag, dt, mus, **mkw, **kw)
            err = np.abs(got.peak_slide - exact.peak_slide).max() / exact.peak_slide.max()
            rows.append([where, name, f"{t * 1e3:.2f}", f"{err:.1e}"])
    print(f"El Centro 1940 (ELC-180), {ag.size} samples at dt = {dt} s, mu = {mus.tolist()}")
    print(
        markdown_table(["floor", "method", "ms (3 objects)", "max rel. error of peak slide"], rows)
    )


if __name__ == "__main__":
    throughput()
    print()
    approximate()
