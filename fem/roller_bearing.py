"""Cylindrical and tapered roller bearings from their internal geometry: line contact by slicing (SI).

Linear algebra that knows nothing of rigs. The inner ring moves by q = (δx, δy, δz, θy, θz) against
the outer ring (x the bearing axis, as :mod:`rvcoax.fem.ball_bearing`); rings are rigid. Each of the
Z rollers is cut into n laminae (slices) of width w = l/n along its effective length l (ISO/TS 16281's
lamina method). Roller j at azimuth ψ_j, its contact normal n_j inclined by the contact angle α to
the radial direction (α = 0: cylindrical; a tapered roller bearing: its raceway contact angle,
thrust carried in +x), and lamina k at s_k along the roller's axis from its middle. The approach of
the rings at the lamina is the ring motion projected on the normal at the lamina's place
p_jk = s_k e_j + (d_m/2) e_r (e_j the roller axis, perpendicular to n_j in the meridian plane):

    g_jk = ( sin α,  cos α cos ψ,  cos α sin ψ,  −(s_k − (d_m/2) sin α) sin ψ,  (s_k − (d_m/2) sin α) cos ψ ),
    δ_jk = g_jk · q − P_d/2 · cos α − c(s_k),

(P_d the diametral radial clearance, c(s) the crown drop of roller and raceways at s), so radial
motion, axial motion (through sin α) and tilt (through the lever s_k, the bearing's tilt stiffness)
all load the laminae. A lamina carries (Palmgren's line-contact law, Harris & Kotzalas vol. 1 ch. 6:
δ = 3.84·10⁻⁵ Q^0.9 / l^0.8 for one roller–raceway contact, δ in mm, Q in N, l in mm; a roller
between two raceways deflects twice that):

    q_jk = c_l (w / l) l^{8/9} max(δ_jk, 0)^{10/9},   c_l = (2 · 3.84·10⁻⁵)^{−10/9}   (N, mm),

so that a roller pressed evenly over its length carries exactly Palmgren's load, Σ_k q_jk = Q(δ) —
the lamina law of ISO/TS 16281 (each lamina as a slice of the whole roller, not as a short roller).
The force the bearing carries and its tangent are

    F = Σ_jk q_jk g_jk,   K_t = Σ_jk (10/9) q_jk / δ_jk g_jk g_jkᵀ

(exact: the approach is linear in q; symmetric; zero where no lamina is loaded).

Crowning (the drop c(s) of roller and raceway profiles together, at |s| ≤ l/2):

- ``logarithmic``: Lundberg's profile, c(s) = (2 Q_d / (π l E')) ln(1 / (1 − (2s/l)²)), which on an elastic
  half-space gives an even pressure along the roller at its design load Q_d (the laminae here are independent,
  so it softens the roller's ends rather than evening the pressure exactly) (G. Lundberg, "Elastische Berührung zweier
  Halbräume", Forsch. Ing.-Wes. 10 (1939) 201–211; ISO/TS 16281 uses a logarithmic profile);
- ``circular``: c(s) = c_e (2s/l)², an arc dropping c_e at the roller's ends;
- ``none``: a straight roller (edge loading under tilt is then the lamina at the end carrying more).

The contact angle of a tapered roller is one effective angle (its cup angle): the cone's angle and
the rib's share of the roller's equilibrium are lumped into it, and the angle does not change under
load (line contact: the raceway's direction is fixed by the ring).

Contact pressure: the Hertz line contact of the most loaded lamina against the inner raceway,
p = √(q' E' / (2π R)), q' = q/w the load per unit length, 1/R = 2/D_w + 2 cos α /(d_m − D_w cos α)
(ISO 76's static limit is 4 000 MPa for roller bearings).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Literal

import numpy as np

from rvcoax.fem.ball_bearing import BEARING_STEEL_POISSON, BEARING_STEEL_YOUNGS_MODULUS_PA, reduced_modulus

__all__ = ["CROWNINGS", "PALMGREN_LINE_MM", "RollerBearingGeometry", "RollerLoads", "palmgren_roller_deflection",
           "roller_loads"]

PALMGREN_LINE_MM = 3.84e-5
"""Palmgren's constant of one roller–raceway line contact: δ = 3.84e-5 Q^0.9 / l^0.8 (mm, N, mm)."""
CROWNINGS = ("logarithmic", "circular", "none")


def palmgren_roller_deflection(load_n: float, length_m: float) -> float:
    """Approach (m) of the two raceways over one roller of effective length ``length_m`` carrying
    ``load_n`` evenly: twice Palmgren's δ = 3.84e-5 Q^0.9 / l^0.8 (mm, N, mm)."""
    return 2.0 * PALMGREN_LINE_MM * load_n**0.9 / (length_m * 1e3) ** 0.8 * 1e-3


@dataclass(frozen=True)
class RollerBearingGeometry:
    """Internal geometry of a single-row cylindrical or tapered roller bearing (SI).

    Parameters
    ----------
    roller_count : int
        Z.
    roller_diameter_m, roller_length_m, pitch_diameter_m : float
        The roller's (mean) diameter D_w and effective contact length l_we, and the pitch diameter d_m.
    contact_angle_rad : float
        0 for a cylindrical roller bearing; a tapered roller bearing's (cup) contact angle, thrust in +x.
    clearance_m : float
        Diametral radial internal clearance P_d of a cylindrical roller bearing (≥ 0); a tapered bearing
        has none of its own (its play or preload is the axial offset of its rings).
    crowning : str
        ``logarithmic``, ``circular`` or ``none``.
    crowning_load_n : float
        Q_d of the logarithmic profile (N).
    crown_drop_m : float
        c_e of the circular profile (m).
    slices : int
        n, the laminae per roller.
    """

    roller_count: int
    roller_diameter_m: float
    roller_length_m: float
    pitch_diameter_m: float
    contact_angle_rad: float = 0.0
    clearance_m: float = 0.0
    crowning: Literal["logarithmic", "circular", "none"] = "logarithmic"
    crowning_load_n: float = 0.0
    crown_drop_m: float = 0.0
    slices: int = 20
    youngs_modulus_Pa: float = BEARING_STEEL_YOUNGS_MODULUS_PA
    poisson: float = BEARING_STEEL_POISSON

    def __post_init__(self) -> None:
        problems = []
        if not (isinstance(self.roller_count, (int, np.integer)) and self.roller_count >= 3):
            problems.append(f"roller count must be an integer >= 3, got {self.roller_count!r}")
        if not (self.roller_diameter_m > 0 and self.roller_length_m > 0 and self.pitch_diameter_m > 0):
            problems.append("roller diameter, roller length and pitch diameter must be positive")
        elif self.roller_count * self.roller_diameter_m >= math.pi * self.pitch_diameter_m:
            problems.append(f"{self.roller_count} rollers of {self.roller_diameter_m * 1e3:g} mm do not fit on a pitch "
                            f"circle of {self.pitch_diameter_m * 1e3:g} mm (Z·D_w ≥ π·d_m)")
        if not 0.0 <= self.contact_angle_rad < math.radians(45.0):
            problems.append(f"contact angle must lie in [0°, 45°), got {math.degrees(self.contact_angle_rad):g}°")
        if not self.clearance_m >= 0:
            problems.append(f"clearance must be >= 0, got {self.clearance_m}")
        elif self.contact_angle_rad > 0 and self.clearance_m:
            problems.append("a tapered roller bearing has no radial clearance of its own (its play or preload is the "
                            "axial offset of its rings)")
        if self.crowning not in CROWNINGS:
            problems.append(f"crowning must be one of {', '.join(CROWNINGS)}, got {self.crowning!r}")
        elif self.crowning == "logarithmic" and not self.crowning_load_n > 0:
            problems.append("a logarithmic crowning needs its design load (> 0 N)")
        elif self.crowning == "circular" and not self.crown_drop_m >= 0:
            problems.append("a circular crowning needs its drop at the roller ends (>= 0)")
        if not (isinstance(self.slices, (int, np.integer)) and 1 <= self.slices <= 500):
            problems.append(f"slices must be an integer in 1 … 500, got {self.slices!r}")
        if problems:
            raise ValueError("; ".join(problems))

    @property
    def e_prime(self) -> float:
        return reduced_modulus(self.youngs_modulus_Pa, self.poisson)

    @cached_property
    def slice_positions_m(self) -> np.ndarray:
        """s_k (n,): the lamina centres along the roller from its middle."""
        width = self.roller_length_m / self.slices
        return (np.arange(self.slices) + 0.5) * width - 0.5 * self.roller_length_m

    @cached_property
    def crown_drop_at_slices_m(self) -> np.ndarray:
        """c(s_k) (n,): the profile drop of roller and raceways at each lamina."""
        ratio = 2.0 * self.slice_positions_m / self.roller_length_m
        if self.crowning == "logarithmic":
            return (2.0 * self.crowning_load_n / (math.pi * self.roller_length_m * self.e_prime)
                    * np.log(1.0 / (1.0 - ratio**2)))
        if self.crowning == "circular":
            return self.crown_drop_m * ratio**2
        return np.zeros(self.slices)

    @cached_property
    def lamina_constant(self) -> float:
        """K_s: q = K_s δ^{10/9} of one lamina (N/m^{10/9}), both raceway contacts in series."""
        length_mm = self.roller_length_m * 1e3
        per_mm = (2.0 * PALMGREN_LINE_MM) ** (-10.0 / 9.0) * length_mm ** (8.0 / 9.0) / self.slices  # N/mm^{10/9}
        return per_mm * 1e3 ** (10.0 / 9.0)

    @property
    def inner_contact_radius_m(self) -> float:
        """R of the roller on the inner raceway in the rolling direction: 1/R = 2/D_w + 2 cos α/(d_m − D_w cos α)."""
        d = self.roller_diameter_m
        cos_a = math.cos(self.contact_angle_rad)
        return 1.0 / (2.0 / d + 2.0 * cos_a / (self.pitch_diameter_m - d * cos_a))

    def with_clearance(self, clearance_m: float) -> RollerBearingGeometry:
        """The same bearing with another diametral clearance."""
        return RollerBearingGeometry(roller_count=self.roller_count, roller_diameter_m=self.roller_diameter_m,
                                     roller_length_m=self.roller_length_m, pitch_diameter_m=self.pitch_diameter_m,
                                     contact_angle_rad=self.contact_angle_rad, clearance_m=clearance_m,
                                     crowning=self.crowning, crowning_load_n=self.crowning_load_n,
                                     crown_drop_m=self.crown_drop_m, slices=self.slices,
                                     youngs_modulus_Pa=self.youngs_modulus_Pa, poisson=self.poisson)

    def max_contact_pressure(self, lamina_load_n):
        """Hertz line-contact pressure p = √(q' E' / (2π R)) (Pa) of laminae carrying ``lamina_load_n`` (N)
        against the inner raceway."""
        per_length = np.maximum(np.asarray(lamina_load_n, dtype=float), 0.0) / (self.roller_length_m / self.slices)
        return np.sqrt(per_length * self.e_prime / (2.0 * math.pi * self.inner_contact_radius_m))


@dataclass(frozen=True)
class RollerLoads:
    """The state of every roller and lamina at one ring displacement."""

    azimuth_rad: np.ndarray  # (Z,)
    lamina_deflection_m: np.ndarray  # (Z, n) approach δ_jk (0 where unloaded)
    lamina_load_n: np.ndarray  # (Z, n) q_jk
    load_n: np.ndarray  # (Z,) Q_j = Σ_k q_jk, the roller's normal load
    contact_angle_rad: np.ndarray  # (Z,) the (fixed) contact angle
    max_contact_pressure_Pa: np.ndarray  # (Z,) the largest lamina pressure of each roller
    force: np.ndarray  # (5,) what the bearing carries, N and N·m
    stiffness: np.ndarray  # (5, 5) tangent dF/dq

    @property
    def loaded_elements(self) -> int:
        """The number of loaded rollers."""
        return int(np.count_nonzero(self.load_n > 0))


def roller_loads(geometry: RollerBearingGeometry, displacement, azimuth0_rad: float = 0.0) -> RollerLoads:
    """Lamina and roller loads, bearing force and tangent stiffness at the inner ring's displacement
    q = (δx, δy, δz, θy, θz) relative to the outer ring (m, rad).

    Parameters
    ----------
    geometry : RollerBearingGeometry
        The bearing's internal geometry (SI).
    displacement : sequence of 5 float
        q, m and rad.
    azimuth0_rad : float
        Angular position of the first roller.

    Returns
    -------
    RollerLoads
    """
    q = np.asarray(displacement, dtype=float)
    if q.shape != (5,):
        raise ValueError(f"displacement must have 5 components (δx, δy, δz, θy, θz), got shape {q.shape}")
    z = int(geometry.roller_count)
    psi = azimuth0_rad + 2.0 * np.pi * np.arange(z) / z
    c, s = np.cos(psi), np.sin(psi)
    sin_a, cos_a = math.sin(geometry.contact_angle_rad), math.cos(geometry.contact_angle_rad)
    lever = geometry.slice_positions_m - 0.5 * geometry.pitch_diameter_m * sin_a  # (n,)
    # g_jk = (sin α, cos α cos ψ, cos α sin ψ, −lever sin ψ, lever cos ψ)
    base = sin_a * q[0] + cos_a * (c * q[1] + s * q[2])  # (Z,)
    tilt = -s * q[3] + c * q[4]  # (Z,)
    delta = (base[:, None] + tilt[:, None] * lever[None, :] - 0.5 * geometry.clearance_m * cos_a
             - geometry.crown_drop_at_slices_m[None, :])
    delta = np.maximum(delta, 0.0)
    constant = geometry.lamina_constant
    lamina = constant * delta ** (10.0 / 9.0)
    slope = (10.0 / 9.0) * constant * delta ** (1.0 / 9.0)
    # sums over laminae with the lever's powers, per roller
    q0, q1 = lamina.sum(axis=1), lamina @ lever
    k0, k1, k2 = slope.sum(axis=1), slope @ lever, slope @ lever**2
    # roller-level gradient parts: a_j = (sin α, cos α c, cos α s, 0, 0), b_j = (0, 0, 0, −s, c); g = a + lever b
    a = np.zeros((z, 5))
    a[:, 0], a[:, 1], a[:, 2] = sin_a, cos_a * c, cos_a * s
    b = np.zeros((z, 5))
    b[:, 3], b[:, 4] = -s, c
    force = q0 @ a + q1 @ b
    stiffness = (np.einsum("j,jp,jq->pq", k0, a, a) + np.einsum("j,jp,jq->pq", k1, a, b)
                 + np.einsum("j,jp,jq->pq", k1, b, a) + np.einsum("j,jp,jq->pq", k2, b, b))
    pressure = geometry.max_contact_pressure(lamina.max(axis=1))
    return RollerLoads(azimuth_rad=psi, lamina_deflection_m=delta, lamina_load_n=lamina, load_n=q0,
                       contact_angle_rad=np.full(z, geometry.contact_angle_rad), max_contact_pressure_Pa=pressure,
                       force=force, stiffness=stiffness)
