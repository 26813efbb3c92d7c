"""Paper 000's coaxiality–transmission-chain error vector model of an RV reducer.

Paper 000 sums the torsion of four parts of the reducer, each referred to the output:

    θ11 = θ1 / i16          input (sun gear) shaft, a four-stage hollow shaft
    θ22 = 2 θ2 / Z4         the two crankshafts, eight stages each
    θ44 = θ4                output disk, three stages
    θ55 = 40 Z5 / Z4 θ5     a pin of the pin gear (40 pins)

and, turning clockwise as positive, θ_total = θ22 − θ11 − θ44 − θ55 (the ``sign`` of each
component in the stage data file). The twist of a part is the sum of its stages' twists; stage k of
length L_k, outer diameter d_k and bore d_kk carries the torque of its average force F_k on the
moment arm r_k:

    θ_k = T_k L_k / (G J_k),   T_k = F_k r_k,   J_k = π (d_k⁴ − d_kk⁴) / 32
    r_k = tan β · (x_k + a / cos β) + d_k / 2

with x_k = (l_k + l_{k−1}) / 2 the stage's mid-length from the part's start (l_k the length up to the
end of stage k) and β, a the tilt and radial offset of the shaft (the coaxiality terms; internal parts
have β = 0). In degrees per metre of length this is the paper's ``7350 T / d⁴`` (T in N·m, d in mm):
7350 = 180/π · 32 / (π G) with G = 79.4 GPa; here G comes from each part's material
(:func:`torsion_constant_deg_per_m`).

Where we read the printed formulas (see the README): the moment-arm vector is printed squared, which
would not give an angle; we use it to the first power, which is a torque, and which is exactly what
the printed crankshaft formula is (``7350 / (Z4 L) Σ F_k L_k / d_k³`` = 2/Z4 · Σ 7350 F_k (d_k/2)
L_k / d_k⁴, with "L" = 1000 mm/m converting the arm to metres). The printed pin formula
``20 Z5 F / (Z4 d³)`` omits the constant and the length; we use its base form 40 Z5/Z4 θ5.

Units: inputs in mm, N and degrees as in the files; the computation is SI; results in degrees.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import Field

from rvcoax.errors import RvcoaxError, problems_text
from rvcoax.geometry.inputfiles import InputFileError, csv_rows, plain_number
from rvcoax.geometry.schema import Part, Rig
from rvcoax.geometry.validation import StrictModel, read_toml_model
from rvcoax.results.io.datafiles import read_data_text

__all__ = ["COAXIALITY_SOURCES", "ChainDataError", "ChainErrorBudget", "ChainModel", "Coaxiality", "Component",
           "Contribution", "NO_TILT", "NonNegative", "Positive", "Reducer", "STAGE_DATA", "Stage", "evaluate_chain_error",
           "contribution", "load_chain_model", "moment_arms_mm", "read_stage_forces", "rig_stages",
           "shear_modulus_Pa", "signed_total", "stage_midpoints_mm", "stage_twists_deg",
           "torsion_constant_deg_per_m"]

STAGE_DATA = "rv20e_chain_stages.toml"
COAXIALITY_SOURCES = ("input", "output", "none")


class ChainDataError(RvcoaxError, ValueError):
    """A stage data file or a forces file that cannot be used; the message names file, key/line and reason."""


# -- stage data file schema ---------------------------------------------------------------------
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False, strict=True)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)]


class _StageEntry(StrictModel):
    length_mm: Positive
    outer_diameter_mm: Positive
    inner_diameter_mm: NonNegative = 0.0


class _Reducer(StrictModel):
    name: str
    ratio_i16: Positive
    cycloid_teeth_Z4: Annotated[int, Field(gt=0, strict=True)]
    pin_teeth_Z5: Annotated[int, Field(gt=0, strict=True)]
    pin_count: Annotated[int, Field(gt=0, strict=True)]


class _MaterialEntry(StrictModel):
    youngs_modulus_MPa: Positive
    poisson_ratio: Annotated[float, Field(gt=-1.0, lt=0.5, strict=True)]


class _ComponentEntry(StrictModel):
    symbol: str
    description: str = ""
    transmission: Literal["1/i16", "2/Z4", "1", "pins*Z5/Z4"]
    sign: Literal[-1, 1]
    coaxiality: Literal["input", "output", "none"]
    rig_part: str | None = None
    material: str | None = None
    stages: list[_StageEntry] | None = None


class _StageFile(StrictModel):
    schema_version: Literal[1]
    reducer: _Reducer
    materials: dict[str, _MaterialEntry] = Field(default_factory=dict)
    components: dict[str, _ComponentEntry] = Field(min_length=1)


# -- model ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Stage:
    """One stage of a stepped shaft (mm)."""

    length_mm: float
    outer_diameter_mm: float
    inner_diameter_mm: float = 0.0

    @property
    def polar_moment_m4(self) -> float:
        """J = π (d⁴ − d_bore⁴) / 32 in m⁴."""
        return math.pi / 32.0 * ((self.outer_diameter_mm * 1e-3) ** 4 - (self.inner_diameter_mm * 1e-3) ** 4)


@dataclass(frozen=True)
class Component:
    """A part of the transmission chain and how its twist reaches the output.

    Attributes
    ----------
    name, symbol, description : str
        Key in the stage data file (``input_shaft``), the paper's symbol (``θ11``), a description.
    stages : tuple of Stage
        From the part's input-side end.
    shear_modulus_Pa : float
        G of the part's material.
    material : str
    transmission : str
        The paper's transfer to the output: ``1/i16``, ``2/Z4``, ``1`` or ``pins*Z5/Z4``.
    transmission_factor : float
        Its value for the reducer.
    sign : int
        Sign of the contribution in the total (paper 000: clockwise positive).
    coaxiality : str
        Whose tilt and offset enter the moment arms: ``input``, ``output`` or ``none``.
    """

    name: str
    symbol: str
    description: str
    stages: tuple[Stage, ...]
    shear_modulus_Pa: float
    material: str
    transmission: str
    transmission_factor: float
    sign: int
    coaxiality: str


@dataclass(frozen=True)
class Reducer:
    """Tooth counts and ratio of the reducer."""

    name: str
    ratio_i16: float
    cycloid_teeth_Z4: int
    pin_teeth_Z5: int
    pin_count: int

    def transmission_factor(self, transmission: str) -> float:
        """Value of a transfer keyword of the stage data file."""
        return {
            "1/i16": 1.0 / self.ratio_i16,
            "2/Z4": 2.0 / self.cycloid_teeth_Z4,
            "1": 1.0,
            "pins*Z5/Z4": self.pin_count * self.pin_teeth_Z5 / self.cycloid_teeth_Z4,
        }[transmission]


@dataclass(frozen=True)
class ChainModel:
    """The reducer and its chain components, with where the data came from."""

    reducer: Reducer
    components: tuple[Component, ...]
    source: str

    def component(self, name: str) -> Component:
        for c in self.components:
            if c.name == name:
                return c
        raise KeyError(name)


@dataclass(frozen=True)
class Coaxiality:
    """Tilt β (degrees) and radial offset a (mm) of a shaft, paper 000's coaxiality terms."""

    beta_deg: float = 0.0
    offset_mm: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.beta_deg) and abs(self.beta_deg) < 90.0):
            raise ValueError(f"tilt beta must be finite and below 90°, got {self.beta_deg}")
        if not math.isfinite(self.offset_mm):
            raise ValueError(f"radial offset a must be finite, got {self.offset_mm}")


NO_TILT = Coaxiality()


@dataclass(frozen=True)
class Contribution:
    """One component's error vector θ at the output (degrees, before its sign in the total)."""

    component: Component
    coaxiality: Coaxiality
    forces_N: np.ndarray
    arms_mm: np.ndarray
    stage_twists_deg: np.ndarray
    value_deg: float
    baseline_deg: float

    @property
    def twist_deg(self) -> float:
        """Twist of the part itself (sum of its stages), before the transfer to the output."""
        return float(self.stage_twists_deg.sum())

    @property
    def coaxiality_part_deg(self) -> float:
        """What the tilt and offset add to the error vector (value − value at β = 0)."""
        return self.value_deg - self.baseline_deg

    @property
    def signed_deg(self) -> float:
        return self.component.sign * self.value_deg


@dataclass(frozen=True)
class ChainErrorBudget:
    """The chain-error budget of a load case: every contribution and the total, θ_total = Σ sign · θ."""

    contributions: tuple[Contribution, ...]
    total_deg: float
    baseline_total_deg: float


# -- formulas ------------------------------------------------------------------------------------
def shear_modulus_Pa(youngs_modulus_MPa: float, poisson_ratio: float) -> float:
    """G = E / (2 (1 + ν)) in Pa."""
    return youngs_modulus_MPa * 1e6 / (2.0 * (1.0 + poisson_ratio))


def torsion_constant_deg_per_m(shear_modulus: float) -> float:
    """The constant C of φ = C T / d⁴ (φ in °/m, T in N·m, d in mm) of a round shaft: 180/π · 32 / (π G).

    Paper 000's 7350 is this constant for G = 79.4 GPa.

    Parameters
    ----------
    shear_modulus : float
        G in Pa.

    Returns
    -------
    float
        C in (°/m) · mm⁴ / (N·m).
    """
    return 180.0 / math.pi * 32.0 / (math.pi * shear_modulus) * 1e12


def stage_midpoints_mm(stages: tuple[Stage, ...]) -> np.ndarray:
    """x_k = (l_k + l_{k−1}) / 2: mid-length of each stage from the part's start (mm)."""
    ends = np.cumsum([s.length_mm for s in stages])
    return (ends + np.concatenate([[0.0], ends[:-1]])) / 2.0


def moment_arms_mm(stages: tuple[Stage, ...], coaxiality: Coaxiality = NO_TILT) -> np.ndarray:
    """r_k = tan β · (x_k + a / cos β) + d_k / 2 for each stage (mm)."""
    beta = math.radians(coaxiality.beta_deg)
    radii = np.array([s.outer_diameter_mm / 2.0 for s in stages])
    return math.tan(beta) * (stage_midpoints_mm(stages) + coaxiality.offset_mm / math.cos(beta)) + radii


def stage_twists_deg(component: Component, forces_N, coaxiality: Coaxiality = NO_TILT) -> np.ndarray:
    """θ_k = F_k r_k L_k / (G J_k) of each stage, in degrees."""
    forces = np.asarray(forces_N, dtype=float)
    if forces.shape != (len(component.stages),):
        raise ValueError(f"{component.name}: {forces.size} forces for {len(component.stages)} stages")
    arms_m = moment_arms_mm(component.stages, coaxiality) * 1e-3
    lengths_m = np.array([s.length_mm for s in component.stages]) * 1e-3
    polar = np.array([s.polar_moment_m4 for s in component.stages])
    return np.degrees(forces * arms_m * lengths_m / (component.shear_modulus_Pa * polar))


def contribution(component: Component, forces_N, coaxiality: Coaxiality = NO_TILT) -> Contribution:
    """The component's error vector at the output: transmission factor × the sum of its stage twists."""
    if component.coaxiality == "none":
        coaxiality = NO_TILT
    twists = stage_twists_deg(component, forces_N, coaxiality)
    baseline = stage_twists_deg(component, forces_N, NO_TILT)
    return Contribution(component=component, coaxiality=coaxiality, forces_N=np.asarray(forces_N, dtype=float),
                        arms_mm=moment_arms_mm(component.stages, coaxiality), stage_twists_deg=twists,
                        value_deg=component.transmission_factor * float(twists.sum()),
                        baseline_deg=component.transmission_factor * float(baseline.sum()))


def signed_total(values_deg: Mapping[str, float], signs: Mapping[str, int]) -> float:
    """θ_total = Σ sign · θ over the components (paper 000: θ22 − θ11 − θ44 − θ55)."""
    return float(sum(signs[name] * value for name, value in values_deg.items()))


def evaluate_chain_error(model: ChainModel, forces_N: Mapping[str, np.ndarray], input_shaft: Coaxiality = NO_TILT,
                         output_shaft: Coaxiality = NO_TILT) -> ChainErrorBudget:
    """Each component's error vector and the total, with the shafts' tilts and offsets.

    Parameters
    ----------
    model : ChainModel
    forces_N : mapping
        Per component name, the average force on each stage (N); a missing component carries none.
    input_shaft, output_shaft : Coaxiality
        β and a of the rig's input and output shafts (components with ``coaxiality = "none"``
        ignore them).

    Returns
    -------
    ChainErrorBudget
        Every component's contribution θ, θ_total, and θ_total with the shafts untilted (baseline), in degrees.
    """
    tilts = {"input": input_shaft, "output": output_shaft, "none": NO_TILT}
    parts = tuple(
        contribution(c, forces_N.get(c.name, np.zeros(len(c.stages))), tilts[c.coaxiality])
        for c in model.components
    )
    signs = {p.component.name: p.component.sign for p in parts}
    return ChainErrorBudget(parts, signed_total({p.component.name: p.value_deg for p in parts}, signs),
                      signed_total({p.component.name: p.baseline_deg for p in parts}, signs))


# -- reading -------------------------------------------------------------------------------------
def rig_stages(part: Part) -> tuple[Stage, ...]:
    """A rig part's segments as stages, adjacent segments with the same section merged."""
    stages: list[Stage] = []
    for segment in sorted(part.segments, key=lambda s: s.x_mm[0]):
        length = segment.x_mm[1] - segment.x_mm[0]
        previous = stages[-1] if stages else None
        if (previous is not None and previous.outer_diameter_mm == segment.outer_diameter_mm
                and previous.inner_diameter_mm == segment.inner_diameter_mm):
            stages[-1] = Stage(previous.length_mm + length, previous.outer_diameter_mm, previous.inner_diameter_mm)
        else:
            stages.append(Stage(length, segment.outer_diameter_mm, segment.inner_diameter_mm))
    return tuple(stages)


def _component(name: str, entry: _ComponentEntry, data: _StageFile, rig: Rig, source: str,  # noqa: PLR0913
               *, reducer: Reducer) -> Component:
    def problem(text: str) -> ChainDataError:
        return ChainDataError(problems_text("stage data", source, [f"components.{name}: {text}"]))

    if (entry.rig_part is None) == (entry.stages is None):
        raise problem("give either rig_part (stages from the rig) or stages, not both or neither")
    if entry.rig_part is not None:
        parts = {p.name: p for p in rig.parts}
        if entry.rig_part not in parts:
            raise problem(f"rig_part '{entry.rig_part}' is not a part of the rig (parts: {', '.join(parts)})")
        part = parts[entry.rig_part]
        stages, material = rig_stages(part), entry.material or part.material
    else:
        if not entry.stages:
            raise problem("stages is empty")
        stages = tuple(Stage(s.length_mm, s.outer_diameter_mm, s.inner_diameter_mm) for s in entry.stages)
        if entry.material is None:
            raise problem("material is required when the stages are given here")
        material = entry.material
    for k, stage in enumerate(stages, start=1):
        if not stage.inner_diameter_mm < stage.outer_diameter_mm:
            raise problem(f"stage {k}: inner_diameter_mm must be below outer_diameter_mm")
    if material in data.materials:
        properties = data.materials[material]
    elif material in rig.materials:
        properties = rig.materials[material]
    else:
        known = sorted(set(data.materials) | set(rig.materials))
        raise problem(f"material '{material}' is neither in the stage data nor in the rig (known: {', '.join(known)})")
    return Component(name=name, symbol=entry.symbol, description=entry.description, stages=stages,
                     shear_modulus_Pa=shear_modulus_Pa(properties.youngs_modulus_MPa, properties.poisson_ratio),
                     material=material, transmission=entry.transmission,
                     transmission_factor=reducer.transmission_factor(entry.transmission), sign=entry.sign,
                     coaxiality=entry.coaxiality)


def load_chain_model(rig: Rig, path: str | Path | None = None) -> ChainModel:
    """Read a stage data file (default: the built-in RV-20E file), taking rig parts' stages from ``rig``.

    Parameters
    ----------
    rig : Rig
        The rig whose shafts and reducer parts the stages belong to.
    path : str or Path, optional
        A stage data TOML file (``results/data/rv20e_chain_stages.toml`` is the example).

    Returns
    -------
    ChainModel
        The reducer, its components and stages with their diameters, lengths, moment arms and moduli.

    Raises
    ------
    ChainDataError
        Naming the file, the key and the reason.
    """
    source, text = read_data_text(path, STAGE_DATA, ChainDataError, "stage data")
    data = read_toml_model(_StageFile, text, lambda problems: ChainDataError(problems_text("stage data", source, problems)))
    r = data.reducer
    reducer = Reducer(r.name, r.ratio_i16, r.cycloid_teeth_Z4, r.pin_teeth_Z5, r.pin_count)
    components = tuple(_component(name, entry, data, rig, source, reducer=reducer)
                       for name, entry in data.components.items())
    return ChainModel(reducer, components, source)


def read_stage_forces(path: str | Path, model: ChainModel) -> dict[str, np.ndarray]:
    """Average force per stage from a CSV with columns ``component, stage, force_N`` (others ignored).

    ``stage`` is 1-based; stages not listed carry no force. Errors name the file, line and reason.

    Parameters
    ----------
    path : str or Path
        The forces CSV (``results/data/paper000_chain_forces.csv`` is paper 000's).
    model : ChainModel
        From :func:`load_chain_model`: the components and stages the file may name.

    Returns
    -------
    dict of str to ndarray
        Component name → force per stage (N).

    Raises
    ------
    ChainDataError
        Naming the file, the line and the reason.
    """
    source, text = read_data_text(path, "", ChainDataError, "forces file")

    def problem(reason: str) -> ChainDataError:  # the one form of an input file's message
        return ChainDataError(problems_text("forces file", source, [reason]))

    try:
        numbered = [(line, cells) for line, cells in csv_rows(text, comment="#") if any(c.strip() for c in cells)]
    except InputFileError as error:
        raise problem(str(error)) from None
    header = [h.strip() for h in numbered[0][1]] if numbered else []
    missing = [c for c in ("component", "stage", "force_N") if c not in header]
    if missing:
        raise problem(f"line {numbered[0][0] if numbered else 1}: missing column(s) {', '.join(missing)} "
                      "(columns: component, stage, force_N)")
    forces = {c.name: np.zeros(len(c.stages)) for c in model.components}
    seen: set[tuple[str, int]] = set()
    for line, cells in numbered[1:]:
        where = f"line {line}"
        row = dict(zip(header, cells))
        if len(cells) < len(header):
            raise problem(f"{where}: {len(cells)} values for {len(header)} columns")
        name = row["component"].strip()
        if name not in forces:
            raise problem(f"{where}: unknown component '{name}' (known: {', '.join(forces)})")
        stage_text = row["stage"].strip()
        if not stage_text.isascii() or not stage_text.isdigit():
            raise problem(f"{where}: stage '{stage_text}' is not a whole number (digits 0-9)")
        stage = int(stage_text)
        if not 1 <= stage <= forces[name].size:
            raise problem(f"{where}: stage {stage} of {name} does not exist (1 … {forces[name].size})")
        try:
            value = plain_number(row["force_N"])
        except ValueError as error:
            raise problem(f"{where}: force_N: {error}") from None
        if (name, stage) in seen:
            raise problem(f"{where}: stage {stage} of {name} is given twice")
        seen.add((name, stage))
        forces[name][stage - 1] = value
    if not seen:
        raise problem("no forces")
    return forces
