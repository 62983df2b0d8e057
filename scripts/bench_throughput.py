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

    python scripts/bench_throughput.py [--quick] [--cli] [--only SECTIONS] [--out FILE.md]

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

    def add(
        self,
        case: str,
        work: float,
        seconds: float,
        target: float | None,
        note: str = "",
        share: float | None = None,
        peer: tuple[str, float, float] | None = None,
    ):
        """One row. `target` is a rate (/s); or `share`, a share of the bare loop (issue 34),
        with `peer` = (name, speed-up measured, speed-up required) judged beside it."""
        rate = work / seconds
        if share is not None:
            ok = rate / self.bare >= share and (peer is None or peer[1] >= peer[2])
            want = f"≥ {share:.2f} of bare" + (
                "" if peer is None else f", ≥ {peer[2]:g}× {peer[0]}"
            )
        else:
            ok = target is not None and rate >= target
            want = "—" if target is None else f"≥ {target:.1e}"
        met = "" if target is None and share is None else ("met" if ok else "not met")
        self.rows.append(
            [
                case,
                f"{seconds * 1e3:.3g} ms",
                f"{rate:.2e}",
                f"{rate / self.bare:.3f}",
                want,
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
        None,
        PROFILED,
        share=SHARE_FLOOR_BLOCKS,
    )
    b.add(
        "rigid block, isolated roof (2.5 s, 10 %), 100 objects",
        n * 100,
        b.time(lambda: fs.slide(ag, dt, mu, building=iso, floor=1)),
        None,
        share=SHARE_FLOOR_BLOCKS,
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
                None,
                PROFILED,
                share=SHARE_OSCILLATOR,
            )


def knet_record() -> tuple[np.ndarray, float]:
    """The bundled K-NET record (AOM008 N-S, off Aomori 2018, 100 Hz, 13,800 samples; raw:
    ``tests/data/raw/PROVENANCE.md``) in m/s², its mean (6 % of its PGA) removed as its
    quality flag ``offset`` advises: a record rich in high frequencies against its peak."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tr = fs.read_record(ROOT / "tests" / "data" / "raw" / "AOM0081801241951.NS")[0]
    acc = np.asarray(tr.data, float)
    return acc - acc.mean(), float(tr.stats.delta)


# issue 34, as shares of the bare loop: ground spectra (and at least 10× pyrotd on every record
# of the bench), floor spectra on linear buildings, floor spectra on nonlinear isolation
SHARE_GROUND, PYROTD_SPEEDUP, SHARE_FLOOR, SHARE_NONLINEAR = 0.33, 10.0, 0.10, 0.05
# the kernels' targets as shares of the bare loop ("Speed of the whole"); where one is not
# met, docs/site/kernel-profiles.md (scripts/profile_kernels.py) measures where the time goes
SHARE_FLOOR_BLOCKS, SHARE_OSCILLATOR, SHARE_PLANE = 0.10, 0.05, 0.02
SHARE_ROCKING, SHARE_BUILDING = 0.05, 0.03
PROFILED = "profile: docs/site/kernel-profiles.md"


def spectra(b: Bench) -> None:
    T = np.geomspace(0.02, 5.0, 100)
    Z = [0.02, 0.05]
    try:
        import pyrotd
    except ImportError:
        pyrotd = None
    try:
        import eqsig
    except ImportError:
        eqsig = None
    for label, (ag, dt) in (("Kobe KAK-000", record_4000()), ("K-NET AOM008", knet_record())):
        n = ag.size
        for nz in (2, 1):
            t = b.time(lambda nz=nz, ag=ag, dt=dt: fs.response_spectrum(ag, dt, T, Z[:nz]))
            notes, peer = [], None
            if pyrotd is not None:
                # pyrotd takes one damping ratio a call
                tp = nz * b.time(lambda ag=ag, dt=dt: pyrotd.calc_spec_accels(dt, ag, 1 / T, Z[0]))
                peer = ("pyrotd", tp / t, PYROTD_SPEEDUP)
                notes.append(f"pyrotd {tp * 1e3:.3g} ms: floorslide {tp / t:.1f}× pyrotd")
            else:
                notes.append("pyrotd not installed")
            if eqsig is not None and nz == 2:
                te = b.time(
                    lambda ag=ag, dt=dt: [
                        eqsig.sdof.pseudo_response_spectra(ag, dt, T, xi=z) for z in Z
                    ]
                )
                notes.append(f"eqsig {te * 1e3:.3g} ms ({te / t:.1f}×)")
            b.add(
                f"spectra, ground, {label} ({n:,} samples), 100 periods × {nz} damping",
                n * T.size * nz,
                t,
                None,
                "; ".join(notes),
                share=SHARE_GROUND,
                peer=peer,
            )
    ag, dt = record_4000()
    n = ag.size
    work = n * T.size * len(Z)
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
        part = max(0.0, first - cached) / first
        b.add(
            f"spectra, {where}, 100 periods × 2 damping",
            work,
            cached,
            None,
            f"uncached call {first * 1e3:.3g} ms: set-up {100 * part:.0f} % of it (target ≤ 20 %)",
            share=SHARE_FLOOR,
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
            None,
            PROFILED,
            share=SHARE_PLANE,
        )
    for k in (1, 100):
        widths = np.linspace(0.1, 0.6, k) if k > 1 else 0.3
        b.add(
            f"rocking block, ground, {k} blocks (h = 1.5 m)",
            n * k,
            b.time(lambda w=widths: fs.rock(ag, dt, width=w, height=1.5)),
            None,
            PROFILED,
            share=SHARE_ROCKING,
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
            None,
            PROFILED,
            share=SHARE_BUILDING,
        )
        T = np.geomspace(0.02, 5.0, 60)
        b.add(
            f"floor spectrum on {name} isolation, roof, 60 periods",
            n * 60,
            b.time(
                lambda nb=nb, T=T: fs.response_spectrum(ag, dt, T, [0.05], building=nb, floor=1)
            ),
            None,
            "the building included",
            share=SHARE_NONLINEAR,
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
    sections = {
        "sliding": ("sliding", sliding),
        "spectra": ("spectra", spectra),
        "carried": ("targets carried from issues 14–16", carried),
        "equipment": ("equipment (issue 32)", equipment),
    }
    ap.add_argument(
        "--only",
        help=f"comma-separated sections to run (of {', '.join(sections)}; default all)",
    )
    args = ap.parse_args()
    chosen = list(sections) if not args.only else [x.strip() for x in args.only.split(",")]
    unknown = [x for x in chosen if x not in sections]
    if unknown:
        ap.error(f"unknown section(s) {', '.join(unknown)}; expected {', '.join(sections)}")
    with threadpool_limits(limits=1):
        bare = bare_rate()
        b = Bench(bare, args.quick)
        for key in chosen:
            title, run = sections[key]
            print(f"{title} …", file=sys.stderr)
            run(b)
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
