"""One input-file toolkit (geometry/validation.py, errors.py): every TOML input of rvcoax has a strict schema,
is read by the one helper and says what is wrong in the one form, naming the file and every key."""

import pytest

import rvcoax
from rvcoax.errors import InputFileProblems, RvcoaxError, problems_text
from rvcoax.geometry.rigfile import RigFileError, parse_rig_text, reference_rig_text
from rvcoax.geometry.schema import Rig
from rvcoax.geometry.validation import StrictModel, key_path
from rvcoax.results.studies.chain_error import ChainDataError, _StageFile, load_chain_model
from rvcoax.results.studies.discrepancy.measured import MeasuredDataError, parse_measured
from rvcoax.results.studies.doe.rig_study import Study, StudyError, load_study
from rvcoax.results.studies.tolerances import ToleranceFileError, _File, parse_tolerances

REFERENCE = rvcoax.load_rig()


def _rig(text, path):
    return parse_rig_text(text, str(path))


def _tolerances(text, path):
    return parse_tolerances(text, str(path), REFERENCE)


def _stages(text, path):
    path.write_text(text, encoding="utf-8")
    return load_chain_model(REFERENCE, path)


def _study(text, path):
    path.write_text(text, encoding="utf-8")
    return load_study(path)


# (what the message calls the file, its reader, its error, a valid start to add a misspelled key to)
READERS = {
    "rig file": (_rig, RigFileError, reference_rig_text()),
    "tolerance file": (_tolerances, ToleranceFileError,
                       "schema_version = 1\n[study]\nname = 's'\n[[parameters]]\n"
                       "address = 'bearings.input_B1.radial_stiffness_N_per_um'\ndistribution = 'normal'\n"
                       "mean_N_per_um = 100.0\nstd_N_per_um = 1.0\n"),
    "stage data": (_stages, ChainDataError, None),
    "study file": (_study, StudyError, None),
}


def test_every_input_schema_is_strict():
    for schema in (Rig, _File, _StageFile, Study):
        assert issubclass(schema, StrictModel), schema
        assert schema.model_config["extra"] == "forbid" and schema.model_config["frozen"]


def test_one_error_base_found_where_it_always_was():
    from rvcoax.fem import RvcoaxError as in_fem
    from rvcoax.fem.errors import RvcoaxError as in_fem_errors

    assert rvcoax.RvcoaxError is RvcoaxError is in_fem is in_fem_errors
    for error in (RigFileError, ToleranceFileError, MeasuredDataError, ChainDataError, StudyError):
        assert issubclass(error, RvcoaxError) and issubclass(error, ValueError)


@pytest.mark.parametrize("what", READERS)
def test_a_file_that_is_not_toml_names_the_file_and_the_line(what, tmp_path):
    read, error, _ = READERS[what]
    path = tmp_path / "input.toml"
    with pytest.raises(error) as caught:
        read("[study\nname = 1\n", path)
    message = str(caught.value)
    assert message.startswith(f"{what} {path}: 1 problem(s):\n  - TOML syntax error: ")
    assert "line 1" in message


@pytest.mark.parametrize("what", ["rig file", "tolerance file"])
def test_a_misspelled_key_is_named_with_its_entry(what, tmp_path):
    read, error, valid = READERS[what]
    path = tmp_path / "input.toml"
    read(valid, path)  # the start is valid: what follows fails only for the key added
    with pytest.raises(error) as caught:
        read(valid + "colour = 'red'\n", path)
    message = str(caught.value)
    assert message.startswith(f"{what} {path}: 1 problem(s):\n  - ")
    assert "colour: unknown key (misspelled? " in message
    assert caught.value.problems == message.split("\n  - ")[1:]


def test_every_reader_lists_each_problem_with_its_key(tmp_path):
    with pytest.raises(ChainDataError) as chain:
        _stages("schema_version = 1\n[reducer]\nname = 'x'\nratio_i16 = -1\n", tmp_path / "c.toml")
    assert str(chain.value).startswith(f"stage data {tmp_path / 'c.toml'}: ")
    assert "\n  - reducer.ratio_i16: Input should be greater than 0 (got -1)" in str(chain.value)
    with pytest.raises(StudyError) as study:
        _study("schema_version = 1\n[study]\nname = 'x'\narray = 'L7'\n", tmp_path / "s.toml")
    assert "\n  - study.array: Input should be 'L9', 'L18', 'L27' or 'L81' (got 'L7')" in str(study.value)
    with pytest.raises(MeasuredDataError) as measured:
        parse_measured("T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm\n1,140,12 mm,0.1\n", "m.csv")
    assert str(measured.value).startswith("measured data m.csv: 1 problem(s):\n  - line 2, column Y_input_mm: ")


def test_the_form_of_the_message():
    assert problems_text("rig file", "a.toml", ["x: bad", "y: worse"]) == "rig file a.toml: 2 problem(s):\n  - x: bad\n  - y: worse"

    class Example(InputFileProblems):
        what = "example file"

    error = Example("e.toml", ["k: no"])
    assert (str(error), error.where, error.problems) == ("example file e.toml: 1 problem(s):\n  - k: no", "e.toml", ["k: no"])


def test_a_list_entry_is_named_by_its_name_label_or_address():
    data = {"parts": [{"name": "shaft"}], "limits": [{"label": "L"}], "parameters": [{"address": "a.b"}], "cases": [{}]}
    assert key_path(("parts", 0, "x_mm"), data) == "parts[0] ('shaft').x_mm"
    assert key_path(("limits", 0), data) == "limits[0] ('L')"
    assert key_path(("parameters", 0, "mean"), data) == "parameters[0] ('a.b').mean"
    assert key_path(("cases", 0, "T1_input_Nm"), data) == "cases[0].T1_input_Nm"
    assert key_path((), data) == "(top level)"
