"""A small, fast study on nonlinear isolation for the run and report tests: short synthetic
records (3 s at 0.01 s), a 1-storey fixed-base building and the same on isolation layers given
by the caller, a box on the roof, histories kept for one record."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from floorslide.run.execute import execute
from floorslide.scene.planner import Plan, plan
from floorslide.scene.schema import load_scene

DT = 0.01
FPS = '{ model = "friction_pendulum", mu = 0.04, capacity = 0.05 }'
LRB = '{ model = "bilinear", q_ratio = 0.05, yield_disp = 0.01 }'


def write_records(folder: Path, n: int = 2) -> None:
    """`n` short synthetic records (g, one column): decaying sine bursts, 3 s."""
    t = np.arange(0.0, 3.0, DT)
    for k in range(n):
        acc = (0.35 + 0.1 * k) * np.sin(2 * np.pi * (0.8 + 0.3 * k) * t) * np.exp(-0.4 * t)
        np.savetxt(folder / f"rec{k + 1}.txt", acc)


def scene_text(isolators: dict[str, str], history: str = "rec1") -> str:
    """The scene: `isolators` maps an isolated building's id to its ``isolator`` table."""
    isolated = "".join(
        f"""
[[buildings]]
id = "{bid}"
kind = "isolated"
superstructure = "fixed"
period = 2.5
isolator = {table}
"""
        for bid, table in isolators.items()
    )
    return f"""
[scene]
name = "hysteresis"

[[records]]
set = "s"
files = ["rec*.txt"]
units = "g"
dt = {DT}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.2
{isolated}
[[contents]]
id = "box"
floors = "roof"
mu = [0.1]

[report]
history_record = "{history}"
"""


def run_study(
    folder: Path, isolators: dict[str, str], n: int = 2, history: str = "rec1"
) -> tuple[Plan, Path]:
    """Write the records and the scene into `folder` and run it: (plan, result file)."""
    write_records(folder, n)
    path = folder / "scene.toml"
    path.write_text(scene_text(isolators, history))
    p = plan(load_scene(path))
    out = folder / "out.h5"
    execute(p, str(out), workers=1)
    return p, out
