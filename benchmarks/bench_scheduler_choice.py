"""Serial against a local Dask cluster for Monte Carlo studies, and what ``--scheduler auto`` picks.

The reference rig's beam model with the example tolerance file (16 parameters, 2 load cases per
sample, ``frame`` strategy), through :func:`rvcoax.results.studies.distributed.run_samples` end to end
(files written, cluster start included) for each study size: serial, a local cluster of one worker per
core, and ``auto`` (its choice and estimates). All three give the same floats (checked). The break-even
of the cost model (:func:`rvcoax.results.studies.distributed.choose_scheduler`) is printed for this
machine's core count with the measured time per sample.

Run: ``.venv/bin/python benchmarks/bench_scheduler_choice.py [--samples 64,400]``; appends to
benchmarks/RESULTS.md (``--no-record``: print only).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import publish  # noqa: E402

EXAMPLE = Path(__file__).resolve().parents[1] / "loadcases" / "data" / "example_tolerances.toml"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", default="64,400")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    from rvcoax.geometry.rigfile import load_rig
    from rvcoax.results.studies.distributed import CLUSTER_START_SECONDS, PAYS_BELOW, TASK_OVERHEAD_SECONDS, run_samples
    from rvcoax.results.studies.montecarlo import evaluate_sample, plan_study
    from rvcoax.results.studies.sampling import sample_values
    from rvcoax.results.studies.tolerances import load_tolerances

    load_before = os.getloadavg()[0]
    rig = load_rig()
    tolerances = load_tolerances(EXAMPLE, rig)
    study = plan_study(rig, tolerances)
    begin = time.perf_counter()
    evaluate_sample(study, sample_values(tolerances.distributions, 1, "lhs", seed=1)[0])
    setup = time.perf_counter() - begin
    rows = [("study", f"beam model, example_tolerances.toml, strategy {study.strategy}, "
                      f"{len(study.cases)} load cases per sample; nominal set-up and first sample {setup:.2f} s")]
    with tempfile.TemporaryDirectory() as folder:
        for n in (int(text) for text in args.samples.split(",")):
            values = sample_values(tolerances.distributions, n, "lhs", seed=5)
            found = {}
            for scheduler in ("serial", "local", "auto"):
                found[scheduler] = run_samples(evaluate_sample, study, values, Path(folder) / f"{n}-{scheduler}",
                                               f"bench-{n}-{scheduler}", scheduler=scheduler, setup_seconds=setup)
            same = found["serial"][0] == found["local"][0] == found["auto"][0]
            serial, local, auto = (found[s][1] for s in ("serial", "local", "auto"))
            rows.append((f"{n} samples: serial / local cluster ({local.workers} workers) / auto",
                         f"{serial.seconds:.1f} s / {local.seconds:.1f} s / {auto.seconds:.1f} s; auto chose "
                         f"{auto.choice.describe()}; same results: {same}"))
            per_sample = serial.seconds / n
    cores = os.cpu_count() or 1
    effective = max(1, cores - 1)
    margin = PAYS_BELOW * per_sample - (per_sample + TASK_OVERHEAD_SECONDS) / effective
    if margin > 0:
        even = (CLUSTER_START_SECONDS + setup) / margin
        rows.append(("cost-model break-even on this machine",
                     f"{cores} cores: the cluster is chosen from about {even:.0f} samples of {per_sample * 1e3:.1f} ms"))
    else:
        rows.append(("cost-model break-even on this machine",
                     f"{cores} cores: never (min(workers, cores - 1) = {effective}: no speed-up to pay the start-up)"))
    publish("bench_scheduler_choice.py: Monte Carlo serial against a local Dask cluster, and the auto choice", rows,
            load_before, not args.no_record)


if __name__ == "__main__":
    main()
