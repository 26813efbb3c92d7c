"""Craig–Bampton against the full finite-element model it condenses: a column clamped at its foot with a light mass
on its top (a pedestal whose own mass moves in the rig's modes: where Guyan's static-shape mass is too coarse).

The reference is the uncondensed solid model (4.3 k DOF) with the same top mass, solved directly; the reduced
models share its mesh, so every difference is the reduction's.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

from rvcoax.fem import solid
from rvcoax.fem.assembly import block_diagonal
from rvcoax.fem.craig_bampton import craig_bampton_reduction, interface_modes_needed
from rvcoax.fem.modal import ModalError, natural_modes
from rvcoax.geometry.housings import BlockGeometry, Reference
from rvcoax.geometry.model.condensed_housing import build_housing_model

E, NU, RHO = 2.1e11, 0.3, 7850.0
COLUMN = BlockGeometry("column", (0.0, 20.0), 20.0, -300.0, 0.0, mesh_size_mm=10.0)
TOP = [Reference((10.0, 0.0, 0.0), ("top", 0.0, 20.0), "rigid")]


@pytest.fixture(scope="module")
def pedestal(tmp_path_factory):
    """The model, its mass, the top mass (a tenth of the column's: 94 g, as a 10 mm disc) and the full model's
    lowest 8 frequencies."""
    model = build_housing_model(COLUMN, E, NU, TOP, cache_dir=tmp_path_factory.mktemp("cb"))
    mass = block_diagonal(model.n_dofs, [(6, solid.mass_matrix(model.basis, RHO))]).tocsr()
    top_kg = 0.1 * RHO * 0.02 * 0.02 * 0.3
    disc = 0.5 * top_kg * 0.01**2
    top = np.diag([top_kg, top_kg, top_kg, 2 * disc, disc, disc])
    with_top = mass.tolil()
    with_top[:6, :6] = with_top[:6, :6].toarray() + top
    full = natural_modes(model.stiffness, with_top.tocsr(), model.elimination, 8).frequencies_hz
    return model, mass, top, full


def _frequencies(reduction, top: np.ndarray) -> np.ndarray:
    m = reduction.mass.copy()
    m[:6, :6] += top
    return np.sqrt(scipy.linalg.eigh(reduction.full_stiffness(), m, eigvals_only=True)) / (2 * np.pi)


def test_guyan_is_coarse_and_craig_bampton_converges_to_the_full_model(pedestal):
    """Full model: 156.8, 156.8 Hz (first bending), 1002.3, 1004.2 Hz (second bending, the column's own mass
    moving), 2328.7 Hz (axial), 2783.5, 2796.1 Hz (torsion, third bending). Guyan (r = 0): the first pair within
    0.3 %, the second pair 43 % too high. Craig–Bampton with the first fixed-interface pair (1158 Hz): the
    second pair within 0.1 %; with 8 modes the lowest 7 within 0.5 % (0.35 % at the axial mode, whose
    fixed-interface partner is the 9th mode)."""
    model, mass, top, full = pedestal
    guyan = _frequencies(craig_bampton_reduction(model.stiffness, model.elimination, model.master_dofs, mass, 0,
                                                 method="superlu"), top)
    assert guyan[:2] == pytest.approx(full[:2], rel=5e-3)
    assert np.all(guyan[2:4] > 1.3 * full[2:4])  # Guyan misses the column's own dynamics
    two = craig_bampton_reduction(model.stiffness, model.elimination, model.master_dofs, mass, 2, method="superlu")
    assert two.interface_frequencies_hz() == pytest.approx([1158.0, 1158.0], rel=2e-3)
    assert _frequencies(two, top)[:4] == pytest.approx(full[:4], rel=1e-3)
    eight = _frequencies(craig_bampton_reduction(model.stiffness, model.elimination, model.master_dofs, mass, 8,
                                                 method="superlu"), top)
    assert eight[:7] == pytest.approx(full[:7], rel=5e-3)
    assert np.all(eight[:7] >= full[:7] * (1 - 1e-9))  # a Ritz reduction: every frequency from above


def test_automatic_rule_keeps_the_modes_below_three_times_the_band():
    omega2 = (2 * np.pi * np.array([1158.0, 1158.0, 3081.0, 3082.0])) ** 2
    assert interface_modes_needed(omega2, 1004.0) == 2  # below 3012 Hz
    assert interface_modes_needed(omega2, 157.0) == 0  # Guyan: its lowest is 7 × the band
    assert interface_modes_needed(omega2, 1100.0) == 4


def test_too_many_interface_modes_is_a_clear_error(pedestal):
    model, mass, _, _ = pedestal
    with pytest.raises(ModalError, match="besides its masters"):
        craig_bampton_reduction(model.stiffness, model.elimination, model.master_dofs, mass, 10**6, method="superlu")
