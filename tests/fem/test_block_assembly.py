"""A solid's stiffness assembled in chunks straight into its 3 × 3-block pattern, and blocks placed side by side."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
import scipy.sparse as sp

from rvcoax.fem import solid
from rvcoax.fem.assembly import (
    add_element_matrices,
    assemble_matrix,
    block_diagonal,
    block_pattern,
    element_positions,
    keep_rows_and_columns,
)
from rvcoax.fem.pieces import Contribution, assemble, solid_contribution
from rvcoax.geometry.meshing import SolidPartGeometry, mesh_part

STEEL = solid.ElasticMaterial(youngs_modulus_Pa=2.1e11, poisson=0.28, density_kg_per_m3=7850.0)


@pytest.fixture(scope="module")
def basis(tmp_path_factory):
    geometry = SolidPartGeometry("bar", ((0.0, 60.0, 30.0, 12.0), (60.0, 100.0, 20.0, 0.0)), (), 6.0)
    return solid.solid_basis(mesh_part(geometry, cache_dir=tmp_path_factory.mktemp("meshes")))


def test_chunked_assembly_is_the_triplet_assembly(basis):
    chunked = solid.stiffness_matrix(basis, 2.1e11, 0.28)
    reference = assemble_matrix(basis.N, [solid.stiffness_triplets(basis, 2.1e11, 0.28)])
    assert np.array_equal(chunked.indptr, reference.indptr) and np.array_equal(chunked.indices, reference.indices)
    # the same additions in the same (element) order: the same floats
    assert np.array_equal(chunked.data, reference.data)


def test_threaded_assembly_adds_the_same_floats_as_one_thread(basis):
    # worker threads compute the blocks, the calling thread adds them in element order: bit for bit the same
    assert basis.mesh.t.shape[1] > 3 * solid._CHUNK_ELEMENTS  # several blocks in flight at once
    serial = solid.stiffness_matrix(basis, 2.1e11, 0.28, threads=1)
    for threads in (2, 3):
        threaded = solid.stiffness_matrix(basis, 2.1e11, 0.28, threads=threads)
        assert np.array_equal(threaded.indptr, serial.indptr) and np.array_equal(threaded.indices, serial.indices)
        assert np.array_equal(threaded.data, serial.data)


def test_element_positions_follow_the_node_rows():
    # node 1 has neighbours 0, 1, 2 (3 blocks): its scalar rows 3, 4, 5 each hold 9 entries from 9 · p_1 = 18 on
    nodes = np.array([[0, 1], [1, 2]])
    pattern = block_pattern(nodes, 3)
    position = element_positions(pattern, nodes[1:]).reshape(2, 3, 2, 3)  # element 1: (a, c, b, d)
    scalar = sp.csr_matrix((np.arange(pattern.nnz, dtype=float), pattern.indices, pattern.indptr)).toarray()
    for a, i in enumerate((1, 2)):
        for b, j in enumerate((1, 2)):
            assert np.array_equal(position[a, :, b, :], scalar[3 * i:3 * i + 3, 3 * j:3 * j + 3])


@pytest.mark.parametrize("threads", [1, 2])
def test_assembly_peak_memory_is_close_to_the_matrix(basis, threads):
    tracemalloc.start()
    try:
        matrix = solid.stiffness_matrix(basis, 2.1e11, 0.28, threads=threads)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    size = matrix.data.nbytes + matrix.indices.nbytes + matrix.indptr.nbytes
    # on top: one chunk of 512 element matrices with its temporaries (about 16 MB whatever the mesh; the
    # ~300 k-DOF benchmark, bench_assembly_memory.py, shows the ratio itself); with worker threads, one more
    # chunk's values and places (8 MB) per block in flight (at most threads + 1)
    assert peak <= 1.5 * size + 16e6 + (8e6 * (threads + 1) if threads > 1 else 0.0)
    triplets = solid.stiffness_triplets(basis, 2.1e11, 0.28)
    assert sum(a.nbytes for a in triplets) > 2 * size  # what the triplet path holds before it even sums


def test_pattern_of_two_elements_sharing_nodes():
    nodes = np.array([[0, 1, 2], [2, 3, 1]])
    pattern = block_pattern(nodes, 4)
    data = np.zeros(pattern.nnz)
    rng = np.random.default_rng(0)
    matrices = rng.standard_normal((2, 9, 9))
    add_element_matrices(pattern, nodes, matrices, data)
    got = sp.csr_matrix((data, pattern.indices, pattern.indptr), shape=(12, 12)).toarray()
    expected = np.zeros((12, 12))
    for element, m in zip(nodes, matrices):
        dofs = (3 * element[:, None] + np.arange(3)).ravel()
        expected[np.ix_(dofs, dofs)] += m
    assert np.array_equal(got, expected)
    assert pattern.nnz == 9 * 14  # node pairs: 4 diagonal + 10 off-diagonal (0-3 never meet)
    with pytest.raises(ValueError, match="not in the pattern"):
        add_element_matrices(pattern, np.array([[0, 3, 1]]), matrices[:1], data)


def test_block_diagonal_places_blocks_and_refuses_overlaps():
    a, b = sp.csr_matrix(np.arange(1.0, 5.0).reshape(2, 2)), sp.csr_matrix(np.array([[7.0]]))
    placed = block_diagonal(6, [(4, b), (1, a)]).toarray()
    expected = np.zeros((6, 6))
    expected[1:3, 1:3], expected[4, 4] = a.toarray(), 7.0
    assert np.array_equal(placed, expected)
    with pytest.raises(ValueError, match="overlaps"):
        block_diagonal(6, [(1, a), (2, b)])


def test_pieces_with_a_solid_block_equal_the_triplet_sum(basis):
    offset = 12
    n = offset + basis.N
    frame = Contribution(stiffness=(np.array([0, 5, 11]), np.array([0, 5, 11]), np.array([1.0, 2.0, 3.0])))
    with_block = assemble(n, [frame, solid_contribution(basis, STEEL, offset, gravity_direction=(0, -1, 0))])
    triplets = solid.stiffness_triplets(basis, 2.1e11, 0.28, dof_offset=offset)
    reference = assemble_matrix(n, [frame.stiffness, triplets])
    assert (with_block.stiffness != reference).nnz == 0
    # a triplet inside the block's range: added instead of placed side by side
    inside = Contribution(stiffness=(np.array([offset + 1]), np.array([offset + 1]), np.array([5.0])))
    added = assemble(n, [inside, solid_contribution(basis, STEEL, offset, gravity_direction=(0, -1, 0))])
    expected = assemble_matrix(n, [inside.stiffness, triplets])
    assert abs(added.stiffness - expected).max() <= 1e-15 * abs(expected).max()


@pytest.mark.parametrize(("overwrite", "threads"), [(False, 1), (True, 1), (True, 2), (False, 3)])
def test_keeping_rows_and_columns_equals_scipys_slices(basis, overwrite, threads):
    stiffness = solid.stiffness_matrix(basis, 2.1e11, 0.28)
    clamped = np.flatnonzero(basis.doflocs[0] < 0.01)  # the DOFs of the first 10 mm
    keep = np.ones(basis.N, dtype=bool)
    keep[clamped] = False
    expected = stiffness[keep][:, keep]
    given = stiffness.copy() if overwrite else stiffness
    # several blocks of rows; with threads, later blocks are read while earlier ones are written over the same arrays
    kept = keep_rows_and_columns(given, keep, overwrite=overwrite, chunk=1000, threads=threads)
    assert kept.shape == expected.shape and kept.has_sorted_indices
    assert np.array_equal(kept.indptr, expected.indptr) and np.array_equal(kept.indices, expected.indices)
    assert np.array_equal(kept.data, expected.data)
    np.testing.assert_array_equal(keep_rows_and_columns(stiffness, np.flatnonzero(keep)).data, expected.data)
    if not overwrite:
        assert np.array_equal(stiffness.data, solid.stiffness_matrix(basis, 2.1e11, 0.28).data)  # left alone


def test_keeping_rows_and_columns_overwrites_without_a_second_matrix(basis):
    stiffness = solid.stiffness_matrix(basis, 2.1e11, 0.28)
    size = stiffness.data.nbytes + stiffness.indices.nbytes
    tracemalloc.start()
    kept = keep_rows_and_columns(stiffness, basis.doflocs[0] >= 0.01, overwrite=True, chunk=256)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    # one block of rows' temporaries (scipy's slices add the row slice and the result: 1.7× the matrix)
    assert peak < 0.2 * size
    assert np.shares_memory(kept.data, stiffness.data)


def test_keeping_rows_and_columns_refuses_what_it_cannot_slice():
    with pytest.raises(ValueError, match="square CSR"):
        keep_rows_and_columns(sp.csr_matrix((3, 4)), np.ones(3, dtype=bool))
    with pytest.raises(ValueError, match="3 entries"):
        keep_rows_and_columns(sp.identity(3, format="csr"), np.ones(4, dtype=bool))


def test_element_positions_on_rows_of_many_lengths():
    # elements of 2 to 6 nodes' rows of very different lengths: every place against a dense lookup
    rng = np.random.default_rng(3)
    nodes = np.array([rng.choice(40, size=4, replace=False) for _ in range(60)])
    pattern = block_pattern(nodes, 40)
    scalar = sp.csr_matrix((np.arange(pattern.nnz, dtype=float), pattern.indices, pattern.indptr)).toarray()
    position = element_positions(pattern, nodes).reshape(len(nodes), 4, 3, 4, 3)
    dofs = 3 * nodes[:, :, None] + np.arange(3)  # (e, a, c)
    expected = scalar[dofs[:, :, :, None, None], dofs[:, None, None, :, :]]
    assert np.array_equal(position, expected)
    with pytest.raises(ValueError, match="not in the pattern"):
        element_positions(block_pattern(nodes[:30], 40), nodes[30:])
