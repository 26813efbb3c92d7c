"""The files of a published-table check, written atomically into an output folder: ``check.csv``,
``check_verdict.json``, the calibrated and blind sweeps' files and the picture."""

from __future__ import annotations

from pathlib import Path

from rvcoax.results.io.result_files import write_sweep
from rvcoax.results.io.writers import write_csv_atomic, write_json_atomic
from rvcoax.results.studies.check import CHECK_QUANTITIES, Comparison
from rvcoax.results.studies.check_run import CheckRun

__all__ = ["check_picture", "check_rows", "write_check"]


def write_check(out: Path, run: CheckRun, rig_source: str, rig_text: str, picture_name: str | None = None,  # noqa: PLR0913
                *, title: str | None = None, table_label: str = "published (paper 000)",
                tolerance: str | None = None, measured: bool = False, pictures=None) -> list[Path]:
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
    pictures : rvcoax.results.io.picture_process.PictureProcess, optional
        A worker process started earlier (matplotlib imported meanwhile): it draws the picture while this
        process writes the other files (or since the caller submitted :func:`check_picture` itself); the same PNG
        as without it, its errors raised here.

    Returns
    -------
    list of Path
        ``check.csv``, ``check_verdict.json``, the calibrated and blind sweeps' files and the picture.
    """
    result = run.calibrated_verdict
    picture = None
    if picture_name is not None:
        drawing = check_picture(run, out / picture_name, title=title, table_label=table_label)
        if pictures is not None and not pictures.submitted:
            from rvcoax.results.io.picture_process import picture_request

            pictures.submit(picture_request(**drawing))  # drawn there while the files below are written
    written = [
        write_csv_atomic(out / "check.csv", check_rows(run.comparison_blind, run.comparison_calibrated,
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
        if pictures is not None:
            picture = pictures.result()
        else:
            from rvcoax.results.io.pictures import plot_y_vs_torque

            picture = plot_y_vs_torque(drawing.pop("model_rows"), drawing.pop("path_png"), **drawing)
        written.append(picture)
    return written


def check_picture(run: CheckRun, path_png: Path, *, title: str | None = None,
                  table_label: str = "published (paper 000)") -> dict:
    """The arguments of :func:`rvcoax.results.io.pictures.plot_y_vs_torque` for the check's picture: Y against
    torque, blind and calibrated, with the table's points (µm and µrad).

    Parameters
    ----------
    run : CheckRun
        The result of :func:`rvcoax.run_check`.
    path_png : Path
        Where the picture goes.
    title : str, optional
        The picture's title.
    table_label : str
        The legend of the table's points.

    Returns
    -------
    dict
        Keyword arguments of ``plot_y_vs_torque`` (``model_rows``, ``path_png``, ``published``, …), or of
        :func:`rvcoax.results.io.picture_process.picture_request`.
    """
    return {"model_rows": {"blind": run.blind, "calibrated": run.calibrated}, "path_png": path_png,
            "published": run.rows, "title": title, "micro": True, "published_label": table_label}


def check_rows(comparison_blind: Comparison, comparison_calibrated: Comparison, rows, fit_rows,
               reference: str = "published") -> list[dict]:
    """The columns of ``check.csv``: the table's values (``published_*`` for paper 000's table, ``measured_*``
    for the user's data: ``reference``), blind and calibrated values and errors per row."""
    out = []
    for i, row in enumerate(rows):
        entry = {"T1_input_Nm": row.case.input_torque_Nm, "T2_output_Nm": row.case.output_torque_Nm,
                 "used_for_fit": i in fit_rows}
        for q in CHECK_QUANTITIES:
            entry[f"{reference}_{q}"] = float(comparison_blind.published[q][i])
            for label, comp in (("blind", comparison_blind), ("calibrated", comparison_calibrated)):
                entry[f"{label}_{q}"] = float(comp.model[q][i])
                entry[f"{label}_abs_error_{q}"] = float(comp.absolute_error[q][i])
                entry[f"{label}_rel_error_{q}"] = float(comp.relative_error[q][i])
            entry[f"calibrated_within_tolerance_{q}"] = bool(comparison_calibrated.within[q][i])
        out.append(entry)
    return out
