"""Reactions at the ground and the global equilibrium check."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fem import DOFS_PER_NODE, bushing


def resultant(coordinates: np.ndarray, nodal_vector: np.ndarray) -> np.ndarray:
    """Total force and moment about the origin of a nodal force vector (6,)."""
    v = np.asarray(nodal_vector).reshape(-1, DOFS_PER_NODE)
    force = v[:, :3].sum(axis=0)
    moment = (np.cross(coordinates, v[:, :3]) + v[:, 3:]).sum(axis=0)
    return np.concatenate([force, moment])


@dataclass(frozen=True)
class Equilibrium:
    """Applied and reaction resultants (force N, moment N·m about the origin)."""

    applied: np.ndarray
    reactions: np.ndarray
    relative_error: float


def ground_reactions(model, stiffness, displacement, load) -> tuple[np.ndarray, np.ndarray]:
    """Per ground bushing force/moment exerted by the ground (n, 6), and the fixed-DOF reactions (n_dofs,)."""
    grounded = np.asarray(model.bushings.node_a) == bushing.GROUND
    # spring_forces is what a spring exerts on its node a (here the ground); the ground
    # therefore pushes the structure with the opposite
    forces = np.where(grounded[:, None], -bushing.spring_forces(model.coordinates, model.bushings, displacement), 0.0)
    fixed = np.zeros(model.n_dofs)
    dofs = np.asarray(model.fixed_dofs, dtype=int)
    if dofs.size:
        fixed[dofs] = (stiffness @ displacement - load)[dofs]
    return forces, fixed


def check_equilibrium(model, stiffness, displacement, load) -> Equilibrium:
    """Compare the resultant of applied loads with the resultant of all ground reactions."""
    bushing_forces, fixed = ground_reactions(model, stiffness, displacement, load)
    grounded = np.asarray(model.bushings.node_a) == bushing.GROUND
    points = np.asarray(model.bushings.point_m)[grounded]
    bf = bushing_forces[grounded]
    reaction = resultant(model.coordinates, fixed)
    reaction[:3] += bf[:, :3].sum(axis=0)
    reaction[3:] += (np.cross(points, bf[:, :3]) + bf[:, 3:]).sum(axis=0)
    applied = resultant(model.coordinates, load)
    magnitude = np.abs(np.asarray(load).reshape(-1, DOFS_PER_NODE))
    extent = max(float(np.ptp(model.coordinates, axis=0).max()), 1.0)
    # force scale includes applied moments over the model size: a pure-moment load has reaction
    # forces that are zero only up to rounding
    scale = max(magnitude[:, :3].sum() + magnitude[:, 3:].sum() / extent, 1e-300)
    total = applied + reaction
    error = max(np.abs(total[:3]).max() / scale, np.abs(total[3:]).max() / (scale * extent))
    return Equilibrium(applied, reaction, float(error))
