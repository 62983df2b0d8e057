"""What a fresh install compiles, kernel by kernel: numba compile time on an empty cache.

Each family of :data:`floorslide.firstrun.FAMILIES` (what ``floorslide warmup`` and the first
run compile) runs in a child process whose ``NUMBA_CACHE_DIR`` is an empty folder. The child
listens to numba's compile events and reports, for every floorslide kernel it compiled, the
time spent compiling it *exclusive* of the floorslide kernels it called that compiled inside it
(their own rows), and the number of specialisations (type signatures) it got; and the child's
CPU time in all (imports and the short calls included).

``--demo`` runs the demo's families one after the other in one shared empty cache (what the
demo's first run compiles; a kernel two families share compiles once); ``--scene`` plans a
scene and runs every task in one process instead (what its tasks need, compiled as they go);
``--command`` runs a floorslide command in one process. Run it from a source tree of an older
commit (``PYTHONPATH=...``) for the table before a change.

Usage::

    python scripts/compile_table.py [--families study,ground [--together]] [--demo]
                                    [--scene SCENE.toml] [--command 'demo -o {tmp}/d']
                                    [--top 25] [--out FILE.md] [--json FILE.json]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

DEMO = ("study", "nonlinear-core", "study-nonlinear")
"""The families the demo's scene needs (``floorslide.firstrun.scene_families``)."""


def _cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def child(names: list[str]) -> dict:
    """Run the families `names` here, timing every floorslide kernel's compilation."""
    from numba.core import event

    stack: list[list] = []  # [name, start, child_time]
    incl: dict[str, float] = defaultdict(float)
    excl: dict[str, float] = defaultdict(float)
    count: dict[str, int] = defaultdict(int)

    class Listener(event.Listener):
        def on_start(self, ev):
            disp = ev.data.get("dispatcher") if isinstance(ev.data, dict) else None
            func = getattr(disp, "py_func", None)
            module = getattr(func, "__module__", "") or ""
            name = f"{module}.{func.__qualname__}" if module.startswith("floorslide") else ""
            stack.append([name, time.perf_counter(), 0.0])

        def on_end(self, ev):
            name, start, inner = stack.pop()
            took = time.perf_counter() - start
            if name:
                incl[name] += took
                excl[name] += took - inner
                count[name] += 1
                if stack:
                    stack[-1][2] += took
            elif stack:  # numba's own overloads: inside their caller's exclusive time
                pass

    t0, c0 = time.perf_counter(), _cpu()
    import floorslide  # noqa: F401  (the import is part of what a first run pays)
    from floorslide import firstrun

    c_import = _cpu() - c0
    from floorslide.run import warmup

    warmup.start = lambda families: []  # no side processes: everything compiles here
    firstrun.prepare = lambda *a, **k: None
    listener = Listener()
    event.register("numba:compile", listener)
    per_family = {}
    for name in names:
        c1 = _cpu()
        if name.startswith("cli:"):  # a command, in this process, compiling as it goes
            from floorslide.cli import cli

            with tempfile.TemporaryDirectory() as tmp:
                argv = [a.replace("{tmp}", tmp) for a in name[4:].split()]
                try:
                    cli.main(argv, standalone_mode=False)
                except SystemExit:
                    pass
        elif name.startswith("tasks:"):  # a scene's planner and every task, here
            from floorslide.run.task import run_task
            from floorslide.scene.planner import plan
            from floorslide.scene.schema import load_scene

            for task in plan(load_scene(name[6:]), evaluate=True).tasks:
                run_task(task)
        else:
            firstrun.FAMILIES[name].run()
        per_family[name] = _cpu() - c1
    event.unregister("numba:compile", listener)
    return dict(
        families=names,
        wall=time.perf_counter() - t0,
        cpu=_cpu() - c0,
        cpu_import=c_import,
        cpu_family=per_family,
        kernels={k: dict(excl=excl[k], incl=incl[k], n=count[k]) for k in excl},
    )


def run(names: list[str]) -> dict:
    """`names` in a child process with an empty numba cache."""
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, NUMBA_CACHE_DIR=tmp, PYTHONWARNINGS="ignore")
        out = subprocess.run(
            [sys.executable, __file__, "--child", "\x1f".join(names)],
            env=env,
            capture_output=True,
            text=True,
            check=False,
        )
    if out.returncode:
        raise SystemExit(out.stderr[-2000:])
    return json.loads(out.stdout.strip().splitlines()[-1])


def table(res: dict, top: int) -> str:
    ks = sorted(res["kernels"].items(), key=lambda kv: -kv[1]["excl"])
    total = sum(v["excl"] for _, v in ks)
    lines = [
        f"**{' + '.join(res['families'])}**: {res['cpu']:.1f} CPU-s in all "
        f"(import {res['cpu_import']:.1f}; "
        + ", ".join(f"{k} {v:.1f}" for k, v in res["cpu_family"].items())
        + f"); floorslide kernels compiling {total:.1f} s, {len(ks)} kernels, "
        f"{sum(v['n'] for _, v in ks)} specialisations",
        "",
        "| kernel | compile s (own) | with callees | specialisations |",
        "|---|---|---|---|",
    ]
    for k, v in ks[:top]:
        short = k.removeprefix("floorslide.")
        lines.append(f"| `{short}` | {v['excl']:.2f} | {v['incl']:.2f} | {v['n']} |")
    rest = ks[top:]
    if rest:
        lines.append(
            f"| {len(rest)} others | {sum(v['excl'] for _, v in rest):.2f} | | "
            f"{sum(v['n'] for _, v in rest)} |"
        )
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--child", help=argparse.SUPPRESS)
    ap.add_argument("--families", help="comma-separated families (default: all, one by one)")
    ap.add_argument("--demo", action="store_true", help="the demo's families in one cache")
    ap.add_argument(
        "--together", action="store_true", help="the --families in one cache, one after another"
    )
    ap.add_argument("--scene", help="a scene's planner and tasks run in one process")
    ap.add_argument(
        "--command",
        help="a floorslide command run in one process, compiling as it goes "
        "(e.g. 'demo -o {tmp}/d --workers 1'; {tmp} is a temporary folder)",
    )
    ap.add_argument("--top", type=int, default=25)
    ap.add_argument("--out")
    ap.add_argument("--json")
    a = ap.parse_args()
    if a.child:
        print(json.dumps(child(a.child.split("\x1f"))))
        return
    from floorslide.firstrun import FAMILIES

    if a.scene:
        groups = [["tasks:" + str(Path(a.scene).resolve())]]
    elif a.command:
        groups = [["cli:" + a.command]]
    elif a.demo:
        groups = [list(DEMO)]
    else:
        names = a.families.split(",") if a.families else list(FAMILIES)
        groups = [names] if a.together else [[n] for n in names]
    results, parts = [], []
    for g in groups:
        res = run(g)
        results.append(res)
        parts.append(table(res, a.top))
        print(parts[-1] + "\n", flush=True)
    if a.out:
        Path(a.out).write_text("\n\n".join(parts) + "\n", encoding="utf-8")
    if a.json:
        Path(a.json).write_text(json.dumps(results, indent=1), encoding="utf-8")


if __name__ == "__main__":
    main()
