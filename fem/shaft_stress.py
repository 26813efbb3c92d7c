"""Section forces and nominal stresses of round (hollow) shafts from beam end forces (SI in, MPa out).

Linear algebra that knows nothing of rigs: the end forces of the beam elements
(:func:`rvcoax.fem.beam.end_forces`) give the section forces at both ends of every element; a round
section of outer diameter D and bore d carries them as

* axial stress      σ_ax = N / A,                       A = π (D² − d²)/4
* bending stress    σ_b = √(M_y² + M_z²) / W_b,          W_b = π (D⁴ − d⁴)/(32 D)  (resultant of both planes)
* torsional shear   τ_t = T / W_t,                       W_t = 2 W_b
* transverse shear  τ_q = Q S / (I b) at the neutral axis, Q = √(Q_y² + Q_z²), S = (D³ − d³)/12, b = D − d,
  I = π (D⁴ − d⁴)/64 (solid: 4/3 Q/A; thin tube: 2 Q/A)
* von Mises         σ_v = max(√((|σ_ax| + σ_b)² + 3 τ_t²), √(σ_ax² + 3 (τ_t + τ_q)²)): the outer fibre of
  largest bending, and the surface point on the neutral axis where the transverse shear adds to the torsional
  shear (a conservative bound there: the transverse shear at the surface is below its neutral-axis mean).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["SectionForces", "SectionStresses", "section_forces", "section_stresses"]


@dataclass(frozen=True)
class SectionForces:
    """Section forces at stations (N, N·m): axial force (tension positive), the two shear forces, torque and the
    two bending moments, in the element's local axes. Arrays of one shape."""

    axial_N: np.ndarray
    shear_y_N: np.ndarray
    shear_z_N: np.ndarray
    torque_Nm: np.ndarray
    moment_y_Nm: np.ndarray
    moment_z_Nm: np.ndarray

    @property
    def bending_moment_Nm(self) -> np.ndarray:
        """Resultant bending moment √(M_y² + M_z²)."""
        return np.hypot(self.moment_y_Nm, self.moment_z_Nm)

    @property
    def shear_force_N(self) -> np.ndarray:
        """Resultant transverse shear force √(Q_y² + Q_z²)."""
        return np.hypot(self.shear_y_N, self.shear_z_N)


@dataclass(frozen=True)
class SectionStresses:
    """Nominal stresses (MPa) at stations; σ_ax signed (tension positive), the others magnitudes."""

    axial_MPa: np.ndarray
    bending_MPa: np.ndarray
    torsion_MPa: np.ndarray
    transverse_shear_MPa: np.ndarray
    von_mises_MPa: np.ndarray


def section_forces(end_forces: np.ndarray) -> tuple[SectionForces, SectionForces]:
    """The section forces at end a and at end b of each element, from its local end forces (n, 12)."""
    f = np.asarray(end_forces, dtype=float)

    def at(block: np.ndarray) -> SectionForces:
        return SectionForces(*(block[:, i] for i in range(6)))

    return at(-f[:, :6]), at(f[:, 6:])


def section_stresses(forces: SectionForces, outer_diameter_m, inner_diameter_m=0.0) -> SectionStresses:
    """Nominal stresses of round sections (outer diameter D, bore d, m) under ``forces``; see the module text."""
    D = np.asarray(outer_diameter_m, dtype=float)
    d = np.broadcast_to(np.asarray(inner_diameter_m, dtype=float), D.shape)
    if np.any(D <= 0.0) or np.any(d < 0.0) or np.any(d >= D):
        raise ValueError("sections need 0 ≤ bore < outer diameter")
    area = np.pi / 4.0 * (D**2 - d**2)
    inertia = np.pi / 64.0 * (D**4 - d**4)
    w_b = 2.0 * inertia / D
    axial = forces.axial_N / area
    bending = forces.bending_moment_Nm / w_b
    torsion = np.abs(forces.torque_Nm) / (2.0 * w_b)
    transverse = forces.shear_force_N * (D**3 - d**3) / 12.0 / (inertia * (D - d))
    outer_fibre = np.sqrt((np.abs(axial) + bending) ** 2 + 3.0 * torsion**2)
    neutral_axis = np.sqrt(axial**2 + 3.0 * (torsion + transverse) ** 2)
    mpa = 1e-6
    return SectionStresses(axial * mpa, bending * mpa, torsion * mpa, transverse * mpa,
                           np.maximum(outer_fibre, neutral_axis) * mpa)
