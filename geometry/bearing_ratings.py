"""What a rig bearing's life needs from the rig file: its load ratings and its speed in a load case.

Load ratings (:func:`load_ratings`): the keys ``dynamic_load_rating_kN`` / ``static_load_rating_kN`` when
given (the catalogue's values); for a ``model = "ball"`` bearing otherwise from its internal geometry by
ISO 281 (C) and ISO 76 (C0, f0) (:mod:`rvcoax.fem.bearing_life`); for an angular-contact, cylindrical or tapered
roller bearing from its catalogue entry or geometry (:func:`rvcoax.geometry.rolling_model.load_ratings_N`), a set
of two rows rating 2^0.7 C (ball) or 2^(7/9) C (roller) and 2 C0. A typed-in (``model = "linear"``) bearing
without C has no life. :func:`equivalent_load` gives ISO 281's P of the angular-contact and roller types. f0 of a typed-in bearing (ISO 281's X and Y under axial load) is
:data:`TYPED_IN_F0` unless its geometry is known.

Speeds (:func:`bearing_speeds_rpm`): the shafts joined to T1's part by couplings turn at the input speed,
those joined to T2's part at the output speed; a ``[[load_cases]]`` entry gives ``output_speed_rpm`` and
``input_speed_rpm`` (default: the output speed × a reducer's ``ratio``). A bearing's inner ring turns with its
shaft, its outer ring stands in the housing.
"""

from __future__ import annotations

from dataclasses import dataclass

from rvcoax.fem import bearing_life

__all__ = ["LoadRatings", "TYPED_IN_F0", "bearing_speeds_rpm", "equivalent_load", "load_ratings", "rig_case_of",
           "set_rows", "shaft_sides"]

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
    e = 1.5 tan α, X/Y of the single row or the pair; cylindrical: an NJ bearing (or one from explicit geometry)
    carries its thrust through the ribs (e = 0.2, P = 0.92 F_r + 0.6 F_a above), an NU or N bearing none (P = F_r:
    the axial spring of the entry stands for a locating element elsewhere).

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
    elif bearing.designation is None or bearing.designation.strip().upper().startswith("NJ"):
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
