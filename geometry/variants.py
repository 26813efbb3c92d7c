"""The reference rig read from geometry (issue 16): gear data, condensed bearing blocks, temperatures.

:func:`reference_from_geometry` returns the built-in reference rig with

* ``gears``: the typed-in ``sun_gear_load_sharing`` replaced by the input stage's gear data
  (:data:`INPUT_GEAR_MESH`, ``[[gear_meshes]]``);
* ``housings``: the typed-in mounts ``input_block_base`` and ``output_block_base`` replaced by the two
  HT200 bearing blocks condensed from a solid model (:data:`BEARING_BLOCKS`, ``[[housings]]``);
* ``thermal``: expansion coefficients of the three materials (:data:`THERMAL_EXPANSION_PER_K`), support
  heights and a warm-running state (:data:`THERMAL`, ``[thermal]``);
* ``pedestals`` (on request, instead of ``housings``): the same two bearing seats carried by web pedestals
  (:data:`BEARING_PEDESTALS`, ``shape = "pedestal"``: a base plate with four bolt feet and a web under the
  seat) instead of solid blocks;
* ``ball_bearings`` (on request, not in the default :data:`READINGS`): the input (6204) and output (6206)
  shaft bearings as CN deep-groove ball bearings from their internal geometry (:data:`SHAFT_BALL_BEARINGS`,
  ``model = "ball"``, solved nonlinearly: the same as ``rvcoax rig reference --variant ball_bearings``).

The same keys, written out, are in docs/rig-file.md. Every number is an assumption [A] unless tagged.
"""

from __future__ import annotations

import tomllib

from rvcoax.geometry.rigfile import parse_rig, reference_rig_text
from rvcoax.geometry.schema import Rig

__all__ = ["BEARING_BLOCKS", "BEARING_PEDESTALS", "INPUT_GEAR_MESH", "OPTIONAL_READINGS", "READINGS", "SHAFT_BALL_BEARINGS", "THERMAL",
           "THERMAL_EXPANSION_PER_K", "reference_from_geometry"]

READINGS = ("gears", "housings", "thermal")
OPTIONAL_READINGS = ("ball_bearings", "pedestals")
"""Readings taken only when asked for: the ball bearings make the sweep nonlinear (case by case); the pedestals
are the bearing blocks' alternative (not with ``housings``)."""
SHAFT_BALL_BEARINGS = {"input_B1": "6204", "input_B2": "6204", "output_B1": "6206", "output_B2": "6206"}  # [S]

INPUT_GEAR_MESH = {
    "name": "input_gear_mesh", "torque": "T1",
    "on": {"part": "input_shaft", "x_mm": 330.0, "band_mm": [322.0, 340.0]},
    "reacted_on": {"part": "reducer", "x_mm": 330.0},
    "normal_module_mm": 1.0, "sun_teeth": 20, "planet_teeth": 40,  # pitch Ø20 mm as the typed-in pitch_radius_mm
    "normal_pressure_angle_deg": 20.0, "face_width_mm": 10.0, "helix_angle_deg": 0.0,
    "planet_angles_deg": [90.0, 270.0],  # crankshafts on the horizontal centre line
    # nominal: an error at the edge of the IT3 band (2 µm [P]) would open one mesh below |T1| = 3.5 N·m, i.e.
    # over the whole reference range, where the linear load sharing does not hold (docs/model.md)
    "planet_position_errors_um": [0.0, 0.0],
}

BEARING_BLOCKS = (
    {"name": "input_block", "part": "input_bearing_block", "material": "HT200", "x_mm": [248.0, 320.0],
     "width_mm": 90.0, "height_above_bed_mm": 100.0, "top_above_axis_mm": 45.0, "bore_diameter_mm": 47.0,
     "foot_thickness_mm": 15.0, "foot_width_mm": 150.0, "attachments_x_mm": [255.0, 315.0],
     "attachment_width_mm": 14.0, "mesh_size_mm": 8.0},
    {"name": "output_block", "part": "output_bearing_block", "material": "HT200", "x_mm": [420.0, 510.0],
     "width_mm": 110.0, "height_above_bed_mm": 100.0, "top_above_axis_mm": 55.0, "bore_diameter_mm": 62.0,
     "foot_thickness_mm": 15.0, "foot_width_mm": 170.0, "attachments_x_mm": [430.0, 500.0],
     "attachment_width_mm": 16.0, "mesh_size_mm": 8.0},
)
BEARING_PEDESTALS = (  # the same seats, bores and axis height as BEARING_BLOCKS; web and base plate [A]
    {"name": "input_block", "part": "input_bearing_block", "material": "HT200", "shape": "pedestal",
     "x_mm": [248.0, 320.0], "width_mm": 90.0, "top_above_axis_mm": 45.0, "bore_diameter_mm": 47.0,
     "seat_below_axis_mm": 40.0, "web_length_mm": 72.0, "web_width_mm": 40.0, "height_above_bed_mm": 100.0,
     "base_length_mm": 120.0, "base_width_mm": 150.0, "base_thickness_mm": 15.0, "foot_pad_mm": 30.0,
     "attachments_x_mm": [255.0, 315.0], "attachment_width_mm": 14.0, "mesh_size_mm": 8.0},
    {"name": "output_block", "part": "output_bearing_block", "material": "HT200", "shape": "pedestal",
     "x_mm": [420.0, 510.0], "width_mm": 110.0, "top_above_axis_mm": 55.0, "bore_diameter_mm": 62.0,
     "seat_below_axis_mm": 45.0, "web_length_mm": 90.0, "web_width_mm": 50.0, "height_above_bed_mm": 100.0,
     "base_length_mm": 140.0, "base_width_mm": 170.0, "base_thickness_mm": 15.0, "foot_pad_mm": 30.0,
     "attachments_x_mm": [430.0, 500.0], "attachment_width_mm": 16.0, "mesh_size_mm": 8.0},
)
REPLACED_MOUNTS = ("input_block_base", "output_block_base")

THERMAL_EXPANSION_PER_K = {"40Cr": 11.0e-6, "HT200": 10.0e-6, "Q460": 12.0e-6}  # sources: docs/rig-file.md
SUPPORT_HEIGHT_MM = 100.0  # axis above the bed
THERMAL = {
    "temperature_rise_K": {"motor_housing": 25.0, "motor_shaft": 20.0, "reducer": 20.0, "input_shaft": 10.0,
                           "output_shaft": 10.0, "brake_housing": 40.0, "brake_shaft": 30.0},
    "bed_temperature_rise_K": 5.0, "bed_material": "Q460", "bed_fixed_x_mm": 0.0,
}


def reference_from_geometry(readings=READINGS, block_mesh_size_mm: float | None = None) -> Rig:
    """The reference rig with the ``readings`` (a subset of :data:`READINGS`) taken from geometry.

    ``block_mesh_size_mm`` overrides the bearing blocks' (or pedestals') mesh size (8 mm, converged to 0.3 %).

    Parameters
    ----------
    readings : tuple of str
        Which values are read from geometry instead of typed in (default: all of :data:`READINGS`).
    block_mesh_size_mm : float, optional
        Mesh size of the condensed bearing blocks.

    Returns
    -------
    Rig
        The validated rig.
    """
    unknown = set(readings) - set(READINGS) - set(OPTIONAL_READINGS)
    if unknown:
        raise ValueError(f"unknown readings {sorted(unknown)}; choose from {', '.join(READINGS + OPTIONAL_READINGS)}")
    if "housings" in readings and "pedestals" in readings:
        raise ValueError("readings 'housings' (solid blocks) and 'pedestals' are alternatives: choose one")
    data = tomllib.loads(reference_rig_text())
    if "gears" in readings:
        data["torque_lateral_loads"] = [t for t in data["torque_lateral_loads"] if t["name"] != "sun_gear_load_sharing"]
        data["gear_meshes"] = [dict(INPUT_GEAR_MESH)]
    if "housings" in readings or "pedestals" in readings:
        data["mounts"] = [m for m in data["mounts"] if m["name"] not in REPLACED_MOUNTS]
        data["housings"] = [dict(block) for block in (BEARING_BLOCKS if "housings" in readings else BEARING_PEDESTALS)]
        if block_mesh_size_mm is not None:
            for block in data["housings"]:
                block["mesh_size_mm"] = block_mesh_size_mm
    if "thermal" in readings:
        for name, alpha in THERMAL_EXPANSION_PER_K.items():
            data["materials"][name]["thermal_expansion_per_K"] = alpha
        for mount in data["mounts"]:
            mount["height_above_bed_mm"] = SUPPORT_HEIGHT_MM
        data["thermal"] = THERMAL
    if "ball_bearings" in readings:
        for bearing in data["bearings"]:
            if bearing["name"] in SHAFT_BALL_BEARINGS:
                for key in ("radial_stiffness_N_per_um", "axial_stiffness_N_per_um", "width_mm"):
                    bearing.pop(key, None)
                bearing.update(model="ball", designation=SHAFT_BALL_BEARINGS[bearing["name"]], clearance_class="CN")
    return parse_rig(data, "<reference rig from geometry>")
