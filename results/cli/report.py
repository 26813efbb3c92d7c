"""``rvcoax report``: one self-contained HTML report of a study (and optionally its PDF)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape

from rvcoax.results.cli import support

__all__ = ["COMMANDS", "PDF_TIMEOUT_RANGE_S", "report"]

PDF_TIMEOUT_RANGE_S = (1.0, 3600.0)  # headless Chromium prints the reference report in a few seconds


@support.model_options
@support.case_options
def report(
    *,
    model_choice: support.ModelChoice,
    case_choice: support.CaseChoice,
    out: support.OutOption = Path("rvcoax_out"),
    measured: Annotated[Path | None, typer.Option("--measured", help="Measured Y to check the model against: a table (T1_input_Nm, T2_output_Nm, Y_input_mm, Y_output_mm) or a paths file (T1_input_Nm, T2_output_Nm, shaft, x_mm, uy_mm).")] = None,
    discrepancy: Annotated[Path | None, typer.Option("--discrepancy", help="A discrepancy.json written by rvcoax discrepancy --out, shown in the report.")] = None,
    pdf: Annotated[bool, typer.Option("--pdf", help="Also print the report to OUT/report.pdf with headless Chromium (Debian package chromium).")] = False,
    pdf_timeout_s: Annotated[float, support.number_option(
        "--pdf-timeout-s", *PDF_TIMEOUT_RANGE_S, "s", help=f"How long headless Chromium may take to print the PDF, "
        f"{PDF_TIMEOUT_RANGE_S[0]:g} … {PDF_TIMEOUT_RANGE_S[1]:g} s; then it and its child processes are "
        "ended.")] = 120.0,
    deformed: Annotated[bool, typer.Option("--deformed/--no-deformed", help="Include the rendered deformed rig of the largest case (off-screen rendering).")] = True,
    modes: Annotated[int, support.number_option("--modes", 0, 500, help="Natural modes in the report (mode table, interference diagram, mode shapes); 0 leaves the section out.", integer=True)] = 12,
    uncertainty_um: Annotated[float | None, typer.Option("--uncertainty-um", min=0.0, max=1e4, help="Measurement uncertainty of --measured, absolute, µm (overrides the file's '# uncertainty_um').")] = None,
    uncertainty_percent: Annotated[float | None, typer.Option("--uncertainty-percent", min=0.0, max=100.0, help="Measurement uncertainty of --measured, % of each value (overrides the file's '# uncertainty_percent').")] = None,
    decides: Annotated[bool, typer.Option("--decides/--no-decides", help="Include the 'what decides Y' table: each input the rig file tags [A] halved and doubled, the rig solved again (beam model, largest-torque case).")] = True,
    paper: Annotated[str, typer.Option("--paper", help="Page size the report prints on (HTML print and --pdf): a4 or letter.")] = "a4",
) -> None:
    """Write OUT/report.html: one self-contained HTML file for a design review (pictures embedded, no
    network needed to open it).

    Sections: the rig with masses and the rig file's provenance tags, the load cases, the bending lines,
    Y and tilt against torque, the coupling and bearing misalignment with verdicts, the shaft stresses and
    DIN 743 safety at the notches, the support reactions, the check against --measured, the --discrepancy result, the natural frequencies (mode table,
    interference diagram, mode shapes; --modes), and the provenance (version, rig file SHA-256, model, solver,
    mesh, date).
    """
    from rvcoax import read_measured, write_report
    from rvcoax.results.reports import PAPER_SIZES, print_pdf, read_discrepancy

    if paper.lower() not in PAPER_SIZES:
        raise support.UserError(f"--paper: '{paper}' is not a page size; use a4 or letter")
    settings = model_choice.settings()
    rig = model_choice.load_rig()
    load_cases = case_choice.load(rig, model_choice.rig_file)
    data = read_measured(measured) if measured is not None else None  # bad files fail before the solve
    if data is None and (uncertainty_um is not None or uncertainty_percent is not None):
        raise support.UserError("--uncertainty-um and --uncertainty-percent describe --measured data: give "
                                "--measured FILE")
    tolerance = None
    if data is not None:
        from rvcoax.results.studies import measurement_tolerance

        tolerance = measurement_tolerance(data, uncertainty_um, uncertainty_percent)
    found = read_discrepancy(discrepancy) if discrepancy is not None else None
    source, text = model_choice.rig_text()
    result = support.run_with_progress(rig, load_cases, settings, "solving load cases",
                                       support.prepare_with_status(rig, settings))
    study = None
    if modes:
        from rvcoax import modes as natural_modes

        with support.console.status(f"computing {modes} natural modes"):
            study = natural_modes(rig, load_cases, n_modes=modes, model=settings.model,
                                  solver="auto" if settings.solver == "amg" else settings.solver,
                                  mesh_size_mm=settings.mesh_size_mm)
    with support.console.status("drawing the pictures, varying the assumed inputs ([A]) and writing the report"
                                if decides else "drawing the pictures and writing the report"):
        written = [write_report(result, out / "report.html", rig_source=source, rig_text=text, measured=data,
                                discrepancy=found, discrepancy_source=str(discrepancy), deformed_view=deformed,
                                modes=study, paper=paper.lower(), decides=decides, measured_tolerance=tolerance)]
    if pdf:
        with support.console.status("printing the report to PDF with headless Chromium"):
            written.append(print_pdf(written[0], out / "report.pdf", timeout_s=pdf_timeout_s))
    support.console.print(f"report of {len(load_cases)} load cases on {escape(rig.rig.name)}")
    support.report_written(written)


COMMANDS = {"report": report}
"""The commands of this module, by name (:func:`rvcoax.results.cli.support.register_commands`)."""
