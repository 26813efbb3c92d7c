"""What every ``rvcoax`` command shares: consoles, option types, and the user-error guard.

A user mistake ends with one paragraph on stderr and exit status 2, never a traceback. Command
modules (``results/*_cli.py``) import from here and register their commands on the main app.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

from fem.solvers import SolverError
from geometry.hybrid import SolidModelError
from geometry.meshing import MeshingError
from geometry.rigfile import RigFileError, reference_rig_text
from loadcases.cases import LoadCaseError, grid_cases, paired_cases, paper_cases, read_cases
from results.preflight import sag_warnings
from results.sweep import ModelError, SweepSettings, prepare_model, run_sweep

console = Console()
if not console.is_terminal:  # logs and pipes: wide enough for the check tables
    console = Console(width=150)
errors = Console(stderr=True, width=None if Console(stderr=True).is_terminal else 150)

RigOption = Annotated[Path | None, typer.Option("--rig", help="Rig file (TOML). Default: the built-in reference rig.")]
ModelOption = Annotated[str, typer.Option("--model", help="Model fidelity: beam, hybrid (measured shafts as solids) or solid.")]
OutOption = Annotated[Path | None, typer.Option("--out", help="Folder for the result files.")]
SolverOption = Annotated[str, typer.Option("--solver", help="Linear solver for solid/hybrid models: auto (by size), superlu, pardiso or amg.")]
MeshOption = Annotated[float | None, typer.Option("--mesh-size-mm", help="Global solid mesh size in mm (default: the rig file's [solid] mesh_size_mm).")]
CasesOption = Annotated[Path | None, typer.Option("--cases", help="CSV (columns T1_input_Nm, T2_output_Nm) or TOML ([[cases]]) of load cases.")]
T1Option = Annotated[str | None, typer.Option("--t1", help="Input torques T1 in N·m, comma-separated.")]
T2Option = Annotated[str | None, typer.Option("--t2", help="Output torques T2 in N·m, comma-separated.")]
GridOption = Annotated[bool, typer.Option("--grid", help="Combine every --t1 with every --t2 (default: pair them in order).")]


class UserError(Exception):
    """A mistake in the user's input: reported in one paragraph, exit status 2."""


def fail(message: str) -> None:
    """Print ``message`` as an error and exit with status 2."""
    errors.print(f"[bold red]error:[/] {escape(message)}", highlight=False)  # the message is plain text, not markup
    raise typer.Exit(code=2)


def warn(message: str) -> None:
    """Print ``message`` as a warning on stderr (the command goes on)."""
    errors.print(f"[bold yellow]warning:[/] {escape(message)}", highlight=False)


def rig_text(path: Path | None) -> tuple[str, str]:
    """(source name, text) of the rig file, or of the built-in reference rig when ``path`` is None."""
    if path is None:
        return "built-in reference_rig.toml", reference_rig_text()
    try:
        return str(path), path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return str(path), ""


def sweep_settings(model: str, method: str = "superposition", solver: str = "auto", mesh_size_mm: float | None = None):
    """Validated :class:`SweepSettings` from command-line options."""
    if mesh_size_mm is not None and not math.isfinite(mesh_size_mm):
        raise UserError(f"--mesh-size-mm: {mesh_size_mm} is not a finite size in mm")
    try:
        return SweepSettings(method=method, model=model, solver=solver, mesh_size_mm=mesh_size_mm)
    except ValueError as error:
        raise UserError(f"--model/--method/--solver/--mesh-size-mm: {error}") from None


def guard(function):
    """Turn user-input errors into a clear message and exit status 2."""

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except (RigFileError, LoadCaseError, UserError) as error:
            fail(str(error))
        except ModelError as error:
            fail(f"rig file {kwargs.get('rig') or 'built-in reference_rig.toml'}: cannot solve the rig: {error}")
        except MeshingError as error:
            fail(f"rig file {kwargs.get('rig') or 'built-in reference_rig.toml'}: cannot mesh the rig: {error}")
        except SolidModelError as error:
            fail(f"rig file {kwargs.get('rig') or 'built-in reference_rig.toml'}: cannot build the solid parts: {error}")
        except SolverError as error:
            fail(f"rig file {kwargs.get('rig') or 'built-in reference_rig.toml'}: the solver failed: {error} "
                 "(try another --solver)")
        except OSError as error:  # reading is handled above, so this is writing the results (--out)
            fail(f"cannot write {error.filename}: {error.strerror}")

    return wrapper


def prepare_with_status(rig, settings):
    """Assemble the model and set up its solver, with a status line and the sag warnings."""
    for message in sag_warnings(rig):
        warn(message)
    with console.status(f"assembling the {settings.model} model and setting up the solver"):
        prepared = prepare_model(rig, settings)
    system = prepared.system
    console.print(f"{settings.model} model: {system.n_dofs} DOF, solver {prepared.solver_name}"
                  + (f", {len(system.solids)} solid part(s)" if system.solids else ""))
    return prepared


def progress_bar() -> Progress:
    return Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                    TimeElapsedColumn(), console=console, transient=True, disable=not console.is_terminal)


def run_with_progress(rig, cases, settings, label: str, prepared=None, on_case=None):
    """A sweep with a progress bar."""
    with progress_bar() as progress:
        task = progress.add_task(label, total=len(cases))
        return run_sweep(rig, cases, settings, progress=lambda i, n: progress.update(task, completed=i),
                         prepared=prepared, on_case=on_case)


def cases_from_options(cases_file: Path | None, t1: str | None, t2: str | None, grid: bool):
    """Load cases from --cases, or --t1/--t2 (paired or --grid), or the paper's 20 pairs."""
    if cases_file is not None:
        if t1 or t2:
            raise UserError("give either --cases FILE or --t1/--t2, not both")
        return read_cases(cases_file)
    if t1 is None and t2 is None:
        return paper_cases()
    if t1 is None or t2 is None:
        raise UserError("--t1 and --t2 go together (comma-separated torques in N·m)")

    def numbers(text: str, name: str) -> list[float]:
        try:
            return [float(v) for v in text.split(",") if v.strip()]
        except ValueError:
            raise UserError(f"{name}: '{text}' is not a comma-separated list of torques in N·m") from None

    values1, values2 = numbers(t1, "--t1"), numbers(t2, "--t2")
    return grid_cases(values1, values2) if grid else paired_cases(values1, values2)
