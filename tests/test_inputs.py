"""Solvers given ObsPy Traces and Streams (docs/design.md §10, issue 12 item 1): dt from the trace,
units
converted with a note or refused in one line — never used raw."""

from __future__ import annotations

import ast
import warnings
from pathlib import Path

import numpy as np
import obspy
import pytest
from obspy import Stream, Trace

import floorslide as fs
from floorslide.errors import ModelError, RecordError, UnitsConversionWarning, UnitsError
from tests.conftest import ROOT, SLAMMER, G
from tests.records.conftest import ELC_FILE, FIXTURES

AT2 = FIXTURES / "ELC180_ngawest2.AT2"  # El Centro 1940 NS, in g (PEER NGA-West2)
V2 = FIXTURES / "ELC180.V2"  # the same, COSMOS V2 in gal
BUILDING = fs.ShearBuilding.from_period(stories=2, period=0.3, damping=0.05)


@pytest.fixture(scope="module")
def trace_g() -> Trace:
    """``obspy.read`` of an AT2 file: data in g, ``stats.units == "g"`` (floorslide's plugin)."""
    tr = obspy.read(str(AT2))[0]
    assert tr.stats.units == "g" and tr.stats.delta == 0.01
    return tr


def one_line(exc: pytest.ExceptionInfo) -> str:
    text = str(exc.value)
    assert "\n" not in text
    return text


# Each solver as f(record, dt) -> the numbers it returns, and its result's notes.
SOLVERS = {
    "slide": lambda r, dt: fs.slide(r, dt, mu_k=[0.05, 0.2]),
    "slide_floor": lambda r, dt: fs.slide(r, dt, mu_k=0.1, building=BUILDING, floor=2),
    "slide_oscillator": lambda r, dt: fs.slide_oscillator(r, dt, mu=0.1, frequency=6.0),
    "response_spectrum": lambda r, dt: fs.response_spectrum(r, dt, [0, 0.1, 0.5, 2.0], 0.05),
    "floor_spectrum": lambda r, dt: fs.response_spectrum(
        r, dt, [0.2, 1.0], building=BUILDING, floor=1
    ),
    "floor_motions": lambda r, dt: fs.floor_motions(BUILDING, r, dt, floors=[1, 2]),
    "peak_floor_acceleration": lambda r, dt: fs.peak_floor_acceleration(BUILDING, r, dt),
    "measures": lambda r, dt: fs.measures(r, dt),
}


def numbers(result) -> list[np.ndarray]:
    """The numeric content of a solver's result."""
    if isinstance(result, np.ndarray):
        return [result]
    if isinstance(result, dict):
        return [np.array([v for k, v in result.items() if k != "notes"], dtype=float)]
    fields = ("peak_slide", "residual_slide", "peak_abs_accel", "peak_deformation", "psa", "sa")
    out = [getattr(result, f) for f in fields if hasattr(result, f)]
    return out + ([result.peak] if hasattr(result, "peak") else [])


def notes(result) -> tuple[str, ...] | None:
    if isinstance(result, np.ndarray):
        return None  # floor_motions returns samples: the warning is its record
    return result["notes"] if isinstance(result, dict) else result.notes


@pytest.mark.parametrize("solver", list(SOLVERS))
@pytest.mark.parametrize("form", ["trace", "trace+dt", "stream"])
def test_a_trace_in_g_is_converted_and_noted(solver, form, trace_g):
    """The result for a Trace in g equals the result for the samples ×9.80665 in m/s² — bit for
    bit — whether dt is left out, given, or the trace comes in a one-trace Stream."""
    record = {"trace": trace_g, "trace+dt": trace_g, "stream": Stream([trace_g])}[form]
    dt = trace_g.stats.delta if form == "trace+dt" else None
    with pytest.warns(UnitsConversionWarning, match=r"from 'g' to 'm/s\*\*2' \(factor 9.80665\)"):
        got = SOLVERS[solver](record, dt)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ref = SOLVERS[solver](trace_g.data.astype(float) * G, 0.01)
    for a, b in zip(numbers(got), numbers(ref), strict=True):
        np.testing.assert_array_equal(a, b)
    if notes(got) is not None:
        assert len(notes(got)) == 1 and "'g'" in notes(got)[0] and "9.80665" in notes(got)[0]
        assert notes(ref) == ()


def test_slide_of_a_trace_in_g_is_not_zero(trace_g):
    """The issue's case: the slide of El Centro at mu = 0.1 read in g was 0 (g taken as m/s²)."""
    with pytest.warns(UnitsConversionWarning):
        res = fs.slide(trace_g, trace_g.stats.delta, mu_k=0.1)
    ref = fs.slide(np.loadtxt(SLAMMER / ELC_FILE) * G, 0.01, mu_k=0.1)  # SLAMMER's copy
    assert res.peak_slide[0] > 0.01
    assert res.peak_slide[0] == pytest.approx(ref.peak_slide[0], rel=1e-3)


def test_spectrum_of_a_trace_in_gal_equals_the_si_one():
    tr = obspy.read(str(V2))[0]
    assert tr.stats.units == "gal"
    with pytest.warns(UnitsConversionWarning, match="'gal'"):
        sp = fs.response_spectrum(tr, periods=[0.0, 0.3, 1.0])
    ref = fs.response_spectrum(tr.data * 0.01, tr.stats.delta, [0.0, 0.3, 1.0])
    np.testing.assert_array_equal(sp.psa, ref.psa)
    assert sp.psa[0, 0] == pytest.approx(0.312881 * G, rel=1e-4)  # PGA of El Centro NS
    assert sp.to_dict()["notes"] == list(sp.notes) and "'gal'" in sp.notes[0]


def test_a_trace_in_si_is_used_as_is_without_warning():
    tr = fs.read_record(SLAMMER / ELC_FILE)[0]
    assert tr.stats.units == "m/s**2"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = fs.slide(tr, mu_k=0.1)
        ref = fs.slide(np.loadtxt(SLAMMER / ELC_FILE) * G, 0.01, mu_k=0.1)
        m = fs.measures(Stream([tr]))
    np.testing.assert_array_equal(res.peak_slide, ref.peak_slide)
    assert res.notes == () and m["notes"] == ()
    other = tr.copy()
    other.stats.units = "m/s^2"  # any spelling of m/s²
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert fs.slide(other, mu_k=0.1).peak_slide[0] == ref.peak_slide[0]


def test_vertical_trace_is_converted_and_its_dt_checked(trace_g):
    ag = trace_g.data * G
    with pytest.warns(UnitsConversionWarning, match="vertical"):
        res = fs.slide(ag, 0.01, 0.1, vertical=trace_g)
    ref = fs.slide(ag, 0.01, 0.1, vertical=trace_g.data * G)
    np.testing.assert_array_equal(res.peak_slide, ref.peak_slide)
    assert any(n.startswith("vertical:") for n in res.notes)
    coarse = trace_g.copy()
    coarse.stats.delta = 0.02
    with pytest.raises(ModelError) as exc, pytest.warns(UnitsConversionWarning):
        fs.slide(ag, 0.01, 0.1, vertical=coarse)
    assert "0.02" in one_line(exc) and "0.01" in one_line(exc)


def test_trace_without_units_is_refused_with_how_to_give_them():
    """ObsPy's own readers (here K-NET, whose data are counts) set no stats.units: refused."""
    tr = obspy.read(str(FIXTURES / "ELC180.knet"))[0]
    assert not tr.stats.get("units")
    for call in (
        lambda: fs.slide(tr, mu_k=0.1),
        lambda: fs.response_spectrum(tr, periods=[1.0]),
        lambda: fs.peak_floor_acceleration(None, tr),
        lambda: fs.measures(tr),
    ):
        with pytest.raises(UnitsError) as exc:
            call()
        text = one_line(exc)
        assert "stats.units" in text and "read_record" in text and "counts" in text


def test_unknown_units_are_refused_naming_them(trace_g):
    tr = trace_g.copy()
    tr.stats.units = "counts"
    with pytest.raises(UnitsError) as exc:
        fs.slide(tr, mu_k=0.1)
    assert "'counts'" in one_line(exc)


def test_units_that_are_not_a_string_name_the_key(trace_g):
    """The message read 'the trace given as acc has units must be a string ...'."""
    tr = trace_g.copy()
    tr.stats.units = 3
    with pytest.raises(UnitsError) as exc:
        fs.slide(tr, mu_k=0.1)
    text = one_line(exc)
    assert "stats.units of the trace given as acc: units must be a string" in text
    assert " has units" not in text


def test_dt_contradicting_the_trace_is_refused(trace_g):
    with pytest.raises(RecordError) as exc:
        fs.slide(trace_g, 0.02, mu_k=0.1)
    assert "0.02" in one_line(exc) and "stats.delta" in one_line(exc)
    with pytest.raises(RecordError):
        fs.measures(trace_g, dt=0.005)


def test_stream_of_several_traces_is_refused_naming_them():
    st = Stream()
    for channel in ("HNE", "HNN", "HNZ"):
        tr = Trace(np.zeros(10), header={"delta": 0.01, "channel": channel})
        tr.stats.units = "m/s**2"
        st.append(tr)
    for call in (
        lambda: fs.slide(st, mu_k=0.1),
        lambda: fs.floor_motions(BUILDING, st),
        lambda: fs.measures(st),
    ):
        with pytest.raises(RecordError) as exc:
            call()
        assert "3 traces (HNE, HNN, HNZ)" in one_line(exc)
    with pytest.raises(RecordError, match="empty Stream"):
        fs.slide(Stream(), mu_k=0.1)


def test_stream_of_obspy_read_at2_names_its_components(trace_g):
    with pytest.raises(RecordError) as exc:
        fs.response_spectrum(Stream([trace_g, trace_g.copy()]), periods=[1.0])
    assert "2 traces (180, 180)" in one_line(exc)


def test_trace_with_gaps_is_refused(trace_g):
    tr = trace_g.copy()
    tr.data = np.ma.masked_array(tr.data, mask=np.arange(tr.stats.npts) == 5)
    with pytest.raises(RecordError, match="gaps"):
        fs.slide(tr, mu_k=0.1)


def test_arrays_still_need_dt_and_missing_arguments_are_named():
    with pytest.raises(ModelError) as exc:
        fs.slide(np.ones(10), mu_k=0.1)
    assert "dt" in one_line(exc)
    with pytest.raises(ModelError, match="mu_k"):
        fs.slide(np.ones(10), 0.01)
    with pytest.raises(ModelError, match="periods"):
        fs.response_spectrum(np.ones(10), 0.01)
    with pytest.raises(ModelError, match="frequency"):
        fs.slide_oscillator(np.ones(10), 0.01, mu=0.1)


CORE = ["building", "contents", "spectra", "inputs.py", "units.py"]


def test_numerical_core_does_not_import_obspy():
    """STYLE: the core (and the input layer it uses) duck-types Traces and never imports ObsPy."""
    package = ROOT / "floorslide"
    files = [p for name in CORE for p in ([package / name] if name.endswith(".py") else [])]
    files += [
        p for name in CORE if not name.endswith(".py") for p in (package / name).rglob("*.py")
    ]
    assert len(files) > 10
    for path in files:
        for node in ast.walk(ast.parse(Path(path).read_text(encoding="utf-8"))):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""]
            for name in names:
                assert not name.startswith(("obspy", "floorslide.records")), (path, name)
