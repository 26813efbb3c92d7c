"""Checks made before solving a rig, so that an unusable model is named in the user's terms.

- :func:`support_problem`: a beam model too large for this machine (counted from the geometry
  before anything is built: :func:`rvcoax.geometry.model.workload.rig_problem`); a part (or a set of parts) that
  can move without deforming anything, with its free directions and the springs whose zero
  stiffness leaves it free; a mechanism of several parts that only move together (a shaft line free to
  turn about the axis when a joint has no torsional stiffness), named by :func:`free_body` as ``rvcoax modes``
  names a zero-frequency mode, with the rig keys whose zero leaves it free; or stiffness values so far apart
  that the solve would lose every digit (named: the stiffest and softest springs).
- :func:`sag_warnings`: a part that hangs only on couplings, or sags absurdly under its own weight
  (not singular, but not a test rig either).
- :func:`estimate_memory`: DOFs and memory of a solid or hybrid model from the rig alone, before
  any meshing, against the memory this machine has available; :func:`peak_memory_bytes` the peak of any model
  (the ``rvcoax`` command sets the C heap's policy by it: :func:`rvcoax.fem.memory.apply_heap_policy`).

All three work on the rig's beam model, assembled as the solve assembles it (a ``[[housings]]`` entry's
condensed stiffness read from its cache), or on its geometry only: milliseconds, at any fidelity.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import DOFS_PER_NODE, bushing, diagnostics
from rvcoax.fem.errors import SingularModelError
from rvcoax.fem.pieces import AssembledSystem, assemble, assemble_frame, frame_mass_contributions
from rvcoax.fem.system import factorize
from rvcoax.geometry.model.beam import SpringId, build_rig_model
from rvcoax.geometry.model.system import beam_contributions
from rvcoax.geometry.schema import Rig

__all__ = ["BASE_BYTES", "BYTES_PER_DOF", "CLASS_SHARE", "COMPONENT_NAMES", "CONDITION_LIMIT", "DIRECTIONS",
           "FREE_BODY_SHARE", "MECHANISM_BOUND", "FreeBody", "MemoryEstimate", "SAG_WARNING_MM",
           "SHORT_ELEMENT_FRACTION", "SPRING_KINDS", "STANDARD_GRAVITY", "TYPICAL_MODULI", "estimate_memory",
           "free_body", "memory_problem", "motion_class", "peak_memory_bytes", "sag_warnings", "short_segment_note",
           "support_problem"]

# A "topological" copy of the beam model: every beam made of steel (Pa) and every non-zero spring as stiff
# as the stiffest beam term (N/m; N·m/rad over the model's length), so that only zeros can leave a part free.
TYPICAL_MODULI = (2.1e11, 8.1e10)
# Jacobi-scaled 1-norm condition number beyond which a solve keeps fewer than ~5 correct digits (ε κ > 1e-5)
# and direct solves start to miss the 1e-6 residual checks (measured on the beam model: κ 5.5e11 gave a
# relative residual of 2e-6, κ 5e12 one of 1e-4; the reference rig is at 3e7, its hybrid model at 4e9)
CONDITION_LIMIT = 1e11
SAG_WARNING_MM = 0.1  # a test-rig part sagging more than this under its own weight is not plausible
STANDARD_GRAVITY = 9.80665
# Peak memory per DOF of a solid/hybrid solve, measured (benchmarks/RESULTS.md, bench_solid_scaling):
# PARDISO 4.02 GB at 298 k DOF, AMG-CG 11.38 GB at 1.04 M DOF (assembly dominates both), SuperLU
# 14 GB at 300 k DOF (fem/solvers.py); plus the interpreter, imports and the beam frame.
BYTES_PER_DOF = {"pardiso": 13.5e3, "amg": 11.0e3, "superlu": 47.0e3}
BASE_BYTES = 0.3e9
COMPONENT_NAMES = diagnostics.MOTION_NAMES
SPRING_KINDS = {"bearing": "bearing", "mount": "mount", "coupling": "coupling", "joint": "joint"}
DIRECTIONS = ("axial", "lateral vertical", "lateral horizontal", "torsional")
"""The classes of a motion, by the frame DOFs that carry it: u_x; u_y, θ_z; u_z, θ_y; θ_x (the axis is x)."""
DIRECTION_COMPONENTS = ((0,), (1, 5), (2, 4), (3,))
CLASS_SHARE = 0.6
"""A motion is of one direction when that direction holds at least this share of its kinetic energy."""
FREE_BODY_SHARE = 0.05
"""A part moves in a free-body motion when it holds more than this share of the motion's kinetic energy."""
MECHANISM_BOUND = 1e14
"""A lower bound of 1/λ_min of the Jacobi-scaled stiffness above which the topological copy (see
:func:`support_problem`) has a motion without energy: a mechanism gives 1.6e16, the held reference rig 1.1e10,
the same rig with 0.5 mm beam elements 1.1e11 (λ_min falls as the elements shrink)."""


def _assembled(frame, structure=None) -> AssembledSystem:
    """The beam model's system as the solve assembles it (:func:`rvcoax.geometry.model.system.beam_contributions`:
    the frame's pieces and each ``[[housings]]`` entry's condensed stiffness); ``structure`` replaces the frame's."""
    if structure is not None:
        frame = dataclasses.replace(frame, structure=structure)
    return assemble(frame.structure.n_dofs, beam_contributions(frame.rig, frame))


def _free_motions(structure, system: AssembledSystem) -> list[diagnostics.FreeMotion]:
    return diagnostics.find_free_motions(structure, system)


def _non_finite_parts(frame, system: AssembledSystem) -> list[str]:
    """The parts whose stiffness entries overflow or are undefined (NaN/inf): nothing can be solved then."""
    stiffness = system.stiffness.tocoo()
    bad = ~np.isfinite(stiffness.data)
    if not bad.any():
        return []
    groups = np.asarray(frame.structure.node_group)
    nodes = np.unique(stiffness.row[bad] // diagnostics.DOFS_PER_NODE)
    return list(dict.fromkeys(str(groups[n]) for n in nodes))


def _spring_label(spring) -> str:
    return f"{SPRING_KINDS.get(spring.kind, spring.kind)} '{spring.name}'"


def _spring_parts(frame) -> list[set[str]]:
    """The parts each bushing of ``frame`` touches (the ground is not a part)."""
    groups = np.asarray(frame.structure.node_group)
    b = frame.structure.bushings
    return [{str(groups[n]) for n in (a, c) if n != bushing.GROUND} for a, c in zip(b.node_a, b.node_b)]


def _zero_springs_note(frame, motions: list[diagnostics.FreeMotion]) -> str:
    """Springs on the free parts whose stiffness is zero in a free direction, or ''."""
    touched = _spring_parts(frame)
    notes: dict[str, str] = {}
    for motion in motions:
        directions = {i for i, name in enumerate(COMPONENT_NAMES) if any(name in d for d in motion.directions)}
        for k, name in enumerate(frame.bushing_names):
            if not touched[k] & set(motion.parts):
                continue
            zero = [COMPONENT_NAMES[i] for i in sorted(directions) if frame.structure.bushings.stiffness[k, i] == 0.0]
            if zero:
                notes.setdefault(name, f"{_spring_label(name)} ({', '.join(zero)})")
    if not notes:
        return ""
    return " Springs with zero stiffness in those directions: " + "; ".join(notes.values()) + "."


def _stiffness_range_note(frame) -> str:
    """The stiffest and the softest non-zero spring component, in the rig file's units."""
    k = frame.structure.bushings.stiffness
    entries = []
    for row, name in enumerate(frame.bushing_names):
        for column in range(6):
            value = k[row, column]
            if value > 0:
                shown = (f"{value * 1e-6:.3g} N/µm" if column < 3 else f"{value:.3g} N·m/rad")
                # compare translations (N/m) with rotations (N·m/rad) over a 0.1 m lever
                entries.append((value if column < 3 else value / 0.01, _spring_label(name), COMPONENT_NAMES[column],
                                shown))
    moduli = frame.structure.beams.youngs_modulus_Pa
    note = f"Young's moduli of the beams {moduli.min() * 1e-6:.3g} … {moduli.max() * 1e-6:.3g} MPa"
    if not entries:
        return note
    stiffest, softest = max(entries), min(entries)
    return (f"stiffest spring: {stiffest[1]} {stiffest[3]} ({stiffest[2]}); softest: {softest[1]} {softest[3]} "
            f"({softest[2]}); {note}")


SHORT_ELEMENT_FRACTION = 0.01
"""A beam segment shorter than this fraction of ``[mesh] max_element_length_mm`` is named when the stiffness
matrix is ill-conditioned: a beam element's bending stiffness grows as 1/L³, so thousands of µm-long
segments (a CAD export's facets) spread the matrix over many orders of magnitude."""


def short_segment_note(rig: Rig) -> str:
    """`` Parts 'a' (120 segments shorter than 0.05 mm, the shortest 0.004 mm at x = 262 mm) …: merge …``,
    or '' when no segment is shorter than :data:`SHORT_ELEMENT_FRACTION` of the element length.

    Parameters
    ----------
    rig : Rig
        The rig whose segments are looked at.

    Returns
    -------
    str
        A sentence for an ill-conditioning message (starting with a space), or ''.
    """
    limit = SHORT_ELEMENT_FRACTION * rig.mesh.max_element_length_mm
    found = []
    for i, part in enumerate(rig.parts):
        short = [s for s in part.segments if s.x_mm[1] - s.x_mm[0] < limit]
        if short:
            shortest = min(short, key=lambda s: s.x_mm[1] - s.x_mm[0])
            found.append(f"parts[{i}] ('{part.name}'): {len(short)} segment(s) shorter than {limit:.3g} mm, the "
                         f"shortest {shortest.x_mm[1] - shortest.x_mm[0]:.3g} mm at x = {shortest.x_mm[0]:g} mm")
    if not found:
        return ""
    return (" The likely cause here: " + "; ".join(found[:3]) + (f" (and {len(found) - 3} more parts)" if len(found) > 3
                                                                  else "")
            + f", against max_element_length_mm = {rig.mesh.max_element_length_mm:g} mm; a beam element's bending "
              "stiffness grows as 1/L³, so very short segments spread the matrix over many orders of magnitude: merge "
              "them into longer ones (a shoulder shorter than a few tenths of a mm does not change a shaft's bending)")


def motion_class(shares: dict[str, float]) -> str:
    """The class of a motion from its kinetic energy share per :data:`DIRECTIONS`: the direction holding at least
    :data:`CLASS_SHARE`, else ``mixed (…)`` with the two largest shares."""
    ranked = sorted(shares.items(), key=lambda kv: -kv[1])
    name, value = ranked[0]
    if value >= CLASS_SHARE:
        return name
    return f"mixed ({ranked[0][0]} {100 * ranked[0][1]:.0f} %, {ranked[1][0]} {100 * ranked[1][1]:.0f} %)"


@dataclass(frozen=True)
class FreeBody:
    """A motion without strain energy: the parts that carry it (largest kinetic energy first) and its class."""

    parts: tuple[str, ...]
    kind: str

    def named(self) -> str:
        return ", ".join(repr(p) for p in self.parts)


def free_body(kinetic: np.ndarray, owner: np.ndarray, direction_shares: dict[str, float]) -> FreeBody:
    """Name a zero-energy motion (a zero-frequency mode, a null vector of the stiffness) as ``rvcoax modes`` and the
    preflight show it.

    Parameters
    ----------
    kinetic : array (n_dofs,)
        φ ⊙ (M φ): the motion's kinetic energy per DOF.
    owner : array of str (n_dofs,)
        The part each DOF belongs to ('' for none).
    direction_shares : dict
        The kinetic energy share of each of :data:`DIRECTIONS`.

    Returns
    -------
    FreeBody
        The parts holding more than :data:`FREE_BODY_SHARE` of the kinetic energy, and :func:`motion_class`.
    """
    total = float(kinetic.sum()) or 1.0
    shares = {str(name): float(kinetic[owner == name].sum()) / total for name in np.unique(owner) if name}
    moving = tuple(n for n, v in sorted(shares.items(), key=lambda kv: -kv[1]) if v > FREE_BODY_SHARE)
    return FreeBody(moving, motion_class(direction_shares))


def _frame_direction_shares(kinetic: np.ndarray) -> dict[str, float]:
    component = np.arange(kinetic.size) % DOFS_PER_NODE
    sums = np.array([max(float(kinetic[np.isin(component, c)].sum()), 0.0) for c in DIRECTION_COMPONENTS])
    total = sums.sum() or 1.0
    return {name: float(v / total) for name, v in zip(DIRECTIONS, sums)}


def _mechanism(frame, topological) -> tuple[FreeBody, np.ndarray] | None:
    """A motion of the ``topological`` copy's beam model without energy that the part-by-part test missed (parts
    that move only together), or None: two steps of inverse iteration bound 1/λ_min of the Jacobi-scaled reduced
    stiffness (milliseconds); only beyond :data:`MECHANISM_BOUND` is the null vector computed, named by
    :func:`free_body` with the frame's mass, and returned with its kinetic energy share per DOF component."""
    import scipy.sparse.linalg as spla

    system = _assembled(frame, topological)
    t = system.elimination
    reduced = (t.T @ system.stiffness @ t).tocsc()
    if reduced.shape[0] < 3:
        return None
    try:
        factor = spla.splu(reduced)
        bound, _ = diagnostics.scaled_inverse_norm_bound(reduced, factor.solve)
    except RuntimeError:  # an exactly singular factor
        bound = math.inf
    if bound < MECHANISM_BOUND:
        return None
    root = np.sqrt(np.maximum(reduced.diagonal(), np.finfo(float).tiny))
    scaled = (sp.diags(1.0 / root) @ reduced @ sp.diags(1.0 / root)).tocsc()
    values, vectors = spla.eigsh(scaled, k=1, sigma=-1.0 / MECHANISM_BOUND, which="LM")
    phi = t @ (vectors[:, 0] / root)
    kinetic = phi * (assemble(frame.structure.n_dofs, frame_mass_contributions(frame.structure)).mass @ phi)
    owner = np.repeat(np.asarray(frame.structure.node_group, dtype=object), DOFS_PER_NODE)
    component_share = np.array([kinetic[c::DOFS_PER_NODE].sum() for c in range(DOFS_PER_NODE)])
    return free_body(kinetic, owner, _frame_direction_shares(kinetic)), component_share / (component_share.sum() or 1)


def _spring_key(rig: Rig, spring, component: int) -> str:
    """The rig key of ``spring``'s stiffness in ``component`` (0-5: x, y, z, about x, y, z), as the rig file names it."""
    entries = getattr(rig, f"{spring.kind}s", [])
    index = next((i for i, e in enumerate(entries) if e.name == spring.name), None)
    where = f"{spring.kind}s[{index}] ('{spring.name}')" if index is not None else _spring_label(spring)
    if spring.kind in ("mount", "joint"):
        key = "translational_stiffness_N_per_um" if component < 3 else "rotational_stiffness_Nm_per_rad"
        return f"{where}.{key}[{component % 3}]"
    return f"{where} ({COMPONENT_NAMES[component]})"


def _motion_name(component: int) -> str:
    return "rotation about x, the axis" if component == 3 else COMPONENT_NAMES[component]


def _mechanism_text(rig: Rig, frame, body: FreeBody, component_share: np.ndarray) -> str:
    """The singular-model message for a mechanism: its parts and motion, and the zero stiffness keys of the springs
    that join its parts to the rest of the rig (mounts and joints; bearings are free in torsion by design)."""
    free = [c for c in range(DOFS_PER_NODE) if component_share[c] > FREE_BODY_SHARE]
    moving = set(body.parts)
    keys, bearings = [], []
    for k, (spring, touched) in enumerate(zip(frame.bushing_names, _spring_parts(frame))):
        if not touched & moving or (len(touched) == 2 and touched <= moving):
            continue  # not on the mechanism, or inside it
        zero = [c for c in free if frame.structure.bushings.stiffness[k, c] == 0.0]
        if spring.kind == "bearing":
            bearings.extend([_spring_label(spring)] if zero else [])
        else:
            keys.extend(f"{_spring_key(rig, spring, c)} = 0" for c in zero)
    text = (f"the model is singular: part(s) {body.named()} move together as a free body ({body.kind} motion: "
            f"{', '.join(_motion_name(c) for c in free)}), though each of them is held on its own: a support or a "
            "stiffness component is missing.")
    if keys:
        text += (f" The zero stiffness that leaves them free: {'; '.join(dict.fromkeys(keys))} (give it a value, or "
                 "add a mount or joint with stiffness in that direction).")
    if bearings:
        text += f" Bearings free in that direction, as bearings are: {', '.join(dict.fromkeys(bearings))}."
    return text


def _beam_condition(system: AssembledSystem) -> float:
    """Estimated condition number of the beam model's reduced stiffness (inf when SuperLU finds it singular)."""
    from rvcoax.fem.solvers import SingularMatrixError, prepare

    try:
        prepared = prepare(system.elimination.T @ system.stiffness @ system.elimination, "superlu")
    except SingularMatrixError:
        return math.inf
    return prepared.condition_estimate()


def support_problem(rig: Rig) -> str | None:
    """Why ``rig`` cannot be solved for lack of supports, or None when every part is held.

    The free-motion test (:func:`rvcoax.fem.diagnostics.find_free_motions`) runs on the rig's beam model,
    which has the same parts and connections at any fidelity. When it finds a motion, it runs again
    on a copy whose springs all have one typical stiffness: if the copy is held, no spring is
    missing, the motion only stores little energy next to much stiffer elements, and the condition
    number decides: above :data:`CONDITION_LIMIT` the message says so (stiffnesses many orders of
    magnitude apart, often a unit mistake) instead of "no support path"; below, the rig is solvable.
    """
    from rvcoax.geometry.model.workload import housing_problem, rig_problem

    too_big = rig_problem(rig) or housing_problem(rig)
    if too_big:
        return too_big
    frame = build_rig_model(rig)
    system = _assembled(frame)
    unusable = _non_finite_parts(frame, system)
    if unusable:
        return (f"the stiffness of part(s) {', '.join(repr(p) for p in unusable)} is not a finite number: a diameter, "
                "length or modulus is too small or too large to compute with (e.g. 1e-300 mm); check their "
                "segments' *_diameter_mm, x_mm and their material's youngs_modulus_MPa")
    motions = _free_motions(frame.structure, system)
    structure = frame.structure
    steel = dataclasses.replace(structure.beams, youngs_modulus_Pa=np.full_like(structure.beams.youngs_modulus_Pa,
                                                                                TYPICAL_MODULI[0]),
                                shear_modulus_Pa=np.full_like(structure.beams.shear_modulus_Pa, TYPICAL_MODULI[1]))
    springless = structure.with_group(steel).with_group(dataclasses.replace(
        structure.bushings, stiffness=np.zeros_like(structure.bushings.stiffness)))
    scale = float(np.abs(assemble_frame(springless).stiffness.diagonal()).max())
    length = max(float(np.ptp(structure.coordinates, axis=0).max()), 1e-3)
    typical = np.where(structure.bushings.stiffness > 0, scale * np.array([1, 1, 1, length**2, length**2, length**2]),
                       0.0)
    topological = springless.with_group(dataclasses.replace(structure.bushings, stiffness=typical))
    if not motions:
        mechanism = _mechanism(frame, topological)
        return None if mechanism is None else _mechanism_text(rig, frame, *mechanism)
    if _free_motions(topological, _assembled(frame, topological)):
        return ("the model is singular: " + "; ".join(m.describe() for m in motions)
                + ". Add a bearing, mount or joint with stiffness in those directions." + _zero_springs_note(frame,
                                                                                                        motions))
    kappa = _beam_condition(system)
    if kappa <= CONDITION_LIMIT:
        return None
    parts = [p for m in motions for p in m.parts]
    who = ", ".join(f"'{p}'" for p in parts[:3]) + (f" … ({len(parts)} parts)" if len(parts) > 3 else "")
    how = (f"estimated condition number {kappa:.2g} > {CONDITION_LIMIT:.0e}" if math.isfinite(kappa)
           else "its factorisation meets a pivot below 1e-14 of the largest")
    return (f"the stiffness matrix is numerically singular although every part is held ({how}): the supports of "
            f"{who} are far softer than the stiffest elements "
            f"next to them, so a solve would lose every digit ({_stiffness_range_note(frame)}). Check the units of "
            "the stiffness keys (N/µm, N/mm, N·m/rad) and of youngs_modulus_MPa." + short_segment_note(rig))


def sag_warnings(rig: Rig, limit_mm: float = SAG_WARNING_MM) -> list[str]:
    """Parts that hang only on couplings, or sag more than ``limit_mm`` under their own weight.

    The beam model is solved once for standard gravity (whether or not the rig switches gravity
    on): a property of the supports, not of the load case. Returns one sentence per part, empty
    when the rig is plausible (the reference rig's largest sag is 1.6 µm). A rig that cannot be
    factorised, or is too large to build (:func:`rvcoax.geometry.model.workload.rig_problem`), gives no warning
    here (:func:`support_problem` names it).

    Parameters
    ----------
    rig : Rig
        The rig to check (its gravity setting is ignored).
    limit_mm : float
        Sag under self-weight above which a part is named.

    Returns
    -------
    list of str
        One sentence per part.
    """
    from rvcoax.geometry.model.workload import housing_problem, rig_problem

    if rig_problem(rig) or housing_problem(rig):
        return []  # too large to build: support_problem says so
    frame = build_rig_model(rig)
    system = _assembled(frame)
    try:
        u = factorize(system.stiffness, system.elimination).solve(STANDARD_GRAVITY * system.loads["gravity"])
    except SingularModelError:
        return []
    groups = np.asarray(frame.structure.node_group)
    held_by = list(zip(frame.bushing_names, _spring_parts(frame)))
    held_by += [(SpringId("housing", h.name), {h.part}) for h in rig.housings]
    warnings = []
    for part in dict.fromkeys(groups.tolist()):
        nodes = np.flatnonzero(groups == part)
        sag_mm = float(np.abs(u[DOFS_PER_NODE * nodes[:, None] + np.arange(3)]).max()) * 1e3
        holders = [spring for spring, parts in held_by if part in parts]
        couplings_only = bool(holders) and all(spring.kind == "coupling" for spring in holders)
        if couplings_only or sag_mm > limit_mm:
            held = ", ".join(_spring_label(spring) for spring in holders) or "nothing"
            reason = "hangs only on flexible coupling(s)" if couplings_only else "sags far more than a rig part should"
            warnings.append(f"part '{part}' {reason} ({held}): it sags {sag_mm:.3g} mm under its own weight; "
                            "check its bearings and mounts")
    return warnings


# ------------------------------------------------------------------------------------------ memory


@dataclass(frozen=True)
class MemoryEstimate:
    """DOFs and peak memory of a solid or hybrid model, estimated from the rig (no meshing).

    Attributes
    ----------
    model : str
    mesh_size_mm : float
        The global mesh size used.
    dofs : int
        Estimated DOFs of all solid parts (the beam frame is negligible).
    part_dofs : dict
        Estimated DOFs per solid part.
    solver : str
        The solver that would run (``auto`` resolved by size).
    bytes_needed : float
    bytes_available : float or None
    """

    model: str
    mesh_size_mm: float
    dofs: int
    part_dofs: dict
    solver: str
    bytes_needed: float
    bytes_available: float | None

    @property
    def fits(self) -> bool:
        return self.bytes_available is None or self.bytes_needed <= self.bytes_available


def _solid_dofs(rig: Rig, model: str, mesh_size_mm: float) -> dict[str, int]:
    from rvcoax.geometry.meshing import SolidPartGeometry, estimate_dofs
    from rvcoax.geometry.model.hybrid import mesh_size_of

    names = rig.hybrid_solid_parts() if model == "hybrid" else tuple(p.name for p in rig.parts)
    out = {}
    for part in (rig.part(name) for name in names):
        segments = tuple((s.x_mm[0], s.x_mm[1], s.outer_diameter_mm, s.inner_diameter_mm)
                         for s in sorted(part.segments, key=lambda s: s.x_mm[0]))
        out[part.name] = estimate_dofs(SolidPartGeometry(part.name, segments, (), mesh_size_of(rig, part, mesh_size_mm)))
    return out


def estimate_memory(rig: Rig, model: str, mesh_size_mm: float | None = None, solver: str = "auto") -> MemoryEstimate:
    """Estimate DOFs (:func:`rvcoax.geometry.meshing.estimate_dofs`, within a factor 1.3) and peak memory."""
    from rvcoax.fem.solvers import choose_method
    from rvcoax.geometry.model.loads import UNIT_LOADS

    size = rig.solid.mesh_size_mm if mesh_size_mm is None else mesh_size_mm
    part_dofs = _solid_dofs(rig, model, size)
    dofs = int(sum(part_dofs.values()))
    # a rig's hybrid or solid model is a tied system: prepare_system chooses for it with amg_cost_known=False
    method = choose_method(dofs, n_rhs=len(UNIT_LOADS), amg_cost_known=False) if solver == "auto" else solver
    needed = BASE_BYTES + BYTES_PER_DOF[method] * dofs
    from rvcoax.geometry.model.workload import available_memory_bytes

    return MemoryEstimate(model=model, mesh_size_mm=size, dofs=dofs, part_dofs=part_dofs, solver=method,
                          bytes_needed=needed, bytes_available=available_memory_bytes())


def peak_memory_bytes(rig: Rig, model: str, mesh_size_mm: float | None = None, solver: str = "auto") -> float:
    """Estimated peak memory of solving ``rig``'s model, from the rig alone (nothing is meshed or built).

    Parameters
    ----------
    rig : Rig
        A validated rig.
    model : str
        ``beam``, ``hybrid`` or ``solid``.
    mesh_size_mm : float, optional
        The solids' global mesh size (the rig file's when None).
    solver : str
        The solver asked for (``auto``: the one the size would choose).

    Returns
    -------
    float
        Bytes: a beam model's counted from its geometry (:func:`rvcoax.geometry.model.workload.beam_size`), a solid
        or hybrid model's by :func:`estimate_memory` (measured bytes per DOF; 1.7–1.8 times the reference rig's
        measured peaks).
    """
    if model == "beam":
        from rvcoax.geometry.model.workload import beam_size

        return beam_size(rig).workload(rig.mesh.max_element_length_mm).bytes_needed
    return estimate_memory(rig, model, mesh_size_mm, solver).bytes_needed


def memory_problem(rig: Rig, model: str, mesh_size_mm: float | None = None, solver: str = "auto") -> str | None:
    """A refusal with the estimate and a suggestion when a solid/hybrid model would not fit in memory."""
    if model == "beam":
        return None
    estimate = estimate_memory(rig, model, mesh_size_mm, solver)
    if estimate.fits:
        return None
    largest = max(estimate.part_dofs, key=estimate.part_dofs.get)
    room = estimate.bytes_available
    # DOFs grow about as h^-3: the mesh size at which this model would fit, rounded up to 0.5 mm
    scale = max((estimate.bytes_needed - BASE_BYTES) / max(0.8 * room - BASE_BYTES, 1.0), 1.0)
    coarser = math.ceil(2.0 * estimate.mesh_size_mm * scale ** (1.0 / 3.0)) / 2.0
    advice = f"use a coarser mesh (--mesh-size-mm {coarser:g} or more)"
    if model == "solid":
        hybrid = estimate_memory(rig, "hybrid", None, solver)
        if hybrid.fits:
            advice += (f", or --model hybrid (only {', '.join(hybrid.part_dofs)} as solids: about {hybrid.dofs:.2g} DOF "
                       f"at the rig's {hybrid.mesh_size_mm:g} mm)")
    return (f"the {model} model at mesh size {estimate.mesh_size_mm:g} mm would have about {estimate.dofs:.3g} DOF "
            f"(largest part '{largest}': {estimate.part_dofs[largest]:.3g}) and need about "
            f"{_gigabytes(estimate.bytes_needed)} GB with {estimate.solver} ({BYTES_PER_DOF[estimate.solver] / 1e3:g} kB "
            f"per DOF, measured), but only {_gigabytes(room)} GB of memory are available; {advice}. "
            "Nothing was meshed.")


def _gigabytes(n_bytes: float) -> str:
    return f"{n_bytes / 1e9:.3g}" if n_bytes < 1e12 else f"{n_bytes / 1e9:,.0f}"

