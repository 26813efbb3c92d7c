"""How much memory this process may still use (Linux: /proc/meminfo and the cgroup v2 limit), giving
freed heap memory back to the operating system before a large allocation (or keeping it for reuse where a model is
small against the memory available), and moving large arrays (a matrix) that are not read for a while out of resident
memory into a file.

**Keeping freed memory.** glibc gives an array above its mmap threshold (at most 32 MB) pages of its own, mapped
afresh and returned when the array is freed, and it returns the free top of its heap above a trim threshold; each
first touch of such a page is a page fault. A model's assembly and factorisation allocate and free arrays of hundreds
of MB many times, so the hybrid reference rig's ``rvcoax check`` took 477 k faults, 0.76–0.92 s of system time, with a
peak of 1.07–1.10e9 bytes (benchmarks/RESULTS.md). :func:`keep_freed_heap` raises both thresholds (``mallopt``) so
that freed memory stays in the heap and serves the next array, and :func:`return_free_heap` gives nothing back
meanwhile: 302–303 k faults, 0.55–0.63 s, and every file of the check the same to the byte (measured: the allocator
places the arrays, the arithmetic is the same). The price is a higher peak (resident memory no longer shrinks between
phases, and a large block that fits in no freed hole extends the heap: 1.18–1.29e9 bytes there; the all-solid rig's
3.97e9 would become 5.0e9), so :func:`apply_heap_policy` keeps freed memory only for a model whose estimated peak is
at most :data:`KEEP_HEAP_SHARE` of the memory available; a large model (the all-solid rig) keeps glibc's own behaviour
and every :func:`return_free_heap`. A kept heap also gets a share of the model's estimated peak mapped ahead by a
background thread (:func:`prefault_heap`), off the main thread's path. Like numpy's huge-page requests
(:mod:`rvcoax.fem.hugepages`) this is a process-wide setting: the library never changes it by itself, the ``rvcoax``
command applies the policy to the model it prepares.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
import mmap
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["KEEP_HEAP_SHARE", "PREFAULT_BYTES", "PREFAULT_SHARE", "HeapPolicy", "apply_heap_policy", "arrays_to_file",
           "available_memory_bytes", "heap_kept", "heap_policy", "keep_freed_heap", "move_to_file", "prefault_bytes",
           "prefault_heap", "return_free_heap"]

_ALIGNMENT = 64  # bytes: each array of a moved matrix starts on a cache line

KEEP_HEAP_SHARE = 0.25
"""A model keeps freed heap memory (:func:`apply_heap_policy`) when its estimated peak is at most this share of the
memory available. Keeping raises the peak by what the heap holds free where a larger block is allocated (the two add
up instead of the one replacing the other), less than the peak again (measured: +10–17 % on the hybrid reference rig,
+26 % on the all-solid one); the estimates (:mod:`rvcoax.geometry.model.preflight`) are 1.7–1.75 and 1.8 times those
models' measured peaks, so a kept heap stays below a third of the memory available. The hybrid reference rig (1.9 GB
estimated) keeps it from 7.5 GB available on; the all-solid rig (7.1 GB) would need 29 GB, and on a 24 GB machine
keeps glibc's behaviour."""
_M_TRIM_THRESHOLD = -1  # glibc's mallopt parameters (malloc.h)
_M_MMAP_THRESHOLD = -3
_KEPT_THRESHOLD = 2**31 - 1
"""Both thresholds while freed memory is kept: the largest value ``mallopt`` takes (an int, 2 GB). An array above it
still gets its own pages."""
_GLIBC_THRESHOLDS = {_M_MMAP_THRESHOLD: 32 << 20, _M_TRIM_THRESHOLD: 64 << 20}
"""The thresholds given back by :func:`keep_freed_heap` ``(False)``: glibc's dynamic ones stop moving once set, and
these are where they settle (mmap 32 MB, trim twice that) after the first large array is freed."""
PREFAULT_SHARE = 0.35
"""Share of a kept model's estimated peak that :func:`prefault_heap` maps ahead (:func:`prefault_bytes`): below what its
heap then uses, so that no page is mapped for nothing (the hybrid reference rig: 1.87e9 estimated, a heap of 1.13e9
at its factorisation; 0.35 of the estimate is 0.65e9)."""
PREFAULT_BYTES = (128 << 20, 1 << 30)
"""What :func:`prefault_heap` maps ahead at least (below, a model's pages are too few to pay for the thread: the beam
model) and at most (bytes)."""
_PREFAULT_CHUNK = 64 << 20  # faulted in per call, so that a stop request waits for one chunk at most
_MADV_POPULATE_WRITE = 23  # Linux 5.14 and later (mman-common.h)
_heap = {"kept": False, "prefault": None}


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
    there is no such call, or while the heap keeps freed memory for reuse (:func:`keep_freed_heap`: pages given back
    there would be faulted in again by the next allocation).

    Arrays below glibc's mmap threshold (which grows to 32 MB as large blocks are freed) live on the heap, and
    what they leave when freed stays resident: the chunked assembly of a solid leaves hundreds of MB (all-solid
    reference rig, 492 k DOF: 1.65 GB resident after assembly, 0.78 GB after this call; benchmarks/RESULTS.md).
    A direct solver's factor is allocated apart from that heap (MKL maps its large blocks), so memory given back
    before a factorisation lowers the process's peak by as much. Nothing is freed that is in use, and the
    pages are mapped afresh if the heap grows again.
    """
    trim = _malloc_trim()
    if trim is None or _heap["kept"]:
        return False
    trim(0)
    return True


@functools.cache
def _mallopt():
    """glibc's ``mallopt``, or None (another C library, or not Linux)."""
    if _malloc_trim() is None:  # ``malloc_trim`` is glibc's own: a C library that has it has glibc's mallopt
        return None
    try:
        setter = ctypes.CDLL(ctypes.util.find_library("c")).mallopt
    except (OSError, AttributeError):
        return None
    setter.argtypes = [ctypes.c_int, ctypes.c_int]
    setter.restype = ctypes.c_int
    return setter


def heap_kept() -> bool:
    """Whether the C heap keeps freed memory for reuse (:func:`keep_freed_heap`)."""
    return _heap["kept"]


def keep_freed_heap(keep: bool = True) -> bool:
    """Make the C heap keep freed memory for the next allocation (``keep``), or give it back as glibc does; True when
    the heap now behaves so, False where it cannot be told (no glibc ``mallopt``: the heap is left as it is).

    Keeping raises glibc's mmap and trim thresholds to 2 GB (``mallopt(M_MMAP_THRESHOLD)``, ``M_TRIM_THRESHOLD``), so
    that arrays below that size come from the heap and what they leave is not returned, and makes
    :func:`return_free_heap` do nothing (module text). Giving back sets the thresholds to where glibc's dynamic ones
    settle (32 MB and 64 MB: they cannot be made dynamic again) and returns the heap's free pages. Nothing is called
    when the heap already behaves as asked: a process that never keeps runs on glibc's defaults throughout.
    """
    keep = bool(keep)
    if _heap["kept"] == keep:
        return True
    setter = _mallopt()
    if setter is None:
        return False
    if keep and all(setter(parameter, _KEPT_THRESHOLD) for parameter in _GLIBC_THRESHOLDS):
        _heap["kept"] = True
        return True
    _stop_prefault()
    # giving back, or a glibc that refused a value: glibc's thresholds, and return_free_heap works again
    restored = all([setter(parameter, value) for parameter, value in _GLIBC_THRESHOLDS.items()])
    _heap["kept"] = False
    return_free_heap()
    return restored and not keep


@dataclass(frozen=True)
class HeapPolicy:
    """What :func:`heap_policy` decided for a model: whether the heap keeps freed memory, and why.

    Attributes
    ----------
    keep : bool
    reason : str
        One sentence, with the estimated peak and the memory available.
    """

    keep: bool
    reason: str


def heap_policy(peak_bytes: float | None, available_bytes: float | None) -> HeapPolicy:
    """Whether a model of estimated peak ``peak_bytes`` should keep freed heap memory: where the peak is at most
    :data:`KEEP_HEAP_SHARE` of ``available_bytes``. Unknown peak or memory: no."""
    if peak_bytes is None or available_bytes is None or not available_bytes > 0:
        return HeapPolicy(False, "the model's peak or the memory available is unknown: freed memory goes back")
    share = peak_bytes / available_bytes
    sizes = f"estimated peak {peak_bytes / 1e9:.3g} GB, {available_bytes / 1e9:.3g} GB available"
    if share <= KEEP_HEAP_SHARE:
        return HeapPolicy(True, f"{sizes}: freed memory is kept for reuse")
    return HeapPolicy(False, f"{sizes} (more than {KEEP_HEAP_SHARE:g} of it): freed memory goes back")


def apply_heap_policy(peak_bytes: float | None, available_bytes: float | None = None) -> HeapPolicy:
    """Decide whether the C heap keeps freed memory for the model about to be prepared, and set it so.

    Decided by :func:`heap_policy`, set by :func:`keep_freed_heap`; a kept heap gets :func:`prefault_bytes` of the
    peak mapped ahead (:func:`prefault_heap`). A process-wide setting (module text): call it before preparing the
    model, with its estimated peak (:func:`rvcoax.geometry.model.peak_memory_bytes`).

    Parameters
    ----------
    peak_bytes : float or None
        The model's estimated peak memory, bytes (None: unknown, nothing kept).
    available_bytes : float, optional
        The memory available, bytes; read from the machine (:func:`available_memory_bytes`) when None.

    Returns
    -------
    HeapPolicy
        Whether the heap now keeps freed memory, and why; where the C library cannot be told (not glibc), not kept,
        with that reason, and nothing changed.
    """
    room = available_memory_bytes() if available_bytes is None else available_bytes
    policy = heap_policy(peak_bytes, room)
    if keep_freed_heap(policy.keep):
        if policy.keep:
            prefault_heap(prefault_bytes(peak_bytes))
        return policy
    return HeapPolicy(False, "the C library does not take glibc's mallopt settings: the heap keeps its own behaviour")


def prefault_bytes(peak_bytes: float | None) -> int:
    """How much of a kept heap :func:`apply_heap_policy` maps ahead for a model of estimated peak ``peak_bytes``:
    :data:`PREFAULT_SHARE` of it, at most ``PREFAULT_BYTES[1]``; 0 below ``PREFAULT_BYTES[0]`` or when unknown."""
    if peak_bytes is None or not peak_bytes > 0:
        return 0
    wanted = min(PREFAULT_SHARE * peak_bytes, PREFAULT_BYTES[1])
    return int(wanted) if wanted >= PREFAULT_BYTES[0] else 0


def prefault_heap(n_bytes: int) -> threading.Thread | None:
    """Map ``n_bytes`` at the top of the kept heap and have a background thread fault their pages in, so that the arrays
    the heap serves from them next (a model's assembly) find their pages mapped; the thread, or None where nothing was
    done (the heap not kept, ``n_bytes`` 0, no glibc).

    The block is allocated and freed at once (on the main thread, whose heap is the one kept: elsewhere nothing is
    done): it stays in the kept heap (:func:`keep_freed_heap`) as free memory that the next allocations take. The
    thread asks the kernel to map its pages writable without writing to them (``madvise(MADV_POPULATE_WRITE)``, Linux
    5.14 and later; on an older kernel it stops at the first refusal), so that nothing the allocator or an array keeps
    there changes, whoever touches a page first. Each page costs a page fault either way; on this thread, on a core
    the single-threaded assembly leaves idle, it is not on the main thread's path (the hybrid reference rig's check:
    the main thread's page faults 266–293 k → 62–107 k, its system time 0.39–0.42 s → 0.13–0.23 s;
    benchmarks/RESULTS.md). Giving the heap back (:func:`keep_freed_heap` ``(False)``) stops the thread first.
    """
    libc = _heap_calls()
    # the main thread's allocations come from the heap that is kept (another thread's this large are mapped apart)
    if n_bytes <= 0 or not _heap["kept"] or libc is None or threading.current_thread() is not threading.main_thread():
        return None
    _stop_prefault()
    malloc, free, madvise = libc
    address = malloc(n_bytes)
    if not address:
        return None
    free(address)  # free memory of the kept heap from here on: only its pages are asked for, never its contents
    page = mmap.PAGESIZE
    start = -(-address // page) * page  # the block's whole pages
    end = (address + n_bytes) // page * page
    stop = threading.Event()

    def fault_in() -> None:
        for first in range(start, end, _PREFAULT_CHUNK):
            if stop.is_set() or madvise(first, min(_PREFAULT_CHUNK, end - first), _MADV_POPULATE_WRITE) != 0:
                return

    thread = threading.Thread(target=fault_in, name="rvcoax-heap-prefault", daemon=True)
    _heap["prefault"] = (thread, stop)
    thread.start()
    return thread


def _stop_prefault() -> None:
    """Stop a :func:`prefault_heap` thread (after the chunk it is on) and wait for it."""
    running = _heap.get("prefault")
    _heap["prefault"] = None
    if running is not None:
        thread, stop = running
        stop.set()
        thread.join()


@functools.cache
def _heap_calls():
    """glibc's ``malloc``, ``free`` and ``madvise`` (as one C library's), or None where :func:`_mallopt` is None."""
    if _mallopt() is None:
        return None
    try:
        library = ctypes.CDLL(ctypes.util.find_library("c"))
        malloc, free, madvise = library.malloc, library.free, library.madvise
    except (OSError, AttributeError):
        return None
    malloc.argtypes, malloc.restype = [ctypes.c_size_t], ctypes.c_void_p
    free.argtypes, free.restype = [ctypes.c_void_p], None
    madvise.argtypes, madvise.restype = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_int], ctypes.c_int
    return malloc, free, madvise


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
