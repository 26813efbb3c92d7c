"""Deep-groove ball bearing from its internal geometry: Hertz contact per ball, load distribution (SI).

Linear algebra that knows nothing of rigs. The inner ring is displaced relative to the outer ring
by q = (δx, δy, δz, θy, θz): x along the shaft axis, y and z radial, θy and θz tilts. Rings are
rigid; each ball is a nonlinear spring Q = K_n δ^1.5 between the two groove curvature centres.

Geometry (Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed., vol. 1 ch. 2 and vol. 2 ch. 1;
Jones' 5-DOF formulation): Z balls of diameter D on the pitch diameter d_m, inner and outer groove
radii r = f D (conformities f_i, f_o), diametral radial internal clearance P_d (ISO 5753-1's "radial
internal clearance": the total radial play of one ring against the other). The groove curvature
centres are A = (f_i + f_o − 1) D apart when a ball just touches both grooves; with the rings centred
they are A − P_d/2 apart radially. Ball j at azimuth ψ_j = ψ_0 + 2πj/Z (ψ from +y towards +z):

    s_r = A − P_d/2 + δy cos ψ + δz sin ψ,   s_a = δx + ℛ_i (θy sin ψ − θz cos ψ),
    s = √(s_r² + s_a²),   δ_j = max(s − A, 0),   Q_j = K_n δ_j^1.5,   tan α_j = s_a / s_r,

ℛ_i = d_m/2 + (f_i − ½) D cos α_0 the radius of the inner groove curvature-centre locus. The force
the bearing carries (the gradient of its elastic energy Σ ⅖ K_n δ_j^{5/2}) and its tangent are

    F = Σ Q_j g_j,  g_j = J_jᵀ n_j,   K_t = Σ 1.5 K_n δ_j^{0.5} g_j g_jᵀ + (Q_j / s_j) J_jᵀ (I − n_j n_jᵀ) J_j,

n_j = (s_r, s_a)/s, J_j the (2 × 5) derivative of (s_r, s_a) by q: exact (tested against finite
differences), symmetric, and zero in a dead band (no ball loaded).

Contact stiffness: Hertz point contact, steel on steel, E' = E/(1 − ν²) (both bodies alike),
with the ellipticity k̄, elliptic integrals Ē and F̄ of Hamrock & Brewe's simplified solution
(B. J. Hamrock and D. Brewe, "Simplified solution for stresses and deformations", J. Lubr. Technol.
105 (1983) 171–177; also Hamrock, *Fundamentals of Fluid Film Lubrication*, ch. 3):

    α_r = R_y / R_x,  k̄ = α_r^{2/π},  Ē = 1 + (π/2 − 1)/α_r,  F̄ = π/2 + (π/2 − 1) ln α_r,
    δ = F̄ [ (9 / (2 Ē R)) (Q / (π k̄ E'))² ]^{1/3},  1/R = 1/R_x + 1/R_y,

exact for two spheres (α_r = 1), a few per cent from the exact elliptic integrals for the groove
contacts (α_r ≈ 10–30). The inner and outer contacts in series: K_n = (K_i^{−2/3} + K_o^{−2/3})^{−3/2},
evaluated at the free contact angle α_0 (cos α_0 = 1 − P_d / (2A)); the change of the raceway
curvature with the operating contact angle of each ball is neglected (below 1 % of K_n for the
small angles of a radially loaded deep-groove bearing).

Angular-contact ball bearings (``contact_angle_rad`` = α_0 > 0) are the same law with the rings at rest
where the balls just touch at α_0 (Harris & Kotzalas vol. 2 ch. 1; Jones): the curvature centres sit
at s_r0 = A cos α_0, s_a0 = A sin α_0, so that

    s_r = A cos α_0 + δy cos ψ + δz sin ψ,   s_a = A sin α_0 + δx + ℛ_i (θy sin ψ − θz cos ψ),

and the contact angle of every ball, tan α_j = s_a/s_r, follows the load. Such a bearing has one high
shoulder per ring and carries thrust in +x only (inner ring against outer): where s_a < 0 the ball
would have to run over the low shoulder, and the model takes s_a = 0 there (contact at the groove
bottom, α_j = 0; the force is continuous, the tangent loses the ball's axial geometric term Q/s there). A bearing facing −x is mirrored
(:mod:`rvcoax.fem.rolling_bearing`).

Contact pressure: the largest Hertz pressure of a ball, p_max = 3 Q / (2π a b), with the semi-axes
a = (6 k̄² Ē Q R / (π E'))^{1/3}, b = (6 Ē Q R / (π k̄ E'))^{1/3} (Hamrock & Brewe), the larger of the
inner and outer contact (ISO 76's static limit is 4 200 MPa for ball bearings).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["BEARING_STEEL_POISSON", "BEARING_STEEL_YOUNGS_MODULUS_PA", "BallBearingGeometry", "BallLoads",
           "DEAD_BAND_FLOOR", "HertzContact", "TILT_COMPONENTS", "axial_offset_for_preload", "ball_loads", "bearing_force",
           "dead_band_regularisation", "hertz_point_contact", "radial_deflection", "reduced_modulus", "released_force", "sphere_contact_deflection"]

# AISI 52100 through-hardened bearing steel (Harris & Kotzalas vol. 1, table of bearing materials): E ≈ 208 GPa
BEARING_STEEL_YOUNGS_MODULUS_PA = 2.08e11
BEARING_STEEL_POISSON = 0.3
TILT_COMPONENTS = (0, 1, 2, 4, 5)
"""The components of a six-component relative motion (x, y, z, θx, θy, θz) a ball bearing resists:
all but the rotation about its own axis."""


def reduced_modulus(youngs_modulus_Pa: float = BEARING_STEEL_YOUNGS_MODULUS_PA,
                    poisson: float = BEARING_STEEL_POISSON) -> float:
    """E' = 2 / ((1 − ν²)/E + (1 − ν²)/E) of two bodies of the same material (Pa)."""
    return youngs_modulus_Pa / (1.0 - poisson**2)


@dataclass(frozen=True)
class HertzContact:
    """A Hertz point contact: Q = ``load_deflection_constant`` · δ^1.5 (N, m).

    Attributes
    ----------
    ellipticity, elliptic_e, elliptic_f : float
        k̄ = a/b, Ē and F̄ of Hamrock & Brewe's simplified solution.
    curvature_radius_m : float
        R with 1/R = 1/R_x + 1/R_y.
    load_deflection_constant : float
        K = π k̄ E' √(2 Ē R / (9 F̄³)) (N/m^1.5).
    """

    ellipticity: float
    elliptic_e: float
    elliptic_f: float
    curvature_radius_m: float
    load_deflection_constant: float

    def deflection(self, load_n):
        """Approach δ (m) of the two bodies under the normal load Q (N)."""
        return (np.asarray(load_n, dtype=float) / self.load_deflection_constant) ** (2.0 / 3.0)

    def max_pressure(self, load_n, e_prime: float):
        """Largest contact pressure p_max = 3 Q / (2π a b) (Pa) under the normal load Q (N); E' in Pa.

        a b = k̄^{1/3} (6 Ē Q R / (π E'))^{2/3} (the product of the semi-axes of Hamrock & Brewe's solution)."""
        load = np.asarray(load_n, dtype=float)
        ab = self.ellipticity ** (1.0 / 3.0) * (6.0 * self.elliptic_e * load * self.curvature_radius_m
                                                 / (math.pi * e_prime)) ** (2.0 / 3.0)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(load > 0, 1.5 * load / (math.pi * np.where(ab > 0, ab, 1.0)), 0.0)


def hertz_point_contact(curvature_x: float, curvature_y: float, e_prime: float) -> HertzContact:
    """Hertz point contact from the curvature sums 1/R_x and 1/R_y (1/m, both > 0) and E' (Pa)."""
    if not (curvature_x > 0 and curvature_y > 0):
        raise ValueError(f"curvature sums must be positive (convex contact), got {curvature_x}, {curvature_y}")
    rx, ry = 1.0 / curvature_x, 1.0 / curvature_y
    ratio = max(rx, ry) / min(rx, ry)  # α_r ≥ 1: the major axis of the contact lies along the larger radius
    q = math.pi / 2.0 - 1.0
    k = ratio ** (2.0 / math.pi)
    e = 1.0 + q / ratio
    f = math.pi / 2.0 + q * math.log(ratio)
    r = 1.0 / (curvature_x + curvature_y)
    constant = math.pi * k * e_prime * math.sqrt(2.0 * e * r / (9.0 * f**3))
    return HertzContact(k, e, f, r, constant)


def sphere_contact_deflection(load_n: float, radius_1_m: float, radius_2_m: float, e_prime: float) -> float:
    """Closed-form Hertz approach of two spheres: δ = (9 Q² / (16 E*² R))^{1/3}, 1/R = 1/R1 + 1/R2,
    E* = E'/2 (the textbook form, for checking :func:`hertz_point_contact`)."""
    r = 1.0 / (1.0 / radius_1_m + 1.0 / radius_2_m)
    e_star = e_prime / 2.0
    return (9.0 * load_n**2 / (16.0 * e_star**2 * r)) ** (1.0 / 3.0)


@dataclass(frozen=True)
class BallBearingGeometry:
    """Internal geometry of a single-row deep-groove ball bearing (SI).

    Parameters
    ----------
    ball_count : int
        Z.
    ball_diameter_m, pitch_diameter_m : float
        D and d_m.
    inner_conformity, outer_conformity : float
        f_i = r_i / D and f_o = r_o / D (> 0.5).
    clearance_m : float
        Diametral radial internal clearance P_d (≥ 0), ISO 5753-1's radial internal clearance.
    youngs_modulus_Pa, poisson : float
        Of balls and rings (bearing steel by default).
    contact_angle_rad : float
        Nominal contact angle α_0 of an angular-contact bearing (0 < α_0 < 60°; the rings touch at α_0
        at rest and it carries thrust in +x only), 0 for a deep-groove bearing.
    """

    ball_count: int
    ball_diameter_m: float
    pitch_diameter_m: float
    inner_conformity: float
    outer_conformity: float
    clearance_m: float = 0.0
    youngs_modulus_Pa: float = BEARING_STEEL_YOUNGS_MODULUS_PA
    poisson: float = BEARING_STEEL_POISSON
    contact_angle_rad: float = 0.0

    def __post_init__(self) -> None:
        problems = []
        if not (isinstance(self.ball_count, (int, np.integer)) and self.ball_count >= 3):
            problems.append(f"ball count must be an integer >= 3, got {self.ball_count!r}")
        if not (self.ball_diameter_m > 0 and self.pitch_diameter_m > 0):
            problems.append("ball and pitch diameters must be positive")
        elif self.ball_count * self.ball_diameter_m >= math.pi * self.pitch_diameter_m:
            problems.append(f"{self.ball_count} balls of {self.ball_diameter_m * 1e3:g} mm do not fit on a pitch "
                            f"circle of {self.pitch_diameter_m * 1e3:g} mm (Z·D ≥ π·d_m)")
        for name, f in (("inner", self.inner_conformity), ("outer", self.outer_conformity)):
            if not 0.5 < f < 1.0:
                problems.append(f"{name} groove conformity r/D must lie in (0.5, 1), got {f}")
        if not 0.0 <= self.contact_angle_rad < math.radians(60.0):
            problems.append(f"contact angle must lie in [0°, 60°), got {math.degrees(self.contact_angle_rad):g}°")
        elif self.contact_angle_rad > 0 and self.clearance_m != 0:
            problems.append("an angular-contact bearing has no radial clearance of its own (its play or preload is "
                            "the axial offset of its rings)")
        if not self.clearance_m >= 0:
            problems.append(f"clearance must be >= 0, got {self.clearance_m}")
        elif not problems and self.clearance_m >= 2.0 * self.curvature_centre_distance_m:
            problems.append("the clearance is larger than twice the groove curvature-centre distance A")
        if problems:
            raise ValueError("; ".join(problems))

    @property
    def curvature_centre_distance_m(self) -> float:
        """A = (f_i + f_o − 1) D."""
        return (self.inner_conformity + self.outer_conformity - 1.0) * self.ball_diameter_m

    @property
    def free_contact_angle_rad(self) -> float:
        """α_0 with cos α_0 = 1 − P_d / (2A): the contact angle after the rings were pushed axially
        until the play is gone (an angular-contact bearing's nominal contact angle)."""
        if self.contact_angle_rad > 0:
            return self.contact_angle_rad
        return math.acos(1.0 - self.clearance_m / (2.0 * self.curvature_centre_distance_m))

    @property
    def inner_centre_radius_m(self) -> float:
        """ℛ_i = d_m/2 + (f_i − ½) D cos α_0, the radius of the inner groove curvature-centre locus."""
        return 0.5 * self.pitch_diameter_m + (self.inner_conformity - 0.5) * self.ball_diameter_m * math.cos(
            self.free_contact_angle_rad)

    def contacts(self) -> tuple[HertzContact, HertzContact]:
        """The inner and outer ball–raceway Hertz contacts at the free contact angle."""
        d = self.ball_diameter_m
        gamma = d * math.cos(self.free_contact_angle_rad) / self.pitch_diameter_m
        e_prime = reduced_modulus(self.youngs_modulus_Pa, self.poisson)
        # curvatures (Harris & Kotzalas vol. 1 ch. 2): ball 2/D in both planes; raceway in the rolling
        # direction ±(2/D) γ/(1 ∓ γ), across the groove −1/(f D) (concave)
        inner = hertz_point_contact(2.0 / d + 2.0 / d * gamma / (1.0 - gamma),
                                    2.0 / d - 1.0 / (self.inner_conformity * d), e_prime)
        outer = hertz_point_contact(2.0 / d - 2.0 / d * gamma / (1.0 + gamma),
                                    2.0 / d - 1.0 / (self.outer_conformity * d), e_prime)
        return inner, outer

    @property
    def load_deflection_constant(self) -> float:
        """K_n of one ball between both raceways: Q = K_n δ^1.5, K_n = (K_i^{−2/3} + K_o^{−2/3})^{−3/2}."""
        inner, outer = self.contacts()
        return (inner.load_deflection_constant ** (-2.0 / 3.0)
                + outer.load_deflection_constant ** (-2.0 / 3.0)) ** (-1.5)

    @property
    def angular_contact(self) -> bool:
        """True for an angular-contact bearing (one-sided, rings at rest touching at α_0)."""
        return self.contact_angle_rad > 0

    @property
    def rest_separation_m(self) -> tuple[float, float]:
        """(s_r0, s_a0): the curvature centres' radial and axial distance with the rings at rest."""
        big_a = self.curvature_centre_distance_m
        if self.angular_contact:
            return big_a * math.cos(self.contact_angle_rad), big_a * math.sin(self.contact_angle_rad)
        return big_a - 0.5 * self.clearance_m, 0.0

    def with_clearance(self, clearance_m: float) -> BallBearingGeometry:
        """The same bearing with another diametral clearance."""
        return BallBearingGeometry(ball_count=self.ball_count, ball_diameter_m=self.ball_diameter_m,
                                   pitch_diameter_m=self.pitch_diameter_m, inner_conformity=self.inner_conformity,
                                   outer_conformity=self.outer_conformity, clearance_m=clearance_m,
                                   youngs_modulus_Pa=self.youngs_modulus_Pa, poisson=self.poisson,
                                   contact_angle_rad=self.contact_angle_rad)

    def max_contact_pressure(self, load_n):
        """The largest Hertz pressure (Pa) of a ball carrying ``load_n`` (N): the larger of its inner and
        outer raceway contact (at the nominal contact angle)."""
        e_prime = reduced_modulus(self.youngs_modulus_Pa, self.poisson)
        inner, outer = self.contacts()
        return np.maximum(inner.max_pressure(load_n, e_prime), outer.max_pressure(load_n, e_prime))


@dataclass(frozen=True)
class BallLoads:
    """The state of every ball at one ring displacement."""

    azimuth_rad: np.ndarray  # (Z,)
    deflection_m: np.ndarray  # (Z,) contact approach δ_j (0 when unloaded)
    load_n: np.ndarray  # (Z,) Q_j
    contact_angle_rad: np.ndarray  # (Z,)
    force: np.ndarray  # (5,) N and N·m: what the bearing carries (reaction on the inner ring is −force)
    stiffness: np.ndarray  # (5, 5) tangent dF/dq

    @property
    def loaded_balls(self) -> int:
        return int(np.count_nonzero(self.load_n > 0))

    @property
    def loaded_elements(self) -> int:
        """The number of loaded balls (the name every rolling-element law shares)."""
        return self.loaded_balls


def ball_loads(geometry: BallBearingGeometry, displacement, azimuth0_rad: float = 0.0,
               constant: float | None = None) -> BallLoads:
    """Ball loads, bearing force and tangent stiffness at the inner ring's displacement
    q = (δx, δy, δz, θy, θz) relative to the outer ring (m, rad). ``constant`` is K_n if known.

    Parameters
    ----------
    geometry : BallBearingGeometry
        The bearing's internal geometry (SI; :func:`rvcoax.geometry.geometry_of` builds it from a rig entry).
    displacement : sequence of 5 float
        q = (δx, δy, δz, θy, θz), m and rad.
    azimuth0_rad : float
        Angular position of the first ball.
    constant : float, optional
        The load-deflection constant K_n (computed from the geometry when not given).

    Returns
    -------
    BallLoads
        Per ball its contact load and angle, with the bearing force and tangent stiffness.
    """
    q = np.asarray(displacement, dtype=float)
    if q.shape != (5,):
        raise ValueError(f"displacement must have 5 components (δx, δy, δz, θy, θz), got shape {q.shape}")
    k_n = geometry.load_deflection_constant if constant is None else constant
    z = int(geometry.ball_count)
    psi = azimuth0_rad + 2.0 * np.pi * np.arange(z) / z
    c, s = np.cos(psi), np.sin(psi)
    big_a = geometry.curvature_centre_distance_m
    radius = geometry.inner_centre_radius_m
    jac = np.zeros((z, 2, 5))
    jac[:, 0, 1], jac[:, 0, 2] = c, s
    jac[:, 1, 0], jac[:, 1, 3], jac[:, 1, 4] = 1.0, radius * s, -radius * c
    sr0, sa0 = geometry.rest_separation_m
    sr = sr0 + jac[:, 0] @ q
    sa = sa0 + jac[:, 1] @ q
    if geometry.angular_contact:  # the low shoulder: no thrust the other way (s_a held at 0 there)
        relieved = sa < 0.0
        sa = np.where(relieved, 0.0, sa)
        jac[relieved, 1, :] = 0.0
    dist = np.hypot(sr, sa)
    delta = np.maximum(dist - big_a, 0.0)
    load = k_n * delta**1.5
    normal = np.stack([sr, sa], axis=1) / dist[:, None]
    g = np.einsum("jkq,jk->jq", jac, normal)
    force = load @ g
    tangent = np.einsum("j,jp,jq->pq", 1.5 * k_n * np.sqrt(delta), g, g)
    projector = np.eye(2)[None] - np.einsum("ja,jb->jab", normal, normal)
    tangent += np.einsum("j,jap,jab,jbq->pq", load / dist, jac, projector, jac)
    return BallLoads(azimuth_rad=psi, deflection_m=delta, load_n=load, contact_angle_rad=np.arctan2(sa, sr), force=force,
                     stiffness=tangent)


def bearing_force(geometry: BallBearingGeometry, relative_motion, preload_offset_m: float = 0.0,
                  azimuth0_rad: float = 0.0, constant: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Force (6,) and tangent stiffness (6, 6) of the bearing at a six-component relative motion
    Δ = (x, y, z, θx, θy, θz) of the inner ring against the outer (global axes, x the bearing axis).

    With an axial preload offset δ_0 (:func:`axial_offset_for_preload`) the balls see Δ + δ_0 e_x and
    the preloading element (the part that holds the rings δ_0 apart: a shoulder, a nut) carries the
    preload back, so the force is F(Δ + δ_0 e_x) − F(δ_0 e_x): zero at Δ = 0. The rotation about
    the axis is free (zero row and column).

    Parameters
    ----------
    geometry : BallBearingGeometry
        The bearing's internal geometry (SI; :func:`rvcoax.geometry.geometry_of` builds it from a rig entry).
    relative_motion : sequence of 6 float
        Δ, m and rad.
    preload_offset_m : float
        δ_0 (0: no preload).
    azimuth0_rad : float
        Angular position of the first ball.
    constant : float, optional
        K_n, when known.

    Returns
    -------
    (ndarray, ndarray)
        The force (6,) in N and N·m, and the tangent stiffness (6, 6).
    """
    motion = np.asarray(relative_motion, dtype=float)
    q = motion[list(TILT_COMPONENTS)].copy()
    q[0] += preload_offset_m
    state = ball_loads(geometry, q, azimuth0_rad, constant)
    force = np.zeros(6)
    stiffness = np.zeros((6, 6))
    index = np.array(TILT_COMPONENTS)
    force[index] = state.force
    stiffness[np.ix_(index, index)] = state.stiffness
    if preload_offset_m:
        force[index] -= ball_loads(geometry, np.array([preload_offset_m, 0, 0, 0, 0]), azimuth0_rad, constant).force
    return force, stiffness


def _solve_monotone(function, target: float, start: float) -> float:
    """The root x > 0 of function(x) = target for a function that grows from 0 (bracketed bisection + brentq)."""
    from scipy.optimize import brentq

    upper = start
    while function(upper) < target:
        upper *= 2.0
        if upper > 1.0:
            raise ValueError("no displacement below 1 m carries that load")
    return brentq(lambda x: function(x) - target, 0.0, upper, xtol=1e-16, rtol=1e-14, maxiter=200)


def radial_deflection(geometry: BallBearingGeometry, radial_load_n: float, azimuth0_rad: float = 0.0) -> float:
    """Radial displacement δ_r (m) of the inner ring under a pure radial load along +y (tilt and axial
    motion held at zero).

    Parameters
    ----------
    geometry : BallBearingGeometry
        The bearing's internal geometry (SI; :func:`rvcoax.geometry.geometry_of` builds it from a rig entry).
    radial_load_n : float
        The radial load (N).
    azimuth0_rad : float
        Angular position of the first ball.

    Returns
    -------
    float
        δ_r in m.
    """
    if radial_load_n <= 0:
        return 0.0
    constant = geometry.load_deflection_constant
    return _solve_monotone(lambda d: ball_loads(geometry, np.array([0.0, d, 0, 0, 0]), azimuth0_rad,
                                                constant).force[1], radial_load_n,
                           0.5 * geometry.clearance_m + 1e-6)


def axial_offset_for_preload(geometry: BallBearingGeometry, preload_n: float) -> float:
    """The axial offset δ_0 (m) of the inner ring at which the balls carry the axial force ``preload_n``."""
    if preload_n <= 0:
        return 0.0
    constant = geometry.load_deflection_constant
    play = math.sqrt(max(geometry.clearance_m * geometry.curvature_centre_distance_m - geometry.clearance_m**2 / 4,
                         0.0))
    return _solve_monotone(lambda d: ball_loads(geometry, np.array([d, 0, 0, 0, 0]), 0.0, constant).force[0],
                           preload_n, play + 1e-6)


DEAD_BAND_FLOOR = 1e-3
"""η: the share of the reference stiffness that :func:`dead_band_regularisation` adds to the tangent."""


def released_force(geometry: BallBearingGeometry, reference_stiffness, relative_motion, preload_offset_m: float = 0.0,
                   constant: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """G(Δ) = k_ref Δ − F(Δ) and its tangent k_ref − K_t, (6,) and (6, 6): the bearing as the condensed
    solve (:func:`rvcoax.fem.bushing.solve_condensed`) sees it, the structure assembled with the linear
    reference springs ``reference_stiffness`` (6,)."""
    reference = np.asarray(reference_stiffness, dtype=float)
    force, stiffness = bearing_force(geometry, relative_motion, preload_offset_m, constant=constant)
    return reference * np.asarray(relative_motion, dtype=float) - force, np.diag(reference) - stiffness


def dead_band_regularisation(reference_stiffness, floor: float = DEAD_BAND_FLOOR) -> np.ndarray:
    """η k_ref (6, 6): what the Newton Jacobian's tangent may borrow where the bearing is in its dead band
    (clearance, no ball loaded: zero tangent) and the part hangs on it alone, so that the step is finite.
    Only the path to the solution changes (:func:`rvcoax.fem.bushing.solve_condensed`), not the solution."""
    return np.diag(floor * np.asarray(reference_stiffness, dtype=float))
