"""Verification of the angular-contact ball and the roller bearing laws (rvcoax.fem.rolling_bearing,
rvcoax.fem.roller_bearing, the angular-contact branch of rvcoax.fem.ball_bearing).

Against what the laws were not made from: Harris' closed form of an angular-contact bearing under pure
thrust, the halves of a matched pair computed on their own, the classical lift-off of a preloaded pair,
Palmgren's line-contact deflection and Harris' constant derived from it, the continuum limit of the
laminae under tilt, the Hertz pressure of a sphere and of a line contact, the kinematics of an end play,
and finite differences of every law's own force for its tangent.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from rvcoax.fem.ball_bearing import BallBearingGeometry, ball_loads, hertz_point_contact, reduced_modulus
from rvcoax.fem.roller_bearing import PALMGREN_LINE_MM, RollerBearingGeometry, palmgren_roller_deflection, roller_loads
from rvcoax.fem.rolling_bearing import BearingRow, RollingBearing, bearing_force, rolling_element_loads

E_PRIME = reduced_modulus()


def _angular(angle_deg: float) -> BallBearingGeometry:
    # a 7206-size bearing: Z = 12, D_w = 9.6 mm, d_m = 46 mm, f_i = 0.52, f_o = 0.53
    return BallBearingGeometry(12, 9.6e-3, 46e-3, 0.52, 0.53, 0.0, contact_angle_rad=math.radians(angle_deg))


def _axial_solve(bearing: RollingBearing, load: float) -> float:
    return brentq(lambda d: bearing.force(np.array([d, 0, 0, 0, 0]))[0][0] - load, 0.0, 1e-3, xtol=1e-16, rtol=1e-14)


@pytest.mark.parametrize("angle_deg", [15.0, 25.0, 40.0])
def test_angular_contact_under_thrust_against_harris_closed_form(angle_deg):
    # Harris & Kotzalas, Rolling Bearing Analysis (5th ed., vol. 1 ch. 7, "thrust load"): with B D = A the
    # curvature-centre distance, F_a = Z K_n sin α (B D)^1.5 (cos α0 / cos α − 1)^1.5, solved for α; the axial
    # deflection δ_a = B D sin(α − α0) / cos α
    geometry = _angular(angle_deg)
    alpha0, big_a, k_n = math.radians(angle_deg), geometry.curvature_centre_distance_m, geometry.load_deflection_constant
    single = RollingBearing((BearingRow(geometry),))
    for load in (50.0, 1000.0, 10000.0):
        alpha = brentq(lambda a, load=load: 12 * k_n * math.sin(a) * big_a**1.5 * (math.cos(alpha0) / math.cos(a) - 1) ** 1.5
                       - load, alpha0 + 1e-12, math.radians(89.0), xtol=1e-15)
        axial = _axial_solve(single, load)
        state = ball_loads(geometry, np.array([axial, 0, 0, 0, 0]))
        assert np.allclose(state.contact_angle_rad, alpha, rtol=1e-8)
        assert axial == pytest.approx(big_a * math.sin(alpha - alpha0) / math.cos(alpha), rel=1e-8)
        assert state.loaded_balls == 12
    # the contact angle grows with the thrust: at 10 kN a 15° bearing runs at several degrees more
    assert math.degrees(alpha) > angle_deg + 2.0


def test_angular_contact_carries_no_thrust_the_other_way_and_turns_radial_load_into_thrust():
    geometry = _angular(25.0)
    single = RollingBearing((BearingRow(geometry),))
    force, stiffness = single.force(np.array([-20e-6, 0, 0, 0, 0]))
    assert not np.any(force) and not np.any(stiffness)  # lifted off the low shoulder
    # a radial displacement alone loads the balls at α0: the bearing pushes back axially (the induced thrust)
    force, _ = single.force(np.array([0.0, 10e-6, 0, 0, 0]))
    assert force[1] > 0 and force[0] > 0
    assert force[0] / force[1] == pytest.approx(math.tan(math.radians(25.0)), rel=0.25)


def test_db_pair_preload_and_stiffness_against_the_sum_of_its_halves():
    geometry = _angular(40.0)
    half = RollingBearing((BearingRow(geometry),))
    preload = 500.0
    offset = _axial_solve(half, preload)
    width = 16e-3
    pair = RollingBearing((BearingRow(geometry, -width / 2, 1, offset), BearingRow(geometry, width / 2, -1, offset)))
    # at rest: no net force, each row carries the preload
    force, stiffness = pair.force(np.zeros(5))
    assert np.abs(force).max() < 1e-9 * preload
    for row in pair.rows:
        assert row.state(np.zeros(5)).force[0] == pytest.approx(preload, rel=1e-10)
    # stiffness at rest: the halves' own stiffness at their preload, twice (axial and radial)
    _, k_half = half.force(np.array([offset, 0, 0, 0, 0]))
    assert stiffness[0, 0] == pytest.approx(2 * k_half[0, 0], rel=1e-10)
    assert stiffness[1, 1] == pytest.approx(2 * k_half[1, 1], rel=1e-10)
    # under thrust: F_pair(δ) = F_half(δ0 + δ) − F_half(δ0 − δ), the halves computed on their own
    for load in (300.0, 1000.0, 3000.0):
        delta = _axial_solve(pair, load)
        own = half.force(np.array([offset + delta, 0, 0, 0, 0]))[0][0] - half.force(
            np.array([offset - delta, 0, 0, 0, 0]))[0][0]
        assert own == pytest.approx(load, rel=1e-9)
    # the unloaded half lifts off at F_a = 2^1.5 F_p (Harris & Kotzalas vol. 1, preloaded pairs; constant contact
    # angle): here within 5 % (the contact angles change)
    lift = brentq(lambda f: pair.rows[1].state(np.array([_axial_solve(pair, f), 0, 0, 0, 0])).force[0] - 1e-3,
                  preload, 10 * preload, xtol=1e-6)
    assert lift / preload == pytest.approx(2**1.5, rel=0.05)


def test_back_to_back_pair_is_stiffer_in_tilt_than_face_to_face():
    # the O arrangement spreads the load centres by d_m tan α beyond the rows, the X arrangement draws them in
    geometry = _angular(40.0)
    offset = _axial_solve(RollingBearing((BearingRow(geometry),)), 300.0)
    db = RollingBearing((BearingRow(geometry, -8e-3, 1, offset), BearingRow(geometry, 8e-3, -1, offset)))
    df = RollingBearing((BearingRow(geometry, -8e-3, -1, offset), BearingRow(geometry, 8e-3, 1, offset)))
    k_db, k_df = db.force(np.zeros(5))[1], df.force(np.zeros(5))[1]
    assert k_db[4, 4] > 3 * k_df[4, 4]
    assert k_db[0, 0] == pytest.approx(k_df[0, 0], rel=1e-10)  # the same rows in thrust
    assert k_db[1, 1] == pytest.approx(k_df[1, 1], rel=1e-10)


def test_palmgren_constant_is_harris_line_contact_constant():
    # Harris & Kotzalas vol. 1 ch. 6: K_l = 8.06e4 l^(8/9) N/mm^(10/9) for one roller-raceway contact, from
    # Palmgren's δ = 3.84e-5 Q^0.9 / l^0.8
    assert PALMGREN_LINE_MM ** (-10 / 9) == pytest.approx(8.06e4, rel=0.005)


def _one_roller(geometry, load):
    """The approach of the roller at ψ = 0 when it carries ``load`` (the radial displacement that loads it)."""
    return brentq(lambda d: roller_loads(geometry, np.array([0, d, 0, 0, 0])).load_n[0] - load, 0.0, 1e-3,
                  xtol=1e-16, rtol=1e-14)


def test_one_roller_against_palmgren():
    # an uncrowned roller pressed evenly: δ = 2 · 3.84e-5 Q^0.9 / l^0.8 (mm, N; two raceway contacts)
    geometry = RollerBearingGeometry(14, 10e-3, 14e-3, 60e-3, crowning="none", slices=20)
    for load in (100.0, 2000.0, 20000.0):
        assert _one_roller(geometry, load) == pytest.approx(palmgren_roller_deflection(load, 14e-3), rel=1e-9)
        assert _one_roller(geometry, load) * 1e3 == pytest.approx(
            2 * 3.84e-5 * load**0.9 / 14.0**0.8, rel=1e-9)
    # logarithmic crowning: softer (the ends carry less), approaching Palmgren from above at loads far beyond
    # the design load
    crowned = RollerBearingGeometry(14, 10e-3, 14e-3, 60e-3, crowning="logarithmic", crowning_load_n=3000.0,
                                    slices=40)
    ratios = [_one_roller(crowned, q) / palmgren_roller_deflection(q, 14e-3) for q in (1000.0, 3000.0, 1e5)]
    assert ratios[0] > ratios[1] > ratios[2] > 1.0
    assert ratios[2] < 1.1
    # the crowned roller's load–deflection converges with the slices: 20 (the default) within 1 % of 400
    fine = RollerBearingGeometry(14, 10e-3, 14e-3, 60e-3, crowning_load_n=3000.0, slices=400)
    default = RollerBearingGeometry(14, 10e-3, 14e-3, 60e-3, crowning_load_n=3000.0, slices=20)
    for load in (500.0, 3000.0, 20000.0):
        assert _one_roller(default, load) == pytest.approx(_one_roller(fine, load), rel=0.01)


def _line_contact_integral(epsilon: float) -> float:
    """J_r(ε) = (1/2π) ∫ (1 − (1 − cos ψ)/(2ε))^(10/9) cos ψ dψ over the load zone (line contact)."""
    limit = math.acos(max(1.0 - 2.0 * epsilon, -1.0))
    value, _ = quad(lambda psi: (1.0 - (1.0 - math.cos(psi)) / (2.0 * epsilon)) ** (10 / 9) * math.cos(psi),
                    -limit, limit, epsabs=1e-13)
    return value / (2.0 * math.pi)


def test_radial_load_distribution_against_the_line_contact_integrals():
    # Stribeck/Sjövall for line contact (Harris & Kotzalas vol. 1 ch. 7): zero clearance Z Q_max / F_r = 1/J_r(½)
    # = 4.08; with clearance Q_max = F_r / (Z J_r(ε)), ε = ½ (1 − P_d / (2 δ_r)); many rollers make the sum the integral
    assert 1.0 / _line_contact_integral(0.5) == pytest.approx(4.08, abs=0.01)
    for clearance in (0.0, 10e-6):
        geometry = RollerBearingGeometry(60, 3e-3, 10e-3, 80e-3, clearance_m=clearance, crowning="none", slices=4)
        for load in (1000.0, 20000.0):
            radial = brentq(lambda d, g=geometry, f=load: roller_loads(g, np.array([0, d, 0, 0, 0])).force[1] - f,
                            0.5 * clearance, 1e-3, xtol=1e-17, rtol=1e-14)
            epsilon = 0.5 * (1.0 - clearance / (2.0 * radial))
            state = roller_loads(geometry, np.array([0, radial, 0, 0, 0]))
            assert state.load_n.max() == pytest.approx(load / (60 * _line_contact_integral(epsilon)), rel=3e-3)


def test_laminae_under_tilt_converge_to_the_continuum_of_palmgren_laminae():
    # uncrowned rollers, no clearance, pure tilt θ: roller j's laminae carry K_l/l (θ |s cos ψ_j|)^(10/9) ds on the
    # half s cos ψ_j > 0, so M = Σ_j K_l/l θ^(10/9) |cos ψ_j|^(19/9) ∫_0^{l/2} s^(19/9) ds
    length, theta = 14e-3, 2e-4
    k_l = (2 * PALMGREN_LINE_MM) ** (-10 / 9) * (length * 1e3) ** (8 / 9) * 1e3 ** (10 / 9)  # N/m^(10/9)
    psi = 2 * np.pi * np.arange(14) / 14
    integral, _ = quad(lambda s: s ** (19 / 9), 0, length / 2)
    moment = np.sum(k_l / length * theta ** (10 / 9) * np.abs(np.cos(psi)) ** (19 / 9)) * integral
    values = {}
    for n in (10, 40, 400):
        geometry = RollerBearingGeometry(14, 10e-3, length, 60e-3, crowning="none", slices=n)
        values[n] = roller_loads(geometry, np.array([0, 0, 0, 0, theta])).force[4]
    assert values[400] == pytest.approx(moment, rel=2e-3)
    assert abs(values[40] / values[400] - 1) < 0.01 < abs(values[10] / values[400] - 1) + 0.01
    # a crowned, tilted and radially loaded roller set: 20 slices (the default) within 1 % of 400
    loaded = {n: roller_loads(RollerBearingGeometry(14, 10e-3, length, 60e-3, clearance_m=10e-6,
                                                    crowning_load_n=3000.0, slices=n),
                              np.array([0, 25e-6, 5e-6, 1e-4, -2e-4])).force for n in (20, 400)}
    assert np.allclose(loaded[20], loaded[400], rtol=0.01, atol=0.01 * np.abs(loaded[400]).max())


def _finite_difference(bearing, motion, h=1e-9):
    columns = []
    for i in range(6):
        step = np.zeros(6)
        step[i] = h if i < 3 else h / 0.05
        if i == 3:
            columns.append(np.zeros(6))
            continue
        columns.append((bearing_force(bearing, motion + step)[0] - bearing_force(bearing, motion - step)[0])
                       / (2 * step[i]))
    return np.array(columns).T


TAPERED = RollerBearingGeometry(15, 8e-3, 11.2e-3, 46e-3, math.radians(13.9), crowning_load_n=3000.0)


@pytest.mark.parametrize("bearing", [
    RollingBearing((BearingRow(_angular(25.0), -8e-3, 1, 8e-6), BearingRow(_angular(25.0), 8e-3, -1, 8e-6))),
    RollingBearing((BearingRow(_angular(15.0), -8e-3, 1, 3e-6), BearingRow(_angular(15.0), 8e-3, 1, 3e-6))),
    RollingBearing((BearingRow(RollerBearingGeometry(13, 9e-3, 10.4e-3, 46e-3, clearance_m=5e-6,
                                                     crowning_load_n=3000.0)),), linear_axial_stiffness=2e7),
    RollingBearing((BearingRow(TAPERED, -9e-3, 1, 4e-6), BearingRow(TAPERED, 9e-3, -1, 4e-6))),
], ids=["angular DB", "angular DT", "cylindrical", "tapered DB"])
def test_tangent_against_finite_differences_of_the_law(bearing):
    motion = np.array([2e-6, 9e-6, -4e-6, 0.0, 1e-4, 2e-4])
    _, stiffness = bearing_force(bearing, motion)
    fd = _finite_difference(bearing, motion)
    scale = np.abs(stiffness).max()
    assert np.abs(stiffness - fd).max() < 2e-5 * scale
    assert np.allclose(stiffness, stiffness.T, atol=1e-9 * scale)
    assert stiffness[1, 1] > 0 and stiffness[5, 5] > 0
    assert not np.any(stiffness[3]) and not np.any(stiffness[:, 3])


def test_a_tapered_pair_closes_its_end_play():
    # DB pair with 20 µm axial play (each row 10 µm apart): free over the play, then the thrust row engages
    play = 20e-6
    pair = RollingBearing((BearingRow(TAPERED, -9e-3, 1, -play / 2), BearingRow(TAPERED, 9e-3, -1, -play / 2)))
    for x in (-0.99 * play / 2, 0.0, 0.5 * play / 2, 0.99 * play / 2):
        force, stiffness = pair.force(np.array([x, 0, 0, 0, 0]))
        assert not np.any(force) and not np.any(stiffness)
    beyond, k = pair.force(np.array([play / 2 + 2e-6, 0, 0, 0, 0]))
    assert beyond[0] > 0 and k[0, 0] > 0
    back, _ = pair.force(np.array([-play / 2 - 2e-6, 0, 0, 0, 0]))
    assert back[0] == pytest.approx(-beyond[0], rel=1e-10)  # the other row, mirrored
    # radially the rollers are free inside the play's radial share: δ_r cos α < (e/2) sin α
    radial_gap = play / 2 * math.tan(TAPERED.contact_angle_rad)
    assert not np.any(pair.force(np.array([0, 0.99 * radial_gap, 0, 0, 0]))[0])
    assert pair.force(np.array([0, 1.01 * radial_gap, 0, 0, 0]))[0][1] > 0
    # closing the play by thrust: the engaged row then carries radial load with its rollers
    engaged = pair.force(np.array([play / 2 + 5e-6, 5e-6, 0, 0, 0]))[1]
    assert engaged[1, 1] > 0 and engaged[0, 1] != 0  # radial–axial coupling of the single engaged row


def test_element_loads_and_contact_pressures():
    # balls: Σ Q_j n_j is the bearing force; the pressure of a ball on a flat is the Hertz sphere's
    geometry = _angular(25.0)
    pair = RollingBearing((BearingRow(geometry, -8e-3, 1, 8e-6), BearingRow(geometry, 8e-3, -1, 8e-6)))
    motion = np.array([3e-6, 6e-6, 0, 0, 0, 1e-4])
    loads = rolling_element_loads(pair, motion)
    assert loads.kind == ("ball", "ball") and loads.load_n.size == 24 and set(loads.row) == {0, 1}
    radial = np.sum(loads.load_n * np.cos(loads.contact_angle_rad) * np.cos(loads.azimuth_rad))
    assert radial == pytest.approx(bearing_force(pair, motion)[0][1], rel=1e-9)
    flat = BallBearingGeometry(12, 9.6e-3, 46e-3, 0.52, 0.53)
    inner, _ = flat.contacts()
    # p_max = 3Q/(2π a²), a³ = 3 Q R/(4 E*), R the sphere's radius (ball on a flat: α_r = 1)
    on_flat = hertz_point_contact(2 / 9.6e-3, 2 / 9.6e-3, E_PRIME)
    a = (3 * 1000.0 * 4.8e-3 / (4 * E_PRIME / 2)) ** (1 / 3)
    assert on_flat.max_pressure(1000.0, E_PRIME) == pytest.approx(3 * 1000.0 / (2 * math.pi * a**2), rel=1e-10)
    assert inner.max_pressure(1000.0, E_PRIME) > on_flat.max_pressure(1000.0, E_PRIME) * 0.3
    # rollers: the line-contact pressure of an evenly loaded lamina, p = √(q' E'/(2π R)) (Hertz, plane strain)
    cylindrical = RollingBearing((BearingRow(RollerBearingGeometry(14, 10e-3, 14e-3, 60e-3, crowning="none")),))
    loads = rolling_element_loads(cylindrical, np.array([0, 20e-6, 0, 0, 0, 0]))
    q = loads.load_n[0] / 14e-3
    radius = 1 / (2 / 10e-3 + 2 / (60e-3 - 10e-3))
    assert loads.max_contact_pressure_Pa[0] == pytest.approx(math.sqrt(q * E_PRIME / (2 * math.pi * radius)), rel=1e-9)
    assert loads.kind == ("roller",) and loads.max_load_n == loads.load_n[0]
    (laminae,) = loads.lamina_load_n
    assert laminae.shape == (14, 20) and np.allclose(laminae.sum(axis=1), loads.load_n, rtol=1e-12)
    assert loads.lamina_width_m == (pytest.approx(14e-3 / 20),)
