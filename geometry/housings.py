"""Housings, bearing blocks and pedestals condensed from a solid FE model to a superelement.

A block (:class:`BlockGeometry`: a box along the rig's x axis, an optional bore on the axis, an
optional wider foot plate on the bed) is meshed with gmsh into curved quadratic tetrahedra
(:func:`rvcoax.geometry.meshing.mesh_part`, cached by content hash), its feet (the bottom face) are
clamped or sit on an elastic bed (a Winkler foundation: normal and shear stiffness per area), and one
6-DOF reference node per attachment is tied to a face (a band of the bore, or the top face). The
supported model is then reduced to the reference nodes (:mod:`rvcoax.fem.condensation`): a 6k × 6k
stiffness against the ground that enters the rig like a bushing. The condensed matrix is cached too,
keyed by everything it depends on.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import skfem

from rvcoax.fem import DOFS_PER_NODE, solid
from rvcoax.fem.assembly import assemble_matrix
from rvcoax.fem.condensation import condensed_stiffness
from rvcoax.fem.constraints import elimination_matrix
from rvcoax.fem.solvers import pardiso_available
from rvcoax.fem.ties import distributing_tie_equations, face_nodes, rigid_tie_equations
from rvcoax.geometry.meshing import MESHER_VERSION, default_cache_dir, mesh_part

__all__ = ["BlockGeometry", "CondensedHousing", "HOUSING_VERSION", "HousingModel", "Reference", "build_housing_model",
           "condense_housing", "housing_faces", "solid_method"]

HOUSING_VERSION = 1
"""Bump whenever a change here changes a condensed matrix (invalidates its cache entries)."""
_TOL_MM = 1e-6


@dataclass(frozen=True)
class BlockGeometry:
    """A block along x in rig coordinates (mm): the rig's axis is y = z = 0.

    Attributes
    ----------
    name : str
    x_mm : (x0, x1)
    width_mm : float
        Along z, centred on the axis.
    bottom_mm, top_mm : float
        y of the bed face (the feet's underside, < 0 when the axis is above the bed) and of the top face.
    bore_diameter_mm : float
        A through bore on the axis (0: none).
    foot_thickness_mm, foot_width_mm : float
        A foot plate (bolt flange) on the bed, wider than the block along z (thickness 0: none).
    split_x_mm : tuple
        Planes x = const where faces are split (edges of the bore bands the references are tied to).
    mesh_size_mm : float
    """

    name: str
    x_mm: tuple[float, float]
    width_mm: float
    bottom_mm: float
    top_mm: float
    bore_diameter_mm: float = 0.0
    foot_thickness_mm: float = 0.0
    foot_width_mm: float = 0.0
    split_x_mm: tuple[float, ...] = ()
    mesh_size_mm: float = 5.0

    def __post_init__(self) -> None:
        x0, x1 = self.x_mm
        where = f"housing '{self.name}'"
        if not x1 > x0:
            raise ValueError(f"{where}: x_mm must be increasing, got {list(self.x_mm)}")
        if not self.top_mm > self.bottom_mm:
            raise ValueError(f"{where}: the top (y = {self.top_mm} mm) must lie above the bed face (y = {self.bottom_mm} mm)")
        radius = 0.5 * self.bore_diameter_mm
        if radius > 0 and not (radius < self.top_mm and radius < -self.bottom_mm - self.foot_thickness_mm
                               and radius < 0.5 * self.width_mm):
            raise ValueError(f"{where}: the bore (Ø{self.bore_diameter_mm:g} mm) does not fit inside the block")
        if self.foot_thickness_mm > 0 and not (self.foot_width_mm >= self.width_mm
                                               and self.foot_thickness_mm < self.top_mm - self.bottom_mm):
            raise ValueError(f"{where}: the foot plate must be at least as wide as the block and thinner than it is tall")
        object.__setattr__(self, "split_x_mm", tuple(sorted(float(x) for x in self.split_x_mm if x0 < x < x1)))

    @property
    def breakpoints_mm(self) -> tuple[float, ...]:
        points = sorted({*self.x_mm, *self.split_x_mm})
        return tuple(points)

    @property
    def volume_mm3(self) -> float:
        length = self.x_mm[1] - self.x_mm[0]
        volume = self.width_mm * (self.top_mm - self.bottom_mm) * length
        volume += (self.foot_width_mm - self.width_mm) * self.foot_thickness_mm * length
        return volume - math.pi / 4 * self.bore_diameter_mm**2 * length

    def cache_key(self) -> str:
        """SHA-256 over the shape, the mesh size, gmsh's version and the mesher's version."""
        import gmsh

        payload = {"kind": "block", "x_mm": list(self.x_mm), "width_mm": self.width_mm, "bottom_mm": self.bottom_mm,
                   "top_mm": self.top_mm, "bore_diameter_mm": self.bore_diameter_mm,
                   "foot": [self.foot_thickness_mm, self.foot_width_mm], "split_x_mm": list(self.split_x_mm),
                   "mesh_size_mm": self.mesh_size_mm, "gmsh": gmsh.__version__, "mesher_version": MESHER_VERSION,
                   "housing_version": HOUSING_VERSION}
        return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()

    def build_occ_model(self, gmsh) -> None:
        """One slab per interval between breakpoints (box ∪ foot plate − bore), fragmented: conforming volumes
        whose faces are split at every breakpoint."""
        occ = gmsh.model.occ
        volumes = []
        points = self.breakpoints_mm
        for x0, x1 in zip(points[:-1], points[1:]):
            length = x1 - x0
            shape = [(3, occ.addBox(x0, self.bottom_mm, -0.5 * self.width_mm, length, self.top_mm - self.bottom_mm,
                                    self.width_mm))]
            if self.foot_thickness_mm > 0 and self.foot_width_mm > self.width_mm:
                foot = occ.addBox(x0, self.bottom_mm, -0.5 * self.foot_width_mm, length, self.foot_thickness_mm,
                                  self.foot_width_mm)
                shape, _ = occ.fuse(shape, [(3, foot)])
            if self.bore_diameter_mm > 0:
                bore = occ.addCylinder(x0, 0.0, 0.0, length, 0.0, 0.0, 0.5 * self.bore_diameter_mm)
                shape, _ = occ.cut(shape, [(3, bore)])
            volumes.extend(shape)
        if len(volumes) > 1:
            occ.fragment(volumes[:1], volumes[1:])
        occ.synchronize()


@dataclass(frozen=True)
class Reference:
    """A reference node at ``point_mm`` tied to a face: ``("bore", x0, x1)`` (a band of the bore), ``("top", x0, x1)``
    (the part of the top face between x0 and x1) — ``tie`` ``"distributing"`` or ``"rigid"``."""

    point_mm: tuple[float, float, float]
    face: tuple[str, float, float]
    tie: str = "distributing"


def _boundary_facets_where(mesh: skfem.MeshTet2, test) -> np.ndarray:
    facets = mesh.boundary_facets()
    corners = mesh.p[:, mesh.facets[:, facets]] / 1e-3  # (3, 3 corners, n), mm
    keep = np.all(test(corners[0], corners[1], corners[2]), axis=0)
    return facets[keep]


def housing_faces(mesh: skfem.MeshTet2, geometry: BlockGeometry, face: tuple[str, float, float]) -> np.ndarray:
    """Boundary facets of ``face``: ``("bore" | "top" | "bottom", x0, x1)``, every corner within [x0, x1]."""
    kind, x0, x1 = face
    tol = 1e-4 * max(geometry.width_mm, geometry.top_mm - geometry.bottom_mm)

    def along(x):
        return (x >= x0 - _TOL_MM) & (x <= x1 + _TOL_MM)

    if kind == "bore":
        radius = 0.5 * geometry.bore_diameter_mm
        facets = _boundary_facets_where(mesh, lambda x, y, z: along(x) & (np.abs(np.hypot(y, z) - radius) < tol))
    elif kind == "top":
        facets = _boundary_facets_where(mesh, lambda x, y, z: along(x) & (np.abs(y - geometry.top_mm) < tol))
    elif kind == "bottom":
        facets = _boundary_facets_where(mesh, lambda x, y, z: along(x) & (np.abs(y - geometry.bottom_mm) < tol))
    else:
        raise ValueError(f"unknown housing face kind {kind!r} (bore, top, bottom)")
    if facets.size == 0:
        raise ValueError(f"housing '{geometry.name}': no mesh facets on its {kind} face between x = {x0:g} and {x1:g} mm")
    return facets


@dataclass(frozen=True, eq=False)
class HousingModel:
    """The supported solid model of a housing with its reference nodes (DOFs 0 … 6k − 1, solid DOFs after).

    Attributes
    ----------
    stiffness, elimination : csr_matrix
        K (n × n) and T (u = T q): ties and clamped feet eliminated.
    master_dofs : array of int
        The reference nodes' DOFs, 6 per node.
    mesh, basis :
        The solid's mesh and P2 basis (its DOFs start at ``6k``).
    """

    stiffness: sp.csr_matrix
    elimination: sp.csr_matrix
    master_dofs: np.ndarray
    mesh: object
    basis: object

    @property
    def n_dofs(self) -> int:
        return int(self.stiffness.shape[0])


def solid_method() -> str:
    """PARDISO where it is installed (a solid's fill-in makes SuperLU 5–10× slower at 15 k DOFs), else ``auto``."""
    return "pardiso" if pardiso_available() else "auto"


def build_housing_model(geometry: BlockGeometry, youngs_modulus_Pa: float, poisson: float,
                        references: list[Reference], feet: str = "clamped",
                        bed_stiffness_N_per_um_per_mm2: tuple[float, float] | None = None,
                        cache_dir: Path | None = None) -> HousingModel:
    """Mesh ``geometry`` and build its supported model: ``feet`` ``"clamped"`` (the bed face held) or ``"bed"``
    (a Winkler bed of (normal, shear) stiffness per area under the bed face)."""
    mesh = mesh_part(geometry, cache_dir=cache_dir)
    basis = solid.solid_basis(mesh)
    offset = DOFS_PER_NODE * len(references)
    n = offset + int(basis.N)
    pieces = [solid.stiffness_triplets(basis, youngs_modulus_Pa, poisson, dof_offset=offset)]
    bottom = housing_faces(mesh, geometry, ("bottom", *geometry.x_mm))
    fixed = np.zeros(0, dtype=int)
    if feet == "clamped":
        fixed = np.unique(face_nodes(mesh, basis, bottom, offset).dofs.ravel())
    elif feet == "bed":
        normal, shear = (v * 1e12 for v in bed_stiffness_N_per_um_per_mm2)  # N/(µm·mm²) → N/m³
        form = skfem.BilinearForm(lambda u, v, w: normal * u[1] * v[1] + shear * (u[0] * v[0] + u[2] * v[2]))
        bed = form.assemble(solid.facet_basis(mesh, bottom)).tocoo()
        pieces.append((bed.row + offset, bed.col + offset, bed.data))
    else:
        raise ValueError(f"unknown feet {feet!r} (clamped, bed)")
    equations: dict[int, dict[int, float]] = {}
    for i, reference in enumerate(references):
        nodes = face_nodes(mesh, basis, housing_faces(mesh, geometry, reference.face), offset)
        point = np.asarray(reference.point_mm, dtype=float) * 1e-3
        tie = rigid_tie_equations if reference.tie == "rigid" else distributing_tie_equations
        equations.update(tie(i, point, nodes))
    stiffness = assemble_matrix(n, pieces)
    elimination = elimination_matrix(n, fixed, equations)[0]
    return HousingModel(stiffness, elimination, np.arange(offset), mesh, basis)


@dataclass(frozen=True)
class CondensedHousing:
    """A housing's condensed stiffness (6k × 6k, SI: N/m, N/rad, N·m/rad) at its reference nodes.

    ``seconds`` is the time it took (meshing included; near 0 when read from the cache) and ``solid_dofs``
    the size of the solid model it came from.
    """

    matrix: np.ndarray
    solid_dofs: int
    seconds: float
    from_cache: bool


def _cache_file(key: dict, cache_dir: Path | None) -> Path:
    digest = hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()
    directory = (default_cache_dir() if cache_dir is None else Path(cache_dir)) / "housings"
    return directory / f"{digest}.npz"


def _save(path: Path, result: CondensedHousing) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    handle = tempfile.NamedTemporaryFile(dir=path.parent, prefix=path.stem + ".", suffix=".tmp", delete=False)
    try:
        with handle:
            np.savez(handle, matrix=result.matrix, solid_dofs=np.array(result.solid_dofs))
        os.replace(handle.name, path)
    except BaseException:
        Path(handle.name).unlink(missing_ok=True)
        raise


def _load(path: Path) -> CondensedHousing | None:
    try:
        with np.load(path, allow_pickle=False) as data:
            matrix, dofs = np.array(data["matrix"]), int(data["solid_dofs"])
        if matrix.ndim != 2 or matrix.shape[0] != matrix.shape[1] or not np.all(np.isfinite(matrix)):
            raise ValueError("bad matrix")
        return CondensedHousing(matrix, dofs, 0.0, True)
    except FileNotFoundError:
        return None
    except Exception:  # damaged entry: computed again and rewritten
        path.unlink(missing_ok=True)
        return None


def condense_housing(geometry: BlockGeometry, youngs_modulus_Pa: float, poisson: float, references: list[Reference],
                     feet: str = "clamped", bed_stiffness_N_per_um_per_mm2: tuple[float, float] | None = None,
                     cache_dir: Path | None = None, use_cache: bool = True) -> CondensedHousing:
    """The condensed stiffness of a housing at its references (cached by everything it depends on)."""
    key = {"geometry": geometry.cache_key(), "E": youngs_modulus_Pa, "nu": poisson, "feet": feet,
           "bed": list(bed_stiffness_N_per_um_per_mm2 or ()),
           "references": [[list(r.point_mm), list(r.face), r.tie] for r in references]}
    path = _cache_file(key, cache_dir)
    if use_cache:
        cached = _load(path)
        if cached is not None:
            return cached
    start = time.perf_counter()
    model = build_housing_model(geometry, youngs_modulus_Pa, poisson, references, feet, bed_stiffness_N_per_um_per_mm2,
                                cache_dir)
    matrix = condensed_stiffness(model.stiffness, model.elimination, model.master_dofs, solid_method())
    result = CondensedHousing(matrix, int(model.basis.N), time.perf_counter() - start, False)
    if use_cache:
        try:
            _save(path, result)
        except OSError:
            pass  # a read-only cache only costs the next run the condensation
    return result
