"""Undamped natural frequencies and modes of a constrained structure: K φ = ω² M φ with u = T q.

The generalised eigenproblem is solved on the independent DOFs, Tᵀ K T q = ω² Tᵀ M T q, by shift-invert
Lanczos (ARPACK through :func:`scipy.sparse.linalg.eigsh` with ``sigma = 0``) whose operator is the static
solve's own (Tᵀ K T)⁻¹: the factorisation a static solve already has is reused, nothing is factorised again.
A low-rank change of the stiffness (nonlinear bearings at their operating tangent stiffness, K + Vᵀ D V) is
applied to that operator by the Woodbury identity

    (K + Vᵀ D V)⁻¹ = K⁻¹ − K⁻¹ Vᵀ D (I + V K⁻¹ Vᵀ D)⁻¹ V K⁻¹,

which needs no inverse of D (D may be singular: a bearing whose tangent equals its reference spring).
Small problems (fewer than :data:`DENSE_LIMIT` independent DOFs, or more modes than ARPACK can give) are
solved densely. For large ones (more than :data:`LARGE_LIMIT`: solid and hybrid models) Tᵀ K T and Tᵀ M T are applied as
operators, never formed (forming them costs as much as the solves of the whole eigensolution), and the Lanczos is a
block one (:func:`block_lanczos`): a direct solver's cost per right-hand side falls about threefold when 20 or more
are solved in one call, which more than pays for the larger Krylov space a block method needs (measured on the
hybrid reference rig: 6 calls of 25 columns instead of 64–75 single solves, 8.4 instead of 10–11.5 s CPU in the
solves; benchmarks/RESULTS.md). Modes are mass-normalised: φᵀ M φ = 1, φᵀ K φ = ω².

Linear algebra only: what the DOFs are is unknown here.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rvcoax.fem.errors import RvcoaxError
from rvcoax.fem.memory import available_memory_bytes

__all__ = ["BLOCK_TOLERANCE", "DENSE_LIMIT", "LARGE_LIMIT", "MAX_BLOCKS", "LowRankUpdate", "ModalError", "Modes",
           "block_lanczos", "block_size", "natural_modes"]

DENSE_LIMIT = 600
"""Below this many independent DOFs the eigenproblem is solved densely (exact, and faster than ARPACK)."""


LARGE_LIMIT = 20000
"""Above this many independent DOFs (and with a given factorisation) Tᵀ K T and Tᵀ M T are not formed."""


class ModalError(RvcoaxError, ValueError):
    """A modal analysis that cannot be done as asked (too many modes, no mass), in the user's terms."""

    stage = "cannot compute the natural frequencies"


@dataclass(frozen=True, eq=False)
class LowRankUpdate:
    """A stiffness change Vᵀ D V on the full DOFs: V (p × n) sparse, D (p × p) dense."""

    operator: sp.csr_matrix
    matrix: np.ndarray


@dataclass(frozen=True, eq=False)
class Modes:
    """The lowest modes of a structure.

    Attributes
    ----------
    eigenvalues : (k,) array
        ω² (rad²/s²), ascending.
    shapes : (n, k) array
        Mode shapes on all DOFs (u = T q), mass-normalised: φᵀ M φ = 1.
    method : str
        ``"shift-invert Lanczos"`` or ``"dense"``.
    """

    eigenvalues: np.ndarray
    shapes: np.ndarray
    method: str

    @property
    def frequencies_hz(self) -> np.ndarray:
        """f = √ω² / 2π (Hz); a negative ω² (an unstable operating point) gives a negative f."""
        return np.sign(self.eigenvalues) * np.sqrt(np.abs(self.eigenvalues)) / (2.0 * np.pi)



def _start_vector(size: int) -> np.ndarray:
    """ARPACK's start vector, the same in every call: without one, ARPACK draws it from a seed it keeps between
    calls, so the digits beyond the tolerance would depend on what the process solved before (a solve is a pure
    function of its inputs)."""
    return np.random.default_rng(20261126).standard_normal(size)

def natural_modes(stiffness: sp.spmatrix, mass: sp.spmatrix, elimination: sp.spmatrix, n_modes: int, *,  # noqa: PLR0913
                  reduced_solve: Callable[[np.ndarray], np.ndarray] | None = None,
                  update: LowRankUpdate | None = None, tolerance: float = 1e-10, shift: float = 0.0) -> Modes:
    """The ``n_modes`` lowest undamped modes of (K + Vᵀ D V, M) on u = T q.

    Parameters
    ----------
    stiffness, mass : sparse (n × n)
        K and M, constraints not applied.
    elimination : sparse (n × m)
        T.
    n_modes : int
    reduced_solve : callable, optional
        x (m,) or (m, r) → (Tᵀ K T)⁻¹ x: the static solve's factorisation. Without it Tᵀ K T is factorised
        here (SuperLU).
    update : LowRankUpdate, optional
        The operating point's change of stiffness (nonlinear bearings' tangent minus their reference springs).
    tolerance : float
        ARPACK's relative accuracy of the eigenvalues.
    shift : float
        σ (rad²/s²) of the shift-invert without ``reduced_solve``: K − σ M is factorised. A negative σ finds the
        zero-frequency modes of a structure that is not supported (K singular).

    Raises
    ------
    ModalError
        ``n_modes`` < 1, or more modes than the model has DOFs with mass.
    """
    t = sp.csr_matrix(elimination)
    m = t.shape[1]
    if n_modes < 1:
        raise ModalError(f"the number of modes must be at least 1, got {n_modes}")
    v_r = d = None
    if update is not None and update.operator.shape[0]:
        v_r = (sp.csr_matrix(update.operator) @ t).toarray()
        d = np.asarray(update.matrix, dtype=float)
    if m > LARGE_LIMIT and reduced_solve is not None and n_modes < m // 4:
        m_r = _reduced_operator(t, mass)
        values, vectors = _lanczos_on_operators(t, stiffness, m_r, n_modes, reduced_solve=reduced_solve,
                                                update=(v_r, d), tolerance=tolerance)
        method = "shift-invert Lanczos"
    else:
        k_r = (t.T @ sp.csr_matrix(stiffness) @ t).tocsr()
        m_r = (t.T @ sp.csr_matrix(mass) @ t).tocsr()
        k_r = (k_r + k_r.T) * 0.5
        m_r = (m_r + m_r.T) * 0.5
        with_mass = int(np.count_nonzero(m_r.diagonal() > 0.0))
        if n_modes > with_mass:
            raise ModalError(f"{n_modes} modes asked for, but the model has only {with_mass} degrees of freedom with "
                             f"mass ({m} independent DOFs): ask for at most {with_mass}")
        if v_r is not None:
            k_r = k_r + sp.csr_matrix(v_r.T @ d @ v_r)
        if m < DENSE_LIMIT or n_modes >= m // 3:  # ARPACK is slow for a large share of the spectrum
            values, vectors = _dense_modes(k_r.toarray(), m_r.toarray(), n_modes)
            method = "dense"
        else:
            sigma = 0.0
            if reduced_solve is None:  # k_r already holds the update
                sigma = float(shift)
                base, v_used, d_used = spla.splu((k_r - sigma * m_r).tocsc()).solve, None, None
            else:
                base, v_used, d_used = reduced_solve, v_r, d
            inverse = _woodbury(base, v_used, d_used)
            operator = spla.LinearOperator((m, m), matvec=lambda x: inverse(np.ravel(x)), dtype=float)
            values, vectors = spla.eigsh(k_r, k=n_modes, M=m_r, sigma=sigma, which="LM", OPinv=operator,
                                         tol=tolerance, v0=_start_vector(m))
            order = np.argsort(values)
            values, vectors = values[order], vectors[:, order]
            method = "shift-invert Lanczos"
    norms = np.sqrt(np.einsum("ik,ik->k", vectors, m_r @ vectors))
    vectors = vectors / norms
    # a sign convention: the largest component of each shape is positive
    signs = np.sign(vectors[np.argmax(np.abs(vectors), axis=0), np.arange(vectors.shape[1])])
    vectors = vectors * np.where(signs == 0, 1.0, signs)
    return Modes(np.asarray(values, dtype=float), np.asarray(t @ vectors), method)


def _reduced_operator(t: sp.csr_matrix, matrix) -> spla.LinearOperator:
    """Tᵀ A T as an operator (never formed)."""
    t_t, full = t.T.tocsr(), sp.csr_matrix(matrix)

    def apply(x):
        return t_t @ (full @ (t @ x))

    return spla.LinearOperator((t.shape[1], t.shape[1]), matvec=apply, matmat=apply, dtype=float)


def _lanczos_on_operators(t, stiffness, m_r, n_modes, *, reduced_solve, update, tolerance):  # noqa: PLR0913
    """Shift-invert block Lanczos with Tᵀ M T applied as an operator, for large models (:func:`block_lanczos`);
    ARPACK on the same operators where it does not converge."""
    v_r, d = update
    inverse = _woodbury(reduced_solve, v_r, d)
    m = t.shape[1]
    room = available_memory_bytes()
    if room is None or _block_basis_bytes(m, n_modes) < 0.25 * room:
        try:
            return block_lanczos(lambda x: m_r @ x, inverse, m, n_modes)
        except ModalError:
            pass
    k_plain = _reduced_operator(t, stiffness)

    def k_op(x):
        out = k_plain @ x
        return out if v_r is None else out + v_r.T @ (d @ (v_r @ x))

    k_r = spla.LinearOperator((m, m), matvec=k_op, dtype=float)
    operator = spla.LinearOperator((m, m), matvec=lambda x: inverse(np.ravel(x)), dtype=float)
    values, vectors = spla.eigsh(k_r, k=n_modes, M=m_r, sigma=0.0, which="LM", OPinv=operator, tol=tolerance,
                                 v0=_start_vector(m))
    order = np.argsort(values)
    return values[order], vectors[:, order]


BLOCK_TOLERANCE = 1e-5
"""Residual ‖A y − μ y‖_M / μ below which a Ritz pair of the block Lanczos is converged (A = K⁻¹ M); the eigenvalue
is then accurate to about its square times μ over the gap to the next one. Measured on the reference rig's hybrid
model (108 k DOF, 20 modes): its frequencies agree with ARPACK's (40 modes at tol 1e-12) to 2.9e-9, the rounding of
the saddle-point solves themselves (ARPACK at 1e-10 and at 1e-12 differ by as much), with 1e-5 and with 1e-4 alike
(6 block solves each); 1e-3 left 1.8e-7 (5)."""
MAX_BLOCKS = 12
"""Krylov blocks after which an unconverged block Lanczos is abandoned (the modes are then found by ARPACK); 20 modes
of the hybrid reference rig take 6."""


def _block_basis_bytes(m: int, n_modes: int) -> float:
    """Memory of a block Lanczos basis at :data:`MAX_BLOCKS` blocks (the blocks and their mass products): where it
    would take more than a quarter of the memory available, ARPACK (a few dozen vectors) is used instead."""
    return 2.0 * 8.0 * m * block_size(n_modes) * MAX_BLOCKS


def block_size(n_modes: int) -> int:
    """Columns per block solve: the wanted modes and a guard of 4–16 (clusters at the top of the band converge from
    its side); at most 64, where a direct solve's cost per column stops falling."""
    return min(n_modes + min(max(4, n_modes // 4), 16), 64)


def block_lanczos(apply_mass: Callable[[np.ndarray], np.ndarray], solve: Callable[[np.ndarray], np.ndarray], m: int,  # noqa: PLR0913
                  n_modes: int, *, tolerance: float = BLOCK_TOLERANCE, seed: int = 0,
                  block: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The ``n_modes`` lowest (ω², φ) of K φ = ω² M φ by shift-invert block Lanczos on A = K⁻¹ M.

    A is self-adjoint in the M inner product; its Krylov space from a random block is built one block solve
    K⁻¹ [M V_j] at a time (every column of the block in one call of the factorisation: a direct solver's cost per
    column falls several-fold from 1 to 20 columns, the factor being read once per call), M-orthogonalised
    against all blocks before it twice (full reorthogonalisation). The Rayleigh–Ritz values μ of A on that space
    give ω² = 1/μ; the residual of each Ritz pair, ‖A y − μ y‖_M = ‖B s‖ (B the next block's coefficient, s the
    Ritz vector's last block), is known after each block solve without another one. It stops when the
    ``n_modes`` largest μ all have ‖A y − μ y‖_M ≤ ``tolerance`` μ: the eigenvalues are then accurate to about the
    square of that (Temple's bound), below the rounding of the solves.

    Parameters
    ----------
    apply_mass : callable
        X (m, r) → M X.
    solve : callable
        X (m, r) → K⁻¹ X, all columns at once.
    m : int
        Size of the problem.
    n_modes : int
    tolerance : float
    seed : int
        Of the random start block (the result does not depend on it beyond the tolerance).
    block : int, optional
        Columns per block (default :func:`block_size`).

    Returns
    -------
    eigenvalues : (n_modes,) array, ascending
    vectors : (m, n_modes) array, M-orthonormal

    Raises
    ------
    ModalError
        No convergence within :data:`MAX_BLOCKS` blocks, or the Krylov space exhausted before ``n_modes``
        modes (fewer DOFs with mass): the caller may use ARPACK instead.
    """
    b = block_size(n_modes) if block is None else int(block)
    rng = np.random.default_rng(seed)
    basis: list[np.ndarray] = []  # V_j, M-orthonormal
    massed: list[np.ndarray] = []  # M V_j
    projected = np.zeros((0, 0))  # Vᵀ M A V
    start = np.asarray(solve(apply_mass(rng.standard_normal((m, b)))), dtype=float).reshape(m, b)
    current, current_massed, _ = _m_orthonormal(start, basis, massed, apply_mass)
    for _ in range(MAX_BLOCKS):
        if current.shape[1] == 0:
            break
        k0 = projected.shape[0]
        basis.append(current)
        massed.append(current_massed)
        w = np.asarray(solve(current_massed), dtype=float).reshape(m, -1)  # A V_j
        coefficients = np.concatenate([mv.T @ w for mv in massed], axis=0)  # Vᵀ M A V_j
        w -= _combine(basis, coefficients)
        k1 = k0 + current.shape[1]
        grown = np.zeros((k1, k1))
        grown[:k0, :k0] = projected
        grown[:, k0:] = coefficients
        grown[k0:, :k0] = coefficients[:k0].T
        projected = 0.5 * (grown + grown.T)
        current, current_massed, coupling = _m_orthonormal(w, basis, massed, apply_mass)
        mu, s = np.linalg.eigh(projected)
        mu, s = mu[::-1], s[:, ::-1]  # largest μ = lowest ω² first
        wanted = min(n_modes, int(np.count_nonzero(mu > 0.0)))
        residual = np.linalg.norm(coupling @ s[k0:, :wanted], axis=0)
        if wanted == n_modes and np.all(residual <= tolerance * mu[:wanted]):
            vectors = _combine(basis, s[:, :n_modes])
            return 1.0 / mu[:n_modes], vectors
    raise ModalError(f"the block Lanczos did not converge to {n_modes} modes in {len(basis)} blocks of {b}")


def _combine(blocks: list[np.ndarray], coefficients: np.ndarray) -> np.ndarray:
    """[V_1 … V_j] C, block by block (the blocks are never joined into one array: at 108 k DOF and 150 columns that
    copy alone is 130 MB)."""
    out = np.zeros((blocks[0].shape[0], coefficients.shape[1]))
    start = 0
    for v in blocks:
        out += v @ coefficients[start:start + v.shape[1]]
        start += v.shape[1]
    return out


def _m_orthonormal(w: np.ndarray, basis: list[np.ndarray], massed: list[np.ndarray],
                   apply_mass) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Q, M Q, C): W M-orthogonalised once more against ``basis`` (M V in ``massed``; the caller did it once) and
    M-orthonormalised, W ≈ Q C; directions below rounding (the Krylov space exhausted) are dropped."""
    if basis:
        w = w - _combine(basis, np.concatenate([mv.T @ w for mv in massed], axis=0))
    mw = np.asarray(apply_mass(w), dtype=float).reshape(w.shape)
    gram = w.T @ mw
    values, vectors = np.linalg.eigh(0.5 * (gram + gram.T))
    keep = values > 1e-20 * max(float(values.max(initial=0.0)), 0.0)
    keep &= values > 0.0
    root = np.sqrt(values[keep])
    scale = vectors[:, keep] / root
    return w @ scale, mw @ scale, root[:, None] * vectors[:, keep].T


def _dense_modes(k: np.ndarray, m: np.ndarray, n_modes: int) -> tuple[np.ndarray, np.ndarray]:
    """The lowest modes of dense (K, M); DOFs without mass are condensed out statically first (exact: no
    inertia acts on them), since a singular M is not allowed by the dense solver."""
    massless = m.diagonal() <= 0.0
    if not massless.any():
        values, vectors = scipy.linalg.eigh(k, m, subset_by_index=[0, n_modes - 1])
        return values, vectors
    keep = ~massless
    k_ss = k[np.ix_(massless, massless)]
    k_sm = k[np.ix_(massless, keep)]
    recover = -scipy.linalg.solve(k_ss, k_sm, assume_a="sym")
    reduced = k[np.ix_(keep, keep)] + k_sm.T @ recover
    values, master = scipy.linalg.eigh(0.5 * (reduced + reduced.T), m[np.ix_(keep, keep)],
                                       subset_by_index=[0, n_modes - 1])
    vectors = np.zeros((k.shape[0], n_modes))
    vectors[keep] = master
    vectors[massless] = recover @ master
    return values, vectors


def _woodbury(solve: Callable, v: np.ndarray | None, d: np.ndarray | None) -> Callable[[np.ndarray], np.ndarray]:
    """x → (K + Vᵀ D V)⁻¹ x from ``solve`` = K⁻¹ (Vᵀ D V skipped when V is None)."""
    if v is None:
        return lambda x: np.asarray(solve(np.asarray(x, dtype=float))).reshape(np.shape(x))
    influence = np.asarray(solve(v.T.copy()), dtype=float).reshape(v.shape[1], -1)  # K⁻¹ Vᵀ
    small = np.eye(v.shape[0]) + v @ influence @ d
    factor = scipy.linalg.lu_factor(small)

    def apply(x):
        x = np.asarray(x, dtype=float)
        y = np.asarray(solve(x), dtype=float).reshape(x.shape)
        return y - influence @ (d @ scipy.linalg.lu_solve(factor, v @ y))

    return apply
