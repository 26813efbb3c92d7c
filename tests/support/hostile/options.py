"""Hostile option values: every numeric option of every command gets nan, ±inf, 0, negatives, 1e-300, 1e300,
empty and blank text, digit separators and non-ASCII digits (as they apply); the scheduler address and the
environment variables too. Each is refused at the boundary, naming the option, the range and the unit."""

from __future__ import annotations

from hostile import Hostile
from hostile._files import DESIGN, FORCES, LEVELS, TOLERANCES, run

K = "options"
MESH_RANGE = "0.05 … 1000 mm"


def _case(label: str, argv, *expected: str, env=None) -> Hostile:
    return Hostile(f"{K}: {label}", K, argv, tuple(expected), env=env or {})


CASES: list[Hostile] = []

# --mesh-size-mm (sweep, check, picture, export, doe rig, montecarlo): 0.05 … 1000 mm
for value, reason in (("nan", "is not a finite number"), ("inf", "is not a finite number"),
                      ("-inf", "is not a finite number"), ("0", "is outside the range"), ("-4", "is outside the range"),
                      ("1e-300", "is outside the range"), ("1e300", "is outside the range"),
                      ("", "the value is empty"), (" ", "the value is empty"), ("1_00", "'_' digit separators"),
                      ("٧٠", "characters that are not ASCII"), ("７０", "characters that are not ASCII"),
                      ("4mm", "'4mm' is not a number"), ("1e999", "beyond the range of a floating-point number")):
    CASES.append(_case(f"sweep --mesh-size-mm {value!r}", run("sweep", "--model", "solid", "--mesh-size-mm", value),
                       "--mesh-size-mm", reason, MESH_RANGE))
for command in (("check",), ("picture",), ("export",), ("doe", "rig")):
    CASES.append(_case(f"{' '.join(command)} --mesh-size-mm 1e-300",
                       run(*command, "--model", "hybrid", "--mesh-size-mm", "1e-300"), "--mesh-size-mm", MESH_RANGE))
CASES.append(_case("montecarlo --mesh-size-mm nan",
                   run("montecarlo", "--tolerances", str(TOLERANCES), "--mesh-size-mm", "nan"), "--mesh-size-mm",
                   "not a finite number"))

# picture --warp-fraction: (0, 1)
for value in ("nan", "0", "1", "-0.1", "1e300"):
    CASES.append(_case(f"picture --warp-fraction {value}", run("picture", "--warp-fraction", value),
                       "--warp-fraction", "(0, 1)"))

# export --input-radial-mm / --output-radial-mm: 0 … 10 mm
for option, value in (("--input-radial-mm", "-1"), ("--input-radial-mm", "nan"), ("--output-radial-mm", "inf"),
                      ("--output-radial-mm", "1e300"), ("--input-radial-mm", "٠٫٥")):
    CASES.append(_case(f"export {option} {value}", run("export", option, value), option, "0 … 10 mm"))

# doe analyze --alpha (0, 0.5) and --pool-below-F 0 … 1000
for option, value, words in (("--alpha", "nan", "(0, 0.5)"), ("--alpha", "0", "(0, 0.5)"),
                             ("--alpha", "0.5", "(0, 0.5)"), ("--alpha", "-inf", "(0, 0.5)"),
                             ("--pool-below-F", "-1", "0 … 1000"), ("--pool-below-F", "nan", "0 … 1000"),
                             ("--pool-below-F", "1e300", "0 … 1000")):
    CASES.append(_case(f"doe analyze {option} {value}",
                       run("doe", "analyze", str(DESIGN), "--levels", str(LEVELS), option, value), option, words))

# chain-error --t1/--t2 (|T| ≤ 1e6 N·m) and --input-radial-mm/--output-radial-mm (0 … 10 mm, old names
# --a-input-mm/--a-output-mm): refused as options,
# not blamed on the rig file
for option, value, words in (("--t1", "nan", "-1e+06 … 1e+06 N·m"), ("--t2", "inf", "-1e+06 … 1e+06 N·m"),
                             ("--t1", "1e300", "is outside the range"), ("--t2", "-1e300", "is outside the range"),
                             ("--input-radial-mm", "-1", "0 … 10 mm"), ("--output-radial-mm", "nan", "0 … 10 mm")):
    CASES.append(_case(f"chain-error {option} {value}", run("chain-error", "--forces", str(FORCES), option, value),
                       option, words))

# montecarlo / sensitivity: whole numbers in range, a real scheduler address
for command, option, value, words in (
        ("montecarlo", "--seed", "-1", "0 … 4294967295"), ("montecarlo", "--seed", "1.5", "not a whole number"),
        ("montecarlo", "--seed", "1e300", "is outside the range"), ("montecarlo", "--samples", "0", "1 … 10000000"),
        ("montecarlo", "--samples", "nan", "not a finite number"), ("montecarlo", "--workers", "0", "1 … 1024"),
        ("montecarlo", "--workers", "2.5", "not a whole number"), ("sensitivity", "--samples", "1", "2 … 10000000"),
        ("sensitivity", "--seed", "", "the value is empty")):
    CASES.append(_case(f"{command} {option} {value!r}", run(command, "--tolerances", str(TOLERANCES), option, value),
                       option, words))
for address, words in (("garbage://x", "protocol 'garbage' is not one of"), ("tcp://host", "needs HOST:PORT"),
                       ("tcp://host:99999", "port 1 … 65535"), ("nowhere", "is not auto, local, serial or an address"),
                       ("tcp://:8786", "needs HOST:PORT")):
    CASES.append(_case(f"montecarlo --scheduler {address}",
                       run("montecarlo", "--tolerances", str(TOLERANCES), "--scheduler", address, "--samples", "2"),
                       "--scheduler", words))

# environment variables that rvcoax reads
for value, words in (("inf", "not a finite number"), ("nan", "not a finite number"), ("1e300", "is outside the range"),
                     ("-1", "is outside the range"), ("soon", "'soon' is not a number")):
    CASES.append(_case(f"RVCOAX_CASE_DELAY_S={value}", run("sweep", "--t1", "1", "--t2", "10"),
                       "environment variable RVCOAX_CASE_DELAY_S", words, "0 … 60 s",
                       env={"RVCOAX_CASE_DELAY_S": value}))

# discrepancy: --margin (ΔBIC) 0 … 1000, --alpha (0, 0.5), --model-form-percent 0 … 50 %, --hold-out-every 0 … 1000
for option, value, words in (("--margin", "nan", "0 … 1000"), ("--margin", "-1", "0 … 1000"),
                             ("--margin", "1_0", "'_' digit separators"), ("--alpha", "0", "(0, 0.5)"),
                             ("--model-form-percent", "inf", "0 … 50 %"), ("--hold-out-every", "-1", "0 … 1000"),
                             ("--hold-out-every", "1.5", "not a whole number")):
    CASES.append(_case(f"discrepancy {option} {value}", run("discrepancy", "--measured", "m.csv", option, value),
                       option, words))

# the ends of the ranges are valid inputs: they must solve (exit 0), not be refused or crash
CASES += [
    Hostile(f"{K}: chain-error --t1 1e6 --t2 -1e6 solves", K,
            run("chain-error", "--forces", str(FORCES), "--t1", "1e6", "--t2", "-1e6"), ("θ_total",), exit_code=0,
            stream="output"),
    Hostile(f"{K}: sweep at ±1e6 N·m and 0 solves", K,
            lambda f: ["sweep", "--t1", "1e6,-1e6,0", "--t2", "1e6,-1e6,0", "--out", str(f / "out")],
            ("3 load cases",), exit_code=0, stream="output"),
    Hostile(f"{K}: export --input-radial-mm 10 (the top of the range) solves", K,
            lambda f: ["export", "--t1", "1", "--t2", "10", "--input-radial-mm", "10", "--out", str(f / "out")],
            ("a: input 10 mm",), exit_code=0, stream="output"),
]
