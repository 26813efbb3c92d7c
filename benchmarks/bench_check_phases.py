"""Where the CPU time of ``rvcoax check`` goes: start-up and imports, the model's preparation (assembly,
factorisation), the sweeps and the calibration, the files, and the picture among them.

The command runs in this process (as ``rvcoax check --model MODEL --out DIR`` would) with a CPU and a wall
clock around each phase; CPU time counts both BLAS threads, so it can exceed the wall time. Run:
``.venv/bin/python benchmarks/bench_check_phases.py [beam|hybrid]`` (default hybrid); prints the figures and
appends them to benchmarks/RESULTS.md with the machine, the date and the load average.
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
    "the picture (plot_y_vs_torque, matplotlib import included)": ("rvcoax.results.io.pictures", "plot_y_vs_torque"),
}


def _timed(spent: dict, phase: str, module_name: str, name: str) -> None:
    module = importlib.import_module(module_name)
    function = getattr(module, name)

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        cpu, wall = time.process_time(), time.perf_counter()
        try:
            return function(*args, **kwargs)
        finally:
            spent[phase] = (time.process_time() - cpu, time.perf_counter() - wall)

    setattr(module, name, wrapper)
    import rvcoax

    if name in getattr(rvcoax, "__all__", ()) or hasattr(rvcoax, name):
        setattr(rvcoax, name, wrapper)  # ``from rvcoax import run_check`` finds the timed one


def main() -> None:
    model = sys.argv[1] if len(sys.argv) > 1 else "hybrid"
    load_before = os.getloadavg()[0]
    from rvcoax.results.cli.app import run

    spent: dict[str, tuple[float, float]] = {}
    for phase, (module_name, name) in PHASES.items():
        _timed(spent, phase, module_name, name)
    out = Path(tempfile.mkdtemp()) / "out"
    sys.argv = ["rvcoax", "check", "--model", model, "--out", str(out)]
    with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):
        run()
    total = (time.process_time() - START_CPU, time.perf_counter() - START_WALL)
    measured = sum(spent[p][0] for p in list(PHASES)[:3]), sum(spent[p][1] for p in list(PHASES)[:3])
    rows = [(f"{model} check, whole process", f"{total[0]:.2f} s CPU, {total[1]:.2f} s wall")]
    rows.append(("start-up, imports, rig and table (the rest)",
                 f"{total[0] - measured[0]:.2f} s CPU, {total[1] - measured[1]:.2f} s wall"))
    rows += [(phase, f"{cpu:.2f} s CPU, {wall:.2f} s wall") for phase, (cpu, wall) in spent.items()]
    publish(f"bench_check_phases.py: `rvcoax check --model {model}` by phase, one process", rows, load_before)


if __name__ == "__main__":
    main()
