"""Files and pictures of sweeps: atomic writers, result records, the sweep journal, field files (VTK/XDMF) and
pictures. Documents over studies (the check's files, the HTML/PDF report) are :mod:`rvcoax.results.reports`.

Public names (loaded on first use), by what they write.
"""

from rvcoax._lazy import lazy_names

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.results.io.writers": ("write_csv_atomic", "write_json_atomic", "write_text_atomic"),
    "rvcoax.results.io.out_lock": ("output_folder_lock",),
    "rvcoax.results.io.records": ("rvcoax_version", "sweep_header"),
    "rvcoax.results.io.result_files": ("write_sweep",),
    "rvcoax.results.io.sweep_files": ("CASE_DELAY_VARIABLE", "CaseStore", "write_sweep_files"),
    "rvcoax.results.io.durable_sweep": ("run_durable_sweep",),
    "rvcoax.results.io.fields": ("sweep_field_cases", "sweep_field_mesh", "write_vtu", "write_xdmf_series"),
    "rvcoax.results.io.pictures": ("RenderingUnavailableError", "plot_y_vs_torque", "render_deformed"),
    "rvcoax.results.io.picture_process": ("PictureProcess", "PictureProcessError", "picture_request"),
    "rvcoax.results.io.sweep_pictures": ("draw_sweep_pictures",),
    "rvcoax.results.io.bending_line": ("plot_bending_line",),
    "rvcoax.results.io.mode_pictures": ("plot_interference", "render_mode"),
}, moved={  # up a floor to rvcoax.results.reports (documents over studies); the old imports keep working
    "rvcoax.results.reports.check_files": ("write_check",),
    "rvcoax.results.reports.report": ("read_discrepancy", "write_report"),
    "rvcoax.results.reports.report_pdf": ("print_pdf",),
})
