"""Built-in data files (``results/data``) and the user files that replace them."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from rvcoax.errors import problems_text
from rvcoax.geometry.inputfiles import InputFileError, read_input_text

__all__ = ["MAX_DATA_FILE_BYTES", "read_data_text"]

MAX_DATA_FILE_BYTES = 10_000_000  # stage data, study files and force tables are a few kB


def read_data_text(path: str | Path | None, builtin: str, error: type[Exception], what: str) -> tuple[str, str]:
    """(source name, text) of ``path``, or of the built-in ``results/data/<builtin>`` when ``path`` is None.

    A file that cannot be read raises ``error(message)``, the message in the form of every input file's
    (:func:`rvcoax.errors.problems_text`).
    """
    if path is None:
        return f"<built-in {builtin}>", resources.files("rvcoax.results").joinpath("data", builtin).read_text(encoding="utf-8")
    try:
        return str(path), read_input_text(path, MAX_DATA_FILE_BYTES, f"a {what}" if what.endswith("file") else f"a {what} file")
    except InputFileError as reason:
        raise error(problems_text(what, str(path), [str(reason)])) from None
