"""Inputs for dynamics models, per load case: tilt β, radial displacement a, lever arms, couplings, bearings.

Paper 000 feeds the static tilts into a transmission-chain error model of the reducer (and into
ADAMS). For a shaft of n stages with radial tilt β and radial displacement a, stage k enters that
model through the coaxiality lever arm

    r_k = tan β · ((l_k + l_{k−1}) / 2 + a / cos β) + d_k / 2,    l_0 = 0,

with l_k the length and d_k the outer diameter of stage k (all in mm here; the paper writes d in m,
which would not be consistent with l and a in mm). A *stage* is a run of the shaft with one
cross-section: adjacent segments of the rig file with the same outer and inner diameter form one
stage (the reference input shaft is the paper's four-stage hollow shaft). Stage 1 is at the reducer,
the shaft's end facing the other measured shaft, as in paper 000's ADAMS model, where the input
shaft's first stage carries the sun-gear contact and its second stage has none.

β is paper 000's tilt, arcsin(Y_max / L), read like ``sweep.csv``'s (from the rig's
``measured_from`` state); a defaults to the IT3 values of paper 000 [P]: 0.002 mm (input shaft)
and 0.003 mm (output shaft).

Couplings and bearings are reported from :mod:`rvcoax.results.connections` in both references: measured
(the same state as Y and β) and ``*_unloaded_ref`` (from the unloaded geometry: for forces, the total
force including self-weight and any installed misalignment).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model.beam import stress_free_motions
from rvcoax.geometry.model.springs import ConnectionStates
from rvcoax.geometry.schema import Rig
from rvcoax.results.connections import connection_states
from rvcoax.results.io.records import rvcoax_version, text_sha256
from rvcoax.results.io.writers import read_csv_cell, write_csv_atomic, write_json_atomic
from rvcoax.results.sweep import Sweep

__all__ = ["CSV_TABLES", "DynamicsExport", "IT3_RADIAL_DISPLACEMENT_MM", "ShaftStage", "UNITS", "UNLOADED",
           "bearing_rows", "coupling_rows", "dynamics_export", "export_document", "export_tables", "lever_arms_mm",
           "read_csv_table", "reducer_end_mm", "shaft_rows", "shaft_stages", "stage_rows", "tilt_direction",
           "write_dynamics_csv", "write_dynamics_json"]

IT3_RADIAL_DISPLACEMENT_MM = {"input": 0.002, "output": 0.003}
"""Paper 000's radial displacement a of each shaft [P] (IT3, GB/T 1800.1-2009, sizes ≤ 500 mm)."""

UNITS = {
    "torque": "N·m", "length": "mm", "Y": "mm (vertical, +Y up)", "beta, angles": "degree",
    "offsets": "µm", "forces": "N", "moments": "N·m", "lever_arm": "mm",
    "stiffness": "N/µm (translations), N·m/rad (tilts)",
}
CSV_TABLES = ("shafts", "stages", "couplings", "bearings")
UNLOADED = "_unloaded_ref"


@dataclass(frozen=True)
class ShaftStage:
    """One stage of a stepped shaft (lengths and diameters in mm); ``number`` 1 is at the reducer."""

    number: int
    x_from_mm: float
    x_to_mm: float
    outer_diameter_mm: float
    inner_diameter_mm: float

    @property
    def length_mm(self) -> float:
        return self.x_to_mm - self.x_from_mm


def reducer_end_mm(rig: Rig, which: str) -> float:
    """x of the measured shaft's end facing the other measured shaft (the reducer sits between them)."""
    part = rig.part(getattr(rig.paths, which).part)
    other = rig.part(getattr(rig.paths, "output" if which == "input" else "input").part)
    lo, hi = part.x_range_mm
    centre = 0.5 * sum(other.x_range_mm)
    return lo if abs(lo - centre) < abs(hi - centre) else hi


def shaft_stages(rig: Rig, which: str) -> tuple[ShaftStage, ...]:
    """Stages of the measured shaft ``which`` (``input``/``output``), numbered from the reducer end."""
    part = rig.part(getattr(rig.paths, which).part)
    runs: list[list[float]] = []  # [x_from, x_to, outer, inner]
    for s in sorted(part.segments, key=lambda s: s.x_mm[0]):
        section = (s.outer_diameter_mm, s.inner_diameter_mm)
        if runs and tuple(runs[-1][2:]) == section and math.isclose(runs[-1][1], s.x_mm[0], abs_tol=1e-9):
            runs[-1][1] = s.x_mm[1]
        else:
            runs.append([s.x_mm[0], s.x_mm[1], *section])
    if reducer_end_mm(rig, which) != part.x_range_mm[0]:
        runs.reverse()
    return tuple(ShaftStage(i + 1, *run) for i, run in enumerate(runs))


def lever_arms_mm(beta_deg: float, radial_mm: float, lengths_mm, outer_diameters_mm) -> tuple[np.ndarray, np.ndarray]:
    """Paper 000's coaxiality lever arm of every stage, and its tilt term, in mm.

    ``tilt_k = tan β · ((l_k + l_{k−1}) / 2 + a / cos β)`` with ``l_0 = 0``; ``r_k = tilt_k + d_k / 2``.
    """
    lengths = np.asarray(lengths_mm, dtype=float)
    previous = np.concatenate([[0.0], lengths[:-1]])
    beta = math.radians(beta_deg)
    tilt = math.tan(beta) * (0.5 * (lengths + previous) + radial_mm / math.cos(beta))
    return tilt + 0.5 * np.asarray(outer_diameters_mm, dtype=float), tilt


@dataclass(frozen=True, eq=False)
class DynamicsExport:
    """A sweep with what the dynamics export adds: a per shaft, stages, spring states in both references."""

    sweep: Sweep
    radial_mm: dict[str, float]
    stages: dict[str, tuple[ShaftStage, ...]]
    measured: ConnectionStates
    unloaded: ConnectionStates

    @property
    def measured_from(self) -> str:
        return self.sweep.rig.paths.measured_from


def dynamics_export(sweep: Sweep, radial_mm: dict[str, float] | None = None) -> DynamicsExport:
    """Collect the dynamics inputs of every case of ``sweep``; ``radial_mm`` overrides a per shaft.

    Parameters
    ----------
    sweep : Sweep
        A solved sweep.
    radial_mm : dict, optional
        ``{"input": a, "output": a}`` in mm; default paper 000's IT3 values.

    Returns
    -------
    DynamicsExport
        Per case and measured shaft: tilt β, radial displacement a and lever arms; per coupling its
        misalignment; per bearing its reaction.

    Raises
    ------
    ConnectionsUnavailableError
        The sweep holds no displacements of its springs (a solid model).
    """
    radial = dict(IT3_RADIAL_DISPLACEMENT_MM)
    radial.update(radial_mm or {})
    for shaft, value in radial.items():
        if not (math.isfinite(value) and value >= 0.0):
            raise ValueError(f"radial displacement a of the {shaft} shaft must be a number ≥ 0 mm, got {value}")
    stages = {shaft: shaft_stages(sweep.rig, shaft) for shaft in MEASURED_SHAFTS}
    return DynamicsExport(sweep, radial, stages, connection_states(sweep, "measured"),
                          connection_states(sweep, "unloaded"))


def _torques(case) -> dict:
    return {"T1_input_Nm": case.case.input_torque_Nm, "T2_output_Nm": case.case.output_torque_Nm}


def tilt_direction(path) -> int:
    """+1 when the shaft's least-squares line rises along +x, −1 when it falls (0: no tilt)."""
    return int(np.sign(path.fitted_tilt_deg))


def shaft_rows(export: DynamicsExport) -> list[dict]:
    """One row per case and measured shaft: Y, β (both references), a."""
    rows = []
    for case in export.sweep.cases:
        for shaft in MEASURED_SHAFTS:
            path, absolute = case.paths[shaft], case.absolute_paths[shaft]
            rows.append({**_torques(case), "shaft": shaft, "part": getattr(export.sweep.rig.paths, shaft).part,
                         "measured_from": export.measured_from, "L_mm": path.length_mm,
                         "Y_max_mm": path.y_max_mm, "Y_signed_mm": path.y_max_signed_mm,
                         "station_of_max_mm": path.station_of_max_mm, "beta_deg": path.beta_deg,
                         "tilt_direction": tilt_direction(path), "fitted_tilt_deg": path.fitted_tilt_deg,
                         "radial_displacement_a_mm": export.radial_mm[shaft],
                         f"Y_max{UNLOADED}_mm": absolute.y_max_mm, f"beta{UNLOADED}_deg": absolute.beta_deg})
    return rows


def stage_rows(export: DynamicsExport) -> list[dict]:
    """One row per case, shaft and stage: l_k, d_k and the lever arm r_k of paper 000."""
    rows = []
    for case in export.sweep.cases:
        for shaft in MEASURED_SHAFTS:
            stages = export.stages[shaft]
            beta = case.paths[shaft].beta_deg
            arms, tilts = lever_arms_mm(beta, export.radial_mm[shaft], [s.length_mm for s in stages],
                                        [s.outer_diameter_mm for s in stages])
            for stage, arm, tilt in zip(stages, arms, tilts):
                rows.append({**_torques(case), "shaft": shaft, "stage": stage.number,
                             "x_from_mm": stage.x_from_mm, "x_to_mm": stage.x_to_mm, "length_mm": stage.length_mm,
                             "outer_diameter_mm": stage.outer_diameter_mm,
                             "inner_diameter_mm": stage.inner_diameter_mm, "beta_deg": beta,
                             "radial_displacement_a_mm": export.radial_mm[shaft],
                             "tilt_term_mm": float(tilt), "lever_arm_mm": float(arm)})
    return rows


def _float_list(values) -> list[float]:
    """Plain floats (no numpy scalars, no −0.0) so that CSV and JSON hold the same values."""
    return [float(v) + 0.0 for v in values]


def _coupling_values(states: ConnectionStates, case: int, row: int, suffix: str = "", installed=None) -> dict:
    delta, force = _float_list(states.deformation[case, row]), _float_list(states.force_on_b[case, row])
    if installed is not None:  # from rest: the installed misalignment stays in the coupling, as in sweep.csv
        delta = [d - float(i) for d, i in zip(delta, installed)]
    um, deg = 1e6, math.degrees(1.0)
    return {
        f"offset_y{suffix}_um": delta[1] * um, f"offset_z{suffix}_um": delta[2] * um,
        f"offset_radial{suffix}_um": math.hypot(delta[1], delta[2]) * um,
        f"angle_about_y{suffix}_deg": delta[4] * deg, f"angle_about_z{suffix}_deg": delta[5] * deg,
        f"angle{suffix}_deg": math.hypot(delta[4], delta[5]) * deg, f"twist{suffix}_deg": delta[3] * deg,
        f"force_y{suffix}_N": force[1], f"force_z{suffix}_N": force[2], f"torque{suffix}_Nm": force[3],
        f"moment_y{suffix}_Nm": force[4], f"moment_z{suffix}_Nm": force[5],
    }


def coupling_rows(export: DynamicsExport) -> list[dict]:
    """One row per case and coupling: misalignment of the ``to`` hub relative to the ``from`` hub.

    Parameters
    ----------
    export : DynamicsExport
        From :func:`dynamics_export`.

    Returns
    -------
    list of dict
        Parallel offset (µm) and angle (degrees) per case and coupling, keys with units.
    """
    rows = []
    stress_free = stress_free_motions(export.sweep.rig)
    from_rest = export.measured_from == "aligned_at_rest"
    for i, case in enumerate(export.sweep.cases):
        for c in export.sweep.rig.couplings:
            row = export.measured.index("coupling", c.name)
            rows.append({**_torques(case), "coupling": c.name, "from_part": c.from_.part, "to_part": c.to.part,
                         "centre_x_mm": c.centre_x_mm, "measured_from": export.measured_from,
                         **_coupling_values(export.measured, i, row, installed=stress_free[row] if from_rest else None),
                         **_coupling_values(export.unloaded, i, row, UNLOADED)})
    return rows


def _bearing_values(states: ConnectionStates, case: int, row: int, suffix: str = "") -> dict:
    force = _float_list(states.force_on_b[case, row])
    return {f"force_x{suffix}_N": force[0], f"force_y{suffix}_N": force[1], f"force_z{suffix}_N": force[2],
            f"force_radial{suffix}_N": math.hypot(force[1], force[2]),
            f"moment_y{suffix}_Nm": force[4], f"moment_z{suffix}_Nm": force[5]}


def _bearing_stiffness(states: ConnectionStates, case: int, row: int) -> dict:
    k = _float_list(states.stiffness[case, row])
    return {"stiffness_axial_N_per_um": k[0] * 1e-6, "stiffness_y_N_per_um": k[1] * 1e-6,
            "stiffness_z_N_per_um": k[2] * 1e-6, "tilt_stiffness_y_Nm_per_rad": k[4],
            "tilt_stiffness_z_Nm_per_rad": k[5]}


def bearing_rows(export: DynamicsExport) -> list[dict]:
    """One row per case and bearing: the force and moment the bearing exerts on its shaft.

    Parameters
    ----------
    export : DynamicsExport
        The sweep's dynamics inputs, with the bearings' reactions (:func:`dynamics_export`).

    Returns
    -------
    list of dict
        Keys with units (``force_y_N``, ``moment_z_Nm``, …), one row per case and bearing, and the
        bearing's operating stiffness in that case (``stiffness_y_N_per_um``, …: the typed-in value of a
        linear bearing; the tangent at the converged state of a bearing with clearance or from ball geometry).
    """
    rows = []
    for i, case in enumerate(export.sweep.cases):
        for b in export.sweep.rig.bearings:
            row = export.measured.index("bearing", b.name)
            rows.append({**_torques(case), "bearing": b.name, "shaft": b.shaft, "housing": b.housing,
                         "x_mm": b.x_mm, "measured_from": export.measured_from,
                         **_bearing_values(export.measured, i, row), **_bearing_values(export.unloaded, i, row, UNLOADED),
                         **_bearing_stiffness(export.measured, i, row)})
    return rows


def export_tables(export: DynamicsExport) -> dict[str, list[dict]]:
    """The four tables of the export, by name (:data:`CSV_TABLES`)."""
    return {"shafts": shaft_rows(export), "stages": stage_rows(export), "couplings": coupling_rows(export),
            "bearings": bearing_rows(export)}


def export_document(export: DynamicsExport, rig_source: str, rig_text: str) -> dict:
    """The JSON document: provenance, units, conventions and the four tables."""
    sweep, rig = export.sweep, export.sweep.rig
    tables = export_tables(export)
    return {
        "rvcoax_version": rvcoax_version(),
        "kind": "rvcoax dynamics export",
        "rig": {"name": rig.rig.name, "source": rig_source, "sha256": text_sha256(rig_text)},
        "model": {"kind": sweep.settings.model, "dofs": sweep.n_dofs, "solver": sweep.solver},
        "measured_from": export.measured_from,
        "units": UNITS,
        "conventions": {
            "axes": "x along the drivetrain, y vertical (+ up), z horizontal; angles about y and z",
            "beta": "arcsin(Y_max / L) (paper 000), from the measured_from state",
            "lever_arm": "tan(beta) * ((l_k + l_{k-1}) / 2 + a / cos(beta)) + d_k / 2, l_0 = 0; stage 1 at the reducer",
            "couplings": "motion of the to-hub relative to the from-hub at the coupling centre, as sweep.csv's "
                         "coupling_<name>_offset_um / _angle_urad (from the measured_from state, with the installed "
                         "misalignment the rig file declares) and, _unloaded_ref, its _offset_from_unloaded_um / "
                         "_angle_from_unloaded_urad; forces on the to-part: the coupling's spring force (stiffness x "
                         "(offset - installed misalignment) from rest, stiffness x offset from the unloaded geometry)",
            "bearings": "force and moment the bearing exerts on its shaft, at the bearing centre; stiffness: the "
                        "operating (tangent) stiffness in the case, the typed-in value for a linear bearing",
            "unloaded_ref": "columns ending in _unloaded_ref: from the unloaded geometry (forces: total, self-weight included)",
        },
        "radial_displacement_a_mm": dict(export.radial_mm),
        "stages": {shaft: [{"stage": s.number, "x_from_mm": s.x_from_mm, "x_to_mm": s.x_to_mm,
                            "length_mm": s.length_mm, "outer_diameter_mm": s.outer_diameter_mm,
                            "inner_diameter_mm": s.inner_diameter_mm} for s in stages]
                   for shaft, stages in export.stages.items()},
        "tables": tables,
    }


def write_dynamics_json(export: DynamicsExport, path: str | Path, rig_source: str, rig_text: str) -> Path:
    """``dynamics.json`` at ``path``: every table of ``export`` with the rig's provenance (source and SHA-256).

    Parameters
    ----------
    export : DynamicsExport
        From :func:`dynamics_export`.
    path : str or Path
        The JSON file.
    rig_source, rig_text : str
        The rig file as the user named it, and its text.

    Returns
    -------
    Path
        ``path``, written atomically.
    """
    return write_json_atomic(path, export_document(export, rig_source, rig_text))


def write_dynamics_csv(export: DynamicsExport, folder: str | Path, stem: str = "dynamics") -> list[Path]:
    """``<stem>_shafts.csv``, ``_stages.csv``, ``_couplings.csv``, ``_bearings.csv`` in ``folder``.

    Parameters
    ----------
    export : DynamicsExport
        From :func:`dynamics_export`.
    folder : str or Path
        Where the tables go.
    stem : str
        The tables' common name.

    Returns
    -------
    list of Path
        The four tables, written atomically.
    """
    return [write_csv_atomic(Path(folder) / f"{stem}_{name}.csv", rows) for name, rows in export_tables(export).items()]


def read_csv_table(path: str | Path) -> list[dict]:
    """Read one export table back: numbers as float/int, text as str (the inverse of :func:`write_dynamics_csv`)."""
    def value(text: str):
        for kind in (int, float):
            try:
                return kind(text)
            except ValueError:
                pass
        return read_csv_cell(text)

    with open(path, encoding="utf-8", newline="") as stream:
        return [{read_csv_cell(k): value(v) for k, v in row.items()} for row in csv.DictReader(stream)]
