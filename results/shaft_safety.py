"""Shaft stresses and DIN 743 safety per load case (issue 25 §5).

From a case's displacement (from the unloaded geometry: self-weight, installed misalignment and torque
together) the beam elements' end forces (:func:`rvcoax.fem.beam.end_forces`, with the self-weight and the
thermal initial strain taken off) give the section forces along every shaft that is a beam (the beam parts of
the hybrid model too; a part modelled as a solid has no section forces and is left out). The nominal stresses
of its round sections follow (:mod:`rvcoax.fem.shaft_stress`): axial, bending (resultant of both planes),
torsional and transverse shear, von Mises.

At every ``[[parts.notches]]`` entry the section forces, interpolated to the notch, enter DIN 743
(:func:`rvcoax.fem.din743.safety`) as the load of a rotating shaft: the bending moment is fixed in space, so
it bends the turning shaft fully reversed (amplitude M/W_b, mean 0); torque and axial force are steady
(mean T/W_t and N/A, amplitude 0). The static proof uses the case's loads × ``[shaft_strength]
peak_load_factor``.

Load cases as a spectrum: each case is judged as a constant load of its own (DIN 743-1 for infinite life);
the spectrum's safety is the smallest over the cases, with the case named: the highest-loaded case taken as the
nominal load, which is conservative (no damage accumulation over the cases' shares, DIN 743-4, is done).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvcoax.fem import beam, din743
from rvcoax.fem.shaft_stress import SectionForces, section_forces, section_stresses
from rvcoax.geometry.gear_loads import gear_contact_torques
from rvcoax.geometry.model.loads import UNIT_LOADS, gravity_acceleration, superpose
from rvcoax.geometry.shaft_notches import notch_geometry, steel_of
from rvcoax.geometry.thermal import part_strain

__all__ = ["NotchCheck", "ShaftStrength", "ShaftStressPeak", "ShaftStressProfile", "case_stress_profiles",
           "notch_label", "shaft_strength",
           "shaft_strength_columns", "strength_of_records", "stress_profiles", "worst_notches"]


@dataclass(frozen=True)
class ShaftStressPeak:
    """The station of a shaft with the largest von Mises stress in a case (MPa, mm), and the largest of each
    nominal stress along the shaft."""

    shaft: str
    x_mm: float
    diameter_mm: float
    von_mises_MPa: float
    bending_max_MPa: float
    torsion_max_MPa: float
    transverse_shear_max_MPa: float
    axial_max_MPa: float

    def entry(self) -> dict:
        return {"shaft": self.shaft, "von_mises_max_MPa": self.von_mises_MPa, "von_mises_max_x_mm": self.x_mm,
                "von_mises_max_diameter_mm": self.diameter_mm, "bending_max_MPa": self.bending_max_MPa,
                "torsion_max_MPa": self.torsion_max_MPa, "transverse_shear_max_MPa": self.transverse_shear_max_MPa,
                "axial_max_MPa": self.axial_max_MPa}


@dataclass(frozen=True)
class NotchCheck:
    """One notch in one case: its section forces, nominal stresses, notch factors and DIN 743 safety."""

    shaft: str
    kind: str
    x_mm: float
    diameter_mm: float
    bending_moment_Nm: float
    torque_Nm: float
    axial_force_N: float
    bending_amplitude_MPa: float
    torsion_mean_MPa: float
    axial_mean_MPa: float
    beta_bending: float
    beta_torsion: float
    K_sigma_bending: float
    K_tau: float
    fatigue_safety: float
    static_safety: float
    minimum_safety: float
    bending_allowed_amplitude_MPa: float  # σ_bADK
    torsion_allowed_amplitude_MPa: float  # τ_tADK
    bending_yield_MPa: float  # σ_bFK
    torsion_yield_MPa: float  # τ_tFK

    @property
    def label(self) -> str:
        return notch_label(self.shaft, self.kind, self.x_mm)

    @property
    def verdict(self) -> str:
        return "ok" if min(self.fatigue_safety, self.static_safety) >= self.minimum_safety else "below S_min"

    def entry(self) -> dict:
        return {"shaft": self.shaft, "kind": self.kind, "x_mm": self.x_mm, "diameter_mm": self.diameter_mm,
                "bending_moment_Nm": self.bending_moment_Nm, "torque_Nm": self.torque_Nm,
                "axial_force_N": self.axial_force_N, "bending_amplitude_MPa": self.bending_amplitude_MPa,
                "torsion_mean_MPa": self.torsion_mean_MPa, "axial_mean_MPa": self.axial_mean_MPa,
                "beta_bending": self.beta_bending, "beta_torsion": self.beta_torsion,
                "K_sigma_bending": self.K_sigma_bending, "K_tau": self.K_tau,
                "sigma_bADK_MPa": self.bending_allowed_amplitude_MPa, "tau_tADK_MPa": self.torsion_allowed_amplitude_MPa,
                "sigma_bFK_MPa": self.bending_yield_MPa, "tau_tFK_MPa": self.torsion_yield_MPa,
                "fatigue_safety": _finite(self.fatigue_safety), "static_safety": _finite(self.static_safety),
                "minimum_safety": self.minimum_safety, "verdict": self.verdict}


@dataclass(frozen=True)
class ShaftStrength:
    """A case's shaft stresses (one peak per beam shaft) and notch checks."""

    peaks: tuple[ShaftStressPeak, ...]
    notches: tuple[NotchCheck, ...]
    solid_shafts: tuple[str, ...] = ()  # shafts modelled as solids (hybrid model): no section forces, not checked

    def row(self) -> dict:
        """The columns of ``sweep.csv``: per shaft its largest von Mises stress and where; per notch its safeties."""
        return shaft_strength_columns(self.peaks, self.notches)

    def entry(self) -> dict:
        return {"shafts": [p.entry() for p in self.peaks], "notches": [n.entry() for n in self.notches],
                "shafts_modelled_as_solids": list(self.solid_shafts)}


def _finite(value: float) -> float | None:
    return None if math.isinf(value) else value  # JSON has no infinity: no amplitude, no fatigue limit reached


def notch_label(shaft: str, kind: str, x_mm: float) -> str:
    """``<shaft>_<kind>_at_<x>mm``: a notch's name in column keys."""
    return f"{shaft}_{kind}_at_{x_mm:g}mm"


def shaft_strength_columns(peaks, notches) -> dict:
    row: dict = {}
    for p in peaks:
        row[f"shaft_{p.shaft}_von_mises_max_MPa"] = p.von_mises_MPa
        row[f"shaft_{p.shaft}_von_mises_max_x_mm"] = p.x_mm
        row[f"shaft_{p.shaft}_bending_max_MPa"] = p.bending_max_MPa
        row[f"shaft_{p.shaft}_torsion_max_MPa"] = p.torsion_max_MPa
    for n in notches:
        row[f"notch_{n.label}_fatigue_safety"] = n.fatigue_safety
        row[f"notch_{n.label}_static_safety"] = n.static_safety
    return row


def _diameters(elements) -> tuple[np.ndarray, np.ndarray]:
    """Outer and inner diameter (m) of round sections from their A and I: D² − d² = 4A/π, D⁴ − d⁴ = 64I/π."""
    difference = 4.0 * elements.area_m2 / np.pi
    total = 64.0 * elements.second_moment_m4 / np.pi / difference
    outer = np.sqrt(0.5 * (total + difference))
    inner = np.sqrt(np.maximum(0.5 * (total - difference), 0.0))
    return outer, np.where(inner < 1e-9 * outer, 0.0, inner)


def _end_forces(rig, frame, u: np.ndarray) -> np.ndarray:
    structure = frame.structure
    elements = structure.beams
    g = gravity_acceleration(rig)
    f = beam.end_forces(structure.coordinates, elements, np.asarray(u)[:structure.n_dofs],
                        acceleration_m_per_s2=np.array([0.0, -g, 0.0]) if g else None)
    if rig.thermal is not None and elements.connectivity.size:
        # the beams' thermal initial strain: N = E A (Δu/L − α ΔT), as the load "prestrain" put it in
        part = frame.node_part[elements.connectivity[:, 0]]
        strain = np.array([part_strain(rig, name) for name in part])
        force = elements.youngs_modulus_Pa * elements.area_m2 * strain
        f[:, 0] += force
        f[:, 6] -= force
    return f


def _interpolate(forces: tuple[SectionForces, SectionForces], element: int, share: float) -> SectionForces:
    a, b = forces
    fields = ("axial_N", "shear_y_N", "shear_z_N", "torque_Nm", "moment_y_Nm", "moment_z_Nm")
    return SectionForces(*(np.array([(1.0 - share) * getattr(a, k)[element] + share * getattr(b, k)[element]])
                           for k in fields))


@dataclass(frozen=True)
class ShaftStressProfile:
    """The nominal stresses along one shaft in one case, at both ends of each of its beam elements (so a diameter
    step shows both sides): stations in the order of the elements, two per element (end a, end b)."""

    shaft: str
    x_mm: np.ndarray
    diameter_mm: np.ndarray
    bore_mm: np.ndarray
    axial_MPa: np.ndarray
    bending_MPa: np.ndarray
    torsion_MPa: np.ndarray
    transverse_shear_MPa: np.ndarray
    von_mises_MPa: np.ndarray


def stress_profiles(rig, frame, u_total: np.ndarray) -> dict[str, ShaftStressProfile]:
    """The nominal stresses along every beam shaft of one case (see the module text).

    Parameters
    ----------
    rig : Rig
    frame : RigModel
        The sweep's frame (``Sweep.frame``).
    u_total : (n_dofs,) array
        The case's displacement from the unloaded geometry (``Sweep.total_displacement`` of a nonlinear sweep;
        of a linear one, the superposed unit responses with the rest loads).

    Returns
    -------
    dict of str to ShaftStressProfile
        One profile per shaft modelled as beams, in the rig file's order.
    """
    return _evaluated(rig, frame, u_total)[0]


def case_stress_profiles(sweep, index: int) -> dict[str, ShaftStressProfile]:
    """:func:`stress_profiles` of case ``index`` of a solved sweep (linear: its unit responses superposed with the
    rest loads; nonlinear: the case's own displacement), from the unloaded geometry.

    Parameters
    ----------
    sweep : Sweep
        A sweep that kept its states (one solved now, not rebuilt from files).
    index : int
        The case's position in ``sweep.cases``.

    Returns
    -------
    dict of str to ShaftStressProfile
    """
    if sweep.states is None:
        raise ValueError("this sweep kept no displacements (rebuilt from files): solve it again for stress profiles")
    if sweep.case_displacements is not None:
        u = sweep.total_displacement(index)
    else:
        unit = {k: sweep.unit_displacements[:, i] for i, k in enumerate(UNIT_LOADS)}
        case = sweep.cases[index].case
        u = superpose(unit, case.input_torque_Nm, case.output_torque_Nm, False, gear_contact_torques(sweep.rig))
    return stress_profiles(sweep.rig, sweep.frame, u)


def _evaluated(rig, frame, u_total: np.ndarray):
    """(profiles, section forces at both ends, element end positions and outer diameters, element parts)."""
    elements = frame.structure.beams
    if not elements.connectivity.size:
        return {}, None, None, None
    forces = section_forces(_end_forces(rig, frame, u_total))
    outer, inner = _diameters(elements)
    stresses = [section_stresses(end, outer, inner) for end in forces]
    first, second = elements.connectivity[:, 0], elements.connectivity[:, 1]
    part = frame.node_part[first]
    xa, xb = frame.node_x_mm[first], frame.node_x_mm[second]
    profiles = {}
    for p in rig.parts:
        mine = np.flatnonzero(part == p.name)
        if p.role != "shaft" or mine.size == 0:
            continue

        def both(a: np.ndarray, b: np.ndarray, mine=mine) -> np.ndarray:
            return np.column_stack([a[mine], b[mine]]).ravel()

        profiles[p.name] = ShaftStressProfile(
            shaft=p.name, x_mm=both(xa, xb), diameter_mm=both(outer, outer) * 1e3, bore_mm=both(inner, inner) * 1e3,
            **{f"{field}_MPa": both(getattr(stresses[0], f"{field}_MPa"), getattr(stresses[1], f"{field}_MPa"))
               for field in ("axial", "bending", "torsion", "transverse_shear", "von_mises")})
    return profiles, forces, (xa, xb, outer), part


def shaft_strength(rig, frame, u_total: np.ndarray) -> ShaftStrength:
    """The shaft stresses and notch checks of one case.

    Parameters
    ----------
    rig : Rig
    frame : RigModel
        The sweep's frame (beam elements of every beam part; solid DOFs follow the frame's in ``u_total``).
    u_total : (n_dofs,) array
        The case's displacement from the unloaded geometry.

    Returns
    -------
    ShaftStrength
        One stress peak per beam shaft, one check per notch (in the rig file's order), and the shafts modelled as
        solids (not judged).
    """
    profiles, forces, ends, part = _evaluated(rig, frame, u_total)
    solid = tuple(p.name for p in rig.parts if p.role == "shaft" and p.name not in profiles)
    peaks, checks = [], []
    for p in rig.parts:
        if p.name not in profiles:
            continue
        profile = profiles[p.name]
        top = int(np.argmax(profile.von_mises_MPa))
        peaks.append(ShaftStressPeak(
            shaft=p.name, x_mm=float(profile.x_mm[top]), diameter_mm=float(profile.diameter_mm[top]),
            von_mises_MPa=float(profile.von_mises_MPa[top]),
            **{f"{field}_max_MPa": float(np.max(np.abs(getattr(profile, f"{field}_MPa"))))
               for field in ("bending", "torsion", "transverse_shear", "axial")}))
        xa, xb, outer = ends
        mine = np.flatnonzero(part == p.name)
        for notch in p.notches:
            geometry = notch_geometry(p, notch)
            target = geometry.outer_diameter_mm if notch.kind == "groove" else geometry.diameter_mm
            holding = [e for e in mine if min(xa[e], xb[e]) - 1e-6 <= notch.x_mm <= max(xa[e], xb[e]) + 1e-6]
            closest = min(abs(outer[e] * 1e3 - target) for e in holding)
            # at a node where a load enters (a hub's attachment) the section forces jump: the worse side counts
            candidates = [_notch_check(rig, p, notch, _interpolate(
                forces, e, min(max((notch.x_mm - xa[e]) / (xb[e] - xa[e]), 0.0), 1.0)))
                for e in holding if abs(outer[e] * 1e3 - target) <= closest + 1e-6]
            checks.append(min(candidates, key=lambda c: (c.fatigue_safety, c.static_safety)))
    return ShaftStrength(tuple(peaks), tuple(checks), solid)


def _notch_check(rig, part, notch, at: SectionForces) -> NotchCheck:
    """DIN 743 at ``notch`` of ``part`` under the section forces ``at`` (one station)."""
    geometry, steel, settings = notch_geometry(part, notch), steel_of(rig.materials[part.material]), rig.shaft_strength
    axial, moment, torque = float(at.axial_N[0]), float(at.bending_moment_Nm[0]), float(abs(at.torque_Nm[0]))
    sigma_zd, sigma_b, tau_t = din743.nominal_stresses(geometry, axial, moment, torque)
    peak = settings.peak_load_factor
    loads = din743.NotchStresses(tension_mean=sigma_zd, tension_max=peak * sigma_zd, bending_amplitude=sigma_b,
                                 bending_max=peak * sigma_b, torsion_mean=tau_t, torsion_max=peak * tau_t)
    d_eff = notch.d_eff_mm if notch.d_eff_mm is not None else geometry.outer_diameter_mm
    result = din743.safety(steel, geometry, loads, d_eff_mm=d_eff, overload_case=settings.overload_case)
    return NotchCheck(shaft=part.name, kind=notch.kind, x_mm=notch.x_mm, diameter_mm=geometry.diameter_mm,
                      bending_moment_Nm=moment, torque_Nm=torque, axial_force_N=axial, bending_amplitude_MPa=sigma_b,
                      torsion_mean_MPa=tau_t, axial_mean_MPa=sigma_zd, beta_bending=result.factors.beta_bending,
                      beta_torsion=result.factors.beta_torsion, K_sigma_bending=result.K_sigma_bending,
                      K_tau=result.K_tau, fatigue_safety=result.fatigue_safety, static_safety=result.static_safety,
                      minimum_safety=settings.minimum_safety, bending_allowed_amplitude_MPa=result.sigma_bADK,
                      torsion_allowed_amplitude_MPa=result.tau_tADK, bending_yield_MPa=result.sigma_bFK,
                      torsion_yield_MPa=result.tau_tFK)


def worst_notches(case_notches: list[tuple[str, list[dict]]]) -> list[dict]:
    """Per notch the smallest fatigue and static safety over the cases, each with the case it comes from.

    Parameters
    ----------
    case_notches : list of (case name, notch entries)
        The ``notches`` of each case's :meth:`ShaftStrength.entry` (as in ``sweep.json``), with the case's name.

    Returns
    -------
    list of dict
        ``{"shaft", "kind", "x_mm", "fatigue_safety", "fatigue_case", "static_safety", "static_case",
        "minimum_safety", "verdict"}`` per notch (a safety of None: no amplitude in any case, infinite).
    """
    worst: dict[tuple, dict] = {}
    for case, notches in case_notches:
        for n in notches:
            key = (n["shaft"], n["kind"], n["x_mm"])
            w = worst.setdefault(key, {"shaft": n["shaft"], "kind": n["kind"], "x_mm": n["x_mm"],
                                       "fatigue_safety": None, "fatigue_case": None, "static_safety": None,
                                       "static_case": None, "minimum_safety": n["minimum_safety"]})
            for which in ("fatigue", "static"):
                value = n[f"{which}_safety"]
                if value is not None and (w[f"{which}_safety"] is None or value < w[f"{which}_safety"]):
                    w[f"{which}_safety"], w[f"{which}_case"] = value, case
    out = []
    for w in worst.values():
        lowest = min((v for v in (w["fatigue_safety"], w["static_safety"]) if v is not None), default=math.inf)
        out.append({**w, "verdict": "ok" if lowest >= w["minimum_safety"] else "below S_min"})
    return out


def strength_of_records(rig, records: list[dict]) -> tuple[list[dict], list[dict]]:
    """The spectrum over a sweep's cases, from its records (``{"row", "entry"}``, as ``sweep.json`` holds them).

    Parameters
    ----------
    rig : Rig
        The rig the records come from (names its cases).
    records : list of dict
        The case records; only their ``entry`` is read.

    Returns
    -------
    (shafts, notches) : list of dict, list of dict
        Per beam shaft its largest von Mises stress over the cases (``von_mises_max_MPa``, ``x_mm``, ``case``);
        per notch :func:`worst_notches`. Empty lists for records without shaft strength.
    """
    from rvcoax.results.engineering import case_name

    shafts: dict[str, dict] = {}
    notches = []
    for record in records:
        entry = record["entry"]
        strength = entry.get("engineering", {}).get("shaft_strength")
        if strength is None:
            continue
        case = case_name(rig, entry["T1_input_Nm"], entry["T2_output_Nm"])
        for s in strength["shafts"]:
            best = shafts.get(s["shaft"])
            if best is None or s["von_mises_max_MPa"] > best["von_mises_max_MPa"]:
                shafts[s["shaft"]] = {"shaft": s["shaft"], "von_mises_max_MPa": s["von_mises_max_MPa"],
                                      "x_mm": s["von_mises_max_x_mm"], "case": case}
        notches.append((case, strength["notches"]))
    return list(shafts.values()), worst_notches(notches)
