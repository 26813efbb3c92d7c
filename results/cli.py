"""The ``rvcoax`` command line: sweep, check, rig show.

Units shown to the user follow paper 000: torques in N·m, lengths and Y in mm, angles in degrees.
A user mistake (bad rig file, bad load cases, unsupported model) ends with a message and exit
status 2, never a traceback.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from fem import blas_threads, hugepages
from geometry.build import build_rig_model
from geometry.rigfile import load_rig, reference_rig_text
from loadcases.cases import paper_table
from results import report
from results.calibration import DEFAULT_PARAMETERS, calibrate
from results.check import EXIT_OUTSIDE, EXIT_WITHIN, QUANTITIES, check_verdict, compare, verdict
from results.cli_support import (
    CasesOption,
    GridOption,
    MeshOption,
    ModelOption,
    OutOption,
    RigOption,
    SolverOption,
    T1Option,
    T2Option,
    UserError,
    add_text_row,
    cases_from_options,
    console,
    guard,
    number_option,
    prepare_with_status,
    progress_bar,
    report_written,
    rig_text,
    run_with_progress,
    sweep_settings,
)
from results.sweep_files import (
    CaseStore,
    JournalReading,
    case_inputs,
    inputs_sha256,
    sweep_inputs,
    write_sweep_files,
)
from results.workload import REPORT_AFTER_S, sweep_workload
from results.writers import write_csv_atomic, write_json_atomic

app = typer.Typer(
    add_completion=False, no_args_is_help=True, rich_markup_mode="rich",
    help=(
        "rvcoax: static coaxiality of an RV-reducer test rig (beam finite elements).\n\n"
        "Units: torques T1 (input) and T2 (output) in N·m; positions, diameters and Y displacements in mm; "
        "tilt angles in degrees. Y is vertical (+ up); beta = arcsin(Y_max / L) with L = the measured shaft "
        "path length (input 120 mm, output 160 mm). Without --rig, the built-in reference RV-20E rig is used."
    ),
)
rig_app = typer.Typer(no_args_is_help=True, help="Inspect rig files.")
app.add_typer(rig_app, name="rig")

def _version_callback(value: bool) -> None:
    if value:
        console.print(f"rvcoax {report.rvcoax_version()}")
        raise typer.Exit()


@app.callback()
def main(
    version: Annotated[bool, typer.Option("--version", callback=_version_callback, is_eager=True,
                                          help="Print the version and exit.")] = False,
) -> None:
    """rvcoax command line."""


def _write_sweep(out: Path, sweep, rig_source: str, rig_text: str, calibration=None, stem: str = "sweep") -> list[Path]:
    header = report.sweep_header(sweep.rig, report.model_section(sweep), rig_source, rig_text, calibration)
    return write_sweep_files(out, stem, header, [report.case_record(case) for case in sweep.cases])


TABLE_ROWS = 40  # a sweep table longer than this shows its first rows only (every case is in sweep.csv)


def _sweep_table(name: str, method: str, rows: list[dict]) -> Table:
    shown = rows[:TABLE_ROWS]
    more = (f"; first {len(shown)} shown, every case in sweep.csv" if len(rows) > len(shown) else "")
    table = Table(title=escape(f"{name}: {len(rows)} load cases ({method}{more})"))
    for column in ("T1 N·m", "T2 N·m", "Y_in mm", "β_in °", "x_max,in mm", "Y_out mm", "β_out °", "x_max,out mm"):
        table.add_column(column, justify="right")
    for row in shown:
        cells = [f"{row['T1_input_Nm']:g}", f"{row['T2_output_Nm']:g}"]
        for shaft in ("input", "output"):
            cells += [f"{row[f'Y_{shaft}_mm']:.5g}", f"{row[f'beta_{shaft}_deg']:.3g}",
                      f"{row[f'station_of_max_{shaft}_mm']:g}"]
        table.add_row(*cells)
    return table


def _solve_sweep(rig_model, load_cases, settings, text: str, store: CaseStore, resume: bool):
    """Solve the cases not yet in ``store`` (all of them without ``resume``), journalling each as it is solved.

    Returns (records of every case in order, the ``model`` section, the Sweep of the cases solved now
    or None when every case was reused).
    """
    sha = report.text_sha256(text)
    common = sweep_inputs(sha, settings)
    case_hashes = [inputs_sha256(case_inputs(sha, case, settings, common)) for case in load_cases]
    model_hash = inputs_sha256(common)
    if resume:
        reading = store.load(case_hashes, model_hash)
    else:
        store.clear()
        reading = JournalReading()
    records, model = reading.cases, reading.model
    missing = [i for i in range(len(load_cases)) if i not in records]
    if resume:
        console.print(f"resuming: {len(records)} of {len(load_cases)} case(s) already solved in {escape(str(store.folder))}, "
                      f"{len(missing)} to solve")
        if reading.rejected:
            console.print(f"not reused from {escape(str(store.path))} (solved again): {reading.describe_rejections()}")
    result = None
    if missing or model is None:
        with store:
            def save(k: int, case_result) -> None:
                records[missing[k]] = report.case_record(case_result)
                store.save(missing[k], case_hashes[missing[k]], records[missing[k]])

            result = run_with_progress(rig_model, tuple(load_cases[i] for i in missing), settings,
                                       "solving load cases", prepare_with_status(rig_model, settings), on_case=save)
            model = report.model_section(result)
            store.save_model(model_hash, model)
    return [records[i] for i in range(len(load_cases))], model, result


@app.command()
@guard
def sweep(
    rig: RigOption = None,
    model: ModelOption = "beam",
    out: OutOption = Path("rvcoax_out"),
    cases: CasesOption = None,
    t1: T1Option = None,
    t2: T2Option = None,
    grid: GridOption = False,
    method: Annotated[str, typer.Option("--method", help="superposition (of unit responses, default) or direct (solve each case).")] = "superposition",
    solver: SolverOption = "auto",
    mesh_size_mm: MeshOption = None,
    fields: Annotated[bool, typer.Option("--fields", help="Also write the full displacement fields: one .vtu per case and an .xdmf time series (open in ParaView).")] = False,
    resume: Annotated[bool, typer.Option("--resume", help="Reuse the cases an interrupted sweep already journalled in OUT/cases (same rig file, torques and settings, checksum verified) and solve only the others.")] = False,
) -> None:
    """Solve a torque sweep (default: the 20 (T1, T2) pairs of paper 000) and write sweep.csv / sweep.json.

    Each case is appended to OUT/cases/journal.jsonl (with a checksum) as soon as it is solved; after
    an interruption, the same command with --resume solves only the missing cases and writes the same
    files.
    """
    if resume and fields:
        raise UserError("--fields needs every case's displacement field, which --resume does not keep: "
                        "run without --resume")
    settings = sweep_settings(model, method, solver, mesh_size_mm)
    rig_model = load_rig(rig)
    load_cases = cases_from_options(cases, t1, t2, grid)
    work = sweep_workload(len(load_cases))
    if work.seconds > REPORT_AFTER_S:
        console.print(f"{work.what}: {work.describe()} (estimated)")
    source, text = rig_text(rig)
    records, model_section, result = _solve_sweep(rig_model, load_cases, settings, text, CaseStore(out / "cases"),
                                                  resume)
    if fields:
        report_written(_write_fields(out / "fields", result))
    console.print(_sweep_table(rig_model.rig.name, method, [r["row"] for r in records]))
    if model_section.get("nonlinear"):
        how = (f"each case solved on its own ({model_section['nonlinear']}; bearings with clearance: "
               f"{', '.join(model_section['gapped_bearings'])})")
    elif method == "superposition":
        how = ("each case built from unit responses (self-weight, force table, engaged load sharing, "
               "T1 = 1 N·m, T2 = 1 N·m)")
    else:
        how = "each case solved directly"
    console.print(f"Y measured from: {rig_model.paths.measured_from}; {how}")
    header = report.sweep_header(rig_model, model_section, source, text)
    report_written(write_sweep_files(out, "sweep", header, records))


def _write_fields(folder: Path, result) -> list[Path]:
    from results.fields import sweep_field_cases, sweep_field_mesh, write_vtu, write_xdmf_series

    mesh, _ = sweep_field_mesh(result)
    cases = sweep_field_cases(result)
    written = [write_vtu(folder / f"case_{i:02d}.vtu", mesh, case) for i, case in enumerate(cases)]
    written += list(write_xdmf_series(folder / "sweep.xdmf", mesh, cases).values())
    return written


def _check_table(shaft: str, comparison_blind, comparison_cal, fit_rows, rows) -> Table:
    table = Table(title=f"{shaft} shaft: published (paper 000) vs rvcoax", title_justify="left")
    for column in ("T1 N·m", "T2 N·m", "fit", "Y pub mm", "Y blind mm", "blind err", "Y cal mm", "cal err",
                   "β pub °", "β cal °", "β cal err", "ok"):
        table.add_column(column, justify="right")
    y, b = f"Y_{shaft}_mm", f"beta_{shaft}_deg"
    for i, row in enumerate(rows):
        ok = comparison_cal.within[y][i] and comparison_cal.within[b][i]
        table.add_row(
            f"{row.case.input_torque_Nm:g}", f"{row.case.output_torque_Nm:g}", "fit" if i in fit_rows else "",
            f"{comparison_cal.published[y][i]:.5g}", f"{comparison_blind.model[y][i]:.4g}",
            f"{100 * comparison_blind.relative_error[y][i]:+.1f} %",
            f"{comparison_cal.model[y][i]:.5g}", f"{100 * comparison_cal.relative_error[y][i]:+.3f} %",
            f"{comparison_cal.published[b][i]:.3g}", f"{comparison_cal.model[b][i]:.4g}",
            f"{100 * comparison_cal.relative_error[b][i]:+.2f} %",
            "[green]yes[/]" if ok else "[red]NO[/]",
        )
    return table


@app.command()
@guard
def check(
    rig: RigOption = None,
    model: ModelOption = "beam",
    out: OutOption = None,
    solver: SolverOption = "auto",
    mesh_size_mm: MeshOption = None,
) -> None:
    """Compare every row of paper 000's Y/β table with the model, blind and calibrated.

    Blind: the rig as built, nothing fitted. Calibrated: two named parameters per shaft fitted on the rows T2 = 10 and T2 = 200 N·m only; the other 18 rows are predictions. Tolerance: 2 % of Y and β, or 1e-7 mm next to the input sign change.

    Exit status: 0 within tolerance with every fitted parameter plausible; 3 within tolerance but only with a fitted parameter outside its plausible range (the model fits the table without explaining it); 1 outside tolerance; 2 a user error.
    """
    settings = sweep_settings(model, solver=solver, mesh_size_mm=mesh_size_mm)
    rig_model = load_rig(rig)
    rows = paper_table()
    cases = tuple(r.case for r in rows)
    prepared = prepare_with_status(rig_model, settings)
    blind = run_with_progress(rig_model, cases, settings, "blind sweep", prepared)
    with console.status("calibrating (least squares on rows T2 = 10 and 200 N·m)"):
        try:
            calibration = calibrate(rig_model, rows, settings=settings, prepared=prepared)
        except KeyError as error:  # the rig lacks a parameter that the calibration fits
            raise UserError(f"rig file {rig_text(rig)[0]}: cannot calibrate: {error.args[0]} (the check fits "
                            + ", ".join(p.address for p in DEFAULT_PARAMETERS) + ")") from None
    calibrated = run_with_progress(calibration.rig, cases, settings, "calibrated sweep", prepared)
    comparison_blind, comparison_cal = compare(rows, blind), compare(rows, calibrated)
    held_out = report.held_out_mask(len(rows), calibration.fit_rows)
    result = verdict(comparison_cal, held_out)
    blind_result = verdict(comparison_blind, np.ones(len(rows), dtype=bool))

    for shaft in ("input", "output"):
        console.print(_check_table(shaft, comparison_blind, comparison_cal, calibration.fit_rows, rows))
    _print_calibration(calibration)
    console.print(
        f"Blind (nothing fitted): worst relative error {100 * blind_result.worst_relative_error:.1f} % "
        f"({blind_result.worst_quantity}, T2 = {rows[blind_result.worst_row].case.output_torque_Nm:g} N·m); "
        f"{blind_result.failures} of {len(rows) * len(QUANTITIES)} values outside tolerance."
    )
    worst = rows[result.worst_row].case
    console.print(
        f"Calibrated, on the {int(held_out.sum())} rows not used to fit: worst relative error "
        f"{100 * result.worst_relative_error:.3f} % ({result.worst_quantity}, T1 = {worst.input_torque_Nm:g}, "
        f"T2 = {worst.output_torque_Nm:g} N·m); {result.failures} values outside tolerance."
    )
    outcome = check_verdict(result, calibration.parameters)
    colour = "green" if outcome.exit_code == EXIT_WITHIN else "red" if outcome.exit_code == EXIT_OUTSIDE else "yellow"
    console.print(f"[bold {colour}]{escape(outcome.text)}[/]")
    if out is not None:
        source, text = rig_text(rig)
        written = [write_csv_atomic(out / "check.csv", report.check_rows(comparison_blind, comparison_cal, rows,
                                                                         calibration.fit_rows)),
                   write_json_atomic(out / "check_verdict.json", {
                       "status": outcome.status, "verdict": outcome.text, "exit_code": outcome.exit_code,
                       "implausible_parameters": list(outcome.implausible),
                       "held_out_values_outside_tolerance": result.failures,
                       "held_out_worst_relative_error_percent": 100 * result.worst_relative_error})]
        written += _write_sweep(out, calibrated, source, text, calibration)
        written += _write_sweep(out, blind, source, text, stem="blind_sweep")
        from results.pictures import plot_y_vs_torque

        written.append(plot_y_vs_torque({"blind": blind, "calibrated": calibrated}, out / f"check_{model}.png",
                                        published=rows, title=f"{rig_model.rig.name}: {model} model vs paper 000"))
        report_written(written)
    raise typer.Exit(code=outcome.exit_code)


def _print_calibration(calibration) -> None:
    table = Table(title="Calibrated parameters (fitted on T2 = 10 and 200 N·m)", title_justify="left")
    for column in ("parameter", "shaft", "reference", "fitted", "unit", "plausible range", "plausible?"):
        table.add_column(column)
    for p in calibration.parameters:
        lo, hi = p.parameter.plausible
        table.add_row(p.parameter.address, p.parameter.shaft, f"{p.reference_value:.4g}", f"{p.fitted_value:.4g}",
                      p.parameter.unit, f"{lo:g} .. {hi:g}", "[green]yes[/]" if p.plausible else "[red]NO[/]")
    console.print(table)
    for p in calibration.parameters:
        if not p.plausible:
            console.print(f"[yellow]note:[/] {p.parameter.address} = {p.fitted_value:.4g} {p.parameter.unit} lies "
                          f"outside the physically plausible range ({p.parameter.meaning}).")
    for alternative in calibration.alternatives:
        values = ", ".join(f"{p.parameter.address.split('.')[-1]} = {p.fitted_value:.4g}" for p in alternative)
        console.print(f"[dim]another exact fit of the two fitting rows ({alternative[0].parameter.shaft} shaft): "
                      f"{values}; not used (farther from the reference values)[/]")


@app.command()
@guard
def picture(
    rig: RigOption = None,
    model: ModelOption = "beam",
    out: OutOption = Path("rvcoax_out"),
    cases: Annotated[Path | None, typer.Option("--cases", help="Load cases file (as for sweep).")] = None,
    t1: Annotated[str | None, typer.Option("--t1", help="Input torques T1 in N·m, comma-separated.")] = None,
    t2: Annotated[str | None, typer.Option("--t2", help="Output torques T2 in N·m, comma-separated.")] = None,
    warp_fraction: Annotated[float, number_option("--warp-fraction", 0.0, 1.0, exclusive=True, help="Largest displacement drawn as this fraction of the rig length, in (0, 1).")] = 0.05,
    solver: SolverOption = "auto",
    mesh_size_mm: MeshOption = None,
) -> None:
    """Off-screen pictures: the deformed rig per case (u_y in µm, same colour limits across the sweep,
    measured paths drawn) and Y against torque with the published points."""
    from results.fields import sweep_field_cases, sweep_field_mesh
    from results.pictures import (
        RenderingUnavailableError,
        enclosing_parts,
        plot_y_vs_torque,
        render_deformed,
        sweep_colour_limits_um,
    )

    settings = sweep_settings(model, solver=solver, mesh_size_mm=mesh_size_mm)
    rig_model = load_rig(rig)
    load_cases = cases_from_options(cases, t1, t2, False)
    result = run_with_progress(rig_model, load_cases, settings, "solving load cases", prepare_with_status(rig_model, settings))
    mesh, paths = sweep_field_mesh(result)
    field_cases = sweep_field_cases(result)
    limits = sweep_colour_limits_um(field_cases)
    housings = enclosing_parts(mesh)
    folder = out / "pictures"
    try:
        with progress_bar() as progress:
            task = progress.add_task("rendering", total=len(field_cases))
            for i, case in enumerate(field_cases):
                info = render_deformed(mesh, case, folder / f"deformed_{model}_{i:02d}.png", paths=paths,
                                       warp_fraction=warp_fraction, colour_limits_um=limits,
                                       translucent_parts=housings,
                                       title=f"{rig_model.rig.name} ({model}): T1 = {case.T1_input_Nm:g} N·m, "
                                             f"T2 = {case.T2_output_Nm:g} N·m")
                progress.update(task, completed=i + 1)
    except RenderingUnavailableError as error:
        raise UserError(str(error)) from None
    published = paper_table() if cases is None and t1 is None else None
    plot = plot_y_vs_torque(result, folder / f"y_vs_torque_{model}.png", published=published,
                            title=f"{rig_model.rig.name} ({model} model)")
    console.print(f"wrote {len(field_cases)} pictures to {escape(str(folder))} (colour limits {limits[0]:.3g} .. {limits[1]:.3g} µm, "
                  f"last warp factor {info['warp_factor']:.3g}) and {escape(str(plot))}")


@rig_app.command("show")
@guard
def rig_show(rig: RigOption = None) -> None:
    """A readable table of the rig: parts with their modelled mass, supports, couplings, torque paths."""
    rig_model = load_rig(rig)
    built = build_rig_model(rig_model)
    parts = Table(title=escape(f"{rig_model.rig.name}: parts (x along the drivetrain, mm)"), title_justify="left")
    for column in ("part", "role", "x from", "x to", "Ø outer mm", "material", "E GPa", "density kg/m³", "mass kg"):
        parts.add_column(column)
    for p in rig_model.parts:
        lo, hi = p.x_range_mm
        diameters = sorted({s.outer_diameter_mm for s in p.segments})
        material = rig_model.materials[p.material]
        density = built.equivalent_density.get(p.name, material.density_kg_per_m3)
        add_text_row(parts, p.name, p.role, f"{lo:g}", f"{hi:g}", "/".join(f"{d:g}" for d in diameters), p.material,
                      f"{material.youngs_modulus_MPa / 1e3:g}",
                      f"{density:.0f}" + (" (equiv.)" if p.name in built.equivalent_density else ""),
                      f"{built.part_mass_kg[p.name]:.3f}")
    console.print(parts)
    console.print(f"total mass {sum(built.part_mass_kg.values()):.2f} kg; beam model: {built.structure.n_nodes} nodes, "
                  f"{built.structure.n_dofs} DOF")
    springs = Table(title="Supports and connections", title_justify="left")
    for column in ("kind", "name", "between", "x mm", "stiffness"):
        springs.add_column(column)
    for b in rig_model.bearings:
        add_text_row(springs, "bearing", b.name, f"{b.shaft} / {b.housing}", f"{b.x_mm:g}",
                        f"radial {b.radial_stiffness_N_per_um:g} N/µm, axial {b.axial_stiffness_N_per_um:g} N/µm")
    for m in rig_model.mounts:
        add_text_row(springs, "mount", m.name, f"{m.part} / ground", f"{m.x_mm:g}",
                        f"{list(m.translational_stiffness_N_per_um)} N/µm, {list(m.rotational_stiffness_Nm_per_rad)} N·m/rad")
    for c in rig_model.couplings:
        add_text_row(springs, "coupling", c.name, f"{c.from_.part} / {c.to.part}", f"{c.centre_x_mm:g}",
                        f"radial {c.radial_stiffness_N_per_mm:g} N/mm, angular {c.angular_stiffness_Nm_per_rad:g} N·m/rad, "
                        f"torsional {c.torsional_stiffness_Nm_per_rad:g} N·m/rad; {c.mass_kg:g} kg")
    for j in rig_model.joints:
        add_text_row(springs, "joint", j.name, f"{j.from_.part} / {j.to.part}", f"{j.to.x_mm:g}",
                        f"{list(j.translational_stiffness_N_per_um)} N/µm, {list(j.rotational_stiffness_Nm_per_rad)} N·m/rad")
    console.print(springs)
    paths = Table(title="How torque becomes a lateral load", title_justify="left")
    for column in ("name", "torque", "kind", "acts on", "N per N·m", "engaged force N", "direction °"):
        paths.add_column(column)
    for t in rig_model.torque_lateral_loads:
        add_text_row(paths, t.name, t.torque, t.kind, f"{t.on.part} @ {t.on.x_mm:g}", f"{t.force_per_torque_N_per_Nm:.4g}",
                      f"{t.engaged_force_N:.4g}", f"{t.direction_deg:g}")
    console.print(paths)
    console.print(f"gravity: {'on' if rig_model.gravity.enabled else 'off'}; paper force table applied: "
                  f"{rig_model.force_table.apply}; Y measured from: {rig_model.paths.measured_from}; paths: input "
                  f"{rig_model.paths.input.part} {rig_model.paths.input.x_start_mm:g} + {rig_model.paths.input.length_mm:g} mm, "
                  f"output {rig_model.paths.output.part} {rig_model.paths.output.x_start_mm:g} + "
                  f"{rig_model.paths.output.length_mm:g} mm")


@rig_app.command("reference")
def rig_reference() -> None:
    """Print the built-in reference rig file (copy it to start your own)."""
    sys.stdout.write(reference_rig_text())


# Command families that live in their own modules; each module has ``register(app)``.
COMMAND_MODULES: tuple[str, ...] = (
    "results.discrepancy_cli",
    "results.montecarlo_cli",
    "results.export_cli",
    "results.doe_cli",
)


def _register_command_modules() -> None:
    import importlib

    for name in COMMAND_MODULES:
        importlib.import_module(name).register(app)


_register_command_modules()


def run() -> None:
    """Console-script entry point."""
    hugepages.avoid_compaction_stalls()  # process-wide numpy setting: see fem/hugepages.py
    blas_threads.single_threaded_openblas()  # process-wide too: see fem/blas_threads.py
    app()


if __name__ == "__main__":
    run()
