"""Bearing lives, static safety and minimum load in a sweep: per case with the case named, over the duty cycle, in
the files, the console and the report (issue 25 item 3)."""

from __future__ import annotations

import csv
import json
import math

import pytest
from typer.testing import CliRunner

from rvcoax.fem import bearing_life
from rvcoax.geometry.builtin import example_rig_text, load_example_rig
from rvcoax.geometry.rigfile import parse_rig_text, reference_rig_text
from rvcoax.loadcases.cases import LoadCase, default_cases
from rvcoax.results.cli.app import app
from rvcoax.results.engineering import duty_cycle_lives, sweep_lives
from rvcoax.results.reports.report_tables import life_tables
from rvcoax.results.sweep import run_sweep


@pytest.fixture(scope="module")
def example_sweep():
    rig = load_example_rig()
    return run_sweep(rig, default_cases(rig))


def test_typed_in_bearing_lives_per_case(example_sweep):
    rig = example_sweep.rig
    first = example_sweep.cases[0].engineering
    life = next(b for b in first.lives if b.name == "output_B2")
    force = next(b for b in first.bearings if b.name == "output_B2")
    assert life.case == "T2_20pct" and life.speed_rpm == 15.0
    assert life.equivalent_load_N == pytest.approx(force.force_radial_N)  # no axial load on output_B2
    assert life.L10_Mrev == pytest.approx((32.5e3 / life.equivalent_load_N) ** 3)
    assert life.L10_h == pytest.approx(life.L10_Mrev * 1e6 / (60 * 15.0))
    assert life.static_safety == pytest.approx(19.0e3 / life.equivalent_load_N)
    assert life.minimum_load_N == pytest.approx(325.0) and life.below_minimum_load
    speeds = {b.name: b.speed_rpm for b in first.lives}
    assert speeds["input_B1"] == pytest.approx(15.0 * 121)  # the input shaft: output speed × the reducer's ratio
    assert rig.reducers[0].ratio == 121


def test_duty_cycle_against_palmgren_miner_by_hand(example_sweep):
    rig = example_sweep.rig
    duty = {d.name: d for d in duty_cycle_lives(rig, [c.engineering for c in example_sweep.cases])}
    lives = [next(b for b in c.engineering.lives if b.name == "output_B2").L10_h for c in example_sweep.cases]
    shares = [c.time_share for c in rig.load_cases]
    assert duty["output_B2"].L10_h == pytest.approx(1.0 / sum(s / life for s, life in zip(shares, lives)))
    assert len(duty["output_B2"].cases_below_minimum_load) == 5


def test_files_console_and_report_carry_the_lives(tmp_path, example_sweep):
    rig_file = tmp_path / "rv40e.toml"
    rig_file.write_text(example_rig_text(), encoding="utf-8")
    result = CliRunner().invoke(app, ["sweep", "--rig", str(rig_file), "--out", str(tmp_path / "out")],
                                terminal_width=220)
    assert result.exit_code == 0, result.output
    assert "Bearing life" in result.output and "duty cycle" in result.output
    said = " ".join(result.output.split())  # the warnings come on stderr, wrapped to the terminal
    assert "warning: bearing output_B2 carries less than its minimum load" in said
    with open(tmp_path / "out" / "sweep.csv", encoding="utf-8") as handle:
        row = next(csv.DictReader(handle))
    assert float(row["bearing_output_B2_L10_Mrev"]) > 0 and row["bearing_output_B2_below_minimum_load"] == "True"
    assert "reducer_RV40E_main_bearings_verdict" in row
    document = json.loads((tmp_path / "out" / "sweep.json").read_text(encoding="utf-8"))
    assert document["cases"][0]["engineering"]["bearing_lives"][0]["case"] == "T2_20pct"
    assert {d["name"] for d in document["bearing_duty_cycle"]} == {"input_B1", "input_B2", "output_B1", "output_B2"}
    captions = [t.caption for t in life_tables(example_sweep)]
    assert any("per case" in c and "life" in c for c in captions)
    assert any("duty cycle" in c for c in captions) and any("Reducers" in c for c in captions)
    table = next(t for t in life_tables(example_sweep) if "life, static safety" in t.caption)
    assert table.columns[0] == "case" and table.rows[0][0] == "T2_20pct"


def test_ball_bearing_lives_from_their_ball_loads():
    """A nonlinear sweep: each ball bearing's L10r from its ball loads, s0 from the largest contact pressure."""
    text = reference_rig_text("ball_bearings").replace(
        'designation = "6206"', 'designation = "6206"\npreload_N = 200.0', 1)
    rig = parse_rig_text(text)
    sweep = run_sweep(rig, (LoadCase(1.43, 200.0),))
    lives = {life.name: life for life in sweep_lives(sweep)[0]}
    preloaded = lives["output_B1"]  # 200 N axial preload: every ball loaded
    assert preloaded.L10r_Mrev is not None and math.isfinite(preloaded.L10r_Mrev)
    assert preloaded.static_safety < 1e3  # the preloaded balls press their raceways
    # P counts the 200 N preload the rings carry axially (the mounting takes it; ISO 281 P = X F_r + Y F_a with
    # Y between 1.0 and 2.30 at this f0 F_a / C0), though the bearing passes only a few newtons on to the housing
    assert 200.0 <= preloaded.equivalent_load_N <= 2.30 * 200.0 + 50.0
    assert not preloaded.below_minimum_load  # the preload loads the balls: the minimum load counts the elements
    assert preloaded.rating_source.startswith("ISO 281")
    c, _ = bearing_life.dynamic_rating_ball(9, 9.525, 46.0), None
    assert preloaded.dynamic_load_rating_N == pytest.approx(c)
    assert lives["output_B2"].below_minimum_load  # the unpreloaded neighbour floats in its clearance
    row = __import__("rvcoax.results.io.records", fromlist=["case_row"]).case_row(sweep.cases[0])
    assert "bearing_output_B1_L10r_Mrev" in row


def test_a_shaft_crossing_its_play_between_neighbouring_cases_is_named():
    """docs/model.md: with CN clearance the input shaft is lifted across input_B2's play between T1 = 0.64 and
    0.79 N·m (the lateral mesh load outgrows its weight): the sweep names the bearing and the two cases."""
    from rvcoax.results import play_crossings

    rig = parse_rig_text(reference_rig_text("ball_bearings"))
    sweep = run_sweep(rig, (LoadCase(0.5, 70.0), LoadCase(0.64, 90.0), LoadCase(0.79, 110.0)))
    found = play_crossings(sweep.solver_report["ball_bearing_operating_points"])
    assert len(found) == 1
    assert found[0].startswith("bearing input_B2 (ball): the shaft crosses its play between "
                               "T1 = 0.64 N·m, T2 = 90 N·m and T1 = 0.79 N·m, T2 = 110 N·m")
    steady = run_sweep(rig, (LoadCase(0.5, 70.0), LoadCase(0.64, 90.0)))
    assert play_crossings(steady.solver_report["ball_bearing_operating_points"]) == []


def test_revolution_shares_and_a_case_at_standstill():
    """Revolution shares: Miner in revolutions, no speed needed. Time shares with a case at standstill: that case
    adds no damage, and the cycle's hours count its standstill time (L_h = 1 / Σ_moving t_k / L_h,k)."""
    text = example_rig_text()
    for old, new in (("time_share = 0.30                   # [A] duty cycle of this bench", "revolution_share = 0.30"),
                     ("time_share = 0.30                   # [A]", "revolution_share = 0.30"),
                     ("time_share = 0.20", "revolution_share = 0.20"), ("time_share = 0.15", "revolution_share = 0.15"),
                     ("time_share = 0.05", "revolution_share = 0.05")):
        text = text.replace(old, new)
    rig = parse_rig_text(text)
    sweep = run_sweep(rig, default_cases(rig))
    duty = {d.name: d for d in duty_cycle_lives(rig, [c.engineering for c in sweep.cases])}
    revs = [next(b for b in c.engineering.lives if b.name == "output_B2").L10_Mrev for c in sweep.cases]
    shares = [c.revolution_share for c in rig.load_cases]
    assert duty["output_B2"].shares == "revolution" and duty["output_B2"].L10_h is None
    assert duty["output_B2"].L10_Mrev == pytest.approx(1.0 / sum(s / r for s, r in zip(shares, revs)))

    standstill = parse_rig_text(example_rig_text().replace(
        "output_speed_rpm = 15               # [S] rated output speed of the RV-40E", "output_speed_rpm = 0"))
    sweep = run_sweep(standstill, default_cases(standstill))
    duty = {d.name: d for d in duty_cycle_lives(standstill, [c.engineering for c in sweep.cases])}
    hours = [next(b for b in c.engineering.lives if b.name == "output_B2").L10_h for c in sweep.cases]
    assert hours[0] is None  # no revolutions in the first case
    shares = [c.time_share for c in standstill.load_cases]
    assert duty["output_B2"].L10_h == pytest.approx(1.0 / sum(s / h for s, h in zip(shares[1:], hours[1:])))


def test_angular_contact_and_roller_bearing_lives_in_a_sweep():
    """The rolling-bearing variant with a zero-clearance NU 204 and the 30206 pair set 10 µm into preload: every
    bearing from geometry gets L10 from ISO 281's X/Y of its type and set, L10r from its element loads, s0 from
    its largest contact pressure, the minimum load — per case, named, in the files. By hand: the 7204 B DB pair's
    C = 2^0.7 C of one row (ISO 281), a 30206's P = 0.4 F_r + 0.4 cot α F_a from the loads its rows carry (the
    preload included: F_a/F_r > e = 1.5 tan α), L10 = (C/P)^(10/3)."""
    from rvcoax.fem.rolling_bearing import carried_force
    from rvcoax.geometry.rolling_catalogue import catalogue_entry
    from rvcoax.results.io.records import case_row

    text = reference_rig_text("rolling_bearings").replace(
        'clearance_class = "C2"              # ISO 5753-1, middle of 0-25 µm', "clearance_um = 0").replace(
        "axial_offset_um = -5", "axial_offset_um = 5")
    sweep = run_sweep(parse_rig_text(text), (LoadCase(1.43, 200.0),))
    lives = {life.name: life for life in sweep_lives(sweep)[0]}
    assert {"input_B1", "input_B2", "output_B1", "output_B2"} <= set(lives)
    assert all(life.case == "T1 = 1.43 N·m, T2 = 200 N·m" for life in lives.values())
    pair = lives["input_B1"]
    assert pair.dynamic_load_rating_N == pytest.approx(2**0.7 * catalogue_entry("7204B", "angular_contact")
                                                       .dynamic_rating_N)
    assert "set of 2" in pair.rating_source
    tapered = lives["output_B1"]
    model = next(m for m in sweep.nonlinear_bearings.rolling if m.name == "output_B1")
    bearings = sweep.nonlinear_bearings
    motion = bearings.motions(bearings.operator @ sweep.total_displacement(0))["output_B1"]
    force = carried_force(model.bearing, motion)
    radial, axial = math.hypot(force[1], force[2]), abs(force[0])
    tan_a = math.tan(model.geometry.contact_angle_rad)
    assert axial > 1.5 * tan_a * radial
    assert tapered.equivalent_load_N == pytest.approx(0.4 * radial + 0.4 / tan_a * axial, rel=1e-9)
    assert tapered.L10_Mrev == pytest.approx((tapered.dynamic_load_rating_N / tapered.equivalent_load_N) ** (10 / 3))
    assert tapered.minimum_load_N == pytest.approx(0.02 * tapered.dynamic_load_rating_N)  # SKF: F_rm = 0.02 C
    assert math.isfinite(tapered.L10r_Mrev) and 1.0 < tapered.static_safety < 1e3
    assert math.isfinite(lives["input_B2"].L10r_Mrev)  # the zero-clearance cylindrical bearing's rollers carry
    row = case_row(sweep.cases[0])
    assert "bearing_output_B1_L10r_Mrev" in row and "bearing_input_B2_static_safety" in row
    # the one warning function the console and the report share names the case as the tables do
    from rvcoax.results.engineering import engineering_warnings
    from rvcoax.results.io.records import case_entry

    said = engineering_warnings(sweep.rig, [case_entry(c) for c in sweep.cases],
                                sweep.solver_report["rolling_bearing_operating_points"])
    assert (f"bearing output_B1 carries less than its minimum load ({tapered.minimum_load_N:.3g} N = 0.02 C, the "
            "makers' rule) in 1 case(s) (T1 = 1.43 N·m, T2 = 200 N·m)") in " ".join(said)



def test_makers_minimum_load_and_a_iso_of_a_roller_bearing_per_case():
    """The NU 204 of the rolling-bearing variant with SKF's k_r, n_r and the oil's viscosity, in a rig load case with
    its speeds: its minimum load is SKF's F_rm = k_r (6 + 4 n/n_r) (d_m/100)² at the input speed (d_m = (20 + 47)/2),
    κ = ν/ν1 at that speed and pitch diameter, a_ISO the roller form with C_u = C0/8.2, L_nm = a_ISO L10r."""
    from rvcoax.geometry.bearing_ratings import load_ratings
    from rvcoax.geometry.rolling_model import rolling_bearing_of

    text = reference_rig_text("rolling_bearings").replace(
        'clearance_class = "C2"              # ISO 5753-1, middle of 0-25 µm',
        "clearance_um = 0\nminimum_load_factor = 0.1\nreference_speed_rpm = 13000\noil_viscosity_mm2_per_s = 20\n"
        "contamination_factor = 0.5") + (
        '\n[[load_cases]]\nT1_input_Nm = 1.43\nT2_output_Nm = 200\nname = "rated"\noutput_speed_rpm = 15\n'
        "input_speed_rpm = 2115\n")
    rig = parse_rig_text(text)
    sweep = run_sweep(rig, (LoadCase(1.43, 200.0),))
    life = next(b for b in sweep_lives(sweep)[0] if b.name == "input_B2")
    assert life.case == "rated" and life.speed_rpm == 2115.0
    assert life.minimum_load_N == pytest.approx(bearing_life.cylindrical_minimum_load_N(0.1, 2115.0, 13000.0, 33.5))
    entry = next(b for b in rig.bearings if b.name == "input_B2")
    pitch = rolling_bearing_of(entry).rows[0].law.pitch_diameter_m * 1e3
    kappa = 20.0 / bearing_life.reference_viscosity_mm2_s(2115.0, pitch)
    expected = bearing_life.a_iso(kappa, 0.5, load_ratings(entry).static_N / 8.2, life.equivalent_load_N, "roller")
    assert life.a_iso == pytest.approx(expected)
    assert life.Lnm_h == pytest.approx(expected * life.L10r_h)
