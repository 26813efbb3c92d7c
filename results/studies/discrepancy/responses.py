"""What the model predicts for the measured observations, and how each candidate effect changes it.

Everything is computed on the *full signed paths*: for every load case and both shafts, u_y at the
rig's path stations. An observation operator then maps full paths to what was measured: an
interpolation to the measured stations (paths schema, linear) or the largest |u_y| along the path
(table schema, nonlinear). A linear effect is therefore exactly linear on the full paths even when
the observations (|Y_max|) are not.

A candidate's response is computed once per base rig: for a linear effect one sweep per
parameter at its typical value; for a one-parameter nonlinear effect the full paths on a grid of
parameter values spanning its physical bounds, interpolated with a cubic spline. The workflow fits
on these responses (cheap) and confirms the result with the true model (:mod:`workflow`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.studies.discrepancy.measured import MeasuredData
from rvcoax.results.sweep import SweepSettings, run_sweep

__all__ = ["COARSE_POINTS", "EffectResponse", "GRID_POINTS", "Observation", "PathLayout", "effect_response",
           "engine_response", "full_paths", "parameter_grid", "solve_full_paths"]

GRID_POINTS = 11


@dataclass(frozen=True)
class PathLayout:
    """Where the full paths are: ``(case, shaft, station)`` flattened; stations in mm from the input-side end."""

    n_cases: int
    stations_mm: dict[str, np.ndarray]
    length_mm: dict[str, float]

    def block(self, case: int, shaft: str) -> slice:
        n_in = self.stations_mm["input"].size
        n_out = self.stations_mm["output"].size
        start = case * (n_in + n_out) + (0 if shaft == "input" else n_in)
        return slice(start, start + (n_in if shaft == "input" else n_out))

    @property
    def size(self) -> int:
        return self.n_cases * sum(s.size for s in self.stations_mm.values())


def full_paths(sweep) -> tuple[np.ndarray, PathLayout]:
    """Signed u_y (mm) of every case and shaft of a sweep, flattened, and its layout."""
    first = sweep.cases[0].paths
    layout = PathLayout(len(sweep.cases), {s: np.asarray(first[s].station_mm, float) for s in MEASURED_SHAFTS},
                        {s: float(first[s].length_mm) for s in MEASURED_SHAFTS})
    return np.concatenate([np.concatenate([c.paths[s].uy_mm for s in MEASURED_SHAFTS]) for c in sweep.cases]), layout


def solve_full_paths(rig, cases, settings: SweepSettings) -> tuple[np.ndarray, PathLayout]:
    """Full paths of ``rig`` for ``cases`` (a real sweep)."""
    return full_paths(run_sweep(rig, cases, settings))


class Observation:
    """Maps full paths to the measured quantities of ``data``."""

    def __init__(self, data: MeasuredData, layout: PathLayout):
        self.data = data
        self.layout = layout
        if data.schema == "paths":
            import scipy.sparse as sp

            rows, cols, vals = [], [], []
            for shaft in MEASURED_SHAFTS:  # one spline evaluation per shaft for all its observations (not per row)
                where = np.flatnonzero(data.shaft == shaft)
                if not where.size:
                    continue
                stations = layout.stations_mm[shaft]
                weights = _spline_weights(stations, data.x_mm[where])  # (rows, stations)
                starts = np.array([layout.block(int(c), shaft).start for c in data.case_index[where]])
                rows.append(np.repeat(where, stations.size))
                cols.append((starts[:, None] + np.arange(stations.size)).ravel())
                vals.append(weights.ravel())
            rows, cols, vals = (np.concatenate(a) if a else np.zeros(0) for a in (rows, cols, vals))
            self.matrix = sp.csr_matrix((vals, (rows.astype(int), cols.astype(int))), shape=(data.n, layout.size))
        else:
            self.blocks = [layout.block(int(c), s) for c, s in zip(data.case_index, data.shaft)]
            self._n_input = layout.stations_mm["input"].size
            self._is_input = data.shaft == "input"

    def __call__(self, paths: np.ndarray) -> np.ndarray:
        if self.data.schema == "paths":
            return self.matrix @ paths
        full = np.abs(paths.reshape(self.layout.n_cases, -1))  # |Y_max| of every case and shaft at once
        first, second = full[:, : self._n_input].max(axis=1), full[:, self._n_input:].max(axis=1)
        return np.where(self._is_input, first[self.data.case_index], second[self.data.case_index])


    def jacobian(self, paths: np.ndarray):
        """d(observations)/d(paths) at ``paths`` (sparse): the interpolation matrix for paths; for a table, sign(Y)
        at the station of each |Y_max|."""
        if self.data.schema == "paths":
            return self.matrix
        import scipy.sparse as sp

        full = paths.reshape(self.layout.n_cases, -1)
        n_in = self._n_input
        first = np.argmax(np.abs(full[:, :n_in]), axis=1)
        second = n_in + np.argmax(np.abs(full[:, n_in:]), axis=1)
        case = self.data.case_index
        column = np.where(self._is_input, first[case], second[case])
        flat = case * full.shape[1] + column
        return sp.csr_matrix((np.sign(paths[flat]) + (paths[flat] == 0), (np.arange(self.data.n), flat)),
                             shape=(self.data.n, paths.size))


def _spline_weights(stations: np.ndarray, x) -> np.ndarray:
    """Weights w with CubicSpline(stations, values)(x) = w · values (the not-a-knot spline is linear in the
    values); ``x`` a station or an array of them (then one row of weights per station)."""
    identity = np.eye(stations.size)
    return CubicSpline(stations, identity, axis=0)(x)


@dataclass(frozen=True)
class EffectResponse:
    """How one candidate effect changes the full paths.

    ``delta(values)`` returns the change of the full paths for parameter values ``values``.
    """

    effect: object
    kind: str  # "linear" | "grid"
    columns: np.ndarray | None = None  # linear: (n_params, n_full), change per unit of each parameter
    grid: np.ndarray | None = None  # grid: parameter values
    grid_paths: np.ndarray | None = None  # grid: (n_grid, n_full) change at each grid value
    bounds: tuple[np.ndarray, np.ndarray] | None = None  # where the response is known
    unit: np.ndarray | None = None  # (n_params or n_grid, 7, n_path): the change of the unit paths, when known

    def delta(self, values) -> np.ndarray:
        values = np.atleast_1d(np.asarray(values, dtype=float))
        if self.kind == "linear":
            return values @ self.columns
        return self._spline(np.clip(values[0], self.grid[0], self.grid[-1]))

    def unit_at(self, values) -> np.ndarray | None:
        """The change of the unit paths (n_unit_loads, n_path) at ``values``; None when only the data's cases were solved."""
        if self.unit is None:
            return None
        values = np.atleast_1d(np.asarray(values, dtype=float))
        if self.kind == "linear":
            return np.tensordot(values, self.unit, axes=1)
        spline = self.__dict__.get("_cached_unit_spline")
        if spline is None:
            spline = CubicSpline(self.grid, self.unit.reshape(self.grid.size, -1), axis=0)
            object.__setattr__(self, "_cached_unit_spline", spline)
        return spline(np.clip(values[0], self.grid[0], self.grid[-1])).reshape(self.unit.shape[1:])

    def extremes(self) -> list[np.ndarray]:
        """Parameter vectors at the ends of the physical range (one parameter at a time)."""
        if self.kind == "grid":
            return [np.array([self.grid[0]]), np.array([self.grid[-1]])]
        out = []
        for i, parameter in enumerate(self.effect.parameters):
            for extreme in (parameter.lower, parameter.upper):
                values = np.zeros(self.n_params)
                values[i] = extreme
                out.append(values)
        return out

    def derivative(self, values) -> np.ndarray:
        """d(full paths)/d(values), (n_params, n_full)."""
        if self.kind == "linear":
            return self.columns
        derivative = self.__dict__.get("_cached_derivative")
        if derivative is None:
            derivative = self._spline.derivative()
            object.__setattr__(self, "_cached_derivative", derivative)
        value = np.atleast_1d(np.asarray(values, dtype=float))[0]
        inside = self.grid[0] <= value <= self.grid[-1]
        return derivative(np.clip(value, self.grid[0], self.grid[-1]))[None, :] * (1.0 if inside else 0.0)

    @property
    def _spline(self):
        spline = self.__dict__.get("_cached_spline")
        if spline is None:
            spline = CubicSpline(self.grid, self.grid_paths, axis=0)
            object.__setattr__(self, "_cached_spline", spline)
        return spline

    @property
    def n_params(self) -> int:
        return len(self.effect.parameters)

    def search_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Where the fit may look: the grid for a nonlinear effect; ±10 × the physical bounds for a linear one."""
        if self.kind == "grid":
            return np.array([self.grid[0]]), np.array([self.grid[-1]])
        lower = np.array([p.lower for p in self.effect.parameters], float)
        upper = np.array([p.upper for p in self.effect.parameters], float)
        span = np.maximum(np.abs(lower), np.abs(upper))
        return -10.0 * span, 10.0 * span

    def start_values(self) -> list[np.ndarray]:
        """Starting points for the fit: zero (linear), every grid value (nonlinear)."""
        if self.kind == "grid":
            return [np.array([g]) for g in self.grid]
        return [np.zeros(self.n_params)]


def parameter_grid(parameter, points: int = GRID_POINTS) -> np.ndarray:
    """Grid values spanning a parameter's physical bounds, zero included (denser near zero for a one-sided one)."""
    if parameter.lower == 0.0 or parameter.upper == 0.0:  # e.g. a gap: denser where the response bends most
        other = parameter.upper if parameter.lower == 0.0 else parameter.lower
        grid = other * np.linspace(0.0, 1.0, points) ** 2
    else:
        grid = np.linspace(parameter.lower, parameter.upper, points)
    grid = np.unique(np.concatenate([grid, [0.0]]))
    return grid[(grid >= parameter.lower) & (grid <= parameter.upper)]


def effect_response(effect, rig, cases, settings: SweepSettings, base_paths: np.ndarray) -> EffectResponse:
    """Compute a candidate's response around ``rig`` (real sweeps; :func:`engine_response` is the fast way)."""
    parameters = effect.parameters
    if effect.linear:
        columns = []
        for i, parameter in enumerate(parameters):
            values = np.zeros(len(parameters))
            values[i] = parameter.typical
            paths, _ = solve_full_paths(effect.apply(rig, values), cases, settings)
            columns.append((paths - base_paths) / parameter.typical)
        return EffectResponse(effect, "linear", columns=np.array(columns))
    if len(parameters) != 1:
        raise ValueError(f"{effect.name}: nonlinear effects with more than one parameter are not supported")
    grid = parameter_grid(parameters[0])
    rows = []
    for value in grid:
        if value == 0.0:
            rows.append(np.zeros_like(base_paths))
            continue
        paths, _ = solve_full_paths(effect.apply(rig, [value]), cases, settings)
        rows.append(paths - base_paths)
    return EffectResponse(effect, "grid", grid=grid, grid_paths=np.array(rows))


COARSE_POINTS = 5


def engine_response(effect, engine, cases, visible=None) -> EffectResponse:
    """A candidate's response on the factorised base model (:mod:`engine`).

    Linear effects: one unit-path change per parameter. Nonlinear ones: a grid over the physical
    bounds, each point exact (a clearance on a linear rig by its condensed 2-D law); anything solved
    by real sweeps first at its bound only, and on a coarse grid only when ``visible(delta_full_paths)``
    says the data can see it there.
    """
    parameters = effect.parameters
    base_unit = engine.unit_paths
    if engine.supports(effect) and effect.linear:
        unit = []
        for i, parameter in enumerate(parameters):
            values = np.zeros(len(parameters))
            values[i] = parameter.typical
            unit.append(engine.unit_change([(effect, values)]) / parameter.typical)
        unit = np.array(unit)
        columns = np.array([engine.full_paths(u, cases) for u in unit])
        return EffectResponse(effect, "linear", columns=columns, unit=unit)
    if len(parameters) != 1:
        raise ValueError(f"{effect.name}: nonlinear effects with more than one parameter are not supported")
    parameter = parameters[0]
    if engine.supports(effect) or (engine.linear and effect.response != "clearance"):  # exact, or solved anew
        grid = parameter_grid(parameter, GRID_POINTS if engine.supports(effect) else COARSE_POINTS)
        unit = []
        for value in grid:
            if value == 0.0:
                unit.append(np.zeros_like(base_unit))
            elif engine.supports(effect):
                unit.append(engine.unit_change([(effect, [value])]))
            else:
                unit.append(engine.swept_unit_paths(effect.apply(engine.rig, [value])) - base_unit)
        unit = np.array(unit)
        return EffectResponse(effect, "grid", grid=grid, grid_paths=np.array([engine.full_paths(u, cases) for u in unit]),
                              unit=unit)
    if engine.linear and effect.response == "clearance":  # exact and cheap: the law condensed to the bearing
        base = engine.full_paths(base_unit, cases)
        grid = parameter_grid(parameter)
        rows = [engine.clearance_paths(effect.location, value, cases) - base if value != 0.0 else np.zeros_like(base)
                for value in grid]
        return EffectResponse(effect, "grid", grid=grid, grid_paths=np.array(rows))
    base = engine.full_paths(base_unit, cases) if engine.linear else engine.swept_paths(engine.rig, cases)
    bound = parameter.upper if abs(parameter.upper) >= abs(parameter.lower) else parameter.lower
    far = engine.swept_paths(effect.apply(engine.rig, [bound]), cases) - base
    grid = np.array(sorted({0.0, bound}))
    rows = {0.0: np.zeros_like(base), bound: far}
    if visible is None or visible(far):
        grid = parameter_grid(parameter, COARSE_POINTS)
        for value in grid:
            if value not in rows:
                rows[value] = engine.swept_paths(effect.apply(engine.rig, [value]), cases) - base
    return EffectResponse(effect, "grid", grid=grid, grid_paths=np.array([rows[v] for v in grid]))
