"""Static solution: one sparse factorisation reused for any number of load vectors."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


class SingularModelError(RuntimeError):
    """The stiffness matrix is singular: some part can move without deforming anything."""


@dataclass(frozen=True, eq=False)
class FactorizedSystem:
    """A factorised reduced stiffness Tᵀ K T, ready to solve for many load vectors.

    Attributes
    ----------
    stiffness : csr_matrix
        Full stiffness K (n × n).
    elimination : csr_matrix
        T, mapping independent DOFs to all DOFs.
    solver_name : str
    """

    stiffness: sp.csr_matrix
    elimination: sp.csr_matrix
    solver_name: str
    _solve: object

    def solve(self, load: np.ndarray) -> np.ndarray:
        """Displacements for one load vector (n,) or several (n, m), full DOF numbering."""
        f = np.asarray(load, dtype=float)
        reduced = self.elimination.T @ f
        q = self._solve(reduced)
        u = self.elimination @ q
        if not np.all(np.isfinite(u)):
            raise SingularModelError("the solution contains NaN or inf: the model is singular")
        return u

    def solve_reduced(self, reduced_load: np.ndarray) -> np.ndarray:
        """q = (Tᵀ K T)⁻¹ r for a load ``r`` in the independent DOFs (no NaN check)."""
        return self._solve(np.asarray(reduced_load, dtype=float))

    def relative_residual(self, displacement: np.ndarray, load: np.ndarray) -> np.ndarray:
        """‖Tᵀ (K u − f)‖ / ‖Tᵀ f‖ per load vector."""
        f = np.asarray(load, dtype=float)
        r = self.elimination.T @ (self.stiffness @ displacement - f)
        scale = np.linalg.norm(self.elimination.T @ f, axis=0)
        return np.linalg.norm(r, axis=0) / np.where(scale > 0, scale, 1.0)


def factorize(stiffness: sp.csr_matrix, elimination: sp.csr_matrix) -> FactorizedSystem:
    """Factorise Tᵀ K T with SuperLU (sparse direct; beam models have a few thousand DOFs)."""
    reduced = (elimination.T @ stiffness @ elimination).tocsc()
    reduced = (reduced + reduced.T) * 0.5
    try:
        lu = spla.splu(reduced.tocsc(), permc_spec="MMD_AT_PLUS_A")
    except RuntimeError as error:  # "Factor is exactly singular"
        raise SingularModelError(str(error)) from error
    diagonal = np.abs(lu.U.diagonal())
    if diagonal.size and diagonal.min() <= 1e-14 * diagonal.max():
        raise SingularModelError(
            f"pivot ratio {diagonal.min() / diagonal.max():.1e}: the stiffness is numerically singular"
        )
    return FactorizedSystem(stiffness, elimination, "SuperLU (scipy.sparse.linalg.splu)", lu.solve)
