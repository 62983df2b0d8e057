"""The single-record solver commands: floorslide slide and floorslide spectrum (DESIGN §3)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from floorslide.contents.sliding import slide
from floorslide.spectra import response_spectrum
from tests.conftest import SLAMMER, load_slammer

RECORD = str(SLAMMER / "ImperialValley_1940_ELC-180.txt")


def run(*args):
    return subprocess.run(
        [sys.executable, "-m", "floorslide.cli", *args], capture_output=True, text=True
    )


def test_slide_json_matches_the_api():
    out = run("slide", RECORD, "--mu", "0.05,0.2", "--mu-s", "0.1,0.25", "--json")
    assert out.returncode == 0, out.stderr
    rows = json.loads(out.stdout)
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    ref = slide(acc, dt, [0.05, 0.2], [0.1, 0.25])
    assert [r["mu_k"] for r in rows] == [0.05, 0.2]
    for key in ("mu_k", "mu_s", "peak_slide", "residual_slide", "peak_abs_accel"):
        assert key in rows[0]
    np.testing.assert_allclose([r["peak_slide"] for r in rows], ref.peak_slide, rtol=1e-12)


def test_slide_scale_pga_and_direction():
    out = run(
        "slide", RECORD, "--mu", "0.1", "--scale-pga", "0.6", "--direction", "positive", "--json"
    )
    assert out.returncode == 0, out.stderr
    row = json.loads(out.stdout)[0]
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    acc = acc * (0.6 * 9.80665 / np.abs(acc).max())
    ref = slide(acc, dt, 0.1, direction="positive")
    assert row["peak_slide"] == pytest.approx(ref.peak_slide[0], rel=1e-12)
    assert row["residual_slide"] <= 0


def test_spectrum_json_keys_and_values():
    out = run("spectrum", RECORD, "--periods", "0,0.2,1", "--damping", "0.02,0.05", "--json")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    for key in ("periods", "damping", "psa", "sa", "sv", "sd"):
        assert key in data
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    ref = response_spectrum(acc, dt, [0, 0.2, 1], [0.02, 0.05])
    np.testing.assert_allclose(data["psa"], ref.psa, rtol=1e-12)
    assert data["periods"] == [0.0, 0.2, 1.0]


def test_spectrum_log_spaced_periods_text_output():
    out = run("spectrum", RECORD, "--periods", "0.1:2:5")
    assert out.returncode == 0, out.stderr
    assert "PSA (g)" in out.stdout and len(out.stdout.splitlines()) == 1 + 1 + 1 + 5


@pytest.mark.parametrize(
    ("args", "code", "text"),
    [
        (("slide", RECORD, "--mu", "abc"), 2, "--mu"),
        (("slide", RECORD), 2, "--mu"),
        (("slide", "missing.AT2", "--mu", "0.1"), 3, "missing.AT2"),
        (("slide", RECORD, "--mu", "-0.1"), 2, "mu_k"),
        (("spectrum", RECORD, "--periods", "1:0.5:3"), 2, "periods"),
        (("spectrum", RECORD, "--damping", "1.5"), 2, "damping"),
    ],
)
def test_user_mistakes_give_one_clear_line(args, code, text):
    out = run(*args)
    assert out.returncode == code
    assert "Traceback" not in out.stderr
    assert text in out.stderr
