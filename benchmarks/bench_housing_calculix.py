"""CalculiX (ccx) against rvcoax on the pedestal and the bracket of issue 16: the same mesh, feet and load.

Each shape (the web pedestal and the wall bracket of tests/geometry/test_housing_shapes.py, Ø35 bore,
four 25 mm bolt feet) is meshed once by rvcoax (gmsh, curved P2 tetrahedra). Both codes then solve the
full solid model on that mesh:

- the bolt feet clamped: every P2 node of the foot facets held in x, y, z (rvcoax's ``feet = "clamped"``
  selection, :func:`rvcoax.geometry.housings.foot_facets`);
- a bearing load on the first seat: a uniform traction over the bore band 0 … 12 mm of total force
  (0, −2000, 500) N, as rvcoax's consistent nodal forces, written to ccx as ``*CLOAD`` (identical loads);
- CalculiX: C3D10 elements (the node order checked by bench_calculix.py's C3D10 Jacobians and volume),
  ``*STATIC``, displacements of the band's nodes from the ``.dat`` file.

Printed and recorded: DOFs, the mean displacement of the band (µm) from each code, and the largest
node-by-node difference relative to the largest displacement. This checks the new geometry (the
fragmented boxes, the bolt feet, the bore bands) and rvcoax's P2 solid against an element
implementation it did not write. Run: ``.venv/bin/python benchmarks/bench_housing_calculix.py
[--mesh-mm 10]``; needs ``ccx`` (exit status 2 without it).
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_calculix import abaqus_connectivity, read_dat_displacements, run_ccx, write_inp  # noqa: E402
from bench_solid_scaling import POISSON, YOUNGS_PA  # noqa: E402
from machine import record  # noqa: E402

AGREEMENT = 1e-3  # relative agreement of the band's mean displacement required for PASS
BAND_FORCE_N = (0.0, -2000.0, 500.0)


def shapes(size_mm: float) -> dict:
    from rvcoax.geometry.housings import BracketGeometry, PedestalGeometry

    seat = dict(x_mm=(0.0, 60.0), width_mm=70.0, top_mm=35.0, bore_diameter_mm=35.0, split_x_mm=(12.0, 48.0),
                mesh_size_mm=size_mm, foot_pad_mm=25.0)
    return {
        "web pedestal": PedestalGeometry(name="pedestal", seat_bottom_mm=-30.0, bottom_mm=-110.0, web_length_mm=60.0,
                                         web_width_mm=25.0, base_length_mm=100.0, base_width_mm=120.0,
                                         base_thickness_mm=12.0, **seat),
        "wall bracket": BracketGeometry(name="bracket", seat_bottom_mm=-35.0, wall_z_mm=-110.0, arm_length_mm=60.0,
                                        arm_height_mm=40.0, plate_length_mm=100.0, plate_height_mm=110.0,
                                        plate_thickness_mm=12.0, **seat),
    }


def compare(label: str, geometry, cache: Path, keep: Path | None) -> tuple[list[tuple[str, str]], bool]:
    from skfem.quadrature import get_quadrature
    from skfem.refdom import RefTet

    from rvcoax.fem import solid
    from rvcoax.fem.system import prepare_system
    from rvcoax.fem.ties import face_nodes
    from rvcoax.geometry.housings import foot_facets, housing_faces
    from rvcoax.geometry.model.condensed_housing import build_housing_model, solid_method

    model = build_housing_model(geometry, YOUNGS_PA, POISSON, [], "clamped", cache_dir=cache)
    mesh, basis = model.mesh, model.basis
    coordinates, dofs = solid.dof_locations(basis)
    connectivity, flipped, volume = abaqus_connectivity(basis, get_quadrature(RefTet, 2))
    if abs(volume - float(basis.dx.sum())) > 1e-9 * volume:
        raise RuntimeError("C3D10 volume differs from scikit-fem's: wrong node order")
    feet = np.concatenate(foot_facets(mesh, geometry))
    fixed = np.unique(face_nodes(mesh, basis, feet).dofs[:, 0] // 3)
    band = housing_faces(mesh, geometry, ("bore", 0.0, 12.0))
    band_nodes = np.unique(face_nodes(mesh, basis, band).dofs[:, 0] // 3)
    force = solid.force_traction_vector(mesh, band, BAND_FORCE_N)
    ours = prepare_system(model.stiffness, model.elimination, solid_method(), symmetrize=True).solve(force)
    ours_band = ours[dofs[band_nodes]]

    work = Path(tempfile.mkdtemp(prefix="rvcoax-housing-ccx-"))
    try:
        write_inp(work / "housing.inp", coordinates, connectivity, fixed, band_nodes, force[dofs])
        run = run_ccx(work, "housing")
        table = read_dat_displacements(work / "housing.dat")
        ccx_band = np.array([table[int(node) + 1] for node in band_nodes])
    finally:
        if keep is not None:
            shutil.copytree(work, keep / label.replace(" ", "_"), dirs_exist_ok=True)
        shutil.rmtree(work, ignore_errors=True)
    mean_ours, mean_ccx = ours_band.mean(axis=0), ccx_band.mean(axis=0)
    relative = float(np.abs(mean_ours - mean_ccx).max() / np.abs(mean_ccx).max())
    nodewise = float(np.abs(ours_band - ccx_band).max() / np.abs(ccx_band).max())
    verdict = relative <= AGREEMENT
    line = (f"{basis.N} DOFs ({flipped} tets re-oriented), {fixed.size} clamped nodes; band mean u (µm): rvcoax "
            + ", ".join(f"{1e6 * v:.4f}" for v in mean_ours) + "; ccx " + ", ".join(f"{1e6 * v:.4f}" for v in mean_ccx)
            + f"; differ by {relative:.1e} of the largest (node by node {nodewise:.1e}); ccx {run['run_seconds']:.1f} s, "
            f"{run['peak_mb']:.0f} MB: {'PASS' if verdict else 'FAIL'}")
    print(f"{label}: {line}")
    return [(f"{label}, mesh {geometry.mesh_size_mm:g} mm, clamped feet, {BAND_FORCE_N} N on a bore band", line)], verdict


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh-mm", type=float, default=10.0)
    parser.add_argument("--keep", type=Path, default=None, help="keep the .inp/.dat files here")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    if shutil.which("ccx") is None:
        print("ccx (CalculiX) is not installed: apt-get install calculix-ccx", file=sys.stderr)
        raise SystemExit(2)
    load = os.getloadavg()
    rows, passed = [], True
    with tempfile.TemporaryDirectory() as cache:
        for label, geometry in shapes(args.mesh_mm).items():
            shape_rows, verdict = compare(label, geometry, Path(cache), args.keep)
            rows += shape_rows
            passed &= verdict
    rows.append(("load average at start / end (1, 5, 15 min)",
                 " / ".join(", ".join(f"{v:.2f}" for v in values) for values in (load, os.getloadavg()))))
    if not args.no_record:
        record("bench_housing_calculix.py: pedestal and bracket, rvcoax against CalculiX on the same mesh", rows)
    raise SystemExit(0 if passed else 1)


if __name__ == "__main__":
    main()
