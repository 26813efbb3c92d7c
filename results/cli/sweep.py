"""``rvcoax sweep``: solve a torque sweep and write sweep.csv / sweep.json (resumable from its journal)."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape
from rich.table import Table

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results import case_text, reaction_sum, torque_path_warnings
from rvcoax.results.cli import support

__all__ = ["COMMANDS", "TABLE_ROWS", "sweep"]

TABLE_ROWS = 40  # a sweep table longer than this shows its first rows only (every case is in sweep.csv)

def _sweep_table(name: str, method: str, rows: list[dict]) -> Table:
    shown = rows[:TABLE_ROWS]
    more = (f"; first {len(shown)} shown, every case in sweep.csv" if len(rows) > len(shown) else "")
    table = Table(title=escape(f"{name}: {len(rows)} load case{'' if len(rows) == 1 else 's'} ({method}{more})"))
    for column in ("T1 N·m", "T2 N·m", "Y_in µm", "β_in (paper)", "tilt_in µrad", "x_max,in mm",
                   "Y_out µm", "β_out (paper)", "tilt_out µrad", "x_max,out mm"):
        table.add_column(column, justify="right")
    for row in shown:
        cells = [f"{row['T1_input_Nm']:g}", f"{row['T2_output_Nm']:g}"]
        for shaft in MEASURED_SHAFTS:
            cells += [f"{row[f'Y_{shaft}_mm'] * 1e3:.4g}",
                      f"{row[f'beta_{shaft}_deg']:.3g}° = {row[f'beta_{shaft}_deg'] * DEG_TO_URAD:.3g} µrad",
                      f"{row[f'fitted_tilt_{shaft}_deg'] * DEG_TO_URAD:+.3g}", f"{row[f'station_of_max_{shaft}_mm']:g}"]
        table.add_row(*cells)
    return table


DEG_TO_URAD = 1e6 * 3.141592653589793 / 180.0


def _percent(value) -> str:
    return "" if value is None else f"{value:.3g} %"


def _maybe_int(value) -> str:
    return "" if value is None else str(value)


def _maybe_g(value) -> str:
    return "" if value is None else f"{value:.4g}"


def _operating_table(where: str, bearings: list[dict]) -> Table:
    """The nonlinear bearings' operating point: axial force, stiffness (the tangent of their law) and rolling-element
    loads."""
    table = Table(title=escape(f"Bearing operating points at {where}: stiffness in this case (the tangent of a "
                               "bearing from geometry's or a clearance's law; a linear bearing's typed-in spring) and "
                               "rolling-element loads"),
                  title_justify="left")
    for column in ("bearing", "model", "axial force N", "k radial N/µm", "k axial N/µm", "k tilt N·m/rad",
                   "elements loaded", "largest element load N"):
        table.add_column(column, justify="left" if column in ("bearing", "model") else "right")
    for b in bearings:
        table.add_row(escape(b["name"]), b["model"], f"{b['force_axial_N']:.4g}", f"{b['radial_stiffness_N_per_um']:.3g}",
                      f"{b['axial_stiffness_N_per_um']:.3g}", f"{b['tilt_stiffness_Nm_per_rad']:.3g}",
                      _maybe_int(b["loaded_elements"]), _maybe_g(b["max_element_load_N"]))
    return table


def _engineering_tables(entry: dict) -> list[Table]:
    """The coupling, bearing and reaction tables of one case (from its ``sweep.json`` entry)."""
    tables = []
    where = case_text(entry["T1_input_Nm"], entry["T2_output_Nm"])
    couplings = entry["engineering"].get("couplings", [])
    if couplings:
        table = Table(title=escape(f"Couplings at {where}: misalignment of the to-hub against the from-hub "
                                   f"({couplings[0]['reference']})"), title_justify="left")
        for column in ("coupling", "rpm", "offset µm", "angle µrad", "angle mm/100 mm", "of allowable offset",
                       "of allowable angle", "alignment grade", "datasheet", "offset from unloaded µm",
                       "angle from unloaded µrad"):
            table.add_column(column, justify="left" if column in ("coupling", "alignment grade", "datasheet") else "right")
        for c in couplings:
            table.add_row(escape(c["name"]), "" if c["speed_rpm"] is None else f"{c['speed_rpm']:g}",
                          f"{c['offset_um']:.3g}", f"{c['angle_urad']:.3g}", f"{c['angularity_mm_per_100mm']:.2g}",
                          _percent(c["offset_use_percent"]), _percent(c["angle_use_percent"]),
                          c["grade"] or "(no speed_rpm)", c["datasheet_verdict"], f"{c['offset_from_unloaded_um']:.3g}",
                          f"{c['angle_from_unloaded_urad']:.3g}")
        tables.append(table)
    bearings = entry["engineering"].get("bearings", [])
    if bearings:
        table = Table(title=escape(f"Bearings at {where}: radial force on the shaft and tilt of the inner ring "
                                   "against the outer (total, and change under load)"), title_justify="left")
        for column in ("bearing", "x mm", "force N", "Δ force N", "tilt µrad", "Δ tilt µrad", "tilt ′",
                       "allowable ′", "of allowable", "verdict"):
            table.add_column(column, justify="left" if column in ("bearing", "verdict") else "right")
        for b in bearings:
            table.add_row(escape(b["name"]), f"{b['x_mm']:g}", f"{b['force_radial_N']:.4g}",
                          f"{b['force_radial_change_N']:.3g}", f"{b['tilt_urad']:.3g}", f"{b['tilt_change_urad']:.3g}",
                          f"{b['tilt_arcmin']:.2g}",
                          "" if b["allowable_tilt_arcmin"] is None else f"{b['allowable_tilt_arcmin']:g}",
                          _percent(b["tilt_use_percent"]), b["verdict"])
        tables.append(table)
        if any(b["model"] != "linear" for b in bearings):  # a linear bearing's stiffness is the rig file's
            tables.append(_operating_table(where, bearings))
    reactions = entry["engineering"].get("reactions", [])
    if reactions:
        table = Table(title=escape(f"Support reactions at {where}: force and moment each ground support exerts on "
                                   "its part (total, self-weight included; a housing as a whole, about the centre "
                                   "of its attachments)"), title_justify="left")
        for column in ("support", "kind", "part", "x mm", "Fx N", "Fy N", "Fz N", "Mx N·m", "My N·m", "Mz N·m"):
            table.add_column(column, justify="left" if column in ("support", "kind", "part") else "right")
        for r in reactions:
            table.add_row(escape(r["name"]), r["kind"], escape(r["part"]), f"{r['x_mm']:g}",
                          *[f"{v:.4g}" for v in r["force_N"]], *[f"{v:.4g}" for v in r["moment_Nm"]])
        total, torque = reaction_sum(reactions)
        table.add_row("sum", "", "", "", *[f"{v:.4g}" for v in total], f"{torque:.4g}", "", "", end_section=False)
        applied = entry["engineering"].get("applied_force_N", [0.0, 0.0, 0.0])
        table.add_row("− (weight and applied loads)", "", "", "", *[f"{-v + 0.0:.4g}" for v in applied],
                      f"{-entry['engineering'].get('applied_torque_x_Nm', 0.0) + 0.0:.4g}", "", "")
        tables.append(table)
    return tables


def _life(value) -> str:
    if value is None:
        return "–"
    return "> 1e9" if not value <= 1e9 else f"{value:.3g}"


def lives_and_reducer_tables(rig, records: list[dict], duty: list) -> list[Table]:
    """Per case and bearing: life, static safety and minimum-load status; per case and reducer: its check against
    the rating table; the duty-cycle lives; per case and rated coupling or shaft: its torque against its rating (the
    warnings: :func:`rvcoax.results.engineering.engineering_warnings`)."""
    from rvcoax.results import case_name, lives_of_records

    tables = []
    lives = [{**dataclasses.asdict(life), "minimum_load_status": life.minimum_load_status}
             for case in lives_of_records(records) for life in case]
    if lives:
        table = Table(title="Bearing life (ISO 281 L10 with the X/Y of its type and set; L10r ISO/TS 16281 from the element "
                            "loads where they are modelled), static "
                            "safety s0 and minimum load, per case", title_justify="left")
        for column in ("case", "bearing", "rpm", "P N", "L10 Mrev", "L10 h", "L10r h|Mrev", "Lnm h", "s0", "min load N",
                       "status"):
            table.add_column(column, justify="left" if column in ("case", "bearing", "status") else "right")
        for life in lives[:TABLE_ROWS]:
            table.add_row(escape(life["case"]), escape(life["name"]), "" if life["speed_rpm"] is None
                          else f"{life['speed_rpm']:g}", f"{life['equivalent_load_N']:.3g}", _life(life["L10_Mrev"]),
                          _life(life["L10_h"]),
                          _life(life["L10r_h"] if life["speed_rpm"] else life["L10r_Mrev"]), _life(life["Lnm_h"]),
                          _life(life["static_safety"]),
                          f"{life['minimum_load_N']:.3g}", life["minimum_load_status"])
        tables.append(table)
    if duty:
        table = Table(title="Bearing life over the duty cycle (Palmgren–Miner over the rig file's load cases)",
                      title_justify="left")
        for column in ("bearing", "shares", "L10 h", "L10 Mrev", "Lnm h", "smallest s0", "cases below minimum load"):
            table.add_column(column, justify="left" if column in ("bearing", "shares", "cases below minimum load")
                             else "right")
        for d in duty:
            table.add_row(escape(d.name), d.shares, _life(d.L10_h), _life(d.L10_Mrev), _life(d.Lnm_h),
                          _life(d.min_static_safety), escape("; ".join(d.cases_below_minimum_load)) or "none")
        tables.append(table)
    reducers = [(r["entry"], red) for r in records for red in r["entry"].get("engineering", {}).get("reducers", [])]
    if reducers:
        table = Table(title="Reducers against the maker's rating table, per case", title_justify="left")
        for column in ("case", "reducer", "torque N·m", "of rated", "of peak", "of momentary",
                       "moment N·m", "of allowable", "axial N", "of max axial", "verdict"):
            table.add_column(column, justify="left" if column in ("case", "reducer", "verdict") else "right")
        for entry, red in reducers[:TABLE_ROWS]:
            case = case_name(rig, entry["T1_input_Nm"], entry["T2_output_Nm"])
            table.add_row(escape(case), escape(red["name"]),
                          f"{red['torque_Nm']:.4g}", _percent(red["torque_rated_percent"]),
                          _percent(red["torque_peak_percent"]), _percent(red["torque_momentary_percent"]),
                          f"{red['moment_Nm']:.3g}", _percent(red["moment_use_percent"]), f"{red['axial_force_N']:.3g}",
                          _percent(red["axial_use_percent"]), red["verdict"])
        tables.append(table)
    rated = [(r["entry"], t) for r in records for t in r["entry"].get("engineering", {}).get("torque_ratings", [])]
    if rated:
        table = Table(title="Couplings and torque sensors against their rated torque, per case", title_justify="left")
        for column in ("case", "coupling or shaft", "torque N·m", "rated N·m", "of rated", "peak N·m", "of peak",
                       "verdict"):
            table.add_column(column, justify="left" if column in ("case", "coupling or shaft", "verdict") else "right")
        for entry, t in rated[:TABLE_ROWS]:
            table.add_row(escape(case_name(rig, entry["T1_input_Nm"], entry["T2_output_Nm"])),
                          escape(f"{t['kind']} {t['name']}"), f"{t['torque_Nm']:.4g}", f"{t['rated_torque_Nm']:g}",
                          _percent(t["rated_use_percent"]), "" if t["peak_torque_Nm"] is None
                          else f"{t['peak_torque_Nm']:g}", _percent(t["peak_use_percent"]), t["verdict"])
        tables.append(table)
    return tables


def _print_lives(rig, records: list[dict], duty: list) -> None:
    for table in lives_and_reducer_tables(rig, records, duty):
        support.console.print(table)


def _safety(value) -> str:
    return "∞" if value is None else f"{value:.3g}"


def _print_shaft_strength(rig, records: list[dict]) -> tuple[list[dict], list[dict]]:
    """One line with each shaft's largest von Mises stress over the cases; the notches' DIN 743 safety, the
    smallest over the cases with the case named (the spectrum's simplification: the worst case as nominal load)."""
    from rvcoax.results import strength_of_records

    shafts, notches = strength_of_records(rig, records)
    solid = {name for r in records
             for name in r["entry"].get("engineering", {}).get("shaft_strength", {}).get("shafts_modelled_as_solids", [])}
    if solid:
        support.console.print("Shafts modelled as solids have no beam section forces: no shaft stresses or DIN 743 "
                              f"check for {escape(', '.join(sorted(solid)))} (run --model beam for them).")
    if shafts:
        support.console.print("Shaft stresses (von Mises, largest over the cases): " + "; ".join(
            f"{escape(s['shaft'])} {s['von_mises_max_MPa']:.3g} MPa at x = {s['x_mm']:g} mm ({escape(s['case'])})"
            for s in shafts))
    if notches:
        table = Table(title="Shaft notches, DIN 743: the smallest safety over the cases (required S_min = "
                            f"{rig.shaft_strength.minimum_safety:g})", title_justify="left")
        for column in ("shaft", "notch", "x mm", "S_D fatigue", "S_D case", "S_F static", "S_F case", "verdict"):
            table.add_column(column, justify="right" if column in ("x mm", "S_D fatigue", "S_F static") else "left")
        for n in notches:
            table.add_row(escape(n["shaft"]), n["kind"], f"{n['x_mm']:g}", _safety(n["fatigue_safety"]),
                          escape(n["fatigue_case"] or "–"), _safety(n["static_safety"]), escape(n["static_case"] or "–"),
                          n["verdict"])
            if n["verdict"] != "ok":
                support.warn(f"shaft {n['shaft']}: the {n['kind']} at x = {n['x_mm']:g} mm is below S_min = "
                             f"{n['minimum_safety']:g} (S_D {_safety(n['fatigue_safety'])} in {n['fatigue_case']}, "
                             f"S_F {_safety(n['static_safety'])} in {n['static_case']}, DIN 743)")
        support.console.print(table)
    return shafts, notches


def _print_engineering(records: list[dict]) -> None:
    """The engineering tables of the case with the largest |T2| (the last such case)."""
    entries = [r["entry"] for r in records if "couplings" in r["entry"].get("engineering", {})]
    if not entries:
        return
    entry = max(reversed(entries), key=lambda e: abs(e["T2_output_Nm"]))
    for table in _engineering_tables(entry):
        support.console.print(table)
    residual = entry["engineering"]["equilibrium_residual"]
    support.console.print(f"Equilibrium residual (applied loads + reactions): {residual['force_N']:.2g} N, "
                          f"{residual['moment_Nm']:.2g} N·m. Every case's tables are in sweep.csv and sweep.json.")


def _solve_sweep(rig, load_cases, settings, text: str, store, *, resume: bool):
    """:func:`rvcoax.results.io.durable_sweep.run_durable_sweep` with the resume messages and a progress bar.

    Returns (records of every case in order, the ``model`` section, the Sweep of the cases solved now
    or None when every case was reused).
    """
    from rvcoax import run_durable_sweep

    def plan(reading, n_missing: int, n_checked: int) -> None:
        if resume:
            support.console.print(f"resuming: {len(reading.cases)} of {len(load_cases)} case(s) already solved in "
                                  f"{escape(str(store.folder))}, {n_missing} to solve")
            if reading.journal_problem:
                support.warn(f"{store.path}: {reading.journal_problem} (a FIFO, device or link is not read as a "
                             "journal); every case is solved again and the journal written anew")
            if reading.rejected:
                support.console.print(f"not reused from {escape(str(store.path))} (solved again): "
                                      f"{reading.describe_rejections()}")
            if n_checked:
                how = ("every reused case (a linear sweep: one back-substitution each)" if n_checked == len(reading.cases)
                       else f"{n_checked} reused case(s) as a spot check (nonlinear: a Newton solve each)")
                support.console.print(f"checking the journal: {how} solved again and compared")

    live = {}  # the progress bar starts with the first solved case, after the model's own status line

    def progress(i: int, n: int) -> None:
        if "bar" not in live:
            live["bar"] = support.progress_bar()
            live["bar"].start()
            live["task"] = live["bar"].add_task("solving load cases", total=n)
        live["bar"].update(live["task"], completed=i)

    try:
        done = run_durable_sweep(rig, load_cases, settings, text, store, resume=resume,
                                 prepare=support.prepare_with_status, on_plan=plan, progress=progress)
    finally:
        if "bar" in live:
            live["bar"].stop()
    if done.disagreed:
        support.warn(f"{store.path}: {len(done.disagreed)} of {len(done.checked)} reused case(s) differ from a new "
                     f"solve (cases {', '.join(str(i + 1) for i in done.disagreed[:10])}"
                     f"{', …' if len(done.disagreed) > 10 else ''}): the journal was edited or written by something "
                     "else; the values solved now are written")
    elif done.checked:
        support.console.print(f"checked: {len(done.checked)} reused case(s) agree with a new solve")
    return done.records, done.model, done.sweep


@support.model_options
@support.case_options
def sweep(
    *,
    model_choice: support.ModelChoice,
    case_choice: support.CaseChoice,
    out: support.OutOption = Path("rvcoax_out"),
    method: Annotated[str, typer.Option("--method", help="superposition (of unit responses, default) or direct (solve each case).")] = "superposition",
    fields: Annotated[bool, typer.Option("--fields", help="Also write the full displacement fields: one .vtu per case and an .xdmf time series (open in ParaView).")] = False,
    resume: Annotated[bool, typer.Option("--resume", help="Reuse the cases an interrupted sweep already journalled in OUT/cases (same rig file, torques and settings, checksum verified) and solve only the others.")] = False,
) -> None:
    r"""Solve a torque sweep and write sweep.csv / sweep.json.

    Load cases: --cases or --t1/--t2; else the rig file's \[\[load_cases]] or \[sweep]; else, for the
    built-in reference rig only, the 20 (T1, T2) pairs of paper 000.

    Each case is appended to OUT/cases/journal.jsonl (with a checksum) as soon as it is solved; after
    an interruption, the same command with --resume solves only the missing cases and writes the same
    files.
    """
    from rvcoax.geometry.model import REPORT_AFTER_S, sweep_workload
    from rvcoax.results.io import CaseStore, sweep_header, write_sweep_files

    if resume and fields:
        raise support.UserError("--fields needs every case's displacement field, which --resume does not keep: "
                        "run without --resume")
    settings = model_choice.settings(method)
    rig = model_choice.load_rig()
    load_cases = case_choice.load(rig, model_choice.rig_file)
    work = sweep_workload(len(load_cases))
    if work.seconds > REPORT_AFTER_S:
        support.console.print(f"{work.what}: {work.describe()} (estimated)")
    source, text = model_choice.rig_text()
    records, model_section, result = _solve_sweep(rig, load_cases, settings, text, CaseStore(out / "cases"),
                                                  resume=resume)
    if fields:
        support.report_written(_write_fields(out / "fields", result))
    shown = "nonlinear: each case by Newton" if model_section.get("nonlinear") else method  # not superposed
    support.console.print(_sweep_table(rig.rig.name, shown, [r["row"] for r in records]))
    support.console.print("β (paper) = arcsin(Y_max / L), paper 000's definition; tilt = slope of the least-squares "
                          "line through u_y(x), the shaft's true tilt.")
    _print_engineering(records)
    from rvcoax.results import duty_cycle_of_records, engineering_warnings

    duty = duty_cycle_of_records(rig, records)
    _print_lives(rig, records, duty)
    strength = _print_shaft_strength(rig, records)
    for line in engineering_warnings(rig, [r["entry"] for r in records],
                                     {**model_section.get("ball_bearing_operating_points", {}),
                                      **model_section.get("rolling_bearing_operating_points", {})}):
        support.warn(line)
    for line in torque_path_warnings([r["entry"] for r in records]):
        support.warn(line)
    if model_section.get("nonlinear"):
        nonlinear = (model_section["gapped_bearings"] + model_section.get("ball_bearings", [])
                     + model_section.get("rolling_bearings", []))
        how = f"each case solved on its own ({model_section['nonlinear']}: {', '.join(nonlinear)})"
    elif method == "superposition":
        how = ("each case built from unit responses (self-weight, force table, engaged load sharing, "
               "T1 = 1 N·m, T2 = 1 N·m)")
    else:
        how = "each case solved directly"
    support.console.print(f"Y measured from: {rig.paths.measured_from}; {how}")
    header = sweep_header(rig, model_section, source, text)
    if duty:
        header = {**header, "bearing_duty_cycle": [{k: list(v) if isinstance(v, tuple) else v
                                                    for k, v in dataclasses.asdict(d).items()} for d in duty]}
    if strength[1]:
        header = {**header, "shaft_notches_worst_case": strength[1]}
    support.report_written(write_sweep_files(out, "sweep", header, records))


def _write_fields(folder: Path, result) -> list[Path]:
    from rvcoax.results.io import sweep_field_cases, sweep_field_mesh, write_vtu, write_xdmf_series

    mesh, _ = sweep_field_mesh(result)
    cases = sweep_field_cases(result)
    written = [write_vtu(folder / f"case_{i:02d}.vtu", mesh, case) for i, case in enumerate(cases)]
    written += list(write_xdmf_series(folder / "sweep.xdmf", mesh, cases).values())
    return written


COMMANDS = {"sweep": sweep}
"""The commands of this module, by name (:func:`rvcoax.results.cli.support.register_commands`)."""
