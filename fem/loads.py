"""Nodal loads: forces and moments at nodes, self-equilibrated pairs, point-mass weight."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rvcoax.fem import DOFS_PER_NODE

__all__ = ["NodalLoads", "PointMasses", "nodal_load_vector", "point_mass_gravity"]


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


def point_mass_gravity(masses: PointMasses, acceleration_m_per_s2: np.ndarray, n_dofs: int) -> np.ndarray:
    """Weight m g of each point mass as nodal forces."""
    force = np.asarray(masses.mass_kg, float)[:, None] * np.asarray(acceleration_m_per_s2)[None, :]
    components = np.concatenate([force, np.zeros_like(force)], axis=1)
    return nodal_load_vector(NodalLoads(np.asarray(masses.node, int), components), n_dofs)

