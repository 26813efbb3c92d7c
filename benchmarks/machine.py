"""Machine description and RESULTS.md bookkeeping shared by the benchmark scripts."""

from __future__ import annotations

import datetime as _dt
import os
import platform
from pathlib import Path

import numpy
import scipy

RESULTS = Path(__file__).with_name("RESULTS.md")


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def machine() -> str:
    return (f"{cpu_model()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
            f"numpy {numpy.__version__}, scipy {scipy.__version__}")


def record(section: str, rows: list[tuple[str, str]]) -> None:
    """Append a dated block of (figure, value) rows under ``section`` in RESULTS.md."""
    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [f"\n### {section} — {stamp}\n", f"Machine: {machine()}\n", "\n| figure | value |\n|---|---|\n"]
    lines += [f"| {name} | {value} |\n" for name, value in rows]
    if not RESULTS.exists():
        RESULTS.write_text("# Benchmark results\n\nEach block is written by the script named in its heading.\n")
    with RESULTS.open("a", encoding="utf-8") as stream:
        stream.writelines(lines)


def publish(section: str, rows: list[tuple[str, str]], load_before: float, keep: bool = True) -> None:
    """Add the 1-minute load average before and now, print the rows, and (``keep``) record them."""
    rows = [*rows, ("load average (1 min) before / after", f"{load_before:.2f} / {os.getloadavg()[0]:.2f}")]
    for name, value in rows:
        print(f"{name}: {value}")
    if keep:
        record(section, rows)
