"""Nodal loads: forces and moments at nodes, self-equilibrated pairs, point-mass weight."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.contribution import Contribution, dense_entries

__all__ = ["NodalLoads", "PointMasses", "nodal_load_vector", "point_mass_gravity", "point_mass_triplets"]


@dataclass(frozen=True)
class NodalLoads:
    """Forces (N) and moments (N·m) at nodes, in global axes.

    Parameters
    ----------
    node : (n,) int array
    components : (n, 6) array
        Fx, Fy, Fz, Mx, My, Mz for each entry; entries at the same node add up.
    """

    node: np.ndarray
    components: np.ndarray


def nodal_load_vector(loads: NodalLoads, n_dofs: int) -> np.ndarray:
    """Global load vector of nodal forces and moments."""
    vector = np.zeros(n_dofs)
    node = np.asarray(loads.node, dtype=int)
    if node.size:
        dofs = DOFS_PER_NODE * node[:, None] + np.arange(DOFS_PER_NODE)
        np.add.at(vector, dofs.ravel(), np.asarray(loads.components, float).ravel())
    return vector


@dataclass(frozen=True)
class PointMasses:
    """Lumped masses (kg) with rotary inertia about their own axes (kg·m²) at nodes."""

    node: np.ndarray
    mass_kg: np.ndarray
    rotary_inertia_kg_m2: np.ndarray  # (n, 3): Ixx, Iyy, Izz

    def contribution(self, coordinates: np.ndarray, n_dofs: int, gravity_direction) -> Contribution:
        """The masses' weight (:func:`point_mass_gravity`) as load ``"gravity"``; no stiffness."""
        weight = point_mass_gravity(self, np.asarray(gravity_direction, dtype=float), n_dofs)
        return Contribution(loads={"gravity": dense_entries(weight)})

    def mass_contribution(self, coordinates: np.ndarray) -> Contribution:
        """Mass and rotary inertia at their nodes (:func:`point_mass_triplets`)."""
        return Contribution(mass=point_mass_triplets(self))


def point_mass_gravity(masses: PointMasses, acceleration_m_per_s2: np.ndarray, n_dofs: int) -> np.ndarray:
    """Weight m g of each point mass as nodal forces."""
    force = np.asarray(masses.mass_kg, float)[:, None] * np.asarray(acceleration_m_per_s2)[None, :]
    components = np.concatenate([force, np.zeros_like(force)], axis=1)
    return nodal_load_vector(NodalLoads(np.asarray(masses.node, int), components), n_dofs)



def point_mass_triplets(masses: PointMasses):
    """The mass matrix of point masses as COO triplets: m on a node's three translations, its rotary inertia
    (Ixx, Iyy, Izz, about axes through the node) on its three rotations."""
    node = np.asarray(masses.node, dtype=int)
    values = np.concatenate([np.repeat(np.asarray(masses.mass_kg, float)[:, None], 3, axis=1),
                             np.asarray(masses.rotary_inertia_kg_m2, float).reshape(-1, 3)], axis=1)
    dofs = (DOFS_PER_NODE * node[:, None] + np.arange(DOFS_PER_NODE)).ravel()
    return dofs, dofs.copy(), values.ravel()
