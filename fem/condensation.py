"""Static (Guyan) condensation of a supported structure to master DOFs, and its superelement.

A housing meshed with solids, its feet clamped or on springs, is reduced to the six DOFs of each
reference node where something attaches (bearings, a part). Two routes, which agree to rounding
(a test checks it):

* :func:`condensed_stiffness` — the flexibility route: solve the supported model for a unit load on
  each master DOF (k columns), read the masters' displacements, F (k × k), and invert,
  K_c = F⁻¹. It works whatever the masters are: independent DOFs, or reference nodes that depend on
  a face (a distributing tie, RBE3-like). It is exact: K_c reproduces the full model's master
  displacements for any load on the masters (Guyan's reduction is exact when only masters are loaded).
* :func:`condensed_stiffness_and_loads` — the same, with the master loads equivalent to loads anywhere on
  the structure (its own weight): f_c = K_c u_m, with u_m the masters' displacement under those loads in
  the full model, so the condensed model moves its masters exactly as the full one does.
* :func:`guyan_reduction` — the same solve also gives the static modes Ψ (the whole structure's displacement
  for a unit displacement of each master DOF, Ψ = U K_c with U the unit-load displacements) and Guyan's mass
  M_c = Ψᵀ M Ψ: the structure's inertia carried by the masters when it moves in its static shapes. Exact for
  the rigid-body inertia the masters see; the structure's own dynamics (its modes with the masters held) are
  left out, so it is good for rig modes well below the housing's own lowest frequency.
* :func:`schur_complement` — Guyan's formula K_c = K_mm − K_ms K_ss⁻¹ K_sm when the masters are
  independent DOFs (no constraints).

:func:`superelement_contribution` puts K_c into a system on the master nodes' DOFs, the way a
bushing enters it (:mod:`rvcoax.fem.pieces`). Linear algebra only: meshes are unknown here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem.errors import SingularModelError
from rvcoax.fem.pieces import Contribution
from rvcoax.fem.system import prepare_system

__all__ = ["GuyanReduction", "StaticModes", "condensed_stiffness", "condensed_stiffness_and_loads", "guyan_reduction",
           "schur_complement", "static_modes", "superelement_contribution", "superelement_mass_contribution"]


def condensed_stiffness(stiffness: sp.csr_matrix, elimination: sp.csr_matrix, master_dofs,
                        method: str = "auto") -> np.ndarray:
    """K_c (k × k) of the model (K, u = T q) at ``master_dofs``: the inverse of its flexibility there.

    Parameters
    ----------
    stiffness : csr_matrix
        K (n × n) of the whole model, supports included.
    elimination : csr_matrix
        T (n × m), with the fixed DOFs and constraint rows eliminated (u = T q).
    master_dofs : array of int
        The k master DOFs (in K's numbering); they may be dependent DOFs of T.
    method : str
        The solver (:func:`rvcoax.fem.system.prepare_system`).

    Raises
    ------
    SingularModelError
        The model is not supported (a rigid-body motion is free) or the flexibility is singular.
    """
    return condensed_stiffness_and_loads(stiffness, elimination, master_dofs, np.zeros((stiffness.shape[0], 0)),
                                         method)[0]


def condensed_stiffness_and_loads(stiffness: sp.csr_matrix, elimination: sp.csr_matrix, master_dofs, loads,
                                  method: str = "auto") -> tuple[np.ndarray, np.ndarray]:
    """K_c (k × k) at ``master_dofs`` and the equivalent master loads f_c = K_c u_m (k × p) of ``loads`` (n × p).

    One factorisation: the k unit loads on the masters and the p ``loads`` are solved together; u_m are the
    masters' displacements under ``loads``. K_c⁻¹ f_c = u_m: the condensed model reproduces the full model's master
    displacements under those loads (and any load on the masters added to them). Parameters and errors as
    :func:`condensed_stiffness`.
    """
    reduction = guyan_reduction(stiffness, elimination, master_dofs, loads, method=method)
    return reduction.stiffness, reduction.loads


@dataclass(frozen=True, eq=False)
class GuyanReduction:
    """K_c (k × k), the equivalent master loads f_c (k × p), Guyan's mass M_c (k × k, or None) and the lowest ω²
    of the structure on its supports with the masters free (None without a mass): the dynamics Guyan leaves out
    start above it."""

    stiffness: np.ndarray
    loads: np.ndarray
    mass: np.ndarray | None
    lowest_eigenvalue: float | None = None


@dataclass(frozen=True, eq=False)
class StaticModes:
    """One factorisation's static condensation: K_c (k × k), the equivalent master loads f_c (k × p), the displacements
    U (m × k) of the independent DOFs q under unit master loads (Ψ = T U K_c), T, and the factorisation's
    q-solve (x → (Tᵀ K T)⁻¹ x), kept for further solves (:mod:`rvcoax.fem.craig_bampton`)."""

    stiffness: np.ndarray
    loads: np.ndarray
    reduced_displacements: np.ndarray
    elimination: sp.csr_matrix
    reduced_solve: object


def static_modes(stiffness: sp.csr_matrix, elimination: sp.csr_matrix, master_dofs, loads, *,
                 method: str = "auto") -> StaticModes:
    """K_c and f_c as :func:`condensed_stiffness_and_loads`, with the unit-load displacements and the solve."""
    masters = np.asarray(master_dofs, dtype=int)
    n = stiffness.shape[0]
    loads = np.asarray(loads, dtype=float).reshape(n, -1)
    t = sp.csr_matrix(elimination)
    system = prepare_system(stiffness, t, method, symmetrize=True)
    reduced = system.solver.solve(np.hstack([t[masters].T.toarray(), t.T @ loads]))
    displacement = t[masters] @ reduced  # the masters' displacements: unit master loads, then ``loads``
    flexibility = displacement[:, : masters.size]
    flexibility = 0.5 * (flexibility + flexibility.T)
    condition = np.linalg.cond(flexibility)
    if not np.isfinite(condition) or condition > 1e14:
        raise SingularModelError(f"the condensed flexibility is singular (condition number {condition:.1e}): a master "
                                 "DOF does not move the structure (check the ties)")
    result = np.linalg.inv(flexibility)
    result = 0.5 * (result + result.T)
    return StaticModes(result, result @ displacement[:, masters.size:], reduced[:, : masters.size], t,
                       system.solver.solve)


def guyan_reduction(stiffness: sp.csr_matrix, elimination: sp.csr_matrix, master_dofs, loads, *, mass=None,  # noqa: PLR0913
                    method: str = "auto") -> GuyanReduction:
    """K_c and f_c as :func:`condensed_stiffness_and_loads`, and with ``mass`` (M, n × n) Guyan's M_c = Ψᵀ M Ψ,
    Ψ = U K_c the static modes (U: the displacements under unit master loads), from the same one solve."""
    statics = static_modes(stiffness, elimination, master_dofs, loads, method=method)
    condensed_mass = lowest = None
    if mass is not None:
        from rvcoax.fem.modal import natural_modes

        shapes = statics.elimination @ (statics.reduced_displacements @ statics.stiffness)  # Ψ: unit master displacements
        condensed_mass = shapes.T @ (sp.csr_matrix(mass) @ shapes)
        condensed_mass = 0.5 * (condensed_mass + condensed_mass.T)
        lowest = float(natural_modes(stiffness, mass, elimination, 1, reduced_solve=statics.reduced_solve).eigenvalues[0])
    return GuyanReduction(statics.stiffness, statics.loads, condensed_mass, lowest)


def schur_complement(stiffness: sp.csr_matrix, master_dofs, fixed_dofs=()) -> np.ndarray:
    """Guyan's K_mm − K_ms K_ss⁻¹ K_sm for independent ``master_dofs`` (the other free DOFs are slaves)."""
    masters = np.asarray(master_dofs, dtype=int)
    n = stiffness.shape[0]
    keep = np.ones(n, dtype=bool)
    keep[masters] = False
    keep[np.asarray(fixed_dofs, dtype=int)] = False
    slaves = np.flatnonzero(keep)
    k = sp.csr_matrix(stiffness)
    k_ss = k[slaves][:, slaves].tocsc()
    k_sm = k[slaves][:, masters].toarray()
    k_mm = k[masters][:, masters].toarray()
    solved = sp.linalg.splu(k_ss).solve(k_sm)
    result = k_mm - k_sm.T @ solved
    return 0.5 * (result + result.T)


def superelement_contribution(matrix: np.ndarray, dofs, ground_dofs=None) -> Contribution:
    """A condensed stiffness K_c between the global ``dofs`` and the ground: stiffness triplets.

    With ``ground_dofs`` (held fixed elsewhere, one per entry of ``dofs``) the ground side is explicit,
    [[K_c, −K_c], [−K_c, K_c]] on (dofs, ground_dofs): the structure sees the same K_c, and the fixed DOFs'
    reactions are the superelement's forces on the ground (for the global equilibrium check).
    """
    dofs = np.asarray(dofs, dtype=int)
    matrix = np.asarray(matrix, dtype=float)
    if matrix.shape != (dofs.size, dofs.size):
        raise ValueError(f"a {matrix.shape} matrix does not fit {dofs.size} DOFs")
    if ground_dofs is not None:
        ground = np.asarray(ground_dofs, dtype=int)
        if ground.shape != dofs.shape:
            raise ValueError(f"{ground.size} ground DOFs for {dofs.size} DOFs")
        dofs = np.concatenate([dofs, ground])
        matrix = np.block([[matrix, -matrix], [-matrix, matrix]])
    rows = np.repeat(dofs, dofs.size)
    cols = np.tile(dofs, dofs.size)
    return Contribution((rows, cols, matrix.ravel()))


def superelement_mass_contribution(matrix: np.ndarray, dofs) -> Contribution:
    """A condensed (Guyan) mass M_c on the global ``dofs``: mass triplets (its ground side is fixed: no inertia)."""
    dofs = np.asarray(dofs, dtype=int)
    matrix = np.asarray(matrix, dtype=float)
    if matrix.shape != (dofs.size, dofs.size):
        raise ValueError(f"a {matrix.shape} matrix does not fit {dofs.size} DOFs")
    return Contribution(mass=(np.repeat(dofs, dofs.size), np.tile(dofs, dofs.size), matrix.ravel()))
