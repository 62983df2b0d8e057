"""The accuracy-versus-cost study (docs/design.md §6): ``floorslide bench --quick`` through the
Python
API and the command line — the table's structure, every solver and method present, finite
numbers, and each approximate method's error shrinking as its step or tolerance shrinks. Never
timings: CPU times are only checked to be positive numbers.
"""

from __future__ import annotations

import csv
import io
import json
import math
import subprocess
import sys
from collections import defaultdict

import pytest

from floorslide.bench import run_bench, study, to_csv, write_outputs
from floorslide.bench.cases import METRICS, QUICK, solvers
from floorslide.bench.output import COLUMNS
from floorslide.errors import ModelError

ROUNDING = 1e-10
"""Largest admissible error floor of an exact method: the exact solvers agree with themselves on
the record resampled at dt/2 to ~1e-13 (measured 5e-16 … 2.5e-13); anything near 1e-10 would
be a real discrepancy."""

FLOOR = 1e-8
"""Below this an approximate method's error is at its own floor rather than its step's or
tolerance's: solve_ivp restarted at every sample is exact to rounding on the ground for any rtol
(the in-step motion is a cubic, which DOP853 integrates exactly) and sits at 2e-9 … 4e-9 on the
isolated roof for every rtol (measured)."""


@pytest.fixture(scope="module")
def quick():
    """The quick study, timed once per method (the tests check its structure, errors and that
    CPU times are positive, never their values: the repeats would only cost time)."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setitem(study.TIMING, "quick", (1, 0.0))
        return run_bench(quick=True)


@pytest.fixture(scope="module")
def quick_cli(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "floorslide.cli",
            "bench",
            "--quick",
            "--json",
            "-o",
            str(out),
            "--only",
            ",".join(CLI_SOLVERS),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout), out


CLI_SOLVERS = ("spectra-ground", "slide-rock-ground")
"""The solvers the command-line test runs (``--only``; two of the quickest: the API's test
runs them all, this one the command's path)."""


def expected_methods(only=None):
    """(solver, method, setting) of every method the quick study defines (peers included when
    installed), of the solvers `only` if given."""
    return {
        (s.key, m.method, m.setting)
        for s in solvers(QUICK)
        if only is None or s.key in only
        for m in s.methods
    }


@pytest.mark.slow
def test_every_solver_and_method_is_in_the_table(quick):
    got = {(r.solver, r.method, r.setting) for r in quick.rows}
    assert got == expected_methods()
    keys = [s.key for s in solvers(QUICK)]
    assert list(quick.solvers) == keys
    assert {
        "slide-ground",
        "slide-stiff-floor",
        "slide-isolated-roof",
        "oscillator-ground",
        "floor-motions-stiff",
        "floor-motions-isolated",
        "spectra-ground",
        "frs-stiff-floor",
        "frs-isolated-roof",
        "plane-ground",
        "plane-roof",
        "slide-coupled",
        "oscillator-plane-ground",
    } <= set(keys)
    # every solver has its exact method and at least one approximate one
    for key in keys:
        methods = {r.method for r in quick.rows if r.solver == key}
        assert "exact" in methods and len(methods) >= 2
    # one single record, and one pair of components for the solvers in the plane
    assert [r["station_id"] for r in quick.records] == ["PET-090", "RSN511"]
    assert [r["components"] for r in quick.records] == [1, 2]
    for s in solvers(QUICK):
        assert quick.inputs[s.key] == (("RSN511",) if s.pair else ("PET-090",))


@pytest.mark.slow
def test_numbers_are_finite(quick):
    for r in quick.rows:
        what = f"{r.solver} {r.method} {r.setting}"
        assert math.isfinite(r.cpu_time) and r.cpu_time > 0, what
        assert math.isfinite(r.time_ratio) and r.time_ratio > 0, what
        assert r.first_call >= 0 and r.compile_time >= 0 and r.repeats >= 1, what
        assert set(r.errors) == set(quick.metrics[r.solver]), what
        for metric, value in r.errors.items():
            assert math.isfinite(value) and value >= 0, (what, metric)
        assert r.error == max(r.errors.values())
        if r.method == "exact":
            assert r.time_ratio == 1.0
            assert r.error < ROUNDING, what


def families(result):
    out = defaultdict(list)
    for r in result.rows:
        if r.method != "exact":
            out[(r.solver, r.family)].append(r)
    return {k: v for k, v in out.items() if len(v) > 1}


@pytest.mark.slow
def test_errors_shrink_as_steps_and_tolerances_shrink(quick):
    """Coarsest against finest setting of each family (in between, a switch or a peak moving
    across a step boundary makes the error non-monotone). Step families refined 16× or more
    (dt/1 → dt/64; first order or better, so ≥ 16× expected: measured 54–29,000× smaller) must
    gain 10×; the others (FFT dt → dt/4, rtol 1e-3 → 1e-7, grip 50 → 800 Hz: measured 2.4–290×,
    and 5,100–7,600× for solve_ivp in the plane) 2×; unless the fine error is at
    :data:`FLOOR`."""
    fams = families(quick)
    assert len(fams) >= 20
    for (solver, family), rows in fams.items():
        coarse, fine = rows[0], rows[-1]
        if coarse.substeps and fine.substeps and fine.substeps / coarse.substeps >= 16:
            factor = 10.0
        else:
            factor = 2.0
        assert fine.error <= max(coarse.error / factor, FLOOR), (
            solver,
            family,
            coarse.setting,
            coarse.error,
            fine.setting,
            fine.error,
        )


@pytest.mark.slow
def test_coarse_approximations_are_visibly_wrong(quick):
    """The study shows a trade: at the record's own step the approximate methods miss by
    percents (docs/design.md §2: a re-interpolated stiff floor loses ~12 % of the FRS peak at
    dt = 0.02 s; measured here 14 % on the slide and 10 % on the FRS)."""
    by = {(r.solver, r.method, r.setting): r.error for r in quick.rows}
    assert by[("slide-stiff-floor", "reinterpolated", "dt/1")] > 0.05
    assert by[("frs-stiff-floor", "reinterpolated", "dt/1")] > 0.05
    assert by[("slide-ground", "newmark", "dt/1")] > 0.01
    assert by[("oscillator-ground", "newmark", "dt/1")] > 0.05
    # in the plane: the record's step costs percents too, and sliding each component alone
    # misses the 2-D slide by tens of percents (measured 51 % and 69 %), whatever its cost
    assert by[("plane-ground", "newmark", "dt/1")] > 0.01
    assert by[("plane-ground", "components", "")] > 0.2
    assert by[("plane-roof", "components", "")] > 0.2
    # the coupled block at the record's step (measured 27 %) and the smoothed friction circle
    # at eps = 1 cm/s (measured 38 %: the oscillator's slides are millimetres)
    assert by[("slide-coupled", "newmark", "dt/1")] > 0.05
    assert by[("oscillator-plane-ground", "smoothed", "eps 0.01 m/s")] > 0.1


@pytest.mark.slow
def test_outputs_are_written(quick, tmp_path):
    paths = write_outputs(quick, tmp_path)
    names = {p.name for p in paths}
    assert {"bench.csv", "bench.md", "bench.json"} <= names
    for key in quick.solvers:
        png = tmp_path / f"{key}.png"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = list(csv.DictReader(io.StringIO(to_csv(quick))))
    assert tuple(rows[0]) == COLUMNS
    assert len(rows) == len(quick.rows)
    md = (tmp_path / "bench.md").read_text()
    for key in quick.solvers:
        assert f"(`{key}`)" in md


@pytest.mark.slow
def test_cli_json(quick_cli):
    data, out = quick_cli
    assert data["quick"] is True and data["compile"] is None
    assert {"rows", "records", "solvers", "metrics", "machine"} <= set(data)
    got = {(r["solver"], r["method"], r["setting"]) for r in data["rows"]}
    assert got == expected_methods(CLI_SOLVERS)
    assert set(data["solvers"]) == set(CLI_SOLVERS)
    for r in data["rows"]:
        assert set(r) == set(COLUMNS)
        assert r["cpu_time"] > 0 and math.isfinite(r["error"])
        for metric in METRICS:
            value = r[f"err_{metric}"]
            assert (value is not None) == (metric in data["metrics"][r["solver"]])
    assert (out / "bench.csv").is_file() and (out / "spectra-ground.png").is_file()


def test_unknown_solver_is_a_model_error():
    with pytest.raises(ModelError, match="unknown solver"):
        run_bench(quick=True, only=("slide-moon",))
    proc = subprocess.run(
        [sys.executable, "-m", "floorslide.cli", "bench", "--quick", "--only", "slide-moon"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2 and "--only" in proc.stderr and "slide-moon" in proc.stderr


@pytest.mark.slow
def test_json_round_trip_and_summary(quick):
    from floorslide.bench import BenchResult, to_json, to_markdown
    from floorslide.bench.output import summary_markdown

    again = BenchResult.from_dict(json.loads(to_json(quick)))
    assert again == quick
    summary = summary_markdown(quick)
    # one line per family and single-point method, each solver named once
    n_lines = len({(r.solver, r.family) for r in quick.rows if r.method != "exact"})
    assert len(summary.splitlines()) == n_lines + 2
    for key in quick.solvers:
        assert summary.count(f"`{key}`") == 1
    assert summary in to_markdown(quick)
