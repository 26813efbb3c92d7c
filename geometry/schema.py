"""The rig file's schema (pydantic): every key, its unit, its physical bounds.

Lengths are in mm, stiffnesses in the unit their key names, as in the file. Cross-references
(parts, materials) and geometric consistency are checked in :func:`rvcoax.geometry.schema.Rig`'s
validators, so a loaded ``Rig`` is always buildable.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.limits import MESH_SIZE_RANGE_MM

__all__ = ["BeamSettings", "Bearing", "Connection", "Coupling", "Diameter", "Finite", "Flag", "ForcePair",
           "ForceTable", "Gravity", "Joint", "Location", "Material", "MeshSettings", "Mount", "Name", "NonNegative",
           "Part", "Path", "Paths", "Positive", "Rig", "RigInfo", "RigLoadCase", "Segment", "SingleForce", "SolidSettings",
           "Strict", "TorqueInput", "TorqueLateralLoad", "TorqueRange", "Torques", "Triple"]

# strict: a number must be written as a number ("40" or true are rejected, 40 is fine)
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False, strict=True)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)]
Finite = Annotated[float, Field(allow_inf_nan=False, strict=True)]
# a rig part's diameter: 0.01 mm is a wire, 100 m no rig; outside, I = πd⁴/64 underflows or overflows
Diameter = Annotated[float, Field(ge=0.01, le=1e5, allow_inf_nan=False, strict=True)]
Name = Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
Flag = Annotated[bool, Field(strict=True)]  # true or false only: "yes", 1 or "on" are rejected


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class RigInfo(Strict):
    name: str
    description: str = ""


class Gravity(Strict):
    enabled: Flag = True
    acceleration_m_per_s2: Positive = 9.80665


class MeshSettings(Strict):
    max_element_length_mm: Positive = 5.0


class BeamSettings(Strict):
    """Shaft beams: Timoshenko (shear flexibility, default) or Euler–Bernoulli.

    ``shear_deformation = false`` makes the beams of every shaft (``role = "shaft"``)
    Euler–Bernoulli (Φ = 0: infinite shear stiffness). ``shear_flexibility_factor`` (0…1)
    multiplies their Φ = 12EI/(κGAL²) when shear is on: 1 is the exact Timoshenko beam, 0 is
    Euler–Bernoulli (a blend for the discrepancy workflow). Bodies (housings: equivalent round
    bodies) stay Timoshenko: their short, thick elements without shear flexibility would be
    ~1e16 N/m stiff and make the system numerically singular (pivot ratio 5e-16 on the
    reference rig). Solid parts are elastic continua and are not affected.
    """

    shear_deformation: Flag = True
    shear_flexibility_factor: Annotated[float, Field(ge=0.0, le=1.0, strict=True)] = 1.0

    @property
    def shear_factor(self) -> float:
        """The factor applied to Φ: 0 when shear deformation is off."""
        return self.shear_flexibility_factor if self.shear_deformation else 0.0


class Material(Strict):
    youngs_modulus_MPa: Positive
    poisson_ratio: Annotated[float, Field(gt=-1.0, lt=0.5, strict=True)]
    density_kg_per_m3: Positive

    @property
    def shear_modulus_MPa(self) -> float:
        return self.youngs_modulus_MPa / (2.0 * (1.0 + self.poisson_ratio))


class Segment(Strict):
    x_mm: tuple[Finite, Finite]
    outer_diameter_mm: Diameter
    inner_diameter_mm: Annotated[float, Field(ge=0, le=1e5, allow_inf_nan=False, strict=True)] = 0.0

    @model_validator(mode="after")
    def _check(self) -> Segment:
        if not self.x_mm[1] > self.x_mm[0]:
            raise ValueError(f"x_mm must be increasing [start, end], got {list(self.x_mm)}")
        if not self.inner_diameter_mm < self.outer_diameter_mm:
            raise ValueError(
                f"inner_diameter_mm ({self.inner_diameter_mm}) must be smaller than "
                f"outer_diameter_mm ({self.outer_diameter_mm})"
            )
        return self

    @property
    def volume_mm3(self) -> float:
        return math.pi / 4 * (self.outer_diameter_mm**2 - self.inner_diameter_mm**2) * (self.x_mm[1] - self.x_mm[0])


class Part(Strict):
    name: Name
    role: Literal["shaft", "body"]
    material: str
    mass_kg: Positive | None = None
    mesh_size_mm: Positive | None = None
    segments: list[Segment] = Field(min_length=1)

    @model_validator(mode="after")
    def _check(self) -> Part:
        ordered = sorted(self.segments, key=lambda s: s.x_mm[0])
        for a, b in zip(ordered, ordered[1:]):
            if b.x_mm[0] < a.x_mm[1] - 1e-9:
                raise ValueError(f"segments overlap: {list(a.x_mm)} and {list(b.x_mm)} mm")
            if b.x_mm[0] > a.x_mm[1] + 1e-9:
                raise ValueError(f"gap between segments {list(a.x_mm)} and {list(b.x_mm)} mm")
        if self.role == "body" and self.mass_kg is None:
            raise ValueError("a body needs mass_kg (its density is set so that its mass equals mass_kg)")
        return self

    @property
    def x_range_mm(self) -> tuple[float, float]:
        return min(s.x_mm[0] for s in self.segments), max(s.x_mm[1] for s in self.segments)

    @property
    def volume_mm3(self) -> float:
        return sum(s.volume_mm3 for s in self.segments)


class Location(Strict):
    """A place on a part. On a solid part it is a face: ``band_mm`` (a band of the lateral surface),
    the end face when x is at the part's end, or a band ``[solid] attachment_band_mm`` wide."""

    part: str
    x_mm: Finite
    band_mm: tuple[Finite, Finite] | None = None
    tie: Literal["distributing", "rigid"] = "distributing"

    @model_validator(mode="after")
    def _check_band(self) -> Location:
        if self.band_mm is not None and not self.band_mm[0] < self.band_mm[1]:
            raise ValueError(f"band_mm must be increasing [start, end], got {list(self.band_mm)}")
        return self


class Bearing(Strict):
    name: Name
    shaft: str
    housing: str  # a part name or "ground"
    x_mm: Finite
    radial_stiffness_N_per_um: Positive
    axial_stiffness_N_per_um: NonNegative = 0.0
    tilt_stiffness_Nm_per_rad: NonNegative = 0.0
    width_mm: Positive = 15.0
    # radial play: the radial spring carries F = k (|d| - c) d/|d| only for |d| > c (d: radial
    # relative displacement in the YZ plane, c measured from the centred position); nonlinear
    radial_clearance_um: Annotated[float, Field(ge=0.0, le=1000.0, allow_inf_nan=False, strict=True)] = 0.0
    # --- limits (issue 15, outputs): what the bearing type tolerates; judged in the engineering tables ---
    # tilt of the inner ring against the outer (deep groove ball bearings: 2′ … 10′ in catalogues)
    allowable_misalignment_arcmin: Annotated[float, Field(gt=0.0, le=600.0, allow_inf_nan=False, strict=True)] | None = None


Triple = tuple[NonNegative, NonNegative, NonNegative]


class Mount(Strict):
    name: Name
    part: str
    x_mm: Finite
    translational_stiffness_N_per_um: Triple
    rotational_stiffness_Nm_per_rad: Triple
    # ground side raised by this much (+Y): thermal growth of a housing, shims; the mount's spring
    # is free of load when the part's attachment point sits this far above its nominal position
    vertical_offset_um: Annotated[float, Field(ge=-1e4, le=1e4, allow_inf_nan=False, strict=True)] = 0.0


class Connection(Strict):
    """Something joining two parts: ``from`` and ``to`` locations."""

    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)

    name: Name
    from_: Location = Field(alias="from")
    to: Location


class Coupling(Connection):
    centre_x_mm: Finite
    hub_length_mm: Positive = 20.0
    mass_kg: NonNegative = 0.0
    radial_stiffness_N_per_mm: Positive
    angular_stiffness_Nm_per_rad: Positive
    torsional_stiffness_Nm_per_rad: Positive
    axial_stiffness_N_per_mm: Positive
    # Misalignment of the coupling as installed between collinear shafts: free of load, the coupling
    # holds the `to` hub's axis parallel_offset_um away from the `from` hub's axis and rotated by
    # angular_misalignment_mrad towards misalignment_direction_deg (0 = +Y, 90 = +Z). The straight
    # rig therefore carries the prestrain force/moment K_c d0 on both hubs, at rest and in every case.
    parallel_offset_um: Annotated[float, Field(ge=-1e4, le=1e4, allow_inf_nan=False, strict=True)] = 0.0
    angular_misalignment_mrad: Annotated[float, Field(ge=-100.0, le=100.0, allow_inf_nan=False, strict=True)] = 0.0
    misalignment_direction_deg: Finite = 0.0
    # --- limits (issue 15, outputs): the coupling maker's allowable misalignment (datasheet) and the
    # running speed that grades the misalignment against alignment tolerances by speed
    # (rvcoax.results.engineering.ALIGNMENT_TOLERANCES) ---
    allowable_parallel_offset_mm: Annotated[float, Field(gt=0.0, le=100.0, allow_inf_nan=False, strict=True)] | None = None
    allowable_angular_misalignment_deg: Annotated[float, Field(gt=0.0, le=45.0, allow_inf_nan=False, strict=True)] | None = None
    speed_rpm: Annotated[float, Field(ge=0.0, le=1e6, allow_inf_nan=False, strict=True)] | None = None


class Joint(Connection):
    translational_stiffness_N_per_um: Triple
    rotational_stiffness_Nm_per_rad: Triple


class TorqueInput(Strict):
    part: str
    x_mm: Finite
    sign: Literal[1, -1] = 1


class Torques(Strict):
    T1: TorqueInput
    T2: TorqueInput


class TorqueLateralLoad(Strict):
    """A lateral force that appears when torque flows, applied as a pair (on / reacted_on).

    Kinds
    -----
    gear_mesh_load_sharing
        A gear meshing with two gears 180° apart (the RV reducer's input gear and its two
        crankshaft gears). The difference of the two mesh loads is
        ``W1 − W2 = imbalance · T / r + k_eff · Δε`` (two-path load sharing with a fixed sun):
        ``imbalance = (k1 − k2) / (k1 + k2)`` from unequal mesh stiffness, ``Δε`` the position
        error of the two meshes along their line of action, ``k_eff = 2 k1 k2 / (k1 + k2)``.
        The net lateral force is (W1 − W2) / cos α along ``direction_deg``.
    crank_load_sharing
        Two crankshafts driving the output carrier at radius R: the same law with r = R and no
        pressure angle.
    torque_arm
        A housing held against rotation by an arm: F = T / arm_length.
    proportional
        A lateral force ``force_per_torque_N_per_Nm`` (signed, N per N·m) times the torque: a
        lateral gear-mesh force proportional to T1 at the reducer input, or a lateral reaction
        proportional to T2 on a housing (a torque arm, an asymmetric pedestal).

    The constant part k_eff · Δε acts only while torque flows (at rest the meshes have
    backlash); its sign follows the torque's sign.
    """

    name: Name
    torque: Literal["T1", "T2"]
    kind: Literal["gear_mesh_load_sharing", "crank_load_sharing", "torque_arm", "proportional"]
    on: Location
    reacted_on: Location | None = None
    direction_deg: Finite = 0.0
    imbalance: Annotated[float, Field(ge=-1.0, le=1.0, strict=True)] | None = None
    position_error_um: Annotated[float, Field(ge=-1000.0, le=1000.0, strict=True)] | None = None
    mesh_stiffness_N_per_um: Positive | None = None
    pitch_radius_mm: Positive | None = None
    pressure_angle_deg: Annotated[float, Field(ge=0.0, lt=45.0, strict=True)] | None = None
    radius_mm: Positive | None = None
    arm_length_mm: Positive | None = None
    # kind "proportional": the file key is force_per_torque_N_per_Nm (the property of that name gives
    # the torque-proportional force of every kind)
    proportional_force_N_per_Nm: Finite | None = Field(None, alias="force_per_torque_N_per_Nm")

    @model_validator(mode="after")
    def _check(self) -> TorqueLateralLoad:
        needed = {
            "gear_mesh_load_sharing": ("imbalance", "position_error_um", "mesh_stiffness_N_per_um",
                                       "pitch_radius_mm", "pressure_angle_deg"),
            "crank_load_sharing": ("imbalance", "position_error_um", "mesh_stiffness_N_per_um", "radius_mm"),
            "torque_arm": ("arm_length_mm",),
            "proportional": ("proportional_force_N_per_Nm",),
        }[self.kind]
        missing = [type(self).model_fields[key].alias or key for key in needed if getattr(self, key) is None]
        if missing:
            raise ValueError(f"kind '{self.kind}' needs {', '.join(missing)}")
        if self.kind != "proportional" and self.proportional_force_N_per_Nm is not None:
            raise ValueError(f"kind '{self.kind}' does not take force_per_torque_N_per_Nm (only kind 'proportional')")
        return self

    @property
    def _line_of_action_factor(self) -> float:
        if self.kind == "gear_mesh_load_sharing":
            return 1.0 / math.cos(math.radians(self.pressure_angle_deg))
        return 1.0

    @property
    def force_per_torque_N_per_Nm(self) -> float:
        """Lateral force per unit torque (N per N·m), the torque-proportional part."""
        if self.kind == "proportional":
            return self.proportional_force_N_per_Nm
        if self.kind == "torque_arm":
            return 1.0 / (self.arm_length_mm * 1e-3)
        radius = self.pitch_radius_mm if self.kind == "gear_mesh_load_sharing" else self.radius_mm
        return self.imbalance / (radius * 1e-3) * self._line_of_action_factor

    @property
    def engaged_force_N(self) -> float:
        """Lateral force present whenever torque flows, independent of its size (N)."""
        if self.kind in ("torque_arm", "proportional"):
            return 0.0
        return self.mesh_stiffness_N_per_um * self.position_error_um * self._line_of_action_factor


class ForcePair(Strict):
    label: str
    force_N: Finite
    plus_at: Location
    minus_at: Location


class SingleForce(Strict):
    label: str
    force_N: Finite
    at: Location


class ForceTable(Strict):
    apply: Flag = False
    scale: Finite = 1.0  # multiplies every force of the table when applied
    pairs: list[ForcePair] = []
    singles: list[SingleForce] = []


# --- load cases in the rig file (issue 15, outputs) ---------------------------------------------

class RigLoadCase(Strict):
    """One ``[[load_cases]]`` entry: a torque pair (N·m)."""

    T1_input_Nm: Finite
    T2_output_Nm: Finite


class TorqueRange(Strict):
    """``[sweep]``: ``cases`` evenly spaced (T1, T2) pairs from the first to the last values (N·m)."""

    T1_input_Nm: tuple[Finite, Finite]
    T2_output_Nm: tuple[Finite, Finite]
    cases: Annotated[int, Field(ge=1, le=100_000, strict=True)]

    @model_validator(mode="after")
    def _check(self) -> TorqueRange:
        if self.cases == 1 and (self.T1_input_Nm[0] != self.T1_input_Nm[1]
                                or self.T2_output_Nm[0] != self.T2_output_Nm[1]):
            raise ValueError("cases = 1 needs equal first and last torques (or give cases >= 2)")
        return self


class SolidSettings(Strict):
    """Solid and hybrid models: which parts are solid in ``hybrid``, and mesh sizes."""

    hybrid_parts: list[str] | None = None
    mesh_size_mm: Positive = 4.0
    elements_per_diameter: Annotated[float, Field(ge=1, le=1000, allow_inf_nan=False, strict=True)] = 6.0
    attachment_band_mm: Positive = 10.0


class Path(Strict):
    part: str
    x_start_mm: Finite
    length_mm: Positive
    stations: Annotated[int, Field(ge=25, le=2001, strict=True)] = 41


class Paths(Strict):
    measured_from: Literal["aligned_at_rest", "unloaded"] = "aligned_at_rest"
    input: Path
    output: Path


class Rig(Strict):
    """A whole rig file."""

    schema_version: Literal[1]
    rig: RigInfo
    gravity: Gravity = Gravity()
    mesh: MeshSettings = MeshSettings()
    beam: BeamSettings = BeamSettings()
    materials: dict[str, Material] = Field(min_length=1)
    parts: list[Part] = Field(min_length=1)
    bearings: list[Bearing] = []
    mounts: list[Mount] = []
    couplings: list[Coupling] = []
    joints: list[Joint] = []
    torques: Torques
    torque_lateral_loads: list[TorqueLateralLoad] = []
    force_table: ForceTable = ForceTable()
    paths: Paths
    solid: SolidSettings = SolidSettings()
    # issue 15 (outputs): the rig's own load cases, a list or a range (not both)
    load_cases: list[RigLoadCase] = []
    sweep: TorqueRange | None = None

    @field_validator("parts")
    @classmethod
    def _unique_parts(cls, parts: list[Part]) -> list[Part]:
        names = [p.name for p in parts]
        duplicated = sorted({n for n in names if names.count(n) > 1})
        if duplicated:
            raise ValueError(f"part names must be unique; repeated: {', '.join(duplicated)}")
        if "ground" in names:
            raise ValueError("'ground' is reserved for the fixed ground and cannot name a part")
        return parts

    @model_validator(mode="after")
    def _cross_references(self) -> Rig:
        problems = list(self.reference_problems())
        if problems:
            raise ValueError("\n".join(problems))  # one problem a line (messages may hold "; ")
        return self

    @model_validator(mode="after")
    def _one_source_of_cases(self) -> Rig:
        if self.load_cases and self.sweep is not None:
            raise ValueError("load_cases and sweep: give the load cases either as [[load_cases]] or as a [sweep] "
                             "range, not both")
        return self

    def hybrid_solid_parts(self) -> tuple[str, ...]:
        """Parts modelled as solids in the hybrid model (default: the two measured shafts)."""
        if self.solid.hybrid_parts is not None:
            return tuple(self.solid.hybrid_parts)
        return tuple(dict.fromkeys((self.paths.input.part, self.paths.output.part)))

    def part(self, name: str) -> Part:
        for p in self.parts:
            if p.name == name:
                return p
        raise KeyError(name)

    def _overlapping_shafts(self):
        """Two shafts whose material occupies the same space: on the one axis of the rig, an x range
        where both have a segment and their rings (inner/2 … outer/2) intersect. A shaft may pass
        through another's bore; housings (``role = "body"``) are equivalent round bodies that enclose
        shafts by design and are not checked."""
        shafts = [(i, p) for i, p in enumerate(self.parts) if p.role == "shaft"]
        for k, (i, a) in enumerate(shafts):
            for j, b in shafts[k + 1:]:
                for sa in a.segments:
                    clash = next((sb for sb in b.segments
                                  if min(sa.x_mm[1], sb.x_mm[1]) - max(sa.x_mm[0], sb.x_mm[0]) > 1e-6
                                  and max(sa.inner_diameter_mm, sb.inner_diameter_mm)
                                  < min(sa.outer_diameter_mm, sb.outer_diameter_mm) - 1e-9), None)
                    if clash is not None:
                        x0, x1 = max(sa.x_mm[0], clash.x_mm[0]), min(sa.x_mm[1], clash.x_mm[1])
                        yield (f"parts[{i}] ('{a.name}') and parts[{j}] ('{b.name}'): overlapping parts: both "
                               f"shafts fill x = {x0:g} … {x1:g} mm at the same radii (Ø{sa.outer_diameter_mm:g} and "
                               f"Ø{clash.outer_diameter_mm:g} mm); check their segments' x_mm")
                        break

    def _metre_scale(self):
        """A rig whose every length is tiny was written in metres, not in the keys' millimetres."""
        lo = min(p.x_range_mm[0] for p in self.parts)
        hi = max(p.x_range_mm[1] for p in self.parts)
        largest = max(s.outer_diameter_mm for p in self.parts for s in p.segments)
        if hi - lo < 5.0 or largest < 1.0:
            yield (f"parts: the rig spans {hi - lo:g} mm along x with outer diameters up to {largest:g} mm: the "
                   "lengths look like metres; x_mm and *_diameter_mm keys are in mm")

    def _mesh_sizes(self):
        """Mesh sizes outside the range that ``--mesh-size-mm`` accepts (checked after the metre scale, which
        explains a rig written in metres better)."""
        low, high = MESH_SIZE_RANGE_MM
        sizes = [("solid.mesh_size_mm", self.solid.mesh_size_mm)]
        sizes += [(f"parts[{i}] ('{p.name}').mesh_size_mm", p.mesh_size_mm) for i, p in enumerate(self.parts)
                  if p.mesh_size_mm is not None]
        for where, size in sizes:
            if not low <= size <= high:
                yield f"{where}: {size:g} mm is outside {low:g} … {high:g} mm (the range of --mesh-size-mm)"

    def reference_problems(self):
        """Yield one message per broken reference or inconsistent position."""
        parts = {p.name: p for p in self.parts}
        for i, p in enumerate(self.parts):
            if p.material not in self.materials:
                yield (f"parts[{i}] ('{p.name}').material: unknown material '{p.material}' "
                       f"(known: {', '.join(sorted(self.materials))})")

        def at(where: str, part: str, x: float, role: str | None = None):
            if part not in parts:
                yield f"{where}: unknown part '{part}' (parts: {', '.join(parts)})"
                return
            lo, hi = parts[part].x_range_mm
            if not lo - 1e-9 <= x <= hi + 1e-9:
                yield f"{where}: x_mm = {x} lies outside part '{part}' ({lo} .. {hi} mm)"
            if role and parts[part].role != role:
                yield f"{where}: part '{part}' is a {parts[part].role}, expected a {role}"

        for i, b in enumerate(self.bearings):
            yield from at(f"bearings[{i}] ('{b.name}').shaft", b.shaft, b.x_mm)
            if b.housing != "ground":
                yield from at(f"bearings[{i}] ('{b.name}').housing", b.housing, b.x_mm)
                if b.housing == b.shaft:
                    yield f"bearings[{i}] ('{b.name}'): shaft and housing are the same part"
        for i, m in enumerate(self.mounts):
            yield from at(f"mounts[{i}] ('{m.name}')", m.part, m.x_mm)
        for group, items in (("couplings", self.couplings), ("joints", self.joints)):
            for i, c in enumerate(items):
                yield from at(f"{group}[{i}] ('{c.name}').from", c.from_.part, c.from_.x_mm)
                yield from at(f"{group}[{i}] ('{c.name}').to", c.to.part, c.to.x_mm)
                if c.from_.part == c.to.part:
                    yield f"{group}[{i}] ('{c.name}'): from and to are the same part '{c.to.part}'"
        for key in ("T1", "T2"):
            t = getattr(self.torques, key)
            yield from at(f"torques.{key}", t.part, t.x_mm)
        for i, t in enumerate(self.torque_lateral_loads):
            yield from at(f"torque_lateral_loads[{i}] ('{t.name}').on", t.on.part, t.on.x_mm)
            if t.reacted_on is not None:
                yield from at(f"torque_lateral_loads[{i}] ('{t.name}').reacted_on", t.reacted_on.part, t.reacted_on.x_mm)
        for i, f in enumerate(self.force_table.pairs):
            yield from at(f"force_table.pairs[{i}] ('{f.label}').plus_at", f.plus_at.part, f.plus_at.x_mm)
            yield from at(f"force_table.pairs[{i}] ('{f.label}').minus_at", f.minus_at.part, f.minus_at.x_mm)
        for i, f in enumerate(self.force_table.singles):
            yield from at(f"force_table.singles[{i}] ('{f.label}').at", f.at.part, f.at.x_mm)
        for key in MEASURED_SHAFTS:
            path = getattr(self.paths, key)
            yield from at(f"paths.{key}.x_start_mm", path.part, path.x_start_mm)
            if path.part in parts:
                lo, hi = parts[path.part].x_range_mm
                end = path.x_start_mm + path.length_mm
                if end > hi + 1e-9:
                    yield (f"paths.{key}.length_mm: the path x_start_mm + length_mm = {path.x_start_mm:g} + "
                           f"{path.length_mm:g} = {end:g} mm runs past the end of part '{path.part}' ({lo:g} .. {hi:g} mm)")
        # overlapping supports: two supports of one part at the same place
        seen: dict[tuple[str, float], str] = {}
        supports = [(f"bearings '{b.name}'", b.shaft, b.x_mm) for b in self.bearings]
        supports += [(f"mounts '{m.name}'", m.part, m.x_mm) for m in self.mounts]
        for label, part, x in supports:
            key = (part, round(x, 6))
            if key in seen:
                yield (f"{label} and {seen[key]} both support part '{part}' at x = {x} mm "
                       "(overlapping supports; merge them into one with the summed stiffness)")
            else:
                seen[key] = label
        yield from self._overlapping_shafts()
        yield from self._metre_scale()
        yield from self._mesh_sizes()
        for name in self.solid.hybrid_parts or []:
            if name not in parts:
                yield f"solid.hybrid_parts: unknown part '{name}' (parts: {', '.join(parts)})"
        names = [item.name for group in (self.bearings, self.mounts, self.couplings, self.joints,
                                         self.torque_lateral_loads) for item in group]
        repeated = sorted({n for n in names if names.count(n) > 1})
        if repeated:
            yield f"names of bearings, mounts, couplings, joints and torque_lateral_loads must be unique; repeated: {', '.join(repeated)}"
