"""Full displacement fields per load case, on a mesh that holds beams and solids, and their files.

A :class:`FieldMesh` is mesh-agnostic: points (m), beam elements as 2-point ``lines`` with their
outer radius (for drawing tubes), and quadratic tetrahedra (``tetra10``, in meshio's node order,
which is VTK_QUADRATIC_TETRA's) for solid parts; every cell carries the id of its part. A
:class:`FieldCase` is one load case on that mesh: the nodal translations (m) and, where a model
provides it at every point, the von Mises stress (Pa); otherwise no stress field at all (a field
of NaN is no result).

In memory everything is SI. The files are in **mm** (points, ``displacement_mm``, ``radius_mm``), the
unit written in every array's name (``displacement_y_um``, ``von_mises_MPa``), so that ParaView shows
mm and "warp by vector" works with the points as they are.

The beam model fills them with :func:`beam_field_mesh` and :func:`beam_field_cases`; the
displacement is "measured" exactly as :func:`rvcoax.results.sweep.run_sweep` measures Y (from the aligned
state at rest, u − u_rest, when ``paths.measured_from = "aligned_at_rest"``), so the field's u_y at
the path nodes equals the sweep's path values.

Files
-----
:func:`write_vtu` writes one ``.vtu`` per case (points in mm; point data ``displacement_mm``,
``displacement_y_um`` and, when the case has it, ``von_mises_MPa``; cell data ``part_id`` and
``radius_mm`` (0 on tetrahedra, which have no tube radius); field data ``T1_input_Nm``, ``T2_output_Nm`` and one ``part_id:<name>`` entry per
part). It is written to a temporary file in the same folder and renamed: atomic.

:func:`write_xdmf_series` writes an XDMF time series over the cases: **time = case index**
(0, 1, …, in the order given), with the same arrays, and ``<stem>.cases.json`` beside it that maps
each time to the case's label, T1 and T2 (XDMF steps carry no field data) and lists the part names.
The heavy data go into ``<stem>.h5`` when h5py is installed (``data_format="HDF"``), otherwise
inline into the XML (``"XML"``); ``"auto"`` (default) picks HDF when it can. All files are first
written into a temporary folder next to the target and then each one is renamed into place (the
``.h5`` first, then the JSON, the ``.xdmf`` last): every file is replaced atomically, the set of
files is not (a reader that opens the old ``.xdmf`` during the renames may see the new ``.h5``).

meshio 5.3.5 cannot write a mixed line + tetra10 topology (it crashes on lines) nor read one back
(its reader has no tetra10 in mixed topologies); the writer and reader here fix both, so hybrid
meshes go into one series that ParaView opens. :func:`read_xdmf_series` and :func:`read_vtu` read
the files back into a FieldMesh and FieldCases.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import meshio
import meshio.xdmf
import numpy as np
from meshio import CellBlock
from meshio.xdmf.common import (
    meshio_type_to_xdmf_index,
    numpy_to_xdmf_dtype,
    xdmf_idx_to_meshio_type,
    xdmf_to_meshio_type,
)

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model.beam import RigModel
from rvcoax.geometry.model.loads import UNIT_LOADS, gear_contact_torques, superpose
from rvcoax.geometry.units import M_TO_MM

LINE = "line"
TETRA10 = "tetra10"
XDMF_TIME = "case index (0, 1, ... in the order of the cases)"


def _readonly(array: np.ndarray) -> np.ndarray:
    array = np.array(array, copy=True)
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class FieldMesh:
    """Points and cells of a model for field output (SI units).

    Attributes
    ----------
    points : (n, 3) float array
        Point positions in m.
    lines : (k, 2) int array
        Beam elements (point indices).
    line_radius_m : (k,) float array
        Outer radius of each beam element (m), for drawing tubes.
    line_part_id : (k,) int array
        Index into ``part_names`` of each beam element.
    part_names : tuple of str
    tetra10 : (t, 10) int array
        Quadratic tetrahedra in meshio's (= VTK_QUADRATIC_TETRA's) node order; may be empty.
    tetra_part_id : (t,) int array
    """

    points: np.ndarray
    lines: np.ndarray
    line_radius_m: np.ndarray
    line_part_id: np.ndarray
    part_names: tuple[str, ...]
    tetra10: np.ndarray = field(default_factory=lambda: np.zeros((0, 10), dtype=np.int64))
    tetra_part_id: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int32))

    def __post_init__(self) -> None:
        points = np.asarray(self.points, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3:
            raise ValueError(f"points must be (n, 3), got {points.shape}")
        lines = np.asarray(self.lines, dtype=np.int64).reshape(-1, 2)
        tets = np.asarray(self.tetra10, dtype=np.int64).reshape(-1, 10)
        radius = np.asarray(self.line_radius_m, dtype=float).reshape(-1)
        line_part = np.asarray(self.line_part_id, dtype=np.int32).reshape(-1)
        tet_part = np.asarray(self.tetra_part_id, dtype=np.int32).reshape(-1)
        names = tuple(str(n) for n in self.part_names)
        if radius.size != lines.shape[0] or line_part.size != lines.shape[0]:
            raise ValueError(f"{lines.shape[0]} lines but {radius.size} radii and {line_part.size} part ids")
        if tet_part.size != tets.shape[0]:
            raise ValueError(f"{tets.shape[0]} tetrahedra but {tet_part.size} part ids")
        for name, cells in (("lines", lines), ("tetra10", tets)):
            if cells.size and (cells.min() < 0 or cells.max() >= points.shape[0]):
                raise ValueError(f"{name} refer to points outside 0..{points.shape[0] - 1}")
        for ids in (line_part, tet_part):
            if ids.size and (ids.min() < 0 or ids.max() >= len(names)):
                raise ValueError(f"part ids must lie in 0..{len(names) - 1}")
        if np.any(~np.isfinite(points)) or np.any(~(radius > 0)):
            raise ValueError("points must be finite and line radii positive")
        for key, value in (("points", points), ("lines", lines), ("tetra10", tets), ("line_radius_m", radius),
                           ("line_part_id", line_part), ("tetra_part_id", tet_part)):
            object.__setattr__(self, key, _readonly(value))
        object.__setattr__(self, "part_names", names)

    @property
    def n_points(self) -> int:
        return int(self.points.shape[0])

    def cell_blocks(self) -> list[tuple[str, np.ndarray]]:
        """meshio cell blocks (non-empty ones only): lines first, then tetra10."""
        blocks = [(LINE, self.lines), (TETRA10, self.tetra10)]
        return [(kind, np.ascontiguousarray(cells)) for kind, cells in blocks if len(cells)]

    def cell_data(self) -> dict[str, list[np.ndarray]]:
        """Cell data per block, in the order of :meth:`cell_blocks`, as written to files (mm)."""
        part, radius = [], []
        if len(self.lines):
            part.append(np.array(self.line_part_id, dtype=np.int32))
            radius.append(np.array(self.line_radius_m, dtype=float) * M_TO_MM)
        if len(self.tetra10):
            part.append(np.array(self.tetra_part_id, dtype=np.int32))
            radius.append(np.zeros(len(self.tetra10)))  # a tetrahedron is drawn as itself, not as a tube
        return {"part_id": part, "radius_mm": radius}

    @property
    def points_mm(self) -> np.ndarray:
        """Point positions in mm, as written to files."""
        return np.asarray(self.points) * M_TO_MM


@dataclass(frozen=True, eq=False)
class FieldCase:
    """The fields of one load case on a :class:`FieldMesh`.

    Attributes
    ----------
    label : str
    T1_input_Nm, T2_output_Nm : float
    displacement_m : (n, 3) float array
        Nodal translation (m), measured as the sweep measures Y.
    von_mises_Pa : (n,) float array or None
        Von Mises stress (Pa) at every point, or None where the model gives none (beams): the
        files then hold no stress field.
    """

    label: str
    T1_input_Nm: float
    T2_output_Nm: float
    displacement_m: np.ndarray
    von_mises_Pa: np.ndarray | None = None

    def __post_init__(self) -> None:
        u = np.asarray(self.displacement_m, dtype=float)
        if u.ndim != 2 or u.shape[1] != 3:
            raise ValueError(f"displacement_m must be (n, 3), got {u.shape}")
        if self.von_mises_Pa is not None:
            vm = np.asarray(self.von_mises_Pa, float)
            if vm.shape != (u.shape[0],) or not np.all(np.isfinite(vm)):
                raise ValueError(f"von_mises_Pa must be ({u.shape[0]},) finite values (or None), got {vm.shape}")
            object.__setattr__(self, "von_mises_Pa", _readonly(vm))
        object.__setattr__(self, "displacement_m", _readonly(u))
        object.__setattr__(self, "T1_input_Nm", float(self.T1_input_Nm))
        object.__setattr__(self, "T2_output_Nm", float(self.T2_output_Nm))

    @property
    def displacement_y_um(self) -> np.ndarray:
        return self.displacement_m[:, 1] * 1e6

    def point_data(self) -> dict[str, np.ndarray]:
        """Point data as written to files (the unit in each name)."""
        data = {"displacement_mm": np.array(self.displacement_m) * M_TO_MM, "displacement_y_um": self.displacement_y_um}
        if self.von_mises_Pa is not None:
            data["von_mises_MPa"] = np.array(self.von_mises_Pa) * 1e-6
        return data


def _check(mesh: FieldMesh, case: FieldCase) -> None:
    if case.displacement_m.shape[0] != mesh.n_points:
        raise ValueError(f"case {case.label!r} has {case.displacement_m.shape[0]} points, the mesh {mesh.n_points}")


# --------------------------------------------------------------------------------------------
# Beam model → fields


def beam_outer_radius_m(area_m2: np.ndarray, second_moment_m4: np.ndarray) -> np.ndarray:
    """Outer radius of a (hollow) circular section from A and I: r_o² = (4I/A + A/π) / 2."""
    area = np.asarray(area_m2, float)
    return np.sqrt(0.5 * (4.0 * np.asarray(second_moment_m4, float) / area + area / np.pi))


def beam_field_mesh(frame: RigModel) -> FieldMesh:
    """The beam model's nodes and elements (tubes of the sections' outer radius), parts in rig order."""
    structure = frame.structure
    names = tuple(p.name for p in frame.rig.parts)
    index = {n: i for i, n in enumerate(names)}
    connectivity = np.asarray(structure.beams.connectivity, dtype=np.int64)
    part_id = np.array([index[frame.node_part[a]] for a in connectivity[:, 0]], dtype=np.int32)
    radius = beam_outer_radius_m(structure.beams.area_m2, structure.beams.second_moment_m4)
    return FieldMesh(structure.coordinates, connectivity, radius, part_id, names)


def _load_case(case):
    """A LoadCase from a LoadCase or a CaseResult."""
    return getattr(case, "case", case)


def beam_field_cases(frame: RigModel, cases: Iterable, unit_responses=None) -> list[FieldCase]:
    """Nodal translations of the beam model for each case (LoadCase or CaseResult).

    Built exactly as :func:`rvcoax.results.sweep.run_sweep` builds them (superposition of the unit
    responses in :data:`rvcoax.geometry.model.loads.UNIT_LOADS` order, minus u_rest when Y is measured from the
    aligned state at rest), so u_y at the path nodes equals the sweep's ``uy_mm`` / 1e3.
    ``unit_responses`` is the (n_dofs, len(UNIT_LOADS)) matrix of
    :func:`rvcoax.results.sweep.solve_unit_responses` when already solved.
    """
    if unit_responses is None:
        from rvcoax.results.sweep import solve_unit_responses

        unit_responses = solve_unit_responses(frame)[2]
    unit_by_name = {k: unit_responses[:, i] for i, k in enumerate(UNIT_LOADS)}
    from_rest = frame.rig.paths.measured_from == "aligned_at_rest"
    contact = gear_contact_torques(frame.rig)
    out = []
    for item in cases:
        case = _load_case(item)
        measured = superpose(unit_by_name, case.input_torque_Nm, case.output_torque_Nm, from_rest, contact)
        out.append(FieldCase(case.label, case.input_torque_Nm, case.output_torque_Nm,
                             measured.reshape(-1, 6)[:, :3]))
    return out


def path_point_indices(frame: RigModel) -> dict[str, np.ndarray]:
    """Point indices of the two measured shaft paths (``"input"``, ``"output"``), input end first."""
    return {which: frame.path_nodes(which)[0] for which in MEASURED_SHAFTS}


def path_polylines(frame: RigModel) -> dict[str, np.ndarray]:
    """Undeformed positions (m) of the measured shaft paths, as (N, 3) polylines."""
    return {which: frame.structure.coordinates[nodes] for which, nodes in path_point_indices(frame).items()}


# --------------------------------------------------------------------------------------------
# VTU


def _replace_durably(source: Path, target: Path) -> None:
    with open(source, "rb+") as stream:
        os.fsync(stream.fileno())
    os.replace(source, target)


def _field_data_xml(mesh: FieldMesh, case: FieldCase) -> str:
    arrays = [f'<DataArray type="Float64" Name="T1_input_Nm" NumberOfTuples="1" format="ascii">'
              f"{case.T1_input_Nm!r}</DataArray>",
              f'<DataArray type="Float64" Name="T2_output_Nm" NumberOfTuples="1" format="ascii">'
              f"{case.T2_output_Nm!r}</DataArray>"]
    for i, name in enumerate(mesh.part_names):
        safe = re.sub(r"[^A-Za-z0-9_.\-]", "_", name)
        arrays.append(f'<DataArray type="Int32" Name="part_id:{safe}" NumberOfTuples="1" format="ascii">'
                      f"{i}</DataArray>")
    return "<FieldData>" + "".join(arrays) + "</FieldData>"


def write_vtu(path: str | Path, mesh: FieldMesh, case: FieldCase) -> Path:
    """Write one case as a VTK unstructured grid (.vtu), atomically; returns the path.

    Parameters
    ----------
    path : str or Path
        The ``.vtu`` file.
    mesh : FieldMesh
        Points and cells (:func:`sweep_field_mesh`).
    case : FieldCase
        The case's fields on those points.

    Returns
    -------
    Path
        ``path``.
    """
    _check(mesh, case)
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=".vtu", dir=target.parent)
    os.close(handle)
    temporary = Path(temporary)
    os.chmod(temporary, 0o644)  # mkstemp makes it private; a result file is readable like any other
    try:
        data = meshio.Mesh(mesh.points_mm, mesh.cell_blocks(), point_data=case.point_data(), cell_data=mesh.cell_data())
        meshio.write(temporary, data, file_format="vtu")
        # meshio 5.3.5 does not write field data (it reads it): add T1, T2 and the part names.
        text = temporary.read_text(encoding="utf-8")
        opening = re.search(r"<UnstructuredGrid[^>]*>", text)
        if opening is None:
            raise RuntimeError("meshio wrote a .vtu without an <UnstructuredGrid> element")
        text = text[:opening.end()] + _field_data_xml(mesh, case) + text[opening.end():]
        temporary.write_text(text, encoding="utf-8")
        _replace_durably(temporary, target)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    return target


def _mesh_from_meshio(points, cells, cell_data, part_names) -> FieldMesh:
    blocks = {b.type if isinstance(b, CellBlock) else b[0]: i for i, b in enumerate(cells)}
    unknown = set(blocks) - {LINE, TETRA10}
    if unknown:
        raise ValueError(f"unexpected cell types {sorted(unknown)}")

    def data(kind):
        if kind not in blocks:
            return None
        block = cells[blocks[kind]]
        return block.data if isinstance(block, CellBlock) else block[1]

    def per_cell(name, kind):
        return np.asarray(cell_data[name][blocks[kind]]).reshape(-1) if kind in blocks else np.zeros(0)

    # files before the unit policy (issue 15) were in m: points, radius_m, displacement
    scale = 1.0 / M_TO_MM if "radius_mm" in cell_data else 1.0
    radius = per_cell("radius_mm", LINE) / M_TO_MM if "radius_mm" in cell_data else per_cell("radius_m", LINE)

    lines = data(LINE)
    tets = data(TETRA10)
    return FieldMesh(points=np.asarray(points, float) * scale,
                     lines=np.zeros((0, 2), np.int64) if lines is None else lines, line_radius_m=radius,
                     line_part_id=per_cell("part_id", LINE).astype(np.int32), part_names=tuple(part_names),
                     tetra10=np.zeros((0, 10), np.int64) if tets is None else tets,
                     tetra_part_id=per_cell("part_id", TETRA10).astype(np.int32))


def read_vtu(path: str | Path) -> tuple[FieldMesh, FieldCase]:
    """Read a file written by :func:`write_vtu` (the case's label is the file's stem)."""
    data = meshio.read(path, file_format="vtu")
    parts = sorted(((int(np.asarray(v).ravel()[0]), k.split(":", 1)[1]) for k, v in data.field_data.items()
                    if k.startswith("part_id:")))
    mesh = _mesh_from_meshio(data.points, data.cells, data.cell_data, [name for _, name in parts])
    t1 = float(np.asarray(data.field_data["T1_input_Nm"]).ravel()[0])
    t2 = float(np.asarray(data.field_data["T2_output_Nm"]).ravel()[0])
    case = FieldCase(Path(path).stem, t1, t2, *_case_fields(data.point_data))
    return mesh, case


def _case_fields(point_data: dict) -> tuple[np.ndarray, np.ndarray | None]:
    """(displacement in m, von Mises in Pa or None) from a file's point data (mm, MPa; or m, Pa before)."""
    if "displacement_mm" in point_data:
        stress = point_data.get("von_mises_MPa")
        return (np.asarray(point_data["displacement_mm"]) / M_TO_MM,
                None if stress is None else np.asarray(stress) * 1e6)
    stress = point_data.get("von_mises")
    if stress is not None and not np.all(np.isfinite(stress)):
        stress = None  # files before the unit policy wrote NaN where a model gave no stress
    return np.asarray(point_data["displacement"]), stress


# --------------------------------------------------------------------------------------------
# XDMF time series


class _SeriesWriter(meshio.xdmf.TimeSeriesWriter):
    """meshio's writer with two fixes: the .h5 goes next to the .xdmf (not into the current
    folder), and a mixed topology with lines is written as XDMF polylines of 2 points."""

    def __enter__(self):
        if self.data_format == "HDF":
            import h5py

            self.h5_filename = str(self.filename.with_suffix(".h5"))
            self.h5_file = h5py.File(self.h5_filename, "w")
        return self

    def cells(self, cells, grid):
        blocks = [CellBlock(*b) if isinstance(b, tuple) else b for b in cells]
        if len(blocks) <= 1:
            return super().cells(blocks, grid)
        pieces = []
        for block in blocks:
            data = np.asarray(block.data, dtype=np.int64)
            prefix = [meshio_type_to_xdmf_index[block.type]] + ([2] if block.type == LINE else [])
            pieces.append(np.hstack([np.tile(prefix, (len(data), 1)), data]).ravel())
        mixed = np.concatenate(pieces)
        topology = ET.SubElement(grid, "Topology", TopologyType="Mixed",
                                 NumberOfElements=str(sum(len(b.data) for b in blocks)))
        data_type, precision = numpy_to_xdmf_dtype[mixed.dtype.name]
        item = ET.SubElement(topology, "DataItem", DataType=data_type, Dimensions=str(mixed.size),
                             Format=self.data_format, Precision=precision)
        item.text = self.numpy_to_xml_string(mixed)


_NODES = {"vertex": 1, LINE: 2, "triangle": 3, "quad": 4, "tetra": 4, "pyramid": 5, "wedge": 6,
          "hexahedron": 8, "triangle6": 6, TETRA10: 10}


def _translate_mixed(data: np.ndarray) -> list[CellBlock]:
    """Mixed XDMF topology → cell blocks (meshio's version lacks tetra10)."""
    kinds, starts = [], []
    r = 0
    while r < len(data):
        kind = xdmf_idx_to_meshio_type[int(data[r])]
        if kind == LINE:
            if data[r + 1] != 2:
                raise ValueError("only 2-point polylines are supported")
            r += 1
        kinds.append(kind)
        starts.append(r + 1)
        r += 1 + _NODES[kind]
    blocks = []
    i = 0
    while i < len(kinds):
        j = i
        while j < len(kinds) and kinds[j] == kinds[i]:
            j += 1
        n = _NODES[kinds[i]]
        index = np.asarray(starts[i:j])[:, None] + np.arange(n)
        blocks.append(CellBlock(kinds[i], data[index]))
        i = j
    return blocks


class _SeriesReader(meshio.xdmf.TimeSeriesReader):
    """meshio's reader, reading mixed topologies with tetra10 too."""

    def read_points_cells(self):
        points, cells = None, []
        for child in self.mesh_grid:
            if child.tag == "Topology":
                data = self._read_data_item(list(child)[0])
                kind = child.attrib.get("Type", child.attrib.get("TopologyType"))
                cells = _translate_mixed(data) if kind == "Mixed" else [CellBlock(xdmf_to_meshio_type[kind], data)]
            elif child.tag == "Geometry":
                points = self._read_data_item(list(child)[0])
        self.cells = cells
        return points, cells


def _data_format(requested: str) -> str:
    if requested != "auto":
        if requested not in ("HDF", "XML"):
            raise ValueError(f"data_format must be 'auto', 'HDF' or 'XML', got {requested!r}")
        return requested
    try:
        import h5py  # noqa: F401
    except ImportError:
        return "XML"
    return "HDF"


def write_xdmf_series(path: str | Path, mesh: FieldMesh, cases: Sequence[FieldCase],
                      data_format: str = "auto") -> dict[str, Path]:
    """Write the cases as an XDMF time series (time = case index) plus ``<stem>.cases.json``.

    ``data_format``: ``"HDF"`` (``<stem>.h5`` beside the .xdmf; needs h5py), ``"XML"`` (inline,
    one self-contained file) or ``"auto"`` (HDF when h5py is installed). Returns the written files
    by kind (``"xdmf"``, ``"json"`` and, for HDF, ``"h5"``). See the module doc for atomicity.

    Parameters
    ----------
    path : str or Path
        The ``.xdmf`` file.
    mesh : FieldMesh
        Points and cells, shared by every step.
    cases : sequence of FieldCase
        One time step each, in order.
    data_format : {"auto", "HDF", "XML"}
        Where the heavy data go.

    Returns
    -------
    dict of str to Path
        The files written, by kind.
    """
    if not cases:
        raise ValueError("no cases to write")
    for case in cases:
        _check(mesh, case)
    fmt = _data_format(data_format)
    target = Path(path)
    if target.suffix.lower() != ".xdmf":
        raise ValueError(f"{target}: the file name must end in .xdmf")
    target.parent.mkdir(parents=True, exist_ok=True)
    names = {"xdmf": target.name, "json": target.stem + ".cases.json"}
    if fmt == "HDF":
        names["h5"] = target.stem + ".h5"
    staging = Path(tempfile.mkdtemp(prefix=f".{target.stem}.", dir=target.parent))
    try:
        with _SeriesWriter(staging / names["xdmf"], data_format=fmt) as writer:
            writer.write_points_cells(mesh.points_mm, mesh.cell_blocks())
            cell_data = mesh.cell_data()
            for i, case in enumerate(cases):
                writer.write_data(i, point_data=case.point_data(), cell_data=cell_data)
        info = {
            "time": XDMF_TIME,
            "units": {"points": "mm", "displacement_mm": "mm", "displacement_y_um": "um", "von_mises_MPa": "MPa",
                      "radius_mm": "mm", "T1_input_Nm": "N m", "T2_output_Nm": "N m"},
            "part_names": list(mesh.part_names),
            "data_format": fmt,
            "cases": [{"time": i, "label": c.label, "T1_input_Nm": c.T1_input_Nm, "T2_output_Nm": c.T2_output_Nm}
                      for i, c in enumerate(cases)],
        }
        (staging / names["json"]).write_text(json.dumps(info, indent=2) + "\n", encoding="utf-8")
        written = {}
        for kind in ("h5", "json", "xdmf"):  # the entry point last
            if kind in names:
                _replace_durably(staging / names[kind], target.parent / names[kind])
                written[kind] = target.parent / names[kind]
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return {k: written[k] for k in ("xdmf", "h5", "json") if k in written}


def read_xdmf_series(path: str | Path) -> tuple[FieldMesh, list[FieldCase]]:
    """Read a series written by :func:`write_xdmf_series` (with its ``.cases.json``)."""
    target = Path(path)
    info = json.loads(target.with_name(target.stem + ".cases.json").read_text(encoding="utf-8"))
    with _SeriesReader(target) as reader:
        points, cells = reader.read_points_cells()
        steps = [reader.read_data(k) for k in range(reader.num_steps)]
    mesh = _mesh_from_meshio(points, cells, steps[0][2], info["part_names"])
    by_time = {c["time"]: c for c in info["cases"]}
    out = []
    for t, point_data, _ in steps:
        meta = by_time[int(round(t))]
        out.append(FieldCase(meta["label"], meta["T1_input_Nm"], meta["T2_output_Nm"], *_case_fields(point_data)))
    return mesh, out


__all__ = [
    "FieldCase", "FieldMesh", "XDMF_TIME", "beam_field_cases", "beam_field_mesh", "beam_outer_radius_m",
    "path_point_indices", "path_polylines", "read_vtu", "read_xdmf_series", "sweep_field_cases", "sweep_field_mesh",
    "write_vtu", "write_xdmf_series",
]


# --------------------------------------------------------------------------------------------
# Any fidelity: the fields of a solved sweep


def _solid_point_dofs(part) -> np.ndarray:
    """(n_points, 3) global DOFs of a solid part's P2 nodes, in meshio's point order (= doflocs)."""
    basis = part.basis
    return np.vstack([basis.nodal_dofs.T, basis.edge_dofs.T]) + part.offset


def sweep_field_mesh(sweep) -> tuple[FieldMesh, dict[str, np.ndarray]]:
    """The field mesh of a solved sweep (beams, solid parts, and the path stations as points).

    Returns the mesh and the point indices of the two measured paths. Path stations on a solid
    shaft are extra points (no cell) on the shaft's axis.

    Parameters
    ----------
    sweep : Sweep
        A solved sweep (beam, hybrid or solid).

    Returns
    -------
    (FieldMesh, dict)
        The mesh, and ``{"input": point indices, "output": point indices}`` of the measured paths.
    """
    from skfem.io.meshio import to_meshio

    system = sweep.system
    frame = beam_field_mesh(system.frame)
    names = frame.part_names
    index = {n: i for i, n in enumerate(names)}
    points = [np.asarray(frame.points)]
    tets, tet_ids = [], []
    count = frame.n_points
    for part in system.solids:
        converted = to_meshio(part.mesh)
        cells = [c.data for c in converted.cells if c.type == "tetra10"][0]
        points.append(np.asarray(converted.points))
        tets.append(cells + count)
        tet_ids.append(np.full(cells.shape[0], index[part.name], dtype=np.int32))
        count += converted.points.shape[0]
    paths: dict[str, np.ndarray] = {}
    for which in MEASURED_SHAFTS:
        path = getattr(system.rig.paths, which)
        if any(p.name == path.part for p in system.solids):
            stations = path.x_start_mm + system.probes[which].stations_mm
            axis = np.column_stack([stations * 1e-3, np.zeros(stations.size), np.zeros(stations.size)])
            points.append(axis)
            paths[which] = np.arange(count, count + stations.size)
            count += stations.size
        else:
            paths[which] = system.frame.path_nodes(which)[0]
    mesh = FieldMesh(points=np.vstack(points), lines=frame.lines, line_radius_m=frame.line_radius_m,
                     line_part_id=frame.line_part_id, part_names=names,
                     tetra10=np.vstack(tets) if tets else np.zeros((0, 10), dtype=np.int64),
                     tetra_part_id=np.concatenate(tet_ids) if tet_ids else np.zeros(0, dtype=np.int32))
    return mesh, paths


def sweep_field_cases(sweep) -> list[FieldCase]:
    """Point displacements (m) of every case of a solved sweep, measured as the sweep measures Y.

    Parameters
    ----------
    sweep : Sweep
        A solved sweep; its displacements are measured as its Y is.

    Returns
    -------
    list of FieldCase
        One per load case, on the points of :func:`sweep_field_mesh`.
    """
    system = sweep.system
    n_frame = system.frame.structure.n_nodes
    solid_dofs = [_solid_point_dofs(part) for part in system.solids]
    solid_paths = [which for which in MEASURED_SHAFTS
                   if any(p.name == getattr(system.rig.paths, which).part for p in system.solids)]
    out = []
    for i, result in enumerate(sweep.cases):
        case = result.case
        measured = sweep.measured_displacement(i)  # also for a nonlinear (bearing clearance) sweep
        blocks = [measured[: 6 * n_frame].reshape(-1, 6)[:, :3]]
        blocks += [measured[dofs] for dofs in solid_dofs]
        for which in solid_paths:
            uy = system.probes[which].uy @ measured
            blocks.append(np.column_stack([np.zeros_like(uy), uy, np.zeros_like(uy)]))
        out.append(FieldCase(case.label, case.input_torque_Nm, case.output_torque_Nm, np.vstack(blocks)))
    return out
