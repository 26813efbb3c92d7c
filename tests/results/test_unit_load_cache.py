"""A prepared model keeps its unit-load solutions: a sweep of a rig that differs only in a load parameter
solves only the load vectors that changed, and gives what a fresh model gives."""

from __future__ import annotations

import numpy as np

from rvcoax import load_rig, paper_cases
from rvcoax.geometry.parameters import with_parameters
from rvcoax.results.sweep import PreparedModel, prepare_model, run_sweep

IMBALANCE = "torque_lateral_loads.crankshaft_load_sharing.imbalance"


def test_a_load_parameter_change_solves_only_the_changed_load_vectors():
    rig = load_rig()
    cases = paper_cases()[:3]
    base = prepare_model(rig)
    solved_columns = []

    def counting(columns):
        solved_columns.append(np.shape(columns)[1] if np.ndim(columns) == 2 else 1)
        return base.solve(columns)

    prepared = PreparedModel(base.system, counting, base.solver_name, base.report)
    first = run_sweep(rig, cases, prepared=prepared, engineering=False)
    n_unit = solved_columns[0]
    trial = with_parameters(rig, {IMBALANCE: 0.3})
    changed = run_sweep(trial, cases, prepared=prepared, engineering=False)
    assert 0 < solved_columns[1] < n_unit  # only the vectors the imbalance enters
    again = run_sweep(rig, cases, prepared=prepared, engineering=False)
    assert len(solved_columns) == 2  # every unit load of the first rig was kept
    fresh = run_sweep(trial, cases, engineering=False)
    for cached, reference in ((changed, fresh), (again, first)):
        for a, b in zip(cached.cases, reference.cases):
            for shaft in a.paths:
                np.testing.assert_allclose(a.paths[shaft].uy_mm, b.paths[shaft].uy_mm, rtol=1e-12,
                                           atol=1e-12 * np.abs(b.paths[shaft].uy_mm).max())
    assert not np.allclose(changed.cases[-1].paths["output"].uy_mm, first.cases[-1].paths["output"].uy_mm)


def test_a_released_model_still_serves_its_cached_unit_loads_and_nothing_else():
    """run_sweep(release_solver=True) frees the factorisation after the unit loads and gives the same sweep; the
    released model answers the same loads from its cache and refuses a new solve."""
    import pytest

    from rvcoax.fem.errors import SolverError

    rig = load_rig()
    cases = paper_cases()[:2]
    kept = run_sweep(rig, cases, prepared=prepare_model(rig), engineering=False)
    prepared = prepare_model(rig)
    released = run_sweep(rig, cases, prepared=prepared, engineering=False, release_solver=True)
    for a, b in zip(released.cases, kept.cases):
        assert a.residual == b.residual
        for shaft in a.paths:
            assert np.array_equal(a.paths[shaft].uy_mm, b.paths[shaft].uy_mm)
    again = run_sweep(rig, cases, prepared=prepared, engineering=False)  # every unit load from the cache
    assert np.array_equal(again.cases[-1].paths["output"].uy_mm, kept.cases[-1].paths["output"].uy_mm)
    with pytest.raises(SolverError, match="released"):
        prepared.solve(np.ones(prepared.system.n_dofs))


def test_a_vector_repeated_in_one_block_is_solved_once():
    """The unit loads that several trial rigs share, asked for in one call, are solved once and copied."""
    rig = load_rig()
    base = prepare_model(rig)
    solved = []

    def counting(columns):
        solved.append(np.shape(columns)[1])
        return base.solve(columns)

    prepared = PreparedModel(base.system, counting, base.solver_name, base.report)
    loads = base.system.unit_loads
    names = [k for k in loads if np.any(loads[k])]
    block = np.column_stack([loads[k] for k in names] + [loads[names[0]], 2.0 * loads[names[-1]], loads[names[0]]])
    solutions = prepared.solve_unit_loads(block)
    assert solved == [len(names) + 1]  # the distinct vectors: each unit load once, and the doubled one
    np.testing.assert_array_equal(solutions[:, len(names)], solutions[:, 0])
    np.testing.assert_array_equal(solutions[:, -1], solutions[:, 0])
    np.testing.assert_allclose(solutions[:, len(names) + 1], 2.0 * solutions[:, len(names) - 1], rtol=1e-12,
                               atol=1e-12 * np.abs(solutions[:, len(names) - 1]).max())


def test_unit_loads_given_as_vectors_or_as_columns_are_the_same_loads():
    """solve_unit_loads takes an (n, m) array or m vectors: the same solutions, one cache, zero vectors never handed
    to the solver (their solution is 0 exactly)."""
    rig = load_rig()
    base = prepare_model(rig)
    handed = []

    def counting(columns):
        handed.append(np.array(columns, copy=True))
        return base.solve(columns)

    loads = base.system.unit_loads
    vectors = [loads[k] for k in loads] + [np.zeros(base.system.n_dofs)]
    from_vectors = PreparedModel(base.system, counting, base.solver_name, base.report).solve_unit_loads(vectors)
    assert len(handed) == 1 and all(np.any(column) for column in handed[0].T)
    assert not np.any(from_vectors[:, -1])
    prepared = PreparedModel(base.system, counting, base.solver_name, base.report)
    from_columns = prepared.solve_unit_loads(np.column_stack(vectors))
    assert np.array_equal(from_vectors, from_columns)
    assert np.array_equal(prepared.solve_unit_loads(vectors[::-1]), from_columns[:, ::-1])  # from the cache alone
    assert len(handed) == 2


def test_solutions_remembered_from_elsewhere_are_served_and_still_checked_against_the_stiffness():
    """PreparedModel.remember keeps solutions found without a solve (a calibration's affine combination); a sweep
    uses them, and its residual check K u - f refuses them when they are not solutions."""
    import pytest

    from rvcoax.results.sweep import ModelError

    rig = load_rig()
    cases = paper_cases()[:2]
    base = prepare_model(rig)
    reference = run_sweep(rig, cases, prepared=base, engineering=False)
    loads = [base.system.unit_loads[k] for k in base.system.unit_loads]
    loaded = [v for v in loads if v.any()]
    exact = base.solve_unit_loads(loaded)
    calls = []

    def counting(columns):
        calls.append(np.shape(columns))
        return base.solve(columns)

    served = PreparedModel(base.system, counting, base.solver_name, base.report)
    served.remember(loaded, exact.T)
    again = run_sweep(rig, cases, prepared=served, engineering=False)
    assert calls == []
    for a, b in zip(again.cases, reference.cases):
        np.testing.assert_array_equal(a.paths["output"].uy_mm, b.paths["output"].uy_mm)
    wrong = PreparedModel(base.system, counting, base.solver_name, base.report)
    wrong.remember(loaded, (1.01 * exact).T)
    with pytest.raises(ModelError, match="residual|equilibrium"):
        run_sweep(rig, cases, prepared=wrong, engineering=False)
