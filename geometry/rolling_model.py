"""A rig file's angular-contact and roller bearing entries → :class:`rvcoax.fem.rolling_bearing.RollingBearing`.

``[[bearings]] model = "angular_contact" | "cylindrical_roller" | "tapered_roller"`` (and ``"ball"``,
the deep-groove bearing of :mod:`rvcoax.geometry.ball_model`, as one row). The catalogue
(:mod:`rvcoax.geometry.rolling_catalogue`) gives the internal geometry of a designation; explicit keys
override it. Angular-contact and tapered bearings are single (``arrangement = "single"``, carrying
thrust in ``axial_direction``) or matched pairs: ``DB`` (back-to-back), ``DF`` (face-to-face), ``DT``
(tandem), the two rows a bearing width apart around the entry's ``x_mm``. Their rings are set by one of

- ``preload_class`` (light, medium, heavy; DB and DF pairs only): each row carries 1 %, 2 % or 4 % of
  its own C axially at rest (ESTIMATED: makers' preload classes are not standardised and differ by
  maker; these are of the order of their light, moderate and heavy classes);
- ``preload_N``: the axial preload each row of a DB/DF pair carries at rest, or that a single bearing
  (a tandem pair: both rows together) carries against its mounting;
- ``axial_offset_um``: the axial offset of the rings from first contact, signed (> 0 pressed together,
  a preload; < 0 apart, an axial play); a DB/DF pair's total (stand-out), split evenly over its rows;

none of them: the rings just touch (zero play, no preload).

A cylindrical roller bearing's rollers carry no thrust on their raceways; its ribs do, by the variant of its
designation (:func:`cylindrical_variant`): NU and N have ribs on one ring only, carry no thrust, and refuse an
``axial_stiffness_N_per_um`` (the shaft is located by another bearing); NJ carries thrust one way, the
``axial_direction`` the shaft moves against the housing (+1: +x), through the contact of the roller ends with
its ribs: a spring of ``axial_stiffness_N_per_um`` that acts only that way; NUP (and a bearing from explicit
geometry) carries it both ways. The rib stiffness, where not given, is the bearing's radial reference stiffness
(ESTIMATED: roller end and rib are an elastic contact of the same size class as roller and raceway; makers
publish no value).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvcoax.fem.ball_bearing import BallBearingGeometry
from rvcoax.fem.roller_bearing import RollerBearingGeometry
from rvcoax.fem.rolling_bearing import BearingRow, RollingBearing
from rvcoax.geometry.ball_model import clearance_from_keys, operating_clearance_m, thermal_clearance_change_um
from rvcoax.geometry.rolling_catalogue import CatalogueRollingBearing, catalogue_entry

__all__ = ["GEOMETRIC_MODELS", "MODEL_KEYS", "PRELOAD_CLASS_SHARE", "RollingBearingModel", "clearance_um_of",
           "cylindrical_variant", "rib_stiffness_N_per_um",
           "clearance_upper_um", "entry_of", "heavy_setting", "load_ratings_N", "reference_stiffness",
           "rolling_bearing_model", "rolling_bearing_of"]

GEOMETRIC_MODELS = ("angular_contact", "cylindrical_roller", "tapered_roller")
PRELOAD_CLASS_SHARE = {"light": 0.01, "medium": 0.02, "heavy": 0.04}
"""ESTIMATED preload per row of a DB/DF pair as a share of one row's C (see the module docstring)."""
_ANGULAR_KEYS = ("designation", "arrangement", "axial_direction", "preload_class", "preload_N", "axial_offset_um",
                 "pitch_diameter_mm", "contact_angle_deg")
_ROLLER_KEYS = ("roller_count", "roller_diameter_mm", "roller_length_mm", "crowning", "crown_drop_um",
                "crowning_load_N", "slices_per_roller")
MODEL_KEYS = {
    "angular_contact": _ANGULAR_KEYS + ("ball_count", "ball_diameter_mm", "inner_conformity", "outer_conformity"),
    "tapered_roller": _ANGULAR_KEYS + _ROLLER_KEYS,
    "cylindrical_roller": ("designation", "clearance_class", "clearance_um", "pitch_diameter_mm", "axial_direction")
    + _ROLLER_KEYS,
}
"""The rig-file keys each model takes (beyond name, shaft, housing, x_mm, the stiffness keys and width)."""

REFERENCE_DEFLECTION_UM = 5.0


def entry_of(bearing) -> CatalogueRollingBearing | None:
    """The catalogue entry of a bearing's ``designation`` (None without one); ValueError naming the nearest."""
    if bearing.designation is None:
        return None
    return catalogue_entry(bearing.designation, bearing.model)


def _value(bearing, entry, key: str, entry_key: str):
    """The entry's ``key`` where given, else the catalogue's ``entry_key`` (None without either)."""
    given = getattr(bearing, key)
    if given is not None or entry is None:
        return given
    return getattr(entry, entry_key)


def _law(bearing, clearance_um: float = 0.0):
    """The row geometry (SI) of a bearing entry; ValueError naming the missing keys."""
    entry = entry_of(bearing)
    if bearing.model == "angular_contact":
        keys = {"ball_count": "element_count", "ball_diameter_mm": "element_diameter_mm",
                "pitch_diameter_mm": "pitch_diameter_mm", "inner_conformity": "inner_conformity",
                "outer_conformity": "outer_conformity", "contact_angle_deg": "contact_angle_deg"}
    else:
        keys = {"roller_count": "element_count", "roller_diameter_mm": "element_diameter_mm",
                "roller_length_mm": "element_length_mm", "pitch_diameter_mm": "pitch_diameter_mm"}
        if bearing.model == "tapered_roller":
            keys["contact_angle_deg"] = "contact_angle_deg"
    values = {key: _value(bearing, entry, key, attribute) for key, attribute in keys.items()}
    missing = [key for key, value in values.items() if value is None]
    if missing:
        raise ValueError(f"model = \"{bearing.model}\" needs a designation or the geometry keys; missing: "
                         f"{', '.join(missing)}")
    try:
        if bearing.model == "angular_contact":
            if not 15.0 <= values["contact_angle_deg"] <= 45.0:
                raise ValueError(f"contact_angle_deg = {values['contact_angle_deg']:g}: an angular-contact bearing's "
                                 "contact angle must lie in 15° … 45°, the range of ISO 281's X/Y table its life "
                                 "is rated with (below 15°: model = \"ball\" with a clearance or preload)")
            return BallBearingGeometry(ball_count=int(values["ball_count"]),
                                       ball_diameter_m=values["ball_diameter_mm"] * 1e-3,
                                       pitch_diameter_m=values["pitch_diameter_mm"] * 1e-3,
                                       inner_conformity=values["inner_conformity"],
                                       outer_conformity=values["outer_conformity"], clearance_m=0.0,
                                       contact_angle_rad=math.radians(values["contact_angle_deg"]))
        if bearing.model == "tapered_roller" and not values["contact_angle_deg"] > 0:
            raise ValueError("a tapered roller bearing needs contact_angle_deg > 0")
        count, diameter, length = (int(values["roller_count"]), values["roller_diameter_mm"] * 1e-3,
                                   values["roller_length_mm"] * 1e-3)
        angle = math.radians(values.get("contact_angle_deg", 0.0))
        crowning_load = 0.0
        if bearing.crowning == "logarithmic":
            crowning_load = (bearing.crowning_load_N if bearing.crowning_load_N is not None
                             else _default_crowning_load(count, diameter, length, values["pitch_diameter_mm"] * 1e-3,
                                                         angle))
        if bearing.crowning == "circular" and bearing.crown_drop_um is None:
            raise ValueError("crowning = \"circular\" needs crown_drop_um (the drop at the roller ends)")
        return RollerBearingGeometry(roller_count=count, roller_diameter_m=diameter, roller_length_m=length,
                                     pitch_diameter_m=values["pitch_diameter_mm"] * 1e-3, contact_angle_rad=angle,
                                     clearance_m=clearance_um * 1e-6, crowning=bearing.crowning,
                                     crowning_load_n=crowning_load, crown_drop_m=(bearing.crown_drop_um or 0.0) * 1e-6,
                                     slices=bearing.slices_per_roller)
    except ValueError as error:
        raise ValueError(f"{bearing.model.replace('_', ' ')} bearing geometry: {error}") from None


def _default_crowning_load(count: int, diameter: float, length: float, pitch: float, angle: float) -> float:
    """Q_d of the logarithmic profile where not given: the roller load at which an evenly loaded roller reaches
    2 000 MPa against the inner raceway (half ISO 76's static limit: a crowning meant for heavy operating
    loads; ESTIMATED — makers choose their own)."""
    plain = RollerBearingGeometry(count, diameter, length, pitch, angle, crowning="none", slices=1)
    # p = √(q' E'/(2π R)) → q' = 2π R p²/E'
    return 2.0 * math.pi * plain.inner_contact_radius_m * 2.0e9**2 / plain.e_prime * length


def clearance_um_of(bearing) -> float:
    """The diametral radial clearance (µm) of a cylindrical roller bearing entry: ``clearance_um``, else the
    middle of ``clearance_class``'s ISO 5753-1 range (CN with a designation)."""
    return clearance_from_keys(bearing, lambda: entry_of(bearing).bore_mm, "cylindrical_roller",
                               "a cylindrical roller bearing")


def _row_width_m(bearing) -> float:
    entry = entry_of(bearing)
    if "width_mm" in bearing.model_fields_set or entry is None:
        width = bearing.width_mm / (1 if bearing.arrangement == "single" else 2)
    else:
        width = entry.width_mm
    return width * 1e-3


def _offset_for_axial_load(law, load_n: float) -> float:
    """The axial offset (m) at which one row (facing +x) carries ``load_n`` axially."""
    row = RollingBearing((BearingRow(law),))

    def carried(offset):
        return row._carried(np.array([offset, 0.0, 0.0, 0.0, 0.0]))[0][0]

    from scipy.optimize import brentq  # here, not at import: scipy.optimize costs every sweep ~0.9 s

    upper = 1e-6
    while carried(upper) < load_n:
        upper *= 2.0
        if upper > 1e-2:
            raise ValueError(f"no axial offset below 10 mm carries {load_n:g} N")
    return brentq(lambda x: carried(x) - load_n, 0.0, upper, xtol=1e-15, rtol=1e-13)


def _row_offset_m(bearing, law, rated_n: float) -> float:
    """δ_r of each row from the preload keys (see the module docstring)."""
    pair = bearing.arrangement in ("DB", "DF")
    if bearing.preload_class is not None:
        return _offset_for_axial_load(law, PRELOAD_CLASS_SHARE[bearing.preload_class] * rated_n)
    if bearing.preload_N:
        share = 1.0 if bearing.arrangement in ("single", "DB", "DF") else 0.5
        try:
            return _offset_for_axial_load(law, share * bearing.preload_N)
        except ValueError as error:
            raise ValueError(f"preload_N = {bearing.preload_N:g} N: {error}") from None
    if bearing.axial_offset_um is not None:
        return bearing.axial_offset_um * 1e-6 / (2.0 if pair else 1.0)
    return 0.0


_GEOMETRY_KEYS = ("ball_count", "ball_diameter_mm", "inner_conformity", "outer_conformity", "pitch_diameter_mm",
                  "contact_angle_deg", "roller_count", "roller_diameter_mm", "roller_length_mm")


def _rated(bearing, law) -> float:
    """C (N) of one row: the catalogue's for a designation without geometry overrides, else ISO 281 on ``law``."""
    from rvcoax.geometry.rolling_catalogue import ball_dynamic_rating_N, roller_dynamic_rating_N

    entry = entry_of(bearing)
    if entry is not None and all(getattr(bearing, key) is None for key in _GEOMETRY_KEYS):
        return entry.dynamic_rating_N
    if isinstance(law, BallBearingGeometry):
        return ball_dynamic_rating_N(law.ball_count, law.ball_diameter_m * 1e3, law.pitch_diameter_m * 1e3,
                                     math.degrees(law.contact_angle_rad))
    return roller_dynamic_rating_N(law.roller_count, law.roller_diameter_m * 1e3, law.roller_length_m * 1e3,
                                   law.pitch_diameter_m * 1e3, math.degrees(law.contact_angle_rad))


def rolling_bearing_of(bearing, rig=None) -> RollingBearing:
    """The rows of an ``angular_contact``, ``cylindrical_roller`` or ``tapered_roller`` entry (SI); with
    ``rig``, its ``[thermal]`` rises act: on a cylindrical roller bearing's clearance, and on an angular
    bearing's rings as the axial offset −ΔP_d / (2 tan α) per row (a shaft warmer than its housing presses
    the rows together).

    Raises
    ------
    ValueError
        Unknown designation (naming the nearest), missing keys, a geometry that cannot be built.
    """
    if bearing.model == "cylindrical_roller":
        law = _law(bearing, clearance_um_of(bearing))
        rib, direction = _ribs(bearing, law)
        if rig is not None:
            law = law.with_clearance(operating_clearance_m(rig, bearing, law))
        return RollingBearing((BearingRow(law),), linear_axial_stiffness=rib * 1e6, axial_spring_direction=direction)
    law = _law(bearing)
    offset = _row_offset_m(bearing, law, _rated(bearing, law))
    change = thermal_clearance_change_um(rig, bearing, law.pitch_diameter_m)
    if change:
        offset += -0.5 * change * 1e-6 / math.tan(law.contact_angle_rad)
    if bearing.arrangement == "single":
        return RollingBearing((BearingRow(law, 0.0, bearing.axial_direction, offset),))
    half = 0.5 * _row_width_m(bearing)
    facings = {"DB": (1, -1), "DF": (-1, 1), "DT": (bearing.axial_direction,) * 2}[bearing.arrangement]
    return RollingBearing((BearingRow(law, -half, facings[0], offset), BearingRow(law, half, facings[1], offset)))


def cylindrical_variant(bearing) -> str | None:
    """NU, N, NJ or NUP: the rib arrangement of a cylindrical roller entry's designation (None without one)."""
    if bearing.designation is None:
        return None
    return entry_of(bearing).designation.rstrip("0123456789")


def _touching_radial_N_per_um(law: RollerBearingGeometry) -> float:
    """The radial tangent (N/µm) of a roller row without clearance at the reference deflection."""
    _, stiffness = RollingBearing((BearingRow(law.with_clearance(0.0)),)).force(
        np.array([0.0, REFERENCE_DEFLECTION_UM * 1e-6, 0.0, 0.0, 0.0]))
    return float(stiffness[1, 1]) * 1e-6


def rib_stiffness_N_per_um(bearing) -> float:
    """The axial stiffness of a cylindrical roller entry's ribs (N/µm): ``axial_stiffness_N_per_um``, else for an
    NJ or NUP bearing the radial reference stiffness (ESTIMATED, see the module docstring), else 0."""
    return _ribs(bearing, _law(bearing))[0]


def _ribs(bearing, law) -> tuple[float, int]:
    """(rib stiffness N/µm, direction: 0 both ways, ±1 one way) of a cylindrical roller entry; ValueError where
    the keys contradict the designation's ribs."""
    variant = cylindrical_variant(bearing)
    given = bearing.axial_stiffness_N_per_um
    if variant in ("NU", "N"):
        if given:
            raise ValueError(f"axial_stiffness_N_per_um = {given:g}: an {variant} bearing ({bearing.designation}) has "
                             f"ribs on {'its outer' if variant == 'NU' else 'its inner'} ring only, its rollers slide "
                             "axially and it carries no thrust; locate the shaft with another bearing (an NJ or NUP "
                             "designation carries thrust through its ribs)")
        if bearing.axial_direction != 1:
            raise ValueError(f"axial_direction: an {variant} bearing carries no thrust either way")
        return 0.0, 0
    if variant == "NUP" and bearing.axial_direction != 1:
        raise ValueError("axial_direction: an NUP bearing carries thrust both ways (ribs on both sides)")
    stiffness = given if given else (_touching_radial_N_per_um(law) if variant is not None else 0.0)
    return stiffness, (bearing.axial_direction if variant == "NJ" else 0)


def load_ratings_N(bearing) -> tuple[float, float]:
    """(C, C0) in N of one row of a bearing from geometry (``ball`` included): the catalogue's values for a
    designation without geometry overrides, else computed from the geometry the same way
    (:mod:`rvcoax.geometry.rolling_catalogue`: C by ISO 281, C0 by ISO 76's definition). A pair's ratings
    follow from a row's by ISO 281/76's rules for i rows."""
    from rvcoax.geometry.rolling_catalogue import ball_static_rating_N, roller_static_rating_N

    if bearing.model == "ball":
        from rvcoax.geometry.ball_model import geometry_of
        from rvcoax.geometry.rolling_catalogue import ball_dynamic_rating_N

        law = geometry_of(bearing).with_clearance(0.0)
        return (ball_dynamic_rating_N(law.ball_count, law.ball_diameter_m * 1e3, law.pitch_diameter_m * 1e3, 0.0),
                ball_static_rating_N(law))
    law = _law(bearing)
    entry = entry_of(bearing)
    if entry is not None and all(getattr(bearing, key) is None for key in _GEOMETRY_KEYS):
        return entry.dynamic_rating_N, entry.static_rating_N
    static = ball_static_rating_N(law) if isinstance(law, BallBearingGeometry) else roller_static_rating_N(
        law.with_clearance(0.0))
    return _rated(bearing, law), static


def clearance_upper_um(bearing) -> float:
    """The largest clearance a cylindrical roller bearing entry plausibly runs with (µm): the top of ISO 5753-1's
    C4 range for its bore, or 100 µm for explicit geometry."""
    from rvcoax.geometry.ball_bearings import clearance_range_um

    if bearing.designation is None:
        return 100.0
    return clearance_range_um(entry_of(bearing).bore_mm, "C4", "cylindrical_roller")[1]


def heavy_setting(bearing) -> tuple[float, float]:
    """An angular-contact or tapered entry's heavy-class setting: the preload force (N; what ``preload_N`` means
    for its arrangement) and the axial offset (µm; what ``axial_offset_um`` means) at which each row carries
    the heavy class's share of its C."""
    law = _law(bearing)
    row_load = PRELOAD_CLASS_SHARE["heavy"] * _rated(bearing, law)
    row_offset_um = _offset_for_axial_load(law, row_load) * 1e6
    force = row_load * (2.0 if bearing.arrangement == "DT" else 1.0)
    return force, row_offset_um * (2.0 if bearing.arrangement in ("DB", "DF") else 1.0)


def reference_stiffness(bearing) -> dict[str, float]:
    """The linear reference springs of an angular-contact or roller bearing entry (rig-file keys and units):
    the radial tangent of the rings just touching (no clearance, no offset) at a 5 µm radial deflection; the
    axial the same (a cylindrical roller bearing: its typed-in axial stiffness, 0 = free); tilt
    radial × ((d_m/2)²/2 + x_r²) (a ring of springs on the pitch circle, the rows x_r from the node); an NJ or NUP
    bearing's axial: its rib stiffness (:func:`rib_stiffness_N_per_um`).
    Only the linear model the nonlinear solve is condensed on: the solution does not depend on them."""
    law = _law(bearing)
    if isinstance(law, RollerBearingGeometry):
        law = law.with_clearance(0.0)
    touching = bearing.model_copy(update={"preload_class": None, "preload_N": 0.0, "axial_offset_um": 0.0})
    rows = rolling_bearing_of(touching) if bearing.model != "cylindrical_roller" else RollingBearing((BearingRow(law),))
    _, stiffness = rows.force(np.array([0.0, REFERENCE_DEFLECTION_UM * 1e-6, 0.0, 0.0, 0.0]))
    radial = float(stiffness[1, 1])
    lever = (0.5 * law.pitch_diameter_m) ** 2 / 2.0 + float(np.mean([r.axial_position_m**2 for r in rows.rows]))
    out = {"radial_stiffness_N_per_um": radial * 1e-6, "tilt_stiffness_Nm_per_rad": radial * lever}
    if bearing.model != "cylindrical_roller":
        out["axial_stiffness_N_per_um"] = radial * 1e-6
    elif cylindrical_variant(bearing) in ("NJ", "NUP"):
        out["axial_stiffness_N_per_um"] = rib_stiffness_N_per_um(bearing)
    return out


@dataclass(frozen=True)
class RollingBearingModel:
    """What the nonlinear solve needs of one bearing from internal geometry (SI)."""

    name: str
    model: str  # the rig file's model key
    bearing: RollingBearing

    @property
    def geometry(self):
        """The first row's geometry."""
        return self.bearing.rows[0].law


def rolling_bearing_model(bearing, rig=None) -> RollingBearingModel:
    """The solver's view of a bearing entry from internal geometry: ``ball`` (one row, its position preload)
    or one of :data:`GEOMETRIC_MODELS`; with ``rig`` at its ``[thermal]`` operating state."""
    if bearing.model == "ball":
        from rvcoax.fem.ball_bearing import axial_offset_for_preload
        from rvcoax.geometry.ball_model import geometry_of, operating_geometry

        law = geometry_of(bearing) if rig is None else operating_geometry(rig, bearing)
        row = BearingRow(law, 0.0, 1, axial_offset_for_preload(law, bearing.preload_N))
        return RollingBearingModel(bearing.name, "ball", RollingBearing((row,)))
    return RollingBearingModel(bearing.name, bearing.model, rolling_bearing_of(bearing, rig))
