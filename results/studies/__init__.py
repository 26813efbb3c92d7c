"""Studies built on sweeps: the published-table check and calibration, the chain-error model, and tolerance
studies (Monte Carlo, sensitivity, their reports, distributed runs). Orthogonal experiments are
:mod:`rvcoax.results.studies.doe`, the discrepancy workflow :mod:`rvcoax.results.studies.discrepancy`.

Public names (loaded on first use), by study.
"""

from rvcoax._lazy import lazy_names

# public name → the module that defines it
_WHERE = {
    "CHECK_QUANTITIES": "rvcoax.results.studies.check",
    "EXIT_IMPLAUSIBLE_FIT": "rvcoax.results.studies.check",
    "EXIT_OUTSIDE": "rvcoax.results.studies.check",
    "EXIT_WITHIN": "rvcoax.results.studies.check",
    "CalibrationError": "rvcoax.results.studies.check_run",
    "CheckRun": "rvcoax.results.studies.check_run",
    "run_check": "rvcoax.results.studies.check_run",
    "calibrate": "rvcoax.results.studies.calibration",
    "ChainDataError": "rvcoax.results.studies.chain_error",
    "Coaxiality": "rvcoax.results.studies.chain_error",
    "evaluate_chain_error": "rvcoax.results.studies.chain_error",
    "load_chain_model": "rvcoax.results.studies.chain_error",
    "read_stage_forces": "rvcoax.results.studies.chain_error",
    "torsion_constant_deg_per_m": "rvcoax.results.studies.chain_error",
    "ToleranceFileError": "rvcoax.results.studies.tolerances",
    "load_tolerances": "rvcoax.results.studies.tolerances",
    "parameter_value": "rvcoax.results.studies.tolerances",
    "SAMPLING_METHODS": "rvcoax.results.studies.sampling",
    "sample_values": "rvcoax.results.studies.sampling",
    "to_values": "rvcoax.results.studies.sampling",
    "STRATEGY_TEXT": "rvcoax.results.studies.montecarlo",
    "evaluate_sample": "rvcoax.results.studies.montecarlo",
    "parameters_needing": "rvcoax.results.studies.montecarlo",
    "plan_study": "rvcoax.results.studies.montecarlo",
    "stack_records": "rvcoax.results.studies.montecarlo",
    "SENSITIVITY_METHODS": "rvcoax.results.studies.sensitivity",
    "design_runs": "rvcoax.results.studies.sensitivity",
    "morris_design": "rvcoax.results.studies.sensitivity",
    "morris_indices": "rvcoax.results.studies.sensitivity",
    "morris_values": "rvcoax.results.studies.sensitivity",
    "sobol_design": "rvcoax.results.studies.sensitivity",
    "sobol_indices": "rvcoax.results.studies.sensitivity",
    "case_label": "rvcoax.results.studies.tolerance_report",
    "distribution_rows": "rvcoax.results.studies.tolerance_report",
    "exceedance_rows": "rvcoax.results.studies.tolerance_report",
    "exceedances": "rvcoax.results.studies.tolerance_report",
    "plot_beta_histograms": "rvcoax.results.studies.tolerance_report",
    "plot_indices": "rvcoax.results.studies.tolerance_report",
    "ranking": "rvcoax.results.studies.tolerance_report",
    "sample_rows": "rvcoax.results.studies.tolerance_report",
    "sensitivity_rows": "rvcoax.results.studies.tolerance_report",
    "study_document": "rvcoax.results.studies.tolerance_report",
    "ClusterError": "rvcoax.results.studies.distributed",
    "ResumeError": "rvcoax.results.studies.distributed",
    "SampleError": "rvcoax.results.studies.distributed",
    "run_samples": "rvcoax.results.studies.distributed",
}

__all__ = [*_WHERE]

__getattr__, __dir__ = lazy_names(__name__, _WHERE, globals())
