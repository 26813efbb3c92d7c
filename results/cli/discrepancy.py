"""``rvcoax discrepancy``: which physical effect is the model missing?"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape
from rich.table import Table

from rvcoax.results.cli.support import (
    ModelOption,
    OutOption,
    RigOption,
    UserError,
    console,
    number_option,
    progress_bar,
    rig_text,
    sweep_settings,
)

__all__ = ["COMMANDS", "discrepancy"]


def _print_result(result, lengths_mm) -> None:
    from rvcoax.results.studies.discrepancy import engineering_summary, rms_table

    message = {"no_gap": "[bold green]VERDICT: no gap beyond the noise; nothing added[/]",
               "explained": "[bold green]VERDICT: explained[/] (the remaining gap is consistent with the noise, and "
                            "held-out load cases improve)",
               "unexplained": "[bold red]VERDICT: unexplained[/] (what is named below reduces the gap but does not "
                              "explain it)"}[result.verdict]
    console.print(message)
    for line in engineering_summary(result, lengths_mm):
        console.print(f"  {escape(line)}")
    shown: dict[str, int] = {}
    for d in result.discriminations:  # the three closest look-alikes of each named effect (all are in the JSON)
        shown[d.effects[0]] = shown.get(d.effects[0], 0) + 1
        if shown[d.effects[0]] > 3:
            continue
        console.print(f"  to tell {d.effects[0]} from {d.effects[1]}: measure u_y on the {d.shaft} shaft at x = "
                      f"{d.x_mm:.0f} mm with T1 = {d.case.input_torque_Nm:.3g}, T2 = {d.case.output_torque_Nm:.3g} N·m"
                      + (" (a new load case)" if d.new_case else "")
                      + (" (Y from the unloaded geometry)" if d.other_datum else "")
                      + f": they differ by {1e3 * abs(d.difference_mm):.3g} µm ({d.in_sigma:.2g} σ)")
    visible = sorted(n for n, v in result.observability.items() if v.visible)
    hidden = {n: v for n, v in result.observability.items() if not v.visible}
    if result.observability:
        console.print(f"what these data can reveal: {len(visible)} of {len(result.observability)} effects: "
                      + escape(", ".join(visible)))
        revealable = {n: v for n, v in hidden.items() if v.suggestion is not None and v.suggestion.in_sigma >= 3}
        console.print(f"cannot reveal {len(hidden)} effects; {len(revealable)} of them with one more measurement:")
        for name, v in sorted(revealable.items()):
            console.print(f"  {escape(name)}: {escape(v.suggestion.sentence())}")
        rest = sorted(set(hidden) - set(revealable))
        if rest:
            console.print("  too small on this rig for any measurement considered: " + escape(", ".join(rest)))
    for group in result.parallel_groups:
        console.print("look-alikes on these data (nearly parallel signatures): " + escape(", ".join(group)))
    if result.sentinel is not None:
        s = result.sentinel
        console.print(f"out-of-vocabulary sentinel: {escape(s.describe())} (χ² {s.chi2:.4g} with {s.k} parameters"
                      + (f"; the vocabulary: χ² {result.vocabulary_chi2:.4g} with "
                         f"{sum(len(e.values) for e in result.selected)}" if result.vocabulary_chi2 is not None else "")
                      + ")")
    for label, cv in (("vocabulary", result.cross_validation), ("sentinel", result.sentinel_cross_validation)):
        if cv is not None:
            console.print(f"cross-validation over load cases ({label}): held-out χ² {cv.chi2_before:.4g} → "
                          f"{cv.chi2_after:.4g} on {cv.n} observations in {cv.folds} folds"
                          + ("" if cv.improves else " [bold red](does not improve)[/]"))
    console.print("[bold]statistics[/]")
    console.print(f"  measured data: {escape(str(result.data.source))} ({result.data.schema}, {result.data.n} "
                  f"observations in {len(result.data.cases)} load cases, {int((~result.fit_mask).sum())} held out)")
    for shaft, sigma in result.noise.noise_mm.items():
        console.print(f"  noise σ {shaft}: {1e3 * sigma:.4g} µm ({result.noise.method[shaft]})")
    console.print(f"  before: {result.test_before.describe()}")
    for finding in (f for f in result.structure if f.significant):
        console.print(f"    {finding.shaft} shaft: {finding.test}: {escape(finding.detail)}")
    for step in result.steps:
        table = Table(title=f"candidates ranked by ΔBIC (step adding {step.added})", title_justify="left")
        table.add_column("effect")
        table.add_column("ΔBIC", justify="right")
        for name, gain in step.ranking:
            table.add_row(name + (" *" if name in step.group else ""), f"{gain:.1f}")
        console.print(table)
    for selected in result.selected:
        effect = result.effects[selected.name]
        values = ", ".join(f"{p.name} = {v:.4g} {p.unit}" for p, v in zip(effect.parameters, selected.values))
        console.print(f"  added: {selected.name} ({values}; ΔBIC {selected.delta_bic:.1f}; "
                      + ("confident" if selected.confident else "not a confident single name") + ")")
    if result.rejected:
        console.print(f"  rejected (outside physical bounds): {len(result.rejected)}; e.g. "
                      + escape(next(iter(result.rejected.values()))))
    for name, reason in result.set_aside.items():
        console.print(f"  set aside (cannot be solved): {escape(name)}: {escape(reason)}")
    table = Table(title="RMS gap, measured − model", title_justify="left")
    for column in ("cases", "shaft", "before µm", "after µm", "before µrad", "after µrad"):
        table.add_column(column, justify="right")
    for subset, values in rms_table(result, lengths_mm).items():
        for shaft in values["rms_before_um"]:
            table.add_row(subset, shaft, f"{values['rms_before_um'][shaft]:.4g}", f"{values['rms_after_um'][shaft]:.4g}",
                          f"{values['rms_tilt_before_urad'].get(shaft, float('nan')):.4g}",
                          f"{values['rms_tilt_after_urad'].get(shaft, float('nan')):.4g}")
    console.print(table)
    console.print(f"  after: {result.test_after.describe()}")


def discrepancy(
    measured: Annotated[Path, typer.Option("--measured", help="Measured data CSV: table (T1_input_Nm, T2_output_Nm, "
                                                              "Y_input_mm, Y_output_mm) or paths (T1_input_Nm, "
                                                              "T2_output_Nm, shaft, x_mm, uy_mm[, sigma_mm]).")],
    rig_file: RigOption = None,
    out: OutOption = None,
    model: ModelOption = "beam",
    hold_out_every: Annotated[int, number_option("--hold-out-every", 0, 1000, integer=True, help="Hold out every "
                                                 "N-th load case (by torque) from the fit and report the gap on "
                                                 "it; 0: fit on all.")] = 3,
    model_form_percent: Annotated[float, number_option("--model-form-percent", 0.0, 50.0, "%", help="Model-form "
                                                       "allowance added to the noise, in % of the signal.")] = 2.0,
    alpha: Annotated[float, number_option("--alpha", 0.0, 0.5, exclusive=True,
                                          help="Significance level of the χ² tests, in (0, 0.5).")] = 0.01,
    margin: Annotated[float, number_option("--margin", 0.0, 1000.0, help="ΔBIC an effect must gain to be "
                                           "added, 0 … 1000.")] = 10.0,
    effects: Annotated[str | None, typer.Option("--effects", help="Comma-separated effect kinds or names to "
                                               "consider (default: the whole library).")] = None,
) -> None:
    """Locate where model and measurement disagree, name the missing effect, add it, show the gap shrink.

    Before fitting it reports which effects the data can see and what measurement would reveal the
    others; it groups look-alike effects, fits a generic out-of-vocabulary load next to the
    vocabulary, and checks every verdict on held-out load cases. Writes (with --out):
    discrepancy.json, discrepancy_observations.csv, discrepancy.png and rig_updated.toml (explained:
    the rig with the effects added, each with a provenance comment) or rig_candidate.toml
    (unexplained: not a fix). Exit status 0 when there is no gap or the gap is explained, 1 when a
    discrepancy remains.
    """
    from rvcoax import DiscrepancySettings, load_rig, read_measured, run_discrepancy
    from rvcoax.geometry import updated_rig_text
    from rvcoax.results.io import rvcoax_version, write_csv_atomic, write_json_atomic, write_text_atomic
    from rvcoax.results.studies.discrepancy import (
        MeasuredDataError,
        discrepancy_document,
        observation_rows,
        plot_discrepancy,
    )

    try:
        data = read_measured(measured)
    except MeasuredDataError as error:
        raise UserError(str(error)) from None
    rig = load_rig(rig_file)
    candidates = None
    if effects:
        from rvcoax.geometry import candidate_effects

        candidates = tuple(e.strip() for e in effects.split(",") if e.strip())
        known = {e.name for e in candidate_effects(rig)} | {e.kind for e in candidate_effects(rig)}
        unknown = [e for e in candidates if e not in known]
        if unknown:
            raise UserError(f"--effects: unknown effect(s) {', '.join(unknown)}; kinds: "
                            + ", ".join(sorted({e.kind for e in candidate_effects(rig)})))
    from rvcoax.geometry import candidate_effects as library_of
    from rvcoax.geometry.model import REPORT_AFTER_S, check_workload
    from rvcoax.results.studies.discrepancy import discrepancy_workload

    n_candidates = sum(1 for e in library_of(rig)
                       if candidates is None or e.name in candidates or e.kind in candidates)
    workload = check_workload(discrepancy_workload(data, n_candidates, rig),
                              f"measured data {measured}",
                              "thin the stations or load cases (the workflow's time grows with cases × candidates), "
                              "or name fewer candidates with --effects")
    if workload.seconds > REPORT_AFTER_S:
        console.print(f"{workload.what}: {workload.describe()} (estimated)")
    settings = DiscrepancySettings(candidates=candidates, sweep=sweep_settings(model), alpha=alpha, bic_margin=margin,
                                   model_form_fraction=model_form_percent / 100.0, hold_out_every=hold_out_every)
    with progress_bar() as bar:
        task = bar.add_task("solving each candidate effect on the rig", total=None)
        try:
            result = run_discrepancy(rig, data, settings,
                                     progress=lambda i, n: bar.update(task, completed=i, total=n))
        except MeasuredDataError as error:
            raise UserError(str(error)) from None
    lengths = {"input": rig.paths.input.length_mm, "output": rig.paths.output.length_mm}
    _print_result(result, lengths)
    if out is not None:
        source, original = rig_text(rig_file)
        written = []
        rig_path = None
        if result.selected:
            names = ", ".join(s.name for s in result.selected)
            candidate = result.verdict != "explained"
            warning = ([f"NOT A FIX: the verdict is '{result.verdict}'. These effects reduce the gap but do not "
                        "explain it;", "this file is a candidate for the next measurement, not an updated rig."]
                       if candidate else [])
            text, _ = updated_rig_text(
                original, result.rig_after,
                note=f"rvcoax discrepancy ({result.verdict}) from {Path(data.source).name}",
                header=warning + [
                    f"{'Candidate' if candidate else 'Updated'} by rvcoax {rvcoax_version()} "
                    f"discrepancy workflow from {source}",
                    f"measured data: {data.source}; verdict: {result.verdict}; effects added: {names}"]
                + [f"  {s.name}: " + ", ".join(f"{p.name} = {v:.6g} {p.unit}" for p, v in
                                                 zip(result.effects[s.name].parameters, s.values))
                   + f" (ΔBIC {s.delta_bic:.1f})" for s in result.selected])
            rig_path = write_text_atomic(out / ("rig_candidate.toml" if candidate else "rig_updated.toml"), text)
            written.append(rig_path)
        written.append(write_json_atomic(out / "discrepancy.json", discrepancy_document(
            result, lengths, None if rig_path is None else str(rig_path), rvcoax_version())))
        written.append(write_csv_atomic(out / "discrepancy_observations.csv", observation_rows(result)))
        written.append(plot_discrepancy(result, lengths, out / "discrepancy.png", title=rig.rig.name))
        for path in written:
            console.print(f"wrote {escape(str(path))}")
    raise typer.Exit(code=1 if result.verdict == "unexplained" else 0)


COMMANDS = {"discrepancy": discrepancy}
"""The commands of this module, by name (:func:`rvcoax.results.cli.support.register_commands`)."""
