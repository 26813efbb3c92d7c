"""A condensed housing's Guyan mass: exact for the rigid-body inertia its attachments see."""

from __future__ import annotations

import numpy as np
import pytest

import rvcoax
from rvcoax.geometry.model.housings import condensed_housing

pytestmark = pytest.mark.slow


def test_guyan_mass_carries_the_housing_mass_that_moves_with_its_seats():
    rig = rvcoax.reference_from_geometry(("housings",))
    housing = rig.housings[0]
    condensed = condensed_housing(rig, housing)
    m = condensed.mass_per_density
    assert m.shape == condensed.matrix.shape and np.allclose(m, m.T)
    assert np.all(np.linalg.eigvalsh(m) > -1e-12 * np.abs(m).max())
    # a rigid vertical translation of every attachment: the static shapes move the housing between seats and bed;
    # the mass it carries lies between nothing and the whole housing (ρ V)
    k = len(housing.attachments_x_mm)
    r = np.zeros(6 * k)
    r[1::6] = 1.0
    carried = float(r @ m @ r)
    assert 0.0 < carried < condensed.volume_m3
    assert condensed.lowest_frequency_hz(rig.materials[housing.material].density_kg_per_m3) > 1000.0
