"""Paper 000's transmission-chain error vector model (results/studies/chain_error.py, `rvcoax chain-error`).

The paper's arithmetic and sign convention, the torsion constant 7350 derived from G, every
component's formula against an independent torsion calculation (the project's Timoshenko beam
elements, one clamped shaft per stage), the printed formulas read with our units, the example
forces file, and the errors a user sees.
"""

from __future__ import annotations

import dataclasses
import json
import math

import frames
import numpy as np
import pytest
from typer.testing import CliRunner

from rvcoax.fem.sections import CircularSection
from rvcoax.geometry.rigfile import load_rig
from rvcoax.results.cli.app import app
from rvcoax.results.studies.chain_error import (
    NO_TILT,
    ChainDataError,
    Coaxiality,
    contribution,
    evaluate_chain_error,
    load_chain_model,
    read_stage_forces,
    signed_total,
    torsion_constant_deg_per_m,
)

DATA = __import__("pathlib").Path(__file__).resolve().parents[3] / "results" / "data"
EXAMPLE_FORCES = DATA / "paper000_chain_forces.csv"
# paper 000: θ_total = θ22 − θ11 − θ44 − θ55 = 0.1020° − 0.000138° − 0.0147° − 0.0815° = 0.005662°
PAPER_CONTRIBUTIONS_DEG = {"crankshaft": 0.1020, "input_shaft": 0.000138, "output_disk": 0.0147, "pin_shaft": 0.0815}
PAPER_TOTAL_DEG = 0.005662


@pytest.fixture(scope="module")
def rig():
    return load_rig()


@pytest.fixture(scope="module")
def chain(rig):
    return load_chain_model(rig)


def test_paper_arithmetic_and_sign_convention(chain):
    signs = {c.name: c.sign for c in chain.components}
    assert signs == {"input_shaft": -1, "crankshaft": 1, "output_disk": -1, "pin_shaft": -1}
    assert signed_total(PAPER_CONTRIBUTIONS_DEG, signs) == pytest.approx(PAPER_TOTAL_DEG, abs=1e-12)
    assert {c.name: c.symbol for c in chain.components} == {
        "input_shaft": "θ11", "crankshaft": "θ22", "output_disk": "θ44", "pin_shaft": "θ55"}


def test_7350_is_the_torsion_constant_of_steel_with_G_79_4_GPa(rig, chain):
    # φ [°/m] = 180/π · T L / (G J) per metre, J = π d⁴ / 32, d in mm → 7350 T / d⁴
    assert round(torsion_constant_deg_per_m(79.4e9)) == 7350
    assert torsion_constant_deg_per_m(79.4e9) == pytest.approx(180 / math.pi * 32 / (math.pi * 79.4e9) * 1e12)
    # G comes from each part's material: the input shaft is Q460 in the rig, G = E / (2 (1 + ν))
    q460 = rig.materials["Q460"]
    expected = q460.youngs_modulus_MPa * 1e6 / (2 * (1 + q460.poisson_ratio))
    assert chain.component("input_shaft").shear_modulus_Pa == pytest.approx(expected, rel=1e-14)
    assert chain.component("input_shaft").material == "Q460"


def test_input_shaft_stages_come_from_the_rig(chain):
    """The reference rig's five input-shaft segments are the paper's four-stage hollow shaft."""
    stages = chain.component("input_shaft").stages
    assert [(s.length_mm, s.outer_diameter_mm, s.inner_diameter_mm) for s in stages] == [
        (28.0, 18.0, 8.0), (14.0, 20.0, 8.0), (46.0, 18.0, 8.0), (32.0, 20.0, 8.0)]
    assert sum(s.length_mm for s in stages) == 120.0  # paper 000's L = 120 mm
    assert len(chain.component("crankshaft").stages) == 8
    assert len(chain.component("output_disk").stages) == 3


def _fem_twist_rad(length_m: float, outer_m: float, inner_m: float, torque_Nm: float, shear_modulus: float) -> float:
    """Twist of a shaft clamped at one end with an end torque, from the beam finite elements."""
    section = CircularSection(outer_m, inner_m)
    coordinates, beams = frames.polyline([[0, 0, 0], [length_m, 0, 0]], 3, section)
    beams = dataclasses.replace(beams, shear_modulus_Pa=np.full(3, shear_modulus))
    structure = frames.model(coordinates, beams, fixed_dofs=np.array(frames.node_dofs(0)))
    u = frames.solve(structure, frames.point_load(structure.n_dofs, 3, [0, 0, 0, torque_Nm, 0, 0]))
    return float(u[frames.dof(3, 3)])


@pytest.mark.parametrize("name", ["input_shaft", "crankshaft", "output_disk", "pin_shaft"])
def test_each_formula_against_an_independent_torsion_calculation(chain, name):
    """θ = transfer · Σ twist of each stage under F_k r_k, with r_k = tan β (x_k + a / cos β) + d_k / 2."""
    component = chain.component(name)
    reducer = chain.reducer
    transfer = {"input_shaft": 1 / 141, "crankshaft": 2 / 39, "output_disk": 1.0, "pin_shaft": 40 * 40 / 39}[name]
    assert (reducer.ratio_i16, reducer.cycloid_teeth_Z4, reducer.pin_teeth_Z5, reducer.pin_count) == (141, 39, 40, 40)
    forces = np.linspace(150.0, 900.0, len(component.stages))
    tilt = Coaxiality(beta_deg=0.5, offset_mm=0.003)  # a large tilt, so that the coaxiality terms matter
    beta = math.radians(tilt.beta_deg) if component.coaxiality != "none" else 0.0
    expected, start = 0.0, 0.0
    for stage, force in zip(component.stages, forces):
        middle = start + stage.length_mm / 2  # (l_k + l_{k−1}) / 2
        start += stage.length_mm
        arm_mm = math.tan(beta) * (middle + tilt.offset_mm / math.cos(beta)) + stage.outer_diameter_mm / 2
        expected += _fem_twist_rad(stage.length_mm * 1e-3, stage.outer_diameter_mm * 1e-3,
                                   stage.inner_diameter_mm * 1e-3, force * arm_mm * 1e-3, component.shear_modulus_Pa)
    result = contribution(component, forces, tilt)
    assert result.value_deg == pytest.approx(transfer * math.degrees(expected), rel=1e-9)
    if component.coaxiality == "none":  # internal parts: the paper ignores their tilt
        assert result.coaxiality_part_deg == 0.0
    else:
        assert result.coaxiality_part_deg > 1e-3 * result.baseline_deg


def test_printed_formulas_at_zero_tilt_with_our_units(chain):
    """At β = 0 and G = 79.4 GPa the model is the printed formulas with L_k in m, d in mm and "L" = 1000 mm/m."""
    def at_paper_G(name):
        return dataclasses.replace(chain.component(name), shear_modulus_Pa=79.4e9)

    rng = np.random.default_rng(5)
    i16, z4, z5 = 141, 39, 40
    for name in ("input_shaft", "output_disk"):
        c = at_paper_G(name)
        f = rng.uniform(100, 1000, len(c.stages))
        # θ = 7350 / (i16 L) Σ F_k L_k / (d_k⁴ (1 − d_kk⁴ / d_k⁴)) · (d_k / 2)   (θ44: no i16)
        printed = 7350 / ((i16 if name == "input_shaft" else 1) * 1000) * sum(
            fk * (s.length_mm * 1e-3) / (s.outer_diameter_mm**4 * (1 - s.inner_diameter_mm**4 / s.outer_diameter_mm**4))
            * s.outer_diameter_mm / 2 for fk, s in zip(f, c.stages))
        assert contribution(c, f).value_deg == pytest.approx(printed, rel=1e-4)
    c = at_paper_G("crankshaft")
    f = rng.uniform(100, 1000, 8)
    printed = 7350 / (z4 * 1000) * sum(fk * (s.length_mm * 1e-3) / s.outer_diameter_mm**3 for fk, s in zip(f, c.stages))
    assert contribution(c, f).value_deg == pytest.approx(printed, rel=1e-4)
    c, s = at_paper_G("pin_shaft"), at_paper_G("pin_shaft").stages[0]
    # printed θ55 = 20 Z5 F / (Z4 d³), times the constant and the length it omits
    printed = 20 * z5 * 50.0 / (z4 * s.outer_diameter_mm**3) * 7350 * (s.length_mm * 1e-3) / 1000
    assert contribution(c, [50.0]).value_deg == pytest.approx(printed, rel=1e-4)


def test_example_forces_reproduce_the_papers_contributions(chain):
    forces = read_stage_forces(EXAMPLE_FORCES, chain)
    assert [int(i) + 1 for i in np.flatnonzero(forces["crankshaft"])] == [2, 4, 6, 8]  # the stages the paper names
    result = evaluate_chain_error(chain, forces)
    for p in result.contributions:
        assert p.value_deg == pytest.approx(PAPER_CONTRIBUTIONS_DEG[p.component.name], rel=1e-5)
    assert result.total_deg == pytest.approx(PAPER_TOTAL_DEG, abs=1e-8)
    # a tilt of the sweep's size changes the total by a tiny amount, and only through θ11 and θ44
    tilted = evaluate_chain_error(chain, forces, Coaxiality(7.3e-5, 1.5e-4), Coaxiality(6.3e-5, 1.8e-4))
    changed = {p.component.name for p in tilted.contributions if p.coaxiality_part_deg != 0}
    assert changed == {"input_shaft", "output_disk"}
    assert 0 < abs(tilted.total_deg - result.total_deg) < 1e-6


def test_tilt_and_offset_validation():
    assert NO_TILT == Coaxiality(0.0, 0.0)
    for bad in ({"beta_deg": 90.0}, {"beta_deg": float("nan")}, {"offset_mm": float("inf")}):
        with pytest.raises(ValueError):
            Coaxiality(**bad)


@pytest.mark.parametrize(("text", "message"), [
    ("component,stage,force_N\ncrank,2,10\n", "line 2: unknown component 'crank'"),
    ("component,stage,force_N\ncrankshaft,9,10\n", "line 2: stage 9 of crankshaft does not exist"),
    ("# note\ncomponent,stage,force_N\npin_shaft,1,ten\n", "line 3: force_N: 'ten' is not a number"),
    ("component,stage,force_N\npin_shaft,1,1\npin_shaft,1,2\n", "line 3: stage 1 of pin_shaft is given twice"),
    ("component,force_N\npin_shaft,1\n", "missing column(s) stage"),
    ("component,stage,force_N\n", "no forces"),
])
def test_forces_file_errors_name_line_and_reason(tmp_path, chain, text, message):
    path = tmp_path / "forces.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ChainDataError) as error:
        read_stage_forces(path, chain)
    assert message in str(error.value) and str(path) in str(error.value)


def test_stage_data_errors(tmp_path, rig):
    text = (DATA / "rv20e_chain_stages.toml").read_text(encoding="utf-8")
    bad = tmp_path / "stages.toml"
    bad.write_text(text.replace('material = "GCr15"', 'material = "unobtainium"'), encoding="utf-8")
    with pytest.raises(ChainDataError, match="components.pin_shaft: material 'unobtainium'"):
        load_chain_model(rig, bad)
    bad.write_text(text.replace("ratio_i16 = 141", "ratio_i16 = -141"), encoding="utf-8")
    with pytest.raises(ChainDataError, match="reducer.ratio_i16"):
        load_chain_model(rig, bad)


def test_cli_chain_error(tmp_path):
    runner = CliRunner()
    result = runner.invoke(app, ["chain-error", "--forces", str(EXAMPLE_FORCES), "--tilt", "none", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "θ22 − θ11 − θ44 − θ55" in result.output
    document = json.loads((tmp_path / "chain_error.json").read_text(encoding="utf-8"))
    assert document["total_deg"] == pytest.approx(PAPER_TOTAL_DEG, abs=1e-8)
    assert {r["symbol"]: r["sign"] for r in document["contributions"]} == {"θ11": -1, "θ22": 1, "θ44": -1, "θ55": -1}
    # β and a from a sweep of the reference rig (beam model)
    result = runner.invoke(app, ["chain-error", "--forces", str(EXAMPLE_FORCES), "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    shafts = json.loads((tmp_path / "chain_error.json").read_text(encoding="utf-8"))["shafts"]
    assert shafts["input"]["beta_deg"] > 0 and shafts["output"]["offset_mm"] > 0
    # a given instead of the sweep's Y_max, under the name `export` uses and under the old name
    for option in ("--output-radial-mm", "--a-output-mm"):
        result = runner.invoke(app, ["chain-error", "--forces", str(EXAMPLE_FORCES), option, "0.003",
                                     "--out", str(tmp_path)])
        assert result.exit_code == 0, result.output
        shafts = json.loads((tmp_path / "chain_error.json").read_text(encoding="utf-8"))["shafts"]
        assert shafts["output"]["offset_mm"] == 0.003
    bad = tmp_path / "bad.csv"
    bad.write_text("component,stage,force_N\ncrankshaft,0,1\n", encoding="utf-8")
    result = runner.invoke(app, ["chain-error", "--forces", str(bad)])
    assert result.exit_code == 2
    assert "line 2: stage 0 of crankshaft does not exist" in result.output + getattr(result, "stderr", "")
    assert "Traceback" not in result.output
