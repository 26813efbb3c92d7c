"""The engineering tables of a sweep (results/engineering.py) against closed forms.

* a shaft simply supported on two bearings with a point load: bearing forces P·b/L and P·a/L, and
  the tilt of each bearing's inner ring, which is the beam's end slope
  θ_A = P·a·b·(L + b) / (6 E I L), θ_B = P·a·b·(L + a) / (6 E I L) (shear deformation does not change
  the section rotation at the supports of a simply supported beam: ∫γ dx = ΔM/κGA = 0);
* a coupling between two shafts, one of them lifted and tilted as a rigid body by raised mounts:
  parallel offset δ1 + θ (c − x1) at the coupling centre c and angle θ = (δ2 − δ1)/(x2 − x1);
* the alignment-tolerance table by running speed, and the global equilibrium residual.
"""

from __future__ import annotations

import math

import pytest

from rvcoax.geometry.rigfile import parse_rig_text
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.engineering import ALIGNMENT_TOLERANCES, alignment_grade, alignment_tolerance, engineering_tables
from rvcoax.results.sweep import run_sweep

E_MPA, DIAMETER_MM = 2.1e5, 30.0
L_MM, A_MM, P_N = 300.0, 100.0, 1000.0

HEADER = """
schema_version = 1
[rig]
name = "closed form"
[gravity]
enabled = false
[materials.steel]
youngs_modulus_MPa = 2.1e5
poisson_ratio = 0.3
density_kg_per_m3 = 7850
"""


def simply_supported_rig() -> str:
    return HEADER + f"""
[[parts]]
name = "shaft"
role = "shaft"
material = "steel"
segments = [{{ x_mm = [0, {L_MM}], outer_diameter_mm = {DIAMETER_MM} }}]
[[bearings]]
name = "A"
shaft = "shaft"
housing = "ground"
x_mm = 0
radial_stiffness_N_per_um = 1e6
axial_stiffness_N_per_um = 1e3
allowable_misalignment_arcmin = 2
[[bearings]]
name = "B"
shaft = "shaft"
housing = "ground"
x_mm = {L_MM}
radial_stiffness_N_per_um = 1e6
[[mounts]]
name = "torsion"
part = "shaft"
x_mm = 50
translational_stiffness_N_per_um = [0, 0, 0]
rotational_stiffness_Nm_per_rad = [1e3, 0, 0]
[torques.T1]
part = "shaft"
x_mm = 10
[torques.T2]
part = "shaft"
x_mm = 290
[force_table]
apply = true
[[force_table.singles]]
label = "P"
force_N = {-P_N}
at = {{ part = "shaft", x_mm = {A_MM} }}
[paths]
measured_from = "unloaded"
[paths.input]
part = "shaft"
x_start_mm = 0
length_mm = 150
[paths.output]
part = "shaft"
x_start_mm = 150
length_mm = 150
"""


def test_bearing_forces_and_tilts_of_a_simply_supported_shaft_are_the_beam_formulas():
    rig = parse_rig_text(simply_supported_rig(), "simply supported")
    tables = engineering_tables(run_sweep(rig, (LoadCase(0.0, 0.0),)))[0]
    L, a = L_MM * 1e-3, A_MM * 1e-3
    b = L - a
    ei = E_MPA * 1e6 * math.pi * (DIAMETER_MM * 1e-3) ** 4 / 64
    slope = {"A": P_N * a * b * (L + b) / (6 * ei * L), "B": P_N * a * b * (L + a) / (6 * ei * L)}
    force = {"A": P_N * b / L, "B": P_N * a / L}
    bearings = {row["name"]: row for row in tables["bearings"]}
    for name in ("A", "B"):
        assert bearings[name]["tilt_urad"] == pytest.approx(slope[name] * 1e6, rel=1e-4)
        assert bearings[name]["force_radial_N"] == pytest.approx(force[name], rel=1e-6)
        assert bearings[name]["force_y_N"] == pytest.approx(force[name], rel=1e-6)  # the bearing holds the shaft up
    # θ_A = 6.65e-4 rad = 2.29′ against an allowable 2′: judged, with the percentage
    assert bearings["A"]["tilt_arcmin"] == pytest.approx(math.degrees(slope["A"]) * 60, rel=1e-4)
    assert bearings["A"]["verdict"] == "exceeds allowable tilt"
    assert bearings["A"]["tilt_use_percent"] == pytest.approx(100 * math.degrees(slope["A"]) * 60 / 2, rel=1e-4)
    assert bearings["B"]["verdict"] == "no allowable tilt given"
    # the grounded bearings are in the reaction table, and the loads balance
    reactions = {row["name"]: row for row in tables["reactions"]}
    assert reactions["A"]["force_N"][1] == pytest.approx(force["A"], rel=1e-6)
    assert reactions["torsion"]["force_N"] == [0.0, 0.0, 0.0]
    assert tables["equilibrium_residual"]["force_N"] < 1e-6 * P_N


DELTA1_UM, DELTA2_UM, X1_MM, X2_MM, CENTRE_MM = 40.0, 100.0, 250.0, 350.0, 205.0


def _raised_mount(name: str, x_mm: float, offset_um: float, axial: float, torsional: float) -> str:
    """A stiff mount under the right shaft whose ground side is raised by ``offset_um``."""
    return "\n".join([
        "[[mounts]]", f'name = "{name}"', 'part = "right"', f"x_mm = {x_mm}",
        f"translational_stiffness_N_per_um = [{axial}, 1e4, 1e4]",
        f"rotational_stiffness_Nm_per_rad = [{torsional}, 0, 0]", f"vertical_offset_um = {offset_um}"])


def offset_shafts_rig(speed_rpm: float) -> str:
    return HEADER + f"""
[[parts]]
name = "left"
role = "shaft"
material = "steel"
segments = [{{ x_mm = [0, 200], outer_diameter_mm = 30 }}]
[[parts]]
name = "right"
role = "shaft"
material = "steel"
segments = [{{ x_mm = [210, 400], outer_diameter_mm = 30 }}]
[[bearings]]
name = "left_a"
shaft = "left"
housing = "ground"
x_mm = 20
radial_stiffness_N_per_um = 1e4
axial_stiffness_N_per_um = 1e3
[[bearings]]
name = "left_b"
shaft = "left"
housing = "ground"
x_mm = 180
radial_stiffness_N_per_um = 1e4
{_raised_mount("raised_1", X1_MM, DELTA1_UM, axial=1e3, torsional=1e3)}
{_raised_mount("raised_2", X2_MM, DELTA2_UM, axial=0, torsional=0)}
[[couplings]]
name = "C"
from = {{ part = "left", x_mm = 190 }}
to = {{ part = "right", x_mm = 220 }}
centre_x_mm = {CENTRE_MM}
radial_stiffness_N_per_mm = 0.01
angular_stiffness_Nm_per_rad = 0.001
torsional_stiffness_Nm_per_rad = 1e3
axial_stiffness_N_per_mm = 0.01
allowable_parallel_offset_mm = 0.1
allowable_angular_misalignment_deg = 1.0
speed_rpm = {speed_rpm}
[torques.T1]
part = "left"
x_mm = 100
[torques.T2]
part = "right"
x_mm = 300
[paths]
measured_from = "unloaded"
[paths.input]
part = "left"
x_start_mm = 0
length_mm = 200
[paths.output]
part = "right"
x_start_mm = 210
length_mm = 190
"""


def test_coupling_between_offset_shafts_reports_the_rigid_body_offset_and_angle():
    rig = parse_rig_text(offset_shafts_rig(1500.0), "offset shafts")
    sweep = run_sweep(rig, (LoadCase(0.0, 0.0),))
    coupling = engineering_tables(sweep)[0]["couplings"][0]
    theta = (DELTA2_UM - DELTA1_UM) * 1e-6 / ((X2_MM - X1_MM) * 1e-3)  # 0.6 mrad
    offset_um = DELTA1_UM + theta * (CENTRE_MM - X1_MM) * 1e3  # the lifted shaft's line at the coupling centre
    assert coupling["offset_um"] == pytest.approx(offset_um, rel=1e-6)
    assert coupling["offset_y_um"] == pytest.approx(offset_um, rel=1e-6)
    assert coupling["angle_urad"] == pytest.approx(theta * 1e6, rel=1e-6)
    assert coupling["angularity_mm_per_100mm"] == pytest.approx(100 * math.tan(theta), rel=1e-6)
    # the lifted shaft really is where the mounts put it (the hub motion the coupling sees)
    path = sweep.cases[0].paths["output"]
    assert path.end_offsets_um[0] == pytest.approx(DELTA1_UM + theta * (210 - X1_MM) * 1e3, rel=1e-6)
    assert path.fitted_tilt_urad == pytest.approx(theta * 1e6, rel=1e-6)
    # 13 µm and 0.06 mm/100 mm at 1500 rpm: offset excellent (≤ 0.06 mm), angularity acceptable (≤ 0.07)
    assert coupling["grade"] == "acceptable"
    assert coupling["offset_use_percent"] == pytest.approx(offset_um * 1e-3 / 0.1 * 100, rel=1e-6)
    assert coupling["datasheet_verdict"] == "within datasheet"
    slow = engineering_tables(run_sweep(parse_rig_text(offset_shafts_rig(600.0), "slow"), (LoadCase(0.0, 0.0),)))
    assert slow[0]["couplings"][0]["grade"] == "excellent"  # 750 rpm row: 0.09 mm/100 mm
    fast = engineering_tables(run_sweep(parse_rig_text(offset_shafts_rig(3600.0), "fast"), (LoadCase(0.0, 0.0),)))
    assert fast[0]["couplings"][0]["grade"] == "out of tolerance"  # 6000 rpm row: 0.03 mm/100 mm


def test_alignment_tolerance_rows_by_speed():
    assert alignment_tolerance(15.0) is ALIGNMENT_TOLERANCES[0]  # slower than the table: its slowest row
    assert alignment_tolerance(750.0) is ALIGNMENT_TOLERANCES[0]
    assert alignment_tolerance(751.0) is ALIGNMENT_TOLERANCES[1]
    assert alignment_tolerance(1e5) is ALIGNMENT_TOLERANCES[-1]
    assert alignment_grade(0.05, 0.04, 1500.0) == "excellent"
    assert alignment_grade(0.08, 0.04, 1500.0) == "acceptable"
    assert alignment_grade(0.10, 0.04, 1500.0) == "out of tolerance"
    assert alignment_grade(0.05, 0.08, 1500.0) == "out of tolerance"
