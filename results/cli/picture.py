"""``rvcoax picture``: off-screen pictures of the deformed rig per case and of Y against torque."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape

from rvcoax.results.cli import support

__all__ = ["picture", "register"]


def picture(
    rig: support.RigOption = None,
    model: support.ModelOption = "beam",
    out: support.OutOption = Path("rvcoax_out"),
    cases: Annotated[Path | None, typer.Option("--cases", help="Load cases file (as for sweep).")] = None,
    t1: Annotated[str | None, typer.Option("--t1", help="Input torques T1 in N·m, comma-separated.")] = None,
    t2: Annotated[str | None, typer.Option("--t2", help="Output torques T2 in N·m, comma-separated.")] = None,
    warp_fraction: Annotated[float, support.number_option("--warp-fraction", 0.0, 1.0, exclusive=True, help="Largest displacement drawn as this fraction of the rig length, in (0, 1).")] = 0.05,
    solver: support.SolverOption = "auto",
    mesh_size_mm: support.MeshOption = None,
) -> None:
    """Off-screen pictures: the deformed rig per case (u_y in µm, same colour limits across the sweep,
    measured paths drawn) and Y against torque with the published points."""
    from rvcoax.geometry.rigfile import load_rig
    from rvcoax.loadcases.cases import paper_table
    from rvcoax.results.io.fields import sweep_field_cases, sweep_field_mesh
    from rvcoax.results.io.pictures import (
        RenderingUnavailableError,
        enclosing_parts,
        plot_y_vs_torque,
        render_deformed,
        sweep_colour_limits_um,
    )

    settings = support.sweep_settings(model, solver=solver, mesh_size_mm=mesh_size_mm)
    rig_model = load_rig(rig)
    load_cases = support.cases_from_options(cases, t1, t2, False)
    result = support.run_with_progress(rig_model, load_cases, settings, "solving load cases", support.prepare_with_status(rig_model, settings))
    mesh, paths = sweep_field_mesh(result)
    field_cases = sweep_field_cases(result)
    limits = sweep_colour_limits_um(field_cases)
    housings = enclosing_parts(mesh)
    folder = out / "pictures"
    try:
        with support.progress_bar() as progress:
            task = progress.add_task("rendering", total=len(field_cases))
            for i, case in enumerate(field_cases):
                info = render_deformed(mesh, case, folder / f"deformed_{model}_{i:02d}.png", paths=paths,
                                       warp_fraction=warp_fraction, colour_limits_um=limits,
                                       translucent_parts=housings,
                                       title=f"{rig_model.rig.name} ({model}): T1 = {case.T1_input_Nm:g} N·m, "
                                             f"T2 = {case.T2_output_Nm:g} N·m")
                progress.update(task, completed=i + 1)
    except RenderingUnavailableError as error:
        raise support.UserError(str(error)) from None
    published = paper_table() if cases is None and t1 is None else None
    plot = plot_y_vs_torque(result, folder / f"y_vs_torque_{model}.png", published=published,
                            title=f"{rig_model.rig.name} ({model} model)")
    support.console.print(f"wrote {len(field_cases)} pictures to {escape(str(folder))} (colour limits {limits[0]:.3g} .. {limits[1]:.3g} µm, "
                  f"last warp factor {info['warp_factor']:.3g}) and {escape(str(plot))}")



def register(app: typer.Typer) -> None:
    """Add ``picture`` to ``app``."""
    app.command()(support.guard(picture))
