"""The rig's unit loads, as loads at rig locations (part, x) plus self-weight.

``gravity``        self-weight of every part (zero when switched off)
``prestrain``      the prestrain of misaligned couplings and raised mounts, K d0 (zero when aligned)
``force_table``    paper 000's force table as interpreted in the rig file (empty unless applied)
``engaged_T1``     the constant lateral loads present while T1 flows (the load-sharing position errors
                   of ``[[torque_lateral_loads]]``)
``engaged_T2``     the same for T2
``T1``, ``T2``     a unit torque (1 N·m) with its torque-proportional lateral loads
``gear_contact_T1`` the constant part of the ``[[gear_meshes]]`` forces on T1 (their position errors),
                   weighted by clip(T1 / T_c, −1, 1) with T_c the stage's full-contact torque
                   (:func:`rvcoax.geometry.gear_loads.gear_contact_torques`): below T_c a planet mesh is open and carries nothing
``gear_contact_T2`` the same for T2

A model turns each :class:`LocatedLoad` into a load vector: nodal forces on a beam part, a face
traction on a solid part. For a linear model the response to (T1, T2) is
``u = u_rest + sign(T1) u_engaged_T1 + sign(T2) u_engaged_T2 + T1 u_T1 + T2 u_T2
+ clip(T1/T_c1, −1, 1) u_gear_contact_T1 + clip(T2/T_c2, −1, 1) u_gear_contact_T2`` with
``u_rest = u_gravity + u_prestrain + u_force_table``. Prestrain is not a located load: it is built
from the bushings where they are assembled (:func:`rvcoax.fem.pieces.prestrain_contribution`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# the gear-mesh forces are rig physics, one floor down; listed here too, where the unit loads use them
from rvcoax.geometry.gear_loads import gear_contact_torques, gear_mesh_forces, gear_mesh_full_contact_torque
from rvcoax.geometry.schema import Rig

__all__ = ["GRAVITY_DIRECTION", "LocatedLoad", "REST_LOADS", "UNIT_LOADS", "case_weights", "force_table_loads",
           "gear_contact_torques", "gear_contact_weight", "gear_mesh_forces", "gear_mesh_full_contact_torque",
           "gravity_acceleration", "located_unit_loads", "superpose", "torque_loads"]

UNIT_LOADS = ("gravity", "prestrain", "force_table", "engaged_T1", "engaged_T2", "T1", "T2",
              "gear_contact_T1", "gear_contact_T2")
REST_LOADS = ("gravity", "prestrain", "force_table")


@dataclass(frozen=True)
class LocatedLoad:
    """A force (N) and moment (N·m), global axes, acting on ``part`` at axial position ``x_mm``."""

    part: str
    x_mm: float
    force_N: tuple[float, float, float]
    moment_Nm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    band_mm: tuple[float, float] | None = None


def _direction(direction_deg: float) -> np.ndarray:
    """Unit vector in the YZ plane at ``direction_deg`` from +Y towards +Z."""
    a = math.radians(direction_deg)
    return np.array([0.0, math.cos(a), math.sin(a)])


def _lateral_loads(rig: Rig, which: str, part: str) -> list[LocatedLoad]:
    """The lateral force pairs tied to torque ``which``: ``proportional`` (per N·m, with the gear meshes') or
    ``engaged`` (of ``[[torque_lateral_loads]]`` only: the gear meshes' constant part is ``gear_contact_*``)."""
    out = []
    for lateral in rig.torque_lateral_loads:
        if lateral.torque != which:
            continue
        size = lateral.force_per_torque_N_per_Nm if part == "proportional" else lateral.engaged_force_N
        force = size * _direction(lateral.direction_deg)
        out.append(LocatedLoad(lateral.on.part, lateral.on.x_mm, tuple(force), band_mm=lateral.on.band_mm))
        if lateral.reacted_on is not None:
            reacted = lateral.reacted_on
            out.append(LocatedLoad(reacted.part, reacted.x_mm, tuple(-force), band_mm=reacted.band_mm))
    return (out + _gear_mesh_loads(rig, which, part)) if part == "proportional" else out


def gear_contact_weight(torque_Nm: float, contact_torque_Nm: float) -> float:
    """The weight of a ``gear_contact_*`` unit load: clip(T / T_c, −1, 1), sign(T) when T_c = 0.

    Two meshes on a rigid sun carry W_i = s_i F + c_i (F = T / r_b, Σ c_i = 0) while both touch; below
    F_c = −c_o / s_o the lagging mesh o is open and the other carries all of F. That is
    W_i = s_i F + c_i F / F_c (W_o = F (s_o + c_o/F_c) = 0, W_j = F (s_j − c_o/F_c) = F): the constant
    part scaled by F / F_c = T / T_c, continuous at T_c and odd in T.
    """
    if contact_torque_Nm > 0.0:
        return float(np.clip(torque_Nm / contact_torque_Nm, -1.0, 1.0))
    return float(np.sign(torque_Nm))


def _gear_mesh_loads(rig: Rig, which: str, part: str) -> list[LocatedLoad]:
    """The net mesh forces of the ``[[gear_meshes]]`` on ``which``: on the driving gear and, reversed, on the case."""
    out = []
    for mesh in rig.gear_meshes:
        if mesh.torque != which:
            continue
        per_torque, engaged, _ = gear_mesh_forces(rig, mesh)
        forces = per_torque if part == "proportional" else engaged
        force, moment = tuple(forces.force_N.tolist()), tuple(forces.moment_Nm.tolist())
        out.append(LocatedLoad(mesh.on.part, mesh.on.x_mm, force, moment, band_mm=mesh.on.band_mm))
        out.append(LocatedLoad(mesh.reacted_on.part, mesh.reacted_on.x_mm, tuple(-np.array(force)),
                               tuple(-np.array(moment)), band_mm=mesh.reacted_on.band_mm))
    return out


def torque_loads(rig: Rig, which: str) -> list[LocatedLoad]:
    """A unit torque (1 N·m) T1 or T2 about +x (times its sign), the opposite one on its ``reacted_on`` stator
    where given, with its proportional lateral loads."""
    torque = getattr(rig.torques, which)
    loads = [LocatedLoad(torque.part, torque.x_mm, (0.0, 0.0, 0.0), (float(torque.sign), 0.0, 0.0))]
    if torque.reacted_on is not None:  # the stator's reaction: the opposite torque on the motor's or brake's housing
        stator = torque.reacted_on
        loads.append(LocatedLoad(stator.part, stator.x_mm, (0.0, 0.0, 0.0), (-float(torque.sign), 0.0, 0.0),
                                 band_mm=stator.band_mm))
    return [*loads, *_lateral_loads(rig, which, "proportional")]


def force_table_loads(rig: Rig) -> list[LocatedLoad]:
    """Paper 000's force pairs and single forces as Y forces, as interpreted in the rig file, times ``scale``."""
    table = rig.force_table
    if not table.apply:
        return []
    out = []
    for pair in table.pairs:
        size = table.scale * pair.force_N
        out.append(LocatedLoad(pair.plus_at.part, pair.plus_at.x_mm, (0.0, size, 0.0)))
        out.append(LocatedLoad(pair.minus_at.part, pair.minus_at.x_mm, (0.0, -size, 0.0)))
    for single in table.singles:
        out.append(LocatedLoad(single.at.part, single.at.x_mm, (0.0, table.scale * single.force_N, 0.0)))
    return out


def located_unit_loads(rig: Rig) -> dict[str, list[LocatedLoad]]:
    """Every unit load except self-weight and prestrain, as located loads (those two are built with the model)."""
    return {
        "gravity": [],
        "prestrain": [],
        "force_table": force_table_loads(rig),
        "engaged_T1": _lateral_loads(rig, "T1", "engaged"),
        "engaged_T2": _lateral_loads(rig, "T2", "engaged"),
        "T1": torque_loads(rig, "T1"),
        "T2": torque_loads(rig, "T2"),
        "gear_contact_T1": _gear_mesh_loads(rig, "T1", "engaged"),
        "gear_contact_T2": _gear_mesh_loads(rig, "T2", "engaged"),
    }


GRAVITY_DIRECTION = np.array([0.0, -1.0, 0.0])
"""Gravity acts along −Y."""


def gravity_acceleration(rig: Rig) -> float:
    """Size of the acceleration of gravity (m/s²); zero when self-weight is off."""
    return rig.gravity.acceleration_m_per_s2 if rig.gravity.enabled else 0.0


def case_weights(input_torque_Nm: float, output_torque_Nm: float, include_rest: bool,
                 contact_torques_Nm: tuple[float, float] = (0.0, 0.0)) -> dict[str, float]:
    """Multipliers of the unit loads for one case; ``include_rest`` adds self-weight, prestrain and force table.

    ``contact_torques_Nm`` is the rig's (T_c1, T_c2) (:func:`gear_contact_torques`); the default (0, 0),
    every gear mesh in contact at any torque, is exact for a rig without gear meshes or position errors.
    """
    rest = 1.0 if include_rest else 0.0
    contact_1, contact_2 = contact_torques_Nm
    return {
        "gravity": rest,
        "prestrain": rest,
        "force_table": rest,
        "engaged_T1": float(np.sign(input_torque_Nm)),
        "engaged_T2": float(np.sign(output_torque_Nm)),
        "T1": float(input_torque_Nm),
        "T2": float(output_torque_Nm),
        "gear_contact_T1": gear_contact_weight(input_torque_Nm, contact_1),
        "gear_contact_T2": gear_contact_weight(output_torque_Nm, contact_2),
    }


def superpose(unit_responses: dict[str, np.ndarray], input_torque_Nm: float, output_torque_Nm: float,
              from_rest: bool, contact_torques_Nm: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """The response of a linear model to the case (T1, T2), from its responses to the unit loads.

    Parameters
    ----------
    unit_responses : dict
        The response to each load of :data:`UNIT_LOADS`, by name (arrays of one shape).
    input_torque_Nm, output_torque_Nm : float
        The case's torques, N·m.
    from_rest : bool
        Subtract ``u_rest`` (Y measured from the aligned rig at rest) instead of returning ``u``.
    contact_torques_Nm : (float, float)
        The rig's gear-mesh full-contact torques (:func:`gear_contact_torques`).
    """
    weights = case_weights(input_torque_Nm, output_torque_Nm, include_rest=True, contact_torques_Nm=contact_torques_Nm)
    response = sum(weights[k] * unit_responses[k] for k in UNIT_LOADS)
    return response - sum(unit_responses[k] for k in REST_LOADS) if from_rest else response
