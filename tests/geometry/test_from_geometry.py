"""The reference rig read from geometry (rvcoax.reference_from_geometry): it solves in the beam and hybrid
models, the typed-in reading is unchanged, and each reading changes what it should."""

from __future__ import annotations

import numpy as np
import pytest

from rvcoax.geometry.rigfile import load_rig
from rvcoax.geometry.variants import reference_from_geometry
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.sweep import SweepSettings, run_sweep

CASES = (LoadCase(0.07, 10.0), LoadCase(1.43, 200.0))
COARSE = 20.0  # mm: the blocks' mesh in these tests (8 mm in the variant; the block is 1 % softer at 20 mm)


def y_max(sweep, which):
    return np.array([c.paths[which].y_max_mm for c in sweep.cases])


def test_readings_from_geometry_solve_and_change_what_they_should():
    typed = run_sweep(load_rig(), CASES)
    gears = run_sweep(reference_from_geometry(("gears",)), CASES)
    everything = run_sweep(reference_from_geometry(block_mesh_size_mm=COARSE), CASES)
    # nominal gear data remove the input stage's typed-in 2 % imbalance: the output path moves a few % (through
    # the reducer), the input path loses its torque-proportional lateral load
    assert y_max(gears, "output") == pytest.approx(y_max(typed, "output"), rel=0.05)
    assert not np.allclose(y_max(gears, "input"), y_max(typed, "input"), rtol=1e-3)
    for sweep in (gears, everything):
        assert all(c.equilibrium_error < 1e-8 for c in sweep.cases)
    # temperatures act at rest: measured from the aligned rig at rest, Y does not see them
    blocks_and_gears = run_sweep(reference_from_geometry(("gears", "housings"), COARSE), CASES)
    for which in ("input", "output"):
        assert y_max(everything, which) == pytest.approx(y_max(blocks_and_gears, which), rel=1e-9)


def test_unknown_reading_is_named():
    with pytest.raises(ValueError, match="unknown readings"):
        reference_from_geometry(("bearings_from_catalogue",))


@pytest.mark.slow
def test_reference_rig_from_geometry_runs_in_the_hybrid_model():
    sweep = run_sweep(reference_from_geometry(block_mesh_size_mm=COARSE), CASES[1:], SweepSettings(model="hybrid", mesh_size_mm=6.0))
    beam = run_sweep(reference_from_geometry(block_mesh_size_mm=COARSE), CASES[1:])
    assert y_max(sweep, "output") == pytest.approx(y_max(beam, "output"), rel=0.1)
