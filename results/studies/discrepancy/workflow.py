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
from rvcoax.results.studies.discrepancy.identify import Fit, Problem, Step, forward_backward
from rvcoax.results.studies.discrepancy.locate import (
    GapTest,
    NoiseEstimate,
    estimate_noise,
    gap_test,
    residual_structure,
)
from rvcoax.results.studies.discrepancy.measured import MeasuredData, check_stations
from rvcoax.results.studies.discrepancy.responses import (
    EffectResponse,
    Observation,
    PathLayout,
    effect_response,
    solve_full_paths,
)
from rvcoax.results.sweep import ModelError, SweepSettings

__all__ = ["CANDIDATE_FAILURES", "CASE_CANDIDATE_S", "CandidateLibrary", "DiscrepancyResult", "DiscrepancySettings",
           "Discrimination", "OBSERVABLE_SIGMA", "OBSERVATION_BYTES", "OBSERVATION_S", "SelectedEffect",
           "build_library", "discrepancy_workload", "held_out_mask", "run_discrepancy"]

# what one candidate's solve may raise; the candidate is set aside with the reason and the run goes on
CANDIDATE_FAILURES = (ModelError, SolverError, np.linalg.LinAlgError, ValueError)

OBSERVABLE_SIGMA = 0.5
# measured costs (2-core AMD EPYC dev machine): the reference table (20 cases, 58 candidates) took 65 s end to
# end, 56 ms per case and candidate (library sweeps, grid points of nonlinear effects, true-model refits);
# per observation 20 µs to parse and 5.3 µs per observation-operator build, built about 100 times per run
# (each true-model evaluation of the refit): a 20,000-row paths file, results/studies/discrepancy/responses.py
CASE_CANDIDATE_S = 0.056
OBSERVATION_S = 20e-6 + 100 * 5.3e-6
OBSERVATION_BYTES = 2e3


@dataclass(frozen=True)
class DiscrepancySettings:
    """Settings of the workflow (margins are in BIC units; fractions are of the signal)."""

    sweep: SweepSettings = SweepSettings()
    alpha: float = 0.01
    bic_margin: float = 10.0
    ambiguity_margin: float = 6.0
    parallel_cosine: float = 0.999
    model_form_fraction: float = 0.02
    hold_out_every: int = 3
    max_effects: int = 4
    max_rounds: int = 2
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


def build_library(rig, cases, settings: SweepSettings, names: tuple[str, ...] | None = None,
                  progress=None) -> CandidateLibrary:
    """Solve the base rig and every candidate's response (real sweeps; beam model ≈ 0.1 s each).

    ``progress(i, n)`` is called after each candidate (for a progress bar with the time remaining)."""
    base_paths, layout = solve_full_paths(rig, cases, settings)
    effects = [e for e in candidate_effects(rig) if names is None or e.name in names or e.kind in names]
    responses, failed = {}, {}
    for done, effect in enumerate(effects, start=1):
        if progress is not None:
            progress(done - 1, len(effects))
        try:
            responses[effect.name] = effect_response(effect, rig, cases, settings, base_paths)
        except CANDIDATE_FAILURES as error:  # e.g. a clearance that leaves a part without support
            failed[effect.name] = f"cannot be solved over its physical range: {error}"
    return CandidateLibrary(rig, tuple(cases), base_paths, layout, responses, failed)


@dataclass(frozen=True)
class SelectedEffect:
    """An effect added to the rig, with its fitted values and the BIC gain when it was added."""

    name: str
    values: tuple[float, ...]
    delta_bic: float
    group: tuple[str, ...]
    round: int

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


@dataclass(frozen=True, eq=False)
class DiscrepancyResult:
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


def discrepancy_workload(data: MeasuredData, n_candidates: int):
    """The estimated time and memory of :func:`run_discrepancy` on ``data`` with ``n_candidates`` candidates."""
    from rvcoax.geometry.model.workload import BASE_BYTES, Workload, count_text

    cases = len(data.cases)
    seconds = CASE_CANDIDATE_S * cases * max(n_candidates, 1) + OBSERVATION_S * data.n
    return Workload(f"{count_text(data.n)} observations in {count_text(cases)} load cases × {n_candidates} "
                    "candidate effects", seconds, BASE_BYTES + OBSERVATION_BYTES * data.n)


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


def _observable(response: EffectResponse, base_paths, observe, base_obs, sigma) -> float:
    """Largest change of any observation (in σ) over the effect's physical range."""
    if response.kind == "grid":
        deltas = list(response.grid_paths)
    else:
        deltas = []
        for i, parameter in enumerate(response.effect.parameters):
            for extreme in (parameter.lower, parameter.upper):
                values = np.zeros(response.n_params)
                values[i] = extreme
                deltas.append(response.delta(values))
    return float(max(np.max(np.abs(observe(base_paths + d) - base_obs) / sigma) for d in deltas))


def _refine_true(rig, effects_by_name, fits: list[tuple[str, np.ndarray]], data, observe_of, sigma, rows,
                 settings: SweepSettings):
    """Fit the selected effects' parameters again with the true model (real sweeps)."""
    names = [name for name, _ in fits]
    sizes = [effects_by_name[n].parameters for n in names]
    x0 = np.concatenate([np.atleast_1d(v) for _, v in fits])
    lower = np.array([p.lower for ps in sizes for p in ps], float)
    upper = np.array([p.upper for ps in sizes for p in ps], float)
    scale = np.array([max(abs(p.typical), 1e-12) for ps in sizes for p in ps])
    splits = np.cumsum([len(ps) for ps in sizes])[:-1]

    def predicted(x):
        values = np.split(x, splits)
        paths, layout = solve_full_paths(_applied(rig, effects_by_name, zip(names, values)), data.cases, settings)
        return observe_of(layout)(paths)

    def residual(x):
        return ((data.value_mm - predicted(x)) / sigma)[rows]

    x0 = np.clip(x0, lower, upper)
    result = least_squares(residual, x0, bounds=(lower, upper), x_scale=scale, diff_step=1e-4, max_nfev=40,
                           xtol=1e-8, ftol=1e-10)
    return list(zip(names, np.split(result.x, splits))), predicted(result.x)


def _discriminate(rig, effects_by_name, prior, group_fits: dict[str, Fit], data: MeasuredData, noise: NoiseEstimate,
                  settings: SweepSettings, set_aside: dict[str, str]) -> list[Discrimination]:
    """For the winner against each other member: the station and case where their predictions differ most.

    A member whose prediction cannot be solved gets no discrimination; ``set_aside`` records why."""
    names = list(group_fits)
    if len(names) < 2:
        return []
    t1 = max(abs(c.input_torque_Nm) for c in data.cases)
    t2 = max(abs(c.output_torque_Nm) for c in data.cases)
    extra = [LoadCase(-t1, -t2), LoadCase(t1 / 2, t2 / 2)]
    cases = list(data.cases) + [c for c in extra if c not in data.cases]
    predictions = {}
    for name in names:
        fitted = group_fits[name]
        member_rig = _applied(rig, effects_by_name, list(prior) + [(name, fitted.values[-1])])
        try:
            predictions[name] = solve_full_paths(member_rig, cases, settings)
        except CANDIDATE_FAILURES as error:
            set_aside[name] = f"no discriminating measurement: its prediction cannot be solved: {error}"
    winner = names[0]
    if winner not in predictions:
        return []
    out = []
    for other in (n for n in names[1:] if n in predictions):
        (a, layout), (b, _) = predictions[winner], predictions[other]
        best = None
        for i, case in enumerate(cases):
            for shaft in MEASURED_SHAFTS:
                block = layout.block(i, shaft)
                scaled = np.abs(a[block] - b[block]) / max(noise.noise_mm.get(shaft, 0.0), 1e-12)
                j = int(np.argmax(scaled))
                if best is None or scaled[j] > best[0]:
                    best = (scaled[j], case, shaft, float(layout.stations_mm[shaft][j]), float(a[block][j] - b[block][j]),
                            i >= len(data.cases))
        out.append(Discrimination((winner, other), best[1], best[2], best[3], best[4], float(best[0]), best[5]))
    return out


def run_discrepancy(rig, data: MeasuredData, settings: DiscrepancySettings = DiscrepancySettings(),
                    library: CandidateLibrary | None = None, progress=None) -> DiscrepancyResult:
    """Locate, name, add and show (see the module docstring). A pure function of its arguments
    (``progress(i, n)`` is told how far each library build is)."""
    sweep_settings = settings.sweep
    base_paths, layout = solve_full_paths(rig, data.cases, sweep_settings)
    check_stations(data, layout.length_mm)
    observe_of = _observation_factory(data)
    observe = observe_of(layout)
    before = observe(base_paths)
    noise = estimate_noise(data, settings.model_form_fraction)
    sigma = noise.sigma_mm
    fit_rows = held_out_mask(data, settings.hold_out_every)
    test_before = gap_test(((data.value_mm - before) / sigma)[fit_rows], settings.alpha)
    structure = residual_structure(data, data.value_mm - before, sigma)
    effects_by_name = {e.name: e for e in candidate_effects(rig)}
    selected: list[SelectedEffect] = []
    steps: list[Step] = []
    not_observable: dict[str, str] = {}
    rejected: dict[str, str] = {}
    set_aside: dict[str, str] = {}
    discriminations: list[Discrimination] = []
    current_rig, after, fitted = rig, before, []
    if test_before.gap:
        for round_ in range(1, settings.max_rounds + 1):
            if library is None or library.rig is not current_rig or library.cases != data.cases:
                names = settings.candidates
                if round_ > 1:  # an effect that could not change the data around the first rig cannot now either
                    names = tuple(n for n, e in effects_by_name.items() if n not in not_observable
                                  and (names is None or n in names or e.kind in names))
                library = build_library(current_rig, data.cases, sweep_settings, names, progress)
            set_aside.update(library.failed)
            round_observe = observe_of(library.layout)
            base_obs = round_observe(library.base_paths)
            responses = {}
            for name, response in library.responses.items():
                if any(name == s.name for s in selected) or name in set_aside:
                    continue
                size = _observable(response, library.base_paths, round_observe, base_obs, sigma)
                if size < OBSERVABLE_SIGMA:
                    not_observable[name] = (f"changes no observation by more than {OBSERVABLE_SIGMA} σ over its "
                                            f"physical range (largest change {size:.2g} σ)")
                else:
                    responses[name] = response
            problem = Problem(data.value_mm, sigma, library.base_paths, round_observe, responses, fit_rows)

            def no_gap_left(fit: Fit) -> bool:
                return stats.chi2.sf(fit.chi2, fit.n) >= settings.alpha

            prior = list(fitted)
            while True:  # until the true model confirms the screening fit (a candidate that fails is set aside)
                screening, round_steps = forward_backward(
                    problem, [n for n in responses if n not in set_aside], settings.bic_margin,
                    settings.ambiguity_margin, settings.parallel_cosine, settings.max_effects - len(selected),
                    stop=no_gap_left)
                if not screening.names:
                    break
                trial = prior + list(zip(screening.names, screening.values))
                try:
                    if prior or any(library.responses[n].kind != "linear" for n in screening.names):
                        trial, trial_after = _refine_true(rig, effects_by_name, trial, data, observe_of, sigma,
                                                          fit_rows, sweep_settings)
                    else:  # linear effects on a linear rig: the screening fit is exact
                        paths, layout = solve_full_paths(_applied(rig, effects_by_name, trial), data.cases,
                                                         sweep_settings)
                        trial_after = observe_of(layout)(paths)
                except CANDIDATE_FAILURES as error:
                    for name in screening.names:
                        set_aside[name] = f"the fit with it cannot be solved with the true model: {error}"
                    continue
                fitted, after = trial, trial_after
                break
            for step in round_steps:
                rejected.update(step.rejected)
            if not screening.names:
                break
            for step in round_steps:
                if step.added in screening.names:
                    discriminations += _discriminate(current_rig, effects_by_name, prior, step.group_fits, data,
                                                     noise, sweep_settings, set_aside)
            gains = {step.added: step for step in round_steps}
            selected = [s for s in selected if s.name in dict(fitted)]
            for name, values in fitted:
                if name in gains:
                    step = gains[name]
                    selected.append(SelectedEffect(name, tuple(float(v) for v in values), step.delta_bic, step.group,
                                                   round_))
                else:
                    selected = [SelectedEffect(s.name, tuple(float(v) for v in values), s.delta_bic, s.group, s.round)
                                if s.name == name else s for s in selected]
            steps += round_steps
            current_rig = _applied(rig, effects_by_name, fitted)
            if not gap_test(((data.value_mm - after) / sigma)[fit_rows], settings.alpha).gap:
                break
    test_after = gap_test((data.value_mm - after) / sigma, settings.alpha)
    held = ~fit_rows
    test_held = gap_test(((data.value_mm - after) / sigma)[held], settings.alpha) if held.any() else None
    verdict = "no_gap" if not test_before.gap else ("explained" if not test_after.gap and selected else "unexplained")
    return DiscrepancyResult(verdict, data, noise, fit_rows, before, after, test_before, test_after, test_held,
                             structure, tuple(selected), tuple(steps), not_observable, rejected, set_aside,
                             tuple(discriminations), rig, current_rig, effects_by_name)


def _observation_factory(data: MeasuredData):
    def observe_of(layout: PathLayout) -> Observation:
        return Observation(data, layout)

    return observe_of
