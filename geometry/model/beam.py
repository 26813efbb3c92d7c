"""Rig → beam model: nodes on the axis, Timoshenko beams, bushings, point masses.

Every part becomes a line of nodes on the drivetrain axis (y = z = 0) at its segment ends, at
every position something attaches, at the path stations, and in between at most
``mesh.max_element_length_mm`` apart. Parts overlapping in x are separate node lines joined only
by the springs the rig file declares.
"""

from __future__ import annotations

import bisect
import itertools
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rvcoax.fem.beam import BeamElements
from rvcoax.fem.bushing import GROUND, Bushings
from rvcoax.fem.loads import PointMasses
from rvcoax.fem.model import StructuralModel
from rvcoax.fem.pieces import Contribution, dense_load_contribution, prestrain_contribution
from rvcoax.fem.sections import CircularSection
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.schema import Rig
from rvcoax.geometry.thermal import beam_thermal_load, thermal_stress_free_motions
from rvcoax.geometry.units import MM

__all__ = ["FrameMasses", "FrameNodes", "FrameSprings", "SpringId", "MM", "MRAD", "NODE_MERGE_MM", "N_PER_MM", "N_PER_UM",
           "RigModel", "UM", "attachment_positions", "build_rig_model", "frame_beams", "frame_masses", "frame_nodes",
           "frame_springs", "housing_bed_group", "prestrain_contributions", "stress_free_motions"]

N_PER_UM = 1e6  # N/µm → N/m
N_PER_MM = 1e3  # N/mm → N/m
# Positions on one part closer than this (mm) share a node: a shorter beam element would be so stiff next to
# its neighbours that the stiffness loses its digits (a bearing 8 nm from a segment end: condition number ×1e3)
NODE_MERGE_MM = 1e-3
UM = 1e-6
MRAD = 1e-3


class SpringId(NamedTuple):
    """Which rig item a spring of the frame model is: its kind (bearing, mount, coupling, joint) and its name."""

    kind: str
    name: str

    def __str__(self) -> str:
        return f"{self.kind}:{self.name}"


@dataclass(frozen=True, eq=False)
class RigModel:
    """A rig's beam model and the maps from rig names to model entities.

    Attributes
    ----------
    rig : Rig
    structure : StructuralModel
    node_part : (n,) array of str
    node_x_mm : (n,) array
    bushing_names : tuple of SpringId
        ``"<kind>:<name>"`` of each bushing row (bearing, mount, coupling, joint).
    part_mass_kg : dict
        Mass of each part as modelled (beams plus the coupling hubs it carries).
    equivalent_density : dict
        Density used for each body (kg/m³).
    """

    rig: Rig
    structure: StructuralModel
    node_part: np.ndarray
    node_x_mm: np.ndarray
    bushing_names: tuple[SpringId, ...]
    part_mass_kg: dict
    equivalent_density: dict

    def node(self, part: str, x_mm: float) -> int:
        """The node of ``part`` at ``x_mm`` (every referenced position is a node, within :data:`NODE_MERGE_MM`)."""
        return _nearest_node(self.node_part, self.node_x_mm, part, x_mm)

    def path_nodes(self, which: str) -> tuple[np.ndarray, np.ndarray]:
        """Node indices and station positions along a shaft path (mm from the path start)."""
        path = getattr(self.rig.paths, which)
        stations = _path_stations(path)
        nodes = np.array([self.node(path.part, x) for x in stations])
        return nodes, stations - path.x_start_mm


def _path_stations(path) -> np.ndarray:
    return path.x_start_mm + np.linspace(0.0, path.length_mm, path.stations)


def attachment_positions(rig: Rig) -> dict[str, list[float]]:
    """Positions where springs attach to each part (bearings, mounts, couplings, joints)."""
    refs: dict[str, list[float]] = {p.name: [] for p in rig.parts}
    for b in rig.bearings:
        refs[b.shaft].append(b.x_mm)
        if b.housing != "ground":
            refs[b.housing].append(b.x_mm)
    for m in rig.mounts:
        refs[m.part].append(m.x_mm)
    for c in list(rig.couplings) + list(rig.joints):
        refs[c.from_.part].append(c.from_.x_mm)
        refs[c.to.part].append(c.to.x_mm)
    return refs


def _referenced_positions(rig: Rig) -> dict[str, list[float]]:
    refs = attachment_positions(rig)
    for t in (rig.torques.T1, rig.torques.T2):
        refs[t.part].append(t.x_mm)
        if t.reacted_on is not None:
            refs[t.reacted_on.part].append(t.reacted_on.x_mm)
    for t in rig.torque_lateral_loads:
        refs[t.on.part].append(t.on.x_mm)
        if t.reacted_on is not None:
            refs[t.reacted_on.part].append(t.reacted_on.x_mm)
    for h in rig.housings:
        refs[h.part].extend(h.attachments_x_mm)
    for g in rig.gear_meshes:
        refs[g.on.part].append(g.on.x_mm)
        refs[g.reacted_on.part].append(g.reacted_on.x_mm)
    for f in rig.force_table.pairs:
        refs[f.plus_at.part].append(f.plus_at.x_mm)
        refs[f.minus_at.part].append(f.minus_at.x_mm)
    for f in rig.force_table.singles:
        refs[f.at.part].append(f.at.x_mm)
    for key in MEASURED_SHAFTS:
        path = getattr(rig.paths, key)
        refs[path.part].extend(_path_stations(path).tolist())
    return refs


def _nearest_node(node_part: np.ndarray, node_x_mm: np.ndarray, part: str, x_mm: float) -> int:
    own = np.flatnonzero(node_part == part)
    distance = np.abs(node_x_mm[own] - x_mm)
    if own.size == 0 or distance.min() > NODE_MERGE_MM:
        raise KeyError(f"no node of part '{part}' at x = {x_mm} mm")
    return int(own[np.argmin(distance)])


def _part_positions(part, referenced: list[float], max_length: float) -> np.ndarray:
    """Sorted node positions of one part (mm): breakpoints refined to max_length. A referenced position
    within :data:`NODE_MERGE_MM` of a segment end or of another one shares its node."""
    ends = np.unique([x for s in part.segments for x in s.x_mm])
    kept: list[float] = []
    for x in np.unique(np.asarray(referenced, dtype=float)):
        k = np.searchsorted(ends, x)
        near_end = min(abs(x - ends[max(k - 1, 0)]), abs(x - ends[min(k, ends.size - 1)]))
        if near_end > NODE_MERGE_MM and (not kept or x - kept[-1] > NODE_MERGE_MM):
            kept.append(float(x))
    breaks = np.unique(np.round(np.concatenate([ends, kept]), 9))
    positions = [breaks[0]]
    for a, b in zip(breaks[:-1], breaks[1:]):
        pieces = max(1, int(np.ceil((b - a) / max_length - 1e-9)))
        positions.extend(np.linspace(a, b, pieces + 1)[1:])
    return np.array(positions)


def _segment_finder(part):
    """``find(x)``: the first of ``part``'s segments (in file order) that holds x, found by bisection over
    the segments sorted by start (a part of thousands of segments: a scan per element made building
    quadratic in the segments)."""
    order = sorted(range(len(part.segments)), key=lambda k: (part.segments[k].x_mm[0], k))
    starts = [part.segments[k].x_mm[0] for k in order]
    reach = list(itertools.accumulate((part.segments[k].x_mm[1] for k in order), max))  # furthest end so far

    def find(x_mid: float):
        last = bisect.bisect_right(starts, x_mid)  # segments order[:last] start at or before x
        first = bisect.bisect_left(reach, x_mid, hi=last)  # … and before that none reaches x
        holding = [order[j] for j in range(first, last) if part.segments[order[j]].x_mm[1] >= x_mid]
        if not holding:
            raise ValueError(f"no segment of part '{part.name}' at x = {x_mid} mm")
        return part.segments[min(holding)]

    return find


@dataclass(frozen=True, eq=False)
class FrameNodes:
    """Stage 1 of :func:`build_rig_model`: every node of the frame, by part and position.

    Attributes
    ----------
    node_part : (n,) array of str
        The part (or housing bed group) of each node.
    node_x_mm : (n,) array
    beam_lines : tuple of (part name, first node, positions)
        The node lines of the parts meshed with beams (not those of ``solid_parts``).
    bed_nodes : tuple of int
        The fixed bed node of each ``[[housings]]`` attachment.
    equivalent_density : dict
        Density used for each body (kg/m³).
    """

    node_part: np.ndarray
    node_x_mm: np.ndarray
    beam_lines: tuple
    bed_nodes: tuple[int, ...]
    equivalent_density: dict

    @property
    def coordinates(self) -> np.ndarray:
        """(n, 3) node positions in m, on the axis."""
        coordinates = np.zeros((self.node_x_mm.size, 3))
        coordinates[:, 0] = self.node_x_mm * MM
        return coordinates

    def node(self, part: str, x_mm: float) -> int:
        return _nearest_node(self.node_part, self.node_x_mm, part, x_mm)


@dataclass(frozen=True, eq=False)
class FrameSprings:
    """Stage 3 of :func:`build_rig_model`: the six-component springs and which rig item each one is."""

    bushings: Bushings
    names: tuple[SpringId, ...]


@dataclass(frozen=True, eq=False)
class FrameMasses:
    """Stage 4 of :func:`build_rig_model`: the coupling hubs as point masses (half a coupling's mass at each end)."""

    point_masses: PointMasses


def frame_nodes(rig: Rig, solid_parts: tuple[str, ...] = ()) -> FrameNodes:
    """Stage 1: the node lines of every part (only the attachment nodes of ``solid_parts``), then one fixed bed node
    per ``[[housings]]`` attachment (the other side of the condensed housing, geometry/model/housings.py; its
    fixed-DOF reactions are the housing's ground reactions)."""
    referenced = _referenced_positions(rig)
    attachments = attachment_positions(rig)
    node_part: list[str] = []
    node_x: list[float] = []
    lines = []
    equivalent_density: dict[str, float] = {}
    for part in rig.parts:
        if part.role == "body":
            equivalent_density[part.name] = part.mass_kg / (part.volume_mm3 * MM**3)
        if part.name in solid_parts:
            positions = np.unique(np.round(np.array(attachments[part.name], dtype=float), 9))
        else:
            positions = _part_positions(part, referenced[part.name], rig.mesh.max_element_length_mm)
            lines.append((part.name, len(node_x), positions))
        node_part.extend([part.name] * positions.size)
        node_x.extend(positions.tolist())
    bed_nodes = []
    for h in rig.housings:
        for x in h.attachments_x_mm:
            bed_nodes.append(len(node_x))
            node_part.append(housing_bed_group(h.name))
            node_x.append(float(x))
    return FrameNodes(np.array(node_part), np.array(node_x), tuple(lines), tuple(bed_nodes), equivalent_density)


def frame_beams(rig: Rig, nodes: FrameNodes) -> BeamElements:
    """Stage 2: one Timoshenko beam between neighbouring nodes of each beam line, with its segment's section and its
    part's material (a body's density is its equivalent density; a shaft's shear flexibility × ``[beam]
    shear_factor``, Euler–Bernoulli when 0)."""
    shaft_shear = rig.beam.shear_factor  # shafts' Φ × factor: κ / factor (∞ when 0: Euler–Bernoulli)
    element_rows: list[tuple] = []
    for name, first, positions in nodes.beam_lines:
        part = rig.part(name)
        material = rig.materials[part.material]
        density = nodes.equivalent_density.get(name, material.density_kg_per_m3)
        shear_factor = shaft_shear if part.role == "shaft" else 1.0
        segment_at = _segment_finder(part)
        for i in range(positions.size - 1):
            segment = segment_at(0.5 * (positions[i] + positions[i + 1]))
            section = CircularSection(segment.outer_diameter_mm * MM, segment.inner_diameter_mm * MM)
            element_rows.append((
                first + i, first + i + 1, section.area_m2, section.second_moment_m4,
                section.polar_moment_m4,
                section.shear_coefficient(material.poisson_ratio) / shear_factor if shear_factor > 0 else np.inf,
                material.youngs_modulus_MPa * 1e6, material.shear_modulus_MPa * 1e6, density,
            ))
    table = np.array(element_rows, dtype=float).reshape(-1, 9)
    return BeamElements(
        connectivity=table[:, :2].astype(int), area_m2=table[:, 2], second_moment_m4=table[:, 3],
        polar_moment_m4=table[:, 4], shear_coefficient=table[:, 5], youngs_modulus_Pa=table[:, 6],
        shear_modulus_Pa=table[:, 7], density_kg_per_m3=table[:, 8],
        reference_vector=np.tile([0.0, 1.0, 0.0], (table.shape[0], 1)),
    )


def frame_springs(rig: Rig, nodes: FrameNodes) -> FrameSprings:
    """Stage 3: bearings, mounts, couplings and joints as six-component springs (N/m, N·m/rad), in that order."""
    node = nodes.node
    rows: list[tuple[int, int, float, list[float]]] = []  # node_a, node_b, point x (mm), stiffness
    names: list[SpringId] = []
    for b in rig.bearings:
        radial = b.radial_stiffness_N_per_um * N_PER_UM
        k = [b.axial_stiffness_N_per_um * N_PER_UM, radial, radial, 0.0,
             b.tilt_stiffness_Nm_per_rad, b.tilt_stiffness_Nm_per_rad]
        a = GROUND if b.housing == "ground" else node(b.housing, b.x_mm)
        rows.append((a, node(b.shaft, b.x_mm), b.x_mm, k))
        names.append(SpringId("bearing", b.name))
    for m in rig.mounts:
        k = [v * N_PER_UM for v in m.translational_stiffness_N_per_um] + list(m.rotational_stiffness_Nm_per_rad)
        rows.append((GROUND, node(m.part, m.x_mm), m.x_mm, k))
        names.append(SpringId("mount", m.name))
    for c in rig.couplings:
        radial = c.radial_stiffness_N_per_mm * N_PER_MM
        k = [c.axial_stiffness_N_per_mm * N_PER_MM, radial, radial, c.torsional_stiffness_Nm_per_rad,
             c.angular_stiffness_Nm_per_rad, c.angular_stiffness_Nm_per_rad]
        rows.append((node(c.from_.part, c.from_.x_mm), node(c.to.part, c.to.x_mm), c.centre_x_mm, k))
        names.append(SpringId("coupling", c.name))
    for j in rig.joints:
        k = [v * N_PER_UM for v in j.translational_stiffness_N_per_um] + list(j.rotational_stiffness_Nm_per_rad)
        rows.append((node(j.from_.part, j.from_.x_mm), node(j.to.part, j.to.x_mm), j.to.x_mm, k))
        names.append(SpringId("joint", j.name))
    points = np.zeros((len(rows), 3))
    points[:, 0] = [r[2] * MM for r in rows]
    bushings = Bushings(
        node_a=np.array([r[0] for r in rows], dtype=int), node_b=np.array([r[1] for r in rows], dtype=int),
        point_m=points, stiffness=np.array([r[3] for r in rows], dtype=float).reshape(len(rows), 6),
    )
    return FrameSprings(bushings, tuple(names))


def frame_masses(rig: Rig, nodes: FrameNodes) -> FrameMasses:
    """Stage 4: half of each coupling's mass at each of its hubs, with half its polar inertia about the axis and a
    quarter about each diameter (a disc); no rotary inertia without ``polar_inertia_kg_m2``."""
    hub_nodes, hub_masses, hub_inertia = [], [], []
    for c in rig.couplings:
        polar = (c.polar_inertia_kg_m2 or 0.0) / 2.0  # per hub; a disc's diametral moment is half its polar one
        for end in (c.from_, c.to):
            hub_nodes.append(nodes.node(end.part, end.x_mm))
            hub_masses.append(c.mass_kg / 2.0)
            hub_inertia.append((polar, polar / 2.0, polar / 2.0))
    return FrameMasses(PointMasses(np.array(hub_nodes, dtype=int), np.array(hub_masses, dtype=float),
                                   np.array(hub_inertia, dtype=float).reshape(-1, 3)))


def _part_masses(rig: Rig, nodes: FrameNodes, structure: StructuralModel) -> dict[str, float]:
    """Mass of each part as modelled: its beams plus the coupling hubs it carries (kg)."""
    beams, hubs = structure.beams, structure.point_masses
    element_mass = (beams.density_kg_per_m3 * beams.area_m2
                    * np.diff(structure.coordinates[beams.connectivity, 0], axis=1).ravel())
    part_mass = {p.name: 0.0 for p in rig.parts}
    for e, m in zip(beams.connectivity[:, 0], element_mass):
        part_mass[str(nodes.node_part[e])] += float(m)
    for n, m in zip(hubs.node, hubs.mass_kg):
        part_mass[str(nodes.node_part[n])] += float(m)
    return part_mass


def build_rig_model(rig: Rig, solid_parts: tuple[str, ...] = ()) -> RigModel:
    """Build the beam model of a validated rig, in four stages: nodes (:func:`frame_nodes`), beams
    (:func:`frame_beams`), springs (:func:`frame_springs`) and masses (:func:`frame_masses`).

    Parts named in ``solid_parts`` get no beams: only reference nodes where springs attach (the
    solid model ties them to faces), and no mass (the solid carries it).

    Parameters
    ----------
    rig : Rig
        A validated rig.
    solid_parts : tuple of str
        Parts that a solid model meshes instead.

    Returns
    -------
    RigModel
        The frame: nodes, beams, springs (bushings), point masses and fixed DOFs, with the maps from rig
        names and positions to nodes and springs.
    """
    nodes = frame_nodes(rig, solid_parts)
    springs = frame_springs(rig, nodes)
    fixed = (6 * np.asarray(nodes.bed_nodes, dtype=int)[:, None] + np.arange(6)).ravel()
    structure = StructuralModel(nodes.coordinates, frame_beams(rig, nodes), springs.bushings,
                                point_masses=frame_masses(rig, nodes).point_masses, node_group=nodes.node_part,
                                fixed_dofs=fixed)
    return RigModel(rig=rig, structure=structure, node_part=nodes.node_part, node_x_mm=nodes.node_x_mm,
                    bushing_names=springs.names, part_mass_kg=_part_masses(rig, nodes, structure),
                    equivalent_density=nodes.equivalent_density)


def housing_bed_group(name: str) -> str:
    """The node group of the bed side of housing ``name`` (not a part name: part names have no spaces)."""
    return f"{name} (bed)"


def stress_free_motions(rig: Rig) -> np.ndarray:
    """Relative motion Δ0 (n_bushings, 6) at which each bushing of ``rig`` is free of load (SI).

    Rows in the order :func:`build_rig_model` builds the bushings (bearings, mounts, couplings,
    joints). A mount raised by ``vertical_offset_um`` has Δ0 = (0, δ, 0, 0, 0, 0); a coupling with
    a parallel offset δ and an angular misalignment α towards direction e = (0, cos φ, sin φ) has
    Δ0 = (δ e, α x × e): its ``to`` hub is free of load δ away from the ``from`` hub and rotated
    by α towards e. ``[thermal]`` adds the supports' lifts, the bed's growth and the grown spacing of
    couplings (:func:`rvcoax.geometry.thermal.thermal_stress_free_motions`). Everything else is zero.
    """
    rows = [np.zeros(6) for _ in rig.bearings]
    for m in rig.mounts:
        rows.append(np.array([0.0, m.vertical_offset_um * UM, 0.0, 0.0, 0.0, 0.0]))
    for c in rig.couplings:
        phi = np.radians(c.misalignment_direction_deg)
        direction = np.array([0.0, np.cos(phi), np.sin(phi)])
        rotation_axis = np.cross([1.0, 0.0, 0.0], direction)  # x rotated towards e: about x × e
        rows.append(np.concatenate([c.parallel_offset_um * UM * direction,
                                    c.angular_misalignment_mrad * MRAD * rotation_axis]))
    rows.extend(np.zeros(6) for _ in rig.joints)
    return np.array(rows, dtype=float).reshape(-1, 6) + thermal_stress_free_motions(rig)


def prestrain_contributions(frame: RigModel, rig: Rig) -> list[Contribution]:
    """The load ``"prestrain"`` of the frame: the bushings' K Δ0 through their rigid arms, then the beams'
    thermal initial strain (a vector on the frame's DOFs; zero without ``[thermal]``).

    ``rig`` gives the offsets and temperatures (it may differ from ``frame.rig`` in those only). Zero when every
    coupling is aligned, every mount at its nominal height and nothing is warm.
    """
    structure = frame.structure
    return [prestrain_contribution(structure, stress_free_motions(rig)),
            dense_load_contribution("prestrain", beam_thermal_load(rig, frame.node_part, structure.beams,
                                                                   structure.n_dofs))]
