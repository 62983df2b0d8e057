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
