"""Static solution: one sparse factorisation reused for any number of load vectors."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import solvers


@dataclass(frozen=True, eq=False)
class FactorizedSystem:
    """A factorised reduced stiffness Tᵀ K T, ready to solve for many load vectors.

    Attributes
    ----------
    stiffness : csr_matrix
        Full stiffness K (n × n).
    elimination : csr_matrix
        T, mapping independent DOFs to all DOFs.
    solver : rvcoax.fem.solvers.PreparedSolver
        The factorisation of Tᵀ K T.
    """

    stiffness: sp.csr_matrix
    elimination: sp.csr_matrix
    solver: object

    @property
    def solver_name(self) -> str:
        return self.solver.report.name

    def solve(self, load: np.ndarray) -> np.ndarray:
        """Displacements for one load vector (n,) or several (n, m), full DOF numbering.

        Raises :class:`SingularModelError` (from the solver) on NaN or a residual above 1e-6.
        """
        return self.elimination @ self.solver.solve(self.elimination.T @ np.asarray(load, dtype=float))

    def condition_estimate(self) -> float:
        """Estimated condition number of the Jacobi-scaled Tᵀ K T (:func:`rvcoax.fem.diagnostics.scaled_condition_estimate`)."""
        return self.solver.condition_estimate()

    def relative_residual(self, displacement: np.ndarray, load: np.ndarray) -> np.ndarray:
        """‖Tᵀ (K u − f)‖ / ‖Tᵀ f‖ per load vector."""
        f = np.asarray(load, dtype=float)
        r = self.elimination.T @ (self.stiffness @ displacement - f)
        scale = np.linalg.norm(self.elimination.T @ f, axis=0)
        return np.linalg.norm(r, axis=0) / np.where(scale > 0, scale, 1.0)


def factorize(stiffness: sp.csr_matrix, elimination: sp.csr_matrix) -> FactorizedSystem:
    """Factorise Tᵀ K T with SuperLU (beam models have a few thousand DOFs).

    The factorisation is :func:`rvcoax.fem.solvers.prepare`'s ``"superlu"`` method, the one SuperLU path of
    the project: symmetric mode, and a singularity test that compares each pivot with its own
    diagonal entry, so that N/m and N·m/rad equations are judged fairly. Every solve checks its
    residual and raises :class:`SingularModelError` on NaN or a residual above 1e-6.
    """
    reduced = (elimination.T @ stiffness @ elimination).tocsr()
    prepared = solvers.prepare((reduced + reduced.T) * 0.5, method="superlu")
    return FactorizedSystem(stiffness, elimination, prepared)
