"""docs/rig-keys.md is generated from the schema: it is up to date, every key has a meaning, and every number
key names its unit (or is one of the few dimensionless numbers)."""

from __future__ import annotations

from pathlib import Path

from rvcoax.geometry.rigkeys import key_rows, render_markdown, unit_of

PAGE = Path(__file__).resolve().parents[2] / "docs" / "rig-keys.md"
DIMENSIONLESS = {"beam.shear_flexibility_factor", "force_table.scale", "materials.<name>.poisson_ratio",
                 "paths.input.stations", "paths.output.stations", "solid.elements_per_diameter",
                 "torque_lateral_loads[].imbalance", "torques.T1.sign", "torques.T2.sign", "schema_version",
                 "sweep.cases", "gear_meshes[].sun_teeth", "gear_meshes[].planet_teeth",
                 "gear_meshes[].profile_shift", "gear_meshes[].dedendum_factor", "gear_meshes[].blank_factor",
                 "gear_meshes[].planet_stiffness_factors", "housings[].stiffness_factor",
                 "bearings[].ball_count", "bearings[].inner_conformity", "bearings[].outer_conformity",
                 "bearings[].viscosity_ratio", "bearings[].contamination_factor", "load_cases[].time_share",
                 "load_cases[].revolution_share", "reducers[].ratio", "bearings[].roller_count",
                 "bearings[].slices_per_roller", "bearings[].minimum_load_factor",
                 "speeds.reduction_ratio", "speeds.input_gear_teeth",
                 "parts[].notches[].keys", "shaft_strength.overload_case", "shaft_strength.minimum_safety",
                 "shaft_strength.peak_load_factor"}


def test_the_committed_key_reference_is_up_to_date():
    assert PAGE.read_text(encoding="utf-8") == render_markdown(), (
        "docs/rig-keys.md is out of date: run `python -m rvcoax.geometry.rigkeys docs/rig-keys.md`")


def test_every_key_has_a_meaning():
    assert [row.key for row in key_rows() if not row.meaning] == []


def test_every_number_key_names_its_unit():
    numbers = [row for row in key_rows() if row.kind.startswith(("number", "integer", "[number")) or
               row.key.endswith(".sign")]
    assert {row.key for row in numbers if not row.unit} <= DIMENSIONLESS
    assert unit_of("radial_stiffness_N_per_um") == "N/µm" and unit_of("x_mm") == "mm"
    assert unit_of("force_per_torque_N_per_Nm") == "N/(N·m)" and unit_of("T2_output_Nm") == "N·m"
    assert unit_of("mesh_stiffness_N_per_mm_per_um") == "N/(mm·µm)" and unit_of("thermal_expansion_per_K") == "1/K"
    assert unit_of("bed_stiffness_N_per_um_per_mm2") == "N/(µm·mm²)" and unit_of("bed_temperature_rise_K").startswith("K")


def test_rows_carry_schema_bounds_defaults_and_catalogue_ranges():
    rows = {row.key: row for row in key_rows()}
    bearing = rows["bearings[].radial_stiffness_N_per_um"]
    assert (bearing.unit, bearing.allowed) == ("N/µm", "> 0") and bearing.default.startswith("required")
    assert bearing.plausible.startswith("1 … 5000") and "0.5·d … 100·d" in bearing.plausible
    assert rows["materials.<name>.poisson_ratio"].allowed == "> -1 and < 0.5"
    assert rows["gravity.enabled"].default == "true"
    assert rows["couplings[].from.part"].kind == "text"  # the alias "from", not the field name from_
