"""Benchmark: floor motions of a 3-storey isolated building under a 4,000-sample record.

All floors (4 outputs). For each method: time per record and relative error (max over floors
and samples, and on the true PFA) against the exact method. Usage::

    python scripts/bench_floor_motions.py
"""

from __future__ import annotations

import numpy as np
from _common import markdown_table, record_4000, timeit

import floorslide as fs


def main() -> None:
    ag, dt = record_4000()
    iso = fs.IsolatedBuilding(fs.ShearBuilding.from_period(3, 0.4, 0.05), 1.0, 2.5, 0.10)
    exact = fs.floor_motions(iso, ag, dt)
    pfa = fs.peak_floor_acceleration(iso, ag, dt).peak
    n_out = exact.shape[0]
    rows = []
    cases = [("exact (FOH)", dict(method="exact"))]
    cases += [("zero-order hold", dict(method="zoh"))]
    cases += [(f"Newmark avg. acc. dt/{k}", dict(method="newmark", substeps=k)) for k in (1, 4, 16)]
    cases += [("python-control forced_response", dict(method="forced_response"))]
    for name, kw in cases:
        t = timeit(lambda kw=kw: fs.floor_motions(iso, ag, dt, **kw), repeat=5)
        y = fs.floor_motions(iso, ag, dt, **kw)
        err = np.abs(y - exact).max() / np.abs(exact).max()
        pfa_err = np.abs(np.abs(y).max(axis=1) - pfa).max() / pfa.max()
        rows.append(
            [name, f"{t * 1e3:.3f}", f"{ag.size * n_out / t:.2e}", f"{err:.1e}", f"{pfa_err:.1e}"]
        )
    t = timeit(lambda: fs.peak_floor_acceleration(iso, ag, dt), repeat=5)
    rows.append(
        ["true PFA inside steps (exact)", f"{t * 1e3:.3f}", f"{ag.size * n_out / t:.2e}", "—", "0"]
    )
    print(
        f"record: {ag.size} samples, dt = {dt} s; building: 3 storeys on isolation, {n_out} floors"
    )
    print(
        markdown_table(
            ["method", "ms / record", "samples·outputs / s", "max rel. error", "PFA rel. error"],
            rows,
        )
    )


if __name__ == "__main__":
    main()
