"""Relative motion and force of a rig model's springs for given displacement vectors: the spring-state operator.

Every bearing, mount, coupling and joint is a bushing (:mod:`rvcoax.fem.bushing`) between two frame nodes,
or a node and the ground, at a point c reached by rigid arms. Its relative motion is
Δ = B_b u_b − B_a u_a: the motion at c of side b (the shaft of a bearing, the ``to`` end of a
coupling or joint, the part of a mount) minus that of side a (the housing, the ``from`` end, the
ground). The spring exerts diag(k) Δ on side a and the opposite on side b.

A spring may be free of load at a relative motion Δ0 ≠ 0 (a coupling installed with a parallel
offset or angle, a raised mount: :func:`rvcoax.geometry.model.beam.stress_free_motions`); it then exerts
diag(k) (Δ − Δ0). The *deformation* is Δ − Δ0 (from the unloaded geometry) or the change of Δ since the
rest state (from rest, where Δ0 cancels), so that force = diag(k) × deformation in both references.

In hybrid and solid models the same bushings attach to the reference nodes tied to solid faces
(:mod:`rvcoax.geometry.model.hybrid`), so this works on the frame part of the displacement vector at every
fidelity. The states of a solved sweep's load cases: :mod:`rvcoax.results.connections`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rvcoax.fem import bushing
from rvcoax.geometry.model.beam import SpringId, housing_bed_group, stress_free_motions

__all__ = ["ConnectionStates", "HousingBed", "SpringMotion", "housing_beds", "spring_states", "with_nonlinear_laws"]


@dataclass(frozen=True, eq=False)
class ConnectionStates:
    """Relative motion and force of every named spring in every case (SI, global axes).

    Attributes
    ----------
    names : tuple of str
        ``"<kind>:<name>"`` per spring (``bearing``, ``mount``, ``coupling``, ``joint``).
    point_m : (n_springs, 3) array
        Where each spring sits.
    deformation : (n_cases, n_springs, 6) array
        Translation (m) and rotation (rad) of side b relative to side a at the spring point, less
        the stress-free Δ0 (or since the rest state).
    force_on_b : (n_cases, n_springs, 6) array
        Force (N) and moment about the spring point (N·m) that the spring exerts on side b.
    stiffness : (n_cases, n_springs, 6) array
        Operating stiffness (N/m, N·m/rad) on each component: the spring's own for a linear spring; for a
        nonlinear bearing (clearance, ball bearing) the diagonal of its tangent ∂F/∂Δ at the case's
        converged state (the same in both references).
    """

    names: tuple[SpringId, ...]
    point_m: np.ndarray
    deformation: np.ndarray
    force_on_b: np.ndarray
    stiffness: np.ndarray

    def index(self, kind: str, name: str) -> int:
        """Row of the spring ``name`` of ``kind`` (bearing, mount, coupling, joint)."""
        try:
            return self.names.index(SpringId(kind, name))
        except ValueError:
            raise KeyError(f"no {kind} named '{name}'") from None


@dataclass(frozen=True, eq=False)
class HousingBed:
    """Where a condensed ``[[housings]]`` entry meets the ground: its fixed bed nodes (one per attachment).

    The fixed DOFs' reactions there, K u − f, are what the ground exerts on the housing (and through it
    on the part it holds); :meth:`resultant` sums them about the housing's centre ``x_mm``.
    """

    name: str
    part: str
    x_mm: float
    dofs: np.ndarray  # (attachments × 6,) frame DOFs of the bed nodes
    attachments_m: np.ndarray  # (attachments, 3)

    def resultant(self, reactions: np.ndarray) -> np.ndarray:
        """Force (N) and moment about (x_mm, 0, 0) (N·m) of the fixed-DOF ``reactions`` (n_dofs,) at the bed."""
        per_node = np.asarray(reactions, dtype=float)[self.dofs].reshape(-1, 6)
        arms = self.attachments_m - np.array([self.x_mm * 1e-3, 0.0, 0.0])
        return np.concatenate([per_node[:, :3].sum(axis=0),
                               (np.cross(arms, per_node[:, :3]) + per_node[:, 3:]).sum(axis=0)])


def housing_beds(model, rig) -> tuple[HousingBed, ...]:
    """The :class:`HousingBed` of every ``[[housings]]`` entry of ``rig`` in ``model`` (a RigModel)."""
    beds = []
    for h in rig.housings:
        nodes = np.array([model.node(housing_bed_group(h.name), x) for x in h.attachments_x_mm])
        points = np.zeros((nodes.size, 3))
        points[:, 0] = np.asarray(h.attachments_x_mm, dtype=float) * 1e-3
        beds.append(HousingBed(h.name, h.part, float(np.mean(h.attachments_x_mm)),
                               (6 * nodes[:, None] + np.arange(6)).ravel(), points))
    return tuple(beds)


@dataclass(frozen=True, eq=False)
class SpringMotion:
    """What turns displacement vectors into spring states, built once per model (the springs' rigid-arm
    operators, their DOFs, stiffnesses and stress-free motions Δ0)."""

    names: tuple[SpringId, ...]
    point_m: np.ndarray
    operator: np.ndarray  # (springs, 6, 12)
    dofs: np.ndarray  # (springs, 12), −1 for the ground
    stiffness: np.ndarray  # (springs, 6)
    stress_free: np.ndarray  # (springs, 6)
    n_dofs: int
    beds: tuple[HousingBed, ...] = ()

    @classmethod
    def of(cls, model, rig) -> SpringMotion:
        """The springs of ``model`` (a :class:`RigModel`) built from ``rig``."""
        frame = model.structure
        operator, dofs = bushing.relative_motion_operator(frame.coordinates, frame.bushings)
        return cls(tuple(model.bushing_names), np.asarray(frame.bushings.point_m, float), operator, dofs,
                   np.asarray(frame.bushings.stiffness, float), stress_free_motions(rig), frame.n_dofs,
                   housing_beds(model, rig))

    def states(self, displacements: np.ndarray, from_rest: bool) -> ConnectionStates:
        """Spring states for displacement vectors (n_dofs, n_cases) or (n_dofs,): measured since the rest
        state (``from_rest``: the stress-free Δ0 cancels) or from the unloaded geometry (Δ0 subtracted)."""
        u = np.asarray(displacements, float)
        u = (u[:, None] if u.ndim == 1 else u)[: self.n_dofs]
        gathered = np.where((self.dofs >= 0)[:, :, None], u[np.maximum(self.dofs, 0)], 0.0)  # (springs, 12, cases)
        deformation = np.einsum("sij,sjc->csi", self.operator, gathered)
        if not from_rest:
            deformation = deformation - self.stress_free[None, :, :]
        stiffness = np.broadcast_to(self.stiffness[None, :, :], deformation.shape)
        return ConnectionStates(self.names, self.point_m, deformation, -stiffness * deformation, stiffness)


def spring_states(model, rig, displacements: np.ndarray, from_rest: bool) -> ConnectionStates:
    """Relative motion and force of every spring of ``model`` (a :class:`RigModel`) for displacement
    vectors ``displacements`` (n_dofs, n_cases) or (n_dofs,) (see :meth:`SpringMotion.states`)."""
    return SpringMotion.of(model, rig).states(displacements, from_rest)


def with_nonlinear_laws(states: ConnectionStates, law, unloaded: np.ndarray,
                        rest: np.ndarray | None = None) -> ConnectionStates:
    """``states`` with each nonlinear bearing's force and operating stiffness taken from its own law.

    Parameters
    ----------
    states : ConnectionStates
        The linear spring states of the cases (every bearing on its linear reference spring).
    law : NonlinearBearings
        The condensed nonlinear bearings (:mod:`rvcoax.geometry.model.nonlinear_bearings`).
    unloaded : (n_dofs, n_cases) or (n_dofs,) array
        The cases' displacements from the unloaded geometry (what the laws see).
    rest : (n_dofs,) array, optional
        The rest state from the unloaded geometry: given, forces are the change since rest,
        −(F(Δ) − F(Δ_rest)); else the totals −F(Δ).

    Returns
    -------
    ConnectionStates
        The same springs, with the nonlinear bearings' rows of ``force_on_b`` and ``stiffness`` replaced
        (the tangent ∂F/∂Δ's diagonal at each case's state, the same in both references).
    """
    operator = law.operator
    u = np.asarray(unloaded, dtype=float)
    motions = np.asarray(operator @ (u[:, None] if u.ndim == 1 else u))  # (p, n_cases), as the laws see them
    rest_force = law.laws(operator @ np.asarray(rest, dtype=float))[0] if rest is not None else 0.0
    force, stiffness = states.force_on_b.copy(), states.stiffness.copy()
    rows = [(states.names.index(spring), list(components), block) for spring, components, block in law.spring_rows()]
    for case in range(motions.shape[1]):
        carried, tangent = law.laws(motions[:, case])
        carried = carried - rest_force
        for row, components, block in rows:
            force[case, row, components] = -carried[block]
            stiffness[case, row, components] = np.diag(tangent[block, block])
    return ConnectionStates(states.names, states.point_m, states.deformation, force, stiffness)
