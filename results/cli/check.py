"""``rvcoax check``: every row of a measured or published Y/β table against the model, blind and calibrated."""

from __future__ import annotations

import contextlib
from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape
from rich.table import Table

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results import case_text
from rvcoax.results.cli import support
from rvcoax.results.io import PictureProcess

__all__ = ["COMMANDS", "check"]

DEG_TO_URAD = 1e6 * 3.141592653589793 / 180.0


def _check_table(shaft: str, comparison_blind, comparison_cal, fit_rows, rows, *, table_name: str) -> Table:
    table = Table(title=escape(f"{shaft} shaft: {table_name} vs rvcoax"), title_justify="left")
    for column in ("T1 N·m", "T2 N·m", "fit", "Y table µm", "Y blind µm", "blind err", "Y cal µm", "cal err",
                   "β table µrad", "β cal µrad", "β cal err", "ok"):
        table.add_column(column, justify="right")
    y, b = f"Y_{shaft}_mm", f"beta_{shaft}_deg"
    for i, row in enumerate(rows):
        ok = comparison_cal.within[y][i] and comparison_cal.within[b][i]
        table.add_row(
            f"{row.case.input_torque_Nm:g}", f"{row.case.output_torque_Nm:g}", "fit" if i in fit_rows else "",
            f"{1e3 * comparison_cal.published[y][i]:.5g}", f"{1e3 * comparison_blind.model[y][i]:.4g}",
            f"{100 * comparison_blind.relative_error[y][i]:+.1f} %",
            f"{1e3 * comparison_cal.model[y][i]:.5g}", f"{100 * comparison_cal.relative_error[y][i]:+.3f} %",
            f"{comparison_cal.published[b][i] * DEG_TO_URAD:.4g}", f"{comparison_cal.model[b][i] * DEG_TO_URAD:.4g}",
            f"{100 * comparison_cal.relative_error[b][i]:+.2f} %",
            "[green]yes[/]" if ok else "[red]NO[/]",
        )
    return table



@support.model_options
def check(
    *,
    model_choice: support.ModelChoice,
    out: support.OutOption = None,
    measured: Annotated[Path | None, typer.Option("--measured", help="Measured Y to compare with: a CSV table (T1_input_Nm, T2_output_Nm, Y_input_mm, Y_output_mm) or measured paths (T1_input_Nm, T2_output_Nm, shaft, x_mm, uy_mm); '#' lines are comments, '# label = …', '# uncertainty_um = …', '# uncertainty_percent = …' describe the data. Default: paper 000's table, for the built-in reference rig only.")] = None,
    uncertainty_um: Annotated[float | None, typer.Option("--uncertainty-um", min=0.0, max=1e4, help="Measurement uncertainty of --measured, absolute, µm (overrides the file's '# uncertainty_um').")] = None,
    uncertainty_percent: Annotated[float | None, typer.Option("--uncertainty-percent", min=0.0, max=100.0, help="Measurement uncertainty of --measured, % of each value (overrides the file's '# uncertainty_percent'). A value is within when |model − measured| ≤ the larger of the two.")] = None,
) -> None:
    """Compare every row of a Y/β table with the model, blind and calibrated.

    The table: --measured FILE; without it, paper 000's published table (built-in reference rig only). Blind: the rig as built, nothing fitted. Calibrated: two named parameters per shaft fitted on the rows of the smallest and the largest T2 only (paper 000: T2 = 10 and 200 N·m); the other rows are predictions. Measured paths are compared at their stations (the largest |u_y| there). Tolerance: paper 000's table, 2 % of Y and β (or 1e-7 mm next to the input sign change); measured data, their measurement uncertainty (--uncertainty-um, --uncertainty-percent, or the file's '#' lines; without any, 2 % and the file's printed resolution, said as an assumption).

    Exit status: 0 within tolerance with every fitted parameter plausible; 3 within tolerance but only with a fitted parameter outside its plausible range (the model fits the table without explaining it); 1 outside tolerance; 2 a user error.
    """
    with contextlib.ExitStack() as stack:
        # the picture's process imports matplotlib on the core that assembly and calibration leave idle
        pictures = stack.enter_context(PictureProcess()) if out is not None else None
        _check(model_choice, out, measured, (uncertainty_um, uncertainty_percent), pictures)


def _check(model_choice, out: Path | None, measured: Path | None, uncertainty, pictures) -> None:
    """The body of :func:`check` (``pictures``: the picture's worker process where files are written)."""
    from rvcoax import run_check, write_check
    from rvcoax.results.studies import (
        CHECK_QUANTITIES,
        EXIT_OUTSIDE,
        EXIT_WITHIN,
        CalibrationError,
        check_loads_ahead,
        fit_output_torques,
    )

    settings = model_choice.settings()
    rig = model_choice.load_rig()
    rows, table_name, tolerance = _table_to_compare(model_choice, rig, measured, uncertainty=uncertainty)
    prepared = support.prepare_with_status(rig, settings, loads_ahead=check_loads_ahead(rig))
    with support.progress_bar() as progress:
        tasks = {}

        def show(stage: str, done: int, total: int) -> None:
            if stage not in tasks:
                tasks[stage] = progress.add_task(stage, total=total)
            progress.update(tasks[stage], completed=done)

        try:
            run = run_check(rig, rows, settings, prepared=prepared, progress=show, tolerance=tolerance)
        except CalibrationError as error:
            raise support.UserError(f"rig file {model_choice.rig_text()[0]}: {error}") from None
    if pictures is not None:  # drawn while the tables below are printed and the files written
        from rvcoax.results.io import picture_request
        from rvcoax.results.reports import check_picture

        pictures.submit(picture_request(**check_picture(run, out / _picture_name(model_choice),
                                                        title=_picture_title(rig, model_choice, table_name),
                                                        table_label=table_name)))
    blind_result, result, held_out = run.blind_verdict, run.calibrated_verdict, run.held_out
    for shaft in MEASURED_SHAFTS:
        support.console.print(_check_table(shaft, run.comparison_blind, run.comparison_calibrated, run.calibration.fit_rows,
                                   rows, table_name=table_name))
    _print_calibration(run.calibration, fit_output_torques(rows))
    support.console.print(
        f"Blind (nothing fitted): worst relative error {100 * blind_result.worst_relative_error:.1f} % "
        f"({blind_result.worst_quantity}, T2 = {rows[blind_result.worst_row].case.output_torque_Nm:g} N·m); "
        f"{blind_result.failures} of {len(rows) * len(CHECK_QUANTITIES)} values outside tolerance."
    )
    worst = rows[result.worst_row].case
    support.console.print(
        f"Calibrated, on the {int(held_out.sum())} rows not used to fit: worst relative error "
        f"{100 * result.worst_relative_error:.3f} % ({result.worst_quantity}, "
        f"{case_text(worst.input_torque_Nm, worst.output_torque_Nm)}); {result.failures} values outside tolerance."
    )
    if tolerance is not None:
        support.console.print(f"Judged with: {escape(tolerance.description)}.")
    outcome = run.outcome
    colour = "green" if outcome.exit_code == EXIT_WITHIN else "red" if outcome.exit_code == EXIT_OUTSIDE else "yellow"
    support.console.print(f"[bold {colour}]{escape(outcome.text)}[/]")
    if out is not None:
        source, text = model_choice.rig_text()
        support.report_written(write_check(out, run, source, text, picture_name=_picture_name(model_choice),
                                           title=_picture_title(rig, model_choice, table_name),
                                           table_label=table_name, measured=measured is not None,
                                           tolerance=None if tolerance is None else tolerance.description,
                                           pictures=pictures))
    raise typer.Exit(code=outcome.exit_code)


def _picture_name(model_choice) -> str:
    return f"check_{model_choice.model}.png"


def _picture_title(rig, model_choice, table_name: str) -> str:
    return f"{rig.rig.name}: {model_choice.model} model vs {table_name}"


def _table_to_compare(model_choice, rig, measured: Path | None, *, uncertainty: tuple[float | None, float | None]):
    """(rows, table name, measurement tolerance or None) of what ``check`` compares with: the --measured file
    judged with its uncertainty, or paper 000's table for the built-in reference rig."""
    from rvcoax import is_reference_rig, paper_table
    from rvcoax.results.studies import NO_TABLE_HELP, measurement_tolerance

    if measured is None and any(value is not None for value in uncertainty):
        raise support.UserError("--uncertainty-um and --uncertainty-percent describe --measured data; paper 000's "
                                "table is judged with its own 2 % (give --measured FILE)")
    if measured is not None:
        from rvcoax import measured_rows, read_measured

        lengths = {s: getattr(rig.paths, s).length_mm for s in MEASURED_SHAFTS}
        data = read_measured(measured)
        return measured_rows(data, lengths), data.name, measurement_tolerance(data, *uncertainty)
    if is_reference_rig(rig):
        return paper_table(), "published (paper 000)", None
    raise support.UserError(f"rig file {model_choice.rig_text()[0]}: nothing to compare with: {NO_TABLE_HELP}")


def _print_calibration(calibration, fit) -> None:
    table = Table(title=f"Calibrated parameters (fitted on T2 = {fit[0]:g} and {fit[1]:g} N·m)", title_justify="left")
    for column in ("parameter", "shaft", "reference", "fitted", "unit", "plausible range", "plausible?"):
        table.add_column(column)
    for p in calibration.parameters:
        lo, hi = p.parameter.plausible
        table.add_row(p.parameter.address, p.parameter.shaft, f"{p.reference_value:.4g}", f"{p.fitted_value:.4g}",
                      p.parameter.unit, f"{lo:g} .. {hi:g}", "[green]yes[/]" if p.plausible else "[red]NO[/]")
    support.console.print(table)
    for p in calibration.parameters:
        if not p.plausible:
            support.console.print(f"[yellow]note:[/] {p.parameter.address} = {p.fitted_value:.4g} {p.parameter.unit} lies "
                          f"outside the physically plausible range ({p.parameter.meaning}).")
    for alternative in calibration.alternatives:
        values = ", ".join(f"{p.parameter.address.split('.')[-1]} = {p.fitted_value:.4g}" for p in alternative)
        support.console.print(f"[dim]another exact fit of the two fitting rows ({alternative[0].parameter.shaft} shaft): "
                      f"{values}; not used (farther from the reference values)[/]")


COMMANDS = {"check": check}
"""The commands of this module, by name (:func:`rvcoax.results.cli.support.register_commands`)."""
