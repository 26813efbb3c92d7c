"""Commands ``rvcoax doe analyze``, ``rvcoax doe rig`` and ``rvcoax chain-error``.

``doe analyze`` reads any orthogonal design with its response (e.g. paper 001's L27 files) and
reports range analysis, ANOVA (error from the empty columns, pooling), the optimal levels and a
second-order regression. ``doe rig`` runs an orthogonal study of rig tolerances, each run a solve of
the rig, and analyses β of both shafts. ``chain-error`` evaluates paper 000's transmission-chain
error vector model with the tilts and offsets of a sweep of the rig.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer
from rich.markup import escape
from rich.table import Table

from rvcoax.geometry import InputFileError, csv_rows, plain_number, read_input_text
from rvcoax.loadcases import MAX_TORQUE_NM
from rvcoax.results.cli import support as options
from rvcoax.results.cli.support import UserError, console, sweep_settings
from rvcoax.results.studies.doe import ALPHA_RANGE, POOL_BELOW_F_RANGE

__all__ = ["AlphaOption", "COMMANDS", "DOE_HELP", "GoalOption", "PoolOption", "TORQUE_RANGE_NM", "chain_error_command",
           "doe_analyze", "doe_rig"]

DOE_HELP = ("Orthogonal experiments: range analysis, ANOVA with pooling, optimal levels and second-order regression "
            "of a design file (doe analyze), or an orthogonal study of rig tolerances on the tilt β (doe rig).")

AlphaOption = Annotated[float, options.number_option("--alpha", *ALPHA_RANGE, exclusive=True,
                                                    help="Significance level of the F tests, in (0, 0.5).")]
PoolOption = Annotated[float, options.number_option(
    "--pool-below-F", *POOL_BELOW_F_RANGE, help="Pool sources whose F (against the empty-column error) is below "
    f"this, {POOL_BELOW_F_RANGE[0]:g} … {POOL_BELOW_F_RANGE[1]:g}; 0: no pooling.")]
TORQUE_RANGE_NM = (-MAX_TORQUE_NM, MAX_TORQUE_NM)
GoalOption = Annotated[str, typer.Option("--goal", help="min (smaller response is better) or max.")]

if TYPE_CHECKING:  # annotations only: the modules load when a command runs
    from rvcoax.results.studies.doe import Analysis


# -- doe analyze ---------------------------------------------------------------------------------
def _terms_option(text: str, n_factors: int):
    """(terms or keyword, published coefficients or None) from --terms."""
    from rvcoax.results.studies.doe import MAX_TABLE_BYTES, parse_term

    if text in ("auto", "full", "stepwise"):
        return text, None
    if not text.strip(" ,"):
        raise UserError(f"--terms '{text}': no terms (give auto, full, stepwise, a comma list such as 1,x1,x1^2 or a CSV)")
    path = Path(text)
    if path.suffix.lower() == ".csv" or path.exists():
        try:
            rows = list(csv_rows(read_input_text(path, MAX_TABLE_BYTES, "a terms file")))
        except InputFileError as error:
            raise UserError(f"--terms {path}: {error}") from None
        rows = [(line, [c.strip() for c in cells]) for line, cells in rows if any(c.strip() for c in cells)]
        header = rows[0][1] if rows else []
        if "term" not in header:
            raise UserError(f"--terms {path}: needs a column 'term' (1, x1, x1^2, x1*x2, …)")
        records = [(line, dict(zip(header, cells))) for line, cells in rows[1:]]
        texts = [r.get("term", "") for _, r in records]
        published = None
        if "coefficient" in header:
            published = []
            for line, record in records:
                try:
                    published.append(plain_number(record.get("coefficient", "")))
                except ValueError as error:
                    raise UserError(f"--terms {path}, line {line}, column coefficient: {error}") from None
    else:
        texts, published = [t for t in text.split(",") if t.strip()], None
    try:
        terms = tuple(parse_term(t, n_factors) for t in texts)
    except ValueError as error:
        raise UserError(f"--terms {text}: {error}") from None
    return terms, published


def _outliers_option(text: str, runs: tuple[str, ...]):
    if text in ("auto", "none"):
        return None if text == "none" else "auto"
    labels = [t.strip() for t in text.split(",") if t.strip()]
    unknown = [t for t in labels if t not in runs]
    if unknown:
        raise UserError(f"--outliers: no run {', '.join(unknown)} in the design (runs {runs[0]} … {runs[-1]})")
    return [runs.index(t) for t in labels]


def _range_table(analysis: Analysis) -> Table:

    table = Table(title="Range analysis (K: level sums, k: level means, R = max k − min k)", title_justify="left")
    n_levels = max(len(r.k) for r in analysis.ranges)
    for column in ["column", *[f"K{i + 1}" for i in range(n_levels)], *[f"k{i + 1}" for i in range(n_levels)], "R"]:
        table.add_column(column, justify="right")
    for r in analysis.ranges:
        table.add_row(r.column, *[f"{v:.5g}" for v in r.K], *[f"{v:.5g}" for v in r.k], f"{r.R:.5g}")
    return table


def _anova_table(table, title: str) -> Table:
    out = Table(title=title, title_justify="left")
    for column in ("source", "S", "f", "V", "F", "p", f"F crit (α = {table.alpha:g})", "significant", "share of S_T"):
        out.add_column(column, justify="right")
    for row in table.rows:
        out.add_row(row.source, f"{row.S:.6g}", str(row.f), f"{row.V:.6g}",
                    "" if row.F is None else f"{row.F:.5g}", "" if row.p is None else f"{row.p:.3g}",
                    "" if row.F_critical is None else f"{row.F_critical:.4g}",
                    "" if row.significant is None else ("[green]yes[/]" if row.significant else "no"),
                    f"{100 * row.S / table.total.S:.1f} %" if table.total.S > 0 else "")
    out.add_row(table.error.source, f"{table.error.S:.6g}", str(table.error.f),
                f"{table.error.V:.6g}" if table.error.f else "", "", "", "", "", "")
    out.add_row("total", f"{table.total.S:.6g}", str(table.total.f), "", "", "", "", "", "")
    return out


def _print_analysis(analysis: Analysis, published_coefficients=None) -> None:
    from rvcoax.results.studies.doe import combination_label, regression_document

    design = analysis.design
    console.print(f"[bold]{escape(design.response_name)}[/]: {len(design.runs)} runs, factors "
                  + ", ".join(escape(f"{f.key} = {f.name} [{f.unit}]") for f in design.factors))
    console.print(_range_table(analysis))
    table = analysis.anova
    console.print(_anova_table(table, "ANOVA (error: what the sources leave"
                               + (f" = empty columns {', '.join(map(str, table.empty_columns))} of the "
                                  f"standard {table.array}" if table.array and table.empty_columns else "") + ")"))
    if analysis.pooled is not table:
        console.print(_anova_table(analysis.pooled, "ANOVA after pooling ("
                                   + (", ".join(analysis.pooled.pooled) or "nothing") + " pooled into the error)"))
    for note in analysis.pooled.notes:
        console.print(f"[dim]{escape(note)}[/]")
    ranked = sorted(analysis.anova.rows, key=lambda r: -r.S)
    console.print("order of influence (by S): " + " > ".join(r.source for r in ranked))
    significant = [r.source for r in analysis.pooled.rows if r.significant]
    console.print(f"optimal levels: [bold]{combination_label(analysis.optimum)}[/] = "
                  + ", ".join(f"{f.key} = {f.values[analysis.optimum[f.key] - 1]:g} {escape(f.unit)}"
                              for f in design.factors)
                  + f" (significant after pooling: {', '.join(significant) or 'none'}; the levels of the others "
                    "hardly matter)")
    fit = analysis.regression
    console.print(f"second-order regression of {escape(design.response_name)}, terms: {escape(analysis.term_selection)}")
    regression = Table()
    regression.add_column("term")
    regression.add_column("coefficient", justify="right")
    if published_coefficients is not None and len(published_coefficients) == len(fit.terms):
        regression.add_column("published", justify="right")
        regression.add_column("difference", justify="right")
    for i, name in enumerate(fit.names):
        cells = [name, f"{fit.coefficients[i]:.6g}"]
        if len(regression.columns) == 4:
            cells += [f"{published_coefficients[i]:.6g}", f"{fit.coefficients[i] - published_coefficients[i]:.2g}"]
        regression.add_row(*cells)
    console.print(regression)
    removed = ", ".join(design.runs[i] for i in fit.removed) or "none"
    if fit.note:
        console.print(f"[yellow]note:[/] {escape(fit.note)}")
    document = regression_document(analysis)
    console.print("variables: " + ", ".join(f"{k} = {escape(v)}" for k, v in document["variables"].items()))
    console.print(f"outliers removed: {escape(removed)}; {int(fit.used.sum())} runs; r² = {fit.r2:.4f} "
                  f"(adjusted {fit.adjusted_r2:.4f}), F = {fit.F:.4g}, p = {fit.p:.3g}; prediction at "
                  f"{document['prediction_at_optimum']['levels']}: {document['prediction_at_optimum']['y']:.6g}")


def doe_analyze(
    design_file: Annotated[Path, typer.Argument(metavar="DESIGN.csv", help=(
        "One row per run: optional run column (test/run), a level-code column per factor (named by its key), "
        "interaction columns <a>x<b>[_n], optional empty columns e<n>, and one response column."))],
    levels: Annotated[Path, typer.Option("--levels", help="CSV: factor, name, unit, level_1, level_2, … (level values).")],
    response: Annotated[str | None, typer.Option("--response", help="Response column (needed if several columns could be).")] = None,
    alpha: AlphaOption = 0.05,
    pool_below_F: PoolOption = 1.0,
    *, pool: Annotated[str | None, typer.Option("--pool", help="Also pool these sources, comma-separated (e.g. AxB,C).")] = None,
    goal: GoalOption = "min",
    terms: Annotated[str, typer.Option("--terms", help=(
        "Regression terms: auto (full second-order if the runs allow, else stepwise), full, stepwise, a comma list "
        "(1,x1,x1^2,x1*x2), or a CSV with a 'term' column (and optionally the published 'coefficient' to compare)."))] = "auto",
    outliers: Annotated[str, typer.Option("--outliers", help="auto (residual intervals at 95 %), none, or run labels, comma-separated.")] = "auto",
    json_file: Annotated[Path | None, typer.Option("--json", help="Write range, anova and regression to this JSON file.")] = None,
) -> None:
    """Analyse an orthogonal experiment: range analysis, ANOVA with pooling, optimal levels, regression."""
    from rvcoax.results.io import write_json_atomic
    from rvcoax.results.studies.doe import DesignError, analyse, analysis_document, read_design, read_levels

    if goal not in ("min", "max"):
        raise UserError(f"--goal: must be min or max, got '{goal}'")
    try:
        factors = read_levels(levels)
        design = read_design(design_file, factors, response)
    except DesignError as error:
        raise UserError(str(error)) from None
    chosen, published = _terms_option(terms, len(design.factors))
    pooled_names = tuple(p.strip() for p in pool.split(",") if p.strip()) if pool else ()
    sources = [s.name for s in design.sources if s.kind != "empty"]
    unknown = [p for p in pooled_names if p not in sources]
    if unknown:
        raise UserError(f"--pool: {', '.join(unknown)} is not a source of {design_file} (sources: {', '.join(sources)})")
    try:
        analysis = analyse(design, alpha, pool_below_F or None, pooled_names, goal, terms=chosen,
                           outliers=_outliers_option(outliers, design.runs))
    except ValueError as error:
        raise UserError(f"{design_file}: {error}") from None
    _print_analysis(analysis, published)
    if json_file is not None:
        options.report_written([write_json_atomic(json_file, analysis_document(analysis))])


# -- doe rig -------------------------------------------------------------------------------------
def _study_outputs(result, analyses: list[Analysis], out: Path, rig_source: str, model: str) -> list[Path]:
    from rvcoax.results.io import write_csv_atomic, write_json_atomic
    from rvcoax.results.studies.doe import analysis_document, anova_rows, plot_main_effects, run_values

    stem = result.array.name.lower()
    design = analyses[0].design
    design_rows = []
    for i, run in enumerate(design.runs):
        row = {"run": run, **{c: int(codes[i]) for c, codes in design.codes.items()}}
        row.update({name: float(values[i]) for name, values in result.responses.items()})
        design_rows.append(row)
    levels_rows = [{"factor": f.key, "name": f.name, "unit": f.unit,
                    **{f"level_{i + 1}": v for i, v in enumerate(f.values)}} for f in design.factors]
    run_rows = []
    for i in range(result.array.runs):
        row = {"run": i + 1, **run_values(result.study, result.array, result.columns, i)}
        row.update({f"Y_{s}_mm": float(v[i]) for s, v in result.y_max_mm.items()})
        row.update({name: float(values[i]) for name, values in result.responses.items()})
        run_rows.append(row)
    settings = {"study": result.study.study.model_dump(), "model": model, "rig": rig_source,
                "columns": result.columns, "factors": [f.model_dump() for f in result.study.factors]}
    anova_json = {"settings": settings}
    regression_json = {"settings": settings}
    for analysis in analyses:
        document = analysis_document(analysis)
        anova_json[analysis.design.response_name] = {k: document[k] for k in
                                                    ("range", "anova", "anova_pooled", "optimal_levels")}
        regression_json[analysis.design.response_name] = document["regression"]
    return [
        write_csv_atomic(out / f"{stem}_design.csv", design_rows),
        write_csv_atomic(out / f"{stem}_levels.csv", levels_rows),
        write_csv_atomic(out / f"{stem}_runs.csv", run_rows),
        write_csv_atomic(out / f"{stem}_anova.csv", [r for a in analyses for r in anova_rows(a)]),
        write_json_atomic(out / f"{stem}_anova.json", anova_json),
        write_json_atomic(out / f"{stem}_regression.json", regression_json),
        plot_main_effects(analyses, out / f"{stem}_main_effects.png",
                          title=f"{result.study.study.name} ({model} model)"),
    ]


def doe_rig(
    study: Annotated[Path | None, typer.Option("--study", help="Study file (TOML). Default: the built-in L27 rig-tolerance study.")] = None,
    rig_file: options.RigOption = None,
    model: options.ModelOption = "beam",
    out: options.OutOption = Path("rvcoax_out/doe_rig"),
    solver: options.SolverOption = "auto",
    *, mesh_size_mm: options.MeshOption = None,
) -> None:
    """Orthogonal study of rig tolerances on β: every run is a solve of the rig (beam: about 0.1 s a run;
    hybrid: about 20 s). Writes the design, levels, runs, ANOVA (CSV and JSON), regression (JSON) and a
    main-effects PNG."""
    from rich.progress import Progress

    from rvcoax import load_rig
    from rvcoax.results.studies.doe import StudyError, analyse, load_study, run_study

    settings = sweep_settings(model, solver=solver, mesh_size_mm=mesh_size_mm)
    rig = load_rig(rig_file)
    try:
        plan = load_study(study)
        with Progress(console=console, transient=True, disable=not console.is_terminal) as progress:
            task = progress.add_task(f"solving the {plan.study.array} runs ({model})", total=None)
            result = run_study(rig, plan, settings,
                               progress=lambda i, n: progress.update(task, completed=i, total=n),
                               source=f"study file {study if study else '<built-in l27_rig_tolerances.toml>'}")
    except StudyError as error:
        raise UserError(str(error)) from None
    s = plan.study
    console.print(f"{escape(s.name)}: {s.array}, {len(plan.factors)} factors on columns "
                  + escape(", ".join(f"{k} → {c}" for k, c in result.columns.items()))
                  + f"; case T1 = {s.T1_input_Nm:g} N·m, T2 = {s.T2_output_Nm:g} N·m; Y measured from: {s.measured_from}")
    analyses = []
    for name in result.responses:
        analysis = analyse(result.design(name), s.alpha, s.pool_below_F, (), s.goal, terms="auto", outliers="auto")
        _print_analysis(analysis)
        analyses.append(analysis)
    options.report_written(_study_outputs(result, analyses, out, str(rig_file) if rig_file else "built-in reference_rig.toml", model))


# -- chain-error ---------------------------------------------------------------------------------
def _chain_table(chain, result) -> tuple[Table, list[dict]]:
    """The chain-error table on the console and its rows for chain_error.csv, one per component."""
    import numpy as np

    from rvcoax.results.studies import torsion_constant_deg_per_m

    table = Table(title=f"Transmission-chain error vector of the {escape(chain.reducer.name)} (paper 000)",
                  title_justify="left")
    for column in ("component", "θ", "stages loaded", "G GPa", "C °/m", "transfer", "part twist °",
                   "θ at β = 0 °", "θ °", "coaxiality part °", "sign"):
        table.add_column(column, justify="right")
    rows = []
    for p in result.contributions:
        c = p.component
        loaded = ",".join(str(i + 1) for i in np.flatnonzero(p.forces_N))
        table.add_row(escape(c.name), escape(c.symbol), loaded or "-", f"{c.shear_modulus_Pa / 1e9:.2f}",
                      f"{torsion_constant_deg_per_m(c.shear_modulus_Pa):.0f}", f"{escape(c.transmission)} = {c.transmission_factor:.4g}",
                      f"{p.twist_deg:.4g}", f"{p.baseline_deg:.4g}", f"{p.value_deg:.6g}",
                      f"{p.coaxiality_part_deg:.3g}", "+" if c.sign > 0 else "−")
        rows.append({"component": c.name, "symbol": c.symbol, "coaxiality": c.coaxiality,
                     "beta_deg": p.coaxiality.beta_deg, "a_mm": p.coaxiality.offset_mm,
                     "shear_modulus_GPa": c.shear_modulus_Pa / 1e9, "transmission_factor": c.transmission_factor,
                     "part_twist_deg": p.twist_deg, "theta_beta0_deg": p.baseline_deg, "theta_deg": p.value_deg,
                     "coaxiality_part_deg": p.coaxiality_part_deg, "sign": c.sign, "signed_theta_deg": p.signed_deg})
    return table, rows


def chain_error_command(
    forces: Annotated[Path, typer.Option("--forces", help="CSV of stage forces: component, stage (1-based), force_N.")],
    rig_file: options.RigOption = None,
    stages: Annotated[Path | None, typer.Option("--stages", help="Stage data file (TOML). Default: the built-in RV-20E stages.")] = None,
    t1: Annotated[float, options.number_option("--t1", *TORQUE_RANGE_NM, "N·m", help="Input torque T1 (N·m) of the sweep case that gives β and a.")] = 1.43,
    t2: Annotated[float, options.number_option("--t2", *TORQUE_RANGE_NM, "N·m", help="Output torque T2 (N·m) of that case.")] = 200.0,
    *, tilt: Annotated[str, typer.Option("--tilt", help="sweep: β and a of each shaft from the sweep case; none: β = 0 (paper 000's baseline).")] = "sweep",
    a_input_mm: Annotated[float | None, options.number_option("--input-radial-mm", *options.RADIAL_OFFSET_RANGE_MM, "mm", aliases=("--a-input-mm",), help="Radial displacement a of the input shaft (mm) instead of the sweep's Y_max (paper 000: 0.002, IT3).")] = None,
    a_output_mm: Annotated[float | None, options.number_option("--output-radial-mm", *options.RADIAL_OFFSET_RANGE_MM, "mm", aliases=("--a-output-mm",), help="Radial displacement a of the output shaft (mm) instead of the sweep's Y_max (paper 000: 0.003, IT3).")] = None,
    model: options.ModelOption = "beam",
    out: options.OutOption = None,
) -> None:
    """Paper 000's transmission-chain error vector: θ11, θ22, θ44, θ55 and θ_total = θ22 − θ11 − θ44 − θ55 (°),
    with the coaxiality terms (tilt β and radial offset a of the input and output shafts) from a sweep of the rig."""

    from rvcoax import LoadCase, load_rig
    from rvcoax.results.io import write_csv_atomic, write_json_atomic
    from rvcoax.results.studies import (
        ChainDataError,
        Coaxiality,
        evaluate_chain_error,
        load_chain_model,
        read_stage_forces,
        torsion_constant_deg_per_m,
    )

    if tilt not in ("sweep", "none"):
        raise UserError(f"--tilt must be sweep or none, got '{tilt}'")
    rig = load_rig(rig_file)
    try:
        chain = load_chain_model(rig, stages)
        stage_forces = read_stage_forces(forces, chain)
    except ChainDataError as error:
        raise UserError(str(error)) from None
    shafts = {"input": Coaxiality(), "output": Coaxiality()}
    if tilt == "sweep":
        from rvcoax import run_sweep

        sweep = run_sweep(rig, (LoadCase(t1, t2),), sweep_settings(model))
        overrides = {"input": a_input_mm, "output": a_output_mm}
        try:
            shafts = {s: Coaxiality(p.beta_deg, p.y_max_mm if overrides[s] is None else overrides[s])
                      for s, p in sweep.cases[0].paths.items()}
        except ValueError as error:
            raise UserError(f"--input-radial-mm/--output-radial-mm: {error}") from None
        console.print(f"β and a from the {model} model at T1 = {t1:g}, T2 = {t2:g} N·m (Y measured from "
                      f"{rig.paths.measured_from}): " + "; ".join(
                          f"{s} β = {c.beta_deg:.4g}°, a = {c.offset_mm:.4g} mm" for s, c in shafts.items()))
    result = evaluate_chain_error(chain, stage_forces, shafts["input"], shafts["output"])
    table, rows = _chain_table(chain, result)
    console.print(table)
    console.print(f"C: torsion constant 180/π · 32 / (π G), φ = C T / d⁴ in °/m (T in N·m, d in mm); paper 000's 7350 is "
                  f"C at G = 79.4 GPa ({torsion_constant_deg_per_m(79.4e9):.1f}). Stage data: {escape(chain.source)}")
    ordered = sorted(result.contributions, key=lambda p: -p.component.sign)  # the paper writes θ22 first
    symbols = " ".join(("+ " if p.component.sign > 0 else "− ") + p.component.symbol for p in ordered)
    console.print(f"θ_total = {symbols.removeprefix('+ ')} = [bold]{result.total_deg:.6g}°[/] "
                  f"(β = 0: {result.baseline_total_deg:.6g}°; coaxiality adds {result.total_deg - result.baseline_total_deg:.3g}°)")
    if out is not None:
        document = {"forces_file": str(forces), "stage_data": chain.source, "reducer": vars(chain.reducer),
                    "shafts": {s: vars(c) for s, c in shafts.items()}, "contributions": rows,
                    "total_deg": result.total_deg, "total_beta0_deg": result.baseline_total_deg,
                    "sign_convention": "clockwise positive: θ_total = Σ sign · θ (paper 000: θ22 − θ11 − θ44 − θ55)"}
        options.report_written((write_csv_atomic(out / "chain_error.csv", rows), write_json_atomic(out / "chain_error.json", document)))


COMMANDS = {"doe": options.CommandGroup(DOE_HELP, {"analyze": doe_analyze, "rig": doe_rig}),
            "chain-error": chain_error_command}
"""The commands of this module, by name (:func:`rvcoax.results.cli.support.register_commands`)."""
