"""Pictures of natural modes: a mode shape over the undeformed rig (off-screen VTK), and the interference diagram.

:func:`render_mode` draws the rig undeformed as a grey ghost and the mode shape over it, coloured by the relative
amplitude of each point (0 … 1 of the mode's largest), every part named under it, the frequency in the title. A
lateral vertical, axial or mixed mode is seen from the side (y up), a lateral horizontal one from above (z up in
the picture); a torsional mode is drawn undeformed, coloured by the twist of each section (beams: θ_x; solids:
the tangential displacement over the radius), since a twisted tube looks like a straight one. Housings around
shafts are drawn translucent, as in the sweep's pictures.

:func:`plot_interference` is the Campbell-style diagram: each mode's frequency (a horizontal line: gyroscopic
effects neglected, see :mod:`rvcoax.results.studies.modes`) against the motor speed, with the excitation orders
as rays from the origin, the speed range shaded and the crossings inside it marked.
"""

from __future__ import annotations

import textwrap
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from rvcoax.results.io.fields import FieldMesh
from rvcoax.results.io.pictures import (
    ENCLOSING_OPACITY,
    _band,
    _draw_ruler,
    _part_labels,
    _part_surfaces,
    _quiet_vtk,
    _RigView,
    _screenshot,
    _title_lines,
    check_offscreen_rendering,
    enclosing_parts,
    mesh_length_m,
)
from rvcoax.results.io.writers import write_png_atomic

__all__ = ["GHOST_OPACITY", "plot_interference", "render_mode"]

GHOST_OPACITY = 0.18  # the undeformed rig behind the mode shape
MODE_WARP_FRACTION = 0.06  # the largest displacement drawn as this fraction of the rig length


def _view_of(kind: str) -> str:
    if kind.startswith("lateral horizontal"):
        return "above"
    if kind.startswith("torsional"):
        return "twist"
    return "side"


def _mode_geometry(mesh: FieldMesh, u: np.ndarray, twist, view_kind: str):
    """(points, deformed points, scalar in 0 … 1, warp factor, rig length in m) of a mode drawn in ``view_kind``:
    turned so that the mode's plane faces the camera, warped to a fixed share of the rig length."""
    points = np.asarray(mesh.points, dtype=float)
    if view_kind == "above":  # turned −90° about x: z is up in the picture
        rotate = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
        points, u = points @ rotate.T, u @ rotate.T
    length = mesh_length_m(mesh)
    amplitude = np.linalg.norm(u, axis=1)
    if view_kind == "twist":
        scalar = np.abs(np.asarray(twist, dtype=float).ravel())
        factor = 0.0
    else:
        scalar = amplitude
        largest = float(amplitude.max())
        factor = MODE_WARP_FRACTION * length / largest if largest > 0 else 0.0
    scalar = scalar / scalar.max() if scalar.max() > 0 else scalar
    deformed = points + factor * u
    return points, deformed, scalar, factor, length


def render_mode(mesh: FieldMesh, displacement_m: np.ndarray, twist: np.ndarray, kind: str, *, title: str,  # noqa: PLR0913
                path_png: str | Path, bearings_x_mm: Sequence[float] = (), window_size: tuple[int, int] = (1600, 600),
                min_radius_fraction: float = 0.002) -> dict:
    """Draw one mode shape over the undeformed rig and write a PNG.

    Parameters
    ----------
    mesh : FieldMesh
        The rig's points and cells (:func:`rvcoax.results.io.fields.sweep_field_mesh`).
    displacement_m : (n, 3) array
        The mode's translation at each point (any scale: it is drawn relative to its largest).
    twist : (n,) array
        The section rotation about the axis at each point (rad, same scale), for torsional modes.
    kind : str
        The mode's class (``lateral vertical``, ``lateral horizontal``, ``torsional``, ``axial``, ``mixed …``):
        chooses the view.
    title : str
        The title (the mode's number, frequency and class).
    path_png : path
        The PNG to write (atomically).
    bearings_x_mm : positions
        Bearing positions marked on the ruler.
    window_size : (width, height)
    min_radius_fraction : float
        Beams thinner than this fraction of the rig length are drawn at that radius.

    Returns
    -------
    dict
        ``path``, ``view`` (side, above, twist), ``warp_factor`` and ``seconds``.
    """
    started = time.perf_counter()
    u = np.asarray(displacement_m, dtype=float).reshape(-1, 3)
    if u.shape[0] != mesh.n_points:
        raise ValueError(f"the mode has {u.shape[0]} points, the mesh {mesh.n_points}")
    view_kind = _view_of(kind)
    points, deformed, scalar, factor, length = _mode_geometry(mesh, u, twist, view_kind)
    target = Path(path_png)
    target.parent.mkdir(parents=True, exist_ok=True)
    check_offscreen_rendering()
    import pyvista as pv

    pv.OFF_SCREEN = True
    radius = np.maximum(mesh.line_radius_m, min_radius_fraction * length)
    with _quiet_vtk():
        ghost = _part_surfaces(mesh, points, np.zeros(mesh.n_points), radius)
        shape = _part_surfaces(mesh, deformed, scalar, radius)
        translucent = {mesh.part_names.index(n) for n in enclosing_parts(mesh, rig_length_m=length)}
        plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
        try:
            plotter.set_background("white")
            band = _band(window_size)
            bar = {"title": "relative twist" if view_kind == "twist" else "relative amplitude", "vertical": True,
                   "color": "black", "fmt": "%.1f", "n_labels": 3, "position_x": 0.9, "position_y": 0.15,
                   "height": 0.7, "width": 0.05, "title_font_size": max(8, round(band)),
                   "label_font_size": max(6, round(0.8 * band))}
            if factor > 0:
                for surface in ghost.values():
                    plotter.add_mesh(surface, color="lightgrey", opacity=GHOST_OPACITY)
            first = True
            for part, surface in shape.items():
                plotter.add_mesh(surface, scalars="u_y_um", cmap="plasma", clim=(0.0, 1.0), smooth_shading=True,
                                 opacity=ENCLOSING_OPACITY if part in translucent else 1.0,
                                 show_scalar_bar=first, scalar_bar_args=bar if first else None)
                first = False
            view = _annotate(plotter, mesh, (points, deformed, radius), title, view_kind, bearings_x_mm=bearings_x_mm,
                             window_size=window_size)
            plotter.enable_depth_peeling(number_of_peels=6)
            _screenshot(plotter, view, target)
        finally:
            plotter.close()
    return {"path": target, "view": view_kind, "warp_factor": factor, "seconds": time.perf_counter() - started}


def _annotate(plotter, mesh: FieldMesh, geometry, title: str, view_kind: str, *, bearings_x_mm,  # noqa: PLR0913
              window_size) -> _RigView:
    """Part names, the ruler, the view's note and the title; returns the fitted view. ``geometry`` is (undeformed
    points, deformed points, tube radii)."""
    points, deformed, radius = geometry
    length = mesh_length_m(mesh)
    bounds = (np.minimum(points.min(axis=0), deformed.min(axis=0)) - radius.max(),
              np.maximum(points.max(axis=0), deformed.max(axis=0)) + radius.max())
    lines = _title_lines(title, window_size)
    view = _RigView.fit(bounds, window_size, label_rows=2, title_lines=len(lines))
    labels = _part_labels(mesh, points, view)
    view = _RigView.fit(bounds, window_size, label_rows=1 + max((r for *_, r in labels), default=0),
                        title_lines=len(lines))
    labels = _part_labels(mesh, points, view)
    front = float(max(points[:, 2].max(), deformed[:, 2].max()) + 1.5 * radius.max())
    _draw_ruler(plotter, view, front + 0.02 * length, bearings_x_mm)
    for name, x_mm, row in labels:
        column, pixel_row = view.label_pixel(x_mm * 1e-3, row, name)
        plotter.add_text(name, position=(column, pixel_row), font_size=view.small_font, color="black")
    note = {"side": "seen from the side (y up); grey: undeformed",
            "above": "seen from above (z up in the picture); grey: undeformed",
            "twist": "drawn undeformed, coloured by the twist of each section"}[view_kind]
    plotter.add_text(note, position=(4, 0.2 * view.band), font_size=view.small_font, color="black")
    plotter.add_text("\n".join(lines), position="upper_edge", font_size=view.title_font, color="black")
    return view


def plot_interference(frequencies_hz: dict, orders: Sequence[tuple[str, float]],  # noqa: PLR0913
                      speed_range_rpm: tuple[float, float], crossings: Sequence, *, path_png: str | Path,
                      title: str = "") -> Path:
    """Write the interference (Campbell-style) diagram as a PNG.

    Parameters
    ----------
    frequencies_hz : dict
        Operating point label → its modes' frequencies (Hz); each a horizontal line (gyroscopic effects
        neglected).
    orders : sequence of (name, order)
        Excitations as multiples of the motor speed: f = order × n / 60.
    speed_range_rpm : (low, high)
        The motor's speed range, shaded.
    crossings : sequence
        Objects with ``crossing_rpm``, ``frequency_hz`` and ``inside``: those inside the range are marked.
    path_png : path
    title : str

    Returns
    -------
    Path
        The PNG written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    low, high = speed_range_rpm
    top_speed = 1.25 * high
    all_f = [f for values in frequencies_hz.values() for f in values]
    f_top = 1.1 * max(all_f) if all_f else 1.0
    figure, axes = plt.subplots(figsize=(10, 6), dpi=120)
    try:
        axes.axvspan(low, high, color="0.92", label=f"motor speed range {low:g}–{high:g} rpm")
        styles = ["-", "--", "-.", ":"]
        for k, (label, values) in enumerate(frequencies_hz.items()):
            for i, f in enumerate(values):
                axes.axhline(f, color="tab:blue", lw=0.8, ls=styles[k % len(styles)], alpha=0.7,
                             label=f"natural frequencies ({label})" if i == 0 else None)
        colours = ["tab:red", "tab:orange", "tab:green", "tab:purple", "tab:brown"]
        speeds = np.array([0.0, top_speed])
        for (name, order), colour in zip(orders, colours * 3):
            axes.plot(speeds, order * speeds / 60.0, color=colour, lw=1.6, label=name)
        inside = [c for c in crossings if c.inside]
        if inside:
            axes.plot([c.crossing_rpm for c in inside], [c.frequency_hz for c in inside], "o", mfc="none",
                      color="black", ms=6, label=f"crossings in the range ({len(inside)})")
        axes.set_xlim(0.0, top_speed)
        axes.set_ylim(0.0, f_top)
        axes.set_xlabel("motor speed n [rpm]")
        axes.set_ylabel("frequency f [Hz]")
        axes.set_title(textwrap.fill(title or "interference diagram: natural frequencies and excitation orders", 95))
        axes.grid(True, color="0.85")
        axes.legend(loc="upper left", fontsize=8, framealpha=0.95)
        figure.tight_layout()
        return write_png_atomic(path_png, figure)
    finally:
        plt.close(figure)
