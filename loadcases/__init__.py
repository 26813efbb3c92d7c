"""Load cases: (T1, T2) torque pairs, from the paper's table, a grid, a list or a file.

Public names (loaded on first use): the load case, its sources, and the limits every source enforces.
"""

if __name__ != "rvcoax.loadcases":  # run from the repository root, the folder itself is on sys.path: not a package of its own
    raise ImportError("'loadcases' is part of rvcoax and is imported as rvcoax.loadcases "
                      "(install the project, e.g. `make test`, and import rvcoax.loadcases)")

from rvcoax._lazy import lazy_names

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.loadcases.cases": ("LoadCase", "grid_cases", "paired_cases", "paper_cases", "paper_table",
                               "read_cases", "NoLoadCasesError", "default_cases", "default_is_paper", "rig_cases"),
    "rvcoax.loadcases.limits": ("MAX_CASE_FILE_BYTES", "MAX_TORQUE_NM"),
})
