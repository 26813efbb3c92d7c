"""Housings condensed from a solid model: exactness of the condensation, beam theory, a Winkler bed,
mesh convergence, the cache, and the superelement in a rig.

Small meshes (a few thousand DOFs, well under a second each); the larger ones are in
benchmarks/bench_housing_condensation.py.
"""

from __future__ import annotations

import numpy as np
import pytest

from rvcoax.fem.condensation import condensed_stiffness, schur_complement, superelement_contribution
from rvcoax.fem.system import prepare_system
from rvcoax.geometry.housings import BlockGeometry, Reference
from rvcoax.geometry.model.condensed_housing import build_housing_model, condense_housing, solid_method

E, NU = 1.57e11, 0.27  # HT200
G = E / (2 * (1 + NU))


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("housings")


BLOCK = BlockGeometry("block", (248.0, 322.0), 90.0, -60.0, 45.0, bore_diameter_mm=47.0, foot_thickness_mm=12.0,
                      foot_width_mm=140.0, split_x_mm=(262.0, 308.0), mesh_size_mm=20.0)
REFERENCES = [Reference((255.0, 0.0, 0.0), ("bore", 248.0, 262.0)), Reference((315.0, 0.0, 0.0), ("bore", 308.0, 322.0))]


def column(size_mm: float, height_mm: float = 300.0, side_mm: float = 20.0) -> BlockGeometry:
    return BlockGeometry("column", (0.0, side_mm), side_mm, -height_mm, 0.0, mesh_size_mm=size_mm)


TOP = [Reference((10.0, 0.0, 0.0), ("top", 0.0, 20.0), "rigid")]


def test_condensed_stiffness_reproduces_the_full_model_at_the_masters(cache):
    """Two bearing seats of a bearing block (distributing ties), feet clamped: for random loads on the 12
    master DOFs, K_c⁻¹ f equals the full solid model's displacement there to rounding."""
    model = build_housing_model(BLOCK, E, NU, REFERENCES, cache_dir=cache)
    condensed = condensed_stiffness(model.stiffness, model.elimination, model.master_dofs, solid_method())
    assert condensed.shape == (12, 12) and np.allclose(condensed, condensed.T, rtol=0, atol=1e-9 * np.abs(condensed).max())
    assert np.all(np.linalg.eigvalsh(condensed) > 0)
    loads = np.random.default_rng(16).normal(size=(12, 5)) * np.array([1e3] * 3 + [50.0] * 3 + [1e3] * 3 + [50.0] * 3)[:, None]
    full = np.zeros((model.n_dofs, 5))
    full[model.master_dofs] = loads
    u = prepare_system(model.stiffness, model.elimination, solid_method(), symmetrize=True).solve(full)
    expected = u[model.master_dofs]
    assert np.linalg.solve(condensed, loads) == pytest.approx(expected, rel=1e-8, abs=1e-10 * np.abs(expected).max())


def test_flexibility_route_equals_guyan_schur_complement(cache):
    """Rigid ties make the reference DOFs independent: K_mm − K_ms K_ss⁻¹ K_sm of Tᵀ K T is the same matrix."""
    references = [Reference(r.point_mm, r.face, "rigid") for r in REFERENCES]
    model = build_housing_model(BLOCK, E, NU, references, cache_dir=cache)
    condensed = condensed_stiffness(model.stiffness, model.elimination, model.master_dofs, solid_method())
    reduced = (model.elimination.T @ model.stiffness @ model.elimination).tocsr()
    # the masters are the first 12 independent DOFs (the reference nodes come first and are not slaves)
    columns = model.elimination[model.master_dofs].tocoo()
    masters_q = columns.col[np.argsort(columns.row)]
    assert np.all(columns.data == 1.0)
    guyan = schur_complement(reduced, masters_q)
    assert guyan == pytest.approx(condensed, rel=1e-7, abs=1e-9 * np.abs(condensed).max())


def test_slender_pedestal_against_timoshenko_beam_theory(cache):
    """A 20 × 20 × 300 mm column clamped on the bed, loaded at its top through a rigid tie: tip compliance
    H³/3EI + H/κGA (κ = 10(1 + ν)/(12 + 11ν), Cowper's rectangle) and axial H/EA, to 1.5 %."""
    result = condense_housing(column(10.0), E, NU, TOP, cache_dir=cache)
    flexibility = np.linalg.inv(result.matrix)
    b, h = 0.02, 0.3
    inertia, area = b**4 / 12, b * b
    kappa = 10 * (1 + NU) / (12 + 11 * NU)
    bending = h**3 / (3 * E * inertia) + h / (kappa * G * area)
    assert flexibility[0, 0] == pytest.approx(bending, rel=0.015)
    assert flexibility[2, 2] == pytest.approx(bending, rel=0.015)
    assert flexibility[1, 1] == pytest.approx(h / (E * area), rel=0.015)
    assert flexibility[5, 5] == pytest.approx(h / (E * inertia), rel=0.015)  # tip rotation per moment about z


def test_pedestal_converges_with_mesh_size(cache):
    """Tip compliance at mesh sizes 20, 10 and 6.7 mm: the change halves (or better) with each refinement and the
    finest is within 1 % of beam theory."""
    values = [np.linalg.inv(condense_housing(column(size), E, NU, TOP, cache_dir=cache).matrix)[0, 0]
              for size in (20.0, 10.0, 6.7)]
    changes = np.abs(np.diff(values))
    assert changes[1] < 0.5 * changes[0]
    kappa = 10 * (1 + NU) / (12 + 11 * NU)
    bending = 0.3**3 / (3 * E * 0.02**4 / 12) + 0.3 / (kappa * G * 0.02**2)
    assert values[-1] == pytest.approx(bending, rel=0.01)


def test_pedestal_on_a_winkler_bed_adds_the_bed_compliance(cache):
    """Axial load on a prism (ν = 0) on a bed of normal stiffness k per area: a uniform stress state, which P2
    tetrahedra hold exactly, so the axial compliance is H/EA + 1/(k A) to rounding."""
    k = 2.0  # N/(µm·mm²)
    result = condense_housing(column(10.0), E, 0.0, TOP, feet="bed", bed_stiffness_N_per_um_per_mm2=(k, k * 1e-3),
                              cache_dir=cache)
    area = 0.02**2
    expected = 0.3 / (E * area) + 1.0 / (k * 1e12 * area)
    assert np.linalg.inv(result.matrix)[1, 1] == pytest.approx(expected, rel=1e-6)


def test_condensation_is_cached_by_content(cache):
    first = condense_housing(column(20.0, 200.0), E, NU, TOP, cache_dir=cache)
    again = condense_housing(column(20.0, 200.0), E, NU, TOP, cache_dir=cache)
    other = condense_housing(column(20.0, 200.0), 2 * E, NU, TOP, cache_dir=cache)
    assert not first.from_cache and again.from_cache and not other.from_cache
    assert np.array_equal(first.matrix, again.matrix)
    assert other.matrix[1, 1] == pytest.approx(2 * first.matrix[1, 1], rel=1e-9)


def test_superelement_contribution_places_the_matrix():
    matrix = np.arange(4.0).reshape(2, 2) + np.eye(2)
    rows, cols, values = superelement_contribution(matrix, [7, 3]).stiffness
    assert list(zip(rows, cols, values)) == [(7, 7, 1.0), (7, 3, 1.0), (3, 7, 2.0), (3, 3, 4.0)]
    with pytest.raises(ValueError, match="does not fit"):
        superelement_contribution(matrix, [1, 2, 3])


# ---- in the rig ------------------------------------------------------------------------------------------

INPUT_BLOCK = {  # the reference rig's input bearing block from geometry (docs/rig-file.md)
    "name": "input_block", "part": "input_bearing_block", "material": "HT200", "x_mm": [248.0, 320.0],
    "width_mm": 90.0, "height_above_bed_mm": 100.0, "top_above_axis_mm": 45.0, "bore_diameter_mm": 47.0,
    "foot_thickness_mm": 15.0, "foot_width_mm": 150.0, "attachments_x_mm": [255.0, 315.0],
    "attachment_width_mm": 14.0, "mesh_size_mm": 20.0,
}


def reference_with_block(**changes):
    import tomllib

    from rvcoax.geometry.rigfile import parse_rig, reference_rig_text

    data = tomllib.loads(reference_rig_text())
    data["mounts"] = [m for m in data["mounts"] if m["name"] != "input_block_base"]
    data["housings"] = [{**INPUT_BLOCK, **changes}]
    return parse_rig(data, "test")


def test_reference_rig_input_block_from_geometry_enters_like_a_bushing():
    """The condensed block replaces the typed-in mount input_block_base: the system gains exactly K_c on the
    block's two nodes, and the rig solves; the housing_stiffness effect scales it."""
    from rvcoax.fem.system import factorize
    from rvcoax.geometry.effects import effect_by_name
    from rvcoax.geometry.model.housings import condensed_housing
    from rvcoax.geometry.model.system import assemble_beam

    rig = reference_with_block()
    matrix = condensed_housing(rig, rig.housings[0]).matrix
    system = assemble_beam(rig)
    nodes = [system.frame.node("input_bearing_block", x) for x in (255.0, 315.0)]
    bed = [system.frame.node("input_block (bed)", x) for x in (255.0, 315.0)]
    dofs = (6 * np.asarray(nodes)[:, None] + np.arange(6)).ravel()
    bed_dofs = (6 * np.asarray(bed)[:, None] + np.arange(6)).ravel()
    softer = effect_by_name(rig, "housing_stiffness@input_block").apply(rig, [-1.0])
    assert softer.housings[0].stiffness_factor == 0.5
    difference = (system.stiffness - assemble_beam(softer).stiffness).toarray()
    assert difference[np.ix_(dofs, dofs)] == pytest.approx(0.5 * matrix, rel=1e-12, abs=1e-6)
    assert difference[np.ix_(dofs, bed_dofs)] == pytest.approx(-0.5 * matrix, rel=1e-12, abs=1e-6)
    both = np.concatenate([dofs, bed_dofs])
    assert np.abs(np.delete(np.delete(difference, both, 0), both, 1)).max() == 0.0
    assert set(bed_dofs) <= set(system.frame.structure.fixed_dofs.tolist())  # the bed side is held
    u = factorize(system.stiffness, system.elimination).solve(system.unit_loads["gravity"])
    assert np.isfinite(u).all() and u[6 * nodes[0] + 1] < 0  # the block sags under the rig's weight


def test_bad_housing_input_is_named():
    from rvcoax.geometry.rigfile import RigFileError

    with pytest.raises(RigFileError, match="does not fit inside the block"):
        reference_with_block(bore_diameter_mm=95.0)
    with pytest.raises(RigFileError, match="outside the housing's x_mm"):
        reference_with_block(attachments_x_mm=[240.0])
    with pytest.raises(RigFileError, match="needs bed_stiffness_N_per_um_per_mm2"):
        reference_with_block(feet="bed")
    with pytest.raises(RigFileError, match="unknown material"):
        reference_with_block(material="bronze")


def test_a_warm_housing_lifts_its_part_by_alpha_delta_t_h():
    """A block held only by its condensed housing (h = 100 mm, HT200 α = 1e-5/K, 30 K warmer, bed 10 K warmer
    pinned at x = 0): part and housing grow alike, so the part follows the housing free of stress:
    u_y = α ΔT h, u_x = α_bed ΔT_bed x_c + α ΔT (x − x_c) about the housing's centre x_c."""
    from closed_form_rigs import body, make_rig, rest_displacement, value

    housing = {**INPUT_BLOCK, "part": "block", "material": "steel", "mesh_size_mm": 20.0}
    rig = make_rig([body("block", 248.0, 320.0, 90.0)], "block", "block", housings=[housing])
    data = rig.model_dump(by_alias=True)
    data["materials"]["steel"]["thermal_expansion_per_K"] = 1e-5
    data["thermal"] = {"temperature_rise_K": {"block": 30.0}, "bed_temperature_rise_K": 10.0, "bed_material": "steel"}
    warm = type(rig).model_validate(data)
    frame, u = rest_displacement(warm)
    for x in (248.0, 255.0, 315.0, 320.0):
        assert value(frame, u, "block", x, 1) == pytest.approx(1e-5 * 30.0 * 0.1, rel=1e-6)
        assert value(frame, u, "block", x, 0) == pytest.approx(1e-5 * (10.0 * 284.0 + 30.0 * (x - 284.0)) * 1e-3,
                                                               rel=1e-6)
        assert abs(value(frame, u, "block", x, 5)) < 1e-12
