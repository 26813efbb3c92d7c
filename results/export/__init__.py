"""Inputs for dynamics models: per-case tilts, offsets and forces (JSON/CSV), ADAMS datasets, ROSS rotors.

Public names (loaded on first use), by target.
"""

from rvcoax._lazy import lazy_names

# public name → the module that defines it
_WHERE = {
    "bearing_rows": "rvcoax.results.export.dynamics",
    "coupling_rows": "rvcoax.results.export.dynamics",
    "dynamics_export": "rvcoax.results.export.dynamics",
    "write_dynamics_csv": "rvcoax.results.export.dynamics",
    "write_dynamics_json": "rvcoax.results.export.dynamics",
    "AdamsExportError": "rvcoax.results.export.adams",
    "adams_fragment": "rvcoax.results.export.adams",
    "parse_adm": "rvcoax.results.export.adams",
    "spline_layout": "rvcoax.results.export.adams",
    "RossUnavailableError": "rvcoax.results.export.ross",
    "compare_static": "rvcoax.results.export.ross",
    "import_ross": "rvcoax.results.export.ross",
    "misalignment_fault": "rvcoax.results.export.ross",
    "misalignment_parameters": "rvcoax.results.export.ross",
}

__all__ = [*_WHERE]

__getattr__, __dir__ = lazy_names(__name__, _WHERE, globals())
