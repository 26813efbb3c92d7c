"""Time the 20-case paper sweep on the reference rig (beam model), end to end and per case.

Run: ``make bench`` (or ``.venv/bin/python benchmarks/bench_sweep.py``). Prints the figures and
appends them to benchmarks/RESULTS.md with the machine and date.
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import record  # noqa: E402

from rvcoax.geometry.model.beam import build_rig_model  # noqa: E402
from rvcoax.geometry.rigfile import load_rig  # noqa: E402
from rvcoax.loadcases.cases import paper_cases, paper_table  # noqa: E402
from rvcoax.results.studies.calibration import calibrate  # noqa: E402
from rvcoax.results.sweep import SweepSettings, run_sweep, solve_unit_responses  # noqa: E402

REPEATS = 5


def best_of(function, repeats: int = REPEATS) -> tuple[float, float]:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times), statistics.median(times)


def main() -> None:
    rig = load_rig()
    cases = paper_cases()
    frame = build_rig_model(rig)
    figures: list[tuple[str, str]] = [("model", f"beam, {frame.structure.n_nodes} nodes, {frame.structure.n_dofs} DOF")]
    t_load, _ = best_of(load_rig)
    t_build, _ = best_of(lambda: build_rig_model(rig))
    t_factor, _ = best_of(lambda: solve_unit_responses(frame))
    t_sweep, t_sweep_median = best_of(lambda: run_sweep(rig, cases))
    t_direct, _ = best_of(lambda: run_sweep(rig, cases, SweepSettings(method="direct")))
    t_single, _ = best_of(lambda: run_sweep(rig, cases[:1]))
    start = time.perf_counter()
    calibrate(rig, paper_table())
    t_calibrate = time.perf_counter() - start
    figures += [
        ("load + validate rig file", f"{1e3 * t_load:.1f} ms"),
        ("build beam model", f"{1e3 * t_build:.1f} ms"),
        ("assemble + mechanism check + factorise + 6 unit solves", f"{1e3 * t_factor:.1f} ms"),
        ("20-case sweep end to end, superposition (best / median of 5)", f"{1e3 * t_sweep:.1f} / {1e3 * t_sweep_median:.1f} ms"),
        ("per case, superposition (incl. equilibrium check)", f"{1e3 * (t_sweep - t_single) / (len(cases) - 1):.2f} ms"),
        ("20-case sweep end to end, direct solve per case", f"{1e3 * t_direct:.1f} ms"),
        ("per case, direct", f"{1e3 * (t_direct - t_single) / (len(cases) - 1):.2f} ms"),
        ("calibration (4 parameters, multi-start least squares)", f"{t_calibrate:.2f} s"),
    ]
    width = max(len(name) for name, _ in figures)
    for name, value in figures:
        print(f"{name:<{width}}  {value}")
    record("bench_sweep.py: 20-case paper sweep, beam model", figures)


if __name__ == "__main__":
    main()
