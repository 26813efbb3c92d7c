"""The nonlinear bearings of a rig as one condensed law: gapped linear bearings and ball bearings.

The system is assembled with every bearing's linear reference spring (the typed-in stiffness; for a
``model = "ball"`` bearing the reference of :func:`rvcoax.geometry.ball_model.reference_stiffness`)
and factorised once. The nonlinear bearings are condensed on their relative motions w = U u:

- a bearing with ``radial_clearance_um > 0``: its radial (y, z) motion, law
  :func:`rvcoax.fem.bushing.gap_forces` (two rows);
- a ball bearing: its six-component motion Δ, law :func:`rvcoax.fem.ball_bearing.bearing_force`
  (six rows; the rotation about the axis carries nothing).

``released(w)`` returns G(w) = K_ref w − F(w) and its tangent, what
:func:`rvcoax.fem.bushing.solve_condensed` iterates on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem import bushing
from rvcoax.fem.ball_bearing import ball_loads, bearing_force, dead_band_regularisation, released_force
from rvcoax.geometry.ball_model import BallBearingModel, ball_bearing_model
from rvcoax.geometry.model.beam import SpringId

__all__ = ["NonlinearBearings", "nonlinear_bearing_names", "prepare_nonlinear_bearings"]


def nonlinear_bearing_names(rig) -> list[str]:
    """The bearings that make ``rig`` nonlinear: a radial clearance, or ``model = "ball"``."""
    return [b.name for b in rig.bearings if b.radial_clearance_um > 0 or b.model == "ball"]


@dataclass(frozen=True, eq=False)
class NonlinearBearings:
    """The condensed nonlinear bearings of an assembled system (SI).

    Attributes
    ----------
    operator, influence, compliance
        U, W = K⁻¹ Uᵀ and S = U W (:func:`rvcoax.fem.bushing.solve_condensed`).
    gaps : RadialGaps
        The gapped bearings (their rows come first in w, two each).
    gap_names, balls
        Names of the gapped bearings; the ball bearings (six rows each, after the gaps).
    ball_reference : (b, 6) array
        The reference stiffness of each ball bearing in the assembled system.
    """

    operator: object
    influence: np.ndarray
    compliance: np.ndarray
    gaps: bushing.RadialGaps
    gap_names: tuple[str, ...]
    balls: tuple[BallBearingModel, ...]
    ball_reference: np.ndarray

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
        for i, ball in enumerate(self.balls):
            block = self._ball_slice(i)
            value[block], tangent[block, block] = released_force(ball.geometry, self.ball_reference[i], w[block],
                                                                 ball.preload_offset_m, ball.constant)
        return value, tangent

    @property
    def reference_stiffness(self) -> np.ndarray:
        """K_ref (p,): the linear reference spring of every condensed row as assembled (the radial stiffness of
        a gapped bearing, twice; each ball bearing's six reference stiffnesses)."""
        return np.concatenate([np.repeat(np.asarray(self.gaps.stiffness, dtype=float), 2),
                               np.asarray(self.ball_reference, dtype=float).ravel()])

    def spring_rows(self) -> tuple[tuple[SpringId, tuple[int, ...], slice], ...]:
        """Per nonlinear bearing: its spring, the components (of x, y, z, θx, θy, θz) of its condensed rows,
        and where they sit in w."""
        gaps = tuple((SpringId("bearing", name), (1, 2), slice(2 * i, 2 * i + 2))
                     for i, name in enumerate(self.gap_names))
        return gaps + tuple((SpringId("bearing", ball.name), tuple(range(6)), self._ball_slice(i))
                            for i, ball in enumerate(self.balls))

    def laws(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """F(w) (p,): what the nonlinear bearings carry at the condensed motion ``w`` (the shaft gets the
        opposite), and their tangent ∂F/∂w (p, p): the operating stiffness. F = K_ref w − G(w)."""
        w = np.asarray(w, dtype=float).ravel()
        value, tangent = self.released(w)
        reference = self.reference_stiffness
        return reference * w - value, np.diag(reference) - tangent

    @property
    def regularisation(self) -> np.ndarray | None:
        """For :func:`rvcoax.fem.bushing.solve_condensed`: the dead-band regularisation of the ball bearings
        (:func:`rvcoax.fem.ball_bearing.dead_band_regularisation`), None without ball bearings."""
        if not self.balls:
            return None
        size = self.compliance.shape[0]
        out = np.zeros((size, size))
        for i in range(len(self.balls)):
            block = self._ball_slice(i)
            out[block, block] = dead_band_regularisation(self.ball_reference[i])
        return out

    def ball_states(self, w: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, object]]:
        """Per ball bearing at the condensed motion ``w``: its motion Δ (6,), the force (6,) it carries, its tangent
        stiffness (6, 6) and its ball loads (:class:`rvcoax.fem.ball_bearing.BallLoads`, preload included)."""
        out = []
        w = np.asarray(w, dtype=float).ravel()
        for i, ball in enumerate(self.balls):
            motion = w[self._ball_slice(i)]
            force, stiffness = bearing_force(ball.geometry, motion, ball.preload_offset_m, constant=ball.constant)
            q = motion[[0, 1, 2, 4, 5]].copy()
            q[0] += ball.preload_offset_m
            out.append((motion, force, stiffness, ball_loads(ball.geometry, q, constant=ball.constant)))
        return out

    def operating_points(self, w: np.ndarray) -> dict[str, dict]:
        """Per ball bearing, at the condensed motion ``w``: force, tangent stiffness, ball loads (user units).

        Forces are what the bearing carries (the shaft gets the opposite); stiffnesses the tangent
        ∂F/∂Δ in global axes (y vertical, z lateral, x the axis; tilt about z is the one in the XY plane).
        """
        out = {}
        for ball, (motion, force, stiffness, state) in zip(self.balls, self.ball_states(w)):
            out[ball.name] = {
                "radial_displacement_um": float(np.hypot(motion[1], motion[2]) * 1e6),
                "displacement_yz_um": [float(motion[1] * 1e6), float(motion[2] * 1e6)],
                "radial_force_N": float(np.hypot(force[1], force[2])),
                "axial_force_N": float(force[0]),
                "tilt_moment_Nm": float(np.hypot(force[4], force[5])),
                "radial_stiffness_y_N_per_um": float(stiffness[1, 1] * 1e-6),
                "radial_stiffness_z_N_per_um": float(stiffness[2, 2] * 1e-6),
                "axial_stiffness_N_per_um": float(stiffness[0, 0] * 1e-6),
                "tilt_stiffness_z_Nm_per_rad": float(stiffness[5, 5]),
                "tilt_stiffness_y_Nm_per_rad": float(stiffness[4, 4]),
                "loaded_balls": state.loaded_balls,
                "max_ball_load_N": float(state.load_n.max()),
                "operating_clearance_um": float(ball.geometry.clearance_m * 1e6),
                "operating_clearance_range_um": (None if ball.clearance_range_um is None
                                                 else [float(v) for v in ball.clearance_range_um]),
            }
        return out


def prepare_nonlinear_bearings(rig, frame_model, solve, n_dofs: int) -> NonlinearBearings:
    """Condense the nonlinear bearings of ``rig`` on ``solve`` (the solver of the system as assembled,
    every bearing on its linear reference spring); ``frame_model`` is the system's frame (RigModel)."""
    structure = frame_model.structure
    gapped = [b for b in rig.bearings if b.radial_clearance_um > 0]
    balls = [b for b in rig.bearings if b.model == "ball"]
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
    return NonlinearBearings(operator, influence, compliance, gaps, tuple(b.name for b in gapped),
                             tuple(ball_bearing_model(b, rig) for b in balls), reference)
