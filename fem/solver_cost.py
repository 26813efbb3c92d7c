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
    AMG: ``(amg_setup_s_per_nnz + n_rhs · iterations · amg_iteration_s_per_nnz) · nnz`` seconds with
    ``iterations = amg_iterations · (n / 1e5)^amg_iteration_exponent``; ``amg_bytes_per_nnz · nnz`` bytes
    above the matrix.
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
    amg_iteration_exponent: float
    amg_bytes_per_nnz: float

    def pardiso_seconds(self, n_dofs: int, n_rhs: int = 1) -> float:
        scale = n_dofs / 1e5
        return self.factor_s * scale ** self.factor_exponent + n_rhs * self.substitution_s * scale ** self.substitution_exponent

    def pardiso_bytes(self, n_dofs: int, nonzeros: float) -> float:
        return self.factor_bytes * (n_dofs / 1e5) ** self.factor_memory_exponent + 6.0 * nonzeros

    def amg_seconds(self, nonzeros: float, n_rhs: int = 1, n_dofs: float | None = None) -> float:
        n = nonzeros / NONZEROS_PER_ROW if n_dofs is None else n_dofs
        iterations = self.amg_iterations * (n / 1e5) ** self.amg_iteration_exponent
        return (self.amg_setup_s_per_nnz + n_rhs * iterations * self.amg_iteration_s_per_nnz) * nonzeros

    def amg_bytes(self, nonzeros: float) -> float:
        return self.amg_bytes_per_nnz * nonzeros


COST_MODEL = SolverCostModel(
    # PARDISO: 61 k, 158 k, 341 k DOF at load average 0.5-1.7 (set-up 1.03, 5.66, 21.9 s; factor 276, 1042, 2951 MB;
    # 20 solves - 1 solve: 7.6, 20, 62 ms per right-hand side). Under load 3-4 its two threads slowed 4x at 341 k (92 s).
    factor_s=2.5, factor_exponent=1.78, substitution_s=0.014, substitution_exponent=1.22,
    factor_bytes=0.57e9, factor_memory_exponent=1.38,
    # AMG-CG with the default stopping rule: 42, 46 and 52 iterations at 61 k, 341 k and 1.14 M DOF (fem/amg.py's
    # Chebyshev cycle). Set-up: 0.9e-7 s per nonzero, estimated for an idle machine from CPU times under load
    # (341 k DOF: 3.2 s CPU, where pyamg's driver took 6.0-6.8 s CPU and 4.94 s idle wall; 61 k DOF: 0.57 s CPU).
    # One iteration: 1.7e-9 s per nonzero, the cantilever's idle runs (1.6-1.8e-9: 1.96 s / 45 it. at 341 k,
    # 8.94 s / 52 it. at 1.14 M DOF). These constants hold for plain elasticity (a part with its supports
    # eliminated), the system they were measured on. A rig's tied system is not such a system: the all-solid rig
    # forced onto AMG (`rvcoax sweep --model solid --solver amg`, 492 k DOF, one case) peaked at 10.3 GB and had not
    # finished after 176 s of CPU time (stopped), where PARDISO's whole sweep takes 26.8 s and 4.14 GB; so
    # rvcoax.fem.system.prepare_system chooses for it with ``amg_cost_known=False`` (AMG only where PARDISO's
    # memory does not fit). 29.5 bytes per nonzero above the matrix at 341 k DOF (pyamg's driver: 37.5).
    amg_setup_s_per_nnz=0.9e-7, amg_iteration_s_per_nnz=1.7e-9, amg_iterations=45.0, amg_iteration_exponent=0.15,
    amg_bytes_per_nnz=30.0,
)
"""Fitted to benchmarks/RESULTS.md, block "bench_solver_choice.py" (see the module docstring)."""
