"""CSV injection: text cells that a spreadsheet would run as a formula are escaped, numbers never, and our
readers give the text back (OWASP, "CSV Injection": prefix such cells with a single quote)."""

from __future__ import annotations

import csv

import pytest
from rigdata import reference_data

from rvcoax.geometry.rigfile import parse_rig
from rvcoax.loadcases.cases import paper_cases
from rvcoax.results.export.dynamics import dynamics_export, read_csv_table, write_dynamics_csv
from rvcoax.results.io.writers import csv_cell, read_csv_cell, write_csv_atomic
from rvcoax.results.sweep import run_sweep

FORMULAS = ["=1+2", "+SUM(A1:A3)", "-A1", "@SUM(A1)", "\tx", "\rx", "=cmd|' /C calc'!A0"]


@pytest.mark.parametrize("text", FORMULAS)
def test_text_a_spreadsheet_would_run_gets_a_quote_in_front(text):
    assert csv_cell(text) == "'" + text
    assert read_csv_cell(csv_cell(text)) == text


@pytest.mark.parametrize("value, written", [
    (-0.5, "-0.5"), (-3, "-3"), (float("-inf"), "-inf"), (-1.23456789012e-7, "-1.23456789e-07"),
    ("-0.5", "-0.5"), ("-1e-3", "-1e-3"), ("+2", "+2"), ("-", "-"), ("input_B1", "input_B1"), ("", ""),
])
def test_numbers_and_harmless_text_are_written_as_they_are(value, written):
    assert csv_cell(value) == written


def test_text_starting_with_a_quote_round_trips():
    for text in ("'=x", "'", "''a", "it's"):
        assert read_csv_cell(csv_cell(text)) == text
    assert csv_cell("'=x") == "''=x" and csv_cell("it's") == "it's"


def test_a_written_file_keeps_numbers_and_escapes_names(tmp_path):
    rows = [{"part": "-A1", "label": "=HYPERLINK(\"x\")", "uy_mm": -0.001, "n": -2},
            {"part": "@x", "label": "plain", "uy_mm": 0.5, "n": 3}]
    path = write_csv_atomic(tmp_path / "t.csv", rows)
    with open(path, encoding="utf-8", newline="") as stream:
        raw = list(csv.reader(stream))
    assert raw[1] == ["'-A1", "'=HYPERLINK(\"x\")", "-0.001", "-2"]
    assert raw[2] == ["'@x", "plain", "0.5", "3"]
    assert read_csv_table(path) == rows


def test_a_bearing_named_like_a_formula_is_escaped_in_the_dynamics_export(tmp_path):
    data = reference_data()
    data["bearings"][0]["name"] = "-A1"  # a name the rig file accepts (letters, digits, _ . -), a formula in Excel
    sweep = run_sweep(parse_rig(data, "rig.toml"), paper_cases()[:1])
    paths = {p.name: p for p in write_dynamics_csv(dynamics_export(sweep), tmp_path)}
    text = paths["dynamics_bearings.csv"].read_text(encoding="utf-8")
    assert ",'-A1," in text and ",-A1," not in text
    assert read_csv_table(paths["dynamics_bearings.csv"])[0]["bearing"] == "-A1"
    assert any(v < 0 for row in read_csv_table(paths["dynamics_shafts.csv"]) for v in row.values()
               if isinstance(v, float))  # negative numbers are still numbers
