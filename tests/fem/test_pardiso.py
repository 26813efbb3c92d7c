"""MKL PARDISO binding: upper-triangle storages (3 × 3 blocks or scalar CSR), factor, solves, release."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rvcoax.fem import pardiso

pytestmark = pytest.mark.skipif(not pardiso.available(), reason="MKL PARDISO not available (x86-64 with mkl only)")


def spd_block_matrix(n_nodes: int, seed: int = 0) -> sp.csr_matrix:
    """Random SPD matrix made of full 3 × 3 blocks on a random symmetric node graph (like a solid's stiffness)."""
    rng = np.random.default_rng(seed)
    graph = sp.random(n_nodes, n_nodes, density=0.05, random_state=rng, format="csr")
    graph = ((graph + graph.T + sp.identity(n_nodes)) != 0).astype(float)
    dense_blocks = sp.kron(graph, np.ones((3, 3)), format="csr")
    values = dense_blocks.multiply(rng.normal(size=dense_blocks.shape))
    values = values + values.T
    matrix = values + sp.identity(3 * n_nodes) * (abs(values).sum(axis=1).max() + 1.0)  # diagonally dominant
    matrix = sp.csr_matrix(matrix)
    matrix.sum_duplicates()
    matrix.sort_indices()
    return matrix


def expand(storage: pardiso.UpperStorage) -> np.ndarray:
    """Dense upper triangle of a storage, for comparisons."""
    if storage.block_size == 1:
        return sp.csr_matrix((storage.data, storage.indices, storage.indptr), shape=(storage.n, storage.n)).toarray()
    bsr = sp.bsr_matrix((storage.data, storage.indices, storage.indptr), shape=(storage.n, storage.n))
    return np.triu(bsr.toarray())


def test_block_matrix_is_stored_in_3x3_blocks_and_equals_its_upper_triangle():
    a = spd_block_matrix(40)
    storage = pardiso.upper_storage(a)
    assert storage.block_size == 3
    assert storage.data.shape[1:] == (3, 3)
    assert storage.indptr.dtype == np.int32 and storage.indices.dtype == np.int32
    np.testing.assert_array_equal(expand(storage), np.triu(a.toarray()))
    # diagonal blocks are kept whole (lower part included), off-diagonal blocks only above the diagonal
    block_rows = np.repeat(np.arange(storage.n // 3), np.diff(storage.indptr))
    assert np.all(storage.indices >= block_rows)


@pytest.mark.parametrize("damage", ["missing entry", "odd size", "shifted blocks"])
def test_matrices_not_made_of_aligned_blocks_fall_back_to_scalar_csr(damage):
    a = spd_block_matrix(30, seed=1).tolil()
    if damage == "missing entry":  # one coupling inside an off-diagonal block removed on both sides
        i, j = 0, int(a.rows[0][-1])
        a[i, j] = 0.0
        a[j, i] = 0.0
    a = sp.csr_matrix(a)
    a.eliminate_zeros()
    if damage == "odd size":
        a = sp.block_diag([a, sp.identity(1)], format="csr")
    if damage == "shifted blocks":
        a = sp.block_diag([sp.identity(1), a], format="csr")
    a.sort_indices()
    storage = pardiso.upper_storage(a)
    assert storage.block_size == 1
    np.testing.assert_array_equal(expand(storage), np.triu(a.toarray()))


def test_upper_csr_equals_scipy_triu():
    a = spd_block_matrix(25, seed=2)
    storage = pardiso.upper_csr(a)
    reference = sp.triu(a, format="csr")
    reference.sort_indices()
    np.testing.assert_array_equal(storage.indptr, reference.indptr)
    np.testing.assert_array_equal(storage.indices, reference.indices)
    np.testing.assert_array_equal(storage.data, reference.data)


def test_unsorted_input_is_refused():
    a = spd_block_matrix(5)
    a.has_sorted_indices = False
    with pytest.raises(ValueError, match="sorted"):
        pardiso.upper_storage(a)


@pytest.mark.parametrize("storage_kind", ["blocks", "scalar"])
def test_factor_solves_like_superlu_for_several_right_hand_sides(storage_kind):
    a = spd_block_matrix(60, seed=3)
    storage = pardiso.upper_storage(a) if storage_kind == "blocks" else pardiso.upper_csr(a)
    assert storage.block_size == (3 if storage_kind == "blocks" else 1)
    rhs = np.random.default_rng(4).normal(size=(a.shape[0], 3))
    factor = pardiso.Factorization(storage)
    x = factor.solve(rhs)
    reference = spla.splu(a.tocsc()).solve(rhs)
    assert x.shape == rhs.shape and x.flags.c_contiguous
    assert np.abs(x - reference).max() < 1e-10 * np.abs(reference).max()
    assert factor.factor_nonzeros > 0 and factor.memory_MB > 0.0
    factor.release()
    factor.release()  # idempotent
    with pytest.raises(RuntimeError, match="released"):
        factor.solve(rhs)


@pytest.mark.parametrize("storage_kind", ["blocks", "csr"])
def test_indefinite_matrix_raises_a_zero_pivot_error_in_the_numerical_factorisation(storage_kind):
    a = spd_block_matrix(20, seed=5)
    shifted = sp.csr_matrix(a - sp.identity(a.shape[0]) * 2.0 * abs(a).sum(axis=1).max())  # negative definite
    shifted.sort_indices()
    storage = pardiso.upper_storage(shifted) if storage_kind == "blocks" else pardiso.upper_csr(shifted)
    with pytest.raises(pardiso.PardisoError) as raised:
        pardiso.Factorization(storage)
    assert raised.value.code == pardiso.ZERO_PIVOT and "pivot" in str(raised.value)
    assert raised.value.phase == "factorisation"  # the analysis (pattern only) went through
    if storage_kind == "csr":  # the unknown is named only where PARDISO's number is one
        assert 0 <= raised.value.equation < shifted.shape[0]
    else:
        assert raised.value.equation is None


@pytest.fixture()
def empty_pool():
    pardiso.clear_analysis_pool()
    yield
    pardiso.set_analysis_reuse(True)
    pardiso.clear_analysis_pool()


def perturbed(a: sp.csr_matrix, seed: int) -> sp.csr_matrix:
    """The same pattern, other (symmetric, still diagonally dominant) values."""
    b = a.copy()
    b.data *= 1.0 + 0.2 * np.random.default_rng(seed).random(b.nnz)
    b = sp.csr_matrix((b + b.T) * 0.5)
    b.sort_indices()
    return b


def test_a_released_factor_leaves_its_analysis_for_the_next_matrix_of_the_same_pattern(empty_pool):
    a = spd_block_matrix(80, seed=6)
    b = perturbed(a, 7)
    rhs = np.random.default_rng(8).normal(size=(a.shape[0], 2))
    first = pardiso.Factorization(pardiso.upper_storage(a))
    assert not first.reused_analysis and pardiso.pooled_analyses() == 0
    first.release()
    assert pardiso.pooled_analyses() == 1
    second = pardiso.Factorization(pardiso.upper_storage(b))
    assert second.reused_analysis and pardiso.pooled_analyses() == 0
    x = second.solve(rhs)
    second.release()
    pardiso.set_analysis_reuse(False)  # SPD: the analysis is the pattern's alone, so the factor is a fresh one's
    fresh = pardiso.Factorization(pardiso.upper_storage(b))
    assert not fresh.reused_analysis
    reference = fresh.solve(rhs)
    fresh.release()
    assert pardiso.pooled_analyses() == 0
    assert np.abs(x - reference).max() <= 1e-12 * np.abs(reference).max()
    assert np.abs(x - spla.spsolve(b.tocsc(), rhs)).max() < 1e-10 * np.abs(reference).max()


def test_other_patterns_kept_analyses_and_the_memory_cap(empty_pool, monkeypatch):
    a = spd_block_matrix(50, seed=9)
    pardiso.Factorization(pardiso.upper_storage(a)).release()
    other = pardiso.Factorization(pardiso.upper_csr(a))  # same matrix, scalar storage: another pattern
    assert not other.reused_analysis
    other.release(keep_analysis=False)  # e.g. a matrix found singular
    assert pardiso.pooled_analyses() == 1
    monkeypatch.setattr(pardiso, "ANALYSIS_POOL_BYTES", 0)  # nothing fits: freed at release
    again = pardiso.Factorization(pardiso.upper_storage(a))
    assert again.reused_analysis
    again.release()
    assert pardiso.pooled_analyses() == 0


def test_indefinite_saddle_point_on_a_reused_analysis_agrees_with_a_fresh_one(empty_pool):
    a = spd_block_matrix(80, seed=10)
    k, d = a.shape[0], 4
    rng = np.random.default_rng(11)
    columns = rng.permutation(k)[:d * 12]  # each constraint row ties 12 unknowns of its own: full rank
    constraint = sp.csr_matrix((rng.normal(size=d * 12), (np.repeat(np.arange(d), 12), columns)), shape=(d, k))
    rhs = np.zeros((k + d, 1))
    rhs[:k, 0] = rng.normal(size=k)
    pardiso.Factorization(pardiso.upper_saddle_point(a.copy(), constraint), indefinite=True).release()
    b = perturbed(a, 12)
    reused = pardiso.Factorization(pardiso.upper_saddle_point(b.copy(), constraint), indefinite=True)
    fresh = pardiso.Factorization(pardiso.upper_saddle_point(b.copy(), constraint), indefinite=True,
                                  reuse_analysis=False)
    assert reused.reused_analysis and not fresh.reused_analysis
    assert reused.inertia == fresh.inertia == (k, d)
    x, reference = reused.solve(rhs), fresh.solve(rhs)
    reused.release()
    fresh.release()
    # the matching and scaling are those of the first matrix: the same solution to rounding
    assert np.abs(x - reference).max() <= 1e-10 * np.abs(reference).max()


@pytest.mark.parametrize("blocks", [True, False])
def test_a_deferred_factorisation_of_values_changed_after_its_analysis_is_the_plain_factor_bit_for_bit(blocks):
    """The analysis runs on a worker thread with other values of the same pattern (the tie-released K_qq before its
    grounding springs); the factor of the values then in the storage is the one a plain set-up of them gives."""
    a = spd_block_matrix(60, seed=4)
    if not blocks:
        a = sp.block_diag([a, sp.identity(1) * 5.0], format="csr")  # odd size: scalar storage
    rows, springs = np.array([0, 7, 95]), np.array([3.0, 1.5, 0.25])
    final = a + sp.csr_matrix((springs, (rows, rows)), shape=a.shape)
    final.sort_indices()
    b = np.random.default_rng(5).standard_normal((a.shape[0], 2))
    plain = pardiso.Factorization(pardiso.upper_storage(final), reuse_analysis=False, reproducible=True)
    expected = plain.solve(b)
    plain.release()
    storage = pardiso.upper_storage(a)
    assert storage.block_size == (3 if blocks else 1)
    deferred = pardiso.Factorization(storage, reuse_analysis=False, reproducible=True, defer=True)
    with pytest.raises(RuntimeError, match="deferred"):
        deferred.solve(b)
    deferred.wait_for_analysis()
    pardiso.add_to_diagonal(storage, rows, springs)
    np.testing.assert_array_equal(expand(storage), np.triu(final.toarray()))
    deferred.factorise()
    np.testing.assert_array_equal(deferred.solve(b), expected)
    with pytest.raises(RuntimeError, match="once"):
        deferred.factorise()
    deferred.release()


def test_a_deferred_factorisation_released_before_its_analysis_ends_frees_it_and_a_failure_is_raised_on_factorise():
    a = spd_block_matrix(80, seed=6)
    pending = pardiso.Factorization(pardiso.upper_storage(a), reuse_analysis=False, defer=True)
    pending.release()  # waits for the worker thread, then frees MKL's memory
    pending.release()
    singular = sp.csr_matrix(a.shape)
    singular = singular + sp.csr_matrix((np.r_[-1.0, np.ones(a.shape[0] - 1)], (np.arange(a.shape[0]),) * 2))
    failing = pardiso.Factorization(pardiso.upper_storage(singular.tocsr()), reuse_analysis=False, defer=True)
    with pytest.raises(pardiso.PardisoError):
        failing.factorise()  # a negative pivot: released, as an undeferred set-up would be


def test_adding_to_a_diagonal_entry_that_is_not_stored_names_its_row():
    a = sp.csr_matrix(np.array([[2.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 3.0]]))
    a.eliminate_zeros()
    storage = pardiso.upper_storage(a)
    with pytest.raises(ValueError, match="row 1"):
        pardiso.add_to_diagonal(storage, np.array([1]), np.array([1.0]))


def test_a_deferred_factorisation_takes_a_pooled_analysis_of_its_pattern(empty_pool):
    a = spd_block_matrix(50, seed=8)
    first = pardiso.Factorization(pardiso.upper_storage(a))
    first.release()  # its analysis goes to the pool
    other = perturbed(a, seed=9)
    b = np.ones((a.shape[0], 1))
    deferred = pardiso.Factorization(pardiso.upper_storage(other), defer=True)
    deferred.factorise()
    assert deferred.reused_analysis
    np.testing.assert_allclose(deferred.solve(b), spla.spsolve(other.tocsc(), b).reshape(-1, 1), rtol=1e-10)
    deferred.release()
