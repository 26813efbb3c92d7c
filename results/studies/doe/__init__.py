"""Orthogonal experiments: standard arrays, range analysis and ANOVA, second-order regression, rig studies.

Public names (loaded on first use): design files, their analysis and report, and rig studies.
"""

from rvcoax._lazy import lazy_names

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.results.studies.doe.limits": ("ALPHA_RANGE", "POOL_BELOW_F_RANGE"),
    "rvcoax.results.studies.doe.design": ("DesignError", "MAX_TABLE_BYTES", "read_design", "read_levels"),
    "rvcoax.results.studies.doe.regression": ("parse_term",),
    "rvcoax.results.studies.doe.report": ("Analysis", "analyse", "analysis_document", "anova_rows",
                                          "combination_label", "plot_main_effects", "regression_document"),
    "rvcoax.results.studies.doe.rig_study": ("StudyError", "load_study", "run_study", "run_values"),
})
