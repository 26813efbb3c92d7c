"""Studies built on sweeps: the published-table check and calibration, the chain-error model, and tolerance
studies (Monte Carlo, sensitivity, their reports, distributed runs). Orthogonal experiments are
:mod:`rvcoax.results.studies.doe`, the discrepancy workflow :mod:`rvcoax.results.studies.discrepancy`.

Public names (loaded on first use), by study.
"""

from rvcoax._lazy import lazy_names

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.results.studies.check": ("CHECK_QUANTITIES", "EXIT_IMPLAUSIBLE_FIT", "EXIT_OUTSIDE", "EXIT_WITHIN",
                                     "measured_rows", "measurement_tolerance"),
    "rvcoax.results.studies.check_run": ("CalibrationError", "CheckRun", "NO_TABLE_HELP", "check_loads_ahead",
                                          "fit_output_torques", "run_check"),
    "rvcoax.results.studies.calibration": ("calibrate",),
    "rvcoax.results.studies.chain_error": ("ChainDataError", "Coaxiality", "evaluate_chain_error", "load_chain_model",
                                           "read_stage_forces", "torsion_constant_deg_per_m"),
    "rvcoax.results.studies.tolerances": ("ToleranceFileError", "load_tolerances", "parameter_value"),
    "rvcoax.results.studies.sampling": ("SAMPLING_METHODS", "sample_values", "to_values"),
    "rvcoax.results.studies.montecarlo": ("STRATEGY_TEXT", "evaluate_sample", "parameters_needing", "plan_study",
                                          "stack_records"),
    "rvcoax.results.studies.sensitivity": ("SENSITIVITY_METHODS", "design_runs", "morris_design", "morris_indices",
                                           "morris_values", "sobol_design", "sobol_indices"),
    "rvcoax.results.studies.tolerance_report": ("case_label", "distribution_rows", "exceedance_rows", "exceedances",
                                                "plot_beta_histograms", "plot_indices", "ranking", "sample_rows",
                                                "sensitivity_rows", "study_document"),
    "rvcoax.results.studies.distributed": ("ClusterError", "ResumeError", "SampleError", "run_samples"),
    "rvcoax.results.studies.modes": ("HOUSING_DYNAMICS", "ModalStudy", "ModeSettings", "ModesError", "crossing_rows",
                                     "mode_field", "mode_rows", "run_modes"),
})
