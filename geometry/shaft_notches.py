"""A rig's shaft notches and shaft steels as DIN 743 sees them (:mod:`rvcoax.fem.din743`).

``[[parts.notches]]`` of a shaft name where the shaft is notched (``x_mm`` on the rig axis) and how; the section's
diameters come from the part's segments: a shoulder sits at a segment boundary where the outer diameter steps
(d the smaller, D the larger, t = (D − d)/2, the fillet in the smaller diameter), a groove, keyway or press fit
inside one segment (a groove's root diameter d = D − 2 t). The steel's strengths come from its material's
``steel_grade`` (:data:`DIN743_STEELS`) or its typed-in ``tensile_strength_MPa`` / ``yield_strength_MPa``.
"""

from __future__ import annotations

import difflib

from rvcoax.fem import din743

__all__ = ["DIN743_STEELS", "DIN743_STEELS_SOURCE", "notch_geometry", "notch_problems", "steel_of", "unknown_grade"]

# σ_B(d_B), σ_S(d_B) in MPa at d_B = 16 mm (quenched and tempered, case hardening) or the group's d_B, and the
# group that sets K1(d_eff). [R]: recalled from DIN 743-3:2012 tables A.1, A.3, A.4; the same numbers stand in
# the open-source transcription github.com/hanslhansl/din743 (din743_3.py). Not checked against the standard.
DIN743_STEELS: dict[str, tuple[float, float, str]] = {
    "S235": (360.0, 235.0, "structural"),
    "S355": (470.0, 355.0, "structural"),
    "E335": (570.0, 335.0, "structural"),
    "C45": (700.0, 490.0, "quenched_tempered"),
    "C50": (750.0, 520.0, "quenched_tempered"),
    "41Cr4": (1000.0, 800.0, "quenched_tempered"),
    "34CrMo4": (1000.0, 800.0, "quenched_tempered"),
    "42CrMo4": (1100.0, 900.0, "quenched_tempered"),
    "50CrMo4": (1100.0, 900.0, "quenched_tempered"),
    "34CrNiMo6": (1200.0, 1000.0, "quenched_tempered"),
    "16MnCr5": (1000.0, 695.0, "case_hardening"),
    "20MnCr5": (1200.0, 850.0, "case_hardening"),
}
DIN743_STEELS_SOURCE = ("[R] recalled from DIN 743-3:2012 (tables A.1, A.3, A.4: strengths at the reference diameter), "
                        "in agreement with the open-source transcription github.com/hanslhansl/din743; not checked "
                        "against the standard: type tensile_strength_MPa / yield_strength_MPa from the material "
                        "certificate for a design review")


def steel_of(material) -> din743.Steel | None:
    """The DIN 743 steel of a rig material (its ``steel_grade`` or typed-in strengths); None without them."""
    if material.tensile_strength_MPa is not None and material.yield_strength_MPa is not None:
        return din743.Steel(material.tensile_strength_MPa, material.yield_strength_MPa,
                            material.steel_group or "quenched_tempered")
    if material.steel_grade is not None:
        tensile, yield_, group = DIN743_STEELS[material.steel_grade]
        return din743.Steel(tensile, yield_, material.steel_group or group)
    return None


def unknown_grade(grade: str) -> str:
    near = difflib.get_close_matches(grade, list(DIN743_STEELS), n=3, cutoff=0.4)
    return (f"unknown steel_grade '{grade}'" + (f" (nearest: {', '.join(near)})" if near else "")
            + f"; known: {', '.join(DIN743_STEELS)}, or give tensile_strength_MPa and yield_strength_MPa")


def _segments_at(part, x: float, tol: float = 1e-6):
    """(segment ending at x, segment starting at x) when x is a boundary, else (segment holding x, None)."""
    ending = [s for s in part.segments if abs(s.x_mm[1] - x) <= tol]
    starting = [s for s in part.segments if abs(s.x_mm[0] - x) <= tol]
    if ending and starting:
        return ending[0], starting[0]
    holding = [s for s in part.segments if s.x_mm[0] - tol <= x <= s.x_mm[1] + tol]
    return (holding[0] if holding else None), None


def notch_geometry(part, notch) -> din743.Notch:
    """The :class:`rvcoax.fem.din743.Notch` of ``notch`` (a ``[[parts.notches]]`` entry) on ``part``.

    Raises ``ValueError`` with the reason when the notch does not fit the part's segments.
    """
    left, right = _segments_at(part, notch.x_mm)
    if left is None:
        lo, hi = part.x_range_mm
        raise ValueError(f"x_mm = {notch.x_mm:g} lies outside the part ({lo:g} .. {hi:g} mm)")
    common = {"roughness_Rz_um": notch.roughness_Rz_um, "hard_surface": notch.hard_surface}
    if notch.kind == "shoulder":
        if right is None:
            raise ValueError(f"a shoulder sits where the outer diameter steps: x_mm = {notch.x_mm:g} is no boundary "
                             "between two segments")
        small, large = sorted((left, right), key=lambda s: s.outer_diameter_mm)
        if large.outer_diameter_mm - small.outer_diameter_mm < 1e-6:
            raise ValueError(f"no step at x_mm = {notch.x_mm:g}: both segments are Ø{small.outer_diameter_mm:g} mm")
        return din743.Notch("shoulder", small.outer_diameter_mm,
                            depth_mm=(large.outer_diameter_mm - small.outer_diameter_mm) / 2.0,
                            radius_mm=notch.fillet_radius_mm, bore_mm=small.inner_diameter_mm, **common)
    if right is not None and abs(left.outer_diameter_mm - right.outer_diameter_mm) > 1e-6:
        raise ValueError(f"a {notch.kind} at x_mm = {notch.x_mm:g} sits on a diameter step "
                         f"(Ø{left.outer_diameter_mm:g} | Ø{right.outer_diameter_mm:g} mm): place it inside a segment")
    segment = left
    if notch.kind == "groove":
        root = segment.outer_diameter_mm - 2.0 * notch.depth_mm
        if root <= segment.inner_diameter_mm:
            raise ValueError(f"the groove (depth_mm = {notch.depth_mm:g}) cuts through the wall of the "
                             f"Ø{segment.outer_diameter_mm:g}/{segment.inner_diameter_mm:g} mm segment")
        return din743.Notch("groove", root, depth_mm=notch.depth_mm, radius_mm=notch.fillet_radius_mm,
                            bore_mm=segment.inner_diameter_mm, **common)
    return din743.Notch(notch.kind, segment.outer_diameter_mm, keys=notch.keys, bore_mm=segment.inner_diameter_mm,
                        **common)


def notch_problems(rig):
    """One message per notch or shaft steel that cannot be checked (key path and reason)."""
    for i, part in enumerate(rig.parts):
        if not part.notches:
            continue
        where = f"parts[{i}] ('{part.name}').notches"
        if part.role != "shaft":
            yield f"{where}: only shafts (role = \"shaft\") carry notches"
            continue
        material = rig.materials.get(part.material)
        if material is not None and steel_of(material) is None:
            yield (f"materials.{part.material}: the notches of part '{part.name}' need the steel's strength: "
                   "steel_grade, or tensile_strength_MPa and yield_strength_MPa")
        for k, notch in enumerate(part.notches):
            try:
                notch_geometry(part, notch)
            except ValueError as error:
                yield f"{where}[{k}] ({notch.kind} at x_mm = {notch.x_mm:g}): {error}"
