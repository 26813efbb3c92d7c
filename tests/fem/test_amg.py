"""MKL sparse products and the AMG V-cycle: products equal scipy's, the hierarchy is pyamg's smoothed aggregation,
the cycle is a symmetric positive operator."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rvcoax.fem import amg, mkl_sparse, solid
from rvcoax.fem.mkl_sparse import SparseOperator
from rvcoax.fem.rigid_body import rigid_body_modes
from rvcoax.fem.solvers import conjugate_gradients, prepare
from rvcoax.geometry.meshing import SolidPartGeometry, mesh_part


@pytest.fixture(scope="module")
def bar(tmp_path_factory):
    """Clamped solid bar: reduced stiffness (3 × 3 blocks per node pair), a tip load, rigid-body modes."""
    geometry = SolidPartGeometry("bar", ((0.0, 120.0, 20.0, 0.0),), (), 7.0)
    mesh = mesh_part(geometry, cache_dir=tmp_path_factory.mktemp("meshes"))
    basis = solid.solid_basis(mesh)
    k = solid.stiffness_matrix(basis, 2.1e11, 0.3)
    clamp = mesh.facets_satisfying(lambda x: np.isclose(x[0], 0.0))
    tip = mesh.facets_satisfying(lambda x: np.isclose(x[0], 0.120))
    free = np.setdiff1d(np.arange(basis.N), basis.get_dofs(clamp).all())
    a = k[free][:, free].tocsr()
    a.sort_indices()
    load = solid.force_traction_vector(mesh, tip, [0.0, -1000.0, 0.0])[free]
    return a, load, rigid_body_modes(basis.doflocs.T)[free]


@pytest.fixture(scope="module")
def exact(bar):
    a, load, _ = bar
    return spla.splu(a.tocsc()).solve(load)


def test_symmetric_product_equals_scipy_in_both_precisions(bar):
    a, _, _ = bar
    x = np.random.default_rng(0).standard_normal(a.shape[0])
    reference = a @ x
    double = SparseOperator.symmetric(a, np.float64)
    single = SparseOperator.symmetric(a, np.float32)
    if mkl_sparse.available():
        assert double.uses_mkl and double.block_size == 3  # a solid's stiffness: 3 × 3 blocks, upper triangle
        assert double.stored_bytes < 0.75 * (a.data.nbytes + a.indices.nbytes)
    scale = np.linalg.norm(reference)
    assert np.linalg.norm(double @ x - reference) < 1e-13 * scale
    assert np.linalg.norm(single @ x.astype(np.float32) - reference) < 1e-5 * scale
    y = np.ones(a.shape[0])
    double.matvec(x, y, alpha=-2.0, beta=3.0)  # y = 3·1 − 2 A x
    assert np.linalg.norm(y - (3.0 - 2.0 * reference)) < 1e-13 * scale


def test_general_product_and_its_transpose_equal_scipy():
    rng = np.random.default_rng(1)
    dense = rng.standard_normal((40, 7)) * (rng.random((40, 7)) < 0.3)
    p = sp.csr_matrix(dense)
    operator = SparseOperator.general(p, np.float64)
    x, y = rng.standard_normal(7), rng.standard_normal(40)
    assert np.allclose(operator.matvec(x), dense @ x, rtol=0, atol=1e-14)
    assert np.allclose(operator.matvec(y, transpose=True), dense.T @ y, rtol=0, atol=1e-14)


def test_products_refuse_vectors_of_another_precision(bar):
    a, _, _ = bar
    with pytest.raises(ValueError, match="float32"):
        SparseOperator.symmetric(a, np.float32).matvec(np.ones(a.shape[0]))


def test_without_mkl_the_same_products_come_from_scipy(bar, monkeypatch):
    a, _, _ = bar
    x = np.random.default_rng(2).standard_normal(a.shape[0])
    monkeypatch.setattr(mkl_sparse, "available", lambda: False)
    operator = SparseOperator.symmetric(a, np.float64)
    assert not operator.uses_mkl
    assert np.linalg.norm(operator @ x - a @ x) < 1e-14 * np.linalg.norm(a @ x)


def test_lanczos_bounds_the_largest_eigenvalue_of_the_scaled_matrix(bar):
    a, _, _ = bar
    inverse_sqrt = 1.0 / np.sqrt(a.diagonal())
    scaled = sp.diags(inverse_sqrt) @ a @ sp.diags(inverse_sqrt)
    exact = spla.eigsh(scaled, k=1, which="LA", return_eigenvectors=False)[0]
    estimate = amg._largest_eigenvalue(SparseOperator.symmetric(a, np.float64), inverse_sqrt)
    assert exact / amg.LAMBDA_MARGIN < estimate <= exact * (1 + 1e-9)  # the margin covers what Lanczos misses


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_v_cycle_is_a_symmetric_positive_definite_operator(bar, dtype):
    a, _, modes = bar
    hierarchy = amg.smoothed_aggregation(a, modes, dtype=dtype)
    assert len(hierarchy.sizes) >= 2 and hierarchy.sizes[0] == a.shape[0]
    rng = np.random.default_rng(3)
    r1, r2 = rng.standard_normal(a.shape[0]), rng.standard_normal(a.shape[0])
    m1, m2 = hierarchy.precondition(r1), hierarchy.precondition(r2)
    tolerance = 1e-4 if dtype == np.float32 else 1e-11
    assert abs(r2 @ m1 - r1 @ m2) < tolerance * np.sqrt((r1 @ m1) * (r2 @ m2))
    assert r1 @ m1 > 0.0 and r2 @ m2 > 0.0
    hierarchy.release()


def test_v_cycle_in_single_precision_converges_like_double(bar, exact):
    """Single precision inside the cycle leaves CG's result at its accuracy and costs at most a few iterations."""
    a, load, modes = bar
    results = {}
    for dtype in (np.float32, np.float64):
        hierarchy = amg.smoothed_aggregation(a, modes, dtype=dtype)
        x, iterations, estimate = conjugate_gradients(hierarchy.matrix, load, hierarchy.precondition, 1e-6)
        error = np.sqrt((x - exact) @ (a @ (x - exact)) / (exact @ (a @ exact)))
        assert error < 1e-6 and estimate < 1e-6
        results[np.dtype(dtype).name] = iterations
        hierarchy.release()
    assert results["float32"] <= results["float64"] + 3


def test_amg_solver_matches_the_direct_solution(bar, exact):
    a, load, modes = bar
    solver = prepare(a, "amg", near_null_space=modes)
    x = solver.solve(load)
    assert "Chebyshev V-cycle" in solver.report.name
    assert np.sqrt((x - exact) @ (a @ (x - exact)) / (exact @ (a @ exact))) < 1e-6
    np.testing.assert_array_equal(solver.solve(load), x)  # a repeated solve gives the same bits
    solver.release()


def test_an_unknown_with_a_zero_diagonal_is_left_at_zero_by_the_coarse_solve():
    """An aggregate with fewer nodes than rigid-body modes gives PᵀAP a zero row and column (pyamg's rank-deficient QR)."""
    spd = np.array([[4.0, 1.0, 0.0], [1.0, 3.0, 0.0], [0.0, 0.0, 0.0]])
    diagonal = amg._checked_diagonal(sp.csr_matrix(spd), 1)
    active = np.flatnonzero(diagonal > 0)
    import scipy.linalg

    coarse = amg._CoarseFactor(active, scipy.linalg.cho_factor(spd[np.ix_(active, active)]), 3)
    x = coarse.solve(np.array([1.0, 2.0, 5.0], dtype=np.float32))
    assert x.dtype == np.float32 and x[2] == 0.0
    assert np.allclose(spd[:2, :2] @ x[:2], [1.0, 2.0], rtol=1e-6)
    with pytest.raises(amg.SolverError, match="not positive definite"):
        amg._checked_diagonal(sp.csr_matrix(np.diag([1.0, -1.0])), 0)


def test_threaded_and_single_thread_products_agree(bar, monkeypatch):
    """Small operators run on one MKL thread (mkl_sparse.THREADED_FROM); the threaded path gives the same product."""
    a, _, _ = bar
    x = np.random.default_rng(4).standard_normal(a.shape[0])
    single = SparseOperator.symmetric(a, np.float64) @ x
    monkeypatch.setattr(mkl_sparse, "THREADED_FROM", 0)
    threaded = SparseOperator.symmetric(a, np.float64) @ x
    assert np.linalg.norm(threaded - single) < 1e-13 * np.linalg.norm(single)


def test_hierarchy_has_pyamgs_levels_and_aggregates(bar):
    """The set-up is pyamg's smoothed aggregation with its defaults: the same aggregates and level sizes."""
    import pyamg
    from pyamg.aggregation import standard_aggregation
    from pyamg.strength import symmetric_strength_of_connection

    a, _, modes = bar
    theirs = pyamg.smoothed_aggregation_solver(a, B=modes, symmetry="symmetric", improve_candidates=None,
                                               presmoother=None, postsmoother=None, keep=True)
    ours = amg.smoothed_aggregation(a, modes)
    assert ours.sizes == [level.A.shape[0] for level in theirs.levels]
    # θ = 0: every stored entry is a strong connection, so the matrix's own pattern gives pyamg's aggregates
    expected, _ = standard_aggregation(symmetric_strength_of_connection(sp.csr_array(a), 0.0))
    assert (amg._aggregates(a, None, 1) != expected).nnz == 0
    assert (amg._aggregates(a, None, 1) != theirs.levels[0].AggOp).nnz == 0
    # a coarse level is aggregated node by node (blocks of the 6 modes), as pyamg's BSR levels: same count
    # (which neighbour a left-over node joins depends on the order of a row's indices, unsorted in pyamg's)
    coarse = amg._aggregates(sp.csr_matrix(theirs.levels[1].A), None, modes.shape[1])
    assert coarse.shape == theirs.levels[1].AggOp.shape


def test_blocked_threaded_products_equal_scipys_formula(bar):
    """P = T − ω/ρ D⁻¹ A T and Pᵀ A P by 3 × 3 blocks and row ranges on threads, against plain scipy."""
    from concurrent.futures import ThreadPoolExecutor

    from pyamg.aggregation import fit_candidates

    a, _, modes = bar
    aggregates = amg._aggregates(a, None, 1)
    inverse_diagonal = 1.0 / a.diagonal()
    rho = 3.0
    tentative, coarse_modes = fit_candidates(aggregates, modes)
    tentative = sp.csr_matrix(tentative)
    expected = tentative - sp.diags(amg.PROLONGATION_OMEGA / rho * inverse_diagonal) @ (a @ tentative)
    blocks = amg._node_blocks(a, 3)
    assert blocks is not None and blocks.blocksize == (3, 3)
    assert amg._node_blocks(a[:, :-1].tocsr()[:-1], 3) is None  # not made of whole blocks
    with ThreadPoolExecutor(2) as pool:
        for matrix in (a, blocks):
            p, candidates = amg._prolongator(matrix, aggregates, inverse_diagonal, rho, modes, pool=pool, parts=3)
            np.testing.assert_array_equal(candidates, coarse_modes)
            assert abs(sp.csr_matrix(p) - expected).max() <= 1e-14 * abs(expected).max()
            coarse = amg._galerkin(matrix, p, pool, 5)
            reference = expected.T @ a @ expected
            assert abs(coarse - reference).max() <= 1e-12 * abs(reference).max()


def test_upper_block_triangle_is_pardisos(bar):
    from rvcoax.fem import pardiso

    a, _, _ = bar
    ours, theirs = pardiso.upper_block_storage(amg._node_blocks(a, 3)), pardiso.upper_storage(a)
    assert (ours.n, ours.block_size) == (theirs.n, theirs.block_size) == (a.shape[0], 3)
    for name in ("indptr", "indices", "data"):
        np.testing.assert_array_equal(getattr(ours, name), getattr(theirs, name))


def test_without_mkl_the_hierarchy_is_built_and_solves_the_same(bar, exact, monkeypatch):
    a, load, modes = bar
    monkeypatch.setattr(mkl_sparse, "available", lambda: False)
    solver = prepare(a, "amg", near_null_space=modes)
    x = solver.solve(load)
    assert "scipy products" in solver.report.name
    assert np.sqrt((x - exact) @ (a @ (x - exact)) / (exact @ (a @ exact))) < 1e-6
    solver.release()
