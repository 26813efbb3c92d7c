"""The golden comparison (tests/support/golden_files.py) stays strict on every golden column and key, and allows
columns and keys added later (issue 15's engineering quantities)."""

import json

import pytest
from golden_files import compare_result_file

GOLDEN_CSV = "T1_input_Nm,Y_input_mm,equilibrium_relative_error\n1.0,0.25,1e-15\n2.0,0.5,2e-15\n"


def _write(folder, name, text):
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def test_new_columns_after_the_golden_ones_are_allowed(tmp_path):
    golden = _write(tmp_path, "golden.csv", GOLDEN_CSV)
    produced = _write(tmp_path, "produced.csv", "T1_input_Nm,Y_input_mm,equilibrium_relative_error,tilt_input_urad\n"
                                                "1.0,0.25,3e-15,4.5\n2.0,0.5,1e-15,9.0\n")
    compare_result_file(golden, produced)


@pytest.mark.parametrize("text", [
    "T1_input_Nm,Y_input_mm,equilibrium_relative_error\n1.0,0.2500001,1e-15\n2.0,0.5,2e-15\n",  # a golden value
    "T1_input_Nm,tilt_input_urad,Y_input_mm,equilibrium_relative_error\n1.0,4.5,0.25,1e-15\n2.0,9,0.5,2e-15\n",
    "T1_input_Nm,equilibrium_relative_error\n1.0,1e-15\n2.0,2e-15\n",  # a golden column missing
])
def test_changed_moved_or_missing_golden_columns_fail(tmp_path, text):
    golden = _write(tmp_path, "golden.csv", GOLDEN_CSV)
    with pytest.raises(AssertionError):
        compare_result_file(golden, _write(tmp_path, "produced.csv", text))


def test_json_keys_may_be_added_but_golden_ones_compare_strictly(tmp_path):
    document = {"rig": {"name": "r", "sha256": "a" * 64}, "cases": [{"Y_max_mm": 0.25, "label": "x"}]}
    golden = _write(tmp_path, "golden.json", json.dumps(document))
    added = {"rig": {"name": "r", "sha256": "b" * 64}, "units": {"_um": "µm"},
             "cases": [{"Y_max_mm": 0.25, "label": "x", "engineering": {"tilt_urad": 1.0}}]}
    compare_result_file(golden, _write(tmp_path, "added.json", json.dumps(added)))  # sha256: provenance only
    for broken in ({**added, "cases": [{"Y_max_mm": 0.26, "label": "x"}]},
                   {**added, "cases": [{"Y_max_mm": 0.25, "label": "y"}]},
                   {**added, "rig": {"name": "r", "sha256": "not a hash"}}):
        with pytest.raises(AssertionError):
            compare_result_file(golden, _write(tmp_path, "broken.json", json.dumps(broken)))


def test_the_unit_load_names_may_grow_at_their_end_only(tmp_path):
    names = ["gravity", "prestrain", "T1", "T2"]
    golden = _write(tmp_path, "golden.json", json.dumps({"model": {"unit_loads": names}, "cases": [1, 2]}))
    grown = {"model": {"unit_loads": [*names, "gear_contact_T1"]}, "cases": [1, 2]}
    compare_result_file(golden, _write(tmp_path, "grown.json", json.dumps(grown)))
    for broken in ({"model": {"unit_loads": ["gear_contact_T1", *names]}, "cases": [1, 2]},
                   {"model": {"unit_loads": names[:3]}, "cases": [1, 2]},
                   {"model": {"unit_loads": names}, "cases": [1, 2, 3]}):  # other lists still may not grow
        with pytest.raises(AssertionError):
            compare_result_file(golden, _write(tmp_path, "broken.json", json.dumps(broken)))
