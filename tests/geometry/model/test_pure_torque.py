"""A pure torque does not move a shaft line sideways, at every fidelity.

With both load-sharing imbalances at zero the torques T1 and T2 are pure couples about the rig's axis.
A straight, round shaft line then twists without any lateral motion: exactly for beams, and for solids
because their meshes are mirror-symmetric about the planes through the axis (rvcoax.geometry.meshing;
a mesh without that symmetry moved the reference rig's output shaft 8.4e-12 m per N·m of T2).
"""

from __future__ import annotations

import numpy as np
import pytest

from rvcoax.fem.system import prepare_system
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model.assemble import assemble_rig
from rvcoax.geometry.rigfile import parse_rig_text, reference_rig_text

IMBALANCE = "imbalance = 0.02 "


@pytest.fixture(scope="module")
def balanced_rig():
    text = reference_rig_text()
    assert text.count(IMBALANCE) == 2  # the sun-gear and the crankshaft load sharing
    return parse_rig_text(text.replace(IMBALANCE, "imbalance = 0.0 "))


@pytest.mark.parametrize(("model", "mesh_size_mm"), [("beam", None), pytest.param("hybrid", 16.0, marks=pytest.mark.slow), pytest.param("solid", 40.0, marks=pytest.mark.slow)])
def test_pure_torque_gives_no_lateral_displacement(balanced_rig, model, mesh_size_mm):
    options = {} if mesh_size_mm is None else {"mesh_size_mm": mesh_size_mm}
    system = assemble_rig(balanced_rig, model, **options)
    reduced = prepare_system(system.stiffness, system.elimination)
    u = reduced.solve(np.column_stack([system.unit_loads["T1"], system.unit_loads["T2"]]))
    for column, torque in enumerate(("T1", "T2")):
        twist = np.abs(u[:, column]).max()  # the rotations and tangential displacements of the twist
        assert twist > 0.0
        for shaft in MEASURED_SHAFTS:
            y = system.probes[shaft].uy @ u[:, column]
            assert np.abs(y).max() <= 1e-10 * twist, f"{model}: {torque} moves the {shaft} shaft by {np.abs(y).max():.2e} m"
