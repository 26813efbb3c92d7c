"""The discrepancy workflow: locate where model and measurement disagree, name the missing
physical effect, add it to the rig, and show the gap shrink.

Data flow: measured file → :mod:`measured` → observation vector; rig + effect library
(:mod:`rvcoax.geometry.effects`) → :mod:`responses` (each candidate's predicted change of every
observation) → :mod:`locate` (noise, χ², structure) → :mod:`identify` (fits, forward/backward
selection by BIC, ambiguity) → :mod:`workflow` (confirmation with the true model, rig file,
report).

Public names (loaded on first use): the measured file, the workflow, and its report.
"""

from rvcoax._lazy import lazy_names

# public name → the module that defines it
_WHERE = {
    "MeasuredDataError": "rvcoax.results.studies.discrepancy.measured",
    "read_measured": "rvcoax.results.studies.discrepancy.measured",
    "DiscrepancyResult": "rvcoax.results.studies.discrepancy.workflow",
    "DiscrepancySettings": "rvcoax.results.studies.discrepancy.workflow",
    "discrepancy_workload": "rvcoax.results.studies.discrepancy.workflow",
    "run_discrepancy": "rvcoax.results.studies.discrepancy.workflow",
    "discrepancy_document": "rvcoax.results.studies.discrepancy.report",
    "observation_rows": "rvcoax.results.studies.discrepancy.report",
    "plot_discrepancy": "rvcoax.results.studies.discrepancy.report",
    "rms_table": "rvcoax.results.studies.discrepancy.report",
}

__all__ = [*_WHERE]

__getattr__, __dir__ = lazy_names(__name__, _WHERE, globals())
