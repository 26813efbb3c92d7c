"""The result files of a sweep, written atomically into an output folder (a check's: :mod:`rvcoax.results.reports.check_files`)."""

from __future__ import annotations

from pathlib import Path

from rvcoax.results.io import records
from rvcoax.results.io.sweep_files import write_sweep_files
from rvcoax.results.sweep import Sweep

__all__ = ["write_sweep"]


def write_sweep(out: Path, sweep: Sweep, rig_source: str, rig_text: str, calibration: records.StudyRecord | None = None,  # noqa: PLR0913
                *, stem: str = "sweep") -> list[Path]:
    """Write ``<stem>.csv``, ``<stem>.json`` and ``<stem>_paths.csv`` of a sweep in ``out``, atomically.

    Parameters
    ----------
    out : Path
        The result folder (created if needed).
    sweep : Sweep
        A solved sweep.
    rig_source : str
        The rig file as the user named it.
    rig_text : str
        The rig file's text: its SHA-256 goes into the JSON header, so that a result can be traced to its input.
    calibration : Calibration, optional
        Recorded in the JSON (:meth:`rvcoax.results.studies.calibration.Calibration.document`) when the sweep
        is of a calibrated rig.
    stem : str
        The files' common name.

    Returns
    -------
    list of Path
        The files written.
    """
    header = records.sweep_header(sweep.rig, records.model_section(sweep), rig_source, rig_text, calibration)
    return write_sweep_files(out, stem, header, [records.case_record(case) for case in sweep.cases])
