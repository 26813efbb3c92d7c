"""``rvcoax montecarlo`` and ``rvcoax sensitivity``: tolerance studies run through Dask.

Both read a tolerance file (:mod:`rvcoax.results.studies.tolerances`), draw a seeded design, solve every sample
as an independent task (:mod:`rvcoax.results.studies.distributed`: a local Dask cluster by default, an existing
one with ``--scheduler tcp://HOST:PORT``, or ``--scheduler serial``), write each sample as it
arrives and then the tables and the picture.
"""

from __future__ import annotations

import hashlib
import inspect
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer
from rich.markup import escape
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn
from rich.table import Table

from rvcoax.results.cli.support import (
    SEED_RANGE,
    ModelChoice,
    UserError,
    console,
    model_options,
    number_option,
    option_block,
    report_written,
    scheduler_address,
)

__all__ = ["MAX_SAMPLES", "ResumeOption", "SchedulerOption", "SeedOption", "TolerancesOption", "WorkersOption",
           "COMMANDS", "StudyChoice", "montecarlo", "sensitivity", "study_options"]

TolerancesOption = Annotated[Path, typer.Option(
    "--tolerances", help="Tolerance file (TOML): parameters with distributions, load cases, β limits. "
                         "Example: loadcases/data/example_tolerances.toml.")]
SchedulerOption = Annotated[str, typer.Option(
    "--scheduler", help="auto (default: serial, or a local Dask cluster when the measured time per sample says "
                        "it pays), local (a Dask cluster on this machine), tcp://HOST:PORT (an existing Dask "
                        "scheduler) or serial (no Dask, in this process).")]
WorkersOption = Annotated[int | None, number_option(
    "--workers", 1, 1024, integer=True, help="Worker processes of the local cluster, 1 … 1024 (default: one per core).")]
ResumeOption = Annotated[bool, typer.Option(
    "--resume", help="Keep the samples already in OUT/samples (same study) and compute only the missing ones. "
                     "Without it, samples left in OUT/samples are deleted first.")]
SeedOption = Annotated[int, number_option("--seed", *SEED_RANGE, integer=True,
                                          help="Seed of the sampling design (same seed, same samples), "
                                               f"{SEED_RANGE[0]} … {SEED_RANGE[1]}.")]
MAX_SAMPLES = 10_000_000  # every sample is a solve: ten million beam solves is days of work


@dataclass(frozen=True)
class StudyChoice:
    """``--tolerances``, ``--scheduler``, ``--workers``, ``--resume``, ``--seed``: the options every tolerance study
    (``montecarlo``, ``sensitivity``) shares."""

    tolerances: Path
    scheduler: str = "auto"
    workers: int | None = None
    resume: bool = False
    seed: int = 0


_STUDY_BLOCK = (("tolerances", TolerancesOption, inspect.Parameter.empty), ("scheduler", SchedulerOption, "auto"),
                ("workers", WorkersOption, None), ("resume", ResumeOption, False), ("seed", SeedOption, 0))


def study_options(function):
    """Give a command the tolerance-study options as one :class:`StudyChoice` argument ``study_choice``."""
    return option_block(function, "study_choice", StudyChoice, _STUDY_BLOCK)

if TYPE_CHECKING:  # annotations only: the modules load when a command runs
    import numpy as np


def _progress() -> Progress:
    return Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                    TimeElapsedColumn(), TimeRemainingColumn(), console=console, transient=True,
                    disable=not console.is_terminal)


def _setup(model_choice: ModelChoice, tolerances_path: Path):
    from rvcoax.results.studies import (
        STRATEGY_TEXT,
        ToleranceFileError,
        load_tolerances,
        parameters_needing,
        plan_study,
    )

    model = model_choice.model
    settings = model_choice.settings()
    rig = model_choice.load_rig()
    try:
        tolerances = load_tolerances(tolerances_path, rig)
    except ToleranceFileError as error:
        raise UserError(str(error)) from None
    with console.status("finding what a sample changes in the model"):
        study = plan_study(rig, tolerances, settings)
    console.print(f"[bold]{escape(tolerances.name)}[/]: {len(tolerances.parameters)} toleranced parameter(s), "
                  f"{len(study.cases)} load case(s), {model} model, Y measured from {study.rig.paths.measured_from}")
    console.print(f"reuse: [bold]{study.strategy}[/] ({STRATEGY_TEXT[study.strategy]})")
    if study.strategy != "loads":
        named = parameters_needing(study.rig, tolerances, study.strategy, model)
        console.print(f"because of: {escape(', '.join(named) or 'their combination')}")
    return tolerances, study


def _start(model_choice: ModelChoice, study_choice: StudyChoice, refusal: str | None):
    """What every tolerance study checks first (the scheduler, ``refusal`` of a bad option, the workers), then
    the tolerance file read and the study planned (:func:`_setup`)."""
    from rvcoax.geometry.model import check_workers

    scheduler_address(study_choice.scheduler)
    if refusal is not None:
        raise UserError(refusal)
    check_workers(study_choice.workers if study_choice.scheduler in ("auto", "local") else None)
    return _setup(model_choice, study_choice.tolerances)


def _solved(study, values: np.ndarray, out: Path, choice: StudyChoice, *key) -> tuple:
    """The nominal solve, then every sample's (:func:`_execute`) under a fingerprint of ``key``: records, run, nominal."""
    begin = time.perf_counter()
    nominal = _nominal(study)  # the model's set-up (and one solve): what every cluster worker would repeat
    records, run = _execute(study, values, out, _fingerprint(study.key, *key), choice,
                            setup_seconds=time.perf_counter() - begin)
    return records, run, nominal


def _nominal(study) -> dict:
    """Solve the nominal rig in this process first: a model error shows before any cluster starts."""
    from rvcoax.geometry import MEASURED_SHAFTS
    from rvcoax.results.studies import case_label, evaluate_sample, parameter_value

    values = [parameter_value(study.rig, a) for a in study.addresses]
    with console.status("solving the nominal rig"):
        result = evaluate_sample(study, values)
    for c, case in enumerate(study.cases):
        console.print(f"nominal, {case_label(case)}: "
                      + ", ".join(f"Y_{s} = {result['Y_max_mm'][c][i]:.4g} mm (β {result['beta_deg'][c][i]:.3g}°)"
                                  for i, s in enumerate(MEASURED_SHAFTS)))
    return {"values": dict(zip(study.addresses, values)), **result}


def _execute(study, values: np.ndarray, out: Path, fingerprint: str, choice: StudyChoice, *,
             setup_seconds: float | None = None):
    from rvcoax.results.studies import ClusterError, ResumeError, SampleError, evaluate_sample, run_samples

    scheduler, workers, resume = choice.scheduler, choice.workers, choice.resume

    where = "this process" if scheduler == "serial" else "this process, or a local Dask cluster where it pays" if (
        scheduler == "auto") else (
        f"a local Dask cluster ({f'{workers} workers' if workers else 'one worker per core'})" if scheduler == "local"
        else f"the Dask scheduler at {scheduler}")
    console.print(f"{len(values)} samples on {escape(where)}; each sample is written to {escape(str(out / 'samples'))} "
                  "as it arrives")
    try:
        with _progress() as progress:
            task = progress.add_task("solving samples", total=len(values))
            records, run = run_samples(evaluate_sample, study, values, out / "samples", fingerprint, scheduler=scheduler,
                                       workers=workers, resume=resume, progress=lambda done, total: progress.update(task, completed=done),
                                       setup_seconds=setup_seconds)
    except (ResumeError, ClusterError) as error:
        raise UserError(str(error)) from None
    except SampleError as error:
        shown = ", ".join(f"{a} = {v:g}" for a, v in zip(study.addresses, values[error.index]))
        raise UserError(f"{error} (values: {shown})") from None
    if run.choice is not None:
        console.print(f"scheduler auto: {escape(run.choice.describe())}")
    rate = f", {run.computed / run.seconds:.1f} samples/s" if run.computed and run.seconds > 0 else ""
    console.print(f"{run.computed} sample(s) solved, {run.resumed} resumed from disk, "
                  f"{run.resubmitted} resubmitted after lost workers; {run.seconds:.1f} s on {run.workers} worker(s){rate}")
    return records, run


def _check_size(n_solves: int, tol, study, option: str, what: str) -> None:
    """Refuse a design too large for this machine before it is drawn; announce a long one."""
    from rvcoax.geometry.model import REPORT_AFTER_S, check_study

    work = check_study(n_solves, len(tol.parameters), len(study.cases), option,
                       f"{what} × {len(study.cases)} load case(s)", model=study.settings.model, strategy=study.strategy)
    if work.seconds > REPORT_AFTER_S:
        console.print(f"{work.what}: {work.describe()} on one core (estimated)")


def _fingerprint(*items) -> str:
    return hashlib.sha256(repr(items).encode()).hexdigest()


@model_options
@study_options
def montecarlo(
    *,
    model_choice: ModelChoice,
    study_choice: StudyChoice,
    samples: Annotated[int, number_option("--samples", 1, MAX_SAMPLES, integer=True, help="Number of samples (each a solve of every load case).")] = 1000,
    sampling: Annotated[str, typer.Option("--sampling", help="lhs (Latin hypercube, default), sobol (scrambled Sobol', a power of two samples) or random.")] = "lhs",
    out: Annotated[Path, typer.Option("--out", help="Folder for the result files.")] = Path("rvcoax_out/montecarlo"),
) -> None:
    """Monte Carlo of the tilt β: distribution of Y and β per shaft and load case, and P(β > limit) with its interval.

    Writes montecarlo_samples.csv (every sample), montecarlo_distribution.csv, montecarlo_exceedance.csv,
    montecarlo.json and montecarlo_beta_histogram.png.
    """
    from rvcoax.geometry.model import count_text
    from rvcoax.results.io import write_csv_atomic, write_json_atomic
    from rvcoax.results.studies import (
        SAMPLING_METHODS,
        distribution_rows,
        exceedance_rows,
        exceedances,
        plot_beta_histograms,
        sample_rows,
        sample_values,
        study_document,
    )

    seed = study_choice.seed
    tol, study = _start(model_choice, study_choice, None if sampling in SAMPLING_METHODS else
                        f"--sampling: must be one of {', '.join(SAMPLING_METHODS)}, got '{sampling}'")
    _check_size(samples, tol, study, "--samples", f"{count_text(samples)} samples")
    try:
        values = sample_values(tol.distributions, samples, sampling, seed)
    except ValueError as error:
        raise UserError(f"--samples/--sampling: {error}") from None
    records, run, nominal = _solved(study, values, out, study_choice, "montecarlo", sampling, seed, samples)
    found = exceedances(study, tol, records)
    source, text = model_choice.rig_text()
    document = study_document(study, tol, source, text,
                                     {"kind": "montecarlo", "sampling": sampling, "seed": seed, "samples": samples},
                                     run=run, nominal=nominal)
    document["distribution"] = distribution_rows(study, records)
    document["exceedance"] = exceedance_rows(study, found)
    written = [
        write_csv_atomic(out / "montecarlo_samples.csv", sample_rows(study, values, records)),
        write_csv_atomic(out / "montecarlo_distribution.csv", document["distribution"]),
        write_csv_atomic(out / "montecarlo_exceedance.csv", document["exceedance"]),
        write_json_atomic(out / "montecarlo.json", document),
        plot_beta_histograms(study, tol, records, found, out / "montecarlo_beta_histogram.png"),
    ]
    console.print(_distribution_table(study, records, found))
    report_written(written)


def _distribution_table(study, records, found) -> Table:
    import numpy as np

    from rvcoax.geometry import MEASURED_SHAFTS
    from rvcoax.results.studies import stack_records

    table = Table(title="Y and β over the samples, and P(β > limit)", title_justify="left")
    for column in ("T1 N·m", "T2 N·m", "shaft", "Y mean mm", "Y 95 % mm", "β mean °", "β 95 % °", "β max °",
                   "limit", "P(β > limit) [interval]"):
        table.add_column(column, justify="right")
    y, beta = stack_records(records, "Y_max_mm"), stack_records(records, "beta_deg")
    for c, case in enumerate(study.cases):
        for s, shaft in enumerate(MEASURED_SHAFTS):
            limits = [(limit, e) for cc, limit, e in found if cc == c and limit.shaft == shaft] or [(None, None)]
            for limit, e in limits:
                table.add_row(f"{case.input_torque_Nm:g}", f"{case.output_torque_Nm:g}", shaft,
                              f"{y[:, c, s].mean():.4g}", f"{np.quantile(y[:, c, s], 0.95):.4g}",
                              f"{beta[:, c, s].mean():.3g}", f"{np.quantile(beta[:, c, s], 0.95):.3g}",
                              f"{beta[:, c, s].max():.3g}",
                              "" if limit is None else f"{escape(limit.label)} ({limit.beta_deg:.3g}°)",
                              "" if e is None else f"{e.probability:.3f} [{e.lower:.3f}, {e.upper:.3f}]")
    return table


@model_options
@study_options
def sensitivity(
    *,
    model_choice: ModelChoice,
    study_choice: StudyChoice,
    samples: Annotated[int, number_option("--samples", 2, MAX_SAMPLES, integer=True, help="sobol: base samples N, a power of two (N (d + 2) solves for d parameters); morris: trajectories r (r (d + 1) solves).")] = 256,
    method: Annotated[str, typer.Option("--method", help="sobol (first-order and total indices, default) or morris (cheaper screening).")] = "sobol",
    out: Annotated[Path, typer.Option("--out", help="Folder for the result files.")] = Path("rvcoax_out/sensitivity"),
) -> None:
    """Global sensitivity of β to the toleranced parameters: which tolerance to tighten first.

    Writes sensitivity_indices.csv, sensitivity_samples.csv, sensitivity.json and sensitivity_indices.png.
    """
    from rvcoax.geometry.model import count_text
    from rvcoax.results.io import write_csv_atomic, write_json_atomic
    from rvcoax.results.studies import (
        SENSITIVITY_METHODS,
        design_runs,
        morris_design,
        morris_values,
        plot_indices,
        sample_rows,
        sensitivity_rows,
        sobol_design,
        stack_records,
        study_document,
        to_values,
    )

    seed = study_choice.seed
    tol, study = _start(model_choice, study_choice, None if method in SENSITIVITY_METHODS else
                        f"--method: must be sobol or morris, got '{method}'")
    d = len(tol.parameters)
    _check_size(design_runs(method, samples, d), tol, study, "--samples",
                f"{count_text(design_runs(method, samples, d))} solves ({method}: --samples {samples}, {d} parameters)")
    try:
        points = sobol_design(samples, d, seed) if method == "sobol" else morris_design(samples, d, seed)
    except ValueError as error:
        raise UserError(f"--samples: {error}") from None
    values = to_values(tol.distributions, points) if method == "sobol" else morris_values(tol.distributions, points)
    console.print(f"{method}: {samples} {'base samples' if method == 'sobol' else 'trajectories'} x "
                  f"({d} + {2 if method == 'sobol' else 1}) = {design_runs(method, samples, d)} solves")
    records, run, nominal = _solved(study, values, out, study_choice, "sensitivity", method, seed, samples)
    found = _indices(stack_records(records, "beta_deg"), points, method, seed, tol)
    source, text = model_choice.rig_text()
    document = study_document(study, tol, source, text,
                                     {"kind": "sensitivity", "method": method, "seed": seed, "samples": samples,
                                      "solves": len(values)}, run=run, nominal=nominal)
    document["indices"] = sensitivity_rows(study, tol, found)
    written = [
        write_csv_atomic(out / "sensitivity_indices.csv", document["indices"]),
        write_csv_atomic(out / "sensitivity_samples.csv", sample_rows(study, values, records)),
        write_json_atomic(out / "sensitivity.json", document),
        plot_indices(study, tol, found, out / "sensitivity_indices.png"),
    ]
    _print_rankings(study, tol, found, method)
    report_written(written)


def _indices(beta, points, method: str, seed: int, tol) -> dict:
    """The sensitivity indices of β per (case, shaft): Sobol' (first-order and total) or Morris (μ*, σ)."""
    from rvcoax.geometry import MEASURED_SHAFTS
    from rvcoax.results.studies import morris_indices, sobol_indices

    d, confidence_level = len(tol.parameters), tol.confidence_level
    found = {}
    for c in range(beta.shape[1]):
        for s, shaft in enumerate(MEASURED_SHAFTS):
            found[(c, shaft)] = (sobol_indices(beta[:, c, s], d, seed, confidence_level) if method == "sobol"
                                 else morris_indices(points, beta[:, c, s], seed, confidence_level))
    return found


def _print_rankings(study, tol, found: dict, method: str) -> None:
    """Per shaft and case: the three parameters to tighten first (or that β does not vary)."""
    from rvcoax.results.studies import case_label, ranking

    for (c, shaft), indices in found.items():
        if indices.constant:
            console.print(f"β {shaft}, {case_label(study.cases[c])}: does not vary with these parameters")
            continue
        ranked = ranking(indices, tol.addresses)
        measure = "ST" if method == "sobol" else "μ* (°)"
        console.print(f"β {shaft}, {case_label(study.cases[c])}: tighten first "
                      + "; ".join(f"{escape(name)} ({measure} {score:.3g})" for name, score in ranked[:3]))


COMMANDS = {"montecarlo": montecarlo, "sensitivity": sensitivity}
"""The commands of this module, by name (:func:`rvcoax.results.cli.support.register_commands`)."""
