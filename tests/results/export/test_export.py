"""Dynamics export: lever arms, coupling misalignment, bearing reactions, CSV/JSON, ADAMS fragment, ROSS adapter.

The beam-model sweep of paper 000's 20 cases is solved once per module. One hybrid test (8 mm
mesh) checks that the spring states also balance a solid shaft. The ROSS tests skip when ROSS is
not installed (``pip install "rvcoax[ross]"``); its absence is reported clearly (tested always).
"""

from __future__ import annotations

import dataclasses
import json
import math
import sys
import tomllib

import numpy as np
import pytest
from typer.testing import CliRunner

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.bushing import GROUND
from rvcoax.fem.equilibrium import DofTable, resultant_of
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model.loads import UNIT_LOADS, case_weights
from rvcoax.geometry.rigfile import load_rig, parse_rig, parse_rig_text, reference_rig_text
from rvcoax.loadcases.cases import LoadCase, grid_cases, paired_cases, paper_cases
from rvcoax.results.cli.app import app
from rvcoax.results.connections import ConnectionsUnavailableError, case_displacements, connection_states
from rvcoax.results.export.adams import (
    MARKER_BASE_ID,
    AdamsExportError,
    AdamsSyntaxError,
    adams_fragment,
    marker_z_axis,
    parse_adm,
    spline_data,
)
from rvcoax.results.export.dynamics import (
    CSV_TABLES,
    IT3_RADIAL_DISPLACEMENT_MM,
    dynamics_export,
    export_document,
    export_tables,
    lever_arms_mm,
    read_csv_table,
    shaft_stages,
    tilt_direction,
    write_dynamics_csv,
    write_dynamics_json,
)
from rvcoax.results.export.ross import RossUnavailableError, import_ross
from rvcoax.results.sweep import SweepSettings, read_path, run_sweep


@pytest.fixture(scope="module")
def rig():
    return load_rig()


@pytest.fixture(scope="module")
def sweep(rig):
    return run_sweep(rig, paper_cases())


@pytest.fixture(scope="module")
def export(sweep):
    return dynamics_export(sweep)


def test_stages_of_the_reference_shafts_are_numbered_from_the_reducer(rig):
    def table(which):
        return [(s.number, s.x_from_mm, s.x_to_mm, s.outer_diameter_mm, s.inner_diameter_mm)
                for s in shaft_stages(rig, which)]

    # the input shaft is paper 000's four-stage hollow shaft: the Ø20 journal and the sun gear are one stage
    assert table("input") == [(1, 308, 340, 20, 8), (2, 262, 308, 18, 8), (3, 248, 262, 20, 8), (4, 220, 248, 18, 8)]
    assert table("output") == [(1, 405, 420, 35, 0), (2, 420, 440, 30, 0), (3, 440, 490, 35, 0), (4, 490, 565, 30, 0)]


def test_lever_arm_against_a_hand_calculation():
    # β = 30°, a = 1 mm, l = (10, 20) mm, d = (4, 6) mm: tan 30° = 1/√3, a / cos 30° = 2/√3
    arms, tilts = lever_arms_mm(30.0, 1.0, [10.0, 20.0], [4.0, 6.0])
    third = 1.0 / math.sqrt(3.0)
    np.testing.assert_allclose(arms, [5 * third + 2 / 3 + 2, 15 * third + 2 / 3 + 3], rtol=1e-14)
    np.testing.assert_allclose(tilts, arms - [2.0, 3.0], rtol=1e-14)
    # no tilt: the lever arm is the stage's radius
    np.testing.assert_array_equal(lever_arms_mm(0.0, 0.002, [32, 46], [20, 18])[0], [10.0, 9.0])


def test_exported_lever_arms_follow_the_formula_with_the_sweeps_beta(export, sweep):
    rows = [r for r in export_tables(export)["stages"] if r["shaft"] == "input"]
    case = sweep.cases[0]
    beta = math.radians(case.paths["input"].beta_deg)
    a = IT3_RADIAL_DISPLACEMENT_MM["input"]
    previous = 0.0
    for row in rows[:4]:
        length = row["length_mm"]
        tilt = math.tan(beta) * ((length + previous) / 2 + a / math.cos(beta))
        assert row["tilt_term_mm"] == pytest.approx(tilt, rel=1e-13)
        assert row["lever_arm_mm"] == pytest.approx(tilt + row["outer_diameter_mm"] / 2, rel=1e-15)
        previous = length
    assert [r["stage"] for r in rows[:4]] == [1, 2, 3, 4]


def test_radial_displacement_defaults_to_it3_and_can_be_set(sweep, export):
    shafts = export_tables(export)["shafts"]
    assert {r["shaft"]: r["radial_displacement_a_mm"] for r in shafts} == {"input": 0.002, "output": 0.003}
    other = dynamics_export(sweep, {"output": 0.01})
    assert other.radial_mm == {"input": 0.002, "output": 0.01}
    with pytest.raises(ValueError, match="output shaft"):
        dynamics_export(sweep, {"output": -1.0})


def test_case_displacements_reproduce_the_sweeps_paths(sweep):
    for reference, attribute in (("measured", "paths"), ("unloaded", "absolute_paths")):
        u = case_displacements(sweep, reference)
        for i, case in enumerate(sweep.cases):
            for shaft in MEASURED_SHAFTS:
                np.testing.assert_allclose(read_path(sweep.system, u[:, i], shaft).uy_mm,
                                           getattr(case, attribute)[shaft].uy_mm, rtol=1e-12, atol=1e-18)


def _point_motion(u, frame, part, x_mm, centre_mm):
    """Translation and rotation at x = centre of a rigid arm from the node (part, x): read off u directly."""
    node = frame.node(part, x_mm)
    ux, uy, uz, rx, ry, rz = u[DOFS_PER_NODE * node: DOFS_PER_NODE * node + 6]
    arm = (centre_mm - x_mm) * 1e-3
    return np.array([uy + rz * arm, uz - ry * arm]), np.array([rx, ry, rz])


@pytest.mark.parametrize("reference, suffix", [("measured", ""), ("unloaded", "_unloaded_ref")])
def test_coupling_offsets_and_angles_from_the_nodal_displacements(sweep, export, reference, suffix):
    u = case_displacements(sweep, reference)
    rows = export_tables(export)["couplings"]
    for coupling in sweep.rig.couplings:
        mine = [r for r in rows if r["coupling"] == coupling.name]
        for i, row in enumerate(mine):
            t_from, r_from = _point_motion(u[:, i], sweep.frame, coupling.from_.part, coupling.from_.x_mm,
                                           coupling.centre_x_mm)
            t_to, r_to = _point_motion(u[:, i], sweep.frame, coupling.to.part, coupling.to.x_mm, coupling.centre_x_mm)
            offset_um, angle_deg = (t_to - t_from) * 1e6, np.degrees(r_to - r_from)
            scale = max(abs(offset_um).max(), 1e-9)
            assert row[f"offset_y{suffix}_um"] == pytest.approx(offset_um[0], abs=1e-12 * scale)
            assert row[f"offset_z{suffix}_um"] == pytest.approx(offset_um[1], abs=1e-12 * scale)
            assert row[f"angle_about_z{suffix}_deg"] == pytest.approx(angle_deg[2], rel=1e-12, abs=1e-20)
            assert row[f"twist{suffix}_deg"] == pytest.approx(angle_deg[0], rel=1e-12, abs=1e-20)
            assert row[f"force_y{suffix}_N"] == pytest.approx(
                -coupling.radial_stiffness_N_per_mm * 1e3 * offset_um[0] * 1e-6, rel=1e-12, abs=1e-15)
    # the couplings carry the torques: C2 transmits T1 to the input shaft, C3 T2 from the output shaft
    c2 = [r for r in rows if r["coupling"] == "C2"]
    assert [r["torque_Nm"] for r in c2] == pytest.approx([c.case.input_torque_Nm for c in sweep.cases], rel=1e-9)


def _part_dofs(system, part: str) -> np.ndarray:
    """Every DOF of ``part``: its frame nodes, and its solid block in a hybrid model."""
    nodes = np.flatnonzero(system.frame.node_part == part)
    dofs = [(DOFS_PER_NODE * nodes[:, None] + np.arange(DOFS_PER_NODE)).ravel()]
    for solid in system.solids:
        if solid.name == part:
            dofs.append(np.arange(solid.offset, solid.offset + solid.n_dofs))
    return np.concatenate(dofs)


def _spring_resultant_on(states, frame, part: str, case: int) -> tuple[np.ndarray, np.ndarray]:
    """Force and moment about the origin of every spring acting on ``part`` (N, N·m), and their sizes."""
    total, size = np.zeros(6), np.zeros(2)
    node_a, node_b = np.asarray(frame.structure.bushings.node_a), np.asarray(frame.structure.bushings.node_b)
    for s in range(len(states.names)):
        on_b = frame.node_part[node_b[s]] == part
        on_a = node_a[s] != GROUND and frame.node_part[node_a[s]] == part
        if on_a == on_b:
            continue  # not touching the part (or a spring inside it)
        load = states.force_on_b[case, s] * (1.0 if on_b else -1.0)
        moment = np.cross(states.point_m[s], load[:3]) + load[3:]
        total += np.concatenate([load[:3], moment])
        size += [np.abs(load[:3]).sum(), np.abs(moment).sum() + np.abs(load[3:]).sum()]
    return total, size


def _assert_each_shaft_in_equilibrium(sweep, states, reference: str, parts):
    """Springs on each part balance its external loads to 1e-9 of their sizes, and to 10 × the solve's
    relative residual times the total applied load (the hybrid model's PARDISO solve leaves ~1e-10)."""
    system = sweep.system
    from_rest = reference == "measured"
    for i, case in enumerate(sweep.cases):
        weights = case_weights(case.case.input_torque_Nm, case.case.output_torque_Nm, include_rest=not from_rest)
        # external loads only: the prestrain "load" K Δ0 is the springs' own force, in their Δ − Δ0
        load = sum(weights[k] * system.unit_loads[k] for k in UNIT_LOADS if k != "prestrain")
        full = sum(w * system.unit_loads[k] for k, w in case_weights(case.case.input_torque_Nm,
                                                                      case.case.output_torque_Nm, True).items())
        floor = 10.0 * case.residual * np.abs(full).sum()
        for part in parts:
            dofs = _part_dofs(system, part)
            table = DofTable(system.dofs.position[dofs], system.dofs.component[dofs])
            applied = resultant_of(table, load[dofs])
            springs, size = _spring_resultant_on(states, sweep.frame, part, i)
            size += np.abs(resultant_of(table, np.abs(load[dofs]))).reshape(2, 3).sum(axis=1)
            error = np.abs(springs + applied)
            assert error[:3].max() <= 1e-9 * size[0] + floor, (part, i, error, size)
            assert error[3:].max() <= 1e-9 * size[1] + floor, (part, i, error, size)
            assert size[0] > 0 or part not in ("input_shaft", "output_shaft")


@pytest.mark.parametrize("reference", ["measured", "unloaded"])
def test_bearing_reactions_balance_the_applied_loads_on_every_shaft(sweep, reference):
    shafts = [p.name for p in sweep.rig.parts if p.role == "shaft"]
    _assert_each_shaft_in_equilibrium(sweep, connection_states(sweep, reference), reference, shafts)


def test_input_shaft_bearings_carry_the_sun_gear_load(sweep, export):
    # from rest, the input shaft carries only the load-sharing force at its sun gear, C2 and its bearings
    rows = export_tables(export)
    lateral = sweep.rig.torque_lateral_loads[0]
    for i, case in enumerate(sweep.cases):
        t1 = case.case.input_torque_Nm
        gear = lateral.force_per_torque_N_per_Nm * t1 + lateral.engaged_force_N * np.sign(t1)
        bearings = sum(r["force_y_N"] for r in rows["bearings"] if r["shaft"] == "input_shaft"
                       and (r["T1_input_Nm"], r["T2_output_Nm"]) == (t1, case.case.output_torque_Nm))
        coupling = [r for r in rows["couplings"] if r["coupling"] == "C2"][i]["force_y_N"]
        assert bearings + coupling + gear == pytest.approx(0.0, abs=1e-10 * abs(gear))


def test_an_installed_coupling_misalignment_is_the_unloaded_reference(rig):
    data = tomllib.loads(reference_rig_text())
    c3 = next(c for c in data["couplings"] if c["name"] == "C3")
    c3["parallel_offset_um"] = 20.0
    shifted = parse_rig(data, "test")
    result = run_sweep(shifted, paired_cases([0.5, 1.0], [70.0, 140.0]))
    states = connection_states(result, "unloaded")
    row = states.index("coupling", "C3")
    # the coupling pulls its hubs towards its free shape: force = k (Δ − Δ0), Δ0 = 20 µm in y
    assert states.force_on_b[0, row, 1] == pytest.approx(-2.5e6 * states.deformation[0, row, 1], rel=1e-12)
    assert -20e-6 < states.deformation[0, row, 1] < -10e-6
    _assert_each_shaft_in_equilibrium(result, states, "unloaded", ["output_shaft", "output_sensor_shaft"])
    # from rest the installed offset cancels: same as the aligned rig
    aligned = connection_states(run_sweep(rig, paired_cases([0.5, 1.0], [70.0, 140.0])), "measured")
    np.testing.assert_allclose(connection_states(result, "measured").force_on_b, aligned.force_on_b, atol=1e-12)


@pytest.mark.slow
def test_hybrid_model_springs_balance_the_solid_input_shaft(rig):
    settings = SweepSettings(model="hybrid", mesh_size_mm=8.0)
    result = run_sweep(rig, paired_cases([0.07, 1.43], [10.0, 200.0]), settings)
    for reference in ("measured", "unloaded"):
        _assert_each_shaft_in_equilibrium(result, connection_states(result, reference), reference,
                                          ["input_shaft", "output_shaft"])


def test_a_sweep_without_unit_responses_is_refused(sweep):
    with pytest.raises(ConnectionsUnavailableError, match="radial clearance"):
        connection_states(dataclasses.replace(sweep, states=None))


NONLINEAR_CASES = (LoadCase(1.43, 200.0), LoadCase(0.07, 10.0))


def _shafts(rig):
    return [p.name for p in rig.parts if p.role == "shaft"]


def test_a_ball_bearing_sweep_exports_each_bearing_s_own_force_and_operating_stiffness():
    # each case is solved by Newton (no unit responses): the export reads the converged state, the ball
    # bearings' forces from their Hertz law and their tangent stiffness, the other springs as linear
    ball_rig = parse_rig_text(reference_rig_text("ball_bearings"), "variant")
    result = run_sweep(ball_rig, NONLINEAR_CASES)
    assert result.unit_displacements is None
    for reference in ("measured", "unloaded"):  # the Hertz forces balance every shaft; k_ref Δ would not
        _assert_each_shaft_in_equilibrium(result, connection_states(result, reference), reference, _shafts(ball_rig))
    rows = export_tables(dynamics_export(result))["bearings"]
    points = result.solver_report["ball_bearing_operating_points"]
    balls = [b.name for b in ball_rig.bearings if b.model == "ball"]
    for i, case in enumerate(NONLINEAR_CASES):
        by_name = {r["bearing"]: r for r in rows if r["T2_output_Nm"] == case.output_torque_Nm}
        for name in balls:
            point, row = points[name][i + 1], by_name[name]  # [0] is the rest state
            assert row["stiffness_y_N_per_um"] == pytest.approx(point["radial_stiffness_y_N_per_um"], rel=1e-9, abs=1e-12)
            assert row["stiffness_axial_N_per_um"] == pytest.approx(point["axial_stiffness_N_per_um"], rel=1e-9, abs=1e-12)
            assert row["tilt_stiffness_z_Nm_per_rad"] == pytest.approx(point["tilt_stiffness_z_Nm_per_rad"], rel=1e-9,
                                                                        abs=1e-9)
            assert row["force_radial_unloaded_ref_N"] == pytest.approx(point["radial_force_N"], rel=1e-9, abs=1e-12)
        loaded = by_name["input_B2"]
        assert loaded["stiffness_y_N_per_um"] > 1.0 and loaded["force_radial_unloaded_ref_N"] > 1.0
        for b in ball_rig.bearings:
            if b.model != "ball":  # a linear bearing keeps its typed-in stiffness
                assert by_name[b.name]["stiffness_y_N_per_um"] == pytest.approx(b.radial_stiffness_N_per_um, rel=1e-12)


def test_a_rolling_bearing_sweep_exports_each_bearing_s_own_force_and_operating_stiffness():
    # angular-contact pair, cylindrical and tapered roller bearings from geometry: the same converged state
    rolling_rig = parse_rig_text(reference_rig_text("rolling_bearings"), "variant")
    result = run_sweep(rolling_rig, NONLINEAR_CASES)
    for reference in ("measured", "unloaded"):
        _assert_each_shaft_in_equilibrium(result, connection_states(result, reference), reference,
                                          _shafts(rolling_rig))
    rows = export_tables(dynamics_export(result))["bearings"]
    points = result.solver_report["rolling_bearing_operating_points"]
    for i, case in enumerate(NONLINEAR_CASES):
        by_name = {r["bearing"]: r for r in rows if r["T2_output_Nm"] == case.output_torque_Nm}
        for name in points:
            point, row = points[name][i + 1], by_name[name]
            assert row["stiffness_y_N_per_um"] == pytest.approx(point["radial_stiffness_y_N_per_um"], rel=1e-9, abs=1e-12)
            assert row["stiffness_axial_N_per_um"] == pytest.approx(point["axial_stiffness_N_per_um"], rel=1e-9, abs=1e-12)
            # 1 µN: the preloaded pair's 100 N/µm times the Newton motion's last digits (1e-16 m) differ by 1e-8 N
            assert row["force_radial_unloaded_ref_N"] == pytest.approx(point["radial_force_N"], rel=1e-9, abs=1e-6)
        assert by_name["input_B1"]["stiffness_y_N_per_um"] > 50.0  # the preloaded pair


def test_a_bearing_with_clearance_exports_the_gap_law_force():
    data = tomllib.loads(reference_rig_text())
    for bearing in data["bearings"]:
        if bearing["name"] in ("input_B1", "input_B2"):
            bearing["radial_clearance_um"] = 5.0
    gapped = parse_rig(data, "test")
    result = run_sweep(gapped, NONLINEAR_CASES)
    for reference in ("measured", "unloaded"):
        _assert_each_shaft_in_equilibrium(result, connection_states(result, reference), reference, _shafts(gapped))
    states = connection_states(result, "unloaded")
    for name in ("input_B1", "input_B2"):
        row = states.index("bearing", name)
        k = next(b for b in gapped.bearings if b.name == name).radial_stiffness_N_per_um * 1e6
        for case in range(len(NONLINEAR_CASES)):
            d = states.deformation[case, row, 1:3]
            size = float(np.hypot(*d))
            # F = k (|d| − c) d/|d| where the gap is closed, none where it is open; the shaft gets −F
            expected = k * max(size - 5e-6, 0.0) * d / size
            np.testing.assert_allclose(states.force_on_b[case, row, 1:3], -expected, rtol=1e-9, atol=1e-12)
            tangent = states.stiffness[case, row, 1:3]
            assert np.all(tangent >= 0) and np.all(tangent <= k * (1 + 1e-12))
            assert (size > 5e-6) == bool(np.any(tangent > 0))


def test_csv_and_json_round_trip(export, tmp_path):
    tables = export_tables(export)
    paths = write_dynamics_csv(export, tmp_path)
    assert [p.name for p in paths] == [f"dynamics_{name}.csv" for name in CSV_TABLES]
    document = json.loads(write_dynamics_json(export, tmp_path / "dynamics.json", "test", "text").read_text(encoding="utf-8"))
    assert document["measured_from"] == "aligned_at_rest"
    assert document["radial_displacement_a_mm"] == IT3_RADIAL_DISPLACEMENT_MM
    assert [s["length_mm"] for s in document["stages"]["input"]] == [32, 46, 14, 28]
    for name, path in zip(CSV_TABLES, paths):
        back = read_csv_table(path)
        assert document["tables"][name] == tables[name]  # JSON keeps every digit
        assert len(back) == len(tables[name]) and list(back[0]) == list(tables[name][0])
        for read, row in zip(back, tables[name]):
            for key, value in row.items():
                if isinstance(value, str):
                    assert read[key] == value
                else:  # CSV keeps 10 significant digits
                    assert read[key] == pytest.approx(value, rel=1e-9, abs=1e-300), (name, key)
    assert export_document(export, "test", "text")["tables"]["shafts"][0]["beta_deg"] == \
        export.sweep.cases[0].paths["input"].beta_deg


def test_adams_fragment_parses_back_with_the_sweeps_beta(export, sweep):
    text = adams_fragment(export)
    assert max(len(line) for line in text.splitlines()) <= 80
    statements = parse_adm(text)
    splines = {s.id: s for s in statements if s.name == "SPLINE"}
    markers = {s.id: s for s in statements if s.name == "MARKER"}
    assert len(markers) == 2 * len(sweep.cases)
    for shaft, torque in (("input", "input_torque_Nm"), ("output", "output_torque_Nm")):
        base = MARKER_BASE_ID[shaft]
        x, curves = spline_data(splines[base])
        order = np.argsort([getattr(c.case, torque) for c in sweep.cases])
        np.testing.assert_array_equal(x, [getattr(sweep.cases[i].case, torque) for i in order])
        assert curves[0][0] is None
        np.testing.assert_array_equal(curves[0][1], [sweep.cases[i].paths[shaft].beta_deg for i in order])
        start = getattr(sweep.rig.paths, shaft).x_start_mm
        for i, case in enumerate(sweep.cases):
            marker = markers[base + i + 1]
            axis = marker_z_axis(marker)
            tilt = math.degrees(math.atan2(axis[1], axis[0]))
            path = case.paths[shaft]
            assert tilt == pytest.approx(tilt_direction(path) * path.beta_deg, abs=1e-12)
            assert abs(axis[2]) < 1e-15
            assert [float(v) for v in marker.values("QP")[0]] == [start, 0.0, 0.0]
    assert "LINEAR_EXTRAPOLATE" in dict(splines[MARKER_BASE_ID["input"]].arguments)


def test_adams_grid_cases_give_a_family_of_curves(rig):
    result = run_sweep(rig, grid_cases([0.3, 0.7, 1.0, 1.4], [20.0, 70.0, 140.0, 200.0]))
    statements = parse_adm(adams_fragment(dynamics_export(result)))
    spline = next(s for s in statements if s.name == "SPLINE" and s.id == MARKER_BASE_ID["input"])
    x, curves = spline_data(spline)
    np.testing.assert_array_equal(x, [0.3, 0.7, 1.0, 1.4])
    assert [z for z, _ in curves] == [20.0, 70.0, 140.0, 200.0]
    beta = {(c.case.input_torque_Nm, c.case.output_torque_Nm): c.paths["input"].beta_deg for c in result.cases}
    for z, values in curves:
        np.testing.assert_array_equal(values, [beta[(t1, z)] for t1 in x])
    # repeated torques that are not a full grid cannot be written as a SPLINE
    few = run_sweep(rig, (LoadCase(1.0, 10.0), LoadCase(1.0, 20.0), LoadCase(1.0, 30.0), LoadCase(0.5, 30.0)))
    with pytest.raises(AdamsExportError, match="full grid|at least 4"):
        adams_fragment(dynamics_export(few))


@pytest.mark.parametrize("text, problem", [
    ("MARKER/1, PART=1, QP=0,0,0, REULER=0D,0D,0D, " + "0" * 60, "characters"),
    (", X=1", "continuation"),
    ("SPLINE/1, X=1,2,3, Y=1,2,3", "at least 4"),
    ("SPLINE/1, X=1,3,2,4, Y=1,2,3,4", "increasing"),
    ("SPLINE/1, X=1,2,3,4, Y=1,2,3", "Y needs"),
    ("MARKER/1, QP=0,0,0, REULER=0,0,0", "PART"),
    ("MARKER/1, PART=1, QP=0,0, REULER=0,0,0", "QP"),
    ("MARKER/1, PART=1, QP=0,0,0, REULER=0,0,0\nMARKER/1, PART=1, QP=0,0,0, REULER=0,0,0", "twice"),
    ("MARKER/1, PART=1, QP=0,,0, REULER=0,0,0", "empty"),
    ("MARKER, PART=1, QP=0,0,0, REULER=0,0,0", "needs an id"),
    ("MARKER/1, PART=1, QP=0,0,0, REULER=0,0,0, 1.5.2", "neither"),
])
def test_adams_reader_rejects_broken_datasets(text, problem):
    with pytest.raises(AdamsSyntaxError, match=problem):
        parse_adm(text)


def test_adams_reader_accepts_comments_continuations_and_radians():
    statements = parse_adm("! a comment\nMARKER/7 ! inline\n, PART=3\n, QP=1.0D+01, 0, -2.5E-1\n"
                           ", REULER=1.5707963267948966, 90D\n, 0\nEND\n")
    marker = statements[0]
    assert (marker.name, marker.id, marker.values("PART")) == ("MARKER", 7, [("3",)])
    np.testing.assert_allclose(marker_z_axis(marker), [1.0, 0.0, 0.0], atol=1e-15)
    assert statements[1].name == "END"


def test_export_command_writes_every_text_format(tmp_path):
    runner = CliRunner()
    for output_format, names in (("csv", [f"dynamics_{t}.csv" for t in CSV_TABLES]), ("json", ["dynamics.json"]),
                                 ("adams", ["dynamics.adm"])):
        result = runner.invoke(app, ["export", "--format", output_format, "--t1", "0.2,0.5,1,1.4",
                                     "--t2", "30,70,140,200", "--output-radial-mm", "0.005", "--out", str(tmp_path)])
        assert result.exit_code == 0, result.output
        for name in names:
            assert (tmp_path / name).stat().st_size > 0
    shafts = read_csv_table(tmp_path / "dynamics_shafts.csv")
    assert len(shafts) == 8 and {r["radial_displacement_a_mm"] for r in shafts} == {0.002, 0.005}
    assert len(parse_adm((tmp_path / "dynamics.adm").read_text(encoding="utf-8"))) == 2 * 4 + 2


@pytest.mark.parametrize("args, message", [
    (["--format", "xml"], "not one of json, csv, adams, ross"),
    (["--input-radial-mm", "-1"], "--input-radial-mm"),
    (["--format", "adams", "--t1", "1,2", "--t2", "10,20"], "at least 4"),
])
def test_export_command_rejects_bad_options(tmp_path, args, message):
    result = CliRunner().invoke(app, ["export", *args, "--out", str(tmp_path)])
    assert result.exit_code == 2
    assert message in " ".join(result.output.split()), result.output
    assert "Traceback" not in result.output


def test_missing_ross_is_reported_with_the_install_instruction(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "ross", None)  # makes `import ross` fail
    with pytest.raises(RossUnavailableError, match=r'pip install "rvcoax\[ross\]"'):
        import_ross()
    result = CliRunner().invoke(app, ["export", "--format", "ross", "--out", str(tmp_path)])
    assert result.exit_code == 2 and "rvcoax[ross]" in result.output


@pytest.fixture(scope="module")
def ross():
    try:
        return import_ross()
    except RossUnavailableError:
        pytest.skip("ROSS is not installed (pip install 'rvcoax[ross]')")


@pytest.mark.parametrize("which", ["input", "output"])
def test_the_shaft_line_names_its_supports_by_record(rig, which):
    """The ROSS shaft line's supports are the shaft's bearings (and joints), as (kind, name) records."""
    from rvcoax.geometry.model.beam import SpringId
    from rvcoax.results.export.ross import shaft_line

    line = shaft_line(rig, which)
    part = getattr(rig.paths, which).part
    bearings = {SpringId("bearing", b.name) for b in rig.bearings if b.shaft == part}
    assert bearings and {s.spring for s in line.supports if s.spring.kind == "bearing"} == bearings
    assert {s.spring.kind for s in line.supports} <= {"bearing", "joint"}


@pytest.mark.parametrize("which", ["input", "output"])
def test_ross_gravity_deflection_equals_ours_on_rigid_supports(ross, rig, which):
    from rvcoax.results.export.ross import compare_static

    rotor, comparison = compare_static(rig, which, ross)
    line = comparison.line
    np.testing.assert_allclose(np.asarray(rotor.nodes_pos) * 1e3, line.node_x_mm - line.node_x_mm[0], atol=1e-9)
    assert {b.n for b in rotor.bearing_elements} == {line.node_at(s.x_mm) for s in line.supports}
    # the same mass: shaft plus hubs, as in the rvcoax beam model
    from rvcoax.geometry.model.beam import build_rig_model

    assert rotor.m == pytest.approx(build_rig_model(rig).part_mass_kg[line.part], rel=1e-12)
    # sag of tens of nm; ROSS's rigid supports are 1e20 N/m springs, ours exact constraints
    assert comparison.largest_sag_m > 1e-8
    assert comparison.relative_difference < 1e-8


def test_ross_misalignment_faults_carry_our_coupling_misalignment(ross, rig, export):
    from rvcoax.results.export.ross import build_rotor, misalignment_fault, misalignment_parameters, shaft_line

    line = shaft_line(rig, "output")
    rotor = build_rotor(line, ross)
    rows = misalignment_parameters(export, line)
    couplings = [r for r in export_tables(export)["couplings"] if r["coupling"] == "C3"]
    assert len(rows) == len(couplings) == len(export.sweep.cases)
    for row, coupling in zip(rows, couplings):
        assert row["mis_distance_y_m"] == pytest.approx(coupling["offset_y_um"] * 1e-6, rel=1e-12)
        assert row["mis_distance_x_m"] == pytest.approx(-coupling["offset_z_um"] * 1e-6, abs=1e-20)
        assert row["mis_angle_rad"] == pytest.approx(math.radians(coupling["angle_deg"]), rel=1e-12)
    fault = misalignment_fault(rotor, rows[0], ross)
    assert fault.shaft_elem.n == rows[0]["n"]
    hub = line.node_at(570 - 27.5)  # the C3 hub at 542.5 mm is a node of the fault's element
    assert hub in (fault.shaft_elem.n_l, fault.shaft_elem.n_r)
    assert fault.delta_y == rows[0]["mis_distance_y_m"] and fault.radial_stiffness == 2.5e6


@pytest.mark.parametrize("which", ["input", "output"])
def test_ross_natural_frequencies_equal_ours_on_the_same_supports(ross, rig, which):
    """ROSS's run_modal at zero speed and rvcoax's modes of the same shaft line: the lowest 4 within 1 %
    (measured: 1e-8; the same Timoshenko theory, consistent masses, springs, hubs with their inertia)."""
    from rvcoax.results.export.ross import compare_modal

    rotor, comparison = compare_modal(rig, which, ross, 4)
    assert comparison.ross_hz.size == comparison.rvcoax_hz.size == 4
    assert np.all(comparison.relative_difference < 0.01), (comparison.ross_hz, comparison.rvcoax_hz)
    assert "typed-in" in rotor.tag


def test_ross_rotor_carries_the_operating_stiffness_of_ball_bearings(ross):
    """A ball bearing exports its operating tangent stiffness in the load case, named in the rotor's tag."""
    from pathlib import Path

    from rvcoax.results.export.ross import build_rotor, compare_modal, operating_supports, shaft_line

    ball_rig = load_rig(Path(__file__).resolve().parents[3] / "geometry" / "data" / "reference_rig_ball_bearings.toml")
    sweep = run_sweep(ball_rig, (LoadCase(0.07, 10.0), LoadCase(1.43, 200.0)))
    light, heavy = operating_supports(sweep, 0), operating_supports(sweep, 1)
    balls = [b.name for b in ball_rig.bearings if b.model == "ball"]
    assert balls and set(light) == set(balls)
    assert any(heavy[name][0] != pytest.approx(light[name][0], rel=1e-6) for name in balls)
    label = sweep.cases[1].case.label
    line = shaft_line(ball_rig, "output", heavy, label)
    rotor = build_rotor(line, ross)
    assert label.replace(" ", "_") in rotor.tag
    stiffness = {b.tag: float(np.ravel(b.kyy)[0]) for b in rotor.bearing_elements}
    for support in line.supports:
        if support.spring.name in heavy:
            assert stiffness[f"bearing_{support.spring.name}"] == pytest.approx(heavy[support.spring.name][0])
    _, comparison = compare_modal(ball_rig, "output", ross, 4, line)
    assert np.all(comparison.relative_difference < 0.01)


def test_every_format_is_written_from_python_as_the_command_writes_it(export, tmp_path):
    """write_export: one function for every format of the registry; the files are those of `rvcoax export`."""
    from rvcoax.results.export import EXPORT_FORMATS, ExportFormatError, adams_fragment, write_export
    from rvcoax.results.export.dynamics import export_document

    assert [f.name for f in EXPORT_FORMATS] == ["json", "csv", "adams", "ross"]
    written = write_export(export, tmp_path / "adams", "adams")
    assert [p.name for p in written.paths] == ["dynamics.adm"] and written.tables == ()
    assert written.paths[0].read_text(encoding="utf-8") == adams_fragment(export)
    csv_files = write_export(export, tmp_path / "csv", "csv").paths
    assert sorted(p.name for p in csv_files) == sorted(f"dynamics_{t}.csv" for t in CSV_TABLES)
    json_file = write_export(export, tmp_path, "json", rig_source="my_rig.toml", rig_text="x = 1\n").paths[0]
    document = json.loads(json_file.read_text(encoding="utf-8"))
    assert document == json.loads(json.dumps(export_document(export, "my_rig.toml", "x = 1\n")))
    with pytest.raises(ExportFormatError, match="give rig_source and rig_text"):
        write_export(export, tmp_path, "json")
    with pytest.raises(ExportFormatError, match="'xml' is not one of json, csv, adams, ross"):
        write_export(export, tmp_path, "xml")


def test_the_export_command_lists_every_registered_format():
    from rvcoax.results.cli.app import load_command
    from rvcoax.results.export import EXPORT_FORMATS

    shown = next(p.help for p in load_command("export").params if p.name == "output_format").replace("\\[", "[")
    for entry in EXPORT_FORMATS:
        assert f"{entry.name} ({entry.description})" in shown
