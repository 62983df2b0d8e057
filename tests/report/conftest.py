"""A small synthetic study written with the real ResultWriter: 2 record sets × (fixed,
isolated@T=2, isolated@T=2.5) × 3 records, a cabinet on floor 1 with 3 friction values, spectra
on floors 0 and 1 at two damping ratios, histories on one task.

The values are plausible but made up; ``Study.truth`` keeps them so that tests compute the
expected statistics with NumPy independently of floorslide.report. Special cases built in:

- mu = 0.2 in set broad-band: no building slides (ratio 0/0);
- mu = 0.2 in set pulse-like: only isolated@T=2 slides (ratio x/0);
- fixed, broad-band, mu = 0.1, record bb3: the object rocks (not simulated, NaN);
- fixed, pulse-like, mu = 0.05: the object rocks under every record.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from floorslide.run.results import ContentResult, Histories, SpectrumResult, TaskResult
from floorslide.run.store import ResultWriter

G = 9.80665
SETS = {"broad-band": ["bb1", "bb2", "bb3"], "pulse-like": ["pl1", "pl2", "pl3"]}
BUILDINGS = {
    "fixed": dict(building_base="fixed", building_kind="fixed", isolation_period=float("nan")),
    "isolated@T=2": dict(building_base="isolated", building_kind="isolated", isolation_period=2.0),
    "isolated@T=2.5": dict(
        building_base="isolated", building_kind="isolated", isolation_period=2.5
    ),
}
MU = np.array([0.05, 0.1, 0.2])
PERIODS = np.geomspace(0.05, 4.0, 25)
DAMPING = np.array([0.02, 0.05])
NPTS = 400
DT = 0.01

SCENE_HEAD = """\
[scene]
name = "synthetic study"

[[records]]
set = "pulse-like"
files = ["pl*.txt"]

[[records]]
set = "broad-band"
files = ["bb*.txt"]

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.2

[[buildings]]
id = "isolated"
kind = "isolated"
superstructure = "fixed"
period = [2.0, 2.5]

[[contents]]
id = "cabinet"
floors = [1]
mu = [0.05, 0.1, 0.2]

[spectra]
floors = "all"
damping = [0.02, 0.05]
periods = { min = 0.05, max = 4.0, n = 25 }
"""

REPORT = """
[report]
periods = [0.1, 0.25, 0.5, 10.0]
damping = 0.05
compare = ["isolated:fixed"]
history_record = "bb1"
"""


@dataclass
class Synthetic:
    """A written result file and the values in it."""

    path: Path
    truth: dict = field(default_factory=dict)  # (set, building, record) → dict of arrays


def _values(rs: str, bid: str, k: int, pga: float):
    """Peak slide, residual, object acceleration, modes per mu; PFA per floor; PSA."""
    iso = BUILDINGS[bid]["building_kind"] == "isolated"
    period = BUILDINGS[bid]["isolation_period"]
    reduction = 0.15 / period if iso else 1.0
    pfa1 = pga * (0.35 + 0.05 * k if iso else 2.2 + 0.3 * k)
    peak = reduction * (0.08 + 0.03 * k + 0.01 * (rs == "pulse-like")) / (MU / 0.05) ** 1.5
    resid = peak * (0.6 - 0.4 * k) * (1 if k % 2 else -1)
    acc = np.minimum(pfa1, (MU + 0.02 * k) * G)
    modes = np.array(["slide"] * 3, dtype=object)
    # mu = 0.2: nothing slides, except isolated@T=2 under the pulse-like set (x/0 ratio)
    if not (rs == "pulse-like" and bid == "isolated@T=2"):
        peak[2] = resid[2] = 0.0
        acc[2] = pfa1
        modes[2] = "rest"
    if bid == "fixed" and rs == "broad-band" and k == 2:
        peak[1] = resid[1] = acc[1] = np.nan
        modes[1] = "rock"
    if bid == "fixed" and rs == "pulse-like":
        peak[0] = resid[0] = acc[0] = np.nan
        modes[0] = "rock"
    pfa = np.array([pga * (1.0 if not iso else 0.9), pfa1])
    shape = np.exp(-((np.log(PERIODS / (period if iso else 0.2))) ** 2))
    psa = np.array(
        [
            [f * p * (1 + (2.5 - z * 10) * shape) * (1 + 0.1 * k) for p in pfa]
            for z, f in zip(DAMPING, (1.3, 1.0), strict=True)
        ]
    )  # (n_damping, n_floors, n_periods)
    return peak, resid, acc, modes, pfa, psa


RACK_MU = np.array([0.1, 0.3])
RACK_SCENE = """
[[contents]]
id = "rack"
floors = [1]
model = "oscillator"
frequency = 8.0
mass_ratio = 0.5
mu = [0.1, 0.3]
"""


def _rack(rs: str, bid: str, k: int, pfa1: float) -> ContentResult:
    """A made-up 2-DOF oscillator result: base slide, spring deformation, top acceleration;
    it rocks on the fixed building under pulse-like record 3 at mu = 0.3 (to test NaNs)."""
    peak = np.array([0.05, 0.01]) * (1 + 0.5 * k) * (1.0 if bid == "fixed" else 0.4)
    deform = np.array([0.004, 0.006]) * (1 + 0.2 * k) + 0.001 * (rs == "pulse-like")
    top = pfa1 * np.array([1.8, 2.1]) * (1 + 0.1 * k)
    base = np.minimum(pfa1, (RACK_MU + 0.05) * G)
    modes = np.array(["slide", "slide"], dtype=object)
    if bid == "fixed" and rs == "pulse-like" and k == 2:
        peak[1] = deform[1] = top[1] = base[1] = np.nan
        modes[1] = "rock"
    return ContentResult(
        content="rack",
        floor=1,
        model="oscillator",
        mode="slide" if len(set(modes)) == 1 else "mixed",
        skipped="",
        mu_k=RACK_MU.copy(),
        mu_s=RACK_MU.copy(),
        peak_slide=peak,
        residual_slide=-0.5 * peak,
        peak_abs_accel=base,
        slide_fraction=np.where(np.isfinite(peak), 0.3, np.nan),
        slip_phases=np.where(np.isfinite(peak), 6, -1),
        peak_deformation=deform,
        peak_top_accel=top,
        modes=modes.astype(str),
    )


def write_study(
    path: Path,
    report: str | None = REPORT,
    order_seed: int = 0,
    *,
    flexible: bool = False,
    broadening: float = 0.0,
    done: int | None = None,
) -> Synthetic:
    """Write the synthetic study to `path`, tasks in a shuffled order (seeded).

    `flexible` adds a 2-DOF oscillator content ``rack``; `broadening` stores broadened spectra
    (``1.25 × PSA``, made up) beside the unbroadened ones; `done` writes only that many tasks
    while the stored plan still counts them all (an interrupted run)."""
    syn = Synthetic(path)
    results = []
    for rs, records in SETS.items():
        for k, rec in enumerate(records):
            pga = 2.0 + 0.7 * k + (1.5 if rs == "pulse-like" else 0.0)
            for bid, b in BUILDINGS.items():
                peak, resid, acc, modes, pfa, psa = _values(rs, bid, k, pga)
                syn.truth[(rs, bid, rec)] = dict(
                    peak=peak, resid=resid, acc=acc, modes=modes, pfa=pfa, pga=pga, psa=psa
                )
                meta = dict(
                    record_set=rs,
                    record=rec,
                    record_file=f"{rec}.txt",
                    building=bid,
                    stories=1,
                    isolation_damping=0.1 if b["building_kind"] == "isolated" else float("nan"),
                    superstructure="fixed" if b["building_kind"] == "isolated" else "",
                    dt=DT,
                    npts=NPTS,
                    pga=pga,
                    scale=1.0,
                    **b,
                )
                content = ContentResult(
                    content="cabinet",
                    floor=1,
                    model="rigid",
                    mode="slide" if len(set(modes)) == 1 else "mixed",
                    skipped="",
                    mu_k=MU.copy(),
                    mu_s=MU.copy(),
                    peak_slide=peak,
                    residual_slide=resid,
                    peak_abs_accel=acc,
                    slide_fraction=np.where(peak > 0, 0.2, 0.0),
                    slip_phases=np.where(peak > 0, 4, 0),
                    modes=modes.astype(str),
                )
                spectra = [
                    SpectrumResult(f, PERIODS, DAMPING, psa[:, i], psa[:, i], psa[:, i], psa[:, i])
                    for i, f in enumerate((0, 1))
                ]
                if broadening:
                    for sp in spectra:
                        sp.broadening = broadening
                        wide = 1.25 * sp.psa
                        sp.psa_broadened = sp.sa_broadened = wide
                        sp.sv_broadened = sp.sd_broadened = wide
                contents = [content]
                if flexible:
                    contents.append(_rack(rs, bid, k, pfa[1]))
                    syn.truth[(rs, bid, rec)]["rack"] = contents[-1]
                hist = None
                if rs == "broad-band" and rec == "bb1" and bid == "fixed":
                    t = np.arange(NPTS) * DT
                    fa = np.vstack([pga * np.sin(2 * np.pi * t), pfa[1] * np.sin(2 * np.pi * t)])
                    u = np.vstack([peak[i] * np.sin(np.pi * t / t[-1]) for i in range(3)])
                    u = np.nan_to_num(u)
                    hist = Histories(
                        DT,
                        np.array([0, 1]),
                        fa,
                        {"cabinet/floor_1": u},
                        {"cabinet/floor_1": MU.copy()},
                    )
                    if flexible:
                        key = "rack/floor_1"
                        hist.slides[key] = 0.5 * u[:2]
                        hist.mu_k[key] = RACK_MU.copy()
                        hist.deformation[key] = 0.01 * np.vstack([np.sin(9 * t)] * 2)
                        hist.top_accel[key] = 3.0 * np.vstack([np.cos(9 * t)] * 2)
                results.append(
                    TaskResult("", meta, np.array([0, 1]), pfa, contents, spectra, hist, 0.01)
                )
    order = np.random.default_rng(order_seed).permutation(len(results))
    scene = SCENE_HEAD + (RACK_SCENE if flexible else "") + (report or "")
    if broadening:
        scene = scene.replace("periods = { min", f"broadening = {broadening}\nperiods = {{ min")
    writer = ResultWriter(path, scene, "synthetic.toml", "synthetic study", {"tasks": len(results)})
    if done is not None:
        order = order[:done]
    for j, i in enumerate(order):
        results[i].task_id = f"t{j:05d}"
        writer.write(results[i])
    if done is None:
        writer.finish()
    return syn


@pytest.fixture(scope="session")
def study(tmp_path_factory) -> Synthetic:
    """The synthetic study with a [report] table."""
    return write_study(tmp_path_factory.mktemp("report") / "study.h5")


@pytest.fixture(scope="session")
def plain_study(tmp_path_factory) -> Synthetic:
    """The same study, its scene without a [report] table."""
    return write_study(tmp_path_factory.mktemp("plain") / "plain.h5", report=None)


@pytest.fixture(scope="session")
def rich_study(tmp_path_factory) -> Synthetic:
    """The study with a 2-DOF oscillator content and broadened spectra (issue 12)."""
    return write_study(tmp_path_factory.mktemp("rich") / "rich.h5", flexible=True, broadening=0.15)


@pytest.fixture(scope="session")
def partial_study(tmp_path_factory) -> Synthetic:
    """The study interrupted after 14 of its 18 tasks."""
    return write_study(tmp_path_factory.mktemp("partial") / "partial.h5", done=14)
