"""Benchmark: a 40-record × 17-isolation-period × 8-mu study, serial and on 2 workers.

The size of published parametric studies of equipment sliding in isolated buildings: 40
records (the 36 bundled SLAMMER records and 4 of them scaled to 0.5 g), a 1-storey fixed-base
building (T = 0.2 s) and the same on isolation at 17 periods (1–5 s), equipment with 8 friction
coefficients on the roof. Reports wall time and peak memory (resident set, sampled) of
``floorslide run`` per setting.

Usage::

    python scripts/bench_study.py [--workers 1,2]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import psutil
from _common import ROOT, markdown_table

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()
SCENE = f"""
[scene]
name = "40 records x 17 isolation periods x 8 mu"

[[records]]
set = "all"
catalog = "{CATALOG}"

[[records]]
set = "scaled"
catalog = "{CATALOG}"
where = {{ station_id = ["ELC-180", "TAF-021", "LCN-260", "RRS-228"] }}
scale_pga = 0.5

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.2
damping = 0.02

[[buildings]]
id = "isolated"
kind = "isolated"
superstructure = "fixed"
period = [1.0, 1.25, 1.5, 1.75, 2.0, 2.25, 2.5, 2.75, 3.0, 3.25, 3.5, 3.75, 4.0, 4.25, 4.5, 4.75,
          5.0]
damping = 0.10

[[contents]]
id = "equipment"
floors = "roof"
mu = [0.05, 0.075, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5]
"""


def measure(cmd: list[str]) -> tuple[float, float]:
    """Wall time and peak RSS (MB, summed over the process tree, sampled every 20 ms)."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL)
    peak = 0.0
    stop = threading.Event()

    def sample():
        nonlocal peak
        p = psutil.Process(proc.pid)
        while not stop.is_set():
            try:
                rss = p.memory_info().rss + sum(
                    c.memory_info().rss for c in p.children(recursive=True)
                )
                peak = max(peak, rss)
            except psutil.Error:
                pass
            time.sleep(0.02)

    th = threading.Thread(target=sample, daemon=True)
    th.start()
    proc.wait()
    stop.set()
    th.join()
    if proc.returncode:
        raise SystemExit(f"floorslide run failed ({proc.returncode})")
    return time.perf_counter() - t0, peak / 1e6


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--workers", default="1,2")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        scene = Path(tmp) / "study.toml"
        scene.write_text(SCENE)
        exe = [sys.executable, "-m", "floorslide.cli", "run", str(scene)]
        subprocess.run(
            [*exe, "-o", str(Path(tmp) / "warm.h5"), "--workers", "1"],
            check=True,
            stdout=subprocess.DEVNULL,
        )  # numba caches warm
        for w in args.workers.split(","):
            out = Path(tmp) / f"w{w}.h5"
            wall, mem = measure([*exe, "-o", str(out), "--workers", w])
            rows.append([w, f"{wall:.1f}", f"{mem:.0f}", f"{out.stat().st_size / 1e6:.1f}"])
    print("40 records × 18 buildings (fixed + 17 isolation periods) = 720 tasks × 8 mu on the roof")
    print(
        markdown_table(
            ["workers", "wall time (s)", "peak memory (MB, all processes)", "result file (MB)"],
            rows,
        )
    )


if __name__ == "__main__":
    main()
