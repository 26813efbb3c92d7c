"""The six rigid-body motions of a set of DOFs: the near-null space of an unsupported structure.

One function for every DOF layout: each DOF has a position and a component (0–2 translation along
x/y/z, 3–5 rotation about x/y/z), so frame nodes (six DOFs), solid nodes (three DOFs) and a mix of
both are treated alike. Used as AMG's near-null space (solid and whole-rig models) and as the trial
motions of the free-motion test (:func:`rvcoax.fem.diagnostics.find_free_motions`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["rigid_body_modes"]


def rigid_body_modes(position, component=None, *, centre=None, length: float = 1.0) -> np.ndarray:
    """Rigid-body modes (N, 6): translations along x, y, z, then rotations about x, y, z through ``centre``.

    Parameters
    ----------
    position : (N, 3) array
        Position of the node each DOF belongs to (m).
    component : (N,) int array, optional
        Component of each DOF, 0–5 (0–2 translations, 3–5 rotations); default ``arange(N) % 3``, the
        interleaved numbering of scikit-fem's vector bases (:func:`rvcoax.fem.solid.dof_components`).
    centre : (3,) array, optional
        The point the rotations turn about; default the mean of ``position``.
    length : float
        The rotation modes are divided by it (the rotation θ = 1 / ``length`` moves points at distance
        ``length`` by about 1, as the translations do).

    Returns
    -------
    (N, 6) array
        Column k < 3 is 1 on the DOFs of component k; column 3 + k is θ e_k × (x − centre) on the
        translations and θ on the rotations about axis k, θ = 1 / ``length``.
    """
    x = np.asarray(position, dtype=float)
    n = x.shape[0]
    c = np.arange(n) % 3 if component is None else np.asarray(component)
    r = x - (x.mean(axis=0) if centre is None else np.asarray(centre, dtype=float))
    modes = np.zeros((n, 6))
    translational = np.flatnonzero(c < 3)
    modes[translational, c[translational]] = 1.0
    for k in range(3):
        axis = np.zeros(3)
        axis[k] = 1.0
        motion = np.cross(axis, r)  # θ e_k × (x − centre)
        modes[translational, 3 + k] = motion[translational, c[translational]] / length
        modes[c == 3 + k, 3 + k] = 1.0 / length
    return modes
