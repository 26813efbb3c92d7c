"""Gear meshes from gear data (``[[gear_meshes]]``): geometry, ISO 6336-1 stiffness, load sharing, forces.

Every check is against a hand calculation written out here: ISO 6336-1's q′ polynomial at its
limits, the involute contact ratio of a standard pair, the two-mesh load split on a common sun
rotation, the torque balance of the mesh forces, and the reference rig's input stage solved with
gear data against the typed-in ``imbalance`` it replaces.
"""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest

from rvcoax.fem.system import factorize
from rvcoax.geometry.gears import GearStage, load_sharing, mesh_forces, single_stiffness
from rvcoax.geometry.model.loads import gear_mesh_forces, located_unit_loads
from rvcoax.geometry.model.system import assemble_beam
from rvcoax.geometry.rigfile import RigFileError, parse_rig, reference_rig_text

SPUR = GearStage(1.0, (20, 40), 20.0, 10.0)

FROM_GEAR_DATA = {  # the reference rig's input stage from gear data (docs/rig-file.md)
    "name": "input_gear_mesh", "torque": "T1",
    "on": {"part": "input_shaft", "x_mm": 330.0, "band_mm": [322.0, 340.0]},
    "reacted_on": {"part": "reducer", "x_mm": 330.0},
    "normal_module_mm": 1.0, "sun_teeth": 20, "planet_teeth": 40, "normal_pressure_angle_deg": 20.0,
    "face_width_mm": 10.0, "planet_angles_deg": [90.0, 270.0], "planet_position_errors_um": [0.0, 2.0],
}


def reference(gear: dict | None = None, keep_typed_in: bool = False):
    data = tomllib.loads(reference_rig_text())
    if not keep_typed_in:
        data["torque_lateral_loads"] = [t for t in data["torque_lateral_loads"] if t["name"] != "sun_gear_load_sharing"]
    if gear is not None:
        data["gear_meshes"] = [gear]
    return parse_rig(data, "test")


# ---- geometry and ISO 6336-1 -----------------------------------------------------------------------------

def test_standard_spur_pair_geometry_and_contact_ratio():
    # r = m z / 2 = 10 and 20 mm, a = 30 mm; r_b = r cos 20°; r_a = r + m
    rb1, rb2 = 10 * math.cos(math.radians(20)), 20 * math.cos(math.radians(20))
    eps = (math.sqrt(11**2 - rb1**2) + math.sqrt(21**2 - rb2**2) - 30 * math.sin(math.radians(20))) \
        / (math.pi * math.cos(math.radians(20)))
    assert SPUR.centre_distance_mm == pytest.approx(30.0, rel=1e-14)
    assert SPUR.contact_ratio == pytest.approx(eps, rel=1e-14)
    assert eps == pytest.approx(1.635, abs=1e-3)


def test_iso6336_single_stiffness_formula():
    # q′ = C1 + C2/20 + C3/40 (x = 0, β = 0); c′ = (1/q′) · 0.8 · C_R · C_B · 1, C_B = 1 + 0.5 (1.2 − 1.25) = 0.975
    stiffness = single_stiffness(SPUR)
    q = 0.04723 + 0.15551 / 20 + 0.25791 / 40
    assert stiffness.q_prime_mm_um_per_N == pytest.approx(q, rel=1e-14)
    assert stiffness.C_B == pytest.approx(0.975, rel=1e-14)
    assert stiffness.single == pytest.approx(0.8 * 0.975 / q, rel=1e-14)
    assert stiffness.mesh == pytest.approx(stiffness.single * (0.75 * SPUR.contact_ratio + 0.25), rel=1e-14)
    # ISO 6336-1 quotes c′ ≈ 14 and c_γα ≈ 20 N/(mm·µm) for standard steel gears (Method C)
    assert 12.0 < stiffness.single < 15.0 and 17.0 < stiffness.mesh < 22.0
    # infinite teeth: q′ = C1; a cast-iron planet lowers c′ by E_eq / E_st
    rack = single_stiffness(GearStage(1.0, (10**9, 10**9)))
    assert rack.theoretical == pytest.approx(1 / 0.04723, rel=1e-6)
    mixed = single_stiffness(SPUR, youngs_moduli_pa=(2.06e11, 1.57e11))
    assert mixed.single / stiffness.single == pytest.approx(2 * 1.57 / (2.06 + 1.57), rel=1e-12)


def test_helical_gear_factors():
    helical = GearStage(1.0, (20, 40), 20.0, 10.0, helix_angle_deg=15.0)
    alpha_t = math.atan(math.tan(math.radians(20)) / math.cos(math.radians(15)))
    beta_b = math.atan(math.tan(math.radians(15)) * math.cos(alpha_t))
    assert helical.transverse_pressure_angle == pytest.approx(alpha_t, rel=1e-14)
    assert helical.virtual_teeth(0) == pytest.approx(20 / (math.cos(beta_b) ** 2 * math.cos(math.radians(15))))
    assert single_stiffness(helical).cos_beta == pytest.approx(math.cos(math.radians(15)))


# ---- load sharing and forces -----------------------------------------------------------------------------

def test_position_error_gives_the_closed_form_share():
    # two meshes k1, k2, errors e1, e2: W1 = k1 F/K + k1 k2 (e2 − e1)/K, W2 = F − W1
    k1, k2, e1, e2, force = 1.4e8, 1.1e8, 0.0, 2e-6, 300.0
    share, constant = load_sharing(np.array([k1, k2]), np.array([e1, e2]))
    w = share * force + constant
    expected = k1 * force / (k1 + k2) + k1 * k2 * (e2 - e1) / (k1 + k2)
    assert w[0] == pytest.approx(expected, rel=1e-14)
    assert w.sum() == pytest.approx(force, rel=1e-14)
    # W1 − W2 = imbalance · F + k_eff Δε, the law of today's typed-in load sharing
    assert w[0] - w[1] == pytest.approx((k1 - k2) / (k1 + k2) * force + 2 * k1 * k2 / (k1 + k2) * (e2 - e1), rel=1e-12)


@pytest.mark.parametrize("angles", [[90.0, 270.0], [0.0, 120.0, 240.0], [30.0, 210.0]])
def test_equal_sharing_gives_no_net_lateral_force(angles):
    n = len(angles)
    share, constant = load_sharing(np.full(n, 1.3e8), np.full(n, 3e-6))  # equal errors: a uniform shift
    assert np.allclose(constant, 0.0, atol=1e-9)
    forces = mesh_forces(SPUR, angles, share * 500.0)
    assert np.abs(forces.force_N).max() < 1e-12 * 500.0
    assert np.abs(forces.moment_Nm).max() < 1e-14 * 500.0


@pytest.mark.parametrize("helix", [0.0, 12.0, -20.0])
def test_mesh_forces_balance_the_torque_exactly(helix):
    stage = GearStage(1.25, (18, 45), 20.0, 12.0, helix, profile_shift=(0.3, -0.1))
    torque = 7.3  # N·m on the sun
    share, constant = load_sharing(np.array([1.5e8, 1.2e8]), np.array([0.0, 4e-6]))
    loads = share * torque / (stage.base_radius_mm(0) * 1e-3) + constant * 0.0
    forces = mesh_forces(stage, [90.0, 270.0], loads)
    assert forces.torque_Nm == pytest.approx(-torque, rel=1e-13)
    # per mesh: radial = tangential · tan α_wt, axial = tangential · tan β_w
    alpha = stage.working_pressure_angle
    tangential = loads * math.cos(alpha)
    assert np.abs(forces.per_mesh_N[:, 2]) == pytest.approx(tangential * math.tan(alpha), rel=1e-12)
    beta_w = math.atan(math.tan(stage.base_helix_angle) / math.cos(alpha))
    assert forces.per_mesh_N[:, 0] == pytest.approx(tangential * math.tan(beta_w), rel=1e-12, abs=1e-14)
    # net: planets on ±Z, the load difference pushes the sun along Y (tangential) and Z (radial)
    difference = loads[0] - loads[1]
    assert forces.force_N[1] == pytest.approx(difference * math.cos(alpha), rel=1e-12)
    assert forces.force_N[2] == pytest.approx(-difference * math.sin(alpha), rel=1e-12)


# ---- in the rig ------------------------------------------------------------------------------------------

def test_rig_gear_mesh_forces_and_their_reaction():
    rig = reference(FROM_GEAR_DATA)
    per_torque, engaged, stiffness = gear_mesh_forces(rig, rig.gear_meshes[0])
    c_mesh = single_stiffness(SPUR, youngs_moduli_pa=(2.06e11, 2.06e11)).mesh  # Q460 sun, same planet
    assert stiffness == pytest.approx(np.full(2, c_mesh * 10.0 * 1e6), rel=1e-12)
    # equal stiffness: no torque-proportional lateral force; the 2 µm error gives ∓k Δε / 2 per mesh
    assert np.abs(per_torque.force_N).max() < 1e-12
    k = stiffness[0]
    assert engaged.per_mesh_N[0, 1] == pytest.approx(k * 1e-6 * math.cos(math.radians(20)), rel=1e-12)
    assert not any(x.part in ("input_shaft", "reducer") for x in located_unit_loads(rig)["engaged_T1"])
    loads = located_unit_loads(rig)["gear_contact_T1"]  # the gear meshes' constant part, weighted by T1 / T_c
    on, reaction = loads
    assert (on.part, reaction.part) == ("input_shaft", "reducer")
    assert np.array(on.force_N) == pytest.approx(-np.array(reaction.force_N))
    # the +Z planet (planet 1) carries more: it pushes the sun to +Y (its tangential reaction) and −Z
    assert on.force_N[1] > 0 and on.force_N[2] < 0


def test_reference_rig_input_stage_from_gear_data_solves_and_matches_the_typed_in_law():
    typed = reference(keep_typed_in=True)
    geared = reference(FROM_GEAR_DATA)
    per_torque, engaged, stiffness = gear_mesh_forces(geared, geared.gear_meshes[0])
    # the typed-in law: net = k_eff Δε (/cos α there, along the line of action here): same size of force
    k_eff = 2 * stiffness[0] * stiffness[1] / stiffness.sum()
    assert np.linalg.norm(engaged.force_N) == pytest.approx(k_eff * 2e-6, rel=1e-12)
    system = assemble_beam(geared)
    solver = factorize(system.stiffness, system.elimination)
    u = solver.solve(system.unit_loads["gear_contact_T1"])
    node = system.frame.node("input_shaft", 330.0)
    assert u[6 * node + 1] > 0  # the sun moves towards +Y with its net force
    assert len(assemble_beam(typed).unit_loads) == len(system.unit_loads)


def test_bad_gear_data_is_named():
    with pytest.raises(RigFileError, match="profile shifts is too negative"):
        reference({**FROM_GEAR_DATA, "profile_shift": [-0.8, -0.8]})
    with pytest.raises(RigFileError, match="overlap"):
        reference({**FROM_GEAR_DATA, "planet_angles_deg": [0.0, 30.0]})
    with pytest.raises(RigFileError, match="one per planet"):
        reference({**FROM_GEAR_DATA, "planet_position_errors_um": [1.0]})
    with pytest.raises(RigFileError, match="unknown material"):
        reference({**FROM_GEAR_DATA, "planet_material": "bronze"})


def test_mesh_position_error_effect_moves_the_first_planet():
    from rvcoax.geometry.effects import effect_by_name

    rig = reference({**FROM_GEAR_DATA, "planet_position_errors_um": [0.0, 0.0]})
    effect = effect_by_name(rig, "mesh_position_error@input_gear_mesh")
    assert (effect.parameters[0].name, effect.parameters[0].unit, effect.linear) == ("position_error_um", "µm", True)
    changed = effect.apply(rig, [2.0])
    assert changed.gear_meshes[0].planet_position_errors_um == [2.0, 0.0]
    _, engaged, stiffness = gear_mesh_forces(changed, changed.gear_meshes[0])
    assert np.linalg.norm(engaged.force_N) == pytest.approx(stiffness[0] * 2e-6, rel=1e-12)  # k_eff = k
    assert np.abs(gear_mesh_forces(rig, rig.gear_meshes[0])[1].force_N).max() == 0.0


def test_contact_loss_below_the_full_contact_torque():
    """Two equal meshes, the second 2 µm behind: it closes at F_c = k Δε (W2 = F/2 − kΔε/2 = 0); below, the first
    carries everything; above, the linear split holds."""
    from rvcoax.geometry.gears import contact_loads, full_contact_force

    k, error = np.array([1.8e8, 1.8e8]), np.array([0.0, 2e-6])
    share, constant = load_sharing(k, error)
    closing = full_contact_force(share, constant)
    assert closing == pytest.approx(1.8e8 * 2e-6, rel=1e-14)
    assert contact_loads(k, error, 0.5 * closing) == pytest.approx([0.5 * closing, 0.0])
    above = 3.0 * closing
    assert contact_loads(k, error, above) == pytest.approx(share * above + constant, rel=1e-14)
    rig = reference({**FROM_GEAR_DATA})
    from rvcoax.geometry.catalogue import plausibility_warnings
    from rvcoax.geometry.model.loads import gear_mesh_full_contact_torque

    torque = gear_mesh_full_contact_torque(rig, rig.gear_meshes[0])
    stiffness = gear_mesh_forces(rig, rig.gear_meshes[0])[2][0]
    assert torque == pytest.approx(stiffness * 2e-6 * SPUR.base_radius_mm(0) * 1e-3, rel=1e-12)
    # two planets: the sweep follows the contact loss exactly (below), nothing to warn about; three different
    # position errors close one after another, which the sweep interpolates: said before the solve
    assert not any("a planet mesh opens" in w for w in plausibility_warnings(rig))
    three = reference({**FROM_GEAR_DATA, "planet_angles_deg": [90.0, 210.0, 330.0],
                       "planet_position_errors_um": [0.0, 1.0, 2.0]})
    assert any("a planet mesh opens" in w and "interpolates" in w for w in plausibility_warnings(three))


def _true_mesh_forces(rig, torque_Nm: float):
    """The net force of the stage on the sun for ``torque_Nm`` from the closed-form contact share: the meshes
    that touch split F = |T| / r_b (:func:`contact_loads`), odd in T."""
    from rvcoax.geometry.gears import contact_loads

    mesh = rig.gear_meshes[0]
    _, _, stiffness = gear_mesh_forces(rig, mesh)
    errors = np.asarray(mesh.planet_position_errors_um) * 1e-6
    loads = contact_loads(stiffness, errors, abs(torque_Nm) / (mesh.stage.base_radius_mm(0) * 1e-3))
    sign = float(rig.torques.T1.sign) * np.sign(torque_Nm)
    return mesh_forces(mesh.stage, mesh.planet_angles_deg, sign * loads)


def test_the_sweep_loads_follow_the_closed_form_share_through_contact_loss():
    # two equal meshes, the second 2 µm behind: below T_c = k Δε r_b the first carries all of F and the second
    # none; the sweep's unit loads weighted by T and clip(T / T_c) give exactly those forces at every torque
    from rvcoax.geometry.model.loads import case_weights, gear_contact_torques

    rig = reference(FROM_GEAR_DATA)
    per_torque, engaged, _ = gear_mesh_forces(rig, rig.gear_meshes[0])
    contact = gear_contact_torques(rig)
    t_c = contact[0]
    assert t_c > 1.0 and contact[1] == 0.0
    for torque in (0.05 * t_c, 0.5 * t_c, 0.999 * t_c, t_c, 1.7 * t_c, 40.0 * t_c, -0.3 * t_c, -3.0 * t_c):
        weights = case_weights(torque, 0.0, include_rest=False, contact_torques_Nm=contact)
        swept = per_torque.per_mesh_N * weights["T1"] + engaged.per_mesh_N * weights["gear_contact_T1"]
        expected = _true_mesh_forces(rig, torque).per_mesh_N
        np.testing.assert_allclose(swept, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())
        if abs(torque) < t_c:
            assert np.abs(swept[1]).max() < 1e-9 * np.abs(swept[0]).max()  # the lagging mesh carries nothing
    # the old all-in-contact weight (sign T) would pull on the open mesh
    weights = case_weights(0.5 * t_c, 0.0, include_rest=False)
    wrong = per_torque.per_mesh_N * weights["T1"] + engaged.per_mesh_N * weights["gear_contact_T1"]
    assert np.abs(wrong[1]).max() > 0.1 * np.abs(wrong[0]).max()


def test_the_input_shaft_s_supports_carry_the_closed_form_gear_force_below_contact():
    from rvcoax.geometry.model.loads import gear_contact_torques
    from rvcoax.loadcases.cases import LoadCase
    from rvcoax.results.connections import connection_states
    from rvcoax.results.sweep import run_sweep

    rig = reference(FROM_GEAR_DATA)
    t_c = gear_contact_torques(rig)[0]
    cases = (LoadCase(0.3 * t_c, 10.0), LoadCase(2.0 * t_c, 10.0))
    sweep = run_sweep(rig, cases)
    states = connection_states(sweep, "measured")  # from rest: the torque's loads only
    springs = [states.index("bearing", b.name) for b in rig.bearings if b.shaft == "input_shaft"]
    springs += [states.index("coupling", c.name) for c in rig.couplings if c.to.part == "input_shaft"]
    for i, case in enumerate(cases):
        gear = _true_mesh_forces(rig, case.input_torque_Nm).force_N
        supports = states.force_on_b[i, springs, :3].sum(axis=0)
        np.testing.assert_allclose((supports + gear)[1:], 0.0, atol=1e-9 * np.abs(gear).max())
    # below T_c the net force is the one mesh's own (|F| = W = F), above it k Δε's: the rig sees the difference
    below = np.linalg.norm(_true_mesh_forces(rig, 0.3 * t_c).force_N)
    assert below == pytest.approx(0.3 * t_c / (SPUR.base_radius_mm(0) * 1e-3), rel=1e-12)
