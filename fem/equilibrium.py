"""Reactions at the ground and the global equilibrium check.

Works on any DOF layout: each DOF has a position and a component (0–2 force along x/y/z,
3–5 moment about x/y/z), so frame nodes (six DOFs) and solid nodes (three DOFs) mix freely.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from rvcoax.fem import DOFS_PER_NODE, bushing

__all__ = ["DofTable", "Equilibrium", "check_equilibrium", "frame_dof_table", "ground_reactions", "resultant",
           "resultant_of"]


@dataclass(frozen=True, eq=False)
class DofTable:
    """Where each DOF sits (m) and which component it is (0–5)."""

    position: np.ndarray
    component: np.ndarray

    @functools.cached_property
    def extent_m(self) -> float:
        """The largest extent of the DOF positions along x, y or z (m); at least 1 m (the moment scale of
        :func:`check_equilibrium`)."""
        return max(float(np.ptp(self.position, axis=0).max()), 1.0) if len(self.position) else 1.0

    @functools.cached_property
    def _by_component(self) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...]]:
        """The DOFs of each component (0–5), and the positions (3, k) of the force DOFs (components 0–2). A sweep checks
        the equilibrium of every case on one table: found once, not per vector."""
        dofs = tuple(np.flatnonzero(self.component == c) for c in range(6))
        return dofs, tuple(np.ascontiguousarray(self.position[dofs[c]].T) for c in range(3))

    @functools.cached_property
    def _force_and_moment(self) -> tuple[np.ndarray, np.ndarray]:
        """Masks of the force DOFs (components 0–2) and of the moments: the load scale of :func:`check_equilibrium`
        (every case of a sweep on one table)."""
        return self.component < 3, self.component >= 3

    def restricted(self, dofs: np.ndarray) -> DofTable:
        """The table of the DOFs ``dofs`` alone (a vector's resultant over only the entries that may be nonzero)."""
        return DofTable(self.position[dofs], self.component[dofs])


def frame_dof_table(coordinates: np.ndarray) -> DofTable:
    """Six DOFs per node, in node order."""
    return DofTable(np.repeat(coordinates, DOFS_PER_NODE, axis=0),
                    np.tile(np.arange(DOFS_PER_NODE), coordinates.shape[0]))


def resultant_of(table: DofTable, vector: np.ndarray) -> np.ndarray:
    """Total force and moment about the origin of a vector of DOF forces/moments (6,).

    The moment of a force f_c (component c) at position p is p × f_c e_c: a force along x at (x, y, z) gives
    (0, z f, −y f), along y (−z f, 0, x f), along z (y f, −x f, 0).
    """
    v = np.asarray(vector)
    dofs, at = table._by_component
    f = [v[dofs[c]] for c in range(3)]
    force = np.array([f[c].sum() for c in range(3)])

    def moment_of(c: int, axis: int) -> float:  # Σ p_axis f_c (multiplied and summed: no threaded BLAS call)
        return float(np.sum(at[c][axis] * f[c]))

    moment = np.array([moment_of(2, 1) - moment_of(1, 2), moment_of(0, 2) - moment_of(2, 0),
                       moment_of(1, 0) - moment_of(0, 1)])
    moment += [v[dofs[3 + axis]].sum() for axis in range(3)]
    return np.concatenate([force, moment])


def resultant(coordinates: np.ndarray, nodal_vector: np.ndarray) -> np.ndarray:
    """Total force and moment about the origin of a six-DOF nodal vector (6,)."""
    return resultant_of(frame_dof_table(coordinates), nodal_vector)


@dataclass(frozen=True)
class Equilibrium:
    """Applied and reaction resultants (force N, moment N·m about the origin)."""

    applied: np.ndarray
    reactions: np.ndarray
    relative_error: float


def _bushing_reactions(model, displacement) -> np.ndarray:
    """Per ground bushing the force/moment exerted by the ground (n, 6); zero for the others."""
    frame = displacement[: model.n_dofs]
    grounded = np.asarray(model.bushings.node_a) == bushing.GROUND
    # spring_forces is what a spring exerts on its node a (here the ground); the ground
    # therefore pushes the structure with the opposite
    return np.where(grounded[:, None], -bushing.spring_forces(model.coordinates, model.bushings, frame), 0.0)


def ground_reactions(model, stiffness, displacement, load, unbalance=None) -> tuple[np.ndarray, np.ndarray]:
    """Per ground bushing force/moment exerted by the ground (n, 6), and the fixed-DOF reactions (n_dofs,).

    ``unbalance``: K u − f where the caller has it already (else it is formed when there are fixed DOFs)."""
    forces = _bushing_reactions(model, displacement)
    fixed = np.zeros(displacement.shape[0])
    dofs = np.asarray(model.fixed_dofs, dtype=int)
    if dofs.size:
        fixed[dofs] = (stiffness @ displacement - load if unbalance is None else unbalance)[dofs]
    return forces, fixed


def check_equilibrium(model, stiffness, displacement, load, dofs: DofTable | None = None, *,  # noqa: PLR0913
                      unbalance=None) -> Equilibrium:
    """Compare the resultant of applied loads with the resultant of all ground reactions.

    ``model`` is the frame (:class:`rvcoax.fem.model.StructuralModel`) holding the ground springs and fixed
    DOFs; ``dofs`` describes the whole DOF vector when it holds more than the frame (solids); ``unbalance`` is
    K u − f where the caller has formed it, at least at the fixed DOFs: only those entries, their reactions, are read.
    """
    table = dofs if dofs is not None else frame_dof_table(model.coordinates)
    bushing_forces = _bushing_reactions(model, displacement)
    # the fixed DOFs' reactions (K u − f there) summed over those DOFs alone, not over a vector of zeros elsewhere
    fixed = np.asarray(model.fixed_dofs, dtype=int)
    if fixed.size:
        values = (stiffness @ displacement - load if unbalance is None else unbalance)[fixed]
        reaction = resultant_of(table.restricted(fixed), values)
    else:
        reaction = np.zeros(6)
    grounded = np.asarray(model.bushings.node_a) == bushing.GROUND
    points = np.asarray(model.bushings.point_m)[grounded]
    bf = bushing_forces[grounded]
    reaction[:3] += bf[:, :3].sum(axis=0)
    reaction[3:] += (np.cross(points, bf[:, :3]) + bf[:, 3:]).sum(axis=0)
    applied = resultant_of(table, load)
    magnitude = np.abs(np.asarray(load))
    is_force, is_moment = table._force_and_moment
    forces = magnitude[is_force].sum()
    moments = magnitude[is_moment].sum()
    extent = table.extent_m
    # force scale includes applied moments over the model size: a pure-moment load has reaction
    # forces that are zero only up to rounding
    scale = max(forces + moments / extent, 1e-300)
    total = applied + reaction
    error = max(np.abs(total[:3]).max() / scale, np.abs(total[3:]).max() / (scale * extent))
    return Equilibrium(applied, reaction, float(error))
