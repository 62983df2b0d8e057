"""Helpers shared by the text-based record formats (AT2, COSMOS, plain text).

Fast paths are vectorised (one ``str.split`` and one NumPy conversion for the whole body); only
when they fail is the text walked line by line, to say exactly where the problem is (line and
column, 1-based, as an editor shows them).
"""

from __future__ import annotations

import io
import os
import re
from collections.abc import Iterable
from pathlib import Path
from typing import IO, BinaryIO

import numpy as np

from floorslide.errors import RecordError
from floorslide.text_numbers import UNDERSCORE_HINT as _NO_UNDERSCORES
from floorslide.text_numbers import parse_count, parse_number

HEAD_BYTES = 8192
"""How much of a file the ``_is_<format>`` checks look at."""

BOM_UTF8 = b"\xef\xbb\xbf"
"""The UTF-8 byte-order mark some editors (Notepad, Excel) write first: skipped."""

_NON_SPACE = re.compile(rb"\S")

_TOKEN = re.compile(r"[^\s,]+")
# A Fortran fixed-width field that ran into its neighbour ("-.123E-02-.456E-02").
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?")


def read_head(filename: str | os.PathLike | IO[bytes], nbytes: int = HEAD_BYTES) -> str | None:
    """The first ``nbytes`` of a file as text, or None if it is unreadable or binary.

    Never raises: this is what the cheap ``_is_<format>`` checks use.
    """
    try:
        if hasattr(filename, "read"):
            position = filename.tell()
            raw = filename.read(nbytes)
            filename.seek(position)
        else:
            with open(filename, "rb") as fh:
                raw = fh.read(nbytes)
    except (OSError, TypeError, ValueError, AttributeError):
        return None
    if not isinstance(raw, bytes):
        return None
    raw = raw.removeprefix(BOM_UTF8)
    if not raw or looks_binary(raw):
        return None
    return raw.decode("latin-1")


def looks_binary(raw: bytes) -> bool:
    """True if a chunk of bytes is not plain text (NUL bytes or many control characters)."""
    if b"\x00" in raw:
        return True
    control = sum(raw.count(bytes([c])) for c in range(32) if c not in (9, 10, 12, 13))
    return control > 0.01 * len(raw)


def read_bytes(filename: str | os.PathLike) -> tuple[bytes, int]:
    """The whole file as bytes and the offset of its text (3 after a UTF-8 byte-order mark, else
    0), with a RecordError for a missing, empty, binary or UTF-16 file. A file whose lines end
    in a bare carriage return (classic Mac OS) comes back with line feeds."""
    path = Path(filename)
    where = str(path)
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise RecordError("no such file", where=where) from None
    except IsADirectoryError:
        raise RecordError("is a directory, not a record file", where=where) from None
    except OSError as exc:
        raise RecordError(f"cannot read file: {exc.strerror or exc}", where=where) from None
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise RecordError(
            "UTF-16 text; floorslide reads ASCII or UTF-8 text: save the file as UTF-8",
            where=where,
        )
    offset = len(BOM_UTF8) if raw.startswith(BOM_UTF8) else 0
    if _NON_SPACE.search(raw, offset) is None:
        raise RecordError("empty file", where=where)
    if looks_binary(raw[offset : offset + HEAD_BYTES]):
        raise RecordError("binary data, not a text record", where=where)
    if b"\n" not in raw and b"\r" in raw:
        raw = raw.replace(b"\r", b"\n")
    return raw, offset


def open_text(filename: str | os.PathLike) -> tuple[BinaryIO, int]:
    """The file opened for reading bytes, and the offset of its text (3 after a UTF-8
    byte-order mark, else 0), positioned there; a RecordError for a missing, binary or UTF-16
    file.

    Only the first kilobytes are read here, so that a large record is parsed block by block
    rather than held whole in memory (docs/design.md §8). A file whose lines end in a bare
    carriage return (classic Mac OS) comes back as an in-memory copy with line feeds, so that
    lines are always separated by ``\\n``. The caller closes the file.
    """
    path = Path(filename)
    where = str(path)
    try:
        fh: BinaryIO = open(path, "rb")
    except FileNotFoundError:
        raise RecordError("no such file", where=where) from None
    except IsADirectoryError:
        raise RecordError("is a directory, not a record file", where=where) from None
    except OSError as exc:
        raise RecordError(f"cannot read file: {exc.strerror or exc}", where=where) from None
    try:
        head = fh.read(HEAD_BYTES)
        if head.startswith((b"\xff\xfe", b"\xfe\xff")):
            raise RecordError(
                "UTF-16 text; floorslide reads ASCII or UTF-8 text: save the file as UTF-8",
                where=where,
            )
        offset = len(BOM_UTF8) if head.startswith(BOM_UTF8) else 0
        if looks_binary(head[offset:]):
            raise RecordError("binary data, not a text record", where=where)
        if b"\n" not in head and b"\r" in head:
            fh.seek(0)
            raw = fh.read()
            if b"\n" not in raw:
                fh.close()
                fh = io.BytesIO(raw.replace(b"\r", b"\n"))
        fh.seek(offset)
    except OSError as exc:
        fh.close()
        raise RecordError(f"cannot read file: {exc.strerror or exc}", where=where) from None
    except RecordError:
        fh.close()
        raise
    return fh, offset


def decode(raw: bytes) -> str:
    """Text of some bytes of a record file: UTF-8, else Latin-1 (which decodes anything)."""
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def read_text(filename: str | os.PathLike) -> str:
    """The whole file as text (without a UTF-8 byte-order mark), with a RecordError for a
    missing, empty, binary or UTF-16 file."""
    raw, offset = read_bytes(filename)
    return decode(raw[offset:])


UNDERSCORE_HINT = f"{_NO_UNDERSCORES} in a record"
"""Why a number such as ``1_000`` is refused: Python's ``float`` reads it as 1000, but no
record format writes digits that way, so it is damage or a typo."""


def parse_floats(
    lines: list[str], first_line: int, where: str, what: str = "a number", commas: bool = True
) -> np.ndarray:
    """All whitespace (and, with `commas`, comma) separated numbers of ``lines`` as one array.

    Formats whose data blocks are whitespace-separated (AT2, COSMOS) pass ``commas=False``: a
    comma there is damage, not a separator (``.349E-01`` → ``,349E-01`` would otherwise read as
    a different number).

    Parameters
    ----------
    lines
        The text lines holding the numbers.
    first_line
        1-based line number of ``lines[0]`` in the file (for messages).
    where
        The file, for messages.
    what
        What each token should be, for messages.

    Raises
    ------
    RecordError
        At the first token that is not a number, giving its line and column.
    """
    if not commas:
        for offset, line in enumerate(lines):
            col = line.find(",")
            if col >= 0:
                raise RecordError(
                    f"line {first_line + offset}, column {col + 1}: ',' in a whitespace-separated "
                    f"data block",
                    where=where,
                )
    body = " ".join(lines).replace(",", " ")
    if "_" not in body:
        try:
            return np.array(body.split(), dtype=np.float64)
        except ValueError:
            pass
    values: list[float] = []
    for offset, line in enumerate(lines):
        for match in _TOKEN.finditer(line):
            token = match.group()
            if "_" not in token:
                try:
                    values.append(float(token))
                    continue
                except ValueError:
                    pass
            parts = _NUMBER.findall(token)
            if parts and "".join(parts) == token:  # run-together fixed-width fields
                values.extend(float(p.replace("d", "e").replace("D", "E")) for p in parts)
                continue
            hint = f" ({UNDERSCORE_HINT})" if "_" in token else ""
            raise RecordError(
                f"line {first_line + offset}, column {match.start() + 1}: "
                f"{token[:40]!r} is not {what}{hint}",
                where=where,
            )
    return np.array(values, dtype=np.float64)


def parse_fixed_width(
    lines: list[str], width: int, per_line: int, count: int, first_line: int, where: str
) -> np.ndarray:
    """``count`` numbers in Fortran fixed-width fields (``per_line`` fields of ``width`` chars).

    Used when whitespace splitting does not give the right count (fields that touch, e.g.
    ``-0.12345-0.23456`` in ``(8F8.5)``).
    """
    padded = [line.rstrip("\r\n").ljust(width * per_line)[: width * per_line] for line in lines]
    fields = np.array(
        [line[i : i + width] for line in padded for i in range(0, width * per_line, width)]
    )[:count]
    try:
        values = np.char.replace(np.char.upper(fields), "D", "E").astype(np.float64)
    except ValueError:
        values = None
    if values is None or values.size < count or any("_" in field for field in fields):
        for index, field in enumerate(fields):
            try:
                if "_" in field:
                    raise ValueError(UNDERSCORE_HINT)
                float(field.replace("D", "E").replace("d", "e"))
            except ValueError:
                line, col = divmod(index, per_line)
                raise RecordError(
                    f"line {first_line + line}, column {col * width + 1}: "
                    f"{field.strip()[:40]!r} is not a number"
                    + (f" ({UNDERSCORE_HINT})" if "_" in field else ""),
                    where=where,
                ) from None
        raise RecordError(f"expected {count} values, found {fields.size}", where=where)
    return values


def locate_token(lines: Iterable[str], first_line: int, index: int) -> tuple[int, int, str]:
    """Line, column (1-based) and text of the ``index``-th number token in ``lines``."""
    seen = 0
    for offset, line in enumerate(lines):
        tokens = list(_TOKEN.finditer(line))
        if seen + len(tokens) > index:
            match = tokens[index - seen]
            return first_line + offset, match.start() + 1, match.group()
        seen += len(tokens)
    return first_line, 1, "?"


def check_finite(values: np.ndarray, where: str, locate=None) -> None:
    """RecordError at the first NaN or infinite sample.

    ``locate(index)`` may return ``(line, column, text)`` of that sample for the message.
    """
    bad = ~np.isfinite(values)
    if not bad.any():
        return
    index = int(np.argmax(bad))
    kind = "NaN" if np.isnan(values[index]) else "infinite"
    place = f"sample {index + 1}"
    if locate is not None:
        line, col, _ = locate(index)
        place = f"line {line}, column {col} (sample {index + 1})"
    raise RecordError(
        f"{place}: {kind} value; a record must hold finite numbers "
        f"({int(bad.sum())} non-finite sample(s) in all)",
        where=where,
    )


def parse_float_field(text: str, name: str, where: str) -> float:
    """A header value as float (a Fortran ``D`` exponent read as ``E``), with a RecordError
    naming the field (:func:`floorslide.text_numbers.parse_number`)."""
    try:
        return parse_number(text.replace("D", "E").replace("d", "e"))
    except ValueError:
        hint = f" ({UNDERSCORE_HINT})" if "_" in text else ""
        raise RecordError(f"{name} {text!r} is not a number{hint}", where=where) from None


def parse_count_field(text: str, name: str, where: str) -> int:
    """A header count (of samples, values, lines) ≥ 0: a whole number in any spelling —
    ``2000``, ``2000.``, ``2.0E+03`` (:func:`floorslide.text_numbers.parse_count`) — with a
    RecordError naming the field."""
    parse_float_field(text, name, where)  # not a number: that error
    try:
        count = parse_count(text.replace("D", "E").replace("d", "e"))
    except ValueError:
        count = -1
    if count < 0:
        raise RecordError(f"{name} {text!r} is not a whole number ≥ 0", where=where)
    return count


def count_mismatch(said: str, count: int, found: int, where: str) -> RecordError:
    """The error for a count the file states (``said`` + `count`, e.g. ``the header says
    NPTS=`` 2000) that disagrees with the `found` values it holds (docs/design.md §9): a
    truncated file, or header and data that disagree; both numbers named."""
    if found < count:
        return RecordError(
            f"truncated: {said}{count} but the file holds only {found} values", where=where
        )
    return RecordError(
        f"{said}{count} but the file holds {found} values; header and data disagree", where=where
    )
