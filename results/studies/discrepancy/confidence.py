"""How often the workflow's verdict is right on data like these: a Monte Carlo of its own decisions.

Synthetic data sets are drawn on the file's own observations (stations, cases, datum, schema), with its noise
(σ estimated or from the ``sigma_mm`` column, the printed quantum of a table) and a model-form difference up to the
allowance (each shaft's signal scaled by 1 + ε and, along a paths file's shaft, bent by a quadratic, together up to
``model_form_fraction`` of the signal). What is hidden in a draw is what the **file's own data support**
(:func:`_supported`): every explanation whose BIC on the file lies within the workflow's BIC margin of the best one —
nothing; one visible candidate at its value fitted to the file (within its physical bounds, or beyond one for a linear
candidate whose best fit lies there); the best single with a second candidate, when the single leaves a gap and both
earn their parameter; a generic load outside the vocabulary (a force ∝ T2, ∝ T1 or constant, or a moment ∝ T2, at a
shaft site where no named effect puts its load, sized like the file's gap). A draw picks a kind with the weights of
:data:`TRUTHS` among the kinds supported, one explanation of that kind, and each value times a factor within
±:data:`JITTER`. The draws therefore hide what data like the file's could hide, at its sizes, not any candidate at
any size: drawn from the whole vocabulary (2–50 % of the signal at random places), the draws were harder than the
files and the stated probability fell below the observed rate (benchmarks/RESULTS.md, issue 28). Where nothing is
supported (the scan cannot run) the draws come from that broad prior (:data:`TRUTHS`: nothing; one or two visible
candidates at 2–50 % of the signal, log-uniform within their bounds; a generic load; a linear candidate at 1.5–4
times one of its bounds, right answered anything but ``explained``).

Each draw is judged by a **replay** of the workflow's decisions on the responses already computed for this file (no
assembly, no solve per draw): the same σ, rows and observation operator; every candidate fitted alone on a grid of
its parameter (exact |Y_max| for a table; closed form for a linear effect on a paths file), forward selection by the
BIC margin up to two effects (the pair fitted on both grids), the stop on the verdict's own gap test, groups within
the ambiguity margin or with parallel fitted signatures (an ``ambiguous`` answer also names the partner of every pair
with its first effect that fits as well), the sentinel scanned for every draw at once
(:func:`sentinel.sentinel_scan`), a generic load at a named effect's place taken as that effect, cancelling effects,
opposite loads at neighbouring places, fits only beyond a bound, a generic load within the noise, groups of more than
three. It omits what costs a solve or a refit per draw: the refinement with the true model, the pair search before
an implausible single, the cross-validation and the curvature rule. The replay's verdict on the file's own data is
reported beside the workflow's, so a reader sees when the two differ.

A draw is *right* as the blind benchmark scores honesty: nothing hidden → ``no_gap``; a vocabulary truth → ``explained``
or ``ambiguous`` with the truth in a named group; a load outside the vocabulary → ``unexplained`` or ``ambiguous``; a
hidden change below 1 σ RMS → nothing added is right too. P(right | verdict, group size, fit quality) is the rate
of right draws among those with the file's verdict, group-size class and fit-quality class (χ²/n after the fit on
the fitted rows at most 1, or above; for ``unexplained``: whether the generic load of the sentinel fits better than
the best named fit by the BIC margin, which marks a load outside the vocabulary), backing off to fewer features while fewer than :data:`MIN_BIN` draws share
them; its uncertainty is the Wilson 95 % interval of that rate. Where fewer than :data:`SAME_VERDICT` of the
draws share the file's verdict, more are drawn from the same prior (up to :data:`MAX_DRAWS`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy import stats

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.studies.discrepancy.engine import CANDIDATE_FAILURES
from rvcoax.results.studies.discrepancy.judge import (
    AMBIGUOUS_GROUP,
    FIGHT_RATIO,
    load_regions,
    load_x,
    look_alike_places,
)
from rvcoax.results.studies.discrepancy.locate import detection_norm
from rvcoax.results.studies.discrepancy.sentinel import FAMILIES, SLOTS, sentinel_scan, site_in

__all__ = ["DRAWS", "MIN_BIN", "TRUTHS", "Confidence", "verdict_confidence", "wilson"]

DRAWS = 160  # the paper's table: about 1 s on a loaded 2-core machine (benchmarks/RESULTS.md)
SAME_VERDICT = 40  # draws with the file's verdict wanted: more are drawn (in half batches) until this many share it
MAX_DRAWS = 480  # ... up to this many in all (per DRAWS asked for)
MIN_BIN = 15  # draws a bin needs before its rate is used
SEED = 28
GRID = 41  # parameter values per candidate, at least
GRID_MAX = 801  # and at most
GRID_CELLS = 2e6  # candidates × values × observations the grids may hold (a table's 40 rows: the finest grids)
PAIR_GRID = 41  # values per candidate in the first look at a pair (then refined by Gauss–Newton steps on the full grids)
# what a draw hides, and how often: nothing, one or two visible candidates within their bounds, a generic load outside
# the vocabulary, or one linear candidate beyond its physical bound (BEYOND times it, log-uniform)
TRUTHS = {"none": 0.15, "single": 0.4, "pair": 0.2, "outside": 0.15, "beyond": 0.1}
BEYOND = (1.5, 4.0)
# a hidden effect's size: RMS change over RMS signal on the shaft it changes most, log-uniform between half and twice
# the file's own gap (measured − model, the same ratio), kept within these limits
FRACTIONS = (0.02, 0.6)
JITTER = 1.25  # a supported hypothesis's fitted values are drawn within this factor either way (log-uniform)
BEND = 0.5  # a shaft's model-form bend, at most this share of the allowance (its scale: all of it)
MAX_CELLS = 60e6  # candidates × grid × observations beyond which the replay is not run (memory)
# the probability model: a logistic regression of "right" on features of each draw's own answer, fitted on the draws
# that share the file's verdict (never on benchmark outcomes)
FEATURES = ("log χ²/n before (the gap)", "log χ²/n after", "generic load's BIC gain / 10", "log group size",
            "margin to the next candidate (ΔBIC) / 10")
MARGIN_CAP = 60.0  # ΔBIC: a margin or a generic load's gain beyond this says nothing more (the features are capped)
RIDGE = 1.0  # L2 penalty on the standardised slopes: a unit-variance Gaussian prior on each (a standard default)


@dataclass(frozen=True)
class Confidence:
    """The probability that the verdict is right, from draws on data like the file's.

    ``probability`` is the rate of right draws in ``bin`` (``right`` of ``draws``, Laplace-smoothed: (right + 1) / (draws + 2)), ``low``/``high`` its Wilson 95 %
    interval; ``total_draws`` all draws, ``replay_verdict`` what the replay said on the file's own data, ``rates``
    the right rate per verdict over all draws ((verdict, right, draws), ...)."""

    probability: float
    low: float
    high: float
    right: int
    draws: int
    total_draws: int
    bin: str
    replay_verdict: str
    seed: int
    seconds: float
    rates: tuple[tuple[str, int, int], ...]
    logistic: float | None = None  # P(right) of a logistic model in :data:`FEATURES` on the draws with the verdict
    nearest: float | None = None  # the rate among the nearest of those draws in the same features
    features: tuple[float, ...] = ()  # the file's own features (:data:`FEATURES`)

    def sentence(self, verdict: str) -> str:
        agree = "" if self.replay_verdict == verdict else \
            f"; the replay of the decisions said {self.replay_verdict} on these data, so the estimate is rough"
        return (f"confidence: the verdict '{verdict}' is right in {100 * self.probability:.0f} % "
                f"(95 % interval {100 * self.low:.0f}–{100 * self.high:.0f} %) of {self.draws} synthetic data sets "
                f"like these with the same answer ({self.bin}; {self.total_draws} drawn, seed {self.seed}){agree}")

    def as_dict(self) -> dict:
        return {"probability": round(self.probability, 4), "interval_95": [round(self.low, 4), round(self.high, 4)],
                "right": self.right, "draws_in_bin": self.draws, "draws": self.total_draws, "bin": self.bin,
                "replay_verdict": self.replay_verdict, "seed": self.seed, "seconds": round(self.seconds, 3),
                "method": "Monte Carlo of the workflow's decisions on synthetic data of this file's rig, observations "
                          "and noise (docs/discrepancy.md, 'Confidence')",
                "right_rate_by_verdict": [{"verdict": v, "right": r, "draws": n} for v, r, n in self.rates],
                "logistic_probability": None if self.logistic is None else round(self.logistic, 4),
                "nearest_draws_probability": None if self.nearest is None else round(self.nearest, 4),
                "features": {name: round(v, 4) for name, v in zip(FEATURES, self.features)}}


def wilson(right: int, n: int, z: float = 1.959964) -> tuple[float, float]:
    """The Wilson score interval of a rate ``right``/``n`` (95 % by default)."""
    if n == 0:
        return 0.0, 1.0
    p = right / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return float(max(centre - half, 0.0)), float(min(centre + half, 1.0))


# ---- the candidates on a grid --------------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class _Curve:
    """One candidate's observed change (mm, every observation) at ``values`` (its grid), ``physical`` where the values
    lie within the physical bounds; ``column``: the change per unit for a linear effect on a paths file (exact)."""

    name: str
    values: np.ndarray
    change: np.ndarray  # (grid, n)
    physical: np.ndarray
    linear: bool
    column: np.ndarray | None


def _observe_many(observe, base_paths: np.ndarray, deltas: np.ndarray) -> np.ndarray:
    """observe(base + delta) for each row of ``deltas``: a product for paths, |Y_max| of every block for a table."""
    if hasattr(observe, "matrix"):
        return np.asarray(observe.matrix @ (base_paths[None, :] + deltas).T).T
    layout = observe.layout
    full = np.abs((base_paths[None, :] + deltas).reshape(deltas.shape[0], layout.n_cases, -1))
    n_in = layout.stations_mm["input"].size
    first, second = full[:, :, :n_in].max(axis=2), full[:, :, n_in:].max(axis=2)
    data = observe.data
    return np.where(data.shaft == "input", first[:, data.case_index], second[:, data.case_index])


def _points(n_candidates: int, n: int) -> int:
    """Values per candidate grid: as many as :data:`GRID_CELLS` allow, :data:`GRID` to :data:`GRID_MAX`."""
    return int(np.clip(GRID_CELLS / max(n_candidates * n, 1), GRID, GRID_MAX))


def _grid_values(response, points: int) -> np.ndarray:
    lower, upper = response.search_bounds()
    lo, hi = float(lower[0]), float(upper[0])
    if response.kind == "grid":  # the response's own grid (dense where it bends), each interval split evenly
        nodes = np.asarray(response.grid, float)
        per = max(int(np.ceil((points - 1) / max(nodes.size - 1, 1))), 1)
        fine = [np.linspace(a, b, per + 1)[:-1] for a, b in zip(nodes[:-1], nodes[1:])]
        return np.unique(np.concatenate(fine + [nodes[-1:], [0.0]]))
    t = np.linspace(-1.0, 1.0, points)  # ±10 × the physical span: dense near zero
    return np.unique(np.concatenate([np.where(t < 0, -lo, hi) * t * np.abs(t), [0.0]]))


def _deltas(response, values: np.ndarray, engine, cases) -> np.ndarray:
    """The response's change of the full paths at each of ``values`` (rows), evaluated at once."""
    from scipy.interpolate import CubicSpline

    if response.kind == "linear":
        return values[:, None] * response.columns[0][None, :]
    v = np.clip(values, response.grid[0], response.grid[-1])
    if response.grid_paths is not None:
        return CubicSpline(response.grid, response.grid_paths, axis=0)(v)
    unit = CubicSpline(response.grid, response.unit.reshape(response.grid.size, -1), axis=0)(v)
    unit = unit.reshape(v.size, *response.unit.shape[1:])  # (values, unit loads, path)
    return np.einsum("cu,jup->jcp", response.weights, unit).reshape(v.size, -1)


def _curves(seen, names) -> list[_Curve]:
    observed = seen.observed
    base, observe = observed.base_paths, observed.observe
    before = observed.before
    points = _points(len(names), observed.data.n)
    out = []
    for name in names:
        response = seen.responses[name]
        if response.n_params != 1:
            continue
        p = response.effect.parameters[0]
        values = _grid_values(response, points)
        if response.kind == "linear" and hasattr(observe, "matrix"):
            column = np.asarray(observe.matrix @ response.columns[0])
            change = values[:, None] * column[None, :]
        else:
            column = None
            deltas = _deltas(response, values, observed.engine, observed.data.cases)
            change = _observe_many(observe, base, deltas) - before[None, :]
        physical = (values >= p.lower - 1e-9 * max(1.0, abs(p.lower))) & \
            (values <= p.upper + 1e-9 * max(1.0, abs(p.upper)))
        out.append(_Curve(name, values, change, physical, response.kind == "linear", column))
    return out


# ---- fits on the grids ----------------------------------------------------------------------------------------

def _parabola(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Vertex (x, y) of the parabola through three points, kept between the outer two."""
    (x0, x1, x2), (y0, y1, y2) = x, y
    denom = (x0 - x1) * (x0 - x2) * (x1 - x2)
    if denom == 0:
        return float(x1), float(y1)
    a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / denom
    b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / denom
    if a <= 0:
        return float(x1), float(y1)
    xv = float(np.clip(-b / (2 * a), x0, x2))
    c = y1 - a * x1 * x1 - b * x1
    return xv, float(max(a * xv * xv + b * xv + c, 0.0))


def _at(curve: _Curve, value: float) -> np.ndarray:
    """The curve's change at ``value`` (linear interpolation between grid points; exact for a linear column)."""
    if curve.column is not None:
        return value * curve.column
    j = int(np.clip(np.searchsorted(curve.values, value), 1, curve.values.size - 1))
    v0, v1 = curve.values[j - 1], curve.values[j]
    w = 0.0 if v1 == v0 else (value - v0) / (v1 - v0)
    return (1 - w) * curve.change[j - 1] + w * curve.change[j]


@dataclass(frozen=True)
class _Single:
    chi2: np.ndarray  # (draws, candidates) on the fitted rows
    value: np.ndarray
    physical: np.ndarray  # fitted value within the physical bounds


def _single_fits(curves: list[_Curve], scaled_fit: np.ndarray, rows: np.ndarray, sigma: np.ndarray) -> _Single:
    """Every candidate fitted alone to every draw (scaled residuals on the fitted rows, (draws, n_fit))."""
    m = scaled_fit.shape[0]
    total = np.einsum("mi,mi->m", scaled_fit, scaled_fit)
    chi2 = np.empty((m, len(curves)))
    value = np.empty_like(chi2)
    physical = np.empty(chi2.shape, dtype=bool)
    s_fit = sigma[rows]
    for c, curve in enumerate(curves):
        if curve.column is not None:  # closed form, within the search bounds
            a = curve.column[rows] / s_fit
            aa = float(a @ a)
            x = scaled_fit @ a / aa if aa > 0 else np.zeros(m)
            x = np.clip(x, curve.values[0], curve.values[-1])
            chi2[:, c] = total - 2 * x * (scaled_fit @ a) + x * x * aa
            value[:, c] = x
        else:
            s = curve.change[:, rows] / s_fit[None, :]
            grid = total[:, None] - 2 * scaled_fit @ s.T + np.einsum("ji,ji->j", s, s)[None, :]
            j = np.argmin(grid, axis=1)
            for d in range(m):
                k = int(j[d])
                if 0 < k < curve.values.size - 1:
                    value[d, c], chi2[d, c] = _parabola(curve.values[k - 1:k + 2], grid[d, k - 1:k + 2])
                else:
                    value[d, c], chi2[d, c] = curve.values[k], grid[d, k]
        lo, hi = curve.values[curve.physical][[0, -1]]
        physical[:, c] = (value[:, c] >= lo - 1e-9 * max(1.0, abs(lo))) & (value[:, c] <= hi + 1e-9 * max(1.0, abs(hi)))
    return _Single(np.maximum(chi2, 0.0), value, physical)


def _coarse(values: np.ndarray) -> np.ndarray:
    """At most :data:`PAIR_GRID` indices of a grid, its ends and zero kept."""
    if values.size <= PAIR_GRID:
        return np.arange(values.size)
    keep = np.unique(np.round(np.linspace(0, values.size - 1, PAIR_GRID)).astype(int))
    return np.unique(np.concatenate([keep, np.flatnonzero(values == 0.0)]))


def _line_search(grid: np.ndarray, norms: np.ndarray, target: np.ndarray) -> tuple[int, np.ndarray]:
    """The index of the grid row closest to ``target`` (scaled), and every row's χ²."""
    chi2 = float(target @ target) - 2 * grid @ target + norms
    return int(np.argmin(chi2)), chi2


def _refine_index(values: np.ndarray, chi2: np.ndarray, k: int) -> tuple[float, float]:
    if 0 < k < values.size - 1:
        return _parabola(values[k - 1:k + 2], chi2[k - 1:k + 2])
    return float(values[k]), float(chi2[k])


# ---- the replay of the decisions -------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Answer:
    verdict: str
    named: tuple[str, ...]  # every member of every named group
    group: int  # the largest named group
    quality: float  # χ²/n on the fitted rows after (before, when nothing is added)
    why: str = ""  # the rule that decided
    generic_gain: float = 0.0  # BIC of the named fit (of no effect, when none is named) − BIC of the best generic load
    gap: float = 0.0  # χ²/n on the fitted rows before any effect: the size of the gap, in σ²
    margin: float = 0.0  # BIC of the best single effect outside the winner's group − BIC of the winner (0: none won)


@dataclass(frozen=True, eq=False)
class _Vocabulary:
    """What the replay needs of the candidates, whatever σ: their grids, and where each puts its load."""

    curves: list
    names: list
    effects: dict
    sites: list
    region_sites: dict  # name → sentinel sites where it puts its load (a generic load there is that effect)
    alike_sites: dict  # name → sentinel sites where it or a look-alike acts
    places_x: dict  # torque-proportional loads: name → x (mm)


def _vocabulary(seen) -> _Vocabulary:
    names = [n for n in seen.responses if n not in seen.set_aside]
    curves = _curves(seen, names)
    names = [c.name for c in curves]
    sites = seen.observed.engine.sentinel_sites()
    regions = load_regions(seen.effects, seen.rig, names, sites)
    places = look_alike_places(seen.effects, seen.rig, names, sites)
    return _Vocabulary(curves, names, seen.effects, sites,
                       {n: frozenset(i for i, s in enumerate(sites) if site_in(s, regions.get(n, ()))) for n in names},
                       {n: frozenset(i for i, s in enumerate(sites) if site_in(s, places.get(n, ()))) for n in names},
                       load_x(seen.effects, seen.rig))


class _Replay:
    """The workflow's decision rules on the file's responses, for many data sets on the same observations and σ."""

    def __init__(self, vocabulary: _Vocabulary, observed, settings):
        self.settings = settings
        self.observed = observed
        self.rows = observed.rows
        self.sigma = observed.sigma
        self.n_fit = int(self.rows.sum())
        self.ln_n = float(np.log(max(self.n_fit, 2)))
        self.curves, self.names, self.effects = vocabulary.curves, vocabulary.names, vocabulary.effects
        self.sites, self.places_x = vocabulary.sites, vocabulary.places_x
        self.region_sites, self.alike_sites = vocabulary.region_sites, vocabulary.alike_sites
        s_fit = self.sigma[self.rows]
        self.grids = [(c.change[:, self.rows] if c.column is None else c.values[:, None] * c.column[self.rows][None, :])
                      / s_fit[None, :] for c in self.curves]
        self.norms = [np.einsum("ji,ji->j", g, g) for g in self.grids]
        self.model_form_norm = settings.model_form_fraction * float(np.linalg.norm(observed.before[self.rows]))
        self.detection = detection_norm(self.n_fit, settings.alpha)  # a difference the gap test sees (in σ)
        self._cross: dict[int, list[np.ndarray]] = {}

    # -- one data set ----------------------------------------------------------------------------------------
    def answers(self, scaled: np.ndarray) -> list[_Answer]:
        """The replay's answer for every row of ``scaled`` ((draws, n): (measured − base) / σ)."""
        rows = self.rows
        scaled_fit = scaled[:, rows]
        singles = _single_fits(self.curves, scaled_fit, rows, self.sigma)
        scan = sentinel_scan(self.observed, scaled)
        entry_site = None if scan is None else np.array([self.sites.index(s) for s in scan.site])
        out = []
        for d in range(scaled.shape[0]):
            out.append(self._answer(scaled[d], singles, d, scan, entry_site))
        return out

    def _gap(self, residual: np.ndarray) -> bool:
        return stats.chi2.sf(float(residual @ residual), residual.size) < self.settings.alpha

    def _answer(self, r: np.ndarray, singles: _Single, d: int, scan, entry_site) -> _Answer:
        settings, rows = self.settings, self.rows
        r_fit = r[rows]
        chi2_0 = float(r_fit @ r_fit)
        generic = float(scan.bic[d].min()) if scan is not None and np.isfinite(scan.bic[d]).any() else np.inf
        gap = chi2_0 / max(self.n_fit, 1)
        if not self._gap(r):  # the workflow's test before any fit reads every row
            return _Answer("no_gap", (), 0, gap, "", chi2_0 - generic, gap)
        bic = singles.chi2[d] + self.ln_n
        valid = singles.physical[d]
        if not valid.any() or chi2_0 - bic[valid].min() < settings.bic_margin:
            return _Answer("unexplained", (), 0, gap, "no effect gains the margin", chi2_0 - generic, gap)
        order = np.flatnonzero(valid)[np.argsort(bic[valid])]
        w = int(order[0])
        group = self._group(w, order, bic, singles=singles, d=d, chi2_0=chi2_0)
        outside = [float(bic[c]) for c in order if int(c) not in group]
        margin = (min(outside) - float(bic[w])) if outside else MARGIN_CAP
        w = self._representative(w, group, bic)
        selected = [(w, float(singles.value[d, w]))]
        fit_bic, fit_chi2 = float(bic[w]), float(singles.chi2[d, w])
        groups = [group]
        model = _at(self.curves[w], selected[0][1]) / self.sigma
        if self._gap(r - model):  # a second effect
            pair = self._second(r, w, fit_bic)
            if pair is not None:
                (c, vw, vc, chi2_pair), second_group = pair
                pair_bic = chi2_pair + 2 * self.ln_n
                if float(bic[c]) - pair_bic < settings.bic_margin:  # the first is pruned: the second alone
                    selected, groups = [(c, float(singles.value[d, c]))], [second_group]
                    fit_bic, fit_chi2 = float(bic[c]), float(singles.chi2[d, c])
                else:
                    selected = [(w, vw), (c, vc)]
                    groups = [group, second_group]
                    fit_bic, fit_chi2 = pair_bic, chi2_pair
                model = sum(_at(self.curves[i], v) for i, v in selected) / self.sigma
        named = tuple(dict.fromkeys(self.names[i] for g in groups for i in g))
        quality = fit_chi2 / max(self.n_fit, 1)
        verdict, why = self._verdict(r, model, selected, groups, bic=fit_bic, chi2=fit_chi2, singles=singles, d=d, scan=scan,
                                     entry_site=entry_site)
        if verdict == "ambiguous":  # the members of every pair with the first effect that fits as well
            w = selected[0][0]
            extra = [self.names[c] for c, (chi2_pair, _, _) in self.pair_fits(r, w).items()
                     if (pair_bic := chi2_pair + 2 * self.ln_n) < fit_bic + settings.ambiguity_margin
                     and pair_bic < bic[w] and (not singles.physical[d, c] or pair_bic < bic[c])]
            named = tuple(dict.fromkeys(named + tuple(extra)))
        return _Answer(verdict, named, max(len(g) for g in groups), quality, why, fit_bic - generic, gap, margin)

    def _group(self, w: int, order, bic, *, singles: _Single, d: int, chi2_0: float) -> list[int]:  # noqa: PLR0913
        settings = self.settings
        best = float(bic[w])
        sw = _at(self.curves[w], singles.value[d, w])[self.rows] / self.sigma[self.rows]
        group = [w]
        for c in order[1:]:
            c = int(c)
            if bic[c] - best < settings.ambiguity_margin:
                group.append(c)
            elif chi2_0 - bic[c] >= settings.bic_margin:
                sc = _at(self.curves[c], singles.value[d, c])[self.rows] / self.sigma[self.rows]
                norm = np.linalg.norm(sw) * np.linalg.norm(sc)
                # a parallel look-alike stays only within the model-form allowance of the winner and below what the gap
                # test detects (the workflow's rule, workflow._fits_as_well)
                if norm > 0 and abs(float(sw @ sc)) / norm > settings.parallel_cosine \
                        and np.linalg.norm((sc - sw) * self.sigma[self.rows]) <= self.model_form_norm \
                        and np.linalg.norm(sc - sw) < self.detection:
                    group.append(c)
        return group

    def _representative(self, w: int, group: list[int], bic) -> int:
        """A linear member within the ambiguity margin in place of a nonlinear winner (as the screen does)."""
        if self.curves[w].linear:
            return w
        linear = [c for c in group if self.curves[c].linear and bic[c] - bic[w] < self.settings.ambiguity_margin]
        return min(linear, key=lambda c: bic[c]) if linear else w

    def _second(self, r: np.ndarray, w: int, fit_bic: float):
        """The best second effect with ``w`` (both refitted: a coarse look at both grids, then Gauss–Newton steps on the
        full ones), and its group; None when none gains the margin."""
        settings = self.settings
        fits = self.pair_fits(r, w)
        if not fits:
            return None
        best = min(fits, key=lambda c: fits[c][0])
        chi2 = fits[best][0]
        if fit_bic - (chi2 + 2 * self.ln_n) < settings.bic_margin:
            return None
        group = [best] + [c for c in fits if c != best and fits[c][0] - chi2 < settings.ambiguity_margin]
        return (best, fits[best][1], fits[best][2], chi2), group

    def pair_fits(self, r: np.ndarray, w: int) -> dict[int, tuple[float, float, float]]:
        """Every candidate fitted with ``w`` (both refitted: a coarse look at both grids, then Gauss–Newton steps on the
        full ones): candidate → (χ², value of ``w``, value of the candidate), pairs within the physical bounds only."""
        target = r[self.rows]
        if w not in self._cross:
            cw = _coarse(self.curves[w].values)
            pairs = []
            for i, c in enumerate(self.curves):
                cc = _coarse(c.values)
                pairs.append((cc, self.grids[w][cw] @ self.grids[i][cc].T))
            self._cross[w] = (cw, pairs)
        cw, crosses = self._cross[w]
        a = self.grids[w]
        coarse = {}
        for c in range(len(self.curves)):
            if c == w:
                continue
            cc, cross = crosses[c]
            b = self.grids[c]
            grid = (float(target @ target) - 2 * (a[cw] @ target)[:, None] - 2 * (b[cc] @ target)[None, :]
                    + self.norms[w][cw][:, None] + self.norms[c][cc][None, :] + 2 * cross)
            i, j = np.unravel_index(int(np.argmin(grid)), grid.shape)
            coarse[c] = (float(grid[i, j]), float(self.curves[w].values[cw[i]]), float(self.curves[c].values[cc[j]]))
        fits = {}
        for c, (start, vw, vc) in coarse.items():  # every one refined: a coarse look misses correlated pairs
            chi2, vw, vc = self._pair_refined(w, c, target, vw=vw, vc=vc, start=start)
            if self._physical(w, vw) and self._physical(c, vc):
                fits[c] = (chi2, vw, vc)
        return fits

    def _point(self, c: int, value: float) -> tuple[np.ndarray, np.ndarray, float]:
        """Candidate ``c``'s scaled change on the fitted rows at ``value`` (linear between grid values), its slope
        there, and the value kept within the grid."""
        values, grid = self.curves[c].values, self.grids[c]
        value = float(np.clip(value, values[0], values[-1]))
        j = int(np.clip(np.searchsorted(values, value), 1, values.size - 1))
        span = values[j] - values[j - 1]
        w = 0.0 if span == 0 else (value - values[j - 1]) / span
        slope = (grid[j] - grid[j - 1]) / span if span else np.zeros_like(grid[j])
        return (1 - w) * grid[j - 1] + w * grid[j], slope, value

    def _pair_refined(self, w: int, c: int, target: np.ndarray, *, vw: float, vc: float, start: float):  # noqa: PLR0913
        """(χ², value of ``w``, value of ``c``): Gauss–Newton steps from the grid's best point on the two curves
        (exact for linear effects on a paths file), the best point seen kept."""
        best = (start, vw, vc)
        for _ in range(4):
            a, da, vw = self._point(w, vw)
            b, db, vc = self._point(c, vc)
            residual = target - a - b
            chi2 = float(residual @ residual)
            if chi2 < best[0]:
                best = (chi2, vw, vc)
            step, *_ = np.linalg.lstsq(np.column_stack([da, db]), residual, rcond=None)
            if not np.all(np.isfinite(step)):
                break
            vw, vc = vw + float(step[0]), vc + float(step[1])
        a, _, vw = self._point(w, vw)
        b, _, vc = self._point(c, vc)
        residual = target - a - b
        chi2 = float(residual @ residual)
        return (chi2, vw, vc) if chi2 < best[0] else best

    def _physical(self, c: int, value: float) -> bool:
        curve = self.curves[c]
        lo, hi = curve.values[curve.physical][[0, -1]]
        return lo - 1e-9 * max(1.0, abs(lo)) <= value <= hi + 1e-9 * max(1.0, abs(hi))

    def _verdict(self, r, model, selected, groups, *, bic, chi2, singles: _Single, d, scan, entry_site) -> str:  # noqa: PLR0913
        settings = self.settings
        if self._gap(r - model):
            return "unexplained", "gap left"
        mimic = compared = generic = None
        if scan is not None:
            mimic = int(np.argmin(scan.bic[d]))
            at = set().union(*(self.region_sites[self.names[i]] for i, _ in selected))
            if entry_site[mimic] in at:
                away = np.where(np.isin(entry_site, list(at)), np.inf, scan.bic[d])
                compared = int(np.argmin(away)) if np.isfinite(away).any() else None
            else:
                compared = mimic
            members = {self.names[i] for g in groups for i in g}
            alike = set().union(*(self.alike_sites[m] for m in members))
            generic = None if compared is None or entry_site[compared] in alike else compared

        def within_noise(e):
            return stats.chi2.sf(float(scan.chi2[d, e]), self.n_fit) >= settings.alpha

        rows = self.rows
        if len(selected) == 2 and (mimic is None or scan.bic[d, mimic] < bic + settings.bic_margin
                                   or within_noise(mimic)):
            sa, sb = (_at(self.curves[i], v)[rows] / self.sigma[rows] for i, v in selected)
            larger = max(np.linalg.norm(sa), np.linalg.norm(sb))
            if larger > 0 and np.linalg.norm(sa + sb) < FIGHT_RATIO * larger:
                return "unexplained", "cancelling effects"
        if len(selected) == 2 and self._opposite(selected):
            return "unexplained", "opposite loads"
        if compared is not None and scan.bic[d, compared] < bic - settings.bic_margin:
            return "unexplained", "generic load fits much better"
        k = len(selected)
        if mimic is not None and k > scan.k[d, mimic] and (scan.bic[d, mimic] < bic or within_noise(mimic)):
            return "unexplained", "more parameters than a generic load"
        beyond = np.where(~singles.physical[d], singles.chi2[d] + self.ln_n, np.inf)
        if np.any(beyond < bic - settings.ambiguity_margin):
            return "unexplained", "only beyond a bound"
        if generic is not None and scan.bic[d, generic] < bic + settings.ambiguity_margin and within_noise(generic):
            return "ambiguous", "generic load within the noise"
        if any(len(g) > AMBIGUOUS_GROUP for g in groups):
            return "ambiguous", "group of more than three"
        if np.any(beyond < bic + settings.ambiguity_margin):
            return "ambiguous", "beyond a bound as well"
        return "explained", ""

    def _opposite(self, selected) -> bool:
        (a, va), (b, vb) = selected
        na, nb = self.names[a], self.names[b]
        ea, eb = self.effects[na], self.effects[nb]
        if ea.kind != eb.kind or ea.parameters[0].unit != "N/(N·m)" or va * vb >= 0:
            return False
        if na in self.places_x and nb in self.places_x:
            lo, hi = sorted((self.places_x[na], self.places_x[nb]))
            if any(lo < x < hi for n, x in self.places_x.items() if self.effects[n].kind == ea.kind):
                return False
        return True


# ---- what the file's own fit supports ----------------------------------------------------------------------------

@dataclass(frozen=True)
class _Hypothesis:
    """An explanation of the file's data that the draws may hide: ``kind`` as :data:`TRUTHS`, ``members`` (candidate
    index, value fitted to the file) and its BIC on the file's fitted rows."""

    kind: str
    members: tuple[tuple[int, float], ...]
    bic: float


def _supported(replay: _Replay, scaled: np.ndarray, settings) -> list[_Hypothesis]:
    """The explanations the file's own data do not exclude: every hypothesis whose BIC on the file lies within the
    workflow's BIC margin of the best one. The hypotheses: nothing; each candidate alone at its fitted value (within
    its physical bounds, or, for a linear one whose best fit lies beyond a bound, beyond it); the best single with
    each other candidate, when the best single leaves a gap (else the workflow's search stops at one effect, and a
    second one would fit the model form) and both earn their parameter (the pair's BIC below each member's alone);
    a generic load outside the vocabulary (the
    sentinel scan's best away from the places where candidates put their loads)."""
    rows, r = replay.rows, scaled[0]
    chi2_0 = float(r[rows] @ r[rows])
    singles = _single_fits(replay.curves, scaled[:, rows], rows, replay.sigma)
    bic = singles.chi2[0] + replay.ln_n
    out = [_Hypothesis("none", (), chi2_0)]
    for c, curve in enumerate(replay.curves):
        kind = "single" if singles.physical[0, c] else "beyond" if curve.linear else None
        if kind is not None:
            out.append(_Hypothesis(kind, ((c, float(singles.value[0, c])),), float(bic[c])))
    scan = sentinel_scan(replay.observed, scaled)
    if scan is not None:  # away from every place where a candidate puts its load (there it is that candidate)
        taken = set().union(*replay.region_sites.values()) if replay.region_sites else set()
        away = np.array([replay.sites.index(site) not in taken for site in scan.site], dtype=bool)
        generic = np.where(away, scan.bic[0], np.inf)
        if np.isfinite(generic).any():
            out.append(_Hypothesis("outside", (), float(generic.min())))
    valid = singles.physical[0]
    if valid.any():
        w = int(np.flatnonzero(valid)[np.argmin(bic[valid])])
        if not replay._gap(r - _at(replay.curves[w], float(singles.value[0, w])) / replay.sigma):
            valid = np.zeros_like(valid)  # the best single leaves no gap: the workflow's search stops there
    if valid.any():
        for c, (chi2, vw, vc) in replay.pair_fits(r, w).items():
            pair_bic = chi2 + 2 * replay.ln_n
            if pair_bic < bic[w] and (not valid[c] or pair_bic < bic[c]):
                out.append(_Hypothesis("pair", ((w, vw), (c, vc)), float(pair_bic)))
    best = min(h.bic for h in out)
    return [h for h in out if h.bic <= best + settings.bic_margin]


# ---- the draws --------------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Truth:
    kind: str  # none | single | pair | outside | beyond
    names: tuple[str, ...]
    detectable: bool


class _Drawer:
    """Synthetic data sets on the file's observations (see the module docstring)."""

    def __init__(self, seen, vocabulary: _Vocabulary, settings, rng, supported: list[_Hypothesis] | None = None):  # noqa: PLR0913
        observed = seen.observed
        self.seen, self.vocabulary, self.settings, self.rng = seen, vocabulary, settings, rng
        self.supported = list(supported or [])
        self.data = observed.data
        self.before = observed.before
        self.signal = {s: float(np.sqrt(np.mean(self.before[self.data.shaft == s] ** 2)))
                       for s in MEASURED_SHAFTS if (self.data.shaft == s).any()}
        self.noise = np.array([seen.noise.noise_mm[s] for s in self.data.shaft]) \
            if self.data.sigma_mm is None else self.data.sigma_mm
        self.sigma_draws = self._sigma()
        self.sizes = self._range()
        self.bend = self._bend()
        engine = observed.engine
        weights = engine.case_weights(self.data.cases, observed.from_rest)
        from rvcoax.geometry.model.loads import UNIT_LOADS

        self.slots = {part: weights[:, UNIT_LOADS.index(slot)] for part, slot in SLOTS.items()
                      if np.any(weights[:, UNIT_LOADS.index(slot)])}
        taken = set().union(*vocabulary.region_sites.values()) if vocabulary.region_sites else set()
        shafts = {p.name for p in engine.rig.parts if p.role == "shaft"}
        self.outside_sites = [i for i, s in enumerate(vocabulary.sites) if s[0] in shafts and i not in taken]
        self.unit_loads = {family: engine.sentinel_paths(vocabulary.sites, component)[self.outside_sites]
                           for family, (component, _) in FAMILIES.items()} if self.outside_sites else {}

    def _sigma(self) -> np.ndarray:
        """σ of the draws as the workflow estimates it for data around the model: the file's noise with the model-form
        allowance of the model's own signal (the file's σ holds the allowance of the measured signal, which may be
        far from the model's: the paper's table measures 24 times the model's output-shaft Y)."""
        from dataclasses import replace

        from rvcoax.results.studies.discrepancy.locate import group_rms

        level = group_rms(replace(self.data, value_mm=np.abs(self.before)))
        sigma = np.sqrt(self.noise ** 2 + (self.settings.model_form_fraction * level) ** 2)
        return np.where(sigma > 0, sigma, self.seen.observed.sigma)

    def _bend(self) -> np.ndarray:
        """A quadratic along each path, zero mean and unit RMS over the stations (0 for a table)."""
        if self.data.schema != "paths":
            return np.zeros(self.data.n)
        out = np.zeros(self.data.n)
        for s in MEASURED_SHAFTS:
            mask = self.data.shaft == s
            if mask.sum() < 3:
                continue
            x = self.data.x_mm[mask]
            q = ((x - x.min()) / max(np.ptp(x), 1e-12) - 0.5) ** 2
            q = q - q.mean()
            out[mask] = q / max(np.sqrt(np.mean(q ** 2)), 1e-12)
        return out

    def _range(self) -> tuple[float, float]:
        """Half to twice the file's gap (RMS of measured − model over the model's RMS signal, on the shaft where it is
        largest), within :data:`FRACTIONS`: draws with gaps like the file's."""
        gap = self._ratio(self.data.value_mm - self.before)
        lo, hi = FRACTIONS
        return float(np.clip(gap / 2, lo, hi / 2)), float(np.clip(2 * gap, 2 * lo, hi))

    def _fraction(self) -> float:
        lo, hi = self.sizes
        return float(np.exp(self.rng.uniform(np.log(lo), np.log(hi))))

    def _ratio(self, change: np.ndarray) -> float:
        return max((float(np.sqrt(np.mean(change[self.data.shaft == s] ** 2))) / v if v > 0 else 0.0)
                   for s, v in self.signal.items())

    def _ratios(self, changes: np.ndarray) -> np.ndarray:
        """:meth:`_ratio` of every row of ``changes``."""
        out = np.zeros(changes.shape[0])
        for s, v in self.signal.items():
            if v > 0:
                mask = self.data.shaft == s
                out = np.maximum(out, np.sqrt(np.mean(changes[:, mask] ** 2, axis=1)) / v)
        return out

    def _sized(self, c: int) -> float:
        """A value of candidate ``c`` (within its physical bounds, a random side) changing the data by a drawn
        fraction of the signal; its bound when it cannot."""
        curve = self.vocabulary.curves[c]
        inside = curve.physical
        values, changes = curve.values[inside], curve.change[inside]
        sides = [side for side in (-1, 1) if np.any(np.sign(values) == side)]
        side = sides[int(self.rng.integers(len(sides)))]
        keep = np.flatnonzero(np.sign(values) == side)
        keep = keep[np.argsort(np.abs(values[keep]))]
        ratios = self._ratios(changes[keep])
        target = self._fraction()
        reach = np.flatnonzero(ratios >= target)
        if reach.size == 0:
            return float(values[keep[-1]])
        j = int(reach[0])
        if j == 0:
            return float(values[keep[0]] * target / max(ratios[0], 1e-300))
        v0, v1, r0, r1 = values[keep[j - 1]], values[keep[j]], ratios[j - 1], ratios[j]
        return float(v0 + (target - r0) / max(r1 - r0, 1e-300) * (v1 - v0))

    def _from_supported(self) -> tuple[str, np.ndarray, tuple[str, ...]]:
        """A truth among the file's supported hypotheses (:func:`_supported`): its kind drawn with the weights of
        :data:`TRUTHS` among the kinds supported, then one of that kind at random; each member at its value fitted to
        the file times a factor log-uniform within ±:data:`JITTER` (an effect in the vocabulary kept within its
        physical bounds); a generic load at a random site away from the named effects, sized like the file's gap."""
        kinds = list(dict.fromkeys(h.kind for h in self.supported))
        weights = np.array([TRUTHS[k] for k in kinds])
        kind = kinds[int(self.rng.choice(len(kinds), p=weights / weights.sum()))]
        if kind == "outside" and not self.outside_sites:
            kind = "none"
        if kind in ("none", "outside"):
            observed = self.seen.observed
            return kind, (self._outside() if kind == "outside" else np.zeros_like(observed.base_paths)), ()
        hypotheses = [h for h in self.supported if h.kind == kind]
        chosen = hypotheses[int(self.rng.integers(len(hypotheses)))]
        delta, names = 0.0, []
        for c, value in chosen.members:
            curve = self.vocabulary.curves[c]
            response = self.seen.responses[curve.name]
            p = response.effect.parameters[0]
            value = value * float(np.exp(self.rng.uniform(-np.log(JITTER), np.log(JITTER))))
            if kind != "beyond":
                value = float(np.clip(value, p.lower, p.upper))
            delta = delta + response.delta([value])
            names.append(curve.name)
        return kind, delta, tuple(names)

    def draw(self) -> tuple[np.ndarray, _Truth]:
        """One data set's values (mm) and what it hides: a truth the file's own fit supports (:meth:`_from_supported`),
        else one from the broad prior :data:`TRUTHS`."""
        if self.supported:
            kind, delta, names = self._from_supported()
            return self._data(kind, delta, names)
        kinds = list(TRUTHS)
        kind = kinds[int(self.rng.choice(len(kinds), p=list(TRUTHS.values())))]
        if kind == "outside" and not self.outside_sites:
            kind = "single"
        beyond = [c for c, curve in enumerate(self.vocabulary.curves) if curve.linear and self._bounds(curve)]
        if kind == "beyond" and not beyond:
            kind = "single"
        observed = self.seen.observed
        delta = np.zeros_like(observed.base_paths)
        names: tuple[str, ...] = ()
        curves = self.vocabulary.curves
        if kind in ("single", "pair") and len(curves) >= (2 if kind == "pair" else 1):
            picked = self.rng.choice(len(curves), size=2 if kind == "pair" else 1, replace=False)
            for c in picked:
                response = self.seen.responses[curves[int(c)].name]
                delta = delta + response.delta([self._sized(int(c))])
            names = tuple(curves[int(c)].name for c in picked)
        elif kind == "outside":
            delta = self._outside()
        elif kind == "beyond":
            c = beyond[int(self.rng.integers(len(beyond)))]
            curve = curves[c]
            bounds = self._bounds(curve)
            bound = bounds[int(self.rng.integers(len(bounds)))]
            factor = float(np.exp(self.rng.uniform(*np.log(BEYOND))))
            delta = self.seen.responses[curve.name].delta([factor * bound])
            names = (curve.name,)
        else:
            kind = "none"
        return self._data(kind, delta, names)

    def _data(self, kind: str, delta: np.ndarray, names: tuple[str, ...]) -> tuple[np.ndarray, _Truth]:
        """The values (mm) of a data set hiding ``delta`` (full paths), with noise, model form and the file's quantum."""
        observed = self.seen.observed
        true = observed.observe(observed.base_paths + delta)
        change = true - self.before
        detectable = bool(np.sqrt(np.mean((change / self.sigma_draws) ** 2)) >= 1.0) if kind != "none" else True
        form = self.rng.uniform(0.0, self.settings.model_form_fraction)
        scale = np.ones(self.data.n)
        for s in self.signal:
            mask = self.data.shaft == s
            e, b = self.rng.uniform(-1.0, 1.0, size=2) * form * np.array([1.0, BEND])
            scale[mask] = 1.0 + e + b * self.bend[mask]
        values = true * scale + self.rng.normal(size=self.data.n) * self.noise
        if self.data.schema == "table":
            quantum = self.data.quantum_mm or {}
            q = np.array([quantum.get(s, 0.0) for s in self.data.shaft])
            q = np.where(np.isfinite(q), q, 0.0)
            values = np.where(q > 0, np.round(values / np.where(q > 0, q, 1.0)) * q, values)
            values = np.abs(values)
        return values, _Truth(kind, names, detectable)

    def _bounds(self, curve: _Curve) -> list[float]:
        """The candidate's nonzero physical bounds (a draw beyond one: a multiple of it)."""
        p = self.seen.responses[curve.name].effect.parameters[0]
        return [float(v) for v in (p.lower, p.upper) if v != 0 and np.isfinite(v)]

    def _outside(self) -> np.ndarray:
        family = "moment" if self.rng.uniform() < 0.2 else "force"
        parts = [p for p in ("T2", "T1", "constant") if p in self.slots]
        p = np.array([{"T2": 0.6, "T1": 0.25, "constant": 0.15}[x] for x in parts])
        part = parts[int(self.rng.choice(len(parts), p=p / p.sum()))]
        j = int(self.rng.integers(len(self.outside_sites)))
        unit = self.unit_loads[family][j]
        change = np.kron(self.slots[part], unit)  # (case, path) flattened as the full paths
        observed = self.seen.observed
        observed_change = observed.observe(observed.base_paths + change) - self.before
        ratio = self._ratio(observed_change)
        size = self._fraction() / ratio if ratio > 0 else 0.0
        return size * change * (1 if self.rng.uniform() < 0.5 else -1)


def _right(answer: _Answer, truth: _Truth) -> bool:
    nothing = not answer.named and answer.verdict != "unexplained"
    if not truth.detectable and nothing:
        return True
    if truth.kind == "none":
        return answer.verdict == "no_gap"
    if truth.kind == "outside":
        return answer.verdict in ("unexplained", "ambiguous")
    if truth.kind == "beyond":  # beyond its bound: anything but explained (as the benchmark scores it)
        return answer.verdict != "explained"
    return answer.verdict in ("explained", "ambiguous") and set(truth.names) <= set(answer.named)


def _size_class(group: int) -> str:
    return "no effect named" if group == 0 else "one effect" if group == 1 else \
        f"a group of 2–{AMBIGUOUS_GROUP}" if group <= AMBIGUOUS_GROUP else f"a group of more than {AMBIGUOUS_GROUP}"


def _quality_class(quality: float) -> str:
    return "χ²/n ≤ 1 after" if quality <= 1.0 else "χ²/n > 1 after"


def _fit_class(verdict: str, quality: float, generic_gain: float, settings) -> str:
    """The fit-quality feature of a bin. For ``unexplained``: whether a generic load (the sentinel) fits better than
    the best named fit by the workflow's own BIC margin, which tells a load outside the vocabulary (the generic load
    fits it) from effects of the vocabulary that the rules refused (a pair that cancels, a fit beyond a bound), where
    the generic load does no better; for the other verdicts χ²/n after the fit."""
    if verdict == "unexplained":
        return "a generic load fits better by the BIC margin" if generic_gain >= settings.bic_margin else \
            "no generic load fits clearly better"
    return _quality_class(quality)


def _features(answers, groups=None, qualities=None) -> np.ndarray:
    """(answers, :data:`FEATURES`) of the replay's answers; ``groups``/``qualities`` in place of theirs (the file's
    own answer takes these from the workflow's result)."""
    groups = [a.group for a in answers] if groups is None else groups
    qualities = [a.quality for a in answers] if qualities is None else qualities
    return np.array([[np.log(max(a.gap, 1e-3)), np.log(max(q, 1e-3)),
                      np.clip(a.generic_gain, -MARGIN_CAP, MARGIN_CAP) / 10.0, np.log(max(g, 1)),
                      np.clip(a.margin, 0.0, MARGIN_CAP) / 10.0]
                     for a, g, q in zip(answers, groups, qualities)], dtype=float).reshape(-1, len(FEATURES))


@dataclass(frozen=True)
class _Logistic:
    intercept: float
    slopes: np.ndarray
    mean: np.ndarray
    scale: np.ndarray

    def __call__(self, x: np.ndarray) -> np.ndarray:
        z = self.intercept + ((np.atleast_2d(x) - self.mean) / self.scale) @ self.slopes
        return 1.0 / (1.0 + np.exp(-np.clip(z, -30.0, 30.0)))


def _logistic(x: np.ndarray, y: np.ndarray) -> _Logistic:
    """P(right | x) by penalised maximum likelihood (Newton steps): standardised features, slopes with a unit Gaussian
    prior (:data:`RIDGE`), the intercept pulled weakly towards the Laplace-smoothed rate, so that a class of draws that
    is all right (or all wrong) gives a finite, cautious answer."""
    mean = x.mean(axis=0)
    scale = x.std(axis=0)
    scale = np.where(scale > 1e-9, scale, np.inf)  # a feature that does not vary says nothing: its column is zero
    z = (x - mean) / scale
    prior = (y.sum() + 1.0) / (y.size + 2.0)
    centre = np.log(prior / (1.0 - prior))
    design = np.column_stack([np.ones(y.size), z])
    penalty = np.full(design.shape[1], RIDGE)
    penalty[0] = 1e-2
    target = np.zeros(design.shape[1])
    target[0] = centre
    beta = target.copy()
    for _ in range(25):
        p = 1.0 / (1.0 + np.exp(-np.clip(design @ beta, -30.0, 30.0)))
        gradient = design.T @ (p - y) + penalty * (beta - target)
        hessian = (design * (p * (1 - p))[:, None]).T @ design + np.diag(penalty)
        step = np.linalg.solve(hessian, gradient)
        beta -= step
        if np.max(np.abs(step)) < 1e-8:
            break
    return _Logistic(float(beta[0]), beta[1:], mean, scale)


def _nearest_rate(x: np.ndarray, y: np.ndarray, mine: np.ndarray) -> float:
    """The rate of right draws among the nearest third of the draws (at least :data:`MIN_BIN`) to the file's features
    (standardised over the draws), Jeffreys-smoothed ((right + ½)/(k + 1)): a local rate that cannot extrapolate."""
    scale = x.std(axis=0)
    scale = np.where(scale > 1e-9, scale, np.inf)
    distance = np.linalg.norm((x - np.atleast_2d(mine)) / scale, axis=1)
    k = int(min(y.size, max(MIN_BIN, int(np.ceil(y.size / 3)))))
    nearest = np.argsort(distance, kind="stable")[:k]
    return float((y[nearest].sum() + 0.5) / (k + 1.0))


def _finer_models(answers, right: np.ndarray, own: _Answer, mine: tuple[str, int, float]):
    """(logistic, nearest, features): P(right) of the logistic model and of the nearest draws in :data:`FEATURES`,
    fitted on the draws that share the file's verdict, at the file's own features (held within the draws' range:
    never extrapolated; ``mine``: the workflow's verdict, largest group and χ²/n after, the replay's answer ``own``
    for the rest); (None, None, ()) while fewer than :data:`MIN_BIN` draws share the verdict."""
    verdict, group, quality = mine
    same = np.array([a.verdict == verdict for a in answers], dtype=bool)
    if same.sum() < MIN_BIN:
        return None, None, ()
    mine = _features([own], [group], [quality])
    x, y = _features([a for a, s in zip(answers, same) if s]), right[same].astype(float)
    logistic = float(_logistic(x, y)(np.clip(mine, x.min(axis=0), x.max(axis=0)))[0])
    return logistic, _nearest_rate(x, y, mine), tuple(float(v) for v in mine[0])


def draw_limit(draws: int) -> int:
    """The most draws made when ``draws`` are asked for: :data:`MAX_DRAWS` per :data:`DRAWS` (at most MAX_DRAWS)."""
    return max(draws, min(MAX_DRAWS, MAX_DRAWS * draws // DRAWS))


def verdict_confidence(seen, result, settings, draws: int | None = None, seed: int = SEED) -> Confidence | None:
    """The probability that ``result``'s verdict is right (see the module docstring); None when the rig is not
    solved on one factorisation (a nonlinear rig), or the file is too large for the replay."""
    start = time.perf_counter()
    draws = DRAWS if draws is None else int(draws)
    observed = seen.observed
    engine = observed.engine
    if draws <= 0 or engine is None or not engine.linear:
        return None
    if len(seen.responses) * (GRID + 2) * observed.data.n > MAX_CELLS:
        return None
    try:
        from dataclasses import replace

        vocabulary = _vocabulary(seen)
        own_replay = _Replay(vocabulary, observed, settings)
        scaled_own = ((observed.data.value_mm - observed.before) / observed.sigma)[None, :]
        own = own_replay.answers(scaled_own)[0]
        supported = _supported(own_replay, scaled_own, settings)
        drawer = _Drawer(seen, vocabulary, settings, np.random.default_rng(seed), supported)
        sigma = drawer.sigma_draws
        replay = _Replay(vocabulary, replace(observed, sigma=sigma), settings)
        made, answers = [], []
        limit = draw_limit(draws)
        while True:  # the first batch, then more while too few draws share the file's verdict (same prior: unbiased)
            batch = [drawer.draw() for _ in range(draws if not made else min(draws // 2 or 1, limit - len(made)))]
            values = np.array([v for v, _ in batch])
            answers += replay.answers((values - observed.before[None, :]) / sigma[None, :])
            made += batch
            if sum(a.verdict == result.verdict for a in answers) >= SAME_VERDICT or len(made) >= limit:
                break
    except CANDIDATE_FAILURES:
        return None
    draws = len(made)
    right = np.array([_right(a, t) for a, (_, t) in zip(answers, made)])
    verdict = result.verdict
    group = max((len(s.group) for s in result.selected), default=0) if verdict != "no_gap" else 0
    quality = (result.vocabulary_chi2 / max(int(result.fit_mask.sum()), 1)) if result.vocabulary_chi2 is not None \
        else result.test_before.chi2 / max(result.test_before.n, 1)
    keys = [(a.verdict, _size_class(a.group), _fit_class(a.verdict, a.quality, a.generic_gain, settings))
            for a in answers]
    mine = (verdict, _size_class(group), _fit_class(verdict, quality, own.generic_gain, settings))
    chosen = None
    for depth in (3, 2, 1):
        hits = np.array([k[:depth] == mine[:depth] for k in keys], dtype=bool)
        if hits.sum() >= MIN_BIN or depth == 1:
            chosen = (depth, hits)
            break
    depth, hits = chosen
    n, k = int(hits.sum()), int(right[hits].sum())
    if n == 0:  # the verdict never came up in the draws: nothing is known beyond the interval
        probability, (low, high) = 0.5, (0.0, 1.0)
    else:
        probability, (low, high) = (k + 1) / (n + 2), wilson(k, n)  # the rate's posterior mean (uniform prior)
    logistic, nearest, features = _finer_models(answers, right, own, mine=(verdict, group, quality))
    rates = tuple((v, int(right[[a.verdict == v for a in answers]].sum()), sum(a.verdict == v for a in answers))
                  for v in ("no_gap", "explained", "ambiguous", "unexplained"))
    return Confidence(probability=float(probability), low=low, high=high, right=k, draws=n, total_draws=draws,
                      bin=", ".join(mine[:depth]), replay_verdict=own.verdict, seed=seed, seconds=time.perf_counter() - start,
                      rates=rates, logistic=logistic, nearest=nearest, features=features)
