"""PARDISO's analysis (ordering + symbolic factorisation) reused across matrices of one pattern.

Run: ``.venv/bin/python benchmarks/bench_symbolic_reuse.py [--h 4.0] [--samples 3] [--no-record]``.

Two measurements, each with the pool of analyses on and off (:func:`rvcoax.fem.pardiso.set_analysis_reuse`),
in one process, CPU time (user + system of this process, ``time.process_time``) beside wall time, because
the machine these figures come from is shared:

- **solid cantilever** (bench_solid_scaling.py's mesh at ``--h``; SPD, 3 × 3 blocks): the stiffness with
  ν = 0.30, then with ν = 0.28 (another matrix, the same pattern) through ``solvers.prepare(..., "pardiso")``;
  per PARDISO phase, and the largest difference of the second solution between reuse and a fresh analysis;
- **hybrid Monte Carlo** (reference rig, loadcases/data/example_tolerances.toml, strategy ``frame``: each
  sample re-assembles the springs and factorises the saddle-point matrix anew): ``--samples`` samples serially
  after the nominal model, per-sample CPU and PARDISO phases, and the largest relative difference of Y and β
  between the two runs (the indefinite analysis' matching and scaling come from another sample's values).

- with ``--cluster-samples N``: the same study on a local Dask cluster of 2 worker processes, each sample's CPU
  time in its worker and whether it ran an analysis (a worker keeps its nominal model and its pool of analyses).

``--h 0`` and ``--samples 0`` skip the first two. Appends the figures to benchmarks/RESULTS.md unless ``--no-record``.
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import publish  # noqa: E402

EXAMPLE = Path(__file__).resolve().parents[1] / "loadcases" / "data" / "example_tolerances.toml"


class PhaseClock:
    """CPU seconds and calls per PARDISO phase (11 analysis, 22 factorisation, 33 solve, 0/−1 release)."""

    def __init__(self):
        from rvcoax.fem import pardiso

        self.seconds = collections.Counter()
        self.calls = collections.Counter()
        original = pardiso._phase

        def timed(handle, iparm, mtype, phase, storage, rhs):
            start = time.process_time()
            try:
                return original(handle, iparm, mtype, phase, storage, rhs)
            finally:
                self.seconds[phase] += time.process_time() - start
                self.calls[phase] += 1

        pardiso._phase = timed

    def reset(self):
        self.seconds.clear()
        self.calls.clear()

    def text(self) -> str:
        names = {11: "analysis", 22: "factorisation", 33: "solves"}
        return ", ".join(f"{names[p]} {self.seconds[p]:.2f} s ({self.calls[p]})" for p in (11, 22, 33))


def cantilever(h: float, poisson: float, cache: str):
    """bench_solver_choice.py's clamped cantilever with Poisson's ratio ``poisson``: (stiffness, tip load)."""
    from bench_solver_choice import system

    stiffness, force, _ = system(h, cache, poisson)
    return stiffness, force


def solid_rows(h: float, clock: PhaseClock) -> list[tuple[str, str]]:
    import numpy as np

    from rvcoax.fem import pardiso, solvers

    with tempfile.TemporaryDirectory() as cache:
        first, force = cantilever(h, 0.30, cache)
        second, _ = cantilever(h, 0.28, cache)
    rows = []
    solutions = {}
    for reuse in (True, False):
        pardiso.set_analysis_reuse(reuse)
        pardiso.clear_analysis_pool()
        solvers.prepare(first, "pardiso").release()
        clock.reset()
        cpu, wall = time.process_time(), time.perf_counter()
        solver = solvers.prepare(second, "pardiso")
        cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        solutions[reuse] = solver.solve(force)
        solver.release()
        rows.append((f"solid cantilever h = {h} mm ({second.shape[0]:,} DOF, {second.nnz:,} nonzeros), second matrix "
                     f"of the pattern, analysis {'reused' if reuse else 'fresh'}",
                     f"set-up CPU {cpu:.2f} s, wall {wall:.2f} s; PARDISO {clock.text()}"))
    pardiso.set_analysis_reuse(True)
    difference = np.abs(solutions[True] - solutions[False]).max() / np.abs(solutions[False]).max()
    rows.append(("solid cantilever: second solution, reused against fresh analysis (largest |Δu| / largest |u|)",
                 f"{difference:.1e}" + (" (bit-identical)" if difference == 0.0 else "")))
    return rows


def hybrid_rows(samples: int, clock: PhaseClock) -> list[tuple[str, str]]:
    import numpy as np

    from rvcoax.fem import pardiso
    from rvcoax.geometry.rigfile import load_rig
    from rvcoax.results.studies.montecarlo import evaluate_sample, plan_study
    from rvcoax.results.studies.sampling import sample_values
    from rvcoax.results.studies.tolerances import load_tolerances
    from rvcoax.results.sweep import SweepSettings

    rig = load_rig()
    tolerances = load_tolerances(EXAMPLE, rig)
    study = plan_study(rig, tolerances, SweepSettings(model="hybrid"))
    values = sample_values(tolerances.distributions, samples, "lhs", seed=2)
    evaluate_sample(study, values[0])  # the nominal model (memoised per process) and a warm-up sample
    rows, results = [], {}
    for reuse in (True, False):
        pardiso.set_analysis_reuse(reuse)
        evaluate_sample(study, values[0])  # puts this mode's analysis in the pool (or not)
        clock.reset()
        cpu, wall = time.process_time(), time.perf_counter()
        results[reuse] = [evaluate_sample(study, row) for row in values]
        cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        rows.append((f"hybrid Monte Carlo (strategy {study.strategy}, {len(study.addresses)} parameters, "
                     f"{len(study.cases)} cases), {samples} samples, analysis {'reused' if reuse else 'fresh'}",
                     f"{cpu / samples:.2f} s CPU per sample ({wall / samples:.2f} s wall); PARDISO per sample: "
                     + ", ".join(f"{n} {clock.seconds[p] / samples:.2f} s" for p, n in
                                 ((11, "analysis"), (22, "factorisation"), (33, "solves")))))
    pardiso.set_analysis_reuse(True)
    worst = 0.0
    for key in ("Y_max_mm", "beta_deg"):
        a = np.array([r[key] for r in results[True]])
        b = np.array([r[key] for r in results[False]])
        worst = max(worst, float(np.abs(a - b).max() / np.abs(b).max()))
    rows.append(("hybrid: samples on a reused analysis against fresh ones, largest |ΔY| or |Δβ| / largest value",
                 f"{worst:.1e}"))
    return rows


def timed_sample(study, row) -> tuple[float, int, int]:
    """In a Dask worker: (CPU seconds, PARDISO analyses, numerical factorisations) of one sample."""
    from rvcoax.fem import pardiso
    from rvcoax.results.studies.montecarlo import evaluate_sample

    if not hasattr(pardiso, "_bench_clock"):
        pardiso._bench_clock = PhaseClock()
    clock = pardiso._bench_clock
    analyses, factorisations = clock.calls[11], clock.calls[22]
    start = time.process_time()
    evaluate_sample(study, row)
    return time.process_time() - start, clock.calls[11] - analyses, clock.calls[22] - factorisations


def cluster_rows(samples: int) -> list[tuple[str, str]]:
    """The hybrid study on a local cluster of 2 worker processes: each keeps its nominal model and its analysis."""
    import logging

    from distributed import Client, LocalCluster

    from rvcoax.geometry.rigfile import load_rig
    from rvcoax.results.studies.montecarlo import plan_study
    from rvcoax.results.studies.sampling import sample_values
    from rvcoax.results.studies.tolerances import load_tolerances
    from rvcoax.results.sweep import SweepSettings

    rig = load_rig()
    tolerances = load_tolerances(EXAMPLE, rig)
    study = plan_study(rig, tolerances, SweepSettings(model="hybrid"))
    values = sample_values(tolerances.distributions, samples, "lhs", seed=3)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None,
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        start = time.perf_counter()
        futures = [client.submit(timed_sample, study, row, pure=False) for row in values]
        found = [(future.result(), next(iter(client.who_has(future)[future.key]))) for future in futures]
        wall = time.perf_counter() - start
    rows = []
    for worker in sorted({w for _, w in found}):
        mine = [r for r, w in found if w == worker]
        text = "; ".join(f"{cpu:.2f} s CPU ({a} analysis, {f} factorisation)" for cpu, a, f in mine)
        rows.append((f"hybrid Monte Carlo on a local cluster, 2 worker processes: worker {len(rows) + 1}, its samples in "
                     "order (the first builds the memoised nominal model)", text))
    later = [cpu for (cpu, a, _), _ in found if a == 0]
    if later:
        rows.append(("hybrid, cluster: CPU per sample on a reused analysis (worker processes)",
                     f"{sum(later) / len(later):.2f} s over {len(later)} samples; {samples} samples in {wall:.0f} s wall"))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--h", type=float, default=4.0, help="cantilever mesh size, mm (4.0: about 61 k DOF)")
    parser.add_argument("--samples", type=int, default=3)
    parser.add_argument("--cluster-samples", type=int, default=0, help="also run this many on 2 Dask workers")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    from rvcoax.fem import blas_threads, hugepages

    hugepages.avoid_compaction_stalls()
    blas_threads.single_threaded_openblas()
    load_before = os.getloadavg()[0]
    clock = PhaseClock()
    rows = [("timer", "CPU = time.process_time() of this process (both MKL threads); wall beside it (shared machine)")]
    if args.h > 0:
        rows += solid_rows(args.h, clock)
    for row in rows[-3:]:
        print(row)
    if args.samples > 0:
        rows += hybrid_rows(args.samples, clock)
    if args.cluster_samples > 0:
        rows += cluster_rows(args.cluster_samples)
    publish("bench_symbolic_reuse.py: PARDISO's analysis reused per sparsity pattern", rows, load_before,
            keep=not args.no_record)


if __name__ == "__main__":
    main()
