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
