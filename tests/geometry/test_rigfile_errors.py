"""Bad rig files: a clear message naming the file, the key and the reason, never a traceback.

Bad files are made from the reference rig: either a TOML text edit of
:func:`rvcoax.geometry.rigfile.reference_rig_text` or a change to its parsed dict, validated with
:func:`rvcoax.geometry.rigfile.parse_rig` (or written back with the small TOML writer below for the
command-line tests).
"""

from __future__ import annotations

import csv
import math
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from rigdata import dump_toml, reference_data

from rvcoax.geometry.model.beam import build_rig_model
from rvcoax.geometry.rigfile import RigFileError, load_rig, parse_rig, reference_rig_text
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.sweep import ModelError, run_sweep

SOURCE = "test.toml"
REPO = Path(__file__).resolve().parents[2]


# ----------------------------------------------------------------------------------------------
# helpers


def index_of(data: dict, group: str, name: str) -> int:
    return next(i for i, item in enumerate(data[group]) if item["name"] == name)


def problems_of(data: dict) -> str:
    """Validate ``data``; return the RigFileError message (fails the test if it validates)."""
    with pytest.raises(RigFileError) as caught:
        parse_rig(data, SOURCE)
    message = str(caught.value)
    assert message.startswith(f"rig file {SOURCE}:"), message
    assert caught.value.source == SOURCE
    assert len(caught.value.problems) >= 1
    assert f"{len(caught.value.problems)} problem(s)" in message
    assert "Traceback" not in message and "pydantic" not in message.lower(), message
    return message


def floating_brake(data: dict) -> dict:
    """Remove the brake's two bearings and its feet: brake_housing then has no support path to ground."""
    data["bearings"] = [b for b in data["bearings"] if b["name"] not in ("brake_a", "brake_b")]
    data["mounts"] = [m for m in data["mounts"] if m["name"] != "brake_feet"]
    return data


def rvcoax(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    """Run the installed ``rvcoax`` script (real stdout / stderr)."""
    script = Path(sys.executable).with_name("rvcoax")
    command = [str(script)] if script.exists() else [sys.executable, "-c", "from rvcoax.results.cli.app import run; run()"]
    return subprocess.run(command + list(args), capture_output=True, text=True, cwd=cwd, timeout=120)


def flat(text: str) -> str:
    """Whitespace collapsed (rich wraps long messages)."""
    return " ".join(text.split())


# ----------------------------------------------------------------------------------------------
# the reference rig and the test helpers themselves


def test_reference_rig_loads_and_builds():
    rig = load_rig()
    model = build_rig_model(rig)
    assert len(rig.parts) == 13
    assert {p.name for p in rig.parts} >= {"input_shaft", "output_shaft", "reducer", "brake_housing"}
    # bodies are modelled with the catalogue mass they declare
    for part in rig.parts:
        if part.role == "body":
            assert model.part_mass_kg[part.name] == pytest.approx(part.mass_kg, rel=1e-9)
    assert model.structure.n_dofs == 6 * model.structure.n_nodes > 0


def test_toml_writer_round_trips_the_reference_rig():
    data = reference_data()
    assert tomllib.loads(dump_toml(data)) == data


def test_reference_rig_text_and_file_load_identically(tmp_path):
    path = tmp_path / "copy.toml"
    path.write_text(reference_rig_text(), encoding="utf-8")
    assert load_rig(path) == load_rig()


def test_reference_rig_tags_its_numbers():
    text = reference_rig_text()
    for tag in ("[A]", "[P]", "[S]", "[R]"):
        assert tag in text, tag
    assert text.count("[A]") >= 20  # most of the rig is our assumption, and says so
    tagged_keys = ("mass_kg", "radial_stiffness_N_per_um", "youngs_modulus_MPa", "poisson_ratio", "density_kg_per_m3")
    for line in text.splitlines():
        key = line.split("=")[0].strip()
        if key in tagged_keys:
            assert re.search(r"\[[APSRD]\]", line), f"untagged value: {line!r}"


def _materials_csv() -> Path | None:
    for candidate in (REPO / "shared" / "reference" / "materials.csv", REPO.parent / "shared" / "reference" / "materials.csv"):
        if candidate.is_file():
            return candidate
    return None


def test_reference_materials_equal_the_papers_table():
    path = _materials_csv()
    if path is None:
        pytest.skip("shared/reference/materials.csv is not available")
    rig = load_rig()
    with path.open(newline="", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    assert {r["material"] for r in rows} == set(rig.materials)
    for row in rows:
        material = rig.materials[row["material"]]
        assert material.youngs_modulus_MPa == pytest.approx(float(row["E_MPa"]), rel=1e-12)
        assert material.poisson_ratio == pytest.approx(float(row["poisson"]), rel=1e-12)
        assert material.density_kg_per_m3 == pytest.approx(float(row["density_kg_m3"]), rel=1e-12)


# ----------------------------------------------------------------------------------------------
# schema errors (parse_rig on an edited dict)


def _set(path: tuple, value):
    def edit(data):
        target = data
        for step in path[:-1]:
            target = target[step]
        target[path[-1]] = value
    return edit


def _delete(path: tuple):
    def edit(data):
        target = data
        for step in path[:-1]:
            target = target[step]
        del target[path[-1]]
    return edit


def _rename_key(path: tuple, old: str, new: str):
    def edit(data):
        target = data
        for step in path:
            target = target[step]
        target[new] = target.pop(old)
    return edit


# (edit, substrings the message must hold: the key path and the reason)
SCHEMA_CASES = {
    "missing bearing stiffness": (
        _delete(("bearings", 0, "radial_stiffness_N_per_um")),
        ["bearings[0] ('motor_front').radial_stiffness_N_per_um", "required key is missing"],
    ),
    "missing paths.output": (
        _delete(("paths", "output")),
        ["paths.output", "required key is missing"],
    ),
    "missing schema_version": (
        _delete(("schema_version",)),
        ["schema_version", "required key is missing"],
    ),
    "misspelled key": (
        _rename_key(("bearings", 4), "radial_stiffness_N_per_um", "radial_stifness_N_per_um"),
        ["bearings[4] ('input_B1').radial_stifness_N_per_um", "unknown key",
         "bearings[4] ('input_B1').radial_stiffness_N_per_um: required key is missing"],
    ),
    "negative diameter": (
        _set(("parts", 5, "segments", 0, "outer_diameter_mm"), -18),
        ["parts[5] ('input_shaft').segments[0].outer_diameter_mm", "greater than or equal to 0.01", "-18"],
    ),
    "zero stiffness": (
        _set(("bearings", 4, "radial_stiffness_N_per_um"), 0),
        ["bearings[4] ('input_B1').radial_stiffness_N_per_um", "greater than 0", "got 0"],
    ),
    "negative stiffness": (
        _set(("bearings", 6, "radial_stiffness_N_per_um"), -60.0),
        ["bearings[6] ('output_B1').radial_stiffness_N_per_um", "greater than 0", "-60"],
    ),
    "negative mount stiffness": (
        _set(("mounts", 3, "translational_stiffness_N_per_um"), [500, -1, 500]),
        ["mounts[3] ('reducer_pedestal').translational_stiffness_N_per_um[1]", "greater than or equal to 0"],
    ),
    "inner equal to outer diameter": (
        _set(("parts", 5, "segments", 0, "inner_diameter_mm"), 18),
        ["parts[5] ('input_shaft').segments[0]", "inner_diameter_mm (18.0) must be smaller than outer_diameter_mm (18.0)"],
    ),
    "inner larger than outer diameter": (
        _set(("parts", 4, "segments", 0, "inner_diameter_mm"), 120),
        ["parts[4] ('input_bearing_block').segments[0]", "inner_diameter_mm (120.0) must be smaller than outer_diameter_mm (90.0)"],
    ),
    "segment x decreasing": (
        _set(("parts", 1, "segments", 0, "x_mm"), [40, -110]),
        ["parts[1] ('motor_shaft').segments[0]", "x_mm must be increasing"],
    ),
    "unknown material": (
        _set(("parts", 5, "material"), "Steel"),
        ["parts[5] ('input_shaft').material", "unknown material 'Steel'", "known: 40Cr, HT200, Q460"],
    ),
    "unknown part in a bearing": (
        _set(("bearings", 4, "shaft"), "inptu_shaft"),
        ["bearings[4] ('input_B1').shaft", "unknown part 'inptu_shaft'", "input_shaft"],
    ),
    "unknown housing in a bearing": (
        _set(("bearings", 4, "housing"), "block"),
        ["bearings[4] ('input_B1').housing", "unknown part 'block'"],
    ),
    "unknown part in a coupling": (
        _set(("couplings", 2, "to", "part"), "torque_sensor"),
        ["couplings[2] ('C3').to", "unknown part 'torque_sensor'"],
    ),
    "x outside the part": (
        _set(("bearings", 6, "x_mm"), 600),
        ["bearings[6] ('output_B1').shaft", "x_mm = 600", "outside part 'output_shaft' (405.0 .. 565.0 mm)",
         "bearings[6] ('output_B1').housing", "outside part 'output_bearing_block'"],
    ),
    "coupling hub outside the part": (
        _set(("couplings", 0, "from", "x_mm"), 60),
        ["couplings[0] ('C1').from", "x_mm = 60", "outside part 'motor_shaft' (-110.0 .. 40.0 mm)"],
    ),
    "path longer than its shaft": (
        _set(("paths", "input", "length_mm"), 200),
        ["paths.input.length_mm", "runs past the end of part 'input_shaft' (220 .. 340 mm)"],
    ),
    "overlapping supports": (
        _set(("bearings", 5, "x_mm"), 255),
        ["bearings 'input_B2' and bearings 'input_B1'", "part 'input_shaft' at x = 255", "overlapping supports",
         "merge them into one with the summed stiffness"],
    ),
    "duplicated part name": (
        _set(("parts", 7, "name"), "input_shaft"),
        ["parts", "part names must be unique", "repeated: input_shaft"],
    ),
    "duplicated bearing name": (
        _set(("bearings", 1, "name"), "motor_front"),
        ["must be unique", "repeated: motor_front"],
    ),
    "part named ground": (
        _set(("parts", 0, "name"), "ground"),
        ["parts", "'ground' is reserved"],
    ),
    "string with a unit for a number": (
        _set(("parts", 5, "segments", 0, "outer_diameter_mm"), "120 mm"),
        ["parts[5] ('input_shaft').segments[0].outer_diameter_mm", "valid number", "'120 mm'"],
    ),
    "string for a stiffness": (
        _set(("bearings", 0, "radial_stiffness_N_per_um"), "stiff"),
        ["bearings[0] ('motor_front').radial_stiffness_N_per_um", "valid number", "'stiff'"],
    ),
    "NaN stiffness": (
        _set(("bearings", 0, "radial_stiffness_N_per_um"), math.nan),
        ["bearings[0] ('motor_front').radial_stiffness_N_per_um", "finite number", "nan"],
    ),
    "NaN position": (
        _set(("bearings", 2, "x_mm"), math.nan),
        ["bearings[2] ('input_sensor_a').x_mm", "finite number", "nan"],
    ),
    "infinite diameter": (
        _set(("parts", 5, "segments", 0, "outer_diameter_mm"), math.inf),
        ["parts[5] ('input_shaft').segments[0].outer_diameter_mm", "finite number", "inf"],
    ),
    "infinite gravity": (
        _set(("gravity", "acceleration_m_per_s2"), math.inf),
        ["gravity.acceleration_m_per_s2", "finite number"],
    ),
    "body without mass": (
        _delete(("parts", 11, "mass_kg")),
        ["parts[11] ('brake_housing')", "a body needs mass_kg"],
    ),
    "segments with a gap": (
        _set(("parts", 5, "segments", 1, "x_mm"), [250, 262]),
        ["parts[5] ('input_shaft')", "gap between segments [220.0, 248.0] and [250.0, 262.0] mm"],
    ),
    "too few path stations": (
        _set(("paths", "output", "stations"), 5),
        ["paths.output.stations", "greater than or equal to 25"],
    ),
    "unknown load-sharing kind": (
        _set(("torque_lateral_loads", 0, "kind"), "gear_mesh"),
        ["torque_lateral_loads[0] ('sun_gear_load_sharing').kind", "'gear_mesh'"],
    ),
    "load sharing missing its radius": (
        _delete(("torque_lateral_loads", 1, "radius_mm")),
        ["torque_lateral_loads[1] ('crankshaft_load_sharing')", "kind 'crank_load_sharing' needs radius_mm"],
    ),
    "schema version 2": (
        _set(("schema_version",), 2),
        ["schema_version", "got 2"],
    ),
}


@pytest.mark.parametrize("edit, expected", list(SCHEMA_CASES.values()), ids=list(SCHEMA_CASES))
def test_bad_rig_names_key_and_reason(edit, expected):
    data = reference_data()
    edit(data)
    message = problems_of(data)
    for text in expected:
        assert text in message, f"{text!r} not in:\n{message}"


def test_the_edits_above_are_the_only_problem():
    """Each message lists exactly the edited key (no cascade of unrelated complaints)."""
    for label in ("negative diameter", "unknown material", "overlapping supports", "duplicated bearing name",
                  "string with a unit for a number"):
        data = reference_data()
        SCHEMA_CASES[label][0](data)
        with pytest.raises(RigFileError) as caught:
            parse_rig(data, SOURCE)
        assert len(caught.value.problems) == 1, (label, caught.value.problems)


def test_a_problem_with_a_semicolon_stays_one_problem():
    """Cross-reference problems are reported one per line, even when their text holds '; '."""
    data = reference_data()
    data["bearings"][5]["x_mm"] = 255          # overlapping supports (message holds "; ")
    data["parts"][5]["material"] = "Steel"     # plus an unknown material
    with pytest.raises(RigFileError) as caught:
        parse_rig(data, SOURCE)
    problems = caught.value.problems
    assert len(problems) == 2, problems
    assert any("overlapping supports; merge them" in p for p in problems)
    assert any("unknown material 'Steel'" in p for p in problems)


def test_every_problem_is_reported_at_once():
    data = reference_data()
    del data["bearings"][0]["radial_stiffness_N_per_um"]
    data["parts"][5]["segments"][0]["outer_diameter_mm"] = -1
    data["mounts"][0]["translational_stiffness_N_per_um"] = [1, "x", 1]
    message = problems_of(data)
    assert "3 problem(s)" in message
    assert "bearings[0] ('motor_front').radial_stiffness_N_per_um" in message
    assert "parts[5] ('input_shaft').segments[0].outer_diameter_mm" in message
    assert "mounts[0] ('motor_bracket').translational_stiffness_N_per_um[1]" in message


def test_toml_text_edit_misspelled_key(tmp_path):
    text = reference_rig_text().replace("radial_stiffness_N_per_um = 50      # [S]",
                                        "radial_stifness_N_per_um = 50      # [S]", 1)
    path = tmp_path / "misspelled.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(RigFileError) as caught:
        load_rig(path)
    message = str(caught.value)
    assert str(path) in message
    assert "bearings[4] ('input_B1').radial_stifness_N_per_um: unknown key" in message
    assert "bearings[4] ('input_B1').radial_stiffness_N_per_um: required key is missing" in message


# ----------------------------------------------------------------------------------------------
# file-level errors (load_rig on a path)


def test_toml_syntax_error(tmp_path):
    path = tmp_path / "syntax.toml"
    path.write_text(reference_rig_text().replace("[gravity]", "[gravity", 1), encoding="utf-8")
    with pytest.raises(RigFileError) as caught:
        load_rig(path)
    message = str(caught.value)
    assert str(path) in message
    assert "TOML syntax error" in message
    line = reference_rig_text().splitlines().index("[gravity]") + 1
    assert f"line {line}" in message


def test_file_not_found(tmp_path):
    path = tmp_path / "nowhere.toml"
    with pytest.raises(RigFileError) as caught:
        load_rig(path)
    assert str(path) in str(caught.value)
    assert "file not found" in str(caught.value)


def test_non_utf8_file(tmp_path):
    path = tmp_path / "latin1.toml"
    text = reference_rig_text()
    path.write_bytes(text.encode("latin-1", errors="replace"))  # "Ø", "µ" and "≈" become single bytes / "?"
    with pytest.raises(RigFileError) as caught:
        load_rig(path)
    first_bad = text.encode("latin-1", errors="replace").index("Ø".encode("latin-1"))
    assert str(path) in str(caught.value)
    assert f"is not UTF-8 text (byte {first_bad})" in str(caught.value)


def test_directory_as_rig_file(tmp_path):
    with pytest.raises(RigFileError) as caught:
        load_rig(tmp_path)
    assert str(tmp_path) in str(caught.value)
    assert "is a directory" in str(caught.value)


def test_empty_file_lists_every_required_section(tmp_path):
    path = tmp_path / "empty.toml"
    path.write_text("", encoding="utf-8")
    with pytest.raises(RigFileError) as caught:
        load_rig(path)
    message = str(caught.value)
    for key in ("schema_version", "rig", "materials", "parts", "torques", "paths"):
        assert f"  - {key}: required key is missing" in message, key


# ----------------------------------------------------------------------------------------------
# a rig that validates but cannot be solved


def test_part_without_support_path_raises_model_error():
    rig = parse_rig(floating_brake(reference_data()), SOURCE)  # valid as a file...
    with pytest.raises(ModelError) as caught:                   # ...but brake_housing floats
        run_sweep(rig, (LoadCase(1.0, 100.0),))
    message = str(caught.value)
    assert "'brake_housing'" in message
    assert "no support path to ground" in message
    assert "translation x" in message and "translation y" in message and "translation z" in message
    # only the housing floats: the brake shaft still hangs on coupling C4
    assert "'brake_shaft'" not in message


def test_unsupported_reducer_names_the_reducer():
    data = reference_data()
    data["mounts"] = [m for m in data["mounts"] if m["part"] != "reducer"]
    data["joints"] = [j for j in data["joints"] if "reducer" not in (j["from"]["part"], j["to"]["part"])]
    data["torque_lateral_loads"] = []
    rig = parse_rig(data, SOURCE)
    with pytest.raises(ModelError) as caught:
        run_sweep(rig, (LoadCase(1.0, 100.0),))
    assert "part 'reducer' can move freely" in str(caught.value)
    for direction in ("translation x", "translation y", "translation z",
                      "rotation about x", "rotation about y", "rotation about z"):
        assert direction in str(caught.value)


# ----------------------------------------------------------------------------------------------
# the same through the command line: exit status 2, the file named, no traceback


def _text_file(text: str):
    def make(folder: Path) -> Path:
        path = folder / "bad.toml"
        path.write_text(text, encoding="utf-8")
        return path
    return make


def _dict_file(edit):
    def make(folder: Path) -> Path:
        data = reference_data()
        edit(data)
        return _text_file(dump_toml(data))(folder)
    return make


CLI_CASES = {
    "missing key": (_dict_file(SCHEMA_CASES["missing bearing stiffness"][0]),
                    ["bearings[0] ('motor_front').radial_stiffness_N_per_um", "required key is missing"]),
    "unknown material": (_dict_file(SCHEMA_CASES["unknown material"][0]),
                         ["parts[5] ('input_shaft').material", "unknown material 'Steel'"]),
    "negative diameter": (_dict_file(SCHEMA_CASES["negative diameter"][0]),
                          ["parts[5] ('input_shaft').segments[0].outer_diameter_mm", "greater than or equal to 0.01"]),
    "unsupported part": (_dict_file(floating_brake),
                         ["cannot solve the rig", "'brake_housing'", "no support path to ground"]),
    "TOML syntax error": (_text_file(reference_rig_text().replace('name = "C2"', 'name = C2', 1)),
                          ["TOML syntax error"]),
    "nonexistent file": (lambda folder: folder / "missing.toml", ["file not found"]),
    "directory": (lambda folder: folder, ["is a directory"]),
    "not UTF-8": (lambda folder: _bytes_file(folder, b"schema_version = 1\n# \xff\xfe\n"), ["is not UTF-8 text"]),
}


def _bytes_file(folder: Path, data: bytes) -> Path:
    path = folder / "bad.toml"
    path.write_bytes(data)
    return path


@pytest.mark.parametrize("make, expected", list(CLI_CASES.values()), ids=list(CLI_CASES))
@pytest.mark.subprocess
def test_cli_bad_rig_exits_2_without_traceback(tmp_path, make, expected):
    rig = make(tmp_path)
    out = tmp_path / "out"
    result = rvcoax("sweep", "--rig", str(rig), "--out", str(out), "--t1", "1", "--t2", "100", cwd=tmp_path)
    both = result.stdout + result.stderr
    assert result.returncode == 2, both
    assert "Traceback" not in both
    assert str(rig) in flat(result.stderr), result.stderr
    for text in expected:
        assert text in flat(result.stderr), f"{text!r} not in:\n{result.stderr}"
    assert not (out / "sweep.csv").exists()


@pytest.mark.subprocess
def test_cli_rig_show_reports_bad_rig(tmp_path):
    rig = _dict_file(SCHEMA_CASES["unknown part in a coupling"][0])(tmp_path)
    result = rvcoax("rig", "show", "--rig", str(rig), cwd=tmp_path)
    assert result.returncode == 2
    assert "Traceback" not in result.stdout + result.stderr
    assert str(rig) in flat(result.stderr)
    assert "couplings[2] ('C3').to: unknown part 'torque_sensor'" in flat(result.stderr)


@pytest.mark.parametrize("edit, expected", [
    (_set(("parts", 1, "segments", 0, "x_mm"), [40, -110]), "x_mm must be increasing [start, end], got [40.0, -110.0]"),
    (_set(("bearings", 0, "shaft"), "[/]"), "bearings[0] ('motor_front').shaft: unknown part '[/]'"),
    (_set(("parts", 5, "material"), "[bold]Steel[/bold]"), "unknown material '[bold]Steel[/bold]'"),
], ids=["brackets in the reason", "closing tag as a name", "markup as a name"])
@pytest.mark.subprocess
def test_cli_prints_messages_verbatim(tmp_path, edit, expected):
    """Square brackets in a message (or in a user's names) are text, not terminal markup."""
    rig = _dict_file(edit)(tmp_path)
    result = rvcoax("sweep", "--rig", str(rig), "--out", str(tmp_path / "out"), "--t1", "1", "--t2", "1", cwd=tmp_path)
    assert result.returncode == 2
    assert "Traceback" not in result.stdout + result.stderr
    assert expected in flat(result.stderr), result.stderr


@pytest.mark.parametrize("value", ["\"40\"", "true"])
def test_numbers_must_be_written_as_numbers(value):
    """A stiffness written as a string or a boolean is rejected, not silently converted."""
    text = reference_rig_text().replace("radial_stiffness_N_per_um = 50      # [S] 40-65 N/µm",
                                        f"radial_stiffness_N_per_um = {value}", 1)
    assert f"radial_stiffness_N_per_um = {value}" in text
    with pytest.raises(RigFileError) as error:
        parse_rig(tomllib.loads(text), "strict.toml")
    assert "radial_stiffness_N_per_um" in str(error.value)
    assert "valid number" in str(error.value)
