"""A rig's mass matrix, on the DOFs of its assembled system (beam, hybrid or solid), from each piece's mass form.

- beams: the consistent Timoshenko mass (:func:`rvcoax.fem.beam.mass_triplets`), bodies at their equivalent
  density, so that each body weighs its ``mass_kg``;
- coupling hubs: half the coupling's mass on each hub node, with half its ``polar_inertia_kg_m2`` about the axis
  and a quarter about each diameter (:func:`rvcoax.fem.loads.point_mass_triplets`);
- solid parts: the consistent P2 mass (:func:`rvcoax.fem.solid.mass_matrix`);
- ``[[housings]]`` with ``self_weight``: Guyan's condensed mass on the nodes the housing holds (its bed side is
  fixed: no inertia), :func:`rvcoax.fem.condensation.guyan_reduction`. Without ``self_weight`` the housing's mass is
  its part's (the body whose weight the rig already carries), exactly as its weight is: not counted twice. Guyan and not Craig–Bampton: a housing's own lowest mode on its
  bed is returned with it (:func:`housing_frequencies`). Where Guyan is too coarse the modal study adds the housing's
  fixed-interface modes as extra DOFs (Craig–Bampton, :func:`housing_modes`): those below
  :data:`rvcoax.fem.craig_bampton.INTERFACE_FACTOR` × the highest rig frequency asked for.

Every piece is a :class:`rvcoax.fem.pieces.Contribution` summed by :func:`rvcoax.fem.pieces.assemble`, the path the
stiffness takes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.condensation import superelement_mass_contribution
from rvcoax.fem.craig_bampton import INTERFACE_FACTOR, AttachedModes, interface_modes_needed
from rvcoax.fem.pieces import Contribution, assemble, frame_mass_contributions, solid_mass_contribution
from rvcoax.geometry.model.condensed_housing import housing_craig_bampton
from rvcoax.geometry.model.housings import condensation_inputs, condensed_housing
from rvcoax.geometry.model.system import RigSystem

__all__ = ["HousingModes", "housing_frequencies", "housing_modes", "mass_contributions", "part_masses",
           "rig_mass_matrix"]


def mass_contributions(system: RigSystem, cache_dir=None) -> list[Contribution]:
    """The mass form of every piece of ``system``, in the order the stiffness is assembled."""
    rig, frame = system.rig, system.frame
    pieces = frame_mass_contributions(frame.structure)
    for housing in rig.housings:
        if not housing.self_weight:  # its mass is its part's (the body held), as its weight is: not counted twice
            continue
        condensed = condensed_housing(rig, housing, cache_dir)
        nodes = [frame.node(housing.part, x) for x in housing.attachments_x_mm]
        dofs = (DOFS_PER_NODE * np.asarray(nodes)[:, None] + np.arange(DOFS_PER_NODE)).ravel()
        density = rig.materials[housing.material].density_kg_per_m3
        pieces.append(superelement_mass_contribution(density * condensed.mass_per_density, dofs))
    pieces += [solid_mass_contribution(s.basis, s.density_kg_per_m3, s.offset) for s in system.solids]
    return pieces


def rig_mass_matrix(system: RigSystem, cache_dir=None) -> sp.csr_matrix:
    """M (n × n) of ``system`` (kg, kg·m, kg·m²), constraints not applied."""
    return assemble(system.n_dofs, mass_contributions(system, cache_dir)).mass


def housing_frequencies(system: RigSystem, cache_dir=None) -> dict[str, float]:
    """Each ``[[housings]]`` entry's lowest natural frequency on its bed (Hz), the limit of its Guyan mass."""
    rig = system.rig
    return {h.name: condensed_housing(rig, h, cache_dir).lowest_frequency_hz(rig.materials[h.material].density_kg_per_m3)
            for h in rig.housings}


@dataclass(frozen=True, eq=False)
class HousingModes:
    """One ``[[housings]]`` entry's choice for the modal study: ``name``, its lowest fixed-interface frequency (Hz;
    the housing on its bed with its attachments held), how many of those modes are kept (0: Guyan's mass) and
    their attachment to the system (None with 0)."""

    name: str
    lowest_interface_hz: float
    kept: int
    attached: AttachedModes | None
    free_interface_bound: bool = False  # lowest_interface_hz is the lowest mode with the attachments free (a bound)


def housing_modes(system: RigSystem, top_frequency_hz: float, request: str = "auto", cache_dir=None) -> list[HousingModes]:
    """Which housings (those with ``self_weight``: the others carry no inertia of their own) get Craig–Bampton
    modes for rig modes up to ``top_frequency_hz``.

    ``request``: ``"auto"`` keeps the fixed-interface modes below ``INTERFACE_FACTOR`` × ``top_frequency_hz``
    (none when the lowest is above: Guyan); ``"craig-bampton"`` the same, and at least 2; ``"guyan"`` none.
    ``"auto"`` first looks at the housing's lowest mode with its attachments free (cached with its condensation):
    holding the attachments can only raise the frequencies, so when that one is above the limit the
    fixed-interface modes are not computed at all.
    """
    rig, frame = system.rig, system.frame
    out = []
    if request == "guyan":
        return out
    for housing in rig.housings:
        if not housing.self_weight:
            continue
        density = rig.materials[housing.material].density_kg_per_m3
        if request == "auto":
            free = np.sqrt(housing.stiffness_factor) * condensed_housing(rig, housing, cache_dir).lowest_frequency_hz(density)
            if free >= INTERFACE_FACTOR * top_frequency_hz:
                out.append(HousingModes(housing.name, free, 0, None, free_interface_bound=True))
                continue
        geometry, youngs, poisson, references, feet, bed = condensation_inputs(rig, housing)
        reduction = housing_craig_bampton(geometry, youngs, poisson, references, feet, bed_stiffness_N_per_um_per_mm2=bed,
                                          cache_dir=cache_dir)
        omega2 = housing.stiffness_factor * reduction.interface_eigenvalues / density
        kept = interface_modes_needed(omega2, top_frequency_hz)
        if request == "craig-bampton":
            kept = min(max(kept, 2), reduction.n_modes)
        lowest = float(np.sqrt(omega2[0]) / (2 * np.pi)) if omega2.size else float("inf")
        attached = None
        if kept:
            nodes = [frame.node(housing.part, x) for x in housing.attachments_x_mm]
            dofs = (DOFS_PER_NODE * np.asarray(nodes)[:, None] + np.arange(DOFS_PER_NODE)).ravel()
            attached = AttachedModes.of(reduction.truncated(kept), dofs, density=density,
                                        stiffness_factor=housing.stiffness_factor)
        out.append(HousingModes(housing.name, lowest, kept, attached))
    return out


def part_masses(system: RigSystem, mass: sp.csr_matrix) -> dict[str, float]:
    """The translational mass (kg) of each part in ``mass``: rᵀ M r for r a unit translation (along y) of the part's
    DOFs alone, frame nodes and solid DOFs; a condensed housing's share sits on the nodes of the part it holds."""
    frame = system.frame
    table = system.dofs
    owner = np.full(system.n_dofs, "", dtype=object)
    frame_dofs = DOFS_PER_NODE * frame.node_part.size
    owner[:frame_dofs] = np.repeat(frame.node_part, DOFS_PER_NODE)
    for s in system.solids:
        owner[s.offset:s.offset + s.n_dofs] = s.name
    out = {}
    for part in system.rig.parts:
        unit = ((owner == part.name) & (table.component == 1)).astype(float)
        out[part.name] = float(unit @ (mass @ unit))
    return out
