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


def test_a_case_unbalance_superposed_from_the_unit_products_is_k_times_its_displacement():
    """A superposition sweep checks K u − f of a case as Σ w_k (K u_k − f_k) (linearity): the superposed products equal
    K times the superposed displacement to 1e-12 of the largest entry, and a product is formed once per distinct
    solution (a column of zeros has the product 0 without one)."""
    from rvcoax.geometry.model.loads import UNIT_LOADS, gear_contact_torques, superpose

    rig = load_rig()
    prepared = prepare_model(rig)
    loads = prepared.system.unit_loads
    unit = prepared.solve_unit_loads([loads[k] for k in UNIT_LOADS])
    formed = []
    stiffness = prepared.system.stiffness

    class Counting:  # K as the model holds it, counting the vectors multiplied
        shape = stiffness.shape

        def __matmul__(self, other):
            formed.append(1 if np.ndim(other) == 1 else np.shape(other)[1])
            return stiffness @ other

    import dataclasses

    counted = dataclasses.replace(prepared, system=dataclasses.replace(prepared.system, stiffness=Counting()))
    products = counted.stiffness_products(unit)
    nonzero = [i for i in range(unit.shape[1]) if np.any(unit[:, i])]
    assert sum(formed) == len(nonzero) and 0 < len(nonzero) < len(UNIT_LOADS)
    again = counted.stiffness_products(np.column_stack([unit, unit[:, nonzero[0]]]))
    assert sum(formed) == len(nonzero)  # every product from the cache, the repeated column too
    assert np.array_equal(again[:, :-1], products) and np.array_equal(again[:, -1], products[:, nonzero[0]])
    assert not np.any(products[:, [i for i in range(unit.shape[1]) if i not in nonzero]])
    by_name = {k: products[:, i] for i, k in enumerate(UNIT_LOADS)}
    unit_by_name = {k: unit[:, i] for i, k in enumerate(UNIT_LOADS)}
    contact = gear_contact_torques(rig)
    for case in paper_cases()[::6]:
        u = superpose(unit_by_name, case.input_torque_Nm, case.output_torque_Nm, False, contact)
        direct = stiffness @ u
        superposed = superpose(by_name, case.input_torque_Nm, case.output_torque_Nm, False, contact)
        # relative to the terms K u is summed from, |K| |u| (what floating point resolves: K u ≈ f cancels ~1e4 of
        # them on this rig), not to K u itself
        terms = np.abs(stiffness) @ np.abs(u)
        assert np.abs(superposed - direct).max() <= 1e-12 * terms.max()
        assert not np.allclose(superposed, stiffness @ (1.001 * u), rtol=1e-9, atol=1e-9 * terms.max())


def test_a_sum_that_leaves_out_the_zero_unit_vectors_is_superpose_bit_for_bit():
    """The sweep superposes only the unit vectors that are not zero; its f and u are superpose()'s, bit for bit (signed
    zeros included), for every case of the paper's table and for negative torques."""
    from rvcoax.geometry.model.loads import UNIT_LOADS, case_weights, gear_contact_torques, superpose
    from rvcoax.loadcases.cases import LoadCase
    from rvcoax.results.sweep import _superposed

    rig = load_rig()
    prepared = prepare_model(rig)
    loads = prepared.system.unit_loads
    unit = prepared.solve_unit_loads([loads[k] for k in UNIT_LOADS])
    contact = gear_contact_torques(rig)
    n = prepared.system.n_dofs
    for vectors in (loads, {k: unit[:, i] for i, k in enumerate(UNIT_LOADS)}):
        nonzero = {k: v for k, v in vectors.items() if np.any(v)}
        assert 0 < len(nonzero) < len(vectors)
        for case in (*paper_cases(), LoadCase(-1.2, -150.0), LoadCase(0.0, 0.0)):
            torques = case.input_torque_Nm, case.output_torque_Nm
            mine = _superposed(nonzero, case_weights(*torques, include_rest=True, contact_torques_Nm=contact), n)
            theirs = superpose(vectors, *torques, False, contact)
            assert mine.tobytes() == theirs.tobytes()


def test_a_corrupted_cached_unit_solution_is_still_refused():
    """The K u kept per unit solution belongs to the very bytes of that solution: a cached solution changed after its
    product was formed gives a new product, and the case's residual check refuses it with the message (and residual)
    it gave when K u was formed per case."""
    import hashlib

    import pytest

    from rvcoax.results.sweep import ModelError

    rig = load_rig()
    cases = paper_cases()[:2]
    prepared = prepare_model(rig)
    good = run_sweep(rig, cases, prepared=prepared, engineering=False)
    assert prepared.products and good.cases[-1].residual < 1e-9
    key = hashlib.sha256(np.ascontiguousarray(prepared.system.unit_loads["T2"])).digest()
    prepared.solved[key] *= 1.01  # a unit solution 1 % off, after the sweep formed its K u
    with pytest.raises(ModelError, match=r"case T1=1.43Nm_T2=200Nm: relative residual 0.0098 exceeds 1e-06"):
        run_sweep(rig, cases, prepared=prepared, engineering=False)


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


def test_a_rig_with_fixed_dofs_gets_the_same_reactions_by_superposition_as_solved_case_by_case():
    """With a condensed housing the frame has fixed DOFs (the housing's bed): a superposition sweep sums the case's
    K u − f there from the unit solutions' and its residual from their reductions Tᵀ(K u_k − f_k); the bed's reaction
    rows and Y agree with the direct method's, which forms K u − f per case, and both checks pass."""
    import tomllib

    from rvcoax.geometry.rigfile import parse_rig, reference_rig_text
    from rvcoax.results.sweep import SweepSettings

    data = tomllib.loads(reference_rig_text())
    data["mounts"] = [m for m in data["mounts"] if m["name"] != "input_block_base"]
    data["housings"] = [{  # the reference rig's input bearing block from geometry (docs/rig-file.md)
        "name": "input_block", "part": "input_bearing_block", "material": "HT200", "x_mm": [248.0, 320.0],
        "width_mm": 90.0, "height_above_bed_mm": 100.0, "top_above_axis_mm": 45.0, "bore_diameter_mm": 47.0,
        "foot_thickness_mm": 15.0, "foot_width_mm": 150.0, "attachments_x_mm": [255.0, 315.0],
        "attachment_width_mm": 14.0, "mesh_size_mm": 20.0}]
    rig = parse_rig(data, "test")
    cases = paper_cases()[::5]
    prepared = prepare_model(rig)
    assert prepared.system.frame.structure.fixed_dofs.size
    superposed = run_sweep(rig, cases, prepared=prepared)
    direct = run_sweep(rig, cases, SweepSettings(method="direct"), prepared=prepared)
    for a, b in zip(superposed.cases, direct.cases):
        scale = max(abs(v) for r in b.engineering.reactions for v in (*r.force_N, *r.force_change_N))
        rows = {r.name: r for r in a.engineering.reactions}
        bed = rows["input_block"]
        assert bed.kind == "housing" and max(abs(v) for v in bed.force_N) > 1e-3 * scale
        for r in b.engineering.reactions:
            for x, y in zip((*rows[r.name].force_N, *rows[r.name].force_change_N), (*r.force_N, *r.force_change_N)):
                assert abs(x - y) <= 1e-12 * scale
        assert a.equilibrium_error < 1e-9 and a.residual < 1e-9
        np.testing.assert_allclose(a.paths["output"].uy_mm, b.paths["output"].uy_mm, rtol=1e-9,
                                   atol=1e-9 * np.abs(b.paths["output"].uy_mm).max())
