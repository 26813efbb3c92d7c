"""Small closed-form test rigs built through the rig schema: steel shafts and bodies, clamps and mounts.

Shared by the closed-form tests of the effects, the housings and the temperatures.
"""

from __future__ import annotations

from frames import POISSON, YOUNGS_MODULUS

from rvcoax.fem.system import factorize
from rvcoax.geometry.model.loads import REST_LOADS
from rvcoax.geometry.model.system import assemble_beam
from rvcoax.geometry.schema import Rig

__all__ = ["CLAMP", "D", "HUGE", "HUGE_ROTATION", "L", "MM", "STEEL", "UM", "body", "make_rig", "mount",
           "rest_displacement", "shaft", "value"]

MM, UM = 1e-3, 1e-6
STEEL = {"youngs_modulus_MPa": YOUNGS_MODULUS / 1e6, "poisson_ratio": POISSON, "density_kg_per_m3": 7850.0}
HUGE, HUGE_ROTATION = 1e9, 1e13  # N/µm and N·m/rad: a clamp whose compliance is below 1e-9 of anything measured
CLAMP = {"translational_stiffness_N_per_um": [HUGE] * 3, "rotational_stiffness_Nm_per_rad": [HUGE_ROTATION] * 3}
L, D = 200.0, 20.0  # mm: the cantilevers


def shaft(name: str, x0: float, x1: float, diameter: float = D) -> dict:
    return {"name": name, "role": "shaft", "material": "steel",
            "segments": [{"x_mm": [x0, x1], "outer_diameter_mm": diameter}]}


def body(name: str, x0: float, x1: float, diameter: float) -> dict:
    return {"name": name, "role": "body", "material": "steel", "mass_kg": 1.0,
            "segments": [{"x_mm": [x0, x1], "outer_diameter_mm": diameter}]}


def mount(name: str, part: str, x: float, stiffness=None, rotational=None, offset_um: float = 0.0) -> dict:
    entry = {"name": name, "part": part, "x_mm": x,
             "translational_stiffness_N_per_um": stiffness or CLAMP["translational_stiffness_N_per_um"],
             "rotational_stiffness_Nm_per_rad": rotational or CLAMP["rotational_stiffness_Nm_per_rad"]}
    if offset_um:
        entry["vertical_offset_um"] = offset_um
    return entry


def make_rig(parts: list[dict], input_part: str, output_part: str, **groups) -> Rig:
    """A validated rig of ``parts``; T1 and T2 act at the start of the input part; Y from the unloaded geometry."""
    spans = {p["name"]: p["segments"][0]["x_mm"] for p in parts}

    def path(name):
        x0, x1 = spans[name]
        return {"part": name, "x_start_mm": x0, "length_mm": x1 - x0}

    start = {"part": input_part, "x_mm": spans[input_part][0]}
    data = {"schema_version": 1, "rig": {"name": "closed-form test rig"}, "gravity": {"enabled": False},
            "materials": {"steel": STEEL}, "parts": parts, "torques": {"T1": start, "T2": start},
            "paths": {"measured_from": "unloaded", "input": path(input_part), "output": path(output_part)}}
    data.update(groups)
    return Rig.model_validate(data)


def rest_displacement(rig: Rig):
    """Beam model and its displacement at rest (self-weight, prestrain, force table)."""
    system = assemble_beam(rig)
    load = sum(system.unit_loads[k] for k in REST_LOADS)
    return system.frame, factorize(system.stiffness, system.elimination).solve(load)


def value(frame, u, part: str, x_mm: float, component: int) -> float:
    return float(u[6 * frame.node(part, x_mm) + component])
