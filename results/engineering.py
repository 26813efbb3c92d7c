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

from rvcoax.geometry.model.springs import ConnectionStates, SpringMotion, with_nonlinear_laws

__all__ = ["ALIGNMENT_TOLERANCES", "ALIGNMENT_TOLERANCE_SOURCE", "AlignmentTolerance", "BearingQuantities",
           "CaseEngineering", "CouplingQuantities", "NOISE", "Reaction", "alignment_grade", "alignment_tolerance",
           "bearing_warnings", "case_engineering", "engineering_tables", "reaction_sum", "shaft_quantities"]

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
        }


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


def case_engineering(rig, model, u_total: np.ndarray, u_change: np.ndarray, measured_from_rest: bool,  # noqa: PLR0913
                     *, applied: np.ndarray, reactions: np.ndarray, springs=None, fixed_total=None,
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
    fixed_total, fixed_change : (n_dofs,) arrays, optional
        K u − f of the total state and of the change since rest: their entries at fixed DOFs are the
        reactions of the fixed supports (the bed nodes of condensed housings). Without them the
        housings have no row in the reaction table.
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
        applied_torque_x_Nm=_denoise(np.asarray(applied, float)[3:4], scale * _extent(springs))[0])


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


def _case_text(entry: dict) -> str:
    return f"T1 = {entry['T1_input_Nm']:g}, T2 = {entry['T2_output_Nm']:g} N·m"


def _carrying(entry: dict) -> dict[str, bool]:
    bearings = entry["engineering"].get("bearings", [])
    largest = max((b["force_radial_N"] for b in bearings), default=0.0)
    return {b["name"]: b["force_radial_N"] > UNLOADED_SHARE * largest and (b.get("loaded_elements") is None
                                                                          or b["loaded_elements"] > 0)
            for b in bearings}


def bearing_warnings(entries: list[dict]) -> list[str]:
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
                     f"in {len(idle)} of {len(entries)} cases ({'; '.join(_case_text(entries[i]) for i in idle[:3])}"
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
                found.append(f"bearing {name} ({b['model']}) {what} between {_case_text(entries[i])} and "
                             f"{_case_text(entries[j])}: Y is not proportional to torque across that step ({jumps})")
    return found
