"""Closed-form verification of the load types behind the effects library.

Each new load type is solved through the rig pipeline (rig data → schema → beam model → unit
loads → solve) on a small rig and compared with a hand calculation written out in the test:
misaligned couplings (parallel offset, angular), raised mounts, a bearing with radial clearance
(dead band and contact), the ``proportional`` torque-to-lateral load, Euler–Bernoulli against
Timoshenko beams, and the force-table scale. Steel as in tests/frames.py; gravity off.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from closed_form_rigs import (
    HUGE,
    HUGE_ROTATION,
    MM,
    UM,
    D,
    L,
    body,
    make_rig,
    mount,
    rest_displacement,
    shaft,
    value,
)
from frames import assert_close, rigidities

from rvcoax.fem import bushing
from rvcoax.fem.sections import CircularSection
from rvcoax.fem.system import factorize
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.io.records import model_section
from rvcoax.results.sweep import ModelError, SweepSettings, prepare_model, run_sweep

SECTION = CircularSection(D * MM)
R = rigidities(SECTION)
TIP_COMPLIANCE = (L * MM) ** 3 / (3 * R.EI) + L * MM / R.kGA  # m/N, tip force on a Timoshenko cantilever
TOL = 1e-7  # relative: the model is exact; clamps and tiny auxiliary springs leave < 1e-8


def tip_load(force_per_torque: float, x_mm: float = L, direction_deg: float = 0.0, part: str = "left", **more) -> dict:
    return {"name": "tip", "torque": "T1", "kind": "proportional", "on": {"part": part, "x_mm": x_mm},
            "force_per_torque_N_per_Nm": force_per_torque, "direction_deg": direction_deg, **more}


def cantilever(**groups) -> Rig:
    """Shaft 'left' (Ø20, 0 … 200 mm) clamped at x = 0."""
    groups.setdefault("mounts", [mount("clamp", "left", 0.0)])
    return make_rig([shaft("left", 0.0, L)], "left", "left", **groups)


# ---- couplings: parallel and angular misalignment ---------------------------------------------------------

def two_cantilevers(offset_um=0.0, angle_mrad=0.0, direction_deg=0.0, radial_N_per_mm=720.0, angular=1e-6) -> Rig:
    """'left' clamped at 0, 'right' clamped at 400 mm, their tips joined at x = 200 by a coupling."""
    coupling = {"name": "C", "from": {"part": "left", "x_mm": L}, "to": {"part": "right", "x_mm": L},
                "centre_x_mm": L, "radial_stiffness_N_per_mm": radial_N_per_mm,
                "angular_stiffness_Nm_per_rad": angular, "torsional_stiffness_Nm_per_rad": 1e3,
                "axial_stiffness_N_per_mm": 1e3, "parallel_offset_um": offset_um,
                "angular_misalignment_mrad": angle_mrad, "misalignment_direction_deg": direction_deg}
    return make_rig([shaft("left", 0.0, L), shaft("right", L, 2 * L)], "left", "right",
                    mounts=[mount("clamp_left", "left", 0.0), mount("clamp_right", "right", 2 * L)],
                    couplings=[coupling])


@pytest.mark.parametrize("direction_deg", [0.0, 90.0, 210.0])
def test_coupling_parallel_offset_between_two_cantilevers(direction_deg):
    """Offset δ: F = k_eff δ with 1/k_eff = 1/k_c + 2/k_b; tips at ±F/k_b along the misalignment direction.

    k_b = 1 / (L³/3EI + L/κGA) is a cantilever's tip stiffness; the coupling (angular stiffness
    negligible) is in series with both cantilevers. Its `to` hub is pushed towards +direction.
    """
    delta, k_c = 40.0, 720.0e3  # µm, N/m
    frame, u = rest_displacement(two_cantilevers(offset_um=delta, direction_deg=direction_deg))
    force = delta * UM / (1 / k_c + 2 * TIP_COMPLIANCE)
    tip = force * TIP_COMPLIANCE
    e = np.array([math.cos(math.radians(direction_deg)), math.sin(math.radians(direction_deg))])
    for part, sign in (("right", 1.0), ("left", -1.0)):
        moved = np.array([value(frame, u, part, L, 1), value(frame, u, part, L, 2)])
        assert_close(moved @ e, sign * tip, TOL)
        assert abs(moved @ [-e[1], e[0]]) < 1e-9 * tip  # nothing across the misalignment plane


def test_coupling_offset_through_the_sweep_is_a_rest_load():
    """The prestrain is in the rest state: seen from the unloaded geometry, gone when aligned at rest."""
    rig = two_cantilevers(offset_um=40.0)
    cases = (LoadCase(0.0, 0.0), LoadCase(1.0, 2.0))
    unloaded = run_sweep(rig, cases)
    tip = 40.0 * UM / (1 / 720.0e3 + 2 * TIP_COMPLIANCE) * TIP_COMPLIANCE / MM  # mm
    for result in unloaded.cases:
        assert_close(result.paths["output"].uy_mm[0], tip, TOL)
        assert_close(result.paths["input"].uy_mm[-1], -tip, TOL)
        assert result.equilibrium_error < 1e-9 and result.residual < 1e-9
    aligned = rig.model_copy(update={"paths": rig.paths.model_copy(update={"measured_from": "aligned_at_rest"})})
    for result in run_sweep(aligned, cases).cases:
        for shaft_name in MEASURED_SHAFTS:
            assert np.abs(result.paths[shaft_name].uy_mm).max() < 1e-12 * tip


@pytest.mark.parametrize("direction_deg", [0.0, 90.0])
def test_coupling_angular_misalignment_is_a_moment(direction_deg):
    """Angle α, angular stiffness k_θ (radial stiffness negligible): M = k_θ α / (1 + 2 k_θ L / EI).

    Each tip turns by M L / EI (the `to` hub towards the misalignment direction, the `from` hub
    away) and both tips move by −M L² / (2EI) along that direction (mirror cantilevers).
    """
    alpha, k_theta = 2.0, 150.0  # mrad, N·m/rad
    frame, u = rest_displacement(two_cantilevers(angle_mrad=alpha, direction_deg=direction_deg,
                                                 radial_N_per_mm=1e-9, angular=k_theta))
    moment = k_theta * alpha * 1e-3 / (1 + 2 * k_theta * L * MM / R.EI)
    lateral, rotation = (1, 5) if direction_deg == 0.0 else (2, 4)  # towards +z: rotation about −y
    sign = 1.0 if direction_deg == 0.0 else -1.0
    for part, turn in (("right", 1.0), ("left", -1.0)):
        assert_close(sign * value(frame, u, part, L, rotation), turn * moment * L * MM / R.EI, TOL)
        assert_close(value(frame, u, part, L, lateral), -moment * (L * MM) ** 2 / (2 * R.EI), TOL)


# ---- raised mounts --------------------------------------------------------------------------------------

def block_on_two_mounts(offsets_um: tuple[float, float]) -> Rig:
    spring = {"stiffness": [1e3, 1e3, 1e3], "rotational": [1e3, 0.0, 0.0]}
    return make_rig([body("block", 0.0, 100.0, 100.0)], "block", "block",
                    mounts=[mount("m0", "block", 0.0, offset_um=offsets_um[0], **spring),
                            mount("m1", "block", 100.0, offset_um=offsets_um[1], **spring)])


@pytest.mark.parametrize("offsets_um", [(30.0, 30.0), (30.0, 0.0), (-12.0, 25.0)], ids=["both", "one", "mixed"])
def test_raised_mounts_move_a_body_as_a_rigid_body(offsets_um):
    """A body on two mounts (no rotational stiffness) follows its mounts exactly, free of stress:
    u_y(x) = δ0 + (δ1 − δ0) x / 100 mm, rotation (δ1 − δ0) / 100 mm."""
    result = run_sweep(block_on_two_mounts(offsets_um), (LoadCase(0.0, 0.0),)).cases[0].paths["input"]
    d0, d1 = offsets_um[0] * 1e-3, offsets_um[1] * 1e-3  # mm
    expected = d0 + (d1 - d0) * result.station_mm / 100.0
    assert np.abs(result.uy_mm - expected).max() < 1e-9 * max(abs(d0), abs(d1))
    assert np.abs(result.rotation_z_rad - (d1 - d0) / 100.0).max() < 1e-9 * max(abs(d0), abs(d1)) / 100.0


def test_shaft_in_a_lifted_housing():
    """Housing on one mount (at x = 50, rotation clamped) raised δ; shaft in two bearings (x = 10, 90)
    held down at x = 50 by a ground spring k_g. A chain of compliances in series carries P = δ / C:

    C = 1/k_m + (a³/3EI_h + a/κGA_h)/2 + 1/(2 k_b) + (l³/48EI + l/4κGA) + 1/k_g,  a = 40, l = 80 mm;
    shaft centre y_s = P / k_g, housing centre y_h = δ − P / k_m.
    """
    delta, k_m, k_b, k_g = 25.0, 100.0e6, 50.0e6, 10.0e6
    bearings = [{"name": f"b{x:g}", "shaft": "shaft", "housing": "housing", "x_mm": x,
                 "radial_stiffness_N_per_um": k_b / 1e6, "axial_stiffness_N_per_um": 1.0} for x in (10.0, 90.0)]
    rig = make_rig([body("housing", 0.0, 100.0, 60.0), shaft("shaft", 0.0, 100.0)], "shaft", "housing",
                   bearings=bearings,
                   mounts=[mount("base", "housing", 50.0, [k_m / 1e6] * 3, [HUGE_ROTATION] * 3, offset_um=delta),
                           mount("hold", "shaft", 50.0, [1.0, k_g / 1e6, k_g / 1e6], [1.0, 0.0, 0.0])])
    housing = rigidities(CircularSection(0.06))
    a, span = 0.04, 0.08
    compliance = (1 / k_m + (a**3 / (3 * housing.EI) + a / housing.kGA) / 2 + 1 / (2 * k_b)
                  + span**3 / (48 * R.EI) + span / (4 * R.kGA) + 1 / k_g)
    force = delta * UM / compliance
    result = run_sweep(rig, (LoadCase(0.0, 0.0),)).cases[0]
    middle = 20  # station 50 mm of 41 over 100 mm
    assert result.paths["input"].station_mm[middle] == pytest.approx(50.0)
    assert_close(result.paths["input"].uy_mm[middle] * MM, force / k_g, TOL)
    assert_close(result.paths["output"].uy_mm[middle] * MM, delta * UM - force / k_m, TOL)
    assert result.equilibrium_error < 1e-9


# ---- bearing clearance ----------------------------------------------------------------------------------

def cantilever_with_gap(clearance_um: float, direction_deg: float = 0.0, housing: str = "ground") -> Rig:
    """The cantilever with a bearing at its tip (radial k = 1 N/µm, gap c) and a tip load of 100 N per N·m of T1."""
    parts = [shaft("left", 0.0, L)]
    mounts = [mount("clamp", "left", 0.0)]
    if housing != "ground":
        parts.append(body(housing, 150.0, 250.0, 80.0))
        mounts.append(mount("sleeve_clamp", housing, L))  # clamped where the bearing sits: no sleeve bending
    bearing = {"name": "tip_bearing", "shaft": "left", "housing": housing, "x_mm": L,
               "radial_stiffness_N_per_um": 1.0, "radial_clearance_um": clearance_um}
    return make_rig(parts, "left", "left", mounts=mounts, bearings=[bearing],
                    torque_lateral_loads=[tip_load(100.0, direction_deg=direction_deg)])


@pytest.mark.parametrize("housing", ["ground", "sleeve"])
@pytest.mark.parametrize("direction_deg", [0.0, 30.0, 180.0])
def test_bearing_clearance_dead_band_and_contact(direction_deg, housing):
    """Tip load P on a cantilever whose tip bearing has a gap c: below P_c = k_b c the bearing carries
    nothing (tip = P / k_b, the dead band); above it the tip moves (P + k c) / (k_b + k) radially."""
    c, k = 10.0 * UM, 1.0e6
    k_b = 1 / TIP_COMPLIANCE
    closing_torque = k_b * c / 100.0  # T1 at which the load P = 100 N/(N·m) · T1 closes the gap
    torques = closing_torque * np.array([0.2, 0.6, 0.999, 1.001, 2.0, 8.0, -0.5, -3.0])
    sweep = run_sweep(cantilever_with_gap(10.0, direction_deg, housing), tuple(LoadCase(t, 0.0) for t in torques))
    for t, result in zip(torques, sweep.cases):
        load = 100.0 * t
        radial = load / k_b if abs(load) <= k_b * c else (load + math.copysign(k * c, load)) / (k_b + k)
        assert_close(result.paths["input"].uy_mm[-1] * MM, radial * math.cos(math.radians(direction_deg)), TOL)
        assert result.residual < 1e-9 and result.equilibrium_error < 1e-9
    assert sweep.unit_displacements is None and sweep.solver_report["gapped_bearings"] == ["tip_bearing"]
    section = model_section(sweep)  # the result files say how the cases were solved: no superposition here
    assert section["method"].startswith("direct (nonlinear") and "superposition" not in section
    assert section["gapped_bearings"] == ["tip_bearing"]
    probe = sweep.system.probes["input"]  # the fields of each case are the solved ones
    for i, result in enumerate(sweep.cases):
        assert np.array_equal(probe.uy @ sweep.measured_displacement(i) * 1e3, result.paths["input"].uy_mm)


def test_shaft_resting_on_two_gapped_bearings():
    """A shaft held only by two gapped bearings (ends, gap c, stiffness k) under a central force P
    falls through the gap at both: mid-span moves c + P/(2k) + PL³/48EI + PL/4κGA, for any P ≠ 0.
    With both gaps open the shaft floats, so the iteration must not stop there."""
    c, k = 10.0, 2.0e6
    bearings = [{"name": f"b{x:g}", "shaft": "left", "housing": "ground", "x_mm": x, "radial_stiffness_N_per_um": k / 1e6,
                 "radial_clearance_um": c} for x in (0.0, L)]
    axial = mount("axial", "left", L / 2, [1.0, 0.0, 0.0], [1e4, 0.0, 0.0])  # axial and torsion only
    rig = cantilever(mounts=[axial], bearings=bearings, torque_lateral_loads=[tip_load(-100.0, x_mm=L / 2)])
    span = L * MM
    for t1 in (0.001, 0.3, -2.0):
        force = -100.0 * t1
        middle = run_sweep(rig, (LoadCase(t1, 0.0),)).cases[0].paths["input"].uy_mm[20] * MM
        bending = force * span**3 / (48 * R.EI) + force * span / (4 * R.kGA)
        assert_close(middle, math.copysign(c * UM, force) + force / (2 * k) + bending, TOL)


def test_clearance_zero_is_the_linear_bearing():
    """c = 0: the clearance law is the linear spring, δ = P / (k_b + k), by superposition."""
    k_b, k = 1 / TIP_COMPLIANCE, 1.0e6
    sweep = run_sweep(cantilever_with_gap(0.0), (LoadCase(0.1, 0.0),))
    assert sweep.unit_displacements is not None  # the linear path
    assert_close(sweep.cases[0].paths["input"].uy_mm[-1] * MM, 10.0 / (k_b + k), TOL)
    assert_close(sweep.measured_displacement(0)[6 * sweep.frame.node("left", L) + 1], 10.0 / (k_b + k), TOL)


def test_clearance_nonlinear_solver_alone():
    """rvcoax.fem.bushing.solve_with_gaps on one spring: a unit mass-less node on a linear spring k1 to
    ground and a gapped spring k to ground; F < k1 c stays in the band, else (F + k c)/(k1 + k)."""
    import frames

    k1, k, c = 2.0e6, 3.0e6, 5e-6
    springs = frames.bushings([bushing.GROUND, bushing.GROUND], [0, 0], np.zeros((2, 3)),
                              [[1.0, k1, k1, 1.0, 1.0, 1.0], [0.0, k, k, 0.0, 0.0, 0.0]])
    structure = frames.model(np.zeros((1, 3)), frames.no_beams(), springs)
    from frames import constraint_elimination, stiffness_matrix

    solver = factorize(stiffness_matrix(structure), constraint_elimination(structure)[0])
    gaps = bushing.prepare_radial_gaps(solver.solve, bushing.radial_operator(structure.coordinates, springs, [1], 6),
                                       [k], [c])
    for force in (1.0, 9.99, 10.01, 40.0, -25.0):
        solution = bushing.solve_with_gaps(gaps, solver.solve, frames.point_load(6, 0, [0, force, 0, 0, 0, 0]))
        expected = force / k1 if abs(force) <= k1 * c else (force + math.copysign(k * c, force)) / (k1 + k)
        assert_close(solution.displacement[1], expected, 1e-10)
        assert bool(solution.closed[0]) == (abs(force) > k1 * c)


def test_clearance_is_beam_only():
    rig = cantilever_with_gap(10.0)
    for call in (lambda: run_sweep(rig, (LoadCase(0.1, 0.0),), SweepSettings(model="hybrid")),
                 lambda: prepare_model(rig, SweepSettings(model="solid"))):  # before any meshing
        with pytest.raises(ModelError, match="bearing.s. tip_bearing have a radial clearance .* only the beam model"):
            call()


# ---- proportional lateral load, shear, force table ------------------------------------------------------

def test_proportional_lateral_load_and_its_reaction():
    """F = f T1 at the tip, reacted (−F) at mid-length a = L/2 on the same cantilever:
    tip = F (L³/3EI + L/κGA) − F (a³/3EI + a/κGA + a²(L − a)/2EI)."""
    f, t1, a = -35.0, 0.4, L / 2 * MM
    reacted = cantilever(torque_lateral_loads=[tip_load(f, reacted_on={"part": "left", "x_mm": L / 2})])
    alone = cantilever(torque_lateral_loads=[tip_load(f)])
    force = f * t1
    expected = force * TIP_COMPLIANCE - force * (a**3 / (3 * R.EI) + a / R.kGA + a**2 * (L * MM - a) / (2 * R.EI))
    cases = (LoadCase(t1, 0.0),)
    assert_close(run_sweep(reacted, cases).cases[0].paths["input"].uy_mm[-1] * MM, expected, TOL)
    assert_close(run_sweep(alone, cases).cases[0].paths["input"].uy_mm[-1] * MM, force * TIP_COMPLIANCE, TOL)
    # along direction 90°: a Z force, no Y
    sideways = cantilever(torque_lateral_loads=[tip_load(f, direction_deg=90.0)])
    assert np.abs(run_sweep(sideways, cases).cases[0].paths["input"].uy_mm).max() < 1e-12


@pytest.mark.parametrize(("beam", "shear_share", "make"),
                         [({"shear_deformation": False}, 0.0, shaft), ({}, 1.0, shaft),
                          ({"shear_flexibility_factor": 0.5}, 0.5, shaft),
                          ({"shear_deformation": False}, 1.0, body)],
                         ids=["euler_bernoulli", "timoshenko", "half_shear", "body_stays_timoshenko"])
def test_euler_bernoulli_and_timoshenko_cantilever(beam, shear_share, make):
    """Stubby cantilever (Ø40, L = 120 mm) with a tip force P: PL³/3EI + share · PL/κGA (+ the clamp's P/k + PL²/k_θ).

    The switch acts on shafts; a body (housing) keeps its shear flexibility."""
    stubby = rigidities(CircularSection(0.04))
    length, force = 0.12, 500.0
    rig = make_rig([make("stub", 0.0, 120.0, 40.0)], "stub", "stub", mounts=[mount("clamp", "stub", 0.0)],
                   torque_lateral_loads=[tip_load(force, x_mm=120.0, part="stub")], beam=beam)
    bending, shear = force * length**3 / (3 * stubby.EI), force * length / stubby.kGA
    assert shear / bending > 0.05  # the two models differ by more than any tolerance here
    tip = run_sweep(rig, (LoadCase(1.0, 0.0),)).cases[0].paths["input"].uy_mm[-1] * MM
    clamp = force / (HUGE * 1e6) + force * length**2 / HUGE_ROTATION
    assert_close(tip, bending + shear_share * shear + clamp, 1e-9)


@pytest.mark.parametrize(("apply", "scale"), [(True, 1.0), (True, -1.5), (False, 2.0)])
def test_force_table_scale(apply, scale):
    """Single force F at the tip and a pair (+F at the tip, −F at mid-length): both times ``scale``."""
    f_single, f_pair, a = 6.0, 10.0, L / 2 * MM
    table = {"apply": apply, "scale": scale,
             "singles": [{"label": "S", "force_N": f_single, "at": {"part": "left", "x_mm": L}}],
             "pairs": [{"label": "P", "force_N": f_pair, "plus_at": {"part": "left", "x_mm": L},
                        "minus_at": {"part": "left", "x_mm": L / 2}}]}
    tip = run_sweep(cantilever(force_table=table), (LoadCase(0.0, 0.0),)).cases[0].paths["input"].uy_mm[-1] * MM
    mid_load_at_tip = a**3 / (3 * R.EI) + a / R.kGA + a**2 * (L * MM - a) / (2 * R.EI)
    expected = (f_single + f_pair) * TIP_COMPLIANCE - f_pair * mid_load_at_tip
    if apply:
        assert_close(tip, scale * expected, TOL)
    else:
        assert tip == 0.0
