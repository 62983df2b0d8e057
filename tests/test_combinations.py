"""Every consumer on every building kind, in 1-D and in the plane, with and without vertical
shaking, from the Python API: each cell gives a result or a one-line
:class:`~floorslide.errors.FloorslideError` naming the argument — never another exception.

The cells that run today are listed (``RUNS``), so that a cell that stops running is seen as well
as one that starts to; the refused ones name the argument at fault.
"""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.errors import FloorslideError
from floorslide.pair import make_pair
from tests.conftest import SLAMMER, G

A = np.loadtxt(SLAMMER / "ImperialValley_1940_ELC-180.txt")[:400] * G
DT = 0.01
AV = 0.3 * A[::-1].copy()
PAIR = make_pair(A, 0.7 * A[::-1].copy(), DT)
PAIR_V = make_pair(A, 0.7 * A[::-1].copy(), DT, vertical=AV)


def _sup():
    return fs.ShearBuilding.from_period(stories=2, period=0.3, damping=0.03)


BUILDINGS = {
    "ground": lambda: None,
    "fixed": _sup,
    "linear isolated": lambda: fs.IsolatedBuilding(_sup(), 1.0, 2.5, 0.1),
    "friction pendulum": lambda: fs.NonlinearIsolatedBuilding(
        _sup(), 1.0, fs.FrictionPendulum(mu=0.05, period=3.0)
    ),
    "lead-rubber": lambda: fs.NonlinearIsolatedBuilding(
        _sup(), 1.0, fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02)
    ),
    "a pair of models": lambda: fs.BuildingPair(
        _sup(), fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.03)
    ),
}


def _floor(b):
    return None if b is None else 2


CONSUMERS = {
    "slide": lambda b, v: fs.slide(A, DT, [0.1], building=b, floor=_floor(b), vertical=v),
    "slide_plane": lambda b, v: fs.slide_plane(
        PAIR_V, None, [0.1], building=b, floor=_floor(b), vertical=v
    ),
    "slide_oscillator": lambda b, v: fs.slide_oscillator(
        A, DT, [0.1], 5.0, building=b, floor=_floor(b), vertical=v
    ),
    "slide_oscillator_plane": lambda b, v: fs.slide_oscillator_plane(
        PAIR_V, None, [0.1], 5.0, building=b, floor=_floor(b), vertical=v
    ),
    "rock": lambda b, v: fs.rock(A, DT, 0.3, 1.2, building=b, floor=_floor(b)),
    "response_spectrum": lambda b, v: fs.response_spectrum(
        A, DT, [0.2, 1.0], building=b, floor=_floor(b)
    ),
    "rotd_spectrum": lambda b, v: fs.rotd_spectrum(
        PAIR, None, [0.2, 1.0], building=b, floor=_floor(b)
    ),
    "slide_coupled": lambda b, v: fs.slide_coupled(
        A, DT, [0.1], mass=0.1, building=b, floor=_floor(b)
    ),
    "slide_rock": lambda b, v: fs.slide_rock(
        A, DT, 0.3, 1.2, 0.3, building=b, floor=_floor(b), vertical=v
    ),
    "floor_motions": lambda b, v: fs.floor_motions(b, A, DT, floors=[1, 2]),
    "peak_floor_acceleration": lambda b, v: fs.peak_floor_acceleration(b, A, DT),
}
VERTICAL = {"slide", "slide_plane", "slide_oscillator_plane", "slide_oscillator", "slide_rock"}
"""The consumers with a ``vertical`` argument (the 2-DOF oscillators and the slide–rock block
refuse it in one line; the rocking block has none yet)."""

RUNS = (
    {
        (c, b, False)
        for c in CONSUMERS
        for b in BUILDINGS
        if not (b == "ground" and c == "floor_motions")
        and not (
            b == "a pair of models"
            and c not in ("slide_plane", "rotd_spectrum", "slide_oscillator_plane")
        )
        # heavy equipment acting back on its floor: 1-D, one model
        and not (c == "slide_coupled" and b == "ground")
    }
    | {
        ("slide", b, True)
        for b in ("ground", "fixed", "linear isolated", "friction pendulum", "lead-rubber")
    }
    | {
        ("slide_plane", b, True)
        for b in (
            "ground",
            "fixed",
            "linear isolated",
            "a pair of models",
            "friction pendulum",
            "lead-rubber",
        )
    }
)
"""The cells that give a result today (consumer, building, with vertical shaking)."""


CELLS = [
    pytest.param(c, b, v, id=f"{c}-{b}{'-vertical' if v else ''}")
    for c in CONSUMERS
    for b in BUILDINGS
    for v in ((False, True) if c in VERTICAL else (False,))
]


@pytest.mark.parametrize(("consumer", "building", "vertical"), CELLS)
def test_every_cell_runs_or_is_refused_in_one_line(consumer, building, vertical):
    b = BUILDINGS[building]()
    try:
        result = CONSUMERS[consumer](b, AV if vertical else None)
    except FloorslideError as exc:
        text = str(exc)
        assert "\n" not in text and exc.where, text
        assert (consumer, building, vertical) not in RUNS, f"refused: {text}"
        return
    assert result is not None
    assert (consumer, building, vertical) in RUNS, "runs: add it to RUNS"
