"""Hybrid and solid models: some (or all) parts as quadratic tetrahedra, tied to the beam frame.

Each solid part is meshed on its own (:mod:`rvcoax.geometry.meshing`) and assembled as a block of the
global system. Wherever the rig attaches something to a solid part (bearing, mount, coupling hub,
joint) the frame has a 6-DOF reference node, tied to a face of the solid: a lateral band (a
bearing's width, a coupling's hub length, ``band_mm`` or ``[solid] attachment_band_mm``), or the end
face when the attachment sits at the part's end. The tie is distributing (RBE3-like) unless the
location says ``tie = "rigid"`` (RBE2-like). Loads on a solid part are face tractions with exactly
the applied resultant. The measured paths on a solid shaft are read as the mean u_y over a ring of
probe points at mid-wall radius (the axis of a hollow shaft lies in its bore).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.errors import RvcoaxError
from rvcoax.fem import memory, solid, ties
from rvcoax.fem.equilibrium import DofTable, frame_dof_table
from rvcoax.fem.pieces import (
    Contribution,
    assemble,
    dense_load_contribution,
    frame_contributions,
    solid_contribution,
    tie_contribution,
)
from rvcoax.fem.ties import FaceNodes, distributing_tie_equations, rigid_tie_equations
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.meshing import SolidPartGeometry, mesh_part
from rvcoax.geometry.model.beam import RigModel, build_rig_model
from rvcoax.geometry.model.housings import housing_contributions
from rvcoax.geometry.model.loads import (
    GRAVITY_DIRECTION,
    LocatedLoad,
    located_unit_loads,
)
from rvcoax.geometry.model.system import PathProbe, RigSystem, UnitLoadBuilder, frame_path_probe, located_contribution
from rvcoax.geometry.schema import Part, Rig
from rvcoax.geometry.thermal import part_strain
from rvcoax.geometry.units import MM

__all__ = ["DERIVED_MESH_DATA", "READ_LATER_TO_FILE_BYTES", "Attachment", "FaceSpec", "RING_POINTS", "SolidLoads", "SolidModelError", "SolidPart", "TOL_MM",
           "assemble_with_solids", "attachments", "face_at", "face_nodes", "forget_derived", "mesh_size_of", "ring_probe",
           "select_facets", "solid_geometry"]

RING_POINTS = 8
TOL_MM = 1e-6


class SolidModelError(RvcoaxError, ValueError):
    """The rig cannot be built as a hybrid or solid model (conflicting faces, unsupported loads); names the part."""

    stage = "cannot build the solid parts"


@dataclass(frozen=True)
class FaceSpec:
    """A face of a round part: ``band`` of the lateral surface [x0, x1] (outer or inner), or ``end`` at x0."""

    kind: str
    x0_mm: float
    x1_mm: float
    surface: str = "outer"


@dataclass(frozen=True, eq=False)
class SolidPart:
    """A meshed solid part and where its DOFs sit in the global vector.

    The part holds its mesh, not its P2 basis: a basis (quadrature-point values and gradients of every shape
    function) is several times the mesh, and a solve needs none once the system is assembled. :attr:`basis`
    builds one on demand for field output, mass matrices and thermal loads (the same basis each time).
    """

    name: str
    geometry: SolidPartGeometry
    mesh: object
    offset: int
    n_dofs: int
    youngs_modulus_Pa: float
    poisson: float
    density_kg_per_m3: float

    @property
    def basis(self) -> object:
        """The vector P2 basis of :attr:`mesh`, built anew on each call (keep it only as long as it is used)."""
        return solid.solid_basis(self.mesh)

    @property
    def material(self) -> solid.ElasticMaterial:
        return solid.ElasticMaterial(self.youngs_modulus_Pa, self.poisson, self.density_kg_per_m3)


@dataclass(frozen=True)
class Attachment:
    part: str
    x_mm: float
    face: FaceSpec
    tie: str


def _has_bore(part: Part, x_mm: float) -> bool:
    for s in part.segments:
        if s.x_mm[0] - TOL_MM <= x_mm <= s.x_mm[1] + TOL_MM and s.inner_diameter_mm > 0:
            return True
    return False


def face_at(part: Part, x_mm: float, width_mm: float | None, band_mm=None, surface: str = "outer") -> FaceSpec:
    """The face of ``part`` that something at ``x_mm`` acts on."""
    lo, hi = part.x_range_mm
    if band_mm is not None:
        return FaceSpec("band", max(lo, band_mm[0]), min(hi, band_mm[1]), surface)
    if width_mm is None:
        if abs(x_mm - lo) < TOL_MM or abs(x_mm - hi) < TOL_MM:
            return FaceSpec("end", x_mm, x_mm)
        raise SolidModelError(f"part '{part.name}': something attaches at x = {x_mm} mm, away from the part's ends, "
                              "without a width to choose its face on the solid ([solid] attachment_band_mm)")
    x0, x1 = max(lo, x_mm - width_mm / 2), min(hi, x_mm + width_mm / 2)
    return FaceSpec("band", x0, x1, surface)


def _location_face(rig: Rig, part: Part, x_mm: float, band_mm=None) -> FaceSpec:
    lo, hi = part.x_range_mm
    if band_mm is None and (abs(x_mm - lo) < TOL_MM or abs(x_mm - hi) < TOL_MM):
        return FaceSpec("end", x_mm, x_mm)
    return face_at(part, x_mm, rig.solid.attachment_band_mm, band_mm)


def attachments(rig: Rig, solid_parts: tuple[str, ...]) -> list[Attachment]:
    """Every place where a spring of the rig attaches to a solid part, with its face and tie."""
    out: list[Attachment] = []
    parts = {p.name: p for p in rig.parts}
    for b in rig.bearings:
        if b.shaft in solid_parts:
            out.append(Attachment(b.shaft, b.x_mm, face_at(parts[b.shaft], b.x_mm, b.width_mm), "distributing"))
        if b.housing in solid_parts:
            housing = parts[b.housing]
            surface = "inner" if _has_bore(housing, b.x_mm) else "outer"
            out.append(Attachment(b.housing, b.x_mm, face_at(housing, b.x_mm, b.width_mm, surface=surface), "distributing"))
    for m in rig.mounts:
        if m.part in solid_parts:
            out.append(Attachment(m.part, m.x_mm, _location_face(rig, parts[m.part], m.x_mm), "distributing"))
    for c in rig.couplings:
        for end in (c.from_, c.to):
            if end.part in solid_parts:
                face = face_at(parts[end.part], end.x_mm, c.hub_length_mm, end.band_mm)
                out.append(Attachment(end.part, end.x_mm, face, end.tie))
    for j in rig.joints:
        for end in (j.from_, j.to):
            if end.part in solid_parts:
                out.append(Attachment(end.part, end.x_mm, _location_face(rig, parts[end.part], end.x_mm, end.band_mm),
                                      end.tie))
    merged: dict[tuple[str, float], Attachment] = {}
    for a in out:
        key = (a.part, round(a.x_mm, 6))
        if key in merged and (merged[key].face != a.face or merged[key].tie != a.tie):
            raise SolidModelError(f"two attachments to solid part '{a.part}' at x = {a.x_mm} mm use different faces "
                             f"({merged[key].face} and {a.face}); move one of them")
        merged[key] = a
    return list(merged.values())


def _load_face(rig: Rig, part: Part, load: LocatedLoad) -> FaceSpec:
    return _location_face(rig, part, load.x_mm, load.band_mm)


def mesh_size_of(rig: Rig, part: Part, global_size_mm: float) -> float:
    """Per-part mesh size: the part's own; else the global size for a shaft, and for a body (housing)
    max(global, largest diameter / elements per diameter), so that a Ø330 brake is not meshed at 4 mm."""
    if part.mesh_size_mm is not None:
        return part.mesh_size_mm
    if part.role == "shaft":
        return global_size_mm
    largest = max(s.outer_diameter_mm for s in part.segments)
    return max(global_size_mm, largest / rig.solid.elements_per_diameter)


def solid_geometry(rig: Rig, part: Part, faces: list[FaceSpec], global_size_mm: float) -> SolidPartGeometry:
    """The part's solid geometry with split planes at every band edge."""
    lo, hi = part.x_range_mm
    splits = sorted({round(x, 6) for f in faces if f.kind == "band" for x in (f.x0_mm, f.x1_mm)
                     if lo + 1e-3 < x < hi - 1e-3})
    segments = tuple((s.x_mm[0], s.x_mm[1], s.outer_diameter_mm, s.inner_diameter_mm)
                     for s in sorted(part.segments, key=lambda s: s.x_mm[0]))
    return SolidPartGeometry(part.name, segments, tuple(splits), mesh_size_of(rig, part, global_size_mm))


def select_facets(part: SolidPart, face: FaceSpec) -> np.ndarray:
    """Boundary facets of ``part`` that form ``face``."""
    mesh = part.mesh
    facets = mesh.boundary_facets()
    corners = mesh.p[:, mesh.facets[:, facets]]  # (3 coords, 3 corners, n)
    centre = corners.mean(axis=1)
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0], axis=0)
    normal /= np.linalg.norm(normal, axis=0)
    x_mm = centre[0] / MM
    radius_mm = np.hypot(centre[1], centre[2]) / MM
    tol = 1e-3 + 1e-6 * abs(x_mm)
    if face.kind == "end":
        keep = (np.abs(normal[0]) > 0.99) & (np.abs(corners[0] / MM - face.x0_mm).max(axis=0) < tol + 1e-3)
    else:
        inside = (corners[0] / MM >= face.x0_mm - 1e-3).all(axis=0) & (corners[0] / MM <= face.x1_mm + 1e-3).all(axis=0)
        lateral = np.abs(normal[0]) < 0.5
        outer, inner = _radii(part.geometry, x_mm)
        middle = 0.5 * (outer + inner)
        keep = inside & lateral & ((radius_mm > middle) if face.surface == "outer" else (radius_mm < middle))
    selected = facets[keep]
    if selected.size == 0:
        raise SolidModelError(f"solid part '{part.name}': no boundary facets on {face}")
    return selected


def _radii(geometry: SolidPartGeometry, x_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Outer and inner radius (mm) of the segment at each x (vectorised)."""
    outer = np.zeros_like(x_mm)
    inner = np.zeros_like(x_mm)
    for x0, x1, d_out, d_in in geometry.segments:
        here = (x_mm >= x0 - TOL_MM) & (x_mm <= x1 + TOL_MM)
        outer = np.where(here, np.maximum(outer, d_out / 2), outer)
        inner = np.where(here & (inner == 0), d_in / 2, inner)
    return outer, inner


def face_nodes(part: SolidPart, facets: np.ndarray, basis=None) -> FaceNodes:
    """The P2 nodes of a set of facets with global DOFs and area weights (area / 6 per facet node).

    ``basis`` is the part's basis where the caller holds one already (else it is built).
    """
    return ties.face_nodes(part.mesh, part.basis if basis is None else basis, facets, part.offset)


def ring_probe(part: SolidPart, stations_x_mm: np.ndarray, n_dofs: int,
               basis=None) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Operators (n_st × n_dofs) for the mean u_y and the section rotation about z at each station.

    ``basis`` is the part's basis where the caller holds one already (else it is built).
    """
    outer, inner = _radii(part.geometry, np.asarray(stations_x_mm, float))
    lo, hi = part.geometry.segments[0][0], part.geometry.segments[-1][1]
    angles = 2 * np.pi * (np.arange(RING_POINTS) + 0.5) / RING_POINTS
    rings = []
    for k, x in enumerate(stations_x_mm):
        r = 0.5 * (outer[k] + inner[k]) * MM
        xs = np.clip(x, lo + 1e-3, hi - 1e-3) * MM
        rings.append(np.vstack([np.full(RING_POINTS, xs), r * np.cos(angles), r * np.sin(angles)]))
    # every ring located in one vectorised Newton iteration, each ring stopping on its own convergence
    stations = np.repeat(np.arange(len(rings)), RING_POINTS)
    probe_all = solid.probe_matrix(part.basis if basis is None else basis, np.hstack(rings).T, groups=stations) if rings else None
    rows_y, rows_r = [], []
    for k, points in enumerate(rings):
        probe = probe_all[3 * RING_POINTS * k:3 * RING_POINTS * (k + 1)]  # (3 * points, N): ux, uy, uz per point
        ux = probe[0::3]
        uy = probe[1::3]
        y = points[1]
        rows_y.append(sp.csr_matrix(uy.mean(axis=0)))
        rows_r.append(sp.csr_matrix(-(y @ ux) / np.sum(y * y)))
    shift = sp.csr_matrix((np.ones(part.n_dofs), (np.arange(part.n_dofs), part.offset + np.arange(part.n_dofs))),
                          shape=(part.n_dofs, n_dofs))
    return sp.vstack(rows_y).tocsr() @ shift, sp.vstack(rows_r).tocsr() @ shift


class SolidLoads:
    """Face-traction load vectors of a set of solid parts, cached per face.

    A traction vector is linear in the applied force, so each face keeps the vectors of a unit
    force along x, y, z and of a unit torque about x; a load is their combination. Calibration,
    which changes only load sizes, then rebuilds loads without touching the mesh.
    """

    def __init__(self, rig: Rig, solids: dict[str, SolidPart]):
        self._parts = {p.name: p for p in rig.parts}
        self._rig = rig
        self._solids = solids
        self._unit: dict[tuple, np.ndarray] = {}

    def _unit_vectors(self, part: SolidPart, face: FaceSpec, x_mm: float) -> np.ndarray:
        key = (part.name, face, round(x_mm, 9))
        if key not in self._unit:
            facets = select_facets(part, face)
            columns = [solid.force_traction_vector(part.mesh, facets, np.eye(3)[k]) for k in range(3)]
            centre = np.array([x_mm * MM, 0.0, 0.0])
            columns.append(solid.torque_traction_vector(part.mesh, facets, centre, np.array([1.0, 0.0, 0.0]), 1.0))
            self._unit[key] = np.column_stack(columns)
        return self._unit[key]

    def cached_tractions(self) -> dict[tuple, np.ndarray]:
        """The traction vectors kept so far, by face (a copy of the cache's index; the arrays are the cache's)."""
        return dict(self._unit)

    def use_cached_tractions(self, tractions: dict[tuple, np.ndarray]) -> None:
        """Keep ``tractions`` (the faces of :meth:`cached_tractions`, their vectors stored elsewhere) instead; the
        values are not read here (a file map's pages stay on disk until a load is rebuilt)."""
        if tractions.keys() != self._unit.keys():
            raise ValueError("the traction vectors given are not those of the cached faces")
        self._unit = dict(tractions)

    def contributions(self, frame: RigModel, name: str, loads: list[LocatedLoad]) -> list[Contribution]:
        """``loads`` as entries of load ``name``: nodal on frame parts, then a face traction per load on a solid part."""
        pieces = [located_contribution(frame, name, [ld for ld in loads if ld.part not in self._solids])]
        for load in loads:
            if load.part not in self._solids:
                continue
            moment = np.asarray(load.moment_Nm, dtype=float)
            if np.any(moment[1:]):
                raise SolidModelError(f"a bending moment load on solid part '{load.part}' is not supported")
            part = self._solids[load.part]
            face = _load_face(self._rig, self._parts[load.part], load)
            weights = np.concatenate([np.asarray(load.force_N, dtype=float), moment[:1]])
            traction = self._unit_vectors(part, face, load.x_mm) @ weights
            pieces.append(dense_load_contribution(name, traction, part.offset))
        return pieces

    def thermal_contributions(self, rig: Rig) -> list[Contribution]:
        """Initial-strain load ``"prestrain"`` of the solid parts' free thermal strain α ΔT (``[thermal]``), one per part."""
        pieces = []
        for name, part in self._solids.items():
            strain = part_strain(rig, name)
            if strain:
                pieces.append(dense_load_contribution("prestrain", solid.thermal_strain_vector(
                    part.basis, part.youngs_modulus_Pa, part.poisson, strain), part.offset))
        return pieces


DERIVED_MESH_DATA = ("_cached_mapping", "_dofs", "_facets", "_t2f", "_f2t", "_f2e", "_edges", "_t2e")
"""What scikit-fem derives from a mesh's nodes and elements and keeps on the mesh (attribute names), each built again
when it is next asked for."""


def forget_derived(mesh) -> None:
    """Let go of what scikit-fem derived from ``mesh`` and keeps on it (:data:`DERIVED_MESH_DATA`).

    Above all the isoparametric mapping of a curved mesh (``MeshTet2``): made once per mesh, it caches the Jacobian
    entries of every set of points it is asked about, the quadrature points of each basis built on the mesh
    (stiffness, weight, DOF table), each loaded or tied face's quadrature points and the probe rings; then the facets,
    edges and their incidence arrays. Nothing reads them between the assembly and the field output, and they stayed
    as long as the mesh, resident through the factorisation and the solves: 144 MB of Jacobians and 25 MB of entity
    arrays on the example rig's all-solid model at 627 k DOF (benchmarks/RESULTS.md). The next basis, traction or
    probe on the mesh derives them again, with the same values.
    """
    for name in DERIVED_MESH_DATA:
        mesh.__dict__.pop(name, None)


READ_LATER_TO_FILE_BYTES = 16 << 20
"""The arrays of an assembled solid or hybrid model that a solve does not read (:func:`_read_later_from_file`) go to a
file when they hold more than this together: the all-solid reference rig at 492 k DOF has 32 MB of them."""


def _read_later_from_file(table: DofTable, loads: UnitLoadBuilder) -> tuple[DofTable, UnitLoadBuilder]:
    """The same DOF table and load builder, their arrays (DOF positions and components, the weight per g, the cached
    face tractions) in a private map of a temporary file (:func:`rvcoax.fem.memory.arrays_to_file`) where they hold
    more than :data:`READ_LATER_TO_FILE_BYTES`.

    Nothing reads them while the model is factorised and solved: the table serves the equilibrium check after the
    solves, the others a rebuild of the unit loads for other load parameters. Their pages come back when read; until
    then they are not resident memory at the peak of a large model's solve (benchmarks/RESULTS.md). Values unchanged;
    where no file can be written they stay in memory.
    """
    tractions = loads.solid_loads.cached_tractions() if loads.solid_loads is not None else {}
    arrays = [table.position, table.component, loads.weight_per_g, *tractions.values()]
    if sum(array.nbytes for array in arrays) <= READ_LATER_TO_FILE_BYTES:
        return table, loads
    moved = memory.arrays_to_file(arrays)
    if moved is None:
        return table, loads
    if tractions:
        loads.solid_loads.use_cached_tractions(dict(zip(tractions, moved[3:])))
    return DofTable(moved[0], moved[1]), dataclasses.replace(loads, weight_per_g=moved[2])


def _dof_table(structure, solids: dict[str, SolidPart], bases: dict) -> DofTable:
    """Where each DOF sits and which component it is: the frame's, then each solid part's in order."""
    frame_table = frame_dof_table(structure.coordinates)
    positions = [frame_table.position]
    components = [frame_table.component]
    for s in solids.values():
        positions.append(bases[s.name].doflocs.T)  # (N, 3), one row per DOF
        components.append(solid.dof_components(bases[s.name]))
    return DofTable(np.vstack(positions), np.concatenate(components))


def assemble_with_solids(rig: Rig, kind: str, mesh_size_mm: float | None = None, cache_dir=None) -> RigSystem:
    """Assemble the hybrid (``kind="hybrid"``) or all-solid (``kind="solid"``) model of ``rig``."""
    solid_names = rig.hybrid_solid_parts() if kind == "hybrid" else tuple(p.name for p in rig.parts)
    global_size = mesh_size_mm if mesh_size_mm is not None else rig.solid.mesh_size_mm
    frame = build_rig_model(rig, solid_parts=solid_names)
    structure = frame.structure
    ties = attachments(rig, solid_names)
    located = located_unit_loads(rig)
    parts = {p.name: p for p in rig.parts}
    load_faces: dict[str, list[FaceSpec]] = {name: [] for name in solid_names}
    for items in located.values():
        for load in items:
            if load.part in load_faces:
                load_faces[load.part].append(_load_face(rig, parts[load.part], load))

    solids: dict[str, SolidPart] = {}
    bases = {}  # held while the system is assembled only: see SolidPart
    offset = structure.n_dofs
    for name in solid_names:
        part = parts[name]
        faces = [a.face for a in ties if a.part == name] + load_faces[name]
        geometry = solid_geometry(rig, part, faces, global_size)
        mesh = mesh_part(geometry, cache_dir=cache_dir)
        basis = bases[name] = solid.solid_basis(mesh)
        material = rig.materials[part.material]
        density = (part.mass_kg / (part.volume_mm3 * MM**3)) if part.role == "body" else material.density_kg_per_m3
        solids[name] = SolidPart(name=name, geometry=geometry, mesh=mesh, offset=offset, n_dofs=int(basis.N),
                                 youngs_modulus_Pa=material.youngs_modulus_MPa * 1e6, poisson=material.poisson_ratio,
                                 density_kg_per_m3=density)
        offset += int(basis.N)
    n = offset

    housed = [h.name for h in rig.housings if h.part in solid_names]
    if housed:
        raise SolidModelError(f"housings {', '.join(housed)}: their part is a solid here; a condensed housing holds a "
                              "beam part's nodes (keep the part out of [solid] hybrid_parts)")
    pieces = frame_contributions(structure, GRAVITY_DIRECTION) + housing_contributions(rig, frame, cache_dir)
    pieces += [solid_contribution(bases[s.name], s.material, s.offset, gravity_direction=GRAVITY_DIRECTION)
               for s in solids.values()]
    for a in ties:
        s = solids[a.part]
        nodes = face_nodes(s, select_facets(s, a.face), bases[s.name])
        reference = frame.node(a.part, a.x_mm)
        tie = rigid_tie_equations if a.tie == "rigid" else distributing_tie_equations
        pieces.append(tie_contribution(tie(reference, structure.coordinates[reference], nodes)))
    assembled = assemble(n, pieces)
    loads = UnitLoadBuilder(frame, n, assembled.loads["gravity"], SolidLoads(rig, solids))

    probes = {}
    for which in MEASURED_SHAFTS:
        path = getattr(rig.paths, which)
        if path.part in solids:
            stations = np.linspace(0.0, path.length_mm, path.stations)
            uy, rz = ring_probe(solids[path.part], path.x_start_mm + stations, n, bases[path.part])
            probes[which] = PathProbe(stations, path.length_mm, uy, rz)
        else:
            probes[which] = frame_path_probe(frame, which, n)

    table = _dof_table(structure, solids, bases)
    unit_loads = loads(rig)
    del bases
    for s in solids.values():
        forget_derived(s.mesh)
    table, loads = _read_later_from_file(table, loads)
    return RigSystem(rig=rig, kind=kind, frame=frame, stiffness=assembled.stiffness, elimination=assembled.elimination,
                     unit_loads=unit_loads, probes=probes, dofs=table, solids=tuple(solids.values()), load_builder=loads)
