"""Quantities along a measured shaft path: Y(x), Y_max, β = arcsin(Y_max / L), true tilt, end slopes and offsets."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["ShaftPathResult", "beta_from_y_deg"]


@dataclass(frozen=True)
class ShaftPathResult:
    """One shaft path in one load case (lengths in mm, angles in degrees).

    Attributes
    ----------
    station_mm : (n,) array
        Distance from the path's input-side end, 0 … L.
    uy_mm : (n,) array
        Signed vertical displacement (Y up).
    length_mm : float
        Path length L.
    rotation_z_rad : (n,) array
        Cross-section rotation about z at the stations (rad).
    """

    station_mm: np.ndarray
    uy_mm: np.ndarray
    length_mm: float
    rotation_z_rad: np.ndarray

    @property
    def index_of_max(self) -> int:
        return int(np.argmax(np.abs(self.uy_mm)))

    @property
    def y_max_mm(self) -> float:
        """Largest |u_y| along the path (the paper's Y)."""
        return float(np.abs(self.uy_mm[self.index_of_max]))

    @property
    def y_max_signed_mm(self) -> float:
        return float(self.uy_mm[self.index_of_max])

    @property
    def station_of_max_mm(self) -> float:
        return float(self.station_mm[self.index_of_max])

    @property
    def beta_deg(self) -> float:
        """Paper 000's tilt β = arcsin(Y_max / L)."""
        return float(np.degrees(np.arcsin(self.y_max_mm / self.length_mm)))

    @property
    def fitted_tilt_deg(self) -> float:
        """Slope of the least-squares line through u_y(x), as an angle (signed)."""
        slope = np.polyfit(self.station_mm, self.uy_mm, 1)[0]
        return float(np.degrees(np.arctan(slope)))

    @property
    def fitted_tilt_urad(self) -> float:
        """The true tilt: slope of the least-squares line through u_y(x), as an angle in µrad (signed)."""
        slope = np.polyfit(self.station_mm, self.uy_mm, 1)[0]
        return float(np.arctan(slope) * 1e6)

    @property
    def beta_urad(self) -> float:
        """Paper 000's β = arcsin(Y_max / L) in µrad."""
        return float(np.arcsin(self.y_max_mm / self.length_mm) * 1e6)

    @property
    def end_slopes_urad(self) -> tuple[float, float]:
        """Slope of the shaft (its cross-section rotation about z) at the path's start and end, µrad (signed)."""
        return float(self.rotation_z_rad[0] * 1e6), float(self.rotation_z_rad[-1] * 1e6)

    @property
    def end_offsets_um(self) -> tuple[float, float]:
        """u_y at the path's start and end, µm (signed, +Y up)."""
        return float(self.uy_mm[0] * 1e3), float(self.uy_mm[-1] * 1e3)

    @property
    def end_rotations_deg(self) -> tuple[float, float]:
        """Cross-section rotation about z at the two path ends (signed, degrees)."""
        return float(np.degrees(self.rotation_z_rad[0])), float(np.degrees(self.rotation_z_rad[-1]))


def beta_from_y_deg(y_mm, length_mm):
    """β = arcsin(Y / L) in degrees (vectorised)."""
    return np.degrees(np.arcsin(np.asarray(y_mm) / length_mm))
