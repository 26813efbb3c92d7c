"""Intel MKL PARDISO for real symmetric matrices, called directly through ctypes.

Matrices and vectors only. PARDISO (``mtype = 2``) factorises an SPD A = L Lᵀ from the upper triangle
of A; with ``indefinite=True`` (``mtype = -2``: L D Lᵀ with Bunch–Kaufman pivoting, weighted matching
and scaling, two steps of iterative refinement) it factorises a symmetric saddle-point matrix (tie
multipliers, :func:`rvcoax.fem.solvers.prepare_saddle_point`), scalar storage only. Storages:

- **3 × 3 blocks** (BSR, ``iparm[36] = 3``) when the matrix is exactly made of 3 × 3 blocks aligned
  with its unknowns: a solid's stiffness, whose unknowns are (u_x, u_y, u_z) per node. The ordering
  (METIS) then works on the node graph, 9× smaller than the graph of the unknowns: at 52 k DOF the
  analysis takes 0.15 s instead of 0.41 s, and the factorisation is as fast or faster
  (benchmarks/RESULTS.md).
- **scalar CSR** otherwise (constraint elimination in the hybrid model mixes the unknowns; :mod:`rvcoax.fem.woodbury`
  stores the hybrid model's tie-released B in whole blocks, the entries it lacks as explicit zeros).

Both upper triangles are cut from the full, sorted CSR matrix by masks (no COO round trip:
``scipy.sparse.triu`` took 2.1 s on the hybrid model's 34 M nonzeros, this takes 0.2 s).

The library is MKL's single dynamic runtime ``libmkl_rt`` (pip package ``mkl``), looked up once per
process in the environment's ``lib`` folder and then by the dynamic loader. Settings: METIS nested
dissection in its OpenMP version (``iparm[1] = 3``: 0.05 s faster than the serial one at 52 k DOF,
0.25 s on the hybrid model), zero-based indices (``iparm[34] = 1``), no iterative refinement,
in-core. The factor lives in MKL memory until :meth:`Factorization.release`. Before each numerical
factorisation the C heap's free pages go back to the operating system (:func:`rvcoax.fem.memory.return_free_heap`):
MKL maps the factor apart from the heap, so what an assembly left free there would otherwise add to the peak.

**The analysis is reused per sparsity pattern.** A released factor gives its numerical factor back to MKL
(phase 0) but keeps its ordering and symbolic factorisation (phase 11) in a small pool keyed by the pattern
(matrix type, size, block size and a digest of the index arrays), within :data:`ANALYSIS_POOL_BYTES` (512 MB) of MKL's
permanent analysis memory. The next factorisation of a matrix with the same pattern (a Monte Carlo sample,
a stiffness calibration's trial, a sensitivity's perturbed model, the factorisation that follows
:func:`analyse`) runs the numerical phase only. In SPD mode the analysis depends on the pattern alone, so the
factor is the one a fresh analysis gives. In indefinite mode the weighted matching and scaling are computed
from the values the pattern was first analysed with; the factor then differs from a fresh one by rounding
(pivoting within a fixed order; MKL's refinement and :mod:`rvcoax.fem.solvers`' residual checks apply as
always), and a factorisation that fails on a reused analysis is repeated with a fresh one.
:func:`set_analysis_reuse` turns the pool off (measurements).

Repeated runs gave
bit-identical solutions on the 52 k-DOF solid (10 of 10) and the hybrid rig (6 of 6), equal to the
serial ordering's; the threaded factorisation is not bitwise reproducible in general (a 3.9 k-DOF
solid in scalar storage: 2 runs of 120 differed, by 4.4e-16 relative).
"""

from __future__ import annotations

import collections
import contextlib
import ctypes
import ctypes.util
import functools
import glob
import hashlib
import sys
import threading
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem.errors import PardisoError
from rvcoax.fem.memory import return_free_heap

__all__ = ["ANALYSIS_POOL_BYTES", "BLOCK_SIZE", "Factorization", "RESOURCE_ERRORS", "TRIM_BEFORE_SOLVE_BYTES",
           "UpperStorage", "ZERO_PIVOT",
           "add_to_diagonal", "analyse", "available", "clear_analysis_pool", "mkl_runtime_path", "pattern_key", "pooled_analyses",
           "set_analysis_reuse", "stored_nonzeros", "upper_block_storage", "upper_csr", "upper_saddle_point",
           "upper_storage"]

BLOCK_SIZE = 3
_SPD = 2  # PARDISO matrix type: real symmetric positive definite
_INDEFINITE = -2  # real symmetric indefinite (Bunch–Kaufman pivoting): saddle-point systems
_ERRORS = {
    -1: "input inconsistent",
    -2: "not enough memory",
    -3: "reordering problem",
    -4: "zero or negative pivot (the matrix is singular or not positive definite)",
    -5: "unclassified internal error",
    -6: "reordering failed",
    -7: "diagonal matrix is singular",
    -8: "32-bit integer overflow (too many nonzeros in the factor)",
    -9: "not enough memory for out-of-core",
    -10: "error opening out-of-core files",
    -11: "read/write error with out-of-core files",
    -13: "undocumented error (seen in the numerical factorisation of singular matrices in 3 × 3 blocks)",
}
ZERO_PIVOT = -4
ANALYSIS_POOL_BYTES = 512 << 20
"""MKL's permanent analysis memory (``iparm[15]``) that idle analyses may hold together; the oldest go first, and an
analysis larger than this is freed with its factor. The hybrid reference rig's holds 158 MB (a process keeps 130 MB
more after the release than with everything freed; benchmarks/RESULTS.md): a pooled analysis must not raise the peak
of a large model's later phases, so the cap is a few such models, not a large solid's."""
TRIM_BEFORE_SOLVE_BYTES = 8 << 20
"""A solve whose right-hand sides fill this much or more gives the heap's free pages back first
(:func:`rvcoax.fem.memory.return_free_heap`): the all-solid rig's three loaded unit loads (12 MB at 492 k DOF) need
about ten times that in MKL's refinement workspace, which the heap's free pages do not serve (benchmarks/RESULTS.md)."""
RESOURCE_ERRORS = frozenset({-2, -8, -9, -10, -11})
"""Codes that say nothing about the matrix's values (memory, integer size, out-of-core files)."""


@functools.cache
def mkl_runtime_path() -> str | None:
    """Path of MKL's runtime library: ``<prefix>/lib`` where pip puts it, else the dynamic loader's choice."""
    for prefix in dict.fromkeys((sys.prefix, sys.base_prefix)):
        found = sorted(glob.glob(f"{prefix}/lib/libmkl_rt.so*") + glob.glob(f"{prefix}/Library/bin/mkl_rt*.dll"),
                       key=len)
        if found:
            return found[0]
    return ctypes.util.find_library("mkl_rt")


@functools.cache
def _library():
    path = mkl_runtime_path()
    if path is None:
        raise OSError("MKL's runtime library (libmkl_rt) was not found: pip install mkl (x86-64 only)")
    library = ctypes.CDLL(path)
    pardiso = library.pardiso
    int_p = ctypes.POINTER(ctypes.c_int32)
    pardiso.argtypes = [ctypes.POINTER(ctypes.c_int64)] + [int_p] * 5 + [ctypes.c_void_p, int_p, int_p, int_p,
                                                                         int_p, int_p, int_p, ctypes.c_void_p,
                                                                         ctypes.c_void_p, int_p]
    pardiso.restype = None
    return pardiso


def _mkl_threads() -> int:
    """MKL's thread count for its next parallel region (``MKL_Get_Max_Threads``)."""
    _library()
    return max(1, int(ctypes.CDLL(mkl_runtime_path()).MKL_Get_Max_Threads()))


def available() -> bool:
    """Whether MKL PARDISO can be loaded (x86-64 with the ``mkl`` package)."""
    try:
        _library()
    except OSError:
        return False
    return True


@dataclass(frozen=True)
class UpperStorage:
    """Upper triangle of a symmetric matrix as PARDISO reads it (zero-based indices, int32).

    Attributes
    ----------
    n : int
        Number of unknowns.
    block_size : int
        1: scalar CSR; 3: BSR of 3 × 3 blocks (rows of blocks, each block stored row by row).
    indptr, indices : int32 arrays
        Row pointers and column indices of the (block) rows.
    data : float64 array
        Values; (nnz,) for CSR, (n_blocks, 3, 3) for BSR.
    """

    n: int
    block_size: int
    indptr: np.ndarray
    indices: np.ndarray
    data: np.ndarray


def _upper_blocks(a: sp.csr_matrix, size: int) -> UpperStorage | None:
    """Upper block triangle of ``a`` if it is exactly made of aligned ``size`` × ``size`` blocks, else None.

    Worked on whole blocks: when the ``size`` rows of block row I have the same length ``size · d_I``, its
    entries are ``size`` rows of d_I groups of ``size`` columns each, so block s of the block row has its row r at
    group ``size · p_I + r d_I + s`` (p_I: blocks before I); the checks and the gather of the upper blocks' values
    are a few passes over the blocks, not over the entries.
    """
    n = a.shape[0]
    if n % size or a.nnz % size:
        return None
    lengths = np.diff(a.indptr).reshape(-1, size)
    if np.any(lengths % size) or np.any(lengths != lengths[:, :1]):
        return None
    columns = a.indices.reshape(-1, size)  # rows hold whole groups of `size` columns, so groups never straddle rows
    first = columns[:, 0]
    if np.any(first % size) or any(np.any(columns[:, k] - first != k) for k in range(1, size)):
        return None
    degree = lengths[:, 0].astype(np.int64) // size  # blocks per block row
    block_ptr = np.zeros(n // size + 1, dtype=np.int64)
    np.cumsum(degree, out=block_ptr[1:])
    repeated = np.repeat(degree, degree)  # d_I of each block
    group = np.arange(int(block_ptr[-1])) + np.repeat((size - 1) * block_ptr[:-1], degree)  # row 0 of each block
    block_column = first[group]
    if any(not np.array_equal(first[group + r * repeated], block_column) for r in range(1, size)):
        return None
    block_column //= size
    block_row = np.repeat(np.arange(n // size, dtype=np.int32), degree)
    upper = block_column >= block_row
    rows_of_block = group[upper, None] + repeated[upper, None] * np.arange(size)  # groups holding each block's rows
    data = a.data.reshape(-1, size)[rows_of_block]  # (n_blocks, row in block, column in block)
    indptr = np.zeros(n // size + 1, dtype=np.int32)
    np.cumsum(np.bincount(block_row[upper], minlength=n // size), out=indptr[1:])
    return UpperStorage(n, size, indptr, block_column[upper].astype(np.int32), data)


def _upper_pattern(indptr: np.ndarray, indices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(indptr of the upper triangle, mask of the stored entries (or blocks) it keeps) of a CSR (or BSR) pattern."""
    n = indptr.size - 1
    rows = np.repeat(np.arange(n, dtype=np.int32), np.diff(indptr))
    keep = indices >= rows
    upper = np.zeros(n + 1, dtype=np.int32)
    np.cumsum(np.bincount(rows[keep], minlength=n), out=upper[1:])
    return upper, keep


def upper_csr(a: sp.csr_matrix) -> UpperStorage:
    """Upper triangle (diagonal included) of a CSR matrix with sorted indices, as scalar CSR."""
    indptr, keep = _upper_pattern(a.indptr, a.indices)
    return UpperStorage(a.shape[0], 1, indptr, a.indices[keep].astype(np.int32), a.data[keep])


def upper_block_storage(blocks: sp.bsr_matrix) -> UpperStorage:
    """Upper block triangle (diagonal blocks whole) of a symmetric BSR matrix with sorted block indices, in
    PARDISO's block storage; blocks that are only partly filled are stored whole, their missing entries as zeros
    (the hybrid model's tie-released B, :mod:`rvcoax.fem.woodbury`; the AMG levels, :mod:`rvcoax.fem.amg`)."""
    indptr, keep = _upper_pattern(blocks.indptr, blocks.indices)
    return UpperStorage(blocks.shape[0], blocks.blocksize[0], indptr, blocks.indices[keep].astype(np.int32),
                        blocks.data[keep])


def add_to_diagonal(storage: UpperStorage, rows: np.ndarray, values: np.ndarray) -> None:
    """Add ``values`` to the diagonal entries ``rows`` (distinct) of ``storage``, in place.

    Each such entry must be stored: in the upper triangle with sorted indices it is the first entry (block) of its
    row; a ValueError says which is missing. The sum is the one a matrix with the values added before it was stored
    has, bit for bit (one addition per entry).
    """
    rows = np.asarray(rows, dtype=np.int64)
    if rows.size == 0:
        return
    size = storage.block_size
    first = storage.indptr[rows // size].astype(np.int64)
    stored = first < storage.indptr[rows // size + 1]
    if not np.all(stored) or np.any(storage.indices[first[stored]] != rows[stored] // size):
        missing = int(rows[~stored][0] if not np.all(stored) else rows[storage.indices[first] != rows // size][0])
        raise ValueError(f"the diagonal entry of row {missing} is not stored")
    if size == 1:
        storage.data[first] += values
    else:
        storage.data[first, rows % size, rows % size] += values


def upper_saddle_point(kept: sp.csr_matrix, constraint: sp.csr_matrix) -> UpperStorage:
    """Upper triangle of the saddle-point matrix [[K, Cᵀ], [C, 0]] as scalar CSR, without forming the matrix.

    The same arrays, entry for entry, as :func:`upper_csr` of the assembled, canonical matrix
    (``scipy.sparse.bmat``): row i < k of the result holds row i of K's upper triangle followed by
    row i of Cᵀ (columns k + j); the rows of the multipliers are empty. Only the upper triangle is
    ever stored: the full saddle-point matrix (both triangles of K once more, and C twice) is not.

    Parameters
    ----------
    kept : csr_matrix (k × k)
        K, symmetric; its duplicates are summed and its indices sorted in place.
    constraint : sparse (d × k)
        C.
    """
    kept.sum_duplicates()
    kept.sort_indices()
    k, d = kept.shape[0], constraint.shape[0]
    upper = upper_csr(kept)
    transposed = sp.csr_matrix(constraint).T.tocsr()  # Cᵀ, k × d
    transposed.sum_duplicates()
    transposed.sort_indices()
    lengths_k = np.diff(upper.indptr).astype(np.int64)
    lengths_c = np.diff(transposed.indptr).astype(np.int64)
    indptr = np.zeros(k + d + 1, dtype=np.int64)
    np.cumsum(lengths_k + lengths_c, out=indptr[1:k + 1])
    indptr[k + 1:] = indptr[k]
    total = int(indptr[-1])
    if total > np.iinfo(np.int32).max:
        raise ValueError(f"the saddle-point matrix's upper triangle has {total} nonzeros, more than 32-bit indices hold")
    indices = np.empty(total, dtype=np.int32)
    data = np.empty(total, dtype=float)
    place = np.repeat(indptr[:k] - upper.indptr[:k], lengths_k) + np.arange(upper.indices.size)
    indices[place] = upper.indices
    data[place] = upper.data
    del upper, place
    place = np.repeat(indptr[:k] + lengths_k - transposed.indptr[:k], lengths_c) + np.arange(transposed.nnz)
    indices[place] = transposed.indices + k
    data[place] = transposed.data
    return UpperStorage(k + d, 1, indptr.astype(np.int32), indices, data)


def stored_nonzeros(storage: UpperStorage) -> int:
    """Nonzeros of the whole symmetric matrix whose upper triangle ``storage`` is (scalar CSR): the upper
    triangle mirrored, so a matrix whose two triangles differ in a few stored entries (a triple product's
    rounding-size leftovers) counts those on both sides."""
    rows = np.repeat(np.arange(storage.n, dtype=np.int32), np.diff(storage.indptr))
    return 2 * int(storage.indices.size) - int(np.count_nonzero(storage.indices == rows))


def upper_storage(a: sp.csr_matrix) -> UpperStorage:
    """3 × 3 block storage when ``a`` allows it, scalar CSR otherwise.

    ``a``: symmetric, CSR with sorted indices and no duplicates (``sum_duplicates``, ``sort_indices``).
    """
    if not (sp.isspmatrix_csr(a) or isinstance(a, sp.csr_array)) or not a.has_sorted_indices:
        raise ValueError("expected a CSR matrix with sorted indices")
    return _upper_blocks(a, BLOCK_SIZE) or upper_csr(a)


@dataclass(frozen=True, eq=False)
class _Analysis:
    """An idle PARDISO handle holding an ordering and symbolic factorisation (no numerical factor)."""

    key: tuple
    handle: np.ndarray
    iparm: np.ndarray
    nbytes: int


_pool: collections.OrderedDict = collections.OrderedDict()
_pool_lock = threading.Lock()
_reuse = {"enabled": True}


def pattern_key(storage: UpperStorage, indefinite: bool = False) -> tuple:
    """What an analysis depends on: matrix type, size, block size, nonzeros and a digest of the index arrays."""
    digest = hashlib.blake2b(digest_size=16)
    digest.update(np.ascontiguousarray(storage.indptr, dtype=np.int32))
    digest.update(np.ascontiguousarray(storage.indices, dtype=np.int32))
    return (_INDEFINITE if indefinite else _SPD, storage.n, storage.block_size, int(storage.indices.size),
            digest.hexdigest())


def set_analysis_reuse(enabled: bool) -> bool:
    """Turn the reuse of analyses on or off for this process (off also empties the pool); returns the old setting."""
    previous = _reuse["enabled"]
    _reuse["enabled"] = bool(enabled)
    if not enabled:
        clear_analysis_pool()
    return previous


def pooled_analyses() -> int:
    """How many idle analyses the pool holds."""
    with _pool_lock:
        return len(_pool)


def _free(handle: np.ndarray, iparm: np.ndarray, mtype: int) -> None:
    """PARDISO phase −1 on a handle: all its memory (the matrix arguments are not read)."""
    one = np.ones(1)
    indptr = np.array([0, 1], dtype=np.int32)
    indices = np.zeros(1, dtype=np.int32)
    _phase(handle, iparm, mtype, -1, UpperStorage(1, 1, indptr, indices, one), rhs=np.zeros((1, 1), order="F"))


def clear_analysis_pool() -> None:
    """Free every idle analysis."""
    with _pool_lock:
        entries = list(_pool.values())
        _pool.clear()
    for entry in entries:
        _free(entry.handle, entry.iparm, entry.key[0])


def _take(key: tuple) -> _Analysis | None:
    with _pool_lock:
        return _pool.pop(key, None)


def _give(entry: _Analysis) -> None:
    """Keep ``entry`` idle for the next matrix of its pattern, within :data:`ANALYSIS_POOL_BYTES`."""
    evicted = []
    with _pool_lock:
        if entry.key in _pool or entry.nbytes > ANALYSIS_POOL_BYTES:
            evicted.append(entry)
        else:
            _pool[entry.key] = entry
            while sum(e.nbytes for e in _pool.values()) > ANALYSIS_POOL_BYTES:
                evicted.append(_pool.popitem(last=False)[1])
    for old in evicted:
        _free(old.handle, old.iparm, old.key[0])


def _phase(handle: np.ndarray, iparm: np.ndarray, mtype: int, phase: int, s: UpperStorage,  # noqa: PLR0913
           *, rhs: np.ndarray) -> tuple[np.ndarray, int]:
    """One call of PARDISO; returns (solution, error code)."""
    x = np.zeros_like(rhs, order="F")
    error = ctypes.c_int32(0)
    int_p = ctypes.POINTER(ctypes.c_int32)
    _library()(
        handle.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)),
        ctypes.byref(ctypes.c_int32(1)),  # maxfct
        ctypes.byref(ctypes.c_int32(1)),  # mnum
        ctypes.byref(ctypes.c_int32(mtype)),
        ctypes.byref(ctypes.c_int32(phase)),
        ctypes.byref(ctypes.c_int32(s.n // s.block_size)),
        s.data.ctypes.data,
        s.indptr.ctypes.data_as(int_p),
        s.indices.ctypes.data_as(int_p),
        None,  # perm
        ctypes.byref(ctypes.c_int32(rhs.shape[1])),
        iparm.ctypes.data_as(int_p),
        ctypes.byref(ctypes.c_int32(0)),  # msglvl
        rhs.ctypes.data,
        x.ctypes.data,
        ctypes.byref(error),
    )
    return x, error.value


def _settings(storage: UpperStorage, indefinite: bool, *, analysis_only: bool, two_level: bool,
              reproducible: bool) -> np.ndarray:
    """PARDISO's ``iparm`` for a fresh analysis of ``storage``."""
    iparm = np.zeros(64, dtype=np.int32)
    iparm[0] = 1  # settings below, not MKL's defaults
    iparm[1] = 2 if reproducible else 3  # METIS nested dissection, OpenMP version (serial where reproducible:)
    iparm[9] = 8  # pivot perturbation 1e-8 (not used for SPD)
    iparm[17] = -1  # report the nonzeros of the factor
    iparm[18] = -1 if analysis_only else 0  # the factorisation's MFLOP (it slows the ordering a little)
    iparm[34] = 1  # zero-based indices
    iparm[36] = storage.block_size if storage.block_size > 1 else 0
    iparm[23] = 1 if two_level else 0  # MKL's two-level factorisation (the hybrid rig's Cholesky: 1.7 s CPU, not 2.6)
    # the same factor, bit for bit, in every run with as many threads (MKL's CNR mode for PARDISO, which MKL's
    # reference for iparm rules out with the OpenMP ordering): the hybrid rig's factor in 3 × 3 blocks differed
    # by 4e-16 between runs without it, and costs no more with it
    iparm[33] = _mkl_threads() if reproducible else 0
    if indefinite:  # MKL's advice for saddle-point matrices: symmetric weighted matching and scaling,
        iparm[10] = 1  # so that the zero block of the multipliers pairs with the constraint columns;
        iparm[12] = 1  # pivots perturbed to 1e-8 (iparm[9]) are made good by iterative refinement
        iparm[7] = 2  # two refinement steps on the saddle-point matrix (MKL stops earlier at rounding)
    return iparm


class _Worker:
    """``work()`` run on a thread of its own; :meth:`result` waits for it and raises what it raised."""

    def __init__(self, work):
        self._outcome: list = []
        self._thread = threading.Thread(target=self._run, args=(work,), name="rvcoax-pardiso-analysis", daemon=True)
        self._thread.start()

    def _run(self, work) -> None:
        try:
            self._outcome.append((work(), None))
        except BaseException as error:  # noqa: BLE001 - handed to the waiting caller as it is
            self._outcome.append((None, error))

    def result(self):
        self._thread.join()
        value, error = self._outcome[0]
        if error is not None:
            raise error
        return value


class Factorization:
    """PARDISO's factor of an SPD matrix (its upper triangle :class:`UpperStorage`); solves any number of columns.

    Raises :class:`PardisoError` from the constructor when the analysis or factorisation fails
    (``code == -4`` and ``equation``: a zero or negative pivot, i.e. the matrix is singular).
    Whether a *singular* matrix fails here is a matter of rounding: the tiny pivots of its
    rigid-body motions come out with either sign, and the threaded factorisation does not round
    the same way every time (a free 3.9 k-DOF solid: 129 of 150 runs failed with −4, 1 with −13,
    20 succeeded), so a caller that must know tests the factor (:mod:`rvcoax.fem.solvers` does).
    """

    def __init__(self, storage: UpperStorage, indefinite: bool = False, analysis_only: bool = False, *,  # noqa: PLR0913
                 reuse_analysis: bool = True, two_level: bool = False, reproducible: bool = False,
                 defer: bool = False):
        """``defer``: start the analysis (ordering and symbolic factorisation, the pattern only) on a worker thread
        and return at once; :meth:`factorise` waits for it and factorises the storage's values as they are then (a
        caller may change them in place, the pattern kept, once :meth:`wait_for_analysis` has returned). The
        caller's Python work meanwhile runs beside MKL's serial ordering, which holds neither the interpreter's
        lock nor the second core (:mod:`rvcoax.fem.woodbury`)."""
        self._pardiso = _library()
        self.storage = storage
        self.mtype = _INDEFINITE if indefinite else _SPD
        self._key = pattern_key(storage, indefinite) if reuse_analysis and _reuse["enabled"] else None
        self._keep_analysis = False  # whether release() gives the analysis to the pool: after a good phase 22 or 11-only
        self.reused_analysis = False
        """Whether the numerical factorisation ran on a pooled analysis of an earlier matrix of the same pattern."""
        self._alive = True
        self._analysis: _Worker | None = None  # the deferred analysis, until factorise() has waited for it
        self._pending = defer  # the numerical factorisation is still to come (factorise())
        self._fresh_settings = _settings(storage, indefinite, analysis_only=analysis_only, two_level=two_level,
                                         reproducible=reproducible)
        pooled = _take(self._key) if self._key is not None and not analysis_only else None
        self._handle_is_pooled = pooled is not None
        if pooled is not None:
            self._handle, self._iparm = pooled.handle, pooled.iparm
            if defer or self._factorise_pooled():
                return
            self._handle_is_pooled = False
        self._handle = np.zeros(64, dtype=np.int64)
        self._iparm = self._fresh_settings
        no_rhs = np.zeros((storage.n, 1), order="F")
        if defer:
            self._analysis = _Worker(lambda: self._call(11, no_rhs, "analysis"))
            return
        try:
            self._call(11, no_rhs, "analysis")  # ordering and symbolic factorisation: the pattern only
            if not analysis_only:
                return_free_heap()  # what the assembly and the analysis left free on the heap (fem.memory)
                self._call(22, no_rhs, "factorisation")  # numerical: a failure here is about the values
            self._keep_analysis = True
        except PardisoError:
            self.release()
            raise

    def _factorise_pooled(self) -> bool:
        """Phase 22 on a pooled analysis; False (the analysis freed) where the values do not suit it."""
        try:
            return_free_heap()  # the factor is mapped apart from the heap: give back what the heap holds free
            self._call(22, np.zeros((self.storage.n, 1), order="F"), "factorisation")
        except PardisoError:  # the values do not suit the analysis of other values: start afresh
            _free(self._handle, self._iparm, self.mtype)
            return False
        self.reused_analysis = True
        self._keep_analysis = True
        return True

    def wait_for_analysis(self) -> None:
        """Wait for a deferred analysis (``defer=True``) to end; afterwards the caller may change the storage's values
        in place (the pattern unchanged) before :meth:`factorise`. Raises :class:`PardisoError` where it failed (this
        factorisation is then released)."""
        if self._analysis is None:
            return
        analysis, self._analysis = self._analysis, None
        try:
            analysis.result()
        except PardisoError:
            self.release()
            raise

    def factorise(self) -> None:
        """The numerical factorisation of a deferred set-up (``defer=True``), once: waits for the analysis, then
        factorises the storage's values as they are now. An SPD analysis depends on the pattern alone, so the factor
        is the one an undeferred set-up of these values gives, bit for bit.

        Raises
        ------
        PardisoError
            The analysis or the factorisation failed (this factorisation is then released).
        """
        if not self._pending:
            raise RuntimeError("factorise() is for a Factorization made with defer=True, once")
        self._pending = False
        self.wait_for_analysis()
        try:
            if not self._keep_analysis and self._handle_is_pooled:
                if self._factorise_pooled():
                    return
                self._handle = np.zeros(64, dtype=np.int64)
                self._iparm = self._fresh_settings
                self._call(11, np.zeros((self.storage.n, 1), order="F"), "analysis")
            return_free_heap()  # what the assembly and the analysis left free on the heap (fem.memory)
            self._call(22, np.zeros((self.storage.n, 1), order="F"), "factorisation")
            self._keep_analysis = True
        except PardisoError:
            self.release()
            raise

    @property
    def factor_nonzeros(self) -> int:
        """Nonzeros of the factor L (scalar entries)."""
        return int(self._iparm[17])

    @property
    def inertia(self) -> tuple[int, int]:
        """Numbers of positive and negative pivots (``iparm[21]``, ``iparm[22]``; indefinite mode)."""
        return int(self._iparm[21]), int(self._iparm[22])

    @property
    def perturbed_pivots(self) -> int:
        """Pivots PARDISO perturbed (``iparm[13]``)."""
        return int(self._iparm[13])

    @property
    def memory_MB(self) -> float:
        """MKL's memory for the factor and its solves (``iparm[15] + iparm[16]``, reported in KiB), MB."""
        return float(int(self._iparm[15]) + int(self._iparm[16])) / 1024.0

    @property
    def factorisation_gflop(self) -> float:
        """Floating-point operations of the numerical factorisation (``iparm[18]``, MFLOP), GFLOP."""
        return float(int(self._iparm[18])) / 1e3

    @property
    def analysis_peak_MB(self) -> float:
        """MKL's peak memory during the analysis (``iparm[14]``, KiB), MB."""
        return float(int(self._iparm[14])) / 1024.0

    def _call(self, phase: int, rhs: np.ndarray, what: str) -> np.ndarray:
        s = self.storage
        x, error = _phase(self._handle, self._iparm, self.mtype, phase, s, rhs=rhs)
        if error:
            # iparm[29] names the unknown of a zero pivot in scalar storage (in blocks it is not one)
            equation = int(self._iparm[29]) if error == ZERO_PIVOT and s.block_size == 1 else None
            raise PardisoError(error, what, equation,
                               f"PARDISO {what} failed with error {error}: {_ERRORS.get(error, 'unknown error')}")
        return x

    def solve(self, block: np.ndarray) -> np.ndarray:
        """Solution X of A X = B for B of shape (n, m), as a C-ordered (n, m) array."""
        if not self._alive:
            raise RuntimeError("the PARDISO factorisation was released")
        if self._pending:
            raise RuntimeError("the PARDISO factorisation was deferred: call factorise() first")
        rhs = np.asfortranarray(block, dtype=float)
        if rhs.nbytes >= TRIM_BEFORE_SOLVE_BYTES:
            return_free_heap()  # MKL's solve workspace grows with the columns: what the heap holds free goes first
        return np.ascontiguousarray(self._call(33, rhs, "solve"))

    def release(self, keep_analysis: bool = True) -> None:
        """Free MKL's memory for this factor (idempotent); no solves afterwards.

        The ordering and symbolic factorisation go to the pool for the next matrix of the same pattern (module
        docstring) unless ``keep_analysis`` is False (a matrix found singular: its values, which an indefinite
        analysis depends on, are not worth keeping), reuse is off, or this factorisation failed.
        """
        if not self._alive:
            return
        self._alive = False
        if self._analysis is not None:  # a deferred analysis still running: MKL's handle is its until it ends
            analysis, self._analysis = self._analysis, None
            with contextlib.suppress(PardisoError):
                analysis.result()
        if keep_analysis and self._keep_analysis and self._key is not None and _reuse["enabled"]:
            self._call(0, np.zeros((self.storage.n, 1), order="F"), "release")  # the numerical factor only
            _give(_Analysis(self._key, self._handle, self._iparm, 1024 * int(self._iparm[15])))
        else:
            self._call(-1, np.zeros((self.storage.n, 1), order="F"), "release")


def analyse(storage: UpperStorage, indefinite: bool = False) -> dict:
    """PARDISO's ordering and symbolic factorisation only: what the factorisation would need, without doing it.

    Returns a dict: ``factor_nonzeros``, ``memory_MB`` (MKL's memory for the factor and its solves),
    ``analysis_peak_MB`` and ``factorisation_gflop``. For sizing a model before factorising it.
    """
    factor = Factorization(storage, indefinite=indefinite, analysis_only=True)
    try:
        return {"factor_nonzeros": factor.factor_nonzeros, "memory_MB": factor.memory_MB,
                "analysis_peak_MB": factor.analysis_peak_MB, "factorisation_gflop": factor.factorisation_gflop}
    finally:
        factor.release()
