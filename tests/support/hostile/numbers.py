"""Number syntax: only plain ASCII decimal numbers are numbers, in every CSV cell and every option.

Digit separators (``1_00``), Arabic-Indic (``٧٠``) and full-width (``７０``) digits, hexadecimal, ``nan`` and
an empty item in a list are refused, naming the file and line and column (or the option and item).
"""

from __future__ import annotations

from hostile import Hostile
from hostile._files import DESIGN, FORCES, LEVELS, TERMS, edited, reference_rig, run, write

K = "numbers"
CASES_HEADER = "T1_input_Nm,T2_output_Nm\n"


def _case(label: str, argv, *expected: str) -> Hostile:
    return Hostile(f"{K}: {label}", K, argv, tuple(expected))


def _cases_csv(cell: str):
    return lambda folder: ["sweep", "--cases", write(folder, "cases.csv", f"{CASES_HEADER}1,100\n{cell},200\n"),
                           "--out", str(folder / "out")]


CASES: list[Hostile] = []

# --t1/--t2 lists (sweep, picture, export)
for value, words in (("1_00", "'_' digit separators"), ("٧٠", "not ASCII"), ("７０", "not ASCII"),
                     ("1,,2", "item 2 of 3: is empty"), ("1,", "item 2 of 2: is empty"), (" ", "item 1 of 1: is empty"),
                     ("", "item 1 of 1: is empty"), ("0x10", "'0x10' is not a number"),
                     ("1e999", "beyond the range of a floating-point number"), ("nan", "'nan' is not a finite number"),
                     ("1.5.2", "'1.5.2' is not a number")):
    CASES.append(_case(f"sweep --t1 {value!r}", run("sweep", "--t1", value, "--t2", "10,20,30"), "--t1", words))
CASES.append(_case("export --t2 '٢٠٠'", run("export", "--t1", "1", "--t2", "٢٠٠"), "--t2 '٢٠٠', item 1 of 1",
                   "not ASCII"))
CASES.append(_case("picture --t2 '10,,20'", run("picture", "--t1", "1,2", "--t2", "10,,20"), "--t2", "item 2 of 3: is empty"))

# load-case CSV cells
for cell, words in (("1_00", "'_' digit separators"), ("٧٠", "not ASCII"), ("７０", "not ASCII"),
                    ("0x1A", "'0x1A' is not a number"), ("1e999", "beyond the range"), ("+-1", "'+-1' is not a number")):
    CASES.append(_case(f"cases.csv T1 {cell!r}", _cases_csv(cell), "cases.csv", "line 3, T1_input_Nm", words))

# chain-error forces CSV: force_N and the stage number
CASES.append(_case("forces.csv force_N '1_0'", lambda f: [
    "chain-error", "--forces", write(f, "forces.csv", "component,stage,force_N\npin_shaft,1,1_0\n")],
    "forces.csv: 1 problem(s): - line 2: force_N", "'_' digit separators"))
CASES.append(_case("forces.csv stage '٢'", lambda f: [
    "chain-error", "--forces", write(f, "forces.csv", "component,stage,force_N\ninput_shaft,٢,10\n")],
    "forces.csv: 1 problem(s): - line 2: stage '٢' is not a whole number"))
CASES.append(_case("forces.csv force_N '７'", lambda f: [
    "chain-error", "--forces", write(f, "forces.csv", edited(FORCES, "406.38116", "７", 1))],
    "forces.csv: 1 problem(s): - line", "force_N", "not ASCII"))

# doe analyze: the response, the level codes, the level values, published coefficients
CASES.append(_case("design response '８.８５１'", lambda f: [
    "doe", "analyze", write(f, "design.csv", edited(DESIGN, "8.851", "８.８５１")), "--levels", str(LEVELS)],
    "design.csv: 1 problem(s): - line 3: column transmission_error_arcsec", "not ASCII"))
CASES.append(_case("design level code '٢'", lambda f: [
    "doe", "analyze", write(f, "design.csv", edited(DESIGN, "2,1,1,1,1,2,2,2,8.851", "2,1,1,1,1,٢,2,2,8.851")),
    "--levels", str(LEVELS)], "design.csv: 1 problem(s): - line 3: column C: level '٢' is not one of 1 … 3"))
CASES.append(_case("design response '1_0'", lambda f: [
    "doe", "analyze", write(f, "design.csv", edited(DESIGN, "8.851", "1_0")), "--levels", str(LEVELS)],
    "design.csv: 1 problem(s): - line 3", "'_' digit separators"))


def _levels_with(old_new):
    def argv(folder):
        text = LEVELS.read_text(encoding="utf-8")
        first = text.splitlines()[1].split(",")  # the first factor's row: factor, name, unit, levels
        row = ",".join(first[:3] + [old_new] + first[4:])
        return ["doe", "analyze", str(DESIGN), "--levels",
                write(folder, "levels.csv", text.replace(text.splitlines()[1], row, 1))]
    return argv


CASES.append(_case("levels value 'nan'", _levels_with("nan"), "levels.csv: 1 problem(s): - line 2: column level_1",
                   "'nan' is not a finite number"))
CASES.append(_case("levels value '٣'", _levels_with("٣"), "levels.csv: 1 problem(s): - line 2: column level_1", "not ASCII"))
CASES.append(_case("terms coefficient '٧٠'", lambda f: [
    "doe", "analyze", str(DESIGN), "--levels", str(LEVELS), "--terms",
    write(f, "terms.csv", edited(TERMS, "-96.8567", "٧٠"))],
    "--terms", "terms.csv, line 2, column coefficient", "not ASCII"))
CASES.append(_case("montecarlo --samples '1_000'", run("montecarlo", "--tolerances", "x.toml", "--samples", "1_000"),
                   "--samples", "'_' digit separators"))



def edited_reference(old: str, new: str) -> str:
    text = reference_rig()
    assert old in text, old
    return text.replace(old, new, 1)


# magnitudes a float holds but a stiffness cannot: the rig file's bounds refuse them by key, and a
# stiffness that overflows anyway is named by part before any solve (never a LinAlgError)
_SHAFT = "segments = [{ x_mm = [-110, 40], outer_diameter_mm = 19 }]"
for value, words in (("1e-300", "greater than or equal to 0.01"), ("1e300", "less than or equal to 100000"),
                     ("0.001", "greater than or equal to 0.01")):
    CASES.append(_case(f"rig outer_diameter_mm = {value}", lambda folder, v=value: [
        "sweep", "--rig", write(folder, "rig.toml", edited_reference(_SHAFT, _SHAFT.replace("= 19", f"= {v}"))),
        "--t1", "1", "--t2", "100", "--out", str(folder / "out")],
        "parts[1] ('motor_shaft').segments[0].outer_diameter_mm", words))
CASES.append(_case("rig youngs_modulus_MPa = 1e300", lambda folder: [
    "sweep", "--rig", write(folder, "rig.toml", edited_reference("youngs_modulus_MPa = 2.12e5", "youngs_modulus_MPa = 1e300")),
    "--t1", "1", "--t2", "100", "--out", str(folder / "out")], "cannot solve the rig", "youngs_modulus_MPa"))
CASES.append(_case("rig youngs_modulus_MPa = 1e-300", lambda folder: [
    "sweep", "--rig", write(folder, "rig.toml", edited_reference("youngs_modulus_MPa = 2.12e5", "youngs_modulus_MPa = 1e-300")),
    "--t1", "1", "--t2", "100", "--out", str(folder / "out")], "cannot solve the rig", "singular"))
