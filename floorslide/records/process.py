"""Processing a record: only the steps asked for, in a fixed order, each one recorded.

:func:`process` is the one processing function of floorslide; the scene's ``[processing]``
table is passed to it as keywords. Steps and their order of application (the order of the
keywords does not matter):

====  ==================  ==========================================================================
 #    keyword             what it does
====  ==================  ==========================================================================
 1    ``demean``          ``True``: remove the mean (ObsPy ``detrend("demean")``)
 2    ``detrend``         ``"constant"``, ``"linear"`` or ``"polynomial"`` (with
                          ``detrend_order``, an int ≥ 1; ``detrend=<int>`` is shorthand), ObsPy
                          ``Trace.detrend``
 3    ``taper``           cosine (Tukey) taper: fraction of the record tapered at *each* end,
                          0 < taper ≤ 0.5 (ObsPy ``Trace.taper(max_percentage=taper,
                          type="cosine")``)
 4    ``highpass``,       Butterworth filters, corner(s) in Hz: ``highpass=f``, ``lowpass=f``
      ``lowpass``,        (both may be given), or ``bandpass=(f1, f2)``; ``filter_order`` (corners,
      ``bandpass``        default 4) and ``zerophase`` (default True: acausal, forward and
                          backward, so the effective order doubles) — ObsPy ``Trace.filter``
 5    ``baseline``        Boore-style baseline correction: fit the displacement with
                          ``c₂t² + … + c_Kt^K`` (no constant or linear term, so the initial
                          displacement and velocity stay 0) by least squares and subtract its
                          second derivative from the acceleration. ``True`` means degree K = 6
                          (as in the NGA-West2 processing of Ancheta et al. 2014 and gmprocess);
                          an int K ≥ 2 gives degrees 2..K.
 6    ``resample``        new time step in s, by ObsPy ``Trace.resample`` (FFT, ideal band limit;
                          ``resample_window`` is passed on as its ``window``, default None — ObsPy's
                          default Hann window would damp the whole upper band, e.g. by 50 % at half
                          the Nyquist frequency, which an engineering record cannot afford)
 7    ``scale_pga``,      scale to a target PGA in g (``scale_pga``) or by a factor
      ``scale``           (``scale``) — not both
====  ==================  ==========================================================================

The order is that of strong-motion processing (gmprocess, NGA-West2): the mean and trend go
first so that the taper and filters start from a record near zero; the taper precedes the
filters to limit their end transients; the baseline fit corrects what the high-pass leaves;
resampling works on the corrected, band-limited record, and scaling comes last so that the
target PGA is that of the final record.

Every step leaves a line in ``trace.stats.processing`` — ObsPy's own methods add theirs
(``ObsPy 1.x: filter(options=...)``), floorslide's steps add ``floorslide x.y: baseline(...)``
and ``floorslide x.y: scale(...)`` with the numbers used. Nothing is applied unless asked; an
unknown keyword or an impossible value raises :class:`~floorslide.errors.ModelError` naming it.

References
----------
Boore, D. M. (2001). Effect of baseline corrections on displacements and response spectra for
several recordings of the 1999 Chi-Chi, Taiwan, earthquake. *Bulletin of the Seismological
Society of America* 91(5), 1199–1211.

Ancheta, T. D., et al. (2014). NGA-West2 database. *Earthquake Spectra* 30(3), 989–1005
(polynomial baseline fit of the displacement, constant and linear terms set to zero).

Boore, D. M., Bommer, J. J. (2005). Processing of strong-motion accelerograms: needs, options
and consequences. *Soil Dynamics and Earthquake Engineering* 25, 93–115.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from obspy import Trace

from floorslide.constants import G
from floorslide.errors import ModelError, UnitsError
from floorslide.records.measures import velocity_displacement
from floorslide.records.read import PROCESSING_PREFIX
from floorslide.records.units import SI_UNITS, canonical_units
from floorslide.text_numbers import parse_number

STEPS = (
    "demean",
    "detrend",
    "detrend_order",
    "taper",
    "highpass",
    "lowpass",
    "bandpass",
    "filter_order",
    "zerophase",
    "baseline",
    "resample",
    "resample_window",
    "scale_pga",
    "scale",
)
"""Keywords :func:`process` accepts, in their order of application."""

_DETRENDS = ("constant", "linear", "polynomial")
_BASELINE_DEFAULT_DEGREE = 6


def _fail(key: str, problem: str) -> ModelError:
    return ModelError(f"processing {key}: {problem}")


def _positive(key: str, value: Any) -> float:
    if isinstance(value, bool):
        raise _fail(key, f"{value!r} is not a number")
    try:
        number = parse_number(value) if isinstance(value, str) else float(value)
    except (TypeError, ValueError):
        raise _fail(key, f"{value!r} is not a number") from None
    if not np.isfinite(number) or number <= 0:
        raise _fail(key, f"{value!r} must be > 0")
    return number


def _integer(key: str, value: Any, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise _fail(key, f"{value!r} must be an integer ≥ {minimum}")
    if value < minimum:
        raise _fail(key, f"{value!r} must be an integer ≥ {minimum}")
    return int(value)


def _corner(key: str, value: Any, nyquist: float) -> float:
    freq = _positive(key, value)
    if freq >= nyquist:
        raise _fail(
            key, f"{freq:g} Hz is at or above the Nyquist frequency {nyquist:g} Hz of this record"
        )
    return freq


def _note(trace: Trace, text: str) -> None:
    trace.stats.setdefault("processing", []).append(f"{PROCESSING_PREFIX}: {text}")


def baseline_correct(
    acc: np.ndarray, dt: float, degree: int = _BASELINE_DEFAULT_DEGREE
) -> tuple[np.ndarray, np.ndarray]:
    """Remove a polynomial baseline fitted to the displacement (Boore 2001; Ancheta et al. 2014).

    Parameters
    ----------
    acc
        Acceleration samples (m/s²).
    dt
        Time step (s).
    degree
        Highest degree K of the polynomial ``u_b(t) = Σ_{j=2}^{K} c_j t^j`` fitted to the
        displacement.

    Returns
    -------
    corrected : ndarray
        ``acc − u_b''(t)`` at the samples.
    coefficients : ndarray
        ``c_2 … c_K`` in SI (m/s^j).

    Notes
    -----
    The displacement is the exact double integral of the piecewise-linear record
    (:func:`~floorslide.records.measures.velocity_displacement`). The fit is done in the
    normalised time ``τ = t/T`` for conditioning. Without constant and linear terms the
    correction keeps the record starting at rest.
    """
    n = acc.size
    if n < degree:
        raise _fail("baseline", f"degree {degree} needs at least {degree} samples, got {n}")
    _, disp = velocity_displacement(acc, dt)
    duration = (n - 1) * dt
    tau = np.arange(n) / (n - 1)
    powers = np.arange(2, degree + 1)
    design = tau[:, None] ** powers[None, :]
    coef_tau, *_ = np.linalg.lstsq(design, disp, rcond=None)
    coefficients = coef_tau / duration**powers
    second = (powers * (powers - 1) * coef_tau)[None, :] * tau[:, None] ** (powers - 2)[None, :]
    return acc - second.sum(axis=1) / duration**2, coefficients


def process(trace: Trace, **steps: Any) -> Trace:
    """A processed copy of a record: only the steps asked for, in the documented order.

    Parameters
    ----------
    trace
        The record (ObsPy Trace, data in m/s²; a trace whose ``stats.units`` says otherwise
        is refused). It is not modified.
    **steps
        Any of ``demean, detrend, detrend_order, taper, highpass, lowpass, bandpass,
        filter_order, zerophase, baseline, resample, resample_window, scale_pga, scale`` (see
        the module docstring for meanings, units and order). ``None`` or ``False`` skip a
        step, so a scene's table can be passed as it is.

    Returns
    -------
    obspy.Trace
        A new trace; ``stats.processing`` gains one line per step applied.

    Raises
    ------
    UnitsError
        If ``trace.stats.units`` is not m/s².
    ModelError
        For an unknown step (named), an invalid value, a corner frequency at or above the
        record's Nyquist frequency, or conflicting steps (``bandpass`` with ``highpass`` or
        ``lowpass``; ``scale`` with ``scale_pga``).

    Examples
    --------
    >>> tr = process(st[0], detrend="linear", taper=0.05, highpass=0.1, lowpass=25.0,
    ...              baseline=True, scale_pga=0.3)                 # doctest: +SKIP
    """
    unknown = [key for key in steps if key not in STEPS]
    if unknown:
        raise ModelError(f"unknown processing step {unknown[0]!r}; known steps: {', '.join(STEPS)}")
    get = {
        key: value
        for key, value in steps.items()
        if value is not None and (value is not False or key == "zerophase")
    }
    units = trace.stats.get("units")
    if units and canonical_units(units) != SI_UNITS:
        raise UnitsError(
            f"trace data are in {units}; processing works on m/s**2 (read_record converts)",
            where=trace.stats.get("record", {}).get("path") or trace.id,
        )
    out = trace.copy()
    out.data = np.asarray(out.data, dtype=np.float64)
    if out.stats.npts == 0:
        raise ModelError("processing: the trace has no samples")

    # 1. demean
    if get.get("demean", False):
        if get["demean"] is not True:
            raise _fail("demean", f"{get['demean']!r} must be true or false")
        out.detrend("demean")

    # 2. detrend
    kind = get.get("detrend", False)
    if kind is not False:
        order = get.get("detrend_order")
        if isinstance(kind, int) and not isinstance(kind, bool):
            kind, order = "polynomial", kind
        if kind not in _DETRENDS:
            raise _fail("detrend", f"{kind!r}; expected one of {', '.join(_DETRENDS)}")
        if kind == "polynomial":
            if order is None:
                raise _fail("detrend_order", "needed for detrend='polynomial'")
            out.detrend("polynomial", order=_integer("detrend_order", order, 1))
        else:
            out.detrend(kind)
    elif "detrend_order" in get:
        raise _fail("detrend_order", "given without detrend='polynomial'")

    # 3. taper
    if get.get("taper", False) is not False:
        fraction = _positive("taper", get["taper"])
        if fraction > 0.5:
            raise _fail("taper", f"{fraction:g} must be ≤ 0.5 (a fraction of the record per end)")
        out.taper(max_percentage=fraction, type="cosine")

    # 4. filters
    nyquist = 0.5 / out.stats.delta
    corners = _integer("filter_order", get.get("filter_order", 4), 1)
    zerophase = get.get("zerophase", True)
    if not isinstance(zerophase, bool):
        raise _fail("zerophase", f"{zerophase!r} must be true or false")
    if "bandpass" in get:
        if "highpass" in get or "lowpass" in get:
            raise _fail("bandpass", "give either bandpass or highpass/lowpass, not both")
        band = get["bandpass"]
        if not isinstance(band, Sequence) or isinstance(band, str) or len(band) != 2:
            raise _fail("bandpass", f"{band!r} must be a pair (low, high) in Hz")
        low, high = (_corner("bandpass", f, nyquist) for f in band)
        if low >= high:
            raise _fail("bandpass", f"low corner {low:g} Hz must be below high corner {high:g}")
        out.filter("bandpass", freqmin=low, freqmax=high, corners=corners, zerophase=zerophase)
    if "highpass" in get:
        freq = _corner("highpass", get["highpass"], nyquist)
        out.filter("highpass", freq=freq, corners=corners, zerophase=zerophase)
    if "lowpass" in get:
        freq = _corner("lowpass", get["lowpass"], nyquist)
        out.filter("lowpass", freq=freq, corners=corners, zerophase=zerophase)

    # 5. baseline
    baseline = get.get("baseline", False)
    if baseline is not False:
        degree = _BASELINE_DEFAULT_DEGREE if baseline is True else _integer("baseline", baseline, 2)
        out.data, coefficients = baseline_correct(out.data, out.stats.delta, degree)
        _note(
            out,
            f"baseline(degrees=2..{degree}, fitted_to='displacement', "
            f"coefficients={[float(f'{c:.6g}') for c in coefficients]})",
        )

    # 6. resample
    if "resample" in get:
        new_dt = _positive("resample", get["resample"])
        window = get.get("resample_window")
        out.resample(1.0 / new_dt, window=window, no_filter=True)

    # 7. scale
    if "scale_pga" in get and "scale" in get:
        raise _fail("scale", "give either scale or scale_pga, not both")
    if "scale_pga" in get:
        target = _positive("scale_pga", get["scale_pga"])
        peak = float(np.abs(out.data).max())
        if peak == 0:
            raise _fail("scale_pga", "the record is all zeros; it cannot be scaled to a PGA")
        factor = target * G / peak
        out.data = out.data * factor
        _note(out, f"scale(target_pga_g={target:g}, factor={factor!r})")
    elif "scale" in get:
        factor = get["scale"]
        if isinstance(factor, bool):
            raise _fail("scale", f"{factor!r} is not a number")
        try:
            factor = float(factor)
        except (TypeError, ValueError):
            raise _fail("scale", f"{factor!r} is not a number") from None
        if not np.isfinite(factor) or factor == 0:
            raise _fail("scale", f"{factor!r} must be a finite, non-zero factor")
        out.data = out.data * factor
        _note(out, f"scale(factor={factor!r})")
    return out
