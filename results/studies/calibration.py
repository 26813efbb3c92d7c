"""Calibration of named physical parameters on chosen rows of the published table.

At most two parameters per shaft are fitted (``scipy.optimize.least_squares``) so that the model
reproduces the published Y of the fitting rows; everything else stays as built. Two rows of
|Y| do not always fix the parameters uniquely: an affine Y(T) = |a T + b| through two
magnitudes has two solutions (with or without a sign change between the rows) and each has a
mirror image (−a, −b), which gives the same |Y| and is dropped. All other exact solutions are kept; the one nearest to the reference values
(distance measured in units of each parameter's plausible range) is used, and the others are
reported.
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.gear_loads import gear_contact_torques
from rvcoax.geometry.model.loads import UNIT_LOADS
from rvcoax.geometry.parameters import get_parameter, with_parameters
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import PublishedRow
from rvcoax.results.studies.check import y_at_stations
from rvcoax.results.sweep import SweepSettings, check_clearance_model, prepare_model, run_sweep

__all__ = ["Calibration", "CalibrationParameter", "DEFAULT_PARAMETERS", "FittedParameter", "LOAD_GROUPS", "calibrate",
           "loads_with_trials", "solve_with_trials"]


@dataclass(frozen=True)
class CalibrationParameter:
    """A named physical parameter that calibration may change.

    Parameters
    ----------
    address : str
        Rig parameter address (see :mod:`rvcoax.geometry.parameters`).
    shaft : str
        The measured shaft it is fitted on ("input" or "output").
    unit : str
    bounds : (float, float)
        Hard limits of the fit.
    plausible : (float, float)
        The range a reviewer would accept as physically real.
    scale : float
        Typical magnitude, for the optimiser and the distance to the reference.
    meaning : str
    """

    address: str
    shaft: str
    unit: str
    bounds: tuple[float, float]
    plausible: tuple[float, float]
    scale: float
    meaning: str


DEFAULT_PARAMETERS = (
    CalibrationParameter(
        address="torque_lateral_loads.sun_gear_load_sharing.imbalance", shaft="input", unit="-", bounds=(-1.0, 1.0),
        plausible=(-0.15, 0.15), scale=0.02,
        meaning="mesh-stiffness imbalance (k1-k2)/(k1+k2) of the two crankshaft gears on the input gear; "
        "|imbalance| <= 0.15 is a load-sharing factor K_gamma <= 1.15",
    ),
    CalibrationParameter(address="torque_lateral_loads.sun_gear_load_sharing.position_error_um", shaft="input",
                         unit="µm", bounds=(-50.0, 50.0), plausible=(-2.0, 2.0), scale=0.01,
                         meaning="position error of the two input-gear meshes along their line of action; IT3 band is ±2 µm [P]"),
    CalibrationParameter(address="torque_lateral_loads.crankshaft_load_sharing.imbalance", shaft="output", unit="-",
                         bounds=(-1.0, 1.0), plausible=(-0.15, 0.15), scale=0.02,
                         meaning="stiffness imbalance of the two crankshafts driving the output carrier"),
    CalibrationParameter(address="torque_lateral_loads.crankshaft_load_sharing.position_error_um", shaft="output",
                         unit="µm", bounds=(-50.0, 50.0), plausible=(-3.0, 3.0), scale=0.01,
                         meaning="position error of the two crankshafts in the carrier; IT3 band is ±3 µm [P]"),
)


@dataclass(frozen=True)
class FittedParameter:
    parameter: CalibrationParameter
    reference_value: float
    fitted_value: float

    @property
    def plausible(self) -> bool:
        lo, hi = self.parameter.plausible
        return lo <= self.fitted_value <= hi


@dataclass(frozen=True)
class Calibration:
    """The result of a calibration."""

    rig: Rig
    parameters: tuple[FittedParameter, ...]
    fit_rows: tuple[int, ...]
    fit_relative_residual: float
    alternatives: tuple[tuple[FittedParameter, ...], ...]

    def values(self) -> dict[str, float]:
        return {p.parameter.address: p.fitted_value for p in self.parameters}

    def document(self) -> dict:
        """The calibration as a sweep's JSON records it: the rows fitted, the residual, each fitted parameter
        (reference and fitted value, plausible range) and the other exact solutions."""
        def entry(p):
            return {"address": p.parameter.address, "shaft": p.parameter.shaft, "unit": p.parameter.unit,
                    "reference_value": p.reference_value, "fitted_value": p.fitted_value,
                    "plausible_range": list(p.parameter.plausible), "plausible": p.plausible,
                    "meaning": p.parameter.meaning}

        return {
            "fit_rows_index": list(self.fit_rows),
            "fit_relative_residual": self.fit_relative_residual,
            "parameters": [entry(p) for p in self.parameters],
            "other_exact_solutions": [[entry(p) for p in alt] for alt in self.alternatives],
        }


LOAD_GROUPS = ("torque_lateral_loads.",)


def _paths(rig: Rig, rows: list[PublishedRow], shaft: str, prepared=None) -> np.ndarray:
    """Signed u_y paths (mm) of ``shaft`` at the fitting rows, shape (rows, stations)."""
    sweep = run_sweep(rig, tuple(r.case for r in rows), prepared=prepared, engineering=False)
    return np.array([c.paths[shaft].uy_mm for c in sweep.cases])


RIGS_PER_CALL = 4
"""Trial rigs whose unit loads are solved in one call (each changes a few of them): the 1 + 2 + 1 of a shaft's fit.
A solve's memory grows with its columns: with MKL's refinement of the indefinite tie form about 6 MB per column on
the hybrid reference rig (4 rigs raised the check's peak by 0.14 GB, so it was 2); the Cholesky form
(:mod:`rvcoax.fem.woodbury`) refines nothing, and 4 rigs a call leave the peak where it was (benchmarks/RESULTS.md)."""


def _solve_together(prepared, rigs: list[Rig], per_call: int | None = RIGS_PER_CALL) -> None:
    """Solve the unit loads of ``rigs`` on ``prepared``, ``per_call`` rigs a call (None: all in one), into its cache of
    solutions.

    Each solve call on a factor has a fixed cost, a pass over the whole factor (the hybrid reference rig's Cholesky:
    about 0.09 s CPU for one column, 0.02 s per added column); the sweeps that follow find every column solved.
    """
    if not rigs or check_clearance_model(rigs[0], prepared.system.kind):  # nonlinear: solved case by case
        return
    step = len(rigs) if per_call is None else per_call
    for first in range(0, len(rigs), step):  # the load vectors of a few rigs at a time: 8 MB per rig
        loads = [prepared.system.with_loads_of(rig).unit_loads for rig in rigs[first:first + step]]
        prepared.solve_unit_loads([load[k] for load in loads for k in UNIT_LOADS])


def _row_y(rig: Rig, rows: list[PublishedRow], shaft: str, paths: np.ndarray) -> np.ndarray:
    """Y of each row from its u_y path: the maximum over the path, or over the row's measured stations."""
    path = getattr(rig.paths, shaft)
    station = np.linspace(0.0, path.length_mm, paths.shape[1])
    return np.array([y_at_stations(station, uy, r.stations_mm(shaft)) for r, uy in zip(rows, paths)])


def _y_max(rig: Rig, rows: list[PublishedRow], shaft: str, prepared=None) -> np.ndarray:
    return _row_y(rig, rows, shaft, _paths(rig, rows, shaft, prepared))


def _affine_surrogate(rig, parameters, rows, shaft, prepared, *, scale):  # noqa: PLR0913
    """If the paths are affine in the (scaled) parameters, a function x → paths that is exact.

    Load-sharing parameters enter the loads linearly, so the paths at the fitting rows are
    u(x) = u0 + Σ x_j (u_j − u0). Built from 1 + n solves and verified at a random point to 1e-6
    (a direct solver reproduces a solution to ~1e-8; the check tolerance is 2e-2);
    None when the model is not affine in them (e.g. a stiffness).
    """
    reference = np.array([get_parameter(rig, p.address) for p in parameters]) / scale

    def trial(x):
        return with_parameters(rig, {p.address: v for p, v in zip(parameters, x * scale)})

    probe = reference + np.random.default_rng(0).uniform(-2.0, 2.0, len(parameters))
    points = [reference, *(reference + np.eye(len(parameters))[j] for j in range(len(parameters))), probe]
    rigs = [trial(x) for x in points]
    _solve_together(prepared, rigs)  # 1 + n + 1 sweeps below, one solve call

    base = _paths(rigs[0], rows, shaft, prepared)
    slopes = [_paths(r, rows, shaft, prepared) - base for r in rigs[1:-1]]

    def surrogate(x):
        return base + sum((x[j] - reference[j]) * slopes[j] for j in range(len(parameters)))

    exact = _paths(rigs[-1], rows, shaft, prepared)
    if np.abs(surrogate(probe) - exact).max() > 1e-6 * max(np.abs(exact).max(), 1e-300):
        return None
    return surrogate


AFFINE_LOADS_RTOL = 1e-10
"""Largest difference, relative to the largest load entry, between the unit loads of a trial rig and their affine
prediction from the reference and one-parameter steps, for the loads to count as affine in the parameters (the
combination's rounding is ~1e-15; a load law that is not affine misses by far more)."""


def _combination(base, steps, coefficients):
    """base + Σ c_j (step_j − base): the affine combination of a reference (``base``) and its one-parameter steps
    (:func:`_joint_trials`) at the scaled parameter changes ``coefficients``, for load vectors and solutions alike."""
    return base + sum(c * (step - base) for c, step in zip(coefficients, steps))


def _affine_at(loads: list[dict], coefficients, target: dict) -> bool:
    """Whether every unit load of ``target`` (by name) is the combination (:func:`_combination`) of the trial rigs'
    ``loads`` (the reference's first, then one per parameter step) at ``coefficients``, to :data:`AFFINE_LOADS_RTOL` of
    its size."""
    for name in UNIT_LOADS:
        base = loads[0][name]
        predicted = _combination(base, [load[name] for load in loads[1:]], coefficients)
        size = max(np.abs(target[name]).max(initial=0.0), np.abs(base).max(initial=0.0))
        if np.abs(predicted - target[name]).max(initial=0.0) > AFFINE_LOADS_RTOL * size:
            return False
    return True


def _joint_trials(rig: Rig, parameters, scale: np.ndarray) -> tuple[np.ndarray, list[Rig]]:
    """(the parameters' scaled reference values, the rigs :func:`_joint_surrogate` sweeps: the reference and one
    step of 1 (scaled) in each parameter)."""
    reference = np.array([get_parameter(rig, p.address) for p in parameters]) / scale
    steps = [reference + np.eye(len(parameters))[j] for j in range(len(parameters))]
    return reference, [with_parameters(rig, {p.address: v for p, v in zip(parameters, x * scale)})
                       for x in (reference, *steps)]


def loads_with_trials(rig: Rig, system, parameters: tuple[CalibrationParameter, ...] = DEFAULT_PARAMETERS) -> list:
    """The unit-load vectors of ``rig`` and of the rigs :func:`calibrate` will sweep, on ``system`` (an assembled
    :class:`rvcoax.geometry.model.RigSystem` of ``rig``): what a check solves after the set-up, for
    :func:`rvcoax.results.sweep.prepare_model`'s ``loads_ahead``.

    Empty where :func:`calibrate` would not use the one-surrogate path (a parameter that is not a load parameter, or
    nonlinear bearings); only ``rig``'s own where it lacks a parameter.
    """
    if not all(p.address.startswith(LOAD_GROUPS) for p in parameters) or check_clearance_model(rig, system.kind):
        return []
    try:
        _, rigs = _joint_trials(rig, parameters, np.array([p.scale for p in parameters]))
    except KeyError:  # the rig lacks a parameter: calibrate() says so, after the sweep of the rig as built
        rigs = []
    return [load[k] for load in (system.with_loads_of(r).unit_loads for r in [rig, *rigs]) for k in UNIT_LOADS]


def solve_with_trials(rig: Rig, prepared, parameters: tuple[CalibrationParameter, ...] = DEFAULT_PARAMETERS) -> None:
    """Solve the unit loads of ``rig`` and of the rigs :func:`calibrate` will sweep on ``prepared`` in one solve call,
    into ``prepared``'s cache of solutions (a caller that sweeps ``rig`` and then calibrates it: each solve call reads
    the whole factor, so one call instead of two saves a pass; the hybrid reference rig: ~0.1 s, benchmarks/RESULTS.md).
    None at all where ``prepared`` was set up with them (:func:`loads_with_trials` as its ``loads_ahead``).

    Does nothing where :func:`calibrate` would not use the one-surrogate path (a parameter that is not a load
    parameter, or nonlinear bearings); only ``rig``'s own where it lacks a parameter.
    """
    vectors = loads_with_trials(rig, prepared.system, parameters)
    if vectors:  # one call: the trial rigs share most of their loads with the rig, and a repeated vector is solved once
        prepared.solve_unit_loads(vectors)


def _joint_surrogate(rig: Rig, parameters, rows: list[PublishedRow], prepared, *, scale: np.ndarray):
    """Where the unit loads are affine in every parameter (scaled by ``scale``), a function x → {shaft: paths} at the
    fitting rows that is exact, from 1 + n sweeps and one solve call; else None.

    Affinity is checked on the load vectors themselves, at a random point of all the parameters together: a solution
    is linear in its load (one factorisation) and a path in its solution, so affine loads give affine paths, whatever
    the solve's accuracy (:func:`_affine_surrogate` checks the solved paths instead, at 1e-6, for each shaft's pair
    of parameters and solves again at the other shaft's fitted values). The case weights must not depend on the
    parameters either (the gear meshes' full-contact torques). One surrogate serves both shafts: the second shaft's
    fit sees the first's fitted values through their slopes.
    """
    reference, rigs = _joint_trials(rig, parameters, scale)
    probe = reference + np.random.default_rng(0).uniform(-2.0, 2.0, len(parameters))
    rigs.append(with_parameters(rig, {p.address: v for p, v in zip(parameters, probe * scale)}))
    if check_clearance_model(rig, prepared.system.kind) or len({gear_contact_torques(r) for r in rigs}) > 1:
        return None
    systems = [prepared.system.with_loads_of(r) for r in rigs]  # each rig's loads built once, for the sweeps too
    loads = [system.unit_loads for system in systems]
    if not _affine_at(loads[:-1], probe - reference, loads[-1]):
        return None
    # every column the sweeps below need, in one solve call (usually cached already: solve_with_trials)
    prepared.solve_unit_loads([load[k] for load in loads[:-1] for k in UNIT_LOADS])
    del loads, systems[-1]  # the probe is not swept

    def both(system):
        sweep = run_sweep(system.rig, tuple(row.case for row in rows), prepared=dataclasses.replace(prepared, system=system),
                          engineering=False)
        return {shaft: np.array([c.paths[shaft].uy_mm for c in sweep.cases]) for shaft in MEASURED_SHAFTS}

    # each system let go once swept: no more load vectors held at once than the affinity check above held
    base = both(systems.pop(0))
    slopes = [{shaft: paths[shaft] - base[shaft] for shaft in MEASURED_SHAFTS}
              for paths in (both(systems.pop(0)) for _ in parameters)]

    def surrogate(x, shaft):
        return base[shaft] + sum((x[j] - reference[j]) * slopes[j][shaft] for j in range(len(parameters)))

    return surrogate


def _remember_fitted(prepared, rig: Rig, parameters, final: Rig, *, scale: np.ndarray) -> None:
    """Keep the unit-load solutions of the calibrated rig ``final`` in ``prepared``'s cache as the affine combination of
    the trial rigs' (:func:`_joint_trials`, solved already) that its loads are, so that its sweeps need no solve call
    (a pass over the whole factor: the hybrid reference rig, ~0.1 s).

    Each of ``final``'s load vectors must equal the same combination of the trial rigs' vectors to
    :data:`AFFINE_LOADS_RTOL` of its size (what :func:`_joint_surrogate` checked at a random point), or nothing is
    kept and the sweep solves as before; the sweeps check every case's residual K u − f against the stiffness as
    always, which the combination has to pass like a solve.
    """
    reference, rigs = _joint_trials(rig, parameters, scale)
    steps = np.array([get_parameter(final, p.address) for p in parameters]) / scale - reference
    system = prepared.system
    loads = [system.with_loads_of(r).unit_loads for r in rigs]
    target = system.with_loads_of(final).unit_loads
    if not _affine_at(loads, steps, target):
        return
    names = [name for name in UNIT_LOADS if np.any(target[name])]
    combinations = []
    for name in names:
        solved = prepared.solve_unit_loads([load[name] for load in loads])  # the trial rigs': in the cache already
        combinations.append(_combination(solved[:, 0], solved[:, 1:].T, steps))
    prepared.remember([target[name] for name in names], combinations)


def _published(rows: list[PublishedRow], shaft: str) -> np.ndarray:
    return np.array([r.y_input_mm if shaft == "input" else r.y_output_mm for r in rows])


def _fit_shaft(rig: Rig, parameters: list[CalibrationParameter], rows: list[PublishedRow], shaft: str,  # noqa: PLR0913
               prepared=None, *, joint=None):
    """All exact solutions for one shaft's parameters (list of value arrays, best first by cost).

    ``joint``: ``(surrogate, x_of)`` — :func:`_joint_surrogate` of every calibrated parameter, and the function that
    places this shaft's (scaled) values among the others' (the ones fitted already at their values, the rest at
    their reference); without it, the shaft's own surrogate (:func:`_affine_surrogate`) or trial sweeps."""
    target = _published(rows, shaft)
    scale = np.array([p.scale for p in parameters])
    lower = np.array([p.bounds[0] for p in parameters]) / scale
    upper = np.array([p.bounds[1] for p in parameters]) / scale
    reference = np.array([get_parameter(rig, p.address) for p in parameters]) / scale

    if joint is not None:
        every, x_of = joint

        def surrogate(x):
            return every(x_of(x), shaft)
    else:
        surrogate = _affine_surrogate(rig, parameters, rows, shaft, prepared, scale=scale) if prepared is not None else None

    def residual(x):
        if surrogate is not None:
            return (_row_y(rig, rows, shaft, surrogate(x)) - target) / target
        trial = with_parameters(rig, {p.address: v for p, v in zip(parameters, x * scale)})
        return (_y_max(trial, rows, shaft, prepared) - target) / target

    solutions = []
    for signs in itertools.product((1.0, -1.0), repeat=len(parameters)):
        start = np.where(reference != 0.0, reference, 1.0) * np.array(signs)
        start = np.clip(start, lower + 1e-9, upper - 1e-9)
        result = least_squares(residual, start, bounds=(lower, upper), x_scale=1.0, xtol=1e-12, ftol=1e-12)
        solutions.append((float(np.max(np.abs(result.fun))), result.x * scale))
    best = min(s[0] for s in solutions)
    exact = [values for cost, values in solutions if cost <= max(10 * best, 1e-6)]
    unique: list[np.ndarray] = []
    tolerance = 1e-9 * np.abs(scale).max()
    for values in exact:
        # a solution with every sign reversed (the mirror image) gives the same |Y|: keep one
        if not any(np.allclose(values, u, rtol=1e-4, atol=tolerance) or np.allclose(-values, u, rtol=2e-2, atol=tolerance)
                   for u in unique):
            unique.append(values)
    return unique, best


def calibrate(  # noqa: PLR0913
    rig: Rig,
    published: tuple[PublishedRow, ...],
    fit_output_torques_Nm=(10.0, 200.0),
    parameters: tuple[CalibrationParameter, ...] = DEFAULT_PARAMETERS,
    settings: SweepSettings | None = None,
    *, prepared=None,
) -> Calibration:
    """Fit ``parameters`` to the published Y of the rows whose T2 is in ``fit_output_torques_Nm``.

    When every parameter is a load parameter, the model is assembled and factorised once
    (``prepared`` may pass one in) and only the unit loads change between evaluations.

    Parameters
    ----------
    rig : Rig
        The rig as built (blind).
    published : tuple of PublishedRow
        The table to fit (:func:`rvcoax.paper_table`).
    fit_output_torques_Nm : tuple of float
        The rows used to fit, by T2; the other rows are predictions.
    parameters : tuple of CalibrationParameter
        Rig-file addresses to fit, each with its bounds and plausible range.
    settings : SweepSettings, optional
        How to solve (default: the beam model).
    prepared : PreparedModel, optional
        A prepared model of ``rig`` to reuse.

    Returns
    -------
    Calibration
        The fitted values, each with its plausibility, the calibrated rig and the fit's residuals.
    """
    if prepared is None and all(p.address.startswith(LOAD_GROUPS) for p in parameters):
        prepared = prepare_model(rig, settings or SweepSettings())
    if prepared is not None and not all(p.address.startswith(LOAD_GROUPS) for p in parameters):
        prepared = None  # a stiffness parameter changes the matrix: assemble per evaluation
    fit_rows = tuple(i for i, r in enumerate(published) if r.case.output_torque_Nm in fit_output_torques_Nm)
    if len(fit_rows) < 2:
        raise ValueError(f"need at least two fitting rows, found {len(fit_rows)} for T2 in {fit_output_torques_Nm}")
    rows = [published[i] for i in fit_rows]
    chosen: dict[str, float] = {}
    alternatives: list[tuple[FittedParameter, ...]] = []
    worst = 0.0
    current = rig
    for shaft in MEASURED_SHAFTS:
        own = [p for p in parameters if p.shaft == shaft]
        if len(own) > 2:
            raise ValueError(f"at most two calibrated parameters per shaft; {shaft} has {len(own)}")
    scale = np.array([p.scale for p in parameters])
    every = _joint_surrogate(rig, parameters, rows, prepared, scale=scale) if prepared is not None else None
    for shaft in MEASURED_SHAFTS:
        own = [p for p in parameters if p.shaft == shaft]
        if not own:
            continue
        joint = None if every is None else (every, _placing(rig, parameters, own, chosen, scale))
        solutions, cost = _fit_shaft(current, own, rows, shaft, prepared, joint=joint)
        worst = max(worst, cost)
        reference = np.array([get_parameter(rig, p.address) for p in own])
        width = np.array([p.plausible[1] - p.plausible[0] for p in own])
        distance = [float(np.sum(((s - reference) / width) ** 2)) for s in solutions]
        order = np.argsort(distance)
        best = solutions[order[0]]
        chosen.update({p.address: float(v) for p, v in zip(own, best)})
        current = with_parameters(current, chosen)
        for k in order[1:]:
            alternatives.append(tuple(FittedParameter(p, float(r), float(v))
                                      for p, r, v in zip(own, reference, solutions[k])))
    fitted = tuple(FittedParameter(p, get_parameter(rig, p.address), chosen[p.address]) for p in parameters
                   if p.address in chosen)
    final = with_parameters(rig, chosen)
    if every is not None:
        _remember_fitted(prepared, rig, parameters, final, scale=scale)
    return Calibration(final, fitted, fit_rows, _fit_residual(final, rows, prepared), tuple(alternatives))


def _placing(rig: Rig, parameters, own, chosen: dict, scale: np.ndarray):
    """x → every parameter, scaled: ``own``'s (one shaft's) values x, the others as fitted so far (``chosen``, read
    when called) or at their reference."""
    mine = [parameters.index(p) for p in own]

    def x_of(x):
        full = np.array([chosen.get(p.address, get_parameter(rig, p.address)) for p in parameters]) / scale
        full[mine] = x
        return full

    return x_of


def _fit_residual(final: Rig, rows: list[PublishedRow], prepared) -> float:
    """The largest relative miss of the calibrated rig at the fitting rows, both shafts from one sweep (the check's
    calibrated sweep then finds its solutions cached)."""
    sweep = run_sweep(final, tuple(r.case for r in rows), prepared=prepared, engineering=False)
    return max(
        float(np.max(np.abs((_row_y(final, rows, s, np.array([c.paths[s].uy_mm for c in sweep.cases]))
                             - _published(rows, s)) / _published(rows, s))))
        for s in MEASURED_SHAFTS
    )
