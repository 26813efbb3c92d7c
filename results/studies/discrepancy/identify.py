"""Name the missing effect: fit candidates, rank by BIC, forward steps with backward pruning,
and groups of candidates that the data cannot tell apart.

With σ known, the information criterion of a fit with k parameters on n observations is
``BIC = χ² + k ln n``. A candidate is added when it lowers the BIC by more than a margin (default
10, "very strong" evidence); after each addition every selected effect whose removal would cost
less than the margin is pruned. Candidates whose best BIC is within the ambiguity margin of the
winner's, or whose scaled signatures are nearly parallel on the data, form a group: the data
name the group, not one member.

A fitted parameter outside its physical bounds rejects the candidate, with the reason.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from rvcoax.results.studies.discrepancy.responses import EffectResponse

__all__ = ["Fit", "Problem", "Step", "forward_backward"]


@dataclass(frozen=True)
class Fit:
    """A set of effects fitted together."""

    names: tuple[str, ...]
    values: tuple[np.ndarray, ...]
    chi2: float
    n: int
    rejected: str | None = None

    @property
    def k(self) -> int:
        return int(sum(v.size for v in self.values))

    @property
    def bic(self) -> float:
        return self.chi2 + self.k * np.log(max(self.n, 2))


@dataclass(frozen=True)
class Step:
    """One forward step: the winner, its BIC gain, the group it belongs to, and what was rejected."""

    added: str
    delta_bic: float
    group: tuple[str, ...]
    fit: Fit
    rejected: dict[str, str] = field(default_factory=dict)
    pruned: tuple[str, ...] = ()
    ranking: tuple[tuple[str, float], ...] = ()
    group_fits: dict[str, Fit] = field(default_factory=dict)
    rejected_fits: dict[str, Fit] = field(default_factory=dict)


SCAN_POINTS = 61  # values of a linear effect's scan on a table (:meth:`Problem._scan_starts`), both signs
SCAN_KEEP = 3  # the best of them kept as starts (with zero)


class Problem:
    """The least-squares problem: measured values, σ, base paths, observation operator, responses."""

    def __init__(self, measured: np.ndarray, sigma: np.ndarray, base_paths: np.ndarray, observe,  # noqa: PLR0913
                 responses: dict[str, EffectResponse], *, rows: np.ndarray | None = None):
        self.measured = measured
        self.sigma = sigma
        self.base_paths = base_paths
        self.observe = observe
        self.responses = responses
        self.rows = np.arange(measured.size) if rows is None else np.flatnonzero(rows)

    def paths(self, names, values) -> np.ndarray:
        total = self.base_paths.copy()
        for name, value in zip(names, values):
            total += self.responses[name].delta(value)
        return total

    def scaled_residual(self, names, values) -> np.ndarray:
        predicted = self.observe(self.paths(names, values))
        return ((self.measured - predicted) / self.sigma)[self.rows]

    def fit(self, names: tuple[str, ...], start: dict[str, np.ndarray] | None = None) -> Fit:
        """Best fit of the effects ``names`` together (multi-start over the new nonlinear ones)."""
        start = start or {}
        if not names:
            r = self.scaled_residual((), ())
            return Fit((), (), float(r @ r), r.size)
        sizes = [self.responses[n].n_params for n in names]
        lower = np.concatenate([self.responses[n].search_bounds()[0] for n in names])
        upper = np.concatenate([self.responses[n].search_bounds()[1] for n in names])
        scale = np.concatenate([[max(abs(p.typical), 1e-12) for p in self.responses[n].effect.parameters]
                                for n in names])
        exact = self._linear_fit(names, sizes, lower, upper)
        if exact is not None:
            return exact
        new = [n for n in names if n not in start]
        choices = [[start[n]] if n in start else
                   self._scan_starts(n, names, start) if len(new) == 1 else self.responses[n].start_values()
                   for n in names]
        starts = [np.concatenate(c) for c in _product(choices, limit=64)]
        if len(starts) > 2:  # a coarse look first: start from the two best grid points only
            split_starts = [tuple(np.array(p) for p in np.split(x0, np.cumsum(sizes)[:-1])) for x0 in starts]
            costs = [float(np.sum(self.scaled_residual(names, v) ** 2)) for v in split_starts]
            starts = [starts[i] for i in np.argsort(costs)[:2]]

        def split(x):
            return tuple(np.array(part) for part in np.split(x, np.cumsum(sizes)[:-1]))

        def jacobian(x):
            values = split(x)
            slope = self.observe.jacobian(self.paths(names, values)) if hasattr(self.observe, "jacobian") else None
            if slope is None:
                return "2-point"
            blocks = [np.asarray(slope @ self.responses[n].derivative(v).T) for n, v in zip(names, values)]
            return (-np.hstack(blocks) / self.sigma[:, None])[self.rows]

        analytic = hasattr(self.observe, "jacobian")
        best = None
        for x0 in starts:
            x0 = np.clip(x0, lower, upper)
            result = least_squares(lambda x: self.scaled_residual(names, split(x)), x0, bounds=(lower, upper),
                                   jac=jacobian if analytic else "2-point",
                                   x_scale=scale, method="trf", xtol=1e-10, ftol=1e-10, gtol=1e-10)
            chi2 = float(2.0 * result.cost)
            if best is None or chi2 < best[0]:
                best = (chi2, result.x)
        values = split(best[1])
        return Fit(tuple(names), values, best[0], int(self.rows.size), _out_of_bounds(self.responses, names, values))

    def _scan_starts(self, name: str, names, start: dict) -> list[np.ndarray]:
        """Starts for the one new effect of a fit: its own (zero for a linear effect, every grid value for a nonlinear
        one), and, for a linear one-parameter effect seen through observations that are not linear in the paths (a
        |Y_max| table), the best values of a scan of its search range. On a table the χ² of a linear effect has
        several valleys (|Y| folds a path's sign: an offset of +0.5 µm and one of −0.3 µm may both lower it), so a
        start at zero may end in the wrong one: the scan, geometric from 10⁻⁴ of its physical span to its search
        bound on either side (:data:`SCAN_POINTS` values, about 1.5 apart), finds the valley each fit starts in."""
        response = self.responses[name]
        own = response.start_values()
        if response.kind != "linear" or response.n_params != 1 or hasattr(self.observe, "matrix"):
            return own
        lower, upper = (float(b[0]) for b in response.search_bounds())
        span = max(abs(lower), abs(upper)) / 10.0
        side = np.geomspace(1e-4 * span, 10.0 * span, SCAN_POINTS // 2)
        values = np.concatenate([-side[::-1], [0.0], side])
        values = values[(values >= lower) & (values <= upper)]
        others = tuple(n for n in names if n != name)
        fixed = tuple(np.atleast_1d(start[n]) for n in others)
        base = self.paths(others, fixed)
        columns = response.columns[0]
        costs = []
        for v in values:
            r = ((self.measured - self.observe(base + v * columns)) / self.sigma)[self.rows]
            costs.append(float(r @ r))
        best = [values[i] for i in np.argsort(costs)[:SCAN_KEEP]]
        return own + [np.array([v]) for v in best if v != 0.0]

    def _observed_columns(self, name: str) -> np.ndarray:
        """Scaled observed change per unit of each parameter of a linear effect (paths data: exact), cached."""
        cache = self.__dict__.setdefault("_columns", {})
        if name not in cache:
            columns = np.asarray(self.observe.matrix @ self.responses[name].columns.T)
            cache[name] = (columns / self.sigma[:, None])[self.rows]
        return cache[name]

    def _linear_fit(self, names, sizes, lower, upper) -> Fit | None:
        """Closed-form least squares when every effect is linear and the observations are linear in the paths
        (paths data); None otherwise, or when the solution leaves the search bounds."""
        if not hasattr(self.observe, "matrix") or any(self.responses[n].kind != "linear" for n in names):
            return None
        a = np.hstack([self._observed_columns(n) for n in names])
        target = self.scaled_residual((), ())
        x, *_ = np.linalg.lstsq(a, target, rcond=None)
        if not np.all((x >= lower) & (x <= upper)):
            return None
        values = tuple(np.array(part) for part in np.split(x, np.cumsum(sizes)[:-1]))
        chi2 = float(np.sum((target - a @ x) ** 2))
        return Fit(tuple(names), values, chi2, int(self.rows.size), _out_of_bounds(self.responses, names, values))

    def signature(self, name: str, values: np.ndarray) -> np.ndarray:
        """Scaled change of the observations made by one effect at ``values`` (for parallelism)."""
        base = self.observe(self.base_paths)
        return ((self.observe(self.base_paths + self.responses[name].delta(values)) - base) / self.sigma)[self.rows]


def _product(choices, limit: int):
    """The Cartesian product of the start lists, thinned to at most ``limit`` combinations."""
    import itertools

    combos = list(itertools.islice(itertools.product(*choices), 4 * limit))
    if len(combos) > limit:
        combos = combos[:: int(np.ceil(len(combos) / limit))]
    return combos


def _out_of_bounds(responses, names, values) -> str | None:
    for name, value in zip(names, values):
        for parameter, v in zip(responses[name].effect.parameters, np.atleast_1d(value)):
            if not parameter.lower - 1e-9 * max(1.0, abs(parameter.lower)) <= v <= \
                    parameter.upper + 1e-9 * max(1.0, abs(parameter.upper)):
                return (f"{name}: fitted {parameter.name} = {v:.4g} {parameter.unit} is outside its physical range "
                        f"[{parameter.lower:g}, {parameter.upper:g}] {parameter.unit}")
    return None


def _representative(problem: Problem, group: list[str], fits: dict[str, Fit], winner: str,
                    margin: float = 6.0) -> tuple[str, Fit]:
    """The member of an ambiguity group that is added: the best linear one if there is one (a linear
    effect keeps the rig linear, so superposition stays valid: the simpler model) when it fits within ``margin`` of
    the winner's BIC; else one solved exactly on the factorisation (not a coarse grid of a clearance); else the
    winner."""
    close = [name for name in group if fits[name].bic - fits[winner].bic < margin]
    linear = [name for name in close if problem.responses[name].kind == "linear"]
    if linear and problem.responses[winner].kind != "linear":
        name = min(linear, key=lambda n: fits[n].bic)
        return name, fits[name]
    exact = [name for name in close if problem.responses[name].unit is not None]  # solved on the factorisation
    if exact and problem.responses[winner].unit is None:
        name = min(exact, key=lambda n: fits[n].bic)
        return name, fits[name]
    return winner, fits[winner]


def _cosine(a: np.ndarray, b: np.ndarray) -> float:
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    return 0.0 if na == 0 or nb == 0 else float(abs(a @ b) / (na * nb))


def forward_backward(problem: Problem, candidates: list[str], *, margin: float = 10.0, ambiguity_margin: float = 6.0,  # noqa: PLR0913
                     parallel_cosine: float = 0.999, max_effects: int = 4, stop=None) -> tuple[Fit, list[Step]]:
    """Forward selection by BIC with backward pruning.

    ``stop(fit)`` (optional) ends the search early when the current fit leaves no gap.
    """
    current = problem.fit(())
    steps: list[Step] = []
    selected: tuple[str, ...] = ()
    while len(selected) < max_effects and (stop is None or not stop(current)):
        start = dict(zip(current.names, current.values))
        trials = {name: problem.fit(selected + (name,), start) for name in candidates if name not in selected}
        rejected = {name: t.rejected for name, t in trials.items() if t.rejected}
        valid = {name: t for name, t in trials.items() if not t.rejected}
        if not valid:
            break
        ranking = sorted(valid.items(), key=lambda item: item[1].bic)
        winner, best = ranking[0]
        before = current.bic
        gain = before - best.bic
        if gain < margin:
            break
        winner_signature = problem.signature(winner, best.values[-1])
        group = [winner] + [name for name, t in ranking[1:]
                            if t.bic - best.bic < ambiguity_margin
                            or (before - t.bic >= margin
                                and _cosine(winner_signature, problem.signature(name, t.values[-1])) > parallel_cosine)]
        winner, best = _representative(problem, group, valid, winner, ambiguity_margin)
        group.remove(winner)
        group.insert(0, winner)
        gain = before - best.bic
        selected, current = selected + (winner,), best
        pruned = []
        while len(selected) > 1:
            reduced = {name: problem.fit(tuple(n for n in selected if n != name), dict(zip(current.names, current.values)))
                       for name in selected if name != winner}
            if not reduced:
                break
            name, fit = min(reduced.items(), key=lambda item: item[1].bic)
            if fit.bic - current.bic >= margin or fit.rejected:
                break
            selected, current = fit.names, fit
            pruned.append(name)
        steps.append(Step(added=winner, delta_bic=float(gain), group=tuple(group), fit=current, rejected=rejected, pruned=tuple(pruned),
                          ranking=tuple((name, float(before - t.bic)) for name, t in ranking[:8]),
                          group_fits={name: valid[name] for name in group},
                          rejected_fits={name: t for name, t in trials.items() if t.rejected}))
    return current, steps
