"""Natural frequencies of Timoshenko beams against their differential equations (tests/fem/timoshenko_closed_forms.py),
the consistent mass matrices' sums, and the eigensolver's reuse of a factorisation and its low-rank update."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp
from timoshenko_closed_forms import Section, frequencies_hz, simply_supported_hz

from rvcoax.fem import beam, loads
from rvcoax.fem.assembly import assemble_matrix
from rvcoax.fem.constraints import elimination_matrix
from rvcoax.fem.modal import LowRankUpdate, ModalError, natural_modes

E, NU, RHO = 2.1e11, 0.3, 7850.0
G = E / (2 * (1 + NU))
D, L = 0.05, 0.5  # a stocky shaft (L/D = 10): shear and rotary inertia lower its modes by a few per cent
A, INERTIA = math.pi * D**2 / 4, math.pi * D**4 / 64
KAPPA = 6 * (1 + NU) / (7 + 6 * NU)
SECTION = Section(L, E, G, RHO, A, INERTIA, KAPPA)
TOLERANCE = 0.005  # the 0.5 % at a converged mesh (40 elements: 0.01 %–0.1 % here)


def _line(n_el: int, kappa: float = KAPPA):
    coords = np.zeros((n_el + 1, 3))
    coords[:, 0] = np.linspace(0.0, L, n_el + 1)
    ones = np.ones(n_el)
    elements = beam.BeamElements(np.c_[np.arange(n_el), np.arange(1, n_el + 1)], A * ones, INERTIA * ones, 2 * INERTIA * ones,
                                 kappa * ones, E * ones, G * ones, RHO * ones, np.tile([0.0, 1.0, 0.0], (n_el, 1)))
    return coords, elements


def _plane_modes(n_el, fixed=(), springs=(), masses=(), count=4, kappa=KAPPA):
    """Modes in the x-y plane (u_x, u_z, θx, θy held): bending only."""
    coords, elements = _line(n_el, kappa)
    n = 6 * (n_el + 1)
    k = assemble_matrix(n, [beam.stiffness_triplets(coords, elements)]).tolil()
    m = assemble_matrix(n, [beam.mass_triplets(coords, elements)]).tolil()
    for dof, value in springs:
        k[dof, dof] += value
    for dof, value in masses:
        m[dof, dof] += value
    held = {6 * i + c for i in range(n_el + 1) for c in (0, 2, 3, 4)} | set(fixed)
    t, _ = elimination_matrix(n, sorted(held), {})
    f = natural_modes(k.tocsr(), m.tocsr(), t, count + 2).frequencies_hz
    return f[f > 1e-3][:count]


def _close(fe, exact):
    assert np.allclose(fe, exact, rtol=TOLERANCE), (fe, exact)


def test_simply_supported_timoshenko_beam():
    exact = [simply_supported_hz(SECTION, n) for n in (1, 2, 3)]
    # the determinant of the differential equations agrees with the closed form (checks the helper)
    assert np.allclose(frequencies_hz(SECTION, ((math.inf, 0), (math.inf, 0)), 3, 5000), exact, rtol=1e-9)
    fe = _plane_modes(40, fixed=(1, 6 * 40 + 1), count=3)
    _close(fe, exact)
    # shear and rotary inertia matter here: Euler–Bernoulli's first mode is above by more than the tolerance
    euler = (math.pi / L) ** 2 * math.sqrt(E * INERTIA / (RHO * A)) / (2 * math.pi) * 3**2
    assert euler > exact[2] * (1 + 10 * TOLERANCE)


def test_free_free_timoshenko_beam():
    exact = frequencies_hz(SECTION, ((0, 0), (0, 0)), 3, 8000)
    _close(_plane_modes(40, count=3), exact)
    coarse = _plane_modes(10, count=3)
    assert abs(coarse[2] / exact[2] - 1) > abs(_plane_modes(40, count=3)[2] / exact[2] - 1)  # converging


def test_cantilever_with_tip_mass():
    tip = 2.0  # kg, 1.3 times the beam's mass
    exact = frequencies_hz(SECTION, ((math.inf, math.inf), (lambda w: -tip * w * w, 0)), 3, 5000)
    _close(_plane_modes(40, fixed=(1, 5), masses=[(6 * 40 + 1, tip)], count=3), exact)
    # the textbook Euler–Bernoulli root (1 + cos βL cosh βL + μ βL (cos βL sinh βL − sin βL cosh βL) = 0) on a
    # slender Euler–Bernoulli line (no shear; rotary inertia 1e-5 of the effect): the first mode
    slender = Section(L, E, G, RHO, A * 1e-4, INERTIA * 1e-8, math.inf)
    mu = tip * 1e-4 / slender.mass_kg

    def equation(b):
        return 1 + math.cos(b) * math.cosh(b) + mu * b * (math.cos(b) * math.sinh(b) - math.sin(b) * math.cosh(b))

    from scipy.optimize import brentq
    beta = brentq(equation, 0.1, 3.0)
    exact_first = beta**2 / L**2 * math.sqrt(E * slender.second_moment_m4 / (RHO * slender.area_m2)) / (2 * math.pi)
    coords, elements = _line(40, math.inf)
    scaled = beam.BeamElements(elements.connectivity, elements.area_m2 * 1e-4, elements.second_moment_m4 * 1e-8,
                               elements.polar_moment_m4 * 1e-8, elements.shear_coefficient, elements.youngs_modulus_Pa,
                               elements.shear_modulus_Pa, elements.density_kg_per_m3, elements.reference_vector)
    n = 6 * 41
    k = assemble_matrix(n, [beam.stiffness_triplets(coords, scaled)])
    m = assemble_matrix(n, [beam.mass_triplets(coords, scaled), (np.array([6 * 40 + 1]), np.array([6 * 40 + 1]),
                                                                    np.array([tip * 1e-4]))])
    held = sorted({6 * i + c for i in range(41) for c in (0, 2, 3, 4)} | {1, 5})
    t, _ = elimination_matrix(n, held, {})
    assert natural_modes(k, m, t, 1).frequencies_hz[0] == pytest.approx(exact_first, rel=TOLERANCE)


def test_shaft_on_two_springs_rigid_body_and_bending():
    k = 2e6  # N/m: soft enough that bounce and rock are nearly rigid-body modes, stiff enough to couple
    exact = frequencies_hz(SECTION, ((k, 0), (k, 0)), 4, 8000)
    fe = _plane_modes(40, springs=[(1, k), (6 * 40 + 1, k)], count=4)
    _close(fe, exact)
    bounce = math.sqrt(2 * k / SECTION.mass_kg) / (2 * math.pi)
    rock = math.sqrt(2 * k * (L / 2) ** 2 / (SECTION.mass_kg * L**2 / 12 + RHO * INERTIA * L)) / (2 * math.pi)
    assert fe[0] == pytest.approx(bounce, rel=0.05) and fe[1] == pytest.approx(rock, rel=0.02)  # rigid-body limit


def test_mass_matrix_sums_to_the_mass_and_inertia():
    coords, elements = _line(7)
    coords = coords @ np.array([[0.6, 0.8, 0.0], [-0.8, 0.6, 0.0], [0.0, 0.0, 1.0]])  # a skewed line
    n = 6 * 8
    masses = loads.PointMasses(np.array([3]), np.array([1.5]), np.array([[0.01, 0.02, 0.03]]))
    m = assemble_matrix(n, [beam.mass_triplets(coords, elements), loads.point_mass_triplets(masses)])
    total = RHO * A * L + 1.5
    for axis in range(3):
        unit = np.zeros(n)
        unit[axis::6] = 1.0
        assert unit @ m @ unit == pytest.approx(total, rel=1e-13)
    # rotation about the line's own axis: ρ (2 INERTIA) L of the beams plus the point mass's Ixx
    axis = np.array([0.6, 0.8, 0.0])
    spin = np.zeros(n)
    for c in range(3):
        spin[3 + c::6] = axis[c]
    assert spin @ m @ spin == pytest.approx(RHO * 2 * INERTIA * L + (0.01 * 0.36 + 0.02 * 0.64), rel=1e-12)
    assert abs(m - m.T).max() < 1e-14 * abs(m).max()


def _frame(n_el=30):
    coords, elements = _line(n_el)
    n = 6 * (n_el + 1)
    k = assemble_matrix(n, [beam.stiffness_triplets(coords, elements)]).tolil()
    for dof in (1, 2, 6 * n_el + 1, 6 * n_el + 2):
        k[dof, dof] += 5e7
    k[0, 0] += 1e8
    k[3, 3] += 1e3
    m = assemble_matrix(n, [beam.mass_triplets(coords, elements)])
    return k.tocsr(), m, elimination_matrix(n, [], {})[0]


def test_lanczos_on_a_given_factorisation_agrees_with_dense():
    k, m, t = _frame(150)  # 906 DOFs: above the dense limit
    dense = np.linalg.eigvalsh(np.linalg.solve(np.linalg.cholesky(m.toarray()),
                                               np.linalg.solve(np.linalg.cholesky(m.toarray()), k.toarray()).T))
    lu = sp.linalg.splu(k.tocsc())
    modes = natural_modes(k, m, t, 8, reduced_solve=lu.solve)
    assert modes.method == "shift-invert Lanczos"
    assert np.allclose(modes.eigenvalues, np.sort(dense)[:8], rtol=1e-8)
    assert np.allclose(modes.shapes.T @ m @ modes.shapes, np.eye(8), atol=1e-9)
    assert np.allclose(np.diag(modes.shapes.T @ k @ modes.shapes), modes.eigenvalues, rtol=1e-8)


def test_low_rank_update_through_the_old_factorisation():
    """A bearing at its operating stiffness: K + Vᵀ D V solved with K's factorisation (Woodbury)."""
    k, m, t = _frame(150)
    n = k.shape[0]
    v = sp.csr_matrix((np.ones(2), ([0, 1], [1, 2])), shape=(2, n))  # u_y, u_z of the first node
    d = np.array([[-4e7, 1e6], [1e6, 2e7]])  # softer vertically, stiffer sideways, coupled
    lu = sp.linalg.splu(k.tocsc())
    updated = natural_modes(k, m, t, 6, reduced_solve=lu.solve, update=LowRankUpdate(v, d))
    direct = natural_modes((k + v.T @ sp.csr_matrix(d) @ v).tocsr(), m, t, 6)
    assert np.allclose(updated.eigenvalues, direct.eigenvalues, rtol=1e-8)


def test_too_many_modes_is_a_clear_error():
    k, m, t = _frame(3)
    with pytest.raises(ModalError, match="only 24 degrees of freedom with mass"):
        natural_modes(k, m, t, 25)
    with pytest.raises(ModalError, match="at least 1"):
        natural_modes(k, m, t, 0)


def test_large_models_apply_the_reduced_matrices_as_operators(monkeypatch):
    """Above LARGE_LIMIT DOFs (here forced on 906) Tᵀ K T and Tᵀ M T are operators: the same modes, with an update."""
    from rvcoax.fem import modal

    k, m, t = _frame(150)
    n = k.shape[0]
    lu = sp.linalg.splu(k.tocsc())
    update = LowRankUpdate(sp.csr_matrix((np.ones(2), ([0, 1], [1, 2])), shape=(2, n)),
                           np.array([[-4e7, 1e6], [1e6, 2e7]]))
    formed = natural_modes(k, m, t, 10, reduced_solve=lu.solve, update=update)
    monkeypatch.setattr(modal, "LARGE_LIMIT", 100)
    applied = natural_modes(k, m, t, 10, reduced_solve=lu.solve, update=update)
    assert np.allclose(applied.eigenvalues, formed.eigenvalues, rtol=1e-9)
    assert np.allclose(np.abs(applied.shapes.T @ m @ formed.shapes).max(axis=0), 1.0, atol=1e-6)


def test_block_lanczos_finds_repeated_eigenvalues():
    """K = diag(1, 1, 2, 2, 3, 3, …) (pairs, as a round shaft's two bending planes), M = diag(2): every pair found
    once per plane (the block holds both members of a pair at once), to the square of the residual limit 1e-5 over
    the relative gap to the next pair (≥ 1/7 here)."""
    from rvcoax.fem.modal import block_lanczos

    stiffness = np.repeat(np.arange(1.0, 201.0), 2)
    mass = np.full(stiffness.size, 2.0)
    values, vectors = block_lanczos(lambda x: mass[:, None] * x, lambda x: x / stiffness[:, None], stiffness.size, 12)
    assert values == pytest.approx(np.repeat(np.arange(1.0, 7.0), 2) / 2.0, rel=1e-9)
    assert vectors.T @ (mass[:, None] * vectors) == pytest.approx(np.eye(12), abs=1e-10)


def test_block_lanczos_refuses_more_modes_than_its_krylov_space_holds():
    from rvcoax.fem.modal import block_lanczos

    mass = np.r_[np.ones(5), np.zeros(45)]  # only 5 DOFs carry mass: 5 finite frequencies
    with pytest.raises(ModalError, match="did not converge to 8 modes"):
        block_lanczos(lambda x: mass[:, None] * x, lambda x: x / np.arange(1.0, 51.0)[:, None], 50, 8)
