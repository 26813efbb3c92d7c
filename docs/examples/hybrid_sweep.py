"""The measured shafts as quadratic tetrahedra tied to the beam frame (hybrid model), two load cases."""

import rvcoax

rig = rvcoax.load_rig()
cases = rvcoax.paired_cases([0.07, 1.43], [10.0, 200.0])
settings = rvcoax.SweepSettings(model="hybrid")  # mesh size from the rig file's [solid] table
sweep = rvcoax.run_sweep(rig, cases, settings)

print(f"hybrid model: {sweep.n_dofs} DOF, solver {sweep.solver}")
for result in sweep.cases:
    print(f"T2 = {result.case.output_torque_Nm:5.0f} N·m: Y_output = {result.paths['output'].y_max_mm * 1e3:.4f} µm")
print(f"y_output_at_200Nm_um = {sweep.cases[-1].paths['output'].y_max_mm * 1e3:.4f}")
