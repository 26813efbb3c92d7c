"""When more than three look-alikes explain a gap equally well: what they share, how large each would be, and the
one extra measurement that splits them.

A group of look-alikes (the effects whose fits on these data are within the ambiguity margin of the named one, or
whose signatures are nearly parallel to it) is described by what its members do to the rig in engineering words
(``Effect.acts``) and where along the rig they act; each member is fitted alone to the gap the named effect explains
(linearised at the end of its physical range), so the group's fitted sizes are a range; and the measurement that
splits it is computed from the engine's unit paths for every measurement considered (:func:`observability.scenarios`:
every station of the measured cases, the other datum, new load cases): the station and case where the members'
data-matched predictions spread most, in σ of that shaft, split at the widest gap between them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.effects import effect_x_mm
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.studies.discrepancy.judge import AMBIGUOUS_GROUP
from rvcoax.results.studies.discrepancy.observability import _strongest, scenarios, shaft_sigmas, signature

__all__ = ["AMBIGUOUS_GROUP", "Ambiguity", "GroupSplit", "MemberSize", "ambiguity"]

@dataclass(frozen=True)
class MemberSize:
    """One member of a group fitted alone to the gap: its value, unit, and whether that lies within its bounds."""

    effect: str
    value: float
    unit: str
    within_bounds: bool


@dataclass(frozen=True)
class GroupSplit:
    """The one extra measurement that best splits a group: where the members' predictions spread most."""

    scenario: str
    case: LoadCase
    shaft: str
    x_mm: float
    new_case: bool
    other_datum: bool
    spread_um: float
    spread_in_sigma: float
    low: tuple[str, ...]
    high: tuple[str, ...]

    def sentence(self) -> str:
        where = ("a new load case" if self.new_case else "a measured load case") + \
            ("; Y from the unloaded geometry" if self.other_datum else "")
        return (f"measure u_y on the {self.shaft} shaft at x = {self.x_mm:.0f} mm with T1 = "
                f"{self.case.input_torque_Nm:.3g}, T2 = {self.case.output_torque_Nm:.3g} N·m ({where}): the "
                f"predictions spread over {self.spread_um:.3g} µm ({self.spread_in_sigma:.2g} σ) and split the group "
                f"into {', '.join(self.low)} and {', '.join(self.high)}")


@dataclass(frozen=True)
class Ambiguity:
    """A named effect's group of look-alikes, as an engineer reads it."""

    effect: str
    members: tuple[str, ...]
    shared: str
    sizes: tuple[MemberSize, ...]
    split: GroupSplit | None

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
        text = (f"{len(self.members)} look-alikes explain the gap equally well: {self.shared}; fitted sizes "
                f"{self.size_range()}")
        return text + (f"; to split them, {self.split.sentence()}" if self.split is not None else "")


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


def _sizes(members, responses: dict, observed, target: np.ndarray):
    """Each member fitted alone (linearised) to ``target``: (MemberSize, unit-path change at that size or None)."""
    out = []
    for name in members:
        response = responses[name]
        values, s = _strongest(response, observed, None)
        scale = float(s @ target) / float(s @ s) if s @ s > 0 else 0.0
        value = scale * float(np.atleast_1d(values)[0])
        p = response.effect.parameters[0]
        unit = response.unit_at(values)
        out.append((MemberSize(name, value, p.unit, bool(p.lower <= value <= p.upper)),
                    None if unit is None else scale * unit))
    return out


def _split(changes: dict[str, np.ndarray], observed) -> GroupSplit | None:
    """The station and case (any measurement considered) where the members' predictions spread most, in σ."""
    engine = observed.engine
    if engine is None or len(changes) < 2:
        return None
    names = list(changes)
    shaft_sigma = shaft_sigmas(observed.data, observed.sigma)
    best = None
    for scenario in scenarios(observed.data, observed.from_rest):
        paths = np.array([engine.full_paths(changes[n], scenario.cases, scenario.from_rest) for n in names])
        layout = engine.layout(len(scenario.cases))
        for i, case in enumerate(scenario.cases):
            for shaft in MEASURED_SHAFTS:
                block = paths[:, layout.block(i, shaft)]
                spread = (block.max(axis=0) - block.min(axis=0)) / shaft_sigma[shaft]
                j = int(np.argmax(spread))
                if best is None or spread[j] > best[0]:
                    best = (float(spread[j]), scenario, case, shaft, j, block[:, j])
    spread, scenario, case, shaft, j, predicted = best
    order = np.argsort(predicted)
    cut = int(np.argmax(np.diff(predicted[order]))) + 1  # the widest gap between neighbouring predictions
    return GroupSplit(scenario=scenario.label, case=case, shaft=shaft, x_mm=float(engine.layout(1).stations_mm[shaft][j]), new_case=scenario.new_cases,
                      other_datum=scenario.other_datum, spread_um=float(1e3 * np.ptp(predicted)), spread_in_sigma=spread,
                      low=tuple(names[k] for k in order[:cut]), high=tuple(names[k] for k in order[cut:]))


def ambiguity(selected, seen, after: np.ndarray) -> Ambiguity:
    """The group of one selected effect (:class:`SelectedEffect`) described: ``seen`` is the observe stage, ``after``
    the model with every selected effect (mm, every observation)."""
    observed = seen.observed
    responses = seen.library.responses
    members = tuple(m for m in selected.group if m in responses)
    own = signature(responses[selected.name], selected.values, observed)
    target = (observed.data.value_mm - after) / observed.sigma + own  # the gap this effect explains
    sized = _sizes(members, responses, observed, target)
    changes = {m.effect: change for m, change in sized if change is not None and m.within_bounds}
    return Ambiguity(selected.name, members, _shared(members, seen.effects, seen.rig),
                     tuple(m for m, _ in sized), _split(changes, observed))
