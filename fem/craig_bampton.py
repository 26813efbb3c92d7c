"""Craig–Bampton reduction: a supported structure condensed to its master DOFs and a few fixed-interface modes.

Guyan's reduction (:func:`rvcoax.fem.condensation.guyan_reduction`) describes the structure by its static modes
Ψ alone (its shape for a unit motion of each master DOF): exact for the stiffness the masters see, but its mass
leaves out the structure's own dynamics, so a rig mode approaching the structure's own modes comes out too high.
Craig & Bampton (1968, "Coupling of substructures for dynamic analyses", AIAA J. 6(7)) add the structure's
lowest modes with the masters held, Φ (the fixed-interface modes, mass-normalised): u = Ψ u_m + Φ η, and

    K_cb = [[K_c, 0], [0, Ω²]],   M_cb = [[Ψᵀ M Ψ, Ψᵀ M Φ], [Φᵀ M Ψ, I]],

K_c the condensed (Guyan) stiffness, Ω² the fixed-interface eigenvalues; Ψᵀ K Φ = 0 since Φ does not move the
masters. With the masters held the structure's frequencies are those of Ω²; the reduction converges to the full
model as modes are added (each mode left out errs above its own frequency).

The fixed-interface modes come from the same factorisation as the static modes: with U = K⁻¹ Bᵀ the
displacements under unit master loads (B picks the masters, u_m = B u; B U = F, the flexibility, K_c = F⁻¹),

    P = K⁻¹ − U K_c Uᵀ

is the inverse of K on the structure with its masters held (B P = 0, and P K x = x for B x = 0): shift-invert
block Lanczos (:func:`rvcoax.fem.modal.block_lanczos`) with P needs no second factorisation, and it works when the
masters are dependent DOFs (a distributing tie's reference node).

Linear algebra only: what the structure is is unknown here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem.condensation import StaticModes, static_modes
from rvcoax.fem.modal import ModalError, block_lanczos

__all__ = ["INTERFACE_FACTOR", "AttachedModes", "CraigBampton", "append_interface_modes", "craig_bampton_reduction",
           "interface_modes_needed"]

INTERFACE_FACTOR = 3.0
"""Fixed-interface modes are kept up to this factor × the highest frequency asked of the assembled model; a
structure whose lowest fixed-interface mode lies above it is left to Guyan's mass (the rule of thumb of CMS:
1.5–2 × the band of interest keeps the band's frequencies within a fraction of a percent; 3 leaves margin)."""


@dataclass(frozen=True, eq=False)
class CraigBampton:
    """K_cb and M_cb of a Craig–Bampton reduction (k master DOFs, then r modal coordinates).

    Attributes
    ----------
    stiffness : (k, k) array
        K_c, Guyan's condensed stiffness at the masters.
    interface_eigenvalues : (r,) array
        Ω²: the fixed-interface eigenvalues (rad²/s²), ascending.
    mass : (k + r, k + r) array
        M_cb = [[Ψᵀ M Ψ, Ψᵀ M Φ], [Φᵀ M Ψ, I]].
    """

    stiffness: np.ndarray
    interface_eigenvalues: np.ndarray
    mass: np.ndarray

    @property
    def n_modes(self) -> int:
        return int(self.interface_eigenvalues.size)

    def full_stiffness(self) -> np.ndarray:
        """K_cb = [[K_c, 0], [0, Ω²]] ((k + r) × (k + r))."""
        k, r = self.stiffness.shape[0], self.n_modes
        out = np.zeros((k + r, k + r))
        out[:k, :k] = self.stiffness
        out[k:, k:] = np.diag(self.interface_eigenvalues)
        return out

    def truncated(self, n_modes: int) -> CraigBampton:
        """The same reduction with only the lowest ``n_modes`` fixed-interface modes (exactly what a reduction with
        that many would give: the modes are kept, not recomputed)."""
        k = self.stiffness.shape[0]
        keep = k + min(int(n_modes), self.n_modes)
        return CraigBampton(self.stiffness, self.interface_eigenvalues[:keep - k], self.mass[:keep, :keep])

    def interface_frequencies_hz(self) -> np.ndarray:
        return np.sqrt(np.maximum(self.interface_eigenvalues, 0.0)) / (2.0 * np.pi)


def _interface_modes(statics: StaticModes, mass: sp.csr_matrix, n_modes: int) -> tuple[np.ndarray, np.ndarray]:
    """(Ω², Φ on the independent DOFs q, mass-normalised) of the structure with its masters held."""
    t = statics.elimination
    m_r = (t.T @ sp.csr_matrix(mass) @ t).tocsr()
    held = statics.reduced_displacements  # U on q: (m, k)
    k_c = statics.stiffness
    free = t.shape[1] - k_c.shape[0]
    if n_modes > free:
        raise ModalError(f"{n_modes} fixed-interface modes asked for, but the structure has only {free} degrees of "
                         "freedom besides its masters")

    def held_inverse(x):
        x = np.asarray(x, dtype=float).reshape(t.shape[1], -1)
        return statics.reduced_solve(x) - held @ (k_c @ (held.T @ x))

    return block_lanczos(lambda x: m_r @ x, held_inverse, t.shape[1], n_modes)


def craig_bampton_reduction(stiffness: sp.csr_matrix, elimination: sp.csr_matrix, master_dofs, mass: sp.spmatrix,  # noqa: PLR0913
                            n_modes: int, *, method: str = "auto") -> CraigBampton:
    """The Craig–Bampton reduction of (K, M, u = T q) to ``master_dofs`` and ``n_modes`` fixed-interface modes.

    Parameters
    ----------
    stiffness, elimination : csr_matrix
        K (n × n) with the supports, T (n × m).
    master_dofs : array of int
        The k master DOFs (K's numbering; they may be dependent DOFs of T).
    mass : sparse (n × n)
        M.
    n_modes : int
        r ≥ 0 (0 gives Guyan's reduction).
    method : str
        The solver (:func:`rvcoax.fem.system.prepare_system`).

    Raises
    ------
    rvcoax.fem.errors.SingularModelError
        Not supported, or a master that does not move the structure.
    ModalError
        More modes than the structure has DOFs besides its masters.
    """
    free = elimination.shape[1] - np.size(master_dofs)
    if n_modes < 0 or n_modes > free:
        raise ModalError(f"{n_modes} fixed-interface modes asked for, but the structure has only {free} degrees of "
                         "freedom besides its masters")
    statics = static_modes(stiffness, elimination, master_dofs, np.zeros((stiffness.shape[0], 0)), method=method)
    t = statics.elimination
    m_full = sp.csr_matrix(mass)
    psi = t @ (statics.reduced_displacements @ statics.stiffness)  # Ψ (n × k)
    m_psi = m_full @ psi
    k = statics.stiffness.shape[0]
    cb_mass = np.zeros((k + n_modes, k + n_modes))
    cb_mass[:k, :k] = psi.T @ m_psi
    values = np.zeros(0)
    if n_modes > 0:
        values, phi_r = _interface_modes(statics, m_full, n_modes)
        coupling = (t.T @ m_psi).T @ phi_r  # Ψᵀ M T Φ_q
        cb_mass[:k, k:] = coupling
        cb_mass[k:, :k] = coupling.T
        cb_mass[k:, k:] = np.eye(n_modes)
    cb_mass = 0.5 * (cb_mass + cb_mass.T)
    return CraigBampton(statics.stiffness, np.asarray(values, dtype=float), cb_mass)


def interface_modes_needed(interface_eigenvalues: np.ndarray, top_frequency_hz: float,
                           factor: float = INTERFACE_FACTOR) -> int:
    """How many fixed-interface modes the automatic rule keeps: those below ``factor`` × ``top_frequency_hz``
    (0 when the lowest lies above it: Guyan's mass is then good to well within the band)."""
    hz = np.sqrt(np.maximum(np.asarray(interface_eigenvalues, dtype=float), 0.0)) / (2.0 * np.pi)
    return int(np.count_nonzero(hz < factor * top_frequency_hz))


@dataclass(frozen=True, eq=False)
class AttachedModes:
    """A reduced structure's fixed-interface modes as r extra DOFs of a system: its master ``dofs`` (k,) in the
    system, the modal stiffness (r,) and mass (r,) of each modal coordinate and the mass coupling (k × r) to the
    masters (the system already holds the structure's K_c and Guyan mass on ``dofs``)."""

    dofs: np.ndarray
    stiffness: np.ndarray
    mass: np.ndarray
    coupling: np.ndarray

    @classmethod
    def of(cls, reduction: CraigBampton, dofs, *, density: float, stiffness_factor: float = 1.0) -> AttachedModes:
        """From a reduction computed for a density of 1 (M_cb ∝ ρ, its modal stiffness ∝ the stiffness factor)."""
        k = reduction.stiffness.shape[0]
        return cls(np.asarray(dofs, dtype=int), stiffness_factor * reduction.interface_eigenvalues,
                   density * np.diag(reduction.mass)[k:].copy(), density * reduction.mass[:k, k:])


def append_interface_modes(stiffness: sp.spmatrix, mass: sp.spmatrix, elimination: sp.spmatrix,  # noqa: PLR0913
                           attached: list[AttachedModes], reduced_solve=None):
    """(K', M', T', solve') of a system (n DOFs, u = T q) with the modal coordinates of ``attached`` appended as
    DOFs n, n + 1, …: K' = blkdiag(K, Ω²), M' = M with the modal masses and the couplings, T' = blkdiag(T, I) and,
    with ``reduced_solve`` (x → (Tᵀ K T)⁻¹ x), solve' = its inverse of T'ᵀ K' T' (the modal block is diagonal: no
    new factorisation). ``solve'`` is None without ``reduced_solve``."""
    n, m = elimination.shape
    r = sum(a.stiffness.size for a in attached)
    rows, cols, values = [], [], []
    start = n
    for a in attached:
        modal = start + np.arange(a.stiffness.size)
        block_rows = np.repeat(a.dofs, modal.size)
        block_cols = np.tile(modal, a.dofs.size)
        rows += [block_rows, block_cols, modal]
        cols += [block_cols, block_rows, modal]
        values += [a.coupling.ravel(), a.coupling.ravel(), a.mass]
        start += modal.size
    extra_mass = sp.csr_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
                               shape=(n + r, n + r)) if attached else sp.csr_matrix((n + r, n + r))
    modal_stiffness = np.concatenate([a.stiffness for a in attached]) if attached else np.zeros(0)
    k_aug = sp.block_diag([sp.csr_matrix(stiffness), sp.diags(modal_stiffness)], format="csr")
    m_aug = (sp.block_diag([sp.csr_matrix(mass), sp.csr_matrix((r, r))], format="csr") + extra_mass).tocsr()
    t_aug = sp.block_diag([sp.csr_matrix(elimination), sp.identity(r)], format="csr")
    solve = None
    if reduced_solve is not None:
        def solve(x):
            x = np.asarray(x, dtype=float)
            out = np.empty_like(x)
            out[:m] = np.asarray(reduced_solve(x[:m])).reshape(x[:m].shape)
            out[m:] = x[m:] / modal_stiffness.reshape((r,) + (1,) * (x.ndim - 1))
            return out
    return k_aug, m_aug, t_aug, solve
