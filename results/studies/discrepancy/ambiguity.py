"""When the data cannot say which explanation is right: what the look-alikes share, how large each would be, and the
one extra measurement that would split them.

Three kinds of tie make an answer ``ambiguous`` (:func:`judge.qualify`), and each is described here:

- a named effect with more than three look-alikes (the effects whose fits on these data are within the ambiguity
  margin of the named one, or within the model-form allowance of its predictions): the group is described by what its
  members do to the rig in engineering words (``Effect.acts``) and where along the rig they act, and each member is
  fitted alone to the gap the named effect explains (linearised at the end of its physical range), so the group's
  fitted sizes are a range;
- the named explanation and a generic load outside the vocabulary (the sentinel) that fits within the noise as well,
  the generic load in every form the data cannot tell apart (:func:`generic_forms`: at one T2/T1 ratio a load ∝ T1
  is the load ∝ T2);
- the named explanation and a fit as good only at a value beyond a physical bound.

**The split measurement.** Every member predicts, from the engine's unit paths, what any measurement that was not
made would read (:func:`split_scenarios`: u_y at every station of a measured shaft — signed, for a |Y_max| table — in
the measured cases, with Y from the other datum, in new load cases with another T1/T2 ratio (T1 alone, T2 alone,
both reversed, at the largest measured torques: the rig has carried those), and the rig at rest read from the
unloaded geometry). A candidate measurement is one station read in one case, or in every case of its scenario (a
reading the data already hold is not an extra measurement and is left out). Its readings are scaled by the σ a new
reading would have, the noise of that shaft combined with the model-form allowance of the model's path there
(:mod:`locate`'s σ). Two members are told apart when their difference over the readings reaches what the gap test
needs on that many readings (:func:`locate.detection_norm`, and at least :data:`observability.REVEAL_SIGMA`: the
detection rule of the visibility report); members closer than that form one set (single linkage over the minimum
spanning tree of their separations), and the members of one explanation (the forms of a generic load) are one class
that must be told apart as a whole. The best candidate tells the most sets apart, then has the largest separation
relative to the rule. When even the best tells nothing apart, the answer says that no measurement in the candidate
set splits them, with the best separation found.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.effects import effect_x_mm
from rvcoax.geometry.model.loads import UNIT_LOADS
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.studies.discrepancy.engine import CANDIDATE_FAILURES
from rvcoax.results.studies.discrepancy.judge import AMBIGUOUS_GROUP, generic_ties
from rvcoax.results.studies.discrepancy.locate import detection_norm
from rvcoax.results.studies.discrepancy.lookalikes import exact_change
from rvcoax.results.studies.discrepancy.observability import (
    DETECTION_ALPHA,
    REVEAL_SIGMA,
    Scenario,
    _strongest,
    scenarios,
    signature,
)
from rvcoax.results.studies.discrepancy.sentinel import FAMILIES, LIMITS, SLOTS, sentinel_columns

__all__ = ["AMBIGUOUS_GROUP", "BEYOND", "GENERIC", "Ambiguity", "GroupSplit", "MemberSize", "ambiguities", "ambiguity",
           "best_split", "beyond_tie", "generic_forms", "generic_predictor", "generic_tie", "generic_ties", "needed_sigma", "split_scenarios"]

GENERIC = "generic load"  # the member name of a generic load outside the vocabulary that ties with the named effects
BEYOND = "beyond its bound"  # the member name of a fit that ties only at a value beyond a physical bound

# a member's prediction of a measurement: (cases, from_rest) → the change of the full paths there (mm)
Predictor = Callable[[tuple, bool], np.ndarray]


@dataclass(frozen=True)
class MemberSize:
    """One member of a group fitted alone to the gap: its value, unit, and whether that lies within its bounds."""

    effect: str
    value: float
    unit: str
    within_bounds: bool


def needed_sigma(readings: int, alpha: float = DETECTION_ALPHA, dof: float = np.inf) -> float:
    """What a difference read ``readings`` times (its norm in σ) must reach to split two members: the gap test's
    detection norm on that many observations, and at least :data:`REVEAL_SIGMA` (the visibility report's rule for a
    measurement that reveals an effect)."""
    return max(detection_norm(readings, alpha, dof), REVEAL_SIGMA)


@dataclass(frozen=True)
class GroupSplit:
    """The one extra measurement that best splits a group: a station of a measured shaft read in ``cases`` (one case,
    or every case of its scenario), with the datum ``from_rest`` says.

    ``parts`` are the sets of members it tells apart (single linkage: two members whose predictions differ by less
    than the gap test needs are in one part), lowest reading first; one part when it splits nothing. ``pair`` is the
    closest pair across two parts (when it splits) or across the widest gap (when not), ``separation_in_sigma`` the
    norm of their difference over the readings, in σ of a new reading (noise and model-form allowance),
    ``needed_sigma`` what the gap test needs on that many readings, ``separation_um`` their largest difference in
    one reading (in ``case``); ``spread_um`` / ``spread_in_sigma`` how far all members lie apart in that reading."""

    scenario: str
    cases: tuple[LoadCase, ...]
    case: LoadCase
    shaft: str
    x_mm: float
    new_case: bool
    other_datum: bool
    from_rest: bool
    signed: bool  # the data are |Y_max|: the suggestion is signed u_y
    parts: tuple[tuple[str, ...], ...]
    pair: tuple[str, str]
    low: tuple[str, ...]  # the members reading below the pair's midpoint in ``case`` (their side of the cut)
    high: tuple[str, ...]
    separation_um: float
    separation_in_sigma: float
    needed_sigma: float
    spread_um: float
    spread_in_sigma: float

    @property
    def splits(self) -> bool:
        """Whether this measurement tells at least two sets of members apart by the gap test's detection rule."""
        return len(self.parts) > 1

    def where(self) -> str:
        """The measurement in words: what is read, where, in which cases and from which datum."""
        what = "signed u_y" if self.signed else "u_y"
        if len(self.cases) == 1:
            c = self.cases[0]
            when = (f"with T1 = {c.input_torque_Nm:.3g}, T2 = {c.output_torque_Nm:.3g} N·m "
                    f"({'a new load case' if self.new_case else 'a measured load case'})")
        elif self.new_case:
            when = "in each of the new load cases " + "; ".join(
                f"T1 = {c.input_torque_Nm:.3g}, T2 = {c.output_torque_Nm:.3g} N·m" for c in self.cases)
        else:
            when = f"in each of the {len(self.cases)} measured load cases"
        datum = "Y from the rig aligned at rest" if self.from_rest else "Y from the unloaded geometry"
        return f"{what} on the {self.shaft} shaft at x = {self.x_mm:.0f} mm {when} ({datum})"

    def _size(self) -> str:
        at = (f" at T1 = {self.case.input_torque_Nm:.3g}, T2 = {self.case.output_torque_Nm:.3g} N·m"
              if len(self.cases) > 1 else "")
        return (f"{self.separation_um:.3g} µm{at} ({self.separation_in_sigma:.2g} σ over {len(self.cases)} "
                f"reading(s); the gap test needs {self.needed_sigma:.2g} σ)")

    def sentence(self) -> str:
        if self.splits:
            sets = " | ".join(", ".join(part) for part in self.parts)
            return (f"to split them, measure {self.where()}: it tells {len(self.parts)} sets apart ({sets}); the "
                    f"closest, {self.pair[0]} and {self.pair[1]}, differ by {self._size()}")
        return (f"no measurement in the candidate set splits them: the best, {self.where()}, separates "
                f"{self.pair[0]} and {self.pair[1]} only by {self._size()}")


@dataclass(frozen=True)
class Ambiguity:
    """A tie the data cannot break, as an engineer reads it: a named effect's group of look-alikes, or (``generic``
    set) the named explanation and a generic load outside the vocabulary."""

    effect: str
    members: tuple[str, ...]
    shared: str
    sizes: tuple[MemberSize, ...]
    split: GroupSplit | None
    generic: str | None = None  # the other explanation of a tie with the named effects (a generic load, a fit beyond a bound)
    unpredicted: tuple[str, ...] = ()  # members left out of the split: no prediction for other measurements
    forms: tuple = ()  # a tie with a generic load: its forms the data cannot tell apart (:func:`generic_forms`)

    def size_range(self) -> str:
        """The fitted sizes across the group, per unit (members beyond their bounds counted apart)."""
        parts = []
        for kind in dict.fromkeys(m.effect.split("@")[0] for m in self.sizes):
            members = [m for m in self.sizes if m.effect.split("@")[0] == kind]
            unit = members[0].unit
            inside = [m.value for m in members if m.within_bounds]
            beyond = sum(1 for m in members if not m.within_bounds)
            text = kind + " " + (f"{min(inside):+.3g} … {max(inside):+.3g} {unit}" if len(inside) > 1 else
                                 f"{inside[0]:+.3g} {unit}" if inside else f"none within bounds ({unit})")
            parts.append(text + (f" ({beyond} more only beyond their bounds)" if beyond else ""))
        return "; ".join(parts)

    def sentence(self) -> str:
        if self.generic is not None:
            sizes = ", ".join(f"{m.effect} at {m.value:+.3g}" + _unit(m.unit) for m in self.sizes)
            other = (f"{self.generic}," if self.effect == BEYOND else
                     f"a generic load outside the vocabulary ({self.generic})")
            text = f"the named explanation ({sizes}) and {other} fit the data equally well"
        else:
            text = (f"{len(self.members)} candidate effects explain the gap equally well (alone, or as the member of a "
                    f"pair that fits as well): {self.shared}; fitted sizes {self.size_range()}")
        if self.split is not None:
            text += "; " + self.split.sentence()
        elif self.unpredicted:
            text += (f"; no split computed: {', '.join(self.unpredicted)} cannot be predicted for other measurements "
                     "(they need real sweeps)")
        elif any(not m.within_bounds for m in self.sizes):
            text += "; no split computed: fewer than two members fit within their physical bounds"
        else:
            text += "; no split computed: no measurement considered could be predicted for the members"
        if self.unpredicted and self.split is not None:
            text += f" (not predicted for other measurements: {', '.join(self.unpredicted)})"
        return text


def _unit(unit: str) -> str:
    """' unit' after a value, nothing for a dimensionless one."""
    return "" if unit in ("", "-") else f" {unit}"


def _shared(members, effects: dict, rig) -> str:
    """What the members do to the rig, in words, and where along it."""
    acts = list(dict.fromkeys(effects[m].acts or effects[m].kind for m in members))
    what = acts[0] if len(acts) == 1 else " or ".join(acts)
    xs = [x for x in (effect_x_mm(effects[m], rig) for m in members) if x is not None]
    places = list(dict.fromkeys(effects[m].location for m in members if effects[m].location is not None))
    if not xs:
        return what
    if len(places) == 1:
        return f"{what}, at the {places[0]} (x = {xs[0]:.0f} mm)"
    return f"{what}, somewhere between x = {min(xs):.0f} and {max(xs):.0f} mm along the rig ({', '.join(places)})"


def _exact_possible(effect, engine) -> bool:
    return engine is not None and engine.linear and (effect.response == "clearance" or engine.supports(effect))


def _unit_predictor(engine, unit: np.ndarray) -> Predictor:
    return lambda cases, from_rest: engine.full_paths(unit, cases, from_rest)


def _exact_predictor(effect, values, engine) -> Predictor:
    return lambda cases, from_rest: exact_change(effect, values, engine, cases, from_rest)


def _sizes(members, responses: dict, observed, target: np.ndarray):
    """Each member fitted alone (linearised) to ``target``: (MemberSize, its predictor at that size or None)."""
    engine, out = observed.engine, []
    for name in members:
        response = responses[name]
        values, s = _strongest(response, observed, None)
        scale = float(s @ target) / float(s @ s) if s @ s > 0 else 0.0
        value = scale * float(np.atleast_1d(values)[0])
        p = response.effect.parameters[0]
        within = bool(p.lower <= value <= p.upper)
        unit = response.unit_at(values)
        if unit is not None:
            predictor = _unit_predictor(engine, scale * unit)
        elif within and _exact_possible(response.effect, engine) and len(response.effect.parameters) == 1:
            predictor = _exact_predictor(response.effect, [value], engine)
        else:
            predictor = None
        out.append((MemberSize(name, value, p.unit, within), predictor))
    return out


def split_scenarios(data, from_rest: bool) -> list[Scenario]:
    """The measurements a split is looked for in: :func:`observability.scenarios` (every station of the measured
    cases, the other datum, new load cases with another T1/T2 ratio) and the rig at rest read from the unloaded
    geometry (a load-independent part, e.g. a stiffness change under the rig's own weight, against a part ∝ torque)."""
    return [*scenarios(data, from_rest),
            Scenario("the rig at rest, Y from the unloaded geometry", (LoadCase(0.0, 0.0),), False, True, from_rest)]


def _tree(d: np.ndarray) -> list[tuple[int, int, float]]:
    """The minimum spanning tree of members with pairwise separations ``d`` (Prim): (i, j, separation) edges."""
    m = d.shape[0]
    used = np.zeros(m, bool)
    used[0] = True
    dist, parent, edges = d[0].copy(), np.zeros(m, int), []
    for _ in range(m - 1):
        j = int(np.argmin(np.where(used, np.inf, dist)))
        edges.append((int(parent[j]), j, float(dist[j])))
        used[j] = True
        closer = d[j] < dist
        dist, parent = np.where(closer, d[j], dist), np.where(closer, j, parent)
    return edges


def _parts(m: int, edges, need: float) -> list[list[int]]:
    """The members linked by tree edges shorter than ``need`` (single linkage: no cut of the members puts its closest
    pair further apart than the tree's edges that cross it)."""
    root = list(range(m))

    def find(i):
        while root[i] != i:
            root[i] = root[root[i]]
            i = root[i]
        return i

    for i, j, w in edges:
        if w < need:
            root[find(i)] = find(j)
    parts: dict[int, list[int]] = {}
    for i in range(m):
        parts.setdefault(find(i), []).append(i)
    return list(parts.values())


def _judged(d: np.ndarray, need: float):
    """(key, parts, pair, separation) of one candidate measurement: it tells ``parts`` apart; the closest pair across
    two parts (or, when it splits nothing, across the widest gap) and their separation. Candidates are ranked by how
    many parts they tell apart, then by that separation relative to ``need``."""
    edges = _tree(d)
    parts = _parts(d.shape[0], edges, need)
    crossing = [e for e in edges if e[2] >= need]
    i, j, w = min(crossing, key=lambda e: e[2]) if crossing else max(edges, key=lambda e: e[2])
    return (len(parts), w / need, w), parts, (i, j), w, edges


def _side(m: int, edges, cut: tuple[int, int]) -> np.ndarray:
    """The members the tree reaches from ``cut[1]`` without the edge ``cut`` (as a mask)."""
    side, stack = np.zeros(m, bool), [cut[1]]
    side[cut[1]] = True
    while stack:
        k = stack.pop()
        for a, b, _ in edges:
            if {a, b} == set(cut):
                continue
            for u, v in ((a, b), (b, a)):
                if u == k and not side[v]:
                    side[v] = True
                    stack.append(v)
    return side


def best_split(predictors: dict[str, Predictor], observed, noise_mm: dict[str, float], *,  # noqa: PLR0913
               model_form_fraction: float, alpha: float = DETECTION_ALPHA,
               classes: dict[str, str] | None = None) -> GroupSplit | None:
    """The measurement of :func:`split_scenarios` that splits the members (their predictors) best: the most sets of
    members told apart by the gap test's detection rule, then the largest separation relative to what the test needs
    (see the module docstring); None with fewer than two members or no engine. ``classes`` (member → name) makes
    several members one explanation (the forms of a generic load the data cannot tell apart): a measurement splits
    two classes only when it tells every member of one from every member of the other."""
    engine = observed.engine
    members = list(predictors)
    labels = [(classes or {}).get(n, n) for n in members]
    names = list(dict.fromkeys(labels))
    if engine is None or len(names) < 2:
        return None
    index = [np.array([i for i, label in enumerate(labels) if label == name]) for name in names]
    best = None
    for scenario in split_scenarios(observed.data, observed.from_rest):
        try:
            paths = np.array([predictors[n](scenario.cases, scenario.from_rest) for n in members])
        except CANDIDATE_FAILURES:
            continue
        base = engine.full_paths(engine.unit_paths, scenario.cases, scenario.from_rest)
        layout = engine.layout(len(scenario.cases))
        k = len(scenario.cases)
        for shaft in MEASURED_SHAFTS:
            blocks = [layout.block(i, shaft) for i in range(k)]
            predicted = np.stack([paths[:, b] for b in blocks], axis=1)  # (members, cases, stations)
            signal = np.sqrt(np.mean(np.stack([base[b] for b in blocks]) ** 2, axis=1))  # the path's RMS per case
            sigma = np.sqrt(noise_mm[shaft] ** 2 + (model_form_fraction * signal) ** 2)
            sigma = np.where(sigma > 0, sigma, np.inf)  # no σ: nothing can be read there
            scaled = predicted / sigma[None, :, None]
            difference = scaled[:, None] - scaled[None, :]  # (m, m, cases, stations)
            options = [(tuple(range(k)), np.sqrt(np.sum(difference ** 2, axis=2)))]
            if k > 1:
                options += [((c,), np.abs(difference[:, :, c])) for c in range(k)]
            made = _already_measured(observed.data, scenario, shaft, engine.stations_mm[shaft])
            for used, separations in options:
                need = needed_sigma(len(used), alpha, observed.dof())
                between = separations if len(names) == len(members) else _by_class(separations, index)
                for j in range(separations.shape[2]):
                    if made[list(used), j].any():  # not an extra measurement: the data hold that reading
                        continue
                    key, parts, pair, w, edges = _judged(between[:, :, j], need)
                    if best is None or key > best[0]:
                        a, b = _closest(separations[:, :, j], index[pair[0]], index[pair[1]])
                        best = (key, scenario, used, shaft, j, w, need, parts, pair, edges, (a, b),
                                predicted[:, :, j], scaled[:, :, j])
    if best is None:
        return None
    _, scenario, used, shaft, j, w, need, parts, pair, edges, (a, b), predicted, scaled = best
    used = list(used)
    worst = used[int(np.argmax(np.abs(predicted[a, used] - predicted[b, used])))]
    reading = np.array([float(np.mean(predicted[i, worst])) for i in index])  # per class
    parts = sorted(parts, key=lambda part: float(np.mean(reading[part])))  # lowest reading first
    lower, upper = sorted(pair, key=lambda c: reading[c])
    if len(parts) > 1:  # the parts reading below the pair's midpoint, and the others
        below = np.zeros(len(names), bool)
        for part in parts:
            below[part] = float(np.mean(reading[part])) < 0.5 * (reading[lower] + reading[upper])
    else:  # the two sides of the widest gap
        below = _side(len(names), edges, (upper, lower))
    return GroupSplit(
        scenario=scenario.label, cases=tuple(scenario.cases[c] for c in used), case=scenario.cases[worst], shaft=shaft,
        x_mm=float(engine.layout(1).stations_mm[shaft][j]), new_case=scenario.new_cases,
        other_datum=scenario.other_datum, from_rest=scenario.from_rest, signed=observed.data.schema == "table",
        parts=tuple(tuple(names[i] for i in sorted(part)) for part in parts), pair=(names[lower], names[upper]),
        low=tuple(n for n, b in zip(names, below) if b), high=tuple(n for n, b in zip(names, below) if not b),
        separation_um=float(1e3 * abs(predicted[a, worst] - predicted[b, worst])), separation_in_sigma=float(w),
        needed_sigma=float(need), spread_um=float(1e3 * np.ptp(predicted[:, worst])),
        spread_in_sigma=float(np.ptp(scaled[:, worst])))


def _already_measured(data, scenario: Scenario, shaft: str, stations_mm: np.ndarray) -> np.ndarray:
    """(cases, stations) of ``scenario``: whether the data already hold that reading (a paths file's own station, within
    0.5 mm, in a measured case and datum); a |Y_max| table holds no signed u_y."""
    made = np.zeros((len(scenario.cases), stations_mm.size), bool)
    if data.schema != "paths" or scenario.new_cases or scenario.other_datum:
        return made
    for i in range(len(scenario.cases)):
        x = data.x_mm[(data.case_index == i) & (data.shaft == shaft)]
        if x.size:
            made[i] = np.min(np.abs(stations_mm[:, None] - x[None, :]), axis=1) <= 0.5
    return made


def _by_class(separations: np.ndarray, index: list[np.ndarray]) -> np.ndarray:
    """Separations between classes of members (``index``: each class's members): their closest pair's."""
    n = len(index)
    out = np.zeros((n, n, separations.shape[2]))
    for a in range(n):
        for b in range(a + 1, n):
            out[a, b] = out[b, a] = separations[np.ix_(index[a], index[b])].min(axis=(0, 1))
    return out


def _closest(separations: np.ndarray, first: np.ndarray, second: np.ndarray) -> tuple[int, int]:
    """The closest pair of members of two classes."""
    block = separations[np.ix_(first, second)]
    i, j = np.unravel_index(int(np.argmin(block)), block.shape)
    return int(first[i]), int(second[j])


def ambiguity(selected, seen, after: np.ndarray, *, model_form_fraction: float = 0.02,
              alpha: float = DETECTION_ALPHA) -> Ambiguity:
    """The group of one selected effect (:class:`SelectedEffect`) described: ``seen`` is the observe stage, ``after``
    the model with every selected effect (mm, every observation)."""
    observed = seen.observed
    responses = seen.library.responses
    members = tuple(m for m in selected.group if m in responses)
    own = signature(responses[selected.name], selected.values, observed)
    target = (observed.data.value_mm - after) / observed.sigma + own  # the gap this effect explains
    sized = _sizes(members, responses, observed, target)
    predictors = {m.effect: p for m, p in sized if p is not None and m.within_bounds}
    return Ambiguity(selected.name, members, _shared(members, seen.effects, seen.rig), tuple(m for m, _ in sized),
                     best_split(predictors, observed, seen.noise.noise_mm, model_form_fraction=model_form_fraction,
                                alpha=alpha),
                     unpredicted=tuple(m.effect for m, p in sized if p is None and m.within_bounds))


def generic_predictor(engine, fit) -> Predictor:
    """A fitted generic load (:class:`sentinel.SentinelFit`) as a change of the unit paths: its force or moment at
    its site, in the slots of its constant, T1 and T2 parts (as the sentinel's scan weights them)."""
    site = [s for s in engine.sentinel_sites() if s[0] == fit.part and s[1] == fit.x_mm]
    shape = engine.sentinel_paths(site[:1], FAMILIES[fit.family][0])[0]
    unit = np.zeros((len(UNIT_LOADS), shape.size))
    for part, coefficient in zip(fit.parts_fitted, fit.coefficients):
        unit[UNIT_LOADS.index(SLOTS[part])] += coefficient * shape
    return _unit_predictor(engine, unit)


def _selection_predictor(fitted, seen, *, exact: bool = True) -> Predictor | None:
    """Effects together at their values (``fitted``: (name, values) pairs; exact on the factorisation where it solves
    them and ``exact``, else from their unit paths, superposed); None when one of them has neither."""
    engine, parts = seen.observed.engine, []
    for name, values in fitted:
        effect, response = seen.effects[name], seen.library.responses.get(name)
        linear = response is not None and response.kind == "linear" and response.unit_at(values) is not None
        if _exact_possible(effect, engine) and (exact or not linear):
            parts.append(_exact_predictor(effect, values, engine))
        elif response is not None and response.unit_at(values) is not None:
            parts.append(_unit_predictor(engine, response.unit_at(values)))
        else:
            return None
    return lambda cases, from_rest: sum(p(cases, from_rest) for p in parts)


def generic_forms(generic, observed, *, bic: float, margin: float, alpha: float) -> list:
    """Every form of ``generic`` (a :class:`sentinel.SentinelFit`) at its site the data cannot tell from the named
    effects: each subset of its constant, T1 and T2 parts fitted on the rows used to fit, kept when it ties with the
    named effects' BIC ``bic`` as the generic load does (:func:`generic_ties`). In cases with one T2/T1 ratio a load
    ∝ T1 and one ∝ T2 are the same load: a measurement splits the named effects from a generic load only when it
    splits them from each of its forms. ``generic`` itself comes first."""
    forms, columns = [generic], {}
    for part in SLOTS:
        try:
            columns[part] = sentinel_columns(replace(generic, parts_fitted=(part,), coefficients=(1.0,)), observed)[:, 0]
        except KeyError:  # (no constant part when Y is read from the rig at rest)
            continue
    rows, sigma = observed.rows, observed.sigma
    target = ((observed.data.value_mm - observed.before) / sigma)[rows]
    limits = LIMITS[generic.family]
    for size in range(1, len(columns) + 1):
        for subset in itertools.combinations(columns, size):
            if subset == generic.parts_fitted:
                continue
            matrix = np.column_stack([columns[p] for p in subset])
            coefficients, *_ = np.linalg.lstsq((matrix / sigma[:, None])[rows], target, rcond=None)
            if np.linalg.matrix_rank((matrix / sigma[:, None])[rows]) < size or any(
                    abs(c) > limits[0 if p == "constant" else 1] for p, c in zip(subset, coefficients)):
                continue
            residual = target - (matrix / sigma[:, None])[rows] @ coefficients
            form = replace(generic, parts_fitted=subset, coefficients=tuple(float(c) for c in coefficients),
                           chi2=float(residual @ residual), change=matrix @ coefficients)
            if generic_ties(form, bic, margin=margin, alpha=alpha):
                forms.append(form)
    return forms


def _terms(form) -> str:
    """A generic load's parts in words: '+1.2 N per N·m of T1, −0.3 N' (its unit: N or N·m)."""
    unit = FAMILIES[form.family][1]
    return ", ".join(f"{c:+.3g} {unit}" if part == "constant" else f"{c:+.3g} {unit} per N·m of {part}"
                     for part, c in zip(form.parts_fitted, form.coefficients))


def generic_tie(selected, generic, seen, *, bic: float, settings) -> Ambiguity:
    """The named explanation (every selected effect at its fitted value) against a generic load (``generic``, a
    :class:`sentinel.SentinelFit`, in every form the data cannot tell apart: :func:`generic_forms`) that fits as
    well, and the measurement that splits the two."""
    observed, engine = seen.observed, seen.observed.engine
    named = " + ".join(s.name for s in selected)
    sizes = tuple(MemberSize(s.name, float(s.values[0]), seen.effects[s.name].parameters[0].unit, True)
                  for s in selected)
    forms = generic_forms(generic, observed, bic=bic, margin=settings.ambiguity_margin, alpha=settings.alpha) \
        if engine is not None else [generic]
    described = generic.describe() + ("" if len(forms) == 1 else "; as well, the same place and cases: " + "; ".join(
        _terms(f) for f in forms[1:]))
    mine = _selection_predictor([(s.name, s.values) for s in selected], seen)
    split = None
    if mine is not None and engine is not None:
        predictors = {named: mine} | {f"{GENERIC} ({'+'.join(f.parts_fitted)})": generic_predictor(engine, f)
                                      for f in forms}
        split = best_split(predictors, observed, seen.noise.noise_mm, model_form_fraction=settings.model_form_fraction,
                           alpha=settings.alpha, classes={n: GENERIC for n in predictors if n != named})
    return Ambiguity(GENERIC, (named, GENERIC),
                     _shared([s.name for s in selected], seen.effects, seen.rig) + f", or {generic.describe()}", sizes,
                     split, generic=described, unpredicted=() if mine is not None else (named,), forms=tuple(forms))


def beyond_tie(selected, fit, seen, *, settings) -> Ambiguity:
    """The named explanation against ``fit`` (an :class:`identify.Fit` the screen rejected for a value beyond a
    physical bound, that fits within the ambiguity margin as well), and the measurement that splits the two."""
    named = " + ".join(s.name for s in selected)
    sizes = tuple(MemberSize(s.name, float(s.values[0]), seen.effects[s.name].parameters[0].unit, True)
                  for s in selected)
    outside = [(n, v) for n, v in zip(fit.names, fit.values) if n not in {s.name for s in selected}] or \
        list(zip(fit.names, fit.values))
    said = ", ".join(f"{n} at {float(np.atleast_1d(v)[0]):+.3g}" + _unit(seen.effects[n].parameters[0].unit)
                     for n, v in outside)
    mine, theirs = _selection_predictor([(s.name, s.values) for s in selected], seen), \
        _selection_predictor(list(zip(fit.names, fit.values)), seen, exact=False)  # the rig file refuses the value
    split = None
    if mine is not None and theirs is not None:
        split = best_split({named: mine, f"{said} ({BEYOND})": theirs}, seen.observed, seen.noise.noise_mm,
                           model_form_fraction=settings.model_form_fraction, alpha=settings.alpha)
    return Ambiguity(BEYOND, (named, f"{said} ({BEYOND})"), f"within the bounds, or {said}", sizes, split,
                     generic=f"{said}, beyond its physical bound",
                     unpredicted=tuple(m for m, p in ((named, mine), (said, theirs)) if p is None))


def _beyond_fit(steps, bic: float, margin: float):
    """The best fit the screen rejected only for a value beyond a physical bound, when it fits within ``margin`` of
    ``bic`` (the answer is then ``ambiguous``: :func:`judge.qualify`); None otherwise."""
    fits = [f for step in steps for f in step.rejected_fits.values()
            if f.rejected and "outside its physical range" in f.rejected and f.bic < bic + margin]
    return min(fits, key=lambda f: f.bic) if fits else None


def ambiguities(selected, seen, after: np.ndarray, *, verdict: str, generic, bic: float,  # noqa: PLR0913
                settings, steps=()) -> tuple[Ambiguity, ...]:
    """Every tie of an ``explained`` or ``ambiguous`` answer described: each named effect's group of look-alikes
    (more than one member), then, when a generic load ties with the named effects (:func:`generic_ties`; the answer
    is then ``ambiguous``), the named explanation against it, and likewise against a fit that ties only beyond a
    physical bound (``steps``: the screen's steps, with their rejected fits)."""
    if verdict not in ("explained", "ambiguous"):
        return ()
    fraction, alpha = settings.model_form_fraction, settings.alpha
    out = [ambiguity(s, seen, after, model_form_fraction=fraction, alpha=alpha) for s in selected if len(s.group) > 1]
    if verdict == "ambiguous" and selected and generic_ties(generic, bic, margin=settings.ambiguity_margin, alpha=alpha):
        out.append(generic_tie(selected, generic, seen, bic=bic, settings=settings))
    beyond = _beyond_fit(steps, bic, settings.ambiguity_margin) if verdict == "ambiguous" and selected else None
    if beyond is not None:
        out.append(beyond_tie(selected, beyond, seen, settings=settings))
    return tuple(out)
