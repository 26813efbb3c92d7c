"""Measured data for the discrepancy workflow, in two schemas, validated on load.

*table*
    ``T1_input_Nm, T2_output_Nm, Y_input_mm, Y_output_mm`` (β columns optional and ignored,
    since β = arcsin(Y/L) follows from Y): one magnitude per shaft per case, like paper 000's table.
*paths*
    ``T1_input_Nm, T2_output_Nm, shaft, x_mm, uy_mm`` and an optional ``sigma_mm``: signed
    vertical displacements (Y up) at any stations ``x_mm`` (0 … L from the shaft's input-side end)
    in any cases; ``shaft`` is ``input`` or ``output``.

The schema is recognised from the columns. Every problem is reported with the file, the line and
the column.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from geometry.inputfiles import InputFileError, read_input_text
from loadcases.cases import LoadCase, separator_hint

SHAFTS = ("input", "output")
TABLE_COLUMNS = ("T1_input_Nm", "T2_output_Nm", "Y_input_mm", "Y_output_mm")
PATH_COLUMNS = ("T1_input_Nm", "T2_output_Nm", "shaft", "x_mm", "uy_mm")
OPTIONAL_COLUMNS = ("sigma_mm", "beta_input_deg", "beta_output_deg")
MAX_BYTES = 50_000_000


class MeasuredDataError(ValueError):
    """Measured data that cannot be used; the message names the file, line/column and reason."""

    def __init__(self, source: str, problem: str):
        super().__init__(f"measured data {source}: {problem}")


@dataclass(frozen=True)
class MeasuredData:
    """Observations of Y, one per row of the file.

    Attributes
    ----------
    schema : str
        ``table`` (magnitudes of Y_max) or ``paths`` (signed u_y at stations).
    cases : tuple of LoadCase
        The distinct load cases, in the order they first appear.
    case_index : (n,) int array
        The case of each observation.
    shaft : (n,) array of str
        ``input`` or ``output``.
    x_mm : (n,) float array
        Station from the shaft's input-side end (NaN for table data: Y_max has no station).
    value_mm : (n,) float array
        Measured Y (table: |Y_max|; paths: signed u_y).
    sigma_mm : (n,) float array or None
        Measurement standard deviation per observation, when the file gives it.
    source : str
        Where the data came from.
    """

    schema: str
    cases: tuple[LoadCase, ...]
    case_index: np.ndarray
    shaft: np.ndarray
    x_mm: np.ndarray
    value_mm: np.ndarray
    sigma_mm: np.ndarray | None
    source: str
    quantum_mm: dict[str, float] | None = None

    @property
    def n(self) -> int:
        return int(self.value_mm.size)

    def subset(self, keep: np.ndarray) -> MeasuredData:
        """The observations where ``keep`` is true (cases renumbered)."""
        keep = np.asarray(keep, dtype=bool)
        used = sorted(set(self.case_index[keep].tolist()))
        renumber = {old: new for new, old in enumerate(used)}
        return MeasuredData(
            self.schema, tuple(self.cases[i] for i in used),
            np.array([renumber[i] for i in self.case_index[keep]], dtype=int), self.shaft[keep],
            self.x_mm[keep], self.value_mm[keep], None if self.sigma_mm is None else self.sigma_mm[keep],
            self.source, self.quantum_mm,
        )


def _number(text: str | None, source: str, line: int, column: str, unit: str) -> float:
    if text is None or not text.strip():
        raise MeasuredDataError(source, f"line {line}, column {column}: value is missing")
    try:
        value = float(text)
    except ValueError:
        raise MeasuredDataError(source, f"line {line}, column {column}: '{text.strip()}' is not a number "
                                f"(the column is in {unit}; write the number only)") from None
    if not math.isfinite(value):
        raise MeasuredDataError(source, f"line {line}, column {column}: {text.strip()} is not a finite number")
    return value


def _decimals(text: str) -> int:
    """Digits after the decimal point of a printed number ('0.0042594' → 7); -1 in exponent form."""
    text = text.strip().lower()
    if "e" in text:
        return -1
    return len(text.split(".")[1]) if "." in text else 0


def parse_measured(text: str, source: str) -> MeasuredData:
    """Parse measured data from CSV text (see the module docstring for the two schemas)."""
    reader = csv.DictReader(io.StringIO(text))
    columns = [c.strip() for c in (reader.fieldnames or [])]
    if not columns:
        raise MeasuredDataError(source, "the file is empty (expected a CSV header line)")
    repeated = sorted({c for c in columns if c and columns.count(c) > 1})
    if repeated:
        raise MeasuredDataError(source, f"line 1: column(s) {', '.join(repeated)} appear more than once")
    reader.fieldnames = columns
    if all(c in columns for c in PATH_COLUMNS):
        schema, needed = "paths", PATH_COLUMNS
    elif all(c in columns for c in TABLE_COLUMNS):
        schema, needed = "table", TABLE_COLUMNS
    else:
        table_missing = [c for c in TABLE_COLUMNS if c not in columns]
        path_missing = [c for c in PATH_COLUMNS if c not in columns]
        raise MeasuredDataError(
            source, "line 1: the columns fit neither schema: a table needs " + ", ".join(TABLE_COLUMNS)
            + f" (missing {', '.join(table_missing)}); paths need " + ", ".join(PATH_COLUMNS)
            + f" (missing {', '.join(path_missing)}); found: {', '.join(columns)}"
            + separator_hint(",".join(columns)))
    unknown = [c for c in columns if c not in needed and c not in OPTIONAL_COLUMNS]
    if unknown:
        raise MeasuredDataError(source, f"line 1: unknown column(s) {', '.join(unknown)} for a {schema} file "
                                f"(allowed: {', '.join(needed + OPTIONAL_COLUMNS)})")
    has_sigma = "sigma_mm" in columns
    cases: dict[tuple[float, float], int] = {}
    rows: list[tuple[int, str, float, float, float, int]] = []  # case, shaft, x, value, sigma, line
    decimals: dict[str, int] = {"input": 0, "output": 0}
    seen: set = set()
    for line, row in enumerate(reader, start=2):
        if None in row:
            raise MeasuredDataError(source, f"line {line}: more values than columns")
        t1 = _number(row["T1_input_Nm"], source, line, "T1_input_Nm", "N·m")
        t2 = _number(row["T2_output_Nm"], source, line, "T2_output_Nm", "N·m")
        case = cases.setdefault((t1, t2), len(cases))
        sigma = _number(row["sigma_mm"], source, line, "sigma_mm", "mm") if has_sigma else math.nan
        if has_sigma and not sigma > 0:
            raise MeasuredDataError(source, f"line {line}, column sigma_mm: {sigma} must be > 0 mm")
        if schema == "table":
            if (t1, t2) in seen:
                raise MeasuredDataError(source, f"line {line}: duplicated load case T1 = {t1:g}, T2 = {t2:g} N·m")
            seen.add((t1, t2))
            for shaft in SHAFTS:
                column = f"Y_{shaft}_mm"
                value = _number(row[column], source, line, column, "mm")
                if value < 0:
                    raise MeasuredDataError(source, f"line {line}, column {column}: {value} < 0; a table holds "
                                            "magnitudes |Y_max| (use the paths schema for signed values)")
                decimals[shaft] = max(decimals[shaft], _decimals(row[column]))
                rows.append((case, shaft, math.nan, value, sigma, line))
        else:
            shaft = (row["shaft"] or "").strip()
            if shaft not in SHAFTS:
                raise MeasuredDataError(source, f"line {line}, column shaft: '{shaft}' is not input or output")
            x = _number(row["x_mm"], source, line, "x_mm", "mm")
            key = (t1, t2, shaft, x)
            if key in seen:
                raise MeasuredDataError(source, f"line {line}: a second value for the {shaft} shaft at x = {x:g} mm "
                                        f"in case T1 = {t1:g}, T2 = {t2:g} N·m")
            seen.add(key)
            rows.append((case, shaft, x, _number(row["uy_mm"], source, line, "uy_mm", "mm"), sigma, line))
    if not rows:
        raise MeasuredDataError(source, "no data rows under the header")
    _check_magnitudes(rows, schema, source)
    case_index, shafts, x, values, sigmas, _ = (np.array(c) for c in zip(*rows))
    quantum = None
    if schema == "table":
        quantum = {s: (10.0 ** -d if d >= 0 else 0.0) for s, d in decimals.items()}
    return MeasuredData(schema, tuple(LoadCase(a, b) for a, b in cases), case_index.astype(int), shafts.astype(str),
                        x.astype(float), values.astype(float), sigmas.astype(float) if has_sigma else None,
                        source, quantum)


LARGEST_PLAUSIBLE_Y_MM = 10.0  # a shaft of a running test rig displaced 10 mm would be wrecked
SHORTEST_PLAUSIBLE_PATH_MM = 0.5  # no measured shaft path is shorter than half a millimetre


def _check_magnitudes(rows: list[tuple], schema: str, source: str) -> None:
    """Refuse numbers whose size says they are in another unit than the column's (m or µm for mm)."""
    values = np.array([r[3] for r in rows])
    worst = int(np.argmax(np.abs(values)))
    if abs(values[worst]) > LARGEST_PLAUSIBLE_Y_MM:
        column = "uy_mm" if schema == "paths" else f"Y_{rows[worst][1]}_mm"
        raise MeasuredDataError(source, f"line {rows[worst][5]}, column {column}: {values[worst]:g} mm is not a "
                                f"plausible displacement of a test-rig shaft (> {LARGEST_PLAUSIBLE_Y_MM:g} mm): "
                                "looks like µm or nm; the column is in mm")
    if schema != "paths":
        return
    for shaft in SHAFTS:
        here = [r for r in rows if r[1] == shaft]
        stations = {r[2] for r in here}
        if len(stations) >= 2 and max(abs(x) for x in stations) <= SHORTEST_PLAUSIBLE_PATH_MM:
            raise MeasuredDataError(source, f"lines {here[0][5]}–{here[-1][5]}, column x_mm: every station of the "
                                    f"{shaft} shaft lies within {max(stations):g} mm of its start: looks like metres; "
                                    "x_mm is in mm (0 … L from the shaft's input-side end)")


def read_measured(path: str | Path) -> MeasuredData:
    """Read and validate a measured-data CSV file (table or paths schema)."""
    source = str(path)
    try:
        text = read_input_text(path, MAX_BYTES, "measured data")
    except InputFileError as error:
        raise MeasuredDataError(source, str(error)) from None
    return parse_measured(text, source)


def check_stations(data: MeasuredData, path_lengths_mm: dict[str, float]) -> None:
    """Raise if a station lies outside its shaft's measured path (0 … L)."""
    if data.schema != "paths":
        return
    for shaft, length in path_lengths_mm.items():
        x = data.x_mm[data.shaft == shaft]
        bad = x[(x < -1e-9) | (x > length + 1e-9)]
        if bad.size:
            raise MeasuredDataError(data.source, f"x_mm = {bad[0]:g} on the {shaft} shaft is outside its measured "
                                    f"path 0 … {length:g} mm (x is measured from the shaft's input-side end)")
