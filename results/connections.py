"""Relative motion and force of the rig's springs in every load case of a sweep.

The spring-state operator (the springs' rigid-arm operators, stiffnesses and stress-free motions, and what
deformation and force mean in each reference) is :mod:`rvcoax.geometry.model.springs`; here it is applied to
the displacements of a solved sweep's cases. For a coupling the deformation is its misalignment: parallel
offset (translation in y and z) and angle (rotation about y and z) of the ``to`` hub relative to the
``from`` hub at the coupling centre. For a bearing, −diag(k) × deformation is the reaction the bearing
exerts on its shaft.

The displacements of a case are rebuilt from the sweep's unit responses,
u = Σ_k w_k u_k (:func:`rvcoax.geometry.model.loads.case_weights`); with ``method="direct"`` the sweep solved
each case on its own, which agrees with this superposition to solver precision.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from rvcoax.errors import RvcoaxError
from rvcoax.geometry.model.loads import UNIT_LOADS, case_weights, gear_contact_torques
from rvcoax.geometry.model.springs import ConnectionStates, spring_states, with_nonlinear_laws

if TYPE_CHECKING:  # the sweep is the floor below; it never imports this module
    from rvcoax.results.sweep import Sweep

__all__ = ["ConnectionsUnavailableError", "REFERENCES", "case_displacements", "connection_states"]

REFERENCES = ("measured", "unloaded")
"""``measured``: from the state the rig's ``[paths] measured_from`` names (the aligned rig at rest by
default, u − u_rest), as Y and β are; ``unloaded``: from the unloaded geometry (u, self-weight included)."""


class ConnectionsUnavailableError(RvcoaxError, ValueError):
    """The sweep cannot give per-case spring states (the message says why)."""


def _from_rest(sweep: Sweep, reference: str) -> bool:
    if reference not in REFERENCES:
        raise ValueError(f"reference must be one of {', '.join(REFERENCES)}, got {reference!r}")
    return reference == "measured" and sweep.rig.paths.measured_from == "aligned_at_rest"


def case_displacements(sweep: Sweep, reference: str = "measured") -> np.ndarray:
    """Displacement vectors of every case, (n_dofs, n_cases), from ``reference`` (see :data:`REFERENCES`).

    A linear sweep superposes its unit responses; a nonlinear one (bearings with radial clearance or
    ball bearings from geometry, solved case by case) holds each case's displacement as measured and
    the rest state."""
    from_rest = _from_rest(sweep, reference)
    if sweep.unit_displacements is None:
        if sweep.case_displacements is None or sweep.rest_displacement is None:
            raise ConnectionsUnavailableError(
                "spring forces and coupling misalignments need the sweep's unit responses (a linear model) or, "
                "for bearings with radial clearance or ball bearings from geometry (nonlinear), each case's "
                "displacement and the rest state; this sweep holds neither")
        measured = np.asarray(sweep.case_displacements, dtype=float)
        if sweep.rig.paths.measured_from == "aligned_at_rest" and not from_rest:
            return measured + np.asarray(sweep.rest_displacement, dtype=float)[:, None]
        return measured
    unit = np.asarray(sweep.unit_displacements)
    contact = gear_contact_torques(sweep.rig)
    weights = np.array([[case_weights(c.case.input_torque_Nm, c.case.output_torque_Nm, include_rest=not from_rest,
                                      contact_torques_Nm=contact)[k] for k in UNIT_LOADS] for c in sweep.cases])
    return unit @ weights.T


def connection_states(sweep: Sweep, reference: str = "measured") -> ConnectionStates:
    """Relative motion and force of every spring of the sweep's rig in every case.

    In a nonlinear sweep each bearing with radial clearance or from ball geometry exerts its own law
    F(Δ) at the case's converged state (:meth:`rvcoax.geometry.model.nonlinear_bearings.NonlinearBearings.laws`),
    −F(Δ) on its shaft from the unloaded geometry and −(F(Δ) − F(Δ_rest)) from rest, and its operating
    stiffness is the tangent ∂F/∂Δ there; every other spring is linear."""
    from_rest = _from_rest(sweep, reference)
    states = spring_states(sweep.frame, sweep.rig, case_displacements(sweep, reference), from_rest=from_rest)
    law = sweep.nonlinear_bearings
    if law is None:
        return states
    rest = np.asarray(sweep.rest_displacement, dtype=float) if from_rest else None
    return with_nonlinear_laws(states, law, case_displacements(sweep, "unloaded"), rest)
