"""Sparse SPD solvers: agreement of the methods, many right-hand sides, reports, auto choice, singularity."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from rvcoax.fem import solid, solvers
from rvcoax.fem.assembly import assemble_matrix
from rvcoax.fem.errors import SingularModelError
from rvcoax.fem.rigid_body import rigid_body_modes
from rvcoax.fem.solvers import SingularMatrixError, SolverError, SolverReport, pardiso_available, prepare
from rvcoax.geometry.meshing import SolidPartGeometry, mesh_part

HAS_PARDISO = pardiso_available()
METHODS = [
    "superlu",
    pytest.param("pardiso", marks=pytest.mark.skipif(not HAS_PARDISO, reason="MKL PARDISO not available")),
    "amg",
]


def laplacian_2d(n: int) -> sp.csr_matrix:
    """SPD 5-point Laplacian on an n × n grid plus a small shift."""
    one_d = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    eye = sp.identity(n)
    return (sp.kron(one_d, eye) + sp.kron(eye, one_d) + 1e-3 * sp.identity(n * n)).tocsr()


@pytest.fixture(scope="module")
def cantilever(tmp_path_factory):
    """Reduced stiffness, load vectors (3 cases) and rigid-body modes of a clamped solid bar."""
    geometry = SolidPartGeometry("bar", ((0.0, 160.0, 20.0, 0.0),), (), 8.0)
    mesh = mesh_part(geometry, cache_dir=tmp_path_factory.mktemp("meshes"))
    basis = solid.solid_basis(mesh)
    k = assemble_matrix(basis.N, [solid.stiffness_triplets(basis, 2.1e11, 0.3)])
    tip = mesh.facets_satisfying(lambda x: np.isclose(x[0], 0.160))
    clamp = mesh.facets_satisfying(lambda x: np.isclose(x[0], 0.0))
    free = np.setdiff1d(np.arange(basis.N), basis.get_dofs(clamp).all())
    loads = np.column_stack([
        solid.force_traction_vector(mesh, tip, [0.0, -1000.0, 0.0]),
        solid.force_traction_vector(mesh, tip, [500.0, 0.0, 200.0]),
        solid.torque_traction_vector(mesh, tip, [0, 0, 0], [1, 0, 0], 50.0),
    ])[free]
    modes = rigid_body_modes(basis.doflocs.T)[free]
    return k[free][:, free].tocsr(), loads, modes, k


def relative_difference(a, b):
    return np.abs(a - b).max() / np.abs(b).max()


@pytest.mark.parametrize("method", METHODS)
def test_methods_agree_on_a_small_spd_system(method):
    a = laplacian_2d(20)
    rhs = np.random.default_rng(1).normal(size=a.shape[0])
    reference = np.linalg.solve(a.toarray(), rhs)
    solver = prepare(a, method)
    assert relative_difference(solver.solve(rhs), reference) < 1e-8
    assert solver.report.name.startswith(method)


@pytest.mark.parametrize("method", METHODS)
def test_methods_agree_on_a_solid_cantilever(cantilever, method):
    k, loads, modes, _ = cantilever
    reference = prepare(k, "superlu").solve(loads)
    solution = prepare(k, method, near_null_space=modes).solve(loads)
    tolerance = 10 * solvers.AMG_ACCURACY if method == "amg" else 1e-8  # AMG: to its stated accuracy
    for j in range(loads.shape[1]):
        assert relative_difference(solution[:, j], reference[:, j]) < tolerance


@pytest.mark.parametrize("accuracy", [1e-4, 1e-6, 1e-8])
def test_amg_outputs_agree_with_the_direct_solve_to_the_stated_accuracy(cantilever, accuracy):
    """The stopping rule's promise: relative energy-norm error ≤ accuracy, and so the tip deflection."""
    k, loads, modes, _ = cantilever
    reference = prepare(k, "superlu").solve(loads)
    solver = prepare(k, "amg", near_null_space=modes, accuracy=accuracy)
    solution = solver.solve(loads)
    for j in range(loads.shape[1]):
        error = solution[:, j] - reference[:, j]
        energy_error = np.sqrt(error @ (k @ error) / (reference[:, j] @ loads[:, j]))
        assert energy_error <= accuracy
        assert relative_difference(solution[:, j], reference[:, j]) <= accuracy
        assert 0.0 < solver.report.error_estimates[j] <= accuracy
    assert max(solver.report.relative_residuals) <= solvers.AMG_RESIDUAL_LIMIT
    # a looser accuracy takes fewer iterations: the rule is not a fixed tiny residual
    if accuracy > 1e-8:
        tight = prepare(k, "amg", near_null_space=modes, accuracy=accuracy * 1e-4)
        tight.solve(loads)
        assert sum(tight.report.iterations) > sum(solver.report.iterations)


def test_conjugate_gradients_refuses_an_indefinite_matrix():
    indefinite = sp.diags([1.0, 2.0, -1.0]).tocsr()
    with pytest.raises(SolverError, match="not positive definite"):
        solvers.conjugate_gradients(indefinite, np.ones(3), lambda r: r.copy())


def test_amg_builds_one_hierarchy_for_every_right_hand_side(cantilever, monkeypatch):
    from rvcoax.fem import amg

    k, loads, modes, _ = cantilever
    builds = []
    real = amg.smoothed_aggregation

    def counting(*args, **kwargs):
        builds.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(amg, "smoothed_aggregation", counting)
    solver = prepare(k, "amg", near_null_space=modes)
    together = solver.solve(loads)
    for j in range(loads.shape[1]):
        np.testing.assert_array_equal(solver.solve(loads[:, j]), together[:, j])
    assert len(builds) == 1 and len(solver.report.iterations) == 1


@pytest.mark.parametrize("method", METHODS)
def test_many_right_hand_sides_equal_single_solves(cantilever, method):
    k, loads, modes, _ = cantilever
    solver = prepare(k, method, near_null_space=modes)
    together = solver.solve(loads)
    assert together.shape == loads.shape
    assert len(solver.report.relative_residuals) == loads.shape[1]
    for j in range(loads.shape[1]):
        single = solver.solve(loads[:, j])
        assert single.shape == (k.shape[0],)
        assert relative_difference(together[:, j], single) < 1e-10


@pytest.mark.parametrize("method", METHODS)
def test_report_fields_are_filled(cantilever, method):
    k, loads, modes, _ = cantilever
    solver = prepare(k, method, near_null_space=modes)
    before = solver.report
    assert isinstance(before, SolverReport)
    assert before.solve_seconds == 0.0 and before.relative_residuals == ()
    solver.solve(loads)
    report = solver.report
    assert report.name.startswith(method)
    assert report.n_dofs == k.shape[0]
    assert report.setup_seconds > 0.0 and report.solve_seconds > 0.0
    assert report.peak_memory_MB > 0.0 and report.peak_memory_increase_MB >= 0.0
    assert len(report.relative_residuals) == loads.shape[1]
    assert max(report.relative_residuals) < (solvers.AMG_RESIDUAL_LIMIT if method == "amg" else 1e-9)
    if method == "amg":
        assert len(report.iterations) == loads.shape[1] and min(report.iterations) > 0
        assert len(report.error_estimates) == loads.shape[1]
    else:
        assert report.iterations == () and report.error_estimates == ()


def test_zero_right_hand_side_gives_zero(cantilever):
    k, _, modes, _ = cantilever
    for method in ("superlu", "amg"):
        x = prepare(k, method, near_null_space=modes).solve(np.zeros(k.shape[0]))
        assert not np.any(x)


def test_auto_picks_by_size(monkeypatch):
    a = laplacian_2d(10)  # 100 DOFs
    assert prepare(a, "auto").report.name.startswith("superlu")
    # above the SuperLU range the cost model decides: a tiny system factorises faster than AMG sets up
    if HAS_PARDISO:
        assert prepare(a, "auto", superlu_max_dofs=50).report.name.startswith("pardiso")
    # without MKL everything above the SuperLU range goes to AMG
    monkeypatch.setattr(solvers, "pardiso_available", lambda: False)
    assert solvers.choose_method(30_000) == "amg"
    assert solvers.choose_method(10_000) == "superlu"
    assert prepare(a, "auto", superlu_max_dofs=50).report.name.startswith("amg")


def crossover(model, n_rhs: int) -> int:
    """The size where the model's PARDISO and AMG times are equal (bisection on the model, not on runs)."""
    low, high = 20_000, 100_000_000
    while high - low > 1:
        middle = (low + high) // 2
        nnz = solvers.NONZEROS_PER_ROW * middle
        if model.pardiso_seconds(middle, n_rhs) <= model.amg_seconds(nnz, n_rhs, middle):
            low = middle
        else:
            high = middle
    return low


@pytest.mark.skipif(not HAS_PARDISO, reason="MKL PARDISO not available")
def test_the_cost_model_choice_flips_where_its_constants_say():
    model = solvers.COST_MODEL
    plenty = 1e15
    for n_rhs in (1, 7, 40):
        n = crossover(model, n_rhs)
        assert solvers.choose_method(n, n_rhs=n_rhs, available_bytes=plenty) == "pardiso"
        assert solvers.choose_method(n + 2, n_rhs=n_rhs, available_bytes=plenty) == "amg"
    # more right-hand sides favour the factorisation (each costs a substitution, not a CG run)
    assert crossover(model, 1) < crossover(model, 7) < crossover(model, 40)
    one = crossover(model, 1)
    assert solvers.choose_method(2 * one, n_rhs=1, available_bytes=plenty) == "amg"
    assert solvers.choose_method(2 * one, n_rhs=40, available_bytes=plenty) == "pardiso"
    # memory: PARDISO is dropped where its factor would not fit
    needed = model.pardiso_bytes(100_000, solvers.NONZEROS_PER_ROW * 100_000)
    assert solvers.choose_method(100_000, n_rhs=9, available_bytes=2 * needed) == "pardiso"
    assert solvers.choose_method(100_000, n_rhs=9, available_bytes=0.5 * needed) == "amg"
    # nonzeros: a denser matrix makes every CG iteration dearer
    assert solvers.choose_method(one, nonzeros=10 * solvers.NONZEROS_PER_ROW * one, available_bytes=plenty) == "pardiso"
    # the defaults on this machine class: small systems unchanged; a 100 k system factorised for a sweep's nine
    # unit loads, solved by AMG-CG for one right-hand side (the cantilever's measured constants)
    assert solvers.choose_method(19_999) == "superlu"
    assert solvers.choose_method(100_000, n_rhs=9, available_bytes=plenty) == "pardiso"
    assert solvers.choose_method(100_000, available_bytes=plenty) == "amg"
    # a system the AMG constants were not measured on (a rig's ties): AMG only where PARDISO does not fit
    assert solvers.choose_method(100_000, available_bytes=plenty, amg_cost_known=False) == "pardiso"
    assert solvers.choose_method(10 * one, n_rhs=1, available_bytes=plenty, amg_cost_known=False) == "pardiso"
    assert solvers.choose_method(100_000, available_bytes=0.5 * needed, amg_cost_known=False) == "amg"


@pytest.mark.parametrize("method", [m for m in METHODS if m != "amg"])
def test_singular_matrix_raises(cantilever, method):
    _, _, _, unconstrained = cantilever  # the free solid: six rigid-body motions
    # every time: PARDISO's threaded factorisation of this matrix succeeds about one run in five,
    # its rigid-body pivots rounded to tiny positive values, fails with -4 or -13 otherwise
    for _ in range(12):
        with pytest.raises(SingularMatrixError, match="singular"):
            prepare(unconstrained, method)
    # two springs in series, nothing grounded: exactly singular
    springs = sp.csr_matrix(np.array([[1.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]))
    with pytest.raises(SingularMatrixError):
        prepare(springs, method)
    # the beam model's error type catches it too
    with pytest.raises(SingularModelError):
        prepare(springs, method)


def test_bad_input_is_rejected():
    a = laplacian_2d(5)
    with pytest.raises(SolverError, match="unknown solver method"):
        prepare(a, "cholesky")
    with pytest.raises(ValueError, match="square"):
        prepare(sp.csr_matrix(np.ones((2, 3))))
    with pytest.raises(TypeError):
        prepare(np.eye(3))
    with pytest.raises(ValueError, match="right-hand side"):
        prepare(a).solve(np.ones(7))


def test_amg_reports_non_convergence(cantilever):
    k, loads, modes, _ = cantilever
    with pytest.raises(SolverError, match="did not reach"):
        prepare(k, "amg", near_null_space=modes, maxiter=2).solve(loads[:, 0])
    with pytest.raises(SolverError, match="accuracy"):
        prepare(k, "amg", near_null_space=modes, accuracy=0.0)


@pytest.mark.parametrize("method", METHODS)
def test_release_frees_the_solver(cantilever, method):
    k, loads, modes, _ = cantilever
    with prepare(k, method, near_null_space=modes) as solver:
        solver.solve(loads[:, 0])
    with pytest.raises(SolverError, match="released"):
        solver.solve(loads[:, 0])
    solver.release()  # twice is harmless


@pytest.mark.skipif(not pardiso_available(), reason="MKL PARDISO not available")
def test_a_new_stiffness_of_the_same_mesh_is_factorised_on_the_pooled_analysis(cantilever):
    """A Monte Carlo sample or a stiffness calibration's trial: another matrix, the same pattern."""
    from rvcoax.fem import pardiso

    k, loads, _, _ = cantilever
    pardiso.clear_analysis_pool()
    scale = 1.0 + 0.3 * np.random.default_rng(0).random(k.shape[0])
    stiffer = sp.csr_matrix(k, copy=True)  # D K D: SPD, the same stored pattern, other values
    stiffer.data *= scale[np.repeat(np.arange(k.shape[0]), np.diff(stiffer.indptr))] * scale[stiffer.indices]
    with prepare(k, "pardiso") as first:
        assert not first.report.analysis_reused
        first.solve(loads)
    with prepare(stiffer, "pardiso") as second:  # the first one's analysis, released into the pool
        assert second.report.analysis_reused
        x = second.solve(loads)
    pardiso.set_analysis_reuse(False)
    try:
        with prepare(stiffer, "pardiso") as fresh:
            assert not fresh.report.analysis_reused
            reference = fresh.solve(loads)
    finally:
        pardiso.set_analysis_reuse(True)
    assert np.abs(x - reference).max() <= 1e-12 * np.abs(reference).max()


@pytest.mark.skipif(not pardiso_available(), reason="MKL PARDISO not available")
def test_pardiso_condition_estimate_on_request_is_the_one_made_at_set_up(cantilever):
    """``estimate_condition=False`` leaves the estimate for later: the same number when it is asked for, the same
    solution, and a singular matrix refused as before (the inverse iteration still runs at set-up)."""
    k, loads, _, unconstrained = cantilever
    with prepare(k, "pardiso") as eager, prepare(k, "pardiso", estimate_condition=False) as lazy:
        assert lazy._condition is None
        np.testing.assert_allclose(lazy.solve(loads), eager.solve(loads), rtol=0.0, atol=1e-12 * np.abs(eager.solve(loads)).max())
        assert lazy.condition_estimate() == pytest.approx(eager.condition_estimate(), rel=1e-9)
    for _ in range(4):  # the threaded factorisation of the free solid succeeds about one run in five
        with pytest.raises(SingularMatrixError, match="singular"):
            prepare(unconstrained, "pardiso", estimate_condition=False)


def test_free_heap_memory_goes_back_to_the_system():
    """What freed arrays below the mmap threshold leave resident is given back, and nothing in use is touched."""
    import sys

    from rvcoax.fem.memory import return_free_heap

    if not sys.platform.startswith("linux"):
        assert return_free_heap() in (True, False)
        return

    def resident_mb() -> float:
        with open("/proc/self/status", encoding="ascii") as status:
            return next(int(line.split()[1]) / 1024 for line in status if line.startswith("VmRSS:"))

    kept = np.arange(1000.0)
    warm = np.ones(1_000_000)  # an 8 MB mapped block freed: glibc's mmap threshold rises to its size
    del warm
    baseline = resident_mb()
    # 2 MB arrays (on the heap now), interleaved with 96 kB survivors so that the heap cannot shrink from its top
    blocks, survivors = [], []
    for _ in range(150):
        blocks.append(np.ones(250_000))
        survivors.append(np.ones(12_000))
    del blocks
    retained = resident_mb() - baseline  # ~300 MB with glibc's default thresholds (none when MALLOC_ options map all)
    assert return_free_heap()
    if retained > 200.0:
        assert resident_mb() - baseline < retained - 200.0
    assert kept.sum() == 499_500.0 and all(s.sum() == 12_000.0 for s in survivors)


def test_solved_ahead_serves_the_columns_it_knows_and_solves_the_others_in_one_call():
    from rvcoax.fem.solvers import SolvedAhead

    rng = np.random.default_rng(3)
    known_rhs = rng.standard_normal((10, 3))
    calls = []

    def solve(block):
        calls.append(block.shape[1])
        return 2.0 * block, (7,), (0.5,)

    solve_ahead = SolvedAhead(solve, known_rhs, 2.0 * known_rhs)
    x, iterations, estimates = solve_ahead(known_rhs[:, [2, 0]])
    np.testing.assert_array_equal(x, 2.0 * known_rhs[:, [2, 0]])
    assert calls == [] and iterations == () and estimates == ()
    fresh = rng.standard_normal((10, 2))
    block = np.column_stack([fresh[:, 0], known_rhs[:, 1], fresh[:, 1]])
    x, iterations, _ = solve_ahead(block)
    np.testing.assert_array_equal(x, 2.0 * block)
    assert calls == [2] and iterations == (7,)  # the two unknown columns, in one call
    nearly = known_rhs[:, :1] * (1.0 + 1e-16 * rng.standard_normal((10, 1)) + 2.3e-16)
    solve_ahead(nearly)  # other numbers, however close: solved
    assert calls == [2, 1]
