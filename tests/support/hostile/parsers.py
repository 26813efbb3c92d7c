"""Parser limits in every reader: TOML nested thousands deep (arrays and inline tables), a CSV field over the
csv module's 131 072 characters, a quote left open, and CR-only (old Mac) line ends, which are valid input
and must read the same as LF."""

from __future__ import annotations

import json

from hostile import Hostile
from hostile._files import (
    DEEP,
    DEEP_TABLES,
    DESIGN,
    FORCES,
    LEVELS,
    LONG_CELL,
    TERMS,
    TOLERANCES,
    edited,
    reference_rig,
    write,
)

K = "parsers"
NESTED = "nested too deeply"
TOO_LONG = "field larger than field limit (131072)"


def _case(label: str, argv, *expected: str, exit_code: int = 2, stream: str = "stderr", check=None) -> Hostile:
    return Hostile(f"{K}: {label}", K, argv, tuple(expected), exit_code=exit_code, stream=stream, check=check)


def _cr(text: str) -> str:
    return text.replace("\r\n", "\n").replace("\n", "\r")


def _cases_in_sweep_json(*pairs):
    def check(folder, stdout, stderr):
        rows = [(r["T1_input_Nm"], r["T2_output_Nm"])
                for r in json.loads((folder / "out" / "sweep.json").read_text(encoding="utf-8"))["cases"]]
        assert rows == list(pairs), rows
    return check


CASES: list[Hostile] = []

# TOML nested thousands deep: rig file, load cases, tolerances, DOE study, chain stage data
for label, text in (("arrays", DEEP), ("inline tables", DEEP_TABLES)):
    CASES += [
        _case(f"rig file {label} nested", lambda f, t=text: ["rig", "show", "--rig", write(f, "rig.toml", t)],
              "rig file", "rig.toml", "line 1", NESTED),
        _case(f"cases.toml {label} nested", lambda f, t=text: ["sweep", "--cases", write(f, "cases.toml", t)],
              "load cases", "cases.toml", "line 1", NESTED),
    ]
CASES += [
    _case("tolerance file arrays nested", lambda f: ["montecarlo", "--tolerances", write(f, "tol.toml", DEEP)],
          "tolerance file", "tol.toml", "line 1", NESTED),
    _case("study file arrays nested", lambda f: ["doe", "rig", "--study", write(f, "study.toml", DEEP)],
          "study file", "study.toml", "line 1", NESTED),
    _case("stage data arrays nested", lambda f: ["chain-error", "--forces", str(FORCES), "--stages",
                                                 write(f, "stages.toml", DEEP)],
          "stage data", "stages.toml", "line 1", NESTED),
    _case("rig file nested deep in a later line", lambda f: [
        "rig", "show", "--rig", write(f, "rig.toml", reference_rig() + "\n[extra]\n" + DEEP)],
          "rig file", NESTED),
]

# a CSV field over 131 072 characters: load cases, design, levels, forces, regression terms
CASES += [
    _case("cases.csv field too long", lambda f: [
        "sweep", "--cases", write(f, "cases.csv", f"T1_input_Nm,T2_output_Nm\n1,100\n{LONG_CELL},200\n")],
          "load cases", "cases.csv", "line 3", TOO_LONG),
    _case("design field too long", lambda f: [
        "doe", "analyze", write(f, "design.csv", edited(DESIGN, "8.851", LONG_CELL)), "--levels", str(LEVELS)],
          "design file", "design.csv", "line 3", TOO_LONG),
    _case("levels field too long", lambda f: [
        "doe", "analyze", str(DESIGN), "--levels", write(f, "levels.csv", edited(LEVELS, "factor", "factor" + LONG_CELL))],
          "levels file", "levels.csv", "line 1", TOO_LONG),
    _case("forces field too long", lambda f: [
        "chain-error", "--forces", write(f, "forces.csv", f'component,stage,force_N\npin_shaft,1,"{LONG_CELL}"\n')],
          "forces file", "forces.csv", "line 2", TOO_LONG),
    _case("terms field too long", lambda f: [
        "doe", "analyze", str(DESIGN), "--levels", str(LEVELS), "--terms",
        write(f, "terms.csv", edited(TERMS, "-96.8567", LONG_CELL))],
          "--terms", "terms.csv", "line 2", TOO_LONG),
    _case("cases.csv quote left open", lambda f: [
        "sweep", "--cases", write(f, "cases.csv", 'T1_input_Nm,T2_output_Nm\n1,100\n"0.5,70\n')],
          "load cases", "cases.csv", "line 3", "is a quote left open?"),
]

# CR-only line ends are valid and read exactly like LF
CASES += [
    _case("cases.csv CR-only line ends solve", lambda f: [
        "sweep", "--cases", write(f, "cases.csv", "T1_input_Nm,T2_output_Nm\r0.5,70\r1.43,200\r"), "--out", str(f / "out")],
          exit_code=0, check=_cases_in_sweep_json((0.5, 70.0), (1.43, 200.0))),
    _case("cases.csv CR-only bad cell names its line", lambda f: [
        "sweep", "--cases", write(f, "cases.csv", "T1_input_Nm,T2_output_Nm\r0.5,70\r1.43,2OO\r")],
          "cases.csv", "line 3, T2_output_Nm", "'2OO' is not a number"),
    _case("forces CR-only line ends solve", lambda f: [
        "chain-error", "--forces", write(f, "forces.csv", _cr(FORCES.read_text(encoding="utf-8"))), "--tilt", "none"],
          "θ_total", exit_code=0, stream="output"),
    _case("design and levels CR-only line ends analyse", lambda f: [
        "doe", "analyze", write(f, "design.csv", _cr(DESIGN.read_text(encoding="utf-8"))),
        "--levels", write(f, "levels.csv", _cr(LEVELS.read_text(encoding="utf-8")))],
          "optimal levels", exit_code=0, stream="output"),
    _case("tolerance file CR-only line ends (TOML needs LF or CRLF)", lambda f: [
        "montecarlo", "--tolerances", write(f, "tol.toml", _cr(TOLERANCES.read_text(encoding="utf-8")))],
          "tolerance file", "tol.toml", "TOML syntax error"),
]

# a quote inside a comment line opens no field (comments are skipped before the CSV is read)
CASES.append(_case("forces comment with a quote solves", lambda f: [
    "chain-error", "--tilt", "none", "--forces",
    write(f, "forces.csv", '# the "pin shaft" row: 6" of text\n' + FORCES.read_text(encoding="utf-8"))],
    "θ_total", exit_code=0, stream="output"))
