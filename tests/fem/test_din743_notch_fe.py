"""DIN 743-2's stress concentration factors α against an axisymmetric finite-element model of the notch.

Why: the published worked examples of DIN 743 (Beiblatt 1) could not be read (see docs/model.md, "Shaft stresses and
DIN 743 safety"), and the open-source cross-check (tests/fem/test_din743.py) exercises only the bending α of one
shoulder. The geometric half of DIN 743-2 — α of a shoulder and of a round groove in tension, bending and torsion,
whose constants (A, B, C, z) are recalled from the standard [R] — can be checked against something we did not make:
the elastic stress at the notch root, computed here with scikit-fem on the meridian section of the shaft.

The reference model (independent of rvcoax.fem.din743):
* the meridian half-section (z along the axis, r radial) meshed by gmsh into triangles, size r/12 at the notch
  radius and d/12 elsewhere, P2 elements, E = 210 GPa, ν = 0.3;
* tension: axisymmetric elasticity (u_r, u_z) with ε_θθ = u_r/r, traction σ at the far end, u_z = 0 at the other;
* torsion: the circumferential displacement v(r, z) alone, γ_rθ = ∂v/∂r − v/r, γ_θz = ∂v/∂z, end shear
  τ_θz ∝ r (a torque), v = 0 at the other end;
* bending: the first Fourier harmonic u_r = U cos θ, u_θ = V sin θ, u_z = W cos θ (unknowns W, P = U + V, V, so that
  W = P = 0 on the axis keeps the section single-valued), end traction σ_zz = M r cos θ / I, the other end clamped;
* α_FE = the largest principal stress (tension, bending) or surface shear (torsion) along the notch arc over the
  nominal stress of the notch section (4F/(π d²), 32M/(π d³), 16T/(π d³)), as DIN 743-2 defines α.

The reference is itself checked against closed forms: a shallow semicircular groove (t = r ≪ d) tends to an edge
notch in a half-space, where α → 2 exactly in torsion (antiplane shear: the semicircle is half of a circular hole,
w = τ/G (y + a² y/ρ²), surface shear 2τ) and α → 3.065 in tension and bending (C. B. Ling 1947, the plane solution for
a semicircular edge notch, as quoted in Peterson's Stress Concentration Factors [R]).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import skfem
from skfem import Basis, BilinearForm, ElementTriP2, ElementVector, FacetBasis, LinearForm, asm, condense, solve

from rvcoax.fem import din743
from rvcoax.geometry.meshing import gmsh_session

E_MPA, NU = 210e3, 0.3
LAME, SHEAR = E_MPA * NU / ((1 + NU) * (1 - 2 * NU)), E_MPA / (2 * (1 + NU))


def meridian_mesh(kind: str, d: float, t: float, r: float, per_radius: float = 12.0):
    """Triangles of the meridian half-section (x = z along the axis, y = radius) of a shaft with one shoulder
    (Ø d → Ø d + 2t, fillet r) or one U-groove (Ø d + 2t, depth t ≥ r, root radius r); mm. Returns the mesh, the
    centre of the notch radius and the shaft's length."""
    a, big = d / 2.0, d / 2.0 + t
    fine, coarse = r / per_radius, a / 6.0
    with gmsh_session("din743_notch") as gmsh:
        geo = gmsh.model.geo

        def point(z, y):
            return geo.addPoint(z, y, 0.0, coarse)

        flank = t - r > 1e-9 * t
        if kind == "shoulder":
            zs = 4.0 * d
            length = zs + 12.0 * big
            centre = (zs - r, a + r)
            p = [point(0, 0), point(0, a), point(zs - r, a)]
            c, p3 = point(*centre), point(zs, a + r)
            curves = [geo.addLine(p[0], p[1]), geo.addLine(p[1], p[2])]
            arcs = [geo.addCircleArc(p[2], c, p3)]
            p4 = point(zs, big) if flank else p3
            curves += arcs + ([geo.addLine(p3, p4)] if flank else [])
            p5, p6 = point(length, big), point(length, 0)
            curves += [geo.addLine(p4, p5), geo.addLine(p5, p6), geo.addLine(p6, p[0])]
        else:
            zg = 4.0 * big
            length = 2.0 * zg
            centre = (zg, big - t + r)
            p0, p1, q1, q5 = point(0, 0), point(0, big), point(zg - r, big), point(zg + r, big)
            q2, q4 = (point(zg - r, big - t + r), point(zg + r, big - t + r)) if flank else (q1, q5)
            c, bottom = point(*centre), point(zg, big - t)
            curves = [geo.addLine(p0, p1), geo.addLine(p1, q1)] + ([geo.addLine(q1, q2)] if flank else [])
            arcs = [geo.addCircleArc(q2, c, bottom), geo.addCircleArc(bottom, c, q4)]
            p5, p6 = point(length, big), point(length, 0)
            curves += arcs + ([geo.addLine(q4, q5)] if flank else [])
            curves += [geo.addLine(q5, p5), geo.addLine(p5, p6), geo.addLine(p6, p0)]
        geo.addPlaneSurface([geo.addCurveLoop(curves)])
        geo.synchronize()
        field = gmsh.model.mesh.field
        distance = field.add("Distance")
        field.setNumbers(distance, "CurvesList", arcs)
        field.setNumber(distance, "Sampling", 200)
        size = field.add("Threshold")
        field.setNumber(size, "InField", distance)
        for key, value in (("SizeMin", fine), ("SizeMax", coarse), ("DistMin", 0.5 * r), ("DistMax", 4 * r + 2 * coarse)):
            field.setNumber(size, key, value)
        field.setAsBackgroundMesh(size)
        for key in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
            gmsh.option.setNumber("Mesh." + key, 0)
        gmsh.model.mesh.generate(2)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        _, nodes = gmsh.model.mesh.getElementsByType(2)
    order = np.argsort(tags)
    index = np.empty(int(tags.max()) + 1, dtype=np.int64)
    index[tags[order]] = np.arange(tags.size)[order]
    triangles = index[nodes.astype(np.int64)].reshape(-1, 3).T
    points = xyz.reshape(-1, 3)[:, :2].T
    used = np.unique(triangles)  # drop gmsh's geometry-only points (the arc centres)
    renumber = np.full(points.shape[1], -1)
    renumber[used] = np.arange(used.size)
    return skfem.MeshTri(np.ascontiguousarray(points[:, used]), np.ascontiguousarray(renumber[triangles])), centre, length


def _notch_arc(mesh, centre, r):
    zc, yc = centre
    return mesh.facets_satisfying(lambda x: np.abs(np.hypot(x[0] - zc, x[1] - yc) - r) < 0.02 * r,
                                  boundaries_only=True)


def _end(mesh, basis_element, length):
    return FacetBasis(mesh, basis_element, facets=mesh.facets_satisfying(lambda x: x[0] > length * (1 - 1e-9),
                                                                          boundaries_only=True))


def _principal_meridian(szz, srr, srz, stt):
    """The largest principal stress of a meridian stress state (σ_zz, σ_rr, τ_rz) and the hoop stress σ_θθ."""
    return np.maximum(0.5 * (szz + srr) + np.sqrt(0.25 * (szz - srr) ** 2 + srz**2), stt).max()


def _kt_tension(mesh, centre, r, d, length):
    element = ElementVector(ElementTriP2())
    basis = Basis(mesh, element)

    def strains(u, radius):
        return u.grad[0, 0], u.grad[1, 1], u[1] / radius, u.grad[0, 1] + u.grad[1, 0]

    @BilinearForm
    def stiffness(u, v, w):
        zu, ru, tu, gu = strains(u, w.x[1])
        zv, rv, tv, gv = strains(v, w.x[1])
        return (LAME * (zu + ru + tu) * (zv + rv + tv) + 2 * SHEAR * (zu * zv + ru * rv + tu * tv)
                + SHEAR * gu * gv) * w.x[1]

    @LinearForm
    def traction(v, w):  # σ_zz = 1 on the far end
        return v[0] * w.x[1]

    fixed = np.concatenate([basis.get_dofs(lambda x: x[0] < 1e-9).all("u^1"),
                            basis.get_dofs(lambda x: x[1] < 1e-9).all("u^2")])
    u = solve(*condense(asm(stiffness, basis), asm(traction, _end(mesh, element, length)), D=fixed))
    arc = FacetBasis(mesh, element, facets=_notch_arc(mesh, centre, r))
    zz, rr, tt, rz = strains(arc.interpolate(u), arc.global_coordinates()[1])
    trace = zz + rr + tt
    peak = _principal_meridian(LAME * trace + 2 * SHEAR * zz, LAME * trace + 2 * SHEAR * rr, SHEAR * rz,
                               LAME * trace + 2 * SHEAR * tt)
    force = math.pi * mesh.p[1].max() ** 2
    return peak / (force / (math.pi * d**2 / 4))


def _kt_torsion(mesh, centre, r, d, length):
    element = ElementTriP2()
    basis = Basis(mesh, element)

    @BilinearForm
    def stiffness(u, v, w):
        radius = w.x[1]
        return SHEAR * ((u.grad[1] - u / radius) * (v.grad[1] - v / radius) + u.grad[0] * v.grad[0]) * radius

    @LinearForm
    def traction(v, w):  # τ_θz = r on the far end
        return w.x[1] ** 2 * v

    fixed = np.concatenate([basis.get_dofs(lambda x: x[0] < 1e-9).all(), basis.get_dofs(lambda x: x[1] < 1e-9).all()])
    u = solve(*condense(asm(stiffness, basis), asm(traction, _end(mesh, element, length)), D=fixed))
    arc = FacetBasis(mesh, element, facets=_notch_arc(mesh, centre, r))
    field, radius = arc.interpolate(u), arc.global_coordinates()[1]
    peak = (SHEAR * np.hypot(field.grad[1] - field / radius, field.grad[0])).max()
    torque = math.pi * mesh.p[1].max() ** 4 / 2
    return peak / (16 * torque / (math.pi * d**3))


def _kt_bending(mesh, centre, r, d, length):
    element = ElementVector(ElementTriP2(), dim=3)  # (W, P = U + V, V)
    basis = Basis(mesh, element)

    def strains(u, radius):
        w_, p_ = u[0], u[1]
        zz, rr, tt = u.grad[0, 0], u.grad[1, 1] - u.grad[2, 1], p_ / radius
        rz = u.grad[1, 0] - u.grad[2, 0] + u.grad[0, 1]
        return zz, rr, tt, rz, u.grad[2, 1] - p_ / radius, u.grad[2, 0] - w_ / radius

    @BilinearForm
    def stiffness(u, v, w):
        zu, ru, tu, gu, hu, ku = strains(u, w.x[1])
        zv, rv, tv, gv, hv, kv = strains(v, w.x[1])
        return (LAME * (zu + ru + tu) * (zv + rv + tv) + 2 * SHEAR * (zu * zv + ru * rv + tu * tv)
                + SHEAR * (gu * gv + hu * hv + ku * kv)) * w.x[1]

    @LinearForm
    def traction(v, w):  # σ_zz = r cos θ on the far end
        return w.x[1] ** 2 * v[0]

    fixed = np.concatenate([basis.get_dofs(lambda x: x[0] < 1e-9).all(),
                            basis.get_dofs(lambda x: x[1] < 1e-9).all(["u^1", "u^2"])])
    u = solve(*condense(asm(stiffness, basis), asm(traction, _end(mesh, element, length)), D=fixed))
    arc = FacetBasis(mesh, element, facets=_notch_arc(mesh, centre, r))
    zz, rr, tt, rz, _, _ = strains(arc.interpolate(u), arc.global_coordinates()[1])
    trace = zz + rr + tt
    peak = _principal_meridian(LAME * trace + 2 * SHEAR * zz, LAME * trace + 2 * SHEAR * rr, SHEAR * rz,
                               LAME * trace + 2 * SHEAR * tt)
    moment = math.pi * mesh.p[1].max() ** 4 / 4
    return peak / (32 * moment / (math.pi * d**3))


def fe_alpha(kind: str, d: float, t: float, r: float, per_radius: float = 12.0) -> dict[str, float]:
    """α of the notch in tension, bending and torsion from the axisymmetric FE model."""
    mesh, centre, length = meridian_mesh(kind, d, t, r, per_radius)
    return {"tension": _kt_tension(mesh, centre, r, d, length), "bending": _kt_bending(mesh, centre, r, d, length),
            "torsion": _kt_torsion(mesh, centre, r, d, length)}


def din_alpha(kind: str, d: float, t: float, r: float) -> dict[str, float]:
    """DIN 743-2's α as rvcoax.fem.din743 computes them (α does not depend on the steel)."""
    f = din743.notch_factors(din743.Notch(kind, d, depth_mm=t, radius_mm=r), 1000.0, 800.0)
    return {"tension": f.alpha_tension, "bending": f.alpha_bending, "torsion": f.alpha_torsion}


# DIN 743-2's α against the FE reference: measured (FE with 12 and 24 elements per notch radius agree to 0.4 %) the
# formula lies 13 % below to 3 % above the elastic stress of the FE model over 13 shoulders and grooves inside its
# range (d/D ≤ 0.98, r/t ≥ 0.03; the table is in docs/model.md). The band below is that accuracy, not ours.
# Measured by perturbing the constants: it catches a load type's constants swapped with another's (α moves by
# 20-65 %) and A or B of most load types off by a factor of 2, not an error of 20-25 % and not the shoulders'
# C (a small term at these geometries).
DIN_BELOW_FE, DIN_ABOVE_FE = 0.15, 0.05
QUICK = [("shoulder", 84.0, 8.0, 4.0), ("groove", 40.0, 2.0, 1.0)]  # the open-source case's shoulder; a groove
GRID = [("shoulder", 40.0, 5.0, 1.0), ("shoulder", 40.0, 5.0, 5.0), ("shoulder", 30.0, 10.0, 2.0),
        ("shoulder", 30.0, 10.0, 6.0), ("shoulder", 100.0, 10.0, 1.0), ("shoulder", 40.0, 2.0, 0.5),
        ("groove", 40.0, 4.0, 1.0), ("groove", 40.0, 2.0, 2.0), ("groove", 40.0, 5.0, 5.0), ("groove", 30.0, 3.0, 0.5)]


@pytest.fixture(scope="module")
def shallow_grooves():
    return {r: fe_alpha("groove", 40.0, r, r) for r in (0.1, 0.2)}


def test_fe_reference_meets_the_closed_forms_of_a_shallow_groove(shallow_grooves):
    """r/d = 0.0025 and 0.005 extrapolated linearly to r/d → 0: the edge notch in a half-space."""
    limit = {load: 2.0 * shallow_grooves[0.1][load] - shallow_grooves[0.2][load] for load in shallow_grooves[0.1]}
    assert limit["torsion"] == pytest.approx(2.0, rel=0.005)  # closed form (antiplane shear)
    assert limit["tension"] == pytest.approx(3.065, rel=0.005)  # Ling 1947 [R]
    assert limit["bending"] == pytest.approx(3.065, rel=0.005)  # the gradient vanishes with r/d


def _within_din_accuracy(kind, d, t, r, fe):
    din = din_alpha(kind, d, t, r)
    for load in fe:
        assert -DIN_BELOW_FE <= din[load] / fe[load] - 1.0 <= DIN_ABOVE_FE, (kind, d, t, r, load, din[load], fe[load])


@pytest.mark.parametrize("geometry", QUICK, ids=lambda g: f"{g[0]}-d{g[1]:g}-t{g[2]:g}-r{g[3]:g}")
def test_din743_alpha_against_fe(geometry):
    _within_din_accuracy(*geometry, fe_alpha(*geometry))


@pytest.mark.slow
@pytest.mark.parametrize("geometry", GRID, ids=lambda g: f"{g[0]}-d{g[1]:g}-t{g[2]:g}-r{g[3]:g}")
def test_din743_alpha_against_fe_over_the_range(geometry):
    _within_din_accuracy(*geometry, fe_alpha(*geometry))


@pytest.mark.slow
def test_fe_reference_is_mesh_converged():
    coarse, fine = fe_alpha("shoulder", 40.0, 5.0, 1.0, 8.0), fe_alpha("shoulder", 40.0, 5.0, 1.0, 16.0)
    for load in coarse:
        assert coarse[load] == pytest.approx(fine[load], rel=0.005)
