"""Figures and table of the README's "Two horizontal components" section: the scene
``data/scenes/pairs.toml`` (10 bundled PEER record pairs; a 3-storey building with a period per
direction, fixed-base and on linear isolation; a cabinet on the ground and the roof) is run into
a temporary folder, and its plane-path figure (Sylmar 1994) and its 2-D against 1-D figure are
copied to ``docs/figures/plane_path.png`` and ``docs/figures/plane_ratio.png``; the ``plane``
design table is printed as Markdown. Usage::

    python scripts/figure_plane.py
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from _common import ROOT

import floorslide as fs

SCENE = ROOT / "data" / "scenes" / "pairs.toml"


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "pairs.h5"
        subprocess.run(
            [sys.executable, "-m", "floorslide.cli", "run", str(SCENE), "-o", str(out)],
            check=True,
        )
        written = fs.plot_figures(out, Path(tmp) / "figures")
        figures = ROOT / "docs" / "figures"
        for p in written:
            if p.name.startswith(("plane_path_", "plane_ratio_")):
                target = figures / (p.name.rsplit("_", 1)[0] + ".png")
                shutil.copyfile(p, target)
                print(f"wrote {target.relative_to(ROOT)}")
        tables = fs.design_tables(out)
        cols = ["building", "floor", "mu_k", "n_records", "slide_2d_median", "slide_1d_median"]
        cols += ["ratio_of_medians", "ratio_median", "ratio_min", "ratio_max", "n_2d_above_1d"]
        print("| " + " | ".join(cols) + " |")
        print("|" + "---|" * len(cols))
        for r in tables["plane"]:
            cells = [f"{r[c]:.3g}" if isinstance(r[c], float) else str(r[c]) for c in cols]
            print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
