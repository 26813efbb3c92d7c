"""Global sensitivity of an output to toleranced parameters (SALib): Sobol' indices and Morris screening.

Both designs are drawn in the unit hypercube and mapped through each parameter's distribution
(:func:`rvcoax.results.studies.sampling.to_values`), so the indices refer to the parameters as they scatter.

**Sobol'** (Saltelli's scheme, Sobol' sequence, first and total order): ``n`` base points give
n (d + 2) model runs. S1_i is the share of the output variance explained by parameter i alone;
ST_i the share it has a part in, alone or with others (ST_i − S1_i: interactions). Confidence
half-widths come from bootstrap resampling of the base points.

**Morris** (elementary effects, ``r`` trajectories, r (d + 1) runs, 4 levels): a cheap screening.
μ*_i is the mean absolute change of the output when parameter i moves by 2/3 of its range in
probability (for a normal law: of its central 99.73 %, ±3 std); σ_i is large when the effect
depends on the other parameters (nonlinearity or interaction).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from SALib.analyze import morris as morris_analysis
from SALib.analyze import sobol as sobol_analysis
from SALib.sample import morris as morris_sampling
from SALib.sample import sobol as sobol_sampling

from rvcoax.results.studies.sampling import EDGE, Distribution, to_values

__all__ = ["BOOTSTRAP_RESAMPLES", "MORRIS_LEVELS", "MorrisIndices", "NORMAL_RANGE", "SENSITIVITY_METHODS",
           "SobolIndices", "design_runs", "morris_design", "morris_indices", "morris_values", "sobol_design",
           "sobol_indices"]

SENSITIVITY_METHODS = ("sobol", "morris")  # Sobol' indices (Saltelli design) or Morris screening
MORRIS_LEVELS = 4
NORMAL_RANGE = (0.00135, 0.99865)  # ±3 std of a normal law: Morris levels need a bounded range
BOOTSTRAP_RESAMPLES = 200


def _problem(d: int) -> dict:
    return {"num_vars": d, "names": [f"x{i}" for i in range(d)], "bounds": [[0.0, 1.0]] * d}


def design_runs(method: str, n: int, d: int) -> int:
    """Model runs of a design: n (d + 2) for Sobol' (n base points), n (d + 1) for Morris (n trajectories).

    Parameters
    ----------
    method : {"sobol", "morris"}
        The design.
    n : int
        Base points (Sobol') or trajectories (Morris).
    d : int
        Parameters.

    Returns
    -------
    int
        Model runs.
    """
    return n * (d + 2) if method == "sobol" else n * (d + 1)


def sobol_design(n: int, d: int, seed: int = 0) -> np.ndarray:
    """Saltelli's design for first- and total-order indices: (n (d + 2), d) points in the unit cube.

    ``n`` (base points) must be a power of two, for the Sobol' sequence to be balanced.

    Parameters
    ----------
    n : int
        Base points, a power of two.
    d : int
        Parameters.
    seed : int
        The same seed gives the same design.

    Returns
    -------
    ndarray, shape (n (d + 2), d)
        Points in the open unit cube.
    """
    if n < 2 or n & (n - 1):
        raise ValueError(f"Sobol' indices need a power of two base samples (e.g. {1 << max(n, 2).bit_length()}), got {n}")
    points = sobol_sampling.sample(_problem(d), n, calc_second_order=False, scramble=True, seed=seed)
    return np.clip(points, EDGE, 1.0 - EDGE)


def morris_design(trajectories: int, d: int, seed: int = 0) -> np.ndarray:
    """Morris trajectories on a 4-level grid: (trajectories (d + 1), d) points in [0, 1].

    Parameters
    ----------
    trajectories : int
        Number of one-at-a-time trajectories.
    d, seed
        As for :func:`sobol_design`.

    Returns
    -------
    ndarray, shape (trajectories (d + 1), d)
        Grid points in the unit cube.
    """
    if trajectories < 2:
        raise ValueError(f"Morris screening needs at least 2 trajectories, got {trajectories}")
    return morris_sampling.sample(_problem(d), trajectories, num_levels=MORRIS_LEVELS, seed=seed)


def morris_values(distributions: tuple[Distribution, ...], points: np.ndarray) -> np.ndarray:
    """Morris grid points to parameter values: a normal law spans its central 99.73 %, bounded ones their range.

    Parameters
    ----------
    distributions : tuple of Distribution
        One per column.
    points : ndarray
        Grid points in the unit cube (:func:`morris_design`).

    Returns
    -------
    ndarray
        Parameter values, same shape as ``points``.
    """
    probabilities = np.array(points, dtype=float)
    for j, dist in enumerate(distributions):
        if not dist.bounded:
            probabilities[:, j] = NORMAL_RANGE[0] + probabilities[:, j] * (NORMAL_RANGE[1] - NORMAL_RANGE[0])
    return to_values(distributions, probabilities)


@dataclass(frozen=True)
class SobolIndices:
    """First-order (S1) and total (ST) indices with bootstrap confidence half-widths, per parameter.

    ``constant`` is True when the output did not vary (every index is then NaN).
    """

    S1: np.ndarray
    S1_conf: np.ndarray
    ST: np.ndarray
    ST_conf: np.ndarray
    confidence_level: float
    constant: bool = False


@dataclass(frozen=True)
class MorrisIndices:
    """Morris elementary-effect statistics per parameter (in the output's unit)."""

    mu: np.ndarray
    mu_star: np.ndarray
    mu_star_conf: np.ndarray
    sigma: np.ndarray
    confidence_level: float
    constant: bool = False


def _nan(d: int) -> np.ndarray:
    return np.full(d, np.nan)


def sobol_indices(outputs, d: int, seed: int = 0, confidence_level: float = 0.95,
                  resamples: int = BOOTSTRAP_RESAMPLES) -> SobolIndices:
    """Sobol' indices of ``outputs`` (one per row of :func:`sobol_design`, same order).

    Parameters
    ----------
    outputs : array_like
        One model output per design point.
    d : int
        Parameters.
    seed : int
        Seed of the bootstrap.
    confidence_level : float
        Of the bootstrap intervals.
    resamples : int
        Bootstrap resamples.

    Returns
    -------
    SobolIndices
        First-order S1 and total ST per parameter, with their intervals.
    """
    y = np.asarray(outputs, dtype=float)
    if np.ptp(y) == 0.0:
        return SobolIndices(_nan(d), _nan(d), _nan(d), _nan(d), confidence_level, constant=True)
    # SALib treats seed 0 as "no seed"; seed + 1 keeps the bootstrap reproducible
    found = sobol_analysis.analyze(_problem(d), y, calc_second_order=False, num_resamples=resamples,
                                   conf_level=confidence_level, seed=seed + 1)
    return SobolIndices(np.asarray(found["S1"]), np.asarray(found["S1_conf"]), np.asarray(found["ST"]),
                        np.asarray(found["ST_conf"]), confidence_level)


def morris_indices(points: np.ndarray, outputs, seed: int = 0, confidence_level: float = 0.95,
                   resamples: int = BOOTSTRAP_RESAMPLES) -> MorrisIndices:
    """Morris statistics of ``outputs`` at the unit-cube ``points`` of :func:`morris_design`.

    Parameters
    ----------
    points : ndarray
        The design (:func:`morris_design`).
    outputs : array_like
        One model output per point, same order.
    seed, confidence_level, resamples
        The bootstrap of μ*, as for :func:`sobol_indices`.

    Returns
    -------
    MorrisIndices
        μ, μ* (with its interval) and σ per parameter.
    """
    y = np.asarray(outputs, dtype=float)
    d = points.shape[1]
    if np.ptp(y) == 0.0:
        return MorrisIndices(_nan(d), _nan(d), _nan(d), _nan(d), confidence_level, constant=True)
    found = morris_analysis.analyze(_problem(d), np.asarray(points, dtype=float), y, num_resamples=resamples,
                                    conf_level=confidence_level, num_levels=MORRIS_LEVELS, seed=seed + 1)
    return MorrisIndices(np.asarray(found["mu"]), np.asarray(found["mu_star"]), np.asarray(found["mu_star_conf"]),
                         np.asarray(found["sigma"]), confidence_level)
