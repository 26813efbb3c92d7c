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

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from rvcoax.fem import mkl_sparse, pardiso
from rvcoax.fem.errors import SolverError
from rvcoax.fem.mkl_sparse import SparseOperator

__all__ = ["CHEBYSHEV_DEGREE", "PRECISION", "SMOOTHING_RANGE", "Hierarchy", "smoothed_aggregation"]

CHEBYSHEV_DEGREE = 3
SMOOTHING_RANGE = 30.0  # the smoother damps eigenvalues of D⁻¹A in [λ_max / SMOOTHING_RANGE, 1.1 λ_max]
LAMBDA_MARGIN = 1.1
LANCZOS_STEPS = 15
PRECISION = np.float32


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


def smoothed_aggregation(a: sp.csr_matrix, near_null_space=None, *, dtype=PRECISION) -> Hierarchy:
    """Set up the V-cycle for the symmetric positive definite ``a`` (CSR, sorted indices).

    Parameters
    ----------
    a : csr_matrix (n, n)
    near_null_space : (n, k) array, optional
        The rigid-body modes restricted to the free unknowns (:func:`rvcoax.fem.rigid_body.rigid_body_modes`).
    dtype : numpy float type
        Precision of the cycle's matrices and vectors.
    """
    import pyamg

    b = None if near_null_space is None else np.asarray(near_null_space, dtype=float).reshape(a.shape[0], -1)
    # improve_candidates=None: the rigid-body modes are exact near-null vectors, so pyamg's default
    # Gauss–Seidel sweeps over them cost set-up time (30 % at 158 k DOF) and save no iteration.
    # The smoother pyamg would attach is not used (presmoother/postsmoother None: nothing to set up).
    hierarchy = pyamg.smoothed_aggregation_solver(a, B=b, symmetry="symmetric", improve_candidates=None,
                                                  presmoother=None, postsmoother=None, coarse_solver="splu")
    complexity = float(hierarchy.operator_complexity())
    sizes = [int(level.A.shape[0]) for level in hierarchy.levels]
    levels = []
    fine = None  # float64 product with A for the conjugate-gradient iteration
    for i, level in enumerate(hierarchy.levels[:-1]):
        matrix = a if i == 0 else sp.csr_matrix(level.A)
        matrix.sum_duplicates()
        matrix.sort_indices()
        diagonal = _checked_diagonal(matrix, i)
        if i == 0 and mkl_sparse.available():
            upper = pardiso.upper_storage(matrix)  # once for both precisions
            fine = SparseOperator.from_upper(upper, np.float64)  # CG's product: not optimised (no MKL copy)
            operator = SparseOperator.from_upper(upper, dtype, optimize=True)
            del upper
        else:
            operator = SparseOperator.symmetric(matrix, dtype, optimize=True)
            if i == 0:
                fine = SparseOperator.symmetric(matrix, np.float64)
        del matrix
        inverse_diagonal = np.divide(1.0, diagonal, out=np.zeros_like(diagonal), where=diagonal > 0.0).astype(dtype)
        lam = _largest_eigenvalue(operator, np.sqrt(inverse_diagonal)) * LAMBDA_MARGIN
        low = lam / SMOOTHING_RANGE
        levels.append(_Level(operator, inverse_diagonal, 0.5 * (lam + low), 0.5 * (lam - low),
                             SparseOperator.general(level.P, dtype), SparseOperator.general(level.R, dtype)))
        level.P = level.R = None
        if i > 0:
            level.A = None
    coarse = hierarchy.levels[-1].A.toarray()
    active = np.flatnonzero(_checked_diagonal(sp.csr_matrix(coarse), len(hierarchy.levels) - 1) > 0.0)
    try:
        factor = _CoarseFactor(active, scipy.linalg.cho_factor(coarse[np.ix_(active, active)]), coarse.shape[0])
    except np.linalg.LinAlgError as error:
        raise SolverError(f"AMG coarsest level ({coarse.shape[0]} unknowns) is not positive definite: {error}") from error
    if fine is None:  # a single level: the whole matrix is the coarsest
        fine = SparseOperator.symmetric(a, np.float64)
    return Hierarchy(fine, levels, factor, complexity, sizes)
