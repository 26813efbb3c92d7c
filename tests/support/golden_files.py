"""Comparing result files with the golden files in tests/golden (see tests/results/test_golden_results.py).

Every golden column and key is compared strictly; columns and keys added later (after the golden
columns, or between golden JSON keys) are allowed, and the rig file's SHA-256 is only checked to be one.
The list of unit-load names may gain names at its end (issue 16: the gear meshes' ``gear_contact_T1/T2``);
the golden names are still compared strictly, in their places.
"""

import json
import math
import re
from pathlib import Path

GOLDEN = Path(__file__).resolve().parents[1] / "golden"
NUMBER = re.compile(r"-?\d+\.?\d*(?:[eE][-+]?\d+)?")
# Rounding noise of the solve itself: compared only as "still tiny", not digit for digit.
NOISE_KEYS = ("equilibrium_relative_error", "solve_relative_residual", "relative_residual")
ESTIMATE_KEYS = ("condition_number_estimate",)
RELATIVE_TO_COLUMN = 1e-7


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


# Provenance of the input, not a result: the reference rig file gained keys that change no result (issue 15:
# coupling and bearing limits, running speeds), so its SHA-256 differs from the golden files'; it must still be one.
PROVENANCE_KEYS = ("/rig/sha256",)
# Lists that may grow at their end: the golden entries are the produced list's first ones.
APPENDABLE_LISTS = ("/model/unit_loads[]",)
SHA256 = re.compile(r"[0-9a-f]{64}")


def _in_order(golden: list[str], produced: list[str]) -> bool:
    """Every golden key is produced, in the golden order (new keys may come between and after them)."""
    position = {key: i for i, key in enumerate(produced)}
    found = [position.get(key, -1) for key in golden]
    return -1 not in found and found == sorted(found)


def _compare_groups(golden: dict[str, list], produced: dict[str, list], where: str) -> None:
    # keys added since the golden files (issue 15's engineering quantities) are allowed; the golden ones are
    # compared strictly, in their order
    assert _in_order(list(golden), list(produced)), (
        f"{where}: golden keys missing or reordered: {[k for k in golden if k not in produced][:5]}")
    for key, expected in golden.items():
        got = produced[key]
        if key in APPENDABLE_LISTS:
            got = got[: len(expected)]
        assert len(got) == len(expected), f"{where}:{key}: {len(got)} values, expected {len(expected)}"
        if key in PROVENANCE_KEYS:
            assert all(isinstance(v, str) and SHA256.fullmatch(v) for v in got), f"{where}:{key}: {got}"
            continue
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


def compare_result_file(golden_file: Path, produced_file: Path) -> None:
    """Assert that ``produced_file`` is ``golden_file`` to the accuracy of its solve (see the module text)."""
    expected, got = golden_file.read_text(), produced_file.read_text()
    if expected == got:
        return
    where = f"{golden_file.parent.name}/{golden_file.name}"
    if golden_file.suffix == ".csv":
        header_a, columns_a = _csv_columns(expected)
        header_b, columns_b = _csv_columns(got)
        assert header_b[: len(header_a)] == header_a, f"{where}: the golden columns are not the first, in order"
        _compare_groups(columns_a, columns_b, where)
    else:
        groups_a: dict[str, list] = {}
        groups_b: dict[str, list] = {}
        for path, value in _json_leaves(json.loads(expected)):
            groups_a.setdefault(path, []).append(value)
        for path, value in _json_leaves(json.loads(got)):
            groups_b.setdefault(path, []).append(value)
        _compare_groups(groups_a, groups_b, where)
