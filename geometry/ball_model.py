"""A rig file's ``[[bearings]] model = "ball"`` entry → :class:`rvcoax.fem.ball_bearing.BallBearingGeometry`.

The catalogue (:mod:`rvcoax.geometry.ball_bearings`) gives the internal geometry of a designation;
explicit keys override it. The clearance is ``clearance_um`` (the radial internal clearance, diametral,
as mounted: after fits, at the temperature the rig was built in) or, without it, the middle of an
ISO 5753-1 class's range (``clearance_class``; CN when a designation is given and neither key is).
A ``[thermal]`` table whose shaft and housing rises differ changes it in operation
(:func:`thermal_clearance_change_um`).
"""

from __future__ import annotations

import numpy as np

from rvcoax.errors import RvcoaxError
from rvcoax.fem.ball_bearing import BallBearingGeometry, ball_loads
from rvcoax.geometry.ball_bearings import BALL_BEARINGS, clearance_range_um

__all__ = ["BALL_BEARINGS", "BALL_KEYS", "BEARING_STEEL_EXPANSION_PER_K", "GEOMETRY_KEYS", "OperatingClearanceError",
           "REFERENCE_DEFLECTION_UM", "clearance_from_keys", "clearance_um_of", "clearance_upper_um", "geometry_of",
           "operating_clearance_m", "operating_geometry", "preload_upper_N", "reference_stiffness",
           "thermal_clearance_change_um"]

BEARING_STEEL_EXPANSION_PER_K = 12.0e-6
"""α of through-hardened bearing steel (100Cr6 / GCr15), 1/K: SKF rolling bearings catalogue, *Materials for
rolling bearings* (12 · 10⁻⁶ /K); rings and balls."""

GEOMETRY_KEYS = ("ball_count", "ball_diameter_mm", "pitch_diameter_mm", "inner_conformity", "outer_conformity")
BALL_KEYS = ("designation", "clearance_class", "clearance_um", "preload_N") + GEOMETRY_KEYS
REFERENCE_DEFLECTION_UM = 5.0
"""The radial deflection (µm, zero clearance) at which the linear reference stiffness is taken."""


def clearance_um_of(bearing) -> float:
    """The diametral radial internal clearance (µm) a ball bearing entry asks for: ``clearance_um`` (the
    operating clearance) when given, else the middle of ``clearance_class``'s ISO 5753-1 range (CN
    when neither is given and there is a designation).

    Parameters
    ----------
    bearing : Bearing
        The bearing entry, with its ``clearance_um`` or ``clearance_class`` and designation.

    Returns
    -------
    float
        The clearance in µm.
    """
    return clearance_from_keys(bearing, lambda: BALL_BEARINGS[bearing.designation].bore_mm, "ball", "a ball bearing")


def clearance_from_keys(bearing, bore_mm, kind: str, what: str) -> float:
    """``clearance_um`` when given, else the middle of ``clearance_class``'s ISO 5753-1 range for the bore
    ``bore_mm()`` of the designation (CN when neither is given), for a bearing of ``kind``
    (:func:`rvcoax.geometry.ball_bearings.clearance_range_um`); ``what`` names it in the errors."""
    if bearing.clearance_um is not None:  # the operating clearance; a class then only records what was bought
        return float(bearing.clearance_um)
    if bearing.designation is None:
        if bearing.clearance_class is not None:
            raise ValueError("clearance_class needs a designation (the class range depends on the bore); "
                             "give clearance_um with explicit geometry")
        raise ValueError(f"{what} with explicit geometry needs clearance_um (the radial internal clearance)")
    low, high = clearance_range_um(bore_mm(), bearing.clearance_class or "CN", kind)
    return 0.5 * (low + high)


def geometry_of(bearing) -> BallBearingGeometry:
    """The internal geometry of a ``model = "ball"`` bearing entry (SI).

    Parameters
    ----------
    bearing : Bearing
        A rig file's ``model = "ball"`` bearing entry.

    Returns
    -------
    BallBearingGeometry
        Ball count and diameter, pitch diameter, raceway conformities, contact angle, clearance.

    Raises
    ------
    ValueError
        Unknown designation, missing geometry keys, or a geometry that cannot be built; the message
        names the keys.
    """
    values = {}
    if bearing.designation is not None:
        if bearing.designation not in BALL_BEARINGS:
            raise ValueError(f"designation: unknown ball bearing {bearing.designation!r} (known: "
                             f"{', '.join(BALL_BEARINGS)}); or give ball_count, ball_diameter_mm, pitch_diameter_mm, "
                             "inner_conformity and outer_conformity")
        entry = BALL_BEARINGS[bearing.designation]
        values = {"ball_count": entry.ball_count, "ball_diameter_mm": entry.ball_diameter_mm,
                  "pitch_diameter_mm": entry.pitch_diameter_mm, "inner_conformity": entry.inner_conformity,
                  "outer_conformity": entry.outer_conformity}
    values.update({key: getattr(bearing, key) for key in GEOMETRY_KEYS if getattr(bearing, key) is not None})
    missing = [key for key in GEOMETRY_KEYS if key not in values]
    if missing:
        raise ValueError(f"model = \"ball\" needs a designation or the geometry keys; missing: {', '.join(missing)}")
    clearance = clearance_um_of(bearing)
    try:
        return BallBearingGeometry(ball_count=int(values["ball_count"]),
                                   ball_diameter_m=values["ball_diameter_mm"] * 1e-3,
                                   pitch_diameter_m=values["pitch_diameter_mm"] * 1e-3,
                                   inner_conformity=values["inner_conformity"],
                                   outer_conformity=values["outer_conformity"], clearance_m=clearance * 1e-6)
    except ValueError as error:
        raise ValueError(f"ball bearing geometry: {error}") from None


def reference_stiffness(bearing) -> dict[str, float]:
    """The linear reference springs of a ball bearing, in the rig file's keys and units.

    Radial: the tangent of the bearing without clearance at :data:`REFERENCE_DEFLECTION_UM`; axial:
    the same value; tilt: radial × ℛ_i²/2 (a ring of springs on the curvature-centre circle). They only
    set the linear model the nonlinear solve is condensed on, and what exports that need one linear
    number per bearing show: the converged solution does not depend on them.
    """
    geometry = geometry_of(bearing).with_clearance(0.0)
    state = ball_loads(geometry, np.array([0.0, REFERENCE_DEFLECTION_UM * 1e-6, 0.0, 0.0, 0.0]))
    radial = float(state.stiffness[1, 1])
    return {"radial_stiffness_N_per_um": radial * 1e-6, "axial_stiffness_N_per_um": radial * 1e-6,
            "tilt_stiffness_Nm_per_rad": radial * geometry.inner_centre_radius_m**2 / 2.0}


class OperatingClearanceError(RvcoaxError, ValueError):
    """The temperatures take up more than a ball bearing's whole clearance (the message says which and by how much)."""

    stage = "cannot solve the rig"


def thermal_clearance_change_um(rig, bearing, pitch_diameter_m: float | None = None) -> float:
    """Change of a ball bearing's diametral clearance (µm) from the ``[thermal]`` rises of its rings.

    The inner ring is as warm as its shaft (ΔT_i: the shaft part's ``temperature_rise_K``), the outer ring as
    its housing part (ΔT_o), the balls at the mean of the two; all bearing steel (α_b,
    :data:`BEARING_STEEL_EXPANSION_PER_K`). The outer raceway diameter d_m + D_w grows by α_b (d_m + D_w) ΔT_o,
    the inner one d_m − D_w by α_b (d_m − D_w) ΔT_i and the two balls by 2 α_b D_w (ΔT_i + ΔT_o)/2, so

        ΔP_d = α_b [(d_m + D_w) ΔT_o − (d_m − D_w) ΔT_i − D_w (ΔT_i + ΔT_o)] = −α_b d_m (ΔT_i − ΔT_o):

    a shaft warmer than its housing takes clearance up; equal rises leave it (the rig grows as a rigid body).
    Fits are not changed by the rises (shaft and housing materials other than steel would). The same holds for
    the rollers of a roller bearing (``pitch_diameter_m`` given: any bearing from geometry).
    """
    thermal = getattr(rig, "thermal", None) if rig is not None else None
    if thermal is None:
        return 0.0
    inner = thermal.temperature_rise_K.get(bearing.shaft, 0.0)
    outer = thermal.temperature_rise_K.get(bearing.housing, 0.0)
    if inner == outer:
        return 0.0
    pitch = geometry_of(bearing).pitch_diameter_m if pitch_diameter_m is None else pitch_diameter_m
    return -BEARING_STEEL_EXPANSION_PER_K * pitch * (inner - outer) * 1e6


def operating_geometry(rig, bearing) -> BallBearingGeometry:
    """:func:`geometry_of` with the clearance the ``[thermal]`` rises leave (:func:`thermal_clearance_change_um`).

    Raises
    ------
    OperatingClearanceError
        The rises take up more than the whole clearance (an interference the model does not take).
    """
    geometry = geometry_of(bearing)
    return geometry.with_clearance(operating_clearance_m(rig, bearing, geometry))


def operating_clearance_m(rig, bearing, geometry) -> float:
    """The diametral clearance (m) of ``geometry`` (a ball or cylindrical roller bearing's) after the ``[thermal]``
    rises of its shaft and housing (:func:`thermal_clearance_change_um`).

    Raises
    ------
    OperatingClearanceError
        The rises take up more than the whole clearance (an interference the model does not take).
    """
    change = thermal_clearance_change_um(rig, bearing, geometry.pitch_diameter_m)
    clearance = geometry.clearance_m + change * 1e-6
    if clearance < 0.0:
        raise OperatingClearanceError(
            f"bearings '{bearing.name}': [thermal] shaft '{bearing.shaft}' "
            f"{rig.thermal.temperature_rise_K.get(bearing.shaft, 0.0):g} K against housing '{bearing.housing}' "
            f"{rig.thermal.temperature_rise_K.get(bearing.housing, 0.0):g} K takes up {-change:.3g} µm of clearance, "
            f"more than its {geometry.clearance_m * 1e6:.3g} µm: the rings would be forced together (an "
            "interference this model does not take); give a larger clearance_um or clearance_class, or closer "
            "temperature rises")
    return clearance


def clearance_upper_um(bearing) -> float:
    """The largest clearance a ball bearing entry plausibly runs with (µm): the top of ISO 5753-1's C4
    range for its bore, or 50 µm for explicit geometry."""
    if bearing.designation is None:
        return 50.0
    return clearance_range_um(BALL_BEARINGS[bearing.designation].bore_mm, "C4")[1]


def preload_upper_N(bearing) -> float:
    """The largest axial preload a deep-groove ball bearing plausibly carries (N): 2 % of its static
    load rating C0 ≈ f0 Z D_w² (ISO 76, f0 ≈ 12.3 for deep-groove ball bearings, D_w in mm)."""
    geometry = geometry_of(bearing)
    return 0.02 * 12.3 * geometry.ball_count * (geometry.ball_diameter_m * 1e3) ** 2
