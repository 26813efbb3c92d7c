"""The measured data as the model sees them: what the stages of the workflow share."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Observed"]


@dataclass(frozen=True, eq=False)
class Observed:
    """The observations, their σ and the base model's paths, read through one observation operator.

    Attributes
    ----------
    data : MeasuredData
        The measurements.
    sigma : ndarray
        σ of every observation (mm): the noise with the model-form allowance.
    base_paths : ndarray
        The base model's full paths (every case, shaft and grid station, flattened).
    observe : Observation
        Full paths → the value of every observation (mm).
    rows : ndarray of bool
        The observations used to fit (the others are held out).
    from_rest : bool
        Y is read from the rig at rest (``paths.measured_from = "aligned_at_rest"``).
    engine : Engine or None
        The factorised base model (None when a library was given without one).
    noise : NoiseEstimate or None
        How σ was obtained (its degrees of freedom: :meth:`dof`); None counts σ as known.
    """

    data: object
    sigma: np.ndarray
    base_paths: np.ndarray
    observe: object
    rows: np.ndarray
    from_rest: bool
    engine: object = None
    noise: object = None

    def dof(self, rows: np.ndarray | None = None) -> float:
        """Degrees of freedom of the σ² that scales the observations ``rows`` (every one when None): ∞ for a known σ."""
        return np.inf if self.noise is None else self.noise.degrees_of_freedom(rows, self.data.shaft)

    @property
    def before(self) -> np.ndarray:
        """The base model's value of every observation (mm)."""
        return self.observe(self.base_paths)

    @property
    def scaled_before(self) -> np.ndarray:
        """(measured − base model) / σ for every observation."""
        return (self.data.value_mm - self.before) / self.sigma
