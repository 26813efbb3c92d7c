"""Range analysis and analysis of variance of an orthogonal experiment, pooling, optimal levels.

Range analysis, per column j and level l: K_jl = Σ y over the runs at level l, k_jl = K_jl / s_jl
(s_jl runs at that level) and R_j = max_l k_jl − min_l k_jl.

ANOVA: S_T = Σ (y − ȳ)², with N − 1 degrees of freedom; a column's S_j = Σ_l K_jl² / s_jl − T² / N
with (levels − 1) degrees of freedom; an interaction spread over several columns adds their S and f.
The error is what the assigned sources leave, S_e = S_T − Σ S_j, f_e = N − 1 − Σ f_j: in a saturated
array (L9, L27, L81) that is exactly the sum over the empty columns, which are found by matching the
design to the standard array (:func:`rvcoax.results.studies.doe.orthogonal.match_columns`). V = S / f, F = V / V_e,
p = P(F(f, f_e) > F). Pooling: sources whose F is below a threshold (or named ones) join the error,
and F and p of the others are taken again against the pooled error.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from rvcoax.results.studies.doe.design import Design, Source
from rvcoax.results.studies.doe.orthogonal import ARRAYS, match_columns, standard_array

__all__ = ["Anova", "AnovaRow", "ColumnRange", "anova", "column_sum_of_squares", "optimal_levels", "range_analysis"]


@dataclass(frozen=True)
class ColumnRange:
    """K (level sums), k (level means) and R (range) of one design column."""

    column: str
    K: tuple[float, ...]
    k: tuple[float, ...]
    R: float

@dataclass(frozen=True)
class AnovaRow:
    """One source: sum of squares S, degrees of freedom f, mean square V, F, p, critical F at α."""

    source: str
    S: float
    f: int
    V: float
    F: float | None = None
    p: float | None = None
    F_critical: float | None = None
    significant: bool | None = None


@dataclass(frozen=True)
class Anova:
    """An ANOVA table: the sources (pooled ones excluded), the error, the total."""

    rows: tuple[AnovaRow, ...]
    error: AnovaRow
    total: AnovaRow
    alpha: float
    pooled: tuple[str, ...] = ()
    array: str | None = None
    empty_columns: tuple[int, ...] = ()
    empty_columns_S: float | None = None
    notes: tuple[str, ...] = field(default_factory=tuple)

    def row(self, source: str) -> AnovaRow:
        return next(r for r in self.rows if r.source == source)


def column_sum_of_squares(codes: np.ndarray, y: np.ndarray) -> float:
    """S = Σ_l K_l² / s_l − T² / N of one column."""
    levels = np.unique(codes)
    sums = np.array([y[codes == level].sum() for level in levels])
    counts = np.array([(codes == level).sum() for level in levels])
    return float((sums**2 / counts).sum() - y.sum() ** 2 / y.size)


def range_analysis(design: Design) -> tuple[ColumnRange, ...]:
    """K, k and R of every coded column of the design."""
    out = []
    for column, codes in design.codes.items():
        levels = np.unique(codes)
        K = tuple(float(design.response[codes == level].sum()) for level in levels)
        k = tuple(float(design.response[codes == level].mean()) for level in levels)
        out.append(ColumnRange(column, K, k, max(k) - min(k)))
    return tuple(out)


def _source_row(design: Design, source: Source) -> AnovaRow:
    S = sum(column_sum_of_squares(design.codes[c], design.response) for c in source.columns)
    f = sum(len(np.unique(design.codes[c])) - 1 for c in source.columns)
    return AnovaRow(source.name, S, f, S / f)


def _tested(row: AnovaRow, error: AnovaRow, alpha: float) -> AnovaRow:
    if error.f == 0 or error.V <= 0:
        return row
    F = row.V / error.V
    p = float(stats.f.sf(F, row.f, error.f))
    return AnovaRow(source=row.source, S=row.S, f=row.f, V=row.V, F=F, p=p,
                    F_critical=float(stats.f.isf(alpha, row.f, error.f)), significant=p < alpha)


def _empty_columns(design: Design) -> tuple[str | None, tuple[int, ...], float | None]:
    """The standard array the design belongs to, its empty columns and their total S."""
    assigned = [c for s in design.sources if s.kind != "empty" for c in s.columns]
    if not assigned:
        return None, (), None
    table = np.column_stack([design.codes[c] for c in assigned])
    for name in ARRAYS:
        array = standard_array(name)
        matched = match_columns(table, array)
        if array.runs == table.shape[0] and all(m is not None for m in matched):
            empty = tuple(j for j in range(1, array.columns + 1) if j not in matched)
            S = sum(column_sum_of_squares(array.table[:, j - 1], design.response) for j in empty)
            return name, empty, float(S)
    return None, (), None


def anova(design: Design, alpha: float = 0.05, pool_below_F: float | None = None,
          pool: tuple[str, ...] = ()) -> Anova:
    """ANOVA of ``design``; factor, interaction and named empty sources, error from what they leave.

    Parameters
    ----------
    alpha : float
        Significance level of the F tests.
    pool_below_F : float, optional
        Pool every source whose F (against the unpooled error) is below this value.
    pool : tuple of str
        Sources to pool by name (also possible when the unpooled error has no degrees of freedom).
    """
    if not 0 < alpha < 1:
        raise ValueError(f"alpha must be in (0, 1), got {alpha}")
    y = design.response
    total = AnovaRow("total", float(((y - y.mean()) ** 2).sum()), y.size - 1, float(np.var(y, ddof=1)))
    rows = [_source_row(design, s) for s in design.sources if s.kind != "empty"]
    unknown = [name for name in pool if name not in {r.source for r in rows}]
    if unknown:
        raise ValueError(f"cannot pool {', '.join(unknown)}: not a source (sources: {', '.join(r.source for r in rows)})")
    S_e = total.S - sum(r.S for r in rows)
    f_e = total.f - sum(r.f for r in rows)
    if f_e < 0:
        raise ValueError(f"the sources use {total.f - f_e} degrees of freedom, more than the {total.f} of the design")
    error = AnovaRow("error", max(S_e, 0.0), f_e, max(S_e, 0.0) / f_e if f_e else float("nan"))
    array, empty, empty_S = _empty_columns(design)
    notes = []
    tested = [_tested(r, error, alpha) for r in rows]
    pooled = set(pool)
    if pool_below_F is not None and error.f > 0:
        pooled |= {r.source for r in tested if r.F is not None and r.F < pool_below_F}
    if pooled:
        S_p = error.S + sum(r.S for r in rows if r.source in pooled)
        f_p = error.f + sum(r.f for r in rows if r.source in pooled)
        error = AnovaRow("error (pooled)", S_p, f_p, S_p / f_p)
        tested = [_tested(r, error, alpha) for r in rows if r.source not in pooled]
        notes.append(f"pooled into the error: {', '.join(sorted(pooled))}")
    if error.f == 0:
        notes.append("no degrees of freedom left for the error: F and p need pooling (pool sources by name)")
    return Anova(rows=tuple(tested), error=error, total=total, alpha=alpha, pooled=tuple(sorted(pooled)), array=array,
                 empty_columns=empty, empty_columns_S=empty_S, notes=tuple(notes))


def optimal_levels(design: Design, table: Anova | None = None, goal: str = "min") -> dict[str, int]:
    """The level of each factor with the best mean response (``goal`` = ``min`` or ``max``).

    Main effects decide, except for a pair of factors whose interaction is significant in ``table``:
    that pair takes the best cell of their two-way table of means.
    """
    if goal not in ("min", "max"):
        raise ValueError(f"goal must be 'min' or 'max', got {goal!r}")
    pick = np.argmin if goal == "min" else np.argmax
    y = design.response
    best = {}
    for factor in design.factors:
        codes = design.codes[factor.key]
        levels = np.unique(codes)
        best[factor.key] = int(levels[pick([y[codes == level].mean() for level in levels])])
    significant = {r.source for r in (table.rows if table else ()) if r.significant}
    for source in design.sources:
        if source.kind == "interaction" and source.name in significant:
            a, b = (design.codes[k] for k in source.factors)
            cells = [(la, lb) for la in np.unique(a) for lb in np.unique(b)]
            means = [y[(a == la) & (b == lb)].mean() for la, lb in cells]
            best[source.factors[0]], best[source.factors[1]] = (int(v) for v in cells[int(pick(means))])
    return best
