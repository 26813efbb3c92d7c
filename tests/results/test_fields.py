"""Field output: beam fields agree with the sweep; .vtu and XDMF files read back with the same arrays."""

from __future__ import annotations

import json

import meshio
import meshio.xdmf
import numpy as np
import pytest

from rvcoax.fem.sections import CircularSection
from rvcoax.geometry.rigfile import load_rig
from rvcoax.loadcases.cases import paper_cases
from rvcoax.results.io.fields import (
    FieldCase,
    FieldMesh,
    beam_field_cases,
    beam_field_mesh,
    beam_outer_radius_m,
    path_point_indices,
    path_polylines,
    read_vtu,
    read_xdmf_series,
    write_vtu,
    write_xdmf_series,
)
from rvcoax.results.sweep import run_sweep


@pytest.fixture(scope="module")
def sweep():
    return run_sweep(load_rig(), paper_cases())


@pytest.fixture(scope="module")
def beam(sweep):
    return beam_field_mesh(sweep.frame), beam_field_cases(sweep.frame, sweep.cases)


def _hybrid() -> tuple[FieldMesh, list[FieldCase]]:
    """Two beams and two quadratic tetrahedra sharing a face, parts 'shaft' and 'block'."""
    corners = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], float)
    edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3), (4, 1), (4, 2), (4, 3)]
    mids = np.array([(corners[a] + corners[b]) / 2 for a, b in edges])
    beam_points = np.array([[-1, 0, 0], [-2, 0, 0]], float)
    points = np.vstack([corners, mids, beam_points])  # corners 0-4, mid-edges 5-13, beam 14-15
    tet_a = [0, 1, 2, 3, 5, 6, 7, 8, 9, 10]
    # second tet (1, 2, 3, 4)... in VTK order: edges (1,2) (2,3) (3,1) (1,4) (2,4) (3,4)
    tet_b = [1, 2, 3, 4, 6, 10, 9, 11, 12, 13]
    mesh = FieldMesh(points, [[15, 14], [14, 0]], [0.1, 0.05], [0, 0], ("shaft", "block"),
                     np.array([tet_a, tet_b]), [1, 1])
    rng = np.random.default_rng(3)
    cases = [FieldCase(f"case {i}", 0.1 * i, 10.0 * i, rng.normal(size=(len(points), 3)) * 1e-6,
                       rng.uniform(1e5, 1e6, len(points)))
             for i in range(3)]
    return mesh, cases


def test_beam_field_equals_sweep_paths(sweep, beam):
    mesh, cases = beam
    assert len(cases) == len(sweep.cases)
    assert mesh.n_points == sweep.frame.structure.n_nodes
    for result, field in zip(sweep.cases, cases):
        assert (field.T1_input_Nm, field.T2_output_Nm) == (result.case.input_torque_Nm, result.case.output_torque_Nm)
        for shaft, nodes in path_point_indices(sweep.frame).items():
            uy_mm = field.displacement_m[nodes, 1] * 1e3
            np.testing.assert_allclose(uy_mm, result.paths[shaft].uy_mm, rtol=0, atol=1e-12)
            # the section rotations (issue 25): about z, the paths' own rotation
            np.testing.assert_allclose(field.rotation_rad[nodes, 2], result.paths[shaft].rotation_z_rad, rtol=0,
                                       atol=1e-15)
        assert field.von_mises_Pa is None  # a beam model gives no stress field (rather than a field of NaN)


def test_beam_field_measured_from_unloaded(sweep):
    rig = sweep.rig
    unloaded = rig.model_copy(update={"paths": rig.paths.model_copy(update={"measured_from": "unloaded"})})
    other = run_sweep(unloaded, paper_cases()[:2])
    fields = beam_field_cases(other.frame, other.cases)
    for result, field in zip(other.cases, fields):
        for shaft, nodes in path_point_indices(other.frame).items():
            np.testing.assert_allclose(field.displacement_m[nodes, 1] * 1e3, result.paths[shaft].uy_mm, atol=1e-12)
            np.testing.assert_allclose(field.displacement_m[nodes, 1] * 1e3, result.absolute_paths[shaft].uy_mm,
                                       atol=1e-12)


def test_beam_mesh_radius_and_parts(sweep, beam):
    mesh, _ = beam
    section = CircularSection(0.018, 0.008)
    assert beam_outer_radius_m(section.area_m2, section.second_moment_m4) == pytest.approx(0.009, rel=1e-12)
    assert mesh.part_names == tuple(p.name for p in sweep.rig.parts)
    shaft = mesh.part_names.index("input_shaft")
    assert set(np.round(mesh.line_radius_m[mesh.line_part_id == shaft] * 2e3, 9)) == {18.0, 20.0}
    assert len(mesh.tetra10) == 0
    polylines = path_polylines(sweep.frame)
    np.testing.assert_array_equal(polylines["input"], mesh.points[path_point_indices(sweep.frame)["input"]])


def test_vtu_roundtrip_beam(tmp_path, beam):
    mesh, cases = beam
    path = write_vtu(tmp_path / "case0.vtu", mesh, cases[0])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["case0.vtu"]  # no temporary left
    data = meshio.read(path)
    np.testing.assert_array_equal(data.points, mesh.points * 1e3)  # files are in mm
    assert [b.type for b in data.cells] == ["line"]
    np.testing.assert_array_equal(data.cells[0].data, mesh.lines)
    np.testing.assert_array_equal(data.point_data["displacement_mm"], cases[0].displacement_m * 1e3)
    np.testing.assert_array_equal(data.point_data["displacement_y_um"], cases[0].displacement_m[:, 1] * 1e6)
    assert "von_mises_MPa" not in data.point_data  # no NaN field
    np.testing.assert_array_equal(data.point_data["rotation_urad"], cases[0].rotation_rad * 1e6)
    for values in [*data.point_data.values(), *(v for blocks in data.cell_data.values() for v in blocks)]:
        assert np.all(np.isfinite(values))
    np.testing.assert_array_equal(data.cell_data["radius_mm"][0], mesh.line_radius_m * 1e3)
    np.testing.assert_array_equal(data.cell_data["part_id"][0], mesh.line_part_id)
    assert float(data.field_data["T1_input_Nm"][0]) == cases[0].T1_input_Nm
    assert float(data.field_data["T2_output_Nm"][0]) == cases[0].T2_output_Nm
    again, case = read_vtu(path)
    assert again.part_names == mesh.part_names
    np.testing.assert_allclose(again.line_radius_m, mesh.line_radius_m, rtol=1e-15)
    np.testing.assert_allclose(again.points, mesh.points, rtol=1e-15, atol=1e-18)
    np.testing.assert_allclose(case.displacement_m, cases[0].displacement_m, rtol=1e-15, atol=1e-24)
    assert case.von_mises_Pa is None
    assert case.label == "case0"


def test_vtu_roundtrip_hybrid(tmp_path):
    mesh, cases = _hybrid()
    path = write_vtu(tmp_path / "h.vtu", mesh, cases[1])
    data = meshio.read(path)
    assert [b.type for b in data.cells] == ["line", "tetra10"]
    np.testing.assert_array_equal(data.cells[1].data, mesh.tetra10)
    np.testing.assert_allclose(data.point_data["von_mises_MPa"], cases[1].von_mises_Pa * 1e-6, rtol=1e-15)
    np.testing.assert_array_equal(data.cell_data["part_id"][1], [1, 1])
    np.testing.assert_array_equal(data.cell_data["radius_mm"][1], [0.0, 0.0])  # tetrahedra have no tube radius
    again, case = read_vtu(path)
    np.testing.assert_array_equal(again.tetra10, mesh.tetra10)
    np.testing.assert_allclose(case.displacement_m, cases[1].displacement_m, rtol=1e-15, atol=1e-24)
    np.testing.assert_allclose(case.von_mises_Pa, cases[1].von_mises_Pa, rtol=1e-15)


@pytest.mark.parametrize("data_format", ["XML", "HDF"])
def test_xdmf_series_roundtrip_beam(tmp_path, beam, data_format):
    if data_format == "HDF":
        pytest.importorskip("h5py")
    mesh, cases = beam
    written = write_xdmf_series(tmp_path / "sweep.xdmf", mesh, cases, data_format=data_format)
    expected = {"sweep.xdmf", "sweep.cases.json"} | ({"sweep.h5"} if data_format == "HDF" else set())
    assert {p.name for p in tmp_path.iterdir()} == expected  # the staging folder is gone
    assert set(written) == {"xdmf", "json"} | ({"h5"} if data_format == "HDF" else set())
    with meshio.xdmf.TimeSeriesReader(written["xdmf"]) as reader:
        points, cells = reader.read_points_cells()
        np.testing.assert_array_equal(points, mesh.points * 1e3)
        np.testing.assert_array_equal(cells[0].data, mesh.lines)
        assert reader.num_steps == len(cases)
        for k, case in enumerate(cases):
            t, point_data, cell_data = reader.read_data(k)
            assert t == k  # time = case index
            np.testing.assert_array_equal(point_data["displacement_mm"], case.displacement_m * 1e3)
            np.testing.assert_array_equal(point_data["displacement_y_um"], case.displacement_y_um)
            assert "von_mises_MPa" not in point_data
            np.testing.assert_array_equal(cell_data["part_id"][0], mesh.line_part_id)
    info = json.loads(written["json"].read_text())
    assert [(c["time"], c["T1_input_Nm"], c["T2_output_Nm"]) for c in info["cases"]] == [
        (k, c.T1_input_Nm, c.T2_output_Nm) for k, c in enumerate(cases)]
    assert info["part_names"] == list(mesh.part_names)
    assert info["units"]["points"] == "mm" and info["units"]["displacement_mm"] == "mm"


@pytest.mark.parametrize("data_format", ["XML", "HDF"])
def test_xdmf_series_roundtrip_hybrid(tmp_path, data_format):
    if data_format == "HDF":
        pytest.importorskip("h5py")
    mesh, cases = _hybrid()
    written = write_xdmf_series(tmp_path / "out" / "hybrid.xdmf", mesh, cases, data_format=data_format)
    again, read = read_xdmf_series(written["xdmf"])
    for name in ("points", "lines", "line_radius_m", "line_part_id", "tetra10", "tetra_part_id"):
        np.testing.assert_allclose(getattr(again, name), getattr(mesh, name), rtol=1e-15)  # mm in the file
    assert again.part_names == mesh.part_names
    for a, b in zip(read, cases):
        assert (a.label, a.T1_input_Nm, a.T2_output_Nm) == (b.label, b.T1_input_Nm, b.T2_output_Nm)
        np.testing.assert_allclose(a.displacement_m, b.displacement_m, rtol=1e-15, atol=1e-24)
        np.testing.assert_allclose(a.von_mises_Pa, b.von_mises_Pa, rtol=1e-15)


def test_xdmf_overwrite_replaces_files(tmp_path, beam):
    mesh, cases = beam
    write_xdmf_series(tmp_path / "s.xdmf", mesh, cases[:2], data_format="XML")
    write_xdmf_series(tmp_path / "s.xdmf", mesh, cases[2:5], data_format="XML")
    _, read = read_xdmf_series(tmp_path / "s.xdmf")
    assert [c.label for c in read] == [c.label for c in cases[2:5]]
    assert {p.name for p in tmp_path.iterdir()} == {"s.xdmf", "s.cases.json"}


def test_invalid_input_is_refused(tmp_path, beam):
    mesh, cases = beam
    with pytest.raises(ValueError, match="outside"):
        FieldMesh(np.zeros((2, 3)), [[0, 2]], [0.1], [0], ("a",))
    with pytest.raises(ValueError, match="part ids"):
        FieldMesh(np.zeros((2, 3)), [[0, 1]], [0.1], [1], ("a",))
    with pytest.raises(ValueError, match="von_mises"):
        FieldCase("x", 0, 0, np.zeros((3, 3)), np.zeros(2))
    with pytest.raises(ValueError, match="von_mises"):
        FieldCase("x", 0, 0, np.zeros((3, 3)), np.array([1.0, np.nan, 2.0]))
    short = FieldCase("short", 0, 0, np.zeros((3, 3)))
    with pytest.raises(ValueError, match="points"):
        write_vtu(tmp_path / "bad.vtu", mesh, short)
    with pytest.raises(ValueError, match="points"):
        write_xdmf_series(tmp_path / "bad.xdmf", mesh, [cases[0], short])
    with pytest.raises(ValueError, match=".xdmf"):
        write_xdmf_series(tmp_path / "bad.h5", mesh, cases[:1])
    assert list(tmp_path.iterdir()) == []
    assert not cases[0].displacement_m.flags.writeable


def test_the_meshio_internals_the_field_files_use_are_there():
    """fields.py subclasses meshio's XDMF time-series writer and reader and uses their internals; a meshio
    release that moves them fails here, with the version, before a series is written wrong."""
    import inspect

    from meshio.xdmf import TimeSeriesReader, TimeSeriesWriter, common

    major, minor = (int(v) for v in meshio.__version__.split(".")[:2])
    assert (5, 3) <= (major, minor) <= (5, 3), f"fields.py is tested with meshio 5.3: {meshio.__version__}"
    assert callable(TimeSeriesReader._read_data_item) and "mesh_grid" in inspect.getsource(TimeSeriesReader)
    assert callable(TimeSeriesWriter.numpy_to_xml_string) and "h5_file" in inspect.getsource(TimeSeriesWriter)
    assert common.meshio_type_to_xdmf_index["line"] == 2 and "tetra10" in common.meshio_type_to_xdmf_index
    assert common.xdmf_idx_to_meshio_type[2] == "line" and common.numpy_to_xdmf_dtype["int64"] == ("Int", "8")
