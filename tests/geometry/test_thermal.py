"""Temperatures (``[thermal]``): free growth against α·L·ΔT, rigid-body motion of a uniformly warm rig,
support lifts against α·h·ΔT, the solid's initial-strain load, and named input errors.

Every expected value is a hand calculation: the models are exact for a uniform strain (beams per
element, P2 tetrahedra hold a linear displacement field), so the tolerances are rounding.
"""

from __future__ import annotations

import numpy as np
import pytest
import skfem
from closed_form_rigs import STEEL, body, make_rig, mount, rest_displacement, shaft, value

from rvcoax.fem import solid
from rvcoax.fem.assembly import assemble_matrix
from rvcoax.fem.solvers import prepare
from rvcoax.geometry.model.system import assemble_beam
from rvcoax.geometry.schema import Rig
from rvcoax.geometry.thermal import free_axial_growth_um, mount_lift_um, radial_growth_um
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.sweep import run_sweep

ALPHA = 11.5e-6  # 1/K
WARM_STEEL = {**STEEL, "thermal_expansion_per_K": ALPHA}


def warm(rig: Rig, **thermal) -> Rig:
    data = rig.model_dump(by_alias=True)
    data["materials"]["steel"] = WARM_STEEL
    data["thermal"] = thermal
    for m in data["mounts"]:
        m.setdefault("height_above_bed_mm", 150.0)
        if m["height_above_bed_mm"] is None:
            m["height_above_bed_mm"] = 150.0
    return Rig.model_validate(data)


def test_free_axial_and_radial_growth():
    """A shaft clamped at x = 0 (its clamp on a cold support) grows ε L at its free end; diameters ε d."""
    rig = warm(make_rig([shaft("s", 0.0, 200.0, 20.0)], "s", "s", mounts=[mount("clamp", "s", 0.0)]),
               temperature_rise_K={"s": 40.0}, support_temperature_rise_K={"clamp": 0.0})
    frame, u = rest_displacement(rig)
    growth = ALPHA * 40.0 * 0.2  # m
    assert value(frame, u, "s", 200.0, 0) == pytest.approx(growth, rel=1e-9)
    assert value(frame, u, "s", 100.0, 0) == pytest.approx(growth / 2, rel=1e-9)
    assert free_axial_growth_um(rig, "s") == pytest.approx(growth * 1e6, rel=1e-14)
    assert radial_growth_um(rig)["s"] == [pytest.approx((ALPHA * 40.0 * 20.0 * 1e3, 0.0), rel=1e-14)]
    assert np.abs(u[1::6]).max() < 1e-15 and np.abs(u[5::6]).max() < 1e-15  # no lateral motion, no tilt


def uniform_rig() -> Rig:
    """Two shafts in a housing and a bearing block, joined by a coupling, on three supports."""
    bearings = [{"name": f"b{x:g}", "shaft": "in", "housing": "block", "x_mm": x, "radial_stiffness_N_per_um": 50.0,
                 "axial_stiffness_N_per_um": 20.0} for x in (20.0, 80.0)]
    bearings += [{"name": f"c{x:g}", "shaft": "out", "housing": "case", "x_mm": x, "radial_stiffness_N_per_um": 60.0,
                  "axial_stiffness_N_per_um": 20.0 if x == 150 else 0.0} for x in (150.0, 250.0)]
    coupling = {"name": "C", "from": {"part": "in", "x_mm": 95.0}, "to": {"part": "out", "x_mm": 125.0},
                "centre_x_mm": 110.0, "radial_stiffness_N_per_mm": 720.0, "angular_stiffness_Nm_per_rad": 150.0,
                "torsional_stiffness_Nm_per_rad": 3.5e4, "axial_stiffness_N_per_mm": 50.0}
    springs = {"stiffness": [500.0, 500.0, 500.0], "rotational": [2e6, 2e6, 2e6]}
    return make_rig([shaft("in", 0.0, 100.0), body("block", 0.0, 100.0, 80.0), shaft("out", 120.0, 280.0, 25.0),
                     body("case", 130.0, 270.0, 90.0)], "in", "out", bearings=bearings, couplings=[coupling],
                    mounts=[mount("m_block", "block", 50.0, **springs), mount("m_case1", "case", 140.0, **springs),
                            mount("m_case2", "case", 260.0, **springs),
                            mount("brake", "out", 200.0, [0.0, 0.0, 0.0], [1e3, 0.0, 0.0])])  # holds the line in torsion


def test_equal_temperatures_everywhere_move_the_rig_as_a_rigid_body():
    """Every part, support and the bed 25 K warmer, one α: u = ε (x − x_fixed) along x, ε h up, no tilt, no force."""
    rise, x_fixed, height = 25.0, 40.0, 150.0
    rig = warm(uniform_rig(), temperature_rise_K={p: rise for p in ("in", "block", "out", "case")},
               bed_temperature_rise_K=rise, bed_material="steel", bed_fixed_x_mm=x_fixed)
    strain = ALPHA * rise
    frame, u = rest_displacement(rig)
    x = frame.node_x_mm * 1e-3
    assert u[0::6] == pytest.approx(strain * (x - x_fixed * 1e-3), rel=1e-9, abs=1e-12 * strain)
    assert u[1::6] == pytest.approx(np.full(x.size, strain * height * 1e-3), rel=1e-9)
    assert np.abs(u[2::6]).max() < 1e-15 and np.abs(u[3::6]).max() < 1e-15
    assert np.abs(u[4::6]).max() < 1e-15 and np.abs(u[5::6]).max() < 1e-15  # rotations: no tilt
    # stress-free: K u equals the initial-strain load term by term, so no spring carries a force
    system = assemble_beam(rig)
    assert np.abs(system.stiffness @ u - system.unit_loads["prestrain"]).max() < 1e-6  # N
    # through the sweep, measured from the unloaded geometry: Y constant along both paths, zero tilt
    result = run_sweep(rig, (LoadCase(0.0, 0.0),)).cases[0]
    for which in ("input", "output"):
        path = result.paths[which]
        assert path.uy_mm == pytest.approx(np.full(path.uy_mm.size, strain * height), rel=1e-9)
        assert np.abs(path.rotation_z_rad).max() < 1e-15


def test_unequal_support_temperatures_tilt_the_block_through_the_supports():
    """A block on two pin supports (no rotational stiffness) follows their lifts α ΔT_i h exactly."""
    spring = {"stiffness": [1e3, 1e3, 1e3], "rotational": [1e3, 0.0, 0.0]}
    rig = warm(make_rig([body("block", 0.0, 100.0, 100.0)], "block", "block",
                        mounts=[mount("m0", "block", 0.0, **spring), mount("m1", "block", 100.0, **spring)]),
               support_temperature_rise_K={"m0": 10.0, "m1": 30.0})
    lifts = [mount_lift_um(rig, m) * 1e-3 for m in rig.mounts]  # mm
    assert lifts == pytest.approx([ALPHA * 10 * 150.0, ALPHA * 30 * 150.0], rel=1e-14)
    path = run_sweep(rig, (LoadCase(0.0, 0.0),)).cases[0].paths["input"]
    expected = lifts[0] + (lifts[1] - lifts[0]) * path.station_mm / 100.0
    assert np.abs(path.uy_mm - expected).max() < 1e-9 * lifts[1]
    assert np.abs(path.rotation_z_rad - (lifts[1] - lifts[0]) / 100.0).max() < 1e-9 * lifts[1] / 100.0


def test_solid_thermal_strain_load_gives_free_growth():
    """P2 box on symmetry planes (u_x = 0 at x = 0, u_y = 0 at y = 0, u_z = 0 at z = 0): u = ε x exactly."""
    mesh = skfem.MeshTet.init_tensor(np.linspace(0, 0.04, 3), np.linspace(0, 0.02, 2), np.linspace(0, 0.01, 2))
    basis = solid.solid_basis(skfem.MeshTet2.from_mesh(mesh))
    strain, youngs, poisson = ALPHA * 60.0, 2.0e11, 0.3
    stiffness = assemble_matrix(basis.N, [solid.stiffness_triplets(basis, youngs, poisson)])
    load = solid.thermal_strain_vector(basis, youngs, poisson, strain)
    locations = basis.doflocs
    components = solid.dof_components(basis)
    fixed = np.flatnonzero(np.isclose(locations[components, np.arange(basis.N)], 0.0))
    free = np.setdiff1d(np.arange(basis.N), fixed)
    u = np.zeros(basis.N)
    u[free] = prepare(stiffness[free][:, free].tocsr()).solve(load[free])
    expected = strain * locations[components, np.arange(basis.N)]
    assert u == pytest.approx(expected, rel=1e-9, abs=1e-9 * strain * 0.04)


@pytest.mark.parametrize("change, words", [
    ({"materials_alpha": False}, "has no thermal_expansion_per_K"),
    ({"height": False}, "height_above_bed_mm: required"),
    ({"bed": True}, "bed_material: required"),
    ({"unknown": True}, "unknown part 'nowhere'"),
])
def test_thermal_input_errors_name_the_key(change, words):
    data = make_rig([shaft("s", 0.0, 200.0)], "s", "s", mounts=[mount("clamp", "s", 0.0)]).model_dump(by_alias=True)
    data["materials"]["steel"] = STEEL if change.get("materials_alpha") is False else WARM_STEEL
    if change.get("height") is not False:
        data["mounts"][0]["height_above_bed_mm"] = 100.0
    data["thermal"] = {"temperature_rise_K": {"s": 10.0}}
    if change.get("bed"):
        data["thermal"]["bed_temperature_rise_K"] = 5.0
    if change.get("unknown"):
        data["thermal"]["temperature_rise_K"]["nowhere"] = 1.0
    with pytest.raises(ValueError, match=words):
        Rig.model_validate(data)


def test_temperature_rise_effect_lifts_the_supports():
    from rvcoax.geometry.effects import candidate_effects, effect_by_name
    from rvcoax.geometry.parameters import get_parameter

    spring = {"stiffness": [1e3, 1e3, 1e3], "rotational": [1e3, 0.0, 0.0]}
    rig = warm(make_rig([body("block", 0.0, 100.0, 100.0)], "block", "block",
                        mounts=[mount("m0", "block", 0.0, **spring), mount("m1", "block", 100.0, **spring)]))
    effect = effect_by_name(rig, "temperature_rise@block")
    assert (effect.parameters[0].name, effect.parameters[0].unit, effect.linear) == ("temperature_rise_K", "°C", True)
    changed = effect.apply(rig, [20.0])
    assert get_parameter(changed, "thermal.temperature_rise_K.block") == 20.0
    assert [mount_lift_um(changed, m) for m in changed.mounts] == pytest.approx([ALPHA * 20 * 150e3] * 2, rel=1e-14)
    # without [thermal] there is no such candidate (a temperature needs α and support heights)
    plain = make_rig([body("block", 0.0, 100.0, 100.0)], "block", "block", mounts=[mount("m0", "block", 0.0)])
    assert not [e for e in candidate_effects(plain) if e.kind == "temperature_rise"]


def test_a_fitted_temperature_is_written_into_the_rig_file():
    """The discrepancy workflow writes fitted effects into the user's file: a temperature lands in the inline table
    of [thermal] temperature_rise_K (no comment there: TOML has none inside inline tables)."""
    from rvcoax.geometry.effects import effect_by_name
    from rvcoax.geometry.rigfile import parse_rig_text, reference_rig_text
    from rvcoax.geometry.rigwrite import updated_rig_text

    text = reference_rig_text()
    for density, alpha in (("7870", "11.0e-6"), ("7210", "10.0e-6"), ("7850", "12.0e-6")):
        key = f"density_kg_per_m3 = {density}            # [P]"
        text = text.replace(key, f"{key}\nthermal_expansion_per_K = {alpha}")
    text = text.replace("rotational_stiffness_Nm_per_rad = [", "height_above_bed_mm = 100\nrotational_stiffness_Nm_per_rad = [",
                        7)  # the seven mounts
    text += "\n[thermal]\ntemperature_rise_K = { reducer = 20.0 }\n"
    rig = parse_rig_text(text)
    for part, expected in (("reducer", 25.0), ("input_shaft", 5.0)):
        changed = effect_by_name(rig, f"temperature_rise@{part}").apply(rig, [5.0])
        written, keys = updated_rig_text(text, changed, "fitted")
        assert keys == [f"thermal.temperature_rise_K.{part}"]
        assert parse_rig_text(written).thermal.temperature_rise_K[part] == expected


def test_ring_temperatures_change_a_ball_bearing_s_clearance_by_alpha_d_delta_t():
    # inner ring as warm as its shaft, outer ring as its housing, balls at the mean: ΔP_d = −α_b d_m (ΔT_i − ΔT_o)
    from rvcoax.geometry.ball_model import (
        BEARING_STEEL_EXPANSION_PER_K,
        OperatingClearanceError,
        geometry_of,
        operating_geometry,
        thermal_clearance_change_um,
    )
    from rvcoax.geometry.variants import reference_from_geometry

    rig = reference_from_geometry(("thermal", "ball_bearings"))
    rises = rig.thermal.temperature_rise_K
    balls = [b for b in rig.bearings if b.model == "ball"]
    expected = {}
    for b in balls:
        d_m = {"6204": 33.5e-3, "6206": 46.0e-3}[b.designation]
        inner, outer = rises.get(b.shaft, 0.0), rises.get(b.housing, 0.0)
        assert inner - outer == 10.0  # the warm-running reading: shafts 10 K above their blocks
        expected[b.name] = -BEARING_STEEL_EXPANSION_PER_K * d_m * (inner - outer) * 1e6
        assert thermal_clearance_change_um(rig, b) == pytest.approx(expected[b.name], rel=1e-12)
        assert operating_geometry(rig, b).clearance_m == pytest.approx(
            geometry_of(b).clearance_m + expected[b.name] * 1e-6, rel=1e-12)
    assert expected["input_B1"] == pytest.approx(-4.02, rel=1e-12)  # 12e-6 · 33.5 mm · 10 K
    # the sweep's nonlinear law runs at that operating clearance
    sweep = run_sweep(rig, (LoadCase(1.43, 200.0),))
    for model in sweep.nonlinear_bearings.balls:
        bearing = next(b for b in balls if b.name == model.name)
        assert model.geometry.clearance_m == pytest.approx(geometry_of(bearing).clearance_m + expected[bearing.name] * 1e-6,
                                                           rel=1e-12)
    # equal rises of shaft and housing leave the clearance; a shaft far warmer than its housing closes it: refused
    level = rig.model_copy(update={"thermal": rig.thermal.model_copy(
        update={"temperature_rise_K": {**rises, "input_bearing_block": rises["input_shaft"]}})})
    assert thermal_clearance_change_um(level, balls[0]) == 0.0
    hot = rig.model_copy(update={"thermal": rig.thermal.model_copy(
        update={"temperature_rise_K": {**rises, "input_shaft": 50.0}})})
    with pytest.raises(OperatingClearanceError, match=r"bearings 'input_B1'.*takes up 20.1 µm.*more than its 12.5 µm"):
        operating_geometry(hot, balls[0])
