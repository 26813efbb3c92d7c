"""The one rigid-body-modes function (rvcoax.fem.rigid_body) on frame DOFs (six per node) and on a mixed layout."""

import numpy as np
from frames import model, polyline, stiffness_matrix

from rvcoax.fem.equilibrium import frame_dof_table
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
