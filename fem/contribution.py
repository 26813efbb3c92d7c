"""What a model piece adds to the system, and what an element type of a frame model provides.

:class:`Contribution` is the one currency of assembly: stiffness triplets or a stiffness block, mass
triplets or a mass block, load entries by load name, constraint rows and fixed DOFs, all in global DOF
numbers. :func:`rvcoax.fem.pieces.assemble` sums any list of them.

:class:`ElementGroup` is the one thing an element type of a frame model is: a table of elements (a frozen
dataclass of arrays, one row per element) with two methods, its stiffness-and-loads contribution and its
mass contribution. A :class:`rvcoax.fem.model.StructuralModel` holds any number of such tables and
:func:`rvcoax.fem.pieces.frame_contributions` asks each for its contributions: a new element type is
declared once, in its own module, and nothing else enumerates the element types.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np
import scipy.sparse as sp

__all__ = ["Contribution", "ElementGroup", "dense_entries"]


def _no_dofs() -> np.ndarray:
    return np.zeros(0, dtype=int)


@dataclass(frozen=True, eq=False)
class Contribution:
    """What one model piece adds to the system.

    Attributes
    ----------
    stiffness : (rows, cols, values) or None
        Stiffness triplets in global DOF numbers (duplicates are summed).
    loads : mapping
        Load name → (dofs, values): entries added to that load vector (a DOF may repeat: every entry adds).
    equations : mapping
        Multi-point constraints u_dependent = Σ c u: dependent DOF → {DOF: coefficient}.
    fixed_dofs : array of int
        DOFs held at zero.
    block : (offset, csr_matrix) or None
        A square stiffness matrix (a solid's, assembled in place: :func:`rvcoax.fem.solid.stiffness_matrix`)
        whose unknowns start at ``offset``; blocks of different pieces do not overlap.
    mass : (rows, cols, values) or None
        Mass triplets in global DOF numbers (kg, kg·m, kg·m²): the piece's mass form.
    mass_block : (offset, csr_matrix) or None
        A square mass matrix placed like ``block`` (a solid's, :func:`rvcoax.fem.solid.mass_matrix`).
    """

    stiffness: tuple | None = None
    loads: Mapping[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    equations: Mapping[int, Mapping[int, float]] = field(default_factory=dict)
    fixed_dofs: np.ndarray = field(default_factory=_no_dofs)
    block: tuple[int, sp.csr_matrix] | None = None
    mass: tuple | None = None
    mass_block: tuple[int, sp.csr_matrix] | None = None


def dense_entries(vector: np.ndarray, offset: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A load vector on the DOFs ``offset, offset + 1, …`` as load entries ``(dofs, values)``."""
    return np.arange(offset, offset + vector.size), vector


@runtime_checkable
class ElementGroup(Protocol):
    """An element type of a frame model: a table of elements that knows what it adds to the system.

    Implemented by :class:`rvcoax.fem.beam.BeamElements`, :class:`rvcoax.fem.bushing.Bushings`,
    :class:`rvcoax.fem.loads.PointMasses` and :class:`rvcoax.fem.constraints.RigidLinks`; a new element type
    implements it in its own module and is put into a :class:`rvcoax.fem.model.StructuralModel` like them.
    """

    def contribution(self, coordinates: np.ndarray, n_dofs: int, gravity_direction: np.ndarray) -> Contribution:
        """Stiffness, loads and constraint rows of the whole table, for nodes at ``coordinates`` (n_nodes, 3) m.

        ``gravity_direction`` (3,) scales the load ``"gravity"``: a unit vector gives the weight per m/s²,
        an acceleration (m/s²) the weight itself. A type without weight or stiffness leaves them out.
        """

    def mass_contribution(self, coordinates: np.ndarray) -> Contribution | None:
        """The mass form of the whole table (mass triplets), or None for a massless type (a spring, a link)."""
