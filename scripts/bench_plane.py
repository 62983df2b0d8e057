"""Benchmark and statistics: rigid blocks sliding in the plane under two horizontal components
(issue 16).

1. Throughput (Sylmar, Northridge 1994, 8,773 samples at 5 ms), 1, 10 and 100 friction values
   in one call, on the ground and on the roof of a 3-storey shear building (T = 0.4 s), against
   the two 1-D runs of the components (fs.slide). Times are the fastest of several runs (the
   machine may be shared: the fastest is the least disturbed).
2. The 2-D slide against the larger 1-D slide of the two components over the 10 bundled pairs
   (data/records/pairs), on the ground, mu = 0.05, 0.1, 0.2 (mu_s = mu_k): median, min and max
   of the ratio, and the peak's direction.

Usage::

    python scripts/bench_plane.py
"""

from __future__ import annotations

import time

import numpy as np
from _common import ROOT, markdown_table

import floorslide as fs

PAIRS = ROOT / "data" / "records" / "pairs" / "index.csv"


def fastest(fn, repeat: int = 5) -> float:
    """The shortest wall time of `fn()` over `repeat` runs after a warm-up, s."""
    fn()
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return float(best)


def throughput() -> list[list[str]]:
    (p,) = fs.read_pairs(PAIRS, where={"rsn": "1084"})
    building = fs.ShearBuilding.from_period(3, 0.4)
    rows = []
    for where, kw in (
        ("ground", {}),
        ("roof, 3 storeys, 0.4 s", {"building": building, "floor": 3}),
    ):
        for n in (1, 10, 100):
            mus = np.linspace(0.03, 0.4, n) if n > 1 else np.array([0.1])
            t2 = fastest(
                lambda mus=mus, kw=kw: fs.slide_plane(p, None, mus, compare_1d=False, **kw)
            )
            t1 = fastest(
                lambda mus=mus, kw=kw: (
                    fs.slide(p.h1, p.dt, mus, **kw),
                    fs.slide(p.h2, p.dt, mus, **kw),
                )
            )
            rows.append(
                [
                    where,
                    str(n),
                    f"{t2 * 1e3:.1f} ms",
                    f"{n * p.npts / t2:.2e}",
                    f"{t1 * 1e3:.1f} ms",
                    f"{t2 / t1:.1f}",
                ]
            )
    return rows


def ratios() -> list[list[str]]:
    pairs = fs.read_pairs(PAIRS)
    mus = np.array([0.05, 0.1, 0.2])
    got = np.array([fs.slide_plane(p, None, mus).ratio_2d_1d for p in pairs])
    rows = []
    for j, mu in enumerate(mus):
        col = got[:, j]
        ok = col[np.isfinite(col)]
        rows.append(
            [
                f"{mu:g}",
                f"{ok.size}/{len(pairs)}",
                f"{np.median(ok):.2f}",
                f"{ok.min():.2f}",
                f"{ok.max():.2f}",
                f"{np.sum(ok > 1.0 + 1e-9)}",
            ]
        )
    return rows


def main() -> None:
    print(
        markdown_table(
            ["floor", "blocks", "2-D time", "2-D block·steps/s", "two 1-D runs", "2-D / (two 1-D)"],
            throughput(),
        )
    )
    print()
    print(
        markdown_table(
            [
                "mu",
                "pairs where a 1-D slide > 0",
                "2-D / max(1-D): median",
                "min",
                "max",
                "pairs where 2-D > max(1-D)",
            ],
            ratios(),
        )
    )


if __name__ == "__main__":
    main()
