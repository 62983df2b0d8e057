"""Record quality checks (floorslide.records.quality): each check trips on a record that has
the defect and stays quiet on one that does not; the raw K-NET record (a DC offset) is flagged,
and is clean after ``demean`` with intensity measures within 1 % of a hand computation."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

import floorslide as fs
from floorslide.cli import cli
from floorslide.records.quality import CHECKS, check_record, flat_runs, pre_event_window
from tests.conftest import SLAMMER, G
from tests.records.conftest import ELC_FILE, FIXTURES

KNET_RAW = FIXTURES.parent / "raw" / "AOM0081801241951.NS"


def knet_by_hand() -> tuple[np.ndarray, float]:
    """The raw K-NET record in m/s², parsed here with NumPy alone (17 header lines, integer
    counts × the header's scale factor in gal), independent of ObsPy and floorslide."""
    lines = KNET_RAW.read_text().splitlines()
    scale = next(line for line in lines if line.startswith("Scale Factor")).split()[-1]
    num, den = scale.split("/")
    factor = float(num.replace("(gal)", "")) / float(den) / 100.0  # gal → m/s²
    counts = np.array([int(v) for line in lines[17:] for v in line.split()], dtype=float)
    freq = next(line for line in lines if line.startswith("Sampling Freq")).split()[-1]
    return counts * factor, 1.0 / float(freq.replace("Hz", ""))


@pytest.fixture(scope="module")
def elc(elc_si) -> tuple[np.ndarray, float]:
    return elc_si, 0.01


# --- the raw K-NET record --------------------------------------------------------------------


def test_raw_knet_is_flagged_for_its_offset_and_clean_after_demean():
    trace = fs.read_record(KNET_RAW)[0]
    raw = check_record(trace.data, trace.stats.delta)
    assert raw.codes == ("offset",)
    off = raw.values["offset"]
    a, dt = knet_by_hand()
    assert trace.data == pytest.approx(a, rel=1e-12)
    duration = (a.size - 1) * dt
    mean = np.trapezoid(a, dx=dt) / duration
    assert off["mean"] == pytest.approx(mean, rel=1e-10)
    assert off["mean_ratio"] == pytest.approx(abs(mean) / np.abs(a).max(), rel=1e-10)
    assert off["mean_ratio"] > 0.05  # 6.3 % of PGA
    # the pre-event window: the first ~16 s, before the P wave
    assert 15.0 < off["pre_event_seconds"] < 17.0
    assert off["pre_event_mean_ratio"] > 0.05
    assert off["displacement_drift"] == pytest.approx(0.5 * mean * duration**2, rel=1e-10)
    assert raw.suggestions() == ["--detrend demean"]
    assert "demean = true" == raw.flags[0].fix_scene

    clean = fs.process(trace, demean=True)
    assert check_record(clean.data, dt).ok


def test_demeaned_knet_measures_match_a_hand_computation_within_1_percent():
    a, dt = knet_by_hand()
    a = a - a.mean()  # demean, by hand
    v = np.concatenate(([0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * dt)))
    u = np.concatenate(([0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * dt)))
    # ∫a² of the piecewise-linear record, step by step: h (a0² + a0 a1 + a1²) / 3
    e = np.concatenate(([0.0], np.cumsum(dt * (a[1:] ** 2 + a[1:] * a[:-1] + a[:-1] ** 2) / 3)))
    t = np.arange(a.size) * dt
    hand = {
        "pga": np.abs(a).max(),
        "pgv": np.abs(v).max(),
        "pgd": np.abs(u).max(),
        "arias": np.pi / (2 * G) * e[-1],
        "d5_95": np.interp(0.95 * e[-1], e, t) - np.interp(0.05 * e[-1], e, t),
    }
    m = fs.measures(fs.process(fs.read_record(KNET_RAW)[0], demean=True))
    for key, value in hand.items():
        assert m[key] == pytest.approx(value, rel=0.01), key
    # and not by accident: the raw record's PGD is thousands of times larger
    assert fs.measures(fs.read_record(KNET_RAW)[0])["pgd"] > 1000 * hand["pgd"]


def test_the_bundled_records_raise_no_flag():
    for path in sorted(SLAMMER.glob("*.txt")):
        tr = fs.read_record(path)[0]
        report = check_record(tr.data, tr.stats.delta)
        assert report.ok, (path.name, report.lines())
        assert report.checked == ("offset", "trend", "clipping", "truncated")


# --- each check: a record that trips it and one that does not --------------------------------


def test_offset(elc):
    a, dt = elc
    pga = np.abs(a).max()
    assert "offset" not in check_record(a, dt).codes
    assert "offset" not in check_record(a + 0.0005 * pga, dt).codes  # 0.05 % < 0.1 %
    report = check_record(a + 0.005 * pga, dt)
    assert report.codes == ("offset",)
    assert report.values["offset"]["mean_ratio"] == pytest.approx(0.005, rel=0.01)


def test_offset_in_the_pre_event_window(elc):
    """A baseline offset throughout a record with a quiet start (the raw K-NET case): the
    pre-event window shows it, its mean is the offset; without an offset the window's mean is
    nothing."""
    a, dt = elc
    pga = np.abs(a).max()
    quiet = np.concatenate((np.zeros(500), a))  # 5 s before the event
    clean = check_record(quiet, dt)
    assert clean.ok and clean.values["offset"]["pre_event_seconds"] >= 4.99
    assert clean.values["offset"]["pre_event_mean_ratio"] < 1e-3
    report = check_record(quiet + 0.03 * pga, dt)
    assert report.codes == ("offset",)
    assert "pre-event mean" in report.flags[0].message
    off = report.values["offset"]
    assert off["pre_event_mean"] == pytest.approx(0.03 * pga, rel=1e-3)


def test_pre_event_window_needs_one_second_and_twenty_samples():
    t = np.arange(0, 10, 0.01)
    a = np.where(t < 0.5, 0.0, np.sin(2 * np.pi * t))
    assert pre_event_window(a, 0.01) == 0  # 0.5 s: too short
    b = np.where(t < 2.0, 0.0, np.sin(2 * np.pi * t))
    onset = int(np.argmax(np.abs(b) >= 0.02 * np.abs(b).max()))  # just after 2 s (sin 0 = 0)
    assert onset in (200, 201) and pre_event_window(b, 0.01) == onset


def test_trend(elc):
    a, dt = elc
    pga = np.abs(a).max()
    t = np.arange(a.size) * dt
    ramp = (t - t.mean()) / (t[-1] - t[0])  # rises by 1 over the record, mean 0
    assert "trend" not in check_record(a + 0.002 * pga * ramp, dt).codes
    report = check_record(a + 0.02 * pga * ramp, dt)
    assert "trend" in report.codes
    assert report.values["trend"]["trend_ratio"] == pytest.approx(0.02, rel=0.02)
    assert "--detrend linear" in report.suggestions()
    processed = fs.process(fs.read_record(SLAMMER / ELC_FILE)[0], detrend="linear")
    processed.data = processed.data + 0.02 * pga * ramp
    assert "trend" in check_record(processed.data, dt).codes
    assert "trend" not in check_record(fs.process(processed, detrend="linear").data, dt).codes


def test_clipping(elc):
    a, dt = elc
    pga = np.abs(a).max()
    clipped = np.clip(a, -0.8 * pga, 0.8 * pga)
    report = check_record(clipped, dt)
    assert report.codes == ("clipping",)
    runs, samples, longest = flat_runs(clipped, 0.99, 3)
    assert report.values["clipping"]["flat_runs"] == runs > 0
    # by hand: the samples at the clip level, in runs of 3 or more
    at = np.abs(clipped) == 0.8 * pga
    padded = np.concatenate(([False], at, [False]))
    edges = np.flatnonzero(padded[1:] != padded[:-1])
    lengths = edges[1::2] - edges[::2]
    assert runs == int((lengths >= 3).sum()) and samples == int(lengths[lengths >= 3].sum())
    assert longest == lengths.max()
    assert report.suggestions() == []  # no processing restores a clipped peak
    assert "lower bounds" in report.flags[0].advice
    # at the peak: two equal samples are not a run; one run of three is quantisation, not
    # clipping; six samples in runs (two plateaus of three, or one of six) are
    b = a.copy()
    k = int(np.argmax(np.abs(b)))
    b[k + 1] = b[k]
    assert "clipping" not in check_record(b, dt).codes
    b[k + 2] = b[k]
    assert flat_runs(b, 0.99, 3) == (1, 3, 3)
    assert "clipping" not in check_record(b, dt).codes
    j = int(np.argmax(np.where(np.arange(b.size) > k + 10, -b * np.sign(b[k]), -np.inf)))
    b[j : j + 3] = -b[k]  # a second plateau, at the other extreme
    assert flat_runs(b, 0.99, 3)[:2] == (2, 6)
    assert "clipping" in check_record(b, dt).codes
    c = a.copy()
    c[k : k + 6] = c[k]
    assert check_record(c, dt).codes == ("clipping",)


def test_truncated(elc):
    a, dt = elc
    cut = a[:800]  # El Centro stopped at 8 s, in its strong shaking
    report = check_record(cut, dt)
    # the cut record also ends moving: its mean (v(8 s)/8 s) and trend flag it too
    assert "truncated" in report.codes
    share = report.values["truncated"]["tail_arias_ratio"]
    centred = cut - np.trapezoid(cut, dx=dt) / ((cut.size - 1) * dt)
    e = np.concatenate(
        (
            [0.0],
            np.cumsum(dt * (centred[1:] ** 2 + centred[1:] * centred[:-1] + centred[:-1] ** 2) / 3),
        )
    )
    start = int(np.floor(0.95 * (cut.size - 1)))
    assert share == pytest.approx((e[-1] - e[start]) / e[-1], rel=1e-12)
    assert share > CHECKS["truncated"].thresholds["tail_arias_ratio"]
    flag = next(f for f in report.flags if f.check == "truncated")
    assert flag.fix == "" and "lower bounds" in flag.advice  # no processing restores it
    assert "truncated" not in check_record(a, dt).codes


def test_samples_per_period(elc):
    a, _ = elc
    assert check_record(a, 0.01).checked[-1] == "truncated"  # no periods: not checked
    assert check_record(a, 0.01, periods=[0.0, 0.04, 1.0]).ok  # 4 samples, and 0 = PGA
    report = check_record(a, 0.01, periods=[0.0, 0.02, 0.03, 1.0])
    assert report.codes == ("samples_per_period",)
    assert report.values["samples_per_period"]["samples_per_period"] == pytest.approx(2.0)
    assert "2 of the 3 periods" in report.flags[0].message
    assert report.suggestions() == [] and "4·dt" in report.flags[0].advice


def test_short_and_zero_records_are_not_judged_by_ratios():
    assert check_record(np.zeros(100), 0.01).ok
    assert check_record(np.array([1.0, 2.0]), 0.01).checked == ()
    huge = np.array([1e300, -1e300, 1e300, 0.0])
    with np.errstate(all="raise"):
        check_record(huge, 0.01)  # no floating-point error escapes


def test_report_to_dict_is_json():
    a, dt = knet_by_hand()
    d = check_record(a, dt).to_dict()
    assert json.loads(json.dumps(d)) == d
    assert d["flags"] == ["offset"] and d["suggest"] == ["--detrend demean"]
    assert set(d["checks"]) == {"offset", "trend", "clipping", "truncated", "samples_per_period"}


# --- the command line ------------------------------------------------------------------------


def invoke(*args: str):
    result = CliRunner().invoke(cli, list(args))
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    return result


def test_inspect_shows_the_flags_and_the_remedy():
    out = invoke("inspect", str(KNET_RAW))
    assert out.exit_code == 0  # flags are not errors
    assert "quality: 1 of 1 records flagged" in out.stdout
    assert "offset: pre-event mean" in out.stdout and "try --detrend demean" in out.stdout
    assert "suggested processing: --detrend demean" in out.stdout
    fixed = invoke("inspect", str(KNET_RAW), "--detrend", "demean")
    assert "quality: no flags on the 1 processed records" in fixed.stdout
    rows = json.loads(invoke("inspect", "--json", str(KNET_RAW), "--detrend", "demean").stdout)
    assert rows[0]["qa"]["flags"] == [] and "demean" in rows[0]["processing"][0]
    assert rows[0]["pgd"] < 0.1
    raw = json.loads(invoke("inspect", "--json", str(KNET_RAW)).stdout)[0]
    assert raw["qa"]["flags"] == ["offset"] and raw["pgd"] > 100


def test_slide_and_spectrum_warn_and_take_the_processing_options():
    out = invoke("slide", str(KNET_RAW), "--mu", "0.002")
    assert "floorslide: warning:" in out.stderr and "offset" in out.stderr
    assert "--detrend demean" in out.stderr
    fixed = invoke("slide", str(KNET_RAW), "--mu", "0.002", "--detrend", "demean", "--json")
    assert fixed.stderr == ""
    row = json.loads(fixed.stdout)[0]
    assert row["qa_flags"] == []
    # the same slide as the Python API on the demeaned record
    tr = fs.process(fs.read_record(KNET_RAW)[0], demean=True)
    assert row["peak_slide"] == fs.slide(tr, mu_k=0.002).peak_slide[0]
    spec = invoke("spectrum", str(KNET_RAW), "--periods", "0.02,1", "--json", "--detrend", "demean")
    qa = json.loads(spec.stdout)["qa"]
    assert qa["flags"] == ["samples_per_period"] and "samples_per_period" in spec.stderr
    filtered = invoke(
        "spectrum",
        str(KNET_RAW),
        "--periods",
        "0.1,1",
        "--json",
        "--detrend",
        "linear",
        "--taper",
        "0.05",
        "--highpass",
        "0.1",
        "--lowpass",
        "20",
    )
    assert filtered.exit_code == 0 and json.loads(filtered.stdout)["qa"]["flags"] == []


def test_processing_option_mistakes_name_the_option():
    out = invoke("slide", str(KNET_RAW), "--mu", "0.1", "--lowpass", "80")
    assert out.exit_code == 2 and "--lowpass" in out.output and "Nyquist" in out.output
    out = invoke("inspect", str(KNET_RAW), "--detrend", "quadratic")
    assert out.exit_code == 2 and "--detrend" in out.output
    out = invoke("spectrum", str(KNET_RAW), "--taper", "0.9")
    assert out.exit_code == 2 and "--taper" in out.output
