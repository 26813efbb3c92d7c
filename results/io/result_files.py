"""The result files of a sweep and of a check, written atomically into an output folder."""

from __future__ import annotations

from pathlib import Path

from rvcoax.results.io import records
from rvcoax.results.io.sweep_files import write_sweep_files
from rvcoax.results.io.writers import write_csv_atomic, write_json_atomic
from rvcoax.results.studies.calibration import Calibration
from rvcoax.results.studies.check_run import CheckRun
from rvcoax.results.sweep import Sweep

__all__ = ["write_check", "write_sweep"]


def write_sweep(out: Path, sweep: Sweep, rig_source: str, rig_text: str, calibration: Calibration | None = None,
                stem: str = "sweep") -> list[Path]:
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
        Recorded in the JSON when the sweep is of a calibrated rig.
    stem : str
        The files' common name.

    Returns
    -------
    list of Path
        The files written.
    """
    header = records.sweep_header(sweep.rig, records.model_section(sweep), rig_source, rig_text, calibration)
    return write_sweep_files(out, stem, header, [records.case_record(case) for case in sweep.cases])


def write_check(out: Path, run: CheckRun, rig_source: str, rig_text: str, picture_name: str | None = None,
                title: str | None = None, table_label: str = "published (paper 000)",
                tolerance: str | None = None, measured: bool = False) -> list[Path]:
    """Write the check's files in ``out``, atomically.

    Parameters
    ----------
    out : Path
        The result folder (created if needed).
    run : CheckRun
        The result of :func:`rvcoax.run_check`.
    rig_source, rig_text : str
        The rig file's name and text, recorded (with the text's SHA-256) in every JSON.
    picture_name : str, optional
        With a name, also the PNG of Y against torque with the published points.
    title : str, optional
        The picture's title.
    table_label : str
        What the table compared with is called (the legend of its points; ``check_verdict.json``).
    tolerance : str, optional
        How values were judged (:attr:`rvcoax.results.studies.check.Tolerance.description`).
    measured : bool
        The table is the user's measured data: ``check.csv`` names its columns ``measured_*`` instead of
        ``published_*``.

    Returns
    -------
    list of Path
        ``check.csv``, ``check_verdict.json``, the calibrated and blind sweeps' files and the picture.
    """
    result = run.calibrated_verdict
    written = [
        write_csv_atomic(out / "check.csv", records.check_rows(run.comparison_blind, run.comparison_calibrated,
                                                               run.rows, run.calibration.fit_rows,
                                                               "measured" if measured else "published")),
        write_json_atomic(out / "check_verdict.json", {
            "status": run.outcome.status, "verdict": run.outcome.text, "exit_code": run.outcome.exit_code,
            **({"compared_with": table_label, "tolerance": tolerance} if measured else {}),
            "implausible_parameters": list(run.outcome.implausible),
            "held_out_values_outside_tolerance": result.failures,
            "held_out_worst_relative_error_percent": 100 * result.worst_relative_error}),
    ]
    written += write_sweep(out, run.calibrated, rig_source, rig_text, run.calibration)
    written += write_sweep(out, run.blind, rig_source, rig_text, stem="blind_sweep")
    if picture_name is not None:
        from rvcoax.results.io.pictures import plot_y_vs_torque

        written.append(plot_y_vs_torque({"blind": run.blind, "calibrated": run.calibrated}, out / picture_name,
                                        published=run.rows, title=title, micro=True, published_label=table_label))
    return written
