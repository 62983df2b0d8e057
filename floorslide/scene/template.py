"""The scene template ``floorslide init`` writes: every section of a scene file (docs/design.md
§4), commented, on the bundled records, so that it runs as written and shows what to change.
"""

from __future__ import annotations

import json
from pathlib import Path

MARKER = "# floorslide scene template (written by floorslide init)"
"""The template's first line."""

TEMPLATE = """\
{marker}
# A scene declares record sets x buildings x contents x spectra (docs/design.md §4). Check it
# with `floorslide run {name} --dry-run`, run it with `floorslide run {name} -o out.h5`, then
# `floorslide table out.h5`, `floorslide plot out.h5` or `floorslide report out.h5`.
# Units are SI: m, s, kg, m/s**2; accelerations given "in g" say so.

[scene]
name = "my study"
# qa = "reject"                 # leave out records whose quality checks trip (default "warn")

# ---- records: a set per [[records]]; relative paths are relative to this file --------------
[[records]]
set = "broad-band"
catalog = {catalog}   # the bundled records: replace with your own
where = {{ set = "broad-band" }}    # keep catalog rows whose column equals this
# files = ["records/*.AT2"]     # or your files instead of a catalog (globs, ** recursive)
# units = "g"                   # required when the files do not state their units
# scale_pga = [0.2, 0.4]        # g: one set per value (broad-band@0.2g, ...)

# [processing]                  # applied to every record, in this order (none by default)
# detrend = "linear"
# taper = 0.05                  # fraction per end
# highpass = 0.1                # Hz

# ---- buildings ----------------------------------------------------------------------------
[[buildings]]
id = "fixed"
kind = "fixed"
stories = 3
period = 0.4                    # s: fundamental period (a list sweeps: fixed@T=...)
damping = 0.05
storey_heights = [4.5, 3.5, 3.5]   # m (optional): z/h of the code comparison (else equal)

[[buildings]]
id = "isolated"
kind = "isolated"
superstructure = "fixed"        # a fixed building above
period = [2.0, 3.0]             # s: isolation period, one building per value
damping = 0.10
base_mass_ratio = 1.0           # base mat mass / superstructure mass

[[buildings]]
id = "fps"                      # the same building on friction-pendulum bearings
kind = "isolated"
superstructure = "fixed"
isolator = {{ model = "friction_pendulum", mu = 0.06, radius = 2.24 }}   # R in m: T = 2π√(R/g)

# ---- contents: equipment on floors (0 = ground, or the base mat of an isolated building) --
[[contents]]
id = "cabinet"
floors = [1, "roof"]            # floor numbers and/or "roof"; or "all"
mu = [0.1, 0.2, 0.3]            # kinetic friction coefficients (not percent)
# mu_s = 0.35                   # static coefficient(s) (default: mu)
width = 0.6                     # m: with height, the rocking check (Shenton 1996)
height = 1.8                    # m
allowable = [0.05, 0.1]         # m: gaps to a wall, the exceedance table

# [[contents]]                  # flexible equipment (a 2-DOF sliding oscillator)
# id = "rack"
# floors = "roof"
# model = "oscillator"
# frequency = 8.0               # Hz (clamped base)
# mu = 0.2

# ---- floor response spectra ----------------------------------------------------------------
[spectra]
floors = "all"
damping = [0.05]
periods = {{ min = 0.1, max = 4.0, n = 40 }}    # s, log-spaced
# broadening = 0.15             # ±15 % in frequency (the unbroadened spectra are kept too)

# ---- report defaults (floorslide table, plot, report) ------------------------------------
[report]
periods = [0.1, 0.2, 0.5, 1.0]
damping = 0.05
compare = ["isolated:fixed"]
"""


def bundled_catalog() -> Path:
    """The bundled records' catalog (``data/records/slammer/index.csv``)."""
    import importlib.resources

    return (
        Path(str(importlib.resources.files("floorslide.data")))
        / "records"
        / "slammer"
        / ("index.csv")
    )


def scene_template(name: str = "scene.toml") -> str:
    """The commented scene template, its records the bundled catalog (an absolute path);
    `name` is the file name its comments use."""
    catalog = json.dumps(bundled_catalog().as_posix(), ensure_ascii=False)
    return TEMPLATE.format(marker=MARKER, name=name, catalog=catalog)
