"""Whether a look-alike fits as well once its own physics is solved exactly, not read off an interpolated response.

The screen fits a nonlinear candidate on a response interpolated between grid values of its parameter (a cubic spline
through exact solves). For a bearing's radial clearance that interpolation can invent a fit: the clearance law bends
sharply where the gap reaches the bearing's deflection in each case (a gap larger than every deflection leaves the
bearing open, it carries nothing), so between the grid's first values — far apart on a stiff bearing that deflects
a fraction of a micrometre — the spline blends "no change" and "bearing removed" into a smooth, load-proportional
softening that the clearance cannot make. Such a member would join a stiffness change's group of look-alikes at a
ΔBIC of 0 although, solved exactly, it fits worse by thousands.

:func:`exact_fit` re-fits a clearance member with its exact change on the factorised engine (its condensed 2-D law):
the χ² profile over its physical range, the other selected effects held at their values (:func:`exact_change` gives a
load's or spring's exact change too, by the Woodbury identity; their splines through 11 exact solves of a smooth law
need no confirmation). On a rig that is not linear (no factorisation) it returns None and the screen's fit stands.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize_scalar

from rvcoax.results.studies.discrepancy.engine import CANDIDATE_FAILURES

__all__ = ["exact_change", "exact_fit"]


def exact_change(effect, value, engine, cases, from_rest: bool | None = None) -> np.ndarray | None:
    """The exact change of the full paths (every case; Y from rest or from the unloaded geometry as ``from_rest``
    says, the engine's datum by default) made by ``effect`` at ``value`` (a number, or one per parameter): a
    clearance on a linear rig by its condensed law, a load or spring on the factorisation; None when neither applies
    (the effect needs real sweeps)."""
    if engine is None or not engine.linear:
        return None
    values = [float(v) for v in np.atleast_1d(value)]
    base = engine.full_paths(engine.unit_paths, cases, from_rest)
    if effect.response == "clearance":
        return engine.clearance_paths(effect.location, values[0], cases, from_rest) - base
    if engine.supports(effect):
        return engine.full_paths(engine.unit_paths + engine.unit_change([(effect, values)]), cases, from_rest) - base
    return None


def exact_fit(problem, trial, member: str, *, effect, observed) -> tuple[float, np.ndarray] | None:
    """The χ² (rows used to fit) and the predicted observations (every row, mm) of ``trial`` (a
    :class:`~identify.Fit` on the screening responses) with ``member``'s interpolated response replaced by its exact
    change, its parameter fitted again over its physical range (the response's grid values and the screen's value as
    starts, then a bounded 1-D search between the neighbours of the best), the other effects held at their fitted
    values (``observed``: the factorised engine and the data's cases). None when ``member`` is not a clearance read off
    its interpolated response or has no cheap exact solve."""
    response = problem.responses[member]
    if response.kind != "grid" or effect.response != "clearance" or len(effect.parameters) != 1 \
            or member not in trial.names:
        return None  # a stiffness's spline through 11 exact solves of a smooth law is exact enough; a gap's is not
    others = problem.base_paths.copy()
    for name, values in zip(trial.names, trial.values):
        if name != member:
            others += problem.responses[name].delta(values)
    parameter, engine, cases = effect.parameters[0], observed.engine, observed.data.cases
    fitted = float(np.atleast_1d(trial.values[trial.names.index(member)])[0])

    def predicted(value: float) -> np.ndarray:
        change = exact_change(effect, value, engine, cases)
        if change is None:
            raise LookupError
        return problem.observe(others + change)

    def chi2(value: float) -> float:
        scaled = ((problem.measured - predicted(value)) / problem.sigma)[problem.rows]
        return float(scaled @ scaled)

    starts = np.unique(np.clip(np.concatenate([response.grid, [fitted]]), parameter.lower, parameter.upper))
    try:
        values = [chi2(v) for v in starts]
        best = int(np.argmin(values))
        value, lowest = float(starts[best]), values[best]
        lo, hi = starts[max(best - 1, 0)], starts[min(best + 1, starts.size - 1)]
        if hi > lo:
            found = minimize_scalar(chi2, bounds=(lo, hi), method="bounded", options={"xatol": 1e-6 * (hi - lo)})
            if found.fun < lowest:
                value, lowest = float(found.x), float(found.fun)
        return lowest, predicted(value)
    except (LookupError, *CANDIDATE_FAILURES):
        return None
