"""Turning sweeps, checks and calibrations into rows, JSON documents and terminal tables."""

from __future__ import annotations

import hashlib
from importlib.metadata import PackageNotFoundError, version

import numpy as np

from geometry.loads import UNIT_LOADS
from results.calibration import Calibration
from results.check import QUANTITIES, Comparison
from results.sweep import SHAFTS, Sweep

UNITS = {
    "torque": "N·m", "length": "mm", "Y": "mm (vertical displacement, +Y up)", "beta": "degree",
    "tilt": "degree", "rotation": "degree",
}


def rvcoax_version() -> str:
    try:
        return version("rvcoax")
    except PackageNotFoundError:
        return "unknown (not installed)"


def text_sha256(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def sweep_rows(sweep: Sweep) -> list[dict]:
    """One row per case: the columns of ``sweep.csv``."""
    rows = []
    for case in sweep.cases:
        row = {"T1_input_Nm": case.case.input_torque_Nm, "T2_output_Nm": case.case.output_torque_Nm}
        for shaft in SHAFTS:
            row[f"Y_{shaft}_mm"] = case.paths[shaft].y_max_mm
        for shaft in SHAFTS:
            row[f"beta_{shaft}_deg"] = case.paths[shaft].beta_deg
        for shaft in SHAFTS:
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
        rows.append(row)
    return rows


def path_rows(sweep: Sweep) -> list[dict]:
    """Long table of the signed Y paths: one row per case, shaft and station."""
    rows = []
    for case in sweep.cases:
        for shaft in SHAFTS:
            path = case.paths[shaft]
            for station, uy in zip(path.station_mm, path.uy_mm):
                rows.append({"T1_input_Nm": case.case.input_torque_Nm, "T2_output_Nm": case.case.output_torque_Nm,
                             "shaft": shaft, "station_mm": float(station), "uy_mm": float(uy)})
    return rows


def calibration_document(calibration: Calibration) -> dict:
    def entry(p):
        return {"address": p.parameter.address, "shaft": p.parameter.shaft, "unit": p.parameter.unit,
                "reference_value": p.reference_value, "fitted_value": p.fitted_value,
                "plausible_range": list(p.parameter.plausible), "plausible": p.plausible,
                "meaning": p.parameter.meaning}

    return {
        "fit_rows_index": list(calibration.fit_rows),
        "fit_relative_residual": calibration.fit_relative_residual,
        "parameters": [entry(p) for p in calibration.parameters],
        "other_exact_solutions": [[entry(p) for p in alt] for alt in calibration.alternatives],
    }


def sweep_document(sweep: Sweep, rig_source: str, rig_text: str, calibration: Calibration | None = None) -> dict:
    """The JSON document of a sweep: units, provenance, method and every case with its paths."""
    cases = []
    for case in sweep.cases:
        entry = {"T1_input_Nm": case.case.input_torque_Nm, "T2_output_Nm": case.case.output_torque_Nm}
        for shaft in SHAFTS:
            path = case.paths[shaft]
            entry[shaft] = {
                "Y_max_mm": path.y_max_mm, "Y_max_signed_mm": path.y_max_signed_mm,
                "station_of_max_mm": path.station_of_max_mm, "beta_deg": path.beta_deg,
                "fitted_tilt_deg": path.fitted_tilt_deg, "end_rotations_deg": list(path.end_rotations_deg),
                "Y_max_from_unloaded_geometry_mm": case.absolute_paths[shaft].y_max_mm,
                "path": {"station_mm": path.station_mm.tolist(), "uy_mm": path.uy_mm.tolist()},
            }
        entry["equilibrium_relative_error"] = case.equilibrium_error
        entry["solve_relative_residual"] = case.residual
        cases.append(entry)
    return {
        "rvcoax_version": rvcoax_version(),
        "units": UNITS,
        "rig": {"name": sweep.rig.rig.name, "source": rig_source, "sha256": text_sha256(rig_text),
                "measured_from": sweep.rig.paths.measured_from,
                "path_lengths_mm": {s: getattr(sweep.rig.paths, s).length_mm for s in SHAFTS}},
        "model": {"kind": sweep.settings.model, "dofs": sweep.n_dofs, "solver": sweep.solver,
                  "method": sweep.settings.method,
                  "superposition": "u = u_rest + sign(T1) u_engaged_T1 + sign(T2) u_engaged_T2 + T1 u_T1 + T2 u_T2",
                  "unit_loads": list(UNIT_LOADS)},
        "beta_definition": "beta = arcsin(Y_max / L) (paper 000); fitted_tilt = slope of the least-squares line through u_y(x)",
        "calibration": calibration_document(calibration) if calibration is not None else None,
        "cases": cases,
    }


def check_rows(comparison_blind: Comparison, comparison_calibrated: Comparison, rows, fit_rows) -> list[dict]:
    """The columns of ``check.csv``: published, blind and calibrated values and errors per row."""
    out = []
    for i, row in enumerate(rows):
        entry = {"T1_input_Nm": row.case.input_torque_Nm, "T2_output_Nm": row.case.output_torque_Nm,
                 "used_for_fit": i in fit_rows}
        for q in QUANTITIES:
            entry[f"published_{q}"] = float(comparison_blind.published[q][i])
            for label, comp in (("blind", comparison_blind), ("calibrated", comparison_calibrated)):
                entry[f"{label}_{q}"] = float(comp.model[q][i])
                entry[f"{label}_abs_error_{q}"] = float(comp.absolute_error[q][i])
                entry[f"{label}_rel_error_{q}"] = float(comp.relative_error[q][i])
            entry[f"calibrated_within_tolerance_{q}"] = bool(comparison_calibrated.within[q][i])
        out.append(entry)
    return out


def held_out_mask(n_rows: int, fit_rows) -> np.ndarray:
    mask = np.ones(n_rows, dtype=bool)
    mask[list(fit_rows)] = False
    return mask
