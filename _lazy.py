"""Lazy public names for the packages' ``__init__`` modules (PEP 562).

A package lists its public names in a table, name → the module that defines it; a name is imported
from its module on first use and kept. ``import rvcoax`` or ``import rvcoax.results.studies`` thus
costs nothing, and the command line starts without numpy, scipy or the model.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping

__all__ = ["lazy_names"]


def lazy_names(package: str, where: Mapping[str, str],
               namespace: dict) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """The module-level ``__getattr__`` and ``__dir__`` of a package whose public names load on use.

    Parameters
    ----------
    package
        The package's ``__name__`` (for the error message).
    where
        Public name → the full name of the module that defines it.
    namespace
        The package's ``globals()``: a loaded name is stored there, so it is looked up only once.

    Returns
    -------
    tuple
        ``(__getattr__, __dir__)`` to assign in the package's ``__init__``.
    """

    def __getattr__(name: str):
        try:
            module = where[name]
        except KeyError:
            raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
        value = getattr(importlib.import_module(module), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(where))

    return __getattr__, __dir__
