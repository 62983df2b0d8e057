"""Writing files: the one function through which floorslide writes every file it makes.

Result files, journal entries, design tables, figures, reports and the benchmark's outputs all
go through :func:`write_output`, which keeps four promises (docs/design.md §9):

- **Atomic.** The bytes go to a temporary file created exclusively (``O_CREAT | O_EXCL |
  O_NOFOLLOW``, a random name) in the target's folder, are flushed to disk (``fsync``) and
  renamed over the target: a reader sees the old file or the new one, never a part; a failure
  (a full disk) removes the temporary file and leaves the target as it was. A symbolic link
  planted where a temporary file would go is never written through.
- **Only regular files are replaced.** A symbolic link, folder, device node, pipe or socket at
  the target is refused, whatever the caller allows.
- **Only what may be replaced is replaced.** An existing regular file is replaced when the
  caller says any file may be (``--overwrite``), or when it is recognisably a file floorslide
  wrote of the same kind (:func:`floorslide_png`, :func:`same_first_line`, ...); anything else
  is refused with a one-line error naming it.
- **Never an input.** A target that is the same file as one of the command's inputs (the
  result file a report is made from) is refused, whatever the caller allows.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
from collections.abc import Callable, Iterable
from pathlib import Path

from floorslide.errors import OutputError, OutputExistsError

HEAD_BYTES = 1 << 16
"""Bytes of an existing file that a replace rule looks at."""

Replace = bool | Callable[[bytes], bool]
"""Whether an existing regular file may be replaced: ``True`` (any), ``False`` (none), or a
rule called with the existing file's first :data:`HEAD_BYTES` bytes."""

PNG_SOFTWARE = "floorslide"
"""The ``Software`` text of every PNG floorslide draws (constant: the same figure gives the
same bytes), by which a figure of an earlier run is recognised."""

_UMASK = os.umask(0o022)
os.umask(_UMASK)


def no_space(exc: BaseException) -> bool:
    """Whether `exc` says the disk (or the user's quota) is full."""
    code = getattr(exc, "errno", None)
    text = str(exc)
    return (
        code in (errno.ENOSPC, errno.EDQUOT)
        or "errno = 28," in text
        or "No space left on device" in text
    )


def _kind(mode: int) -> str | None:
    """What a non-regular file is, in words (None for a regular file)."""
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISLNK(mode):
        return "a symbolic link"
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISFIFO(mode):
        return "a pipe"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def head(path: str | Path, n: int = HEAD_BYTES) -> bytes:
    """The first `n` bytes of the file `path` (b"" when it cannot be read)."""
    try:
        with open(path, "rb") as fh:
            return fh.read(n)
    except OSError:
        return b""


def same_input(path: str | Path, inputs: Iterable[str | Path]) -> bool:
    """Whether `path` is the same file (device and inode, through links) as one of `inputs`."""
    try:
        st = os.stat(path)
    except OSError:
        return False
    for other in inputs:
        try:
            o = os.stat(other)
        except OSError:
            continue
        if (st.st_dev, st.st_ino) == (o.st_dev, o.st_ino):
            return True
    return False


def check_target(
    path: str | Path,
    *,
    inputs: Iterable[str | Path] = (),
    replace: Replace = False,
    advice: str = "choose another output, or move the file away",
) -> bool:
    """Whether `path` may be written: True when it exists and may be replaced, False when it
    does not exist.

    Parameters
    ----------
    path
        The file to write.
    inputs
        Files the command reads: never replaced.
    replace
        Which existing regular file may be replaced (:data:`Replace`).
    advice
        What the user can do instead, said after a refusal.

    Raises
    ------
    OutputExistsError
        `path` is an input, not a regular file, or a regular file that may not be replaced
        (exit code 2): one line naming it; nothing is written.
    """
    path = Path(path)
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return False
    except OSError as exc:
        raise OutputExistsError(f"cannot be checked: {exc.strerror}", str(path)) from None
    if same_input(path, inputs):
        raise OutputExistsError(f"is an input of this command; not replaced ({advice})", str(path))
    kind = _kind(st.st_mode)
    if kind is not None:
        raise OutputExistsError(
            f"is {kind}; not replaced: floorslide writes regular files only ({advice})",
            str(path),
        )
    if replace is True or (callable(replace) and replace(head(path))):
        return True
    raise OutputExistsError(
        f"exists and is not a file floorslide wrote of this kind; not replaced ({advice})",
        str(path),
    )


def _fsync_dir(folder: Path) -> None:
    with contextlib.suppress(OSError):
        fd = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def temporary(path: str | Path) -> tuple[int, Path]:
    """A new, empty temporary file beside `path`, created exclusively (no link followed), with
    the mode a new file gets (0666 less the umask): its open descriptor and path.

    Raises
    ------
    OSError
        The folder cannot be written.
    """
    path = Path(path)
    fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.fchmod(fd, 0o666 & ~_UMASK)
    except OSError:
        os.close(fd)
        with contextlib.suppress(OSError):
            os.unlink(name)
        raise
    return fd, Path(name)


def replace_atomically(tmp: str | Path, path: str | Path) -> None:
    """Rename the finished temporary file `tmp` over `path` and make the rename durable."""
    os.replace(tmp, path)
    _fsync_dir(Path(path).parent)


def write_atomically(path: str | Path, data: bytes) -> None:
    """Write `data` as the file `path`: a temporary file (:func:`temporary`), ``fsync``,
    rename. No check of what is at `path` (:func:`write_output` does that).

    Raises
    ------
    OSError
        Cannot be written (a full disk): the temporary file is removed, `path` left as it was.
    """
    fd, tmp = temporary(path)
    try:
        try:
            view = memoryview(data)
            while view:
                view = view[os.write(fd, view) :]
            os.fsync(fd)
        finally:
            os.close(fd)
        replace_atomically(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


def write_output(
    path: str | Path,
    data: bytes | str,
    *,
    inputs: Iterable[str | Path] = (),
    replace: Replace = False,
    advice: str = "choose another output, or move the file away",
    what: str = "",
) -> Path:
    """Write `data` as the file `path`, atomically, refusing what may not be replaced.

    Parameters
    ----------
    path
        The file to write (its folder is created).
    data
        The file's bytes (text is written as UTF-8).
    inputs, replace, advice
        As for :func:`check_target`.
    what
        What the file is, for the error message (``"the report"``).

    Returns
    -------
    Path
        `path`.

    Raises
    ------
    OutputExistsError
        What is at `path` may not be replaced (exit code 2).
    OutputError
        It cannot be written (a full disk, an unwritable folder): one line; `path` is left as
        it was.
    """
    path = Path(path)
    inputs = list(inputs)
    check_target(path, inputs=inputs, replace=replace, advice=advice)
    if isinstance(data, str):
        data = data.encode("utf-8")
    label = f"cannot write {what}" if what else "cannot write"
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        write_atomically(path, data)
    except OSError as exc:
        if no_space(exc):
            raise OutputError(
                f"no space left on device; {what or 'the file'} is not written (an earlier "
                "version, if any, is left as it was)",
                str(path),
            ) from None
        raise OutputError(f"{label}: {exc.strerror or exc}", str(path)) from None
    return path


# --- rules: files floorslide wrote ---------------------------------------------------------


def floorslide_png(existing: bytes) -> bool:
    """Whether a file's first bytes are those of a figure floorslide drew (a PNG whose
    ``Software`` text, written before the image data, is :data:`PNG_SOFTWARE`)."""
    marker = b"tEXtSoftware\x00" + PNG_SOFTWARE.encode()
    return existing.startswith(b"\x89PNG\r\n\x1a\n") and marker in existing[:4096]


def starts_with(prefix: bytes) -> Callable[[bytes], bool]:
    """A rule: files that begin with `prefix`."""
    return lambda existing: existing.startswith(prefix)


def contains(marker: bytes, within: int = 4096) -> Callable[[bytes], bool]:
    """A rule: files whose first `within` bytes hold `marker`."""
    return lambda existing: marker in existing[:within]


def _first_line(data: bytes) -> bytes | None:
    """The first line that is not a ``#`` comment (a CSV's header), None for none."""
    for line in data.splitlines():
        if line and not line.startswith(b"#"):
            return line.rstrip(b"\r")
    return None


def same_first_line(new: bytes | str) -> Callable[[bytes], bool]:
    """A rule for CSV files: an existing file whose first line that is not a ``#`` comment
    (its header) is that of `new` — the same table, written before."""
    mine = _first_line(new.encode("utf-8") if isinstance(new, str) else new)
    return lambda existing: mine is not None and _first_line(existing) == mine
