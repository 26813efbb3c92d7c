"""Second-order polynomial regression with outlier removal and stepwise term selection.

    y = a + Σ b_j x_j + Σ b_jj x_j² + Σ_{j<k} b_jk x_j x_k

Terms are written as in paper 001's coefficient table: ``1``, ``x1``, ``x1^2``, ``x1*x2`` (factors
numbered from 1 in the order of the levels file). A fit is ordinary least squares on the level
values; r² = 1 − SSE/SST, F = (SSR / (p − 1)) / (SSE / (n − p)) and its p value.

Outliers are runs whose residual interval r_i ± t_{1−α/2, n−p−1} s_(i) √(1 − h_ii) excludes zero
(s_(i): the residual standard deviation without run i, h_ii: leverage), i.e. whose externally
studentized residual exceeds the t quantile. This is MATLAB's ``regress``/``rcoplot`` criterion,
which paper 001 used; they are removed once and the model refitted.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass

import numpy as np
from scipy import stats

__all__ = ["RegressionFit", "Term", "design_matrix", "fit", "fit_without_outliers", "full_quadratic", "outlier_runs",
           "parse_term", "stepwise_terms", "studentized_residuals", "term_name"]

Term = tuple[int, ...]  # () intercept, (j,) linear, (j, j) square, (j, k) product; 0-based factor indices


@dataclass(frozen=True, eq=False)
class RegressionFit:
    """A least-squares fit and its statistics.

    Attributes
    ----------
    terms : tuple of Term
    coefficients : (p,) array
    r2, adjusted_r2, F, p : float
        Goodness of fit; F and p of the regression (all terms but the intercept).
    residual_std : float
        s = √(SSE / (n − p)).
    used : (N,) bool array
        Runs used in the fit (False where removed as outliers).
    removed : tuple of int
        Indices (0-based) of the removed runs.
    studentized : (N,) array
        Externally studentized residuals of the fit that decided the outliers (NaN if not computed).
    note : str
        Why flagged outliers were kept, if they were.
    """

    terms: tuple[Term, ...]
    coefficients: np.ndarray
    r2: float
    adjusted_r2: float
    F: float
    p: float
    residual_std: float
    used: np.ndarray
    removed: tuple[int, ...]
    studentized: np.ndarray
    note: str = ""

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(term_name(t) for t in self.terms)

    def predict(self, x) -> np.ndarray:
        """Predicted response at the factor values ``x`` (one row per point, or a single point)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        return design_matrix(x, self.terms) @ self.coefficients


def term_name(term: Term) -> str:
    if not term:
        return "1"
    if len(term) == 1:
        return f"x{term[0] + 1}"
    if term[0] == term[1]:
        return f"x{term[0] + 1}^2"
    return f"x{term[0] + 1}*x{term[1] + 1}"


def parse_term(text: str, n_factors: int) -> Term:
    """``1``, ``xj``, ``xj^2`` or ``xj*xk`` (j, k from 1) → Term.

    Parameters
    ----------
    text : str
        The term as written.
    n_factors : int
        Factors of the design (j, k ≤ this).

    Returns
    -------
    Term
        0-based factor indices: ``()``, ``(j,)`` or ``(j, k)``.

    Raises
    ------
    ValueError
        The text is not a term of this design.
    """
    text = text.replace(" ", "")
    if text == "1":
        return ()
    match = re.fullmatch(r"x(\d+)(?:\^2|\*x(\d+))?", text)
    if not match:
        raise ValueError(f"term '{text}' is not 1, xj, xj^2 or xj*xk")
    j = int(match[1])
    k = j if text.endswith("^2") else (int(match[2]) if match[2] else None)
    for index in (j, k):
        if index is not None and not 1 <= index <= n_factors:
            raise ValueError(f"term '{text}': there are {n_factors} factors (x1 … x{n_factors})")
    if k is None:
        return (j - 1,)
    return tuple(sorted((j - 1, k - 1)))


def full_quadratic(n_factors: int) -> tuple[Term, ...]:
    """Intercept, linear, square and every two-factor product term."""
    linear = [(j,) for j in range(n_factors)]
    squares = [(j, j) for j in range(n_factors)]
    products = list(itertools.combinations(range(n_factors), 2))
    return ((),) + tuple(linear) + tuple(squares) + tuple(products)


def design_matrix(x: np.ndarray, terms: tuple[Term, ...]) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    return np.column_stack([np.prod(x[:, list(t)], axis=1) if t else np.ones(x.shape[0]) for t in terms])


def _least_squares(matrix: np.ndarray, y: np.ndarray) -> np.ndarray:
    scale = np.linalg.norm(matrix, axis=0)
    scale[scale == 0] = 1.0
    solution, *_ = np.linalg.lstsq(matrix / scale, y, rcond=None)
    return solution / scale


def studentized_residuals(matrix: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Externally studentized residuals r_i / (s_(i) √(1 − h_ii)); NaN where a run has leverage 1."""
    n, p = matrix.shape
    residual = y - matrix @ _least_squares(matrix, y)
    q, _ = np.linalg.qr(matrix)
    leverage = (q**2).sum(axis=1)
    sse = residual @ residual
    with np.errstate(divide="ignore", invalid="ignore"):
        s_without = (sse - residual**2 / (1.0 - leverage)) / (n - p - 1)
        t = residual / np.sqrt(s_without * (1.0 - leverage))
    t[leverage > 1.0 - 1e-10] = np.nan
    return t


def fit(x: np.ndarray, y: np.ndarray, terms: tuple[Term, ...], used=None, removed=(), *, studentized=None,  # noqa: PLR0913
        note: str = "") -> RegressionFit:
    """Least-squares fit of ``terms`` (must include the intercept) on the runs ``used``."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    used = np.ones(y.size, dtype=bool) if used is None else np.asarray(used, dtype=bool)
    if () not in terms:
        raise ValueError("the model needs the intercept term 1")
    matrix, target = design_matrix(x[used], terms), y[used]
    n, p = matrix.shape
    if n <= p:
        raise ValueError(f"{p} terms need more than {p} runs, got {n}")
    if np.linalg.matrix_rank(matrix) < p:
        raise ValueError("the terms are linearly dependent on these runs: the design cannot tell them apart "
                         "(e.g. x^2 of a two-level factor, or aliased products); choose fewer terms or stepwise")
    coefficients = _least_squares(matrix, target)
    sse = float(((target - matrix @ coefficients) ** 2).sum())
    sst = float(((target - target.mean()) ** 2).sum())
    r2 = 1.0 - sse / sst if sst > 0 else 1.0
    adjusted = 1.0 - (1.0 - r2) * (n - 1) / (n - p)
    if p > 1 and sse > 0:
        F = (sst - sse) / (p - 1) / (sse / (n - p))
        p_value = float(stats.f.sf(F, p - 1, n - p))
    else:
        F, p_value = (float("inf"), 0.0) if p > 1 else (float("nan"), float("nan"))
    return RegressionFit(terms=tuple(terms), coefficients=coefficients, r2=r2, adjusted_r2=adjusted, F=float(F),
                         p=p_value, residual_std=float(np.sqrt(sse / (n - p))), used=used, removed=tuple(removed),
                         studentized=np.full(y.size, np.nan) if studentized is None else studentized, note=note)


def outlier_runs(x: np.ndarray, y: np.ndarray, terms: tuple[Term, ...], alpha: float = 0.05) -> tuple[np.ndarray, tuple[int, ...]]:
    """(studentized residuals, indices of the outliers) of the fit on every run."""
    matrix = design_matrix(np.asarray(x, dtype=float), terms)
    n, p = matrix.shape
    if n - p - 1 < 1:
        raise ValueError(f"outlier detection needs at least {p + 2} runs for {p} terms")
    t = studentized_residuals(matrix, np.asarray(y, dtype=float))
    limit = stats.t.ppf(1.0 - alpha / 2.0, n - p - 1)
    return t, tuple(int(i) for i in np.flatnonzero(np.abs(t) > limit))


def fit_without_outliers(x, y, terms: tuple[Term, ...], outliers="auto", alpha: float = 0.05) -> RegressionFit:
    """Fit after removing outliers: ``"auto"`` (residual intervals at α), ``None`` or given 0-based run indices."""
    y = np.asarray(y, dtype=float)
    studentized, note = None, ""
    if outliers == "auto":
        studentized, removed = outlier_runs(x, y, terms, alpha)
        kept = np.setdiff1d(np.arange(y.size), removed)
        if removed and np.linalg.matrix_rank(design_matrix(np.asarray(x, float)[kept], terms)) < len(terms):
            note = (f"runs {', '.join(str(i + 1) for i in removed)} were flagged as outliers but kept: without them "
                    "the terms cannot be told apart")
            removed = ()
    else:
        removed = tuple(sorted(set(outliers or ())))
        if any(not 0 <= i < y.size for i in removed):
            raise ValueError(f"outlier runs must be among the {y.size} runs")
    used = np.ones(y.size, dtype=bool)
    used[list(removed)] = False
    return fit(x, y, terms, used, removed, studentized=studentized, note=note)


def _coefficient_p_values(x, y, terms) -> np.ndarray:
    matrix = design_matrix(x, terms)
    n, p = matrix.shape
    coefficients = _least_squares(matrix, y)
    residual = y - matrix @ coefficients
    s2 = residual @ residual / (n - p)
    covariance = s2 * np.linalg.pinv(matrix.T @ matrix)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = coefficients / np.sqrt(np.diag(covariance))
    return np.where(np.isfinite(t), 2.0 * stats.t.sf(np.abs(t), n - p), 0.0)


def stepwise_terms(x, y, candidates: tuple[Term, ...] | None = None, p_enter: float = 0.05, p_remove: float = 0.10,  # noqa: PLR0913
                   *, min_residual_dof: int = 3) -> tuple[Term, ...]:
    """Forward–backward selection from ``candidates`` (default: the full second-order model).

    Starting from the intercept, add the candidate with the smallest partial-F p value while it is
    below ``p_enter``; after each addition, drop the term with the largest coefficient p value while
    it exceeds ``p_remove``. At least ``min_residual_dof`` residual degrees of freedom are kept.
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    candidates = full_quadratic(x.shape[1]) if candidates is None else candidates
    chosen: list[Term] = [()]
    for _ in range(4 * len(candidates)):
        if y.size - len(chosen) - 1 < min_residual_dof:
            break
        base = design_matrix(x, tuple(chosen))
        sse_base = float(((y - base @ _least_squares(base, y)) ** 2).sum())
        best, best_p = None, p_enter
        for term in candidates:
            if term in chosen:
                continue
            matrix = np.column_stack([base, design_matrix(x, (term,))])
            if np.linalg.matrix_rank(matrix) < matrix.shape[1]:
                continue
            sse = float(((y - matrix @ _least_squares(matrix, y)) ** 2).sum())
            dof = y.size - matrix.shape[1]
            if sse <= 0:
                p_value = 0.0
            else:
                p_value = float(stats.f.sf((sse_base - sse) / (sse / dof), 1, dof))
            if p_value < best_p:
                best, best_p = term, p_value
        if best is None:
            break
        chosen.append(best)
        while len(chosen) > 2:
            p_values = _coefficient_p_values(x, y, tuple(chosen))[1:]
            worst = int(np.argmax(p_values))
            if p_values[worst] <= p_remove or chosen[worst + 1] == best:
                break
            chosen.pop(worst + 1)
    return tuple(chosen)
