"""Six-component springs (bushings) between two nodes or between a node and ground.

A bushing sits at a point ``c``. Each attached node reaches ``c`` through a rigid arm, so the
relative motion at ``c`` is Δ = B_b u_b − B_a u_a with B = [[I, −[r]×], [0, I]], r = c − x_node.
The spring force is diag(k) Δ in global axes: a rigid-body motion of the pair stores no energy,
also when the nodes are not coincident. Ground bushings have no node ``a``. Bearings, mounts,
flexible couplings and gear meshes are all bushings with different stiffness components.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fem import DOFS_PER_NODE

GROUND = -1
"""Node index meaning "the fixed ground"."""


@dataclass(frozen=True)
class Bushings:
    """A table of bushings (SI).

    Parameters
    ----------
    node_a, node_b : (n,) int arrays
        Attached nodes; ``node_a == GROUND`` attaches ``node_b`` to the ground.
    point_m : (n, 3) array
        Location of each spring.
    stiffness : (n, 6) array
        Diagonal stiffness in global axes: kx, ky, kz (N/m) and krx, kry, krz (N·m/rad).
    """

    node_a: np.ndarray
    node_b: np.ndarray
    point_m: np.ndarray
    stiffness: np.ndarray


def _arm_matrix(arm: np.ndarray) -> np.ndarray:
    """B (n, 6, 6) mapping a node's DOFs to the motion of a rigidly attached point."""
    n = arm.shape[0]
    b = np.zeros((n, 6, 6))
    b[:, :3, :3] = np.eye(3)
    b[:, 3:, 3:] = np.eye(3)
    # u_point = u + θ × r = u − r × θ  →  −[r]× θ
    rx, ry, rz = arm[:, 0], arm[:, 1], arm[:, 2]
    b[:, 0, 4], b[:, 0, 5] = rz, -ry
    b[:, 1, 3], b[:, 1, 5] = -rz, rx
    b[:, 2, 3], b[:, 2, 4] = ry, -rx
    return b


def relative_motion_operator(coordinates: np.ndarray, bushings: Bushings):
    """Per bushing: the (6, 12) operator from [u_a, u_b] to Δ and the 12 DOF numbers.

    For ground bushings the first six columns are zero and their DOF numbers are −1.
    """
    point = np.asarray(bushings.point_m, dtype=float)
    node_a = np.asarray(bushings.node_a)
    node_b = np.asarray(bushings.node_b)
    grounded = node_a == GROUND
    coords_a = np.where(grounded[:, None], point, coordinates[np.where(grounded, 0, node_a)])
    b_a = _arm_matrix(point - coords_a)
    b_b = _arm_matrix(point - coordinates[node_b])
    b_a[grounded] = 0.0
    operator = np.concatenate([-b_a, b_b], axis=2)
    offsets = np.arange(DOFS_PER_NODE)
    dofs_a = np.where(grounded[:, None], -1, DOFS_PER_NODE * node_a[:, None] + offsets)
    dofs_b = DOFS_PER_NODE * node_b[:, None] + offsets
    return operator, np.concatenate([dofs_a, dofs_b], axis=1)


def stiffness_triplets(coordinates: np.ndarray, bushings: Bushings):
    """Global stiffness of all bushings as COO triplets ``(rows, cols, values)``."""
    if len(bushings.node_b) == 0:
        empty = np.zeros(0)
        return empty.astype(int), empty.astype(int), empty
    operator, dofs = relative_motion_operator(coordinates, bushings)
    k = np.einsum("eji,ej,ejk->eik", operator, np.asarray(bushings.stiffness, float), operator)
    rows = np.repeat(dofs, 12, axis=1).ravel()
    cols = np.tile(dofs, (1, 12)).ravel()
    keep = (rows >= 0) & (cols >= 0)
    return rows[keep], cols[keep], k.ravel()[keep]


def spring_forces(coordinates: np.ndarray, bushings: Bushings, displacement: np.ndarray) -> np.ndarray:
    """Force and moment carried by each bushing, diag(k) Δ, shape (n, 6) (N, N·m).

    It is what the spring exerts on node ``a`` (and the ground); node ``b`` gets the opposite.
    """
    operator, dofs = relative_motion_operator(coordinates, bushings)
    u = np.where(dofs >= 0, displacement[np.maximum(dofs, 0)], 0.0)
    delta = np.einsum("eij,ej->ei", operator, u)
    return np.asarray(bushings.stiffness, float) * delta
