"""``[[housings]]`` in a rig model: each housing's condensed stiffness on the frame nodes it holds.

The condensed matrix (:func:`rvcoax.geometry.model.condensed_housing.condense_housing`, cached by content) is a
superelement between the ground and the reference nodes of the housing's part at
``attachments_x_mm``; it enters the system like a bushing (:func:`rvcoax.fem.condensation.superelement_contribution`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.condensation import superelement_contribution
from rvcoax.fem.pieces import Contribution, dense_load_contribution
from rvcoax.geometry.housings import Reference
from rvcoax.geometry.model.beam import housing_bed_group
from rvcoax.geometry.model.condensed_housing import CondensedHousing, condense_housing
from rvcoax.geometry.schema import Housing, Rig
from rvcoax.geometry.thermal import bed_growth_mm

__all__ = ["SEAT_DIRECTIONS", "SeatStiffness", "condensation_inputs", "condensed_housing", "housing_contributions", "housing_prestrain",
           "housing_condensation", "housing_weight", "seat_stiffness"]


def condensed_housing(rig: Rig, housing: Housing, cache_dir=None, compute: bool = True) -> CondensedHousing | None:
    """The condensed stiffness of ``housing`` (6k × 6k, SI), before its ``stiffness_factor``.

    Parameters
    ----------
    rig : Rig
        The rig (its materials).
    housing : Housing
        One of its ``[[housings]]`` entries.
    cache_dir : Path, optional
        Where condensations are cached (default: the mesh cache's folder).
    compute : bool
        False: only what the cache holds (None before the first solve has condensed it).

    Returns
    -------
    CondensedHousing or None
        The matrix, the solid's DOF count, the weight load, volume and centroid.
    """
    geometry, youngs, poisson, references, feet, bed = condensation_inputs(rig, housing)
    return condense_housing(geometry, youngs, poisson, references, feet, bed_stiffness_N_per_um_per_mm2=bed,
                            cache_dir=cache_dir, compute=compute)


def condensation_inputs(rig: Rig, housing: Housing) -> tuple:
    """(geometry, E in Pa, ν, references, feet, bed stiffness per area) of ``housing``'s solid model."""
    face = "bore" if housing.bore_diameter_mm > 0 else "top"
    references = [Reference((x, 0.0, 0.0), (face, *band), housing.tie)
                  for x, band in zip(housing.attachments_x_mm, housing.bands_mm())]
    material = rig.materials[housing.material]
    bed = housing.bed_stiffness_per_area()  # springs per bolt foot: the same law, per area of the foot
    return (housing.geometry, material.youngs_modulus_MPa * 1e6, material.poisson_ratio, references,
            "clamped" if bed is None else "bed", bed)


def _dofs(nodes) -> np.ndarray:
    return (DOFS_PER_NODE * np.asarray(nodes)[:, None] + np.arange(DOFS_PER_NODE)).ravel()


def housing_contributions(rig: Rig, frame, cache_dir=None) -> list[Contribution]:
    """One superelement per ``[[housings]]`` entry between the frame nodes of its part and their fixed bed nodes
    (:func:`rvcoax.geometry.model.beam.housing_bed_group`), with its own weight where it has ``self_weight``
    (:func:`housing_weight`); empty without housings."""
    pieces = []
    for housing in rig.housings:
        nodes = [frame.node(housing.part, x) for x in housing.attachments_x_mm]
        bed = [frame.node(housing_bed_group(housing.name), x) for x in housing.attachments_x_mm]
        condensed = condensed_housing(rig, housing, cache_dir)
        pieces.append(superelement_contribution(housing.stiffness_factor * condensed.matrix, _dofs(nodes), _dofs(bed)))
        if housing.self_weight:
            density = rig.materials[housing.material].density_kg_per_m3
            pieces.append(Contribution(loads={"gravity": housing_weight(condensed, density, housing.attachments_x_mm,
                                                                        _dofs(nodes), _dofs(bed[:1]))}))
    return pieces


def housing_weight(condensed: CondensedHousing, density_kg_per_m3: float, attachments_x_mm, dofs,
                   bed_dofs) -> tuple[np.ndarray, np.ndarray]:
    """The housing's weight per m/s² along gravity (−y) as load entries: the equivalent master load ρ f_c on the
    attachment ``dofs`` (the seats sag as in the full solid model) and the rest of the weight ρ V at the centroid —
    force and moment about the first attachment — on the fixed ``bed_dofs`` (6) there, so that the ground's
    reactions sum to ρ g V."""
    seats = density_kg_per_m3 * condensed.weight_load
    per_node = seats.reshape(-1, DOFS_PER_NODE)
    points = np.zeros((per_node.shape[0], 3))
    points[:, 0] = np.asarray(attachments_x_mm, dtype=float) * 1e-3
    origin = points[0]
    weight = np.array([0.0, -density_kg_per_m3 * condensed.volume_m3, 0.0])
    force = weight - per_node[:, :3].sum(axis=0)
    moment = (np.cross(np.asarray(condensed.centroid_m) - origin, weight)
              - (np.cross(points - origin, per_node[:, :3]) + per_node[:, 3:]).sum(axis=0))
    return np.concatenate([np.asarray(dofs), np.asarray(bed_dofs)]), np.concatenate([seats, force, moment])


def housing_prestrain(rig: Rig, frame, n_dofs: int) -> Contribution:
    """The load of warm housings on their part's nodes, K_c Δ0, as load ``"prestrain"`` (a vector of length
    ``n_dofs``; zero without ``[thermal]``).

    The housing's bed side moves by Δ0 = (α_bed ΔT_bed (x_c − x_fixed) + α ΔT (x − x_c), α ΔT h, α ΔT d, 0, 0, 0) at
    each attachment x (α of the housing's material, ΔT its ``support_temperature_rise_K`` or else its part's
    rise, h its ``height_above_bed_mm`` and d = 0 for a block or pedestal, h = 0 and d its ``wall_distance_mm``
    for a wall bracket, x_c the housing's centre): the housing lifts what it holds (a bracket pushes it away
    from its wall), as a mount's support does, and grows along x about its centre, carried by the bed there.
    """
    vector = np.zeros(n_dofs)
    if rig.thermal is None:
        return dense_load_contribution("prestrain", vector)
    for housing in rig.housings:
        thermal = rig.thermal
        rise = thermal.support_temperature_rise_K.get(housing.name, thermal.temperature_rise_K.get(housing.part, 0.0))
        alpha = rig.materials[housing.material].thermal_expansion_per_K or 0.0
        motion = np.zeros((len(housing.attachments_x_mm), DOFS_PER_NODE))
        centre = 0.5 * sum(housing.x_mm)
        motion[:, 0] = [(bed_growth_mm(rig, centre) + alpha * rise * (x - centre)) * 1e-3 for x in housing.attachments_x_mm]
        lift_mm, away_mm = housing.thermal_motion_mm_per_K()
        motion[:, 1] = alpha * rise * lift_mm * 1e-3
        motion[:, 2] = alpha * rise * away_mm * 1e-3
        if not motion.any():
            continue
        matrix = housing.stiffness_factor * condensed_housing(rig, housing).matrix
        nodes = [frame.node(housing.part, x) for x in housing.attachments_x_mm]
        vector[_dofs(nodes)] += matrix @ motion.ravel()
    return dense_load_contribution("prestrain", vector)


SEAT_DIRECTIONS = {"vertical (y)": 1, "lateral (z)": 2}


@dataclass(frozen=True)
class SeatStiffness:
    """The stiffness a bearing sees at one seat of a condensed housing, in one direction (N/µm).

    ``held``: the diagonal entry of K_c, this seat moved with every other master DOF of the housing held
    (its other seat and every rotation): an upper bound no bearing sees. ``alone``: this seat loaded, the
    other seat and the rotations free (1 / F_ii, F = K_c⁻¹): one bearing loaded. ``together``: every seat
    loaded with the same force in this direction, per seat (force / this seat's displacement): both
    bearings of a shaft pushed the same way, as its weight and a lateral gear force do.
    """

    housing: str
    seat_x_mm: float
    direction: str
    held_N_per_um: float
    alone_N_per_um: float
    together_N_per_um: float


def seat_stiffness(housing: Housing, matrix: np.ndarray) -> tuple[SeatStiffness, ...]:
    """The :class:`SeatStiffness` of every seat of ``housing`` in both lateral directions.

    Parameters
    ----------
    housing : Housing
        The ``[[housings]]`` entry (its seats and ``stiffness_factor``, applied here).
    matrix : (6k, 6k) array
        Its condensed stiffness (:func:`condensed_housing`), SI, before ``stiffness_factor``.

    Returns
    -------
    tuple of SeatStiffness
        Per direction (vertical, lateral) and seat: held, alone and together (N/µm).
    """
    stiffness = housing.stiffness_factor * np.asarray(matrix, dtype=float)
    flexibility = np.linalg.inv(stiffness)
    seats = len(housing.attachments_x_mm)
    out = []
    for direction, component in SEAT_DIRECTIONS.items():
        rows = DOFS_PER_NODE * np.arange(seats) + component
        together = flexibility[:, rows].sum(axis=1)
        for i, x in enumerate(housing.attachments_x_mm):
            row = rows[i]
            out.append(SeatStiffness(housing=housing.name, seat_x_mm=float(x), direction=direction,
                                     held_N_per_um=float(stiffness[row, row]) * 1e-6,
                                     alone_N_per_um=1e-6 / float(flexibility[row, row]),
                                     together_N_per_um=1e-6 / float(together[row])))
    return tuple(out)


housing_condensation = condensed_housing  # the public name (rvcoax.geometry.model.condensed_housing is a module)
