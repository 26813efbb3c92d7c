"""The report's section on the rig's dynamics: the mode table, the interference diagram with its crossings, and
mode-shape pictures, from a :class:`rvcoax.results.studies.modes.ModalStudy`."""

from __future__ import annotations

import html
from pathlib import Path

from rvcoax.results.reports.report_tables import Table, _g

__all__ = ["MODE_PICTURES", "modes_section_html"]

MODE_PICTURES = 4  # mode-shape pictures in the report (the lowest modes)


def _mode_table(study) -> Table:
    case = study.cases[0]
    total = sum(study.part_mass_kg.values())
    rows = []
    for mode in case.modes:
        owners = [item for k, item in enumerate(mode.energy_share.items()) if k == 0 or item[1] >= 0.005][:2]
        rows.append((str(mode.number), _g(mode.frequency_hz), mode.kind,
                     "; ".join(f"{name} {100 * share:.0f} %" for name, share in owners),
                     *(_g(v) if v > 1e-9 * total else "0" for v in (mode.effective_mass["y_kg"],
                                                                    mode.effective_mass["z_kg"],
                                                                    mode.effective_mass["x_kg"]))))
    label = case.label if len(study.cases) == 1 else f"{case.label} (the first of {len(study.cases)}; all in modes.csv)"
    return Table(f"Natural modes, {study.settings.model} model — load case: {label}",
                 ("mode", "f Hz", "class", "strain energy: owner, next", "m_eff y kg", "m_eff z kg", "m_eff x kg"),
                 tuple(rows),
                 note="Class: the direction holding at least 60 % of the mode's kinetic energy (axial u_x; lateral "
                      "vertical u_y with θz; lateral horizontal u_z with θy; torsional θx), else mixed. Owner: the "
                      "part or spring storing the largest share of the mode's strain energy. m_eff: effective modal "
                      "mass (φᵀ M r)² with φ mass-normalised and r a rigid translation of the whole rig.")


def _crossing_table(study) -> Table:
    rows = tuple((c.case, str(c.mode), _g(c.frequency_hz), c.order, _g(c.crossing_rpm),
                  "inside the range" if c.inside else f"{c.margin_percent:.1f} % above")
                 for c in study.crossings)
    low, high = study.rig.speeds.motor_rpm
    return Table(f"Crossings of natural frequencies with excitation orders (motor {low:g}–{high:g} rpm)",
                 ("load case", "mode", "f Hz", "order", "crossing motor speed rpm", "margin"), rows,
                 note="Crossing speed n = 60 f / order; margin: 0 inside the speed range, else the distance above "
                      "its top speed (listed up to 25 % above it). Gyroscopic effects neglected: see the notes.")


def modes_section_html(study, folder: Path, table_html, png_uri) -> str:
    """The section's HTML body: notes, mode table, interference diagram and crossings, mode pictures.

    Parameters
    ----------
    study : ModalStudy
    folder : Path
        Where the pictures are drawn before they are embedded.
    table_html, png_uri : callable
        The report's own table renderer and picture embedder.

    Returns
    -------
    str
    """
    from rvcoax.results.io.mode_pictures import plot_interference, render_mode
    from rvcoax.results.io.pictures import RenderingUnavailableError
    from rvcoax.results.studies.modes import mode_field

    parts = [table_html(_mode_table(study))]
    parts.append('<p class="note">' + "<br>".join(html.escape(n) for n in study.notes) + "</p>")
    rig = study.rig
    if rig.speeds is not None:
        frequencies = {c.label: [m.frequency_hz for m in c.modes] for c in study.cases}
        png = plot_interference(frequencies, study.orders, rig.speeds.motor_rpm, study.crossings,
                                path_png=folder / "interference.png",
                                title=f"{rig.rig.name}: natural frequencies and excitation orders")
        parts.append(f'<h3>Interference diagram</h3><img alt="interference diagram" src="{png_uri(png)}">')
        parts.append(table_html(_crossing_table(study)))
    else:
        parts.append('<p class="missing">The rig file has no [speeds] (motor_rpm, reduction_ratio, '
                     "input_gear_teeth): no interference diagram.</p>")
    case = study.cases[0]
    pictures = []
    try:
        for i, mode in enumerate(case.modes[:MODE_PICTURES]):
            mesh, u, twist = mode_field(study, 0, i)
            title = f"mode {mode.number}: {mode.frequency_hz:.1f} Hz, {mode.kind} ({case.label})"
            info = render_mode(mesh, u, twist, mode.kind, title=title, path_png=folder / f"mode_{mode.number:02d}.png",
                               bearings_x_mm=[b.x_mm for b in rig.bearings])
            pictures.append(f'<img alt="mode {mode.number}" src="{png_uri(info["path"])}">')
    except RenderingUnavailableError as error:
        pictures.append(f'<p class="missing">Mode-shape pictures unavailable: {html.escape(str(error))}</p>')
    parts.append("<h3>Mode shapes</h3>" + "".join(pictures))
    return "\n".join(parts)
