"""The floors of the package: every module imports only modules of its own floor or of the floors below.

Data flows one way (DEVELOPERS.md): rig file → geometry → model → solve → results → files, studies,
documents, exports → the command line. Every import counts, wherever it is: at module level, inside a
function, under ``if TYPE_CHECKING:``, and a package's lazy name table (a name loaded on use is imported
then). The import graph itself: tests/support/import_graph.py; its cycles: tests/package/test_package.py.

One exception, declared where it is made: a name that moved up a floor can stay importable from where it
was (``lazy_names(…, moved={module: names})``, e.g. ``rvcoax.results.io.write_report``, now in
``rvcoax.results.reports``); such a name is no longer the package's own (not in its ``__all__``) and is not
an edge here. tests/package/test_public_api.py checks that each still loads.
"""

from import_graph import edges, module_files

# Bottom first. ``name.*`` is a package and everything below it; a plain name is that one module. A module
# belongs to the longest entry that covers it; a module no entry covers fails the test: place it.
FLOORS = (
    ("package helpers", ("rvcoax._lazy", "rvcoax.errors")),
    ("fem", ("rvcoax.fem.*",)),
    ("geometry, load cases", ("rvcoax.geometry.*", "rvcoax.loadcases.*")),
    ("geometry/model", ("rvcoax.geometry.model.*",)),
    ("results core", ("rvcoax.results", "rvcoax.results.paths", "rvcoax.results.engineering", "rvcoax.results.sweep",
                      "rvcoax.results.connections", "rvcoax.results.shaft_safety", "rvcoax.results.torque_path")),
    ("results/io", ("rvcoax.results.io.*",)),
    ("results/studies", ("rvcoax.results.studies.*",)),
    ("results/reports, results/export", ("rvcoax.results.reports.*", "rvcoax.results.export.*")),
    ("public API", ("rvcoax",)),  # the lazy names of `import rvcoax`, which the command line imports
    ("results/cli", ("rvcoax.results.cli.*",)),
)


def floor_of(module: str, floors=FLOORS) -> int | None:
    """The index in ``floors`` of the floor ``module`` is on (None: no floor names it)."""
    best, level = -1, None
    for index, (_, entries) in enumerate(floors):
        for entry in entries:
            package = entry.removesuffix(".*")
            covers = module == package or (entry.endswith(".*") and module.startswith(package + "."))
            if covers and len(package) > best:
                best, level = len(package), index
    return level


def floor_problems(sources: dict[str, str], floors=FLOORS) -> list[str]:
    """Every module without a floor and every import that goes up a floor, as text."""
    problems = [f"{name}: on no floor (add it to FLOORS)" for name in sources if floor_of(name, floors) is None]
    for name, text in sources.items():
        own = floor_of(name, floors)
        if own is None:
            continue
        for edge in edges(name, text, sources):
            target = floor_of(edge.target, floors)
            if target is not None and target > own:
                problems.append(f"{edge}: up from {floors[own][0]} to {floors[target][0]}")
    return problems


def test_every_module_imports_only_its_own_floor_or_lower():
    sources = {name: path.read_text(encoding="utf-8") for name, path in module_files().items()}
    problems = floor_problems(sources)
    assert not problems, "\n".join(problems)


def test_every_floor_holds_modules():
    floors = {floor_of(name) for name in module_files()}
    assert floors == set(range(len(FLOORS))), [FLOORS[i][0] for i in set(range(len(FLOORS))) - floors]


def test_the_floor_check_catches_every_kind_of_import_up():
    """A top-level, an in-function, a type-only and a lazy-table import up a floor are each caught; imports
    across one floor and down are not; a module on no floor is named."""
    sources = {
        "rvcoax.fem.a": "import rvcoax.geometry.b\n",
        "rvcoax.geometry.b": "from rvcoax.fem import a\nfrom rvcoax.loadcases.c import f\n"
                             "def g():\n    from rvcoax.results.sweep import run_sweep\n",
        "rvcoax.loadcases.c": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                              "    from rvcoax.geometry.model.d import X\n",
        "rvcoax.geometry.model.d": "",
        "rvcoax.results.sweep": "",
        "rvcoax.results.io": "from rvcoax._lazy import lazy_names\n"
                             "x = lazy_names(__name__, globals(), {'rvcoax.results.studies.e': ('E',)})\n",
        "rvcoax.results.studies.e": "from rvcoax.results.io import writers\n",
        "rvcoax.results.unplaced": "",
    }
    problems = floor_problems(sources)
    assert problems[0] == "rvcoax.results.unplaced: on no floor (add it to FLOORS)"
    assert sorted(p.split(": up")[0] for p in problems[1:]) == [
        "rvcoax.fem.a:1 → rvcoax.geometry.b (import)",
        "rvcoax.geometry.b:4 → rvcoax.results.sweep (function)",
        "rvcoax.loadcases.c:3 → rvcoax.geometry.model.d (type-checking)",
        "rvcoax.results.io:2 → rvcoax.results.studies.e (lazy)",
    ], problems
