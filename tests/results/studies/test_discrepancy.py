"""The discrepancy workflow on data in which the effect is hidden.

The data come from the rig *with* an effect (a real sweep) at about 30 % of the signal, plus 1 % or
5 % Gaussian noise; the workflow starts from the rig without it and must name the effect (or a group
that contains it), shrink the gap, and not add anything when nothing is hidden. The rig is the
reference rig with Y measured from the unloaded geometry (so load-independent effects are
observable), self-weight off (so ``self_weight`` is a candidate) and Euler–Bernoulli shafts (so
``shear_deformation`` is one). Identification rates over many seeds: ``benchmarks/bench_discrepancy.py``.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from discrepancy_data import (
    LENGTHS,
    STATIONS,
    claims_what_the_data_carry,
    discrepancy_rig,
    hidden_data,
    write_cli_inputs,
)
from typer.testing import CliRunner

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.effects import candidate_effects
from rvcoax.geometry.rigfile import parse_rig
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import paper_cases
from rvcoax.results.cli.app import app
from rvcoax.results.studies.discrepancy.measured import MeasuredData, MeasuredDataError, parse_measured
from rvcoax.results.studies.discrepancy.responses import Observation, solve_full_paths
from rvcoax.results.studies.discrepancy.synthetic import effect_size_for, observation_layout, synthetic_data
from rvcoax.results.studies.discrepancy.workflow import DiscrepancySettings, build_library, run_discrepancy
from rvcoax.results.sweep import SweepSettings

# cost, for `make test-fast` (-m "not slow and not dask and not render")
pytestmark = [pytest.mark.slow]

# One location per kind: where the kind reaches the measured shafts most (see the benchmark for all).
HIDDEN = ("self_weight", "bearing_stiffness@input_B1", "bearing_stiffness@output_B2", "bearing_clearance@input_B2",
          "mount_compliance@reducer", "coupling_offset@C2", "coupling_angle@C3", "mesh_force@reducer_input",
          "torque_reaction@reducer", "thermal_growth@output_bearing_block")


@pytest.fixture(scope="module")
def rig() -> Rig:
    return discrepancy_rig()


@pytest.fixture(scope="module")
def library(rig):
    return build_library(rig, paper_cases(), SweepSettings())


@pytest.fixture(scope="module")
def effects(rig):
    return {e.name: e for e in candidate_effects(rig)}


def named(result, name) -> bool:
    return any(name in s.group for s in result.selected)


def rms_shrink(result) -> float:
    """Fraction of the RMS gap removed (all shafts together)."""
    before = np.sqrt(np.mean((result.data.value_mm - result.before) ** 2))
    after = np.sqrt(np.mean((result.data.value_mm - result.after) ** 2))
    return 1.0 - after / before


@pytest.mark.parametrize("name", HIDDEN)
def test_hidden_effect_is_named_on_paths(rig, library, effects, name):
    for noise, seed in ((0.01, 11), (0.05, 12)):
        data = hidden_data(rig, effects, name, "paths", noise, seed)
        result = run_discrepancy(rig, data, DiscrepancySettings(), library=library)
        assert claims_what_the_data_carry(result), (noise, result.verdict, [s.name for s in result.selected])
        assert named(result, name), (noise, [s.group for s in result.selected])
        noise_floor = noise * np.sqrt(np.mean(data.value_mm ** 2))
        after = np.sqrt(np.mean((data.value_mm - result.after) ** 2))
        assert rms_shrink(result) >= 0.9 or after <= 1.5 * noise_floor, (noise, rms_shrink(result), after, noise_floor)


@pytest.mark.parametrize("name", ("bearing_stiffness@input_B1", "coupling_offset@C3", "torque_reaction@reducer",
                                  "thermal_growth@output_bearing_block", "bearing_clearance@input_B2"))
def test_hidden_effect_on_table_data_is_in_the_named_group(rig, library, effects, name):
    data = hidden_data(rig, effects, name, "table", 0.01, 21)
    result = run_discrepancy(rig, data, DiscrepancySettings(), library=library)
    assert claims_what_the_data_carry(result), (result.verdict, result.reasons)
    assert named(result, name), [s.group for s in result.selected]


def test_table_data_with_fixed_torque_ratio_groups_torque_proportional_effects(rig, library, effects):
    """T2/T1 is the same in every case of the paper's table: a load ∝ T1 at the reducer input and a
    stiffness change of an input bearing scale alike; a magnitude-only table cannot tell them apart."""
    data = hidden_data(rig, effects, "mesh_force@reducer_input", "table", 0.01, 22)
    result = run_discrepancy(rig, data, DiscrepancySettings(), library=library)
    group = result.selected[0].group
    assert "mesh_force@reducer_input" in group and len(group) > 1
    assert result.discriminations, "an ambiguous group must come with the measurement that separates it"
    assert all(d.in_sigma > 1 for d in result.discriminations)


def test_no_hidden_effect_adds_nothing(rig, library, effects):
    settings = DiscrepancySettings(confidence_draws=0)  # 20 runs: the confidence estimate is tested on its own
    runs = [run_discrepancy(rig, hidden_data(rig, effects, None, schema, noise, seed), settings, library=library)
            for schema in ("paths", "table") for noise in (0.01, 0.05) for seed in range(5)]
    added = sum(bool(r.selected) for r in runs)
    assert added <= 0.05 * len(runs), [r.verdict for r in runs]
    assert all(r.verdict == "no_gap" for r in runs if not r.selected)


def test_two_hidden_effects_are_both_found_and_nothing_spurious(rig, library, effects):
    template = observation_layout(paper_cases(), STATIONS, LENGTHS, "paths")
    first, second = effects["mesh_force@reducer_input"], effects["coupling_angle@C3"]
    truth = first.apply(rig, [effect_size_for(first, rig, paper_cases(), template, 0.3)])
    truth = second.apply(truth, [effect_size_for(second, rig, paper_cases(), template, 0.3)])
    for noise, seed in ((0.01, 31), (0.05, 32)):
        result = run_discrepancy(rig, synthetic_data(truth, template, noise, seed), DiscrepancySettings(),
                                 library=library)
        assert claims_what_the_data_carry(result), (result.verdict, result.reasons)
        assert len(result.selected) == 2, [s.name for s in result.selected]
        assert named(result, first.name) and named(result, second.name)


def _out_of_library(rig, shaft: str, schema: str, noise: float, seed: int) -> MeasuredData:
    """Data with an effect the library does not have: a lateral point load on ``shaft`` that grows with
    the square of its torque (30 % of that shaft's signal). Every library effect is linear in torque
    or a dead band."""
    cases = paper_cases()
    template = observation_layout(cases, STATIONS, LENGTHS, schema)
    base, layout = solve_full_paths(rig, cases, SweepSettings())
    blocks = [layout.block(i, shaft) for i in range(len(cases))]
    signal = np.sqrt(np.mean(np.concatenate([base[b] for b in blocks]) ** 2))
    torque, part, x_mm = ("T2", "output_shaft", 470.0) if shaft == "output" else ("T1", "input_shaft", 270.0)
    data = rig.model_dump(by_alias=True)
    data["torque_lateral_loads"].append({"name": "hidden", "torque": torque, "kind": "proportional",
                                         "on": {"part": part, "x_mm": x_mm}, "force_per_torque_N_per_Nm": 1.0})
    loaded, _ = solve_full_paths(Rig.model_validate(data), cases, SweepSettings())
    t = np.array([c.output_torque_Nm if shaft == "output" else c.input_torque_Nm for c in cases])
    extra = np.zeros_like(base)
    for i, b in enumerate(blocks):
        extra[b] = (loaded[b] - base[b]) * t[i] / t.max()
    extra *= 0.3 * signal / np.sqrt(np.mean(np.concatenate([extra[b] for b in blocks]) ** 2))
    clean = Observation(template, layout)(base + extra)
    sigma = np.array([noise * np.sqrt(np.mean(clean[template.shaft == s] ** 2)) for s in template.shaft])
    values = clean + np.random.default_rng(seed).normal(size=clean.size) * sigma
    return MeasuredData(schema, template.cases, template.case_index, template.shaft, template.x_mm, values, None,
                        f"torque² load on the {shaft} shaft (not in the library)")


@pytest.mark.parametrize("shaft", MEASURED_SHAFTS)
def test_effect_outside_the_library_is_unexplained(rig, library, shaft):
    for seed in (41,):  # each run rebuilds the library once (a gap remains after round 1): ~45 s
        result = run_discrepancy(rig, _out_of_library(rig, shaft, "paths", 0.01, seed), DiscrepancySettings(),
                                 library=library)
        assert result.verdict == "unexplained", [s.name for s in result.selected]


def test_unobservable_effects_are_set_aside_with_the_reason(rig, library, effects):
    data = hidden_data(rig, effects, "coupling_angle@C3", "paths", 0.01, 51)
    result = run_discrepancy(rig, data, DiscrepancySettings(), library=library)
    # the shear of the short, thick shafts and motor-side bearings cannot move the measured paths
    assert "bearing_stiffness@motor_rear" in result.not_observable
    assert "σ" in result.not_observable["bearing_stiffness@motor_rear"]


def test_out_of_bounds_fits_are_rejected_with_the_reason(rig, library, effects):
    data = hidden_data(rig, effects, "mesh_force@reducer_input", "paths", 0.01, 52)
    result = run_discrepancy(rig, data, DiscrepancySettings(), library=library)
    assert result.rejected, "some candidate must need an implausible value to fit these data"
    assert all("outside its physical range" in reason for reason in result.rejected.values())


def test_measured_data_schemas_and_errors():
    table = parse_measured("T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm\n1.43,200,0.0000603,0.0042594\n", "t.csv")
    assert table.schema == "table" and table.n == 2 and table.quantum_mm["output"] == 1e-7
    paths = parse_measured("T1_input_Nm,T2_output_Nm,shaft,x_mm,uy_mm,sigma_mm\n1,140,output,10,-0.001,1e-5\n", "p.csv")
    assert paths.schema == "paths" and paths.sigma_mm[0] == 1e-5
    for text, expected in (
        ("T1_input_Nm,Y_input_mm\n1,2\n", "fit neither schema"),
        ("T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm\n1,140,12 mm,0.1\n", "line 2, column Y_input_mm"),
        ("T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm\n1,140,-1,0.1\n", "magnitudes"),
        ("T1_input_Nm,T2_output_Nm,shaft,x_mm,uy_mm\n1,140,middle,10,0.1\n", "not input or output"),
        ("T1_input_Nm,T2_output_Nm,shaft,x_mm,uy_mm\n1,140,input,10,nan\n", "not a finite number"),
        ("T1_input_Nm,T2_output_Nm,shaft,x_mm,uy_mm\n1,140,input,10,1\n1,140,input,10,2\n", "second value"),
        ("", "empty"),
    ):
        with pytest.raises(MeasuredDataError, match=expected):
            parse_measured(text, "bad.csv")


def test_cli_writes_json_plot_and_updated_rig(tmp_path, rig, effects):
    """The command end to end on paths data with a hidden lift of the output bearing block, which has no look-alike
    (a small candidate list keeps it fast; a C3 offset has four look-alikes, an ``ambiguous`` answer)."""
    rig_file, measured = write_cli_inputs(tmp_path, rig, hidden_data(rig, effects, "thermal_growth@output_bearing_block",
                                                                     "paths", 0.01, 61))
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["discrepancy", "--measured", str(measured), "--rig", str(rig_file), "--out",
                                      str(out), "--effects", "coupling_offset,thermal_growth,mesh_force,bearing_stiffness"])
    assert result.exit_code == 0, result.output
    document = json.loads((out / "discrepancy.json").read_text())
    assert document["verdict"] == "explained"
    assert document["selected"][0]["effect"] == "thermal_growth@output_bearing_block"
    lift = document["selected"][0]["parameters"]["lift_um"]
    assert lift["unit"] == "µm" and lift["value"] > 0 and lift["at_bound"] is None
    assert document["rms_after_mm"]["output"] < 0.2 * document["rms_before_mm"]["output"]
    assert set(document) >= {"verdict", "selected", "ambiguous_groups", "rms_before_mm", "rms_after_mm", "rig_file"}
    updated = (out / "rig_updated.toml").read_text()
    assert "rvcoax discrepancy" in updated
    import tomllib

    rig_after = parse_rig(tomllib.loads(updated), "rig_updated.toml")
    lifted = [m.vertical_offset_um for m in rig_after.mounts if m.part == "output_bearing_block"]
    assert lifted and all(v == pytest.approx(lift["value"], rel=1e-6) for v in lifted)
    assert (out / "discrepancy.png").stat().st_size > 10_000
    bad = CliRunner().invoke(app, ["discrepancy", "--measured", str(measured), "--effects", "warp_drive"])
    assert bad.exit_code == 2 and "unknown effect" in bad.output
