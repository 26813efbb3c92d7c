"""How much memory this process may still use (Linux: /proc/meminfo and the cgroup v2 limit), giving
freed heap memory back to the operating system before a large allocation, and moving large arrays (a matrix) that are
not read for a while out of resident memory into a file."""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
import mmap
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["arrays_to_file", "available_memory_bytes", "move_to_file", "return_free_heap"]

_ALIGNMENT = 64  # bytes: each array of a moved matrix starts on a cache line


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


def move_to_file(matrix, folder: str | None = None) -> bool:
    """Move a scipy sparse matrix's arrays (``data``, ``indices``, ``indptr``) into a private memory map of an unlinked
    temporary file, in place; True when done, False (the matrix untouched) where the file cannot be written.

    The matrix stays what it was, entry for entry, and usable as before (:func:`arrays_to_file`). For a matrix that is
    not read for a long, memory-hungry stretch: the all-solid reference rig's stiffness K (492 k DOF, 0.46 GB) while
    PARDISO factorises and solves the tied saddle-point matrix, which does not read K (benchmarks/RESULTS.md).

    Parameters
    ----------
    matrix : scipy.sparse matrix in CSR, CSC or BSR form
    folder : str, optional
        As for :func:`arrays_to_file`.
    """
    names = [name for name in ("data", "indices", "indptr") if isinstance(getattr(matrix, name, None), np.ndarray)]
    if len(names) != 3:
        return False
    moved = arrays_to_file([getattr(matrix, name) for name in names], folder)
    if moved is None:
        return False
    for name, array in zip(names, moved):
        setattr(matrix, name, array)
    return True


def arrays_to_file(arrays, folder: str | None = None) -> list[np.ndarray] | None:
    """Copies of ``arrays`` (same values, dtypes and shapes, C order) in a private memory map of one unlinked temporary
    file; None where the file cannot be written, or where it would be memory too.

    The copies are usable as the arrays were: their pages are read back from the page cache (or the disk) when
    something reads them, and a write changes this process's copy only (copy-on-write), never the file. Until then
    they are not part of the process's resident memory, and under memory pressure the system can drop them without
    swap. For arrays that are not read for a long, memory-hungry stretch (a factorisation and its solves). The file
    goes when the last array that maps it goes.

    Parameters
    ----------
    arrays : sequence of numpy arrays
    folder : str, optional
        Where the temporary file is made (the system's temporary folder by default). On a file system held in memory
        (tmpfs, ramfs) the file would be memory too: nothing is made there.
    """
    arrays = [np.ascontiguousarray(array) for array in arrays]
    if _in_memory_filesystem(folder or tempfile.gettempdir()):
        return None
    offsets, total = [], 0
    for array in arrays:
        offsets.append(total)
        total += -(-array.nbytes // _ALIGNMENT) * _ALIGNMENT
    if total == 0:
        return None
    try:
        with tempfile.TemporaryFile(dir=folder) as handle:
            for array, offset in zip(arrays, offsets):
                handle.seek(offset)
                array.tofile(handle)
            handle.truncate(total)
            handle.flush()
            mapped = mmap.mmap(handle.fileno(), total, access=mmap.ACCESS_COPY)
    except (OSError, ValueError):
        return None
    return [np.frombuffer(mapped, dtype=array.dtype, count=array.size, offset=offset).reshape(array.shape)
            for array, offset in zip(arrays, offsets)]


def _in_memory_filesystem(folder: str) -> bool:
    """Whether ``folder`` lies on a file system held in memory (tmpfs, ramfs: /proc/mounts, the longest mount point
    that contains it); False where that cannot be read."""
    try:
        path = str(Path(folder).resolve())
        best, kind = "", ""
        for line in Path("/proc/mounts").read_text().splitlines():
            fields = line.split()
            if len(fields) < 3:
                continue
            mount = fields[1].replace("\\040", " ")
            inside = path == mount or path.startswith(mount.rstrip("/") + "/")
            if inside and len(mount) >= len(best):
                best, kind = mount, fields[2]
    except OSError:
        return False
    return kind in ("tmpfs", "ramfs")
