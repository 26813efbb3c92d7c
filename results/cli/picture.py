"""``rvcoax picture``: off-screen pictures of the deformed rig per case and of Y against torque."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

from rich.markup import escape

from rvcoax.results.cli import support

__all__ = ["COMMANDS", "picture"]


@support.model_options
@support.case_options
def picture(
    *,
    model_choice: support.ModelChoice,
    case_choice: support.CaseChoice,
    out: support.OutOption = Path("rvcoax_out"),
    warp_fraction: Annotated[float, support.number_option("--warp-fraction", 0.0, 1.0, exclusive=True, help="Largest displacement drawn as this fraction of the rig length, in (0, 1).")] = 0.05,
) -> None:
    """Off-screen pictures: the deformed rig per case (u_y in µm, same colour limits across the sweep,
    measured paths drawn) and Y against torque with the published points."""
    from rvcoax import draw_sweep_pictures, paper_table
    from rvcoax.loadcases import default_is_paper
    from rvcoax.results.io import RenderingUnavailableError

    settings = model_choice.settings()
    rig = model_choice.load_rig()
    load_cases = case_choice.load(rig)
    result = support.run_with_progress(rig, load_cases, settings, "solving load cases",
                                       support.prepare_with_status(rig, settings))
    folder = out / "pictures"
    published = paper_table() if not case_choice.given and default_is_paper(rig) else None
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


COMMANDS = {"picture": picture}
"""The commands of this module, by name (:func:`rvcoax.results.cli.support.register_commands`)."""
