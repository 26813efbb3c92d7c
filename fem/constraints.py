"""Linear multi-point constraints by elimination: u = T q.

Fixed DOFs (u_i = 0) and rigid links (slave node follows a master node as a rigid body:
u_s = u_m + θ_m × (x_s − x_m), θ_s = θ_m) are both written as slave DOFs expressed in other
DOFs. ``T`` maps the independent DOFs ``q`` to all DOFs; the reduced system is Tᵀ K T q = Tᵀ f.
The same mechanism will carry beam–solid ties.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.contribution import Contribution

__all__ = ["RigidLinks", "elimination_matrix", "rigid_link_equations"]


@dataclass(frozen=True)
class RigidLinks:
    """Slave nodes rigidly attached to master nodes (all six DOFs)."""

    master: np.ndarray
    slave: np.ndarray

    def contribution(self, coordinates: np.ndarray, n_dofs: int, gravity_direction) -> Contribution:
        """The links' constraint rows (:func:`rigid_link_equations`)."""
        return Contribution(equations=rigid_link_equations(coordinates, self))

    def mass_contribution(self, coordinates: np.ndarray) -> None:
        """None: a rigid link carries no mass."""
        return None


def rigid_link_equations(coordinates: np.ndarray, links: RigidLinks) -> dict[int, dict[int, float]]:
    """Slave DOF → {master DOF: coefficient} for each rigid link."""
    equations: dict[int, dict[int, float]] = {}
    for master, slave in zip(np.asarray(links.master, int), np.asarray(links.slave, int)):
        r = coordinates[slave] - coordinates[master]
        m = DOFS_PER_NODE * master
        s = DOFS_PER_NODE * slave
        # u_s = u_m + θ × r:  (θy rz − θz ry, θz rx − θx rz, θx ry − θy rx)
        equations[s + 0] = {m + 0: 1.0, m + 4: r[2], m + 5: -r[1]}
        equations[s + 1] = {m + 1: 1.0, m + 5: r[0], m + 3: -r[2]}
        equations[s + 2] = {m + 2: 1.0, m + 3: r[1], m + 4: -r[0]}
        for k in range(3, 6):
            equations[s + k] = {m + k: 1.0}
    return equations


def elimination_matrix(n_dofs: int, fixed_dofs, equations: dict[int, dict[int, float]]):
    """Build T (n_dofs × n_free, CSR) and the list of independent DOFs.

    Parameters
    ----------
    n_dofs : int
    fixed_dofs : iterable of int
        DOFs held at zero.
    equations : dict
        Slave DOF → {DOF: coefficient}; a right-hand DOF may itself be a slave (chains are
        resolved) but cycles are an error.
    """
    fixed = set(int(d) for d in fixed_dofs)
    both = sorted(fixed & set(equations))
    if both:
        raise ValueError(f"DOFs {both[:6]} are both held fixed and driven by a rigid link; "
                         "fix the master node instead")
    resolved: dict[int, dict[int, float]] = {}

    def resolve(dof: int, stack: tuple[int, ...] = ()) -> dict[int, float]:
        if dof in fixed:
            return {}
        if dof not in equations:
            return {dof: 1.0}
        if dof in resolved:
            return resolved[dof]
        if dof in stack:
            raise ValueError(f"constraint equations form a cycle through DOF {dof}")
        combined: dict[int, float] = {}
        for other, coefficient in equations[dof].items():
            for base, c in resolve(other, stack + (dof,)).items():
                combined[base] = combined.get(base, 0.0) + coefficient * c
        resolved[dof] = combined
        return combined

    # the free DOFs by a mask, not a Python loop over every DOF (the hybrid rig: 109 k DOFs, 0.05 s)
    is_free = np.ones(n_dofs, dtype=bool)
    is_free[np.fromiter((d for d in fixed | set(equations) if 0 <= d < n_dofs), dtype=int)] = False
    free = np.flatnonzero(is_free)
    column = np.full(n_dofs, -1, dtype=int)
    column[free] = np.arange(free.size)
    rows, cols, vals = [], [], []
    for dof in sorted(equations):
        for base, c in resolve(dof).items():
            if 0 <= base < n_dofs and column[base] >= 0 and c != 0.0:
                rows.append(dof)
                cols.append(int(column[base]))
                vals.append(c)
    t = sp.csr_matrix((np.concatenate([np.ones(free.size), np.asarray(vals, dtype=float)]),
                       (np.concatenate([free, np.asarray(rows, dtype=int)]),
                        np.concatenate([np.arange(free.size), np.asarray(cols, dtype=int)]))),
                      shape=(n_dofs, free.size))
    return t, free
