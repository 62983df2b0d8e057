"""Benchmark: buildings on nonlinear isolation (lead-rubber, friction pendulum) against the same
superstructure on linear isolation, on one core.

1. The building alone (``fs.isolator_response``: every floor's true peak acceleration, the
   isolator's peak displacement and force): building·steps per second on the 4,000-sample
   record (set-up included, the building's matrices memoised after the first call) and on a
   400,000-sample record (the kernel's rate).
2. Rigid blocks on the roof, 1, 10 and 100 friction values: object·steps per second, and the
   same on the linear isolated roof (``fs.IsolatedBuilding``, same period, 10 % damping) —
   with mu 0.05–0.3 (they slide on the pendulum's roof, not on the linear one's: not the same
   work) and with mu 1–2 (no block slides anywhere: the same work, the cost of the building
   under them).
3. Floor response spectra on the roof, 60 periods 0.02–5 s, 5 %: time per record.

Usage::

    python scripts/bench_nonlinear_isolation.py
"""

from __future__ import annotations

import numpy as np
from _common import markdown_table, record_4000, timeit

import floorslide as fs


def main() -> None:
    ag, dt = record_4000()
    long = np.tile(ag, 100)
    sup = fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.03)
    layers = {
        "lead-rubber (Q/W 0.06, D_y 20 mm, T_d 2.5 s)": fs.BilinearIsolator(
            q_ratio=0.06, period=2.5, yield_disp=0.02
        ),
        "friction pendulum (mu 0.06, T 3 s)": fs.FrictionPendulum(mu=0.06, period=3.0),
    }
    linear = fs.IsolatedBuilding(sup, 1.0, period=3.0, damping=0.10)
    rows = []
    for name, iso in layers.items():
        b = fs.NonlinearIsolatedBuilding(sup, 1.0, iso)
        t = timeit(lambda b=b: fs.isolator_response(b, ag, dt), repeat=5)
        t_long = timeit(lambda b=b: fs.isolator_response(b, long, dt), repeat=3)
        rows.append(
            [
                name,
                "building alone",
                f"{t * 1e3:.2f} ms",
                f"{ag.size / t:.2e} (4,000 samples); {long.size / t_long:.2e} (400,000)",
            ]
        )
    for lo, hi in ((0.05, 0.3), (1.0, 2.0)):
        for n in (1, 10, 100):
            mus = np.linspace(lo, hi, n)
            for name, b in [("linear isolation (T 3 s, 10 %)", linear)] + [
                (k, fs.NonlinearIsolatedBuilding(sup, 1.0, v)) for k, v in layers.items()
            ]:
                t = timeit(
                    lambda b=b, mus=mus: fs.slide(ag, dt, mus, building=b, floor=1), repeat=3
                )
                slips = int(fs.slide(ag, dt, mus, building=b, floor=1).slip_phases.sum())
                rows.append(
                    [
                        name,
                        f"{n} blocks on the roof, mu {lo:g}–{hi:g} ({slips} slip phases)",
                        f"{t * 1e3:.2f} ms",
                        f"{n * ag.size / t:.2e}",
                    ]
                )
    periods = np.geomspace(0.02, 5.0, 60)
    for name, b in [("linear isolation (T 3 s, 10 %)", linear)] + [
        (k, fs.NonlinearIsolatedBuilding(sup, 1.0, v)) for k, v in layers.items()
    ]:
        t = timeit(
            lambda b=b: fs.response_spectrum(ag, dt, periods, [0.05], building=b, floor=1),
            repeat=3,
        )
        rows.append(
            [name, "roof spectrum, 60 periods", f"{t * 1e3:.1f} ms", f"{60 * ag.size / t:.2e}"]
        )
    print(markdown_table(["building", "case", "time per record", "rate (·steps/s)"], rows))


if __name__ == "__main__":
    main()
