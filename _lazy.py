"""Lazy public names for the packages' ``__init__`` modules (PEP 562).

A package lists its public names by the module that defines them; a name is imported from its
module on first use and kept. ``import rvcoax`` or ``import rvcoax.results.studies`` thus costs
nothing, and the command line starts without numpy, scipy or the model.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping

__all__ = ["lazy_names"]


def lazy_names(package: str, namespace: dict, modules: Mapping[str, tuple[str, ...]], eager: tuple[str, ...] = (),
               moved: Mapping[str, tuple[str, ...]] | None = None
               ) -> tuple[dict[str, str], list[str], Callable[[str], object], Callable[[], list[str]]]:
    """The public names of a package whose names load on use, and the ``__getattr__``/``__dir__`` that load them.

    Parameters
    ----------
    package
        The package's ``__name__`` (for the error message).
    namespace
        The package's ``globals()``: a loaded name is stored there, so it is looked up only once.
    modules
        The full name of each module → the public names it defines, in the order they are listed.
    eager
        Public names the package defines itself (listed first in ``__all__``).
    moved
        Names that moved to another package (the full name of their module → the names): still found here on
        use, so that existing imports keep working, but not listed in ``__all__`` nor in ``_WHERE``.

    Returns
    -------
    tuple
        ``(_WHERE, __all__, __getattr__, __dir__)`` for the package's ``__init__``: ``_WHERE`` maps every
        lazy name to its module.
    """
    where = {name: module for module, names in modules.items() for name in names}
    found = {**{name: module for module, names in (moved or {}).items() for name in names}, **where}

    def __getattr__(name: str):
        try:
            module = found[name]
        except KeyError:
            raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
        value = getattr(importlib.import_module(module), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(where))

    return where, [*eager, *where], __getattr__, __dir__
