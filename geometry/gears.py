"""A gear stage from its gear data: geometry, ISO 6336-1 mesh stiffness, load sharing, mesh forces.

The RV reducer's first stage is a driving gear (the input or sun gear, on the input shaft) in mesh
with two or more planet gears (the spur gears on the crankshafts) whose centres sit at fixed angles
around it. Everything here is plain numbers: the rig file's ``[[gear_meshes]]`` entry is turned into
a :class:`GearStage` and its loads by :func:`mesh_loads`.

Conventions
-----------
Axis x; a planet at angle φ (from +Y towards +Z) has its centre along e = (0, cos φ, sin φ) from the
sun's axis; t = x × e is the direction in which the sun's surface at that mesh moves when the sun
turns positively about +x. Loads are the **transverse line-of-action force** W of each mesh
(along the base tangent, the force of ISO 6336's F_bt) and the **position error** e of each mesh
along its line of action (positive: that mesh's flank is e behind nominal, so it engages later).

Sources: ISO 6336-1:2006 §9 (single stiffness c′, Method B, eq. 85–89 and Table 9; mesh stiffness
c_γα = c′ (0.75 ε_α + 0.25)); ISO 21771:2007 (involute geometry, contact ratio); the load sharing of
parallel meshes on a common rotation is the statically indeterminate split of Kahraman (1994),
"Load sharing characteristics of planetary transmissions", Mech. Mach. Theory 29(8), for a sun held
radially (both planets' meshes see the same sun rotation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["ISO6336_Q_COEFFICIENTS", "MeshForces", "GearStage", "SingleStiffness", "STEEL_YOUNGS_MODULUS_PA",
           "contact_loads", "full_contact_force", "involute", "load_sharing", "mesh_forces", "single_stiffness"]

ISO6336_Q_COEFFICIENTS = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
"""C1 … C9 of ISO 6336-1:2006 Table 9 (q′ in mm·µm/N)."""
STEEL_YOUNGS_MODULUS_PA = 2.06e11
"""The steel modulus ISO 6336-1's c′ is fitted for; another pair scales c′ by E_eq / E_st."""
ISO6336_C_M = 0.8
"""ISO 6336-1 theoretical-to-measured correction factor C_M for solid disc gears."""


def involute(angle_rad: float) -> float:
    """inv α = tan α − α."""
    return math.tan(angle_rad) - angle_rad


def _inverse_involute(value: float) -> float:
    if not value > 0.0:
        raise ValueError(f"inv α_wt = {value:.4g} ≤ 0: the sum of the profile shifts is too negative for these tooth counts")
    angle = (3.0 * value) ** (1.0 / 3.0)  # start from the small-angle series, then Newton
    for _ in range(50):
        step = (involute(angle) - value) / math.tan(angle) ** 2
        angle -= step
        if abs(step) < 1e-15:
            break
    return angle


@dataclass(frozen=True)
class SingleStiffness:
    """ISO 6336-1 Method B single stiffness and its factors.

    c′ = c′_th · C_M · C_R · C_B · cos β · E_eq / E_st, with c′_th = 1 / q′,
    q′ = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2 + C8 x1² + C9 x2²  (mm·µm/N),
    z_n = z / (cos² β_b cos β); the mesh stiffness is c_γα = c′ (0.75 ε_α + 0.25). All N/(mm·µm).
    """

    q_prime_mm_um_per_N: float
    theoretical: float
    C_M: float
    C_R: float
    C_B: float
    cos_beta: float
    material_factor: float
    contact_ratio: float

    @property
    def single(self) -> float:
        """c′, N/(mm·µm)."""
        return self.theoretical * self.C_M * self.C_R * self.C_B * self.cos_beta * self.material_factor

    @property
    def mesh(self) -> float:
        """c_γα = c′ (0.75 ε_α + 0.25), N/(mm·µm): the mean stiffness over the mesh cycle."""
        return self.single * (0.75 * self.contact_ratio + 0.25)


@dataclass(frozen=True)
class GearStage:
    """An external involute pair: the driving (sun) gear 1 and a planet gear 2, standard basic rack.

    Attributes
    ----------
    normal_module_mm, normal_pressure_angle_deg, helix_angle_deg : float
        m_n, α_n, β (β > 0: right hand on gear 1; 0 for spur gears).
    teeth : (int, int)
        z1 (sun), z2 (planet).
    face_width_mm : float
        b, the common face width.
    profile_shift : (float, float)
        x1, x2.
    dedendum_factor : float
        h_fP / m_n of the basic rack (1.25 for ISO 53 profile A).
    """

    normal_module_mm: float
    teeth: tuple[int, int]
    normal_pressure_angle_deg: float = 20.0
    face_width_mm: float = 10.0
    helix_angle_deg: float = 0.0
    profile_shift: tuple[float, float] = (0.0, 0.0)
    dedendum_factor: float = 1.25

    @property
    def beta(self) -> float:
        return math.radians(self.helix_angle_deg)

    @property
    def transverse_pressure_angle(self) -> float:
        """α_t = atan(tan α_n / cos β), rad."""
        return math.atan(math.tan(math.radians(self.normal_pressure_angle_deg)) / math.cos(self.beta))

    @property
    def transverse_module_mm(self) -> float:
        return self.normal_module_mm / math.cos(self.beta)

    def pitch_radius_mm(self, gear: int = 0) -> float:
        """r = m_t z / 2."""
        return 0.5 * self.transverse_module_mm * self.teeth[gear]

    def base_radius_mm(self, gear: int = 0) -> float:
        """r_b = r cos α_t."""
        return self.pitch_radius_mm(gear) * math.cos(self.transverse_pressure_angle)

    @property
    def base_helix_angle(self) -> float:
        """β_b = atan(tan β cos α_t), rad."""
        return math.atan(math.tan(self.beta) * math.cos(self.transverse_pressure_angle))

    @property
    def working_pressure_angle(self) -> float:
        """α_wt from inv α_wt = inv α_t + 2 tan α_n (x1 + x2) / (z1 + z2), rad."""
        shift = sum(self.profile_shift)
        if shift == 0.0:
            return self.transverse_pressure_angle
        value = involute(self.transverse_pressure_angle) + 2.0 * math.tan(math.radians(self.normal_pressure_angle_deg)) \
            * shift / sum(self.teeth)
        return _inverse_involute(value)

    @property
    def centre_distance_mm(self) -> float:
        """a_w = (r_b1 + r_b2) / cos α_wt."""
        return (self.base_radius_mm(0) + self.base_radius_mm(1)) / math.cos(self.working_pressure_angle)

    def tip_radius_mm(self, gear: int) -> float:
        """r_a = r + m_n (1 + x) (no tip shortening)."""
        return self.pitch_radius_mm(gear) + self.normal_module_mm * (1.0 + self.profile_shift[gear])

    @property
    def contact_ratio(self) -> float:
        """Transverse contact ratio ε_α = (√(r_a1² − r_b1²) + √(r_a2² − r_b2²) − a_w sin α_wt) / p_bt."""
        if any(self.tip_radius_mm(g) <= self.base_radius_mm(g) for g in (0, 1)):
            raise ValueError("a tip circle lies inside its base circle: no involute flank (check profile_shift)")
        length = sum(math.sqrt(self.tip_radius_mm(g) ** 2 - self.base_radius_mm(g) ** 2) for g in (0, 1))
        length -= self.centre_distance_mm * math.sin(self.working_pressure_angle)
        return length / (math.pi * self.transverse_module_mm * math.cos(self.transverse_pressure_angle))

    def virtual_teeth(self, gear: int) -> float:
        """z_n = z / (cos² β_b cos β)."""
        return self.teeth[gear] / (math.cos(self.base_helix_angle) ** 2 * math.cos(self.beta))


def single_stiffness(stage: GearStage, blank_factor: float = 1.0,
                     youngs_moduli_pa: tuple[float, float] = (STEEL_YOUNGS_MODULUS_PA, STEEL_YOUNGS_MODULUS_PA)
                     ) -> SingleStiffness:
    """ISO 6336-1:2006 Method B single stiffness c′ of ``stage`` (see :class:`SingleStiffness`).

    ``blank_factor`` is C_R (1 for solid disc gears); C_B = [1 + 0.5 (1.2 − h_fP/m_n)] [1 − 0.02 (20° − α_n)];
    the material factor is E_eq / E_st with E_eq = 2 E1 E2 / (E1 + E2). The standard's load correction for
    F_t K_A / b < 100 N/mm is not applied (the rig's model is linear in torque).
    """
    c = ISO6336_Q_COEFFICIENTS
    zn1, zn2 = stage.virtual_teeth(0), stage.virtual_teeth(1)
    x1, x2 = stage.profile_shift
    q = (c[0] + c[1] / zn1 + c[2] / zn2 + c[3] * x1 + c[4] * x1 / zn1 + c[5] * x2 + c[6] * x2 / zn2
         + c[7] * x1**2 + c[8] * x2**2)
    c_b = (1.0 + 0.5 * (1.2 - stage.dedendum_factor)) * (1.0 - 0.02 * (20.0 - stage.normal_pressure_angle_deg))
    e1, e2 = youngs_moduli_pa
    material = 2.0 * e1 * e2 / (e1 + e2) / STEEL_YOUNGS_MODULUS_PA
    return SingleStiffness(q_prime_mm_um_per_N=q, theoretical=1.0 / q, C_M=ISO6336_C_M, C_R=blank_factor, C_B=c_b,
                           cos_beta=math.cos(stage.beta), material_factor=material, contact_ratio=stage.contact_ratio)


def load_sharing(stiffness: np.ndarray, position_error: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The split of a line-of-action force F over parallel meshes on one rigid driving gear.

    Every mesh i deflects by δ_i = s − e_i (s: the driving gear's base-circle travel, e_i: the
    mesh's position error) and carries W_i = k_i δ_i; ΣW_i = F gives s = (F + Σ k_j e_j) / Σ k_j and

        W_i = (k_i / K) F + k_i (ē − e_i),    K = Σ k_j,  ē = Σ k_j e_j / K.

    Valid while every W_i > 0 (all meshes in contact).

    Returns
    -------
    share, constant : arrays
        W_i = share_i · F + constant_i (units of ``stiffness × position_error``); Σ share = 1, Σ constant = 0.
    """
    k = np.asarray(stiffness, dtype=float)
    e = np.asarray(position_error, dtype=float)
    total = k.sum()
    mean_error = float(k @ e) / total
    return k / total, k * (mean_error - e)


def full_contact_force(share: np.ndarray, constant: np.ndarray) -> float:
    """The line-of-action force F above which every mesh of :func:`load_sharing` carries load: max(−c_i / s_i, 0)."""
    return float(max(0.0, np.max(-np.asarray(constant) / np.asarray(share))))


def contact_loads(stiffness: np.ndarray, position_error: np.ndarray, force: float) -> np.ndarray:
    """The mesh loads W_i ≥ 0 for a line-of-action force ``force`` ≥ 0, meshes that would pull opened.

    Below :func:`full_contact_force` the meshes with the largest position errors stay open (W = 0) and
    the others share F by :func:`load_sharing` among themselves (an active set, at most n passes).
    """
    k = np.asarray(stiffness, dtype=float)
    e = np.asarray(position_error, dtype=float)
    active = np.ones(k.size, dtype=bool)
    loads = np.zeros(k.size)
    for _ in range(k.size):
        share, constant = load_sharing(k[active], e[active])
        trial = share * force + constant
        if np.all(trial >= 0.0):
            loads[active] = trial
            return loads
        index = np.flatnonzero(active)[np.argmin(trial)]
        active[index] = False
    raise AssertionError("unreachable: one mesh alone always carries a non-negative force")


@dataclass(frozen=True)
class MeshForces:
    """Forces of the planets' meshes on the driving gear, at its axis (global axes).

    Attributes
    ----------
    force_N : (3,) array
        Net force on the driving gear (x: axial; y, z: lateral).
    moment_Nm : (3,) array
        Net moment about its axis point of the mesh forces, without the transmitted torque (x component zero).
    torque_Nm : float
        The moment of the mesh forces about +x: minus the torque they resist.
    per_mesh_N : (n, 3) array
        Each mesh's force on the driving gear.
    """

    force_N: np.ndarray
    moment_Nm: np.ndarray
    torque_Nm: float
    per_mesh_N: np.ndarray


def mesh_forces(stage: GearStage, planet_angles_deg, line_of_action_loads_N) -> MeshForces:
    """Forces on the driving gear from meshes carrying transverse line-of-action loads W_i.

    Per mesh, at the working pitch point p = r_w e: tangential −W cos α_wt · t, radial −W sin α_wt · e
    (towards the gear's axis), axial W tan β_b · x (β > 0, right hand on the driving gear turning +x);
    Σ (p × f)·x = −Σ W_i r_b.
    """
    loads = np.asarray(line_of_action_loads_N, dtype=float)
    angles = np.radians(np.asarray(planet_angles_deg, dtype=float))
    e = np.column_stack([np.zeros_like(angles), np.cos(angles), np.sin(angles)])
    t = np.cross([1.0, 0.0, 0.0], e)
    alpha = stage.working_pressure_angle
    radius_m = stage.base_radius_mm(0) / math.cos(alpha) * 1e-3
    per_mesh = (-(loads * math.cos(alpha))[:, None] * t - (loads * math.sin(alpha))[:, None] * e
                + np.outer(loads * math.tan(stage.base_helix_angle), [1.0, 0.0, 0.0]))
    moments = np.cross(radius_m * e, per_mesh)
    moment = moments.sum(axis=0)
    return MeshForces(per_mesh.sum(axis=0), np.array([0.0, moment[1], moment[2]]), float(moment[0]), per_mesh)
