"""A ``[[housings]]`` entry's finite-element half: its supported solid model, condensed to a superelement, cached.

The shape (:mod:`rvcoax.geometry.housings`) is meshed into curved quadratic tetrahedra
(:func:`rvcoax.geometry.meshing.mesh_part`, cached by content hash); its feet are clamped or sit on an elastic bed
(a Winkler foundation: normal and shear stiffness per area), and one 6-DOF reference node per attachment is tied
to a face. Every piece (the solid, the bed under each foot, the ties, the clamped feet) is a
:class:`rvcoax.fem.pieces.Contribution` summed by :func:`rvcoax.fem.pieces.assemble`; the supported model is then
reduced to the reference nodes (:mod:`rvcoax.fem.condensation`): a 6k × 6k stiffness against the ground that
enters the rig like a bushing (:mod:`rvcoax.geometry.model.housings`). The condensed matrix is cached too, keyed
by everything it depends on.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import skfem

from rvcoax.fem import DOFS_PER_NODE, solid
from rvcoax.fem.assembly import block_diagonal
from rvcoax.fem.condensation import guyan_reduction
from rvcoax.fem.craig_bampton import CraigBampton, craig_bampton_reduction
from rvcoax.fem.pieces import Contribution, assemble, tie_contribution
from rvcoax.fem.solvers import pardiso_available
from rvcoax.fem.ties import distributing_tie_equations, face_nodes, rigid_tie_equations
from rvcoax.geometry.housings import HousingGeometry, Reference, foot_facets, housing_faces
from rvcoax.geometry.meshing import default_cache_dir, mesh_part

__all__ = ["INTERFACE_CANDIDATES", "CondensedHousing", "HousingModel", "build_housing_model", "condense_housing",
           "housing_craig_bampton", "solid_method"]

INTERFACE_CANDIDATES = 12
"""Fixed-interface modes computed (and cached) per housing: the automatic rule keeps those it needs of them."""


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


def build_housing_model(geometry: HousingGeometry, youngs_modulus_Pa: float, poisson: float,  # noqa: PLR0913
                        references: list[Reference], feet: str = "clamped",
                        *, bed_stiffness_N_per_um_per_mm2: tuple[float, float] | None = None,
                        cache_dir: Path | None = None) -> HousingModel:
    """Mesh ``geometry`` and build its supported model: ``feet`` ``"clamped"`` (the feet held) or ``"bed"`` (a
    Winkler bed of (normal, shear) stiffness per area under the feet; normal along the feet's normal, shear in
    their plane)."""
    mesh = mesh_part(geometry, cache_dir=cache_dir)
    basis = solid.solid_basis(mesh)
    offset = DOFS_PER_NODE * len(references)
    pieces = [Contribution(solid.stiffness_triplets(basis, youngs_modulus_Pa, poisson, dof_offset=offset))]
    pieces += _support_contributions(mesh, basis, geometry, offset, (feet, bed_stiffness_N_per_um_per_mm2))
    for i, reference in enumerate(references):
        nodes = face_nodes(mesh, basis, housing_faces(mesh, geometry, reference.face), offset)
        point = np.asarray(reference.point_mm, dtype=float) * 1e-3
        tie = rigid_tie_equations if reference.tie == "rigid" else distributing_tie_equations
        pieces.append(tie_contribution(tie(i, point, nodes)))
    system = assemble(offset + int(basis.N), pieces)
    return HousingModel(system.stiffness, system.elimination, np.arange(offset), mesh, basis)


def _support_contributions(mesh, basis, geometry: HousingGeometry, offset: int, support: tuple) -> list[Contribution]:
    """The feet held (``support`` = ("clamped", None): their DOFs fixed) or on a Winkler bed (("bed", (normal,
    shear) stiffness per area in N/(µm·mm²)): a stiffness per foot); the solid's DOFs start at ``offset``."""
    feet, bed_stiffness_N_per_um_per_mm2 = support
    if feet == "clamped":
        bottom = np.concatenate(foot_facets(mesh, geometry))
        return [Contribution(fixed_dofs=np.unique(face_nodes(mesh, basis, bottom, offset).dofs.ravel()))]
    if feet != "bed":
        raise ValueError(f"unknown feet {feet!r} (clamped, bed)")
    normal, shear = (v * 1e12 for v in bed_stiffness_N_per_um_per_mm2)  # N/(µm·mm²) → N/m³
    pieces = []
    for foot, facets in zip(geometry.feet, foot_facets(mesh, geometry)):
        k = np.full(3, shear)
        k[foot.axis] = normal
        form = skfem.BilinearForm(lambda u, v, w, k=k: k[0] * u[0] * v[0] + k[1] * u[1] * v[1] + k[2] * u[2] * v[2])
        bed = form.assemble(solid.facet_basis(mesh, facets)).tocoo()
        pieces.append(Contribution((bed.row + offset, bed.col + offset, bed.data)))
    return pieces


@dataclass(frozen=True)
class CondensedHousing:
    """A housing's condensed stiffness (6k × 6k, SI: N/m, N/rad, N·m/rad) at its reference nodes, and its weight.

    ``weight_load`` (6k,) is the master load equivalent to the solid's own weight for a density of 1 kg/m³ under
    1 m/s² along −y (N per kg/m³ per m/s²; :func:`rvcoax.fem.condensation.condensed_stiffness_and_loads`);
    ``volume_m3`` and ``centroid_m`` are the meshed solid's. ``seconds`` is the time it took (meshing included;
    near 0 when read from the cache) and ``solid_dofs`` the size of the solid model it came from.
    """

    matrix: np.ndarray
    solid_dofs: int
    seconds: float
    from_cache: bool
    weight_load: np.ndarray | None = None
    volume_m3: float = 0.0
    centroid_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    mass_per_density: np.ndarray | None = None  # Guyan's M_c (6k × 6k) for 1 kg/m³ (fem.condensation.guyan_reduction)
    lowest_eigenvalue_per_density: float = 0.0  # ω² of the housing on its bed (references free) × ρ, in (rad/s)² kg/m³

    def lowest_frequency_hz(self, density_kg_per_m3: float) -> float:
        """The housing's lowest natural frequency on its bed (Hz): Guyan's mass leaves out what happens above it."""
        return float(np.sqrt(self.lowest_eigenvalue_per_density / density_kg_per_m3) / (2 * np.pi))


def _cache_file(key: dict, cache_dir: Path | None) -> Path:
    digest = hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()
    directory = (default_cache_dir() if cache_dir is None else Path(cache_dir)) / "housings"
    return directory / f"{digest}.npz"


def _save(path: Path, result: CondensedHousing) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    handle = tempfile.NamedTemporaryFile(dir=path.parent, prefix=path.stem + ".", suffix=".tmp", delete=False)
    try:
        with handle:
            np.savez(handle, matrix=result.matrix, solid_dofs=np.array(result.solid_dofs), weight_load=result.weight_load,
                     volume_m3=np.array(result.volume_m3), centroid_m=np.array(result.centroid_m),
                     mass_per_density=result.mass_per_density,
                     lowest_eigenvalue_per_density=np.array(result.lowest_eigenvalue_per_density))
        os.replace(handle.name, path)
    except BaseException:
        Path(handle.name).unlink(missing_ok=True)
        raise


def _load(path: Path) -> CondensedHousing | None:
    try:
        with np.load(path, allow_pickle=False) as data:
            matrix, dofs = np.array(data["matrix"]), int(data["solid_dofs"])
            weight, volume, centroid = np.array(data["weight_load"]), float(data["volume_m3"]), np.array(data["centroid_m"])
            mass, lowest = np.array(data["mass_per_density"]), float(data["lowest_eigenvalue_per_density"])
        if matrix.ndim != 2 or matrix.shape[0] != matrix.shape[1] or not np.all(np.isfinite(matrix)):
            raise ValueError("bad matrix")
        if weight.shape != (matrix.shape[0],) or centroid.shape != (3,) or mass.shape != matrix.shape:
            raise ValueError("bad weight or mass")
        return CondensedHousing(matrix=matrix, solid_dofs=dofs, seconds=0.0, from_cache=True, weight_load=weight,
                                volume_m3=volume, centroid_m=tuple(float(c) for c in centroid), mass_per_density=mass,
                                lowest_eigenvalue_per_density=lowest)
    except FileNotFoundError:
        return None
    except Exception:  # damaged entry: computed again and rewritten
        path.unlink(missing_ok=True)
        return None


def condense_housing(geometry: HousingGeometry, youngs_modulus_Pa: float, poisson: float, references: list[Reference],  # noqa: PLR0913
                     feet: str = "clamped", *, bed_stiffness_N_per_um_per_mm2: tuple[float, float] | None = None,
                     cache_dir: Path | None = None, use_cache: bool = True,
                     compute: bool = True) -> CondensedHousing | None:
    """The condensed stiffness of a housing at its references (cached by everything it depends on); with
    ``compute=False`` only what the cache holds (None when it does not hold it)."""
    key = {"geometry": geometry.cache_key(), "E": youngs_modulus_Pa, "nu": poisson, "feet": feet,
           "bed": list(bed_stiffness_N_per_um_per_mm2 or ()),
           "references": [[list(r.point_mm), list(r.face), r.tie] for r in references]}
    path = _cache_file(key, cache_dir)
    if use_cache:
        cached = _load(path)
        if cached is not None:
            return cached
    if not compute:
        return None
    start = time.perf_counter()
    model = build_housing_model(geometry, youngs_modulus_Pa, poisson, references, feet, bed_stiffness_N_per_um_per_mm2=bed_stiffness_N_per_um_per_mm2,
                                cache_dir=cache_dir)
    weight = np.zeros(model.n_dofs)
    weight[model.master_dofs.size:] = solid.body_force_vector(model.basis, 1.0, np.array([0.0, -1.0, 0.0]))
    mass = block_diagonal(model.n_dofs, [(model.master_dofs.size, solid.mass_matrix(model.basis, 1.0))])
    reduction = guyan_reduction(model.stiffness, model.elimination, model.master_dofs, weight, mass=mass,
                                method=solid_method())
    matrix, equivalent = reduction.stiffness, reduction.loads
    volume = float(skfem.Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(model.basis))
    centroid = tuple(float(skfem.Functional(lambda w, i=i: w.x[i]).assemble(model.basis)) / volume for i in range(3))
    result = CondensedHousing(matrix=matrix, solid_dofs=int(model.basis.N), seconds=time.perf_counter() - start,
                              from_cache=False, weight_load=equivalent[:, 0], volume_m3=volume, centroid_m=centroid,
                              mass_per_density=reduction.mass, lowest_eigenvalue_per_density=reduction.lowest_eigenvalue)
    if use_cache:
        try:
            _save(path, result)
        except OSError:
            pass  # a read-only cache only costs the next run the condensation
    return result


def housing_craig_bampton(geometry: HousingGeometry, youngs_modulus_Pa: float, poisson: float,  # noqa: PLR0913
                          references: list[Reference], feet: str = "clamped", *,
                          bed_stiffness_N_per_um_per_mm2: tuple[float, float] | None = None,
                          n_modes: int = INTERFACE_CANDIDATES, cache_dir: Path | None = None,
                          use_cache: bool = True) -> CraigBampton:
    """The housing's Craig–Bampton reduction (:func:`rvcoax.fem.craig_bampton.craig_bampton_reduction`) at its
    references with ``n_modes`` fixed-interface modes, for a density of 1 kg/m³ (M_cb scales with the density, the
    fixed-interface eigenvalues with its inverse); cached by everything it depends on. Fewer modes are its
    truncation (:meth:`CraigBampton.truncated`)."""
    key = {"geometry": geometry.cache_key(), "E": youngs_modulus_Pa, "nu": poisson, "feet": feet,
           "bed": list(bed_stiffness_N_per_um_per_mm2 or ()),
           "references": [[list(r.point_mm), list(r.face), r.tie] for r in references],
           "craig_bampton_modes": int(n_modes)}
    path = _cache_file(key, cache_dir)
    if use_cache:
        try:
            with np.load(path, allow_pickle=False) as data:
                cached = CraigBampton(np.array(data["stiffness"]), np.array(data["interface_eigenvalues"]),
                                      np.array(data["mass"]))
            if cached.mass.shape == (cached.stiffness.shape[0] + cached.n_modes,) * 2:
                return cached
        except (OSError, KeyError, ValueError):
            path.unlink(missing_ok=True)
    model = build_housing_model(geometry, youngs_modulus_Pa, poisson, references, feet,
                                bed_stiffness_N_per_um_per_mm2=bed_stiffness_N_per_um_per_mm2, cache_dir=cache_dir)
    mass = block_diagonal(model.n_dofs, [(model.master_dofs.size, solid.mass_matrix(model.basis, 1.0))])
    free = model.elimination.shape[1] - model.master_dofs.size
    result = craig_bampton_reduction(model.stiffness, model.elimination, model.master_dofs, mass, min(n_modes, free),
                                     method=solid_method())
    if use_cache:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            handle = tempfile.NamedTemporaryFile(dir=path.parent, prefix=path.stem + ".", suffix=".tmp", delete=False)
            with handle:
                np.savez(handle, stiffness=result.stiffness, interface_eigenvalues=result.interface_eigenvalues,
                         mass=result.mass)
            os.replace(handle.name, path)
        except OSError:
            pass  # a read-only cache only costs the next run the reduction
    return result
