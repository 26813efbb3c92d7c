"""The discrepancy workflow on data from the all-solid model (issue 28, item 7).

The files in ``tests/results/studies/data/blind_solid`` were written by ``benchmarks/blind_solid.py``: rvcoax's
all-solid model of the reference rig (every part quadratic tetrahedra, 8 mm on the shafts; self-weight off), hidden
effects applied to the rig file, 7 of paper 000's cases, 6 stations per shaft; ``manifest.json`` holds each file's
truth. The workflow identifies with the beam model (Timoshenko shafts), a discretisation that did not make the data.
The scored benchmark over 132 such sets is ``benchmarks/bench_discrepancy_blind.py --source solid``.
"""

from __future__ import annotations

import json
from pathlib import Path

from discrepancy_data import assert_honest_answer, discrepancy_rig, relative_gap_to_the_model

import rvcoax
from rvcoax.geometry.schema import Rig
from rvcoax.results.studies.discrepancy.workflow import DiscrepancySettings

FOLDER = Path(__file__).parent / "data" / "blind_solid"
MANIFEST = json.loads((FOLDER / "manifest.json").read_text())
SETS = {s["id"]: s for s in MANIFEST["sets"]}


def identification_rig(datum: str) -> Rig:
    data = discrepancy_rig().model_dump(by_alias=True)
    data["paths"]["measured_from"] = datum
    data["beam"]["shear_deformation"] = True
    return Rig.model_validate(data)


def test_all_solid_files_differ_from_the_beam_model_by_a_model_form_amount():
    """Provenance and schema of every file; the file without a hidden effect is neither the beam model (more than
    its 1 % noise off on the input shaft) nor far from it."""
    assert MANIFEST["generator"] == "benchmarks/blind_solid.py" and "all-solid" in MANIFEST["model"]
    for name, entry in SETS.items():
        data = rvcoax.read_measured(FOLDER / entry["file"])
        assert data.schema == entry["schema"] and len(data.cases) == 7, name
    entry = SETS["none"]
    data = rvcoax.read_measured(FOLDER / entry["file"])
    relative = relative_gap_to_the_model(identification_rig(entry["datum"]), data)
    assert 0.01 < relative["input"] < 0.05 and relative["output"] < 0.05, relative


def test_workflow_on_an_all_solid_file_answers_honestly():
    """A hidden torque reaction at the output bearing block (30 % of the signal, 1 % noise, paths): the answer
    covers the truth with a verdict that claims no more than the data carry, and names nothing else with
    confidence."""
    entry = SETS["torque_reaction"]
    rig = identification_rig(entry["datum"])
    result = rvcoax.run_discrepancy(rig, rvcoax.read_measured(FOLDER / entry["file"]), DiscrepancySettings())
    assert_honest_answer(result, set(entry["truth"]))
