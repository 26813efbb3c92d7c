"""How much can the blind benchmark's data carry? An oracle that knows the truth, beside the workflow's answers.

For every blind data set (``bench_discrepancy_blind.py``'s sets: hybrid, CalculiX beam, CalculiX solid shafts) the
oracle asks whether *any* honest rule could give an informative answer on these data (issue 28: the truth named
alone, in a named pair, or in an ``explained`` group of at most three; ``unexplained`` for a load outside the
vocabulary or a truth beyond its bounds; ``no_gap`` when nothing is hidden). It uses the workflow's own functions
(read-only) and its own settings:

1. **detectable**: the truth's noise-free change, in units of the workflow's σ (noise estimated from the file, the
   rounding of its printed digits and the 2 % model-form allowance, ``locate.estimate_noise``), must reach the gap
   test's detection norm on the rows used to fit (``locate.detection_norm``: the χ² it adds lifts the expected χ² to
   the test's critical value). The change is the identification model's change at the true value (manifest); for a
   load outside the vocabulary, the best generic load's fit (the sentinel, ``sentinel.fit_sentinel``); with nothing
   hidden, the data must pass the gap test itself;
2. **separable**: the truth fitted at its best size (``identify.Problem.fit``, started from the true value too) is
   compared with every hypothesis that excludes it: every single candidate the workflow screens, within its physical
   bounds; every pair of candidates that earns both its parameters (the pair's BIC below either member's alone, the
   screen's criterion) and is no mimicked shape (``judge.fighting_pairs``, ``judge.opposite_loads``); and the
   workflow's generic load (the sentinel, compared as the verdict compares it: ``judge.generic_ties``, away from the
   truth's own load site). An alternative "fits as well" by the workflow's group rule (``workflow._fits_as_well``): its
   BIC within the ambiguity margin (6) of the truth's, or its predictions within the model-form allowance (2 % of the
   signal) of the truth's. The smallest group an honest rule could name holds the truth and every alternative's
   effects (for a pair, each member's group holds the effects that replace it with the other member kept; an
   alternative that replaces both joins both groups).

A set is **informative-possible** when detectable and every group that holds the truth has at most three effects, and
no generic load ties (a set whose hidden change is below the noise by construction, ``detectable`` false in the
manifest, is possible too when its data pass the gap test: nothing added is informative there). Out of vocabulary: detectable and no vocabulary
hypothesis within the margin of the generic load. Beyond bounds: the truth's fit beyond its bound better than every
in-bounds hypothesis by more than the margin (``judge.qualify``'s rule).

Pairs are searched with the first member among the best :data:`PAIR_FIRST` single candidates and the second among all,
each started from the members' single fits: an alternative outside that search is missed, so the ceiling is an upper
bound (it can only be lower).

Prints per source, schema and class the ceiling (informative-possible fraction) beside the workflow's informative
rate, and the sets where the workflow is below the oracle (its real misses) and above it. The workflow's answers are
read from documents kept by ``bench_discrepancy_blind.py --keep DIR`` (``--docs DIR``) or computed here (``--draws
0``, no confidence estimate). Appends the figures to benchmarks/RESULTS.md (``--no-record``: print only).

Usage::

    python benchmarks/bench_discrepancy_ceiling.py [--source hybrid|calculix|calculix_solid_full] [--limit N]
        [--seed S] [--docs DIR] [--max-minutes M] [--no-record]
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

PAIR_FIRST = 12  # the best single candidates that open a pair alternative (the workflow's own search opens 8)
VERSION = "2"  # of the saved files (--save): files of an earlier version are judged again where it judged otherwise
GROUP_LIMIT = 3  # issue 28: an explained group of at most three is informative (judge.AMBIGUOUS_GROUP)


@dataclass(frozen=True)
class Ceiling:
    """What an honest rule could say on one data set, knowing what the oracle knows.

    ``norm_sigma`` is the truth's noise-free change in σ on the rows used to fit, ``threshold`` the gap test's
    detection norm there; ``truth_bic`` the truth's best BIC; ``alternatives`` the hypotheses that exclude the truth
    and fit as well, with their BIC; ``groups`` the smallest group an honest rule could name per truth member;
    ``generic`` whether the workflow's generic load ties with the truth."""

    detectable: bool
    norm_sigma: float
    threshold: float
    truth_bic: float
    alternatives: tuple[tuple[tuple[str, ...], float], ...]
    groups: tuple[tuple[str, ...], ...]
    generic: bool
    possible: bool
    why: str
    parsimonious: bool | None = None  # possible when pairs do not count against a true single effect
    with_form: bool | None = None  # possible when the model-form clause of the group rule counts too

    @property
    def group_size(self) -> int:
        return max((len(g) for g in self.groups), default=0)


def detectable(signature_on_rows: np.ndarray, alpha: float) -> tuple[bool, float, float]:
    """(detectable, ‖s‖, threshold): the gap test's rule for a noise-free change ``s`` (in σ, rows used to fit)."""
    from rvcoax.results.studies.discrepancy.locate import detection_norm

    norm = float(np.linalg.norm(signature_on_rows))
    threshold = detection_norm(int(signature_on_rows.size), alpha)
    return norm >= threshold, norm, threshold


def _equivalent(problem, fit, truth_predicted, truth_bic: float, settings, signal_norm: float) -> tuple[bool, bool]:
    """(by the margin, by the model form): the BIC of ``fit`` within the ambiguity margin of the truth's (the margin the
    workflow forms groups by); its predictions within the model-form allowance of the truth's (RMS of their difference
    at most that fraction of the signal on the rows used to fit: the second clause of ``workflow._fits_as_well``)."""
    margin = bool(fit.bic - truth_bic < settings.ambiguity_margin)
    predicted = problem.observe(problem.paths(fit.names, fit.values))[problem.rows]
    form = bool(np.linalg.norm(predicted - truth_predicted) <= settings.model_form_fraction * signal_norm)
    return margin, form


def alternatives(problem, truth: tuple[str, ...], candidates, settings, *, reference, effects=None, places=None,  # noqa: PLR0913
                 in_bounds_only: bool = True, pair_first: int = PAIR_FIRST, model_form: bool = False):
    """Every hypothesis that excludes ``truth`` (single candidates, pairs that earn both parameters) and fits as well
    as the truth: [(names, bic), …], best first. ``reference`` is the truth's (BIC, predicted observations on the rows
    used to fit); "as well" is the BIC within the ambiguity margin, or (``model_form``) predictions within the
    model-form allowance too. A pair that holds one member of a true pair and swaps the other counts (it excludes the
    truth pair), a pair that holds a true single effect does not; ``in_bounds_only``: fits beyond a physical bound are
    no alternative."""
    found = _alternatives(problem, truth, candidates, settings, reference=reference, effects=effects, places=places,
                          in_bounds_only=in_bounds_only, pair_first=pair_first)
    return [(names, bic) for names, bic, margin in found if margin or model_form]


def _alternatives(problem, truth, candidates, settings, *, reference, effects, places, in_bounds_only,  # noqa: PLR0913
                  pair_first):
    """:func:`alternatives` with both clauses: [(names, bic, within the BIC margin), …] of every hypothesis that fits
    as well by either."""
    from rvcoax.results.studies.discrepancy.engine import CANDIDATE_FAILURES
    from rvcoax.results.studies.discrepancy.judge import fighting_pairs, opposite_loads

    signal = problem.observe(problem.base_paths)[problem.rows]
    signal_norm = float(np.linalg.norm(signal))
    truth_bic, truth_predicted = float(reference[0]), reference[1]
    found = []
    singles = {}
    for name in candidates:
        try:
            fit = problem.fit((name,))
        except CANDIDATE_FAILURES:
            continue
        usable = not (in_bounds_only and fit.rejected)
        singles[name] = (fit.bic if usable else np.inf, fit)
        if (name,) != tuple(truth) and usable:
            margin, form = _equivalent(problem, fit, truth_predicted, truth_bic, settings, signal_norm)
            if margin or form:
                found.append(((name,), float(fit.bic), margin))
    first = sorted(singles, key=lambda n: singles[n][0])[:pair_first]
    tried = set()
    for a in first:
        for b in candidates:
            key = frozenset((a, b))
            if a == b or key in tried or key == frozenset(truth) or (len(truth) == 1 and truth[0] in key):
                continue
            tried.add(key)
            start = {n: singles[n][1].values[0] for n in (a, b) if n in singles}
            try:
                fit = problem.fit((a, b), start)
            except CANDIDATE_FAILURES:
                continue
            if (in_bounds_only and fit.rejected) or fit.bic >= singles.get(a, (np.inf,))[0] \
                    or fit.bic >= singles.get(b, (np.inf,))[0]:
                continue  # a member that does not earn its parameter: the single is the hypothesis
            margin, form = _equivalent(problem, fit, truth_predicted, truth_bic, settings, signal_norm)
            if not (margin or form):
                continue
            pair = list(zip(fit.names, fit.values))
            if fighting_pairs(problem, pair) or opposite_loads(pair, effects or {}, places):
                continue  # a mimicked shape: no explanation by the workflow's own rules
            found.append(((a, b), float(fit.bic), margin))
    return sorted(found, key=lambda item: item[1])


NOTHING = "(nothing)"  # a member of a true pair that the data do not need: its group holds "nothing"


def groups_of(truth: tuple[str, ...], found) -> tuple[tuple[str, ...], ...]:
    """The smallest group an honest rule could name for each truth member: the member and the effects that replace
    it. An alternative that keeps one member of a true pair adds its other effect to the other member's group; one that
    replaces a true pair by two effects adds one to each member's group (the assignment that adds fewer new members); a
    single effect that replaces a whole true pair joins one group and puts :data:`NOTHING` in the other (the data do not
    show that there are two effects); every alternative of a true single effect joins its group."""
    groups = {m: [m] for m in truth}
    later = []
    for names, _ in found:
        kept = [m for m in truth if m in names]
        others = [n for n in names if n not in truth]
        if len(truth) == 1:
            groups[truth[0]] += [n for n in others if n not in groups[truth[0]]]
        elif kept:
            for m in (m for m in truth if m not in kept):
                groups[m] += [n for n in others or [NOTHING] if n not in groups[m]]
        else:
            later.append(others)
    for others in later:  # alternatives that replace a whole true pair, after the swaps that pin members down
        options = []
        fill = others if len(others) == 2 else [others[0], NOTHING]
        for order in (fill, fill[::-1]):
            trial = {m: groups[m] + [n] if n not in groups[m] else groups[m] for m, n in zip(truth, order)}
            added = sum(len(trial[m]) - len(groups[m]) for m in truth)
            options.append((added, max(len(g) for g in trial.values()), trial))
        groups = min(options, key=lambda o: o[:2])[2]
    return tuple(tuple(groups[m]) for m in truth)


def truth_fit(problem, truth: tuple[str, ...], values: dict):
    """The truth at its best size: the better of the workflow's fit and a fit started at the true values."""
    fits = [problem.fit(truth)]
    start = {n: np.atleast_1d(np.asarray(values[n], float)) for n in truth if n in values}
    if len(start) == len(truth):
        fits.append(problem.fit(truth, start))
    return min(fits, key=lambda f: f.chi2)


# ---- one blind data set ------------------------------------------------------------------------------------------

def _sentinel_tie(seen, observed, truth, group_members, bic: float, settings) -> bool:
    """Whether the workflow's generic load ties with the truth, as ``workflow._judge`` passes it to ``judge.qualify``:
    the best generic load, unless it acts where a load among the group's members acts (``workflow._generic_elsewhere``:
    there it is that look-alike); else, when it acts at the truth's own load site, the best one away from there
    (``workflow._sentinel_away``). A generic load at a stiffness's or clearance's place is no load of the group: the data
    must tell the two apart."""
    from rvcoax.results.studies.discrepancy.judge import generic_ties, load_regions
    from rvcoax.results.studies.discrepancy.sentinel import fit_sentinel, site_in
    from rvcoax.results.studies.discrepancy.workflow import SelectedEffect, _generic_elsewhere

    engine = seen.library.engine
    sentinel = fit_sentinel(observed)
    if sentinel is None:
        return False
    selected = [SelectedEffect(truth[0], (), 0.0, tuple(group_members), 1)]
    generic = _generic_elsewhere(seen, sentinel, selected)
    if generic is None:
        regions = load_regions(seen.effects, seen.rig, list(truth), engine.sentinel_sites())
        if any(site_in((sentinel.part, sentinel.x_mm), r) for r in regions.values()):
            away = fit_sentinel(observed, exclude=tuple(x for r in regions.values() for x in r))
            generic = _generic_elsewhere(seen, away, selected)
    return generic_ties(generic, bic, margin=settings.ambiguity_margin, alpha=settings.alpha)


def oracle(dataset: dict, seen, settings) -> Ceiling:  # noqa: PLR0914
    """The :class:`Ceiling` of one blind data set (see the module docstring); ``seen`` is the workflow's observe stage
    on it (``workflow._observe``)."""
    from rvcoax.results.studies.discrepancy.identify import Problem
    from rvcoax.results.studies.discrepancy.judge import load_x
    from rvcoax.results.studies.discrepancy.locate import gap_test
    from rvcoax.results.studies.discrepancy.sentinel import fit_sentinel

    observed = seen.observed
    group = dataset["group"]
    quiet = not gap_test(observed.scaled_before[observed.rows], settings.alpha).gap  # the data show no gap
    hidden = not dataset.get("detectable", True) and quiet  # nothing added is informative (the scorer's rule)
    if group == "none":
        test = gap_test(observed.scaled_before[observed.rows], settings.alpha)
        return Ceiling(True, float(np.sqrt(test.chi2)), 0.0, np.nan, (), (), False, not test.gap,
                       "no gap on the data" if not test.gap else f"the data show a gap with nothing hidden "
                       f"({test.describe()}): model form beyond the allowance", not test.gap, not test.gap)
    truth = tuple(dataset["truth"])
    responses = dict(seen.responses)
    for name in truth:
        responses.setdefault(name, seen.library.responses[name])
    problem = Problem(observed.data.value_mm, observed.sigma, observed.base_paths, observed.observe, responses,
                      rows=observed.rows)
    candidates = list(seen.responses)
    places = load_x(seen.effects, seen.rig)
    if group == "out_of_vocabulary":
        sentinel = fit_sentinel(observed)
        change = sentinel.change[observed.rows] / observed.sigma[observed.rows] if sentinel is not None else \
            np.zeros(int(observed.rows.sum()))
        seen_, norm, threshold = detectable(change, settings.alpha)
        if sentinel is None:
            return Ceiling(seen_, norm, threshold, np.nan, (), (), False, False, "no generic load fits")

        reference = (float(sentinel.bic), (observed.before + sentinel.change)[observed.rows])
        every = _alternatives(problem, (), candidates, settings, reference=reference, effects=seen.effects,
                              places=places, in_bounds_only=True, pair_first=PAIR_FIRST)
        found = [(names, bic) for names, bic, margin in every if margin]
        possible = (seen_ and not found) or hidden
        with_form = (seen_ and not every) or hidden
        why = ("below the gap test" if not seen_ else
               f"{len(found)} vocabulary hypotheses fit as well as the generic load: {_names(found)}" if found else
               "only the generic load fits: unexplained is informative") + _by_construction(dataset, quiet)
        return Ceiling(seen_, norm, threshold, float(sentinel.bic), tuple(found), (), False, possible, why, possible,
                       with_form)
    values = dataset.get("values", {})
    change = problem.observe(problem.paths(truth, [np.atleast_1d(values[n]) for n in truth])) \
        - problem.observe(problem.base_paths)
    seen_, norm, threshold = detectable((change / problem.sigma)[problem.rows], settings.alpha)
    fit = truth_fit(problem, truth, values)
    beyond = group == "out_of_bounds"
    reference = (float(fit.bic), problem.observe(problem.paths(fit.names, fit.values))[problem.rows])
    every = _alternatives(problem, truth, candidates, settings, reference=reference, effects=seen.effects,
                          places=places, in_bounds_only=True, pair_first=PAIR_FIRST)
    found = [(names, bic) for names, bic, margin in every if margin]
    formed = [(names, bic) for names, bic, _ in every]
    groups = groups_of(truth, found)
    members = list(dict.fromkeys(m for g in groups for m in g if m != NOTHING))
    tie = False if beyond else _sentinel_tie(seen, observed, truth, members, float(fit.bic), settings)
    singles = [f for f in found if len(f[0]) == 1] if len(truth) == 1 else found  # pairs against a single: parsimony
    if beyond:  # informative is 'unexplained': the beyond-bound fit must beat every in-bounds hypothesis
        possible, parsimonious, with_form = seen_ and not found, seen_ and not singles, seen_ and not formed
        why = ("below the gap test" if not seen_ else
               f"{len(found)} in-bounds hypotheses fit as well as the truth beyond its bound: {_names(found)}"
               if found else "only a value beyond the bound fits: unexplained is informative")
    else:
        def small(gs):
            return all(len(g) <= GROUP_LIMIT and NOTHING not in g for g in gs)

        possible = (seen_ and small(groups) and not tie) or hidden
        lean = groups_of(truth, singles)
        lean_members = list(dict.fromkeys(m for g in lean for m in g if m != NOTHING))
        lean_tie = tie if lean_members == members else \
            _sentinel_tie(seen, observed, truth, lean_members, float(fit.bic), settings)
        parsimonious = (seen_ and small(lean) and not lean_tie) or hidden
        with_form = (seen_ and small(groups_of(truth, formed)) and not tie) or hidden
        size = max(len(g) for g in groups)
        parts = ([] if seen_ else ["below the gap test"]) + (["a generic load ties with the truth"] if tie else []) \
            + [f"smallest group {size}" + (f" ({_names(found)})" if found else "")]
        why = "; ".join(parts) + _by_construction(dataset, quiet)
    return Ceiling(seen_, norm, threshold, float(fit.bic), tuple(found), groups, tie, possible, why, parsimonious,
                   with_form)


def _by_construction(dataset: dict, quiet: bool) -> str:
    if dataset.get("detectable", True):
        return ""
    return " (below the noise by construction" + (": no gap on the data, nothing added is informative)" if quiet else
                                                  ", but the data show a gap)")


def _names(found, most: int = 6) -> str:
    text = ", ".join("+".join(n.split("@")[0] + ("@" + n.split("@")[1] if "@" in n else "") for n in names)
                     for names, _ in found[:most])
    return text + (f", … ({len(found)} in all)" if len(found) > most else "")


CLASSES = {"vocabulary": "one effect", "faint": "one effect (faint)", "pair": "pair",
           "out_of_vocabulary": "out of vocabulary", "out_of_bounds": "beyond bounds", "none": "none"}


def main() -> None:  # noqa: PLR0915
    import bench_discrepancy_blind as blind
    import blind_data

    import rvcoax
    from rvcoax.results.studies.discrepancy.workflow import DiscrepancySettings, _observe, build_library

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--source", choices=("hybrid", "calculix", "calculix_solid_full"), default="hybrid")
    parser.add_argument("--limit", type=int, default=None, help="a stratified subset of this many sets")
    parser.add_argument("--seed", type=int, default=0, help="seed of the subset")
    parser.add_argument("--ids", default="", help="only these set ids (comma-separated)")
    parser.add_argument("--docs", default="", help="the workflow's discrepancy.json documents kept by "
                        "bench_discrepancy_blind.py --keep (default: run the workflow here, no confidence draws)")
    parser.add_argument("--max-minutes", type=float, default=None, help="start no set after this many minutes")
    parser.add_argument("--save", default="", help="write every set's ceiling and the workflow's reading to this JSON "
                        "file (--summary reads it back)")
    parser.add_argument("--summary", default="", help="print (and record) the figures of a file written by --save, "
                        "without running anything")
    parser.add_argument("--what-if", action="store_true", help="which extra measurement would let the data carry "
                        "more: for every one-effect table of the source, data made by the identification model itself "
                        "(the truth's change at its true value, the file's noise level) as the table, the table with "
                        "three cases at other torque ratios, and a paths file, each given to the oracle")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    if args.what_if:
        _finish(what_if(args), args.source + ", what if", args.no_record)
        return
    if args.summary:
        saved = json.loads(Path(args.summary).read_text())
        rows = [(r["dataset"], Ceiling(**{k: tuple(tuple(g) if isinstance(g, list) else g for g in v)
                                          if isinstance(v, list) else v for k, v in r["ceiling"].items()}),
                 r["reading"], r["document"]) for r in saved["rows"]]
        rows = _hidden_again(rows, saved["source"], saved.get("version", ""))
        lines = summary(rows, saved["source"], saved["total"], saved["cpu_s"], saved["wall_s"])
        _finish(lines, saved["source"], args.no_record)
        return

    folder = blind.SOURCES[args.source][0]
    sets, _ = blind.load_sets(folder)
    if args.ids:
        sets = [s for s in sets if s["id"] in args.ids.split(",")]
    chosen = blind.stratified(sets, args.limit, args.seed)
    settings = DiscrepancySettings(confidence_draws=0)
    rigs = {datum: blind_data.identification_rig(datum) for datum in blind_data.DATUMS}
    libraries = {}
    rows = []
    cpu0, start = time.process_time(), time.perf_counter()
    for dataset in chosen:
        if args.max_minutes is not None and time.perf_counter() - start > 60 * args.max_minutes:
            print(f"stopped after {args.max_minutes:g} min: {len(rows)} of {len(chosen)} sets", flush=True)
            break
        rig = rigs[dataset["datum"]]
        if dataset["datum"] not in libraries:
            libraries[dataset["datum"]] = build_library(rig, blind_data.paper_cases(), settings.sweep)
        data = rvcoax.read_measured(folder / dataset["file"])
        t = time.process_time()
        seen = _observe(rig, data, settings, libraries[dataset["datum"]], None)
        ceiling = oracle(dataset, seen, settings)
        seconds = time.process_time() - t
        if args.docs:
            kept = Path(args.docs) / f"{dataset['id']}.json"
            document = json.loads(kept.read_text()) if kept.exists() else None
        else:
            result = rvcoax.run_discrepancy(rig, data, settings, library=libraries[dataset["datum"]])
            document = blind._document(result, rig)
        reading = blind.criteria(document, dataset) if document and "error" not in document else None
        rows.append((dataset, ceiling, reading, document))
        answer = "—" if reading is None else ("informative" if reading["informative"] else
                                              f"{document.get('verdict')}, not informative")
        print(f"{dataset['id']} {dataset['group']:17s} {dataset['schema']:5s} {100 * dataset['noise']:g}% "
              f"{','.join(dataset['truth']) or dataset['load'] or 'none':55s} oracle "
              f"{'possible' if ceiling.possible else 'not possible'} ({ceiling.why}; ‖s‖ {ceiling.norm_sigma:.3g} σ "
              f"of {ceiling.threshold:.3g}) | workflow {answer} [{seconds:.1f} s CPU]", flush=True)
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - start
    if args.save:
        Path(args.save).write_text(json.dumps({
            "version": VERSION, "source": args.source, "total": len(sets), "cpu_s": cpu, "wall_s": wall,
            "rows": [{"dataset": d, "ceiling": c.__dict__, "reading": r,
                      "document": {k: doc.get(k) for k in ("verdict", "selected")} if doc else None}
                     for d, c, r, doc in rows]}, default=_plain))
    _finish(summary(rows, args.source, len(sets), cpu, wall), args.source, args.no_record or not rows)


def _hidden_again(rows, source: str, saved_version: str):
    """Sets of a file saved by an earlier version, judged again where that version judged otherwise (the others as
    saved): the generic load compared as ``workflow._judge`` compares it, with the group the saved alternatives make
    (strict, and single effects alone), and a hidden change below the noise by construction counted as informative only
    where the data pass the gap test. The alternatives are not fitted again; the model-form variant keeps its saved
    value unless the strict group's generic load now ties."""
    from dataclasses import replace

    import bench_discrepancy_blind as blind
    import blind_data

    import rvcoax
    from rvcoax.results.studies.discrepancy.locate import gap_test
    from rvcoax.results.studies.discrepancy.workflow import DiscrepancySettings, _observe, build_library

    if saved_version == VERSION:
        return rows
    settings = DiscrepancySettings(confidence_draws=0)
    libraries, out = {}, []
    for dataset, ceiling, reading, document in rows:
        hidden_set = not dataset.get("detectable", True)
        if dataset["group"] in ("vocabulary", "faint", "pair") and (ceiling.possible or ceiling.parsimonious or hidden_set):
            rig = blind_data.identification_rig(dataset["datum"])
            if dataset["datum"] not in libraries:
                libraries[dataset["datum"]] = build_library(rig, blind_data.paper_cases(), settings.sweep)
            data = rvcoax.read_measured(blind.SOURCES[source][0] / dataset["file"])
            seen = _observe(rig, data, settings, libraries[dataset["datum"]], None)
            observed, truth = seen.observed, tuple(dataset["truth"])
            hidden = hidden_set and not gap_test(observed.scaled_before[observed.rows], settings.alpha).gap
            found = [(tuple(n), b) for n, b in ceiling.alternatives]
            singles = [f for f in found if len(f[0]) == 1] if len(truth) == 1 else found
            possible, tie = _judged_again(seen, ceiling, groups_of(truth, found), hidden, settings)
            parsimonious, _ = _judged_again(seen, ceiling, groups_of(truth, singles), hidden, settings)
            ceiling = replace(ceiling, possible=possible, parsimonious=parsimonious, generic=tie,
                              with_form=bool(ceiling.with_form) and (not tie or hidden))
        out.append((dataset, ceiling, reading, document))
    return out


def _judged_again(seen, ceiling: Ceiling, groups, hidden: bool, settings) -> tuple[bool, bool]:
    """(informative-possible, the generic load ties) of a saved ceiling with ``groups``."""
    truth = tuple(g[0] for g in groups)
    members = list(dict.fromkeys(m for g in groups for m in g if m != NOTHING))
    small = all(len(g) <= GROUP_LIMIT and NOTHING not in g for g in groups)
    tie = small and ceiling.detectable and _sentinel_tie(seen, seen.observed, truth, members, ceiling.truth_bic, settings)
    return (ceiling.detectable and small and not tie) or hidden, tie


def _plain(value):
    return value.tolist() if isinstance(value, np.ndarray) else float(value) if isinstance(value, np.floating) \
        else bool(value) if isinstance(value, np.bool_) else str(value)


def _finish(lines, source: str, no_record: bool) -> None:
    from machine import record

    print()
    for name, value in lines:
        print(f"{name}: {value}")
    if not no_record:
        record(f"bench_discrepancy_ceiling.py: what the blind data can carry ({source} data), the oracle's "
               "ceiling beside the workflow", lines)


def extra_cases(cases) -> tuple:
    """The cases an engineer adds to a table to change its torque ratio: T1 alone, T2 alone and both reversed, at the
    table's largest torques (the same new cases the workflow's observability report considers)."""
    from rvcoax.loadcases.cases import LoadCase

    t1 = max(abs(c.input_torque_Nm) for c in cases)
    t2 = max(abs(c.output_torque_Nm) for c in cases)
    return (LoadCase(t1, 0.0), LoadCase(0.0, t2), LoadCase(-t1, -t2))


def _made_data(library, truth: dict, schema: str, noise: float, seed: int):
    """Data of the identification model with ``truth`` (name → value) at the library's cases, noise σ = ``noise`` × RMS
    of each shaft's values (|Y_max| for a table)."""
    from dataclasses import replace

    import blind_data

    from rvcoax.geometry import MEASURED_SHAFTS
    from rvcoax.results.studies.discrepancy.responses import Observation
    from rvcoax.results.studies.discrepancy.synthetic import observation_layout

    template = observation_layout(library.cases, blind_data.STATIONS, blind_data.LENGTHS, schema)
    paths = library.base_paths + sum(library.responses[n].delta(np.atleast_1d(v)) for n, v in truth.items())
    values = Observation(template, library.layout)(paths)
    rms = {shaft: float(np.sqrt(np.mean(values[template.shaft == shaft] ** 2))) for shaft in MEASURED_SHAFTS}
    sigma = noise * np.array([rms[shaft] for shaft in template.shaft])  # as blind_data.noisy_observations
    noisy = values + np.random.default_rng(seed).normal(size=values.size) * sigma
    return replace(template, value_mm=np.abs(noisy) if schema == "table" else noisy, source="what-if")


def what_if(args) -> list[tuple[str, str]]:
    """The oracle on the same truths measured three ways (see ``--what-if``); returns the figures."""
    import bench_discrepancy_blind as blind
    import blind_data

    from rvcoax.results.studies.discrepancy.workflow import DiscrepancySettings, _observe, build_library

    sets, _ = blind.load_sets(blind.SOURCES[args.source][0])
    sets = [s for s in sets if s["group"] == "vocabulary" and s["schema"] == "table"]
    chosen = blind.stratified(sets, args.limit, args.seed)
    settings = DiscrepancySettings(confidence_draws=0)
    ways = {"table (the paper's 20 cases)": ("table", False), "table + T1 alone, T2 alone, both reversed": ("table", True),
            "paths file (11 stations per shaft, 20 cases)": ("paths", False)}
    libraries: dict = {}
    counts: dict = collections.defaultdict(collections.Counter)
    cpu0, start = time.process_time(), time.perf_counter()
    for dataset in chosen:
        rig = blind_data.identification_rig(dataset["datum"])
        outcome = []
        for way, (schema, extra) in ways.items():
            key = (dataset["datum"], extra)
            if key not in libraries:
                cases = blind_data.paper_cases()
                libraries[key] = build_library(rig, cases + extra_cases(cases) if extra else cases, settings.sweep)
            library = libraries[key]
            data = _made_data(library, dataset["values"], schema, dataset["noise"], int(dataset["id"]))
            ceiling = oracle(dict(dataset, schema=schema, detectable=True), _observe(rig, data, settings, library, None),
                             settings)
            counts[way]["n"] += 1
            counts[way]["possible"] += ceiling.possible
            counts[way]["detectable"] += ceiling.detectable
            counts[way]["group"] += ceiling.group_size if ceiling.detectable else 0
            outcome.append(f"{'possible' if ceiling.possible else 'not'} (group {ceiling.group_size})")
        print(f"{dataset['id']} {dataset['truth'][0]:45s} {100 * dataset['noise']:g}% " + " | ".join(outcome), flush=True)
    load = ", ".join(f"{v:.2f}" for v in os.getloadavg())
    lines = [("what if (data of the identification model, the truths of the one-effect tables)",
              f"{len(chosen)} truths of the {args.source} tables; CPU {(time.process_time() - cpu0) / 60:.1f} min, wall "
              f"{(time.perf_counter() - start) / 60:.1f} min, load average at the end {load}")]
    for way, c in counts.items():
        lines.append((f"what if, {way}", f"informative-possible {c['possible']}/{c['n']} "
                      f"({100 * c['possible'] / c['n']:.1f} %), detectable {c['detectable']}/{c['n']}, mean smallest "
                      f"group when detectable {c['group'] / max(c['detectable'], 1):.1f}"))
    return lines


def summary(rows, source: str, total: int, cpu: float, wall: float) -> list[tuple[str, str]]:
    load = ", ".join(f"{v:.2f}" for v in os.getloadavg())
    lines = [("data sets", f"{len(rows)} of {total} ({source}); oracle CPU {cpu / 60:.1f} min, wall {wall / 60:.1f} min, "
                           f"load average at the end {load}")]
    table: dict = collections.defaultdict(collections.Counter)
    for dataset, ceiling, reading, _ in rows:
        for key in (f"{dataset['schema']} all", f"{dataset['schema']} {CLASSES[dataset['group']]}"):
            table[key]["n"] += 1
            table[key]["possible"] += ceiling.possible
            table[key]["parsimonious"] += bool(ceiling.parsimonious)
            table[key]["with_form"] += bool(ceiling.with_form)
            table[key]["scored"] += reading is not None
            table[key]["informative"] += bool(reading and reading["informative"])
    for key in sorted(table, key=lambda k: (k.split()[0], not k.endswith(" all"), k)):
        c = table[key]
        lines.append((f"ceiling vs workflow, {key}", f"informative-possible {c['possible']}/{c['n']} "
                      f"({100 * c['possible'] / c['n']:.1f} %; pairs not counted against a single effect "
                      f"{100 * c['parsimonious'] / c['n']:.1f} %; the model-form clause counted too "
                      f"{100 * c['with_form'] / c['n']:.1f} %), workflow informative {c['informative']}/{c['scored']} "
                      f"({100 * c['informative'] / max(c['scored'], 1):.1f} %)"))
    sizes = [c.group_size for d, c, _, _ in rows if d["group"] in ("vocabulary", "faint") and c.detectable]
    for schema in ("paths", "table"):
        s = [c.group_size for d, c, _, _ in rows if d["group"] in ("vocabulary", "faint") and c.detectable
             and d["schema"] == schema]
        if s:
            lines.append((f"smallest honest group, one effect, detectable, {schema}",
                          f"median {np.median(s):g}, max {max(s)}; groups of 1: {s.count(1)}, ≤ 3: "
                          f"{sum(x <= 3 for x in s)} of {len(s)}"))
    del sizes
    twins: dict = collections.defaultdict(list)
    for d, c, _, _ in rows:
        if d["schema"] == "paths":
            twins[_twin(d)].append(c.possible)
    blocked = [d for d, c, _, _ in rows if d["schema"] == "table" and not c.possible and _twin(d) in twins]
    if blocked:
        lines.append(("tables where no honest rule is informative, whose paths twin is informative-possible (the same "
                      "values, datum and noise)", f"{sum(any(twins[_twin(d)]) for d in blocked)} of {len(blocked)}"))
    below = [(d, c, r, doc) for d, c, r, doc in rows if r is not None and c.possible and not r["informative"]]
    above = [(d, c, r, doc) for d, c, r, doc in rows if r is not None and not c.possible and r["informative"]]
    lines.append(("workflow below the oracle (informative possible, not given)",
                  f"{len(below)}: " + "; ".join(_miss(d, c, doc) for d, c, _, doc in below)))
    loose = [d for d, c, r, _ in rows if r is not None and c.parsimonious and not c.possible and not r["informative"]]
    lines.append(("workflow below the oracle only when pairs do not count against a single effect",
                  f"{len(loose)}: " + ", ".join(f"{d['id']} ({CLASSES[d['group']]}, {d['schema']})" for d in loose)))
    lines.append(("workflow above the oracle (informative although the oracle says impossible)",
                  f"{len(above)}: " + "; ".join(_miss(d, c, doc) for d, c, _, doc in above)))
    beyond = [(d, c, r, doc) for d, c, r, doc in rows if r is not None and not c.parsimonious and r["informative"]]
    lines.append(("workflow above even the oracle that does not count pairs against a single effect",
                  f"{len(beyond)}: " + "; ".join(_miss(d, c, doc) for d, c, _, doc in beyond)))
    return lines


def _twin(dataset: dict) -> tuple:
    """What a paths file and a table of the same hidden truth share (the same values, datum and noise)."""
    values = tuple(sorted((k, float(f"{v:.6g}")) for k, v in dataset.get("values", {}).items()))
    return dataset["group"], tuple(dataset["truth"]), dataset["load"], dataset["datum"], dataset["noise"], values


def _miss(dataset: dict, ceiling: Ceiling, document: dict) -> str:
    selected = document.get("selected") or []
    said = ", ".join(f"{e['effect']}[{len(e.get('group') or [e['effect']])}]" for e in selected)
    return (f"{dataset['id']} ({CLASSES[dataset['group']]}, {dataset['schema']}, "
            f"{','.join(dataset['truth']) or dataset['load'] or 'none'}): oracle {ceiling.why}; workflow "
            f"{document.get('verdict')} {said}")


if __name__ == "__main__":
    main()
