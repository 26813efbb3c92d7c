"""Operating clearance of a ball bearing from its fits: ISO 286 tolerance classes, ISO 492 ring tolerances,
thick-ring (Lamé) expansion of the inner and contraction of the outer raceway (µm, mm, MPa).

Interference (diametral, µm; negative: a clearance fit, which leaves the ring as it is)
    shaft d + [ei, es] (ISO 286-2, :data:`SHAFT_DEVIATIONS`) on the inner ring's bore d + [Δ_dmp, 0]
    (ISO 492 normal tolerance class, :data:`BORE_TOLERANCE`): I_i ∈ [ei, es − Δ_dmp];
    outer ring D + [Δ_Dmp, 0] in the housing bore D + [EI, ES]: I_o ∈ [Δ_Dmp − ES, −EI].
    The interference is taken as toleranced (the smoothing of the surfaces by the press fit, 1–3 µm, is not
    subtracted: the clearance comes out a little small, the safe side for a preload check).
Thick rings (Lamé; plane stress, each body its own E and ν)
    inner ring a = d/2 … b = d_1/2 (d_1 = D_pw − D_w, the groove bottom) on a shaft c = d_bore/2 … a, pressure p:
        p [a/E_r ((b² + a²)/(b² − a²) + ν_r) + a/E_s ((a² + c²)/(a² − c²) − ν_s)] = I_i/2,
        raceway growth Δd_1 = 4 p a² b / (E_r (b² − a²));
    outer ring e = D_1/2 (D_1 = D_pw + D_w) … f = D/2 in a housing f … g = D_h/2:
        p [f/E_r ((f² + e²)/(f² − e²) − ν_r) + f/E_h ((g² + f²)/(g² − f²) + ν_h)] = I_o/2,
        raceway shrinkage ΔD_1 = 4 p f² e / (E_r (f² − e²)).
    For a solid shaft of the ring's steel, Δd_1 = I_i d/d_1 exactly (the textbook rule; tested).
Operating clearance
    P_op = P_unmounted − Δd_1 − ΔD_1 (+ the [thermal] change, as before), as a range from the loosest
    (smallest interferences, largest clearance of the class) to the tightest combination; solved with the
    middle of the class and the mean interference (``fit_clearance = "mean"``), or either end.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

__all__ = ["BORE_TOLERANCE", "FitClearance", "HOLE_DEVIATIONS", "OUTSIDE_TOLERANCE", "SHAFT_DEVIATIONS", "SIZE_STEPS",
           "fit_clearance", "housing_interference_um", "inner_raceway_growth_um", "it_grade_um",
           "outer_raceway_shrinkage_um", "shaft_interference_um", "tolerance_zone_um"]

SIZE_STEPS = (3, 6, 10, 18, 30, 50, 80, 120, 180, 250, 315, 400, 500)
"""ISO 286-1 nominal size steps (mm): a size over one step up to and including the next."""
# ISO 286-1 table 1: standard tolerance grades IT5 … IT7 (µm) per size step (0 … 3 mm first)
_IT = {5: (4, 5, 6, 8, 9, 11, 13, 15, 18, 20, 23, 25, 27),
       6: (6, 8, 9, 11, 13, 16, 19, 22, 25, 29, 32, 36, 40),
       7: (10, 12, 15, 18, 21, 25, 30, 35, 40, 46, 52, 57, 63)}
# ISO 286-2: shaft fundamental deviations (µm) per size step: ("es", values) upper or ("ei", values) lower
SHAFT_DEVIATIONS = {
    "g": ("es", (-2, -4, -5, -6, -7, -9, -10, -12, -14, -15, -17, -18, -20)),
    "h": ("es", (0,) * 13),
    "j": ("ei", (-2, -2, -2, -3, -4, -5, -7, -9, -11, -13, -16, -18, -20)),  # j5 and j6
    "k": ("ei", (0, 1, 1, 1, 2, 2, 2, 3, 3, 4, 4, 4, 5)),
    "m": ("ei", (2, 4, 6, 7, 8, 9, 11, 13, 15, 17, 20, 21, 23)),
    "n": ("ei", (4, 8, 10, 12, 15, 17, 20, 23, 27, 31, 34, 37, 40)),
    "p": ("ei", (6, 12, 15, 18, 22, 26, 32, 37, 43, 50, 56, 62, 68)),
}
# ISO 286-2: hole deviations (µm) per size step for grades 6 and 7: ("EI", values) or ("ES", {grade: values})
HOLE_DEVIATIONS = {
    "G": ("EI", (2, 4, 5, 6, 7, 9, 10, 12, 14, 15, 17, 18, 20)),
    "H": ("EI", (0,) * 13),
    "J": ("ES", {6: (2, 5, 5, 6, 8, 10, 13, 16, 18, 22, 25, 29, 33), 7: (4, 6, 8, 10, 12, 14, 18, 22, 26, 30, 36, 39, 43)}),
    "K": ("ES", {6: (0, 2, 2, 2, 2, 3, 4, 4, 4, 5, 5, 7, 8), 7: (0, 3, 5, 6, 6, 7, 9, 10, 12, 13, 16, 17, 18)}),
    "M": ("ES", {6: (-2, -1, -3, -4, -4, -4, -5, -6, -8, -8, -9, -10, -10), 7: (-2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0)}),
    "N": ("ES", {6: (-4, -5, -7, -9, -11, -12, -14, -16, -20, -22, -25, -26, -27),
                 7: (-4, -4, -4, -5, -7, -8, -9, -10, -12, -14, -14, -16, -17)}),
    "P": ("ES", {7: (-6, -8, -9, -11, -14, -17, -21, -24, -28, -33, -36, -41, -45)}),
}
# ISO 492 normal tolerance class: lower deviation of the mean bore Δ_dmp and mean outside diameter Δ_Dmp (µm;
# upper 0) by size, (over … incl mm)
BORE_TOLERANCE = ((2.5, 10, -8), (10, 18, -8), (18, 30, -10), (30, 50, -12), (50, 80, -15), (80, 120, -20),
                  (120, 180, -25), (180, 250, -30), (250, 315, -35), (315, 400, -40), (400, 500, -45))
OUTSIDE_TOLERANCE = ((6, 18, -8), (18, 30, -9), (30, 50, -11), (50, 80, -13), (80, 120, -15), (120, 150, -18),
                     (150, 180, -25), (180, 250, -30), (250, 315, -35), (315, 400, -40), (400, 500, -45),
                     (500, 630, -50))
_CLASS = re.compile(r"^(?P<letter>[a-zA-Z]{1,2})(?P<grade>\d)$")


def _step(size_mm: float) -> int:
    if not 0.0 < size_mm <= SIZE_STEPS[-1]:
        raise ValueError(f"size {size_mm:g} mm is outside ISO 286's table here (0 … {SIZE_STEPS[-1]} mm)")
    return int(np.searchsorted(SIZE_STEPS, size_mm, side="left"))


def it_grade_um(grade: int, size_mm: float) -> float:
    """The standard tolerance IT``grade`` (µm) at a nominal size (ISO 286-1; grades 5 … 7)."""
    if grade not in _IT:
        raise ValueError(f"IT{grade}: only grades 5, 6 and 7 are tabulated here")
    return float(_IT[grade][_step(size_mm)])


def tolerance_zone_um(tolerance_class: str, size_mm: float) -> tuple[float, float]:
    """(lower, upper) deviation (µm) of an ISO 286 tolerance class at a nominal size: shafts lower case
    (g5 … p6, js), holes upper case (G6 … P7, JS).

    Raises
    ------
    ValueError
        An unknown class or grade, or a size outside the table; the message lists the known classes.
    """
    match = _CLASS.match(tolerance_class)
    known = ("shafts: " + ", ".join(f"{k}5, {k}6" for k in SHAFT_DEVIATIONS) + ", js5, js6; housings: "
             + ", ".join(f"{k}6, {k}7" for k in HOLE_DEVIATIONS if k != "P") + ", P7, JS6, JS7")
    if not match:
        raise ValueError(f"{tolerance_class!r} is not an ISO 286 tolerance class (letter and grade, e.g. k5 or H7; {known})")
    letter, grade = match["letter"], int(match["grade"])
    step = _step(size_mm)
    if letter in ("js", "JS"):
        half = it_grade_um(grade, size_mm) / 2.0
        return -half, half
    if letter in SHAFT_DEVIATIONS and grade in (5, 6):
        it = it_grade_um(grade, size_mm)
        side, values = SHAFT_DEVIATIONS[letter]
        return (values[step] - it, float(values[step])) if side == "es" else (float(values[step]), values[step] + it)
    if letter in HOLE_DEVIATIONS and grade in (6, 7):
        side, values = HOLE_DEVIATIONS[letter]
        it = it_grade_um(grade, size_mm)
        if side == "EI":
            return float(values[step]), values[step] + it
        if grade in values:
            return values[grade][step] - it, float(values[grade][step])
    raise ValueError(f"tolerance class {tolerance_class!r} is not tabulated here ({known})")


def _ring_tolerance(table, size_mm: float, what: str) -> float:
    for low, high, lower in table:
        if low < size_mm <= high:
            return float(lower)
    raise ValueError(f"{what} {size_mm:g} mm is outside ISO 492's normal tolerance table")


def shaft_interference_um(shaft_class: str, bore_mm: float) -> tuple[float, float]:
    """(smallest, largest) diametral interference (µm) of the inner ring on a shaft of ``shaft_class``."""
    lower, upper = tolerance_zone_um(shaft_class, bore_mm)
    bore_lower = _ring_tolerance(BORE_TOLERANCE, bore_mm, "bore")
    return lower - 0.0, upper - bore_lower


def housing_interference_um(housing_class: str, outside_mm: float) -> tuple[float, float]:
    """(smallest, largest) diametral interference (µm) of the outer ring in a housing bore of ``housing_class``."""
    lower, upper = tolerance_zone_um(housing_class, outside_mm)
    ring_lower = _ring_tolerance(OUTSIDE_TOLERANCE, outside_mm, "outside diameter")
    return ring_lower - upper, 0.0 - lower


def inner_raceway_growth_um(interference_um: float, bore_mm: float, raceway_mm: float, shaft_bore_mm: float,  # noqa: PLR0913
                            *, ring: tuple[float, float], shaft: tuple[float, float]) -> float:
    """Δd_1 (µm): growth of the inner raceway diameter d_1 from an interference on a (hollow) shaft (Lamé); ``ring``
    and ``shaft`` are (E in MPa, ν)."""
    if interference_um <= 0.0:
        return 0.0
    (ring_modulus_MPa, ring_poisson), (shaft_modulus_MPa, shaft_poisson) = ring, shaft
    a, b, c = bore_mm / 2.0, raceway_mm / 2.0, shaft_bore_mm / 2.0
    ring_term = a / ring_modulus_MPa * ((b**2 + a**2) / (b**2 - a**2) + ring_poisson)
    shaft_term = a / shaft_modulus_MPa * ((a**2 + c**2) / (a**2 - c**2) - shaft_poisson)
    pressure = interference_um / 2.0 / (ring_term + shaft_term)  # in 1e-3 MPa (µm over mm/MPa); linear, so µm come out
    return 4.0 * pressure * a**2 * b / (ring_modulus_MPa * (b**2 - a**2))


def outer_raceway_shrinkage_um(interference_um: float, outside_mm: float, raceway_mm: float,  # noqa: PLR0913
                               housing_outside_mm: float | None, *, ring: tuple[float, float],
                               housing: tuple[float, float]) -> float:
    """ΔD_1 (µm): shrinkage of the outer raceway diameter D_1 from an interference in a housing of outer diameter
    ``housing_outside_mm`` (None: a housing much larger than the ring, (g² + f²)/(g² − f²) → 1) (Lamé)."""
    if interference_um <= 0.0:
        return 0.0
    (ring_modulus_MPa, ring_poisson), (housing_modulus_MPa, housing_poisson) = ring, housing
    e, f = raceway_mm / 2.0, outside_mm / 2.0
    ring_term = f / ring_modulus_MPa * ((f**2 + e**2) / (f**2 - e**2) - ring_poisson)
    wall = 1.0 if housing_outside_mm is None else ((housing_outside_mm / 2.0) ** 2 + f**2) / ((housing_outside_mm / 2.0) ** 2 - f**2)
    housing_term = f / housing_modulus_MPa * (wall + housing_poisson)
    pressure = interference_um / 2.0 / (ring_term + housing_term)
    return 4.0 * pressure * f**2 * e / (ring_modulus_MPa * (f**2 - e**2))


@dataclass(frozen=True)
class FitClearance:
    """A ball bearing's mounted clearance from its fits (µm): unmounted range, interferences, the reduction and
    the mounted range; ``chosen_um`` the value the model solves with (before [thermal])."""

    unmounted_um: tuple[float, float]
    shaft_interference_um: tuple[float, float]
    housing_interference_um: tuple[float, float]
    reduction_um: tuple[float, float]  # (smallest, largest)
    mounted_um: tuple[float, float]  # (tightest, loosest)
    chosen_um: float
    which: str


def fit_clearance(unmounted_um: tuple[float, float], shaft_fit: str | None, housing_fit: str | None, *, bore_mm: float,  # noqa: PLR0913
                  outside_mm: float, pitch_diameter_mm: float, ball_diameter_mm: float, shaft_bore_mm: float,
                  housing_outside_mm: float | None, shaft_material: tuple[float, float],
                  housing_material: tuple[float, float], ring_material: tuple[float, float],
                  which: str = "mean") -> FitClearance:
    """The mounted clearance range of a ball bearing with its fits (materials as (E in MPa, ν))."""
    inner_race, outer_race = pitch_diameter_mm - ball_diameter_mm, pitch_diameter_mm + ball_diameter_mm
    shaft = shaft_interference_um(shaft_fit, bore_mm) if shaft_fit else (0.0, 0.0)
    housing = housing_interference_um(housing_fit, outside_mm) if housing_fit else (0.0, 0.0)

    def reduction(i_shaft: float, i_housing: float) -> float:
        return (inner_raceway_growth_um(i_shaft, bore_mm, inner_race, shaft_bore_mm, ring=ring_material,
                                        shaft=shaft_material)
                + outer_raceway_shrinkage_um(i_housing, outside_mm, outer_race, housing_outside_mm, ring=ring_material,
                                             housing=housing_material))

    smallest, largest = reduction(shaft[0], housing[0]), reduction(shaft[1], housing[1])
    mean = reduction(0.5 * sum(shaft), 0.5 * sum(housing))
    mounted = (unmounted_um[0] - largest, unmounted_um[1] - smallest)
    chosen = {"mean": 0.5 * sum(unmounted_um) - mean, "min": mounted[0], "max": mounted[1]}
    if which not in chosen:
        raise ValueError(f"fit_clearance must be mean, min or max, got {which!r}")
    return FitClearance(unmounted_um=tuple(unmounted_um), shaft_interference_um=shaft, housing_interference_um=housing,
                        reduction_um=(smallest, largest), mounted_um=mounted, chosen_um=chosen[which], which=which)
