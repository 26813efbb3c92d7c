"""The discrepancy workflow on data from a discretisation it never uses: CalculiX *solid* measured shafts.

The files in ``tests/results/studies/data/calculix_solid`` were written by ``benchmarks/calculix_solid.py`` (which
needs ``ccx``; these tests do not): the reference rig's two measured shafts as C3D10 tetrahedra in CalculiX, their
bearings, couplings and the reducer joint as springs on points tied to the attachment's face as the rig file says
(distributing ``*EQUATION`` ties, RBE3-like), the rest of the line CalculiX beams and springs; Y is the area-weighted
mean u_y
of each station's section. Self-weight off, Y from the rig aligned at rest, 7 of paper 000's cases, 6 stations per
shaft; ``manifest.json`` holds each file's truth. The workflow identifies with the beam model (Timoshenko shafts).
"""

from __future__ import annotations

import json
from pathlib import Path

from discrepancy_data import assert_honest_answer, identification_rig, relative_gap_to_the_model

import rvcoax
from rvcoax.results.studies.discrepancy.workflow import DiscrepancySettings

FOLDER = Path(__file__).parent / "data" / "calculix_solid"
MANIFEST = json.loads((FOLDER / "manifest.json").read_text())
SETS = {s["id"]: s for s in MANIFEST["sets"]}


def test_solid_files_come_from_calculix_solids_and_differ_from_the_beam_model_by_a_model_form_amount():
    """Provenance, schema and a model-form gap: the file without a hidden effect is neither the beam model (more
    than its 1 % noise off) nor far from it."""
    assert MANIFEST["generator"] == "benchmarks/calculix_solid.py" and "C3D10" in MANIFEST["model"]
    for name, entry in SETS.items():
        data = rvcoax.read_measured(FOLDER / entry["file"])
        assert data.schema == entry["schema"] and len(data.cases) == 7, name
    data = rvcoax.read_measured(FOLDER / SETS["none_paths_1"]["file"])
    for shaft, relative in relative_gap_to_the_model(identification_rig(), data).items():
        assert 0.005 < relative < 0.08, (shaft, relative)


def test_workflow_on_a_calculix_solid_file_answers_honestly():
    """A hidden torque reaction at the output bearing block (30 % of the signal, 1 % noise, paths): the answer
    covers the truth with a verdict that claims no more than the data carry, and names nothing else with
    confidence."""
    entry = SETS["torque_reaction_paths_1"]
    rig = identification_rig()
    result = rvcoax.run_discrepancy(rig, rvcoax.read_measured(FOLDER / entry["file"]), DiscrepancySettings())
    assert_honest_answer(result, set(entry["truth"]))


def test_an_effect_beyond_its_bound_in_calculix_solid_data_is_never_explained():
    """A torque reaction at twice its physical bound (1 % noise, paths): no effect within its bounds may be offered
    as the explanation; the answer is ``unexplained`` (or ``ambiguous``), never ``explained``."""
    entry = SETS["beyond_bound_paths_1"]
    assert entry["group"] == "out_of_bounds"
    rig = identification_rig()
    result = rvcoax.run_discrepancy(rig, rvcoax.read_measured(FOLDER / entry["file"]),
                                    DiscrepancySettings(confidence_draws=0))  # the verdict only: no estimate needed
    assert result.verdict in ("unexplained", "ambiguous"), (result.verdict, result.reasons)
