"""Torque load cases and how to read them.

A load case is a pair (T1 input torque, T2 output torque) in N·m. The default sweep is the 20
pairs of paper 000's coaxiality table. Files: CSV with columns ``T1_input_Nm, T2_output_Nm`` (other
columns ignored) or TOML with ``[[cases]] T1_input_Nm = .. T2_output_Nm = ..``.
"""

from __future__ import annotations

import csv
import io
import math
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

PAPER_TABLE = "paper000_coaxiality_table.csv"


class LoadCaseError(ValueError):
    """Load cases that cannot be used; the message names the source and the reason."""

    def __init__(self, source: str, problem: str):
        super().__init__(f"load cases {source}: {problem}")


@dataclass(frozen=True)
class LoadCase:
    """One torque pair (N·m)."""

    input_torque_Nm: float
    output_torque_Nm: float

    @property
    def label(self) -> str:
        return f"T1={self.input_torque_Nm:g}Nm_T2={self.output_torque_Nm:g}Nm"


def _validated(pairs: list[tuple[float, float]], source: str) -> tuple[LoadCase, ...]:
    if not pairs:
        raise LoadCaseError(source, "no load cases")
    seen = set()
    for i, (t1, t2) in enumerate(pairs, start=1):
        for name, value in (("T1_input_Nm", t1), ("T2_output_Nm", t2)):
            if not math.isfinite(value):
                raise LoadCaseError(source, f"case {i}: {name} = {value} is not a finite number")
            if abs(value) > 1e6:
                raise LoadCaseError(source, f"case {i}: {name} = {value} N·m is beyond any plausible rig torque")
        if (t1, t2) in seen:
            raise LoadCaseError(source, f"case {i}: duplicated load case T1 = {t1}, T2 = {t2} N·m")
        seen.add((t1, t2))
    return tuple(LoadCase(float(a), float(b)) for a, b in pairs)


def paper_cases() -> tuple[LoadCase, ...]:
    """The 20 (T1, T2) pairs of paper 000's coaxiality table, in the table's order."""
    text = resources.files("loadcases").joinpath("data", PAPER_TABLE).read_text(encoding="utf-8")
    return _read_csv_text(text, f"<built-in {PAPER_TABLE}>")


def grid_cases(t1_values, t2_values) -> tuple[LoadCase, ...]:
    """Every combination of the given T1 and T2 values (N·m)."""
    return _validated([(float(a), float(b)) for a in t1_values for b in t2_values], "grid")


def paired_cases(t1_values, t2_values, source: str = "command line") -> tuple[LoadCase, ...]:
    """Cases from two equally long lists of T1 and T2 (N·m)."""
    if len(t1_values) != len(t2_values):
        raise LoadCaseError(source, f"{len(t1_values)} T1 values but {len(t2_values)} T2 values")
    return _validated([(float(a), float(b)) for a, b in zip(t1_values, t2_values)], source)


def _number(text: str | None, source: str, where: str) -> float:
    if text is None:  # a row with fewer fields than the header
        raise LoadCaseError(source, f"{where}: value is missing")
    try:
        return float(text)
    except ValueError:
        raise LoadCaseError(source, f"{where}: '{text}' is not a number (torques are plain numbers in N·m)") from None


def _read_csv_text(text: str, source: str) -> tuple[LoadCase, ...]:
    reader = csv.DictReader(io.StringIO(text))
    columns = reader.fieldnames or []
    missing = [c for c in ("T1_input_Nm", "T2_output_Nm") if c not in columns]
    if missing:
        raise LoadCaseError(source, f"missing column(s) {', '.join(missing)} (found: {', '.join(columns) or 'none'})")
    pairs = []
    for line, row in enumerate(reader, start=2):
        pairs.append((_number(row["T1_input_Nm"], source, f"line {line}, T1_input_Nm"),
                      _number(row["T2_output_Nm"], source, f"line {line}, T2_output_Nm")))
    return _validated(pairs, source)


def read_cases(path: str | Path) -> tuple[LoadCase, ...]:
    """Read load cases from a CSV or TOML file."""
    source = str(path)
    try:
        text = Path(path).read_bytes().decode("utf-8")
    except FileNotFoundError:
        raise LoadCaseError(source, "file not found") from None
    except UnicodeDecodeError:
        raise LoadCaseError(source, "not UTF-8 text") from None
    except OSError as error:
        raise LoadCaseError(source, f"cannot be read: {error.strerror}") from None
    if source.lower().endswith(".toml"):
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as error:
            raise LoadCaseError(source, f"TOML syntax error: {error}") from None
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
    """One row of paper 000's coaxiality table (lengths in mm, angles in degrees)."""

    case: LoadCase
    y_input_mm: float
    y_output_mm: float
    beta_input_deg: float
    beta_output_deg: float


def paper_table() -> tuple[PublishedRow, ...]:
    """The published ANSYS results of paper 000 (shared/reference/coaxiality_table.csv)."""
    text = resources.files("loadcases").joinpath("data", PAPER_TABLE).read_text(encoding="utf-8")
    rows = []
    for row in csv.DictReader(io.StringIO(text)):
        rows.append(PublishedRow(
            LoadCase(float(row["T1_input_Nm"]), float(row["T2_output_Nm"])),
            float(row["Y_input_mm"]), float(row["Y_output_mm"]),
            float(row["beta_input_deg"]), float(row["beta_output_deg"]),
        ))
    return tuple(rows)
