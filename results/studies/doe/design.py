"""An orthogonal design with its response, and reading one from CSV files.

A design file (CSV) has one row per run: an optional run column (``test`` or ``run``), one column
of level codes (1, 2, 3, …) per factor named by the factor's key (``A``), interaction columns named
``<key>x<key>`` with an optional ``_<n>`` suffix (``AxB_1``, ``AxB_2``: their sums of squares add up
to the interaction's), optional empty columns named ``e<n>`` (error), and one numeric response
column. A levels file has columns ``factor, name, unit, level_1, level_2, …`` (the level values).
Paper 001's ``l27_transmission_error.csv`` and ``l27_levels.csv`` are such files.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvcoax.errors import RvcoaxError, problems_text
from rvcoax.geometry.inputfiles import InputFileError, csv_rows, plain_number, read_input_text
from rvcoax.results.studies.doe.orthogonal import orthogonality_problems

__all__ = ["Design", "DesignError", "Factor", "MAX_TABLE_BYTES", "RUN_COLUMNS", "Source", "build_sources",
           "read_design", "read_levels"]

RUN_COLUMNS = ("test", "run")
_EMPTY = re.compile(r"^e\d*$")
MAX_TABLE_BYTES = 10_000_000  # a design or levels table has tens of rows


class DesignError(RvcoaxError, ValueError):
    """A design or levels file that cannot be analysed; the message names the file, line/column and reason."""


@dataclass(frozen=True)
class Factor:
    """A factor: its key (design column), name, unit and the value of each level (level 1 first)."""

    key: str
    name: str
    unit: str
    values: tuple[float, ...]


@dataclass(frozen=True)
class Source:
    """A source of variation: a factor, an interaction (several columns) or an empty column."""

    name: str
    columns: tuple[str, ...]
    kind: str  # "factor", "interaction" or "empty"
    factors: tuple[str, ...] = ()


@dataclass(frozen=True, eq=False)
class Design:
    """Level codes per column, the factors, the sources and the response of each run."""

    runs: tuple[str, ...]
    codes: dict[str, np.ndarray]
    factors: tuple[Factor, ...]
    sources: tuple[Source, ...]
    response: np.ndarray
    response_name: str

    def __post_init__(self) -> None:
        n = len(self.runs)
        if self.response.shape != (n,) or any(c.shape != (n,) for c in self.codes.values()):
            raise ValueError("every column needs one value per run")
        constant = [c for c, codes in self.codes.items() if np.unique(codes).size < 2]
        if constant:
            raise DesignError(f"{n} run(s), and column(s) {', '.join(constant)} use a single level: range analysis "
                              "and ANOVA compare levels, so every column needs at least two (an L9 has 9 runs)")
        problems = orthogonality_problems(np.column_stack(list(self.codes.values())), list(self.codes))
        if problems:
            raise DesignError("the design is not an orthogonal array (range analysis and ANOVA need one): "
                              + "; ".join(problems[:5]) + ("; …" if len(problems) > 5 else ""))

    @property
    def columns(self) -> tuple[str, ...]:
        return tuple(self.codes)

    def factor(self, key: str) -> Factor:
        return next(f for f in self.factors if f.key == key)

    def values(self) -> np.ndarray:
        """Level values of every factor in every run (runs × factors), e.g. for regression."""
        return np.column_stack([np.asarray(f.values)[self.codes[f.key] - 1] for f in self.factors])

def build_sources(factors: tuple[Factor, ...], columns: list[str]) -> tuple[Source, ...]:
    """Sources from column names: factor keys, ``<a>x<b>[_n]`` interactions and ``e<n>`` empty columns."""
    keys = [f.key for f in factors]
    sources: list[Source] = [Source(k, (k,), "factor") for k in keys if k in columns]
    interactions: dict[tuple[str, str], list[str]] = {}
    for column in columns:
        if column in keys:
            continue
        pair = next(((a, b) for a in keys for b in keys
                     if a != b and re.fullmatch(rf"{re.escape(a)}x{re.escape(b)}(_\d+)?", column)), None)
        if pair is not None:
            interactions.setdefault(pair, []).append(column)
        elif _EMPTY.match(column):
            sources.append(Source(column, (column,), "empty"))
    sources += [Source(f"{a}x{b}", tuple(cols), "interaction", (a, b)) for (a, b), cols in interactions.items()]
    return tuple(sources)


def _file_error(what: str, path: Path, problem: str) -> DesignError:
    """A design or levels file's problem in the one form of an input file's message (:func:`rvcoax.errors.problems_text`)."""
    return DesignError(problems_text(what, str(path), [problem]))


def _rows(path: Path, what: str) -> tuple[list[str], list[tuple[int, dict]]]:
    try:
        text = read_input_text(path, MAX_TABLE_BYTES, f"a {what}")
        numbered = [(line, cells) for line, cells in csv_rows(text, comment="#") if any(c.strip() for c in cells)]
    except InputFileError as error:
        raise _file_error(what, path, str(error)) from None
    if not numbered:
        raise _file_error(what, path, "empty")
    header = [h.strip() for h in numbered[0][1]]
    rows = []
    for number, values in numbered[1:]:
        if len(values) != len(header):
            raise _file_error(what, path, f"line {number}: {len(values)} values for {len(header)} columns")
        rows.append((number, dict(zip(header, (v.strip() for v in values)))))
    if not rows:
        raise _file_error(what, path, "no rows after the header")
    return header, rows


def _number(text: str, column: str) -> float:
    """``text`` as a plain number; a ValueError naming ``column`` and the reason when it is not one."""
    try:
        return plain_number(text)
    except ValueError as error:
        raise ValueError(f"column {column}: {error}") from None


def read_levels(path: str | Path) -> tuple[Factor, ...]:
    """Factors from a levels CSV (``factor, name, unit, level_1, level_2, …``).

    Parameters
    ----------
    path : str or Path
        The levels CSV.

    Returns
    -------
    tuple of Factor
        Key, name, unit and level values of each factor.

    Raises
    ------
    DesignError
        Naming the file, the line and the reason.
    """
    path = Path(path)
    header, rows = _rows(path, "levels file")
    level_columns = sorted((h for h in header if re.fullmatch(r"level_\d+", h)), key=lambda h: int(h[6:]))
    if "factor" not in header or not level_columns:
        raise _file_error("levels file", path, f"needs columns factor and level_1, level_2, … (got {', '.join(header)})")
    factors, seen = [], set()
    for number, row in rows:
        where = f"line {number}"
        key = row["factor"]
        if not re.fullmatch(r"[A-Za-z][A-Za-z0-9]*", key):
            raise _file_error("levels file", path, f"{where}: factor '{key}' must be a letter followed by letters or digits")
        if key in seen:
            raise _file_error("levels file", path, f"{where}: factor {key} is listed twice")
        seen.add(key)
        try:
            values = tuple(_number(row[c], c) for c in level_columns if row[c] != "")
        except ValueError as error:
            raise _file_error("levels file", path, f"{where}: {error}") from None
        if len(values) < 2 or len(set(values)) != len(values):
            raise _file_error("levels file", path, f"{where}: factor {key} needs at least two distinct level values")
        factors.append(Factor(key, row.get("name", key) or key, row.get("unit", ""), values))
    return tuple(factors)


def read_design(path: str | Path, factors: tuple[Factor, ...], response: str | None = None) -> Design:
    """A design CSV with the given factors; ``response`` names the response column if several could be.

    Parameters
    ----------
    path : str or Path
        The design CSV: one row per run, a column per factor (levels 1, 2, 3), empty or interaction
        columns, and the response.
    factors : tuple of Factor
        From :func:`read_levels`.
    response : str, optional
        The response column.

    Returns
    -------
    Design
        Runs, level codes, sources and the response.

    Raises
    ------
    DesignError
        Naming the file, the line or column and the reason.
    """
    path = Path(path)
    header, rows = _rows(path, "design file")
    keys = {f.key for f in factors}
    missing = [f.key for f in factors if f.key not in header]
    if missing:
        raise _file_error("design file", path, f"no column for factor(s) {', '.join(missing)} of the levels file")
    run_column = next((c for c in header if c.lower() in RUN_COLUMNS), None)
    sources = build_sources(factors, header)
    coded = [c for s in sources for c in s.columns]
    others = [c for c in header if c not in coded and c != run_column]
    if response is None:
        if len(others) != 1:
            raise _file_error("design file", path, f"cannot tell the response column among {', '.join(others) or 'none'}"
                              " (give --response NAME)")
        response = others[0]
    elif response not in others:
        raise _file_error("design file", path, f"no response column '{response}' (candidates: {', '.join(others)})")
    levels_of = {f.key: len(f.values) for f in factors}
    codes = {c: np.zeros(len(rows), dtype=int) for c in coded}
    y = np.zeros(len(rows))
    for i, (number, row) in enumerate(rows):
        where = f"line {number}"
        for column in coded:
            text = row[column]
            allowed = levels_of.get(column) or max(levels_of.get(k, 0) for k in keys)
            if not re.fullmatch(r"[0-9]+", text) or not 1 <= int(text) <= allowed:
                raise _file_error("design file", path, f"{where}: column {column}: level '{text}' is not one of 1 … {allowed}")
            codes[column][i] = int(text)
        try:
            y[i] = _number(row[response], response)
        except ValueError as error:
            raise _file_error("design file", path, f"{where}: {error}") from None
    runs = tuple(row[run_column] if run_column else str(i + 1) for i, (_, row) in enumerate(rows))
    try:
        return Design(runs=runs, codes=codes, factors=tuple(f for f in factors if f.key in keys), sources=sources,
                      response=y, response_name=response)
    except DesignError as error:
        raise _file_error("design file", path, str(error)) from None
