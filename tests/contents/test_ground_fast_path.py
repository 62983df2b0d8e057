"""The ground's own kernel (``contents/_ground_kernel.py``) against the general kernel.

``slide()`` on the ground without vertical shaking runs a kernel specialised to the ground (a
linear floor acceleration inside a step); the general event-driven kernel, run on the ground's
motion (``_slide_exact(..., general=True)``), is its reference. The specialised kernel replays
the general one's decisions and arithmetic, so every result must be the same **bits**; the
tolerance check (1e-12 of the peak slide) comes first so that a failure says how large the
difference is. Real records read by :func:`floorslide.read_record`, many friction values
(zero, 1e-4, 5, the range where blocks chatter, ``mu_s`` above and below ``mu_k``), the three
directions, histories, every way the ground reaches the solver (samples, Trace, FloorMotion,
floor 0 of a fixed-base building), the event limit, and the unchanged validation.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.exact_motion import floor_motion
from floorslide.constants import G
from floorslide.contents import sliding
from floorslide.contents.sliding import _slide_exact, friction_pairs, slide
from floorslide.errors import ModelError, SolverLimitError

DATA = Path(__file__).resolve().parents[2] / "data" / "records"
RECORDS = [
    "slammer/Kobe_1995_KAK-000.txt",
    "slammer/ImperialValley_1940_ELC-180.txt",
    "slammer/CapeMendocino_1992_PET-090.txt",
    "slammer/Landers_1992_LCN-260.txt",
    "pairs/RSN1084_NORTHR_SCS052.AT2",
    "pairs/RSN511_PALMSPR_ARM270.AT2",
]
FIELDS = (
    "peak_slide",
    "residual_slide",
    "peak_abs_accel",
    "slide_fraction",
    "slip_phases",
    "time_of_peak",
    "liftoff_time",
    "liftoff_count",
    "duration",
)
HISTORIES = ("u", "v", "abs_accel")


def _record(name):
    tr = fs.read_record(DATA / name)[0]
    return np.ascontiguousarray(tr.data, dtype=float), float(tr.stats.delta)


def _frictions(acc):
    """Kinetic coefficients from none to far above the record's peak: 0, 1e-4, 5, and a grid
    through the chattering range ``mu·g`` ≈ PGA."""
    pga = float(np.max(np.abs(acc)))
    eta = np.concatenate([np.linspace(0.01, 1.1, 31), [0.999, 1.0, 1.001]])
    return np.concatenate([[0.0, 1e-4, 5.0], eta * pga / G])


def general(acc, dt, mk, ms=None, direction="both", histories=False):
    """The general kernel on the ground's motion: the reference."""
    return _slide_exact(
        floor_motion(None, acc, dt=dt),
        *friction_pairs(mk, ms),
        None,
        direction,
        histories,
        general=True,
    )


def same(fast, ref, histories=False):
    """Within 1e-12 of the peak slide (rounding), then bit for bit, sign of zero included."""
    scale = np.maximum(ref.peak_slide, 1e-12)
    for name in ("peak_slide", "residual_slide"):
        err = np.abs(getattr(fast, name) - getattr(ref, name)) / scale
        assert np.max(err) <= 1e-12, (name, float(np.max(err)))
    if histories:
        for name in ("u", "v"):
            err = np.max(np.abs(getattr(fast, name) - getattr(ref, name)), axis=1) / scale
            assert np.max(err) <= 1e-12, (name, float(np.max(err)))
    for name in FIELDS + (HISTORIES if histories else ()):
        x = np.asarray(getattr(fast, name))
        y = np.asarray(getattr(ref, name))
        assert x.shape == y.shape, name
        assert np.array_equal(x, y), name
        assert np.array_equal(np.signbit(x), np.signbit(y)), name
    if not histories:
        assert fast.u is None and ref.u is None


@pytest.fixture(scope="module", params=RECORDS)
def record(request):
    return _record(request.param)


@pytest.mark.parametrize("ratio", [1.0, 1.5, 0.6])
def test_real_records(record, ratio):
    """``mu_s = ratio·mu_k``: equal, static above kinetic, and below (breakaway at mu_k)."""
    acc, dt = record
    mk = _frictions(acc)
    ms = ratio * mk
    same(slide(acc, dt, mk, ms), general(acc, dt, mk, ms))


@pytest.mark.parametrize("direction", ["positive", "negative"])
def test_one_way(record, direction):
    acc, dt = record
    mk = _frictions(acc)
    same(
        slide(acc, dt, mk, 1.2 * mk, direction=direction),
        general(acc, dt, mk, 1.2 * mk, direction=direction),
    )


@pytest.mark.parametrize("direction", ["both", "positive"])
def test_histories(direction):
    acc, dt = _record(RECORDS[0])
    mk = _frictions(acc)[::3]
    fast = slide(acc, dt, mk, 1.3 * mk, direction=direction, histories=True)
    same(fast, general(acc, dt, mk, 1.3 * mk, direction=direction, histories=True), True)


def test_one_object_per_call_and_scalars(record):
    """Scalar friction (the quick entry of slide) gives the batch's row, bit for bit."""
    acc, dt = record
    mk = _frictions(acc)[::4]
    batch = slide(acc, dt, mk, 1.5 * mk)
    for i, m in enumerate(mk):
        one = slide(acc, dt, float(m), float(1.5 * m))
        assert one.peak_slide[0] == batch.peak_slide[i]
        assert one.residual_slide[0] == batch.residual_slide[i]
        assert one.slip_phases[0] == batch.slip_phases[i]
        assert one.time_of_peak[0] == batch.time_of_peak[i]


def test_chatter():
    """Stick–slip chatter: a floor that oscillates about the breakaway level every sample, and
    a record starting beyond it (a block that moves at t = 0), with zero friction too."""
    rng = np.random.default_rng(3)
    n = 3000
    t = np.arange(n) * 0.005
    mu = 0.2
    acc = mu * G * (1.0 + 0.02 * (-1.0) ** np.arange(n)) * np.sin(2 * np.pi * 0.7 * t)
    acc += 0.01 * rng.standard_normal(n)
    shifted = acc + 1.5 * mu * G
    for a in (acc, shifted, -shifted):
        mk = np.array([0.0, 1e-4, 0.19, 0.199, 0.2, 0.201, 0.21, 0.3, 5.0])
        for ms in (mk, 1.05 * mk, 0.95 * mk):
            for direction in ("both", "positive", "negative"):
                same(
                    slide(a, 0.005, mk, ms, direction=direction, histories=True),
                    general(a, 0.005, mk, ms, direction=direction, histories=True),
                    True,
                )


def test_short_records():
    for acc in (np.array([0.0]), np.array([3.0]), np.array([0.0, 4.0]), np.array([-5.0, 5.0])):
        mk = np.array([0.0, 0.1, 0.5, 5.0])
        same(slide(acc, 0.01, mk, histories=True), general(acc, 0.01, mk, histories=True), True)


def test_every_ground_entry():
    """Samples, an ObsPy Trace, a FloorMotion of the ground and floor 0 of a fixed-base
    building all reach the ground's kernel and give the reference's bits."""
    tr = fs.read_record(DATA / RECORDS[1])[0]
    acc, dt = np.ascontiguousarray(tr.data, dtype=float), float(tr.stats.delta)
    mk = _frictions(acc)[::2]
    ref = general(acc, dt, mk)
    same(slide(acc, dt, mk), ref)
    same(slide(tr, mu_k=mk), ref)
    same(slide(floor_motion(None, acc, dt=dt), mu_k=mk), ref)
    same(slide(list(acc), dt, mk), ref)  # not a plain array: the full path
    strided = np.repeat(acc, 2)[::2]  # not C-ordered: the full path
    same(slide(strided, dt, mk), ref)
    building = fs.ShearBuilding.from_period(3, 0.4, 0.05)
    same(slide(acc, dt, mk, building=building, floor=0), ref)
    # vertical shaking goes through the general kernel
    vert = 0.3 * acc[::-1].copy()
    with_v = slide(acc, dt, mk, vertical=vert)
    ref_v = _slide_exact(
        floor_motion(None, acc, dt=dt), *friction_pairs(mk), vert, "both", False, general=True
    )
    same(with_v, ref_v)


def test_event_limit(monkeypatch):
    """Both kernels stop at the same event with the same message when the limit is reached."""
    acc, dt = _record(RECORDS[0])
    mk = _frictions(acc)
    monkeypatch.setattr(sliding, "SLIDE_MAX_EVENTS", 1)
    with pytest.raises(SolverLimitError) as fast:
        slide(acc, dt, mk)
    with pytest.raises(SolverLimitError) as ref:
        general(acc, dt, mk)
    assert str(fast.value) == str(ref.value)


@pytest.mark.parametrize(
    "args, kwargs, match",
    [
        ((np.array([0.0, np.nan]), 0.01, 0.1), {}, "NaN or infinite"),
        ((np.array([0.0, np.inf]), 0.01, -0.1), {}, "NaN or infinite"),  # record first
        ((np.array([0.0, 1.0]), 0.01, -0.1), {}, "mu_k must be finite"),
        ((np.array([0.0, 1.0]), 0.01, 0.1, np.nan), {}, "mu_s must be finite"),
        ((np.array([0.0, 1.0]), 0.0, 0.1), {}, "dt must be > 0"),
        ((np.array([0.0, 1.0]), None, 0.1), {}, "dt .* is required"),
        ((np.array([]), 0.01, 0.1), {}, "non-empty"),
        ((np.array([0.0, 1.0]), 0.01, None), {}, "mu_k .* is required"),
        ((np.array([0.0, 1.0]), 0.01, 0.1), {"direction": "up"}, "direction must be one of"),
        ((np.array([0.0, 1.0]), 0.01, [0.1, 0.2], [0.1, 0.2, 0.3]), {}, "must be one value"),
    ],
)
def test_validation_unchanged(args, kwargs, match):
    with pytest.raises(ModelError, match=match):
        slide(*args, **kwargs)
