"""Verification of the finite-element core against closed-form solutions.

Every case is solved with the full pipeline (assembly, constraint elimination, sparse
factorisation) and compared with a textbook formula written out in the test, to 0.5 %
(frames.REL_TOL); the exact Timoshenko element should meet them to rounding. Every solve also
checks the reduced residual and the global equilibrium of applied loads and reactions
(frames.solve).
"""

from __future__ import annotations

import frames
import numpy as np
import pytest
from frames import (
    DENSITY,
    GRAVITY,
    REL_TOL,
    SHEAR_MODULUS,
    assert_close,
    constraint_elimination,
    dof,
    gravity_load_vector,
    node_dofs,
    rigidities,
    stiffness_matrix,
)

from rvcoax.fem.bushing import GROUND
from rvcoax.fem.constraints import RigidLinks
from rvcoax.fem.diagnostics import MOTION_NAMES, find_free_motions
from rvcoax.fem.equilibrium import ground_reactions
from rvcoax.fem.errors import SingularModelError
from rvcoax.fem.loads import PointMasses
from rvcoax.fem.pieces import assemble_frame
from rvcoax.fem.sections import CircularSection
from rvcoax.fem.system import factorize

SOLID = CircularSection(0.04)
HOLLOW = CircularSection(0.04, 0.028)
SECTIONS = pytest.mark.parametrize("section", [SOLID, HOLLOW], ids=["solid", "hollow"])


def straight(length: float, n_elements: int, section: CircularSection, direction=(1.0, 0.0, 0.0), **kwargs):
    """Nodes and beams of a straight beam from the origin along ``direction``."""
    end = length * np.asarray(direction, float) / np.linalg.norm(direction)
    return frames.polyline([np.zeros(3), end], n_elements, section, **kwargs)


def fixed_reactions(structure, u, f) -> np.ndarray:
    """Reaction forces at the fixed DOFs (zero elsewhere), K u − f."""
    return ground_reactions(structure, stiffness_matrix(structure), u, f)[1]


# 0 ---------------------------------------------------------------------------------------------
def test_circular_section_properties():
    """Section formulas: A, I = π(D⁴−d⁴)/64, J = 2I, and Cowper's κ with its solid and thin-tube limits."""
    big, small, nu = 0.04, 0.028, 0.3
    section = CircularSection(big, small)
    assert_close(section.area_m2, np.pi * (big**2 - small**2) / 4)
    assert_close(section.second_moment_m4, np.pi * (big**4 - small**4) / 64)
    assert_close(section.polar_moment_m4, np.pi * (big**4 - small**4) / 32)
    # solid: κ = 6 (1 + ν) / (7 + 6 ν);  thin tube (d → D): κ → 2 (1 + ν) / (4 + 3 ν)
    assert_close(CircularSection(big).shear_coefficient(nu), 6 * (1 + nu) / (7 + 6 * nu))
    assert_close(CircularSection(big, big * (1 - 1e-9)).shear_coefficient(nu), 2 * (1 + nu) / (4 + 3 * nu))
    # hollow, m = d/D: κ = 6 (1 + ν)(1 + m²)² / [(7 + 6ν)(1 + m²)² + (20 + 12ν) m²]
    m2 = (small / big) ** 2
    assert_close(section.shear_coefficient(nu),
                 6 * (1 + nu) * (1 + m2) ** 2 / ((7 + 6 * nu) * (1 + m2) ** 2 + (20 + 12 * nu) * m2))


# 1 ---------------------------------------------------------------------------------------------
@SECTIONS
@pytest.mark.parametrize("axis", [1, 2], ids=["force_y", "force_z"])
def test_cantilever_tip_force_timoshenko(section, axis):
    """Stubby cantilever (L/D = 3) with a tip force, bending in the x-y or x-z plane."""
    length, n, force = 3.0 * section.outer_diameter_m, 3, 2.0e3
    r = rigidities(section)
    coordinates, beams = straight(length, n, section)
    structure = frames.model(coordinates, beams, fixed_dofs=np.array(node_dofs(0)))
    load = np.zeros(6)
    load[axis] = force
    u = frames.solve(structure, frames.point_load(structure.n_dofs, n, load))

    # δ = P L³ / (3 E I) + P L / (κ G A)
    bending, shear = force * length**3 / (3 * r.EI), force * length / r.kGA
    assert shear / (bending + shear) > 0.05
    assert_close(u[dof(n, axis)], bending + shear)
    # tip rotation P L² / (2 E I): +θz for a force in +y, −θy for a force in +z (θy = −dw/dx)
    rotation = force * length**2 / (2 * r.EI)
    assert_close(u[dof(n, 5)] if axis == 1 else -u[dof(n, 4)], rotation)
    # nothing moves out of the loaded plane
    assert abs(u[dof(n, 3 - axis)]) < 1e-12 * abs(u[dof(n, axis)])


# 2 ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("axis", [1, 2], ids=["gravity_y", "gravity_z"])
def test_simply_supported_self_weight(axis):
    """Pinned–pinned beam under its consistent self-weight: midspan deflection and reactions."""
    section, length, n = CircularSection(0.05), 0.4, 8
    r = rigidities(section)
    coordinates, beams = straight(length, n, section)
    pins = node_dofs(0, range(4)) + node_dofs(n, range(3))  # translations at both ends, torsion at one
    structure = frames.model(coordinates, beams, fixed_dofs=np.array(pins))
    g = np.zeros(3)
    g[axis] = -GRAVITY
    f = gravity_load_vector(structure, g)
    u = frames.solve(structure, f)

    q = DENSITY * section.area_m2 * GRAVITY
    # w(L/2) = 5 q L⁴ / (384 E I) + q L² / (8 κ G A), downwards
    assert_close(-u[dof(n // 2, axis)], 5 * q * length**4 / (384 * r.EI) + q * length**2 / (8 * r.kGA))
    # each support carries q L / 2 upwards
    reactions = fixed_reactions(structure, u, f)
    assert_close(reactions[[dof(0, axis), dof(n, axis)]], [q * length / 2] * 2)


# 3 ---------------------------------------------------------------------------------------------
@SECTIONS
@pytest.mark.parametrize("direction", [(1.0, 0.0, 0.0), (1.0, 2.0, 3.0)], ids=["along_x", "skew"])
def test_torsion(section, direction):
    """Shaft clamped at one end with an end torque about its own axis (also on a skew axis)."""
    length, n, torque = 0.8, 4, 150.0
    axis = np.asarray(direction) / np.linalg.norm(direction)
    coordinates, beams = straight(length, n, section, direction=axis)
    structure = frames.model(coordinates, beams, fixed_dofs=np.array(node_dofs(0)))
    u = frames.solve(structure, frames.point_load(structure.n_dofs, n, np.concatenate([np.zeros(3), torque * axis])))

    # φ = T L / (G J),  J = π (D⁴ − d⁴) / 32
    polar = np.pi * (section.outer_diameter_m**4 - section.inner_diameter_m**4) / 32
    rotation = u[node_dofs(n, range(3, 6))]
    assert_close(rotation @ axis, torque * length / (SHEAR_MODULUS * polar))
    assert np.linalg.norm(rotation - (rotation @ axis) * axis) < 1e-12 * np.linalg.norm(rotation)


# 4 ---------------------------------------------------------------------------------------------
def test_beam_on_two_springs_central_load():
    """Beam resting on two grounded translational springs at its ends, central point load."""
    section, length, n, force, k = CircularSection(0.03), 0.5, 4, -1.5e3, 2.0e6
    r = rigidities(section)
    coordinates, beams = straight(length, n, section)
    springs = frames.bushings([GROUND, GROUND], [0, n], coordinates[[0, n]], [[k, k, k, 0.0, 0.0, 0.0]] * 2)
    structure = frames.model(coordinates, beams, springs, fixed_dofs=np.array([dof(0, 3)]))
    u = frames.solve(structure, frames.point_load(structure.n_dofs, n // 2, [0.0, 0.0, force, 0.0, 0.0, 0.0]))

    # w(L/2) = P / (2 k) + P L³ / (48 E I) + P L / (4 κ G A)
    spring_part = force / (2 * k)
    assert_close(u[dof(n // 2, 2)], spring_part + force * length**3 / (48 * r.EI) + force * length / (4 * r.kGA))
    # each spring shortens by P / (2 k)
    assert_close(u[[dof(0, 2), dof(n, 2)]], [spring_part] * 2)


def test_axial_spring_in_series_with_bar():
    """Bar grounded through an axial spring, axial end force: u = P / k + P L / (E A)."""
    section, length, n, force, k = HOLLOW, 0.7, 3, 4.0e3, 5.0e7
    coordinates, beams = straight(length, n, section)
    stiff = 1e12
    spring = frames.bushings([GROUND], [0], coordinates[:1], [[k, stiff, stiff, stiff, stiff, stiff]])
    structure = frames.model(coordinates, beams, spring)
    u = frames.solve(structure, frames.point_load(structure.n_dofs, n, [force, 0.0, 0.0, 0.0, 0.0, 0.0]))

    # u(L) = P / k + P L / (E A)
    assert_close(u[dof(n, 0)], force / k + force * length / rigidities(section).EA)


# 5 ---------------------------------------------------------------------------------------------
def test_two_span_continuous_beam():
    """Two equal spans on three pins under self-weight: the middle support takes ≈ 1.25 q L.

    Removing the middle support leaves a simply supported span 2L. Its midspan deflection under
    q, 5 q (2L)⁴/(384 E I) + q (2L)²/(8 κ G A), must be cancelled by the reaction R with
    R (2L)³/(48 E I) + R (2L)/(4 κ G A), so with s = 3 E I / (κ G A L²):
    R = q L (5/4 + s) / (1 + s)  (Euler–Bernoulli: s = 0, R = 10 q L / 8), ends (2 q L − R) / 2.
    """
    section, span, n = CircularSection(0.05), 0.2, 6
    r = rigidities(section)
    coordinates, beams = frames.polyline([[0, 0, 0], [span, 0, 0], [2 * span, 0, 0]], n, section)
    supports = [0, n, 2 * n]
    pins = [dof(node, c) for node in supports for c in (1, 2)] + [dof(0, 0), dof(0, 3)]
    structure = frames.model(coordinates, beams, fixed_dofs=np.array(pins))
    f = gravity_load_vector(structure, [0.0, 0.0, -GRAVITY])
    reactions = fixed_reactions(structure, frames.solve(structure, f), f)[[dof(node, 2) for node in supports]]

    q = DENSITY * section.area_m2 * GRAVITY
    s = 3 * r.EI / (r.kGA * span**2)
    middle = q * span * (1.25 + s) / (1 + s)
    end = (2 * q * span - middle) / 2
    assert_close(reactions, [end, middle, end])
    # the shear correction matters here: the Euler–Bernoulli 1.25 q L would be off by more than the tolerance
    assert abs(1.25 * q * span / middle - 1) > REL_TOL


# 6 ---------------------------------------------------------------------------------------------
def test_l_frame_out_of_plane_load():
    """L-shaped frame in the x-y plane clamped at the origin, force P in z at the free end.

    Member 1 (length a along x) carries the force P and the torque P b about x; member 2
    (length b along y) is a cantilever from the corner. The twist φ = P b a / (G J) of member 1
    lifts the tip by φ b; its bending slope about y does not move the tip (offset along y).
    """
    section, a, b, n, force = SOLID, 0.6, 0.4, 4, 800.0
    r = rigidities(section)
    # reference z is perpendicular to both members
    coordinates, beams = frames.polyline([[0, 0, 0], [a, 0, 0], [a, b, 0]], n, section, reference=(0, 0, 1))
    structure = frames.model(coordinates, beams, fixed_dofs=np.array(node_dofs(0)))
    tip = 2 * n
    u = frames.solve(structure, frames.point_load(structure.n_dofs, tip, [0.0, 0.0, force, 0.0, 0.0, 0.0]))

    twist = force * b * a / r.GJ
    # w = P a³/(3EI) + P b³/(3EI) + P a b²/(GJ) + P (a + b)/(κGA)
    assert_close(u[dof(tip, 2)], force * (a**3 + b**3) / (3 * r.EI) + twist * b + force * (a + b) / r.kGA)
    # θx = P a b/(GJ) + P b²/(2EI);  θy = −P a²/(2EI)
    assert_close(u[dof(tip, 3)], twist + force * b**2 / (2 * r.EI))
    assert_close(u[dof(tip, 4)], -force * a**2 / (2 * r.EI))


# 7 ---------------------------------------------------------------------------------------------
def test_bushings_in_series():
    """Ground spring k1 and node-to-node spring k2 in series on coincident nodes, all six components.

    u0 = F / k1 and u1 = F / k1 + F / k2, component by component.
    """
    point = np.array([0.2, 0.1, -0.3])
    k1 = np.array([1e6, 2e6, 3e6, 4e4, 5e4, 6e4])
    k2 = np.array([7e6, 5e6, 2e6, 1e4, 9e4, 3e4])
    springs = frames.bushings([GROUND, 0], [0, 1], [point, point], [k1, k2])
    structure = frames.model([point, point], frames.no_beams(), springs)
    load = np.array([100.0, -200.0, 300.0, 10.0, -20.0, 30.0])
    u = frames.solve(structure, frames.point_load(structure.n_dofs, 1, load))

    assert_close(u[node_dofs(0)], load / k1)
    assert_close(u[node_dofs(1)], load / k1 + load / k2)


def test_offset_bushing_lever_arm():
    """Node 1 held by a bushing at distance e from it (node 0 clamped), transverse force F.

    The spring at the bushing point takes F and the moment F e:
    u_y = F / k_y + F e² / k_rz,  θ_z = F e / k_rz.
    """
    e, force = 0.5, 300.0
    stiffness = np.array([1e7, 2e6, 3e6, 4e4, 5e4, 6e4])
    springs = frames.bushings([0], [1], [[1.0 - e, 0.0, 0.0]], [stiffness])
    structure = frames.model([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], frames.no_beams(), springs,
                             fixed_dofs=np.array(node_dofs(0)))
    u = frames.solve(structure, frames.point_load(structure.n_dofs, 1, [0.0, force, 0.0, 0.0, 0.0, 0.0]))

    assert_close(u[dof(1, 1)], force / stiffness[1] + force * e**2 / stiffness[5])
    assert_close(u[dof(1, 5)], force * e / stiffness[5])


def test_offset_bushing_rigid_body_motion_stores_no_energy():
    """A bushing between non-coincident nodes, away from both: K has exactly the six rigid modes as kernel."""
    coordinates = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 3.0]])
    stiffness = np.array([1e7, 2e6, 3e6, 4e4, 5e4, 6e4])
    springs = frames.bushings([0], [1], [[0.3, -0.5, 0.7]], [stiffness])
    k = stiffness_matrix(frames.model(coordinates, frames.no_beams(), springs)).toarray()

    # rigid motion of both nodes: translation t and rotation θ give u_i = t + θ × x_i, θ_i = θ
    modes = np.zeros((12, 6))
    for j in range(6):
        motion = np.eye(6)[j]
        for node, x in enumerate(coordinates):
            modes[6 * node:6 * node + 3, j] = motion[:3] + np.cross(motion[3:], x)
            modes[6 * node + 3:6 * node + 6, j] = motion[3:]
    assert np.abs(k @ modes).max() < 1e-12 * np.abs(k).max() * np.abs(modes).max()
    # and nothing else is free: the six relative motions all store energy
    eigenvalues = np.linalg.eigvalsh(k)
    assert np.all(eigenvalues[6:] > 1e-6 * stiffness.min())
    assert np.allclose(k, k.T)


# 8 ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("beam_density", [0.0, DENSITY], ids=["massless_beam", "heavy_beam"])
def test_point_mass_weight_on_cantilever(beam_density):
    """Cantilever with a point mass at the tip under gravity in −y.

    δ = m g L³/(3EI) + m g L/(κGA), plus q L⁴/(8EI) + q L²/(2κGA) for the beam's own weight q = ρ A g.
    """
    section, length, n, mass = CircularSection(0.03), 0.5, 5, 20.0
    r = rigidities(section)
    coordinates, beams = straight(length, n, section, density=beam_density)
    masses = PointMasses(np.array([n]), np.array([mass]), np.array([[0.1, 0.2, 0.3]]))
    structure = frames.model(coordinates, beams, point_masses=masses, fixed_dofs=np.array(node_dofs(0)))
    u = frames.solve(structure, gravity_load_vector(structure, [0.0, -GRAVITY, 0.0]))

    weight, q = mass * GRAVITY, beam_density * section.area_m2 * GRAVITY
    expected = (weight * length**3 / (3 * r.EI) + weight * length / r.kGA
                + q * length**4 / (8 * r.EI) + q * length**2 / (2 * r.kGA))
    assert_close(-u[dof(n, 1)], expected)


# 9 ---------------------------------------------------------------------------------------------
def test_rigid_link_offset_load():
    """Cantilever whose tip is rigidly linked to an offset node (e_x, e_y, 0) loaded by F in z.

    At the tip F acts with the moment (e_x, e_y, 0) × (0, 0, F) = (e_y F, −e_x F, 0):
    w_tip = F L³/(3EI) + F L/(κGA) + e_x F L²/(2EI),  slope w' = F L²/(2EI) + e_x F L/(EI),
    twist φ = e_y F L/(GJ), and the offset node moves by w_tip + e_x w' + e_y φ.
    """
    section, length, n, force, ex, ey = SOLID, 0.6, 4, 500.0, 0.1, 0.05
    r = rigidities(section)
    coordinates, beams = straight(length, n, section)
    coordinates = np.vstack([coordinates, [length + ex, ey, 0.0]])
    offset = n + 1
    structure = frames.model(coordinates, beams, fixed_dofs=np.array(node_dofs(0))).with_group(
        RigidLinks(np.array([n]), np.array([offset])))
    u = frames.solve(structure, frames.point_load(structure.n_dofs, offset, [0.0, 0.0, force, 0.0, 0.0, 0.0]))

    w_tip = force * length**3 / (3 * r.EI) + force * length / r.kGA + ex * force * length**2 / (2 * r.EI)
    slope = force * length**2 / (2 * r.EI) + ex * force * length / r.EI
    twist = ey * force * length / r.GJ
    assert_close(u[[dof(n, 2), dof(n, 4), dof(n, 3)]], [w_tip, -slope, twist])
    assert_close(u[dof(offset, 2)], w_tip + ex * slope + ey * twist)
    assert np.array_equal(u[node_dofs(offset, range(3, 6))], u[node_dofs(n, range(3, 6))])


# 10 --------------------------------------------------------------------------------------------
def free_motions(structure):
    """find_free_motions of a model."""
    return find_free_motions(structure, assemble_frame(structure))


def motion_names(motion) -> set[str]:
    """The elementary motions named in a FreeMotion's directions."""
    return {name for direction in motion.directions for name in direction.split(" + ")}


def housing_and_rotor(bearing_stiffness):
    """A clamped 'housing' beam and a coaxial 'rotor' beam joined by two node-to-node bearings."""
    coordinates, beams = frames.join(straight(0.5, 2, SOLID), straight(0.5, 2, SOLID))
    bearings = frames.bushings([0, 2], [3, 5], coordinates[[0, 2]], [bearing_stiffness] * 2)
    return frames.model(coordinates, beams, bearings, fixed_dofs=np.array(node_dofs(0)),
                        node_group=np.array(["housing"] * 3 + ["rotor"] * 3))


def test_free_beam_is_reported_and_singular():
    """An unsupported 3D bracket next to a clamped beam: only the bracket is named, in all six directions."""
    bracket = frames.polyline([[0, 0, 0.1], [0.3, 0, 0.1], [0.3, 0.2, 0.1], [0.3, 0.2, 0.5]], 2, SOLID,
                              reference=(1, 1, 1))
    coordinates, beams = frames.join(straight(0.5, 2, SOLID), bracket)
    structure = frames.model(coordinates, beams, fixed_dofs=np.array(node_dofs(0)),
                             node_group=np.array(["housing"] * 3 + ["bracket"] * 7))
    motions = free_motions(structure)
    assert [m.parts for m in motions] == [("bracket",)]
    assert motion_names(motions[0]) == set(MOTION_NAMES)
    assert "'bracket'" in motions[0].describe()
    elimination, _ = constraint_elimination(structure)
    with pytest.raises(SingularModelError):
        factorize(stiffness_matrix(structure), elimination)


def test_shaft_on_radial_bushings_is_free_axially_and_in_spin():
    """A shaft on two grounded radial-only bushings can slide along and spin about x, nothing else."""
    coordinates, beams = straight(0.5, 4, SOLID)
    radial = frames.bushings([GROUND, GROUND], [0, 4], coordinates[[0, 4]], [[0.0, 1e8, 1e8, 0.0, 0.0, 0.0]] * 2)
    motions = free_motions(frames.model(coordinates, beams, radial))
    assert [m.parts for m in motions] == [("shaft",)]
    assert len(motions[0].directions) == 2
    assert motion_names(motions[0]) == {"translation x", "rotation about x"}


def test_rotor_on_radial_bearings_in_housing_is_free():
    """Radial-only bearings to a clamped housing leave the rotor (not the housing) free in x and spin."""
    motions = free_motions(housing_and_rotor([0.0, 1e8, 1e8, 0.0, 0.0, 0.0]))
    assert [m.parts for m in motions] == [("rotor",)]
    assert motion_names(motions[0]) == {"translation x", "rotation about x"}


def test_supported_models_report_nothing():
    """With axial and torsional bearing stiffness the rotor is held, and a torque on it is carried.

    The torque T at the rotor's middle flows to ground along two paths in parallel: half the
    rotor plus a bearing (k) into the clamped housing end, and half the rotor plus a bearing
    plus the whole housing (length L). θ = T / (1/C1 + 1/C2), C1 = L/(2GJ) + 1/k, C2 = C1 + L/(GJ).
    """
    length, k, torque = 0.5, 1e3, 10.0
    structure = housing_and_rotor([1e8, 1e8, 1e8, k, 0.0, 0.0])
    assert free_motions(structure) == []
    u = frames.solve(structure, frames.point_load(structure.n_dofs, 4, [0.0, 0.0, 0.0, torque, 0.0, 0.0]))

    gj = rigidities(SOLID).GJ
    near = length / (2 * gj) + 1 / k
    far = near + length / gj
    assert_close(u[dof(4, 3)], torque / (1 / near + 1 / far))


# 11 --------------------------------------------------------------------------------------------
def test_superposition_of_load_matrix():
    """Solving several load vectors at once equals solving them one by one, and loads superpose."""
    section, a, b, n = HOLLOW, 0.6, 0.4, 3
    coordinates, beams = frames.polyline([[0, 0, 0], [a, 0, 0], [a, b, 0]], n, section, reference=(0, 0, 1))
    structure = frames.model(coordinates, beams, fixed_dofs=np.array(node_dofs(0)))
    tip = 2 * n
    loads = np.column_stack([
        frames.point_load(structure.n_dofs, tip, [0.0, 0.0, 800.0, 0.0, 0.0, 0.0]),
        frames.point_load(structure.n_dofs, n, [300.0, -200.0, 0.0, 0.0, 0.0, 50.0]),
        gravity_load_vector(structure, [0.0, 0.0, -GRAVITY]),
    ])
    elimination, _ = constraint_elimination(structure)
    system = factorize(stiffness_matrix(structure), elimination)
    together = system.solve(loads)
    assert together.shape == loads.shape
    assert np.all(system.relative_residual(together, loads) < 1e-10)
    one_by_one = np.column_stack([frames.solve(structure, loads[:, j]) for j in range(loads.shape[1])])
    assert np.abs(together - one_by_one).max() <= 1e-12 * np.abs(one_by_one).max()
    combined = frames.solve(structure, loads.sum(axis=1))
    assert np.abs(combined - one_by_one.sum(axis=1)).max() <= 1e-12 * np.abs(combined).max()
