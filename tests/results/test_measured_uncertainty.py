"""Issue 24 item 3: user data are judged by the user's measurement uncertainty and labelled as theirs.

``rvcoax check --measured`` takes the uncertainty from the options or the file's ``#`` lines (absolute µm and
relative %), prints it and judges with it; the labels (console, check_verdict.json, the picture's legend)
are the file's; check.csv names the user's values ``measured_*``; the tables use µm and µrad; a ``#``
comment line anywhere in the file is accepted.
"""

from __future__ import annotations

import csv
import json

import pytest
from typer.testing import CliRunner

from rvcoax.results.cli.app import app
from rvcoax.results.studies.check import measurement_tolerance
from rvcoax.results.studies.discrepancy.measured import MeasuredDataError, parse_measured


def _invoke(*args: str):
    return CliRunner().invoke(app, list(args))


@pytest.fixture(scope="module")
def example(tmp_path_factory):
    """The example rig, and its own Y as 'measured' data, printed to 3 digits: exact in the two rows the check
    fits (the smallest and the largest T2), ±3 % in the rows between."""
    folder = tmp_path_factory.mktemp("measured")
    rig = folder / "example.toml"
    rig.write_text(_invoke("rig", "example").stdout, encoding="utf-8")
    result = _invoke("sweep", "--rig", str(rig), "--out", str(folder / "sweep"))
    assert result.exit_code == 0, result.output
    with (folder / "sweep" / "sweep.csv").open(newline="", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    lines = ["T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm"]
    for i, r in enumerate(rows):
        f = 1.0 if i in (0, len(rows) - 1) else 1.03 if i % 2 else 0.97
        lines.append(f"{r['T1_input_Nm']},{r['T2_output_Nm']},{float(r['Y_input_mm']) * f:.3g},"
                     f"{float(r['Y_output_mm']) * (2 - f):.3g}")
        if i == 1:
            lines.append("# a remark between two rows, with a \"quote\" and a comma, ignored")
    return rig, folder, lines


def _write(folder, name: str, header: list[str], lines: list[str]):
    path = folder / name
    path.write_text("\n".join(header + lines) + "\n", encoding="utf-8")
    return path


def test_the_files_uncertainty_and_label_are_used_and_shown(example):
    rig, folder, lines = example
    data = _write(folder, "gauges.csv", ["# bench 2", '# label = "dial gauges, bench 2"', "# uncertainty_um = 0.002",
                                         "# uncertainty_percent = 5"], lines)
    out = folder / "check_file"
    result = _invoke("check", "--rig", str(rig), "--measured", str(data), "--out", str(out))
    text = " ".join(result.output.split())
    assert result.exit_code == 0, result.output  # ±3 % data within ±5 %
    assert "dial gauges, bench 2 vs rvcoax" in text and "published" not in text and "paper 000 vs" not in text
    assert "Judged with: measurement uncertainty ±0.002 µm (from the file) or ±5 % of each value (from the file)" in text
    assert "β table µrad" in text
    verdict = json.loads((out / "check_verdict.json").read_text(encoding="utf-8"))
    assert verdict["compared_with"] == "dial gauges, bench 2" and "±5 %" in verdict["tolerance"]
    with (out / "check.csv").open(newline="", encoding="utf-8") as stream:
        header = next(csv.reader(stream))
    assert "measured_Y_input_mm" in header and not any(c.startswith("published_") for c in header)


def test_a_tighter_uncertainty_on_the_command_line_judges_the_same_data_outside(example):
    rig, folder, lines = example
    data = _write(folder, "gauges_tight.csv", ["# uncertainty_percent = 5"], lines)
    result = _invoke("check", "--rig", str(rig), "--measured", str(data), "--uncertainty-percent", "1",
                     "--uncertainty-um", "0.001")
    text = " ".join(result.output.split())
    assert result.exit_code == 1, result.output  # the ±3 % rows are outside ±1 %
    assert "±0.001 µm (from the command line) or ±1 % of each value (from the command line)" in text
    assert "VERDICT: outside tolerance" in text


def test_without_an_uncertainty_the_assumption_is_said():
    data = parse_measured("T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm\n1,100,0.00006,0.000123\n", "m.csv")
    tolerance = measurement_tolerance(data)
    assert tolerance.description.startswith("no measurement uncertainty given")
    assert "input 0.01 µm" in tolerance.description  # the resolution the file prints: 0.00006 mm → 1e-5 mm
    # the printed resolution is the floor: a 1 nm disagreement at 0.06 µm is not judged against 2 % of it
    assert tolerance.limit("Y_input_mm", 6e-5, 120.0) == pytest.approx(1e-5)
    given = measurement_tolerance(data, uncertainty_um=0.5)
    assert given.limit("Y_output_mm", 1.23e-4, 160.0) == pytest.approx(5e-4)


def test_comment_lines_and_bad_metadata(tmp_path):
    data = parse_measured("# taken on bench 2\n# label = 'gauges'\nT1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm\n"
                          "# first row next\n1,100,0.0001,0.0002\n", "m.csv")
    assert data.n == 2 and data.name == "gauges" and data.line.tolist() == [5, 5]
    assert parse_measured("T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm\n1,100,1e-4,2e-4\n", "m.csv").name \
        == "measured (m.csv)"
    with pytest.raises(MeasuredDataError, match=r"m\.csv[\s\S]*line 1, # uncertainty_um: .* must lie in 0 … 10000"):
        parse_measured("# uncertainty_um = -3\nT1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm\n1,100,1e-4,2e-4\n",
                       "m.csv")
    with pytest.raises(MeasuredDataError, match=r"line 2, # uncertainty_percent"):
        parse_measured("T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm\n# uncertainty_percent = five\n"
                       "1,100,1e-4,2e-4\n", "m.csv")
    with pytest.raises(MeasuredDataError, match="line 3: unknown column"):
        parse_measured("# one\n\nT1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm,extra\n", "m.csv")


def test_uncertainty_options_need_measured_data():
    result = _invoke("check", "--uncertainty-um", "0.5")
    assert result.exit_code == 2 and "describe --measured data" in " ".join(result.output.split())
