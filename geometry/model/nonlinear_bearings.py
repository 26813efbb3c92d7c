"""The nonlinear bearings of a rig as one condensed law: gapped linear bearings and bearings from geometry.

The system is assembled with every bearing's linear reference spring (the typed-in stiffness; for a
``model = "ball"`` bearing the reference of :func:`rvcoax.geometry.ball_model.reference_stiffness`)
and factorised once. The nonlinear bearings are condensed on their relative motions w = U u:

- a bearing with ``radial_clearance_um > 0``: its radial (y, z) motion, law
  :func:`rvcoax.fem.bushing.gap_forces` (two rows);
- a bearing from internal geometry (``model = "ball"``, ``"angular_contact"``, ``"cylindrical_roller"``,
  ``"tapered_roller"``): its six-component motion Δ, law :func:`rvcoax.fem.rolling_bearing.bearing_force`
  (six rows; the rotation about the axis carries nothing).

``released(w)`` returns G(w) = K_ref w − F(w) and its tangent, what
:func:`rvcoax.fem.bushing.solve_condensed` iterates on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import bushing
from rvcoax.fem.ball_bearing import dead_band_regularisation
from rvcoax.fem.rolling_bearing import bearing_force, released_force, rolling_element_loads
from rvcoax.geometry.model.beam import SpringId
from rvcoax.geometry.rolling_model import RollingBearingModel, rolling_bearing_model

__all__ = ["NonlinearBearings", "nonlinear_bearing_names", "prepare_nonlinear_bearings"]


def nonlinear_bearing_names(rig) -> list[str]:
    """The bearings that make ``rig`` nonlinear: a radial clearance, or a bearing from internal geometry."""
    return [b.name for b in rig.bearings if b.radial_clearance_um > 0 or b.model != "linear"]


@dataclass(frozen=True, eq=False)
class NonlinearBearings:
    """The condensed nonlinear bearings of an assembled system (SI).

    Attributes
    ----------
    operator, influence, compliance
        U, W = K⁻¹ Uᵀ and S = U W (:func:`rvcoax.fem.bushing.solve_condensed`).
    gaps : RadialGaps
        The gapped bearings (their rows come first in w, two each).
    gap_names, rolling
        Names of the gapped bearings; the bearings from internal geometry (six rows each, after the gaps).
    rolling_reference : (b, 6) array
        The reference stiffness of each bearing from geometry in the assembled system.
    """

    operator: object
    influence: np.ndarray
    compliance: np.ndarray
    gaps: bushing.RadialGaps
    gap_names: tuple[str, ...]
    rolling: tuple[RollingBearingModel, ...]
    rolling_reference: np.ndarray

    @property
    def balls(self) -> tuple[RollingBearingModel, ...]:
        """The deep-groove ball bearings (``model = "ball"``) among :attr:`rolling`."""
        return tuple(m for m in self.rolling if m.model == "ball")

    def _ball_slice(self, i: int) -> slice:
        start = 2 * len(self.gap_names) + 6 * i
        return slice(start, start + 6)

    def released(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G(w) = K_ref w − F(w) (p,) and its tangent K_ref − ∂F/∂w (p, p)."""
        w = np.asarray(w, dtype=float).ravel()
        value = np.empty_like(w)
        tangent = np.zeros((w.size, w.size))
        n_gap = 2 * len(self.gap_names)
        if n_gap:
            gap_value, gap_tangent, _ = bushing._released(w[:n_gap].reshape(-1, 2), self.gaps)
            value[:n_gap] = gap_value.ravel()
            tangent[:n_gap, :n_gap] = gap_tangent
        for i, model in enumerate(self.rolling):
            block = self._ball_slice(i)
            value[block], tangent[block, block] = released_force(model.bearing, self.rolling_reference[i], w[block])
        return value, tangent

    @property
    def reference_stiffness(self) -> np.ndarray:
        """K_ref (p,): the linear reference spring of every condensed row as assembled (the radial stiffness of
        a gapped bearing, twice; each bearing from geometry's six reference stiffnesses)."""
        return np.concatenate([np.repeat(np.asarray(self.gaps.stiffness, dtype=float), 2),
                               np.asarray(self.rolling_reference, dtype=float).ravel()])

    def spring_rows(self) -> tuple[tuple[SpringId, tuple[int, ...], slice], ...]:
        """Per nonlinear bearing: its spring, the components (of x, y, z, θx, θy, θz) of its condensed rows,
        and where they sit in w."""
        gaps = tuple((SpringId("bearing", name), (1, 2), slice(2 * i, 2 * i + 2))
                     for i, name in enumerate(self.gap_names))
        return gaps + tuple((SpringId("bearing", model.name), tuple(range(6)), self._ball_slice(i))
                            for i, model in enumerate(self.rolling))

    def laws(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """F(w) (p,): what the nonlinear bearings carry at the condensed motion ``w`` (the shaft gets the
        opposite), and their tangent ∂F/∂w (p, p): the operating stiffness. F = K_ref w − G(w)."""
        w = np.asarray(w, dtype=float).ravel()
        value, tangent = self.released(w)
        reference = self.reference_stiffness
        return reference * w - value, np.diag(reference) - tangent

    @property
    def regularisation(self) -> np.ndarray | None:
        """For :func:`rvcoax.fem.bushing.solve_condensed`: the dead-band regularisation of the bearings from
        geometry (:func:`rvcoax.fem.ball_bearing.dead_band_regularisation`), None without them."""
        if not self.rolling:
            return None
        size = self.compliance.shape[0]
        out = np.zeros((size, size))
        for i in range(len(self.rolling)):
            block = self._ball_slice(i)
            out[block, block] = dead_band_regularisation(self.rolling_reference[i])
        return out

    def motions(self, w: np.ndarray) -> dict[str, np.ndarray]:
        """Per bearing from geometry, its six-component relative motion Δ (m, rad) at the condensed motion ``w``:
        what :func:`rvcoax.fem.rolling_bearing.rolling_element_loads` takes."""
        w = np.asarray(w, dtype=float).ravel()
        return {model.name: w[self._ball_slice(i)].copy() for i, model in enumerate(self.rolling)}

    def operating_points(self, w: np.ndarray, models: tuple[str, ...] = ("ball",)) -> dict[str, dict]:
        """Per bearing from geometry of ``models``, at the condensed motion ``w``: force, tangent stiffness,
        rolling-element loads (user units).

        Forces are what the bearing carries (the shaft gets the opposite); stiffnesses the tangent
        ∂F/∂Δ in global axes (y vertical, z lateral, x the axis; tilt about z is the one in the XY plane).
        Deep-groove ball bearings name their elements balls (``loaded_balls``, ``max_ball_load_N``); the
        other models ``loaded_elements``, ``max_element_load_N``, with the largest contact pressure and the
        range of the balls' operating contact angles.
        """
        out = {}
        motions = self.motions(w)
        for model in self.rolling:
            if model.model not in models:
                continue
            motion = motions[model.name]
            force, stiffness = bearing_force(model.bearing, motion)
            elements = rolling_element_loads(model.bearing, motion)
            point = {
                "radial_displacement_um": float(np.hypot(motion[1], motion[2]) * 1e6),
                "radial_force_N": float(np.hypot(force[1], force[2])),
                "axial_force_N": float(force[0]),
                "tilt_moment_Nm": float(np.hypot(force[4], force[5])),
                "radial_stiffness_y_N_per_um": float(stiffness[1, 1] * 1e-6),
                "radial_stiffness_z_N_per_um": float(stiffness[2, 2] * 1e-6),
                "axial_stiffness_N_per_um": float(stiffness[0, 0] * 1e-6),
                "tilt_stiffness_z_Nm_per_rad": float(stiffness[5, 5]),
                "tilt_stiffness_y_Nm_per_rad": float(stiffness[4, 4]),
            }
            point["displacement_yz_um"] = [float(motion[1] * 1e6), float(motion[2] * 1e6)]
            if model.model == "ball":
                point.update(loaded_balls=elements.loaded_elements, max_ball_load_N=elements.max_load_n,
                             operating_clearance_um=float(model.geometry.clearance_m * 1e6))
            else:
                loaded = elements.load_n > 0
                angles = np.degrees(elements.contact_angle_rad[loaded]) if loaded.any() else np.zeros(1)
                point.update(model=model.model, loaded_elements=elements.loaded_elements,
                             max_element_load_N=elements.max_load_n,
                             max_contact_pressure_MPa=elements.max_pressure_Pa * 1e-6,
                             contact_angle_min_deg=float(angles.min()), contact_angle_max_deg=float(angles.max()))
                if model.model == "cylindrical_roller":
                    point["operating_clearance_um"] = float(model.geometry.clearance_m * 1e6)
            out[model.name] = point
        return out


def prepare_nonlinear_bearings(rig, frame_model, solve, n_dofs: int) -> NonlinearBearings:
    """Condense the nonlinear bearings of ``rig`` on ``solve`` (the solver of the system as assembled,
    every bearing on its linear reference spring); ``frame_model`` is the system's frame (RigModel)."""
    structure = frame_model.structure
    gapped = [b for b in rig.bearings if b.radial_clearance_um > 0]
    balls = [b for b in rig.bearings if b.model != "linear"]
    gap_rows = [frame_model.bushing_names.index(SpringId("bearing", b.name)) for b in gapped]
    ball_rows = [frame_model.bushing_names.index(SpringId("bearing", b.name)) for b in balls]
    blocks = []
    if gap_rows:
        blocks.append(bushing.radial_operator(structure.coordinates, structure.bushings, gap_rows, n_dofs))
    if ball_rows:
        blocks.append(bushing.motion_operator(structure.coordinates, structure.bushings, ball_rows, n_dofs))
    operator = sp.vstack(blocks).tocsr()
    influence = np.asarray(solve(operator.T.toarray()), dtype=float).reshape(operator.shape[1], -1)
    compliance = np.asarray(operator @ influence)
    gap_operator = operator[: 2 * len(gap_rows)]
    gaps = bushing.RadialGaps(gap_operator, structure.bushings.stiffness[gap_rows, 1],
                              np.array([b.radial_clearance_um * 1e-6 for b in gapped]),
                              influence[:, : 2 * len(gap_rows)], compliance[: 2 * len(gap_rows), : 2 * len(gap_rows)])
    reference = np.asarray(structure.bushings.stiffness[ball_rows], dtype=float).reshape(-1, 6)
    return NonlinearBearings(operator=operator, influence=influence, compliance=compliance, gaps=gaps,
                             gap_names=tuple(b.name for b in gapped),
                             rolling=tuple(rolling_bearing_model(b, rig) for b in balls), rolling_reference=reference)
