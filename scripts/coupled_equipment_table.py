"""What the decoupled assumption misses for heavy equipment: a rigid block on the roof of a
3-storey building that acts back on its floor (:func:`floorslide.slide_coupled`: sticking, it
adds its mass; sliding, it loads the floor with its friction) against the usual decoupled
analysis (the building alone, the block sliding on its roof motion: :func:`floorslide.slide`).

Buildings: fixed base, 3 storeys, T = 0.5 s, 5 % damping, 100 t per floor; the same on a linear
isolation layer (base mat 100 % of the superstructure's mass, T_i = 2.5 s, 10 %). Block masses:
0.1 %, 1 %, 3 %, 10 %, 30 % of the roof's mass. Friction ``mu_k = mu_s`` = half the decoupled
roof PFA over g for each record and building, so that every block slides. For each building and
mass ratio, the median (and range) over the records of the ratios coupled / decoupled of the
peak slide and of the roof's PFA (true peaks inside steps, with and without the block), and the
median ratio of the roof's floor spectrum (PSA, 5 %) at 0.2, 0.5 and 1 s with and without the
block — both spectra from the roof's acceleration at the samples (:func:`floorslide.
response_spectrum` on them: sample-based on both sides, so the ratio compares like with like).
Prints Markdown, then the solver's speed on a whole record. Usage::

    python scripts/coupled_equipment_table.py [--records N]
"""

from __future__ import annotations

import argparse

import numpy as np
from _common import markdown_table, slammer, timeit

import floorslide as fs

RECORDS = [
    "ImperialValley_1940_ELC-180.txt",
    "Northridge_1994_RRS-228.txt",
    "CapeMendocino_1992_PET-090.txt",
    "Landers_1992_YER-270.txt",
    "Kobe_1995_KAK-000.txt",
]
RATIOS = [0.001, 0.01, 0.03, 0.1, 0.3]
PERIODS = [0.2, 0.5, 1.0]
FLOOR_MASS = 1.0e5
ROOF = 3


def buildings() -> dict[str, fs.ShearBuilding | fs.IsolatedBuilding]:
    fixed = fs.ShearBuilding.from_period(ROOF, 0.5, damping=0.05, mass=FLOOR_MASS)
    return {"fixed, T = 0.5 s": fixed, "isolated, T_i = 2.5 s": fs.IsolatedBuilding(fixed)}


def ratios(b, a, dt) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """mu, and per mass ratio coupled / decoupled peak slide, roof PFA and roof PSA at
    :data:`PERIODS` (``(ratios, periods)``), for one record."""
    pfa = fs.peak_floor_acceleration(b, a, dt, floors=[ROOF]).peak[0]
    mu = 0.5 * pfa / fs.G
    dec = fs.slide(a, dt, mu, building=b, floor=ROOF).peak_slide[0]
    r = fs.slide_coupled(a, dt, mu, mass=np.array(RATIOS) * FLOOR_MASS, building=b, floor=ROOF,
                         histories=True)  # fmt: skip
    slide = r.peak_slide / dec
    alone = fs.floor_motions(b, a, dt, floors=[ROOF])[0]
    psa0 = fs.response_spectrum(alone, dt, PERIODS, 0.05).psa[0]
    psa = np.array(
        [fs.response_spectrum(f, dt, PERIODS, 0.05).psa[0] for f in r.floor_acceleration]
    )
    return mu, slide, r.pfa / pfa, psa / psa0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=len(RECORDS), help="how many records")
    args = ap.parse_args()
    records = [(name, *slammer(name)) for name in RECORDS[: args.records]]
    rows = []
    for label, b in buildings().items():
        slides, pfas, psas, mus = [], [], [], []
        for _name, a, dt in records:
            mu, s, p, q = ratios(b, a, dt)
            mus.append(mu)
            slides.append(s)
            pfas.append(p)
            psas.append(q)
        slides, pfas, psas = np.array(slides), np.array(pfas), np.array(psas)
        for i, ratio in enumerate(RATIOS):
            rows.append(
                [
                    label,
                    f"{100 * ratio:g} %",
                    f"{np.median(slides[:, i]):.3f} ({slides[:, i].min():.3f}–"
                    f"{slides[:, i].max():.3f})",
                    f"{np.median(pfas[:, i]):.3f} ({pfas[:, i].min():.3f}–{pfas[:, i].max():.3f})",
                    *(f"{np.median(psas[:, i, j]):.3f}" for j in range(len(PERIODS))),
                ]
            )
        print(f"{label}: mu = {', '.join(f'{m:.3f}' for m in mus)} ({len(records)} records)")
    print()
    header = ["building", "m / M_roof", "peak slide coupled/decoupled", "roof PFA coupled/alone"]
    header += [f"roof PSA {T:g} s coupled/alone" for T in PERIODS]
    print(markdown_table(header, rows))
    print()
    # speed: one block on the roof, a whole record
    a, dt = slammer("Kobe_1995_KAK-000.txt")
    for label, b in buildings().items():
        t = timeit(lambda b=b: fs.slide_coupled(a, dt, 0.1, mass=0.1 * FLOOR_MASS, building=b,
                                                 floor=ROOF))  # fmt: skip
        r = fs.slide_coupled(a, dt, 0.1, mass=0.1 * FLOOR_MASS, building=b, floor=ROOF)
        print(
            f"speed, {label}: {a.size - 1} steps (dt {dt:g} s, {r.substeps} sub-steps) in "
            f"{1e3 * t:.2f} ms: {(a.size - 1) / t:,.0f} steps/s"
        )


if __name__ == "__main__":
    main()
