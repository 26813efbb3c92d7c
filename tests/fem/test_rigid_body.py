"""The one rigid-body-modes function (rvcoax.fem.rigid_body) on frame DOFs (six per node) and on a mixed layout."""

import numpy as np
from frames import model, polyline, stiffness_matrix

from rvcoax.fem.equilibrium import DofTable, frame_dof_table, resultant_of
from rvcoax.fem.rigid_body import rigid_body_modes
from rvcoax.fem.sections import CircularSection


def test_the_modes_of_a_free_bent_frame_store_no_energy():
    """A free L-shaped frame of beams: K m = 0 for the six modes (to rounding), and they are independent."""
    coordinates, beams = polyline([[0, 0, 0], [0.4, 0, 0], [0.4, 0.3, 0.1]], 6, CircularSection(0.02))
    k = stiffness_matrix(model(coordinates, beams))
    table = frame_dof_table(coordinates)
    modes = rigid_body_modes(table.position, table.component, length=0.5)
    scale = abs(k).max() * np.abs(modes).max(axis=0)
    assert np.all(np.abs(k @ modes).max(axis=0) <= 1e-9 * scale)
    assert np.linalg.matrix_rank(modes) == 6


def test_a_rotation_moves_points_as_theta_cross_r_and_turns_the_rotation_dofs():
    position = np.array([[1.0, 2.0, 3.0]] * 6 + [[0.0, 0.0, 0.0]] * 3)
    component = np.array([0, 1, 2, 3, 4, 5, 0, 1, 2])
    modes = rigid_body_modes(position, component, centre=[0.0, 0.0, 0.0], length=2.0)
    # rotation about z by 1/2: u = (−y, x, 0) / 2 at (1, 2, 3), θz = 1/2
    np.testing.assert_array_equal(modes[:6, 5], [-1.0, 0.5, 0.0, 0.0, 0.0, 0.5])
    np.testing.assert_array_equal(modes[:6, 0], [1.0, 0, 0, 0, 0, 0])
    assert not modes[6:, 3:].any()  # the centre does not move under a rotation
    # default: centre at the mean position, components interleaved x, y, z
    default = rigid_body_modes(position[6:] + 1.0)
    np.testing.assert_array_equal(default[:, :3], np.eye(3))


def test_resultant_is_the_sum_of_forces_and_of_their_moments_about_the_origin():
    """resultant_of: (Σ f, Σ p × f + Σ m) over a DOF table of mixed three- and six-DOF nodes, from per-table DOF lists."""
    rng = np.random.default_rng(11)
    position = rng.normal(size=(300, 3))
    component = rng.integers(0, 6, 300)
    table = DofTable(position, component)
    vector = rng.normal(size=300)
    force = np.zeros((300, 3))
    force[component < 3, component[component < 3]] = vector[component < 3]
    moment = np.cross(position, force).sum(axis=0) + [vector[component == 3 + a].sum() for a in range(3)]
    np.testing.assert_allclose(resultant_of(table, vector), np.concatenate([force.sum(axis=0), moment]),
                               rtol=0, atol=1e-12 * np.abs(vector).sum() * np.abs(position).max())
    assert table.extent_m == max(float(np.ptp(position, axis=0).max()), 1.0)
