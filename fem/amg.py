"""Algebraic multigrid preconditioner for elasticity: pyamg's coarsening, a V-cycle on both cores.

Matrices and vectors only. The hierarchy (aggregates, smoothed prolongators P, Galerkin coarse
matrices PᵀAP) is pyamg's smoothed aggregation with the rigid-body modes as near-null space, as
before. The V-cycle is this module's, built for speed at a million unknowns:

- **Chebyshev smoothing on the Jacobi-scaled matrix** (polynomial of degree :data:`CHEBYSHEV_DEGREE`
  in D⁻¹A over [λ_max / :data:`SMOOTHING_RANGE`, 1.1 λ_max], λ_max from a short Lanczos run). It
  needs only products with A, where pyamg's default symmetric Gauss–Seidel is a sequential sweep on one
  core that cost 15 products' worth of time per cycle (benchmarks/RESULTS.md).
- **Products through MKL's threaded sparse BLAS** (:mod:`rvcoax.fem.mkl_sparse`): each level's A as its
  upper triangle in 3 × 3 blocks where it has them (MKL-optimised for the product), P and Pᵀ as CSR.
- **Single precision inside the cycle** (:data:`PRECISION`): the preconditioner only has to be a fixed
  symmetric positive definite operator close to A⁻¹; its values and vectors in float32 halve the bytes
  every product reads. The conjugate-gradient iteration around it (:func:`rvcoax.fem.solvers.conjugate_gradients`)
  and its product with A stay in float64, and its stopping rule judges the float64 iterate.
- The coarsest matrix (a few dozen unknowns) is solved by a dense Cholesky factor in float64.

Pre- and post-smoother are the same symmetric polynomial, so the cycle is a symmetric operator; it is
positive definite as long as λ_max is not underestimated by more than the 10 % margin (the Lanczos
estimate from below converges fast for the largest eigenvalue; :class:`SolverError` from CG's
curvature test would tell otherwise).
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from rvcoax.fem import mkl_sparse, pardiso
from rvcoax.fem.assembly import worker_threads
from rvcoax.fem.errors import SolverError
from rvcoax.fem.mkl_sparse import SparseOperator

__all__ = ["CHEBYSHEV_DEGREE", "PRECISION", "SMOOTHING_RANGE", "Hierarchy", "smoothed_aggregation"]

CHEBYSHEV_DEGREE = 3
SMOOTHING_RANGE = 30.0  # the smoother damps eigenvalues of D⁻¹A in [λ_max / SMOOTHING_RANGE, 1.1 λ_max]
LAMBDA_MARGIN = 1.1
LANCZOS_STEPS = 15
PRECISION = np.float32
PROLONGATION_OMEGA = 4.0 / 3.0  # pyamg's Jacobi prolongation smoother: P = (I − ω/ρ(D⁻¹A) D⁻¹A) T
MAX_COARSE = 10  # pyamg's default: coarsen until a level has at most this many nodes (blocks of k candidates) ...
MAX_LEVELS = 10  # ... or there are this many levels
NODE_BLOCK = 3  # unknowns per node of the fine level (a solid's u_x, u_y, u_z), used where its matrix has such blocks
PARALLEL_FROM = 1_000_000  # stored values of a level from which its set-up products run on threads


def _largest_eigenvalue(operator: SparseOperator, inverse_sqrt_diagonal: np.ndarray, steps: int = LANCZOS_STEPS) -> float:
    """Largest eigenvalue of D^-½ A D^-½ (= that of D⁻¹A) by ``steps`` Lanczos steps from a fixed start."""
    n = operator.shape[0]
    start = np.random.default_rng(12345).standard_normal(n)
    q = (start / np.linalg.norm(start)).astype(operator.dtype)
    q_previous = np.zeros_like(q)
    alphas, betas = [], []
    beta = 0.0
    for _ in range(min(steps, n)):
        w = inverse_sqrt_diagonal * operator.matvec(inverse_sqrt_diagonal * q)
        alpha = float(np.dot(w.astype(float), q.astype(float)))
        w -= alpha * q + beta * q_previous
        alphas.append(alpha)
        beta = float(np.linalg.norm(w.astype(float)))
        if beta <= 1e-12 * abs(alpha):
            break
        betas.append(beta)
        q_previous, q = q, (w / beta).astype(operator.dtype)
    k = len(alphas)
    ritz = scipy.linalg.eigh_tridiagonal(np.array(alphas), np.array(betas[:k - 1]), eigvals_only=True)
    return float(ritz[-1])


def _checked_diagonal(matrix: sp.csr_matrix, level: int) -> np.ndarray:
    """The diagonal of a level's matrix; :class:`SolverError` where one is negative.

    A zero diagonal entry is an unknown that the level does not use: an aggregate with fewer nodes than
    near-null-space vectors gets a zero column in its prolongator (pyamg's QR of the rigid-body modes
    restricted to it is rank deficient), so its row and column of PᵀAP are zero. The smoother and the
    coarse solve leave it at zero.
    """
    diagonal = matrix.diagonal()
    if np.any(diagonal < 0.0) or not np.all(np.isfinite(diagonal)):
        raise SolverError(f"AMG level {level}: the matrix has {int(np.sum(~(diagonal >= 0.0)))} negative or "
                          "non-finite diagonal entries: it is not positive definite")
    return diagonal


@dataclass(frozen=True)
class _CoarseFactor:
    """Dense Cholesky factor of the coarsest matrix on its unknowns with a nonzero diagonal."""

    active: np.ndarray
    factor: tuple
    n: int

    def solve(self, b: np.ndarray) -> np.ndarray:
        x = np.zeros(self.n, dtype=b.dtype)
        x[self.active] = scipy.linalg.cho_solve(self.factor, b[self.active].astype(float))
        return x


@dataclass(eq=False)
class _Level:
    """One level above the coarsest: its matrix, Jacobi scaling, Chebyshev interval and prolongator."""

    a: SparseOperator
    inverse_diagonal: np.ndarray
    theta: float  # centre of the smoothing interval
    delta: float  # half its width
    prolongation: SparseOperator
    restriction: SparseOperator  # Pᵀ, stored: MKL's product with a stored CSR matrix beats its transposed product

    def smooth(self, b: np.ndarray, x: np.ndarray | None) -> np.ndarray:
        """Chebyshev iteration of CHEBYSHEV_DEGREE steps on D⁻¹A x = D⁻¹b, from x (zero when None)."""
        if x is None:
            r = b.copy()
            x = np.zeros_like(b)
        else:
            r = self.a.matvec(x, b.copy(), alpha=-1.0, beta=1.0)
        sigma = self.theta / self.delta
        rho = 1.0 / sigma
        scalar = b.dtype.type
        d = self.inverse_diagonal * r
        d *= scalar(1.0 / self.theta)
        x += d
        for _ in range(1, CHEBYSHEV_DEGREE):
            self.a.matvec(d, r, alpha=-1.0, beta=1.0)
            rho_next = 1.0 / (2.0 * sigma - rho)
            d *= scalar(rho_next * rho)
            d += scalar(2.0 * rho_next / self.delta) * (self.inverse_diagonal * r)
            x += d
            rho = rho_next
        return x


class Hierarchy:
    """A V-cycle z = M⁻¹ r over a pyamg smoothed-aggregation hierarchy (see the module's description).

    Use :func:`smoothed_aggregation`. :meth:`precondition` takes and gives float64 vectors.
    """

    def __init__(self, matrix: SparseOperator, levels: list[_Level], coarse_factor, operator_complexity: float,  # noqa: PLR0913
                 sizes: list[int]) -> None:
        self.matrix = matrix
        self._levels = levels
        self._coarse = coarse_factor
        self.operator_complexity = operator_complexity
        self.sizes = sizes

    def _cycle(self, level: int, b: np.ndarray) -> np.ndarray:
        if level == len(self._levels):
            return self._coarse.solve(b)
        lvl = self._levels[level]
        x = lvl.smooth(b, None)
        r = lvl.a.matvec(x, b.copy(), alpha=-1.0, beta=1.0)
        coarse = self._cycle(level + 1, lvl.restriction.matvec(r))
        lvl.prolongation.matvec(coarse, x, alpha=1.0, beta=1.0)
        return lvl.smooth(b, x)

    def precondition(self, r: np.ndarray) -> np.ndarray:
        """One V-cycle from zero on A z = r."""
        dtype = self._levels[0].inverse_diagonal.dtype if self._levels else np.float64
        return self._cycle(0, np.ascontiguousarray(r, dtype=dtype)).astype(np.float64)

    def release(self) -> None:
        """Give the MKL handles back."""
        self.matrix.release()
        for lvl in self._levels:
            lvl.a.release()
            lvl.prolongation.release()
            lvl.restriction.release()
        self._levels = []


def _node_blocks(a: sp.csr_matrix, size: int) -> sp.bsr_matrix | None:
    """``a`` as ``size`` × ``size`` blocks (BSR) if it is exactly made of aligned blocks, else None.

    A solid's stiffness is (one 3 × 3 block per pair of nodes); the smoothed-aggregation products with its
    blocks run 2–3× faster than with the scalar matrix (benchmarks/RESULTS.md). scipy's conversion fills
    partly stored blocks with zeros: none was filled exactly when the blocks hold as many values as ``a``.
    """
    if size == 1 or a.shape[0] % size:
        return None
    blocks = a.tobsr(blocksize=(size, size))
    return blocks if blocks.data.size == a.nnz else None


def _row_block(a, r0: int, r1: int):
    """(Block) rows r0:r1 of a CSR or BSR matrix, its values and indices views of ``a``'s."""
    s, e = int(a.indptr[r0]), int(a.indptr[r1])
    if isinstance(a, sp.bsr_matrix):
        rows, _ = a.blocksize
        return sp.bsr_matrix((a.data[s:e], a.indices[s:e], a.indptr[r0:r1 + 1] - s),
                             shape=((r1 - r0) * rows, a.shape[1]), blocksize=a.blocksize, copy=False)
    return sp.csr_matrix((a.data[s:e], a.indices[s:e], a.indptr[r0:r1 + 1] - s), shape=(r1 - r0, a.shape[1]),
                         copy=False)


def _row_ranges(a, parts: int) -> list[tuple[int, int]]:
    """``parts`` ranges of (block) rows of ``a`` with about equal numbers of stored blocks."""
    stored = int(a.indptr[-1])
    targets = np.arange(1, parts) * (stored / parts)
    bounds = np.unique(np.concatenate([[0], np.searchsorted(a.indptr, targets), [a.indptr.size - 1]]))
    return [(int(r0), int(r1)) for r0, r1 in zip(bounds[:-1], bounds[1:])]


def _stack_rows(blocks: list, shape: tuple[int, int]):
    """Row blocks (all CSR or all BSR of one block size, in order) joined into one matrix."""
    if len(blocks) == 1:
        return blocks[0]
    offsets = np.cumsum([0] + [int(b.indptr[-1]) for b in blocks])
    indptr = np.concatenate([[0]] + [b.indptr[1:].astype(np.int64) + o for b, o in zip(blocks, offsets[:-1])])
    arrays = (np.concatenate([b.data for b in blocks]), np.concatenate([b.indices for b in blocks]), indptr)
    if isinstance(blocks[0], sp.bsr_matrix):
        return sp.bsr_matrix(arrays, shape=shape, blocksize=blocks[0].blocksize)
    return sp.csr_matrix(arrays, shape=shape)


def _prolongator(matrix, aggregates, inverse_diagonal: np.ndarray, rho: float, candidates: np.ndarray, *,  # noqa: PLR0913
                 pool: ThreadPoolExecutor, parts: int):
    """Smoothed-aggregation prolongator P = (I − ω/ρ D⁻¹A) T and the coarse candidates (pyamg's building blocks).

    ``matrix``: the level's matrix, CSR or in ``block`` × ``block`` blocks (BSR). Aggregates: pyamg's
    standard aggregation of the matrix graph; on a coarse level, the graph of its ``block`` × ``block`` blocks
    (one block per pair of coarse aggregates, as pyamg's BSR levels). Its default strength of connection
    (symmetric, θ = 0) keeps every stored entry, so the graph is the matrix's own pattern, and computing the
    strength matrix (two copies of the matrix and a row scaling: a third of pyamg's set-up) changes nothing.
    T: pyamg's fit of the candidates on each aggregate (QR). ρ: the largest eigenvalue of D⁻¹A, the same
    Lanczos estimate the Chebyshev smoother uses (pyamg estimates it again, by Arnoldi on a scaled copy).
    The product A T runs on ``pool`` by blocks of rows (scipy's product releases the GIL); with a blocked
    matrix, P is stored in blocks of (block rows × candidates): the rows of one node share their pattern.
    """
    from pyamg.aggregation import fit_candidates

    k = candidates.shape[1]
    tentative, coarse_candidates = fit_candidates(aggregates, candidates)
    rows_per_block = matrix.blocksize[0] if isinstance(matrix, sp.bsr_matrix) else 1
    tentative = (sp.bsr_matrix(tentative, blocksize=(rows_per_block, k)) if rows_per_block > 1
                 else sp.csr_matrix(tentative))
    weights = (PROLONGATION_OMEGA / rho) * inverse_diagonal

    def rows(bounds):
        r0, r1 = bounds
        smoothing = _row_block(matrix, r0, r1) @ tentative
        if rows_per_block > 1:
            smoothing = sp.bsr_matrix(smoothing, blocksize=(rows_per_block, k))
            scale = weights[r0 * rows_per_block:r1 * rows_per_block].reshape(-1, rows_per_block)
            smoothing.data *= np.repeat(scale, np.diff(smoothing.indptr), axis=0)[:, :, None]  # ω/ρ D⁻¹ A T
        else:
            smoothing = sp.csr_matrix(smoothing)
            smoothing.data *= np.repeat(weights[r0:r1], np.diff(smoothing.indptr))
        result = _row_block(tentative, r0, r1) - smoothing
        result = sp.bsr_matrix(result, blocksize=(rows_per_block, k)) if rows_per_block > 1 else sp.csr_matrix(result)
        result.sort_indices()
        return result

    prolongation = _stack_rows(list(pool.map(rows, _row_ranges(matrix, parts))), tentative.shape)
    return prolongation, coarse_candidates


def _aggregates(matrix: sp.csr_matrix, blocks: sp.bsr_matrix | None, block: int):
    """pyamg's standard aggregation of the matrix's graph (CSR) or, on a coarse level (``block`` > 1), of
    the graph of its ``block`` × ``block`` blocks (``blocks``: the matrix in such blocks, or None)."""
    from pyamg.aggregation import standard_aggregation

    if block == 1:
        graph = matrix
    else:
        if blocks is None or blocks.blocksize != (block, block):
            blocks = sp.bsr_matrix(matrix, blocksize=(block, block))
        graph = sp.csr_matrix((np.ones(blocks.indices.size), blocks.indices, blocks.indptr),
                              shape=(matrix.shape[0] // block,) * 2)
    aggregates, _ = standard_aggregation(sp.csr_array(graph))
    return aggregates


def _galerkin(matrix, prolongation, pool: ThreadPoolExecutor, parts: int) -> sp.csr_matrix:
    """The coarse matrix Pᵀ A P (CSR), summed over blocks of rows of A on ``pool``: Σ P[rows]ᵀ (A[rows] P).

    No A P of the whole matrix is held (at a million unknowns it would be about as large as A).
    """
    def part(bounds):
        r0, r1 = bounds
        return _row_block(prolongation, r0, r1).T @ (_row_block(matrix, r0, r1) @ prolongation)

    coarse = None
    for term in pool.map(part, _row_ranges(matrix, parts)):
        coarse = term if coarse is None else coarse + term
    coarse = sp.csr_matrix(coarse)
    coarse.sum_duplicates()
    coarse.sort_indices()
    return coarse


def _operators(matrix: sp.csr_matrix, blocks: sp.bsr_matrix | None, dtype):
    """The level's product in float64 (for λ_max, and CG's on the fine level) and its upper (block)
    triangle's arrays for the cycle's product in ``dtype`` (None without MKL: the scipy fallback)."""
    if not mkl_sparse.available():
        return SparseOperator.symmetric(matrix, np.float64), None
    upper = pardiso.upper_storage(matrix) if blocks is None else pardiso.upper_block_storage(blocks)
    return SparseOperator.from_upper(upper, np.float64), upper  # float64 values: no copy, not optimised


def _coarsen(matrix: sp.csr_matrix, candidates: np.ndarray, *, index: int, block: int, dtype,  # noqa: PLR0913
             pool: ThreadPoolExecutor):
    """One level: its operators, Chebyshev interval, prolongator and the next level's matrix and candidates.

    ``index``: the level's number (0: the fine level); ``block``: unknowns per node of its aggregation graph.
    Returns (level, float64 product of this level's matrix, coarse matrix, coarse candidates). The
    matrix's blocks are held only while the products need them; the cycle's optimised product (an MKL copy)
    is made after they are dropped, which keeps the peak memory at a million unknowns down.
    """
    diagonal = _checked_diagonal(matrix, index)
    blocks = _node_blocks(matrix, NODE_BLOCK if index == 0 else block)
    exact, upper = _operators(matrix, blocks, dtype)
    inverse_diagonal = np.divide(1.0, diagonal, out=np.zeros_like(diagonal), where=diagonal > 0.0)
    rho = _largest_eigenvalue(exact, np.sqrt(inverse_diagonal))
    parts = worker_threads() if matrix.nnz >= PARALLEL_FROM else 1
    factors = matrix if blocks is None else blocks
    prolongation, coarse_candidates = _prolongator(factors, _aggregates(matrix, blocks, block), inverse_diagonal,
                                                   rho, candidates, pool=pool, parts=parts)
    coarse = _galerkin(factors, prolongation, pool, 4 * parts)
    del factors, blocks
    operator = (SparseOperator.symmetric(matrix, dtype, optimize=True) if upper is None
                else SparseOperator.from_upper(upper, dtype, optimize=True))
    prolongation = sp.csr_matrix(prolongation)
    lam = rho * LAMBDA_MARGIN
    low = lam / SMOOTHING_RANGE
    level = _Level(operator, inverse_diagonal.astype(dtype), 0.5 * (lam + low), 0.5 * (lam - low),
                   SparseOperator.general(prolongation, dtype), SparseOperator.general(prolongation.T.tocsr(), dtype))
    return level, exact, coarse, coarse_candidates


def smoothed_aggregation(a: sp.csr_matrix, near_null_space=None, *, dtype=PRECISION) -> Hierarchy:
    """Set up the V-cycle for the symmetric positive definite ``a`` (CSR, sorted indices).

    The hierarchy is pyamg's smoothed aggregation with its defaults (symmetric strength θ = 0, standard
    aggregation, Jacobi prolongation smoother ω = 4/3 of degree 1, no candidate improvement, coarsening
    down to :data:`MAX_COARSE` nodes), built here level by level from pyamg's aggregation and candidate
    fit, with the products on the solid's 3 × 3 blocks and on both cores, and each level's largest
    eigenvalue estimated once (:func:`_prolongator`, :func:`_galerkin`). pyamg's own driver took 4.9 s of
    a 10.3 s solve at 345 k DOF on one core (benchmarks/RESULTS.md).

    Parameters
    ----------
    a : csr_matrix (n, n)
    near_null_space : (n, k) array, optional
        The rigid-body modes restricted to the free unknowns (:func:`rvcoax.fem.rigid_body.rigid_body_modes`).
    dtype : numpy float type
        Precision of the cycle's matrices and vectors.
    """
    n = a.shape[0]
    candidates = (np.ones((n, 1)) if near_null_space is None
                  else np.asarray(near_null_space, dtype=float).reshape(n, -1))
    levels = []
    sizes = [n]
    stored = [a.nnz]
    fine = None  # float64 product with A for the conjugate-gradient iteration
    matrix = a
    block = 1  # unknowns per node of the aggregation graph: 1 on the fine level, k candidates on coarse ones
    with ThreadPoolExecutor(worker_threads()) as pool:
        while matrix.shape[0] // block > MAX_COARSE and len(sizes) < MAX_LEVELS:
            level, exact, matrix, candidates = _coarsen(matrix, candidates, index=len(levels), block=block,
                                                         dtype=dtype, pool=pool)
            levels.append(level)
            fine = exact if fine is None else fine
            block = candidates.shape[1]
            sizes.append(matrix.shape[0])
            stored.append(matrix.nnz)
    coarse = matrix.toarray()
    active = np.flatnonzero(_checked_diagonal(matrix, len(levels)) > 0.0)
    try:
        factor = _CoarseFactor(active, scipy.linalg.cho_factor(coarse[np.ix_(active, active)]), coarse.shape[0])
    except np.linalg.LinAlgError as error:
        raise SolverError(f"AMG coarsest level ({coarse.shape[0]} unknowns) is not positive definite: {error}") from error
    if fine is None:  # a single level: the whole matrix is the coarsest
        fine = SparseOperator.symmetric(a, np.float64)
    return Hierarchy(fine, levels, factor, float(sum(stored)) / float(stored[0]), sizes)
