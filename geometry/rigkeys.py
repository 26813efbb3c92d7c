"""The rig-file key reference (``docs/rig-keys.md``), generated from the schema.

Every key of :class:`rvcoax.geometry.schema.Rig` is listed with its unit (read from its name: the
project's rule is that every key says its unit), its default (or "required"), the range the schema
accepts, the plausible range the catalogue warns outside (:mod:`rvcoax.geometry.catalogue`) and its
meaning (the key's pydantic ``description`` when it has one, else :data:`MEANINGS`).

Run ``python -m rvcoax.geometry.rigkeys docs/rig-keys.md`` to rewrite the page; a test fails when the
committed page differs from what this module writes, or when a key has no meaning.
"""

from __future__ import annotations

import sys
import types
import typing
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from pydantic import BaseModel
from pydantic.fields import FieldInfo

from rvcoax.geometry.catalogue import CATALOGUE, RADIAL_STIFFNESS_PER_BORE
from rvcoax.geometry.schema import Rig

__all__ = ["KeyRow", "MEANINGS", "UNIT_SUFFIXES", "key_rows", "render_markdown", "unit_of"]

# key-name endings → the unit they name (longest first wins)
UNIT_SUFFIXES = {
    "_N_per_um": "N/µm", "_N_per_mm": "N/mm", "_Nm_per_rad": "N·m/rad", "_N_per_Nm": "N/(N·m)", "_Nm_per_arcmin": "N·m/′", "_kN": "kN",
    "_kg_per_m3": "kg/m³", "_kg_m2": "kg·m²", "_m_per_s2": "m/s²", "_MPa": "MPa", "_mm": "mm", "_um": "µm", "_kg": "kg",
    "_deg": "°", "_mrad": "mrad", "_arcmin": "′ (arcminute)", "_rpm": "1/min", "_Nm": "N·m", "_N": "N",
    "_N_per_mm_per_um": "N/(mm·µm)", "_N_per_um_per_mm2": "N/(µm·mm²)", "_per_K": "1/K",
    "_K": "K (= °C of difference)", "_mm2_per_s": "mm²/s",
}

# where a key's meaning is not in the schema itself (dotted path; [] = any entry of a list,
# <name> = any key of a table)
MEANINGS = {
    "schema_version": "Version of the rig-file format; 1.",
    "rig.name": "Name of the rig, shown in every output.",
    "rig.description": "One line describing the rig's layout.",
    "gravity.enabled": "Apply the self-weight of every part and coupling (−y).",
    "gravity.acceleration_m_per_s2": "Gravitational acceleration.",
    "mesh.max_element_length_mm": "Longest beam element; beams are exact per element, so this only sets "
                                  "how densely results are sampled.",
    "beam.shear_deformation": "Timoshenko shafts (true) or Euler–Bernoulli shafts (false).",
    "beam.shear_flexibility_factor": "Multiplies the shafts' shear flexibility Φ: 1 exact Timoshenko, "
                                     "0 Euler–Bernoulli.",
    "materials.<name>.youngs_modulus_MPa": "Young's modulus E of the material.",
    "materials.<name>.poisson_ratio": "Poisson's ratio ν (sets G = E / 2(1 + ν)).",
    "materials.<name>.density_kg_per_m3": "Density (for a body, replaced by the one that gives mass_kg).",
    "materials.<name>.thermal_expansion_per_K": "Mean linear thermal expansion coefficient α; needed by every "
                                                "material that [thermal] warms (part, support, housing, bed).",
    "parts[].name": "Unique name of the part (letters, digits, _ . -).",
    "parts[].role": "shaft (rotates, density of its material) or body (a housing drawn as an equivalent "
                    "round body).",
    "parts[].material": "Name of an entry of [materials].",
    "parts[].mass_kg": "A body's catalogue mass; its density is set so that the modelled mass equals it. "
                       "Required for bodies.",
    "parts[].mesh_size_mm": "Solid mesh size of this part in hybrid and solid models (default [solid]).",
    "parts[].segments[].x_mm": "Start and end of the segment along the rig axis [start, end].",
    "parts[].segments[].outer_diameter_mm": "Outer diameter of the segment.",
    "parts[].segments[].inner_diameter_mm": "Bore of the segment (0: solid).",
    "bearings[].name": "Unique name of the bearing.",
    "bearings[].shaft": "The part the inner ring sits on.",
    "bearings[].housing": "The part holding the outer ring, or \"ground\".",
    "bearings[].x_mm": "Bearing centre along the rig axis.",
    "bearings[].radial_stiffness_N_per_um": "Radial stiffness (datasheet rigidity, or Palmgren's law at the "
                                            "expected load): one of the numbers that matter most.",
    "bearings[].axial_stiffness_N_per_um": ("Axial stiffness (0: the bearing floats axially); on a cylindrical_roller "
                                            "bearing its ribs' contact: NJ one way (axial_direction), NUP both, "
                                            "NU/N none (refused); default for NJ/NUP the radial reference stiffness "
                                            "(estimated)."),
    "bearings[].tilt_stiffness_Nm_per_rad": "Moment stiffness against tilting the rings (0 for a single "
                                            "deep-groove ball bearing).",
    "bearings[].width_mm": "Bearing width (catalogue), for drawing and solid attachment bands.",
    "bearings[].radial_clearance_um": "Radial play; above 0 the bearing is solved as a nonlinear gap "
                                      "(beam model).",
    "bearings[].allowable_misalignment_arcmin": "Tilt of the inner ring against the outer that the bearing "
                                                "type tolerates (catalogue; deep-groove ball bearings 2′ … 10′).",
    "mounts[].name": "Unique name of the mount.",
    "mounts[].part": "The part the mount holds to the ground.",
    "mounts[].x_mm": "Mount position along the rig axis.",
    "mounts[].translational_stiffness_N_per_um": "Stiffness in x, y, z (bolted feet, pedestals; 0: free).",
    "mounts[].rotational_stiffness_Nm_per_rad": "Stiffness about x, y, z (0: free).",
    "mounts[].vertical_offset_um": "Ground side raised by this much (+y): shims, thermal growth.",
    "mounts[].height_above_bed_mm": "Axis height h above the bed at the mount: a support ΔT warmer lifts the "
                                    "part by α ΔT h ([thermal]); required when the support warms.",
    "mounts[].support_material": "Material of the support (pedestal, bracket), whose α sets that lift "
                                 "(default: the part's material).",
    "couplings[].name": "Unique name of the coupling.",
    "couplings[].from.part": "The part the first hub sits on.",
    "couplings[].from.x_mm": "Where the first hub grips its shaft.",
    "couplings[].from.band_mm": "On a solid part: the band of its surface the hub grips [start, end].",
    "couplings[].from.tie": "How a solid face is tied to the spring: distributing or rigid.",
    "couplings[].to.part": "The part the second hub sits on.",
    "couplings[].to.x_mm": "Where the second hub grips its shaft.",
    "couplings[].to.band_mm": "On a solid part: the band of its surface the hub grips [start, end].",
    "couplings[].to.tie": "How a solid face is tied to the spring: distributing or rigid.",
    "couplings[].centre_x_mm": "Coupling centre (where offset and angle are reported).",
    "couplings[].hub_length_mm": "Length of a hub.",
    "couplings[].mass_kg": "Mass of the coupling, carried by its two hubs (datasheet).",
    "couplings[].radial_stiffness_N_per_mm": "Lateral stiffness between the hubs (datasheet): sets the force "
                                             "a parallel offset puts on the shafts.",
    "couplings[].angular_stiffness_Nm_per_rad": "Bending stiffness between the hubs (datasheet).",
    "couplings[].torsional_stiffness_Nm_per_rad": "Torsional stiffness (datasheet).",
    "couplings[].axial_stiffness_N_per_mm": "Axial stiffness (datasheet).",
    "couplings[].parallel_offset_um": "Parallel offset of the to hub's axis as installed (alignment).",
    "couplings[].angular_misalignment_mrad": "Angle of the to hub's axis as installed (alignment).",
    "couplings[].misalignment_direction_deg": "Direction of the installed misalignment: 0 = +y, 90 = +z.",
    "couplings[].allowable_parallel_offset_mm": "Parallel offset the coupling maker allows (datasheet).",
    "couplings[].allowable_angular_misalignment_deg": "Angular misalignment the coupling maker allows "
                                                      "(datasheet).",
    "couplings[].speed_rpm": "Running speed, which grades the misalignment against alignment tolerances.",
    "couplings[].polar_inertia_kg_m2": "Polar mass moment of the coupling about its axis, half on each hub "
                                       "(natural frequencies); without it the hubs are point masses.",
    "speeds.motor_rpm": "The motor's speed range [lowest, highest] for the interference diagram of rvcoax modes.",
    "speeds.reduction_ratio": "The reducer's ratio: output speed = motor speed / ratio (the output order).",
    "speeds.input_gear_teeth": "Teeth of the input gear: its mesh frequency = teeth × motor speed.",
    "joints[].name": "Unique name of the joint.",
    "joints[].from.part": "First part joined.",
    "joints[].from.x_mm": "Where the joint sits on the first part.",
    "joints[].from.band_mm": "On a solid part: the band of its surface tied [start, end].",
    "joints[].from.tie": "How a solid face is tied: distributing or rigid.",
    "joints[].to.part": "Second part joined.",
    "joints[].to.x_mm": "Where the joint sits on the second part.",
    "joints[].to.band_mm": "On a solid part: the band of its surface tied [start, end].",
    "joints[].to.tie": "How a solid face is tied: distributing or rigid.",
    "joints[].translational_stiffness_N_per_um": "Stiffness in x, y, z between the parts (bolted flange, "
                                                 "reducer bearings).",
    "joints[].rotational_stiffness_Nm_per_rad": "Stiffness about x, y, z between the parts.",
    "reducers[].name": "Unique name; the reducer's main bearings and output are the joint of this name.",
    "reducers[].case.part": "The reducer's housing part (role body).",
    "reducers[].case.x_mm": "The main bearings' centre (where their moment is checked).",
    "reducers[].case.band_mm": "On a solid part: the band of its surface tied [start, end].",
    "reducers[].case.tie": "How a solid face is tied: distributing or rigid.",
    "reducers[].output.part": "The part bolted to the output flange (the output shaft).",
    "reducers[].output.x_mm": "Same x as the case: the main bearings' centre.",
    "reducers[].output.band_mm": "On a solid part: the band of its surface tied [start, end].",
    "reducers[].output.tie": "rigid for a bolted flange (the face moves as a rigid body).",
    "torques.T1.part": "Where the input torque T1 enters (the motor shaft).",
    "torques.T1.x_mm": "Position of the input torque.",
    "torques.T1.sign": "+1 or −1: the direction of T1 on that part.",
    "torques.T2.part": "Where the output torque T2 is reacted (the brake shaft).",
    "torques.T2.x_mm": "Position of the output torque.",
    "torques.T2.sign": "+1 or −1: the direction of T2 on that part.",
    **{f"torques.{key}.reacted_on.{item}": text for key in ("T1", "T2") for item, text in (
        ("part", f"The stator of the motor or brake that applies {key} (its housing): takes the opposite torque, so "
                 "the support under it carries it as on the bench; none: the rig's torsional springs take it."),
        ("x_mm", "Where the opposite torque acts."),
        ("band_mm", "On a solid part: the band of its surface loaded [start, end]."),
        ("tie", "How a solid face is loaded: distributing or rigid."))},
    "torque_lateral_loads[].name": "Unique name of the load.",
    "torque_lateral_loads[].torque": "The torque that drives the load: T1 or T2.",
    "torque_lateral_loads[].kind": "gear_mesh_load_sharing, crank_load_sharing, torque_arm or proportional "
                                   "(see docs/rig-file.md).",
    "torque_lateral_loads[].on.part": "Part the lateral force acts on.",
    "torque_lateral_loads[].on.x_mm": "Where it acts.",
    "torque_lateral_loads[].on.band_mm": "On a solid part: the band of its surface loaded [start, end].",
    "torque_lateral_loads[].on.tie": "How a solid face is loaded: distributing or rigid.",
    "torque_lateral_loads[].reacted_on.part": "Part that carries the opposite force (the housing); none: "
                                              "reacted by the ground.",
    "torque_lateral_loads[].reacted_on.x_mm": "Where the opposite force acts.",
    "torque_lateral_loads[].reacted_on.band_mm": "On a solid part: the band of its surface loaded.",
    "torque_lateral_loads[].reacted_on.tie": "How a solid face is loaded: distributing or rigid.",
    "torque_lateral_loads[].direction_deg": "Direction of the force: 0 = +y, 90 = +z.",
    "torque_lateral_loads[].imbalance": "(k1 − k2)/(k1 + k2) of the two load paths (load sharing kinds).",
    "torque_lateral_loads[].position_error_um": "Position error Δε of the two meshes along their line of "
                                                "action (load sharing kinds).",
    "torque_lateral_loads[].mesh_stiffness_N_per_um": "Mesh stiffness of one path (load sharing kinds).",
    "torque_lateral_loads[].pitch_radius_mm": "Pitch radius of the gear (gear_mesh_load_sharing).",
    "torque_lateral_loads[].pressure_angle_deg": "Pressure angle α (gear_mesh_load_sharing).",
    "torque_lateral_loads[].radius_mm": "Radius of the crankshafts' circle (crank_load_sharing).",
    "torque_lateral_loads[].arm_length_mm": "Length of the torque arm (torque_arm): F = T / arm.",
    "torque_lateral_loads[].force_per_torque_N_per_Nm": "Lateral force per unit torque (proportional).",
    "gear_meshes[].name": "Unique name of the gear stage (the discrepancy effect mesh_position_error@<name>).",
    "gear_meshes[].torque": "The torque the driving gear transmits (times its sign): T1 or T2.",
    "gear_meshes[].on.part": "Part carrying the driving (input, sun) gear: the net mesh force acts on it.",
    "gear_meshes[].on.x_mm": "Where the driving gear sits (the mesh forces act).",
    "gear_meshes[].on.band_mm": "On a solid part: the band of its surface loaded [start, end].",
    "gear_meshes[].on.tie": "How a solid face is loaded: distributing or rigid.",
    "gear_meshes[].reacted_on.part": "Part carrying the planets' bearings (the reducer case): takes the "
                                     "reversed net force and moment.",
    "gear_meshes[].reacted_on.x_mm": "Where the reaction acts.",
    "gear_meshes[].reacted_on.band_mm": "On a solid part: the band of its surface loaded [start, end].",
    "gear_meshes[].reacted_on.tie": "How a solid face is loaded: distributing or rigid.",
    "gear_meshes[].normal_module_mm": "Normal module m_n (pitch radius r = m_n z / 2 cos β).",
    "gear_meshes[].sun_teeth": "Number of teeth z1 of the driving (sun) gear.",
    "gear_meshes[].planet_teeth": "Number of teeth z2 of each planet gear.",
    "gear_meshes[].normal_pressure_angle_deg": "Normal pressure angle α_n of the basic rack.",
    "gear_meshes[].face_width_mm": "Common face width b: each mesh's stiffness is c_γα · b (times its factor).",
    "gear_meshes[].helix_angle_deg": "Helix angle β (0: spur; > 0: right hand on the driving gear): axial mesh "
                                     "forces W tan β_b and their tilting moment.",
    "gear_meshes[].profile_shift": "Profile shift coefficients [x_sun, x_planet] (in modules): set the working "
                                   "pressure angle, the tip radii and ISO 6336-1's q′.",
    "gear_meshes[].dedendum_factor": "Basic-rack dedendum h_fP/m_n (1.25: ISO 53 profile A): sets ISO 6336-1's "
                                     "C_B.",
    "gear_meshes[].blank_factor": "Gear blank factor C_R of ISO 6336-1 (1: solid disc gears).",
    "gear_meshes[].planet_material": "Material of the planet gears, whose E enters E_eq of the mesh stiffness "
                                     "(default: the driving gear's part's material).",
    "gear_meshes[].mesh_stiffness_N_per_mm_per_um": "Mesh stiffness per face width c_γα given instead of "
                                                    "ISO 6336-1's (then no material or blank factor enters).",
    "gear_meshes[].planet_angles_deg": "Angle φ of each planet's centre from +y towards +z: one entry per planet "
                                       "(2 … 12).",
    "gear_meshes[].planet_position_errors_um": "Each planet mesh's position error along its line of action "
                                               "(+ = engages later; default 0): the constant part of the load "
                                               "sharing.",
    "gear_meshes[].planet_stiffness_factors": "Multiplies each planet mesh's stiffness (default 1): unequal "
                                              "stiffnesses share the torque unequally.",
    "housings[].name": "Unique name of the housing (a key of support_temperature_rise_K; the discrepancy "
                       "effect housing_stiffness@<name>).",
    "housings[].part": "The part whose nodes the condensed housing holds to the ground (it keeps its beam and "
                       "mass; not a solid of the hybrid model).",
    "housings[].material": "Material of the housing's solid model (E, ν; α for its thermal lift).",
    "housings[].shape": "block (a box down to the bed), pedestal (bearing seat on a web on a base plate with "
                        "bolt feet) or bracket (bearing seat on an arm from a plate bolted to a wall).",
    "housings[].x_mm": "Start and end of the block or bearing seat along the rig axis [start, end].",
    "housings[].width_mm": "Width of the block or bearing seat across the axis (z), centred on it.",
    "housings[].height_above_bed_mm": "Axis height above the bed face (the feet's underside): the block's or "
                                      "base plate's bottom, and h of its thermal lift α ΔT h (block, pedestal).",
    "housings[].top_above_axis_mm": "Height of the block's or seat's top face above the axis.",
    "housings[].bore_diameter_mm": "Through bore on the axis (the bearing seat the attachments tie to); 0: no "
                                   "bore, they tie to the top face.",
    "housings[].foot_thickness_mm": "Block: thickness of a foot plate (bolt flange) on the bed (0: none).",
    "housings[].foot_width_mm": "Block: width (z) of the foot plate, at least the block's width.",
    "housings[].seat_below_axis_mm": "Pedestal, bracket: depth of the bearing seat's underside below the axis "
                                     "(more than the bore's radius).",
    "housings[].web_length_mm": "Pedestal: the web's length along the axis (x), centred under the seat; short: "
                                "a plate across the axis.",
    "housings[].web_width_mm": "Pedestal: the web's width across the axis (z); narrow: a plate along the axis.",
    "housings[].base_length_mm": "Pedestal: the base plate's length along the axis (x), centred under the seat.",
    "housings[].base_width_mm": "Pedestal: the base plate's width across the axis (z), centred on it.",
    "housings[].base_thickness_mm": "Pedestal: the base plate's thickness; the web runs from its top to the seat.",
    "housings[].wall_distance_mm": "Bracket: distance from the axis to the wall face (the plate's back), on the "
                                   "−z side; d of its thermal push α ΔT d (+z).",
    "housings[].arm_length_mm": "Bracket: the arm's length along the axis (x), centred on the seat.",
    "housings[].arm_height_mm": "Bracket: the arm's height (y), centred on the axis; it runs along z from the "
                                "wall plate to the seat's side face.",
    "housings[].plate_length_mm": "Bracket: the wall plate's length along the axis (x), centred on the seat.",
    "housings[].plate_height_mm": "Bracket: the wall plate's height (y), centred on the axis.",
    "housings[].plate_thickness_mm": "Bracket: the wall plate's thickness (z).",
    "housings[].foot_pad_mm": "Pedestal, bracket: side of the four square bolt feet at the corners of the base "
                              "or wall plate (the areas clamped or sprung; 0: the whole plate face).",
    "housings[].attachments_x_mm": "Each attachment (bearing seat): a 6-DOF node on the axis, inside x_mm, that "
                                   "the condensed stiffness acts at on the part's node there.",
    "housings[].attachment_width_mm": "Width along x of the band of the bore (or top face) each attachment "
                                      "node is tied to (the bearing's width).",
    "housings[].tie": "How each attachment node is tied to its band: distributing (RBE3-like) or rigid.",
    "housings[].feet": "Feet (the bed face, or the bolt feet) clamped, resting on a Winkler bed (\"bed\": "
                       "bed_stiffness_N_per_um_per_mm2) or on a spring each (\"springs\": foot_stiffness_N_per_um).",
    "housings[].bed_stiffness_N_per_um_per_mm2": "Normal stiffness per area of the Winkler bed under the feet (y; "
                                                 "z for a bracket's wall); required with feet = \"bed\".",
    "housings[].bed_shear_stiffness_N_per_um_per_mm2": "Shear stiffness per area of the Winkler bed in the feet's "
                                                       "plane (default: the normal one).",
    "housings[].foot_stiffness_N_per_um": "Normal stiffness of each foot's spring (the bed's or wall's, and the "
                                          "bolt's), spread evenly over the foot; required with feet = \"springs\".",
    "housings[].foot_shear_stiffness_N_per_um": "Shear stiffness of each foot's spring in the foot's plane "
                                                "(default: the normal one).",
    "housings[].mesh_size_mm": "Solid mesh size of the housing (condensed once, then read from the cache).",
    "housings[].stiffness_factor": "Multiplies the condensed stiffness matrix.",
    "housings[].self_weight": "Add the solid's own weight (density × modelled volume) under gravity: the seats "
                              "sag as in the full solid; leave it out of the part's mass_kg.",
    "thermal.temperature_rise_K.<name>": "Steady temperature rise ΔT of a part over the state the rig was aligned "
                                         "in: it grows by α ΔT axially and radially (parts not named: 0).",
    "thermal.support_temperature_rise_K.<name>": "Temperature rise of a mount's support or of a housing, by its "
                                                 "name (default: its part's): lifts the axis by α ΔT h.",
    "thermal.bed_temperature_rise_K": "Temperature rise of the bed: it carries mounts, ground bearings and "
                                      "housings along x by α_bed ΔT (x − bed_fixed_x_mm).",
    "thermal.bed_material": "Material of the bed (its α); required when bed_temperature_rise_K is not 0.",
    "thermal.bed_fixed_x_mm": "Where the bed is pinned along the rig axis: it grows from there.",
    "force_table.apply": "Apply the measured force table (true) or not.",
    "force_table.scale": "Multiplies every force of the table.",
    "force_table.pairs[].label": "Name of the force pair.",
    "force_table.pairs[].force_N": "Size of the pair: +force at plus_at, −force at minus_at (y).",
    "force_table.pairs[].plus_at.part": "Part loaded with +force.",
    "force_table.pairs[].plus_at.x_mm": "Where +force acts.",
    "force_table.pairs[].plus_at.band_mm": "On a solid part: the band loaded.",
    "force_table.pairs[].plus_at.tie": "How a solid face is loaded: distributing or rigid.",
    "force_table.pairs[].minus_at.part": "Part loaded with −force.",
    "force_table.pairs[].minus_at.x_mm": "Where −force acts.",
    "force_table.pairs[].minus_at.band_mm": "On a solid part: the band loaded.",
    "force_table.pairs[].minus_at.tie": "How a solid face is loaded: distributing or rigid.",
    "force_table.singles[].label": "Name of the force.",
    "force_table.singles[].force_N": "Vertical force (+y up).",
    "force_table.singles[].at.part": "Part loaded.",
    "force_table.singles[].at.x_mm": "Where the force acts.",
    "force_table.singles[].at.band_mm": "On a solid part: the band loaded.",
    "force_table.singles[].at.tie": "How a solid face is loaded: distributing or rigid.",
    "paths.measured_from": "Y from the aligned rig at rest (aligned_at_rest, as a dial gauge zeroed at "
                           "rest) or from the unloaded geometry (unloaded).",
    "paths.input.part": "The measured input shaft.",
    "paths.input.x_start_mm": "Start of the measured input path along the rig axis.",
    "paths.input.length_mm": "Length L of the input path (β = arcsin(Y_max / L)).",
    "paths.input.stations": "Number of stations Y is read at along the path.",
    "paths.output.part": "The measured output shaft.",
    "paths.output.x_start_mm": "Start of the measured output path along the rig axis.",
    "paths.output.length_mm": "Length L of the output path.",
    "paths.output.stations": "Number of stations Y is read at along the path.",
    "solid.hybrid_parts": "Parts that are solids in the hybrid model (default: the two measured shafts).",
    "solid.mesh_size_mm": "Global solid mesh size.",
    "solid.elements_per_diameter": "At least this many elements across a solid part's diameter.",
    "solid.attachment_band_mm": "Width of the surface band a spring attaches to on a solid part.",
    "load_cases[].T1_input_Nm": "Input torque of one load case.",
    "load_cases[].T2_output_Nm": "Output torque of one load case.",
    "load_cases[].name": "The case's name in the tables (default: its torques).",
    "load_cases[].output_speed_rpm": "Output speed in this case (bearing lives in hours).",
    "load_cases[].time_share": "Share of the duty cycle's time in this case (all cases; sum 1): Palmgren–Miner.",
    "load_cases[].revolution_share": "Share of the duty cycle's output revolutions (instead of time_share).",
    "sweep.T1_input_Nm": "First and last input torque of an evenly spaced sweep [first, last].",
    "sweep.T2_output_Nm": "First and last output torque [first, last].",
    "sweep.cases": "Number of evenly spaced load cases from first to last.",
}

_CATALOGUE_KINDS = {"bearings": "bearing", "couplings": "coupling", "mounts": "mount", "joints": "joint",
                    "torque_lateral_loads": "torque_lateral_load", "parts": "segment",
                    "materials": "material"}


@dataclass(frozen=True)
class KeyRow:
    """One line of the key reference."""

    section: str
    key: str
    kind: str
    unit: str
    default: str
    allowed: str
    plausible: str
    meaning: str


def unit_of(name: str) -> str:
    """The unit a key's name ends in ('' for a plain number, a name or a flag)."""
    for suffix in sorted(UNIT_SUFFIXES, key=len, reverse=True):
        if name.endswith(suffix):
            return UNIT_SUFFIXES[suffix]
    return ""


def _strip(annotation):
    """(the type without Optional and Annotated, the FieldInfos met on the way, optional?)."""
    infos, optional = [], False
    while True:
        origin = typing.get_origin(annotation)
        if origin is typing.Annotated:
            args = typing.get_args(annotation)
            infos += [a for a in args[1:] if isinstance(a, FieldInfo)]
            annotation = args[0]
        elif origin in (typing.Union, types.UnionType):
            args = [a for a in typing.get_args(annotation) if a is not type(None)]
            optional = optional or len(args) < len(typing.get_args(annotation))
            if len(args) != 1:
                return annotation, infos, optional
            annotation = args[0]
        else:
            return annotation, infos, optional


def _bounds_text(metadata) -> str:
    parts = {}
    for item in metadata:
        for attribute, symbol in (("gt", ">"), ("ge", "≥"), ("lt", "<"), ("le", "≤")):
            value = getattr(item, attribute, None)
            if value is not None:
                parts[symbol] = value
    low = next(((s, parts[s]) for s in (">", "≥") if s in parts), None)
    high = next(((s, parts[s]) for s in ("<", "≤") if s in parts), None)
    if low and high:
        if low[0] == "≥" and high[0] == "≤":
            return f"{low[1]:g} … {high[1]:g}"
        return f"{low[0]} {low[1]:g} and {high[0]} {high[1]:g}"
    if low:
        return f"{low[0]} {low[1]:g}"
    if high:
        return f"{high[0]} {high[1]:g}"
    return ""


def _kind_and_allowed(annotation, field: FieldInfo | None) -> tuple[str, str]:
    core, infos, _ = _strip(annotation)
    metadata = list(field.metadata if field is not None else []) + [m for i in infos for m in i.metadata]
    origin = typing.get_origin(core)
    if origin is typing.Literal:
        return "choice", " or ".join(repr(a).replace("'", "\"") for a in typing.get_args(core))
    if origin is tuple:
        items = typing.get_args(core)
        inner_kind, inner = _kind_and_allowed(items[0], None)
        return f"[{', '.join([inner_kind] * len(items))}]", inner
    if origin is list:
        inner_kind, inner = _kind_and_allowed(typing.get_args(core)[0], None)
        return f"list of {inner_kind}", inner
    if core is bool:
        return "true/false", "true or false"
    if core is int:
        return "integer", _bounds_text(metadata)
    if core is float:
        text = _bounds_text(metadata)
        return "number", text or "finite"
    if core is str:
        pattern = next((getattr(m, "pattern", None) for m in metadata if getattr(m, "pattern", None)), None)
        return "text", "letters, digits, _ . -" if pattern else ""
    return getattr(core, "__name__", str(core)), ""


def _default_text(field: FieldInfo) -> str:
    extra = field.json_schema_extra if isinstance(field.json_schema_extra, dict) else {}
    if "default_text" in extra:  # a default that depends on another key (a bearing's model)
        return str(extra["default_text"])
    if field.is_required():
        return "required"
    value = field.get_default(call_default_factory=True)
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, BaseModel):
        return "(table)"
    if isinstance(value, list | tuple):
        return "[]" if not value else str(list(value))
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def _plausible(section: str, name: str) -> str:
    kind = _CATALOGUE_KINDS.get(section)
    row = next((r for r in CATALOGUE if r.kind == kind and r.key == name), None)
    if row is None:
        return ""
    text = f"{row.low:g} … {row.high:g}" + (" (or 0)" if row.zero_allowed else "")
    if (kind, name) == ("bearing", "radial_stiffness_N_per_um"):
        low, high = RADIAL_STIFFNESS_PER_BORE
        text += f", and {low:g}·d … {high:g}·d for a bore of d mm"
    return text


def _walk(model: type[BaseModel], prefix: str, section: str) -> Iterator[KeyRow]:
    for name, field in model.model_fields.items():
        key = field.alias or name
        path = f"{prefix}{key}"
        core, _, _ = _strip(field.annotation)
        origin = typing.get_origin(core)
        if isinstance(core, type) and issubclass(core, BaseModel):
            yield from _walk(core, f"{path}.", section or key)
            continue
        if origin is list and isinstance(typing.get_args(core)[0], type) \
                and issubclass(typing.get_args(core)[0], BaseModel):
            yield from _walk(typing.get_args(core)[0], f"{path}[].", section or key)
            continue
        if origin is dict:
            value_type, _, _ = _strip(typing.get_args(core)[1])
            if isinstance(value_type, type) and issubclass(value_type, BaseModel):
                yield from _walk(value_type, f"{path}.<name>.", section or key)
                continue
            # a map of plain values keyed by name (e.g. a temperature rise per part): one row, <name> = value
            kind, allowed = _kind_and_allowed(typing.get_args(core)[1], None)
            meaning = field.description or MEANINGS.get(f"{path}.<name>", "")
            yield KeyRow(section=section or key, key=f"{path}.<name>", kind=f"{kind} per name", unit=unit_of(key),
                         default=_default_text(field), allowed=allowed, plausible=_plausible(section or key, key),
                         meaning=meaning)
            continue
        kind, allowed = _kind_and_allowed(field.annotation, field)
        meaning = field.description or MEANINGS.get(path, "")
        yield KeyRow(section=section or key, key=path, kind=kind, unit=unit_of(key), default=_default_text(field),
                     allowed=allowed, plausible=_plausible(section or key, key), meaning=meaning)


def key_rows() -> list[KeyRow]:
    """Every key of the rig file, in the schema's order."""
    return list(_walk(Rig, "", ""))


def _cell(text: str) -> str:
    return text.replace("|", "\\|") or "–"


def render_markdown() -> str:
    """The key reference page (Markdown), as committed in ``docs/rig-keys.md``."""
    lines = ["# Rig-file keys", "",
             "<!-- generated by `python -m rvcoax.geometry.rigkeys docs/rig-keys.md` from the schema "
             "(geometry/schema.py); do not edit by hand: a test fails when this page is out of date -->", "",
             "Every key of a rig file, grouped by its table. **Unit**: named by the key itself (`_mm`, "
             "`_N_per_um`, …). **Allowed**: what the rig file accepts (anything else is refused with the key "
             "and the reason). **Plausible**: outside this range `rvcoax` warns before solving (a likely unit "
             "slip), see `geometry/catalogue.py`. `[]` marks any entry of a list (`[[bearings]]`), `<name>` "
             "any key of a table (`[materials.40Cr]`). How the keys fit together: [rig-file.md](rig-file.md); "
             "a worked example: [tutorial.md](tutorial.md).", ""]
    current = None
    for row in key_rows():
        if row.section != current:
            current = row.section
            lines += ["", f"## `{current}`", "",
                      "| key | type | unit | default | allowed | plausible | meaning |",
                      "|---|---|---|---|---|---|---|"]
        lines.append(f"| `{row.key}` | {_cell(row.kind)} | {_cell(row.unit)} | {_cell(row.default)} | "
                     f"{_cell(row.allowed)} | {_cell(row.plausible)} | {_cell(row.meaning)} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    """Write the page to the path given (default: print it)."""
    args = sys.argv[1:] if argv is None else argv
    text = render_markdown()
    if args:
        Path(args[0]).write_text(text, encoding="utf-8")
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
