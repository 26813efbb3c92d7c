"""An orthogonal study of rig tolerances: every run of the array is a real solve of the rig.

A study file (TOML, default ``results/data/l27_rig_tolerances.toml``) names the array, the load
case, whether Y is measured from the unloaded geometry, and the factors: each sets one or more rig
parameters (addresses of :mod:`rvcoax.geometry.parameters`) to one of its level values. Run r solves the
rig with the levels of row r and records, per measured shaft, Y_max and β = arcsin(Y_max / L).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import Field, model_validator

from rvcoax.errors import RvcoaxError, problems_text
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.parameters import get_parameter, with_parameters
from rvcoax.geometry.schema import Rig
from rvcoax.geometry.validation import StrictModel, read_toml_model
from rvcoax.loadcases.cases import MAX_TORQUE_NM, LoadCase
from rvcoax.results.io.datafiles import read_data_text
from rvcoax.results.studies.doe.design import Design, Factor, build_sources
from rvcoax.results.studies.doe.limits import ALPHA_RANGE, POOL_BELOW_F_RANGE
from rvcoax.results.studies.doe.orthogonal import ARRAYS, OrthogonalArray, standard_array, three_level_coefficients
from rvcoax.results.sweep import SweepSettings, run_sweep

STUDY_FILE = "l27_rig_tolerances.toml"
RESPONSES = ("beta_input_deg", "beta_output_deg")

Finite = Annotated[float, Field(allow_inf_nan=False, strict=False)]
Torque = Annotated[float, Field(ge=-MAX_TORQUE_NM, le=MAX_TORQUE_NM, allow_inf_nan=False)]  # as every load-case reader


class StudyError(RvcoaxError, ValueError):
    """A study file that cannot be used; the message names the file, key and reason."""


class StudySettings(StrictModel):
    """The ``[study]`` table."""

    name: str
    array: Literal["L9", "L18", "L27", "L81"] = "L27"
    measured_from: Literal["aligned_at_rest", "unloaded"] = "unloaded"
    goal: Literal["min", "max"] = "min"
    alpha: Annotated[float, Field(gt=ALPHA_RANGE[0], lt=ALPHA_RANGE[1], allow_inf_nan=False)] = 0.05
    pool_below_F: Annotated[float, Field(ge=POOL_BELOW_F_RANGE[0], le=POOL_BELOW_F_RANGE[1], allow_inf_nan=False)] | None = 1.0
    T1_input_Nm: Torque = 1.43
    T2_output_Nm: Torque = 200.0


class StudyFactor(StrictModel):
    """One ``[[factors]]`` entry."""

    key: Annotated[str, Field(pattern=r"^[A-Za-z][A-Za-z0-9]*$")]
    name: str
    addresses: list[str] = Field(min_length=1)
    levels: list[Finite] = Field(min_length=2)
    unit: str
    source: str
    column: Annotated[int, Field(ge=1)] | None = None

    @model_validator(mode="after")
    def _distinct(self) -> StudyFactor:
        if len(set(self.levels)) != len(self.levels):
            raise ValueError(f"factor {self.key}: level values must be distinct, got {self.levels}")
        return self


class Study(StrictModel):
    """A whole study file."""

    schema_version: Literal[1]
    study: StudySettings
    factors: list[StudyFactor] = Field(min_length=1)

    @model_validator(mode="after")
    def _unique(self) -> Study:
        keys = [f.key for f in self.factors]
        if len(set(keys)) != len(keys):
            raise ValueError(f"factor keys must be unique, got {keys}")
        return self


@dataclass(frozen=True, eq=False)
class StudyResult:
    """Runs of a study: the array, the column of each factor, the rig values and responses per run."""

    study: Study
    array: OrthogonalArray
    columns: dict[str, int]
    settings: SweepSettings
    responses: dict[str, np.ndarray]
    y_max_mm: dict[str, np.ndarray]

    @property
    def factors(self) -> tuple[Factor, ...]:
        return tuple(Factor(f.key, f.name, f.unit, tuple(f.levels)) for f in self.study.factors)

    def design(self, response: str) -> Design:
        """The design (factor and empty columns of the array) with one response, ready for analysis."""
        codes = {}
        for j in range(1, self.array.columns + 1):
            key = next((k for k, c in self.columns.items() if c == j), f"e{j}")
            codes[key] = self.array.table[:, j - 1]
        runs = tuple(str(i + 1) for i in range(self.array.runs))
        return Design(runs=runs, codes=codes, factors=self.factors, sources=build_sources(self.factors, list(codes)),
                      response=self.responses[response], response_name=response)


def load_study(path: str | Path | None = None) -> Study:
    """Read and validate a study file (default: the built-in L27 rig-tolerance study).

    Parameters
    ----------
    path : str or Path, optional
        A study TOML file (``docs/doe.md``).

    Returns
    -------
    Study
        Array, factors with their rig-file addresses and levels, load case, model.

    Raises
    ------
    StudyError
        Naming the file, the key and the reason.
    """
    source, text = read_data_text(path, STUDY_FILE, StudyError, "study file")
    return read_toml_model(Study, text, lambda problems: StudyError(problems_text("study file", source, problems)))


def preferred_columns(array: OrthogonalArray) -> list[int]:
    """Columns in the order factors are assigned by default.

    Linear three-level arrays: the base columns first, then the columns of the highest-order
    interactions (those are the last to matter), then the rest; L18: the three-level columns 2 … 8.
    """
    if array.name == "L18":
        return list(range(2, 9))
    order = np.count_nonzero(three_level_coefficients(round(np.log(array.runs) / np.log(3))), axis=1)
    base = [j + 1 for j in range(array.columns) if order[j] == 1]
    rest = sorted((j + 1 for j in range(array.columns) if order[j] != 1), key=lambda j: (-order[j - 1], j))
    return base + rest


def assign_columns(study: Study, array: OrthogonalArray, source: str = "study file") -> dict[str, int]:
    """Array column of each factor: its ``column`` if given, else the next free preferred column."""
    taken = {f.column for f in study.factors if f.column is not None}
    free = [j for j in preferred_columns(array) if j not in taken]
    columns = {}
    for factor in study.factors:
        column = factor.column if factor.column is not None else (free.pop(0) if free else None)
        if column is None or column > array.columns:
            raise StudyError(f"{source}: factor {factor.key}: {array.name} has {array.columns} columns "
                             f"({len(study.factors)} factors)")
        if array.levels[column - 1] != len(factor.levels):
            raise StudyError(f"{source}: factor {factor.key} has {len(factor.levels)} levels but column {column} "
                             f"of {array.name} has {array.levels[column - 1]}")
        columns[factor.key] = column
    if len(set(columns.values())) != len(columns):
        raise StudyError(f"{source}: two factors share a column ({columns})")
    return columns


def study_rig(rig: Rig, study: Study) -> Rig:
    """``rig`` with Y measured as the study says."""
    data = rig.model_dump(by_alias=True)
    data["paths"]["measured_from"] = study.study.measured_from
    return Rig.model_validate(data)


def run_values(study: Study, array: OrthogonalArray, columns: dict[str, int], run: int) -> dict[str, float]:
    """Rig parameter values (address → value) of run ``run`` (0-based).

    Parameters
    ----------
    study : Study
        From :func:`load_study`.
    array : OrthogonalArray
        The study's array.
    columns : dict of str to int
        Factor key → its column of the array (1-based).
    run : int
        The run.

    Returns
    -------
    dict of str to float
        Each factor's level value at each of its addresses.
    """
    values = {}
    for factor in study.factors:
        level = int(array.table[run, columns[factor.key] - 1])
        for address in factor.addresses:
            values[address] = float(factor.levels[level - 1])
    return values


def check_addresses(rig: Rig, study: Study, source: str = "study file") -> None:
    """Raise :class:`StudyError` for an address the rig does not have."""
    for factor in study.factors:
        for address in factor.addresses:
            try:
                get_parameter(rig, address)
            except KeyError as error:
                raise StudyError(f"{source}: factor {factor.key}: {error.args[0]}") from None


def run_study(rig: Rig, study: Study, settings: SweepSettings | None = None,  # noqa: PLR0913
              progress: Callable[[int, int], None] | None = None, runs: range | None = None,
              *, source: str = "study file") -> StudyResult:
    """Solve the rig once per run of the study's array and collect β and Y_max of both shafts.

    ``runs`` limits the solves to some runs (the others stay NaN), e.g. to try a slow model;
    ``source`` names the study in error messages.

    Parameters
    ----------
    rig : Rig
        The rig whose addresses the study names.
    study : Study
        From :func:`load_study`.
    settings : SweepSettings, optional
        How each run is solved (default: the study's model).
    progress : callable, optional
        ``progress(done, total)`` after each run.
    runs : range, optional
        The runs to solve.
    source : str
        The study's name in error messages.

    Returns
    -------
    StudyResult
        The array, the columns, and per run the responses (β per shaft) and Y_max.
    """
    settings = SweepSettings() if settings is None else settings
    array = standard_array(study.study.array)
    columns = assign_columns(study, array, source)
    base = study_rig(rig, study)
    check_addresses(base, study, source)
    case = (LoadCase(study.study.T1_input_Nm, study.study.T2_output_Nm),)
    beta = {s: np.full(array.runs, np.nan) for s in MEASURED_SHAFTS}
    y_max = {s: np.full(array.runs, np.nan) for s in MEASURED_SHAFTS}
    selected = range(array.runs) if runs is None else runs
    for count, run in enumerate(selected, start=1):
        sweep = run_sweep(with_parameters(base, run_values(study, array, columns, run)), case, settings,
                          engineering=False)  # Y and β only
        for shaft in MEASURED_SHAFTS:
            path = sweep.cases[0].paths[shaft]
            beta[shaft][run], y_max[shaft][run] = path.beta_deg, path.y_max_mm
        if progress is not None:
            progress(count, len(selected))
    return StudyResult(study=study, array=array, columns=columns, settings=settings,
                       responses={f"beta_{s}_deg": beta[s] for s in MEASURED_SHAFTS}, y_max_mm=y_max)


__all__ = ["ARRAYS", "RESPONSES", "Study", "StudyError", "StudyResult", "assign_columns", "load_study",
           "preferred_columns", "run_study", "run_values"]
