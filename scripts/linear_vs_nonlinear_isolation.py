"""What the equivalent-linear model misses: buildings on lead-rubber and friction-pendulum
isolation against their equivalent-linear models (secant stiffness and loop-energy damping at
the peak isolator displacement of each record), on bundled records scaled ×1.5.

For each record and layer: peak isolator displacement, roof PFA, roof PSA (5 %) at 0.2, 0.5 and
1 s, and peak slides of rigid blocks on the roof (mu 0.05, 0.1), nonlinear and linear, and
their ratios linear/nonlinear (median over records). Prints a Markdown table. Usage::

    python scripts/linear_vs_nonlinear_isolation.py
"""

from __future__ import annotations

import warnings

import numpy as np
from _common import slammer

import floorslide as fs

RECORDS = [
    "ImperialValley_1940_ELC-180.txt",
    "KernCounty_1952_TAF-021.txt",
    "Landers_1992_LCN-260.txt",
    "Northridge_1994_RRS-228.txt",
    "Kobe_1995_TAK-000.txt",
    "LomaPrieta_1989_STG-000.txt",
]
PERIODS = [0.2, 0.5, 1.0]
MUS = [0.05, 0.1]


def main() -> None:
    sup = fs.ShearBuilding.from_period(stories=3, period=0.4, damping=0.03)
    layers = {
        "lead-rubber (Q/W 0.06, D_y 20 mm, T_d 2.5 s)": fs.BilinearIsolator(
            q_ratio=0.06, period=2.5, yield_disp=0.02
        ),
        "friction pendulum (mu 0.06, T 3 s)": fs.FrictionPendulum(mu=0.06, period=3.0),
    }
    print("| layer | quantity | median linear/nonlinear | range |")
    print("|---|---|---|---|")
    for name, iso in layers.items():
        b = fs.NonlinearIsolatedBuilding(sup, 1.0, iso)
        ratios: dict[str, list[float]] = {}
        for rec in RECORDS:
            ag, dt = slammer(rec)
            ag = 1.5 * ag
            nl = fs.isolator_response(b, ag, dt, floors=[3])
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                lin = b.equivalent_linear(nl.peak_displacement)
            lin_pfa = fs.peak_floor_acceleration(lin, ag, dt, floors=[3]).peak[0]
            iso_peak = np.abs(fs.floor_motions(lin, ag, dt, output="isolator")).max()
            vals = {
                "peak isolator displacement": (nl.peak_displacement, iso_peak),
                "roof PFA": (nl.pfa[0], lin_pfa),
            }
            spn = fs.response_spectrum(ag, dt, PERIODS, 0.05, building=b, floor=3)
            spl = fs.response_spectrum(ag, dt, PERIODS, 0.05, building=lin, floor=3)
            for j, T in enumerate(PERIODS):
                vals[f"roof PSA at {T:g} s"] = (spn.psa[0, j], spl.psa[0, j])
            sn = fs.slide(ag, dt, MUS, building=b, floor=3)
            sl = fs.slide(ag, dt, MUS, building=lin, floor=3)
            for j, mu in enumerate(MUS):
                vals[f"roof slide, mu {mu:g}"] = (sn.peak_slide[j], sl.peak_slide[j])
            for key, (a, c) in vals.items():
                if a > 0:
                    ratios.setdefault(key, []).append(c / a)
        for key, r in ratios.items():
            print(f"| {name} | {key} | {np.median(r):.2f} | {min(r):.2f}–{max(r):.2f} |")


if __name__ == "__main__":
    main()
