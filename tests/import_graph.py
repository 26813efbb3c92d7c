"""The import graph of the rvcoax source tree, read from the files (nothing is imported).

An edge is every ``import rvcoax…`` / ``from rvcoax… import …`` at any depth: at module level, inside a
function, and under ``if TYPE_CHECKING:`` (a type-only import still ties the two modules together), plus
every module a package's lazy name table (``lazy_names(…, {module: names})``, ``rvcoax/_lazy.py``) loads on
use. Used by the cycle test (tests/package/test_package.py) and the floor test (tests/package/test_layers.py).
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Edge", "ROOT", "edges", "module_files", "resolve"]

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("fem", "geometry", "loadcases", "results")


@dataclass(frozen=True)
class Edge:
    """``source`` imports ``target`` at ``line``; ``how``: ``import``, ``function``, ``type-checking`` or ``lazy``."""

    source: str
    target: str
    line: int
    how: str

    def __str__(self) -> str:
        return f"{self.source}:{self.line} → {self.target} ({self.how})"


def module_files(root: Path = ROOT) -> dict[str, Path]:
    """Every module of the package, by its full name (``rvcoax.results.sweep``), with its file."""
    found = {}
    for path in [root / "__init__.py", *root.glob("*.py"), *(p for d in PACKAGES for p in (root / d).rglob("*.py"))]:
        parts = list(path.relative_to(root).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(["rvcoax", *parts])] = path
    return found


def resolve(name: str, modules) -> str | None:
    """The module an imported name lives in: the name itself or its longest prefix that is a module."""
    while name not in modules and "." in name:
        name = name.rsplit(".", 1)[0]
    return name if name in modules else None


def _kinds(tree: ast.Module) -> dict[int, str]:
    """id(node) → ``type-checking`` or ``function`` for the nodes inside such blocks."""
    kinds = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            for inner in ast.walk(node):
                kinds.setdefault(id(inner), "function")
    for node in ast.walk(tree):
        test = getattr(node, "test", None) if isinstance(node, ast.If) else None
        if test is not None and (getattr(test, "id", "") == "TYPE_CHECKING" or getattr(test, "attr", "") == "TYPE_CHECKING"):
            for inner in node.body:
                for deeper in ast.walk(inner):
                    kinds[id(deeper)] = "type-checking"
    return kinds


def _lazy_tables(tree: ast.Module) -> list[tuple[str, int]]:
    """(module, line) of every key of a ``lazy_names(package, globals(), {module: names})`` table."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "lazy_names" and len(node.args) >= 3:
            table = node.args[2]
            if isinstance(table, ast.Dict):
                found += [(key.value, key.lineno) for key in table.keys if isinstance(key, ast.Constant)]
    return found


def edges(source: str, text: str, modules) -> list[Edge]:
    """The rvcoax imports of module ``source`` whose text is ``text``, resolved to modules of ``modules``."""
    tree = ast.parse(text)
    kinds = _kinds(tree)
    found = []
    for node in ast.walk(tree):
        names = []
        if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "rvcoax" \
                and node.level == 0:
            names = [f"{node.module}.{alias.name}" for alias in node.names]
        elif isinstance(node, ast.Import):
            names = [alias.name for alias in node.names if alias.name.split(".")[0] == "rvcoax"]
        for name in names:
            target = resolve(name, modules)
            if target is not None and target != source:
                found.append(Edge(source, target, node.lineno, kinds.get(id(node), "import")))
    for name, line in _lazy_tables(tree):
        target = resolve(name, modules)
        if target is not None and target != source:
            found.append(Edge(source, target, line, "lazy"))
    return found
