"""Issue 14: the hysteresis loop of a building on nonlinear isolation kept with the history
record (isolator displacement and force / W at the samples), through the result file and back,
equal to the API; files written before it was kept still load."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from floorslide.building.nonlinear import isolator_response
from floorslide.run.store import ResultFile
from tests.format1 import to_format1
from tests.run.isolation_study import FPS, LRB, run_study


def run(tmp_path, isolator: str, n: int = 2):
    """Run the study with one building ``iso`` on `isolator`: (plan, result file)."""
    return run_study(tmp_path, {"iso": isolator}, n)


@pytest.mark.parametrize("isolator", [FPS, LRB])
def test_the_hysteresis_loop_round_trips_and_equals_the_api(tmp_path, isolator):
    p, out = run(tmp_path, isolator)
    tasks = {(t.meta["record"], t.meta["building"]): t for t in ResultFile(out).tasks()}
    rec = next(r for r in p.records if r.record == "rec1")
    model = next(b for b in p.scene.buildings if b.id == "iso").build()
    direct = isolator_response(model, rec.acc, rec.dt, floors=[0, 1])
    h = tasks[("rec1", "iso")].histories
    assert h is not None
    np.testing.assert_allclose(
        h.isolator_displacement, direct.isolator_displacement, rtol=1e-12, atol=0
    )
    np.testing.assert_allclose(
        h.isolator_force_ratio, direct.isolator_force / model.weight, rtol=1e-12, atol=0
    )
    assert h.isolator_displacement.shape == rec.acc.shape
    # the loop's extremes are those of the samples: at most the true peaks inside steps
    meta = tasks[("rec1", "iso")].meta
    assert np.abs(h.isolator_displacement).max() <= meta["isolator_peak_displacement"]
    assert np.abs(h.isolator_force_ratio).max() <= meta["isolator_peak_force_ratio"] * (1 + 1e-12)
    # the other record and the fixed-base building keep no loop
    assert tasks[("rec2", "iso")].histories is None
    fixed = tasks[("rec1", "fixed")].histories
    assert fixed.isolator_displacement is None and fixed.isolator_force_ratio is None
    with h5py.File(out, "r") as f:
        g = f[f"histories/{tasks[('rec1', 'iso')].task_id}"]
        assert g["isolator_displacement"].attrs["units"] == "m"
        assert g["isolator_force_ratio"].attrs["units"] == "1"
        other = f[f"histories/{tasks[('rec1', 'fixed')].task_id}"]
        assert "isolator_displacement" not in other


def test_the_isolator_parameters_are_task_attributes(tmp_path):
    p, out = run(tmp_path, FPS, n=1)
    t = next(t for t in ResultFile(out).tasks() if t.meta["building"] == "iso")
    model = next(b for b in p.scene.buildings if b.id == "iso").build()
    assert t.meta["isolator"] == "friction_pendulum"
    assert t.meta["isolator_mu"] == 0.04 and t.meta["isolator_mu_s"] == 0.04
    assert t.meta["isolator_radius"] == pytest.approx(model.isolator.R, rel=1e-15)
    assert t.meta["isolator_capacity"] == 0.05
    assert "isolator_q_ratio" not in t.meta


def test_a_file_without_the_loop_still_loads(tmp_path):
    """A result file written before the loop was kept (no isolator datasets in histories/)
    reads, with both histories None."""
    from floorslide.run.snapshot import digest, snapshot
    from floorslide.run.store import BOOKKEEPING

    _, out = run(tmp_path, FPS, n=1)
    to_format1(out)  # files before the loop were of format 1: one group per task
    tid = next(t.task_id for t in ResultFile(out).tasks() if t.meta["building"] == "iso")
    with h5py.File(out, "r+") as f:
        g = f[f"tasks/{tid}"]
        del g["histories/isolator_displacement"]
        del g["histories/isolator_force_ratio"]
        g.attrs["sha256"] = digest(snapshot(g), BOOKKEEPING)  # as an older writer signed it
    t = next(t for t in ResultFile(out).tasks() if t.task_id == tid)
    assert t.histories is not None and t.histories.floor_acceleration.shape[0] == 1
    assert t.histories.isolator_displacement is None and t.histories.isolator_force_ratio is None
