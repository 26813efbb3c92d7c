"""Section forces and shaft stresses from beam end forces against closed forms.

Statically determinate cases, so the section forces do not depend on the stiffness: the moment of a simply
supported stepped shaft under a point load (M = F b x / L left of the load, F a (L − x)/L right of it), under
its own weight (M = q x (L − x)/2 per uniform part), and a cantilevered hollow shaft in torsion and tension
(τ = T (D/2)/J, σ = N/A). Stresses: σ_b = M/W_b with each section's own diameter (Gere & Goodno, *Mechanics of
Materials*, the flexure and torsion formulas; τ_q,max = 4/3 Q/A of a solid round section).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rvcoax.fem import beam
from rvcoax.fem.sections import CircularSection
from rvcoax.fem.shaft_stress import SectionForces, section_forces, section_stresses

E, G, RHO = 210e9, 80.8e9, 7850.0


def _shaft(x: np.ndarray, outer: np.ndarray, inner: np.ndarray):
    """Nodes on the x axis and one beam per interval with its section (outer/inner diameter per element, m)."""
    n = x.size - 1
    sections = [CircularSection(o, i) for o, i in zip(outer, inner)]
    elements = beam.BeamElements(
        connectivity=np.column_stack([np.arange(n), np.arange(1, n + 1)]),
        area_m2=np.array([s.area_m2 for s in sections]),
        second_moment_m4=np.array([s.second_moment_m4 for s in sections]),
        polar_moment_m4=np.array([s.polar_moment_m4 for s in sections]),
        shear_coefficient=np.array([s.shear_coefficient(0.3) for s in sections]),
        youngs_modulus_Pa=np.full(n, E), shear_modulus_Pa=np.full(n, G), density_kg_per_m3=np.full(n, RHO),
        reference_vector=np.tile([0.0, 1.0, 0.0], (n, 1)))
    coordinates = np.column_stack([x, np.zeros_like(x), np.zeros_like(x)])
    return coordinates, elements


def _solve(coordinates, elements, load: np.ndarray, fixed: list[int]) -> np.ndarray:
    n_dofs = 6 * coordinates.shape[0]
    rows, cols, values = beam.stiffness_triplets(coordinates, elements)
    k = sp.csr_matrix((values, (rows, cols)), shape=(n_dofs, n_dofs))
    free = np.setdiff1d(np.arange(n_dofs), fixed)
    u = np.zeros(n_dofs)
    u[free] = spla.spsolve(k[free][:, free].tocsc(), load[free])
    return u


STEP_X = 0.12  # m: Ø30 → Ø40 (bore 12 mm over the thicker part)
L = 0.30


def _stepped():
    x = np.linspace(0.0, L, 31)
    mid = 0.5 * (x[:-1] + x[1:])
    outer = np.where(mid < STEP_X, 0.030, 0.040)
    inner = np.where(mid < STEP_X, 0.0, 0.012)
    return _shaft(x, outer, inner), outer, inner


def _simply_supported(n_nodes: int) -> list[int]:
    last = 6 * (n_nodes - 1)
    return [0, 1, 2, 3, last + 1, last + 2]


def test_stepped_shaft_point_load_moment_and_bending_stress():
    """M(x) = F b x / L and σ_b = M/W_b on each side of the step, to rounding (statically determinate)."""
    (coordinates, elements), outer, inner = _stepped()
    x = coordinates[:, 0]
    load_node, force = 18, -2000.0  # 0.18 m, N in −y
    f = np.zeros(6 * x.size)
    f[6 * load_node + 1] = force
    u = _solve(coordinates, elements, f, _simply_supported(x.size))
    a_end, b_end = section_forces(beam.end_forces(coordinates, elements, u))
    a, b = x[load_node], L - x[load_node]

    def moment(xs):
        return np.where(xs <= a, abs(force) * b * xs / L, abs(force) * a * (L - xs) / L)

    np.testing.assert_allclose(a_end.bending_moment_Nm, moment(x[:-1]), atol=1e-9 * abs(force) * L)
    np.testing.assert_allclose(b_end.bending_moment_Nm, moment(x[1:]), atol=1e-9 * abs(force) * L)
    stresses = section_stresses(b_end, outer, inner)
    w_b = np.pi * (outer**4 - inner**4) / (32.0 * outer)
    np.testing.assert_allclose(stresses.bending_MPa, moment(x[1:]) / w_b * 1e-6, rtol=1e-9, atol=1e-9)
    # the step: the same moment, a stress jump by the ratio of the section moduli
    step = int(np.flatnonzero(np.isclose(x, STEP_X))[0])
    left, right = stresses.bending_MPa[step - 1], section_stresses(a_end, outer, inner).bending_MPa[step]
    assert left / right == pytest.approx((np.pi * 0.04**4 * (1 - 0.3**4) / (32 * 0.04)) / (np.pi * 0.03**3 / 32))
    # shear force: F b / L left of the load, 4/3 Q/A on the solid part
    np.testing.assert_allclose(b_end.shear_force_N[: load_node], abs(force) * b / L, rtol=1e-9)
    solid = stresses.transverse_shear_MPa[0]
    assert solid == pytest.approx(4.0 / 3.0 * abs(force) * b / L / (np.pi / 4 * 0.03**2) * 1e-6, rel=1e-9)
    assert np.all(stresses.torsion_MPa < 1e-9) and np.all(np.abs(stresses.axial_MPa) < 1e-9)


def test_self_weight_moment_with_consistent_load_subtracted():
    """A uniform simply supported shaft under its own weight: M(x) = q x (L − x)/2 at every node, which only
    holds with the elements' consistent line load taken off their end forces."""
    x = np.linspace(0.0, L, 13)
    coordinates, elements = _shaft(x, np.full(12, 0.03), np.zeros(12))
    g = np.array([0.0, -9.81, 0.0])
    u = _solve(coordinates, elements, beam.gravity_load(coordinates, elements, g, 6 * x.size),
               _simply_supported(x.size))
    _, b_end = section_forces(beam.end_forces(coordinates, elements, u, acceleration_m_per_s2=g))
    q = RHO * np.pi / 4 * 0.03**2 * 9.81
    np.testing.assert_allclose(b_end.bending_moment_Nm, q * x[1:] * (L - x[1:]) / 2.0, atol=1e-9 * q * L**2)
    _, raw = section_forces(beam.end_forces(coordinates, elements, u))
    assert np.max(np.abs(raw.bending_moment_Nm - q * x[1:] * (L - x[1:]) / 2.0)) > 1e-3 * q * L**2 / 8


def test_hollow_shaft_torsion_and_tension():
    """A cantilevered hollow shaft with an end torque and an end pull: τ_t = T (D/2)/J, σ_ax = N/A, and
    von Mises √(σ² + 3τ²) at the outer fibre, along the whole shaft."""
    x = np.linspace(0.0, 0.2, 9)
    D, d = 0.05, 0.03
    coordinates, elements = _shaft(x, np.full(8, D), np.full(8, d))
    torque, pull = 350.0, 20e3
    f = np.zeros(6 * x.size)
    f[6 * 8 + 3], f[6 * 8] = torque, pull
    u = _solve(coordinates, elements, f, list(range(6)))
    a_end, b_end = section_forces(beam.end_forces(coordinates, elements, u))
    for forces in (a_end, b_end):
        np.testing.assert_allclose(forces.torque_Nm, torque, rtol=1e-9)
        np.testing.assert_allclose(forces.axial_N, pull, rtol=1e-9)
        s = section_stresses(forces, np.full(8, D), np.full(8, d))
        tau = torque * (D / 2) / (np.pi * (D**4 - d**4) / 32) * 1e-6
        sigma = pull / (np.pi / 4 * (D**2 - d**2)) * 1e-6
        np.testing.assert_allclose(s.torsion_MPa, tau, rtol=1e-9)
        np.testing.assert_allclose(s.axial_MPa, sigma, rtol=1e-9)
        np.testing.assert_allclose(s.von_mises_MPa, np.hypot(sigma, np.sqrt(3) * tau), rtol=1e-9)


def test_section_stresses_refuse_bad_sections():
    forces = SectionForces(*(np.zeros(1) for _ in range(6)))
    with pytest.raises(ValueError, match="bore"):
        section_stresses(forces, np.array([0.02]), np.array([0.02]))
