"""Files and pictures: atomic writers, result records, the sweep journal, field files (VTK/XDMF) and pictures.

Public names (loaded on first use), by what they write.
"""

from rvcoax._lazy import lazy_names

# public name → the module that defines it
_WHERE = {
    "write_csv_atomic": "rvcoax.results.io.writers",
    "write_json_atomic": "rvcoax.results.io.writers",
    "write_text_atomic": "rvcoax.results.io.writers",
    "output_folder_lock": "rvcoax.results.io.out_lock",
    "rvcoax_version": "rvcoax.results.io.records",
    "sweep_header": "rvcoax.results.io.records",
    "write_check": "rvcoax.results.io.result_files",
    "write_sweep": "rvcoax.results.io.result_files",
    "CASE_DELAY_VARIABLE": "rvcoax.results.io.sweep_files",
    "CaseStore": "rvcoax.results.io.sweep_files",
    "write_sweep_files": "rvcoax.results.io.sweep_files",
    "run_durable_sweep": "rvcoax.results.io.durable_sweep",
    "sweep_field_cases": "rvcoax.results.io.fields",
    "sweep_field_mesh": "rvcoax.results.io.fields",
    "write_vtu": "rvcoax.results.io.fields",
    "write_xdmf_series": "rvcoax.results.io.fields",
    "RenderingUnavailableError": "rvcoax.results.io.pictures",
    "plot_y_vs_torque": "rvcoax.results.io.pictures",
    "render_deformed": "rvcoax.results.io.pictures",
    "draw_sweep_pictures": "rvcoax.results.io.sweep_pictures",
}

__all__ = [*_WHERE]

__getattr__, __dir__ = lazy_names(__name__, _WHERE, globals())
