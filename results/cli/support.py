"""What every ``rvcoax`` command shares: consoles, option types, and the user-error guard.

A user mistake ends with one paragraph on stderr and exit status 2, never a traceback. Command
modules (``results/cli/<command>.py``) import from here and register their commands on the main app.
"""

from __future__ import annotations

import functools
import inspect
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

from rvcoax import RvcoaxError
from rvcoax.fem import SolverError
from rvcoax.geometry import MESH_SIZE_RANGE_MM, plain_number
from rvcoax.results.io import output_folder_lock

__all__ = ["CaseChoice", "CasesOption", "CommandGroup", "GridOption", "MeshOption", "ModelChoice", "ModelOption", "OutOption", "RADIAL_OFFSET_RANGE_MM",
           "RigOption", "SCHEDULER_PROTOCOLS", "SEED_RANGE", "SolverOption", "T1Option", "T2Option", "UserError",
           "add_text_row", "case_options", "cases_from_options", "check_environment", "console", "errors", "fail", "finite_option",
           "guard", "model_options", "number_option", "option_block", "prepare_with_status", "register_commands", "progress_bar", "report_written", "rig_text",
           "run_with_progress", "scheduler_address", "standard_output_failed", "sweep_settings", "torque_list", "warn", "write_error_text"]

console = Console()
if not console.is_terminal:  # logs and pipes: wide enough for the check tables
    console = Console(width=150)
errors = Console(stderr=True, width=None if Console(stderr=True).is_terminal else 150)

RADIAL_OFFSET_RANGE_MM = (0.0, 10.0)  # radial displacement a of a shaft: IT3 is 0.002 mm; 10 mm is a broken rig
SEED_RANGE = (0, 2**32 - 1)  # what numpy's and scipy's seeded generators take everywhere
SCHEDULER_PROTOCOLS = ("tcp", "tls", "ucx", "ws", "wss")  # Dask's network protocols


class UserError(RvcoaxError):
    """A mistake in the user's input: reported in one paragraph, exit status 2."""


def _range_text(low: float, high: float, unit: str, exclusive: bool, integer: bool = False) -> str:
    unit_text = f" {unit}" if unit else ""
    a, b = (f"{int(low)}", f"{int(high)}") if integer else (f"{low:g}", f"{high:g}")
    return f"({a}, {b}){unit_text}" if exclusive else f"{a} … {b}{unit_text}"


def finite_option(value: float | int | str, option: str, low: float, high: float, unit: str = "",
                  *, exclusive: bool = False, integer: bool = False) -> float | int:
    """The value of a numeric command-line option, checked at the boundary.

    Parameters
    ----------
    value : float, int or str
        The text the user typed (a plain ASCII decimal number, see
        :func:`rvcoax.geometry.inputfiles.plain_number`) or an already numeric default.
    option : str
        The option's name for the message (``"--mesh-size-mm"``).
    low, high : float
        The physical range, inclusive (exclusive with ``exclusive=True``).
    unit : str
        The option's unit for the message (``"mm"``; ``""`` for a pure number).
    integer : bool
        Accept whole numbers only (and return an int).

    Raises
    ------
    UserError
        Not a plain finite number, not whole where it must be, or outside the range; the message names
        the option, the value, the range and the unit.
    """
    wanted = "a whole number" if integer else "a number"
    in_range = f"{wanted} in {_range_text(low, high, unit, exclusive, integer)}"
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise UserError(f"{option}: {value!r} is not {in_range}")
    try:
        number = plain_number(value) if isinstance(value, str) else float(value)
    except ValueError as error:
        raise UserError(f"{option}: {error}; give {in_range}") from None
    if not math.isfinite(number):
        raise UserError(f"{option}: {value} is not a finite number; give {in_range}")
    inside = low < number < high if exclusive else low <= number <= high
    if not inside:
        raise UserError(f"{option}: {number:g} is outside the range: give {in_range}")
    if integer:
        if isinstance(value, str) and not value.strip(" \t").lstrip("+-").isdigit():
            raise UserError(f"{option}: '{value.strip()}' is not {wanted} (write digits 0-9 only); give {in_range}")
        if number != int(number):
            raise UserError(f"{option}: {number:g} is not {wanted}; give {in_range}")
        return int(value.strip(" \t")) if isinstance(value, str) else int(number)
    return number


def number_option(name: str, low: float, high: float, unit: str = "", help: str = "", *, exclusive: bool = False,
                  integer: bool = False, aliases: tuple[str, ...] = ()):
    """A ``typer.Option`` for a numeric option checked by :func:`finite_option` as it is parsed.

    Click's own FLOAT accepts ``nan``, ``1_00`` and ``٧٠``, and its range errors print a usage block;
    an option made here refuses those with the same one-paragraph error (exit status 2, through
    :func:`fail`) as every other user mistake, naming the option, the range and the unit. ``aliases`` are
    older names that still work (errors name ``name``).
    """

    def parse(value):
        try:
            return finite_option(value, name, low, high, unit, exclusive=exclusive, integer=integer)
        except UserError as error:
            fail(str(error))

    parse.__name__ = "INTEGER" if integer else "FLOAT"  # the metavar that --help shows
    return typer.Option(name, *aliases, parser=parse, help=help)


def torque_list(text: str, option: str) -> list[float]:
    """Comma-separated torques in N·m (``--t1 0.5,1``): every item a plain number with |T| ≤ the load-case bound.

    Raises
    ------
    UserError
        Naming the option, the item (1-based) and the reason: an empty item (``1,,2``), a number
        that is not plain ASCII, or a torque beyond the load-case bound.
    """
    from rvcoax.loadcases import MAX_TORQUE_NM

    values = []
    items = text.split(",")
    for i, item in enumerate(items, start=1):
        where = f"{option} '{text}', item {i} of {len(items)}"
        if not item.strip(" \t"):
            raise UserError(f"{where}: is empty (write torques in N·m separated by single commas, e.g. 0.5,1.43)")
        try:
            value = plain_number(item)
        except ValueError as error:
            raise UserError(f"{where}: {error} (torques are plain numbers in N·m)") from None
        if abs(value) > MAX_TORQUE_NM:
            raise UserError(f"{where}: {value:g} N·m is beyond any plausible rig torque (|T| ≤ {MAX_TORQUE_NM:g} N·m)")
        values.append(value)
    return values


def scheduler_address(text: str) -> str:
    """``auto``, ``local``, ``serial`` or a Dask scheduler address ``PROTOCOL://HOST:PORT``; else :class:`UserError`."""
    if text in ("auto", "local", "serial"):
        return text
    expected = f"auto, local, serial or an address such as tcp://HOST:8786 (protocols {', '.join(SCHEDULER_PROTOCOLS)})"
    protocol, separator, rest = text.partition("://")
    if not separator:
        raise UserError(f"--scheduler: '{text}' is not {expected}")
    if protocol not in SCHEDULER_PROTOCOLS:
        raise UserError(f"--scheduler: '{text}': protocol '{protocol}' is not one of {', '.join(SCHEDULER_PROTOCOLS)}")
    host, colon, port = rest.rpartition(":")
    if not colon or not host or not (port.isascii() and port.isdigit()) or not 1 <= int(port) <= 65535:
        raise UserError(f"--scheduler: '{text}': needs HOST:PORT after {protocol}:// with a port 1 … 65535 "
                        "(e.g. tcp://127.0.0.1:8786)")
    if protocol in TLS_PROTOCOLS:
        missing = _missing_tls_settings()
        if missing:
            raise UserError(f"--scheduler: '{text}': a {protocol}:// scheduler needs the client's TLS certificates, "
                            f"and Dask's configuration has no {' and no '.join(missing)} (set them in a Dask config "
                            "file or as DASK_DISTRIBUTED__COMM__TLS__CA_FILE, …__CLIENT__CERT, …__CLIENT__KEY), or "
                            "use tcp:// over a trusted network or an SSH tunnel")
    return text


TLS_PROTOCOLS = ("tls", "wss")


def _missing_tls_settings() -> list[str]:
    """The Dask settings that a TLS client needs and that are not set (ca-file, client.cert)."""
    import dask.config

    return [f"distributed.comm.tls.{key}" for key in ("ca-file", "client.cert")
            if not dask.config.get(f"distributed.comm.tls.{key}", None)]


RigOption = Annotated[Path | None, typer.Option("--rig", help="Rig file (TOML). Default: the built-in reference rig.")]
ModelOption = Annotated[str, typer.Option("--model", help="Model fidelity: beam, hybrid (measured shafts as solids) or solid.")]
OutOption = Annotated[Path | None, typer.Option("--out", help="Folder for the result files.")]
SolverOption = Annotated[str, typer.Option("--solver", help="Linear solver for solid/hybrid models: auto (by size), superlu, pardiso or amg.")]
MeshOption = Annotated[float | None, number_option(
    "--mesh-size-mm", *MESH_SIZE_RANGE_MM, "mm", help=f"Global solid mesh size in mm, {MESH_SIZE_RANGE_MM[0]:g} … {MESH_SIZE_RANGE_MM[1]:g} "
         "(default: the rig file's \\[solid] mesh_size_mm).")]
CasesOption = Annotated[Path | None, typer.Option("--cases", help="CSV (columns T1_input_Nm, T2_output_Nm) or TOML (\\[\\[cases]]) of load cases.")]
T1Option = Annotated[str | None, typer.Option("--t1", help="Input torques T1 in N·m, comma-separated.")]
T2Option = Annotated[str | None, typer.Option("--t2", help="Output torques T2 in N·m, comma-separated.")]
GridOption = Annotated[bool, typer.Option("--grid", help="Combine every --t1 with every --t2 (default: pair them in order).")]


@dataclass(frozen=True)
class ModelChoice:
    """``--rig``, ``--model``, ``--solver``, ``--mesh-size-mm``: which rig, at which fidelity, solved how."""

    rig_file: Path | None = None
    model: str = "beam"
    solver: str = "auto"
    mesh_size_mm: float | None = None

    def settings(self, method: str = "superposition"):
        """The validated :class:`rvcoax.SweepSettings` of these options."""
        return sweep_settings(self.model, method, self.solver, self.mesh_size_mm)

    def load_rig(self):
        """The rig file (or the built-in reference rig), validated."""
        from rvcoax import load_rig

        return load_rig(self.rig_file)

    def rig_text(self) -> tuple[str, str]:
        """(source name, text) of the rig file (:func:`rig_text`)."""
        return rig_text(self.rig_file)


@dataclass(frozen=True)
class CaseChoice:
    """``--cases``, ``--t1``, ``--t2``, ``--grid``: the load cases asked for (else the rig's own)."""

    cases: Path | None = None
    t1: str | None = None
    t2: str | None = None
    grid: bool = False

    @property
    def given(self) -> bool:
        """Whether the command line names the load cases (else the rig file's, or paper 000's, are solved)."""
        return self.cases is not None or self.t1 is not None or self.t2 is not None

    def load(self, rig, rig_file: Path | None = None) -> list:
        """The load cases (:func:`cases_from_options`); ``rig_file`` names the rig in a message."""
        return cases_from_options(self.cases, self.t1, self.t2, self.grid, rig, rig_file=rig_file)


_MODEL_BLOCK = (("rig_file", RigOption, None), ("model", ModelOption, "beam"), ("solver", SolverOption, "auto"),
                ("mesh_size_mm", MeshOption, None))
_CASE_BLOCK = (("cases", CasesOption, None), ("t1", T1Option, None), ("t2", T2Option, None),
               ("grid", GridOption, False))


def option_block(function, name: str, record, block):
    """``function`` with the options of ``block`` in front of its own, passed to it as one ``record`` named ``name``."""
    own = [p for p in inspect.signature(function, eval_str=True).parameters.values() if p.name != name]
    added = [inspect.Parameter(key, inspect.Parameter.KEYWORD_ONLY, default=default, annotation=annotation)
             for key, annotation, default in block]

    @functools.wraps(function)
    def wrapper(**options):
        values = {key: options.pop(key) for key, _, _ in block}
        return function(**options, **{name: record(**values)})

    parameters = [*added, *(p.replace(kind=inspect.Parameter.KEYWORD_ONLY) for p in own)]
    wrapper.__signature__ = inspect.Signature(parameters, return_annotation=None)
    wrapper.__annotations__ = {p.name: p.annotation for p in parameters}
    return wrapper


def model_options(function):
    """Give a command ``--rig``, ``--model``, ``--solver`` and ``--mesh-size-mm`` as one :class:`ModelChoice`
    argument ``model_choice`` (the same options, help and defaults for every command)."""
    return option_block(function, "model_choice", ModelChoice, _MODEL_BLOCK)


def case_options(function):
    """Give a command ``--cases``, ``--t1``, ``--t2`` and ``--grid`` as one :class:`CaseChoice` argument
    ``case_choice``."""
    return option_block(function, "case_choice", CaseChoice, _CASE_BLOCK)


@dataclass(frozen=True)
class CommandGroup:
    """A command with subcommands (``rvcoax rig show``): its help and its subcommands by name."""

    help: str
    commands: dict


def register_commands(app: typer.Typer, commands: dict) -> None:
    """Add each of ``commands`` (name → a command function, or a :class:`CommandGroup` of them) to ``app``: the one
    way a command module's commands are registered; every command function runs under :func:`guard`."""
    for name, command in commands.items():
        if isinstance(command, CommandGroup):
            group = typer.Typer(no_args_is_help=True, help=command.help)
            register_commands(group, command.commands)
            app.add_typer(group, name=name)
        else:
            app.command(name)(guard(command))


def fail(message: str) -> None:
    """Print ``message`` as an error and exit with status 2."""
    errors.print(f"[bold red]error:[/] {escape(message)}", highlight=False)  # the message is plain text, not markup
    raise typer.Exit(code=2)


def report_written(paths) -> None:
    """``wrote PATH`` for every result file written (paths are the user's text: printed as text, not markup)."""
    for path in paths:
        console.print(f"wrote {escape(str(path))}", highlight=False)


def add_text_row(table, *cells) -> None:
    """``table.add_row`` for cells that are plain text (names and values from the user's files), not markup."""
    table.add_row(*(escape(str(cell)) for cell in cells))


def warn(message: str) -> None:
    """Print ``message`` as a warning on stderr (the command goes on)."""
    errors.print(f"[bold yellow]warning:[/] {escape(message)}", highlight=False)


def rig_text(path: Path | None) -> tuple[str, str]:
    """(source name, text) of the rig file, or of the built-in reference rig when ``path`` is None."""
    from rvcoax import reference_rig_text

    if path is None:
        return "built-in reference_rig.toml", reference_rig_text()
    try:
        return str(path), path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return str(path), ""


def sweep_settings(model: str, method: str = "superposition", solver: str = "auto", mesh_size_mm: float | None = None):
    """Validated :class:`SweepSettings` from command-line options."""
    from rvcoax import SweepSettings

    if mesh_size_mm is not None:
        finite_option(mesh_size_mm, "--mesh-size-mm", *MESH_SIZE_RANGE_MM, "mm")
    try:
        return SweepSettings(method=method, model=model, solver=solver, mesh_size_mm=mesh_size_mm)
    except ValueError as error:
        raise UserError(f"--model/--method/--solver/--mesh-size-mm: {error}") from None


def write_error_text(error: OSError, out: Path | None = None) -> str:
    """``cannot write FILE: reason`` for an OSError raised while writing results (``no space left on device``).

    An error that names no file (``write()`` on a full disk) names the ``--out`` folder ``out`` when it
    is known, or standard output when that is what failed (``rvcoax rig example > /dev/full``)."""
    reason = error.strerror or (os.strerror(error.errno) if error.errno else str(error)) or type(error).__name__
    reason = reason[:1].lower() + reason[1:]
    if error.filename is not None:
        where = error.filename
    elif standard_output_failed():
        where = "to standard output"
    elif out is not None:
        where = f"into the --out folder {out}"
    else:
        where = "the result files (--out)"
    return f"cannot write {where}: {reason}"


def standard_output_failed() -> bool:
    """True when standard output cannot take what was printed (a full device, a closed pipe). Output still
    held for it is then dropped (standard output is pointed at the null device), so that Python's flush
    at exit does not fail a second time with a traceback of its own."""
    import sys

    if not getattr(sys.stdout, "failed", False):  # (rvcoax.results.cli.app.WatchedOutput)
        try:
            sys.stdout.flush()
            return False
        except OSError:
            pass
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)
    except (OSError, ValueError, AttributeError):  # (a stream without a descriptor: a test runner's)
        pass
    return True


def check_environment() -> None:
    """Refuse environment variables that rvcoax reads and that hold a value it cannot use.

    ``RVCOAX_CASE_DELAY_S`` (a test hook, seconds to pause after each solved case) must be a plain
    number in 0 … 60 s; ``inf`` would never return and ``nan`` or a word would be silently ignored.
    """
    from rvcoax.results.io import CASE_DELAY_VARIABLE

    delay = os.environ.get(CASE_DELAY_VARIABLE)
    if delay:
        try:
            finite_option(delay, f"environment variable {CASE_DELAY_VARIABLE}", 0.0, 60.0, "s")
        except UserError as error:
            raise UserError(f"{error} (unset it: it only slows a sweep down for tests)") from None


def guard(function):
    """Turn user-input errors into a clear message and exit status 2."""

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        try:
            check_environment()
            out = kwargs.get("out")
            if not isinstance(out, Path):  # no --out folder: nothing to lock
                return function(*args, **kwargs)
            with output_folder_lock(out):  # one command at a time per output folder
                return function(*args, **kwargs)
        except RvcoaxError as error:  # every error rvcoax raises on purpose: one paragraph, exit status 2
            text = error.describe(f"rig file {kwargs.get('rig_file') or 'built-in reference_rig.toml'}")
            fail(f"{text} (try another --solver)" if isinstance(error, SolverError) else text)
        except OSError as error:  # reading is handled above, so this is writing the results (--out)
            out = kwargs.get("out")
            fail(write_error_text(error, out if isinstance(out, Path) else None))

    return wrapper


def condense_housings(rig) -> None:
    """Condense every ``[[housings]]`` entry the cache does not hold yet, one at a time, saying what is done and
    how long it took (the first condensation of a fine mesh takes about a minute; later runs read the cache)."""
    from rvcoax.geometry.model import housing_condensation, housing_problem, seat_stiffness

    if housing_problem(rig) is not None:  # too large to mesh: the model's preflight refuses it, naming the cause
        return
    missing = [h for h in rig.housings if housing_condensation(rig, h, compute=False) is None]
    for k, housing in enumerate(missing, start=1):
        what = (f"condensing housing {k} of {len(missing)}, '{housing.name}' ({housing.shape}, {housing.material}, "
                f"{housing.mesh_size_mm:g} mm mesh): meshing the solid with gmsh, assembling its stiffness and "
                f"solving it for each of the {6 * len(housing.attachments_x_mm)} seat motions (cached afterwards)")
        with console.status(escape(what)):
            condensed = housing_condensation(rig, housing)
        seats = seat_stiffness(housing, condensed.matrix)
        together = {d: min(s.together_N_per_um for s in seats if s.direction == d) for d in dict.fromkeys(
            s.direction for s in seats)}
        console.print(escape(f"condensed housing '{housing.name}': {condensed.solid_dofs} solid DOF in "
                             f"{condensed.seconds:.0f} s; stiffness at its seats, all pushed together (softest seat): "
                             + ", ".join(f"{d} {v:.3g} N/µm" for d, v in together.items())
                             + " (rvcoax rig show: every load pattern)"))


def prepare_with_status(rig, settings, *, loads_ahead=None):
    """Assemble the model and set up its solver, with a status line and the sag warnings (``loads_ahead``: see
    :func:`rvcoax.results.sweep.prepare_model`)."""
    from rvcoax import prepare_model
    from rvcoax.geometry import plausibility_warnings
    from rvcoax.geometry.model import (
        REPORT_AFTER_S,
        beam_size,
        housing_problem,
        housing_workload,
        rig_problem,
        sag_warnings,
    )

    condense_housings(rig)  # first: the size and sag checks below assemble the condensed housings too
    if settings.model == "beam" and rig_problem(rig) is None:  # (a rig too large is refused below)
        size = beam_size(rig).workload(rig.mesh.max_element_length_mm)
        if size.seconds > REPORT_AFTER_S:
            console.print(f"{size.what}: {size.describe()} to assemble and factorise (estimated)")
    if housing_problem(rig) is None:  # (a housing too large is refused below, before it is meshed)
        for housing in rig.housings:
            size = housing_workload(housing)
            if size.seconds > REPORT_AFTER_S:
                console.print(f"{escape(size.what)}: {size.describe()} to mesh and condense (estimated; read from the "
                              "cache when these dimensions were condensed before)", highlight=False)
    for message in plausibility_warnings(rig) + sag_warnings(rig):
        warn(message)
    with console.status(f"assembling the {settings.model} model and setting up the solver"):
        prepared = prepare_model(rig, settings, loads_ahead=loads_ahead)
    system = prepared.system
    console.print(f"{settings.model} model: {system.n_dofs} DOF, solver {prepared.solver_name}"
                  + (f", {len(system.solids)} solid part(s)" if system.solids else ""))
    return prepared


def progress_bar() -> Progress:
    """A progress bar on the console: what runs, the bar, done/total, the time taken and the time left."""
    columns = (TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
               TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn())
    return Progress(*columns, console=console, transient=True, disable=not console.is_terminal)


def run_with_progress(rig, cases, settings, label: str, prepared=None, *, on_case=None):
    """A sweep with a progress bar."""
    from rvcoax import run_sweep

    with progress_bar() as progress:
        task = progress.add_task(label, total=len(cases))
        return run_sweep(rig, cases, settings, progress=lambda i, n: progress.update(task, completed=i),
                         prepared=prepared, on_case=on_case)


def _case_rows_upper_bound(path: Path) -> int | None:
    """At most how many load cases ``path`` holds (lines of a CSV, ``[[cases]]`` of a TOML file), counted
    without parsing; None when it cannot be read (:func:`rvcoax.loadcases.cases.read_cases` says why)."""
    from rvcoax.loadcases import MAX_CASE_FILE_BYTES

    try:
        with path.open("rb") as stream:
            data = stream.read(MAX_CASE_FILE_BYTES + 1)
    except OSError:
        return None
    return data.count(b"[[cases]]") if path.suffix.lower() == ".toml" else max(data.count(b"\n"), 1)


def cases_from_options(cases_file: Path | None, t1: str | None, t2: str | None, grid: bool, rig, *,  # noqa: PLR0913
                       rig_file: Path | None = None):
    """Load cases from --cases, or --t1/--t2 (paired or --grid), or the rig file's own
    (:func:`rvcoax.loadcases.cases.default_cases`: paper 000's 20 pairs for the reference rig only)."""
    from rvcoax import default_cases, grid_cases, paired_cases, read_cases
    from rvcoax.geometry.model import check_cases, count_text
    from rvcoax.loadcases import NoLoadCasesError

    if cases_file is not None:
        if t1 or t2:
            raise UserError("give either --cases FILE or --t1/--t2, not both")
        rows = _case_rows_upper_bound(cases_file)
        if rows is not None:  # refused before the file is parsed (a million rows take seconds)
            check_cases(rows, f"load-case file {cases_file}", f"about {count_text(rows)} load cases ({rows:,} lines)")
        with console.status(f"reading the load cases of {cases_file}"):
            cases = read_cases(cases_file)
        check_cases(len(cases), f"load-case file {cases_file}")
        return cases
    if t1 is None and t2 is None:
        try:
            cases = default_cases(rig)
        except NoLoadCasesError as error:
            raise UserError(f"rig file {rig_file}: {error}" if rig_file is not None else str(error)) from None
        check_cases(len(cases), "the rig file's load cases")
        return cases
    if t1 is None or t2 is None:
        raise UserError("--t1 and --t2 go together (comma-separated torques in N·m)")
    values1, values2 = torque_list(t1, "--t1"), torque_list(t2, "--t2")
    if grid:  # refused before the grid's cases are built
        check_cases(len(values1) * len(values2), "--t1/--t2 --grid",
                    f"{count_text(len(values1) * len(values2))} load cases ({len(values1)} T1 × {len(values2)} T2)")
        return grid_cases(values1, values2)
    check_cases(max(len(values1), len(values2)), "--t1/--t2")
    return paired_cases(values1, values2)
