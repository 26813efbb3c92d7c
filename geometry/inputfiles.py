"""Checks made on an input file's path before a byte of it is read.

A rig file, a load-case file or a measured-data file that is not a regular file (``/dev/zero``, a
named pipe) would hang the reader or fill memory, and so would a file far larger than any real
one (an export of the wrong table, a disk image): both are refused with a message first.
"""

from __future__ import annotations

from pathlib import Path


class InputFileError(ValueError):
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
