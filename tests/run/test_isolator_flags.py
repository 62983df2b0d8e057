"""A run says where a nonlinear isolation layer went beyond what its model covers: beyond its
capacity, or — a friction pendulum without one — beyond 0.2·R, where the small-angle restoring
force (W/R)·u is more than 2 % off: a flag in the task, the per-record and ``isolators``
tables, and one warning line naming the record and the building."""

from __future__ import annotations

import pytest

from floorslide.report import design_tables, record_table
from floorslide.run.store import ResultFile
from tests.run.isolation_study import scene_text, write_records

# period 2.5 s: R = 1.5525 m, 0.2·R = 0.3105 m; the peaks are 0.332 m (rec1), 0.303 m, 0.269 m
ISOLATORS = {
    "fps": '{ model = "friction_pendulum", mu = 0.04 }',
    "fpscap": '{ model = "friction_pendulum", mu = 0.04, capacity = 0.32 }',
}


def test_flags_in_the_tasks_the_tables_and_one_warning_line(tmp_path, capsys):
    from floorslide.cli import run

    write_records(tmp_path, 3)
    (tmp_path / "scene.toml").write_text(scene_text(ISOLATORS))
    out = tmp_path / "out.h5"
    with pytest.raises(SystemExit) as exit_:
        run.main([str(tmp_path / "scene.toml"), "-o", str(out), "--workers", "1"],
                 standalone_mode=False)  # fmt: skip
        raise SystemExit(0)
    assert exit_.value.code in (0, None)
    warnings = [ln for ln in capsys.readouterr().err.splitlines() if "isolator displacement" in ln]
    assert len(warnings) == 2, warnings
    small, cap = sorted(warnings, key=lambda ln: "capacity 0.32" in ln)
    assert small.startswith("floorslide: warning: record rec1 (s) on building fps: ")
    assert "beyond 0.2·R = 0.3105 m" in small and "small-angle" in small
    assert cap.startswith("floorslide: warning: record rec1 (s) on building fpscap: ")
    assert "exceeds its capacity 0.32 m" in cap
    metas = {(t.meta["record"], t.meta["building"]): t.meta for t in ResultFile(out).tasks()}
    assert metas[("rec1", "fps")]["isolator_small_angle_exceeded"] == 1
    assert metas[("rec2", "fps")]["isolator_small_angle_exceeded"] == 0
    assert metas[("rec1", "fpscap")]["isolator_small_angle_exceeded"] == 0
    df = record_table(out).set_index(["record", "building"]).isolator_small_angle_exceeded
    assert bool(df[("rec1", "fps")]) is True
    assert not df[("rec2", "fps")] and not df[("rec1", "fpscap")]
    assert df[("rec1", "fixed")] != df[("rec1", "fixed")]  # NaN without nonlinear isolation
    rows = {r["building"]: r for r in design_tables(out)["isolators"]}
    assert rows["fps"]["n_small_angle_exceeded"] == 1
    assert "beyond 0.2·R under 1 of 3 records" in rows["fps"]["note"]
    assert rows["fpscap"]["n_small_angle_exceeded"] == 0
    assert rows["fpscap"]["n_capacity_exceeded"] == 1
