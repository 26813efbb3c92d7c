"""No constructor call in the library passes more than five positional arguments (issue 23): a record with more
fields is built by keyword, so that a field added or moved cannot silently shift the values into the wrong ones."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MAX_POSITIONAL = 5
LIBRARY = ("fem", "geometry", "loadcases", "results")


def _library_files() -> list[Path]:
    return sorted(p for folder in LIBRARY for p in (ROOT / folder).rglob("*.py"))


def _long_positional_calls(source: str) -> list[tuple[int, str, int]]:
    """(line, class name, positional arguments) of each call of a capitalised name with more than five positional
    arguments (a class, by the naming convention every module keeps)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.Call):
            continue
        func = node.func
        name = func.id if isinstance(func, ast.Name) else func.attr if isinstance(func, ast.Attribute) else ""
        if name[:1].isupper() and len(node.args) > MAX_POSITIONAL:
            found.append((node.lineno, name, len(node.args)))
    return found


def test_no_library_constructor_call_passes_more_than_five_positional_arguments():
    problems = [f"{path.relative_to(ROOT)}:{line}: {name}(…) with {count} positional arguments"
                for path in _library_files() for line, name, count in _long_positional_calls(path.read_text("utf-8"))]
    assert len(_library_files()) > 100
    assert not problems, "\n".join(problems)


def test_the_scan_finds_a_long_positional_call():
    source = "x = Record(1, 2, 3, 4, 5, 6)\ny = module.Record(1, 2, 3, 4, 5, sixth=6)\nz = make(1, 2, 3, 4, 5, 6)\n"
    assert _long_positional_calls(source) == [(1, "Record", 6)]


def test_no_library_function_waives_the_positional_or_statement_rules():
    """The rules issue 23 turned on (ruff PLR0917, at most five positional parameters; PLR0915, at most 50
    statements) hold without waivers: a function with more parameters takes the rest by keyword."""
    waived = [f"{path.relative_to(ROOT)}:{number}" for path in _library_files()
              for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1)
              if "noqa" in line and ("PLR0917" in line or "PLR0915" in line)]
    assert not waived, waived
