"""Rolling-bearing life, static safety and minimum load (N, mm, MPa as the standards write them).

Linear algebra and tables that know nothing of rigs; a bearing enters as its load ratings, or as its
internal geometry (:class:`rvcoax.fem.ball_bearing.BallBearingGeometry`) and the loads of its rolling
elements (:class:`rvcoax.fem.ball_bearing.BallLoads`). Other bearing types plug in through the same
per-element description: a load Q_j and a basic dynamic rating of the element-raceway contact Q_c per
ring (:func:`element_rating_life`).

Basic rating life (ISO 281:2007)
    Radial ball bearing, D_w ≤ 25.4 mm:  C_r = b_m f_c (i cos α)^0.7 Z^(2/3) D_w^1.8 (N, mm), b_m = 1.3, f_c
    from ISO 281 table 2 (single-row deep groove) by D_w cos α / D_pw (:data:`FC_TABLE`);
    P = X F_r + Y F_a with e, X, Y from ISO 281 table 3 by f0 F_a / C0 (:func:`deep_groove_xy`);
    L10 = (C/P)^p million revolutions, p = 3 (ball) or 10/3 (roller); L10h = 10⁶ L10 / (60 n).
Static load rating (ISO 76:2006)
    C0 = f0 i Z D_w² cos α with f0 from ISO 76 table (radial contact groove ball bearings, :data:`F0_TABLE`);
    P0 = max(0.6 F_r + 0.5 F_a, F_r); s0 = C0 / P0. From the loads of the elements: C0 is the load at
    which the most loaded contact reaches 4200 MPa (ball) or 4000 MPa (roller), and Hertz' p ∝ Q^(1/3), so
    s0 = (p_limit / p_max)³ (:func:`static_safety_from_pressure`).
Modified reference rating life (ISO/TS 16281:2008)
    Per ring the Lundberg–Palmgren basic dynamic rating of a contact (N, mm)
    Q_c = 98.1 b_m (2f/(2f − 1))^0.41 (1 ∓ γ)^1.39 / (1 ± γ)^(1/3) (γ/cos α)^0.3 D_w^1.8 Z^(−1/3)
    (upper signs inner ring), γ = D_w cos α / D_pw; the equivalent element load of the rotating ring
    Q_e = (Σ Q_j³ / Z)^(1/3), of the stationary ring (Σ Q_j^(10/3) / Z)^(3/10); L_ring = (Q_c / Q_e)³ and
    L10r = (L_i^(−10/9) + L_e^(−10/9))^(−9/10). Tilt, clearance and preload enter through the element
    loads. For the load case behind C (zero clearance, pure radial load, no tilt) it agrees with
    ISO 281's L10 (tested: within 3 % in load).
Life modification factor a_ISO (ISO 281:2007, 9.3.3)
    Radial ball bearings: a_ISO = 0.1 [1 − (2.5671 − c1/κ^c2)^0.83 (e_C C_u / P)^(1/3)]^(−9.3), (c1, c2) =
    (2.2649, 0.054381) for 0.1 ≤ κ < 0.4, (1.9987, 0.19087) for 0.4 ≤ κ < 1, (1.9987, 0.071739) for 1 ≤ κ ≤ 4;
    radial roller bearings: a_ISO = 0.1 [1 − (1.5859 − c1/κ^c2) (e_C C_u / P)^0.4]^(−9.185), (c1, c2) =
    (1.3993, 0.054381), (1.2348, 0.19087), (1.2348, 0.071739) over the same ranges (κ > 4: 4; a_ISO ≤ 50).
    The constants as ISO 281 prints them, quoted in two independent open implementations: Dessia-tech/
    MechanicalComponents, mechanical_components/bearings.py (RadialRollerBearing.AIso, and the ball form;
    its ball code mistypes 0.19087 as 0.019087, which our continuity test at κ = 0.4 would catch), and a
    Korean ISO 281/16281 Rust solver in a public code index (its file `a_iso_ball`, eqs. (31)–(36) named in its comments; the index does not name its repository).
    Fatigue load limit C_u (ISO 281 annex B, simplified): C0/22 for ball, C0/8.2 for roller bearings of
    D_pw ≤ 100 mm, times (100/D_pw)^0.5 (ball) or (100/D_pw)^0.3 (roller) above (same two sources).
    Viscosity ratio κ = ν/ν1, ν1 = 45000 n^(−0.83) D_pw^(−0.5) (n < 1000 r/min), 4500 n^(−0.5) D_pw^(−0.5)
    (n ≥ 1000) in mm²/s (ISO 281 eqs. (28)/(29), same two sources).
Minimum load (the makers' rules; SKF's, as its catalogue prints them)
    Rule of thumb: 0.01 C for ball, 0.02 C for roller bearings (SKF, "Requisite minimum load",
    skf.com .../requisite-minimum-load). With the bearing's minimum load factor k_r (a maker's product-table
    value, a rig key) the speed-dependent forms, F in kN, d_m = (d + D)/2 in mm:
    deep-groove and angular-contact ball bearings F_rm = k_r (ν n / 1000)^(2/3) (d_m / 100)² (ν the operating
    viscosity, mm²/s; SKF Rolling bearings catalogue, deep groove ball bearings "Loads", as quoted with its
    page in MYCELA784/MYCELA784.github.io js/dgbb_calc.js; SKF's angular-contact "Loads" page lists the same
    symbols k_r, ν, n, d_m); cylindrical roller bearings F_rm = k_r (6 + 4 n / n_r) (d_m / 100)² (n_r the
    reference speed; SKF Rolling bearings 17000 EN, printed page 509, tpsbearing.com/catalog/Rollingbearings
    page511); tapered roller bearings F_rm = 0.02 C (SKF tapered roller bearings "Loads"; 0.017 C for SKF
    Explorer). Checked on P, or, with element loads, on the larger of P and C L10r^(−1/p) (a preload loads
    the elements).
Duty cycle (Palmgren–Miner)
    With time shares t_k of the load cases at speeds n_k: L_h = 1 / Σ (t_k / L_h,k); with revolution shares
    r_k: L = 1 / Σ (r_k / L_k) (revolutions).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["ANGULAR_XY", "ANGULAR_XY_15", "BALL_CONTACT_LIMIT_MPA", "B_M_BALL", "B_M_ROLLER", "LAMBDA_NU_ROLLER", "F0_TABLE", "FC_TABLE", "LifeResult", "MINIMUM_LOAD_SHARE",
           "ROLLER_CONTACT_LIMIT_MPA", "XY_TABLE", "a_iso", "ball_contact_pressures_mpa", "ball_reference_life",
           "basic_rating_life", "deep_groove_xy", "dynamic_rating_ball", "element_rating_life", "equivalent_load",
           "equivalent_static_load", "hours", "angular_contact_xy", "cylindrical_xy", "lamina_contact_ratings",
           "line_contact_life", "pair_dynamic_rating", "rows_reference_life", "rows_static_safety", "system_life",
           "tapered_xy", "life_exponent", "life_from_forces", "miner_life", "minimum_load", "ring_contact_ratings",
           "static_rating_ball", "static_safety", "static_safety_from_pressure", "A_ISO_CONSTANTS",
           "TAPERED_MINIMUM_LOAD_SHARE", "ball_minimum_load_N", "cylindrical_minimum_load_N", "fatigue_load_limit",
           "reference_viscosity_mm2_s"]

B_M_BALL = 1.3
"""ISO 281:2007 table 1: rating factor b_m for contemporary bearing steel, radial ball bearings."""

# ISO 281:2007 table 2, single-row radial contact groove ball bearings: f_c by D_w cos α / D_pw (0.01 … 0.40)
FC_TABLE = (np.round(np.arange(1, 41) * 0.01, 2),
            np.array([29.1, 35.8, 40.3, 43.8, 46.7, 49.1, 51.1, 52.8, 54.3, 55.5, 56.6, 57.5, 58.2, 58.8, 59.3,
                      59.6, 59.8, 59.9, 60.0, 59.9, 59.8, 59.6, 59.3, 59.0, 58.6, 58.2, 57.7, 57.1, 56.6, 56.0,
                      55.3, 54.6, 53.9, 53.2, 52.4, 51.7, 50.9, 50.0, 49.2, 48.4]))
# ISO 76:2006 table for radial contact groove ball bearings: f0 by D_w cos α / D_pw (0.00 … 0.40)
F0_TABLE = (np.round(np.arange(0, 41) * 0.01, 2),
            np.array([14.7, 14.9, 15.1, 15.3, 15.5, 15.7, 15.9, 16.1, 16.3, 16.5, 16.4, 16.1, 15.9, 15.6, 15.4,
                      15.2, 14.9, 14.7, 14.4, 14.2, 14.0, 13.7, 13.5, 13.2, 13.0, 12.8, 12.5, 12.3, 12.1, 11.8,
                      11.6, 11.4, 11.2, 10.9, 10.7, 10.5, 10.3, 10.0, 9.8, 9.6, 9.4]))
# ISO 281:2007 table 3, single-row radial contact groove ball bearings (normal clearance):
# f0 F_a / C0 → e, and Y for F_a / F_r > e (X = 0.56); F_a / F_r ≤ e: X = 1, Y = 0
XY_TABLE = (np.array([0.172, 0.345, 0.689, 1.03, 1.38, 2.07, 3.45, 5.17, 6.89]),
            np.array([0.19, 0.22, 0.26, 0.28, 0.30, 0.34, 0.38, 0.42, 0.44]),
            np.array([2.30, 1.99, 1.71, 1.55, 1.45, 1.31, 1.15, 1.04, 1.00]))
BALL_CONTACT_LIMIT_MPA = 4200.0  # ISO 76: the contact pressure C0 stands for, ball bearings (self-aligning: 4600)
ROLLER_CONTACT_LIMIT_MPA = 4000.0  # ISO 76: roller bearings
MINIMUM_LOAD_SHARE = {"ball": 0.01, "roller": 0.02}  # of C: the SKF catalogue's rule of thumb


def life_exponent(elements: str) -> float:
    """p of L = (C/P)^p: 3 for ball, 10/3 for roller bearings (ISO 281)."""
    if elements not in ("ball", "roller"):
        raise ValueError(f"rolling elements must be 'ball' or 'roller', got {elements!r}")
    return 3.0 if elements == "ball" else 10.0 / 3.0


def _ratio(ball_diameter_mm: float, pitch_diameter_mm: float, contact_angle_rad: float) -> float:
    return ball_diameter_mm * math.cos(contact_angle_rad) / pitch_diameter_mm


def dynamic_rating_ball(balls: int, ball_diameter_mm: float, pitch_diameter_mm: float,
                        contact_angle_rad: float = 0.0, rows: int = 1) -> float:
    """ISO 281 basic dynamic radial load rating C_r (N) of a radial ball bearing (D_w ≤ 25.4 mm)."""
    if ball_diameter_mm > 25.4:
        raise ValueError(f"ball diameter {ball_diameter_mm:g} mm > 25.4 mm: ISO 281 uses D_w^1.4 · 3.647 there; "
                         "give the catalogue's dynamic_load_rating_kN")
    ratio = _ratio(ball_diameter_mm, pitch_diameter_mm, contact_angle_rad)
    if not FC_TABLE[0][0] <= ratio <= FC_TABLE[0][-1]:
        raise ValueError(f"D_w cos α / D_pw = {ratio:.3f} is outside ISO 281's f_c table (0.01 … 0.40)")
    f_c = float(np.interp(ratio, *FC_TABLE))
    return (B_M_BALL * f_c * (rows * math.cos(contact_angle_rad)) ** 0.7 * balls ** (2.0 / 3.0)
            * ball_diameter_mm ** 1.8)


def static_rating_ball(balls: int, ball_diameter_mm: float, pitch_diameter_mm: float,
                       contact_angle_rad: float = 0.0, rows: int = 1) -> tuple[float, float]:
    """ISO 76 basic static radial load rating C0 (N) of a radial ball bearing, and its factor f0."""
    ratio = _ratio(ball_diameter_mm, pitch_diameter_mm, contact_angle_rad)
    if not 0.0 <= ratio <= F0_TABLE[0][-1]:
        raise ValueError(f"D_w cos α / D_pw = {ratio:.3f} is outside ISO 76's f0 table (0 … 0.40)")
    f0 = float(np.interp(ratio, *F0_TABLE))
    return f0 * rows * balls * ball_diameter_mm**2 * math.cos(contact_angle_rad), f0


def deep_groove_xy(radial_N: float, axial_N: float, static_rating_N: float, f0: float) -> tuple[float, float, float]:
    """(X, Y, e) of ISO 281 table 3 for a single-row deep-groove ball bearing; f0 F_a / C0 interpolated
    linearly in the table and held at its ends."""
    radial, axial = abs(radial_N), abs(axial_N)
    if axial == 0.0:
        return 1.0, 0.0, float(XY_TABLE[1][0])
    key = f0 * axial / static_rating_N
    e = float(np.interp(key, XY_TABLE[0], XY_TABLE[1]))
    if radial > 0.0 and axial / radial <= e:
        return 1.0, 0.0, e
    return 0.56, float(np.interp(key, XY_TABLE[0], XY_TABLE[2])), e


def equivalent_load(radial_N: float, axial_N: float, static_rating_N: float | None = None,
                    f0: float | None = None) -> float:
    """P (N) of a deep-groove ball bearing: X F_r + Y F_a (ISO 281). Without an axial load P = F_r;
    with one, C0 and f0 are needed."""
    if axial_N == 0.0:
        return abs(radial_N)
    if static_rating_N is None or f0 is None:
        raise ValueError("an axial load needs the static load rating C0 and f0 for ISO 281's X and Y")
    x, y, _ = deep_groove_xy(radial_N, axial_N, static_rating_N, f0)
    return x * abs(radial_N) + y * abs(axial_N)


def basic_rating_life(dynamic_rating_N: float, equivalent_load_N: float, elements: str = "ball") -> float:
    """L10 = (C/P)^p in millions of revolutions (inf at P = 0)."""
    if equivalent_load_N <= 0.0:
        return math.inf
    return (dynamic_rating_N / equivalent_load_N) ** life_exponent(elements)


def hours(life_million_rev: float, speed_rpm: float | None) -> float | None:
    """L_h = 10⁶ L / (60 n); None without a speed or at standstill."""
    if speed_rpm is None or speed_rpm <= 0.0:
        return None
    return life_million_rev * 1e6 / (60.0 * speed_rpm)


A_ISO_CONSTANTS = {
    "ball": ((2.2649, 0.054381), (1.9987, 0.19087), (1.9987, 0.071739), 2.5671, 0.83, 1.0 / 3.0, 9.3),
    "roller": ((1.3993, 0.054381), (1.2348, 0.19087), (1.2348, 0.071739), 1.5859, 1.0, 0.4, 9.185),
}
"""ISO 281:2007 9.3.3, radial bearings: per kind the (c1, c2) of κ in [0.1, 0.4), [0.4, 1), [1, 4], then the
bracket's constant, its power, the power of e_C C_u/P and the outer exponent (sources in the module docstring)."""


def a_iso(kappa: float, contamination: float, fatigue_limit_N: float, equivalent_load_N: float,  # noqa: PLR0913
          elements: str = "ball") -> float:
    """ISO 281's life modification factor a_ISO of a radial ball or roller bearing (0.1 … 50).

    Parameters
    ----------
    kappa : float
        Viscosity ratio κ = ν/ν1 (0.1 … 4; above 4 taken as 4).
    contamination : float
        e_C (0 … 1).
    fatigue_limit_N, equivalent_load_N : float
        C_u and P.
    elements : str
        ``ball`` or ``roller`` (:data:`A_ISO_CONSTANTS`).
    """
    life_exponent(elements)  # validates the kind
    if not 0.1 <= kappa:
        raise ValueError(f"viscosity ratio κ = {kappa:g} is below 0.1, where ISO 281's a_ISO does not apply")
    if not 0.0 <= contamination <= 1.0:
        raise ValueError(f"contamination factor e_C = {contamination:g} must lie in 0 … 1")
    if equivalent_load_N <= 0.0:
        return 50.0
    kappa = min(kappa, 4.0)
    low, middle, high, constant, power, load_power, exponent = A_ISO_CONSTANTS[elements]
    c1, c2 = low if kappa < 0.4 else middle if kappa < 1.0 else high
    base = max(constant - c1 / kappa**c2, 0.0)
    inner = 1.0 - base**power * (contamination * fatigue_limit_N / equivalent_load_N) ** load_power
    if inner <= 0.0:
        return 50.0
    return float(min(max(0.1 * inner ** (-exponent), 0.1), 50.0))


def fatigue_load_limit(static_rating_N: float, pitch_diameter_mm: float | None = None, elements: str = "ball") -> float:
    """C_u (N) by ISO 281 annex B's simplified rule: C0/22 (ball) or C0/8.2 (roller) for D_pw ≤ 100 mm, times
    (100/D_pw)^0.5 (ball) or (100/D_pw)^0.3 (roller) above; without D_pw the small-bearing form."""
    life_exponent(elements)
    divisor, power = (22.0, 0.5) if elements == "ball" else (8.2, 0.3)
    limit = static_rating_N / divisor
    if pitch_diameter_mm is not None and pitch_diameter_mm > 100.0:
        limit *= (100.0 / pitch_diameter_mm) ** power
    return limit


def reference_viscosity_mm2_s(speed_rpm: float, pitch_diameter_mm: float) -> float:
    """ν1 (mm²/s), ISO 281 eqs. (28)/(29): the viscosity a bearing of D_pw at n needs for κ = 1."""
    if speed_rpm <= 0.0 or pitch_diameter_mm <= 0.0:
        raise ValueError("the reference viscosity ν1 needs a speed and a pitch diameter > 0")
    if speed_rpm < 1000.0:
        return 45000.0 * speed_rpm ** (-0.83) * pitch_diameter_mm ** (-0.5)
    return 4500.0 * speed_rpm ** (-0.5) * pitch_diameter_mm ** (-0.5)


TAPERED_MINIMUM_LOAD_SHARE = 0.02
"""SKF's minimum radial load of a tapered roller bearing, F_rm = 0.02 C (0.017 C for SKF Explorer)."""


def ball_minimum_load_N(factor: float, viscosity_mm2_s: float, speed_rpm: float, mean_diameter_mm: float) -> float:
    """SKF's minimum radial load of a deep-groove or angular-contact ball bearing (N):
    F_rm = k_r (ν n / 1000)^(2/3) (d_m / 100)² kN (sources in the module docstring)."""
    if factor <= 0.0 or viscosity_mm2_s <= 0.0 or mean_diameter_mm <= 0.0:
        raise ValueError("the minimum load needs k_r, ν and d_m > 0")
    return 1e3 * factor * (viscosity_mm2_s * max(speed_rpm, 0.0) / 1000.0) ** (2.0 / 3.0) * (mean_diameter_mm / 100.0) ** 2


def cylindrical_minimum_load_N(factor: float, speed_rpm: float, reference_speed_rpm: float,
                               mean_diameter_mm: float) -> float:
    """SKF's minimum radial load of a cylindrical roller bearing (N): F_rm = k_r (6 + 4 n / n_r) (d_m / 100)² kN
    (SKF Rolling bearings 17000 EN, p. 509)."""
    if factor <= 0.0 or reference_speed_rpm <= 0.0 or mean_diameter_mm <= 0.0:
        raise ValueError("the minimum load needs k_r, n_r and d_m > 0")
    return 1e3 * factor * (6.0 + 4.0 * max(speed_rpm, 0.0) / reference_speed_rpm) * (mean_diameter_mm / 100.0) ** 2


def equivalent_static_load(radial_N: float, axial_N: float) -> float:
    """P0 of a radial ball bearing (ISO 76): max(0.6 F_r + 0.5 F_a, F_r)."""
    return max(0.6 * abs(radial_N) + 0.5 * abs(axial_N), abs(radial_N))


def static_safety(static_rating_N: float, static_load_N: float) -> float:
    """s0 = C0 / P0 (inf when unloaded)."""
    return math.inf if static_load_N <= 0.0 else static_rating_N / static_load_N


def static_safety_from_pressure(max_pressure_MPa: float, elements: str = "ball") -> float:
    """s0: the factor on the loads that brings the largest contact pressure to ISO 76's 4200 MPa (ball) or
    4000 MPa (roller); inf when nothing is loaded. Hertz: a point contact's pressure grows as Q^(1/3), so
    s0 = (p_limit / p_max)³; a line contact's as q'^(1/2), so s0 = (p_limit / p_max)²."""
    life_exponent(elements)  # validates the kind
    limit, power = (BALL_CONTACT_LIMIT_MPA, 3) if elements == "ball" else (ROLLER_CONTACT_LIMIT_MPA, 2)
    return math.inf if max_pressure_MPa <= 0.0 else (limit / max_pressure_MPa) ** power


def minimum_load(dynamic_rating_N: float, elements: str = "ball") -> float:
    """The maker's minimum load (N): 0.01 C for ball, 0.02 C for roller bearings."""
    life_exponent(elements)  # validates the kind
    return MINIMUM_LOAD_SHARE[elements] * dynamic_rating_N


def miner_life(lives, shares) -> float:
    """Palmgren–Miner: 1 / Σ (share_k / L_k) for shares that sum to 1 (time shares with lives in hours, or
    revolution shares with lives in revolutions); an infinite L_k contributes nothing."""
    lives, shares = np.asarray(lives, dtype=float), np.asarray(shares, dtype=float)
    if lives.shape != shares.shape:
        raise ValueError("one share per load case")
    if np.any(shares < 0) or abs(shares.sum() - 1.0) > 1e-6:
        raise ValueError(f"duty-cycle shares must be >= 0 and sum to 1, they sum to {shares.sum():.6g}")
    damage = float(np.sum(np.where(np.isfinite(lives) & (shares > 0), shares / np.where(lives > 0, lives, np.nan), 0.0)))
    return math.inf if damage == 0.0 else 1.0 / damage


# --------------------------------------------------------------------------------------------
# From the loads of the rolling elements (ISO/TS 16281)


def ring_contact_ratings(balls: int, ball_diameter_mm: float, pitch_diameter_mm: float, inner_conformity: float,  # noqa: PLR0913
                         outer_conformity: float, *, contact_angle_rad) -> tuple[np.ndarray, np.ndarray]:
    """Q_ci and Q_ce (N): the Lundberg–Palmgren basic dynamic ratings of the inner and outer ball-raceway
    contacts (ISO/TS 16281, with ISO 281's b_m), at each element's contact angle (array)."""
    alpha = np.asarray(contact_angle_rad, dtype=float)
    cos_a = np.cos(alpha)
    gamma = ball_diameter_mm * cos_a / pitch_diameter_mm
    common = 98.1 * B_M_BALL * (ball_diameter_mm / pitch_diameter_mm) ** 0.3 * ball_diameter_mm**1.8 * balls ** (-1.0 / 3.0)
    inner = common * (2 * inner_conformity / (2 * inner_conformity - 1)) ** 0.41 * (1 - gamma) ** 1.39 / (1 + gamma) ** (1 / 3)
    outer = common * (2 * outer_conformity / (2 * outer_conformity - 1)) ** 0.41 * (1 + gamma) ** 1.39 / (1 - gamma) ** (1 / 3)
    return inner, outer


def element_rating_life(loads_N, inner_rating_N, outer_rating_N, *, rotating: str = "inner", exponent: float = 3.0,  # noqa: PLR0913
                        ring_exponent: float = 10.0 / 9.0) -> float:
    """L10r (million revolutions) from element loads Q_j and the contact ratings of both rings.

    The rotating ring's equivalent load is the cubic mean (Σ (Q_j/Q_cj)^p / Z)^(1/p) with p = ``exponent``,
    the stationary ring's with p + 1/3 (ISO/TS 16281: 10/3 for ball bearings); each ring lives
    (Q_c/Q_e)^p and the bearing (L_i^(−e) + L_e^(−e))^(−1/e), e = ``ring_exponent``.
    """
    q = np.abs(np.asarray(loads_N, dtype=float))
    if not np.any(q > 0):
        return math.inf
    inner_p = exponent if rotating == "inner" else exponent + 1.0 / 3.0
    outer_p = exponent + 1.0 / 3.0 if rotating == "inner" else exponent
    lives = []
    for rating, p in ((inner_rating_N, inner_p), (outer_rating_N, outer_p)):
        mean = np.mean((q / np.asarray(rating, dtype=float)) ** p) ** (1.0 / p)
        lives.append(mean ** (-exponent))
    return float((lives[0] ** (-ring_exponent) + lives[1] ** (-ring_exponent)) ** (-1.0 / ring_exponent))


def ball_reference_life(geometry, loads, rotating: str = "inner") -> float:
    """L10r (million revolutions) of a ball bearing from its ball loads.

    Parameters
    ----------
    geometry : BallBearingGeometry
        Internal geometry (SI).
    loads : BallLoads
        :func:`rvcoax.fem.ball_bearing.ball_loads` at the operating point.
    rotating : str
        ``inner`` (shaft rotates, default) or ``outer``.
    """
    inner, outer = ring_contact_ratings(geometry.ball_count, geometry.ball_diameter_m * 1e3,
                                        geometry.pitch_diameter_m * 1e3, geometry.inner_conformity,
                                        geometry.outer_conformity, contact_angle_rad=loads.contact_angle_rad)
    return element_rating_life(loads.load_n, inner, outer, rotating=rotating)


def ball_contact_pressures_mpa(geometry, loads_N) -> tuple[np.ndarray, np.ndarray]:
    """Hertz maximum pressure p = 3Q/(2π a b) (MPa) of each ball's inner and outer contact.

    Semi-axes from Hamrock & Brewe's simplified solution (as the stiffness in :mod:`rvcoax.fem.ball_bearing`):
    a = (6 k̄² Ē Q R / (π E'))^(1/3), b = (6 Ē Q R / (π k̄ E'))^(1/3).
    """
    from rvcoax.fem.ball_bearing import reduced_modulus

    q = np.abs(np.asarray(loads_N, dtype=float))
    e_prime = reduced_modulus(geometry.youngs_modulus_Pa, geometry.poisson)
    out = []
    for contact in geometry.contacts():
        k, e, r = contact.ellipticity, contact.elliptic_e, contact.curvature_radius_m
        a = (6.0 * k**2 * e * q * r / (math.pi * e_prime)) ** (1.0 / 3.0)
        b = (6.0 * e * q * r / (math.pi * k * e_prime)) ** (1.0 / 3.0)
        with np.errstate(invalid="ignore", divide="ignore"):
            out.append(np.where(q > 0, 1.5 * q / (math.pi * np.where(a > 0, a * b, 1.0)), 0.0) * 1e-6)
    return out[0], out[1]


@dataclass(frozen=True)
class LifeResult:
    """Life, static safety and minimum-load status of one bearing in one load case.

    ``basic_life_Mrev``: ISO 281 L10 (from the equivalent load); ``reference_life_Mrev``: ISO/TS 16281
    L10r from the element loads (None where the bearing has no elements: typed-in springs);
    ``modified_life_Mrev``: a_ISO × the reference (or basic) life when κ and e_C are given; ``*_h``: the same
    in hours at ``speed_rpm``; ``static_safety``: s0; ``minimum_load_N`` and ``below_minimum_load``.
    """

    equivalent_load_N: float
    basic_life_Mrev: float
    reference_life_Mrev: float | None
    a_iso: float | None
    modified_life_Mrev: float | None
    speed_rpm: float | None
    basic_life_h: float | None
    reference_life_h: float | None
    modified_life_h: float | None
    static_safety: float
    minimum_load_N: float
    below_minimum_load: bool


def life_from_forces(radial_N: float, axial_N: float, dynamic_rating_N: float, static_rating_N: float | None,  # noqa: PLR0913
                     f0: float | None, *, elements: str = "ball", speed_rpm: float | None = None,
                     kappa: float | None = None, contamination: float | None = None,
                     reference_life_Mrev: float | None = None, static_safety_value: float | None = None,
                     equivalent_load_N: float | None = None, minimum_load_N: float | None = None,
                     fatigue_limit_N: float | None = None) -> LifeResult:
    """Life, static safety and minimum-load status of a bearing from the forces it carries.

    ``reference_life_Mrev`` (L10r from the element loads) and ``static_safety_value`` (s0 from the largest
    contact pressure) replace nothing: they are reported beside L10 and, where given, s0 is taken from the
    pressure rather than from C0/P0. ``equivalent_load_N`` replaces the deep-groove/radial-roller P (an
    angular-contact or tapered bearing's from :func:`angular_contact_xy` / :func:`tapered_xy`). a_ISO (ball and
    roller bearings) needs κ, e_C and C_u (``fatigue_limit_N``; else :func:`fatigue_load_limit` of C0).
    ``minimum_load_N`` is the maker's minimum load where the caller knows it (:func:`ball_minimum_load_N`,
    :func:`cylindrical_minimum_load_N`), else the rule of thumb :func:`minimum_load`. It is checked on the larger
    of P and the load that gives L10r by ISO 281 (so a preload the elements carry counts).
    """
    if equivalent_load_N is not None:
        load = equivalent_load_N
    elif axial_N != 0.0 and (static_rating_N is None or f0 is None) and elements == "ball":
        load = abs(radial_N) + float(XY_TABLE[2][0]) * abs(axial_N)  # no C0: X = 1, Y = 2.30 bound both branches
    elif elements == "ball":
        load = equivalent_load(radial_N, axial_N, static_rating_N, f0)
    else:
        load = abs(radial_N)  # radial roller bearings carry no axial load in this model
    basic = basic_rating_life(dynamic_rating_N, load, elements)
    factor = None
    if fatigue_limit_N is None and static_rating_N is not None:
        fatigue_limit_N = fatigue_load_limit(static_rating_N, elements=elements)
    if kappa is not None and contamination is not None and fatigue_limit_N is not None:
        factor = a_iso(kappa, contamination, fatigue_limit_N, load, elements)
    base = reference_life_Mrev if reference_life_Mrev is not None else basic
    modified = None if factor is None else factor * base
    if static_safety_value is not None:
        safety = static_safety_value
    elif static_rating_N is not None:
        safety = static_safety(static_rating_N, equivalent_static_load(radial_N, axial_N))
    else:
        safety = math.nan
    minimum = minimum_load(dynamic_rating_N, elements) if minimum_load_N is None else minimum_load_N
    # the rolling elements' own load: with a reference life, the load that gives it by ISO 281 (C L10r^(−1/p));
    # a preload loads the elements though the bearing passes little force on
    carried = load
    if reference_life_Mrev is not None and reference_life_Mrev > 0.0:
        carried = max(load, 0.0 if math.isinf(reference_life_Mrev)
                      else dynamic_rating_N * reference_life_Mrev ** (-1.0 / life_exponent(elements)))
    return LifeResult(equivalent_load_N=load, basic_life_Mrev=basic, reference_life_Mrev=reference_life_Mrev,
                      a_iso=factor, modified_life_Mrev=modified, speed_rpm=speed_rpm,
                      basic_life_h=hours(basic, speed_rpm),
                      reference_life_h=None if reference_life_Mrev is None else hours(reference_life_Mrev, speed_rpm),
                      modified_life_h=None if modified is None else hours(modified, speed_rpm), static_safety=safety,
                      minimum_load_N=minimum, below_minimum_load=carried < minimum)


# --------------------------------------------------------------------------------------------
# Angular-contact, tapered and cylindrical roller bearings (ISO 281 X/Y; ISO/TS 16281 line contact)

B_M_ROLLER = 1.1
"""ISO 281:2007 table 1: b_m for radial roller bearings (cylindrical, tapered)."""
LAMBDA_NU_ROLLER = 0.83
"""λν of ISO 281's roller f_c (207.9 λν …, 207.9 = 0.377 · 552): the reduction for edge stresses and the line-contact
exponent; with it the roller f_c formula reproduces ISO 281 table 7 (tested)."""

# ISO 281:2007 table 3, single-row angular-contact ball bearings (α ≥ 20°): α → (e, X, Y) of a single bearing
# or a tandem set for F_a/F_r > e (X = 1, Y = 0 below), and (Y1; X2, Y2) of a back-to-back or face-to-face
# pair (F_a/F_r ≤ e: X = 1, Y = Y1; above: X2, Y2). Checked against JTEKT (Koyo) catalogue, "Calculation of
# equivalent radial / axial load" (30°, 40°, 15°), and a maker's transcription of the same table (25°).
ANGULAR_XY = {20.0: (0.57, 0.43, 1.00, 1.09, 0.70, 1.63), 25.0: (0.68, 0.41, 0.87, 0.92, 0.67, 1.41),
              30.0: (0.80, 0.39, 0.76, 0.78, 0.63, 1.24), 35.0: (0.95, 0.37, 0.66, 0.66, 0.60, 1.07),
              40.0: (1.14, 0.35, 0.57, 0.55, 0.57, 0.93), 45.0: (1.34, 0.33, 0.50, 0.47, 0.54, 0.81)}
# α = 15°: by i F_a / C0 (C0 of one bearing): (i F_a/C0, e, Y single (X = 0.44), Y1 pair, Y2 pair (X2 = 0.72))
ANGULAR_XY_15 = (np.array([0.015, 0.029, 0.058, 0.087, 0.12, 0.17, 0.29, 0.44, 0.58]),
                 np.array([0.38, 0.40, 0.43, 0.46, 0.47, 0.50, 0.55, 0.56, 0.56]),
                 np.array([1.47, 1.40, 1.30, 1.23, 1.19, 1.12, 1.02, 1.00, 1.00]),
                 np.array([1.65, 1.57, 1.46, 1.38, 1.34, 1.26, 1.14, 1.12, 1.12]),
                 np.array([2.39, 2.28, 2.11, 2.00, 1.93, 1.82, 1.66, 1.63, 1.63]))


def _angular_row(contact_angle_deg: float, axial_over_c0: float) -> tuple[float, ...]:
    """(e, X, Y, Y1, X2, Y2) at ``contact_angle_deg``: the 15° row by i F_a/C0, the others from the table,
    linear in α between its rows (15° … 45°)."""
    alpha = float(contact_angle_deg)
    if not 15.0 - 1e-9 <= alpha <= 45.0 + 1e-9:
        raise ValueError(f"contact angle {alpha:g}° is outside ISO 281's angular-contact table (15° … 45°)")
    key = axial_over_c0
    row15 = (float(np.interp(key, ANGULAR_XY_15[0], ANGULAR_XY_15[1])), 0.44,
             float(np.interp(key, ANGULAR_XY_15[0], ANGULAR_XY_15[2])),
             float(np.interp(key, ANGULAR_XY_15[0], ANGULAR_XY_15[3])), 0.72,
             float(np.interp(key, ANGULAR_XY_15[0], ANGULAR_XY_15[4])))
    angles = sorted(ANGULAR_XY)
    if alpha <= angles[0]:
        t = (alpha - 15.0) / (angles[0] - 15.0)
        return tuple((1.0 - t) * a + t * b for a, b in zip(row15, ANGULAR_XY[angles[0]]))
    return tuple(float(np.interp(alpha, angles, [ANGULAR_XY[a][k] for a in angles])) for k in range(6))


def angular_contact_xy(radial_N: float, axial_N: float, contact_angle_deg: float, *, pair: bool = False,  # noqa: PLR0913
                       static_rating_N: float | None = None, rows: int = 1) -> tuple[float, float, float]:
    """(X, Y, e) of ISO 281 table 3 for an angular-contact ball bearing: a single bearing or a tandem set
    (``pair=False``), or a back-to-back / face-to-face pair (``pair=True``; F_r and F_a on the pair).

    Parameters
    ----------
    radial_N, axial_N : float
        F_r and F_a on the bearing (set).
    contact_angle_deg : float
        α (15° … 45°; between the table's angles linear).
    static_rating_N : float, optional
        C0 of one bearing: needed at α < 20° (the 15° row goes by i F_a / C0).
    rows : int
        i, the bearings of the set (the 15° row's i F_a / C0).
    """
    radial, axial = abs(radial_N), abs(axial_N)
    key = 0.0
    if contact_angle_deg < 20.0:
        if static_rating_N is None:
            raise ValueError("an angular-contact bearing below 20° needs C0 for ISO 281's i F_a / C0")
        key = rows * axial / static_rating_N
    e, x, y, y1, x2, y2 = _angular_row(contact_angle_deg, key)
    above = axial > e * radial
    if pair:
        return (x2, y2, e) if above else (1.0, y1, e)
    return (x, y, e) if above else (1.0, 0.0, e)


def tapered_xy(radial_N: float, axial_N: float, contact_angle_rad: float, *, pair: bool = False
               ) -> tuple[float, float, float]:
    """(X, Y, e) of ISO 281 for a tapered roller bearing of contact angle α: e = 1.5 tan α; single row (or a
    tandem set): F_a/F_r ≤ e → (1, 0), else (0.4, 0.4 cot α); a back-to-back / face-to-face pair: (1, 0.45 cot α),
    else (0.67, 0.67 cot α) (ISO 281:2007 table 8; makers print e, Y (= Y2/…) per size with the same rules)."""
    radial, axial = abs(radial_N), abs(axial_N)
    tan_a = math.tan(contact_angle_rad)
    e = 1.5 * tan_a
    above = axial > e * radial
    if pair:
        return (0.67, 0.67 / tan_a, e) if above else (1.0, 0.45 / tan_a, e)
    return (0.4, 0.4 / tan_a, e) if above else (1.0, 0.0, e)


def cylindrical_xy(radial_N: float, axial_N: float) -> tuple[float, float, float]:
    """(X, Y, e) of a cylindrical roller bearing with ribs on both rings (NJ, NUP) carrying a thrust through them
    (the makers' rule for the 10, 2, 3 and 4 series: e = 0.2, F_a/F_r > e → P = 0.92 F_r + 0.6 F_a, as a maker's
    technical page prints it, honghui188.com "Radial Equivalent Dynamic Load"; SKF's double-row full-complement
    pages give the same form with their own e, Y); P = F_r without thrust."""
    radial, axial = abs(radial_N), abs(axial_N)
    return (0.92, 0.6, 0.2) if axial > 0.2 * radial else (1.0, 0.0, 0.2)


def pair_dynamic_rating(rating_N: float, rows: int, elements: str) -> float:
    """C of i equal bearings (rows) working as a unit (ISO 281): i^0.7 C (ball), i^(7/9) C (roller)."""
    life_exponent(elements)
    return rating_N * rows ** (0.7 if elements == "ball" else 7.0 / 9.0)


def lamina_contact_ratings(rollers: int, roller_diameter_mm: float, length_mm: float, pitch_diameter_mm: float,  # noqa: PLR0913
                           *, contact_angle_rad: float, slices: int) -> tuple[float, float]:
    """q_ci and q_ce (N): the basic dynamic ratings of one lamina's inner and outer line contact (ISO/TS 16281,
    Lundberg–Palmgren's line contact with ISO 281's b_m and λν):

    q_c = 552 b_m λν (1 ∓ γ)^(29/27) / (1 ± γ)^(1/4) (γ/cos α)^(2/9) D_w^(29/27) l_we^(7/9) Z^(−1/4) n^(−7/9),
    γ = D_w cos α / d_m (upper signs inner ring; a lamina of width l_we/n rates (1/n)^(7/9) of the roller).
    """
    cos_a = math.cos(contact_angle_rad)
    gamma = roller_diameter_mm * cos_a / pitch_diameter_mm
    common = (552.0 * B_M_ROLLER * LAMBDA_NU_ROLLER * (gamma / cos_a) ** (2.0 / 9.0)
              * roller_diameter_mm ** (29.0 / 27.0) * length_mm ** (7.0 / 9.0) * rollers ** (-0.25)
              * slices ** (-7.0 / 9.0))
    inner = common * (1.0 - gamma) ** (29.0 / 27.0) / (1.0 + gamma) ** 0.25
    outer = common * (1.0 + gamma) ** (29.0 / 27.0) / (1.0 - gamma) ** 0.25
    return inner, outer


def line_contact_life(lamina_loads_N, inner_rating_N: float, outer_rating_N: float, *, rotating: str = "inner"
                      ) -> float:
    """L10r (million revolutions) of a roller row from its lamina loads q_jk (Z, n) (ISO/TS 16281):

    per lamina k the rotating ring's equivalent load (Σ_j q_jk⁴ / Z)^(1/4), the stationary ring's
    (Σ_j q_jk^4.5 / Z)^(1/4.5); L_k = (q_c / q_e)⁴ per ring; L10r = (Σ_k (L_ik^(−9/8) + L_ek^(−9/8)))^(−8/9).
    """
    q = np.abs(np.asarray(lamina_loads_N, dtype=float))
    if q.ndim != 2:
        raise ValueError("lamina loads must be (rollers, laminae)")
    if not np.any(q > 0):
        return math.inf
    weibull = 9.0 / 8.0
    damage = 0.0
    for rating, power in ((inner_rating_N, 4.0 if rotating == "inner" else 4.5),
                          (outer_rating_N, 4.5 if rotating == "inner" else 4.0)):
        equivalent = np.mean(q**power, axis=0) ** (1.0 / power)  # (n,)
        loaded = equivalent > 0
        damage += float(np.sum((equivalent[loaded] / rating) ** (4.0 * weibull)))
    return damage ** (-1.0 / weibull)


def system_life(lives, weibull_slope: float) -> float:
    """The life of components that fail on their own (rows of a pair): (Σ L_r^(−e))^(−1/e); inf if all are."""
    lives = [life for life in lives if math.isfinite(life)]
    if not lives:
        return math.inf
    return float(sum(life ** (-weibull_slope) for life in lives) ** (-1.0 / weibull_slope))


def rows_reference_life(bearing, elements, rotating: str = "inner") -> float:
    """L10r (million revolutions, ISO/TS 16281) of a rolling bearing of one or more rows from the loads of its
    rolling elements: a ball row from its ball loads and contact angles (:func:`ring_contact_ratings`,
    :func:`element_rating_life`), a roller row from its lamina loads (:func:`lamina_contact_ratings`,
    :func:`line_contact_life`); the rows, failing on their own, combine as :func:`system_life` with the Weibull
    slope of their contacts (10/9 ball, 9/8 roller; a mixed bearing does not occur).

    Parameters
    ----------
    bearing : RollingBearing
        Its rows (:mod:`rvcoax.fem.rolling_bearing`).
    elements : ElementLoads
        :func:`rvcoax.fem.rolling_bearing.rolling_element_loads` at the operating point.
    rotating : str
        ``inner`` (shaft rotates, default) or ``outer``.
    """
    from rvcoax.fem.ball_bearing import BallBearingGeometry

    lives, slope = [], 10.0 / 9.0
    for r, row in enumerate(bearing.rows):
        law = row.law
        if isinstance(law, BallBearingGeometry):
            mine = elements.row == r
            inner, outer = ring_contact_ratings(law.ball_count, law.ball_diameter_m * 1e3, law.pitch_diameter_m * 1e3,
                                                law.inner_conformity, law.outer_conformity,
                                                contact_angle_rad=elements.contact_angle_rad[mine])
            lives.append(element_rating_life(elements.load_n[mine], inner, outer, rotating=rotating))
        else:
            slope = 9.0 / 8.0
            inner, outer = lamina_contact_ratings(law.roller_count, law.roller_diameter_m * 1e3,
                                                  law.roller_length_m * 1e3, law.pitch_diameter_m * 1e3,
                                                  contact_angle_rad=law.contact_angle_rad, slices=law.slices)
            lives.append(line_contact_life(elements.lamina_load_n[r], inner, outer, rotating=rotating))
    return system_life(lives, slope)


def rows_static_safety(elements) -> float:
    """s0 of a bearing from its most pressed contact (ISO 76: 4200 MPa ball, 4000 MPa roller;
    :func:`static_safety_from_pressure` per row, the smallest)."""
    safeties = [math.inf]
    for r, kind in enumerate(elements.kind):
        pressure = elements.max_contact_pressure_Pa[elements.row == r]
        safeties.append(static_safety_from_pressure(float(pressure.max(initial=0.0)) * 1e-6, kind))
    return min(safeties)
