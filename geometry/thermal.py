"""Steady temperature rises (``[thermal]``) → free thermal growth of parts, supports and the bed.

A part ΔT warmer than when the rig was aligned grows by the strain ε = α ΔT in every direction
(α: its material's ``thermal_expansion_per_K``). In the rig model this is an **initial strain**:

* beams (the line model): the equivalent nodal forces ∓ E A ε of each element, which lengthen a free
  element by ε L exactly (:func:`beam_thermal_load`);
* solid parts (hybrid and solid models): ∫ (3λ + 2μ) ε div v dV (:func:`rvcoax.fem.solid.thermal_strain_vector`);
* radial growth, Δd = ε d of every diameter (:func:`radial_growth_um`): a round part grows about its
  own axis, which therefore does not move; it changes fits and bearing clearances, reported, not
  applied;
* supports: a mount of height h (``height_above_bed_mm``, axis above the bed) whose support is ΔT_s
  warmer lifts its part by α_s ΔT_s h; the bed grows along x from its fixed point by α_bed ΔT_bed;
* springs whose two nodes are at different x (a coupling's hubs) are free of load at the spacing grown
  with the two parts they join, so that a uniformly warmer rig is stress-free.

All of it enters as the stress-free motions of the springs and the initial-strain load, i.e. in the
``prestrain`` unit load (a state of the rig at rest, like ``vertical_offset_um``, which these lifts
replace).
"""

from __future__ import annotations

import numpy as np

from rvcoax.geometry.schema import Rig

__all__ = ["beam_thermal_load", "bed_growth_mm", "free_axial_growth_um", "mount_lift_um", "part_strain",
           "radial_growth_um", "thermal_stress_free_motions"]


def _alpha(rig: Rig, material: str) -> float:
    value = rig.materials[material].thermal_expansion_per_K
    return 0.0 if value is None else float(value)


def part_strain(rig: Rig, part: str) -> float:
    """Free thermal strain α ΔT of ``part`` (0 without ``[thermal]`` or a rise for it)."""
    if rig.thermal is None:
        return 0.0
    rise = rig.thermal.temperature_rise_K.get(part, 0.0)
    return _alpha(rig, rig.part(part).material) * rise if rise else 0.0


def free_axial_growth_um(rig: Rig, part: str) -> float:
    """Free axial growth of ``part`` over its length, ε L (µm).

    Parameters
    ----------
    rig : Rig
        A validated rig with a ``[thermal]`` table (or none: no growth).
    part : str
        The part's name.

    Returns
    -------
    float
        The growth in µm.
    """
    lo, hi = rig.part(part).x_range_mm
    return part_strain(rig, part) * (hi - lo) * 1e3


def radial_growth_um(rig: Rig) -> dict[str, list[tuple[float, float]]]:
    """Growth of the (outer, inner) diameter of every segment of every part, ε d (µm)."""
    return {p.name: [(part_strain(rig, p.name) * s.outer_diameter_mm * 1e3,
                      part_strain(rig, p.name) * s.inner_diameter_mm * 1e3) for s in p.segments] for p in rig.parts}


def mount_lift_um(rig: Rig, mount) -> float:
    """Vertical lift of ``mount``'s support, α_s ΔT_s h (µm); ΔT_s defaults to its part's rise.

    Parameters
    ----------
    rig : Rig
        A validated rig.
    mount : Mount
        One of ``rig.mounts``.

    Returns
    -------
    float
        The lift in µm; zero without ``[thermal]`` or without the support's height above the bed.
    """
    thermal = rig.thermal
    if thermal is None or mount.height_above_bed_mm is None:
        return 0.0
    rise = thermal.support_temperature_rise_K.get(mount.name, thermal.temperature_rise_K.get(mount.part, 0.0))
    material = mount.support_material or rig.part(mount.part).material
    return _alpha(rig, material) * rise * mount.height_above_bed_mm * 1e3


def bed_growth_mm(rig: Rig, x_mm: float) -> float:
    """Axial motion of the bed at ``x_mm``, α_bed ΔT_bed (x − bed_fixed_x_mm) (mm)."""
    thermal = rig.thermal
    if thermal is None or not thermal.bed_temperature_rise_K:
        return 0.0
    return _alpha(rig, thermal.bed_material) * thermal.bed_temperature_rise_K * (x_mm - thermal.bed_fixed_x_mm)


def _spacing_growth_mm(rig: Rig, from_end, to_end, centre_x: float) -> float:
    """Growth of the axial spacing of two ends (``part``, ``x_mm``) joined at ``centre_x``: each part's strain on
    its side."""
    return (part_strain(rig, from_end.part) * (centre_x - from_end.x_mm)
            + part_strain(rig, to_end.part) * (to_end.x_mm - centre_x))


def thermal_stress_free_motions(rig: Rig) -> np.ndarray:
    """The thermal part of each spring's stress-free relative motion (n_bushings, 6), SI.

    Rows in the order the beam model builds its bushings (bearings, mounts, couplings, joints).
    Ground springs: the bed's axial growth at the spring and, for a mount, its support's lift.
    """
    rows = []
    for b in rig.bearings:
        row = np.zeros(6)
        if b.housing == "ground":
            row[0] = bed_growth_mm(rig, b.x_mm) * 1e-3
        rows.append(row)
    for m in rig.mounts:
        rows.append(np.array([bed_growth_mm(rig, m.x_mm) * 1e-3, mount_lift_um(rig, m) * 1e-6, 0.0, 0.0, 0.0, 0.0]))
    for c in rig.couplings:
        growth = _spacing_growth_mm(rig, c.from_, c.to, c.centre_x_mm)
        rows.append(np.array([growth * 1e-3, 0.0, 0.0, 0.0, 0.0, 0.0]))
    for j in rig.joints:
        growth = _spacing_growth_mm(rig, j.from_, j.to, j.to.x_mm)
        rows.append(np.array([growth * 1e-3, 0.0, 0.0, 0.0, 0.0, 0.0]))
    return np.array(rows, dtype=float).reshape(-1, 6)


def beam_thermal_load(rig: Rig, node_part: np.ndarray, beams, n_dofs: int) -> np.ndarray:
    """Initial-strain load of the beams: −E A ε on the first node's x, +E A ε on the second's (elements along +x)."""
    vector = np.zeros(n_dofs)
    if rig.thermal is None or not beams.connectivity.size:
        return vector
    strain = {p.name: part_strain(rig, p.name) for p in rig.parts}
    first = beams.connectivity[:, 0]
    element_strain = np.array([strain[node_part[n]] for n in first])
    force = beams.youngs_modulus_Pa * beams.area_m2 * element_strain
    np.add.at(vector, 6 * beams.connectivity[:, 0], -force)
    np.add.at(vector, 6 * beams.connectivity[:, 1], force)
    return vector
