"""One interface for every model piece: what it adds to the system, in global DOF numbers.

A piece (a frame model's element groups and fixed DOFs, a solid part, a tie between a reference node and
a solid face) returns a :class:`Contribution` (:mod:`rvcoax.fem.contribution`): stiffness triplets, load
entries by load name, and constraint rows; its mass form (a frame's :func:`frame_mass_contributions`,
:func:`solid_mass_contribution`, a condensed housing's Guyan mass) is a Contribution too, carrying mass
triplets or a mass block, summed by the same :func:`assemble`. :func:`assemble` sums any list of them into
the system, in the order given (so that the result does not depend on how the pieces were grouped).
A frame's element types (beams, bushings, point masses, rigid links, or a new one) each say what they add
(:class:`rvcoax.fem.contribution.ElementGroup`): nothing here enumerates them. The beam, hybrid
and solid rig models, calibration and a Monte Carlo sample that swaps springs all go through it.

Loads are pieces too: nodal forces (:func:`nodal_load_contribution`) and the springs' prestrain
(:func:`prestrain_contribution`) under the load name the caller gives, summed by :func:`load_vectors`.

Matrices, vectors and DOF numbers only: the rig is unknown here. The one load name the pieces
themselves give is ``"gravity"``: the weight per m/s² of acceleration along the direction asked for.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import DOFS_PER_NODE, bushing, loads, solid
from rvcoax.fem.assembly import assemble_matrix, block_diagonal
from rvcoax.fem.constraints import elimination_matrix
from rvcoax.fem.contribution import Contribution, dense_entries

__all__ = ["AssembledSystem", "Contribution", "assemble", "assemble_frame", "beam_contribution", "bushing_contribution",
           "constraint_contribution", "dense_load_contribution", "frame_contributions", "load_vectors", "nodal_load_contribution",
           "point_mass_contribution", "prestrain_contribution", "solid_contribution", "tie_contribution",
           "beam_mass_contribution", "frame_mass_contributions", "point_mass_mass_contribution",
           "solid_mass_contribution"]


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
    mass : csr_matrix or None
        M (n × n) from the pieces' mass forms; None when no piece has one (a static model).
    """

    n_dofs: int
    stiffness: sp.csr_matrix
    loads: dict
    equations: dict
    fixed_dofs: np.ndarray
    mass: sp.csr_matrix | None = None

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
    stiffness = _summed(n_dofs, [c.stiffness for c in contributions], [c.block for c in contributions])
    has_mass = any(c.mass is not None or c.mass_block is not None for c in contributions)
    mass = _summed(n_dofs, [c.mass for c in contributions], [c.mass_block for c in contributions]) if has_mass else None
    equations: dict[int, Mapping[int, float]] = {}
    for c in contributions:
        equations.update(c.equations)
    fixed = np.concatenate([np.asarray(c.fixed_dofs, dtype=int) for c in contributions] or [np.zeros(0, dtype=int)])
    return AssembledSystem(n_dofs=int(n_dofs), stiffness=stiffness, loads=load_vectors(n_dofs, contributions),
                           equations=equations, fixed_dofs=fixed, mass=mass)


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


def _summed(n_dofs: int, triplet_pieces: list, block_pieces: list) -> sp.csr_matrix:
    """Triplets summed, then the blocks placed: side by side when the triplets stay before the first block
    (a frame and its solids: the matrix is written once), else added. Stiffness and mass alike."""
    triplets = assemble_matrix(n_dofs, [t for t in triplet_pieces if t is not None])
    blocks = [b for b in block_pieces if b is not None]
    if not blocks:
        return triplets
    first = min(offset for offset, _ in blocks)
    if triplets.nnz == 0 or (triplets.indptr[first] == triplets.nnz and triplets.indices.max() < first):
        head = triplets[:first, :first].tocsr()
        del triplets
        return block_diagonal(n_dofs, [(0, head), *blocks]) if first else block_diagonal(n_dofs, blocks)
    return (triplets + block_diagonal(n_dofs, blocks)).tocsr()


def beam_contribution(model, gravity_direction) -> Contribution:
    """The beams of a frame model (:class:`rvcoax.fem.model.StructuralModel`): stiffness and consistent weight."""
    return model.beams.contribution(model.coordinates, model.n_dofs, gravity_direction)


def bushing_contribution(model) -> Contribution:
    """The six-component springs of a frame model."""
    return model.bushings.contribution(model.coordinates, model.n_dofs, (0.0, 0.0, 0.0))


def point_mass_contribution(model, gravity_direction) -> Contribution:
    """The point masses of a frame model: their weight."""
    return model.point_masses.contribution(model.coordinates, model.n_dofs, gravity_direction)


def nodal_load_contribution(name: str, nodal: loads.NodalLoads) -> Contribution:
    """Forces and moments at frame nodes (:class:`rvcoax.fem.loads.NodalLoads`) as entries of load ``name``."""
    node = np.asarray(nodal.node, dtype=int)
    dofs = (DOFS_PER_NODE * node[:, None] + np.arange(DOFS_PER_NODE)).ravel()
    return Contribution(loads={name: (dofs, np.asarray(nodal.components, dtype=float).ravel())})


def dense_load_contribution(name: str, vector: np.ndarray, offset: int = 0) -> Contribution:
    """A load given as a vector on the DOFs ``offset, offset + 1, …`` (a thermal initial strain, a face traction)."""
    return Contribution(loads={name: dense_entries(np.asarray(vector, dtype=float), offset)})


def prestrain_contribution(model, stress_free: np.ndarray, name: str = "prestrain") -> Contribution:
    """The springs of a frame model pushing their nodes towards their stress-free relative motion Δ0 (n, 6)."""
    return Contribution(loads={name: bushing.prestrain_entries(model.coordinates, model.bushings, stress_free)})


def constraint_contribution(model) -> Contribution:
    """The rigid links and fixed DOFs of a frame model."""
    links = model.rigid_links.contribution(model.coordinates, model.n_dofs, (0.0, 0.0, 0.0))
    return Contribution(equations=links.equations, fixed_dofs=np.asarray(model.fixed_dofs, dtype=int))


def frame_contributions(model, gravity_direction) -> list[Contribution]:
    """Every piece of a frame model, in assembly order: each element group's, then the fixed DOFs.

    Each group (:class:`rvcoax.fem.contribution.ElementGroup`) says what it adds: a new element type is put
    into the model (:class:`rvcoax.fem.model.StructuralModel`) and every frame model (the rig's, the checks
    before a solve, the exports) assembles it, without a list of types here.
    ``gravity_direction`` scales the load ``"gravity"``: a unit vector gives the weight per m/s², an
    acceleration (m/s²) the weight itself.
    """
    direction = np.asarray(gravity_direction, dtype=float)
    pieces = [g.contribution(model.coordinates, model.n_dofs, direction) for g in model.groups]
    return [*pieces, Contribution(fixed_dofs=np.asarray(model.fixed_dofs, dtype=int))]


def assemble_frame(model, gravity_direction=(0.0, 0.0, 0.0)) -> AssembledSystem:
    """A frame model alone (:func:`frame_contributions`) summed by :func:`assemble`."""
    return assemble(model.n_dofs, frame_contributions(model, gravity_direction))


def solid_contribution(basis, material: solid.ElasticMaterial, dof_offset: int, *, gravity_direction) -> Contribution:
    """A solid part (P2 tetrahedra) of ``material`` whose DOFs start at ``dof_offset``: stiffness and body weight."""
    weight = solid.body_force_vector(basis, material.density_kg_per_m3, np.asarray(gravity_direction, dtype=float))
    return Contribution(loads={"gravity": dense_entries(weight, dof_offset)},
                        block=(dof_offset, solid.stiffness_matrix(basis, material.youngs_modulus_Pa, material.poisson)))


def beam_mass_contribution(model) -> Contribution:
    """The beams of a frame model: their consistent mass (:func:`rvcoax.fem.beam.mass_triplets`)."""
    return model.beams.mass_contribution(model.coordinates)


def point_mass_mass_contribution(model) -> Contribution:
    """The point masses of a frame model (coupling hubs): mass and rotary inertia at their nodes."""
    return model.point_masses.mass_contribution(model.coordinates)


def frame_mass_contributions(model) -> list[Contribution]:
    """The mass forms of a frame model's element groups, in their order (springs and links carry none)."""
    forms = (g.mass_contribution(model.coordinates) for g in model.groups)
    return [form for form in forms if form is not None]


def solid_mass_contribution(basis, density_kg_per_m3: float, dof_offset: int) -> Contribution:
    """A solid part's consistent mass (:func:`rvcoax.fem.solid.mass_matrix`), its DOFs from ``dof_offset``."""
    return Contribution(mass_block=(dof_offset, solid.mass_matrix(basis, density_kg_per_m3)))


def tie_contribution(equations: Mapping[int, Mapping[int, float]]) -> Contribution:
    """A tie between a reference node and a solid face (:mod:`rvcoax.fem.ties` gives its rows)."""
    return Contribution(equations=equations)
