"""Torque load cases and how to read them.

A load case is a pair (T1 input torque, T2 output torque) in N·m. A rig's own cases come from its
file (``[[load_cases]]`` or a ``[sweep]`` range: :func:`rig_cases`); only the built-in reference
rig falls back on the 20 pairs of paper 000's coaxiality table (:func:`default_cases`). Files: CSV with columns ``T1_input_Nm, T2_output_Nm`` (other
columns ignored) or TOML with ``[[cases]] T1_input_Nm = .. T2_output_Nm = ..``.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from rvcoax.errors import InputFileProblems, RvcoaxError
from rvcoax.geometry.inputfiles import InputFileError, csv_rows, parse_toml, plain_number, read_input_text
from rvcoax.loadcases.limits import MAX_CASE_FILE_BYTES, MAX_TORQUE_NM

__all__ = ["LoadCase", "LoadCaseError", "NoLoadCasesError", "PAPER_TABLE", "default_cases", "default_is_paper", "rig_cases", "PublishedRow", "grid_cases", "paired_cases", "paper_cases",
           "paper_table", "read_cases", "separator_hint", "torque_matrix"]

PAPER_TABLE = "paper000_coaxiality_table.csv"


class LoadCaseError(InputFileProblems):
    """Load cases that cannot be used; the message (:func:`rvcoax.errors.problems_text`) names the source (a file,
    ``command line``, ``grid``), the line, case or key, and the reason."""

    what = "load cases"

    def __init__(self, source: str, problem: str):
        super().__init__(source, [problem])


@dataclass(frozen=True)
class LoadCase:
    """One torque pair (N·m)."""

    input_torque_Nm: float
    output_torque_Nm: float

    @property
    def label(self) -> str:
        return f"T1={self.input_torque_Nm:g}Nm_T2={self.output_torque_Nm:g}Nm"

    @property
    def text(self) -> str:
        """The case as tables, reports and warnings name it: ``"T1 = 0.5 N·m, T2 = 40 N·m"``."""
        return f"T1 = {self.input_torque_Nm:g} N·m, T2 = {self.output_torque_Nm:g} N·m"


def _validated(pairs: list[tuple[float, float]], source: str, where: list[str] | None = None) -> tuple[LoadCase, ...]:
    """Check finiteness, magnitude and uniqueness; ``where`` names each pair's place (default ``case i``)."""
    if not pairs:
        raise LoadCaseError(source, "no load cases")
    places = where if where is not None else [f"case {i}" for i in range(1, len(pairs) + 1)]
    seen: dict[tuple[float, float], str] = {}
    for place, (t1, t2) in zip(places, pairs):
        for name, value in (("T1_input_Nm", t1), ("T2_output_Nm", t2)):
            if not math.isfinite(value):
                raise LoadCaseError(source, f"{place}: {name} = {value} is not a finite number")
            if abs(value) > MAX_TORQUE_NM:
                raise LoadCaseError(source, f"{place}: {name} = {value:g} N·m is beyond any plausible rig torque "
                                    f"(|T| ≤ {MAX_TORQUE_NM:g} N·m)")
        if (t1, t2) in seen:
            raise LoadCaseError(source, f"{place}: duplicated load case T1 = {t1}, T2 = {t2} N·m "
                                f"(the same as {seen[(t1, t2)]})")
        seen[(t1, t2)] = place
    return tuple(LoadCase(float(a), float(b)) for a, b in pairs)


def paper_cases() -> tuple[LoadCase, ...]:
    """The 20 (T1, T2) pairs of paper 000's coaxiality table, in the table's order.

    Returns
    -------
    tuple of LoadCase
        Input torque T1 0.07 … 1.43 N·m paired with output torque T2 10 … 200 N·m.
    """
    text = resources.files("rvcoax.loadcases").joinpath("data", PAPER_TABLE).read_text(encoding="utf-8")
    return _read_csv_text(text, f"<built-in {PAPER_TABLE}>")


class NoLoadCasesError(RvcoaxError, ValueError):
    """A rig that names no load cases, asked for its default ones."""


NO_CASES_HELP = ("give them in the rig file ([[load_cases]] tables with T1_input_Nm and T2_output_Nm, or a "
                 "[sweep] range: T1_input_Nm = [first, last], T2_output_Nm = [first, last], cases = n), or on "
                 "the command line (--cases FILE, or --t1/--t2)")


def rig_cases(rig) -> tuple[LoadCase, ...] | None:
    """The load cases a rig file names (``[[load_cases]]`` or ``[sweep]``), or None when it names none.

    Parameters
    ----------
    rig : Rig
        A validated rig.

    Returns
    -------
    tuple of LoadCase or None
        In the file's order (a ``[sweep]`` gives evenly spaced pairs).
    """
    if rig.load_cases:
        return _validated([(c.T1_input_Nm, c.T2_output_Nm) for c in rig.load_cases], "of the rig file",
                          [f"load_cases[{i}]" for i in range(len(rig.load_cases))])
    if rig.sweep is not None:
        r = rig.sweep
        t1 = np.linspace(*r.T1_input_Nm, r.cases)
        t2 = np.linspace(*r.T2_output_Nm, r.cases)
        return _validated([(float(a), float(b)) for a, b in zip(t1, t2)], "of the rig file's [sweep]",
                          [f"sweep case {i}" for i in range(1, r.cases + 1)])
    return None


def default_cases(rig) -> tuple[LoadCase, ...]:
    """The cases to solve when none are given: the rig file's own, else paper 000's 20 pairs for the
    built-in reference rig only (:func:`rvcoax.geometry.builtin.is_reference_rig`).

    Parameters
    ----------
    rig : Rig
        The rig whose cases are wanted.

    Returns
    -------
    tuple of LoadCase
        Its own cases, or paper 000's for the reference rig.

    Raises
    ------
    NoLoadCasesError
        Another rig that names no load cases: the message says where to give them.
    """
    from rvcoax.geometry.builtin import is_reference_rig, reference_differences

    own = rig_cases(rig)
    if own is not None:
        return own
    if is_reference_rig(rig):
        return paper_cases()
    changes = reference_differences(rig, limit=COPY_CHANGES + 1)
    if len(changes) <= COPY_CHANGES:  # a copy of the reference rig with a value or two changed
        raise NoLoadCasesError(
            f"rig '{rig.rig.name}' names no load cases. It is a copy of the built-in reference rig but no longer "
            f"the reference rig itself ({'; '.join(changes)}), and paper 000's load cases belong to the reference "
            f"rig only: {NO_CASES_HELP}")
    raise NoLoadCasesError(f"rig '{rig.rig.name}' names no load cases (paper 000's table belongs to the built-in "
                           f"reference rig only): {NO_CASES_HELP}")


COPY_CHANGES = 3
"""A rig that differs from the built-in reference rig in at most this many values is told it is a copy of it."""


def default_is_paper(rig) -> bool:
    """True when :func:`default_cases` of ``rig`` are paper 000's (the reference rig naming no cases of its own).

    Parameters
    ----------
    rig : Rig
        The rig in question.

    Returns
    -------
    bool
        Whether the default cases are the paper's.
    """
    from rvcoax.geometry.builtin import is_reference_rig

    return rig_cases(rig) is None and is_reference_rig(rig)


def grid_cases(t1_values, t2_values) -> tuple[LoadCase, ...]:
    """Every combination of the given T1 and T2 values.

    Parameters
    ----------
    t1_values, t2_values : sequence of float
        Input and output torques in N·m.

    Returns
    -------
    tuple of LoadCase
        T1 varies slowest: ``(t1_values[0], t2_values[0]), (t1_values[0], t2_values[1]), …``.
    """
    return _validated([(float(a), float(b)) for a in t1_values for b in t2_values], "grid")


def paired_cases(t1_values, t2_values, source: str = "command line") -> tuple[LoadCase, ...]:
    """Cases from two equally long lists of T1 and T2, paired in order.

    Parameters
    ----------
    t1_values, t2_values : sequence of float
        Input and output torques in N·m.
    source : str
        What to call the lists in error messages.

    Returns
    -------
    tuple of LoadCase
        ``(t1_values[i], t2_values[i])`` for every i.

    Raises
    ------
    LoadCaseError
        The lists differ in length, or a torque is out of range.
    """
    if len(t1_values) != len(t2_values):
        raise LoadCaseError(source, f"{len(t1_values)} T1 values but {len(t2_values)} T2 values")
    return _validated([(float(a), float(b)) for a, b in zip(t1_values, t2_values)], source)


def _number(text: str | None, source: str, where: str) -> float:
    if text is None:  # a row with fewer fields than the header
        raise LoadCaseError(source, f"{where}: value is missing")
    if not text.strip():
        raise LoadCaseError(source, f"{where}: '' is not a number (the cell is empty; torques are plain numbers in N·m)")
    try:
        return plain_number(text)
    except ValueError as error:
        raise LoadCaseError(source, f"{where}: {error} (torques are plain numbers in N·m)") from None


def separator_hint(header: str) -> str:
    """A hint when a CSV header is written with ';' or tabs (spreadsheets in many locales), else ''."""
    for mark, name in ((";", "semicolons"), ("\t", "tabs")):
        if mark in header and "," not in header:
            return f"; the header is separated by {name}: save the file as comma-separated CSV (with '.' decimals)"
    return ""


def _read_csv_text(text: str, source: str) -> tuple[LoadCase, ...]:
    try:
        rows = list(csv_rows(text))
    except InputFileError as error:
        raise LoadCaseError(source, str(error)) from None
    header = rows[0][1] if rows else None
    columns = [c.strip() for c in header or []]
    missing = [c for c in ("T1_input_Nm", "T2_output_Nm") if c not in columns]
    if missing:
        hint = separator_hint(",".join(header or []))
        raise LoadCaseError(source, f"line 1: missing column(s) {', '.join(missing)} "
                            f"(found: {', '.join(columns) or 'none'}){hint}")
    repeated = sorted({c for c in columns if c and columns.count(c) > 1})
    if repeated:
        raise LoadCaseError(source, f"line 1: column(s) {', '.join(repeated)} appear more than once")
    pairs, places = [], []
    for line, values in rows[1:]:
        if not any(v.strip() for v in values):
            continue  # a blank line
        if len(values) > len(columns):
            raise LoadCaseError(source, f"line {line}: {len(values)} values but {len(columns)} columns in the header "
                                "(a ',' decimal separator, or a stray comma?)")
        row = dict(zip(columns, values))
        pairs.append((_number(row.get("T1_input_Nm"), source, f"line {line}, T1_input_Nm"),
                      _number(row.get("T2_output_Nm"), source, f"line {line}, T2_output_Nm")))
        places.append(f"line {line} (case {len(pairs)})")
    return _validated(pairs, source, places)


def read_cases(path: str | Path) -> tuple[LoadCase, ...]:
    """Read load cases from a CSV or TOML file.

    Parameters
    ----------
    path : str or Path
        A CSV with the columns ``T1_input_Nm, T2_output_Nm`` (any order, other columns ignored), or a TOML
        file of ``[[cases]]`` tables with those keys.

    Returns
    -------
    tuple of LoadCase
        In the file's order.

    Raises
    ------
    LoadCaseError
        Naming the file, the line or table and the reason (a missing column, a value that is not a plain
        number, a torque out of range, a duplicated case).
    """
    source = str(path)
    try:
        text = read_input_text(path, MAX_CASE_FILE_BYTES, "a load-case file")
    except InputFileError as error:
        raise LoadCaseError(source, str(error)) from None
    if source.lower().endswith(".toml"):
        try:
            data = parse_toml(text)
        except InputFileError as error:
            raise LoadCaseError(source, str(error)) from None
        cases = data.get("cases")
        if not isinstance(cases, list):
            raise LoadCaseError(source, "expected [[cases]] tables with T1_input_Nm and T2_output_Nm")
        pairs = []
        for i, case in enumerate(cases, start=1):
            if not isinstance(case, dict):
                raise LoadCaseError(source, f"cases[{i}]: {case!r} is not a table with T1_input_Nm and T2_output_Nm")
            for key in ("T1_input_Nm", "T2_output_Nm"):
                if key not in case:
                    raise LoadCaseError(source, f"cases[{i}]: missing key {key}")
                if not isinstance(case[key], (int, float)) or isinstance(case[key], bool):
                    raise LoadCaseError(source, f"cases[{i}].{key}: {case[key]!r} is not a number in N·m")
            pairs.append((float(case["T1_input_Nm"]), float(case["T2_output_Nm"])))
        return _validated(pairs, source)
    return _read_csv_text(text, source)


def torque_matrix(cases) -> np.ndarray:
    """(n, 2) array of [T1, T2] per case."""
    return np.array([[c.input_torque_Nm, c.output_torque_Nm] for c in cases], dtype=float)


@dataclass(frozen=True)
class PublishedRow:
    """One row of a published or measured Y/β table (lengths in mm, angles in degrees).

    ``stations_input_mm`` / ``stations_output_mm``: where Y was sampled along each path (measured
    paths), so that the model is read at the same stations; None when Y is the path's maximum.
    """

    case: LoadCase
    y_input_mm: float
    y_output_mm: float
    beta_input_deg: float
    beta_output_deg: float
    stations_input_mm: tuple[float, ...] | None = None
    stations_output_mm: tuple[float, ...] | None = None

    def stations_mm(self, shaft: str) -> tuple[float, ...] | None:
        """The stations Y of ``shaft`` was sampled at, or None (the maximum over the whole path)."""
        return self.stations_input_mm if shaft == "input" else self.stations_output_mm


def paper_table() -> tuple[PublishedRow, ...]:
    """The published ANSYS results of paper 000 (loadcases/data/paper000_coaxiality_table.csv).

    Returns
    -------
    tuple of PublishedRow
        Per row: the load case, Y_input_mm, Y_output_mm, beta_input_deg and beta_output_deg as published.
    """
    text = resources.files("rvcoax.loadcases").joinpath("data", PAPER_TABLE).read_text(encoding="utf-8")
    rows = []
    for row in csv.DictReader(io.StringIO(text)):
        rows.append(PublishedRow(
            LoadCase(float(row["T1_input_Nm"]), float(row["T2_output_Nm"])),
            float(row["Y_input_mm"]), float(row["Y_output_mm"]),
            float(row["beta_input_deg"]), float(row["beta_output_deg"]),
        ))
    return tuple(rows)
