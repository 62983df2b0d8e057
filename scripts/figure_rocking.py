"""Figure: a slender cabinet rocking on the roof of the demo's buildings under a pulse-like
record — fixed-base, on linear isolation and on a friction pendulum — by the linearised
(``method="exact"``) and the full equation (``method="nonlinear"``). Written to
docs/figures/rocking.png. Usage::

    python scripts/figure_rocking.py

The record (Cape Mendocino 1992, Petrolia 090, PGA 0.66 g) is interpolated linearly onto dt/10
(which leaves the piecewise-linear record unchanged), so the samples draw θ densely.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from _common import ROOT, slammer

import floorslide as fs

WIDTH, HEIGHT = 0.3, 1.8  # m: B/H = 0.17, α = 0.17 rad


def main() -> None:
    ag, dt = slammer("CapeMendocino_1992_PET-090.txt")
    ag = ag[: int(25 / dt)]
    fine = 10
    t = np.arange(ag.size) * dt
    tf = np.arange((ag.size - 1) * fine + 1) * (dt / fine)
    agf = np.interp(tf, t, ag)
    sup = fs.ShearBuilding.from_period(stories=1, period=0.2, damping=0.02)
    buildings = {
        "fixed-base, T = 0.2 s": sup,
        "linear isolation, T = 3 s, 10 %": fs.IsolatedBuilding(sup, 1.0, 3.0, 0.1),
        "friction pendulum, mu = 0.06, T = 3 s": fs.NonlinearIsolatedBuilding(
            sup, 1.0, fs.FrictionPendulum(mu=0.06, period=3.0)
        ),
    }
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8), sharey=True)
    for ax, (name, b) in zip(axes, buildings.items(), strict=True):
        for method, style in (("exact", "-"), ("nonlinear", "--")):
            r = fs.rock(agf, dt / fine, WIDTH, HEIGHT, building=b, floor=1, method=method,
                        histories=True)  # fmt: skip
            label = "linearised" if method == "exact" else "full equation"
            ratio = r.theta[0] / r.alpha[0]
            extra = (
                f"overturns at {r.overturn_time[0]:.2f} s"
                if r.overturned[0]
                else f"peak {r.peak_ratio[0]:.2f}, {r.impacts[0]} impacts"
            )
            line = ax.plot(tf, ratio, style, lw=1.0, label=f"{label}: {extra}")[0]
            if r.overturned[0]:
                last = ratio[np.isfinite(ratio)][-1]
                ax.plot(r.overturn_time[0], np.sign(last), "X", color=line.get_color(), ms=8)
        for y in (-1, 1):
            ax.axhline(y, color="red", ls=":", lw=0.8)
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("time (s)")
        ax.legend(fontsize=7, loc="lower left")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("θ / α  (±1: overturns)")
    axes[0].set_ylim(-1.15, 1.15)
    fig.suptitle(
        f"Cabinet {WIDTH} × {HEIGHT} m (α = {np.arctan(WIDTH / HEIGHT):.2f} rad) rocking on the "
        "roof, Cape Mendocino 1992 Petrolia 090 (PGA 0.66 g)",
        fontsize=10,
    )
    fig.tight_layout()
    out = ROOT / "docs" / "figures" / "rocking.png"
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
