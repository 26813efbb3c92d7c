"""Tracebacks (issue 24, part 5): inputs that ended in a traceback now end in one paragraph and exit status 2.

- ``report --discrepancy`` given JSON of the wrong types (each key the report reads), a special file
  (``/dev/zero``, a FIFO, a folder), JSON nested 100 000 deep, bytes that are not UTF-8, an empty file;
- ``rig example`` / ``rig reference`` / ``--help`` / ``--version`` writing to a full device (``/dev/full``: a real
  process, its standard output sent there);
- ``--scheduler tls://…`` and ``wss://…`` without Dask's TLS settings (distributed raised a TypeError about
  ``ssl_context``).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from hostile import Hostile
from hostile._files import TOLERANCES, write

K = "tracebacks"
REPORT = ("report", "--t1", "1", "--t2", "10", "--no-deformed")
GIVE = "give the discrepancy.json written by rvcoax discrepancy --out"


def _discrepancy(content: str | bytes):
    def argv(folder: Path) -> list[str]:
        path = folder / "d.json"
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            write(folder, "d.json", content)
        return [*REPORT, "--discrepancy", str(path), "--out", str(folder / "out")]
    return argv


def _document(**keys) -> str:
    return json.dumps({"verdict": "explained", **keys})


def _wrong(label: str, keys: dict, *expected: str) -> Hostile:
    return Hostile(f"{K}: report --discrepancy, {label}", K, _discrepancy(_document(**keys)),
                   ("discrepancy result", "d.json", *expected, GIVE))


def _special(label: str, make, *expected: str) -> Hostile:
    def argv(folder: Path) -> list[str]:
        return [*REPORT, "--discrepancy", make(folder), "--out", str(folder / "out")]
    return Hostile(f"{K}: report --discrepancy, {label}", K, argv, ("discrepancy result", *expected))


def _fifo(folder: Path) -> str:
    os.mkfifo(folder / "d.json")
    return str(folder / "d.json")


DEEP_ARRAYS = "[" * 100_000 + "]" * 100_000
DEEP_OBJECTS = '{"a":' * 100_000 + "1" + "}" * 100_000

CASES: list[Hostile] = [
    _wrong("verdict a number", {"verdict": 3}, "'verdict' is a number, expected a string"),
    _wrong("named a number", {"named": 5}, "'named' is a number, expected an array"),
    _wrong("selected an object", {"selected": {"effect": "x"}}, "'selected' is an object, expected an array"),
    _wrong("selected entry a string", {"selected": ["x"]}, "'selected[0]' is a string, expected an object"),
    _wrong("parameters an array", {"selected": [{"effect": "x", "parameters": [1, 2]}]},
           "'selected[0].parameters' is an array, expected an object"),
    _wrong("parameter value a string", {"selected": [{"effect": "x", "parameters": {"k": {"value": "big"}}}]},
           "'selected[0].parameters.k.value' is a string, expected a number"),
    _wrong("group a number", {"selected": [{"effect": "x", "group": 1}]}, "'selected[0].group' is a number"),
    _wrong("effect a list", {"named": [{"effect": ["x"], "meaning": "m"}]}, "'named[0].effect' is an array"),
    _wrong("rms table a list", {"rms": {"fit": {"rms_before_um": [1]}}},
           "'rms.fit.rms_before_um' is an array, expected an object"),
    _wrong("rms value text", {"rms": {"fit": {"rms_before_um": {"input": "2 µm"}}}},
           "'rms.fit.rms_before_um.input' is a string, expected a number"),
    _wrong("rms_before_mm a string", {"rms_before_mm": "0.002"}, "'rms_before_mm' is a string"),
    _wrong("rms_after_mm value a bool", {"rms_after_mm": {"input": True}}, "'rms_after_mm.input' is true or false"),
    _wrong("confident a string", {"confident": "yes"}, "'confident' is a string, expected true or false"),
    _wrong("observability.invisible a list", {"observability": {"visible": [], "invisible": []}},
           "'observability.invisible' is an array, expected an object"),
    _wrong("cross_validation a number", {"cross_validation": 0.97}, "'cross_validation' is a number"),
    _wrong("summary an object", {"summary": {"a": 1}}, "'summary' is an object, expected a string or an array"),
    Hostile(f"{K}: report --discrepancy, a JSON array", K, _discrepancy("[1, 2]"),
            ("d.json", "has no 'verdict' key")),
    Hostile(f"{K}: report --discrepancy, arrays 100 000 deep", K, _discrepancy(DEEP_ARRAYS),
            ("d.json", "nested too deeply")),
    Hostile(f"{K}: report --discrepancy, objects 100 000 deep", K, _discrepancy(DEEP_OBJECTS),
            ("d.json", "nested too deeply")),
    Hostile(f"{K}: report --discrepancy, verdict nested 100 000 deep", K,
            _discrepancy('{"verdict": ' + DEEP_ARRAYS + "}"), ("d.json", "nested too deeply")),
    Hostile(f"{K}: report --discrepancy, not UTF-8", K, _discrepancy(b'{"verdict": "\xff\xfe"}'),
            ("d.json", "line 1: is not UTF-8 text")),
    Hostile(f"{K}: report --discrepancy, empty file", K, _discrepancy(""), ("d.json", "not a JSON file")),
    _special("/dev/zero", lambda folder: "/dev/zero", "/dev/zero", "is not a regular file"),
    _special("a FIFO", _fifo, "d.json", "is not a regular file"),
    _special("a folder", lambda folder: str(folder), "is a directory"),
    _special("a missing file", lambda folder: str(folder / "none.json"), "none.json", "file not found"),
]

# standard output on a full device: a real process (the console script), never a traceback
FULL = ("cannot write to standard output: no space left on device",)
for args in (("rig", "example"), ("rig", "reference"), ("rig", "reference", "--variant", "ball_bearings"),
             ("--help",), ("--version",), ("sweep", "--help"), ("rig", "show")):
    CASES.append(Hostile(f"{K}: rvcoax {' '.join(args)} > /dev/full", K, lambda folder, args=args: list(args), FULL,
                         stdout_to="/dev/full"))

# TLS schedulers without certificates
TLS = ("--scheduler", "a tls:// scheduler needs the client's TLS certificates", "distributed.comm.tls.ca-file",
       "DASK_DISTRIBUTED__COMM__TLS__CA_FILE")
for command in ("montecarlo", "sensitivity"):
    CASES.append(Hostile(f"{K}: {command} --scheduler tls:// without certificates", K,
                         lambda folder, command=command: [command, "--tolerances", str(TOLERANCES), "--scheduler",
                                                          "tls://127.0.0.1:8786", "--samples", "2"], TLS))
CASES.append(Hostile(f"{K}: montecarlo --scheduler wss:// without certificates", K,
                     lambda folder: ["montecarlo", "--tolerances", str(TOLERANCES), "--scheduler",
                                     "wss://scheduler.lan:8786", "--samples", "2"],
                     ("--scheduler", "a wss:// scheduler needs the client's TLS certificates")))
