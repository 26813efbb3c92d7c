"""Where the CPU time of ``rvcoax check`` goes: start-up and imports, the model's preparation (assembly,
factorisation), the sweeps and the calibration, the files, and the picture's process beside them.

The command runs in this process (as ``rvcoax check --model MODEL --out DIR`` would) with a CPU and a wall
clock around each phase; CPU time counts both BLAS threads, so it can exceed the wall time. The picture is drawn by a
second process (:mod:`rvcoax.results.io.picture_process`): its CPU is given apart, and the main process's wait for it
as a part of writing the files. Run:
``.venv/bin/python benchmarks/bench_check_phases.py [beam|hybrid] [--no-record]`` (default hybrid); prints the
figures and (without ``--no-record``) appends them to benchmarks/RESULTS.md with the machine, the date and the load
average. Indented rows are parts of the phase above them; a function called several times adds up.
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import io
import os
import sys
import tempfile
import time
from pathlib import Path

START_CPU, START_WALL = time.process_time(), time.perf_counter()
sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import publish  # noqa: E402

PHASES = {  # phase → (module, function); the CLI reaches each through its module attribute
    "model preparation (assembly, factorisation, checks)": ("rvcoax.results.cli.support", "prepare_with_status"),
    "run_check (blind and calibrated sweeps, calibration)": ("rvcoax.results.studies.check_run", "run_check"),
    "write_check (all files, the picture included)": ("rvcoax.results.reports.check_files", "write_check"),
    "the wait for the picture process (its drawing not hidden behind the other files)":
        ("rvcoax.results.io.picture_process", "PictureProcess.result"),
}
PARTS = {  # within the phases above: where the preparation and the check spend it
    "  preparation: assembly (meshes, stiffness, ties, loads, probes)": ("rvcoax.results.sweep", "assemble_model"),
    "  preparation: solver set-up (factorisation, update, checks)": ("rvcoax.fem.system", "prepare_system"),
    "    set-up: PARDISO factorisation, and the wait for its analysis (on a thread since the set-up began)":
        ("rvcoax.fem.pardiso", "Factorization.factorise"),
    "    set-up: the tie update's pieces (grounding, V, N⁻¹), beside the analysis": ("rvcoax.fem.woodbury", "_update"),
    "    set-up: singularity test and condition estimate": ("rvcoax.fem.solvers", "refuse_singular"),
    "  run_check: calibration": ("rvcoax.results.studies.check_run", "calibrate"),
    "    calibration: its sweeps of the fitting rows": ("rvcoax.results.studies.calibration", "run_sweep"),
    "  run_check: the blind and calibrated sweeps": ("rvcoax.results.studies.check_run", "run_sweep"),
    "  every solve call (PARDISO, the update, the residual check)": ("rvcoax.fem.solvers", "PreparedSolver.solve"),
}


def _timed(spent: dict, phase: str, module_name: str, name: str) -> None:
    """Wrap ``module_name.name`` (``Class.method`` too) to add its CPU and wall time to ``spent[phase]``; a name
    the module lacks (a private one made public later) is looked up with a leading underscore."""
    owner = importlib.import_module(module_name)
    module = owner
    *path, name = name.split(".")
    for part in path:
        owner = getattr(owner, part)
    if not hasattr(owner, name):
        name = "_" + name
    function = getattr(owner, name)
    spent.setdefault(phase, (0.0, 0.0))

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        cpu, wall = time.process_time(), time.perf_counter()
        try:
            return function(*args, **kwargs)
        finally:
            before = spent[phase]
            spent[phase] = (before[0] + time.process_time() - cpu, before[1] + time.perf_counter() - wall)

    setattr(owner, name, wrapper)
    if owner is not module:
        return
    import rvcoax

    if name in getattr(rvcoax, "__all__", ()) or hasattr(rvcoax, name):
        setattr(rvcoax, name, wrapper)  # ``from rvcoax import run_check`` finds the timed one


def main() -> None:
    keep = "--no-record" not in sys.argv[1:]
    arguments = [a for a in sys.argv[1:] if a != "--no-record"]
    model = arguments[0] if arguments else "hybrid"
    load_before = os.getloadavg()[0]
    from rvcoax.results.cli.app import run

    spent: dict[str, tuple[float, float]] = {}
    for phase, (module_name, name) in {**PHASES, **PARTS}.items():
        _timed(spent, phase, module_name, name)
    out = Path(tempfile.mkdtemp()) / "out"
    sys.argv = ["rvcoax", "check", "--model", model, "--out", str(out)]
    with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):
        run(end_process=False)
    total = (time.process_time() - START_CPU, time.perf_counter() - START_WALL)
    measured = sum(spent[p][0] for p in list(PHASES)[:3]), sum(spent[p][1] for p in list(PHASES)[:3])
    times = os.times()  # the picture's worker process, waited for: its CPU (imports and drawing), on the other core
    rows = [(f"{model} check, whole process", f"{total[0]:.2f} s CPU, {total[1]:.2f} s wall"),
            ("the picture process (matplotlib import and drawing, beside the main process)",
             f"{times.children_user + times.children_system:.2f} s CPU")]
    rows.append(("start-up, imports, rig and table (the rest)",
                 f"{total[0] - measured[0]:.2f} s CPU, {total[1] - measured[1]:.2f} s wall"))
    rows += [(phase, f"{cpu:.2f} s CPU, {wall:.2f} s wall") for phase, (cpu, wall) in spent.items()]
    publish(f"bench_check_phases.py: `rvcoax check --model {model}` by phase, one process", rows, load_before,
            keep=keep)


if __name__ == "__main__":
    main()
