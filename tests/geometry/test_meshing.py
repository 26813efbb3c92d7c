"""Solid meshing of round parts: geometry, conformity to split planes, the mesh cache, DOF estimate."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
import skfem

from rvcoax.geometry.meshing import MeshingError, SolidPartGeometry, cache_path, estimate_dofs, mesh_part

# a stepped hollow shaft: bore through two segments, a solid end, a load band between 60 and 70 mm
STEPPED = SolidPartGeometry(
    "stepped", ((0.0, 40.0, 30.0, 10.0), (40.0, 100.0, 40.0, 10.0), (100.0, 120.0, 25.0, 0.0)), (60.0, 70.0), 6.0
)


@pytest.fixture
def cache(tmp_path):
    return tmp_path / "meshes"


@pytest.fixture(scope="module")
def stepped_mesh(tmp_path_factory):
    return mesh_part(STEPPED, cache_dir=tmp_path_factory.mktemp("meshes"))


def curved_volume(mesh) -> float:
    return float(skfem.Basis(mesh, skfem.ElementTetP2(), intorder=4).dx.sum())


def test_volume_of_stepped_hollow_shaft(stepped_mesh):
    """∫ 1 dV over the curved P2 mesh (metres) equals the analytic volume to 0.2 %."""
    exact = STEPPED.volume_mm3 * 1e-9
    assert STEPPED.volume_mm3 == pytest.approx(math.pi / 4 * (800 * 40 + 1500 * 60 + 625 * 20))
    assert isinstance(stepped_mesh, skfem.MeshTet2)
    assert curved_volume(stepped_mesh) == pytest.approx(exact, rel=2e-3)
    # the mesh is in metres, on the x axis
    assert stepped_mesh.p[0].min() == pytest.approx(0.0, abs=1e-12)
    assert stepped_mesh.p[0].max() == pytest.approx(0.120)
    assert np.hypot(stepped_mesh.p[1], stepped_mesh.p[2]).max() == pytest.approx(0.020, rel=1e-9)


def test_facets_conform_to_every_breakpoint(stepped_mesh):
    """Facets lie in each split plane and segment end, they cover its cross-section, no tet straddles it."""
    mesh = stepped_mesh
    x_vertices = mesh.p[0, : mesh.t.max() + 1]
    for x_mm in STEPPED.breakpoints_mm:
        x = x_mm * 1e-3
        on_plane = np.flatnonzero(np.all(np.isclose(x_vertices[mesh.facets], x, atol=1e-9), axis=0))
        assert on_plane.size > 0, f"no facet in the plane x = {x_mm} mm"
        # no tetrahedron has vertices on both sides of the plane
        side = np.sign(np.round((x_vertices[mesh.t] - x) / 1e-9))
        assert not np.any((side.min(axis=0) < 0) & (side.max(axis=0) > 0)), f"a tet straddles x = {x_mm} mm"
        if 0.0 < x_mm < 120.0 and x_mm not in (40.0, 100.0):  # split planes: the facets tile the full section
            outer, inner = STEPPED.section_at(x_mm)
            area = skfem.FacetBasis(mesh, skfem.ElementTetP2(), facets=on_plane, intorder=4).dx.sum()
            assert area == pytest.approx(math.pi / 4 * (outer**2 - inner**2) * 1e-6, rel=1e-3)


def test_breakpoints_merge_segment_ends_and_splits():
    geometry = SolidPartGeometry("g", ((0, 10, 5, 0), (10, 20, 4, 0)), (10.0, 15.0), 2.0)
    assert geometry.breakpoints_mm == (0.0, 10.0, 15.0, 20.0)
    assert geometry.section_at(12.0) == (4.0, 0.0)


@pytest.mark.parametrize(
    "segments, splits, size, message",
    [
        ((), (), 1.0, "no segments"),
        (((0, 10, 5, 0), (11, 20, 5, 0)), (), 1.0, "starts at"),
        (((0, 10, 5, 5),), (), 1.0, "inner diameter"),
        (((0, 10, 5, 0),), (10.0,), 1.0, "strictly inside"),
        (((10, 0, 5, 0),), (), 1.0, "x_end"),
        (((0, 10, 5, 0),), (), 0.0, "mesh size"),
    ],
)
def test_invalid_geometry_is_rejected(segments, splits, size, message):
    with pytest.raises(ValueError, match=message):
        SolidPartGeometry("bad", segments, splits, size)


def test_cache_hit_returns_identical_arrays_faster(cache):
    start = time.perf_counter()
    first = mesh_part(STEPPED, cache_dir=cache)
    built = time.perf_counter() - start
    assert cache_path(STEPPED, cache).exists()
    start = time.perf_counter()
    second = mesh_part(STEPPED, cache_dir=cache)
    loaded = time.perf_counter() - start
    np.testing.assert_array_equal(first.doflocs, second.doflocs)
    np.testing.assert_array_equal(first.t, second.t)
    assert loaded < built
    # the name is not part of the key: equal shapes share the entry
    renamed = SolidPartGeometry("other", STEPPED.segments, STEPPED.split_x_mm, STEPPED.mesh_size_mm)
    assert cache_path(renamed, cache) == cache_path(STEPPED, cache)
    coarser = SolidPartGeometry("other", STEPPED.segments, STEPPED.split_x_mm, 8.0)
    assert cache_path(coarser, cache) != cache_path(STEPPED, cache)


def test_default_cache_dir_from_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("RVCOAX_CACHE_DIR", str(tmp_path / "env"))
    geometry = SolidPartGeometry("tiny", ((0.0, 20.0, 10.0, 0.0),), (), 5.0)
    mesh_part(geometry)
    assert cache_path(geometry).parent == tmp_path / "env"
    assert cache_path(geometry).exists()


@pytest.mark.parametrize("damage", ["truncate", "garbage", "checksum"])
def test_corrupt_cache_entry_is_rebuilt(cache, damage):
    geometry = SolidPartGeometry("tiny", ((0.0, 20.0, 10.0, 0.0),), (), 4.0)
    reference = mesh_part(geometry, cache_dir=cache)
    path = cache_path(geometry, cache)
    if damage == "truncate":
        path.write_bytes(path.read_bytes()[:100])
    elif damage == "garbage":
        path.write_bytes(b"not a zip file")
    else:  # valid file, arrays changed behind the checksum's back
        with np.load(path) as data:
            doflocs, t, checksum = data["doflocs"] + 1e-3, data["t"], data["checksum"]
        with open(path, "wb") as handle:
            np.savez_compressed(handle, doflocs=doflocs, t=t, checksum=checksum)
    rebuilt = mesh_part(geometry, cache_dir=cache)
    np.testing.assert_array_equal(rebuilt.doflocs, reference.doflocs)
    np.testing.assert_array_equal(rebuilt.t, reference.t)
    again = mesh_part(geometry, cache_dir=cache)  # the rewritten entry is good
    np.testing.assert_array_equal(again.doflocs, reference.doflocs)


def test_meshing_is_reproducible_without_cache():
    first = mesh_part(STEPPED, use_cache=False)
    second = mesh_part(STEPPED, use_cache=False)
    assert first.p.shape == second.p.shape
    np.testing.assert_array_equal(first.doflocs, second.doflocs)


def test_coarse_size_on_small_bore_gives_valid_curved_tets(cache):
    """A mesh size larger than the part: curvature sizing and high-order optimisation keep tets valid."""
    geometry = SolidPartGeometry("thin", ((0.0, 30.0, 12.0, 4.0), (30.0, 80.0, 16.0, 4.0)), (10.0,), 30.0)
    mesh = mesh_part(geometry, cache_dir=cache)
    det = mesh._mapping().detDF(skfem.ElementTetP2().doflocs.T)
    assert np.all(det.min(axis=1) * det.max(axis=1) > 0)
    assert curved_volume(mesh) == pytest.approx(geometry.volume_mm3 * 1e-9, rel=2e-3)


def test_gmsh_failure_is_a_meshing_error(monkeypatch):
    import rvcoax.geometry.meshing as meshing

    def broken(gmsh, geometry):
        raise RuntimeError("OCC exploded")

    monkeypatch.setattr(meshing, "_build_occ_model", broken)
    with pytest.raises(MeshingError, match="OCC exploded"):
        mesh_part(STEPPED, use_cache=False)


@pytest.mark.parametrize("size", [3.0, 6.0])
def test_dof_estimate_within_factor_two(stepped_mesh, size):
    geometry = SolidPartGeometry("stepped", STEPPED.segments, STEPPED.split_x_mm, size)
    mesh = stepped_mesh if size == STEPPED.mesh_size_mm else mesh_part(geometry, use_cache=False)
    actual = 3 * mesh.p.shape[1]
    assert 0.5 < estimate_dofs(geometry) / actual < 2.0


def test_meshing_leaves_a_foreign_gmsh_session_alone():
    """If the caller runs gmsh already, mesh_part neither finalises it nor touches the caller's model."""
    import gmsh

    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("callers_model")
        mesh = mesh_part(SolidPartGeometry("tiny", ((0.0, 20.0, 10.0, 0.0),), (), 5.0), use_cache=False)
        assert mesh.p.shape[1] > 0
        assert gmsh.isInitialized()
        assert "callers_model" in gmsh.model.list()
    finally:
        gmsh.finalize()


def test_meshing_from_a_worker_thread():
    from concurrent.futures import ThreadPoolExecutor

    geometry = SolidPartGeometry("tiny", ((0.0, 20.0, 10.0, 0.0),), (), 5.0)
    with ThreadPoolExecutor(1) as pool:
        mesh = pool.submit(mesh_part, geometry, None, False).result()
    assert mesh.p.shape[1] > 0
