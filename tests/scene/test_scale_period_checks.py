"""A ``scale.period`` (or ``scale.periods``) whose spectra a record cannot have — above 10 000 s,
or below dt/1000 of the set's records — is a key-path error of the scene (exit 2, caught by
``--dry-run``), not an "unreadable record" for every record of the set (exit 3, an empty result
file)."""

from __future__ import annotations

import sys

import numpy as np
import pytest

SCENE = """
[[records]]
set = "s"
files = ["r*.txt"]
units = "g"
dt = 0.01
scale = {{ target = {{ sds = 1.0, sd1 = 0.6, tl = 8.0 }}, {scale} }}

[[buildings]]
id = "f"
kind = "fixed"
period = 0.3

[[contents]]
id = "c"
mu = [0.1]
"""


@pytest.mark.parametrize(
    ("scale", "expected"),
    [
        (
            "period = 1e5",
            "records[0].scale.period: the records' spectra would reach 200000 s (the fit range "
            "0.2·T–2·T), above 10000 s, beyond any structure",
        ),
        (
            "periods = [0.5, 2e4]",
            "records[0].scale.periods: the records' spectra would reach 20000 s, above 10000 s",
        ),
        (
            "period = 1e-9",
            "records[0].scale.period: the records' spectra would reach down to 2e-10 s (0.2·T), "
            "below dt/1000 = 1e-05 s of record ",
        ),
        (
            "periods = [1e-7, 1.0]",
            "records[0].scale.periods: the records' spectra would reach down to 1e-07 s, below",
        ),
        ("period = -1.0", "records[0].scale.period: must be > 0, got -1.0"),
    ],
)
def test_a_scale_period_no_spectrum_can_have_is_a_scene_error(tmp_path, monkeypatch, capsys,
                                                              scale, expected):  # fmt: skip
    from floorslide.cli import main

    t = np.arange(0.0, 5.0, 0.01)
    for k in range(2):
        np.savetxt(tmp_path / f"r{k}.txt", 0.3 * np.sin(2 * np.pi * (1 + k) * t))
    path = tmp_path / "scene.toml"
    path.write_text(SCENE.format(scale=scale))
    for extra in (["--dry-run"], ["-o", str(tmp_path / "o.h5")]):
        monkeypatch.setattr(sys, "argv", ["floorslide", "run", str(path), *extra])
        with pytest.raises(SystemExit) as exit_:
            main()
        err = capsys.readouterr().err
        assert exit_.value.code == 2, err
        assert len(err.strip().splitlines()) == 1 and "unreadable" not in err
        assert err.startswith(f"floorslide: error: {path}: {expected}"), err
    assert not (tmp_path / "o.h5").exists()
