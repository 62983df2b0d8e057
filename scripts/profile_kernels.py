"""Where the time of the kernels below their throughput targets goes (issue 34, part 3).

Each unmet case of ``scripts/bench_throughput.py`` (built the same way, through the public API)
is decomposed into

1. **per call**: the cost that does not scale with the record (input checks, set-up,
   allocation, the result) — the time of a call on a 3-sample record;
2. **quiet path**: ns per object·step on the same record scaled down until nothing happens
   (blocks stuck, oscillators stuck and elastic, blocks not rocking, isolators elastic or
   stuck), and the share of the bare loop it reaches: the kernel's ceiling without events;
3. **per event**: the real record's time above the quiet path, divided by the events the
   result counts (slip phases, impacts and uplifts, isolator branch changes) — so each
   "event" carries everything its phase costs beyond a quiet step (the search for its start
   and end, the closed-form or general steps in between);
4. **breakdowns** of the quiet path by variants (1 vs many objects, the floor motion alone,
   sub-steps per record step).

Shares are of the *bare loop* ``x = a·x + b[i]`` (numba) timed in the same run, as in
``bench_throughput.py``. One core (BLAS on one thread).

Usage::

    python scripts/profile_kernels.py [--quick] [--out FILE.md]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np
from _common import markdown_table, record_4000, timeit
from bench_throughput import _pair, bare_rate, machine
from threadpoolctl import threadpool_limits

import floorslide as fs
from floorslide.building.exact_motion import building_motion

SHORT = 3  # samples of the "per call" record
QUIET = 1e-3  # scale of the record on which nothing happens


def _load() -> str:
    try:
        return ", ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "n/a"


class Case:
    """One benchmark case: ``run(acc) -> result`` on a record ``acc`` (samples of the case's
    ``dt``), ``objects`` per step, and ``events(result)``: the events the result counts."""

    def __init__(self, name, run, acc, objects, events, target, what, busy=None, quiet=QUIET):
        self.name, self.run, self.acc, self.objects = name, run, acc, objects
        self.events, self.target, self.what, self.quiet = events, target, what, quiet
        self.busy = busy
        """``busy(result, steps)``: the object·steps spent moving (sliding, rocking), or None."""


class Profiler:
    def __init__(self, bare: float, quick: bool) -> None:
        self.bare = bare
        self.quick = quick
        self.rows: list[list] = []
        self.found: dict[str, dict] = {}
        self.bares: list[float] = [bare]

    def time(self, fn) -> float:
        return timeit(fn, repeat=3 if self.quick else 7)

    def bare_now(self) -> float:
        """The bare loop's rate now (the machine is shared: each case is compared with the
        bare loop measured beside it), kept in ``self.bare`` and ``self.bares``."""
        self.bare = bare_rate(2_000_000)
        self.bares.append(self.bare)
        return self.bare

    def share(self, ns_per_step: float) -> float:
        """Share of the bare loop of a cost of `ns_per_step` per object·step."""
        return 1e9 / ns_per_step / self.bare

    def profile(self, c: Case) -> dict:
        a = c.acc
        steps = len(a) - 1
        quiet = c.quiet * a
        before = self.bare_now()
        t_short = self.time(lambda: c.run(a[:SHORT].copy()))
        t_quiet = self.time(lambda: c.run(quiet))
        t_real = self.time(lambda: c.run(a))
        e_quiet = c.events(c.run(quiet))
        r_real = c.run(a)
        e_real = c.events(r_real)
        busy = c.busy(r_real, steps) if c.busy else None
        work = steps * c.objects
        self.bare = 0.5 * (before + bare_rate(2_000_000))  # the mean of both sides
        # per call: the short record less its own steps at the quiet rate (a fixed point)
        q = t_quiet / work
        for _ in range(3):
            per_call = max(t_short - (SHORT - 1) * c.objects * q, 0.0)
            q = (t_quiet - per_call) / work
        ns_q = q * 1e9
        ns_event = (t_real - t_quiet) / e_real * 1e9 if e_real else float("nan")
        d = dict(
            per_call=per_call,
            ns_quiet=ns_q,
            share_quiet=self.share(ns_q),
            share_quiet_call=work / t_quiet / self.bare,
            share_real=work / t_real / self.bare,
            events=e_real,
            events_quiet=e_quiet,
            rate_events=e_real / work,
            ns_event=ns_event,
            t_real=t_real,
            t_quiet=t_quiet,
            event_share=(t_real - t_quiet) / t_real,
            call_share=per_call / t_real,
            busy=busy,
            ns_busy=(t_real - t_quiet) / busy * 1e9 if busy else float("nan"),
        )
        self.found[c.name] = d
        self.rows.append(
            [
                c.name,
                f"{self.bare:.2e}",
                f"{100 * c.target:.0f} %",
                f"{100 * d['share_real']:.2f} %",
                f"{per_call * 1e6:.0f} µs ({100 * d['call_share']:.0f} %)",
                f"{ns_q:.1f}",
                f"{100 * d['share_quiet']:.2f} %",
                f"{e_real:,} {c.what}" + (f" (quiet: {e_quiet})" if e_quiet else ""),
                f"{d['rate_events']:.2e}",
                f"{ns_event:,.0f} ({100 * d['event_share']:.0f} %)",
                "—" if busy is None else f"{busy / work:.3f}: {d['ns_busy']:.0f}",
            ]
        )
        print(
            f"  {c.name}: real {100 * d['share_real']:.2f} %, per call {per_call * 1e6:.0f} µs, "
            f"quiet {ns_q:.1f} ns ({100 * d['share_quiet']:.2f} %), {e_real} events, "
            f"{ns_event:.0f} ns/event",
            file=sys.stderr,
        )
        return d


# ---- the cases (as in bench_throughput.py) -------------------------------------------------


def _slips(r) -> int:
    return int(np.sum(r.slip_phases))


def _rock_events(r) -> int:
    print(
        f"    rock: {int(np.sum(r.uplifts))} uplifts, {int(np.sum(r.impacts))} impacts "
        f"({int(np.sum(r.significant_impacts))} significant)",
        file=sys.stderr,
    )
    return int(np.sum(r.impacts) + np.sum(r.uplifts))


def _sliding(r, steps) -> float:
    return float(np.sum(r.slide_fraction)) * steps


def cases() -> list[Case]:
    ag, dt = record_4000()
    out = []
    fixed = fs.ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    mu = np.linspace(0.02, 0.5, 100)
    out.append(
        Case(
            "floor blocks, 1-storey fixed roof (T = 0.2 s), 100 objects",
            lambda a, mu=mu: fs.slide(a, dt, mu, building=fixed, floor=1),
            ag,
            100,
            _slips,
            0.10,
            "slip phases",
            _sliding,
        )
    )
    for where, kw in (("ground", {}), ("fixed roof", dict(building=fixed, floor=1))):
        for k in (1, 10, 100):
            muk = np.linspace(0.05, 0.5, k) if k > 1 else 0.2

            def run(a, muk=muk, kw=kw):
                return fs.slide_oscillator(
                    a, dt, mu=muk, frequency=5.0, damping=0.02, mass_ratio=1.0, **kw
                )

            out.append(
                Case(
                    f"2-DOF sliding oscillator, {where}, {k} mu",
                    run,
                    ag,
                    k,
                    _slips,
                    0.05,
                    "slip phases",
                    _sliding,
                )
            )
    pair = _pair()
    A2 = np.stack([pair.h1, pair.h2])
    for k in (1, 100):
        mu = np.linspace(0.05, 0.5, k) if k > 1 else 0.2
        out.append(
            Case(
                f"rigid block in the plane, ground, {k} objects (8,773 samples)",
                lambda a, mu=mu: fs.slide_plane((a[0], a[1]), pair.dt, mu, compare_1d=False),
                A2.T,  # time first, so that a[:n] is a short record
                k,
                _slips,
                0.02,
                "slip phases",
                _sliding,
            )
        )
    for k in (1, 100):
        widths = np.linspace(0.1, 0.6, k) if k > 1 else 0.3
        out.append(
            Case(
                f"rocking blocks (fs.rock), ground, {k} blocks (h = 1.5 m)",
                lambda a, w=widths: fs.rock(a, dt, width=w, height=1.5),
                ag,
                k,
                _rock_events,
                0.05,
                "uplifts + impacts",
                lambda r, steps: float(np.sum(r.rocking_time)) / dt,
            )
        )
    sup = fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.02)
    for name, iso in (
        ("lead-rubber", fs.BilinearIsolator(q_ratio=0.06, yield_disp=0.02, period=2.5)),
        ("friction pendulum", fs.FrictionPendulum(mu=0.06, period=3.0)),
    ):
        nb = fs.NonlinearIsolatedBuilding(sup, 1.0, iso)
        out.append(
            Case(
                f"building on {name} isolation alone",
                lambda a, nb=nb: fs.isolator_response(nb, a, dt),
                ag,
                1,
                lambda r: len(r.event_times),
                0.03,
                "branch changes",
            )
        )
    return out


def _plane_fix(c: Case) -> Case:
    """The plane's record is kept time-first (``(n, 2)``) so that slicing shortens it; the
    call gets the two components as C-ordered rows."""
    run = c.run
    c.run = lambda a: run(np.ascontiguousarray(a.T))
    return c


# ---- breakdowns of the quiet path ----------------------------------------------------------


def breakdowns(p: Profiler) -> list[list]:
    ag, dt = record_4000()
    steps = ag.size - 1
    q = QUIET * ag
    rows: list[list] = []

    def row(what, seconds, work, note=""):
        p.bare_now()
        ns = seconds / work * 1e9
        rows.append(
            [
                what,
                f"{seconds * 1e3:.3g} ms",
                f"{ns:.1f}",
                f"{p.bare:.2e}",
                f"{100 * p.share(ns):.2f} %",
                note,
            ]
        )
        print(f"  {what}: {ns:.1f} ns per unit", file=sys.stderr)

    fixed = fs.ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    fm = fs.floor_motion(fixed, ag, 1, dt)
    m = fm.substeps
    row(
        "fixed roof T = 0.2 s: the floor motion alone (streamed states, as slide builds it)",
        p.time(
            lambda: [None for _ in building_motion(fixed, ag, dt, max_bytes=0).floor(1).chunks()]
        ),
        steps,
        f"per record step; {m} sub-steps per record step",
    )
    for k in (1, 10, 100):
        mu = np.linspace(0.02, 0.5, k) if k > 1 else 0.5
        row(
            f"fixed roof, {k} blocks stuck (quiet), per object·step",
            p.time(lambda mu=mu: fs.slide(q, dt, mu, building=fixed, floor=1)),
            steps * k,
        )
    mu = np.linspace(0.02, 0.5, 100)
    fmq = fs.floor_motion(fixed, q, 1, dt)
    row(
        "fixed roof, 100 blocks stuck, on a FloorMotion built once (kernel only)",
        p.time(lambda: fs.slide(fmq, mu_k=mu)),
        steps * 100,
        "per object·step",
    )
    row(
        "fixed roof, 100 blocks real record, on a FloorMotion built once",
        p.time(lambda: fs.slide(fm, mu_k=mu)),
        steps * 100,
        "per object·step",
    )
    row(
        "ground, 100 blocks stuck (the ground's kernel)",
        p.time(lambda: fs.slide(q, dt, mu)),
        steps * 100,
    )
    # the same events on linear segments: the roof's samples given as a ground record (the
    # ground's kernel) — what the events cost without the floor's Taylor polynomial
    roof = fm.samples()
    r_roof, r_samp = fs.slide(fm, mu_k=mu), fs.slide(roof, dt, mu)
    row(
        "100 blocks on the roof's samples as a ground record (ground kernel, real)",
        p.time(lambda: fs.slide(roof, dt, mu)),
        steps * 100,
        f"{int(r_samp.slip_phases.sum()):,} slip phases (on the roof: "
        f"{int(r_roof.slip_phases.sum()):,}), sliding share "
        f"{r_samp.slide_fraction.mean():.3f} (roof: {r_roof.slide_fraction.mean():.3f})",
    )
    for k in (1, 100):
        muk = np.linspace(0.05, 0.5, k) if k > 1 else 0.2
        for where, kw in (("ground", {}), ("fixed roof", dict(building=fixed, floor=1))):
            for scale, what in ((QUIET, "stuck, elastic"), (1.0, "real")):
                row(
                    f"oscillator, {where}, {k} mu, {what}: time per mu·step",
                    p.time(
                        lambda muk=muk, kw=kw, s=scale: fs.slide_oscillator(
                            s * ag, dt, mu=muk, frequency=5.0, damping=0.02, mass_ratio=1.0, **kw
                        )
                    ),
                    steps * k,
                )
    muk = np.linspace(0.05, 0.5, 100)
    osc = dict(frequency=5.0, damping=0.02, mass_ratio=1.0)
    r_o = fs.slide_oscillator(roof, dt, mu=muk, **osc)
    row(
        "oscillator, 100 mu on the roof's samples as a ground record (real): per mu·step",
        p.time(lambda: fs.slide_oscillator(roof, dt, mu=muk, **osc)),
        steps * 100,
        f"{int(r_o.slip_phases.sum()):,} slip phases, sliding share "
        f"{r_o.slide_fraction.mean():.3f}",
    )
    # isolators: the linear engine on the same building (the elastic isolator as a linear
    # one): its states alone, then with the floor samples, then with the true in-step peaks
    sup = fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.02)
    lin = fs.IsolatedBuilding(sup, 1.0, 2.5, 0.10)

    def lin_states():
        for _ in building_motion(lin, q, dt, max_bytes=0).chunks():
            pass

    def lin_samples():
        building_motion(lin, q, dt).samples([0, 1])

    def lin_peaks():
        m_ = building_motion(lin, q, dt)
        m_.samples([0, 1])
        m_.peaks([0, 1])

    for what, fn in (
        ("states only", lin_states),
        ("states + floor samples", lin_samples),
        ("states + samples + true peaks", lin_peaks),
    ):
        row(
            f"linear isolated building (2.5 s, 10 %) on the same 1-storey: {what}",
            p.time(fn),
            steps,
            "per record step",
        )
    # isolators: sub-steps and the quiet path
    for name, iso in (
        ("lead-rubber", fs.BilinearIsolator(q_ratio=0.06, yield_disp=0.02, period=2.5)),
        ("friction pendulum", fs.FrictionPendulum(mu=0.06, period=3.0)),
    ):
        nb = fs.NonlinearIsolatedBuilding(sup, 1.0, iso)
        r = fs.isolator_response(nb, ag, dt)
        row(
            f"{name}: isolator_response, quiet",
            p.time(lambda nb=nb: fs.isolator_response(nb, q, dt)),
            steps,
            f"{r.substeps} sub-steps per record step",
        )
    return rows


def _oscillator_run(fm, a, mk, ms, w, xi, r, counts, preset_peaks=False):
    """:func:`floorslide.contents.oscillator._exact_states` (batched, no histories), with the
    option of peaks preset beyond reach (``preset_peaks``: no part is then sent to the series
    for a new peak — an instrumented variant, its results not the real ones)."""
    from floorslide.constants import G
    from floorslide.contents import _oscillator_batch as batch
    from floorslide.contents import _oscillator_kernel as cols
    from floorslide.contents.events import OSCILLATOR_MAX_EVENTS
    from floorslide.contents.oscillator import _propagators, oscillator_parts

    m_o, ho, K = oscillator_parts(fm, w, xi, r)
    states = np.zeros((mk.size, cols.O_NCOL))
    states[:, cols.O_LIMIT_AT] = -1.0
    if preset_peaks:
        states[:, cols.O_PEAK_U : cols.O_PEAK_BASE + 1] = 1e300
    hist = np.zeros((0, 0, 4))
    prop = _propagators(ho, K, w, xi, r)
    for k0, X in fm.chunks():
        batch.oscillator_batch_kernel(
            X, k0, fm.R, fm.beta, a, fm.substeps, fm.h, m_o, K, w, xi, r, G,
            np.maximum(mk, ms), mk, *prop, states, hist, False, OSCILLATOR_MAX_EVENTS, counts,
        )  # fmt: skip
    return states


def oscillator_parts(p: Profiler) -> list[list]:
    """What the batched oscillator kernel did with each part (its own counters): parts per
    mu·step, and the shares cleared by the bounds, advanced by the series for a new peak only
    (``quiet_part``) and sent to the event kernel, in stick and in slip; and the kernel's time
    per mu·step (the floor motion built once), also with the peaks preset beyond reach."""
    from floorslide.building.exact_motion import floor_motion
    from floorslide.contents import _oscillator_batch as batch
    from floorslide.contents.oscillator import oscillator_parameters
    from floorslide.contents.sliding import friction_pairs

    ag, dt = record_4000()
    steps = ag.size - 1
    fixed = fs.ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    f, xi, r = oscillator_parameters(5.0, 0.02, 1.0)
    w = 2 * np.pi * f
    rows = []
    for where, bld, fl in (("ground", None, 0), ("fixed roof", fixed, 1)):
        for k in (1, 100):
            mk, ms = friction_pairs(np.linspace(0.05, 0.5, k) if k > 1 else 0.2, None)
            for scale, what in ((QUIET, "quiet"), (1.0, "real")):
                a = scale * ag
                fm = floor_motion(bld, a, fl, dt)
                counts = np.zeros(batch.C_NCOL, dtype=np.int64)
                mine = _oscillator_run(fm, a, mk, ms, w, xi, r, counts)
                ref = fs.slide_oscillator(
                    fm, mu=mk, frequency=5.0, damping=0.02, mass_ratio=1.0
                ).peak_slide
                same = np.array_equal(mine[:, 5], ref)  # O_PEAK_U
                n = counts.sum()
                st, sl = counts[:5], counts[5:]
                scratch = np.zeros(batch.C_NCOL, dtype=np.int64)
                args = (fm, a, mk, ms, w, xi, r, scratch)
                t = p.time(lambda args=args: _oscillator_run(*args))
                t_pre = p.time(lambda args=args: _oscillator_run(*args, preset_peaks=True))
                ns, ns_pre = t / (k * steps) * 1e9, t_pre / (k * steps) * 1e9

                def pc(x, n=n):
                    return f"{100 * x / n:.2f} %"

                rows.append(
                    [
                        f"{where}, {k} mu, {what}",
                        f"{n / (k * steps):.2f}",
                        pc(st[0]),
                        pc(st[2:].sum()),
                        pc(st[1]),
                        pc(sl[0]),
                        pc(sl[2:].sum()),
                        pc(sl[1]),
                        f"{ns:.1f}",
                        f"{ns_pre:.1f}" if what == "quiet" else "—",
                        "yes" if same else "NO",
                    ]
                )
                print(f"  oscillator parts {rows[-1]}", file=sys.stderr)
    return rows


def slide_paths(p: Profiler) -> list[list]:
    """Which path the blocks on the fixed roof take, sub-step by sub-step: an instrumented copy
    of :mod:`floorslide.contents._kernels` (counters added, nothing else changed; compiled
    here, not cached) counts the object·sub-steps cleared stuck, cleared sliding one way (the
    closed form) and sent to the event search (:func:`_general`), stuck or sliding."""
    import importlib.util
    import tempfile

    from floorslide.constants import G
    from floorslide.contents import _kernels as kn
    from floorslide.contents.events import SLIDE_MAX_EVENTS

    src = Path(kn.__file__).read_text(encoding="utf-8")
    edits = [
        (
            "                ab_abs = max(amax, -amin)\n",
            "                flags[9] += 1\n                ab_abs = max(amax, -amin)\n",
        ),
        (
            "                if monotone:\n",
            "                if monotone:\n                    flags[8] += 1\n",
        ),
        (
            "        if not have_c:\n",
            "        flags[6 if mode == 0.0 else 7] += 1\n        if not have_c:\n",
        ),
        (
            "max_events, 0, nobj], dtype=np.int64",
            "max_events, 0, nobj, 0, 0, 0, 0], dtype=np.int64",
        ),
        (
            "    liftoff[2] = 1.0 if in_lift else 0.0",
            "    liftoff[2] = 1.0 if in_lift else 0.0\n    return flags",
        ),
        ("cache=True", "cache=False"),
    ]
    for old, new in edits:
        if old not in src:
            print("  slide_paths: the kernel's source changed; skipped", file=sys.stderr)
            return []
        src = src.replace(old, new)
    tmp = Path(tempfile.mkdtemp()) / "_kernels_counted.py"
    tmp.write_text(src, encoding="utf-8")
    spec = importlib.util.spec_from_file_location("_kernels_counted", tmp)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)

    ag, dt = record_4000()
    steps = ag.size - 1
    fixed = fs.ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    mu = np.linspace(0.02, 0.5, 100)
    rows = []
    for scale, what in ((QUIET, "quiet"), (1.0, "real")):
        a = scale * ag
        fm = fs.floor_motion(fixed, a, 1, dt)
        states = np.zeros((mu.size, kn.NCOL))
        states[:, kn.LIMIT_AT] = -1.0
        total = np.zeros(4, dtype=np.int64)
        for k0, X in fm.chunks():
            flags = mod.slide_kernel(
                X, k0, fm.R, fm.beta, fm.rv, fm.rd, a, np.zeros(1), False, fm.substeps, fm.h,
                G, mu, mu, True, True, states, np.zeros((0, 0)), np.zeros((0, 0)),
                np.zeros((0, 0)), False, np.zeros(3), SLIDE_MAX_EVENTS,
            )  # fmt: skip
            total += flags[6:]
        ref = fs.slide(fm, mu_k=mu)
        same = np.array_equal(states[:, kn.PEAK_DISP], ref.peak_slide)
        n = mu.size * steps * fm.substeps
        rows.append(
            [
                f"fixed roof, 100 blocks, {what}",
                f"{100 * total[3] / n:.2f} %",
                f"{100 * total[2] / n:.2f} %",
                f"{100 * total[0] / n:.2f} %",
                f"{100 * total[1] / n:.2f} %",
                "yes" if same else "NO",
            ]
        )
        print(f"  slide paths {rows[-1]}", file=sys.stderr)
    return rows


# ---- main ----------------------------------------------------------------------------------


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    ap.add_argument("--out", help="also write the tables to this Markdown file")
    ap.add_argument("--only", help="profile only the cases whose name contains this")
    args = ap.parse_args()
    load0 = _load()
    with threadpool_limits(limits=1):
        bare = bare_rate()
        p = Profiler(bare, args.quick)
        print("cases …", file=sys.stderr)
        for c in cases():
            if args.only and args.only not in c.name:
                continue
            if c.name.startswith("rigid block in the plane"):
                c = _plane_fix(c)
            p.profile(c)
        print("breakdowns …", file=sys.stderr)
        brows = [] if args.only else breakdowns(p)
        orows = [] if args.only else oscillator_parts(p)
        srows = [] if args.only else slide_paths(p)
        bare2 = bare_rate()
    out = [
        f"Machine: {machine()}; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; "
        f"load average (1, 5, 15 min) {load0} at the start, {_load()} at the end.",
        "",
        f"Bare loop `x = a·x + b[i]` (numba): **{bare:.2e} steps/s** at the start, "
        f"{bare2:.2e} at the end; measured again beside every case and row (from "
        f"{min(p.bares):.2e} to {max(p.bares):.2e}), and each share is of the bare loop "
        "measured beside it.",
        "",
        f"Per call: a {SHORT}-sample record (its own steps at the quiet rate taken off), and its "
        "share of the real call. Quiet: the record scaled by "
        f"{QUIET:g} (nothing happens); ns per object·step without the per-call cost, and that "
        "as a share of the bare loop (the ceiling without events). Events: counted by the "
        "result on the real record; ns per event = (real − quiet) / events, and the share of "
        "the real call that is. Moving: the share of object·steps spent sliding or rocking "
        "(from the result) and the same excess time per moving object·step.",
        "",
        markdown_table(
            [
                "case",
                "bare loop (/s)",
                "target",
                "real share",
                "per call",
                "quiet ns/obj·step",
                "quiet share",
                "events",
                "events/obj·step",
                "ns/event (share of call)",
                "moving share of obj·steps: ns per moving obj·step",
            ],
            p.rows,
        ),
    ]
    if brows:
        out += [
            "",
            "Breakdowns (time per call; ns per unit named in the row; share of the bare loop):",
            "",
            markdown_table(
                ["variant", "time per call", "ns", "bare loop (/s)", "share", "note"], brows
            ),
        ]
    if srows:
        out += [
            "",
            "The blocks on the fixed roof, by path (an instrumented copy of the kernel counts "
            "object·sub-steps; its peaks are checked equal to `fs.slide`'s):",
            "",
            markdown_table(
                [
                    "blocks",
                    "stuck, cleared",
                    "sliding one way, closed form",
                    "event search from stick",
                    "event search while sliding",
                    "same peaks",
                ],
                srows,
            ),
        ]
    if orows:
        out += [
            "",
            "The batched oscillator kernel's parts (its own counters), per mu·step and by fate: "
            "cleared by the chord bounds, advanced by the series for a new peak only, sent to "
            "the event kernel (an event may lie in the part); the kernel's time per mu·step on a "
            "floor motion built once, and on the quiet record with every peak preset beyond "
            "reach (an instrumented variant: no part needs the series for a new peak):",
            "",
            markdown_table(
                [
                    "oscillator",
                    "parts per mu·step",
                    "stick: cleared",
                    "stick: new peak",
                    "stick: event kernel",
                    "slip: cleared",
                    "slip: new peak",
                    "slip: event kernel",
                    "kernel ns/mu·step",
                    "same, peaks preset",
                    "same peaks as the API",
                ],
                orows,
            ),
        ]
    text = "\n".join(out)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
