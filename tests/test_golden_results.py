"""The reference rig's result files are what they were before the package moved under ``rvcoax``.

``tests/golden/`` holds the files ``rvcoax sweep``, ``rvcoax check`` and ``rvcoax sweep --model hybrid``
wrote on the reference rig at commit d73afe7, the last one before the library restructure (issue 13),
made on a 2-core AMD EPYC with two BLAS threads. On that machine and thread count the files after the
move were compared byte for byte (see ``benchmarks/RESULTS.md``). Here, on any machine, every key,
column, string and the layout must be identical, and every number equal to the accuracy of its solve:
the floating-point rounding of a factorisation differs between CPUs and thread counts (the hybrid
model's files differ at 3e-7 relative between one and two PARDISO threads on the same machine, on
values 1e-6 of their column's largest), so a byte comparison across machines would test the CPU, not
the code.
"""

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import pytest

GOLDEN = Path(__file__).parent / "golden"
NUMBER = re.compile(r"-?\d+\.?\d*(?:[eE][-+]?\d+)?")
# Rounding noise of the solve itself: compared only as "still tiny", not digit for digit.
NOISE_KEYS = ("equilibrium_relative_error", "solve_relative_residual", "relative_residual")
ESTIMATE_KEYS = ("condition_number_estimate",)
RELATIVE_TO_COLUMN = 1e-7


def _rvcoax() -> str:
    return str(Path(sys.executable).with_name("rvcoax"))


def _csv_columns(text: str) -> tuple[list[str], dict[str, list[str]]]:
    lines = text.splitlines()
    header = lines[0].split(",")
    columns: dict[str, list[str]] = {name: [] for name in header}
    for line in lines[1:]:
        for name, value in zip(header, line.split(",")):
            columns[name].append(value)
    return header, columns


def _json_leaves(value, path=""):
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _json_leaves(item, f"{path}/{key}")
    elif isinstance(value, list):
        for item in value:
            yield from _json_leaves(item, f"{path}[]")
    else:
        yield path, value


def _is_number(text) -> bool:
    return isinstance(text, (int, float)) and not isinstance(text, bool) or (
        isinstance(text, str) and NUMBER.fullmatch(text) is not None)


def _compare_groups(golden: dict[str, list], produced: dict[str, list], where: str) -> None:
    assert list(golden) == list(produced), f"{where}: keys differ"
    for key, expected in golden.items():
        got = produced[key]
        assert len(got) == len(expected), f"{where}:{key}: {len(got)} values, expected {len(expected)}"
        numeric = [i for i, v in enumerate(expected) if _is_number(v)]
        for i, v in enumerate(expected):
            if i not in numeric:
                assert got[i] == v, f"{where}:{key}[{i}]: {got[i]!r} != {v!r}"
        if not numeric:
            continue
        a = [float(expected[i]) for i in numeric]
        b = [float(got[i]) for i in numeric]
        if any(estimate in key for estimate in ESTIMATE_KEYS):
            assert all(0.5 * x <= y <= 2.0 * x for x, y in zip(a, b)), f"{where}:{key}: {b} against {a}"
            continue
        if any(noise in key for noise in NOISE_KEYS):
            assert all(abs(x) < 1e-6 for x in b), f"{where}:{key}: residual {max(map(abs, b))}"
            continue
        scale = max(map(abs, a)) or 1.0
        for i, x, y in zip(numeric, a, b):
            assert math.isclose(x, y, rel_tol=1e-9, abs_tol=RELATIVE_TO_COLUMN * scale), (
                f"{where}:{key}[{i}]: {y!r} != {x!r} (column scale {scale:g})")


def _compare(golden_file: Path, produced_file: Path) -> None:
    expected, got = golden_file.read_text(), produced_file.read_text()
    if expected == got:
        return
    where = f"{golden_file.parent.name}/{golden_file.name}"
    if golden_file.suffix == ".csv":
        header_a, columns_a = _csv_columns(expected)
        header_b, columns_b = _csv_columns(got)
        assert header_a == header_b, f"{where}: header differs"
        _compare_groups(columns_a, columns_b, where)
    else:
        groups_a: dict[str, list] = {}
        groups_b: dict[str, list] = {}
        for path, value in _json_leaves(json.loads(expected)):
            groups_a.setdefault(path, []).append(value)
        for path, value in _json_leaves(json.loads(got)):
            groups_b.setdefault(path, []).append(value)
        _compare_groups(groups_a, groups_b, where)


COMMANDS = {
    "sweep": ["sweep"],
    "check": ["check"],
    "hybrid": ["sweep", "--model", "hybrid"],
}


@pytest.mark.parametrize("name", list(COMMANDS))
def test_reference_rig_files_match_the_files_written_before_the_restructure(name, tmp_path):
    out = tmp_path / name
    done = subprocess.run([_rvcoax(), *COMMANDS[name], "--out", str(out)], capture_output=True, text=True)
    assert done.returncode in (0, 3), done.stdout + done.stderr
    golden_files = sorted((GOLDEN / name).iterdir())
    assert golden_files
    for golden_file in golden_files:
        produced = out / golden_file.name
        assert produced.is_file(), f"{name}: {golden_file.name} was not written"
        _compare(golden_file, produced)
