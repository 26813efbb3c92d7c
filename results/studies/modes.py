"""The rig's natural frequencies and modes about each load case's operating point, and where they meet its speeds.

A pure function of (rig, load cases, settings): :func:`run_modes`.

- **Operating point.** The stiffness is the static model's (:func:`rvcoax.results.sweep.prepare_model`: the same
  assembly and the same factorisation). A rig whose bearings are all linear has one stiffness in every case: its
  modes are computed once and hold for every case. A rig with nonlinear bearings (radial clearance, ball bearings
  from geometry) is first solved for its cases (:func:`rvcoax.results.sweep.run_sweep`, Newton on the condensed
  bearing motions); each case's modes then use every nonlinear bearing's tangent ∂F/∂w at that case's solution
  (a clearance open or closed as it is there), applied to the static factorisation as a low-rank update
  (:class:`rvcoax.fem.modal.LowRankUpdate`).
- **Modes.** K φ = ω² M φ, the lowest N by shift-invert Lanczos on the static factorisation
  (:func:`rvcoax.fem.modal.natural_modes`); M from every piece's mass form
  (:func:`rvcoax.geometry.model.mass.rig_mass_matrix`).
- **What each mode is.** Its kinetic energy split by direction (axial u_x; lateral vertical u_y with θ_z; lateral
  horizontal u_z with θ_y; torsional θ_x; on solid parts from each slice's rigid motion, fitted by mass-weighted
  least squares), its class (the direction with at least :data:`CLASS_SHARE` of it, else ``mixed``), its strain
  energy per part and per spring (½ φᵀ K_piece φ over ½ ω², the nonlinear bearings' tangent counted with them)
  with the piece that owns most of it, and its effective modal mass along x, y, z and about the axis
  (Γ² = (φᵀ M r)², r a rigid motion of the whole rig; φ mass-normalised).
- **Interference.** Each mode's frequency against the excitation orders of ``[speeds]`` (motor ×1, ×2, the input
  gear mesh, the reducer's output ×1) over the motor's speed range: the crossing speeds n = 60 f / order, with the
  separation margin of each from the range.
- **Gyroscopic effects** are neglected. The criterion, checked per mode: γ = Σ Ω_i J_p,i (θ_y,i² + θ_z,i²) / ω
  over the rotating nodes (Ω_i the speed of the shaft line the node turns with at the top of the range, J_p,i its
  polar mass moment, φ mass-normalised) bounds the relative split of the forward and backward whirl frequencies;
  it must stay below :data:`GYROSCOPIC_LIMIT`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import DOFS_PER_NODE, beam, bushing
from rvcoax.fem.craig_bampton import INTERFACE_FACTOR, append_interface_modes
from rvcoax.fem.errors import RvcoaxError
from rvcoax.fem.modal import LowRankUpdate, ModalError, Modes, natural_modes
from rvcoax.geometry.model.mass import housing_frequencies, housing_modes, part_masses, rig_mass_matrix
from rvcoax.geometry.model.nonlinear_bearings import nonlinear_bearing_names
from rvcoax.geometry.model.preflight import CLASS_SHARE, DIRECTIONS, free_body, motion_class
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.sweep import ModelError, SweepSettings, prepare_model, run_sweep

__all__ = ["CLASS_SHARE", "DIRECTIONS", "FREE_BODY_HZ", "GYROSCOPIC_LIMIT", "HOUSING_DYNAMICS", "CaseModes", "Crossing",
           "ModalStudy",
           "Mode", "ModeSettings", "ModesError", "crossing_rows", "crossings", "excitation_orders", "mode_field",
           "mode_rows", "modes", "run_modes"]

HOUSING_DYNAMICS = ("auto", "craig-bampton", "guyan")
"""How a ``[[housings]]`` entry with ``self_weight`` moves in the modes (:class:`ModeSettings`)."""
GYROSCOPIC_LIMIT = 0.02
"""γ above this (a whirl split of 2 % or more of the frequency) makes the neglect of gyroscopic effects wrong."""
FREE_BODY_HZ = 0.01
"""A mode below this is a part moving as a rigid body (a support missing): named, and refused."""


class ModesError(RvcoaxError, ValueError):
    """A modal analysis that cannot be done as asked (mode count, speeds), in the user's terms."""

    stage = "cannot compute the natural frequencies"


@dataclass(frozen=True)
class ModeSettings:
    """How to compute the modes: how many, which model, solver and mesh (as :class:`SweepSettings`), and how the
    mass of a ``[[housings]]`` entry with ``self_weight`` enters: ``housing_dynamics`` ``"auto"`` (Craig–Bampton
    where its lowest fixed-interface mode is below 3 × the top rig frequency, else Guyan), ``"craig-bampton"``
    (at least 2 fixed-interface modes) or ``"guyan"``."""

    n_modes: int = 20
    model: str = "beam"
    solver: str = "auto"
    mesh_size_mm: float | None = None
    housing_dynamics: str = "auto"

    def __post_init__(self) -> None:
        if isinstance(self.n_modes, bool) or not isinstance(self.n_modes, int) or self.n_modes < 1:
            raise ModesError(f"the number of modes must be a whole number ≥ 1, got {self.n_modes!r}")
        SweepSettings(model=self.model, solver=self.solver, mesh_size_mm=self.mesh_size_mm)  # checks them
        if self.housing_dynamics not in HOUSING_DYNAMICS:
            raise ModesError(f"housing dynamics must be one of {', '.join(HOUSING_DYNAMICS)}, got "
                             f"{self.housing_dynamics!r}")

    def sweep_settings(self) -> SweepSettings:
        # an eigensolver needs an exact inverse: a direct solver, never AMG's approximate one
        solver = "superlu" if self.model == "beam" and self.solver == "auto" else self.solver
        if solver in ("auto", "amg"):
            from rvcoax.fem.solvers import pardiso_available

            solver = "pardiso" if pardiso_available() else "superlu"
        return SweepSettings(model=self.model, solver=solver, mesh_size_mm=self.mesh_size_mm)


@dataclass(frozen=True)
class Mode:
    """One natural mode about one operating point.

    ``direction_share``: kinetic energy share per :data:`DIRECTIONS`; ``energy_share``: strain energy share per
    part (``part:<name>``) and spring (``bearing:<name>``, ``coupling:…``, ``mount:…``, ``joint:…``,
    ``housing:<name>``), largest first; ``effective_mass``: Γ² along ``x_kg``, ``y_kg``, ``z_kg`` and
    ``torsion_kg_m2`` about the axis; ``gyroscopic_ratio``: γ of the module's criterion.
    """

    number: int
    frequency_hz: float
    kind: str
    direction_share: dict
    energy_share: dict
    effective_mass: dict
    gyroscopic_ratio: float

    @property
    def owner(self) -> str:
        """The part or spring that stores most of the mode's strain energy."""
        return next(iter(self.energy_share), "")


@dataclass(frozen=True, eq=False)
class CaseModes:
    """The modes about one operating point: ``label`` names the load case (``every load case`` for a linear rig)."""

    label: str
    case: LoadCase | None
    modes: tuple[Mode, ...]
    shapes: np.ndarray = field(repr=False)  # (n_dofs, k), mass-normalised
    method: str = ""


@dataclass(frozen=True)
class Crossing:
    """Where an excitation order meets a mode: motor speed (rpm) of the crossing, and its margin from the range."""

    case: str
    mode: int
    frequency_hz: float
    order: str
    crossing_rpm: float
    inside: bool
    margin_percent: float  # 0 inside the range; else the distance to the nearest end over that end


@dataclass(frozen=True, eq=False)
class ModalStudy:
    """Every operating point's modes, the interference with the speeds, and the checks made."""

    rig: Rig
    settings: ModeSettings
    system: object  # RigSystem
    mass: sp.csr_matrix = field(repr=False)
    cases: tuple[CaseModes, ...]
    part_mass_kg: dict
    crossings: tuple[Crossing, ...] = ()
    orders: tuple = ()
    housing_limits_hz: dict = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    seconds: dict = field(default_factory=dict)

    @property
    def gyroscopic_ratio_max(self) -> float:
        return max((m.gyroscopic_ratio for c in self.cases for m in c.modes), default=0.0)


def excitation_orders(rig: Rig) -> tuple[tuple[str, float], ...]:
    """(name, order relative to the motor speed) of each excitation ``[speeds]`` defines."""
    s = rig.speeds
    if s is None:
        return ()
    return (("motor ×1", 1.0), ("motor ×2", 2.0), (f"input gear mesh ×{s.input_gear_teeth}", float(s.input_gear_teeth)),
            (f"reducer output ×1 (1/{s.reduction_ratio:g})", 1.0 / s.reduction_ratio))


def crossings(rig: Rig, cases: tuple[CaseModes, ...], reach: float = 1.25) -> tuple[Crossing, ...]:
    """Every (mode, order) whose crossing speed is in the motor's range or within ``reach`` × its top."""
    if rig.speeds is None:
        return ()
    low, high = rig.speeds.motor_rpm
    out = []
    for case in cases:
        for mode in case.modes:
            for name, order in excitation_orders(rig):
                speed = 60.0 * mode.frequency_hz / order
                if speed > reach * high:
                    continue
                inside = low <= speed <= high
                margin = 0.0 if inside else (100.0 * (speed - high) / high if speed > high else
                                             100.0 * (low - speed) / low)
                out.append(Crossing(case=case.label, mode=mode.number, frequency_hz=mode.frequency_hz, order=name,
                                    crossing_rpm=speed, inside=inside, margin_percent=margin))
    return tuple(out)


def run_modes(rig: Rig, cases: tuple[LoadCase, ...] | None = None, settings: ModeSettings = ModeSettings(),
              cache_dir=None) -> ModalStudy:
    """The rig's natural modes about each load case's operating point.

    Parameters
    ----------
    rig : Rig
        A validated rig.
    cases : tuple of LoadCase, optional
        The load cases (their operating points matter only with nonlinear bearings); default the rig's own
        (:func:`rvcoax.loadcases.cases.default_cases`).
    settings : ModeSettings
    cache_dir : path, optional
        Mesh and housing cache.

    Returns
    -------
    ModalStudy

    Raises
    ------
    ModelError
        A part without support (named), as for a static solve.
    ModesError
        More modes than the model has DOFs with mass; a mode at zero frequency (the part that moves is named).
    """

    started = time.perf_counter()
    seconds = {}
    try:
        prepared = prepare_model(rig, settings.sweep_settings())
    except ModelError as error:
        if "singular" not in str(error):
            raise
        raise ModesError(_free_body_text(rig, settings, cache_dir)) from None
    system = prepared.system
    seconds["assemble_and_factorise"] = time.perf_counter() - started
    lap = time.perf_counter()
    mass = rig_mass_matrix(system, cache_dir)
    seconds["mass"] = time.perf_counter() - lap
    nonlinear = nonlinear_bearing_names(rig)
    notes = []
    operating, analysis_rows = _operating_points(rig, cases, settings, prepared, seconds)
    if not nonlinear:
        notes.append("every bearing is linear: the stiffness, and so the modes, are the same in every load case")
    else:
        notes.append(f"nonlinear bearings ({', '.join(nonlinear)}): each case's modes use their tangent stiffness "
                     "at that case's static solution")
    lap = time.perf_counter()
    analysis = _ModeAnalysis(system, mass, analysis_rows)
    results = _case_modes(system, mass, prepared, operating, analysis, n_modes=settings.n_modes, housings=[])
    chosen = []
    if any(h.self_weight for h in rig.housings) and settings.housing_dynamics != "guyan":
        top = max((m.frequency_hz for c in results for m in c.modes), default=0.0)
        chosen = housing_modes(system, top, settings.housing_dynamics, cache_dir)
        if any(h.kept for h in chosen):  # solved again with the housings' fixed-interface modes as extra DOFs
            results = _case_modes(system, mass, prepared, operating, analysis, n_modes=settings.n_modes,
                                  housings=chosen)
    seconds["eigen"] = time.perf_counter() - lap
    limits = housing_frequencies(system, cache_dir)
    notes += _housing_notes(rig, chosen, results)
    gamma = max((m.gyroscopic_ratio for c in results for m in c.modes), default=0.0)
    if rig.speeds is not None:
        verdict = "neglected rightly" if gamma <= GYROSCOPIC_LIMIT else "NOT negligible: treat these results with care"
        notes.append(f"gyroscopic effects {verdict}: γ ≤ {gamma:.2g} for every mode at {rig.speeds.motor_rpm[1]:g} "
                     f"rpm (limit {GYROSCOPIC_LIMIT:g})")
    seconds["total"] = time.perf_counter() - started
    results = tuple(results)
    return ModalStudy(rig=rig, settings=settings, system=system, mass=mass, cases=results,
                      part_mass_kg=part_masses(system, mass), crossings=crossings(rig, results),
                      orders=excitation_orders(rig), housing_limits_hz=limits, notes=tuple(notes), seconds=seconds)


def _case_modes(system, mass, prepared, operating, analysis, *, n_modes: int, housings: list) -> list:  # noqa: PLR0913
    """Each operating point's modes, described; ``housings`` (:class:`rvcoax.geometry.model.mass.HousingModes`) with
    kept fixed-interface modes add them as extra DOFs (Craig–Bampton), whose strain energy is their housing's."""
    attached = [h for h in housings if h.kept]
    n = system.n_dofs
    stiffness, full_mass, elimination, solve = system.stiffness, mass, system.elimination, prepared.reduced_solve
    if attached:
        stiffness, full_mass, elimination, solve = append_interface_modes(
            stiffness, mass, elimination, [h.attached for h in attached], prepared.reduced_solve)
    extra = stiffness.shape[0] - n
    results = []
    for label, case, update in operating:
        if update is not None and extra:
            update = LowRankUpdate(sp.hstack([update.operator, sp.csr_matrix((update.operator.shape[0], extra))]).tocsr(),
                                   update.matrix)
        try:
            modes = natural_modes(stiffness, full_mass, elimination, n_modes, reduced_solve=solve, update=update)
        except ModalError as error:
            raise ModesError(str(error)) from None
        interface = None
        if extra:
            interface = _Interface([(f"housing:{h.name}", h.attached.stiffness) for h in attached],
                                   modes.shapes[n:], full_mass[:n, n:].tocsr())
            modes = Modes(modes.eigenvalues, modes.shapes[:n], modes.method)
            update = None if update is None else LowRankUpdate(update.operator[:, :n], update.matrix)
        _check_free_bodies(system, mass, modes, label)
        described = tuple(analysis.describe(i + 1, modes, i, update, interface) for i in range(modes.eigenvalues.size))
        results.append(CaseModes(label, case, described, modes.shapes, modes.method))
    return results


@dataclass(frozen=True, eq=False)
class _Interface:
    """Fixed-interface (Craig–Bampton) coordinates of the modes: per housing (name, modal stiffness (r,)), their
    values (R, k) and their mass coupling to the system's DOFs (n × R)."""

    housings: list
    values: np.ndarray
    coupling: sp.csr_matrix

    def energies(self, index: int) -> dict:
        out, start = {}, 0
        for name, stiffness in self.housings:
            eta = self.values[start:start + stiffness.size, index]
            out[name] = float(0.5 * np.sum(stiffness * eta * eta))
            start += stiffness.size
        return out


def _housing_notes(rig: Rig, chosen: list, results: list) -> list[str]:
    """How each housing's mass entered: Guyan, or Craig–Bampton with how many fixed-interface modes, and why."""
    top = max((m.frequency_hz for c in results for m in c.modes), default=0.0)
    notes = []
    by_name = {h.name: h for h in chosen}
    for housing in rig.housings:
        h = by_name.get(housing.name)
        if not housing.self_weight:
            notes.append(f"housing {housing.name}: no self_weight, so no inertia of its own (its mass is its part's)")
        elif h is None:
            notes.append(f"housing {housing.name}: Guyan (static-shape) mass, as asked")
        elif h.kept:
            why = (f"below {INTERFACE_FACTOR:g} × the top rig frequency {top:.0f} Hz"
                   if h.lowest_interface_hz < INTERFACE_FACTOR * top else "as asked")
            notes.append(f"housing {housing.name}: Craig–Bampton with {h.kept} fixed-interface mode(s) (the lowest "
                         f"{h.lowest_interface_hz:.0f} Hz, {why})")
        else:
            which = ("lowest mode with its attachments free (a lower bound of the fixed-interface ones)"
                     if h.free_interface_bound else "lowest fixed-interface mode")
            notes.append(f"housing {housing.name}: Guyan (static-shape) mass; its {which}, "
                         f"{h.lowest_interface_hz:.0f} Hz, is above {INTERFACE_FACTOR:g} × the top rig frequency")
    return notes


def _operating_points(rig: Rig, cases, settings: ModeSettings, prepared, seconds: dict):
    """[(label, case, LowRankUpdate or None)] per operating point, and each nonlinear bearing's rows of w: one point
    for a linear rig; else each case's Newton solution (a sweep on ``prepared``) and its bearings' tangent."""
    from rvcoax.loadcases.cases import default_cases

    if not nonlinear_bearing_names(rig):
        return [("every load case", None, None)], []
    chosen = tuple(cases) if cases else default_cases(rig)
    lap = time.perf_counter()
    sweep = run_sweep(rig, chosen, settings.sweep_settings(), prepared=prepared, engineering=False)
    seconds["operating_points"] = time.perf_counter() - lap
    bearings = sweep.nonlinear_bearings
    from_rest = rig.paths.measured_from == "aligned_at_rest"
    operating = []
    for i, result in enumerate(sweep.cases):
        u = sweep.case_displacements[:, i] + (sweep.rest_displacement if from_rest else 0.0)
        _, tangent = bearings.laws(bearings.operator @ u)
        update = LowRankUpdate(bearings.operator, tangent - np.diag(bearings.reference_stiffness))
        operating.append((result.case.label, result.case, update))
    return operating, [(str(spring), rows) for spring, _, rows in bearings.spring_rows()]


def _free_body_text(rig: Rig, settings: ModeSettings, cache_dir) -> str:
    """Why a singular rig cannot vibrate: its zero-frequency modes (found with K + M factorised, σ = −1 rad²/s²) and
    the parts that carry them."""
    from rvcoax.geometry.model.assemble import assemble_rig

    options = {} if settings.mesh_size_mm is None else {"mesh_size_mm": settings.mesh_size_mm}
    system = assemble_rig(rig, settings.model, **options)
    mass = rig_mass_matrix(system, cache_dir)
    modes = natural_modes(system.stiffness, mass, system.elimination, 6, shift=-1.0)
    try:
        _check_free_bodies(system, mass, modes, "the rig")
    except ModesError as error:
        return str(error)
    return "the stiffness matrix is singular, but no mode at zero frequency was found: check the springs' units"


def _check_free_bodies(system, mass, modes: Modes, label: str) -> None:
    """Refuse a zero-frequency mode, naming the parts that carry its motion."""
    low = np.flatnonzero(modes.frequencies_hz < FREE_BODY_HZ)
    if not low.size:
        return
    phi = modes.shapes[:, low[0]]
    body = free_body(phi * (mass @ phi), _dof_owners(system), _ModeAnalysis(system, mass)._directions(phi))
    raise ModesError(f"{label}: {low.size} mode(s) at zero frequency ({body.kind} motion of mode {low[0] + 1}): part(s) "
                     f"{', '.join(body.parts)} move as a free body — a support or a stiffness component is missing")


def _dof_owners(system) -> np.ndarray:
    frame = system.frame
    owner = np.full(system.n_dofs, "", dtype=object)
    owner[:DOFS_PER_NODE * frame.node_part.size] = np.repeat(frame.node_part, DOFS_PER_NODE)
    for s in system.solids:
        owner[s.offset:s.offset + s.n_dofs] = s.name
    return owner


class _ModeAnalysis:
    """What each mode of one system is: directions, energies, effective masses, gyroscopic ratio."""

    def __init__(self, system, mass, update_rows=()):
        self.system = system
        self.update_rows = list(update_rows)  # (spring name, rows of w) of each nonlinear bearing
        self.mass = mass
        rig, frame = system.rig, system.frame
        structure = frame.structure
        self.frame_dofs = DOFS_PER_NODE * structure.n_nodes
        component = system.dofs.component
        self.frame_direction = np.full(self.frame_dofs, -1)
        for c, d in ((0, 0), (1, 1), (5, 1), (2, 2), (4, 2), (3, 3)):
            self.frame_direction[np.flatnonzero(component[:self.frame_dofs] == c)] = d
        # beams: element matrices per part
        beams = structure.beams
        self.element_part = frame.node_part[beams.connectivity[:, 0]] if beams.connectivity.size else np.zeros(0, str)
        if beams.connectivity.size:
            rows, _, values = beam.stiffness_triplets(structure.coordinates, beams)
            self.element_k = values.reshape(-1, 12, 12)
            self.element_dofs = beam.element_dofs(beams.connectivity)
        self.spring_operator, self.spring_dofs = bushing.relative_motion_operator(structure.coordinates,
                                                                                  structure.bushings)
        self.spring_k = np.asarray(structure.bushings.stiffness, float)
        self.spring_names = [str(n) for n in frame.bushing_names]
        self.housings = []
        if rig.housings:
            from rvcoax.geometry.model.housings import condensed_housing

            for h in rig.housings:
                nodes = [frame.node(h.part, x) for x in h.attachments_x_mm]
                dofs = (DOFS_PER_NODE * np.asarray(nodes)[:, None] + np.arange(DOFS_PER_NODE)).ravel()
                self.housings.append((f"housing:{h.name}", dofs, h.stiffness_factor * condensed_housing(rig, h).matrix))
        self.solid_blocks = [(s, system.stiffness[s.offset:s.offset + s.n_dofs, s.offset:s.offset + s.n_dofs])
                             for s in system.solids]
        self.slices = [_SolidSlices(s, mass) for s in system.solids]
        # rigid motions of the whole rig: translations x, y, z and the rotation about the x axis
        position, comp = system.dofs.position, component
        rigid = np.zeros((system.n_dofs, 4))
        translational = np.ones(system.n_dofs, bool)
        translational[:self.frame_dofs] = comp[:self.frame_dofs] < 3
        for axis in range(3):
            rigid[translational & (comp == axis), axis] = 1.0
        rigid[~translational & (comp == 3), 3] = 1.0
        rigid[translational & (comp == 1), 3] = -position[translational & (comp == 1), 2]
        rigid[translational & (comp == 2), 3] = position[translational & (comp == 2), 1]
        self.rigid = rigid
        # gyroscopic data: the speed (rad/s at the top of the range) each frame node turns with, its polar moment
        self.node_speed = _node_speeds(rig, frame)
        diagonal = mass.diagonal()
        self.node_polar = diagonal[3:self.frame_dofs:DOFS_PER_NODE]
        self.part_speed = {p.name: s for p, s in zip(rig.parts, _part_speeds(rig))}

    def describe(self, number: int, modes: Modes, index: int, update: LowRankUpdate | None,  # noqa: PLR0913
                 interface: _Interface | None = None) -> Mode:
        phi = modes.shapes[:, index]
        omega2 = float(modes.eigenvalues[index])
        frequency = float(modes.frequencies_hz[index])
        directions = self._directions(phi)
        kind = motion_class(directions)
        energy = self._energies(phi, update)
        if interface is not None:
            for name, value in interface.energies(index).items():
                energy[name] = energy.get(name, 0.0) + value
        total = sum(energy.values())
        scale = total if total > 0 else 1.0
        shares = {k: v / scale for k, v in sorted(energy.items(), key=lambda kv: -kv[1]) if v / scale >= 1e-4}
        gamma = self._gyroscopic(phi, omega2)
        participation = self.rigid.T @ (self.mass @ phi)
        if interface is not None:  # the housings' modal coordinates carry mass coupled to the rig's DOFs
            participation = participation + self.rigid.T @ (interface.coupling @ interface.values[:, index])
        effective = {"x_kg": float(participation[0] ** 2), "y_kg": float(participation[1] ** 2),
                     "z_kg": float(participation[2] ** 2), "torsion_kg_m2": float(participation[3] ** 2)}
        return Mode(number=number, frequency_hz=frequency, kind=kind, direction_share=directions, energy_share=shares,
                    effective_mass=effective, gyroscopic_ratio=gamma)

    def _directions(self, phi: np.ndarray) -> dict:
        kinetic = phi * (self.mass @ phi)
        sums = np.zeros(4)
        frame = kinetic[:self.frame_dofs]
        for d in range(4):
            sums[d] += frame[self.frame_direction == d].sum()
        for slices in self.slices:
            sums += slices.direction_energy(phi)
        sums = np.maximum(sums, 0.0)
        total = sums.sum() or 1.0
        return {name: float(v / total) for name, v in zip(DIRECTIONS, sums)}

    def _energies(self, phi: np.ndarray, update: LowRankUpdate | None) -> dict:
        energy: dict[str, float] = {}
        if self.element_part.size:
            local = phi[self.element_dofs]
            per_element = 0.5 * np.einsum("ei,eij,ej->e", local, self.element_k, local)
            for part in np.unique(self.element_part):
                energy[f"part:{part}"] = float(per_element[self.element_part == part].sum())
        u = np.where(self.spring_dofs >= 0, phi[np.maximum(self.spring_dofs, 0)], 0.0)
        delta = np.einsum("eij,ej->ei", self.spring_operator, u)
        for name, k, d in zip(self.spring_names, self.spring_k, delta):
            energy[name] = energy.get(name, 0.0) + float(0.5 * np.sum(k * d * d))
        if update is not None and update.operator.shape[0]:
            w = update.operator @ phi
            extra = 0.5 * w * (update.matrix @ w)  # per condensed row: a nonlinear bearing's tangent minus reference
            for name, where in self.update_rows:
                energy[name] = energy.get(name, 0.0) + float(extra[where].sum())
        for name, dofs, matrix in self.housings:
            energy[name] = float(0.5 * phi[dofs] @ matrix @ phi[dofs])
        for s, block in self.solid_blocks:
            local = phi[s.offset:s.offset + s.n_dofs]
            energy[f"part:{s.name}"] = energy.get(f"part:{s.name}", 0.0) + float(0.5 * local @ (block @ local))
        return {k: max(v, 0.0) for k, v in energy.items()}

    def _gyroscopic(self, phi: np.ndarray, omega2: float) -> float:
        if omega2 <= 0:
            return math.inf
        nodes = phi[:self.frame_dofs].reshape(-1, DOFS_PER_NODE)
        tilt = nodes[:, 4] ** 2 + nodes[:, 5] ** 2
        gyro = float(np.sum(self.node_speed * self.node_polar * tilt))
        for slices in self.slices:
            gyro += self.part_speed.get(slices.name, 0.0) * slices.gyroscopic(phi)
        return gyro / math.sqrt(omega2)


def _part_speeds(rig: Rig) -> list[float]:
    """Each part's spin (rad/s) at the top of the motor's range: shafts joined to T1's part through couplings and
    shaft-to-shaft joints turn at the motor speed, those joined to T2's at the output speed, other shafts at the
    motor speed (the safe side); bodies do not turn. Zero without ``[speeds]``."""
    if rig.speeds is None:
        return [0.0] * len(rig.parts)
    shafts = {p.name for p in rig.parts if p.role == "shaft"}
    links: dict[str, set[str]] = {name: set() for name in shafts}
    for c in list(rig.couplings) + list(rig.joints):
        a, b = c.from_.part, c.to.part
        if a in shafts and b in shafts:
            links[a].add(b)
            links[b].add(a)

    def line(start: str) -> set[str]:
        seen, todo = set(), [start]
        while todo:
            name = todo.pop()
            if name in seen or name not in links:
                continue
            seen.add(name)
            todo.extend(links[name])
        return seen

    motor = rig.speeds.motor_rpm[1] * 2 * math.pi / 60
    output_line = line(rig.torques.T2.part) - line(rig.torques.T1.part)
    return [0.0 if p.role != "shaft" else (motor / rig.speeds.reduction_ratio if p.name in output_line else motor)
            for p in rig.parts]


def _node_speeds(rig: Rig, frame) -> np.ndarray:
    speed = dict(zip((p.name for p in rig.parts), _part_speeds(rig)))
    return np.array([speed.get(str(p), 0.0) for p in frame.node_part])


class _SolidSlices:
    """A solid part cut into slices along x; each slice's rigid motion fitted to a mode by mass-weighted least
    squares, for the mode's direction shares and gyroscopic ratio."""

    def __init__(self, part, mass):
        from rvcoax.fem.solid import dof_locations

        self.name = part.name
        self.offset = part.offset
        coordinates, dofs = dof_locations(part.basis)
        self.dofs = dofs + part.offset
        block = mass[part.offset:part.offset + part.n_dofs, part.offset:part.offset + part.n_dofs]
        lumped = np.asarray(block.sum(axis=1)).ravel()[dofs[:, 0]]  # row sums: each node's share of the mass
        x = coordinates[:, 0]
        count = max(4, int(round((x.max() - x.min()) / 0.005)))
        edges = np.linspace(x.min(), x.max(), count + 1)
        self.slice_of = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, count - 1)
        self.count = count
        self.m = lumped
        self.block = block
        self.coordinates = coordinates
        self.centre = np.zeros((count, 3))
        self.slice_mass = np.bincount(self.slice_of, weights=lumped, minlength=count)
        for c in range(3):
            self.centre[:, c] = np.bincount(self.slice_of, weights=lumped * coordinates[:, c], minlength=count) / \
                np.maximum(self.slice_mass, 1e-300)
        self.r = coordinates - self.centre[self.slice_of]
        r = self.r
        # inertia tensor of each slice about its centre
        inertia = np.zeros((count, 3, 3))
        r2 = np.sum(r * r, axis=1)
        for i in range(3):
            for j in range(3):
                value = lumped * ((r2 if i == j else 0.0) - r[:, i] * r[:, j])
                inertia[:, i, j] = np.bincount(self.slice_of, weights=value, minlength=count)
        self.inertia = inertia

    def _fit(self, phi: np.ndarray):
        u = phi[self.dofs]
        m = self.m
        mean = np.stack([np.bincount(self.slice_of, weights=m * u[:, c], minlength=self.count) for c in range(3)], 1)
        mean /= np.maximum(self.slice_mass, 1e-300)[:, None]
        moment = np.cross(self.r, u) * m[:, None]  # Σ m r × u = I θ for a rigid motion
        h = np.stack([np.bincount(self.slice_of, weights=moment[:, c], minlength=self.count) for c in range(3)], 1)
        theta = np.linalg.solve(self.inertia + 1e-30 * np.eye(3), h[:, :, None])[:, :, 0]
        return u, mean, theta

    def direction_energy(self, phi: np.ndarray) -> np.ndarray:
        u, mean, theta = self._fit(phi)
        m, inertia = self.slice_mass, self.inertia
        parts = np.array([
            np.sum(m * mean[:, 0] ** 2),
            np.sum(m * mean[:, 1] ** 2 + inertia[:, 2, 2] * theta[:, 2] ** 2),
            np.sum(m * mean[:, 2] ** 2 + inertia[:, 1, 1] * theta[:, 1] ** 2),
            np.sum(inertia[:, 0, 0] * theta[:, 0] ** 2),
        ])
        local = np.zeros(self.block.shape[0])
        local[self.dofs.ravel() - self.offset] = u.ravel()
        exact = float(local @ (self.block @ local))  # the part's kinetic energy (×2/ω²); the fit's parts rescaled to it
        fitted = parts.sum()
        return parts * (exact / fitted) if fitted > 0 else parts

    def gyroscopic(self, phi: np.ndarray) -> float:
        _, _, theta = self._fit(phi)
        return float(np.sum(self.inertia[:, 0, 0] * (theta[:, 1] ** 2 + theta[:, 2] ** 2)))


def mode_rows(study: ModalStudy) -> list[dict]:
    """The mode table: one row per operating point and mode, every value with its unit in its key.

    Parameters
    ----------
    study : ModalStudy

    Returns
    -------
    list of dict
        ``load_case``, ``mode``, ``frequency_Hz``, ``class``, the kinetic energy shares ``axial_percent`` …
        ``torsional_percent``, the owner of most strain energy (``owner``, ``owner_energy_percent``) and the next
        two, the effective masses ``effective_mass_{x,y,z}_kg`` and ``effective_inertia_x_kg_m2``, and
        ``gyroscopic_ratio``.
    """
    rows = []
    for case in study.cases:
        for mode in case.modes:
            ranked = list(mode.energy_share.items())
            row = {"load_case": case.label, "mode": mode.number, "frequency_Hz": mode.frequency_hz, "class": mode.kind}
            for name, share in mode.direction_share.items():
                row[f"{name.replace(' ', '_')}_percent"] = 100.0 * share
            for k in range(3):
                name, share = ranked[k] if k < len(ranked) else ("", 0.0)
                suffix = "" if k == 0 else f"_{k + 1}"
                row[f"owner{suffix}"] = name
                row[f"owner{suffix}_energy_percent"] = 100.0 * share
            row.update({"effective_mass_x_kg": mode.effective_mass["x_kg"],
                        "effective_mass_y_kg": mode.effective_mass["y_kg"],
                        "effective_mass_z_kg": mode.effective_mass["z_kg"],
                        "effective_inertia_x_kg_m2": mode.effective_mass["torsion_kg_m2"],
                        "gyroscopic_ratio": mode.gyroscopic_ratio})
            rows.append(row)
    return rows


def crossing_rows(study: ModalStudy) -> list[dict]:
    """The interference table: one row per (operating point, mode, order) crossing in or near the speed range.

    Parameters
    ----------
    study : ModalStudy
        A modal study; its crossings were computed with it (none where the rig has no ``[speeds]`` section).

    Returns
    -------
    list of dict
        ``load_case``, ``mode``, ``frequency_Hz``, ``order``, ``crossing_motor_rpm``, ``in_speed_range`` and
        ``margin_percent`` (0 inside the range; else the distance to its nearest end over that end).
    """
    return [{"load_case": c.case, "mode": c.mode, "frequency_Hz": c.frequency_hz, "order": c.order,
             "crossing_motor_rpm": c.crossing_rpm, "in_speed_range": c.inside, "margin_percent": c.margin_percent}
            for c in study.crossings]


def mode_field(study: ModalStudy, case_index: int, mode_index: int):
    """One mode on the rig's field mesh, for a picture.

    Parameters
    ----------
    study : ModalStudy
    case_index, mode_index : int
        Which operating point and mode (0-based).

    Returns
    -------
    (FieldMesh, (n, 3) array, (n,) array)
        The mesh (:func:`rvcoax.results.io.fields.sweep_field_mesh`), the mode's translation at each point and the
        section twist about the axis (rad per unit of the mass-normalised shape).
    """
    from types import SimpleNamespace

    from rvcoax.results.io.fields import sweep_field_mesh

    system = study.system
    mesh, _ = sweep_field_mesh(SimpleNamespace(system=system))
    phi = study.cases[case_index].shapes[:, mode_index]
    n_frame = system.frame.structure.n_nodes
    nodes = phi[:DOFS_PER_NODE * n_frame].reshape(-1, DOFS_PER_NODE)
    u = np.zeros((mesh.n_points, 3))
    twist = np.zeros(mesh.n_points)
    u[:n_frame] = nodes[:, :3]
    twist[:n_frame] = nodes[:, 3]
    start = n_frame
    for part in system.solids:
        basis = part.basis
        dofs = np.vstack([basis.nodal_dofs.T, basis.edge_dofs.T]) + part.offset
        count = dofs.shape[0]
        u[start:start + count] = phi[dofs]
        points = mesh.points[start:start + count]
        r2 = points[:, 1] ** 2 + points[:, 2] ** 2
        tangential = -points[:, 2] * u[start:start + count, 1] + points[:, 1] * u[start:start + count, 2]
        twist[start:start + count] = np.where(r2 > 0, tangential / np.maximum(r2, 1e-30), 0.0)
        start += count
    return mesh, u, twist


def modes(rig=None, cases=None, *, n_modes: int = 20, model: str = "beam", solver: str = "auto",  # noqa: PLR0913
          mesh_size_mm: float | None = None, housing_dynamics: str = "auto") -> ModalStudy:
    """The rig's natural frequencies and modes about each load case's operating point (the API of ``rvcoax modes``).

    Parameters
    ----------
    rig : Rig, path or None
        A validated rig, a rig file, or None for the built-in reference rig.
    cases : tuple of LoadCase, optional
        Operating points (they matter with nonlinear bearings); default the rig's own.
    n_modes : int
        How many of the lowest modes.
    model : {"beam", "hybrid", "solid"}
    solver : {"auto", "superlu", "pardiso"}
        A direct solver (AMG cannot serve an eigensolver; ``auto`` picks PARDISO where installed for solids).
    mesh_size_mm : float, optional
        Solid mesh size.
    housing_dynamics : {"auto", "craig-bampton", "guyan"}
        How a ``[[housings]]`` entry with ``self_weight`` moves: its Guyan (static-shape) mass, or with its
        fixed-interface modes as extra DOFs (Craig–Bampton); ``auto`` adds the modes below 3 × the top rig frequency.

    Returns
    -------
    ModalStudy
        Per operating point the modes (frequency, class, energy shares, effective masses), the crossings with
        the excitation orders of ``[speeds]``, and notes on what was assumed and checked.
    """
    from rvcoax.geometry.rigfile import load_rig

    if rig is None or not isinstance(rig, Rig):
        rig = load_rig(rig)
    return run_modes(rig, cases, ModeSettings(n_modes=n_modes, model=model, solver=solver, mesh_size_mm=mesh_size_mm,
                                                housing_dynamics=housing_dynamics))
