"""The discrepancy workflow on a synthetic measurement file with a hidden effect.

A "measured" paths file is made from the reference rig with its output bearing B2 four times softer
(a real sweep of that rig, with 1 % noise), written as a CSV a test rig's dial gauges could give,
and read back; the workflow starts from the rig as built and must name the bearing.
"""

import csv
import tempfile
from pathlib import Path

import numpy as np

import rvcoax
from rvcoax.geometry.effects import candidate_effects
from rvcoax.results.studies.discrepancy.workflow import build_library

rig = rvcoax.load_rig()
cases = rvcoax.paper_cases()
hidden = {e.name: e for e in candidate_effects(rig)}["bearing_stiffness@output_B2"]
truth = hidden.apply(rig, [-2.0])  # log2 of the factor on B2's radial stiffness: 2^-2, four times softer
sweep = rvcoax.run_sweep(truth, cases)

rng = np.random.default_rng(1)
path = Path(tempfile.mkdtemp()) / "measured_paths.csv"
with path.open("w", newline="") as file:
    writer = csv.writer(file)
    writer.writerow(["T1_input_Nm", "T2_output_Nm", "shaft", "x_mm", "uy_mm"])
    for result in sweep.cases:
        for shaft, shaft_path in result.paths.items():
            noise = 0.01 * np.sqrt(np.mean(shaft_path.uy_mm ** 2))
            for x, uy in zip(shaft_path.station_mm[::4], shaft_path.uy_mm[::4]):
                writer.writerow([result.case.input_torque_Nm, result.case.output_torque_Nm, shaft, f"{x:g}",
                                 f"{uy + rng.normal(0.0, noise):.6e}"])

data = rvcoax.read_measured(path)
settings = rvcoax.DiscrepancySettings()
# a few candidates keep the example short; leave `library` out to try the whole effect library
library = build_library(rig, data.cases, settings.sweep, names=("bearing_stiffness", "coupling_offset"))
result = rvcoax.run_discrepancy(rig, data, settings, library=library)

print(f"verdict: {result.verdict}")
for effect in result.selected:
    print(f"named: {', '.join(effect.group)} = {effect.values}")
named = [e for e in result.selected if "bearing_stiffness@output_B2" in e.group]
print(f"named_output_B2 = {bool(named)}")
if named:  # the parameter is log2 of the stiffness factor
    print(f"fitted_stiffness_factor_output_B2 = {2.0 ** named[0].values[0]:.4f}")
