"""Distributing ties kept as unknowns with Lagrange multipliers: same solution as Tᵀ K T, no dense block."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rvcoax.fem import pardiso, solid
from rvcoax.fem.assembly import assemble_matrix
from rvcoax.fem.constraints import elimination_matrix
from rvcoax.fem.rigid_body import rigid_body_modes
from rvcoax.fem.solvers import SingularMatrixError, pardiso_available
from rvcoax.fem.system import (
    LONG_ROW,
    ReleasedStiffness,
    constrained_stiffness,
    independent_modes,
    long_rows,
    prepare_system,
    reduced_stiffness,
    tied_rows,
)
from rvcoax.fem.ties import FaceNodes, distributing_tie_equations
from rvcoax.fem.woodbury import grounded_dofs
from rvcoax.geometry.meshing import SolidPartGeometry, mesh_part

needs_pardiso = pytest.mark.skipif(not pardiso_available(), reason="MKL PARDISO not available")
FRAME_DOFS = 12  # two 6-DOF reference nodes, then the solid


def end_face(basis, x_m: float) -> FaceNodes:
    """The P2 nodes of the end face at x (unit weights), DOFs shifted past the frame."""
    ux = np.flatnonzero((solid.dof_components(basis) == 0) & np.isclose(basis.doflocs[0], x_m))
    dofs = np.column_stack([ux, ux + 1, ux + 2]) + FRAME_DOFS
    return FaceNodes(basis.doflocs[:, ux].T, dofs, np.ones(ux.size))


@pytest.fixture(scope="module")
def tied_bar_and_modes(tmp_path_factory):
    """A solid bar, each end face tied (RBE3) to a reference node; node 0 on springs to ground, load on node 1;
    with the rigid-body modes of all its DOFs."""
    mesh = mesh_part(SolidPartGeometry("bar", ((0.0, 50.0, 40.0, 0.0),), (), 8.0),
                     cache_dir=tmp_path_factory.mktemp("meshes"))
    basis = solid.solid_basis(mesh)
    n = FRAME_DOFS + basis.N
    ground = np.array([1e9, 1e9, 1e9, 1e5, 1e5, 1e5])
    k = assemble_matrix(n, [solid.stiffness_triplets(basis, 2.1e11, 0.3, dof_offset=FRAME_DOFS),
                            (np.arange(6), np.arange(6), ground)])
    equations = {**distributing_tie_equations(0, np.zeros(3), end_face(basis, 0.0)),
                 **distributing_tie_equations(1, np.array([0.05, 0.0, 0.0]), end_face(basis, 0.05))}
    t = elimination_matrix(n, [], equations)[0]
    loads = np.zeros((n, 3))
    loads[6 + 1, 0] = -500.0  # lateral force
    loads[6 + 3, 1] = 20.0  # torque
    loads[6 + 0, 2], loads[6 + 5, 2] = 300.0, 7.0  # axial force and bending moment
    position = np.vstack([np.zeros((6, 3)), np.tile([0.05, 0.0, 0.0], (6, 1)), basis.doflocs.T])
    component = np.concatenate([np.arange(12) % 6, solid.dof_components(basis)])
    return k, t, loads, ground, rigid_body_modes(position, component)


@pytest.fixture(scope="module")
def tied_bar(tied_bar_and_modes):
    return tied_bar_and_modes[:4]


def test_long_rows_are_the_distributing_ties(tied_bar):
    _, t, _, _ = tied_bar
    assert np.array_equal(long_rows(t), np.arange(12))  # both reference nodes, nothing else
    assert np.diff(t.indptr)[:12].min() > LONG_ROW


def test_constrained_stiffness_is_the_reduced_stiffness_without_forming_it(tied_bar):
    k, t, _, _ = tied_bar
    formed = reduced_stiffness(k, t)
    operator = constrained_stiffness(k, t, long_rows(t))
    x = np.random.default_rng(1).standard_normal((t.shape[1], 2))
    assert np.allclose(operator @ x, formed @ x, rtol=0, atol=1e-12 * abs(formed).max() * np.abs(x).max())
    assert np.allclose(operator.diagonal(), formed.diagonal(), rtol=1e-12)
    root = np.sqrt(formed.diagonal())
    exact = abs(sp.diags(1 / root) @ formed @ sp.diags(1 / root)).sum(axis=0).max()
    assert operator.scaled_one_norm(root, columns_per_chunk=97) == pytest.approx(exact, rel=1e-12)
    # the same with K' read from PARDISO's upper triangle (|K'| applied from it for the column bounds)
    served = operator.served_from(operator.saddle_point_upper())
    assert served.scaled_one_norm(root, columns_per_chunk=97) == pytest.approx(exact, rel=1e-12)
    # the multiplier form adds the tie rows (twice) to K and no dense face block
    tie_entries = t[long_rows(t)].nnz
    assert operator.saddle_point_matrix().nnz <= k.nnz + 2 * tie_entries + 2 * 12
    grounded_face = np.diff(t.indptr)[1] // 3  # nodes on the face tied to the grounded node
    assert formed.nnz > k.nnz + (3 * grounded_face) ** 2 // 2


def test_upper_triangle_is_built_without_the_whole_saddle_point_matrix(tied_bar):
    """PARDISO's input, built from K' and C directly, is entry for entry the upper triangle of the whole matrix."""
    k, t, _, _ = tied_bar
    operator = constrained_stiffness(k, t, long_rows(t))
    whole = operator.saddle_point_matrix()
    whole.sum_duplicates()
    whole.sort_indices()
    expected = pardiso.upper_csr(whole)
    built = operator.saddle_point_upper()
    assert built.n == expected.n == whole.shape[0] and built.block_size == 1
    for name in ("indptr", "indices", "data"):
        assert getattr(built, name).dtype == getattr(expected, name).dtype
        assert np.array_equal(getattr(built, name), getattr(expected, name)), name
    # the symmetric pattern's count (K' = T'ᵀ K T' leaves a few entries of one triangle only, rounding-size)
    assert pardiso.stored_nonzeros(built) == (sp.triu(whole) + sp.triu(whole, 1).T).nnz
    assert abs(pardiso.stored_nonzeros(built) - whole.nnz) < 1e-3 * whole.nnz
    assert np.array_equal(operator.diagonal(), operator.diagonal())  # kept, and a copy each time
    operator.diagonal()[0] = -1.0
    assert operator.diagonal()[0] > 0.0
    # K' read back from that upper triangle: the same operator, to rounding, sparse and dense
    served = operator.served_from(built)
    assert served.kept._upper.data is built.data or np.shares_memory(served.kept._upper.data, built.data)
    x = np.random.default_rng(2).standard_normal((t.shape[1], 3))
    scale = abs(operator.kept).max() * np.abs(x).max()
    assert np.allclose(served @ x, operator @ x, rtol=0, atol=1e-13 * scale)
    assert np.allclose(served @ x[:, 0], operator @ x[:, 0], rtol=0, atol=1e-13 * scale)
    assert np.array_equal(served.diagonal(), operator.diagonal())
    assert np.array_equal(served.kept.diagonal(), operator.kept.diagonal())
    sparse = sp.random(operator.kept.shape[0], 5, density=0.01, random_state=3, format="csc")
    assert abs(served.kept @ sparse - operator.kept @ sparse).max() <= 1e-13 * abs(operator.kept).max()
    root = np.sqrt(operator.diagonal())
    assert served.scaled_one_norm(root, 97) == pytest.approx(operator.scaled_one_norm(root, 97), rel=1e-12)
    # |K'| x taken by absolute value a chunk of rows at a time (no copy of the whole triangle): the same product
    v = np.random.default_rng(4).standard_normal(operator.kept.shape[0])
    whole_abs = abs(operator.kept) @ v
    for chunk in (1, 1000, 1 << 21):
        assert np.allclose(served.kept.absolute_product(v, chunk), whole_abs, rtol=0, atol=1e-13 * np.abs(whole_abs).max())


@needs_pardiso
@pytest.mark.slow  # 2.7 s idle, 15 s on a loaded 2-core machine (SuperLU of the dense reference, condition estimates)
def test_multiplier_solve_equals_the_eliminated_solve(tied_bar):
    k, t, loads, _ = tied_bar
    kept = prepare_system(k, t, "pardiso")
    assert "multipliers" in kept.solver_name and "mtype=-2" in kept.solver_name
    eliminated = prepare_system(k, t, "superlu", symmetrize=True)
    u, reference = kept.solve(loads), eliminated.solve(loads)
    assert np.all(np.abs(u - reference).max(axis=0) <= 1e-10 * np.abs(reference).max(axis=0))
    assert kept.relative_residual(u, loads).max() < 1e-10
    report = kept.solver.report
    assert report.factor_nonzeros > 0 and report.matrix_nonzeros < reduced_stiffness(k, t).nnz
    condition = kept.condition_estimate()
    assert condition == pytest.approx(eliminated.condition_estimate(), rel=1e-6)


@needs_pardiso
@pytest.mark.slow
def test_singular_constrained_stiffness_is_refused_every_time(tied_bar):
    k, t, _, ground = tied_bar
    free = k - sp.csr_matrix((ground, (np.arange(6), np.arange(6))), shape=k.shape)  # nothing grounded
    for _ in range(3):
        with pytest.raises(SingularMatrixError, match="singular"):
            prepare_system(free.tocsr(), t, "pardiso")


@needs_pardiso
@pytest.mark.slow  # the tied bar's mesh and three factorisations: 3.7 s idle
def test_a_factor_of_a_nearby_matrix_is_refined_to_the_operators_accuracy(tied_bar, monkeypatch):
    """Perturbed pivots factorise a nearby matrix; the solve refines against A itself until the residual is small."""
    from rvcoax.fem import solvers

    k, t, loads, _ = tied_bar
    operator = constrained_stiffness(k, t, long_rows(t))
    augmented = operator.saddle_point_matrix().tocsr()
    m = operator.shape[0]
    stiffened = np.zeros(augmented.shape[0])
    stiffened[:m] = 1e-10 * augmented.diagonal()[:m]  # K' · (1 + 1e-10) on its diagonal: residual ~3e-6 unrefined
    nearby = (augmented + sp.diags(stiffened)).tocsr()
    rhs = t.T @ loads
    refined = solvers.prepare_saddle_point(operator, nearby)
    residual = np.linalg.norm(rhs - operator @ refined.solve(rhs), axis=0) / np.linalg.norm(rhs, axis=0)
    assert residual.max() <= solvers.REFINE_ABOVE
    monkeypatch.setattr(solvers, "MAX_REFINEMENT_STEPS", 0)
    once = solvers.prepare_saddle_point(operator, nearby)
    with pytest.raises(SingularMatrixError, match="relative residual"):  # as a 10 mm solid rig once did
        once.solve(rhs)


@needs_pardiso
@pytest.mark.slow  # the tied bar's three factorisations, like the test above
def test_a_refusal_on_a_reused_analysis_is_judged_again_on_a_fresh_one(tied_bar, monkeypatch):
    """The pooled matching and scaling are another matrix's: a refusal must not rest on them."""
    from rvcoax.fem import solvers

    k, t, loads, _ = tied_bar
    pardiso.clear_analysis_pool()
    prepare_system(k, t, "pardiso").solver.release()  # leaves its analysis in the pool
    original = solvers.refuse_singular
    judged = []

    def refuse_on_reused(matrix, solve, factor):
        judged.append(factor.reused_analysis)
        if factor.reused_analysis:
            raise SingularMatrixError("refused on the reused analysis (made up for the test)")
        return original(matrix, solve, factor)

    monkeypatch.setattr(solvers, "refuse_singular", refuse_on_reused)
    system = prepare_system(k, t, "pardiso")
    assert judged == [True, False]
    assert not system.solver.report.analysis_reused
    assert system.relative_residual(system.solve(loads), loads).max() < 1e-10


def test_tied_rows_leave_out_the_reference_dofs_nothing_is_attached_to(tied_bar):
    """Node 1 carries only loads: its six long rows add nothing to Tᵀ K T and are no unknowns of the solve."""
    k, t, _, _ = tied_bar
    assert np.array_equal(tied_rows(k, t), np.arange(6))
    x = np.random.default_rng(4).standard_normal(t.shape[1])
    assert np.allclose(constrained_stiffness(k, t, tied_rows(k, t)) @ x, reduced_stiffness(k, t) @ x, rtol=0,
                       atol=1e-12 * abs(k).max() * np.abs(x).max())


def test_the_released_bar_floats_and_six_grounded_dofs_hold_it(tied_bar_and_modes):
    """With its ties released the bar is free (six rigid modes); six grounded DOFs hold all six."""
    k, t, _, _, modes = tied_bar_and_modes
    operator = constrained_stiffness(k, t, tied_rows(k, t))
    m = operator.shape[0]
    k_qq = operator.kept[:m, :m].tocsr()
    q_modes = independent_modes(t, modes)
    assert q_modes.shape == (m, 6)
    assert np.abs(k_qq @ q_modes).max() < 1e-8 * abs(k_qq).max() * np.abs(q_modes).max()  # it floats
    ground = grounded_dofs(k_qq, q_modes)
    assert ground.size == 6 and ground.min() >= 0
    # no rigid motion of the bar leaves all six grounded DOFs at rest: K_qq + G is positive definite
    assert np.linalg.matrix_rank(q_modes[ground] / np.abs(q_modes[ground]).max(axis=0)) == 6


@needs_pardiso
@pytest.mark.slow  # the SuperLU reference of the dense tie blocks, as the multiplier test above
def test_cholesky_with_the_ties_as_a_low_rank_update_equals_the_eliminated_solve(tied_bar_and_modes):
    """The SPD path (Cholesky of the released, grounded stiffness; Woodbury update) gives Tᵀ K T's solution."""
    k, t, loads, _, modes = tied_bar_and_modes
    updated = prepare_system(k, t, "pardiso", near_null_space=lambda: modes)
    assert "mtype=2" in updated.solver_name and "rank-18 update" in updated.solver_name  # 2 × 6 ties + 6 grounded
    eliminated = prepare_system(k, t, "superlu", symmetrize=True)
    u, reference = updated.solve(loads), eliminated.solve(loads)
    assert np.all(np.abs(u - reference).max(axis=0) <= 1e-10 * np.abs(reference).max(axis=0))
    assert updated.relative_residual(u, loads).max() < 1e-10
    assert updated.condition_estimate() == pytest.approx(eliminated.condition_estimate(), rel=1e-6)
    without_modes = prepare_system(k, t, "pardiso")  # the released bar floats: the multiplier form instead
    assert "multipliers" in without_modes.solver_name


@needs_pardiso
def test_a_singular_tied_stiffness_is_refused_with_modes_too(tied_bar_and_modes):
    k, t, _, ground, modes = tied_bar_and_modes
    free = k - sp.csr_matrix((ground, (np.arange(6), np.arange(6))), shape=k.shape)  # nothing grounded
    with pytest.raises(SingularMatrixError, match="singular"):
        prepare_system(free.tocsr(), t, "pardiso", near_null_space=lambda: modes)


@needs_pardiso
def test_the_cholesky_path_serves_the_tied_stiffness_from_its_own_arrays(tied_bar_and_modes):
    """K' applied from B's upper triangle less the grounding (ReleasedStiffness) is K', dense and sparse, and gives
    the same 1-norm; the whole K' is not kept."""
    k, t, _, _, modes = tied_bar_and_modes
    served = prepare_system(k, t, "pardiso", near_null_space=lambda: modes).solver.matrix
    whole = constrained_stiffness(k, t, tied_rows(k, t))
    assert isinstance(served.kept, ReleasedStiffness)
    x = np.random.default_rng(5).standard_normal((t.shape[1], 2))
    scale = abs(whole.kept).max() * np.abs(x).max()
    assert np.allclose(served @ x, whole @ x, rtol=0, atol=1e-13 * scale)
    assert np.allclose(served @ x[:, 0], whole @ x[:, 0], rtol=0, atol=1e-13 * scale)
    assert np.array_equal(served.diagonal(), whole.diagonal())
    sparse = sp.random(whole.kept.shape[0], 5, density=0.01, random_state=6, format="csc")
    assert abs(served.kept @ sparse - whole.kept @ sparse).max() <= 1e-13 * abs(whole.kept).max()
    root = np.sqrt(whole.diagonal())
    assert served.scaled_one_norm(root, 97) == pytest.approx(whole.scaled_one_norm(root, 97), rel=1e-12)


def test_the_released_stiffness_is_stored_in_whole_3x3_blocks(tied_bar_and_modes):
    """B in PARDISO's block storage is B: the blocks expanded give B's upper triangle, the entries B lacks as zeros."""
    from rvcoax.fem.woodbury import _upper_blocks

    k, t, _, _, _ = tied_bar_and_modes
    operator = constrained_stiffness(k, t, tied_rows(k, t))
    m = operator.shape[0]
    b = operator.kept[:m, :m].tocsr()
    b.sum_duplicates()
    b.sort_indices()
    stored = _upper_blocks(b)
    assert m % 3 == 0 and stored.block_size == 3  # 3 DOFs per solid node; the reference nodes' 6 are left out and stored.data.shape[1:] == (3, 3)
    whole = sp.bsr_matrix((stored.data, stored.indices, stored.indptr), shape=(m, m)).toarray()
    assert np.array_equal(np.triu(whole), np.triu(b.toarray()))
    block_rows = np.repeat(np.arange(m // 3), np.diff(stored.indptr))
    assert np.all(stored.indices >= block_rows)  # the upper block triangle only


@needs_pardiso
def test_the_stiffness_moved_to_a_file_while_factorising_gives_the_same_solution(tied_bar, monkeypatch):
    """Above MOVE_OUT_BYTES the saddle-point path moves K into a file mapping once the saddle-point matrix exists:
    K keeps every entry, and the solution, its residual and the reactions (K u at fixed DOFs) are the same bits."""
    import mmap

    from rvcoax.fem import system

    k, t, loads, _ = tied_bar
    kept = prepare_system(k, t, "pardiso")
    u, residual = kept.solve(loads), kept.relative_residual(kept.solve(loads), loads)
    monkeypatch.setattr(system, "MOVE_OUT_BYTES", 0)
    moved_k = k.copy()
    moved = prepare_system(moved_k, t, "pardiso")
    base = moved_k.data
    while isinstance(base, np.ndarray):
        base = base.base
    assert isinstance(getattr(base, "obj", base), mmap.mmap)  # K's values now live in the file mapping
    assert (moved_k != k).nnz == 0 and np.array_equal(moved_k.indptr, k.indptr)
    v = moved.solve(loads)
    assert np.array_equal(v, u)
    assert np.array_equal(moved.relative_residual(v, loads), residual)
    assert np.array_equal(moved_k @ v, k @ u)


def test_auto_chooses_for_a_tied_system_without_the_plain_elasticity_amg_constants(tied_bar, monkeypatch):
    """The AMG cost constants were measured on plain elasticity (rvcoax.fem.solver_cost); a system with ties (a row
    of T with several entries) is chosen for with ``amg_cost_known=False``, a support elimination alone without."""
    from rvcoax.fem import solvers

    k, t, _, _ = tied_bar
    seen = []

    class Chosen(Exception):
        pass

    def spy(*args, **kwargs):
        seen.append(kwargs.get("amg_cost_known", True))
        raise Chosen  # the choice is what this test reads; nothing is solved

    monkeypatch.setattr(solvers, "choose_method", spy)
    supports = sp.eye(k.shape[0], format="csr")[:, 12:]  # the reference nodes' DOFs held: no ties left
    for elimination in (t, supports):
        with pytest.raises(Chosen):
            prepare_system(k, elimination, "auto")
    assert seen == [False, True]


@pytest.mark.skipif(not pardiso_available(), reason="MKL PARDISO not available")
def test_loads_solved_ahead_ride_in_the_set_ups_solve_call_and_equal_a_solve_of_their_own(tied_bar_and_modes, monkeypatch):
    """The Cholesky path's set-up solves the update's columns, the singularity test's first block and the caller's
    loads in one PARDISO call; solving those loads afterwards makes no call, and gives what a set-up without them
    solves (to the rounding of a different number of right-hand sides)."""
    k, t, loads, _, modes = tied_bar_and_modes
    calls = []
    phase = pardiso._phase

    def counting(handle, iparm, mtype, step, storage, *, rhs):
        if step == 33:
            calls.append(rhs.shape[1])
        return phase(handle, iparm, mtype, step, storage, rhs=rhs)

    monkeypatch.setattr(pardiso, "_phase", counting)
    plain = prepare_system(k, t, "pardiso", near_null_space=lambda: modes)
    assert plain.solver_name.startswith("pardiso (MKL PARDISO, SPD")  # the Cholesky path, not the multipliers
    plain_calls = list(calls)
    assert len(plain_calls) == 2  # the update's columns with the singularity test's first block; its second block
    expected = plain.solve(loads)
    calls.clear()
    ahead = prepare_system(k, t, "pardiso", near_null_space=lambda: modes, ahead=lambda: loads)
    assert calls == [plain_calls[0] + loads.shape[1], plain_calls[1]]  # more columns, no more calls
    set_up = len(calls)
    served = ahead.solve(loads)
    assert len(calls) == set_up  # no solve call of their own
    np.testing.assert_allclose(served, expected, rtol=0, atol=1e-12 * np.abs(expected).max())
    assert ahead.condition_estimate() == pytest.approx(plain.condition_estimate(), rel=1e-8)
    other = ahead.solve(loads[:, ::-1] * 2.0)  # columns it has not seen: one call, solved as any load
    assert len(calls) == set_up + 1
    np.testing.assert_allclose(other, 2.0 * expected[:, ::-1], rtol=0, atol=1e-12 * np.abs(expected).max())


def test_the_first_block_the_singularity_test_solves_is_the_one_a_set_up_can_solve_ahead():
    from rvcoax.fem.diagnostics import first_solve_block, singularity_and_condition

    a = sp.diags([np.full(40, -1.0), np.linspace(2.5, 40.0, 41), np.full(40, -1.0)], [-1, 0, 1], format="csc")
    asked = []

    def solve(block):
        asked.append(np.array(block))
        return spla.spsolve(a, block).reshape(block.shape)

    singularity_and_condition(a, solve)
    np.testing.assert_array_equal(asked[0], first_solve_block(a))
    assert len(asked) >= 2 and asked[1].shape[1] >= 2  # its second block depends on the first's solution
