"""The tables of the study report (:mod:`rvcoax.results.reports.report`), as plain rows.

Each function returns a :class:`Table`: a caption, column headings with their units, and rows of
already formatted cells, so that the HTML writer only lays them out. Numbers follow one policy:
displacements in µm, angles in µrad (and degrees or arcminutes where datasheets use them), forces
in N, torques in N·m.

:func:`misalignment_tables` is the one place the coupling and bearing judgements come from; it
reads the spring states of :mod:`rvcoax.results.connections` and the allowable values of the rig
file when the schema has them (``allowable_parallel_offset_mm``, ``allowable_angular_misalignment_deg``
of a coupling; ``allowable_misalignment_arcmin`` of a bearing).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model.springs import ConnectionStates
from rvcoax.results.connections import connection_states

__all__ = ["PROVENANCE_TAGS", "Table", "check_table", "load_case_table", "misalignment_tables", "provenance_tags",
           "reaction_table", "rig_tables", "shaft_table", "verdict_of"]

PROVENANCE_TAGS = {"S": "datasheet or catalogue", "P": "paper 000", "R": "catalogue value from memory (estimate)",
                   "A": "assumption", "D": "derived from tagged numbers"}
_TAG = re.compile(r"\[([SPRAD])\]")


@dataclass(frozen=True)
class Table:
    """A table of the report: ``caption``, ``columns`` (heading with unit) and formatted ``rows``.

    ``verdict_column``: index of a column whose cells are verdicts (coloured in the HTML), or None.
    """

    caption: str
    columns: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]
    verdict_column: int | None = None
    note: str = ""


def _g(value: float, digits: int = 4) -> str:
    """A number with ``digits`` significant digits, plain (no 1e-05 for a µm value)."""
    if value is None or not math.isfinite(value):
        return "–"
    if value == 0:
        return "0"
    magnitude = math.floor(math.log10(abs(value)))
    if -4 <= magnitude < 7:
        decimals = max(digits - 1 - magnitude, 0)
        return f"{value:.{decimals}f}"
    return f"{value:.{digits - 1}e}"


# --------------------------------------------------------------------------------------------
# The rig file's provenance tags


def provenance_tags(rig_text: str) -> dict[tuple[str, str], dict[str, str]]:
    """(table, name) → {key: tags} from the ``# [S] …`` comments of a rig file.

    ``table`` is the array-of-tables a line belongs to (``parts``, ``bearings``, ``couplings``, …;
    ``materials.<name>`` for a material) and ``name`` the entry's ``name`` key (the material's name
    for materials). Tags on a line without a key (a comment line inside the entry) count for the
    entry as a whole (key ``""``).
    """
    found: dict[tuple[str, str], dict[str, str]] = {}
    table, name, pending = "", "", []
    for raw in rig_text.splitlines():
        line = raw.strip()
        code, _, comment = line.partition("#")
        header = re.match(r"^\[\[?\s*([A-Za-z0-9_.\-]+)\s*\]\]?", code.strip())
        if header:
            table = header.group(1)
            name = table.split(".", 1)[1] if table.startswith("materials.") else ""
            table = "materials" if table.startswith("materials.") else table
            pending = []
            continue
        key_match = re.match(r"^([A-Za-z0-9_\-]+)\s*=", code.strip())
        if key_match and key_match.group(1) == "name":
            value = re.search(r"=\s*\"([^\"]*)\"", code)
            name = value.group(1) if value else name
            for key, tags in pending:
                _add(found, table, name, key, tags)
            pending = []
        tags = "".join(f"[{t}]" for t in _TAG.findall(comment))
        if not tags:
            continue
        key = key_match.group(1) if key_match else ""
        if name or table == "materials":
            _add(found, table, name, key, tags)
        else:
            pending.append((key, tags))
    return found


def _add(found, table, name, key, tags):
    entry = found.setdefault((table, name), {})
    merged = dict.fromkeys(_TAG.findall(entry.get(key, "") + tags))  # each tag once, in order of appearance
    entry[key] = "".join(f"[{t}]" for t in merged)


def _tags_text(tags: dict[str, str], keys: tuple[str, ...] | None = None) -> str:
    """``key [S]; key [A]`` for the tagged keys (all when ``keys`` is None)."""
    items = [(k, v) for k, v in tags.items() if keys is None or k in keys or k == ""]
    return "; ".join(f"{k} {v}" if k else v for k, v in items) or "untagged"


# --------------------------------------------------------------------------------------------
# The rig


def _bearing_stiffness_cells(bearing) -> tuple[str, str]:
    """The radial and tilt stiffness cells of the rig's bearing table: the typed-in values of a linear bearing; for
    a bearing from internal geometry its kind (its stiffness follows from its state: see the solver's operating
    points), not the linear reference the solve is condensed on."""
    if bearing.model == "linear":
        return _g(bearing.radial_stiffness_N_per_um, 3), _g(bearing.tilt_stiffness_Nm_per_rad, 3)
    kind = {"ball": "deep-groove ball", "angular_contact": "angular-contact ball",
            "cylindrical_roller": "cylindrical roller", "tapered_roller": "tapered roller"}[bearing.model]
    pair = "" if bearing.model == "ball" or bearing.arrangement == "single" else f" {bearing.arrangement} pair"
    return f"from geometry: {kind} {bearing.designation or ''}{pair}".rstrip(), "from geometry"


def rig_tables(sweep, rig_text: str) -> list[Table]:
    """Parts (with modelled masses), bearings and couplings, each with its provenance tags."""
    rig, frame = sweep.rig, sweep.frame
    tags = provenance_tags(rig_text)
    masses = getattr(frame, "part_mass_kg", {}) or {}
    parts = []
    for p in rig.parts:
        x0, x1 = p.x_range_mm
        outer = max(s.outer_diameter_mm for s in p.segments)
        parts.append((p.name, p.role, p.material, f"{x0:g} … {x1:g}", f"{outer:g}",
                      "–" if p.mass_kg is None else _g(p.mass_kg, 3), _g(masses.get(p.name, float("nan")), 3),
                      _tags_text(tags.get(("parts", p.name), {}))))
    total = sum(masses.get(p.name, 0.0) for p in rig.parts)  # a part's modelled mass includes its coupling hubs
    tables = [Table("Parts along the rig axis", ("part", "role", "material", "x [mm]", "largest Ø [mm]",
                                                 "mass in the file [kg]", "mass as modelled [kg]", "provenance"),
                    tuple(parts), note=f"Mass of the whole rig as modelled (parts and coupling hubs): {total:.3g} kg.")]
    bearings = tuple((b.name, b.shaft, b.housing, f"{b.x_mm:g}", *_bearing_stiffness_cells(b),
                      _tags_text(tags.get(("bearings", b.name), {})))
                     for b in rig.bearings)
    if bearings:
        tables.append(Table("Bearings", ("bearing", "shaft", "housing", "x [mm]", "radial stiffness [N/µm]",
                                         "tilt stiffness [N·m/rad]", "provenance"), bearings))
    couplings = tuple((c.name, f"{c.from_.part} → {c.to.part}", f"{c.centre_x_mm:g}", _g(c.mass_kg, 3),
                       _g(c.radial_stiffness_N_per_mm, 3), _g(c.angular_stiffness_Nm_per_rad, 3),
                       _tags_text(tags.get(("couplings", c.name), {}))) for c in rig.couplings)
    if couplings:
        tables.append(Table("Couplings", ("coupling", "from → to", "centre x [mm]", "mass [kg]",
                                          "radial stiffness [N/mm]", "angular stiffness [N·m/rad]", "provenance"),
                            couplings))
    materials = tuple((name, _g(m.youngs_modulus_MPa, 4), _g(m.poisson_ratio, 3), _g(m.density_kg_per_m3, 4),
                       _tags_text(tags.get(("materials", name), {}))) for name, m in rig.materials.items())
    tables.append(Table("Materials", ("material", "E [MPa]", "ν", "ρ [kg/m³]", "provenance"), materials))
    return tables


def load_case_table(sweep) -> Table:
    rows = tuple((str(i + 1), f"{c.case.input_torque_Nm:g}", f"{c.case.output_torque_Nm:g}")
                 for i, c in enumerate(sweep.cases))
    return Table("Load cases", ("case", "T1 input torque [N·m]", "T2 output torque [N·m]"), rows)


def shaft_table(sweep) -> Table:
    """Per case and measured shaft: Y, the paper's β, the true tilt and the end slopes."""
    rows = []
    for case in sweep.cases:
        for shaft in MEASURED_SHAFTS:
            path = case.paths[shaft]
            rows.append((f"{case.case.input_torque_Nm:g}", f"{case.case.output_torque_Nm:g}", shaft,
                         _g(path.y_max_mm * 1e3), _g(path.beta_deg * math.pi / 180 * 1e6),
                         _g(path.fitted_tilt_deg * math.pi / 180 * 1e6),
                         _g(path.rotation_z_rad[0] * 1e6), _g(path.rotation_z_rad[-1] * 1e6)))
    return Table("Measured shafts: displacement and tilt",
                 ("T1 [N·m]", "T2 [N·m]", "shaft", "Y_max [µm]", "β paper 000 = arcsin(Y_max/L) [µrad]",
                  "true tilt: slope of the least-squares line [µrad]", "slope at start [µrad]",
                  "slope at end [µrad]"), tuple(rows),
                 note="β as paper 000 defines it is not a tilt: a symmetric bow with level ends has β > 0. "
                      "The true tilt is the slope of the least-squares line through u_y(x).")


# --------------------------------------------------------------------------------------------
# Couplings and bearings: misalignment against the allowable values


def verdict_of(ratio: float | None) -> str:
    """A verdict from value / allowable: ``no allowable given``, ``fine``, ``within allowable``, ``EXCEEDS``."""
    if ratio is None:
        return "no allowable given"
    if ratio <= 0.5:
        return "fine (≤ 50 % of allowable)"
    if ratio <= 1.0:
        return "within allowable"
    return "EXCEEDS allowable"


def _worst(values: np.ndarray) -> tuple[float, int]:
    index = int(np.argmax(values))
    return float(values[index]), index


def _coupling_table(sweep, measured: ConnectionStates, unloaded: ConnectionStates) -> Table:
    rows = []
    for c in sweep.rig.couplings:
        row = unloaded.index("coupling", c.name)
        offset = np.hypot(unloaded.deformation[:, row, 1], unloaded.deformation[:, row, 2]) * 1e6  # µm
        angle = np.hypot(unloaded.deformation[:, row, 4], unloaded.deformation[:, row, 5]) * 1e6  # µrad
        worst_offset, i = _worst(offset)
        worst_angle, j = _worst(angle)
        change = np.hypot(measured.deformation[:, row, 1], measured.deformation[:, row, 2]).max() * 1e6
        allow_offset = getattr(c, "allowable_parallel_offset_mm", None)
        allow_angle = getattr(c, "allowable_angular_misalignment_deg", None)
        ratios = []
        if allow_offset:
            ratios.append(worst_offset * 1e-3 / allow_offset)
        if allow_angle:
            ratios.append(math.degrees(worst_angle * 1e-6) / allow_angle)
        rows.append((c.name, _g(worst_offset), _g(change), _g(worst_angle), _g(worst_angle * 1e-6 * 100, 3),
                     _g(math.degrees(worst_angle * 1e-6), 3),
                     f"{allow_offset:g} mm" if allow_offset else "–", f"{allow_angle:g}°" if allow_angle else "–",
                     f"T2 = {sweep.cases[max(i, j, key=lambda k: offset[k] + angle[k])].case.output_torque_Nm:g}",
                     verdict_of(max(ratios) if ratios else None)))
    return Table("Couplings: misalignment between the hubs (worst case of the sweep, from the unloaded geometry)",
                 ("coupling", "parallel offset [µm]", "offset change under load [µm]", "angle [µrad]",
                  "angle [mm/100 mm]", "angle [°]", "allowable offset", "allowable angle", "worst case [N·m]", "verdict"),
                 tuple(rows), verdict_column=9,
                 note="Offset and angle of the to hub against the from hub at the coupling centre, installed "
                      "misalignment and self-weight included. Allowable values are the coupling maker's "
                      "(rig keys allowable_parallel_offset_mm, allowable_angular_misalignment_deg).")


def _bearing_table(sweep, measured: ConnectionStates, unloaded: ConnectionStates) -> Table:
    rows = []
    for b in sweep.rig.bearings:
        row = unloaded.index("bearing", b.name)
        total = np.hypot(unloaded.force_on_b[:, row, 1], unloaded.force_on_b[:, row, 2])
        change = np.hypot(measured.force_on_b[:, row, 1], measured.force_on_b[:, row, 2])
        tilt = np.hypot(unloaded.deformation[:, row, 4], unloaded.deformation[:, row, 5]) * 1e6
        worst_tilt, _ = _worst(tilt)
        allowable = getattr(b, "allowable_misalignment_arcmin", None)
        arcmin = math.degrees(worst_tilt * 1e-6) * 60
        rows.append((b.name, b.shaft, f"{b.x_mm:g}", _g(total.max(), 4), _g(change.max(), 4), _g(worst_tilt),
                     _g(arcmin, 3), f"{allowable:g}′" if allowable else "–",
                     verdict_of(arcmin / allowable if allowable else None)))
    return Table("Bearings: radial force and tilt of the inner ring against the outer (worst case of the sweep)",
                 ("bearing", "shaft", "x [mm]", "radial force, total [N]", "change under load [N]",
                  "tilt [µrad]", "tilt [′]", "allowable tilt", "verdict"), tuple(rows), verdict_column=8,
                 note="Total: from the unloaded geometry (self-weight included); change: since the rig at rest. "
                      "Allowable tilt: rig key allowable_misalignment_arcmin (deep-groove ball bearings: "
                      "2′ … 10′ in catalogues).")


def _life_text(value) -> str:
    if value is None:
        return "–"
    if not math.isfinite(value) or value > 1e9:
        return "> 1e9"
    return _g(value, 3)


def life_tables(sweep) -> list[Table]:
    """Bearing life, static safety and minimum load per case (every row names its case), the lives over the rig
    file's duty cycle, and each reducer against its rating table per case."""
    from rvcoax.results.engineering import case_name, duty_cycle_of_lives, sweep_lives, sweep_reducer_checks

    out = []
    balls = [b for b in sweep.rig.bearings if b.model == "ball"]
    if balls:
        from rvcoax.geometry.ball_model import clearance_range_um_of, operating_geometry

        rows = []
        for b in balls:
            low, high = clearance_range_um_of(sweep.rig, b)
            rows.append((b.name, b.designation or "explicit geometry", b.clearance_class or ("–" if b.clearance_um is not None else "CN"),
                         f"{b.shaft_fit or '–'} / {b.housing_fit or '–'}", f"{_g(low, 3)} … {_g(high, 3)}",
                         _g(operating_geometry(sweep.rig, b).clearance_m * 1e6, 3)))
        out.append(Table("Ball bearings: operating radial clearance (diametral)",
                         ("bearing", "designation", "class", "fits shaft / housing", "operating range [µm]",
                          "solved with [µm]"), tuple(rows),
                         note="The class's unmounted range (ISO 5753-1) less the rings' expansion by the fits' "
                              "interference (ISO 286, ISO 492, thick rings), tightest to loosest, plus the [thermal] "
                              "change; solved with the middle (fit_clearance = mean) unless chosen otherwise."))
    per_case = sweep_lives(sweep)
    rows = tuple((life.case, life.name, "–" if life.speed_rpm is None else f"{life.speed_rpm:g}",
                  _g(life.equivalent_load_N, 3), _life_text(life.L10_Mrev), _life_text(life.L10_h),
                  _life_text(life.L10r_h if life.speed_rpm else life.L10r_Mrev), _life_text(life.Lnm_h),
                  _life_text(life.static_safety), _g(life.minimum_load_N, 3), life.minimum_load_status)
                 for lives in per_case for life in lives)
    if rows:
        out.append(Table("Bearings: life, static safety and minimum load, per case",
                         ("case", "bearing", "speed [1/min]", "equivalent load P [N]", "L10 [10⁶ rev]", "L10 [h]",
                          "L10r [h, or 10⁶ rev without a speed]", "L_nm = a_ISO L [h]", "static safety s0",
                          "minimum load [N]", "minimum load"), rows, verdict_column=10,
                         note="L10: ISO 281 basic rating life from P = X F_r + Y F_a and the load rating C (rig key "
                              "dynamic_load_rating_kN, or ISO 281 from the internal geometry). L10r: ISO/TS 16281 "
                              "reference life from the ball loads (tilt, clearance and preload count); only for "
                              "bearings from internal geometry. L_nm: with viscosity_ratio and contamination_factor. "
                              "s0: C0/P0 (ISO 76), or (4200 MPa / p_max)³ from the ball loads. Minimum load: 0.01 C "
                              "(ball), 0.02 C (roller), the makers' rule, on P or, from the ball loads, on the load "
                              "that gives L10r (a preload counts)."))
    duty = duty_cycle_of_lives(sweep.rig, per_case)
    if duty:
        out.append(Table(f"Bearings: life over the duty cycle ({duty[0].shares} shares of the rig file's load cases)",
                         ("bearing", "L10 [h]", "L10 [10⁶ rev]", "L_nm [h]", "smallest s0", "cases below minimum load"),
                         tuple((d.name, _life_text(d.L10_h), _life_text(d.L10_Mrev), _life_text(d.Lnm_h),
                                _life_text(d.min_static_safety), ", ".join(d.cases_below_minimum_load) or "none")
                               for d in duty),
                         note="Palmgren–Miner: L = 1 / Σ (share_k / L_k) over the cases; a case at standstill adds no "
                              "damage."))
    checks = [(c.case, r) for c, case_checks in zip(sweep.cases, sweep_reducer_checks(sweep)) for r in case_checks]
    if checks:
        out.append(Table("Reducers against the maker's rating table, per case",
                         ("case", "reducer", "torque [N·m]", "of rated", "of peak", "of momentary", "moment on the "
                          "main bearings [N·m]", "of allowable moment", "axial force [N]", "of max. axial", "verdict"),
                         tuple((case_name(sweep.rig, case.input_torque_Nm, case.output_torque_Nm),
                                f"{r.name} ({r.designation})", _g(r.torque_Nm), f"{r.torque_rated_percent:.3g} %",
                                f"{r.torque_peak_percent:.3g} %", f"{r.torque_momentary_percent:.3g} %",
                                _g(r.moment_Nm, 3), f"{r.moment_use_percent:.3g} %", _g(r.axial_force_N, 3),
                                f"{r.axial_use_percent:.3g} %", r.verdict) for case, r in checks),
                         verdict_column=10,
                         note="Rated, peak (allowable acceleration/deceleration) and momentary maximum torque, "
                              "allowable moment and maximum axial load from the reducer's rating table "
                              "(geometry/data/rv_reducers.csv, tagged values); the moment is the one the model's "
                              "reducer joint carries at the main bearings' centre."))
    return out


def gear_mesh_tables(sweep) -> list[Table]:
    """Each planet mesh's misalignment in gear terms (f_Σβ, f_Σδ over the face width), per case."""
    rows = []
    for c in sweep.cases:
        if c.engineering is None:
            continue
        for g in c.engineering.gear_meshes:
            rows.append((f"T1 = {c.case.input_torque_Nm:g}, T2 = {c.case.output_torque_Nm:g}", g.name,
                         f"{g.planet} ({g.planet_angle_deg:g}°)", _g(g.face_width_mm, 3), _g(g.relative_tilt_urad, 3),
                         _g(g.f_sigma_beta_um, 3), _g(g.f_sigma_delta_um, 3)))
    if not rows:
        return []
    return [Table("Gear meshes: misalignment over the face width, per case",
                  ("case [N·m]", "gear mesh", "planet", "face width b [mm]", "relative tilt [µrad]",
                   "f_Σβ in the plane of action [µm]", "f_Σδ normal to it [µm]"), tuple(rows),
                  note="From the section rotations of the gear and its mate's carrier at the mesh (read like Y: "
                       "since the aligned rest state by default); f_Σβ is the deformation part of the mesh "
                       "misalignment ISO 6336-1's K_Hβ takes. A member modelled as a solid is left out.")]


def misalignment_tables(sweep) -> list[Table]:
    """The coupling and bearing tables with verdicts (one function, so that the source can be swapped)."""
    measured, unloaded = connection_states(sweep, "measured"), connection_states(sweep, "unloaded")
    tables = []
    if sweep.rig.couplings:
        tables.append(_coupling_table(sweep, measured, unloaded))
    if sweep.rig.bearings:
        tables.append(_bearing_table(sweep, measured, unloaded))
    return tables


def reaction_table(sweep) -> Table:
    """Every spring to the ground (mounts, grounded bearings): the force it exerts on the rig, per case,
    its total and change under load, and the equilibrium residual of each case."""
    measured, unloaded = connection_states(sweep, "measured"), connection_states(sweep, "unloaded")
    grounded = [("mount", m.name) for m in sweep.rig.mounts]
    grounded += [("bearing", b.name) for b in sweep.rig.bearings if b.housing == "ground"]
    last = max(range(len(sweep.cases)), key=lambda i: (abs(sweep.cases[i].case.output_torque_Nm),
                                                       abs(sweep.cases[i].case.input_torque_Nm)))
    rows = []
    for kind, name in grounded:
        row = unloaded.index(kind, name)
        f_total, f_change = unloaded.force_on_b[last, row], measured.force_on_b[last, row]
        rows.append((f"{kind} {name}", _g(f_total[1], 4), _g(f_total[2], 4), _g(f_change[1], 4),
                     _g(f_change[2], 4), _g(f_total[3], 4)))
    if grounded:
        rows_total = np.sum([unloaded.force_on_b[last, unloaded.index(k, n)] for k, n in grounded], axis=0)
        rows.append(("sum", _g(rows_total[1], 4), _g(rows_total[2], 4), "", "", _g(rows_total[3], 4)))
    case = sweep.cases[last].case
    residual = max(c.equilibrium_error for c in sweep.cases)
    return Table(f"Support reactions on the rig (case T1 = {case.input_torque_Nm:g} N·m, "
                 f"T2 = {case.output_torque_Nm:g} N·m)",
                 ("support", "F_y total [N]", "F_z total [N]", "F_y change under load [N]",
                  "F_z change under load [N]", "torque about x [N·m]"), tuple(rows),
                 note="Total: from the unloaded geometry (self-weight included, so ΣF_y is the rig's weight); "
                      "change: since the rig at rest. Equilibrium residual (resultant of the ground reactions "
                      f"against the applied loads, relative), largest over the {len(sweep.cases)} cases: "
                      f"{residual:.1e}.")


def check_table(measured, sweep) -> Table:
    """Measured data (table or paths schema) against the model, row by row (µm)."""
    from rvcoax.results.studies.discrepancy.measured import check_stations

    lengths = {s: getattr(sweep.rig.paths, s).length_mm for s in MEASURED_SHAFTS}
    check_stations(measured, lengths)
    rows, gaps = [], []
    for k in range(measured.n):
        case_index = int(measured.case_index[k])
        case = sweep.cases[case_index]
        shaft = str(measured.shaft[k])
        path = case.paths[shaft]
        if measured.schema == "table":
            model = path.y_max_mm
            where = "Y_max"
        else:
            model = float(np.interp(measured.x_mm[k], path.station_mm, path.uy_mm))
            where = f"x = {measured.x_mm[k]:g} mm"
        value = float(measured.value_mm[k])
        gaps.append(model - value)
        rows.append((f"{case.case.input_torque_Nm:g}", f"{case.case.output_torque_Nm:g}", shaft, where,
                     _g(value * 1e3), _g(model * 1e3), _g((model - value) * 1e3),
                     f"{100 * (model - value) / value:+.1f} %" if value else "–"))
    rms = float(np.sqrt(np.mean(np.square(gaps)))) * 1e3 if gaps else float("nan")
    return Table(f"Model against the measured data {measured.source} ({measured.schema} schema)",
                 ("T1 [N·m]", "T2 [N·m]", "shaft", "where", "measured [µm]", "model [µm]", "model − measured [µm]",
                  "relative"), tuple(rows), note=f"RMS of model − measured: {_g(rms, 3)} µm over {len(rows)} values.")
