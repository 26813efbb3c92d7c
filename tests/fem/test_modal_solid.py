"""The P2 solid's mass and modes: mass sums, a slender bar's bending frequency against the Timoshenko beam, and
CalculiX's *FREQUENCY on the same mesh (C3D10, the same nodes)."""

from __future__ import annotations

import math
import shutil
import subprocess

import numpy as np
import pytest
from timoshenko_closed_forms import Section, frequencies_hz

from rvcoax.fem import solid
from rvcoax.fem.constraints import elimination_matrix
from rvcoax.fem.modal import natural_modes
from rvcoax.geometry.meshing import SolidPartGeometry, mesh_part

E, NU, RHO = 2.1e11, 0.3, 7850.0
L_MM, D_MM = 200.0, 20.0

pytestmark = [pytest.mark.slow, pytest.mark.subprocess]  # CalculiX runs as a process of its own


@pytest.fixture(scope="module")
def bar(tmp_path_factory):
    mesh = mesh_part(SolidPartGeometry("bar", ((0.0, L_MM, D_MM, 0.0),), (), 4.0),
                     cache_dir=tmp_path_factory.mktemp("mesh"))
    basis = solid.solid_basis(mesh)
    k = solid.stiffness_matrix(basis, E, NU)
    m = solid.mass_matrix(basis, RHO)
    coordinates, dofs = solid.dof_locations(basis)
    clamped = np.flatnonzero(coordinates[:, 0] < 1e-9)
    t, _ = elimination_matrix(basis.N, dofs[clamped].ravel(), {})
    return basis, k, m, t, coordinates, dofs, clamped


def test_solid_mass_sums_to_rho_times_volume(bar):
    basis, _, m, *_ = bar
    volume = float(basis.mesh.p.shape[1] and solid.mass_matrix(basis, 1.0).sum() / 3.0)
    nominal = math.pi / 4 * (D_MM * 1e-3) ** 2 * L_MM * 1e-3
    for c in range(3):
        unit = np.zeros(basis.N)
        unit[c::3] = 1.0
        assert unit @ m @ unit == pytest.approx(RHO * volume, rel=1e-12)  # each direction carries the whole mass
    assert volume == pytest.approx(nominal, rel=2e-3)  # the curved P2 mesh holds the cylinder's volume
    assert abs(m - m.T).max() <= 1e-14 * abs(m).max()


def test_slender_solid_bar_bends_as_the_timoshenko_beam(bar):
    """Clamped–free, L/D = 10: the lowest bending pair of the P2 solid against the beam's differential equations
    (κ of a solid circle, Cowper). The clamp is stiffer than a beam's (no warping of the end face): ~0.5 %."""
    basis, k, m, t, *_ = bar
    modes = natural_modes(k, m, t, 4)
    g = E / (2 * (1 + NU))
    d = D_MM * 1e-3
    section = Section(L_MM * 1e-3, E, g, RHO, math.pi * d**2 / 4, math.pi * d**4 / 64, 6 * (1 + NU) / (7 + 6 * NU))
    exact = frequencies_hz(section, ((math.inf, math.inf), (0, 0)), 1, 3000)[0]
    bending = modes.frequencies_hz[:2]
    assert bending[1] == pytest.approx(bending[0], rel=1e-3)  # the y and z pair
    print("solid", bending, "beam", exact)
    assert bending[0] == pytest.approx(exact, rel=0.01)


def _write_inp(path, coordinates, connectivity, clamped_nodes, n_modes):
    lines = ["*NODE, NSET=NALL"]
    lines += [f"{i + 1}, {x:.12e}, {y:.12e}, {z:.12e}" for i, (x, y, z) in enumerate(coordinates)]
    lines.append("*ELEMENT, TYPE=C3D10, ELSET=EALL")
    lines += [f"{e + 1}, " + ", ".join(str(int(n) + 1) for n in row) for e, row in enumerate(connectivity)]
    lines.append("*NSET, NSET=FIXED")
    lines += [", ".join(str(int(n) + 1) for n in clamped_nodes[i:i + 8]) for i in range(0, len(clamped_nodes), 8)]
    lines += ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{E:.6e}, {NU}", "*DENSITY", f"{RHO}",
              "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL", "*BOUNDARY", "FIXED, 1, 3",
              "*STEP", "*FREQUENCY", f"{n_modes}", "*END STEP"]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def _read_frequencies(dat: str) -> np.ndarray:
    rows, reading = [], False
    for line in dat.splitlines():
        if "E I G E N V A L U E   O U T P U T" in line:
            reading = True
            continue
        if reading:
            parts = line.split()
            if len(parts) == 5 and parts[0].isdigit():
                rows.append(float(parts[3]))  # CYCLES/TIME
            elif rows and not parts:
                break
    return np.array(rows)


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX's ccx is not installed (apt-get install calculix-ccx)")
def test_calculix_frequency_on_the_same_mesh(bar, tmp_path):
    basis, k, m, t, coordinates, dofs, clamped = bar
    nodes = (basis.element_dofs[0::3] // 3).T.astype(np.int64)
    points = coordinates
    corners = points[nodes[:, :4]]
    volume = np.einsum("ij,ij->i", np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]),
                       corners[:, 3] - corners[:, 0])
    swap = np.array([0, 2, 1, 3, 6, 5, 4, 7, 9, 8])  # corners 2 and 3 exchanged (a negatively oriented tet)
    nodes[volume < 0] = nodes[volume < 0][:, swap]
    _write_inp(tmp_path / "bar.inp", points, nodes, clamped, 6)
    run = subprocess.run(["ccx", "bar"], cwd=tmp_path, capture_output=True, text=True, timeout=600,
                         env={"OMP_NUM_THREADS": "2", "PATH": "/usr/bin:/bin"})
    assert run.returncode == 0, run.stdout[-2000:]
    ccx = _read_frequencies((tmp_path / "bar.dat").read_text())
    ours = natural_modes(k, m, t, 6).frequencies_hz
    assert ccx.size == 6
    print("rvcoax P2", ours, "ccx C3D10", ccx, "max rel", np.max(np.abs(ours / ccx - 1)))
    assert np.allclose(ours, ccx, rtol=0.005), (ours, ccx)
