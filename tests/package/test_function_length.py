"""No function in the library is longer than 80 lines (issue 23): a longer pipeline is split into named stages
with small records between them, so that each stage can be read, tested and changed on its own."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MAX_LINES = 80
LIBRARY = ("fem", "geometry", "loadcases", "results")


def _long_functions(source: str) -> list[tuple[int, str, int]]:
    """(line, name, lines) of each function or method longer than :data:`MAX_LINES`, from its ``def`` line to its
    last line (decorators excluded; docstring, blank and comment lines included)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            length = node.end_lineno - node.lineno + 1
            if length > MAX_LINES:
                found.append((node.lineno, node.name, length))
    return found


def test_no_library_function_is_longer_than_80_lines():
    files = sorted(p for folder in LIBRARY for p in (ROOT / folder).rglob("*.py")) + sorted(ROOT.glob("*.py"))
    problems = [f"{path.relative_to(ROOT)}:{line}: {name} has {length} lines"
                for path in files for line, name, length in _long_functions(path.read_text("utf-8"))]
    assert len(files) > 100
    assert not problems, "\n".join(problems)


def test_the_scan_finds_a_long_function():
    source = "def short():\n    pass\n\n\ndef long():\n" + "    x = 1\n" * 80 + "\n\nclass A:\n    def m(self):\n" + "        y = 2\n" * 80
    assert [(name, length) for _, name, length in _long_functions(source)] == [("long", 81), ("m", 81)]
