"""The ``rvcoax`` application: its commands, loaded only when one of them runs.

``rvcoax --help`` lists the commands from :data:`COMMANDS` without importing them, so it prints
in a fraction of a second; running a command imports its module (``rvcoax.results.cli.<module>``),
whose ``COMMANDS`` (name → command function or command group) are added the one way
(:func:`rvcoax.results.cli.support.register_commands`: every command under the user-error guard), and
that module imports numpy, scipy and the model only inside the command's body. A test checks that the listed help equals each command's own.

Units shown to the user follow paper 000: torques in N·m, lengths and Y in mm, angles in degrees.
A user mistake ends with one paragraph and exit status 2, never a traceback.
"""

from __future__ import annotations

import importlib
import os
import sys
from typing import Annotated

import typer
from typer.core import TyperCommand, TyperGroup

__all__ = ["COMMANDS", "app", "load_command", "reflow", "run"]

# name → (module under rvcoax.results.cli, the short help that `rvcoax --help` shows)
COMMANDS: dict[str, tuple[str, str]] = {
    "sweep": ("sweep", "Solve a torque sweep and write sweep.csv / sweep.json."),
    "check": ("check", "Compare every row of a Y/β table with the model, blind and calibrated."),
    "picture": ("picture", "Off-screen pictures: the deformed rig per case (u_y in µm, same colour limits across the "
                           "sweep, measured paths drawn) and Y against torque with the published points."),
    "discrepancy": ("discrepancy", "Locate where model and measurement disagree, name the missing effect, add it, "
                                   "show the gap shrink."),
    "montecarlo": ("montecarlo", "Monte Carlo of the tilt β: distribution of Y and β per shaft and load case, and "
                                 "P(β > limit) with its interval."),
    "sensitivity": ("montecarlo", "Global sensitivity of β to the toleranced parameters: which tolerance to tighten "
                                  "first."),
    "export": ("export", "Export dynamics inputs per load case: tilt β and radial displacement a of both measured "
                         "shafts, paper 000's lever arm per shaft stage, offset and angle at every coupling, bearing "
                         "reactions (N, N·m)."),
    "chain-error": ("doe", "Paper 000's transmission-chain error vector: θ11, θ22, θ44, θ55 and θ_total = θ22 − θ11 − "
                           "θ44 − θ55 (°), with the coaxiality terms (tilt β and radial offset a of the input and "
                           "output shafts) from a sweep of the rig."),
    "modes": ("modes", "Natural frequencies and mode shapes of the rig about each load case's operating point, each "
                       "mode's class and the part or spring that owns it, and the interference (Campbell) diagram "
                       "against the motor speeds of the rig file's speeds section."),
    "report": ("report", "Write OUT/report.html: one self-contained HTML file for a design review (pictures "
                         "embedded, no network needed to open it)."),
    "rig": ("rig", "Inspect rig files."),
    "doe": ("doe", "Orthogonal experiments: range analysis, ANOVA with pooling, optimal levels and second-order "
                   "regression of a design file (doe analyze), or an orthogonal study of rig tolerances on the tilt β "
                   "(doe rig)."),
}


def reflow(text: str | None) -> str | None:
    """A docstring's paragraphs as single lines, so that the terminal wraps them, not the source's line breaks."""
    if not text:
        return text
    paragraphs = [" ".join(line.strip() for line in block.splitlines()) for block in text.strip().split("\n\n")]
    return "\n\n".join(paragraphs)


def _reflow_help(command) -> None:
    command.help = reflow(command.help)
    for sub in getattr(command, "commands", {}).values():
        _reflow_help(sub)


def load_command(name: str) -> TyperCommand | TyperGroup:
    """The real click command ``name``: imports its module and lets it register on a fresh app."""
    from rvcoax.results.cli.support import register_commands

    module = importlib.import_module(f"rvcoax.results.cli.{COMMANDS[name][0]}")
    holder = typer.Typer(rich_markup_mode="rich")
    register_commands(holder, {name: module.COMMANDS[name]})
    command = typer.main.get_group(holder).commands[name]
    _reflow_help(command)
    return command


class LazyCommands(TyperGroup):
    """A command group whose commands are imported when they run, not when the group's help lists them."""

    def list_commands(self, ctx) -> list[str]:
        return list(COMMANDS)

    def get_command(self, ctx, name: str) -> TyperCommand | TyperGroup | None:
        if name not in COMMANDS:
            return None
        if ctx.resilient_parsing or ctx.info_name == name:  # pragma: no cover - completion
            return load_command(name)
        # the group's --help only needs the name and the short help
        return TyperCommand(name, help=COMMANDS[name][1], short_help=COMMANDS[name][1])

    def resolve_command(self, ctx, args: list[str]):
        name = args[0] if args else None
        if name in COMMANDS:
            return name, load_command(name), args[1:]
        return super().resolve_command(ctx, args)


app = typer.Typer(
    cls=LazyCommands, add_completion=False, no_args_is_help=True, rich_markup_mode="rich",
    help=(
        "rvcoax: static coaxiality and modes of an RV-reducer test rig (beam, hybrid and solid finite elements).\n\n"
        "Units: torques T1 (input) and T2 (output) in N·m; positions, diameters and Y displacements in mm; "
        "tilt angles in degrees. Y is vertical (+ up); beta = arcsin(Y_max / L) with L = the measured shaft "
        "path length (input 120 mm, output 160 mm). Without --rig, the built-in reference RV-20E rig is used."
    ),
)


def _version_callback(value: bool) -> None:
    if value:
        from importlib.metadata import PackageNotFoundError, version

        try:
            text = version("rvcoax")
        except PackageNotFoundError:  # pragma: no cover - running from a copy that is not installed
            text = "unknown (not installed)"
        typer.echo(f"rvcoax {text}")
        raise typer.Exit()


@app.callback()
def main(
    version: Annotated[bool, typer.Option("--version", callback=_version_callback, is_eager=True,
                                          help="Print the version and exit.")] = False,
) -> None:
    """rvcoax command line."""


def run(*, end_process: bool = True) -> None:
    """Console-script entry point.

    ``end_process``: end the process when the command has finished (:func:`_end_process`); False raises the
    command's ``SystemExit`` instead (a caller that times the command in its own process, ``benchmarks/``).
    """
    from rvcoax.fem import avoid_compaction_stalls, single_threaded_openblas

    avoid_compaction_stalls()  # process-wide numpy setting: see fem/hugepages.py
    single_threaded_openblas()  # process-wide too: see fem/blas_threads.py
    sys.stdout = WatchedOutput(sys.stdout)
    try:
        try:
            app()
        except OSError as error:  # outside a command's guard: help or version text to a full device or closed pipe
            from rvcoax.results.cli.support import standard_output_failed, write_error_text

            if error.filename is not None or not standard_output_failed():
                raise
            sys.stderr.write(f"error: {write_error_text(error)}\n")
            sys.exit(2)
    except SystemExit as finished:
        if not end_process:
            raise
        _end_process(finished)


def _end_process(finished: SystemExit) -> None:
    """End the process once the command has finished, as the interpreter would, less its teardown.

    The exit status is the one ``finished`` carries, the ``atexit`` handlers run (the solver's and the temporary
    files' finalisers, logging, a cluster's shutdown) and the standard streams are flushed; the interpreter's
    teardown of its modules and objects is left out (after the hybrid check 0.1-0.16 s of wall time; the operating
    system frees the memory either way). Where a stream cannot be flushed, the status is not a number or a thread
    that the interpreter would wait for still runs, the interpreter's own exit takes over, as before.
    """
    import atexit
    import threading

    code = finished.code
    if not (code is None or isinstance(code, int)):
        raise finished
    if any(t.is_alive() and not t.daemon for t in threading.enumerate() if t is not threading.main_thread()):
        raise finished  # a thread the interpreter would wait for
    run_exit_functions = getattr(atexit, "_run_exitfuncs", None)
    if run_exit_functions is None:  # pragma: no cover - another interpreter
        raise finished
    run_exit_functions()  # and forgets them: the interpreter's own exit below, where it takes over, runs none twice
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except OSError:
        raise finished from None
    os._exit(0 if code is None else code & 0xFF)


class WatchedOutput:
    """Standard output that remembers when a write to it failed (``failed``), so that an OSError without a
    file name can be told apart: the terminal's output (``rvcoax rig example > /dev/full``) or a result file."""

    def __init__(self, stream):
        self._stream = stream
        self.failed = False

    def write(self, text):
        try:
            return self._stream.write(text)
        except OSError:
            self.failed = True
            raise

    def flush(self):
        try:
            return self._stream.flush()
        except OSError:
            self.failed = True
            raise

    def __getattr__(self, name):
        return getattr(self._stream, name)


if __name__ == "__main__":
    run()
