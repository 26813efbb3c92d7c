"""Linear elasticity on curved quadratic tetrahedra (scikit-fem ``MeshTet2``), vectorised.

Element matrices are computed with numpy from the basis gradients scikit-fem evaluates at the
quadrature points (same numbers as scikit-fem's ``BilinearForm`` to 1e-16, about 15× faster; with
the COO → CSR conversion, which then dominates, 3× faster overall: 0.7 s vs 2.2 s at 46 k DOF)
and returned as COO triplets like every other model piece (:mod:`rvcoax.fem.assembly`). Units are SI:
coordinates in m, moduli in Pa, forces in N.

DOF numbering (scikit-fem 12, ``ElementVector(ElementTetP2())``): **interleaved per node**. The
P2 nodes are the mesh vertices (``0 … n_vertices − 1``) followed by one mid-edge node per edge,
in the order of ``mesh.doflocs``; node k carries DOFs ``3k, 3k + 1, 3k + 2`` = (u_x, u_y, u_z).
:func:`dof_locations` returns this table, and a test pins the convention down.

Quadrature: ``intorder = 2`` (4 points per tet). For straight-sided P2 tets it integrates the
stiffness exactly. For the curved tets of round shafts the tip-load energy of a cantilever
differs from ``intorder = 4`` (11 points) by 6e-6 (solid bar, h = D/5) to 3e-5 (tube, h = 8 mm)
and 4e-4 on a very coarse mesh (h = 0.4 D), always far below the discretisation error (0.2–1 %
between successive meshes), at about half the assembly time (tests/test_solid.py checks 1e-4).

Load vectors (body force, tractions) are full-length vectors in the same numbering; add the
solid's DOF offset when placing them in a larger model.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import skfem
from scipy.spatial import cKDTree

__all__ = ["DEFAULT_INTORDER", "ElasticMaterial", "FACET_INTORDER", "body_force_vector", "dof_components", "dof_locations",
           "facet_basis", "force_traction_vector", "lame_parameters", "logger", "mass_matrix", "MASS_INTORDER", "PARALLEL_MIN_ELEMENTS",
           "probe_matrix", "solid_basis", "stiffness_matrix", "stiffness_triplets", "stress_at_nodes",
           "torque_traction_vector", "von_mises", "von_mises_at_nodes"]

logger = logging.getLogger(__name__)

DEFAULT_INTORDER = 2
MASS_INTORDER = 4  # ρ Nₐ N_b is of degree 4 on a straight P2 tet: the 4-point rule would leave the mass rank-deficient
FACET_INTORDER = 4  # surface integrals are cheap: integrate curved facets accurately
_N_P2 = 10  # scalar P2 functions per tet
_CHUNK_ELEMENTS = 512  # element matrices are computed in blocks of this many tets (~4 MB temporaries)
PARALLEL_MIN_ELEMENTS = 4 * _CHUNK_ELEMENTS
"""From this many tets on, :func:`stiffness_matrix` computes its blocks on worker threads."""


@dataclass(frozen=True)
class ElasticMaterial:
    """An isotropic linear-elastic material (SI): what a solid part's stiffness, weight and mass need.

    Attributes
    ----------
    youngs_modulus_Pa : float
    poisson : float
        Poisson's ratio.
    density_kg_per_m3 : float
    """

    youngs_modulus_Pa: float
    poisson: float
    density_kg_per_m3: float


def lame_parameters(youngs_modulus_Pa: float, poisson: float) -> tuple[float, float]:
    """(λ, μ) from E and ν."""
    if not youngs_modulus_Pa > 0.0:
        raise ValueError(f"Young's modulus must be > 0, got {youngs_modulus_Pa}")
    if not -1.0 < poisson < 0.5:
        raise ValueError(f"Poisson's ratio must be in (-1, 0.5), got {poisson}")
    lam = youngs_modulus_Pa * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson))
    mu = youngs_modulus_Pa / (2.0 * (1.0 + poisson))
    return lam, mu


class _JacobianOnce:
    """A mesh mapping whose inverse Jacobian is computed once per set of points.

    scikit-fem's vector basis evaluates each of its 30 functions separately, and each evaluation
    asks the mapping for the inverse Jacobian at the same quadrature points: 30 identical
    computations, 0.11 of the 0.19 s a basis takes at 53 k DOF. This wrapper keeps the latest
    result (with references to its arguments, so identity cannot be confused) and delegates
    everything else; the basis gets the plain mapping back once it is built.
    """

    def __init__(self, mapping) -> None:
        self._mapping = mapping
        self._latest = None

    def invDF(self, X, tind=None):  # noqa: N802, N803 - scikit-fem's names
        latest = self._latest
        if latest is not None and latest[0] is X and latest[1] is tind:
            return latest[2]
        result = self._mapping.invDF(X, tind)
        self._latest = (X, tind, result)
        return result

    def __getattr__(self, name):
        return getattr(self._mapping, name)


def solid_basis(mesh: skfem.MeshTet2, intorder: int = DEFAULT_INTORDER) -> skfem.CellBasis:
    """Vector P2 basis (``ElementVector(ElementTetP2())``) on a (curved) quadratic tet mesh."""
    mapping = mesh.mapping()
    basis = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTetP2()), mapping=_JacobianOnce(mapping),
                        intorder=intorder)
    basis.mapping = mapping
    return basis


def _scalar_values(basis) -> np.ndarray:
    """Values of the 10 scalar P2 functions at the quadrature points, shape (10, n_elements, n_points)."""
    return np.stack([np.asarray(basis.basis[3 * a][0])[0] for a in range(_N_P2)])


def _check_vector_p2(basis) -> None:
    elem = basis.elem
    if not (isinstance(elem, skfem.ElementVector) and isinstance(elem.elem, skfem.ElementTetP2) and elem.dim == 3):
        raise TypeError(f"expected a basis of ElementVector(ElementTetP2()), got {type(elem).__name__}")


def _element_stiffness_into(out: np.ndarray, grads: np.ndarray, dx: np.ndarray, lam: float, mu: float) -> None:
    """Write element matrices into ``out`` (n, 900) from scalar gradients (10, 3, n, q) and weights (n, q)."""
    n = grads.shape[2]
    b = grads.transpose(2, 3, 0, 1).reshape(n, -1, 3 * _N_P2)  # (e, q, 30), column 3 a + i = ∂ᵢNₐ
    c = np.matmul((b * dx[:, :, None]).transpose(0, 2, 1), b).reshape(n, _N_P2, 3, _N_P2, 3)  # ∫ ∂ᵢNₐ ∂ⱼN_b
    k = out.reshape(n, _N_P2, 3, _N_P2, 3)
    np.multiply(c, lam, out=k)
    k += mu * c.transpose(0, 1, 4, 3, 2)
    laplace = mu * np.einsum("eakbk->eab", c)
    for i in range(3):
        k[:, :, i, :, i] += laplace


def _lame_and_gradients(basis, youngs_modulus_Pa, poisson):
    _check_vector_p2(basis)
    lam, mu = lame_parameters(youngs_modulus_Pa, poisson)
    # ElementVector function 3 a + c is scalar function a in component c: its component-c gradient
    # is the scalar gradient; stacked: (10, 3, n_elements, n_points).
    grads = np.stack([basis.basis[3 * a][0].grad[0] for a in range(_N_P2)])
    return lam, mu, grads


def stiffness_triplets(basis, youngs_modulus_Pa: float, poisson: float, dof_offset: int = 0):
    """Stiffness of an isotropic linear-elastic solid as COO triplets ``(rows, cols, values)``.

    Element matrices are computed in blocks of :data:`_CHUNK_ELEMENTS` tets straight into the
    output (small temporaries stay in cache and are reused by the allocator).

    Parameters
    ----------
    basis : skfem.CellBasis
        From :func:`solid_basis`.
    youngs_modulus_Pa, poisson : float
    dof_offset : int
        Added to every DOF number (the solid's first DOF in a larger model).

    Returns
    -------
    rows, cols : (n_elements · 900,) int arrays
        int32 while the DOF numbers fit (half the memory of int64: 78 MB less to write at 53 k DOF),
        int64 beyond.
    values : (n_elements · 900,) float array
    """
    lam, mu, grads = _lame_and_gradients(basis, youngs_modulus_Pa, poisson)
    index_type = np.int32 if basis.N + dof_offset < np.iinfo(np.int32).max else np.int64
    element_dofs = (basis.element_dofs.T.astype(np.int64) + dof_offset).astype(index_type)  # (e, 30)
    n, m = element_dofs.shape
    rows = np.repeat(element_dofs, m, axis=1).ravel()
    cols = np.tile(element_dofs, (1, m)).ravel()
    values = np.empty((n, m * m))
    for start in range(0, n, _CHUNK_ELEMENTS):
        block = slice(start, min(start + _CHUNK_ELEMENTS, n))
        _element_stiffness_into(values[block], grads[:, :, block, :], basis.dx[block], lam, mu)
    return rows, cols, values.ravel()


def stiffness_matrix(basis, youngs_modulus_Pa: float, poisson: float, *, threads: int | None = None) -> sp.csr_matrix:
    """Stiffness (N × N, CSR) assembled in blocks of elements straight into its 3 × 3-block pattern.

    No triplet arrays: the pattern (:func:`rvcoax.fem.assembly.block_pattern`) is built from the
    element–node incidence and each block of :data:`_CHUNK_ELEMENTS` element matrices is added into
    the values in place, so the peak memory of the assembly is the matrix plus the pattern's node
    keys and a few blocks' temporaries (benchmarks/RESULTS.md, bench_assembly_memory.py). Equal to
    ``assemble_matrix(N, [stiffness_triplets(...)])`` bit for bit: the same additions in element order.

    With more than one thread (default: :func:`rvcoax.fem.assembly.worker_threads` from
    :data:`PARALLEL_MIN_ELEMENTS` elements on) worker threads compute the blocks' element matrices and
    their places in the pattern (numpy's array operations release the GIL) while the calling thread adds
    the finished blocks in element order, at most ``threads`` blocks ahead: the same floats as one thread.
    """
    from rvcoax.fem.assembly import add_element_matrices, block_pattern, element_positions, in_order, worker_threads

    _check_vector_p2(basis)
    lam, mu = lame_parameters(youngs_modulus_Pa, poisson)
    gradients = [basis.basis[3 * a][0].grad[0] for a in range(_N_P2)]  # views: no stacked copy of all elements
    element_nodes = np.ascontiguousarray(basis.element_dofs[0::3].T // 3)  # (e, 10): DOFs 3 i + c per node i
    pattern = block_pattern(element_nodes, basis.N // 3)
    data = np.zeros(pattern.nnz)
    n = element_nodes.shape[0]
    blocks = [slice(start, min(start + _CHUNK_ELEMENTS, n)) for start in range(0, n, _CHUNK_ELEMENTS)]
    if threads is None:
        threads = worker_threads() if n >= PARALLEL_MIN_ELEMENTS else 1
    if threads <= 1:
        chunk = np.empty((_CHUNK_ELEMENTS, 9 * _N_P2 * _N_P2))
        for block in blocks:
            values = chunk[: block.stop - block.start]
            grads = np.stack([g[:, block, :] for g in gradients])
            _element_stiffness_into(values, grads, basis.dx[block], lam, mu)
            add_element_matrices(pattern, element_nodes[block], values, data)
    else:
        def element_block(block: slice) -> tuple[np.ndarray, np.ndarray]:
            values = np.empty((block.stop - block.start, 9 * _N_P2 * _N_P2))
            _element_stiffness_into(values, np.stack([g[:, block, :] for g in gradients]), basis.dx[block], lam, mu)
            return element_positions(pattern, element_nodes[block]), values.reshape(-1)

        in_order(element_block, blocks, lambda placed: np.add.at(data, *placed), threads)
    return sp.csr_matrix((data, pattern.indices, pattern.indptr), shape=(basis.N, basis.N))


def mass_matrix(basis, density_kg_per_m3: float, intorder: int = MASS_INTORDER) -> sp.csr_matrix:
    """Consistent mass ρ ∫ Nₐ N_b dV δᵢⱼ (N × N, CSR) of a solid on the DOFs of ``basis`` (:func:`solid_basis`).

    Integrated with a rule of order ``intorder`` (default 4: exact on straight-sided P2 tets, whose products
    Nₐ N_b are quartic) on the same mesh, assembled into the 3 × 3-block pattern of the stiffness. The P2
    functions sum to one, so the entries of each component sum to ρ V, V the mesh volume of the same rule.
    """
    from rvcoax.fem.assembly import add_element_matrices, block_pattern

    _check_vector_p2(basis)
    if not density_kg_per_m3 > 0.0:
        raise ValueError(f"density must be > 0, got {density_kg_per_m3}")
    scalar = skfem.CellBasis(basis.mesh, skfem.ElementTetP2(), mapping=basis.mapping, intorder=intorder)
    element_nodes = np.ascontiguousarray(basis.element_dofs[0::3].T // 3)  # (e, 10)
    if not np.array_equal(scalar.element_dofs.T, element_nodes):
        raise RuntimeError("the scalar and vector P2 bases number their nodes differently")
    pattern = block_pattern(element_nodes, basis.N // 3)
    data = np.zeros(pattern.nnz)
    n = element_nodes.shape[0]
    identity = np.eye(3)
    for start in range(0, n, _CHUNK_ELEMENTS):
        block = slice(start, min(start + _CHUNK_ELEMENTS, n))
        values = np.stack([np.asarray(scalar.basis[a][0])[block] for a in range(_N_P2)])  # (10, e, q)
        local = density_kg_per_m3 * np.einsum("aeq,beq,eq->eab", values, values, scalar.dx[block])
        matrices = np.einsum("eab,cd->eacbd", local, identity).reshape(-1, 3 * _N_P2, 3 * _N_P2)
        add_element_matrices(pattern, element_nodes[block], matrices, data)
    return sp.csr_matrix((data, pattern.indices, pattern.indptr), shape=(basis.N, basis.N))


def _scatter(basis, local: np.ndarray) -> np.ndarray:
    """Sum element vectors ``local`` (30, n_elements) into a global vector."""
    return np.bincount(basis.element_dofs.ravel(), weights=local.ravel(), minlength=basis.N)


def body_force_vector(basis, density_kg_per_m3: float, acceleration_m_per_s2) -> np.ndarray:
    """Consistent load vector of the body force ρ g (self-weight: g = (0, −9.81, 0) or similar), (N,)."""
    _check_vector_p2(basis)
    g = np.asarray(acceleration_m_per_s2, dtype=float).reshape(3)
    integrals = np.einsum("aeq,eq->ae", _scalar_values(basis), basis.dx)  # ∫ Nₐ dV, (10, e)
    local = density_kg_per_m3 * integrals[:, None, :] * g[None, :, None]  # (10, 3, e)
    return _scatter(basis, local.reshape(3 * _N_P2, -1))


def thermal_strain_vector(basis, youngs_modulus_Pa: float, poisson: float, strain: float) -> np.ndarray:
    """Equivalent load of a uniform free (thermal) strain ε I: ∫ (3λ + 2μ) ε div v dV, (N,).

    Applied to an unconstrained body it gives the free growth u = ε (x − x₀) exactly (P2 holds it).
    """
    _check_vector_p2(basis)
    lam, mu = lame_parameters(youngs_modulus_Pa, poisson)
    bulk_strain = (3.0 * lam + 2.0 * mu) * strain
    form = skfem.LinearForm(lambda v, w: bulk_strain * (v.grad[0][0] + v.grad[1][1] + v.grad[2][2]))
    return form.assemble(basis)


# ---------------------------------------------------------------------------------------- surfaces


def facet_basis(mesh: skfem.MeshTet2, facets, intorder: int = FACET_INTORDER) -> skfem.FacetBasis:
    """Vector P2 basis on a set of (boundary) facets, with the same DOF numbering as :func:`solid_basis`."""
    facets = np.asarray(facets, dtype=np.int64)
    if facets.size == 0:
        raise ValueError("no facets given")
    # no DOF locations: the whole mesh would be mapped for them (0.03 s at 53 k DOF), and loads need none
    return skfem.FacetBasis(mesh, skfem.ElementVector(skfem.ElementTetP2()), facets=facets, intorder=intorder,
                            disable_doflocs=True)


def _traction_vector(fbasis, traction: np.ndarray) -> np.ndarray:
    """Load vector of a traction field (3, n_facets, n_points) on the facets of ``fbasis``."""
    local = np.einsum("afq,cfq,fq->acf", _scalar_values(fbasis), traction, fbasis.dx)
    return _scatter(fbasis, local.reshape(3 * _N_P2, -1))


def force_traction_vector(mesh: skfem.MeshTet2, facets, force_N, intorder: int = FACET_INTORDER) -> np.ndarray:
    """Load vector (N,) of the uniform traction F / A on ``facets``.

    A is integrated with the same quadrature as the load, and the P2 functions sum to one, so the
    nodal forces sum to F to rounding.
    """
    fbasis = facet_basis(mesh, facets, intorder)
    area = fbasis.dx.sum()
    force = np.asarray(force_N, dtype=float).reshape(3)
    traction = np.broadcast_to((force / area)[:, None, None], (3,) + fbasis.dx.shape)
    return _traction_vector(fbasis, traction)


def torque_traction_vector(  # noqa: PLR0913
    mesh: skfem.MeshTet2, facets, axis_point, axis_dir, torque_Nm: float, *, intorder: int = FACET_INTORDER
) -> np.ndarray:
    """Load vector (N,) of a torsional shear traction with moment ``torque_Nm`` about the axis.

    τ = T (e × r) / J, with e the unit axis, r the in-plane radius vector and J = ∫ |r|² dA
    (same quadrature as the load). r is measured from the axis through the facets' area centroid
    (projected on the plane ⊥ e), so that ∫ r dA = 0 exactly: the resultant force is zero to
    rounding and the traction is a pure couple, whose moment about ``axis_point`` + s e is T to
    rounding (mapping is isoparametric, so Σ xₖ × fₖ over the nodes is the integral of x × τ). For a
    face or band centred on the axis the centroid lies on it (measured: 1e-17 of the radius on gmsh
    end faces); an off-centre set of facets (> 1e-3 of its rms radius) is logged as a warning.
    Sign: right-handed about ``axis_dir``.
    """
    fbasis = facet_basis(mesh, facets, intorder)
    e = np.asarray(axis_dir, dtype=float).reshape(3)
    e = e / np.linalg.norm(e)
    x = np.asarray(fbasis.global_coordinates())  # (3, f, q)
    relative = x - np.asarray(axis_point, dtype=float).reshape(3, 1, 1)
    r = relative - np.einsum("c,cfq->fq", e, relative)[None] * e[:, None, None]
    area = fbasis.dx.sum()
    offset = np.einsum("cfq,fq->c", r, fbasis.dx) / area
    r = r - offset[:, None, None]
    polar = np.einsum("cfq,cfq,fq->", r, r, fbasis.dx)
    if not polar > 0.0:
        raise ValueError("the facets have no extent around the axis (J = 0)")
    rms_radius = np.sqrt(polar / area)
    if np.linalg.norm(offset) > 1e-3 * rms_radius:
        logger.warning(
            "torque facets are off-centre by %.3g m (rms radius %.3g m): applied as a couple about their centroid",
            np.linalg.norm(offset),
            rms_radius,
        )
    traction = torque_Nm / polar * np.cross(e[:, None, None], r, axis=0)
    return _traction_vector(fbasis, traction)


# ------------------------------------------------------------------------------- nodes and probing


def dof_locations(basis) -> tuple[np.ndarray, np.ndarray]:
    """P2 node coordinates and their DOF numbers.

    Returns
    -------
    coordinates : (n_nodes, 3) array
        Vertices first, then mid-edge nodes (the order of ``mesh.doflocs``).
    dofs : (n_nodes, 3) int array
        DOF numbers of (u_x, u_y, u_z) at each node; with scikit-fem 12 ``dofs[k] = 3k + (0, 1, 2)``.
    """
    _check_vector_p2(basis)
    dofs = np.hstack([basis.nodal_dofs, basis.edge_dofs]).T.astype(np.int64)
    return np.ascontiguousarray(basis.doflocs[:, dofs[:, 0]].T), dofs


def dof_components(basis) -> np.ndarray:
    """Component (0 = x, 1 = y, 2 = z) of every DOF, shape (N,)."""
    _, dofs = dof_locations(basis)
    components = np.empty(basis.N, dtype=np.int64)
    for c in range(3):
        components[dofs[:, c]] = c
    return components


def _locate_among(basis, points: np.ndarray, n_candidates: int, outside_tolerance: float, groups: np.ndarray):
    """Element and reference coordinates of each point (k, 3), by Newton on the curved mapping.

    ``groups`` (k,) numbers the points 0 … g − 1: each group iterates until its own largest step is
    below 1e-13, then stops, exactly as if it were located alone (the points of all groups share one
    vectorised iteration).
    """
    mesh, mapping = basis.mesh, basis.mapping
    if not hasattr(mesh, "_rvcoax_centroid_tree"):
        centroids = mesh.p[:, mesh.t].mean(axis=1).T
        mesh._rvcoax_centroid_tree = cKDTree(centroids)
    tree = mesh._rvcoax_centroid_tree
    n_candidates = min(n_candidates, mesh.t.shape[1])
    _, candidates = tree.query(points, n_candidates)
    candidates = np.asarray(candidates).reshape(len(points), n_candidates)
    point_of, tind = _plausible_candidates(mesh, points, candidates)
    x = points.T[:, point_of, None]  # (3, candidates, 1)
    ref = np.full(x.shape, 0.25)
    group_of = groups[point_of]
    active = np.ones(int(groups.max()) + 1 if groups.size else 0, dtype=bool)
    for _ in range(30):
        moving = np.flatnonzero(active[group_of])
        if not moving.size:
            break
        here = ref[:, moving]
        step = np.einsum("ijkl,jkl->ikl", mapping.invDF(here, tind[moving]), x[:, moving] - mapping.F(here, tind[moving]))
        ref[:, moving] = np.clip(here + step, -2.0, 3.0)
        largest = np.zeros(active.size)
        np.maximum.at(largest, group_of[moving], np.abs(step).max(axis=(0, 2)))
        active &= ~(largest < 1e-13)
    # a candidate counts only where Newton converged (clipped or diverged iterations do not)
    extent = np.ptp(mesh.p, axis=1).max()
    mismatch = np.linalg.norm(x - mapping.F(ref, tind), axis=0)[:, 0]
    ref = ref[:, :, 0]
    barycentric = np.vstack([1.0 - ref.sum(axis=0), ref])
    worst = np.where(mismatch <= 1e-10 * extent, barycentric.min(axis=0), -np.inf)
    # each point's best candidate (the first of equals, in the order of the nearest centroids)
    order = np.lexsort((-worst, point_of))
    chosen = order[np.searchsorted(point_of[order], np.arange(len(points)))]
    outside = worst[chosen] < -outside_tolerance
    return tind[chosen], ref[:, chosen], outside


STRAIGHT_MARGIN = 0.25
"""How far outside a candidate tet's straight-sided (P1) version a point may lie, in barycentric coordinates, and
the candidate still be iterated on: a P2 tet's curved edges move it from its straight version by far less
(a cylinder of radius R meshed at size h: the sagitta h²/(8R), 1/8 of the tet at h = R)."""


def _plausible_candidates(mesh, points: np.ndarray, candidates: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(point index, tet) of the candidates worth Newton's iteration: those whose straight-sided tet holds the point
    within :data:`STRAIGHT_MARGIN`, in the candidates' order; every candidate of a point that none holds.

    The others cannot be the point's tet, and they are the costly ones: from far outside a tet Newton on its curved
    mapping converges slowly or not at all, and kept every point of their group iterating to the limit."""
    k, c = candidates.shape
    corners = mesh.p[:, mesh.t[:4, candidates.ravel()]]  # (3, 4, k·c)
    edges = np.moveaxis(corners[:, 1:] - corners[:, :1], 2, 0)  # (k·c, 3 coordinates, 3 edges)
    offset = (np.repeat(points, c, axis=0) - corners[:, 0].T)[:, :, None]
    try:
        local = np.linalg.solve(edges, offset)[:, :, 0]
    except np.linalg.LinAlgError:  # a flat tet among them: no shortcut
        local = np.zeros((k * c, 3))
    nearest = np.minimum(local.min(axis=1), 1.0 - local.sum(axis=1)).reshape(k, c)
    keep = nearest >= -STRAIGHT_MARGIN  # NaN (a flat tet) is dropped
    keep[~keep.any(axis=1)] = True
    point_of, slot = np.nonzero(keep)
    return point_of, candidates[point_of, slot]


def _locate(basis, points: np.ndarray, outside_tolerance: float, groups: np.ndarray):
    """Element and reference coordinates of each point (k, 3), by Newton on the curved mapping.

    Candidates are the tets with the nearest centroids: 16 first, then 256 for points not found
    (stretched tets can have their centroid farther away than 16 others').
    """
    cells, ref, outside = _locate_among(basis, points, 16, outside_tolerance, groups)
    if np.any(outside):
        retry = np.flatnonzero(outside)
        cells_r, ref_r, outside_r = _locate_among(basis, points[retry], 256, outside_tolerance, groups[retry])
        cells[retry], ref[:, retry] = cells_r, ref_r
        outside[retry] = outside_r
    if np.any(outside):
        bad = np.flatnonzero(outside)
        raise ValueError(f"{bad.size} probe points lie outside the mesh, e.g. {points[bad[0]].tolist()} m")
    return cells, ref


def probe_matrix(basis, points, outside_tolerance: float = 1e-6, groups=None) -> sp.csr_matrix:
    """Interpolation matrix P (3 k, N) with ``(P @ u).reshape(k, 3)`` the displacement at the points.

    Row ``3 p + c`` gives component c (0 = x) at point p. Points are located by Newton iteration on
    the curved element mapping (candidates: the 16 tets with the nearest centroids), all points in
    one vectorised iteration. A point may lie outside the discrete geometry by ``outside_tolerance``
    in reference coordinates (the field is extrapolated that little); farther away it is an error.
    ``groups`` (k,), optional: integer labels 0 … g − 1; each group's iteration stops on its own
    convergence, so that the result for a group is the one a call with that group's points alone
    gives (without it, all points are one group).
    """
    _check_vector_p2(basis)
    points = np.atleast_2d(np.asarray(points, dtype=float))
    if points.shape[1] != 3:
        raise ValueError(f"points must have shape (k, 3), got {points.shape}")
    labels = np.zeros(len(points), dtype=np.int64) if groups is None else np.asarray(groups, dtype=np.int64)
    if labels.shape != (len(points),) or (labels.size and labels.min() < 0):
        raise ValueError(f"groups must be {len(points)} labels >= 0, got shape {labels.shape}")
    cells, ref = _locate(basis, points, outside_tolerance, labels)
    scalar = skfem.ElementTetP2()
    values = np.stack([scalar.lbasis(ref, a)[0] for a in range(_N_P2)])  # (10, k)
    k = len(points)
    rows = (3 * np.arange(k)[None, None, :] + np.arange(3)[None, :, None]).repeat(_N_P2, axis=0)  # (10, 3, k)
    cols = basis.element_dofs[:, cells].reshape(_N_P2, 3, k)
    vals = np.repeat(values[:, None, :], 3, axis=1)
    return sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(3 * k, basis.N))


# ------------------------------------------------------------------------------------------ output


def stress_at_nodes(basis, displacement, youngs_modulus_Pa: float, poisson: float) -> np.ndarray:
    """Cauchy stress (n_nodes, 3, 3) at the P2 nodes, averaged over the tets sharing each node.

    Each tet's stress is evaluated at its own 10 nodes (exact for its P2 displacement); the
    values are then averaged (arithmetic mean, per tensor component) over the tets that share a
    node. Nodes are ordered as in :func:`dof_locations`.
    """
    _check_vector_p2(basis)
    lam, mu = lame_parameters(youngs_modulus_Pa, poisson)
    u = np.asarray(displacement, dtype=float)
    scalar = skfem.ElementTetP2()
    at_nodes = skfem.Basis(basis.mesh, scalar, mapping=basis.mapping, quadrature=(scalar.doflocs.T, np.ones(10)))
    grads = np.stack([at_nodes.basis[a][0].grad for a in range(_N_P2)])  # (10, 3, e, q=10 nodes)
    u_local = u[basis.element_dofs].reshape(_N_P2, 3, -1)  # (a, c, e)
    du = np.einsum("ace,aieq->eqci", u_local, grads)  # ∂u_c/∂x_i at node q of tet e
    strain = 0.5 * (du + du.transpose(0, 1, 3, 2))
    trace = np.trace(strain, axis1=2, axis2=3)
    stress = 2.0 * mu * strain + lam * trace[..., None, None] * np.eye(3)
    nodes = at_nodes.element_dofs.T  # (e, 10): scalar DOF = node number, local node q ↔ reference node q
    n_nodes = at_nodes.N
    flat_nodes, flat_stress = nodes.ravel(), stress.reshape(-1, 9)
    count = np.bincount(flat_nodes, minlength=n_nodes)
    total = np.column_stack([np.bincount(flat_nodes, flat_stress[:, j], minlength=n_nodes) for j in range(9)])
    return (total / count[:, None]).reshape(n_nodes, 3, 3)


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Equivalent von Mises stress of tensors (..., 3, 3)."""
    deviator = stress - np.trace(stress, axis1=-2, axis2=-1)[..., None, None] / 3.0 * np.eye(3)
    return np.sqrt(1.5 * np.einsum("...ij,...ij->...", deviator, deviator))


def von_mises_at_nodes(basis, displacement, youngs_modulus_Pa: float, poisson: float) -> np.ndarray:
    """Von Mises stress (n_nodes,) of the node-averaged stress (:func:`stress_at_nodes`), Pa."""
    return von_mises(stress_at_nodes(basis, displacement, youngs_modulus_Pa, poisson))
