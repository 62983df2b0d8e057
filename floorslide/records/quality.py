"""Quality checks of a record: what is wrong with it, with numbers — never altering it.

Every record floorslide reads for a study or a command is checked here (docs/design.md §1, step
2b). A check *measures*; it never changes the data. Each one that trips becomes a
:class:`Flag` carrying its numbers, the threshold it crossed and, where processing removes the
defect, the processing that does (``--detrend demean`` on the command line, ``demean = true``
in a scene's ``[processing]``). What the checks see is the record *as it will be used*: after
the processing that was asked for, so that a flag that the processing removes is gone.

The checks (thresholds in :data:`CHECKS`, each with where it comes from):

``offset`` — mean offset (a baseline shift: the sensor's or digitiser's zero is not the ground's)
    The exact mean of the piecewise-linear record over its whole duration ``T`` is ``v(T)/T``:
    zero for ground that ends at rest, so ``|mean| > 0.1 %`` of PGA means a residual velocity
    (``mean·T``) and a displacement drift (``mean·T²/2``) that are not ground motion. Where the
    record has a *pre-event window* — the samples before ``|a − median(a)|`` first reaches 2 %
    of its largest value, if they last at least 1 s and 20 samples — its mean is compared with
    PGA too (threshold 2 %: noise before the event is zero-mean; measured on the 63 processed
    records bundled or shared with the project the largest is 1.0 %). Removed by ``demean``
    (or ``detrend = "linear"``). Boore & Bommer (2005) §3; gmprocess removes the mean first
    (its ``detrend`` steps, ``demean``).
``trend`` — linear trend
    The least-squares line through the samples; its rise over the record ``|b|·T`` against
    PGA, threshold 0.5 % (largest of the processed records above: 0.14 %). Removed by
    ``detrend = "linear"``. gmprocess detrends linearly before anything else.
``clipping`` — flat runs at the extreme
    Runs of three or more consecutive equal samples within 1 % of the record's extreme of
    their sign (a saturated sensor or digitiser holds its full-scale value), flagged when they
    hold six samples or more — one run of three at a weak record's peak is quantisation (seen
    on a 1-gal CWB excerpt stored to 0.001 gal), not clipping. Not removed by any processing:
    the peaks are lost; treat PGA, the spectra and every slide as lower bounds or leave the
    record out. gmprocess's standard-deviation clipping test (``Std_Dev``: low variance of
    neighbouring samples at ≥ 85 % of the extremes, failed above 5 such points) is the anchor;
    exact equality is used here because floorslide reads the values as stored.
``truncated`` — the record ends during strong shaking
    The share of the Arias intensity (of the record with its mean removed, so that an offset
    does not pass for shaking) in the last 5 % of the duration, threshold 1 % (a record that
    decays into its coda holds far less: at most 0.15 % on the processed records above;
    uniform shaking would hold 5 %). Not removable: the part of the motion after the end is
    missing; results are lower bounds. Anchor: gmprocess's ``check_tail`` (velocity and
    displacement in the tail against the whole record), Trifunac & Brady (1975) for the Husid
    curve.
``samples_per_period`` — too few samples per shortest period asked for
    Spectra at periods ``T < 4·dt`` (the oscillator above half the Nyquist frequency): the
    record holds nothing there but its anti-alias and processing filters and the linear
    interpolation between samples, so such ordinates describe the recorder, not the ground
    (Boore & Goulet 2014). floorslide's spectra are exact for the piecewise-linear record at
    any period; this check is about the record. Checked only when periods are asked for.

Non-finite samples are refused when a record is read (:func:`floorslide.read_record`).

References
----------
Boore, D. M., Bommer, J. J. (2005). Processing of strong-motion accelerograms: needs, options
and consequences. *Soil Dynamics and Earthquake Engineering* 25, 93–115.

Boore, D. M., Goulet, C. A. (2014). The effect of sampling rate and anti-aliasing filters on
high-frequency response spectra. *Bulletin of Earthquake Engineering* 12, 203–216.

Hearne, M., Thompson, E. M., Schovanec, H., Rekoske, J., Aagaard, B. T., Worden, C. B. (2019).
USGS automated ground motion processing software (gmprocess), USGS software release,
doi:10.5066/P9ANQXN3 (``sanity_checks.check_tail``, ``clipping.std_dev``).

Trifunac, M. D., Brady, A. G. (1975). A study on the duration of strong earthquake ground
motion. *Bulletin of the Seismological Society of America* 65(3), 581–626.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from floorslide.records.measures import husid


@dataclass(frozen=True)
class Check:
    """One quality check: its code, what it finds, its threshold(s) and what removes it."""

    code: str
    title: str
    thresholds: dict[str, float]
    fix_cli: str = ""
    """The command-line processing that removes the defect ('' when none does)."""
    fix_scene: str = ""
    """The same as a scene's ``[processing]`` setting."""
    advice: str = ""
    """What to do when no processing removes it."""


CHECKS: dict[str, Check] = {
    c.code: c
    for c in (
        Check(
            "offset",
            "mean offset (baseline shift)",
            {"pre_event_mean_ratio": 0.02, "mean_ratio": 0.001},
            "--detrend demean",
            "demean = true",
        ),
        Check(
            "trend",
            "linear trend",
            {"trend_ratio": 0.005},
            "--detrend linear",
            'detrend = "linear"',
        ),
        Check(
            "clipping",
            "flat runs at the extreme (clipped)",
            {"min_run": 3, "min_samples": 6, "level": 0.99},
            advice="no processing restores clipped peaks: results are lower bounds; "
            "leave the record out or use another",
        ),
        Check(
            "truncated",
            "ends during strong shaking",
            {"tail_arias_ratio": 0.01, "tail": 0.05},
            advice="the motion after the end is missing: results are lower bounds; "
            "use the complete record",
        ),
        Check(
            "samples_per_period",
            "too few samples per shortest period asked for",
            {"min_samples": 4.0},
            advice="ask for periods ≥ 4·dt, or use a record sampled faster",
        ),
    )
}
"""The checks, in the order they are reported (module notes give their sources)."""

PRE_EVENT_LEVEL = 0.02
"""The pre-event window ends where ``|a − median(a)|`` first reaches this share of its maximum."""
PRE_EVENT_MIN_SECONDS = 1.0
PRE_EVENT_MIN_SAMPLES = 20


@dataclass(frozen=True)
class Flag:
    """A check that tripped: its code, one line with its numbers, and the remedy."""

    check: str
    message: str
    values: dict[str, float]
    fix: str = ""
    """Command-line processing that removes it ('' when none does)."""
    fix_scene: str = ""
    advice: str = ""

    def line(self) -> str:
        """One line: ``offset: … ; try --detrend demean``."""
        tail = f"; try {self.fix}" if self.fix else (f"; {self.advice}" if self.advice else "")
        return f"{self.check}: {self.message}{tail}"

    def to_dict(self) -> dict:
        return {
            "check": self.check,
            "message": self.message,
            "values": dict(self.values),
            "fix": self.fix,
            "fix_scene": self.fix_scene,
            "advice": self.advice,
        }


@dataclass(frozen=True)
class QualityReport:
    """The numbers of every check and the flags of those that tripped."""

    values: dict[str, dict[str, float]]
    flags: tuple[Flag, ...] = ()
    checked: tuple[str, ...] = field(default_factory=tuple)

    @property
    def ok(self) -> bool:
        """No check tripped."""
        return not self.flags

    @property
    def codes(self) -> tuple[str, ...]:
        """The codes of the checks that tripped, in report order."""
        return tuple(f.check for f in self.flags)

    def suggestions(self) -> list[str]:
        """The command-line processing that removes the flags, without repeats."""
        out: list[str] = []
        for f in self.flags:
            if f.fix and f.fix not in out:
                out.append(f.fix)
        return out

    def lines(self) -> list[str]:
        """One line per flag (see :meth:`Flag.line`)."""
        return [f.line() for f in self.flags]

    def to_dict(self) -> dict:
        """JSON-ready: ``flags`` (codes), ``details`` (one dict per flag), ``checks`` (every
        check's numbers, tripped or not), ``suggest`` (processing that removes them)."""
        return {
            "flags": list(self.codes),
            "details": [f.to_dict() for f in self.flags],
            "checks": {k: dict(v) for k, v in self.values.items()},
            "suggest": self.suggestions(),
        }


def _flag(code: str, message: str, values: dict[str, float]) -> Flag:
    c = CHECKS[code]
    return Flag(code, message, values, c.fix_cli, c.fix_scene, c.advice)


def pre_event_window(acc: np.ndarray, dt: float) -> int:
    """Number of leading samples before the event (0 when there is no such window).

    The window ends at the first sample where ``|a − median(a)|`` reaches
    :data:`PRE_EVENT_LEVEL` of its maximum (the median stands for the record's baseline, also
    when that is offset); it counts only if it lasts at least :data:`PRE_EVENT_MIN_SECONDS` and
    :data:`PRE_EVENT_MIN_SAMPLES` samples.
    """
    if acc.size < PRE_EVENT_MIN_SAMPLES:
        return 0
    dev = np.abs(acc - np.median(acc))
    top = dev.max()
    if not top > 0:
        return 0
    onset = int(np.argmax(dev >= PRE_EVENT_LEVEL * top))
    if onset < PRE_EVENT_MIN_SAMPLES or onset * dt < PRE_EVENT_MIN_SECONDS:
        return 0
    return onset


def _pct(x: float) -> str:
    return f"{100 * x:.3g} %"


def _offset(acc: np.ndarray, dt: float, pga: float, duration: float) -> tuple[dict, Flag | None]:
    c = CHECKS["offset"].thresholds
    # the exact mean of the piecewise-linear record: ∫a dt / T = v(T) / T
    mean = float(dt * (acc.sum() - 0.5 * (acc[0] + acc[-1])) / duration)
    n_pre = pre_event_window(acc, dt)
    pre_mean = float(acc[:n_pre].mean()) if n_pre else float("nan")
    values = {
        "mean": mean,
        "mean_ratio": abs(mean) / pga,
        "pre_event_seconds": n_pre * dt,
        "pre_event_mean": pre_mean,
        "pre_event_mean_ratio": abs(pre_mean) / pga if n_pre else float("nan"),
        "velocity_drift": mean * duration,
        "displacement_drift": 0.5 * mean * duration * duration,
    }
    pre_trips = bool(n_pre) and values["pre_event_mean_ratio"] > c["pre_event_mean_ratio"]
    whole_trips = values["mean_ratio"] > c["mean_ratio"]
    if not (pre_trips or whole_trips):
        return values, None
    parts = []
    if n_pre:
        parts.append(
            f"pre-event mean {pre_mean:.3g} m/s² = {_pct(values['pre_event_mean_ratio'])} of "
            f"PGA over the first {n_pre * dt:.3g} s (limit {_pct(c['pre_event_mean_ratio'])})"
        )
    parts.append(
        f"whole-record mean {mean:.3g} m/s² = {_pct(values['mean_ratio'])} of PGA (limit "
        f"{_pct(c['mean_ratio'])}): {values['velocity_drift']:.3g} m/s and "
        f"{values['displacement_drift']:.3g} m of drift by the end"
    )
    return values, _flag("offset", "; ".join(parts), values)


def _trend(acc: np.ndarray, dt: float, pga: float, duration: float) -> tuple[dict, Flag | None]:
    limit = CHECKS["trend"].thresholds["trend_ratio"]
    n = acc.size
    # least-squares slope of a against t (t centred: no cancellation)
    t = (np.arange(n, dtype=np.float64) - 0.5 * (n - 1)) * dt
    slope = float(np.dot(t, acc) / np.dot(t, t))
    rise = abs(slope) * duration
    values = {"slope": slope, "rise": rise, "trend_ratio": rise / pga}
    if values["trend_ratio"] <= limit:
        return values, None
    msg = (
        f"least-squares line rising {slope * duration:.3g} m/s² over the record = "
        f"{_pct(values['trend_ratio'])} of PGA (limit {_pct(limit)})"
    )
    return values, _flag("trend", msg, values)


def flat_runs(acc: np.ndarray, level: float, min_run: int) -> tuple[int, int, int]:
    """Runs of at least ``min_run`` consecutive equal samples at ``level`` × the extreme of
    their sign or beyond: ``(runs, samples in them, longest)``."""
    top, bottom = float(acc.max()), float(acc.min())
    near = np.zeros(acc.size, dtype=bool)
    if top > 0:
        near |= acc >= level * top
    if bottom < 0:
        near |= acc <= level * bottom
    same = near[1:] & near[:-1] & (acc[1:] == acc[:-1])
    if not same.any():
        return 0, 0, 1
    # runs of True in `same`: a run of k equal steps is k + 1 equal samples
    padded = np.concatenate(([False], same, [False]))
    edges = np.flatnonzero(padded[1:] != padded[:-1])
    lengths = edges[1::2] - edges[::2] + 1
    long = lengths[lengths >= min_run]
    return int(long.size), int(long.sum()), int(lengths.max())


def _clipping(acc: np.ndarray) -> tuple[dict, Flag | None]:
    c = CHECKS["clipping"].thresholds
    runs, samples, longest = flat_runs(acc, c["level"], int(c["min_run"]))
    values = {"flat_runs": runs, "flat_samples": samples, "longest_run": longest}
    if samples < c["min_samples"]:
        return values, None
    msg = (
        f"{runs} runs of ≥ {int(c['min_run'])} equal samples at the extremes ({samples} "
        f"samples, longest {longest}; max {acc.max():.4g}, min {acc.min():.4g} m/s²)"
    )
    return values, _flag("clipping", msg, values)


def _truncated(acc: np.ndarray, dt: float, duration: float) -> tuple[dict, Flag | None]:
    c = CHECKS["truncated"].thresholds
    centred = acc - float(dt * (acc.sum() - 0.5 * (acc[0] + acc[-1])) / duration)
    energy = husid(centred, dt)
    total = float(energy[-1])
    start = int(np.floor((1.0 - c["tail"]) * (acc.size - 1)))
    share = (total - float(energy[start])) / total if total > 0 else float("nan")
    tail_peak = float(np.abs(acc[start:]).max()) / float(np.abs(acc).max())
    values = {"tail_seconds": (acc.size - 1 - start) * dt, "tail_arias_ratio": share}
    values["tail_pga_ratio"] = tail_peak
    if not share > c["tail_arias_ratio"]:
        return values, None
    msg = (
        f"{_pct(share)} of the Arias intensity in the last {_pct(c['tail'])} of the record "
        f"({values['tail_seconds']:.3g} s; limit {_pct(c['tail_arias_ratio'])}); the "
        f"largest sample there is {_pct(tail_peak)} of PGA"
    )
    return values, _flag("truncated", msg, values)


def _samples(dt: float, periods: Iterable[float] | None) -> tuple[dict, Flag | None]:
    need = CHECKS["samples_per_period"].thresholds["min_samples"]
    values: dict[str, float] = {"dt": dt, "shortest_resolved_period": need * dt}
    positive = [float(T) for T in (() if periods is None else periods) if float(T) > 0]
    if not positive:
        return values, None
    shortest = min(positive)
    values["shortest_period"] = shortest
    values["samples_per_period"] = shortest / dt
    if shortest / dt >= need * (1 - 1e-9):
        return values, None
    below = sum(1 for T in positive if T / dt < need * (1 - 1e-9))
    msg = (
        f"{below} of the {len(positive)} periods asked for are below {need:g}·dt = "
        f"{need * dt:.3g} s (the shortest, {shortest:.3g} s, spans {shortest / dt:.3g} "
        "samples): there the record holds only its filters and the interpolation between samples"
    )
    return values, _flag("samples_per_period", msg, values)


def check_record(
    acc: np.ndarray | Sequence[float],
    dt: float,
    *,
    periods: Iterable[float] | None = None,
) -> QualityReport:
    """Run every quality check on a record (m/s²); nothing is changed.

    Parameters
    ----------
    acc
        Acceleration samples (m/s²), finite.
    dt
        Time step (s).
    periods
        Periods asked for (spectra, s); the ``samples_per_period`` check runs only when given
        (a period of 0, the peak acceleration, is ignored).

    Returns
    -------
    QualityReport
        ``values`` (every check's numbers), ``flags`` (the checks that tripped, with one line
        each and the processing that removes them), ``checked`` (the checks that ran: a record
        of zeros or of fewer than 3 samples cannot be judged by the ratio checks).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(0, 20, 0.01)
    >>> a = np.cos(2 * np.pi * t) * np.exp(-0.2 * t)
    >>> check_record(a, 0.01).ok
    True
    >>> check_record(a + 0.05, 0.01).codes
    ('offset',)
    """
    a = np.ascontiguousarray(acc, dtype=np.float64)
    dt = float(dt)
    values: dict[str, dict[str, float]] = {}
    flags: list[Flag] = []
    checked: list[str] = []
    pga = float(np.abs(a).max()) if a.size else 0.0
    duration = (a.size - 1) * dt
    if a.size >= 3 and pga > 0 and duration > 0:
        with np.errstate(over="ignore", invalid="ignore"):  # samples near the float limit
            results = (
                ("offset", _offset(a, dt, pga, duration)),
                ("trend", _trend(a, dt, pga, duration)),
                ("clipping", _clipping(a)),
                ("truncated", _truncated(a, dt, duration)),
            )
        for code, (vals, flag) in results:
            values[code] = vals
            checked.append(code)
            if flag is not None:
                flags.append(flag)
    vals, flag = _samples(dt, periods)
    values["samples_per_period"] = vals
    if periods is not None:
        checked.append("samples_per_period")
    if flag is not None:
        flags.append(flag)
    return QualityReport(values, tuple(flags), tuple(checked))
