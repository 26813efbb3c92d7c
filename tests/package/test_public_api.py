"""The public API: the names a notebook user imports, and the only ones the command line may import.

The public surface is the top-level ``rvcoax`` and the documented namespaces in :data:`NAMESPACES`;
each lists its names in ``__all__`` and loads them on first use (``rvcoax/_lazy.py``).
"""

import ast
import importlib
import inspect
import pkgutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
NAMESPACES = ("rvcoax", "rvcoax.fem", "rvcoax.geometry", "rvcoax.geometry.model", "rvcoax.loadcases", "rvcoax.results",
              "rvcoax.results.io", "rvcoax.results.export", "rvcoax.results.reports", "rvcoax.results.studies",
              "rvcoax.results.studies.doe",
              "rvcoax.results.studies.discrepancy")
CLI = "rvcoax.results.cli"


def _public(namespace: str) -> set[str]:
    return set(importlib.import_module(namespace).__all__)


def _cli_imports(path: Path) -> list[tuple[int, str, str | None]]:
    """(line, module, name or None for ``import module``) of every rvcoax import, at any depth, TYPE_CHECKING too."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "rvcoax":
            found += [(node.lineno, node.module, alias.name) for alias in node.names]
        elif isinstance(node, ast.Import):
            found += [(node.lineno, a.name, None) for a in node.names if a.name.split(".")[0] == "rvcoax"]
    return found


def _cli_problems(path: Path) -> list[str]:
    siblings = {p.stem for p in path.parent.glob("*.py")} - {"__init__"}
    problems = []
    for line, module, name in _cli_imports(path):
        where = f"{path.name}:{line}: "
        if name is None:
            problems.append(where + f"import {module} (import public names instead)")
        elif module == CLI:
            if name not in siblings:
                problems.append(where + f"from {module} import {name}")
        elif module.startswith(CLI + "."):
            if module.rsplit(".", 1)[1] not in siblings:
                problems.append(where + f"from {module} import {name}")
        elif module not in NAMESPACES or name not in _public(module):
            problems.append(where + f"from {module} import {name} is not public API")
    return problems


def test_the_command_line_imports_only_the_public_api():
    files = sorted((ROOT / "results" / "cli").glob("*.py"))
    assert len(files) >= 10
    problems = [p for path in files for p in _cli_problems(path)]
    assert not problems, "\n".join(problems)


def test_the_check_catches_an_internal_import(tmp_path):
    """The rule above can fail: an internal module, a private name and a module import are all caught."""
    (tmp_path / "support.py").write_text("", encoding="utf-8")
    command = tmp_path / "command.py"
    command.write_text("from rvcoax import load_rig\nfrom rvcoax.results.cli import support\n"
                       "def f():\n    from rvcoax.geometry.rigfile import load_rig\n"
                       "    from rvcoax.results.io import records\n    import rvcoax.fem.beam\n"
                       "    from rvcoax.results.cli.nothing import x\n", encoding="utf-8")
    problems = _cli_problems(command)
    assert [p.split(":")[1] for p in problems] == ["4", "5", "6", "7"], problems


@pytest.mark.parametrize("namespace", NAMESPACES)
def test_every_public_name_loads_and_none_hides_a_submodule(namespace):
    """A public name equal to a submodule's name would become that module once the submodule is imported."""
    package = importlib.import_module(namespace)
    submodules = {m.name for m in pkgutil.iter_modules(package.__path__)}
    assert not set(package.__all__) & submodules
    assert len(package.__all__) == len(set(package.__all__))
    assert set(package.__all__) <= set(dir(package))
    for name in package.__all__:
        assert getattr(package, name) is not None, name
    with pytest.raises(AttributeError, match="has no attribute 'nothing'"):
        package.nothing  # noqa: B018


def _documented_constants(value_module: str) -> set[str]:
    """Module-level names assigned with a docstring right after them, or a comment on the same line."""
    path = Path(importlib.import_module(value_module).__file__)
    source = path.read_text(encoding="utf-8").splitlines()
    body = ast.parse("\n".join(source)).body
    found = set()
    for i, node in enumerate(body):
        if isinstance(node, ast.Assign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names = {t.id for t in targets if isinstance(t, ast.Name)}
            after = body[i + 1] if i + 1 < len(body) else None
            docstring = isinstance(after, ast.Expr) and isinstance(getattr(after, "value", None), ast.Constant)
            comment = "#" in source[node.end_lineno - 1] or "#" in source[node.lineno - 2]
            if docstring or comment:
                found |= names
    return found


@pytest.mark.parametrize("namespace", NAMESPACES)
def test_every_public_name_is_documented(namespace):
    """Functions and classes have a docstring; constants a docstring or comment where they are defined."""
    package = importlib.import_module(namespace)
    table = getattr(package, "_WHERE", {})
    missing = []
    for name in package.__all__:
        value = getattr(package, name)
        if inspect.isfunction(value) or inspect.isclass(value):
            doc = (inspect.getdoc(value) or "").strip()
            if not doc or doc.startswith(f"{value.__name__}("):  # a dataclass without one gets its signature
                missing.append(name)
        elif not name.startswith("__") and name not in _documented_constants(table.get(name, namespace)):
            missing.append(name)
    assert not missing, f"{namespace}: undocumented {missing}"


@pytest.mark.parametrize("namespace", NAMESPACES)
def test_public_functions_have_numpy_style_docstrings(namespace):
    """Every public function says what each parameter is and what it returns (numpydoc sections)."""
    package = importlib.import_module(namespace)
    missing = []
    for name in package.__all__:
        value = getattr(package, name)
        if not inspect.isfunction(value):
            continue
        doc, signature = inspect.getdoc(value) or "", inspect.signature(value)
        if signature.parameters and "Parameters\n----------" not in doc:
            missing.append(f"{name}: Parameters")
        if signature.return_annotation not in (None, "None") and not ("Returns\n-------" in doc
                                                                        or "Yields\n------" in doc):
            missing.append(f"{name}: Returns")
    assert not missing, f"{namespace}: {missing}"


def test_docs_api_lists_every_public_name_and_nothing_else():
    """docs/api.md's table row of each namespace names exactly its ``__all__``; the core table names ``rvcoax``'s."""
    import re

    text = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    core, namespaces = text.split("## The namespaces", 1)
    core_rows = [line.split("|")[2] for line in core.split("## The core workflow", 1)[1].splitlines()
                 if line.startswith("| ") and not line.startswith("| step")]
    documented = {"rvcoax": {name for row in core_rows for name in re.findall(r"`(\w+)[(`]", row)} | {"__version__"}}
    for line in namespaces.splitlines():
        row = re.match(r"\| `(rvcoax[\w.]*)` \|[^|]*\|(.*)\|$", line)
        if row:
            documented[row.group(1)] = set(re.findall(r"`(\w+)`", row.group(2)))
    assert set(documented) == set(NAMESPACES)
    for namespace, names in documented.items():
        assert names == _public(namespace), namespace


def test_names_moved_up_a_floor_still_import_from_where_they_were():
    """``rvcoax.results.io`` lost the documents over studies to ``rvcoax.results.reports``; old imports work."""
    import rvcoax.results.io as io
    import rvcoax.results.reports as reports

    for name in ("write_check", "write_report", "read_discrepancy", "print_pdf"):
        assert name not in io.__all__ and name in reports.__all__
        assert getattr(io, name) is getattr(reports, name)
