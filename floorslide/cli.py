"""The ``floorslide`` command line: parses, calls, prints; no numerics here.

Exit codes (docs/design.md §3, §10): 0 success; 2 bad usage, an invalid scene, a missing,
corrupt or foreign result file (or one with a task that fails its integrity check), or an
output file that exists (``run`` without ``--resume`` or ``--overwrite``); 3 unreadable
record(s), the others still processed; 4 ``table`` or ``plot`` of an incomplete result file
without ``--allow-incomplete``; 1 unexpected error, results that could not be written (a full
disk) or a Dask scheduler without workers. A user mistake is reported as one line naming the
file or key at fault, never as a traceback.
"""

from __future__ import annotations

import math
import os
import signal
import sys
import warnings

import click

from floorslide.errors import FloorslideError

EXIT_OK = 0
EXIT_UNEXPECTED = 1
EXIT_USAGE = 2
EXIT_RECORD = 3
EXIT_INCOMPLETE = 4


def fail(error: FloorslideError) -> None:
    """Print a user error as one line on stderr and exit with its code."""
    click.echo(f"floorslide: error: {error}", err=True)
    sys.exit(error.exit_code)


def _kernels(*families: str, workers: int | None = None) -> None:
    """Compile the kernel families a command needs, once per installation, saying so on stderr
    (floorslide.firstrun); silent when they are compiled already."""
    from floorslide.firstrun import prepare

    prepare(families, workers=workers)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="floorslide")
def cli() -> None:
    """floorslide: how far the equipment on each floor of a building slides under recorded
    earthquakes, fixed-base versus base-isolated, and what the floors feel."""


INSPECT_COLUMNS = (
    ("format", "format", "{}"),
    ("dt", "dt(s)", "{:.4g}"),
    ("npts", "npts", "{:d}"),
    ("duration", "dur(s)", "{:.2f}"),
    ("pga", "pga(m/s2)", "{:.4g}"),
    ("pga_g", "pga(g)", "{:.4g}"),
    ("pgv", "pgv(m/s)", "{:.4g}"),
    ("pgd", "pgd(m)", "{:.4g}"),
    ("arias", "arias(m/s)", "{:.4g}"),
    ("cav", "cav(m/s)", "{:.4g}"),
    ("d5_75", "d5-75(s)", "{:.2f}"),
    ("d5_95", "d5-95(s)", "{:.2f}"),
)
"""Columns of the ``inspect`` table: JSON key, heading, format."""

PROGRESS_MIN_RECORDS = 20
"""Show a progress bar (stderr, terminals only) from this many records on."""


def _cell(value: object, fmt: str) -> str:
    if value is None or (isinstance(value, float) and value != value):
        return "-"
    return fmt.format(value)


def _print_table(rows: list[dict]) -> None:
    headings = ["record"] + [heading for _, heading, _ in INSPECT_COLUMNS]
    table = [
        [row["record"] + (f" [{row['component']}]" if row.get("multi") else "")]
        + [_cell(row[key], fmt) for key, _, fmt in INSPECT_COLUMNS]
        for row in rows
    ]
    widths = [max(len(h), *(len(r[i]) for r in table)) for i, h in enumerate(headings)]
    line = "  ".join(
        h.ljust(widths[0]) if i == 0 else h.rjust(widths[i]) for i, h in enumerate(headings)
    )
    click.echo(line)
    for r in table:
        click.echo(
            "  ".join(c.ljust(widths[0]) if i == 0 else c.rjust(widths[i]) for i, c in enumerate(r))
        )


def _print_notes(rows: list[dict]) -> None:
    """The notes of the inspected records (a measure that is NaN and why ...), below the
    table."""
    for row in rows:
        label = row["record"] + (f" [{row['component']}]" if row.get("multi") else "")
        for note in row["notes"]:
            click.echo(f"note: {label}: {note}")


def _processing_notes(trace) -> list[str]:
    """The processing steps applied to a trace (``stats.processing``), unit conversions left
    out."""
    return [p for p in trace.stats.get("processing", []) if "convert_units" not in p]


def _print_quality(rows: list[dict], processed: bool) -> None:
    """The quality flags of the inspected records, below the table, and the processing that
    removes them."""
    flagged = [row for row in rows if row["qa"]["flags"]]
    if not flagged:
        what = "processed " if processed else ""
        click.echo(f"quality: no flags on the {len(rows)} {what}records")
        return
    click.echo(f"quality: {len(flagged)} of {len(rows)} records flagged")
    fixes: list[str] = []
    for row in flagged:
        label = row["record"] + (f" [{row['component']}]" if row.get("multi") else "")
        for detail in row["qa"]["details"]:
            tail = f"; try {detail['fix']}" if detail["fix"] else f"; {detail['advice']}"
            click.echo(f"  {label}: {detail['check']}: {detail['message']}{tail}")
        fixes += [f for f in row["qa"]["suggest"] if f not in fixes]
    if fixes:
        click.echo(f"suggested processing: {' '.join(fixes)} (nothing is applied unless asked)")


def _finite(value):
    """`value` with every float that is NaN or infinite, at any depth, replaced by None."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(v) for v in value]
    return value


def _strict_json(data) -> str:
    """`data` as strict JSON (docs/design.md §3): ``null`` for undefined numbers, never
    ``NaN`` or ``Infinity``, which JSON does not have."""
    import json

    return json.dumps(_finite(data), indent=1, allow_nan=False)


def _check_format(ctx, param, value: str | None) -> str | None:
    """``--format``: a format floorslide or ObsPy knows, else a usage error (exit 2)."""
    if value is None:
        return None
    from floorslide.errors import RecordError
    from floorslide.records.read import resolve_format

    try:
        resolve_format(value)
    except RecordError as exc:
        raise click.BadParameter(exc.message, ctx=ctx, param=param) from None
    return value


def _check_units(ctx, param, value: str | None) -> str | None:
    """``--units``: an acceleration unit floorslide knows, else a usage error (exit 2)."""
    if value is None:
        return None
    from floorslide.errors import UnitsError
    from floorslide.units import canonical_units

    try:
        canonical_units(value)
    except UnitsError as exc:
        raise click.BadParameter(exc.message, ctx=ctx, param=param) from None
    return value


def _number(text: str) -> float:
    """``float(text)``, refusing underscores (Python reads ``0_01`` as 1.0, a typo for 0.01;
    :func:`floorslide.text_numbers.parse_number`)."""
    from floorslide.text_numbers import parse_number

    return parse_number(text)


def _whole(text: str) -> int:
    """A whole number (``100``, ``100.``, ``1e2``), refusing underscores (Python reads ``1_00``
    as 100) and fractions (:func:`floorslide.text_numbers.parse_count`)."""
    from floorslide.text_numbers import parse_count

    return parse_count(text)


class _Number(click.ParamType):
    """A number option: as click's ``float``, but ``0_01`` is refused, not read as 1.0."""

    name = "number"

    def convert(self, value, param, ctx) -> float:
        if isinstance(value, float):
            return value
        try:
            return _number(str(value))
        except ValueError:
            self.fail(f"expected a number, got {value!r}", param, ctx)


NUMBER = _Number()


def _check_dt(ctx, param, value: float | None) -> float | None:
    """``--dt``: a finite time step > 0 s, else a usage error (exit 2)."""
    if value is not None and not (0 < value < float("inf")):
        raise click.BadParameter(f"the time step must be > 0 s, got {value:g}", ctx, param)
    return value


FORMAT_OPTION = click.option(
    "--format",
    "fmt",
    metavar="F",
    callback=_check_format,
    help="Record format: AT2, COSMOSV2, text, an ObsPy format (MSEED, SAC, KNET ...) or "
    "gmprocess (DMG V2, GeoNet, CWB, UNAM, SMC, ESM ...: needs floorslide[gmprocess]); "
    "default: detected.",
)
UNITS_OPTION = click.option(
    "--units",
    metavar="U",
    callback=_check_units,
    help="Units of the file's values: g|gal|m/s**2|mm/s**2 (needed when the file does not say).",
)
DT_OPTION = click.option(
    "--dt",
    type=NUMBER,
    metavar="SECONDS",
    callback=_check_dt,
    help="Time step of single-column text.",
)


DETREND_CHOICES = ("demean", "constant", "linear")


def _check_detrend(ctx, param, value: str | None) -> str | None:
    """``--detrend``: demean, constant, linear or a polynomial order ≥ 1."""
    if value is None:
        return None
    key = value.strip().lower()
    if key in DETREND_CHOICES or (key.isdigit() and int(key) >= 1):
        return key
    raise click.BadParameter(
        f"expected demean, constant, linear or a polynomial order (an integer ≥ 1), got {value!r}",
        ctx,
        param,
    )


def processing_options(func):
    """``--detrend/--taper/--highpass/--lowpass``: the scene's ``[processing]`` steps of the
    same names for one record (docs/design.md §3), applied in the order of
    :func:`floorslide.process`."""
    for option in reversed(
        [
            click.option(
                "--detrend",
                metavar="demean|linear|N",
                callback=_check_detrend,
                help="Remove the mean (demean, or constant), a line (linear) or a polynomial "
                "of order N before anything else.",
            ),
            click.option(
                "--taper",
                type=NUMBER,
                metavar="FRACTION",
                help="Cosine taper of this fraction of the record at each end (0 < f ≤ 0.5).",
            ),
            click.option(
                "--highpass",
                type=NUMBER,
                metavar="HZ",
                help="Butterworth high-pass corner (Hz; order 4, zero-phase).",
            ),
            click.option(
                "--lowpass",
                type=NUMBER,
                metavar="HZ",
                help="Butterworth low-pass corner (Hz; order 4, zero-phase).",
            ),
        ]
    ):
        func = option(func)
    return func


def _processing(
    detrend: str | None, taper: float | None, highpass: float | None, lowpass: float | None
) -> dict:
    """The keywords of :func:`floorslide.process` for the processing options given."""
    steps: dict = {}
    if detrend == "demean":
        steps["demean"] = True
    elif detrend in ("constant", "linear"):
        steps["detrend"] = detrend
    elif detrend is not None:
        steps["detrend"] = "polynomial"
        steps["detrend_order"] = int(detrend)
    for key, value in (("taper", taper), ("highpass", highpass), ("lowpass", lowpass)):
        if value is not None:
            steps[key] = value
    return steps


def _apply_processing(trace, steps: dict):
    """`trace` processed as asked (unchanged when nothing is asked); a value the record cannot
    take (a corner above its Nyquist frequency ...) is a usage error naming the option."""
    if not steps:
        return trace
    from floorslide.errors import ModelError
    from floorslide.records.process import process

    try:
        return process(trace, **steps)
    except ModelError as exc:
        text = str(exc)
        key = text.split(":", 1)[0].removeprefix("processing ").strip()
        hint = "--detrend" if key.startswith("detrend") else f"--{key}"
        raise click.BadParameter(text.split(":", 1)[-1].strip(), param_hint=hint) from None


def _warn_quality(label: str, report) -> None:
    """The flags of a record's quality checks, one warning line each on stderr."""
    for line in report.lines():
        click.echo(f"floorslide: warning: {label}: {line}", err=True)


@cli.command()
@click.argument("records", nargs=-1, required=True)
@click.option("--json", "as_json", is_flag=True, help="Print a JSON list (SI values) on stdout.")
@FORMAT_OPTION
@UNITS_OPTION
@DT_OPTION
@click.option("--component", metavar="C", help="Component to keep from multi-trace files.")
@processing_options
def inspect(
    records: tuple[str, ...],
    as_json: bool,
    fmt: str | None,
    units: str | None,
    dt: float | None,
    component: str | None,
    detrend: str | None,
    taper: float | None,
    highpass: float | None,
    lowpass: float | None,
) -> None:
    """Intensity measures of each RECORD: format, dt, npts, duration, PGA (m/s² and g), PGV,
    PGD, Arias intensity, CAV, significant durations D5-75 and D5-95.

    RECORD may be a record file (PEER .AT2, COSMOS V2, plain text, MiniSEED, SAC, K-NET and
    every ObsPy format), a catalog CSV (columns file, dt, units; or file_h1, file_h2 ...: each
    component is shown), or a directory, searched recursively for both (files a catalog lists
    are read once, through it; documentation such as *.md is skipped). --format/--units/--dt/
    --component apply to record files, not to catalog rows, which carry their own. Measures
    are exact for the piecewise-linear record; nothing is filtered unless --detrend, --taper,
    --highpass or --lowpass ask for it (then the measures are those of the processed record).
    A measure that is undefined (the durations of a record of zeros, one beyond floating
    point) is '-' in the table and null in JSON, and a note says why.

    Every record is checked (floorslide.records.quality): mean offset, linear trend, clipping,
    a record that ends during strong shaking. Each check that trips is listed below the table
    with its numbers and the processing that removes it (e.g. --detrend demean); in JSON each
    record has "qa" with the flags, every check's numbers and the suggestions. Flags do not
    change the exit code.

    Exit codes: 0 every record read; 3 a record could not be read (or a file named is not a
    record, or nothing was found to read) — reported on stderr in one line each, the others
    still shown; 2 bad usage (e.g. an unknown --units or --format).
    """
    from tqdm import tqdm

    from floorslide.errors import RecordError
    from floorslide.records.discover import discover
    from floorslide.records.measures import MEASURE_KEYS, measures
    from floorslide.records.quality import check_record
    from floorslide.records.read import format_name

    steps = _processing(detrend, taper, highpass, lowpass)
    sources, problems = discover(records)
    failed = bool(problems)
    for problem in problems:
        click.echo(f"floorslide: error: {problem}", err=True)
    rows: list[dict] = []
    show = sys.stderr.isatty() and len(sources) >= PROGRESS_MIN_RECORDS
    with tqdm(
        total=len(sources), file=sys.stderr, disable=not show, leave=False, unit="record"
    ) as bar:
        for source in sources:
            try:
                stream = source.read(format=fmt, units=units, dt=dt, component=component)
                stream = [_apply_processing(trace, steps) for trace in stream]
                found = [
                    (trace, measures(trace), check_record(trace.data, trace.stats.delta))
                    for trace in stream
                ]
            except RecordError as exc:
                failed = True
                bar.write(f"floorslide: error: {exc}", file=sys.stderr)
                bar.update()
                continue
            for trace, values, quality in found:
                record = trace.stats.record
                row = {
                    "record": source.label,
                    "format": format_name(record.format),
                    "component": record.component,
                    "station": record.station,
                    "event": record.event,
                    **{key: values[key] for key in MEASURE_KEYS},
                    "notes": list(values["notes"]),
                    "processing": _processing_notes(trace),
                    "qa": quality.to_dict(),
                    "multi": len(stream) > 1,
                }
                rows.append(row)
            bar.update()
    if as_json:
        out = [{k: v for k, v in row.items() if k != "multi"} for row in rows]
        click.echo(_strict_json(out))
    elif rows:
        _print_table(rows)
        _print_notes(rows)
        _print_quality(rows, bool(steps))
    if failed:
        sys.exit(EXIT_RECORD)


def _floats(text: str, name: str) -> list[float]:
    """Comma-separated numbers of an option (at most ``MAX_LIST``; no empty item: ``0.1,,0.2``
    is a typo, not two values), or a one-line usage error naming it."""
    from floorslide.constants import MAX_LIST

    items = text.split(",")
    if not text.strip():
        raise click.BadParameter("expected at least one number", param_hint=name)
    if len(items) > MAX_LIST:
        raise click.BadParameter(f"at most {MAX_LIST} values, got {len(items)}", param_hint=name)
    empty = next((k for k, v in enumerate(items) if not v.strip()), None)
    if empty is not None:
        raise click.BadParameter(
            f"item {empty + 1} of {text[:60]!r} is empty; expected numbers separated by commas",
            param_hint=name,
        )
    try:
        values = [_number(v) for v in items]
    except ValueError:
        raise click.BadParameter(
            f"expected numbers separated by commas, got {text[:60]!r}", param_hint=name
        ) from None
    if name in ("--mu", "--mu-s"):
        from floorslide.scene.schema import friction_warning

        for message in dict.fromkeys(filter(None, map(friction_warning, values))):
            click.echo(f"floorslide: warning: {name}: {message}", err=True)
    return values


def _read_one(
    record: str, fmt: str | None, units: str | None, dt: float | None, component: str | None
):
    """The single trace of RECORD (one component), in m/s²; nothing else is applied."""
    from floorslide.errors import RecordError
    from floorslide.records.read import read_record

    stream = read_record(record, format=fmt, units=units, dt=dt, component=component)
    if len(stream) != 1:
        names = ", ".join(tr.stats.channel or tr.id for tr in stream)
        raise RecordError(
            f"{len(stream)} components ({names}); choose one with --component", record
        )
    return stream[0]


def record_options(func):
    """The options every single-record command takes (docs/design.md §3)."""
    for option in reversed(
        [
            FORMAT_OPTION,
            UNITS_OPTION,
            DT_OPTION,
            click.option("--component", metavar="C", help="Component of a multi-trace file."),
        ]
    ):
        func = option(func)
    return func


BUILDING_HELP = (
    "Put the object on a floor of this building, KIND:key=value,... e.g. "
    "'fixed:period=0.4,stories=3,damping=0.05', "
    "'isolated:period=2.5,damping=0.1,super_period=0.4,stories=3' or "
    "'fixed:masses=2e5/2e5/1.5e5,stiffnesses=3e8/3e8/2e8'; on nonlinear isolation "
    "'fps:period=3,mu=0.06,super_period=0.4,stories=3' (friction pendulums) or "
    "'lrb:q_ratio=0.06,period=2.5,yield_disp=0.02,super_period=0.4,stories=3' (lead-rubber) "
    "(keys as in a scene's [[buildings]]; lists separated by '/'). Default: the ground."
)


def building_options(func):
    """``--building SPEC`` and ``--floor N|roof`` of the single-record solver commands."""
    func = click.option(
        "--floor",
        metavar="N|roof",
        help="Floor of --building: 0 (ground, or the base mat of an isolated building) to N, "
        "or roof (default).",
    )(func)
    return click.option("--building", "building_spec", metavar="SPEC", help=BUILDING_HELP)(func)


def _building(spec: str | None, floor: str | None):
    """The building and floor of ``--building``/``--floor`` (None, 0 for the ground), and the
    header line that says which; usage errors name the option and the key at fault."""
    from floorslide.building.spec import describe_building, parse_building
    from floorslide.errors import ModelError

    if spec is None:
        if floor is not None:
            raise click.BadParameter(
                "needs --building (without it: the ground)", param_hint="--floor"
            )
        return None, 0, "on the ground"
    try:
        building = parse_building(spec)
    except ModelError as exc:
        raise click.BadParameter(str(exc), param_hint="--building") from None
    top = building.stories
    if floor is None or floor.strip().lower() == "roof":
        number = top
    else:
        try:
            number = _whole(floor)
        except ValueError:
            raise click.BadParameter(
                f"expected a floor number 0..{top} or roof, got {floor!r}", param_hint="--floor"
            ) from None
        if not 0 <= number <= top:
            raise click.BadParameter(
                f"floor {number} does not exist; floors are 0..{top} (or roof)",
                param_hint="--floor",
            )
    if number == top:
        name = f"floor {number} (roof)"
    elif number == 0:
        name = "floor 0 (base mat)" if _kind(building) == "isolated" else "floor 0 (ground)"
    else:
        name = f"floor {number}"
    return building, number, f"on {name} of: {describe_building(building)}"


def _family_of(building) -> str:
    """The kernel family a single-record command on `building` needs (the first-run notice):
    ``nonlinear`` on nonlinear isolation, else ``floors``."""
    return "nonlinear" if getattr(building, "segmented", False) else "floors"


def _record_on_floor(record, reading, processing, scale_pga, building, floor_no):
    """The single-object commands' input: RECORD read (``reading`` = format, units, dt,
    component) and processed, its quality flags warned about on stderr, scaled to
    ``--scale-pga``, and the exact motion of the floor (the ground without a building),
    integrated once. Returns ``(trace, quality report, FloorMotion)``."""
    from floorslide.building.exact_motion import floor_motion
    from floorslide.records.process import process
    from floorslide.records.quality import check_record

    tr = _apply_processing(_read_one(record, *reading), processing)
    quality = check_record(tr.data, tr.stats.delta)
    _warn_quality(record, quality)
    if scale_pga is not None:
        if not scale_pga > 0:
            raise click.BadParameter("must be > 0", param_hint="--scale-pga")
        tr = process(tr, scale_pga=scale_pga)
    fm = floor_motion(building, tr.data, floor_no if building is not None else None, tr.stats.delta)
    return tr, quality, fm


def _pair_traces(record, record2, reading):
    """The two horizontal Traces (and a label) of ``slide RECORD RECORD2`` or ``--pair``."""
    from floorslide.records.pairs import _split, knet_siblings
    from floorslide.records.read import read_record

    fmt, units, dt, component = reading
    if component is not None:
        raise click.BadParameter("a pair takes both horizontal components", "--component")
    if record2 is not None:
        return _read_one(record, fmt, units, dt, None), _read_one(record2, fmt, units, dt, None)
    stream = read_record(record, format=fmt, units=units, dt=dt)
    if len(stream) == 1:
        sibs = knet_siblings(record)
        if sibs is None:
            from floorslide.errors import RecordError

            raise RecordError(
                "one component in the file; --pair needs a multi-channel file or a K-NET "
                "recording (give the second component as RECORD2)",
                record,
            )
        return _read_one(str(sibs[0]), fmt, units, dt, None), _read_one(
            str(sibs[1]), fmt, units, dt, None
        )
    (t1, t2), _ = _split(stream, record)
    return t1, t2


def _slide_pair(record, record2, mus, mus_s, scale_pga, building, building_h2, floor_no, where,
                reading, processing, as_json):  # fmt: skip
    """``floorslide slide`` with two horizontal components: sliding in the plane."""
    import numpy as np

    from floorslide.building.spec import describe_building
    from floorslide.constants import G
    from floorslide.contents.plane import slide_plane
    from floorslide.pair import make_pair

    pair, model, where, codes = _pair_input(record, record2, reading, processing, building,
                                            building_h2, where)  # fmt: skip
    names, labels = pair.names, [record, record2 or f"{record} (2nd)"]
    if scale_pga is not None:
        if not scale_pga > 0:
            raise click.BadParameter("must be > 0", param_hint="--scale-pga")
        top = max(np.abs(pair.h1).max(), np.abs(pair.h2).max())
        if top == 0:
            raise click.BadParameter("both components are zero: nothing to scale",
                                     param_hint="--scale-pga")  # fmt: skip
        f = scale_pga * G / top
        pair = make_pair(f * pair.h1, f * pair.h2, pair.dt, names=pair.names, label=pair.label)
    res = slide_plane(pair, None, mus, mus_s, building=model,
                      floor=floor_no if building is not None else None)  # fmt: skip
    rows = []
    for i in range(res.mu_k.size):
        rows.append(
            {
                "mu_k": float(res.mu_k[i]),
                "mu_s": float(res.mu_s[i]),
                "peak_slide": float(res.peak_slide[i]),
                "peak_angle": float(res.peak_angle[i]),
                "time_of_peak": float(res.time_of_peak[i]),
                "residual": [float(v) for v in res.residual[i]],
                "slide_fraction": float(res.slide_fraction[i]),
                "slip_phases": int(res.slip_phases[i]),
                "peak_slide_1d": [float(v) for v in res.peak_slide_1d[i]],
                "ratio_2d_1d": float(res.ratio_2d_1d[i]),
            }
        )
    if as_json:
        for row in rows:
            row["records"] = labels if record2 is not None else [record]
            row["components"] = list(names)
            row["building"] = None if building is None else describe_building(building)
            row["floor"] = floor_no
            row["qa_flags"] = codes
            row["notes"] = list(res.notes)
        click.echo(_strict_json(rows))
        return
    click.echo(
        f"{pair.label}: dt = {pair.dt:g} s, {pair.npts} samples, components {names[0]} (x) and "
        f"{names[1]} (y), sliding in the plane, {where}"
    )
    for note in res.notes:
        click.echo(f"  note: {note}")
    click.echo(
        f"{'mu_k':>7} {'mu_s':>7} {'peak slide (m)':>15} {'dir (deg)':>9} "
        f"{'residual x, y (m)':>23} {'sliding':>8} {'1-D ' + names[0]:>10} {'1-D ' + names[1]:>10} "
        f"{'2-D/1-D':>8}"
    )
    for row in rows:
        rx, ry = row["residual"]
        d1, d2 = row["peak_slide_1d"]
        click.echo(
            f"{row['mu_k']:7.4g} {row['mu_s']:7.4g} {row['peak_slide']:15.6g} "
            f"{row['peak_angle']:9.1f} {rx:11.4g},{ry:11.4g} {row['slide_fraction']:8.1%} "
            f"{d1:10.4g} {d2:10.4g} {row['ratio_2d_1d']:8.3f}"
        )


@cli.command()
@click.argument("record")
@click.argument("record2", required=False)
@click.option("--mu", required=True, metavar="MU[,MU...]", help="Kinetic friction coefficient(s).")
@click.option("--mu-s", "mu_s", metavar="MU_S", help="Static coefficient(s) (default: --mu).")
@click.option("--scale-pga", type=NUMBER, metavar="G", help="Scale the record to this PGA, in g.")
@click.option(
    "--direction",
    type=click.Choice(["both", "positive", "negative"]),
    default="both",
    show_default=True,
    help="One-way sliding (Newmark slope convention) or both ways.",
)
@click.option(
    "--pair",
    "as_pair",
    is_flag=True,
    help="RECORD holds both horizontal components (a multi-channel file, or one file of a K-NET "
    "recording whose .NS/.EW files are beside it): slide in the plane.",
)
@click.option(
    "--building-h2",
    "building_h2",
    metavar="SPEC",
    help="In the plane: the building's model along the second component (as --building; "
    "default: the same as --building).",
)
@click.option("--json", "as_json", is_flag=True, help="Print a JSON list (SI values) on stdout.")
@building_options
@record_options
@processing_options
def slide(
    record,
    record2,
    as_pair,
    building_h2,
    mu,
    mu_s,
    scale_pga,
    direction,
    as_json,
    building_spec,
    floor,
    fmt,
    units,
    dt,
    component,
    detrend,
    taper,
    highpass,
    lowpass,
):
    """Sliding of a rigid block under RECORD — on the ground, or on a floor of a building given
    with --building (and --floor) — one row per friction coefficient: peak slide, residual
    slide (m), peak absolute acceleration of the object (m/s²), fraction of time sliding and
    number of slip phases. Exact for the piecewise-linear record, end to end (ground →
    building → object); no filtering unless asked (--detrend, --taper, --highpass,
    --lowpass, applied before --scale-pga). The header says where the object stands and, on a
    floor, its peak floor acceleration. The record's quality flags (mean offset, trend,
    clipping, truncation: floorslide inspect) are printed as warnings on stderr, with the
    processing that removes them; in JSON each row also has "qa_flags".

    With two horizontal components — RECORD and RECORD2, or --pair — the block slides in the
    plane (isotropic Coulomb friction; docs/design.md §10d): peak slide magnitude and its
    direction (degrees from the first component towards the second), residual vector, and
    beside them each component's 1-D slide and the ratio 2-D / max(1-D). --scale-pga scales
    both components by one factor, so that the larger PGA is G; --building-h2 gives the
    building a model of its own along the second component.
    """
    from floorslide.constants import G
    from floorslide.contents.sliding import slide as slide_exact

    mus = _floats(mu, "--mu")
    mus_s = _floats(mu_s, "--mu-s") if mu_s else None
    building, floor_no, where = _building(building_spec, floor)
    processing = _processing(detrend, taper, highpass, lowpass)
    pair = record2 is not None or as_pair
    _kernels("plane" if pair else "ground" if building is None else _family_of(building))
    if pair:
        if direction != "both":
            raise click.BadParameter(
                "one-way sliding is 1-D; in the plane a block slides both ways",
                param_hint="--direction",
            )
        if record2 is not None and as_pair:
            raise click.BadParameter("give RECORD2 or --pair, not both", param_hint="--pair")
        _slide_pair(record, record2, mus, mus_s, scale_pga, building, building_h2, floor_no,
                    where, (fmt, units, dt, component), processing, as_json)  # fmt: skip
        return
    if building_h2 is not None:
        raise click.BadParameter(
            "is for two components (RECORD2 or --pair)", param_hint="--building-h2"
        )
    tr, quality, fm = _record_on_floor(record, (fmt, units, dt, component), processing,
                                       scale_pga, building, floor_no)  # fmt: skip
    res = slide_exact(fm, None, mus, mus_s, direction=direction)
    rows = res.to_records()
    if as_json:
        for row in rows:
            row["record"] = record
            row["direction"] = direction
            row["building"] = building_spec
            row["floor"] = floor_no
            row["qa_flags"] = list(quality.codes)
        click.echo(_strict_json(rows))
        return
    click.echo(
        f"{record}: dt = {tr.stats.delta:g} s, {tr.stats.npts} samples, direction {direction}"
        + (f", {where}" if building is None else "")
    )
    if building is not None:
        pfa = fm.peak()[0]
        click.echo(f"{where}; PFA = {pfa:.4g} m/s2 ({pfa / G:.4f} g)")
    click.echo(
        f"{'mu_k':>7} {'mu_s':>7} {'peak slide (m)':>15} {'residual (m)':>13} "
        f"{'peak acc (m/s2)':>16} {'(g)':>7} {'sliding':>8} {'slips':>6}"
    )
    for row in rows:
        click.echo(
            f"{row['mu_k']:7.4g} {row['mu_s']:7.4g} {row['peak_slide']:15.6g} "
            f"{row['residual_slide']:13.6g} {row['peak_abs_accel']:16.5g} "
            f"{row['peak_abs_accel'] / G:7.4f} {row['slide_fraction']:8.1%} {row['slip_phases']:6d}"
        )


@cli.command()
@click.argument("record")
@click.option("--width", required=True, metavar="B[,B...]", help="Base width(s) of the block, m.")
@click.option(
    "--height", required=True, metavar="H[,H...]", help="Height(s), m (one, or one per width)."
)
@click.option(
    "--restitution",
    type=NUMBER,
    metavar="R",
    help="Angular-velocity ratio after/before an impact, 0–1 (default Housner's 1 − 1.5 sin²α).",
)
@click.option(
    "--method",
    type=click.Choice(["exact", "nonlinear"]),
    default="exact",
    show_default=True,
    help="exact: the linearised (slender-block) equation, exact; nonlinear: the full equation, "
    "exact to rounding.",
)
@click.option(
    "--mu",
    metavar="MU[,MU...]",
    help="Kinetic friction at the contact: the blocks may slide while they rock (slide–rock, "
    "docs/design.md §10g; the full equations), one row per block and friction value.",
)
@click.option("--mu-s", metavar="MU[,MU...]", help="Static friction with --mu (default --mu).")
@click.option("--scale-pga", type=NUMBER, metavar="G", help="Scale the record to this PGA, in g.")
@click.option("--json", "as_json", is_flag=True, help="Print a JSON list (SI values) on stdout.")
@building_options
@record_options
@processing_options
def rock(
    record,
    width,
    height,
    restitution,
    method,
    mu,
    mu_s,
    scale_pga,
    as_json,
    building_spec,
    floor,
    fmt,
    units,
    dt,
    component,
    detrend,
    taper,
    highpass,
    lowpass,
):
    """Rocking of rigid blocks (Housner) under RECORD — on the ground, or on a floor of a
    building given with --building (and --floor) — one row per block: slenderness α =
    atan(B/H), peak rotation over slenderness θ/α (1 = overturned), impacts, uplifts, time spent
    rocking, and whether and when it overturned. Friction is assumed to hold the corner (Shenton:
    mu_s > B/H; else the block slides: floorslide slide) — unless --mu is given: then each
    block rests, slides, rocks or slides while it rocks (slide–rock, the full equations), and
    the rows add the peak slide and the time in each mode. Exact for the piecewise-linear
    record, end to end; uplift, impacts and overturning located inside steps. No filtering
    unless asked. The record's quality flags are printed as warnings on stderr.
    """
    from floorslide.constants import G
    from floorslide.contents.rocking_block import rock as rock_blocks
    from floorslide.errors import ModelError

    widths = _floats(width, "--width")
    heights = _floats(height, "--height")
    building, floor_no, where = _building(building_spec, floor)
    processing = _processing(detrend, taper, highpass, lowpass)
    _kernels(_family_of(building))
    tr, quality, fm = _record_on_floor(record, (fmt, units, dt, component), processing,
                                       scale_pga, building, floor_no)  # fmt: skip
    if mu is not None or mu_s is not None:
        _slide_rock_rows(record, tr, quality, fm, building, building_spec, floor_no, where, widths,
                         heights, restitution, mu, mu_s, as_json)  # fmt: skip
        return
    try:
        res = rock_blocks(fm, width=widths, height=heights, restitution=restitution, method=method)
    except ModelError as exc:
        raise click.BadParameter(exc.message, param_hint=f"--{exc.where or 'width'}") from None
    rows = res.to_records()
    if as_json:
        for row in rows:
            row.update(record=record, method=method, building=building_spec, floor=floor_no)
            row["qa_flags"] = list(quality.codes)
        click.echo(_strict_json(rows))
        return
    click.echo(
        f"{record}: dt = {tr.stats.delta:g} s, {tr.stats.npts} samples, {method} "
        f"({'linearised' if method == 'exact' else 'full'} equation)"
        + (f", {where}" if building is None else "")
    )
    if building is not None:
        pfa = fm.peak()[0]
        click.echo(f"{where}; PFA = {pfa:.4g} m/s2 ({pfa / G:.4f} g)")
    click.echo(
        f"{'B (m)':>7} {'H (m)':>7} {'B/H':>6} {'alpha':>7} {'r':>6} {'peak th/a':>10} "
        f"{'impacts':>8} {'uplifts':>8} {'rocking':>9}  outcome"
    )
    for row in rows:
        outcome = f"overturns at {row['overturn_time']:.4g} s" if row["overturned"] else row["mode"]
        click.echo(
            f"{row['width']:7.4g} {row['height']:7.4g} {row['width'] / row['height']:6.3f} "
            f"{row['alpha']:7.4f} {row['restitution']:6.3f} {row['peak_ratio']:10.4f} "
            f"{row['impacts']:8d} {row['uplifts']:8d} {row['rocking_time']:8.3f}s  {outcome}"
        )


def _slide_rock_rows(record, tr, quality, fm, building, building_spec, floor_no, where, widths,
                     heights, restitution, mu, mu_s, as_json):  # fmt: skip
    """``floorslide rock --mu``: slide–rock blocks, one row per block and friction value."""
    import numpy as np

    from floorslide.constants import G
    from floorslide.contents.slide_rock import slide_rock
    from floorslide.errors import ModelError

    if mu is None:
        raise click.BadParameter("--mu-s needs --mu (the kinetic friction)", param_hint="--mu-s")
    mk = _floats(mu, "--mu")
    ms = _floats(mu_s, "--mu-s") if mu_s is not None else list(mk)
    if len(ms) != len(mk):
        raise click.BadParameter(
            f"give one --mu-s per --mu value ({len(mk)}), got {len(ms)}", param_hint="--mu-s"
        )
    B, H = np.broadcast_arrays(np.asarray(widths, float), np.asarray(heights, float))
    nb, nm = B.size, len(mk)
    try:
        res = slide_rock(fm, None, np.repeat(B, nm), np.repeat(H, nm), np.tile(mk, nb),
                         mu_s=np.tile(ms, nb), restitution=restitution)  # fmt: skip
    except (ModelError, ValueError) as exc:
        hint = getattr(exc, "where", None) or "width"
        raise click.BadParameter(str(getattr(exc, "message", exc)),
                                 param_hint=f"--{hint.replace('_', '-')}") from None  # fmt: skip
    rows = res.to_records()
    if as_json:
        for row in rows:
            row.update(record=record, method="slide-rock", building=building_spec, floor=floor_no)
            row["qa_flags"] = list(quality.codes)
        click.echo(_strict_json(rows))
        return
    click.echo(
        f"{record}: dt = {tr.stats.delta:g} s, {tr.stats.npts} samples, slide–rock (full "
        "equations)" + (f", {where}" if building is None else "")
    )
    if building is not None:
        pfa = fm.peak()[0]
        click.echo(f"{where}; PFA = {pfa:.4g} m/s2 ({pfa / G:.4f} g)")
    click.echo(
        f"{'B (m)':>7} {'H (m)':>7} {'mu_k':>6} {'mu_s':>6} {'peak th/a':>10} {'slide (m)':>10} "
        f"{'impacts':>8} {'slide':>8} {'rock':>8} {'sl-rock':>8}  outcome"
    )
    for row in rows:
        outcome = f"overturns at {row['overturn_time']:.4g} s" if row["overturned"] else row["mode"]
        click.echo(
            f"{row['width']:7.4g} {row['height']:7.4g} {row['mu_k']:6.3g} {row['mu_s']:6.3g} "
            f"{row['peak_ratio']:10.4f} {row['peak_slide']:10.4g} {row['impacts']:8d} "
            f"{row['time_slide']:7.3f}s {row['time_rock']:7.3f}s {row['time_slide_rock']:7.3f}s"
            f"  {outcome}"
        )


def _periods(text: str | None):
    """``--periods`` as a list ``0.1,0.5,1`` or a log-spaced ``min:max:n``."""
    if text is None:
        return {"min": 0.02, "max": 5.0, "n": 100}
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise click.BadParameter(
                "expected MIN:MAX:N or a comma-separated list", param_hint="--periods"
            )
        try:
            return {"min": _number(parts[0]), "max": _number(parts[1]), "n": _whole(parts[2])}
        except ValueError:
            raise click.BadParameter(
                "expected MIN:MAX:N with numbers", param_hint="--periods"
            ) from None
    return _floats(text, "--periods")


SPECTRUM_UNITS = {
    "periods": "s",
    "damping": "1",
    "psa": "m/s**2",
    "sa": "m/s**2",
    "sv": "m/s",
    "sd": "m",
    "psv": "m/s",
}
"""Units of ``spectrum --json`` (SI; the text table prints PSA and SA in g)."""

ROTD_UNITS = {
    "periods": "s",
    "damping": "1",
    "rotd50": "m/s**2",
    "rotd100": "m/s**2",
    "angle100": "deg",
    "time100": "s",
    "h1": SPECTRUM_UNITS,
    "h2": SPECTRUM_UNITS,
}
"""Units of ``spectrum --json`` with two components (the text table prints g)."""


def _floor_name(building, floor_no: int) -> str:
    """``ground``, ``base mat``, ``roof`` or ``floor N`` (the ground without a building)."""
    from floorslide.report.columns import floor_label

    if building is None:
        return "ground"
    return floor_label(_kind(building), floor_no, building.stories)


def _kind(building) -> str:
    """``isolated`` (on linear or nonlinear isolation: floor 0 is its base mat) or ``fixed``."""
    return "isolated" if hasattr(building, "superstructure") else "fixed"


def _spectrum_grid(periods: str | None, damping: str):
    """The periods and damping ratios of ``spectrum``, checked before anything is read: at most
    as many as a scene allows, none absurd (a usage error naming the option, exit 2)."""
    from floorslide.errors import ModelError
    from floorslide.spectra.core import check_oscillators, damping_ratios, period_grid

    zetas = _floats(damping, "--damping")
    try:
        grid, ratios = period_grid(_periods(periods)), damping_ratios(zetas)
        check_oscillators(grid, ratios)
    except ModelError as exc:
        raise click.BadParameter(exc.message, param_hint=f"--{exc.where}") from None
    return grid, ratios


@cli.command()
@click.argument("record")
@click.argument("record2", required=False)
@click.option(
    "--pair",
    "as_pair",
    is_flag=True,
    help="RECORD holds both horizontal components (a multi-channel file, or one file of a K-NET "
    "recording): RotD50 and RotD100 spectra.",
)
@click.option(
    "--building-h2",
    "building_h2",
    metavar="SPEC",
    help="With two components: the building's model along the second (default: --building).",
)
@click.option(
    "--damping", default="0.05", show_default=True, metavar="Z[,Z...]", help="Damping ratio(s)."
)
@click.option(
    "--periods",
    metavar="T[,T...]|MIN:MAX:N",
    help="Periods in s (0 = peak ground acceleration); default 0.02:5:100 (log-spaced).",
)
@click.option(
    "--json",
    "as_json",
    is_flag=True,
    help="Print JSON on stdout: SI values (PSA and SA in m/s**2, not g as in the text table), "
    "their units under 'units'.",
)
@building_options
@record_options
@processing_options
def spectrum(
    record,
    record2,
    as_pair,
    building_h2,
    damping,
    periods,
    as_json,
    building_spec,
    floor,
    fmt,
    units,
    dt,
    component,
    detrend,
    taper,
    highpass,
    lowpass,
):
    """Response spectra of RECORD — or, with --building (and --floor), floor response spectra
    of that floor: pseudo-spectral acceleration PSA, absolute acceleration SA, relative
    velocity SV, displacement SD (and pseudo-velocity PSV), exact for the piecewise-linear
    record with peaks inside steps, end to end (ground → building → oscillator). No filtering
    is applied unless asked (--detrend, --taper, --highpass, --lowpass). The header says which
    motion the spectra are of. The record's quality flags (mean offset, trend, clipping,
    truncation, periods below 4·dt) are printed as warnings on stderr; in JSON under "qa".

    With two horizontal components — RECORD and RECORD2, or --pair — the spectra are RotD50
    and RotD100 (Boore 2010: the median and the largest over every direction of the peak
    response along it, exact with peaks inside steps) beside each component's PSA;
    --building-h2 gives the building its own model along the second component.
    """
    from floorslide.constants import G
    from floorslide.errors import ModelError
    from floorslide.records.quality import check_record
    from floorslide.spectra.core import check_oscillators, response_spectrum

    grid, zetas = _spectrum_grid(periods, damping)
    building, floor_no, where = _building(building_spec, floor)
    _kernels("plane" if record2 is not None or as_pair else _family_of(building))
    if record2 is not None or as_pair:
        if record2 is not None and as_pair:
            raise click.BadParameter("give RECORD2 or --pair, not both", param_hint="--pair")
        _spectrum_pair(record, record2, grid, zetas, building, building_h2, floor_no, where,
                       (fmt, units, dt, component),
                       _processing(detrend, taper, highpass, lowpass), as_json)  # fmt: skip
        return
    if building_h2 is not None:
        raise click.BadParameter(
            "is for two components (RECORD2 or --pair)", param_hint="--building-h2"
        )
    tr = _read_one(record, fmt, units, dt, component)
    tr = _apply_processing(tr, _processing(detrend, taper, highpass, lowpass))
    try:
        check_oscillators(grid, zetas, tr.stats.delta)
    except ModelError as exc:
        raise click.BadParameter(exc.message, param_hint="--periods") from None
    quality = check_record(tr.data, tr.stats.delta, periods=grid)
    _warn_quality(record, quality)
    sp = response_spectrum(
        tr.data,
        tr.stats.delta,
        grid,
        zetas,
        building=building,
        floor=floor_no if building is not None else None,
    )
    if as_json:
        out = {
            "record": record,
            "building": building_spec,
            "floor": floor_no,
            "floor_label": _floor_name(building, floor_no),
            **sp.to_dict(),
            "units": SPECTRUM_UNITS,
            "qa": quality.to_dict(),
        }
        click.echo(_strict_json(out))
        return
    click.echo(
        f"{record}: dt = {tr.stats.delta:g} s, {tr.stats.npts} samples"
        + (", spectra of the ground motion" if building is None else "")
    )
    if building is not None:
        click.echo(f"floor response spectra {where}")
    for i, z in enumerate(sp.damping):
        click.echo(f"damping {z:g}")
        click.echo(f"{'T (s)':>9} {'PSA (g)':>9} {'SA (g)':>9} {'SV (m/s)':>10} {'SD (m)':>10}")
        for j, t in enumerate(sp.periods):
            click.echo(
                f"{t:9.4g} {sp.psa[i, j] / G:9.4f} {sp.sa[i, j] / G:9.4f} "
                f"{sp.sv[i, j]:10.4g} {sp.sd[i, j]:10.4g}"
            )


def _pair_input(record, record2, reading, processing, building, building_h2, where):
    """Two components read and processed (each checked, flags warned on stderr), as a pair,
    and the building in the plane (with ``--building-h2``); returns ``(pair, model, where,
    qa)``."""
    from floorslide.building.directions import BuildingPair
    from floorslide.building.spec import describe_building, parse_building
    from floorslide.errors import ModelError
    from floorslide.pair import make_pair
    from floorslide.records.pairs import check_components
    from floorslide.records.quality import check_record

    labels = [record, record2 or f"{record} (2nd)"]
    raw = _pair_traces(record, record2, reading)
    check_components(*raw, *labels)
    t1, t2 = (_apply_processing(t, processing) for t in raw)
    codes = []
    for tr, label in zip((t1, t2), labels, strict=True):
        quality = check_record(tr.data, tr.stats.delta)
        _warn_quality(label, quality)
        codes.append(list(quality.codes))
    names = tuple(
        str(getattr(getattr(t.stats, "record", None), "component", "") or t.stats.channel or h)
        for t, h in ((t1, "h1"), (t2, "h2"))
    )
    pair = make_pair(t1.data, t2.data, float(t1.stats.delta), names=names,
                     label=" + ".join(labels), dt2=float(t2.stats.delta))  # fmt: skip
    model = building
    if building_h2 is not None:
        if building is None:
            raise click.BadParameter("needs --building", param_hint="--building-h2")
        try:
            model = BuildingPair(building, parse_building(building_h2))
        except ModelError as exc:
            raise click.BadParameter(str(exc), param_hint="--building-h2") from None
        where += f"; along {names[1]}: {describe_building(model.h2)}"
    return pair, model, where, codes


def _spectrum_pair(record, record2, grid, zetas, building, building_h2, floor_no, where,
                   reading, processing, as_json):  # fmt: skip
    """``floorslide spectrum`` with two horizontal components: RotD50 and RotD100."""
    from floorslide.constants import G
    from floorslide.errors import ModelError
    from floorslide.spectra.core import check_oscillators
    from floorslide.spectra.rotd import rotd_spectrum

    pair, model, where, codes = _pair_input(record, record2, reading, processing, building,
                                            building_h2, where)  # fmt: skip
    try:
        check_oscillators(grid, zetas, pair.dt)
    except ModelError as exc:
        raise click.BadParameter(exc.message, param_hint="--periods") from None
    r = rotd_spectrum(pair, None, grid, zetas, building=model,
                      floor=floor_no if building is not None else None)  # fmt: skip
    if as_json:
        out = {
            "records": [record] + ([record2] if record2 else []),
            "components": list(pair.names),
            "floor": floor_no,
            "floor_label": _floor_name(building, floor_no),
            **r.to_dict(),
            "units": ROTD_UNITS,
            "qa_flags": codes,
            "notes": list(pair.notes),
        }
        out.pop("psa_angles", None)
        click.echo(_strict_json(out))
        return
    click.echo(
        f"{pair.label}: dt = {pair.dt:g} s, {pair.npts} samples, components {pair.names[0]} and "
        f"{pair.names[1]}: RotD50 and RotD100 (Boore 2010), {where}"
    )
    for note in pair.notes:
        click.echo(f"  note: {note}")
    for i, z in enumerate(r.damping):
        click.echo(f"damping {z:g}")
        click.echo(
            f"{'T (s)':>9} {'RotD50 (g)':>11} {'RotD100 (g)':>12} {'dir100 (deg)':>13} "
            f"{'PSA ' + pair.names[0] + ' (g)':>12} {'PSA ' + pair.names[1] + ' (g)':>12}"
        )
        for j, t in enumerate(r.periods):
            click.echo(
                f"{t:9.4g} {r.rotd50[i, j] / G:11.4f} {r.rotd100[i, j] / G:12.4f} "
                f"{r.angle100[i, j]:13.1f} {r.h1.psa[i, j] / G:12.4f} {r.h2.psa[i, j] / G:12.4f}"
            )


def _print_summary(summary, plan) -> None:
    """The end of a run: counts, time, where the results are, the flags of finished tasks,
    unreadable records and failed tasks."""
    click.echo(
        f"{summary.ran} tasks run, {summary.resumed} already done, {summary.tasks} in all, "
        f"in {summary.seconds:.1f} s → {summary.out}"
    )
    for warning in summary.warnings:
        click.echo(f"floorslide: warning: {warning}", err=True)
    for failure in summary.failures:
        click.echo(f"floorslide: error: {failure}", err=True)


def _print_results(out: str) -> None:
    """The study's results after a run (:mod:`floorslide.report.summary`): what
    ``floorslide table --summary`` prints. A file that cannot be summarised (no finished
    task) gets one line on stderr; the run's outcome stays as it was."""
    from floorslide.errors import FloorslideError
    from floorslide.report.summary import format_summary
    from floorslide.report.tables import design_tables

    try:
        tables = design_tables(out, allow_incomplete=True)
    except FloorslideError as exc:
        click.echo(f"floorslide: note: no summary of {out}: {exc}", err=True)
        return
    click.echo("")
    click.echo(format_summary(tables))
    click.echo(f"(again: floorslide table {out} --summary; all tables: floorslide table {out})")


@cli.command()
@click.argument("scene", type=click.Path(dir_okay=False))
@click.option("-o", "--out", metavar="OUT.h5", help="Result file (default: SCENE's name .h5 here).")
@click.option("--dry-run", is_flag=True, help="Print the plan (what runs, what is skipped, why).")
@click.option(
    "--resume",
    is_flag=True,
    help="Continue an interrupted run of the same scene in OUT.h5; finished tasks are kept "
    "(each checked against its digest; one that fails runs again).",
)
@click.option(
    "--overwrite",
    is_flag=True,
    help="Replace an existing OUT.h5. Without it (or --resume) an existing file is refused.",
)
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    metavar="N",
    help="Local worker processes (default: all cores; at most one per task and 2 per core).",
)
@click.option(
    "--scheduler", metavar="ADDRESS", help="Send the tasks to a running Dask distributed scheduler."
)
@click.option(
    "--scheduler-timeout",
    type=click.FloatRange(min=0, min_open=True),
    metavar="SECONDS",
    help="With --scheduler: give up after this long without any worker connected (default: 60).",
)
@click.option(
    "--force", is_flag=True, hidden=True, help="Integrate even where the answer is known."
)
def run(scene, out, dry_run, resume, overwrite, workers, scheduler, scheduler_timeout, force):
    """Run a scene file (TOML): records × buildings × contents → OUT.h5.

    The planner simulates only what the scene asks for and says what it skipped; results are
    written as tasks finish, so an interrupted run keeps them and --resume continues it.
    An existing OUT.h5 is never replaced unless --overwrite is given. Unreadable records and
    tasks that fail (a solver at its event limit) are reported, left out of OUT.h5 (which
    stays INCOMPLETE) and the others still run (exit code 3).

    Exit codes: 0 done; 1 results could not be written (e.g. a full disk: the finished tasks
    are kept, free space and rerun with --resume) or no Dask worker came; 2 bad usage, an
    invalid scene, or OUT.h5 exists (without --resume or --overwrite) or is foreign; 3 a
    record could not be read or a task failed; 128 + signal when interrupted (130 Ctrl-C,
    143 SIGTERM, 129 SIGHUP; what finished is kept).
    """
    from pathlib import Path

    from floorslide.errors import Interrupted
    from floorslide.run.execute import SCHEDULER_TIMEOUT, execute, interrupt_signals
    from floorslide.scene.planner import plan as make_plan
    from floorslide.scene.schema import load_scene

    if resume and overwrite:
        raise click.UsageError("--resume and --overwrite exclude each other")
    if scheduler_timeout is not None and not scheduler:
        raise click.BadParameter("needs --scheduler", param_hint="--scheduler-timeout")
    # SIGINT, SIGTERM and SIGHUP stop a run alike, from planning to the last line of its
    # summary; none is lost (one whose exception was swallowed still counts), and once the run
    # has begun each ends with the line below and exit 128 + signal (130, 143, 129)
    with interrupt_signals() as received:
        sc = load_scene(scene)
        from floorslide.firstrun import scene_families

        _kernels(*scene_families(sc), workers=workers)
        # the per-object rules need each task's true PFA: the dry run evaluates them to count
        # them; a real run leaves them to the tasks, so each building is integrated once per
        # record
        plan = make_plan(sc, force=force, evaluate=dry_run)
        if received:
            raise Interrupted(received[0])
        if dry_run:
            click.echo(plan.describe())  # lists the scene's warnings
            sys.exit(EXIT_RECORD if plan.failures else EXIT_OK)
        for warning in sc.warnings:
            click.echo(f"floorslide: warning: {scene}: {warning}", err=True)
        out = out or f"{Path(scene).stem}.h5"
        summary = None
        try:
            summary = execute(
                plan,
                out,
                workers=workers,
                scheduler=scheduler,
                resume=resume,
                overwrite=overwrite,
                force=force,
                scheduler_timeout=scheduler_timeout or SCHEDULER_TIMEOUT,
                signals=received,
            )
            if not summary.interrupted:
                _print_summary(summary, plan)
                _print_results(out)
        except KeyboardInterrupt:
            received.append(signal.SIGINT)  # (an Interrupted has put its signal first)
    if received or summary.interrupted:
        signum = received[0] if received else summary.signal
        kept = summary.kept if summary is not None else _journaled(out)
        click.echo(
            f"floorslide: interrupted ({signal.Signals(signum).name}); {kept} finished tasks "
            f"are in {out} (continue with --resume)",
            err=True,
        )
        sys.exit(128 + signum)
    if summary.failures:
        sys.exit(EXIT_RECORD)


def _journaled(out: str) -> int:
    """Finished tasks kept for ``--resume`` of a run interrupted before its summary: the
    entries of its journal."""
    from floorslide.run.store import journal_entries

    try:
        return len(journal_entries(out))
    except (OSError, ValueError):
        return 0


REPORT_TABLES = (
    "slides",
    "pfa",
    "frs",
    "slide_ratios",
    "pfa_ratios",
    "records",
    "isolators",
    "rocking",
    "plane",
    "scaling",
    "suite",
    "code",
    "exceedance",
    "fragility",
)
"""The design tables, in output order (floorslide.report.tables.TABLE_NAMES)."""

REPORT_EXIT_CODES = (
    "Exit codes: 0 written; 2 bad usage, or OUT.h5 missing, corrupt or not a floorslide result "
    "file, or a task in it fails its integrity check (its values changed after it was written: "
    "rebuild it with floorslide run SCENE -o OUT.h5 --resume); 4 OUT.h5 is incomplete (tasks "
    "missing: finish it with floorslide run SCENE -o OUT.h5 --resume, or pass "
    "--allow-incomplete for output labelled INCOMPLETE)."
)


def _compare_option(ctx, param, value: tuple[str, ...]) -> tuple[str, ...]:
    """``--compare A:B``: the syntax here; the building ids once the file is read."""
    from floorslide.report.tables import parse_comparison

    for spec in value:
        try:
            parse_comparison(spec)
        except ValueError as exc:
            raise click.BadParameter(str(exc), ctx=ctx, param=param) from None
    return value


def _report_call(ctx, func, *args, **kwargs):
    """Call a report function; a bad --compare/--periods/--damping becomes a usage error."""
    from floorslide.errors import ModelError

    try:
        return func(*args, **kwargs)
    except ModelError as exc:
        if exc.where in ("compare", "periods", "damping"):
            raise click.BadParameter(exc.message, ctx=ctx, param_hint=f"--{exc.where}") from None
        raise


def _load_for_report(result: str, allow_incomplete: bool):
    """The study of OUT.h5; an incomplete one is refused (exit 4) unless allowed, and then
    announced on stderr."""
    from floorslide.report.study import load_study

    study = load_study(result)
    study.require_complete(allow_incomplete)
    for note in study.notes:
        click.echo(f"floorslide: note: {study.source}: {note}", err=True)
    if study.status:
        click.echo(
            f"floorslide: warning: {study.source}: {study.status}; output labelled INCOMPLETE",
            err=True,
        )
    return study


_ALLOW_INCOMPLETE = click.option(
    "--allow-incomplete",
    is_flag=True,
    help="Report a result file whose run is not finished (tasks missing); every output is "
    "labelled INCOMPLETE. Without it such a file is refused (exit code 4).",
)
_FIGURE_WORKERS = click.option(
    "--workers",
    type=click.IntRange(min=1),
    metavar="N",
    help="Draw the figures in N processes (default: all cores; at most 2 per core and one "
    "per figure); the files are the same.",
)


def _figure_workers(workers: int | None) -> int:
    """``--workers`` of plot and report capped at the machine (one line when reduced); the
    figures cap it again at their number."""
    from floorslide.parallel import worker_count

    n, note = worker_count(workers, sys.maxsize, "figures")
    if note:
        click.echo(f"floorslide: warning: {note}", err=True)
    return n


@cli.command(epilog=REPORT_EXIT_CODES)
@click.argument("result", metavar="OUT.h5")
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["md", "csv", "json"]),
    default="md",
    show_default=True,
    help="Markdown, CSV or JSON.",
)
@click.option("--json", "as_json", is_flag=True, help="Same as --format json.")
@click.option(
    "--compare",
    multiple=True,
    metavar="A:B",
    callback=_compare_option,
    help="Ratios A / B between buildings (ids or base ids; repeatable). Default: the scene's "
    "[report] compare, else each isolated building over its superstructure.",
)
@click.option(
    "--periods",
    metavar="T[,T...]",
    help="FRS periods in s (default: [report] periods, else 0.1,0.2,0.3,0.5,1,2,3).",
)
@click.option("--damping", type=NUMBER, metavar="Z", help="FRS damping ratio (one stored).")
@click.option(
    "--table",
    "only",
    multiple=True,
    type=click.Choice(REPORT_TABLES),
    help="Only this table (repeatable; default all).",
)
@click.option(
    "--per-record",
    is_flag=True,
    help="Instead of the statistics, one row per record × building × floor × content × "
    "friction value (CSV, or JSON with --json).",
)
@click.option(
    "--summary",
    is_flag=True,
    help="Instead of the tables, the study's summary (what run and demo print last): per "
    "record set, content and floor the median peak slide (mm) per building and friction "
    "value, rocking and overturning counts, the median PFA (g). With --json: its rows.",
)
@_ALLOW_INCOMPLETE
@click.option(
    "-o",
    "--out",
    metavar="FILE|DIR",
    help="Write to FILE (md, json, --per-record) or one NAME.csv per table into DIR (csv) "
    "instead of stdout.",
)
def table(
    result,
    fmt,
    as_json,
    compare,
    periods,
    damping,
    only,
    per_record,
    summary,
    allow_incomplete,
    out,
):
    """Design tables from a result file OUT.h5: per record set, building, floor, content and
    friction coefficient the number of records, mean, median and 84th percentile (empirical,
    numpy 'linear') of peak slide, |residual| slide and peak object acceleration (for 2-DOF
    oscillators also spring deformation and top-mass acceleration), and how many records made
    the object slide or rock; PFA per floor; FRS ordinates (unbroadened and broadened); ratios
    between buildings (--compare A:B); the records and their quality flags; per building on
    nonlinear isolation the isolator's peak and residual displacement, peak force / W and the
    records that exceed its capacity (table isolators); per content with a width and height
    whose friction holds its corner (mu_s >= B/H) how many records made it rock and overturn,
    its peak rotation theta/alpha (median, p84) and impacts (table rocking). Design practice
    (docs/design.md §10e): each record's scale factor and log misfit to the target spectrum
    (scaling), the suite check against 90 % of the target (suite), ASCE 7-22 H_f beside the
    median and p84 PFA/PGA per floor (code), the fraction of records exceeding each allowable
    displacement or overturning (exceedance) and lognormal fragility over stripes (fragility).

    Rocking objects are simulated as slide–rock blocks, not as sliders, and never count as 0
    slide: each is its own outcome, ranked above every slide, and a statistic that falls on
    rocking records reads 'rocks' (Markdown) with its *_outcome column 'rock'. Rows over fewer
    than 8 records carry few_records (a p84 marked † in Markdown).

    Markdown goes to stdout by default. CSV on stdout gives each table after a line
    '# table: NAME' (one --table NAME: that table alone, a plain CSV); with -o DIR it writes
    one NAME.csv per table. NaN (undefined, e.g. 0/0
    ratios) is '—' in Markdown, empty in CSV and null in JSON; x/0 is '∞', 'inf' and null.
    """
    from floorslide.report import formats
    from floorslide.report import tables as tb

    if as_json:
        if fmt not in ("md", "json"):
            raise click.UsageError(f"--json and --format {fmt} conflict")
        fmt = "json"
    if per_record and only:
        raise click.UsageError("--per-record and --table conflict")
    if summary and (per_record or only or fmt == "csv"):
        what = "--per-record" if per_record else "--table" if only else "--format csv"
        raise click.UsageError(f"--summary and {what} conflict")
    names = tuple(n for n in REPORT_TABLES if n in only) if only else REPORT_TABLES
    study = _load_for_report(result, allow_incomplete)
    if per_record:
        from floorslide.report.records import RECORD_COLUMNS, record_rows

        rows = record_rows(study)
        if fmt == "json":
            text = formats.format_rows_json(RECORD_COLUMNS, rows, study.source, study.status)
            text += "\n"
        else:
            text = formats.format_rows_csv(RECORD_COLUMNS, rows, study.status)
        _emit(text, out, result)
        return
    dt = _report_call(
        click.get_current_context(),
        tb.design_tables,
        study,
        compare=list(compare) or None,
        periods=_floats(periods, "--periods") if periods is not None else None,
        damping=damping,
        allow_incomplete=True,
    )
    if summary:
        from floorslide.report.summary import format_summary, summary_rows

        if fmt == "json":
            data = {"status": dt.status, "complete": dt.complete, "rows": summary_rows(dt)}
            text = _strict_json(data) + "\n"
        else:
            text = format_summary(dt) + "\n"
        _emit(text, out, result)
        return
    if fmt == "csv":
        if out:
            for path in formats.write_csv(dt, out, names, inputs=[result]):
                click.echo(str(path))
            return
        if len(names) == 1:  # one table: plain CSV, as pandas.read_csv takes it
            click.echo(formats.format_csv(names[0], dt[names[0]], dt.status), nl=False)
            return
        click.echo(formats.format_csv_sections(dt, names), nl=False)
        return
    if fmt == "json":
        text = formats.format_json(dt, names) + "\n"
    else:
        text = formats.format_markdown(dt, names)
    _emit(text, out, result)


def _emit(text: str, out: str | None, source: str) -> None:
    """`text` to stdout, or to the file `out` (then its path is printed): never over the
    result file `source`, nor over a file floorslide did not write."""
    from floorslide.report.formats import write_text

    if out:
        click.echo(str(write_text(out, text, inputs=[source])))
        return
    click.echo(text, nl=False)


@cli.command(epilog=REPORT_EXIT_CODES)
@click.argument("result", metavar="OUT.h5")
@click.option(
    "-o",
    "--out",
    metavar="DIR",
    help="Folder of the figures (default: OUT-figures/ beside OUT.h5).",
)
@click.option(
    "--compare",
    multiple=True,
    metavar="A:B",
    callback=_compare_option,
    help="Peak-slide ratio figures A / B (default as for floorslide table).",
)
@click.option("--damping", type=NUMBER, metavar="Z", help="FRS damping ratio (one stored).")
@_ALLOW_INCOMPLETE
@click.option("--json", "as_json", is_flag=True, help="Print the files written as a JSON list.")
@_FIGURE_WORKERS
def plot(result, out, compare, damping, allow_incomplete, as_json, workers):
    """Figures (PNG) from a result file OUT.h5, one per kind and record set: floor motions and
    sliding histories of the stored history record; the isolator's hysteresis loop (force / W
    versus displacement) of each building on nonlinear isolation under that record
    (hysteresis_<set>.png); the rotation theta/alpha of the contents that rock under that
    record, overturning marked (rocking_<set>.png); median floor response spectra per floor
    (unbroadened, and broadened when stored); peak slide versus friction per floor (median and
    84th percentile per building; a statistic that falls on rocking records is drawn at the
    top of the panel, never at 0); spring deformation and top-mass acceleration of 2-DOF
    equipment; the fraction of records that rock and overturn each rocking content, per
    building (overturning_<set>.png); median peak-slide ratio A / B versus isolation period, one
    curve per friction coefficient. A figure without data in the file is not drawn. Prints the
    files written.
    """
    import json
    from pathlib import Path

    from floorslide.report.plots import plot_figures

    study = _load_for_report(result, allow_incomplete)
    folder = Path(out) if out else Path(result).with_name(f"{Path(result).stem}-figures")
    paths = _report_call(
        click.get_current_context(),
        plot_figures,
        study,
        folder,
        compare=list(compare) or None,
        damping=damping,
        allow_incomplete=True,
        workers=_figure_workers(workers),
    )
    if as_json:
        click.echo(json.dumps([str(p) for p in paths], indent=1))
        return
    for p in paths:
        click.echo(str(p))


def demo_summary(tables) -> str:
    """The summary of a study (:func:`floorslide.report.summary.format_summary`): per record
    set, content and floor the median peak slide (mm) per building and friction value over
    every record, rocking and overturning counts, and each building's median PFA at the
    content's floor; then the records' quality checks."""
    from floorslide.report.summary import format_summary

    return format_summary(tables)


def _older_demo(h5, scene_text: str) -> bool:
    """Whether `h5` is a demo result written by an earlier floorslide (its demo scene had other
    text under the same ``[scene] name``; its header is read even where it fails its digest:
    a damaged demo result is still the demo's own)."""
    import tomllib

    from floorslide.errors import FloorslideError
    from floorslide.run.store import ResultFile

    name = tomllib.loads(scene_text).get("scene", {}).get("name")
    try:
        return bool(name) and ResultFile(h5, repair=True).scene_name == name
    except FloorslideError:
        return False


def _demo_may_replace(h5, scene_text: str) -> bool:
    """Whether the demo may replace `h5` (and the journal beside it): only its own output.

    Returns
    -------
    bool
        True when `h5` is a result of the demo scene (finished or not; also one written by an
        earlier floorslide's demo), or is absent with an old journal beside it; False when
        there is nothing to replace.

    Raises
    ------
    OutputExistsError
        `h5` is anything else (exit code 2): it is left alone.
    """
    from floorslide.errors import OutputExistsError
    from floorslide.run.store import journal_entries, written_for

    folder = h5.parent
    if folder.is_symlink() or (folder.exists() and not folder.is_dir()):
        raise OutputExistsError(
            "is not a folder; the demo writes a folder of results (choose another with -o)",
            str(folder),
        )
    if not (h5.exists() or h5.is_symlink()):
        if journal_entries(h5):
            return True
        if folder.is_dir() and any(folder.iterdir()):
            raise OutputExistsError(
                "holds files and no demo result; the demo writes only into a new or empty "
                "folder, or one of an earlier demo (choose another folder with -o)",
                str(folder),
            )
        return False
    if written_for(h5, scene_text) or _older_demo(h5, scene_text):
        return True
    raise OutputExistsError(
        "exists and is not a floorslide result of the demo scene; not replaced (choose "
        "another folder with -o, or move the file away)",
        str(h5),
    )


@cli.command(epilog=REPORT_EXIT_CODES)
@click.argument("result", metavar="OUT.h5")
@click.option(
    "-o",
    "--out",
    metavar="FILE",
    help="The report (default: OUT-report.html beside OUT.h5).",
)
@_ALLOW_INCOMPLETE
@_FIGURE_WORKERS
def report(result, out, allow_incomplete, workers):
    """One self-contained HTML report of a result file OUT.h5: the design tables, every figure
    (embedded), the records with their provenance and quality flags, the scene as run and the
    software versions, INCOMPLETE in a banner when the run is not finished; it prints on A4.
    Prints the file written."""
    from pathlib import Path

    from floorslide.report.html import write_report

    study = _load_for_report(result, allow_incomplete)
    path = Path(out) if out else Path(result).with_name(f"{Path(result).stem}-report.html")
    written = _report_call(
        click.get_current_context(),
        write_report,
        study,
        path,
        allow_incomplete=True,
        workers=_figure_workers(workers),
    )
    click.echo(str(written))


def _import_report() -> None:
    """Import what the tables, figures and report need (run while a study's workers compute)."""
    import floorslide.report.html
    import floorslide.report.plots
    import floorslide.report.study
    import floorslide.report.tables  # noqa: F401


@cli.command()
@click.option(
    "-o",
    "--out",
    "out_dir",
    default="floorslide-demo",
    show_default=True,
    metavar="DIR",
    help="Folder for results.h5, tables and figures.",
)
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    metavar="N",
    help="Worker processes (default: all cores).",
)
def demo(out_dir, workers):
    """Run the bundled demo: a broad-band and a pulse-like set of recorded earthquakes, a
    1-storey fixed-base building (T = 0.2 s, 2 %), the same on linear isolation swept over
    T_i = 1.5…4 s (ξ_i = 10 %) and on friction-pendulum bearings (mu = 0.06, T = 3 s),
    equipment with mu = 0.05…0.5 on the roof and gaps of 5, 10 and 30 cm to a wall, floor
    response spectra per floor. Writes DIR/results.h5, DIR/tables (CSV and Markdown),
    DIR/figures and DIR/report.html (everything in one self-contained file).

    Run again, it replaces DIR/results.h5 only if that file is a floorslide result of the demo
    scene (a previous demo, finished or not); any other file there is left alone and the demo
    stops (exit code 2).
    """
    import importlib.resources
    from pathlib import Path

    from floorslide.run.execute import execute
    from floorslide.scene.planner import plan as make_plan
    from floorslide.scene.schema import load_scene

    scene_path = importlib.resources.files("floorslide.data") / "scenes" / "demo.toml"
    out = Path(out_dir)
    h5 = out / "results.h5"
    with importlib.resources.as_file(scene_path) as path:
        sc = load_scene(path)
        replace = _demo_may_replace(h5, sc.text)  # before the work: a refusal comes at once
        from floorslide.firstrun import scene_families

        _kernels(*scene_families(sc), workers=workers)
        # as `floorslide run`: the per-object rules are left to the tasks (each building
        # integrated once per record, not a second time to count them beforehand)
        plan = make_plan(sc, evaluate=False)
    click.echo(plan.describe())
    # the report's modules (pandas, matplotlib): imported while the workers compute the tasks
    summary = execute(plan, str(h5), workers=workers, overwrite=replace, meanwhile=_import_report)
    if summary.interrupted:
        click.echo(
            f"floorslide: interrupted ({signal.Signals(summary.signal).name}); "
            f"{summary.kept} finished tasks are in {h5}",
            err=True,
        )
        sys.exit(128 + summary.signal)
    from floorslide.report import design_tables, format_markdown, plot_figures, write_csv
    from floorslide.report.formats import write_text
    from floorslide.report.html import write_report
    from floorslide.report.study import load_study

    study = load_study(h5)  # the result file read once, for the tables and the figures
    tables = design_tables(study)
    csvs = write_csv(tables, out / "tables", inputs=[h5])
    md = write_text(out / "tables" / "tables.md", format_markdown(tables), inputs=[h5])
    figures = plot_figures(
        study, out / "figures", workers=workers or os.cpu_count() or 1, tables=tables
    )
    html = write_report(study, out / "report.html", tables=tables, figures=figures)
    click.echo("")
    click.echo(demo_summary(tables))
    click.echo(f"{summary.tasks} tasks in {summary.seconds:.1f} s")
    click.echo(f"results: {h5}")
    click.echo(f"tables:  {md} and {len(csvs)} CSV files in {out / 'tables'}")
    click.echo(f"figures: {len(figures)} PNG files in {out / 'figures'}")
    click.echo(f"report:  {html.resolve().as_uri()} (one self-contained HTML file)")
    if summary.failures:
        for failure in summary.failures:
            click.echo(f"floorslide: error: {failure}", err=True)
        sys.exit(EXIT_RECORD)


@cli.command()
@click.option(
    "--quick", is_flag=True, help="The short study: one record, fewer settings and repeats."
)
@click.option("--json", "as_json", is_flag=True, help="Print the table as JSON on stdout.")
@click.option(
    "-o",
    "--out",
    default="floorslide-bench",
    show_default=True,
    metavar="DIR",
    help="Directory for bench.csv, bench.md, bench.json and the figures.",
)
@click.option(
    "--only",
    metavar="KEY[,KEY...]",
    help="Run only these solvers (the table's solver keys, e.g. slide-ground,slide-rock-ground).",
)
def bench(quick, as_json, out, only):
    """The accuracy-versus-cost study (docs/design.md §6): for every solver (rigid-block sliding on
    the
    ground, a stiff floor and an isolated roof, and in the plane under pairs of components; the
    2-DOF sliding oscillator; floor motions; response and floor response spectra) the exact
    method and each approximate one over a range of steps or tolerances, on bundled real
    records: relative error in peak and residual
    slide, spring deformation, PFA, floor samples and PSA against the exact method, and CPU
    time (median of repeats after a warm-up call, one thread; numba compilation apart — on a
    fresh cache in a child process, except with --quick).

    Writes a table (CSV, Markdown, JSON) and one work-precision figure per solver (error versus
    CPU time, log-log) to DIR, and prints the Markdown table (or, with --json, the JSON).
    --quick runs one record (and one pair) and fewer settings, in under a minute; --only runs
    the solvers named.
    """
    from floorslide.bench import run_bench, to_json, to_markdown, write_outputs
    from floorslide.bench.compile import fresh_compile_times
    from floorslide.errors import ModelError
    from floorslide.firstrun import FAMILIES

    _kernels(*FAMILIES)
    show = sys.stderr.isatty()

    def progress(message: str) -> None:
        if show:
            click.echo(f"\rbench: {message[:68]:<68}", err=True, nl=False)

    keys = None
    if only is not None:
        keys = tuple(k.strip() for k in only.split(",") if k.strip())
        if not keys:
            raise click.BadParameter("give at least one solver key", param_hint="--only")
    try:
        result = run_bench(quick=quick, progress=progress, only=keys)
    except ModelError as exc:
        raise click.BadParameter(exc.message, param_hint="--only") from None
    if not quick:
        progress("numba compilation on an empty cache")
    compile_rows = None if quick else fresh_compile_times()
    if show:
        click.echo("\r" + " " * 76 + "\r", err=True, nl=False)
    paths = write_outputs(result, out, compile_rows)
    if as_json:
        click.echo(to_json(result, compile_rows))
        return
    click.echo(to_markdown(result, compile_rows))
    click.echo(f"{len(paths)} files written to {out}")


@cli.command()
@click.argument("old", metavar="OLD.h5")
@click.option(
    "-o",
    "--out",
    metavar="NEW.h5",
    help="Write the converted file here (default: replace OLD.h5 once converted).",
)
def upgrade(old, out):
    """Convert a result file of format 1 (written before the columnar format; one HDF5 group per
    task) to the columnar format written now (docs/design.md §5): every task is checked
    against its digest, then written as rows of the tables with the same digest. Old files
    also read as they are (slower); a file with a task that fails its integrity check is
    refused (rebuild it with floorslide run --resume first). Prints the file written."""
    from floorslide.run.store import upgrade as convert

    path, n = convert(old, out)
    click.echo(f"{path}: {n} tasks in the columnar format")


@cli.command()
@click.argument("path", default="scene.toml", required=False, metavar="[PATH]")
def init(path):
    """Write a commented scene template to PATH (default scene.toml): every section of a
    scene file (docs/design.md §4) on the bundled records, ready for
    `floorslide run PATH --dry-run`. An existing file is replaced only when it is an unedited
    template; anything else there is refused (exit code 2) and left alone."""
    from pathlib import Path

    from floorslide import outputs
    from floorslide.scene.template import scene_template

    text = scene_template(Path(path).name)
    mine = text.encode("utf-8")
    outputs.write_output(
        path,
        text,
        replace=lambda existing: existing == mine,
        advice="choose another PATH, or move the file away",
        what="the scene template",
    )
    click.echo(f"wrote {path}: a scene on the bundled records; edit it, then")
    click.echo(f"  floorslide run {path} --dry-run")


@cli.command()
@click.argument("families", nargs=-1, metavar="[FAMILY]...")
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    metavar="N",
    help="Compile N families at once (default: one per core).",
)
def warmup(families, workers):
    """Compile the numerical kernels now, once per installation, instead of on first use.

    floorslide's kernels are compiled by numba when first called and kept in a disk cache, so
    the first run of a fresh install (or after an upgrade) spends up to a few minutes
    compiling; every command that needs kernels says so on stderr ("compiling numerical
    kernels (first run only, ~N s)") and compiles what it needs. This command compiles them
    all in advance, several families at once where cores allow, and prints nothing to compile
    when they are cached already. FAMILY (default: all but bench): ground (rigid blocks on the
    ground), floors (linear buildings, blocks, rocking and spectra on floors), oscillator
    (2-DOF equipment), nonlinear (nonlinear isolation), plane (two horizontal components),
    bench (the approximate methods of floorslide bench).
    """
    from floorslide.firstrun import FAMILIES, USER_FAMILIES, compile_families, missing

    unknown = [f for f in families if f not in FAMILIES]
    if unknown:
        raise click.BadParameter(
            f"unknown family {unknown[0]!r}; families: {', '.join(FAMILIES)}",
            param_hint="FAMILY",
        )
    names = list(families) or list(USER_FAMILIES)
    todo = missing(names)
    if todo:
        done = compile_families(todo, workers=workers)
        if len(done) < len(todo):
            sys.exit(EXIT_UNEXPECTED)
    click.echo(f"kernels compiled: {', '.join(names)}" + ("" if todo else " (already)"))


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """floorslide's own warnings as one line on stderr (``floorslide: warning: ...``); others as
    Python shows them."""
    from floorslide.errors import FloorslideWarning, one_line

    if issubclass(category, FloorslideWarning):
        click.echo(f"floorslide: warning: {one_line(str(message))}", err=True)
        return
    _python_show_warning(message, category, filename, lineno, file, line)


_python_show_warning = warnings.showwarning


def _interrupt(signum, frame) -> None:
    """SIGTERM and SIGHUP end a command as Ctrl-C does (``floorslide: interrupted``, exit
    128 + signal); a run keeps what finished (:func:`floorslide.run.execute.interrupt_signals`)."""
    from floorslide.errors import Interrupted

    raise Interrupted(signum)


def main() -> None:
    """Entry point of the ``floorslide`` console script."""
    warnings.showwarning = _show_warning
    for name in ("SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), _interrupt)
    try:
        cli.main(standalone_mode=False)
    except click.exceptions.Abort as exc:  # click's form of a KeyboardInterrupt
        click.echo("floorslide: interrupted", err=True)
        sys.exit(128 + getattr(exc.__cause__, "signum", signal.SIGINT))
    except click.ClickException as exc:
        exc.show()
        sys.exit(EXIT_USAGE if exc.exit_code in (1, 2) else exc.exit_code)
    except FloorslideError as exc:
        fail(exc)
    except KeyboardInterrupt as exc:
        click.echo("floorslide: interrupted", err=True)
        sys.exit(128 + getattr(exc, "signum", signal.SIGINT))
    except SystemExit:
        raise


def entry() -> None:
    """The ``floorslide`` console script (and ``python -m floorslide.cli``): :func:`main`,
    then :func:`leave` — no interpreter teardown after the work is done."""
    try:
        main()
    except SystemExit as exc:
        leave(exc.code)
    leave(0)


def exit_status(code: int | str | None) -> int:
    """The exit status of ``sys.exit(code)``, as Python gives it: 0 for None, a message
    printed on stderr and 1, else the integer."""
    if code is None:
        return 0
    if not isinstance(code, int):
        print(code, file=sys.stderr)
        return 1
    return code


def leave(code: int | str | None) -> None:
    """End the process with `code` as ``sys.exit(code)`` would, without the interpreter's
    teardown when nothing needs it.

    Python's finalisation frees every imported module's objects one by one (NumPy, SciPy,
    numba and its compiled kernels, matplotlib, ObsPy, h5py): 0.2 s for a one-record
    command, 0.45 s after the demo, measured — work whose only effect is on a process about
    to end. Here the standard streams are flushed and the ``atexit`` functions run (logging,
    multiprocessing), then the process ends with :func:`os._exit`. Not while another
    non-daemon thread runs or an HDF5 object is open (HDF5 closes its files in the C
    library's own exit handler, which :func:`os._exit` skips): then ``sys.exit`` as usual.
    :func:`main` itself never does this (it is called in-process, by tests and scripts).
    """
    import atexit
    import threading

    code = exit_status(code)
    h5py = sys.modules.get("h5py")
    busy = any(
        t.is_alive() and not t.daemon and t is not threading.main_thread()
        for t in threading.enumerate()
    )
    if busy or (
        h5py is not None and h5py.h5f.get_obj_count(h5py.h5f.OBJ_ALL, h5py.h5f.OBJ_FILE) > 0
    ):
        sys.exit(code)
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):  # a closed pipe: Python's own exit reports it
        sys.exit(code)
    atexit._run_exitfuncs()
    os._exit(code)


if __name__ == "__main__":  # pragma: no cover
    entry()
