"""Plausible ranges of rig-file values per component kind, and the warnings for values outside them.

A value outside its range is not refused (a special rig may need it) but warned about, with the
rig-file key, the value, the range and the likely unit slip: a bearing stiffness typed in N/m into
an ``_N_per_um`` key (8e7 "N/µm") changes Y by tens of percent without a word otherwise. The ranges
are deliberately wide — a warning means "probably a mistake", not "unusual":

- rolling bearings, radial: 1 … 5000 N/µm (deep-groove ball bearings of 10–50 mm bore are about
  20–300 N/µm, large roller bearings up to a few thousand; Harris & Kotzalas, catalogue rigidity data);
- couplings: bellows/disc/jaw couplings of 1–1000 N·m rating, from datasheets (radial 10 … 1e6 N/mm,
  angular 1 … 1e6 N·m/rad, torsional 100 … 1e7 N·m/rad, axial 1 … 1e6 N/mm);
- mounts and joints: a bolted foot or flange is 1 … 1e5 N/µm and 1e2 … 1e9 N·m/rad (zero means a free
  direction and is not checked);
- materials: metals and engineering polymers, E 1e3 … 5e5 MPa, ν 0.1 … 0.45, ρ 500 … 25 000 kg/m³;
- a body's mass against its segments' volume × density: 0.05 … 20 times (a housing is a hollow or
  finned body drawn as an equivalent round one).

Topology that solves but means something else than intended is warned about too: a torque applied
on a housing (a ``body``), a bearing whose shaft and housing roles are swapped, and a torque-driven
lateral load that is reacted on the part it acts on (it cancels itself).
"""

from __future__ import annotations

from dataclasses import dataclass

from rvcoax.geometry.schema import Rig

__all__ = ["CATALOGUE", "MASS_TO_VOLUME_RANGE", "PlausibleRange", "plausibility_warnings", "plausible_range"]


@dataclass(frozen=True)
class PlausibleRange:
    """The range of one rig-file key for one kind of component.

    Attributes
    ----------
    kind : str
        Component kind (``bearing``, ``coupling``, ``mount``, ``joint``, ``material``, ``part``).
    key : str
        The rig-file key (its unit is in its name).
    low, high : float
        The plausible range in the key's unit.
    unit : str
        The unit, as printed.
    slips : tuple of (float, str)
        ``(factor, hint)``: when ``value * factor`` lies in the range, ``hint`` names the likely slip.
    zero_allowed : bool
        Zero means "no stiffness in this direction" and is not warned about.
    """

    kind: str
    key: str
    low: float
    high: float
    unit: str
    slips: tuple[tuple[float, str], ...] = ()
    zero_allowed: bool = False


_PER_UM = ((1e-6, "written in N/m?"), (1e-3, "written in N/mm?"))
_PER_MM = ((1e-3, "written in N/m?"), (1e3, "written in N/µm?"))
_PER_RAD = ((1e-3, "written in N·mm/rad?"), (1e3, "written in kN·m/rad?"))

CATALOGUE = (
    PlausibleRange("bearing", "radial_stiffness_N_per_um", 1.0, 5000.0, "N/µm", _PER_UM),
    PlausibleRange("bearing", "axial_stiffness_N_per_um", 0.5, 5000.0, "N/µm", _PER_UM, zero_allowed=True),
    PlausibleRange("bearing", "tilt_stiffness_Nm_per_rad", 1.0, 1e7, "N·m/rad", _PER_RAD, zero_allowed=True),
    PlausibleRange("coupling", "radial_stiffness_N_per_mm", 10.0, 1e6, "N/mm", _PER_MM),
    PlausibleRange("coupling", "angular_stiffness_Nm_per_rad", 1.0, 1e6, "N·m/rad", _PER_RAD),
    PlausibleRange("coupling", "torsional_stiffness_Nm_per_rad", 100.0, 1e7, "N·m/rad", _PER_RAD),
    PlausibleRange("coupling", "axial_stiffness_N_per_mm", 1.0, 1e6, "N/mm", _PER_MM),
    PlausibleRange("mount", "translational_stiffness_N_per_um", 1.0, 1e5, "N/µm", _PER_UM, zero_allowed=True),
    PlausibleRange("mount", "rotational_stiffness_Nm_per_rad", 100.0, 1e9, "N·m/rad", _PER_RAD, zero_allowed=True),
    PlausibleRange("joint", "translational_stiffness_N_per_um", 1.0, 1e5, "N/µm", _PER_UM, zero_allowed=True),
    PlausibleRange("joint", "rotational_stiffness_Nm_per_rad", 0.1, 1e9, "N·m/rad", _PER_RAD, zero_allowed=True),
    PlausibleRange("material", "youngs_modulus_MPa", 1e3, 5e5, "MPa", ((1e-6, "written in Pa?"), (1e3, "written in GPa?"))),
    PlausibleRange("material", "poisson_ratio", 0.1, 0.45, ""),
    PlausibleRange("material", "density_kg_per_m3", 500.0, 25000.0, "kg/m³", ((1e3, "written in g/cm³?"),)),
)
MASS_TO_VOLUME_RANGE = (0.05, 20.0)  # a body's mass_kg over its segments' volume × density


def plausible_range(kind: str, key: str) -> PlausibleRange:
    """The catalogue row of ``key`` for a component of ``kind`` (KeyError if there is none)."""
    for row in CATALOGUE:
        if row.kind == kind and row.key == key:
            return row
    raise KeyError(f"{kind}.{key}")


def _value_warning(where: str, row: PlausibleRange, value: float) -> str | None:
    if (row.zero_allowed and value == 0.0) or row.low <= value <= row.high:
        return None
    hint = next((h for factor, h in row.slips if row.low <= value * factor <= row.high), None)
    unit = f" {row.unit}" if row.unit else ""
    return (f"{where}.{row.key} = {value:g}{unit} is outside the plausible range of a {row.kind} "
            f"({row.low:g} … {row.high:g}{unit})" + (f": {hint}" if hint else ""))


def _component_warnings(rig: Rig) -> list[str]:
    found = []
    for kind, table, items in (("bearing", "bearings", rig.bearings), ("coupling", "couplings", rig.couplings),
                               ("mount", "mounts", rig.mounts), ("joint", "joints", rig.joints)):
        rows = [r for r in CATALOGUE if r.kind == kind]
        for i, item in enumerate(items):
            where = f"{table}[{i}] ('{item.name}')"
            for row in rows:
                values = getattr(item, row.key)
                for value in (values if isinstance(values, tuple | list) else (values,)):
                    message = _value_warning(where, row, float(value))
                    if message:
                        found.append(message)
                        break  # one warning per key
    for name, material in rig.materials.items():
        for row in (r for r in CATALOGUE if r.kind == "material"):
            message = _value_warning(f"materials.{name}", row, float(getattr(material, row.key)))
            if message:
                found.append(message)
    return found


def _mass_warnings(rig: Rig) -> list[str]:
    found = []
    low, high = MASS_TO_VOLUME_RANGE
    for i, part in enumerate(rig.parts):
        if part.mass_kg is None or part.material not in rig.materials:
            continue
        solid_kg = sum(s.volume_mm3 for s in part.segments) * 1e-9 * rig.materials[part.material].density_kg_per_m3
        if solid_kg > 0 and not low <= part.mass_kg / solid_kg <= high:
            found.append(f"parts[{i}] ('{part.name}').mass_kg = {part.mass_kg:g} kg is {part.mass_kg / solid_kg:.3g} times "
                         f"its segments' volume × density ({solid_kg:.3g} kg); plausible {low:g} … {high:g} times "
                         "(a mass in g, or segments in m?)")
    return found


def _topology_warnings(rig: Rig) -> list[str]:
    roles = {p.name: p.role for p in rig.parts}
    found = []
    for name in ("T1", "T2"):
        torque = getattr(rig.torques, name)
        if roles.get(torque.part) == "body":
            found.append(f"torques.{name}.part = '{torque.part}' is a housing (role body): a drive or brake torque "
                         "enters the rig through a shaft; on a housing it only loads its mounts")
    for i, bearing in enumerate(rig.bearings):
        if roles.get(bearing.shaft) == "body" and roles.get(bearing.housing) == "shaft":
            found.append(f"bearings[{i}] ('{bearing.name}'): shaft = '{bearing.shaft}' is a housing (role body) and "
                         f"housing = '{bearing.housing}' is a shaft: are shaft and housing swapped?")
    for i, load in enumerate(rig.torque_lateral_loads):
        if load.reacted_on is not None and load.reacted_on.part == load.on.part:
            found.append(f"torque_lateral_loads[{i}] ('{load.name}'): on.part and reacted_on.part are both "
                         f"'{load.on.part}': the force pair acts and reacts on one part and cancels there "
                         "(react it on the housing or support that carries it)")
    return found


def plausibility_warnings(rig: Rig) -> list[str]:
    """One sentence per rig-file value outside its catalogue range, and per suspicious topology.

    Each sentence names the key (``bearings[4] ('input_B1').radial_stiffness_N_per_um``), the value
    with its unit, the plausible range and, where a unit factor would bring the value into range,
    the likely slip. Empty for a plausible rig (the built-in reference rig among them).
    """
    return _component_warnings(rig) + _mass_warnings(rig) + _topology_warnings(rig)
