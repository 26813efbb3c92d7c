"""A rolling bearing as a set of rows, each a ball or roller law, at one node (SI).

Linear algebra that knows nothing of rigs. A single bearing is one row; a matched pair (back-to-back
DB, face-to-face DF, tandem DT) is two rows beside each other. Row r sits at x_r along the axis from
the bearing's node, faces f_r = ±1 (+1: it carries the thrust of the inner ring moving in +x against
the outer ring; −1: mirrored) and has its rings pressed δ_r into contact along its facing (δ_r < 0: apart,
an axial play). With the node's relative motion q = (δx, δy, δz, θy, θz) the row sees

    q_r = M_r T_r q + δ_r e_x,   T_r: δy + θz x_r, δz − θy x_r (the rigid inner ring at x_r),
    M_r = diag(f_r, 1, 1, f_r, f_r)   (a mirror x → −x turns δx, θy and θz),

and the bearing carries F(q) = Σ_r T_rᵀ M_r F_r(q_r) − F_rest, tangent K = Σ_r T_rᵀ M_r K_r M_r T_r.
F_rest = Σ_r T_rᵀ M_r F_r(δ_r e_x) is the force of the rows at rest: zero for a DB or DF pair, whose
rows preload each other; for a single row or a tandem pair the preload is taken by the mounting (a
nut, a spring, the opposed bearing modelled as its own entry), as for the deep-groove bearing's
position preload. So F(0) = 0 and the solve sees only what the loads add.

The row laws: :func:`rvcoax.fem.ball_bearing.ball_loads` (deep-groove and angular-contact ball
bearings: the contact angle of every ball follows the load) and
:func:`rvcoax.fem.roller_bearing.roller_loads` (cylindrical and tapered roller bearings, laminae).

:func:`rolling_element_loads` gives, at a state, each rolling element's contact load, contact angle and
largest contact pressure — what a life (ISO/TS 16281) or static-safety (ISO 76) calculation reads.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from rvcoax.fem.ball_bearing import TILT_COMPONENTS, BallBearingGeometry, ball_loads
from rvcoax.fem.roller_bearing import RollerBearingGeometry, roller_loads

__all__ = ["BearingRow", "ElementLoads", "RollingBearing", "bearing_force", "carried_force", "released_force",
           "rolling_element_loads", "row_states"]


@dataclass(frozen=True)
class BearingRow:
    """One row of a rolling bearing.

    Attributes
    ----------
    law : BallBearingGeometry or RollerBearingGeometry
        The row's internal geometry.
    axial_position_m : float
        x_r, the row's mid-plane from the bearing's node along +x.
    facing : int
        f_r, +1 or −1.
    axial_offset_m : float
        δ_r: the rings pressed into contact (> 0, a preload) or held apart (< 0, a play), along the facing.
    """

    law: BallBearingGeometry | RollerBearingGeometry
    axial_position_m: float = 0.0
    facing: int = 1
    axial_offset_m: float = 0.0

    def __post_init__(self) -> None:
        if self.facing not in (1, -1):
            raise ValueError(f"facing must be +1 or -1, got {self.facing!r}")

    @cached_property
    def transform(self) -> np.ndarray:
        """M_r T_r (5, 5)."""
        t = np.eye(5)
        t[1, 4], t[2, 3] = self.axial_position_m, -self.axial_position_m
        return np.diag([self.facing, 1.0, 1.0, self.facing, self.facing]) @ t

    @cached_property
    def ball_constant(self) -> float | None:
        return self.law.load_deflection_constant if isinstance(self.law, BallBearingGeometry) else None

    def state(self, q: np.ndarray):
        """The row law's state (BallLoads or RollerLoads) at the node's motion q (5,)."""
        local = self.transform @ q
        local[0] += self.axial_offset_m
        if isinstance(self.law, BallBearingGeometry):
            return ball_loads(self.law, local, constant=self.ball_constant)
        return roller_loads(self.law, local)


@dataclass(frozen=True)
class RollingBearing:
    """A rolling bearing of one or more rows at one node (see the module docstring).

    ``linear_axial_stiffness`` (N/m) is an axial spring beside the rows: the ribs that locate a cylindrical
    roller bearing axially, whose rollers carry no thrust on their raceways. ``axial_spring_direction`` 0: it
    acts both ways (ribs on both sides of both rings, as an NUP bearing); +1 or −1: only while the inner ring
    moves that way against the outer ring (an NJ bearing: the outer ring's rib and the inner ring's one rib
    meet the roller ends one way; the other way the rings part), a contact, F_x = k max(f δx, 0) f.
    """

    rows: tuple[BearingRow, ...]
    linear_axial_stiffness: float = 0.0
    axial_spring_direction: int = 0

    def __post_init__(self) -> None:
        if not self.rows:
            raise ValueError("a rolling bearing needs at least one row")
        if self.axial_spring_direction not in (0, 1, -1):
            raise ValueError(f"axial_spring_direction must be 0, +1 or -1, got {self.axial_spring_direction!r}")

    def _carried(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        force = np.zeros(5)
        stiffness = np.zeros((5, 5))
        for row in self.rows:
            state = row.state(q)
            force += row.transform.T @ state.force
            stiffness += row.transform.T @ state.stiffness @ row.transform
        return force, stiffness

    @cached_property
    def rest_force(self) -> np.ndarray:
        """F_rest (5,): what the rows carry at q = 0 (taken by the mounting)."""
        return self._carried(np.zeros(5))[0]

    def force(self, q) -> tuple[np.ndarray, np.ndarray]:
        """F(q) − F_rest (5,) and the tangent (5, 5) at q = (δx, δy, δz, θy, θz)."""
        q = np.asarray(q, dtype=float)
        force, stiffness = self._carried(q)
        force = force - self.rest_force
        if self.linear_axial_stiffness and (self.axial_spring_direction == 0 or self.axial_spring_direction * q[0] > 0):
            force[0] += self.linear_axial_stiffness * q[0]
            stiffness[0, 0] += self.linear_axial_stiffness
        return force, stiffness


def bearing_force(bearing: RollingBearing, relative_motion) -> tuple[np.ndarray, np.ndarray]:
    """Force (6,) and tangent stiffness (6, 6) of ``bearing`` at a six-component relative motion
    Δ = (x, y, z, θx, θy, θz) of the inner ring against the outer (the rotation about the axis is free).

    Parameters
    ----------
    bearing : RollingBearing
        Its rows.
    relative_motion : sequence of 6 float
        Δ, m and rad.

    Returns
    -------
    (ndarray, ndarray)
        The force (6,) in N and N·m, and the tangent stiffness (6, 6).
    """
    motion = np.asarray(relative_motion, dtype=float)
    index = np.array(TILT_COMPONENTS)
    five, tangent = bearing.force(motion[index])
    force = np.zeros(6)
    stiffness = np.zeros((6, 6))
    force[index] = five
    stiffness[np.ix_(index, index)] = tangent
    return force, stiffness


def carried_force(bearing: RollingBearing, relative_motion) -> np.ndarray:
    """What the bearing's rows (and its linear axial spring) carry at Δ, the preload its mounting takes
    included: F(Δ) + F_rest (6,), N and N·m. A single row or a tandem pair set δ_r into contact carries its
    preload axially though it passes none on; a DB/DF pair's preloads cancel (F_rest = 0). This is the load
    ISO 281's equivalent load P is taken from."""
    force, _ = bearing_force(bearing, relative_motion)
    index = np.array(TILT_COMPONENTS)
    force[index] += bearing.rest_force
    return force


def released_force(bearing: RollingBearing, reference_stiffness, relative_motion) -> tuple[np.ndarray, np.ndarray]:
    """G(Δ) = k_ref Δ − F(Δ) and its tangent k_ref − K_t, (6,) and (6, 6): the bearing as the condensed
    solve (:func:`rvcoax.fem.bushing.solve_condensed`) sees it on the linear reference springs (6,)."""
    reference = np.asarray(reference_stiffness, dtype=float)
    force, stiffness = bearing_force(bearing, relative_motion)
    return reference * np.asarray(relative_motion, dtype=float) - force, np.diag(reference) - stiffness


def row_states(bearing: RollingBearing, relative_motion) -> tuple:
    """The state of each row (BallLoads or RollerLoads, in the row's own axes) at the six-component motion."""
    q = np.asarray(relative_motion, dtype=float)[list(TILT_COMPONENTS)]
    return tuple(row.state(q) for row in bearing.rows)


@dataclass(frozen=True)
class ElementLoads:
    """Every rolling element of a bearing at one state (all rows, row after row).

    Attributes
    ----------
    row : (m,) int array
        The row each element belongs to.
    azimuth_rad, load_n, contact_angle_rad : (m,) arrays
        Its azimuth, its normal contact load Q (N; a roller's summed over its laminae) and contact angle.
    max_contact_pressure_Pa : (m,) array
        The largest Hertz contact pressure of the element (point contact for a ball, its most loaded
        lamina for a roller).
    kind : tuple of str
        Per row, ``ball`` or ``roller`` (ISO 76/281 treat them apart).
    lamina_load_n : tuple
        Per row, the (Z, n) lamina loads of a roller row (ISO/TS 16281's life sums over them), None for a ball row.
    lamina_width_m : tuple
        Per row, the lamina width of a roller row, None for a ball row.
    """

    row: np.ndarray
    azimuth_rad: np.ndarray
    load_n: np.ndarray
    contact_angle_rad: np.ndarray
    max_contact_pressure_Pa: np.ndarray
    kind: tuple[str, ...]
    lamina_load_n: tuple = ()
    lamina_width_m: tuple = ()

    @property
    def max_load_n(self) -> float:
        return float(self.load_n.max()) if self.load_n.size else 0.0

    @property
    def max_pressure_Pa(self) -> float:
        return float(self.max_contact_pressure_Pa.max()) if self.max_contact_pressure_Pa.size else 0.0

    @property
    def loaded_elements(self) -> int:
        return int(np.count_nonzero(self.load_n > 0))


def rolling_element_loads(bearing: RollingBearing, relative_motion) -> ElementLoads:
    """Contact load, contact angle and largest contact pressure of every rolling element of ``bearing``
    at the six-component relative motion Δ (m, rad) of its inner ring against its outer ring.

    This is the state a life calculation from the load distribution (ISO/TS 16281) or a static safety
    from the largest contact pressure (ISO 76) reads; the motion is what the nonlinear solve converged
    to (e.g. ``NonlinearBearings.motions``).

    Parameters
    ----------
    bearing : RollingBearing
    relative_motion : sequence of 6 float

    Returns
    -------
    ElementLoads
    """
    rows, azimuth, load, angle, pressure, kinds, laminae, widths = [], [], [], [], [], [], [], []
    for r, (row, state) in enumerate(zip(bearing.rows, row_states(bearing, relative_motion))):
        rows.append(np.full(state.load_n.size, r))
        azimuth.append(state.azimuth_rad)
        load.append(state.load_n)
        angle.append(state.contact_angle_rad)
        if isinstance(row.law, BallBearingGeometry):
            pressure.append(row.law.max_contact_pressure(state.load_n))
            kinds.append("ball")
            laminae.append(None)
            widths.append(None)
        else:
            pressure.append(state.max_contact_pressure_Pa)
            kinds.append("roller")
            laminae.append(state.lamina_load_n)
            widths.append(row.law.roller_length_m / row.law.slices)
    return ElementLoads(row=np.concatenate(rows), azimuth_rad=np.concatenate(azimuth), load_n=np.concatenate(load),
                        contact_angle_rad=np.concatenate(angle), max_contact_pressure_Pa=np.concatenate(pressure),
                        kind=tuple(kinds), lamina_load_n=tuple(laminae), lamina_width_m=tuple(widths))
