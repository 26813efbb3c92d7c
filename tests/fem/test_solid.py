"""Quadratic-tetrahedron elasticity: assembly, DOF numbering, loads, probes, stresses, and beam theory."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import skfem
from skfem.models.elasticity import lame_parameters, linear_elasticity

from rvcoax.fem import solid
from rvcoax.fem.assembly import assemble_matrix
from rvcoax.fem.rigid_body import rigid_body_modes
from rvcoax.fem.sections import CircularSection
from rvcoax.fem.solvers import prepare
from rvcoax.geometry.meshing import SolidPartGeometry, mesh_part

E, NU, RHO = 2.1e11, 0.3, 7850.0
G = E / (2 * (1 + NU))


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("meshes")


@pytest.fixture(scope="module")
def stepped(cache):
    geometry = SolidPartGeometry(
        "stepped", ((0.0, 40.0, 30.0, 10.0), (40.0, 100.0, 40.0, 10.0), (100.0, 120.0, 25.0, 0.0)), (60.0, 70.0), 10.0
    )
    mesh = mesh_part(geometry, cache_dir=cache)
    return geometry, mesh, solid.solid_basis(mesh)


def at_x(mesh, x_m):
    return mesh.facets_satisfying(lambda x: np.isclose(x[0], x_m, atol=1e-9))


def test_assembly_equals_scikit_fem_reference(stepped):
    _, _, basis = stepped
    matrix = assemble_matrix(basis.N, [solid.stiffness_triplets(basis, E, NU)])
    reference = skfem.asm(linear_elasticity(*lame_parameters(E, NU)), basis)
    difference = (matrix - reference).tocoo()
    assert np.linalg.norm(difference.data) <= 1e-10 * np.linalg.norm(reference.data)
    assert abs(matrix - matrix.T).max() <= 1e-12 * abs(matrix).max()
    # the offset shifts every DOF
    rows, cols, values = solid.stiffness_triplets(basis, E, NU, dof_offset=7)
    rows0, cols0, values0 = solid.stiffness_triplets(basis, E, NU)
    np.testing.assert_array_equal(rows, rows0 + 7)
    np.testing.assert_array_equal(cols, cols0 + 7)
    np.testing.assert_array_equal(values, values0)


def test_vector_dofs_are_interleaved_per_node(stepped):
    """scikit-fem 12 ElementVector(ElementTetP2): node k (vertices, then edges) owns DOFs 3k, 3k+1, 3k+2."""
    _, mesh, basis = stepped
    coordinates, dofs = solid.dof_locations(basis)
    n_nodes = mesh.doflocs.shape[1]
    assert basis.N == 3 * n_nodes
    np.testing.assert_array_equal(dofs, 3 * np.arange(n_nodes)[:, None] + np.arange(3))
    np.testing.assert_array_equal(coordinates, mesh.doflocs.T)
    np.testing.assert_array_equal(basis.doflocs.T, np.repeat(coordinates, 3, axis=0))
    np.testing.assert_array_equal(solid.dof_components(basis), np.arange(basis.N) % 3)
    # the basis function 3a + c of an element is scalar function a in component c
    element = 5
    local = basis.element_dofs[:, element]
    np.testing.assert_array_equal(local % 3, np.tile(np.arange(3), 10))


def test_intorder_two_is_accurate_for_curved_tets(cache):
    """Bending energy of a cantilever with 4 vs 2 quadrature orders: 1e-4 apart, far below discretisation error."""
    geometry = SolidPartGeometry("bar", ((0.0, 160.0, 20.0, 0.0),), (), 6.0)
    mesh = mesh_part(geometry, cache_dir=cache)
    energies = []
    for order in (2, 4):
        basis = solid.solid_basis(mesh, intorder=order)
        k = assemble_matrix(basis.N, [solid.stiffness_triplets(basis, E, NU)])
        f = solid.force_traction_vector(mesh, at_x(mesh, 0.160), [0.0, -1000.0, 0.0])
        free = np.setdiff1d(np.arange(basis.N), basis.get_dofs(at_x(mesh, 0.0)).all())
        u = np.zeros(basis.N)
        u[free] = prepare(k[free][:, free]).solve(f[free])
        energies.append(f @ u)
    assert energies[0] == pytest.approx(energies[1], rel=1e-4)


def test_body_force_resultant_is_weight(stepped):
    geometry, _, basis = stepped
    g = np.array([0.0, -9.81, 0.0])
    f = solid.body_force_vector(basis, RHO, g)
    _, dofs = solid.dof_locations(basis)
    resultant = f[dofs].sum(axis=0)
    discrete_mass = RHO * basis.dx.sum()
    np.testing.assert_allclose(resultant, discrete_mass * g, rtol=1e-12, atol=1e-12 * discrete_mass)
    assert -resultant[1] == pytest.approx(RHO * geometry.volume_mm3 * 1e-9 * 9.81, rel=2e-3)


def test_force_traction_resultant_is_exact(stepped):
    _, mesh, basis = stepped
    force = np.array([120.0, -3400.0, 56.0])
    for facets in (at_x(mesh, 0.120), at_x(mesh, 0.0)):
        f = solid.force_traction_vector(mesh, facets, force)
        assert f.shape == (basis.N,)
        _, dofs = solid.dof_locations(basis)
        np.testing.assert_allclose(f[dofs].sum(axis=0), force, rtol=0, atol=1e-12 * np.linalg.norm(force))
        # only DOFs of the loaded facets carry load
        loaded = np.unique(basis.get_dofs(facets).all())
        off_facet = f[np.setdiff1d(np.arange(basis.N), loaded)]
        assert np.abs(off_facet).max() <= 1e-12 * np.abs(f).max()  # zero up to rounding


def mantle_band(mesh, x0_m, x1_m, min_radius_m):
    """Boundary facets between two planes x = const, farther than ``min_radius_m`` from the axis.

    (facets_satisfying tests the centroid of the straight facet, inside the curved surface)
    """
    return mesh.facets_satisfying(
        lambda x: (x[0] > x0_m) & (x[0] < x1_m) & (np.hypot(x[1], x[2]) > min_radius_m), boundaries_only=True
    )


@pytest.mark.parametrize("where", ["end face", "annular end face", "mantle band"])
def test_torque_traction_is_a_pure_couple(stepped, where):
    """Moment about the axis = T to rounding, resultant force 0 to rounding, for faces and a mantle band."""
    _, mesh, basis = stepped
    facets = {
        "end face": at_x(mesh, 0.120),
        "annular end face": at_x(mesh, 0.0),
        "mantle band": mantle_band(mesh, 0.060, 0.070, 0.015),
    }[where]
    assert facets.size > 0
    torque, axis = 37.5, np.array([1.0, 0.0, 0.0])
    f = solid.torque_traction_vector(mesh, facets, [0.0, 0.0, 0.0], 2.0 * axis, torque)
    coordinates, dofs = solid.dof_locations(basis)
    nodal = f[dofs]
    radius = 0.02
    np.testing.assert_allclose(nodal.sum(axis=0), 0.0, atol=1e-12 * torque / radius)
    moment = np.cross(coordinates, nodal).sum(axis=0)
    assert moment[0] == pytest.approx(torque, rel=1e-12)
    # transverse moments: exactly zero for a plane face; ∫ x r dA ≈ 0 only to the mesh's asymmetry on a band
    np.testing.assert_allclose(moment[1:], 0.0, atol=1e-8 * torque)
    # any other point on the axis gives the same moment (pure couple)
    shifted = np.cross(coordinates - [0.05, 0.0, 0.0], nodal).sum(axis=0)
    assert shifted[0] == pytest.approx(torque, rel=1e-12)


def test_probe_matrix_interpolates_linear_fields_exactly(stepped):
    """A linear field is reproduced exactly by the isoparametric P2 mesh; rows are point-major (3 p + c)."""
    _, mesh, basis = stepped
    gradient = np.array([[1.0, 2.0, -1.0], [0.5, -3.0, 2.0], [4.0, 1.0, 0.0]])
    shift = np.array([1e-3, -2e-3, 5e-4])
    coordinates, dofs = solid.dof_locations(basis)
    u = np.zeros(basis.N)
    u[dofs] = coordinates @ gradient.T + shift
    rng = np.random.default_rng(0)
    x = rng.uniform(0.0, 0.12, 20)
    angle = rng.uniform(0.0, 2 * np.pi, 20)
    outer = np.array([solid_outer for solid_outer in (15.0 if xi < 0.04 else 20.0 if xi < 0.1 else 12.5 for xi in x)])
    inner = np.where(x < 0.1, 5.0, 0.0)
    radius = 1e-3 * (inner + rng.uniform(0.05, 0.95, 20) * (outer - inner))
    points = np.column_stack([x, radius * np.cos(angle), radius * np.sin(angle)])
    points = np.vstack([points, coordinates[[0, 10, len(coordinates) - 1]]])  # nodes on the surface too
    probe = solid.probe_matrix(basis, points)
    assert probe.shape == (3 * len(points), basis.N)
    np.testing.assert_allclose((probe @ u).reshape(-1, 3), points @ gradient.T + shift, rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="outside the mesh"):
        solid.probe_matrix(basis, [[0.06, 0.0, 0.0]])  # in the bore


def test_probe_matrix_groups_give_the_rows_of_separate_calls_bit_for_bit(stepped):
    """Points located together in labelled groups give exactly the matrix of one call per group
    (each group's Newton iteration stops on its own convergence); a bad label is refused."""
    _, _, basis = stepped
    rng = np.random.default_rng(3)
    rings = []
    for x in (0.01, 0.05, 0.07, 0.11):
        radius = 1e-3 * (8.0 if x < 0.1 else 6.0)
        angle = rng.uniform(0.0, 2 * np.pi, 5)
        rings.append(np.column_stack([np.full(5, x), radius * np.cos(angle), radius * np.sin(angle)]))
    together = solid.probe_matrix(basis, np.vstack(rings), groups=np.repeat(np.arange(4), 5))
    apart = sp.vstack([solid.probe_matrix(basis, ring) for ring in rings]).tocsr()
    assert (together != apart).nnz == 0
    with pytest.raises(ValueError, match="groups"):
        solid.probe_matrix(basis, rings[0], groups=[0, 1])


def test_probe_matrix_iterates_only_on_plausible_tets_and_finds_the_same_ones(stepped, monkeypatch):
    """Newton's iteration runs on the candidate tets whose straight-sided version holds the point (within
    STRAIGHT_MARGIN); every candidate iterated (an infinite margin) gives the same tets and, to rounding, the
    same interpolation: the dropped candidates could not have held the point."""
    _, _, basis = stepped
    rng = np.random.default_rng(7)
    x = rng.uniform(0.002, 0.118, 40)
    radius = 1e-3 * np.where(x < 0.1, rng.uniform(6.0, 12.0, 40), rng.uniform(1.0, 11.0, 40))
    angle = rng.uniform(0.0, 2 * np.pi, 40)
    points = np.column_stack([x, radius * np.cos(angle), radius * np.sin(angle)])
    pruned = solid.probe_matrix(basis, points)
    monkeypatch.setattr(solid, "STRAIGHT_MARGIN", np.inf)
    every = solid.probe_matrix(basis, points)
    assert abs(pruned - every).max() <= 1e-12
    point_of, _ = solid._plausible_candidates(basis.mesh, points, np.tile(np.arange(16), (len(points), 1)))
    assert point_of.size == 16 * len(points)  # infinite margin: nothing dropped


def test_stress_of_uniform_strain(stepped):
    """u = ε x gives σ = λ tr(ε) I + 2 μ ε at every node; von Mises from the deviator."""
    _, _, basis = stepped
    strain = np.array([[1.0, 0.3, 0.0], [0.3, -0.5, 0.2], [0.0, 0.2, 0.25]]) * 1e-4
    coordinates, dofs = solid.dof_locations(basis)
    u = np.zeros(basis.N)
    u[dofs] = coordinates @ strain.T
    lam, mu = lame_parameters(E, NU)
    expected = lam * np.trace(strain) * np.eye(3) + 2 * mu * strain
    stress = solid.stress_at_nodes(basis, u, E, NU)
    assert stress.shape == (len(coordinates), 3, 3)
    np.testing.assert_allclose(stress, np.broadcast_to(expected, stress.shape), atol=1e-6 * np.abs(expected).max())
    s = expected
    vm = np.sqrt(0.5 * ((s[0, 0] - s[1, 1]) ** 2 + (s[1, 1] - s[2, 2]) ** 2 + (s[2, 2] - s[0, 0]) ** 2)
                 + 3 * (s[0, 1] ** 2 + s[1, 2] ** 2 + s[0, 2] ** 2))
    np.testing.assert_allclose(solid.von_mises_at_nodes(basis, u, E, NU), vm, rtol=1e-6)


def test_rigid_body_modes_are_the_null_space(stepped):
    _, _, basis = stepped
    k = assemble_matrix(basis.N, [solid.stiffness_triplets(basis, E, NU)])
    modes = rigid_body_modes(basis.doflocs.T)
    assert modes.shape == (basis.N, 6)
    np.testing.assert_array_equal(modes, rigid_body_modes(basis.doflocs.T, solid.dof_components(basis)))
    scale = abs(k).max() * np.abs(modes).max(axis=0)
    assert np.all(np.abs(k @ modes).max(axis=0) <= 1e-9 * scale)
    assert np.linalg.matrix_rank(modes) == 6


# ------------------------------------------------------------------------------- beam theory


def cantilever(mesh, basis, end_m, load_n, torque_nm):
    """Clamp x = 0, load the end face with a shear force (−y) and a torque; mean tip deflection and twist."""
    k = assemble_matrix(basis.N, [solid.stiffness_triplets(basis, E, NU)])
    tip = at_x(mesh, end_m)
    f = np.column_stack([
        solid.force_traction_vector(mesh, tip, [0.0, -load_n, 0.0]),
        solid.torque_traction_vector(mesh, tip, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], torque_nm),
    ])
    free = np.setdiff1d(np.arange(basis.N), basis.get_dofs(at_x(mesh, 0.0)).all())
    u = np.zeros((basis.N, 2))
    u[free] = prepare(k[free][:, free]).solve(f[free])
    face = solid.facet_basis(mesh, tip)
    area = face.dx.sum()
    deflection = -(np.asarray(face.interpolate(u[:, 0]))[1] * face.dx).sum() / area
    x = np.asarray(face.global_coordinates())
    w = np.asarray(face.interpolate(u[:, 1]))
    twist = ((x[1] * w[2] - x[2] * w[1]) * face.dx).sum() / ((x[1] ** 2 + x[2] ** 2) * face.dx).sum()
    return deflection, twist


def beam_theory(section: CircularSection, length_m, load_n, torque_nm):
    bending = load_n * length_m**3 / (3 * E * section.second_moment_m4)
    shear = load_n * length_m / (section.shear_coefficient(NU) * G * section.area_m2)
    return bending + shear, torque_nm * length_m / (G * section.polar_moment_m4)


def test_solid_cantilever_converges_to_timoshenko(cache):
    """Round bar, L/D = 8, end face clamped: tip deflection → within 1 % of P L³/3EI + P L/κGA as h ↓.

    The fully clamped face restrains the Poisson contraction, so the solid is slightly stiffer
    than the beam (converged ≈ −0.8 %). Torsion: T L / G J to 1e-3 on every mesh.
    """
    length, load, torque = 0.160, 1000.0, 100.0
    section = CircularSection(0.020)
    expected_deflection, expected_twist = beam_theory(section, length, load, torque)
    errors = []
    for size in (8.0, 5.0, 4.0):
        geometry = SolidPartGeometry("bar", ((0.0, 160.0, 20.0, 0.0),), (), size)
        mesh = mesh_part(geometry, cache_dir=cache)
        deflection, twist = cantilever(mesh, solid.solid_basis(mesh), length, load, torque)
        errors.append(deflection / expected_deflection - 1.0)
        assert twist == pytest.approx(expected_twist, rel=1e-3)
    assert abs(errors[0]) > abs(errors[1]) > abs(errors[2])  # converging
    assert abs(errors[2]) < 0.01, errors


def test_hollow_shaft_cantilever_and_torsion(cache):
    """Tube D = 40, d = 30 mm, L/D = 8: tip deflection within 1 % of Timoshenko, twist within 1e-3 of T L / G J."""
    length, load, torque = 0.320, 2000.0, 300.0
    geometry = SolidPartGeometry("tube", ((0.0, 320.0, 40.0, 30.0),), (), 10.0)
    mesh = mesh_part(geometry, cache_dir=cache)
    deflection, twist = cantilever(mesh, solid.solid_basis(mesh), length, load, torque)
    expected_deflection, expected_twist = beam_theory(CircularSection(0.040, 0.030), length, load, torque)
    assert deflection == pytest.approx(expected_deflection, rel=0.01)
    assert twist == pytest.approx(expected_twist, rel=1e-3)
