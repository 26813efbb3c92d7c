"""Deep-groove ball bearings by designation: internal geometry and ISO 5753-1 radial internal clearance.

The catalogue is ``geometry/data/ball_bearings.csv``. Makers publish boundary dimensions and load ratings, rarely the internal geometry. Each number below
says where it comes from:

- bore d and outside diameter D_o: ISO 15 boundary dimensions (dimension series 02 and 03), as in
  every maker's catalogue.
- ball count Z and ball diameter D_w:
  [CWRU] Case Western Reserve University Bearing Data Center, SKF 6203-2RS JEM and 6205-2RS JEM
  (published ball count, ball and pitch diameter, in inches: 6203 D_w = 0.2656, d_m = 1.122;
  6205 D_w = 0.3126, d_m = 1.537);
  [H&K] Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed., vol. 1, the 209 deep-groove bearing
  of the worked examples (Z = 9, D = 12.7 mm, d_i = 52.291, d_o = 77.706 mm → d_m = 65.0 mm,
  r_i = r_o = 6.6 mm → f = 0.52, P_d = 15 µm);
  [typ] ESTIMATED: the complement used in bearing defect-frequency tables for the size (standard
  inch ball sizes, named in the row), checked here only for plausibility: the balls fit the Conrad filling limit
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

import csv
import io
from dataclasses import dataclass
from importlib import resources

__all__ = ["BALL_BEARINGS", "CATALOGUE_FILE", "CLEARANCE_CLASSES", "CatalogueBallBearing", "clearance_range_um"]


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


CATALOGUE_FILE = "ball_bearings.csv"
"""The catalogue in ``rvcoax.geometry.data``: one row per designation, the source of its numbers in ``source``."""


def _read_catalogue() -> dict[str, CatalogueBallBearing]:
    rows = csv.DictReader(io.StringIO(resources.files("rvcoax.geometry").joinpath("data", CATALOGUE_FILE)
                                      .read_text(encoding="utf-8")))
    out = {}
    for row in rows:
        out[row["designation"]] = CatalogueBallBearing(designation=row["designation"], bore_mm=float(row["bore_mm"]),
                                                       outside_diameter_mm=float(row["outside_diameter_mm"]),
                                                       width_mm=float(row["width_mm"]),
                                                       ball_count=int(row["ball_count"]),
                                                       ball_diameter_mm=float(row["ball_diameter_mm"]),
                                                       pitch_diameter_mm=float(row["pitch_diameter_mm"]),
                                                       inner_conformity=float(row["inner_conformity"]),
                                                       outer_conformity=float(row["outer_conformity"]),
                                                       source=row["source"])
    return out


BALL_BEARINGS: dict[str, CatalogueBallBearing] = _read_catalogue()  # designation → its catalogue entry

CLEARANCE_CLASSES = ("C2", "CN", "C3", "C4")

# ISO 5753-1:2009, radial internal clearance of radial ball bearings (µm): bore d over … incl,
# then (min, max) for C2, CN, C3, C4; checked against two makers' printed copies (tests/geometry/
# test_published_tables.py: they differ from each other by 1–3 µm at two class edges, named there)
_CLEARANCE_TABLE_UM = (
    (6.0, 10.0, ((0, 7), (2, 13), (8, 23), (14, 29))),
    (10.0, 18.0, ((0, 9), (3, 18), (11, 25), (18, 33))),
    (18.0, 24.0, ((0, 10), (5, 20), (13, 28), (20, 36))),
    (24.0, 30.0, ((1, 11), (5, 20), (13, 28), (23, 41))),
    (30.0, 40.0, ((1, 11), (6, 20), (15, 33), (28, 46))),
    (40.0, 50.0, ((1, 11), (6, 23), (18, 36), (30, 51))),
    (50.0, 65.0, ((1, 15), (8, 28), (23, 43), (38, 61))),
)


# ISO 5753-1, radial internal clearance of cylindrical roller bearings with a cylindrical bore (µm), the same
# layout (written from memory of the makers' catalogue tables, then checked against a maker's printed copy:
# tests/geometry/test_published_tables.py, every entry equal)
_CYLINDRICAL_CLEARANCE_TABLE_UM = (
    (10.0, 24.0, ((0, 25), (20, 45), (35, 60), (50, 75))),
    (24.0, 30.0, ((0, 25), (20, 45), (35, 60), (50, 75))),
    (30.0, 40.0, ((5, 30), (25, 50), (45, 70), (60, 85))),
    (40.0, 50.0, ((5, 35), (30, 60), (50, 80), (70, 100))),
    (50.0, 65.0, ((10, 40), (40, 70), (60, 90), (80, 110))),
)
_CLEARANCE_TABLES = {"ball": _CLEARANCE_TABLE_UM, "cylindrical_roller": _CYLINDRICAL_CLEARANCE_TABLE_UM}


def clearance_range_um(bore_mm: float, clearance_class: str, kind: str = "ball") -> tuple[float, float]:
    """The ISO 5753-1 radial internal clearance range (min, max) in µm of a radial ball bearing (``kind`` =
    ``"ball"``) or a cylindrical roller bearing with a cylindrical bore (``"cylindrical_roller"``).

    Raises
    ------
    ValueError
        Unknown class, or a bore outside the table (balls 6 … 65 mm, rollers 10 … 65 mm).
    """
    if clearance_class not in CLEARANCE_CLASSES:
        raise ValueError(f"unknown clearance class {clearance_class!r} (known: {', '.join(CLEARANCE_CLASSES)})")
    table = _CLEARANCE_TABLES[kind]
    for low, high, ranges in table:
        if low < bore_mm <= high:
            return tuple(float(v) for v in ranges[CLEARANCE_CLASSES.index(clearance_class)])
    raise ValueError(f"bore {bore_mm:g} mm is outside the clearance table (over {table[0][0]:g} up to "
                     f"{table[-1][1]:g} mm); give clearance_um")
