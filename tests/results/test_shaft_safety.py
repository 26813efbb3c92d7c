"""Shaft stresses and DIN 743 notch checks of a whole sweep (rvcoax.results.shaft_safety) on a closed-form rig.

A stepped shaft (Ø30 on 0…120 mm, Ø40 on 120…300 mm), pinned at both ends (the right end also holds the
torque), a 2000 N point load at x = 180 mm (the force table) and the torque T1 at its left end: statically
determinate, so at the shoulder M = F b x / L = 96 N·m (b = 120 mm), T = T1, N = 0 whatever the stiffness.
The notch checks must equal :func:`rvcoax.fem.din743.safety` at those section forces (the chain itself is
verified in tests/fem/test_din743.py), and the von Mises peak must sit at the shoulder's thin side.
"""

from __future__ import annotations

import math

import pytest
from closed_form_rigs import HUGE, HUGE_ROTATION, STEEL, make_rig

from rvcoax.fem import din743
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.io.records import case_entry, case_row
from rvcoax.results.shaft_safety import strength_of_records
from rvcoax.results.sweep import run_sweep

FORCE_N, LOAD_X, LENGTH, STEP_X = 2000.0, 180.0, 300.0, 120.0


def _rig(**changes):
    shaft = {"name": "s", "role": "shaft", "material": "steel",
             "segments": [{"x_mm": [0.0, STEP_X], "outer_diameter_mm": 30.0},
                          {"x_mm": [STEP_X, LENGTH], "outer_diameter_mm": 40.0}],
             "notches": [{"x_mm": STEP_X, "kind": "shoulder", "fillet_radius_mm": 2.0},
                         {"x_mm": 60.0, "kind": "keyway"}]}
    pinned = {"translational_stiffness_N_per_um": [HUGE] * 3}
    mounts = [{"name": "left", "part": "s", "x_mm": 0.0, **pinned, "rotational_stiffness_Nm_per_rad": [0.0] * 3},
              {"name": "right", "part": "s", "x_mm": LENGTH, **pinned,
               "rotational_stiffness_Nm_per_rad": [HUGE_ROTATION, 0.0, 0.0]}]
    table = {"apply": True, "singles": [{"label": "P", "force_N": -FORCE_N, "at": {"part": "s", "x_mm": LOAD_X}}]}
    return make_rig([shaft], "s", "s", mounts=mounts, force_table=table,
                    materials={"steel": {**STEEL, "steel_grade": "42CrMo4"}}, **changes)


@pytest.fixture(scope="module")
def swept():
    rig = _rig()
    return rig, run_sweep(rig, (LoadCase(50.0, 0.0), LoadCase(120.0, 0.0)))


def test_notch_section_forces_and_safety_match_the_closed_form(swept):
    rig, sweep = swept
    moment = FORCE_N * (LENGTH - LOAD_X) * STEP_X / LENGTH * 1e-3  # 96 N·m
    for case, torque in zip(sweep.cases, (50.0, 120.0)):
        shoulder, keyway = case.shaft_strength.notches
        assert shoulder.bending_moment_Nm == pytest.approx(moment, rel=1e-6)
        assert shoulder.torque_Nm == pytest.approx(torque, rel=1e-6)
        assert abs(shoulder.axial_force_N) < 1e-6 * FORCE_N
        assert keyway.bending_moment_Nm == pytest.approx(moment / 2, rel=1e-6)
        notch = din743.Notch("shoulder", 30.0, depth_mm=5.0, radius_mm=2.0)
        sigma_b = moment * 1e3 / (math.pi * 30.0**3 / 32)
        tau = torque * 1e3 / (math.pi * 30.0**3 / 16)
        expected = din743.safety(din743.Steel(1100.0, 900.0), notch, din743.NotchStresses(
            bending_amplitude=sigma_b, bending_max=sigma_b, torsion_mean=tau, torsion_max=tau), d_eff_mm=40.0)
        assert shoulder.bending_amplitude_MPa == pytest.approx(sigma_b, rel=1e-6)
        assert shoulder.fatigue_safety == pytest.approx(expected.fatigue_safety, rel=1e-6)
        assert shoulder.static_safety == pytest.approx(expected.static_safety, rel=1e-6)


def test_von_mises_peak_at_the_thin_side_of_the_shoulder(swept):
    _, sweep = swept
    (peak,) = sweep.cases[0].shaft_strength.peaks
    sigma_b = 96.0e3 / (math.pi * 30.0**3 / 32)
    tau = 50.0e3 / (math.pi * 30.0**3 / 16)
    assert (peak.shaft, peak.x_mm, peak.diameter_mm) == ("s", STEP_X, pytest.approx(30.0))
    assert peak.von_mises_MPa == pytest.approx(math.hypot(sigma_b, math.sqrt(3) * tau), rel=1e-6)


def test_columns_entries_and_the_worst_case_over_the_spectrum(swept):
    rig, sweep = swept
    rows = [case_row(c) for c in sweep.cases]
    assert rows[0]["notch_s_shoulder_at_120mm_fatigue_safety"] > rows[1]["notch_s_shoulder_at_120mm_fatigue_safety"]
    assert {"shaft_s_von_mises_max_MPa", "shaft_s_von_mises_max_x_mm"} <= set(rows[0])
    records = [{"row": r, "entry": case_entry(c)} for r, c in zip(rows, sweep.cases)]
    shafts, notches = strength_of_records(rig, records)
    assert shafts[0]["case"] == "T1 = 120 N·m, T2 = 0 N·m"  # the larger torque: the larger von Mises stress
    worst = {n["kind"]: n for n in notches}
    assert worst["shoulder"]["fatigue_safety"] == pytest.approx(rows[1]["notch_s_shoulder_at_120mm_fatigue_safety"])
    assert worst["shoulder"]["fatigue_case"] == "T1 = 120 N·m, T2 = 0 N·m"


def test_notches_that_do_not_fit_the_shaft_are_refused_with_their_key():
    from pydantic import ValidationError

    def refused(notch: dict, match: str, **material):
        shaft = {"name": "s", "role": "shaft", "material": "steel", "notches": [notch],
                 "segments": [{"x_mm": [0.0, STEP_X], "outer_diameter_mm": 30.0},
                              {"x_mm": [STEP_X, LENGTH], "outer_diameter_mm": 40.0}]}
        with pytest.raises(ValidationError, match=match):
            make_rig([shaft], "s", "s", materials={"steel": {**STEEL, **(material or {"steel_grade": "C45"})}})

    refused({"x_mm": 100.0, "kind": "shoulder", "fillet_radius_mm": 1.0}, r"notches\[0\].*no boundary")
    refused({"x_mm": STEP_X, "kind": "keyway"}, "diameter step")
    refused({"x_mm": 50.0, "kind": "groove", "depth_mm": 1.0}, "fillet_radius_mm: required")
    refused({"x_mm": STEP_X, "kind": "shoulder", "fillet_radius_mm": 0.1}, "r/t")
    refused({"x_mm": 400.0, "kind": "keyway"}, "outside the part")
    refused({"x_mm": 50.0, "kind": "keyway"}, "need the steel's strength", youngs_modulus_MPa=2.1e5)
    refused({"x_mm": 50.0, "kind": "keyway"}, "nearest: C50, C45", steel_grade="C54")
    refused({"x_mm": 50.0, "kind": "keyway"}, "give tensile_strength_MPa and yield_strength_MPa together",
            tensile_strength_MPa=700.0)


def test_report_tables_name_the_case_of_each_value(swept):
    from rvcoax.results.reports.report_tables import case_entries
    from rvcoax.results.reports.shaft_tables import shaft_strength_tables

    _, sweep = swept
    tables, note = shaft_strength_tables(sweep, case_entries(sweep))
    stresses, notches, details = tables
    assert note == ""
    assert stresses.rows[0][:2] == ("s", "T1 = 120 N·m, T2 = 0 N·m")
    shoulder = next(r for r in notches.rows if r[1] == "shoulder")
    assert shoulder[4] == shoulder[6] == "T1 = 120 N·m, T2 = 0 N·m" and shoulder[7] == "ok"
    assert notches.columns[notches.verdict_column] == "verdict"
    assert "required S_min = 1.2" in notches.caption
    # the chain behind each S_D, in the same case: only the bending alternates, so S_D = σ_bADK/σ_ba
    columns = details.columns
    for row in details.rows:
        summary = next(r for r in notches.rows if r[:3] == row[:3])
        assert row[columns.index("case")] == summary[4]
        assert row[columns.index("S_D fatigue")] == summary[3]
        ratio = float(row[columns.index("σ_bADK [MPa]")]) / float(row[columns.index("σ_ba [MPa]")])
        assert ratio == pytest.approx(float(summary[3]), rel=0.015)  # three printed digits each
    for entry in case_entries(sweep):
        for n in entry["engineering"]["shaft_strength"]["notches"]:
            assert n["sigma_bADK_MPa"] / n["bending_amplitude_MPa"] == pytest.approx(n["fatigue_safety"], rel=1e-12)
    shoulder, keyway = details.rows
    assert shoulder[3] == "Ø30/40, r\u00a02" and keyway[3] == "Ø30, 1\u00a0key"
    assert "42CrMo4 σ_B 1100, σ_S 900 MPa" in details.note and "overload case 2" in details.note


def test_stress_profile_along_the_shaft_is_the_closed_form(swept):
    """σ_b(x) = M(x)/W_b(x) at every station, both sides of the step; τ_t = T/W_t; axial 0."""
    import numpy as np

    from rvcoax.results import case_stress_profiles

    _, sweep = swept
    profile = case_stress_profiles(sweep, 0)["s"]
    x, d = profile.x_mm, profile.diameter_mm
    moment = np.where(x <= LOAD_X, FORCE_N * (LENGTH - LOAD_X) * x / LENGTH,
                      FORCE_N * LOAD_X * (LENGTH - x) / LENGTH) * 1e-3  # N·m
    np.testing.assert_allclose(profile.bending_MPa, moment * 1e3 / (np.pi * d**3 / 32), rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(profile.torsion_MPa, 50.0e3 / (np.pi * d**3 / 16), rtol=1e-6)
    assert np.max(np.abs(profile.axial_MPa)) < 1e-6
    assert set(np.round(d, 9)) == {30.0, 40.0} and np.all(profile.bore_mm == 0.0)


def test_self_weight_through_a_sweep_gives_q_l_squared_over_8():
    """Gravity on, no other load: the uniform Ø30 shaft's midspan moment is q L²/8, so the self-weight the model
    applies and the one taken off the elements' end forces agree in size and direction."""
    import numpy as np

    from rvcoax.results import case_stress_profiles

    shaft = {"name": "s", "role": "shaft", "material": "steel",
             "segments": [{"x_mm": [0.0, LENGTH], "outer_diameter_mm": 30.0}]}
    pinned = {"translational_stiffness_N_per_um": [HUGE] * 3}
    mounts = [{"name": "left", "part": "s", "x_mm": 0.0, **pinned, "rotational_stiffness_Nm_per_rad": [0.0] * 3},
              {"name": "right", "part": "s", "x_mm": LENGTH, **pinned,
               "rotational_stiffness_Nm_per_rad": [HUGE_ROTATION, 0.0, 0.0]}]
    rig = make_rig([shaft], "s", "s", mounts=mounts, gravity={"enabled": True, "acceleration_m_per_s2": 9.81})
    sweep = run_sweep(rig, (LoadCase(0.0, 0.0),))
    profile = case_stress_profiles(sweep, 0)["s"]
    q = STEEL["density_kg_per_m3"] * math.pi / 4 * 0.03**2 * 9.81  # N/m
    x = profile.x_mm * 1e-3
    moment = q * x * (LENGTH * 1e-3 - x) / 2.0
    w_b = math.pi * 0.03**3 / 32
    peak = q * (LENGTH * 1e-3) ** 2 / 8 / w_b * 1e-6  # MPa
    np.testing.assert_allclose(profile.bending_MPa, moment / w_b * 1e-6, rtol=0, atol=1e-6 * peak)
    assert profile.bending_MPa.max() == pytest.approx(peak, rel=1e-3)  # midspan is a node
