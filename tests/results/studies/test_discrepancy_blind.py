"""The committed blind fixtures: hidden-effect data from the hybrid model, identified with the beam model.

The files in ``tests/results/studies/data/blind`` were written by ``benchmarks/blind_data.py`` from the hybrid
model of the reference rig (solid measured shafts tied into the beam line), 7 of paper 000's cases,
6 stations per shaft; ``manifest.json`` holds each file's truth. These tests check that they are
what they claim to be (readable in every notation, independent of the beam model by a model-form
amount, carrying their hidden effect) and that the workflow runs on one of them. The scored
benchmark over about 250 such data sets is ``benchmarks/bench_discrepancy_blind.py``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from discrepancy_data import discrepancy_rig

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import paper_cases
from rvcoax.results.studies.discrepancy.measured import read_measured
from rvcoax.results.studies.discrepancy.responses import Observation, solve_full_paths
from rvcoax.results.studies.discrepancy.workflow import DiscrepancySettings, run_discrepancy
from rvcoax.results.sweep import SweepSettings

FOLDER = Path(__file__).parent / "data" / "blind"
MANIFEST = json.loads((FOLDER / "manifest.json").read_text())
SETS = {s["id"]: s for s in MANIFEST["sets"]}


def rig_for(datum: str) -> Rig:
    """The identification rig: the discrepancy tests' rig with Timoshenko beams (the hybrid model's solid shafts
    deform in shear) and Y from ``datum``."""
    data = discrepancy_rig().model_dump(by_alias=True)
    data["paths"]["measured_from"] = datum
    data["beam"]["shear_deformation"] = True
    return Rig.model_validate(data)


def beam_prediction(data, datum: str) -> np.ndarray:
    paths, layout = solve_full_paths(rig_for(datum), data.cases, SweepSettings())
    return Observation(data, layout)(paths)


def relative_rms(a: np.ndarray, b: np.ndarray, data, shaft: str) -> float:
    mask = data.shaft == shaft
    return float(np.sqrt(np.mean((a - b)[mask] ** 2)) / np.sqrt(np.mean(b[mask] ** 2)))


def test_every_fixture_reads_with_its_schema_and_cases():
    notations = set()
    for name, entry in SETS.items():
        data = read_measured(FOLDER / entry["file"])
        assert data.schema == entry["schema"], name
        assert set(data.cases) <= set(paper_cases()) and len(data.cases) == 7, name
        notations.add(entry["notation"])
        if entry["notation"] in ("e", "E"):  # an exponent-notation table keeps its digits (not a 1 mm quantum)
            assert all(q < 1e-6 for q in (data.quantum_mm or {"paths": 0.0}).values()), name
    assert notations == {"fixed", "e", "E", "mixed"}
    assert {e["schema"] for e in SETS.values()} == {"paths", "table"}
    assert {e["datum"] for e in SETS.values()} == {"unloaded", "aligned_at_rest"}


def test_fixtures_are_independent_of_the_beam_model():
    """On the unmodified rig the hybrid model differs from the beam model by a model-form amount: more than
    the beam model's own reproducibility, less than a gross error."""
    data = read_measured(FOLDER / SETS["none_exact"]["file"])
    beam = beam_prediction(data, "unloaded")
    for shaft in MEASURED_SHAFTS:
        assert 1e-3 < relative_rms(data.value_mm, beam, data, shaft) < 0.05, shaft


def test_hidden_effects_are_in_the_fixtures():
    """A fixture with a hidden effect or load differs from the beam model by far more than its noise and the
    model form; a fixture without one does not."""
    for name, entry in SETS.items():
        data = read_measured(FOLDER / entry["file"])
        beam = beam_prediction(data, entry["datum"])
        change = max(relative_rms(data.value_mm, beam, data, s) for s in MEASURED_SHAFTS)
        if entry["group"] == "none":
            assert change < 0.03 + 3 * entry["noise"], name
        else:  # (a table's |Y_max| changes less than the paths: 6 % for the torque reaction, 30 % on its paths)
            assert change > 0.04 + entry["noise"], name


@pytest.mark.slow
def test_workflow_names_a_hidden_reaction_in_an_exponent_table():
    """The workflow on a hybrid-model table (aligned datum, 1 % noise, E notation) with a hidden torque reaction,
    among the torque-proportional candidates: the reaction is named (alone or in its group)."""
    entry = SETS["torque_reaction"]
    data = read_measured(FOLDER / entry["file"])
    result = run_discrepancy(rig_for(entry["datum"]), data,
                             DiscrepancySettings(candidates=("torque_reaction", "mesh_force")))
    assert result.verdict != "no_gap"
    assert any(entry["truth"][0] in s.group or s.name == entry["truth"][0] for s in result.selected)
