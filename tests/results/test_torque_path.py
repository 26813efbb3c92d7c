"""The torque path check (results/torque_path.py) and the stators' reactions on the RV-40E example rig: with a torsional spring between the
brake's rotor and stator (the shipped rig had one, 1e4 N·m/rad, until the brake torque was recognised as that
coupling) it warns and names the spring and its share; the shipped rig is silent, every shaft line carrying its
whole torque to the reducer.

The share is checked against the closed form of two torsional paths in parallel from the brake's rotor, where T2
acts, to its stator, which takes the opposite torque: the spring, and the line (brake shaft, coupling C3, sensor
shaft, C2, output shaft, the reducer's main bearings, the reducer body, its pedestal, the ground, the brake feet),
each shaft section L / (G J) with J = π D⁴ / 32 and G = E / (2 (1 + ν)), each spring 1/k.
"""

from __future__ import annotations

import math
import tomllib

import pytest
from rigdata import dump_toml
from typer.testing import CliRunner

from rvcoax.geometry.builtin import example_rig_text
from rvcoax.geometry.rigfile import RigFileError, parse_rig
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.cli.app import app
from rvcoax.results.io.records import case_record
from rvcoax.results.sweep import run_sweep
from rvcoax.results.torque_path import shaft_lines, torque_path_warnings

GAP = {"name": "brake_hysteresis_gap", "from": {"part": "brake_housing", "x_mm": 925},
       "to": {"part": "brake_shaft", "x_mm": 925}, "translational_stiffness_N_per_um": [0, 0, 0],
       "rotational_stiffness_Nm_per_rad": [1e4, 0, 0]}
CASES = (LoadCase(0.0, 100.0), LoadCase(0.801, 82.4))


def _with_gap() -> dict:
    data = tomllib.loads(example_rig_text())
    data["joints"].append(dict(GAP))
    return data


@pytest.fixture(scope="module")
def old():
    rig = parse_rig(_with_gap(), "old.toml")
    return rig, [case_record(c)["entry"] for c in run_sweep(rig, CASES).cases]


@pytest.fixture(scope="module")
def fixed():
    rig = parse_rig(tomllib.loads(example_rig_text()), "fixed.toml")
    return rig, [case_record(c)["entry"] for c in run_sweep(rig, CASES).cases]


def _compliance(rig, part: str, start_mm: float, end_mm: float) -> float:
    """Σ L / (G J) of ``part``'s segments between two stations (rad per N·m)."""
    p = next(q for q in rig.parts if q.name == part)
    m = rig.materials[p.material]
    g = m.youngs_modulus_MPa * 1e6 / (2 * (1 + m.poisson_ratio))
    total = 0.0
    for s in p.segments:
        length = max(0.0, min(s.x_mm[1], end_mm) - max(s.x_mm[0], start_mm)) * 1e-3
        d, bore = s.outer_diameter_mm * 1e-3, (s.inner_diameter_mm or 0.0) * 1e-3
        total += length / (g * math.pi * (d**4 - bore**4) / 32)
    return total


def _line(entry: dict, label: str) -> dict:
    return next(line for line in entry["engineering"]["torque_paths"] if line["line"] == label)


def test_a_brake_gap_spring_takes_its_closed_form_share_of_T2(old):
    rig, entries = old
    k = {c.name: c.torsional_stiffness_Nm_per_rad for c in rig.couplings}
    joint = next(j for j in rig.joints if j.name == "RV40E_main_bearings")
    pedestal = next(m for m in rig.mounts if m.name == "reducer_pedestal")
    feet = next(m for m in rig.mounts if m.name == "brake_feet")
    line = (_compliance(rig, "brake_shaft", 762.5, 925) + 1 / k["C3"]
            + _compliance(rig, "output_sensor_shaft", 562.5, 717.5) + 1 / k["C2"]
            + _compliance(rig, "output_shaft", 275, 517.5) + 1 / joint.rotational_stiffness_Nm_per_rad[0]
            + _compliance(rig, "reducer", 230, 275) + 1 / pedestal.rotational_stiffness_Nm_per_rad[0])
    # the brake's stator takes +T2 (reacted_on): from the rotor to the stator the torque has two parallel paths, the
    # spring, and the line to the ground and back through the brake feet; they share it as their stiffnesses
    loop = line + 1 / feet.rotational_stiffness_Nm_per_rad[0]
    expected = 100 * loop / (loop + 1 / 1e4)
    t2 = _line(entries[0], "T2")  # T1 = 0: nothing else twists the reducer body
    assert t2["reaction"] == "joint:RV40E_main_bearings" and t2["reaction_rule"] == "reducer"
    assert t2["applied_Nm"] == -100.0  # the brake's sign -1
    leak = next(e for e in t2["exits"] if e["spring"] == "joint:brake_hysteresis_gap")
    assert leak["share_percent"] == pytest.approx(expected, rel=1e-6)
    assert 22 < expected < 24
    assert t2["carried_percent"] + leak["share_percent"] == pytest.approx(100, abs=1e-6)


def test_the_old_gap_warns_once_naming_the_spring_its_share_and_the_case(old):
    _, entries = old
    warnings = torque_path_warnings(entries)
    assert len(warnings) == 1, warnings
    text = warnings[0]
    assert "joint 'brake_hysteresis_gap' carries 23.1 % of T2" in text
    assert "past the reaction, joint 'RV40E_main_bearings'" in text
    shares = [next(e["share_percent"] for e in _line(entry, "T2")["exits"] if "gap" in e["spring"]) for entry in entries]
    worst = entries[shares.index(max(shares))]  # T1 twists the reducer body too: the shares differ a little
    assert f"T1 = {worst['T1_input_Nm']:g} N·m, T2 = {worst['T2_output_Nm']:g} N·m" in text
    assert "in all 2 cases" in text
    assert "\n" not in text


def test_the_shipped_rig_carries_every_torque_to_the_reducer_and_is_silent(fixed):
    rig, entries = fixed
    assert shaft_lines(rig) == [("motor_shaft", "input_shaft"), ("output_shaft", "output_sensor_shaft", "brake_shaft")]
    assert torque_path_warnings(entries) == []
    for entry in entries:
        for label, torque in (("T1", entry["T1_input_Nm"]), ("T2", -entry["T2_output_Nm"])):
            line = _line(entry, label)
            assert len(line["exits"]) == 1
            assert line["carried_Nm"] == pytest.approx(torque, rel=1e-8, abs=1e-12)
    assert _line(entries[1], "T1")["reaction"] == "joint:input_gear_mesh"  # the line's far end from the motor


def test_reaction_spring_names_the_reaction_and_an_unknown_name_is_refused(tmp_path):
    data = _with_gap()
    data["torques"]["T2"]["reaction_spring"] = "brake_hysteresis_gap"  # the user says the brake reacts T2
    rig = parse_rig(data, "marked.toml")
    entries = [case_record(c)["entry"] for c in run_sweep(rig, CASES[:1]).cases]
    t2 = _line(entries[0], "T2")
    assert (t2["reaction"], t2["reaction_rule"]) == ("joint:brake_hysteresis_gap", "reaction_spring")
    assert "joint 'RV40E_main_bearings' carries 76.9 % of T2" in torque_path_warnings(entries)[0]
    data["torques"]["T2"]["reaction_spring"] = "brake_gap"
    with pytest.raises(RigFileError, match=r"torques.T2.reaction_spring: no bearing, mount, coupling, joint or reducer "
                                           r"named 'brake_gap'"):
        parse_rig(data, "typo.toml")


def test_sweep_writes_the_carried_torque_and_warns_on_the_console(tmp_path):
    data = _with_gap()
    data["load_cases"] = [{"T1_input_Nm": 0.801, "T2_output_Nm": 82.4}]
    rig_file = tmp_path / "rig.toml"
    rig_file.write_text(dump_toml(data), encoding="utf-8")
    result = CliRunner().invoke(app, ["sweep", "--rig", str(rig_file), "--out", str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    assert "brake_hysteresis_gap" in " ".join(result.output.split())
    header, row = (tmp_path / "out" / "sweep.csv").read_text().splitlines()[:2]
    values = dict(zip(header.split(","), row.split(",")))
    assert float(values["torque_line_T2_applied_Nm"]) == -82.4
    assert float(values["torque_line_T2_carried_Nm"]) == pytest.approx(-63.34, abs=0.01)
    assert float(values["torque_line_T2_leak_joint_brake_hysteresis_gap_percent"]) == pytest.approx(23.13, abs=0.01)


def test_the_stators_take_the_opposite_torques_so_the_supports_carry_the_benchs(fixed):
    """[torques.*] reacted_on: the motor bracket carries T1, the brake feet T2, the reducer pedestal T2 − T1, and
    the applied torques sum to zero about x (Newton's third law between rotor and stator)."""
    _, entries = fixed
    for entry in entries:
        t1, t2 = entry["T1_input_Nm"], entry["T2_output_Nm"]
        mx = {r["name"]: r["moment_Nm"][0] for r in entry["engineering"]["reactions"]}
        assert mx["motor_bracket"] == pytest.approx(t1, rel=1e-8)
        assert mx["brake_feet"] == pytest.approx(-t2, rel=1e-8)
        assert mx["reducer_pedestal"] == pytest.approx(t2 - t1, rel=1e-8)
        assert abs(entry["engineering"]["applied_torque_x_Nm"]) < 1e-9 * t2


def test_a_stator_off_the_rig_is_refused():
    data = tomllib.loads(example_rig_text())
    data["torques"]["T2"]["reacted_on"] = {"part": "brake_stator", "x_mm": 925}
    with pytest.raises(RigFileError, match=r"torques.T2.reacted_on.*brake_stator"):
        parse_rig(data, "stator.toml")
    data["torques"]["T2"]["reacted_on"] = {"part": "brake_shaft", "x_mm": 925}
    with pytest.raises(RigFileError, match=r"torques.T2: part and reacted_on are the same part 'brake_shaft'"):
        parse_rig(data, "stator.toml")
