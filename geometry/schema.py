"""The rig file's schema (pydantic): every key, its unit, its physical bounds.

Lengths are in mm, stiffnesses in the unit their key names, as in the file. Cross-references
(parts, materials) and geometric consistency are checked in :func:`rvcoax.geometry.schema.Rig`'s
validators, so a loaded ``Rig`` is always buildable.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import ConfigDict, Field, field_serializer, field_validator, model_validator
from pydantic_core import PydanticCustomError

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.limits import MESH_SIZE_RANGE_MM
from rvcoax.geometry.validation import StrictModel

__all__ = ["BeamSettings", "Bearing", "Connection", "Coupling", "Diameter", "Finite", "Flag", "ForcePair",
           "ForceTable", "GearMesh", "Gravity", "Housing", "Joint", "Location", "Material", "MeshSettings", "Mount", "Name", "NonNegative",
           "Part", "Path", "Paths", "Positive", "RatedTorque", "Reducer", "Rig", "RigInfo", "RigLoadCase", "Segment", "ShaftNotch", "ShaftStrength", "SingleForce", "SolidSettings",
           "Strict", "Thermal", "TorqueInput", "TorqueLateralLoad", "TorqueRange", "Torques", "Triple"]

# strict: a number must be written as a number ("40" or true are rejected, 40 is fine)
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False, strict=True)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)]
Finite = Annotated[float, Field(allow_inf_nan=False, strict=True)]
# a rig part's diameter: 0.01 mm is a wire, 100 m no rig; outside, I = πd⁴/64 underflows or overflows
Diameter = Annotated[float, Field(ge=0.01, le=1e5, allow_inf_nan=False, strict=True)]
Name = Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
Flag = Annotated[bool, Field(strict=True)]  # true or false only: "yes", 1 or "on" are rejected


# a rated torque (a coupling's nominal torque, a torque sensor's nominal torque) and the peak its maker allows
# above it (a coupling's maximum torque, a sensor's limit torque): N·m, 1 mN·m … 10 MN·m
RatedTorque = Annotated[float, Field(ge=1e-3, le=1e7, allow_inf_nan=False, strict=True)]


def _check_torque_rating(rated: float | None, peak: float | None) -> None:
    """A peak torque needs the rated torque it lies above; ValueError naming the key and the reason."""
    if peak is None:
        return
    if rated is None:
        raise ValueError("peak_torque_Nm needs rated_torque_Nm (the peak is the maker's allowance above the rated torque)")
    if peak < rated:
        raise ValueError(f"peak_torque_Nm = {peak:g} N·m is below rated_torque_Nm = {rated:g} N·m: the peak (maximum, "
                         "limit) torque a maker allows is at least the rated one")


Strict = StrictModel  # the name the rig schema had for it (rvcoax.geometry.validation.StrictModel)


class RigInfo(StrictModel):
    name: str
    description: str = ""


class Gravity(StrictModel):
    enabled: Flag = True
    acceleration_m_per_s2: Positive = 9.80665


class MeshSettings(StrictModel):
    max_element_length_mm: Positive = 5.0


class BeamSettings(StrictModel):
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


class Material(StrictModel):
    youngs_modulus_MPa: Positive
    poisson_ratio: Annotated[float, Field(gt=-1.0, lt=0.5, strict=True)]
    density_kg_per_m3: Positive
    # thermal growth ([thermal], issue 16 item 4): mean linear expansion coefficient, 1/K (≈ 1.1e-5 for steel)
    thermal_expansion_per_K: Annotated[float, Field(ge=0.0, le=1e-4, allow_inf_nan=False, strict=True)] | None = None
    # shaft strength (DIN 743, issue 25 §5): needed by the shafts that carry [[parts.notches]]
    steel_grade: str | None = Field(None, description=(
        "DIN 743-3 steel of a shaft with notches: S235, S355, E335, C45, C50, 41Cr4, 34CrMo4, 42CrMo4, 50CrMo4, "
        "34CrNiMo6, 16MnCr5, 20MnCr5 (tensile and yield strength at the reference diameter [R], see "
        "docs/model.md); typed-in strengths take precedence."))
    tensile_strength_MPa: Annotated[float, Field(gt=0.0, le=3000.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="σ_B(d_B): tensile strength at the steel's reference diameter (DIN 743-3), for the shaft "
                          "strength check; with yield_strength_MPa.")
    yield_strength_MPa: Annotated[float, Field(gt=0.0, le=3000.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="σ_S(d_B): yield strength at the steel's reference diameter (DIN 743-3); with "
                          "tensile_strength_MPa.")
    steel_group: Literal["quenched_tempered", "case_hardening", "structural", "nitriding"] | None = Field(
        None, description="The steel's group, which sets how its strength falls with the heat-treatment diameter "
                          "(K1(d_eff), DIN 743-3); default: the grade's, else quenched_tempered.")

    @model_validator(mode="after")
    def _strengths(self) -> Material:
        typed = (self.tensile_strength_MPa is not None, self.yield_strength_MPa is not None)
        if any(typed) and not all(typed):
            missing = "yield_strength_MPa" if typed[0] else "tensile_strength_MPa"
            raise ValueError(f"{missing}: give tensile_strength_MPa and yield_strength_MPa together")
        if all(typed) and self.yield_strength_MPa > self.tensile_strength_MPa:
            raise ValueError(f"yield_strength_MPa ({self.yield_strength_MPa:g}) exceeds tensile_strength_MPa "
                             f"({self.tensile_strength_MPa:g})")
        if self.steel_grade is not None:
            from rvcoax.geometry.shaft_notches import DIN743_STEELS, unknown_grade

            if self.steel_grade not in DIN743_STEELS:
                raise ValueError(f"steel_grade: {unknown_grade(self.steel_grade)}")
        return self

    @property
    def shear_modulus_MPa(self) -> float:
        return self.youngs_modulus_MPa / (2.0 * (1.0 + self.poisson_ratio))


class Segment(StrictModel):
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


class ShaftNotch(StrictModel):
    """A notch of a shaft for its DIN 743 strength check (issue 25 §5); its diameters come from the segments."""

    x_mm: Finite = Field(description="Where the notch sits on the rig axis: a shoulder at the segment boundary "
                                     "where the diameter steps, the others inside a segment.")
    kind: Literal["shoulder", "groove", "keyway", "press_fit"] = Field(description=(
        "shoulder (diameter step with a fillet), groove (round groove of depth_mm, fillet_radius_mm at its root), "
        "keyway (feather-key slot, end-milled), press_fit (hub pressed on): notch factors per DIN 743-2."))
    fillet_radius_mm: Annotated[float, Field(gt=0.0, le=1e4, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="shoulder: the fillet radius; groove: the root radius (required for both).")
    depth_mm: Annotated[float, Field(gt=0.0, le=1e4, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="groove: its depth t (required); a shoulder's depth comes from its segments.")
    keys: Literal[1, 2] = Field(1, description="keyway: one feather key, or two (β × 1.15).")
    roughness_Rz_um: Annotated[float, Field(gt=0.0, le=200.0, allow_inf_nan=False, strict=True)] = Field(
        6.3, description="Mean roughness depth Rz of the notch surface (K_Fσ, K_Fτ; keyways and press fits carry "
                         "theirs in β).")
    d_eff_mm: Annotated[float, Field(gt=0.0, le=500.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="Diameter that governed the heat treatment (K1(d_eff)); default: the larger diameter "
                          "at the notch.")
    hard_surface: Flag = Field(False, description="The notch has a hard surface layer (case-hardened, nitrided): "
                                                 "no support from plasticity, K2F = 1.")

    @model_validator(mode="after")
    def _keys_of_kind(self) -> ShaftNotch:
        if self.kind in ("shoulder", "groove") and self.fillet_radius_mm is None:
            raise ValueError(f"fillet_radius_mm: required for a {self.kind}")
        if self.kind == "groove" and self.depth_mm is None:
            raise ValueError("depth_mm: required for a groove")
        if self.kind == "shoulder" and self.depth_mm is not None:
            raise ValueError("depth_mm: a shoulder's depth comes from the diameters of its two segments; leave it out")
        if self.kind in ("keyway", "press_fit") and (self.fillet_radius_mm, self.depth_mm) != (None, None):
            raise ValueError(f"fillet_radius_mm, depth_mm: a {self.kind}'s notch factor comes from DIN 743-2's "
                             "measured values, not from a radius or depth")
        if self.kind != "keyway" and self.keys != 1:
            raise ValueError("keys: only a keyway has keys")
        return self


class Part(StrictModel):
    name: Name
    role: Literal["shaft", "body"]
    material: str
    mass_kg: Positive | None = None
    mesh_size_mm: Positive | None = None
    segments: list[Segment] = Field(min_length=1)
    notches: list[ShaftNotch] = Field([], description="A shaft's notches for its DIN 743 static and fatigue safety "
                                                      "(shaft stresses are computed without them too).")
    rated_torque_Nm: RatedTorque | None = Field(None, description=(
        "A shaft's rated torque: a torque sensor's nominal (rated) torque on its measuring shaft (datasheet). Each "
        "case's torque through the shaft is checked against it (warning above it; sweep.csv/json, the report). A "
        "rating that shears the shaft's thinnest section outside 0.5 … 2000 MPa is warned about (a unit slip)."))
    peak_torque_Nm: RatedTorque | None = Field(None, description=(
        "The torque the shaft's maker allows above the rated one (a torque sensor's limit torque), when the "
        "datasheet gives one; needs rated_torque_Nm."))

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
        if self.role == "body" and self.rated_torque_Nm is not None:
            raise ValueError("rated_torque_Nm: a body (housing) carries no shaft torque; give a torque sensor's rating "
                             "on its measuring shaft (role = \"shaft\")")
        _check_torque_rating(self.rated_torque_Nm, self.peak_torque_Nm)
        return self

    @property
    def x_range_mm(self) -> tuple[float, float]:
        return min(s.x_mm[0] for s in self.segments), max(s.x_mm[1] for s in self.segments)

    @property
    def volume_mm3(self) -> float:
        return sum(s.volume_mm3 for s in self.segments)


class Location(StrictModel):
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


class _PositiveUpTo:
    """``_PositiveUpTo[upper]``: a finite float in (0, upper]."""

    def __class_getitem__(cls, upper: float):
        return Annotated[float, Field(gt=0.0, le=upper, allow_inf_nan=False, strict=True)]


class Bearing(StrictModel):
    """A bearing between a shaft and its housing (or the ground).

    ``model = "linear"`` (default): springs typed in (``radial_stiffness_N_per_um`` required).
    ``model = "ball"``: a deep-groove ball bearing from its internal geometry (see the block below and
    :mod:`rvcoax.fem.ball_bearing`); ``"angular_contact"``, ``"cylindrical_roller"``, ``"tapered_roller"``:
    those bearings (single or paired) from their internal geometry (:mod:`rvcoax.geometry.rolling_model`).
    The stiffness keys are then optional and only set the linear reference the nonlinear solve is condensed
    on (filled from the geometry when absent; a cylindrical roller bearing's axial key is its axial spring).
    """

    name: Name
    shaft: str
    housing: str  # a part name or "ground"
    x_mm: Finite
    model: Literal["linear", "ball", "angular_contact", "cylindrical_roller", "tapered_roller"] = Field(
        "linear", description=(  # before the stiffness keys: their check reads it
            "linear: the stiffness keys typed in; ball: a deep-groove ball bearing from its internal geometry "
            "(Hertz contact per ball, clearance, preload; solved nonlinearly); angular_contact: an angular-contact "
            "ball bearing or matched pair (Hertz contact per ball, contact angles follow the load); "
            "cylindrical_roller, tapered_roller: roller bearings, line contact by slicing (Palmgren laminae, "
            "crowning)."))
    radial_stiffness_N_per_um: Annotated[Positive | None, Field(validate_default=True, json_schema_extra={
        "default_text": "required (a bearing from geometry: from its geometry)"})] = None
    axial_stiffness_N_per_um: NonNegative = 0.0
    tilt_stiffness_Nm_per_rad: NonNegative = 0.0
    width_mm: Positive = 15.0
    # radial play: the radial spring carries F = k (|d| - c) d/|d| only for |d| > c (d: radial
    # relative displacement in the YZ plane, c measured from the centred position); nonlinear
    radial_clearance_um: Annotated[float, Field(ge=0.0, le=1000.0, allow_inf_nan=False, strict=True)] = 0.0
    # --- limits (issue 15, outputs): what the bearing type tolerates; judged in the engineering tables ---
    # tilt of the inner ring against the outer (deep groove ball bearings: 2′ … 10′ in catalogues)
    allowable_misalignment_arcmin: Annotated[float, Field(gt=0.0, le=600.0, allow_inf_nan=False, strict=True)] | None = None

    # ---- model = "ball": deep-groove ball bearing from internal geometry (issue 16 item 1) ----------
    designation: str | None = Field(None, description=(
        "Catalogue bearing: model = \"ball\" 6200 … 6210, 6300 … 6310 (geometry/data/ball_bearings.csv); "
        "angular_contact 7000 … 7010, 7200 … 7210, 7300 … 7310 with suffix B (40°), AC (25°) or C (15°); "
        "cylindrical_roller NU, N, NJ or NUP 204 … 210, 304 … 310; tapered_roller 30204 … 30210, 32004X … 32010X, "
        "32204 … 32210 (geometry/data/rolling_bearings.csv; internal geometry estimated, see docs/model.md)."))
    clearance_class: Literal["C2", "CN", "C3", "C4"] | None = Field(None, description=(
        "model = \"ball\" or \"cylindrical_roller\": ISO 5753-1 radial internal clearance class; the middle of "
        "its range for the bore (CN when neither this nor clearance_um is given)."))
    clearance_um: Annotated[float, Field(ge=0.0, le=500.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="model = \"ball\" or \"cylindrical_roller\": radial internal clearance (diametral) as "
                          "mounted, after fits; used "
                          "instead of the class when given. [thermal] rises of shaft and housing change it in "
                          "operation by −α d_m (ΔT_shaft − ΔT_housing).")
    preload_N: Annotated[float, Field(ge=0.0, le=1e5, allow_inf_nan=False, strict=True)] = Field(
        0.0, description="model = \"ball\": axial position preload, carried by the balls at rest (takes up the "
                         "clearance, stiffens the bearing); angular_contact, tapered_roller: the axial preload "
                         "each row of a DB/DF pair carries at rest, or a single bearing (DT pair) against its "
                         "mounting.")
    ball_count: Annotated[int, Field(ge=3, le=200, strict=True)] | None = Field(
        None, description="model = \"ball\", angular_contact: number of balls Z (overrides the catalogue).")
    ball_diameter_mm: Annotated[float, Field(gt=0.0, le=500.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="model = \"ball\", angular_contact: ball diameter D_w (overrides the catalogue).")
    pitch_diameter_mm: Annotated[float, Field(gt=0.0, le=5000.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="model = \"ball\", angular_contact, cylindrical_roller, tapered_roller: pitch diameter "
                          "d_m of the rolling elements (overrides the catalogue).")
    inner_conformity: Annotated[float, Field(gt=0.5, lt=1.0, strict=True)] | None = Field(
        None, description="model = \"ball\", angular_contact: inner groove radius over ball diameter, f_i = r_i / D_w.")
    outer_conformity: Annotated[float, Field(gt=0.5, lt=1.0, strict=True)] | None = Field(
        None, description="model = \"ball\", angular_contact: outer groove radius over ball diameter, f_o = r_o / D_w.")

    # ---- angular_contact, cylindrical_roller, tapered_roller (issue 25 item 1) -------------------------
    arrangement: Literal["single", "DB", "DF", "DT"] = Field("single", description=(
        "angular_contact, tapered_roller: a single bearing, or a matched pair back-to-back (DB), face-to-face "
        "(DF) or in tandem (DT), its two rows a bearing width apart around x_mm."))
    axial_direction: Literal[1, -1] = Field(1, description=(
        "angular_contact, tapered_roller, single or DT, and an NJ cylindrical_roller: the direction (+1: +x, "
        "−1: −x) of the shaft's axial motion against the housing that the bearing carries."))
    preload_class: Literal["light", "medium", "heavy"] | None = Field(None, description=(
        "angular_contact, tapered_roller, DB or DF pair: each row carries 1 %, 2 % or 4 % of its C axially at "
        "rest (estimated: makers' classes differ). Not for a single bearing (nothing to preload against)."))
    axial_offset_um: Annotated[float, Field(ge=-1000.0, le=1000.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="angular_contact, tapered_roller: axial offset of the rings from first contact, signed "
                          "(> 0 pressed together: a preload; < 0 apart: an axial play); a DB/DF pair's total.")
    contact_angle_deg: Annotated[float, Field(gt=0.0, lt=60.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="angular_contact, tapered_roller: nominal contact angle α0 (overrides the catalogue).")
    roller_count: Annotated[int, Field(ge=3, le=200, strict=True)] | None = Field(
        None, description="cylindrical_roller, tapered_roller: number of rollers Z (overrides the catalogue).")
    roller_diameter_mm: Annotated[float, Field(gt=0.0, le=500.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="cylindrical_roller, tapered_roller: (mean) roller diameter D_w (overrides the catalogue).")
    roller_length_mm: Annotated[float, Field(gt=0.0, le=500.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="cylindrical_roller, tapered_roller: effective roller length l_we (overrides the catalogue).")
    crowning: Literal["logarithmic", "circular", "none"] = Field("logarithmic", description=(
        "cylindrical_roller, tapered_roller: roller profile: logarithmic (Lundberg, even pressure at "
        "crowning_load_N), circular (crown_drop_um at the ends) or none."))
    crown_drop_um: Annotated[float, Field(ge=0.0, le=200.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="crowning = \"circular\": drop of the profile at the roller ends.")
    crowning_load_N: Annotated[float, Field(gt=0.0, le=1e7, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="crowning = \"logarithmic\": the roller load the profile is designed for (default: "
                          "the load giving 2000 MPa on an evenly loaded roller).")
    slices_per_roller: Annotated[int, Field(ge=1, le=500, strict=True)] = Field(
        20, description="cylindrical_roller, tapered_roller: laminae per roller of the line-contact slicing.")

    shaft_fit: str | None = Field(None, description=(
        "model = \"ball\": ISO 286 tolerance class of the shaft seat (g5 … p6, js5, js6; e.g. k5, j6, m6): with "
        "housing_fit, the mounted clearance is the class's unmounted clearance less the rings' expansion and "
        "contraction by the interference (thick rings; docs/model.md)."))
    housing_fit: str | None = Field(None, description=(
        "model = \"ball\": ISO 286 tolerance class of the housing bore (G6 … P7, JS6, JS7; e.g. H7, J7, K7)."))
    fit_clearance: Literal["mean", "min", "max"] = Field("mean", description=(
        "model = \"ball\" with fits: solve with the mean mounted clearance (middle of the class, mean "
        "interference), or the tightest (min) or loosest (max) combination; the range is reported."))

    @field_validator("shaft_fit", "housing_fit")
    @classmethod
    def _known_fit(cls, value, info):
        if value is None:
            return value
        from rvcoax.geometry.fits import tolerance_zone_um

        shaft = info.field_name == "shaft_fit"
        if value[0].islower() != shaft:
            raise ValueError(f"{value!r}: a {'shaft' if shaft else 'housing'} class is written in "
                             f"{'lower' if shaft else 'upper'} case (ISO 286: k5 for a shaft, K7 for a housing bore)")
        tolerance_zone_um(value, 30.0)  # ValueError naming the known classes
        return value

    # ---- life, static safety, minimum load (issue 25 item 3; rvcoax.fem.bearing_life) ---------------
    dynamic_load_rating_kN: Annotated[float, Field(gt=0.0, le=1e5, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="Basic dynamic load rating C (catalogue); a bearing from geometry: from the catalogue or "
                          "the geometry (ISO 281) when not given; a DB/DF/DT set: the set's C (else 2^0.7 C ball, "
                          "2^(7/9) C roller of one). Without it (model = \"linear\") no life is computed.")
    static_load_rating_kN: Annotated[float, Field(gt=0.0, le=1e5, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="Basic static load rating C0 (catalogue); a bearing from geometry: from the catalogue or "
                          "the geometry (ISO 76) when not given; a DB/DF/DT set: the set's C0 (else 2 C0 of one).")
    rolling_elements: Literal["ball", "roller"] = Field(
        "ball", description="model = \"linear\": what rolls (life exponent 3 or 10/3, minimum load 0.01 C or "
                            "0.02 C, s0 limit).")
    viscosity_ratio: Annotated[float, Field(ge=0.1, le=100.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="κ = ν/ν1 of the lubricant at operating temperature; with contamination_factor gives "
                          "ISO 281's a_ISO.")
    contamination_factor: Annotated[float, Field(ge=0.0, le=1.0, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="e_C of ISO 281 (1: extreme cleanliness … 0: severe contamination).")
    # the maker's minimum load and κ from the oil (rvcoax.geometry.bearing_ratings.life_options)
    oil_viscosity_mm2_per_s: _PositiveUpTo[1e5] | None = Field(None, description=(
        "A bearing from geometry: the lubricant's kinematic viscosity ν at operating temperature; gives κ = ν/ν1 "
        "per case (ISO 281's ν1 at the case's speed) instead of viscosity_ratio, and the ball bearings' "
        "speed-dependent minimum load."))
    minimum_load_factor: _PositiveUpTo[10.0] | None = Field(None, description=(
        "The maker's minimum load factor k_r (SKF product tables): ball and angular_contact F_rm = k_r "
        "(ν n/1000)^(2/3) (d_m/100)² kN (needs oil_viscosity_mm2_per_s), cylindrical_roller F_rm = k_r "
        "(6 + 4 n/n_r) (d_m/100)² kN (needs reference_speed_rpm); without it the rule of thumb 0.01 C (ball) / "
        "0.02 C (roller)."))
    reference_speed_rpm: _PositiveUpTo[1e6] | None = Field(None, description=(
        "cylindrical_roller: the catalogue's reference speed n_r (minimum load)."))

    @model_validator(mode="after")
    def _check_life_keys(self) -> Bearing:
        from rvcoax.geometry.bearing_ratings import check_life_keys

        check_life_keys(self)
        return self

    @field_validator("radial_stiffness_N_per_um")
    @classmethod
    def _linear_needs_stiffness(cls, value, info):
        if value is None and info.data.get("model", "linear") == "linear":
            raise PydanticCustomError("missing", "required key (model = \"linear\", the default)")
        return value

    @model_validator(mode="after")
    def _check_model(self) -> Bearing:
        from rvcoax.geometry import ball_model, rolling_model

        every = set(ball_model.BALL_KEYS).union(*rolling_model.MODEL_KEYS.values())
        allowed = set(ball_model.BALL_KEYS) if self.model == "ball" else set(rolling_model.MODEL_KEYS.get(self.model, ()))
        given = [key for key in Bearing.model_fields if key in every and key not in allowed
                 and getattr(self, key) not in (None, 0.0, Bearing.model_fields[key].default)]
        if given:
            takes = [m for m, keys in (("ball", ball_model.BALL_KEYS), *rolling_model.MODEL_KEYS.items())
                     if given[0] in keys]
            if self.model == "linear":
                raise ValueError(f"{', '.join(given)} only apply to model = "
                                 f"{' or '.join(f'{chr(34)}{m}{chr(34)}' for m in takes)} (this bearing is model = "
                                 "\"linear\": set model or remove them)")
            raise ValueError(f"{', '.join(given)}: not a key of model = \"{self.model}\" (it applies to "
                             f"{', '.join(takes)})")
        if self.model == "linear":
            return self
        if self.radial_clearance_um > 0:
            takes = {"ball": "a ball bearing takes clearance_um (the radial internal clearance) or clearance_class",
                     "cylindrical_roller": "a cylindrical roller bearing takes clearance_um (the radial internal "
                                           "clearance) or clearance_class"}.get(
                self.model, f"an {self.model.replace('_', ' ')} bearing's play is axial_offset_um < 0"
                if self.model == "angular_contact" else "a tapered roller bearing's play is axial_offset_um < 0")
            raise ValueError(f"radial_clearance_um is the gap of the linear model; {takes}")
        if self.model != "ball":
            return self._check_rolling(rolling_model)
        if (self.shaft_fit or self.housing_fit) and self.clearance_um is not None:
            raise ValueError("clearance_um is the clearance as mounted; with shaft_fit/housing_fit give the unmounted "
                             "clearance_class instead (the fits take the clearance from it)")
        if (self.shaft_fit or self.housing_fit) and self.designation is None:
            raise ValueError("shaft_fit/housing_fit need a designation (the ring's bore and outside diameter)")
        ball_model.geometry_of(self)  # raises ValueError naming the key
        rating = rolling_model.load_ratings_N(self)[1]
        if self.preload_N > ball_model.PRELOAD_REFUSED_C0 * rating:
            raise ValueError(f"preload_N = {self.preload_N:g} N is beyond the bearing's static load rating: C0 = "
                             f"{rating / 1e3:.3g} kN (ISO 76 from its ball set) and an axial load Fa gives P0 = 0.5 Fa, "
                             f"so the raceways deform permanently above {ball_model.PRELOAD_REFUSED_C0 * rating:.4g} N "
                             "and the Hertz model no longer holds; a preload is a few % of C0 (N, not kN or mN?)")
        # the linear reference of the condensed Newton solve, where not given; the catalogue's width
        for key, value in ball_model.reference_stiffness(self).items():
            if not getattr(self, key):
                object.__setattr__(self, key, value)
        if "width_mm" not in self.model_fields_set and self.designation is not None:
            object.__setattr__(self, "width_mm", ball_model.BALL_BEARINGS[self.designation].width_mm)
        return self

    def _check_rolling(self, rolling_model) -> Bearing:
        """angular_contact, cylindrical_roller, tapered_roller: the preload keys fit the arrangement, the
        geometry builds; the linear reference and the catalogue width filled in."""
        chosen = [key for key in ("preload_class", "preload_N", "axial_offset_um") if getattr(self, key) not in (None, 0.0)]
        if len(chosen) > 1:
            raise ValueError(f"{' and '.join(chosen)}: give one way of setting the rings (a preload class, a preload "
                             "force or an axial offset)")
        if self.preload_class is not None and self.arrangement not in ("DB", "DF"):
            what = "a single bearing" if self.arrangement == "single" else "a tandem (DT) pair"
            raise ValueError(f"preload_class = \"{self.preload_class}\" needs a DB or DF pair (arrangement): "
                             f"{what} has no partner row to be preloaded against; give preload_N (a preload "
                             "against its mounting) or axial_offset_um")
        for key, crowning in (("crown_drop_um", "circular"), ("crowning_load_N", "logarithmic")):
            if getattr(self, key) is not None and self.crowning != crowning:
                raise ValueError(f"{key} applies to crowning = \"{crowning}\" (this bearing's crowning is "
                                 f"\"{self.crowning}\")")
        if self.axial_direction != 1 and self.arrangement in ("DB", "DF"):
            raise ValueError(f"axial_direction: a {self.arrangement} pair carries thrust both ways (its rows' "
                             "directions follow from the arrangement)")
        rolling_model.rolling_bearing_of(self)  # raises ValueError naming the key
        for key, value in rolling_model.reference_stiffness(self).items():
            if not getattr(self, key):
                object.__setattr__(self, key, value)
        if "width_mm" not in self.model_fields_set and self.designation is not None:
            rows = 1 if self.arrangement == "single" else 2
            object.__setattr__(self, "width_mm", rows * rolling_model.entry_of(self).width_mm)
        return self


Triple = tuple[NonNegative, NonNegative, NonNegative]


class Mount(StrictModel):
    name: Name
    part: str
    x_mm: Finite
    translational_stiffness_N_per_um: Triple
    rotational_stiffness_Nm_per_rad: Triple
    # ground side raised by this much (+Y): thermal growth of a housing, shims; the mount's spring
    # is free of load when the part's attachment point sits this far above its nominal position
    vertical_offset_um: Annotated[float, Field(ge=-1e4, le=1e4, allow_inf_nan=False, strict=True)] = 0.0
    # thermal growth ([thermal], issue 16 item 4): the support lifts the axis by α ΔT · height_above_bed_mm,
    # α of support_material (default: the part's material), ΔT the support's temperature rise
    height_above_bed_mm: Annotated[float, Field(ge=0.0, le=1e4, allow_inf_nan=False, strict=True)] | None = None
    support_material: str | None = None


class Connection(StrictModel):
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
    # --- dynamics (issue 26): the coupling's polar mass moment, half on each hub (each hub a disc: its
    # diametral moment half its polar one); without it the hubs are point masses ---
    polar_inertia_kg_m2: Annotated[float, Field(ge=0.0, le=1e3, allow_inf_nan=False, strict=True)] | None = None
    # --- rating (issue 25): the torque each case carries through the coupling against its maker's rating ---
    rated_torque_Nm: RatedTorque | None = Field(None, description=(
        "The coupling's rated (nominal) torque from its datasheet. Each case's torque through the coupling is checked "
        "against it (warning above it; sweep.csv/json, the report). A rating that twists the coupling outside "
        "1e-5 … 0.3 rad (T / torsional_stiffness_Nm_per_rad) is warned about (a unit slip)."))
    peak_torque_Nm: RatedTorque | None = Field(None, description=(
        "The maximum torque the coupling's maker allows above the rated one (peaks, start and stop), when the "
        "datasheet gives one; needs rated_torque_Nm."))

    @model_validator(mode="after")
    def _check_rating(self) -> Coupling:
        _check_torque_rating(self.rated_torque_Nm, self.peak_torque_Nm)
        return self


class Joint(Connection):
    translational_stiffness_N_per_um: Triple
    rotational_stiffness_Nm_per_rad: Triple


class Reducer(StrictModel):
    """``[[reducers]]``: an RV reducer from the catalogue (:mod:`rvcoax.geometry.reducers`).

    Its main bearings and output become a joint named like the reducer, between ``case`` (the reducer's
    housing part) and ``output`` (the part bolted to the output flange), at the main bearings' centre:
    torsional and moment rigidity from the rating table, the bearings' radial stiffness from the moment
    rigidity (k_r = 4 K_M / ℓ², ℓ the spread of their pressure centres). Each load case is checked against
    the table: the torque ``torque`` (T2 by default) against rated, peak and momentary torque, the moment
    and axial force on the main bearings against the allowable values.
    """

    name: Name
    designation: str = Field(description="RV-6E, RV-20E, RV-40E, RV-80E, RV-110E, RV-160E, RV-320E or RV-450E "
                                         "(geometry/data/rv_reducers.csv).")
    case: Location = Field(description="The reducer's housing part at the main bearings' centre.")
    output: Location = Field(description="The part bolted to the output flange, at the same x (tie = \"rigid\" "
                                         "for a bolted flange).")
    torque: Literal["T1", "T2"] = Field("T2", description="The rig torque the reducer's output carries.")
    ratio: Positive | None = Field(None, description="Reduction ratio i: the input shaft runs i times the output "
                                                     "speed (bearing lives).")
    moment_rigidity_Nm_per_arcmin: Positive | None = Field(None, description="Overrides the catalogue.")
    torsional_rigidity_Nm_per_arcmin: Positive | None = Field(None, description="Overrides the catalogue.")
    main_bearing_spread_mm: Positive | None = Field(None, description=(
        "Distance of the main bearings' pressure centres ℓ (catalogue: an estimate, tagged [E]); sets their "
        "radial stiffness 4 K_M / ℓ²."))
    radial_stiffness_N_per_um: Positive | None = Field(None, description="Main bearings' radial stiffness; "
                                                                         "overrides 4 K_M / ℓ².")
    axial_stiffness_N_per_um: Positive | None = Field(None, description="Main bearings' axial stiffness (default: "
                                                                        "the radial one).")

    @field_validator("designation")
    @classmethod
    def _known(cls, value: str) -> str:
        from rvcoax.geometry.reducers import reducer_entry

        reducer_entry(value)  # ValueError naming the nearest designations
        return value


class TorqueInput(StrictModel):
    part: str
    x_mm: Finite
    sign: Literal[1, -1] = 1
    reacted_on: Location | None = Field(None, description=(
        "Where the torque's reaction acts: the stator of the motor or brake that applies it (its housing). The "
        "opposite torque is applied there, so the support under it carries it as the real one does; none: the "
        "rig's torsional springs take it to the ground (the supports' Mx then do not show the real ones)."))
    reaction_spring: str | None = Field(None, description=(
        "The spring meant to take this torque out of its shaft line (the reducer's gear mesh or output joint); "
        "default: a [[reducers]] joint, else the line's torsional spring farthest from the torque. `rvcoax "
        "sweep` warns when another spring carries more than 2 % of it."))


class Torques(StrictModel):
    T1: TorqueInput
    T2: TorqueInput


class TorqueLateralLoad(StrictModel):
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


# ---- gear meshes from gear data (issue 16 item 3) ------------------------------------------------------------

PlanetError = Annotated[float, Field(ge=-100.0, le=100.0, allow_inf_nan=False, strict=True)]


class GearMesh(StrictModel):
    """``[[gear_meshes]]``: a driving gear in mesh with planet gears, from its gear data.

    The RV reducer's first stage: the input (sun) gear on part ``on`` drives ``len(planet_angles_deg)``
    planet gears whose bearings sit in part ``reacted_on`` (the reducer case). From the torque ``torque``
    (times its sign) the mesh forces per planet follow (:mod:`rvcoax.geometry.gears`): each mesh's
    stiffness is ``face_width_mm`` × ISO 6336-1's c_γα (or ``mesh_stiffness_N_per_mm_per_um``) ×
    its ``planet_stiffness_factors`` entry; the meshes share the load by their stiffnesses and their
    position errors ``planet_position_errors_um`` (along the line of action, + = engages later). The net
    force on the driving gear (lateral, axial for helical gears, and the tilting moment of the axial
    forces) acts on ``on``, its reaction on ``reacted_on``. The transmitted torque itself is not
    applied here: it is carried by the rig's torsional springs, as without gear data.
    """

    name: Name
    torque: Literal["T1", "T2"] = "T1"
    on: Location
    reacted_on: Location
    normal_module_mm: Annotated[float, Field(ge=0.05, le=100.0, allow_inf_nan=False, strict=True)]
    sun_teeth: Annotated[int, Field(ge=6, le=1000, strict=True)]
    planet_teeth: Annotated[int, Field(ge=6, le=1000, strict=True)]
    normal_pressure_angle_deg: Annotated[float, Field(ge=10.0, le=35.0, strict=True)] = 20.0
    face_width_mm: Positive
    helix_angle_deg: Annotated[float, Field(gt=-45.0, lt=45.0, strict=True)] = 0.0
    profile_shift: tuple[Annotated[float, Field(ge=-1.0, le=1.5, strict=True)],
                         Annotated[float, Field(ge=-1.0, le=1.5, strict=True)]] = (0.0, 0.0)
    dedendum_factor: Annotated[float, Field(ge=1.0, le=1.6, strict=True)] = 1.25
    blank_factor: Annotated[float, Field(gt=0.2, le=1.0, strict=True)] = 1.0
    planet_material: str | None = None
    mesh_stiffness_N_per_mm_per_um: Annotated[float, Field(gt=0.0, le=100.0, strict=True)] | None = None
    planet_angles_deg: list[Finite] = Field(min_length=2, max_length=12)
    planet_position_errors_um: list[PlanetError]
    planet_stiffness_factors: list[Annotated[float, Field(ge=0.1, le=10.0, strict=True)]]

    @model_validator(mode="before")
    @classmethod
    def _per_planet_defaults(cls, data):
        """No position errors and the nominal stiffness for every planet unless given."""
        if isinstance(data, dict) and isinstance(data.get("planet_angles_deg"), list):
            n = len(data["planet_angles_deg"])
            data = {"planet_position_errors_um": [0.0] * n, "planet_stiffness_factors": [1.0] * n, **data}
        return data

    @model_validator(mode="after")
    def _check(self) -> GearMesh:
        n = len(self.planet_angles_deg)
        for key in ("planet_position_errors_um", "planet_stiffness_factors"):
            values = getattr(self, key)
            if len(values) != n:
                raise ValueError(f"{key} has {len(values)} values, planet_angles_deg {n}: one per planet")
        stage = self.stage
        if self.face_width_mm > MAX_FACE_WIDTH_MODULES * self.normal_module_mm:
            raise ValueError(f"face_width_mm = {self.face_width_mm:g} mm is {self.face_width_mm / self.normal_module_mm:.3g} "
                             f"normal modules wide (normal_module_mm = {self.normal_module_mm:g}): gear faces are about "
                             f"6 … 40 modules wide, more than {MAX_FACE_WIDTH_MODULES:g} is refused (a length in m or "
                             "µm, or the module?)")
        for gear, key in ((0, "sun"), (1, "planet")):
            thickness = stage.tip_thickness_mm(gear)
            if thickness <= 0.0:
                raise ValueError(f"profile_shift = {list(self.profile_shift)}: the {key} gear's teeth are pointed (tip "
                                 f"thickness {thickness / self.normal_module_mm:.2f} × normal_module_mm ≤ 0 with "
                                 f"{key}_teeth = {getattr(self, key + '_teeth')}): its tip circle lies beyond the point "
                                 "where the flanks meet; use a smaller profile shift for it")
        ratio = stage.contact_ratio
        if not ratio >= 1.0:
            raise ValueError(f"the gear data give a transverse contact ratio of {ratio:.3f} < 1: the teeth lose "
                             "contact (check normal_module_mm, the tooth counts and profile_shift)")
        angles = sorted(a % 360.0 for a in self.planet_angles_deg)
        gaps = [b - a for a, b in zip(angles, angles[1:] + [angles[0] + 360.0])]
        clearance = 2.0 * stage.centre_distance_mm * math.sin(math.radians(min(gaps)) / 2.0)
        if clearance <= 2.0 * stage.tip_radius_mm(1):
            raise ValueError(f"planet_angles_deg: planets {min(gaps):g}° apart on a centre distance of "
                             f"{stage.centre_distance_mm:g} mm overlap (tip diameter {2 * stage.tip_radius_mm(1):g} mm)")
        return self

    @property
    def stage(self):
        """The :class:`rvcoax.geometry.gears.GearStage` of the sun and one planet."""
        from rvcoax.geometry.gears import GearStage

        return GearStage(normal_module_mm=self.normal_module_mm, teeth=(self.sun_teeth, self.planet_teeth),
                         normal_pressure_angle_deg=self.normal_pressure_angle_deg, face_width_mm=self.face_width_mm,
                         helix_angle_deg=self.helix_angle_deg, profile_shift=tuple(self.profile_shift),
                         dedendum_factor=self.dedendum_factor)



MAX_FACE_WIDTH_MODULES = 100.0
"""A gear face wider than this many normal modules is refused (ISO 6336 gears: b / m_n ≈ 6 … 40)."""


# ---- housings condensed from a solid model (issue 16 item 2) ------------------------------------------------

HOUSING_SHAPE_KEYS = {
    "block": {"required": ("height_above_bed_mm",), "optional": ("foot_thickness_mm", "foot_width_mm")},
    "pedestal": {"required": ("height_above_bed_mm", "seat_below_axis_mm", "web_length_mm", "web_width_mm",
                              "base_length_mm", "base_width_mm", "base_thickness_mm"), "optional": ("foot_pad_mm",)},
    "bracket": {"required": ("seat_below_axis_mm", "wall_distance_mm", "arm_length_mm", "arm_height_mm",
                             "plate_length_mm", "plate_height_mm", "plate_thickness_mm"), "optional": ("foot_pad_mm",)},
}
"""The dimension keys of each ``[[housings]]`` shape (the others are refused for it)."""

OptionalLength = Annotated[float, Field(gt=0.0, le=1e5, allow_inf_nan=False, strict=True)] | None
FootStiffness = Annotated[float, Field(gt=0.0, le=1e7, allow_inf_nan=False, strict=True)] | None


class Housing(StrictModel):
    """``[[housings]]``: a housing of part ``part`` (bearing block, web pedestal, wall bracket), condensed from a
    solid model.

    Every shape has a bearing seat spanning ``x_mm`` along the axis, ``width_mm`` across (z), up to
    ``top_above_axis_mm`` above the axis, with an optional bore (``bore_diameter_mm``) on the axis:

    * ``shape = "block"``: the seat reaches down to the bed face ``height_above_bed_mm`` below the axis, with an
      optional foot plate (``foot_thickness_mm`` × ``foot_width_mm``); its foot is the whole bed face;
    * ``"pedestal"``: the seat's underside is ``seat_below_axis_mm`` below the axis; a web (``web_length_mm`` ×
      ``web_width_mm``) carries it from a base plate (``base_length_mm`` × ``base_width_mm`` ×
      ``base_thickness_mm``) on the bed ``height_above_bed_mm`` below the axis;
    * ``"bracket"``: an arm (``arm_length_mm`` × ``arm_height_mm``) carries the seat from a plate
      (``plate_length_mm`` × ``plate_height_mm`` × ``plate_thickness_mm``) bolted to a wall parallel to the axis,
      ``wall_distance_mm`` from it on the −z side.

    A pedestal's or bracket's bolt feet are four squares of side ``foot_pad_mm`` at its plate's corners (0: the
    whole plate face). The feet are ``clamped``, sit on a Winkler ``bed`` (normal and shear stiffness per area), or
    on ``springs`` (``foot_stiffness_N_per_um`` per foot, spread over its area). At each of ``attachments_x_mm`` a
    reference node on the axis is tied to a band ``attachment_width_mm`` wide of the bore (of the top face without
    a bore); the solid model condensed to these nodes (a 6k × 6k stiffness to the ground, times
    ``stiffness_factor``) acts on the nodes of ``part`` there, as a bushing would. With ``self_weight`` the solid's
    own weight (its material's density × its volume) loads the rig too: the part of it the seats carry at the
    attachments, the rest straight on the bed. See :mod:`rvcoax.geometry.housings`.
    """

    name: Name
    part: str
    material: str
    shape: Literal["block", "pedestal", "bracket"] = "block"
    x_mm: tuple[Finite, Finite]
    width_mm: Positive
    height_above_bed_mm: OptionalLength = None
    top_above_axis_mm: Positive
    bore_diameter_mm: NonNegative = 0.0
    foot_thickness_mm: NonNegative = 0.0
    foot_width_mm: NonNegative = 0.0
    seat_below_axis_mm: OptionalLength = None
    web_length_mm: OptionalLength = None
    web_width_mm: OptionalLength = None
    base_length_mm: OptionalLength = None
    base_width_mm: OptionalLength = None
    base_thickness_mm: OptionalLength = None
    wall_distance_mm: OptionalLength = None
    arm_length_mm: OptionalLength = None
    arm_height_mm: OptionalLength = None
    plate_length_mm: OptionalLength = None
    plate_height_mm: OptionalLength = None
    plate_thickness_mm: OptionalLength = None
    foot_pad_mm: NonNegative = 0.0
    attachments_x_mm: list[Finite] = Field(min_length=1, max_length=8)
    attachment_width_mm: Positive = 10.0
    tie: Literal["distributing", "rigid"] = "distributing"
    feet: Literal["clamped", "bed", "springs"] = "clamped"
    bed_stiffness_N_per_um_per_mm2: Annotated[float, Field(gt=0.0, le=1e4, strict=True)] | None = None
    bed_shear_stiffness_N_per_um_per_mm2: Annotated[float, Field(gt=0.0, le=1e4, strict=True)] | None = None
    foot_stiffness_N_per_um: FootStiffness = None
    foot_shear_stiffness_N_per_um: FootStiffness = None
    mesh_size_mm: Positive = 8.0
    stiffness_factor: Annotated[float, Field(gt=0.0, le=100.0, allow_inf_nan=False, strict=True)] = 1.0
    self_weight: Flag = False

    @model_validator(mode="after")
    def _check(self) -> Housing:
        x0, x1 = self.x_mm
        for x in self.attachments_x_mm:
            if not x0 <= x <= x1:
                raise ValueError(f"attachments_x_mm: {x:g} lies outside the housing's x_mm [{x0:g}, {x1:g}]")
        ordered = sorted(self.attachments_x_mm)
        for a, b in zip(ordered, ordered[1:]):
            if not b - a >= self.attachment_width_mm:
                raise ValueError(f"attachment_width_mm = {self.attachment_width_mm:g}: the bore bands of the attachments "
                                 f"at x = {a:g} and {b:g} mm (attachments_x_mm) overlap; each band ties its own stretch "
                                 f"of the bore, so the width must be at most their distance, {b - a:g} mm")
        keys = HOUSING_SHAPE_KEYS[self.shape]
        missing = [key for key in keys["required"] if getattr(self, key) is None]
        if missing:
            raise ValueError(f"shape = \"{self.shape}\" needs {', '.join(missing)}")
        own = set(keys["required"]) | set(keys["optional"])
        # by value, not by what was typed: a dumped and re-read rig carries every default
        foreign = sorted({key for shape in HOUSING_SHAPE_KEYS.values() for key in (*shape["required"], *shape["optional"])
                          if key not in own and getattr(self, key) != type(self).model_fields[key].default})
        if foreign:
            owners = {key: [s for s, k in HOUSING_SHAPE_KEYS.items() if key in (*k["required"], *k["optional"])]
                      for key in foreign}
            raise ValueError(f"shape = \"{self.shape}\" has no " + "; ".join(
                f"{key} (a key of shape {' / '.join(owners[key])})" for key in foreign))
        if self.feet == "bed" and self.bed_stiffness_N_per_um_per_mm2 is None:
            raise ValueError("feet = \"bed\" needs bed_stiffness_N_per_um_per_mm2")
        if self.feet == "springs" and self.foot_stiffness_N_per_um is None:
            raise ValueError("feet = \"springs\" needs foot_stiffness_N_per_um (per bolt foot)")
        for key, feet in (("bed_stiffness_N_per_um_per_mm2", "bed"), ("bed_shear_stiffness_N_per_um_per_mm2", "bed"),
                          ("foot_stiffness_N_per_um", "springs"), ("foot_shear_stiffness_N_per_um", "springs")):
            if getattr(self, key) is not None and self.feet != feet:
                raise ValueError(f"{key} is used only with feet = \"{feet}\" (feet = \"{self.feet}\")")
        low, high = MESH_SIZE_RANGE_MM
        if not low <= self.mesh_size_mm <= high:
            raise ValueError(f"mesh_size_mm = {self.mesh_size_mm:g} mm is outside {low:g} … {high:g} mm")
        self.geometry  # noqa: B018 - raises ValueError naming what does not fit
        return self

    def bands_mm(self) -> list[tuple[float, float]]:
        """The band [x0, x1] each reference node is tied to (inside the housing)."""
        half = 0.5 * self.attachment_width_mm
        return [(max(x - half, self.x_mm[0]), min(x + half, self.x_mm[1])) for x in self.attachments_x_mm]

    def bed_stiffness_per_area(self) -> tuple[float, float] | None:
        """(normal, shear) stiffness per area under the feet, N/(µm·mm²): the Winkler bed's, or each bolt foot's
        spring spread over the foot's area (uniformly: a foot moved as a whole resists with its spring); None when
        clamped."""
        if self.feet == "bed":
            normal = self.bed_stiffness_N_per_um_per_mm2
            return normal, self.bed_shear_stiffness_N_per_um_per_mm2 or normal
        if self.feet == "springs":
            area = self.geometry.feet[0].area_mm2
            normal = self.foot_stiffness_N_per_um
            return normal / area, (self.foot_shear_stiffness_N_per_um or normal) / area
        return None

    def thermal_motion_mm_per_K(self) -> tuple[float, float]:
        """(y, z) growth of the axis per kelvin and per unit α: the pedestal's or block's height above the bed
        (it lifts the axis), a bracket's distance from its wall (it pushes the axis away along +z)."""
        if self.shape == "bracket":
            return 0.0, self.wall_distance_mm
        return self.height_above_bed_mm, 0.0

    @property
    def geometry(self):
        """The :class:`rvcoax.geometry.housings.HousingGeometry` (rig coordinates, mm)."""
        from rvcoax.geometry.housings import BlockGeometry, BracketGeometry, PedestalGeometry

        splits = tuple(x for band in self.bands_mm() for x in band)
        if self.shape == "block":
            return BlockGeometry(name=self.name, x_mm=tuple(self.x_mm), width_mm=self.width_mm,
                                 bottom_mm=-self.height_above_bed_mm, top_mm=self.top_above_axis_mm,
                                 bore_diameter_mm=self.bore_diameter_mm, foot_thickness_mm=self.foot_thickness_mm,
                                 foot_width_mm=self.foot_width_mm, split_x_mm=splits, mesh_size_mm=self.mesh_size_mm)
        seat = {"name": self.name, "x_mm": tuple(self.x_mm), "width_mm": self.width_mm, "top_mm": self.top_above_axis_mm,
                "seat_bottom_mm": -self.seat_below_axis_mm, "bore_diameter_mm": self.bore_diameter_mm,
                "split_x_mm": splits, "mesh_size_mm": self.mesh_size_mm, "foot_pad_mm": self.foot_pad_mm}
        if self.shape == "pedestal":
            return PedestalGeometry(**seat, bottom_mm=-self.height_above_bed_mm, web_length_mm=self.web_length_mm,
                                    web_width_mm=self.web_width_mm, base_length_mm=self.base_length_mm,
                                    base_width_mm=self.base_width_mm, base_thickness_mm=self.base_thickness_mm)
        return BracketGeometry(**seat, wall_z_mm=-self.wall_distance_mm, arm_length_mm=self.arm_length_mm,
                               arm_height_mm=self.arm_height_mm, plate_length_mm=self.plate_length_mm,
                               plate_height_mm=self.plate_height_mm, plate_thickness_mm=self.plate_thickness_mm)


# ---- temperatures (issue 16 item 4) ------------------------------------------------------------------------

TemperatureRise = Annotated[float, Field(ge=-100.0, le=300.0, allow_inf_nan=False, strict=True)]


class Thermal(StrictModel):
    """``[thermal]``: steady temperature rises (K, = °C of difference) from the state the rig was built in.

    ``temperature_rise_K`` per part (missing parts: 0) grows every part axially and radially by its
    material's ``thermal_expansion_per_K``; ``support_temperature_rise_K`` per mount or housing (default:
    its part's) lifts the mount or housing by α ΔT · ``height_above_bed_mm``; the bed (``bed_material``) grows along x
    from ``bed_fixed_x_mm`` by ``bed_temperature_rise_K``. See :mod:`rvcoax.geometry.thermal`.
    """

    temperature_rise_K: dict[str, TemperatureRise] = {}
    support_temperature_rise_K: dict[str, TemperatureRise] = {}
    bed_temperature_rise_K: TemperatureRise = 0.0
    bed_material: str | None = None
    bed_fixed_x_mm: Finite = 0.0


class ForcePair(StrictModel):
    label: str
    force_N: Finite
    plus_at: Location
    minus_at: Location


class SingleForce(StrictModel):
    label: str
    force_N: Finite
    at: Location


class ForceTable(StrictModel):
    apply: Flag = False
    scale: Finite = 1.0  # multiplies every force of the table when applied
    pairs: list[ForcePair] = []
    singles: list[SingleForce] = []


# --- load cases in the rig file (issue 15, outputs) ---------------------------------------------

class RigLoadCase(StrictModel):
    """One ``[[load_cases]]`` entry: a torque pair (N·m); optionally a name, speeds and its share of a duty
    cycle (bearing lives: :mod:`rvcoax.fem.bearing_life`)."""

    T1_input_Nm: Finite
    T2_output_Nm: Finite
    name: Name | None = None
    output_speed_rpm: Annotated[float, Field(ge=0.0, le=1e5, allow_inf_nan=False, strict=True)] | None = None
    input_speed_rpm: Annotated[float, Field(ge=0.0, le=1e6, allow_inf_nan=False, strict=True)] | None = Field(
        None, description="Default: output_speed_rpm × the reducer's ratio.")
    time_share: Annotated[float, Field(ge=0.0, le=1.0, allow_inf_nan=False, strict=True)] | None = None
    revolution_share: Annotated[float, Field(ge=0.0, le=1.0, allow_inf_nan=False, strict=True)] | None = None


class TorqueRange(StrictModel):
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


class Speeds(StrictModel):
    """``[speeds]``: the rig's running speeds, for the interference (Campbell) diagram of ``rvcoax modes``.

    The excitation orders: the motor speed n (×1 and ×2), the input gear's mesh frequency
    ``input_gear_teeth`` × n and the reducer's output speed n / ``reduction_ratio`` (×1).
    """

    motor_rpm: tuple[NonNegative, Positive]
    reduction_ratio: Annotated[float, Field(gt=1.0, le=1e5, allow_inf_nan=False, strict=True)]
    input_gear_teeth: Annotated[int, Field(ge=1, le=1000, strict=True)]

    @model_validator(mode="after")
    def _check(self) -> Speeds:
        low, high = self.motor_rpm
        if not low < high:
            raise ValueError(f"motor_rpm = [{low:g}, {high:g}] is no speed range: give [lowest, highest] with "
                             "lowest < highest (rpm)")
        return self


class SolidSettings(StrictModel):
    """Solid and hybrid models: which parts are solid in ``hybrid``, and mesh sizes."""

    hybrid_parts: list[str] | None = None
    mesh_size_mm: Positive = 4.0
    elements_per_diameter: Annotated[float, Field(ge=1, le=1000, allow_inf_nan=False, strict=True)] = 6.0
    attachment_band_mm: Positive = 10.0


class Path(StrictModel):
    part: str
    x_start_mm: Finite
    length_mm: Positive
    stations: Annotated[int, Field(ge=25, le=2001, strict=True)] = 41


class ShaftStrength(StrictModel):
    """How the shafts' DIN 743 safety is judged (issue 25 §5)."""

    overload_case: Literal[1, 2] = Field(2, description=(
        "DIN 743-1 overload case: 2 (default) mean and amplitude stresses grow together as the load grows; 1 the "
        "mean stress stays constant."))
    minimum_safety: Annotated[float, Field(ge=1.0, le=10.0, allow_inf_nan=False, strict=True)] = Field(
        1.2, description="Required safety S_min against fatigue fracture and permanent deformation (DIN 743-1: 1.2).")
    peak_load_factor: Annotated[float, Field(ge=1.0, le=10.0, allow_inf_nan=False, strict=True)] = Field(
        1.0, description="Maximum load of the static proof as a multiple of each case's load (start-up, braking, "
                         "an application factor); 1: the case's own load.")


class Paths(StrictModel):
    measured_from: Literal["aligned_at_rest", "unloaded"] = "aligned_at_rest"
    input: Path
    output: Path


class Rig(StrictModel):
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
    reducers: list[Reducer] = []
    torques: Torques
    torque_lateral_loads: list[TorqueLateralLoad] = []
    gear_meshes: list[GearMesh] = []
    thermal: Thermal | None = None
    housings: list[Housing] = []
    force_table: ForceTable = ForceTable()
    paths: Paths
    solid: SolidSettings = SolidSettings()
    # issue 15 (outputs): the rig's own load cases, a list or a range (not both)
    load_cases: list[RigLoadCase] = []
    sweep: TorqueRange | None = None
    # issue 26 (dynamics): running speeds for the interference diagram
    speeds: Speeds | None = None
    # issue 25 §5: the shafts' DIN 743 strength check
    shaft_strength: ShaftStrength = ShaftStrength()

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
    def _reducer_joints(self) -> Rig:
        """Each ``[[reducers]]`` entry stands in the model as a joint of its name (not written back to files)."""
        if self.reducers:
            from rvcoax.geometry.reducers import reducer_joint_data

            object.__setattr__(self, "joints", list(self.joints) + [Joint.model_validate(reducer_joint_data(r))
                                                                     for r in self.reducers])
        return self

    @property
    def generated_joint_names(self) -> tuple[str, ...]:
        """Joints that stand for a ``[[reducers]]`` entry (:mod:`rvcoax.geometry.reducers`)."""
        return tuple(r.name for r in self.reducers)

    @field_serializer("joints", mode="wrap")
    def _typed_joints(self, joints, handler):
        generated = set(self.generated_joint_names)
        return handler([j for j in joints if j.name not in generated])

    @model_validator(mode="after")
    def _cross_references(self) -> Rig:
        problems = list(self.reference_problems())
        if problems:
            raise ValueError("\n".join(problems))  # one problem a line (messages may hold "; ")
        return self

    @model_validator(mode="after")
    def _duty_cycle(self) -> Rig:
        """Shares of a duty cycle: one kind for all cases, each case with one, summing to 1."""
        for kind in ("time_share", "revolution_share"):
            shares = [getattr(c, kind) for c in self.load_cases]
            given = [s for s in shares if s is not None]
            if not given:
                continue
            other = "revolution_share" if kind == "time_share" else "time_share"
            if any(getattr(c, other) is not None for c in self.load_cases):
                raise ValueError(f"load_cases: give a duty cycle as {kind} or as {other}, not both")
            missing = [i for i, s in enumerate(shares) if s is None]
            if missing:
                raise ValueError(f"load_cases[{missing[0]}].{kind}: missing (a duty cycle gives every case its share)")
            if abs(sum(given) - 1.0) > 1e-3:
                raise ValueError(f"load_cases.{kind}: the shares sum to {sum(given):.6g}, not 1 (Palmgren–Miner needs "
                                 "the whole cycle)")
        names = [c.name for c in self.load_cases if c.name is not None]
        repeated = sorted({n for n in names if names.count(n) > 1})
        if repeated:
            raise ValueError(f"load_cases.name: repeated: {', '.join(repeated)}")
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

    def _gear_inside_shaft(self, i: int, g: GearMesh):
        """A driving gear whose teeth lie inside the shaft it sits on (tip circle within the shaft's Ø at
        ``on.x_mm``): module or tooth count far too small, or ``on`` names the wrong part."""
        part = next((p for p in self.parts if p.name == g.on.part), None)
        if part is None:
            return
        here = [s.outer_diameter_mm for s in part.segments if s.x_mm[0] - 1e-9 <= g.on.x_mm <= s.x_mm[1] + 1e-9]
        stage = g.stage
        tip = 2.0 * stage.tip_radius_mm(0)
        if here and tip <= max(here):
            yield (f"gear_meshes[{i}] ('{g.name}'): the driving gear's tip circle (Ø{tip:.4g} mm; pitch circle "
                   f"Ø{2 * stage.pitch_radius_mm(0):.4g} mm = normal_module_mm × sun_teeth / cos β) lies inside the "
                   f"shaft '{g.on.part}' (Ø{max(here):g} mm at on.x_mm = {g.on.x_mm:g}): its teeth cannot mesh; "
                   "check normal_module_mm and sun_teeth, or on.part")

    def _thermal_problems(self):
        """Unknown names, and a temperature rise on a material without ``thermal_expansion_per_K``."""
        for i, m in enumerate(self.mounts):
            if m.support_material is not None and m.support_material not in self.materials:
                yield (f"mounts[{i}] ('{m.name}').support_material: unknown material '{m.support_material}' "
                       f"(known: {', '.join(sorted(self.materials))})")
        thermal = self.thermal
        if thermal is None:
            return
        parts = {p.name: p for p in self.parts}
        mounts = {m.name: m for m in self.mounts}

        def expands(where: str, material: str | None):
            if material is None or material not in self.materials:
                return
            if self.materials[material].thermal_expansion_per_K is None:
                yield f"{where}: material '{material}' has no thermal_expansion_per_K (needed for a temperature rise)"

        for name, rise in thermal.temperature_rise_K.items():
            if name not in parts:
                yield f"thermal.temperature_rise_K.{name}: unknown part '{name}' (parts: {', '.join(parts)})"
            elif rise != 0.0:
                yield from expands(f"thermal.temperature_rise_K.{name}", parts[name].material)
        housings = {h.name: h for h in self.housings}
        for name in thermal.support_temperature_rise_K:
            if name not in mounts and name not in housings:
                yield (f"thermal.support_temperature_rise_K.{name}: unknown mount or housing '{name}' "
                       f"(mounts: {', '.join(mounts) or 'none'}; housings: {', '.join(housings) or 'none'})")
        for i, h in enumerate(self.housings):
            rise = thermal.support_temperature_rise_K.get(h.name, thermal.temperature_rise_K.get(h.part, 0.0))
            if rise != 0.0:
                yield from expands(f"housings[{i}] ('{h.name}').material", h.material)
        for i, m in enumerate(self.mounts):
            rise = thermal.support_temperature_rise_K.get(m.name, thermal.temperature_rise_K.get(m.part, 0.0))
            if rise == 0.0 or m.part not in parts:
                continue
            if m.height_above_bed_mm is None:
                yield (f"mounts[{i}] ('{m.name}').height_above_bed_mm: required when its support is {rise:g} K warmer "
                       "([thermal]): the support lifts the axis by α ΔT · height")
            yield from expands(f"mounts[{i}] ('{m.name}')", m.support_material or parts[m.part].material)
        if thermal.bed_temperature_rise_K != 0.0:
            if thermal.bed_material is None:
                yield "thermal.bed_material: required when bed_temperature_rise_K is not 0"
            elif thermal.bed_material not in self.materials:
                yield (f"thermal.bed_material: unknown material '{thermal.bed_material}' "
                       f"(known: {', '.join(sorted(self.materials))})")
            else:
                yield from expands("thermal.bed_material", thermal.bed_material)

    def _reducer_problems(self):
        """A typed-in joint that doubles a reducer's (same parts, same place), and a case that is no housing."""
        generated = set(self.generated_joint_names)
        for i, r in enumerate(self.reducers):
            for j, joint in enumerate(self.joints):
                if joint.name in generated:
                    continue
                if ({joint.from_.part, joint.to.part} == {r.case.part, r.output.part}
                        and abs(joint.from_.x_mm - r.case.x_mm) < 1e-6):
                    yield (f"joints[{j}] ('{joint.name}') joins '{r.case.part}' and '{r.output.part}' at x = "
                           f"{r.case.x_mm:g} mm, where reducers[{i}] ('{r.name}') already stands for the main "
                           "bearings: remove the joint (its stiffness would count twice)")

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
        yield from self._connection_problems(parts)
        yield from self._load_problems(parts)
        yield from self._thermal_problems()
        yield from self._housing_problems(parts)
        yield from self._force_table_problems(parts)
        yield from self._path_problems(parts)
        yield from self._overlapping_supports()
        yield from self._overlapping_shafts()
        yield from self._metre_scale()
        yield from self._mesh_sizes()
        for name in self.solid.hybrid_parts or []:
            if name not in parts:
                yield f"solid.hybrid_parts: unknown part '{name}' (parts: {', '.join(parts)})"
        yield from self._repeated_names()
        from rvcoax.geometry.shaft_notches import notch_problems

        yield from notch_problems(self)

    @staticmethod
    def _at(parts: dict, where: str, part: str, x: float, role: str | None = None):
        """A position ``x`` on ``part``: the part exists, ``x`` lies on it (and the part has ``role``)."""
        if part not in parts:
            yield f"{where}: unknown part '{part}' (parts: {', '.join(parts)})"
            return
        lo, hi = parts[part].x_range_mm
        if not lo - 1e-9 <= x <= hi + 1e-9:
            yield f"{where}: x_mm = {x} lies outside part '{part}' ({lo} .. {hi} mm)"
        if role and parts[part].role != role:
            yield f"{where}: part '{part}' is a {parts[part].role}, expected a {role}"

    def _connection_problems(self, parts: dict):
        """Bearings, mounts, couplings and joints: their parts and positions."""
        for i, b in enumerate(self.bearings):
            yield from self._at(parts, f"bearings[{i}] ('{b.name}').shaft", b.shaft, b.x_mm)
            if b.housing != "ground":
                yield from self._at(parts, f"bearings[{i}] ('{b.name}').housing", b.housing, b.x_mm)
                if b.housing == b.shaft:
                    yield f"bearings[{i}] ('{b.name}'): shaft and housing are the same part"
        for i, m in enumerate(self.mounts):
            yield from self._at(parts, f"mounts[{i}] ('{m.name}')", m.part, m.x_mm)
        for group, items in (("couplings", self.couplings), ("joints", self.joints)):
            for i, c in enumerate(items):
                yield from self._at(parts, f"{group}[{i}] ('{c.name}').from", c.from_.part, c.from_.x_mm)
                yield from self._at(parts, f"{group}[{i}] ('{c.name}').to", c.to.part, c.to.x_mm)
                if c.from_.part == c.to.part:
                    yield f"{group}[{i}] ('{c.name}'): from and to are the same part '{c.to.part}'"

    def _load_problems(self, parts: dict):
        """The torques, the torque-proportional lateral loads and the gear meshes: where they act."""
        springs = {item.name for group in (self.bearings, self.mounts, self.couplings, self.joints) for item in group}
        springs |= {r.name for r in self.reducers}
        for key in ("T1", "T2"):
            t = getattr(self.torques, key)
            yield from self._at(parts, f"torques.{key}", t.part, t.x_mm)
            if t.reacted_on is not None:
                yield from self._at(parts, f"torques.{key}.reacted_on", t.reacted_on.part, t.reacted_on.x_mm)
                if t.reacted_on.part == t.part:
                    yield f"torques.{key}: part and reacted_on are the same part '{t.part}'"
            if t.reaction_spring is not None and t.reaction_spring not in springs:
                yield (f"torques.{key}.reaction_spring: no bearing, mount, coupling, joint or reducer named "
                       f"'{t.reaction_spring}'")
        yield from self._reducer_problems()
        for i, t in enumerate(self.torque_lateral_loads):
            yield from self._at(parts, f"torque_lateral_loads[{i}] ('{t.name}').on", t.on.part, t.on.x_mm)
            if t.reacted_on is not None:
                yield from self._at(parts, f"torque_lateral_loads[{i}] ('{t.name}').reacted_on", t.reacted_on.part, t.reacted_on.x_mm)
        for i, g in enumerate(self.gear_meshes):
            yield from self._at(parts, f"gear_meshes[{i}] ('{g.name}').on", g.on.part, g.on.x_mm)
            yield from self._at(parts, f"gear_meshes[{i}] ('{g.name}').reacted_on", g.reacted_on.part, g.reacted_on.x_mm)
            if g.planet_material is not None and g.planet_material not in self.materials:
                yield (f"gear_meshes[{i}] ('{g.name}').planet_material: unknown material '{g.planet_material}' "
                       f"(known: {', '.join(sorted(self.materials))})")
            if g.on.part == g.reacted_on.part:
                yield f"gear_meshes[{i}] ('{g.name}'): on and reacted_on are the same part '{g.on.part}'"
            yield from self._gear_inside_shaft(i, g)

    def _housing_problems(self, parts: dict):
        """``[[housings]]``: their part, attachments and material."""
        for i, h in enumerate(self.housings):
            yield from self._at(parts, f"housings[{i}] ('{h.name}').part", h.part, h.attachments_x_mm[0])
            for x in h.attachments_x_mm[1:]:
                yield from self._at(parts, f"housings[{i}] ('{h.name}').attachments_x_mm", h.part, x)
            if h.material not in self.materials:
                yield (f"housings[{i}] ('{h.name}').material: unknown material '{h.material}' "
                       f"(known: {', '.join(sorted(self.materials))})")

    def _force_table_problems(self, parts: dict):
        """The force table's pairs and single forces: where they act."""
        for i, f in enumerate(self.force_table.pairs):
            yield from self._at(parts, f"force_table.pairs[{i}] ('{f.label}').plus_at", f.plus_at.part, f.plus_at.x_mm)
            yield from self._at(parts, f"force_table.pairs[{i}] ('{f.label}').minus_at", f.minus_at.part, f.minus_at.x_mm)
        for i, f in enumerate(self.force_table.singles):
            yield from self._at(parts, f"force_table.singles[{i}] ('{f.label}').at", f.at.part, f.at.x_mm)

    def _path_problems(self, parts: dict):
        """The measured paths: on their part, not running past its end."""
        for key in MEASURED_SHAFTS:
            path = getattr(self.paths, key)
            yield from self._at(parts, f"paths.{key}.x_start_mm", path.part, path.x_start_mm)
            if path.part in parts:
                lo, hi = parts[path.part].x_range_mm
                end = path.x_start_mm + path.length_mm
                if end > hi + 1e-9:
                    yield (f"paths.{key}.length_mm: the path x_start_mm + length_mm = {path.x_start_mm:g} + "
                           f"{path.length_mm:g} = {end:g} mm runs past the end of part '{path.part}' ({lo:g} .. {hi:g} mm)")

    def _overlapping_supports(self):
        """Two supports of one part at the same place."""
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

    def _repeated_names(self):
        """Names of connections, loads and housings are unique."""
        names = [item.name for group in (self.bearings, self.mounts, self.couplings, self.joints,
                                         self.torque_lateral_loads, self.gear_meshes, self.housings)
                 for item in group]
        repeated = sorted({n for n in names if names.count(n) > 1})
        if repeated:
            yield f"names of bearings, mounts, couplings, joints, torque_lateral_loads, gear_meshes and housings must be unique; repeated: {', '.join(repeated)}"
