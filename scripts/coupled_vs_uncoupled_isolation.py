"""What the uncoupled model misses: a building on friction pendulums under the bundled record
pairs, its bearings coupled in the plane (the friction circle:
:func:`floorslide.building.plane_isolation.plane_isolator_response`) against the per-direction
(uncoupled) model — each direction's 1-D building under its own component, as if the bearing
had a friction force of its own along each axis.

For each pair: peak bearing displacement and roof PFA (the vector's peak at the samples), the
roof PSA (5 %) along h1 and h2 at 0.2, 0.5 and 1 s, and the peak slide of rigid blocks on the
roof (mu 0.05, 0.1: coupled, blocks in the plane on the coupled roof motion; uncoupled, the
larger of the two directions' 1-D slides on their own roofs). Prints a Markdown table of the
ratios uncoupled / coupled (median and range over the pairs). Usage::

    python scripts/coupled_vs_uncoupled_isolation.py [--scale 1.0]
"""

from __future__ import annotations

import argparse
import dataclasses
import warnings

import numpy as np
from _common import ROOT

import floorslide as fs
from floorslide.building.plane_isolation import PlaneIsolatedMotion
from floorslide.errors import FloorslideError
from floorslide.spectra.poly_segments import spectrum_on_poly

PERIODS = [0.2, 0.5, 1.0]
MUS = [0.05, 0.1]
ROOF = 3


def compare(b, pair) -> dict[str, list[float]]:
    """Ratios uncoupled / coupled for one pair (a list per quantity)."""
    h1, h2, dt = pair.h1, pair.h2, pair.dt
    motion = PlaneIsolatedMotion(b, h1, h2, dt)
    r = motion.response
    one = [fs.isolator_response(b, a, dt) for a in (h1, h2)]
    out: dict[str, list[float]] = {}
    coupled = np.hypot(r.displacement[:, 0], r.displacement[:, 1]).max()
    un = np.hypot(one[0].isolator_displacement, one[1].isolator_displacement).max()
    out["peak bearing displacement"] = [un / coupled]
    acc = r.floor_acceleration[:, ROOF]
    un_acc = [fs.floor_motions(b, a, dt, floors=[ROOF])[0] for a in (h1, h2)]
    out["roof PFA"] = [np.hypot(*un_acc).max() / np.hypot(acc[:, 0], acc[:, 1]).max()]
    for d, a in enumerate((h1, h2)):
        spc = spectrum_on_poly(motion, ROOF, PERIODS, direction=d)
        spu = fs.response_spectrum(a, dt, PERIODS, 0.05, building=b, floor=ROOF)
        for i, T in enumerate(PERIODS):
            out.setdefault(f"roof PSA {T:g} s", []).append(spu.psa[0, i] / spc.psa[0, i])
    plane = fs.slide_plane((h1, h2), dt, MUS, building=b, floor=ROOF, compare_1d=False)
    lines = [fs.slide(a, dt, MUS, building=b, floor=ROOF).peak_slide for a in (h1, h2)]
    for i, mu in enumerate(MUS):
        un = max(lines[0][i], lines[1][i])
        if plane.peak_slide[i] > 1e-3:  # ratios of slides under 1 mm say little
            out.setdefault(f"roof slide mu {mu:g}", []).append(un / plane.peak_slide[i])
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scale", type=float, default=1.0, help="scale of every pair")
    args = ap.parse_args()
    sup = fs.ShearBuilding.from_period(stories=ROOF, period=0.4, damping=0.03)
    b = fs.NonlinearIsolatedBuilding(sup, 1.0, fs.FrictionPendulum(mu=0.06, period=3.0))
    pairs = fs.read_pairs(ROOT / "data" / "records" / "pairs" / "index.csv")
    ratios: dict[str, list[float]] = {}
    failed = []
    for p in pairs:
        p = dataclasses.replace(p, h1=args.scale * p.h1, h2=args.scale * p.h2)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                got = compare(b, p)
        except FloorslideError as exc:
            failed.append(f"{p.label or p.names[0]}: {exc}")
            continue
        for k, v in got.items():
            ratios.setdefault(k, []).extend(v)
    print(
        f"friction pendulum mu 0.06, T 3 s under a 3-storey superstructure (T 0.4 s); "
        f"{len(pairs) - len(failed)} of {len(pairs)} bundled pairs ×{args.scale:g}\n"
    )
    print("| quantity | median uncoupled/coupled | range | n |")
    print("|---|---|---|---|")
    for k, v in ratios.items():
        v = np.asarray(v)
        print(f"| {k} | {np.median(v):.3f} | {v.min():.3f}–{v.max():.3f} | {v.size} |")
    for f in failed:
        print(f"\nnot run: {f}")


if __name__ == "__main__":
    main()
