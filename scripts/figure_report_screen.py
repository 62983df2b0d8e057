"""Figure: the first screen (1280 × 800) of the demo's HTML report as headless Chromium shows
it — the results, not caveats. Written to docs/figures/report-first-screen.png. Usage::

    floorslide demo -o /tmp/floorslide-demo
    python scripts/figure_report_screen.py /tmp/floorslide-demo/report.html

Needs Chromium (or Chrome) on the PATH.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from _common import ROOT

SCREEN = (1280, 800)


def main(report: str) -> None:
    browser = next(
        (
            shutil.which(n)
            for n in ("chromium", "chromium-browser", "google-chrome")
            if shutil.which(n)
        ),
        None,
    )
    if browser is None:
        sys.exit("no Chromium or Chrome on the PATH")
    out = ROOT / "docs" / "figures" / "report-first-screen.png"
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run(
            [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
             "--no-first-run", "--disable-background-networking", "--disable-sync",
             f"--user-data-dir={tmp}", f"--screenshot={out}",
             f"--window-size={SCREEN[0]},{SCREEN[1]}", Path(report).resolve().as_uri()],
            check=True, capture_output=True, timeout=120,
        )  # fmt: skip
    print(out)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "floorslide-demo/report.html")
