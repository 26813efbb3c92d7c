"""Pictures: off-screen renders of the deformed rig and the Y-against-torque plot are drawn and not blank."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from rvcoax.geometry.rigfile import load_rig
from rvcoax.loadcases.cases import paper_cases, paper_table
from rvcoax.results.io import pictures
from rvcoax.results.io.fields import (
    FieldCase,
    FieldMesh,
    beam_field_cases,
    beam_field_mesh,
    path_point_indices,
    path_polylines,
)
from rvcoax.results.io.pictures import (
    RenderingUnavailableError,
    enclosing_parts,
    plot_y_vs_torque,
    render_deformed,
    sweep_colour_limits_um,
)
from rvcoax.results.sweep import run_sweep

# cost, for `make test-fast` (-m "not slow and not dask and not render")
pytestmark = [pytest.mark.render]

SIZE = (800, 300)


@pytest.fixture(scope="module")
def sweep():
    return run_sweep(load_rig(), paper_cases()[::9])  # 3 cases: first, middle, last row


@pytest.fixture(scope="module")
def beam(sweep):
    return beam_field_mesh(sweep.frame), beam_field_cases(sweep.frame, sweep.cases)


@pytest.fixture(scope="module")
def rendered(tmp_path_factory, sweep, beam):
    """Two cases of a sweep rendered with the sweep's colour limits."""
    mesh, cases = beam
    folder = tmp_path_factory.mktemp("pictures")
    limits = sweep_colour_limits_um(cases)
    housings = enclosing_parts(mesh)
    infos = [render_deformed(mesh, case, folder / f"case{i}.png", rig_length_m=None,
                             paths=path_point_indices(sweep.frame), colour_limits_um=limits,
                             translucent_parts=housings, title=case.label, window_size=SIZE)
             for i, case in enumerate(cases[:2])]
    return folder, limits, infos


def _pixels(path) -> np.ndarray:
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"), dtype=float)


def _assert_not_blank(path, size, min_fraction=0.02):
    pixels = _pixels(path)
    assert pixels.shape == (size[1], size[0], 3)
    assert pixels.std() > 10.0
    drawn = np.any(np.abs(pixels - 255.0) > 30.0, axis=2)
    assert drawn.sum() > min_fraction * drawn.size


def test_deformed_pictures_exist_have_size_and_content(rendered):
    folder, _, infos = rendered
    for info in infos:
        assert info["path"].exists()
        _assert_not_blank(info["path"], SIZE)
    assert sorted(p.name for p in folder.iterdir()) == ["case0.png", "case1.png"]  # no temporary left


def test_sweep_pictures_share_colour_limits(rendered, beam):
    _, limits, infos = rendered
    _, cases = beam
    assert infos[0]["colour_limits_um"] == infos[1]["colour_limits_um"] == limits
    largest = max(np.abs(c.displacement_y_um).max() for c in cases)
    assert limits == (-largest, largest)
    # the scalar bars (right-hand strip with its labels) are drawn identically
    bars = [_pixels(info["path"])[int(0.1 * SIZE[1]):int(0.9 * SIZE[1]), int(0.89 * SIZE[0]):] for info in infos]
    np.testing.assert_array_equal(bars[0], bars[1])


def test_warp_factor_and_translucent_housings(rendered, beam):
    mesh, cases = beam
    _, _, infos = rendered
    length = float(np.ptp(mesh.points, axis=0).max())
    for info, case in zip(infos, cases):
        largest = np.linalg.norm(case.displacement_m, axis=1).max()
        assert info["max_displacement_m"] == pytest.approx(largest)
        assert info["warp_factor"] * largest == pytest.approx(0.05 * length)
    housings = set(infos[0]["translucent_parts"])
    assert {"reducer", "input_bearing_block", "output_bearing_block", "brake_housing"} <= housings
    assert not housings & {"input_shaft", "output_shaft", "motor_shaft"}


def test_render_hybrid_mesh_and_default_limits(tmp_path):
    corners = np.array([[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]], float)
    edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
    points = np.vstack([corners, [(corners[a] + corners[b]) / 2 for a, b in edges], [[-0.2, 0, 0]]])
    mesh = FieldMesh(points, [[10, 0]], [0.01], [0], ("shaft", "block"), [list(range(10))], [1])
    u = np.zeros((11, 3))
    u[:, 1] = np.linspace(-1e-6, 2e-6, 11)
    case = FieldCase("hybrid", 1.0, 100.0, u)
    info = render_deformed(mesh, case, tmp_path / "h.png", rig_length_m=0.3, paths=[[10, 0]],
                           window_size=(400, 200))
    _assert_not_blank(info["path"], (400, 200))
    assert info["colour_limits_um"] == pytest.approx((-2.0, 2.0))


def test_paths_given_as_coordinates(beam, sweep, tmp_path):
    mesh, cases = beam
    # input and output shafts overlap housings: their nodes coincide with housing nodes
    with pytest.raises(ValueError, match="point indices"):
        render_deformed(mesh, cases[0], tmp_path / "x.png", paths=list(path_polylines(sweep.frame).values()))
    with pytest.raises(ValueError, match="unknown parts"):
        render_deformed(mesh, cases[0], tmp_path / "x.png", translucent_parts=["no_such_part"])
    assert list(tmp_path.iterdir()) == []


def test_missing_rendering_libraries_are_named(monkeypatch):
    monkeypatch.setattr(pictures, "_probe_result", None)
    monkeypatch.setattr(pictures, "_try_window", lambda window: (False, f"{window} failed (exit status -11)"))
    monkeypatch.delenv("VTK_DEFAULT_OPENGL_WINDOW", raising=False)
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    with pytest.raises(RenderingUnavailableError, match="libegl1 libegl-mesa0 libgl1-mesa-dri"):
        pictures.check_offscreen_rendering()


def test_y_vs_torque_plot(tmp_path, sweep):
    path = plot_y_vs_torque(sweep, tmp_path / "y.png", published=paper_table(), title="reference rig")
    _assert_not_blank(path, Image.open(path).size, min_fraction=0.01)
    rows = {
        "T1_input_Nm": [c.case.input_torque_Nm for c in sweep.cases],
        "T2_output_Nm": [c.case.output_torque_Nm for c in sweep.cases],
        "Y_input_mm": [c.paths["input"].y_max_mm for c in sweep.cases],
        "Y_output_mm": [c.paths["output"].y_max_mm for c in sweep.cases],
    }
    two = plot_y_vs_torque({"blind": sweep, "as arrays": rows}, tmp_path / "two.png", path_lengths_mm=(120, 160))
    _assert_not_blank(two, Image.open(two).size, min_fraction=0.01)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["two.png", "y.png"]


def test_bending_line_reads_the_measured_shafts_as_the_sweep_does(sweep):
    """The bending line of the measured shafts is the sweep's own u_y and section rotation along the paths
    (same nodes, same reference), so the picture shows what Y and β are computed from."""
    from rvcoax.results.io.bending_line import bending_lines

    lines = {line.part: line for line in bending_lines(sweep)}
    assert list(lines) == [p.name for p in sweep.rig.parts]
    for shaft in ("input", "output"):
        path = getattr(sweep.rig.paths, shaft)
        line = lines[path.part]
        for i, case in enumerate(sweep.cases):
            result = case.paths[shaft]
            x = path.x_start_mm + result.station_mm
            for drawn, read in ((line.u_y_um[i], result.uy_mm * 1e3), (line.rotation_z_urad[i], result.rotation_z_rad * 1e6)):
                on_path = np.interp(x, line.x_mm, drawn)
                np.testing.assert_allclose(on_path, read, rtol=1e-9, atol=1e-9 * np.abs(read).max())
        assert np.abs(line.u_z_um).max() < 1e-6 * np.abs(line.u_y_um).max()  # the reference rig loads only in x–y


def test_label_rows_never_overlap():
    from rvcoax.results.io.bending_line import stack_rows

    spans = [(0, 10), (5, 12), (11, 20), (12.5, 30), (0, 3)]
    rows = stack_rows(spans, gap=0.5)
    for a in range(len(spans)):
        for b in range(a + 1, len(spans)):
            if rows[a] == rows[b]:
                (s0, e0), (s1, e1) = sorted((spans[a], spans[b]))
                assert s1 >= e0 + 0.5
    assert rows == [0, 1, 0, 1, 2]


@pytest.mark.slow
def test_picture_command_on_a_rig_of_another_layout(tmp_path):
    """`rvcoax picture` on the tutorial's RV-40E bench: one warp factor for every case (the one of the largest
    displacement of the sweep, printed), the bending line, and the legend in the lower right, clear of the title."""
    from tutorial_rig import rig_text
    from typer.testing import CliRunner

    from rvcoax.geometry.rigfile import parse_rig_text
    from rvcoax.loadcases.cases import paired_cases
    from rvcoax.results.cli.app import app
    from rvcoax.results.io.fields import sweep_field_cases, sweep_field_mesh
    from rvcoax.results.io.pictures import mesh_length_m, sweep_warp_factor

    rig_file = tmp_path / "rv40e.toml"
    rig_file.write_text(rig_text(), encoding="utf-8")
    done = CliRunner().invoke(app, ["picture", "--rig", str(rig_file), "--t1", "0.801,4.006", "--t2", "82.4,412",
                                    "--out", str(tmp_path / "out")])
    assert done.exit_code == 0, (done.output, done.exception)
    solved = run_sweep(parse_rig_text(rig_text(), "rv40e.toml"), paired_cases([0.801, 4.006], [82.4, 412.0]))
    mesh, _ = sweep_field_mesh(solved)
    factor = sweep_warp_factor(sweep_field_cases(solved), mesh_length_m(mesh))
    assert f"one warp factor for every case: × {factor:.4g}" in " ".join(done.output.split())
    folder = tmp_path / "out" / "pictures"
    names = ["bending_line_beam.png", "deformed_beam_00.png", "deformed_beam_01.png", "y_vs_torque_beam.png"]
    assert sorted(p.name for p in folder.iterdir()) == names
    for name in names:
        _assert_not_blank(folder / name, Image.open(folder / name).size, min_fraction=0.01)
    pixels = _pixels(folder / "deformed_beam_01.png")
    height, width = pixels.shape[:2]
    assert (pixels[: int(0.07 * height)] < 128).any()  # the title, on top
    assert (pixels[int(0.85 * height):, int(0.87 * width):] < 128).any()  # the legend, in the lower right
