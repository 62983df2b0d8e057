"""The ``floorslide`` command line: parses, calls, prints; no numerics here.

Exit codes (DESIGN §3): 0 success; 2 bad usage or invalid scene; 3 unreadable record(s), the
others still processed; 1 unexpected error. A user mistake is reported as one line naming the
file or key at fault, never as a traceback.
"""

from __future__ import annotations

import sys

import click

from floorslide.errors import FloorslideError

EXIT_OK = 0
EXIT_UNEXPECTED = 1
EXIT_USAGE = 2
EXIT_RECORD = 3


def fail(error: FloorslideError) -> None:
    """Print a user error as one line on stderr and exit with its code."""
    click.echo(f"floorslide: error: {error}", err=True)
    sys.exit(error.exit_code)


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


@cli.command()
@click.argument("records", nargs=-1, required=True)
@click.option("--json", "as_json", is_flag=True, help="Print a JSON list (SI values) on stdout.")
@click.option("--format", "fmt", metavar="F", help="Record format (default: detected).")
@click.option("--units", metavar="U", help="Units of the files: g|gal|m/s**2|mm/s**2.")
@click.option("--dt", type=float, metavar="SECONDS", help="Time step of single-column text.")
@click.option("--component", metavar="C", help="Component to keep from multi-trace files.")
def inspect(
    records: tuple[str, ...],
    as_json: bool,
    fmt: str | None,
    units: str | None,
    dt: float | None,
    component: str | None,
) -> None:
    """Intensity measures of each RECORD: format, dt, npts, duration, PGA (m/s² and g), PGV,
    PGD, Arias intensity, CAV, significant durations D5-75 and D5-95.

    RECORD may be a record file (PEER .AT2, COSMOS V2, plain text, MiniSEED, SAC, K-NET and
    every ObsPy format), a catalog CSV (columns file, dt, units), or a directory, searched
    recursively for both (files a catalog lists are read once, through it; documentation such
    as *.md is skipped). --format/--units/--dt/--component apply to record files, not to
    catalog rows, which carry their own. Measures are exact for the piecewise-linear record;
    nothing is filtered. An unreadable record is reported on stderr and the others are still
    shown; the exit code is then 3.
    """
    import json

    from tqdm import tqdm

    from floorslide.errors import RecordError
    from floorslide.records.discover import discover
    from floorslide.records.measures import measures

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
                found = [(trace, measures(trace)) for trace in stream]
            except RecordError as exc:
                failed = True
                bar.write(f"floorslide: error: {exc}", file=sys.stderr)
                bar.update()
                continue
            for trace, values in found:
                record = trace.stats.record
                row = {
                    "record": source.label,
                    "format": record.format,
                    "component": record.component,
                    "station": record.station,
                    "event": record.event,
                    **values,
                    "multi": len(stream) > 1,
                }
                rows.append(row)
            bar.update()
    if as_json:
        out = []
        for row in rows:
            clean = {k: v for k, v in row.items() if k != "multi"}
            out.append(
                {k: (None if isinstance(v, float) and v != v else v) for k, v in clean.items()}
            )
        click.echo(json.dumps(out, indent=1))
    elif rows:
        _print_table(rows)
    if failed:
        sys.exit(EXIT_RECORD)


def main() -> None:
    """Entry point of the ``floorslide`` console script."""
    try:
        cli.main(standalone_mode=False)
    except click.exceptions.Abort:
        click.echo("floorslide: interrupted", err=True)
        sys.exit(130)
    except click.ClickException as exc:
        exc.show()
        sys.exit(EXIT_USAGE if exc.exit_code in (1, 2) else exc.exit_code)
    except FloorslideError as exc:
        fail(exc)
    except KeyboardInterrupt:
        click.echo("floorslide: interrupted", err=True)
        sys.exit(130)
    except SystemExit:
        raise


if __name__ == "__main__":  # pragma: no cover
    main()
