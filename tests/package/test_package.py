"""The package as installed: one import name, no import cycles, a thin CLI that starts fast.

The public API and the rule that the command line imports only it: tests/package/test_public_api.py.
"""

import ast
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from import_graph import ROOT, edges, module_files

import rvcoax
from rvcoax.results.cli import app as cli_app

PACKAGES = ("fem", "geometry", "loadcases", "results")


def import_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every circle found by a depth-first walk of ``graph`` (module → the modules it imports)."""
    cycles, state = [], {}

    def visit(node, trail):
        state[node] = "open"
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                cycles.append(trail[trail.index(nxt):] + [nxt])
            elif nxt not in state:
                visit(nxt, trail + [nxt])
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node, [node])
    return cycles


def _graph(sources: dict[str, str]) -> dict[str, set[str]]:
    """Module → the modules it imports when it runs (a package's lazy table of its own names is no such edge:
    the floor test reads those)."""
    graph = {name: set() for name in sources}
    for name, text in sources.items():
        graph[name] |= {e.target for e in edges(name, text, sources) if e.target != "rvcoax" and e.how != "lazy"}
    return graph


def test_no_import_cycles_even_through_imports_inside_functions_or_for_type_checking():
    sources = {name: path.read_text(encoding="utf-8") for name, path in module_files().items()}
    cycles = import_cycles(_graph(sources))
    assert not cycles, "import cycles: " + "; ".join(" → ".join(c) for c in cycles)


def test_a_type_only_import_closes_a_circle():
    """The check can fail: a type-only import back, or one inside a function, makes a circle."""
    sources = {"rvcoax.a": "from rvcoax.b import f\n",
               "rvcoax.b": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from rvcoax.a import A\n",
               "rvcoax.c": "def g():\n    from rvcoax.a import f\n", "rvcoax.d": "import rvcoax.c\n"}
    assert import_cycles(_graph(sources)) == [["rvcoax.a", "rvcoax.b", "rvcoax.a"]]
    sources["rvcoax.a"] += "def h():\n    from rvcoax.d import x\n"
    assert ["rvcoax.a", "rvcoax.d", "rvcoax.c", "rvcoax.a"] in import_cycles(_graph(sources))


def test_every_module_says_what_it_offers():
    missing = [name for name, path in module_files().items()
               if path.name != "__init__.py" and "__all__" not in path.read_text(encoding="utf-8")]
    assert not missing


def test_import_rvcoax_loads_nothing_heavy_and_names_load_on_use():
    code = ("import sys, rvcoax; heavy = [m for m in ('numpy', 'scipy', 'pydantic', 'skfem') if m in sys.modules]; "
            "print(heavy); rvcoax.load_rig; print('pydantic' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=Path.home())
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[:2] == ["[]", "True"]
    assert set(rvcoax.__all__) <= set(dir(rvcoax))
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        rvcoax.nothing  # noqa: B018


def test_the_help_list_matches_every_command_own_help():
    """``rvcoax --help`` lists the commands without loading them: its texts must be theirs."""
    for name, (_, short_help) in cli_app.COMMANDS.items():
        command = cli_app.load_command(name)
        assert command.name == name
        assert command.get_short_help_str(limit=1000) == short_help, name


def test_help_imports_no_command_module():
    code = ("import sys; from rvcoax.results.cli.app import app; from typer.testing import CliRunner; "
            "r = CliRunner().invoke(app, ['--help']); assert r.exit_code == 0, r.output; "
            "print(sorted(m for m in sys.modules if m.startswith('rvcoax.results.cli.') or m in ('numpy', 'scipy')))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=Path.home())
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "['rvcoax.results.cli.app']"


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("wheel")
    source = folder / "source"  # pip builds in the source tree: build a copy, not the checkout
    shutil.copytree(ROOT, source, ignore=shutil.ignore_patterns(".venv", ".git", "build", "*.egg-info", "rvcoax_out",
                                                                "__pycache__", ".pytest_cache", ".ruff_cache"))
    done = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q",
                           "-w", str(folder), str(source)], capture_output=True, text=True)
    if done.returncode != 0 and "setuptools" in done.stderr and "version" in done.stderr.lower():
        pytest.skip(f"this environment's setuptools cannot build the wheel offline: {done.stderr[-300:]}")
    assert done.returncode == 0, done.stderr[-2000:]
    (path,) = folder.glob("rvcoax-*.whl")
    return path


def test_the_wheel_holds_nothing_outside_rvcoax(wheel):
    names = zipfile.ZipFile(wheel).namelist()
    outside = [n for n in names if not (n.startswith("rvcoax/") or n.startswith("rvcoax-"))]
    assert not outside, outside
    for data in ("rvcoax/geometry/data/reference_rig.toml", "rvcoax/loadcases/data/paper000_coaxiality_table.csv",
                 "rvcoax/results/cli/app.py", "rvcoax/__init__.py"):
        assert data in names
    assert not [n for n in names if n.startswith(("rvcoax/tests/", "rvcoax/benchmarks/", "rvcoax/docs/"))]


def test_the_installed_wheel_runs_and_the_old_names_are_gone(wheel, tmp_path):
    target = tmp_path / "site"
    done = subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "-q", "--target", str(target),
                           str(wheel)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    assert sorted(p.name.split("-")[0] for p in target.iterdir() if p.name != "bin") == ["rvcoax", "rvcoax"]
    environment = {**os.environ, "PYTHONPATH": str(target)}
    code = ("import importlib.util, rvcoax; print(rvcoax.__file__); "
            "print([n for n in ('fem', 'geometry', 'loadcases', 'results') if importlib.util.find_spec(n)])")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path,
                          env=environment)
    assert done.returncode == 0, done.stderr
    location, old_names = done.stdout.splitlines()
    assert location.startswith(str(target)) and old_names == "[]"
    out = tmp_path / "out"
    done = subprocess.run([sys.executable, "-c", "from rvcoax.results.cli.app import run; run()", "sweep",
                           "--out", str(out)], capture_output=True, text=True, cwd=tmp_path, env=environment)
    assert done.returncode == 0, done.stdout + done.stderr
    from golden_files import GOLDEN, compare_result_file

    for name in ("sweep.csv", "sweep.json", "sweep_paths.csv"):
        compare_result_file(GOLDEN / "sweep" / name, out / name)


def test_tests_import_helpers_not_other_test_modules():
    """Shared test helpers live in plain modules (tests/frames.py, tests/rigdata.py, …), found because the
    tests folder holds the root conftest.py; a test module is never imported by another."""
    problems = []
    for path in (ROOT / "tests").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = ([node.module or ""] if isinstance(node, ast.ImportFrom)
                     else [a.name for a in node.names] if isinstance(node, ast.Import) else [])
            problems += [f"{path.relative_to(ROOT)}:{node.lineno}: {name}" for name in names
                         if name.split(".")[0] == "tests" or name.rsplit(".", 1)[-1].startswith("test_")]
    assert not problems, problems


def test_the_folders_are_not_packages_of_their_own_from_the_repository_root():
    """Python started in the repository root sees the folders; importing one says to import rvcoax.<name>."""
    for name in ("fem", "geometry", "loadcases", "results"):
        done = subprocess.run([sys.executable, "-c", f"import {name}"], capture_output=True, text=True, cwd=ROOT)
        assert done.returncode == 1
        assert f"ImportError: '{name}' is part of rvcoax and is imported as rvcoax.{name}" in done.stderr


def test_one_name_one_meaning():
    """``MM`` is defined once (mm → m, geometry/units.py), and a class named ``…Error`` is an exception, never a
    result type."""
    import importlib

    defined, not_errors = [], []
    for name, path in module_files().items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:
            if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "MM" for t in node.targets):
                defined.append(name)
            if isinstance(node, ast.ClassDef) and node.name.endswith("Error"):
                if not issubclass(getattr(importlib.import_module(name), node.name), BaseException):
                    not_errors.append(f"{name}.{node.name}")
    assert defined == ["rvcoax.geometry.units"]
    assert not not_errors
