"""Issue 24 item 4: a nonlinear sweep (ball bearings from geometry, a radial clearance) keeps every table of a
linear one, with each bearing's own force, operating stiffness and ball loads, and says when a bearing hangs
in its play or takes it up between neighbouring cases."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
import tomlkit
from typer.testing import CliRunner

from rvcoax.geometry.rigfile import parse_rig_text, reference_rig_text
from rvcoax.results.cli.app import app

CASES = ("--t1", "0.07,0.3,0.7,1.43", "--t2", "10,40,100,200")


def _sweep(tmp_path, text: str | None):
    args = ["sweep", *CASES, "--out", str(tmp_path / "out")]
    if text is not None:
        (tmp_path / "rig.toml").write_text(text, encoding="utf-8")
        args += ["--rig", str(tmp_path / "rig.toml")]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, (result.output, result.exception)
    with (tmp_path / "out" / "sweep.csv").open(newline="", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    return result.output, rows, json.loads((tmp_path / "out" / "sweep.json").read_text(encoding="utf-8"))


LIFE_SUFFIXES = ("_equivalent_load_N", "_L10_Mrev", "_L10_h", "_L10r_Mrev", "_L10r_h", "_Lnm_h", "_static_safety",
                 "_below_minimum_load")


def _groups(header) -> dict[str, int]:
    return {prefix: sum(k.startswith(prefix) for k in header) for prefix in ("coupling_", "bearing_", "reaction_")}


@pytest.fixture(scope="module")
def linear(tmp_path_factory):
    return _sweep(tmp_path_factory.mktemp("linear"), None)


@pytest.fixture(scope="module")
def balls(tmp_path_factory):
    return _sweep(tmp_path_factory.mktemp("balls"), reference_rig_text("ball_bearings"))


def test_a_ball_bearing_sweep_keeps_every_table_of_the_linear_one(linear, balls):
    _, linear_rows, _ = linear
    output, rows, document = balls
    groups, reference = _groups(rows[0]), _groups(linear_rows[0])
    assert groups["coupling_"] == reference["coupling_"] and groups["reaction_"] == reference["reaction_"]
    # the ball bearings' lives (from their ball loads) come on top of the linear rig's bearing columns
    lives = sum(k.startswith("bearing_") and k.endswith(LIFE_SUFFIXES) for k in rows[0])
    assert lives >= 4 * 4
    assert groups["bearing_"] == reference["bearing_"] + 2 * 4 + lives  # loaded elements, largest element load
    for title in ("Couplings at", "Bearings at", "Bearing operating points at", "Support reactions at"):
        assert title in output
    # every bearing's force is its own law's: the reactions and the applied loads balance in every case
    for case in document["cases"]:
        engineering = case["engineering"]
        vertical = sum(r["force_N"][1] for r in engineering["reactions"])
        assert vertical == pytest.approx(-engineering["applied_force_N"][1], rel=1e-8)
        b2 = next(b for b in engineering["bearings"] if b["name"] == "input_B2")
        assert b2["model"] == "ball" and b2["loaded_elements"] is not None


def test_operating_stiffness_is_the_tangent_not_the_reference_spring(balls):
    """The ball bearings' operating stiffness agrees with the solver report's operating points (the tangent of the
    ball law at each case), and differs from the linear reference spring the model is assembled with."""
    _, rows, document = balls
    rig = parse_rig_text(reference_rig_text("ball_bearings"))
    points = document["model"]["ball_bearing_operating_points"]
    for name in ("input_B1", "input_B2", "output_B1", "output_B2"):
        reference = next(b for b in rig.bearings if b.name == name).radial_stiffness_N_per_um
        for k, row in enumerate(rows):
            point = points[name][k + 1]  # [0] is the rest state
            expected = 0.5 * (point["radial_stiffness_y_N_per_um"] + point["radial_stiffness_z_N_per_um"])
            assert float(row[f"bearing_{name}_radial_stiffness_N_per_um"]) == pytest.approx(expected, rel=1e-9,
                                                                                            abs=1e-9)
            assert float(row[f"bearing_{name}_max_element_load_N"]) == pytest.approx(point["max_ball_load_N"], rel=1e-9,
                                                                                   abs=1e-12)
            assert float(row[f"bearing_{name}_radial_stiffness_N_per_um"]) != pytest.approx(reference, rel=0.05)


def test_a_bearing_in_its_play_and_a_play_taken_up_are_warned(balls):
    output = " ".join(balls[0].split())
    assert "warning: bearing input_B1 (ball) carries (nearly) nothing in all 4 cases" in output
    assert "takes up its play between" in output and "Y is not proportional to torque" in output


def test_a_radial_clearance_keeps_the_tables_and_is_warned(tmp_path, linear):
    document = tomlkit.parse(reference_rig_text())
    for bearing in document["bearings"]:
        if bearing["name"] == "input_B1":
            bearing["radial_clearance_um"] = 8.0
    output, rows, result = _sweep(tmp_path, tomlkit.dumps(document))
    assert _groups(rows[0]) == _groups(linear[1][0])
    flat = " ".join(output.split())
    assert "warning: bearing input_B1 (clearance) carries (nearly) nothing" in flat
    for case in result["cases"]:
        b1 = next(b for b in case["engineering"]["bearings"] if b["name"] == "input_B1")
        assert b1["model"] == "clearance" and b1["radial_stiffness_N_per_um"] == 0.0  # inside its play
        assert b1["force_radial_N"] == 0.0


def test_the_ross_shaft_line_takes_the_operating_stiffness():
    """A nonlinear bearing needs its operating stiffness for the ROSS rotor; the filled-in reference is refused."""
    from rvcoax.loadcases.cases import LoadCase
    from rvcoax.results.export.ross import operating_supports, shaft_line
    from rvcoax.results.sweep import run_sweep

    rig = parse_rig_text(reference_rig_text("ball_bearings"))
    with pytest.raises(ValueError, match="input_B1, input_B2 of the input shaft are nonlinear"):
        shaft_line(rig, "input")
    operating = operating_supports(run_sweep(rig, (LoadCase(0.7, 100.0), LoadCase(1.43, 200.0))), 1)
    assert set(operating) == {"input_B1", "input_B2", "output_B1", "output_B2"}
    line = shaft_line(rig, "input", operating)
    stiffness = {s.spring.name: s.radial_stiffness_N_per_m for s in line.supports}
    assert stiffness["input_B2"] == pytest.approx(operating["input_B2"][0]) and np.isfinite(stiffness["input_B1"])


def test_rounding_is_not_drawn_or_printed_as_data():
    """The ball-bearing sweep's u_z (~4e-12 µm against Y of µm) is rounding: the bending line draws it as 0; a
    real lateral motion (a pedestal's lateral flexibility, 2e-4 of Y) is drawn. A reaction component below 1e-9
    of the largest support force prints as 0."""
    from rvcoax.loadcases.cases import LoadCase
    from rvcoax.results.io.bending_line import bending_lines, out_of_plane_is_rounding
    from rvcoax.results.sweep import run_sweep

    sweep = run_sweep(parse_rig_text(reference_rig_text("ball_bearings")), (LoadCase(1.43, 200.0),))
    flat_z, flat_ry, largest = out_of_plane_is_rounding(bending_lines(sweep))
    assert flat_z and flat_ry and 0.0 < largest < 1e-9
    for reaction in sweep.cases[0].engineering.reactions:
        assert reaction.force_N[2] == 0.0  # no lateral load: its rounding (~1e-20 N) is written as exactly 0
    line = bending_lines(sweep)[0]
    tilted = type(line)(line.part, line.role, line.solid, line.x_mm, line.u_y_um, line.u_y_um * 2e-4,
                        line.rotation_z_urad, line.rotation_z_urad * 2e-4)
    assert out_of_plane_is_rounding([tilted])[:2] == (False, False)
