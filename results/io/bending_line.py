"""The bending line of the whole rig: u_y, u_z and the section rotations of every part against x.

The line is read from the beam nodes of the model (the frame of a hybrid or solid model: a solid
part there has only the reference nodes where its springs attach), measured as Y is
(``paths.measured_from``: from the aligned rig at rest by default). One figure has three panels
on one x axis, and a strip above them naming every part (housings hatched) with the bearings (▲)
and couplings (◆) marked and named, so that a reader finds where a shaft bends and what holds it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.io.writers import write_png_atomic

__all__ = ["NOISE", "PartLine", "bending_lines", "out_of_plane_is_rounding", "plot_bending_line", "stack_rows"]

NOISE = 1e-6
"""Out-of-plane motion (u_z, rotation about y) at most this share of the in-plane one is the solve's rounding and
is drawn as 0, with a note."""


@dataclass(frozen=True, eq=False)
class PartLine:
    """The bending line of one part in every case of a sweep.

    Attributes
    ----------
    part : str
    role : str
        ``shaft`` or ``body`` (a housing).
    solid : bool
        The part is a solid in this model: only its spring attachment points are on the line.
    x_mm : (n,) array
        Node positions along the rig axis.
    u_y_um, u_z_um : (n_cases, n) arrays
        Translation of the section centre, µm (+y up).
    rotation_z_urad, rotation_y_urad : (n_cases, n) arrays
        Section rotation about z (slope du_y/dx in the x–y plane) and about y (−du_z/dx), µrad.
    """

    part: str
    role: str
    solid: bool
    x_mm: np.ndarray
    u_y_um: np.ndarray
    u_z_um: np.ndarray
    rotation_z_urad: np.ndarray
    rotation_y_urad: np.ndarray


def bending_lines(sweep) -> list[PartLine]:
    """One :class:`PartLine` per part of a solved sweep, in the rig file's order."""
    system = sweep.system
    frame = system.frame if system is not None else sweep.frame
    n_nodes = frame.structure.n_nodes
    motion = np.stack([sweep.measured_displacement(i)[: 6 * n_nodes].reshape(-1, 6)
                       for i in range(len(sweep.cases))])  # (cases, nodes, 6)
    solid = {p.name for p in getattr(system, "solids", ())}
    lines = []
    for part in sweep.rig.parts:
        nodes = np.flatnonzero(frame.node_part == part.name)
        nodes = nodes[np.argsort(frame.node_x_mm[nodes], kind="stable")]
        picked = motion[:, nodes, :]
        lines.append(PartLine(part=part.name, role=part.role, solid=part.name in solid,
                              x_mm=np.asarray(frame.node_x_mm[nodes], float), u_y_um=picked[:, :, 1] * 1e6,
                              u_z_um=picked[:, :, 2] * 1e6, rotation_z_urad=picked[:, :, 5] * 1e6,
                              rotation_y_urad=picked[:, :, 4] * 1e6))
    return lines


def stack_rows(spans: Sequence[tuple[float, float]], gap: float = 0.0) -> list[int]:
    """Row of each span so that spans in one row do not overlap (greedy, in the given order)."""
    ends: list[float] = []
    rows = []
    for start, end in spans:
        row = next((i for i, last in enumerate(ends) if start >= last + gap), len(ends))
        if row == len(ends):
            ends.append(end)
        else:
            ends[row] = end
        rows.append(row)
    return rows


def _chosen_cases(n: int, cases: Sequence[int] | None, most: int = 4) -> list[int]:
    if cases is not None:
        chosen = [int(c) for c in cases]
        bad = [c for c in chosen if not 0 <= c < n]
        if bad:
            raise ValueError(f"case indices {bad} are outside 0 … {n - 1}")
        return chosen
    return sorted(set(np.linspace(0, n - 1, min(n, most)).round().astype(int).tolist()))


def _text_width(text: str, axis, fontsize: float) -> float:
    """Width of ``text`` in x data units of ``axis`` (an estimate: 0.6 em per character)."""
    figure = axis.figure
    width_px = axis.get_position().width * figure.get_figwidth() * figure.dpi
    low, high = axis.get_xlim()
    return 0.6 * fontsize * figure.dpi / 72.0 * len(text) * (high - low) / width_px


def _strip(axis, sweep, lines: list[PartLine]) -> None:
    """Parts as bars (shafts solid, housings hatched), bearings ▲ and couplings ◆ with their names."""
    rig = sweep.rig
    parts = [(p.name, p.role, *p.x_range_mm) for p in rig.parts]
    font = 7.5
    spans = []
    for name, _, x0, x1 in parts:
        text = _text_width(name, axis, font)
        spans.append((x0, max(x1, x0 + text)))
    rows = stack_rows(spans, gap=0.01 * (axis.get_xlim()[1] - axis.get_xlim()[0]))
    n_rows = max(rows) + 1
    for (name, role, x0, x1), row in zip(parts, rows):
        y = n_rows - row
        style = {"facecolor": "#4c72b0", "edgecolor": "#4c72b0"} if role == "shaft" else \
            {"facecolor": "#dddddd", "edgecolor": "#777777", "hatch": "///"}
        axis.barh(y, x1 - x0, left=x0, height=0.35, **style)
        axis.text(x0, y + 0.22, name, fontsize=font, va="bottom", ha="left")
    marks = [(b.x_mm, "^", "#c44e52", b.name) for b in rig.bearings]
    marks += [(c.centre_x_mm, "D", "#55a868", c.name) for c in rig.couplings]
    marks.sort()
    label_spans = [(x - 0.5 * _text_width(n, axis, 6.5), x + 0.5 * _text_width(n, axis, 6.5)) for x, *_, n in marks]
    label_rows = stack_rows(label_spans, gap=0.005 * (axis.get_xlim()[1] - axis.get_xlim()[0]))
    for (x, marker, colour, name), row in zip(marks, label_rows):
        axis.plot([x], [-0.1], marker=marker, color=colour, ms=6, clip_on=False)
        axis.text(x, -0.55 - 0.7 * row, name, fontsize=6.5, ha="center", va="top", color=colour)
    axis.set_ylim(-0.75 - 0.7 * (max(label_rows, default=0) + 1), n_rows + 0.9)
    axis.set_yticks([])
    for side in ("left", "right", "top"):
        axis.spines[side].set_visible(False)
    axis.tick_params(axis="x", labelbottom=False)


def out_of_plane_is_rounding(lines: list[PartLine]) -> tuple[bool, bool, float]:
    """Whether u_z and the rotation about y are the solve's rounding (at most :data:`NOISE` of u_y and of the
    rotation about z, whose solves hold ~1e-10), and the largest |u_z| (µm): such a panel is drawn as 0.

    Parameters
    ----------
    lines : list of PartLine
        :func:`bending_lines` of a sweep.

    Returns
    -------
    (bool, bool, float)
        u_z is rounding, the rotation about y is rounding, the largest |u_z|.
    """
    drawn = [line for line in lines if line.x_mm.size]

    def largest(values) -> float:
        return max((float(abs(v).max()) for v in values), default=0.0)

    largest_z = largest(line.u_z_um for line in drawn)
    return (largest_z <= NOISE * largest(line.u_y_um for line in drawn),
            largest(line.rotation_y_urad for line in drawn) <= NOISE * largest(line.rotation_z_urad for line in drawn),
            largest_z)


def _draw_case(panels, sweep, lines, case_index: int, colour: str) -> None:
    """One case's u_y, u_z and section rotations along every part (a solid measured shaft: its path as read);
    out-of-plane motion that is the solve's rounding (:func:`out_of_plane_is_rounding`) drawn as 0."""
    flat_z, flat_ry, _ = out_of_plane_is_rounding(lines)
    for line in lines:
        if not line.x_mm.size:
            continue
        style = {"color": colour, "lw": 1.6 if line.role == "shaft" else 0.9,
                 "ls": "-" if line.role == "shaft" else "--"}
        if line.solid:
            style.update(ls="none", marker="o", ms=3)
        panels[0].plot(line.x_mm, line.u_y_um[case_index], **style)
        panels[1].plot(line.x_mm, 0.0 * line.x_mm if flat_z else line.u_z_um[case_index], **style)
        panels[2].plot(line.x_mm, line.rotation_z_urad[case_index], **style)
        panels[2].plot(line.x_mm, 0.0 * line.x_mm if flat_ry else line.rotation_y_urad[case_index],
                       **{**style, "lw": 0.8, "alpha": 0.6, "ls": ":"})
    for shaft in MEASURED_SHAFTS:  # a solid measured shaft: its path as the sweep reads it (axis u_y, rotation)
        path = getattr(sweep.rig.paths, shaft)
        if any(line.solid and line.part == path.part for line in lines):
            read = sweep.cases[case_index].paths[shaft]
            x = path.x_start_mm + read.station_mm
            panels[0].plot(x, read.uy_mm * 1e3, color=colour, lw=1.6)
            panels[2].plot(x, read.rotation_z_rad * 1e6, color=colour, lw=1.6)


def _draw_panel_frames(panels, sweep, lines) -> None:
    """The bearings and couplings as vertical lines, the axis labels, and a note when u_z is zero everywhere."""
    for x in [b.x_mm for b in sweep.rig.bearings]:
        for axis in panels:
            axis.axvline(x, color="#c44e52", lw=0.5, alpha=0.35)
    for x in [c.centre_x_mm for c in sweep.rig.couplings]:
        for axis in panels:
            axis.axvline(x, color="#55a868", lw=0.5, alpha=0.5, ls="-.")
    labels = ("u_y (vertical, + up) [µm]", "u_z (horizontal) [µm]", "section rotation [µrad]")
    for axis, label in zip(panels, labels):
        axis.set_ylabel(label)
        axis.grid(True, alpha=0.3)
        axis.axhline(0.0, color="black", lw=0.6)
    for axis in panels[:-1]:
        axis.tick_params(axis="x", labelbottom=False)
    panels[-1].set_xlabel("x along the rig axis [mm]")
    flat_z, _, largest_z = out_of_plane_is_rounding(lines)
    if flat_z:
        panels[1].set_ylim(-1.0, 1.0)
        panels[1].text(0.5, 0.7, "u_z = 0 along the whole rig: every load of these cases acts in the x–y plane"
                       + (f" (the solve's rounding, |u_z| ≤ {largest_z:.0e} µm, is drawn as 0)" if largest_z else ""),
                       transform=panels[1].transAxes, ha="center", va="center", fontsize=9, color="#444444",
                       bbox={"facecolor": "white", "edgecolor": "#cccccc"})



def plot_bending_line(sweep, path_png: str | Path, *, cases: Sequence[int] | None = None, title: str | None = None,
                      dpi: int = 150) -> Path:
    """Draw the bending line of the whole rig (u_y, u_z, section rotations against x) as a PNG.

    Parameters
    ----------
    sweep : Sweep
        A solved sweep (any model).
    cases : indices, optional
        The cases drawn; default up to four spread over the sweep (first and last included).
    title : str, optional
        The figure's title (the legend sits below the panels, clear of it).

    Returns
    -------
    Path
        ``path_png`` (``dpi`` sets its resolution), written atomically.
    """
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    lines = bending_lines(sweep)
    chosen = _chosen_cases(len(sweep.cases), cases)
    figure = Figure(figsize=(13, 9.5), dpi=dpi, layout="constrained")
    grid = figure.add_gridspec(4, 1, height_ratios=[1.5, 2, 2, 2])
    strip = figure.add_subplot(grid[0])
    panels = [figure.add_subplot(grid[i], sharex=strip) for i in (1, 2, 3)]
    low = min(p.x_range_mm[0] for p in sweep.rig.parts)
    high = max(p.x_range_mm[1] for p in sweep.rig.parts)
    pad = 0.02 * (high - low)
    strip.set_xlim(low - pad, high + pad)
    colours = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"]
    for k, case_index in enumerate(chosen):
        _draw_case(panels, sweep, lines, case_index, colours[k % len(colours)])
    _draw_panel_frames(panels, sweep, lines)
    _strip(strip, sweep, lines)
    cases_legend = [Line2D([], [], color=colours[k % len(colours)], lw=1.6,
                           label=f"T1 = {sweep.cases[i].case.input_torque_Nm:g} N·m, "
                                 f"T2 = {sweep.cases[i].case.output_torque_Nm:g} N·m")
                    for k, i in enumerate(chosen)]
    kinds = [Line2D([], [], color="grey", lw=1.6, label="shaft"),
             Line2D([], [], color="grey", lw=0.9, ls="--", label="housing"),
             Line2D([], [], color="grey", lw=0.8, ls=":", label="rotation about y (x–z plane)"),
             Line2D([], [], color="#c44e52", marker="^", ls="none", label="bearing"),
             Line2D([], [], color="#55a868", marker="D", ls="none", label="coupling")]
    if any(line.solid for line in lines):
        kinds.append(Line2D([], [], color="grey", marker="o", ls="none", ms=3,
                            label="solid part: attachments (measured path: line)"))
    figure.legend(handles=cases_legend + kinds, loc="outside lower center", ncol=4, fontsize=8, frameon=False)
    measured = sweep.rig.paths.measured_from.replace("_", " ")
    figure.suptitle((title + "\n" if title else "") + f"bending line ({sweep.settings.model} model, measured from the "
                    f"{measured} state); rotation: about z (x–y plane) solid, about y dotted", fontsize=11)
    return write_png_atomic(path_png, figure)
