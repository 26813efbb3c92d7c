"""Relative motion and force of the rig's springs in every load case of a sweep.

Every bearing, mount, coupling and joint is a bushing (:mod:`rvcoax.fem.bushing`) between two frame nodes,
or a node and the ground, at a point c reached by rigid arms. Its relative motion is
Δ = B_b u_b − B_a u_a: the motion at c of side b (the shaft of a bearing, the ``to`` end of a
coupling or joint, the part of a mount) minus that of side a (the housing, the ``from`` end, the
ground). The spring exerts diag(k) Δ on side a and the opposite on side b.

A spring may be free of load at a relative motion Δ0 ≠ 0 (a coupling installed with a parallel
offset or angle, a raised mount: :func:`rvcoax.geometry.model.beam.stress_free_motions`); it then exerts
diag(k) (Δ − Δ0). The *deformation* reported here is Δ − Δ0 (from the unloaded geometry) or the
change of Δ since the rest state (from rest, where Δ0 cancels), so that force = diag(k) × deformation
in both references. For a coupling it is its misalignment: parallel offset (translation in y and z)
and angle (rotation about y and z) of the ``to`` hub relative to the ``from`` hub at the coupling
centre. For a bearing, −diag(k) × deformation is the reaction the bearing exerts on its shaft.

In hybrid and solid models the same bushings attach to the reference nodes tied to solid faces
(:mod:`rvcoax.geometry.model.hybrid`), so everything here works on the frame part of the displacement vector at
every fidelity.

The displacements of a case are rebuilt from the sweep's unit responses,
u = Σ_k w_k u_k (:func:`rvcoax.geometry.model.loads.case_weights`); with ``method="direct"`` the sweep solved
each case on its own, which agrees with this superposition to solver precision.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from rvcoax.fem import bushing
from rvcoax.fem.errors import RvcoaxError
from rvcoax.geometry.model.beam import SpringId, housing_bed_group, stress_free_motions
from rvcoax.geometry.model.loads import UNIT_LOADS, case_weights, gear_contact_torques

if TYPE_CHECKING:
    from rvcoax.results.sweep import Sweep

__all__ = ["ConnectionStates", "ConnectionsUnavailableError", "HousingBed", "housing_beds", "REFERENCES", "SpringMotion", "case_displacements",
           "connection_states", "spring_states", "with_nonlinear_laws"]

REFERENCES = ("measured", "unloaded")
"""``measured``: from the state the rig's ``[paths] measured_from`` names (the aligned rig at rest by
default, u − u_rest), as Y and β are; ``unloaded``: from the unloaded geometry (u, self-weight included)."""


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


class ConnectionsUnavailableError(RvcoaxError, ValueError):
    """The sweep cannot give per-case spring states (the message says why)."""


def _from_rest(sweep: Sweep, reference: str) -> bool:
    if reference not in REFERENCES:
        raise ValueError(f"reference must be one of {', '.join(REFERENCES)}, got {reference!r}")
    return reference == "measured" and sweep.rig.paths.measured_from == "aligned_at_rest"


def case_displacements(sweep: Sweep, reference: str = "measured") -> np.ndarray:
    """Displacement vectors of every case, (n_dofs, n_cases), from ``reference`` (see :data:`REFERENCES`).

    A linear sweep superposes its unit responses; a nonlinear one (bearings with radial clearance or
    ball bearings from geometry, solved case by case) holds each case's displacement as measured and
    the rest state."""
    from_rest = _from_rest(sweep, reference)
    if sweep.unit_displacements is None:
        if sweep.case_displacements is None or sweep.rest_displacement is None:
            raise ConnectionsUnavailableError(
                "spring forces and coupling misalignments need the sweep's unit responses (a linear model) or, "
                "for bearings with radial clearance or ball bearings from geometry (nonlinear), each case's "
                "displacement and the rest state; this sweep holds neither")
        measured = np.asarray(sweep.case_displacements, dtype=float)
        if sweep.rig.paths.measured_from == "aligned_at_rest" and not from_rest:
            return measured + np.asarray(sweep.rest_displacement, dtype=float)[:, None]
        return measured
    unit = np.asarray(sweep.unit_displacements)
    contact = gear_contact_torques(sweep.rig)
    weights = np.array([[case_weights(c.case.input_torque_Nm, c.case.output_torque_Nm, include_rest=not from_rest,
                                      contact_torques_Nm=contact)[k] for k in UNIT_LOADS] for c in sweep.cases])
    return unit @ weights.T


def connection_states(sweep: Sweep, reference: str = "measured") -> ConnectionStates:
    """Relative motion and force of every spring of the sweep's rig in every case.

    In a nonlinear sweep each bearing with radial clearance or from ball geometry exerts its own law
    F(Δ) at the case's converged state (:meth:`rvcoax.geometry.model.nonlinear_bearings.NonlinearBearings.laws`),
    −F(Δ) on its shaft from the unloaded geometry and −(F(Δ) − F(Δ_rest)) from rest, and its operating
    stiffness is the tangent ∂F/∂Δ there; every other spring is linear."""
    from_rest = _from_rest(sweep, reference)
    states = spring_states(sweep.frame, sweep.rig, case_displacements(sweep, reference), from_rest=from_rest)
    law = sweep.nonlinear_bearings
    if law is None:
        return states
    rest = np.asarray(sweep.rest_displacement, dtype=float) if from_rest else None
    return with_nonlinear_laws(states, law, case_displacements(sweep, "unloaded"), rest)


def with_nonlinear_laws(states: ConnectionStates, law, unloaded: np.ndarray,
                        rest: np.ndarray | None = None) -> ConnectionStates:
    """``states`` with each nonlinear bearing's force and operating stiffness taken from its own law.

    Parameters
    ----------
    states : ConnectionStates
        The linear spring states of the cases (every bearing on its linear reference spring).
    law : NonlinearBearings
        The sweep's condensed nonlinear bearings.
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
