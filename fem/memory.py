"""How much memory this process may still use (Linux: /proc/meminfo and the cgroup v2 limit), and giving
freed heap memory back to the operating system before a large allocation."""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
from pathlib import Path

__all__ = ["available_memory_bytes", "return_free_heap"]


@functools.cache
def _malloc_trim():
    """glibc's ``malloc_trim``, or None (another C library, or not Linux)."""
    name = ctypes.util.find_library("c")
    try:
        trim = ctypes.CDLL(name).malloc_trim if name else None
    except (OSError, AttributeError):
        return None
    if trim is not None:
        trim.argtypes = [ctypes.c_size_t]
        trim.restype = ctypes.c_int
    return trim


def return_free_heap() -> bool:
    """Give the free pages of the C heap back to the operating system (glibc ``malloc_trim(0)``); False where
    there is no such call.

    Arrays below glibc's mmap threshold (which grows to 32 MB as large blocks are freed) live on the heap, and
    what they leave when freed stays resident: the chunked assembly of a solid leaves hundreds of MB (all-solid
    reference rig, 492 k DOF: 1.65 GB resident after assembly, 0.78 GB after this call; benchmarks/RESULTS.md).
    A direct solver's factor is allocated apart from that heap (MKL maps its large blocks), so memory given back
    before a factorisation lowers the process's peak by as much. Nothing is freed that is in use, and the
    pages are mapped afresh if the heap grows again.
    """
    trim = _malloc_trim()
    if trim is None:
        return False
    trim(0)
    return True


def available_memory_bytes() -> float | None:
    """Memory this process may still use: MemAvailable (/proc/meminfo), capped by a cgroup v2 limit.

    None where neither can be read (not Linux).
    """
    available = None
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                available = float(line.split()[1]) * 1024.0
                break
    except (OSError, ValueError, IndexError):
        pass
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()
        if limit != "max":
            used = float(Path("/sys/fs/cgroup/memory.current").read_text().strip())
            room = float(limit) - used
            available = room if available is None else min(available, room)
    except (OSError, ValueError):
        pass
    return available
