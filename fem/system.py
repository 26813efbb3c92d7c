"""The one entry to the linear solvers: reduce K with the constraint elimination T, set up a solver for
Tᵀ K T, solve any number of load vectors in the full DOF numbering, and check residuals.

Matrices and vectors only (no rigs, no meshes). :func:`prepare_system` is used for every model
(beam, hybrid, solid) and every method (SuperLU, PARDISO, AMG: :mod:`rvcoax.fem.solvers`);
:func:`factorize` is its SuperLU form for small models.

**Long rows of T without fill-in.** A distributing (RBE3-like) tie makes its reference node's DOFs
combinations of every DOF of a solid face: rows of T as long as the face. Tᵀ K T then couples every
pair of face DOFs that the springs at the reference node reach, a dense block per face (the
reference rig's hybrid model: 33.7 M nonzeros at 87 k DOF, 389 per row, where P2 tetrahedra alone
give about 80). For PARDISO, :func:`prepare_system` instead keeps the DOFs of the long rows as
unknowns p and imposes p = T_p q by Lagrange multipliers (:class:`ConstrainedStiffness`,
:func:`rvcoax.fem.solvers.prepare_saddle_point`); the solution is the same to rounding, and Tᵀ K T is
never formed.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import memory, pardiso, solvers, woodbury

__all__ = ["LONG_ROW", "ConstrainedStiffness", "ReducedSystem", "ReleasedStiffness", "UpperTriangleOperator", "constrained_stiffness",
           "factorize", "independent_modes", "long_rows", "prepare_system", "reduced_stiffness", "tied_rows"]

LONG_ROW = 64
"""A row of T with more nonzeros than this (a distributing tie's reference DOF over a face of 22 or more
nodes) is kept as an unknown with a multiplier when PARDISO solves; rigid links and rigid ties have 1–6."""


def long_rows(elimination: sp.csr_matrix, longer_than: int = LONG_ROW) -> np.ndarray:
    """The rows of T (DOFs) with more than ``longer_than`` nonzeros."""
    t = sp.csr_matrix(elimination)
    return np.flatnonzero(np.diff(t.indptr) > longer_than)


def tied_rows(stiffness: sp.csr_matrix, elimination: sp.csr_matrix, longer_than: int = LONG_ROW) -> np.ndarray:
    """The long rows of T (:func:`long_rows`) whose DOF has stiffness (a nonzero in its row of K).

    A DOF that no element or spring touches adds nothing to Tᵀ K T, however long its row of T: a reference
    node's rotations where only a force acts, its axial DOF where a bearing is radial only. Kept as unknowns
    with multipliers, each such DOF is a 2 × 2 block [[0, c], [c, 0]] that PARDISO's 1 × 1 pivots perturb (20 of
    the 21 perturbed pivots of the reference rig's hybrid model); left in T, it is only an output (u = T q).
    """
    long = long_rows(elimination, longer_than)
    k = sp.csr_matrix(stiffness)
    touched = np.asarray(abs(k[long]).sum(axis=1)).reshape(-1) > 0.0
    return long[touched]


def independent_modes(elimination: sp.csr_matrix, modes: np.ndarray) -> np.ndarray | None:
    """Rigid-body modes (n × k, all DOFs) restricted to the independent DOFs q (m × k), or None.

    An independent DOF's row of T is a single 1 in its own column (u_i = q_j); a dependent DOF may have such a
    row too (a rigid link's rotation, θ_s = θ_m), and under constraints that keep rigid motions it carries the
    same value. None when some column of T has no such row.
    """
    t = sp.csr_matrix(elimination)
    count = np.diff(t.indptr)
    rows = np.flatnonzero(count == 1)
    rows = rows[t.data[t.indptr[rows]] == 1.0]
    columns, first = np.unique(t.indices[t.indptr[rows]], return_index=True)
    if columns.size != t.shape[1]:
        return None
    return np.asarray(modes, dtype=float).reshape(t.shape[0], -1)[rows[first]]


class UpperTriangleOperator:
    """A symmetric K (k × k) applied from the leading k rows and columns of a stored upper triangle.

    PARDISO keeps the upper triangle of the saddle-point matrix (:class:`rvcoax.fem.pardiso.UpperStorage`)
    for its solves anyway; its leading block is K'. Applying K' from it (K' x = U x + Uᵀ x − diag(K') x,
    the arrays shared, not copied) lets the whole K' go before the factorisation: at 420 k DOF 0.4 GB
    less at PARDISO's peak. The products round differently from those of the whole K' (a few units in the
    last place of each entry of K' x).

    Parameters
    ----------
    storage : rvcoax.fem.pardiso.UpperStorage
        Scalar CSR, whose leading ``size`` rows and columns are K's upper triangle; or 3 × 3 blocks (the
        Cholesky path's B, :mod:`rvcoax.fem.woodbury`), of which a scalar upper triangle is made once (the
        blocks' own arrays are PARDISO's).
    size : int
    """

    def __init__(self, storage: pardiso.UpperStorage, size: int):
        n = storage.n
        if storage.block_size != 1:
            blocks = sp.bsr_matrix((storage.data, storage.indices, storage.indptr), shape=(n, n)).tocsr()
            blocks.sort_indices()
            storage = pardiso.upper_csr(blocks)  # the diagonal blocks are stored whole: their lower entries go
        self._upper = sp.csr_matrix((storage.data, storage.indices, storage.indptr), shape=(n, n), copy=False)
        self.shape = (size, size)
        self.dtype = np.dtype(float)
        self._diagonal = self._upper.diagonal()[:size]

    def diagonal(self) -> np.ndarray:
        return self._diagonal.copy()

    def absolute_product(self, x: np.ndarray, nonzeros_per_chunk: int = 1 << 21) -> np.ndarray:
        """|K'| x for a vector x (entries of K' by absolute value), from the same upper triangle, taken by absolute
        value ``nonzeros_per_chunk`` entries (whole rows) at a time.

        Not |U| whole: that copy of the upper triangle (0.24 GB at 492 k DOF) was made next to PARDISO's factor, at
        the singularity test's start, and was the all-solid rig's peak there (benchmarks/RESULTS.md). Each row's part
        is the same sum as before; the transposed part's sums are grouped by chunk (rounding differences only).
        """
        k, n = self.shape[0], self._upper.shape[0]
        upper = self._upper
        padded = np.zeros(n)
        padded[:k] = x
        rows_part, columns_part = np.zeros(n), np.zeros(n)
        bounds = np.searchsorted(upper.indptr, np.arange(0, upper.indptr[-1], nonzeros_per_chunk), side="right") - 1
        bounds = np.unique(np.append(bounds, n))
        for start, stop in zip(bounds[:-1], bounds[1:]):
            first, last = upper.indptr[start], upper.indptr[stop]
            chunk = sp.csr_matrix((np.abs(upper.data[first:last]), upper.indices[first:last],
                                   upper.indptr[start:stop + 1] - first), shape=(stop - start, n))
            rows_part[start:stop] = chunk @ padded
            columns_part += chunk.T @ padded[start:stop]
        return rows_part[:k] + columns_part[:k] - np.abs(self._diagonal) * x

    def __matmul__(self, x):
        k, n = self.shape[0], self._upper.shape[0]
        if sp.issparse(x):
            padded = sp.vstack([sp.csr_matrix(x), sp.csr_matrix((n - k, x.shape[1]))]).tocsr()
            return ((self._upper @ padded)[:k] + (self._upper.T @ padded).tocsr()[:k]
                    - sp.diags(self._diagonal) @ sp.csr_matrix(x))
        x = np.asarray(x, dtype=float)
        padded = np.zeros((n,) + x.shape[1:])
        padded[:k] = x
        diagonal = self._diagonal.reshape((k,) + (1,) * (x.ndim - 1))
        return (self._upper @ padded)[:k] + (self._upper.T @ padded)[:k] - diagonal * x


def _absolute(kept, x: np.ndarray) -> np.ndarray:
    """|K'| x for K' stored whole (csr) or as an operator (:class:`UpperTriangleOperator`, :class:`ReleasedStiffness`)."""
    if hasattr(kept, "absolute_product"):
        return kept.absolute_product(x)
    return abs(kept) @ x


class ReleasedStiffness:
    """K' = [[K_qq, K_qp], [K_pq, K_pp]] applied from the Cholesky path's own arrays, without K' stored whole.

    The factorised B = K_qq + G (:mod:`rvcoax.fem.woodbury`) is kept as PARDISO's upper triangle anyway; K_qq is
    B less the grounding springs G (a few diagonal entries), and K_qp, K_pp are as small as the ties' springs.
    On the hybrid reference rig this is 0.1 GB less than K' whole.

    Parameters
    ----------
    grounded : UpperTriangleOperator
        B (m × m), from its upper triangle.
    ground, springs : arrays
        The grounded DOFs and their springs (G).
    coupling : csr_matrix (m × d)
        K_qp.
    ties : csr_matrix (d × d)
        K_pp.
    """

    def __init__(self, grounded: UpperTriangleOperator, ground: np.ndarray, springs: np.ndarray,  # noqa: PLR0913
                 coupling: sp.csr_matrix, ties: sp.csr_matrix):
        self._grounded = grounded
        m, d = coupling.shape
        self._springs = sp.csr_matrix((springs, (ground, ground)), shape=(m, m))
        self._coupling = sp.csr_matrix(coupling)
        self._ties = sp.csr_matrix(ties)
        self.shape = (m + d, m + d)
        self.dtype = np.dtype(float)
        self._diagonal = np.concatenate([grounded.diagonal() - self._springs.diagonal(), self._ties.diagonal()])

    def diagonal(self) -> np.ndarray:
        return self._diagonal.copy()

    def _apply(self, grounded_part, springs, coupling, ties, x):
        m = self._coupling.shape[0]
        q, p = x[:m], x[m:]
        top = grounded_part(q) - springs @ q + coupling @ p
        bottom = coupling.T @ q + ties @ p
        return sp.vstack([top, bottom]).tocsr() if sp.issparse(x) else np.concatenate([top, bottom])

    def __matmul__(self, x):
        if not sp.issparse(x):
            x = np.asarray(x, dtype=float)
        return self._apply(self._grounded.__matmul__, self._springs, self._coupling, self._ties, x)

    def absolute_product(self, x: np.ndarray) -> np.ndarray:
        """|K'| x (B's diagonal exceeds G's, so |K_qq| = |B| − G)."""
        return self._apply(self._grounded.absolute_product, self._springs, abs(self._coupling), abs(self._ties),
                           np.asarray(x, dtype=float))


class ConstrainedStiffness:
    """A = Sᵀ K' S (m × m) with S = [I; Q]: Tᵀ K T without forming it.

    K' = T'ᵀ K T' is the stiffness in the unknowns y = [q; p], T' being T with its long rows replaced
    by unit columns of p; the long rows themselves are Q (p = Q q), and T' S = T. Only K', Q and
    the saddle-point matrix built from them are stored.

    Attributes
    ----------
    kept : csr_matrix ((m + d) × (m + d)) or UpperTriangleOperator
        K' (after :meth:`served_from`, read from PARDISO's input).
    dependent : csr_matrix (d × m)
        Q.
    """

    def __init__(self, kept: sp.csr_matrix, dependent: sp.csr_matrix):
        self.kept = kept.tocsr() if sp.issparse(kept) else kept
        self.dependent = dependent.tocsr()
        m = dependent.shape[1]
        self.shape = (m, m)
        self.dtype = np.dtype(float)
        self._expansion = sp.vstack([sp.identity(m, format="csr"), self.dependent]).tocsr()  # S
        self._diagonal: np.ndarray | None = None

    def __matmul__(self, x: np.ndarray) -> np.ndarray:
        return self._expansion.T @ (self.kept @ (self._expansion @ x))

    def diagonal(self) -> np.ndarray:
        """diag(Sᵀ K' S), one column of S at a time in effect (sparse products, no dense block).

        Computed once and kept (a copy is returned): the product K' S it needs is as large as K', and
        the singularity test and the condition estimate ask for it again while the factor is alive.
        """
        if self._diagonal is None and sp.issparse(self.kept):
            # diag(K_qq + K_qp Q + Qᵀ K_pq + Qᵀ K_pp Q), block by block: only Q's columns get the three
            # corrections, so the product K' S (as large as K') is never formed
            m, q = self.shape[0], self.dependent
            kept = self.kept
            coupled = kept[m:].tocsr()  # [K_pq, K_pp] (d rows)
            corrections = (sp.csr_matrix(kept[:m, m:].T).multiply(q) + coupled[:, :m].multiply(q)
                           + (coupled[:, m:] @ q).multiply(q))
            self._diagonal = kept.diagonal()[:m] + np.asarray(corrections.sum(axis=0)).reshape(-1)
        elif self._diagonal is None:
            ks = (self.kept @ self._expansion).tocsc()
            self._diagonal = np.asarray(ks.multiply(self._expansion).sum(axis=0)).reshape(-1)
        return self._diagonal.copy()

    def scaled_one_norm(self, root: np.ndarray, columns_per_chunk: int = 2048) -> float:
        """‖diag(1/root) A diag(1/root)‖₁, exact, A formed ``columns_per_chunk`` columns at a time, and only where
        it can matter.

        The tie rows make A dense in blocks (each face's DOFs with each other), so forming all of it is
        the cost (1.5 s on the hybrid rig). Every column's sum of |entries| is at most that of
        |Sᵀ| |K'| |S| (no cancellation), which costs three sparse products with one vector; columns are
        formed in the order of that bound, and the search stops when the largest exact sum found is at
        least the bound of every column not yet formed. The maximum is the same number: the columns
        that decide it are formed exactly as before.
        """
        s = self._expansion.tocsc()
        st = self._expansion.T.tocsr()
        inverse_root = 1.0 / root
        magnitude = abs(s)
        bound = (magnitude.T @ _absolute(self.kept, magnitude @ inverse_root)) * inverse_root
        bound *= 1.0 + 1e-12  # the rounding of the exact sums below cannot lift one above its bound
        order = np.argsort(-bound, kind="stable")
        norm = 0.0
        for start in range(0, self.shape[0], columns_per_chunk):
            if norm >= bound[order[start]]:
                break
            chosen = np.sort(order[start:start + columns_per_chunk])
            block = (st @ (self.kept @ s[:, chosen])).tocsc()
            sums = np.asarray(abs(sp.diags(inverse_root) @ block).sum(axis=0)).reshape(-1) / root[chosen]
            norm = max(norm, float(sums.max(initial=0.0)))
        return norm

    def constraint(self) -> sp.csr_matrix:
        """C = D [−Q, I] (d × (m + d)), D scaling each multiplier row to its p's stiffness."""
        m, d = self.shape[0], self.dependent.shape[0]
        scale = self.kept.diagonal()[m:]
        scale = np.where(scale > 0.0, scale, 1.0)
        return sp.diags(scale) @ sp.hstack([-self.dependent, sp.identity(d)]).tocsr()

    def saddle_point_matrix(self) -> sp.csr_matrix:
        """[[K', Cᵀ], [C, 0]] (both triangles; the solver needs only :meth:`saddle_point_upper`)."""
        c = self.constraint()
        return sp.bmat([[self.kept, c.T], [c, None]], format="csr")

    def served_from(self, upper: pardiso.UpperStorage) -> ConstrainedStiffness:
        """The same A with K' applied from ``upper`` (:meth:`saddle_point_upper`'s arrays, shared): the whole
        K' is then no longer needed. The diagonal of A is computed first, from the whole K', and carried over."""
        served = ConstrainedStiffness(UpperTriangleOperator(upper, self.kept.shape[0]), self.dependent)
        served._diagonal = self.diagonal()
        return served

    def served_by(self, kept) -> ConstrainedStiffness:
        """The same A with K' applied by ``kept`` (a :class:`ReleasedStiffness`); the diagonal of A is computed
        first, from the whole K', and carried over."""
        served = ConstrainedStiffness(kept, self.dependent)
        served._diagonal = self.diagonal()
        return served

    def saddle_point_upper(self) -> pardiso.UpperStorage:
        """The upper triangle of :meth:`saddle_point_matrix`, the same arrays as ``pardiso.upper_csr`` of it, built
        from K' and C without forming the whole matrix (at 420 k DOF that matrix is 0.4 GB more at PARDISO's peak)."""
        return pardiso.upper_saddle_point(self.kept, self.constraint())


def constrained_stiffness(stiffness: sp.csr_matrix, elimination: sp.csr_matrix, rows: np.ndarray) -> ConstrainedStiffness:
    """Tᵀ K T as :class:`ConstrainedStiffness`, the DOFs ``rows`` (long rows of T) kept as unknowns."""
    t = sp.csr_matrix(elimination)
    n, m = t.shape
    rows = np.asarray(rows, dtype=int)
    keep = np.ones(n, dtype=bool)
    keep[rows] = False
    short = sp.diags(keep.astype(float)) @ t  # T with the long rows emptied
    unit = sp.csr_matrix((np.ones(rows.size), (rows, np.arange(rows.size))), shape=(n, rows.size))
    expanded = sp.hstack([short, unit]).tocsr()  # T'
    # K T' first, then T'ᵀ as a CSR matrix: scipy's product of T'ᵀ (CSC) with K went through conversions (the hybrid
    # rig: 0.17-0.4 s, this way 0.08 s; the same pattern, the values to the rounding of the sums' order)
    kept = (expanded.T.tocsr() @ (stiffness @ expanded)).tocsr()
    return ConstrainedStiffness(kept, t[rows])


@dataclass(frozen=True, eq=False)
class ReducedSystem:
    """A reduced stiffness Tᵀ K T with its solver set up, ready to solve for many load vectors.

    Attributes
    ----------
    stiffness : csr_matrix
        Full stiffness K (n × n).
    elimination : csr_matrix
        T, mapping independent DOFs to all DOFs (u = T q).
    solver : rvcoax.fem.solvers.PreparedSolver
        The factorisation (or AMG hierarchy) of Tᵀ K T.
    """

    stiffness: sp.csr_matrix
    elimination: sp.csr_matrix
    solver: solvers.PreparedSolver

    @property
    def solver_name(self) -> str:
        return self.solver.report.name

    def solve(self, load: np.ndarray) -> np.ndarray:
        """Displacements for one load vector (n,) or several (n, m), full DOF numbering.

        Raises :class:`rvcoax.fem.errors.SingularMatrixError` (from the solver) on NaN or, for a
        direct solver, a residual above 1e-6.
        """
        return self.elimination @ self.solver.solve(self.elimination.T @ np.asarray(load, dtype=float))

    def condition_estimate(self) -> float | None:
        """Estimated condition number of the Jacobi-scaled Tᵀ K T (direct solvers; None for AMG)."""
        return self.solver.condition_estimate()

    def relative_residual(self, displacement: np.ndarray, load: np.ndarray) -> np.ndarray:
        """‖Tᵀ (K u − f)‖ / ‖Tᵀ f‖ per load vector."""
        f = np.asarray(load, dtype=float)
        r = self.elimination.T @ (self.stiffness @ displacement - f)
        scale = np.linalg.norm(self.elimination.T @ f, axis=0)
        return np.linalg.norm(r, axis=0) / np.where(scale > 0, scale, 1.0)

    def summary(self) -> dict:
        """Method, size, set-up and solve time, peak memory and condition estimate, as a plain dict."""
        report = self.solver.report
        return {"name": report.name, "n_dofs": report.n_dofs, "setup_seconds": report.setup_seconds,
                "solve_seconds": report.solve_seconds, "peak_memory_MB": report.peak_memory_MB,
                "condition_estimate": self.condition_estimate()}


def reduced_stiffness(stiffness: sp.csr_matrix, elimination: sp.csr_matrix, symmetrize: bool = False) -> sp.csr_matrix:
    """Tᵀ K T; with ``symmetrize`` the mean of it and its transpose (removes the rounding asymmetry of the
    triple product, which SuperLU's symmetric mode would otherwise see)."""
    reduced = (elimination.T @ stiffness @ elimination).tocsr()
    return (reduced + reduced.T) * 0.5 if symmetrize else reduced


def _serve(operator: ConstrainedStiffness, storage: pardiso.UpperStorage, ground: np.ndarray,
           springs: np.ndarray) -> ConstrainedStiffness:
    """``operator`` with K' applied from B's upper triangle ``storage`` (:class:`ReleasedStiffness`)."""
    m = operator.shape[0]
    kept = operator.kept
    return operator.served_by(ReleasedStiffness(UpperTriangleOperator(storage, m), ground, springs,
                                                kept[:m, m:].tocsr(), kept[m:, m:].tocsr()))


MOVE_OUT_BYTES = 256 * 2**20
"""A stiffness K larger than this (its CSR arrays) goes to a file while PARDISO factorises and solves the tied
saddle-point matrix (:func:`_move_out_while_factorising`)."""


def _move_out_while_factorising(stiffness: sp.csr_matrix) -> bool:
    """Move K (above :data:`MOVE_OUT_BYTES`) out of resident memory (:func:`rvcoax.fem.memory.move_to_file`) once the
    saddle-point matrix is built from it: the factorisation, the singularity test and the solves read only that matrix
    (A is applied from its upper triangle), and K is next read by the caller's residuals and reactions, after the
    solves. The all-solid reference rig at 492 k DOF: K 0.46 GB less at the peak (benchmarks/RESULTS.md). K's values
    are unchanged; where no temporary file can be written it stays in memory."""
    size = sum(getattr(stiffness, name).nbytes for name in ("data", "indices", "indptr"))
    return size > MOVE_OUT_BYTES and memory.move_to_file(stiffness)


def prepare_system(stiffness: sp.csr_matrix, elimination: sp.csr_matrix, method: str = "auto",  # noqa: PLR0913
                   near_null_space: Callable[[], np.ndarray] | None = None, symmetrize: bool = False,
                   *, n_rhs: int = 1, ahead: Callable[[], np.ndarray | None] | None = None) -> ReducedSystem:
    """Reduce K with T and set up ``method`` for Tᵀ K T.

    Parameters
    ----------
    stiffness, elimination : csr_matrix
        K (n × n) and T (n × m).
    method : {"auto", "superlu", "pardiso", "amg"}
        ``"auto"`` picks by size, nonzeros (those of K stand in for Tᵀ K T's), ``n_rhs`` and the
        memory available (:func:`rvcoax.fem.solvers.choose_method`).
    near_null_space : callable, optional
        Returns the rigid-body modes of the full DOF vector (n × k); called only when AMG is used.
    symmetrize : bool
        See :func:`reduced_stiffness`.
    n_rhs : int
        How many right-hand sides the set-up will serve (a sweep: its unit loads).
    ahead : callable, optional
        Returns the load vectors (n, k), full DOF numbering, or None, that the caller will solve next; called only
        where the set-up makes a solve call of its own (the tied Cholesky path,
        :func:`rvcoax.fem.woodbury.prepare_tied`): they ride along in it, and :meth:`ReducedSystem.solve` serves them
        from there. Elsewhere they are solved when asked for, as any load.

    Raises
    ------
    rvcoax.fem.errors.SingularMatrixError
        A direct factorisation found Tᵀ K T singular.
    """
    # a DOF tied to several others (a row of T with more than one entry) makes this a rig's tied system, not the
    # plain elasticity whose AMG iterations the cost model knows (rvcoax.fem.solver_cost)
    chosen = (solvers.choose_method(elimination.shape[1], stiffness.nnz, n_rhs,
                                    amg_cost_known=long_rows(elimination, 1).size == 0) if method == "auto" else method)
    long = tied_rows(stiffness, elimination) if chosen == "pardiso" and solvers.pardiso_available() else np.zeros(0, dtype=int)
    if long.size:
        # too large an update with the ties alone: the Cholesky path would refuse only after K' is formed (the
        # all-solid rig: 156 multipliers, 2 s of K' for nothing)
        if woodbury.update_fits(elimination.shape[1], 2 * long.size):
            modes = independent_modes(elimination, near_null_space()) if near_null_space is not None else None
            # no reference kept here: the Cholesky path lets K' go once it serves K' from its own arrays
            loads = None if ahead is None else ahead()
            reduced_ahead = None if loads is None else np.asarray(elimination.T @ loads).reshape(elimination.shape[1], -1)
            del loads
            updated = woodbury.prepare_tied(constrained_stiffness(stiffness, elimination, long), modes, serve=_serve,
                                            ahead=reduced_ahead)
            del reduced_ahead
            del modes
            if updated is not None:
                return ReducedSystem(stiffness, elimination, updated)
        operator = constrained_stiffness(stiffness, elimination, long)
        upper = operator.saddle_point_upper()
        operator = operator.served_from(upper)  # K' itself is freed here, before PARDISO allocates its factor
        _move_out_while_factorising(stiffness)
        return ReducedSystem(stiffness, elimination, solvers.prepare_saddle_point(operator, upper))
    reduced = reduced_stiffness(stiffness, elimination, symmetrize)
    modes = elimination.T @ near_null_space() if chosen == "amg" and near_null_space is not None else None
    return ReducedSystem(stiffness, elimination, solvers.prepare(reduced, method=chosen, near_null_space=modes))


def factorize(stiffness: sp.csr_matrix, elimination: sp.csr_matrix) -> ReducedSystem:
    """Tᵀ K T factorised with SuperLU (beam models have a few thousand DOFs).

    SuperLU in symmetric mode, with a singularity test that compares each pivot with its own
    diagonal entry, so that N/m and N·m/rad equations are judged fairly. Every solve checks its
    residual and raises :class:`rvcoax.fem.errors.SingularMatrixError` on NaN or a residual above 1e-6.
    """
    return prepare_system(stiffness, elimination, "superlu", symmetrize=True)
