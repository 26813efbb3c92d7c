"""Plausible ranges of rig-file values per component kind, and the warnings for values outside them.

A value outside its range is not refused (a special rig may need it) but warned about, with the
rig-file key, the value, the range and the likely unit slip: a bearing stiffness typed in N/m into
an ``_N_per_um`` key (8e7 "N/µm") changes Y by tens of percent without a word otherwise. The ranges
are deliberately wide — a warning means "probably a mistake", not "unusual":

- rolling bearings, radial: 1 … 5000 N/µm (deep-groove ball bearings of 10–50 mm bore are about
  20–300 N/µm, large roller bearings up to a few thousand; Harris & Kotzalas, catalogue rigidity data);
  and for its bore d (the shaft's outer diameter at the bearing): 0.5·d … 100·d N/µm with d in mm
  (:data:`RADIAL_STIFFNESS_PER_BORE`). A deep-groove ball bearing loaded from 1 % to 50 % of its
  dynamic rating is 2·d … 11·d by Palmgren's contact law (:func:`ball_bearing_radial_stiffness_N_per_um`);
  the band leaves a factor 4 below that and room above for roller and preloaded bearings;
- bearing width 2 … 500 mm, coupling hub length 2 … 500 mm, coupling mass 0.005 … 100 kg (zero: the
  hubs' mass is left out); a segment's outer diameter 1 … 3000 mm (a test-rig shaft or housing);
- torque-driven lateral loads: mesh stiffness 10 … 10 000 N/µm (ISO 6336 c′ ≈ 14 N/(mm·µm) times a face
  width of 1 … 700 mm), pitch, crank-circle and arm radii 1 … 2000 mm;
- couplings: bellows/disc/jaw couplings of 1–1000 N·m rating, from datasheets (radial 10 … 1e6 N/mm,
  angular 1 … 1e6 N·m/rad, torsional 100 … 1e7 N·m/rad, axial 1 … 1e6 N/mm);
- mounts and joints: a bolted foot or flange is 1 … 1e5 N/µm and 1e2 … 1e9 N·m/rad (zero means a free
  direction and is not checked);
- materials: metals and engineering polymers, E 1e3 … 5e5 MPa, ν 0.1 … 0.45, ρ 500 … 25 000 kg/m³,
  thermal expansion 4e-6 … 3e-5 1/K (metals);
- a body's mass against its segments' volume × density: 0.05 … 20 times (a housing is a hollow or
  finned body drawn as an equivalent round one).
- rated torques (``rated_torque_Nm``, ``peak_torque_Nm``), judged by what they do to the part rated: a coupling
  twists 1e-5 … 0.3 rad at its rated torque, T / k_t (disc and bellows couplings about 1e-4 … 2e-3 rad, e.g.
  RINGFEDER GWB AKN 30: 36 N·m / 35e3 N·m/rad = 1.0e-3; elastomer and tyre couplings a few degrees); a shaft (a torque
  sensor's measuring shaft) sees a nominal torsional shear 16 T D / (π (D⁴ − d⁴)) of 0.5 … 2000 MPa at its thinnest
  section (a 10 N·m sensor's Ø15 shaft about 15 MPa): a torque in kN·m or N·mm lands outside by 1000 ×.

Topology that solves but means something else than intended is warned about too: a torque applied
on a housing (a ``body``), a bearing whose shaft and housing roles are swapped, and a torque-driven
lateral load that is reacted on the part it acts on (it cancels itself).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rvcoax.geometry.gear_loads import gear_contact_torques, gear_mesh_full_contact_torque
from rvcoax.geometry.schema import Rig

__all__ = ["CATALOGUE", "MASS_TO_VOLUME_RANGE", "PlausibleRange", "RADIAL_STIFFNESS_PER_BORE",
           "ball_bearing_radial_stiffness_N_per_um", "bearing_bore_mm", "plausibility_warnings", "plausible_range"]


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
_LENGTH_MM = ((1e3, "written in m?"), (1e-3, "written in µm?"))

# kind, key, low, high, unit, likely unit slips ((factor, what it suggests), …), zero allowed
_RANGES = (
    ("bearing", "radial_stiffness_N_per_um", 1.0, 5000.0, "N/µm", _PER_UM, False),
    ("bearing", "axial_stiffness_N_per_um", 0.5, 5000.0, "N/µm", _PER_UM, True),
    ("bearing", "tilt_stiffness_Nm_per_rad", 1.0, 1e7, "N·m/rad", _PER_RAD, True),
    ("bearing", "width_mm", 2.0, 500.0, "mm", _LENGTH_MM, False),
    ("coupling", "radial_stiffness_N_per_mm", 10.0, 1e6, "N/mm", _PER_MM, False),
    ("coupling", "angular_stiffness_Nm_per_rad", 1.0, 1e6, "N·m/rad", _PER_RAD, False),
    ("coupling", "torsional_stiffness_Nm_per_rad", 100.0, 1e7, "N·m/rad", _PER_RAD, False),
    ("coupling", "axial_stiffness_N_per_mm", 1.0, 1e6, "N/mm", _PER_MM, False),
    ("coupling", "hub_length_mm", 2.0, 500.0, "mm", _LENGTH_MM, False),
    ("coupling", "mass_kg", 0.005, 100.0, "kg", ((1e-3, "written in g?"),), True),
    ("mount", "translational_stiffness_N_per_um", 1.0, 1e5, "N/µm", _PER_UM, True),
    ("mount", "rotational_stiffness_Nm_per_rad", 100.0, 1e9, "N·m/rad", _PER_RAD, True),
    ("joint", "translational_stiffness_N_per_um", 1.0, 1e5, "N/µm", _PER_UM, True),
    ("joint", "rotational_stiffness_Nm_per_rad", 0.1, 1e9, "N·m/rad", _PER_RAD, True),
    ("torque_lateral_load", "mesh_stiffness_N_per_um", 10.0, 1e4, "N/µm", _PER_UM, False),
    ("torque_lateral_load", "pitch_radius_mm", 1.0, 2000.0, "mm", _LENGTH_MM, False),
    ("torque_lateral_load", "radius_mm", 1.0, 2000.0, "mm", _LENGTH_MM, False),
    ("torque_lateral_load", "arm_length_mm", 1.0, 2000.0, "mm", _LENGTH_MM, False),
    ("segment", "outer_diameter_mm", 1.0, 3000.0, "mm", _LENGTH_MM, False),
    ("material", "youngs_modulus_MPa", 1e3, 5e5, "MPa", ((1e-6, "written in Pa?"), (1e3, "written in GPa?")), False),
    ("material", "poisson_ratio", 0.1, 0.45, "", (), False),
    ("material", "density_kg_per_m3", 500.0, 25000.0, "kg/m³", ((1e3, "written in g/cm³?"),), False),
    # metals 4e-6 (Invar-like steels excluded) … 2.5e-5 (aluminium, zinc); polymers reach 1e-4 but do not carry rigs
    ("material", "thermal_expansion_per_K", 4e-6, 3e-5, "1/K", (), False),
)
CATALOGUE = tuple(PlausibleRange(kind=kind, key=key, low=low, high=high, unit=unit, slips=slips, zero_allowed=zero)
                  for kind, key, low, high, unit, slips, zero in _RANGES)

MASS_TO_VOLUME_RANGE = (0.05, 20.0)  # a body's mass_kg over its segments' volume × density
RADIAL_STIFFNESS_PER_BORE = (0.5, 100.0)  # a rolling bearing's radial stiffness (N/µm) per mm of its bore

# Palmgren's deflection of a steel ball between two steel raceways, δ = c Q^(2/3) / D_w^(1/3) (δ in mm,
# Q in N, D_w in mm), and Stribeck's load on the most loaded ball of a radially loaded bearing with zero
# clearance, Q_max = 4.37 F_r / Z (Harris & Kotzalas, Rolling Bearing Analysis, ch. 6 and 7).
PALMGREN_BALL_MM = 4.36e-4
STRIBECK_ZERO_CLEARANCE = 4.37


def ball_bearing_radial_stiffness_N_per_um(balls: int, ball_diameter_mm: float, radial_load_N: float) -> float:
    """Radial stiffness dF/dδ of a deep-groove ball bearing (zero clearance) under ``radial_load_N``.

    δ_r = δ(Q_max) with Q_max = 4.37 F/Z and δ = 4.36e-4 Q^(2/3) D_w^(-1/3) mm, so δ_r ∝ F^(2/3) and
    k = dF/dδ_r = 1.5 F / δ_r.
    """
    q_max = STRIBECK_ZERO_CLEARANCE * radial_load_N / balls
    deflection_mm = PALMGREN_BALL_MM * q_max ** (2.0 / 3.0) / ball_diameter_mm ** (1.0 / 3.0)
    return 1.5 * radial_load_N / deflection_mm * 1e-3


def bearing_bore_mm(rig: Rig, bearing) -> float | None:
    """The bore of a bearing: the largest outer diameter of its shaft's segments at the bearing's x."""
    try:
        part = rig.part(bearing.shaft)
    except KeyError:
        return None
    here = [s.outer_diameter_mm for s in part.segments if s.x_mm[0] - 1e-9 <= bearing.x_mm <= s.x_mm[1] + 1e-9]
    return max(here) if here else None


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
    return (f"{where}.{row.key} = {value:g}{unit} is outside the plausible range of a {row.kind.replace('_', ' ')} "
            f"({row.low:g} … {row.high:g}{unit})" + (f": {hint}" if hint else ""))


def _component_warnings(rig: Rig) -> list[str]:
    found = []
    for kind, table, items in (("bearing", "bearings", rig.bearings), ("coupling", "couplings", rig.couplings),
                               ("mount", "mounts", rig.mounts), ("joint", "joints", rig.joints),
                               ("torque_lateral_load", "torque_lateral_loads", rig.torque_lateral_loads)):
        rows = [r for r in CATALOGUE if r.kind == kind]
        for i, item in enumerate(items):
            where = f"{table}[{i}] ('{item.name}')"
            for row in rows:
                values = getattr(item, row.key)
                if values is None:  # a key this kind of load does not take
                    continue
                for value in (values if isinstance(values, tuple | list) else (values,)):
                    message = _value_warning(where, row, float(value))
                    if message:
                        found.append(message)
                        break  # one warning per key
    diameter = plausible_range("segment", "outer_diameter_mm")
    for i, part in enumerate(rig.parts):
        for j, segment in enumerate(part.segments):
            message = _value_warning(f"parts[{i}] ('{part.name}').segments[{j}]", diameter, segment.outer_diameter_mm)
            if message:
                found.append(message.replace("range of a segment", "range of a rig part's diameter"))
    for name, material in rig.materials.items():
        for row in (r for r in CATALOGUE if r.kind == "material" and getattr(material, r.key) is not None):
            message = _value_warning(f"materials.{name}", row, float(getattr(material, row.key)))
            if message:
                found.append(message)
    return found


def _bore_warnings(rig: Rig, already: list[str]) -> list[str]:
    """A bearing's radial stiffness against the band for its bore (when the plain range did not warn)."""
    found = []
    low, high = RADIAL_STIFFNESS_PER_BORE
    for i, bearing in enumerate(rig.bearings):
        where = f"bearings[{i}] ('{bearing.name}')"
        bore = bearing_bore_mm(rig, bearing)
        diameter = plausible_range("segment", "outer_diameter_mm")
        if bore is None or not diameter.low <= bore <= diameter.high \
                or any(m.startswith(f"{where}.radial_stiffness_N_per_um") for m in already):
            continue  # no bore, an implausible one (warned about already), or the plain range warned
        row = PlausibleRange(kind="bearing", key="radial_stiffness_N_per_um", low=low * bore, high=high * bore,
                             unit="N/µm", slips=_PER_UM)
        value = bearing.radial_stiffness_N_per_um
        message = _value_warning(where, row, value)
        if message:
            found.append(message.replace("the plausible range of a bearing",
                                         f"the plausible range of a rolling bearing of {bore:g} mm bore (the "
                                         f"shaft's Ø at x = {bearing.x_mm:g} mm)"))
    return found


def _ball_bore_warnings(rig: Rig) -> list[str]:
    """A catalogue bearing (``model = "ball"`` or another model from geometry, ``designation``) whose bore is not
    the shaft's Ø at it."""
    from rvcoax.geometry.ball_bearings import BALL_BEARINGS
    from rvcoax.geometry.rolling_catalogue import normalise_designation, rolling_bearings

    found = []
    for i, bearing in enumerate(rig.bearings):
        bore = bearing_bore_mm(rig, bearing)
        entry = None
        if bearing.designation and bearing.model == "ball":
            entry = BALL_BEARINGS.get(bearing.designation)
        elif bearing.designation and bearing.model != "linear":
            entry = rolling_bearings().get(normalise_designation(bearing.designation))
        if entry is not None and bore is not None and abs(entry.bore_mm - bore) > 0.05 * entry.bore_mm:
            found.append(f"bearings[{i}] ('{bearing.name}').designation = {bearing.designation}: its bore is "
                         f"{entry.bore_mm:g} mm, but the shaft's Ø at x = {bearing.x_mm:g} mm is {bore:g} mm: "
                         "another designation, or the shaft's segment?")
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


COUPLING_TWIST_AT_RATING_RAD = (1e-5, 0.3)
SHAFT_SHEAR_AT_RATING_MPA = (0.5, 2000.0)
_TORQUE_SLIPS = ((1e3, "written in kN·m?"), (1e-3, "written in N·mm?"))


def _rating_warning(stated: str, effect: float, band: tuple[float, float], said: str) -> str | None:
    """``stated`` (``"<where>.<key> = <torque> N·m"``) when ``effect`` (proportional to the torque) lies outside
    ``band``; ``said`` phrases the effect."""
    low, high = band
    if low <= effect <= high:
        return None
    hint = next((h for factor, h in _TORQUE_SLIPS if low <= effect * factor <= high), None)
    return f"{stated} {said.format(effect)}" + (f": {hint}" if hint else "")


def _torque_rating_warnings(rig: Rig) -> list[str]:
    """Rated and peak torques of couplings and shafts whose effect at that torque is implausible (a unit slip)."""
    found = []
    low, high = COUPLING_TWIST_AT_RATING_RAD
    for i, c in enumerate(rig.couplings):
        for key in ("rated_torque_Nm", "peak_torque_Nm"):
            torque = getattr(c, key)
            if torque is not None:
                message = _rating_warning(f"couplings[{i}] ('{c.name}').{key} = {torque:g} N·m",
                                          torque / c.torsional_stiffness_Nm_per_rad, COUPLING_TWIST_AT_RATING_RAD,
                                          f"twists the coupling {{:.2g}} rad (torsional_stiffness_Nm_per_rad = "
                                          f"{c.torsional_stiffness_Nm_per_rad:g}); couplings twist {low:g} … {high:g} "
                                          "rad at their rating")
                found += [message] if message else []
    low, high = SHAFT_SHEAR_AT_RATING_MPA
    for i, part in enumerate(rig.parts):
        # the smallest torsional section modulus W_t = π (D⁴ − d⁴) / (16 D) of its segments, mm³
        modulus = min(math.pi * (s.outer_diameter_mm**4 - (s.inner_diameter_mm or 0.0) ** 4) / (16 * s.outer_diameter_mm)
                      for s in part.segments)
        for key in ("rated_torque_Nm", "peak_torque_Nm"):
            torque = getattr(part, key)
            if torque is not None:
                message = _rating_warning(f"parts[{i}] ('{part.name}').{key} = {torque:g} N·m", torque * 1e3 / modulus,
                                          SHAFT_SHEAR_AT_RATING_MPA,
                                          f"shears the shaft's thinnest section at {{:.2g}} MPa; a measuring shaft "
                                          f"sees {low:g} … {high:g} MPa at its rating")
                found += [message] if message else []
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

    Parameters
    ----------
    rig : Rig
        A validated rig (the reference rig gives no warning).

    Returns
    -------
    list of str
        The warnings, in rig-file order.
    """
    components = _component_warnings(rig)
    return (components + _bore_warnings(rig, components) + _ball_bore_warnings(rig) + _ball_input_warnings(rig)
            + _rolling_preload_warnings(rig) + _mass_warnings(rig) + _topology_warnings(rig)
            + _gear_contact_warnings(rig) + _gear_shape_warnings(rig) + _fit_warnings(rig) + _torque_rating_warnings(rig))


BALL_IGNORED_KEYS = ("radial_stiffness_N_per_um", "axial_stiffness_N_per_um", "tilt_stiffness_Nm_per_rad")
"""Stiffness keys that a ``model = "ball"`` bearing takes only as the linear reference its Newton solve is
condensed on: its answer comes from the ball set, whatever they say."""
NEARLY_POINTED_MODULES = 0.2
"""A tooth tip thinner than this many normal modules is warned about (a common lower limit for the tip
thickness s_a of case-hardened teeth; the tip chips or is cut away)."""


def _ball_input_warnings(rig: Rig) -> list[str]:
    """A ball bearing with typed-in stiffness keys (which the ball model does not use), or an axial preload
    above what a deep-groove ball bearing should carry axially (:data:`rvcoax.geometry.ball_model.PRELOAD_WARNED_C0`)."""
    from rvcoax.geometry import ball_model
    from rvcoax.geometry.rolling_model import load_ratings_N

    found = []
    for i, bearing in enumerate(rig.bearings):
        if bearing.model != "ball":
            continue
        typed = [key for key in BALL_IGNORED_KEYS if key in bearing.model_fields_set]
        if typed:
            found.append(f"bearings[{i}] ('{bearing.name}'): {', '.join(f'{k} = {getattr(bearing, k):g}' for k in typed)} "
                         "is not used by model = \"ball\": its stiffness comes from the ball set, clearance and "
                         "preload (the typed value only sets the linear reference the solve starts from, not the "
                         "answer); remove it, or set model = \"linear\" to use it")
        rating = load_ratings_N(bearing)[1]
        if ball_model.PRELOAD_WARNED_C0 * rating < bearing.preload_N:
            found.append(f"bearings[{i}] ('{bearing.name}').preload_N = {bearing.preload_N:g} N is "
                         f"{bearing.preload_N / rating:.2g} × its static load rating C0 = {rating / 1e3:.3g} kN (ISO 76 "
                         f"from its ball set): a single-row deep groove ball bearing should carry at most "
                         f"{ball_model.PRELOAD_WARNED_C0:g} C0 axially; preloads are a few % of C0")
    return found


def _gear_shape_warnings(rig: Rig) -> list[str]:
    """Gear data that a stage accepts but that are implausible: nearly pointed teeth, a driving gear whose pitch
    circle lies inside the shaft it sits on (its tips still stand out of it; a tip inside is refused)."""
    found = []
    for i, mesh in enumerate(rig.gear_meshes):
        stage = mesh.stage
        for gear, key in ((0, "sun"), (1, "planet")):
            thickness = stage.tip_thickness_mm(gear) / mesh.normal_module_mm
            if 0.0 < thickness < NEARLY_POINTED_MODULES:
                found.append(f"gear_meshes[{i}] ('{mesh.name}').profile_shift = {list(mesh.profile_shift)}: the {key} "
                             f"gear's tips are nearly pointed (tip thickness {thickness:.2f} × normal_module_mm, "
                             f"commonly at least {NEARLY_POINTED_MODULES:g}); a smaller profile shift for it")
        try:
            part = rig.part(mesh.on.part)
        except KeyError:
            continue
        here = [s.outer_diameter_mm for s in part.segments if s.x_mm[0] - 1e-9 <= mesh.on.x_mm <= s.x_mm[1] + 1e-9]
        pitch = 2.0 * stage.pitch_radius_mm(0)
        if here and pitch < max(here) - 1e-9:
            found.append(f"gear_meshes[{i}] ('{mesh.name}'): the driving gear's pitch circle (Ø{pitch:.4g} mm = "
                         f"normal_module_mm × sun_teeth / cos β) lies inside the shaft '{mesh.on.part}' (Ø{max(here):g} mm "
                         f"at on.x_mm = {mesh.on.x_mm:g}): check normal_module_mm and sun_teeth, or the shaft's segment")
    return found


PRELOAD_SHARE_LIMIT = 0.1
"""A row of an angular-contact or tapered roller bearing preloaded beyond this share of its C (2.5 times the
heavy class of :data:`rvcoax.geometry.rolling_model.PRELOAD_CLASS_SHARE`) is warned about: a unit slip or a
mistaken offset rather than a design."""


def _rolling_preload_warnings(rig: Rig) -> list[str]:
    """An angular-contact or tapered roller bearing whose rows carry more than a tenth of their C at rest."""
    import numpy as np

    from rvcoax.geometry.rolling_model import load_ratings_N, rolling_bearing_of

    found = []
    for i, bearing in enumerate(rig.bearings):
        if bearing.model not in ("angular_contact", "tapered_roller"):
            continue
        rows = rolling_bearing_of(bearing).rows
        carried = max(abs(row.state(np.zeros(5)).force[0]) for row in rows)
        rating = load_ratings_N(bearing)[0]
        if carried > PRELOAD_SHARE_LIMIT * rating:
            key = next((k for k in ("preload_N", "axial_offset_um") if getattr(bearing, k)), "preload_class")
            found.append(f"bearings[{i}] ('{bearing.name}').{key}: each row carries {carried:.4g} N at rest, "
                         f"{100 * carried / rating:.0f} % of its C = {rating:.4g} N (a heavy preload class is 4 %; "
                         f"warned above {100 * PRELOAD_SHARE_LIMIT:.0f} %): a unit slip, or an offset meant in another "
                         "unit?")
    return found


def _fit_warnings(rig: Rig) -> list[str]:
    """A ball bearing whose fits can, at the tight end of their tolerances, take up all its clearance (solved with
    the value ``fit_clearance`` chooses; the tight end would preload the bearing)."""
    from rvcoax.geometry.ball_model import OperatingClearanceError, fit_clearance_of

    found = []
    for i, bearing in enumerate(rig.bearings):
        if bearing.model != "ball" or not (bearing.shaft_fit or bearing.housing_fit):
            continue
        try:
            result = fit_clearance_of(rig, bearing)
        except (OperatingClearanceError, ValueError):
            continue  # refused where the model is built, with its reason
        if result.mounted_um[0] < 0.0:
            found.append(f"bearings[{i}] ('{bearing.name}'): shaft_fit = {bearing.shaft_fit}, housing_fit = "
                         f"{bearing.housing_fit} leave {result.mounted_um[0]:.3g} … {result.mounted_um[1]:.3g} µm of "
                         f"clearance: at the tight end of the tolerances the rings are preloaded (solved with "
                         f"{result.chosen_um:.3g} µm, fit_clearance = {result.which}); a larger clearance_class or "
                         "looser fits avoid it")
    return found


def _gear_contact_warnings(rig: Rig) -> list[str]:
    """A gear stage whose contact loss the sweep interpolates rather than follows exactly.

    Below its full-contact torque T_c a stage's lagging meshes are open; the sweep weights the meshes'
    constant part by clip(T / T_c, −1, 1), exact when the position errors take at most two values (two
    planets always: :func:`rvcoax.geometry.model.loads.gear_contact_weight`) and one stage per torque.
    """
    found = []
    largest = dict(zip(("T1", "T2"), gear_contact_torques(rig)))
    for i, mesh in enumerate(rig.gear_meshes):
        torque = gear_mesh_full_contact_torque(rig, mesh)
        if torque <= 0.0:
            continue
        where = f"gear_meshes[{i}] ('{mesh.name}'): below |{mesh.torque}| = {torque:.3g} N·m a planet mesh opens"
        if len(set(mesh.planet_position_errors_um)) > 2:
            found.append(f"{where}, and with more than two different planet_position_errors_um the meshes close one "
                         "after another: the sweep interpolates their load linearly in the torque below that torque "
                         "(exact at 0 and above it; docs/model.md, gear meshes)")
        elif torque != largest[mesh.torque]:
            found.append(f"{where}, but another stage on {mesh.torque} opens below {largest[mesh.torque]:.3g} N·m: the "
                         "sweep scales both stages' constant force with that torque (one per torque is exact; "
                         "docs/model.md, gear meshes)")
    return found
