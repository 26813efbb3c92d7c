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

Lines that start with ``#`` are comments. Three of them, before the header or anywhere, describe the
data as a whole (``# key = value``):

``# label = "dial gauges, bench 2, March run"``   what the data are called in tables and pictures
``# uncertainty_um = 0.5``                        the measurement uncertainty, absolute (µm) …
``# uncertainty_percent = 3``                     … and relative (% of each value)

The check judges the model with the larger of the two (``rvcoax check --measured``); options given on
the command line take precedence.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvcoax.errors import InputFileProblems
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.inputfiles import InputFileError, csv_rows, plain_number, read_input_text
from rvcoax.loadcases.cases import MAX_TORQUE_NM, LoadCase, separator_hint

__all__ = ["LARGEST_PLAUSIBLE_Y_MM", "MAX_BYTES", "METADATA_KEYS", "MeasuredData", "MeasuredDataError", "OPTIONAL_COLUMNS",
           "PATH_COLUMNS", "MEASURED_SHAFTS", "SHORTEST_PLAUSIBLE_PATH_MM", "TABLE_COLUMNS", "check_stations",
           "parse_measured", "printed_quantum", "read_measured"]

TABLE_COLUMNS = ("T1_input_Nm", "T2_output_Nm", "Y_input_mm", "Y_output_mm")
PATH_COLUMNS = ("T1_input_Nm", "T2_output_Nm", "shaft", "x_mm", "uy_mm")
OPTIONAL_COLUMNS = ("sigma_mm", "beta_input_deg", "beta_output_deg")
MAX_BYTES = 50_000_000


class MeasuredDataError(InputFileProblems):
    """Measured data that cannot be used; the message names the file, line/column and reason."""

    what = "measured data"

    def __init__(self, source: str, problem: str):
        super().__init__(source, [problem])


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
    line: np.ndarray | None = None  # (n,) the file's line of each observation, when read from a file
    label: str | None = None  # the file's ``# label = …``
    uncertainty_um: float | None = None  # the file's ``# uncertainty_um = …`` (absolute)
    uncertainty_percent: float | None = None  # the file's ``# uncertainty_percent = …`` (relative)

    @property
    def n(self) -> int:
        return int(self.value_mm.size)

    def subset(self, keep: np.ndarray) -> MeasuredData:
        """The observations where ``keep`` is true (cases renumbered)."""
        keep = np.asarray(keep, dtype=bool)
        used = sorted(set(self.case_index[keep].tolist()))
        renumber = {old: new for new, old in enumerate(used)}
        return MeasuredData(
            schema=self.schema, cases=tuple(self.cases[i] for i in used),
            case_index=np.array([renumber[i] for i in self.case_index[keep]], dtype=int), shaft=self.shaft[keep],
            x_mm=self.x_mm[keep], value_mm=self.value_mm[keep], sigma_mm=None if self.sigma_mm is None else self.sigma_mm[keep],
            source=self.source, quantum_mm=self.quantum_mm, line=None if self.line is None else self.line[keep],
            label=self.label, uncertainty_um=self.uncertainty_um, uncertainty_percent=self.uncertainty_percent,
        )

    @property
    def name(self) -> str:
        """What the data are called: the file's ``# label``, else ``measured (<file>)``."""
        return self.label or f"measured ({self.source})"


def _number(text: str | None, source: str, line: int, column: str, unit: str) -> float:
    if text is None or not text.strip():
        raise MeasuredDataError(source, f"line {line}, column {column}: value is missing")
    try:
        return plain_number(text)
    except ValueError as error:
        raise MeasuredDataError(source, f"line {line}, column {column}: {error} (the column is in {unit}; write "
                                "the number only)") from None


def _torque(text: str | None, source: str, line: int, column: str) -> float:
    value = _number(text, source, line, column, "N·m")
    if abs(value) > MAX_TORQUE_NM:
        raise MeasuredDataError(source, f"line {line}, column {column}: {value:g} N·m is beyond any plausible rig "
                                f"torque (|T| ≤ {MAX_TORQUE_NM:g} N·m, as for load cases)")
    return value


def printed_quantum(text: str) -> float:
    """The rounding quantum of a printed number: one unit of its last printed digit (mm for mm).

    ``0.0042594`` → 1e-7, ``6e-05`` → 1e-5, ``6.03E-05`` → 1e-7, ``1.5e+2`` → 10, ``42`` → 1: the
    exponent shifts the mantissa's last digit, so fixed and exponent notation of the same digits agree.
    """
    mantissa, _, exponent = text.strip(" \t").lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 10.0 ** (int(exponent or 0) - decimals)


def _schema_of(columns: list[str], source: str, header_line: int) -> str:
    """The schema (``paths`` or ``table``) the header line (file line ``header_line``) names; refuses an empty, repeated or unknown column."""
    if not columns:
        raise MeasuredDataError(source, "the file is empty (expected a CSV header line)")
    repeated = sorted({c for c in columns if c and columns.count(c) > 1})
    if repeated:
        raise MeasuredDataError(source, f"line {header_line}: column(s) {', '.join(repeated)} appear more "
                                "than once")
    if all(c in columns for c in PATH_COLUMNS):
        schema, needed = "paths", PATH_COLUMNS
    elif all(c in columns for c in TABLE_COLUMNS):
        schema, needed = "table", TABLE_COLUMNS
    else:
        table_missing = [c for c in TABLE_COLUMNS if c not in columns]
        path_missing = [c for c in PATH_COLUMNS if c not in columns]
        raise MeasuredDataError(
            source, f"line {header_line}: the columns fit neither schema: a table needs " + ", ".join(TABLE_COLUMNS)
            + f" (missing {', '.join(table_missing)}); paths need " + ", ".join(PATH_COLUMNS)
            + f" (missing {', '.join(path_missing)}); found: {', '.join(columns)}"
            + separator_hint(",".join(columns)))
    unknown = [c for c in columns if c not in needed and c not in OPTIONAL_COLUMNS]
    if unknown:
        raise MeasuredDataError(source, f"line {header_line}: unknown column(s) {', '.join(unknown)} for a {schema} file "
                                f"(allowed: {', '.join(needed + OPTIONAL_COLUMNS)})")
    return schema


METADATA_KEYS = ("label", "uncertainty_um", "uncertainty_percent")
_METADATA = re.compile(r"^\s*#\s*(?P<key>[A-Za-z_]+)\s*=\s*(?P<value>.*?)\s*$")


def _metadata(text: str, source: str) -> dict:
    """The ``# label``, ``# uncertainty_um`` and ``# uncertainty_percent`` comment lines of a measured file."""
    found: dict = {}
    for number, line in enumerate(text.replace("\r\n", "\n").replace("\r", "\n").split("\n"), start=1):
        match = _METADATA.match(line)
        if not match or match["key"] not in METADATA_KEYS:
            continue
        key, value = match["key"], match["value"]
        if key in found:
            raise MeasuredDataError(source, f"line {number}: a second '# {key} = …' line")
        if key == "label":
            value = value.strip().strip('"').strip("'").strip()
            if not value or len(value) > 200 or not value.isprintable():
                raise MeasuredDataError(source, f"line {number}, # label: give 1 … 200 printable characters")
            found[key] = value
            continue
        try:
            number_value = plain_number(value)
        except ValueError as error:
            raise MeasuredDataError(source, f"line {number}, # {key}: {error} (write the number only)") from None
        limit = 1e4 if key == "uncertainty_um" else 100.0
        if not 0.0 <= number_value <= limit:
            raise MeasuredDataError(source, f"line {number}, # {key}: {number_value:g} must lie in 0 … {limit:g}")
        found[key] = number_value
    return found


def parse_measured(text: str, source: str) -> MeasuredData:
    """Parse measured data from CSV text (see the module docstring for the two schemas and the ``#`` lines)."""
    metadata = _metadata(text, source)
    try:
        rows_of_file = [row for row in csv_rows(text, comment="#") if any(c.strip() for c in row[1])]
    except InputFileError as error:
        raise MeasuredDataError(source, str(error)) from None
    columns = [c.strip() for c in (rows_of_file[0][1] if rows_of_file else [])]
    schema = _schema_of(columns, source, rows_of_file[0][0] if rows_of_file else 1)
    has_sigma = "sigma_mm" in columns
    cases: dict[tuple[float, float], int] = {}
    rows: list[tuple[int, str, float, float, float, int]] = []  # case, shaft, x, value, sigma, line
    quantum: dict[str, float] = {"input": math.inf, "output": math.inf}
    seen: set = set()
    for line, cells in rows_of_file[1:]:
        if not any(c.strip() for c in cells):
            continue  # a blank line
        if len(cells) > len(columns):
            raise MeasuredDataError(source, f"line {line}: {len(cells)} values but {len(columns)} columns in the "
                                    "header (a ',' decimal separator, or a stray comma?)")
        row = dict(zip(columns, cells))
        t1 = _torque(row.get("T1_input_Nm"), source, line, "T1_input_Nm")
        t2 = _torque(row.get("T2_output_Nm"), source, line, "T2_output_Nm")
        case = cases.setdefault((t1, t2), len(cases))
        sigma = _number(row.get("sigma_mm"), source, line, "sigma_mm", "mm") if has_sigma else math.nan
        if has_sigma and not sigma > 0:
            raise MeasuredDataError(source, f"line {line}, column sigma_mm: {sigma} must be > 0 mm")
        if schema == "table":
            if (t1, t2) in seen:
                raise MeasuredDataError(source, f"line {line}: duplicated load case T1 = {t1:g}, T2 = {t2:g} N·m")
            seen.add((t1, t2))
            for shaft in MEASURED_SHAFTS:
                column = f"Y_{shaft}_mm"
                value = _number(row.get(column), source, line, column, "mm")
                if value < 0:
                    raise MeasuredDataError(source, f"line {line}, column {column}: {value} < 0; a table holds "
                                            "magnitudes |Y_max| (use the paths schema for signed values)")
                quantum[shaft] = min(quantum[shaft], printed_quantum(row[column]))
                rows.append((case, shaft, math.nan, value, sigma, line))
        else:
            shaft = (row.get("shaft") or "").strip()
            if shaft not in MEASURED_SHAFTS:
                raise MeasuredDataError(source, f"line {line}, column shaft: '{shaft}' is not input or output")
            x = _number(row.get("x_mm"), source, line, "x_mm", "mm")
            key = (t1, t2, shaft, x)
            if key in seen:
                raise MeasuredDataError(source, f"line {line}: a second value for the {shaft} shaft at x = {x:g} mm "
                                        f"in case T1 = {t1:g}, T2 = {t2:g} N·m")
            seen.add(key)
            rows.append((case, shaft, x, _number(row.get("uy_mm"), source, line, "uy_mm", "mm"), sigma, line))
    if not rows:
        raise MeasuredDataError(source, "no data rows under the header")
    _check_magnitudes(rows, schema, source)
    case_index, shafts, x, values, sigmas, lines = (np.array(c) for c in zip(*rows))
    return MeasuredData(schema=schema, cases=tuple(LoadCase(a, b) for a, b in cases), case_index=case_index.astype(int), shaft=shafts.astype(str),
                        x_mm=x.astype(float), value_mm=values.astype(float), sigma_mm=sigmas.astype(float) if has_sigma else None,
                        source=source, quantum_mm=quantum if schema == "table" else None, line=lines.astype(int),
                        label=metadata.get("label"), uncertainty_um=metadata.get("uncertainty_um"),
                        uncertainty_percent=metadata.get("uncertainty_percent"))


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
    for shaft in MEASURED_SHAFTS:
        here = [r for r in rows if r[1] == shaft]
        stations = {r[2] for r in here}
        if len(stations) >= 2 and max(abs(x) for x in stations) <= SHORTEST_PLAUSIBLE_PATH_MM:
            raise MeasuredDataError(source, f"lines {here[0][5]}–{here[-1][5]}, column x_mm: every station of the "
                                    f"{shaft} shaft lies within {max(stations):g} mm of its start: looks like metres; "
                                    "x_mm is in mm (0 … L from the shaft's input-side end)")


def read_measured(path: str | Path) -> MeasuredData:
    """Read and validate a measured-data CSV file (table or paths schema).

    Parameters
    ----------
    path : str or Path
        A table of Y_max per load case and shaft, or Y at stations along the shafts (``docs/discrepancy.md``).

    Returns
    -------
    MeasuredData
        One observation per row, with its printed resolution.

    Raises
    ------
    MeasuredDataError
        Naming the file, the line and the reason.
    """
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
        outside = np.flatnonzero((data.shaft == shaft) & ((data.x_mm < -1e-9) | (data.x_mm > length + 1e-9)))
        if outside.size:
            first = outside[0]
            where = "" if data.line is None else f"line {data.line[first]}, column x_mm: "
            raise MeasuredDataError(data.source, f"{where}x_mm = {data.x_mm[first]:g} on the {shaft} shaft is outside "
                                    f"its measured path 0 … {length:g} mm (x is measured from the shaft's input-side "
                                    f"end; {outside.size} station(s) outside)")
