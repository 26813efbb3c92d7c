"""Two-node 3D Timoshenko beam element (12 DOF), vectorised over elements: an element type of a frame model.

The stiffness is the exact one of a uniform Timoshenko beam (shear-flexibility factor
Φ = 12 E I / (κ G A L²) in each bending plane), so nodal values are exact for end loads and
for uniformly distributed loads with the consistent load vector below. Axial and torsional
parts are the usual bar and shaft terms. All inputs are arrays with one row per element.

Local axes: x along the element; y from the reference vector (projected), z = x × y.
DOF order per node: ux, uy, uz, rx, ry, rz.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.contribution import Contribution, dense_entries

__all__ = ["BeamElements", "element_dofs", "end_forces", "gravity_load", "local_mass",
           "local_stiffness", "mass_triplets", "stiffness_triplets"]


@dataclass(frozen=True)
class BeamElements:
    """A table of beam elements with their section and material properties (SI).

    Parameters
    ----------
    connectivity : (n, 2) int array
        Node indices of each element.
    area_m2, second_moment_m4, polar_moment_m4, shear_coefficient : (n,) arrays
        ``shear_coefficient = inf`` makes Φ = 0: an Euler–Bernoulli element (no shear flexibility).
    youngs_modulus_Pa, shear_modulus_Pa, density_kg_per_m3 : (n,) arrays
    reference_vector : (n, 3) array
        A vector not parallel to the element axis that fixes local y.
    """

    connectivity: np.ndarray
    area_m2: np.ndarray
    second_moment_m4: np.ndarray
    polar_moment_m4: np.ndarray
    shear_coefficient: np.ndarray
    youngs_modulus_Pa: np.ndarray
    shear_modulus_Pa: np.ndarray
    density_kg_per_m3: np.ndarray
    reference_vector: np.ndarray

    def contribution(self, coordinates: np.ndarray, n_dofs: int, gravity_direction) -> Contribution:
        """Stiffness (:func:`stiffness_triplets`) and consistent weight (:func:`gravity_load`) as load ``"gravity"``."""
        weight = gravity_load(coordinates, self, np.asarray(gravity_direction, dtype=float), n_dofs)
        return Contribution(stiffness_triplets(coordinates, self), {"gravity": dense_entries(weight)})

    def mass_contribution(self, coordinates: np.ndarray) -> Contribution:
        """The consistent mass (:func:`mass_triplets`)."""
        return Contribution(mass=mass_triplets(coordinates, self))


def _rotations(coordinates: np.ndarray, elements: BeamElements) -> tuple[np.ndarray, np.ndarray]:
    """Direction-cosine matrices (n, 3, 3), rows = local axes in global coordinates, and lengths."""
    a = coordinates[elements.connectivity[:, 0]]
    b = coordinates[elements.connectivity[:, 1]]
    axis = b - a
    length = np.linalg.norm(axis, axis=1)
    if np.any(length <= 0.0):
        bad = np.flatnonzero(length <= 0.0)
        raise ValueError(f"beam elements {bad.tolist()} have zero length")
    ex = axis / length[:, None]
    ref = np.asarray(elements.reference_vector, dtype=float)
    ey = ref - np.sum(ref * ex, axis=1)[:, None] * ex
    norm = np.linalg.norm(ey, axis=1)
    if np.any(norm < 1e-9 * np.linalg.norm(ref, axis=1)):
        bad = np.flatnonzero(norm < 1e-9 * np.linalg.norm(ref, axis=1))
        raise ValueError(f"reference vector parallel to beam axis for elements {bad.tolist()}")
    ey = ey / norm[:, None]
    ez = np.cross(ex, ey)
    return np.stack([ex, ey, ez], axis=1), length


def _transformation(direction_cosines: np.ndarray) -> np.ndarray:
    """Block-diagonal 12×12 transformation global → local for each element."""
    n = direction_cosines.shape[0]
    t = np.zeros((n, 12, 12))
    for block in range(4):
        s = slice(3 * block, 3 * block + 3)
        t[:, s, s] = direction_cosines
    return t


def local_stiffness(length_m, elements: BeamElements) -> np.ndarray:
    """Local 12×12 stiffness matrices of uniform Timoshenko beams, shape (n, 12, 12)."""
    L = np.asarray(length_m, dtype=float)
    E = elements.youngs_modulus_Pa
    G = elements.shear_modulus_Pa
    A = elements.area_m2
    inertia = elements.second_moment_m4
    J = elements.polar_moment_m4
    kappa = np.asarray(elements.shear_coefficient, dtype=float)
    phi = np.where(np.isinf(kappa), 0.0, 12.0 * E * inertia / (kappa * G * A * L**2))  # κ = ∞: Euler–Bernoulli
    k = np.zeros((L.size, 12, 12))

    def put(i, j, value):
        k[:, i, j] = value
        k[:, j, i] = value

    axial = E * A / L
    put(0, 0, axial), put(6, 6, axial), put(0, 6, -axial)
    torsion = G * J / L
    put(3, 3, torsion), put(9, 9, torsion), put(3, 9, -torsion)

    c = E * inertia / ((1.0 + phi) * L**3)
    # bending in local x-y plane: DOFs v (1, 7) and θz (5, 11)
    put(1, 1, 12 * c), put(7, 7, 12 * c), put(1, 7, -12 * c)
    put(1, 5, 6 * L * c), put(1, 11, 6 * L * c), put(5, 7, -6 * L * c), put(7, 11, -6 * L * c)
    put(5, 5, (4 + phi) * L**2 * c), put(11, 11, (4 + phi) * L**2 * c)
    put(5, 11, (2 - phi) * L**2 * c)
    # bending in local x-z plane: DOFs w (2, 8) and θy (4, 10); θy = −dw/dx
    put(2, 2, 12 * c), put(8, 8, 12 * c), put(2, 8, -12 * c)
    put(2, 4, -6 * L * c), put(2, 10, -6 * L * c), put(4, 8, 6 * L * c), put(8, 10, 6 * L * c)
    put(4, 4, (4 + phi) * L**2 * c), put(10, 10, (4 + phi) * L**2 * c)
    put(4, 10, (2 - phi) * L**2 * c)
    return k


def _shear_parameter(length_m, elements: BeamElements) -> np.ndarray:
    """Φ = 12 E I / (κ G A L²) per element (0 for κ = ∞: Euler–Bernoulli)."""
    L = np.asarray(length_m, dtype=float)
    kappa = np.asarray(elements.shear_coefficient, dtype=float)
    return np.where(np.isinf(kappa), 0.0, 12.0 * elements.youngs_modulus_Pa * elements.second_moment_m4
                    / (kappa * elements.shear_modulus_Pa * elements.area_m2 * L**2))


def local_mass(length_m, elements: BeamElements) -> np.ndarray:
    """Local 12×12 consistent mass matrices of uniform Timoshenko beams, shape (n, 12, 12).

    The interpolation is the one the stiffness is exact for (the static Timoshenko deflection shapes, which
    depend on Φ): translational inertia ρ A and rotary inertia ρ I of the sections in both bending planes
    (Przemieniecki's matrices, *Theory of Matrix Structural Analysis*, 1968, eqs. 11.41–11.42, as polynomials
    in Φ over (1 + Φ)²), linear axial (ρ A) and torsional (ρ (I_y + I_z), the polar mass moment of the
    section) terms. Φ = 0 gives the Euler–Bernoulli consistent mass with rotary inertia.
    """
    L = np.asarray(length_m, dtype=float)
    phi = _shear_parameter(L, elements)
    rho = np.asarray(elements.density_kg_per_m3, dtype=float)
    A = elements.area_m2
    inertia = elements.second_moment_m4
    m = np.zeros((L.size, 12, 12))

    def put(i, j, value):
        m[:, i, j] = value
        m[:, j, i] = value

    axial = rho * A * L / 6.0
    put(0, 0, 2 * axial), put(6, 6, 2 * axial), put(0, 6, axial)
    polar = rho * 2.0 * inertia * L / 6.0  # circular sections: I_y = I_z = I
    put(3, 3, 2 * polar), put(9, 9, 2 * polar), put(3, 9, polar)

    d = (1.0 + phi) ** 2
    t = rho * A * L / d  # translational inertia
    t11 = t * (13 / 35 + 7 * phi / 10 + phi**2 / 3)
    t12 = t * L * (11 / 210 + 11 * phi / 120 + phi**2 / 24)
    t13 = t * (9 / 70 + 3 * phi / 10 + phi**2 / 6)
    t14 = t * L * (13 / 420 + 3 * phi / 40 + phi**2 / 24)
    t22 = t * L**2 * (1 / 105 + phi / 60 + phi**2 / 120)
    t24 = t * L**2 * (1 / 140 + phi / 60 + phi**2 / 120)
    r = rho * inertia / (L * d)  # rotary inertia
    r11 = r * 6 / 5
    r12 = r * L * (1 / 10 - phi / 2)
    r22 = r * L**2 * (2 / 15 + phi / 6 + phi**2 / 3)
    r24 = r * L**2 * (-1 / 30 - phi / 6 + phi**2 / 6)
    # x-y plane: v (1, 7), θz = dv/dx (5, 11)
    put(1, 1, t11 + r11), put(7, 7, t11 + r11), put(1, 7, t13 - r11)
    put(1, 5, t12 + r12), put(7, 11, -t12 - r12), put(1, 11, -t14 + r12), put(5, 7, t14 - r12)
    put(5, 5, t22 + r22), put(11, 11, t22 + r22), put(5, 11, -t24 + r24)
    # x-z plane: w (2, 8), θy = −dw/dx (4, 10): the w–θ couplings change sign
    put(2, 2, t11 + r11), put(8, 8, t11 + r11), put(2, 8, t13 - r11)
    put(2, 4, -t12 - r12), put(8, 10, t12 + r12), put(2, 10, t14 - r12), put(4, 8, -t14 + r12)
    put(4, 4, t22 + r22), put(10, 10, t22 + r22), put(4, 10, -t24 + r24)
    return m


def element_dofs(connectivity: np.ndarray) -> np.ndarray:
    """Global DOF numbers of each element, shape (n, 12)."""
    base = DOFS_PER_NODE * np.asarray(connectivity)
    offsets = np.arange(DOFS_PER_NODE)
    return np.concatenate([base[:, :1] + offsets, base[:, 1:2] + offsets], axis=1)


def _global_triplets(coordinates: np.ndarray, elements: BeamElements, local) -> tuple:
    """The local matrices ``local(length, elements)`` (n, 12, 12) rotated to global axes, as COO triplets."""
    if elements.connectivity.size == 0:
        return _empty_triplets()
    cosines, length = _rotations(coordinates, elements)
    t = _transformation(cosines)
    matrices = np.einsum("eji,ejk,ekl->eil", t, local(length, elements), t)
    dofs = element_dofs(elements.connectivity)
    rows = np.repeat(dofs, 12, axis=1).ravel()
    cols = np.tile(dofs, (1, 12)).ravel()
    return rows, cols, matrices.ravel()


def stiffness_triplets(coordinates: np.ndarray, elements: BeamElements):
    """Global stiffness of all beam elements as COO triplets ``(rows, cols, values)``."""
    return _global_triplets(coordinates, elements, local_stiffness)


def mass_triplets(coordinates: np.ndarray, elements: BeamElements):
    """Global consistent mass of all beam elements (:func:`local_mass`) as COO triplets ``(rows, cols, values)``."""
    return _global_triplets(coordinates, elements, local_mass)


def gravity_load(
    coordinates: np.ndarray, elements: BeamElements, acceleration_m_per_s2: np.ndarray, n_dofs: int
) -> np.ndarray:
    """Consistent nodal load vector of the beams' self-weight ρ A g (N, N·m).

    For a uniform line load q the consistent vector is q L / 2 per node and ∓ q L² / 12 end
    moments, which is exact at the nodes for Timoshenko beams too.
    """
    load = np.zeros(n_dofs)
    if elements.connectivity.size == 0:
        return load
    cosines, length = _rotations(coordinates, elements)
    q_global = (elements.density_kg_per_m3 * elements.area_m2)[:, None] * np.asarray(acceleration_m_per_s2)
    q = np.einsum("eij,ej->ei", cosines, q_global)  # local components
    f = np.zeros((length.size, 12))
    half = length / 2.0
    moment = length**2 / 12.0
    for node, sign in ((0, 1.0), (1, -1.0)):
        o = 6 * node
        f[:, o + 0] = q[:, 0] * half
        f[:, o + 1] = q[:, 1] * half
        f[:, o + 2] = q[:, 2] * half
        f[:, o + 5] = sign * q[:, 1] * moment
        f[:, o + 4] = -sign * q[:, 2] * moment
    f_global = np.einsum("eji,ej->ei", _transformation(cosines), f)
    np.add.at(load, element_dofs(elements.connectivity).ravel(), f_global.ravel())
    return load


def end_forces(coordinates: np.ndarray, elements: BeamElements, displacement: np.ndarray,
               acceleration_m_per_s2=None) -> np.ndarray:
    """Element end forces in local axes, f = k T u_e − f_line (N, N·m), shape (n, 12).

    Row layout as the DOFs: the forces and moments the nodes exert on the element at end a (0…5) and
    end b (6…11). The section forces follow: at end b N = f[6] (tension positive), Q_y = f[7], Q_z = f[8],
    T = f[9], M_y = f[10], M_z = f[11]; at end a the same components of −f[0…5]. With
    ``acceleration_m_per_s2`` the consistent self-weight load of the element (:func:`gravity_load`) is
    subtracted, so that the end forces are those of the loaded element and equilibrium holds per element.

    Parameters
    ----------
    coordinates : (n_nodes, 3) array
        Node positions (m).
    elements : BeamElements
    displacement : (n_dofs,) array
        The global displacement vector (only the beams' DOFs are read).
    acceleration_m_per_s2 : (3,) array, optional
        Gravity acting on the beams' mass, as in :func:`gravity_load`.
    """
    n = elements.connectivity.shape[0]
    if n == 0:
        return np.zeros((0, 12))
    cosines, length = _rotations(coordinates, elements)
    t = _transformation(cosines)
    u_local = np.einsum("eij,ej->ei", t, np.asarray(displacement, float)[element_dofs(elements.connectivity)])
    f = np.einsum("eij,ej->ei", local_stiffness(length, elements), u_local)
    if acceleration_m_per_s2 is not None:
        q_global = (elements.density_kg_per_m3 * elements.area_m2)[:, None] * np.asarray(acceleration_m_per_s2)
        q = np.einsum("eij,ej->ei", cosines, q_global)
        half, moment = length / 2.0, length**2 / 12.0
        for node, sign in ((0, 1.0), (1, -1.0)):
            o = 6 * node
            f[:, o:o + 3] -= q * half[:, None]
            f[:, o + 5] -= sign * q[:, 1] * moment
            f[:, o + 4] += sign * q[:, 2] * moment
    return f


def _empty_triplets():
    empty = np.zeros(0)
    return empty.astype(int), empty.astype(int), empty
