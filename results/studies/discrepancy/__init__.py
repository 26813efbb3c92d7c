"""The discrepancy workflow: locate where model and measurement disagree, name the missing
physical effect, add it to the rig, and show the gap shrink.

Data flow: measured file → :mod:`measured` → observation vector; rig + effect vocabulary
(:mod:`rvcoax.geometry.effects`) → :mod:`engine` and :mod:`responses` (each candidate's predicted change of
every observation, on one factorisation) → :mod:`observability` (what the data can reveal) → :mod:`locate`
(noise, χ², structure) and :mod:`sentinel` (the best generic load) → :mod:`identify` (fits, forward/backward
selection by BIC, look-alikes) → :mod:`judge` (the verdict's rules) and :mod:`ambiguity` (what a group of
look-alikes shares, how to split it); :mod:`workflow` runs the stages (observe, locate, screen, refine, judge);
:mod:`report` writes the JSON, CSV and PNG.

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
