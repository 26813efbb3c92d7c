"""Natural frequencies of a uniform Timoshenko beam in one bending plane, from its differential equations.

κ G A (v'' − ψ') + ρ A ω² v = 0 and E I ψ'' + κ G A (v' − ψ) + ρ I ω² ψ = 0 (shear deformation and rotary
inertia; Timoshenko 1921). Below the cut-off frequency ω_c = √(κ G A / ρ I) the solution is
v = C1 cosh px + C2 sinh px + C3 cos qx + C4 sin qx with ψ from the first equation; each end has a
translational spring k_v and a rotational spring k_θ to ground (0: free; ``inf``: held; −m ω² and −J ω²: a tip
mass and its rotary inertia). The frequencies are the roots of the 4 × 4 determinant of the end conditions
−Q(0) + k_v v(0) = 0, −M(0) + k_θ ψ(0) = 0, Q(L) + k_v v(L) = 0, M(L) + k_θ ψ(L) = 0 (Q = κ G A (v' − ψ),
M = E I ψ'), found by bracketing and Brent's method. No finite element is involved.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq


@dataclass(frozen=True)
class Section:
    length_m: float
    youngs_modulus_Pa: float
    shear_modulus_Pa: float
    density_kg_per_m3: float
    area_m2: float
    second_moment_m4: float
    shear_coefficient: float  # κ; inf: no shear deformation

    @property
    def mass_kg(self) -> float:
        return self.density_kg_per_m3 * self.area_m2 * self.length_m


def _basis(section: Section, omega: float, x: float):
    """(v, ψ, Q, M) of the four basis solutions at x, shape (4, 4): rows v, ψ, Q, M; columns C1..C4."""
    kga = section.shear_coefficient * section.shear_modulus_Pa * section.area_m2
    ei = section.youngs_modulus_Pa * section.second_moment_m4
    b = section.density_kg_per_m3 * section.area_m2 * omega**2
    r = section.density_kg_per_m3 * section.second_moment_m4 * omega**2
    if math.isinf(kga):  # Euler–Bernoulli with rotary inertia: ψ = v'
        # E I v'''' − ρ I ω² v'' − ρ A ω² v = 0: s⁴ ei − r s² − b = 0
        disc = math.sqrt(r * r + 4 * ei * b)
        p = math.sqrt((r + disc) / (2 * ei))
        q = math.sqrt((disc - r) / (2 * ei))
        alpha = beta = 0.0  # ψ = v'
    else:
        # (kga s² + b)(ei s² − kga + r) + kga² s² = 0 → A s⁴ + B s² + C = 0
        big_a = kga * ei
        big_b = kga * r + b * ei
        big_c = b * (r - kga)
        disc = math.sqrt(big_b**2 - 4 * big_a * big_c)
        p2 = (-big_b + disc) / (2 * big_a)
        q2 = (big_b + disc) / (2 * big_a)
        p, q = math.sqrt(p2), math.sqrt(q2)
        alpha = (kga * p2 + b) / (kga * p)
        beta = (b - kga * q2) / (kga * q)
    ch, sh, c, s = math.cosh(p * x), math.sinh(p * x), math.cos(q * x), math.sin(q * x)
    v = np.array([ch, sh, c, s])
    dv = np.array([p * sh, p * ch, -q * s, q * c])
    psi = np.array([alpha * sh, alpha * ch, beta * s, -beta * c]) if not math.isinf(kga) else dv
    dpsi = (np.array([alpha * p * ch, alpha * p * sh, beta * q * c, beta * q * s]) if not math.isinf(kga)
            else np.array([p * p * ch, p * p * sh, -q * q * c, -q * q * s]))
    if math.isinf(kga):
        # Q = −E I v''' − ρ I ω² v' (from the moment equation with ψ = v')
        d3 = np.array([p**3 * sh, p**3 * ch, q**3 * s, -q**3 * c])
        shear = -(ei * d3 + r * dv)
    else:
        shear = kga * (dv - psi)
    return np.vstack([v, psi, shear, ei * dpsi])


def _rows(values, spring_v, spring_t, sign):
    v, psi, shear, moment = values
    rows = []
    rows.append(v if math.isinf(spring_v) else -sign * shear + spring_v * v)
    rows.append(psi if math.isinf(spring_t) else -sign * moment + spring_t * psi)
    return rows


def determinant(section: Section, omega: float, ends) -> float:
    """The end-condition determinant at ω; ``ends`` = ((k_v0, k_θ0), (k_vL, k_θL)) as callables of ω or numbers."""
    def value(k):
        return k(omega) if callable(k) else k

    (kv0, kt0), (kv1, kt1) = ends
    a = _basis(section, omega, 0.0)
    b = _basis(section, omega, section.length_m)
    matrix = np.vstack(_rows(a, value(kv0), value(kt0), 1.0) + _rows(b, value(kv1), value(kt1), -1.0))
    matrix = matrix / np.linalg.norm(matrix, axis=1, keepdims=True)
    return float(np.linalg.det(matrix))


def frequencies_hz(section: Section, ends, count: int, f_max_hz: float, steps: int = 20000) -> np.ndarray:
    """The lowest ``count`` nonzero roots below ``f_max_hz`` (bracketed on a grid of ``steps``)."""
    grid = np.linspace(f_max_hz * 1e-6, f_max_hz, steps) * 2 * np.pi
    values = np.array([determinant(section, w, ends) for w in grid])
    roots = []
    for i in np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0):
        w = brentq(lambda om: determinant(section, om, ends), grid[i], grid[i + 1], xtol=1e-12, rtol=1e-14)
        # a sign change across a pole is no root: the determinant there is large on both sides
        if abs(determinant(section, w, ends)) < 1e-6:
            roots.append(w / (2 * np.pi))
        if len(roots) == count:
            break
    return np.array(roots)


def simply_supported_hz(section: Section, n: int) -> float:
    """The closed form of the n-th mode of a simply supported Timoshenko beam (lower root of the quadratic
    in ω² with k = nπ/L)."""
    k = n * math.pi / section.length_m
    e, g, rho = section.youngs_modulus_Pa, section.shear_modulus_Pa, section.density_kg_per_m3
    a, i, kappa = section.area_m2, section.second_moment_m4, section.shear_coefficient
    ratio = 0.0 if math.isinf(kappa) else e / (kappa * g)
    c4 = rho * rho * i / (kappa * g) if not math.isinf(kappa) else 0.0
    c2 = -(rho * a + rho * i * k * k * (1 + ratio))
    c0 = e * i * k**4
    if c4 == 0.0:
        w2 = -c0 / c2
    else:
        w2 = (-c2 - math.sqrt(c2 * c2 - 4 * c4 * c0)) / (2 * c4)
    return math.sqrt(w2) / (2 * math.pi)
