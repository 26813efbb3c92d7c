"""Find parts that can move as rigid bodies without deforming anything (mechanisms).

For each group of nodes (a part) and for each connected set of parts, the six rigid-body
motions of the group are tested for strain energy against K + β Cᵀ C, where C holds the
constraint equations (fixed DOFs, rigid links). A near-zero eigenvalue of the 6 × 6 energy
matrix is a free motion; its eigenvector names the direction.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.equilibrium import frame_dof_table
from rvcoax.fem.rigid_body import rigid_body_modes

__all__ = ["FreeMotion", "MOTION_NAMES", "constraint_penalty", "find_free_motions", "first_solve_block",
           "scaled_condition_estimate",
           "scaled_inverse_norm_bound", "singularity_and_condition"]

MOTION_NAMES = ("translation x", "translation y", "translation z", "rotation about x",
                "rotation about y", "rotation about z")


@dataclass(frozen=True)
class FreeMotion:
    """A rigid-body motion of some parts that stores no strain energy."""

    parts: tuple[str, ...]
    directions: tuple[str, ...]

    def describe(self) -> str:
        who = ", ".join(f"'{p}'" for p in self.parts)
        noun = "part" if len(self.parts) == 1 else "parts"
        return f"{noun} {who} can move freely ({'; '.join(self.directions)}): no support path to ground"


def _part_modes(coordinates: np.ndarray, nodes: np.ndarray, n_dofs: int) -> np.ndarray:
    """The rigid-body modes (n_dofs, 6) of the frame ``nodes`` (six DOFs each), rotations scaled so that the
    largest motion is about 1; zero elsewhere."""
    extent = max(float(np.ptp(coordinates[nodes], axis=0).max()), 1e-3)
    table = frame_dof_table(coordinates[nodes])
    modes = np.zeros((n_dofs, 6))
    dofs = (DOFS_PER_NODE * nodes[:, None] + np.arange(DOFS_PER_NODE)).ravel()
    modes[dofs] = rigid_body_modes(table.position, table.component, centre=coordinates[nodes].mean(axis=0),
                                   length=extent)
    return modes


def _describe_direction(vector: np.ndarray) -> str:
    weights = np.abs(vector) / np.abs(vector).max()
    names = [MOTION_NAMES[i] for i in np.argsort(-weights) if weights[i] > 0.3]
    return " + ".join(names)


def constraint_penalty(n_dofs: int, elimination: sp.csr_matrix, free_dofs: np.ndarray) -> sp.csr_matrix:
    """Cᵀ C for the constraints encoded in T: each dependent DOF must equal its T row."""
    dependent = np.setdiff1d(np.arange(n_dofs), free_dofs)
    if dependent.size == 0:
        return sp.csr_matrix((n_dofs, n_dofs))
    selector = sp.csr_matrix((np.ones(dependent.size), (np.arange(dependent.size), dependent)),
                             shape=(dependent.size, n_dofs))
    expand = sp.csr_matrix((np.ones(free_dofs.size), (np.arange(free_dofs.size), free_dofs)),
                           shape=(free_dofs.size, n_dofs))
    c = selector - selector @ elimination @ expand
    return (c.T @ c).tocsr()


def find_free_motions(structure, system, *, relative_tolerance: float = 1e-9) -> list[FreeMotion]:
    """Rigid-body motions of single parts, and of connected sets of parts, with no energy.

    ``structure`` gives the node ``coordinates`` and each node's part (``node_group``; a
    :class:`rvcoax.fem.model.StructuralModel`), ``system`` the ``stiffness``, its constraint ``elimination`` and
    ``free_dofs`` (a :class:`rvcoax.fem.pieces.AssembledSystem`).
    """
    coordinates, node_group = structure.coordinates, structure.node_group
    stiffness, elimination, free_dofs = system.stiffness, system.elimination, system.free_dofs
    n_dofs = stiffness.shape[0]
    scale = float(np.abs(stiffness.diagonal()).max()) or 1.0
    k = (stiffness + scale * constraint_penalty(n_dofs, elimination, free_dofs)).tocsr()
    groups = np.asarray(node_group)
    names = list(dict.fromkeys(groups.tolist()))

    def free_directions(nodes: np.ndarray) -> list[str]:
        modes = _part_modes(coordinates, nodes, n_dofs)
        energy = modes.T @ (k @ modes)
        own = np.concatenate([DOFS_PER_NODE * nodes + a for a in range(DOFS_PER_NODE)])
        local_scale = float(np.abs(stiffness.diagonal()[own]).max()) or scale
        values, vectors = np.linalg.eigh(0.5 * (energy + energy.T))
        return [_describe_direction(vectors[:, i]) for i in range(6)
                if values[i] <= relative_tolerance * local_scale]

    found: list[FreeMotion] = []
    # connected sets of parts (through any coupling term in K + penalty)
    node_of_dof = np.arange(n_dofs) // DOFS_PER_NODE
    coo = k.tocoo()
    part_index = {name: i for i, name in enumerate(names)}
    node_part = np.array([part_index[g] for g in groups])
    link = sp.csr_matrix((np.ones(coo.nnz), (node_part[node_of_dof[coo.row]], node_part[node_of_dof[coo.col]])),
                         shape=(len(names), len(names)))
    n_sets, labels = connected_components(link, directed=False)
    reported: set[str] = set()
    for label in range(n_sets):
        members = [names[i] for i in np.flatnonzero(labels == label)]
        nodes = np.flatnonzero(np.isin(groups, members))
        directions = free_directions(nodes)
        if directions:
            found.append(FreeMotion(tuple(members), tuple(directions)))
            reported.update(members)
    for name in names:
        if name in reported:
            continue
        directions = free_directions(np.flatnonzero(groups == name))
        if directions:
            found.append(FreeMotion((name,), tuple(directions)))
    return found


def _diagonal(matrix) -> np.ndarray:
    """The diagonal of a sparse matrix, or of an operator with a ``diagonal()`` method."""
    return np.asarray(matrix.diagonal(), dtype=float)


def scaled_inverse_norm_bound(matrix: sp.spmatrix, solve, steps: int = 2, seed: int = 0) -> tuple[float, int]:
    """Lower bound of ‖S⁻¹‖₂ = 1 / λ_min(S) for the Jacobi-scaled S = D^-½ A D^-½, by inverse iteration.

    Each step solves with the existing factorisation ``solve`` and amplifies the direction of
    λ_min by λ₂ / λ_min against the others, so two steps from a fixed pseudo-random start single
    out a rigid-body motion of a singular matrix whatever its size: the free 3.9 k-DOF solid gives
    1.1e19, the clamped one 6.6e5, the hybrid rig 6.6e7 (S has a unit diagonal, so ‖S‖ ≥ 1 and the
    bound is also one of κ(S)). Deterministic up to the rounding of ``solve``.

    Returns
    -------
    bound : float
        ``inf`` when a solve gives NaN or inf.
    equation : int
        The unknown that moves most in the last iterate (where the weakest motion lives).
    """
    n = matrix.shape[0]
    if n == 0:
        return 0.0, 0
    root = np.sqrt(_diagonal(matrix))
    iteration = _InverseIteration(n, steps, seed)
    iteration.finish(lambda b: root * np.asarray(solve(root * b), dtype=float).reshape(-1))
    return iteration.bound, iteration.equation


class _InverseIteration:
    """The steps of :func:`scaled_inverse_norm_bound` in the scaled space, one column at a time, so that they
    can ride along in the solves of another computation (:func:`singularity_and_condition`)."""

    def __init__(self, n: int, steps: int, seed: int):
        self.y = np.random.default_rng(seed).standard_normal(n)
        self.left = steps
        self.bound = 0.0
        self.equation = 0

    def column(self) -> np.ndarray:
        """The next vector to solve for (the last iterate, normalised)."""
        return self.y / np.linalg.norm(self.y)

    def take(self, y: np.ndarray) -> None:
        """Record S⁻¹ of :meth:`column`."""
        self.left -= 1
        self.y = y
        self.bound = float(np.linalg.norm(y))
        if not np.isfinite(self.bound):
            self.bound, self.equation, self.left = float("inf"), int(np.argmax(~np.isfinite(y))), 0
        elif self.left == 0:
            self.equation = int(np.argmax(np.abs(y)))

    def finish(self, inverse) -> None:
        """The steps still left, each its own solve ``inverse(vector)`` = S⁻¹ vector."""
        while self.left > 0:
            self.take(inverse(self.column()))


def singularity_and_condition(matrix, solve, steps: int = 2, seed: int = 0) -> tuple[float, int, float]:
    """:func:`scaled_inverse_norm_bound` and :func:`scaled_condition_estimate` in the same solves.

    Each inverse-iteration step is one more column in a solve of the condition estimate (the two
    are independent): the estimate's two solve calls are the test's two (a third where its guess misses),
    and a solve call with a direct factor costs far less per added column than per call. Returns (bound,
    equation, condition estimate).
    """
    n = matrix.shape[0]
    if n == 0:
        return 0.0, 0, 1.0
    iteration = _InverseIteration(n, steps, seed)
    kappa = scaled_condition_estimate(matrix, solve, riding=iteration)
    root = np.sqrt(_diagonal(matrix))
    iteration.finish(lambda b: root * np.asarray(solve(root[:, None] * b[:, None]), dtype=float).reshape(-1))
    return iteration.bound, iteration.equation, kappa


def first_solve_block(matrix, seed: int = 0) -> np.ndarray:
    """The block :func:`singularity_and_condition` (its default steps and ``seed``) asks ``solve`` for first: the
    condition estimate's starting vectors and the inverse iteration's first step, scaled, the same numbers. A set-up
    with a solve call of its own to make can carry these columns and serve them back when they are asked for
    (:class:`rvcoax.fem.solvers.SolvedAhead`): one solve call fewer."""
    n = matrix.shape[0]
    root = np.sqrt(_diagonal(matrix))
    return root[:, None] * np.column_stack([_starting_block(n, 1), _InverseIteration(n, 1, seed).column()])


def _scaled_one_norm(matrix, root: np.ndarray) -> float:
    """‖D^-½ A D^-½‖₁ (root = D^½), exact; an operator never formed as one matrix computes it itself."""
    if hasattr(matrix, "scaled_one_norm"):  # fem.system.ConstrainedStiffness
        return float(matrix.scaled_one_norm(root))
    a = sp.csr_matrix(matrix)
    inverse_root = 1.0 / root
    magnitude = sp.csr_matrix((np.abs(a.data), a.indices, a.indptr), shape=a.shape)
    # column j of the scaled matrix sums to (Σ_i |a_ij| / root_i) / root_j: one product with |A|ᵀ, no scaled copy
    return float(((magnitude.T @ inverse_root) * inverse_root).max())


def _starting_block(n: int, t: int) -> np.ndarray:
    """The first solve's columns: t probe vectors of unit 1-norm (ones, then ±1 columns none parallel to another:
    Higham & Tisseur, step 1, made deterministic) and Higham's alternating vector."""
    start = np.ones((n, t))
    for j in range(1, t):
        start[:, j] = np.where((np.arange(n) // j) % 2 == 0, 1.0, -1.0)
    alternating = (-1.0) ** np.arange(n) * (1.0 + np.arange(n) / max(n - 1, 1))
    return np.column_stack([start / n, alternating])


def _unit_columns(n: int, indices) -> np.ndarray:
    """The unit vectors e_k for k in ``indices``, as the columns of an (n, len(indices)) array."""
    indices = np.asarray(indices, dtype=int)
    x = np.zeros((n, indices.size))
    x[indices, np.arange(indices.size)] = 1.0
    return x


def _block_iterations(inverse, y: np.ndarray, estimate: float, *, max_iterations: int,  # noqa: C901
                      hints: tuple[int, ...] = ()) -> float:
    """Steps 2-5 of Higham & Tisseur's Algorithm 2.4 from the first block ``y`` = (scaled A)⁻¹ X and its estimate:
    the largest column 1-norm of (scaled A)⁻¹ found (inf where a solve overflows).

    ``hints``: unit vectors solved along with the first sign vectors (their columns of the inverse count in the
    estimate). ``max_iterations`` is their itmax; with 1 the search ends after the first sign-vector solve,
    and a unit vector that solve points to is solved only where the gain is certain: ‖A⁻¹ e_j‖₁ ≥ |z_j|
    (z = A⁻¹ ξ, ξ a sign vector: Hölder), so e_j is solved when |z_j| exceeds the estimate so far.
    """
    n, t = y.shape
    visited = np.zeros(n, dtype=bool)
    known: dict[int, np.ndarray] = {}  # unit vectors already solved: index → column of the inverse
    best = -1
    old_signs = None
    pending: list[int] = []  # the unit vectors of the next block (set at the end of each iteration)
    z = np.zeros(n)
    for iteration in range(max(max_iterations, 2)):
        if iteration > 0:
            if max_iterations == 1:  # the last block: only where the gain is certain
                pending = [k for k in pending if k in known or z[k] > estimate]
                if not pending:
                    break
            missing = [k for k in pending if k not in known]
            if missing:
                solved = inverse(_unit_columns(n, missing))
                known.update({k: solved[:, c] for c, k in enumerate(missing)})
            y = np.column_stack([known[k] for k in pending])
            sums = np.abs(y).sum(axis=0)
            if not np.all(np.isfinite(sums)):
                return float("inf")
            if sums.max() <= estimate:  # no gain: stop (step 3 of Algorithm 2.4)
                break
            estimate = float(sums.max())
            if iteration >= max_iterations:  # itmax reached: no confirming solve
                break
        signs = np.where(y >= 0, 1.0, -1.0)
        if old_signs is not None and all(np.any(np.all(signs[:, [j]] == old_signs, axis=0)) for j in range(t)):
            break  # every sign vector seen before: converged (step 4)
        old_signs = signs
        guesses = [int(k) for k in dict.fromkeys(hints) if int(k) not in known] if iteration == 0 else []
        solved = inverse(np.column_stack([signs, _unit_columns(n, guesses)]))
        known.update({k: solved[:, t + c] for c, k in enumerate(guesses)})
        found = np.abs(solved[:, t:]).sum(axis=0)
        if not np.all(np.isfinite(found)):
            return float("inf")
        estimate = max([estimate, *found.tolist()])
        z = np.abs(solved[:, :t]).max(axis=1)
        if iteration > 0 and z.max() == z[best]:  # step 5
            break
        order = np.argsort(-z, kind="stable")
        fresh = order[~visited[order]][:t]
        if fresh.size == 0:
            break
        best = int(order[0])
        visited[fresh] = True
        pending = [int(k) for k in fresh]
    return estimate


def scaled_condition_estimate(matrix: sp.spmatrix, solve, max_iterations: int = 1, columns: int = 1, *,  # noqa: PLR0913
                              riding: _InverseIteration | None = None, guided: bool = True) -> float:
    """Estimated 1-norm condition number of the Jacobi-scaled matrix D^-½ A D^-½ (D = diag A).

    The scaling removes what only reflects units (N/m next to N·m/rad), so the number measures how
    many digits a solve loses (about log10 κ of 16). ‖A⁻¹‖₁ is estimated by the block form of Hager's
    method (Hager 1984, "Condition estimates", SIAM J. Sci. Stat. Comput. 5, 311-316; Higham & Tisseur 2000,
    "A block algorithm for matrix 1-norm estimation", SIAM J. Matrix Anal. Appl. 21, 1185-1201, Algorithm 2.4,
    the one behind scipy's ``onenormest``; with one column it is Higham's refinement of Hager's method,
    LAPACK's ``xLACN2``) with ``columns`` probe vectors, each step one multi-column solve with the
    existing factorisation ``solve`` (a symmetric A: A⁻ᵀ = A⁻¹). The start is fixed (the vector of ones,
    then ±1 columns), so the estimate is deterministic, unlike ``onenormest``'s random start; Higham's
    alternating vector rides along in the first solve instead of taking one of its own.

    Solve calls, not columns, are what a factor charges for (62 k-DOF solid: 0.077 s of CPU for one column,
    0.13 s for three), so the search is guided into two calls: the first solve also carries the inverse
    iteration's first step from its fixed random start r (``riding``'s, or the same step of its own), whose
    largest entry marks where the weakest motion lives, and the largest column of A⁻¹ with it (A⁻¹ ≈ v vᵀ / λ_min
    when λ_min stands apart); the second solve, of the sign vector, also solves that unit vector. With
    ``max_iterations`` = 1 (Higham & Tisseur's itmax) the search then ends: the unit vector e_j the sign
    vector's solution z points to is solved (a third call) only where the gain is certain, |z_j| above the
    estimate so far (‖A⁻¹ e_j‖₁ ≥ |z_j| by Hölder's inequality). Every vector solved is a column of A⁻¹ or a
    probe of unit 1-norm, so the result is a lower bound of κ₁ in exact arithmetic; exact for a diagonal matrix
    (1 after the scaling) and for a matrix with a nonnegative inverse (a spring chain's M-matrix: the sign
    vector is the vector of ones and its solution points at the largest column). No factor holds for every
    matrix (Hager 1984; Higham & Tisseur report estimates mostly within a factor of 3). Measured
    (benchmarks/RESULTS.md, issue 27, h27cond): on the beam, hybrid and all-solid (default and 12 mm meshes)
    rigs and the 62 k-DOF solid cantilever the value of the full search (itmax 5, unguided: four to six calls)
    to 6 digits, in two calls; on 200 random graded SPD matrices (κ₁ 1e2 … 1e10) never below 0.53 κ₁ (the full
    search: 0.47 κ₁).

    Parameters
    ----------
    matrix : sparse (n, n), or an operator with ``shape``, ``diagonal()`` and ``scaled_one_norm(root)``
        Symmetric positive definite.
    solve : callable
        X = A⁻¹ B for a block B (n, k).
    max_iterations : int
        Higham & Tisseur's itmax: 1 ends the search after the sign vector's solve (two calls, three where a gain
        is certain); 5 is scipy's ``onenormest`` (up to eleven calls).
    columns : int
        Probe vectors per block (t of Higham & Tisseur).
    riding : optional
        Inverse-iteration steps to take as an extra column of the first solves
        (:func:`singularity_and_condition`).
    guided : bool
        Solve the unit vector the inverse iteration's first step points to (above); False: Higham & Tisseur's
        search alone.
    """
    n = matrix.shape[0]
    if n == 0:
        return 1.0
    diagonal = _diagonal(matrix)
    if np.any(diagonal <= 0) or not np.all(np.isfinite(diagonal)):
        return float("inf")
    root = np.sqrt(diagonal)
    norm = _scaled_one_norm(matrix, root)

    def inverse(b: np.ndarray) -> np.ndarray:  # (D^-½ A D^-½)⁻¹ B = D^½ A⁻¹ D^½ B, all columns at once
        ride = riding is not None and riding.left > 0
        if ride:
            b = np.column_stack([b, riding.column()])
        block = root[:, None] * np.asarray(solve(root[:, None] * b), dtype=float).reshape(n, b.shape[1])
        if ride:
            riding.take(block[:, -1])
            return block[:, :-1]
        return block

    t = max(1, min(columns, n))
    if guided and (riding is None or riding.left == 0):  # the test's first step, or the same step of its own
        riding = _InverseIteration(n, 1, 0)
    first = inverse(_starting_block(n, t))
    y, extra = first[:, :t], float(np.abs(first[:, t]).sum()) * 2.0 / (3.0 * n)
    estimate = float(np.abs(y).sum(axis=0).max())
    if not np.isfinite(estimate) or not np.isfinite(extra):
        return float("inf")
    hints = (int(np.argmax(np.abs(riding.y))),) if guided and np.all(np.isfinite(riding.y)) else ()
    estimate = _block_iterations(inverse, y, estimate, max_iterations=max_iterations, hints=hints)
    return max(estimate, extra) * norm
