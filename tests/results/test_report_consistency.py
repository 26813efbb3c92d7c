"""Issue 24: every number of the report is the one the result files hold, under one name, from one case.

For each rig (the reference rig, the RV-40E example, the ball-bearing variant, a rig with a radial
clearance, and the reference rig with its input bearing block as a condensed block, pedestal and wall
bracket), ``rvcoax sweep`` and ``rvcoax report`` run through the real CLI on the same cases; every table
of report.html computed from the sweep is then recomputed from sweep.json by the independent path of
tests/report_check.py (its own worst-case search, sums and labels) and compared cell by cell.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest
import tomlkit
from report_check import check_report_against_sweep, signature
from typer.testing import CliRunner

from rvcoax.geometry.rigfile import reference_rig_text
from rvcoax.geometry.variants import BEARING_BLOCKS, BEARING_PEDESTALS
from rvcoax.results.cli.app import app

CASES = ("--t1", "0.07,0.3,0.7,1.43", "--t2", "10,40,100,200")
BRACKET = {"name": "input_block", "part": "input_bearing_block", "material": "HT200", "shape": "bracket",
           "x_mm": [248.0, 320.0], "width_mm": 90.0, "top_above_axis_mm": 45.0, "seat_below_axis_mm": 45.0,
           "bore_diameter_mm": 47.0, "wall_distance_mm": 160.0, "arm_length_mm": 72.0, "arm_height_mm": 60.0,
           "plate_length_mm": 120.0, "plate_height_mm": 140.0, "plate_thickness_mm": 15.0, "foot_pad_mm": 30.0,
           "attachments_x_mm": [255.0, 315.0], "attachment_width_mm": 14.0, "feet": "clamped"}
HOUSINGS = {"block": BEARING_BLOCKS[0], "pedestal": BEARING_PEDESTALS[0], "bracket": BRACKET}


def invoke(*args: str):
    result = CliRunner().invoke(app, list(args))
    assert result.exit_code == 0, (result.output, result.exception)
    return result


def with_housing(shape: str) -> str:
    """The reference rig with its input block's mount replaced by a condensed ``shape`` (coarse 24 mm mesh)."""
    document = tomlkit.parse(reference_rig_text())
    mounts = document["mounts"]
    keep = [m for m in mounts if m["name"] != "input_block_base"]
    document["mounts"] = tomlkit.aot()
    for m in keep:
        document["mounts"].append(m)
    entry = {**HOUSINGS[shape], "mesh_size_mm": 24.0}
    housings = tomlkit.aot()
    housings.append(tomlkit.item(entry))
    document["housings"] = housings
    return tomlkit.dumps(document)


def with_clearance() -> str:
    document = tomlkit.parse(reference_rig_text())
    for bearing in document["bearings"]:
        if bearing["name"] == "input_B1":
            bearing["radial_clearance_um"] = 8.0
    return tomlkit.dumps(document)


def rig_text(kind: str) -> str | None:
    if kind == "reference":
        return None
    if kind == "example":
        return invoke("rig", "example").stdout
    if kind == "ball":
        return invoke("rig", "reference", "--variant", "ball_bearings").stdout
    if kind == "clearance":
        return with_clearance()
    return with_housing(kind)


def run(kind: str, folder: Path, *extra: str) -> tuple[str, dict, Path | None]:
    text = rig_text(kind)
    rig = []
    path = None
    if text is not None:
        path = folder / f"{kind}.toml"
        path.write_text(text, encoding="utf-8")
        rig = ["--rig", str(path)]
    cases = [] if kind == "example" else list(CASES)
    out = folder / "out"
    invoke("sweep", *rig, *cases, "--out", str(out))
    decides = [] if kind in ("reference", "example") else ["--no-decides"]  # (its own test below; seconds each)
    invoke("report", *rig, *cases, "--out", str(out), "--no-deformed", *decides, *extra)
    return ((out / "report.html").read_text(encoding="utf-8"),
            json.loads((out / "sweep.json").read_text(encoding="utf-8")), path)


@pytest.mark.parametrize("kind", ["reference", "example", "ball", "clearance", "block", "pedestal", "bracket"])
def test_every_report_table_is_the_sweep_json_value_by_value(kind, tmp_path):
    html_text, document, path = run(kind, tmp_path)
    summary = check_report_against_sweep(html_text, document)
    counts = summary["counts"]
    assert counts["shafts"] > 0 and counts["reactions"] > 0 and counts["couplings"] > 0 and counts["bearings"] > 0
    # signed: rig file, its SHA-256, version, date
    sign = signature(html_text)
    text = path.read_bytes().decode("utf-8") if path is not None else reference_rig_text()
    assert hashlib.sha256(text.encode("utf-8")).hexdigest() in sign
    assert (str(path) if path is not None else "reference") in sign and "rvcoax:" in sign and "UTC" in sign
    assert "size: A4" in html_text
    tables = summary["tables"]
    _, rows = tables.find("[[mounts]]")
    assert rows and all(r["provenance"] for r in rows)
    if kind in ("reference", "example"):
        _, rows = tables.find("[[torque_lateral_loads]]")
        imbalance = [r for r in rows if r["key"] == "imbalance"]
        assert imbalance and all("[A]" in r["provenance"] for r in imbalance)
        _, rows = tables.find("[[joints]]")
        assert any(r["key"] == "rotational_stiffness_Nm_per_rad" for r in rows)  # the reducer's main bearings
        _, rows = tables.find("What decides Y")
        assert len(rows) >= 5 and rows[0]["rank"] == "1"
    if kind in HOUSINGS:
        _check_seat_table(tables, path)
        # the housing's reaction is in the table, and the reactions carry the rig's weight and applied loads
        assert "housing" in summary["reaction_kinds"]
        case = document["cases"][-1]["engineering"]
        housing = next(r for r in case["reactions"] if r["kind"] == "housing")
        assert housing["name"] == "input_block" and housing["force_N"][1] > 1.0


def _check_seat_table(tables, path: Path) -> None:
    """The report's seat stiffness against K_c solved here with loads on the seats (not its inverse): held is
    K_ii, alone 1/u_i for a unit load at seat i, together 1/u_i for unit loads at both seats."""
    import numpy as np

    from rvcoax.geometry.model import housing_condensation
    from rvcoax.geometry.rigfile import load_rig

    rig = load_rig(path)
    housing = rig.housings[0]
    matrix = housing.stiffness_factor * housing_condensation(rig, housing, compute=False).matrix
    _, rows = tables.find("Housings condensed from solid models")
    assert len(rows) == 4
    for row in rows:
        seat = housing.attachments_x_mm.index(float(row["seat x [mm]"]))
        component = 1 if row["direction"].startswith("vertical") else 2
        i = 6 * seat + component
        one, both = np.zeros(12), np.zeros(12)
        one[i] = 1.0
        both[[component, 6 + component]] = 1.0
        report_check_same = float(row["held: diagonal of K_c [N/µm]"])
        assert report_check_same == pytest.approx(matrix[i, i] * 1e-6, rel=6e-4)
        assert float(row["this seat alone [N/µm]"]) == pytest.approx(1e-6 / np.linalg.solve(matrix, one)[i], rel=6e-4)
        assert float(row["both seats pushed together [N/µm]"]) == pytest.approx(
            1e-6 / np.linalg.solve(matrix, both)[i], rel=6e-4)
        assert float(row["held: diagonal of K_c [N/µm]"]) >= float(row["this seat alone [N/µm]"])


@pytest.mark.parametrize("shape", list(HOUSINGS))
def test_housing_reactions_sum_to_the_weight_through_the_cli(shape, tmp_path, monkeypatch):
    """rvcoax sweep on the reference rig with each housing shape in place of the input block's mount: the console
    and sweep.csv list the housing's reaction, and in every case the support forces (mounts and the housing)
    sum to the weight of the rig as modelled (its parts and coupling hubs, Σ m g) plus the applied forces,
    which the reference rig's force table keeps self-equilibrated (zero resultant)."""
    from rvcoax.geometry.model.beam import build_rig_model
    from rvcoax.geometry.rigfile import load_rig

    rig = tmp_path / "rig.toml"
    rig.write_text(with_housing(shape), encoding="utf-8")
    out = tmp_path / "out"
    monkeypatch.setenv("RVCOAX_CACHE_DIR", str(tmp_path / "cache"))  # nothing condensed yet
    shown = " ".join(invoke("rig", "show", "--rig", str(rig)).stdout.split())
    # the first condensation says what it does and what it found; then the seat stiffness in every load pattern
    assert "condensed housing 'input_block':" in shown and "all pushed together (softest seat): vertical (y)" in shown
    assert "Condensed housings: stiffness at the bearing seats" in shown and "both seats pushed together" in shown
    result = invoke("sweep", "--rig", str(rig), *CASES, "--out", str(out))
    assert "input_block" in result.stdout and "housing" in result.stdout
    header = (out / "sweep.csv").read_text(encoding="utf-8").splitlines()[0].split(",")
    assert "reaction_input_block_Fy_N" in header and "reaction_input_block_Mx_Nm" in header
    document = json.loads((out / "sweep.json").read_text(encoding="utf-8"))
    model = load_rig(rig)
    weight = sum(build_rig_model(model).part_mass_kg.values()) * model.gravity.acceleration_m_per_s2
    for case in document["cases"]:
        engineering = case["engineering"]
        vertical = sum(r["force_N"][1] for r in engineering["reactions"])
        assert vertical == pytest.approx(weight, rel=1e-9)
        assert engineering["applied_force_N"][1] == pytest.approx(-weight, rel=1e-9)
        housing = next(r for r in engineering["reactions"] if r["kind"] == "housing")
        assert 5.0 < housing["force_N"][1] < 0.5 * weight  # it carries its share of the input side


def test_what_decides_y_ranks_the_reducers_lateral_load_first():
    """The tutorial's finding, recomputed for the reference rig: the crankshafts' load-sharing imbalance decides the
    output shaft's Y (doubling it roughly doubles Y), the sun gear's the input shaft's; the reducer's main-bearing
    (flange) stiffness comes next for the output shaft; couplings hardly matter."""
    from rvcoax.geometry.rigfile import load_rig
    from rvcoax.loadcases.cases import LoadCase
    from rvcoax.results.reports.report_tables import assumed_inputs
    from rvcoax.results.studies.decides import what_decides_y

    rig = load_rig()
    decides = what_decides_y(rig, assumed_inputs(rig, reference_rig_text()), LoadCase(1.43, 200.0))
    order = [r.address for r in decides.ranked]
    first = decides.ranked[0]
    assert first.address == "torque_lateral_loads.crankshaft_load_sharing.imbalance"
    assert 0.8 < first.y_change_um["output"][1] / decides.y_um["output"] < 1.2  # ×2: Y nearly doubles
    assert first.y_change_um["output"][0] == pytest.approx(-0.5 * first.y_change_um["output"][1], rel=0.05)
    sun = next(r for r in decides.ranked if r.address == "torque_lateral_loads.sun_gear_load_sharing.imbalance")
    assert 0.8 < sun.y_change_um["input"][1] / decides.y_um["input"] < 1.2
    assert order.index("joints.reducer_output_flange.translational_stiffness_N_per_um") < 6
    coupling = max(r.largest_y_change_um for r in decides.ranked if r.section == "couplings")
    assert coupling < 0.01 * first.largest_y_change_um
    # the input shaft does not feel the output side's load sharing at all: exactly 0, not rounding shown as data
    assert first.y_change_um["input"] == (0.0, 0.0) and first.tilt_change_urad["input"] == (0.0, 0.0)
    from rvcoax.results.studies.decides import _change

    assert _change(0.29 + 2e-15, 0.29) == 0.0 and _change(0.2916, 0.29) == pytest.approx(0.0016)


def test_rig_show_prints_the_warnings_a_solve_prints(tmp_path):
    """A bearing typed in N/mm instead of N/µm: the solve warns, and so does rig show (without solving)."""
    document = tomlkit.parse(reference_rig_text())
    for bearing in document["bearings"]:
        if bearing["name"] == "input_B1":
            bearing["radial_stiffness_N_per_um"] = 50000.0
    rig = tmp_path / "slip.toml"
    rig.write_text(tomlkit.dumps(document), encoding="utf-8")
    shown = CliRunner().invoke(app, ["rig", "show", "--rig", str(rig)])
    assert shown.exit_code == 0, shown.output
    assert "warning:" in shown.output and "input_B1" in shown.output and "radial_stiffness_N_per_um" in shown.output
