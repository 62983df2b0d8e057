"""The floor motion as one object (issue 20 §2): integrated once, read by every exact solver,
memory-bounded, and giving the same bits whichever way it is held or reached."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building import exact_motion
from floorslide.errors import ModelError

PERIODS = np.r_[0.0, np.geomspace(0.03, 4.0, 25)]


@pytest.fixture(scope="module")
def record():
    rng = np.random.default_rng(20)
    dt = 0.01
    t = np.arange(1500) * dt
    a = 3.0 * np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.2 * t) + rng.normal(0.0, 0.8, t.size)
    return a, dt


@pytest.fixture(scope="module")
def buildings():
    fb = fs.ShearBuilding.from_period(3, 0.4, 0.05)
    return {"fixed": fb, "isolated": fs.IsolatedBuilding(fb, 1.0, 2.5, 0.10)}


def _everything(fm, vertical):
    mus = np.array([0.03, 0.08, 0.2])
    s = fs.slide(fm, mu_k=mus, histories=True, vertical=vertical)
    o = fs.slide_oscillator(fm, mu=mus, frequency=9.0, damping=0.05, histories=True)
    sp = fs.response_spectrum(fm, periods=PERIODS, damping=[0.02, 0.05])
    return [
        s.peak_slide,
        s.residual_slide,
        s.u,
        s.abs_accel,
        np.array([s.liftoff_time, s.liftoff_count]),
        o.peak_slide,
        o.peak_deformation,
        o.u,
        o.z,
        sp.sd,
        sp.sa,
        np.array(fm.peak()),
        fm.samples(),
    ]


@pytest.mark.parametrize("kind,floor", [("fixed", 3), ("isolated", 3), ("isolated", 0)])
def test_chunked_motion_gives_the_same_bits(record, buildings, kind, floor, monkeypatch):
    """A motion too long to keep whole (checkpoints, chunks recomputed on demand) gives every
    consumer exactly the numbers of the whole one, chunk boundaries and lift-off included."""
    a, dt = record
    vert = 1.2 * fs.G * np.sin(2 * np.pi * 3.0 * np.arange(a.size) * dt)
    whole = fs.building_motion(buildings[kind], a, dt)
    assert whole.kept_whole
    monkeypatch.setattr(exact_motion, "CHUNK_BYTES", 64 * whole.n * whole.substeps * 8)
    chunked = fs.building_motion(buildings[kind], a, dt, max_bytes=1000)
    assert not chunked.kept_whole and chunked.chunk_steps == 64
    assert len(list(chunked.chunks())) == -(-(a.size - 1) // 64)
    for x, y in zip(
        _everything(whole.floor(floor), vert), _everything(chunked.floor(floor), vert), strict=True
    ):
        np.testing.assert_array_equal(x, y)


@pytest.mark.parametrize("kind,floor", [(None, 0), ("fixed", 0), ("fixed", 2), ("isolated", 1)])
def test_floor_motion_equals_building_and_floor_arguments(record, buildings, kind, floor):
    """``slide(fm, ...)`` is ``slide(acc, dt, ..., building=, floor=)``, bit for bit (and so
    for the oscillator and the spectra)."""
    a, dt = record
    b = buildings.get(kind)
    fm = fs.floor_motion(b, a, floor, dt)
    on = dict(building=b, floor=floor) if b is not None else {}
    mus = [0.05, 0.15]
    x, y = fs.slide(fm, mu_k=mus), fs.slide(a, dt, mus, **on)
    np.testing.assert_array_equal(x.peak_slide, y.peak_slide)
    np.testing.assert_array_equal(x.residual_slide, y.residual_slide)
    x = fs.slide_oscillator(fm, mu=mus, frequency=5.0)
    y = fs.slide_oscillator(a, dt, mus, 5.0, **on)
    np.testing.assert_array_equal(x.peak_slide, y.peak_slide)
    np.testing.assert_array_equal(x.peak_deformation, y.peak_deformation)
    x = fs.response_spectrum(fm, periods=PERIODS)
    y = fs.response_spectrum(a, dt, PERIODS, **on)
    np.testing.assert_array_equal(x.sa, y.sa)
    np.testing.assert_array_equal(x.sd, y.sd)
    if b is not None:
        np.testing.assert_array_equal(
            fm.peak()[0], fs.peak_floor_acceleration(b, a, dt, [floor]).peak[0]
        )
        np.testing.assert_allclose(
            fm.samples(), fs.floor_motions(b, a, dt, [floor])[0], rtol=0, atol=1e-12
        )


def test_consumers_never_integrate_the_building_again(record, buildings, monkeypatch):
    """One ``foh_states`` pass builds the motion; the slides, oscillators, spectra, peaks and
    samples of every floor then read it."""
    a, dt = record
    calls = []
    real = exact_motion.foh_states

    def counting(*args):
        calls.append(1)
        return real(*args)

    monkeypatch.setattr(exact_motion, "foh_states", counting)
    motion = fs.building_motion(buildings["isolated"], a, dt)
    assert len(calls) == 1
    for floor in (0, 1, 3):
        fm = motion.floor(floor)
        fs.slide(fm, mu_k=[0.1])
        fs.slide_oscillator(fm, mu=[0.1], frequency=4.0)
        fs.response_spectrum(fm, periods=[0.0, 0.5])
    motion.peaks()
    motion.samples()
    assert len(calls) == 1


def test_the_motion_is_its_own_copy(record, buildings):
    """Changing the caller's array afterwards changes nothing; the motion's arrays are
    read-only."""
    a, dt = record
    mine = a.copy()
    motion = fs.building_motion(buildings["fixed"], mine, dt)
    before = fs.slide(motion.floor(3), mu_k=[0.1]).peak_slide
    mine[:] = 0.0
    assert fs.slide(motion.floor(3), mu_k=[0.1]).peak_slide == before
    for arr in (motion.acc, next(iter(motion.chunks()))[1]):
        with pytest.raises(ValueError):
            arr[0] = 1.0


def test_bad_combinations_are_refused(record, buildings):
    a, dt = record
    fm = fs.floor_motion(buildings["fixed"], a, 2, dt)
    with pytest.raises(ModelError, match="FloorMotion"):
        fs.slide(fm, mu_k=[0.1], building=buildings["fixed"], floor=2)
    with pytest.raises(ModelError, match="dt"):
        fs.response_spectrum(fm, 0.02, [0.5])
    with pytest.raises(ModelError, match="by keyword"):  # friction values in dt's place
        fs.slide_oscillator(fm, [0.1, 0.2], 5.0)
    with pytest.raises(ModelError, match="floor 7 does not exist"):
        fs.building_motion(buildings["fixed"], a, dt).floor(7)
    with pytest.raises(ModelError, match="needs building"):
        fs.building_motion(None, a, dt).floor(2)


def test_a_long_record_is_streamed_in_bounded_memory(buildings):
    """10⁶ samples on a 3-storey isolated building: whole, the states take 64 MB per sub-step;
    streamed, the first pass needs well under a megabyte (checkpoints and one chunk) and gives
    the peak of the whole motion, bit for bit; a second pass starts from the checkpoints."""
    import tracemalloc

    rng = np.random.default_rng(1)
    a = np.repeat(rng.normal(0.0, 1.0, 10_001), 100)[:1_000_000]
    b = buildings["isolated"]
    fs.building_motion(b, a[:50], 0.005, max_bytes=0).peaks([3])  # compile outside
    tracemalloc.start()
    motion = fs.building_motion(b, a, 0.005, max_bytes=8 * 2**20, copy=False)
    peak, _ = motion.peaks([3])
    used = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert not motion.kept_whole
    assert used < 1e6
    assert len(motion._checkpoints) == -(-(a.size - 1) // motion.chunk_steps)
    np.testing.assert_array_equal(motion.peaks([3])[0], peak)
    whole = fs.building_motion(b, a, 0.005)
    assert whole.kept_whole
    np.testing.assert_array_equal(peak, whole.peaks([3])[0])
