"""An exact kernel that reaches its event limit inside a sub-step says so (SolverLimitError)
instead of returning a response that skipped the rest of the step (issue 20, item 1)."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
import floorslide.contents.oscillator as osc_mod
import floorslide.contents.sliding as sliding_mod
from floorslide.errors import SolverLimitError

G = 9.80665


def _pulses(n=200, dt=0.01):
    t = np.arange(n) * dt
    return 0.5 * G * np.sin(2 * np.pi * 2.0 * t), dt


def test_slide_reports_the_event_limit(monkeypatch):
    acc, dt = _pulses()
    fs.slide(acc, dt, 0.1)  # fine with the real limit
    monkeypatch.setattr(sliding_mod, "SLIDE_MAX_EVENTS", 1)
    with pytest.raises(SolverLimitError, match=r"more than 1 friction events .* t = "):
        fs.slide(acc, dt, 0.1)


def test_oscillator_reports_the_event_limit(monkeypatch):
    acc, dt = _pulses()
    fs.slide_oscillator(acc, dt, mu=0.1, frequency=5.0)
    monkeypatch.setattr(osc_mod, "OSCILLATOR_MAX_EVENTS", 1)
    with pytest.raises(SolverLimitError, match="slide_oscillator: more than 1"):
        fs.slide_oscillator(acc, dt, mu=0.1, frequency=5.0)


def test_the_cli_gives_one_line(monkeypatch, tmp_path, capsys):
    from floorslide.cli import main

    acc, dt = _pulses()
    path = tmp_path / "r.txt"
    np.savetxt(path, acc / G)
    monkeypatch.setattr(sliding_mod, "SLIDE_MAX_EVENTS", 1)
    argv = ["floorslide", "slide", str(path), "--dt", str(dt), "--units", "g", "--mu", "0.1"]
    monkeypatch.setattr("sys.argv", argv)
    with pytest.raises(SystemExit) as exit_:
        main()
    err = capsys.readouterr().err.strip().splitlines()
    assert exit_.value.code == 1
    # the synthetic pulse train is flagged by the quality checks (warnings); the error is one line
    errors = [line for line in err if not line.startswith("floorslide: warning:")]
    assert len(errors) == 1 and "friction events" in errors[0]
    assert errors[0].startswith("floorslide: error:")
