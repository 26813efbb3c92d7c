"""The report's shaft-strength tables (issue 25 §5): stresses along the shafts and DIN 743 at the notches, each
row naming the load case its value comes from (the worst over the sweep's cases)."""

from __future__ import annotations

from rvcoax.geometry.shaft_notches import notch_geometry, steel_of
from rvcoax.results.engineering import case_name
from rvcoax.results.reports.report_tables import Table
from rvcoax.results.shaft_safety import strength_of_records

__all__ = ["shaft_strength_tables"]


def _g(value, digits: int = 3) -> str:
    return "∞ (no amplitude)" if value is None else f"{value:.{digits}g}"


_STEEL_GROUPS = {"quenched_tempered": "quenched and tempered", "case_hardening": "case-hardening steel",
                 "structural": "structural steel", "nitriding": "nitriding steel"}


def _geometry(notch) -> str:
    """The notch as DIN 743-2 sees it, in mm: Ø d/D and r (shoulder, groove with its depth), Ø d (keyway, press fit);
    no-break spaces inside each item, so that a narrow column wraps only after a comma."""
    nb = "\u00a0"
    if notch.kind == "shoulder":
        return f"Ø{notch.diameter_mm:g}/{notch.outer_diameter_mm:g}, r{nb}{notch.radius_mm:g}"
    if notch.kind == "groove":
        return (f"Ø{notch.diameter_mm:g}/{notch.outer_diameter_mm:g}, t{nb}{notch.depth_mm:g}, "
                f"r{nb}{notch.radius_mm:g}")
    if notch.kind == "keyway":
        return f"Ø{notch.diameter_mm:g}, {notch.keys}{nb}key" + ("s" if notch.keys > 1 else "")
    return f"Ø{notch.diameter_mm:g}"


def _notch_details(sweep, entries: list[dict], notches: list[dict]) -> Table:
    """Per notch the DIN 743 chain in the case of its smallest S_D (of its smallest S_F without an amplitude)."""
    rig = sweep.rig
    parts = {p.name: p for p in rig.parts}
    by_case = {}
    for e in entries:
        name = case_name(rig, e["T1_input_Nm"], e["T2_output_Nm"])
        for n in e.get("engineering", {}).get("shaft_strength", {}).get("notches", []):
            by_case[(name, n["shaft"], n["kind"], n["x_mm"])] = n
    rows, steels = [], {}
    for w in notches:
        part = parts[w["shaft"]]
        notch = next(n for n in part.notches if n.kind == w["kind"] and n.x_mm == w["x_mm"])
        steel = steel_of(rig.materials[part.material])
        grade = rig.materials[part.material].steel_grade
        steels[w["shaft"]] = (f"{w['shaft']}: {grade + ' ' if grade else ''}σ_B {steel.tensile_strength_MPa:g}, "
                              f"σ_S {steel.yield_strength_MPa:g} MPa at the reference diameter d_B "
                              f"({_STEEL_GROUPS[steel.group]})")
        case = w["fatigue_case"] or w["static_case"]
        n = by_case[(case, w["shaft"], w["kind"], w["x_mm"])]
        rows.append((w["shaft"], w["kind"], f"{w['x_mm']:g}", _geometry(notch_geometry(part, notch)), case,
                     _g(n["bending_amplitude_MPa"]), _g(n["torsion_mean_MPa"]), _g(n["beta_bending"]),
                     _g(n["beta_torsion"]), _g(n["K_sigma_bending"]), _g(n["sigma_bADK_MPa"]),
                     _g(n["fatigue_safety"])))
    settings = rig.shaft_strength
    return Table(
        "DIN 743 at each notch, in the case of its smallest S_D",
        ("shaft", "notch", "x [mm]", "geometry [mm]", "case", "σ_ba [MPa]", "τ_tm [MPa]", "β_σ", "β_τ", "K_σ",
         "σ_bADK [MPa]", "S_D fatigue"), tuple(rows),
        note="σ_ba = M_b/W_b, the bending amplitude of the rotating shaft, and τ_tm = T/W_t, the steady torsion, at the "
             "notch diameter d; β_σ, β_τ the notch factors (DIN 743-2: from α and the support number for shoulders and "
             "grooves, measured for keyways and press fits); K_σ = β_σ/K2(d) + 1/K_Fσ − 1 (K_V = 1); σ_bADK the "
             f"amplitude the notch endures at this mean stress (overload case {settings.overload_case}). With only the "
             "bending alternating, S_D = σ_bADK/σ_ba."
             + (" In overload case 2 the mean stress grows with the amplitude: where the bending amplitude is tiny "
                "against the steady stresses (their equivalent mean σ_mv = √((σ_zdm + σ_bm)² + 3 τ_tm²)), "
                "σ_bADK is tiny too and S_D comes close to the static S_F; the notch is then loaded statically "
                "rather than in fatigue." if settings.overload_case == 2 else "")
             + " Steels: " + "; ".join(steels.values()) + ". sweep.json: "
             "engineering.shaft_strength.notches (also τ_tADK, σ_bFK, τ_tFK).")


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
            f"Shaft notches, DIN 743: the smallest safety over the cases (required S_min = {minimum:g})",
            ("shaft", "notch", "x [mm]", "S_D fatigue", "S_D case", "S_F static", "S_F case", "verdict"),
            tuple((n["shaft"], n["kind"], f"{n['x_mm']:g}", _g(n["fatigue_safety"]), n["fatigue_case"] or "–",
                   _g(n["static_safety"]), n["static_case"] or "–", n["verdict"]) for n in notches),
            verdict_column=7,
            note="DIN 743-1…3 (2012) at each [[parts.notches]] entry, the shaft rotating: its bending moment bends it "
                 "fully reversed, torque and axial force are steady. Each case is judged as a constant load; the "
                 "spectrum's safety is the smallest over the cases (the highest-loaded case as nominal load, no damage "
                 "accumulation). Static proof at the case's loads × [shaft_strength] peak_load_factor = "
                 f"{sweep.rig.shaft_strength.peak_load_factor:g}. sweep.csv: notch_<shaft>_<kind>_at_<x>mm_…_safety."))
        tables.append(_notch_details(sweep, entries, notches))
    solid = sorted({name for e in entries
                    for name in e.get("engineering", {}).get("shaft_strength", {}).get("shafts_modelled_as_solids", [])})
    note = (f"Modelled as solids (no beam section forces, not judged): {', '.join(solid)}." if solid else "")
    return tables, note
