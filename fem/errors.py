"""The errors rvcoax raises on purpose, and those of the finite-element core.

Every error rvcoax raises for a reason a user can act on derives from :class:`RvcoaxError`; the
command line turns any of them into one paragraph and exit status 2, and a script can catch them
all with one clause. Each error still derives from the built-in class it always had
(``ValueError`` for bad input, ``RuntimeError`` for a model or solver that fails), so code that
caught those keeps working.
"""

from __future__ import annotations

__all__ = ["GapConvergenceError", "PardisoError", "RvcoaxError", "SingularMatrixError", "SingularModelError",
           "SolverError"]


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


class SingularModelError(RvcoaxError, RuntimeError):
    """The stiffness matrix is singular: some part can move without deforming anything."""

    stage = "cannot solve the rig"


class SolverError(RvcoaxError, RuntimeError):
    """A linear solve failed (iterative solver did not converge, bad input, solver library error)."""

    stage = "the solver failed"


class SingularMatrixError(SolverError, SingularModelError):
    """A direct factorisation found the matrix singular (a part can move without deforming)."""

    stage = SolverError.stage


class PardisoError(RvcoaxError, RuntimeError):
    """PARDISO returned an error code.

    ``code`` is that code, ``phase`` the step that failed (``"analysis"``, ``"factorisation"``,
    ``"solve"``, ``"release"``) and ``equation`` the failing unknown or None.
    """

    stage = "the solver failed"

    def __init__(self, code: int, phase: str, equation: int | None = None, message: str = ""):
        self.code, self.phase, self.equation = code, phase, equation
        super().__init__(message or f"PARDISO {phase} failed with error {code}",
                         where=None if equation is None else f"equation {equation}")


class GapConvergenceError(RvcoaxError, RuntimeError):
    """The clearance iteration did not converge."""

    stage = "cannot solve the rig"
