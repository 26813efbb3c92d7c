"""The assembled structural model: nodes, pieces, constraints and their global matrices."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import DOFS_PER_NODE, beam, bushing, loads
from rvcoax.fem.assembly import assemble_matrix
from rvcoax.fem.constraints import RigidLinks, elimination_matrix, rigid_link_equations

__all__ = ["StructuralModel", "constraint_elimination", "gravity_load_vector", "stiffness_matrix"]


def _no_links() -> RigidLinks:
    return RigidLinks(np.zeros(0, int), np.zeros(0, int))


def _no_masses() -> loads.PointMasses:
    return loads.PointMasses(np.zeros(0, int), np.zeros(0), np.zeros((0, 3)))


@dataclass(frozen=True, eq=False)
class StructuralModel:
    """Everything that makes the stiffness of a frame model (SI units).

    Parameters
    ----------
    coordinates : (n_nodes, 3) array
        Node positions in m.
    beams : BeamElements
    bushings : Bushings
    point_masses : PointMasses
    rigid_links : RigidLinks
    fixed_dofs : (k,) int array
        DOFs held at zero.
    node_group : (n_nodes,) array of str
        The part each node belongs to; used to name unsupported parts.
    """

    coordinates: np.ndarray
    beams: beam.BeamElements
    bushings: bushing.Bushings
    point_masses: loads.PointMasses = field(default_factory=_no_masses)
    rigid_links: RigidLinks = field(default_factory=_no_links)
    fixed_dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    node_group: np.ndarray | None = None

    @property
    def n_nodes(self) -> int:
        return int(self.coordinates.shape[0])

    @property
    def n_dofs(self) -> int:
        return DOFS_PER_NODE * self.n_nodes


def stiffness_matrix(model: StructuralModel) -> sp.csr_matrix:
    """Global stiffness of all beams and bushings (constraints not applied)."""
    return assemble_matrix(
        model.n_dofs,
        [
            beam.stiffness_triplets(model.coordinates, model.beams),
            bushing.stiffness_triplets(model.coordinates, model.bushings),
        ],
    )


def constraint_elimination(model: StructuralModel):
    """Elimination matrix T (u = T q) and the independent DOF numbers."""
    equations = rigid_link_equations(model.coordinates, model.rigid_links)
    return elimination_matrix(model.n_dofs, model.fixed_dofs, equations)


def gravity_load_vector(model: StructuralModel, acceleration_m_s2) -> np.ndarray:
    """Weight of beams (consistent) and point masses as a global load vector."""
    g = np.asarray(acceleration_m_s2, dtype=float)
    return beam.gravity_load(model.coordinates, model.beams, g, model.n_dofs) + loads.point_mass_gravity(
        model.point_masses, g, model.n_dofs
    )
