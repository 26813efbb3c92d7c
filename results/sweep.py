"""A torque sweep on a rig: a pure function of (rig, load cases, settings).

The model is linear, so each case is a superposition of unit responses solved with one
factorisation (or one preconditioner set-up): u = u_rest + sign(T1) u_engaged_T1 +
sign(T2) u_engaged_T2 + T1 u_T1 + T2 u_T2 (:mod:`rvcoax.geometry.model.loads`). ``method="direct"`` assembles
each case's own load vector and solves it instead (same factorisation), as a check that both agree.

Y is read from the aligned rig at rest (``paths.measured_from = "aligned_at_rest"``: u − u_rest)
or from the unloaded geometry (``"unloaded"``: u). Both are kept per case.

A rig with a bearing clearance (``radial_clearance_um > 0``, beam model) or a ball bearing from
geometry (``model = "ball"``, beam and hybrid models) is not linear: the rest state and every case
are then solved on their own by Newton's method on the condensed bearing motions
(:func:`rvcoax.fem.bushing.solve_condensed`), on the same factorisation.
"""

from __future__ import annotations

import dataclasses
import hashlib
from dataclasses import dataclass, field

import numpy as np

from rvcoax.errors import RvcoaxError
from rvcoax.fem import bushing, equilibrium
from rvcoax.fem import system as fem_system
from rvcoax.fem.errors import SingularModelError
from rvcoax.fem.rigid_body import rigid_body_modes
from rvcoax.fem.system import factorize
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model import preflight
from rvcoax.geometry.model.assemble import MODEL_KINDS, assemble_rig
from rvcoax.geometry.model.beam import RigModel
from rvcoax.geometry.model.loads import REST_LOADS, UNIT_LOADS, case_weights, gear_contact_torques, superpose
from rvcoax.geometry.model.nonlinear_bearings import (
    NonlinearBearings,
    nonlinear_bearing_names,
    prepare_nonlinear_bearings,
)
from rvcoax.geometry.model.springs import SpringMotion
from rvcoax.geometry.model.system import RigSystem, assemble_beam
from rvcoax.geometry.rolling_model import GEOMETRIC_MODELS
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.engineering import CaseEngineering, case_engineering, reducer_checks, rolling_bearing_lives
from rvcoax.results.paths import ShaftPathResult
from rvcoax.results.shaft_safety import ShaftStrength, shaft_strength
from rvcoax.results.torque_path import TorquePaths, torque_paths

__all__ = ["CONDITION_LIMIT", "CaseResult", "EQUILIBRIUM_LIMIT", "GAP_BACKWARD_LIMIT", "LinearStates", "MEASURED_SHAFTS",
           "ModelError", "NonlinearStates", "PreparedModel", "Sweep", "SweepSettings", "check_clearance_model", "check_condition", "check_solution",
           "assemble_model", "check_supports", "prepare_model", "prepare_system", "read_path", "run_gap_sweep",
           "run_sweep", "solve_unit_responses"]



@dataclass(frozen=True)
class SweepSettings:
    """How to solve.

    Parameters
    ----------
    method : str
        ``superposition`` of unit responses (default) or ``direct`` per case.
    model : str
        ``beam``, ``hybrid`` or ``solid``.
    solver : str
        ``auto`` (by size), ``superlu``, ``pardiso`` or ``amg`` (solid and hybrid models).
    mesh_size_mm : float or None
        Global solid mesh size; None keeps the rig file's.
    """

    method: str = "superposition"
    model: str = "beam"
    solver: str = "auto"
    mesh_size_mm: float | None = None

    def __post_init__(self) -> None:
        if self.method not in ("superposition", "direct"):
            raise ValueError(f"method must be 'superposition' or 'direct', got {self.method!r}")
        if self.model not in MODEL_KINDS:
            raise ValueError(f"model must be one of {', '.join(MODEL_KINDS)}, got {self.model!r}")
        if self.solver not in ("auto", "superlu", "pardiso", "amg"):
            raise ValueError(f"solver must be auto, superlu, pardiso or amg, got {self.solver!r}")
        if self.mesh_size_mm is not None and not self.mesh_size_mm > 0:
            raise ValueError(f"mesh size must be > 0 mm, got {self.mesh_size_mm}")


@dataclass(frozen=True, kw_only=True)
class CaseResult:
    """Results of one load case."""

    case: LoadCase
    paths: dict[str, ShaftPathResult]
    absolute_paths: dict[str, ShaftPathResult]
    equilibrium_error: float
    residual: float
    engineering: CaseEngineering | None = None  # couplings, bearings, reactions (results/engineering.py)
    ball_lives: tuple = ()  # nonlinear sweeps: the lives of the bearings from geometry from their element loads
    reducer_checks: tuple = ()  # nonlinear sweeps: each reducer against its rating table (ReducerCheck)
    shaft_strength: ShaftStrength | None = None  # shaft stresses and DIN 743 notch safety (results/shaft_safety.py)
    torque_paths: TorquePaths | None = None  # where each applied torque leaves its shaft line (results/torque_path.py)
    operating_points: dict = field(default_factory=dict)  # nonlinear sweeps: bearing from geometry → its listed point


@dataclass(frozen=True, eq=False)
class LinearStates:
    """The states of a linear sweep: its unit-load responses; a case's displacement superposes them.

    Attributes
    ----------
    unit_displacements : (n_dofs, len(UNIT_LOADS)) array
        One column per unit load of :data:`rvcoax.geometry.model.loads.UNIT_LOADS`, in that order (m, rad).
    """

    unit_displacements: np.ndarray


@dataclass(frozen=True, eq=False)
class NonlinearStates:
    """The states of a sweep with nonlinear bearings: each case solved on its own.

    Attributes
    ----------
    case_displacements : (n_dofs, n_cases) array
        Each case's displacement as Y is measured (from the rest state when the rig is aligned at rest).
    rest_displacement : (n_dofs,) array
        The rest state from the unloaded geometry.
    bearings : NonlinearBearings
        Their condensed laws (operating forces and stiffness).
    """

    case_displacements: np.ndarray
    rest_displacement: np.ndarray
    bearings: NonlinearBearings


@dataclass(frozen=True, eq=False, kw_only=True)
class Sweep:
    """All cases of a sweep, plus what is needed to explain how they were obtained.

    ``states`` holds the displacements every case comes from: :class:`LinearStates` (unit responses) or
    :class:`NonlinearStates` (each case's own); None for a sweep rebuilt without them.
    """

    rig: Rig
    frame: RigModel
    settings: SweepSettings
    cases: tuple[CaseResult, ...]
    unit_paths: dict[str, dict[str, ShaftPathResult]] = field(default_factory=dict)
    solver: str = ""
    n_dofs: int = 0
    system: RigSystem | None = None
    states: LinearStates | NonlinearStates | None = None
    solver_report: dict = field(default_factory=dict)

    @property
    def unit_displacements(self) -> np.ndarray | None:
        """The unit-load responses (n_dofs, len(UNIT_LOADS)) of a linear sweep; None otherwise."""
        return self.states.unit_displacements if isinstance(self.states, LinearStates) else None

    @property
    def case_displacements(self) -> np.ndarray | None:
        """(n_dofs, n_cases), as measured, of a nonlinear sweep; None otherwise."""
        return self.states.case_displacements if isinstance(self.states, NonlinearStates) else None

    @property
    def rest_displacement(self) -> np.ndarray | None:
        """(n_dofs,), the rest state from the unloaded geometry, of a nonlinear sweep; None otherwise."""
        return self.states.rest_displacement if isinstance(self.states, NonlinearStates) else None

    @property
    def nonlinear_bearings(self) -> NonlinearBearings | None:
        """The condensed laws of a nonlinear sweep's bearings; None otherwise."""
        return self.states.bearings if isinstance(self.states, NonlinearStates) else None

    def measured_displacement(self, index: int) -> np.ndarray:
        """The displacement of case ``index`` measured as Y is (u − u_rest when aligned at rest, else u)."""
        if isinstance(self.states, NonlinearStates):
            return self.states.case_displacements[:, index]
        unit = {k: self.states.unit_displacements[:, i] for i, k in enumerate(UNIT_LOADS)}
        case = self.cases[index].case
        return superpose(unit, case.input_torque_Nm, case.output_torque_Nm,
                         self.rig.paths.measured_from == "aligned_at_rest", gear_contact_torques(self.rig))


    def total_displacement(self, index: int | None) -> np.ndarray:
        """The full displacement u of case ``index`` (None: the rest state) of a nonlinear sweep, from the
        unloaded geometry (not measured from rest)."""
        if self.case_displacements is None or self.rest_displacement is None:
            raise ValueError("total_displacement needs a nonlinear sweep (bearings from geometry or clearance)")
        if index is None:
            return self.rest_displacement
        measured = self.case_displacements[:, index]
        return measured + self.rest_displacement if self.rig.paths.measured_from == "aligned_at_rest" else measured

    def rolling_element_loads(self, index: int | None) -> dict:
        """Per bearing from internal geometry, every rolling element's contact load, contact angle and largest
        contact pressure in case ``index`` (None: at rest): :func:`rvcoax.fem.rolling_bearing.rolling_element_loads`
        at the converged state — what a life (ISO/TS 16281) or static-safety (ISO 76) calculation reads."""
        from rvcoax.fem.rolling_bearing import rolling_element_loads

        if self.nonlinear_bearings is None:
            return {}
        motions = self.nonlinear_bearings.motions(self.nonlinear_bearings.operator @ self.total_displacement(index))
        return {m.name: rolling_element_loads(m.bearing, motions[m.name]) for m in self.nonlinear_bearings.rolling}


class ModelError(RvcoaxError, RuntimeError):
    """A model that cannot be solved, with the reason in the user's terms."""

    stage = "cannot solve the rig"


def read_path(system: RigSystem, displacement: np.ndarray, which: str) -> ShaftPathResult:
    """The measured shaft path ``which`` of a displacement vector."""
    probe = system.probes[which]
    return ShaftPathResult(probe.stations_mm, (probe.uy @ displacement) * 1e3, probe.length_mm,
                           probe.rotation_z @ displacement)


def check_supports(rig: Rig) -> None:
    """Raise :class:`ModelError` naming every part that can move without deforming anything
    (:func:`rvcoax.geometry.model.preflight.support_problem`: on the rig's beam model, cheap at any fidelity)."""
    problem = preflight.support_problem(rig)
    if problem:
        raise ModelError(problem)


CONDITION_LIMIT = preflight.CONDITION_LIMIT
# a clearance solution's backward error: ~1e-16 measured; 1e-12 (≈ 4500 ε) leaves room for summation order
# and the Newton stop (1e-13 of the condensed terms) and still catches an unconverged law (force errors ~k R)
GAP_BACKWARD_LIMIT = 1e-12
EQUILIBRIUM_LIMIT = 1e-6  # relative error of the ground reactions' resultant, and of the reduced residual


def check_condition(kappa: float | None, rig: Rig | None = None) -> None:
    """Raise :class:`ModelError` when the estimated condition number says the solution has no digits left
    (naming ``rig``'s very short segments when it has them: :func:`rvcoax.geometry.model.preflight.short_segment_note`)."""
    if kappa is not None and not kappa <= CONDITION_LIMIT:
        raise ModelError(f"the stiffness matrix is ill-conditioned: estimated condition number {kappa:.2g} "
                         f"(Jacobi-scaled, 1-norm; limit {CONDITION_LIMIT:.0e}), so a solve would keep fewer than 5 "
                         "correct digits. Stiffness values many orders of magnitude apart (a unit mistake in a "
                         "stiffness key?), very short beam segments or an almost free part cause this."
                         + (preflight.short_segment_note(rig) if rig is not None else ""))


def check_solution(label: str, u: np.ndarray, equilibrium_error: float, residual: float) -> None:
    """Raise :class:`ModelError` when a solution holds NaN/inf or does not satisfy equilibrium."""
    if not np.all(np.isfinite(u)):
        raise ModelError(f"case {label}: the solution contains NaN or inf")
    for name, value in (("equilibrium error (ground reactions vs applied loads)", equilibrium_error),
                        ("relative residual", residual)):
        if not value <= EQUILIBRIUM_LIMIT:
            raise ModelError(f"case {label}: {name} {value:.2g} exceeds {EQUILIBRIUM_LIMIT:g}: the solution is not "
                             "trustworthy (ill-conditioned stiffness?)")


def _prepare(system: RigSystem, settings: SweepSettings, ahead=None):
    """The system's solver: returns (solve function, solver name, summary dict, the solve of Tᵀ K T itself).

    A beam model with the automatic or SuperLU solver is factorised by SuperLU in symmetric mode (the
    reduced matrix symmetrised); everything else goes to the method ``settings.solver`` names or, for
    ``auto``, the one its size calls for, AMG with the rigid-body modes as near-null space. ``ahead``: a callable
    returning the load vectors to solve in the set-up's own solve call where it makes one
    (:func:`rvcoax.fem.system.prepare_system`).
    """
    beam_superlu = system.kind == "beam" and settings.solver in ("auto", "superlu")
    try:
        reduced = fem_system.prepare_system(
            system.stiffness, system.elimination, "superlu" if beam_superlu else settings.solver,
            near_null_space=lambda: rigid_body_modes(system.dofs.position, system.dofs.component),
            symmetrize=beam_superlu, n_rhs=len(UNIT_LOADS), ahead=ahead)
    except SingularModelError as error:
        raise ModelError(f"the model is singular ({error}); check that every part is supported") from None
    check_condition(reduced.condition_estimate(), system.frame.rig)
    return reduced.solve, reduced.solver_name, reduced.summary(), reduced.solver.solve, reduced.solver.release


def _first_of_each(keys: list[bytes | None], among) -> dict[bytes, int]:
    """Of the vectors ``among`` (indices), the first of each distinct one that is not zeros, by key
    (:func:`_vector_keys`): a vector repeated (the loads a calibration's trial rigs share) is solved once."""
    first: dict[bytes, int] = {}
    for j in among:
        if keys[j] is not None:
            first.setdefault(keys[j], j)
    return first


def _distinct_loaded(vectors) -> list[int]:
    """Indices of the distinct load vectors of ``vectors`` that are not all zeros, each the first of its kind: the
    columns a solve of them all needs (:meth:`PreparedModel.solve_unit_loads`)."""
    keys = _vector_keys(vectors)[1]
    return list(_first_of_each(keys, range(len(keys))).values())


CACHED_SOLUTIONS = 64  # unit-load solutions kept per prepared model, and at most 2**25 numbers (256 MB)
CACHED_SOLUTION_FLOATS = 2**25


@dataclass(frozen=True, eq=False)
class PreparedModel:
    """An assembled system with its solver set up (one factorisation), reusable across sweeps.

    The solutions of the unit loads are kept (the last :data:`CACHED_SOLUTIONS`, within
    :data:`CACHED_SOLUTION_FLOATS` numbers) by the bytes of each load vector, so that a sweep whose rig differs only in some
    load parameters (a calibration's trial, a tolerance sample) solves only the vectors that changed. The products
    K u of those solutions are kept the same way, by the bytes of each solution u (:meth:`stiffness_products`): a
    superposition sweep checks every case's K u − f as the same superposition of the unit solutions' K u_k − f_k.
    """

    system: RigSystem
    solve: object
    solver_name: str
    report: dict  # rvcoax.fem.system.ReducedSystem.summary(): method, size, times, memory, condition estimate
    solved: dict = field(default_factory=dict, repr=False)
    reduced_solve: object = field(default=None, repr=False)  # x → (Tᵀ K T)⁻¹ x on the independent DOFs (modes)
    release_solver: object = field(default=None, repr=False)  # frees the factorisation (PARDISO's factor) now
    products: dict = field(default_factory=dict, repr=False)  # SHA-256 of a solution u's bytes → K u

    def release(self) -> None:
        """Free the solver's factorisation now, for a caller that solves nothing more on this model: the unit-load
        solutions already found stay cached (:meth:`solve_unit_loads` still serves them); any other solve raises
        :class:`rvcoax.fem.errors.SolverError`."""
        if self.release_solver is not None:
            self.release_solver()

    def solve_unit_loads(self, columns) -> np.ndarray:
        """Solutions of the load vectors ``columns`` (an (n, m) array, or m vectors of length n), as an (n, m) array:
        those solved before are taken from the cache, the others are solved together in one call (the first sweep of a
        model solves them all at once), each distinct vector once."""
        vectors, keys = _vector_keys(columns)
        n, m = len(vectors[0]), len(vectors)
        # a load vector of zeros (a rig without a force table, thermal load or gear contact) has the solution 0 exactly:
        # neither solved nor kept (the reference rig: 6 of its 9 unit loads; the all-solid rig's solve call then needs a
        # third of MKL's workspace, benchmarks/RESULTS.md)
        missing = [j for j, key in enumerate(keys) if key is not None and key not in self.solved]
        first = _first_of_each(keys, missing)
        unique = list(first.values())
        # only the distinct loaded vectors are copied for the solver, and the (n, m) result is made once the solver has
        # given its workspace back: the all-solid rig's 9-column copy and zero-filled result (2 × 35 MB at 492 k DOF)
        # are no longer held through MKL's solve, the process's peak
        solved = np.asarray(self.solve(np.column_stack([vectors[j] for j in unique]))).reshape(n, -1) if unique else None
        if len(unique) == m:
            solutions = solved
        else:
            solutions = np.zeros((n, m), order="F")  # each solution contiguous: the sweeps superpose them
            for i, j in enumerate(unique):
                solutions[:, j] = solved[:, i]
        del solved
        new = set(missing)
        for j, key in enumerate(keys):
            if key is None:
                continue
            if j not in new:
                solutions[:, j] = self.solved[key]
            elif first[key] != j:
                solutions[:, j] = solutions[:, first[key]]
        _keep(self.solved, {keys[j]: solutions[:, j] for j in missing}, n, m)
        return solutions

    def remember(self, vectors, solutions) -> None:
        """Keep ``solutions`` (one per load vector of ``vectors``, full DOF numbering) as if :meth:`solve_unit_loads` had
        solved them: a caller that found them otherwise, exactly (a calibration's affine combination of solved unit
        loads, :func:`rvcoax.results.studies.calibration.calibrate`). The sweeps that use them check every case's
        residual against the stiffness as always (a vector of zeros is not kept: its solution is 0)."""
        keys = _vector_keys(vectors)[1]
        kept = {key: solution for key, solution in zip(keys, solutions) if key is not None}
        _keep(self.solved, kept, self.system.n_dofs, len(kept))

    def stiffness_products(self, solutions) -> np.ndarray:
        """K u of each vector u of ``solutions`` (an (n, m) array's columns, or m vectors of length n), as an (n, m)
        array: those formed before are taken from the cache (by the bytes of u, so a product always belongs to the very
        vector it is asked for), the others are formed here, each distinct vector once; a vector of zeros has the
        product 0.

        A superposition sweep's case is u = Σ w_k u_k, so its K u − f is Σ w_k (K u_k − f_k): the unit solutions'
        products, formed once per model, replace one product with K per case (the hybrid reference rig's K, 8.3 M
        nonzeros: 4 ms CPU each)."""
        vectors, keys = _vector_keys(solutions)
        n, m = len(vectors[0]), len(vectors)
        first = _first_of_each(keys, [j for j, key in enumerate(keys) if key not in self.products])
        unique = list(first.values())
        stiffness = self.system.stiffness
        formed = (stiffness @ np.column_stack([vectors[j] for j in unique]) if len(unique) >= BLOCK_PRODUCT_FROM else
                  [stiffness @ vectors[j] for j in unique])
        new = {keys[j]: formed[:, i].copy() if isinstance(formed, np.ndarray) else formed[i]  # each its own array
               for i, j in enumerate(unique)}
        products = np.zeros((n, m), order="F")
        for j, key in enumerate(keys):
            if key is not None:
                products[:, j] = new[key] if key in new else self.products[key]
        _keep(self.products, new, n, m, copy=False)
        return products


BLOCK_PRODUCT_FROM = 8
"""Fewest vectors whose K u is formed as one block product: scipy's product with a block costs more per nonzero of K
than with one vector (the hybrid rig's K, 8.3 M nonzeros: 21 ms for 2 columns, 47 ms for 20, 5 ms for one vector);
per column the same sums in the same order as K u alone."""


def _vector_keys(columns) -> tuple[list | np.ndarray, list[bytes | None]]:
    """The vectors of ``columns`` (an (n, m) array's columns, or m vectors), and the SHA-256 of each one's bytes (None
    for a vector of zeros, whose solution and product are 0 exactly: neither hashed nor kept)."""
    vectors = columns.T if isinstance(columns, np.ndarray) and columns.ndim == 2 else columns
    # the columns of an array read as rows of one transposed copy (half the CPU time of a copy and a BLAKE2 digest per
    # column: the CPU's SHA instructions); vectors given apart, as they are. A test for zeros costs an eighth of a digest
    rows = np.ascontiguousarray(np.asarray(columns, dtype=float).T) if vectors is not columns else vectors
    keys = [hashlib.sha256(np.ascontiguousarray(v, dtype=float)).digest() if np.any(v) else None for v in rows]
    return vectors, keys


def _keep(cache: dict, new: dict, n: int, m: int, *, copy: bool = True) -> None:
    """Add the vectors ``new`` (key → (n,) array; copied unless ``copy`` is False: arrays of their own) to ``cache``,
    keeping the newest :data:`CACHED_SOLUTIONS` within :data:`CACHED_SOLUTION_FLOATS` numbers, and at least the ``m``
    of the call that adds them."""
    room = max(m, min(CACHED_SOLUTIONS, CACHED_SOLUTION_FLOATS // max(n, 1)))
    for key, vector in new.items():
        cache[key] = np.array(vector, dtype=float) if copy else vector
    while len(cache) > room:
        del cache[next(iter(cache))]


def check_clearance_model(rig: Rig, kind: str) -> list[str]:
    """The nonlinear bearings (radial clearance, or a bearing from internal geometry); raise :class:`ModelError` for a
    radial clearance outside the beam model, or a ball bearing in the solid model (the fidelities their
    nonlinear solve is tested on)."""
    gapped = [b.name for b in rig.bearings if b.radial_clearance_um > 0]
    balls = [b.name for b in rig.bearings if b.model != "linear"]
    if gapped and kind != "beam":
        raise ModelError(f"bearing(s) {', '.join(gapped)} have a radial clearance (radial_clearance_um > 0), which "
                         "makes the model nonlinear; only the beam model solves it (use --model beam, or set "
                         "radial_clearance_um = 0)")
    if balls and kind not in ("beam", "hybrid"):
        raise ModelError(f"bearing(s) {', '.join(balls)} are ball bearings from geometry (model = \"ball\") or "
                         "other bearings from internal geometry, which "
                         "makes the model nonlinear; the beam and hybrid models solve it (use --model beam or "
                         "hybrid)")
    return nonlinear_bearing_names(rig)


def prepare_model(rig: Rig, settings: SweepSettings = SweepSettings(), *, loads_ahead=None) -> PreparedModel:
    """Check supports, assemble ``rig`` at the settings' fidelity and set up its solver.

    Parameters
    ----------
    rig : Rig
        A validated rig (:func:`rvcoax.load_rig`).
    settings : SweepSettings
        The model (beam, hybrid, solid), the solver and the solid mesh size.
    loads_ahead : callable, optional
        ``loads_ahead(system)`` → more load vectors (each of the assembled system's length) that the caller will solve
        on this model, besides the rig's own unit loads (a calibration's trial rigs:
        :func:`rvcoax.results.studies.calibration.loads_with_trials`); see :func:`prepare_system`.

    Returns
    -------
    PreparedModel
        The assembled system and its factorisation, to pass to :func:`run_sweep` (or calibration) so that
        several sweeps of one rig assemble and factorise it once.
    """
    system = assemble_model(rig, settings)
    return prepare_system(system, settings, loads_ahead=None if loads_ahead is None else (lambda: loads_ahead(system)))


def assemble_model(rig: Rig, settings: SweepSettings = SweepSettings()) -> RigSystem:
    """Check supports and memory, and assemble ``rig`` at the settings' fidelity, without setting up a solver
    (:func:`prepare_model` does both; a study that only re-uses the assembled pieces needs this alone)."""
    check_clearance_model(rig, settings.model)
    check_supports(rig)
    too_big = preflight.memory_problem(rig, settings.model, settings.mesh_size_mm, settings.solver)
    if too_big:
        raise ModelError(too_big)
    options = {} if settings.mesh_size_mm is None else {"mesh_size_mm": settings.mesh_size_mm}
    return assemble_rig(rig, settings.model, **options)


def prepare_system(system: RigSystem, settings: SweepSettings, *, loads_ahead=None) -> PreparedModel:
    """Set up the solver of an already assembled system (e.g. one whose springs a sample changed).

    Where the set-up makes a solve call of its own (the tied Cholesky path of the hybrid model), the system's unit
    loads, and those ``loads_ahead()`` returns, ride along in it: the sweeps that follow find them solved
    (:class:`rvcoax.fem.solvers.SolvedAhead`) instead of making a solve call, a pass over the whole factor, of their own.
    """
    def ahead() -> np.ndarray | None:
        vectors = [system.unit_loads[k] for k in UNIT_LOADS] + list(() if loads_ahead is None else loads_ahead())
        distinct = _distinct_loaded(vectors)
        return np.column_stack([vectors[j] for j in distinct]) if distinct else None

    solve, name, report, reduced_solve, release = _prepare(system, settings, ahead)
    return PreparedModel(system, solve, name, report, reduced_solve=reduced_solve, release_solver=release)


def _relative_residual(reduce, unbalance: np.ndarray, load: np.ndarray) -> float:
    """‖Tᵀ(K u − f)‖ / ‖Tᵀ f‖: the relative residual of a linear case on the constrained DOFs (0 without load);
    ``reduce`` is Tᵀ (``system.elimination.T``, made once per sweep: scipy builds and checks a new matrix each time)."""
    scale = np.linalg.norm(reduce @ load)
    return float(np.linalg.norm(reduce @ unbalance) / scale) if scale > 0 else 0.0


def _unit_solutions(prepared: PreparedModel, loads: dict) -> tuple[np.ndarray, dict, np.ndarray]:
    """The solutions of every unit load (as columns and by name) and of the loads present at rest."""
    unit = prepared.solve_unit_loads([loads[k] for k in UNIT_LOADS])
    unit_by_name = {k: unit[:, i] for i, k in enumerate(UNIT_LOADS)}
    return unit, unit_by_name, sum(unit_by_name[k] for k in REST_LOADS)


def _unit_unbalances(prepared: PreparedModel, loads: dict, unit_by_name: dict) -> dict:
    """K u_k − f_k of the unit loads ``loads`` (by name; those that are not zeros: a load of zeros has the solution 0
    exactly, :meth:`PreparedModel.solve_unit_loads`, and K u_k − f_k = 0) from their solutions ``unit_by_name``: the
    unbalance a case superposes (K products kept by the model: :meth:`PreparedModel.stiffness_products`)."""
    if not loads:
        return {}
    products = prepared.stiffness_products([unit_by_name[k] for k in loads])  # the columns as they are, not a copy
    return {k: products[:, j] - load for j, (k, load) in enumerate(loads.items())}


def _case_responses(prepared: PreparedModel, loads: dict, unit_by_name: dict, direct: bool) -> tuple:
    """The unit loads, their responses and unbalances K u_k − f_k (by name) that a sweep's cases are formed from
    (:func:`_solved_cases`): with the direct method every unit load and no unbalances; by superposition the unit loads
    that are not zeros (the reference rig: 3 of 9), whose solutions, products and weights a case sums."""
    if direct:
        return loads, unit_by_name, None
    loaded = {k: loads[k] for k in UNIT_LOADS if np.any(loads[k])}
    return loaded, {k: unit_by_name[k] for k in loaded}, _unit_unbalances(prepared, loaded, unit_by_name)


def _superposed(vectors: dict, weights: dict, n: int, scratch: np.ndarray | None = None) -> np.ndarray:
    """Σ w_k v_k over the vectors ``vectors`` holds (by name; the weights of
    :func:`rvcoax.geometry.model.loads.case_weights`), in :data:`UNIT_LOADS` order.

    Bit for bit what :func:`rvcoax.geometry.model.loads.superpose` gives (``from_rest`` False) when the vectors left
    out are zeros: its sum starts from 0, so no entry of the running total is −0, and adding w · 0 = ±0 (finite w) to
    such a total changes nothing; only the work is left out (the reference rig: 6 of its 9 unit loads are zero).
    ``scratch``, an (n,) array, holds each term w_k v_k (the same numbers, without a new array for each: on the hybrid
    rig a temporary of 0.9 MB costs more than the product it holds)."""
    total = np.zeros(n)
    scratch = np.empty(n) if scratch is None else scratch
    for name in UNIT_LOADS:
        if name in vectors:
            total += np.multiply(vectors[name], weights[name], out=scratch)
    return total


def _announce(i: int, n: int, result: CaseResult, on_case, progress) -> None:
    """Hand case ``i`` of ``n`` to ``on_case`` (to save it at once) and report the progress, where asked."""
    if on_case is not None:
        on_case(i, result)
    if progress is not None:
        progress(i + 1, n)


@dataclass(frozen=True, eq=False)
class _CaseChecks:
    """What a superposition sweep checks each case with, from the unit loads that are not zeros (by name), formed once:
    their unbalances K u_k − f_k at the frame's fixed DOFs (the fixed supports' reactions) and on the constrained DOFs,
    Tᵀ(K u_k − f_k), with the loads there, Tᵀ f_k. A case with weights w_k sums them
    (:func:`rvcoax.geometry.model.loads.case_weights`)."""

    fixed: np.ndarray  # the frame's fixed DOFs
    at_fixed: dict  # name → (K u_k − f_k)[fixed]
    reduced_unbalances: dict  # name → Tᵀ(K u_k − f_k)
    reduced_loads: dict  # name → Tᵀ f_k
    n_dofs: int

    @classmethod
    def of(cls, system: RigSystem, loads: dict, unbalances: dict) -> _CaseChecks:
        """From the unit loads ``loads`` and their unbalances ``unbalances`` (:func:`_unit_unbalances`), by name."""
        fixed = np.asarray(system.frame.structure.fixed_dofs, dtype=int)
        reduce = system.elimination.T
        return cls(fixed, {k: r[fixed] for k, r in unbalances.items()},
                   {k: np.asarray(reduce @ r) for k, r in unbalances.items()},
                   {k: np.asarray(reduce @ f) for k, f in loads.items()}, system.n_dofs)

    def residual(self, weights: dict, scratch: np.ndarray) -> float:
        """‖Tᵀ(K u − f)‖ / ‖Tᵀ f‖ of the case (:func:`_relative_residual`), each a sum of the units' (``scratch``: a
        vector of the constrained DOFs' length)."""
        m = len(scratch)
        scale = np.linalg.norm(_superposed(self.reduced_loads, weights, m, scratch))
        return float(np.linalg.norm(_superposed(self.reduced_unbalances, weights, m, scratch)) / scale) if scale > 0 else 0.0

    def at_fixed_dofs(self, weights: dict) -> np.ndarray | None:
        """A vector of the model's length holding the case's K u − f at the fixed DOFs (zeros elsewhere: the reactions
        :func:`rvcoax.fem.equilibrium.check_equilibrium` and the housings' beds read); None without fixed DOFs."""
        if not self.fixed.size:
            return None
        vector = np.zeros(self.n_dofs)
        vector[self.fixed] = _superposed(self.at_fixed, weights, self.fixed.size)
        return vector


def _solved_cases(system: RigSystem, cases, responses: tuple[dict, dict, dict | None], contact, *, solve=None):
    """(index, case, load f, displacement u, relative residual, K u − f, its change since rest) of every case, in
    order; ``responses``: the unit loads, the unit responses and their unbalances K u_k − f_k
    (:func:`_unit_unbalances`), by name (by superposition: only the unit loads that are not zeros, and their responses;
    with ``solve``: every unit load).

    By superposition of the unit responses (``solve`` None), f = Σ w_k f_k, u = Σ w_k u_k and K u − f =
    Σ w_k (K u_k − f_k), the same weights (:func:`rvcoax.geometry.model.loads.case_weights`, :func:`_superposed`): no
    product with K per case. K u − f is then summed where it is read, at the fixed DOFs (a vector of zeros elsewhere,
    :meth:`_CaseChecks.at_fixed_dofs`; None without fixed DOFs), and the residual from its reduction Tᵀ(K u − f).
    With ``solve`` (the direct method) each case is solved, its K u − f formed, and handed on before the next.
    """
    loads, unit_by_name, unbalance_by_name = responses  # the last None with ``solve``
    rest_weights = {k: float(k in REST_LOADS) for k in UNIT_LOADS}
    if solve is not None:
        reduce = system.elimination.T
        rest = sum(unit_by_name[k] for k in REST_LOADS)
        rest_unbalance = system.stiffness @ rest - sum(loads[k] for k in REST_LOADS)
        for i, case in enumerate(cases):
            f = superpose(loads, case.input_torque_Nm, case.output_torque_Nm, False, contact)
            u = solve(f)
            unbalance = system.stiffness @ u - f
            yield i, case, f, u, _relative_residual(reduce, unbalance, f), unbalance, unbalance - rest_unbalance
        return
    checks = _CaseChecks.of(system, loads, unbalance_by_name)
    rest_unbalance = checks.at_fixed_dofs(rest_weights)
    scratch, reduced_scratch = np.empty(system.n_dofs), np.empty(system.elimination.shape[1])
    for i, case in enumerate(cases):
        weights = case_weights(case.input_torque_Nm, case.output_torque_Nm, include_rest=True,
                               contact_torques_Nm=contact)  # as superpose weighs them
        unbalance = checks.at_fixed_dofs(weights)
        yield (i, case, _superposed(loads, weights, system.n_dofs, scratch),
               _superposed(unit_by_name, weights, system.n_dofs, scratch), checks.residual(weights, reduced_scratch),
               unbalance, None if unbalance is None else unbalance - rest_unbalance)


def run_sweep(rig: Rig, cases: tuple[LoadCase, ...], settings: SweepSettings = SweepSettings(), progress=None,  # noqa: PLR0913
              prepared: PreparedModel | None = None, *, on_case=None, engineering: bool = True,
              release_solver: bool = False) -> Sweep:
    """Solve every load case of ``cases`` on ``rig``.

    A rig with bearing clearance is solved case by case (:func:`run_gap_sweep`); otherwise every case
    is a superposition of unit loads on one factorisation.

    Parameters
    ----------
    rig : Rig
        A validated rig (:func:`rvcoax.load_rig`).
    cases : tuple of LoadCase
        The (T1, T2) pairs (:func:`rvcoax.paper_cases`, :func:`rvcoax.read_cases`, …).
    settings : SweepSettings
        The model (beam, hybrid, solid), the method, the solver and the solid mesh size.
    progress : callable, optional
        ``progress(i, n)`` after each case.
    prepared : PreparedModel, optional
        An assembled, factorised model whose structure is ``rig``'s, to reuse (only load parameters may
        differ: the unit loads are rebuilt from ``rig``, unless ``prepared.system`` holds this very rig's).
    on_case : callable, optional
        ``on_case(i, CaseResult)`` as soon as case ``i`` is solved (to save it before the sweep ends).
    engineering : bool
        Also compute each case's coupling, bearing and reaction tables
        (:func:`rvcoax.results.engineering.case_engineering`; off for sweeps that only need Y, e.g. a fit).
    release_solver : bool
        Free ``prepared``'s factorisation once its unit loads are solved, before the cases' residuals and reactions
        read K (superposition sweeps; :meth:`PreparedModel.release`), for a caller that solves nothing more on it. A
        model this function prepares is always freed so: the factor (2 GB at 492 k DOF) and K are never both resident.

    Returns
    -------
    Sweep
        Per case: Y along each measured shaft, Y_max, β = arcsin(Y_max / L) and the true tilt, with the
        residual of the solve; and the rig, settings and solver that produced them.
    """
    gapped = check_clearance_model(rig, settings.model if prepared is None else prepared.system.kind)
    if prepared is None:
        prepared = prepare_model(rig, settings)
        system = prepared.system
        release_solver = True  # nobody else holds this model
    else:  # the loads of ``rig`` (frozen) are rebuilt unless the prepared system holds them already
        system = prepared.system if prepared.system.rig is rig else prepared.system.with_loads_of(rig)
    solve, solver_name, report = prepared.solve, prepared.solver_name, prepared.report
    if gapped:
        return run_gap_sweep(cases, settings, dataclasses.replace(prepared, system=system), progress=progress,
                             on_case=on_case, engineering=engineering)
    loads = system.unit_loads
    unit, unit_by_name, rest = _unit_solutions(prepared, loads)
    direct = settings.method == "direct"
    if release_solver and not direct:
        prepared.release()
    from_rest = rig.paths.measured_from == "aligned_at_rest"
    springs = SpringMotion.of(system.frame, rig) if engineering else None
    contact = gear_contact_torques(rig)
    responses, results = _case_responses(prepared, loads, unit_by_name, direct), []
    # K u − f at the fixed DOFs: the fixed supports' reactions (condensed housings' beds), in total and since rest
    for i, case, load, u, residual, unbalance, since_rest in _solved_cases(system, cases, responses, contact,
                                                                           solve=solve if direct else None):
        check = equilibrium.check_equilibrium(system.frame.structure, system.stiffness, u, load, system.dofs,
                                              unbalance=unbalance)
        check_solution(case.label, u, check.relative_error, residual)
        change = u - rest
        measured = change if from_rest else u
        results.append(CaseResult(
            case=case,
            paths={s: read_path(system, measured, s) for s in MEASURED_SHAFTS},
            absolute_paths={s: read_path(system, u, s) for s in MEASURED_SHAFTS},
            equilibrium_error=check.relative_error, residual=residual,
            engineering=case_engineering(rig, system.frame, u, change, from_rest, applied=check.applied,
                                         reactions=check.reactions, springs=springs, case=case, fixed_total=unbalance,
                                         fixed_change=since_rest) if engineering else None,
            shaft_strength=shaft_strength(rig, system.frame, u) if engineering else None,
            torque_paths=torque_paths(rig, springs, u, case) if engineering else None))
        _announce(i, len(cases), results[-1], on_case, progress)
    unit_paths = {k: {s: read_path(system, unit_by_name[k], s) for s in MEASURED_SHAFTS} for k in UNIT_LOADS}
    return Sweep(rig=rig, frame=system.frame, settings=settings, cases=tuple(results), unit_paths=unit_paths,
                 solver=solver_name, n_dofs=system.n_dofs, system=system, states=LinearStates(unit),
                 solver_report=dict(report))


@dataclass(frozen=True, eq=False)
class _NonlinearProblem:
    """What every case of a sweep with nonlinear bearings is solved on: the system, its condensed bearings, the
    solve of the linear reference model and |K| (for the backward error)."""

    system: RigSystem
    bearings: NonlinearBearings
    solve: object
    abs_stiffness: object


def _solve_nonlinear_case(problem: _NonlinearProblem, weights: dict, label: str):
    """One case by Newton on the condensed bearing motions, checked: (u, solution, equilibrium, residual, K u − f)
    (the last at the fixed DOFs: their supports' reactions)."""
    system, bearings = problem.system, problem.bearings
    load = sum(weights[k] * system.unit_loads[k] for k in UNIT_LOADS)
    try:
        solution = bushing.solve_condensed(bearings, problem.solve, load, bearings.released, what="nonlinear bearing",
                                           regularisation=bearings.regularisation)
    except bushing.GapConvergenceError as error:
        raise ModelError(f"case {label}: {error}") from None
    u = solution.displacement
    # the nonlinear laws as a load: K u = f + Uᵀ G(U u) is their equilibrium
    released, _ = bearings.released(bearings.operator @ u)
    effective = load + bearings.operator.T @ released
    reduced_residual = np.linalg.norm(system.elimination.T @ (system.stiffness @ u - effective))
    loads_norm = np.linalg.norm(system.elimination.T @ load) + np.linalg.norm(system.elimination.T @ (effective - load))
    residual = float(reduced_residual / loads_norm) if loads_norm > 0 else 0.0
    # backward error: against the terms K u is summed from (|K| |u|), which is what floating point resolves
    terms = loads_norm + np.linalg.norm(system.elimination.T @ (problem.abs_stiffness @ np.abs(u)))
    backward = float(reduced_residual / terms) if terms > 0 else 0.0
    if not np.all(np.isfinite(u)) or not backward <= GAP_BACKWARD_LIMIT:
        raise ModelError(f"case {label}: the nonlinear bearing solution misses equilibrium: backward error "
                         f"{backward:.1e} (> {GAP_BACKWARD_LIMIT:g}, relative to |K| |u| and the loads)")
    check = equilibrium.check_equilibrium(system.frame.structure, system.stiffness, u, effective, system.dofs)
    check_solution(label, u, check.relative_error, residual)
    return u, solution, check, residual, system.stiffness @ u - effective


def _nonlinear_summary(report, bearings: NonlinearBearings, iterations: list[int], operating: dict) -> dict:
    """The solver report of a nonlinear sweep: which nonlinearity, the Newton iterations, the operating points of
    the bearings from internal geometry."""
    summary = dict(report)
    others = [m.name for m in bearings.rolling if m.model != "ball"]
    kinds = ((["bearing clearance"] if bearings.gap_names else []) + (["ball bearings"] if bearings.balls else [])
             + (["rolling bearings from geometry"] if others else []))
    summary.update({"nonlinear": f"{' and '.join(kinds)}, Newton on the condensed bearing motions",
                    "gapped_bearings": list(bearings.gap_names),
                    "newton_iterations_max": int(max(iterations))})
    if bearings.balls:
        summary["ball_bearings"] = [ball.name for ball in bearings.balls]
        summary["ball_bearing_operating_points"] = {m.name: operating[m.name] for m in bearings.balls}
    if others:
        summary["rolling_bearings"] = others
        summary["rolling_bearing_operating_points"] = {name: operating[name] for name in others}
    return summary


def run_gap_sweep(cases, settings: SweepSettings, prepared: PreparedModel, *, progress=None, on_case=None,  # noqa: PLR0913
                  engineering: bool = True) -> Sweep:
    """The sweep of a model with nonlinear bearings (radial clearance: beam; ball bearings from geometry:
    beam or hybrid): the rest state and each case solved on its own.

    ``prepared.solve`` solves the model as assembled (every bearing on its linear reference spring); the
    nonlinear bearings are condensed on it once
    (:func:`rvcoax.geometry.model.nonlinear_bearings.prepare_nonlinear_bearings`) and each case is
    solved by Newton's method on the condensed motions (:func:`rvcoax.fem.bushing.solve_condensed`)
    with that one factorisation. Each solution is checked: the backward error
    ‖Tᵀ(K u − f − Uᵀ G(U u))‖ / (‖Tᵀ |K| |u|‖ + ‖Tᵀ f‖ + ‖Tᵀ Uᵀ G‖) must be below
    :data:`GAP_BACKWARD_LIMIT`, the relative residual (against the loads f and Uᵀ G) below
    :data:`EQUILIBRIUM_LIMIT` as for every case, and the global equilibrium uses the bearing forces
    of the nonlinear laws. (Against ‖Tᵀ f‖ alone, the floating-point floor of K u, ε ‖|K| |u|‖, is
    1.7e-9 for T1 = 0.01 N·m with an open gap: a correct solution failed a 1e-9 limit.) No unit
    responses exist: ``unit_paths`` is empty and ``unit_displacements`` None; ``case_displacements``
    holds each case's displacement as measured, ``rest_displacement`` the rest state and
    ``nonlinear_bearings`` the condensed laws, from which :func:`rvcoax.results.connections.connection_states`
    gives every spring's state with each nonlinear bearing's own force and operating stiffness. The solver report lists each ball bearing's operating
    point (force, tangent stiffness, ball loads) at rest and in every case.
    """
    system, solve = prepared.system, prepared.solve
    rig = system.rig
    bearings = prepare_nonlinear_bearings(rig, system.frame, solve, system.n_dofs)
    problem = _NonlinearProblem(system, bearings, solve, abs(system.stiffness))

    def solve_case(weights: dict, label: str):
        return _solve_nonlinear_case(problem, weights, label)

    contact = gear_contact_torques(rig)
    # the reducers' joints are linear springs: their checks need the spring states even without the tables
    springs = SpringMotion.of(system.frame, rig) if engineering or rig.reducers else None
    rest_u, rest_solution, _, _, rest_unbalance = solve_case(case_weights(0.0, 0.0, include_rest=True), "at rest")
    every = ("ball",) + GEOMETRIC_MODELS
    operating = {name: [{"case": "at rest", **point}]
                 for name, point in bearings.operating_points(rest_solution.motion, every).items()}
    from_rest = rig.paths.measured_from == "aligned_at_rest"
    results, iterations, measured_all = [], [rest_solution.iterations], []
    for i, case in enumerate(cases):
        weights = case_weights(case.input_torque_Nm, case.output_torque_Nm, include_rest=True,
                               contact_torques_Nm=contact)
        u, solution, check, residual, unbalance = solve_case(weights, case.label)
        iterations.append(solution.iterations)
        lives = rolling_bearing_lives(rig, bearings, solution.motion, case.input_torque_Nm, case.output_torque_Nm)
        checks = (reducer_checks(rig, springs.states(u, from_rest=False), case.input_torque_Nm, case.output_torque_Nm)
                  if rig.reducers else ())
        points = bearings.operating_points(solution.motion, every)
        listed = {name: {"case": case.label, "T1_input_Nm": case.input_torque_Nm,
                         "T2_output_Nm": case.output_torque_Nm, **point} for name, point in points.items()}
        for name, point in listed.items():
            operating[name].append(point)
        measured = u - rest_u if from_rest else u
        measured_all.append(measured)
        # the engineering tables with every nonlinear bearing's force and operating stiffness from its own law
        tables = (case_engineering(rig, system.frame, u, u - rest_u, from_rest, applied=check.applied,
                                   reactions=check.reactions, springs=springs, fixed_total=unbalance,
                                   fixed_change=unbalance - rest_unbalance, nonlinear=bearings, rest_total=rest_u,
                                   balls=points) if engineering else None)
        results.append(CaseResult(case=case, paths={s: read_path(system, measured, s) for s in MEASURED_SHAFTS},
                                  absolute_paths={s: read_path(system, u, s) for s in MEASURED_SHAFTS},
                                  equilibrium_error=check.relative_error, residual=residual, engineering=tables,
                                  ball_lives=lives, reducer_checks=checks, operating_points=listed,
                                  shaft_strength=shaft_strength(rig, system.frame, u) if engineering else None,
                                  torque_paths=torque_paths(rig, springs, u, case) if engineering else None))
        _announce(i, len(cases), results[-1], on_case, progress)
    summary = _nonlinear_summary(prepared.report, bearings, iterations, operating)
    states = NonlinearStates(np.column_stack(measured_all) if measured_all else np.zeros((system.n_dofs, 0)),
                             rest_u, bearings)
    return Sweep(rig=rig, frame=system.frame, settings=settings, cases=tuple(results), solver=prepared.solver_name,
                 n_dofs=system.n_dofs, system=system, states=states,
                 solver_report=summary)


def solve_unit_responses(frame: RigModel):
    """Beam model only (kept for callers that hold a RigModel): (system, loads, unit displacements)."""
    system = assemble_beam(frame.rig)
    factorised = factorize(system.stiffness, system.elimination)
    return factorised, system.unit_loads, factorised.solve(np.column_stack([system.unit_loads[k] for k in UNIT_LOADS]))
