"""The C heap's policy (``rvcoax.fem.memory.apply_heap_policy``) on ``rvcoax check``: page faults, CPU and peak, on and off.

Runs ``rvcoax check --model MODEL --out DIR`` in fresh processes, alternately as shipped ("on": a model small against
the memory available keeps freed heap memory for reuse) and with the policy replaced by a no-op ("off": glibc's
defaults, freed memory given back before each factorisation), ``--runs`` times each. Per run, from the process's
resource usage (``os.wait4``, its picture process included): minor page faults, user and system CPU time, peak
resident memory (decimal bytes) and wall time; printed as medians and ranges, with whether every result file of every
run is identical byte for byte (a policy that only places arrays must not change a digit). Run:
``.venv/bin/python benchmarks/bench_heap_policy.py [--model hybrid] [--runs 3] [--no-record]``; appends the figures to
benchmarks/RESULTS.md with the machine, the date and the load average (without ``--no-record``).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import publish  # noqa: E402

LAUNCH = """
import sys
if sys.argv[1] == "off":
    from rvcoax.fem import memory
    memory.apply_heap_policy = lambda peak, available_bytes=None: memory.HeapPolicy(False, "off: measurement")
from rvcoax.results.cli.app import run
sys.argv = ["rvcoax", *sys.argv[2:]]
run()
"""
CHECK_EXIT_STATUSES = (0, 1, 3)  # within, outside, within only with implausible parameters: the check ran


def one_run(policy: str, model: str, out: Path) -> dict:
    """One ``rvcoax check`` in a fresh process with the policy ``on`` or ``off``: its resource usage and wall time."""
    start = time.perf_counter()
    child = subprocess.Popen([sys.executable, "-c", LAUNCH, policy, "check", "--model", model, "--out", str(out)],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    stderr = child.stderr.read()
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode not in CHECK_EXIT_STATUSES:
        raise SystemExit(f"rvcoax check ({policy}) failed with status {child.returncode}:\n{stderr.decode()[-2000:]}")
    return {"faults": usage.ru_minflt, "user_s": usage.ru_utime, "sys_s": usage.ru_stime,
            "peak_bytes": usage.ru_maxrss * 1024.0, "wall_s": wall}


def same_files(folders: list[Path]) -> bool:
    """Whether every folder holds the same files with the same bytes."""
    def contents(folder: Path) -> dict[str, bytes]:
        return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}

    first = contents(folders[0])
    return bool(first) and all(contents(folder) == first for folder in folders[1:])


def summary(runs: list[dict], key: str, scale: float, unit: str, digits: str) -> str:
    values = [run[key] * scale for run in runs]
    return (f"{statistics.median(values):{digits}} {unit} (range {min(values):{digits}}–{max(values):{digits}})"
            if len(values) > 1 else f"{values[0]:{digits}} {unit}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", default="hybrid", choices=("beam", "hybrid", "solid"))
    parser.add_argument("--runs", type=int, default=3, help="runs with the policy on and as many off, alternately")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    load_before = os.getloadavg()[0]
    folder = Path(tempfile.mkdtemp(prefix="bench_heap_policy_"))
    runs: dict[str, list[dict]] = {"on": [], "off": []}
    outs = []
    for i in range(max(1, args.runs)):
        for policy in ("on", "off"):
            outs.append(folder / f"{policy}{i}")
            runs[policy].append(one_run(policy, args.model, outs[-1]))
    rows = []
    for policy, what in (("on", "policy on (as shipped)"), ("off", "policy off (glibc's defaults)")):
        r = runs[policy]
        rows.append((f"{args.model} check, {what}, {len(r)} fresh processes",
                     f"minor faults {summary(r, 'faults', 1e-3, 'k', '.0f')}; user {summary(r, 'user_s', 1, 's', '.2f')}; "
                     f"sys {summary(r, 'sys_s', 1, 's', '.2f')}; peak {summary(r, 'peak_bytes', 1e-9, 'GB', '.3f')}; "
                     f"wall {summary(r, 'wall_s', 1, 's', '.2f')}"))
    rows.append(("every result file of every run identical byte for byte", "yes" if same_files(outs) else "NO"))
    publish(f"bench_heap_policy.py: `rvcoax check --model {args.model}` with the heap policy on and off", rows,
            load_before, keep=not args.no_record)


if __name__ == "__main__":
    main()
