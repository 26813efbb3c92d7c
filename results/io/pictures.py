"""Pictures of a sweep: the deformed rig (off-screen VTK) and Y against torque (matplotlib).

Intended call sequence for a sweep::

    from pathlib import Path
    from rvcoax.geometry.rigfile import load_rig
    from rvcoax.loadcases.cases import paper_cases, paper_table
    from rvcoax.results.io.fields import beam_field_cases, beam_field_mesh, path_point_indices
    from rvcoax.results.io.pictures import enclosing_parts, plot_y_vs_torque, render_deformed, sweep_colour_limits_um
    from rvcoax.results.sweep import run_sweep

    out = Path("rvcoax_out/pictures")
    sweep = run_sweep(load_rig(), paper_cases())
    mesh = beam_field_mesh(sweep.frame)
    cases = beam_field_cases(sweep.frame, sweep.cases)      # u measured as the sweep measures Y
    paths = path_point_indices(sweep.frame)                  # {"input": nodes, "output": nodes}
    limits = sweep_colour_limits_um(cases)                   # the same colours in every picture
    housings = enclosing_parts(mesh)                         # the same parts translucent in every picture
    for i, case in enumerate(cases):
        info = render_deformed(mesh, case, out / f"deformed_{i:02d}.png", rig_length_m=None, paths=paths,
                               colour_limits_um=limits, translucent_parts=housings, title=case.label)
        print(info["warp_factor"], info["colour_limits_um"], info["seconds"])
    plot_y_vs_torque(sweep, out / "y_vs_torque.png", published=paper_table())

``render_deformed`` scales each picture so that its largest displacement is ``warp_fraction`` of the
rig length; pass ``warp_factor=sweep_warp_factor(cases, rig_length_m)`` to draw every case of a
sweep with one scale instead.

Rendering is off screen. Without a display, VTK's EGL window is used (Mesa's software renderer on
a machine without a GPU); on Debian that needs the packages in :data:`RENDER_PACKAGES`. Before the
first picture, a tiny render runs in a child process (about 1 s, once per process), because a VTK
window that cannot be created can crash the process; if it fails,
:class:`RenderingUnavailableError` names what is missing.
"""

from __future__ import annotations

import contextlib
import glob
import os
import subprocess
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rvcoax.errors import RvcoaxError
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.io.processes import run_group
from rvcoax.results.io.writers import naming_errors, write_png_atomic

if TYPE_CHECKING:  # only named in annotations: the Y-T plot of `check` need not import meshio (~0.05 s)
    from rvcoax.results.io.fields import FieldCase, FieldMesh

RENDER_PACKAGES = ("libegl1", "libegl-mesa0", "libgl1-mesa-dri")
BACKGROUND = (255, 255, 255)
COLOURMAP = "coolwarm"
ENCLOSING_OPACITY = 0.3
PATH_COLOURS = ("black", "darkgreen", "purple", "darkorange")
RULER_CAPTION = "ruler: x in mm, red marks: bearings"
RULER_END = 0.84  # the ruler and the part labels end here (fraction of the width); the legend is right of it


class RenderingUnavailableError(RvcoaxError, RuntimeError):
    """Off-screen rendering cannot run on this machine; the message says what to install."""


# --------------------------------------------------------------------------------------------
# Headless rendering set-up

_PROBE = r"""
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (registers the OpenGL window classes)
from vtkmodules.vtkFiltersSources import vtkConeSource
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderWindow, vtkRenderer,
                                         vtkWindowToImageFilter)
window = vtkRenderWindow()
window.SetOffScreenRendering(1)
window.SetSize(16, 16)
renderer = vtkRenderer()
renderer.SetBackground(1.0, 1.0, 1.0)
window.AddRenderer(renderer)
cone = vtkConeSource()
mapper = vtkPolyDataMapper()
mapper.SetInputConnection(cone.GetOutputPort())
actor = vtkActor()
actor.SetMapper(mapper)
actor.GetProperty().SetColor(0.0, 0.0, 0.0)
renderer.AddActor(actor)
window.Render()
grab = vtkWindowToImageFilter()
grab.SetInput(window)
grab.Update()
pixels = grab.GetOutput().GetPointData().GetScalars()
values = [pixels.GetValue(i) for i in range(pixels.GetNumberOfValues())]
print("RVCOAX_PROBE", window.GetClassName(), min(values), max(values))
"""

_probe_result: str | None = None


def _missing_libraries() -> list[str]:
    import ctypes.util

    missing = []
    if ctypes.util.find_library("EGL") is None:
        missing.append("libEGL.so.1 (libegl1)")
    if not glob.glob("/usr/lib/*/libEGL_mesa.so.0") and not glob.glob("/usr/lib/libEGL_mesa.so.0"):
        missing.append("libEGL_mesa.so.0 (libegl-mesa0)")
    if not glob.glob("/usr/lib/*/dri/swrast_dri.so") and not glob.glob("/usr/lib/dri/swrast_dri.so"):
        missing.append("dri/swrast_dri.so (libgl1-mesa-dri)")
    return missing


def _try_window(window_class: str | None) -> tuple[bool, str]:
    env = dict(os.environ)
    if window_class is not None:
        env["VTK_DEFAULT_OPENGL_WINDOW"] = window_class
    try:
        done = run_group([sys.executable, "-c", _PROBE], 120, env=env)  # (a hung probe's children end with it)
    except subprocess.TimeoutExpired:
        return False, "the test render did not finish in 120 s"
    for line in done.stdout.splitlines():
        if line.startswith("RVCOAX_PROBE"):
            _, name, low, high = line.split()
            if int(low) < 128 <= int(high):
                return True, name
            return False, f"{name} rendered a blank image"
    tail = (done.stderr or "").strip().splitlines()[-3:]
    reason = f"exit status {done.returncode}" + (f": {' | '.join(tail)}" if tail else "")
    return False, f"{window_class or 'the default window'} failed ({reason})"


def check_offscreen_rendering() -> str:
    """Make sure VTK can render off screen here; returns the window class used.

    Without a display (no ``DISPLAY``/``WAYLAND_DISPLAY``) it selects the EGL window (else OSMesa)
    through ``VTK_DEFAULT_OPENGL_WINDOW``, so VTK does not try an X server first. The result is
    cached for the process. Raises :class:`RenderingUnavailableError`.
    """
    global _probe_result
    if _probe_result is not None:
        return _probe_result
    chosen = os.environ.get("VTK_DEFAULT_OPENGL_WINDOW")
    if chosen:
        candidates = [chosen]
    elif os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        candidates = [None, "vtkEGLRenderWindow", "vtkOSMesaRenderWindow"]
    else:
        candidates = ["vtkEGLRenderWindow", "vtkOSMesaRenderWindow"]
    failures = []
    for candidate in candidates:
        ok, detail = _try_window(candidate)
        if ok:
            if candidate is not None:
                os.environ["VTK_DEFAULT_OPENGL_WINDOW"] = candidate
            _probe_result = detail
            return detail
        failures.append(detail)
    missing = _missing_libraries()
    raise RenderingUnavailableError(
        "off-screen rendering is not available: " + "; ".join(failures)
        + (f". Missing shared libraries: {', '.join(missing)}" if missing else "")
        + f". On Debian/Ubuntu install them with: apt-get install {' '.join(RENDER_PACKAGES)}"
        + " (EGL with Mesa's software renderer; `make test` installs them when run as root)"
        + ", or run with DISPLAY set to an X server."
    )


@contextlib.contextmanager
def _quiet_vtk():
    """Silence VTK's warnings and log messages (e.g. "bad X server connection") while rendering."""
    import pyvista as pv
    from vtkmodules.vtkCommonCore import vtkObject

    previous = vtkObject.GetGlobalWarningDisplay()
    vtkObject.GlobalWarningDisplayOff()
    try:
        with pv.vtk_verbosity("off"):
            yield
    finally:
        vtkObject.SetGlobalWarningDisplay(previous)


# --------------------------------------------------------------------------------------------
# Scales


def sweep_colour_limits_um(cases: Sequence[FieldCase]) -> tuple[float, float]:
    """Symmetric u_y colour limits (µm) covering every case: (−m, m) with m = max |u_y|."""
    largest = max((float(np.max(np.abs(c.displacement_y_um))) for c in cases if c.displacement_m.size), default=0.0)
    if not np.isfinite(largest) or largest <= 0.0:
        largest = 1e-9
    return -largest, largest


def _largest_displacement_m(case: FieldCase) -> float:
    return float(np.max(np.linalg.norm(case.displacement_m, axis=1))) if case.displacement_m.size else 0.0


def mesh_length_m(mesh: FieldMesh) -> float:
    """The largest extent of the mesh's bounding box (m): the rig length for a rig along x."""
    return float(np.max(np.ptp(mesh.points, axis=0)))


def warp_factor_for(largest_displacement_m: float, rig_length_m: float, warp_fraction: float = 0.05) -> float:
    """Factor that draws ``largest_displacement_m`` as ``warp_fraction`` of ``rig_length_m`` (1 if zero)."""
    if largest_displacement_m <= 0.0 or not np.isfinite(largest_displacement_m):
        return 1.0
    return warp_fraction * rig_length_m / largest_displacement_m


def sweep_warp_factor(cases: Sequence[FieldCase], rig_length_m: float, warp_fraction: float = 0.05) -> float:
    """One warp factor for all cases: the largest displacement of the sweep → warp_fraction × length."""
    return warp_factor_for(max((_largest_displacement_m(c) for c in cases), default=0.0), rig_length_m, warp_fraction)


# --------------------------------------------------------------------------------------------
# The deformed rig


def _runs(lines: np.ndarray, radius: np.ndarray) -> list[tuple[list[int], float]]:
    """Chains of consecutive lines (end of one = start of the next) of one radius: (points, radius)."""
    runs: list[tuple[list[int], float]] = []
    for (a, b), r in zip(lines, radius):
        if runs and runs[-1][0][-1] == a and runs[-1][1] == r:
            runs[-1][0].append(int(b))
        else:
            runs.append(([int(a), int(b)], float(r)))
    return runs


def _segment_tubes(mesh: FieldMesh, points: np.ndarray, uy_um: np.ndarray, radius: np.ndarray, select: np.ndarray):
    """Tubes for the selected lines, one capped tube per chain of equal radius (radii can jump)."""
    import pyvista as pv

    runs = _runs(mesh.lines[select], radius[select])
    index = np.concatenate([np.asarray(chain) for chain, _ in runs])
    cells, start = [], 0
    for chain, _ in runs:
        cells.extend([len(chain), *range(start, start + len(chain))])
        start += len(chain)
    poly = pv.PolyData(points[index], lines=np.asarray(cells))
    poly.point_data["radius"] = np.concatenate([np.full(len(chain), r) for chain, r in runs])
    poly.point_data["u_y_um"] = uy_um[index]
    return poly.tube(scalars="radius", absolute=True, n_sides=24, capping=True)


def _tet_surface(mesh: FieldMesh, points: np.ndarray, uy_um: np.ndarray, select: np.ndarray):
    import pyvista as pv

    grid = pv.UnstructuredGrid({pv.CellType.QUADRATIC_TETRA: mesh.tetra10[select]}, points)
    grid.point_data["u_y_um"] = uy_um
    try:
        return grid.extract_surface(nonlinear_subdivision=1, algorithm="dataset_surface")
    except TypeError:  # pyvista < 0.47 has no `algorithm`
        return grid.extract_surface(nonlinear_subdivision=1)


def _part_surfaces(mesh: FieldMesh, points: np.ndarray, uy_um: np.ndarray, radius: np.ndarray) -> dict:
    """Part index → its drawn surface (tubes of its beams and the surface of its tetrahedra)."""
    surfaces = {}
    for part in range(len(mesh.part_names)):
        pieces = []
        if np.any(mesh.line_part_id == part):
            pieces.append(_segment_tubes(mesh, points, uy_um, radius, mesh.line_part_id == part))
        if np.any(mesh.tetra_part_id == part):
            pieces.append(_tet_surface(mesh, points, uy_um, mesh.tetra_part_id == part))
        if pieces:
            surfaces[part] = pieces[0] if len(pieces) == 1 else pieces[0].merge(pieces[1:]).extract_surface()
    return surfaces


def enclosing_parts(mesh: FieldMesh, *, rig_length_m: float | None = None, min_radius_fraction: float = 0.002,
                    samples: int = 300) -> tuple[str, ...]:
    """Parts that hide another part in the side view (housings around shafts), on the undeformed mesh.

    A part hides another when a ray from one of the other part's camera-facing surface points
    (up to ``samples`` per part) towards the camera (+z) hits it. :func:`render_deformed` draws
    these parts translucent; computing them once for a sweep keeps every picture alike.
    """
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkFiltersGeneral import vtkOBBTree

    length = mesh_length_m(mesh) if rig_length_m is None else float(rig_length_m)
    radius = np.maximum(mesh.line_radius_m, min_radius_fraction * length)
    with _quiet_vtk():
        surfaces = _part_surfaces(mesh, mesh.points, np.zeros(mesh.n_points), radius)
        facing = {}
        for part, surface in surfaces.items():
            if "TubeNormals" in surface.point_data and surface.n_points == len(surface.point_data["TubeNormals"]):
                normals = np.asarray(surface.point_data["TubeNormals"])
            else:
                normals = np.asarray(surface.compute_normals(cell_normals=False, split_vertices=False)
                                     .point_data["Normals"])
            points = np.asarray(surface.points)[normals[:, 2] > 0.5]
            if len(points) > samples:
                points = points[np.linspace(0, len(points) - 1, samples).astype(int)]
            facing[part] = points
        hits = vtkPoints()
        found = []
        for part, surface in surfaces.items():
            tree = vtkOBBTree()
            tree.SetDataSet(surface)
            tree.BuildLocator()
            others = [facing[q] for q in surfaces if q != part and len(facing[q])]
            for p in np.vstack(others) if others else []:
                start = (float(p[0]), float(p[1]), float(p[2]) + 1e-6 * length)
                if tree.IntersectWithLine(start, (start[0], start[1], start[2] + 2.0 * length), hits, None):
                    found.append(mesh.part_names[part])
                    break
    return tuple(found)


def _path_points(mesh: FieldMesh, case: FieldCase, polyline: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Undeformed positions and displacements along a path given by point indices or positions.

    Positions must coincide with exactly one mesh point each, or lie inside the solids (then the
    displacement is interpolated). Where parts overlap (a shaft inside a housing), several points
    coincide: pass point indices (:func:`rvcoax.results.io.fields.path_point_indices`) instead.
    """
    if np.issubdtype(polyline.dtype, np.integer):
        if polyline.ndim != 1 or polyline.min() < 0 or polyline.max() >= mesh.n_points:
            raise ValueError("a path of point indices must be a 1-D array of indices into the mesh's points")
        return mesh.points[polyline], case.displacement_m[polyline]
    from scipy.spatial import cKDTree

    tolerance = 1e-9 * max(mesh_length_m(mesh), 1e-12)
    distance, index = cKDTree(mesh.points).query(polyline, k=2)
    if np.any(distance[:, 1] <= tolerance):
        raise ValueError("path points coincide with points of several parts (overlapping parts); "
                         "pass the path as point indices (rvcoax.results.io.fields.path_point_indices)")
    out = case.displacement_m[index[:, 0]].copy()
    far = distance[:, 0] > tolerance
    if np.any(far):
        if not len(mesh.tetra10):
            raise ValueError("path points must coincide with mesh points when the mesh has no solid cells")
        import pyvista as pv

        grid = pv.UnstructuredGrid({pv.CellType.QUADRATIC_TETRA: mesh.tetra10}, mesh.points)
        grid.point_data["u"] = case.displacement_m
        probe = pv.PolyData(polyline[far]).sample(grid)
        if not np.all(probe.point_data["vtkValidPointMask"]):
            raise ValueError("some path points lie outside the mesh")
        out[far] = probe.point_data["u"]
    return polyline, out


def _named_paths(paths) -> list[tuple[str, np.ndarray]]:
    if paths is None:
        return []
    if isinstance(paths, Mapping):
        items = list(paths.items())
    else:
        items = list(paths)
        names = ["input", "output"] if len(items) == 2 else [str(i + 1) for i in range(len(items))]
        items = list(zip(names, items))
    out = []
    for name, polyline in items:
        polyline = np.asarray(polyline)
        if not np.issubdtype(polyline.dtype, np.integer):
            polyline = polyline.astype(float)
            if polyline.ndim != 2 or polyline.shape[1] != 3:
                raise ValueError(f"path {name!r} must be (N,) point indices or an (N, 3) polyline, got {polyline.shape}")
        if len(polyline) < 2:
            raise ValueError(f"path {name!r} needs at least 2 points")
        out.append((f"{name} shaft path" if name in MEASURED_SHAFTS else f"path {name}", polyline))
    return out


def render_deformed(mesh: FieldMesh, case: FieldCase, path_png: str | Path, *, rig_length_m: float | None = None,  # noqa: PLR0913
                    paths=None, warp_fraction: float = 0.05, colour_limits_um: tuple[float, float] | None = None,
                    title: str | None = None, window_size: tuple[int, int] = (1600, 600),
                    warp_factor: float | None = None, translucent_parts: Sequence[str] | None = None,
                    min_radius_fraction: float = 0.002, bearings_x_mm: Sequence[float] | None = None) -> dict:
    """Draw the deformed rig, coloured by u_y (µm), seen from the side; write a PNG.

    Every part is named under the rig (labels in rows that do not overlap), an x ruler in mm runs
    under the names with the bearings marked on it, the title sits above the rig and the legend of
    the paths in the lower right corner, clear of both.

    Parameters
    ----------
    rig_length_m : float, optional
        Length the warp refers to; default the mesh's largest extent.
    paths : list of arrays, or dict name → array, optional
        The measured shafts, each as (N,) point indices (exact; use this where parts overlap, e.g.
        :func:`rvcoax.results.io.fields.path_point_indices`) or as an (N, 3) undeformed polyline in m (each
        point must coincide with one mesh point, or lie inside the solids: then interpolated).
        Drawn as thick lines on the deformed shape; a list of two is labelled "input" and "output".
        They are moved towards the camera (+z) so that the tubes around them do not hide them;
        in the parallel side view this leaves their place in the picture unchanged.
    warp_fraction : float
        The largest displacement magnitude is drawn as this fraction of the rig length.
    colour_limits_um : (low, high), optional
        Fixed u_y colour range; default symmetric about 0 over this case
        (for a sweep: :func:`sweep_colour_limits_um` for every picture).
    warp_factor : float, optional
        Use this factor instead of the one from ``warp_fraction`` (e.g. :func:`sweep_warp_factor`).
    translucent_parts : names, optional
        Parts drawn translucent; default :func:`enclosing_parts` (housings around shafts).
    min_radius_fraction : float
        Beams thinner than this fraction of the rig length are drawn at that radius.
    bearings_x_mm : positions, optional
        Where the bearings sit along x (mm), marked on the ruler.

    Returns
    -------
    dict with ``path``, ``warp_factor``, ``colour_limits_um``, ``max_displacement_m``,
    ``translucent_parts``, ``window_class`` and ``seconds`` (time to build, render and write).
    """
    started = time.perf_counter()
    scene = _deformed_scene(mesh, case, _SceneOptions(
        rig_length_m=rig_length_m, paths=paths, warp_fraction=warp_fraction, colour_limits_um=colour_limits_um,
        warp_factor=warp_factor, translucent_parts=translucent_parts, min_radius_fraction=min_radius_fraction))
    target = Path(path_png)
    target.parent.mkdir(parents=True, exist_ok=True)

    window_class = check_offscreen_rendering()
    import pyvista as pv

    pv.OFF_SCREEN = True
    with _quiet_vtk():
        surfaces = _part_surfaces(mesh, scene.deformed, case.displacement_y_um, scene.radius)
        names = scene.translucent_parts
        if names is None:
            names = enclosing_parts(mesh, rig_length_m=scene.length_m, min_radius_fraction=min_radius_fraction)
        translucent = {mesh.part_names.index(n) for n in names}

        plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
        try:
            plotter.set_background("white")
            _draw_surfaces(plotter, surfaces, scene.limits, translucent, window_size)
            title_lines = _title_lines(title, window_size)
            view, labels = _fit_view(mesh, scene, window_size, len(title_lines))
            _draw_overlays(plotter, scene, _Overlays(view, tuple(labels), tuple(title_lines) if title else (),
                                                     tuple(bearings_x_mm or ())))
            _write_screenshot(plotter, target, bool(translucent), view)
        finally:
            plotter.close()
    return {
        "path": target,
        "warp_factor": scene.factor,
        "colour_limits_um": scene.limits,
        "max_displacement_m": scene.largest_m,
        "translucent_parts": tuple(mesh.part_names[i] for i in sorted(translucent)),
        "window_class": window_class,
        "seconds": time.perf_counter() - started,
    }


@dataclass(frozen=True, eq=False)
class _DeformedScene:
    """Stage 1 of :func:`render_deformed`: what is drawn, checked and scaled (SI, µm for u_y)."""

    deformed: np.ndarray  # (n, 3) warped points, m
    radius: np.ndarray  # drawn radius of each line cell, m
    length_m: float
    largest_m: float
    factor: float
    limits: tuple[float, float]
    path_lines: tuple  # (label, undeformed points, their displacement) per measured path
    translucent_parts: tuple[str, ...] | None  # as asked for (None: the enclosing parts)


@dataclass(frozen=True, eq=False)
class _SceneOptions:
    """The drawing options of :func:`render_deformed` that decide what is drawn (see its parameters)."""

    rig_length_m: float | None
    paths: object
    warp_fraction: float
    colour_limits_um: tuple[float, float] | None
    warp_factor: float | None
    translucent_parts: object
    min_radius_fraction: float


def _deformed_scene(mesh: FieldMesh, case: FieldCase, options: _SceneOptions) -> _DeformedScene:
    """Check the inputs of :func:`render_deformed` and scale the case: the warp factor, the colour limits, the paths."""
    rig_length_m, colour_limits_um, translucent_parts = (options.rig_length_m, options.colour_limits_um,
                                                         options.translucent_parts)
    warp_fraction, warp_factor, min_radius_fraction = (options.warp_fraction, options.warp_factor,
                                                       options.min_radius_fraction)
    paths = options.paths
    if case.displacement_m.shape[0] != mesh.n_points:
        raise ValueError(f"case {case.label!r} has {case.displacement_m.shape[0]} points, the mesh {mesh.n_points}")
    length = mesh_length_m(mesh) if rig_length_m is None else float(rig_length_m)
    if not length > 0:
        raise ValueError("rig_length_m must be positive")
    largest = _largest_displacement_m(case)
    factor = warp_factor_for(largest, length, warp_fraction) if warp_factor is None else float(warp_factor)
    limits = sweep_colour_limits_um([case]) if colour_limits_um is None else tuple(map(float, colour_limits_um))
    if not limits[0] < limits[1]:
        raise ValueError(f"colour_limits_um must be (low, high) with low < high, got {limits}")
    path_lines = tuple((label, *_path_points(mesh, case, polyline)) for label, polyline in _named_paths(paths))
    if isinstance(translucent_parts, str):
        translucent_parts = (translucent_parts,)
    unknown = set(translucent_parts or ()) - set(mesh.part_names)
    if unknown:
        raise ValueError(f"unknown parts {sorted(unknown)}; parts are {', '.join(mesh.part_names)}")
    return _DeformedScene(deformed=mesh.points + factor * case.displacement_m,
                          radius=np.maximum(mesh.line_radius_m, min_radius_fraction * length), length_m=length,
                          largest_m=largest, factor=factor, limits=limits, path_lines=path_lines,
                          translucent_parts=None if translucent_parts is None else tuple(translucent_parts))


def _draw_surfaces(plotter, surfaces: dict, limits, translucent: set, window_size) -> None:
    """Stage 2: every part's surface coloured by u_y, the colour bar with the first one."""
    # VTK's built-in font draws "[" as "(": the title goes through matplotlib's mathtext
    bar = {"title": "$u_y$ [µm]", "vertical": True, "color": "black", "fmt": "%.3g", "n_labels": 5,
           "position_x": 0.9, "position_y": 0.15, "height": 0.7, "width": 0.05,
           "title_font_size": max(8, round(_band(window_size))),
           "label_font_size": max(6, round(0.8 * _band(window_size)))}
    first = True
    for part, surface in surfaces.items():
        plotter.add_mesh(surface, scalars="u_y_um", cmap=COLOURMAP, clim=limits, smooth_shading=True,
                         split_sharp_edges=True,
                         opacity=ENCLOSING_OPACITY if part in translucent else 1.0,
                         show_scalar_bar=first, scalar_bar_args=bar if first else None)
        first = False


def _fit_view(mesh: FieldMesh, scene: _DeformedScene, window_size, title_rows: int):
    """Stage 3: the camera and the rows of part labels under the rig (fitted twice: the labels need the view)."""
    view = _RigView.fit(_bounds(scene.deformed, scene.radius), window_size, label_rows=2, title_lines=title_rows)
    labels = _part_labels(mesh, scene.deformed, view)
    view = _RigView.fit(_bounds(scene.deformed, scene.radius), window_size,
                        label_rows=1 + max((r for *_, r in labels), default=0), title_lines=title_rows)
    return view, _part_labels(mesh, scene.deformed, view)


@dataclass(frozen=True, eq=False)
class _Overlays:
    """What stage 4 of :func:`render_deformed` draws over the rig, placed by ``view``."""

    view: _RigView
    labels: tuple  # (part name, x mm, row)
    title_lines: tuple[str, ...]  # empty: no title
    bearings_x_mm: tuple[float, ...]


def _draw_overlays(plotter, scene: _DeformedScene, overlays: _Overlays) -> None:
    """Stage 4: the measured paths in front of the rig, the x ruler, the part names, the legend, the warp and the
    title."""
    import pyvista as pv

    view, length = overlays.view, scene.length_m
    radius = scene.radius
    front = (float(scene.deformed[:, 2].max() + 1.5 * radius.max()) if len(radius)
             else float(scene.deformed[:, 2].max()))
    legend = []
    for (label, where, moved), colour in zip(scene.path_lines, PATH_COLOURS * 4):
        line = where + scene.factor * moved
        line[:, 2] = front + 0.01 * length
        plotter.add_mesh(pv.lines_from_points(line), color=colour, line_width=6, render_lines_as_tubes=True)
        legend.append([label, colour])
    _draw_ruler(plotter, view, front + 0.02 * length, overlays.bearings_x_mm)
    for name, x_mm, row in overlays.labels:
        column, pixel_row = view.label_pixel(x_mm * 1e-3, row, name)
        plotter.add_text(name, position=(column, pixel_row), font_size=view.small_font, color="black")
    if legend:
        plotter.add_legend(legend, bcolor="white", border=True, size=(1 - RULER_END - 0.02, 0.1), loc="lower right",
                           face="line")
    factor, largest = scene.factor, scene.largest_m
    warp = (f"warp factor × {factor:.4g}: largest displacement {largest * 1e6:.4g} µm drawn as "
            f"{factor * largest / length:.3g} of {length * 1e3:.0f} mm")
    if view.text_width_px(warp + RULER_CAPTION) + 4 * view.band > RULER_END * view.window[0]:
        warp = f"warp × {factor:.4g} ({largest * 1e6:.4g} µm drawn as {factor * largest / length:.3g} of L)"
    plotter.add_text(warp, position=(4, 0.2 * view.band), font_size=view.small_font, color="black")
    if overlays.title_lines:
        plotter.add_text("\n".join(overlays.title_lines), position="upper_edge", font_size=view.title_font,
                         color="black")


def _write_screenshot(plotter, target: Path, translucent: bool, view: _RigView) -> None:
    """Stage 5: depth peeling for translucent parts, anti-aliasing, the camera, and the PNG written atomically."""
    if translucent:
        plotter.enable_depth_peeling(number_of_peels=6)
    plotter.enable_anti_aliasing("ssaa")
    view.apply(plotter)
    temporary = target.with_name(f".{target.stem}.{os.getpid()}.tmp.png")
    try:
        with naming_errors(target):  # (a full disk's ENOSPC names no file)
            plotter.screenshot(str(temporary), return_img=False)
            os.replace(temporary, target)
    finally:
        temporary.unlink(missing_ok=True)


def _screenshot(plotter, view, target: Path) -> None:
    """Anti-alias, set the camera of ``view`` and write the PNG ``target`` atomically (a temporary file beside it)."""
    plotter.enable_anti_aliasing("ssaa")
    view.apply(plotter)
    temporary = target.with_name(f".{target.stem}.{os.getpid()}.tmp.png")
    try:
        plotter.screenshot(str(temporary), return_img=False)
        os.replace(temporary, target)
    finally:
        temporary.unlink(missing_ok=True)


def _bounds(points: np.ndarray, radius: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    pad = float(radius.max()) if len(radius) else 0.0
    return points.min(axis=0) - pad, points.max(axis=0) + pad


@dataclass(frozen=True)
class _RigView:
    """A parallel side view (looking along −z, y up) laid out in pixel bands, top to bottom: the title,
    the rig, the rows of part labels, the x ruler with the bearing marks, the line with the warp factor.
    World (m) and pixel positions map linearly: ``pixel = centre + (world − focal) / metres_per_pixel``."""

    window: tuple[int, int]
    focal: tuple[float, float, float]
    metres_per_pixel: float
    depth: float
    band: float  # height of one text band, pixels
    rig_bottom_px: float  # pixel row (from the bottom) of the rig's lowest point

    @classmethod
    def fit(cls, bounds, window_size, label_rows: int, title_lines: int = 1, width_fraction: float = 0.86) -> _RigView:
        low, high = bounds
        width_px, height_px = (int(v) for v in window_size)
        band = _band(window_size)
        top = (1.0 + 1.2 * title_lines) * band  # the title
        bottom = (label_rows + 3.9) * band  # the labels, the ruler (ticks, numbers) and the warp line
        usable = max(height_px - top - bottom, 0.25 * height_px)
        size = np.maximum(high - low, 1e-12)
        per_px = 1.03 * max(size[0] / (width_fraction * width_px), size[1] / usable)
        centre = 0.5 * (low + high)
        rig_centre_px = bottom + 0.5 * usable
        focal = (float(centre[0] + (0.5 - 0.5 * width_fraction) * width_px * per_px),
                 float(centre[1] + (0.5 * height_px - rig_centre_px) * per_px), float(centre[2]))
        rig_bottom = 0.5 * height_px + (low[1] - focal[1]) / per_px
        return cls((width_px, height_px), focal, float(per_px), float(max(size)), band, float(rig_bottom))

    @property
    def small_font(self) -> int:
        """VTK's font size for labels: its capitals are about 1.45 × the size high (pixels)."""
        return max(6, int(round(0.55 * self.band)))

    @property
    def title_font(self) -> int:
        return max(8, int(round(0.75 * self.band)))

    def pixel_x(self, x_m: float) -> float:
        return 0.5 * self.window[0] + (x_m - self.focal[0]) / self.metres_per_pixel

    def world_y(self, pixel_row: float) -> float:
        return self.focal[1] + (pixel_row - 0.5 * self.window[1]) * self.metres_per_pixel

    def text_width_px(self, text: str) -> float:
        return 1.1 * self.small_font * len(text)  # measured on VTK's default font

    def label_pixel(self, x_m: float, row: int, text: str) -> tuple[float, float]:
        """Lower-left pixel of a part label centred under ``x_m`` in label row ``row`` (0: just under the rig)."""
        column = self.pixel_x(x_m) - 0.5 * self.text_width_px(text)
        column = min(max(column, 2.0), self.window[0] * RULER_END - self.text_width_px(text))
        return column, self.rig_bottom_px - (row + 1.1) * self.band

    @property
    def ruler_px(self) -> float:
        """Pixel row of the ruler line: under the lowest label row."""
        return 2.9 * self.band

    def apply(self, plotter) -> None:
        camera = plotter.camera
        camera.focal_point = self.focal
        camera.position = (self.focal[0], self.focal[1], self.focal[2] + 10 * self.depth)
        camera.up = (0.0, 1.0, 0.0)
        camera.parallel_projection = True
        camera.parallel_scale = 0.5 * self.window[1] * self.metres_per_pixel
        plotter.renderer.ResetCameraClippingRange()


def _band(window_size) -> float:
    """Height of one line of text in a picture of ``window_size`` (pixels): 1/30 of the height, 11 at least."""
    return max(11.0, int(window_size[1]) / 30.0)


def _title_lines(title: str | None, window_size) -> list[str]:
    """The title in at most two lines that fit the window's width at the title's font size."""
    import textwrap

    if not title:
        return []
    font = max(8, int(round(0.75 * _band(window_size))))
    fits = max(int(0.9 * int(window_size[0]) / (1.1 * font)), 10)
    if len(title) <= fits:
        return [title]
    head, colon, tail = title.rpartition(": ")  # "rig (model): T1 = …, T2 = …" breaks after the colon
    lines = [head + ":", tail] if colon and len(head) < fits and len(tail) < fits else textwrap.wrap(title, fits)
    return lines[:1] + [textwrap.shorten(" ".join(lines[1:]), fits, placeholder=" …")] if len(lines) > 1 else lines


def _part_labels(mesh: FieldMesh, deformed: np.ndarray, view: _RigView) -> list[tuple[str, float, int]]:
    """(name, x centre in mm, row) of every part, rows chosen so that no two labels overlap."""
    from rvcoax.results.io.bending_line import stack_rows

    placed = []
    for part, name in enumerate(mesh.part_names):
        points = np.concatenate([mesh.lines[mesh.line_part_id == part].ravel(),
                                 mesh.tetra10[mesh.tetra_part_id == part].ravel()])
        if points.size:
            x = deformed[points, 0]
            placed.append((name, 0.5 * float(x.min() + x.max()) * 1e3))
    placed.sort(key=lambda item: item[1])
    spans = []
    for name, x_mm in placed:
        start, _ = view.label_pixel(x_mm * 1e-3, 0, name)
        spans.append((start, start + view.text_width_px(name)))
    rows = stack_rows(spans, gap=0.8 * view.small_font)
    return [(name, x_mm, row) for (name, x_mm), row in zip(placed, rows)]


def _nice_step(span: float, ticks: int = 10) -> float:
    raw = span / ticks
    power = 10.0 ** np.floor(np.log10(raw))
    return float(next(m * power for m in (1, 2, 5, 10) if m * power >= raw))


def _draw_ruler(plotter, view: _RigView, z: float, bearings_x_mm) -> None:
    """An x ruler in mm under the labels, with the bearings as red triangles on it."""
    import pyvista as pv

    per_px = view.metres_per_pixel
    left = view.focal[0] - 0.5 * view.window[0] * per_px
    right = view.focal[0] + (RULER_END - 0.5) * view.window[0] * per_px
    step = _nice_step((right - left) * 1e3) * 1e-3
    y = view.world_y(view.ruler_px)
    ticks = np.arange(np.ceil(left / step) * step, right, step)
    points = [(left, y, z), (right, y, z)]
    for x in ticks:
        points += [(x, y, z), (x, y - 0.35 * view.band * per_px, z)]
    segments = np.asarray(points, float)
    cells = np.hstack([[2, i, i + 1] for i in range(0, len(segments), 2)])
    plotter.add_mesh(pv.PolyData(segments, lines=cells), color="black", line_width=1)
    for x in ticks:
        text = f"{x * 1e3:.0f}"
        column = view.pixel_x(x) - 0.5 * view.text_width_px(text)
        if column > 2 and column + view.text_width_px(text) < RULER_END * view.window[0]:
            plotter.add_text(text, position=(column, view.ruler_px - 1.5 * view.band), font_size=view.small_font,
                             color="black")
    plotter.add_text(RULER_CAPTION, position=(RULER_END * view.window[0] - view.text_width_px(RULER_CAPTION),
                                              0.2 * view.band),
                     font_size=view.small_font, color="black")
    height = 0.7 * view.band * per_px
    for x_mm in bearings_x_mm:
        x = float(x_mm) * 1e-3
        if not left <= x <= right:
            continue
        triangle = pv.PolyData(np.array([(x - 0.4 * height, y, z), (x + 0.4 * height, y, z), (x, y + height, z)]),
                               faces=[3, 0, 1, 2])
        plotter.add_mesh(triangle, color="#c8102e")


# --------------------------------------------------------------------------------------------
# Y against torque

_KEYS = ("T1_input_Nm", "T2_output_Nm", "Y_input_mm", "Y_output_mm")


def _series(rows) -> tuple[dict[str, np.ndarray], dict[str, float]]:
    """(arrays keyed like sweep.csv, path lengths) from a Sweep, CaseResults, PublishedRows, a
    mapping of arrays or a list of row dicts."""
    lengths: dict[str, float] = {}
    items = rows.cases if hasattr(rows, "cases") and hasattr(rows, "frame") else rows
    if isinstance(items, Mapping):
        data = {k: np.asarray(items[k], float) for k in items if k in _KEYS}
    else:
        items = list(items)
        if items and hasattr(items[0], "paths"):  # CaseResult
            data = {"T1_input_Nm": [c.case.input_torque_Nm for c in items],
                    "T2_output_Nm": [c.case.output_torque_Nm for c in items],
                    "Y_input_mm": [c.paths["input"].y_max_mm for c in items],
                    "Y_output_mm": [c.paths["output"].y_max_mm for c in items]}
            lengths = {s: items[0].paths[s].length_mm for s in MEASURED_SHAFTS}
        elif items and hasattr(items[0], "y_input_mm"):  # PublishedRow
            data = {"T1_input_Nm": [r.case.input_torque_Nm for r in items],
                    "T2_output_Nm": [r.case.output_torque_Nm for r in items],
                    "Y_input_mm": [r.y_input_mm for r in items], "Y_output_mm": [r.y_output_mm for r in items]}
        else:
            data = {k: [float(r[k]) for r in items] for k in _KEYS}
        data = {k: np.asarray(v, float) for k, v in data.items()}
    missing = [k for k in _KEYS if k not in data]
    if missing:
        raise ValueError(f"rows lack {', '.join(missing)}")
    return data, lengths


def _beta_axis(ax, length: float, micro: bool) -> None:
    """The right-hand axis β = arcsin(Y / L) of a Y panel, ``length`` in the unit of the Y axis."""
    if micro:
        functions = (lambda y, L=length: 1e6 * np.arcsin(np.clip(y / L, -1, 1)),
                     lambda b, L=length: L * np.sin(1e-6 * np.asarray(b)))
    else:
        functions = (lambda y, L=length: np.degrees(np.arcsin(np.clip(y / L, -1, 1))),
                     lambda b, L=length: L * np.sin(np.radians(b)))
    secondary = ax.secondary_yaxis("right", functions=functions)
    secondary.set_ylabel("β = arcsin(Y / L) (paper 000) [" + ("µrad]" if micro else "°]"))
    if not micro:
        secondary.ticklabel_format(style="sci", scilimits=(-3, 3))


def plot_y_vs_torque(model_rows, path_png: str | Path, *, published=None, title: str | None = None,  # noqa: PLR0913
                     path_lengths_mm: tuple[float, float] | None = None, dpi: int = 150,
                     micro: bool = False, published_label: str = "published (paper 000)") -> Path:
    """Two panels, Y_input (mm) against T1 and Y_output (mm) against T2 (N·m), written as a PNG.

    Y is the path's largest |u_y|, as published. Each panel gets a right-hand axis with
    β = arcsin(Y / L) in degrees when the path length L is known.

    Parameters
    ----------
    model_rows
        A Sweep, a sequence of CaseResult, a mapping of arrays or a list of dicts with the sweep.csv keys
        ``T1_input_Nm, T2_output_Nm, Y_input_mm, Y_output_mm``; or a dict label → one of those to draw
        several models (e.g. blind and calibrated).
    path_png : str or Path
        Where the picture goes.
    published : optional
        Paper rows (:func:`rvcoax.paper_table`) or the same kinds of rows, drawn as markers.
    title : str, optional
        The figure's title.
    path_lengths_mm : (float, float), optional
        ``(L_input, L_output)`` for the β axis when ``model_rows`` is not a Sweep.
    dpi : int
        Resolution of the PNG.
    micro : bool
        Y in µm and β in µrad instead of mm and degrees (sub-µm values read as plain numbers, without a
        1e-4 offset on the axis).
    published_label : str
        The legend of the ``published`` points (the measured data's own name for a user's table).

    Returns
    -------
    Path
        ``path_png``.
    """
    import matplotlib
    from matplotlib.figure import Figure  # no pyplot: the figure is drawn by Agg, whatever the backend

    if isinstance(model_rows, Mapping) and not any(k in model_rows for k in _KEYS):
        series = {str(k): _series(v) for k, v in model_rows.items()}
    else:
        series = {"model": _series(model_rows)}
    lengths = dict(zip(MEASURED_SHAFTS, path_lengths_mm)) if path_lengths_mm else {}
    for _, found in series.values():
        lengths = lengths or found
    reference = _series(published)[0] if published is not None else None

    figure = Figure(figsize=(12, 4.8), dpi=dpi, layout="constrained")
    axes = figure.subplots(1, 2)
    colours = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    scale, unit = (1e3, "µm") if micro else (1.0, "mm")
    for ax, shaft, torque, torque_label in ((axes[0], "input", "T1_input_Nm", "T1 (input torque) [N·m]"),
                                           (axes[1], "output", "T2_output_Nm", "T2 (output torque) [N·m]")):
        key = f"Y_{shaft}_mm"
        for (label, (data, _)), colour in zip(series.items(), colours * 4):
            order = np.argsort(data[torque], kind="stable")
            ax.plot(data[torque][order], scale * data[key][order], "-", color=colour, lw=1.8, marker=".", ms=4,
                    label=label)
        if reference is not None:
            ax.plot(reference[torque], scale * reference[key], "o", mfc="none", mec="black", ms=7, mew=1.3,
                    label=published_label, zorder=5)
        ax.set_xlabel(torque_label)
        ax.set_ylabel(f"Y_{shaft} (largest |u_y| on the {shaft} shaft) [{unit}]")
        if not micro:
            ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
        ax.set_xlim(left=0)
        ax.set_ylim(bottom=0)
        ax.grid(True, alpha=0.3)
        ax.set_title(f"{shaft} shaft" + (f", L = {lengths[shaft]:g} mm" if shaft in lengths else ""))
        if shaft in lengths:
            _beta_axis(ax, lengths[shaft] * scale, micro)
        ax.legend(loc="upper left", fontsize=9)
    if title:
        figure.suptitle(title)
    return write_png_atomic(path_png, figure)


__all__ = [
    "RENDER_PACKAGES", "RenderingUnavailableError", "check_offscreen_rendering", "enclosing_parts", "mesh_length_m",
    "plot_y_vs_torque", "render_deformed", "sweep_colour_limits_um", "sweep_warp_factor", "warp_factor_for",
]
