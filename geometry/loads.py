"""The rig's unit load vectors.

``gravity``        self-weight of every part (zero when switched off)
``force_table``    paper 000's force table as interpreted in the rig file (zero unless applied)
``engaged_T1``     the constant lateral loads present while T1 flows (load-sharing position errors)
``engaged_T2``     the same for T2
``T1``, ``T2``     a unit torque (1 N·m) with its torque-proportional lateral loads

For a linear model the response to (T1, T2) is
``u = u_rest + sign(T1) u_engaged_T1 + sign(T2) u_engaged_T2 + T1 u_T1 + T2 u_T2`` with
``u_rest = u_gravity + u_force_table``.
"""

from __future__ import annotations

import math

import numpy as np

from fem.loads import NodalLoads, nodal_load_vector
from fem.model import gravity_load_vector
from geometry.build import RigModel

UNIT_LOADS = ("gravity", "force_table", "engaged_T1", "engaged_T2", "T1", "T2")
REST_LOADS = ("gravity", "force_table")


def _direction(direction_deg: float) -> np.ndarray:
    """Unit vector in the YZ plane at ``direction_deg`` from +Y towards +Z."""
    a = math.radians(direction_deg)
    return np.array([0.0, math.cos(a), math.sin(a)])


def _lateral_pairs(model: RigModel, which: str, part: str) -> tuple[list[int], list[list[float]]]:
    """Nodes and force components of the lateral loads tied to torque ``which``.

    ``part`` is ``"proportional"`` (per N·m) or ``"engaged"`` (the constant part).
    """
    nodes, components = [], []
    for lateral in model.rig.torque_lateral_loads:
        if lateral.torque != which:
            continue
        size = lateral.force_per_torque_N_per_Nm if part == "proportional" else lateral.engaged_force_N
        force = size * _direction(lateral.direction_deg)
        nodes.append(model.node(lateral.on.part, lateral.on.x_mm))
        components.append([*force, 0.0, 0.0, 0.0])
        if lateral.reacted_on is not None:
            nodes.append(model.node(lateral.reacted_on.part, lateral.reacted_on.x_mm))
            components.append([*(-force), 0.0, 0.0, 0.0])
    return nodes, components


def _vector(model: RigModel, nodes, components) -> np.ndarray:
    if not nodes:
        return np.zeros(model.structure.n_dofs)
    return nodal_load_vector(NodalLoads(np.array(nodes, int), np.array(components, float)), model.structure.n_dofs)


def torque_load_vector(model: RigModel, which: str) -> np.ndarray:
    """Load vector of a unit torque (1 N·m) T1 or T2, with its proportional lateral loads."""
    torque = getattr(model.rig.torques, which)
    nodes, components = _lateral_pairs(model, which, "proportional")
    nodes.insert(0, model.node(torque.part, torque.x_mm))
    components.insert(0, [0.0, 0.0, 0.0, float(torque.sign), 0.0, 0.0])
    return _vector(model, nodes, components)


def engaged_load_vector(model: RigModel, which: str) -> np.ndarray:
    """Constant lateral loads present while torque ``which`` flows."""
    return _vector(model, *_lateral_pairs(model, which, "engaged"))


def force_table_vector(model: RigModel) -> np.ndarray:
    """The paper's force pairs and single forces as Y forces, as interpreted in the rig file."""
    table = model.rig.force_table
    nodes, components = [], []
    for pair in table.pairs:
        for where, sign in ((pair.plus_at, 1.0), (pair.minus_at, -1.0)):
            nodes.append(model.node(where.part, where.x_mm))
            components.append([0.0, sign * pair.force_N, 0.0, 0.0, 0.0, 0.0])
    for single in table.singles:
        nodes.append(model.node(single.at.part, single.at.x_mm))
        components.append([0.0, single.force_N, 0.0, 0.0, 0.0, 0.0])
    return _vector(model, nodes, components)


def unit_load_vectors(model: RigModel) -> dict[str, np.ndarray]:
    """All unit load vectors, keyed as in :data:`UNIT_LOADS`."""
    rig = model.rig
    n = model.structure.n_dofs
    gravity = (gravity_load_vector(model.structure, [0.0, -rig.gravity.acceleration_m_per_s2, 0.0])
               if rig.gravity.enabled else np.zeros(n))
    return {
        "gravity": gravity,
        "force_table": force_table_vector(model) if rig.force_table.apply else np.zeros(n),
        "engaged_T1": engaged_load_vector(model, "T1"),
        "engaged_T2": engaged_load_vector(model, "T2"),
        "T1": torque_load_vector(model, "T1"),
        "T2": torque_load_vector(model, "T2"),
    }


def case_weights(input_torque_Nm: float, output_torque_Nm: float, include_rest: bool) -> dict[str, float]:
    """Multipliers of the unit loads for one case; ``include_rest`` adds self-weight and force table."""
    rest = 1.0 if include_rest else 0.0
    return {
        "gravity": rest,
        "force_table": rest,
        "engaged_T1": float(np.sign(input_torque_Nm)),
        "engaged_T2": float(np.sign(output_torque_Nm)),
        "T1": float(input_torque_Nm),
        "T2": float(output_torque_Nm),
    }
