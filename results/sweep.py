"""A torque sweep on a rig: a pure function of (rig, load cases, settings).

The model is linear, so each case is a superposition of unit responses solved with one
factorisation (or one preconditioner set-up): u = u_rest + sign(T1) u_engaged_T1 +
sign(T2) u_engaged_T2 + T1 u_T1 + T2 u_T2 (:mod:`geometry.loads`). ``method="direct"`` assembles
each case's own load vector and solves it instead (same factorisation), as a check that both agree.

Y is read from the aligned rig at rest (``paths.measured_from = "aligned_at_rest"``: u − u_rest)
or from the unloaded geometry (``"unloaded"``: u). Both are kept per case.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from fem import diagnostics, equilibrium
from fem import model as fem_model
from fem.solve import SingularModelError, factorize
from geometry.build import RigModel
from geometry.loads import REST_LOADS, UNIT_LOADS, case_weights
from geometry.schema import Rig
from geometry.system import MODEL_KINDS, RigSystem, assemble_beam, assemble_rig
from loadcases.cases import LoadCase
from results.paths import ShaftPathResult

SHAFTS = ("input", "output")


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


@dataclass(frozen=True)
class CaseResult:
    """Results of one load case."""

    case: LoadCase
    paths: dict[str, ShaftPathResult]
    absolute_paths: dict[str, ShaftPathResult]
    equilibrium_error: float
    residual: float


@dataclass(frozen=True, eq=False)
class Sweep:
    """All cases of a sweep, plus what is needed to explain how they were obtained."""

    rig: Rig
    model: RigModel
    settings: SweepSettings
    cases: tuple[CaseResult, ...]
    unit_paths: dict[str, dict[str, ShaftPathResult]] = field(default_factory=dict)
    solver: str = ""
    n_dofs: int = 0
    system: RigSystem | None = None
    unit_displacements: np.ndarray | None = None
    solver_report: dict = field(default_factory=dict)


class ModelError(RuntimeError):
    """A model that cannot be solved, with the reason in the user's terms."""


def read_path(system: RigSystem, displacement: np.ndarray, which: str) -> ShaftPathResult:
    """The measured shaft path ``which`` of a displacement vector."""
    probe = system.probes[which]
    return ShaftPathResult(probe.stations_mm, (probe.uy @ displacement) * 1e3, probe.length_mm,
                           probe.rotation_z @ displacement)


def check_supports(rig: Rig) -> None:
    """Raise :class:`ModelError` naming every part that can move without deforming anything.

    The test runs on the rig's beam model, which has the same parts and connections at any
    fidelity, so it is cheap also for solid models.
    """
    frame = assemble_beam(rig).frame.structure
    stiffness = fem_model.stiffness_matrix(frame)
    elimination, free = fem_model.constraint_elimination(frame)
    motions = diagnostics.find_free_motions(frame.coordinates, stiffness, elimination, free, frame.node_group)
    if motions:
        raise ModelError("the model is singular: " + "; ".join(m.describe() for m in motions)
                         + ". Add a bearing, mount or joint with stiffness in those directions.")


def _prepare(system: RigSystem, settings: SweepSettings):
    """A solver for the reduced system; returns (solve function, name, report dict)."""
    if system.kind == "beam" and settings.solver in ("auto", "superlu"):
        try:
            factorised = factorize(system.stiffness, system.elimination)
        except SingularModelError as error:
            raise ModelError(f"the model is singular ({error}); check that every part is supported") from None
        return factorised.solve, factorised.solver_name, {"solver": factorised.solver_name, "n_dofs": system.n_dofs}
    from fem import solvers

    reduced = (system.elimination.T @ system.stiffness @ system.elimination).tocsr()
    near_null = None
    method = solvers.choose_method(reduced.shape[0]) if settings.solver == "auto" else settings.solver
    if method == "amg":
        near_null = system.elimination.T @ rigid_body_modes(system)
    try:
        prepared = solvers.prepare(reduced, method=method, near_null_space=near_null)
    except solvers.SingularMatrixError as error:
        raise ModelError(f"the model is singular ({error}); check that every part is supported") from None

    def solve(load):
        return system.elimination @ prepared.solve(system.elimination.T @ load)

    return solve, prepared.report.name, prepared


def rigid_body_modes(system: RigSystem) -> np.ndarray:
    """The six rigid-body motions of the whole DOF vector (near-null space for AMG)."""
    table = system.dofs
    modes = np.zeros((system.n_dofs, 6))
    translational = table.component < 3
    centre = table.position.mean(axis=0)
    r = table.position - centre
    for axis in range(3):
        modes[table.component == axis, axis] = 1.0
        modes[table.component == 3 + axis, 3 + axis] = 1.0
    for rot in range(3):
        e = np.zeros(3)
        e[rot] = 1.0
        motion = np.cross(e, r)  # θ × r
        rows = np.flatnonzero(translational)
        modes[rows, 3 + rot] = motion[rows, table.component[rows]]
    return modes


@dataclass(frozen=True, eq=False)
class PreparedModel:
    """An assembled system with its solver set up (one factorisation), reusable across sweeps."""

    system: RigSystem
    solve: object
    solver_name: str
    report: object


def prepare_model(rig: Rig, settings: SweepSettings = SweepSettings()) -> PreparedModel:
    """Check supports, assemble ``rig`` at the settings' fidelity and set up its solver."""
    check_supports(rig)
    options = {} if settings.mesh_size_mm is None else {"mesh_size_mm": settings.mesh_size_mm}
    system = assemble_rig(rig, settings.model, **options)
    return PreparedModel(system, *_prepare(system, settings))


def run_sweep(rig: Rig, cases: tuple[LoadCase, ...], settings: SweepSettings = SweepSettings(), progress=None,
              prepared: PreparedModel | None = None) -> Sweep:
    """Solve every load case of ``cases`` on ``rig``; ``progress(i, n)`` is called per case.

    ``prepared`` reuses an assembled, factorised model whose structure is ``rig``'s (only load
    parameters may differ: the unit loads are rebuilt from ``rig``).
    """
    if prepared is None:
        prepared = prepare_model(rig, settings)
        system = prepared.system
    else:
        system = prepared.system.with_loads_of(rig)
    solve, solver_name, report = prepared.solve, prepared.solver_name, prepared.report
    loads = system.unit_loads
    unit = solve(np.column_stack([loads[k] for k in UNIT_LOADS]))
    unit_by_name = {k: unit[:, i] for i, k in enumerate(UNIT_LOADS)}
    rest = sum(unit_by_name[k] for k in REST_LOADS)
    from_rest = rig.paths.measured_from == "aligned_at_rest"
    frame = system.frame.structure
    results = []
    for i, case in enumerate(cases):
        weights = case_weights(case.input_torque_Nm, case.output_torque_Nm, include_rest=True)
        load = sum(weights[k] * loads[k] for k in UNIT_LOADS)
        u = sum(weights[k] * unit_by_name[k] for k in UNIT_LOADS) if settings.method == "superposition" else solve(load)
        if not np.all(np.isfinite(u)):
            raise ModelError(f"case {case.label}: the solution contains NaN or inf")
        check = equilibrium.check_equilibrium(frame, system.stiffness, u, load, system.dofs)
        reduced_residual = system.elimination.T @ (system.stiffness @ u - load)
        scale = np.linalg.norm(system.elimination.T @ load)
        residual = float(np.linalg.norm(reduced_residual) / scale) if scale > 0 else 0.0
        measured = u - rest if from_rest else u
        results.append(CaseResult(
            case,
            {s: read_path(system, measured, s) for s in SHAFTS},
            {s: read_path(system, u, s) for s in SHAFTS},
            check.relative_error,
            residual,
        ))
        if progress is not None:
            progress(i + 1, len(cases))
    unit_paths = {k: {s: read_path(system, unit_by_name[k], s) for s in SHAFTS} for k in UNIT_LOADS}
    summary = report if isinstance(report, dict) else _report_dict(report)
    return Sweep(rig, system.frame, settings, tuple(results), unit_paths, solver_name, system.n_dofs, system, unit,
                 summary)


def _report_dict(prepared) -> dict:
    r = prepared.report
    return {key: getattr(r, key) for key in ("name", "n_dofs", "setup_seconds", "solve_seconds", "peak_memory_MB")
            if hasattr(r, key)}


def solve_unit_responses(model: RigModel):
    """Beam model only (kept for callers that hold a RigModel): (system, loads, unit displacements)."""
    system = assemble_beam(model.rig)
    factorised = factorize(system.stiffness, system.elimination)
    return factorised, system.unit_loads, factorised.solve(np.column_stack([system.unit_loads[k] for k in UNIT_LOADS]))
