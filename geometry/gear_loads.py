"""The forces a rig's gear meshes put on their driving gears, and the torque below which a planet mesh opens.

Rig physics from the ``[[gear_meshes]]`` of a rig file and the stage formulas of :mod:`rvcoax.geometry.gears`;
the model turns them into unit loads (:mod:`rvcoax.geometry.model.loads`) and the plausibility check warns
where the sweep interpolates a mesh's contact loss (:mod:`rvcoax.geometry.catalogue`).
"""

from __future__ import annotations

import numpy as np

from rvcoax.geometry.gears import full_contact_force, load_sharing, mesh_forces, single_stiffness
from rvcoax.geometry.schema import GearMesh, Rig

__all__ = ["gear_contact_torques", "gear_mesh_forces", "gear_mesh_full_contact_torque"]


def gear_mesh_forces(rig: Rig, mesh: GearMesh):
    """The mesh forces on the driving gear of ``mesh`` (:class:`rvcoax.geometry.gears.MeshForces`).

    Parameters
    ----------
    rig : Rig
        The rig, for the torque paths and positions the mesh refers to.
    mesh : GearMesh
        One of its ``gear_meshes``, with the gear data (module, teeth, width, position errors).

    Returns
    -------
    per_torque, engaged : MeshForces
        ``per_torque``: for 1 N·m of the mesh's torque (times its sign); ``engaged``: the part present
        whenever torque flows, from the position errors (sign of the torque).
    stiffness_N_per_m : ndarray
        Each mesh's stiffness along its line of action.

    The split is the all-meshes-in-contact one (:func:`rvcoax.geometry.gears.load_sharing`), linear in the
    torque. Below :func:`gear_mesh_full_contact_torque` T_c a mesh opens: the true loads
    (:func:`rvcoax.geometry.gears.contact_loads`) are then the straight line from no load at T = 0 to the
    split at T_c whenever the position errors take at most two values (two planets always), which the
    sweep reproduces by weighting ``engaged`` with clip(T / T_c, −1, 1) (:func:`gear_contact_weight`);
    with more values it is a polyline and that weight interpolates it (a warning says so before a solve).
    """
    stage = mesh.stage
    if mesh.mesh_stiffness_N_per_mm_per_um is not None:
        per_width = mesh.mesh_stiffness_N_per_mm_per_um
    else:
        sun = rig.materials[rig.part(mesh.on.part).material]
        planet = rig.materials[mesh.planet_material] if mesh.planet_material is not None else sun
        per_width = single_stiffness(stage, mesh.blank_factor,
                                     (sun.youngs_modulus_MPa * 1e6, planet.youngs_modulus_MPa * 1e6)).mesh
    stiffness = per_width * mesh.face_width_mm * 1e6 * np.asarray(mesh.planet_stiffness_factors)  # N/(mm·µm)·mm → N/m
    share, constant = load_sharing(stiffness, np.asarray(mesh.planet_position_errors_um) * 1e-6)
    sign = float(getattr(rig.torques, mesh.torque).sign)
    per_torque = mesh_forces(stage, mesh.planet_angles_deg, sign * share / (stage.base_radius_mm(0) * 1e-3))
    return per_torque, mesh_forces(stage, mesh.planet_angles_deg, sign * constant), stiffness


def gear_mesh_full_contact_torque(rig: Rig, mesh: GearMesh) -> float:
    """|T| (N·m) below which a planet mesh of ``mesh`` opens (0 when the position errors are equal)."""
    _, _, stiffness = gear_mesh_forces(rig, mesh)
    share, constant = load_sharing(stiffness, np.asarray(mesh.planet_position_errors_um) * 1e-6)
    return full_contact_force(share, constant) * mesh.stage.base_radius_mm(0) * 1e-3


def gear_contact_torques(rig: Rig) -> tuple[float, float]:
    """Per torque, the full-contact torque of the rig's gear stages: below it a planet mesh is open.

    Parameters
    ----------
    rig : Rig
        The rig, with its ``[[gear_meshes]]`` (none: no contact loss).

    Returns
    -------
    (float, float)
        (T_c1, T_c2) in N·m: for each of T1 and T2 the largest |T| below which a mesh of a stage it drives
        opens (:func:`gear_mesh_full_contact_torque`; 0 without stages or with equal position errors).
        :func:`rvcoax.geometry.model.loads.case_weights` scales the stages' constant force by clip(T / T_c, −1, 1).
    """
    out = {"T1": 0.0, "T2": 0.0}
    for mesh in rig.gear_meshes:
        out[mesh.torque] = max(out[mesh.torque], gear_mesh_full_contact_torque(rig, mesh))
    return out["T1"], out["T2"]
