"""``[[housings]]`` in a rig model: each housing's condensed stiffness on the frame nodes it holds.

The condensed matrix (:func:`rvcoax.geometry.housings.condense_housing`, cached by content) is a
superelement between the ground and the reference nodes of the housing's part at
``attachments_x_mm``; it enters the system like a bushing (:func:`rvcoax.fem.condensation.superelement_contribution`).
"""

from __future__ import annotations

import numpy as np

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.condensation import superelement_contribution
from rvcoax.fem.pieces import Contribution, dense_load_contribution
from rvcoax.geometry.housings import CondensedHousing, Reference, condense_housing
from rvcoax.geometry.model.beam import housing_bed_group
from rvcoax.geometry.schema import Housing, Rig
from rvcoax.geometry.thermal import bed_growth_mm

__all__ = ["condensed_housing", "housing_contributions", "housing_prestrain"]


def condensed_housing(rig: Rig, housing: Housing, cache_dir=None) -> CondensedHousing:
    """The condensed stiffness of ``housing`` (6k × 6k, SI), before its ``stiffness_factor``."""
    face = "bore" if housing.bore_diameter_mm > 0 else "top"
    references = [Reference((x, 0.0, 0.0), (face, *band), housing.tie)
                  for x, band in zip(housing.attachments_x_mm, housing.bands_mm())]
    material = rig.materials[housing.material]
    bed = housing.bed_stiffness_per_area()  # springs per bolt foot: the same law, per area of the foot
    return condense_housing(housing.geometry, material.youngs_modulus_MPa * 1e6, material.poisson_ratio, references,
                            "clamped" if bed is None else "bed", bed, cache_dir=cache_dir)


def _dofs(nodes) -> np.ndarray:
    return (DOFS_PER_NODE * np.asarray(nodes)[:, None] + np.arange(DOFS_PER_NODE)).ravel()


def housing_contributions(rig: Rig, frame, cache_dir=None) -> list[Contribution]:
    """One superelement per ``[[housings]]`` entry between the frame nodes of its part and their fixed bed nodes
    (:func:`rvcoax.geometry.model.beam.housing_bed_group`); empty without housings."""
    pieces = []
    for housing in rig.housings:
        nodes = [frame.node(housing.part, x) for x in housing.attachments_x_mm]
        bed = [frame.node(housing_bed_group(housing.name), x) for x in housing.attachments_x_mm]
        matrix = housing.stiffness_factor * condensed_housing(rig, housing, cache_dir).matrix
        pieces.append(superelement_contribution(matrix, _dofs(nodes), _dofs(bed)))
    return pieces


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
