"""Processing: each step does what it says, is recorded, and only when asked."""

from __future__ import annotations

import numpy as np
import pytest
from obspy import Trace

import floorslide as fs
from floorslide.errors import ModelError, UnitsError
from floorslide.records.measures import velocity_displacement
from floorslide.records.process import STEPS, baseline_correct
from tests.conftest import SLAMMER, G
from tests.records.conftest import ELC_FILE


def trace_of(data: np.ndarray, dt: float) -> Trace:
    tr = Trace(np.asarray(data, dtype=np.float64))
    tr.stats.delta = dt
    tr.stats.units = "m/s**2"
    return tr


@pytest.fixture
def elc():
    return fs.read_record(SLAMMER / ELC_FILE)[0]


def test_nothing_applied_unless_asked(elc):
    before = list(elc.stats.processing)
    out = fs.process(elc)
    assert out is not elc
    np.testing.assert_array_equal(out.data, elc.data)
    assert out.stats.processing == before
    # None and False skip a step, so a scene table can be passed as it is
    out = fs.process(elc, highpass=None, taper=False, baseline=False, demean=False)
    np.testing.assert_array_equal(out.data, elc.data)
    assert out.stats.processing == before


def test_input_is_not_modified(elc):
    data = elc.data.copy()
    fs.process(elc, demean=True, highpass=0.1, scale=2.0)
    np.testing.assert_array_equal(elc.data, data)


def test_demean_and_detrend():
    t = np.arange(1000) * 0.01
    tr = trace_of(3.0 + 0.5 * t, 0.01)
    assert abs(fs.process(tr, demean=True).data.mean()) < 1e-12
    assert np.abs(fs.process(tr, detrend="linear").data).max() < 1e-10
    cubic = trace_of(1 + t - 0.3 * t**2 + 0.02 * t**3, 0.01)
    out = fs.process(cubic, detrend="polynomial", detrend_order=3)
    assert np.abs(out.data).max() < 1e-8
    assert np.abs(fs.process(cubic, detrend=3).data).max() < 1e-8
    assert "type='polynomial'" in out.stats.processing[-1]


def test_taper_touches_only_the_ends():
    tr = trace_of(np.ones(1000), 0.01)
    out = fs.process(tr, taper=0.05)
    assert out.data[0] == 0.0 and out.data[-1] == 0.0
    np.testing.assert_array_equal(out.data[50:950], 1.0)
    assert "taper" in out.stats.processing[-1] and "max_percentage=0.05" in out.stats.processing[-1]


def _two_sines(dt=0.01, duration=200.0):
    t = np.arange(round(duration / dt)) * dt
    low = np.sin(2 * np.pi * 0.05 * t)
    high = np.sin(2 * np.pi * 5.0 * t)
    return t, low, high


def test_highpass_removes_a_low_frequency_sine():
    _, low, high = _two_sines()
    out = fs.process(trace_of(low + high, 0.01), highpass=1.0)
    middle = slice(5000, 15000)  # away from the end transients of the acausal filter
    # zero-phase 4-pole Butterworth: gain (1 + (fc/f)^8)^-1 = 1 - 4e-6 at 5 Hz, 4e-11 at 0.05 Hz
    np.testing.assert_allclose(out.data[middle], high[middle], atol=1e-4)
    assert "type='highpass'" in out.stats.processing[-1]
    assert "'zerophase': True" in out.stats.processing[-1]


def test_lowpass_and_bandpass():
    _, low, high = _two_sines()
    middle = slice(5000, 15000)
    out = fs.process(trace_of(low + high, 0.01), lowpass=1.0)
    np.testing.assert_allclose(out.data[middle], low[middle], atol=1e-4)
    band = fs.process(trace_of(low + high, 0.01), bandpass=(1.0, 20.0), filter_order=6)
    np.testing.assert_allclose(band.data[middle], high[middle], atol=1e-3)
    assert "'corners': 6" in band.stats.processing[-1]


def test_causal_filter_on_request():
    _, low, high = _two_sines()
    out = fs.process(trace_of(low + high, 0.01), highpass=1.0, zerophase=False)
    assert "'zerophase': False" in out.stats.processing[-1]
    middle = slice(5000, 15000)
    assert np.abs(out.data[middle] - high[middle]).max() > 0.01  # a causal filter shifts phase
    assert np.abs(out.data[middle]).max() == pytest.approx(1.0, abs=0.01)


def test_baseline_removes_a_polynomial_drift_in_displacement(elc):
    """Adding a polynomial u_d(t) = c2 t² + c3 t³ to the displacement (2 c2 + 6 c3 t to the
    acceleration, which is linear, so the piecewise-linear double integral is exactly u_d) does
    not change the corrected record: the drift lies in the space the fit removes."""
    dt = elc.stats.delta
    t = np.arange(elc.stats.npts) * dt
    drift = 2 * 0.004 + 6 * (-0.0002) * t
    clean = fs.process(elc, baseline=3)
    dirty = fs.process(trace_of(elc.data + drift, dt), baseline=3)
    np.testing.assert_allclose(dirty.data, clean.data, atol=1e-9 * np.abs(elc.data).max())
    # a pure drift is removed completely
    only = fs.process(trace_of(drift, dt), baseline=3)
    assert np.abs(only.data).max() < 1e-12
    assert "baseline(degrees=2..3" in clean.stats.processing[-1]


def test_baseline_default_degree_and_effect(elc):
    out = fs.process(elc, baseline=True)
    assert "degrees=2..6" in out.stats.processing[-1]
    # what is left of the displacement has no component along t², ..., t⁶ (up to the O(dt²)
    # of integrating the sampled correction as piecewise linear)
    _, after = velocity_displacement(out.data, elc.stats.delta)
    tau = np.linspace(0, 1, after.size)
    basis = np.stack([tau**j / np.linalg.norm(tau**j) for j in range(2, 7)])
    assert np.abs(basis @ after).max() < 1e-4 * np.linalg.norm(after)
    # no constant or linear term: the record still starts at rest
    corrected, coef = baseline_correct(elc.data, elc.stats.delta, 6)
    assert coef.size == 5
    np.testing.assert_array_equal(corrected, out.data)


def test_resample_keeps_a_sine_amplitude():
    """A whole number of periods is periodic, so FFT resampling (ideal band limit, no window)
    is exact: the resampled samples are the sine at the new times."""
    dt = 0.01
    t = np.arange(1000) * dt
    tr = trace_of(np.sin(2 * np.pi * 1.0 * t), dt)
    for new_dt in (0.005, 0.02, 0.004):
        out = fs.process(tr, resample=new_dt)
        assert out.stats.delta == pytest.approx(new_dt, rel=1e-12)
        t_new = np.arange(out.stats.npts) * new_dt
        np.testing.assert_allclose(out.data, np.sin(2 * np.pi * t_new), atol=1e-10)
        assert "resample(" in out.stats.processing[-1]
    # ObsPy's default Hann window would have damped the amplitude
    hann = fs.process(tr, resample=0.02, resample_window="hann")
    assert np.abs(hann.data).max() < 0.999


def test_scale_to_target_pga(elc):
    out = fs.process(elc, scale_pga=0.3)
    assert np.abs(out.data).max() == pytest.approx(0.3 * G, rel=1e-15)
    assert fs.measures(out)["pga_g"] == pytest.approx(0.3, rel=1e-15)
    assert "scale(target_pga_g=0.3" in out.stats.processing[-1]
    double = fs.process(elc, scale=2.0)
    np.testing.assert_array_equal(double.data, 2.0 * elc.data)
    assert double.stats.processing[-1].endswith("scale(factor=2.0)")


def test_order_of_application_is_fixed(elc):
    a = fs.process(elc, scale_pga=0.3, highpass=0.1, taper=0.05, demean=True)
    b = fs.process(elc, demean=True, taper=0.05, highpass=0.1, scale_pga=0.3)
    np.testing.assert_array_equal(a.data, b.data)
    steps = [line.split(": ", 1)[1].split("(")[0] for line in a.stats.processing[1:]]
    assert steps == ["detrend", "taper", "filter", "scale"]
    assert np.abs(a.data).max() == pytest.approx(0.3 * G, rel=1e-15)  # scaling comes last


def test_full_chain_is_recorded(elc):
    out = fs.process(
        elc,
        demean=True,
        detrend="linear",
        taper=0.05,
        highpass=0.1,
        lowpass=20.0,
        baseline=True,
        resample=0.005,
        scale_pga=0.25,
    )
    assert len(out.stats.processing) == 1 + 8
    assert out.stats.delta == 0.005
    assert out.data.dtype == np.float64


@pytest.mark.parametrize(
    ("steps", "message"),
    [
        ({"highpas": 0.1}, "unknown processing step 'highpas'"),
        ({"highpass": 60.0}, r"highpass: 60 Hz is at or above the Nyquist frequency 50 Hz"),
        ({"lowpass": 50.0}, r"lowpass: 50 Hz is at or above the Nyquist"),
        ({"highpass": -1.0}, r"highpass: -1.0 must be > 0"),
        ({"highpass": "fast"}, r"highpass: 'fast' is not a number"),
        ({"highpass": "0_1"}, r"highpass: '0_1' is not a number"),  # float('0_1') is 1.0
        ({"bandpass": (0.1, 20), "highpass": 0.1}, "either bandpass or highpass"),
        ({"bandpass": (20, 0.1)}, "low corner 20 Hz must be below"),
        ({"bandpass": 5.0}, "must be a pair"),
        ({"detrend": "quadratic"}, "detrend: 'quadratic'"),
        ({"detrend": "polynomial"}, "detrend_order: needed"),
        ({"detrend_order": 2}, "without detrend='polynomial'"),
        ({"taper": 0.7}, "must be ≤ 0.5"),
        ({"baseline": 1}, "baseline: 1 must be an integer ≥ 2"),
        ({"filter_order": 2.5, "highpass": 0.1}, "filter_order: 2.5 must be an integer"),
        ({"zerophase": "yes", "highpass": 0.1}, "zerophase: 'yes' must be true or false"),
        ({"resample": 0.0}, r"resample: 0.0 must be > 0"),
        ({"scale_pga": 0.3, "scale": 2.0}, "either scale or scale_pga"),
        ({"scale": 0.0}, "finite, non-zero"),
        ({"demean": "yes"}, "demean: 'yes' must be true or false"),
    ],
)
def test_bad_steps_are_clear_errors(elc, steps, message):
    with pytest.raises(ModelError, match=message):
        fs.process(elc, **steps)


def test_trace_in_other_units_is_refused():
    tr = trace_of(np.ones(10), 0.01)
    tr.stats.units = "g"
    with pytest.raises(UnitsError, match="processing works on m/s"):
        fs.process(tr, scale_pga=0.3)


def test_steps_constant_lists_every_keyword():
    assert STEPS[0] == "demean" and STEPS[-1] == "scale"
    assert len(set(STEPS)) == len(STEPS)
