"""Sparse symmetric positive definite solvers: one set-up, any number of right-hand sides.

Matrices and vectors only (no meshes). Three methods (their measured costs: benchmarks/RESULTS.md,
bench_solid_scaling.py):

- ``"superlu"``: scipy's SuperLU (``splu``), symmetric mode. Robust, no extra dependency; best
  for small systems (time and memory grow fast: 14 GB at 300 k DOF).
- ``"pardiso"``: Intel MKL PARDISO (:mod:`rvcoax.fem.pardiso`) in SPD mode (``mtype=2``, upper triangle
  only; the unsymmetric mode costs twice the time and memory), in 3 × 3 blocks when the matrix
  is made of them (a solid). Fastest up to a few 100 k DOF; all right-hand sides in one call.
  x86-64 only.
- ``"amg"``: pyamg smoothed aggregation (near null space: the rigid-body modes), V-cycle of :mod:`rvcoax.fem.amg`, as a
  preconditioner of conjugate gradients. Least memory; the hierarchy is built once and serves every
  right-hand side. CG stops when the estimated relative error of the displacement in the energy norm
  is below ``accuracy`` (:data:`AMG_ACCURACY`, 1e-6) and the relative residual below
  :data:`AMG_RESIDUAL_LIMIT` (see :func:`conjugate_gradients`), not at a fixed tiny residual.

``"auto"`` picks SuperLU below ``superlu_max_dofs`` (20 k: small models solve exactly as they always
have); above, PARDISO or AMG, whichever the measured cost model (:mod:`rvcoax.fem.solver_cost`)
expects to finish first for the system's unknowns, stored nonzeros and number of right-hand sides,
among those whose memory fits in what the machine has available (AMG without MKL).

:func:`prepare_saddle_point` solves an SPD matrix that is never formed (Tᵀ K T with distributing ties,
:class:`rvcoax.fem.system.ConstrainedStiffness`) through its sparse saddle-point form, with PARDISO in
symmetric indefinite mode; its inertia and the same inverse-iteration test refuse a singular matrix.
"""

from __future__ import annotations

import hashlib
import resource
import time
import weakref
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rvcoax.fem import pardiso
from rvcoax.fem.diagnostics import scaled_inverse_norm_bound, singularity_and_condition
from rvcoax.fem.errors import SingularMatrixError, SolverError
from rvcoax.fem.memory import available_memory_bytes
from rvcoax.fem.solver_cost import COST_MODEL, NONZEROS_PER_ROW, SolverCostModel

__all__ = ["AMG_ACCURACY", "AMG_ERROR_DELAY", "AMG_RESIDUAL_LIMIT", "DIRECT_RESIDUAL_LIMIT", "METHODS",
           "PreparedSolver", "SINGULAR_INVERSE_NORM", "SINGULAR_PIVOT_RATIO", "SUPERLU_MAX_DOFS", "SolvedAhead",
           "SolverReport",
           "choose_method", "conjugate_gradients", "pardiso_available", "peak_rss_mb", "prepare", "prepare_saddle_point",
           "refuse_singular"]

METHODS = ("superlu", "pardiso", "amg")
SUPERLU_MAX_DOFS = 20_000
MEMORY_HEADROOM = 0.8  # a method is considered only when its estimated memory is below this share of what is available
# AMG-CG stopping rule (conjugate_gradients): the outputs (Y along a shaft, tilts, fields in µm) are printed to
# 4 significant digits and the meshes' own discretisation error is ≥ 1e-3 (bench_convergence.py); 1e-6 of the
# displacement's energy norm is far below both. The residual limit is half the sweep's equilibrium check
# (results/sweep.py, EQUILIBRIUM_LIMIT 1e-6), which every solution must pass; on the solid cantilever it is the
# limit that ends CG (61 k DOF: 39 iterations reach the accuracy, 47 the residual; benchmarks/RESULTS.md).
AMG_ACCURACY = 1e-6
AMG_RESIDUAL_LIMIT = 5e-7
AMG_ERROR_DELAY = 4  # CG steps between the iterate whose error is estimated and the one returned
SINGULAR_PIVOT_RATIO = 1e-14  # SuperLU: |pivot| / |its diagonal entry| below this: numerically singular
SINGULAR_INVERSE_NORM = 1.0 / SINGULAR_PIVOT_RATIO  # PARDISO: 1/λ_min of the Jacobi-scaled matrix above this
DIRECT_RESIDUAL_LIMIT = 1e-6  # a direct solve worse than this means a (nearly) singular matrix
REFINE_ABOVE = 1e-7  # direct solves: a column with a relative residual on the matrix above this is refined
MAX_REFINEMENT_STEPS = 3  # ... at most this many times, and only while each step at least halves it


@dataclass(frozen=True)
class SolverReport:
    """What a prepared solver did.

    Attributes
    ----------
    name : str
        Method and library, e.g. ``"pardiso (MKL PARDISO, SPD, mtype=2)"``.
    n_dofs : int
    setup_seconds : float
        Factorisation (direct; PARDISO: with its singularity test and condition estimate) or AMG hierarchy
        (iterative), wall time.
    solve_seconds : float
        Wall time of the latest :meth:`PreparedSolver.solve` call (all its right-hand sides).
    peak_memory_MB : float
        Peak resident memory of the whole process so far (``ru_maxrss``), which includes C and
        Fortran allocations (MKL, SuperLU) that tracemalloc does not see. It is a process-wide
        high-water mark: it includes whatever ran before the solver.
    peak_memory_increase_MB : float
        How much that high-water mark rose during set-up and solves (0 when an earlier peak was
        higher): a lower bound of the solver's own memory.
    relative_residuals : tuple of float
        ‖A x − b‖ / ‖b‖ per right-hand side of the latest solve.
    iterations : tuple of int
        CG iterations per right-hand side (AMG only; empty for direct methods).
    error_estimates : tuple of float
        AMG only: per right-hand side, the estimated relative energy-norm error of the displacement
        when CG stopped (:func:`conjugate_gradients`); empty for direct methods.
    matrix_nonzeros : int
        Stored nonzeros of the matrix solved (both triangles).
    factor_nonzeros : int
        Nonzeros of the factor (PARDISO's L, SuperLU's L + U); 0 for AMG.
    factor_memory_MB : float
        The library's memory for the factor and its solves (PARDISO); 0 where unknown.
    analysis_reused : bool
        PARDISO: the numerical factorisation ran on the pooled analysis of an earlier matrix of the same
        pattern (:mod:`rvcoax.fem.pardiso`), so the set-up time holds no ordering.
    """

    name: str
    n_dofs: int
    setup_seconds: float
    solve_seconds: float = 0.0
    peak_memory_MB: float = 0.0
    peak_memory_increase_MB: float = 0.0
    relative_residuals: tuple[float, ...] = ()
    iterations: tuple[int, ...] = ()
    error_estimates: tuple[float, ...] = ()
    matrix_nonzeros: int = 0
    factor_nonzeros: int = 0
    factor_memory_MB: float = 0.0
    analysis_reused: bool = False


def peak_rss_mb() -> float:
    """Peak resident memory of this process so far, MiB (``ru_maxrss``; C and Fortran allocations included).

    A process-wide high-water mark: the solvers take it before and after a set-up to report how much it rose
    (:attr:`SolverReport.peak_memory_increase_MB`).
    """
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # KiB on Linux


def pardiso_available() -> bool:
    """Whether MKL PARDISO can be loaded (x86-64 with the ``mkl`` package); checked once per process."""
    return pardiso.available()


def choose_method(  # noqa: PLR0913
    n_dofs: int,
    nonzeros: float | None = None,
    n_rhs: int = 1,
    available_bytes: float | None = None,
    *,
    superlu_max_dofs: int = SUPERLU_MAX_DOFS,
    cost_model: SolverCostModel = COST_MODEL,
    amg_cost_known: bool = True,
) -> str:
    """The ``"auto"`` choice for a system of ``n_dofs`` unknowns.

    SuperLU below ``superlu_max_dofs``. Above, among PARDISO (when MKL loads) and AMG-CG, the one the
    measured ``cost_model`` expects to take the least time for ``n_rhs`` right-hand sides, after
    dropping PARDISO when its estimated memory exceeds :data:`MEMORY_HEADROOM` of ``available_bytes``
    (read from the machine, :func:`rvcoax.fem.memory.available_memory_bytes`, when None).

    Parameters
    ----------
    n_dofs : int
    nonzeros : float, optional
        Stored nonzeros of the matrix (both triangles); estimated as
        :data:`rvcoax.fem.solver_cost.NONZEROS_PER_ROW` per row when None.
    n_rhs : int
        Right-hand sides the set-up will serve.
    available_bytes : float, optional
    amg_cost_known : bool
        False for a system unlike the one the AMG constants were measured on (plain elasticity, supports
        eliminated): a rig's system with ties, whose CG iterations the cost model does not know. AMG is then
        chosen only where PARDISO's memory does not fit.
    """
    if n_dofs < superlu_max_dofs:
        return "superlu"
    if not pardiso_available():
        return "amg"
    nnz = NONZEROS_PER_ROW * n_dofs if nonzeros is None else float(nonzeros)
    room = available_memory_bytes() if available_bytes is None else available_bytes
    if room is not None and cost_model.pardiso_bytes(n_dofs, nnz) > MEMORY_HEADROOM * room:
        return "amg"
    if not amg_cost_known:
        return "pardiso"
    return "pardiso" if cost_model.pardiso_seconds(n_dofs, n_rhs) <= cost_model.amg_seconds(nnz, n_rhs, n_dofs) else "amg"


class SolvedAhead:
    """Solutions found before they were asked for: ``solve(block)`` serves each column it has, by its exact numbers,
    and solves the others in one call of ``solve``.

    A direct solver's set-up makes one solve call of its own (:mod:`rvcoax.fem.woodbury`: the update's columns); the
    columns a caller will ask for next (the singularity test's first block, a sweep's unit loads) ride along in it,
    and each later solve call they would have cost is saved (the hybrid rig's factor: ~0.09 s a call). A column is
    recognised by the SHA-256 of its bytes: the same numbers, or it is solved as any other.
    """

    def __init__(self, solve, rhs: np.ndarray, solutions: np.ndarray):
        self._solve = solve
        self._known = {self._key(rhs[:, j]): solutions[:, j] for j in range(rhs.shape[1])}

    @staticmethod
    def _key(column: np.ndarray) -> bytes:
        return hashlib.sha256(np.ascontiguousarray(column, dtype=float)).digest()

    def __call__(self, block: np.ndarray):
        """``solve``'s (X, iterations, estimates) for ``block`` (n, k)."""
        if not self._known:
            return self._solve(block)
        found = [self._known.get(self._key(block[:, j])) for j in range(block.shape[1])]
        missing = [j for j, x in enumerate(found) if x is None]
        if len(missing) == block.shape[1]:
            return self._solve(block)
        x = np.empty(block.shape)
        for j, column in enumerate(found):
            if column is not None:
                x[:, j] = column
        iterations, estimates = (), ()
        if missing:
            solved, iterations, estimates = self._solve(block[:, missing])
            x[:, missing] = solved
        return x, iterations, estimates


class PreparedSolver:
    """A matrix set up for solving (factorised or with its AMG hierarchy). Use :func:`prepare`."""

    def __init__(self, matrix: sp.csr_matrix, name: str, solve_block, setup_seconds: float, rss_before: float,  # noqa: PLR0913
                 *, release=None, factor: tuple = (0, 0.0), matrix_nonzeros: int | None = None,
                 condition: float | None = None):
        self.matrix = matrix
        self._solve_block = solve_block
        self._rss_before = rss_before
        self._direct = not name.startswith("amg")
        self._condition = condition  # PARDISO: estimated at set-up, in the singularity test's solves
        # library memory outside Python (PARDISO's factor) is freed when this object goes away
        self._finalizer = weakref.finalize(self, release) if release is not None else None
        peak = peak_rss_mb()
        self._report = SolverReport(name=name, n_dofs=matrix.shape[0], setup_seconds=setup_seconds, solve_seconds=0.0,
                                    peak_memory_MB=peak, peak_memory_increase_MB=max(0.0, peak - rss_before),
                                    matrix_nonzeros=int(matrix.nnz if matrix_nonzeros is None else matrix_nonzeros),
                                    factor_nonzeros=int(factor[0]), factor_memory_MB=float(factor[1]),
                                    analysis_reused=bool(factor[2]) if len(factor) > 2 else False)

    def release(self) -> None:
        """Free the factorisation now (PARDISO keeps it in MKL memory until then); no solves afterwards."""
        if self._finalizer is not None:
            self._finalizer()
        self._solve_block = None

    def __enter__(self) -> PreparedSolver:
        return self

    def __exit__(self, *exc) -> None:
        self.release()

    @property
    def report(self) -> SolverReport:
        """Report of the set-up and the latest solve."""
        return self._report

    @property
    def n_dofs(self) -> int:
        return self.matrix.shape[0]

    def condition_estimate(self) -> float | None:
        """Estimated condition number of the Jacobi-scaled matrix (:func:`rvcoax.fem.diagnostics.scaled_condition_estimate`).

        SuperLU: two or three solve calls with the factorisation, made on the first call. PARDISO: made at
        set-up in the singularity test's two solve calls (:func:`rvcoax.fem.diagnostics.singularity_and_condition`),
        or on the first call when :func:`prepare` was told not to (``estimate_condition=False``). None for AMG,
        where every solve is a full CG run (a preconditioned solve that converges is its own evidence of
        conditioning).
        """
        if not self._direct:
            return None
        if self._condition is None:
            from rvcoax.fem.diagnostics import scaled_condition_estimate

            self._condition = scaled_condition_estimate(self.matrix, lambda b: self._solve_block(b)[0])
        return self._condition

    def _refine(self, block, x, residual, residuals, scale):
        """Iterative refinement against the matrix itself, column by column, only where it is needed.

        A column whose relative residual is above :data:`REFINE_ABOVE` gets a correction solve, at most
        :data:`MAX_REFINEMENT_STEPS` times and only while a step at least halves its residual. Measured
        (issue 17): an unconditional step on the tied models changed their solutions by 4e-10 for twice the
        solve time and does not lower their rounding floor of 4e-9 … 4e-8; a factor of a nearby matrix
        (PARDISO's perturbed pivots on a saddle-point matrix: a fresh 10 mm solid-rig mesh once left 2.8e-6,
        above :data:`DIRECT_RESIDUAL_LIMIT`) is what refinement repairs.
        """
        for _ in range(MAX_REFINEMENT_STEPS):
            rough = residuals > REFINE_ABOVE
            if not np.any(rough):
                break
            trial = x[:, rough] + self._solve_block(residual[:, rough])[0]
            trial_residual = block[:, rough] - self.matrix @ trial
            trial_residuals = np.linalg.norm(trial_residual, axis=0) / scale[rough]
            better = trial_residuals <= 0.5 * residuals[rough]
            if not np.any(better):
                break
            columns = np.flatnonzero(rough)[better]
            x[:, columns] = trial[:, better]
            residual[:, columns] = trial_residual[:, better]
            residuals[columns] = trial_residuals[better]
        return x, residuals

    def solve(self, rhs) -> np.ndarray:
        """Solution of A x = b for b of shape (n,) or (n, m) (all columns in one go), same shape.

        Direct methods refine a column against the matrix where its residual needs it (:meth:`_refine`).
        """
        b = np.asarray(rhs, dtype=float)
        if b.ndim not in (1, 2) or b.shape[0] != self.n_dofs:
            raise ValueError(f"right-hand side must have shape ({self.n_dofs},) or ({self.n_dofs}, m), got {b.shape}")
        block = b.reshape(self.n_dofs, -1)
        if self._solve_block is None:
            raise SolverError(f"{self._report.name}: solver was released")
        start = time.perf_counter()
        x, iterations, estimates = self._solve_block(block)
        if not np.all(np.isfinite(x)):
            raise SingularMatrixError(f"{self._report.name}: the solution contains NaN or inf (singular matrix)")
        scale = np.linalg.norm(block, axis=0)
        scale = np.where(scale > 0.0, scale, 1.0)
        residual = block - self.matrix @ x
        residuals = np.linalg.norm(residual, axis=0) / scale
        if self._direct:
            x, residuals = self._refine(block, x, residual, residuals, scale)
        elapsed = time.perf_counter() - start
        if self._direct and np.any(residuals > DIRECT_RESIDUAL_LIMIT):
            raise SingularMatrixError(
                f"{self._report.name}: relative residual {residuals.max():.1e} after a direct solve; "
                "the matrix is numerically singular (a part can move without deforming?)"
            )
        peak = peak_rss_mb()
        self._report = replace(
            self._report,
            solve_seconds=elapsed,
            peak_memory_MB=peak,
            peak_memory_increase_MB=max(0.0, peak - self._rss_before),
            relative_residuals=tuple(float(r) for r in residuals),
            iterations=tuple(iterations),
            error_estimates=tuple(float(e) for e in estimates),
        )
        return x.reshape(b.shape)


def _symmetric_csr(matrix) -> sp.csr_matrix:
    if not sp.issparse(matrix):
        raise TypeError(f"expected a scipy sparse matrix, got {type(matrix).__name__}")
    a = sp.csr_matrix(matrix, dtype=float)
    if a.shape[0] != a.shape[1]:
        raise ValueError(f"matrix must be square, got shape {a.shape}")
    a.sum_duplicates()
    a.sort_indices()
    return a


def _setup_superlu(a: sp.csr_matrix):
    try:
        lu = spla.splu(
            a.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
        )
    except RuntimeError as error:  # "Factor is exactly singular"
        raise SingularMatrixError(f"SuperLU: {error}") from error
    # each pivot against its own diagonal entry (diagonal pivoting: U_kk pairs with a_kk of the permuted
    # order), so that N/m and N·m/rad equations compare fairly; for an SPD matrix the ratio lies in (0, 1]
    pivots = np.abs(lu.U.diagonal())
    diagonal = np.abs(a.diagonal())[np.argsort(lu.perm_c)]
    relative = pivots / np.where(diagonal > 0.0, diagonal, np.inf)
    if relative.size and relative.min() <= SINGULAR_PIVOT_RATIO:
        raise SingularMatrixError(
            f"SuperLU: pivot {relative.min():.1e} times its diagonal entry at equation {int(np.argmin(relative))}: "
            "the matrix is numerically singular"
        )

    def solve(block):
        return lu.solve(block), (), ()

    return "superlu (scipy SuperLU, symmetric mode)", solve, None, (lu.L.nnz + lu.U.nnz, 0.0)


def _setup_pardiso(a: sp.csr_matrix, estimate_condition: bool = True):
    if not pardiso.available():
        raise SolverError("method 'pardiso' needs Intel MKL (x86-64 only): pip install mkl")
    diagonal = a.diagonal()
    if np.any(diagonal <= 0.0):  # an SPD matrix has a positive diagonal; PARDISO may crash on an empty row
        equation = int(np.flatnonzero(diagonal <= 0.0)[0])
        raise SingularMatrixError(f"PARDISO: diagonal entry {diagonal[equation]:.1e} at equation {equation}: "
                                  "the matrix is singular or not positive definite")
    storage = pardiso.upper_storage(a)
    try:
        factor = pardiso.Factorization(storage)
    except pardiso.PardisoError as error:
        raise _pardiso_singular(error) from error

    def solve(block):
        try:
            return factor.solve(block), (), ()
        except pardiso.PardisoError as error:
            raise SolverError(str(error)) from error

    # A singular matrix may also factorise, its rigid-body pivots rounded to tiny positive values
    # (it does so at random: the threaded factorisation does not round the same way every time);
    # two solves of inverse iteration tell it apart from any usable matrix, every time.
    condition = refuse_singular(a, solve, factor, estimate_condition=estimate_condition)

    blocks = " 3×3 blocks," if storage.block_size == 3 else ""
    return (f"pardiso (MKL PARDISO, SPD,{blocks} mtype=2)", solve, factor.release,
            (factor.factor_nonzeros, factor.memory_MB, factor.reused_analysis), condition)


def refuse_singular(matrix, solve, factor: pardiso.Factorization, *, estimate_condition: bool = True) -> float | None:
    """The singularity test of a PARDISO set-up, with the condition estimate in the same solves.

    Inverse iteration (two solves, :func:`rvcoax.fem.diagnostics.scaled_inverse_norm_bound`) bounds 1/λ_min of
    the Jacobi-scaled ``matrix``; above :data:`SINGULAR_INVERSE_NORM` the matrix is singular whatever the factor
    says (a singular matrix may factorise, its rigid-body pivots rounded to tiny positive values).

    Parameters
    ----------
    matrix : sparse (n, n), or an operator with ``shape``, ``diagonal()``, ``@`` and ``scaled_one_norm(root)``
        The SPD matrix ``solve`` solves with.
    solve : callable
        ``solve(block)`` → (X, iterations, estimates), X = matrix⁻¹ block for a block (n, k), as a set-up's
        solve function returns.
    factor : rvcoax.fem.pardiso.Factorization
        Released (analysis included) when the matrix is refused or a solve fails.
    estimate_condition : bool
        Also make the condition estimate, its solves carrying the iteration's two steps as one more column
        (:func:`rvcoax.fem.diagnostics.singularity_and_condition`: the same two solve calls where the estimate's
        search ends there, one more where a larger column is certain). False: the iteration's two single-column solves alone.

    Returns
    -------
    float or None
        The condition estimate of the Jacobi-scaled matrix, or None without ``estimate_condition``.

    Raises
    ------
    SingularMatrixError
        The bound is above :data:`SINGULAR_INVERSE_NORM` (the message names the equation that moves most).
    SolverError
        A solve failed.
    """
    try:
        if estimate_condition:
            bound, equation, condition = singularity_and_condition(matrix, lambda b: solve(b)[0])
        else:
            (bound, equation), condition = scaled_inverse_norm_bound(matrix, lambda b: solve(b[:, None])[0]), None
    except SolverError:
        factor.release(keep_analysis=False)
        raise
    if bound > SINGULAR_INVERSE_NORM:
        factor.release(keep_analysis=False)
        raise SingularMatrixError(
            f"PARDISO: the Jacobi-scaled matrix has 1/λ_min ≥ {bound:.1e} (largest motion at equation "
            f"{equation}): the matrix is numerically singular"
        )
    return condition


def _pardiso_singular(error: pardiso.PardisoError) -> SolverError:
    if error.phase == "factorisation" and error.code not in pardiso.RESOURCE_ERRORS:
        where = f" at equation {error.equation}" if error.code == pardiso.ZERO_PIVOT else ""
        return SingularMatrixError(f"PARDISO: numerical factorisation failed{where} (error {error.code}): "
                                   "the matrix is singular or not positive definite")
    return SolverError(str(error))


class _RefusedOnReusedAnalysis(Exception):
    """A saddle-point matrix refused on an analysis (matching, scaling) computed from another matrix's values."""


def _factorise_saddle_point(operator, upper: pardiso.UpperStorage, d: int, *, reuse_analysis: bool):
    """PARDISO's factor of the saddle-point matrix, its solve of A and the condition estimate, after the inertia
    and the singularity test; a refusal on a reused analysis raises :class:`_RefusedOnReusedAnalysis` instead."""
    m = operator.shape[0]
    total = upper.n
    try:
        factor = pardiso.Factorization(upper, indefinite=True, reuse_analysis=reuse_analysis)
    except pardiso.PardisoError as error:
        raise _pardiso_singular(error) from error

    # MKL refines each solve on the saddle-point matrix (iparm[7]); PreparedSolver.solve refines against
    # A itself where a column's residual needs it (REFINE_ABOVE).
    def solve(block):
        padded = np.zeros((total, block.shape[1]), order="F")  # PARDISO's column order: no second copy for it
        padded[:m] = block
        try:
            return factor.solve(padded)[:m], (), ()
        except pardiso.PardisoError as error:
            raise SolverError(str(error)) from error

    try:
        positive, negative = factor.inertia
        if negative != d or positive != m + d:  # Sylvester: inertia = that of A plus (d, d), C having full rank
            factor.release(keep_analysis=False)
            raise SingularMatrixError(f"PARDISO: the constrained stiffness has {m + d - positive} non-positive "
                                      f"eigenvalue(s) of {m}: the matrix is singular or not positive definite")
        condition = refuse_singular(operator, solve, factor)
    except SingularMatrixError as error:
        if factor.reused_analysis:
            raise _RefusedOnReusedAnalysis() from error
        raise
    return factor, solve, condition


def prepare_saddle_point(operator, augmented: sp.csr_matrix | pardiso.UpperStorage) -> PreparedSolver:
    """Set up A q = b for an SPD A that is known only as an operator, through its saddle-point form.

    A = Sᵀ K' S, S = [I; Q] ((m + d) × m), is the stiffness with d dependent unknowns p = Q q (tie
    reference nodes, rows of Q as long as a face) eliminated: formed, it is dense where Q is. The
    saddle-point matrix [[K', Cᵀ], [C, 0]] with C = D [−Q, I] (D a positive row scaling) keeps p as an
    unknown and the relation as d Lagrange multipliers λ; it is as sparse as K' and C. Its solution
    for the right-hand side [b; 0; 0] has q = A⁻¹ b (the constraint gives y = S q, and Sᵀ K' S q = b).
    Factorised by MKL PARDISO in symmetric indefinite mode (``mtype = -2``, weighted matching and
    scaling, MKL's iterative refinement on the saddle-point matrix).

    Parameters
    ----------
    operator : rvcoax.fem.system.ConstrainedStiffness
        A: ``shape`` (m, m), ``diagonal()``, ``@``, ``scaled_one_norm(root)``.
    augmented : csr_matrix (m + 2d, m + 2d), or its upper triangle (:class:`rvcoax.fem.pardiso.UpperStorage`)
        The saddle-point matrix, symmetric, the m rows of q first. Pass the upper triangle
        (:meth:`rvcoax.fem.system.ConstrainedStiffness.saddle_point_upper`) where memory counts: PARDISO
        reads only that, and the whole matrix given here is alive until the call returns.

    Raises
    ------
    SingularMatrixError
        A is singular: a failed factorisation, an inertia other than (m + d, d), or the inverse
        iteration of :func:`rvcoax.fem.diagnostics.scaled_inverse_norm_bound` above 1e14.
    SolverError
        MKL missing, or a library error.
    """
    rss_before = peak_rss_mb()
    if not pardiso.available():
        raise SolverError("method 'pardiso' needs Intel MKL (x86-64 only): pip install mkl")
    start = time.perf_counter()
    m = operator.shape[0]
    upper = augmented if isinstance(augmented, pardiso.UpperStorage) else pardiso.upper_csr(_symmetric_csr(augmented))
    del augmented  # the caller's whole matrix, if any, is the caller's; only the upper triangle is kept here
    total = upper.n
    d = (total - m) // 2
    diagonal = operator.diagonal()
    if np.any(diagonal <= 0.0):
        equation = int(np.flatnonzero(diagonal <= 0.0)[0])
        raise SingularMatrixError(f"PARDISO: diagonal entry {diagonal[equation]:.1e} at equation {equation}: "
                                  "the matrix is singular or not positive definite")
    del diagonal
    try:
        factor, solve, condition = _factorise_saddle_point(operator, upper, d, reuse_analysis=True)
    except _RefusedOnReusedAnalysis:  # the pooled matching and scaling were another matrix's: judge on its own
        factor, solve, condition = _factorise_saddle_point(operator, upper, d, reuse_analysis=False)
    name = f"pardiso (MKL PARDISO, ties as {d} multipliers, symmetric indefinite, mtype=-2)"
    return PreparedSolver(operator, name, solve, setup_seconds=time.perf_counter() - start, rss_before=rss_before,
                          release=factor.release, factor=(factor.factor_nonzeros, factor.memory_MB,
                                                          factor.reused_analysis),
                          matrix_nonzeros=pardiso.stored_nonzeros(upper), condition=condition)


def conjugate_gradients(matrix, b: np.ndarray, precondition, accuracy: float = AMG_ACCURACY,  # noqa: PLR0913
                        residual_limit: float = AMG_RESIDUAL_LIMIT, *, maxiter: int | None = None,
                        delay: int = AMG_ERROR_DELAY) -> tuple[np.ndarray, int, float]:
    """Preconditioned CG from x₀ = 0 that stops on an estimate of the displacement's error.

    Stopping rule: after step k, the Hestenes–Stiefel sum ν = Σ_{j=k−d+1..k} α_j (r_jᵀ z_j) over the
    last d = ``delay`` steps is the drop of ‖x − x_j‖²_A from x_{k−d+1} to x_{k+1}, a lower bound of
    ‖x − x_{k−d+1}‖²_A (Strakoš & Tichý 2002, "On error estimation in the conjugate gradient
    method and why it works in finite precision computations"), and bᵀx_{k+1} = ‖x_{k+1}‖²_A. CG
    stops when sqrt(ν / bᵀx_{k+1}) ≤ ``accuracy`` and ‖r_{k+1}‖ ≤ ``residual_limit`` ‖b‖ and returns
    x_{k+1}: d steps past the iterate whose error was estimated, so that with the contraction of an
    AMG-preconditioned CG step (≤ 0.6 measured) the returned error is well below the estimate.
    A relative energy-norm error ε bounds the error of a displacement output ℓᵀx by
    ε ‖ℓ‖_{A⁻¹} ‖x‖_A; for displacements where the load acts that factor is about 1. The bound is
    relative to the whole field: an output far smaller than the field's scale (the lateral motion
    under a nearly pure torque) is accurate to ε of that scale, not to ε of itself.

    Parameters
    ----------
    matrix : sparse (n, n), SPD
    b : (n,) array
    precondition : callable
        z = M⁻¹ r (one AMG V-cycle).
    accuracy, residual_limit : float
    maxiter : int, optional
        10 n when None (scipy's default).
    delay : int

    Returns
    -------
    x : (n,) array
    iterations : int
    estimate : float
        sqrt(ν / bᵀx) when CG stopped.

    Raises
    ------
    SolverError
        Not converged in ``maxiter`` steps, or a non-positive curvature (matrix or preconditioner not SPD).
    """
    maxiter = 10 * b.shape[0] if maxiter is None else maxiter
    x = np.zeros_like(b)
    r = b.copy()
    z = precondition(r)
    p = z.copy()
    rz = float(r @ z)
    b_norm = float(np.linalg.norm(b))
    terms: list[float] = []
    estimate = np.inf
    for k in range(maxiter):
        q = matrix @ p
        curvature = float(p @ q)
        if not curvature > 0.0 or not rz > 0.0:
            raise SolverError(f"AMG-preconditioned CG broke down at iteration {k + 1} (pᵀAp = {curvature:.1e}, "
                              f"rᵀM⁻¹r = {rz:.1e}): the matrix or its preconditioner is not positive definite")
        alpha = rz / curvature
        x += alpha * p
        r -= alpha * q
        terms.append(alpha * rz)
        if len(terms) >= delay:
            energy = float(b @ x)
            estimate = float(np.sqrt(sum(terms[-delay:]) / energy)) if energy > 0.0 else np.inf
            if estimate <= accuracy and np.linalg.norm(r) <= residual_limit * b_norm:
                return x, k + 1, estimate
        z = precondition(r)
        rz_next = float(r @ z)
        p *= rz_next / rz
        p += z
        rz = rz_next
    raise SolverError(f"AMG-preconditioned CG did not reach the estimated relative error {accuracy:.0e} in "
                      f"{maxiter} iterations (estimate {estimate:.1e})")


def _setup_amg(a: sp.csr_matrix, near_null_space, accuracy: float, maxiter: int | None):
    from rvcoax.fem import amg, mkl_sparse

    hierarchy = amg.smoothed_aggregation(a, near_null_space)

    def solve(block):  # one hierarchy, every right-hand side
        x = np.zeros_like(block)
        iterations, estimates = [], []
        for j in range(block.shape[1]):
            if not np.any(block[:, j]):
                iterations.append(0)
                estimates.append(0.0)
                continue
            x[:, j], count, estimate = conjugate_gradients(hierarchy.matrix, np.ascontiguousarray(block[:, j]),
                                                           hierarchy.precondition, accuracy, maxiter=maxiter)
            iterations.append(count)
            estimates.append(estimate)
        return x, iterations, estimates

    n_modes = 1 if near_null_space is None else np.asarray(near_null_space).reshape(a.shape[0], -1).shape[1]
    products = "MKL threaded products" if mkl_sparse.available() else "scipy products"
    return (f"amg (pyamg smoothed aggregation, {n_modes} near-null-space vectors; Chebyshev V-cycle in "
            f"{np.dtype(amg.PRECISION).name}, {products}; CG to a relative energy error of {accuracy:.0e})",
            solve, hierarchy.release, (0, 0.0))


def prepare(  # noqa: PLR0913
    matrix,
    method: str = "auto",
    near_null_space=None,
    *,
    n_rhs: int = 1,
    superlu_max_dofs: int = SUPERLU_MAX_DOFS,
    available_bytes: float | None = None,
    accuracy: float = AMG_ACCURACY,
    maxiter: int | None = None,
    estimate_condition: bool = True,
) -> PreparedSolver:
    """Set up a symmetric positive definite matrix for solving.

    Parameters
    ----------
    matrix : scipy sparse (n, n)
        Symmetric positive definite (constraints already eliminated).
    method : {"auto", "superlu", "pardiso", "amg"}
    near_null_space : (n, k) array, optional
        AMG only: the rigid-body modes of the unconstrained structure (:func:`rvcoax.fem.rigid_body.rigid_body_modes`)
        restricted to the free DOFs. Without them AMG converges slowly on elasticity.
    n_rhs : int
        ``"auto"``: how many right-hand sides the set-up will serve (:func:`choose_method`).
    superlu_max_dofs : int
        ``"auto"``: SuperLU below this size.
    available_bytes : float, optional
        ``"auto"``: memory to plan with; the machine's available memory when None.
    accuracy, maxiter : AMG-preconditioned CG stopping rule (:func:`conjugate_gradients`).
    estimate_condition : bool
        PARDISO: make the condition estimate at set-up, as more columns of the singularity test's two solve
        calls (:func:`rvcoax.fem.diagnostics.singularity_and_condition`; a third call where a larger column is
        certain). False: the singularity test alone (two single-column solves, the same refusal
        of a singular matrix); :meth:`PreparedSolver.condition_estimate` then makes the estimate when it is
        asked for (two or three solve calls of its own). At 62 k DOF the estimate adds about 0.1 s of CPU time
        to a 2 s set-up and solve (benchmarks/RESULTS.md); SuperLU always estimates on request, AMG never.

    Raises
    ------
    SingularMatrixError
        A direct factorisation found the matrix singular.
    SolverError
        Unknown method, MKL missing for ``"pardiso"``, or a solver library error.
    """
    rss_before = peak_rss_mb()
    a = _symmetric_csr(matrix)
    if not 0.0 < accuracy < 1.0:
        raise SolverError(f"AMG accuracy must lie in (0, 1), got {accuracy!r}")
    chosen = (choose_method(a.shape[0], a.nnz, n_rhs, available_bytes, superlu_max_dofs=superlu_max_dofs)
              if method == "auto" else method)
    start = time.perf_counter()
    condition = None  # SuperLU: estimated on request (PreparedSolver.condition_estimate); AMG: none
    if chosen == "superlu":
        name, solve, release, factor = _setup_superlu(a)
    elif chosen == "pardiso":
        name, solve, release, factor, condition = _setup_pardiso(a, estimate_condition)
    elif chosen == "amg":
        name, solve, release, factor = _setup_amg(a, near_null_space, accuracy, maxiter)
    else:
        raise SolverError(f"unknown solver method '{method}': choose one of auto, {', '.join(METHODS)}")
    return PreparedSolver(a, name, solve, setup_seconds=time.perf_counter() - start, rss_before=rss_before,
                          release=release, factor=factor, condition=condition)
