"""The base of every error rvcoax raises on purpose, and the one form of an input file's error message.

Every error rvcoax raises for a reason a user can act on derives from :class:`RvcoaxError`; the
command line turns any of them into one paragraph and exit status 2, and a script can catch them
all with one clause. Each error still derives from the built-in class it always had
(``ValueError`` for bad input, ``RuntimeError`` for a model or solver that fails), so code that
caught those keeps working.

An input file that cannot be used says so in one form (:func:`problems_text`): the file, then every
key (or line) with its reason. Its errors derive from :class:`InputFileProblems`.
"""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["InputFileProblems", "RvcoaxError", "problems_text"]


class RvcoaxError(Exception):
    """Base of every error rvcoax raises on purpose.

    Attributes
    ----------
    stage : str
        The step of the work that failed, in the user's words (class attribute), e.g. ``"solving
        the rig"``; empty for errors whose message already says everything (bad input files).
    where : str or None
        The file, option, key, part or equation where it happened, when the raiser knows it.
    """

    stage = ""

    def __init__(self, *args, where: str | None = None):
        super().__init__(*args)
        self.where = where

    def describe(self, subject: str | None = None) -> str:
        """One paragraph for a user: ``"<subject>: <stage>: <message>"``, leaving out what is empty."""
        parts = [part for part in (subject if self.stage else None, self.stage, str(self)) if part]
        return ": ".join(parts)


def problems_text(what: str, source: str, problems: Sequence[str]) -> str:
    """The message of an input file that cannot be used: ``"<what> <source>: N problem(s):"`` and one
    ``"  - <key>: <reason>"`` line per problem.

    Parameters
    ----------
    what : str
        What the file is (``"rig file"``, ``"tolerance file"``).
    source : str
        The file as the user named it.
    problems : sequence of str
        Each problem, naming its key or line first.

    Returns
    -------
    str
        The message.
    """
    listing = "\n".join(f"  - {p}" for p in problems)
    return f"{what} {source}: {len(problems)} problem(s):\n{listing}"


class InputFileProblems(RvcoaxError, ValueError):
    """An input file that cannot be used; the message (:func:`problems_text`) names the file, each key and reason.

    Attributes
    ----------
    what : str
        What the file is, for the message (class attribute).
    source : str
        The file.
    problems : list of str
        Each problem, key or line first.
    """

    what = "input file"

    def __init__(self, source: str, problems: Sequence[str]):
        self.source = source
        self.problems = list(problems)
        super().__init__(problems_text(self.what, source, self.problems), where=source)
