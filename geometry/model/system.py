"""The assembled system of a rig, whatever its fidelity: stiffness, constraints, unit loads, probes.

:func:`rvcoax.geometry.model.assemble.assemble_rig` returns a :class:`RigSystem` for ``kind`` = ``beam`` (every part a
line of Timoshenko beams), ``hybrid`` (the parts named in ``[solid] hybrid_parts`` as quadratic
tetrahedra, the rest beams) or ``solid`` (every part a solid). Everything downstream (sweep,
results, check) works on a RigSystem only.

DOF layout: first the frame (six DOFs per frame node: beam nodes, and reference nodes where
something attaches to a solid), then each solid part's block of three DOFs per P2 node.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.equilibrium import DofTable, frame_dof_table
from rvcoax.fem.loads import NodalLoads
from rvcoax.fem.pieces import (
    Contribution,
    assemble,
    dense_load_contribution,
    frame_contributions,
    load_vectors,
    nodal_load_contribution,
)
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model.beam import RigModel, build_rig_model, prestrain_contributions
from rvcoax.geometry.model.housings import housing_contributions, housing_prestrain
from rvcoax.geometry.model.loads import (
    GRAVITY_DIRECTION,
    UNIT_LOADS,
    LocatedLoad,
    gravity_acceleration,
    located_unit_loads,
)
from rvcoax.geometry.schema import Rig

__all__ = ["MODEL_KINDS", "PathProbe", "RigSystem", "UnitLoadBuilder", "assemble_beam", "beam_contributions", "frame_path_probe",
           "located_contribution"]

MODEL_KINDS = ("beam", "hybrid", "solid")
"""The models a rig can be solved with: beams only, beams with solid parts, or solids wherever meshed."""


@dataclass(frozen=True, eq=False)
class PathProbe:
    """Reads a measured shaft path from a displacement vector.

    ``uy`` and ``rotation_z`` are sparse (n_stations × n_dofs) operators giving u_y (m) and the
    section rotation about z (rad) at each station; ``stations_mm`` run from 0 to L.
    """

    stations_mm: np.ndarray
    length_mm: float
    uy: sp.csr_matrix
    rotation_z: sp.csr_matrix


@dataclass(frozen=True, eq=False)
class RigSystem:
    """A rig's model ready to solve.

    Attributes
    ----------
    rig : Rig
    kind : str
    frame : RigModel
        Beam nodes and reference nodes with bushings, point masses, fixed DOFs.
    stiffness, elimination : csr_matrix
        K (n × n) and T (u = T q).
    unit_loads : dict
        One load vector per name in :data:`rvcoax.geometry.model.loads.UNIT_LOADS`.
    probes : dict
        ``"input"`` / ``"output"`` → :class:`PathProbe`.
    dofs : DofTable
        Position and component of every DOF (for equilibrium).
    solids : tuple
        Solid parts (for field output); empty for the beam model.
    load_builder : UnitLoadBuilder
        Rebuilds ``unit_loads`` for a rig that differs from ``rig`` in load parameters only.
    """

    rig: Rig
    kind: str
    frame: RigModel
    stiffness: sp.csr_matrix
    elimination: sp.csr_matrix
    unit_loads: dict
    probes: dict
    dofs: DofTable
    solids: tuple = field(default_factory=tuple)
    load_builder: UnitLoadBuilder | None = None

    @property
    def n_dofs(self) -> int:
        return int(self.stiffness.shape[0])

    def with_loads_of(self, rig: Rig) -> RigSystem:
        """The same structure with the unit loads of ``rig``, whose structure must be this one's.

        Used when only load parameters change (calibration of load-sharing parameters; gravity,
        force-table scale, coupling and mount offsets), so that the mesh, the stiffness and its
        factorisation are reused.
        """
        return dataclasses.replace(self, rig=rig, unit_loads=self.load_builder(rig))


@dataclass(frozen=True, eq=False)
class UnitLoadBuilder:
    """The unit loads of a rig on an assembled structure, rebuilt when only load parameters change.

    Attributes
    ----------
    frame : RigModel
        Where located loads and the springs' prestrain act.
    n_dofs : int
        Length of every load vector.
    weight_per_g : ndarray
        The model's weight per m/s² of acceleration along gravity (every piece's ``"gravity"`` load).
    solid_loads : SolidLoads or None
        Turns loads on solid parts into face tractions (hybrid and solid models); None for beams.
    """

    frame: RigModel
    n_dofs: int
    weight_per_g: np.ndarray
    solid_loads: object | None = None

    def __call__(self, rig: Rig) -> dict:
        """One load vector per name in :data:`UNIT_LOADS`, for the loads of ``rig``: every load a
        :class:`rvcoax.fem.pieces.Contribution`, summed by :func:`rvcoax.fem.pieces.load_vectors`."""
        located = located_unit_loads(rig)
        pieces = []
        for name in UNIT_LOADS:
            if self.solid_loads is None:
                pieces.append(located_contribution(self.frame, name, located[name]))
            else:
                pieces += self.solid_loads.contributions(self.frame, name, located[name])
        pieces.append(dense_load_contribution("gravity", gravity_acceleration(rig) * self.weight_per_g))
        pieces += prestrain_contributions(self.frame, rig)  # springs and beams act on frame nodes
        if rig.thermal is not None and rig.housings:
            pieces.append(housing_prestrain(rig, self.frame, self.n_dofs))
        if self.solid_loads is not None and rig.thermal is not None:
            pieces += self.solid_loads.thermal_contributions(rig)
        vectors = load_vectors(self.n_dofs, pieces)
        return {name: vectors[name] if name in vectors else np.zeros(self.n_dofs) for name in UNIT_LOADS}


def located_contribution(frame: RigModel, name: str, loads: list[LocatedLoad]) -> Contribution:
    """Located loads on frame parts as the nodal entries of load ``name``."""
    nodes = np.array([frame.node(load.part, load.x_mm) for load in loads], dtype=int)
    components = np.array([[*load.force_N, *load.moment_Nm] for load in loads], dtype=float).reshape(-1, 6)
    return nodal_load_contribution(name, NodalLoads(nodes, components))


def frame_path_probe(frame: RigModel, which: str, n_dofs: int) -> PathProbe:
    """Path probe reading the beam nodes of a frame part."""
    nodes, stations = frame.path_nodes(which)
    rows = np.arange(nodes.size)

    def pick(component: int) -> sp.csr_matrix:
        return sp.csr_matrix((np.ones(nodes.size), (rows, DOFS_PER_NODE * nodes + component)), shape=(nodes.size, n_dofs))

    return PathProbe(stations, getattr(frame.rig.paths, which).length_mm, pick(1), pick(5))


def beam_contributions(rig: Rig, frame: RigModel) -> list[Contribution]:
    """Every piece of the beam model of ``rig`` on ``frame``: the frame's (beams, springs, point masses, constraints;
    weight per m/s² along gravity) and each ``[[housings]]`` entry's condensed stiffness and weight."""
    return frame_contributions(frame.structure, GRAVITY_DIRECTION) + housing_contributions(rig, frame)


def assemble_beam(rig: Rig) -> RigSystem:
    """The beam model of a rig as a :class:`RigSystem`: every piece of the frame through :func:`rvcoax.fem.pieces.assemble`."""
    frame = build_rig_model(rig)
    structure = frame.structure
    n = structure.n_dofs
    assembled = assemble(n, beam_contributions(rig, frame))
    loads = UnitLoadBuilder(frame, n, assembled.loads["gravity"])
    probes = {which: frame_path_probe(frame, which, n) for which in MEASURED_SHAFTS}
    return RigSystem(rig=rig, kind="beam", frame=frame, stiffness=assembled.stiffness, elimination=assembled.elimination,
                     unit_loads=loads(rig), probes=probes, dofs=frame_dof_table(structure.coordinates),
                     load_builder=loads)
