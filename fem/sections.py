"""Cross-section properties of solid and hollow round shafts."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["CircularSection"]


@dataclass(frozen=True)
class CircularSection:
    """Solid (``inner_diameter_m == 0``) or hollow round section.

    Parameters
    ----------
    outer_diameter_m : float
        Outer diameter in m.
    inner_diameter_m : float
        Bore diameter in m; 0 for a solid section.
    """

    outer_diameter_m: float
    inner_diameter_m: float = 0.0

    def __post_init__(self) -> None:
        if not self.outer_diameter_m > 0.0:
            raise ValueError(f"outer diameter must be > 0, got {self.outer_diameter_m}")
        if not 0.0 <= self.inner_diameter_m < self.outer_diameter_m:
            raise ValueError(
                f"inner diameter must be in [0, outer) = [0, {self.outer_diameter_m}), "
                f"got {self.inner_diameter_m}"
            )

    @property
    def area_m2(self) -> float:
        return np.pi / 4.0 * (self.outer_diameter_m**2 - self.inner_diameter_m**2)

    @property
    def second_moment_m4(self) -> float:
        """Area moment of inertia about any diameter, I = π (D⁴ − d⁴) / 64."""
        return np.pi / 64.0 * (self.outer_diameter_m**4 - self.inner_diameter_m**4)

    @property
    def polar_moment_m4(self) -> float:
        """Torsion constant of a round section, J = 2 I."""
        return 2.0 * self.second_moment_m4

    def shear_coefficient(self, poisson: float) -> float:
        """Timoshenko shear coefficient κ of a (hollow) circle after Cowper (1966).

        κ = 6 (1 + ν)(1 + m²)² / [(7 + 6ν)(1 + m²)² + (20 + 12ν) m²],  m = d / D.
        """
        m2 = (self.inner_diameter_m / self.outer_diameter_m) ** 2
        return 6.0 * (1.0 + poisson) * (1.0 + m2) ** 2 / (
            (7.0 + 6.0 * poisson) * (1.0 + m2) ** 2 + (20.0 + 12.0 * poisson) * m2
        )
