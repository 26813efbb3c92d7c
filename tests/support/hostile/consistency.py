"""Consistency between readers (load-case side): a torque, a non-finite value or a duplicated case means the same
in a CSV, a TOML, the --t1/--t2 lists, chain-error's --t1, a tolerance file and a study file; the same cases read
the same from LF, CRLF and CR-only CSV, with or without a byte-order mark, and from TOML; a result file that
cannot be written is named with the reason."""

from __future__ import annotations

import json

from hostile import Hostile
from hostile._files import FORCES, STUDY, TOLERANCES, edited, reference_rig, run, write

K = "consistency"
BOUND = "beyond any plausible rig torque (|T| ≤ 1e+06 N·m)"
HEADER = "T1_input_Nm,T2_output_Nm"
PAIRS = ((0.5, 70.0), (1.43, 200.0))


def _case(label: str, argv, *expected: str, exit_code: int = 2, check=None) -> Hostile:
    return Hostile(f"{K}: {label}", K, argv, tuple(expected), exit_code=exit_code,
                   stream="stderr" if exit_code else "output", check=check)


def _sweep(name: str, text: str, newline: str | None = ""):
    return lambda f: ["sweep", "--cases", write(f, name, text, newline), "--out", str(f / "out")]


def _same_cases(folder, stdout, stderr):
    cases = json.loads((folder / "out" / "sweep.json").read_text(encoding="utf-8"))["cases"]
    assert [(c["T1_input_Nm"], c["T2_output_Nm"]) for c in cases] == list(PAIRS)


def _toml(t1, t2) -> str:
    return f"[[cases]]\nT1_input_Nm = {t1}\nT2_output_Nm = {t2}\n"


CSV_ROWS = "".join(f"{a},{b}\n" for a, b in PAIRS)
TOML_ROWS = "".join(_toml(a, b) for a, b in PAIRS)

CASES: list[Hostile] = [
    # one torque bound, |T| ≤ 1e6 N·m, in every reader, and the same words
    _case("torque bound: cases.csv", _sweep("cases.csv", f"{HEADER}\n1e12,200\n"), "cases.csv",
          "line 2 (case 1): T1_input_Nm = 1e+12 N·m", BOUND),
    _case("torque bound: cases.toml", _sweep("cases.toml", _toml(1, "1e12")), "cases.toml",
          "case 1: T2_output_Nm = 1e+12 N·m", BOUND),
    _case("torque bound: sweep --t1", run("sweep", "--t1", "1e12", "--t2", "1"), "--t1 '1e12', item 1 of 1",
          "1e+12 N·m is beyond any plausible rig torque (|T| ≤ 1e+06 N·m)"),
    _case("torque bound: export --t2", run("export", "--t1", "1", "--t2", "-2e6"), "--t2 '-2e6'",
          "-2e+06 N·m is beyond any plausible rig torque (|T| ≤ 1e+06 N·m)"),
    _case("torque bound: chain-error --t1", run("chain-error", "--forces", str(FORCES), "--t1", "1e12"),
          "--t1: 1e+12 is outside the range", "-1e+06 … 1e+06 N·m"),
    _case("torque bound: tolerance [[cases]]", lambda f: [
        "montecarlo", "--tolerances", write(f, "tol.toml", edited(TOLERANCES, "T1_input_Nm = 1.43", "T1_input_Nm = 1e12"))],
          "tol.toml", "T1_input_Nm = 1e+12 N·m", BOUND),
    _case("torque bound: study file", lambda f: [
        "doe", "rig", "--study", write(f, "study.toml", edited(STUDY, "T2_output_Nm = 200.0", "T2_output_Nm = -1e12"))],
          "study.toml", "study.T2_output_Nm", "greater than or equal to -1000000"),
    # a value that is not finite, in every form
    _case("not finite: cases.csv", _sweep("cases.csv", f"{HEADER}\n1,inf\n"), "cases.csv",
          "line 2, T2_output_Nm: 'inf' is not a finite number"),
    _case("not finite: cases.toml", _sweep("cases.toml", _toml("nan", 1)), "cases.toml",
          "case 1: T1_input_Nm = nan is not a finite number"),
    _case("not finite: --t2", run("sweep", "--t1", "1", "--t2", "-inf"), "--t2 '-inf', item 1 of 1",
          "'-inf' is not a finite number"),
    # a duplicated case, in every form
    _case("duplicate: cases.csv", _sweep("cases.csv", f"{HEADER}\n1,100\n1.0,1e2\n"), "cases.csv",
          "line 3 (case 2): duplicated load case", "the same as line 2 (case 1)"),
    _case("duplicate: cases.toml", _sweep("cases.toml", _toml(1, 100) + _toml("1.0", "1e2")), "cases.toml",
          "case 2: duplicated load case", "the same as case 1"),
    _case("duplicate: --t1/--t2", run("sweep", "--t1", "1,1", "--t2", "100,100"), "command line",
          "case 2: duplicated load case", "the same as case 1"),
    # a torque written as text with its unit: refused in CSV and TOML alike
    _case("unit in a value: cases.csv", _sweep("cases.csv", f"{HEADER}\n1 Nm,100\n"), "cases.csv",
          "line 2, T1_input_Nm", "'1 Nm' is not a number"),
    _case("unit in a value: cases.toml", _sweep("cases.toml", _toml('"1 Nm"', 100)), "cases.toml",
          "cases[1].T1_input_Nm", "'1 Nm' is not a number"),
    # the same cases, however the file is written
    _case("same cases: CSV with LF", _sweep("cases.csv", f"{HEADER}\n{CSV_ROWS}"), exit_code=0, check=_same_cases),
    _case("same cases: CSV with CRLF", _sweep("cases.csv", f"{HEADER}\r\n{CSV_ROWS.replace(chr(10), chr(13) + chr(10))}"),
          exit_code=0, check=_same_cases),
    _case("same cases: CSV with CR only", _sweep("cases.csv", f"{HEADER}\r{CSV_ROWS.replace(chr(10), chr(13))}"),
          exit_code=0, check=_same_cases),
    _case("same cases: CSV with a byte-order mark", _sweep("cases.csv", f"\ufeff{HEADER}\n{CSV_ROWS}"),
          exit_code=0, check=_same_cases),
    _case("same cases: TOML", _sweep("cases.toml", TOML_ROWS), exit_code=0, check=_same_cases),
    # result files that cannot be written: the file and the reason, never "None"
    _case("write: --out below a regular file", lambda f: [
        "chain-error", "--forces", str(FORCES), "--tilt", "none", "--out", str(f / write(f, "file.txt", "x") / "sub")],
          "cannot write", "file.txt/sub", "not a directory"),
    _case("write: doe --json names a folder", lambda f: [
        "doe", "analyze", str(FORCES.parent / "paper001_l27_transmission_error.csv"), "--levels",
        str(FORCES.parent / "paper001_l27_levels.csv"), "--json", str(f)], "cannot write", "is a directory"),
]


def _rig(old: str, new: str):
    def argv(folder):
        text = reference_rig()
        assert old in text, old
        return ["sweep", "--model", "hybrid", "--rig", write(folder, "rig.toml", text.replace(old, new, 1))]
    return argv


# the rig file's mesh sizes obey the range of --mesh-size-mm (a size of 1e-300 mm once divided by zero in the
# memory estimate)
CASES += [
    _case("mesh range: rig [solid] mesh_size_mm 1e-300", _rig("mesh_size_mm = 4.0", "mesh_size_mm = 1e-300"),
          "rig.toml", "solid.mesh_size_mm: 1e-300 mm is outside 0.05 … 1000 mm (the range of --mesh-size-mm)"),
    _case("mesh range: rig [solid] mesh_size_mm 1e300", _rig("mesh_size_mm = 4.0", "mesh_size_mm = 1e300"),
          "rig.toml", "solid.mesh_size_mm: 1e+300 mm is outside 0.05 … 1000 mm"),
    _case("mesh range: rig elements_per_diameter 1e-300",
          _rig("elements_per_diameter = 6.0", "elements_per_diameter = 1e-300"),
          "rig.toml", "solid.elements_per_diameter", "greater than or equal to 1"),
]
