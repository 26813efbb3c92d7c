"""Solid mesh of one round part (stepped, hollow shaft along x) as curved quadratic tetrahedra.

The part is built with gmsh's OpenCASCADE kernel: one cylinder (minus its bore) for every interval
between consecutive breakpoints (segment ends and the extra split planes), fragmented together so
that the volumes are conforming and every surface is split at every breakpoint: facets never
straddle a band edge where a load or a bearing attaches. The mesh is second order with mid-edge
nodes on the true (curved) geometry: straight-sided P2 tets overestimate a shaft's deflection by
0.6–2 % (measured on this FE stack when the mesher was chosen). gmsh runs with one thread, so the same geometry
always gives the same mesh.

The mesh of a round part is **mirror-symmetric about the planes z = 0 and y = 0**: gmsh meshes the quarter y ≥ 0,
z ≥ 0 and the quarter is mirrored twice. A part of revolution is symmetric about both planes, and
so is its mesh: a pure torque (odd under either mirror) then cannot move a shaft sideways (even
under one of them). A mesh without that symmetry couples twist and bending at the level of its
discretisation error: on the reference rig's hybrid model a pure output torque moved the output
shaft by 8.4e-12 m per N·m (0.08 % of its Y at 200 N·m with the reference load sharing).

Meshes are cached on disk (compressed ``.npz``, checksummed, written atomically); a corrupt entry
is detected, deleted and rebuilt. Coordinates of the returned mesh are in metres.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import logging
import math
import os
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import skfem

from rvcoax.errors import RvcoaxError
from rvcoax.geometry.units import MM

__all__ = ["MESHER_VERSION", "MIN_SHAPE_QUALITY", "MeshingError", "SolidPartGeometry", "cache_path",
           "check_mesh", "default_cache_dir", "estimate_dofs", "gmsh_session", "logger", "mesh_part", "shape_quality"]

logger = logging.getLogger(__name__)

MESHER_VERSION = 2
"""Bump whenever a change here changes the meshes produced (invalidates every cache entry)."""

_TOL_MM = 1e-6  # breakpoints closer than this are one plane
_ELEMENTS_PER_CIRCLE = 8  # gmsh Mesh.MeshSizeFromCurvature

# a mirror image reverses a tet's orientation; swapping vertices 0 and 1 restores it (edges follow)
_MIRRORED_TET10 = np.array([1, 0, 2, 3, 4, 6, 5, 8, 7, 9])
_QUARTER = 1e5  # mm: half the side of the box that keeps the quarter y ≥ 0, z ≥ 0

# gmsh's 10-node tetrahedron lists the mid-edge nodes of edges (0,1), (1,2), (2,0), (3,0), (3,2),
# (3,1); scikit-fem expects (0,1), (1,2), (0,2), (0,3), (1,3), (2,3): swap the last two.
_GMSH_TO_SKFEM_TET10 = np.array([0, 1, 2, 3, 4, 5, 6, 7, 9, 8])


class MeshingError(RvcoaxError, RuntimeError):
    """gmsh failed, or produced a mesh that cannot be used (inverted curved elements)."""

    stage = "cannot mesh the rig"


@dataclass(frozen=True)
class SolidPartGeometry:
    """A round part on the global x axis, in millimetres.

    Parameters
    ----------
    name : str
        For messages only (not part of the cache key: equal shapes share one cache entry).
    segments : tuple of (x_start_mm, x_end_mm, outer_diameter_mm, inner_diameter_mm)
        Contiguous along x (each segment starts where the previous one ends); inner diameter 0
        for a solid segment.
    split_x_mm : tuple of float
        Extra planes x = const where the volume and its surfaces are split (edges of the bands
        where loads or bearings attach), strictly inside the part.
    mesh_size_mm : float
        Target (largest) element edge length.
    """

    name: str
    segments: tuple[tuple[float, float, float, float], ...]
    split_x_mm: tuple[float, ...] = ()
    mesh_size_mm: float = 5.0

    def __post_init__(self) -> None:
        segments = tuple(tuple(float(v) for v in segment) for segment in self.segments)
        splits = tuple(sorted(float(x) for x in self.split_x_mm))
        object.__setattr__(self, "segments", segments)
        object.__setattr__(self, "split_x_mm", splits)
        object.__setattr__(self, "mesh_size_mm", float(self.mesh_size_mm))
        where = f"part '{self.name}'"
        if not segments:
            raise ValueError(f"{where}: no segments")
        for k, segment in enumerate(segments):
            if len(segment) != 4 or not all(math.isfinite(v) for v in segment):
                raise ValueError(f"{where}, segment {k}: expected 4 finite numbers, got {segment}")
            x0, x1, outer, inner = segment
            if not x1 > x0:
                raise ValueError(f"{where}, segment {k}: x_end {x1} must be > x_start {x0}")
            if not outer > 0.0:
                raise ValueError(f"{where}, segment {k}: outer diameter must be > 0, got {outer}")
            if not 0.0 <= inner < outer:
                raise ValueError(f"{where}, segment {k}: inner diameter must be in [0, {outer}), got {inner}")
            if k and abs(x0 - segments[k - 1][1]) > _TOL_MM:
                raise ValueError(
                    f"{where}: segment {k} starts at x = {x0} mm, the previous one ends at {segments[k - 1][1]} mm"
                )
        start, end = segments[0][0], segments[-1][1]
        for x in splits:
            if not (math.isfinite(x) and start < x < end):
                raise ValueError(f"{where}: split plane x = {x} mm is not strictly inside ({start}, {end}) mm")
        if not (math.isfinite(self.mesh_size_mm) and self.mesh_size_mm > 0.0):
            raise ValueError(f"{where}: mesh size must be > 0, got {self.mesh_size_mm}")

    @property
    def breakpoints_mm(self) -> tuple[float, ...]:
        """Sorted planes x = const bounding the meshed intervals (segment ends and split planes)."""
        candidates = sorted([s[0] for s in self.segments] + [self.segments[-1][1]] + list(self.split_x_mm))
        merged = [candidates[0]]
        for x in candidates[1:]:
            if x - merged[-1] > _TOL_MM:
                merged.append(x)
        return tuple(merged)

    def section_at(self, x_mm: float) -> tuple[float, float]:
        """(outer, inner) diameter in mm of the segment containing ``x_mm`` (first one on a boundary)."""
        for x0, x1, outer, inner in self.segments:
            if x0 - _TOL_MM <= x_mm <= x1 + _TOL_MM:
                return outer, inner
        raise ValueError(f"x = {x_mm} mm is outside part '{self.name}'")

    @property
    def volume_mm3(self) -> float:
        """Exact volume of the part."""
        return sum(math.pi / 4.0 * (o * o - i * i) * (x1 - x0) for x0, x1, o, i in self.segments)

    def cache_key(self) -> str:
        """SHA-256 over the shape, the mesh size, gmsh's version and :data:`MESHER_VERSION`."""
        import gmsh

        payload = {
            "segments": [list(s) for s in self.segments],
            "split_x_mm": list(self.split_x_mm),
            "mesh_size_mm": self.mesh_size_mm,
            "gmsh": gmsh.__version__,
            "mesher_version": MESHER_VERSION,
        }
        return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()


# --------------------------------------------------------------------------------------------- cache


def default_cache_dir() -> Path:
    """``$RVCOAX_CACHE_DIR`` if set, else ``~/.cache/rvcoax/meshes``."""
    env = os.environ.get("RVCOAX_CACHE_DIR")
    return Path(env) if env else Path.home() / ".cache" / "rvcoax" / "meshes"


def cache_path(geometry: SolidPartGeometry, cache_dir: Path | None = None) -> Path:
    """The cache file of ``geometry`` (whether or not it exists)."""
    directory = default_cache_dir() if cache_dir is None else Path(cache_dir)
    return directory / f"{geometry.cache_key()}.npz"


def _checksum(doflocs: np.ndarray, t: np.ndarray) -> str:
    digest = hashlib.sha256()
    for array in (doflocs, t):
        digest.update(f"{array.dtype.str}{array.shape}".encode())
        digest.update(np.ascontiguousarray(array).tobytes())
    return digest.hexdigest()


def _write_cache(path: Path, mesh: skfem.MeshTet2) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    doflocs, t = np.ascontiguousarray(mesh.doflocs), np.ascontiguousarray(mesh.t)
    handle = tempfile.NamedTemporaryFile(dir=path.parent, prefix=path.stem + ".", suffix=".tmp", delete=False)
    try:
        with handle:
            np.savez_compressed(handle, doflocs=doflocs, t=t, checksum=np.array(_checksum(doflocs, t)))
            handle.flush()
            os.fsync(handle.fileno())
        os.chmod(handle.name, 0o644)  # mkstemp creates 0600
        os.replace(handle.name, path)
    except BaseException:
        Path(handle.name).unlink(missing_ok=True)
        raise


def _read_cache(path: Path) -> skfem.MeshTet2 | None:
    """The cached mesh, or None when absent; a damaged entry is deleted (and None returned)."""
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            doflocs, t, checksum = data["doflocs"], data["t"], str(data["checksum"])
        if checksum != _checksum(doflocs, t) or doflocs.ndim != 2 or doflocs.shape[0] != 3 or t.shape[0] != 4:
            raise ValueError("checksum or shape mismatch")
        mesh = skfem.MeshTet2(doflocs, t)
        check_mesh(mesh, path.stem)
        return mesh
    except Exception as error:  # truncated zip, missing key, bad checksum, inverted elements, ...
        logger.warning("mesh cache entry %s is damaged (%s): deleted, meshing again", path, error)
        path.unlink(missing_ok=True)
        return None


# ------------------------------------------------------------------------------------------- meshing


def _build_occ_model(gmsh, geometry: SolidPartGeometry) -> None:
    occ = gmsh.model.occ
    volumes = []
    breakpoints = geometry.breakpoints_mm
    for x0, x1 in zip(breakpoints[:-1], breakpoints[1:]):
        outer, inner = geometry.section_at(0.5 * (x0 + x1))
        volume = (3, occ.addCylinder(x0, 0.0, 0.0, x1 - x0, 0.0, 0.0, 0.5 * outer))
        if inner > 0.0:
            bore = occ.addCylinder(x0, 0.0, 0.0, x1 - x0, 0.0, 0.0, 0.5 * inner)
            volume = occ.cut([volume], [(3, bore)])[0][0]
        box = occ.addBox(x0 - 1.0, 0.0, 0.0, x1 - x0 + 2.0, _QUARTER, _QUARTER)
        quarter, _ = occ.intersect([volume], [(3, box)])
        volumes.extend(quarter)
    if len(volumes) > 1:
        occ.fragment(volumes[:1], volumes[1:])
    occ.synchronize()


def _gmsh_tet10(gmsh) -> tuple[np.ndarray, np.ndarray]:
    """Node coordinates (3, n) in mm and 10-node tets (10, n_tets) in scikit-fem's node order."""
    node_tags, coordinates, _ = gmsh.model.mesh.getNodes()
    element_types, _, element_nodes = gmsh.model.mesh.getElements(3)
    tet10 = gmsh.model.mesh.getElementType("Tetrahedron", 2)
    if list(element_types) != [tet10]:
        raise MeshingError(f"expected only 10-node tetrahedra, gmsh produced element types {list(element_types)}")
    index = np.full(int(node_tags.max()) + 1, -1, dtype=np.int64)
    index[node_tags.astype(np.int64)] = np.arange(node_tags.size)
    t = index[np.asarray(element_nodes[0], dtype=np.int64).reshape(-1, 10)][:, _GMSH_TO_SKFEM_TET10]
    if np.any(t < 0):
        raise MeshingError("a tetrahedron refers to a node gmsh did not list")
    return coordinates.reshape(-1, 3).T, t.T


def _mirrored(coordinates_mm: np.ndarray, t: np.ndarray, axis: int) -> tuple[np.ndarray, np.ndarray]:
    """The mesh and its mirror image about the plane ``coordinate[axis] = 0``, joined at that plane."""
    extent = np.abs(coordinates_mm).max()
    on_plane = np.abs(coordinates_mm[axis]) <= 1e-9 * extent
    coordinates_mm = coordinates_mm.copy()
    coordinates_mm[axis, on_plane] = 0.0
    if np.any(coordinates_mm[axis] < 0.0):
        raise MeshingError("the quarter mesh reaches past its symmetry plane")
    n = coordinates_mm.shape[1]
    off_plane = np.flatnonzero(~on_plane)
    image = np.arange(n)
    image[off_plane] = n + np.arange(off_plane.size)
    mirror = coordinates_mm[:, off_plane].copy()
    mirror[axis] *= -1.0
    return np.hstack([coordinates_mm, mirror]), np.hstack([t, image[t][_MIRRORED_TET10]])


def _symmetric(coordinates_mm: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The quarter y ≥ 0, z ≥ 0 mirrored about z = 0, then the half about y = 0."""
    return _mirrored(*_mirrored(coordinates_mm, t, 2), 1)


def _to_skfem(coordinates_mm: np.ndarray, t: np.ndarray) -> skfem.MeshTet2:
    return skfem.MeshTet2(np.ascontiguousarray(coordinates_mm * MM), np.ascontiguousarray(t))


def _inverted_elements(mesh: skfem.MeshTet2) -> np.ndarray:
    """Indices of curved tets whose Jacobian determinant changes sign over their 10 nodes."""
    det = mesh._mapping().detDF(skfem.ElementTetP2().doflocs.T)  # (n_tets, 10)
    return np.flatnonzero(det.min(axis=1) * det.max(axis=1) <= 0.0)


MIN_SHAPE_QUALITY = 1e-3
"""Tets of their vertices' shape quality 6√2 V / l_rms³ below this (1 = regular; gmsh's are > 0.05) are
degenerate: flat or needle-like, with a stiffness matrix that is numerically singular."""


def shape_quality(mesh: skfem.MeshTet2) -> np.ndarray:
    """Shape quality 6√2 V / l_rms³ of each tet's straight vertex tetrahedron (1 regular, 0 flat); signed by V."""
    corners = mesh.p[:, mesh.t]  # (3, 4, n_tets)
    a, b, c = (corners[:, k] - corners[:, 0] for k in (1, 2, 3))
    volume = np.einsum("ij,ij->j", a, np.cross(b, c, axis=0)) / 6.0
    pairs = ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))
    squares = sum(np.sum((corners[:, i] - corners[:, j]) ** 2, axis=0) for i, j in pairs) / 6.0
    return 6.0 * np.sqrt(2.0) * volume / np.maximum(squares, 1e-300) ** 1.5


def check_mesh(mesh: skfem.MeshTet2, name: str) -> None:
    """Raise :class:`MeshingError` naming part ``name`` when a curved tet is inverted (its Jacobian changes
    sign or vanishes) or degenerate (|shape quality| below :data:`MIN_SHAPE_QUALITY`)."""
    problems = []
    inverted = _inverted_elements(mesh)
    if inverted.size:
        problems.append(f"{inverted.size} curved tetrahedra are inverted (Jacobian changes sign or vanishes, first "
                        f"element {int(inverted[0])})")
    quality = np.abs(shape_quality(mesh))
    degenerate = np.flatnonzero(quality < MIN_SHAPE_QUALITY)
    if degenerate.size:
        problems.append(f"{degenerate.size} tetrahedra are degenerate (shape quality down to {quality.min():.1e} < "
                        f"{MIN_SHAPE_QUALITY:g}: flat or needle-like, first element {int(degenerate[0])})")
    if problems:
        raise MeshingError(f"part '{name}': " + "; ".join(problems) + "; use a smaller mesh size (or set the "
                           "part's mesh_size_mm)")


@contextlib.contextmanager
def gmsh_session(model: str):
    """gmsh with a model of our own, quiet and on one thread (two threads give different node counts per run).

    gmsh is a process-wide singleton: if someone else has initialised it, work in a model of our own and remove it
    afterwards (our options stay set); otherwise initialise and always finalise. Yields the ``gmsh`` module.
    """
    import gmsh

    owner = not gmsh.isInitialized()
    if owner:
        # gmsh's SIGINT handler can only be installed from the main thread
        gmsh.initialize(readConfigFiles=False, interruptible=threading.current_thread() is threading.main_thread())
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.Verbosity", 2)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add(model)
        yield gmsh
    finally:
        if owner:
            gmsh.finalize()
        elif gmsh.isInitialized():
            gmsh.model.remove()


def _run_gmsh(geometry: SolidPartGeometry) -> skfem.MeshTet2:
    """Mesh with gmsh (in a :func:`gmsh_session` of its own)."""
    try:
        with gmsh_session(geometry.name or "part") as gmsh:
            # a geometry that is not a round part (a housing) builds its own, whole OpenCASCADE model; a
            # round part is built as its quarter y ≥ 0, z ≥ 0 and mirrored twice once meshed
            own_model = getattr(geometry, "build_occ_model", None)
            if own_model is not None:
                own_model(gmsh)
            else:
                _build_occ_model(gmsh, geometry)

            def whole(coordinates_mm, t):
                return (coordinates_mm, t) if own_model is not None else _symmetric(coordinates_mm, t)

            gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
            # at least ~8 elements around every circle: a small bore under a coarse size would otherwise
            # give intersecting facets (gmsh "PLC Error") or inverted curved tets
            gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", _ELEMENTS_PER_CIRCLE)
            gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
            gmsh.option.setNumber("Mesh.MeshSizeMax", geometry.mesh_size_mm)
            gmsh.option.setNumber("Mesh.ElementOrder", 2)
            gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)  # mid-edge nodes on the curved geometry
            gmsh.model.mesh.generate(3)
            mesh = _to_skfem(*whole(*_gmsh_tet10(gmsh)))
            if _inverted_elements(mesh).size:
                # curving boundary edges of coarse tets can invert them; gmsh's high-order optimiser
                # moves the interior high-order nodes (cheap, deterministic, only needed when coarse)
                gmsh.model.mesh.optimize("HighOrder")
                mesh = _to_skfem(*whole(*_gmsh_tet10(gmsh)))
    except MeshingError:
        raise
    except Exception as error:
        raise MeshingError(f"gmsh failed to mesh part '{geometry.name}': {error}") from error
    check_mesh(mesh, geometry.name)
    return mesh


def mesh_part(
    geometry: SolidPartGeometry, cache_dir: Path | None = None, use_cache: bool = True
) -> skfem.MeshTet2:
    """Curved quadratic tetrahedral mesh of ``geometry``, coordinates in metres.

    Parameters
    ----------
    geometry : SolidPartGeometry
    cache_dir : Path, optional
        Where cached meshes live; None: :func:`default_cache_dir`.
    use_cache : bool
        False: neither read nor write the cache (always run gmsh).

    Returns
    -------
    skfem.MeshTet2
        Vertex nodes first, then one mid-edge node per edge (scikit-fem's order), in metres.

    Raises
    ------
    MeshingError
        When gmsh fails or a curved element is inverted.
    """
    path = cache_path(geometry, cache_dir) if use_cache else None
    if path is not None:
        cached = _read_cache(path)
        if cached is not None:
            return cached
    mesh = _run_gmsh(geometry)
    if path is not None:
        try:
            _write_cache(path, mesh)
        except OSError as error:
            logger.warning("could not write mesh cache entry %s: %s", path, error)
    return mesh


# Fit to gmsh 4.15 (one thread, curvature sizing as above) on 6 solid, hollow and stepped shafts with
# h = 2–15 mm (35 meshes of 1.3 k–184 k nodes): estimate / actual node count within 0.82–1.28.
_NODES_PER_VOLUME = 6.3
_NODES_PER_AREA = 7.7
# Coarse meshes (few elements across a part, split planes, the mirror planes of a quarter mesh) have far
# more surface nodes than that: a second fit, on the 13 parts of the all-solid reference rig at global
# sizes 3–16 mm (78 mirrored meshes, 7.8 k–391 k DOF), of which the estimate takes the larger.
_COARSE_NODES_PER_VOLUME = 2.0
_COARSE_NODES_PER_AREA = 17.0


def _surface_size(h: float, diameter: float) -> float:
    """Element size gmsh uses on a cylinder of ``diameter``: h, or less on small circles."""
    return min(h, math.pi * diameter / _ELEMENTS_PER_CIRCLE) if diameter > 0.0 else h


def estimate_dofs(geometry: SolidPartGeometry) -> int:
    """Rough number of P2 displacement DOFs :func:`mesh_part` will produce (no meshing).

    ``DOFs ≈ 3 Σ_segments (a V / h_v³ + b Σ_surfaces A / h_s²)``, with h_s = min(h, π D / 8) the
    size on a cylinder of diameter D (gmsh's curvature sizing), h_v = √(h_outer h_bore) the size
    inside a segment (h_bore = h for a solid one), end faces and shoulder rings meshed at the
    smaller size of their segment, and a = 6.3, b = 7.7 nodes: 1.3 × the values fitted to gmsh's
    output (vertices plus mid-edge nodes) before meshes were mirrored from a quarter, which adds
    21–34 % (reference rig, 4 mm: the two shafts 108,981 DOF, estimated 95,248). Coarse meshes have
    more surface nodes than that: the estimate is the larger of it and the same sum with a = 2.0,
    b = 17.0 nodes, fitted on the mirrored meshes of the all-solid reference rig's 13 parts at global
    sizes 3–16 mm. Within a factor of 1.3 for shafts at h = 2–15 mm; for the whole all-solid
    reference rig within 0.96–1.07 of the actual total from 3 to 16 mm (16 mm: 142,194 DOF, estimated
    133 k, 83 k before the coarse fit; 3 mm: 893,106, estimated 872 k), parts within 0.71–1.45.
    Use it to warn before building a huge model.
    """
    h = geometry.mesh_size_mm
    segments = geometry.segments
    volume_term = surface_term = 0.0
    for k, (x0, x1, outer, inner) in enumerate(segments):
        h_outer, h_bore = _surface_size(h, outer), _surface_size(h, inner)
        volume_term += math.pi / 4.0 * (outer**2 - inner**2) * (x1 - x0) / (h_outer * h_bore) ** 1.5
        surface_term += math.pi * (x1 - x0) * (outer / h_outer**2 + inner / h_bore**2)
        face = math.pi / 4.0 * (outer**2 - inner**2) / min(h_outer, h_bore) ** 2
        surface_term += face * ((k == 0) + (k == len(segments) - 1))
        if k:
            previous_outer, previous_inner = segments[k - 1][2], segments[k - 1][3]
            surface_term += math.pi / 4.0 * abs(outer**2 - previous_outer**2) / h_outer**2
            surface_term += math.pi / 4.0 * abs(inner**2 - previous_inner**2) / h_bore**2
    fine = _NODES_PER_VOLUME * volume_term + _NODES_PER_AREA * surface_term
    coarse = _COARSE_NODES_PER_VOLUME * volume_term + _COARSE_NODES_PER_AREA * surface_term
    return int(round(3.0 * max(fine, coarse)))
