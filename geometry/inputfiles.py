"""Checks made on an input file's path before a byte of it is read.

A rig file, a load-case file or a measured-data file that is not a regular file (``/dev/zero``, a
named pipe) would hang the reader or fill memory, and so would a file far larger than any real
one (an export of the wrong table, a disk image): both are refused with a message first.
"""

from __future__ import annotations

import csv
import io
import math
import re
import tomllib
from collections.abc import Iterator
from pathlib import Path

from rvcoax.errors import RvcoaxError

__all__ = ["InputFileError", "check_readable_file", "csv_rows", "parse_toml", "plain_number", "read_input_text",
           "toml_error_text"]


class InputFileError(RvcoaxError, ValueError):
    """An input path that must not be read: not a regular file, or too large."""


def check_readable_file(path: str | Path, max_bytes: int, what: str) -> None:
    """Refuse a path that is not a regular file or is larger than ``max_bytes``, before reading it.

    Parameters
    ----------
    path : str or Path
    max_bytes : int
        Size limit in bytes.
    what : str
        What the file should be, for the message (``"a rig file"``).

    Raises
    ------
    InputFileError
        Not a regular file, or too large (the message says which and the limit).
    FileNotFoundError, IsADirectoryError, OSError
        As :func:`os.stat` and the reader would raise them, so that callers keep their messages.
    """
    target = Path(path)
    status = target.stat()
    if target.is_dir():
        raise IsADirectoryError(21, "Is a directory", str(path))
    if not target.is_file():
        raise InputFileError(f"is not a regular file (a device, pipe or socket cannot be {what})")
    if status.st_size > max_bytes:
        raise InputFileError(f"{status.st_size / 1e6:.1f} MB is too large for {what} (limit {max_bytes / 1e6:g} MB; "
                             "is this the right file?)")


def toml_error_text(error: Exception, text: str) -> str:
    """tomllib's message, with the line named also when it says only "at end of document"."""
    message = str(error)
    if "line" not in message:
        message += f" (the file ends at line {text.count(chr(10)) + 1}: is it cut short?)"
    return message


def read_input_text(path: str | Path, max_bytes: int, what: str) -> str:
    """The text of an input file, or :class:`InputFileError` with a message a user can act on.

    Checks the path first (:func:`check_readable_file`); decodes UTF-8 with or without a
    byte-order mark (spreadsheets and Windows editors write one) and names the line of the first
    byte that is not UTF-8.

    Parameters
    ----------
    path : str or Path
        The input file.
    max_bytes : int
        Larger files are refused before they are read.
    what : str
        What the file is, for the message (``"load-case file"``).

    Returns
    -------
    str
        The decoded text.
    """
    try:
        check_readable_file(path, max_bytes, what)
        raw = Path(path).read_bytes()
    except FileNotFoundError:
        raise InputFileError("file not found") from None
    except IsADirectoryError:
        raise InputFileError(f"cannot be read: it is a directory (a folder), not {what}") from None
    except OSError as error:
        raise InputFileError(f"cannot be read: {error.strerror}") from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        line = raw[: error.start].count(b"\n") + 1
        raise InputFileError(f"line {line}: is not UTF-8 text (byte {error.start}); save the file as UTF-8") from None


# ------------------------------------------------------------------------------ shared parsing of input text
# Every reader of user files (rig TOML, load cases, measured data, study files) parses through these three,
# so that a number, a line end or a nesting depth means the same thing in every file.

_PLAIN_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


def plain_number(text: str) -> float:
    """The value of a plain ASCII decimal number, or ValueError saying why ``text`` is not one.

    Accepted: ``70``, ``-1.5``, ``+.5``, ``6e-05``, ``1.43E+2`` (what spreadsheets, pandas, numpy and
    Python's ``repr`` write). Refused although :func:`float` takes them: digit separators (``1_00``),
    non-ASCII digits (Arabic-Indic ``٧٠``, full-width ``７０``), ``nan``/``inf``, hexadecimal and
    anything with a unit or a decimal comma.

    Parameters
    ----------
    text : str
        One cell or option value; surrounding spaces and tabs are ignored.

    Returns
    -------
    float
        A finite value (an exponent that overflows, ``1e999``, is refused too).
    """
    stripped = text.strip(" \t")
    if _PLAIN_NUMBER.fullmatch(stripped):
        value = float(stripped)
        if math.isfinite(value):
            return value
        raise ValueError(f"'{stripped}' is beyond the range of a floating-point number")
    lowered = stripped.lower().lstrip("+-")
    if lowered in ("nan", "inf", "infinity"):
        raise ValueError(f"'{stripped}' is not a finite number")
    if not stripped:
        raise ValueError("the value is empty")
    if not stripped.isascii():
        raise ValueError(f"'{stripped}' is not a plain number: it has characters that are not ASCII "
                         "(write the digits 0-9, '.', 'e')")
    if "_" in stripped:
        raise ValueError(f"'{stripped}' is not a plain number: '_' digit separators are not accepted")
    if "," in stripped:
        raise ValueError(f"'{stripped}' is not a plain number: write '.' as the decimal point")
    raise ValueError(f"'{stripped}' is not a number")


def csv_rows(text: str, comment: str | None = None) -> Iterator[tuple[int, list[str]]]:
    """The rows of CSV ``text`` as (line number, cells), with LF, CRLF or CR-only (old Mac) line ends.

    With ``comment`` (e.g. ``"#"``), lines that start with it (after blanks) are skipped before the CSV
    is read, so that a quote in a comment cannot open a field; line numbers stay those of the file.

    Parameters
    ----------
    text : str
        The file's text.
    comment : str, optional
        A prefix that marks comment lines.

    Returns
    -------
    iterator of (int, list of str)
        The 1-based line number where each row starts, and its cells as text.

    Raises
    ------
    InputFileError
        ``line N: ...`` where the csv module cannot read a row (a field over the csv module's
        131 072-character limit, a quote left open at the end of the file).
    """
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    if comment is not None:
        lines = ["" if line.lstrip().startswith(comment) else line for line in lines]
    reader = csv.reader(io.StringIO("\n".join(lines)), strict=True)
    while True:
        start = reader.line_num + 1  # the line where the row that fails begins (a quoted field may span lines)
        try:
            cells = next(reader)
        except StopIteration:
            return
        except csv.Error as error:
            hint = "; is a quote left open?" if "end of data" in str(error) else ""
            raise InputFileError(f"line {start}: cannot be read as CSV ({error}{hint})") from None
        yield reader.line_num, cells


def parse_toml(text: str) -> dict:
    """``tomllib.loads(text)``, with every failure as :class:`InputFileError` naming the line.

    Arrays or inline tables nested thousands deep make tomllib recurse until Python's stack limit;
    that is refused as a nesting error instead of a RecursionError.
    """
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise InputFileError(f"TOML syntax error: {toml_error_text(error, text)}") from None
    except RecursionError:
        depth_line = _deepest_line(text)
        raise InputFileError(f"line {depth_line}: arrays or inline tables are nested too deeply (no key of an "
                             "rvcoax input needs more than a few levels)") from None


def _deepest_line(text: str) -> int:
    """The line where bracket nesting (outside strings, roughly) is deepest: for the message only."""
    depth = best = 0
    best_line = line = 1
    for char in text:
        if char == "\n":
            line += 1
        elif char in "[{":
            depth += 1
            if depth > best:
                best, best_line = depth, line
        elif char in "]}":
            depth -= 1
    return best_line
