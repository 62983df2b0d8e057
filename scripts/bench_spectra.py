"""Benchmark: response spectra and floor response spectra, floorslide against pyrotd and eqsig.

100 periods (0.02–5 s, log-spaced) × 3 damping ratios × one 4,000-sample record, on the ground and
on the roof of a 3-storey isolated building. The peers get the record (or the exact floor samples
— what a user would export) and their error on PSA is measured against floorslide's exact result.
floorslide caches the set-up of a (periods, damping ratios, dt, floor) grid — a study reuses it
for every record —, so the first call on a new grid is timed too.
pyrotd and eqsig are optional (``pip install -e ".[bench]"``).

Usage::

    python scripts/bench_spectra.py
"""

from __future__ import annotations

import numpy as np
from _common import markdown_table, record_4000, timeit

import floorslide as fs
from floorslide.building.exact_motion import single_use_motion
from floorslide.spectra import core as spectra_core

T = np.geomspace(0.02, 5.0, 100)
Z = [0.02, 0.05, 0.1]


def peers(motion, dt):
    out = {}
    try:
        import pyrotd

        def run_pyrotd():
            return np.array([pyrotd.calc_spec_accels(dt, motion, 1 / T, z).spec_accel for z in Z])

        out["pyrotd 0.6 (frequency domain)"] = run_pyrotd
    except ImportError:
        pass
    try:
        import eqsig

        def run_eqsig():
            return np.array([eqsig.sdof.pseudo_response_spectra(motion, dt, T, xi=z)[2] for z in Z])

        out["eqsig 1.2 (Nigam–Jennings, peaks at samples)"] = run_eqsig
    except ImportError:
        pass
    return out


def main() -> None:
    ag, dt = record_4000()
    iso = fs.IsolatedBuilding(fs.ShearBuilding.from_period(3, 0.4, 0.05), 1.0, 2.5, 0.10)
    rows = []
    searched = []
    for where, kw in (("ground", {}), ("roof of 3-storey isolated", dict(building=iso, floor=3))):
        exact = fs.response_spectrum(ag, dt, T, Z, **kw)
        t_exact = timeit(lambda kw=kw: fs.response_spectrum(ag, dt, T, Z, **kw), repeat=5)
        n = T.size * len(Z) * ag.size
        rows.append(
            [where, "floorslide exact", f"{t_exact * 1e3:.1f}", f"{n / t_exact:.2e}", "0", "1"]
        )

        def first_call(kw=kw):
            spectra_core._kernel_data.cache_clear()
            fs.response_spectrum(ag, dt, T, Z, **kw)

        t_first = timeit(first_call, repeat=5)
        rows.append(
            [
                where,
                "floorslide exact, first call on a new grid (set-up not cached)",
                f"{t_first * 1e3:.1f}",
                f"{n / t_first:.2e}",
                "0",
                f"{t_first / t_exact:.2f}",
            ]
        )
        counts = np.zeros(2, dtype=np.int64)
        motion = single_use_motion(kw.get("building"), ag, dt, kw.get("floor"))
        spectra_core._exact(motion, np.asarray(T, float), np.asarray(Z, float), counts=counts)
        searched.append(f"{where}: {counts[0] / n:.2%}")
        methods = [("floorslide peaks at samples", dict(method="samples"))]
        methods += [
            (f"floorslide Newmark dt/{k}", dict(method="newmark", substeps=k)) for k in (1, 4)
        ]
        methods += [("floorslide FFT", dict(method="fft"))]
        if kw:
            methods += [("floorslide re-interpolated floor", dict(method="reinterpolated"))]
        for name, mkw in methods:
            t = timeit(
                lambda mkw=mkw, kw=kw: fs.response_spectrum(ag, dt, T, Z, **mkw, **kw), repeat=3
            )
            got = fs.response_spectrum(ag, dt, T, Z, **mkw, **kw).psa
            err = np.max(np.abs(got - exact.psa) / exact.psa)
            rows.append(
                [where, name, f"{t * 1e3:.1f}", f"{n / t:.2e}", f"{err:.1e}", f"{t / t_exact:.2f}"]
            )
        motion = fs.floor_motions(iso, ag, dt, floors=[3])[0] if kw else ag
        for name, fn in peers(motion, dt).items():
            t = timeit(fn, repeat=3)
            err = np.max(np.abs(fn() - exact.psa) / exact.psa)
            rows.append(
                [where, name, f"{t * 1e3:.1f}", f"{n / t:.2e}", f"{err:.1e}", f"{t / t_exact:.2f}"]
            )
    print(f"record: {ag.size} samples at dt = {dt} s; 100 periods × 3 damping ratios")
    print("oscillator·steps searched inside the step by the exact method:", "; ".join(searched))
    print(
        markdown_table(
            [
                "floor",
                "method",
                "ms",
                "oscillator·steps / s",
                "max rel. error of PSA",
                "time / exact",
            ],
            rows,
        )
    )


if __name__ == "__main__":
    main()
