"""A corpus of hostile command lines, one module per class of input (issue 12's classes).

Every module of this package defines ``CASES``, a list of :class:`Hostile`. A case builds its
input files in a folder and returns the ``rvcoax`` arguments; ``tests/test_hostile_corpus.py``
runs each through the real command line and asserts the exit status, that the message names the
file or option, the line or key, and the reason (``expected``), and that no traceback is printed.
A valid extreme input is a case too: it must either solve (exit 0) or be refused with an estimate.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

# the classes of issue 12 (the module that holds each class's cases has the same name)
CLASSES = ("markup", "parsers", "options", "numbers", "studies", "consistency", "sizes", "trust", "physics",
           "measured")


@dataclass(frozen=True)
class Hostile:
    """One hostile (or extreme but valid) command line.

    Attributes
    ----------
    name : str
        Unique test id.
    klass : str
        One of :data:`CLASSES`.
    argv : callable
        ``argv(folder) -> list[str]``: writes the input files into ``folder`` (an empty folder of its
        own) and returns the arguments after ``rvcoax``. Output folders go under ``folder`` too.
    expected : tuple of str
        Substrings that the message must contain (whitespace collapsed, case kept): the file or
        option, the line or key, and the reason.
    exit_code : int
        The documented exit status (2 for a user error, 0 for a valid input that must solve).
    env : mapping
        Environment variables set for the run.
    stream : str
        Where ``expected`` is looked for: ``stderr`` (errors, warnings) or ``output`` (both).
    check : callable or None
        ``check(folder, stdout, stderr)``: further assertions (files written or not), or None.
    """

    name: str
    klass: str
    argv: Callable[[Path], list[str]]
    expected: tuple[str, ...] = ()
    exit_code: int = 2
    env: Mapping[str, str] = field(default_factory=dict)
    stream: str = "stderr"
    check: Callable[[Path, str, str], None] | None = None


def all_cases() -> list[Hostile]:
    """The cases of every class module that exists (a class is added by adding its module)."""
    cases: list[Hostile] = []
    for klass in CLASSES:
        try:
            module = importlib.import_module(f"hostile.{klass}")
        except ModuleNotFoundError as error:
            if error.name != f"hostile.{klass}":
                raise
            continue
        for case in module.CASES:
            assert case.klass == klass, f"{case.name}: class {case.klass} in module {klass}"
            cases.append(case)
    return cases
