"""Hidden-effect data from CalculiX *solid* shafts: the measured shafts as C3D10 tetrahedra in ``ccx``.

The discrepancy workflow identifies with rvcoax's beam model. ``calculix_rig.py`` makes data with CalculiX beams;
this module makes them on a discretisation the workflow never uses: the two measured shafts (``[paths]``) are
quadratic tetrahedra (``C3D10``) in CalculiX, the rest of the shaft line stays the beam-and-spring deck of
``calculix_rig.build_deck``.

- **Mesh**: rvcoax's own gmsh meshing (``rvcoax.geometry.meshing.mesh_part``) of the shaft's stepped, possibly
  hollow segments at ``MESH_MM`` (6 mm; finer where a curved element would be inverted in CalculiX's integration
  points: 4 mm on the reference input shaft's Ø8 bore), with split planes at the edges of every band something acts on
  *and at the 11 stations the files use*, so that each station is a plane of nodes. The P2 nodes are
  written as ``C3D10`` elements (corner nodes, then the mid-edge nodes 1-2, 2-3, 3-1, 1-4, 2-4, 3-4, each element
  oriented to a positive volume).
- **Attachments** (bearings, couplings, the joint to the reducer flange): the points the springs of ``calculix_rig``
  act on (the point on the axis, the ends of the tilt-spring arms at x ± d, a torsion arm) follow the attachment's face
  (a bearing's width or the attachment band, outer surface; an end face at a part's end: the faces of rvcoax's hybrid
  model, ``hybrid.attachments``) with **the tie the rig file gives it**, as rvcoax's hybrid model does: distributing
  (RBE3-like, every bearing and mount, and couplings and joints unless their location says ``tie = "rigid"``), written
  as ``*EQUATION`` lines, u_P = ū + θ × (x_P − x̄) with rvcoax's own operator (``fem.ties.distributing_tie_operator``,
  weights a sixth of each facet's area on each of its six nodes; each point is the dependent term of its own three
  equations and of no other, coefficients printed in at most 20 characters, the field width ccx reads); a rigid tie as
  a ``*RIGID BODY`` of the face and the points (RBE2-like). ``--ties rigid`` makes every face a rigid ring, as the deck
  did before issue 28's check: the rings stiffened every bearing seat over its width, which the rig file does not say,
  and made this model differ from rvcoax's by 3.7 % and 6.0 % of the signal (``benchmarks/RESULTS.md``).
- **Cost**: 26 k solid nodes on the reference rig; one ccx run (4 steps) 64 s CPU with the distributing ties (13 s with
  rigid rings: the equations couple each face's nodes densely).
- **Against rvcoax** (``--compare``, unmodified rig, 20 cases): 0.30 % (input) and 0.09 % (output shaft) RMS from the
  hybrid model, 1.5 % and 1.1 % from the beam model the workflow identifies with (Y_max within 1.6 %). With every face
  a rigid ring (``--ties rigid``) it is 3.7 % and 6.0 % from the hybrid model, and 0.25 % and 0.25 % from the hybrid
  model with every tie made rigid: the two codes agree when they model the same ties.
- **Loads** on a measured shaft (a hidden lateral load): nodal forces on the load's face (the attachment band around
  x, or its ``band_mm``) in proportion to the same area weights.
- **Read-out**: u_y at a station is the area-weighted mean u_y over the section's nodes (the plane x = station).
  rvcoax's hybrid model reads a ring of 8 probe points at mid-wall radius instead.

Hidden effects, out-of-vocabulary loads, pairs and the files themselves come from ``calculix_rig`` (``write_sets``,
``full_design``) with this solver in place of the beam deck; every ``ccx`` solve is cached under
``.blindcache/ccx_solid/`` (keyed by the deck's text), so the data can be made in pieces (``--max-solves``).

Usage::

    python benchmarks/calculix_solid.py --compare                 # the unmodified rig: ccx solid against rvcoax
    python benchmarks/calculix_solid.py --bench .blindcache/calculix_solid --max-solves 1   # repeat until done
    python benchmarks/calculix_solid.py --full DIR --max-solves 1   # calculix_rig's whole design (288 sets, 20 solves)
    python benchmarks/calculix_solid.py --out tests/results/studies/data/calculix_solid    # the committed files
    python benchmarks/bench_discrepancy_blind.py --source calculix_solid

Needs CalculiX's ``ccx`` (Debian: ``apt-get install calculix-ccx``).
"""

from __future__ import annotations

import argparse
import hashlib
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import blind_data  # noqa: E402
import calculix_rig  # noqa: E402

from rvcoax.geometry import MEASURED_SHAFTS  # noqa: E402
from rvcoax.geometry.meshing import SolidPartGeometry, mesh_part  # noqa: E402
from rvcoax.geometry.model.hybrid import FaceSpec, attachments, face_at  # noqa: E402
from rvcoax.geometry.model.loads import located_unit_loads  # noqa: E402
from rvcoax.geometry.schema import Rig  # noqa: E402
from rvcoax.loadcases.cases import paper_cases  # noqa: E402

MESH_MM = 6.0
CACHE = blind_data.CACHE / "ccx_solid"
# skfem's P2 tetrahedron: 4 vertex DOFs, then one per edge; CalculiX's C3D10 mid-edge nodes sit on these corner pairs
C3D10_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))


class SolidShaft:
    """One measured shaft as C3D10 elements: nodes (mm), elements, faces, couplings, station sections."""

    def __init__(self, rig: Rig, name: str, mesh_mm: float = MESH_MM, stations: int = blind_data.STATIONS):
        import skfem

        part = rig.part(name)
        self.name, self.part, self.rig = name, part, rig
        self.material = part.material
        faces = [a.face for a in attachments(rig, (name,)) if a.part == name]
        self._faces = {round(a.x_mm, 6): a.face for a in attachments(rig, (name,)) if a.part == name}
        self._ties = {round(a.x_mm, 6): a.tie for a in attachments(rig, (name,)) if a.part == name}
        for loads in located_unit_loads(rig).values():
            faces += [self.load_face(ld.x_mm, ld.band_mm) for ld in loads if ld.part == name]
        lo, hi = part.x_range_mm
        station_count, stations = stations, []
        for key in MEASURED_SHAFTS:
            path = getattr(rig.paths, key)
            if path.part == name:
                stations = list(np.linspace(path.x_start_mm, path.x_start_mm + path.length_mm, station_count))
        splits = {round(x, 6) for f in faces if f.kind == "band" for x in (f.x0_mm, f.x1_mm)}
        splits |= {round(x, 6) for x in stations}
        splits = tuple(sorted(x for x in splits if lo + 1e-3 < x < hi - 1e-3))
        segments = tuple((s.x_mm[0], s.x_mm[1], s.outer_diameter_mm, s.inner_diameter_mm)
                         for s in sorted(part.segments, key=lambda s: s.x_mm[0]))
        self.geometry = SolidPartGeometry(name, segments, splits, mesh_mm)
        mesh = mesh_part(self.geometry)
        basis = skfem.Basis(mesh, skfem.ElementTetP2())
        self.mesh = mesh
        self.nodes_mm = basis.doflocs.T * 1e3  # (N, 3)
        self.elements = self._c3d10(np.asarray(basis.element_dofs).T)
        self.straightened = self._straighten_inverted()
        self._midside = {}
        for e in self.elements:
            for k, (a, b) in enumerate(C3D10_EDGES):
                self._midside[(min(e[a], e[b]), max(e[a], e[b]))] = e[4 + k]

    def _c3d10(self, dofs: np.ndarray) -> np.ndarray:
        """skfem's P2 element DOFs (vertices, then edges in skfem's order) in C3D10 order, positive volume."""
        p = self.nodes_mm
        out = np.empty_like(dofs)
        out[:, :4] = dofs[:, :4]
        for k, (a, b) in enumerate(C3D10_EDGES):  # the edge DOF nearest the middle of corners a, b
            middle = 0.5 * (p[dofs[:, a]] + p[dofs[:, b]])
            distance = np.stack([np.linalg.norm(p[dofs[:, 4 + j]] - middle, axis=1) for j in range(6)], axis=1)
            out[:, 4 + k] = dofs[np.arange(len(dofs)), 4 + np.argmin(distance, axis=1)]
        c = p[out[:, :4]]
        volume = np.einsum("ij,ij->i", np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]), c[:, 3] - c[:, 0])
        flip = volume < 0  # swap corners 2 and 3 (0-based 1, 2): edges 1-2 ↔ 1-3 (4 ↔ 6), 2-4 ↔ 3-4 (8 ↔ 9)
        out[flip] = out[flip][:, [0, 2, 1, 3, 6, 5, 4, 7, 9, 8]]
        return out

    def _straighten_inverted(self) -> int:
        """Put the mid-edge nodes of every element whose Jacobian is not positive at one of CalculiX's 4 integration
        points (a coarse curved element on a small bore) on the straight edge; the number of elements so treated."""
        r, q = 0.1381966011250105, 0.5854101966249685
        gauss = ((r, r, r), (q, r, r), (r, q, r), (r, r, q))
        corners = np.array([[-1.0, -1.0, -1.0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
        gradients = []
        for point in gauss:
            L = (1.0 - sum(point), *point)
            rows = [(4 * L[i] - 1) * corners[i] for i in range(4)]
            rows += [4 * (L[i] * corners[j] + L[j] * corners[i]) for i, j in C3D10_EDGES]
            gradients.append(np.array(rows))
        treated = 0
        for _ in range(5):
            x = self.nodes_mm[self.elements]
            dets = np.stack([np.linalg.det(np.einsum("eni,nj->eij", x, g)) for g in gradients], axis=1)
            bad = np.flatnonzero(dets.min(axis=1) <= 1e-3 * np.abs(dets).mean(axis=1))
            if not bad.size:
                return treated
            treated += bad.size
            for k, (a, b) in enumerate(C3D10_EDGES):
                e = self.elements[bad]
                self.nodes_mm[e[:, 4 + k]] = 0.5 * (self.nodes_mm[e[:, a]] + self.nodes_mm[e[:, b]])
        raise InvertedElements(f"calculix_solid: inverted elements in '{self.name}' after straightening")

    def load_face(self, x_mm: float, band_mm=None) -> FaceSpec:
        lo, hi = self.part.x_range_mm
        if band_mm is None and (abs(x_mm - lo) < 1e-6 or abs(x_mm - hi) < 1e-6):
            return FaceSpec("end", x_mm, x_mm)
        return face_at(self.part, x_mm, self.rig.solid.attachment_band_mm, band_mm)

    def face(self, x_mm: float) -> FaceSpec:
        return self._faces.get(round(x_mm, 6)) or self.load_face(x_mm)

    def tie(self, x_mm: float) -> str:
        """The rig's tie of the attachment at ``x_mm``: ``distributing`` (bearings, mounts, and couplings and joints
        unless their location says ``tie = "rigid"``), as rvcoax's hybrid model reads it."""
        return self._ties.get(round(x_mm, 6), "distributing")

    def _triangles(self, facets: np.ndarray, every_node: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Node numbers (0-based) and consistent nodal areas (mm²) of quadratic triangles (corner indices): the
        mid-edge nodes carry a third of the area each; ``every_node``: a sixth on each of the six nodes (the weights
        of rvcoax's distributing tie, ``fem.ties.face_nodes``)."""
        p = self.nodes_mm
        area = 0.5 * np.linalg.norm(np.cross(p[facets[:, 1]] - p[facets[:, 0]], p[facets[:, 2]] - p[facets[:, 0]]),
                                    axis=1)
        nodes, weights = [], []
        for (a, b) in ((0, 1), (1, 2), (0, 2)):
            nodes += [self._midside[(min(u, v), max(u, v))] for u, v in zip(facets[:, a], facets[:, b])]
            weights.append(area / (6.0 if every_node else 3.0))
        if every_node:
            for a in range(3):
                nodes += list(facets[:, a])
                weights.append(area / 6.0)
        nodes = np.array(nodes)
        weights = np.concatenate(weights)
        unique, inverse = np.unique(nodes, return_inverse=True)
        return unique, np.bincount(inverse, weights)

    def face_nodes(self, face: FaceSpec, every_node: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """The nodes of ``face`` (0-based) and their area weights (mm², see :meth:`_triangles`)."""
        mesh = self.mesh
        boundary = mesh.boundary_facets()
        corners = mesh.facets[:, boundary].T  # vertex numbers are the first DOFs of the P2 basis
        p = self.nodes_mm[corners]  # (n, 3 corners, 3)
        normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        x = p[..., 0]
        if face.kind == "end":
            keep = (np.abs(normal[:, 0]) > 0.99) & (np.abs(x - face.x0_mm).max(axis=1) < 1e-3)
        else:
            radius = np.hypot(p[..., 1], p[..., 2]).mean(axis=1)
            outer, inner = self._radii(x.mean(axis=1))
            side = radius > 0.5 * (outer + inner) if face.surface == "outer" else radius < 0.5 * (outer + inner)
            keep = ((x >= face.x0_mm - 1e-3).all(axis=1) & (x <= face.x1_mm + 1e-3).all(axis=1)
                    & (np.abs(normal[:, 0]) < 0.5) & side)
        if not keep.any():
            raise ValueError(f"calculix_solid: no facets of '{self.name}' on {face}")
        return self._triangles(corners[keep], every_node)

    def _radii(self, x_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        outer, inner = np.zeros_like(x_mm), np.zeros_like(x_mm)
        for x0, x1, d_out, d_in in self.geometry.segments:
            here = (x_mm >= x0 - 1e-6) & (x_mm <= x1 + 1e-6)
            outer = np.where(here, np.maximum(outer, d_out / 2), outer)
            inner = np.where(here & (inner == 0), d_in / 2, inner)
        return outer, inner

    def section(self, x_mm: float) -> tuple[np.ndarray, np.ndarray]:
        """The nodes of the plane x = ``x_mm`` (a split plane or an end face) and their area weights."""
        mesh = self.mesh
        corners = mesh.facets.T
        on = (np.abs(self.nodes_mm[corners, 0] - x_mm) < 1e-4).all(axis=1)
        if not on.any():
            raise ValueError(f"calculix_solid: no plane of nodes at x = {x_mm} mm in '{self.name}'")
        return self._triangles(corners[on])


def solid_shaft(rig: Rig, name: str, mesh_mm: float = MESH_MM) -> SolidShaft:
    """The shaft meshed at ``mesh_mm``, or finer (2/3, 1/2 of it) where a coarse curved element is inverted in
    CalculiX's integration points even with straightened edges (the reference input shaft's Ø8 bore at 6 mm)."""
    for size in (mesh_mm, 2 * mesh_mm / 3, mesh_mm / 2):
        try:
            return SolidShaft(rig, name, size)
        except InvertedElements:
            continue
    raise ValueError(f"calculix_solid: '{name}' has inverted elements at every mesh size down to {mesh_mm / 2:g} mm")


class InvertedElements(ValueError):
    pass


@dataclass
class Solver:
    """``calculix_rig.solve_units`` with the measured shafts as C3D10 solids, cached per deck."""

    mesh_mm: float = MESH_MM
    solves: int = 0  # ccx runs made (not read from the cache)
    max_solves: int | None = None
    ties: str = "rig"  # "rig": the rig file's ties (distributing unless it says rigid); "rigid": every face a ring

    def __call__(self, rig: Rig, work: Path | None = None, element_mm: float = calculix_rig.ELEMENT_MM):
        shafts = {getattr(rig.paths, k).part: solid_shaft(rig, getattr(rig.paths, k).part, self.mesh_mm)
                  for k in MEASURED_SHAFTS}
        deck = calculix_rig.build_deck(rig, element_mm, solids=shafts, read_stations=blind_data.STATIONS,
                                     solid_ties=self.ties)
        key = hashlib.sha1(deck.text.encode()).hexdigest()[:20]
        path = CACHE / f"{key}.npz"
        if path.exists():
            stored = np.load(path)
            units = {step: {k: stored[f"{step}_{k}"] for k in MEASURED_SHAFTS} for step in calculix_rig.STEPS}
            return units, deck
        if self.max_solves is not None and self.solves >= self.max_solves:
            raise SolveBudget(f"{self.solves} ccx solves made; run again to go on (each is cached)")
        start = time.process_time()
        units = calculix_rig.run_deck(deck, work)
        self.solves += 1
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez(path.with_suffix(".tmp.npz"), **{f"{s}_{k}": units[s][k] for s in units for k in units[s]})
        path.with_suffix(".tmp.npz").replace(path)
        print(f"  ccx solid solve: {len(deck.text) / 1e6:.1f} MB deck, {time.process_time() - start:.1f} s CPU here "
              f"(ccx itself: {calculix_rig.LAST_RUN.get('cpu_s', float('nan')):.1f} s CPU)", flush=True)
        return units, deck


class SolveBudget(RuntimeError):
    pass


def compare(solver: Solver, log=print) -> dict:
    """The unmodified reference rig, paper 000's 20 cases, 11 stations per shaft: ccx solid shafts against rvcoax's
    hybrid model (solid shafts too), rvcoax's beam model (Timoshenko) and the CalculiX beam deck."""
    from rvcoax.results.sweep import SweepSettings

    cases = (blind_data.REST, *paper_cases())
    rig = calculix_rig.truth_rig()
    units, deck = solver(rig)
    sizes = [len(deck.sections[k]) for k in MEASURED_SHAFTS]
    ccx = calculix_rig.case_paths(units, cases).reshape(len(cases), -1)[1:]
    ccx_beam_units, _ = calculix_rig.solve_units(rig)
    ccx_beam = calculix_rig.case_paths(ccx_beam_units, cases).reshape(len(cases), -1)[1:]
    references = {
        "rvcoax hybrid": blind_data.absolute_paths(rig, SweepSettings(model="hybrid"), cases=cases, log=log)[0],
        "rvcoax beam (Timoshenko)": blind_data.absolute_paths(calculix_rig.identification_rig(), SweepSettings(),
                                                              cases=cases, log=log)[0],
        "ccx beam (B32R)": None,
    }
    out = {}
    for label, paths in references.items():
        other = ccx_beam if paths is None else paths.reshape(len(cases), -1)[1:]
        full = other.shape[1] // 2  # 41 stations per shaft; the solid deck reads every 4th (11)
        other = np.hstack([other[:, k * full:(k + 1) * full][:, ::(full - 1) // (sizes[k] - 1)] for k in range(2)])
        for key, (rel, worst) in calculix_rig.path_differences(ccx, other, sizes).items():
            out[f"{label} {key}"] = {"rms_relative": rel, "ymax_relative_worst": worst}
            log(f"ccx solid vs {label:26s} {key:6s}: RMS difference {100 * rel:.2f} % of the signal, Y_max worst "
                f"{100 * worst:+.2f} %")
    return out


# the committed files: calculix_rig's small set (7 cases, 6 stations) but for the effects that cost a ccx solve each
COMMITTED_HIDDEN = {k: calculix_rig.HIDDEN[k] for k in ("torque_reaction@output_bearing_block", "mesh_force@reducer_input")}


def committed_sets() -> list[tuple]:
    return [(name, truth, calculix_rig.committed_load(oov), schema, noise, notation, "aligned_at_rest", seed)
            for seed, (name, truth, oov, schema, noise, notation) in enumerate(calculix_rig.SETS)
            if set(truth) <= set(COMMITTED_HIDDEN)]


def bench_design() -> list[tuple]:
    """The benchmark set these solves afford: ``calculix_rig.full_design`` (both datums and schemas, 1 % and 5 %
    noise, 20 cases, 11 stations) restricted to the committed effects, the load outside the vocabulary at x = 485 mm
    and no effect, and the two effects at twice their bound (72 files from four ccx solves)."""
    return [row for row in calculix_rig.full_design()
            if (len(row[1]) == 1 and set(row[1]) <= set(COMMITTED_HIDDEN)) or row[2] == calculix_rig.OOV
            or (not row[1] and not row[2])]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--compare", action="store_true", help="compare with rvcoax on the unmodified rig")
    parser.add_argument("--out", default="", help="write the small committed set (10 files) to this folder")
    parser.add_argument("--bench", default="", help="write the benchmark set of the committed effects (72 files)")
    parser.add_argument("--full", default="", help="write calculix_rig's whole benchmark design (288 files; 20 solves)")
    parser.add_argument("--max-solves", type=int, default=None, help="stop after this many new ccx solves")
    parser.add_argument("--mesh-mm", type=float, default=MESH_MM)
    parser.add_argument("--ties", choices=("rig", "rigid"), default="rig",
                        help="faces of the solid shafts: as the rig file says (default: distributing, RBE3-like, unless "
                             "a location says tie = \"rigid\") or every one a rigid ring (the data before issue 28)")
    parser.add_argument("--keep", default="", help="keep the unmodified rig's deck and ccx output here")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    calculix_rig.require_ccx()
    solver = Solver(args.mesh_mm, max_solves=args.max_solves, ties=args.ties)
    try:
        if args.keep:
            solver(calculix_rig.truth_rig(), Path(args.keep))
        if args.compare:
            figures = compare(solver)
            if not args.no_record:
                from machine import record
                rows = [(f"ccx solid shafts against {name}: RMS difference / RMS signal, Y_max worst of 20 cases",
                         f"{100 * v['rms_relative']:.2f} %, {100 * v['ymax_relative_worst']:+.2f} %")
                        for name, v in figures.items()]
                rows.append(("load average (1, 5, 15 min)", ", ".join(f"{v:.2f}" for v in os.getloadavg())))
                record("CalculiX solid (C3D10) measured shafts against rvcoax on the reference rig "
                       "(benchmarks/calculix_solid.py --compare)", rows)
        if args.out:
            calculix_rig.write_sets(Path(args.out), committed_sets(), COMMITTED_HIDDEN, solve_with=solver, model=MODEL)
        if args.bench:
            calculix_rig.write_sets(Path(args.bench), bench_design(), COMMITTED_HIDDEN,
                                    {calculix_rig.OOV: ("proportional", calculix_rig.OOV_X_MM)}, tuple(range(20)),
                                    blind_data.STATIONS, solve_with=solver, model=MODEL)
        if args.full:
            calculix_rig.write_sets(Path(args.full), calculix_rig.full_design(), calculix_rig.FULL_HIDDEN,
                                    calculix_rig.FULL_LOADS, tuple(range(20)), blind_data.STATIONS, solve_with=solver,
                                    model=MODEL)
    except SolveBudget as stop:
        print(f"stopped: {stop}")
        raise SystemExit(3) from None


MODEL = (f"CalculiX ccx: the measured shafts as C3D10 tetrahedra ({MESH_MM:g} mm, rvcoax's gmsh meshing, a plane of "
         "nodes at every station, Y the section's area-weighted mean), attachments tied to their faces as the rig "
         "says (distributing *EQUATION ties, rigid *RIGID BODY where the rig says tie = rigid); the rest B32R "
         "beams and SPRING1/SPRING2 springs as calculix_rig.py; "
         "reference rig, self-weight off; see benchmarks/calculix_solid.py")


if __name__ == "__main__":
    main()
