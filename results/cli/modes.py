"""``rvcoax modes``: the rig's natural frequencies and mode shapes, and where they meet its running speeds.

Writes OUT/modes.csv (the mode table), OUT/modes.json (the same with the notes, the interference crossings and
the part masses), OUT/modes_crossings.csv, OUT/modes_interference.png (with ``[speeds]``) and the mode-shape
pictures OUT/modes/mode_NN.png. See :mod:`rvcoax.results.studies.modes` for what is computed.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table

from rvcoax.results.cli import support

__all__ = ["COMMANDS", "modes", "write_mode_files"]

MODES_RANGE = (1, 100_000)  # the model refuses more than its DOFs with mass, naming how many it has
PICTURES_RANGE = (0, 100)


def _mass(value: float, study) -> str:
    """An effective mass, 0 where it is rounding (below 1e-9 of the rig's mass)."""
    return f"{value:.3g}" if value > 1e-9 * sum(study.part_mass_kg.values()) else "0"


def _table(study) -> Table:
    case = study.cases[0]
    table = Table(title=f"natural modes ({study.settings.model} model) — load case: {case.label}", title_justify="left")
    for column in ("mode", "f Hz", "class", "owner (strain energy)", "m_eff y kg", "m_eff z kg"):
        table.add_column(column, justify="right" if column not in ("class", "owner (strain energy)") else "left")
    for mode in case.modes:
        share = next(iter(mode.energy_share.values()), 0.0)
        table.add_row(str(mode.number), f"{mode.frequency_hz:.2f}", mode.kind, f"{mode.owner} {100 * share:.0f} %",
                      _mass(mode.effective_mass["y_kg"], study), _mass(mode.effective_mass["z_kg"], study))
    return table


def write_mode_files(study, out: Path, pictures: int, rig_source: str) -> list[Path]:
    """The mode table, its JSON, the crossings, the interference diagram and ``pictures`` mode pictures."""
    from rvcoax.results.io import plot_interference, render_mode, write_csv_atomic, write_json_atomic
    from rvcoax.results.studies import crossing_rows, mode_field, mode_rows

    rows = mode_rows(study)
    written = [write_csv_atomic(out / "modes.csv", rows)]
    rig = study.rig
    speeds = rig.speeds
    data = {"rig": rig.rig.name, "rig_file": rig_source, "model": study.settings.model,
            "n_dofs": study.system.n_dofs, "modes": rows, "crossings": crossing_rows(study),
            "notes": list(study.notes), "part_mass_kg": study.part_mass_kg,
            "housing_lowest_frequency_Hz": study.housing_limits_hz,
            "speeds": None if speeds is None else {"motor_rpm": list(speeds.motor_rpm),
                                                    "reduction_ratio": speeds.reduction_ratio,
                                                    "input_gear_teeth": speeds.input_gear_teeth},
            "seconds": study.seconds}
    written.append(write_json_atomic(out / "modes.json", data))
    if speeds is not None:
        written.append(write_csv_atomic(out / "modes_crossings.csv", crossing_rows(study)))
        frequencies = {c.label: [m.frequency_hz for m in c.modes] for c in study.cases}
        written.append(plot_interference(frequencies, study.orders, speeds.motor_rpm, study.crossings,
                                         path_png=out / "modes_interference.png",
                                         title=f"{rig.rig.name}: natural frequencies ({study.settings.model} model) "
                                               "and excitation orders"))
    bearings = [b.x_mm for b in rig.bearings]
    case = study.cases[0]
    for i, mode in enumerate(case.modes[:pictures]):
        mesh, u, twist = mode_field(study, 0, i)
        title = (f"mode {mode.number}: {mode.frequency_hz:.1f} Hz, {mode.kind} — {rig.rig.name} "
                 f"({study.settings.model} model): {case.label}")
        info = render_mode(mesh, u, twist, mode.kind, title=title,
                           path_png=out / "modes" / f"mode_{mode.number:02d}.png", bearings_x_mm=bearings)
        written.append(info["path"])
    return written


@support.model_options
@support.case_options
def modes(
    *,
    model_choice: support.ModelChoice,
    case_choice: support.CaseChoice,
    count: Annotated[int, support.number_option("--modes", *MODES_RANGE, help="How many of the lowest modes.",
                                                integer=True)] = 20,
    out: support.OutOption = Path("rvcoax_out"),
    pictures: Annotated[int, support.number_option("--pictures", *PICTURES_RANGE,
                                                   help="Mode-shape pictures to draw (the lowest modes).",
                                                   integer=True)] = 6,
    interference: Annotated[bool, typer.Option(
        "--interference/--no-interference",
        help="Require the interference diagram: fails when the rig file has no [speeds].")] = False,
    housing_dynamics: Annotated[str, typer.Option(
        "--housing-dynamics",
        help="How a \\[\\[housings]] entry with self_weight moves: auto (Craig–Bampton where its lowest fixed-interface "
             "mode is below 3 × the top rig frequency, else Guyan), craig-bampton, or guyan (static shapes).")]
    = "auto",
) -> None:
    """Natural frequencies and mode shapes of the rig about each load case's operating point, each mode's class
    and the part or spring that owns it, and the interference (Campbell) diagram against the motor speeds
    of the rig file's speeds section."""
    from rvcoax import modes as run

    settings = model_choice.settings()  # checks the options
    if settings.solver == "amg":
        raise support.UserError("--solver amg: an eigensolver needs an exact factorisation; use auto, superlu "
                                "or pardiso")
    from rvcoax.results.studies import HOUSING_DYNAMICS

    if housing_dynamics not in HOUSING_DYNAMICS:
        raise support.UserError(f"--housing-dynamics {housing_dynamics}: choose one of {', '.join(HOUSING_DYNAMICS)}")
    rig = model_choice.load_rig()
    if interference and rig.speeds is None:
        raise support.UserError("--interference: the rig file has no [speeds] (motor_rpm = [lowest, highest], "
                                "reduction_ratio, input_gear_teeth): the diagram needs the rig's speeds")
    load_cases = case_choice.load(rig) if case_choice.given else None
    with support.console.status(f"assembling the {settings.model} model and computing {count} modes"):
        study = run(rig, load_cases, n_modes=count, model=settings.model, solver=settings.solver,
                    mesh_size_mm=settings.mesh_size_mm, housing_dynamics=housing_dynamics)
    support.console.print(_table(study))
    for note in study.notes:
        support.console.print(f"note: {note}")
    if rig.speeds is None:
        support.console.print("no [speeds] in the rig file: no interference diagram (see docs/rig-keys.md)")
    else:
        inside = [c for c in study.crossings if c.inside]
        support.console.print(f"{len(inside)} crossing(s) of a mode with an excitation order inside "
                              f"{rig.speeds.motor_rpm[0]:g}–{rig.speeds.motor_rpm[1]:g} rpm (modes_crossings.csv)")
    source, _ = model_choice.rig_text()
    with support.console.status("writing the mode table and pictures"):
        written = write_mode_files(study, out, pictures, source)
    support.report_written(written)


COMMANDS = {"modes": modes}
"""The commands of this module, by name (:func:`rvcoax.results.cli.support.register_commands`)."""
