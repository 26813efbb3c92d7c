"""RV reducers by designation: the maker's rating table, and what the rig model takes from it.

The catalogue is ``geometry/data/rv_reducers.csv``, one row per size of Nabtesco's RV-E series
(RV-6E … RV-450E). Columns and their meaning in the maker's rating table (Nabtesco, *Precision Reduction
Gear RV™ — E Series / C Series / Original Series*, catalogue, "Rating table" of the E series; the same
table is in Nabtesco's *Reducer for high precision control — RV series* technical data):

- ``rated_torque_Nm`` at ``rated_output_speed_rpm``: the torque for the rated life (6000 h);
- ``acceleration_torque_Nm``: allowable acceleration/deceleration torque (start and stop, the permitted peak
  torque of normal operation);
- ``momentary_max_torque_Nm``: momentary maximum allowable torque (emergency stop, shock);
- ``allowable_moment_Nm`` and ``momentary_max_moment_Nm``: the tilting moment the main bearings (an
  angular-contact ball-bearing pair) carry continuously, and at most momentarily;
- ``max_axial_load_N``: the largest axial load on the output (with no moment; with a moment the maker's
  allowable-moment diagram lowers it);
- ``torsional_rigidity_Nm_per_arcmin`` and ``moment_rigidity_Nm_per_arcmin``: the output's stiffness against
  twist (between the knees of the hysteresis curve) and against tilt (main bearings with the case);
- ``mass_kg``.

Provenance, in ``source``: **[R]**: the value as recalled from that rating table; the table itself could not be
retrieved (public transcriptions of the catalogue exist, but none whose rating-table pages could be read while this
catalogue was checked), so every [R] value is to be checked against the maker's current catalogue before a design
review relies on it. **[S2]**: a value that a public secondary source quoting the maker gives too:
RV-20E 167 / 412 / 833 N·m (rated, acceleration/deceleration, momentary maximum), 4.7 kg, and RV-40E
412 / 1029 / 2058 N·m, 9.3 kg (a robotics knowledge base's RV-20E-81 and RV-40E-105 component pages, which cite
Nabtesco's product pages and its *RV Series* catalogue); 167 N·m and 4.7 kg at 15 rpm once more in a project's
primary-source review that cites Nabtesco's RV-E product page (precision.nabtesco.com/…/products/detail/RV-E), in a
row that names the RV-20E together with a competitor's equivalent.
Not a primary source, so [S2], not [S1]. Also seen and **not** used: an uncited reducer-selection tool (public
code) lists the rated torques of RV-6E, RV-80E, RV-110E, RV-160E and RV-320E as 58, 784, 1078, 1568, 3136 N·m —
the table's values, noted in ``source`` but not enough to upgrade [R] — and gives RV-20E 196 and RV-40E 392 N·m
against the 167 and 412 N·m kept here: two sources quoting the maker agree on 167 / 412, the tool cites nothing
and its other columns are generic (one 5 × peak factor and 20 000 h life for every size, where the maker rates
6000 h), so its two values are taken for a slip. A Chinese maker's ZKRV-E table (own ratings of its RV-E-like
sizes) is a different product and is not used. Lost motion and backlash (≤ 1 arcmin in the secondary sources)
are not part of the model and not in the file.
**[E]**: estimated here, with how:
``main_bearing_spread_mm``, the distance of the two main bearings' pressure centres, is not published; it is
ℓ = 50 mm · (T_rated / 167 N·m)^(1/3), the RV-20E's 50 mm taken as 0.6 × its 85 mm case length and scaled
with the size (the linear size of geometrically similar reducers grows with the cube root of the torque).
The rating table (as recalled, [R]) gives no permitted radial load: a radial load W at a distance ℓ_W from the main bearings'
centre loads them with the moment W·ℓ_W, which the model's moment at the bearings includes (checked against
the allowable moment).

What the rig model takes (:func:`reducer_joint`): the reducer's output is a six-component spring between
the case and the output flange at the main bearings' centre — torsion from the torsional rigidity, tilt about
both lateral axes from the moment rigidity, radial stiffness of the bearing pair from the moment rigidity
k_r = 4 K_M / ℓ² (two equal bearings ℓ apart: K_M = 2 (k_r/2)(ℓ/2)²), axial stiffness taken equal to the
radial one (a pair of ≈ 45° angular-contact bearings) [E]. Rig keys override each.
"""

from __future__ import annotations

import csv
import difflib
import io
import math
from dataclasses import dataclass
from importlib import resources

__all__ = ["ARCMIN_PER_RAD", "CATALOGUE_FILE", "RV_REDUCERS", "CatalogueReducer", "ReducerCheck", "nearest_designations",
           "reducer_check", "reducer_entry", "reducer_joint_data", "reducer_stiffness"]

ARCMIN_PER_RAD = 60.0 * 180.0 / math.pi
CATALOGUE_FILE = "rv_reducers.csv"


@dataclass(frozen=True)
class CatalogueReducer:
    """One size of the rating table (N·m, N, N·m/arcmin, kg, mm)."""

    designation: str
    rated_torque_Nm: float
    rated_output_speed_rpm: float
    acceleration_torque_Nm: float
    momentary_max_torque_Nm: float
    allowable_moment_Nm: float
    momentary_max_moment_Nm: float
    max_axial_load_N: float
    torsional_rigidity_Nm_per_arcmin: float
    moment_rigidity_Nm_per_arcmin: float
    mass_kg: float
    main_bearing_spread_mm: float
    source: str


def _read() -> dict[str, CatalogueReducer]:
    text = resources.files("rvcoax.geometry").joinpath("data", CATALOGUE_FILE).read_text(encoding="utf-8")
    out = {}
    for row in csv.DictReader(io.StringIO(text)):
        values = {k: (v if k in ("designation", "source") else float(v)) for k, v in row.items()}
        out[row["designation"]] = CatalogueReducer(**values)
    return out


RV_REDUCERS: dict[str, CatalogueReducer] = _read()


def nearest_designations(designation: str, known) -> list[str]:
    """Up to three known designations nearest to ``designation`` (by spelling)."""
    known = list(known)
    close = difflib.get_close_matches(designation.upper(), [k.upper() for k in known], n=3, cutoff=0.4)
    return [next(k for k in known if k.upper() == c) for c in close]


def reducer_entry(designation: str) -> CatalogueReducer:
    """The catalogue entry; ValueError naming the nearest designations for an unknown one."""
    if designation in RV_REDUCERS:
        return RV_REDUCERS[designation]
    near = nearest_designations(designation, RV_REDUCERS)
    raise ValueError(f"unknown reducer {designation!r}" + (f" (nearest: {', '.join(near)})" if near else "")
                     + f"; known: {', '.join(RV_REDUCERS)}")


def reducer_stiffness(reducer) -> dict[str, float]:
    """The output spring of a ``[[reducers]]`` entry in rig-file units: torsional and moment rigidity
    (N·m/rad), radial and axial stiffness of the main bearings (N/µm), and the spread used (mm).

    Rig keys (``moment_rigidity_Nm_per_arcmin``, ``torsional_rigidity_Nm_per_arcmin``,
    ``main_bearing_spread_mm``, ``radial_stiffness_N_per_um``, ``axial_stiffness_N_per_um``) override the
    catalogue.
    """
    entry = reducer_entry(reducer.designation)
    moment = (reducer.moment_rigidity_Nm_per_arcmin or entry.moment_rigidity_Nm_per_arcmin) * ARCMIN_PER_RAD
    torsion = (reducer.torsional_rigidity_Nm_per_arcmin or entry.torsional_rigidity_Nm_per_arcmin) * ARCMIN_PER_RAD
    spread = reducer.main_bearing_spread_mm or entry.main_bearing_spread_mm
    radial = reducer.radial_stiffness_N_per_um or 4.0 * moment / (spread * 1e-3) ** 2 * 1e-6
    axial = reducer.axial_stiffness_N_per_um or radial
    return {"torsional_Nm_per_rad": torsion, "moment_Nm_per_rad": moment, "radial_N_per_um": radial,
            "axial_N_per_um": axial, "spread_mm": spread}


def reducer_joint_data(reducer) -> dict:
    """The ``[[joints]]`` entry (file keys) that stands for a reducer's main bearings and output."""
    k = reducer_stiffness(reducer)
    return {"name": reducer.name, "from": reducer.case.model_dump(exclude_none=True),
            "to": reducer.output.model_dump(exclude_none=True),
            "translational_stiffness_N_per_um": [k["axial_N_per_um"], k["radial_N_per_um"], k["radial_N_per_um"]],
            "rotational_stiffness_Nm_per_rad": [k["torsional_Nm_per_rad"], k["moment_Nm_per_rad"],
                                                k["moment_Nm_per_rad"]]}


@dataclass(frozen=True)
class ReducerCheck:
    """One reducer in one load case: its output torque, the moment and axial force on its main bearings, each
    against the rating table (``*_use_percent``: of the allowable), and the verdict."""

    name: str
    designation: str
    torque_Nm: float
    moment_Nm: float
    axial_force_N: float
    radial_force_N: float
    torque_rated_percent: float
    torque_peak_percent: float
    torque_momentary_percent: float
    moment_use_percent: float
    moment_momentary_percent: float
    axial_use_percent: float

    @property
    def verdict(self) -> str:
        """``within rating``, ``above rated torque``, ``EXCEEDS …`` (the worst that applies)."""
        worst = []
        if self.torque_momentary_percent > 100.0:
            worst.append("EXCEEDS momentary maximum torque")
        elif self.torque_peak_percent > 100.0:
            worst.append("EXCEEDS allowable peak (acceleration) torque")
        if self.moment_momentary_percent > 100.0:
            worst.append("EXCEEDS momentary maximum moment")
        elif self.moment_use_percent > 100.0:
            worst.append("EXCEEDS allowable moment")
        if self.axial_use_percent > 100.0:
            worst.append("EXCEEDS maximum axial load")
        if worst:
            return "; ".join(worst)
        if self.torque_rated_percent > 100.0:
            return "above rated torque (peak range: shortens life)"
        return "within rating"

    @property
    def exceeds(self) -> bool:
        return self.verdict.startswith("EXCEEDS") or "EXCEEDS" in self.verdict


def reducer_check(reducer, torque_Nm: float, force_N, moment_Nm) -> ReducerCheck:
    """A reducer's check in one case from its output torque and the force (x, y, z) and moment (x, y, z) its
    main bearings carry (at their centre, where the rig places the reducer's joint)."""
    entry = reducer_entry(reducer.designation)
    torque = abs(float(torque_Nm))
    moment = math.hypot(float(moment_Nm[1]), float(moment_Nm[2]))
    axial = abs(float(force_N[0]))
    radial = math.hypot(float(force_N[1]), float(force_N[2]))
    return ReducerCheck(name=reducer.name, designation=entry.designation, torque_Nm=torque, moment_Nm=moment,
                        axial_force_N=axial, radial_force_N=radial,
                        torque_rated_percent=100.0 * torque / entry.rated_torque_Nm,
                        torque_peak_percent=100.0 * torque / entry.acceleration_torque_Nm,
                        torque_momentary_percent=100.0 * torque / entry.momentary_max_torque_Nm,
                        moment_use_percent=100.0 * moment / entry.allowable_moment_Nm,
                        moment_momentary_percent=100.0 * moment / entry.momentary_max_moment_Nm,
                        axial_use_percent=100.0 * axial / entry.max_axial_load_N)
