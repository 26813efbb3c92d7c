"""Six-component springs (bushings) between two nodes or between a node and ground.

A bushing sits at a point ``c``. Each attached node reaches ``c`` through a rigid arm, so the
relative motion at ``c`` is Δ = B_b u_b − B_a u_a with B = [[I, −[r]×], [0, I]], r = c − x_node.
The spring force is diag(k) Δ in global axes: a rigid-body motion of the pair stores no energy,
also when the nodes are not coincident. Ground bushings have no node ``a``. Bearings, mounts,
flexible couplings and gear meshes are all bushings with different stiffness components.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.contribution import Contribution
from rvcoax.fem.errors import GapConvergenceError  # noqa: F401 (re-exported)

__all__ = ["Bushings", "CondensedSolution", "GROUND", "GapSolution", "RadialGaps", "gap_forces", "motion_operator",
           "prepare_radial_gaps", "prestrain_entries", "prestrain_load", "radial_operator", "relative_motion_operator",
           "solve_condensed", "solve_with_gaps", "spring_forces", "stiffness_triplets"]

GROUND = -1
"""Node index meaning "the fixed ground"."""


@dataclass(frozen=True)
class Bushings:
    """A table of bushings (SI).

    Parameters
    ----------
    node_a, node_b : (n,) int arrays
        Attached nodes; ``node_a == GROUND`` attaches ``node_b`` to the ground.
    point_m : (n, 3) array
        Location of each spring.
    stiffness : (n, 6) array
        Diagonal stiffness in global axes: kx, ky, kz (N/m) and krx, kry, krz (N·m/rad).
    """

    node_a: np.ndarray
    node_b: np.ndarray
    point_m: np.ndarray
    stiffness: np.ndarray

    def contribution(self, coordinates: np.ndarray, n_dofs: int, gravity_direction) -> Contribution:
        """The springs' stiffness (:func:`stiffness_triplets`); a spring has no weight."""
        return Contribution(stiffness_triplets(coordinates, self))

    def mass_contribution(self, coordinates: np.ndarray) -> None:
        """None: a spring carries no mass (its parts' masses are elements of their own)."""
        return None


def _arm_matrix(arm: np.ndarray) -> np.ndarray:
    """B (n, 6, 6) mapping a node's DOFs to the motion of a rigidly attached point."""
    n = arm.shape[0]
    b = np.zeros((n, 6, 6))
    b[:, :3, :3] = np.eye(3)
    b[:, 3:, 3:] = np.eye(3)
    # u_point = u + θ × r = u − r × θ  →  −[r]× θ
    rx, ry, rz = arm[:, 0], arm[:, 1], arm[:, 2]
    b[:, 0, 4], b[:, 0, 5] = rz, -ry
    b[:, 1, 3], b[:, 1, 5] = -rz, rx
    b[:, 2, 3], b[:, 2, 4] = ry, -rx
    return b


def relative_motion_operator(coordinates: np.ndarray, bushings: Bushings):
    """Per bushing: the (6, 12) operator from [u_a, u_b] to Δ and the 12 DOF numbers.

    For ground bushings the first six columns are zero and their DOF numbers are −1.
    """
    point = np.asarray(bushings.point_m, dtype=float)
    node_a = np.asarray(bushings.node_a)
    node_b = np.asarray(bushings.node_b)
    grounded = node_a == GROUND
    coords_a = np.where(grounded[:, None], point, coordinates[np.where(grounded, 0, node_a)])
    b_a = _arm_matrix(point - coords_a)
    b_b = _arm_matrix(point - coordinates[node_b])
    b_a[grounded] = 0.0
    operator = np.concatenate([-b_a, b_b], axis=2)
    offsets = np.arange(DOFS_PER_NODE)
    dofs_a = np.where(grounded[:, None], -1, DOFS_PER_NODE * node_a[:, None] + offsets)
    dofs_b = DOFS_PER_NODE * node_b[:, None] + offsets
    return operator, np.concatenate([dofs_a, dofs_b], axis=1)


def stiffness_triplets(coordinates: np.ndarray, bushings: Bushings):
    """Global stiffness of all bushings as COO triplets ``(rows, cols, values)``."""
    if len(bushings.node_b) == 0:
        empty = np.zeros(0)
        return empty.astype(int), empty.astype(int), empty
    operator, dofs = relative_motion_operator(coordinates, bushings)
    k = np.einsum("eji,ej,ejk->eik", operator, np.asarray(bushings.stiffness, float), operator)
    rows = np.repeat(dofs, 12, axis=1).ravel()
    cols = np.tile(dofs, (1, 12)).ravel()
    keep = (rows >= 0) & (cols >= 0)
    return rows[keep], cols[keep], k.ravel()[keep]


def spring_forces(coordinates: np.ndarray, bushings: Bushings, displacement: np.ndarray) -> np.ndarray:
    """Force and moment carried by each bushing, diag(k) Δ, shape (n, 6) (N, N·m).

    It is what the spring exerts on node ``a`` (and the ground); node ``b`` gets the opposite.
    """
    operator, dofs = relative_motion_operator(coordinates, bushings)
    u = np.where(dofs >= 0, displacement[np.maximum(dofs, 0)], 0.0)
    delta = np.einsum("eij,ej->ei", operator, u)
    return np.asarray(bushings.stiffness, float) * delta


def prestrain_entries(coordinates: np.ndarray, bushings: Bushings, stress_free: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Equivalent nodal load of bushings that are free of load at a relative motion Δ0 ≠ 0, as (DOFs, values).

    A bushing with a stress-free relative motion Δ0 (a misaligned coupling, a raised mount) exerts
    diag(k) (Δ − Δ0): on the straight, unloaded structure it pushes its nodes with
    f = Opᵀ diag(k) Δ0 (Op the relative-motion operator). The pair on two nodes is
    self-equilibrated; on a ground bushing it is reacted by the ground. ``stress_free`` is (n, 6).
    A DOF appears once per bushing attached to it (the entries are summed where they are assembled).
    """
    stress_free = np.asarray(stress_free, dtype=float)
    if len(bushings.node_b) == 0 or not np.any(stress_free):
        return np.zeros(0, dtype=int), np.zeros(0)
    operator, dofs = relative_motion_operator(coordinates, bushings)
    nodal = np.einsum("eji,ej->ei", operator, np.asarray(bushings.stiffness, float) * stress_free)
    keep = dofs >= 0
    return dofs[keep], nodal[keep]


def prestrain_load(coordinates: np.ndarray, bushings: Bushings, stress_free: np.ndarray, n_dofs: int) -> np.ndarray:
    """:func:`prestrain_entries` summed into a load vector of length ``n_dofs``."""
    load = np.zeros(n_dofs)
    np.add.at(load, *prestrain_entries(coordinates, bushings, stress_free))
    return load


# ---- radial clearance (bearings with play) ----------------------------------------------------------
# A bearing with radial clearance c carries F = k (|d| − c) d/|d| for |d| > c, else nothing, d the
# radial (y, z) relative motion at the bearing. The structure is linear elsewhere, so the problem
# is condensed on the 2m radial motions d of the m gapped bearings. With K the stiffness *with*
# the radial springs fully engaged (c = 0; the model as assembled), U the radial operator,
# W = K⁻¹ Uᵀ and S = U W (2m × 2m):
#     K_lin u + Uᵀ F(U u) = f   ⇔   u = K⁻¹ f + W G(d),  d = U u,  G(d) = k d − F(d),
# so d solves R(d) = d − U K⁻¹ f − S G(d) = 0, a small nonlinear system solved by Newton's method
# on the tangent (active set: open springs have G' = k I, closed ones k c/|d| (I − n nᵀ)).


@dataclass(frozen=True, eq=False)
class RadialGaps:
    """Bearings with radial clearance, condensed for repeated nonlinear solves (SI).

    Attributes
    ----------
    operator : (2m, n) sparse matrix
        U: the (y, z) relative motion at each gapped bushing, rows 2i and 2i + 1.
    stiffness, clearance : (m,) arrays
        Radial stiffness k (N/m) and clearance c (m, > 0).
    influence : (n, 2m) array
        W = K⁻¹ Uᵀ with K the stiffness with every radial spring engaged.
    compliance : (2m, 2m) array
        S = U W.
    """

    operator: object
    stiffness: np.ndarray
    clearance: np.ndarray
    influence: np.ndarray
    compliance: np.ndarray


@dataclass(frozen=True)
class GapSolution:
    """A converged solution with gaps: displacement, radial motions, which gaps are closed."""

    displacement: np.ndarray
    radial_motion: np.ndarray  # (m, 2) m
    closed: np.ndarray  # (m,) bool
    iterations: int
    condensed_residual: float


def radial_operator(coordinates: np.ndarray, bushings: Bushings, rows, n_dofs: int):
    """U (2m × n_dofs, CSR): the y and z relative motion at the point of each bushing in ``rows``."""
    return motion_operator(coordinates, bushings, rows, n_dofs, (1, 2))


def motion_operator(coordinates: np.ndarray, bushings: Bushings, rows, n_dofs: int, components=tuple(range(6))):
    """U (c·m × n_dofs, CSR): the ``components`` (of x, y, z, θx, θy, θz) of the relative motion at the
    point of each bushing in ``rows``, c rows per bushing in the order given."""
    import scipy.sparse as sp

    rows = np.asarray(rows, dtype=int)
    components = tuple(components)
    width = len(components)
    subset = Bushings(np.asarray(bushings.node_a)[rows], np.asarray(bushings.node_b)[rows],
                      np.asarray(bushings.point_m)[rows], np.asarray(bushings.stiffness)[rows])
    operator, dofs = relative_motion_operator(coordinates, subset)
    r, c, v = [], [], []
    for i in range(rows.size):
        for local, component in enumerate(components):
            keep = dofs[i] >= 0
            r.extend([width * i + local] * int(keep.sum()))
            c.extend(dofs[i][keep].tolist())
            v.extend(operator[i, component][keep].tolist())
    return sp.csr_matrix((v, (r, c)), shape=(width * rows.size, n_dofs))


def prepare_radial_gaps(solve, operator, stiffness, clearance) -> RadialGaps:
    """Condense the gapped bearings on a solver ``solve`` of the fully engaged stiffness K."""
    influence = np.asarray(solve(operator.T.toarray()), dtype=float).reshape(operator.shape[1], -1)
    return RadialGaps(operator, np.asarray(stiffness, float), np.asarray(clearance, float), influence,
                      np.asarray(operator @ influence))


def gap_forces(radial_motion: np.ndarray, stiffness: np.ndarray, clearance: np.ndarray) -> np.ndarray:
    """F = k (|d| − c) d/|d| where |d| > c, else 0; ``radial_motion`` (m, 2) → (m, 2) (N)."""
    d = np.asarray(radial_motion, dtype=float).reshape(-1, 2)
    size = np.linalg.norm(d, axis=1)
    closed = size > clearance
    scale = np.where(closed, stiffness * (1.0 - clearance / np.where(closed, size, 1.0)), 0.0)
    return scale[:, None] * d


def _released(d: np.ndarray, gaps: RadialGaps) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """G(d) = k d − F(d) (m, 2), its tangent (2m × 2m) and the closed states."""
    k, c = gaps.stiffness, gaps.clearance
    size = np.linalg.norm(d, axis=1)
    closed = size > c
    value = k[:, None] * d - gap_forces(d, k, c)
    tangent = np.zeros((2 * k.size, 2 * k.size))
    for i in range(k.size):
        block = slice(2 * i, 2 * i + 2)
        if closed[i]:
            n = d[i] / size[i]
            tangent[block, block] = k[i] * c[i] / size[i] * (np.eye(2) - np.outer(n, n))
        else:
            tangent[block, block] = k[i] * np.eye(2)
    return value, tangent, closed


def solve_with_gaps(gaps: RadialGaps, solve, load: np.ndarray, tolerance: float = 1e-13,
                    max_iterations: int = 100) -> GapSolution:
    """Static solution of a structure whose gapped bearings follow the clearance law
    (:func:`solve_condensed` with the clearance law's released force G(d) = k d − F(d)).

    Raises
    ------
    GapConvergenceError
        No convergence within ``max_iterations``.
    """
    def released(w):
        value, tangent, _ = _released(w.reshape(-1, 2), gaps)
        return value.ravel(), tangent

    solution = solve_condensed(gaps, solve, load, released, tolerance, max_iterations=max_iterations, what="bearing-clearance")
    d = solution.motion.reshape(-1, 2)
    return GapSolution(solution.displacement, d, np.linalg.norm(d, axis=1) > gaps.clearance, solution.iterations,
                       solution.condensed_residual)


@dataclass(frozen=True)
class CondensedSolution:
    """A converged solution of :func:`solve_condensed`."""

    displacement: np.ndarray
    motion: np.ndarray  # (p,) w = U u
    released: np.ndarray  # (p,) G(w)
    iterations: int
    condensed_residual: float


def solve_condensed(condensed, solve, load: np.ndarray, released, tolerance: float = 1e-13,  # noqa: PLR0913
                    *, max_iterations: int = 100, what: str = "nonlinear spring",
                    regularisation: np.ndarray | None = None) -> CondensedSolution:
    """Static solution of a linear structure with nonlinear springs, condensed on their motions.

    ``condensed`` holds U (``operator``), W = K⁻¹ Uᵀ (``influence``) and S = U W (``compliance``) of
    the structure K *with* the springs' linear reference stiffness K_ref; ``released(w)`` returns
    G(w) = K_ref w − F(w) (what the nonlinear law releases of the reference) and its tangent
    K_ref − ∂F/∂w. Then K u = f + Uᵀ G(U u), so w = U u solves R(w) = w − U K⁻¹ f − S G(w) = 0:
    Newton's method on this small system (Jacobian I − S G'(w), least-squares steps), from the
    reference solution, with a backtracking line search on ‖R‖. Converged when
    ‖R‖ ≤ ``tolerance`` × (‖w‖ + ‖U K⁻¹ f‖ + ‖S G(w)‖): the residual relative to the terms it is
    computed from, whose floating-point floor is a few machine epsilons (1e-13 ≈ 450 ε). No scale
    of the law (a clearance) enters: measured against a clearance, a small load in an open gap
    stopped with an error far above the case's own forces. A continuous law needs no unchanged
    active set: a spring at the edge of its dead band may switch state from step to step.

    ``regularisation`` (p × p, e.g. a small share of K_ref) is for laws with a dead band of zero
    stiffness: where a part hangs on such springs alone the exact Jacobian is singular there and its
    least-squares step cannot reduce R. Then (the linearised residual not halved, or no decrease along
    the exact step) the step of the Jacobian with the tangent stiffened by ``regularisation`` is taken.
    The residual is always the exact one, so the solution does not depend on the regularisation.

    Raises
    ------
    GapConvergenceError
        No convergence within ``max_iterations``.
    """
    linear = np.asarray(solve(load), dtype=float)
    start = np.asarray(condensed.operator @ linear).ravel()
    S = condensed.compliance
    eye = np.eye(S.shape[0])

    def residual(w):
        value, tangent = released(w)
        coupled = S @ value
        scale = float(np.linalg.norm(w) + np.linalg.norm(start) + np.linalg.norm(coupled))
        return w - start - coupled, tangent, value, scale

    def search(w, step, norm):
        t = 1.0
        while True:
            trial = w + t * step
            state = residual(trial)
            if np.linalg.norm(state[0]) < norm or t < 1e-6:
                return trial, state, bool(np.linalg.norm(state[0]) < norm)
            t *= 0.5

    w = start.copy()
    r, tangent, value, scale = residual(w)
    for iteration in range(1, max_iterations + 1):
        norm = float(np.linalg.norm(r))
        if norm <= tolerance * scale:
            u = linear + condensed.influence @ value
            return CondensedSolution(u, w, value, iteration - 1, norm / scale if scale > 0 else 0.0)
        jacobian = eye - S @ tangent
        step, *_ = np.linalg.lstsq(jacobian, -r, rcond=1e-14)
        stalled = regularisation is not None and np.linalg.norm(jacobian @ step + r) > 0.5 * norm
        if not stalled:
            trial, state, decreased = search(w, step, norm)
            stalled = regularisation is not None and not decreased
        if stalled:
            step, *_ = np.linalg.lstsq(eye - S @ (tangent - regularisation), -r, rcond=1e-14)
            trial, state, _ = search(w, step, norm)
        w, (r, tangent, value, scale) = trial, state
    raise GapConvergenceError(f"the {what} iteration did not converge in {max_iterations} steps "
                              f"(relative residual {np.linalg.norm(r) / max(scale, 1e-300):.1e}, "
                              f"limit {tolerance:.0e})")
