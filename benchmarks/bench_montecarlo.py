"""Monte Carlo throughput: samples per second, beam and hybrid, serial and on a local Dask cluster.

Run: ``.venv/bin/python benchmarks/bench_montecarlo.py [--beam-samples N] [--hybrid-samples N]``.
Prints the figures and appends them to benchmarks/RESULTS.md with the machine and date.

Measured, each with the example tolerance file (loadcases/data/example_tolerances.toml, 16
parameters, 2 load cases) on the reference rig:

- beam model, serial, one sample = 2 load cases, for the three reuse strategies: ``loads`` (only
  the load parameters of the file toleranced), ``frame`` (the whole file: springs change) and
  ``full`` (the whole file, every sample assembled from scratch);
- beam model through :func:`rvcoax.results.studies.distributed.run_samples`: serial, and a local Dask cluster of
  1 and 2 worker processes, end to end (cluster start included) and in steady state (first to
  last result);
- hybrid model (default 4 mm mesh), ``frame`` strategy: nominal set-up and per-sample time
  serially, a local cluster of 2 workers, the peak memory of a worker, and the largest difference
  between a sample on the reused model and the same sample assembled from scratch;
- ``--per-sample beam,hybrid,solid`` (alone with ``--only-per-sample``): the cost of each sample, wall
  and CPU time, serially in this process and in each worker of a local cluster of 2 processes, first
  sample (the worker's nominal model: meshing, assembly, PARDISO's analysis) apart from the later
  ones, with how many of each worker's factorisations ran on a pooled PARDISO analysis (the
  symbolic factorisation kept per sparsity pattern, rvcoax.fem.pardiso) and the worker's peak memory.
  The solid model runs on a coarse mesh (``--solid-mesh-mm``, default 12 mm).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import record  # noqa: E402

EXAMPLE = Path(__file__).resolve().parents[1] / "loadcases" / "data" / "example_tolerances.toml"


def peak_rss_mb() -> float:
    """Peak resident memory of this process (MB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def load_only(tolerances):
    """The tolerance file restricted to the parameters that only change loads."""
    from rvcoax.results.studies.montecarlo import classify_parameter
    from rvcoax.results.studies.tolerances import study_rig

    rig = study_rig(RIG, tolerances)
    kept = tuple(p for p in tolerances.parameters
                 if classify_parameter(rig, p.address, float(p.distribution.quantile(0.9))) == "loads")
    return dataclasses.replace(tolerances, parameters=kept)


def serial_rate(study, values) -> tuple[float, float]:
    """(seconds for the first sample, samples per second after it), evaluated in this process."""
    from rvcoax.results.studies.montecarlo import evaluate_sample

    start = time.perf_counter()
    evaluate_sample(study, values[0])
    first = time.perf_counter() - start
    start = time.perf_counter()
    for row in values[1:]:
        evaluate_sample(study, row)
    return first, (len(values) - 1) / (time.perf_counter() - start)


def cluster_run(study, values, scheduler: str, workers: int | None) -> dict:
    """End-to-end and steady-state rate of :func:`run_samples`, and the workers' peak memory."""
    from rvcoax.results.studies.distributed import run_samples
    from rvcoax.results.studies.montecarlo import evaluate_sample

    stamps = []
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        _, report = run_samples(evaluate_sample, study, values, folder, f"bench-{scheduler}-{workers}", scheduler=scheduler,
                                workers=workers, on_result=lambda index, result: stamps.append(time.perf_counter()))
        total = time.perf_counter() - start
    steady = (len(stamps) - 1) / (stamps[-1] - stamps[0]) if len(stamps) > 1 else float("nan")
    return {"total_s": total, "end_to_end": len(values) / total, "steady": steady, "first_result_s": stamps[0] - start,
            "workers": report.workers}


def _process_counts() -> dict:
    """This process's counts of samples and of PARDISO factorisations on a pooled analysis or a fresh one.

    Kept on the imported pardiso module's class, so that they last across the tasks a worker runs (this
    function reaches the workers by value, with its globals).
    """
    from rvcoax.fem import pardiso

    counts = getattr(pardiso.Factorization, "_bench_counts", None)
    if counts is None:
        counts = {"fresh": 0, "reused": 0, "samples": 0}
        original = pardiso.Factorization.__init__

        def counted(self, *args, **kwargs):
            original(self, *args, **kwargs)
            if not kwargs.get("analysis_only", False):
                counts["reused" if self.reused_analysis else "fresh"] += 1

        pardiso.Factorization.__init__ = counted
        pardiso.Factorization._bench_counts = counts
    return counts


def timed_sample(study, values) -> dict:
    """:func:`evaluate_sample` with its wall and CPU time, the process and its PARDISO analyses so far."""
    from rvcoax.results.studies.montecarlo import evaluate_sample

    counts = _process_counts()
    before, start = resource.getrusage(resource.RUSAGE_SELF), time.perf_counter()
    result = evaluate_sample(study, values)
    after = resource.getrusage(resource.RUSAGE_SELF)
    result.update(wall_s=time.perf_counter() - start, pid=os.getpid(), peak_rss_mb=peak_rss_mb(),
                  cpu_s=after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime,
                  fresh_analyses=counts["fresh"], reused_analyses=counts["reused"], sequence=counts["samples"])
    counts["samples"] += 1
    return result


def _split(samples: list[dict], memory: bool = True) -> str:
    """'first … s CPU (… s wall), later … s CPU (… s wall) per sample' of one process's samples in order."""
    first, later = samples[0], samples[1:]
    text = f"first {first['cpu_s']:.2f} s CPU ({first['wall_s']:.2f} s wall)"
    if later:
        text += (f", later {np.mean([r['cpu_s'] for r in later]):.3f} s CPU "
                 f"({np.mean([r['wall_s'] for r in later]):.3f} s wall) per sample over {len(later)}")
    last = samples[-1]
    text += f"; PARDISO analyses fresh {last['fresh_analyses']}, reused {last['reused_analyses']} (process total)"
    # a worker's ru_maxrss starts at its parent's when the worker is forked: only this process's is its own
    return text + (f"; peak RSS {last['peak_rss_mb']:.0f} MB" if memory else "")


def per_sample(model: str, rig, tolerances, n_serial: int, n_cluster: int, mesh_mm: float | None) -> list[tuple[str, str]]:  # noqa: PLR0913
    """Per-sample cost of ``model`` serially (this process) and per worker of a local 2-process cluster
    (``n_cluster`` = 0: serially only)."""
    import logging

    from distributed import Client, LocalCluster

    from rvcoax.results.studies.distributed import run_samples
    from rvcoax.results.studies.montecarlo import plan_study
    from rvcoax.results.studies.sampling import sample_values
    from rvcoax.results.sweep import SweepSettings

    study = plan_study(rig, tolerances, SweepSettings(model=model, mesh_size_mm=mesh_mm))
    tag = f"{model}{f' ({mesh_mm:g} mm)' if mesh_mm else ''}, strategy {study.strategy}"
    values = sample_values(tolerances.distributions, max(n_serial, n_cluster), "lhs", seed=3)
    serial = [timed_sample(study, row) for row in values[:n_serial]]
    rows = [(f"per sample, {tag}, serial in process", _split(serial))]
    print(rows[-1], flush=True)
    if n_cluster == 0:
        return rows
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None, silence_logs=logging.ERROR) as cluster, Client(cluster):
        with tempfile.TemporaryDirectory() as folder:
            start = time.perf_counter()
            results, _ = run_samples(timed_sample, study, values[:n_cluster], folder, f"bench-{model}",
                                     scheduler=cluster.scheduler_address)
            total = time.perf_counter() - start
    by_worker: dict[int, list[dict]] = {}
    for result in sorted(results, key=lambda r: r["sequence"]):
        by_worker.setdefault(result["pid"], []).append(result)
    for k, samples in enumerate(by_worker.values()):
        rows.append((f"per sample, {tag}, local cluster of 2 workers: worker {k + 1}", _split(samples, memory=False)))
    rows.append((f"per sample, {tag}, local cluster of 2 workers: {n_cluster} samples",
                 f"{total:.1f} s wall end to end (cluster start included)"))
    serial_y = np.array([r["Y_max_mm"] for r in serial])
    cluster_y = np.array([r["Y_max_mm"] for r in results[:n_serial]])
    rows.append((f"per sample, {tag}: cluster vs serial, largest ΔY / largest Y",
                 f"{np.abs(serial_y - cluster_y).max() / np.abs(serial_y).max():.1e}"))
    for row in rows[1:]:
        print(row, flush=True)
    return rows


def worker_memory(study, values, workers: int) -> tuple[dict, list[float]]:
    """Run on a local cluster and read every worker's peak memory (MB) before it closes."""
    import logging

    from distributed import Client, LocalCluster

    from rvcoax.results.studies.distributed import run_samples
    from rvcoax.results.studies.montecarlo import evaluate_sample

    stamps = []
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None, silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        with tempfile.TemporaryDirectory() as folder:
            start = time.perf_counter()
            run_samples(evaluate_sample, study, values, folder, "bench-hybrid", scheduler=cluster.scheduler_address,
                        on_result=lambda index, result: stamps.append(time.perf_counter()))
            total = time.perf_counter() - start
        memory = list(client.run(peak_rss_mb).values())
    steady = (len(stamps) - 1) / (stamps[-1] - stamps[0]) if len(stamps) > 1 else float("nan")
    return {"total_s": total, "end_to_end": len(values) / total, "steady": steady,
            "first_result_s": stamps[0] - start}, memory


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--beam-samples", type=int, default=400)
    parser.add_argument("--hybrid-samples", type=int, default=8)
    parser.add_argument("--per-sample", default="", help="comma-separated models (beam, hybrid, solid) whose "
                        "per-sample cost to measure serially and per worker of a 2-process cluster")
    parser.add_argument("--per-sample-n", type=int, default=6, help="samples per cluster run (serial: half)")
    parser.add_argument("--serial-only", action="store_true", help="per-sample cost: no cluster run")
    parser.add_argument("--solid-mesh-mm", type=float, default=12.0, help="mesh size of the solid model's parts")
    parser.add_argument("--only-per-sample", action="store_true", help="skip the throughput figures")
    args = parser.parse_args()

    import numpy as np

    from rvcoax.results.studies.montecarlo import Study, evaluate_sample, plan_study
    from rvcoax.results.studies.sampling import sample_values
    from rvcoax.results.studies.tolerances import load_tolerances
    from rvcoax.results.sweep import SweepSettings

    started = time.perf_counter()
    load_before = os.getloadavg()[0]
    tolerances = load_tolerances(EXAMPLE, RIG)
    values = sample_values(tolerances.distributions, args.beam_samples, "lhs", seed=1)
    figures: list[tuple[str, str]] = [("tolerance file", f"{EXAMPLE.name}: {len(tolerances.parameters)} parameters, "
                                                         f"{len(tolerances.cases)} load cases per sample")]

    for model in [m.strip() for m in args.per_sample.split(",") if m.strip()]:
        figures += per_sample(model, RIG, tolerances, max(2, args.per_sample_n // 2),
                              0 if args.serial_only else args.per_sample_n, args.solid_mesh_mm if model == "solid" else None)
    if args.only_per_sample:
        figures.append(("load average (1 min) before / after", f"{load_before:.2f} / {os.getloadavg()[0]:.2f}"))
        record("bench_montecarlo.py: Monte Carlo cost per sample, serial and per worker of a 2-process cluster", figures)
        return

    loads_file = load_only(tolerances)
    loads_study = plan_study(RIG, loads_file)
    loads_values = sample_values(loads_file.distributions, args.beam_samples, "lhs", seed=1)
    frame_study = plan_study(RIG, tolerances)
    full_study = Study(frame_study.rig, frame_study.cases, frame_study.settings, frame_study.addresses, "full",
                       frame_study.key + "-full")
    for study, rows in ((loads_study, loads_values), (frame_study, values),
                        (full_study, values[: max(20, args.beam_samples // 4)])):
        first, rate = serial_rate(study, rows)
        figures.append((f"beam, strategy {study.strategy} ({len(study.addresses)} parameters), serial in process",
                        f"{rate:.1f} samples/s ({1e3 / rate:.1f} ms per sample; first sample with set-up "
                        f"{1e3 * first:.0f} ms)"))
        print(figures[-1])

    for scheduler, workers in (("serial", None), ("local", 1), ("local", 2)):
        found = cluster_run(frame_study, values, scheduler, workers)
        label = "serial (run_samples, files written)" if scheduler == "serial" else f"local cluster, {workers} worker(s)"
        figures.append((f"beam, strategy frame, {args.beam_samples} samples, {label}",
                        f"{found['end_to_end']:.1f} samples/s end to end ({found['total_s']:.1f} s, first result "
                        f"after {found['first_result_s']:.1f} s); steady {found['steady']:.1f} samples/s"))
        print(figures[-1])

    hybrid = plan_study(RIG, tolerances, SweepSettings(model="hybrid"))
    hybrid_values = sample_values(tolerances.distributions, args.hybrid_samples, "lhs", seed=2)
    before = peak_rss_mb()
    first, rate = serial_rate(hybrid, hybrid_values)
    figures.append((f"hybrid (4 mm), strategy {hybrid.strategy}, {args.hybrid_samples} samples, serial in process",
                    f"nominal set-up + first sample {first:.1f} s, then {rate:.3f} samples/s "
                    f"({1 / rate:.2f} s per sample); peak memory {peak_rss_mb():.0f} MB (before: {before:.0f} MB)"))
    print(figures[-1])
    fresh = Study(hybrid.rig, hybrid.cases, hybrid.settings, hybrid.addresses, "full", hybrid.key + "-full")
    reused, rebuilt = evaluate_sample(hybrid, hybrid_values[0]), evaluate_sample(fresh, hybrid_values[0])
    difference = np.abs(np.subtract(reused["Y_max_mm"], rebuilt["Y_max_mm"])).max() / np.abs(rebuilt["Y_max_mm"]).max()
    figures.append(("hybrid: reused model (frame) vs the sample assembled from scratch, largest ΔY / largest Y",
                    f"{difference:.2e}"))
    print(figures[-1])
    found, memory = worker_memory(hybrid, hybrid_values, 2)
    figures.append((f"hybrid (4 mm), strategy frame, {args.hybrid_samples} samples, local cluster, 2 workers",
                    f"{found['end_to_end']:.3f} samples/s end to end ({found['total_s']:.1f} s, first result after "
                    f"{found['first_result_s']:.1f} s); steady {found['steady']:.3f} samples/s"))
    figures.append(("hybrid: peak memory per worker (MB)", ", ".join(f"{m:.0f}" for m in memory)))
    print(figures[-2:])

    figures.append(("load average (1 min) before / after", f"{load_before:.2f} / {os.getloadavg()[0]:.2f}"))
    figures.append(("script runtime", f"{time.perf_counter() - started:.0f} s"))
    width = max(len(name) for name, _ in figures)
    for name, value in figures:
        print(f"{name:<{width}}  {value}")
    record("bench_montecarlo.py: Monte Carlo samples per second, serial and Dask", figures)


if __name__ == "__main__":  # worker processes are spawned: nothing runs on import
    from rvcoax.geometry.rigfile import load_rig

    RIG = load_rig()
    main()
