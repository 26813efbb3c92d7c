"""The published-table check as a function: blind sweep, calibration on two rows, verdict on the other 18."""

import rvcoax

run = rvcoax.run_check(rvcoax.load_rig())  # paper 000's table by default

print(f"blind: {run.blind_verdict.failures} values outside tolerance, worst "
      f"{100 * run.blind_verdict.worst_relative_error:.1f} %")
for fitted in run.calibration.parameters:
    print(f"fitted {fitted.parameter.address} = {fitted.fitted_value:.4g} {fitted.parameter.unit} "
          f"(plausible: {fitted.plausible})")
print(run.outcome.text)
print(f"held_out_worst_relative_error_percent = {100 * run.calibrated_verdict.worst_relative_error:.4f}")
