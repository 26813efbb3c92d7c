"""The discrepancy workflow from measured data to an updated rig file (pure functions).

Five stages, each a function passing a small frozen record to the next:

1. **observe** (:class:`Seen`): σ, the rows to fit, the base model factorised once and every candidate effect's
   response on it (:mod:`engine`, :mod:`responses`), what these data can reveal of each (:mod:`observability`)
   and which candidates look alike on them;
2. **locate** (:class:`Located`): the χ² test of the gap and its structure (:mod:`locate`), the best generic load
   (:mod:`sentinel`);
3. **screen**: forward selection with backward pruning by BIC on the responses (:mod:`identify`), until the
   verdict's own gap test finds no gap;
4. **refine** (:class:`Named`): the screened effects fitted again with the true model (no response interpolation,
   no additivity assumption); a candidate that cannot be solved is set aside and the screen runs again;
5. **judge** (:class:`DiscrepancyResult`): each effect with its look-alikes and the measurements that tell them
   apart, the tests after, the cross-validation and the verdict (:mod:`judge`): ``no_gap``, ``explained`` or
   ``unexplained``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from scipy import stats
from scipy.optimize import least_squares

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.effects import candidate_effects
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.studies.discrepancy.ambiguity import Ambiguity, ambiguities
from rvcoax.results.studies.discrepancy.confidence import Confidence, verdict_confidence
from rvcoax.results.studies.discrepancy.engine import CANDIDATE_FAILURES, Engine, prepare_engine, rig_is_linear
from rvcoax.results.studies.discrepancy.identify import Fit, Problem, Step, forward_backward
from rvcoax.results.studies.discrepancy.judge import (
    STRUCTURE_T,
    fighting_pairs,
    load_regions,
    load_x,
    look_alike_places,
    opposite_loads,
    verdict,
)
from rvcoax.results.studies.discrepancy.locate import (
    GapTest,
    NoiseEstimate,
    detection_norm,
    estimate_noise,
    gap_test,
    residual_structure,
)
from rvcoax.results.studies.discrepancy.lookalikes import exact_fit
from rvcoax.results.studies.discrepancy.measured import MeasuredData, check_stations
from rvcoax.results.studies.discrepancy.observability import (
    VISIBLE_NORM,
    Suggestion,
    Visibility,
    direction,
    discriminate,
    observability,
    parallel_groups,
)
from rvcoax.results.studies.discrepancy.observed import Observed
from rvcoax.results.studies.discrepancy.responses import (
    EffectResponse,
    Observation,
    PathLayout,
    engine_response,
    solve_full_paths,
)
from rvcoax.results.studies.discrepancy.sentinel import (
    CrossValidation,
    SentinelFit,
    case_folds,
    cross_validate,
    fit_sentinel,
    sentinel_columns,
    site_in,
)
from rvcoax.results.sweep import SweepSettings

__all__ = ["CANDIDATE_FAILURES", "CASE_CANDIDATE_BYTES", "CASE_CANDIDATE_S", "NONLINEAR_CASE_CANDIDATE_S", "CandidateLibrary", "DiscrepancyResult", "DiscrepancySettings",
           "Discrimination", "OBSERVABLE_SIGMA", "OBSERVATION_BYTES", "OBSERVATION_S", "SelectedEffect",
           "build_library", "discrepancy_workload", "held_out_mask", "run_discrepancy"]

OBSERVABLE_SIGMA = 0.5  # kept for callers; observability now uses the signature's norm (VISIBLE_NORM)
# measured costs (2-core AMD EPYC dev machine, loaded): the reference table (20 cases, 57 candidates) takes 6 s
# end to end on one factorisation, ≈ 6 ms per case and candidate (it took 65 s with one sweep per candidate);
# per observation 20 µs to parse and 5.3 µs per observation-operator build, built about 100 times per run
# (each true-model evaluation of the refit): a 20,000-row paths file, results/studies/discrepancy/responses.py
# Re-measured (issue 24) with synthetic paths and table files of 250 and 500 cases, 57 candidates, load 9–11 on 2
# cores, CPU time: a case costs 0.087 ms and 23 kB per candidate (9 kB once grid candidates keep unit paths), a paths-file
# row 0.21 ms and 5.6 kB once the observation operator is built once per layout and the sentinel scan keeps its
# normal equations, not rows × sites × parts (benchmarks/RESULTS.md, 2026-11-26). The end-to-end figure below
# (fixed costs included) is kept for the case term: it overstates large files, never understates small ones.
CASE_CANDIDATE_S = 0.006
# on a nonlinear rig (ball bearings, clearances) every candidate is solved by real Newton sweeps, at its bound and on
# a coarse grid: the reference rig with ball bearings and the paper's table (20 cases, 57 candidates) took 121 s on
# the same machine (load average 3–5), ≈ 0.11 s per case and candidate
NONLINEAR_CASE_CANDIDATE_S = 0.11
OBSERVATION_S = 0.21e-3
# memory: a candidate keeps its change of every case's paths on a grid (12 × 82 stations × 8 bytes per case, and
# the observed values and copies the fits make: 9 kB measured); a row keeps its observed responses and fits
CASE_CANDIDATE_BYTES = 9e3
OBSERVATION_BYTES = 5.6e3


@dataclass(frozen=True)
class DiscrepancySettings:
    """Settings of the workflow (margins are in BIC units; fractions are of the signal)."""

    sweep: SweepSettings = SweepSettings()
    alpha: float = 0.01
    bic_margin: float = 10.0
    ambiguity_margin: float = 6.0
    parallel_cosine: float = 0.98
    model_form_fraction: float = 0.02
    hold_out_every: int = 3
    max_effects: int = 4
    max_rounds: int = 1  # kept for callers: one round on the factorised base model
    candidates: tuple[str, ...] | None = None  # effect names or kinds; None: the whole library
    confidence_draws: int = 160  # synthetic data sets of the confidence estimate (:mod:`confidence`); 0: none


@dataclass(frozen=True)
class CandidateLibrary:
    """Responses of every candidate effect around one rig, for one set of load cases."""

    rig: object
    cases: tuple[LoadCase, ...]
    base_paths: np.ndarray
    layout: PathLayout
    responses: dict[str, EffectResponse]
    failed: dict[str, str] = field(default_factory=dict)
    engine: Engine | None = None


def build_library(rig, cases, settings: SweepSettings, names: tuple[str, ...] | None = None, *,  # noqa: PLR0913
                  progress=None, visible=None, engine: Engine | None = None) -> CandidateLibrary:
    """The base rig factorised once and every candidate's response on it (:mod:`engine`).

    ``progress(i, n)`` is called after each candidate; ``visible(delta_full_paths)`` (optional) tells
    whether a nonlinear candidate that must be solved case by case is worth a grid (else only its bound)."""
    cases = tuple(cases)
    engine = engine if engine is not None and engine.rig is rig else prepare_engine(rig, settings)
    if engine.linear:
        base_paths, layout = engine.full_paths(engine.unit_paths, cases), engine.layout(len(cases))
    else:
        base_paths, layout = solve_full_paths(rig, cases, settings)
    effects = [e for e in candidate_effects(rig) if names is None or e.name in names or e.kind in names]
    responses, failed = {}, {}
    for done, effect in enumerate(effects, start=1):
        if progress is not None:
            progress(done - 1, len(effects))
        try:
            responses[effect.name] = engine_response(effect, engine, cases, visible)
        except CANDIDATE_FAILURES as error:  # e.g. a clearance that leaves a part without support
            failed[effect.name] = f"cannot be solved over its physical range: {error}"
    if progress is not None:
        progress(len(effects), len(effects))
    return CandidateLibrary(rig=rig, cases=cases, base_paths=base_paths, layout=layout, responses=responses, failed=failed, engine=engine)


@dataclass(frozen=True)
class SelectedEffect:
    """An effect added to the rig, with its fitted values and the BIC gain when it was added."""

    name: str
    values: tuple[float, ...]
    delta_bic: float
    group: tuple[str, ...]
    round: int
    confident: bool = False
    pair_members: tuple[str, ...] = ()  # members of ``group`` that only a pair fitting as well brought in (ambiguous)

    def parameters(self, effect) -> dict:
        """Per parameter: its value, unit, bounds, and ``at_bound`` (``lower`` or ``upper`` when the fit sits on a
        bound, pushed against it; else None)."""
        return {p.name: {"value": float(v), "unit": p.unit, "bounds": [p.lower, p.upper], "at_bound": at_bound(p, v)}
                for p, v in zip(effect.parameters, self.values)}


def at_bound(parameter, value: float) -> str | None:
    """``lower`` or ``upper`` when ``value`` sits on that physical bound of ``parameter`` (within 0.1 % of its range,
    where a bounded fit that is pushed against it stops), else None."""
    tolerance = 1e-3 * (parameter.upper - parameter.lower)
    if value <= parameter.lower + tolerance:
        return "lower" if parameter.lower != 0.0 else None  # a zero bound is "nothing": no push
    if value >= parameter.upper - tolerance:
        return "upper"
    return None


@dataclass(frozen=True)
class PairSearch:
    """A pair searched before a single effect at an implausible size, or with structure left, was accepted.

    ``single`` and ``single_value`` are the effect the screen named alone and its size; ``pair`` the two effects
    fitted together instead (None when no pair fitted better), ``correlation`` the correlation of their two fitted
    sizes (−cos of their signatures: near ±1 the data trade one for the other), ``why`` what prompted the search."""

    single: str
    single_value: float
    single_bic: float
    why: str
    pair: tuple[str, str] | None = None
    pair_values: tuple[float, float] | None = None
    pair_bic: float | None = None
    correlation: float | None = None


@dataclass(frozen=True)
class Discrimination:
    """The measurement that best tells two members of a group apart."""

    effects: tuple[str, str]
    case: LoadCase
    shaft: str
    x_mm: float
    difference_mm: float
    in_sigma: float
    new_case: bool
    other_datum: bool = False


@dataclass(frozen=True, eq=False, kw_only=True)
class DiscrepancyResult:
    """What :func:`run_discrepancy` found.

    Attributes
    ----------
    verdict : str
        ``no_gap`` (no gap beyond the noise before any effect), ``explained`` (effects were selected and no
        gap remains on the fitted rows) or ``unexplained``.
    data : MeasuredData
        The measurements.
    noise : NoiseEstimate
        The measurement noise σ used by the gap tests.
    fit_mask : ndarray of bool
        The observations used to fit; the others are held out.
    before, after : ndarray
        The model's value of every observation (mm) without and with the selected effects.
    test_before, test_after, test_after_held_out : GapTest
        χ² tests of the gap before, after (fitted rows) and after on the held-out rows.
    structure : list of StructureFinding
        Tests of the residual before any effect, along the sweep and along the shaft.
    selected : tuple of SelectedEffect
        The effects added, with their fitted values and ΔBIC.
    steps : tuple of Step
        The forward/backward selection, step by step.
    not_observable, rejected, set_aside : dict
        Candidate → why it could not be seen in these data, was not selected, or could not be solved.
    discriminations : tuple of Discrimination
        For pairs of candidates that explain the data alike: the measurement that best tells them apart.
    rig_before, rig_after : Rig
        The rig as modelled, and with the selected effects added.
    effects : dict
        Candidate name → its effect definition.
    """

    verdict: str
    data: MeasuredData
    noise: NoiseEstimate
    fit_mask: np.ndarray
    before: np.ndarray
    after: np.ndarray
    test_before: GapTest
    test_after: GapTest
    test_after_held_out: GapTest | None
    structure: list
    selected: tuple[SelectedEffect, ...]
    steps: tuple[Step, ...]
    not_observable: dict[str, str]
    rejected: dict[str, str]
    set_aside: dict[str, str]
    discriminations: tuple[Discrimination, ...]
    rig_before: object
    rig_after: object
    effects: dict = field(default_factory=dict)
    observability: dict[str, Visibility] = field(default_factory=dict)
    parallel_groups: tuple[tuple[str, ...], ...] = ()
    sentinel: SentinelFit | None = None
    cross_validation: CrossValidation | None = None
    sentinel_cross_validation: CrossValidation | None = None
    reasons: tuple[str, ...] = ()
    vocabulary_chi2: float | None = None
    sentinel_elsewhere: SentinelFit | None = None
    sentinel_at: tuple[str, ...] = ()
    ambiguities: tuple[Ambiguity, ...] = ()
    pair_search: PairSearch | None = None
    beyond_bounds: tuple[str, ...] = ()
    confidence: Confidence | None = None

    @property
    def verdict_sentinel(self) -> SentinelFit | None:
        """The generic load the verdict compared the vocabulary with: the best one, or, when that one acts where a
        named effect already puts its load (``sentinel_at``), the best one away from there."""
        return self.sentinel_elsewhere if self.sentinel_at else self.sentinel

    def rms_mm(self, which: str, rows: np.ndarray | None = None) -> dict[str, float]:
        """RMS of measured − model per shaft (``which`` = before | after) over ``rows`` (default all)."""
        residual = self.data.value_mm - (self.before if which == "before" else self.after)
        rows = np.ones(self.data.n, bool) if rows is None else rows
        return {s: float(np.sqrt(np.mean(residual[(self.data.shaft == s) & rows] ** 2)))
                for s in MEASURED_SHAFTS if ((self.data.shaft == s) & rows).any()}

    def rms_tilt_urad(self, which: str, rows: np.ndarray | None = None, lengths_mm: dict | None = None) -> dict:
        """RMS tilt gap per shaft in µrad: β = arcsin(Y/L) (table) or the least-squares slope (paths)."""
        model = self.before if which == "before" else self.after
        rows = np.ones(self.data.n, bool) if rows is None else rows
        out = {}
        for shaft in MEASURED_SHAFTS:
            gaps = []
            for case in np.unique(self.data.case_index[rows]):
                mask = rows & (self.data.shaft == shaft) & (self.data.case_index == case)
                if not mask.any():
                    continue
                if self.data.schema == "table":
                    length = lengths_mm[shaft]
                    gaps.append(np.arcsin(np.clip(self.data.value_mm[mask][0] / length, -1, 1))
                                - np.arcsin(np.clip(model[mask][0] / length, -1, 1)))
                elif mask.sum() >= 2 and np.ptp(self.data.x_mm[mask]) > 0:
                    gaps.append(np.polyfit(self.data.x_mm[mask], self.data.value_mm[mask] - model[mask], 1)[0])
            if gaps:
                out[shaft] = float(1e6 * np.sqrt(np.mean(np.square(gaps))))
        return out


def discrepancy_workload(data: MeasuredData, n_candidates: int, rig=None):
    """The estimated time and memory of :func:`run_discrepancy` on ``data`` with ``n_candidates`` candidates.

    Parameters
    ----------
    data : MeasuredData
        The measurements (:func:`read_measured`).
    n_candidates : int
        Candidate effects to solve.
    rig : Rig, optional
        The rig: on a nonlinear one (ball bearings, clearances) each candidate is solved by real sweeps, not on
        one factorisation (default: a linear rig).

    Returns
    -------
    Workload
        Estimated time and memory, to check or announce before the run.
    """
    from rvcoax.geometry.model.workload import BASE_BYTES, Workload, count_text

    cases = len(data.cases)
    per = CASE_CANDIDATE_S if rig is None or rig_is_linear(rig) else NONLINEAR_CASE_CANDIDATE_S
    seconds = per * cases * max(n_candidates, 1) + OBSERVATION_S * data.n
    return Workload(f"{count_text(data.n)} observations in {count_text(cases)} load cases × {n_candidates} "
                    "candidate effects", seconds,
                    BASE_BYTES + OBSERVATION_BYTES * data.n + CASE_CANDIDATE_BYTES * cases * max(n_candidates, 1))


def held_out_mask(data: MeasuredData, every: int) -> np.ndarray:
    """True for observations of the cases used to fit; every ``every``-th case (by torque) is held out.

    The lightest and heaviest cases always stay in the fit. ``every`` = 0 fits on all cases.
    """
    n_cases = len(data.cases)
    if every <= 1 or n_cases < 2 * every:
        return np.ones(data.n, bool)
    order = sorted(range(n_cases), key=lambda i: (abs(data.cases[i].output_torque_Nm),
                                                   abs(data.cases[i].input_torque_Nm)))
    held = {order[i] for i in range(every - 1, n_cases - 1, every)}
    return np.array([c not in held for c in data.case_index])


def _applied(rig, effects_by_name, selected) -> object:
    for name, values in selected:
        rig = effects_by_name[name].apply(rig, list(values))
    return rig


def _true_paths(rig, effects_by_name, fits, cases, *, settings: SweepSettings, engine: Engine | None):  # noqa: PLR0913
    """Full paths of ``rig`` with the effects ``fits`` applied: exact on the factorisation when the engine
    solves every one of them, else a real sweep."""
    if engine is not None and engine.rig is rig and engine.linear and len(fits) == 1 \
            and effects_by_name[fits[0][0]].response == "clearance":
        (name, values), = fits
        return (engine.clearance_paths(effects_by_name[name].location, float(np.atleast_1d(values)[0]), cases),
                engine.layout(len(cases)))
    if engine is not None and engine.rig is rig and all(engine.supports(effects_by_name[n]) for n, _ in fits):
        change = engine.unit_change([(effects_by_name[n], list(v)) for n, v in fits])
        return engine.full_paths(engine.unit_paths + change, cases), engine.layout(len(cases))
    return solve_full_paths(_applied(rig, effects_by_name, fits), cases, settings)


# ---- the stages and what passes between them -------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class Seen:
    """The observe stage: the data as the base model sees them, and which candidates they can reveal.

    ``responses`` are the visible candidates that could be evaluated; ``groups`` the look-alikes among them (nearly
    parallel signatures on these data, independent of the noise level); ``set_aside`` the candidates that could not
    be solved, with the reason."""

    rig: object
    observed: Observed
    noise: NoiseEstimate
    library: CandidateLibrary
    effects: dict
    visibility: dict[str, Visibility]
    responses: dict[str, EffectResponse]
    groups: tuple[tuple[str, ...], ...]
    set_aside: dict[str, str]

    @property
    def not_observable(self) -> dict[str, str]:
        return {n: v.reason for n, v in self.visibility.items() if not v.visible}


@dataclass(frozen=True, eq=False)
class Located:
    """The locate stage: whether there is a gap, its structure, and the best generic load (the sentinel)."""

    test_before: GapTest
    structure: list
    folds: list
    sentinel: SentinelFit | None
    sentinel_cv: CrossValidation | None
    set_aside: dict[str, str]


@dataclass(frozen=True, eq=False)
class Named:
    """The screen and refine stages: the effects added, fitted again with the true model, and the model with them."""

    problem: Problem
    steps: tuple[Step, ...]
    fitted: tuple[tuple[str, np.ndarray], ...]
    after: np.ndarray
    set_aside: dict[str, str]
    pair_search: PairSearch | None = None


def _observe(rig, data: MeasuredData, settings: DiscrepancySettings, library: CandidateLibrary | None,
             progress) -> Seen:
    """σ, the rows to fit, the base model's predictions (one factorisation), every candidate's response, and what
    these data can reveal of each (:mod:`observability`)."""
    from_rest = rig.paths.measured_from == "aligned_at_rest"
    noise = estimate_noise(data, settings.model_form_fraction)
    sigma = noise.sigma_mm
    observe_of = _observation_factory(data)

    def visible(delta):
        base = observe(library_base)
        return bool(np.linalg.norm((observe(library_base + delta) - base) / sigma) >= VISIBLE_NORM)

    if library is None or library.rig is not rig or library.cases != tuple(data.cases):
        engine = prepare_engine(rig, settings.sweep)
        check_stations(data, engine.length_mm)
        observe = observe_of(engine.layout(len(data.cases)))
        library_base = (engine.full_paths(engine.unit_paths, data.cases) if engine.linear
                        else solve_full_paths(rig, data.cases, settings.sweep)[0])
        library = build_library(rig, data.cases, settings.sweep, settings.candidates, progress=progress,
                                visible=visible, engine=engine)
    else:
        check_stations(data, library.layout.length_mm)
        observe = observe_of(library.layout)
        library_base = library.base_paths
    observed = Observed(data=data, sigma=sigma, base_paths=library.base_paths, observe=observe, rows=held_out_mask(data, settings.hold_out_every),
                        from_rest=from_rest, engine=library.engine, noise=noise)
    set_aside: dict[str, str] = dict(library.failed)
    seen = {}
    for name, response in library.responses.items():
        try:
            seen.update(observability({name: response}, observed) if observed.engine is not None else {})
        except CANDIDATE_FAILURES as error:
            set_aside[name] = f"its signature cannot be evaluated: {error}"
    responses = {n: r for n, r in library.responses.items()
                 if not (n in seen and not seen[n].visible) and n not in set_aside}
    directions = {n: direction(r, observed, observed.rows) for n, r in responses.items()}
    groups = tuple(tuple(g) for g in parallel_groups(directions, settings.parallel_cosine))
    return Seen(rig=rig, observed=observed, noise=noise, library=library,
                effects={e.name: e for e in candidate_effects(rig)}, visibility=seen, responses=responses,
                groups=groups, set_aside=set_aside)


def _locate(seen: Seen, settings: DiscrepancySettings) -> Located:
    """The χ² test of the gap, its structure, and the best generic load with its cross-validation."""
    observed = seen.observed
    data, sigma, before = observed.data, observed.sigma, observed.before
    test_before = gap_test(observed.scaled_before, settings.alpha, observed.dof())  # every row, as the test after the fit
    structure = residual_structure(data, data.value_mm - before, sigma,
                                   model_form_fraction=settings.model_form_fraction)
    folds = case_folds(data)
    set_aside = dict(seen.set_aside)
    sentinel = sentinel_cv = None
    if observed.engine is not None and test_before.gap:
        try:  # the sentinel, like any candidate, never ends the run
            sentinel = fit_sentinel(observed)
            sentinel_cv = _sentinel_cv(sentinel, observed, folds)
        except CANDIDATE_FAILURES as error:
            set_aside["sentinel"] = f"the generic load could not be fitted: {error}"
    return Located(test_before=test_before, structure=structure, folds=folds, sentinel=sentinel,
                   sentinel_cv=sentinel_cv, set_aside=set_aside)


def _screen(problem: Problem, candidates: list[str], observed: Observed, settings: DiscrepancySettings):
    """Forward selection with backward pruning on the responses, until the verdict's own gap test finds no gap."""
    data, sigma = observed.data, observed.sigma

    def no_gap_left(fit: Fit) -> bool:
        # the same test as the verdict's: every row, the held-out ones predicted by the fit on the others
        scaled = (data.value_mm - observed.observe(problem.paths(fit.names, fit.values))) / sigma
        return stats.chi2.sf(float(scaled @ scaled), scaled.size) >= settings.alpha

    return forward_backward(problem, candidates, margin=settings.bic_margin,
                            ambiguity_margin=settings.ambiguity_margin, parallel_cosine=settings.parallel_cosine,
                            max_effects=settings.max_effects, stop=no_gap_left)


def _refine(seen: Seen, trial: list, settings: SweepSettings):
    """The screening fit confirmed with the true model: exact for linear effects on a linear rig, else fitted again
    (no response interpolation, no additivity assumption)."""
    observed, engine = seen.observed, seen.library.engine
    observe_of = _observation_factory(observed.data)
    if all(seen.library.responses[n].kind == "linear" for n, _ in trial):
        paths, layout = _true_paths(seen.rig, seen.effects, trial, observed.data.cases, settings=settings,
                                    engine=engine)
        return trial, observe_of(layout)(paths)
    names = [name for name, _ in trial]
    sizes = [seen.effects[n].parameters for n in names]
    x0 = np.concatenate([np.atleast_1d(v) for _, v in trial])
    lower = np.array([p.lower for ps in sizes for p in ps], float)
    upper = np.array([p.upper for ps in sizes for p in ps], float)
    scale = np.array([max(abs(p.typical), 1e-12) for ps in sizes for p in ps])
    splits = np.cumsum([len(ps) for ps in sizes])[:-1]

    def predicted(x):
        paths, layout = _true_paths(seen.rig, seen.effects, list(zip(names, np.split(x, splits))),
                                    observed.data.cases, settings=settings, engine=engine)
        return observe_of(layout)(paths)

    def residual(x):
        return ((observed.data.value_mm - predicted(x)) / observed.sigma)[observed.rows]

    x0 = np.clip(x0, lower, upper)
    result = least_squares(residual, x0, bounds=(lower, upper), x_scale=scale, diff_step=1e-4, max_nfev=40,
                           xtol=1e-8, ftol=1e-10)
    return list(zip(names, np.split(result.x, splits))), predicted(result.x)


def _name(seen: Seen, located: Located, settings: DiscrepancySettings) -> Named:
    """Screen and refine until the true model confirms the screening fit (a candidate that fails is set aside)."""
    observed = seen.observed
    problem = Problem(observed.data.value_mm, observed.sigma, observed.base_paths, observed.observe, seen.responses,
                      rows=observed.rows)
    set_aside = dict(located.set_aside)
    fitted, after, steps, searched = [], observed.before, [], None
    while located.test_before.gap:
        try:
            screening, steps = _screen(problem, [n for n in seen.responses if n not in set_aside], observed, settings)
        except CANDIDATE_FAILURES as error:  # a response that cannot be evaluated: never ends the run
            set_aside["(screening)"] = f"the screening fit failed: {error}"
            screening, steps = Fit((), (), 0.0, 0), []
        if not screening.names:
            break
        searched = _pair_search(problem, screening, steps, seen, settings) if len(screening.names) == 1 else None
        if searched is not None and searched.pair is not None:
            screening, steps = _with_pair(problem, searched, steps)
        try:
            fitted, after = _refine(seen, list(zip(screening.names, screening.values)), settings.sweep)
        except CANDIDATE_FAILURES as error:
            for name in screening.names:
                set_aside[name] = f"the fit with it cannot be solved with the true model: {error}"
            continue
        break
    return Named(problem=problem, steps=tuple(steps), fitted=tuple(fitted), after=after, set_aside=set_aside,
                 pair_search=searched if fitted else None)


# a single effect at three quarters of its physical bound or more is an implausible size (at half the bound the pair
# search also replaced true single effects, a bearing at a quarter of its stiffness in CalculiX data, by a pair that
# absorbed the model form)
IMPLAUSIBLE_FRACTION = 0.75
PAIR_POOL = 8  # the best single candidates of the first step, paired with each other


def _pair_search(problem: Problem, single: Fit, steps, seen: Seen, settings: DiscrepancySettings) -> PairSearch | None:
    """Before a single effect at an implausible size (three quarters of its physical bound or more) is accepted, every
    pair of the best single candidates is fitted; the best pair replaces it when it fits better by the ambiguity
    margin (the structure the single leaves, along the sweep or the shaft, is reported with it)."""
    name, value = single.names[0], float(np.atleast_1d(single.values[0])[0])
    p = seen.effects[name].parameters[0]
    bound = p.upper if value > 0 else p.lower
    if not (bound != 0.0 and value / bound >= IMPLAUSIBLE_FRACTION):  # a plausible size: no search
        return None
    observed = seen.observed
    residual = observed.data.value_mm - observed.observe(problem.paths(single.names, single.values))
    structure = [f for f in residual_structure(observed.data, residual, observed.sigma, threshold=STRUCTURE_T,
                                               model_form_fraction=settings.model_form_fraction) if f.significant]
    why = (f"{name} alone at {value:.4g} {p.unit}, {100 * value / bound:.0f} % of its bound {bound:g} {p.unit}"
           + (f", leaving structure ({structure[0].shaft} shaft: {structure[0].test})" if structure else ""))
    found = PairSearch(name, value, float(single.bic), why)
    pool = list(dict.fromkeys([name] + [n for n, _ in steps[0].ranking[:PAIR_POOL]])) if steps else [name]
    need = settings.ambiguity_margin
    best = None
    for i, a in enumerate(pool):
        for b in pool[i + 1:]:
            try:
                fit = problem.fit((a, b))
            except CANDIDATE_FAILURES:
                continue
            if fit.rejected is None and fit.bic < single.bic - need and (best is None or fit.bic < best.bic):
                best = fit
    if best is None:
        return found
    a, b = best.names
    sa = problem.signature(a, np.atleast_1d(best.values[0]))
    sb = problem.signature(b, np.atleast_1d(best.values[1]))
    cosine = float(sa @ sb / (np.linalg.norm(sa) * np.linalg.norm(sb))) if np.any(sa) and np.any(sb) else 0.0
    signs = np.sign(float(np.atleast_1d(best.values[0])[0]) * float(np.atleast_1d(best.values[1])[0])) or 1.0
    return replace(found, pair=(a, b), pair_values=tuple(float(np.atleast_1d(v)[0]) for v in best.values),
                   pair_bic=float(best.bic), correlation=float(-cosine * signs))


def _with_pair(problem: Problem, searched: PairSearch, steps) -> tuple[Fit, list[Step]]:
    """The screening fit and steps with the pair found by :func:`_pair_search` in place of the single effect."""
    pair = problem.fit(searched.pair)
    first = steps[0] if steps else None
    kept = [s for s in steps if s.added in searched.pair]
    for name in searched.pair:
        if not any(s.added == name for s in kept):
            kept.append(Step(name, float(searched.single_bic - pair.bic), (name,), pair,
                             ranking=first.ranking if first is not None else ()))
    return pair, kept


def _discriminations(pairs, seen: Seen) -> list[Discrimination]:
    """For each pair of look-alikes: the station and case where their predictions differ most."""
    out = []
    for first, other in pairs:
        found = discriminate(seen.library.responses[first], seen.library.responses[other], seen.observed) \
            if seen.library.engine is not None else None
        if found is not None:
            out.append(_as_discrimination((first, other), found))
    return out


def _as_discrimination(pair, found: Suggestion) -> Discrimination:
    return Discrimination(effects=pair, case=found.case, shaft=found.shaft, x_mm=found.x_mm, difference_mm=1e-3 * found.change_um, in_sigma=found.in_sigma,
                          new_case=found.new_case, other_datum=found.other_datum)


def _confirmed(problem: Problem, fit: Fit, name: str, seen: Seen) -> tuple[float, np.ndarray]:
    """(BIC, predicted observations) of ``fit``, with ``name`` solved exactly when it is a clearance the screen read off
    its interpolated response (:func:`lookalikes.exact_fit`)."""
    exact = exact_fit(problem, fit, name, effect=seen.effects[name], observed=seen.observed)
    if exact is None:
        return fit.bic, problem.observe(problem.paths(fit.names, fit.values))
    return exact[0] + fit.k * np.log(max(fit.n, 2)), exact[1]


def _fits_as_well(seen: Seen, named: Named, name: str, member: str, settings: DiscrepancySettings) -> bool:
    """Whether ``member`` in place of ``name`` (with the other effects added, within its physical bounds) explains the
    data as well as the selection: its BIC within the ambiguity margin of the selection's, or its predictions within the
    model-form allowance of the selection's (RMS of their difference at most that fraction of the RMS signal on the
    rows used to fit: the identification model itself is trusted no closer, so a difference smaller than that does not
    tell them apart, whatever the χ² says) and below the gap test's detection rule (the norm of their difference in σ
    of the rows used to fit, :func:`locate.detection_norm`: σ already holds the model-form allowance of each row, so a
    difference the gap test would find as a gap is one the data see, wherever along the sweep it lies, however small
    beside the largest readings). A look-alike that the data tell apart is not in the group, however parallel its
    signature. A clearance read off its interpolated response is confirmed with its exact law on the factorisation
    (:func:`lookalikes.exact_fit`), not the spline between its grid values."""
    problem, names = named.problem, tuple(n for n, _ in named.fitted)
    start = dict(named.fitted)
    try:
        current = problem.fit(names, start)
        trial = problem.fit(tuple(n for n in names if n != name) + (member,), start)
    except CANDIDATE_FAILURES:
        return True  # cannot tell: keep it in the group
    if trial.rejected is not None:
        return False
    current_bic, current_predicted = _confirmed(problem, current, name, seen)
    trial_bic, trial_predicted = _confirmed(problem, trial, member, seen)
    if trial_bic - current_bic < settings.ambiguity_margin:
        return True
    rows = problem.rows
    difference = (trial_predicted - current_predicted)[rows]
    within_model_form = np.linalg.norm(difference) <= settings.model_form_fraction * np.linalg.norm(seen.observed.before[rows])
    seen_by_the_test = np.linalg.norm(difference / problem.sigma[rows]) >= detection_norm(rows.size, settings.alpha)
    return bool(within_model_form and not seen_by_the_test)


def _earns_beside(named: Named, member: str) -> bool:
    """Whether ``member`` added beside the final selection earns its parameter (the BIC with it lower than without,
    within its physical bounds: the criterion by which :func:`_pairs_as_well` takes a pair's second member): the data
    cannot exclude it as a companion of the named effects."""
    problem, names = named.problem, tuple(n for n, _ in named.fitted)
    if member in names:
        return False
    start = dict(named.fitted)
    try:
        current, trial = problem.fit(names, start), problem.fit(names + (member,), start)
    except CANDIDATE_FAILURES:
        return True  # cannot tell: keep it in the group
    return trial.rejected is None and trial.bic < current.bic


def _groups(seen: Seen, named: Named, settings: DiscrepancySettings) -> tuple[list[SelectedEffect], tuple[Discrimination, ...]]:
    """Each effect added with its group: the candidates of its step (within the ambiguity margin of the winner there,
    or with a nearly parallel signature) and of its signature group, each kept only when, in place of the effect with
    the other effects added, it explains the data as well (:func:`_fits_as_well`); and the measurements that tell the
    members apart, the closest look-alikes first, each pair once.

    Every member is judged in the final selection, also when effects were pruned since its step: the step's group was
    formed beside companions that no longer explain the data, so only the final selection says which members the
    data still cannot tell apart (a step's group kept whole had made a pair 'ambiguous' with members 60 BIC worse).
    A member of such a step leaves the group only when the data exclude it both in place of the effect and beside
    it (:func:`_earns_beside`): a member the screen met beside companions that it pruned since may be the second of a
    pair whose other member the final selection names."""
    gains = {step.added: step for step in named.steps}
    pruned = any(step.pruned for step in named.steps) or {n for n, _ in named.fitted} != {s.added for s in named.steps}
    selected = []
    for name, values in named.fitted:
        step = gains.get(name)
        group = [name]
        considered = list(step.group) if step is not None else []
        for members in seen.groups:  # nearly parallel signatures on these data
            if name in members:
                considered += [m for m in members if m not in considered and m not in group and m in seen.responses]
        group += [m for m in considered if m not in group and m in seen.responses
                  and (_fits_as_well(seen, named, name, m, settings)
                       or (pruned and step is not None and m in step.group and _earns_beside(named, m)))]
        selected.append(SelectedEffect(name, tuple(float(v) for v in values),
                                       step.delta_bic if step is not None else 0.0, tuple(group), 1))
    pairs = [(s.name, m) for s in selected for m in s.group[1:]]
    unique, seen_pairs = [], set()
    for d in sorted(_discriminations(pairs, seen), key=lambda d: d.in_sigma):
        if frozenset(d.effects) not in seen_pairs:
            seen_pairs.add(frozenset(d.effects))
            unique.append(d)
    return selected, tuple(unique)


def _sentinel_away(seen: Seen, located: Located, named: Named, set_aside: dict):
    """A generic load where a named effect already puts its load (a mesh force's teeth, a reaction) is that effect's
    load with a model-form difference in how it is spread or reacted, not a load outside the vocabulary: the verdict
    then compares with the best generic load away from there. Returns (that load or None, the named effects)."""
    sentinel, engine = located.sentinel, seen.library.engine
    if sentinel is None or not named.fitted or engine is None:
        return None, ()
    regions = load_regions(seen.effects, seen.rig, [n for n, _ in named.fitted], engine.sentinel_sites())
    at = tuple(n for n, r in regions.items() if site_in((sentinel.part, sentinel.x_mm), r))
    if not at:
        return None, ()
    try:
        return fit_sentinel(seen.observed, exclude=tuple(x for r in regions.values() for x in r)), at
    except CANDIDATE_FAILURES as error:
        set_aside["sentinel"] = f"the generic load away from the named loads could not be fitted: {error}"
        return None, at


def _generic_elsewhere(seen: Seen, sentinel: SentinelFit | None, selected) -> SentinelFit | None:
    """``sentinel``, unless it acts where a named effect or one of its look-alikes that is itself a load acts
    (:func:`look_alike_places`): there it is that look-alike, which the group already holds, not a load outside the
    vocabulary. A stiffness, a clearance or another change of the rig's springs is not a load: the force it adds
    (Δk times the deflection there) follows the deflection, a generic load there follows the torques, and when the
    data cannot tell the two apart the answer is not ``explained``."""
    engine = seen.library.engine
    if sentinel is None or engine is None:
        return sentinel
    names = list(dict.fromkeys(m for s in selected for m in s.group
                               if m in seen.effects and seen.effects[m].response == "load"))
    places = look_alike_places(seen.effects, seen.rig, names, engine.sentinel_sites())
    return None if any(site_in((sentinel.part, sentinel.x_mm), r) for r in places.values()) else sentinel


# the verdict's reasons that reject a fit for its form (two effects cancelling, one load at two places with opposite
# signs), not for what it leaves: a pair of the vocabulary that fits as well without that form makes the answer
# ambiguous (the data cannot tell the vocabulary pair from a load the couple mimics)
MIMICS = ("cancel each other", "opposite signs")
PAIR_FIRST = 8  # the best single candidates of the first step that may open a pair alternative (with the groups)


def _pairs_as_well(seen: Seen, named: Named, selected: list[SelectedEffect], settings: DiscrepancySettings, *,  # noqa: PLR0913
                   places: dict | None = None, covered_too: bool = False):
    """An ``ambiguous`` answer names every candidate the data cannot exclude, pairs included: two effects that together
    fit as well as the selection (BIC within the ambiguity margin of its BIC), each earning its parameter (the pair's
    BIC below that of either member alone, the criterion by which the screen adds an effect), are both added to the
    groups, unless both are there already. A pair whose second member is small (a torque reaction of a tenth of a
    N per N·m beside a mesh force) fits a table as well as one look-alike of the first and gains less than the screen's
    margin, so the screen stops at one effect: without this the group excluded a truth the data cannot exclude.

    The first member comes from the named groups and the best single candidates of the first step
    (:data:`PAIR_FIRST`), the second from every candidate seen. Returns the groups (each new member joins the group
    that holds its partner, else the first) and a reason per pair added. A pair that cancels itself or is one load at
    two neighbouring places with opposite signs (:func:`judge.opposite_loads`, ``places``) is no alternative.
    ``covered_too``: look at pairs of members already named too, until one is found (the named fit was refused for its
    form, so its groups are no answer yet)."""
    problem = named.problem
    if not named.fitted:
        return selected, []
    limit = _bic(problem, named.fitted, named.after) + settings.ambiguity_margin
    covered = {m for s in selected for m in s.group}
    first = list(dict.fromkeys([m for s in selected for m in s.group]
                               + ([n for n, _ in named.steps[0].ranking[:PAIR_FIRST]] if named.steps else [])))
    first = [n for n in first if n in seen.responses]
    singles: dict[str, tuple[float, np.ndarray | None]] = {}

    def alone(name: str) -> float:
        """BIC of ``name`` fitted alone (inf beyond its bounds or unsolvable); its values start the pair fits."""
        if name not in singles:
            try:
                fit = problem.fit((name,))
                singles[name] = (np.inf if fit.rejected else fit.bic, fit.values[0])
            except CANDIDATE_FAILURES:
                singles[name] = (np.inf, None)
        return singles[name][0]

    groups = [list(s.group) for s in selected]
    reasons, tried = [], set()
    for a in first:
        for b in seen.responses:
            key = frozenset((a, b))
            if b == a or key in tried or ({a, b} <= covered and not (covered_too and not reasons)):
                continue
            tried.add(key)
            alone(a), alone(b)
            start = {n: singles[n][1] for n in (a, b) if singles[n][1] is not None}
            try:
                fit = problem.fit((a, b), start)
            except CANDIDATE_FAILURES:
                continue
            if fit.rejected is not None or fit.bic >= limit or fit.bic >= alone(a) or fit.bic >= alone(b):
                continue
            pair = list(zip(fit.names, fit.values))
            if fighting_pairs(problem, pair) or opposite_loads(pair, seen.effects, places):
                continue
            for member, partner in ((a, b), (b, a)):
                if member not in covered:
                    home = next((g for g in groups if partner in g), groups[0])
                    home.append(member)
                    covered.add(member)
            reasons.append(f"the pair {a} + {b} fits as well (BIC {fit.bic:.4g} against {limit - settings.ambiguity_margin:.4g}"
                           f"; each member alone: {alone(a):.4g}, {alone(b):.4g})")
    return [replace(s, group=tuple(g), pair_members=tuple(m for m in g if m not in s.group))
            for s, g in zip(selected, groups)], reasons


def _bic(problem: Problem, fitted, after: np.ndarray) -> float:
    """The vocabulary's BIC on the rows used to fit, with the true model's ``after``."""
    scaled = ((problem.measured - after) / problem.sigma)[problem.rows]
    k = int(sum(np.atleast_1d(v).size for _, v in fitted))
    return float(scaled @ scaled + k * np.log(max(problem.rows.size, 2)))


def _beyond_bounds(named: Named) -> list[tuple[str, float]]:
    """Fits the screen rejected because a value lies beyond its physical bound, with their BIC: (reason, BIC), the best
    of each candidate, best first."""
    best: dict[str, tuple[str, float]] = {}
    for step in named.steps:
        for name, fit in step.rejected_fits.items():
            if fit.rejected and "outside its physical range" in fit.rejected \
                    and (name not in best or fit.bic < best[name][1]):
                best[name] = (fit.rejected, float(fit.bic))
    return sorted(best.values(), key=lambda item: item[1])


def _judge(seen: Seen, located: Located, named: Named, settings: DiscrepancySettings) -> DiscrepancyResult:
    """The tests after, the cross-validation, the verdict and its reasons, and the result."""
    observed, problem, fitted, after = seen.observed, named.problem, named.fitted, named.after
    data, sigma = observed.data, observed.sigma
    rejected = {}
    for step in named.steps:
        rejected.update(step.rejected)
    selected, discriminations = _groups(seen, named, settings)
    scaled_after = (data.value_mm - after) / sigma
    test_after = gap_test(scaled_after, settings.alpha, observed.dof())
    held = ~observed.rows
    test_held = gap_test(scaled_after[held], settings.alpha, observed.dof(held)) if held.any() else None
    cv = _vocabulary_cv(problem, tuple(n for n, _ in fitted), dict(fitted), observed.scaled_before, located.folds) \
        if fitted and all(n in seen.responses for n, _ in fitted) else None
    set_aside = dict(named.set_aside)
    elsewhere, at = _sentinel_away(seen, located, named, set_aside)
    kinds = [seen.effects[n].kind for n, _ in fitted]
    places = load_x(seen.effects, seen.rig) if len(kinds) > len(set(kinds)) else None  # one load at two places
    beyond = _beyond_bounds(named)
    generic = _generic_elsewhere(seen, located.sentinel, selected) \
        or _generic_elsewhere(seen, elsewhere if at else None, selected)
    outcome, reasons = verdict(problem, list(fitted), after, data=data, tests=(located.test_before, test_after),
                               sentinel=elsewhere if at else located.sentinel, mimic=located.sentinel, cv=cv,
                               settings=settings, effects=seen.effects, places=places,
                               groups=[s.group for s in selected], beyond=beyond, generic=generic)
    mimicked = outcome == "unexplained" and bool(reasons) and all(any(m in r for m in MIMICS) for r in reasons)
    if outcome == "ambiguous" or mimicked:
        groups, pairs = _pairs_as_well(seen, named, selected, settings, places=load_x(seen.effects, seen.rig),
                                       covered_too=mimicked)
        if outcome == "ambiguous" or pairs:  # a couple the vocabulary also explains without one: not unexplained
            outcome, selected = "ambiguous", groups
            reasons = list(reasons) + pairs
    final = tuple(replace(s, confident=outcome == "explained" and len(s.group) == 1) for s in selected)
    ties = ambiguities(final, seen, after, verdict=outcome, generic=generic, settings=settings,
                       bic=_bic(problem, fitted, after) if fitted else np.inf, steps=named.steps)
    return DiscrepancyResult(
        verdict=outcome, data=data, noise=seen.noise, fit_mask=observed.rows, before=observed.before, after=after,
        test_before=located.test_before, test_after=test_after, test_after_held_out=test_held,
        structure=located.structure, selected=final, steps=named.steps, not_observable=seen.not_observable,
        rejected=rejected, set_aside=set_aside, discriminations=discriminations, rig_before=seen.rig,
        rig_after=_applied(seen.rig, seen.effects, fitted), effects=seen.effects, observability=seen.visibility,
        parallel_groups=seen.groups, sentinel=located.sentinel, cross_validation=cv,
        sentinel_cross_validation=located.sentinel_cv, reasons=tuple(reasons),
        vocabulary_chi2=float(np.sum(scaled_after[observed.rows] ** 2)) if fitted else None,
        sentinel_elsewhere=elsewhere, sentinel_at=at, ambiguities=ties, pair_search=named.pair_search,
        beyond_bounds=tuple(reason for reason, b in beyond if fitted and b < _bic(problem, fitted, after)
                            + settings.ambiguity_margin))


def _vocabulary_cv(problem: Problem, names: tuple[str, ...], start: dict, scaled: np.ndarray, folds) -> CrossValidation | None:
    """Held-out χ² of the selected vocabulary effects, each fold refitted without its cases."""
    if not names:
        return None

    def predict(train):
        fold = Problem(problem.measured, problem.sigma, problem.base_paths, problem.observe, problem.responses,
                       rows=train)
        fit = fold.fit(names, start)
        predicted = problem.observe(fold.paths(names, fit.values))
        return (predicted - problem.observe(problem.base_paths)) / problem.sigma

    return cross_validate(scaled, predict, folds)


def _sentinel_cv(sentinel: SentinelFit | None, observed: Observed, folds):
    if sentinel is None or observed.engine is None:
        return None
    scaled = observed.scaled_before
    columns = sentinel_columns(sentinel, observed) / observed.sigma[:, None]

    def predict(train):
        coefficients, *_ = np.linalg.lstsq(columns[train], scaled[train], rcond=None)
        return columns @ coefficients

    return cross_validate(scaled, predict, folds)


def run_discrepancy(rig, data: MeasuredData, settings: DiscrepancySettings = DiscrepancySettings(),
                    library: CandidateLibrary | None = None, progress=None) -> DiscrepancyResult:
    """Observe, locate, screen, refine and judge (see the module docstring). A pure function of its arguments
    (``progress(i, n)`` is told how far each library build is).

    Parameters
    ----------
    rig : Rig
        The rig as modelled.
    data : MeasuredData
        The measurements (:func:`rvcoax.read_measured`).
    settings : DiscrepancySettings
        Candidates, significance level, BIC margin, model-form allowance, held-out rows, the sweep settings.
    library : CandidateLibrary, optional
        Solved candidate responses to reuse (built when not given).
    progress : callable, optional
        ``progress(i, n)`` as each library build goes.

    Returns
    -------
    DiscrepancyResult
        The verdict, the selected effects with their values, the rig with them added, and the gaps before
        and after, on fitted and held-out rows.
    """
    seen = _observe(rig, data, settings, library, progress)
    located = _locate(seen, settings)
    named = _name(seen, located, settings)
    result = _judge(seen, located, named, settings)
    return replace(result, confidence=verdict_confidence(seen, result, settings, settings.confidence_draws))


def _observation_factory(data):
    """``observe_of(layout)``: the observation operator of ``data`` on a path layout, built once per layout (the
    refit evaluates the true model about 100 times on the same layout; rebuilding the operator each time made a
    large measured file cost 100 operator builds per row)."""
    built: dict[tuple, Observation] = {}

    def observe_of(layout: PathLayout) -> Observation:
        key = (layout.n_cases,
               tuple((s, np.asarray(layout.stations_mm[s]).tobytes()) for s in sorted(layout.stations_mm)))
        if key not in built:
            built[key] = Observation(data, layout)
        return built[key]

    return observe_of
