"""The one piece interface (rvcoax.fem.pieces): contributions in global DOF numbers, summed by one function.

Checked against closed forms, against the rig's beam system (bit for bit), and for
independence of how the same pieces are grouped.
"""

import numpy as np
import pytest
from frames import GRAVITY, assert_close, bushings, dof, model, no_beams, node_dofs, polyline, rigidities

from rvcoax.fem.bushing import GROUND
from rvcoax.fem.loads import NodalLoads, nodal_load_vector
from rvcoax.fem.pieces import (
    Contribution,
    assemble,
    assemble_frame,
    beam_contribution,
    bushing_contribution,
    constraint_contribution,
    dense_load_contribution,
    frame_contributions,
    load_vectors,
    nodal_load_contribution,
    point_mass_contribution,
    prestrain_contribution,
)
from rvcoax.fem.sections import CircularSection
from rvcoax.fem.system import factorize
from rvcoax.geometry.model.loads import GRAVITY_DIRECTION
from rvcoax.geometry.model.system import assemble_beam
from rvcoax.geometry.rigfile import load_rig

SECTION = CircularSection(0.02)
LENGTH = 0.5


def cantilever(n: int = 20):
    coordinates, beams = polyline([[0, 0, 0], [LENGTH, 0, 0]], n, SECTION)
    return model(coordinates, beams, fixed_dofs=np.array(node_dofs(0)))


def test_a_cantilever_assembled_from_pieces_bends_as_timoshenko_says():
    structure = cantilever()
    system = assemble(structure.n_dofs, frame_contributions(structure, (0.0, -1.0, 0.0)))
    force = 1000.0
    load = np.zeros(structure.n_dofs)
    load[dof(structure.n_nodes - 1, 1)] = -force
    u = factorize(system.stiffness, system.elimination).solve(load)
    r = rigidities(SECTION)
    assert_close(-u[dof(structure.n_nodes - 1, 1)], force * LENGTH**3 / (3 * r.EI) + force * LENGTH / r.kGA, 1e-9)
    # the pieces' own load "gravity": the beam's weight per m/s², a uniform line load ρ A
    w = system.loads["gravity"]
    assert_close(-w[1::6].sum(), SECTION.area_m2 * LENGTH * 7850.0, 1e-12)
    tip_sag = factorize(system.stiffness, system.elimination).solve(GRAVITY * w)[dof(structure.n_nodes - 1, 1)]
    q = 7850.0 * SECTION.area_m2 * GRAVITY
    assert_close(-tip_sag, q * LENGTH**4 / (8 * r.EI) + q * LENGTH**2 / (2 * r.kGA), 1e-9)


def test_the_frame_pieces_are_the_beam_rig_system_bit_for_bit():
    """The rig's beam model is its frame's pieces (and no housing here) through the one assembly path."""
    rig_system = assemble_beam(load_rig())
    structure = rig_system.frame.structure
    assembled = assemble_frame(structure, GRAVITY_DIRECTION)
    assert (rig_system.stiffness != assembled.stiffness).nnz == 0
    assert (rig_system.elimination != assembled.elimination).nnz == 0
    assert np.array_equal(rig_system.load_builder.weight_per_g, assembled.loads["gravity"])
    # the weight per m/s²: beams' ρ A L and the coupling hubs, along −y only
    weight = assembled.loads["gravity"].reshape(-1, 6)
    total_kg = sum(rig_system.frame.part_mass_kg.values())
    assert -weight[:, 1].sum() == pytest.approx(total_kg, rel=1e-12)
    assert not weight[:, [0, 2]].any()


def test_a_free_dof_list_comes_with_the_elimination():
    structure = cantilever(4)
    system = assemble_frame(structure)
    assert np.array_equal(system.free_dofs, np.arange(6, structure.n_dofs))
    assert system.elimination.shape == (structure.n_dofs, structure.n_dofs - 6)


def test_grouping_the_same_pieces_differently_gives_the_same_system():
    structure = assemble_beam(load_rig()).frame.structure
    pieces = [beam_contribution(structure, GRAVITY_DIRECTION), bushing_contribution(structure),
              point_mass_contribution(structure, GRAVITY_DIRECTION), constraint_contribution(structure)]
    together = assemble(structure.n_dofs, pieces)
    rows, cols, values = (np.concatenate(parts) for parts in zip(pieces[0].stiffness, pieces[1].stiffness))
    merged = Contribution((rows, cols, values), pieces[0].loads)
    regrouped = assemble(structure.n_dofs, [merged, *pieces[2:]])
    assert (together.stiffness != regrouped.stiffness).nnz == 0
    assert np.array_equal(together.loads["gravity"], regrouped.loads["gravity"])
    assert (together.elimination != regrouped.elimination).nnz == 0


def test_load_entries_and_constraint_rows_add_up():
    a = Contribution(loads={"f": (np.array([0, 2]), np.array([1.0, 2.0]))}, equations={3: {1: 2.0}},
                     fixed_dofs=np.array([0]))
    b = Contribution(loads={"f": (np.array([2, 3]), np.array([0.5, 4.0])), "g": (np.array([1]), np.array([7.0]))})
    system = assemble(4, [a, b])
    assert np.array_equal(system.loads["f"], [1.0, 0.0, 2.5, 4.0])
    assert np.array_equal(system.loads["g"], [0.0, 7.0, 0.0, 0.0])
    assert system.stiffness.shape == (4, 4) and system.stiffness.nnz == 0
    t = system.elimination.toarray()  # u = T q with u0 = 0 and u3 = 2 u1: q = (u1, u2)
    assert np.array_equal(t, [[0, 0], [1, 0], [0, 1], [2, 0]])


def test_loads_are_pieces_too_and_repeated_dofs_add():
    """Two forces on one node add (nodal loads), and a grounded spring with a stress-free offset Δ0 pushes
    its node with k Δ0 (prestrain): the closed forms, summed by the same function as every other load."""
    nodal = NodalLoads(np.array([1, 1, 0]), np.array([[0, 2.0, 0, 0, 0, 1.0], [0, 3.0, 0, 0, 0, 0], [1.0, 0, 0, 0, 0, 0]]))
    k, offset = 2.5e7, 12e-6
    springs = bushings([GROUND], [1], [[0.1, 0.0, 0.0]], [[1e6, k, 1e6, 1.0, 1.0, 1.0]])  # at the node: no arm
    structure = model([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0]], no_beams(), springs)
    stress_free = np.array([[0.0, offset, 0.0, 0.0, 0.0, 0.0]])
    vectors = load_vectors(12, [nodal_load_contribution("T1", nodal), prestrain_contribution(structure, stress_free)])
    assert np.array_equal(vectors["T1"], nodal_load_vector(nodal, 12))
    assert vectors["T1"][dof(1, 1)] == 5.0 and vectors["T1"][dof(1, 5)] == 1.0 and vectors["T1"][dof(0, 0)] == 1.0
    assert_close(vectors["prestrain"][dof(1, 1)], k * offset, 1e-15)
    assert np.count_nonzero(vectors["prestrain"]) == 1
    assert load_vectors(12, [prestrain_contribution(structure, np.zeros((1, 6)))])["prestrain"].tolist() == [0.0] * 12



def test_a_load_given_as_a_vector_lands_at_its_offset_and_adds_in_order():
    """A vector load (a thermal initial strain, a face traction) on DOFs offset… adds to the entries before it."""
    vectors = load_vectors(6, [Contribution(loads={"prestrain": (np.array([2, 3]), np.array([1.0, 2.0]))}),
                               dense_load_contribution("prestrain", np.array([0.5, 1.0]), offset=2)])
    assert vectors["prestrain"].tolist() == [0.0, 0.0, 1.5, 3.0, 0.0, 0.0]


def test_an_index_outside_the_system_is_refused():
    with pytest.raises(ValueError, match="out of range"):
        assemble(3, [Contribution((np.array([0, 3]), np.array([0, 0]), np.array([1.0, 1.0])))])
