"""Natural modes of the reference rig: 20 modes of the beam model (target < 1 s) and of the hybrid model at the
default mesh (target < 15 s on 2 cores), each as `rvcoax.modes` does it (assembly, factorisation, mass,
shift-invert Lanczos, the per-mode analysis), wall and CPU time with the process's peak memory.

Usage::

    python benchmarks/bench_modes.py [--model beam|hybrid|both] [--no-record]

Each model runs in a child process of its own (a fresh peak memory); the figures go to RESULTS.md.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import publish  # noqa: E402

CHILD = """
import json, resource, time, os
import rvcoax
from rvcoax.fem import avoid_compaction_stalls, single_threaded_openblas
avoid_compaction_stalls(); single_threaded_openblas()
rig = rvcoax.load_rig()
from rvcoax.results.studies.modes import run_modes  # imports are not the modes' time
from rvcoax.results.io import fields  # noqa: F401
wall, cpu = time.perf_counter(), time.process_time()
study = rvcoax.modes(rig, n_modes=20, model=MODEL)
out = {"wall_s": time.perf_counter() - wall, "cpu_s": time.process_time() - cpu,
       "peak_MiB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, "n_dofs": study.system.n_dofs,
       "phases": study.seconds, "f_Hz": [m.frequency_hz for m in study.cases[0].modes]}
print(json.dumps(out))
"""


def run(model: str) -> dict:
    code = CHILD.replace("MODEL", repr(model))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", choices=("beam", "hybrid", "both"), default="both")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    load = os.getloadavg()[0]
    rows = []
    for model in ("beam", "hybrid") if args.model == "both" else (args.model,):
        started = time.perf_counter()
        result = run(model)
        phases = ", ".join(f"{k} {v:.2f}" for k, v in result["phases"].items())
        target = 1.0 if model == "beam" else 15.0
        rows += [(f"{model}: 20 modes, wall (target < {target:g} s)",
                  f"{result['wall_s']:.2f} s ({'met' if result['wall_s'] < target else 'NOT met'}); CPU "
                  f"{result['cpu_s']:.2f} s; phases: {phases}"),
                 (f"{model}: peak memory", f"{result['peak_MiB']:.0f} MiB ({result['n_dofs']} DOF)"),
                 (f"{model}: f1 … f20 Hz", ", ".join(f"{f:.1f}" for f in result["f_Hz"])),
                 (f"{model}: child process incl. imports", f"{time.perf_counter() - started:.1f} s")]
    publish("bench_modes.py: natural modes of the reference rig", rows, load, keep=not args.no_record)


if __name__ == "__main__":
    main()
