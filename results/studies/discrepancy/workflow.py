"""The discrepancy workflow from measured data to an updated rig file (pure functions).

locate → name → add → show:

1. the base model's predictions and σ (:mod:`locate`); a χ² test says whether there is a gap;
2. every candidate effect of the library (:mod:`rvcoax.geometry.effects`) gets its response around the
   current rig (:mod:`responses`); effects that cannot change the observations by half a σ over
   their physical range are set aside as *not observable on these data*;
3. forward selection with backward pruning by BIC (:mod:`identify`) on the cases used to fit;
4. the selected effects are applied to the rig with their fitted values and fitted again with the
   true model (no response interpolation, no additivity assumption); if a gap remains, the
   library is rebuilt around the updated rig and the search goes on (at most ``max_rounds``);
5. the verdict: ``no_gap``, ``explained`` (the remaining gap is consistent with the noise on every
   case, held-out ones included) or ``unexplained``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import stats
from scipy.optimize import least_squares

from rvcoax.fem.solvers import SolverError
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.effects import candidate_effects
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.studies.discrepancy.engine import Engine, prepare_engine, rig_is_linear
from rvcoax.results.studies.discrepancy.identify import Fit, Problem, Step, forward_backward
from rvcoax.results.studies.discrepancy.locate import (
    GapTest,
    NoiseEstimate,
    estimate_noise,
    gap_test,
    residual_structure,
)
from rvcoax.results.studies.discrepancy.measured import MeasuredData, check_stations
from rvcoax.results.studies.discrepancy.observability import (
    VISIBLE_NORM,
    Suggestion,
    Visibility,
    direction,
    discriminate,
    observability,
    parallel_groups,
    signature,
)
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
    scan_spacing_mm,
    sentinel_columns,
    site_in,
)
from rvcoax.results.sweep import ModelError, SweepSettings

__all__ = ["CANDIDATE_FAILURES", "CASE_CANDIDATE_BYTES", "CASE_CANDIDATE_S", "NONLINEAR_CASE_CANDIDATE_S", "CandidateLibrary", "DiscrepancyResult", "DiscrepancySettings",
           "Discrimination", "OBSERVABLE_SIGMA", "OBSERVATION_BYTES", "OBSERVATION_S", "SelectedEffect",
           "build_library", "discrepancy_workload", "held_out_mask", "run_discrepancy"]

# what one candidate's solve may raise; the candidate is set aside with the reason and the run goes on
CANDIDATE_FAILURES = (ModelError, SolverError, np.linalg.LinAlgError, ValueError)

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


def build_library(rig, cases, settings: SweepSettings, names: tuple[str, ...] | None = None,
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
    return CandidateLibrary(rig, cases, base_paths, layout, responses, failed, engine)


@dataclass(frozen=True)
class SelectedEffect:
    """An effect added to the rig, with its fitted values and the BIC gain when it was added."""

    name: str
    values: tuple[float, ...]
    delta_bic: float
    group: tuple[str, ...]
    round: int
    confident: bool = False

    def parameters(self, effect) -> dict:
        return {p.name: {"value": float(v), "unit": p.unit, "bounds": [p.lower, p.upper]}
                for p, v in zip(effect.parameters, self.values)}


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


@dataclass(frozen=True, eq=False)
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


def _true_paths(rig, effects_by_name, fits, cases, settings: SweepSettings, engine: Engine | None):
    """Full paths of ``rig`` with the effects ``fits`` applied: exact on the factorisation when the engine
    solves every one of them, else a real sweep."""
    if engine is not None and engine.rig is rig and engine.linear and len(fits) == 1 \
            and effects_by_name[fits[0][0]].kind == "bearing_clearance":
        (name, values), = fits
        return (engine.clearance_paths(effects_by_name[name].location, float(np.atleast_1d(values)[0]), cases),
                engine.layout(len(cases)))
    if engine is not None and engine.rig is rig and all(engine.supports(effects_by_name[n]) for n, _ in fits):
        change = engine.unit_change([(effects_by_name[n], list(v)) for n, v in fits])
        return engine.full_paths(engine.unit_paths + change, cases), engine.layout(len(cases))
    return solve_full_paths(_applied(rig, effects_by_name, fits), cases, settings)


def _refine_true(rig, effects_by_name, fits: list[tuple[str, np.ndarray]], data, observe_of, sigma, rows,
                 settings: SweepSettings, engine: Engine | None = None):
    """Fit the selected effects' parameters again with the true model (no response interpolation)."""
    names = [name for name, _ in fits]
    sizes = [effects_by_name[n].parameters for n in names]
    x0 = np.concatenate([np.atleast_1d(v) for _, v in fits])
    lower = np.array([p.lower for ps in sizes for p in ps], float)
    upper = np.array([p.upper for ps in sizes for p in ps], float)
    scale = np.array([max(abs(p.typical), 1e-12) for ps in sizes for p in ps])
    splits = np.cumsum([len(ps) for ps in sizes])[:-1]

    def predicted(x):
        paths, layout = _true_paths(rig, effects_by_name, list(zip(names, np.split(x, splits))), data.cases, settings,
                                    engine)
        return observe_of(layout)(paths)

    def residual(x):
        return ((data.value_mm - predicted(x)) / sigma)[rows]

    x0 = np.clip(x0, lower, upper)
    result = least_squares(residual, x0, bounds=(lower, upper), x_scale=scale, diff_step=1e-4, max_nfev=40,
                           xtol=1e-8, ftol=1e-10)
    return list(zip(names, np.split(result.x, splits))), predicted(result.x)


def _discriminations(group_fits: dict[str, Fit], library: CandidateLibrary, data, observe, sigma,
                     from_rest: bool) -> list[Discrimination]:
    """For the winner against each other member: the station and case where their predictions differ most."""
    names = list(group_fits)
    out = []
    for other in names[1:]:
        found = discriminate(library.responses[names[0]], library.responses[other], data, library.base_paths, observe,
                             sigma, library.engine, from_rest) if library.engine is not None else None
        if found is not None:
            out.append(_as_discrimination((names[0], other), found))
    return out


def _as_discrimination(pair, found: Suggestion) -> Discrimination:
    return Discrimination(pair, found.case, found.shaft, found.x_mm, 1e-3 * found.change_um, found.in_sigma,
                          found.new_case, found.other_datum)


FIGHT_RATIO = 0.5  # two effects whose sum is less than half the larger of them cancel each other
STRUCTURE_T = 4.0  # standard errors by which a curvature left along a shaft exceeds the model-form allowance


def _opposite_loads(fitted: list[tuple[str, np.ndarray]], effects: dict, places: dict | None = None) -> list[str]:
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


def _fighting_pairs(problem: Problem, fitted: list[tuple[str, np.ndarray]]) -> list[str]:
    """Pairs of selected effects that cancel each other: each large, their sum small."""
    signatures = {n: signature(problem.responses[n], v, problem.base_paths, problem.observe, problem.sigma, problem.rows)
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


def _vocabulary_cv(problem: Problem, names: tuple[str, ...], start: dict, scaled: np.ndarray, folds) -> CrossValidation | None:
    """Held-out χ² of the selected vocabulary effects, each fold refitted without its cases."""
    if not names:
        return None

    def predict(train):
        fold = Problem(problem.measured, problem.sigma, problem.base_paths, problem.observe, problem.responses, train)
        fit = fold.fit(names, start)
        predicted = problem.observe(fold.paths(names, fit.values))
        return (predicted - problem.observe(problem.base_paths)) / problem.sigma

    return cross_validate(scaled, predict, folds)


def _sentinel_cv(engine, sentinel: SentinelFit | None, data, base_paths, observe, sigma, scaled, folds, from_rest):
    if sentinel is None or engine is None:
        return None
    columns = sentinel_columns(engine, sentinel, data, base_paths, observe, from_rest) / sigma[:, None]

    def predict(train):
        coefficients, *_ = np.linalg.lstsq(columns[train], scaled[train], rcond=None)
        return columns @ coefficients

    return cross_validate(scaled, predict, folds)


def run_discrepancy(rig, data: MeasuredData, settings: DiscrepancySettings = DiscrepancySettings(),
                    library: CandidateLibrary | None = None, progress=None) -> DiscrepancyResult:
    """Observe, locate, name, add and show (see the module docstring). A pure function of its arguments
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
    sweep_settings = settings.sweep
    from_rest = rig.paths.measured_from == "aligned_at_rest"
    noise = estimate_noise(data, settings.model_form_fraction)
    sigma = noise.sigma_mm
    fit_rows = held_out_mask(data, settings.hold_out_every)
    observe_of = _observation_factory(data)

    def visible(delta):
        base = observe(library_base)
        return bool(np.linalg.norm((observe(library_base + delta) - base) / sigma) >= VISIBLE_NORM)

    if library is None or library.rig is not rig or library.cases != tuple(data.cases):
        engine = prepare_engine(rig, sweep_settings)
        check_stations(data, engine.length_mm)
        observe = observe_of(engine.layout(len(data.cases)))
        library_base = (engine.full_paths(engine.unit_paths, data.cases) if engine.linear
                        else solve_full_paths(rig, data.cases, sweep_settings)[0])
        library = build_library(rig, data.cases, sweep_settings, settings.candidates, progress, visible, engine)
    else:
        check_stations(data, library.layout.length_mm)
        observe = observe_of(library.layout)
        library_base = library.base_paths
    engine = library.engine
    base_paths = library.base_paths
    before = observe(base_paths)
    scaled_before = (data.value_mm - before) / sigma
    test_before = gap_test(scaled_before[fit_rows], settings.alpha)
    structure = residual_structure(data, data.value_mm - before, sigma,
                                   model_form_fraction=settings.model_form_fraction)
    effects_by_name = {e.name: e for e in candidate_effects(rig)}
    set_aside: dict[str, str] = dict(library.failed)
    # 1. observability: which effects can these data see at all, and what would reveal the others
    seen = {}
    for name, response in library.responses.items():
        try:
            seen.update(observability({name: response}, data, base_paths, observe, sigma, engine, from_rest)
                        if engine is not None else {})
        except CANDIDATE_FAILURES as error:
            set_aside[name] = f"its signature cannot be evaluated: {error}"
    not_observable = {n: v.reason for n, v in seen.items() if not v.visible}
    responses = {n: r for n, r in library.responses.items() if n not in not_observable and n not in set_aside}
    # 2. groups of look-alikes, from the signatures alone (independent of the noise level)
    directions = {n: direction(r, base_paths, observe, sigma, fit_rows) for n, r in responses.items()}
    groups = tuple(tuple(g) for g in parallel_groups(directions, settings.parallel_cosine))
    # 3. the out-of-vocabulary sentinel and the folds for cross-validation
    folds = case_folds(data)
    sentinel = sentinel_cv = None
    if engine is not None and test_before.gap:
        try:  # the sentinel, like any candidate, never ends the run
            sentinel = fit_sentinel(engine, data, base_paths, observe, sigma, fit_rows, from_rest)
            sentinel_cv = _sentinel_cv(engine, sentinel, data, base_paths, observe, sigma, scaled_before, folds,
                                       from_rest)
        except CANDIDATE_FAILURES as error:
            set_aside["sentinel"] = f"the generic load could not be fitted: {error}"

    selected: list[SelectedEffect] = []
    steps: list[Step] = []
    rejected: dict[str, str] = {}
    discriminations: list[Discrimination] = []
    after, fitted = before, []
    problem = Problem(data.value_mm, sigma, base_paths, observe, responses, fit_rows)
    if test_before.gap:
        def no_gap_left(fit: Fit) -> bool:
            # the same test as the verdict's: every row, the held-out ones predicted by the fit on the others
            scaled = (data.value_mm - observe(problem.paths(fit.names, fit.values))) / sigma
            return stats.chi2.sf(float(scaled @ scaled), scaled.size) >= settings.alpha

        while True:  # until the true model confirms the screening fit (a candidate that fails is set aside)
            candidates = [n for n in responses if n not in set_aside]
            try:
                screening, steps = forward_backward(problem, candidates, settings.bic_margin, settings.ambiguity_margin,
                                                    settings.parallel_cosine, settings.max_effects, stop=no_gap_left)
            except CANDIDATE_FAILURES as error:  # a response that cannot be evaluated: never ends the run
                set_aside["(screening)"] = f"the screening fit failed: {error}"
                screening, steps = Fit((), (), 0.0, 0), []
            if not screening.names:
                break
            trial = list(zip(screening.names, screening.values))
            try:
                if any(library.responses[n].kind != "linear" for n in screening.names):
                    trial, trial_after = _refine_true(rig, effects_by_name, trial, data, observe_of, sigma, fit_rows,
                                                      sweep_settings, engine)
                else:  # linear effects on a linear rig: the screening fit is exact
                    paths, layout = _true_paths(rig, effects_by_name, trial, data.cases, sweep_settings, engine)
                    trial_after = observe_of(layout)(paths)
            except CANDIDATE_FAILURES as error:
                for name in screening.names:
                    set_aside[name] = f"the fit with it cannot be solved with the true model: {error}"
                continue
            fitted, after = trial, trial_after
            break
        for step in steps:
            rejected.update(step.rejected)
        for step in steps:
            if step.added in dict(fitted):
                discriminations += _discriminations(step.group_fits, library, data, observe, sigma, from_rest)
        gains = {step.added: step for step in steps}
        for name, values in fitted:
            step = gains.get(name)
            group = list(step.group) if step is not None else [name]
            for members in groups:  # nearly parallel signatures on these data: the group, not one name
                if name in members:
                    group += [m for m in members if m not in group]
            selected.append(SelectedEffect(name, tuple(float(v) for v in values),
                                           step.delta_bic if step is not None else 0.0, tuple(group), 1))
        for name, _ in fitted:  # a parallel look-alike that is not in the step's group still needs telling apart
            step = gains.get(name)
            extra = [m for m in next((g for g in groups if name in g), ()) if m != name
                     and (step is None or m not in step.group_fits)]
            for other in extra:
                found = discriminate(library.responses[name], library.responses[other], data, base_paths, observe,
                                     sigma, engine, from_rest) if engine is not None else None
                if found is not None:
                    discriminations.append(_as_discrimination((name, other), found))
    unique, seen_pairs = [], set()
    for d in sorted(discriminations, key=lambda d: d.in_sigma):  # the closest look-alikes first, each pair once
        if frozenset(d.effects) not in seen_pairs:
            seen_pairs.add(frozenset(d.effects))
            unique.append(d)
    discriminations = unique
    current_rig = _applied(rig, effects_by_name, fitted)
    test_after = gap_test((data.value_mm - after) / sigma, settings.alpha)
    held = ~fit_rows
    test_held = gap_test(((data.value_mm - after) / sigma)[held], settings.alpha) if held.any() else None
    cv = _vocabulary_cv(problem, tuple(n for n, _ in fitted), dict(fitted), scaled_before, folds) \
        if fitted and all(n in responses for n, _ in fitted) else None
    # a generic load where a named effect already puts its load (a mesh force's teeth, a reaction) is that
    # effect's load with a model-form difference in how it is spread or reacted, not a load outside the
    # vocabulary: the verdict then compares with the best generic load away from there
    sentinel_elsewhere, sentinel_at = None, ()
    if sentinel is not None and fitted and engine is not None:
        sites = engine.sentinel_sites()
        regions = _load_regions(effects_by_name, rig, [n for n, _ in fitted], sites)
        sentinel_at = tuple(n for n, r in regions.items() if site_in((sentinel.part, sentinel.x_mm), r))
        if sentinel_at:
            try:
                sentinel_elsewhere = fit_sentinel(engine, data, base_paths, observe, sigma, fit_rows, from_rest,
                                                  exclude=tuple(x for r in regions.values() for x in r))
            except CANDIDATE_FAILURES as error:
                set_aside["sentinel"] = f"the generic load away from the named loads could not be fitted: {error}"
    kinds = [effects_by_name[n].kind for n, _ in fitted]
    places = _load_x(effects_by_name, rig) if len(kinds) > len(set(kinds)) else None  # the same load at two places
    verdict, reasons = _verdict(test_before, test_after, selected, fitted, problem, data, after, sigma,
                                sentinel_elsewhere if sentinel_at else sentinel, cv, settings, effects_by_name,
                                mimic=sentinel, places=places)
    final = []
    for s in selected:
        confident = verdict == "explained" and len(s.group) == 1
        final.append(SelectedEffect(s.name, s.values, s.delta_bic, s.group, s.round, confident))
    vocabulary_chi2 = float(np.sum((((data.value_mm - after) / sigma)[fit_rows]) ** 2)) if fitted else None
    return DiscrepancyResult(verdict, data, noise, fit_rows, before, after, test_before, test_after, test_held,
                             structure, tuple(final), tuple(steps), not_observable, rejected, set_aside,
                             tuple(discriminations), rig, current_rig, effects_by_name, seen, groups, sentinel, cv,
                             sentinel_cv, tuple(reasons), vocabulary_chi2, sentinel_elsewhere, sentinel_at)


def _changed_loads(effect, rig) -> list:
    """The lateral loads (torque_lateral_loads) that ``effect`` at its typical value adds to ``rig`` or changes."""
    before = {t.name: t for t in rig.torque_lateral_loads}
    try:
        changed = effect.apply(rig, [p.typical for p in effect.parameters])
    except CANDIDATE_FAILURES:
        return []
    return [load for load in changed.torque_lateral_loads if before.get(load.name) != load]


def _load_x(effects_by_name: dict, rig) -> dict[str, float]:
    """x (mm) where each torque-proportional load of the vocabulary (one parameter in N per N·m) acts."""
    out = {}
    for name, effect in effects_by_name.items():
        if len(effect.parameters) == 1 and effect.parameters[0].unit == "N/(N·m)":
            loads = _changed_loads(effect, rig)
            if loads:
                out[name] = float(loads[0].on.x_mm)
    return out


def _load_regions(effects_by_name: dict, rig, names, sites) -> dict[str, tuple[tuple[str, float, float], ...]]:
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


def _verdict(test_before, test_after, selected, fitted, problem: Problem, data, after, sigma, sentinel, cv, settings,
             effects: dict | None = None, mimic=None, places: dict | None = None):
    """``no_gap``, ``explained`` or ``unexplained``, with the reasons for the last.

    ``sentinel`` is the generic load the vocabulary must beat by the BIC margin; ``mimic`` (default ``sentinel``)
    the best generic load anywhere, which tells whether effects that cancel each other mimic a load's shape and
    whether the vocabulary needs more parameters than one load for a fit as good; ``places`` where the
    vocabulary's torque-proportional loads act (:func:`_opposite_loads`)."""
    if not test_before.gap:
        return "no_gap", []
    reasons = []
    if not selected:
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
        reasons += _fighting_pairs(problem, fitted)
    reasons += _opposite_loads(fitted, effects or {}, places)
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
    return ("unexplained" if reasons else "explained"), reasons


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
