"""Synthetic measured data with a hidden effect, to test the workflow on data where the answer is known.

The data come from the rig *with* the effect (a real sweep), at a stated size relative to the
signal, plus Gaussian noise; the workflow then starts from the rig *without* it.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.studies.discrepancy.measured import MeasuredData
from rvcoax.results.studies.discrepancy.responses import Observation, solve_full_paths
from rvcoax.results.sweep import SweepSettings

__all__ = ["BEAM", "effect_size_for", "observation_layout", "synthetic_data"]

BEAM = SweepSettings()


def observation_layout(cases, stations_per_shaft: int, lengths_mm: dict[str, float], schema: str) -> MeasuredData:
    """An empty data set (values zero) with the observations of ``schema`` at evenly spaced stations."""
    case_index, shaft, x = [], [], []
    for i, _ in enumerate(cases):
        for s in MEASURED_SHAFTS:
            if schema == "table":
                case_index.append(i), shaft.append(s), x.append(np.nan)
            else:
                for station in np.linspace(0.0, lengths_mm[s], stations_per_shaft):
                    case_index.append(i), shaft.append(s), x.append(float(station))
    n = len(case_index)
    return MeasuredData(schema=schema, cases=tuple(cases), case_index=np.array(case_index), shaft=np.array(shaft), x_mm=np.array(x), value_mm=np.zeros(n), sigma_mm=None,
                        source="synthetic")


def _relative_change(delta_obs: np.ndarray, signal_obs: np.ndarray, shaft: np.ndarray) -> float:
    """Largest over the shafts of RMS(change) / RMS(signal)."""
    ratios = []
    for s in MEASURED_SHAFTS:
        mask = shaft == s
        signal = np.sqrt(np.mean(signal_obs[mask] ** 2))
        if signal > 0:
            ratios.append(np.sqrt(np.mean(delta_obs[mask] ** 2)) / signal)
    return float(max(ratios)) if ratios else 0.0


def effect_size_for(effect, rig, cases, template: MeasuredData, fraction: float, *,  # noqa: PLR0913
                    settings: SweepSettings = BEAM) -> float:
    """Parameter value (within the effect's bounds, sign of its typical value) at which the effect changes
    the observations of ``template`` by ``fraction`` of the signal (RMS, on the shaft it changes most)."""
    base_paths, layout = solve_full_paths(rig, cases, settings)
    observe = Observation(template, layout)
    signal = observe(base_paths)
    parameter = effect.parameters[0]
    bound = parameter.upper if parameter.typical >= 0 else parameter.lower

    def excess(value: float) -> float:
        paths, _ = solve_full_paths(effect.apply(rig, [value] + [0.0] * (len(effect.parameters) - 1)), cases, settings)
        return _relative_change(observe(paths) - signal, signal, template.shaft) - fraction

    if effect.linear:
        per_unit = excess(parameter.typical) + fraction
        return float(np.clip(parameter.typical * fraction / per_unit, parameter.lower, parameter.upper)) \
            if per_unit > 0 else parameter.typical
    if excess(bound) <= 0:
        return float(bound)
    return float(brentq(excess, 0.0, bound, xtol=1e-6 * max(abs(bound), 1e-9)))


def synthetic_data(rig, template: MeasuredData, noise_fraction: float, seed: int,  # noqa: PLR0913
                   settings: SweepSettings = BEAM, *, with_sigma: bool = False) -> MeasuredData:
    """Data of ``rig`` at the observations of ``template`` plus Gaussian noise (σ = ``noise_fraction`` × RMS
    of each shaft's values)."""
    paths, layout = solve_full_paths(rig, template.cases, settings)
    values = Observation(template, layout)(paths)
    rng = np.random.default_rng(seed)
    sigma = np.zeros_like(values)
    for s in MEASURED_SHAFTS:
        mask = template.shaft == s
        sigma[mask] = noise_fraction * np.sqrt(np.mean(values[mask] ** 2))
    noisy = values + rng.normal(size=values.size) * sigma
    if template.schema == "table":
        noisy = np.abs(noisy)
    return MeasuredData(schema=template.schema, cases=template.cases, case_index=template.case_index, shaft=template.shaft, x_mm=template.x_mm, value_mm=noisy,
                        sigma_mm=sigma if with_sigma else None, source=f"synthetic (noise {100 * noise_fraction:g} %, seed {seed})")

