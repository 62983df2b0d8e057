"""Benchmark: RotD50 / RotD100 spectra (Boore 2010), floorslide against pyrotd.

100 periods (0.01–10 s, log-spaced) × 1 and 2 damping ratios × 180 angles on one bundled PEER
pair (Northridge-01, Sylmar Converter Station 052/142: 8,773 samples at dt = 0.005 s), on the
ground and on the roof of a 5-storey building (1.0 s). floorslide: exact (peaks inside steps),
with and without the ordinary spectra of each direction beside it, and peaks at samples; the
first call on a new grid (set-up not cached) too. pyrotd (optional, ``pip install -e ".[bench]"``)
gets the record or the exact floor samples at the record's samples; its RotD100 is the largest of
its 180 angles, floorslide's the continuous maximum over all directions. Errors are relative to
floorslide's exact values.

Usage::

    python scripts/bench_rotd.py
"""

from __future__ import annotations

import numpy as np
from _common import ROOT, markdown_table, timeit

import floorslide as fs
from floorslide.records.pairs import read_pairs
from floorslide.spectra import core as spectra_core

T = np.geomspace(0.01, 10.0, 100)
ROOF = fs.ShearBuilding.from_period(5, 1.0)


def pyrotd_run(a1, a2, dt, Z):
    """pyrotd's RotD50 and RotD100 ``(len(Z), len(T))``, or None when it is not installed."""
    try:
        import pyrotd
    except ImportError:
        return None
    out = np.zeros((2, len(Z), T.size))
    for i, z in enumerate(Z):
        r = pyrotd.calc_rotated_spec_accels(dt, a1, a2, 1 / T, z, percentiles=[50, 100])
        for k, p in enumerate((50, 100)):
            sel = r[r.percentile == p]
            out[k, i] = sel.spec_accel[np.argsort(1 / sel.osc_freq)]
    return out


def main() -> None:
    pair = read_pairs(ROOT / "data" / "records" / "pairs" / "index.csv")[0]
    dt = pair.dt
    rows = []
    for where, kw in (("ground", {}), ("roof, 5-storey 1.0 s", dict(building=ROOF, floor=5))):
        for Z in ([0.05], [0.02, 0.05]):
            n = T.size * len(Z)
            exact = fs.rotd_spectrum(pair, periods=T, damping=Z, directions=False, **kw)

            def run(kw=kw, Z=Z, **more):
                return fs.rotd_spectrum(pair, periods=T, damping=Z, **kw, **more)

            def first(kw=kw, Z=Z):
                spectra_core._kernel_data.cache_clear()
                return fs.rotd_spectrum(pair, periods=T, damping=Z, directions=False, **kw)

            t_exact = timeit(lambda: run(directions=False), repeat=5)
            cases = [
                ("floorslide exact", t_exact, exact),
                ("floorslide exact, with h1/h2 spectra", timeit(run, repeat=5), exact),
                ("floorslide exact, first call (set-up not cached)", timeit(first, 3), exact),
            ]
            samples = run(directions=False, method="samples")
            t = timeit(lambda: run(directions=False, method="samples"), repeat=5)
            cases.append(("floorslide peaks at samples", t, samples))
            a1, a2 = pair.h1, pair.h2
            if kw:
                a1 = fs.floor_motions(ROOF, pair.h1, dt, floors=[5])[0]
                a2 = fs.floor_motions(ROOF, pair.h2, dt, floors=[5])[0]
            peer = pyrotd_run(a1, a2, dt, Z)
            if peer is not None:
                t = timeit(lambda a1=a1, a2=a2, Z=Z: pyrotd_run(a1, a2, dt, Z), repeat=3)
                got = type("R", (), dict(rotd50=peer[0], rotd100=peer[1]))
                cases.append(("pyrotd 0.6 (frequency domain)", t, got))
            for name, t, got in cases:
                e50 = np.abs(got.rotd50 / exact.rotd50 - 1)
                e100 = np.abs(got.rotd100 / exact.rotd100 - 1)
                rows.append(
                    [
                        where,
                        len(Z),
                        name,
                        f"{t * 1e3:.1f}",
                        f"{n / t:.0f}",
                        f"{e50.max():.1e} / {np.median(e50):.1e}",
                        f"{e100.max():.1e} / {np.median(e100):.1e}",
                    ]
                )
    print(
        f"pair: {pair.names[0]}/{pair.names[1]} ({pair.label.split('/')[-1]}), {pair.npts} samples"
        f" at dt = {dt} s;"
        f" {T.size} periods {T[0]:g}–{T[-1]:g} s; 180 angles"
    )
    print(
        markdown_table(
            [
                "floor",
                "damping ratios",
                "method",
                "ms",
                "oscillators / s",
                "RotD50 rel. error max / median",
                "RotD100 rel. error max / median",
            ],
            rows,
        )
    )


if __name__ == "__main__":
    main()
