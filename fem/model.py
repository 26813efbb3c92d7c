"""A frame model: nodes, any number of element groups and fixed DOFs (data only).

An element group is a table of one element type (:class:`rvcoax.fem.contribution.ElementGroup`: beams,
bushings, point masses, rigid links, or a type of your own) that says itself what it adds to the system.
The model holds the groups in assembly order and knows none of their types: its pieces enter a system
through :func:`rvcoax.fem.pieces.frame_contributions` and :func:`rvcoax.fem.pieces.assemble`, like every
other model piece.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rvcoax.fem import DOFS_PER_NODE, beam, bushing, loads
from rvcoax.fem.constraints import RigidLinks
from rvcoax.fem.contribution import ElementGroup

__all__ = ["StructuralModel"]


@dataclass(frozen=True, eq=False, init=False)
class StructuralModel:
    """Everything that makes the stiffness and mass of a frame model (SI units).

    ``StructuralModel(coordinates, beams, bushings, links, fixed_dofs=dofs)``: the element groups in assembly
    order; ``point_masses=hubs`` (the rig builder's form) is appended after them.

    Parameters
    ----------
    coordinates : (n_nodes, 3) array
        Node positions in m.
    *tables : ElementGroup
        Element tables, at most one of each type (:meth:`group` finds a table by its type).
    groups : tuple of ElementGroup, optional
        More tables, after ``tables`` (the field's name: ``dataclasses.replace`` works on a model).
    point_masses : PointMasses, optional
        One more table, after ``tables`` and ``groups``.
    fixed_dofs : (k,) int array
        DOFs held at zero.
    node_group : (n_nodes,) array of str
        The part each node belongs to; used to name unsupported parts.
    """

    coordinates: np.ndarray
    groups: tuple[ElementGroup, ...]
    fixed_dofs: np.ndarray
    node_group: np.ndarray | None

    def __init__(self, coordinates: np.ndarray, *tables: ElementGroup, groups: tuple[ElementGroup, ...] = (),
                 point_masses: loads.PointMasses | None = None, fixed_dofs: np.ndarray | None = None,
                 node_group: np.ndarray | None = None) -> None:
        groups = (*tables, *groups, *(() if point_masses is None else (point_masses,)))
        for g in groups:
            if not isinstance(g, ElementGroup):
                raise TypeError(f"{type(g).__name__} is not an element group (no contribution/mass_contribution)")
        kinds = [type(g) for g in groups]
        if len(set(kinds)) != len(kinds):
            raise ValueError(f"two element groups of one type: {[k.__name__ for k in kinds]}")
        object.__setattr__(self, "coordinates", coordinates)
        object.__setattr__(self, "groups", groups)
        object.__setattr__(self, "fixed_dofs", np.zeros(0, int) if fixed_dofs is None else fixed_dofs)
        object.__setattr__(self, "node_group", node_group)

    @property
    def n_nodes(self) -> int:
        return int(self.coordinates.shape[0])

    @property
    def n_dofs(self) -> int:
        return DOFS_PER_NODE * self.n_nodes

    def group(self, kind: type, default=None):
        """The element table of type ``kind``, or ``default`` when the model has none."""
        return next((g for g in self.groups if type(g) is kind), default)

    def with_group(self, table: ElementGroup) -> StructuralModel:
        """This model with ``table`` in place of the table of its type (appended when there is none)."""
        kind = type(table)
        groups = [table if type(g) is kind else g for g in self.groups]
        if self.group(kind) is None:
            groups.append(table)
        return StructuralModel(self.coordinates, *groups, fixed_dofs=self.fixed_dofs, node_group=self.node_group)

    # The rig's own element types by name (a model without one of them reads as an empty table).
    @property
    def beams(self) -> beam.BeamElements:
        found = self.group(beam.BeamElements)
        if found is None:
            none = np.zeros(0)
            return beam.BeamElements(connectivity=np.zeros((0, 2), int), area_m2=none, second_moment_m4=none,
                                     polar_moment_m4=none, shear_coefficient=none, youngs_modulus_Pa=none,
                                     shear_modulus_Pa=none, density_kg_per_m3=none, reference_vector=np.zeros((0, 3)))
        return found

    @property
    def bushings(self) -> bushing.Bushings:
        found = self.group(bushing.Bushings)
        return bushing.Bushings(np.zeros(0, int), np.zeros(0, int), np.zeros((0, 3)), np.zeros((0, 6))) \
            if found is None else found

    @property
    def point_masses(self) -> loads.PointMasses:
        found = self.group(loads.PointMasses)
        return loads.PointMasses(np.zeros(0, int), np.zeros(0), np.zeros((0, 3))) if found is None else found

    @property
    def rigid_links(self) -> RigidLinks:
        found = self.group(RigidLinks)
        return RigidLinks(np.zeros(0, int), np.zeros(0, int)) if found is None else found
