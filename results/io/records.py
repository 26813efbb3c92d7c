"""Turning sweeps into rows and JSON documents.

A study that changed the rig a sweep solved (a calibration) records itself in the sweep's JSON through its
own ``document()`` (:class:`StudyRecord`); the files of a study are written on the floors above
(:mod:`rvcoax.results.reports`).
"""

from __future__ import annotations

import hashlib
import json
from importlib.metadata import PackageNotFoundError, version
from typing import Protocol

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model.loads import UNIT_LOADS
from rvcoax.results.engineering import (
    ALIGNMENT_TOLERANCE_SOURCE,
    life_columns,
    life_entries,
    reducer_columns,
    reducer_entries,
    shaft_quantities,
)
from rvcoax.results.sweep import CaseResult, Sweep

__all__ = ["ENGINEERING_DEFINITIONS", "StudyRecord", "UNITS", "canonical", "case_entry", "case_record", "case_row",
           "entry_path_rows", "model_section", "rvcoax_version", "sweep_header", "sweep_rows", "text_sha256"]

UNITS = {
    "torque": "N·m", "length": "mm", "Y": "mm (vertical displacement, +Y up)", "beta": "degree",
    "tilt": "degree", "rotation": "degree",
    # issue 15: keys ending in _um, _urad, _N, _Nm, _mm_per_100mm, _arcmin, _percent carry that unit
    "keys_ending_in": {"_mm": "mm", "_um": "µm", "_deg": "degree", "_urad": "µrad", "_arcmin": "arcminute",
                       "_mm_per_100mm": "mm per 100 mm (angularity: gap difference over 100 mm of coupling diameter)",
                       "_N": "N", "_Nm": "N·m", "_rpm": "rev/min", "_percent": "% of the allowable value",
                       "_MPa": "MPa (N/mm²)", "_safety": "dimensionless safety factor (DIN 743)"},
}


ENGINEERING_DEFINITIONS = {
    "shafts": "beta_paper: paper 000's beta = arcsin(Y_max / L), not a tilt; tilt: slope of the least-squares line "
              "through u_y(x), the shaft's true tilt; end_slopes: cross-section rotation about z at the path's ends; "
              "end_offsets: u_y at the path's ends (all from the measured_from state)",
    "couplings": "offset_um / angle_urad / angularity_mm_per_100mm: parallel offset and angular misalignment of the "
                 "to-hub against the from-hub at the coupling centre, from the measured_from state (a rig is aligned "
                 "at rest: the change under load), with the installed misalignment the rig file declares "
                 "(parallel_offset_um, angular_misalignment_mrad); offset_from_unloaded_um / angle_from_unloaded_urad: "
                 "the same misalignment from the unloaded geometry (self-weight included), a different quantity; "
                 "use_percent: offset_um and angle of the datasheet allowable (allowable_parallel_offset_mm, "
                 "allowable_angular_misalignment_deg); grade: excellent / acceptable / out of tolerance against the "
                 "alignment tolerance for speed_rpm",
    "alignment_tolerances": ALIGNMENT_TOLERANCE_SOURCE,
    "bearings": "force the bearing exerts on its shaft (force_radial_N: total from the unloaded geometry, self-weight "
                "included; force_radial_change_N: since the rest state) and tilt of the inner ring against the outer "
                "(total and change), against allowable_misalignment_arcmin; model: linear, clearance, or the model from "
                "geometry (ball, angular_contact, cylindrical_roller, tapered_roller); "
                "radial/axial/tilt_stiffness: the operating stiffness in the case (a linear bearing's typed-in spring, "
                "the tangent of a clearance's or a bearing from geometry's force law; radial: mean of y and z); "
                "loaded_elements, max_element_load_N: a bearing from geometry's balls or rollers in contact and its "
                "largest rolling-element load",
    "reactions": "force and moment (about the support point; a housing: the centre of its attachments) each mount, "
                 "each bearing housed in ground and each condensed housing as a whole (kind) exerts on the rig, total "
                 "(self-weight included) and change under load; components below 1e-9 of the case's largest support "
                 "force are rounding and written as 0",
    "applied": "applied_force_N: resultant of every load on the rig (weight and applied forces), which the reactions' "
               "forces sum to minus; applied_torque_x_Nm: the applied loads' moment about the rig axis",
    "equilibrium_residual": "|applied loads + ground reactions| of the total state, force and moment about the origin",
    "shaft_strength": "shafts: per beam shaft the largest von Mises stress (outer fibre: |σ_ax| + σ_b with τ_t; neutral "
                      "axis: σ_ax with τ_t + τ_q) and where, and the largest bending, torsional, transverse-shear and "
                      "axial stress along it, from the section forces of the total state (self-weight included); "
                      "notches: DIN 743 at each [[parts.notches]] entry, the shaft rotating (bending fully reversed: "
                      "amplitude M/W_b; torque and axial force steady: means), static proof at the case's loads × "
                      "[shaft_strength] peak_load_factor; fatigue_safety / static_safety null: no amplitude (infinite); "
                      "the spectrum's safety is the smallest over the cases (no damage accumulation)",
    "torque_paths": "per shaft line that a torque acts on (line: the torques on it): applied_Nm = Σ sign × T about +x; "
                    "exits: every spring with torsional stiffness from the line to another part or the ground, with "
                    "the torque it carries out of the line (N·m, in the sense of the applied torque) and its share of "
                    "it (%); reaction: the exit meant to take the torque (reaction_rule: reaction_spring, reducer or far "
                    "end); carried_Nm: the torque that reaches it, which the line's couplings and sensors carry",
    "torque_ratings": "per coupling and shaft with rated_torque_Nm in the rig file (kind coupling or shaft): torque_Nm = "
                      "|torque| it carries (a coupling: through its spring; a shaft: the largest torque entering or "
                      "leaving it through one torsional spring or applied to it), rated_use_percent and "
                      "peak_use_percent (null without peak_torque_Nm) of the datasheet values, and the verdict",
}


class StudyRecord(Protocol):
    """A study recorded in a sweep's JSON header (:meth:`rvcoax.results.studies.calibration.Calibration.document`)."""

    def document(self) -> dict:
        """The study as a JSON-ready dict."""
        ...


def rvcoax_version() -> str:
    """The installed rvcoax version, as result files record it (``unknown (not installed)`` from a bare copy).

    Returns
    -------
    str
        The version string.
    """
    try:
        return version("rvcoax")
    except PackageNotFoundError:
        return "unknown (not installed)"


def text_sha256(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def case_row(case: CaseResult) -> dict:
    """The row of ``sweep.csv`` of one case."""
    row = {"T1_input_Nm": case.case.input_torque_Nm, "T2_output_Nm": case.case.output_torque_Nm}
    for shaft in MEASURED_SHAFTS:
        row[f"Y_{shaft}_mm"] = case.paths[shaft].y_max_mm
    for shaft in MEASURED_SHAFTS:
        row[f"beta_{shaft}_deg"] = case.paths[shaft].beta_deg
    for shaft in MEASURED_SHAFTS:
        path = case.paths[shaft]
        start, end = path.end_rotations_deg
        row[f"Y_{shaft}_signed_mm"] = path.y_max_signed_mm
        row[f"station_of_max_{shaft}_mm"] = path.station_of_max_mm
        row[f"fitted_tilt_{shaft}_deg"] = path.fitted_tilt_deg
        row[f"end_rotation_{shaft}_start_deg"] = start
        row[f"end_rotation_{shaft}_end_deg"] = end
        row[f"Y_{shaft}_unloaded_ref_mm"] = case.absolute_paths[shaft].y_max_mm
    row["equilibrium_relative_error"] = case.equilibrium_error
    row["solve_relative_residual"] = case.residual
    # issue 15: the quantities rig engineers read, after the columns above (which keep their order)
    for shaft in MEASURED_SHAFTS:
        row.update({f"{key}_{shaft}{unit}": value for key, unit, value in _shaft_columns(case.paths[shaft])})
    if case.engineering is not None:
        row.update(case.engineering.row())
    row.update(life_columns(getattr(case, "ball_lives", ())))
    row.update(reducer_columns(getattr(case, "reducer_checks", ())))
    if getattr(case, "shaft_strength", None) is not None:
        row.update(case.shaft_strength.row())
    if getattr(case, "torque_paths", None) is not None:
        row.update(case.torque_paths.row())
    return row


def _shaft_columns(path) -> list[tuple[str, str, float]]:
    start_slope, end_slope = path.end_slopes_urad
    start_offset, end_offset = path.end_offsets_um
    return [("Y", "_um", path.y_max_mm * 1e3), ("beta_paper", "_urad", path.beta_urad),
            ("tilt", "_urad", path.fitted_tilt_urad), ("end_slope_start", "_urad", start_slope),
            ("end_slope_end", "_urad", end_slope), ("offset_start", "_um", start_offset),
            ("offset_end", "_um", end_offset)]


def entry_path_rows(entry: dict) -> list[dict]:
    """The rows of ``sweep_paths.csv`` of one case (one per shaft and station), from its :func:`case_entry`: the
    signed Y and the section rotation about z (the slope of the bending line, µrad; a record written before it
    was kept has none)."""
    rows = []
    for shaft in MEASURED_SHAFTS:
        path = entry[shaft]["path"]
        rotations = path.get("rotation_z_urad")
        for k, (station, uy) in enumerate(zip(path["station_mm"], path["uy_mm"])):
            row = {"T1_input_Nm": entry["T1_input_Nm"], "T2_output_Nm": entry["T2_output_Nm"], "shaft": shaft,
                   "station_mm": float(station), "uy_mm": float(uy)}
            if rotations is not None:
                row["rotation_z_urad"] = float(rotations[k])
            rows.append(row)
    return rows


def case_entry(case: CaseResult) -> dict:
    """The entry of one case in ``sweep.json``'s ``cases``."""
    entry = {"T1_input_Nm": case.case.input_torque_Nm, "T2_output_Nm": case.case.output_torque_Nm}
    for shaft in MEASURED_SHAFTS:
        path = case.paths[shaft]
        entry[shaft] = {
            "Y_max_mm": path.y_max_mm, "Y_max_signed_mm": path.y_max_signed_mm,
            "station_of_max_mm": path.station_of_max_mm, "beta_deg": path.beta_deg,
            "fitted_tilt_deg": path.fitted_tilt_deg, "end_rotations_deg": list(path.end_rotations_deg),
            "Y_max_from_unloaded_geometry_mm": case.absolute_paths[shaft].y_max_mm,
            "path": {"station_mm": path.station_mm.tolist(), "uy_mm": path.uy_mm.tolist(),
                     "rotation_z_urad": (np.asarray(path.rotation_z_rad) * 1e6).tolist()},
        }
    entry["equilibrium_relative_error"] = case.equilibrium_error
    entry["solve_relative_residual"] = case.residual
    entry["engineering"] = {"shafts": {s: shaft_quantities(case.paths[s]) for s in MEASURED_SHAFTS},
                            **(case.engineering.entry() if case.engineering is not None else {})}
    if getattr(case, "ball_lives", ()):
        entry["engineering"]["bearing_lives"] = (entry["engineering"].get("bearing_lives", [])
                                                 + life_entries(case.ball_lives))
    if getattr(case, "reducer_checks", ()):
        entry["engineering"]["reducers"] = reducer_entries(case.reducer_checks)
    if getattr(case, "shaft_strength", None) is not None:
        entry["engineering"]["shaft_strength"] = case.shaft_strength.entry()
    if getattr(case, "torque_paths", None) is not None:
        entry["engineering"]["torque_paths"] = case.torque_paths.entry()
        if case.torque_paths.ratings:
            entry["engineering"]["torque_ratings"] = case.torque_paths.rating_entries()
    return entry


def case_record(case: CaseResult) -> dict:
    """Everything the result files hold about one case, as plain JSON data (see :func:`canonical`): its ``row``
    of ``sweep.csv``, its ``entry`` of ``sweep.json``'s cases and, in a nonlinear sweep with bearings from
    geometry, their ``bearing_operating_points`` (bearing → point), from which a resumed sweep lists every
    case's operating points in ``model`` (:func:`rvcoax.results.io.durable_sweep.run_durable_sweep`)."""
    record = {"row": case_row(case), "entry": case_entry(case)}
    if getattr(case, "operating_points", None):
        record["bearing_operating_points"] = case.operating_points
    return canonical(record)


def canonical(data):
    """``data`` as it reads back from JSON (numpy scalars become floats, tuples lists).

    Result files are always written from canonical data, so a case solved now and a case read
    back from an earlier, interrupted run give the same bytes.
    """
    return json.loads(json.dumps(data, default=float, allow_nan=True))


def sweep_rows(sweep: Sweep) -> list[dict]:
    """One row per case: the columns of ``sweep.csv``."""
    return [case_row(case) for case in sweep.cases]


def model_section(sweep: Sweep) -> dict:
    """How the sweep was solved: fidelity, DOFs, solver (requested and used), condition number, mesh.

    No wall-clock time or memory: the same inputs give the same section, byte for byte.
    """
    settings = sweep.settings
    kappa = sweep.solver_report.get("condition_estimate")
    section = {"kind": settings.model, "dofs": sweep.n_dofs, "solver": sweep.solver,
               "solver_requested": settings.solver, "method": settings.method,
               "condition_number_estimate": None if kappa is None else float(f"{kappa:.3g}")}
    if "nonlinear" in sweep.solver_report:  # clearance: every case solved on its own, nothing superposed
        section["method"] = "direct (nonlinear: each case solved by Newton iteration)"
    else:
        section["superposition"] = "u = u_rest + sign(T1) u_engaged_T1 + sign(T2) u_engaged_T2 + T1 u_T1 + T2 u_T2"
        section["unit_loads"] = list(UNIT_LOADS)
    section["beam_max_element_length_mm"] = sweep.rig.mesh.max_element_length_mm
    if settings.model != "beam":
        section["mesh_size_mm"] = settings.mesh_size_mm if settings.mesh_size_mm is not None \
            else sweep.rig.solid.mesh_size_mm
        solids = sweep.system.solids if sweep.system is not None else ()
        section["solid_parts"] = {
            part.name: {"mesh_size_mm": part.geometry.mesh_size_mm, "nodes": int(part.mesh.doflocs.shape[1]),
                        "elements": int(part.mesh.t.shape[1]), "dofs": part.n_dofs}
            for part in solids}
    for key in ("nonlinear", "gapped_bearings", "newton_iterations_max", "ball_bearings",
                "ball_bearing_operating_points", "rolling_bearings", "rolling_bearing_operating_points"):
        if key in sweep.solver_report:
            section[key] = sweep.solver_report[key]
    return canonical(section)


def sweep_header(rig, model: dict, rig_source: str, rig_text: str, calibration: StudyRecord | None = None) -> dict:
    """``sweep.json`` without its cases: units, provenance (version, rig and its SHA-256), ``model``.

    Parameters
    ----------
    rig : Rig
        The rig solved.
    model : dict
        The ``model`` section (model kind, mesh, solver, DOFs, residual summary).
    rig_source, rig_text : str
        The rig file as the user named it, and its text.
    calibration : Calibration, optional
        Recorded (its ``document()``) when the sweep is of a calibrated rig.

    Returns
    -------
    dict
        The JSON header, in the order it is written.
    """
    return canonical({
        "rvcoax_version": rvcoax_version(),
        "units": UNITS,
        "rig": {"name": rig.rig.name, "source": rig_source, "sha256": text_sha256(rig_text),
                "measured_from": rig.paths.measured_from,
                "path_lengths_mm": {s: getattr(rig.paths, s).length_mm for s in MEASURED_SHAFTS}},
        "model": model,
        "beta_definition": "beta = arcsin(Y_max / L) (paper 000); fitted_tilt = slope of the least-squares line through u_y(x)",
        "engineering_definitions": ENGINEERING_DEFINITIONS,
        "calibration": calibration.document() if calibration is not None else None,
    })
