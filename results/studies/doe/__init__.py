"""Orthogonal experiments: standard arrays, range analysis and ANOVA, second-order regression, rig studies.

Public names (loaded on first use): design files, their analysis and report, and rig studies.
"""

from rvcoax._lazy import lazy_names

# public name → the module that defines it
_WHERE = {
    "ALPHA_RANGE": "rvcoax.results.studies.doe.limits",
    "POOL_BELOW_F_RANGE": "rvcoax.results.studies.doe.limits",
    "DesignError": "rvcoax.results.studies.doe.design",
    "MAX_TABLE_BYTES": "rvcoax.results.studies.doe.design",
    "read_design": "rvcoax.results.studies.doe.design",
    "read_levels": "rvcoax.results.studies.doe.design",
    "parse_term": "rvcoax.results.studies.doe.regression",
    "Analysis": "rvcoax.results.studies.doe.report",
    "analyse": "rvcoax.results.studies.doe.report",
    "analysis_document": "rvcoax.results.studies.doe.report",
    "anova_rows": "rvcoax.results.studies.doe.report",
    "combination_label": "rvcoax.results.studies.doe.report",
    "plot_main_effects": "rvcoax.results.studies.doe.report",
    "regression_document": "rvcoax.results.studies.doe.report",
    "StudyError": "rvcoax.results.studies.doe.rig_study",
    "load_study": "rvcoax.results.studies.doe.rig_study",
    "run_study": "rvcoax.results.studies.doe.rig_study",
    "run_values": "rvcoax.results.studies.doe.rig_study",
}

__all__ = [*_WHERE]

__getattr__, __dir__ = lazy_names(__name__, _WHERE, globals())
