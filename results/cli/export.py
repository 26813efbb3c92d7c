"""``rvcoax export``: inputs for dynamics models (JSON, CSV, an ADAMS dataset fragment, ROSS rotors).

See :mod:`rvcoax.results.export.dynamics` for what is exported, :mod:`rvcoax.results.export.adams` and :mod:`rvcoax.results.export.ross`
for the two dynamics packages.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.cli import support

__all__ = ["FORMATS", "register"]

FORMATS = ("json", "csv", "adams", "ross")


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


def _check_adams_cases(cases) -> None:
    """Refuse, before solving, cases that cannot make the ADAMS splines."""
    from rvcoax.results.export import AdamsExportError, spline_layout

    try:
        for shaft in MEASURED_SHAFTS:
            spline_layout(cases, shaft)
    except AdamsExportError as error:
        raise support.UserError(f"--format adams: {error}") from None


def _write_adams(export, out: Path) -> list[Path]:
    from rvcoax.results.export import AdamsExportError, adams_fragment, parse_adm
    from rvcoax.results.io import write_text_atomic

    try:
        text = adams_fragment(export)
    except AdamsExportError as error:
        raise support.UserError(f"--format adams: {error}") from None
    parse_adm(text)  # the fragment must read back under the dataset rules it claims to follow
    return [write_text_atomic(out / "dynamics.adm", text)]


def _save_rotor(rotor, path: Path) -> Path:
    """``rotor.save`` through a temporary file in the same folder (ROSS picks the format by suffix)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f".{path.stem}.partial{path.suffix}")
    try:
        rotor.save(temporary)
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
    return path


def _write_ross(export, out: Path) -> list[Path]:
    from rvcoax.results.export import (
        RossUnavailableError,
        compare_static,
        import_ross,
        misalignment_fault,
        misalignment_parameters,
        operating_radial_stiffness,
    )
    from rvcoax.results.io import write_csv_atomic

    try:
        ross = import_ross()
    except RossUnavailableError as error:
        raise support.UserError(str(error)) from None
    written, faults, static = [], [], []
    table = Table(title="ROSS static analysis (gravity, rigid supports) vs rvcoax on the same shaft",
                  title_justify="left")
    for column in ("shaft", "nodes", "supports", "largest sag rvcoax nm", "largest sag ROSS nm", "largest difference"):
        table.add_column(column, justify="right")
    for shaft in MEASURED_SHAFTS:
        with support.console.status(f"building and solving the ROSS rotor of the {shaft} shaft"):
            rotor, comparison = compare_static(export.sweep.rig, shaft, ross, operating_radial_stiffness(export))
        line = comparison.line
        parameters = misalignment_parameters(export, line)
        for row in parameters:
            misalignment_fault(rotor, row, ross)  # ROSS accepts every set of parameters
        faults += parameters
        static += [{"shaft": shaft, "x_mm": float(x), "uy_ross_um": float(a * 1e6), "uy_rvcoax_um": float(b * 1e6)}
                   for x, a, b in zip(line.node_x_mm, comparison.ross_uy_m, comparison.rvcoax_uy_m)]
        written.append(_save_rotor(rotor, out / f"ross_{shaft}_rotor.toml"))
        table.add_row(shaft, str(line.node_x_mm.size), ", ".join(s.spring.name for s in line.supports),
                      f"{comparison.largest_sag_m * 1e9:.4g}", f"{abs(comparison.ross_uy_m).max() * 1e9:.4g}",
                      f"{comparison.relative_difference:.1e}")
    written.append(write_csv_atomic(out / "ross_misalignment.csv", faults))
    written.append(write_csv_atomic(out / "ross_static.csv", static))
    support.console.print(table)
    return written


def register(app: typer.Typer) -> None:
    """Add ``rvcoax export`` to ``app``."""
    from rvcoax import load_rig


    @app.command()
    @support.guard
    def export(
        output_format: Annotated[str, typer.Option("--format", help="json (dynamics.json), csv (dynamics_*.csv), adams "
                                            "(dynamics.adm, an ADAMS/Solver dataset fragment) or ross (ROSS rotors "
                                            "of the measured shafts, misalignment fault parameters, static check; "
                                            "needs the rvcoax\\[ross] extra).")] = "json",
        rig_file: support.RigOption = None,
        model: support.ModelOption = "beam",
        out: support.OutOption = Path("rvcoax_out"),
        cases: support.CasesOption = None,
        t1: support.T1Option = None,
        t2: support.T2Option = None,
        grid: support.GridOption = False,
        input_radial_mm: Annotated[float | None, support.number_option(
            "--input-radial-mm", *support.RADIAL_OFFSET_RANGE_MM, "mm",
            help="Radial displacement a of the input shaft (mm); default 0.002 (paper 000, IT3).")] = None,
        output_radial_mm: Annotated[float | None, support.number_option(
            "--output-radial-mm", *support.RADIAL_OFFSET_RANGE_MM, "mm",
            help="Radial displacement a of the output shaft (mm); default 0.003 (paper 000, IT3).")] = None,
        solver: support.SolverOption = "auto",
        mesh_size_mm: support.MeshOption = None,
    ) -> None:
        """Export dynamics inputs per load case: tilt β and radial displacement a of both measured shafts, paper
        000's lever arm per shaft stage, offset and angle at every coupling, bearing reactions (N, N·m)."""
        from rvcoax.results import ConnectionsUnavailableError
        from rvcoax.results.export import dynamics_export, write_dynamics_csv, write_dynamics_json

        if output_format not in FORMATS:
            raise support.UserError(f"--format: '{output_format}' is not one of {', '.join(FORMATS)}")
        radial = {"input": input_radial_mm, "output": output_radial_mm}
        if output_format == "ross":
            from rvcoax.results.export import RossUnavailableError, import_ross

            try:  # before solving: a missing optional package should not cost a sweep
                import_ross()
            except RossUnavailableError as error:
                raise support.UserError(str(error)) from None
        settings = support.sweep_settings(model, solver=solver, mesh_size_mm=mesh_size_mm)
        rig = load_rig(rig_file)
        load_cases = support.cases_from_options(cases, t1, t2, grid, rig)
        if output_format == "adams":
            _check_adams_cases(load_cases)
        result = support.run_with_progress(rig, load_cases, settings, "solving load cases",
                                   support.prepare_with_status(rig, settings))
        try:
            exported = dynamics_export(result, {k: v for k, v in radial.items() if v is not None})
        except ConnectionsUnavailableError as error:
            raise support.UserError(f"rig file {rig_file or 'built-in reference_rig.toml'}: cannot export: {error}") from None
        support.console.print(_summary(exported))
        if output_format == "json":
            source, text = support.rig_text(rig_file)
            written = [write_dynamics_json(exported, out / "dynamics.json", source, text)]
        elif output_format == "csv":
            written = write_dynamics_csv(exported, out)
        elif output_format == "adams":
            written = _write_adams(exported, out)
        else:
            written = _write_ross(exported, out)
        support.console.print(f"a: input {exported.radial_mm['input']:g} mm, output {exported.radial_mm['output']:g} mm; "
                      f"couplings, bearings and β from the {exported.measured_from} state "
                      "(columns *_unloaded_ref: from the unloaded geometry)")
        support.report_written(written)
