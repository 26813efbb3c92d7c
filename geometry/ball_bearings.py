"""Deep-groove ball bearings by designation: internal geometry and ISO 5753-1 radial internal clearance.

Makers publish boundary dimensions and load ratings, rarely the internal geometry. Each number below
says where it comes from:

- bore d and outside diameter D_o: ISO 15 boundary dimensions (dimension series 02 and 03), as in
  every maker's catalogue.
- ball count Z and ball diameter D_w:
  [CWRU] Case Western Reserve University Bearing Data Center, SKF 6203-2RS JEM and 6205-2RS JEM
  (published ball count, ball and pitch diameter, in inches);
  [H&K] Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed., vol. 1, the 209 deep-groove bearing
  of the worked examples (Z = 9, D = 12.7 mm, d_i = 52.291, d_o = 77.706 mm → d_m = 65.0 mm,
  r_i = r_o = 6.6 mm → f = 0.52, P_d = 15 µm);
  [typ] ESTIMATED: the complement used in bearing defect-frequency tables for the size (standard
  inch ball grades), checked here only for plausibility: the balls fit the Conrad filling limit
  Z ≤ 1 + 0.556 π d_m / D_w (filling angle 200°) and D_w / (D_o − d) lies in 0.23 … 0.33.
- pitch diameter d_m: [CWRU]/[H&K] where given, else ESTIMATED as (d + D_o)/2.
- groove conformities f_i = r_i/D_w, f_o = r_o/D_w: [H&K] for 6209; else ESTIMATED as the loosest
  conformity the ISO 281:2007 load ratings assume for radial ball bearings (r_i ≤ 0.52 D_w,
  r_o ≤ 0.53 D_w); makers' own grooves are often a little closer (stiffer).
- radial internal clearance ranges (µm, unmounted, zero measuring load) by bore: ISO 5753-1:2009
  table for radial ball bearings (the same values as e.g. the SKF catalogue's table of radial internal
  clearance of deep groove ball bearings). A class gives the middle of its range.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["BALL_BEARINGS", "CLEARANCE_CLASSES", "CatalogueBallBearing", "clearance_range_um"]

INCH_MM = 25.4


@dataclass(frozen=True)
class CatalogueBallBearing:
    """A catalogue deep-groove ball bearing (mm)."""

    designation: str
    bore_mm: float
    outside_diameter_mm: float
    width_mm: float
    ball_count: int
    ball_diameter_mm: float
    pitch_diameter_mm: float
    inner_conformity: float
    outer_conformity: float
    source: str  # which of the sources above each geometric number comes from


_ISO281 = (0.52, 0.53)  # ESTIMATED conformities f_i, f_o (ISO 281 basis, see the module docstring)


def _bearing(designation, d, d_o, b, z, d_w, source, pitch=None, conformity=_ISO281):
    return CatalogueBallBearing(designation, d, d_o, b, z, d_w, (d + d_o) / 2.0 if pitch is None else pitch,
                                *conformity, source)


BALL_BEARINGS: dict[str, CatalogueBallBearing] = {b.designation: b for b in (
    # designation, d, D_o, B (ISO 15), Z, D_w (mm), source of Z/D_w/d_m/f
    _bearing("6200", 10, 30, 9, 7, 4.762, "Z, D_w [typ, 3/16 in]; d_m, f estimated"),
    _bearing("6201", 12, 32, 10, 7, 5.953, "Z, D_w [typ, 15/64 in]; d_m, f estimated"),
    _bearing("6202", 15, 35, 11, 8, 5.953, "Z, D_w [typ, 15/64 in]; d_m, f estimated"),
    _bearing("6203", 17, 40, 12, 8, 0.2656 * INCH_MM, "Z, D_w, d_m [CWRU]; f estimated", pitch=1.122 * INCH_MM),
    _bearing("6204", 20, 47, 14, 8, 7.938, "Z, D_w [typ, 5/16 in]; d_m, f estimated"),
    _bearing("6205", 25, 52, 15, 9, 0.3126 * INCH_MM, "Z, D_w, d_m [CWRU]; f estimated", pitch=1.537 * INCH_MM),
    _bearing("6206", 30, 62, 16, 9, 9.525, "Z, D_w [typ, 3/8 in]; d_m, f estimated"),
    _bearing("6207", 35, 72, 17, 9, 11.112, "Z, D_w [typ, 7/16 in]; d_m, f estimated"),
    _bearing("6208", 40, 80, 18, 9, 12.700, "Z, D_w [typ, 1/2 in]; d_m, f estimated"),
    _bearing("6209", 45, 85, 19, 9, 12.700, "Z, D_w, d_m, f [H&K 209]", pitch=65.0, conformity=(0.52, 0.52)),
    _bearing("6210", 50, 90, 20, 10, 12.700, "Z, D_w [typ, 1/2 in]; d_m, f estimated"),
    _bearing("6300", 10, 35, 11, 6, 7.144, "Z, D_w [typ, 9/32 in]; d_m, f estimated"),
    _bearing("6301", 12, 37, 12, 6, 7.938, "Z, D_w [typ, 5/16 in]; d_m, f estimated"),
    _bearing("6302", 15, 42, 13, 7, 7.938, "Z, D_w [typ, 5/16 in]; d_m, f estimated"),
    _bearing("6303", 17, 47, 14, 7, 8.731, "Z, D_w [typ, 11/32 in]; d_m, f estimated"),
    _bearing("6304", 20, 52, 15, 7, 9.525, "Z, D_w [typ, 3/8 in]; d_m, f estimated"),
    _bearing("6305", 25, 62, 17, 8, 10.319, "Z, D_w [typ, 13/32 in]; d_m, f estimated"),
    _bearing("6306", 30, 72, 19, 8, 11.906, "Z, D_w [typ, 15/32 in]; d_m, f estimated"),
    _bearing("6307", 35, 80, 21, 8, 13.494, "Z, D_w [typ, 17/32 in]; d_m, f estimated"),
    _bearing("6308", 40, 90, 23, 8, 15.081, "Z, D_w [typ, 19/32 in]; d_m, f estimated"),
    _bearing("6309", 45, 100, 25, 8, 17.462, "Z, D_w [typ, 11/16 in]; d_m, f estimated"),
    _bearing("6310", 50, 110, 27, 8, 19.050, "Z, D_w [typ, 3/4 in]; d_m, f estimated"),
)}

CLEARANCE_CLASSES = ("C2", "CN", "C3", "C4")

# ISO 5753-1:2009, radial internal clearance of radial ball bearings (µm): bore d over … incl,
# then (min, max) for C2, CN, C3, C4
_CLEARANCE_TABLE_UM = (
    (6.0, 10.0, ((0, 7), (2, 13), (8, 23), (14, 29))),
    (10.0, 18.0, ((0, 9), (3, 18), (11, 25), (18, 33))),
    (18.0, 24.0, ((0, 10), (5, 20), (13, 28), (20, 36))),
    (24.0, 30.0, ((1, 11), (5, 20), (13, 28), (23, 41))),
    (30.0, 40.0, ((1, 11), (6, 20), (15, 33), (28, 46))),
    (40.0, 50.0, ((1, 11), (6, 23), (18, 36), (30, 51))),
    (50.0, 65.0, ((1, 15), (8, 28), (23, 43), (38, 61))),
)


def clearance_range_um(bore_mm: float, clearance_class: str) -> tuple[float, float]:
    """The ISO 5753-1 radial internal clearance range (min, max) in µm of a radial ball bearing.

    Raises
    ------
    ValueError
        Unknown class, or a bore outside the table (6 … 65 mm).
    """
    if clearance_class not in CLEARANCE_CLASSES:
        raise ValueError(f"unknown clearance class {clearance_class!r} (known: {', '.join(CLEARANCE_CLASSES)})")
    for low, high, ranges in _CLEARANCE_TABLE_UM:
        if low < bore_mm <= high:
            return tuple(float(v) for v in ranges[CLEARANCE_CLASSES.index(clearance_class)])
    raise ValueError(f"bore {bore_mm:g} mm is outside the clearance table (over 6 up to 65 mm); give clearance_um")
