"""Every file floorslide writes goes through one function (floorslide.outputs.write_output):
atomic (an exclusive temporary file in the same folder, no link followed, a rename), replacing
only a regular file floorslide wrote of the same kind (or any regular file with --overwrite),
never the command's input, never a link, folder or device."""

from __future__ import annotations

import errno
import os
import shutil
import stat

import pytest

from floorslide import outputs
from floorslide.errors import OutputError, OutputExistsError
from floorslide.run.store import journal_dir
from tests.robustness.conftest import cli


def run(scene, out, *args: str):
    return cli("run", str(scene), "-o", str(out), "--workers", "1", *args)


@pytest.fixture()
def study(reference_file, tmp_path):
    """A finished study of its own (a copy of the reference run)."""
    path = tmp_path / "res.h5"
    shutil.copyfile(reference_file, path)
    return path


# --- the function itself -------------------------------------------------------------------


def test_write_output_is_atomic_and_leaves_no_temporary(tmp_path):
    path = tmp_path / "a" / "t.md"
    outputs.write_output(path, "# Design tables: x\n", replace=False)
    assert path.read_text() == "# Design tables: x\n"
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~outputs._UMASK
    rule = outputs.starts_with(b"# Design tables: ")
    outputs.write_output(path, "# Design tables: y\n", replace=rule)
    assert path.read_text() == "# Design tables: y\n"
    assert sorted(p.name for p in path.parent.iterdir()) == ["t.md"]


def test_a_failed_write_leaves_the_old_file_whole(tmp_path, monkeypatch):
    """A full disk in the middle of a write: the old file is untouched (not a 0-byte or
    truncated file), no temporary file is left, one line says so."""
    path = tmp_path / "fig.png"
    outputs.write_output(path, b"\x89PNG\r\n\x1a\n" + b"tEXtSoftware\x00floorslide" + b"x" * 99)
    before = path.read_bytes()
    real = os.write

    def full(fd, data):
        real(fd, bytes(data)[:10])
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "write", full)
    with pytest.raises(OutputError) as err:
        outputs.write_output(path, b"\x89PNG new figure" * 1000, replace=outputs.floorslide_png)
    monkeypatch.undo()
    assert "no space left on device" in str(err.value) and "\n" not in str(err.value)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["fig.png"]


@pytest.mark.parametrize("replace", [True, False, outputs.floorslide_png])
def test_links_folders_and_devices_are_never_replaced(tmp_path, replace):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    link = tmp_path / "link.png"
    link.symlink_to(victim)
    folder = tmp_path / "folder.png"
    folder.mkdir()
    for target, kind in ((link, "a symbolic link"), (folder, "a folder")):
        with pytest.raises(OutputExistsError, match=f"is {kind}; not replaced"):
            outputs.write_output(target, b"data", replace=replace)
    with pytest.raises(OutputExistsError, match="is a device; not replaced"):
        outputs.check_target("/dev/null", replace=replace)
    assert victim.read_text() == "precious" and link.is_symlink() and folder.is_dir()


def test_the_input_is_never_replaced(tmp_path):
    source = tmp_path / "res.h5"
    source.write_bytes(b"results")
    alias = tmp_path / "alias.h5"
    os.link(source, alias)
    for target in (source, alias):
        with pytest.raises(OutputExistsError, match="is an input of this command"):
            outputs.write_output(target, b"report", inputs=[source], replace=True)
    assert source.read_bytes() == b"results"


def test_a_file_floorslide_did_not_write_is_refused(tmp_path):
    notes = tmp_path / "notes.md"
    notes.write_text("my notes\n")
    rule = outputs.starts_with(b"# Design tables: ")
    with pytest.raises(OutputExistsError, match="not a file floorslide wrote of this kind"):
        outputs.write_output(notes, "# Design tables: x\n", replace=rule)
    assert notes.read_text() == "my notes\n"


def test_same_first_line_recognises_the_same_table(tmp_path):
    rule = outputs.same_first_line("# INCOMPLETE: x\nset,building\n1,2\n")
    assert rule(b"set,building\n3,4\n")
    assert rule(b"# a note\nset,building\n")
    assert not rule(b"name,phone\n")
    assert not rule(b"")


def test_a_planted_temporary_link_is_not_written_through(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    out = tmp_path / "r.md"
    for name in ("r.md.tmp", ".r.md.tmp"):
        (tmp_path / name).symlink_to(victim)
    outputs.write_output(out, "text")
    assert victim.read_text() == "precious" and out.read_text() == "text"


# --- the commands ------------------------------------------------------------------------


@pytest.mark.parametrize("command", ["report", "table"])
def test_report_and_table_refuse_their_own_input(study, command):
    before = study.read_bytes()
    done = cli(command, str(study), "-o", str(study))
    assert done.returncode == 2, done.stderr
    (line,) = done.stderr.strip().splitlines()
    assert line.startswith(f"floorslide: error: {study}: is an input of this command")
    assert study.read_bytes() == before


def test_table_and_report_replace_their_own_output_but_not_a_users_file(study, tmp_path):
    md = tmp_path / "tables.md"
    assert cli("table", str(study), "-o", str(md)).returncode == 0
    first = md.read_text()
    assert first.startswith("# Design tables: ")
    again = cli("table", str(study), "-o", str(md))
    assert again.returncode == 0, again.stderr
    assert md.read_text() == first
    notes = tmp_path / "notes.md"
    notes.write_text("field notes\n")
    done = cli("table", str(study), "-o", str(notes))
    assert done.returncode == 2 and "not a file floorslide wrote" in done.stderr
    assert notes.read_text() == "field notes\n"
    html = tmp_path / "r.html"
    html.write_text("<html>someone's page</html>")
    done = cli("report", str(study), "-o", str(html))
    assert done.returncode == 2 and "not a file floorslide wrote" in done.stderr
    assert html.read_text() == "<html>someone's page</html>"


@pytest.mark.slow
def test_plot_replaces_its_own_figures_but_not_other_pngs(study, tmp_path):
    folder = tmp_path / "figs"
    first = cli("plot", str(study), "-o", str(folder), "--workers", "1")
    assert first.returncode == 0, first.stderr
    pngs = sorted(folder.glob("*.png"))
    assert pngs and all(outputs.floorslide_png(outputs.head(p)) for p in pngs)
    again = cli("plot", str(study), "-o", str(folder), "--workers", "1")
    assert again.returncode == 0, again.stderr
    foreign = pngs[0]
    foreign.write_bytes(b"\x89PNG\r\n\x1a\n a photograph")
    done = cli("plot", str(study), "-o", str(folder), "--workers", "1")
    assert done.returncode == 2 and "not a file floorslide wrote" in done.stderr
    assert foreign.read_bytes() == b"\x89PNG\r\n\x1a\n a photograph"


def test_overwrite_never_replaces_a_device_or_folder(the_plan, tmp_path):
    done = run(the_plan.scene.path, "/dev/null", "--overwrite")
    assert done.returncode == 2, done.stderr
    (line,) = done.stderr.strip().splitlines()
    assert line.startswith("floorslide: error: /dev/null: is a device; not replaced")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    folder = tmp_path / "adir.h5"
    folder.mkdir()
    done = run(the_plan.scene.path, folder, "--overwrite")
    assert done.returncode == 2, done.stderr
    (line,) = done.stderr.strip().splitlines()
    assert line.startswith(f"floorslide: error: {folder}: is a folder; not replaced")
    assert "--resume" not in line and folder.is_dir()


def test_planted_links_at_temporary_names_are_not_written_through(the_plan, tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    out = tmp_path / "out.h5"
    (tmp_path / "out.h5.tmp").symlink_to(victim)
    folder = journal_dir(out)
    folder.mkdir()
    for tid in ("t00000", "t00001"):
        (folder / f"{tid}.entry.tmp").symlink_to(victim)
    done = run(the_plan.scene.path, out, "--resume")
    assert done.returncode == 0, done.stderr
    assert victim.read_text() == "precious"


def test_the_demo_does_not_write_into_a_folder_of_other_files(tmp_path):
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "thesis.tex").write_text("chapter 1")
    done = cli("demo", "-o", str(folder), "--workers", "1")
    assert done.returncode == 2, done.stderr
    (line,) = done.stderr.strip().splitlines()
    assert line.startswith(f"floorslide: error: {folder}: holds files and no demo result")
    assert sorted(p.name for p in folder.iterdir()) == ["thesis.tex"]
