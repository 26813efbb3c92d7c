"""Sparse matrix × vector products through MKL's threaded sparse BLAS, called directly through ctypes.

Matrices and vectors only. scipy's ``A @ x`` runs on one core; MKL's inspector-executor sparse BLAS
(``mkl_sparse_?_mv``) runs on MKL's OpenMP threads, and for a symmetric matrix it reads the upper
triangle alone (half the bytes of a full CSR matrix: a product is bound by memory bandwidth, not by
arithmetic). :class:`SparseOperator` holds one matrix in MKL's form:

- **3 × 3 blocks** (BSR) when the matrix is exactly made of aligned 3 × 3 blocks (a solid's stiffness:
  one block per pair of nodes, one column index per 9 values), scalar CSR otherwise;
- **symmetric** (upper triangle only) or general;
- **float64 or float32**: a multigrid preconditioner (:mod:`rvcoax.fem.amg`) may run in single precision,
  which halves the bytes again; the conjugate-gradient iteration around it stays in double precision.

The library is the same ``libmkl_rt`` that PARDISO uses (:func:`rvcoax.fem.pardiso.mkl_runtime_path`).
Where it is missing (not x86-64), :func:`available` is False and :class:`SparseOperator` multiplies
with scipy instead: same result up to rounding, one core.
"""

from __future__ import annotations

import ctypes
import functools

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import pardiso
from rvcoax.fem.errors import SolverError

__all__ = ["THREADED_FROM", "SparseOperator", "available"]

# mkl_spblas.h enumerations
_ZERO_BASED = 0
_NON_TRANSPOSE, _TRANSPOSE = 10, 11
_GENERAL, _SYMMETRIC = 20, 21
_UPPER = 41
_NON_UNIT = 50
_ROW_MAJOR = 101
_STATUS = {1: "not initialised", 2: "allocation failed", 3: "invalid value", 4: "execution failed",
           5: "internal error", 6: "not supported"}
_EXPECTED_CALLS = 1000
THREADED_FROM = 2_000_000
"""Stored values from which a product runs on MKL's threads; a smaller one runs on one thread. Each threaded
call wakes and joins MKL's OpenMP threads: on a small matrix that costs more than it saves, and on a loaded
machine (a test suite on two cores with two pytest workers) it cost 20 × (an AMG solve of a few thousand
unknowns: 13.2 s on two threads, 0.64 s on one; benchmarks/RESULTS.md)."""  # hint to the inspector: the operator is applied many times (a multigrid cycle)


class _Descr(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int), ("mode", ctypes.c_int), ("diag", ctypes.c_int)]


@functools.cache
def _library():
    path = pardiso.mkl_runtime_path()
    if path is None:
        raise OSError("MKL's runtime library (libmkl_rt) was not found: pip install mkl (x86-64 only)")
    lib = ctypes.CDLL(path)
    handle_p, int_p, vp = ctypes.POINTER(ctypes.c_void_p), ctypes.POINTER(ctypes.c_int32), ctypes.c_void_p
    for prefix, real in (("s", ctypes.c_float), ("d", ctypes.c_double)):
        create_csr = getattr(lib, f"mkl_sparse_{prefix}_create_csr")
        create_csr.argtypes = [handle_p, ctypes.c_int, ctypes.c_int32, ctypes.c_int32, int_p, int_p, int_p, vp]
        create_bsr = getattr(lib, f"mkl_sparse_{prefix}_create_bsr")
        create_bsr.argtypes = [handle_p, ctypes.c_int, ctypes.c_int, ctypes.c_int32, ctypes.c_int32, ctypes.c_int32,
                               int_p, int_p, int_p, vp]
        mv = getattr(lib, f"mkl_sparse_{prefix}_mv")
        mv.argtypes = [ctypes.c_int, real, ctypes.c_void_p, _Descr, vp, real, vp]
    lib.mkl_sparse_set_mv_hint.argtypes = [ctypes.c_void_p, ctypes.c_int, _Descr, ctypes.c_int32]
    lib.mkl_sparse_optimize.argtypes = [ctypes.c_void_p]
    lib.mkl_sparse_destroy.argtypes = [ctypes.c_void_p]
    lib.MKL_Set_Num_Threads_Local.argtypes = [ctypes.c_int]
    lib.MKL_Set_Num_Threads_Local.restype = ctypes.c_int
    return lib


def available() -> bool:
    """Whether MKL's sparse BLAS can be loaded (x86-64 with the ``mkl`` package)."""
    try:
        _library()
    except (OSError, AttributeError):
        return False
    return True


def _check(status: int, what: str) -> None:
    if status != 0:
        raise SolverError(f"MKL sparse BLAS {what} failed: {_STATUS.get(status, f'status {status}')}")


class SparseOperator:
    """y = A x with MKL's threaded sparse BLAS (scipy where MKL is missing).

    Build with :meth:`symmetric` or :meth:`general`. The operator keeps its own copy of the values in its
    precision; the caller may drop the matrix it came from.
    """

    def __init__(self, shape, dtype, *, symmetric: bool, block_size: int, arrays=None, fallback=None,  # noqa: PLR0913
                 optimize: bool = False) -> None:
        self.shape = tuple(shape)
        self.dtype = np.dtype(dtype)
        self.block_size = block_size
        self._symmetric = symmetric
        self._handle = None
        self._scipy = fallback
        if fallback is not None:
            return
        indptr, indices, data = arrays
        self._indptr = np.ascontiguousarray(indptr, dtype=np.int32)
        self._indices = np.ascontiguousarray(indices, dtype=np.int32)
        self._data = np.ascontiguousarray(data, dtype=self.dtype)
        lib = _library()
        prefix = "s" if self.dtype == np.float32 else "d"
        handle = ctypes.c_void_p()
        int_p = ctypes.POINTER(ctypes.c_int32)
        starts = self._indptr[:-1].ctypes.data_as(int_p)
        ends = self._indptr[1:].ctypes.data_as(int_p)
        columns = self._indices.ctypes.data_as(int_p)
        if block_size > 1:
            status = getattr(lib, f"mkl_sparse_{prefix}_create_bsr")(
                ctypes.byref(handle), _ZERO_BASED, _ROW_MAJOR, self.shape[0] // block_size,
                self.shape[1] // block_size, block_size, starts, ends, columns, self._data.ctypes.data)
        else:
            status = getattr(lib, f"mkl_sparse_{prefix}_create_csr")(
                ctypes.byref(handle), _ZERO_BASED, self.shape[0], self.shape[1], starts, ends, columns,
                self._data.ctypes.data)
        _check(status, "matrix creation")
        self._handle = handle
        self._one_thread = self._data.size < THREADED_FROM
        self._lib = lib
        self._descr = _Descr(_SYMMETRIC if symmetric else _GENERAL, _UPPER, _NON_UNIT)
        self._mv = getattr(lib, f"mkl_sparse_{prefix}_mv")
        if optimize:
            _check(lib.mkl_sparse_set_mv_hint(handle, _NON_TRANSPOSE, self._descr, _EXPECTED_CALLS), "hint")
            _check(lib.mkl_sparse_optimize(handle), "optimisation")

    @classmethod
    def symmetric(cls, matrix, dtype=np.float64, *, optimize: bool = False) -> SparseOperator:
        """A symmetric matrix: its upper (block) triangle in 3 × 3 blocks where it is made of them.

        ``matrix``: CSR with sorted indices and no duplicates (:func:`rvcoax.fem.pardiso.upper_storage`).
        ``optimize``: let MKL's inspector prepare the product (``mkl_sparse_optimize``): faster products
        (float32 upper 3 × 3 blocks at 341 k DOF: 8.3 ms CPU against 13.9 ms), for an internal copy that
        MKL keeps (about the size of the stored values; benchmarks/RESULTS.md).
        """
        if not available():
            return cls(matrix.shape, dtype, symmetric=True, block_size=1,
                       fallback=sp.csr_matrix(matrix).astype(dtype))
        return cls.from_upper(pardiso.upper_storage(matrix), dtype, optimize=optimize)

    @classmethod
    def from_upper(cls, upper: pardiso.UpperStorage, dtype=np.float64, *, optimize: bool = False) -> SparseOperator:
        """A symmetric matrix from its upper triangle as PARDISO stores it (MKL required)."""
        return cls((upper.n, upper.n), dtype, symmetric=True, block_size=upper.block_size,
                   arrays=(upper.indptr, upper.indices, upper.data.reshape(-1)), optimize=optimize)

    @classmethod
    def general(cls, matrix, dtype=np.float64) -> SparseOperator:
        """Any sparse matrix, scalar CSR, not optimised (a transposed product works, but is slower than a
        product with the stored transpose)."""
        a = sp.csr_matrix(matrix)
        if not available():
            return cls(a.shape, dtype, symmetric=False, block_size=1, fallback=a.astype(dtype))
        return cls(a.shape, dtype, symmetric=False, block_size=1, arrays=(a.indptr, a.indices, a.data))

    @property
    def uses_mkl(self) -> bool:
        return self._scipy is None

    @property
    def stored_bytes(self) -> int:
        """Bytes of the values and indices this operator keeps (MKL's own optimisation data not counted)."""
        if self._scipy is not None:
            return self._scipy.data.nbytes + self._scipy.indices.nbytes + self._scipy.indptr.nbytes
        return self._data.nbytes + self._indices.nbytes + self._indptr.nbytes

    def matvec(self, x: np.ndarray, out: np.ndarray | None = None, *, transpose: bool = False,
               alpha: float = 1.0, beta: float = 0.0) -> np.ndarray:
        """out = alpha op(A) x + beta out, op(A) = A or Aᵀ; x and out contiguous of this operator's dtype."""
        rows = self.shape[1] if transpose else self.shape[0]
        if x.dtype != self.dtype or not x.flags.c_contiguous or (out is not None and out.dtype != self.dtype):
            raise ValueError(f"vectors must be contiguous {self.dtype.name}")
        if out is None:
            out = np.zeros(rows, dtype=self.dtype)
            beta = 0.0
        if self._scipy is not None:
            product = (self._scipy.T @ x) if transpose else (self._scipy @ x)
            if beta == 0.0:
                np.multiply(product, alpha, out=out)
            else:
                out *= beta
                out += alpha * product
            return out
        if transpose and self._symmetric:
            transpose = False
        previous = self._lib.MKL_Set_Num_Threads_Local(1) if self._one_thread else None
        try:
            status = self._mv(_TRANSPOSE if transpose else _NON_TRANSPOSE, alpha, self._handle, self._descr,
                              x.ctypes.data, beta, out.ctypes.data)
        finally:
            if previous is not None:
                self._lib.MKL_Set_Num_Threads_Local(previous)
        _check(status, "product")
        return out

    def __matmul__(self, x: np.ndarray) -> np.ndarray:
        return self.matvec(np.ascontiguousarray(x, dtype=self.dtype))

    def release(self) -> None:
        """Give MKL's handle back (the operator is unusable afterwards)."""
        if self._handle is not None:
            _library().mkl_sparse_destroy(self._handle)
            self._handle = None

    def __del__(self) -> None:
        try:
            self.release()
        except Exception:  # noqa: BLE001,S110 - interpreter shutdown: the library may be gone
            pass
