"""A new element type is declared once: a table with its stiffness and mass contributions, put into a model.

The element type below lives in this test module and nowhere else: no list of types in ``rvcoax.fem``
names it, yet the one assembly path (:func:`rvcoax.fem.pieces.assemble_frame`,
:func:`rvcoax.fem.pieces.frame_mass_contributions`) adds its stiffness, its weight and its mass.
Checked against closed forms: a cantilever propped by a spring at its tip, and a mass on a spring.
"""

import dataclasses
from dataclasses import dataclass

import numpy as np
import pytest
import scipy.linalg
from frames import GRAVITY, assert_close, dof, model, no_beams, node_dofs, polyline, rigidities

from rvcoax.fem.contribution import Contribution, ElementGroup
from rvcoax.fem.model import StructuralModel
from rvcoax.fem.pieces import assemble, assemble_frame, frame_mass_contributions
from rvcoax.fem.sections import CircularSection

SECTION = CircularSection(0.02)
LENGTH = 0.5


@dataclass(frozen=True)
class SprungMasses:
    """A lumped mass on a grounded spring along global y at each of some nodes (a test-local element type)."""

    node: np.ndarray
    stiffness_N_per_m: np.ndarray
    mass_kg: np.ndarray

    def _dofs(self) -> np.ndarray:
        return 6 * np.asarray(self.node, dtype=int) + 1

    def contribution(self, coordinates, n_dofs, gravity_direction) -> Contribution:
        dofs = self._dofs()
        weight = np.asarray(self.mass_kg, float) * float(gravity_direction[1])
        return Contribution((dofs, dofs, np.asarray(self.stiffness_N_per_m, float)), {"gravity": (dofs, weight)})

    def mass_contribution(self, coordinates) -> Contribution:
        dofs = self._dofs()
        return Contribution(mass=(dofs, dofs, np.asarray(self.mass_kg, float)))


def _mass_matrix(structure: StructuralModel):
    return assemble(structure.n_dofs, frame_mass_contributions(structure)).mass


def _cantilevers(n: int, extra: SprungMasses):
    coordinates, beams = polyline([[0, 0, 0], [LENGTH, 0, 0]], n, SECTION)
    fixed = np.array(node_dofs(0))
    bare = model(coordinates, beams, fixed_dofs=fixed)
    return bare, bare.with_group(extra)


def test_a_test_local_element_type_is_assembled_into_stiffness_weight_and_mass():
    n = 8
    extra = SprungMasses(np.array([n]), np.array([3.0e5]), np.array([2.5]))
    assert isinstance(extra, ElementGroup)
    bare, with_extra = _cantilevers(n, extra)
    tip = dof(n, 1)
    k_difference = (assemble_frame(with_extra).stiffness - assemble_frame(bare).stiffness).tocoo()
    assert k_difference.nnz == 1 and (k_difference.row[0], k_difference.col[0]) == (tip, tip)
    assert k_difference.data[0] == pytest.approx(3.0e5, rel=1e-12)
    m_difference = (_mass_matrix(with_extra) - _mass_matrix(bare)).tocoo()
    assert m_difference.nnz == 1 and m_difference.data[0] == pytest.approx(2.5, rel=1e-12)
    weight = assemble_frame(with_extra, (0.0, -GRAVITY, 0.0)).loads["gravity"]
    assert weight[tip] - assemble_frame(bare, (0.0, -GRAVITY, 0.0)).loads["gravity"][tip] == pytest.approx(
        -2.5 * GRAVITY, rel=1e-12)
    # the propped cantilever: a tip force F moves the tip F / (1/f + k), f = L³/(3EI) + L/(κGA)
    system = assemble_frame(with_extra)
    k_reduced = (system.elimination.T @ system.stiffness @ system.elimination).toarray()
    load = np.zeros(with_extra.n_dofs)
    load[tip] = -100.0
    u = system.elimination @ np.linalg.solve(k_reduced, system.elimination.T @ load)
    r = rigidities(SECTION)
    flexibility = LENGTH**3 / (3 * r.EI) + LENGTH / r.kGA
    assert_close(-u[tip], 100.0 / (1.0 / flexibility + 3.0e5), 1e-9)


def test_a_mass_on_a_spring_of_the_new_type_rings_at_its_closed_form_frequency():
    k, m = 4.0e6, 1.6
    structure = StructuralModel(np.zeros((1, 3)), no_beams(), SprungMasses(np.array([0]), np.array([k]), np.array([m])),
                                fixed_dofs=np.array([0, 2, 3, 4, 5]))
    system = assemble(structure.n_dofs, frame_mass_contributions(structure))
    stiffness = assemble_frame(structure)
    t = stiffness.elimination
    omega_squared = scipy.linalg.eigh((t.T @ stiffness.stiffness @ t).toarray(), (t.T @ system.mass @ t).toarray(),
                                      eigvals_only=True)
    assert_close(np.sqrt(omega_squared[0]), np.sqrt(k / m), 1e-12)


def test_a_model_takes_one_table_per_type_and_finds_it_by_type():
    extra = SprungMasses(np.array([0]), np.array([1.0]), np.array([1.0]))
    structure = StructuralModel(np.zeros((1, 3)), no_beams(), extra)
    assert structure.group(SprungMasses) is extra and structure.group(CircularSection) is None
    with pytest.raises(ValueError, match="two element groups of one type"):
        StructuralModel(np.zeros((1, 3)), extra, extra)
    with pytest.raises(TypeError, match="not an element group"):
        StructuralModel(np.zeros((1, 3)), SECTION)
    replaced = structure.with_group(SprungMasses(np.array([0]), np.array([2.0]), np.array([1.0])))
    assert [type(g) for g in replaced.groups] == [type(g) for g in structure.groups]
    assert replaced.group(SprungMasses).stiffness_N_per_m[0] == 2.0
    moved = dataclasses.replace(replaced, fixed_dofs=np.array([0, 1]))
    assert moved.groups == replaced.groups and moved.fixed_dofs.tolist() == [0, 1]
    # the rig's own types read as empty tables where a model has none
    assert len(structure.bushings.node_b) == 0 and len(structure.point_masses.node) == 0
