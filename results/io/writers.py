"""Atomic writing of result files (temporary file in the same folder, then rename).

A reader never sees a half-written file, and a process killed while writing leaves at most a
hidden ``.name.*.tmp`` file next to the old one. Result files get the permissions an ordinary
``open()`` would give them (0666 less the umask, typically 0644), not mkstemp's 0600.
"""

from __future__ import annotations

import contextlib
import csv
import errno
import io
import json
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["csv_cell", "format_number", "naming_errors", "read_csv_cell", "write_csv_atomic", "write_json_atomic",
           "write_png_atomic", "write_text_atomic"]

FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r")
"""First characters that make a spreadsheet read a CSV cell as a formula (OWASP, "CSV Injection")."""


def _umask() -> int:
    """The process umask, read without changing it (Linux: /proc/self/status), else by setting it back."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def naming_errors(target: Path) -> Iterator[None]:
    """Re-raise an OSError as one naming ``target``, the result file being written, so that the user
    reads which file and why: a full disk's ENOSPC comes from ``write()`` without a file name, and a
    failed ``mkstemp`` names a hidden temporary file the user never asked for."""
    try:
        yield
    except OSError as error:
        if error.filename == str(target) and error.errno is not None:
            raise
        code = error.errno if error.errno is not None else errno.EIO
        reason = error.strerror or os.strerror(code)
        raise OSError(code, reason, str(target)) from error


def write_text_atomic(path: str | Path, text: str, durable: bool = True) -> Path:
    """Write ``text`` to ``path`` so that a reader never sees a half-written file.

    ``durable=False`` skips the fsync: still atomic, but after a power cut the file may be empty
    (for files that are checked when read again, such as Monte Carlo samples). An OSError names
    ``path`` (see :func:`naming_errors`).

    Parameters
    ----------
    path : str or Path
        The file; its folder is created if needed.
    text : str
        Written as UTF-8.
    durable : bool
        Fsync the file and its folder, so that it survives a power cut.

    Returns
    -------
    Path
        ``path``.
    """
    target = Path(path)
    with naming_errors(target):
        target.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
        try:
            os.fchmod(handle, 0o666 & ~_umask())
            with os.fdopen(handle, "w", encoding="utf-8", newline="") as stream:
                stream.write(text)
                stream.flush()
                if durable:
                    os.fsync(stream.fileno())
            os.replace(temporary, target)
        except BaseException:
            Path(temporary).unlink(missing_ok=True)
            raise
    return target


def format_number(value) -> str:
    """Fixed, round-trip float formatting (so equal inputs give byte-identical files)."""
    if isinstance(value, bool) or value is None:
        return str(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(float(f"{value:.10g}")) if value == value else "nan"
    return str(value)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def csv_cell(value) -> str:
    """One CSV cell: a number as :func:`format_number` writes it; text that a spreadsheet would run as a
    formula (a part, label or case name starting with ``=``, ``+``, ``-``, ``@``, a tab or a carriage
    return) with a ``'`` in front, as OWASP advises against CSV injection.

    Numbers are never escaped, nor is text that reads as one (``-0.5``, ``-inf``): they stay numbers. A
    lone ``-`` (a unit-less column's unit) is no formula and stays as it is. Text that starts with ``'``
    gets one more, so that :func:`read_csv_cell` gives every text back exactly.
    """
    text = format_number(value)
    if not isinstance(value, str) or text == "-":
        return text
    if text.startswith("'") or (text.startswith(FORMULA_STARTS) and not _is_number(text)):
        return "'" + text
    return text


def read_csv_cell(text: str) -> str:
    """The text :func:`csv_cell` was given (its ``'`` in front taken away): for readers of our own CSV files."""
    return text[1:] if text.startswith("'") else text


def write_csv_atomic(path: str | Path, rows: list[dict]) -> Path:
    """Write a list of dicts (same keys, in order) as CSV.

    Parameters
    ----------
    path : str or Path
        The file; its folder is created if needed.
    rows : list of dict
        The header is the first row's keys; each cell is written by :func:`csv_cell` (text that a
        spreadsheet would run as a formula is escaped).

    Returns
    -------
    Path
        ``path``.
    """
    buffer = io.StringIO()
    if rows:
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow([csv_cell(key) for key in rows[0]])
        for row in rows:
            writer.writerow([csv_cell(v) for v in row.values()])
    return write_text_atomic(path, buffer.getvalue())


def write_json_atomic(path: str | Path, data, durable: bool = True) -> Path:
    """Write ``data`` as indented UTF-8 JSON (numpy numbers as floats), atomically like :func:`write_text_atomic`.

    Parameters
    ----------
    path : str or Path
        The file; its folder is created if needed.
    data
        Anything :func:`json.dumps` takes, with numpy numbers.
    durable : bool
        Fsync before the rename (see :func:`write_text_atomic`).

    Returns
    -------
    Path
        ``path``.
    """
    return write_text_atomic(path, json.dumps(data, indent=2, sort_keys=False, ensure_ascii=False, default=float) + "\n",
                             durable)


def write_png_atomic(path: str | Path, figure, **options) -> Path:
    """Save a matplotlib ``figure`` as a PNG (white background unless ``options`` say otherwise), atomically.

    Every text of the figure is drawn as typed: titles and labels carry the user's names (a rig called
    ``$\\frac{x$`` or ``50 %``), which matplotlib would otherwise parse as mathtext and fail on.
    """
    from matplotlib.text import Text

    for text in figure.findobj(Text):
        text.set_parse_math(False)
    target = Path(path)
    with naming_errors(target):
        target.parent.mkdir(parents=True, exist_ok=True)
        temporary = target.with_name(f".{target.stem}.{os.getpid()}.tmp.png")
        try:
            figure.savefig(temporary, format="png", **{"facecolor": "white", **options})
            os.replace(temporary, target)
        finally:
            temporary.unlink(missing_ok=True)
    return target
