"""The one entry to the linear solvers: reduce K with the constraint elimination T, set up a solver for
Tᵀ K T, solve any number of load vectors in the full DOF numbering, and check residuals.

Matrices and vectors only (no rigs, no meshes). :func:`prepare_system` is used for every model
(beam, hybrid, solid) and every method (SuperLU, PARDISO, AMG: :mod:`rvcoax.fem.solvers`);
:func:`factorize` is its SuperLU form for small models.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import solvers

__all__ = ["ReducedSystem", "factorize", "prepare_system", "reduced_stiffness"]


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


def prepare_system(stiffness: sp.csr_matrix, elimination: sp.csr_matrix, method: str = "auto",
                   near_null_space: Callable[[], np.ndarray] | None = None, symmetrize: bool = False) -> ReducedSystem:
    """Reduce K with T and set up ``method`` for Tᵀ K T.

    Parameters
    ----------
    stiffness, elimination : csr_matrix
        K (n × n) and T (n × m).
    method : {"auto", "superlu", "pardiso", "amg"}
        ``"auto"`` picks by size (:func:`rvcoax.fem.solvers.choose_method`).
    near_null_space : callable, optional
        Returns the rigid-body modes of the full DOF vector (n × k); called only when AMG is used.
    symmetrize : bool
        See :func:`reduced_stiffness`.

    Raises
    ------
    rvcoax.fem.errors.SingularMatrixError
        A direct factorisation found Tᵀ K T singular.
    """
    reduced = reduced_stiffness(stiffness, elimination, symmetrize)
    chosen = solvers.choose_method(reduced.shape[0]) if method == "auto" else method
    modes = elimination.T @ near_null_space() if chosen == "amg" and near_null_space is not None else None
    return ReducedSystem(stiffness, elimination, solvers.prepare(reduced, method=chosen, near_null_space=modes))


def factorize(stiffness: sp.csr_matrix, elimination: sp.csr_matrix) -> ReducedSystem:
    """Tᵀ K T factorised with SuperLU (beam models have a few thousand DOFs).

    SuperLU in symmetric mode, with a singularity test that compares each pivot with its own
    diagonal entry, so that N/m and N·m/rad equations are judged fairly. Every solve checks its
    residual and raises :class:`rvcoax.fem.errors.SingularMatrixError` on NaN or a residual above 1e-6.
    """
    return prepare_system(stiffness, elimination, "superlu", symmetrize=True)
