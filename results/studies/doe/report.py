"""Documents (JSON), table rows (CSV) and the main-effects plot of an orthogonal experiment."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvcoax.results.io.writers import write_png_atomic
from rvcoax.results.studies.doe.analysis import Anova, AnovaRow, ColumnRange, anova, optimal_levels, range_analysis
from rvcoax.results.studies.doe.design import Design
from rvcoax.results.studies.doe.regression import (
    RegressionFit,
    Term,
    design_matrix,
    fit_without_outliers,
    full_quadratic,
    stepwise_terms,
)

__all__ = ["Analysis", "OUTLIER_RULE", "analyse", "analysis_document", "anova_document", "anova_rows",
           "choose_terms", "combination_label", "optimum_values", "plot_main_effects", "regression_document"]

OUTLIER_RULE = ("removed once: runs whose residual interval r ± t(1−α/2, n−p−1) s_(i) √(1−h) excludes zero "
                "(externally studentized residual beyond the t quantile; MATLAB regress/rcoplot)")


@dataclass(frozen=True, eq=False)
class Analysis:
    """Everything `doe analyze` reports for one response."""

    design: Design
    ranges: tuple[ColumnRange, ...]
    anova: Anova
    pooled: Anova
    optimum: dict[str, int]
    regression: RegressionFit
    term_selection: str


def choose_terms(design: Design, terms: str | tuple[Term, ...] = "auto") -> tuple[tuple[Term, ...], str]:
    """The regression terms and how they were chosen.

    ``auto``: the full second-order model when the design can tell all its terms apart and leaves at
    least 4 residual degrees of freedom (an orthogonal array of resolution III cannot), else stepwise
    selection from it; ``full``; ``stepwise``; or an explicit tuple of terms.
    """
    x, y = design.values(), design.response
    if not isinstance(terms, str):
        return tuple(terms), "given"
    full = full_quadratic(x.shape[1])
    estimable = y.size - len(full) >= 4 and np.linalg.matrix_rank(design_matrix(x, full)) == len(full)
    if terms == "full" or (terms == "auto" and estimable):
        return full, "full second-order model"
    if terms in ("auto", "stepwise"):
        return stepwise_terms(x, y, full), "stepwise from the full second-order model (enter p < 0.05, remove p > 0.10)"
    raise ValueError(f"terms must be auto, full, stepwise or a list of terms, got {terms!r}")


def analyse(design: Design, alpha: float = 0.05, pool_below_F: float | None = 1.0, pool: tuple[str, ...] = (),  # noqa: PLR0913
            goal: str = "min", *, terms: str | tuple[Term, ...] = "auto", outliers="auto") -> Analysis:
    """Range analysis, ANOVA (unpooled and pooled), optimal levels and the second-order regression.

    Parameters
    ----------
    design : Design
        From :func:`read_design`.
    alpha : float
        Significance level of the F tests.
    pool_below_F : float or None
        Pool every source whose F is below this into the error (None: no pooling by F).
    pool : tuple of str
        Sources to pool by name.
    goal : {"min", "max"}
        Which response is better.
    terms : {"auto", "full", "stepwise"} or tuple of Term
        Regression terms (:func:`choose_terms`).
    outliers : "auto", None or sequence of int
        Runs left out of the regression: flagged by residual intervals, none, or given (0-based).

    Returns
    -------
    Analysis
        Ranges, both ANOVA tables, the optimal levels and the regression.
    """
    table = anova(design, alpha)
    pooled = anova(design, alpha, pool_below_F, pool) if (pool_below_F is not None or pool) else table
    chosen, how = choose_terms(design, terms)
    regression = fit_without_outliers(design.values(), design.response, chosen, outliers, alpha=0.05)
    return Analysis(design=design, ranges=range_analysis(design), anova=table, pooled=pooled,
                    optimum=optimal_levels(design, pooled, goal), regression=regression, term_selection=how)


def combination_label(optimum: dict[str, int]) -> str:
    """``A3B1C2D3E1``.

    Parameters
    ----------
    optimum : dict of str to int
        Factor key → level (1-based).

    Returns
    -------
    str
        The factors' keys with their levels, in order.
    """
    return "".join(f"{key}{level}" for key, level in optimum.items())


def optimum_values(design: Design, optimum: dict[str, int]) -> np.ndarray:
    return np.array([f.values[optimum[f.key] - 1] for f in design.factors])


def _row(row: AnovaRow) -> dict:
    return {"S": row.S, "f": row.f, "V": row.V, "F": row.F, "p": row.p, "F_critical": row.F_critical,
            "significant": row.significant}


def anova_document(table: Anova) -> dict:
    return {
        "alpha": table.alpha,
        "sources": {r.source: _row(r) for r in table.rows},
        "error": {"S": table.error.S, "f": table.error.f, "V": table.error.V},
        "total": {"S": table.total.S, "f": table.total.f},
        "pooled_into_error": list(table.pooled),
        "array": table.array,
        "empty_columns": list(table.empty_columns),
        "empty_columns_S": table.empty_columns_S,
        "notes": list(table.notes),
    }


def regression_document(analysis: Analysis) -> dict:
    """The regression part of the JSON of ``doe analyze``: terms, coefficients, fit statistics, prediction at the optimum.

    Parameters
    ----------
    analysis : Analysis
        From :func:`analyse`: its regression fit, design and optimal levels.

    Returns
    -------
    dict
        The ``regression`` section.
    """
    fit, design = analysis.regression, analysis.design
    point = optimum_values(design, analysis.optimum)
    return {
        "response": design.response_name,
        "variables": {f"x{i + 1}": f"{f.key}: {f.name} [{f.unit}]" for i, f in enumerate(design.factors)},
        "term_selection": analysis.term_selection,
        "terms": list(fit.names),
        "coefficients": [float(c) for c in fit.coefficients],
        "r2": fit.r2,
        "adjusted_r2": fit.adjusted_r2,
        "F": fit.F,
        "p": fit.p,
        "residual_std": fit.residual_std,
        "runs_used": int(fit.used.sum()),
        "removed_runs": [design.runs[i] for i in fit.removed],
        "outlier_rule": OUTLIER_RULE,
        "outlier_note": fit.note,
        "studentized_residuals": {run: (None if np.isnan(t) else float(t)) for run, t in zip(design.runs, fit.studentized)},
        "prediction_at_optimum": {"levels": combination_label(analysis.optimum),
                                  "x": [float(v) for v in point], "y": float(fit.predict(point)[0])},
    }


def analysis_document(analysis: Analysis) -> dict:
    """The JSON of `doe analyze`: range (K, k, R per column), anova (S, f, V, F, p per source), regression.

    Parameters
    ----------
    analysis : Analysis
        One response's analysis (:func:`analyse`).

    Returns
    -------
    dict
        The document, ready for :func:`rvcoax.results.io.write_json_atomic`.
    """
    design = analysis.design
    return {
        "response": design.response_name,
        "runs": len(design.runs),
        "factors": {f.key: {"name": f.name, "unit": f.unit, "levels": list(f.values)} for f in design.factors},
        "range": {r.column: {"K": list(r.K), "k": list(r.k), "R": r.R} for r in analysis.ranges},
        "anova": anova_document(analysis.anova),
        "anova_pooled": anova_document(analysis.pooled),
        "optimal_levels": {"levels": analysis.optimum, "combination": combination_label(analysis.optimum)},
        "regression": regression_document(analysis),
    }


def anova_rows(analysis: Analysis) -> list[dict]:
    """One CSV row per source of both tables (unpooled and pooled).

    Parameters
    ----------
    analysis : Analysis
        Both of its ANOVA tables are written.

    Returns
    -------
    list of dict
        Keys response, table (``unpooled`` or ``pooled``), source, S, f, V, F, p, F_critical and
        significant; the error and total rows close each table.
    """
    rows = []
    for label, table in (("unpooled", analysis.anova), ("pooled", analysis.pooled)):
        for row in (*table.rows, table.error, table.total):
            rows.append({"response": analysis.design.response_name, "table": label, "source": row.source,
                         "S": row.S, "f": row.f, "V": row.V if row.source != "total" else None,
                         "F": row.F, "p": row.p, "F_critical": row.F_critical, "significant": row.significant})
    return rows


def plot_main_effects(analyses: list[Analysis], path_png: str | Path, title: str | None = None, dpi: int = 130) -> Path:
    """Mean response at each level of each factor (one row of panels per response), as a PNG.

    Parameters
    ----------
    analyses : list of Analysis
        One per response.
    path_png : str or Path
        Where the picture goes.
    title : str, optional
        The figure's title.
    dpi : int
        Resolution.

    Returns
    -------
    Path
        ``path_png``, written atomically.
    """
    from matplotlib.figure import Figure  # Agg, no display needed

    n_factors = max(len(a.design.factors) for a in analyses)
    figure = Figure(figsize=(2.3 * n_factors + 1, 2.6 * len(analyses) + 0.6), dpi=dpi, layout="constrained")
    axes = np.atleast_2d(figure.subplots(len(analyses), n_factors, sharey="row", squeeze=False))
    for row, analysis in zip(axes, analyses):
        design = analysis.design
        ranges = {r.column: r for r in analysis.ranges}
        mean = float(design.response.mean())
        significant = {r.source for r in analysis.pooled.rows if r.significant}
        for ax, factor in zip(row, design.factors):
            r = ranges[factor.key]
            ax.plot(factor.values, r.k, "o-", color="C3" if factor.key in significant else "C0")
            ax.axhline(mean, color="grey", lw=0.8, ls="--")
            ax.set_title(f"{factor.key}: R = {r.R:.3g}" + (" *" if factor.key in significant else ""), fontsize=9)
            ax.set_xlabel(f"{factor.name} [{factor.unit}]", fontsize=7)
            ax.tick_params(labelsize=7)
            ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
            ax.grid(True, alpha=0.3)
        row[0].set_ylabel(f"mean {design.response_name}", fontsize=8)
        for ax in row[len(design.factors):]:
            ax.set_visible(False)
    figure.suptitle((title + "\n" if title else "") + "main effects (* significant after pooling; dashed: grand mean)",
                    fontsize=10)
    return write_png_atomic(path_png, figure)
