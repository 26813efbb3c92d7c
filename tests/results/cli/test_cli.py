"""The ``rvcoax`` command line: version, help, rig inspection, sweeps, the published-table check.

Successful runs go through :class:`typer.testing.CliRunner` (in process, fast); exit statuses and
"no traceback" are checked with the installed script in a subprocess so that stderr is real.
``rvcoax check`` (≈ 8 s) runs once, in a module-scoped fixture.
"""

from __future__ import annotations

import csv
import hashlib
import json
import subprocess
import sys
import tomllib
from importlib import resources
from importlib.metadata import version
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.rigfile import load_rig, parse_rig, reference_rig_text
from rvcoax.loadcases.cases import PAPER_TABLE, paper_cases, paper_table
from rvcoax.results.cli.app import app
from rvcoax.results.studies.calibration import DEFAULT_PARAMETERS

FIRST_COLUMNS = ["T1_input_Nm", "T2_output_Nm", "Y_input_mm", "Y_output_mm", "beta_input_deg", "beta_output_deg"]
QUANTITIES = ("Y_input_mm", "Y_output_mm", "beta_input_deg", "beta_output_deg")
PAPER_PAIRS = [(c.input_torque_Nm, c.output_torque_Nm) for c in paper_cases()]


def rvcoax(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    """Run the installed ``rvcoax`` script."""
    script = Path(sys.executable).with_name("rvcoax")
    command = [str(script)] if script.exists() else [sys.executable, "-c", "from rvcoax.results.cli.app import run; run()"]
    return subprocess.run(command + list(args), capture_output=True, text=True, cwd=cwd, timeout=300)


def invoke(*args: str):
    """Run a command in process; fail with its output if it does not exit 0."""
    result = CliRunner().invoke(app, list(args))
    assert result.exit_code == 0, (result.output, result.exception)
    return result


def read_csv(path: Path) -> tuple[list[str], list[dict]]:
    with path.open(newline="", encoding="utf-8") as stream:
        reader = csv.DictReader(stream)
        return list(reader.fieldnames or []), list(reader)


def column(rows: list[dict], name: str) -> np.ndarray:
    return np.array([float(r[name]) for r in rows])


def flat(text: str) -> str:
    return " ".join(text.split())


# ----------------------------------------------------------------------------------------------
# version, help, rig


@pytest.mark.subprocess
def test_version(tmp_path):
    result = rvcoax("--version", cwd=tmp_path)
    assert result.returncode == 0
    assert result.stdout.strip() == f"rvcoax {version('rvcoax')}"


@pytest.mark.subprocess
def test_help_states_units_and_commands(tmp_path):
    result = rvcoax("--help", cwd=tmp_path)
    assert result.returncode == 0
    text = flat(result.stdout)
    for unit in ("N·m", "mm", "degree"):
        assert unit in text, unit
    for command in ("sweep", "check", "rig"):
        assert command in text


def test_rig_show_lists_parts_and_masses():
    output = invoke("rig", "show").output
    for part in load_rig().parts:
        assert part.name in output
    row = next(line for line in output.splitlines() if "brake_housing" in line)
    assert "46.000" in row and "body" in row
    assert "reducer" in output and "4.700" in output
    for name in ("input_B1", "reducer_pedestal", "C3", "sun_gear_mesh", "sun_gear_load_sharing"):
        assert name in output
    assert "total mass" in output


def test_rig_reference_prints_a_loadable_rig(tmp_path):
    result = invoke("rig", "reference")
    assert result.stdout == reference_rig_text()
    data = tomllib.loads(result.stdout)
    assert parse_rig(data, "stdout") == load_rig()
    # and the printed file works as --rig
    path = tmp_path / "my_rig.toml"
    path.write_text(result.stdout, encoding="utf-8")
    assert load_rig(path) == load_rig()


# ----------------------------------------------------------------------------------------------
# sweep


@pytest.fixture(scope="module")
def default_sweep(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("sweep")
    result = invoke("sweep", "--out", str(out))
    assert "wrote" in result.output
    return out


@pytest.fixture(scope="module")
def direct_sweep(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("direct")
    invoke("sweep", "--method", "direct", "--out", str(out))
    return out


def test_sweep_csv_columns_and_rows(default_sweep):
    columns, rows = read_csv(default_sweep / "sweep.csv")
    assert columns[:6] == FIRST_COLUMNS
    assert len(rows) == 20
    assert [(float(r["T1_input_Nm"]), float(r["T2_output_Nm"])) for r in rows] == PAPER_PAIRS
    for name in ("Y_input_mm", "Y_output_mm"):
        assert np.all(column(rows, name) > 0)
    # beta = arcsin(Y / L), L = 120 and 160 mm
    for shaft, length in (("input", 120.0), ("output", 160.0)):
        beta = np.degrees(np.arcsin(column(rows, f"Y_{shaft}_mm") / length))
        np.testing.assert_allclose(column(rows, f"beta_{shaft}_deg"), beta, rtol=1e-8)
        np.testing.assert_allclose(np.abs(column(rows, f"Y_{shaft}_signed_mm")), column(rows, f"Y_{shaft}_mm"),
                                   rtol=1e-9)


def test_sweep_equilibrium(default_sweep):
    _, rows = read_csv(default_sweep / "sweep.csv")
    errors = column(rows, "equilibrium_relative_error")
    assert np.all(np.isfinite(errors))
    assert np.all(errors < 1e-9), errors.max()
    assert np.all(column(rows, "solve_relative_residual") < 1e-9)


def test_sweep_json(default_sweep):
    document = json.loads((default_sweep / "sweep.json").read_text(encoding="utf-8"))
    assert document["units"]["torque"] == "N·m"
    assert document["units"]["Y"].startswith("mm")
    assert document["units"]["beta"] == "degree"
    assert document["rig"]["sha256"] == hashlib.sha256(reference_rig_text().encode("utf-8")).hexdigest()
    assert document["rig"]["path_lengths_mm"] == {"input": 120.0, "output": 160.0}
    assert document["model"]["method"] == "superposition"
    assert document["calibration"] is None
    assert len(document["cases"]) == 20
    _, rows = read_csv(default_sweep / "sweep.csv")
    for case, row in zip(document["cases"], rows):
        assert (case["T1_input_Nm"], case["T2_output_Nm"]) == (float(row["T1_input_Nm"]), float(row["T2_output_Nm"]))
        for shaft, length in (("input", 120.0), ("output", 160.0)):
            path = case[shaft]["path"]
            stations, uy = np.array(path["station_mm"]), np.array(path["uy_mm"])
            assert len(stations) == len(uy) >= 25
            assert stations[0] == 0.0 and stations[-1] == pytest.approx(length)
            assert np.max(np.abs(uy)) == pytest.approx(case[shaft]["Y_max_mm"], rel=1e-12)
            assert case[shaft]["Y_max_mm"] == pytest.approx(float(row[f"Y_{shaft}_mm"]), rel=1e-9)


def test_sweep_paths_csv_matches_json(default_sweep):
    columns, rows = read_csv(default_sweep / "sweep_paths.csv")
    assert columns == ["T1_input_Nm", "T2_output_Nm", "shaft", "station_mm", "uy_mm", "rotation_z_urad"]
    document = json.loads((default_sweep / "sweep.json").read_text(encoding="utf-8"))
    expected = [(c["T1_input_Nm"], c["T2_output_Nm"], shaft, s, u, r)
                for c in document["cases"] for shaft in MEASURED_SHAFTS
                for s, u, r in zip(c[shaft]["path"]["station_mm"], c[shaft]["path"]["uy_mm"],
                                   c[shaft]["path"]["rotation_z_urad"])]
    assert len(rows) == len(expected) >= 20 * 2 * 25
    for row, (t1, t2, shaft, station, uy, rotation) in zip(rows, expected):
        assert (float(row["T1_input_Nm"]), float(row["T2_output_Nm"]), row["shaft"]) == (t1, t2, shaft)
        assert float(row["station_mm"]) == pytest.approx(station, abs=1e-9)
        assert float(row["uy_mm"]) == pytest.approx(uy, rel=1e-9, abs=1e-18)
        assert float(row["rotation_z_urad"]) == pytest.approx(rotation, rel=1e-9, abs=1e-15)


def test_direct_method_equals_superposition(default_sweep, direct_sweep):
    _, rows = read_csv(default_sweep / "sweep.csv")
    _, direct_rows = read_csv(direct_sweep / "sweep.csv")
    assert len(direct_rows) == len(rows) == 20
    for name in ("Y_input_mm", "Y_output_mm", "Y_input_signed_mm", "Y_output_signed_mm"):
        np.testing.assert_allclose(column(direct_rows, name), column(rows, name), rtol=1e-9)
    assert np.all(column(direct_rows, "equilibrium_relative_error") < 1e-9)
    superposed = json.loads((default_sweep / "sweep.json").read_text(encoding="utf-8"))
    direct = json.loads((direct_sweep / "sweep.json").read_text(encoding="utf-8"))
    assert direct["model"]["method"] == "direct"
    for a, b in zip(superposed["cases"], direct["cases"]):
        for shaft in MEASURED_SHAFTS:
            ua, ub = np.array(a[shaft]["path"]["uy_mm"]), np.array(b[shaft]["path"]["uy_mm"])
            np.testing.assert_allclose(ub, ua, rtol=1e-9, atol=1e-9 * np.abs(ua).max())


def test_sweep_paired_torques(tmp_path, default_sweep):
    invoke("sweep", "--t1", "0.5,1.0", "--t2", "70,140", "--out", str(tmp_path))
    _, rows = read_csv(tmp_path / "sweep.csv")
    assert [(float(r["T1_input_Nm"]), float(r["T2_output_Nm"])) for r in rows] == [(0.5, 70.0), (1.0, 140.0)]
    # the same case gives the same Y as in the default sweep (T1 = 1.00, T2 = 140 is a paper row)
    _, paper_rows = read_csv(default_sweep / "sweep.csv")
    paper_row = next(r for r in paper_rows if float(r["T2_output_Nm"]) == 140.0)
    assert float(rows[1]["Y_output_mm"]) == pytest.approx(float(paper_row["Y_output_mm"]), rel=1e-9)


def test_sweep_grid(tmp_path):
    invoke("sweep", "--t1", "0.5,1.0", "--t2", "70,140", "--grid", "--out", str(tmp_path))
    _, rows = read_csv(tmp_path / "sweep.csv")
    assert [(float(r["T1_input_Nm"]), float(r["T2_output_Nm"])) for r in rows] == [
        (0.5, 70.0), (0.5, 140.0), (1.0, 70.0), (1.0, 140.0)]


@pytest.mark.parametrize("name, text", [
    ("cases.csv", "T1_input_Nm,T2_output_Nm\n0.5,70\n1.0,140\n1.43,200\n"),
    ("cases.toml", "[[cases]]\nT1_input_Nm = 0.5\nT2_output_Nm = 70\n[[cases]]\nT1_input_Nm = 1.0\nT2_output_Nm = 140\n"
                   "[[cases]]\nT1_input_Nm = 1.43\nT2_output_Nm = 200\n"),
])
def test_sweep_cases_file(tmp_path, name, text):
    cases = tmp_path / name
    cases.write_text(text, encoding="utf-8")
    invoke("sweep", "--cases", str(cases), "--out", str(tmp_path / "out"))
    _, rows = read_csv(tmp_path / "out" / "sweep.csv")
    assert [(float(r["T1_input_Nm"]), float(r["T2_output_Nm"])) for r in rows] == [(0.5, 70.0), (1.0, 140.0), (1.43, 200.0)]


# ----------------------------------------------------------------------------------------------
# user errors: exit status 2, a message, no traceback


def _user_error(tmp_path: Path, *args: str) -> str:
    result = rvcoax(*args, cwd=tmp_path)
    both = result.stdout + result.stderr
    assert result.returncode == 2, both
    assert "Traceback" not in both
    assert flat(result.stderr).startswith("error:"), result.stderr
    return flat(result.stderr)


@pytest.mark.subprocess
def test_unknown_model_is_rejected(tmp_path):
    message = _user_error(tmp_path, "sweep", "--model", "shell", "--out", str(tmp_path / "out"))
    assert "'shell'" in message and "beam, hybrid, solid" in message
    assert not (tmp_path / "out").exists()


@pytest.mark.subprocess
def test_bad_method(tmp_path):
    message = _user_error(tmp_path, "sweep", "--method", "fast", "--out", str(tmp_path / "out"))
    assert "'superposition' or 'direct'" in message and "'fast'" in message


@pytest.mark.subprocess
def test_non_numeric_torque(tmp_path):
    message = _user_error(tmp_path, "sweep", "--t1", "abc", "--t2", "1", "--out", str(tmp_path / "out"))
    assert "--t1" in message and "'abc'" in message and "N·m" in message
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("args, expected", [
    (("--t1", "1,2", "--t2", "100"), "2 T1 values but 1 T2 values"),
    (("--t1", "1"), "--t1 and --t2 go together"),
    (("--t1", "1", "--t2", "1", "--cases", "cases.csv"), "either --cases FILE or --t1/--t2"),
    (("--t1", "nan", "--t2", "1"), "--t1 'nan', item 1 of 1: 'nan' is not a finite number"),
    (("--cases", "missing.csv"), "load cases missing.csv: 1 problem(s): - file not found"),
], ids=["unequal lists", "t1 alone", "cases and t1", "nan", "missing cases file"])
@pytest.mark.subprocess
def test_bad_load_cases(tmp_path, args, expected):
    assert expected in _user_error(tmp_path, "sweep", *args, "--out", str(tmp_path / "out"))


@pytest.mark.subprocess
def test_cases_file_with_a_short_row(tmp_path):
    (tmp_path / "short.csv").write_text("T1_input_Nm,T2_output_Nm\n1.0,100\n0.5\n", encoding="utf-8")
    message = _user_error(tmp_path, "sweep", "--cases", "short.csv", "--out", str(tmp_path / "out"))
    assert "load cases short.csv: 1 problem(s): - line 3, T2_output_Nm: value is missing" in message


@pytest.mark.subprocess
def test_out_is_a_file(tmp_path):
    (tmp_path / "taken").write_text("not a folder", encoding="utf-8")
    message = _user_error(tmp_path, "sweep", "--t1", "1", "--t2", "100", "--out", "taken")
    assert "cannot write" in message and "taken" in message
    assert (tmp_path / "taken").read_text(encoding="utf-8") == "not a folder"


@pytest.mark.subprocess
def test_check_on_a_rig_without_the_calibrated_parameters(tmp_path):
    rig = tmp_path / "renamed.toml"
    rig.write_text(reference_rig_text().replace('name = "sun_gear_load_sharing"', 'name = "sun_mesh"'), encoding="utf-8")
    # an edited reference rig is not the reference rig: the paper's table is no longer its default
    message = _user_error(tmp_path, "check", "--rig", str(rig))
    assert str(rig) in message and "nothing to compare with" in message and "--measured" in message
    table = tmp_path / "paper.csv"
    table.write_text(resources.files("rvcoax.loadcases").joinpath("data", PAPER_TABLE).read_text(), encoding="utf-8")
    message = _user_error(tmp_path, "check", "--rig", str(rig), "--measured", str(table))
    assert str(rig) in message
    assert "cannot calibrate" in message and "sun_gear_load_sharing" in message


# ----------------------------------------------------------------------------------------------
# check (run once)


@pytest.fixture(scope="module")
def check_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("check")
    result = rvcoax("check", "--out", str(out), cwd=out)
    return result, out


def test_check_names_the_implausible_fit_and_exits_3(check_run):
    """The reference rig meets the tolerance on every held-out row, but only with an output imbalance
    of 0.48 (plausible ±0.15): the verdict says so and the exit status is 3, not a plain pass."""
    result, out = check_run
    assert result.returncode == 3, result.stdout + result.stderr
    assert "Traceback" not in result.stdout + result.stderr
    text = " ".join(result.stdout.split())
    assert "VERDICT: within tolerance, but fits only with implausible parameter(s): " \
           "torque_lateral_loads.crankshaft_load_sharing.imbalance (output shaft) = 0.47" in text
    written = json.loads((out / "check_verdict.json").read_text(encoding="utf-8"))
    assert written["status"] == "within_tolerance_implausible_fit" and written["exit_code"] == 3
    assert written["held_out_values_outside_tolerance"] == 0
    assert len(written["implausible_parameters"]) == 1


def test_check_csv(check_run):
    _, out = check_run
    columns, rows = read_csv(out / "check.csv")
    assert len(rows) == 20
    assert [(float(r["T1_input_Nm"]), float(r["T2_output_Nm"])) for r in rows] == PAPER_PAIRS
    for q in QUANTITIES:
        for prefix in ("published_", "blind_", "calibrated_", "calibrated_within_tolerance_"):
            assert prefix + q in columns
    assert {r["used_for_fit"] for r in rows} == {"True", "False"}
    fit = [float(r["T2_output_Nm"]) for r in rows if r["used_for_fit"] == "True"]
    assert sorted(fit) == [10.0, 200.0]
    table = paper_table()
    for row, published in zip(rows, table):
        assert float(row["published_Y_input_mm"]) == published.y_input_mm
        assert float(row["published_Y_output_mm"]) == published.y_output_mm
        if row["used_for_fit"] == "False":
            for q in QUANTITIES:
                assert row[f"calibrated_within_tolerance_{q}"] == "True", (row["T2_output_Nm"], q)
        else:  # the fitting rows are reproduced (two parameters, two rows, per shaft)
            for q in ("Y_input_mm", "Y_output_mm"):
                assert abs(float(row[f"calibrated_rel_error_{q}"])) < 1e-6


def test_check_writes_the_calibrated_sweep(check_run):
    _, out = check_run
    for name in ("sweep.csv", "sweep.json", "sweep_paths.csv", "blind_sweep.csv", "blind_sweep.json"):
        assert (out / name).is_file(), name


def test_check_picture_comes_from_its_process_whole(check_run):
    """The picture is drawn by a second process (rvcoax.results.io.picture_process): it is there, a whole PNG,
    and no temporary file of its atomic write is left beside it."""
    _, out = check_run
    picture = out / "check_beam.png"
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and picture.stat().st_size > 10_000
    assert not [p.name for p in out.iterdir() if ".tmp" in p.name]
    document = json.loads((out / "sweep.json").read_text(encoding="utf-8"))
    calibration = document["calibration"]
    assert calibration is not None
    assert [p["address"] for p in calibration["parameters"]] == [p.address for p in DEFAULT_PARAMETERS]
    assert len(calibration["parameters"]) == 4
    assert calibration["fit_rows_index"] == [0, 19]
    assert calibration["fit_relative_residual"] < 1e-6
    assert json.loads((out / "blind_sweep.json").read_text(encoding="utf-8"))["calibration"] is None
    # sweep.csv holds the calibrated values that check.csv reports
    _, sweep_rows = read_csv(out / "sweep.csv")
    _, check_rows = read_csv(out / "check.csv")
    for q in QUANTITIES:
        np.testing.assert_allclose(column(sweep_rows, q), column(check_rows, f"calibrated_{q}"), rtol=1e-9)
