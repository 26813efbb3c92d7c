"""Small builders for the verification tests: straight and polyline beam models in steel.

Everything is SI. A model is built from a polyline of key points, each segment divided into
equal beam elements of one circular section; supports are given as fixed DOFs or bushings.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.beam import BeamElements
from rvcoax.fem.bushing import Bushings
from rvcoax.fem.equilibrium import check_equilibrium
from rvcoax.fem.loads import NodalLoads, nodal_load_vector
from rvcoax.fem.model import StructuralModel
from rvcoax.fem.pieces import assemble_frame
from rvcoax.fem.sections import CircularSection
from rvcoax.fem.system import factorize

YOUNGS_MODULUS = 210e9
POISSON = 0.3
SHEAR_MODULUS = YOUNGS_MODULUS / (2.0 * (1.0 + POISSON))
DENSITY = 7850.0
GRAVITY = 9.81

REL_TOL = 5e-3
"""Relative tolerance of every closed-form comparison (0.5 %)."""

EQUILIBRIUM_TOL = 1e-9
"""Largest accepted relative error of the global equilibrium check."""


class Rigidities(NamedTuple):
    """Section rigidities of one circular section in steel."""

    EI: float  # bending, N·m²
    kGA: float  # shear, κ G A in N
    GJ: float  # torsion, N·m²
    EA: float  # axial, N


def rigidities(section: CircularSection) -> Rigidities:
    """Bending, shear (with Cowper's κ), torsion and axial rigidity of ``section``."""
    return Rigidities(
        EI=YOUNGS_MODULUS * section.second_moment_m4,
        kGA=section.shear_coefficient(POISSON) * SHEAR_MODULUS * section.area_m2,
        GJ=SHEAR_MODULUS * section.polar_moment_m4,
        EA=YOUNGS_MODULUS * section.area_m2,
    )


def dof(node: int, component: int) -> int:
    """Global DOF number of ``component`` (0..5 = ux, uy, uz, rx, ry, rz) of ``node``."""
    return DOFS_PER_NODE * node + component


def node_dofs(node: int, components=range(DOFS_PER_NODE)) -> list[int]:
    """Global DOF numbers of several components of one node."""
    return [dof(node, c) for c in components]


def point_load(n_dofs: int, node: int, components) -> np.ndarray:
    """Load vector of one nodal force/moment ``components`` = (Fx, Fy, Fz, Mx, My, Mz)."""
    return nodal_load_vector(NodalLoads(np.array([node]), np.asarray(components, float)[None, :]), n_dofs)


def polyline(points, n_per_segment: int, section: CircularSection, reference=(0.0, 0.0, 1.0),
             density: float = DENSITY) -> tuple[np.ndarray, BeamElements]:
    """Nodes and beam elements along a polyline.

    Parameters
    ----------
    points : (k, 3) array_like
        Key points; node ``i * n_per_segment`` sits on key point ``i``.
    n_per_segment : int
        Number of equal elements per segment.
    section : CircularSection
        Section of every element.
    reference : (3,) array_like
        Reference vector of every element (must not be parallel to any segment).
    density : float
        Mass density in kg/m³.

    Returns
    -------
    coordinates : (n_nodes, 3) ndarray
    beams : BeamElements
    """
    points = np.asarray(points, dtype=float)
    t = np.linspace(0.0, 1.0, n_per_segment + 1)[1:, None]
    coordinates = np.vstack([points[:1]] + [a + t * (b - a) for a, b in zip(points[:-1], points[1:], strict=True)])
    n = coordinates.shape[0] - 1
    ones = np.ones(n)
    beams = BeamElements(
        connectivity=np.column_stack([np.arange(n), np.arange(1, n + 1)]),
        area_m2=section.area_m2 * ones,
        second_moment_m4=section.second_moment_m4 * ones,
        polar_moment_m4=section.polar_moment_m4 * ones,
        shear_coefficient=section.shear_coefficient(POISSON) * ones,
        youngs_modulus_Pa=YOUNGS_MODULUS * ones,
        shear_modulus_Pa=SHEAR_MODULUS * ones,
        density_kg_per_m3=density * ones,
        reference_vector=np.tile(np.asarray(reference, dtype=float), (n, 1)),
    )
    return coordinates, beams


def join(*parts) -> tuple[np.ndarray, BeamElements]:
    """Put several ``(coordinates, beams)`` parts into one node and element numbering.

    Nodes of part ``k`` follow those of parts ``0 .. k−1``; nothing connects the parts.
    """
    offsets = np.cumsum([0] + [len(coordinates) for coordinates, _ in parts[:-1]])
    tables = [beams for _, beams in parts]
    fields = {name: np.concatenate([vars(table)[name] for table in tables])
              for name in vars(tables[0]) if name != "connectivity"}
    connectivity = np.vstack([table.connectivity + offset for table, offset in zip(tables, offsets, strict=True)])
    return np.vstack([coordinates for coordinates, _ in parts]), BeamElements(connectivity=connectivity, **fields)


def no_beams() -> BeamElements:
    """An empty beam table (models made of bushings only)."""
    empty = np.zeros(0)
    return BeamElements(np.zeros((0, 2), int), empty, empty, empty, empty, empty, empty, empty, np.zeros((0, 3)))


def bushings(node_a, node_b, point_m, stiffness) -> Bushings:
    """Bushing table from lists (one row per bushing); ``node_a = GROUND`` grounds node b."""
    return Bushings(np.asarray(node_a, int), np.asarray(node_b, int),
                    np.asarray(point_m, float).reshape(-1, 3), np.asarray(stiffness, float).reshape(-1, 6))


def no_bushings() -> Bushings:
    """An empty bushing table."""
    return bushings([], [], np.zeros((0, 3)), np.zeros((0, 6)))


def model(coordinates, beams, bushing_table=None, group: str = "shaft", **kwargs) -> StructuralModel:
    """A StructuralModel whose nodes all belong to one part ``group``; kwargs go to the model."""
    return StructuralModel(
        np.asarray(coordinates, float),
        beams,
        no_bushings() if bushing_table is None else bushing_table,
        node_group=kwargs.pop("node_group", np.full(len(coordinates), group)),
        **kwargs,
    )


def stiffness_matrix(structure: StructuralModel):
    """K of a frame model, through the one assembly path (:func:`rvcoax.fem.pieces.assemble_frame`)."""
    return assemble_frame(structure).stiffness


def constraint_elimination(structure: StructuralModel):
    """T (u = T q) and the independent DOFs of a frame model."""
    system = assemble_frame(structure)
    return system.elimination, system.free_dofs


def gravity_load_vector(structure: StructuralModel, acceleration_m_per_s2) -> np.ndarray:
    """The weight of a frame model's beams and point masses under ``acceleration_m_per_s2`` (3,)."""
    return assemble_frame(structure, acceleration_m_per_s2).loads["gravity"]


def solve(structure: StructuralModel, load: np.ndarray) -> np.ndarray:
    """Static displacements for one load vector, after checking residual and global equilibrium.

    Raises
    ------
    AssertionError
        If the reduced residual or the equilibrium error exceeds its tolerance.
    """
    stiffness = stiffness_matrix(structure)
    elimination, _ = constraint_elimination(structure)
    system = factorize(stiffness, elimination)
    displacement = system.solve(load)
    assert system.relative_residual(displacement, load) < 1e-10
    error = check_equilibrium(structure, stiffness, displacement, load).relative_error
    assert error < EQUILIBRIUM_TOL, f"equilibrium error {error:.2e}"
    return displacement


def relative_error(actual, expected) -> float:
    """Largest ``|actual − expected| / |expected|`` over the entries."""
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    return float(np.max(np.abs(actual - expected) / np.abs(expected)))


def assert_close(actual, expected, rtol: float = REL_TOL) -> float:
    """Assert agreement with a closed-form value within ``rtol``; returns the relative error."""
    error = relative_error(actual, expected)
    assert error < rtol, f"FE {actual} vs closed form {expected}: relative error {error:.2e}"
    return error
