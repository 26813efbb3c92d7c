"""The errors of the finite-element core: a singular model, a failed solve, PARDISO, a bearing gap that does not
converge. They derive from :class:`rvcoax.errors.RvcoaxError`, the base of every error rvcoax raises on purpose
(also found here, where it was first defined).
"""

from __future__ import annotations

from rvcoax.errors import RvcoaxError

__all__ = ["GapConvergenceError", "PardisoError", "RvcoaxError", "SingularMatrixError", "SingularModelError",
           "SolverError"]


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
