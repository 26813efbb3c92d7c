"""One factorisation for every candidate: unit-load superposition on the prepared base model.

The base rig is assembled and factorised once (:func:`rvcoax.results.sweep.prepare_model`). Its
responses to the unit loads (:data:`rvcoax.geometry.model.loads.UNIT_LOADS`) are read on the
measured paths as *unit paths* (n_unit_loads, n_path) in mm. Any load case and either datum is then a weighted
sum of unit paths, so a candidate's response is known for the data's cases and for cases that
were not measured (what the observability report needs to suggest a measurement).

How each candidate changes the unit paths, exactly, on the same factorisation:

- *load effects* (self-weight, force table, coupling and mount offsets, torque-proportional and
  engaged lateral loads): the rig's unit loads are rebuilt (:meth:`RigSystem.with_loads_of`) and
  the change is solved with the base factorisation;
- *spring effects* (a bearing's radial stiffness, a mount's vertical stiffness, beam models): the
  stiffness changes by Uᵀ δ U on a few spring components; the Woodbury identity gives
  u' = W(u + K⁻¹ Δf) with W(v) = v − G (I + δ U G)⁻¹ δ U v, G = K⁻¹ Uᵀ (a few solves), Δf the
  change of the loads (the springs' prestrain changes with their stiffness);
- anything else (shear deformation, bearing clearance, a rig that is not linear) is solved with a
  real sweep; a clearance reuses the factorisation through :func:`rvcoax.results.sweep.run_sweep`.

The generic *sentinel* loads (a unit lateral force or moment at a node of any part) are solved
here too, all at once.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import DOFS_PER_NODE, bushing
from rvcoax.fem.solvers import SolverError
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model.beam import SpringId, stress_free_motions
from rvcoax.geometry.model.loads import REST_LOADS, UNIT_LOADS, case_weights, gear_contact_torques
from rvcoax.results.studies.discrepancy.responses import PathLayout
from rvcoax.results.sweep import ModelError, SweepSettings, check_solution, prepare_model, run_sweep

__all__ = ["CANDIDATE_FAILURES", "Engine", "case_matrix", "prepare_engine"]

# what one candidate's solve may raise; the candidate is set aside with the reason and the run goes on
CANDIDATE_FAILURES = (ModelError, SolverError, np.linalg.LinAlgError, ValueError)

N_PER_UM = 1e6
RESIDUAL_LIMIT = 1e-6


def case_matrix(cases, from_rest: bool, contact_torques_Nm: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """W (n_cases, n_unit_loads): the weights of the unit loads in each case, minus the rest loads when Y is read
    from rest; ``contact_torques_Nm``: the rig's gear-mesh full-contact torques
    (:func:`rvcoax.geometry.gear_loads.gear_contact_torques`)."""
    rows = []
    for case in cases:
        weights = case_weights(case.input_torque_Nm, case.output_torque_Nm, include_rest=True,
                               contact_torques_Nm=contact_torques_Nm)
        if from_rest:
            for k in REST_LOADS:
                weights[k] -= 1.0
        rows.append([weights[k] for k in UNIT_LOADS])
    return np.array(rows, dtype=float).reshape(-1, len(UNIT_LOADS))


@dataclass(frozen=True, eq=False)
class Engine:
    """The base rig's factorised model and its unit paths (see the module docstring)."""

    rig: object
    settings: SweepSettings
    prepared: object
    unit: np.ndarray  # (n_dofs, 7) displacement per unit load
    path_operator: object  # (n_path, n_dofs) → u_y in mm, input stations then output stations
    stations_mm: dict
    length_mm: dict
    linear: bool

    @property
    def system(self):
        return self.prepared.system

    @property
    def unit_paths(self) -> np.ndarray:
        return np.asarray(self.path_operator @ self.unit).T  # (n_unit_loads, n_path)

    def layout(self, n_cases: int) -> PathLayout:
        return PathLayout(n_cases, self.stations_mm, self.length_mm)

    def full_paths(self, unit_paths: np.ndarray, cases, from_rest: bool | None = None) -> np.ndarray:
        """Flattened (case, shaft, station) paths of unit paths ``(n_unit_loads, n_path)`` for ``cases``."""
        return (self.case_weights(cases, from_rest) @ unit_paths).ravel()

    def case_weights(self, cases, from_rest: bool | None = None) -> np.ndarray:
        """W (n_cases, n_unit_loads) of :func:`case_matrix` for this rig (Y from rest as its file says, by default)."""
        from_rest = self.rig.paths.measured_from == "aligned_at_rest" if from_rest is None else from_rest
        return case_matrix(cases, from_rest, gear_contact_torques(self.rig))

    # -- candidates ---------------------------------------------------------------------------------------
    def supports(self, effect) -> bool:
        """Whether :meth:`unit_change` solves ``effect`` exactly on this factorisation."""
        return self.linear and (effect.response == "load" or (effect.response == "spring" and self.system.kind == "beam"))

    def unit_change(self, applied: list) -> np.ndarray:
        """Change of the unit paths (n_unit_loads, n_path) when the effects ``applied`` [(effect, values)] act together."""
        rig = self.rig
        for effect, values in applied:
            rig = effect.apply(rig, list(values))
        system = self.system
        base_loads = system.unit_loads
        springs_only = all(effect.response == "spring" for effect, _ in applied)
        try:
            loads = base_loads if springs_only else system.with_loads_of(rig).unit_loads
        except KeyError:  # a load where the base mesh has no node: the rig's own mesh, by a real sweep
            return self.swept_unit_paths(rig) - self.unit_paths
        operator, delta = self._springs(rig)
        change = np.zeros_like(self.unit) if springs_only else np.column_stack([loads[k] - base_loads[k]
                                                                                 for k in UNIT_LOADS])
        if operator is not None:  # the springs' prestrain K Δ0 with their new stiffness
            change[:, UNIT_LOADS.index("prestrain")] += self._prestrain_change(rig, operator, delta)
        solve = self.prepared.solve
        moved = solve(change) if np.any(change) else np.zeros_like(self.unit)
        u = self.unit + moved
        if operator is not None:
            g, ug = self._influence(operator)
            small = np.eye(delta.size) + delta[:, None] * ug
            if not np.linalg.cond(small) < 1e12:
                raise ModelError("the changed spring stiffness makes the model (nearly) singular")
            u = u - g @ np.linalg.solve(small, delta[:, None] * np.asarray(operator @ u))
            if not springs_only:
                self._check(system.stiffness + operator.T @ sp.diags(delta) @ operator, u,
                            self._loads_with(loads, change))
        elif np.any(change):
            self._check(system.stiffness, u, self._loads_with(loads, change))
        return np.asarray(self.path_operator @ (u - self.unit)).T

    def _influence(self, operator):
        """G = K⁻¹ Uᵀ and U G of a spring operator (cached: a grid of one spring reuses them)."""
        cache = self.__dict__.setdefault("_influence_cache", {})
        key = (operator.indices.tobytes(), operator.data.tobytes(), operator.indptr.tobytes())
        if key not in cache:
            g = np.asarray(self.prepared.solve(operator.T.toarray()))
            cache[key] = (g, np.asarray(operator @ g))
        return cache[key]

    def _loads_with(self, loads, change):
        return np.column_stack([self.system.unit_loads[k] for k in UNIT_LOADS]) + change

    def _check(self, stiffness, u, load) -> None:
        elimination = self.system.elimination
        residual = np.linalg.norm(elimination.T @ (stiffness @ u - load), axis=0)
        absolute = self.__dict__.get("_absolute_stiffness")
        if absolute is None:
            absolute = abs(self.system.stiffness)
            object.__setattr__(self, "_absolute_stiffness", absolute)
        scale = np.linalg.norm(elimination.T @ load, axis=0) + np.linalg.norm(
            elimination.T @ (absolute @ np.abs(u)), axis=0)
        worst = float(np.max(np.where(scale > 0, residual / np.where(scale > 0, scale, 1.0), 0.0)))
        if not np.all(np.isfinite(u)) or worst > RESIDUAL_LIMIT:
            raise ModelError(f"the updated unit responses miss equilibrium (relative residual {worst:.1e})")

    def _springs(self, rig):
        """U (stacked spring components) and δ (their stiffness change, SI) between the base rig and ``rig``."""
        frame = self.system.frame
        structure = frame.structure
        rows, components, delta = [], [], []
        for before, after in zip(self.rig.bearings, rig.bearings):
            change = (after.radial_stiffness_N_per_um - before.radial_stiffness_N_per_um) * N_PER_UM
            if change != 0.0:
                row = frame.bushing_names.index(SpringId("bearing", before.name))
                rows += [row, row]
                components += [0, 1]  # y and z of the radial operator
                delta += [change, change]
        for before, after in zip(self.rig.mounts, rig.mounts):
            change = (after.translational_stiffness_N_per_um[1] - before.translational_stiffness_N_per_um[1]) * N_PER_UM
            if change != 0.0:
                rows.append(frame.bushing_names.index(SpringId("mount", before.name)))
                components.append(0)
                delta.append(change)
        if not rows:
            return None, None
        radial = bushing.radial_operator(structure.coordinates, structure.bushings, rows, self.system.n_dofs)
        pick = np.array([2 * i + c for i, c in enumerate(components)])
        return radial[pick], np.array(delta, float)

    def _prestrain_change(self, rig, operator, delta) -> np.ndarray:
        structure = self.system.frame.structure
        stiffness = np.array(structure.bushings.stiffness, float, copy=True)
        for bearing in rig.bearings:
            row = self.system.frame.bushing_names.index(SpringId("bearing", bearing.name))
            stiffness[row, 1:3] = bearing.radial_stiffness_N_per_um * N_PER_UM
        for mount in rig.mounts:
            row = self.system.frame.bushing_names.index(SpringId("mount", mount.name))
            stiffness[row, 1] = mount.translational_stiffness_N_per_um[1] * N_PER_UM
        free = stress_free_motions(rig)
        if not np.any(free):
            return np.zeros(self.system.n_dofs)
        n = structure.n_dofs
        out = np.zeros(self.system.n_dofs)
        out[:n] = (bushing.prestrain_load(structure.coordinates, replace(structure.bushings, stiffness=stiffness), free, n)
                   - bushing.prestrain_load(structure.coordinates, structure.bushings, free, n))
        return out

    # -- a bearing clearance (nonlinear, condensed to the bearing's two radial motions) ------------------------
    def clearance_paths(self, bearing: str, clearance_um: float, cases, from_rest: bool | None = None) -> np.ndarray:
        """Full paths with a radial clearance at ``bearing`` (linear base rig): per case the 2-D clearance law
        d = d_lin + U G r(d) is solved on the factorisation, r the force the gap releases (k d while open,
        k c d/|d| once closed), then u = u_lin + G r. The rest state is solved the same way."""
        from_rest = self.rig.paths.measured_from == "aligned_at_rest" if from_rest is None else from_rest
        frame = self.system.frame
        row = frame.bushing_names.index(SpringId("bearing", bearing))
        operator = bushing.radial_operator(frame.structure.coordinates, frame.structure.bushings, [row],
                                           self.system.n_dofs)
        g, ug = self._influence(operator)
        k = float(frame.structure.bushings.stiffness[row, 1])
        c = clearance_um * 1e-6
        paths_g = np.asarray(self.path_operator @ g)  # (n_path, 2)
        unit_d = np.asarray(operator @ self.unit)  # (2, 7)
        contact = gear_contact_torques(self.rig)
        weights = case_matrix(cases, False, contact)
        rest = case_matrix([type(cases[0])(0.0, 0.0)], False, contact)[0] if cases else None
        linear_paths = weights @ self.unit_paths

        def released(d_lin):
            open_d = np.linalg.solve(np.eye(2) - k * ug, d_lin)
            if np.linalg.norm(open_d) <= c:
                return k * open_d
            d = d_lin.copy() if np.linalg.norm(d_lin) > c else open_d
            for _ in range(60):
                size = np.linalg.norm(d)
                r = k * c * d / size
                jac = np.eye(2) - ug @ (k * c * (np.eye(2) / size - np.outer(d, d) / size ** 3))
                step = np.linalg.solve(jac, d - d_lin - ug @ r)
                d = d - step
                if np.linalg.norm(step) <= 1e-14 * max(np.linalg.norm(d), c):
                    break
            else:
                raise ModelError(f"the clearance law of bearing {bearing} did not converge")
            return k * c * d / np.linalg.norm(d)

        out = np.array([linear_paths[i] + paths_g @ released(unit_d @ w) for i, w in enumerate(weights)])
        if from_rest:
            rest_paths = rest @ self.unit_paths + paths_g @ released(unit_d @ rest)
            out = out - rest_paths
        return out.ravel()

    # -- sentinel loads ------------------------------------------------------------------------------------
    def sentinel_sites(self, per_part: int = 25) -> list[tuple[str, float, int]]:
        """(part, x_mm, node) for up to ``per_part`` evenly spread nodes of every part."""
        frame = self.system.frame
        sites = []
        for part in self.rig.parts:
            own = np.flatnonzero(frame.node_part == part.name)
            if own.size == 0:
                continue
            order = own[np.argsort(frame.node_x_mm[own])]
            pick = np.unique(np.round(np.linspace(0, order.size - 1, min(per_part, order.size))).astype(int))
            sites += [(part.name, float(frame.node_x_mm[order[i]]), int(order[i])) for i in pick]
        return sites

    def sentinel_paths(self, sites, component: int) -> np.ndarray:
        """Paths (n_sites, n_path) in mm of a unit force along Y (``component`` 1, N) or a unit moment about Z
        (``component`` 5, N·m) at each site."""
        key = (tuple(int(s[2]) for s in sites), int(component))
        cache = self.__dict__.setdefault("_sentinel_paths", {})  # the scan asks for the same sites several times
        if key not in cache:
            n = self.system.n_dofs
            load = np.zeros((n, len(sites)))
            for j, (_, _, node) in enumerate(sites):
                load[DOFS_PER_NODE * node + component, j] = 1.0
            u = self.prepared.solve(load)
            cache[key] = np.asarray(self.path_operator @ u).T
            cache[key].setflags(write=False)
        return cache[key]

    # -- fallbacks -----------------------------------------------------------------------------------------
    def swept_unit_paths(self, rig) -> np.ndarray:
        """Unit paths (n_unit_loads, n_path) of a linear ``rig`` assembled and solved on its own (a real sweep)."""
        from rvcoax.loadcases.cases import LoadCase

        sweep = run_sweep(rig, (LoadCase(0.0, 0.0),), self.settings)
        return np.array([np.concatenate([sweep.unit_paths[k][s].uy_mm for s in MEASURED_SHAFTS]) for k in UNIT_LOADS])

    def swept_paths(self, rig, cases) -> np.ndarray:
        """Full paths of ``rig`` (the base rig's structure with a clearance, or any rig) by a real sweep."""
        from rvcoax.results.studies.discrepancy.responses import full_paths

        same_structure = (self.system.kind == "beam" and _same_but_clearance(self.rig, rig)
                          and _loads_on_nodes(self.system.frame, rig))
        sweep = run_sweep(rig, tuple(cases), self.settings, prepared=self.prepared if same_structure else None)
        return full_paths(sweep)[0]


def _loads_on_nodes(frame, rig) -> bool:
    """True when every place a lateral load of ``rig`` acts on is a node of ``frame`` (a load added at a new place,
    e.g. a torque reaction at a housing's middle, needs the rig meshed anew)."""
    for load in rig.torque_lateral_loads:
        for place in (load.on, load.reacted_on):
            if place is None:
                continue
            try:
                frame.node(place.part, place.x_mm)
            except KeyError:
                return False
    return True


def _same_but_clearance(base, rig) -> bool:
    """True when ``rig`` differs from ``base`` in bearing clearances and load parameters only."""
    a = base.model_dump()
    b = rig.model_dump()
    for data in (a, b):
        for bearing in data["bearings"]:
            bearing["radial_clearance_um"] = 0.0
        for key in ("torque_lateral_loads", "force_table", "gravity"):
            data.pop(key, None)
        for coupling in data["couplings"]:
            coupling.pop("parallel_offset_um", None)
            coupling.pop("angular_misalignment_mrad", None)
        for mount in data["mounts"]:
            mount.pop("vertical_offset_um", None)
    return a == b


def rig_is_linear(rig) -> bool:
    """True when the rig's response is linear in its loads: no bearing with a clearance, no ball bearing."""
    return not any(b.radial_clearance_um > 0 or getattr(b, "model", "linear") != "linear" for b in rig.bearings)


def prepare_engine(rig, settings: SweepSettings) -> Engine:
    """Assemble and factorise ``rig`` once and solve its unit loads."""
    prepared = prepare_model(rig, settings)
    system = prepared.system
    loads = np.column_stack([system.unit_loads[k] for k in UNIT_LOADS])
    unit = np.asarray(prepared.solve(loads))
    operator = sp.vstack([system.probes[s].uy for s in MEASURED_SHAFTS]).tocsr() * 1e3
    linear = rig_is_linear(rig)
    for i, k in enumerate(UNIT_LOADS):
        reduced = system.elimination.T @ (system.stiffness @ unit[:, i] - loads[:, i])
        scale = np.linalg.norm(system.elimination.T @ loads[:, i])
        check_solution(f"unit load {k}", unit[:, i], 0.0, float(np.linalg.norm(reduced) / scale) if scale > 0 else 0.0)
    stations = {s: np.asarray(system.probes[s].stations_mm, float) for s in MEASURED_SHAFTS}
    lengths = {s: float(system.probes[s].length_mm) for s in MEASURED_SHAFTS}
    return Engine(rig=rig, settings=settings, prepared=prepared, unit=unit, path_operator=operator, stations_mm=stations, length_mm=lengths, linear=linear)
