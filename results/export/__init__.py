"""Inputs for dynamics models: per-case tilts, offsets and forces (JSON/CSV), ADAMS datasets, ROSS rotors.

Public names (loaded on first use), by target.
"""

from rvcoax._lazy import lazy_names

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.results.export.dynamics": ("bearing_rows", "coupling_rows", "dynamics_export", "write_dynamics_csv",
                                       "write_dynamics_json"),
    "rvcoax.results.export.adams": ("AdamsExportError", "adams_fragment", "parse_adm", "spline_layout"),
    "rvcoax.results.export.ross": ("RossUnavailableError", "compare_static", "import_ross", "misalignment_fault",
                                   "misalignment_parameters", "operating_radial_stiffness"),
    "rvcoax.results.export.formats": ("EXPORT_FORMATS", "ExportFiles", "ExportFormat", "ExportFormatError",
                                      "ExportTable", "export_format", "write_export"),
})
