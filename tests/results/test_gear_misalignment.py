"""Gear-mesh misalignment in gear terms (issue 25 item 5, second part): f_Σβ and f_Σδ of each planet mesh."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.geometry.variants import reference_from_geometry
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.engineering import mesh_misalignment
from rvcoax.results.sweep import run_sweep


def test_projection_on_the_plane_of_action_by_hand():
    """A gear tilted 100 µrad about z (its axis turns towards +y, d = (1e-4, 0)) meshing with a planet at φ = 90°
    (e = +z, t = x × e = −y): the line of action l = −cos α t − sin α e = (cos α, −sin α), so over b = 10 mm
    f_Σβ = b 1e-4 cos 20° = 0.9397 µm and, normal to the plane of action (m = (sin α, cos α)), f_Σδ = 0.3420 µm.
    A planet on the y axis (φ = 0) sees the same tilt normal to its plane of action instead."""
    alpha = math.radians(20.0)
    beta, delta = mesh_misalignment((0.0, 1e-4), (0.0, 0.0), 90.0, alpha, 10.0)
    assert beta == pytest.approx(10.0 * 1e-4 * math.cos(alpha) * 1e3, rel=1e-12)
    assert delta == pytest.approx(10.0 * 1e-4 * math.sin(alpha) * 1e3, rel=1e-12)
    beta0, delta0 = mesh_misalignment((0.0, 1e-4), (0.0, 0.0), 0.0, alpha, 10.0)
    assert (beta0, delta0) == pytest.approx((delta, beta), rel=1e-12)
    # only the relative rotation counts, and the length of the tilt is shared by the two parts
    assert mesh_misalignment((3e-5, 1e-4), (3e-5, 0.0), 90.0, alpha, 10.0) == pytest.approx((beta, delta))
    b, d = mesh_misalignment((2e-5, 7e-5), (0.0, 0.0), 33.0, alpha, 10.0)
    assert math.hypot(b, d) == pytest.approx(10.0 * math.hypot(2e-5, 7e-5) * 1e3, rel=1e-12)


def test_every_planet_mesh_of_the_reference_stage_per_case():
    rig = reference_from_geometry(("gears",))
    sweep = run_sweep(rig, (LoadCase(1.43, 200.0),))
    case = sweep.cases[0]
    meshes = case.engineering.gear_meshes
    assert [m.planet_angle_deg for m in meshes] == [90.0, 270.0]
    # the members' section rotations at the mesh, read from the solution by hand
    frame = sweep.frame
    mesh = rig.gear_meshes[0]
    u = sweep.case_displacements[:, 0] if sweep.case_displacements is not None else None
    if u is None:  # linear sweeps keep unit responses: rebuild this case's measured displacement
        from rvcoax.geometry.model.loads import case_weights

        weights = case_weights(1.43, 200.0, include_rest=False)
        u = sum(w * sweep.unit_displacements[:, i] for i, w in enumerate(weights.values()))
    on, mate = frame.node(mesh.on.part, mesh.on.x_mm), frame.node(mesh.reacted_on.part, mesh.reacted_on.x_mm)
    rotation = np.array([u[DOFS_PER_NODE * on + k] - u[DOFS_PER_NODE * mate + k] for k in (4, 5)])
    assert meshes[0].relative_tilt_urad == pytest.approx(np.hypot(*rotation) * 1e6, rel=1e-6)
    assert meshes[0].f_sigma_beta_um > 0.0
    assert math.hypot(meshes[0].f_sigma_beta_um, meshes[0].f_sigma_delta_um) == pytest.approx(
        mesh.face_width_mm * np.hypot(*rotation) * 1e3, rel=1e-6)
    row = case.engineering.row()
    assert row["gear_input_gear_mesh_planet0_f_sigma_beta_um"] == meshes[0].f_sigma_beta_um


def test_section_rotations_in_the_path_rows():
    """sweep_paths.csv carries the section rotation about z at every station: the slope of the bending line."""
    from rvcoax.geometry.rigfile import load_rig
    from rvcoax.results.io.records import case_entry, entry_path_rows

    sweep = run_sweep(load_rig(), (LoadCase(1.43, 200.0),))
    rows = [r for r in entry_path_rows(case_entry(sweep.cases[0])) if r["shaft"] == "output"]
    path = sweep.cases[0].paths["output"]
    assert [r["rotation_z_urad"] for r in rows] == pytest.approx(list(path.rotation_z_rad * 1e6))
    # a beam's rotation about z is its slope du_y/dx less the shear angle (Timoshenko): equal where no shear force
    # acts (the overhang beyond the last bearing), within the shear angle (≤ 15 % here, next to the flange) elsewhere
    station, uy = np.array([r["station_mm"] for r in rows]), np.array([r["uy_mm"] for r in rows])
    slope = np.gradient(uy, station) * 1e6  # mm/mm → µrad
    rotation = path.rotation_z_rad * 1e6
    assert slope[-3:] == pytest.approx(rotation[-3:], rel=1e-6)
    assert np.max(np.abs(slope[1:-1] - rotation[1:-1])) < 0.15 * np.max(np.abs(slope))
