"""The quantities a rig engineer reads per load case: coupling misalignment, bearing loads and tilts,
support reactions and the equilibrium residual, each against its allowable value.

Computed for every case of a sweep (:func:`case_engineering`, called by :func:`rvcoax.results.sweep.run_sweep`)
from the spring states of :mod:`rvcoax.results.connections` in two references:

*total*
    from the unloaded geometry (``u``; the springs' stress-free Δ0 subtracted): what a bearing
    carries, self-weight included.
*change*
    since the rest state (``u − u_rest``): what the torque adds.

Couplings are read like Y and β, from the state ``[paths] measured_from`` names (the aligned rig
at rest by default: the change; ``unloaded``: the total), because a rig is aligned at rest; the
installed misalignment a rig file declares for a coupling (``parallel_offset_um``,
``angular_misalignment_mrad``) stays in the coupling in both, as it does on the rig.

Coupling grades follow alignment practice: the parallel offset and the angularity (gap difference
per 100 mm of coupling diameter, i.e. the angle in mm/100 mm) against the tolerance for the
coupling's running speed (:data:`ALIGNMENT_TOLERANCES`, short flexible couplings), and against
the coupling maker's allowable offset and angle (``allowable_parallel_offset_mm``,
``allowable_angular_misalignment_deg``). Bearing tilts (inner ring against outer) are judged
against ``allowable_misalignment_arcmin`` of the bearing.

Everything is in the units its name says: µm, µrad, mm/100 mm, N, N·m, arcmin, degrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvcoax.fem import DOFS_PER_NODE, bearing_life
from rvcoax.geometry.bearing_ratings import (
    bearing_speeds_rpm,
    life_options,
    load_ratings,
    rib_thrust_warnings,
    rig_case_of,
)
from rvcoax.geometry.model.springs import ConnectionStates, SpringMotion, with_nonlinear_laws
from rvcoax.geometry.reducers import ReducerCheck, reducer_check
from rvcoax.loadcases import LoadCase
from rvcoax.results.torque_path import rating_sentence

__all__ = ["ALIGNMENT_TOLERANCES", "ALIGNMENT_TOLERANCE_SOURCE", "AlignmentTolerance", "BearingLifeQuantities",
           "BearingQuantities", "CaseEngineering", "CouplingQuantities", "DutyCycleLife", "GearMeshMisalignment",
           "NOISE", "Reaction", "alignment_grade", "alignment_tolerance", "bearing_warnings",
           "case_engineering", "case_name", "case_text", "duty_cycle_lives", "duty_cycle_of_lives", "duty_cycle_of_records",
           "engineering_warnings", "minimum_load_warnings", "reducer_warnings", "torque_rating_warnings",
           "engineering_tables", "life_columns", "life_entries", "lives_of_records", "mesh_misalignment",
           "play_crossings", "reaction_sum", "reducer_checks", "reducer_columns", "reducer_entries", "rolling_bearing_lives",
           "shaft_quantities", "sweep_lives", "sweep_reducer_checks"]

UM = 1e6  # m → µm
URAD = 1e6  # rad → µrad
ARCMIN = 60.0 * 180.0 / math.pi  # rad → arcmin


@dataclass(frozen=True)
class AlignmentTolerance:
    """One row of the alignment-tolerance table: up to ``speed_rpm``, short flexible couplings.

    Offsets in mm at the coupling; angularity as the gap difference in mm per 100 mm of coupling
    diameter (= the angle in mm/100 mm, 0.1 mm/100 mm = 1 mrad).
    """

    speed_rpm: float
    offset_excellent_mm: float
    offset_acceptable_mm: float
    angularity_excellent_mm_per_100mm: float
    angularity_acceptable_mm_per_100mm: float


ALIGNMENT_TOLERANCES = (
    AlignmentTolerance(750.0, 0.09, 0.19, 0.09, 0.13),
    AlignmentTolerance(1500.0, 0.06, 0.09, 0.05, 0.07),
    AlignmentTolerance(3000.0, 0.03, 0.06, 0.03, 0.04),
    AlignmentTolerance(6000.0, 0.02, 0.03, 0.02, 0.03),
)
ALIGNMENT_TOLERANCE_SOURCE = (
    "suggested shaft-alignment tolerances for short flexible couplings, metric table (50 Hz speeds), as "
    "published by laser-alignment makers (PRUFTECHNIK ROTALIGN handbook) in the form of ANSI/ASA S2.75-2017 "
    "Part 1; the row of the smallest table speed at or above the running speed (below 750 rpm: the 750 rpm "
    "row; above 6000 rpm: the 6000 rpm row)")


def alignment_tolerance(speed_rpm: float) -> AlignmentTolerance:
    """The row of :data:`ALIGNMENT_TOLERANCES` that applies at ``speed_rpm``."""
    for row in ALIGNMENT_TOLERANCES:
        if speed_rpm <= row.speed_rpm:
            return row
    return ALIGNMENT_TOLERANCES[-1]


def alignment_grade(offset_mm: float, angularity_mm_per_100mm: float, speed_rpm: float) -> str:
    """``excellent``, ``acceptable`` or ``out of tolerance`` at ``speed_rpm`` (both must hold)."""
    row = alignment_tolerance(speed_rpm)
    if offset_mm <= row.offset_excellent_mm and angularity_mm_per_100mm <= row.angularity_excellent_mm_per_100mm:
        return "excellent"
    if offset_mm <= row.offset_acceptable_mm and angularity_mm_per_100mm <= row.angularity_acceptable_mm_per_100mm:
        return "acceptable"
    return "out of tolerance"


def _percent(value: float, allowable: float | None) -> float | None:
    return None if allowable is None else 100.0 * value / allowable


@dataclass(frozen=True)
class CouplingQuantities:
    """Misalignment of a coupling's ``to`` hub against its ``from`` hub at the coupling centre.

    ``offset_*_um``: parallel offset; ``angle_*``: angular misalignment; ``angularity_mm_per_100mm``:
    the angle as alignment practice writes it; all from the state ``reference`` names (``[paths]
    measured_from``: the change since the aligned rest state by default), which is what the coupling's
    limits are judged with. ``offset_from_unloaded_um`` / ``angle_from_unloaded_urad``: the same
    misalignment measured from the unloaded geometry (self-weight included), a different quantity
    under its own name (equal to ``offset_um`` / ``angle_urad`` when ``measured_from = "unloaded"``). ``*_use_percent``: of the datasheet allowable (None
    without one). ``grade``: :func:`alignment_grade` at ``speed_rpm`` (None without a speed).
    """

    name: str
    reference: str
    offset_y_um: float
    offset_z_um: float
    offset_um: float
    angle_urad: float
    angle_deg: float
    angularity_mm_per_100mm: float
    offset_from_unloaded_um: float
    angle_from_unloaded_urad: float
    allowable_offset_mm: float | None
    allowable_angle_deg: float | None
    offset_use_percent: float | None
    angle_use_percent: float | None
    speed_rpm: float | None
    grade: str | None

    @property
    def datasheet_verdict(self) -> str:
        """``within datasheet``, ``exceeds datasheet`` or ``no datasheet limit``."""
        uses = [u for u in (self.offset_use_percent, self.angle_use_percent) if u is not None]
        if not uses:
            return "no datasheet limit"
        return "within datasheet" if max(uses) <= 100.0 else "exceeds datasheet"


@dataclass(frozen=True)
class BearingQuantities:
    """Load and tilt of a bearing (force the bearing exerts on its shaft; tilt of the inner ring,
    on the shaft, against the outer ring, in the housing).

    ``model``: ``linear`` (typed-in springs), ``clearance`` (radial play) or the model from internal geometry
    (``ball``, ``angular_contact``, ``cylindrical_roller``, ``tapered_roller``).
    ``*_stiffness_*``: the operating stiffness in this case: the typed-in spring of a linear bearing, the
    tangent ∂F/∂Δ of a nonlinear one at the case's state (radial: mean of y and z; tilt: mean about y
    and z), never the linear reference spring a nonlinear bearing is assembled with.
    ``loaded_elements`` / ``max_element_load_N``: a bearing from geometry's rolling elements in contact (balls or
    rollers) and its largest element load (None for other bearings).
    """

    name: str
    shaft: str
    housing: str
    x_mm: float
    force_y_N: float
    force_z_N: float
    force_axial_N: float
    force_radial_N: float
    force_radial_change_N: float
    tilt_urad: float
    tilt_change_urad: float
    tilt_arcmin: float
    allowable_tilt_arcmin: float | None
    tilt_use_percent: float | None
    model: str = "linear"
    radial_stiffness_N_per_um: float = float("nan")
    axial_stiffness_N_per_um: float = float("nan")
    tilt_stiffness_Nm_per_rad: float = float("nan")
    loaded_elements: int | None = None
    max_element_load_N: float | None = None

    @property
    def verdict(self) -> str:
        """``within allowable tilt``, ``exceeds allowable tilt`` or ``no allowable tilt given``."""
        if self.tilt_use_percent is None:
            return "no allowable tilt given"
        return "within allowable tilt" if self.tilt_use_percent <= 100.0 else "exceeds allowable tilt"


@dataclass(frozen=True)
class BearingLifeQuantities:
    """Life, static safety and minimum-load status of a bearing in one load case (:mod:`rvcoax.fem.bearing_life`).

    ``case``: the load case's name in the rig file, else its torques. ``L10_*``: ISO 281 basic rating life from
    the equivalent load ``equivalent_load_N``; ``L10r_*``: ISO/TS 16281 reference life from the element loads
    (bearings from internal geometry only); ``a_iso`` and ``Lnm_h``: with the rig keys viscosity_ratio and
    contamination_factor. Lives in million revolutions (``_Mrev``) and hours (``_h``, at ``speed_rpm``; None
    without a speed). ``static_safety``: s0; ``minimum_load_N``: the maker's rule (SKF's k_r forms where the rig gives k_r, else 0.01 C ball, 0.02 C roller).
    """

    name: str
    case: str
    speed_rpm: float | None
    rating_source: str
    dynamic_load_rating_N: float
    equivalent_load_N: float
    L10_Mrev: float
    L10_h: float | None
    L10r_Mrev: float | None
    L10r_h: float | None
    a_iso: float | None
    Lnm_h: float | None
    static_safety: float
    minimum_load_N: float
    below_minimum_load: bool

    @property
    def minimum_load_status(self) -> str:
        return "BELOW minimum load (skidding risk)" if self.below_minimum_load else "above minimum load"


def life_columns(lives) -> dict:
    """The ``sweep.csv`` columns of a case's bearing lives."""
    row = {}
    for life in lives:
        row[f"bearing_{life.name}_equivalent_load_N"] = life.equivalent_load_N
        row[f"bearing_{life.name}_L10_Mrev"] = life.L10_Mrev
        if life.L10_h is not None:
            row[f"bearing_{life.name}_L10_h"] = life.L10_h
        if life.L10r_Mrev is not None:
            row[f"bearing_{life.name}_L10r_Mrev"] = life.L10r_Mrev
        if life.L10r_h is not None:
            row[f"bearing_{life.name}_L10r_h"] = life.L10r_h
        if life.Lnm_h is not None:
            row[f"bearing_{life.name}_Lnm_h"] = life.Lnm_h
        row[f"bearing_{life.name}_static_safety"] = life.static_safety
        row[f"bearing_{life.name}_below_minimum_load"] = life.below_minimum_load
    return row


def reducer_columns(checks) -> dict:
    """The ``sweep.csv`` columns of a case's reducer checks."""
    row = {}
    for r in checks:
        row[f"reducer_{r.name}_torque_rated_percent"] = r.torque_rated_percent
        row[f"reducer_{r.name}_moment_Nm"] = r.moment_Nm
        row[f"reducer_{r.name}_moment_use_percent"] = r.moment_use_percent
        row[f"reducer_{r.name}_axial_use_percent"] = r.axial_use_percent
        row[f"reducer_{r.name}_verdict"] = r.verdict
    return row


def reducer_entries(checks) -> list[dict]:
    """The ``sweep.json`` entries of a case's reducer checks."""
    return [{**{k: getattr(r, k) for k in ReducerCheck.__dataclass_fields__}, "verdict": r.verdict} for r in checks]


def life_entries(lives) -> list[dict]:
    """The ``sweep.json`` entries of a case's bearing lives."""
    return [{**{k: getattr(b, k) for k in BearingLifeQuantities.__dataclass_fields__},
             "minimum_load_status": b.minimum_load_status} for b in lives]


@dataclass(frozen=True)
class DutyCycleLife:
    """A bearing's life over the rig file's duty cycle (Palmgren–Miner over its cases)."""

    name: str
    shares: str  # "time" or "revolution"
    L10_h: float | None
    L10_Mrev: float | None
    Lnm_h: float | None
    min_static_safety: float
    cases_below_minimum_load: tuple[str, ...]


@dataclass(frozen=True)
class GearMeshMisalignment:
    """The misalignment of one planet mesh of a ``[[gear_meshes]]`` stage in gear terms (ISO 6336-1).

    ``relative_tilt_urad``: the tilt of the driving gear's axis (``on``) against its mate's carrier
    (``reacted_on``) from the section rotations of both members; ``f_sigma_beta_um``: its inclination in the plane
    of action over the face width b (what K_Hβ takes as the mesh misalignment from deformation);
    ``f_sigma_delta_um``: the part normal to the plane of action. Read like Y, from the state ``[paths]
    measured_from`` names (the aligned rig at rest by default).
    """

    name: str
    planet: int
    planet_angle_deg: float
    face_width_mm: float
    relative_tilt_urad: float
    f_sigma_beta_um: float
    f_sigma_delta_um: float


def mesh_misalignment(rotation_on, rotation_mate, planet_angle_deg: float, pressure_angle_rad: float,
                      face_width_mm: float) -> tuple[float, float]:
    """(f_Σβ, f_Σδ) in µm of a mesh from the section rotations (θ_y, θ_z, rad) of both members.

    The relative rotation ω tilts the gear's axis by d = ω × x = (ω_z, −ω_y) in (y, z); the planet at angle φ
    (from +y towards +z, e = (cos φ, sin φ), t = x × e) has its line of action l = −cos α t − sin α e
    (:func:`rvcoax.geometry.gears.mesh_forces`) and m = x × l normal to the plane of action:
    f_Σβ = b |d · l|, f_Σδ = b |d · m|.
    """
    wy = float(rotation_on[0]) - float(rotation_mate[0])
    wz = float(rotation_on[1]) - float(rotation_mate[1])
    phi = math.radians(planet_angle_deg)
    e = np.array([math.cos(phi), math.sin(phi)])
    t = np.array([-math.sin(phi), math.cos(phi)])
    line = -math.cos(pressure_angle_rad) * t - math.sin(pressure_angle_rad) * e
    normal = np.array([-line[1], line[0]])
    d = np.array([wz, -wy])
    return (face_width_mm * abs(float(d @ line)) * 1e3, face_width_mm * abs(float(d @ normal)) * 1e3)


@dataclass(frozen=True)
class Reaction:
    """What a support to the ground (a mount, a bearing housed in ``ground``, a condensed ``[[housings]]``
    entry as a whole, ``kind`` says which) exerts on its part, at the support point (a housing: the
    centre of its attachments): force (N) and moment (N·m) along/about x, y, z; total and change under
    load. Values below the solve's accuracy (:data:`NOISE`) are written as 0."""

    name: str
    kind: str
    part: str
    x_mm: float
    force_N: tuple[float, float, float]
    moment_Nm: tuple[float, float, float]
    force_change_N: tuple[float, float, float]
    moment_change_Nm: tuple[float, float, float]


@dataclass(frozen=True)
class CaseEngineering:
    """The engineering tables of one load case, and the global equilibrium residual.

    ``residual_force_N`` / ``residual_moment_Nm``: |applied loads + ground reactions| (force, and
    moment about the origin) of the total state; zero up to rounding when equilibrium holds.
    ``applied_force_N``: the resultant of every load on the rig (its weight and the applied forces);
    the reactions' forces sum to its opposite. ``applied_torque_x_Nm``: the applied loads' moment about
    the rig axis (the torques T1, T2 and what the reducer's housing passes on); the reactions' moments
    about x sum to its opposite.
    """

    couplings: tuple[CouplingQuantities, ...]
    bearings: tuple[BearingQuantities, ...]
    reactions: tuple[Reaction, ...]
    residual_force_N: float
    residual_moment_Nm: float
    lives: tuple[BearingLifeQuantities, ...] = ()
    reducers: tuple[ReducerCheck, ...] = ()
    gear_meshes: tuple[GearMeshMisalignment, ...] = ()
    applied_force_N: tuple[float, float, float] = (0.0, 0.0, 0.0)
    applied_torque_x_Nm: float = 0.0

    def row(self) -> dict:
        """The columns this case adds to ``sweep.csv``."""
        row = {}
        for c in self.couplings:
            row[f"coupling_{c.name}_offset_um"] = c.offset_um
            row[f"coupling_{c.name}_angle_urad"] = c.angle_urad
            row[f"coupling_{c.name}_angularity_mm_per_100mm"] = c.angularity_mm_per_100mm
            row[f"coupling_{c.name}_offset_from_unloaded_um"] = c.offset_from_unloaded_um
            row[f"coupling_{c.name}_angle_from_unloaded_urad"] = c.angle_from_unloaded_urad
            if c.offset_use_percent is not None:  # columns only for the limits the rig file gives
                row[f"coupling_{c.name}_offset_use_percent"] = c.offset_use_percent
            if c.angle_use_percent is not None:
                row[f"coupling_{c.name}_angle_use_percent"] = c.angle_use_percent
            if c.grade is not None:
                row[f"coupling_{c.name}_alignment_grade"] = c.grade
        for b in self.bearings:
            row[f"bearing_{b.name}_force_radial_N"] = b.force_radial_N
            row[f"bearing_{b.name}_force_radial_change_N"] = b.force_radial_change_N
            row[f"bearing_{b.name}_tilt_urad"] = b.tilt_urad
            row[f"bearing_{b.name}_tilt_change_urad"] = b.tilt_change_urad
            if b.tilt_use_percent is not None:
                row[f"bearing_{b.name}_tilt_use_percent"] = b.tilt_use_percent
            row[f"bearing_{b.name}_radial_stiffness_N_per_um"] = b.radial_stiffness_N_per_um
            row[f"bearing_{b.name}_axial_stiffness_N_per_um"] = b.axial_stiffness_N_per_um
            row[f"bearing_{b.name}_tilt_stiffness_Nm_per_rad"] = b.tilt_stiffness_Nm_per_rad
            if b.loaded_elements is not None:
                row[f"bearing_{b.name}_loaded_elements"] = b.loaded_elements
                row[f"bearing_{b.name}_max_element_load_N"] = b.max_element_load_N
        row.update(life_columns(self.lives))
        row.update(reducer_columns(self.reducers))
        for g in self.gear_meshes:
            row[f"gear_{g.name}_planet{g.planet}_f_sigma_beta_um"] = g.f_sigma_beta_um
            row[f"gear_{g.name}_planet{g.planet}_f_sigma_delta_um"] = g.f_sigma_delta_um
        for r in self.reactions:
            for axis, value in zip("xyz", r.force_N):
                row[f"reaction_{r.name}_F{axis}_N"] = value
            for axis, value in zip("xyz", r.moment_Nm):
                row[f"reaction_{r.name}_M{axis}_Nm"] = value
        for axis, value in zip("xyz", self.applied_force_N):
            row[f"applied_F{axis}_N"] = value
        row["applied_Mx_Nm"] = self.applied_torque_x_Nm
        row["equilibrium_residual_force_N"] = self.residual_force_N
        row["equilibrium_residual_moment_Nm"] = self.residual_moment_Nm
        return row

    def entry(self) -> dict:
        """The keys this case adds to its entry in ``sweep.json``."""
        return {
            "couplings": [{**{k: getattr(c, k) for k in CouplingQuantities.__dataclass_fields__},
                           "datasheet_verdict": c.datasheet_verdict} for c in self.couplings],
            "bearings": [{**{k: getattr(b, k) for k in BearingQuantities.__dataclass_fields__},
                          "verdict": b.verdict} for b in self.bearings],
            "reactions": [{k: (list(v) if isinstance(v, tuple) else v) for k, v in
                           ((k, getattr(r, k)) for k in Reaction.__dataclass_fields__)} for r in self.reactions],
            "applied_force_N": list(self.applied_force_N),
            "applied_torque_x_Nm": self.applied_torque_x_Nm,
            "equilibrium_residual": {"force_N": self.residual_force_N, "moment_Nm": self.residual_moment_Nm},
        } | {key: value for key, value in (
            ("bearing_lives", life_entries(self.lives)), ("reducers", reducer_entries(self.reducers)),
            ("gear_meshes", [{k: getattr(g, k) for k in GearMeshMisalignment.__dataclass_fields__}
                             for g in self.gear_meshes])) if value}  # only what the rig has


NOISE = 1e-9
"""Relative size below which a reaction or bearing force is rounding, not data: the solves keep
equilibrium to ~1e-10 of the loads (``equilibrium_relative_error``), so a component below 1e-9 of the
case's largest support force (moment: times the rig's length) is written as 0."""


def reaction_sum(reactions: list[dict]) -> tuple[tuple[float, float, float], float]:
    """The sum of one case's support forces and of their moments about the rig axis.

    Parameters
    ----------
    reactions : list of dict
        The case's ``reactions`` (its ``sweep.json`` entry, or :meth:`CaseEngineering.entry`).

    Returns
    -------
    ((float, float, float), float)
        ΣF (N) along x, y, z and ΣM_x (N·m); rounding below :data:`NOISE` of the largest force written as 0.
    """
    scale = max((abs(v) for r in reactions for v in r["force_N"]), default=0.0)
    forces = _denoise([math.fsum(r["force_N"][k] for r in reactions) for k in range(3)], scale)
    torque = _denoise([math.fsum(r["moment_Nm"][0] for r in reactions)], scale)[0]
    return forces, torque


def _extent(springs: SpringMotion) -> float:
    """The lever (m) that turns a force scale into a moment scale: the springs' spread along x, at least 1 m."""
    return max(float(np.ptp(springs.point_m[:, 0])) if len(springs.point_m) else 0.0, 1.0)


def _denoise(values, scale: float) -> tuple[float, ...]:
    return tuple(0.0 if abs(v) <= NOISE * scale else float(v) + 0.0 for v in values)


def _coupling(c, states: ConnectionStates, unloaded: ConnectionStates, reference: str) -> CouplingQuantities:
    row = states.index("coupling", c.name)
    d = states.deformation[0, row]
    total = unloaded.deformation[0, row]
    offset_m = math.hypot(d[1], d[2])
    angle = math.hypot(d[4], d[5])
    angularity = 100.0 * math.tan(angle)  # gap difference over 100 mm of diameter, mm
    offset_mm = offset_m * 1e3
    return CouplingQuantities(name=c.name, reference=reference, offset_y_um=float(d[1] * UM),
                              offset_z_um=float(d[2] * UM), offset_um=offset_m * UM, angle_urad=angle * URAD,
                              angle_deg=math.degrees(angle), angularity_mm_per_100mm=angularity,
                              offset_from_unloaded_um=math.hypot(total[1], total[2]) * UM,
                              angle_from_unloaded_urad=math.hypot(total[4], total[5]) * URAD,
                              allowable_offset_mm=c.allowable_parallel_offset_mm,
                              allowable_angle_deg=c.allowable_angular_misalignment_deg,
                              offset_use_percent=_percent(offset_mm, c.allowable_parallel_offset_mm),
                              angle_use_percent=_percent(math.degrees(angle), c.allowable_angular_misalignment_deg),
                              speed_rpm=c.speed_rpm,
                              grade=None if c.speed_rpm is None else alignment_grade(offset_mm, angularity, c.speed_rpm))


def _bearing_model(b) -> str:
    """``linear``, ``clearance`` (a linear bearing with radial play) or the model from geometry (``ball``,
    ``angular_contact``, ``cylindrical_roller``, ``tapered_roller``)."""
    if b.model != "linear":
        return b.model
    return "clearance" if b.radial_clearance_um > 0 else "linear"


def _elements(point: dict | None) -> tuple[int | None, float | None]:
    """(loaded rolling elements, largest element load N) of a bearing's operating point (balls or rollers)."""
    if point is None:
        return None, None
    loaded = point.get("loaded_balls", point.get("loaded_elements"))  # a ball bearing's point names them balls
    largest = point.get("max_ball_load_N", point.get("max_element_load_N"))
    return (None if loaded is None else int(loaded)), (None if largest is None else float(largest))


def _bearing(b, total: ConnectionStates, change: ConnectionStates, scale: float, balls: dict) -> BearingQuantities:
    row = total.index("bearing", b.name)
    f, d = total.force_on_b[0, row], total.deformation[0, row]
    df, dd = change.force_on_b[0, row], change.deformation[0, row]
    k = total.stiffness[0, row]
    f = np.array(_denoise(f[:3], scale))
    df = np.array(_denoise(df[:3], scale))
    tilt = math.hypot(d[4], d[5])
    loaded, largest = _elements(balls.get(b.name))
    return BearingQuantities(name=b.name, shaft=b.shaft, housing=b.housing, x_mm=b.x_mm, force_y_N=float(f[1]) + 0.0,
                             force_z_N=float(f[2]) + 0.0, force_axial_N=float(f[0]) + 0.0,
                             force_radial_N=math.hypot(f[1], f[2]), force_radial_change_N=math.hypot(df[1], df[2]),
                             tilt_urad=tilt * URAD, tilt_change_urad=math.hypot(dd[4], dd[5]) * URAD,
                             tilt_arcmin=tilt * ARCMIN, allowable_tilt_arcmin=b.allowable_misalignment_arcmin,
                             tilt_use_percent=_percent(tilt * ARCMIN, b.allowable_misalignment_arcmin),
                             model=_bearing_model(b), radial_stiffness_N_per_um=float(0.5 * (k[1] + k[2]) * 1e-6),
                             axial_stiffness_N_per_um=float(k[0] * 1e-6),
                             tilt_stiffness_Nm_per_rad=float(0.5 * (k[4] + k[5])), loaded_elements=loaded,
                             max_element_load_N=largest)


def _reactions(rig, springs: SpringMotion, total: ConnectionStates, change: ConnectionStates, *,  # noqa: PLR0913
               fixed_total: np.ndarray | None, fixed_change: np.ndarray | None) -> tuple[Reaction, ...]:
    supports = [("mount", m.name, m.part, m.x_mm) for m in rig.mounts]
    supports += [("bearing", b.name, b.shaft, b.x_mm) for b in rig.bearings if b.housing == "ground"]
    found = []
    for kind, name, part, x in supports:
        row = total.index(kind, name)
        found.append((name, kind, part, x, total.force_on_b[0, row], change.force_on_b[0, row]))
    for bed in springs.beds:  # a condensed housing: the reactions of its fixed bed nodes, as a whole
        if fixed_total is None:
            continue
        change_of = bed.resultant(fixed_change) if fixed_change is not None else np.full(6, np.nan)
        found.append((bed.name, "housing", bed.part, bed.x_mm, bed.resultant(fixed_total), change_of))
    forces = [abs(v) for *_, f, df in found for v in (*f[:3], *df[:3]) if np.isfinite(v)]
    scale = max(forces, default=0.0)
    extent = _extent(springs)
    return tuple(Reaction(name=name, kind=kind, part=part, x_mm=x, force_N=_denoise(f[:3], scale),
                          moment_Nm=_denoise(f[3:], scale * extent), force_change_N=_denoise(df[:3], scale),
                          moment_change_Nm=_denoise(df[3:], scale * extent))
                 for name, kind, part, x, f, df in found)


def case_name(rig, input_torque_Nm: float, output_torque_Nm: float) -> str:
    """A load case as the tables name it: its ``name`` in the rig file, else its torques.

    Parameters
    ----------
    rig : Rig
        The rig (its ``[[load_cases]]`` entries).
    input_torque_Nm, output_torque_Nm : float
        The case's torques.

    Returns
    -------
    str
        The name, or :func:`case_text` (``"T1 = 0.5 N·m, T2 = 40 N·m"``).
    """
    entry = rig_case_of(rig, input_torque_Nm, output_torque_Nm)
    if entry is not None and entry.name is not None:
        return entry.name
    return case_text(input_torque_Nm, output_torque_Nm)


def case_text(input_torque_Nm: float, output_torque_Nm: float) -> str:
    """A load case by its torques, as the console, the report and the warnings write it.

    Parameters
    ----------
    input_torque_Nm, output_torque_Nm : float
        The case's input torque T1 and output torque T2, N·m.

    Returns
    -------
    str
        ``"T1 = 0.5 N·m, T2 = 40 N·m"`` (``:g`` format; :attr:`rvcoax.loadcases.LoadCase.text`).
    """
    return LoadCase(input_torque_Nm, output_torque_Nm).text


def _lives(rig, total: ConnectionStates, input_torque_Nm: float, output_torque_Nm: float):
    speeds = bearing_speeds_rpm(rig, rig_case_of(rig, input_torque_Nm, output_torque_Nm))
    name = case_name(rig, input_torque_Nm, output_torque_Nm)
    out = []
    for b in rig.bearings:
        ratings = load_ratings(b)
        if ratings is None or b.model != "linear":
            continue  # bearings from geometry: their life comes with their element loads (nonlinear sweep)
        f = total.force_on_b[0, total.index("bearing", b.name)]
        life = bearing_life.life_from_forces(math.hypot(f[1], f[2]), float(f[0]), ratings.dynamic_N, ratings.static_N,
                                             ratings.f0, elements=ratings.elements, speed_rpm=speeds[b.name],
                                             **life_options(b, ratings, speeds[b.name]))
        out.append(life_quantities(b.name, name, ratings, life))
    return tuple(out)


def life_quantities(bearing_name: str, case: str, ratings, life) -> BearingLifeQuantities:
    """A :class:`BearingLifeQuantities` row from a :class:`rvcoax.fem.bearing_life.LifeResult`."""
    return BearingLifeQuantities(
        name=bearing_name, case=case, speed_rpm=life.speed_rpm, rating_source=ratings.source,
        dynamic_load_rating_N=ratings.dynamic_N, equivalent_load_N=life.equivalent_load_N, L10_Mrev=life.basic_life_Mrev,
        L10_h=life.basic_life_h, L10r_Mrev=life.reference_life_Mrev, L10r_h=life.reference_life_h, a_iso=life.a_iso,
        Lnm_h=life.modified_life_h, static_safety=life.static_safety, minimum_load_N=life.minimum_load_N,
        below_minimum_load=life.below_minimum_load)


def rolling_bearing_lives(rig, nonlinear, motion: np.ndarray, input_torque_Nm: float,
                          output_torque_Nm: float) -> tuple[BearingLifeQuantities, ...]:
    """The lives of the bearings from internal geometry at a nonlinear solution's condensed motion
    (:class:`rvcoax.geometry.model.nonlinear_bearings.NonlinearBearings`): deep-groove ball, angular-contact
    (single or a set), cylindrical and tapered roller bearings.

    L10 (ISO 281) from the forces the rows carry (the preload a single row's mounting takes included) through the
    type's X/Y factors (:func:`rvcoax.geometry.bearing_ratings.equivalent_load`; a deep-groove bearing's from
    ISO 281 table 3) and the set's C; L10r (ISO/TS 16281) from the element loads: ball loads with their contact
    angles, roller lamina loads (:func:`rvcoax.fem.bearing_life.rows_reference_life`); s0 from the largest
    contact pressure (ISO 76: 4200 MPa ball, 4000 MPa roller); the minimum load (the maker's rule,
    :func:`rvcoax.geometry.bearing_ratings.life_options`) on the larger of P and the load that gives L10r.
    """
    from rvcoax.fem.rolling_bearing import carried_force, rolling_element_loads
    from rvcoax.geometry.bearing_ratings import equivalent_load

    speeds = bearing_speeds_rpm(rig, rig_case_of(rig, input_torque_Nm, output_torque_Nm))
    name = case_name(rig, input_torque_Nm, output_torque_Nm)
    entries = {b.name: b for b in rig.bearings}
    motions = nonlinear.motions(motion)
    out = []
    for model in nonlinear.rolling:
        bearing = entries[model.name]
        ratings = load_ratings(bearing)
        elements = rolling_element_loads(model.bearing, motions[model.name])
        force = carried_force(model.bearing, motions[model.name])
        radial, axial = math.hypot(force[1], force[2]), float(force[0])
        equivalent = None if model.model == "ball" else equivalent_load(bearing, model.geometry, ratings, radial,
                                                                        axial)[0]
        life = bearing_life.life_from_forces(
            radial, axial, ratings.dynamic_N, ratings.static_N, ratings.f0, elements=ratings.elements,
            speed_rpm=speeds[model.name], **life_options(bearing, ratings, speeds[model.name]),
            reference_life_Mrev=bearing_life.rows_reference_life(model.bearing, elements),
            static_safety_value=bearing_life.rows_static_safety(elements), equivalent_load_N=equivalent)
        out.append(life_quantities(model.name, name, ratings, life))
    return tuple(out)


def reducer_checks(rig, total: ConnectionStates, input_torque_Nm: float,
                   output_torque_Nm: float) -> tuple[ReducerCheck, ...]:
    """Each ``[[reducers]]`` entry against its rating table in one case, from the force and moment its joint
    carries (``total``: the spring states from the unloaded geometry, one case)."""
    return _reducers(rig, total, input_torque_Nm, output_torque_Nm)


def _gear_meshes(rig, model, u: np.ndarray) -> tuple[GearMeshMisalignment, ...]:
    """Each planet mesh's misalignment from the section rotations of the gear and its mate's carrier (frame nodes;
    a member modelled as a solid has none: that stage is left out)."""
    out = []
    for mesh in rig.gear_meshes:
        try:
            on, mate = model.node(mesh.on.part, mesh.on.x_mm), model.node(mesh.reacted_on.part, mesh.reacted_on.x_mm)
        except KeyError:
            continue
        rotation_on = (u[DOFS_PER_NODE * on + 4], u[DOFS_PER_NODE * on + 5])
        rotation_mate = (u[DOFS_PER_NODE * mate + 4], u[DOFS_PER_NODE * mate + 5])
        tilt = math.hypot(rotation_on[0] - rotation_mate[0], rotation_on[1] - rotation_mate[1])
        alpha = mesh.stage.working_pressure_angle
        for i, angle in enumerate(mesh.planet_angles_deg):
            beta, delta = mesh_misalignment(rotation_on, rotation_mate, angle, alpha, mesh.face_width_mm)
            out.append(GearMeshMisalignment(name=mesh.name, planet=i, planet_angle_deg=float(angle),
                                            face_width_mm=mesh.face_width_mm, relative_tilt_urad=tilt * URAD,
                                            f_sigma_beta_um=beta, f_sigma_delta_um=delta))
    return tuple(out)


def _reducers(rig, total: ConnectionStates, input_torque_Nm: float, output_torque_Nm: float):
    out = []
    for r in rig.reducers:
        f = total.force_on_b[0, total.index("joint", r.name)]
        torque = output_torque_Nm if r.torque == "T2" else input_torque_Nm
        out.append(reducer_check(r, torque, f[:3], f[3:]))
    return tuple(out)


def lives_of_records(records: list[dict]) -> list[tuple[BearingLifeQuantities, ...]]:
    """Per case of ``sweep.json``'s records, every bearing's :class:`BearingLifeQuantities` (its entry's
    ``engineering.bearing_lives``: typed-in bearings from their forces, ball bearings from their ball loads).

    Parameters
    ----------
    records : list of dict
        Case records as written to the journal (``{"row": …, "entry": …}``).

    Returns
    -------
    list of tuple of BearingLifeQuantities
        One tuple per record, in order.
    """
    fields = BearingLifeQuantities.__dataclass_fields__
    return [tuple(BearingLifeQuantities(**{k: v for k, v in life.items() if k in fields})
                  for life in record["entry"].get("engineering", {}).get("bearing_lives", [])) for record in records]


def play_crossings(operating_points: dict) -> list[str]:
    """Bearings with a radial clearance (deep-groove ball, cylindrical roller) whose shaft crosses its play between
    neighbouring cases of a nonlinear sweep: the radial motion (y, z) changes by at least half the diametral
    operating clearance from one case to the next (the shaft leaves the elements on one side for those on the
    other: the sweep's Y steps there).

    Parameters
    ----------
    operating_points : dict
        ``sweep.json``'s ``model.ball_bearing_operating_points`` and/or ``model.rolling_bearing_operating_points``
        (per bearing, the rest state then every case).

    Returns
    -------
    list of str
        One sentence per bearing and jump.
    """
    found = []
    for name, points in operating_points.items():
        cases = [p for p in points if p.get("case") != "at rest" and "displacement_yz_um" in p]
        for before, after in zip(cases, cases[1:]):
            jump = math.dist(before["displacement_yz_um"], after["displacement_yz_um"])
            clearance = after.get("operating_clearance_um", 0.0)
            if clearance > 0.0 and jump >= 0.5 * clearance:
                found.append(f"bearing {name} ({after.get('model', 'ball')}): the shaft crosses its play between {_point_case(before)} and "
                             f"{_point_case(after)} (its radial motion changes by {jump:.3g} µm, the operating clearance is "
                             f"{clearance:.3g} µm): Y steps there; a preload or a smaller clearance keeps it seated")
    return found


def _point_case(point: dict) -> str:
    """An operating point's case as the warnings name it (:func:`case_text`; a record without torques: its label)."""
    if "T1_input_Nm" in point and "T2_output_Nm" in point:
        return case_text(point["T1_input_Nm"], point["T2_output_Nm"])
    return point["case"]


def duty_cycle_of_records(rig, records: list[dict]) -> list[DutyCycleLife]:
    """:func:`duty_cycle_lives` from ``sweep.json`` case records (:func:`lives_of_records`).

    Parameters
    ----------
    rig : Rig
        The rig whose ``[[load_cases]]`` carry the duty cycle's shares.
    records : list of dict
        Case records (``{"row": …, "entry": …}``).

    Returns
    -------
    list of DutyCycleLife
        One per bearing with a life; empty without a duty cycle.
    """
    return duty_cycle_of_lives(rig, lives_of_records(records))


def sweep_lives(sweep) -> list[tuple[BearingLifeQuantities, ...]]:
    """Per case of a solved sweep, every bearing's life: the typed-in bearings' from the engineering tables, the
    ball bearings' from their ball loads (nonlinear sweeps).

    Parameters
    ----------
    sweep : Sweep
        A solved sweep.

    Returns
    -------
    list of tuple of BearingLifeQuantities
        One tuple per case, in the sweep's order.
    """
    return [(case.engineering.lives if case.engineering is not None else ()) + tuple(case.ball_lives)
            for case in sweep.cases]


def sweep_reducer_checks(sweep) -> list[tuple[ReducerCheck, ...]]:
    """Per case of a solved sweep, each reducer's check (from the engineering tables, or from a nonlinear
    sweep's own spring states)."""
    return [(case.engineering.reducers if case.engineering is not None else ()) + tuple(case.reducer_checks)
            for case in sweep.cases]


def duty_cycle_lives(rig, cases: list[CaseEngineering]) -> list[DutyCycleLife]:
    """Per bearing with a life, its life over the rig file's duty cycle (``time_share`` or ``revolution_share``
    of its ``[[load_cases]]``): Palmgren–Miner over the cases (:func:`rvcoax.fem.bearing_life.miner_life`).

    Parameters
    ----------
    rig : Rig
        The rig whose ``[[load_cases]]`` carry the shares.
    cases : list of CaseEngineering
        The engineering tables of the sweep's cases.

    Returns
    -------
    list of DutyCycleLife
        One per bearing; empty without a duty cycle or when the sweep did not solve every case of it.
    """
    return duty_cycle_of_lives(rig, [case.lives for case in cases])


def duty_cycle_of_lives(rig, case_lives: list[tuple[BearingLifeQuantities, ...]]) -> list[DutyCycleLife]:
    kind = ("time" if any(c.time_share is not None for c in rig.load_cases)
            else "revolution" if any(c.revolution_share is not None for c in rig.load_cases) else None)
    if kind is None or not case_lives:
        return []
    names = [case_name(rig, c.T1_input_Nm, c.T2_output_Nm) for c in rig.load_cases]
    shares = {n: getattr(c, f"{kind}_share") for n, c in zip(names, rig.load_cases)}
    by_bearing: dict[str, list[BearingLifeQuantities]] = {}
    for lives in case_lives:
        for life in lives:
            by_bearing.setdefault(life.name, []).append(life)
    out = []
    for name, lives in by_bearing.items():
        if sorted(life.case for life in lives) != sorted(names):
            continue  # the sweep did not solve every case of the duty cycle
        weights = [shares[life.case] for life in lives]
        hours, revs, modified = None, None, None
        if kind == "time":
            # a case at standstill (no speed) turns no revolutions: it adds no damage
            moving = [(w, life) for w, life in zip(weights, lives) if life.L10_h is not None]
            if moving:
                total_share = sum(w for w, _ in moving)
                hours = bearing_life.miner_life([life.L10_h for _, life in moving],
                                                [w / total_share for w, _ in moving]) / total_share
                if all(life.Lnm_h is not None for _, life in moving):
                    modified = bearing_life.miner_life([life.Lnm_h for _, life in moving],
                                                       [w / total_share for w, _ in moving]) / total_share
        else:
            revs = bearing_life.miner_life([life.L10_Mrev for life in lives], weights)
        out.append(DutyCycleLife(name=name, shares=kind, L10_h=hours, L10_Mrev=revs, Lnm_h=modified,
                                 min_static_safety=min(life.static_safety for life in lives),
                                 cases_below_minimum_load=tuple(life.case for life in lives if life.below_minimum_load)))
    return out


def case_engineering(rig, model, u_total: np.ndarray, u_change: np.ndarray, measured_from_rest: bool,  # noqa: PLR0913
                     *, applied: np.ndarray, reactions: np.ndarray, springs=None, case=None, fixed_total=None,
                     fixed_change=None, nonlinear=None, rest_total=None, balls=None) -> CaseEngineering:
    """The engineering tables of one case.

    Parameters
    ----------
    rig : Rig
    model : RigModel
        The sweep's frame (its springs).
    u_total, u_change : (n_dofs,) arrays
        The case's displacement from the unloaded geometry, and since the rest state.
    measured_from_rest : bool
        Couplings read from the change (rig aligned at rest) or from the total.
    applied, reactions : (6,) arrays
        Resultants of the applied loads and of the ground reactions of the total state
        (:func:`rvcoax.fem.equilibrium.check_equilibrium`).
    springs : SpringMotion, optional
        :meth:`rvcoax.geometry.model.springs.SpringMotion.of` ``(model, rig)``, built once for many cases.
    case : LoadCase, optional
        The case's torques: with them, the bearing lives and the reducer checks.
    fixed_total, fixed_change : (n_dofs,) arrays, optional
        K u − f of the total state and of the change since rest: their entries at fixed DOFs, the only ones
        read, are the reactions of the fixed supports (the bed nodes of condensed housings). Without them
        the housings have no row in the reaction table.
    nonlinear : NonlinearBearings, optional
        The condensed nonlinear bearings of a nonlinear sweep; with ``rest_total`` (the rest state from
        the unloaded geometry), their forces and operating stiffness come from their laws.
    balls : dict, optional
        :meth:`NonlinearBearings.operating_points` of the case (loaded rolling elements, largest element load).
    """
    springs = SpringMotion.of(model, rig) if springs is None else springs
    total = springs.states(u_total, from_rest=False)
    change = springs.states(u_change, from_rest=True)
    linear_change = springs.states(u_change, from_rest=False)
    if nonlinear is not None:
        total = with_nonlinear_laws(total, nonlinear, u_total)
        change = with_nonlinear_laws(change, nonlinear, u_total, rest_total)
    # a coupling's misalignment is what its element accommodates, Δ − Δ0: from the aligned rest state (the
    # change under load) or from the unloaded geometry, in both cases less the installed misalignment Δ0
    # that the rig file declares (parallel_offset_um, angular_misalignment_mrad; zero by default)
    coupled = ((linear_change, "change since the aligned rest state, with the installed misalignment")
               if measured_from_rest else (total, "from the unloaded geometry"))
    residual = np.asarray(applied, float) + np.asarray(reactions, float)
    support_reactions = _reactions(rig, springs, total, change, fixed_total=fixed_total, fixed_change=fixed_change)
    scale = max((abs(v) for r in support_reactions for v in r.force_N), default=0.0)
    return CaseEngineering(
        couplings=tuple(_coupling(c, coupled[0], total, coupled[1]) for c in rig.couplings),
        bearings=tuple(_bearing(b, total, change, scale, balls or {}) for b in rig.bearings),
        reactions=support_reactions,
        residual_force_N=float(np.linalg.norm(residual[:3])), residual_moment_Nm=float(np.linalg.norm(residual[3:])),
        applied_force_N=_denoise(np.asarray(applied, float)[:3], scale),
        applied_torque_x_Nm=_denoise(np.asarray(applied, float)[3:4], scale * _extent(springs))[0],
        lives=() if case is None else _lives(rig, total, case.input_torque_Nm, case.output_torque_Nm),
        reducers=() if case is None else _reducers(rig, total, case.input_torque_Nm, case.output_torque_Nm),
        gear_meshes=_gear_meshes(rig, model, u_change if measured_from_rest else u_total))


def shaft_quantities(path) -> dict:
    """A measured shaft's engineering quantities (µm, µrad; degrees where paper 000 uses them)."""
    start_slope, end_slope = path.end_slopes_urad
    start_offset, end_offset = path.end_offsets_um
    return {"Y_max_um": path.y_max_mm * 1e3, "beta_paper_deg": path.beta_deg, "beta_paper_urad": path.beta_urad,
            "tilt_urad": path.fitted_tilt_urad, "tilt_deg": path.fitted_tilt_deg,
            "end_slopes_urad": [start_slope, end_slope], "end_offsets_um": [start_offset, end_offset]}


def engineering_tables(sweep) -> list[dict]:
    """Per case of ``sweep``: ``{"T1_input_Nm", "T2_output_Nm", "shafts", "couplings", "bearings",
    "reactions", "equilibrium_residual"}``, plain data (lists of dicts) ready for a table or a report.

    ``shafts``: per measured shaft the paper's β (``beta_paper_*``, arcsin(Y_max/L)), the true tilt
    (least-squares slope), the end slopes and the offsets at both ends. The other tables are
    :meth:`CaseEngineering.entry`'s. Raises ``ValueError`` when the sweep carries no engineering
    tables (a sweep run with ``engineering=False``).

    Parameters
    ----------
    sweep : Sweep
        A sweep solved with ``engineering=True`` (the default).

    Returns
    -------
    list of dict
        One entry per case, in the sweep's order.
    """
    out = []
    for case in sweep.cases:
        if case.engineering is None:
            raise ValueError("this sweep was solved without engineering tables (run_sweep(..., engineering=False))")
        out.append({"T1_input_Nm": case.case.input_torque_Nm, "T2_output_Nm": case.case.output_torque_Nm,
                    "shafts": {s: shaft_quantities(p) for s, p in case.paths.items()}, **case.engineering.entry()})
    return out


UNLOADED_SHARE = 0.01
"""A bearing whose radial force is below this share of the largest bearing force of its case carries
(nearly) nothing: a ball bearing hanging in its clearance, a shaft inside a radial play."""


def _case_text(entry: dict, rig=None) -> str:
    if rig is not None:
        return case_name(rig, entry["T1_input_Nm"], entry["T2_output_Nm"])
    return case_text(entry["T1_input_Nm"], entry["T2_output_Nm"])


def _carrying(entry: dict) -> dict[str, bool]:
    bearings = entry["engineering"].get("bearings", [])
    largest = max((b["force_radial_N"] for b in bearings), default=0.0)
    return {b["name"]: b["force_radial_N"] > UNLOADED_SHARE * largest and (b.get("loaded_elements") is None
                                                                          or b["loaded_elements"] > 0)
            for b in bearings}


def bearing_warnings(entries: list[dict], rig=None) -> list[str]:
    """What a nonlinear sweep should say about its bearings, one sentence each, from the ``sweep.json`` case
    entries.

    * a bearing with a clearance or from ball geometry that carries (nearly) nothing in a case (radial force below :data:`UNLOADED_SHARE` of the
      case's largest bearing force, or no rolling element loaded): the load goes elsewhere;
    * a bearing with a clearance or from ball geometry that takes up its play (or lifts off) between two
      neighbouring cases (ordered by T2, then T1): Y is not proportional to torque across that step.

    Parameters
    ----------
    entries : list of dict
        The ``cases`` of ``sweep.json`` (each with its ``engineering.bearings``).
    rig : Rig, optional
        With it, cases are named as the tables name them (:func:`case_name`), else by their torques.

    Returns
    -------
    list of str
        The warnings (empty for a sweep whose bearings all carry load in every case).
    """
    if not entries or not entries[0].get("engineering", {}).get("bearings"):
        return []
    carrying = [_carrying(e) for e in entries]
    found = []
    nonlinear = [b for b in entries[0]["engineering"]["bearings"] if b["model"] != "linear"]
    for b in nonlinear:  # (a linear bearing's force passes through zero where torque cancels weight: no play)
        name = b["name"]
        idle = [i for i, state in enumerate(carrying) if not state[name]]
        if idle:
            cases = (f"in all {len(entries)} cases" if len(idle) == len(entries) else
                     f"in {len(idle)} of {len(entries)} cases ({'; '.join(_case_text(entries[i], rig) for i in idle[:3])}"
                     + (", …)" if len(idle) > 3 else ")"))
            found.append(f"bearing {name} ({b['model']}) carries (nearly) nothing {cases}: less than "
                         f"{100 * UNLOADED_SHARE:g} % of the largest bearing force"
                         + (", no rolling element loaded" if b.get("loaded_elements") is not None else "")
                         + "; its neighbours carry the shaft")
    order = sorted(range(len(entries)), key=lambda i: (entries[i]["T2_output_Nm"], entries[i]["T1_input_Nm"]))
    for b in nonlinear:
        name = b["name"]
        for i, j in zip(order, order[1:]):
            if carrying[i][name] != carrying[j][name]:
                shafts = entries[i]["engineering"].get("shafts", {})
                jumps = ", ".join(f"Y_{s} {shafts[s]['Y_max_um']:.3g} → "
                                  f"{entries[j]['engineering']['shafts'][s]['Y_max_um']:.3g} µm" for s in shafts)
                what = "takes up its play" if carrying[j][name] else "lifts off into its play"
                found.append(f"bearing {name} ({b['model']}) {what} between {_case_text(entries[i], rig)} and "
                             f"{_case_text(entries[j], rig)}: Y is not proportional to torque across that step ({jumps})")
    return found


def minimum_load_warnings(case_lives) -> list[str]:
    """One sentence per bearing that carries less than its minimum load in some case (the cases named).

    Parameters
    ----------
    case_lives : list of tuple of BearingLifeQuantities
        Per case, every bearing's life (:func:`sweep_lives`, :func:`lives_of_records`).

    Returns
    -------
    list of str
        One sentence per bearing below its minimum load in any case.
    """
    below: dict[str, list[BearingLifeQuantities]] = {}
    for lives in case_lives:
        for life in lives:
            if life.below_minimum_load:
                below.setdefault(life.name, []).append(life)
    found = []
    for name, lives in below.items():
        first = lives[0]
        share = first.minimum_load_N / first.dynamic_load_rating_N
        found.append(f"bearing {name} carries less than its minimum load ({first.minimum_load_N:.3g} N = {share:.2g} C, "
                     f"the makers' rule) in {len(lives)} case(s) ({'; '.join(life.case for life in lives)}): the "
                     "rolling elements may skid (smearing); preload it or load it radially")
    return found


def _beyond_rating(rig, entries: list[dict], group: str):
    """(case name, item) of every ``engineering.<group>`` item of the ``sweep.json`` case entries whose verdict is
    not ``within rating``."""
    for entry in entries:
        for item in entry.get("engineering", {}).get(group, []):
            if item["verdict"] != "within rating":
                yield case_name(rig, entry["T1_input_Nm"], entry["T2_output_Nm"]), item


def reducer_warnings(rig, entries: list[dict]) -> list[str]:
    """One sentence per reducer and case beyond its rating table (:func:`rvcoax.geometry.reducers.reducer_check`),
    from ``sweep.json`` case entries (their ``engineering.reducers``)."""
    return [f"reducer {red['name']} ({red['designation']}) in case {case}: {red['verdict']} (torque "
            f"{red['torque_Nm']:.4g} N·m = {red['torque_rated_percent']:.3g} % of rated; moment "
            f"{red['moment_Nm']:.3g} N·m = {red['moment_use_percent']:.3g} % of allowable; axial force "
            f"{red['axial_force_N']:.3g} N = {red['axial_use_percent']:.3g} % of the maximum)"
            for case, red in _beyond_rating(rig, entries, "reducers")]


def torque_rating_warnings(rig, entries: list[dict]) -> list[str]:
    """One sentence per rated coupling or shaft (torque sensor) and case above its rated torque
    (:func:`rvcoax.results.torque_path.torque_ratings`), from ``sweep.json`` case entries (their
    ``engineering.torque_ratings``): ``coupling C3 (rated 240 N·m) in case T1 = 1.43 N·m, T2 = 300 N·m: EXCEEDS rated
    torque (carries 300 N·m = 125 % of rated)``."""
    return [rating_sentence(r, case) for case, r in _beyond_rating(rig, entries, "torque_ratings")]


def engineering_warnings(rig, entries: list[dict], operating_points: dict | None = None) -> list[str]:
    """Every warning a sweep gives about its bearings and reducers, one sentence each, in one form
    (``bearing <name> (<model>) …``, ``reducer <name> (<designation>) …``, cases named as the tables name them):
    bearings that carry (nearly) nothing or take up their play (:func:`bearing_warnings`), bearings below their
    minimum load (:func:`minimum_load_warnings`), reducers beyond their rating table (:func:`reducer_warnings`),
    couplings and shafts (torque sensors) above their rated torque (:func:`torque_rating_warnings`),
    shafts crossing a bearing's play between neighbouring cases (:func:`play_crossings`), NJ/NUP ribs carrying more
    thrust than SKF allows (:func:`rvcoax.geometry.bearing_ratings.rib_thrust_warnings`). The console prints them
    with ``warning:``, the report in its misalignment section.

    Parameters
    ----------
    rig : Rig
        The rig (its case names).
    entries : list of dict
        The ``cases`` of ``sweep.json``.
    operating_points : dict, optional
        ``model.ball_bearing_operating_points`` and ``model.rolling_bearing_operating_points`` merged.

    Returns
    -------
    list of str
        The sentences (empty when nothing is wrong).
    """
    tables = [e for e in entries if "couplings" in e.get("engineering", {})]
    return (bearing_warnings(tables, rig) + minimum_load_warnings(lives_of_records([{"entry": e} for e in entries]))
            + reducer_warnings(rig, entries) + torque_rating_warnings(rig, entries)
            + play_crossings(operating_points or {})
            + rib_thrust_warnings(rig, tables, lambda entry: _case_text(entry, rig)))
