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


RATINGS = {"C2": (100.0, None), "C3": (70.0, 90.0)}  # rated, peak torque (N·m): made up to straddle the cases
SENSOR_RATED = 80.0


def _with_gap() -> dict:
    data = tomllib.loads(example_rig_text())
    data["joints"].append(dict(GAP))
    return data


def _rated(data: dict) -> dict:
    """``data`` with :data:`RATINGS` on its couplings and :data:`SENSOR_RATED` on the output sensor's shaft."""
    for c in data["couplings"]:
        if c["name"] in RATINGS:
            rated, peak = RATINGS[c["name"]]
            c["rated_torque_Nm"] = rated
            if peak is not None:
                c["peak_torque_Nm"] = peak
    next(p for p in data["parts"] if p["name"] == "output_sensor_shaft")["rated_torque_Nm"] = SENSOR_RATED
    return data


@pytest.fixture(scope="module")
def old():
    """The example rig with the old brake gap spring, its output couplings and sensor shaft rated (ratings change no
    result: they are only checked)."""
    rig = parse_rig(_rated(_with_gap()), "old.toml")
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


def _gap_share_percent(rig) -> float:
    """The closed-form share (%) of T2 the brake gap spring takes (module text), with T1 = 0."""
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
    return 100 * loop / (loop + 1 / 1e4)


def test_a_brake_gap_spring_takes_its_closed_form_share_of_T2(old):
    rig, entries = old
    expected = _gap_share_percent(rig)
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


def test_rated_couplings_and_sensor_carry_the_hand_computed_torque_against_their_ratings(old):
    """Hand computation: with T1 = 0 and T2 = 100 N·m the brake gap spring takes the closed-form share s of T2, so C3,
    the output sensor's shaft and C2 in series carry T2 (1 − s) ≈ 76.9 N·m each; against C3's 70 / 90 N·m that is
    above rated within peak, against C2's 100 N·m and the sensor's 80 N·m within rating."""
    rig, entries = old
    carried = 100.0 * (1 - _gap_share_percent(rig) / 100)
    ratings = {r["name"]: r for r in entries[0]["engineering"]["torque_ratings"]}
    assert list(ratings) == ["C2", "C3", "output_sensor_shaft"]  # couplings first, then shafts, file order
    for name, rated, peak, verdict in (("C2", 100.0, None, "within rating"),
                                       ("C3", 70.0, 90.0, "above rated torque (within peak)"),
                                       ("output_sensor_shaft", SENSOR_RATED, None, "within rating")):
        r = ratings[name]
        assert r["torque_Nm"] == pytest.approx(carried, rel=1e-6)
        assert r["rated_use_percent"] == pytest.approx(100 * carried / rated, rel=1e-6)
        assert r["peak_use_percent"] == (None if peak is None else pytest.approx(100 * carried / peak, rel=1e-6))
        assert r["verdict"] == verdict
        assert r["kind"] == ("shaft" if name.endswith("shaft") else "coupling")
    assert 76 < carried < 78


def test_a_torque_above_a_rating_warns_once_per_case_in_the_one_form(old):
    from rvcoax.results.engineering import engineering_warnings, torque_rating_warnings

    rig, entries = old
    warnings = torque_rating_warnings(rig, entries)
    assert all(w in engineering_warnings(rig, entries) for w in warnings)
    c3 = [w for w in warnings if w.startswith("coupling C3")]
    assert len(c3) == len(warnings) == 1  # C3 above 70 N·m at T2 = 100 (not at 82.4: 63 N·m); C2, the sensor within
    assert c3[0].startswith("coupling C3 (rated 70 N·m) in case T1 = 0 N·m, T2 = 100 N·m: above rated torque (within "
                            "peak) (carries 76.87 N·m = 110 % of rated, 85.4 % of the peak 90 N·m)")
    rating = next(r for r in entries[0]["engineering"]["torque_ratings"] if r["name"] == "C3")
    over = {**entries[0], "engineering": {"torque_ratings": [{**rating, "torque_Nm": 95.0, "rated_use_percent": 135.7,
                                                             "peak_use_percent": 105.6, "verdict": "EXCEEDS peak torque"}]}}
    assert torque_rating_warnings(rig, [over]) == [
        "coupling C3 (rated 70 N·m) in case T1 = 0 N·m, T2 = 100 N·m: EXCEEDS peak torque (carries 95 N·m = 136 % of "
        "rated, 106 % of the peak 90 N·m)"]


def test_the_verdicts_of_a_rating():
    from rvcoax.results.torque_path import TorqueRating

    def verdict(torque, peak=None):
        rated = 50.0
        return TorqueRating("coupling", "C", torque, rated, peak, 100 * torque / rated,
                            None if peak is None else 100 * torque / peak).verdict

    assert verdict(50.0) == verdict(50.0 * (1 + 1e-12)) == "within rating"  # at the rating, up to rounding
    assert verdict(60.0) == "EXCEEDS rated torque"
    assert verdict(60.0, 75.0) == "above rated torque (within peak)"
    assert verdict(80.0, 75.0) == "EXCEEDS peak torque"


def test_sweep_files_and_console_carry_the_ratings(tmp_path):
    data = _rated(tomllib.loads(example_rig_text()))
    data["load_cases"] = [{"T1_input_Nm": 0.0, "T2_output_Nm": 95.0}]
    rig_file = tmp_path / "rig.toml"
    rig_file.write_text(dump_toml(data), encoding="utf-8")
    result = CliRunner().invoke(app, ["sweep", "--rig", str(rig_file), "--out", str(tmp_path / "out")],
                                terminal_width=200)
    assert result.exit_code == 0, result.output
    said = " ".join(result.output.split())
    assert ("warning: coupling C3 (rated 70 N·m) in case T1 = 0 N·m, T2 = 95 N·m: EXCEEDS peak torque (carries 95 N·m "
            "= 136 % of rated, 106 % of the peak 90 N·m)") in said
    assert "shaft output_sensor_shaft (rated 80 N·m) in case T1 = 0 N·m, T2 = 95 N·m: EXCEEDS rated torque" in said
    assert "coupling C2 (rated" not in said  # 95 % of its 100 N·m: within
    assert "Couplings and torque sensors against their rated torque, per case" in said  # the console's table
    assert "coupling C2 95 100 95 % within rating" in " ".join(said.replace("│", " ").split())
    header, row = (tmp_path / "out" / "sweep.csv").read_text().splitlines()[:2]
    values = dict(zip(header.split(","), row.split(",")))
    assert float(values["coupling_C3_torque_Nm"]) == pytest.approx(95.0, rel=1e-8)  # no gap: the line carries T2
    assert float(values["coupling_C3_torque_rated_percent"]) == pytest.approx(100 * 95 / 70, rel=1e-8)
    assert float(values["coupling_C3_torque_peak_percent"]) == pytest.approx(100 * 95 / 90, rel=1e-8)
    assert values["coupling_C2_torque_verdict"] == "within rating" and "coupling_C2_torque_peak_percent" not in values
    assert float(values["shaft_output_sensor_shaft_torque_rated_percent"]) == pytest.approx(100 * 95 / 80, rel=1e-8)
    entry = __import__("json").loads((tmp_path / "out" / "sweep.json").read_text())["cases"][0]
    assert [r["name"] for r in entry["engineering"]["torque_ratings"]] == ["C2", "C3", "output_sensor_shaft"]


@pytest.mark.parametrize(("where", "key", "value", "reason"), [
    ("couplings", "rated_torque_Nm", -240.0, r"couplings\[1\] \('C2'\)\.rated_torque_Nm: Input should be greater than "
                                              r"or equal to 0\.001 \(got -240\.0\)"),
    ("couplings", "rated_torque_Nm", "240 Nm", r"couplings\[1\] \('C2'\)\.rated_torque_Nm: Input should be a valid "
                                               r"number \(got '240 Nm'\)"),
    ("couplings", "rated_torque_kNm", 0.24, r"couplings\[1\] \('C2'\)\.rated_torque_kNm: unknown key"),
    ("couplings", "peak_torque_Nm", 500.0, r"couplings\[1\] \('C2'\): peak_torque_Nm needs rated_torque_Nm"),
    ("parts", "rated_torque_Nm", 500.0, r"parts\[\d+\] \('output_sensor_housing'\): rated_torque_Nm: a body "
                                        r"\(housing\) carries no shaft torque"),
])
def test_bad_ratings_are_refused_with_file_key_and_reason(where, key, value, reason):
    data = tomllib.loads(example_rig_text())
    target = (data["couplings"][1] if where == "couplings"
              else next(p for p in data["parts"] if p["name"] == "output_sensor_housing"))
    target[key] = value
    with pytest.raises(RigFileError, match=r"rig file bench\.toml: 1 problem\(s\):\n  - " + reason):
        parse_rig(data, "bench.toml")
    data = _rated(tomllib.loads(example_rig_text()))
    data["couplings"][2]["peak_torque_Nm"] = 60.0  # below C3's rated 70 N·m
    with pytest.raises(RigFileError, match=r"couplings\[2\] \('C3'\): peak_torque_Nm = 60 N·m is below "
                                           r"rated_torque_Nm = 70 N·m"):
        parse_rig(data, "bench.toml")


def test_the_reference_rig_rates_the_couplings_whose_datasheet_is_known():
    """C1 and C3 are RINGFEDER GWB AKN sizes 30 and 200 (RINGFEDER, Tech Paper "Metal Bellows Couplings GWB AKN", EN
    08.2019: C_r 720 / 2500 N/mm, C_T 35 / 170 kN·m/rad, 0.245 / 1.054 kg, the rig file's [S] values): transmissible
    torque T = 36 and 240 N·m. C2, C4 and both torque sensors are not identified: no rating. The paper's largest case
    (T1 = 1.43, T2 = 200 N·m) is within both."""
    from rvcoax.geometry.rigfile import REFERENCE_VARIANTS, load_rig, reference_rig_text
    from rvcoax.loadcases.cases import paper_cases

    rig = load_rig()
    assert {c.name: (c.rated_torque_Nm, c.peak_torque_Nm) for c in rig.couplings} == {
        "C1": (36.0, None), "C2": (None, None), "C3": (240.0, None), "C4": (None, None)}
    assert all(p.rated_torque_Nm is None for p in rig.parts)
    for variant in REFERENCE_VARIANTS:  # every variant rates the same couplings
        text = reference_rig_text(variant)
        assert text.count("rated_torque_Nm = 36 ") == text.count("rated_torque_Nm = 240 ") == 1
        assert text.count("[S] RINGFEDER GWB AKN size") == 2
    case = max(paper_cases(), key=lambda c: (c.output_torque_Nm, c.input_torque_Nm))
    ratings = {r.name: r for r in run_sweep(rig, (case,)).cases[0].torque_paths.ratings}
    assert ratings["C3"].torque_Nm == pytest.approx(case.output_torque_Nm, rel=1e-8)
    assert ratings["C3"].rated_use_percent == pytest.approx(100 * 200 / 240, rel=1e-8)
    assert ratings["C1"].rated_use_percent == pytest.approx(100 * case.input_torque_Nm / 36, rel=1e-6)
    assert {r.verdict for r in ratings.values()} == {"within rating"}


def test_the_report_lists_every_rated_coupling_and_shaft_per_case(old):
    from rvcoax.results.reports.report_tables import life_tables

    rig, _ = old
    sweep = run_sweep(rig, CASES[:1])
    table = next(t for t in life_tables(sweep) if t.caption.startswith("Couplings and torque sensors"))
    assert [row[:2] for row in table.rows] == [("T1 = 0 N·m, T2 = 100 N·m", "coupling C2"),
                                               ("T1 = 0 N·m, T2 = 100 N·m", "coupling C3"),
                                               ("T1 = 0 N·m, T2 = 100 N·m", "shaft output_sensor_shaft")]
    c3 = table.rows[1]
    assert c3[2:] == ("76.87", "70", "110 %", "90", "85.4 %", "above rated torque (within peak)")
    assert table.verdict_column == 7


def test_a_rating_in_the_wrong_unit_is_warned_about_before_solving():
    """A kN·m or N·mm slip: C2's 500 N·m written as 0.5 twists it 0.5 / 3.2e5 = 1.6e-6 rad at its 'rating' (couplings
    twist 1e-5 … 0.3 rad at theirs); the sensor shaft's (Ø40, W_t = π 40³ / 16 = 12 566 mm³) 0.5 N·m shears it at
    0.04 MPa (0.5 … 2000 MPa); 500 000 'N·m' on C3 twists it 1.6 rad. The shipped rigs are silent."""
    from rvcoax.geometry.catalogue import plausibility_warnings
    from rvcoax.geometry.rigfile import REFERENCE_VARIANTS, load_rig, parse_rig_text, reference_rig_text

    data = tomllib.loads(example_rig_text())
    data["couplings"][1]["rated_torque_Nm"] = 0.5
    data["couplings"][2]["rated_torque_Nm"] = 5e5
    next(p for p in data["parts"] if p["name"] == "output_sensor_shaft")["rated_torque_Nm"] = 0.5
    next(p for p in data["parts"] if p["name"] == "brake_shaft")["rated_torque_Nm"] = 500.0  # Ø45: 28 MPa, plausible
    warnings = plausibility_warnings(parse_rig(data, "slips.toml"))
    assert warnings == [
        "couplings[1] ('C2').rated_torque_Nm = 0.5 N·m twists the coupling 1.6e-06 rad (torsional_stiffness_Nm_per_rad "
        "= 320000); couplings twist 1e-05 … 0.3 rad at their rating: written in kN·m?",
        "couplings[2] ('C3').rated_torque_Nm = 500000 N·m twists the coupling 1.6 rad (torsional_stiffness_Nm_per_rad "
        "= 320000); couplings twist 1e-05 … 0.3 rad at their rating: written in N·mm?",
        "parts[8] ('output_sensor_shaft').rated_torque_Nm = 0.5 N·m shears the shaft's thinnest section at 0.04 MPa; a "
        "measuring shaft sees 0.5 … 2000 MPa at its rating: written in kN·m?"]
    assert 0.5e3 / (math.pi * 40**3 / 16) == pytest.approx(0.0398, abs=1e-4)
    assert plausibility_warnings(load_rig()) == []
    assert all(plausibility_warnings(parse_rig_text(reference_rig_text(v))) == [] for v in REFERENCE_VARIANTS)
