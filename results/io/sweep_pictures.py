"""The pictures of a sweep: the deformed rig per case (one colour scale and one warp factor for the whole sweep),
Y against torque, and the bending line of the whole rig."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from rvcoax.results.io.bending_line import plot_bending_line
from rvcoax.results.io.fields import sweep_field_cases, sweep_field_mesh
from rvcoax.results.io.pictures import (
    enclosing_parts,
    mesh_length_m,
    plot_y_vs_torque,
    render_deformed,
    sweep_colour_limits_um,
    sweep_warp_factor,
)
from rvcoax.results.sweep import Sweep

__all__ = ["SweepPictures", "draw_sweep_pictures"]


@dataclass(frozen=True)
class SweepPictures:
    """What :func:`draw_sweep_pictures` wrote.

    Attributes
    ----------
    deformed : tuple of Path
        One PNG of the deformed rig per case.
    y_vs_torque : Path
        Y of both measured shafts against torque.
    colour_limits_um : (float, float)
        The u_y colour scale shared by every case, µm.
    warp_factor : float
        The displacement magnification of every picture (one for the whole sweep, printed on each).
    bending_line : Path
        u_y, u_z and the section rotations of every part against x.
    """

    deformed: tuple[Path, ...]
    y_vs_torque: Path
    colour_limits_um: tuple[float, float]
    warp_factor: float
    bending_line: Path


def draw_sweep_pictures(sweep: Sweep, folder: Path, *, warp_fraction: float = 0.05, published=None,  # noqa: PLR0913
                        progress: Callable[[int, int], None] | None = None,
                        window_size: tuple[int, int] = (1600, 600)) -> SweepPictures:
    """Draw every case of ``sweep`` off screen into ``folder``.

    Parameters
    ----------
    sweep : Sweep
        A solved sweep (beam, hybrid or solid).
    folder : Path
        Where the PNGs go: ``deformed_<model>_<i>.png``, ``y_vs_torque_<model>.png`` and
        ``bending_line_<model>.png``.
    warp_fraction : float
        The largest displacement of the whole sweep is drawn as this fraction of the rig length; every
        case uses the same factor, so that a larger torque shows a larger bend.
    published : tuple of PublishedRow, optional
        Published points drawn with Y against torque.
    progress : callable, optional
        ``progress(done, total)`` after each rendered case.
    window_size : (width, height)
        Size of each picture of the deformed rig, pixels.

    Returns
    -------
    SweepPictures
        The PNG of each case and the PNG of Y against torque.

    Raises
    ------
    RenderingUnavailableError
        Off-screen rendering cannot start on this machine (the message says what to install).
    """
    model = sweep.settings.model
    name = sweep.rig.rig.name
    mesh, paths = sweep_field_mesh(sweep)
    field_cases = sweep_field_cases(sweep)
    limits = sweep_colour_limits_um(field_cases)
    housings = enclosing_parts(mesh)
    factor = sweep_warp_factor(field_cases, mesh_length_m(mesh), warp_fraction)
    bearings = [b.x_mm for b in sweep.rig.bearings]
    written = []
    for i, case in enumerate(field_cases):
        path = folder / f"deformed_{model}_{i:02d}.png"
        render_deformed(mesh, case, path, paths=paths, warp_factor=factor, colour_limits_um=limits,
                        translucent_parts=housings, bearings_x_mm=bearings, window_size=window_size,
                        title=f"{name} ({model}): T1 = {case.T1_input_Nm:g} N·m, T2 = {case.T2_output_Nm:g} N·m")
        written.append(path)
        if progress is not None:
            progress(i + 1, len(field_cases))
    plot = plot_y_vs_torque(sweep, folder / f"y_vs_torque_{model}.png", published=published,
                            title=f"{name} ({model} model)")
    bending = plot_bending_line(sweep, folder / f"bending_line_{model}.png", title=name)
    return SweepPictures(tuple(written), plot, limits, float(factor), bending)
