"""Load cases: the paper's 20 pairs, grids, paired lists, files, and the errors a user can make."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from rvcoax.loadcases.cases import (
    LoadCase,
    LoadCaseError,
    grid_cases,
    paired_cases,
    paper_cases,
    paper_table,
    read_cases,
    torque_matrix,
)

REPO = Path(__file__).resolve().parents[2]

# T1, T2 of the published table (paper 000), in its order
PUBLISHED_PAIRS = [
    (1.43, 200), (1.35, 190), (1.29, 180), (1.21, 170), (1.14, 160), (1.07, 150), (1.00, 140), (0.93, 130),
    (0.86, 120), (0.79, 110), (0.71, 100), (0.64, 90), (0.57, 80), (0.50, 70), (0.43, 60), (0.35, 50),
    (0.28, 40), (0.21, 30), (0.14, 20), (0.07, 10),
]


# ----------------------------------------------------------------------------------------------
# the built-in cases


def test_paper_cases_are_the_published_pairs():
    cases = paper_cases()
    assert len(cases) == 20
    assert all(isinstance(c, LoadCase) for c in cases)
    assert [(c.input_torque_Nm, c.output_torque_Nm) for c in cases] == PUBLISHED_PAIRS
    assert len(set(cases)) == 20


def test_paper_cases_match_the_shared_reference_table():
    for candidate in (REPO / "shared" / "reference" / "coaxiality_table.csv",
                      REPO.parent / "shared" / "reference" / "coaxiality_table.csv"):
        if candidate.is_file():
            break
    else:
        pytest.skip("shared/reference/coaxiality_table.csv is not available")
    with candidate.open(newline="", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    assert [(float(r["T1_input_Nm"]), float(r["T2_output_Nm"])) for r in rows] == \
        [(c.input_torque_Nm, c.output_torque_Nm) for c in paper_cases()]
    table = paper_table()
    for row, published in zip(rows, table):
        assert published.y_input_mm == float(row["Y_input_mm"])
        assert published.y_output_mm == float(row["Y_output_mm"])
        assert published.beta_input_deg == float(row["beta_input_deg"])
        assert published.beta_output_deg == float(row["beta_output_deg"])


def test_paper_table_rows_follow_the_cases():
    table = paper_table()
    assert tuple(r.case for r in table) == paper_cases()
    # the published output Y grows with the torque (the table is in decreasing T2)
    y_out = np.array([r.y_output_mm for r in table])
    assert np.all(np.diff(y_out) < 0)
    # beta = arcsin(Y / L) with L = 160 mm (output) to the table's 3 significant digits
    for r in table:
        assert math.degrees(math.asin(r.y_output_mm / 160.0)) == pytest.approx(r.beta_output_deg, rel=6e-3)


def test_grid_cases_every_combination_in_order():
    cases = grid_cases([0.5, 1.0], [70, 140, 200])
    assert [(c.input_torque_Nm, c.output_torque_Nm) for c in cases] == [
        (0.5, 70), (0.5, 140), (0.5, 200), (1.0, 70), (1.0, 140), (1.0, 200)]
    assert all(isinstance(c.input_torque_Nm, float) for c in cases)


def test_paired_cases_pair_in_order():
    cases = paired_cases([0.5, 1.0], [70, 140])
    assert [(c.input_torque_Nm, c.output_torque_Nm) for c in cases] == [(0.5, 70.0), (1.0, 140.0)]


def test_torque_matrix_and_label():
    cases = paired_cases([0.5, -1.0], [70, 140])
    assert torque_matrix(cases).tolist() == [[0.5, 70.0], [-1.0, 140.0]]
    assert cases[0].label == "T1=0.5Nm_T2=70Nm"


# ----------------------------------------------------------------------------------------------
# files


def test_read_cases_csv_ignores_other_columns(tmp_path):
    path = tmp_path / "cases.csv"
    path.write_text("note,T2_output_Nm,T1_input_Nm\nlow,70,0.5\nhigh,140,1.0\n", encoding="utf-8")
    cases = read_cases(path)
    assert [(c.input_torque_Nm, c.output_torque_Nm) for c in cases] == [(0.5, 70.0), (1.0, 140.0)]


def test_read_cases_toml(tmp_path):
    path = tmp_path / "cases.toml"
    path.write_text("[[cases]]\nT1_input_Nm = 0.5\nT2_output_Nm = 70\n\n"
                    "[[cases]]\nT1_input_Nm = 1\nT2_output_Nm = 140.0\n", encoding="utf-8")
    cases = read_cases(path)
    assert [(c.input_torque_Nm, c.output_torque_Nm) for c in cases] == [(0.5, 70.0), (1.0, 140.0)]


def test_read_cases_toml_suffix_is_case_insensitive(tmp_path):
    path = tmp_path / "CASES.TOML"
    path.write_text("[[cases]]\nT1_input_Nm = 0.5\nT2_output_Nm = 70\n", encoding="utf-8")
    assert read_cases(path) == (LoadCase(0.5, 70.0),)


def test_paper_table_written_as_csv_reads_back(tmp_path):
    path = tmp_path / "paper.csv"
    with path.open("w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream)
        writer.writerow(["T1_input_Nm", "T2_output_Nm"])
        writer.writerows(PUBLISHED_PAIRS)
    assert read_cases(path) == paper_cases()


# ----------------------------------------------------------------------------------------------
# errors: each a LoadCaseError naming the source and the reason


def _error(path: Path) -> str:
    with pytest.raises(LoadCaseError) as caught:
        read_cases(path)
    message = str(caught.value)
    assert message.startswith(f"load cases {path}: "), message
    return message


CSV_ERRORS = {
    "missing torque column": ("T1_input_Nm,T2\n1,100\n", ["missing column(s) T2_output_Nm", "found: T1_input_Nm, T2"]),
    "both columns missing": ("a,b\n1,2\n", ["missing column(s) T1_input_Nm, T2_output_Nm"]),
    "torque with a unit": ("T1_input_Nm,T2_output_Nm\n1,100\n0.86,120 Nm\n",
                           ["line 3, T2_output_Nm", "'120 Nm' is not a number"]),
    "empty value": ("T1_input_Nm,T2_output_Nm\n,100\n", ["line 2, T1_input_Nm", "'' is not a number"]),
    "short row": ("T1_input_Nm,T2_output_Nm\n1,100\n0.5\n", ["line 3, T2_output_Nm", "value is missing"]),
    "duplicated case": ("T1_input_Nm,T2_output_Nm\n1,100\n0.5,70\n1.0,100.0\n",
                        ["case 3", "duplicated load case T1 = 1.0, T2 = 100.0"]),
    "empty file": ("", ["missing column(s) T1_input_Nm, T2_output_Nm", "found: none"]),
    "header only": ("T1_input_Nm,T2_output_Nm\n", ["no load cases"]),
    "NaN": ("T1_input_Nm,T2_output_Nm\n1,100\nnan,70\n", ["line 3, T1_input_Nm", "'nan' is not a finite number"]),
    "infinite": ("T1_input_Nm,T2_output_Nm\n1,inf\n", ["line 2, T2_output_Nm", "'inf' is not a finite number"]),
    "implausible torque": ("T1_input_Nm,T2_output_Nm\n1,2e7\n", ["case 1", "beyond any plausible rig torque"]),
}


TOML_ERRORS = {
    "missing torque key": ("[[cases]]\nT1_input_Nm = 1\n", ["cases[1]: missing key T2_output_Nm"]),
    "torque with a unit": ('[[cases]]\nT1_input_Nm = 1\nT2_output_Nm = "120 Nm"\n',
                           ["cases[1].T2_output_Nm", "'120 Nm' is not a number in N·m"]),
    "boolean": ("[[cases]]\nT1_input_Nm = true\nT2_output_Nm = 1\n", ["cases[1].T1_input_Nm", "True is not a number"]),
    "duplicated case": ("[[cases]]\nT1_input_Nm = 1\nT2_output_Nm = 100\n[[cases]]\nT1_input_Nm = 1.0\nT2_output_Nm = 100.0\n",
                        ["case 2", "duplicated load case"]),
    "empty file": ("", ["expected [[cases]] tables"]),
    "cases not tables": ("cases = [1, 2]\n", ["cases[1]", "is not a table"]),
    "cases as one table": ("[cases]\nT1_input_Nm = 1\nT2_output_Nm = 1\n", ["expected [[cases]] tables"]),
    "NaN": ("[[cases]]\nT1_input_Nm = nan\nT2_output_Nm = 1\n", ["case 1", "T1_input_Nm = nan is not a finite number"]),
    "syntax error": ("[[cases]\nT1_input_Nm = 1\n", ["TOML syntax error"]),
}


FILE_ERRORS = [("cases.csv", name, text, expected) for name, (text, expected) in CSV_ERRORS.items()]
FILE_ERRORS += [("cases.toml", name, text, expected) for name, (text, expected) in TOML_ERRORS.items()]


@pytest.mark.parametrize("filename, name, text, expected", FILE_ERRORS, ids=[f"{f}: {n}" for f, n, _, _ in FILE_ERRORS])
def test_file_errors(tmp_path, filename, name, text, expected):
    """Every bad load-case file names the source, the line/case/key and the reason."""
    path = tmp_path / filename
    path.write_text(text, encoding="utf-8")
    message = _error(path)
    assert str(path) in message
    for part in expected:
        assert part in message, f"{name}: {part!r} not in {message!r}"


def test_missing_file(tmp_path):
    assert "file not found" in _error(tmp_path / "none.csv")


def test_non_utf8_file(tmp_path):
    path = tmp_path / "cases.csv"
    path.write_bytes(b"T1_input_Nm,T2_output_Nm\n1,100 \xb5\n")
    assert "not UTF-8 text" in _error(path)


def test_directory(tmp_path):
    message = _error(tmp_path)
    assert "cannot be read" in message


def test_mismatched_list_lengths():
    with pytest.raises(LoadCaseError) as caught:
        paired_cases([0.5, 1.0, 1.5], [70, 140])
    # the one form of an input's problems (rvcoax.errors.problems_text): the source, then each problem
    assert str(caught.value) == "load cases command line: 1 problem(s):\n  - 3 T1 values but 2 T2 values"
    assert caught.value.source == "command line" and caught.value.problems == ["3 T1 values but 2 T2 values"]
    with pytest.raises(LoadCaseError, match=r"^load cases my list: 1 problem\(s\):\n  - 1 T1 values but 2 T2 values$"):
        paired_cases([0.5], [70, 140], source="my list")


def test_grid_and_paired_errors_name_their_source():
    with pytest.raises(LoadCaseError, match=r"^load cases grid: 1 problem\(s\):\n  - no load cases$"):
        grid_cases([], [70])
    with pytest.raises(LoadCaseError, match=r"^load cases grid: .*\n  - case 1: T2_output_Nm = nan is not a finite number$"):
        grid_cases([1.0], [math.nan])
    with pytest.raises(LoadCaseError, match=r"^load cases command line: .*\n  - case 2: duplicated load case"):
        paired_cases([1.0, 1.0], [70, 70])


def test_load_case_error_is_a_value_error():
    assert issubclass(LoadCaseError, ValueError)


def test_superpose_weights_each_unit_response():
    """u = u_rest + sign(T1) u_e1 + sign(T2) u_e2 + T1 u_T1 + T2 u_T2; from rest drops u_rest."""
    from rvcoax.geometry.model.loads import UNIT_LOADS, superpose

    unit = {name: np.eye(len(UNIT_LOADS))[i] for i, name in enumerate(UNIT_LOADS)}  # one slot per load
    u = superpose(unit, -0.5, 120.0, from_rest=False)
    expected = {"gravity": 1.0, "prestrain": 1.0, "force_table": 1.0, "engaged_T1": -1.0, "engaged_T2": 1.0,
                "T1": -0.5, "T2": 120.0, "gear_contact_T1": -1.0, "gear_contact_T2": 1.0}
    assert u.tolist() == [expected[name] for name in UNIT_LOADS]
    measured = superpose(unit, -0.5, 120.0, from_rest=True)
    assert measured.tolist() == [0.0, 0.0, 0.0, -1.0, 1.0, -0.5, 120.0, -1.0, 1.0]
    # below a gear stage's full-contact torque its constant mesh part scales with T / T_c
    clipped = dict(zip(UNIT_LOADS, superpose(unit, -0.5, 120.0, from_rest=False, contact_torques_Nm=(2.0, 100.0))))
    assert (clipped["gear_contact_T1"], clipped["gear_contact_T2"], clipped["engaged_T1"]) == (-0.25, 1.0, -1.0)
    assert superpose(unit, 0.0, 0.0, from_rest=True).tolist() == [0.0] * len(UNIT_LOADS)
