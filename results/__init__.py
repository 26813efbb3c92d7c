"""Solving and sweeps, shaft-path results, and the rooms that use them: files and pictures (:mod:`.io`),
dynamics exports (:mod:`.export`), studies (:mod:`.studies`) and the command line (:mod:`.cli`).

Public names (loaded on first use): a sweep, its settings and the prepared model it solves; bearing lives per
case and over a duty cycle; shaft stresses and DIN 743 notch safety per case and over the cases; the torque path of each shaft line.
"""

if __name__ != "rvcoax.results":  # run from the repository root, the folder itself is on sys.path: not a package of its own
    raise ImportError("'results' is part of rvcoax and is imported as rvcoax.results "
                      "(install the project, e.g. `make test`, and import rvcoax.results)")

from rvcoax._lazy import lazy_names

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.results.sweep": ("PreparedModel", "Sweep", "SweepSettings", "prepare_model", "run_sweep"),
    "rvcoax.results.connections": ("ConnectionsUnavailableError",),
    "rvcoax.results.engineering": ("bearing_warnings", "case_name", "case_text", "duty_cycle_lives", "duty_cycle_of_records",
                                   "engineering_warnings", "lives_of_records", "play_crossings", "reaction_sum",
                                   "sweep_lives"),
    "rvcoax.results.shaft_safety": ("case_stress_profiles", "shaft_strength", "strength_of_records", "stress_profiles",
                                    "worst_notches"),
    "rvcoax.results.torque_path": ("torque_path_warnings", "torque_paths"),
})
