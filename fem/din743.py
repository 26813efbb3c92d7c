"""Shaft strength per DIN 743 (2012): static and fatigue safety at one notch (N, mm, MPa as the standard
writes them).

Plain functions and frozen dataclasses that know nothing of rigs: a notch enters as its geometry
(:class:`Notch`), the steel as :class:`Steel`, the loads as nominal stresses (:class:`NotchStresses`,
mean, amplitude and maximum per loading type). :func:`safety` returns every intermediate factor, so a
reader can check the chain the way the standard's examples print it.

Part 1 (safety)
    S_D = 1 / √((σ_zda/σ_zdADK + σ_ba/σ_bADK)² + (τ_ta/τ_tADK)²) against fatigue fracture,
    S_F = 1 / √((σ_zdmax/σ_zdFK + σ_bmax/σ_bFK)² + (τ_tmax/τ_tFK)²) against permanent deformation;
    σ_WK = σ_W(d_B) K1(d_eff) / K_σ, K_σ = (β_σ / K2(d) + 1/K_Fσ − 1) / K_V (K_V = 1: no surface hardening);
    ψ_σK = σ_WK / (2 K1(d_eff) σ_B(d_B) − σ_WK); equivalent mean stress σ_mv = √((σ_zdm + σ_bm)² + 3 τ_tm²),
    τ_mv = σ_mv/√3; overload case 1 (σ_mv constant) σ_ADK = σ_WK − ψ σ_mv (≤ σ_FK − σ_mv past the yield line),
    case 2 (σ_mv/σ_a constant, the default) σ_ADK = σ_WK / (1 + ψ σ_mv/σ_a) (σ_FK / (1 + σ_mv/σ_a) past it);
    σ_FK = K1(d_eff) K2F γF σ_S(d_B), τ_FK = K1 K2F γF σ_S/√3 with K2F = 1.2 (bending, torsion; solid,
    not surface-hardened), 1.1 / 1.0 (hollow bending / torsion), 1.0 (tension; and with a hard surface
    layer), γF by α_σ for circumferential notches (1.0 / 1.05 / 1.1 / 1.15 at α < 1.5 / < 2 / < 3 / ≥ 3),
    1.0 otherwise and for torsion.
Part 2 (notch factors)
    Shoulder and round groove from their stress concentration factor
    α = 1 + 1/√(A r/t + 2B (r/d)(1 + 2r/d)² + C (r/t)^z d/D) (tension, bending, torsion constants
    :data:`SHOULDER_CONSTANTS`, :data:`GROOVE_CONSTANTS`) and the support number
    n = 1 + √(G′ mm) 10^−(0.33 + σ_S(d)/712 MPa) (surface-hardened: 10^−0.7), G′ = 2.3 (1 + φ)/r (shoulder,
    tension and bending), 1.15/r (shoulder torsion), 2 (1 + φ)/r and 1/r (groove), φ = 1/(4√(t/r) + 2) for
    d/D ≥ 0.67, else 0; β = α/n (n ≤ α). Keyway (feather key, end-milled) and press fit from the measured
    values at d_BK = 40 mm: β_σ = 3.0 (σ_B(d)/1000 MPa)^0.38 (keyway; × 1.15 for two keys), β_τ = 0.56 β_σ + 0.1;
    β_σ = 2.7 (σ_B(d)/1000 MPa)^0.43 (press fit), β_τ = 0.65 β_σ; carried to the diameter by
    β(d) = β(d_BK) K3(d_BK)/K3(d), K3(d) = 1 − 0.2 lg β lg(d/7.5 mm)/lg 20 (d ≥ 150 mm: 1 − 0.2 lg β).
    Keyways and press fits carry their surface in β: K_F = 1 there.
    Geometric size factor K2(d) = 1 − 0.2 lg(d/7.5 mm)/lg 20 (bending, torsion; 0.8 from 150 mm; 1 below
    7.5 mm and for tension); roughness factor K_Fσ = 1 − 0.22 lg(Rz/µm)(lg(σ_B(d)/20 MPa) − 1),
    K_Fτ = 0.575 K_Fσ + 0.425.
Part 3 (material)
    σ_bW = 0.5 σ_B(d_B), σ_zdW = 0.4 σ_B(d_B), τ_tW = 0.3 σ_B(d_B); technological size factor K1(d_eff)
    per steel group (:func:`technological_size_factor`), for the tensile strength and for the yield point.

Sources: DIN 743-1…3:2012-12 as their equations are quoted in the project's docs (docs/model.md); the
constants are recalled from the standard [R] and agree with an independent open-source transcription
(github.com/hanslhansl/din743); :func:`safety` reproduces that project's published test cases to the
four digits they assert (tests/fem/test_din743.py). The stress concentration factors α lie within −13 % … +3 % of
an axisymmetric FE model's elastic α over 13 shoulders and grooves (tests/fem/test_din743_notch_fe.py). No
published DIN 743 worked example (Beiblatt 1) could be read: see docs/model.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

__all__ = ["GROOVE_CONSTANTS", "NOTCH_KINDS", "SHOULDER_CONSTANTS", "STEEL_GROUPS", "Din743Result", "Notch",
           "NotchFactors", "NotchStresses", "Steel", "geometric_size_factor", "notch_factors", "nominal_stresses",
           "roughness_factors", "safety", "technological_size_factor"]

STEEL_GROUPS = ("quenched_tempered", "case_hardening", "structural", "nitriding")
NOTCH_KINDS = ("shoulder", "groove", "keyway", "press_fit")

# (A, B, C, z) of α = 1 + 1/√(A r/t + 2B r/d (1 + 2r/d)² + C (r/t)^z d/D), per tension, bending, torsion [R]
SHOULDER_CONSTANTS = {"tension": (0.62, 3.5, 0.0, 0.0), "bending": (0.62, 5.8, 0.2, 3.0),
                      "torsion": (3.4, 19.0, 1.0, 2.0)}
GROOVE_CONSTANTS = {"tension": (0.22, 1.37, 0.0, 0.0), "bending": (0.2, 2.75, 0.0, 0.0),
                    "torsion": (0.7, 10.3, 0.0, 0.0)}
REFERENCE_DIAMETER_BK_MM = 40.0  # d_BK of the measured keyway and press-fit notch factors


@dataclass(frozen=True)
class Steel:
    """A steel's strength at its reference diameter d_B (DIN 743-3), MPa.

    ``group``: ``quenched_tempered`` (Vergütungsstahl), ``case_hardening`` (Einsatzstahl), ``structural``
    (Baustahl), ``nitriding`` (Nitrierstahl): it sets K1(d_eff).
    """

    tensile_strength_MPa: float
    yield_strength_MPa: float
    group: Literal["quenched_tempered", "case_hardening", "structural", "nitriding"] = "quenched_tempered"

    def __post_init__(self) -> None:
        if self.group not in STEEL_GROUPS:
            raise ValueError(f"steel group must be one of {', '.join(STEEL_GROUPS)}, got {self.group!r}")
        if not 0.0 < self.yield_strength_MPa <= self.tensile_strength_MPa:
            raise ValueError(f"need 0 < yield strength ({self.yield_strength_MPa} MPa) ≤ tensile strength "
                             f"({self.tensile_strength_MPa} MPa)")


@dataclass(frozen=True)
class Notch:
    """The notch at a shaft section (mm, µm).

    ``diameter_mm`` is d, the notch section's diameter (the smaller diameter at a shoulder, the groove root
    for a groove, the shaft under a keyway or hub); ``depth_mm`` t (shoulder: (D − d)/2; groove: its
    depth); ``radius_mm`` r (shoulder fillet, groove root). ``bore_mm`` > 0 makes it a hollow shaft (K2F).
    """

    kind: Literal["shoulder", "groove", "keyway", "press_fit"]
    diameter_mm: float
    depth_mm: float = 0.0
    radius_mm: float = 0.0
    keys: int = 1
    roughness_Rz_um: float = 6.3
    bore_mm: float = 0.0
    hard_surface: bool = False

    def __post_init__(self) -> None:
        if self.kind not in NOTCH_KINDS:
            raise ValueError(f"notch kind must be one of {', '.join(NOTCH_KINDS)}, got {self.kind!r}")
        if self.kind in ("shoulder", "groove"):
            if not (self.depth_mm > 0.0 and self.radius_mm > 0.0):
                raise ValueError(f"a {self.kind} needs depth_mm > 0 and radius_mm > 0")
            if self.radius_mm / self.depth_mm < 0.03:
                raise ValueError(f"{self.kind}: r/t = {self.radius_mm / self.depth_mm:.3g} is below 0.03, outside "
                                 "DIN 743-2's stress concentration formula")
            if self.diameter_mm / self.outer_diameter_mm > 0.98:
                raise ValueError(f"{self.kind}: d/D = {self.diameter_mm / self.outer_diameter_mm:.4g} is above 0.98, "
                                 "outside DIN 743-2's stress concentration formula (no notch to speak of)")
        if self.keys not in (1, 2):
            raise ValueError(f"keys must be 1 or 2, got {self.keys}")

    @property
    def outer_diameter_mm(self) -> float:
        """D = d + 2t."""
        return self.diameter_mm + 2.0 * self.depth_mm

    @property
    def circumferential(self) -> bool:
        """A notch all round the shaft (γF applies to it)."""
        return self.kind in ("shoulder", "groove", "press_fit")


@dataclass(frozen=True)
class NotchStresses:
    """Nominal stresses at the notch section, MPa: mean, amplitude and maximum per loading type.

    Tension/compression σ_zd (compression negative), bending σ_b, torsion τ_t. A rotating shaft under a
    steady bending moment M has σ_ba = M/W_b and σ_bm = 0; a steady torque T gives τ_tm = T/W_t, τ_ta = 0.
    """

    tension_mean: float = 0.0
    tension_amplitude: float = 0.0
    tension_max: float = 0.0
    bending_mean: float = 0.0
    bending_amplitude: float = 0.0
    bending_max: float = 0.0
    torsion_mean: float = 0.0
    torsion_amplitude: float = 0.0
    torsion_max: float = 0.0


@dataclass(frozen=True)
class NotchFactors:
    """β (and α where the notch has one) per tension, bending and torsion."""

    beta_tension: float
    beta_bending: float
    beta_torsion: float
    alpha_tension: float | None = None
    alpha_bending: float | None = None
    alpha_torsion: float | None = None


@dataclass(frozen=True)
class Din743Result:
    """One notch's DIN 743 safety with its chain of factors (MPa where a stress)."""

    fatigue_safety: float
    static_safety: float
    factors: NotchFactors
    K1_tensile: float
    K1_yield: float
    K2_bending: float
    K_F_sigma: float
    K_F_tau: float
    K_sigma_tension: float
    K_sigma_bending: float
    K_tau: float
    sigma_zdWK: float
    sigma_bWK: float
    tau_tWK: float
    sigma_mv: float
    sigma_zdADK: float
    sigma_bADK: float
    tau_tADK: float
    sigma_zdFK: float
    sigma_bFK: float
    tau_tFK: float


def technological_size_factor(group: str, d_eff_mm: float, yield_point: bool = False) -> float:
    """K1(d_eff), DIN 743-3 [R]: how the strength at the reference diameter falls with the heat-treatment diameter.

    quenched_tempered: 1 up to 16 mm, 1 − 0.26 lg(d_eff/16 mm) (yield point: 0.34) up to 300 mm, 0.67 (0.57) to
    500 mm; case_hardening: 1 − 0.41 lg(d_eff/16 mm) to 150 mm, 0.6 to 500 mm; structural (tensile strength) and
    nitriding: 1 up to 100 mm, 1 − 0.23 lg(d_eff/100 mm) to 300 mm, 0.89 to 500 mm; structural (yield point): 1 up
    to 32 mm, 1 − 0.26 lg(d_eff/32 mm) to 300 mm, 0.75 to 500 mm.
    """
    if not 0.0 < d_eff_mm <= 500.0:
        raise ValueError(f"d_eff = {d_eff_mm:g} mm is outside DIN 743-3's range (0, 500] mm")
    d = d_eff_mm
    if group == "quenched_tempered":
        k = 0.34 if yield_point else 0.26
        return 1.0 if d <= 16.0 else 1.0 - k * math.log10(d / 16.0) if d <= 300.0 else (0.57 if yield_point else 0.67)
    if group == "case_hardening":
        return 1.0 if d <= 16.0 else 1.0 - 0.41 * math.log10(d / 16.0) if d <= 150.0 else 0.6
    if group == "structural" and yield_point:
        return 1.0 if d <= 32.0 else 1.0 - 0.26 * math.log10(d / 32.0) if d <= 300.0 else 0.75
    if group in ("structural", "nitriding"):
        return 1.0 if d <= 100.0 else 1.0 - 0.23 * math.log10(d / 100.0) if d <= 300.0 else 0.89
    raise ValueError(f"steel group must be one of {', '.join(STEEL_GROUPS)}, got {group!r}")


def geometric_size_factor(d_mm: float) -> float:
    """K2(d) for bending and torsion (tension: 1): 1 − 0.2 lg(d/7.5 mm)/lg 20, 1 below 7.5 mm, 0.8 from 150 mm."""
    if d_mm < 7.5:
        return 1.0
    if d_mm >= 150.0:
        return 0.8
    return 1.0 - 0.2 * math.log10(d_mm / 7.5) / math.log10(20.0)


def _k3(d_mm: float, beta: float) -> float:
    if d_mm < 7.5:
        return 1.0
    share = 1.0 if d_mm >= 150.0 else math.log10(d_mm / 7.5) / math.log10(20.0)
    return 1.0 - 0.2 * math.log10(beta) * share


def roughness_factors(Rz_um: float, tensile_strength_MPa: float) -> tuple[float, float]:
    """(K_Fσ, K_Fτ) of a machined surface of roughness Rz at the tensile strength σ_B(d)."""
    if Rz_um <= 1.0:
        return 1.0, 1.0
    k = 1.0 - 0.22 * math.log10(Rz_um) * (math.log10(tensile_strength_MPa / 20.0) - 1.0)
    return k, 0.575 * k + 0.425


def _alpha(constants, r: float, t: float, d: float, D: float) -> float:
    A, B, C, z = constants
    return 1.0 + 1.0 / math.sqrt(A * r / t + 2.0 * B * r / d * (1.0 + 2.0 * r / d) ** 2 + C * (r / t) ** z * d / D)


def notch_factors(notch: Notch, tensile_strength_MPa: float, yield_strength_MPa: float) -> NotchFactors:
    """β_σ (tension, bending) and β_τ of ``notch`` at the strengths σ_B(d), σ_S(d) of its section (MPa)."""
    if notch.kind in ("shoulder", "groove"):
        d, r, t, D = notch.diameter_mm, notch.radius_mm, notch.depth_mm, notch.outer_diameter_mm
        constants = SHOULDER_CONSTANTS if notch.kind == "shoulder" else GROOVE_CONSTANTS
        alphas = {k: _alpha(c, r, t, d, D) for k, c in constants.items()}
        phi = 1.0 / (4.0 * math.sqrt(t / r) + 2.0) if d / D >= 0.67 else 0.0
        g = (2.3, 1.15) if notch.kind == "shoulder" else (2.0, 1.0)
        gradients = {"tension": g[0] * (1.0 + phi) / r, "bending": g[0] * (1.0 + phi) / r, "torsion": g[1] / r}
        exponent = 0.7 if notch.hard_surface else 0.33 + yield_strength_MPa / 712.0
        betas = {k: alphas[k] / min(1.0 + math.sqrt(gradients[k]) * 10.0 ** (-exponent), alphas[k]) for k in alphas}
        return NotchFactors(betas["tension"], betas["bending"], betas["torsion"], alpha_tension=alphas["tension"],
                            alpha_bending=alphas["bending"], alpha_torsion=alphas["torsion"])
    strength = tensile_strength_MPa / 1000.0
    if notch.kind == "keyway":
        two = 1.15 if notch.keys == 2 else 1.0
        sigma, tau = 3.0 * strength ** 0.38 * two, (0.56 * 3.0 * strength ** 0.38 + 0.1) * two
    else:  # press fit
        sigma = 2.7 * strength ** 0.43
        tau = 0.65 * sigma

    def at_diameter(beta: float) -> float:
        return beta * _k3(REFERENCE_DIAMETER_BK_MM, beta) / _k3(notch.diameter_mm, beta)

    return NotchFactors(at_diameter(sigma), at_diameter(sigma), at_diameter(tau))


def nominal_stresses(notch: Notch, axial_force_N: float, bending_moment_Nm: float, torque_Nm: float) -> tuple:
    """(σ_zd, σ_b, τ_t) in MPa of the section forces on the notch section (d, its bore)."""
    d, bore = notch.diameter_mm, notch.bore_mm
    area = math.pi / 4.0 * (d**2 - bore**2)
    w_b = math.pi / 32.0 * (d**4 - bore**4) / d
    return axial_force_N / area, bending_moment_Nm * 1e3 / w_b, torque_Nm * 1e3 / (2.0 * w_b)


def _gamma_F(alpha: float | None, notch: Notch) -> float:
    if not notch.circumferential or notch.hard_surface or alpha is None:
        return 1.0
    return 1.0 if alpha < 1.5 else 1.05 if alpha < 2.0 else 1.1 if alpha < 3.0 else 1.15


def _adk(case: int, mean: float, amplitude: float, strengths: tuple[float, float, float]) -> float:
    """σ_ADK of overload case 1 or 2 (DIN 743-1 eqs. 10–19); ``strengths`` = (σ_FK, σ_WK, ψ_σK)."""
    yield_k, fatigue_k, psi = strengths
    if case == 1:
        if mean <= (yield_k - fatigue_k) / (1.0 - psi):
            return fatigue_k - psi * mean
        return yield_k - mean
    if amplitude == 0.0:
        return fatigue_k  # no amplitude: its term is 0 whatever σ_ADK
    ratio = mean / amplitude
    if ratio <= (yield_k - fatigue_k) / (fatigue_k - yield_k * psi):
        return fatigue_k / (1.0 + psi * ratio)
    return yield_k / (1.0 + ratio)


def _ratio(a: float, b: float) -> float:
    return 0.0 if a == 0.0 else abs(a) / b if b > 0.0 else math.inf


def safety(steel: Steel, notch: Notch, stresses: NotchStresses, *, d_eff_mm: float | None = None,  # noqa: PLR0913
           overload_case: int = 2, factors: NotchFactors | None = None) -> Din743Result:
    """DIN 743 fatigue and static safety of one notch.

    Parameters
    ----------
    steel : Steel
    notch : Notch
    stresses : NotchStresses
        Nominal stresses at the notch section, MPa.
    d_eff_mm : float, optional
        The diameter that governs the heat treatment (default: D of a shoulder, else d).
    overload_case : {1, 2}
        1: the mean stress stays as the load grows; 2 (default): mean and amplitude grow together.
    factors : NotchFactors, optional
        Notch factors to use instead of DIN 743-2's (a measured β).

    Returns
    -------
    Din743Result
    """
    if overload_case not in (1, 2):
        raise ValueError(f"overload_case must be 1 or 2, got {overload_case}")
    d_eff = notch.outer_diameter_mm if d_eff_mm is None else d_eff_mm
    k1b = technological_size_factor(steel.group, d_eff)
    k1s = technological_size_factor(steel.group, d_eff, yield_point=True)
    sigma_B, sigma_S = k1b * steel.tensile_strength_MPa, k1s * steel.yield_strength_MPa
    f = notch_factors(notch, sigma_B, sigma_S) if factors is None else factors
    k2 = geometric_size_factor(notch.diameter_mm)
    kf_sigma, kf_tau = (1.0, 1.0) if notch.kind in ("keyway", "press_fit") else roughness_factors(
        notch.roughness_Rz_um, sigma_B)
    k_zd = f.beta_tension + 1.0 / kf_sigma - 1.0
    k_b = f.beta_bending / k2 + 1.0 / kf_sigma - 1.0
    k_t = f.beta_torsion / k2 + 1.0 / kf_tau - 1.0
    base = steel.tensile_strength_MPa
    zdWK, bWK, tWK = 0.4 * base * k1b / k_zd, 0.5 * base * k1b / k_b, 0.3 * base * k1b / k_t

    def psi(wk: float) -> float:
        return wk / (2.0 * k1b * base - wk)

    hollow = notch.bore_mm > 0.0
    k2f_b = 1.0 if notch.hard_surface else 1.1 if hollow else 1.2
    k2f_t = 1.0 if notch.hard_surface or hollow else 1.2
    zdFK = k1s * _gamma_F(f.alpha_tension, notch) * steel.yield_strength_MPa
    bFK = k1s * k2f_b * _gamma_F(f.alpha_bending, notch) * steel.yield_strength_MPa
    tFK = k1s * k2f_t * steel.yield_strength_MPa / math.sqrt(3.0)
    s = stresses
    normal_mean = s.tension_mean + s.bending_mean
    squared = normal_mean * abs(normal_mean) + 3.0 * s.torsion_mean**2  # compression lowers σ_mv
    sigma_mv = math.copysign(math.sqrt(abs(squared)), squared)
    tau_mv = max(sigma_mv, 0.0) / math.sqrt(3.0)
    zdADK = _adk(overload_case, sigma_mv, abs(s.tension_amplitude), (zdFK, zdWK, psi(zdWK)))
    bADK = _adk(overload_case, sigma_mv, abs(s.bending_amplitude), (bFK, bWK, psi(bWK)))
    tADK = _adk(overload_case, tau_mv, abs(s.torsion_amplitude), (tFK, tWK, psi(tWK)))
    fatigue = math.hypot(_ratio(s.tension_amplitude, zdADK) + _ratio(s.bending_amplitude, bADK),
                         _ratio(s.torsion_amplitude, tADK))
    static = math.hypot(_ratio(s.tension_max, zdFK) + _ratio(s.bending_max, bFK), _ratio(s.torsion_max, tFK))
    return Din743Result(
        fatigue_safety=math.inf if fatigue == 0.0 else 1.0 / fatigue,
        static_safety=math.inf if static == 0.0 else 1.0 / static,
        factors=f, K1_tensile=k1b, K1_yield=k1s, K2_bending=k2, K_F_sigma=kf_sigma, K_F_tau=kf_tau,
        K_sigma_tension=k_zd, K_sigma_bending=k_b, K_tau=k_t, sigma_zdWK=zdWK, sigma_bWK=bWK, tau_tWK=tWK,
        sigma_mv=sigma_mv, sigma_zdADK=zdADK, sigma_bADK=bADK, tau_tADK=tADK, sigma_zdFK=zdFK, sigma_bFK=bFK,
        tau_tFK=tFK)

