"""One interface for every model piece: what it adds to the system, in global DOF numbers.

A piece (beams, bushings, point masses, rigid links and fixed DOFs, a solid part, a tie between a
reference node and a solid face) returns a :class:`Contribution`: stiffness triplets, load entries
by load name, and constraint rows. :func:`assemble` sums any list of them into the system, in the
order given (so that the result does not depend on how the pieces were grouped). The beam, hybrid
and solid rig models, calibration and a Monte Carlo sample that swaps springs all go through it.

Loads are pieces too: nodal forces (:func:`nodal_load_contribution`) and the springs' prestrain
(:func:`prestrain_contribution`) under the load name the caller gives, summed by :func:`load_vectors`.

Matrices, vectors and DOF numbers only: the rig is unknown here. The one load name the pieces
themselves give is ``"gravity"``: the weight per m/s² of acceleration along the direction asked for.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import DOFS_PER_NODE, beam, bushing, loads, solid
from rvcoax.fem.assembly import assemble_matrix, block_diagonal
from rvcoax.fem.constraints import elimination_matrix, rigid_link_equations

__all__ = ["AssembledSystem", "Contribution", "assemble", "assemble_frame", "beam_contribution", "bushing_contribution",
           "constraint_contribution", "dense_load_contribution", "frame_contributions", "load_vectors", "nodal_load_contribution",
           "point_mass_contribution", "prestrain_contribution", "solid_contribution", "tie_contribution"]


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
    """

    stiffness: tuple | None = None
    loads: Mapping[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    equations: Mapping[int, Mapping[int, float]] = field(default_factory=dict)
    fixed_dofs: np.ndarray = field(default_factory=_no_dofs)
    block: tuple[int, sp.csr_matrix] | None = None


@dataclass(frozen=True, eq=False)
class AssembledSystem:
    """The sum of a list of contributions.

    Attributes
    ----------
    n_dofs : int
    stiffness : csr_matrix
        K (n × n), constraints not applied.
    loads : dict
        Load name → vector of length n.
    equations : dict
        Every constraint row, later pieces overriding earlier ones for the same dependent DOF.
    fixed_dofs : array of int
    """

    n_dofs: int
    stiffness: sp.csr_matrix
    loads: dict
    equations: dict
    fixed_dofs: np.ndarray

    @functools.cached_property
    def _reduction(self) -> tuple[sp.csr_matrix, np.ndarray]:
        return elimination_matrix(self.n_dofs, self.fixed_dofs, self.equations)

    @property
    def elimination(self) -> sp.csr_matrix:
        """T (n × m) with u = T q: the fixed DOFs and constraint rows eliminated."""
        return self._reduction[0]

    @property
    def free_dofs(self) -> np.ndarray:
        """The m independent DOFs q (T's columns), in increasing order."""
        return self._reduction[1]


def assemble(n_dofs: int, contributions: Iterable[Contribution]) -> AssembledSystem:
    """Sum ``contributions`` (in their order) into one system of ``n_dofs`` unknowns."""
    contributions = list(contributions)
    stiffness = _stiffness(n_dofs, contributions)
    equations: dict[int, Mapping[int, float]] = {}
    for c in contributions:
        equations.update(c.equations)
    fixed = np.concatenate([np.asarray(c.fixed_dofs, dtype=int) for c in contributions] or [_no_dofs()])
    return AssembledSystem(int(n_dofs), stiffness, load_vectors(n_dofs, contributions), equations, fixed)


def load_vectors(n_dofs: int, contributions: Iterable[Contribution]) -> dict[str, np.ndarray]:
    """The load entries of ``contributions`` summed (in their order) into one vector per load name.

    :func:`assemble` sums loads this way; a model whose loads change without its stiffness (calibration,
    a Monte Carlo sample of load parameters) calls it alone.
    """
    vectors: dict[str, np.ndarray] = {}
    for c in contributions:
        for name, (dofs, values) in c.loads.items():
            np.add.at(vectors.setdefault(name, np.zeros(n_dofs)), dofs, values)
    return vectors


def _stiffness(n_dofs: int, contributions: list[Contribution]) -> sp.csr_matrix:
    """Triplets summed, then the blocks placed: side by side when the triplets stay before the first block
    (a frame and its solids: the matrix is written once), else added."""
    triplets = assemble_matrix(n_dofs, [c.stiffness for c in contributions if c.stiffness is not None])
    blocks = [c.block for c in contributions if c.block is not None]
    if not blocks:
        return triplets
    first = min(offset for offset, _ in blocks)
    if triplets.nnz == 0 or (triplets.indptr[first] == triplets.nnz and triplets.indices.max() < first):
        head = triplets[:first, :first].tocsr()
        del triplets
        return block_diagonal(n_dofs, [(0, head), *blocks]) if first else block_diagonal(n_dofs, blocks)
    return (triplets + block_diagonal(n_dofs, blocks)).tocsr()


def _dense(vector: np.ndarray, offset: int = 0) -> tuple[np.ndarray, np.ndarray]:
    return np.arange(offset, offset + vector.size), vector


def beam_contribution(model, gravity_direction) -> Contribution:
    """The beams of a frame model (:class:`rvcoax.fem.model.StructuralModel`): stiffness and consistent weight."""
    weight = beam.gravity_load(model.coordinates, model.beams, np.asarray(gravity_direction, dtype=float),
                               model.n_dofs)
    return Contribution(beam.stiffness_triplets(model.coordinates, model.beams), {"gravity": _dense(weight)})


def bushing_contribution(model) -> Contribution:
    """The six-component springs of a frame model."""
    return Contribution(bushing.stiffness_triplets(model.coordinates, model.bushings))


def point_mass_contribution(model, gravity_direction) -> Contribution:
    """The point masses of a frame model: their weight."""
    weight = loads.point_mass_gravity(model.point_masses, np.asarray(gravity_direction, dtype=float), model.n_dofs)
    return Contribution(loads={"gravity": _dense(weight)})


def nodal_load_contribution(name: str, nodal: loads.NodalLoads) -> Contribution:
    """Forces and moments at frame nodes (:class:`rvcoax.fem.loads.NodalLoads`) as entries of load ``name``."""
    node = np.asarray(nodal.node, dtype=int)
    dofs = (DOFS_PER_NODE * node[:, None] + np.arange(DOFS_PER_NODE)).ravel()
    return Contribution(loads={name: (dofs, np.asarray(nodal.components, dtype=float).ravel())})


def dense_load_contribution(name: str, vector: np.ndarray, offset: int = 0) -> Contribution:
    """A load given as a vector on the DOFs ``offset, offset + 1, …`` (a thermal initial strain, a face traction)."""
    return Contribution(loads={name: _dense(np.asarray(vector, dtype=float), offset)})


def prestrain_contribution(model, stress_free: np.ndarray, name: str = "prestrain") -> Contribution:
    """The springs of a frame model pushing their nodes towards their stress-free relative motion Δ0 (n, 6)."""
    return Contribution(loads={name: bushing.prestrain_entries(model.coordinates, model.bushings, stress_free)})


def constraint_contribution(model) -> Contribution:
    """The rigid links and fixed DOFs of a frame model."""
    return Contribution(equations=rigid_link_equations(model.coordinates, model.rigid_links),
                        fixed_dofs=np.asarray(model.fixed_dofs, dtype=int))


def frame_contributions(model, gravity_direction) -> list[Contribution]:
    """Every piece of a frame model, in assembly order: beams, bushings, point masses, constraints.

    The one list of a frame's element types: a new one (a field of :class:`rvcoax.fem.model.StructuralModel`)
    is added here, and every frame model (the rig's, the checks before a solve, the exports) assembles it.
    ``gravity_direction`` scales the load ``"gravity"``: a unit vector gives the weight per m/s², an
    acceleration (m/s²) the weight itself.
    """
    return [beam_contribution(model, gravity_direction), bushing_contribution(model),
            point_mass_contribution(model, gravity_direction), constraint_contribution(model)]


def assemble_frame(model, gravity_direction=(0.0, 0.0, 0.0)) -> AssembledSystem:
    """A frame model alone (:func:`frame_contributions`) summed by :func:`assemble`."""
    return assemble(model.n_dofs, frame_contributions(model, gravity_direction))


def solid_contribution(basis, youngs_modulus_Pa: float, poisson: float, density_kg_per_m3: float, dof_offset: int,  # noqa: PLR0913
                       *, gravity_direction) -> Contribution:
    """A solid part (P2 tetrahedra) whose DOFs start at ``dof_offset``: stiffness and body weight."""
    weight = solid.body_force_vector(basis, density_kg_per_m3, np.asarray(gravity_direction, dtype=float))
    return Contribution(loads={"gravity": _dense(weight, dof_offset)},
                        block=(dof_offset, solid.stiffness_matrix(basis, youngs_modulus_Pa, poisson)))


def tie_contribution(equations: Mapping[int, Mapping[int, float]]) -> Contribution:
    """A tie between a reference node and a solid face (:mod:`rvcoax.fem.ties` gives its rows)."""
    return Contribution(equations=equations)
