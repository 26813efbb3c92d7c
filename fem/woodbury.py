"""The tied stiffness A = Sᵀ K' S solved by a Cholesky factor and a low-rank update (Woodbury identity).

Matrices and vectors only. K' = [[K_qq, K_qp], [K_pq, K_pp]] is the stiffness in the independent DOFs q and
the d DOFs p of the distributing ties' reference nodes (:class:`rvcoax.fem.system.ConstrainedStiffness`), and
p = Q q, Q's rows as long as a tied face. Formed, A = K_qq + K_qp Q + Qᵀ K_pq + Qᵀ K_pp Q is dense where Q is;
the saddle-point form keeps it sparse but is indefinite (PARDISO ``mtype = -2``: perturbed pivots, and two
refinement passes in every solve). Here instead

    A = B + V N Vᵀ,  B = K_qq + G,  V = [Qᵀ, K_qp, E],  N = [[K_pp, I, 0], [I, 0, 0], [0, 0, −G_E]],

where G = E G_E Eᵀ grounds a few DOFs (E: unit columns) of every part that K_qq leaves free to move (a solid
held only by its distributing ties floats once they are released). B is sparse and positive definite:
PARDISO's Cholesky (``mtype = 2``), one pass per solve. With Y = B⁻¹ V (r = 2d + g columns, solved once) and
the r × r capacitance matrix C = N⁻¹ + Vᵀ Y,

    A⁻¹ b = x₀ − Y C⁻¹ Vᵀ x₀,  x₀ = B⁻¹ b,

exact in exact arithmetic (C is nonsingular exactly when A is: det A = det B det N det C), N⁻¹ =
[[0, I, 0], [I, −K_pp, 0], [0, 0, −G_E⁻¹]] always exists.

The grounded DOFs are chosen from the rigid-body modes: in each connected component of K_qq's graph whose
rigid motions K_qq maps to (nearly) zero, as many DOFs as those motions have rank, by pivoted QR of the modes
restricted to the component (the DOFs where the motions are largest and most independent). Grounding more
than needed costs columns of Y, never accuracy: the update removes every added spring exactly.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from rvcoax.fem import diagnostics, pardiso, solvers
from rvcoax.fem.errors import PardisoError, SolverError

__all__ = ["FLOATING_TOLERANCE", "UPDATE_BYTES", "grounded_dofs", "prepare_tied", "update_fits"]

UPDATE_BYTES = 64 * 2**20
"""Largest Y = B⁻¹ V (m × r doubles) this path keeps; larger models use the saddle-point form (the hybrid reference
rig: 108 k × 50 columns, 43 MB; a 500 k-DOF solid rig with twice the ties would need 0.4 GB more at its peak)."""


def update_fits(m: int, rank: int) -> bool:
    """Whether Y = B⁻¹ V of ``m`` unknowns and a rank-``rank`` update (2 per tie, 1 per grounded DOF) stays within
    :data:`UPDATE_BYTES`; with ``rank`` = 2 × ties (no grounding yet), whether this path can apply at all."""
    return 8.0 * m * rank <= UPDATE_BYTES

FLOATING_TOLERANCE = 1e-8
"""A component floats in a rigid mode n when ‖K_cc n‖ ≤ this × max|diag K_cc| × ‖n‖ (rounding leaves ~1e-13)."""


def grounded_dofs(stiffness: sp.csr_matrix, modes: np.ndarray) -> np.ndarray:
    """DOFs to ground so that no connected component of ``stiffness`` can move as a rigid body.

    Parameters
    ----------
    stiffness : csr_matrix (m × m)
        Symmetric positive semi-definite (K_qq: the ties released).
    modes : (m, k) array
        Rigid-body modes in the same DOFs.

    Returns
    -------
    Sorted DOF indices, for each floating component as many as its floating modes have rank.
    """
    count, labels = connected_components(stiffness, directed=False)
    moved = stiffness @ modes
    largest = np.zeros(count)
    np.maximum.at(largest, labels, np.abs(stiffness.diagonal()))
    residual = np.column_stack([np.bincount(labels, moved[:, j] ** 2, count) for j in range(modes.shape[1])])
    size = np.column_stack([np.bincount(labels, modes[:, j] ** 2, count) for j in range(modes.shape[1])])
    floats = (size > 0.0) & (residual <= (FLOATING_TOLERANCE * largest[:, None]) ** 2 * size)
    order = np.argsort(labels, kind="stable")
    starts = np.searchsorted(labels[order], np.arange(count + 1))
    chosen = []
    for component in np.flatnonzero(floats.any(axis=1)):
        dofs = order[starts[component]:starts[component + 1]]
        motions = modes[np.ix_(dofs, np.flatnonzero(floats[component]))]
        _, r, pivots = la.qr(motions.T, mode="economic", pivoting=True)
        rank = int(np.count_nonzero(np.abs(np.diag(r)) > 1e-10 * abs(r[0, 0])))
        chosen.append(dofs[pivots[:rank]])
    return np.sort(np.concatenate(chosen)) if chosen else np.zeros(0, dtype=int)


def _capacitance(core_inverse: np.ndarray, v: sp.csc_matrix, y: np.ndarray):
    """LU of C = N⁻¹ + Vᵀ Y, equilibrated (its blocks differ by many orders: 1, stiffnesses, compliances)."""
    c = core_inverse + (v.T @ y)
    c = 0.5 * (c + c.T)
    scale = np.abs(c).max(axis=1)
    if not np.all(np.isfinite(c)) or np.any(scale <= 0.0):
        return None, None
    root = 1.0 / np.sqrt(scale)
    scaled = root[:, None] * c * root[None, :]
    lu = la.lu_factor(scaled, check_finite=False)
    pivots = np.abs(np.diag(lu[0]))
    if pivots.min() <= 1e-13 * pivots.max():  # A (numerically) singular, or B too far from it: not this path
        return None, None
    return lu, root


def _upper_blocks(b: sp.csr_matrix) -> pardiso.UpperStorage:
    """B's upper block triangle in PARDISO's 3 × 3 block storage, every block touched stored whole (the entries B
    lacks as explicit zeros); scalar storage where B's size is no multiple of 3.

    The ordering then works on the graph of the blocks, 9 times smaller than that of the unknowns: on the hybrid
    reference rig (108 k unknowns, 8.2 M nonzeros; 4 % more stored as zeros) PARDISO's analysis took 0.3 s CPU instead
    of 0.9–1.3 s, and the factor has the same 47 M nonzeros (benchmarks/RESULTS.md). B's beam and tie unknowns
    mixed into the solids' (u_x, u_y, u_z) triples by the constraint elimination do not form whole blocks by
    themselves, so :func:`rvcoax.fem.pardiso.upper_storage` alone would keep it scalar.
    """
    if b.shape[0] % pardiso.BLOCK_SIZE:
        return pardiso.upper_storage(b)
    blocks = b.tobsr(blocksize=(pardiso.BLOCK_SIZE, pardiso.BLOCK_SIZE))
    blocks.sort_indices()
    return pardiso.upper_block_storage(blocks)


@dataclass(frozen=True)
class _Update:
    """The low-rank part of A = B + V N Vᵀ: V, N⁻¹ and the grounding G (DOFs, springs)."""

    v: sp.csc_matrix
    core_inverse: np.ndarray
    ground: np.ndarray
    springs: np.ndarray


def _tie_released(operator) -> sp.csr_matrix | None:
    """K_qq (canonical, no stored zeros), the pattern and values of B but for the grounding springs on its diagonal;
    None where Y would exceed :data:`UPDATE_BYTES` with the ties alone or K_qq has an empty row."""
    m, d = operator.shape[0], operator.dependent.shape[0]
    if d == 0 or not update_fits(m, 2 * d):
        return None
    k_qq = sp.csr_matrix(operator.kept)[:m, :m].tocsr()
    k_qq.eliminate_zeros()  # B = K_qq + G as a sum stores none: the same pattern
    k_qq.sum_duplicates()
    k_qq.sort_indices()
    if np.any(k_qq.diagonal() <= 0.0):  # PARDISO may crash on an empty row
        return None
    return k_qq


def _update(operator, k_qq: sp.csr_matrix, modes: np.ndarray | None) -> _Update | None:
    """V, N⁻¹ and the grounding of A = B + V N Vᵀ; None where Y would exceed :data:`UPDATE_BYTES`."""
    kept, dependent = sp.csr_matrix(operator.kept), sp.csr_matrix(operator.dependent)
    m, d = operator.shape[0], dependent.shape[0]
    ground = grounded_dofs(k_qq, modes) if modes is not None else np.zeros(0, dtype=int)
    rank = 2 * d + ground.size
    if not update_fits(m, rank):
        return None
    springs = k_qq.diagonal()[ground]
    v = sp.hstack([dependent.T, kept[:m, m:], sp.csr_matrix((np.ones(ground.size), (ground, np.arange(ground.size))),
                                                            shape=(m, ground.size))]).tocsc()
    core_inverse = np.zeros((rank, rank))
    core_inverse[:d, d:2 * d] = core_inverse[d:2 * d, :d] = np.eye(d)
    core_inverse[d:2 * d, d:2 * d] = -kept[m:, m:].toarray()
    core_inverse[2 * d:, 2 * d:] = -np.diag(1.0 / springs)
    return _Update(v, core_inverse, ground, springs)


def _factorise_released(operator, modes: np.ndarray | None, serve):
    """PARDISO's Cholesky factor of B = K_qq + G with the update's pieces: (factor, ``operator`` as served, the
    :class:`_Update`, B's stored nonzeros), or None where this path does not apply (:func:`prepare_tied`)."""
    k_qq = _tie_released(operator)
    if k_qq is None:
        return None
    storage, stored = _upper_blocks(k_qq), k_qq.nnz
    # PARDISO's ordering needs B's pattern only, K_qq's: it runs on a worker thread (serial METIS, one core) while
    # this one grounds the floating parts, forms V and N⁻¹ and A's diagonal (the hybrid rig: 0.27 s of ordering beside
    # ~0.25 s)
    factor = pardiso.Factorization(storage, two_level=True, reproducible=True, defer=True)
    try:
        released = _update(operator, k_qq, modes)
        del k_qq
        if released is None:
            factor.release(keep_analysis=False)
            return None
        operator.diagonal()  # A's diagonal (the singularity test's scaling), kept by the operator: also beside it
        factor.wait_for_analysis()
        pardiso.add_to_diagonal(storage, released.ground, released.springs)  # B = K_qq + G
        if serve is not None:  # with ``serve``, the whole K' goes here (it reads B's values: after the springs)
            operator = serve(operator, storage, released.ground, released.springs)
        factor.factorise()
    except PardisoError:
        factor.release(keep_analysis=False)
        return None  # not positive definite: some part still floats (modes missing or not rigid-body modes)
    except BaseException:
        factor.release(keep_analysis=False)  # waits for the analysis thread, frees MKL's memory
        raise
    return factor, operator, released, stored


def prepare_tied(operator, modes: np.ndarray | None, *, serve=None,
                 ahead: np.ndarray | None = None) -> solvers.PreparedSolver | None:
    """Set up A = Sᵀ K' S (``operator``) by Cholesky of the tie-released K_qq plus a low-rank update.

    Parameters
    ----------
    operator : rvcoax.fem.system.ConstrainedStiffness
        A, with K' whole (``kept`` a csr matrix) and Q (``dependent``).
    modes : (m, k) array, optional
        Rigid-body modes of the independent DOFs q; without them only a K_qq that holds every part is used.
    serve : callable, optional
        ``serve(operator, storage, ground, springs)`` → the same A with K' applied from B's upper triangle
        ``storage`` (:func:`rvcoax.fem.system._serve`), so that the whole K' is freed before PARDISO's factor is
        allocated (a caller that keeps no reference of its own to ``operator``).
    ahead : (m, k) array, optional
        Right-hand sides the caller will ask for (a sweep's unit loads, reduced): solved in the set-up's own solve
        call, with the update's columns and the singularity test's first block, and served from there
        (:class:`rvcoax.fem.solvers.SolvedAhead`) instead of costing solve calls of their own.

    Returns
    -------
    PreparedSolver, or None where this path does not apply: Y above :data:`UPDATE_BYTES`, a K_qq that the
    grounding does not make positive definite, or a first solve not accurate to
    :data:`rvcoax.fem.solvers.REFINE_ABOVE` (the caller then uses the saddle-point form).

    Raises
    ------
    SingularMatrixError
        A is singular (the inverse iteration of :func:`rvcoax.fem.diagnostics.singularity_and_condition` on A).
    """
    rss_before = solvers.peak_rss_mb()
    start = time.perf_counter()
    m = operator.shape[0]
    factorised = _factorise_released(operator, modes, serve)
    if factorised is None:
        return None
    factor, operator, released, stored = factorised
    v, ground = released.v, released.ground
    rank = released.core_inverse.shape[0]
    probe = np.random.default_rng(0).standard_normal((m, 1))  # rides along: is the update accurate?
    # so do the singularity test's first block and the caller's loads: the solve call is a pass over the whole factor
    early = np.column_stack([diagnostics.first_solve_block(operator), *([] if ahead is None else [ahead])])
    y = factor.solve(np.column_stack([v.toarray(), probe, early]))
    y, probe_x0, early_x0 = y[:, :rank], y[:, rank:rank + 1], y[:, rank + 1:]
    lu, root = _capacitance(released.core_inverse, v, y)
    if lu is None:
        factor.release(keep_analysis=False)
        return None

    def update(x):
        x -= y @ (root[:, None] * la.lu_solve(lu, root[:, None] * (v.T @ x), check_finite=False))
        return x

    def solve_with_factor(block):
        try:
            return update(factor.solve(block)), (), ()
        except PardisoError as error:
            raise SolverError(str(error)) from error

    residual = np.linalg.norm(probe - operator @ update(probe_x0)) / np.linalg.norm(probe)
    if not residual <= solvers.REFINE_ABOVE:
        factor.release(keep_analysis=False)
        return None
    solve = solvers.SolvedAhead(solve_with_factor, early, update(early_x0))
    condition = solvers.refuse_singular(operator, solve, factor)
    name = (f"pardiso (MKL PARDISO, SPD, mtype=2: Cholesky of the stiffness with the ties released and "
            f"{ground.size} DOF(s) grounded, ties and groundings as a rank-{rank} update)")
    return solvers.PreparedSolver(operator, name, solve, setup_seconds=time.perf_counter() - start,
                                  rss_before=rss_before, release=factor.release,
                                  factor=(factor.factor_nonzeros, factor.memory_MB + y.nbytes / 2**20,
                                          factor.reused_analysis),
                                  matrix_nonzeros=stored, condition=condition)
