"""The effect catalogue (rvcoax.geometry.effects) on the reference rig, beam model.

Every candidate at zero reproduces the base sweep, linear ones are affine, each changes the Y
path of the shaft(s) it physically reaches at its typical value (Y measured from the unloaded
geometry), and each applied rig is valid, survives a TOML round trip, and is described by its
``rig_changes`` and ``new_items``.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from rigdata import dump_toml

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.effects import candidate_effects, effect_by_name
from rvcoax.geometry.parameters import get_parameter, with_parameters
from rvcoax.geometry.rigfile import load_rig, parse_rig
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import paper_cases
from rvcoax.results.sweep import prepare_model, run_sweep

CASES = paper_cases()
SEEN = 1e-9  # mm: a change of Y larger than this is a real change (rounding is ~1e-15 mm)
# The reducer joins the input shaft in torsion only (sun_gear_mesh), so the two sides are
# laterally independent: an effect upstream of the reducer moves the input shaft only.
INPUT_SIDE = {"motor_front", "motor_rear", "input_sensor_a", "input_sensor_b", "input_B1", "input_B2", "C1", "C2",
              "motor_housing", "input_sensor_housing", "input_bearing_block"}
OUTPUT_SIDE = {"output_B1", "output_B2", "output_sensor_a", "output_sensor_b", "brake_a", "brake_b", "C3", "C4",
               "reducer", "output_bearing_block", "output_sensor_housing", "brake_housing"}
GLOBAL_SHAFTS = {
    "self_weight": {"input", "output"},
    "force_pairs": {"input"},  # F3, F5, F9 act at one point each (cancel); F1 and F2 sit upstream
    "mesh_force@reducer_input": {"input", "output"},  # on the input gear, reacted on the reducer
    "mesh_position_error@sun_gear_load_sharing": {"input", "output"},  # same place as the mesh force
    "mesh_position_error@crankshaft_load_sharing": {"output"},  # on the output carrier, reacted in the reducer
}


def measured_from(rig: Rig, where: str) -> Rig:
    return rig.model_copy(update={"paths": rig.paths.model_copy(update={"measured_from": where})})


def y_paths(rig: Rig, prepared=None) -> np.ndarray:
    """Y paths (cases × shafts × stations, mm)."""
    sweep = run_sweep(rig, CASES, prepared=prepared)
    return np.array([[case.paths[s].uy_mm for s in MEASURED_SHAFTS] for case in sweep.cases])


@pytest.fixture(scope="module")
def rig() -> Rig:
    return measured_from(load_rig(), "unloaded")


@pytest.fixture(scope="module")
def responses(rig):
    """Per effect: Y paths at 0, at its typical value, and at twice that (linear effects)."""
    out = {}
    for effect in candidate_effects(rig):
        typical = effect.parameters[0].typical
        entry = {"zero": y_paths(effect.apply(rig, [0.0])), "typical": y_paths(effect.apply(rig, [typical]))}
        if effect.linear:
            entry["double"] = y_paths(effect.apply(rig, [2 * typical]))
        out[effect.name] = entry
    return out


def test_reference_rig_candidates(rig):
    names = {e.name for e in candidate_effects(rig)}
    bearings = [b.name for b in rig.bearings]
    expected = ({"self_weight", "force_pairs", "mesh_force@reducer_input"}
                | {f"{kind}@{b}" for b in bearings for kind in ("bearing_stiffness", "bearing_clearance")}
                | {f"{kind}@{c.name}" for c in rig.couplings for kind in ("coupling_offset", "coupling_angle")}
                | {f"{kind}@{m.part}" for m in rig.mounts for kind in ("mount_compliance", "thermal_growth")}
                | {f"torque_reaction@{p}" for p in ("input_sensor_housing", "input_bearing_block", "reducer",
                                                    "output_bearing_block", "output_sensor_housing", "brake_housing")}
                | {f"mesh_position_error@{t.name}" for t in rig.torque_lateral_loads
                   if t.kind in ("gear_mesh_load_sharing", "crank_load_sharing")})
    assert names == expected  # no shear_deformation: the reference rig already has it
    for effect in candidate_effects(rig):
        assert len(effect.parameters) == 1 and effect.description
        p = effect.parameters[0]
        assert p.lower <= 0.0 <= p.upper and p.lower <= p.typical <= p.upper and p.typical != 0.0
        assert effect.kind == effect.name.split("@")[0]
        assert effect.location == (effect.name.split("@")[1] if "@" in effect.name else None)
        assert effect.linear == (effect.kind in ("self_weight", "force_pairs", "coupling_offset", "coupling_angle",
                                                 "mesh_force", "torque_reaction", "thermal_growth",
                                                 "mesh_position_error"))


@pytest.mark.slow
def test_every_effect_at_zero_is_the_base_rig(rig, responses):
    base = y_paths(rig)
    for name, entry in responses.items():
        assert np.abs(entry["zero"] - base).max() < 1e-12, name


@pytest.mark.slow
def test_linear_effects_are_affine(responses):
    for name, entry in responses.items():
        if "double" in entry:
            once, twice = entry["typical"] - entry["zero"], entry["double"] - entry["zero"]
            assert np.abs(twice - 2 * once).max() <= 1e-9 * np.abs(once).max() + 1e-15, name


@pytest.mark.slow
def test_nonlinear_effects_are_not_affine(rig, responses):
    """bearing_stiffness: doubling the log-factor does not double the change."""
    entry = responses["bearing_stiffness@input_B1"]
    once = entry["typical"] - entry["zero"]
    twice = y_paths(effect_by_name(rig, "bearing_stiffness@input_B1").apply(rig, [-2.0])) - entry["zero"]
    assert np.abs(twice - 2 * once).max() > 1e-3 * np.abs(once).max()


@pytest.mark.slow
def test_each_effect_moves_the_shafts_it_reaches(rig, responses):
    for effect in candidate_effects(rig):
        change = np.abs(responses[effect.name]["typical"] - responses[effect.name]["zero"]).max(axis=(0, 2))
        moved = {s for s, c in zip(MEASURED_SHAFTS, change) if c > SEEN}
        if effect.location in INPUT_SIDE:
            expected = {"input"}
        elif effect.location in OUTPUT_SIDE:
            expected = {"output"}
        else:
            expected = GLOBAL_SHAFTS[effect.name]
        assert moved == expected, (effect.name, change)
        assert all(c < 1e-12 for s, c in zip(MEASURED_SHAFTS, change) if s not in expected), (effect.name, change)


def test_torque_independent_effects_vanish_when_aligned_at_rest(rig):
    """Y = u − u_rest: a load-independent effect is not observable on a linear rig; a torque one is."""
    aligned = measured_from(rig, "aligned_at_rest")
    base = y_paths(aligned)
    for name in ("self_weight", "coupling_offset@C3", "coupling_angle@C2", "thermal_growth@reducer", "force_pairs"):
        effect = effect_by_name(aligned, name)
        assert np.abs(y_paths(effect.apply(aligned, [effect.parameters[0].typical])) - base).max() < 1e-12, name
    effect = effect_by_name(aligned, "torque_reaction@reducer")
    assert np.abs(y_paths(effect.apply(aligned, [2.0])) - base).max() > 1e-4


def test_applied_rig_round_trips_and_matches_its_changes(rig):
    for effect in candidate_effects(rig):
        values = [effect.parameters[0].typical]
        applied = effect.apply(rig, values)
        text = dump_toml(applied.model_dump(by_alias=True, exclude_none=True, mode="json"))
        assert parse_rig(tomllib.loads(text), f"<{effect.name}>") == applied, effect.name
        changes, added = effect.rig_changes(rig, values), effect.new_items(rig, values)
        assert changes or added, effect.name
        for address, value in changes.items():
            assert get_parameter(applied, address) == pytest.approx(value, rel=1e-15), (effect.name, address)
        for group, items in added.items():
            names = [item.name for item in getattr(applied, group)]
            assert all(item["name"] in names for item in items), effect.name
        # applying the changes to a rig that already has the new items gives the same rig
        if not added:
            assert with_parameters(rig, changes) == applied, effect.name


def test_new_lateral_load_is_reused_once_written(rig):
    """After the new item is in the rig, the same effect changes its value instead of adding another."""
    effect = effect_by_name(rig, "torque_reaction@reducer")
    once = effect.apply(rig, [2.0])
    again = effect_by_name(once, "torque_reaction@reducer")
    assert again.new_items(once, [1.0]) == {}
    assert again.rig_changes(once, [1.0]) == {"torque_lateral_loads.torque_reaction_reducer.force_per_torque_N_per_Nm": 3.0}
    assert np.allclose(y_paths(again.apply(once, [1.0])) - y_paths(rig),
                       1.5 * (y_paths(once) - y_paths(rig)), rtol=1e-9, atol=1e-15)


def test_load_only_effects_reuse_the_factorised_model(rig):
    """Offsets, gravity, force table and lateral loads change loads only: a prepared model gives the same Y."""
    prepared = prepare_model(rig)
    for name in ("self_weight", "force_pairs", "coupling_offset@C3", "thermal_growth@input_bearing_block",
                 "mesh_force@reducer_input"):
        effect = effect_by_name(rig, name)
        changed = effect.apply(rig, [effect.parameters[0].typical])
        if name == "mesh_force@reducer_input":
            continue  # a new item adds a load point: not the same structure
        assert np.abs(y_paths(changed, prepared=prepared) - y_paths(changed)).max() < 1e-15, name


def test_shear_deformation_is_a_candidate_only_when_off(rig):
    euler = rig.model_copy(update={"beam": rig.beam.model_copy(update={"shear_deformation": False})})
    assert "shear_deformation" not in {e.name for e in candidate_effects(rig)}
    effect = effect_by_name(euler, "shear_deformation")
    assert not effect.linear
    assert np.abs(y_paths(effect.apply(euler, [1.0])) - y_paths(rig)).max() < 1e-15
    assert np.abs(y_paths(effect.apply(euler, [0.0])) - y_paths(euler)).max() == 0.0
    assert np.abs(y_paths(euler) - y_paths(rig)).max() > 1e-6  # shear matters on the reference rig


def test_clearance_makes_every_effect_nonlinear(rig):
    gapped = effect_by_name(rig, "bearing_clearance@output_B2").apply(rig, [5.0])
    effects = candidate_effects(gapped)
    assert not any(e.linear for e in effects)
    clearance = effect_by_name(gapped, "bearing_clearance@output_B2").parameters[0]
    assert (clearance.lower, clearance.upper) == (-5.0, 10.0)  # increments keeping the total gap in 0 … 15 µm


def test_bounds_names_and_bad_values(rig):
    effect = effect_by_name(rig, "coupling_offset@C1")
    assert effect.out_of_bounds([50.0]) == []
    assert effect.out_of_bounds([150.0]) == ["offset_um = 150 µm lies outside its physical bounds [-100, 100] µm"]
    with pytest.raises(KeyError, match="candidates: self_weight"):
        effect_by_name(rig, "coupling_offset@nowhere")
    with pytest.raises(ValueError, match="takes 1 value"):
        effect.apply(rig, [1.0, 2.0])
    with pytest.raises(ValueError, match="radial_clearance_um"):
        effect_by_name(rig, "bearing_clearance@input_B1").apply(rig, [-1.0])


def test_parameter_addresses_of_the_new_keys(rig):
    changed = with_parameters(rig, {"couplings.C1.parallel_offset_um": 12.0, "mounts.reducer_pedestal.vertical_offset_um": -3.0,
                                    "bearings.input_B1.radial_clearance_um": 4.0, "force_table.scale": 0.5,
                                    "gravity.acceleration_m_per_s2": 9.0, "gravity.enabled": 0.0,
                                    "beam.shear_deformation": 0.0})
    assert changed.couplings[0].parallel_offset_um == 12.0
    assert get_parameter(changed, "mounts.reducer_pedestal.vertical_offset_um") == -3.0
    assert get_parameter(changed, "bearings.input_B1.radial_clearance_um") == 4.0
    assert changed.force_table.scale == 0.5 and changed.gravity.acceleration_m_per_s2 == 9.0
    assert changed.gravity.enabled is False and changed.beam.shear_deformation is False
    assert get_parameter(changed, "gravity.enabled") == 0.0
    assert get_parameter(rig, "torque_lateral_loads.sun_gear_load_sharing.imbalance") == 0.02  # old syntax
    with pytest.raises(KeyError, match="no key"):
        get_parameter(rig, "force_table.nothing")
    with pytest.raises(KeyError, match="not set"):
        get_parameter(rig, "torque_lateral_loads.sun_gear_load_sharing.force_per_torque_N_per_Nm")


def test_each_kind_is_declared_once_and_describes_itself(rig):
    """The vocabulary is one tuple: every candidate's kind is declared there once, with how it changes the model and
    what a fitted value means in words that name its place and its size."""
    from rvcoax.geometry.effects import EFFECT_KINDS, RESPONSES

    kinds = [k.kind for k in EFFECT_KINDS]
    assert len(kinds) == len(set(kinds)) and all(k.response in RESPONSES for k in EFFECT_KINDS)
    for effect in candidate_effects(rig):
        assert effect.kind in kinds
        sentence = effect.meaning([0.37])
        assert "0.37" in sentence or "1.37" in sentence or "1.29" in sentence, (effect.name, sentence)  # 2^0.37
        if effect.location is not None and effect.kind != "mesh_force":
            assert effect.location in sentence, (effect.name, sentence)


def test_effects_declared_as_loads_change_only_the_loads(rig):
    """An effect whose response is ``load`` leaves the stiffness as it is: the factorised base model gives the changed
    rig's Y exactly (the discrepancy engine relies on it). Effects adding a lateral load at a new point are left out:
    the new point changes the mesh, not the stiffness."""
    prepared = prepare_model(rig)
    for effect in candidate_effects(rig):
        if effect.response != "load" or effect.new_items(rig, [effect.parameters[0].typical]):
            continue
        changed = effect.apply(rig, [effect.parameters[0].typical])
        assert np.abs(y_paths(changed, prepared=prepared) - y_paths(changed)).max() < 1e-12, effect.name
