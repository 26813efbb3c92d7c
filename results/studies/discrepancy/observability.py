"""What the data can see, before any fit: signatures, observability, groups of look-alikes, and the
measurement that would reveal or separate them.

The *signature* of an effect is the change it makes to every observation, divided by that
observation's σ (noise and model-form allowance), at the end of its physical range where it is
largest. Its norm is the square root of the Fisher information of the effect's size at that
value: ‖s‖² is the χ² the effect can add to a fit. An effect with ‖s‖ < :data:`VISIBLE_NORM` cannot
be seen on these data (stations, cases and datum); the same signature computed for cases and a
datum that were *not* measured (:mod:`engine` gives any case from the unit paths) says which
measurement would reveal it.

Two effects whose signatures on the data are nearly parallel (the cosine of the principal angle
between their response directions ≥ :data:`PARALLEL_COSINE`) cannot be told apart, whatever the
noise: scaled to fit, one mimics the other within ``sin θ`` of its size. They form a *group*;
the measurement where their (data-matched) predictions differ most separates them.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.studies.discrepancy.locate import detection_norm
from rvcoax.results.studies.discrepancy.observed import Observed

__all__ = ["PARALLEL_COSINE", "REVEAL_SIGMA", "Scenario", "Suggestion", "VISIBLE_NORM", "Visibility", "direction",
           "discriminate", "observability", "parallel_groups", "scenarios", "signature"]

VISIBLE_NORM = 3.0  # ‖s‖ at the end of the physical range: Δχ² = 9 (a 3 σ detection)
PARALLEL_COSINE = 0.98  # sin θ = 0.2: scaled to fit, one effect mimics the other within 20 % of its size
REVEAL_SIGMA = 3.0  # one new observation must change by 3 σ to reveal an effect
DETECTION_ALPHA = 0.01  # the gap test's significance level (the workflow's default)


@dataclass(frozen=True)
class Scenario:
    """A measurement that was not (necessarily) made: cases, datum, and whether every station is read."""

    label: str
    cases: tuple[LoadCase, ...]
    from_rest: bool
    new_cases: bool
    other_datum: bool


@dataclass(frozen=True)
class Suggestion:
    """Where one measurement shows an effect (or the difference of two) best."""

    scenario: str
    case: LoadCase
    shaft: str
    x_mm: float
    change_um: float
    in_sigma: float
    new_case: bool
    other_datum: bool
    series_in_sigma: float = 0.0
    cases_in_series: int = 1
    dof: float = np.inf  # of the σ² that scales the readings (the file's: ∞ when σ is known)

    @property
    def reveals(self) -> bool:
        """Whether measuring u_y at this station in every case of the suggestion (``cases_in_series``) would make
        the gap test fire on those measurements alone (:func:`detection_norm`)."""
        return self.series_in_sigma >= max(detection_norm(self.cases_in_series, DETECTION_ALPHA, self.dof), REVEAL_SIGMA)

    def sentence(self) -> str:
        datum = "Y from the unloaded geometry" if self.other_datum else "Y as now"
        kind = "a new load case" if self.new_case else "a measured load case"
        if not self.new_case and not self.other_datum:
            kind = "signed u_y at this station of a measured load case"
        return (f"u_y on the {self.shaft} shaft at x = {self.x_mm:.0f} mm with T1 = {self.case.input_torque_Nm:.3g}, "
                f"T2 = {self.case.output_torque_Nm:.3g} N·m ({kind}; {datum}): {self.change_um:+.3g} µm "
                f"({self.in_sigma:.2g} σ)")


@dataclass(frozen=True)
class Visibility:
    """How well the data see one effect, and what would reveal it."""

    effect: str
    norm_sigma: float
    largest_sigma: float
    visible: bool
    suggestion: Suggestion | None
    reason: str
    detectable: bool = True


def signature(response, values, view, rows=None) -> np.ndarray:
    """Scaled change of the observations by the effect at ``values``; ``view`` has ``base_paths``, ``observe`` and
    ``sigma`` (an :class:`Observed`, a fitting problem)."""
    base = view.observe(view.base_paths)
    change = (view.observe(view.base_paths + response.delta(values)) - base) / view.sigma
    return change if rows is None else change[rows]


def _strongest(response, view, rows) -> tuple[np.ndarray, np.ndarray]:
    """(values, signature) at the end of the physical range with the largest signature."""
    best, best_key = None, None
    for values in response.extremes():
        s = signature(response, values, view, rows)
        unit = response.unit_at(values)
        key = (float(s @ s), 0.0 if unit is None else float(np.abs(unit).sum()))  # invisible here: the larger change
        if best is None or key > best_key:
            best, best_key = (values, s), key
    return best


def direction(response, view, rows=None) -> np.ndarray:
    """Unit vector of the effect's dominant signature direction (grid effects: over the whole grid)."""
    if response.kind == "linear":
        stack = [signature(response, np.eye(response.n_params)[i] * p.typical, view, rows)
                 for i, p in enumerate(response.effect.parameters)]
    else:
        stack = [signature(response, [g], view, rows) for g in response.grid if g != 0.0]
    matrix = np.array(stack)
    if not np.any(matrix):
        return np.zeros(matrix.shape[1])
    _, _, vt = np.linalg.svd(matrix, full_matrices=False)
    return vt[0]


def scenarios(data, from_rest: bool) -> list[Scenario]:
    """The measurements considered besides the data: every station in the data's cases, the other datum, and
    new cases (T1 alone, T2 alone, both reversed) at the data's largest torques."""
    t1 = max(abs(c.input_torque_Nm) for c in data.cases) or 1.0
    t2 = max(abs(c.output_torque_Nm) for c in data.cases) or 1.0
    out = [Scenario("every station of the measured cases", tuple(data.cases), from_rest, False, False)]
    if from_rest:
        out.append(Scenario("Y from the unloaded geometry", tuple(data.cases), False, False, True))
    new = (LoadCase(t1, 0.0), LoadCase(0.0, t2), LoadCase(-t1, -t2))
    out.append(Scenario("new load cases", new, from_rest, True, False))
    if from_rest:
        out.append(Scenario("new load cases, Y from the unloaded geometry", new, False, True, True))
    return out


def _best_station(engine, unit_change, scenario: Scenario, shaft_sigma: dict, dof: float = np.inf) -> Suggestion | None:
    paths = engine.full_paths(unit_change, scenario.cases, scenario.from_rest)
    layout = engine.layout(len(scenario.cases))
    best, where = None, None
    for i, case in enumerate(scenario.cases):
        for shaft in MEASURED_SHAFTS:
            block = paths[layout.block(i, shaft)]
            scaled = np.abs(block) / shaft_sigma[shaft]
            j = int(np.argmax(scaled))
            if best is None or scaled[j] > best.in_sigma:
                best = Suggestion(scenario=scenario.label, case=case, shaft=shaft, x_mm=float(layout.stations_mm[shaft][j]),
                                  change_um=float(1e3 * block[j]), in_sigma=float(scaled[j]), new_case=scenario.new_cases, other_datum=scenario.other_datum)
                where = (shaft, j)
    if best is None:
        return None
    shaft, j = where  # the same station measured in every case of the scenario: what a gap test would see
    series = np.array([paths[layout.block(i, shaft)][j] for i in range(len(scenario.cases))]) / shaft_sigma[shaft]
    return replace(best, series_in_sigma=float(np.linalg.norm(series)), cases_in_series=len(scenario.cases), dof=dof)


def shaft_sigmas(data, sigma) -> dict:
    """A typical σ per shaft for a new observation (the median σ of that shaft's observations)."""
    out = {}
    for shaft in MEASURED_SHAFTS:
        mask = data.shaft == shaft
        out[shaft] = float(np.median(sigma[mask])) if mask.any() else float(np.median(sigma))
    return out


def observability(responses: dict, observed: Observed, alpha: float = DETECTION_ALPHA) -> dict[str, Visibility]:
    """The :class:`Visibility` of every response; for an invisible one, the measurement that would reveal it.

    ``visible`` (‖s‖ ≥ :data:`VISIBLE_NORM`) decides which candidates are screened; ``detectable`` whether the gap
    test at ``alpha`` would find the effect alone on these data (:func:`detection_norm` of every row, as the test reads them):
    what the report calls "can reveal"."""
    threshold = detection_norm(int(observed.data.n), alpha, observed.dof())  # the gap test reads every row
    shaft_sigma = shaft_sigmas(observed.data, observed.sigma)
    options = scenarios(observed.data, observed.from_rest)
    out = {}
    for name, response in responses.items():
        values, s = _strongest(response, observed, None)
        norm, largest = float(np.linalg.norm(s)), float(np.max(np.abs(s))) if s.size else 0.0
        visible = norm >= VISIBLE_NORM
        detectable = norm >= threshold
        suggestion = None
        if not detectable:
            unit = response.unit_at(values)
            candidates = []
            if unit is not None:
                candidates = [_best_station(observed.engine, unit, scenario, shaft_sigma, observed.dof()) for scenario in options]
            candidates = [c for c in candidates if c is not None]
            if candidates:
                suggestion = max(candidates, key=lambda c: c.in_sigma)
        if detectable:
            reason = f"visible: up to {norm:.3g} σ over the data (Δχ² {norm ** 2:.3g}) within its physical range"
        elif suggestion is not None and suggestion.reveals:
            reason = (f"{'below what the gap test detects' if visible else 'invisible'} on these data ({norm:.2g} σ "
                      f"at most within its physical range, the test needs {threshold:.2g} σ); revealed by "
                      + suggestion.sentence() + f", measured in each of its {suggestion.cases_in_series} case(s) "
                      f"({suggestion.series_in_sigma:.2g} σ together)")
        elif suggestion is not None:
            reason = (f"{'below what the gap test detects' if visible else 'invisible'} on these data ({norm:.2g} σ, "
                      f"the test needs {threshold:.2g} σ) and on any single station considered (best "
                      f"{suggestion.series_in_sigma:.2g} σ over {suggestion.cases_in_series} case(s): "
                      f"{suggestion.scenario}): too small on this rig")
        else:
            reason = (f"{'below what the gap test detects' if visible else 'invisible'} on these data ({norm:.2g} σ at "
                      f"most within its physical range, the test needs {threshold:.2g} σ)")
        out[name] = Visibility(effect=name, norm_sigma=norm, largest_sigma=largest, visible=visible, suggestion=suggestion, reason=reason, detectable=detectable)
    return out


def parallel_groups(directions: dict[str, np.ndarray], cosine: float = PARALLEL_COSINE) -> list[list[str]]:
    """Effects linked by |cos| ≥ ``cosine`` of their signature directions (connected groups of two or more)."""
    names = [n for n, d in directions.items() if np.any(d)]
    if not names:
        return []
    matrix = np.abs(np.array([directions[n] for n in names]) @ np.array([directions[n] for n in names]).T)
    parent = list(range(len(names)))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            if matrix[i, j] >= cosine:
                parent[root(i)] = root(j)
    groups: dict[int, list[str]] = {}
    for i, name in enumerate(names):
        groups.setdefault(root(i), []).append(name)
    return sorted((g for g in groups.values() if len(g) > 1), key=len, reverse=True)


def cosine_between(a: np.ndarray, b: np.ndarray) -> float:
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    return 0.0 if na == 0 or nb == 0 else float(abs(a @ b) / (na * nb))


def discriminate(first, second, observed: Observed) -> Suggestion | None:
    """Where the predictions of two effects, each scaled to explain the data equally, differ most (in σ)."""
    va, sa = _strongest(first, observed, None)
    vb, sb = _strongest(second, observed, None)
    ua, ub = first.unit_at(va), second.unit_at(vb)
    if ua is None or ub is None or not sb @ sb:
        return None
    scale = float(sa @ sb) / float(sb @ sb)
    shaft_sigma = shaft_sigmas(observed.data, observed.sigma)
    found = [_best_station(observed.engine, ua - scale * ub, scenario, shaft_sigma, observed.dof())
             for scenario in scenarios(observed.data, observed.from_rest)]
    found = [f for f in found if f is not None]
    return max(found, key=lambda f: f.in_sigma) if found else None
