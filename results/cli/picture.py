"""``rvcoax picture``: off-screen pictures of the deformed rig per case and of Y against torque."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape

from rvcoax.results.cli import support

__all__ = ["picture", "register"]


def picture(
    rig_file: support.RigOption = None,
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
    from rvcoax import draw_sweep_pictures, load_rig, paper_table
    from rvcoax.loadcases import default_is_paper
    from rvcoax.results.io import RenderingUnavailableError

    settings = support.sweep_settings(model, solver=solver, mesh_size_mm=mesh_size_mm)
    rig = load_rig(rig_file)
    load_cases = support.cases_from_options(cases, t1, t2, False, rig, rig_file)
    result = support.run_with_progress(rig, load_cases, settings, "solving load cases",
                                       support.prepare_with_status(rig, settings))
    folder = out / "pictures"
    published = paper_table() if cases is None and t1 is None and default_is_paper(rig) else None
    try:
        with support.progress_bar() as bar:
            task = bar.add_task("rendering", total=len(load_cases))
            drawn = draw_sweep_pictures(result, folder, warp_fraction=warp_fraction, published=published,
                                        progress=lambda i, n: bar.update(task, completed=i))
    except RenderingUnavailableError as error:
        raise support.UserError(str(error)) from None
    low, high = drawn.colour_limits_um
    support.console.print(f"wrote {len(drawn.deformed)} pictures of the deformed rig to {escape(str(folder))} "
                          f"(colour limits {low:.3g} .. {high:.3g} µm; one warp factor for every case: "
                          f"× {drawn.warp_factor:.4g}), {escape(drawn.y_vs_torque.name)} and "
                          f"{escape(drawn.bending_line.name)}")


def register(app: typer.Typer) -> None:
    """Add ``picture`` to ``app``."""
    app.command()(support.guard(picture))
