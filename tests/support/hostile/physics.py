"""Physically suspicious but valid rigs: they solve (exit 0) and the warning names the key and the range.

Each case edits one value or one reference of the built-in reference rig (unit slips such as N/m in an
``_N_per_um`` key, a torque on a housing, a bearing with shaft and housing swapped, a load reacted on
its own part) and runs ``sweep``; stderr must carry a warning with the rig-file key and the plausible
range from :mod:`rvcoax.geometry.catalogue` (or the topology's explanation).
"""

from __future__ import annotations

from hostile import Hostile
from hostile._files import reference_rig, write

K = "physics"


def _rig_case(label: str, old: str, new: str, *expected: str) -> Hostile:
    def argv(folder):
        text = reference_rig()
        assert old in text, old
        path = write(folder, "rig.toml", text.replace(old, new, 1))
        return ["sweep", "--rig", path, "--t1", "1", "--t2", "100", "--out", str(folder / "out")]

    return Hostile(f"{K}: {label}", K, argv, ("warning:", *expected), exit_code=0, stream="stderr")


B1 = 'radial_stiffness_N_per_um = 50      # [S] 40-65 N/µm'
CASES: list[Hostile] = [
    _rig_case("bearing radial stiffness in N/m", B1, "radial_stiffness_N_per_um = 8e7",
              "bearings[4] ('input_B1').radial_stiffness_N_per_um = 8e+07 N/µm", "(1 … 5000 N/µm)", "written in N/m?"),
    _rig_case("bearing radial stiffness in N/mm", B1, "radial_stiffness_N_per_um = 5e4",
              "bearings[4] ('input_B1').radial_stiffness_N_per_um = 50000 N/µm", "written in N/mm?"),
    _rig_case("bearing radial stiffness tiny", B1, "radial_stiffness_N_per_um = 0.05",
              "bearings[4] ('input_B1').radial_stiffness_N_per_um = 0.05 N/µm", "(1 … 5000 N/µm)"),
    _rig_case("bearing axial stiffness in N/m", "axial_stiffness_N_per_um = 20       # [A] locating bearing\n[[bearings]]\nname = \"input_B2\"",
              "axial_stiffness_N_per_um = 2e7\n[[bearings]]\nname = \"input_B2\"",
              "bearings[4] ('input_B1').axial_stiffness_N_per_um = 2e+07 N/µm", "written in N/m?"),
    _rig_case("coupling radial stiffness in N/m", "radial_stiffness_N_per_mm = 720                     # [S]",
              "radial_stiffness_N_per_mm = 7.2e8", "couplings[0] ('C1').radial_stiffness_N_per_mm = 7.2e+08 N/mm",
              "(10 … 1e+06 N/mm)", "written in N/m?"),
    _rig_case("coupling angular stiffness in N·mm/rad", "angular_stiffness_Nm_per_rad = 150 ",
              "angular_stiffness_Nm_per_rad = 1.5e8 ", "couplings[0] ('C1').angular_stiffness_Nm_per_rad = 1.5e+08 N·m/rad",
              "written in N·mm/rad?"),
    _rig_case("coupling torsional stiffness in kN·m/rad", "torsional_stiffness_Nm_per_rad = 3.5e4              # [S]",
              "torsional_stiffness_Nm_per_rad = 35", "couplings[0] ('C1').torsional_stiffness_Nm_per_rad = 35 N·m/rad",
              "(100 … 1e+07 N·m/rad)", "written in kN·m/rad?"),
    _rig_case("mount stiffness in N/m", "translational_stiffness_N_per_um = [200, 100, 100]",
              "translational_stiffness_N_per_um = [2e8, 100, 100]",
              "mounts[0] ('motor_bracket').translational_stiffness_N_per_um = 2e+08 N/µm", "written in N/m?"),
    _rig_case("mount rotational stiffness tiny", "rotational_stiffness_Nm_per_rad = [5e5, 2e5, 2e5]",
              "rotational_stiffness_Nm_per_rad = [5e5, 2e5, 2]",
              "mounts[0] ('motor_bracket').rotational_stiffness_Nm_per_rad = 2 N·m/rad", "(100 … 1e+09 N·m/rad)"),
    # (in Pa, 2.12e11, the rig is refused as numerically singular, after this warning)
    _rig_case("Young's modulus ten times too high", "youngs_modulus_MPa = 2.12e5", "youngs_modulus_MPa = 2.12e6",
              "materials.40Cr.youngs_modulus_MPa = 2.12e+06 MPa", "(1000 … 500000 MPa)"),
    _rig_case("Young's modulus in GPa", "youngs_modulus_MPa = 2.12e5", "youngs_modulus_MPa = 212",
              "materials.40Cr.youngs_modulus_MPa = 212 MPa", "written in GPa?"),
    _rig_case("density in g/cm³", "density_kg_per_m3 = 7870", "density_kg_per_m3 = 7.87",
              "materials.40Cr.density_kg_per_m3 = 7.87 kg/m³", "written in g/cm³?"),
    _rig_case("Poisson's ratio near 0.5", "poisson_ratio = 0.277", "poisson_ratio = 0.49",
              "materials.40Cr.poisson_ratio = 0.49", "(0.1 … 0.45)"),
    _rig_case("housing mass in g", "mass_kg = 2.5                       # [R] 750 W class servo motor",
              "mass_kg = 2500", "parts[0] ('motor_housing').mass_kg = 2500 kg", "(a mass in g, or segments in m?)"),
    # (the stator's reaction, reacted_on, is dropped with it: a torque and its reaction on one part is refused)
    _rig_case("drive torque on a housing", '[torques.T1]\npart = "motor_shaft"\nx_mm = 0\nsign = 1                            # +x\n'
              'reacted_on = { part = "motor_housing", x_mm = 0 }', '[torques.T1]\npart = "motor_housing"\nx_mm = 0\nsign = 1',
              "torques.T1.part = 'motor_housing' is a housing (role body)"),
    _rig_case("brake torque on a housing", '[torques.T2]\npart = "brake_shaft"\nx_mm = 1000\nsign = -1                           '
              '# the brake opposes the output rotation\nreacted_on = { part = "brake_housing", x_mm = 1000 }',
              '[torques.T2]\npart = "brake_housing"\nx_mm = 1000\nsign = -1',
              "torques.T2.part = 'brake_housing' is a housing"),
    _rig_case("bearing shaft and housing swapped", 'shaft = "input_shaft"\nhousing = "input_bearing_block"',
              'shaft = "input_bearing_block"\nhousing = "input_shaft"',
              "bearings[4] ('input_B1'): shaft = 'input_bearing_block' is a housing", "swapped?"),
    _rig_case("load reacted on its own part", 'reacted_on = { part = "reducer", x_mm = 405 }',
              'reacted_on = { part = "output_shaft", x_mm = 420 }',
              "torque_lateral_loads[1] ('crankshaft_load_sharing'): on.part and reacted_on.part are both 'output_shaft'"),
]
