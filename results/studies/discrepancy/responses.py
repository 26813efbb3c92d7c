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

__all__ = ["EffectResponse", "GRID_POINTS", "Observation", "PathLayout", "effect_response", "full_paths",
           "solve_full_paths"]

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

    def __call__(self, paths: np.ndarray) -> np.ndarray:
        if self.data.schema == "paths":
            return self.matrix @ paths
        return np.array([np.max(np.abs(paths[b])) for b in self.blocks])


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

    def delta(self, values) -> np.ndarray:
        values = np.atleast_1d(np.asarray(values, dtype=float))
        if self.kind == "linear":
            return values @ self.columns
        return self._spline(np.clip(values[0], self.grid[0], self.grid[-1]))

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


def effect_response(effect, rig, cases, settings: SweepSettings, base_paths: np.ndarray) -> EffectResponse:
    """Compute a candidate's response around ``rig`` (real sweeps)."""
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
    parameter = parameters[0]
    if parameter.lower == 0.0 or parameter.upper == 0.0:  # e.g. a gap: denser where the response bends most
        other = parameter.upper if parameter.lower == 0.0 else parameter.lower
        grid = other * np.linspace(0.0, 1.0, GRID_POINTS) ** 2
    else:
        grid = np.linspace(parameter.lower, parameter.upper, GRID_POINTS)
    grid = np.unique(np.concatenate([grid, [0.0]]))
    grid = grid[(grid >= parameter.lower) & (grid <= parameter.upper)]
    rows = []
    for value in grid:
        if value == 0.0:
            rows.append(np.zeros_like(base_paths))
            continue
        paths, _ = solve_full_paths(effect.apply(rig, [value]), cases, settings)
        rows.append(paths - base_paths)
    return EffectResponse(effect, "grid", grid=grid, grid_paths=np.array(rows))
