"""The condition estimate's share of whole runs: CPU and wall time of the estimate against the whole process.

Each run is a fresh Python process that runs one workload with the solver's singularity test and condition
estimate timed from inside (:mod:`rvcoax.fem.solvers`, :mod:`rvcoax.fem.diagnostics`):

- ``check-beam``, ``check-hybrid``, ``check-solid``: ``rvcoax check --model M`` (default mesh);
- ``sweep-beam``, ``sweep-hybrid``, ``sweep-solid``: ``rvcoax sweep --model M`` of the reference rig's table;
- ``sweep-solid-amg``, ``sweep-solid-12mm-amg``: ``rvcoax sweep --model solid --solver amg`` on the default and a
  12 mm mesh (no estimate: AMG reports none);
- ``cantilever``: the clamped solid cantilever (4 mm: 62 k DOF), ``prepare(K, "pardiso")`` and one solve;
- ``montecarlo-beam``, ``montecarlo-hybrid``, ``montecarlo-solid-12mm``: ``rvcoax montecarlo --scheduler serial``
  with the example tolerance file and a few samples (``--samples``), each sample a set-up of its own (the
  all-solid rig on a 12 mm mesh, 155 k DOF);
- ``calibrate``: the calibration of the hybrid model alone (``rvcoax.calibrate``; ``rvcoax check`` holds one too).

"estimate" is the time the condition estimate adds: where PARDISO makes it at set-up, the time of
``singularity_and_condition`` less that of the singularity test alone (measured right after it on the same
factor, and taken out of the whole process's figures as well); where it is made on request
(``PreparedSolver.condition_estimate``: SuperLU, or ``estimate_condition=False``), the whole call. CPU time
counts every thread of the process (``RUSAGE_CHILDREN`` of the run), wall time includes Python's start-up.

Run: ``.venv/bin/python benchmarks/bench_condition_share.py [RUN ...] [--samples N] [--no-record]``
(default: every run but the solid rig on its default mesh, which needs ~5 GB and several minutes: name those). Prints a table and
appends it to benchmarks/RESULTS.md with the machine, the date and the load average. With
``RVCOAX_BENCH_COMPARE_FULL=1`` each estimate is also made by the full search (itmax 5, unguided) on the
same factor, its time taken out of the figures, both values printed.
"""

from __future__ import annotations

import argparse
import inspect
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))

TOLERANCES = str(ROOT / "loadcases" / "data" / "example_tolerances.toml")
RUNS = {
    "check-beam": ["check", "--model", "beam"],
    "check-hybrid": ["check", "--model", "hybrid"],
    "check-solid": ["check", "--model", "solid"],
    "sweep-beam": ["sweep", "--model", "beam"],
    "sweep-hybrid": ["sweep", "--model", "hybrid"],
    "sweep-solid": ["sweep", "--model", "solid"],
    "sweep-solid-amg": ["sweep", "--model", "solid", "--solver", "amg"],
    "sweep-solid-12mm-amg": ["sweep", "--model", "solid", "--mesh-size-mm", "12", "--solver", "amg"],
    "montecarlo-beam": ["montecarlo", "--model", "beam", "--scheduler", "serial", "--tolerances", TOLERANCES],
    "montecarlo-hybrid": ["montecarlo", "--model", "hybrid", "--scheduler", "serial", "--tolerances", TOLERANCES],
    "montecarlo-solid-12mm": ["montecarlo", "--model", "solid", "--mesh-size-mm", "12", "--scheduler", "serial",
                              "--tolerances", TOLERANCES],
    "cantilever": None,
    "calibrate": None,
}
DEFAULT_RUNS = [r for r in RUNS if "solid" not in r or r == "montecarlo-solid-12mm"]


class _Clock:
    """CPU and wall seconds and solve calls spent in the estimate, the singularity test and the instrument."""

    def __init__(self):
        self.estimate = [0.0, 0.0]
        self.test = [0.0, 0.0]
        self.instrument = [0.0, 0.0]  # the extra singularity tests run only to be subtracted
        self.calls = []  # per set-up: solve calls (columns) of the estimate with the test
        self.inside = False
        self.part = None  # the cantilever: set-up and solve alone
        self.values = []  # per estimate: its value, and the full search's (itmax 5, no guesses) on the same factor
        self.compare = os.environ.get("RVCOAX_BENCH_COMPARE_FULL") == "1"

    @staticmethod
    def now():
        return time.process_time(), time.perf_counter()

    @staticmethod
    def add(into, start):
        cpu, wall = _Clock.now()
        into[0] += cpu - start[0]
        into[1] += wall - start[1]


def _instrument(clock: _Clock) -> None:
    """Wrap the solver's estimate and test so that ``clock`` adds up their times."""
    from rvcoax.fem import diagnostics, solvers

    together = solvers.singularity_and_condition
    alone = solvers.scaled_inverse_norm_bound
    on_request = diagnostics.scaled_condition_estimate

    def counted(solve, calls):
        def inner(block):
            calls.append(int(block.shape[1]) if block.ndim == 2 else 1)
            return solve(block)
        return inner

    def timed_together(matrix, solve, *args, **kwargs):
        calls = []
        start = clock.now()
        clock.inside = True
        try:
            result = together(matrix, counted(solve, calls), *args, **kwargs)
        finally:
            clock.inside = False
        both = [0.0, 0.0]
        clock.add(both, start)
        start = clock.now()
        alone(matrix, lambda b: solve(b[:, None]))
        test = [0.0, 0.0]
        clock.add(test, start)
        clock.add(clock.instrument, start)
        clock.test[0] += test[0]
        clock.test[1] += test[1]
        clock.estimate[0] += max(0.0, both[0] - test[0])
        clock.estimate[1] += max(0.0, both[1] - test[1])
        clock.calls.append(calls)
        _record(clock, result[2], matrix, solve)
        return result

    def timed_alone(*args, **kwargs):
        start = clock.now()
        try:
            return alone(*args, **kwargs)
        finally:
            clock.add(clock.test, start)

    def timed_on_request(matrix, solve, *args, **kwargs):
        if clock.inside:
            return on_request(matrix, solve, *args, **kwargs)
        calls = []
        start = clock.now()
        try:
            value = on_request(matrix, counted(solve, calls), *args, **kwargs)
        finally:
            clock.add(clock.estimate, start)
            clock.calls.append(calls)
        _record(clock, value, matrix, solve)
        return value

    def _record(clock, value, matrix, solve):
        full = None
        if clock.compare and "guided" in inspect.signature(on_request).parameters:
            start = clock.now()
            full = on_request(matrix, solve, max_iterations=5, guided=False)
            clock.add(clock.instrument, start)
        clock.values.append((float(value), None if full is None else float(full)))

    solvers.singularity_and_condition = timed_together
    solvers.scaled_inverse_norm_bound = timed_alone
    diagnostics.scaled_condition_estimate = timed_on_request


def _cantilever(clock: _Clock) -> None:
    import numpy as np
    from bench_solver_choice import system

    from rvcoax.fem import solvers

    with tempfile.TemporaryDirectory() as cache:
        a, force, _ = system(4.0, str(Path(os.environ.get("RVCOAX_BENCH_CACHE", cache))))
    start, clock.part = clock.now(), [0.0, 0.0]
    solver = solvers.prepare(a, "pardiso")
    x = solver.solve(force)
    clock.add(clock.part, start)
    clock.part = [clock.part[0] - clock.instrument[0], clock.part[1] - clock.instrument[1]]
    print(f"cantilever {a.shape[0]:,} DOF, tip deflection {np.abs(x).max():.4e} m, "
          f"condition estimate {solver.condition_estimate():.3g}")


def _calibrate() -> None:
    import rvcoax

    result = rvcoax.calibrate(rvcoax.load_rig(), rvcoax.paper_table(), settings=rvcoax.SweepSettings(model="hybrid"))
    print(type(result).__name__)


def child(name: str, out: str, samples: int) -> None:
    clock = _Clock()
    _instrument(clock)
    if name == "cantilever":
        _cantilever(clock)
    elif name == "calibrate":
        _calibrate()
    else:
        from rvcoax.results.cli.app import run

        extra = ["--samples", str(samples)] if name.startswith("montecarlo") else []
        sys.argv = ["rvcoax", *RUNS[name], *extra, "--out", out]
        try:
            run(end_process=False)
        except SystemExit as stop:  # check: 0, 1 or 3 are verdicts on the table, 2 a user error
            if stop.code not in (0, None, 1, 3):
                raise
    print("RESULT " + json.dumps({"estimate": clock.estimate, "test": clock.test, "instrument": clock.instrument,
                                  "calls": clock.calls, "part": clock.part,
                                  "values": clock.values}), flush=True)


def measure(name: str, samples: int) -> dict:
    with tempfile.TemporaryDirectory() as out:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        done = subprocess.run([sys.executable, __file__, "--child", name, out, str(samples)], capture_output=True,
                              text=True, check=False)
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    lines = [line for line in done.stdout.splitlines() if line.startswith("RESULT ")]
    if done.returncode != 0 or not lines:
        return {"failed": (done.stderr or done.stdout).strip().splitlines()[-3:]}
    found = json.loads(lines[-1][len("RESULT "):])
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    found["whole"] = [cpu - found["instrument"][0], wall - found["instrument"][1]]
    found["peak_MB"] = after.ru_maxrss / 1024.0
    return found


def row(name: str, found: dict) -> tuple[str, str]:
    if "failed" in found:
        return name, "failed: " + " / ".join(found["failed"])
    whole, estimate, test = found["whole"], found["estimate"], found["test"]
    calls = found["calls"]
    if not calls:
        text = (f"whole {whole[0]:.2f} s CPU ({whole[1]:.2f} s wall); no condition estimate; "
                f"singularity test {test[0]:.2f} s CPU")
        return name, text
    setups = len(calls)
    pattern = ", ".join(str(c) for c in calls[0])
    text = (f"whole {whole[0]:.2f} s CPU ({whole[1]:.2f} s wall); estimate {estimate[0]:.2f} s CPU "
            f"({estimate[1]:.2f} s wall) = **{100 * estimate[0] / whole[0]:.1f} %** CPU, "
            f"{100 * estimate[1] / whole[1]:.1f} % wall; singularity test {test[0]:.2f} s CPU; "
            f"{setups} estimate(s), the first {len(calls[0])} solve calls of [{pattern}] columns "
            f"(the test's columns included)")
    values = found.get("values") or []
    if values:
        text += f"; estimate {values[0][0]:.6g}" + (f" (full search {values[0][1]:.6g})" if values[0][1] else "")
    if found.get("part"):
        part = found["part"]
        text += (f"; of the set-up and solve alone ({part[0]:.2f} s CPU, {part[1]:.2f} s wall) "
                 f"{100 * estimate[0] / part[0]:.1f} % CPU")
    return name, text


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="*", default=DEFAULT_RUNS, help=f"any of {', '.join(RUNS)}")
    parser.add_argument("--samples", type=int, default=4, help="Monte Carlo samples (default 4)")
    parser.add_argument("--label", default="", help="what the code measured is (e.g. a commit)")
    parser.add_argument("--no-record", action="store_true")
    parser.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.child[0], args.child[1], int(args.child[2]))
        return
    unknown = [r for r in args.runs if r not in RUNS]
    if unknown:
        parser.error(f"unknown run(s) {', '.join(unknown)}; choose from {', '.join(RUNS)}")
    from machine import publish

    load_before = os.getloadavg()[0]
    rows = []
    for name in args.runs:
        rows.append(row(name, measure(name, args.samples)))
        print(f"{rows[-1][0]}: {rows[-1][1]} (load {os.getloadavg()[0]:.1f})", flush=True)
    label = f" ({args.label})" if args.label else ""
    publish(f"Condition estimate's share of whole runs (bench_condition_share.py){label}", rows, load_before,
            keep=not args.no_record)


if __name__ == "__main__":
    main()
