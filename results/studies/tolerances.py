"""Tolerance files (TOML): which rig parameters scatter, how, under which load cases, against which β limits.

A tolerance file::

    schema_version = 1
    [study]
    name = "RV-20E rig, assembly scatter"
    measured_from = "unloaded"        # optional: override the rig's [paths] measured_from
    confidence_level = 0.95           # optional: of every interval reported

    [[cases]]                         # optional; default: T1 = 1.43 N·m, T2 = 200 N·m
    T1_input_Nm = 1.43
    T2_output_Nm = 200

    [[parameters]]
    address = "bearings.input_B1.radial_stiffness_N_per_um"
    distribution = "uniform"          # normal | uniform | truncated_normal
    low_N_per_um = 40
    high_N_per_um = 65
    source = "[S] 6204 radial stiffness 40-65 N/µm"

    [[limits]]
    shaft = "input"
    Y_max_mm = 0.002                  # or beta_deg = ...
    source = "[P] paper 000: a_input = 0.002 mm (IT3)"

An address is any rig parameter address of :mod:`rvcoax.geometry.parameters`
(``<group>.<name>.<key>[index]``), or ``parts.<part>.outer_diameter_deviation_mm`` (added to
every outer diameter of that part; nominal 0). The statistics carry the unit of the address's
key in their own key (``mean_um`` for ``..._um``; plain ``mean`` for a dimensionless key such as
``imbalance``), so a value in the wrong unit is an error, not a silent factor of 1000.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Literal

from pydantic import Field, ValidationError, model_validator

from rvcoax.errors import InputFileProblems
from rvcoax.geometry.inputfiles import InputFileError, read_input_text
from rvcoax.geometry.parameters import get_parameter, with_parameters
from rvcoax.geometry.schema import Rig
from rvcoax.geometry.validation import StrictModel, read_toml_model
from rvcoax.loadcases.cases import LoadCase, LoadCaseError, paired_cases
from rvcoax.results.studies.sampling import Distribution

__all__ = ["BetaLimit", "DEFAULT_CASES", "MAX_TOLERANCE_FILE_BYTES", "Number", "PART_DEVIATION_KEY", "STATISTICS",
           "ToleranceFileError", "Tolerances", "ToleratedParameter", "UNIT_SUFFIXES", "apply_values",
           "load_tolerances", "parameter_value", "parse_tolerances", "study_rig", "unit_of"]

UNIT_SUFFIXES = ("N_per_um", "N_per_mm", "Nm_per_rad", "N_per_Nm", "m_per_s2", "kg_per_m3", "MPa", "mrad", "rad", "deg", "um", "mm", "kg", "Nm", "N")
STATISTICS = ("mean", "std", "low", "high")
PART_DEVIATION_KEY = "outer_diameter_deviation_mm"
DEFAULT_CASES = ((1.43, 200.0),)
MAX_TOLERANCE_FILE_BYTES = 1_000_000  # a tolerance file lists tens of parameters: a few kB  # the largest torque pair of paper 000's table [P]

Number = Annotated[float, Field(allow_inf_nan=False, strict=True)]


class ToleranceFileError(InputFileProblems):
    """A tolerance file that cannot be used; the message names the file, the keys and the reasons."""

    what = "tolerance file"


class _Study(StrictModel):
    name: str
    description: str = ""
    measured_from: Literal["aligned_at_rest", "unloaded"] | None = None
    confidence_level: Annotated[float, Field(gt=0.5, lt=1.0, strict=True)] = 0.95


class _Case(StrictModel):
    T1_input_Nm: Number
    T2_output_Nm: Number


class _Parameter(StrictModel):
    address: str
    distribution: Literal["normal", "uniform", "truncated_normal"]
    mean: Number | None = None
    std: Number | None = None
    low: Number | None = None
    high: Number | None = None
    source: str = ""

    @model_validator(mode="after")
    def _check(self) -> _Parameter:
        Distribution(self.distribution, self.mean, self.std, self.low, self.high)  # raises ValueError
        return self


class _Limit(StrictModel):
    shaft: Literal["input", "output"]
    label: str = ""
    Y_max_mm: Annotated[float, Field(gt=0, allow_inf_nan=False, strict=True)] | None = None
    beta_deg: Annotated[float, Field(gt=0, lt=90, allow_inf_nan=False, strict=True)] | None = None
    source: str = ""

    @model_validator(mode="after")
    def _check(self) -> _Limit:
        if (self.Y_max_mm is None) == (self.beta_deg is None):
            raise ValueError("give exactly one of Y_max_mm (β = arcsin(Y_max_mm / L)) or beta_deg")
        return self


class _File(StrictModel):
    schema_version: Literal[1]
    study: _Study
    cases: list[_Case] = []
    parameters: list[_Parameter] = Field(min_length=1)
    limits: list[_Limit] = []


@dataclass(frozen=True)
class ToleratedParameter:
    """One rig parameter with its distribution (values in ``unit``, the unit of the address's key)."""

    address: str
    unit: str
    distribution: Distribution
    source: str


@dataclass(frozen=True)
class BetaLimit:
    """A tilt limit of one shaft: P(β > beta_deg) is reported."""

    shaft: str
    label: str
    beta_deg: float
    y_max_mm: float | None
    source: str


@dataclass(frozen=True)
class Tolerances:
    """A validated tolerance file."""

    source: str
    text: str
    name: str
    description: str
    measured_from: str | None
    confidence_level: float
    cases: tuple[LoadCase, ...]
    parameters: tuple[ToleratedParameter, ...]
    limits: tuple[BetaLimit, ...]

    @property
    def addresses(self) -> tuple[str, ...]:
        return tuple(p.address for p in self.parameters)

    @property
    def distributions(self) -> tuple[Distribution, ...]:
        return tuple(p.distribution for p in self.parameters)


def unit_of(address: str) -> str:
    """The unit named at the end of an address's key ('' for a dimensionless key)."""
    key = re.sub(r"\[\d+\]$", "", address.rsplit(".", 1)[-1])
    for suffix in sorted(UNIT_SUFFIXES, key=len, reverse=True):
        if key.endswith("_" + suffix):
            return suffix
    return ""


def _parts_address(address: str) -> tuple[str, str] | None:
    """(part, key) of a ``parts.<part>.<key>`` address, else None."""
    if not address.startswith("parts."):
        return None
    item, _, key = address[len("parts."):].rpartition(".")
    return item, key


def parameter_value(rig: Rig, address: str) -> float:
    """The rig's current (nominal) value at ``address``; a diameter deviation is 0.

    Parameters
    ----------
    rig : Rig
        A validated rig.
    address : str
        A rig-file address (``bearings.input_B1.radial_stiffness_N_per_um``).

    Returns
    -------
    float
        The value, in the unit its key names.
    """
    parts = _parts_address(address)
    if parts is None:
        return get_parameter(rig, address)
    name, key = parts
    if key != PART_DEVIATION_KEY:
        raise KeyError(f"'parts.{name}' has no toleranced key '{key}' (only {PART_DEVIATION_KEY})")
    rig.part(name)  # KeyError for an unknown part
    return 0.0


def apply_values(rig: Rig, values: dict[str, float]) -> Rig:
    """A copy of ``rig`` with the toleranced parameters set (validated again; the original is unchanged)."""
    deviations = {}
    others = {}
    for address, value in values.items():
        parts = _parts_address(address)
        if parts is None:
            others[address] = value
        else:
            parameter_value(rig, address)
            deviations[parts[0]] = float(value)
    changed = with_parameters(rig, others) if others else rig
    if not deviations:
        return changed
    data = changed.model_dump(by_alias=True)
    for part in data["parts"]:
        if part["name"] in deviations:
            for segment in part["segments"]:
                segment["outer_diameter_mm"] = float(segment["outer_diameter_mm"] + deviations[part["name"]])
    return Rig.model_validate(data)


def _normalise_units(raw: list, problems: list[str]) -> list:
    """Turn ``mean_<unit>`` keys into ``mean`` after checking the unit against the address's key."""
    out = []
    for i, item in enumerate(raw):
        if not isinstance(item, dict) or not isinstance(item.get("address"), str):
            out.append(item)
            continue
        expected = unit_of(item["address"])
        where = f"parameters[{i}] ('{item['address']}')"
        converted = {}
        for key, value in item.items():
            match = re.fullmatch(r"(mean|std|low|high)(?:_(\w+))?", key)
            if match is None:
                converted[key] = value
                continue
            unit = match[2] or ""
            if unit != expected:
                wanted = f"{match[1]}_{expected}" if expected else match[1]
                unit_text = f"unit {unit}" if unit else "no unit"
                expected_text = f"in {expected}" if expected else "dimensionless"
                problems.append(f"{where}.{key}: {unit_text}, but the parameter is {expected_text}; write {wanted}")
                continue
            converted[match[1]] = value
        out.append(converted)
    return out


def _statistic_key(location: tuple, key: str, data) -> str:
    """A parameter's statistic as the file writes it, with the unit of its address: ``mean`` → ``mean_um``."""
    if len(location) >= 3 and location[0] == "parameters" and isinstance(location[1], int) and location[2] in STATISTICS:
        try:
            address = data["parameters"][location[1]].get("address")
        except (IndexError, AttributeError, KeyError, TypeError):
            address = None
        if address:
            unit = unit_of(address)
            return key.rsplit(".", 1)[0] + f".{location[2]}" + (f"_{unit}" if unit else "")
    return key


UNKNOWN_KEY = "statistics are mean/std/low/high with the parameter's unit, e.g. mean_um"


def _check_against_rig(parsed: _File, rig: Rig) -> list[str]:
    problems = []
    seen = set()
    for i, p in enumerate(parsed.parameters):
        where = f"parameters[{i}] ('{p.address}')"
        if p.address in seen:
            problems.append(f"{where}.address: the same parameter is toleranced twice")
        seen.add(p.address)
        try:
            parameter_value(rig, p.address)
        except KeyError as error:
            problems.append(f"{where}.address: {error.args[0]}")
            continue
        distribution = Distribution(p.distribution, p.mean, p.std, p.low, p.high)
        for extreme in distribution.extremes:
            try:
                apply_values(rig, {p.address: extreme})
            except ValidationError as error:
                reason = error.errors()[0]["msg"].removeprefix("Value error, ")
                hint = " (use truncated_normal with low/high)" if p.distribution == "normal" else ""
                problems.append(f"{where}: the distribution reaches {extreme:g}, which the rig rejects: {reason}{hint}")
                break
    return problems


def _limit(limit: _Limit, rig: Rig) -> BetaLimit:
    length = getattr(rig.paths, limit.shaft).length_mm
    beta = limit.beta_deg if limit.beta_deg is not None else math.degrees(math.asin(min(limit.Y_max_mm / length, 1.0)))
    label = limit.label or (f"Y_max {limit.Y_max_mm:g} mm" if limit.Y_max_mm is not None else f"beta {limit.beta_deg:g} deg")
    return BetaLimit(limit.shaft, label, float(beta), limit.Y_max_mm, limit.source)


def parse_tolerances(text: str, source: str, rig: Rig) -> Tolerances:
    """Validate a tolerance file's text against ``rig``; raise :class:`ToleranceFileError` naming every problem."""
    problems: list[str] = []

    def prepare(data: dict) -> dict:
        normalised = dict(data)
        if isinstance(data.get("parameters"), list):
            normalised["parameters"] = _normalise_units(data["parameters"], problems)
        return normalised

    parsed = read_toml_model(_File, text, lambda found: ToleranceFileError(source, problems + found), prepare=prepare,
                             unknown_key=UNKNOWN_KEY, rename=_statistic_key)
    if problems:
        raise ToleranceFileError(source, problems)
    problems = _check_against_rig(parsed, rig)
    pairs = [(c.T1_input_Nm, c.T2_output_Nm) for c in parsed.cases] or list(DEFAULT_CASES)
    try:
        cases = paired_cases([a for a, _ in pairs], [b for _, b in pairs], source=f"{source} [[cases]]")
    except LoadCaseError as error:
        problems.append(f"cases: {error}")
    if problems:
        raise ToleranceFileError(source, problems)
    parameters = tuple(
        ToleratedParameter(p.address, unit_of(p.address), Distribution(p.distribution, p.mean, p.std, p.low, p.high),
                           p.source)
        for p in parsed.parameters
    )
    study = parsed.study
    return Tolerances(source=source, text=text, name=study.name, description=study.description,
                      measured_from=study.measured_from, confidence_level=study.confidence_level, cases=cases,
                      parameters=parameters, limits=tuple(_limit(x, rig) for x in parsed.limits))


def load_tolerances(path: str | Path, rig: Rig) -> Tolerances:
    """Read and validate a tolerance file against ``rig``.

    Parameters
    ----------
    path : str or Path
        The tolerance TOML file (``docs/tolerances.md``).
    rig : Rig
        The rig whose rig-file addresses the tolerances name.

    Returns
    -------
    Tolerances
        The parameters with their distributions, the β limits and the study settings.

    Raises
    ------
    ToleranceFileError
        Naming the file, the key and the reason.
    """
    source = str(path)
    try:
        text = read_input_text(path, MAX_TOLERANCE_FILE_BYTES, "a tolerance file")
    except InputFileError as error:
        raise ToleranceFileError(source, [str(error)]) from None
    return parse_tolerances(text, source, rig)


def study_rig(rig: Rig, tolerances: Tolerances) -> Rig:
    """``rig`` with the tolerance file's ``measured_from`` (if it sets one)."""
    if tolerances.measured_from is None or tolerances.measured_from == rig.paths.measured_from:
        return rig
    return rig.model_copy(update={"paths": rig.paths.model_copy(update={"measured_from": tolerances.measured_from})})

