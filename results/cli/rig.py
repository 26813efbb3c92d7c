"""``rvcoax rig show`` and ``rvcoax rig reference``: inspect rig files."""

from __future__ import annotations

import sys
from typing import Annotated

import typer
from rich.markup import escape
from rich.table import Table

from rvcoax.results.cli.support import (
    CommandGroup,
    RigOption,
    UserError,
    add_text_row,
    console,
    warn,
)

__all__ = ["COMMANDS", "rig_example", "rig_reference", "rig_show"]

def rig_show(rig_file: RigOption = None) -> None:
    """A readable table of the rig: parts with their modelled mass, supports, couplings, torque paths."""
    from rvcoax import load_rig
    from rvcoax.geometry.model import build_rig_model

    rig = load_rig(rig_file)
    frame = build_rig_model(rig)
    parts = Table(title=escape(f"{rig.rig.name}: parts (x along the drivetrain, mm)"), title_justify="left")
    for column in ("part", "role", "x from", "x to", "Ø outer mm", "material", "E GPa", "density kg/m³", "mass kg"):
        parts.add_column(column)
    for p in rig.parts:
        lo, hi = p.x_range_mm
        diameters = sorted({s.outer_diameter_mm for s in p.segments})
        material = rig.materials[p.material]
        density = frame.equivalent_density.get(p.name, material.density_kg_per_m3)
        add_text_row(parts, p.name, p.role, f"{lo:g}", f"{hi:g}", "/".join(f"{d:g}" for d in diameters), p.material,
                      f"{material.youngs_modulus_MPa / 1e3:g}",
                      f"{density:.0f}" + (" (equiv.)" if p.name in frame.equivalent_density else ""),
                      f"{frame.part_mass_kg[p.name]:.3f}")
    console.print(parts)
    console.print(f"total mass {sum(frame.part_mass_kg.values()):.2f} kg; beam model: {frame.structure.n_nodes} nodes, "
                  f"{frame.structure.n_dofs} DOF")
    _print_springs(rig)
    _print_seat_table(rig)
    _print_torque_paths(rig)
    if rig.thermal is not None:
        from rvcoax.geometry import free_axial_growth_um, mount_lift_um

        grows = [f"{name} {free_axial_growth_um(rig, name):.1f}" for name in rig.thermal.temperature_rise_K]
        lifts = [f"{m.name} {mount_lift_um(rig, m):.1f}" for m in rig.mounts if mount_lift_um(rig, m)]
        console.print(f"temperatures: free axial growth µm: {', '.join(grows) or 'none'}; support lifts µm: "
                      f"{', '.join(lifts) or 'none'}")
    console.print(f"gravity: {'on' if rig.gravity.enabled else 'off'}; paper force table applied: "
                  f"{rig.force_table.apply}; Y measured from: {rig.paths.measured_from}; paths: input "
                  f"{rig.paths.input.part} {rig.paths.input.x_start_mm:g} + {rig.paths.input.length_mm:g} mm, "
                  f"output {rig.paths.output.part} {rig.paths.output.x_start_mm:g} + "
                  f"{rig.paths.output.length_mm:g} mm")
    _warn_as_a_solve_does(rig)


def _print_springs(rig) -> None:
    """The table of supports and connections: bearings, mounts, housings, couplings, joints."""
    springs = Table(title="Supports and connections", title_justify="left")
    for column in ("kind", "name", "between", "x mm", "stiffness"):
        springs.add_column(column)
    for b in rig.bearings:
        if b.model == "ball":
            from rvcoax.geometry import clearance_um_of, geometry_of

            g = geometry_of(b)
            stiffness = (f"ball bearing {b.designation or ''} ({g.ball_count} × Ø{g.ball_diameter_m * 1e3:.3f} mm), "
                         f"clearance {clearance_um_of(b):g} µm, preload {b.preload_N:g} N: nonlinear")
        elif b.model != "linear":
            kind = {"angular_contact": "angular-contact ball bearing", "cylindrical_roller": "cylindrical roller bearing",
                    "tapered_roller": "tapered roller bearing"}[b.model]
            arrangement = "" if b.arrangement == "single" else f" {b.arrangement} pair"
            rings = (f"{b.preload_class} preload" if b.preload_class else f"preload {b.preload_N:g} N" if b.preload_N
                     else f"axial offset {b.axial_offset_um:g} µm" if b.axial_offset_um is not None
                     else f"clearance {b.clearance_um:g} µm" if b.clearance_um is not None
                     else f"clearance {b.clearance_class}" if b.clearance_class else "")
            stiffness = (f"{kind} {b.designation or ''}{arrangement}" + (f", {rings}" if rings else "")
                         + ": from geometry, nonlinear")
        else:
            stiffness = f"radial {b.radial_stiffness_N_per_um:g} N/µm, axial {b.axial_stiffness_N_per_um:g} N/µm"
        add_text_row(springs, "bearing", b.name, f"{b.shaft} / {b.housing}", f"{b.x_mm:g}", stiffness)
    for m in rig.mounts:
        add_text_row(springs, "mount", m.name, f"{m.part} / ground", f"{m.x_mm:g}",
                        f"{list(m.translational_stiffness_N_per_um)} N/µm, {list(m.rotational_stiffness_Nm_per_rad)} N·m/rad")
    for h in rig.housings:
        bore = f", bore Ø{h.bore_diameter_mm:g}" if h.bore_diameter_mm else ""
        add_text_row(springs, "housing", h.name, f"{h.part} / ground", "/".join(f"{x:g}" for x in h.attachments_x_mm),
                     f"condensed from a {h.material} {h.shape}, seat {h.x_mm[1] - h.x_mm[0]:g} × {h.width_mm:g} mm"
                     f"{bore}, {_housing_reach(h)}, {_housing_feet(h)}, mesh "
                     f"{h.mesh_size_mm:g} mm (× {h.stiffness_factor:g}); computed when solved, then cached")
    for c in rig.couplings:
        add_text_row(springs, "coupling", c.name, f"{c.from_.part} / {c.to.part}", f"{c.centre_x_mm:g}",
                        f"radial {c.radial_stiffness_N_per_mm:g} N/mm, angular {c.angular_stiffness_Nm_per_rad:g} N·m/rad, "
                        f"torsional {c.torsional_stiffness_Nm_per_rad:g} N·m/rad; {c.mass_kg:g} kg")
    for j in rig.joints:
        add_text_row(springs, "joint", j.name, f"{j.from_.part} / {j.to.part}", f"{j.to.x_mm:g}",
                        f"{list(j.translational_stiffness_N_per_um)} N/µm, {list(j.rotational_stiffness_Nm_per_rad)} N·m/rad")
    console.print(springs)


def _print_torque_paths(rig) -> None:
    """The table of how torque becomes a lateral load: the torque-to-load table and the gear meshes."""
    import numpy as np

    from rvcoax.geometry.model import gear_mesh_forces

    paths = Table(title="How torque becomes a lateral load", title_justify="left")
    for column in ("name", "torque", "kind", "acts on", "N per N·m", "engaged force N", "direction °"):
        paths.add_column(column)
    for t in rig.torque_lateral_loads:
        add_text_row(paths, t.name, t.torque, t.kind, f"{t.on.part} @ {t.on.x_mm:g}", f"{t.force_per_torque_N_per_Nm:.4g}",
                      f"{t.engaged_force_N:.4g}", f"{t.direction_deg:g}")
    for g in rig.gear_meshes:
        per_torque, engaged, _ = gear_mesh_forces(rig, g)
        lateral = per_torque.force_N[1:]
        add_text_row(paths, g.name, g.torque, "gear mesh (from gear data)", f"{g.on.part} @ {g.on.x_mm:g}",
                     f"{float(np.hypot(*lateral)):.4g}", f"{float(np.hypot(*engaged.force_N[1:])):.4g}",
                     f"{np.degrees(np.arctan2(lateral[1], lateral[0])):.4g}" if np.any(lateral) else "-")
    console.print(paths)


def _print_seat_table(rig) -> None:
    from rvcoax.results.cli.support import condense_housings

    if rig.housings:
        condense_housings(rig)  # the sag check a solve makes (printed below) needs them condensed anyway
        console.print(_seat_table(rig))


def _warn_as_a_solve_does(rig) -> None:
    """The plausibility and sag warnings a solve of ``rig`` prints (rig show solves nothing)."""
    from rvcoax.geometry import plausibility_warnings
    from rvcoax.geometry.model import sag_warnings

    for message in plausibility_warnings(rig) + sag_warnings(rig):
        warn(message)


def _seat_table(rig) -> Table | str:
    """The stiffness a bearing sees at each seat of each condensed housing, in the load patterns that occur; the
    housings not condensed yet (before the first solve) are named instead."""
    from rvcoax.geometry.model import housing_condensation, seat_stiffness

    table = Table(title="Condensed housings: stiffness at the bearing seats, N/µm (the factor stiffness_factor "
                        "applied)", title_justify="left")
    for column in ("housing", "seat x mm", "direction", "both seats pushed together", "this seat alone",
                   "held (diagonal of K_c)"):
        table.add_column(column, justify="left" if column in ("housing", "direction") else "right")
    waiting = []
    for housing in rig.housings:
        condensed = housing_condensation(rig, housing, compute=False)
        if condensed is None:
            waiting.append(housing.name)
            continue
        for seat in seat_stiffness(housing, condensed.matrix):
            add_text_row(table, housing.name, f"{seat.seat_x_mm:g}", seat.direction, f"{seat.together_N_per_um:.4g}",
                         f"{seat.alone_N_per_um:.4g}", f"{seat.held_N_per_um:.4g}")
    if waiting:
        note = (f"housing(s) {', '.join(waiting)}: condensed at the first solve (rvcoax sweep), about a minute for "
                "an 8 mm mesh; rig show then prints their stiffness at the seats")
        if not table.rows:
            return escape(note)
        table.caption = escape(note)
    table.caption = ((table.caption + "; ") if table.caption else "") + (
        "together: the force per seat when every seat of the housing is pushed the same way (a shaft's weight, a "
        "lateral gear force); alone: one seat loaded, the other free; held: the other seat and all rotations held, "
        "an upper bound no bearing sees. The bearing is in series with these.")
    return table


def rig_reference(
    variant: Annotated[str | None, typer.Option(
        help="A variant of the reference rig: ball_bearings (the input 6204 and output 6206 shaft bearings as "
             "deep-groove ball bearings from their internal geometry, CN clearance, solved nonlinearly); "
             "rolling_bearings (the input shaft on a 7204 B DB pair and an NU 204, the output shaft on two 30206 "
             "tapered roller bearings with end play, from internal geometry); "
             "catalogue_reducer (the RV-20E's main bearings and output from the reducer catalogue instead of the "
             "assumed joint)")] = None,
) -> None:
    """Print the built-in reference rig file (copy it to start your own)."""
    from rvcoax import reference_rig_text
    from rvcoax.geometry import REFERENCE_VARIANTS

    if variant is not None and variant not in REFERENCE_VARIANTS:
        raise UserError(f"--variant '{variant}': not a variant of the reference rig (known: "
                        f"{', '.join(REFERENCE_VARIANTS)}; leave --variant out for the reference rig itself)")
    sys.stdout.write(reference_rig_text(variant))


def rig_example() -> None:
    """Print the built-in example rig of another layout (RV-40E bench, one torque sensor, 260 mm output shaft, hysteresis brake, its own load cases)."""
    from rvcoax import example_rig_text

    sys.stdout.write(example_rig_text())


def _housing_reach(housing) -> str:
    """How far the housing carries the axis: above the bed, or out from the wall."""
    if housing.shape == "bracket":
        return f"axis {housing.wall_distance_mm:g} mm from the wall"
    return f"axis {housing.height_above_bed_mm:g} mm above the bed"


def _housing_feet(housing) -> str:
    """How the housing's feet are held, and whether its own weight loads the rig."""
    if housing.feet == "bed":
        feet = f"feet on a bed of {housing.bed_stiffness_N_per_um_per_mm2:g} N/(µm·mm²)"
    elif housing.feet == "springs":
        feet = f"feet on springs of {housing.foot_stiffness_N_per_um:g} N/µm each"
    else:
        feet = "feet clamped"
    return feet + (", its own weight included" if housing.self_weight else "")


COMMANDS = {"rig": CommandGroup("Inspect rig files.", {"show": rig_show, "reference": rig_reference,
                                                       "example": rig_example})}
"""The commands of this module, by name (:func:`rvcoax.results.cli.support.register_commands`)."""
