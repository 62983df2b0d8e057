"""Throughput of floorslide's exact solvers against this machine's limit (issue 17).

Every case is timed through the public API, as a user calls it (input checks, set-up and the
compiled kernel), on bundled real records, one core (BLAS on one thread). Each rate is
``work / time`` — object·steps/s for sliding and rocking, oscillator·steps/s for spectra,
building·steps/s for a building alone — and is shown beside its target and as a share of the
*bare loop* measured in the same run: a dependent scalar recurrence ``x = a·x + b[i]``
compiled by numba, about the fastest a step-by-step loop can go on one core. Peers are timed
in the same process where installed (``pip install -e ".[bench]"``: pyrotd, eqsig).

``--cli`` adds the command line: ``floorslide --help``, ``inspect`` of one record, and the demo
warm (kernels in the disk cache) and fresh (an empty cache: every kernel it runs compiles),
each in a subprocess.

Usage::

    python scripts/bench_throughput.py [--quick] [--cli] [--out FILE.md]

Times are medians of repeated calls (``_common.timeit``); the machine is described at the top
of the output. Numbers on a loaded machine are lower: run it on a quiet one.
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import ROOT, markdown_table, record_4000, timeit
from numba import njit
from threadpoolctl import threadpool_limits

import floorslide as fs


@njit(cache=False)
def _bare(a, b):
    x = 0.0
    for i in range(b.size):
        x = a * x + b[i]
    return x


def bare_rate(n: int = 10_000_000) -> float:
    """Steps per second of the dependent scalar loop ``x = a·x + b[i]`` (numba)."""
    b = np.random.default_rng(0).standard_normal(n)
    _bare(0.5, b[:10])
    return n / timeit(lambda: _bare(0.5, b), repeat=7)


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    import numba

    return (
        f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, numba "
        f"{numba.__version__}, NumPy {np.__version__}, floorslide {fs.__version__}"
    )


def _pair():
    p = ROOT / "data" / "records" / "pairs"
    return fs.read_pair(p / "RSN1084_NORTHR_SCS052.AT2", p / "RSN1084_NORTHR_SCS142.AT2")


class Bench:
    """Collects the rows of the table."""

    def __init__(self, bare: float, quick: bool) -> None:
        self.bare = bare
        self.quick = quick
        self.rows: list[list] = []

    def add(self, case: str, work: float, seconds: float, target: float | None, note: str = ""):
        rate = work / seconds
        met = "" if target is None else ("met" if rate >= target else "not met")
        self.rows.append(
            [
                case,
                f"{seconds * 1e3:.3g} ms",
                f"{rate:.2e}",
                f"{rate / self.bare:.3f}",
                "—" if target is None else f"≥ {target:.1e}",
                met,
                note,
            ]
        )
        print(f"  {case}: {rate:.3e}/s ({seconds * 1e3:.3g} ms) {met} {note}", file=sys.stderr)

    def time(self, fn) -> float:
        return timeit(fn, repeat=3 if self.quick else 7)


def sliding(b: Bench) -> None:
    ag, dt = record_4000()
    n = ag.size
    long = np.tile(ag, 100)  # 399,900 samples: per-call set-up becomes negligible
    mu1 = 0.1
    b.add(
        "rigid block, ground, 1 object per call (4k samples)",
        n,
        b.time(lambda: fs.slide(ag, dt, mu1)),
        1.3e8,
    )
    b.add(
        "rigid block, ground, 1 object per call (400k samples)",
        long.size,
        b.time(lambda: fs.slide(long, dt, mu1)),
        1.3e8,
    )
    for k in (100, 1000):
        mu = np.linspace(0.02, 0.5, k)
        b.add(
            f"rigid block, ground, {k} objects",
            n * k,
            b.time(lambda mu=mu: fs.slide(ag, dt, mu)),
            3e8,
        )
    mu = np.linspace(0.02, 0.5, 100)
    fixed = fs.ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    iso = fs.IsolatedBuilding(fixed, 1.0, 2.5, 0.10)
    b.add(
        "rigid block, 1-storey fixed roof (T = 0.2 s), 100 objects",
        n * 100,
        b.time(lambda: fs.slide(ag, dt, mu, building=fixed, floor=1)),
        5e7,
    )
    b.add(
        "rigid block, isolated roof (2.5 s, 10 %), 100 objects",
        n * 100,
        b.time(lambda: fs.slide(ag, dt, mu, building=iso, floor=1)),
        1.3e8,
    )
    for where, kw in (("ground", {}), ("fixed roof", dict(building=fixed, floor=1))):
        for k in (1, 10, 100):
            muk = np.linspace(0.05, 0.5, k) if k > 1 else 0.2

            def run(muk=muk, kw=kw):
                return fs.slide_oscillator(
                    ag, dt, mu=muk, frequency=5.0, damping=0.02, mass_ratio=1.0, **kw
                )

            b.add(
                f"2-DOF sliding oscillator, {where}, {k} mu (5 Hz, 2 %)",
                n * k,
                b.time(run),
                3e7,
            )


def spectra(b: Bench) -> None:
    ag, dt = record_4000()
    n = ag.size
    T = np.geomspace(0.02, 5.0, 100)
    Z = [0.02, 0.05]
    work = n * T.size * len(Z)
    t_ground = b.time(lambda: fs.response_spectrum(ag, dt, T, Z))
    peers = []
    try:
        import pyrotd

        t1 = b.time(lambda: pyrotd.calc_spec_accels(dt, ag, 1 / T, Z[0]))
        peers.append(f"pyrotd: 1 damping {t1 * 1e3:.3g} ms, 2 dampings {2 * t1 * 1e3:.3g} ms")
        peers.append(f"floorslide {2 * t1 / t_ground:.1f}× pyrotd at 2 dampings")
    except ImportError:
        peers.append("pyrotd not installed")
    try:
        import eqsig

        te = b.time(lambda: [eqsig.sdof.pseudo_response_spectra(ag, dt, T, xi=z) for z in Z])
        peers.append(f"eqsig {te * 1e3:.3g} ms ({te / t_ground:.1f}×)")
    except ImportError:
        pass
    b.add("spectra, ground, 100 periods × 2 damping", work, t_ground, 2e8, "; ".join(peers))
    try:
        import pyrotd

        t1 = b.time(lambda: fs.response_spectrum(ag, dt, T, Z[:1]))
        tp = b.time(lambda: pyrotd.calc_spec_accels(dt, ag, 1 / T, Z[0]))
        b.add(
            "spectra, ground, 100 periods × 1 damping",
            n * T.size,
            t1,
            2e8,
            f"pyrotd {tp * 1e3:.3g} ms: floorslide {tp / t1:.1f}× pyrotd",
        )
    except ImportError:
        pass
    fixed = fs.ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    iso = fs.IsolatedBuilding(fs.ShearBuilding.from_period(3, 0.4, 0.05), 1.0, 2.5, 0.10)
    rng = np.random.default_rng(1)
    for where, kw in (
        ("1-storey fixed roof", dict(building=fixed, floor=1)),
        ("3-storey isolated roof", dict(building=iso, floor=3)),
    ):
        cached = b.time(lambda kw=kw: fs.response_spectrum(ag, dt, T, Z, **kw))
        fresh = []
        for _ in range(3):
            Tn = T * (1 + 1e-9 * rng.random())  # a new grid: nothing cached
            t0 = time.perf_counter()
            fs.response_spectrum(ag, dt, Tn, Z, **kw)
            fresh.append(time.perf_counter() - t0)
        first = float(np.median(fresh))
        share = max(0.0, first - cached) / first
        b.add(
            f"spectra, {where}, 100 periods × 2 damping",
            work,
            cached,
            1e8,
            f"uncached call {first * 1e3:.3g} ms: set-up {100 * share:.0f} % of it (target ≤ 20 %)",
        )


def carried(b: Bench) -> None:
    """The targets issues 14–16 left to this one."""
    ag, dt = record_4000()
    n = ag.size
    pair = _pair()
    for k in (1, 100):
        mu = np.linspace(0.05, 0.5, k) if k > 1 else 0.2
        b.add(
            f"rigid block in the plane, ground, {k} objects (8,773 samples)",
            pair.h1.size * k,
            b.time(lambda mu=mu: fs.slide_plane((pair.h1, pair.h2), pair.dt, mu, compare_1d=False)),
            1e7,
        )
    for k in (1, 100):
        widths = np.linspace(0.1, 0.6, k) if k > 1 else 0.3
        b.add(
            f"rocking block, ground, {k} blocks (h = 1.5 m)",
            n * k,
            b.time(lambda w=widths: fs.rock(ag, dt, width=w, height=1.5)),
            5e7,
        )
    sup = fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.02)
    for name, iso in (
        ("lead-rubber", fs.BilinearIsolator(q_ratio=0.06, yield_disp=0.02, period=2.5)),
        ("friction pendulum", fs.FrictionPendulum(mu=0.06, period=3.0)),
    ):
        nb = fs.NonlinearIsolatedBuilding(sup, 1.0, iso)
        b.add(
            f"building on {name} isolation alone",
            n,
            b.time(lambda nb=nb: fs.isolator_response(nb, ag, dt)),
            2e7,
        )
        T = np.geomspace(0.02, 5.0, 60)
        b.add(
            f"floor spectrum on {name} isolation, roof, 60 periods",
            n * 60,
            b.time(
                lambda nb=nb, T=T: fs.response_spectrum(ag, dt, T, [0.05], building=nb, floor=1)
            ),
            None,
        )


def equipment(b: Bench) -> None:
    """The targets of issue 32: slide–rock blocks batched on the ground where they rock, and
    heavy equipment coupled with the roof of a 3-storey building."""
    ag, dt = record_4000()
    n = ag.size
    acc = 3.5 * ag  # strong enough that every block rocks
    k = 100
    lam = np.linspace(0.15, 0.6, k)
    W, H = lam * 1.5, np.full(k, 1.5)
    b.add(
        f"slide–rock blocks, ground, {k} blocks that rock (never slipping)",
        n * k,
        b.time(lambda: fs.slide_rock(acc, dt, W, H, 100.0)),
        1e7,
    )
    b.add(
        f"slide–rock blocks, ground, {k} blocks that rock and slide (mu_s 1.1 tan α)",
        n * k,
        b.time(lambda: fs.slide_rock(acc, dt, W, H, 1.02 * lam, mu_s=1.1 * lam)),
        1e7,
    )
    b.add(
        f"rocking blocks (fs.rock, full equation), ground, {k} blocks, same",
        n * k,
        b.time(lambda: fs.rock(acc, dt, W, H, method="nonlinear")),
        None,
        "the same blocks without friction: slide–rock's yardstick",
    )
    sup = fs.ShearBuilding.from_period(stories=3, period=0.5, damping=0.05)
    for mu, what in ((2.0, "mu 2: stuck"), (0.15, "mu 0.15: sliding")):
        b.add(
            f"heavy equipment (3 % of the roof) coupled, 3-storey roof, {what}",
            n,
            b.time(lambda mu=mu: fs.slide_coupled(ag, dt, mu, mass=0.03, building=sup, floor=3)),
            1e7,
        )


def _wall(cmd: list[str], env: dict | None = None, cwd: str | None = None) -> float:
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True, env=env, cwd=cwd)
    return time.perf_counter() - t0


def cli(rows: list[list]) -> None:
    exe = shutil.which("floorslide") or "floorslide"
    rec = ROOT / "data" / "records" / "slammer" / "Kobe_1995_KAK-000.txt"
    helps = [_wall([exe, "--help"]) for _ in range(5)]
    rows.append(["floorslide --help", f"{min(helps):.2f} s", "≤ 0.3 s"])
    ins = [_wall([exe, "inspect", str(rec), "--units", "g", "--dt", "0.01"]) for _ in range(3)]
    rows.append(["floorslide inspect (one record)", f"{min(ins):.2f} s", "≤ 0.8 s"])
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, FLOORSLIDE_CACHE_DIR=str(Path(tmp) / "cache"))
        env.pop("NUMBA_CACHE_DIR", None)
        fresh = _wall([exe, "demo", "-o", str(Path(tmp) / "demo")], env=env)
        warm = min(_wall([exe, "demo", "-o", str(Path(tmp) / "demo")], env=env) for _ in range(2))
    rows.append(["floorslide demo, fresh install (empty kernel cache)", f"{fresh:.1f} s", "≤ 30 s"])
    rows.append(["floorslide demo, warm", f"{warm:.1f} s", "≤ 8 s"])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    ap.add_argument("--cli", action="store_true", help="also time the command line (minutes)")
    ap.add_argument("--out", help="also write the tables to this Markdown file")
    args = ap.parse_args()
    with threadpool_limits(limits=1):
        bare = bare_rate()
        b = Bench(bare, args.quick)
        print("sliding …", file=sys.stderr)
        sliding(b)
        print("spectra …", file=sys.stderr)
        spectra(b)
        print("targets carried from issues 14–16 …", file=sys.stderr)
        carried(b)
        print("equipment (issue 32) …", file=sys.stderr)
        equipment(b)
    out = [
        f"Machine: {machine()}; {time.strftime('%Y-%m-%d')}.",
        "",
        f"Bare loop `x = a·x + b[i]` (numba): **{bare:.2e} steps/s**.",
        "",
        markdown_table(
            ["case", "time per call", "rate (/s)", "share of bare loop", "target", "", "notes"],
            b.rows,
        ),
    ]
    if args.cli:
        print("command line …", file=sys.stderr)
        rows: list[list] = []
        cli(rows)
        out += ["", markdown_table(["command", "wall time", "target"], rows)]
    text = "\n".join(out)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
