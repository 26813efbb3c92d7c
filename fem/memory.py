"""How much memory this process may still use (Linux: /proc/meminfo and the cgroup v2 limit)."""

from __future__ import annotations

from pathlib import Path

__all__ = ["available_memory_bytes"]


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
