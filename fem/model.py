"""A frame model: nodes, beams, bushings, point masses, rigid links and fixed DOFs (data only).

Its pieces enter a system through :func:`rvcoax.fem.pieces.frame_contributions` and
:func:`rvcoax.fem.pieces.assemble`, like every other model piece.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rvcoax.fem import DOFS_PER_NODE, beam, bushing, loads
from rvcoax.fem.constraints import RigidLinks

__all__ = ["StructuralModel"]


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
