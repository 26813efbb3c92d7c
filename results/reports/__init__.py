"""Documents over studies: the files of a published-table check and the study report (HTML, and PDF through a
headless browser). A study's own files are written by the study (:mod:`rvcoax.results.studies`); a sweep's by
:mod:`rvcoax.results.io`.

Public names (loaded on first use), by document.
"""

from rvcoax._lazy import lazy_names

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.results.reports.check_files": ("check_picture", "write_check"),
    "rvcoax.results.reports.report": ("PAPER_SIZES", "read_discrepancy", "write_report"),
    "rvcoax.results.reports.report_pdf": ("print_pdf",),
})
