"""A generated corpus of bad input files: rig TOML, load-case CSV/TOML and measured-data CSV.

Every :class:`BadInput` writes one file (or names a path) and lists what the error message must
say besides the file's name: where (a key path such as ``bearings[4] ('input_B1').x_mm`` or a
``line N``) and why. The cases are generated systematically from the reference rig (every
required key of a sample of tables deleted, keys misspelled, wrong types, NaN/inf, zero and
negative values, units written into numbers, metres for millimetres, overlapping parts, unknown
materials, broken references, TOML syntax errors, truncated files) and from small valid CSVs
(missing, misspelled and mis-separated columns, non-numbers, duplicates, encodings, huge files).
``tests/test_bad_inputs.py`` runs each one through the real command line.
"""

from __future__ import annotations

import copy
import math
import os
import random
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from rigdata import dump_toml, reference_data

from rvcoax.geometry.rigfile import reference_rig_text
from rvcoax.loadcases.cases import paper_table

HUGE_BYTES = 200_000_000  # written sparsely: the readers must refuse it before reading


@dataclass(frozen=True)
class BadInput:
    """One bad input file.

    Attributes
    ----------
    name : str
        Unique test id.
    kind : str
        ``rig`` (a rig file), ``model`` (a valid rig file that cannot be solved: ``sweep`` only),
        ``cases`` (``sweep --cases``) or ``measured`` (``discrepancy --measured``).
    make : callable
        ``make(folder) -> Path``: writes the file into ``folder`` (or returns a path to refuse).
    expected : tuple of str
        Substrings of the message (whitespace collapsed): the location and the reason.
    options : tuple of str
        More command-line options (``--model solid``).
    """

    name: str
    kind: str
    make: Callable[[Path], Path]
    expected: tuple[str, ...]
    options: tuple[str, ...] = ()


# ------------------------------------------------------------------------------------------ writers


def text_file(text: str, filename: str) -> Callable[[Path], Path]:
    def make(folder: Path) -> Path:
        path = folder / filename
        path.write_text(text, encoding="utf-8")
        return path
    return make


def bytes_file(data: bytes, filename: str) -> Callable[[Path], Path]:
    def make(folder: Path) -> Path:
        path = folder / filename
        path.write_bytes(data)
        return path
    return make


def huge_file(filename: str) -> Callable[[Path], Path]:
    """A 200 MB file made in an instant (sparse: a header, then a hole)."""
    def make(folder: Path) -> Path:
        path = folder / filename
        with path.open("wb") as stream:
            stream.write(b"T1_input_Nm,T2_output_Nm\n")
            stream.truncate(HUGE_BYTES)
        return path
    return make


def folder_itself(folder: Path) -> Path:
    return folder


def missing_file(filename: str) -> Callable[[Path], Path]:
    return lambda folder: folder / filename


def device(_: Path) -> Path:
    return Path(os.devnull)


def file_level_cases(kind: str, suffix: str) -> list[BadInput]:
    """Problems of the file itself, the same for every kind of input."""
    return [
        BadInput(f"{kind}: 200 MB file", kind, huge_file(f"huge{suffix}"), ("200.0 MB is too large",)),
        BadInput(f"{kind}: a folder", kind, folder_itself, ("folder" if kind != "rig" else "directory",)),
        BadInput(f"{kind}: no such file", kind, missing_file(f"nowhere{suffix}"), ("file not found",)),
        BadInput(f"{kind}: a device", kind, device, ("is not a regular file",)),
    ]


# ------------------------------------------------------------------------------------------ rig files


def _label(data: dict, group: str, index: int) -> str:
    name = data[group][index].get("name") or data[group][index].get("label")
    return f"{group}[{index}]" + (f" ('{name}')" if name else "")


def _walk(data, path: tuple):
    for step in path:
        data = data[step]
    return data


def _key_path(data: dict, path: tuple) -> str:
    """The key path the rig loader prints for ``path`` (tables in lists are named)."""
    out = ""
    for depth, step in enumerate(path):
        if isinstance(step, int):
            parent = _walk(data, path[:depth])
            name = parent[step].get("name") if isinstance(parent[step], dict) else None
            out += f"[{step}]" + (f" ('{name}')" if name and depth == 1 else "")
        else:
            out += ("." if out else "") + step
    return out


def _rig_edit(name: str, edit: Callable[[dict], None], expected: tuple[str, ...], kind: str = "rig",
              options: tuple[str, ...] = ()) -> BadInput:
    def make(folder: Path) -> Path:
        data = reference_data()
        edit(data)
        return text_file(dump_toml(data), "rig.toml")(folder)
    return BadInput(name, kind, make, expected, options)


def _setter(path: tuple, value):
    def edit(data: dict) -> None:
        _walk(data, path[:-1])[path[-1]] = copy.deepcopy(value)
    return edit


def _deleter(path: tuple):
    def edit(data: dict) -> None:
        del _walk(data, path[:-1])[path[-1]]
    return edit


def _renamer(path: tuple, new: str):
    def edit(data: dict) -> None:
        table = _walk(data, path[:-1])
        table[new] = table.pop(path[-1])
    return edit


REQUIRED_KEYS = {
    (): ("schema_version", "rig", "materials", "parts", "torques", "paths"),
    ("rig",): ("name",),
    ("materials", "Q460"): ("youngs_modulus_MPa", "poisson_ratio", "density_kg_per_m3"),
    ("parts", 1): ("name", "role", "material", "segments"),
    ("parts", 5): ("role", "material", "segments"),
    ("parts", 11): ("role", "segments", "mass_kg"),
    ("parts", 5, "segments", 0): ("x_mm", "outer_diameter_mm"),
    ("bearings", 0): ("name", "shaft", "housing", "x_mm", "radial_stiffness_N_per_um"),
    ("bearings", 4): ("shaft", "housing", "x_mm", "radial_stiffness_N_per_um"),
    ("bearings", 11): ("housing", "radial_stiffness_N_per_um"),
    ("mounts", 0): ("part", "x_mm", "translational_stiffness_N_per_um", "rotational_stiffness_Nm_per_rad"),
    ("mounts", 3): ("part", "translational_stiffness_N_per_um"),
    ("couplings", 1): ("from", "to", "centre_x_mm", "radial_stiffness_N_per_mm", "angular_stiffness_Nm_per_rad",
                       "torsional_stiffness_Nm_per_rad", "axial_stiffness_N_per_mm"),
    ("couplings", 2): ("radial_stiffness_N_per_mm", "axial_stiffness_N_per_mm"),
    ("joints", 0): ("from", "to", "translational_stiffness_N_per_um", "rotational_stiffness_Nm_per_rad"),
    ("torques", "T1"): ("part", "x_mm"),
    ("torques", "T2"): ("part",),
    ("paths", "input"): ("part", "x_start_mm", "length_mm"),
    ("paths", "output"): ("length_mm",),
    ("torque_lateral_loads", 1): ("radius_mm",),
}


def missing_key_cases() -> list[BadInput]:
    data = reference_data()
    out = []
    for table, keys in REQUIRED_KEYS.items():
        for key in keys:
            path = (*table, key)
            where = _key_path(data, path)
            if table == ("parts", 11) and key == "mass_kg":
                expected = (_key_path(data, table), "a body needs mass_kg")
            elif table == ("torque_lateral_loads", 1):
                expected = (_key_path(data, table), "needs radius_mm")
            elif key == "name" and isinstance(table[-1], int):  # the table loses its label
                expected = (f"{table[0]}[{table[1]}].name", "required key is missing")
            else:
                expected = (where, "required key is missing")
            out.append(_rig_edit(f"rig: missing {where}", _deleter(path), expected))
    return out


MISSPELLINGS = (
    (("bearings", 4, "radial_stiffness_N_per_um"), "radial_stifness_N_per_um"),
    (("couplings", 2, "angular_stiffness_Nm_per_rad"), "angular_stiffnes_Nm_per_rad"),
    (("parts", 5, "segments", 0, "outer_diameter_mm"), "outer_diamter_mm"),
    (("mounts", 3, "translational_stiffness_N_per_um"), "translational_stiffness_N_per_mm"),
    (("gravity",), "gravty"),
    (("gravity", "acceleration_m_per_s2"), "acceleration_mm_per_s2"),
    (("paths", "input", "length_mm"), "length_m"),
    (("materials", "Q460", "youngs_modulus_MPa"), "youngs_modulus_GPa"),
    (("parts", 11, "mass_kg"), "mass_g"),
    (("bearings", 0, "x_mm"), "x_m"),
    (("couplings", 0, "hub_length_mm"), "hub_lenght_mm"),
    (("solid", "mesh_size_mm"), "mesh_size"),
    (("torques", "T1", "x_mm"), "X_mm"),
    (("paths", "measured_from"), "measured_form"),
)


def misspelled_key_cases() -> list[BadInput]:
    data = reference_data()
    out = []
    for path, wrong in MISSPELLINGS:
        where = _key_path(data, (*path[:-1], wrong))
        out.append(_rig_edit(f"rig: misspelled {where}", _renamer(path, wrong), (where, "unknown key")))
    return out


NUMBER_KEYS = (
    ("bearings", 4, "radial_stiffness_N_per_um"),
    ("parts", 5, "segments", 0, "outer_diameter_mm"),
    ("materials", "Q460", "density_kg_per_m3"),
    ("couplings", 1, "centre_x_mm"),
    ("paths", "output", "length_mm"),
)
WRONG_TYPES = (("a word", "fast"), ("a boolean", True), ("a list", [1, 2]), ("a table", {"value": 1}))


def wrong_type_cases() -> list[BadInput]:
    data = reference_data()
    out = []
    for path in NUMBER_KEYS:
        where = _key_path(data, path)
        for label, value in WRONG_TYPES:
            out.append(_rig_edit(f"rig: {label} for {where}", _setter(path, value), (where, "valid number")))
    others = (
        (("parts", 5, "material"), 40, "valid string"),
        (("bearings", 0, "shaft"), 3, "valid string"),
        (("paths", "input", "stations"), 41.5, "valid integer"),
        (("rig", "name"), ["a", "b"], "valid string"),
        (("materials", "Q460"), 5, "valid dictionary"),
        (("bearings",), {"a": 1}, "valid list"),
        (("mounts", 0, "translational_stiffness_N_per_um"), [500, 500], "required key is missing"),
        (("gravity", "enabled"), "yes", "valid boolean"),
        (("gravity", "enabled"), 1, "valid boolean"),
        (("force_table", "apply"), "true", "valid boolean"),
    )
    for path, value, reason in others:
        where = _key_path(data, path)
        out.append(_rig_edit(f"rig: {value!r} for {where}", _setter(path, value), (where, reason)))
    return out


NON_FINITE_KEYS = (
    ("bearings", 2, "x_mm"),
    ("parts", 5, "segments", 0, "outer_diameter_mm"),
    ("couplings", 1, "radial_stiffness_N_per_mm"),
    ("mounts", 0, "translational_stiffness_N_per_um", 1),
    ("gravity", "acceleration_m_per_s2"),
    ("materials", "HT200", "youngs_modulus_MPa"),
    ("paths", "input", "x_start_mm"),
)


def non_finite_cases() -> list[BadInput]:
    data = reference_data()
    out = []
    for path in NON_FINITE_KEYS:
        where = _key_path(data, path)
        for value in (math.nan, math.inf, -math.inf):
            out.append(_rig_edit(f"rig: {value} for {where}", _setter(path, value), (where, "finite number")))
    return out


NON_POSITIVE = (
    (("parts", 5, "segments", 0, "outer_diameter_mm"), (0, -18), "greater than or equal to 0.01"),
    (("parts", 11, "mass_kg"), (0, -1.5), "greater than 0"),
    (("bearings", 6, "radial_stiffness_N_per_um"), (0, -60), "greater than 0"),
    (("couplings", 2, "radial_stiffness_N_per_mm"), (0, -1), "greater than 0"),
    (("couplings", 2, "torsional_stiffness_Nm_per_rad"), (0,), "greater than 0"),
    (("materials", "Q460", "youngs_modulus_MPa"), (0, -2.06e5), "greater than 0"),
    (("materials", "Q460", "density_kg_per_m3"), (0,), "greater than 0"),
    (("paths", "output", "length_mm"), (0, -160), "greater than 0"),
    (("bearings", 0, "width_mm"), (-15,), "greater than 0"),
    (("mounts", 3, "translational_stiffness_N_per_um", 1), (-1,), "greater than or equal to 0"),
    (("parts", 5, "segments", 0, "inner_diameter_mm"), (-8,), "greater than or equal to 0"),
    (("solid", "mesh_size_mm"), (0,), "greater than 0"),
    (("gravity", "acceleration_m_per_s2"), (0,), "greater than 0"),
)


def non_positive_cases() -> list[BadInput]:
    data = reference_data()
    out = []
    for path, values, reason in NON_POSITIVE:
        where = _key_path(data, path)
        for value in values:
            out.append(_rig_edit(f"rig: {value} for {where}", _setter(path, value), (where, reason)))
    return out


UNITS_IN_NUMBERS = (
    (("parts", 5, "segments", 0, "outer_diameter_mm"), "120 mm"),
    (("bearings", 4, "radial_stiffness_N_per_um"), "50 N/um"),
    (("couplings", 1, "angular_misalignment_mrad"), "0.5 mrad"),
    (("materials", "Q460", "youngs_modulus_MPa"), "206 GPa"),
    (("gravity", "acceleration_m_per_s2"), "9.81 m/s2"),
    (("paths", "input", "length_mm"), "120mm"),
    (("bearings", 5, "x_mm"), "315 mm"),
    (("mounts", 2, "translational_stiffness_N_per_um", 0), "500 N/µm"),
)


def unit_in_number_cases() -> list[BadInput]:
    data = reference_data()
    return [_rig_edit(f"rig: '{value}' for {_key_path(data, path)}", _setter(path, value),
                      (_key_path(data, path), "valid number", f"'{value}'")) for path, value in UNITS_IN_NUMBERS]


def _scale_lengths(data, factor: float, keys=lambda key: key.endswith("_mm")) -> None:
    """Multiply every length (keys ending in _mm) of a parsed rig by ``factor``, in place."""
    if isinstance(data, dict):
        for key, value in data.items():
            if keys(key) and isinstance(value, (int, float)) and not isinstance(value, bool):
                data[key] = value * factor
            elif keys(key) and isinstance(value, list):
                data[key] = [v * factor for v in value]
            else:
                _scale_lengths(value, factor, keys)
    elif isinstance(data, list):
        for item in data:
            _scale_lengths(item, factor, keys)


def metre_cases() -> list[BadInput]:
    return [
        _rig_edit("rig: every length in metres", lambda d: _scale_lengths(d, 1e-3),
                  ("parts:", "look like metres")),
        _rig_edit("rig: diameters in metres", lambda d: _scale_lengths(d, 1e-3, lambda k: k.endswith("diameter_mm")),
                  ("parts:", "look like metres")),
    ]


def unknown_material_cases() -> list[BadInput]:
    data = reference_data()
    out = []
    for index, name in ((5, "Steel"), (7, "q460"), (1, "40Cr "), (11, ""), (3, "HT-200")):
        where = _key_path(data, ("parts", index, "material"))
        out.append(_rig_edit(f"rig: material {name!r} in {where}", _setter(("parts", index, "material"), name),
                             (where, f"unknown material '{name}'", "known: 40Cr, HT200, Q460")))
    return out


def _append_copy(group: str, index: int, **changes):
    def edit(data: dict) -> None:
        item = copy.deepcopy(data[group][index])
        item.update(changes)
        data[group].append(item)
    return edit


def overlapping_part_cases() -> list[BadInput]:
    data = reference_data()
    label = lambda i: _label(data, "parts", i)  # noqa: E731
    return [
        _rig_edit("rig: output sensor shaft runs into the brake shaft",
                  _setter(("parts", 10, "segments", 0, "x_mm"), [575, 820]),
                  (f"{label(10)} and {label(12)}", "overlapping parts", "x = 800 … 820 mm")),
        _rig_edit("rig: motor shaft runs into the input sensor shaft",
                  _setter(("parts", 1, "segments", 0, "x_mm"), [-110, 60]),
                  (f"{label(1)} and {label(3)}", "overlapping parts", "x = 50 … 60 mm")),
        _rig_edit("rig: a second input shaft in the same place", _append_copy("parts", 5, name="input_shaft_2"),
                  (f"{label(5)} and parts[13] ('input_shaft_2')", "overlapping parts")),
    ]


def literal_cases() -> list[BadInput]:
    data = reference_data()
    edits = (
        (("parts", 0, "role"), "housing", "'shaft' or 'body'"),
        (("paths", "measured_from"), "rest", "'aligned_at_rest' or 'unloaded'"),
        (("torque_lateral_loads", 0, "kind"), "gear", "'gear'"),
        (("torques", "T1", "sign"), 2, "Input should be"),
        (("torque_lateral_loads", 0, "torque"), "T3", "'T1' or 'T2'"),
        (("couplings", 1, "from", "tie"), "glued", "'distributing' or 'rigid'"),
        (("schema_version",), 2, "got 2"),
        (("parts", 5, "name"), "input shaft", "should match pattern"),
    )
    out = []
    for path, value, reason in edits:
        where = _key_path(data, path)
        if path == ("parts", 5, "name"):
            where = "parts[5] ('input shaft').name"
        out.append(_rig_edit(f"rig: {value!r} for {where}", _setter(path, value), (where, reason)))
    return out


def reference_cases() -> list[BadInput]:
    data = reference_data()
    b = lambda i: _label(data, "bearings", i)  # noqa: E731
    edits = (
        ("bearing on an unknown shaft", _setter(("bearings", 4, "shaft"), "inptu_shaft"),
         (f"{b(4)}.shaft", "unknown part 'inptu_shaft'")),
        ("bearing in an unknown housing", _setter(("bearings", 4, "housing"), "block"),
         (f"{b(4)}.housing", "unknown part 'block'")),
        ("coupling to an unknown part", _setter(("couplings", 2, "to", "part"), "torque_sensor"),
         ("couplings[2] ('C3').to", "unknown part 'torque_sensor'")),
        ("mount outside its part", _setter(("mounts", 6, "x_mm"), 2000),
         ("mounts[6] ('brake_feet')", "x_mm = 2000", "outside part 'brake_housing'")),
        ("path on an unknown part", _setter(("paths", "input", "part"), "shaft"),
         ("paths.input.x_start_mm", "unknown part 'shaft'")),
        ("path longer than its shaft", _setter(("paths", "output", "length_mm"), 400),
         ("paths.output.length_mm", "runs past the end of part 'output_shaft'")),
        ("coupling from a part to itself", _setter(("couplings", 0, "to", "part"), "motor_shaft"),
         ("couplings[0] ('C1')", "same part 'motor_shaft'")),
        ("two parts with one name", _setter(("parts", 7, "name"), "input_shaft"),
         ("parts", "repeated: input_shaft")),
        ("two bearings with one name", _setter(("bearings", 1, "name"), "motor_front"),
         ("must be unique", "repeated: motor_front")),
        ("a part named ground", _setter(("parts", 0, "name"), "ground"), ("parts", "'ground' is reserved")),
        ("unknown hybrid part", _setter(("solid", "hybrid_parts"), ["input_shaft", "outputshaft"]),
         ("solid.hybrid_parts", "unknown part 'outputshaft'")),
        ("two bearings at one place", _setter(("bearings", 5, "x_mm"), 255),
         ("bearings 'input_B2' and bearings 'input_B1'", "overlapping supports")),
        ("torque on an unknown part", _setter(("torques", "T2", "part"), "output"),
         ("torques.T2", "unknown part 'output'")),
        ("segments with a gap", _setter(("parts", 5, "segments", 1, "x_mm"), [250, 262]),
         ("parts[5] ('input_shaft')", "gap between segments")),
        ("segment x decreasing", _setter(("parts", 1, "segments", 0, "x_mm"), [40, -110]),
         ("parts[1] ('motor_shaft').segments[0]", "x_mm must be increasing")),
        ("bore as large as the shaft", _setter(("parts", 5, "segments", 0, "inner_diameter_mm"), 18),
         ("parts[5] ('input_shaft').segments[0]", "must be smaller than outer_diameter_mm")),
    )
    return [_rig_edit(f"rig: {label}", edit, expected) for label, edit, expected in edits]


def toml_text_cases() -> list[BadInput]:
    """Syntax errors, duplicated keys and tables, truncated files: the loader names the line."""
    text = reference_rig_text()
    lines = text.splitlines(keepends=True)
    gravity = lines.index("[gravity]\n")
    edits = {
        "duplicated key": text.replace("schema_version = 1\n", "schema_version = 1\nschema_version = 1\n", 1),
        "duplicated table": text.replace("[gravity]\n", "[gravity]\nenabled = true\n[gravity]\n", 1),
        "unclosed bracket": text.replace("[gravity]\n", "[gravity\n", 1),
        "unclosed string": text.replace('name = "C2"', 'name = "C2', 1),
        "bare word as a value": text.replace('name = "C2"', "name = C2", 1),
        "key without value": "".join(lines[:gravity + 1]) + "enabled =\n" + "".join(lines[gravity + 2:]),
        "unclosed array": text.replace("x_mm = [220, 248]", "x_mm = [220, 248", 1),
        "invalid escape": text.replace('name = "C2"', 'name = "C\\q2"', 1),
    }
    out = [BadInput(f"rig: TOML {label}", "rig", text_file(edited, "rig.toml"), ("TOML syntax error", "line"))
           for label, edited in edits.items()]
    for fraction in (0.05, 0.25, 0.45, 0.65, 0.85):
        cut = text[: int(len(text) * fraction)]
        cut = cut[: cut.rfind("=") + 2] if "=" in cut[-40:] else cut  # end in the middle of a value
        expected = ("TOML syntax error", "line") if _is_bad_toml(cut) else ("problem(s)", "required key is missing")
        out.append(BadInput(f"rig: truncated at {fraction:.0%}", "rig", text_file(cut, "rig.toml"), expected))
    return out


def _is_bad_toml(text: str) -> bool:
    import tomllib

    try:
        tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        return True
    return False


def rig_file_cases() -> list[BadInput]:
    text = reference_rig_text()
    generator = random.Random(6)
    noise = bytes(generator.randrange(256) for _ in range(4000))
    latin1 = text.encode("latin-1", errors="replace")
    first_bad = latin1.index("Ø".encode("latin-1"))
    bad_line = latin1[:first_bad].count(b"\n") + 1
    return [
        BadInput("rig: empty file", "rig", text_file("", "rig.toml"), ("schema_version: required key is missing",)),
        BadInput("rig: only blanks", "rig", text_file("\n  \n\t\n", "rig.toml"), ("parts: required key is missing",)),
        BadInput("rig: only comments", "rig", text_file("# a rig\n# nothing here\n", "rig.toml"),
                 ("paths: required key is missing",)),
        BadInput("rig: latin-1 bytes", "rig", bytes_file(latin1, "rig.toml"),
                 (f"line {bad_line}: is not UTF-8 text (byte {first_bad})",)),
        BadInput("rig: UTF-16", "rig", bytes_file(text.encode("utf-16"), "rig.toml"), ("is not UTF-8 text",)),
        BadInput("rig: random bytes", "rig", bytes_file(noise, "rig.toml"), ("is not UTF-8 text",)),
        BadInput("rig: a PNG", "rig", bytes_file(b"\x89PNG\r\n\x1a\n" + b"\0" * 64, "rig.png"), ("is not UTF-8 text",)),
        BadInput("rig: JSON instead of TOML", "rig", text_file('{"schema_version": 1}\n', "rig.json"),
                 ("TOML syntax error", "line 1")),
        BadInput("rig: a CSV", "rig", text_file("T1_input_Nm,T2_output_Nm\n1,100\n", "rig.csv"),
                 ("TOML syntax error", "line 1")),
        *file_level_cases("rig", ".toml"),
    ]


def _floating_brake(data: dict) -> None:
    data["bearings"] = [b for b in data["bearings"] if b["name"] not in ("brake_a", "brake_b")]
    data["mounts"] = [m for m in data["mounts"] if m["name"] != "brake_feet"]


def _zero_feet_without_bearings(data: dict) -> None:
    data["bearings"] = [b for b in data["bearings"] if b["name"] not in ("brake_a", "brake_b")]
    feet = next(m for m in data["mounts"] if m["name"] == "brake_feet")
    feet["translational_stiffness_N_per_um"] = [0, 0, 0]
    feet["rotational_stiffness_Nm_per_rad"] = [0, 0, 0]


def _unsupported_reducer(data: dict) -> None:
    data["mounts"] = [m for m in data["mounts"] if m["part"] != "reducer"]
    data["joints"] = [j for j in data["joints"] if "reducer" not in (j["from"]["part"], j["to"]["part"])]
    data["torque_lateral_loads"] = []


def model_cases() -> list[BadInput]:
    """Valid rig files that cannot be solved: named before any solve (``sweep`` only)."""
    return [
        _rig_edit("model: brake housing floats", _floating_brake,
                  ("cannot solve the rig", "'brake_housing'", "no support path to ground", "translation y"), "model"),
        _rig_edit("model: zero-stiffness brake feet", _zero_feet_without_bearings,
                  ("'brake_housing'", "no support path to ground", "Springs with zero stiffness",
                   "mount 'brake_feet' (translation x"), "model"),
        _rig_edit("model: reducer without supports", _unsupported_reducer,
                  ("part 'reducer' can move freely", "rotation about x"), "model"),
        _rig_edit("model: a joint 1e12 times too stiff", _setter(("joints", 1, "translational_stiffness_N_per_um"),
                                                                 [5e14, 5e14, 5e14]),
                  ("numerically singular although every part is held",
                   "stiffest spring: joint 'reducer_output_flange' 5e+14 N/µm"), "model"),
        _rig_edit("model: Young's modulus in Pa", _setter(("materials", "40Cr", "youngs_modulus_MPa"), 2.11e11),
                  ("numerically singular although every part is held", "youngs_modulus_MPa"), "model"),
        _rig_edit("model: bearing clearance in the solid model", _setter(("bearings", 4, "radial_clearance_um"), 5.0),
                  ("bearing(s) input_B1 have a radial clearance", "only the beam model solves it"), "model",
                  ("--model", "solid")),
    ]


def rig_cases() -> list[BadInput]:
    return (missing_key_cases() + misspelled_key_cases() + wrong_type_cases() + non_finite_cases()
            + non_positive_cases() + unit_in_number_cases() + metre_cases() + unknown_material_cases()
            + overlapping_part_cases() + literal_cases() + reference_cases() + toml_text_cases() + rig_file_cases())


# ------------------------------------------------------------------------------------------ load cases

CSV_HEADER = "T1_input_Nm,T2_output_Nm\n"
CSV_ROWS = "0.07,10\n0.5,70\n1.43,200\n"


def load_case_cases() -> list[BadInput]:
    csv_cases = {
        "missing T2 column": ("T1_input_Nm,T2\n1,100\n", ("line 1", "missing column(s) T2_output_Nm", "found: T1_input_Nm, T2")),
        "missing T1 column": ("T2_output_Nm\n100\n", ("line 1", "missing column(s) T1_input_Nm")),
        "misspelled column": ("T1_input_Nmm,T2_output_Nm\n1,100\n", ("line 1", "missing column(s) T1_input_Nm",
                                                                      "found: T1_input_Nmm")),
        "kN·m column": ("T1_input_Nm,T2_output_kNm\n1,0.1\n", ("line 1", "missing column(s) T2_output_Nm")),
        "lower-case columns": ("t1_input_nm,t2_output_nm\n1,100\n", ("line 1", "missing column(s)")),
        "semicolons": ("T1_input_Nm;T2_output_Nm\n0,5;100\n", ("line 1", "separated by semicolons")),
        "tabs": ("T1_input_Nm\tT2_output_Nm\n0.5\t100\n", ("line 1", "separated by tabs")),
        "empty": ("", ("missing column(s) T1_input_Nm, T2_output_Nm", "found: none")),
        "header only": (CSV_HEADER, ("no load cases",)),
        "unit in a number": (CSV_HEADER + "1.2 Nm,100\n", ("line 2, T1_input_Nm", "'1.2 Nm' is not a number")),
        "a word": (CSV_HEADER + "0.5,70\nfull,200\n", ("line 3, T1_input_Nm", "'full' is not a number")),
        "empty value": (CSV_HEADER + "1,\n", ("line 2, T2_output_Nm", "'' is not a number")),
        "too few values": (CSV_HEADER + CSV_ROWS + "1\n", ("line 5, T2_output_Nm", "value is missing")),
        "too many values": (CSV_HEADER + "1,2,3\n", ("line 2", "3 values but 2 columns")),
        "decimal comma": (CSV_HEADER + '"0,5",100\n', ("line 2, T1_input_Nm", "'0,5' is not a plain number", "write '.' as the decimal point")),
        "NaN": (CSV_HEADER + "1,100\nnan,70\n", ("line 3, T1_input_Nm", "'nan' is not a finite number")),
        "inf": (CSV_HEADER + "1,inf\n", ("line 2, T2_output_Nm", "'inf' is not a finite number")),
        "-inf": (CSV_HEADER + "-inf,1\n", ("line 2, T1_input_Nm", "'-inf' is not a finite number")),
        "N·mm for N·m": (CSV_HEADER + "1,2e7\n", ("line 2 (case 1)", "beyond any plausible rig torque")),
        "duplicated case": (CSV_HEADER + CSV_ROWS + "0.5,70\n", ("line 5 (case 4)", "duplicated load case",
                                                                 "the same as line 3")),
        "duplicated case, other spelling": (CSV_HEADER + "1,100\n1.0,1e2\n", ("line 3 (case 2)", "duplicated load case")),
        "duplicated column": ("T1_input_Nm,T2_output_Nm,T1_input_Nm\n1,2,3\n", ("line 1", "appear more than once")),
    }
    out = [BadInput(f"cases: CSV {label}", "cases", text_file(text, "cases.csv"), expected)
           for label, (text, expected) in csv_cases.items()]
    out += [
        BadInput("cases: CSV latin-1", "cases", bytes_file(b"T1_input_Nm,T2_output_Nm\n1,100 \xb5\n", "cases.csv"),
                 ("line 2: is not UTF-8 text",)),
        BadInput("cases: CSV UTF-16", "cases", bytes_file((CSV_HEADER + CSV_ROWS).encode("utf-16"), "cases.csv"),
                 ("line 1: is not UTF-8 text",)),
    ]
    table = "[[cases]]\nT1_input_Nm = {t1}\nT2_output_Nm = {t2}\n"
    toml_cases = {
        "syntax error": ("[[cases]\nT1_input_Nm = 1\n", ("TOML syntax error", "line 1")),
        "misspelled table": ("[[case]]\nT1_input_Nm = 1\nT2_output_Nm = 100\n", ("expected [[cases]]",)),
        "cases is a number": ("cases = 5\n", ("expected [[cases]]",)),
        "cases of numbers": ("cases = [1, 2]\n", ("cases[1]", "is not a table")),
        "missing T2": ("[[cases]]\nT1_input_Nm = 1\n", ("cases[1]", "missing key T2_output_Nm")),
        "misspelled key": ("[[cases]]\nT1_input_Nmm = 1\nT2_output_Nm = 100\n", ("cases[1]", "missing key T1_input_Nm")),
        "unit in a string": (table.format(t1='"1 Nm"', t2=100), ("cases[1].T1_input_Nm", "'1 Nm' is not a number")),
        "a boolean": (table.format(t1=1, t2="true"), ("cases[1].T2_output_Nm", "True is not a number")),
        "nan": (table.format(t1="nan", t2=100), ("case 1", "T1_input_Nm = nan is not a finite number")),
        "duplicated": (table.format(t1=1, t2=100) + table.format(t1=1.0, t2=100.0),
                       ("case 2", "duplicated load case")),
        "empty": ("", ("expected [[cases]]",)),
        "inf": (table.format(t1=1, t2="-inf"), ("case 1", "T2_output_Nm = -inf is not a finite number")),
    }
    out += [BadInput(f"cases: TOML {label}", "cases", text_file(text, "cases.toml"), expected)
            for label, (text, expected) in toml_cases.items()]
    return out + file_level_cases("cases", ".csv")


# ------------------------------------------------------------------------------------------ measured data


def _paper_table_csv() -> list[list[str]]:
    rows = [["T1_input_Nm", "T2_output_Nm", "Y_input_mm", "Y_output_mm"]]
    rows += [[f"{r.case.input_torque_Nm:g}", f"{r.case.output_torque_Nm:g}", f"{r.y_input_mm:g}",
              f"{r.y_output_mm:g}"] for r in paper_table()]
    return rows


def _csv(rows: list[list[str]], separator: str = ",") -> str:
    return "".join(separator.join(row) + "\n" for row in rows)


def _edited_table(edit: Callable[[list[list[str]]], None]) -> str:
    rows = _paper_table_csv()
    edit(rows)
    return _csv(rows)


def _cell(row: int, column: int, value: str):
    def edit(rows):
        rows[row][column] = value
    return edit


def _paths_csv(x_scale: float = 1.0, uy_scale: float = 1.0, extra: str = "") -> str:
    lines = ["T1_input_Nm,T2_output_Nm,shaft,x_mm,uy_mm"]
    for t1, t2 in ((0.5, 70), (1.43, 200)):
        for shaft, length in (("input", 120), ("output", 160)):
            for k in range(5):
                x = length * k / 4
                lines.append(f"{t1:g},{t2:g},{shaft},{x * x_scale:g},{(1e-4 * (k + 1) * t2 / 200) * uy_scale:g}")
    return "\n".join(lines) + "\n" + extra


def measured_cases() -> list[BadInput]:
    def drop_column(name):
        def edit(rows):
            index = rows[0].index(name)
            for row in rows:
                del row[index]
        return edit

    def add_column(name, value):
        def edit(rows):
            rows[0].append(name)
            for row in rows[1:]:
                row.append(value)
        return edit

    def scale_column(index, factor):
        def edit(rows):
            for row in rows[1:]:
                row[index] = f"{float(row[index]) * factor:g}"
        return edit

    table = {
        "missing Y_output_mm": (drop_column("Y_output_mm"), ("line 1", "fit neither schema", "missing Y_output_mm")),
        "missing torque column": (drop_column("T2_output_Nm"), ("line 1", "fit neither schema",
                                                                "missing T2_output_Nm")),
        "misspelled column": (lambda rows: rows[0].__setitem__(2, "Y_input_m"), ("line 1", "missing Y_input_mm",
                                                                                 "found: T1_input_Nm, T2_output_Nm, Y_input_m")),
        "unknown column": (add_column("comment", "ok"), ("line 1", "unknown column(s) comment")),
        "unit in a number": (_cell(3, 2, "0.0042 mm"), ("line 4, column Y_input_mm", "'0.0042 mm' is not a number")),
        "NaN": (_cell(5, 3, "nan"), ("line 6, column Y_output_mm", "not a finite number")),
        "infinite torque": (_cell(2, 1, "inf"), ("line 3, column T2_output_Nm", "not a finite number")),
        "negative Y": (_cell(7, 2, "-0.0001"), ("line 8, column Y_input_mm", "a table holds magnitudes")),
        "Y in nm": (scale_column(3, 1e6), ("column Y_output_mm", "looks like µm or nm")),
        "duplicated case": (lambda rows: rows.append(list(rows[4])), ("line 22", "duplicated load case")),
        "more values than columns": (lambda rows: rows[3].append("7"), ("line 4", "5 values but 4 columns in the header")),
        "missing value": (_cell(9, 3, ""), ("line 10, column Y_output_mm", "value is missing")),
        "missing value at the end": (lambda rows: rows[6].pop(), ("line 7, column Y_output_mm", "value is missing")),
        "duplicated column": (add_column("Y_input_mm", "0.1"), ("line 1", "Y_input_mm appear more than once")),
        "sigma zero": (add_column("sigma_mm", "0"), ("line 2, column sigma_mm", "must be > 0")),
        "sigma negative": (add_column("sigma_mm", "-1e-6"), ("line 2, column sigma_mm", "must be > 0")),
        "sigma a word": (add_column("sigma_mm", "small"), ("line 2, column sigma_mm", "'small' is not a number")),
    }
    out = [BadInput(f"measured: table {label}", "measured", text_file(_edited_table(edit), "measured.csv"), expected)
           for label, (edit, expected) in table.items()]
    header_only = _csv(_paper_table_csv()[:1])
    out += [
        BadInput("measured: empty", "measured", text_file("", "measured.csv"), ("the file is empty",)),
        BadInput("measured: header only", "measured", text_file(header_only, "measured.csv"), ("no data rows",)),
        BadInput("measured: semicolons", "measured", text_file(_csv(_paper_table_csv(), ";"), "measured.csv"),
                 ("line 1", "separated by semicolons")),
        BadInput("measured: latin-1", "measured",
                 bytes_file(_csv(_paper_table_csv()).encode() + b"1,2,3 \xb5m,4\n", "measured.csv"),
                 ("line 22: is not UTF-8 text",)),
        BadInput("measured: UTF-16", "measured", bytes_file(_csv(_paper_table_csv()).encode("utf-16"), "m.csv"),
                 ("line 1: is not UTF-8 text",)),
    ]
    paths = {
        "unknown shaft": (_paths_csv().replace(",input,", ",middle,", 1), ("line 2, column shaft",
                                                                           "'middle' is not input or output")),
        "x in metres": (_paths_csv(x_scale=1e-3), ("column x_mm", "looks like metres")),
        "uy in nm": (_paths_csv(uy_scale=1e6), ("column uy_mm", "looks like µm or nm")),
        "duplicated station": (_paths_csv(extra="0.5,70,input,60,0.0001\n"), ("line 22", "a second value",
                                                                              "x = 60 mm")),
        "uy NaN": (_paths_csv().replace(",0.0001\n", ",nan\n", 1), ("column uy_mm", "not a finite number")),
        "x with a unit": (_paths_csv().replace(",input,30,", ",input,30 mm,", 1), ("line 3, column x_mm",
                                                                                    "'30 mm' is not a number")),
        "missing uy column": (_paths_csv().replace(",uy_mm", ",u_mm", 1), ("line 1", "fit neither schema",
                                                                            "missing uy_mm")),
        "missing T2": (_paths_csv().replace("1.43,200,output,40,", "1.43,,output,40,", 1),
                       ("column T2_output_Nm", "value is missing")),
    }
    out += [BadInput(f"measured: paths {label}", "measured", text_file(text, "measured.csv"), expected)
            for label, (text, expected) in paths.items()]
    return out + file_level_cases("measured", ".csv")


def all_cases() -> list[BadInput]:
    return rig_cases() + model_cases() + load_case_cases() + measured_cases()
