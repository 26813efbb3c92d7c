"""A torque sweep on a rig: a pure function of (rig, load cases, settings).

The beam model is linear, so each case is a superposition of unit responses solved with one
factorisation (:mod:`geometry.loads`): u = u_rest + sign(T1) u_engaged_T1 + sign(T2) u_engaged_T2
+ T1 u_T1 + T2 u_T2. ``method="direct"`` assembles each case's own load vector and solves it
instead (same factorisation), as a check that both agree.

Y is read from the aligned rig at rest (``paths.measured_from = "aligned_at_rest"``: u − u_rest)
or from the unloaded geometry (``"unloaded"``: u). Both are kept per case.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from fem import diagnostics, equilibrium
from fem import model as fem_model
from fem.solve import SingularModelError, factorize
from geometry.build import RigModel, build_rig_model
from geometry.loads import REST_LOADS, UNIT_LOADS, case_weights, unit_load_vectors
from geometry.schema import Rig
from loadcases.cases import LoadCase
from results.paths import ShaftPathResult

SHAFTS = ("input", "output")


@dataclass(frozen=True)
class SweepSettings:
    """How to solve: ``superposition`` of unit responses (default) or ``direct`` per case."""

    method: str = "superposition"
    model: str = "beam"

    def __post_init__(self) -> None:
        if self.method not in ("superposition", "direct"):
            raise ValueError(f"method must be 'superposition' or 'direct', got {self.method!r}")
        if self.model != "beam":
            raise ValueError(f"model {self.model!r} is not available yet; only 'beam'")


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


class ModelError(RuntimeError):
    """A model that cannot be solved, with the reason in the user's terms."""


def _path(model: RigModel, displacement: np.ndarray, which: str) -> ShaftPathResult:
    nodes, stations = model.path_nodes(which)
    path = getattr(model.rig.paths, which)
    return ShaftPathResult(stations, displacement[6 * nodes + 1] * 1e3, path.length_mm, displacement[6 * nodes + 5])


def solve_unit_responses(model: RigModel):
    """Factorise once and solve the four unit loads; returns (factorised system, loads, displacements)."""
    structure = model.structure
    stiffness = fem_model.stiffness_matrix(structure)
    elimination, free = fem_model.constraint_elimination(structure)
    motions = diagnostics.find_free_motions(structure.coordinates, stiffness, elimination, free, structure.node_group)
    if motions:
        raise ModelError("the model is singular: " + "; ".join(m.describe() for m in motions)
                         + ". Add a bearing, mount or joint with stiffness in those directions.")
    try:
        system = factorize(stiffness, elimination)
    except SingularModelError as error:
        raise ModelError(f"the model is singular ({error}); check that every part is supported") from None
    loads = unit_load_vectors(model)
    matrix = np.column_stack([loads[k] for k in UNIT_LOADS])
    return system, loads, system.solve(matrix)


def run_sweep(rig: Rig, cases: tuple[LoadCase, ...], settings: SweepSettings = SweepSettings(), progress=None) -> Sweep:
    """Solve every load case of ``cases`` on ``rig``; ``progress(i, n)`` is called per case."""
    model = build_rig_model(rig)
    system, loads, unit = solve_unit_responses(model)
    unit_by_name = {k: unit[:, i] for i, k in enumerate(UNIT_LOADS)}
    rest = sum(unit_by_name[k] for k in REST_LOADS)
    from_rest = rig.paths.measured_from == "aligned_at_rest"
    results = []
    for i, case in enumerate(cases):
        weights = case_weights(case.input_torque_Nm, case.output_torque_Nm, include_rest=True)
        load = sum(weights[k] * loads[k] for k in UNIT_LOADS)
        if settings.method == "superposition":
            u = sum(weights[k] * unit_by_name[k] for k in UNIT_LOADS)
        else:
            u = system.solve(load)
        if not np.all(np.isfinite(u)):
            raise ModelError(f"case {case.label}: the solution contains NaN or inf")
        check = equilibrium.check_equilibrium(model.structure, system.stiffness, u, load)
        residual = float(system.relative_residual(u, load))
        measured = u - rest if from_rest else u
        results.append(CaseResult(
            case,
            {s: _path(model, measured, s) for s in SHAFTS},
            {s: _path(model, u, s) for s in SHAFTS},
            check.relative_error,
            residual,
        ))
        if progress is not None:
            progress(i + 1, len(cases))
    unit_paths = {k: {s: _path(model, unit_by_name[k], s) for s in SHAFTS} for k in UNIT_LOADS}
    return Sweep(rig, model, settings, tuple(results), unit_paths, system.solver_name, model.structure.n_dofs)
