"""Measured cost of the sparse solvers: time and memory of PARDISO and AMG-CG from the system's sizes.

Matrices' sizes only (no meshes). :func:`rvcoax.fem.solvers.choose_method` uses :data:`COST_MODEL` to
pick, for ``"auto"``, the method that is expected to finish first among those whose memory fits.

- **PARDISO** (MKL, SPD, 3 × 3 blocks, 2 threads): the factorisation's time and memory grow as powers
  of the number of unknowns n (nested dissection on a 3-D mesh: flops ~ n², factor ~ n^(4/3));
  each right-hand side costs one forward and back substitution, ~ the factor's size.
- **AMG-CG** (pyamg smoothed aggregation, one V-cycle per CG iteration): set-up, every iteration
  and the memory are proportional to the matrix's stored nonzeros; the iterations per right-hand
  side to reach :data:`rvcoax.fem.solvers.AMG_ACCURACY` are nearly independent of the size.

Every constant is fitted to measurements on the development machine (2-core AMD EPYC, idle) of
the solid cantilever of ``benchmarks/bench_solid_scaling.py`` (P2 tets, 80 stored nonzeros per row);
benchmarks/RESULTS.md, block "bench_solver_choice.py", has the runs behind each one. Other machines
differ by a small factor, which moves the cross-over by less than that factor; re-measure there
(``benchmarks/bench_solver_choice.py``), not here.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["COST_MODEL", "NONZEROS_PER_ROW", "SolverCostModel"]

NONZEROS_PER_ROW = 80.0  # P2 tetrahedra, 3 unknowns per node (stored, both triangles): used when nnz is unknown


@dataclass(frozen=True)
class SolverCostModel:
    """Time (s) and memory (bytes) of PARDISO and AMG-CG as functions of size and right-hand sides.

    PARDISO: ``factor_s · (n / 1e5)^factor_exponent`` + ``n_rhs · substitution_s · (n / 1e5)^substitution_exponent``
    seconds; ``factor_bytes · (n / 1e5)^factor_memory_exponent`` + 12 bytes per stored nonzero (its
    upper-triangle copy of the matrix) bytes.
    AMG: ``(amg_setup_s_per_nnz + n_rhs · amg_iterations · amg_iteration_s_per_nnz) · nnz`` seconds;
    ``amg_bytes_per_nnz · nnz`` bytes.
    """

    factor_s: float
    factor_exponent: float
    substitution_s: float
    substitution_exponent: float
    factor_bytes: float
    factor_memory_exponent: float
    amg_setup_s_per_nnz: float
    amg_iteration_s_per_nnz: float
    amg_iterations: float
    amg_bytes_per_nnz: float

    def pardiso_seconds(self, n_dofs: int, n_rhs: int = 1) -> float:
        scale = n_dofs / 1e5
        return self.factor_s * scale ** self.factor_exponent + n_rhs * self.substitution_s * scale ** self.substitution_exponent

    def pardiso_bytes(self, n_dofs: int, nonzeros: float) -> float:
        return self.factor_bytes * (n_dofs / 1e5) ** self.factor_memory_exponent + 6.0 * nonzeros

    def amg_seconds(self, nonzeros: float, n_rhs: int = 1) -> float:
        return (self.amg_setup_s_per_nnz + n_rhs * self.amg_iterations * self.amg_iteration_s_per_nnz) * nonzeros

    def amg_bytes(self, nonzeros: float) -> float:
        return self.amg_bytes_per_nnz * nonzeros


COST_MODEL = SolverCostModel(
    factor_s=2.5, factor_exponent=1.78, substitution_s=0.014, substitution_exponent=1.22,
    factor_bytes=0.57e9, factor_memory_exponent=1.38,
    amg_setup_s_per_nnz=1.4e-7, amg_iteration_s_per_nnz=9.2e-9, amg_iterations=45.0, amg_bytes_per_nnz=40.0,
)
"""Fitted to benchmarks/RESULTS.md, block "bench_solver_choice.py" (see the module docstring)."""
