"""Seeded sampling of toleranced parameters: points in the unit cube, then each parameter's distribution.

A design is first drawn in the unit hypercube (0, 1)^d: Latin hypercube (``lhs``) or scrambled
Sobol' (``sobol``, balanced only for a power of two) from :mod:`scipy.stats.qmc`, or plain
pseudo-random (``random``). Each column is then mapped through the inverse CDF (quantile
function) of its parameter's distribution. The same seed gives the same sample, on any machine
and with any number of workers.

Distributions (all values in the unit of the parameter's key):

``normal``            mean, std
``uniform``           low, high
``truncated_normal``  mean, std, low, high (the normal law restricted to [low, high])

Unit-cube points are kept inside [2^-53, 1 − 2^-53], so a normal draw stays within ±8.2 std.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats
from scipy.stats import qmc

__all__ = ["DISTRIBUTIONS", "Distribution", "EDGE", "SAMPLING_METHODS", "sample_values", "to_values", "unit_design"]

DISTRIBUTIONS = ("normal", "uniform", "truncated_normal")
SAMPLING_METHODS = ("lhs", "sobol", "random")  # Latin hypercube, scrambled Sobol' points, plain random
EDGE = 2.0**-53


@dataclass(frozen=True)
class Distribution:
    """A one-dimensional distribution with a quantile function.

    Parameters
    ----------
    kind : str
        ``normal``, ``uniform`` or ``truncated_normal``.
    mean, std : float or None
        Normal and truncated normal: the underlying normal law.
    low, high : float or None
        Uniform and truncated normal: the support.
    """

    kind: str
    mean: float | None = None
    std: float | None = None
    low: float | None = None
    high: float | None = None

    def __post_init__(self) -> None:
        needed = {"normal": ("mean", "std"), "uniform": ("low", "high"),
                  "truncated_normal": ("mean", "std", "low", "high")}
        if self.kind not in needed:
            raise ValueError(f"distribution must be one of {', '.join(DISTRIBUTIONS)}, got {self.kind!r}")
        missing = [key for key in needed[self.kind] if getattr(self, key) is None]
        if missing:
            raise ValueError(f"a {self.kind} distribution needs {', '.join(missing)}")
        extra = [key for key in ("mean", "std", "low", "high")
                 if key not in needed[self.kind] and getattr(self, key) is not None]
        if extra:
            raise ValueError(f"a {self.kind} distribution takes no {', '.join(extra)}")
        for key in needed[self.kind]:
            if not math.isfinite(getattr(self, key)):
                raise ValueError(f"{key} must be a finite number, got {getattr(self, key)}")
        if self.std is not None and not self.std > 0:
            raise ValueError(f"std must be > 0, got {self.std}")
        if self.low is not None and not self.high > self.low:
            raise ValueError(f"high ({self.high}) must be greater than low ({self.low})")
        if self.kind == "truncated_normal" and self.probability_mass_kept < 1e-12:
            raise ValueError(f"[low, high] = [{self.low}, {self.high}] holds almost none of the normal law "
                             f"(mean {self.mean}, std {self.std})")

    @property
    def _law(self):
        if self.kind == "normal":
            return stats.norm(loc=self.mean, scale=self.std)
        if self.kind == "uniform":
            return stats.uniform(loc=self.low, scale=self.high - self.low)
        a, b = (self.low - self.mean) / self.std, (self.high - self.mean) / self.std
        return stats.truncnorm(a, b, loc=self.mean, scale=self.std)

    @property
    def probability_mass_kept(self) -> float:
        """Truncated normal: the share of the normal law inside [low, high]."""
        a, b = (self.low - self.mean) / self.std, (self.high - self.mean) / self.std
        return float(stats.norm.cdf(b) - stats.norm.cdf(a))

    @property
    def bounded(self) -> bool:
        return self.kind != "normal"

    def quantile(self, u) -> np.ndarray:
        """Values at cumulative probabilities ``u`` (clipped to [2^-53, 1 − 2^-53])."""
        return self._law.ppf(np.clip(np.asarray(u, dtype=float), EDGE, 1.0 - EDGE))

    def cdf(self, x) -> np.ndarray:
        return self._law.cdf(x)

    @property
    def extremes(self) -> tuple[float, float]:
        """The smallest and largest value a sample can take."""
        low, high = self.quantile([0.0, 1.0])
        return float(low), float(high)

    def describe(self) -> str:
        if self.kind == "normal":
            return f"normal(mean {self.mean:g}, std {self.std:g})"
        if self.kind == "uniform":
            return f"uniform({self.low:g} .. {self.high:g})"
        return f"truncated normal(mean {self.mean:g}, std {self.std:g}, {self.low:g} .. {self.high:g})"


def unit_design(n: int, d: int, method: str = "lhs", seed: int = 0) -> np.ndarray:
    """``n`` points in the unit hypercube (0, 1)^d, seeded.

    Raises
    ------
    ValueError
        Unknown method, n < 1, or ``sobol`` with an n that is not a power of two (a Sobol' design
        is balanced only then).
    """
    if n < 1:
        raise ValueError(f"the number of samples must be at least 1, got {n}")
    if d < 1:
        raise ValueError("at least one toleranced parameter is needed")
    rng = np.random.default_rng(seed)
    if method == "lhs":
        points = qmc.LatinHypercube(d, rng=rng).random(n)
    elif method == "sobol":
        if n & (n - 1):
            raise ValueError(f"Sobol' sampling needs a power of two samples (e.g. {1 << n.bit_length()}), got {n}")
        points = qmc.Sobol(d, scramble=True, rng=rng).random_base2(n.bit_length() - 1)
    elif method == "random":
        points = rng.random((n, d))
    else:
        raise ValueError(f"sampling must be one of {', '.join(SAMPLING_METHODS)}, got {method!r}")
    return np.clip(points, EDGE, 1.0 - EDGE)


def to_values(distributions: tuple[Distribution, ...], unit_points: np.ndarray) -> np.ndarray:
    """Map unit-cube points (n, d) to parameter values (n, d), column j through distribution j.

    Parameters
    ----------
    distributions : tuple of Distribution
        One per column.
    unit_points : ndarray, shape (n, d)
        Points in the open unit cube.

    Returns
    -------
    ndarray, shape (n, d)
        Parameter values.
    """
    unit_points = np.atleast_2d(unit_points)
    if unit_points.shape[1] != len(distributions):
        raise ValueError(f"{unit_points.shape[1]} columns for {len(distributions)} distributions")
    return np.column_stack([dist.quantile(unit_points[:, j]) for j, dist in enumerate(distributions)])


def sample_values(distributions: tuple[Distribution, ...], n: int, method: str = "lhs", seed: int = 0) -> np.ndarray:
    """``n`` seeded samples (n, d) of the parameters' distributions.

    Parameters
    ----------
    distributions : tuple of Distribution
        One per parameter (normal, uniform or truncated normal, in the parameter's unit).
    n : int
        Samples.
    method : {"lhs", "sobol", "random"}
        Latin hypercube, scrambled Sobol' points or plain random.
    seed : int
        The same seed gives the same samples.

    Returns
    -------
    ndarray, shape (n, d)
        Parameter values.
    """
    return to_values(distributions, unit_design(n, len(distributions), method, seed))
