"""Ball bearings from geometry in a rig: the rig-file keys, the reference-rig variant, the nonlinear
sweep with operating stiffness per bearing and case, and the discrepancy vocabulary's bearing effects."""

from __future__ import annotations

import difflib

import numpy as np
import pytest
from rigdata import assert_input_b1_refused, with_bearing_keys

from rvcoax.geometry.ball_model import clearance_um_of, geometry_of
from rvcoax.geometry.effects import candidate_effects, effect_by_name
from rvcoax.geometry.rigfile import parse_rig_text, reference_rig_text
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.io.records import model_section
from rvcoax.results.sweep import ModelError, SweepSettings, run_sweep

BALL_NAMES = ("input_B1", "input_B2", "output_B1", "output_B2")
CASES = (LoadCase(1.43, 200.0), LoadCase(0.07, 10.0))
INPUT_B1 = '''name = "input_B1"                   # 6204 at the coupling side
shaft = "input_shaft"
housing = "input_bearing_block"
x_mm = 255                          # rig_reference part 5
'''


def _variant():
    return parse_rig_text(reference_rig_text("ball_bearings"), "variant")


def _with_input_b1(keys: str):
    """The variant with input_B1's model keys replaced by ``keys``."""
    return with_bearing_keys("ball_bearings", INPUT_B1, keys)


def test_the_variant_differs_from_the_reference_rig_only_in_the_four_shaft_bearings():
    reference, variant = reference_rig_text().splitlines(), reference_rig_text("ball_bearings").splitlines()
    changed = [line for line in difflib.unified_diff(reference, variant, lineterm="", n=0)
               if line[:1] in "+-" and not line.startswith(("+++", "---"))]
    body = [line for line in changed if not line.startswith("+#")]  # the variant's header comment
    assert sum(line.startswith("+model = \"ball\"") for line in body) == 4
    assert all("width_mm" in line or "stiffness_N_per_um" in line or line.startswith("+")
               or line.startswith("-name = ") for line in body if line.startswith("-"))
    rig = _variant()
    balls = {b.name: b for b in rig.bearings if b.model == "ball"}
    assert tuple(balls) == BALL_NAMES
    assert balls["input_B1"].width_mm == 14 and balls["output_B2"].width_mm == 16  # from the catalogue
    assert clearance_um_of(balls["input_B1"]) == 12.5  # CN for a 20 mm bore: 5–20 µm
    assert geometry_of(balls["output_B1"]).ball_count == 9
    assert 20 < balls["input_B1"].radial_stiffness_N_per_um < 200  # the linear reference, filled in


def test_a_designation_whose_bore_is_not_the_shaft_is_a_plausibility_warning():
    from rvcoax.geometry.catalogue import plausibility_warnings

    assert plausibility_warnings(_variant()) == []  # 6204 on the Ø20 input shaft, 6206 on the Ø30 output shaft
    rig = parse_rig_text(_with_input_b1('model = "ball"\ndesignation = "6206"'))
    assert plausibility_warnings(rig) == [
        "bearings[4] ('input_B1').designation = 6206: its bore is 30 mm, but the shaft's Ø at x = 255 mm is 20 mm: "
        "another designation, or the shaft's segment?"]


def test_the_from_geometry_reference_rig_takes_the_same_ball_bearings_on_request():
    from rvcoax.geometry.variants import READINGS, reference_from_geometry

    assert "ball_bearings" not in READINGS  # the default reading stays linear
    assert reference_from_geometry(("ball_bearings",)).bearings == _variant().bearings


def test_ball_bearing_keys_give_clear_errors():
    cases = {
        'model = "ball"\ndesignation = "6299"': "unknown ball bearing '6299'",
        'model = "ball"\nball_count = 8\nball_diameter_mm = 7.9': "missing: pitch_diameter_mm, inner_conformity",
        'model = "ball"\nclearance_class = "C3"\nball_count = 8\nball_diameter_mm = 7.9\npitch_diameter_mm = 33.5\n'
        'inner_conformity = 0.52\nouter_conformity = 0.53': "clearance_class needs a designation",
        'model = "ball"\ndesignation = "6204"\nradial_clearance_um = 5': "a ball bearing takes clearance_um",
        'radial_stiffness_N_per_um = 50\ndesignation = "6204"': "designation only apply to model = \"ball\"",
        'model = "ball"\ndesignation = "6204"\nclearance_class = "C7"': "clearance_class",
        'model = "ball"\ndesignation = "6204"\nclearance_um = -3': "clearance_um",
        'model = "ball"\nball_count = 30\nball_diameter_mm = 7.9\npitch_diameter_mm = 33.5\n'
        'inner_conformity = 0.52\nouter_conformity = 0.53\nclearance_um = 10': "do not fit on a pitch circle",
    }
    assert_input_b1_refused(_with_input_b1, cases)


def test_the_nonlinear_sweep_reports_operating_stiffness_per_bearing_and_case():
    sweep = run_sweep(_variant(), CASES)
    report = sweep.solver_report
    assert report["ball_bearings"] == list(BALL_NAMES)
    points = report["ball_bearing_operating_points"]
    assert set(points) == set(BALL_NAMES)
    for name in BALL_NAMES:
        assert [p["case"] for p in points[name]] == ["at rest"] + [c.label for c in CASES]
        for p in points[name]:
            assert p["radial_stiffness_y_N_per_um"] >= 0 and 0 <= p["loaded_balls"] <= 9
            assert (p["loaded_balls"] == 0) == (p["radial_force_N"] == 0.0)
    section = model_section(sweep)
    assert section["ball_bearings"] == list(BALL_NAMES) and "ball_bearing_operating_points" in section
    assert "ball bearings" in section["nonlinear"]
    # with CN clearance the lightly loaded input bearings let the torque's lateral load move the shaft
    # through the play: far more Y than the typed-in 50 N/µm reading
    typed = run_sweep(parse_rig_text(reference_rig_text()), CASES)
    assert sweep.cases[0].paths["input"].y_max_mm > 10 * typed.cases[0].paths["input"].y_max_mm


def test_preload_takes_up_the_clearance_and_stiffens_the_rig():
    loose = run_sweep(_variant(), CASES[:1])
    tight = _with_input_b1('model = "ball"\ndesignation = "6204"\nclearance_um = 0\npreload_N = 100')
    tight = tight.replace('''name = "input_B2"                   # 6204 at the reducer side''', '''name = "input_B2"
preload_N = 100''')
    preloaded = run_sweep(parse_rig_text(tight), CASES[:1])
    points = preloaded.solver_report["ball_bearing_operating_points"]
    assert points["input_B1"][0]["loaded_balls"] == 8  # every ball carries the preload at rest
    assert points["input_B1"][0]["radial_stiffness_y_N_per_um"] > 20
    assert preloaded.cases[0].paths["input"].y_max_mm < 0.2 * loose.cases[0].paths["input"].y_max_mm


def test_ball_bearings_are_refused_by_the_solid_model():
    with pytest.raises(ModelError, match="ball bearings from geometry .* the beam and hybrid models solve it"):
        run_sweep(_variant(), CASES[:1], SweepSettings(model="solid"))


@pytest.mark.slow
def test_the_hybrid_model_solves_ball_bearings_like_the_beam_model():
    # the nonlinear solve is the same on the hybrid system (solid input and output shafts); ~30–110 s
    hybrid = run_sweep(_variant(), CASES[:1], SweepSettings(model="hybrid"))
    beam = run_sweep(_variant(), CASES[:1])
    assert "ball bearings" in hybrid.solver_report["nonlinear"]
    for shaft in ("input", "output"):
        assert hybrid.cases[0].paths[shaft].y_max_mm == pytest.approx(beam.cases[0].paths[shaft].y_max_mm, rel=0.02)


def test_the_discrepancy_vocabulary_has_clearance_and_preload_of_ball_bearings():
    rig = _variant()
    names = {e.name: e for e in candidate_effects(rig)}
    assert "bearing_stiffness@input_B1" not in names  # the stiffness follows from geometry
    clearance, preload = names["bearing_clearance@input_B1"], names["bearing_preload@input_B1"]
    (c,), (p,) = clearance.parameters, preload.parameters
    assert (c.name, c.unit, c.lower, c.upper) == ("clearance_um", "µm", -12.5, 36.0 - 12.5)  # 0 … C4 max
    assert (p.name, p.unit, p.lower) == ("preload_N", "N", 0.0) and 50 < p.upper < 300
    assert not clearance.linear and not preload.linear
    assert clearance_um_of(next(b for b in clearance.apply(rig, [-10.0]).bearings if b.name == "input_B1")) == 2.5
    assert next(b for b in preload.apply(rig, [40.0]).bearings if b.name == "input_B1").preload_N == 40.0
    assert clearance.out_of_bounds([-13.0]) and not clearance.out_of_bounds([5.0])
    # zero leaves the results as they are
    base = run_sweep(rig, CASES[1:])
    same = run_sweep(effect_by_name(rig, "bearing_clearance@input_B1").apply(rig, [0.0]), CASES[1:])
    assert np.array_equal(base.cases[0].paths["input"].uy_mm, same.cases[0].paths["input"].uy_mm)
