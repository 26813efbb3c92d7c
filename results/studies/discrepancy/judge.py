"""The verdict's rules: when effects that fit the data are still not an explanation.

A fit that leaves no gap is ``explained`` unless one of these holds (each gives a reason, and the verdict is then
``unexplained``): the effects cancel each other; the same torque-proportional load is added at neighbouring places
with opposite signs; a single generic load (the sentinel) fits much better, or as well with fewer parameters;
held-out load cases do not improve; a curvature is left along a shaft beyond the model-form allowance.
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from rvcoax.results.studies.discrepancy.engine import CANDIDATE_FAILURES
from rvcoax.results.studies.discrepancy.identify import Problem
from rvcoax.results.studies.discrepancy.locate import residual_structure
from rvcoax.results.studies.discrepancy.observability import signature
from rvcoax.results.studies.discrepancy.sentinel import scan_spacing_mm

__all__ = ["AMBIGUOUS_GROUP", "FIGHT_RATIO", "STRUCTURE_T", "look_alike_places", "qualify", "fighting_pairs", "load_regions", "load_x", "opposite_loads", "verdict"]

FIGHT_RATIO = 0.5  # two effects whose sum is less than half the larger of them cancel each other
STRUCTURE_T = 4.0  # standard errors by which a curvature left along a shaft exceeds the model-form allowance


def opposite_loads(fitted: list[tuple[str, np.ndarray]], effects: dict, places: dict | None = None) -> list[str]:
    """Pairs of the same torque-proportional load (N per N·m) at two neighbouring places with opposite signs: a
    force couple between them, i.e. a localized load or moment that the vocabulary does not hold, mimicked by two
    reactions. ``places`` (name → x in mm of every such candidate) restricts the pairs to neighbours: no candidate
    of the same kind acts between them (the vocabulary would put a load there itself); without it every pair
    counts."""
    loads = {}
    for name, values in fitted:
        effect = effects.get(name)
        values = np.atleast_1d(values)
        if effect is not None and len(effect.parameters) == 1 and effect.parameters[0].unit == "N/(N·m)":
            loads.setdefault(effect.kind, []).append((name, float(values[0])))
    out = []
    for members in loads.values():
        for i, (a, va) in enumerate(members):
            for b, vb in members[i + 1:]:
                if places and a in places and b in places:
                    lo, hi = sorted((places[a], places[b]))
                    kind = effects[a].kind
                    if any(lo < x < hi for n, x in places.items() if effects[n].kind == kind):
                        continue  # not neighbours
                if va * vb < 0:
                    out.append(f"{a} and {b} are the same load at two places with opposite signs ({va:+.3g} and "
                               f"{vb:+.3g} N per N·m): a couple mimicking a load between them, not an explanation")
    return out


def fighting_pairs(problem: Problem, fitted: list[tuple[str, np.ndarray]]) -> list[str]:
    """Pairs of selected effects that cancel each other: each large, their sum small."""
    signatures = {n: signature(problem.responses[n], v, problem, problem.rows)
                  for n, v in fitted if n in problem.responses}
    out = []
    names = list(signatures)
    total = sum(signatures.values()) if signatures else 0.0
    largest = max((np.linalg.norm(v) for v in signatures.values()), default=0.0)
    if len(names) > 2 and largest > 0 and np.linalg.norm(total) < FIGHT_RATIO * largest:
        out.append(f"{', '.join(names)} cancel each other (the largest {largest:.3g} σ, together "
                   f"{np.linalg.norm(total):.3g} σ): a shape mimicked, not an explanation")
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            sa, sb = signatures[a], signatures[b]
            larger = max(np.linalg.norm(sa), np.linalg.norm(sb))
            if larger > 0 and np.linalg.norm(sa + sb) < FIGHT_RATIO * larger:
                out.append(f"{a} and {b} cancel each other (each {np.linalg.norm(sa):.3g} and {np.linalg.norm(sb):.3g} σ, "
                           f"together {np.linalg.norm(sa + sb):.3g} σ): a shape mimicked, not an explanation")
    return out


def _changed_loads(effect, rig) -> list:
    """The lateral loads (torque_lateral_loads) that ``effect`` at its typical value adds to ``rig`` or changes."""
    before = {t.name: t for t in rig.torque_lateral_loads}
    try:
        changed = effect.apply(rig, [p.typical for p in effect.parameters])
    except CANDIDATE_FAILURES:
        return []
    return [load for load in changed.torque_lateral_loads if before.get(load.name) != load]


def load_x(effects_by_name: dict, rig) -> dict[str, float]:
    """x (mm) where each torque-proportional load of the vocabulary (one parameter in N per N·m) acts."""
    out = {}
    for name, effect in effects_by_name.items():
        if len(effect.parameters) == 1 and effect.parameters[0].unit == "N/(N·m)":
            loads = _changed_loads(effect, rig)
            if loads:
                out[name] = float(loads[0].on.x_mm)
    return out


def load_regions(effects_by_name: dict, rig, names, sites) -> dict[str, tuple[tuple[str, float, float], ...]]:
    """Where each named effect puts a lateral load on the rig: (part, lo_mm, hi_mm) of every load it adds or
    changes, at its ``on`` and ``reacted_on`` places (the band of the teeth where given), widened by the
    sentinel scan's spacing on that part (the scan cannot place a load more finely).

    Two places more, both model form rather than a load the vocabulary lacks:
    - a bearing whose stiffness an effect changes acts on its shaft and housing as a force over the bearing's
      width (Δk times the deflection there), so a generic load there is that effect's load;
    - on a housing (a body, far stiffer than the shafts) a load anywhere differs from the named load at another
      x of the same body only by a moment about its mount, which the way another model spreads and reacts the
      load decides: a named load on a body claims the whole body, and the shaft where a joint that carries
      lateral force (a flange; not a torsion-only gear mesh or brake gap) ties the body to it."""
    bodies = {p.name for p in rig.parts if p.role == "body"}
    bearings = {b.name: b for b in rig.bearings}
    lateral_joints = [pair for j in rig.joints if j.translational_stiffness_N_per_um[1] > 0
                      for pair in ((j.from_, j.to), (j.to, j.from_))]

    def region(part, lo, hi):
        if part in bodies:
            return (part, -np.inf, np.inf)
        pad = scan_spacing_mm(sites, part)
        return (part, float(lo) - pad, float(hi) + pad)

    out = {}
    for name in names:
        regions = []
        for load in _changed_loads(effects_by_name[name], rig):
            for place in (load.on, load.reacted_on):
                if place is None:
                    continue
                lo, hi = place.band_mm if place.band_mm is not None else (place.x_mm, place.x_mm)
                regions.append(region(place.part, lo, hi))
                if place.part in bodies:  # through a joint that carries lateral force (a flange) into a shaft
                    regions += [region(b.part, b.x_mm, b.x_mm) for a, b in lateral_joints if a.part == place.part]
        bearing = bearings.get(effects_by_name[name].location)
        if bearing is not None and effects_by_name[name].kind == "bearing_stiffness":
            half = 0.5 * bearing.width_mm  # the bearing's reaction spreads over its width
            regions += [region(bearing.shaft, bearing.x_mm - half, bearing.x_mm + half),
                        region(bearing.housing, bearing.x_mm - half, bearing.x_mm + half)]
        if regions:
            out[name] = tuple(regions)
    return out


def look_alike_places(effects: dict, rig, names, sites) -> dict[str, tuple[tuple[str, float, float], ...]]:
    """Where each of ``names`` acts on the rig, for telling a generic load from a look-alike in the vocabulary: the
    places of :func:`load_regions`, and more that are no lateral load of the rig file: a housing whose mounts an
    effect lifts or softens (or whose temperature or stiffness it changes) is that body, whole, with the shafts its
    flanges carry; a coupling's offset or angle acts at its two hubs."""
    out = dict(load_regions(effects, rig, names, sites))
    bodies = {p.name for p in rig.parts if p.role == "body"}
    couplings = {c.name: c for c in rig.couplings}
    lateral_joints = [pair for j in rig.joints if j.translational_stiffness_N_per_um[1] > 0
                      for pair in ((j.from_, j.to), (j.to, j.from_))]
    for name in names:
        effect, extra = effects[name], []
        if effect.location in bodies:
            extra.append((effect.location, -np.inf, np.inf))
            extra += [(b.part, b.x_mm - scan_spacing_mm(sites, b.part), b.x_mm + scan_spacing_mm(sites, b.part))
                      for a, b in lateral_joints if a.part == effect.location]
        elif effect.location in couplings:
            c = couplings[effect.location]
            extra += [(end.part, end.x_mm - scan_spacing_mm(sites, end.part), end.x_mm + scan_spacing_mm(sites, end.part))
                      for end in (c.from_, c.to)]
        if extra:
            out[name] = tuple(out.get(name, ())) + tuple(extra)
    return out


def verdict(problem: Problem, fitted: list[tuple[str, np.ndarray]], after: np.ndarray, *, data, tests, sentinel,  # noqa: PLR0913
            mimic, cv, settings, effects: dict, places: dict | None, groups=(), beyond=(),
            generic="same") -> tuple[str, list[str]]:
    """``no_gap``, ``explained`` or ``unexplained``, with the reasons for the last.

    ``problem`` holds σ and the rows used to fit, ``data`` the measurements; ``fitted`` the effects added with their values, ``after`` the model with them
    (every observation, mm); ``tests`` the gap tests (before, after). ``sentinel`` is the generic load the vocabulary
    must beat by the BIC margin; ``mimic`` (default ``sentinel``) the best generic load anywhere, which tells
    whether effects that cancel each other mimic a load's shape and whether the vocabulary needs more parameters
    than one load for a fit as good; ``places`` where the vocabulary's torque-proportional loads act
    (:func:`opposite_loads`). A fit that passes them all is then qualified (:func:`qualify`) with ``groups`` (the
    named effects' look-alike groups), ``beyond`` (fits better than the vocabulary's only beyond a bound) and
    ``generic`` (the generic load that may tie with the vocabulary; default ``sentinel``; None: none away from the
    places of the named effects and their look-alikes)."""
    test_before, test_after = tests
    sigma = problem.sigma
    if not test_before.gap:
        return "no_gap", []
    reasons = []
    if not fitted:
        reasons.append("no effect of the vocabulary improves the fit by the margin")
    if test_after.gap:
        reasons.append(f"the gap left is beyond the noise and the model-form allowance ({test_after.describe()})")
    mimic = sentinel if mimic is None else mimic
    rows = problem.rows
    chi2 = float(np.sum((((data.value_mm - after) / sigma)[rows]) ** 2))
    k = int(sum(np.atleast_1d(v).size for _, v in fitted))
    bic = chi2 + k * np.log(max(rows.size, 2))
    # effects that cancel each other mimic a shape only if some simpler load makes that shape: when every single
    # generic load fits far worse than the pair and leaves a gap itself, the two oppose each other in the data, as
    # real effects may
    if mimic is None or mimic.bic < bic + settings.bic_margin or stats.chi2.sf(mimic.chi2, mimic.n) >= settings.alpha:
        reasons += fighting_pairs(problem, fitted)
    reasons += opposite_loads(fitted, effects or {}, places)
    if fitted:
        better = sentinel is not None and sentinel.bic < bic - settings.bic_margin
        if better:
            reasons.append(f"a single generic load fits much better than the vocabulary (BIC {sentinel.bic:.4g} "
                           f"against {bic:.4g})")
        # more parameters than one generic load for a fit as good: judged against the best generic load anywhere,
        # also where a named effect puts its load (a named load and spurious companions mimicking its form)
        elif mimic is not None and k > mimic.k \
                and (mimic.bic < bic or stats.chi2.sf(mimic.chi2, mimic.n) >= settings.alpha):
            reasons.append(f"the vocabulary needs {k} parameters where one generic load needs {mimic.k} for a "
                           f"fit as good (χ² {chi2:.4g} against {mimic.chi2:.4g})")
        if cv is not None and not cv.improves:
            reasons.append(f"held-out load cases do not improve (χ² {cv.chi2_before:.4g} → {cv.chi2_after:.4g})")
        residual = data.value_mm - after
        for finding in residual_structure(data, residual, sigma, threshold=STRUCTURE_T,
                                          model_form_fraction=settings.model_form_fraction):
            if finding.test == "curvature along the shaft" and finding.significant:
                reasons.append(f"structure left along the {finding.shaft} shaft (curvature, {finding.detail})")
    if reasons:
        return "unexplained", reasons
    return qualify(bic, sentinel=sentinel if generic == "same" else generic, groups=groups, beyond=beyond,
                   settings=settings)


AMBIGUOUS_GROUP = 3  # a group of more than three look-alikes is "one of many", not an explanation


def generic_ties(generic, bic: float, *, margin: float, alpha: float) -> bool:
    """Whether a generic load fits within the noise (its χ² test finds no gap at ``alpha``) and within the ambiguity
    ``margin`` of the named effects' BIC ``bic``: the data cannot tell them apart."""
    return generic is not None and generic.bic < bic + margin and stats.chi2.sf(generic.chi2, generic.n) >= alpha


def qualify(bic: float, *, sentinel, groups, beyond, settings) -> tuple[str, list[str]]:
    """What a fit that leaves no gap and passes every rule may claim (the vocabulary's BIC is ``bic``):

    - ``unexplained`` when a candidate fitted beyond its physical bound fits better by more than the ambiguity
      margin (``beyond``: (reason, BIC) pairs): only a value outside the bounds closes the gap as well;
    - ``ambiguous`` when a generic load (the sentinel the verdict compares with) fits within the noise as well as the
      named effects (its BIC within the ambiguity margin): the data cannot tell a named effect from a load outside
      the vocabulary; or when a named effect's group has more than :data:`AMBIGUOUS_GROUP` look-alikes; or when a
      candidate beyond its physical bound fits within the ambiguity margin as well (an effect beyond its bound is
      never ``explained`` by in-bounds look-alikes pinned at theirs);
    - ``explained`` otherwise."""
    better = [(reason, b) for reason, b in beyond if b < bic - settings.ambiguity_margin]
    if better:
        return "unexplained", [f"only a value beyond a physical bound closes the gap as well: {reason} (BIC {b:.4g} "
                               f"against {bic:.4g} within the bounds)" for reason, b in better]
    reasons = []
    if generic_ties(sentinel, bic, margin=settings.ambiguity_margin, alpha=settings.alpha):
        reasons.append(f"a single generic load fits within the noise as well as the named effects ({sentinel.describe()}; "
                       f"BIC {sentinel.bic:.4g} against {bic:.4g}): the data cannot tell them apart")
    reasons += [f"{len(g)} look-alikes explain the gap equally well ({', '.join(g)})" for g in groups
                if len(g) > AMBIGUOUS_GROUP]
    reasons += [f"a value beyond a physical bound fits as well (BIC {b:.4g} against {bic:.4g} within the bounds): "
                f"{reason}; the data cannot tell whether the truth lies within the bounds" for reason, b in beyond
                if b < bic + settings.ambiguity_margin]
    return ("ambiguous", reasons) if reasons else ("explained", [])
