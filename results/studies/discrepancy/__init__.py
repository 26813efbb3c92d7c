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

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.results.studies.discrepancy.measured": ("MeasuredDataError", "read_measured"),
    "rvcoax.results.studies.discrepancy.workflow": ("DiscrepancyResult", "DiscrepancySettings",
                                                    "discrepancy_workload", "run_discrepancy"),
    "rvcoax.results.studies.discrepancy.report": ("engineering_summary", "discrepancy_document", "observation_rows", "plot_discrepancy",
                                                  "rms_table"),
})
