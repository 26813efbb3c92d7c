"""The report's shaft-strength tables (issue 25 §5): stresses along the shafts and DIN 743 at the notches, each
row naming the load case its value comes from (the worst over the sweep's cases)."""

from __future__ import annotations

from rvcoax.results.reports.report_tables import Table
from rvcoax.results.shaft_safety import strength_of_records

__all__ = ["shaft_strength_tables"]


def _g(value, digits: int = 3) -> str:
    return "∞ (no amplitude)" if value is None else f"{value:.{digits}g}"


def shaft_strength_tables(sweep, entries: list[dict]) -> tuple[list[Table], str]:
    """(tables, note): the shafts' largest stresses and the notches' smallest DIN 743 safety over the cases; the
    note names the shafts the model cannot judge (modelled as solids), empty otherwise."""
    records = [{"entry": e} for e in entries]
    shafts, notches = strength_of_records(sweep.rig, records)
    by_case = {}
    for e in entries:
        for s in e.get("engineering", {}).get("shaft_strength", {}).get("shafts", []):
            by_case.setdefault(s["shaft"], []).append(s)
    tables = []
    if shafts:
        rows = []
        for s in shafts:
            peak = max(by_case[s["shaft"]], key=lambda p: p["von_mises_max_MPa"])
            rows.append((s["shaft"], s["case"], _g(s["von_mises_max_MPa"]), f"{s['x_mm']:g}",
                         _g(peak["von_mises_max_diameter_mm"]), _g(peak["bending_max_MPa"]),
                         _g(peak["torsion_max_MPa"]), _g(peak["transverse_shear_max_MPa"]), _g(peak["axial_max_MPa"])))
        tables.append(Table(
            "Shaft stresses: the case of the largest von Mises stress per shaft",
            ("shaft", "case", "σ_v max [MPa]", "at x [mm]", "Ø there [mm]", "σ_b max [MPa]", "τ_t max [MPa]",
             "τ_q max [MPa]", "|σ_ax| max [MPa]"), tuple(rows),
            note="Nominal stresses of the round sections from the beam section forces of the total state (self-weight "
                 "included; without notch factors): σ_b from the resultant of both bending moments, τ_t torsion, τ_q "
                 "transverse shear at the neutral axis, σ_v von Mises (outer fibre, or neutral axis with τ_t + τ_q). "
                 "The maxima along the shaft in that case. sweep.csv: shaft_<name>_von_mises_max_MPa, …"))
    if notches:
        minimum = sweep.rig.shaft_strength.minimum_safety
        tables.append(Table(
            f"Shaft notches, DIN 743: the smallest safety over the cases (S_min = {minimum:g})",
            ("shaft", "notch", "x [mm]", "S_D fatigue", "case", "S_F static", "case", "verdict"),
            tuple((n["shaft"], n["kind"], f"{n['x_mm']:g}", _g(n["fatigue_safety"]), n["fatigue_case"] or "–",
                   _g(n["static_safety"]), n["static_case"] or "–", n["verdict"]) for n in notches),
            verdict_column=7,
            note="DIN 743-1…3 (2012) at each [[parts.notches]] entry, the shaft rotating: its bending moment bends it "
                 "fully reversed, torque and axial force are steady. Each case is judged as a constant load; the "
                 "spectrum's safety is the smallest over the cases (the highest-loaded case as nominal load, no damage "
                 "accumulation). Static proof at the case's loads × [shaft_strength] peak_load_factor = "
                 f"{sweep.rig.shaft_strength.peak_load_factor:g}. sweep.csv: notch_<shaft>_<kind>_at_<x>mm_…_safety."))
    solid = sorted({name for e in entries
                    for name in e.get("engineering", {}).get("shaft_strength", {}).get("shafts_modelled_as_solids", [])})
    note = (f"Modelled as solids (no beam section forces, not judged): {', '.join(solid)}." if solid else "")
    return tables, note
