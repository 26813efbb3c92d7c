"""What a rig bearing's life needs from the rig file: its load ratings and its speed in a load case.

Load ratings (:func:`load_ratings`): the keys ``dynamic_load_rating_kN`` / ``static_load_rating_kN`` when
given (the catalogue's values); for a ``model = "ball"`` bearing otherwise from its internal geometry by
ISO 281 (C) and ISO 76 (C0, f0) (:mod:`rvcoax.fem.bearing_life`); for an angular-contact, cylindrical or tapered
roller bearing from its catalogue entry or geometry (:func:`rvcoax.geometry.rolling_model.load_ratings_N`), a set
of two rows rating 2^0.7 C (ball) or 2^(7/9) C (roller) and 2 C0. A typed-in (``model = "linear"``) bearing
without C has no life. :func:`equivalent_load` gives ISO 281's P of the angular-contact and roller types. f0 of a typed-in bearing (ISO 281's X and Y under axial load) is
:data:`TYPED_IN_F0` unless its geometry is known.

Life options (:func:`life_options`): κ from ``viscosity_ratio``, or from ``oil_viscosity_mm2_per_s`` and the
case's speed (κ = ν/ν1, ISO 281's ν1 at the pitch diameter); C_u by ISO 281 annex B from C0 and the pitch
diameter; the maker's minimum load from ``minimum_load_factor`` (SKF's k_r: with ν and n for ball and
angular-contact bearings, with n and ``reference_speed_rpm`` for cylindrical roller bearings; 0.02 C for tapered
roller bearings), else the rule of thumb 0.01 C / 0.02 C (:mod:`rvcoax.fem.bearing_life`).

Speeds (:func:`bearing_speeds_rpm`): the shafts joined to T1's part by couplings turn at the input speed,
those joined to T2's part at the output speed; a ``[[load_cases]]`` entry gives ``output_speed_rpm`` and
``input_speed_rpm`` (default: the output speed × a reducer's ``ratio``). A bearing's inner ring turns with its
shaft, its outer ring stands in the housing.
"""

from __future__ import annotations

from dataclasses import dataclass

from rvcoax.fem import bearing_life

__all__ = ["LIFE_KEYS", "LoadRatings", "RIB_THRUST_SHARE", "TYPED_IN_F0", "rib_thrust_warnings", "bearing_speeds_rpm", "check_life_keys", "equivalent_load",
           "life_options", "load_ratings", "rig_case_of", "set_rows", "shaft_sides"]

TYPED_IN_F0 = 13.0
"""f0 (ISO 76) taken for a typed-in ball bearing: the table's value at D_w/D_pw ≈ 0.23, the middle of the 62 and
63 series (12 … 14 over the catalogue)."""


@dataclass(frozen=True)
class LoadRatings:
    """C and C0 (N), f0, the rolling elements and where C comes from."""

    dynamic_N: float
    static_N: float | None
    f0: float | None
    elements: str
    source: str


def load_ratings(bearing) -> LoadRatings | None:
    """The load ratings of a rig bearing entry, or None when none are known (a typed-in bearing without C)."""
    typed_c = None if bearing.dynamic_load_rating_kN is None else bearing.dynamic_load_rating_kN * 1e3
    typed_c0 = None if bearing.static_load_rating_kN is None else bearing.static_load_rating_kN * 1e3
    if bearing.model == "ball":
        from rvcoax.geometry.ball_model import geometry_of

        geometry = geometry_of(bearing)
        z, d, dm = geometry.ball_count, geometry.ball_diameter_m * 1e3, geometry.pitch_diameter_m * 1e3
        c = typed_c if typed_c is not None else bearing_life.dynamic_rating_ball(z, d, dm)
        c0, f0 = bearing_life.static_rating_ball(z, d, dm)
        source = "rig keys" if typed_c is not None else "ISO 281 / ISO 76 from the internal geometry"
        return LoadRatings(c, typed_c0 if typed_c0 is not None else c0, f0, "ball", source)
    if bearing.model in ("angular_contact", "cylindrical_roller", "tapered_roller"):
        from rvcoax.geometry.rolling_model import entry_of, load_ratings_N

        c_row, c0_row = load_ratings_N(bearing)
        rows = set_rows(bearing)
        elements = "ball" if bearing.model == "angular_contact" else "roller"
        entry = entry_of(bearing)
        source = ("catalogue " + entry.designation + " (C by ISO 281 from its ESTIMATED geometry)"
                  if entry is not None else "ISO 281 / ISO 76 from the internal geometry")
        if rows > 1:
            source += f", a set of {rows}: C = {rows}^{'0.7' if elements == 'ball' else '7/9'} C of one, C0 = {rows} C0"
        c = typed_c if typed_c is not None else bearing_life.pair_dynamic_rating(c_row, rows, elements)
        c0 = typed_c0 if typed_c0 is not None else rows * c0_row
        return LoadRatings(c, c0, None, elements, "rig keys" if typed_c is not None else source)
    if typed_c is None:
        return None
    return LoadRatings(typed_c, typed_c0, TYPED_IN_F0 if bearing.rolling_elements == "ball" else None,
                       bearing.rolling_elements, "rig keys")


def set_rows(bearing) -> int:
    """i: the bearings of a set that share the load (a DB, DF or DT pair: 2; else 1)."""
    return 2 if getattr(bearing, "arrangement", "single") in ("DB", "DF", "DT") else 1


def equivalent_load(bearing, law, ratings: LoadRatings, radial_N: float, axial_N: float) -> tuple[float, float, float]:
    """(P, X, Y) of ISO 281 for an angular-contact, tapered or cylindrical roller entry (its set, as a unit).

    Angular-contact: ISO 281 table 3 by the nominal contact angle (a DB/DF pair with the pair's factors, a tandem
    set and a single bearing with the single-row ones; below 20° by i F_a / C0, C0 of one bearing); tapered:
    e = 1.5 tan α, X/Y of the single row or the pair; cylindrical: an NJ or NUP bearing (or one from explicit
    geometry) carries its thrust through the ribs (e = 0.2, P = 0.92 F_r + 0.6 F_a above: SKF Rolling bearings
    17000 EN p. 509 for the 10, 2, 3 and 4 series), an NU or N bearing none (P = F_r).

    Parameters
    ----------
    bearing : Bearing
        The rig entry.
    law : BallBearingGeometry or RollerBearingGeometry
        Its row geometry (the nominal contact angle).
    ratings : LoadRatings
        :func:`load_ratings` of the entry.
    radial_N, axial_N : float
        The loads on the set.
    """
    import math

    pair = bearing.arrangement in ("DB", "DF")
    rows = set_rows(bearing)
    if bearing.model == "angular_contact":
        c0_one = None if ratings.static_N is None else ratings.static_N / rows
        x, y, _ = bearing_life.angular_contact_xy(radial_N, axial_N, math.degrees(law.contact_angle_rad), pair=pair,
                                                  static_rating_N=c0_one, rows=rows)
    elif bearing.model == "tapered_roller":
        x, y, _ = bearing_life.tapered_xy(radial_N, axial_N, law.contact_angle_rad, pair=pair)
    elif bearing.designation is None or _cylindrical_variant(bearing) in ("NJ", "NUP"):
        x, y, _ = bearing_life.cylindrical_xy(radial_N, axial_N)
    else:
        x, y = 1.0, 0.0
    return x * abs(radial_N) + y * abs(axial_N), x, y


def rig_case_of(rig, input_torque_Nm: float, output_torque_Nm: float):
    """The rig file's ``[[load_cases]]`` entry with these torques, or None (cases from elsewhere)."""
    for case in rig.load_cases:
        if case.T1_input_Nm == input_torque_Nm and case.T2_output_Nm == output_torque_Nm:
            return case
    return None


def shaft_sides(rig) -> dict[str, str]:
    """``{shaft part: "input" | "output"}``: the shafts joined by couplings to T1's part (input) or T2's (output)."""
    links: dict[str, set[str]] = {p.name: set() for p in rig.parts if p.role == "shaft"}
    for c in rig.couplings:
        if c.from_.part in links and c.to.part in links:
            links[c.from_.part].add(c.to.part)
            links[c.to.part].add(c.from_.part)
    sides = {}
    for side, torque in (("input", rig.torques.T1), ("output", rig.torques.T2)):
        todo = [torque.part] if torque.part in links else []
        while todo:
            part = todo.pop()
            if part in sides:
                continue
            sides[part] = side
            todo.extend(links[part] - sides.keys())
    return sides


def bearing_speeds_rpm(rig, rig_case) -> dict[str, float | None]:
    """Each bearing's speed (rpm) in a ``[[load_cases]]`` entry; None where unknown."""
    output = None if rig_case is None else rig_case.output_speed_rpm
    inputs = None if rig_case is None else rig_case.input_speed_rpm
    if inputs is None and output is not None:
        ratios = [r.ratio for r in rig.reducers if r.ratio is not None]
        inputs = output * ratios[0] if ratios else None
    speed = {"input": inputs, "output": output}
    sides = shaft_sides(rig)
    return {b.name: speed.get(sides.get(b.shaft)) for b in rig.bearings}


def _cylindrical_variant(bearing) -> str | None:
    from rvcoax.geometry.rolling_model import cylindrical_variant

    return cylindrical_variant(bearing)


LIFE_KEYS = ("minimum_load_factor", "oil_viscosity_mm2_per_s", "reference_speed_rpm")
"""The rig keys of the maker's minimum load and of κ from the oil (:func:`life_options`)."""


def check_life_keys(bearing) -> None:
    """ValueError (naming the key) where a bearing entry's minimum-load and lubricant keys do not fit its model."""
    factor, viscosity, reference = (getattr(bearing, key) for key in LIFE_KEYS)
    if viscosity is not None and bearing.viscosity_ratio is not None:
        raise ValueError("oil_viscosity_mm2_per_s and viscosity_ratio both give κ: give one (the oil's viscosity at "
                         "operating temperature lets κ follow each case's speed)")
    if bearing.model == "linear":
        given = [key for key in LIFE_KEYS if getattr(bearing, key) is not None]
        if given:
            raise ValueError(f"{', '.join(given)}: need the bearing's mean diameter, known for a bearing from "
                             "geometry (model = \"ball\", \"angular_contact\", \"cylindrical_roller\", "
                             "\"tapered_roller\"); a typed-in bearing takes viscosity_ratio")
        return
    if reference is not None and bearing.model != "cylindrical_roller":
        raise ValueError("reference_speed_rpm: the maker's reference speed enters the minimum load of a cylindrical "
                         f"roller bearing only (this bearing is model = \"{bearing.model}\")")
    if factor is None:
        return
    if bearing.model == "tapered_roller":
        raise ValueError("minimum_load_factor: a tapered roller bearing's minimum load is 0.02 C (SKF), no factor")
    if bearing.model == "cylindrical_roller" and reference is None:
        raise ValueError("minimum_load_factor: a cylindrical roller bearing's minimum load F_rm = k_r (6 + 4 n/n_r) "
                         "(d_m/100)² kN also needs reference_speed_rpm (n_r, the catalogue's reference speed)")
    if bearing.model in ("ball", "angular_contact") and viscosity is None:
        raise ValueError("minimum_load_factor: a ball bearing's minimum load F_rm = k_r (ν n/1000)^(2/3) (d_m/100)² kN "
                         "also needs oil_viscosity_mm2_per_s (ν, the oil at operating temperature)")


def _diameters_mm(bearing) -> tuple[float, float]:
    """(pitch diameter, mean diameter (d + D)/2) in mm of a bearing from geometry (the mean: the catalogue's
    bore and outside diameter, else the pitch diameter)."""
    if bearing.model == "ball":
        from rvcoax.geometry.ball_model import BALL_BEARINGS, geometry_of

        pitch = geometry_of(bearing).pitch_diameter_m * 1e3
        entry = None if bearing.designation is None else BALL_BEARINGS.get(bearing.designation)
    else:
        from rvcoax.geometry.rolling_model import _law, entry_of

        pitch = _law(bearing).pitch_diameter_m * 1e3
        entry = entry_of(bearing)
    mean = pitch if entry is None else 0.5 * (entry.bore_mm + entry.outside_diameter_mm)
    return pitch, mean


def life_options(bearing, ratings: LoadRatings, speed_rpm: float | None) -> dict:
    """The keyword arguments of :func:`rvcoax.fem.bearing_life.life_from_forces` a rig bearing's keys give in a
    case at ``speed_rpm``: ``kappa``, ``contamination``, ``fatigue_limit_N`` and ``minimum_load_N`` (None: the
    rule of thumb)."""
    options = {"kappa": bearing.viscosity_ratio, "contamination": bearing.contamination_factor,
               "fatigue_limit_N": None, "minimum_load_N": None}
    if bearing.model == "linear":
        return options
    pitch, mean = _diameters_mm(bearing)
    if ratings.static_N is not None:
        options["fatigue_limit_N"] = bearing_life.fatigue_load_limit(ratings.static_N, pitch, ratings.elements)
    viscosity = bearing.oil_viscosity_mm2_per_s
    if viscosity is not None and speed_rpm is not None and speed_rpm > 0.0:
        options["kappa"] = viscosity / bearing_life.reference_viscosity_mm2_s(speed_rpm, pitch)
    factor = bearing.minimum_load_factor
    if bearing.model == "tapered_roller":
        options["minimum_load_N"] = bearing_life.TAPERED_MINIMUM_LOAD_SHARE * ratings.dynamic_N
    elif factor is not None and speed_rpm is not None:
        options["minimum_load_N"] = (
            bearing_life.cylindrical_minimum_load_N(factor, speed_rpm, bearing.reference_speed_rpm, mean)
            if bearing.model == "cylindrical_roller" else
            bearing_life.ball_minimum_load_N(factor, viscosity, speed_rpm, mean))
    return options


RIB_THRUST_SHARE = 0.5
"""SKF's limit on the thrust of a locating single-row cylindrical roller bearing (NJ, NUP): F_a ≤ 0.5 F_r (SKF Rolling
bearings 17000 EN p. 509, "F_a must not exceed 0,5 F_r")."""


def rib_thrust_warnings(rig, entries: list[dict], name_of) -> list[str]:
    """One sentence per NJ or NUP bearing whose ribs carry more thrust than :data:`RIB_THRUST_SHARE` of its radial load
    in some case (cases named by ``name_of(entry)``), from the ``sweep.json`` case entries' bearing forces."""
    if rig is None:
        return []
    ribbed = {b.name: _cylindrical_variant(b) for b in rig.bearings if b.model == "cylindrical_roller"
              and _cylindrical_variant(b) in ("NJ", "NUP")}
    found = []
    for name, variant in ribbed.items():
        over = [name_of(e) for e in entries for b in e.get("engineering", {}).get("bearings", ())
                if b["name"] == name and abs(b["force_axial_N"]) > max(RIB_THRUST_SHARE * b["force_radial_N"], 1.0)]
        if over:
            found.append(f"bearing {name} ({variant}) carries more thrust on its ribs than {RIB_THRUST_SHARE:g} F_r, the "
                         f"limit for a locating cylindrical roller bearing (SKF), in {len(over)} case(s) ("
                         + "; ".join(over[:3]) + (", …)" if len(over) > 3 else ")"))
    return found
