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

# the classes of issue 12 (the module that holds each class's cases has the same name), then those of issue 24,
# part 5 (data loss and trust, exports, tracebacks, hangs, silent accepts, unclear messages, processes)
CLASSES = ("markup", "parsers", "options", "numbers", "studies", "consistency", "sizes", "trust", "physics",
           "measured", "data_loss", "exports", "tracebacks", "hangs", "silent", "messages", "processes")


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
    patch : callable or None
        ``patch(folder, monkeypatch)`` before the run: what an argv cannot set up (an environment variable that
        names a file of the case, a failing ``os.fsync`` standing in for a full disk), or None.
    stdout_to : str or None
        Run the installed ``rvcoax`` as a real process with its standard output sent to this file (``/dev/full``)
        instead of in-process; None for the in-process run.
    """

    name: str
    klass: str
    argv: Callable[[Path], list[str]]
    expected: tuple[str, ...] = ()
    exit_code: int = 2
    env: Mapping[str, str] = field(default_factory=dict)
    stream: str = "stderr"
    check: Callable[[Path, str, str], None] | None = None
    patch: Callable[[Path, object], None] | None = None
    stdout_to: str | None = None


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
