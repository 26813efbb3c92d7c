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
from rvcoax.geometry.model.beam import SpringId, stress_free_motions

__all__ = ["ConnectionStates", "SpringMotion", "spring_states"]


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

    @classmethod
    def of(cls, model, rig) -> SpringMotion:
        """The springs of ``model`` (a :class:`RigModel`) built from ``rig``."""
        frame = model.structure
        operator, dofs = bushing.relative_motion_operator(frame.coordinates, frame.bushings)
        return cls(tuple(model.bushing_names), np.asarray(frame.bushings.point_m, float), operator, dofs,
                   np.asarray(frame.bushings.stiffness, float), stress_free_motions(rig), frame.n_dofs)

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
