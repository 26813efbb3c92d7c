"""``rvcoax export``: inputs for dynamics models (JSON, CSV, an ADAMS dataset fragment, ROSS rotors).

See :mod:`rvcoax.results.export.dynamics` for what is exported, :mod:`rvcoax.results.export.adams` and :mod:`rvcoax.results.export.ross`
for the two dynamics packages.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table

from rvcoax.results.cli import support

__all__ = ["COMMANDS", "export"]


def _summary(export) -> Table:
    """Largest coupling misalignment and bearing force over the cases (measured reference)."""
    from rvcoax.results.export import bearing_rows, coupling_rows

    table = Table(title=f"over {len(export.sweep.cases)} cases, from the {export.measured_from} state",
                  title_justify="left")
    for column in ("spring", "largest radial offset µm", "largest angle °", "largest radial force N"):
        table.add_column(column, justify="right")
    for kind, rows, key in (("coupling", coupling_rows(export), "coupling"), ("bearing", bearing_rows(export), "bearing")):
        for name in dict.fromkeys(r[key] for r in rows):
            mine = [r for r in rows if r[key] == name]
            offset = f"{max(r['offset_radial_um'] for r in mine):.4g}" if kind == "coupling" else ""
            angle = f"{max(r['angle_deg'] for r in mine):.4g}" if kind == "coupling" else ""
            force = max(math.hypot(r["force_y_N"], r["force_z_N"]) for r in mine)
            table.add_row(f"{kind} {name}", offset, angle, f"{force:.4g}")
    return table


def _format_help() -> str:
    """``--format``'s help: every format of the registry with its files."""
    from rvcoax.results.export import EXPORT_FORMATS

    named = [f"{f.name} ({f.description.replace('[', chr(92) + '[')})" for f in EXPORT_FORMATS]
    return ", ".join(named[:-1]) + f" or {named[-1]}."


def _refusal(name: str, check, *args) -> None:
    """Run a format's check before solving; its refusal becomes a user error naming the format."""
    from rvcoax import RvcoaxError

    try:
        check(*args)
    except RvcoaxError as error:
        raise support.UserError(f"--format {name}: {error}") from None


def _print_table(table) -> None:
    shown = Table(title=table.title, title_justify="left")
    for column in table.columns:
        shown.add_column(column, justify="right")
    for row in table.rows:
        shown.add_row(*row)
    support.console.print(shown)


@support.model_options
@support.case_options
def export(
    *,
    model_choice: support.ModelChoice,
    case_choice: support.CaseChoice,
    output_format: Annotated[str, typer.Option("--format", help=_format_help())] = "json",
    out: support.OutOption = Path("rvcoax_out"),
    input_radial_mm: Annotated[float | None, support.number_option(
        "--input-radial-mm", *support.RADIAL_OFFSET_RANGE_MM, "mm",
        help="Radial displacement a of the input shaft (mm); default 0.002 (paper 000, IT3).")] = None,
    output_radial_mm: Annotated[float | None, support.number_option(
        "--output-radial-mm", *support.RADIAL_OFFSET_RANGE_MM, "mm",
        help="Radial displacement a of the output shaft (mm); default 0.003 (paper 000, IT3).")] = None,
) -> None:
    """Export dynamics inputs per load case: tilt β and radial displacement a of both measured shafts, paper
    000's lever arm per shaft stage, offset and angle at every coupling, bearing reactions (N, N·m)."""
    from rvcoax.results import ConnectionsUnavailableError
    from rvcoax.results.export import ExportFormatError, dynamics_export, export_format, write_export

    try:
        chosen = export_format(output_format)
    except ExportFormatError as error:
        raise support.UserError(f"--format: {error}") from None
    _refusal(chosen.name, chosen.check_ready)  # before solving: a missing optional package should not cost a sweep
    radial = {"input": input_radial_mm, "output": output_radial_mm}
    settings = model_choice.settings()
    rig = model_choice.load_rig()
    load_cases = case_choice.load(rig)
    _refusal(chosen.name, chosen.check_cases, load_cases)
    result = support.run_with_progress(rig, load_cases, settings, "solving load cases",
                                       support.prepare_with_status(rig, settings))
    try:
        exported = dynamics_export(result, {k: v for k, v in radial.items() if v is not None})
    except ConnectionsUnavailableError as error:
        raise support.UserError(f"rig file {model_choice.rig_text()[0]}: cannot export: {error}") from None
    support.console.print(_summary(exported))
    source, text = model_choice.rig_text()
    with support.console.status(f"writing the {chosen.name} export"):
        written = write_export(exported, out, chosen.name, rig_source=source, rig_text=text)
    for table in written.tables:
        _print_table(table)
    support.console.print(f"a: input {exported.radial_mm['input']:g} mm, output {exported.radial_mm['output']:g} mm; "
                          f"couplings, bearings and β from the {exported.measured_from} state "
                          "(columns *_unloaded_ref: from the unloaded geometry)")
    support.report_written(list(written.paths))


COMMANDS = {"export": export}
"""The commands of this module, by name (:func:`rvcoax.results.cli.support.register_commands`)."""
