"""What a run stores (issue 12): unbroadened and broadened spectra, each labelled; the 2-DOF
oscillator's spring deformation and top-mass acceleration, also in the histories; a result
file without the new datasets still reads."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from floorslide.contents.oscillator import slide_oscillator
from floorslide.run.execute import execute
from floorslide.run.store import ResultFile
from floorslide.scene.planner import plan
from floorslide.scene.schema import parse_scene
from floorslide.spectra.core import broaden, response_spectrum
from tests.conftest import ROOT
from tests.format1 import to_format1

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()
RECORD = "ImperialValley_1940_ELC-180"

SCENE = f"""
[[records]]
set = "one"
catalog = "{CATALOG}"
where = {{ station_id = "ELC-180" }}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.25
damping = 0.03

[[contents]]
id = "rack"
floors = [1]
model = "oscillator"
frequency = 6.0
damping = 0.02
mass_ratio = 0.5
mu = [0.05, 0.2]

[spectra]
floors = [1]
damping = [0.02, 0.05]
periods = [0.1, 0.2, 0.25, 0.3, 0.5, 1.0]
broadening = 0.15

[report]
history_record = "{RECORD}"
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The scene run once: (plan, path of the result file)."""
    path = tmp_path_factory.mktemp("outputs") / "r.h5"
    p = plan(parse_scene(SCENE, ROOT / "s.toml"))
    execute(p, str(path), workers=1, progress=False)
    return p, path


def test_unbroadened_and_broadened_spectra_are_both_stored(run):
    p, path = run
    rec = p.records[0]
    model = p.scene.buildings[0].build()
    periods = np.array(p.scene.spectra.periods)
    raw = response_spectrum(rec.acc, rec.dt, periods, [0.02, 0.05], building=model, floor=1)
    wide = broaden(raw, 0.15)
    (task,) = ResultFile(path).tasks()
    (s,) = task.spectra
    assert s.broadening == 0.15
    np.testing.assert_array_equal(s.psa, raw.psa)
    np.testing.assert_array_equal(s.sd, raw.sd)
    np.testing.assert_array_equal(s.psa_broadened, wide.psa)
    np.testing.assert_array_equal(s.sv_broadened, wide.sv)
    assert (s.psa_broadened >= s.psa).all() and (s.psa_broadened > s.psa).any()
    with h5py.File(path, "r") as f:  # format 2: the spectra table, one row per floor
        g = f["spectra"]
        assert g.attrs["rows"] == 1 and g["group"][0] == b"floor_1"
        assert g["broadening"][0] == 0.15
        assert g["psa"].attrs["broadening"] == 0.0 and g["psa"].attrs["units"] == "m/s**2"
        assert g["broadened.psa"].attrs["broadening"] == 0.15
        assert g["broadened.sd"].attrs["units"] == "m"
        np.testing.assert_array_equal(g["broadened.psa"][0], wide.psa)


def test_a_file_from_before_keeps_reading(run, tmp_path):
    """Without the labels (an older file), stored spectra of a scene with broadening are the
    broadened ones, and are read as such: the unbroadened ones are NaN (they were lost)."""
    _, path = run
    old = to_format1(path, tmp_path / "old.h5")  # an older file: one group per task
    with h5py.File(old, "a") as f:
        del f.attrs["task_digest"]  # an older file kept no digests either
        for task in f["tasks"].values():
            del task.attrs["sha256"]
            g = task["spectra"]["floor_1"]
            for name in ("psa", "sa", "sv", "sd"):
                data = g["broadened"][name][()]
                del g[name]
                g[name] = data
            del g["broadened"]
            del g.attrs["broadening"]
            h = task["histories"]["slides"]["rack"]["floor_1"]
            del h["z"], h["top_accel"]
    (new,) = ResultFile(path).tasks()
    (task,) = ResultFile(old).tasks()
    (s,) = task.spectra
    assert s.broadening == 0.15 and np.isnan(s.psa).all()
    np.testing.assert_array_equal(s.psa_broadened, new.spectra[0].psa_broadened)
    assert task.histories.deformation == {} and "rack/floor_1" in task.histories.slides


def test_oscillator_results_and_histories(run):
    p, path = run
    rec = p.records[0]
    model = p.scene.buildings[0].build()
    (task,) = ResultFile(path).tasks()
    (c,) = task.contents
    ref = slide_oscillator(
        rec.acc, rec.dt, [0.05, 0.2], 6.0, 0.02, 0.5, building=model, floor=1, histories=True
    )
    np.testing.assert_array_equal(c.peak_deformation, ref.peak_deformation)
    np.testing.assert_array_equal(c.peak_top_accel, ref.peak_top_accel)
    np.testing.assert_array_equal(c.peak_abs_accel, ref.peak_base_accel)
    h = task.histories
    key = "rack/floor_1"
    np.testing.assert_array_equal(h.mu_k[key], [0.05, 0.2])
    np.testing.assert_array_equal(h.slides[key], ref.u)
    np.testing.assert_array_equal(h.deformation[key], ref.z)
    np.testing.assert_array_equal(h.top_accel[key], ref.top_accel)
    with h5py.File(path, "r") as f:  # format 2: histories stay a group per task
        g = f["histories"][task.task_id]["slides"]["rack"]["floor_1"]
        assert g.attrs["model"] == "oscillator"
        assert g["z"].attrs["units"] == "m" and g["top_accel"].attrs["units"] == "m/s**2"
