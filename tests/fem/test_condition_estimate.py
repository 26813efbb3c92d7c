"""The condition estimate (Hager's one-norm estimator on the factor at hand) against closed forms and numpy.

References: W. W. Hager, "Condition estimates", SIAM J. Sci. Stat. Comput. 5 (1984) 311-316: the estimate is
‖A⁻¹ x‖₁ for vectors x of unit 1-norm, so a lower bound of ‖A⁻¹‖₁, found by steepest ascent of a convex function
on the 1-norm ball; N. J. Higham & F. Tisseur, "A block algorithm for matrix 1-norm estimation", SIAM J. Matrix
Anal. Appl. 21 (2000) 1185-1201 (Algorithm 2.4; the estimate is exact for many matrices and usually within a
factor of 3; no factor holds for every matrix). Closed forms used here: a diagonal matrix is the identity after
Jacobi scaling (κ₁ = 1); the n × n second-difference matrix T = tridiag(−1, 2, −1) has
(T⁻¹)ᵢⱼ = min(i, j) (n + 1 − max(i, j)) / (n + 1) (i, j from 1), all positive, so ‖T‖₁ = 4 and
‖T⁻¹‖₁ = max_j j (n + 1 − j) / 2: κ₁ = (n + 1)² / 2 for odd n, n (n + 2) / 2 for even n (G. H. Golub &
C. F. Van Loan, Matrix Computations, 4th ed., §4.8: the inverse of a tridiagonal matrix); for a nonnegative
inverse Hager's first step already points at the largest column, so the estimate is exact.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from rvcoax.fem import solvers
from rvcoax.fem.diagnostics import scaled_condition_estimate, singularity_and_condition

EPS = np.finfo(float).eps


def counted_solve(dense: np.ndarray, calls: list):
    """A solve function of ``dense`` (factorised once, like the solvers' factors) that records each call's columns."""
    factor = sla.lu_factor(dense)

    def solve(block):
        calls.append(np.shape(block)[1] if np.ndim(block) == 2 else 1)
        return sla.lu_solve(factor, block)

    return solve


def second_difference(n: int) -> sp.csr_matrix:
    return sp.diags([-np.ones(n - 1), 2.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1]).tocsr()


def scaled_condition(dense: np.ndarray) -> float:
    """numpy's exact 1-norm condition number of the Jacobi-scaled matrix."""
    d = 1.0 / np.sqrt(np.diag(dense))
    return float(np.linalg.cond(d[:, None] * dense * d[None, :], 1))


def test_a_diagonal_matrix_is_perfectly_conditioned_after_scaling():
    a = sp.diags(np.logspace(-6, 9, 40)).tocsr()  # N/m next to N·m/rad: units only
    calls = []
    assert scaled_condition_estimate(a, counted_solve(a.toarray(), calls)) == pytest.approx(1.0, rel=1e-12)
    assert len(calls) <= 3


@pytest.mark.parametrize("n", [5, 6, 51, 200])
def test_the_second_difference_matrix_is_estimated_exactly(n):
    t = second_difference(n)
    closed_form = (n + 1) ** 2 / 2 if n % 2 else n * (n + 2) / 2
    assert np.linalg.cond(t.toarray(), 1) == pytest.approx(closed_form, rel=1e-10)  # numpy agrees with the form
    calls = []
    estimate = scaled_condition_estimate(t, counted_solve(t.toarray(), calls))
    assert estimate == pytest.approx(closed_form, rel=1e-10)
    # ones, Higham's vector and the inverse iteration's start; the sign vector and the unit vector the iteration
    # points to; the middle column, where that is not it
    assert calls[:2] == [3, 2] and len(calls) <= 3


@pytest.mark.parametrize("n", [4, 6, 8])
def test_the_hilbert_matrix_against_numpy(n):
    """κ₁ of the scaled Hilbert matrix from 1e4 to 9e9: a lower bound up to the solves' rounding (n ε κ), within
    the usual factor of 3 (measured: 0.97 to 1)."""
    h = sla.hilbert(n)
    exact = scaled_condition(h)
    calls = []
    estimate = scaled_condition_estimate(sp.csr_matrix(h), counted_solve(h, calls))
    assert exact / 3 <= estimate <= exact * (1 + 10 * n * EPS * exact)
    assert len(calls) <= 3


def test_graded_matrices_keep_the_bracket_of_the_five_iteration_search():
    """Random SPD matrices, κ₁ 1e2 … 1e10: each estimate a lower bound within the factor 3 the literature reports as
    usual, the worst one no worse than that of the full search (itmax 5, unguided), in at most three
    solve calls (the full search: up to six here)."""
    ratios, full_ratios, most_calls = [], [], 0
    for seed in range(24):
        rng = np.random.default_rng(seed)
        n = int(rng.integers(20, 80))
        q, _ = np.linalg.qr(rng.standard_normal((n, n)))
        a = (q * np.logspace(0, rng.uniform(2, 10), n)) @ q.T
        a = 0.5 * (a + a.T)
        exact = scaled_condition(a)
        calls = []
        estimate = scaled_condition_estimate(sp.csr_matrix(a), counted_solve(a, calls))
        full = scaled_condition_estimate(sp.csr_matrix(a), counted_solve(a, []), max_iterations=5, guided=False)
        assert estimate <= exact * (1 + n * EPS * exact)
        ratios.append(estimate / exact)
        full_ratios.append(full / exact)
        most_calls = max(most_calls, len(calls))
    assert min(ratios) >= 1 / 3
    assert min(ratios) >= min(full_ratios) * (1 - 1e-9)
    assert most_calls <= 3


def test_the_singularity_test_carries_the_estimate_in_its_two_solve_calls():
    """The inverse iteration's two steps ride in the estimate's calls: two calls where no larger column is certain, the same
    estimate as alone, and a singular matrix still far above the refusal bound."""
    t = second_difference(51).toarray()
    calls = []
    bound, _, kappa = singularity_and_condition(sp.csr_matrix(t), counted_solve(t, calls))
    assert calls[:2] == [3, 3] and len(calls) <= 3  # the test's start is the estimate's guide: no column of its own
    assert kappa == pytest.approx(52**2 / 2, rel=1e-10)
    assert 0.0 < bound <= (1 + 1e-9) / np.linalg.eigvalsh(t / 2.0)[0]  # a lower bound of 1/λ_min of the scaled T
    singular = t.copy()
    singular[0, 0] = singular[-1, -1] = 1.0  # a free chain: rigid translation
    calls.clear()
    bound, _, _ = singularity_and_condition(sp.csr_matrix(singular), counted_solve(singular + 1e-18 * np.eye(51), calls))
    assert bound > solvers.SINGULAR_INVERSE_NORM


@pytest.mark.skipif(not solvers.pardiso_available(), reason="MKL PARDISO not available")
def test_a_pardiso_set_up_tests_and_estimates_in_two_or_three_solve_calls(monkeypatch):
    """A 2-D Laplacian (900 unknowns, shifted: SPD): the set-up's singularity test and condition estimate share
    their solve calls, and the estimate brackets numpy's κ₁; the same matrix without the shift (a free membrane,
    singular) is refused as before."""
    from rvcoax.fem import pardiso

    n = 30
    one_d = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    laplacian = (sp.kron(one_d, sp.identity(n)) + sp.kron(sp.identity(n), one_d)).tocsr()
    a = (laplacian + 1e-3 * sp.identity(n * n)).tocsr()
    calls = []
    original = pardiso.Factorization.solve

    def counted(self, block):
        calls.append(np.shape(block)[1])
        return original(self, block)

    monkeypatch.setattr(pardiso.Factorization, "solve", counted)
    with solvers.prepare(a, "pardiso") as solver:
        assert 2 <= len(calls) <= 3
        exact = scaled_condition(a.toarray())
        assert exact / 3 <= solver.condition_estimate() <= exact * (1 + 1e-8)
    free = laplacian.tolil()
    free.setdiag(-np.asarray(laplacian.sum(axis=1)).ravel() + laplacian.diagonal())  # rows summing to zero
    with pytest.raises(solvers.SingularMatrixError, match="singular"):
        solvers.prepare(free.tocsr(), "pardiso")
