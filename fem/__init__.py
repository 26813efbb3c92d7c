"""Finite-element core of rvcoax: 3D Timoshenko beams, bushings, point masses, constraints.

Everything here knows nothing about rigs: it works on node coordinates, element tables and
DOF numbers, in SI units. Each model piece returns COO triplets or load vectors that are
assembled the same way (:mod:`rvcoax.fem.assembly`).
"""

__all__ = ["DOFS_PER_NODE"]

DOFS_PER_NODE = 6
"""Nodal DOFs: ux, uy, uz, rx, ry, rz (translations in m, rotations in rad)."""
