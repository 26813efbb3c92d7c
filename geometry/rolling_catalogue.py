"""Angular-contact ball, cylindrical roller and tapered roller bearings by designation.

The boundary dimensions are in ``geometry/data/rolling_bearings.csv``; the internal geometry and the
load ratings follow here from rules, and every number says where it comes from (``sources``):

- **published** — bore d, outside diameter D, width B (tapered: total width T and cup width C): ISO 15
  (radial bearings; 70xx, 72xx, 73xx, NU2xx, NU3xx share the dimensions of 60xx, 62xx, 63xx) and
  ISO 355 (tapered roller bearings, series 02, 20 (X), 22), as in every maker's catalogue (the 60xx and tapered
  rows written from memory of those tables, the tapered bores 20–30 mm checked against a maker's table in the
  tests; 72xx/73xx/NU from the 62xx/63xx rows of the ball catalogue).
- **ESTIMATED** — the internal geometry (makers publish it rarely):

  * angular-contact ball bearings: d_m = (d + D)/2, D_w = 0.30 (D − d) (the 62xx/63xx ball sizes are
    0.29–0.31 of it), Z = ⌊π d_m / (1.2 D_w)⌋ (filled through the low shoulder: a ball pitch of 1.2 D_w,
    more balls than a Conrad deep-groove bearing), groove conformities f_i = 0.52, f_o = 0.53 (the
    loosest ISO 281 assumes); contact angle by suffix: B 40°, AC 25°, C 15° (the suffix's definition);
  * cylindrical roller bearings (NU, N, NJ, NUP): d_m = (d + D)/2, D_w = 0.28 (D − d), l_we = 0.65 B,
    Z = ⌊π d_m / (1.25 D_w)⌋, logarithmic crowning;
  * tapered roller bearings: d_m = (d + D)/2, mean roller diameter D_w = 0.25 (D − d),
    l_we = 0.8 C, Z = ⌊π d_m / (1.2 D_w)⌋, contact angle from the catalogue's calculation factor e:
    tan α = e / 1.5 with e = 0.37 for the 302 and 322 series and 0.43 for 320 X (typical of those
    series; makers' e vary by size from about 0.35 to 0.46).
- **COMPUTED** — the load ratings from that (estimated) geometry:

  * C, ISO 281:2007: ball C = b_m f_c (i cos α)^0.7 Z^(2/3) D_w^1.8 (b_m = 1.3), roller
    C = b_m f_c (i l_we cos α)^(7/9) Z^(3/4) D_w^(29/27) (b_m = 1.1), f_c from ISO 281's tables by
    γ = D_w cos α / d_m (:data:`BALL_FC`, :data:`ROLLER_FC`, interpolated linearly);
  * C0, ISO 76's definition evaluated with this model's Hertz contact: the radial load at which the
    most loaded element reaches 4 200 MPa (ball) or 4 000 MPa (roller), with Q_max = 5 F_r/(Z cos α)
    (ball) and 4.6 F_r/(Z cos α) (roller), ISO 76's load-distribution factors.

An unknown designation is refused with the nearest ones (:func:`nearest_designations`).
"""

from __future__ import annotations

import csv
import difflib
import functools
import io
import math
from dataclasses import dataclass, field
from importlib import resources

import numpy as np

from rvcoax.fem.ball_bearing import BallBearingGeometry
from rvcoax.fem.roller_bearing import RollerBearingGeometry

__all__ = ["ANGULAR_CONTACT_SUFFIXES", "BALL_FC", "CYLINDRICAL_VARIANTS", "CatalogueRollingBearing",
           "ROLLER_FC", "ROLLING_BEARINGS", "ROLLING_CATALOGUE_FILE", "TAPERED_E", "ball_dynamic_rating_N",
           "ball_static_rating_N", "catalogue_entry", "nearest_designations", "normalise_designation",
           "roller_dynamic_rating_N", "roller_static_rating_N", "rolling_bearings"]

ROLLING_CATALOGUE_FILE = "rolling_bearings.csv"
ANGULAR_CONTACT_SUFFIXES = {"B": 40.0, "AC": 25.0, "C": 15.0}
"""Contact angle (°) of an angular-contact ball bearing by its designation's suffix."""
CYLINDRICAL_VARIANTS = ("NU", "N", "NJ", "NUP")
"""NU and N: ribs on one ring only (no thrust); NJ: one rib on the inner ring (thrust one way); NUP: a loose rib
washer too (thrust both ways)."""
TAPERED_E = {"302": 0.37, "320": 0.43, "322": 0.37}
"""ESTIMATED calculation factor e of a tapered roller bearing series (tan α = e / 1.5)."""

# ISO 281:2007 f_c (N, mm) against γ = D_w cos α / d_m: single-row radial and angular-contact ball
# bearings (table 2), radial roller bearings (table 7); written from memory of the standard's tables, then checked
# against the closed forms they are computed from (tests/fem/test_rolling_life.py): the roller table within
# 0.1 % of ISO 281's f_c formula (λν = 0.83) at every entry, the ball table one constant (±0.15 %) times the ball
# formula with f_i = f_e = 0.52 (the shape right at every entry; the 6204's C lands within 6 % of the maker's)
BALL_FC = ((0.01, 29.1), (0.02, 35.8), (0.03, 40.3), (0.04, 43.8), (0.05, 46.7), (0.06, 49.1), (0.07, 51.1),
           (0.08, 52.8), (0.09, 54.3), (0.10, 55.5), (0.12, 57.5), (0.14, 58.8), (0.16, 59.6), (0.18, 59.9),
           (0.20, 59.9), (0.22, 59.6), (0.24, 59.0), (0.26, 58.2), (0.28, 57.1), (0.30, 56.0), (0.32, 54.6),
           (0.34, 53.2), (0.36, 51.7), (0.38, 50.0), (0.40, 48.4))
ROLLER_FC = ((0.01, 52.1), (0.02, 60.8), (0.03, 66.5), (0.04, 70.7), (0.05, 74.1), (0.06, 76.9), (0.07, 79.2),
             (0.08, 81.2), (0.09, 82.8), (0.10, 84.2), (0.12, 86.4), (0.14, 87.7), (0.16, 88.5), (0.18, 88.8),
             (0.20, 88.7), (0.22, 88.2), (0.24, 87.5), (0.26, 86.4), (0.28, 85.2), (0.30, 83.8))
BALL_STATIC_PRESSURE_PA = 4.2e9
ROLLER_STATIC_PRESSURE_PA = 4.0e9


def _fc(table, gamma: float) -> float:
    x, y = np.array(table).T
    if not x[0] <= gamma <= x[-1]:
        raise ValueError(f"γ = D_w cos α / d_m = {gamma:.3g} is outside ISO 281's f_c table ({x[0]:g} … {x[-1]:g})")
    return float(np.interp(gamma, x, y))


def ball_dynamic_rating_N(ball_count: int, ball_diameter_mm: float, pitch_diameter_mm: float,
                          contact_angle_deg: float, rows: int = 1) -> float:
    """ISO 281 basic dynamic radial load rating C (N) of a radial ball bearing (D_w ≤ 25.4 mm)."""
    cos_a = math.cos(math.radians(contact_angle_deg))
    fc = _fc(BALL_FC, ball_diameter_mm * cos_a / pitch_diameter_mm)
    return 1.3 * fc * (rows * cos_a) ** 0.7 * ball_count ** (2.0 / 3.0) * ball_diameter_mm**1.8


def roller_dynamic_rating_N(roller_count: int, roller_diameter_mm: float, roller_length_mm: float,  # noqa: PLR0913
                            pitch_diameter_mm: float, contact_angle_deg: float, *, rows: int = 1) -> float:
    """ISO 281 basic dynamic radial load rating C (N) of a radial roller bearing."""
    cos_a = math.cos(math.radians(contact_angle_deg))
    fc = _fc(ROLLER_FC, roller_diameter_mm * cos_a / pitch_diameter_mm)
    return (1.1 * fc * (rows * roller_length_mm * cos_a) ** (7.0 / 9.0) * roller_count**0.75
            * roller_diameter_mm ** (29.0 / 27.0))


def _static_rating(pressure_of, limit_pa: float, count: int, contact_angle_deg: float, factor: float) -> float:
    from scipy.optimize import brentq  # here, not at import: scipy.optimize costs every command ~0.9 s

    element = brentq(lambda q: float(pressure_of(q)) - limit_pa, 1e-3, 1e8, xtol=1e-6)
    return count * math.cos(math.radians(contact_angle_deg)) * element / factor


def ball_static_rating_N(geometry: BallBearingGeometry) -> float:
    """ISO 76 basic static radial load rating C0 (N) by its definition: 4 200 MPa at the most loaded ball,
    Q_max = 5 F_r / (Z cos α)."""
    return _static_rating(geometry.max_contact_pressure, BALL_STATIC_PRESSURE_PA, geometry.ball_count,
                          math.degrees(geometry.free_contact_angle_rad), 5.0)


def roller_static_rating_N(geometry: RollerBearingGeometry) -> float:
    """ISO 76 basic static radial load rating C0 (N) by its definition: 4 000 MPa at the most loaded roller
    (evenly loaded over its length), Q_max = 4.6 F_r / (Z cos α)."""
    return _static_rating(lambda q: geometry.max_contact_pressure(q / geometry.slices), ROLLER_STATIC_PRESSURE_PA,
                          geometry.roller_count, math.degrees(geometry.contact_angle_rad), 4.6)


@dataclass(frozen=True)
class CatalogueRollingBearing:
    """A catalogue angular-contact ball, cylindrical roller or tapered roller bearing (mm, N, degrees).

    ``element_length_mm`` is None for balls; ``inner_conformity``/``outer_conformity`` None for rollers.
    ``sources`` maps each field to where its number comes from (published, ESTIMATED, COMPUTED).
    """

    designation: str
    kind: str  # angular_contact, cylindrical_roller, tapered_roller
    bore_mm: float
    outside_diameter_mm: float
    width_mm: float
    contact_angle_deg: float
    element_count: int
    element_diameter_mm: float
    pitch_diameter_mm: float
    element_length_mm: float | None
    inner_conformity: float | None
    outer_conformity: float | None
    dynamic_rating_N: float
    static_rating_N: float
    sources: dict = field(default_factory=dict, compare=False, hash=False)


def _angular(designation: str, row: dict, suffix: str) -> CatalogueRollingBearing:
    d, big_d, width = float(row["bore_mm"]), float(row["outside_diameter_mm"]), float(row["width_mm"])
    pitch = 0.5 * (d + big_d)
    ball = round(0.30 * (big_d - d), 3)
    count = int(math.pi * pitch / (1.2 * ball))
    angle = ANGULAR_CONTACT_SUFFIXES[suffix]
    geometry = BallBearingGeometry(ball_count=count, ball_diameter_m=ball * 1e-3, pitch_diameter_m=pitch * 1e-3,
                                   inner_conformity=0.52, outer_conformity=0.53, clearance_m=0.0,
                                   contact_angle_rad=math.radians(angle))
    estimated = "ESTIMATED (rules in rvcoax.geometry.rolling_catalogue)"
    return CatalogueRollingBearing(
        designation=designation, kind="angular_contact", bore_mm=d, outside_diameter_mm=big_d, width_mm=width,
        contact_angle_deg=angle, element_count=count, element_diameter_mm=ball, pitch_diameter_mm=pitch,
        element_length_mm=None, inner_conformity=0.52, outer_conformity=0.53,
        dynamic_rating_N=ball_dynamic_rating_N(count, ball, pitch, angle), static_rating_N=ball_static_rating_N(geometry),
        sources={"bore_mm": row["source"], "outside_diameter_mm": row["source"], "width_mm": row["source"],
         "contact_angle_deg": f"suffix {suffix}", "element_count": estimated, "element_diameter_mm": estimated,
         "pitch_diameter_mm": estimated, "inner_conformity": estimated, "outer_conformity": estimated,
         "dynamic_rating_N": "COMPUTED (ISO 281) from the estimated geometry",
         "static_rating_N": "COMPUTED (ISO 76's definition) from the estimated geometry"})


def _roller(designation: str, row: dict, kind: str, series: str) -> CatalogueRollingBearing:
    d, big_d, width = float(row["bore_mm"]), float(row["outside_diameter_mm"]), float(row["width_mm"])
    pitch = 0.5 * (d + big_d)
    if kind == "cylindrical_roller":
        roller, length, spacing, angle = round(0.28 * (big_d - d), 3), round(0.65 * width, 3), 1.25, 0.0
        angle_source = "cylindrical (0°)"
    else:
        roller, length, spacing = round(0.25 * (big_d - d), 3), round(0.8 * float(row["cup_width_mm"]), 3), 1.2
        angle = math.degrees(math.atan(TAPERED_E[series] / 1.5))
        angle_source = f"ESTIMATED from e = {TAPERED_E[series]:g} (tan α = e/1.5)"
    count = int(math.pi * pitch / (spacing * roller))
    geometry = RollerBearingGeometry(count, roller * 1e-3, length * 1e-3, pitch * 1e-3, math.radians(angle),
                                     crowning="none", slices=1)
    estimated = "ESTIMATED (rules in rvcoax.geometry.rolling_catalogue)"
    return CatalogueRollingBearing(
        designation=designation, kind=kind, bore_mm=d, outside_diameter_mm=big_d, width_mm=width,
        contact_angle_deg=angle, element_count=count, element_diameter_mm=roller, pitch_diameter_mm=pitch,
        element_length_mm=length, inner_conformity=None, outer_conformity=None,
        dynamic_rating_N=roller_dynamic_rating_N(count, roller, length, pitch, angle),
        static_rating_N=roller_static_rating_N(geometry),
        sources={"bore_mm": row["source"], "outside_diameter_mm": row["source"], "width_mm": row["source"],
         "contact_angle_deg": angle_source, "element_count": estimated, "element_diameter_mm": estimated,
         "pitch_diameter_mm": estimated, "element_length_mm": estimated,
         "dynamic_rating_N": "COMPUTED (ISO 281) from the estimated geometry",
         "static_rating_N": "COMPUTED (ISO 76's definition) from the estimated geometry"})


def _read_catalogue() -> dict[str, CatalogueRollingBearing]:
    text = resources.files("rvcoax.geometry").joinpath("data", ROLLING_CATALOGUE_FILE).read_text(encoding="utf-8")
    out = {}
    for row in csv.DictReader(io.StringIO(text)):
        name = row["designation"]
        if row["type"] == "angular_contact":
            for suffix in ANGULAR_CONTACT_SUFFIXES:
                out[name + suffix] = _angular(name + suffix, row, suffix)
        elif row["type"] == "cylindrical_roller":
            for variant in CYLINDRICAL_VARIANTS:
                full = variant + name[2:]
                out[full] = _roller(full, row, "cylindrical_roller", "")
        else:
            out[name] = _roller(name, row, "tapered_roller", name[:3])
    return out


@functools.cache
def rolling_bearings() -> dict[str, CatalogueRollingBearing]:
    """Designation → catalogue entry: 70xx/72xx/73xx with suffix B, AC or C; NU/N/NJ/NUP 2xx and 3xx (04–10);
    302xx, 320xx X and 322xx (04–10).

    Built on first use (176 entries, each C0 by a root search) and kept: a command that meets no catalogue
    bearing does not pay for it. The module attribute ``ROLLING_BEARINGS`` is this same dict.
    """
    return _read_catalogue()


ROLLING_BEARINGS: dict[str, CatalogueRollingBearing]  # declared only: module __getattr__ builds it when first read
"""Designation → catalogue entry (:func:`rolling_bearings`, built on first use): 70xx/72xx/73xx with suffix B, AC
or C; NU/N/NJ/NUP 2xx and 3xx (04–10); 302xx, 320xx X and 322xx (04–10)."""


def __getattr__(name: str):
    if name == "ROLLING_BEARINGS":
        return rolling_bearings()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def normalise_designation(designation: str) -> str:
    """Upper case without spaces (``"7206 b"`` → ``"7206B"``, ``"32006 X"`` → ``"32006X"``)."""
    return "".join(designation.split()).upper()


def nearest_designations(designation: str, kind: str | None = None, count: int = 5) -> list[str]:
    """The catalogue designations (of ``kind`` when given) closest in spelling to ``designation``."""
    names = [n for n, e in rolling_bearings().items() if kind is None or e.kind == kind]
    return difflib.get_close_matches(normalise_designation(designation), names, n=count, cutoff=0.0)


def catalogue_entry(designation: str, kind: str) -> CatalogueRollingBearing:
    """The catalogue entry of ``designation`` for a bearing of ``kind``.

    Raises
    ------
    ValueError
        Unknown designation (the message names the nearest ones) or one of another kind.
    """
    entry = rolling_bearings().get(normalise_designation(designation))
    if entry is None or entry.kind != kind:
        other = f" (it is a designation of model = \"{entry.kind}\")" if entry is not None else ""
        raise ValueError(f"designation: unknown {kind.replace('_', ' ')} bearing {designation!r}{other}; nearest: "
                         f"{', '.join(nearest_designations(designation, kind))}")
    return entry
