"""Rig → torque sweep → tilt β: the reference rig under paper 000's 20 load cases, beam model."""

import rvcoax

rig = rvcoax.load_rig()  # the built-in reference rig; give a path for your own rig file
sweep = rvcoax.run_sweep(rig, rvcoax.paper_cases())

for result in sweep.cases[:3]:
    output = result.paths["output"]  # the measured output shaft, L = 160 mm
    print(f"T1 = {result.case.input_torque_Nm:5.2f} N·m, T2 = {result.case.output_torque_Nm:5.0f} N·m: "
          f"Y_max = {output.y_max_mm * 1e3:.4f} µm, β = {output.beta_deg * 1e6:.2f} µ° (paper 000's definition)")

largest = max(sweep.cases, key=lambda r: r.case.output_torque_Nm)
print(f"beta_output_at_200Nm_udeg = {largest.paths['output'].beta_deg * 1e6:.3f}")
