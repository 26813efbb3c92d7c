"""Hostile inputs through the real command line, and valid inputs that must never be refused.

Each case of the generated corpus (``tests/support/bad_inputs.py``: rig TOML files, load-case CSV/TOML,
measured-data CSV) is run through ``rvcoax`` in process (typer's CliRunner on ``rvcoax.results.cli.app.app``):
rig files through ``rig show`` and ``sweep``, unsolvable rigs through ``sweep``, load cases through
``sweep --cases``, measured data through ``discrepancy --measured`` (validated before any solve).
Each must end with exit status 2 and one message on stderr that names the file, the line or key
and the reason, and no traceback. A few run as real processes too. The property tests draw valid
variations (stiffnesses, positions, materials, formatting of CSVs) and check that none is refused.
"""

from __future__ import annotations

import math
import subprocess
import sys
import time
from pathlib import Path

import pytest
from bad_inputs import all_cases
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from rigdata import dump_toml, reference_data
from typer.testing import CliRunner

from rvcoax.geometry.model.preflight import support_problem
from rvcoax.geometry.rigfile import parse_rig
from rvcoax.loadcases.cases import read_cases
from rvcoax.results.cli.app import app
from rvcoax.results.studies.discrepancy.measured import read_measured

CORPUS = all_cases()
BY_NAME = {case.name: case for case in CORPUS}


def flat(text: str) -> str:
    return " ".join(text.split())


def commands(kind: str, path: Path, out: Path) -> list[list[str]]:
    """The command lines that must refuse an input of ``kind``."""
    solve = ["--t1", "1", "--t2", "100", "--out", str(out)]
    return {
        "rig": [["rig", "show", "--rig", str(path)], ["sweep", "--rig", str(path), *solve]],
        "model": [["sweep", "--rig", str(path), *solve]],
        "cases": [["sweep", "--cases", str(path), "--out", str(out)]],
        "measured": [["discrepancy", "--measured", str(path), "--out", str(out)]],
    }[kind]


def test_the_corpus_is_large_and_covers_every_input():
    assert len(CORPUS) >= 200
    assert len(BY_NAME) == len(CORPUS)  # unique ids
    counts = {kind: sum(c.kind == kind for c in CORPUS) for kind in ("rig", "model", "cases", "measured")}
    assert counts["rig"] >= 150 and counts["cases"] >= 30 and counts["measured"] >= 30 and counts["model"] >= 5


@pytest.mark.parametrize("case", CORPUS, ids=[c.name for c in CORPUS])
def test_bad_input_ends_with_a_clear_message(case, tmp_path):
    folder = tmp_path / "in"
    folder.mkdir()
    path = case.make(folder)
    out = tmp_path / "out"
    for args in commands(case.kind, path, out):
        result = CliRunner().invoke(app, args + list(case.options))
        message = flat(result.stderr)
        context = f"{args}\nstdout: {result.stdout}\nstderr: {result.stderr}\nexception: {result.exception!r}"
        assert result.exit_code == 2, context
        assert isinstance(result.exception, SystemExit), context  # not an uncaught error
        assert "Traceback" not in result.output, context
        # the error paragraph, after any warnings about the same input (a stiffness 1e12 times too high is
        # named as implausible, then as the reason the rig cannot be solved)
        assert message.startswith(("error:", "warning:")) and "error:" in message, context
        message = message[message.index("error:"):]
        assert str(path) in message, context
        for text in case.expected:
            assert text in message, f"{text!r} missing\n{context}"
    assert not (out / "sweep.csv").exists() and not (out / "discrepancy.json").exists()


@pytest.mark.parametrize("name", ["rig: 200 MB file", "cases: 200 MB file", "measured: 200 MB file"])
def test_huge_files_are_refused_before_reading(name, tmp_path):
    path = BY_NAME[name].make(tmp_path)
    assert path.stat().st_size == 200_000_000 and path.stat().st_blocks * 512 < 1_000_000  # sparse
    start = time.perf_counter()
    result = CliRunner().invoke(app, commands(BY_NAME[name].kind, path, tmp_path / "out")[0])
    assert result.exit_code == 2 and "too large" in result.stderr
    assert time.perf_counter() - start < 5.0  # reading 200 MB of zeros and parsing them would take far longer


@pytest.mark.parametrize("name", ["rig: a CSV", "cases: CSV semicolons", "measured: paths x in metres",
                                  "model: zero-stiffness brake feet"])
@pytest.mark.subprocess
def test_a_real_process_prints_the_message_and_no_traceback(name, tmp_path):
    case = BY_NAME[name]
    path = case.make(tmp_path)
    script = Path(sys.executable).with_name("rvcoax")
    result = subprocess.run([str(script), *commands(case.kind, path, tmp_path / "out")[0]], capture_output=True,
                            text=True, timeout=120)
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stdout + result.stderr
    assert str(path) in flat(result.stderr)
    for text in case.expected:
        assert text in flat(result.stderr), result.stderr


# ------------------------------------------------------------------------------------------ valid inputs


@st.composite
def rig_variations(draw) -> dict:
    """The reference rig with plausible values drawn for stiffnesses (a third to three times the
    reference's), positions, materials and options. Far wider ranges are not all valid: all
    mounts at 1e3 N·m/rad and 50 N/µm, for one, leave a condition number of 5.5e11, rightly refused."""
    data = reference_data()
    unit = st.floats(0.0, 1.0)
    factor = st.floats(1 / 3, 3.0)
    for bearing in data["bearings"]:
        bearing["radial_stiffness_N_per_um"] *= draw(factor)
        if "axial_stiffness_N_per_um" in bearing:  # the locating bearings (no axial stiffness at all is a mechanism)
            bearing["axial_stiffness_N_per_um"] *= draw(factor)
    # bearing positions inside both the shaft and the housing, apart from the other bearing
    data["bearings"][4]["x_mm"] = 248.0 + 52.0 * draw(unit)
    data["bearings"][6]["x_mm"] = 420.0 + 70.0 * draw(unit)
    for mount in data["mounts"]:
        mount["translational_stiffness_N_per_um"] = [v * draw(factor) for v in mount["translational_stiffness_N_per_um"]]
        mount["rotational_stiffness_Nm_per_rad"] = [v * draw(factor) for v in mount["rotational_stiffness_Nm_per_rad"]]
        mount["vertical_offset_um"] = draw(st.floats(-50.0, 50.0))
    for coupling in data["couplings"]:
        for key in ("radial_stiffness_N_per_mm", "angular_stiffness_Nm_per_rad", "torsional_stiffness_Nm_per_rad"):
            coupling[key] *= draw(factor)
        coupling["mass_kg"] = draw(st.floats(0.0, 2.0))
        coupling["parallel_offset_um"] = draw(st.floats(-100.0, 100.0))
        coupling["angular_misalignment_mrad"] = draw(st.floats(-1.0, 1.0))
        coupling["misalignment_direction_deg"] = draw(st.floats(0.0, 360.0))
    for material in data["materials"].values():
        material["youngs_modulus_MPa"] *= draw(st.floats(0.5, 2.0))
        material["poisson_ratio"] = draw(st.floats(0.2, 0.35))
        material["density_kg_per_m3"] = draw(st.floats(6000.0, 9000.0))
    for part in data["parts"]:
        if part["role"] == "body":
            part["mass_kg"] *= draw(st.floats(0.5, 2.0))
    for segment in data["parts"][5]["segments"]:
        segment["outer_diameter_mm"] = draw(st.floats(16.0, 24.0))
    for load in data["torque_lateral_loads"]:
        load["imbalance"] = draw(st.floats(-0.15, 0.15))
        load["position_error_um"] = draw(st.floats(-3.0, 3.0))
    data["gravity"]["enabled"] = draw(st.booleans())
    data["paths"]["measured_from"] = draw(st.sampled_from(["aligned_at_rest", "unloaded"]))
    data["paths"]["output"]["stations"] = draw(st.integers(25, 201))
    return data


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=rig_variations())
def test_valid_rig_variations_are_never_refused(data, tmp_path_factory):
    rig = parse_rig(data, "variation")
    assert support_problem(rig) is None
    folder = tmp_path_factory.mktemp("rig")
    path = folder / "rig.toml"
    path.write_text(dump_toml(data), encoding="utf-8")
    result = CliRunner().invoke(app, ["sweep", "--rig", str(path), "--t1", "0.5,1.43", "--t2", "70,200",
                                      "--out", str(folder / "out")])
    assert result.exit_code == 0, (result.stderr, result.exception)
    assert (folder / "out" / "sweep.csv").is_file()


def written(tmp_path_factory, text: str) -> Path:
    """``text`` in a new CSV file (UTF-8 bytes as given: BOM and line ends kept)."""
    path = tmp_path_factory.mktemp("valid") / "input.csv"
    path.write_bytes(text.encode("utf-8"))
    return path


NUMBER_FORMATS = (repr, lambda v: f"{v:.6e}", lambda v: f"{v:g}", lambda v: f" {v!r} ")


@st.composite
def valid_case_files(draw) -> tuple[str, list[tuple[float, float]]]:
    """A CSV of unique torque pairs, formatted as spreadsheets and hands write them."""
    torques = st.tuples(st.floats(-2.0, 2.0, allow_nan=False), st.floats(-300.0, 300.0, allow_nan=False))
    pairs = draw(st.lists(torques, min_size=1, max_size=8))
    fmt = draw(st.sampled_from(NUMBER_FORMATS))
    texts = [(fmt(t1), fmt(t2)) for t1, t2 in pairs]
    values = [(float(a), float(b)) for a, b in texts]
    unique = list(dict.fromkeys(values))
    texts = [texts[values.index(v)] for v in unique]
    columns = ["T1_input_Nm", "T2_output_Nm"] + (["note"] if draw(st.booleans()) else [])
    order = draw(st.permutations(columns))
    newline = draw(st.sampled_from(["\n", "\r\n"]))
    lines = [",".join(f" {c} " if draw(st.booleans()) else c for c in order)]
    for t1, t2 in texts:
        cell = {"T1_input_Nm": t1, "T2_output_Nm": t2, "note": "measured"}
        lines.append(",".join(cell[c] for c in order))
        if draw(st.booleans()):
            lines.append("")  # a blank line
    text = newline.join(lines) + (newline if draw(st.booleans()) else "")
    return ("\ufeff" if draw(st.booleans()) else "") + text, unique


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(case_file=valid_case_files())
def test_valid_load_case_files_are_never_refused(case_file, tmp_path_factory):
    text, expected = case_file
    cases = read_cases(written(tmp_path_factory, text))
    assert [(c.input_torque_Nm, c.output_torque_Nm) for c in cases] == expected


def test_an_odd_but_valid_case_file_runs_through_the_command_line(tmp_path):
    path = tmp_path / "cases.csv"
    path.write_bytes("\ufeff note , T2_output_Nm , T1_input_Nm \r\nfirst, 70 , 0.5 \r\n\r\nsecond,2.0e2,1.43\r\n"
                     .encode("utf-8"))
    result = CliRunner().invoke(app, ["sweep", "--cases", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 0, result.stderr
    rows = (tmp_path / "out" / "sweep.csv").read_text(encoding="utf-8").splitlines()
    assert [r.split(",")[:2] for r in rows[1:]] == [["0.5", "70.0"], ["1.43", "200.0"]]


@st.composite
def valid_measured_files(draw) -> tuple[str, int]:
    """Measured data in either schema with plausible values, optional σ, BOM and CRLF."""
    newline = draw(st.sampled_from(["\n", "\r\n"]))
    sigma = draw(st.booleans())
    torques = st.tuples(st.floats(0.0, 2.0), st.floats(0.0, 300.0))
    cases = list(dict.fromkeys(draw(st.lists(torques, min_size=1, max_size=6))))
    if draw(st.booleans()):
        lines = ["T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm" + (",sigma_mm" if sigma else "")]
        for t1, t2 in cases:
            y = [draw(st.floats(0.0, 1.0)) for _ in range(2)]
            lines.append(f"{t1!r},{t2!r},{y[0]!r},{y[1]!r}" + (f",{draw(st.floats(1e-9, 1e-3))!r}" if sigma else ""))
        count = 2 * len(cases)
    else:
        lines = ["T1_input_Nm,T2_output_Nm,shaft,x_mm,uy_mm" + (",sigma_mm" if sigma else "")]
        count = 0
        for t1, t2 in cases:
            for shaft, length in (("input", 120.0), ("output", 160.0)):
                stations = draw(st.lists(st.floats(0.0, length), min_size=2, max_size=6, unique=True))
                if max(stations) <= 0.5:
                    stations.append(length)  # a path shorter than 0.5 mm is metres, rightly refused
                for x in stations:
                    lines.append(f"{t1!r},{t2!r},{shaft},{x!r},{draw(st.floats(-1.0, 1.0))!r}"
                                 + (f",{draw(st.floats(1e-9, 1e-3))!r}" if sigma else ""))
                count += len(stations)
    text = newline.join(lines) + newline
    return ("\ufeff" if draw(st.booleans()) else "") + text, count


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(measured=valid_measured_files())
def test_valid_measured_files_are_never_refused(measured, tmp_path_factory):
    text, count = measured
    data = read_measured(written(tmp_path_factory, text))
    assert data.n == count
    assert all(math.isfinite(v) for v in data.value_mm)
