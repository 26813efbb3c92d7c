"""Load cases: (T1, T2) torque pairs, from the paper's table, a grid, a list or a file.

Public names (loaded on first use): the load case, its sources, and the limits every source enforces.
"""

from rvcoax._lazy import lazy_names

# public name → the module that defines it
_WHERE = {
    "LoadCase": "rvcoax.loadcases.cases",
    "grid_cases": "rvcoax.loadcases.cases",
    "paired_cases": "rvcoax.loadcases.cases",
    "paper_cases": "rvcoax.loadcases.cases",
    "paper_table": "rvcoax.loadcases.cases",
    "read_cases": "rvcoax.loadcases.cases",
    "MAX_CASE_FILE_BYTES": "rvcoax.loadcases.limits",
    "MAX_TORQUE_NM": "rvcoax.loadcases.limits",
}

__all__ = [*_WHERE]

__getattr__, __dir__ = lazy_names(__name__, _WHERE, globals())
