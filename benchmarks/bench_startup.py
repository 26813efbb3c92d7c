"""How fast the command line answers: ``rvcoax --help``, a bad option, and the beam sweep of the 20 paper cases.

Each figure is the wall time of a new process (the way a user meets it), median and best of
several runs. Run: ``.venv/bin/python benchmarks/bench_startup.py``; prints the figures and appends
them to benchmarks/RESULTS.md with the machine, the date and the load average.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import record  # noqa: E402

RUNS = 7
RVCOAX = str(Path(sys.executable).with_name("rvcoax"))


def wall(command: list[str], expect: tuple[int, ...] = (0,)) -> tuple[float, float]:
    times = []
    for _ in range(RUNS):
        start = time.perf_counter()
        done = subprocess.run(command, capture_output=True, text=True)
        times.append(time.perf_counter() - start)
        if done.returncode not in expect:
            raise SystemExit(f"{' '.join(command)} exited {done.returncode}: {done.stderr[-500:]}")
    return statistics.median(times), min(times)


def main() -> None:
    load_before = os.getloadavg()[0]
    out = Path(tempfile.mkdtemp()) / "out"
    figures = [
        ("python -c pass (the interpreter alone)", wall([sys.executable, "-c", "pass"])),
        ("python -c 'import rvcoax'", wall([sys.executable, "-c", "import rvcoax"])),
        ("rvcoax --help", wall([RVCOAX, "--help"])),
        ("rvcoax sweep --help", wall([RVCOAX, "sweep", "--help"])),
        ("rvcoax sweep --mesh-size-mm nan (error message, exit 2)", wall([RVCOAX, "sweep", "--mesh-size-mm", "nan"],
                                                                          expect=(2,))),
        ("rvcoax sweep --out DIR (beam, 20 paper cases, files written)", wall([RVCOAX, "sweep", "--out", str(out)])),
    ]
    rows = [(name, f"{median:.3f} s median, {best:.3f} s best of {RUNS}") for name, (median, best) in figures]
    rows.append(("load average (1 min) before / after", f"{load_before:.2f} / {os.getloadavg()[0]:.2f}"))
    width = max(len(name) for name, _ in rows)
    for name, value in rows:
        print(f"{name:<{width}}  {value}")
    record("bench_startup.py: command-line start and the beam sweep, new process each", rows)


if __name__ == "__main__":
    main()
