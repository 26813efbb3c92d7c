"""The second shipped rig (an RV-40E bench of another layout) end to end, and the neutral defaults:
load cases and the compared table come from the rig and the user, paper 000's only for the reference rig.
"""

from __future__ import annotations

import csv
import re

import numpy as np
import pytest
from typer.testing import CliRunner

from rvcoax.geometry.builtin import EXAMPLE_RIG, example_rig_text, is_reference_rig, load_example_rig
from rvcoax.geometry.rigfile import RigFileError, load_rig, parse_rig_text, reference_rig_text
from rvcoax.loadcases.cases import NoLoadCasesError, default_cases, paper_cases, rig_cases
from rvcoax.results.cli.app import app
from rvcoax.results.engineering import engineering_tables
from rvcoax.results.studies.check import measured_rows
from rvcoax.results.studies.check_run import MissingTableError, run_check
from rvcoax.results.studies.discrepancy.measured import parse_measured
from rvcoax.results.sweep import run_sweep

CASES_BLOCK = re.compile(r"\[\[load_cases\]\]\n(?:[A-Za-z0-9_]+ += [^\n]*\n)+")


@pytest.fixture(scope="module")
def rig():
    return load_example_rig()


@pytest.fixture(scope="module")
def sweep(rig):
    return run_sweep(rig, default_cases(rig))


@pytest.fixture(scope="module")
def rig_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("rig") / EXAMPLE_RIG
    path.write_text(example_rig_text(), encoding="utf-8")
    return path


def test_example_rig_names_its_own_load_cases(rig):
    cases = default_cases(rig)
    assert [c.output_torque_Nm for c in cases] == [82.4, 164.8, 247.2, 329.6, 412.0]  # 20 … 100 % of rated
    assert not is_reference_rig(rig)
    assert rig.paths.output.length_mm == 260.0
    assert default_cases(load_rig()) == paper_cases()  # the reference rig alone falls back on the paper


def test_reference_rig_is_recognised_by_its_content_not_its_name():
    text = reference_rig_text()
    assert is_reference_rig(parse_rig_text(text))
    without_comments = "\n".join(line.split("#")[0].rstrip() for line in text.splitlines())
    assert is_reference_rig(parse_rig_text(without_comments))  # layout and comments do not matter
    assert not is_reference_rig(parse_rig_text(text.replace("mass_kg = 46.0", "mass_kg = 46.5")))
    reference_name = load_rig().rig.name
    impostor = example_rig_text().replace(load_example_rig().rig.name, reference_name)
    assert not is_reference_rig(parse_rig_text(impostor))  # a name is no identity


def test_a_sweep_range_in_the_rig_file_and_its_errors():
    text = CASES_BLOCK.sub("", example_rig_text())
    no_cases = parse_rig_text(text)
    assert rig_cases(no_cases) is None
    with pytest.raises(NoLoadCasesError, match=r"\[\[load_cases\]\].*--cases"):
        default_cases(no_cases)
    ranged = parse_rig_text(text + "\n[sweep]\nT1_input_Nm = [0.5, 2.5]\nT2_output_Nm = [50.0, 250.0]\ncases = 5\n")
    cases = rig_cases(ranged)
    assert [c.output_torque_Nm for c in cases] == pytest.approx([50, 100, 150, 200, 250])
    assert [c.input_torque_Nm for c in cases] == pytest.approx([0.5, 1.0, 1.5, 2.0, 2.5])
    with pytest.raises(RigFileError, match="not both"):
        parse_rig_text(example_rig_text() + "\n[sweep]\nT1_input_Nm = [0.5, 2.5]\nT2_output_Nm = [50.0, 250.0]\ncases = 5\n")


def test_engineering_tables_of_the_example_rig(rig, sweep):
    tables = engineering_tables(sweep)
    assert len(tables) == 5
    last = tables[-1]
    assert [c["name"] for c in last["couplings"]] == ["C1", "C2", "C3"]
    assert {c["grade"] for c in last["couplings"]} <= {"excellent", "acceptable", "out of tolerance"}
    assert [b["name"] for b in last["bearings"]] == [b.name for b in rig.bearings]
    assert [r["name"] for r in last["reactions"]] == [m.name for m in rig.mounts]
    weight = sum(r["force_N"][1] for r in last["reactions"])  # the mounts carry the whole rig's weight
    mass_kg = sum(sweep.frame.part_mass_kg.values())  # coupling masses are in their hubs' parts
    assert weight == pytest.approx(mass_kg * 9.80665, rel=1e-9)
    assert last["equilibrium_residual"]["force_N"] < 1e-6 * weight
    # torque flows: the stators take the opposite torques (reacted_on), so the reactions about x sum to zero and the
    # reducer's pedestal carries T2 − T1, the brake's feet T2 and the motor's bracket T1
    moments = {r["name"]: r["moment_Nm"][0] for r in last["reactions"]}
    assert abs(sum(moments.values())) < 1e-9 * last["T2_output_Nm"]
    assert moments["reducer_pedestal"] == pytest.approx(last["T2_output_Nm"] - last["T1_input_Nm"], rel=1e-6)
    assert moments["brake_feet"] == pytest.approx(-last["T2_output_Nm"], rel=1e-6)
    assert moments["motor_bracket"] == pytest.approx(last["T1_input_Nm"], rel=1e-6)
    output = last["shafts"]["output"]
    assert output["Y_max_um"] == pytest.approx(sweep.cases[-1].paths["output"].y_max_mm * 1e3)
    assert output["beta_paper_urad"] == pytest.approx(np.radians(output["beta_paper_deg"]) * 1e6)
    # a linear model: the change under load doubles from 40 % to 80 % of the rated torque (T1 is rounded
    # to four digits in the file: 3.205 against 2 × 1.602)
    b1 = [next(b for b in t["bearings"] if b["name"] == "output_B1") for t in tables]
    assert b1[3]["force_radial_change_N"] == pytest.approx(2 * b1[1]["force_radial_change_N"], rel=1e-4)
    assert b1[3]["force_radial_change_N"] != pytest.approx(b1[1]["force_radial_change_N"], rel=0.5)


def test_an_installed_coupling_misalignment_stays_in_the_coupling(rig):
    text = example_rig_text().replace("speed_rpm = 15                      # [S] rated output speed of the RV-40E",
                                      "speed_rpm = 15\nparallel_offset_um = 30.0", 1)
    misaligned = parse_rig_text(text)
    assert misaligned.couplings[1].parallel_offset_um == 30.0
    sweep = run_sweep(misaligned, default_cases(misaligned)[:1])
    coupling = engineering_tables(sweep)[0]["couplings"][1]
    # aligned at rest, the load adds well under a µm (C2 at 82 N·m: 0.006 µm) to the installed 30 µm
    assert coupling["offset_um"] == pytest.approx(30.0, abs=0.1)
    assert coupling["offset_use_percent"] == pytest.approx(100 * 0.030 / 0.25, abs=0.1)
    # issue 24: one name, one definition: the dynamics export's offsets are sweep.csv's, in both references
    from rvcoax.results.export.dynamics import coupling_rows, dynamics_export

    row = next(r for r in coupling_rows(dynamics_export(sweep)) if r["coupling"] == coupling["name"])
    assert row["offset_radial_um"] == pytest.approx(coupling["offset_um"], rel=1e-12)
    assert row["offset_radial_unloaded_ref_um"] == pytest.approx(coupling["offset_from_unloaded_um"], rel=1e-12)
    assert row["angle_deg"] == pytest.approx(coupling["angle_deg"], rel=1e-12, abs=1e-15)


def _invoke(*args):
    return CliRunner().invoke(app, list(args), env={"COLUMNS": "200"})


def test_rig_example_prints_the_example_rig():
    result = _invoke("rig", "example")
    assert result.exit_code == 0
    assert parse_rig_text(result.output) == load_example_rig()


def test_sweep_command_on_the_example_rig(rig_file, tmp_path):
    result = _invoke("sweep", "--rig", str(rig_file), "--out", str(tmp_path))
    assert result.exit_code == 0, result.output
    assert "5 load cases" in result.output and "β_in (paper)" in result.output
    for title in ("Couplings at T1 = 4.006 N·m, T2 = 412 N·m", "Bearings at", "Support reactions at", "Equilibrium residual"):
        assert title in result.output
    with (tmp_path / "sweep.csv").open(newline="", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    assert len(rows) == 5
    columns = list(rows[0])
    assert columns[:2] == ["T1_input_Nm", "T2_output_Nm"]
    for name in ("tilt_output_urad", "end_slope_start_output_urad", "offset_end_output_um", "Y_output_um",
                 "coupling_C2_offset_um", "coupling_C2_alignment_grade", "bearing_output_B2_tilt_use_percent",
                 "reaction_brake_feet_Fy_N", "equilibrium_residual_force_N"):
        assert name in columns
    assert "bearing_brake_a_tilt_use_percent" not in columns  # no allowable given: no column


def test_sweep_command_without_load_cases_says_what_is_needed(tmp_path):
    path = tmp_path / "no_cases.toml"
    path.write_text(CASES_BLOCK.sub("", example_rig_text()), encoding="utf-8")
    result = _invoke("sweep", "--rig", str(path), "--out", str(tmp_path / "out"))
    assert result.exit_code == 2
    text = " ".join(result.output.split())
    assert "names no load cases" in text and "[[load_cases]]" in text and "--t1/--t2" in text
    assert not (tmp_path / "out" / "sweep.csv").exists()
    assert _invoke("sweep", "--rig", str(path), "--t1", "1", "--t2", "100", "--out", str(tmp_path / "o")).exit_code == 0


def _measured_files(sweep, folder):
    """A table and a paths file made from the model's own results (Y scaled, to see the fit work)."""
    table = folder / "measured_table.csv"
    lines = ["T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm"]
    for i, case in enumerate(sweep.cases):
        scale = 1.0 + 0.01 * (i - 2)
        lines.append(f"{case.case.input_torque_Nm},{case.case.output_torque_Nm},"
                     f"{case.paths['input'].y_max_mm * 1.05:.6g},{case.paths['output'].y_max_mm * scale:.6g}")
    table.write_text("\n".join(lines) + "\n", encoding="utf-8")
    paths = folder / "measured_paths.csv"
    lines = ["T1_input_Nm,T2_output_Nm,shaft,x_mm,uy_mm"]
    for case in sweep.cases:
        for shaft, path in case.paths.items():
            for k in (0, 10, 20, 30, 40):  # five of the path's stations
                lines.append(f"{case.case.input_torque_Nm},{case.case.output_torque_Nm},{shaft},"
                             f"{path.station_mm[k]:.6g},{path.uy_mm[k]:.8g}")
    paths.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return table, paths


def test_check_api_on_the_example_rig(rig, sweep, tmp_path):
    with pytest.raises(MissingTableError, match="measured"):
        run_check(rig)
    table, paths = _measured_files(sweep, tmp_path)
    lengths = {"input": rig.paths.input.length_mm, "output": rig.paths.output.length_mm}
    rows = measured_rows(parse_measured(paths.read_text(), str(paths)), lengths)
    assert rows[0].stations_output_mm is not None and len(rows[0].stations_output_mm) == 5
    run = run_check(rig, rows)
    # the model's own values at the measured stations: blind agrees to the printed digits
    assert run.blind_verdict.worst_relative_error < 1e-6
    assert run.outcome.status == "within_tolerance"


def test_check_command_on_the_example_rig(rig_file, sweep, tmp_path):
    result = _invoke("check", "--rig", str(rig_file))
    assert result.exit_code == 2
    assert "--measured" in result.output and "reference rig only" in " ".join(result.output.split())
    table, _ = _measured_files(sweep, tmp_path)
    result = _invoke("check", "--rig", str(rig_file), "--measured", str(table), "--out", str(tmp_path / "check"))
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "measured (" in text and "fitted on T2 = 82.4 and 412 N·m" in text and "paper 000" not in text
    with (tmp_path / "check" / "check.csv").open(newline="", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    assert [r["used_for_fit"] for r in rows] == ["True", "False", "False", "False", "True"]
